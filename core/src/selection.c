/* selection.c - one frame: a level per patch, culling, statistics and error measurement.
 *
 * Based on: Vanek & Jezek (WSCG 2004) section 3 for distance LoD and AABB culling; Brodersen
 * (2005) section 3 for the error-driven selection. Formulas are in lod.c.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

#define TP__STALE UINT32_MAX

/* The error-mode bound of one patch for the current view (see lod.c): a vertical error of d
 * metres anywhere in the patch's AABB projects to at most d * num / (zmin - d * |vz|) pixels. */
typedef struct proj_bound {
    double num;  /* f * sqrt(Amax^2 + Bmax^2) / zmin; INFINITY when the box reaches the near plane */
    double zmin; /* smallest depth of the box's corners */
} proj_bound;

struct tp_selection {
    const tp_terrain* t;
    int count;
    uint8_t* level;
    uint8_t* next;     /* scratch: levels being selected */
    uint8_t* visible;
    uint8_t* dirty;
    proj_bound* proj;  /* error mode: each visible patch's projection bound */
    uint32_t* tris;    /* cached drawn-triangle count per patch, TP__STALE when unknown */
    tp_vertex* vbuf;   /* scratch for one patch at level n */
    uint32_t* tbuf;
};

static int neighbor(const tp_terrain* t, int p, int side)
{
    int pc = t->info.patch_cols, pr = t->info.patch_rows, c = p % pc, r = p / pc;
    switch (side) {
    case TP_SIDE_TOP: return r > 0 ? p - pc : -1;
    case TP_SIDE_RIGHT: return c + 1 < pc ? p + 1 : -1;
    case TP_SIDE_BOTTOM: return r + 1 < pr ? p + pc : -1;
    default: return c > 0 ? p - 1 : -1;
    }
}

static void mark_dirty(tp_selection* s, int p)
{
    s->dirty[p] = 1;
    s->tris[p] = TP__STALE;
    for (int side = 0; side < 4; side++) {
        int q = neighbor(s->t, p, side);
        if (q >= 0) {
            s->dirty[q] = 1;
            s->tris[q] = TP__STALE;
        }
    }
}

tp_status tp_selection_create(const tp_terrain* t, tp_selection** out, tp_error* err)
{
    if (!t || !out)
        return tp__fail(err, TP_ERR_INVALID_ARG, "selection: terrain and out must not be NULL");
    tp_selection* s = calloc(1, sizeof *s);
    if (!s)
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "selection: out of memory");
    int count = t->info.patch_count;
    size_t v = ((size_t)1 << t->n) + 1;
    s->t = t;
    s->count = count;
    s->level = malloc((size_t)count);
    s->next = malloc((size_t)count);
    s->visible = malloc((size_t)count);
    s->dirty = malloc((size_t)count);
    s->proj = calloc((size_t)count, sizeof *s->proj);
    s->tris = malloc((size_t)count * sizeof *s->tris);
    s->vbuf = malloc(v * v * sizeof *s->vbuf);
    s->tbuf = malloc(3 * 2 * (v - 1) * (v - 1) * sizeof *s->tbuf);
    if (!s->level || !s->next || !s->visible || !s->dirty || !s->proj || !s->tris || !s->vbuf ||
        !s->tbuf) {
        tp_selection_destroy(s);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "selection: out of memory for %d patches",
                        count);
    }
    memset(s->level, t->n, (size_t)count);
    memset(s->visible, 1, (size_t)count);
    memset(s->dirty, 1, (size_t)count);
    for (int p = 0; p < count; p++)
        s->tris[p] = TP__STALE;
    *out = s;
    return TP_OK;
}

void tp_selection_destroy(tp_selection* s)
{
    if (!s)
        return;
    free(s->level);
    free(s->next);
    free(s->visible);
    free(s->dirty);
    free(s->proj);
    free(s->tris);
    free(s->vbuf);
    free(s->tbuf);
    free(s);
}

int tp_selection_level(const tp_selection* s, int patch)
{
    return s->level[patch];
}

int tp_selection_visible(const tp_selection* s, int patch)
{
    return s->visible[patch];
}

