/* patch_error.c - per-patch error tables: delta_k and the stitching bounds.
 *
 * The lattice computations themselves (delta_k, the stitched triangles' eps) live in
 * lattice_error.c, shared with the tree's nodes: a patch is one lattice of (2^n+1)^2 samples, and
 * measuring at its own samples is exact since it holds every sample of its area.
 *
 * Errors are measured against the decoded grid, in units of err_unit steps, rounded up.
 * err_unit is step/16 unless some patch spans so many steps that its largest possible error
 * (its height range) would not fit 16 bits; then the finest power of two that fits.
 *
 * Vertex adding (patch_stitch_add.c) re-triangulates a grid triangle T with an edge on a side that
 * takes a finer neighbour's vertices into triangles inside T whose vertices are T's own and
 * the added ones. There the drawn surface is T's plane plus the linear interpolation of d,
 * d = height - plane at each added vertex (0 at T's corners), so its error is at most T's own
 * plus the largest |d| on T's edges. eta[side][k][kn] is the max of that over the side's grid
 * triangles with level-kn vertices added (the plane along an edge is the edge's
 * interpolation); tp_patch_error_bound_add takes the max of delta_k and the adding sides' eta.
 */
#include "terrain_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Sample u (0 .. 2^n) along side `side` of a patch's samples q ((2^n+1)^2, row-major), u
 * growing with x (TOP, BOTTOM) or y (LEFT, RIGHT). */
static int32_t side_q(const int32_t* q, int n, int side, int u)
{
    const int full = 1 << n, v = full + 1;
    switch (side) {
    case TP_SIDE_TOP: return q[u];
    case TP_SIDE_RIGHT: return q[u * v + full];
    case TP_SIDE_BOTTOM: return q[full * v + u];
    default: return q[u * v];
    }
}

/* Largest |height - the edge's interpolation| (steps) at the samples a < u < b of side `side`
 * that are multiples of stride: the offsets of the vertices added there. */
static double edge_offset(const int32_t* q, int n, int side, int a, int b, int stride)
{
    const double za = side_q(q, n, side, a), zb = side_q(q, n, side, b);
    double worst = 0;
    for (int u = a + stride; u < b; u += stride) {
        const double d = fabs(side_q(q, n, side, u) - (za + (zb - za) * (u - a) / (b - a)));
        worst = d > worst ? d : worst;
    }
    return worst;
}

/* Largest |height - plane| (steps) over the samples of the level-k grid triangle of cell
 * (x0, y0) .. + step: its upper-left half (upper) or lower-right one, both closed. */
static double grid_triangle_error(const int32_t* q, int n, int x0, int y0, int step, int upper)
{
    const int v = (1 << n) + 1, x1 = x0 + step, y1 = y0 + step;
    const double z00 = q[y0 * v + x0], z10 = q[y0 * v + x1], z01 = q[y1 * v + x0],
                 z11 = q[y1 * v + x1];
    double worst = 0;
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++) {
            const int d = (x - x0) + (y - y0);
            if (upper ? d > step : d < step)
                continue;
            const double plane =
                upper ? z00 + (z10 - z00) * (x - x0) / step + (z01 - z00) * (y - y0) / step
                      : z11 + (z01 - z11) * (x1 - x) / step + (z10 - z11) * (y1 - y) / step;
            const double e = fabs(q[y * v + x] - plane);
            worst = e > worst ? e : worst;
        }
    return worst;
}

/* The eta table (this file's header): eta[side][k][kn - 1], k < kn, in table units. For each
 * grid triangle T with an edge on the side: T's own error plus the largest offset of the level-kn
 * vertices on that edge, and on T's other patch-side edge (a corner triangle) the largest of
 * the level-n ones (whatever that side takes: the lattices nest); the max over T. */
static void side_eta(const tp_terrain* t, int n, const int32_t* q, uint16_t* eta)
{
    const int full = 1 << n;
    for (int k = 0; k < n; k++) {
        const int step = 1 << (n - k), cells = 1 << k;
        for (int side = 0; side < 4; side++) {
            double worst[TP_MAX_N + 1] = {0}; /* by kn, steps */
            for (int i = 0; i < cells; i++) {
                /* T: the side's triangle in its i-th border cell; the other side at a corner */
                int x0, y0, upper, other = -1;
                switch (side) {
                case TP_SIDE_TOP:
                    x0 = i * step, y0 = 0, upper = 1, other = i == 0 ? TP_SIDE_LEFT : -1;
                    break;
                case TP_SIDE_LEFT:
                    x0 = 0, y0 = i * step, upper = 1, other = i == 0 ? TP_SIDE_TOP : -1;
                    break;
                case TP_SIDE_RIGHT:
                    x0 = full - step, y0 = i * step, upper = 0;
                    other = i == cells - 1 ? TP_SIDE_BOTTOM : -1;
                    break;
                default:
                    x0 = i * step, y0 = full - step, upper = 0;
                    other = i == cells - 1 ? TP_SIDE_RIGHT : -1;
                    break;
                }
                const int a = i * step, oa = upper ? 0 : full - step;
                const double own = grid_triangle_error(q, n, x0, y0, step, upper);
                const double corner = other >= 0 ? edge_offset(q, n, other, oa, oa + step, 1) : 0;
                for (int kn = k + 1; kn <= n; kn++) {
                    const double off = edge_offset(q, n, side, a, a + step, 1 << (n - kn));
                    const double e = own + (off > corner ? off : corner);
                    worst[kn] = e > worst[kn] ? e : worst[kn];
                }
            }
            for (int kn = k + 1; kn <= n; kn++) /* not exact: round up generously, as eps */
                eta[(side * n + k) * n + (kn - 1)] = tp__err_units(worst[kn] + 1e-6, t->err_unit);
        }
    }
}

