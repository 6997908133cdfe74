/* qm_tile.c - one quantized-mesh tile of a store: lattice, TIN, heights, bytes (see qm_tile.h). */
#include "qm_tile.h"

#include <limits.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NP (TP_QM_CELLS + 1)               /* lattice posts a side */
#define NC (TP_QM_CELLS / TP_QM_COARSE + 1) /* coarse nodes a side */

/* Exact: WGS84 (lat, lon) to the store's grid (column, row) and the geoid's undulation there
 * (0 without one). 0 where the projection fails (far outside the store's zone). */
static int geo_to_grid(const qm_source* s, double lat, double lon, double* gx, double* gy,
                       double* und)
{
    double e, n;
    if (tp_georef_geo_to_proj(s->georef, lat, lon, &e, &n, NULL) != TP_OK)
        return 0;
    tp_georef_proj_to_grid(s->georef, e, n, gx, gy);
    *und = 0;
    if (s->geoid && tp_geoid_undulation(s->geoid, 1, &lat, &lon, und, NULL) != TP_OK)
        return 0;
    return isfinite(*gx) && isfinite(*gy);
}

/* Whether (lat, lon) lies in the store's padded extent widened by margin degrees. */
static int near_store(const qm_source* s, double lat, double lon, double margin)
{
    return lat >= s->lat_lo - margin && lat <= s->lat_hi + margin && lon >= s->lon_lo - margin &&
           lon <= s->lon_hi + margin;
}

/* One coarse node: grid position and undulation, NaN where unknown. */
typedef struct node {
    double gx, gy, und;
} node;

/* Linear between two nodes (t in [0, 1]); NaN if either is unknown. */
static node lerp(node a, node b, double t)
{
    node r = {a.gx + t * (b.gx - a.gx), a.gy + t * (b.gy - a.gy), a.und + t * (b.und - a.und)};
    return r;
}

/* The lattice of one tile: per post the grid position, undulation and height (NaN: no data). */
typedef struct lattice {
    int z, x, y;
    double d;            /* degrees between posts */
    long long gx0, gy0;  /* global index of the tile's south-west post */
    node* nodes;         /* NC x NC, row 0 = south */
    int interp;          /* 1: interpolate between coarse nodes; 0: exact at every post */
    float* h;            /* NP x NP heights for the TIN (row 0 = north), no data = 0 */
    uint8_t* valid;      /* NP x NP */
    double* px;          /* NP x NP grid column (NaN unknown) */
    double* py;
    double* und;
} lattice;

static double lon_of(const lattice* l, long long gx) { return -180.0 + (double)gx * l->d; }
static double lat_of(const lattice* l, long long gy) { return -90.0 + (double)gy * l->d; }

/* Exact node at global post (gx, gy): NaN where unknown or far from the store. */
static node exact_node(const qm_source* s, const lattice* l, long long gx, long long gy)
{
    node r = {NAN, NAN, NAN};
    double lat = lat_of(l, gy), lon = lon_of(l, gx);
    if (!near_store(s, lat, lon, (TP_QM_COARSE + 2) * l->d))
        return r;
    if (!geo_to_grid(s, lat, lon, &r.gx, &r.gy, &r.und))
        r.gx = r.gy = r.und = NAN;
    return r;
}

/* Post (i from the west, k from the south) of the tile, as a function of its global index
 * alone: on a coarse line only the nodes of that line are read, so two tiles that share a post
 * compute it bit for bit alike. */
static node post_node(const qm_source* s, const lattice* l, int i, int k)
{
    if (!l->interp)
        return exact_node(s, l, l->gx0 + i, l->gy0 + k);
    const int ci = i / TP_QM_COARSE, ck = k / TP_QM_COARSE;
    const int ri = i % TP_QM_COARSE, rk = k % TP_QM_COARSE;
    const node* nd = l->nodes;
#define N_AT(a, b) nd[(size_t)(b) * NC + (a)]
    if (!ri && !rk)
        return N_AT(ci, ck);
    if (!ri)
        return lerp(N_AT(ci, ck), N_AT(ci, ck + 1), rk / (double)TP_QM_COARSE);
    if (!rk)
        return lerp(N_AT(ci, ck), N_AT(ci + 1, ck), ri / (double)TP_QM_COARSE);
    node a = lerp(N_AT(ci, ck), N_AT(ci + 1, ck), ri / (double)TP_QM_COARSE);
    node b = lerp(N_AT(ci, ck + 1), N_AT(ci + 1, ck + 1), ri / (double)TP_QM_COARSE);
#undef N_AT
    return lerp(a, b, rk / (double)TP_QM_COARSE);
}