void tp_selection_neighbor_levels(const tp_selection* s, int patch, int out[4])
{
    for (int side = 0; side < 4; side++) {
        int q = neighbor(s->t, patch, side);
        out[side] = q >= 0 ? s->level[q] : TP_NO_NEIGHBOR;
    }
}

int tp_selection_dirty(const tp_selection* s, int patch)
{
    return s->dirty[patch];
}

void tp_selection_clear_dirty(tp_selection* s)
{
    memset(s->dirty, 0, (size_t)s->count);
}

tp_status tp_selection_set_level(tp_selection* s, int patch, int k)
{
    const tp_terrain* t = s->t;
    if (patch < 0 || patch >= s->count || k < 0 || k > t->n)
        return TP_ERR_INVALID_ARG;
    if (!t->patches[patch].complete)
        k = t->n;
    if (s->level[patch] != k) {
        s->level[patch] = (uint8_t)k;
        mark_dirty(s, patch);
    }
    memset(s->visible, 1, (size_t)s->count);
    return TP_OK;
}

void tp_selection_cull(tp_selection* s, const tp_camera* cam)
{
    tp_frustum f;
    tp_frustum_from_camera(cam, &f);
    for (int p = 0; p < s->count; p++) {
        tp_patch_info pi;
        tp_patch_get_info(s->t, p, &pi);
        s->visible[p] = tp_frustum_test_aabb(&f, pi.aabb_min, pi.aabb_max) != TP_CULL_OUTSIDE;
    }
}

static proj_bound projection_bound(const tp__view* v, const tp_patch_info* pi)
{
    /* The world's vertical in camera coordinates. */
    double vx = v->right[2], vy = v->up[2], vz = v->fwd[2];
    double zmin = INFINITY, amax = 0, bmax = 0;
    for (int c = 0; c < 8; c++) {
        double d[3] = {(c & 1 ? pi->aabb_max[0] : pi->aabb_min[0]) - v->pos[0],
                       (c & 2 ? pi->aabb_max[1] : pi->aabb_min[1]) - v->pos[1],
                       (c & 4 ? pi->aabb_max[2] : pi->aabb_min[2]) - v->pos[2]};
        double x = d[0] * v->right[0] + d[1] * v->right[1] + d[2] * v->right[2];
        double y = d[0] * v->up[0] + d[1] * v->up[1] + d[2] * v->up[2];
        double z = d[0] * v->fwd[0] + d[1] * v->fwd[1] + d[2] * v->fwd[2];
        double A = fabs(vx * z - x * vz), B = fabs(vy * z - y * vz);
        zmin = z < zmin ? z : zmin;
        amax = A > amax ? A : amax;
        bmax = B > bmax ? B : bmax;
    }
    proj_bound pb = {INFINITY, zmin};
    if (zmin > v->near_m)
        pb.num = v->f_px * sqrt(amax * amax + bmax * bmax) / zmin;
    return pb;
}

/* Pixels that a vertical error of d metres in the patch can project to at most. */
static double projected_px(const proj_bound* pb, double vz, double d)
{
    double den = pb->zmin - d * fabs(vz);
    return den > 0 ? d * pb->num / den : INFINITY;
}

static double aabb_distance(const double pos[3], const tp_patch_info* pi)
{
    double d2 = 0;
    for (int a = 0; a < 3; a++) {
        double d = pos[a] < pi->aabb_min[a] ? pi->aabb_min[a] - pos[a]
                 : pos[a] > pi->aabb_max[a] ? pos[a] - pi->aabb_max[a]
                 : 0;
        d2 += d * d;
    }
    return sqrt(d2);
}

/* Geometric part (metres, no quantisation) of the stitching bound of one side. */
static double side_bound_m(const tp_terrain* t, int p, int side, int kn)
{
    const tp__patch* P = &t->patches[p];
    unsigned e = tp__eps_tab(t, p, side)[kn];
    double range = (double)(P->qmax - P->qmin);
    double steps = e >= TP__ERR_SAT ? range : e * t->err_unit;
    return (steps < range ? steps : range) * t->step;
}