tp_status tp__patch_errors_compute(tp_terrain* t, tp_error* err)
{
    int n = t->n, pc = t->info.patch_cols, count = pc * t->info.patch_rows, side = t->ps + 1;
    int32_t* q = tp__alloc(&t->alloc, (size_t)side * side, sizeof(int32_t));
    if (!q)
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
        for (int y = 0; y < side; y++)
            for (int x = 0; x < side; x++)
                q[y * side + x] = tp__q(t, x0 + x, y0 + y);
        for (int k = 0; k <= n; k++)
            tab[k] = tp__err_units(tp__lattice_level_error(n, q, NULL, k), t->err_unit);
        double eps[4][TP_MAX_N];
        tp__lattice_eps(n, q, NULL, 0, eps);
        for (int s = 0; s < 4; s++)
            for (int kn = 0; kn < n; kn++)
                /* Interpolation at moved vertices is not exact: round up generously. */
                tab[n + 1 + s * n + kn] = tp__err_units(eps[s][kn] + 1e-6, t->err_unit);
    }
    tp__free(&t->alloc, q);
    return TP_OK;
}

tp_status tp_terrain_prepare_stitch_add(tp_terrain* t, tp_error* err)
{
    assert(t);
    if (t->add_tab)
        return TP_OK;
    const int n = t->n, pc = t->info.patch_cols, count = pc * t->info.patch_rows;
    const int side = t->ps + 1;
    const size_t stride = (size_t)4 * (size_t)n * (size_t)n;
    uint16_t* tab = tp__calloc(&t->alloc, (size_t)count * stride, sizeof *tab);
    int32_t* q = tp__alloc(&t->alloc, (size_t)side * side, sizeof(int32_t));
    if (!tab || !q) {
        tp__free(&t->alloc, tab);
        tp__free(&t->alloc, q);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY,
                        "terrain: out of memory for vertex adding's error table");
    }
    for (int p = 0; p < count; p++) {
        /* an incomplete patch is drawn at level n: adds nothing */
        if (!t->patches[p].has_drawn || !t->patches[p].complete)
            continue;
        const int x0 = (p % pc) * t->ps, y0 = (p / pc) * t->ps;
        for (int y = 0; y < side; y++)
            for (int x = 0; x < side; x++)
                q[y * side + x] = tp__q(t, x0 + x, y0 + y);
        side_eta(t, n, q, tab + (size_t)p * stride);
    }
    tp__free(&t->alloc, q);
    t->add_tab = tab;
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

double tp__patch_add_bound_m(const tp_terrain* t, int patch, int k, const int neighbor_levels[4])
{
    const tp__patch* P = &t->patches[patch];
    const int n = t->n;
    unsigned units = tp__delta_tab(t, patch)[k];
    for (int s = 0; neighbor_levels && s < 4 && k < n; s++) {
        const int kn = neighbor_levels[s] > n ? n : neighbor_levels[s];
        if (neighbor_levels[s] != TP_NO_NEIGHBOR && kn > k) {
            /* without the table (tp_terrain_prepare_stitch_add), the height range */
            const unsigned e = t->add_tab ? tp__eta_tab(t, patch, s, k)[kn - 1] : TP__ERR_SAT;
            units = e > units ? e : units;
        }
    }
    const double range = (double)(P->qmax - P->qmin);
    const double steps = units >= TP__ERR_SAT ? range : units * t->err_unit;
    return (steps < range ? steps : range) * t->step;
}

double tp_patch_error_bound_add(const tp_terrain* t, int patch, int k, const int neighbor_levels[4])
{
    assert(t && patch >= 0 && patch < t->info.patch_count && k >= 0 && k <= t->n);
    return tp__patch_add_bound_m(t, patch, k, neighbor_levels) + t->quant_err;
}