/* Where the store's surface has no height (a cell touching a void), the nearest of the cell's
 * four posts that has one (NaN if none): the lattice then follows the void's outline up to the
 * posts on it, which its neighbours' cells measure. */
static int cell_post(const qm_source* s, double x, double y, double* h, tp_error* err)
{
    const double x0 = floor(x), y0 = floor(y);
    double best = INFINITY;
    *h = NAN;
    for (int k = 0; k < 4; k++) {
        const double px = fmin(x0 + (k & 1), s->width - 1), py = fmin(y0 + (k >> 1), s->height - 1);
        const double d = (px - x) * (px - x) + (py - y) * (py - y);
        double v;
        if (d >= best)
            continue;
        if (tp_ground_height(s->ground, px, py, &v, err) != TP_OK)
            return 0;
        if (isfinite(v)) {
            best = d;
            *h = v;
        }
    }
    return 1;
}

/* Samples the tile's lattice; 0 with err on a read failure. */
static int sample(const qm_source* s, lattice* l, double* interp_gap, tp_error* err)
{
    /* interpolation where a coarse cell is small (its size in metres along a meridian) */
    l->interp = l->d * TP_QM_COARSE * 111320.0 <= s->interp_max_m;
    *interp_gap = 0;
    if (l->interp) {
        for (int b = 0; b < NC; b++)
            for (int a = 0; a < NC; a++)
                l->nodes[(size_t)b * NC + a] =
                    exact_node(s, l, l->gx0 + (long long)a * TP_QM_COARSE,
                               l->gy0 + (long long)b * TP_QM_COARSE);
        /* the interpolation checked against the exact projection at each coarse cell's centre
         * (a post: 7 is odd, so 3 + 3 / 7 ... the post nearest it) */
        for (int b = 0; b + 1 < NC; b++)
            for (int a = 0; a + 1 < NC; a++) {
                const int i = a * TP_QM_COARSE + TP_QM_COARSE / 2;
                const int k = b * TP_QM_COARSE + TP_QM_COARSE / 2;
                node p = post_node(s, l, i, k), e = exact_node(s, l, l->gx0 + i, l->gy0 + k);
                double gap = hypot(p.gx - e.gx, p.gy - e.gy);
                if (isfinite(gap) && gap > *interp_gap)
                    *interp_gap = gap;
            }
    }
    for (int j = 0; j < NP; j++)
        for (int i = 0; i < NP; i++) {
            const size_t at = (size_t)j * NP + i;
            node p = post_node(s, l, i, TP_QM_CELLS - j);
            l->px[at] = p.gx;
            l->py[at] = p.gy;
            l->und[at] = p.und;
            double h = NAN;
            int inside = 0;
            if (isfinite(p.gx) && isfinite(p.gy)) {
                /* outside the store (near it) the height of the nearest point of its grid: the
                 * cells across the store's outline then hold no cliff down to 0 */
                inside = p.gx >= 0 && p.gy >= 0 && p.gx <= s->width - 1 && p.gy <= s->height - 1;
                const double cx = fmin(fmax(p.gx, 0), s->width - 1);
                const double cy = fmin(fmax(p.gy, 0), s->height - 1);
                if (tp_ground_height(s->ground, cx, cy, &h, err) != TP_OK)
                    return 0;
                if (!isfinite(h) && !cell_post(s, cx, cy, &h, err))
                    return 0;
                if (isfinite(h) && s->geoid) {
                    if (!isfinite(p.und)) {
                        h = NAN;
                    } else {
                        h += p.und;
                    }
                }
            }
            l->valid[at] = inside && isfinite(h);
            /* a void of the store stays NaN (the TIN neither measures nor inserts it); far
             * from the store the ground is 0 */
            l->h[at] = isfinite(h) ? (float)h : isfinite(p.gx) && isfinite(p.gy) ? NAN : 0.0f;
        }
    return 1;
}

/* A corner's height where its post is void: the nearest post of the store with a height
 * (Chebyshev rings, row order within a ring) within 64 posts, its undulation added, else 0; a
 * function of the corner's position alone, so the four tiles around it agree. */