tp_status tp_selection_update(tp_selection* s, const tp_camera* cam, const tp_lod_params* params,
                              tp_error* err)
{
    const tp_terrain* t = s->t;
    tp_lod_params lp;
    tp_status st = tp_lod_params_resolve(t, params, &lp, err);
    if (st != TP_OK)
        return st;
    if (!cam)
        return tp__fail(err, TP_ERR_INVALID_ARG, "selection: camera must not be NULL");
    tp__view v;
    tp__view_from_camera(cam, &v);
    tp_frustum f;
    tp_frustum_from_camera(cam, &f);
    int n = t->n;

    for (int p = 0; p < s->count; p++) {
        tp_patch_info pi;
        tp_patch_get_info(t, p, &pi);
        int vis = tp_frustum_test_aabb(&f, pi.aabb_min, pi.aabb_max) != TP_CULL_OUTSIDE;
        s->visible[p] = (uint8_t)vis;
        int k = n;
        s->proj[p] = (proj_bound){0, 0};
        if (lp.mode == TP_LOD_DISTANCE) {
            k = tp_lod_level_distance(n, aabb_distance(v.pos, &pi), lp.mindist_m, lp.maxdist_m,
                                      lp.exponent);
        } else if (lp.mode == TP_LOD_ERROR) {
            /* A culled patch has no error of its own to show; the stitching pass below
             * raises it where a visible neighbour needs that. */
            k = 0;
            if (vis) {
                proj_bound pb = projection_bound(&v, &pi);
                s->proj[p] = pb;
                /* Coarsest level such that it and every finer level project to <= tau, so that
                 * raising the patch later never breaks its own bound. */
                k = n;
                while (k > 0 && (pi.delta_m[k - 1] == 0 ||
                                 projected_px(&pb, v.fwd[2], pi.delta_m[k - 1]) <= lp.tau_px))
                    k--;
            }
        }
        if (!t->patches[p].complete || k < 0)
            k = n;
        s->next[p] = (uint8_t)k;
    }

    if (lp.mode == TP_LOD_ERROR) {
        /* Stitched border triangles of a patch next to a coarser neighbour can exceed both
         * patches' delta: raise that neighbour until every stitched side projects <= tau.
         * Levels only go up, so this ends. */
        for (int changed = 1; changed;) {
            changed = 0;
            for (int p = 0; p < s->count; p++) {
                if (s->proj[p].num == 0)
                    continue;
                for (int side = 0; side < 4; side++) {
                    int q = neighbor(t, p, side);
                    if (q < 0 || s->next[q] >= s->next[p])
                        continue;
                    double geo = side_bound_m(t, p, side, s->next[q]);
                    if (geo > 0 && projected_px(&s->proj[p], v.fwd[2], geo + t->quant_err) >
                                       lp.tau_px) {
                        s->next[q]++;
                        changed = 1;
                    }
                }
            }
        }
    }

    for (int p = 0; p < s->count; p++)
        if (s->next[p] != s->level[p]) {
            s->level[p] = s->next[p];
            mark_dirty(s, p);
        }
    return TP_OK;
}

static uint32_t patch_triangle_count(tp_selection* s, int p)
{
    if (s->tris[p] == TP__STALE) {
        int nb[4], k = s->level[p];
        tp_selection_neighbor_levels(s, p, nb);
        size_t v = ((size_t)1 << s->t->n) + 1;
        tp_patch_vertices(s->t, p, k, nb, s->vbuf, v * v);
        s->tris[p] = (uint32_t)tp_patch_triangles(s->vbuf, k, NULL, 0);
    }
    return s->tris[p];
}

/* Samples a patch owns (each grid sample belongs to exactly one patch). */
static double owned_samples(const tp_terrain* t, int p)
{
    int pc = t->info.patch_cols, pr = t->info.patch_rows, c = p % pc, r = p / pc;
    return (double)(c + 1 == pc ? t->ps + 1 : t->ps) * (double)(r + 1 == pr ? t->ps + 1 : t->ps);
}

