/* tp_terrain.h - the resident terrain: triangle strips, the quantised height grid and its queries,
 * patches and crack removal (strip.c, terrain.c, surface.c, patch_error.c, patch_stitch.c,
 * patch_stitch_add.c, triangle_raster.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_TERRAIN_H
#define TP_TERRAIN_H

#include "tp_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Triangle strips (one per level, shared by every patch of one size)
 *
 * The level-k patch has v = 2^k + 1 vertices per side, indexed row * v + col. Its strip is the
 * Vanek & Jezek construction: rows alternate direction and each row ends with two repeated
 * indices, so the whole patch is one GL_TRIANGLE_STRIP of (2v+2)(v-1) indices with degenerate
 * triangles between rows. Every cell (c, r)-(c+1, r+1) is split along the diagonal from
 * (c+1, r) to (c, r+1). Decoded with the GL strip rule (odd triangles swap their first two
 * vertices), every real triangle is clockwise in (column, row) coordinates, which is
 * counter-clockwise seen from above in (east, north) for a north-up grid (gt[1] > 0, gt[5] < 0).
 */

/* Returns the number of indices of the level-k strip, (2v+2)(v-1) with v = 2^k+1, for k in
 * 0..TP_MAX_N. Cannot fail. */
size_t tp_strip_index_count(int k);

/* Writes the level-k strip (k in 0..TP_MAX_N) into indices: exactly tp_strip_index_count(k)
 * elements, which index_capacity must be at least. The _u16 variant also requires v*v <= 65536,
 * i.e. k <= 7 (use _u32 beyond). Cannot fail. */
void tp_strip_build_u32(int k, uint32_t* indices, size_t index_capacity);
void tp_strip_build_u16(int k, uint16_t* indices, size_t index_capacity);

/* ---------------------------------------------------------------------------------------------
 * Terrain: the resident, quantised height grid with its per-patch tables
 */
typedef enum tp_fit {
    TP_FIT_DEFAULT = 0, /* = TP_FIT_PAD */
    TP_FIT_PAD,         /* add padding samples on the far edges (right and bottom); exact */
    TP_FIT_RESAMPLE     /* bilinear resample to the nearest multiple; georeference updated;
                           needs at least 2x2 samples (TP_ERR_INVALID_ARG otherwise) */
} tp_fit;

/* What a sample of the fitted grid is. Only VALID and FILLED samples are drawn. */
typedef enum tp_sample_class {
    TP_SAMPLE_VALID = 0,
    TP_SAMPLE_FILLED,  /* a void filled by interpolation: drawn, but marked */
    TP_SAMPLE_NODATA,  /* nodata / NaN in the source: never drawn */
    TP_SAMPLE_PADDING, /* added by TP_FIT_PAD: never drawn */
    TP_SAMPLE_OUTSIDE  /* the coordinates are outside the fitted grid */
} tp_sample_class;

typedef struct tp_terrain_desc {
    /* Source heights in metres, row-major, width * height values, row 0 first.
     * NaN or infinite values are nodata. The array is only read during tp_terrain_create. */
    const float* heights;
    size_t height_count;
    int width, height; /* >= 1 each */
    /* GDAL geotransform of the source. All zeros means (0, 1, 0, 0, 0, -1): 1 m north-up.
     * Rotated geotransforms (gt[2] or gt[4] non-zero) are rejected. */
    double geotransform[6];
    /* Optional: width * height flags, non-zero marking a sample filled by interpolation. */
    const uint8_t* filled;
    size_t filled_count;
    int patch_size;       /* 17, 33, 65, 129 or 257; 0 means TP_DEFAULT_PATCH_SIZE */
    tp_fit fit;           /* 0 means pad */
    double height_step_m; /* global quantisation step; 0 means automatic (see tp_terrain_create) */
    tp_allocator allocator; /* zero: malloc / free */
} tp_terrain_desc;

typedef struct tp_terrain tp_terrain;

