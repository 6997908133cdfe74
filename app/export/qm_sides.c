/* qm_sides.c - the store's posts on a quantized-mesh tile's sides, and the side vertices they need
 * (see qm_tile.h): the TIN's side polylines see the lattice posts on the side only, and where a
 * row or column of the store's posts runs along a side (geographic stores at coarse levels) the
 * posts between them stand off the polyline; both tiles of the side measure them. */
#include "qm_tile.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Posts within this many codes of a side's line are the side's: the inside's refinement puts a
 * vertex no nearer to the side than 1 code, so a post between it and the side could only be
 * held by the side (its vertices at the posts' positions along it). */
#define QM_SIDE_BAND 1.5

/* A post on a side: its position along the side (codes, fractional) and height. */
typedef struct side_post {
    double at, h;
} side_post;

/* A polyline vertex: code along the side, height in steps. */
typedef struct pvert {
    long long at, hq;
} pvert;

static int cmp_pvert(const void* a, const void* b)
{
    const pvert *p = a, *q = b;
    return (p->at > q->at) - (p->at < q->at);
}

static int cmp_ll2(const void* a, const void* b)
{
    const long long *p = a, *q = b;
    if (p[0] != q[0])
        return (p[0] > q[0]) - (p[0] < q[0]);
    return (p[1] > q[1]) - (p[1] < q[1]);
}

static int push(void** p, size_t* n, size_t* cap, const void* item, size_t size)
{
    if (*n == *cap) {
        const size_t c = *cap ? 2 * *cap : 256;
        void* q = realloc(*p, c * size);
        if (!q)
            return 0;
        *p = q;
        *cap = c;
    }
    memcpy((char*)*p + *n * size, item, size);
    (*n)++;
    return 1;
}

/* The store's posts within QM_SIDE_BAND codes of side `side` (0 west, 1 south, 2 east, 3 north) of the
 * tile whose south-west corner is (w, so) degrees and side `size` degrees. 0 on failure. */
static int side_posts(const qm_source* s, int side, double w, double so, double size,
                      side_post** out, size_t* n, tp_error* err)
{
    const double code = size / TP_QMESH_MAX_CODE;
    const int ns = side == 1 || side == 3; /* a line of latitude */
    const double fixed = side == 0 ? w : side == 2 ? w + size : side == 1 ? so : so + size;
    const double start = ns ? w : so;
    long long* cand = NULL;
    size_t nc = 0, cc = 0, cap = 0;
    *out = NULL;
    *n = 0;
    /* the line on the grid: 65 points, each segment walked along its major axis */
    double gx[65], gy[65];
    int okp[65];
    for (int k = 0; k <= 64; k++) {
        const double t = start + size * k / 64.0;
        double e, nn;
        okp[k] = tp_georef_geo_to_proj(s->georef, ns ? fixed : t, ns ? t : fixed, &e, &nn, NULL) ==
                 TP_OK;
        if (okp[k])
            tp_georef_proj_to_grid(s->georef, e, nn, &gx[k], &gy[k]);
        okp[k] = okp[k] && isfinite(gx[k]) && isfinite(gy[k]);
    }
    for (int k = 0; k < 64; k++) {
        if (!okp[k] || !okp[k + 1])
            continue;
        const double dx = gx[k + 1] - gx[k], dy = gy[k + 1] - gy[k];
        const int major_x = fabs(dx) >= fabs(dy);
        const double a0 = major_x ? gx[k] : gy[k], a1 = major_x ? gx[k + 1] : gy[k + 1];
        const double lo = fmax(fmin(a0, a1), -1), hi = fmin(fmax(a0, a1), major_x ? s->width : s->height);
        for (long long m = (long long)ceil(lo); m <= (long long)floor(hi); m++) {
            const double t = a1 == a0 ? 0 : (m - a0) / (a1 - a0);
            const double minor = major_x ? gy[k] + t * dy : gx[k] + t * dx;
            for (long long q = (long long)floor(minor) - 1; q <= (long long)ceil(minor) + 1; q++) {
                const long long px = major_x ? m : q, py = major_x ? q : m;
                if (px < 0 || py < 0 || px > s->width - 1 || py > s->height - 1)
                    continue;
                const long long item[2] = {px, py};
                if (!push((void**)&cand, &nc, &cc, item, sizeof item))
                    goto oom;
            }
        }
    }
    if (nc)
        qsort(cand, nc, 2 * sizeof *cand, cmp_ll2);
    for (size_t k = 0; k < nc; k++) {
        if (k && cand[2 * k] == cand[2 * k - 2] && cand[2 * k + 1] == cand[2 * k - 1])
            continue;
        double e, nn, lat, lon, h, und = 0;
        tp_georef_grid_to_proj(s->georef, (double)cand[2 * k], (double)cand[2 * k + 1], &e, &nn);
        if (tp_georef_proj_to_geo(s->georef, e, nn, &lat, &lon, NULL) != TP_OK)
            continue;
        const double across = ns ? lat : lon, along = ns ? lon : lat;
        if (!(fabs(across - fixed) <= QM_SIDE_BAND * code))
            continue;
        const double at = (along - start) / code;
        if (!(at > 0.5 && at < TP_QMESH_MAX_CODE - 0.5))
            continue;
        if (tp_ground_height(s->ground, (double)cand[2 * k], (double)cand[2 * k + 1], &h, err) != TP_OK)
            goto fail;
        if (isfinite(h) && s->geoid && tp_geoid_undulation(s->geoid, 1, &lat, &lon, &und, NULL) != TP_OK)
            continue;
        if (!isfinite(h) || !isfinite(und))
            continue;
        const side_post p = {at, h + und};
        if (!push((void**)out, n, &cap, &p, sizeof p))
            goto oom;
    }
    free(cand);
    return 1;
oom:
    tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
fail:
    free(cand);
    free(*out);
    *out = NULL;
    return 0;
}

/* The polyline's height (m) at position at: between the vertices around it (sorted). */
static double poly_at(const pvert* v, size_t nv, double at, double step)
{
    size_t lo = 0, hi = nv - 1; /* v[lo].at <= at <= v[hi].at */
    while (hi - lo > 1) {
        const size_t mid = (lo + hi) / 2;
        if (v[mid].at <= at)
            lo = mid;
        else
            hi = mid;
    }
    const double t = (at - v[lo].at) / (double)(v[hi].at - v[lo].at);
    return ((1 - t) * v[lo].hq + t * v[hi].hq) * step;
}

int tp_qm_side_vertices(const qm_source* s, const qm_work* w, int z, int x, int y, double bound_m,
                        const float* lattice_h, const uint8_t* valid, qm_height_fn height,
                        void* ctx, qm_side_vertex** out, size_t* n, tp_error* err)
{
    const double size = 180.0 / ldexp(1.0, z), west = -180.0 + x * size, south = -90.0 + y * size;
    const double per_cell = TP_QMESH_MAX_CODE / TP_QM_CELLS;
    size_t cap = 0;
    *out = NULL;
    *n = 0;
    pvert* pv = malloc(w->nv * sizeof *pv + sizeof *pv);
    if (!pv)
        return tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory"), 0;
    for (int side = 0; side < 4; side++) {
        const int ns = side == 1 || side == 3;
        const int line = side == 0 || side == 1 ? 0 : TP_QMESH_MAX_CODE;
        size_t nv = 0;
        for (size_t k = 0; k < w->nv; k++)
            if ((ns ? w->v[k] : w->u[k]) == line)
                pv[nv++] = (pvert){ns ? w->u[k] : w->v[k], w->hq[k]};
        qsort(pv, nv, sizeof *pv, cmp_pvert);
        side_post* posts;
        size_t np, pcap;
        if (!side_posts(s, side, west, south, size, &posts, &np, err))
            goto fail;
        /* and the lattice's posts on the side that the measure reads (the same in both tiles):
         * a vertex added between the TIN's must not take the line away from them */
        pcap = np;
        for (int k = 1; k < TP_QM_CELLS; k++) {
            const int i = ns ? k : line ? TP_QM_CELLS : 0;
            const int j = ns ? (line ? 0 : TP_QM_CELLS) : TP_QM_CELLS - k;
            const size_t at = (size_t)j * (TP_QM_CELLS + 1) + i;
            const side_post p = {k * per_cell, lattice_h[at]};
            if (valid[at] && !push((void**)&posts, &np, &pcap, &p, sizeof p)) {
                free(posts);
                tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
                goto fail;
            }
        }
        size_t first_new = *n;
        for (;;) { /* the worst post above the bound, until none */
            /* half the bound: a post beside the line (up to QM_SIDE_BAND codes) is a mix of
             * the side's polyline and the inside's vertex nearest it */
            double worst = 0.5 * bound_m;
            long long at = -1;
            for (size_t k = 0; k < np; k++) {
                const double e = fabs(poly_at(pv, nv, posts[k].at, s->height_step_m) - posts[k].h);
                if (e > worst) {
                    const long long c = llround(posts[k].at);
                    int taken = 0; /* a vertex there already: the post stays as it is */
                    for (size_t i = 0; i < nv && !taken; i++)
                        taken = pv[i].at == c;
                    if (!taken)
                        worst = e, at = c;
                }
            }
            if (at < 0)
                break;
            const double along = at / per_cell, edge = line / per_cell;
            double h = NAN;
            if (!height(ctx, ns ? along : edge, ns ? TP_QM_CELLS - edge : TP_QM_CELLS - along, &h)) {
                free(posts);
                goto fail;
            }
            if (!isfinite(h)) { /* off the grid: the nearest post's own height */
                double best = INFINITY;
                for (size_t k = 0; k < np; k++)
                    if (fabs(posts[k].at - at) < best)
                        best = fabs(posts[k].at - at), h = posts[k].h;
            }
            const qm_side_vertex sv = {(uint16_t)(ns ? at : line), (uint16_t)(ns ? line : at),
                                       llround(h / s->height_step_m)};
            pvert* grown = realloc(pv, (w->nv + *n - first_new + nv + 2) * sizeof *pv);
            if (!grown || !push((void**)out, n, &cap, &sv, sizeof sv)) {
                if (grown)
                    pv = grown;
                free(posts);
                tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
                goto fail;
            }
            pv = grown;
            pv[nv++] = (pvert){at, sv.hq};
            qsort(pv, nv, sizeof *pv, cmp_pvert);
        }
        free(posts);
    }
    free(pv);
    return 1;
fail:
    free(pv);
    free(*out);
    *out = NULL;
    *n = 0;
    return 0;
}