void tp_selection_stats(const tp_selection* cs, tp_frame_stats* out)
{
    /* Only the triangle-count cache is written here. */
    tp_selection* s = (tp_selection*)cs;
    memset(out, 0, sizeof *out);
    double sum = 0, weight = 0;
    for (int p = 0; p < s->count; p++) {
        if (!s->visible[p]) {
            out->culled_patches++;
            continue;
        }
        out->visible_patches++;
        out->patches_per_level[s->level[p]]++;
        out->triangles += patch_triangle_count(s, p);
        int nb[4];
        tp_selection_neighbor_levels(s, p, nb);
        double b = tp_patch_error_bound(s->t, p, s->level[p], nb), w = owned_samples(s->t, p);
        out->bound_max_error_m = b > out->bound_max_error_m ? b : out->bound_max_error_m;
        sum += w * b * b;
        weight += w;
    }
    out->bound_rms_error_m = weight > 0 ? sqrt(sum / weight) : 0;
}

/* ---- exact measurement over the drawn triangles ---- */

typedef struct {
    const tp_terrain* t;
    uint8_t* seen; /* one bit per grid sample */
    const tp__view* view;
    double max, sum;
    size_t count;
} measure;

static int first_visit(measure* m, int x, int y)
{
    if (!m->seen) /* one patch: a maximum needs no deduplication */
        return 1;
    size_t i = (size_t)y * m->t->w + x;
    if (m->seen[i >> 3] >> (i & 7) & 1)
        return 0;
    m->seen[i >> 3] |= (uint8_t)(1u << (i & 7));
    return 1;
}

static void vertical_sample(int x, int y, double z, void* user)
{
    measure* m = user;
    int32_t q = tp__q(m->t, x, y);
    if (q == INT32_MIN || !first_visit(m, x, y))
        return;
    double e = fabs(z - q) * m->t->step;
    m->max = e > m->max ? e : m->max;
    m->sum += e * e;
    m->count++;
}

static void to_camera(const tp__view* v, const double w[3], double c[3])
{
    double d[3] = {w[0] - v->pos[0], w[1] - v->pos[1], w[2] - v->pos[2]};
    c[0] = d[0] * v->right[0] + d[1] * v->right[1] + d[2] * v->right[2];
    c[1] = d[0] * v->up[0] + d[1] * v->up[1] + d[2] * v->up[2];
    c[2] = d[0] * v->fwd[0] + d[1] * v->fwd[1] + d[2] * v->fwd[2];
}

static void screen_sample(int x, int y, double z, void* user)
{
    measure* m = user;
    const tp__view* v = m->view;
    int32_t q = tp__q(m->t, x, y);
    if (q == INT32_MIN)
        return;
    double ws[3], wd[3], cs[3], cd[3];
    tp_terrain_grid_to_world(m->t, x, y, &ws[0], &ws[1]);
    wd[0] = ws[0];
    wd[1] = ws[1];
    ws[2] = q * m->t->step;
    wd[2] = z * m->t->step;
    to_camera(v, ws, cs);
    /* Only samples inside the view and in front of the near plane count. */
    if (cs[2] < v->near_m || (v->far_m > 0 && cs[2] > v->far_m) ||
        fabs(cs[0]) > v->tan_x * cs[2] || fabs(cs[1]) > v->tan_y * cs[2])
        return;
    if (!first_visit(m, x, y))
        return;
    to_camera(v, wd, cd);
    double e;
    if (wd[2] == ws[2])
        e = 0;
    else if (cd[2] <= 0)
        e = INFINITY;
    else {
        double du = v->f_px * (cd[0] / cd[2] - cs[0] / cs[2]);
        double dv = v->f_px * (cd[1] / cd[2] - cs[1] / cs[2]);
        e = sqrt(du * du + dv * dv);
    }
    m->max = e > m->max ? e : m->max;
    m->sum += e * e;
    m->count++;
}