/* Builds the resident terrain: fits the grid to (r*2^n+1) x (s*2^n+1), quantises heights to
 * 16 bits with ONE global step and per-patch integer offsets (a sample shared by two patches
 * decodes to the same value in both), and computes per patch its AABB, delta_k for every level
 * and the stitching error bounds.
 * Automatic step: 1 m when every valid height is an integer (exact for Int16 sources), else the
 * finest power of two 2^-p metres (p <= 10) for which every patch's height range fits 16 bits.
 * Returns TP_OK and sets *out to the new terrain (free it with tp_terrain_destroy). Fails with
 * TP_ERR_BAD_DATA if no sample is valid; TP_ERR_INVALID_ARG for sizes out of range, a height or
 * filled count that does not match width * height (also NULL heights), a patch size not listed,
 * a half-set allocator, a rotated geotransform, or an explicit step too fine for the data;
 * TP_ERR_OUT_OF_MEMORY. */
tp_status tp_terrain_create(const tp_terrain_desc* desc, tp_terrain** out, tp_error* err);
void tp_terrain_destroy(tp_terrain* t); /* accepts NULL */

typedef struct tp_terrain_info {
    int src_width, src_height; /* the grid given to tp_terrain_create */
    int width, height;         /* the fitted grid: patch_cols * 2^n + 1, patch_rows * 2^n + 1 */
    int patch_size;            /* 2^n + 1 */
    int n;                     /* finest level */
    int levels;                /* n + 1 */
    int patch_cols, patch_rows, patch_count;
    tp_fit fit;
    double fit_max_error_m, fit_rms_error_m; /* resample: error of the rendered full-resolution
                                                surface at the original valid posts; 0 for pad */
    double geotransform[6];                  /* of the fitted grid */
    double height_step_m;                    /* the global quantisation step */
    double quant_max_error_m;                /* max |source - decoded| over valid samples */
    double error_unit_m;                     /* resolution of the stored error tables: bounds
                                                are rounded up to it (step/16 .. step) */
    double min_height_m, max_height_m;       /* over drawn samples (decoded) */
    size_t valid_samples, filled_samples, nodata_samples, padding_samples; /* of the fitted grid */
    /* Resident terrain data by the program's own accounting. */
    size_t heights_bytes, mask_bytes, patch_table_bytes, resident_bytes;
    double bytes_per_source_sample; /* resident_bytes / (src_width * src_height) */
} tp_terrain_info;

/* Writes the terrain's sizes, errors and memory use into *out. Cannot fail. */
void tp_terrain_get_info(const tp_terrain* t, tp_terrain_info* out);

/* Query: returns the decoded height (metres) of sample (x, y); NaN if it is not drawn or
 * outside the grid. */
double tp_terrain_sample(const tp_terrain* t, int x, int y);
/* Query: returns what sample (x, y) is; TP_SAMPLE_OUTSIDE for any (x, y) outside the grid. */
tp_sample_class tp_terrain_sample_class(const tp_terrain* t, int x, int y);

/* Query: returns the height (metres) of the rendered full-resolution surface at grid
 * coordinates (x, y): the same triangle split as the strips (diagonal from (c+1, r) to
 * (c, r+1)). O(1). NaN only where no drawn triangle contains the point (a point on an edge or
 * vertex is on every triangle that touches it), outside the grid, or for NaN coordinates. */
double tp_terrain_height_at(const tp_terrain* t, double x, double y);

/* Query: the same surface over a plain grid, before any terrain exists: heights is
 * width * height floats, row-major, row 0 first, NaN = no height (height_count must be
 * width * height). Heights are used as given, not quantised, so on a terrain's own source grid
 * the result differs from tp_terrain_height_at by at most the quantisation error. NaN outside
 * the grid, where no triangle with three heights contains the point, and for grids under 2 x 2. */
double tp_grid_height_at(const float* heights, size_t height_count, int width, int height,
                         double x, double y);

/* Writes the unit surface normal (world frame: east, north, up) at sample (x, y), from central
 * differences of the decoded grid (one-sided at borders and next to undrawn samples; a slope
 * with no drawn neighbour counts as 0, so an isolated or outside sample gets (0, 0, 1)).
 * Cannot fail. */
void tp_terrain_normal(const tp_terrain* t, int x, int y, float normal[3]);

/* The slope rule of tp_terrain_normal along one axis, for heights a (before), c (here) and b
 * (after), spacing apart (NaN: no height): central where a and b are known, else one-sided
 * where c and one neighbour are, else 0. Every normal of the project (terrains, tree nodes,
 * the viewer's normal map) is made of it, so they agree wherever they see the same heights. */
