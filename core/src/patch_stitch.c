/* patch_stitch.c - crack removal by moving vertices on tp_terrain's patches, and the triangles a
 * patch really draws: the patch's level-k lattice (lattice.c, which gives the rule and its
 * sources) placed on the grid and read from the decoded heights.
 */
#include "terrain_int.h"

int tp__vertex_position(const tp_terrain* t, int patch, int k, const int nb[4], int i, int j,
                        int32_t* gx, int32_t* gy)
{
    int pc = t->info.patch_cols, s = 1 << (t->n - k);
    int x0 = (patch % pc) * t->ps, y0 = (patch / pc) * t->ps;
    int mi, mj;
    int moved = tp__lattice_vertex(k, nb, i, j, &mi, &mj);
    *gx = x0 + mi * s;
    *gy = y0 + mj * s;
    return moved;
}

void tp_patch_vertices(const tp_terrain* t, int patch, int k, const int neighbor_levels[4],
                       tp_vertex* vertices, size_t vertex_capacity)
{
    assert(t && patch >= 0 && patch < t->info.patch_count && k >= 0 && k <= t->n && vertices);
    int v = (1 << k) + 1;
    assert(vertex_capacity >= (size_t)v * v);
    (void)vertex_capacity; /* only asserted */
    for (int j = 0; j < v; j++)
        for (int i = 0; i < v; i++) {
            tp_vertex* out = &vertices[j * v + i];
            int32_t ox, oy;
            tp__vertex_position(t, patch, k, NULL, i, j, &ox, &oy);
            tp__vertex_position(t, patch, k, neighbor_levels, i, j, &out->x, &out->y);
            /* A moved vertex takes its target's height (and so its normal). */
            out->z_m = (float)tp_terrain_sample(t, out->x, out->y);
            out->cls = (uint8_t)tp_terrain_sample_class(t, ox, oy);
        }
}

size_t tp_patch_triangles(const tp_vertex* vertices, int k, uint32_t* triangles,
                          size_t triangle_capacity)
{
    return tp__strip_triangles(vertices, k, NULL, NULL, triangles, triangle_capacity);
}
