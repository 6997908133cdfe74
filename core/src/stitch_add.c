/* stitch_add.c - crack removal by adding vertices (tp_core.h, tp_patch_triangles_add).
 *
 * Based on: Brodersen, "Real-time visualization of large textured terrains" (GRAPHITE 2005),
 * section 4: instead of moving the finer patch's border vertices onto the coarser lattice
 * (stitch.c, Vanek & Jezek), the coarser patch takes the finer neighbour's extra border
 * vertices. A patch is five regions: its interior, drawn as the regular grid of its level, and
 * four border strips, each re-triangulated between the patch's side (with the added vertices)
 * and the first inner row by a zipper that advances along whichever chain is behind. A level-0
 * patch has no inner row: it takes its centre sample and fans from it.
 */
#include "internal.h"

#include <assert.h>

typedef struct emit_ctx {
    uint32_t* tri;
    size_t cap, count;
    int side_samples; /* 2^n + 1 */
} emit_ctx;

/* Sample coordinates (x, y), 0 .. 2^n; triangles are given with a positive cross product in
 * (column, row) and written reversed, as the strips wind (tp_strip_build_u32). */
static void emit(emit_ctx* e, int ax, int ay, int bx, int by, int cx, int cy)
{
    if (e->count < e->cap) {
        uint32_t* t = e->tri + 3 * e->count;
        t[0] = (uint32_t)(ay * e->side_samples + ax);
        t[1] = (uint32_t)(cy * e->side_samples + cx);
        t[2] = (uint32_t)(by * e->side_samples + bx);
    }
    e->count++;
}

/* Side s's point at u along it (0 .. full, clockwise around the patch from its first corner),
 * d in from the border: TOP left to right, RIGHT top to bottom, BOTTOM
 * right to left, LEFT bottom to top. */
static void side_point(int s, int full, int d, int u, int* x, int* y)
{
    switch (s) {
    case TP_SIDE_TOP: *x = u, *y = d; break;
    case TP_SIDE_RIGHT: *x = full - d, *y = u; break;
    case TP_SIDE_BOTTOM: *x = full - u, *y = full - d; break;
    default: *x = d, *y = full - u; break;
    }
}

size_t tp_patch_triangles_add(int n, int k, const int neighbor_levels[4], uint32_t* triangles,
                              size_t triangle_capacity)
{
    assert(n >= 0 && n <= TP_MAX_N && k >= 0 && k <= n);
    assert(triangles || triangle_capacity == 0);
    const int full = 1 << n, step = 1 << (n - k), cells = 1 << k;
    emit_ctx e = {triangles, triangle_capacity, 0, full + 1};
    int stride[4], adds = 0;
    for (int s = 0; s < 4; ++s) {
        const int nb = neighbor_levels ? neighbor_levels[s] : TP_NO_NEIGHBOR;
        const int kn = nb > n ? n : nb;
        stride[s] = nb != TP_NO_NEIGHBOR && kn > k ? 1 << (n - kn) : step;
        adds |= stride[s] != step;
    }
    if (k == 0 && adds) { /* no inner row: a fan from the centre sample */
        const int c = full / 2;
        for (int s = 0; s < 4; ++s)
            for (int u = 0; u < full; u += stride[s]) {
                int ax, ay, bx, by;
                side_point(s, full, 0, u, &ax, &ay);
                side_point(s, full, 0, u + stride[s], &bx, &by);
                emit(&e, ax, ay, bx, by, c, c);
            }
        return e.count;
    }
    /* the regular grid: every cell when nothing is added, else the interior only */
    const int first = adds ? 1 : 0, last = adds ? cells - 1 : cells;
    for (int r = first; r < last; ++r)
        for (int c = first; c < last; ++c) {
            const int x0 = c * step, y0 = r * step, x1 = x0 + step, y1 = y0 + step;
            emit(&e, x0, y0, x1, y0, x0, y1); /* split from (c+1, r) to (c, r+1) */
            emit(&e, x1, y0, x1, y1, x0, y1);
        }
    if (!adds)
        return e.count;
    /* the border strips: outer chain 0 .. full by stride[s], inner chain step .. full - step
       (one vertex, the centre, for k = 1) */
    for (int s = 0; s < 4; ++s) {
        int uo = 0, ui = step;
        while (uo < full || ui < full - step) {
            int ox, oy, ix, iy, nx, ny;
            side_point(s, full, 0, uo, &ox, &oy);
            side_point(s, full, step, ui, &ix, &iy);
            const int advance_outer =
                ui >= full - step || (uo < full && uo + stride[s] <= ui + step);
            if (advance_outer) {
                side_point(s, full, 0, uo + stride[s], &nx, &ny);
                emit(&e, ox, oy, nx, ny, ix, iy);
                uo += stride[s];
            } else {
                side_point(s, full, step, ui + step, &nx, &ny);
                emit(&e, ox, oy, nx, ny, ix, iy);
                ui += step;
            }
        }
    }
    return e.count;
}