double tp_slope3(double a, double c, double b, double spacing);

/* Convert between grid coordinates (x, y) and world (easting, northing) with the fitted grid's
 * geotransform; any finite coordinates, inside the grid or not. Cannot fail. */
void tp_terrain_grid_to_world(const tp_terrain* t, double x, double y, double* e, double* n);
void tp_terrain_world_to_grid(const tp_terrain* t, double e, double n, double* x, double* y);

/* ---------------------------------------------------------------------------------------------
 * Patches
 *
 * Patch p = row * patch_cols + col covers grid samples [col*2^n, (col+1)*2^n] x
 * [row*2^n, (row+1)*2^n]; neighbours share their border row/column.
 */
typedef enum tp_side {
    TP_SIDE_TOP = 0, /* the patch's first row (smallest y; north for a north-up grid) */
    TP_SIDE_RIGHT,   /* last column (largest x) */
    TP_SIDE_BOTTOM,  /* last row */
    TP_SIDE_LEFT     /* first column */
} tp_side;

/* Level given for a side that has no neighbour (terrain border): never causes a vertex move. */
#define TP_NO_NEIGHBOR (-1)

typedef struct tp_patch_info {
    int col, row;
    int x0, y0;          /* grid coordinates of the first sample */
    double aabb_min[3];  /* world: E, N, height */
    double aabb_max[3];
    int complete;        /* 1 if every sample is drawn; else the patch is always drawn at level n */
    /* delta_k + quantisation error: max vertical error (m) of the unstitched level-k
     * triangulation against the decoded samples of the patch, rounded up to error_unit_m,
     * plus quant_max_error_m: an upper bound of the error against the source. */
    double delta_m[TP_MAX_LEVELS];
} tp_patch_info;

/* Writes patch `patch`'s grid position, box and per-level errors into *out. Cannot fail. */
void tp_patch_get_info(const tp_terrain* t, int patch, tp_patch_info* out);

/* Returns an upper bound (metres, quantisation included) of the vertical error of patch `patch`
 * drawn at level k (0..n) with the given neighbour levels (indexed by tp_side; TP_NO_NEIGHBOR
 * for none; the array may be NULL for an unstitched patch) after crack removal, against every
 * source sample of the patch. Neighbours at level >= k do not move this patch's vertices; a
 * coarser neighbour does, and its stitched triangles are bounded by a per-side table. Cannot
 * fail. (It used to return INFINITY for a bad patch or k; those are now asserted.) */
double tp_patch_error_bound(const tp_terrain* t, int patch, int k, const int neighbor_levels[4]);

/* The same bound when cracks are removed by adding vertices (tp_patch_triangles_add, `--stitch
 * add`): a neighbour at a level above k (levels above n taken as n) adds its border vertices to
 * this patch's side, re-triangulating the grid triangles on that side inside themselves; others
 * change nothing. Such a triangle's surface is the grid triangle's plane plus the interpolated
 * offsets of the added vertices from it, so its error is at most the grid triangle's own plus
 * the largest offset on its edges: the bound is the max of delta_k and, for each side that
 * takes vertices, the max of that over its grid triangles (a per-side table per k and
 * neighbour level, made by tp_terrain_prepare_stitch_add; before that a side that takes
 * vertices is bounded by the patch's height range), plus quant_max_error_m. With nothing added
 * it is tp_patch_error_bound(t, patch, k, NULL). Cannot fail. */
double tp_patch_error_bound_add(const tp_terrain* t, int patch, int k,
                                const int neighbor_levels[4]);

/* Computes vertex adding's per-side table (above) for every patch: 8 n^2 bytes a patch (128
 * for patches of 17: half a byte per sample), so it is made only for a terrain drawn with
 * `--stitch add`, not with the other tables. Call it once before
 * tp_patch_error_bound_add or a selection with tp_selection_set_stitch_add is used (again: a
 * no-op). Not thread-safe against those readers. TP_ERR_OUT_OF_MEMORY (nothing changed). */
tp_status tp_terrain_prepare_stitch_add(tp_terrain* t, tp_error* err);

/* One vertex of a patch's vertex data, after crack removal: the global grid coordinates of the
 * sample it was moved to (or its own), and that sample's decoded height. */
