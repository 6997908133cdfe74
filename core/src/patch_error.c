/* patch_error.c - per-patch error tables: delta_k and the stitching bounds.
 *
 * delta_k (Brodersen section 3): the largest vertical distance between a full-resolution sample
 * of the patch and the level-k triangulation (same split as the strips).
 *
 * Stitching: crack removal moves border vertices (stitch.c), so the border triangles belong to
 * neither level's triangulation and their error can exceed both patches' delta. For every side
 * and every neighbour level kn < n we store eps[side][kn]: the largest error of any triangle
 * with a vertex moved by that side, over every level k > kn of this patch. With nearest-vertex
 * snapping toward the corners, a triangle with vertices moved by two sides collapses for k >= 2
 * (the vertices next to a corner both snap onto it), so one side at a time is exact there; at
 * k = 1 all 16 combinations of moved sides are measured.
 *
 * Errors are measured against the decoded grid, in units of err_unit steps, rounded up.
 * err_unit is step/16 unless some patch spans so many steps that its largest possible error
 * (its height range) would not fit 16 bits; then the finest power of two that fits.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

static uint16_t to_units(const tp_terrain* t, double err_steps)
{
    double u = ceil(err_steps / t->err_unit - 1e-9);
    return u >= TP__ERR_SAT ? (uint16_t)TP__ERR_SAT : (uint16_t)(u < 0 ? 0 : u);
}

/* One patch's samples decoded once (global quantised heights, INT32_MIN = not drawn): every
 * error below reads them many times. */
typedef struct {
    int x0, y0, side;
    int32_t* q;
} patch_grid;

static inline int32_t pq(const patch_grid* g, int x, int y)
{
    return g->q[(size_t)(y - g->y0) * g->side + (x - g->x0)];
}

typedef struct {
    const patch_grid* g;
    double max; /* in steps */
} err_acc;

static void acc_sample(int x, int y, double z, void* user)
{
    err_acc* a = user;
    int32_t q = pq(a->g, x, y);
    if (q == INT32_MIN)
        return;
    double e = fabs(z - q);
    a->max = e > a->max ? e : a->max;
}

/* delta_k in steps for the unstitched level-k triangulation of a patch. */
static double level_error(const tp_terrain* t, const patch_grid* g, int k)
{
    int x0 = g->x0, y0 = g->y0;
    int s = 1 << (t->n - k), cells = 1 << k;
    double mx = 0;
    for (int cy = 0; cy < cells; cy++)
        for (int cx = 0; cx < cells; cx++) {
            int xa = x0 + cx * s, ya = y0 + cy * s;
            int32_t q00 = pq(g, xa, ya), q10 = pq(g, xa + s, ya);
            int32_t q01 = pq(g, xa, ya + s), q11 = pq(g, xa + s, ya + s);
            int lower = q00 != INT32_MIN && q10 != INT32_MIN && q01 != INT32_MIN;
            int upper = q11 != INT32_MIN && q10 != INT32_MIN && q01 != INT32_MIN;
            for (int j = 0; j <= s; j++)
                for (int i = 0; i <= s; i++) {
                    int32_t q = pq(g, xa + i, ya + j);
                    if (q == INT32_MIN)
                        continue;
                    double fx = (double)i / s, fy = (double)j / s, z;
                    /* Exact: i/s is dyadic and heights are integers. */
                    if (i + j <= s && lower)
                        z = q00 + fx * ((double)q10 - q00) + fy * ((double)q01 - q00);
                    else if (i + j >= s && upper)
                        z = q11 + (1 - fx) * ((double)q01 - q11) + (1 - fy) * ((double)q10 - q11);
                    else
                        continue;
                    double e = fabs(z - q);
                    mx = e > mx ? e : mx;
                }
        }
    return mx;
}

/* Vertex (i, j) of level k lies on which side (-1 for none or a corner)? */
static int side_of(int i, int j, int last)
{
    int corner = (i == 0 || i == last) && (j == 0 || j == last);
    if (corner)
        return -1;
    if (j == 0)
        return TP_SIDE_TOP;
    if (i == last)
        return TP_SIDE_RIGHT;
    if (j == last)
        return TP_SIDE_BOTTOM;
    if (i == 0)
        return TP_SIDE_LEFT;
    return -1;
}

/* Measures the stitched triangles of cells [cx0, cx1) x [cy0, cy1) of patch p at level k with
 * neighbour levels nb; each triangle's error (steps) is folded into out[side] for every side
 * that moved one of its vertices. */
