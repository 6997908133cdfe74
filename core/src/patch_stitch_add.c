/* patch_stitch_add.c - crack removal by adding vertices (tp_core.h, tp_patch_triangles_add).
 *
 * Based on: Brodersen, "Real-time visualization of large textured terrains" (GRAPHITE 2005),
 * section 4: instead of moving the finer patch's border vertices onto the coarser lattice
 * (patch_stitch.c, Vanek & Jezek), the coarser patch takes the finer neighbour's extra border
 * vertices. The paper's five regions (the interior and four border strips) are kept as small
 * as they can be: the patch is the level's grid, every cell split from (c + 1, r) to (c, r + 1)
 * as the strip splits it, and only a grid triangle with an edge on a side that takes vertices
 * is re-triangulated, inside itself. Each cell's upper-left triangle holds its top and left
 * edges, its lower-right one its right and bottom edges, so a triangle takes the vertices of at
 * most two sides, both meeting at its right-angle corner: it is zipped between those two
 * chains (a fan from the opposite vertex when one side takes nothing). The result refines the
 * grid triangulation: every drawn triangle lies inside one of the level's grid triangles.
 */
#include "internal.h"
#include "tp_terrain.h"

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

/* One grid triangle (O, O + len * q, O + len * p), positive in (column, row), q and p unit
 * axis vectors: its edge along q holds a vertex every sq samples, its edge along p one every
 * sp (len when nothing is added there). Zipped from the far edge (the cell's diagonal) toward
 * the corner O, advancing the chain whose current vertex is farther from O (q on a tie), and
 * closed by the triangle at O; with nothing added, the triangle itself. */
static void corner_triangle(emit_ctx* e, int ox, int oy, int qx, int qy, int px, int py, int len,
                            int sq, int sp)
{
    int i = len, j = len; /* current vertices: O + i * q and O + j * p (sample units) */
    while (i > sq || j > sp) {
        if (i > sq && (j <= sp || i >= j)) {
            emit(e, ox + (i - sq) * qx, oy + (i - sq) * qy, ox + i * qx, oy + i * qy, ox + j * px,
                 oy + j * py);
            i -= sq;
        } else {
            emit(e, ox + i * qx, oy + i * qy, ox + j * px, oy + j * py, ox + (j - sp) * px,
                 oy + (j - sp) * py);
            j -= sp;
        }
    }
    emit(e, ox, oy, ox + i * qx, oy + i * qy, ox + j * px, oy + j * py);
}

size_t tp_patch_triangles_add(int n, int k, const int neighbor_levels[4], uint32_t* triangles,
                              size_t triangle_capacity)
{
    assert(n >= 0 && n <= TP_MAX_N && k >= 0 && k <= n);
    assert(triangles || triangle_capacity == 0);
    const int full = 1 << n, step = 1 << (n - k), cells = 1 << k;
    emit_ctx e = {triangles, triangle_capacity, 0, full + 1};
    int stride[4]; /* per side: the distance between its vertices (step: nothing added) */
    for (int s = 0; s < 4; ++s) {
        const int nb = neighbor_levels ? neighbor_levels[s] : TP_NO_NEIGHBOR;
        const int kn = nb > n ? n : nb;
        stride[s] = nb != TP_NO_NEIGHBOR && kn > k ? 1 << (n - kn) : step;
    }
    for (int r = 0; r < cells; ++r)
        for (int c = 0; c < cells; ++c) {
            const int x0 = c * step, y0 = r * step, x1 = x0 + step, y1 = y0 + step;
            /* upper left: corner (x0, y0), the top edge toward +x, the left edge toward +y */
            corner_triangle(&e, x0, y0, 1, 0, 0, 1, step, r == 0 ? stride[TP_SIDE_TOP] : step,
                            c == 0 ? stride[TP_SIDE_LEFT] : step);
            /* lower right: corner (x1, y1), the bottom edge toward -x, the right edge toward
               -y */
            corner_triangle(&e, x1, y1, -1, 0, 0, -1, step,
                            r == cells - 1 ? stride[TP_SIDE_BOTTOM] : step,
                            c == cells - 1 ? stride[TP_SIDE_RIGHT] : step);
        }
    return e.count;
}