typedef struct tp_vertex {
    int32_t x, y;
    float z_m;
    uint8_t cls; /* tp_sample_class of the ORIGINAL (unmoved) vertex */
} tp_vertex;

/* Writes the vertex data of a patch at level k (0..n): (2^k+1)^2 vertices in strip order
 * (row * v + col), which vertex_capacity must be at least. neighbor_levels may be NULL (no
 * neighbours: nothing moves).
 * Crack removal (Vanek & Jezek Fig. 4): where a neighbour is coarser (level < k), every border
 * vertex the neighbour lacks is moved onto the nearest vertex the neighbour has; ties go toward
 * the nearer patch corner, and the exact middle of a side (a tie only with a level-0 neighbour)
 * goes around the patch: TOP toward the first column, RIGHT toward the first row, BOTTOM toward
 * the last column, LEFT toward the last row. Corners never move. Both sides of a shared edge
 * then produce bit-identical positions. Cannot fail. (It used to return TP_ERR_INVALID_ARG
 * for a bad k or capacity; those are now asserted.) */
void tp_patch_vertices(const tp_terrain* t, int patch, int k, const int neighbor_levels[4],
                       tp_vertex* vertices, size_t vertex_capacity);

/* Triangles actually drawn from vertex data of level k (0..TP_MAX_N, (2^k+1)^2 vertices, as
 * tp_patch_vertices writes them) decoded through the level-k strip, in strip order and winding:
 * index triples into `vertices`, skipping degenerate triangles (two vertices at the same grid
 * position, or zero area) and triangles with a vertex that is not drawn. Returns the number of
 * such triangles (at most 2 * 4^k) and writes the first min(that, triangle_capacity) of them
 * (3 indices each); triangles may be NULL when triangle_capacity is 0, to count first and fill
 * second. Cannot fail. */
size_t tp_patch_triangles(const tp_vertex* vertices, int k, uint32_t* triangles,
                          size_t triangle_capacity);

/* Crack removal by adding vertices (Brodersen, section 4; `--stitch add`), the alternative to
 * moving them (tp_patch_vertices): the coarser patch's border takes its finer neighbour's
 * vertices, the finer patch moves nothing. The triangles of a level-k patch of a (2^n+1)^2
 * sample patch (n in 0..TP_MAX_N, k in 0..n) whose side s takes the vertices of a neighbour at
 * level neighbor_levels[s] in this patch's sample units (> k: every 2^(n - level)-th sample of
 * that side, levels above n taken as n; <= k or TP_NO_NEIGHBOR: the side's own level-k
 * vertices; the array may be NULL), as index triples of samples (row * (2^n + 1) + column),
 * wound as the strips' triangles (tp_strip_build_u32). The level-k grid, every cell split from
 * (c + 1, r) to (c, r + 1) as the strip splits it, in which only the grid triangles with an edge
 * on a side that takes vertices are re-triangulated, inside themselves: each is zipped between
 * its two short edges (a fan from its opposite vertex when only one takes vertices), so every
 * other triangle is the grid's own and every drawn triangle lies inside one grid triangle;
 * 2 * 4^k triangles plus one per added vertex. Every side then has exactly the vertices its
 * finer neighbour draws there, so shared edges match: watertight (tests/test_stitch_add.c
 * checks every configuration up to n = 5). Returns the number of triangles and writes the
 * first min(that, triangle_capacity) (triangles may be NULL for 0). Cannot fail. */
size_t tp_patch_triangles_add(int n, int k, const int neighbor_levels[4], uint32_t* triangles,
                              size_t triangle_capacity);

/* Rasterises a triangle onto the sample lattice: calls visit(x, y, z, user) for every grid
 * sample inside or on the triangle (a, b, c) (grid coordinates), with the height z linearly
 * interpolated there from za, zb, zc (any unit). Exact integer inside test; zero-area triangles
 * visit nothing. user may be NULL. Cannot fail. */
typedef void (*tp_sample_visitor)(int x, int y, double z, void* user);
void tp_triangle_rasterize(const int32_t a[2], const int32_t b[2], const int32_t c[2], double za,
                           double zb, double zc, tp_sample_visitor visit, void* user);

#ifdef __cplusplus
}
#endif
#endif /* TP_TERRAIN_H */
