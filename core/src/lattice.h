/* lattice.h - the level-k vertex lattice of (2^n+1)^2 samples that tp_terrain's patches and a
 * tree's nodes share: crack removal on it and the triangles its strip draws (lattice.c), its
 * error tables (lattice_error.c), and the rasteriser that measures triangles over the sample
 * lattice (triangle_raster.c). Depends on no other module's private state. */
#ifndef TP_CORE_LATTICE_H
#define TP_CORE_LATTICE_H

#include "internal.h"
#include "tp_terrain.h"
#include "tp_tree.h"

/* Error tables are uint16 in units of err_unit steps (step/16, or coarser when a patch's height
 * range would not fit), rounded up. TP__ERR_SAT means "at least this large": the bound then
 * falls back to the patch's height range, which bounds any error inside the patch. */
#define TP__ERR_SAT 0xFFFFu

/* Crack removal on the level-k vertex lattice (0..2^k per side) of a patch or tree node:
 * writes where vertex (i, j) goes against the given neighbour levels (NULL: nowhere), in
 * level-k vertex units. Returns 1 if it was moved (lattice.c). */
int tp__lattice_vertex(int k, const int nb[4], int i, int j, int* mi, int* mj);

/* Position (global grid coordinates) of vertex (i, j) of node `node` of a tree geometry at level
 * k after crack removal against the given neighbour levels (vertex stride 2^(n-k+s) grid
 * samples), for the tree's selection and its tests (lattice.c). Returns 1 if it was moved. */
int tp__node_vertex_position(const tp_tree_geometry* g, int64_t node, int k, const int nb[4], int i,
                             int j, int32_t* gx, int32_t* gy);

/* tp_patch_triangles with another rule: keep(a, b, c, user) says whether the strip's
 * triangle (a, b, c) is drawn (NULL: when its three vertices are). Zero-area triangles are
 * skipped either way (lattice.c). */
typedef int (*tp__tri_keep)(const tp_vertex* a, const tp_vertex* b, const tp_vertex* c, void* user);
size_t tp__strip_triangles(const tp_vertex* vertices, int k, tp__tri_keep keep, void* user,
                           uint32_t* triangles, size_t triangle_capacity);

/* The bounding box of a triangle's 3 lattice or grid positions: b = x0, y0, x1, y1. */
static inline void tp__tri_box(const int32_t pos[3][2], int32_t b[4])
{
    b[0] = b[2] = pos[0][0], b[1] = b[3] = pos[0][1];
    for (int v = 1; v < 3; v++) {
        b[0] = pos[v][0] < b[0] ? pos[v][0] : b[0];
        b[2] = pos[v][0] > b[2] ? pos[v][0] : b[2];
        b[1] = pos[v][1] < b[1] ? pos[v][1] : b[1];
        b[3] = pos[v][1] > b[3] ? pos[v][1] : b[3];
    }
}

/* The height at (x, y) of the triangle of grid positions pos with heights q, area its doubled
 * signed area (not 0): 1, writing *z, when the point is inside or on it (every barycentric
 * weight >= -1e-9), else 0. The drawn surface's queries (selection_query.c, cut_draw.c). */
static inline int tp__tri_height(const int32_t pos[3][2], const double q[3], double area, double x,
                                 double y, double* z)
{
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
    return 0;
}

/* ---- error tables over one lattice of (2^n+1)^2 samples (lattice_error.c) ----
 *
 * The lattice is a patch's samples, or a tree node's (every 2^s-th sample); q holds their
 * global quantised heights row-major, INT32_MIN where a sample is not drawn. Errors are in
 * steps. Both tp_terrain's patch tables (patch_error.c) and tree nodes' metas use these. */

/* Largest |S_k - q| over the lattice samples under the drawn triangles of the unstitched
 * level-k triangulation (delta_k of the lattice). mask NULL: a triangle is drawn when its
 * vertices are (a patch); else by the cell mask's rule (tp_node_mask_from_q: a node). */
double tp__lattice_level_error(int n, const int32_t* q, const uint16_t* mask, int k);

/* eps[side][kn], kn = 0..n-1: the largest error of any triangle with a vertex moved by a
 * neighbour at level kn on that side, over every level k > kn. cells = 0: measured at the lattice
 * samples the triangle covers (exact against the lattice samples: a patch, a leaf); cells = 1:
 * at every corner of every lattice cell the triangle touches, with the triangle's plane extended
 * there (a bound against the lattice's full-resolution surface S_n, see lattice_error.c). */
/* mask: as tp__lattice_level_error (with a mask, a leaf's level-n triangles still follow
 * their vertices: cells = 0 and k = n). */
void tp__lattice_eps(int n, const int32_t* q, const uint16_t* mask, int cells,
                     double eps[4][TP_MAX_N]);

/* The error (steps) of one triangle of lattice positions pos with heights z (steps) against the
 * lattice q (side samples a row): cells = 0, the largest |T - q| over the samples it covers
 * (closed; exact against a leaf's full resolution); cells = 1, its cell bound (every corner of
 * every lattice cell it touches, its plane extended there: a bound against the lattice's surface
 * S_n, as the eps tables of a node of scale >= 1 use). 0 for a triangle of zero area. */
double tp__lattice_triangle_error(const int32_t* q, int side, const int32_t pos[3][2],
                                  const int64_t z[3], int cells);

/* An error of `steps` in table units of unit_steps, rounded up; TP__ERR_SAT when it does not
 * fit. */
static inline uint16_t tp__err_units(double steps, double unit_steps)
{
    double u = ceil(steps / unit_steps - 1e-9);
    return u >= TP__ERR_SAT ? (uint16_t)TP__ERR_SAT : (uint16_t)(u < 0 ? 0 : u);
}

/* Rasterises triangle (a, b, c) in grid coordinates over the integer sample lattice: calls
 * fn(x, y, z_interp, user) for each sample inside or on the triangle, z interpolated linearly
 * from za, zb, zc (any units). Degenerate triangles are skipped. (triangle_raster.c) */
typedef void (*tp__sample_fn)(int x, int y, double z, void* user);
void tp__raster_triangle(const int32_t a[2], const int32_t b[2], const int32_t c[2], double za,
                         double zb, double zc, tp__sample_fn fn, void* user);
/* tp__raster_triangle over the samples clip[0] <= x <= clip[2], clip[1] <= y <= clip[3] only
 * (the same samples, heights and order as the whole triangle's, less those outside). */
void tp__raster_triangle_clip(const int32_t a[2], const int32_t b[2], const int32_t c[2],
                              double za, double zb, double zc, const int32_t clip[4],
                              tp__sample_fn fn, void* user);

#endif