/* Rasterises patch p's triangles at level k (neighbour levels nb) through fn. */
static void measure_patch(tp_selection* s, measure* m, tp__sample_fn fn, int p, int k,
                          const int nb[4])
{
    const tp_terrain* t = s->t;
    size_t v = ((size_t)1 << t->n) + 1, vcap = v * v, tcap = 2 * (v - 1) * (v - 1);
    tp_patch_vertices(t, p, k, nb, s->vbuf, vcap);
    size_t nt = tp_patch_triangles(s->vbuf, k, s->tbuf, tcap);
    for (size_t i = 0; i < nt; i++) {
        const tp_vertex* a = &s->vbuf[s->tbuf[3 * i]];
        const tp_vertex* b = &s->vbuf[s->tbuf[3 * i + 1]];
        const tp_vertex* c = &s->vbuf[s->tbuf[3 * i + 2]];
        int32_t pa[2] = {a->x, a->y}, pb[2] = {b->x, b->y}, pcv[2] = {c->x, c->y};
        tp__raster_triangle(pa, pb, pcv, tp__q(t, a->x, a->y), tp__q(t, b->x, b->y),
                            tp__q(t, c->x, c->y), fn, m);
    }
}

double tp_selection_patch_screen_error(const tp_selection* cs, const tp_camera* cam, int patch,
                                       int k)
{
    tp_selection* s = (tp_selection*)cs; /* scratch buffers only */
    if (!cam || patch < 0 || patch >= s->count || k < 0 || k > s->t->n)
        return NAN;
    tp__view v;
    tp__view_from_camera(cam, &v);
    measure m = {0};
    m.t = s->t;
    m.view = &v;
    int nb[4];
    tp_selection_neighbor_levels(s, patch, nb);
    measure_patch(s, &m, screen_sample, patch, k, nb);
    return m.max;
}

static tp_status measure_drawn(const tp_selection* cs, measure* m, tp__sample_fn fn)
{
    tp_selection* s = (tp_selection*)cs; /* scratch buffers only */
    const tp_terrain* t = s->t;
    m->t = t;
    m->seen = calloc(((size_t)t->w * t->h + 7) / 8, 1);
    if (!m->seen)
        return TP_ERR_OUT_OF_MEMORY;
    for (int p = 0; p < s->count; p++) {
        if (!s->visible[p])
            continue;
        int nb[4];
        tp_selection_neighbor_levels(s, p, nb);
        measure_patch(s, m, fn, p, s->level[p], nb);
    }
    free(m->seen);
    return TP_OK;
}

tp_status tp_selection_measure_error(const tp_selection* s, tp_error_measure* out)
{
    measure m = {0};
    tp_status st = measure_drawn(s, &m, vertical_sample);
    if (st != TP_OK)
        return st;
    out->max_error_m = m.max;
    out->rms_error_m = m.count ? sqrt(m.sum / m.count) : 0;
    out->samples = m.count;
    return TP_OK;
}

tp_status tp_selection_measure_screen_error(const tp_selection* s, const tp_camera* cam,
                                            double* max_px, double* rms_px, size_t* samples)
{
    tp__view v;
    tp__view_from_camera(cam, &v);
    measure m = {0};
    m.view = &v;
    tp_status st = measure_drawn(s, &m, screen_sample);
    if (st != TP_OK)
        return st;
    if (max_px)
        *max_px = m.max;
    if (rms_px)
        *rms_px = m.count ? sqrt(m.sum / m.count) : 0;
    if (samples)
        *samples = m.count;
    return TP_OK;
}

/* ---- queries against the drawn surface ---- */

