/* lattice.c - the level-k vertex lattice of (2^n+1)^2 samples, a patch's or a tree node's:
 * where crack removal by moving vertices puts each vertex, and which triangles the level's strip
 * draws over it. Shared by tp_terrain's patches (patch_stitch.c), the error tables
 * (lattice_error.c) and the cut over a tree (cut_stitch.c, cut_draw.c).
 *
 * Based on: Vanek & Jezek, "Real-Time Terrain Visualization on PC" (WSCG 2004), section 3 and
 * Fig. 4: the strips stay fixed per level, so cracks are removed in the vertex data. A border
 * vertex of the finer patch that the coarser neighbour lacks is moved onto a vertex the
 * neighbour has. We snap to the NEAREST such vertex: snapping always one way folds triangles
 * over near a corner when the neighbour is two or more levels coarser. A tie (the vertex is
 * halfway) goes toward the nearer patch corner, so the vertices next to a corner collapse onto
 * it; the exact middle of a side (a tie only against a level-0 neighbour) goes around the patch
 * in a fixed rotation - TOP toward the first column, RIGHT toward the first row, BOTTOM toward
 * the last column, LEFT toward the last row - which, with the strips' diagonal, keeps the level-1
 * patch against four level-0 neighbours a clean fan of four triangles.
 */
#include "lattice.h"

/* Snap position a (0..last, in level-k vertex units) to a multiple of m. */
static int snap(int a, int m, int last, int toward_low_at_middle)
{
    int r = a % m;
    if (r == 0)
        return a;
    if (2 * r < m)
        return a - r;
    if (2 * r > m)
        return a + m - r;
    if (2 * a < last)
        return a - r;
    if (2 * a > last)
        return a + m - r;
    return toward_low_at_middle ? a - r : a + m - r;
}

int tp__lattice_vertex(int k, const int nb[4], int i, int j, int* mi_out, int* mj_out)
{
    int last = 1 << k;
    int mi = i, mj = j;
    if (nb) {
        int on_x_edge = (i == 0 || i == last), on_y_edge = (j == 0 || j == last);
        if (!(on_x_edge && on_y_edge)) { /* corners never move */
            int side = j == 0      ? TP_SIDE_TOP
                       : i == last ? TP_SIDE_RIGHT
                       : j == last ? TP_SIDE_BOTTOM
                       : i == 0    ? TP_SIDE_LEFT
                                   : -1;
            if (side >= 0 && nb[side] >= 0 && nb[side] < k) {
                int m = 1 << (k - nb[side]);
                switch (side) {
                case TP_SIDE_TOP: mi = snap(i, m, last, 1); break;
                case TP_SIDE_RIGHT: mj = snap(j, m, last, 1); break;
                case TP_SIDE_BOTTOM: mi = snap(i, m, last, 0); break;
                default: mj = snap(j, m, last, 0); break;
                }
            }
        }
    }
    *mi_out = mi;
    *mj_out = mj;
    return mi != i || mj != j;
}

int tp__node_vertex_position(const tp_tree_geometry* g, int64_t node, int k, const int nb[4], int i,
                             int j, int32_t* gx, int32_t* gy)
{
    assert(g && k >= 0 && k <= g->n);
    int s, c, r, mi, mj;
    tp_tree_node_locate(g, node, &s, &c, &r);
    int moved = tp__lattice_vertex(k, nb, i, j, &mi, &mj);
    int shift = g->n - k + s; /* vertex stride 2^(n-k+s) grid samples */
    *gx = (int32_t)(((int64_t)c << (g->n + s)) + ((int64_t)mi << shift));
    *gy = (int32_t)(((int64_t)r << (g->n + s)) + ((int64_t)mj << shift));
    return moved;
}

static int drawn(const tp_vertex* v)
{
    return v->cls == TP_SAMPLE_VALID || v->cls == TP_SAMPLE_FILLED;
}

size_t tp__strip_triangles(const tp_vertex* vertices, int k, tp__tri_keep keep, void* user,
                           uint32_t* triangles, size_t triangle_capacity)
{
    assert(vertices && k >= 0 && k <= TP_MAX_N && (triangles || triangle_capacity == 0));
    /* Decode the level's strip: triangle t is (i_t, i_t+1, i_t+2), odd ones swap the first two
     * so that all keep the same winding. */
    int v = (1 << k) + 1;
    size_t written = 0, pos = 0;
    uint32_t window[3] = {0, 0, 0};
    for (int row = 0; row + 1 < v; row++) {
        for (int c = 0; c < 2 * v + 2; c++, pos++) {
            uint32_t idx;
            int r = row, j;
            if (c < 2 * v) {
                j = row % 2 ? v - 1 - c / 2 : c / 2;
                idx = (uint32_t)((c % 2 == (row % 2 ? 0 : 1) ? r + 1 : r) * v + j);
            } else {
                idx = (uint32_t)(row % 2 ? (r + 1) * v : (r + 2) * v - 1);
            }
            window[0] = window[1];
            window[1] = window[2];
            window[2] = idx;
            if (pos < 2)
                continue;
            uint32_t a = window[0], b = window[1], c3 = window[2];
            if ((pos - 2) % 2) {
                uint32_t tmp = a;
                a = b;
                b = tmp;
            }
            const tp_vertex *A = &vertices[a], *B = &vertices[b], *C = &vertices[c3];
            if (keep ? !keep(A, B, C, user) : (!drawn(A) || !drawn(B) || !drawn(C)))
                continue;
            int64_t area = ((int64_t)B->x - A->x) * ((int64_t)C->y - A->y) -
                           ((int64_t)B->y - A->y) * ((int64_t)C->x - A->x);
            if (area == 0)
                continue; /* collapsed or zero-area */
            if (written < triangle_capacity) {
                triangles[3 * written + 0] = a;
                triangles[3 * written + 1] = b;
                triangles[3 * written + 2] = c3;
            }
            written++;
        }
    }
    return written;
}