static int void_corner(const qm_source* s, const lattice* l, size_t at, float* out, tp_error* err)
{
    *out = 0.0f;
    const long cx = lround(l->px[at]), cy = lround(l->py[at]);
    for (int r = 1; r <= 64; r++)
        for (long y = cy - r; y <= cy + r; y++)
            for (long x = cx - r; x <= cx + r; x++) {
                if (labs(y - cy) != r && labs(x - cx) != r)
                    continue;
                if (x < 0 || y < 0 || x > s->width - 1 || y > s->height - 1)
                    continue;
                double h;
                if (tp_ground_height(s->ground, (double)x, (double)y, &h, err) != TP_OK)
                    return 0;
                if (isfinite(h)) {
                    *out = (float)(h + (isfinite(l->und[at]) ? l->und[at] : 0));
                    return 1;
                }
            }
    return 1;
}

static uint64_t fnv(uint64_t h, uint64_t v)
{
    for (int b = 0; b < 8; b++) {
        h ^= (v >> (8 * b)) & 0xff;
        h *= 1099511628211ull;
    }
    return h;
}

static int cmp_ll2(const void* a, const void* b)
{
    const long long *p = a, *q = b;
    return (p[0] > q[0]) - (p[0] < q[0]);
}

/* The sides' signatures: each side's vertices (code along it, height in steps) in order. */
static int edge_hashes(const qm_work* w, uint64_t out[4])
{
    long long* at = malloc(2 * (w->nv + 1) * sizeof *at);
    if (!at)
        return 0;
    for (int side = 0; side < 4; side++) { /* west, south, east, north */
        size_t n = 0;
        for (size_t k = 0; k < w->nv; k++) {
            const int u = w->u[k], v = w->v[k];
            const int on = side == 0 ? u == 0 : side == 1 ? v == 0
                                      : side == 2 ? u == TP_QMESH_MAX_CODE : v == TP_QMESH_MAX_CODE;
            if (on) {
                at[2 * n] = side == 0 || side == 2 ? v : u;
                at[2 * n++ + 1] = w->hq[k];
            }
        }
        qsort(at, n, 2 * sizeof *at, cmp_ll2);
        uint64_t h = 1469598103934665603ull;
        for (size_t i = 0; i < n; i++)
            h = fnv(fnv(h, (uint64_t)at[2 * i]), (uint64_t)at[2 * i + 1]);
        out[side] = h;
    }
    free(at);
    return 1;
}

/* The header's range and the height codes: every vertex decodes to hq * step. */
static void quantise(const qm_source* s, const qm_work* w, uint16_t* hc, double* lo_m,
                     double* hi_m)
{
    const double step = s->height_step_m;
    long long lo = LLONG_MAX, hi = LLONG_MIN;
    for (size_t k = 0; k < w->nv; k++) {
        lo = w->hq[k] < lo ? w->hq[k] : lo;
        hi = w->hq[k] > hi ? w->hq[k] : hi;
    }
    /* codes of 2^k per step, the most that fit 32767 and keep the range a float (24 bits) */
    int k = 0;
    while (k < 15 && (hi - lo) * (2LL << k) <= TP_QMESH_MAX_CODE &&
           (fabs((double)lo) + 32768.0) * (double)(2LL << k) < 16777216.0)
        k++;
    for (size_t v = 0; v < w->nv; v++)
        hc[v] = (uint16_t)((w->hq[v] - lo) << k);
    *lo_m = (double)lo * step;
    *hi_m = *lo_m + TP_QMESH_MAX_CODE * step / (double)(1LL << k);
}

