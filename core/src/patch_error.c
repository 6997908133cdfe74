/* patch_error.c - per-patch error tables: delta_k and the stitching bounds.
 *
 * The lattice computations themselves (delta_k, the stitched triangles' eps) live in
 * node_meta.c, shared with the tree's nodes: a patch is one lattice of (2^n+1)^2 samples, and
 * measuring at its own samples is exact since it holds every sample of its area.
 *
 * Errors are measured against the decoded grid, in units of err_unit steps, rounded up.
 * err_unit is step/16 unless some patch spans so many steps that its largest possible error
 * (its height range) would not fit 16 bits; then the finest power of two that fits.
 */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

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