/* Height (steps) of the stitched triangle of cell (cx, cy) half h containing (x, y), if any. */
static int cell_height(const tp_terrain* t, int p, int k, const int nb[4], int cx, int cy,
                       double x, double y, double* z)
{
    static const int tri[2][3][2] = {{{0, 0}, {0, 1}, {1, 0}}, {{1, 0}, {0, 1}, {1, 1}}};
    for (int h = 0; h < 2; h++) {
        int32_t pos[3][2];
        double q[3];
        int ok = 1;
        for (int v = 0; v < 3; v++) {
            int32_t ox, oy;
            tp__vertex_position(t, p, k, NULL, cx + tri[h][v][0], cy + tri[h][v][1], &ox, &oy);
            ok &= tp__q(t, ox, oy) != INT32_MIN;
            tp__vertex_position(t, p, k, nb, cx + tri[h][v][0], cy + tri[h][v][1], &pos[v][0],
                                &pos[v][1]);
            q[v] = tp__q(t, pos[v][0], pos[v][1]);
        }
        double area = (double)(pos[1][0] - pos[0][0]) * (pos[2][1] - pos[0][1]) -
                      (double)(pos[1][1] - pos[0][1]) * (pos[2][0] - pos[0][0]);
        if (!ok || area == 0)
            continue;
        double w[3];
        for (int v = 0; v < 3; v++) {
            const int32_t* a = pos[(v + 1) % 3];
            const int32_t* b = pos[(v + 2) % 3];
            w[v] = ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) / area;
        }
        const double eps = 1e-9;
        if (w[0] >= -eps && w[1] >= -eps && w[2] >= -eps) {
            *z = w[0] * q[0] + w[1] * q[1] + w[2] * q[2];
            return 1;
        }
    }
    return 0;
}

/* Drawn height (steps) of patch (px, py) at (x, y) inside it, or NaN. */
static double patch_drawn_height(const tp_selection* s, int px, int py, double x, double y)
{
    const tp_terrain* t = s->t;
    int p = py * t->info.patch_cols + px, k = s->level[p], nb[4], last = 1 << k;
    tp_selection_neighbor_levels(s, p, nb);
    double cell = (double)(t->ps >> k);
    double lx = (x - px * t->ps) / cell, ly = (y - py * t->ps) / cell;
    int cx = (int)lx < last ? (int)lx : last - 1, cy = (int)ly < last ? (int)ly : last - 1;
    double z;
    /* On a cell's left or top edge the point also lies in the cell before it. */
    for (int dy = 0; dy <= (ly == cy && cy > 0); dy++)
        for (int dx = 0; dx <= (lx == cx && cx > 0); dx++)
            if (cell_height(t, p, k, nb, cx - dx, cy - dy, x, y, &z))
                return z;
    /* The point is in a stitched border strip where moved vertices shifted the triangles:
     * search the strips of the sides whose neighbour is coarser. */
    for (int side = 0; side < 4; side++) {
        if (nb[side] < 0 || nb[side] >= k)
            continue;
        for (int i = 0; i < last; i++) {
            int ccx = side == TP_SIDE_LEFT ? 0 : side == TP_SIDE_RIGHT ? last - 1 : i;
            int ccy = side == TP_SIDE_TOP ? 0 : side == TP_SIDE_BOTTOM ? last - 1 : i;
            if (cell_height(t, p, k, nb, ccx, ccy, x, y, &z))
                return z;
        }
    }
    return NAN;
}

double tp_selection_drawn_height_at(const tp_selection* s, double x, double y)
{
    const tp_terrain* t = s->t;
    if (!(x >= 0 && y >= 0 && x <= t->w - 1 && y <= t->h - 1))
        return NAN;
    int pc = t->info.patch_cols, pr = t->info.patch_rows;
    int px = (int)x >> t->n, py = (int)y >> t->n;
    px = px < pc ? px : pc - 1;
    py = py < pr ? py : pr - 1;
    /* On a patch border the point belongs to the patch before it too. */
    int bx = px > 0 && x == px * t->ps, by = py > 0 && y == py * t->ps;
    for (int dy = 0; dy <= by; dy++)
        for (int dx = 0; dx <= bx; dx++) {
            double z = patch_drawn_height(s, px - dx, py - dy, x, y);
            if (!isnan(z))
                return z * t->step;
        }
    return NAN;
}

int tp_selection_keep_above(const tp_selection* s, double position[3], double clearance_m)
{
    double x, y;
    tp_terrain_world_to_grid(s->t, position[0], position[1], &x, &y);
    double a = tp_terrain_height_at(s->t, x, y), b = tp_selection_drawn_height_at(s, x, y);
    double ground = isnan(a) ? b : isnan(b) ? a : (a > b ? a : b);
    if (isnan(ground) || position[2] >= ground + clearance_m)
        return 0;
    position[2] = ground + clearance_m;
    return 1;
}