static void stitched_error(const tp_terrain* t, const patch_grid* g, int p, int k,
                           const int nb[4], int cx0, int cx1, int cy0, int cy1, double out[4])
{
    int last = 1 << k;
    for (int cy = cy0; cy < cy1; cy++)
        for (int cx = cx0; cx < cx1; cx++) {
            /* The two triangles of the cell, in strip winding. */
            static const int tri[2][3][2] = {{{0, 0}, {0, 1}, {1, 0}}, {{1, 0}, {0, 1}, {1, 1}}};
            for (int h = 0; h < 2; h++) {
                int32_t pos[3][2];
                double z[3];
                int sides = 0, drawn = 1;
                for (int v = 0; v < 3; v++) {
                    int i = cx + tri[h][v][0], j = cy + tri[h][v][1];
                    int32_t ox, oy;
                    tp__vertex_position(t, p, k, NULL, i, j, &ox, &oy);
                    if (pq(g, ox, oy) == INT32_MIN)
                        drawn = 0;
                    if (tp__vertex_position(t, p, k, nb, i, j, &pos[v][0], &pos[v][1]))
                        sides |= 1 << side_of(i, j, last);
                    int32_t q = pq(g, pos[v][0], pos[v][1]);
                    drawn &= q != INT32_MIN;
                    z[v] = q;
                }
                if (!sides || !drawn)
                    continue;
                err_acc a = {g, 0};
                tp__raster_triangle(pos[0], pos[1], pos[2], z[0], z[1], z[2], acc_sample, &a);
                for (int s = 0; s < 4; s++)
                    if (sides >> s & 1)
                        out[s] = a.max > out[s] ? a.max : out[s];
            }
        }
}

tp_status tp__patch_errors_compute(tp_terrain* t, tp_error* err)
{
    int n = t->n, pc = t->info.patch_cols, count = pc * t->info.patch_rows;
    patch_grid g = {0, 0, t->ps + 1,
                    tp__alloc(&t->alloc, (size_t)(t->ps + 1) * (t->ps + 1), sizeof(int32_t))};
    if (!g.q)
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "terrain: out of memory for error tables");
    int32_t span = 0;
    for (int p = 0; p < count; p++)
        span = t->patches[p].qmax - t->patches[p].qmin > span ? t->patches[p].qmax - t->patches[p].qmin
                                                               : span;
    t->err_unit = 1.0 / 16;
    while (t->err_unit < 1 && span / t->err_unit > 65534.0)
        t->err_unit *= 2;
    for (int p = 0; p < count; p++) {
        uint16_t* tab = t->err_tab + (size_t)p * t->err_stride;
        int x0 = (p % pc) * t->ps, y0 = (p / pc) * t->ps;
        if (!t->patches[p].has_drawn)
            continue;
        g.x0 = x0;
        g.y0 = y0;
        for (int y = 0; y < g.side; y++)
            for (int x = 0; x < g.side; x++)
                g.q[y * g.side + x] = tp__q(t, x0 + x, y0 + y);
        for (int k = 0; k <= n; k++)
            tab[k] = to_units(t, level_error(t, &g, k));
        double eps[4][TP_MAX_N];
        memset(eps, 0, sizeof eps);
        for (int k = 1; k <= n; k++) {
            int cells = 1 << k;
            for (int kn = 0; kn < k; kn++)
                for (int s = 0; s < 4; s++) {
                    int nb[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
                    nb[s] = kn;
                    double e[4] = {0, 0, 0, 0};
                    /* Only the strip of cells along side s has moved vertices. */
                    int cx0 = s == TP_SIDE_RIGHT ? cells - 1 : 0;
                    int cx1 = s == TP_SIDE_LEFT ? 1 : cells;
                    int cy0 = s == TP_SIDE_BOTTOM ? cells - 1 : 0;
                    int cy1 = s == TP_SIDE_TOP ? 1 : cells;
                    stitched_error(t, &g, p, k, nb, cx0, cx1, cy0, cy1, e);
                    eps[s][kn] = e[s] > eps[s][kn] ? e[s] : eps[s][kn];
                }
            if (k == 1) /* every side touches every cell: measure all combinations */
                for (int mask = 1; mask < 16; mask++) {
                    int nb[4];
                    for (int s = 0; s < 4; s++)
                        nb[s] = mask >> s & 1 ? 0 : TP_NO_NEIGHBOR;
                    double e[4] = {0, 0, 0, 0};
                    stitched_error(t, &g, p, 1, nb, 0, 2, 0, 2, e);
                    for (int s = 0; s < 4; s++)
                        eps[s][0] = e[s] > eps[s][0] ? e[s] : eps[s][0];
                }
        }
        for (int s = 0; s < 4; s++)
            for (int kn = 0; kn < n; kn++)
                /* Interpolation at moved vertices is not exact: round up generously. */
                tab[n + 1 + s * n + kn] = to_units(t, eps[s][kn] + 1e-6);
    }
    tp__free(&t->alloc, g.q);
    return TP_OK;
}

double tp_patch_error_bound(const tp_terrain* t, int patch, int k, const int neighbor_levels[4])
{
    assert(t && patch >= 0 && patch < t->info.patch_count && k >= 0 && k <= t->n);
    const tp__patch* P = &t->patches[patch];
    unsigned units = tp__delta_tab(t, patch)[k];
    for (int s = 0; neighbor_levels && s < 4; s++) {
        int kn = neighbor_levels[s];
        if (kn >= 0 && kn < k) {
            unsigned e = tp__eps_tab(t, patch, s)[kn];
            units = e > units ? e : units;
        }
    }
    /* A saturated entry falls back to the patch's height range, which bounds any error. */
    double steps = units >= TP__ERR_SAT ? (double)(P->qmax - P->qmin) : units * t->err_unit;
    double range = (double)(P->qmax - P->qmin);
    return (steps < range ? steps : range) * t->step + t->quant_err;
}