static int fail_oom(tp_error* err) { return tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory"), 0; }

/* The TIN as a mesh to refine: vertices at their u, v codes, heights on the common step. */
static int work_of(const qm_source* s, const tp_tin* t, qm_work* w)
{
    const int per_cell = TP_QMESH_MAX_CODE / TP_QM_CELLS;
    w->nv = w->cap_v = t->vertex_count;
    w->nt = t->triangle_count;
    w->cap_t = 3 * w->nt;
    w->u = malloc(w->nv * sizeof *w->u);
    w->v = malloc(w->nv * sizeof *w->v);
    w->hq = malloc(w->nv * sizeof *w->hq);
    w->tris = malloc(w->cap_t * sizeof *w->tris);
    if (!w->u || !w->v || !w->hq || !w->tris)
        return 0;
    for (size_t k = 0; k < w->nv; k++) {
        w->u[k] = (uint16_t)((int)t->vertices[3 * k] * per_cell);
        w->v[k] = (uint16_t)((TP_QM_CELLS - (int)t->vertices[3 * k + 1]) * per_cell);
        w->hq[k] = llround(t->vertices[3 * k + 2] / s->height_step_m);
    }
    memcpy(w->tris, t->triangles, w->cap_t * sizeof *w->tris);
    return 1;
}

/* Measures tile w (as mesh m, built here over the buffers ij and zd of w->nv vertices) against
 * the lattice posts with a height and the store's posts in box (west, south, east, north); the
 * points above c->above appended to c (NULL: none). 0 on failure. */
static int measure(const qm_source* s, const lattice* l, const qm_work* w, const double box[4],
                   double* ij, double* zd, qm_mesh* m, qm_index** ix, qm_points* c,
                   double* max_m, size_t* posts, tp_error* err)
{
    const double per_cell = TP_QMESH_MAX_CODE / TP_QM_CELLS;
    for (size_t k = 0; k < w->nv; k++) {
        ij[2 * k] = w->u[k] / per_cell;
        ij[2 * k + 1] = TP_QM_CELLS - w->v[k] / per_cell;
        zd[k] = (double)w->hq[k] * s->height_step_m;
    }
    *m = (qm_mesh){TP_QM_CELLS, w->nv, w->nt, ij, zd, w->tris};
    double mx = 0;
    for (int j = 0; j < NP; j++)
        for (int i = 0; i < NP; i++)
            if (l->valid[(size_t)j * NP + i]) {
                const double h = l->h[(size_t)j * NP + i], hm = tp_qm_mesh_height(m, ix, i, j);
                if (isnan(hm) || (c && !tp_qm_points_add(c, i, j, h, fabs(hm - h))))
                    return fail_oom(err);
                mx = fmax(mx, fabs(hm - h));
            }
    double post_err = 0;
    if (!tp_qm_measure_posts(s, m, ix, box[0], box[1], box[2], box[3], &post_err, posts, c, err))
        return 0;
    *max_m = fmax(mx, post_err);
    return 1;
}

/* The refinement's height function: the store's surface at a lattice position (exact
 * projection), its undulation added; NaN off the grid or in a void. */
typedef struct surface_ctx {
    const qm_source* s;
    const lattice* l;
    tp_error* err;
} surface_ctx;

static int surface_at(void* ctx, double fi, double fj, double* h)
{
    const surface_ctx* c = ctx;
    const double lon = -180.0 + ((double)c->l->gx0 + fi) * c->l->d;
    const double lat = -90.0 + ((double)c->l->gy0 + TP_QM_CELLS - fj) * c->l->d;
    double gx, gy, und;
    *h = NAN;
    if (!geo_to_grid(c->s, lat, lon, &gx, &gy, &und) || gx < 0 || gy < 0 ||
        gx > c->s->width - 1 || gy > c->s->height - 1)
        return 1;
    if (tp_ground_height(c->s->ground, gx, gy, h, c->err) != TP_OK)
        return 0;
    *h += und;
    return 1;
}

/* Refinement passes before the measure is taken as it is. */
#define QM_PASSES 8
/* Points a measure keeps for the refinement (24 bytes each): this many between half the bound
 * and the bound, 4 times as many in all. */
#define QM_POINTS_MAX ((size_t)1 << 19)

/* Measures the tile and, while a post or lattice post is above the bound, refines it with the
 * points the measure found above half the bound and measures again (docs/quantized_mesh.md, "The
 * measured error"). r's measure fields set. 0 on failure. */
static int refine_measured(const qm_source* s, const lattice* l, qm_work* w, const double box[4],
                           double bound_m, qm_tile_result* r, tp_error* err)
{
    qm_points c = {NULL, 0, 0, QM_POINTS_MAX, 0.5 * bound_m, bound_m};
    qm_index* ix = NULL;
    double *ij = NULL, *zd = NULL;
    size_t cap = 0;
    int ok = 0;
    for (int pass = 0;; pass++) {
        if (w->nv > cap) {
            free(ij);
            free(zd);
            cap = w->nv;
            ij = malloc(2 * cap * sizeof *ij);
            zd = malloc(cap * sizeof *zd);
            if (!ij || !zd) {
                fail_oom(err);
                break;
            }
        }
        c.n = 0;
        tp_qm_index_free(ix);
        ix = NULL;
        qm_mesh m;
        if (!measure(s, l, w, box, ij, zd, &m, &ix, pass < QM_PASSES ? &c : NULL,
                     &r->measured_m, &r->posts_measured, err))
            break;
        if (r->measured_m <= bound_m || pass == QM_PASSES) {
            ok = 1;
            break;
        }
        /* a hair below the bound: the measure's arithmetic is not the refinement's */
        size_t added;
        surface_ctx sc = {s, l, err};
        if (!tp_qm_refine(w, &m, &ix, c.p, c.n, bound_m * (1 - 1e-9), s->height_step_m,
                          surface_at, &sc, &added, &r->stuck_m, err))
            break;
        r->inserted += added;
        r->passes = pass + 1;
        if (!added) {
            ok = 1;
            break;
        }
    }
    tp_qm_index_free(ix);
    free(ij);
    free(zd);
    free(c.p);
    return ok;
}

int tp_qm_tile_build(const qm_source* s, int z, int x, int y, double bound_m, qm_tile_result* r,
                     tp_error* err)
{
    memset(r, 0, sizeof *r);
    r->bound_m = bound_m;
    lattice l = {z, x, y, 180.0 / ldexp((double)TP_QM_CELLS, z), (long long)x * TP_QM_CELLS,
                 (long long)y * TP_QM_CELLS, NULL, 0, NULL, NULL, NULL, NULL, NULL};
    const size_t np = (size_t)NP * NP;
    l.nodes = malloc((size_t)NC * NC * sizeof *l.nodes);
    l.h = malloc(np * sizeof *l.h);
    l.valid = malloc(np);
    l.px = malloc(np * sizeof *l.px);
    l.py = malloc(np * sizeof *l.py);
    l.und = malloc(np * sizeof *l.und);
    tp_tin* t = NULL;
    qm_work w = {NULL, NULL, NULL, 0, 0, NULL, 0, 0};
    uint16_t* hc = NULL;
    uint8_t* raw = NULL;
    int ok = 0;
    if (!l.nodes || !l.h || !l.valid || !l.px || !l.py || !l.und) {
        fail_oom(err);
        goto done;
    }
    if (!sample(s, &l, &r->proj_interp_m, err))
        goto done;
    float cz[4];
    const size_t corner_at[4] = {0, NP - 1, np - NP, np - 1};
    for (int c = 0; c < 4; c++) {
        cz[c] = l.h[corner_at[c]];
        if (cz[c] != cz[c] && !void_corner(s, &l, corner_at[c], &cz[c], err))
            goto done;
    }
    /* the TIN's bound leaves room for the heights' rounding to the step (half a step): the sides,
     * which the refinement never touches, then hold the bound as decoded */
    const double half = 0.5 * s->height_step_m;
    const double tin_bound = bound_m - half > 0.5 * bound_m ? bound_m - half : 0.5 * bound_m;
    if (tp_tin_build_tile(l.h, NP, NP, NP, 0, 0, NP, NP, cz, tin_bound, 0, &t, err) != TP_OK)
        goto done;
    if (!work_of(s, t, &w)) {
        fail_oom(err);
        goto done;
    }
    double w_deg, s_deg, e_deg, n_deg;
    tp_qmesh_tile_bounds(z, x, y, &w_deg, &s_deg, &e_deg, &n_deg);
    const double box[4] = {w_deg, s_deg, e_deg, n_deg};
    /* the posts on the sides first (both tiles of a side add the same vertices), then the
     * inside refined until the measure is within the bound */
    surface_ctx sc = {s, &l, err};
    qm_side_vertex* sv = NULL;
    size_t nsv = 0;
    if (!tp_qm_side_vertices(s, &w, z, x, y, bound_m, l.h, l.valid, surface_at, &sc, &sv, &nsv,
                             err))
        goto done;
    const int sides_ok = tp_qm_insert_sides(&w, sv, nsv, err);
    free(sv);
    r->side_vertices = nsv;
    if (!sides_ok || !refine_measured(s, &l, &w, box, bound_m, r, err))
        goto done;
    hc = malloc(w.nv * sizeof *hc);
    if (!hc) {
        fail_oom(err);
        goto done;
    }
    double lo_m, hi_m;
    quantise(s, &w, hc, &lo_m, &hi_m);
    if (!edge_hashes(&w, r->edge_hash)) {
        fail_oom(err);
        goto done;
    }
    tp_qmesh_tile qt = {w_deg, s_deg, e_deg, n_deg, lo_m, hi_m, w.nv, w.u, w.v, hc, w.nt, w.tris};
    if (tp_qmesh_encode(&qt, &raw, &r->raw_size, NULL, err) != TP_OK)
        goto done;
    if (tp_gzip(raw, r->raw_size, 6, &r->gz, &r->gz_size, err) != TP_OK)
        goto done;
    r->vertices = w.nv;
    r->triangles = w.nt;
    ok = 1;
done:
    if (!ok) {
        free(r->gz);
        r->gz = NULL;
    }
    tp_tin_destroy(t);
    free(raw);
    free(hc);
    free(w.u);
    free(w.v);
    free(w.hq);
    free(w.tris);
    free(l.nodes);
    free(l.h);
    free(l.valid);
    free(l.px);
    free(l.py);
    free(l.und);
    return ok;
}
