/*
 * tp_core.h - the terrapatch core: a quantised height grid tiled into overlapping
 * (2^n+1)^2 patches, per-patch level of detail, shared degenerate triangle strips,
 * crack removal by moving vertices, AABB frustum culling and O(1) height queries.
 *
 * Pure C11 over libc and libm. This header is the documentation of the core.
 *
 * Based on:
 *   J. Vanek, B. Jezek, "Real-Time Terrain Visualization on PC", WSCG 2004
 *     (patches, levels, distance LoD, degenerate strips, moving vertices, AABB culling)
 *   A. Brodersen, "Real-Time Visualization of Large Textured Terrains", 2005
 *     (per-level maximum error delta_k, screen-space error threshold tau, < 2.5 bytes per sample)
 *
 * Conventions used everywhere in this header:
 *   - Grid coordinates (x, y) are (column, row) of the fitted grid; integer values are sample
 *     centres. Row 0 is the first row of the raster (north for a north-up DEM).
 *   - World coordinates are the DEM's projected CRS: easting, northing (metres for a projected
 *     DEM) and height in metres, as doubles. Sample (x, y) lies at
 *     E = gt[0] + (x + 0.5) * gt[1],  N = gt[3] + (y + 0.5) * gt[5]   (GDAL geotransform).
 *   - Levels: k = n is full resolution, k = 0 is the 2x2 patch (as in Vanek & Jezek).
 *   - Heights of samples that are not drawn (nodata, padding) and queries outside the grid are NaN.
 *
 * Failure: one convention for every function below (STYLE.md section 4).
 *   - Caller bugs are assert()ed at the top of the function, not reported: a NULL pointer where
 *     the function's comment does not allow NULL, a patch index outside 0..patch_count-1, a
 *     level k outside 0..n (0..TP_MAX_N where no terrain is involved), a capacity smaller than
 *     the size the comment gives. Check these before the call; under NDEBUG they are undefined.
 *   - Bad data and invalid values that can come from a user or a file (a number outside its
 *     documented range, NaN where a number is needed, a malformed grid) and running out of
 *     memory are reported: such a function returns tp_status, TP_OK on success, and delivers
 *     its results through out-parameters that it writes ONLY on success. On failure its inputs
 *     and outputs are left as they were and nothing is leaked. A trailing tp_error* err, where
 *     there is one, receives a one-line message on failure; err may be NULL.
 *   - A function that returns anything else (void, a count, a height, a class, a 1/0 answer)
 *     cannot fail once its arguments pass the asserts.
 *   - Queries return NaN for "no surface here" (nodata, padding, outside the grid, nothing
 *     drawn there), and tp_terrain_sample_class returns TP_SAMPLE_OUTSIDE outside the grid;
 *     that is an answer, not a failure. So is the 0 of a yes/no function (tp_camera_project,
 *     tp_selection_visible, tp_selection_dirty, tp_selection_keep_above answer 1 or 0).
 * Each comment below says what the function returns and what makes it fail; it repeats none of
 * this, only what differs (a pointer that may be NULL, a further condition).
 */
#ifndef TP_CORE_H
#define TP_CORE_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define TP_VERSION "0.1.0"

/* Largest supported n: patches of up to 2^8+1 = 257 samples per side. */
#define TP_MAX_N 8
#define TP_MAX_LEVELS (TP_MAX_N + 1)
#define TP_DEFAULT_PATCH_SIZE 17

/* ---------------------------------------------------------------------------------------------
 * Status and errors
 */
typedef enum tp_status {
    TP_OK = 0,
    TP_ERR_INVALID_ARG, /* value outside its documented range */
    TP_ERR_BAD_DATA,    /* input file or buffer malformed */
    TP_ERR_IO,
    TP_ERR_OUT_OF_MEMORY,
    TP_ERR_BACKEND /* a wrapped C++ library failed; see the message */
} tp_status;

/* Returns the short English name of a status ("invalid argument", ...); "unknown status" for a
 * value outside the enum. Never NULL; a static string. */
const char* tp_status_str(tp_status s);

/* Optional out-parameter of failing calls: a one-line message saying what was expected and
 * what was received. Functions that take a tp_error* accept NULL. On success it is untouched. */
typedef struct tp_error {
    char message[512];
} tp_error;

/* Writes a printf-style message into err->message (when err is not NULL) and returns s: how
 * every function that takes a tp_error* fails, in the core and above it. A message longer than
 * the buffer keeps its start and its end with "..." between them (cut on UTF-8 character
 * boundaries), so the reason at the end of "PATH: reason" survives a very long path. */
tp_status tp_error_set(tp_error* err, tp_status s, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* tp_error_set with a va_list (for wrappers that take their own "..."). */
tp_status tp_error_setv(tp_error* err, tp_status s, const char* fmt, va_list ap);

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

/* Optional allocator (the cgltf / sokol shape). Both functions NULL means malloc and free; else
 * both must be set. alloc returns NULL on failure; free accepts NULL. When given in
 * tp_terrain_desc it makes every allocation of the terrain, of its selections and of their
 * measurements (which may run on several threads at once: it must then be thread-safe). */
typedef struct tp_allocator {
    void* (*alloc)(size_t size, void* user_data);
    void (*free)(void* ptr, void* user_data);
    void* user_data;
} tp_allocator;

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

/* ---------------------------------------------------------------------------------------------
 * Level of detail
 */
typedef enum tp_lod_mode {
    TP_LOD_DEFAULT = 0, /* = TP_LOD_ERROR */
    TP_LOD_DISTANCE,    /* Vanek & Jezek: mindist, maxdist, exponent */
    TP_LOD_ERROR,       /* Brodersen / de Boer: coarsest level whose error projects to <= tau px */
    TP_LOD_FULL,        /* every patch at level n (the full-resolution baseline) */
    TP_LOD_MAX_ERROR    /* static, no camera: coarsest levels whose measured vertical error is
                           <= max_error_m everywhere (see tp_selection_update) */
} tp_lod_mode;

/* The default widest hole along a void's edge (tp_lod_params.hole_px): docs/hierarchy.md,
 * "Voids", says how it was chosen. */
#define TP_DEFAULT_HOLE_PX 4.0

typedef struct tp_lod_params {
    tp_lod_mode mode;
    /* distance mode. mindist and maxdist BOTH zero mean defaults derived from the terrain:
     * mindist = 1 patch width, maxdist = 24 patch widths; otherwise they are used as given
     * (mindist 0 is valid). exponent 0 means 1. */
    double mindist_m, maxdist_m, exponent;
    double tau_px; /* error mode: screen-space error threshold in pixels; 0 means 1 */
    /* error mode over a tree (tp_cut_update): the widest hole, in pixels, that an incomplete
     * node drawn below its finest level may leave along a void's edge (valid samples in cells
     * that are not whole, see tp_node_mask_from_q); 0 means TP_DEFAULT_HOLE_PX. Infinity: no
     * limit; a tiny value keeps every such node at full resolution (what an export wants). */
    double hole_px;
    /* max-error mode: the bound (metres, finite, > 0; no default). The error is measured
     * against reference_heights when given: the source grid as given to tp_terrain_create
     * (src_width * src_height values, row-major, NaN = none; padded fits only), so that
     * quantisation counts; else against the decoded grid. The array is read only during
     * tp_selection_update. */
    double max_error_m;
    const float* reference_heights;
    size_t reference_height_count;
    /* distance mode over a tree (tp_cut_update; `--lod spheres`): nonzero selects through a
     * sphere tree (Blow, "Terrain rendering at high levels of detail", Part II; tree_spheres.c):
     * each node's refine and merge distances are surfaces around its area box, and a frame
     * re-decides only the nodes whose surfaces the eye crossed since the last update of the
     * same cut. The cut is exactly the plain traversal's (same nodes, levels, neighbours,
     * requests): frustum culling, residency and stitching run every frame as before. Ignored
     * by the other modes and by tp_selection_update. */
    int sphere_tree;
} tp_lod_params;

/* The distance formula (Vanek & Jezek section 3) for a patch with finest level n (0..TP_MAX_N):
 *   dist <= mindist: n;   dist > maxdist: 0;
 *   else k = ceil(n * (1 - ((dist - mindist) / (maxdist - mindist))^exponent)),
 * rounded UP so that a patch is never coarser than the formula asks. With mindist == maxdist
 * it is a step: n up to mindist, 0 beyond. exponent 0 gives 0 beyond mindist; a huge exponent
 * gives n up to maxdist (an infinite exponent too). A negative dist is clamped to 0.
 * Returns TP_OK and writes the level (0..n) to *out_level. TP_ERR_INVALID_ARG, with a message,
 * for a NaN dist, a negative or NaN mindist or maxdist, maxdist < mindist, or a negative or NaN
 * exponent (the parameters may come from the command line; unlike tp_lod_params_resolve this
 * applies no defaults). (It used to return the level, or -1 for invalid parameters.) */
tp_status tp_lod_level_distance(int n, double dist_m, double mindist_m, double maxdist_m,
                                double exponent, int* out_level, tp_error* err);

/* Validates params and fills in defaults for terrain t: returns TP_OK and writes the resolved
 * parameters to *out (which may be `in`). `in` may be NULL (all defaults); t may be NULL (the
 * distance defaults then assume 1 m patches). TP_ERR_INVALID_ARG with a message for an unknown
 * mode, negative / NaN / infinite values, maxdist < mindist, or tau below 0 (tau = 0 is the
 * default 1; use TP_LOD_FULL for an exact surface); in max-error mode also for max_error_m not
 * > 0 and for reference heights of the wrong count or with a resampled fit (these need t). */
tp_status tp_lod_params_resolve(const tp_terrain* t, const tp_lod_params* in, tp_lod_params* out,
                                tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Camera and frustum culling
 */
typedef struct tp_camera {
    double position[3];         /* world: E, N, height */
    double forward[3], up[3];   /* need not be unit; up must not be parallel to forward.
                                   All zero forward means looking north and level. */
    double fov_y_rad;           /* vertical field of view; 0 means 60 degrees */
    int viewport_w_px, viewport_h_px; /* 0 means 1280 x 720 */
    double near_m, far_m;       /* 0 near means 1 m; 0 far means no far plane */
} tp_camera;

/* Writes the camera of a pose: eye position (world), yaw in degrees clockwise from grid north, pitch
 * in degrees (-90 looks straight down, +90 straight up), vertical field of view in degrees (0
 * means 60), viewport in pixels (0 means 1280 x 720); near plane 1 m, no far plane. The up
 * vector is defined for every pitch (it is right x forward with right = (cos yaw, -sin yaw, 0)).
 * Cannot fail. */
void tp_camera_from_pose(const double position[3], double yaw_deg, double pitch_deg,
                         double fov_y_deg, int width_px, int height_px, tp_camera* out);

/* Writes the pose of a camera: yaw in [0, 360) clockwise from grid north, pitch in [-90, 90].
 * Cannot fail. */
void tp_camera_get_pose(const tp_camera* cam, double* yaw_deg, double* pitch_deg);

/* The camera's orthonormal frame and intrinsics, defaults applied. */
typedef struct tp_camera_frame {
    double position[3];
    double forward[3], right[3], up[3]; /* unit vectors, world frame */
    double focal_px;                    /* pixels per unit of tangent: (h/2) / tan(fov_y/2) */
    int width_px, height_px;
    double near_m, far_m;               /* far 0: none */
} tp_camera_frame;

/* Writes the frame of cam into *out. Cannot fail. */
void tp_camera_get_frame(const tp_camera* cam, tp_camera_frame* out);

/* Projects a world point to pixel coordinates (x to the right, y down, (0, 0) the top-left
 * corner of the image, (w/2, h/2) its centre). Answers whether the point is in front of the
 * near plane: 1, writing pixel[2] (and *depth_m, the distance along the view axis, if depth_m
 * is not NULL); else 0 (also for a NaN point), writing nothing. That 0 is an answer, not a
 * failure. The pixel may lie outside the viewport. */
int tp_camera_project(const tp_camera* cam, const double world[3], double pixel[2],
                      double* depth_m);

/* Writes the unit direction (world frame) of the ray from the eye through pixel (x, y), the
 * inverse of tp_camera_project. Cannot fail. */
void tp_camera_pixel_ray(const tp_camera* cam, double x_px, double y_px, double dir[3]);

/* Writes the column-major 4x4 projection * view matrix of the camera with its eye at the origin
 * (callers subtract the eye position from world positions first, so that floats keep their
 * precision), OpenGL clip conventions, depth range [near, far_m]; far_m must be > the camera's
 * near plane (asserted). Cannot fail. */
void tp_camera_view_projection(const tp_camera* cam, double far_m, double out[16]);

typedef struct tp_frustum {
    double planes[6][4]; /* a*E + b*N + c*h + d >= 0 inside; unit normals */
    int plane_count;     /* 5 without a far plane, else 6 */
} tp_frustum;

/* Writes the camera's frustum planes into *out. Cannot fail. */
void tp_frustum_from_camera(const tp_camera* cam, tp_frustum* out);

typedef enum tp_cull { TP_CULL_OUTSIDE = 0, TP_CULL_INTERSECTS, TP_CULL_INSIDE } tp_cull;

/* Query: returns where the AABB lies against the frustum planes (n/p-vertex test). OUTSIDE only
 * if the box is entirely on the outer side of some plane (conservative: a box outside but not
 * behind one plane is reported as INTERSECTS). Cannot fail. */
tp_cull tp_frustum_test_aabb(const tp_frustum* f, const double aabb_min[3], const double aabb_max[3]);

/* ---------------------------------------------------------------------------------------------
 * Selection: one frame's levels, visibility and statistics
 */
typedef struct tp_selection tp_selection;

/* Creates a selection of terrain t, every patch at level n, visible and dirty; t must outlive
 * it. Returns TP_OK and sets *out; fails only with TP_ERR_OUT_OF_MEMORY. */
tp_status tp_selection_create(const tp_terrain* t, tp_selection** out, tp_error* err);
void tp_selection_destroy(tp_selection* s); /* accepts NULL */

/* Selects a level for every patch (visible or not: culled patches still stitch their visible
 * neighbours) with params (NULL: the defaults; resolved by tp_lod_params_resolve), then, in
 * error mode, raises the coarser neighbour of any stitched side whose
 * bound projects above tau until none does (levels only go up, so it ends; with
 * tp_selection_set_stitch_add, the patches that take vertices instead), and culls.
 * Incomplete patches are always at level n.
 * TP_LOD_MAX_ERROR ignores cam (it may be NULL) and marks every patch visible: each patch
 * starts at the coarsest level whose delta_m is <= max_error_m; then, in rounds, each patch
 * whose own or a neighbour's level changed in the previous round (every patch in the first) is
 * measured (its stitched triangles against the reference heights of every sample they cover)
 * and, above the bound, its coarser neighbours go up to one level finer than they were, or, if
 * none is coarser, the patch itself goes up one level, until no patch measures above the
 * bound (a patch at level n above it, possible when the bound is below quant_max_error_m,
 * stays there). It allocates scratch: TP_ERR_OUT_OF_MEMORY, levels unchanged, if that fails.
 * Every other mode needs cam (asserted). Fails with tp_lod_params_resolve's TP_ERR_INVALID_ARG
 * for invalid params; on any failure levels, visibility and dirty flags are unchanged. */
tp_status tp_selection_update(tp_selection* s, const tp_camera* cam, const tp_lod_params* params,
                              tp_error* err);

/* Sets one patch's level (0..n) by hand (tests, export, frozen views). Incomplete patches stay
 * at n. All patches are marked visible until the next tp_selection_update or tp_selection_cull.
 * Cannot fail. (It used to return TP_ERR_INVALID_ARG for a bad patch or k; those are now
 * asserted: no user value reaches it unchecked.) */
void tp_selection_set_level(tp_selection* s, int patch, int k);
/* Re-runs culling only, keeping levels. Cannot fail. */
void tp_selection_cull(tp_selection* s, const tp_camera* cam);

/* Returns the patch's current level (0..n). */
int tp_selection_level(const tp_selection* s, int patch);
/* Answers whether the patch passed the last culling: 1 visible, 0 culled. */
int tp_selection_visible(const tp_selection* s, int patch);
/* Writes the neighbour levels of a patch, indexed by tp_side (TP_NO_NEIGHBOR at the terrain
 * border). Cannot fail. */
void tp_selection_neighbor_levels(const tp_selection* s, int patch, int out[4]);
/* Answers 1 if the patch's level or a neighbour's level changed since the previous call to
 * tp_selection_clear_dirty (initially every patch is dirty): its vertex data must be rebuilt. */
int tp_selection_dirty(const tp_selection* s, int patch);
/* Marks every patch clean (after their vertex data was rebuilt). Cannot fail. */
void tp_selection_clear_dirty(tp_selection* s);

typedef struct tp_frame_stats {
    int patches_per_level[TP_MAX_LEVELS]; /* visible patches only */
    int visible_patches, culled_patches;
    size_t triangles;                     /* non-degenerate drawn triangles of visible patches */
    /* The delta-bound (quantisation included) over visible patches: max, and RMS of the bound
     * weighted by the samples each patch owns. */
    double bound_max_error_m, bound_rms_error_m;
} tp_frame_stats;

/* Writes the statistics of the current levels into *out. Cannot fail. Not const: it fills the
 * selection's cache of drawn-triangle counts (and uses its scratch), so it must not run at the
 * same time as any other call on the same selection. (It used to take a const pointer and
 * write through it.) */
void tp_selection_stats(tp_selection* s, tp_frame_stats* out);

/* Threads: the functions below take a const selection and write nothing in it; each call
 * allocates its own scratch and frees it before returning. Several threads may call them on
 * one selection at once, as long as no thread changes the selection meanwhile (update,
 * set_level, cull, clear_dirty, stats). The measures fail only with TP_ERR_OUT_OF_MEMORY
 * (scratch); tp_selection_ray_cast also with TP_ERR_INVALID_ARG. */

/* Exact vertical error of the drawn (stitched) geometry of visible patches against every drawn
 * sample they own, measured against the decoded grid (add quant_max_error_m for the source).
 * Each sample is counted once. Returns TP_OK and writes *out; TP_ERR_OUT_OF_MEMORY. */
typedef struct tp_error_measure {
    double max_error_m, rms_error_m;
    size_t samples;
} tp_error_measure;
tp_status tp_selection_measure_error(const tp_selection* s, tp_error_measure* out);

/* Screen-space error (pixels) for cam: for every drawn sample of a visible patch that is inside
 * the view and in front of the near plane, the on-screen length between the projections of
 * the sample and of the drawn surface vertically above/below it. Occlusion is ignored.
 * Returns TP_OK and writes the maximum, the RMS and the number of samples to those of max_px,
 * rms_px and samples that are not NULL; TP_ERR_OUT_OF_MEMORY. */
tp_status tp_selection_measure_screen_error(const tp_selection* s, const tp_camera* cam,
                                            double* max_px, double* rms_px, size_t* samples);

/* The same measure for one patch as if it alone were drawn at level k (0..n; its neighbours at
 * their current levels, its border stitched to them): returns TP_OK and writes to *out_px the
 * largest screen error (px) of the samples its triangles cover, 0 when none is in view. Used
 * to ask how far the error LoD's bound is from the coarsest level each patch could really
 * have. Fails only with TP_ERR_OUT_OF_MEMORY. (It used to return TP_ERR_INVALID_ARG for a NULL
 * cam or out_px or a bad patch or k; those are now asserted.) */
tp_status tp_selection_patch_screen_error(const tp_selection* s, const tp_camera* cam, int patch,
                                          int k, double* out_px);

/* How the drawn geometry removes cracks: 0 (the default) by moving vertices (tp_patch_vertices:
 * the error mode raises the coarser neighbour of a stitched side, as tp_selection_update says),
 * nonzero by adding them (tp_patch_triangles_add, `--stitch add`): the error mode then raises,
 * instead, each visible patch that takes a finer neighbour's vertices until its
 * tp_patch_error_bound_add projects <= tau (levels only go up, so it ends), and
 * tp_frame_stats' bound is tp_patch_error_bound_add. The measures and queries below still
 * describe vertex moving's geometry. Takes effect at the next update. Cannot fail; the max-error
 * mode, which measures vertex moving's geometry, then refuses to update (TP_ERR_INVALID_ARG). */
void tp_selection_set_stitch_add(tp_selection* s, int add);
int tp_selection_stitch_add(const tp_selection* s); /* 1 when adding */

/* The vertical scales a selection accepts: below 1/1000 a drawn height loses its metres to
 * rounding (the ray cast divides by the scale), above 1000 nothing is terrain any more. */
#define TP_VERTICAL_SCALE_MIN 1e-3
#define TP_VERTICAL_SCALE_MAX 1e3

/* Vertical exaggeration: the surface is drawn with heights times scale (> 0; 1 by default).
 * Everything that depends on the drawn geometry follows it: culling boxes, the error LoD's
 * projection (tau holds on screen), the screen-error measures, tp_selection_keep_above and
 * tp_selection_ray_cast, whose positions are in drawn space (E, N, height * scale). Errors
 * in metres (tp_frame_stats, tp_selection_measure_error) and tp_selection_drawn_height_at stay
 * true heights. Returns TP_OK; TP_ERR_INVALID_ARG, scale unchanged, for a scale that is not a
 * number in [TP_VERTICAL_SCALE_MIN, TP_VERTICAL_SCALE_MAX] (it comes from the command line). */
tp_status tp_selection_set_vertical_scale(tp_selection* s, double scale);
/* Returns the current vertical scale. */
double tp_selection_vertical_scale(const tp_selection* s);

/* Query: returns the height (metres) of the surface actually drawn at grid coordinates (x, y)
 * under the current levels (stitching included); NaN where nothing is drawn, outside the grid
 * or for NaN coordinates. O(1) inside a patch, O(2^k) along a stitched border. */
double tp_selection_drawn_height_at(const tp_selection* s, double x, double y);

/* Camera collision: raises position[2] (drawn space) so the eye is at least clearance_m (finite,
 * >= 0) above both the full-resolution surface and the drawn surface at its (E, N), heights
 * times the vertical scale. Answers whether it moved the eye: 1, or 0 when the eye is already
 * high enough or there is no surface below it (outside the terrain, nodata, a NaN position),
 * position then unchanged. Cannot fail. */
int tp_selection_keep_above(const tp_selection* s, double position[3], double clearance_m);

/* Where a ray meets the drawn surface. */
typedef struct tp_ray_hit {
    int hit;            /* 1 if the ray meets a drawn triangle */
    double position[3]; /* E, N and the TRUE height of the drawn surface there */
    double distance_m;  /* from the origin along the ray, in drawn space */
    int patch;          /* the patch hit; -1 if none (and for tp_cut_ray_cast) */
    int64_t node;       /* tp_cut_ray_cast: the tree node hit; -1 if none (and for a selection) */
} tp_ray_hit;

/* Casts the ray origin + t * dir (t >= 0; drawn space: heights times the vertical scale; dir
 * need not be unit) against the triangles the selection draws (levels and crack removal as
 * drawn), culled patches included, and writes the nearest hit (out->hit = 0 if none). Exact up
 * to rounding: the hit lies on a drawn triangle. Walks only the patches the ray's ground track
 * crosses, nearest first, skipping those whose box it passes above or below.
 * Returns TP_OK also when nothing is hit. TP_ERR_INVALID_ARG for a zero or NaN direction or a
 * NaN origin (they may come from a mouse position), TP_ERR_OUT_OF_MEMORY; *out is untouched. */
tp_status tp_selection_ray_cast(const tp_selection* s, const double origin[3],
                                const double dir[3], tp_ray_hit* out);

/* ---------------------------------------------------------------------------------------------
 * Hierarchy: a tree of nodes over the patch grid, by nested decimation (issue 12)
 *
 * The full-resolution grid is fitted as tp_terrain's TP_FIT_PAD does: cols * 2^n + 1 by
 * rows * 2^n + 1 samples, the samples at x >= src_width or y >= src_height being padding (never
 * drawn). Leaves (scale 0) are today's patches: leaf (c, r) covers samples [c*2^n, (c+1)*2^n] x
 * [r*2^n, (r+1)*2^n]. A node of scale s covers 2^s x 2^s leaves with every 2^s-th sample: its
 * (2^n+1)^2 samples lie at grid coordinates (c*2^(n+s) + i*2^s, r*2^(n+s) + j*2^s), i, j in
 * 0..2^n. So a parent's samples are samples of its children (its level k is, sample for sample,
 * the children's level k-1) and vertex moving keeps shared edges bit-identical between nodes of
 * any size.
 *
 * Node (s, c, r) exists iff (c+1) * 2^s <= cols and (r+1) * 2^s <= rows: only whole quadtree
 * nodes exist. A node whose parent does not exist is a root: one root over the whole map when
 * cols = rows = 2^S, else a few more roots along the far edges (a forest; every leaf lies under
 * exactly one root). Node ids run from the top scale down, row-major within a scale:
 * id = first_node[s] + r * node_cols[s] + c, so the largest nodes come first.
 *
 * A node at level k draws the level-k strip over its own samples: vertex stride 2^(n-k+s) grid
 * samples. "Complete" means every full-resolution sample of its AREA is drawn; an incomplete
 * node draws only the triangles its cell mask allows (tp_node_mask_from_q).
 */
#define TP_TREE_MAX_SCALES 24

typedef struct tp_tree_geometry {
    int n;                          /* node size 2^n + 1 (4 .. TP_MAX_N) */
    int src_width, src_height;      /* the grid before padding */
    int width, height;              /* fitted: cols * 2^n + 1, rows * 2^n + 1 */
    int cols, rows;                 /* leaves */
    int scales;                     /* scales 0 .. scales-1 hold at least one node (at most
                                       TP_TREE_MAX_SCALES: coarser nodes are not built) */
    int node_cols[TP_TREE_MAX_SCALES], node_rows[TP_TREE_MAX_SCALES]; /* cols >> s, rows >> s */
    int64_t first_node[TP_TREE_MAX_SCALES]; /* id of node (s, 0, 0) */
    int64_t node_count;
    int64_t root_count;             /* nodes without a parent */
} tp_tree_geometry;

/* Writes the geometry of a src_width x src_height grid (each 1 .. 2^30) tiled into nodes of
 * patch_size (17, 33, 65, 129 or 257). TP_ERR_INVALID_ARG for sizes out of range. */
tp_status tp_tree_geometry_init(int src_width, int src_height, int patch_size,
                                tp_tree_geometry* out, tp_error* err);

/* Node ids <-> (scale, column, row). Caller bugs (an id or position that does not exist) are
 * asserted. tp_tree_node_parent returns -1 for a root; tp_tree_node_child writes the 4 children
 * (quadrant q = 0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right) of a node of scale >= 1
 * (they always exist). */
int64_t tp_tree_node_id(const tp_tree_geometry* g, int s, int c, int r);
void tp_tree_node_locate(const tp_tree_geometry* g, int64_t id, int* s, int* c, int* r);
int64_t tp_tree_node_parent(const tp_tree_geometry* g, int64_t id);
int64_t tp_tree_node_child(const tp_tree_geometry* g, int64_t id, int q);
/* Writes the ids of every root, in id order, into roots (root_count of them). */
void tp_tree_roots(const tp_tree_geometry* g, int64_t* roots, size_t root_capacity);

/* A node's samples as stored and resident: (2^n+1)^2 uint16 in row-major order, each the
 * global quantised height minus the node's qmin, TP_TREE_NO_HEIGHT where the sample is not
 * drawn (nodata, padding). The decoded height of a sample is (stored + qmin) * height_step_m,
 * the same in every node that holds it. A resident node's block is its samples followed by
 * its cell mask (tp_node_mask_words(n) words; see tp_node_mask_from_q), then its filled bits
 * (tp_node_filled_words(n) words; see TP_NODE_HAS_FILLED): tp_tree_block_words. */
#define TP_TREE_NO_HEIGHT 0xFFFFu
size_t tp_tree_block_words(int n); /* (2^n+1)^2 + tp_node_mask_words(n) + tp_node_filled_words(n) */
/* Filled bits: bit k % 16 of word k / 16 for sample k (row-major, k = j (2^n+1) + i) is set when
 * that sample is drawn but was not measured: an interior void filled by the build (by
 * interpolation or from a second source). A node's samples are full-resolution samples (nested
 * decimation), so a sample's bit is the same in every node that holds it. Only nodes with
 * TP_NODE_HAS_FILLED have any set; a block's filled bits are all 0 otherwise. */
size_t tp_node_filled_words(int n); /* ceil((2^n+1)^2 / 16) */

/* What the tree keeps about every node, resident or not (the store's node table). Errors are
 * uint16 in units of the tree's err_unit (TP_NODE_ERR_SAT: "at least this large"; the bound is
 * then the node's area range). Every bound is against EVERY full-resolution sample of the
 * node's area, rounded up; quantisation is not included (add quant_max_error_m). */
#define TP_NODE_ERR_SAT 0xFFFFu
/* TP_NODE_HAS_FILLED: at least one of the node's OWN samples is a filled void sample (its
 * block's filled bits say which); set by the tree builder when given filled flags
 * (tp_tree_builder_add_band_filled), never by tp_node_meta_compute. */
enum { TP_NODE_COMPLETE = 1, TP_NODE_HAS_DRAWN = 2, TP_NODE_HAS_FILLED = 4 };
typedef struct tp_node_meta {
    int32_t qmin, qmax;   /* global quantised range over the node's OWN drawn samples (its
                             drawn geometry: the AABB); 0, -1 when none */
    int32_t area_qmin, area_qmax; /* over every drawn full-resolution sample of its area;
                                     0, -1 when none */
    uint8_t flags;        /* TP_NODE_COMPLETE: every full-resolution sample of the area is
                             drawn; TP_NODE_HAS_DRAWN: at least one is */
    uint8_t pad_[3];
    /* delta[k], k = 0..n: the unstitched level-k triangulation of the node's samples against
     * every full-resolution sample of its area. */
    uint16_t delta[TP_MAX_LEVELS];
    /* eps[side][kn], kn = 0..n-1: any triangle with a vertex moved by a neighbour at (relative)
     * level kn on that side, over every level k > kn, against every full-resolution sample it
     * covers. */
    uint16_t eps[4][TP_MAX_N];
} tp_node_meta;

/* The error unit of a tree (steps): step/16, or the finest power of two of steps up to 1 for
 * which the global height range (steps, >= 0) fits TP_NODE_ERR_SAT - 1 units. Every bound is
 * clamped to its node's area range, so with this unit TP_NODE_ERR_SAT is never stored unless
 * the global range exceeds 65534 steps (tp_tree_create_from_grid never lets it). */
double tp_tree_err_unit_steps(double range_steps);

/* Cell masks: which parts of an incomplete node are drawn below its finest triangles.
 *
 * A node's level-n lattice has 2^n x 2^n cells; cell (cx, cy) spans its samples (cx, cy) ..
 * (cx+1, cy+1), i.e. 2^s x 2^s full-resolution cells. Its mask bit (bit b % 16 of word b / 16,
 * b = cy * 2^n + cx) is set iff EVERY full-resolution sample of the closed cell is drawn: for a
 * leaf, its 4 corners; for a node of scale >= 1, the child's level n-1 cell there, i.e. the 2x2
 * cells of the child's mask. A level-k cell (2^(n-k) lattice cells a side) is "whole" iff every
 * lattice cell in it is set. Drawing rule (tp_cut_triangles, the error tables, the queries): a
 * leaf at level n draws each triangle whose three vertices are drawn (as tp_patch_triangles);
 * anything else draws a triangle only if every lattice cell in the bounding box of its
 * (stitched) vertices is set, so no drawn triangle covers an undrawn sample and every bound
 * holds against every full-resolution sample under it. Valid samples in cells that are not
 * whole are not drawn: a hole of at most one level-k cell (wider only next to a coarser
 * neighbour's stitched triangles). A complete node's mask is all set. */
size_t tp_node_mask_words(int n); /* uint16 words of a mask: 4^n / 16 (n >= 2) */
/* Leaf masks from its samples: q as tp_node_meta_compute takes them (INT32_MIN = not drawn) or
 * as stored (TP_TREE_NO_HEIGHT = not drawn). */
void tp_node_mask_from_q(int n, const int32_t* q, uint16_t* mask);
void tp_node_mask_from_samples(int n, const uint16_t* samples, uint16_t* mask);
/* The mask of a node of scale >= 1 from its 4 children's masks (quadrants as
 * tp_tree_node_child numbers them). */
void tp_node_mask_from_children(int n, const uint16_t* const children[4], uint16_t* mask);
/* 1 if every lattice cell (x, y), x0 <= x < x1, y0 <= y < y1 (inside 0..2^n), is set. */
int tp_node_mask_all(const uint16_t* mask, int n, int x0, int y0, int x1, int y1);

/* Computes the meta of one node from its own samples q ((2^n+1)^2 global quantised heights,
 * row-major, INT32_MIN where not drawn), its cell mask (from tp_node_mask_from_q for a leaf,
 * tp_node_mask_from_children above) and, for a node of scale >= 1, its 4 children's metas
 * (children[q] as tp_tree_node_child numbers them; NULL for a leaf): the children carry the
 * error of the full-resolution samples between this node's samples, and the area's range and
 * flags. err_unit_steps from tp_tree_err_unit_steps. A complete leaf's tables are
 * exactly tp_terrain's patch tables for the same samples (one implementation; an incomplete
 * patch is drawn only at level n, an incomplete leaf at any level by its mask). For scale >= 1:
 * delta[k] = delta_own(k) + carry, delta[n] = carry, eps = the stitched triangles' error at the
 * corners of every cell they touch + carry, carry = max of the children's delta[n-1] (see
 * node_meta.c); an incomplete node's tables count only the triangles the mask lets it draw.
 * Cannot fail. */
void tp_node_meta_compute(int n, int scale, const int32_t* q, const uint16_t* mask,
                          const tp_node_meta* const children[4], double err_unit_steps,
                          tp_node_meta* out);

/* Bound (metres, quantisation NOT included) of node's vertical error at level k with the given
 * relative neighbour levels (as tp_patch_error_bound; TP_NO_NEIGHBOR for none or for "no vertex
 * moves on that side"; neighbor_levels may be NULL), against every full-resolution sample
 * under the node's drawn triangles. Cannot fail. */
double tp_node_error_bound(const tp_node_meta* m, int n, int k, const int neighbor_levels[4],
                           double step_m, double err_unit_steps);

/* ---- building a tree, one band of leaf rows at a time (tree_build.c) ----
 *
 * The builder takes the fitted grid top to bottom in bands of 2^n + 1 rows (band r is rows
 * r*2^n .. (r+1)*2^n: consecutive bands share a row), computes every leaf of the band, keeps the
 * decimated rows each coarser scale needs, and emits each node once, as soon as its samples and
 * its children are known: every node after its 4 children (within a band: its leaves left to
 * right, then each coarser scale's completed row). Memory, all allocated by
 * tp_tree_builder_create, nothing per band, whatever the height: at most
 *   4 (2^n+1) ((2 + 2^-n) width + scales) + 4 cols (sizeof(tp_node_meta) + 2^(2n-3))
 *   + cols (2^(2n-3) + 2^(n-2) + 2) + 2048 bytes
 * (the decimated rows of every scale, one block of samples per node of a row, two rows of
 * metas and masks per scale, a row of nodes' filled bits), plus (2^n+1) (width + scales) bytes
 * once filled flags are given (tp_tree_builder_add_band_filled: the decimated rows' flags).
 * The per-node work (tp_node_meta_compute) may be spread over threads by the caller's
 * parallel_for. */
typedef struct tp_tree_builder tp_tree_builder;

typedef struct tp_tree_builder_desc {
    tp_tree_geometry geometry;
    double err_unit_steps;
    /* Called once per node, in an order where children precede parents (from one thread at a
     * time). q: the node's (2^n+1)^2 global quantised heights (INT32_MIN = not drawn), mask its
     * cell mask (tp_node_mask_words(n) words), valid during the call. Returning non-zero stops the build (tp_tree_builder_add_band then fails
     * with TP_ERR_IO and the message the callback left in err). */
    int (*emit)(int64_t node, const tp_node_meta* meta, const int32_t* q, const uint16_t* mask,
                void* user, tp_error* err);
    /* Optional, called instead of emit when set: also the node's filled bits
     * (tp_node_filled_words(n) words, see tp_node_filled_words), NULL when the node has none
     * (meta lacks TP_NODE_HAS_FILLED). */
    int (*emit_filled)(int64_t node, const tp_node_meta* meta, const int32_t* q,
                       const uint16_t* mask, const uint16_t* filled, void* user, tp_error* err);
    /* Optional: run fn(i, ctx) for i in 0..count-1, possibly on several threads at once;
     * NULL runs them in order here. */
    void (*parallel_for)(int count, void (*fn)(int i, void* ctx), void* ctx, void* user);
    void* user;
    tp_allocator allocator;
} tp_tree_builder_desc;

tp_status tp_tree_builder_create(const tp_tree_builder_desc* desc, tp_tree_builder** out,
                                 tp_error* err);
/* Adds band r (0 .. rows-1, in order): q holds (2^n+1) rows of `width` global quantised heights
 * (INT32_MIN = not drawn, padding included), q_count = (2^n+1) * width (asserted). Emits the
 * band's leaves and every node completed by them. TP_ERR_INVALID_ARG for a band out of order
 * (nothing emitted, the builder unchanged) or after an emit failure (the builder then refuses
 * every band); TP_ERR_IO when emit returns non-zero. */
tp_status tp_tree_builder_add_band(tp_tree_builder* b, int r, const int32_t* q, size_t q_count,
                                   tp_error* err);
/* tp_tree_builder_add_band with, for each of its samples, whether it is a filled void sample
 * (filled[i] != 0; drawn samples only, a flag on an undrawn one is ignored; NULL: none). The
 * builder keeps the flags of the decimated rows beside the heights (one byte a sample: the
 * memory bound above grows by a quarter) and marks every node holding a flagged sample
 * TP_NODE_HAS_FILLED. */
tp_status tp_tree_builder_add_band_filled(tp_tree_builder* b, int r, const int32_t* q,
                                          const uint8_t* filled, size_t q_count, tp_error* err);
void tp_tree_builder_destroy(tp_tree_builder* b); /* accepts NULL */

/* ---- the tree at run time: metas for every node, samples for the resident ones ---- */
typedef struct tp_tree tp_tree;

typedef struct tp_tree_desc {
    tp_tree_geometry geometry;
    double geotransform[6];    /* of the fitted grid */
    double height_step_m;      /* global quantisation step */
    double quant_max_error_m;  /* max |source - decoded| over valid samples */
    double err_unit_steps;
    const tp_node_meta* metas; /* node_count of them, borrowed (may be memory-mapped); must
                                  outlive the tree */
    size_t meta_count;
    tp_allocator allocator;
} tp_tree_desc;

/* TP_ERR_INVALID_ARG for a geometry not from tp_tree_geometry_init, metas NULL or meta_count
 * not node_count, a step or unit not > 0, a half-set allocator; TP_ERR_OUT_OF_MEMORY. No node
 * is resident at first. */
tp_status tp_tree_create(const tp_tree_desc* desc, tp_tree** out, tp_error* err);
void tp_tree_destroy(tp_tree* t); /* accepts NULL */
const tp_tree_geometry* tp_tree_get_geometry(const tp_tree* t);
const tp_node_meta* tp_tree_meta(const tp_tree* t, int64_t node);

/* Residency: the caller owns node blocks (tp_tree_block_words(n) uint16: samples and cell
 * mask, see TP_TREE_NO_HEIGHT) and
 * attaches them while they are valid; the tree only reads them. Attach / detach from the
 * thread that selects and draws (a loader thread decodes into a block, the render thread
 * attaches it). */
void tp_tree_attach(tp_tree* t, int64_t node, const uint16_t* samples);
void tp_tree_detach(tp_tree* t, int64_t node);
const uint16_t* tp_tree_samples(const tp_tree* t, int64_t node); /* NULL when not resident */

/* Builds a whole tree in memory from a float grid (NaN = nodata): metas and every node's samples
 * owned by the tree and attached. For tests and small grids; the store build uses the builder.
 * geotransform NULL or all zeros: (0, 1, 0, 0, 0, -1); patch_size 0: TP_DEFAULT_PATCH_SIZE.
 * height_step_m 0: automatic as tp_terrain_create (1 m for integral heights, else the finest
 * 2^-p m, p <= 10), but for ONE range: every node up to the root stores its samples in 16 bits,
 * so the global range must fit 65534 steps (a coarser step is chosen where it does not).
 * TP_ERR_INVALID_ARG for a count that does not match, sizes or patch size out of range, a
 * rotated geotransform, an explicit step too fine; TP_ERR_BAD_DATA if no height is valid;
 * TP_ERR_OUT_OF_MEMORY. */
tp_status tp_tree_create_from_grid(const float* heights, size_t height_count, int width,
                                   int height, const double geotransform[6], int patch_size,
                                   double height_step_m, tp_tree** out, tp_error* err);

/* The tree's georeference, quantisation and height range (over every drawn sample: the roots'
 * area ranges). */
typedef struct tp_tree_info {
    double geotransform[6];
    double height_step_m, quant_max_error_m, err_unit_steps;
    double min_height_m, max_height_m; /* NaN when nothing is drawn */
} tp_tree_info;
void tp_tree_get_info(const tp_tree* t, tp_tree_info* out);

/* Writes the unit normal (east, north, up) at grid sample (x, y) of resident node `node` (a
 * position on its lattice, inside it): from the full-resolution samples around it when the
 * leaves there are resident (central differences, one-sided next to undrawn samples: what
 * tp_terrain_normal gives on the same grid, so neighbouring nodes of any scale agree); else
 * from the node's own samples at its stride ((0, 0, 1) where no slope is known). */
void tp_tree_node_normal(const tp_tree* t, int64_t node, int32_t x, int32_t y, float normal[3]);

/* Query: decoded height of full-resolution sample (x, y) if a resident node holds it at that
 * position (the finest resident one), else NaN. */
double tp_tree_sample(const tp_tree* t, int x, int y);

/* ---- selection over the tree: the drawn cut (tree_select.c, tree_stitch.c) ----
 *
 * From the roots down: a node outside the frustum (its area's AABB, which holds every
 * descendant; see tp_cut_update) is culled and not visited further; a node whose level-n
 * bound (stitching as in tp_node_error_bound) projects above tau (error mode, the same
 * projection bound as tp_selection_update), or whose holes would be wider than hole_px (an
 * incomplete node, see tp_node_mask_from_q), is replaced by its 4 children; else it is drawn at
 * its coarsest level whose bound projects to <= tau and whose holes stay within hole_px. Then levels are raised (never lowered) until every pair of visible nodes sharing an
 * edge can be stitched by moving the finer side's vertices onto the coarser side's: the coarser
 * stride must divide the finer node's side (its corners are vertices of both), and a coarser
 * stride may only be on the larger (or equal) node. Children that are not resident are not
 * entered: their ancestor is drawn in their place ("substituted"), and they are listed as
 * requests for the loader, nearest first. Cost is proportional to the nodes visited. */
typedef struct tp_cut_node {
    int64_t node;
    int8_t level;       /* 0..n */
    int8_t nb[4];       /* neighbour level per side, relative to this node's own samples, as
                           tp_patch_vertices takes it: kn < level moves this side's vertices
                           onto every 2^(level-kn)-th; TP_NO_NEIGHBOR: nothing moves */
    int8_t add[4];      /* --stitch add (tp_cut_set_stitch_add): per side, the level of the
                           finer neighbour of this node's size whose vertices this side takes
                           (> level; tp_patch_triangles_add's neighbor_levels); TP_NO_NEIGHBOR:
                           none. Always TP_NO_NEIGHBOR with vertex moving. */
    uint8_t substituted;/* drawn in place of finer nodes that are not resident */
    uint8_t near_plane; /* its box reaches the near plane, or its error could carry a point
                           of the box there (a low eye; an ancestor drawn in place of nodes not
                           resident): bound_px bounds what is drawn of it, in front of the near
                           plane and inside the view (the whole box's bound is infinite) */
    float bound_px;     /* the projected error bound of this node as drawn (error mode): finite */
} tp_cut_node;

typedef struct tp_cut_stats {
    int visited, drawn, culled;
    int substituted;           /* drawn nodes standing in for missing descendants */
    int requests;
    int nodes_per_scale[TP_TREE_MAX_SCALES];
    size_t triangles;          /* non-degenerate triangles of the drawn nodes */
    double max_bound_px;       /* largest projected bound among drawn nodes (error mode) */
    double substitution_bound_px; /* largest projected bound among substituted nodes */
    int near_plane_nodes;         /* drawn nodes whose bound covers only what is drawn of them
                                     (tp_cut_node.near_plane) */
    /* distance mode: distance decisions the update computed (eye to a node's area box, then
     * the formula): one per node in view for the plain traversal; with sphere_tree only those
     * of nodes whose refine or merge surface the eye crossed. */
    int decisions;
    int sphere_visited; /* sphere_tree: sphere-tree entries (and root clusters) visited */
    int sphere_nodes;   /* sphere_tree: entries held (the distance cut over the whole map) */
    int add_sides;      /* --stitch add: drawn nodes' sides that take a neighbour's vertices */
    int moved_sides;    /* drawn nodes' sides whose vertices move (tp_cut_node.nb) */
} tp_cut_stats;

typedef struct tp_cut tp_cut;
tp_status tp_cut_create(const tp_tree* t, tp_cut** out, tp_error* err);
void tp_cut_destroy(tp_cut* c); /* accepts NULL */
/* Selects the cut for cam (error, distance or full mode; params NULL = defaults). Only
 * resident nodes are drawn. TP_ERR_INVALID_ARG for bad params and for TP_LOD_MAX_ERROR;
 * TP_ERR_OUT_OF_MEMORY (the cut is then empty until the next successful update).
 * Details:
 *   - Culling: the traversal stops at a node whose AREA box (area_qmin..area_qmax: every
 *     descendant's geometry) is outside the frustum; a node chosen for drawing is culled when
 *     its own drawn box (qmin..qmax) is. A node with nothing drawn in its area is skipped.
 *   - Error mode: a node is refined while its level-n bound plus quant_max_error_m projects
 *     above tau (lod.c's bound over its area box) or, incomplete, the holes it may leave at
 *     level n exceed hole_px (see hole_ok in tree_select.c); else it is drawn at the coarsest
 *     level k such that k and every finer level meet both.
 *   - Distance mode (Vanek & Jezek over strides): at distance d (eye to the area box) the leaf
 *     formula's level kl asks for vertex stride 2^(n-kl) grid samples; beyond maxdist the
 *     stride doubles with every doubling of d (2^(n + floor(log2(d / maxdist))))), so far
 *     terrain collapses into large nodes. A node of scale s (strides 2^s .. 2^(s+n)) is
 *     refined when that stride is below 2^s, else drawn at the level giving that stride
 *     (level 0 when the stride is coarser still). mindist = maxdist = 0: 1 and 24 LEAF widths.
 *   - Sphere tree (distance mode with params->sphere_tree; tree_spheres.c): the same
 *     decisions, kept from one update to the next with the distance interval over which each
 *     holds, over the whole map's distance cut; an update re-decides only the nodes whose
 *     interval the eye's distance left, skipping every subtree whose nearest threshold is
 *     farther than the eye moved. The cut is the same; the first update, and any update after
 *     a change of mindist, maxdist, exponent, hole_px, focal length or vertical scale, builds
 *     the distance cut of the whole map (tp_cut_stats.sphere_nodes entries).
 *   - Full mode: every visible leaf at level n.
 *   - Stitching (tree_stitch.c): levels only go up; where two drawn neighbours differ by more
 *     than n scales the larger one is split if its children are resident, else the smaller
 *     one's ancestor n scales below the larger is drawn at level n instead (not marked
 *     substituted: its own children may well be resident).
 *     Culled nodes are not stitched against. A crack can remain only between two roots more
 *     than n scales apart whose larger one's children are not resident.
 *   - Requests: children the cut wanted but found not resident (a root not resident, which
 *     leaves a hole, is requested first). Priority: the parent's projected level-n bound
 *     (error mode), else 1 / (1 + distance). */
tp_status tp_cut_update(tp_cut* c, const tp_camera* cam, const tp_lod_params* params,
                        tp_error* err);
/* tp_cut_update for its requests only (a prefetch: what a camera elsewhere would ask for):
 * the same selection without the stitching pass and without output, so tp_cut_nodes is
 * empty afterwards. Its requests are tp_cut_update's, less those only the stitching pass
 * makes (splitting a node more than n scales larger than its neighbour). About 40% cheaper
 * (docs/PERFORMANCE.md, "The CPU side of a frame"). Same errors as tp_cut_update. */
tp_status tp_cut_update_requests(tp_cut* c, const tp_camera* cam, const tp_lod_params* params,
                                 tp_error* err);
/* The drawn nodes of the last update (visible only), and the nodes it wanted but found not
 * resident, most urgent first (their priorities: larger = sooner). Valid until the next update. */
const tp_cut_node* tp_cut_nodes(const tp_cut* c, size_t* count);
const int64_t* tp_cut_requests(const tp_cut* c, size_t* count);
/* Statistics of the last update. O(visited nodes), cheap enough for every frame: each drawn
 * node's triangles were counted by the update (complete nodes from a table by level and
 * neighbour levels, incomplete ones once per node and neighbour levels, cached in the cut). */
void tp_cut_get_stats(const tp_cut* c, tp_cut_stats* out);
/* Vertex data of drawn node i (0..count-1) after crack removal: (2^level+1)^2 vertices as
 * tp_patch_vertices writes them (global grid coordinates, decoded heights; cls is VALID,
 * FILLED, NODATA or PADDING). FILLED where the node's filled bits (TP_NODE_HAS_FILLED) mark
 * the sample the vertex stands on: a vertex that crack removal moves onto a coarser
 * neighbour's lattice vertex takes that sample's height and so its flag; drawn or not is the
 * original vertex's, as before. */
void tp_cut_vertices(const tp_cut* c, size_t i, tp_vertex* vertices, size_t vertex_capacity);
/* The triangles drawn node i draws, from its vertex data (tp_cut_vertices): as
 * tp_patch_triangles (strip order and winding, index triples, returns the count, writes the
 * first triangle_capacity), by the cell mask's rule for an incomplete node below a leaf's level
 * n (tp_node_mask_from_q). What the viewer and the export draw of an incomplete node. */
size_t tp_cut_triangles(const tp_cut* c, size_t i, const tp_vertex* vertices,
                        uint32_t* triangles, size_t triangle_capacity);
/* Height (m) of the surface the cut draws at grid (x, y); NaN where nothing is drawn. */
double tp_cut_drawn_height_at(const tp_cut* c, double x, double y);
/* Screen error (px) of the drawn cut against every full-resolution sample of the drawn nodes'
 * areas that is in view, as tp_selection_measure_screen_error; needs the full-resolution
 * samples: it reads the resident leaves, and skips (counting them in *skipped) samples whose
 * leaf is not resident. Any of the outputs may be NULL. With --stitch add
 * (tp_cut_set_stitch_add) it measures the triangles drawn, added vertices included; only then
 * does it allocate, and can fail: TP_ERR_OUT_OF_MEMORY. Else it returns TP_OK. */
tp_status tp_cut_measure_screen_error(const tp_cut* c, const tp_camera* cam, double* max_px,
                                      double* rms_px, size_t* samples, size_t* skipped);

/* Vertical exaggeration, as tp_selection_set_vertical_scale: boxes, the error mode's projection
 * and tp_cut_measure_screen_error follow heights times scale (tau holds on screen); heights
 * (vertices, tp_cut_drawn_height_at) stay true. Takes effect at the next update. Returns
 * TP_OK; TP_ERR_INVALID_ARG, scale unchanged, outside [TP_VERTICAL_SCALE_MIN,
 * TP_VERTICAL_SCALE_MAX] or NaN. */
tp_status tp_cut_set_vertical_scale(tp_cut* c, double scale);

/* Crack removal by adding vertices over a tree (`--stitch add`; Brodersen, section 4), from the
 * next update on (add = 0: vertex moving, the default). Brodersen's patches are all one size:
 * between two drawn nodes of the same size the coarser one's side takes the finer one's
 * vertices (tp_cut_node.add) and nothing moves; between nodes of different sizes the smaller
 * one's side still moves onto the larger one's vertices (tp_cut_node.nb), as with vertex moving,
 * and so does a side next to an incomplete node of its size (only complete nodes take
 * vertices). A node never both takes vertices on one side and moves them on the other side of
 * the same corner triangle (TOP and LEFT, BOTTOM and RIGHT: tp_patch_triangles_add's two
 * triangles holding two sides): it is raised to the finer neighbour's level instead. In error
 * mode a node that takes vertices is raised until its bound with the added vertices
 * (tp_cut_add_bound_m) projects to tau or less. tp_cut_measure_screen_error measures the
 * triangles drawn; tp_cut_vertices, tp_cut_triangles and the queries (tp_cut_drawn_height_at,
 * ray casts) still describe vertex moving's surface, which differs from the drawn one only
 * inside the grid triangles that take vertices, by at most the added offsets. */
void tp_cut_set_stitch_add(tp_cut* c, int add);
int tp_cut_stitch_add(const tp_cut* c);
/* Bound (m, true heights, quantisation not included) on the error against full resolution of
 * drawn node i at its level with the finer neighbours' vertices added on the sides add[] names
 * (as tp_cut_node.add): the node's level error delta_k plus the largest offset of an added
 * sample from its side's level-k edge (nested decimation keeps every sample's true height, and
 * the added vertices' offsets are interpolated linearly inside the grid triangle). */
double tp_cut_add_bound_m(const tp_cut* c, size_t i, const int add[4]);
/* tp_cut_vertices on the node's level-m lattice (level <= m <= n; (2^m+1)^2 vertices): the
 * vertices of node i's own level moved as tp_cut_vertices moves them, every other one where
 * its sample is. What --stitch add's triangles index (tp_patch_triangles_add's samples, at
 * m = the finest of the node's and its add[] levels). */
void tp_cut_vertices_at_level(const tp_cut* c, size_t i, int m, tp_vertex* vertices,
                              size_t vertex_capacity);

/* Test hook: installs a hand-made cut, nodes[i] drawn at levels[i] (resident, distinct, not
 * overlapping), every node visible, no camera, and runs the stitching
 * pass on it (levels raised, nodes split or collapsed as in tp_cut_update; a split child keeps
 * its parent's stride). tp_cut_nodes, _vertices and _drawn_height_at then describe it.
 * TP_ERR_OUT_OF_MEMORY (the cut is then empty). */
tp_status tp_cut_set_nodes(tp_cut* c, const int64_t* nodes, const int* levels, size_t count,
                           tp_error* err);

/* ---- queries on the tree and the cut (cut_query.c) ----
 *
 * The same questions the viewer asks a tp_selection, asked of a tree whose nodes stream in.
 * Grid coordinates are those of the fitted grid; the tree's geotransform puts sample (x, y) at
 * E = gt[0] + (x + 0.5) * gt[1], N = gt[3] + (y + 0.5) * gt[5] (as tp_terrain does). */
void tp_tree_world_to_grid(const tp_tree* t, double e, double n, double* x, double* y);
void tp_tree_grid_to_world(const tp_tree* t, double x, double y, double* e, double* n);

/* The leaf whose square holds grid (x, y) (a point on a shared border: the leaf after it, the
 * one holding the split cell there; the last leaf at the far edges), or -1 outside the grid or
 * for NaN. Make it resident
 * before a full-resolution query there. */
int64_t tp_tree_leaf_at(const tp_tree* t, double x, double y);

/* Height (m) of the full-resolution surface at grid (x, y): the split cells of
 * tp_terrain_height_at over the decoded samples. NaN outside the grid, where no drawn triangle
 * holds the point, and where the leaf holding it is not resident (tp_tree_leaf_at). */
double tp_tree_height_at(const tp_tree* t, double x, double y);

/* The scale tp_cut_set_vertical_scale set (1 by default). tp_cut_keep_above and
 * tp_cut_ray_cast work in drawn space (E, N, height * scale); tp_tree_height_at stays true. */
double tp_cut_vertical_scale(const tp_cut* c);

/* Casts the ray origin + t * dir (t >= 0, drawn space, dir need not be unit) against the
 * triangles the cut draws (levels and crack removal as drawn) and writes the nearest hit
 * (out->node, out->patch = -1). Exact up to rounding, as tp_selection_ray_cast: walks the
 * leaves the ray's ground track crosses, nearest first (a 2D DDA), and in each drawn node the
 * ray's box test passes, the cells its track crosses (the whole border strip where a side is
 * stitched). TP_ERR_INVALID_ARG for a zero or NaN direction or a NaN origin, *out untouched;
 * else TP_OK, also when nothing is hit. */
tp_status tp_cut_ray_cast(const tp_cut* c, const double origin[3], const double dir[3],
                          tp_ray_hit* out);

/* Camera collision, as tp_selection_keep_above: raises position[2] (drawn space) to
 * clearance_m above the higher of the full-resolution surface (tp_tree_height_at: make the
 * leaf under the eye resident first, else only the drawn surface counts) and the drawn surface
 * at its (E, N). 1 if it moved the eye, 0 otherwise. */
int tp_cut_keep_above(const tp_cut* c, double position[3], double clearance_m);

/* ---------------------------------------------------------------------------------------------
 * Viewshed (viewshed.c): which samples an observer sees
 *
 * One pass over the grid outwards from the observer carrying a horizon height per sample
 * (Wang, Robinson & White 2000; GDAL's GVM_Edge mode of GDALViewshedGenerate), O(samples) in
 * the radius' window: about 10 ms for a 20 km radius on 30 m posts (docs/PERFORMANCE.md).
 * docs/field.md states its error behaviour and where it differs from gdal_viewshed.
 *
 * Conventions are gdal_viewshed's: heights above the ground (observer 2 m, target 0 m); a
 * sample's height is lowered by curvature_coeff * d^2 / (2 * earth_radius_m) at horizontal
 * distance d from the observer (0.85714 = curvature with standard refraction, 1 = curvature
 * without refraction, 0 = a flat earth: as GDAL's -cc, which "1" does NOT turn off); distances
 * are between sample centres, in the units of the geotransform (metres on a render grid), and
 * use |gt[1]| and |gt[5]| (rotated grids are refused). A target at a sample is seen when its
 * corrected height plus target_height_m reaches the horizon there (equal counts as seen).
 * Values: TP_VIEWSHED_VISIBLE (255), TP_VIEWSHED_HIDDEN (0), TP_VIEWSHED_OUTSIDE (0: beyond
 * the radius), as GDALViewshedGenerate's defaults; a nodata sample (NaN) is never seen (0) and
 * does not block the view (a sight line passes over it at the horizon it inherits). The
 * observer's sample and its eight neighbours are always seen (no sample lies between).
 */
#define TP_VIEWSHED_VISIBLE 255
#define TP_VIEWSHED_HIDDEN 0
#define TP_VIEWSHED_OUTSIDE 0
#define TP_VIEWSHED_OBSERVER_HEIGHT_M 2.0
#define TP_VIEWSHED_TARGET_HEIGHT_M 0.0
#define TP_VIEWSHED_CURVATURE_COEFF 0.85714
/* Within this many posts of the observer (Chebyshev) a sample gets the exact horizon of its
 * sight line instead of the interpolated one, and the sweep carries on from those: XDraw's
 * interpolation errs most where the rings are short (a ridge a few posts away smeared across a
 * whole sector behind it), and the exact test there costs about (2K+1)^2 * K steps (1.4 M for
 * 64: 5-16 ms more than interpolating, measured under load). docs/field.md "Exact near the
 * observer" gives the measured effect. */
#define TP_VIEWSHED_EXACT_RADIUS_PX 64

typedef struct tp_viewshed_options {
    double observer_height_m; /* eye above the ground at the observer's sample, >= 0 */
    double target_height_m;   /* target above the ground at each sample, >= 0 */
    double curvature_coeff;   /* >= 0; see above */
    double radius_m;          /* samples further than this are TP_VIEWSHED_OUTSIDE; 0: no limit */
    double earth_radius_m;    /* the sphere of the curvature term (GDAL: the CRS's semi-major
                                 axis); 0 means WGS84's 6378137 m */
    int exact_radius_px;      /* >= 0: samples within this many posts (Chebyshev) get the exact
                                 horizon (R3: the ground linear between the posts where the
                                 sight line crosses each grid line); 0: interpolated everywhere,
                                 exactly GDAL's GVM_Edge */
} tp_viewshed_options;

/* gdal_viewshed's defaults: 2 m, 0 m, 0.85714, no radius limit, WGS84's semi-major axis; exact
 * within TP_VIEWSHED_EXACT_RADIUS_PX. (A zeroed struct is valid too: an eye on the ground, a
 * flat earth, GDAL's interpolation everywhere.) */
tp_viewshed_options tp_viewshed_options_default(void);

/* Computes the viewshed of an observer standing on sample (observer_x, observer_y) (column,
 * row) of heights (width * height floats, row 0 first, NaN = nodata; height_count = width *
 * height) into out (out_count >= width * height bytes, one per sample, the values above). Every
 * byte of out is written, those outside the radius' window too (0). The georeference is the
 * GDAL geotransform of the grid (only its post spacings matter).
 * Fails (out untouched) with TP_ERR_INVALID_ARG for an observer outside the grid, a non-finite
 * or rotated geotransform, a zero post spacing, options outside their ranges (negative or NaN
 * heights, radius or coefficient); TP_ERR_BAD_DATA for an observer on a nodata sample;
 * TP_ERR_OUT_OF_MEMORY (three rows of doubles of scratch). Reentrant: no state between calls. */
tp_status tp_viewshed_compute(const float* heights, size_t height_count, int width, int height,
                              const double geotransform[6], int observer_x, int observer_y,
                              const tp_viewshed_options* options, uint8_t* out,
                              size_t out_count, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Line of sight (los.c): does an observer see a target, and what is in the way
 *
 * Conventions are the viewshed's (above; gdal_viewshed's): the eye observer_height_m above the
 * ground at the observer, the target target_height_m above the ground at the target, every
 * height lowered by curvature_coeff * d^2 / (2 * earth_radius_m) at horizontal distance d from
 * the observer (0.85714 default, 1 curvature without refraction, 0 a flat earth), distances
 * between grid positions in the geotransform's units (|gt[1]| per column, |gt[5]| per row:
 * metres on a render grid; not geodesic).
 *
 * The ground is asked for through a callback at fractional grid positions (column, row; sample
 * centres at integers), so any surface works: the app's full-resolution ground (ground.h), a
 * float grid interpolated by a test. It is sampled along the straight line in the grid at
 * equal steps of at most step_px posts in x and in y (0: 0.25), endpoints included.
 *
 * The sight line runs straight (in the curvature-corrected frame) from the eye to the target's
 * top. A sample blocks when its corrected ground is above the line (on the line counts as
 * seen). Samples within one post of either end (max(|dx|, |dy|) < 1 in grid units) are where
 * observer and target stand and are not tested, as the viewshed always sees the observer's
 * eight neighbours and takes a target's horizon from the ring one post nearer. Void samples
 * (NaN from the callback) block nothing and are counted. The target is visible when no tested
 * sample blocks.
 *
 * The obstruction reported is the highest point above the line (most negative clearance) of
 * the first run of consecutive blocking samples from the observer: the first ridge in the way;
 * blocking_m is how far its ground rises above the sight line there. Clearance at a sample is
 * line - ground (both corrected, so the same as uncorrected line + drop - ground); the
 * smallest over the tested samples is negative exactly when the target is hidden (then minus
 * the worst blocking along the whole line).
 */
#define TP_LOS_STEP_PX 0.25

typedef struct tp_los_options {
    double observer_height_m; /* >= 0 */
    double target_height_m;   /* >= 0 */
    double curvature_coeff;   /* >= 0 */
    double earth_radius_m;    /* 0 means WGS84's 6378137 m */
    double step_px;           /* > 0, at most 1 post; 0 means TP_LOS_STEP_PX */
} tp_los_options;

/* gdal_viewshed's defaults: 2 m, 0 m, 0.85714, WGS84, step 0.25 posts. */
tp_los_options tp_los_options_default(void);

/* The ground at grid (x, y): TP_OK with *height_m (NaN: a void), or an error (with err) that
 * tp_los_compute returns as it is. */
typedef tp_status (*tp_los_height_fn)(void* user, double x, double y, double* height_m,
                                      tp_error* err);

/* One sample along the line (the profile). */
typedef struct tp_los_sample {
    double x, y;        /* grid */
    double distance_m;  /* horizontal, from the observer */
    double ground_m;    /* as the callback gave it; NaN in a void */
    double line_m;      /* the sight line's height above the uncorrected ground's datum:
                           corrected line + drop, so that it plots against ground_m */
    double clearance_m; /* line_m - ground_m; NaN in a void */
    int tested;         /* 0 within one post of either end */
    int seen;           /* only when samples are asked for: a target target_height_m above
                           the ground here would be seen from the eye over the samples at
                           least one post from the observer and one post before this one (its
                           slope from the eye against theirs): the line seen / hidden along the
                           ground. The last sample's equals the result's visible. Always 1
                           within one post of the observer; 0 in a void. */
} tp_los_sample;

typedef struct tp_los_result {
    int visible;                 /* 1: no tested sample blocks */
    double distance_m;           /* observer to target, horizontal */
    double eye_m;                /* observer's ground + observer_height_m */
    double target_m;             /* target's ground + target_height_m (uncorrected) */
    double drop_m;               /* curvature correction at the target */
    int obstructed;              /* !visible; then the obstruction_* fields are set */
    double obstruction_x, obstruction_y, obstruction_distance_m, obstruction_blocking_m;
    double obstruction_ground_m; /* the ground there, as the callback gave it */
    double min_clearance_m;      /* NaN when no sample was tested (endpoints a post apart) */
    double min_clearance_x, min_clearance_y, min_clearance_distance_m;
    size_t sample_count;         /* samples along the line, endpoints included */
    size_t tested_count;         /* samples tested (not near the ends, not void) */
    size_t void_count;           /* tested positions in a void */
} tp_los_result;

/* Samples tp_los_compute takes between these grid positions with these options (>= 2). */
size_t tp_los_sample_count(double from_x, double from_y, double to_x, double to_y,
                           const tp_los_options* options);

/* Line of sight from grid (from_x, from_y) to (to_x, to_y) over the ground height() gives.
 * samples: NULL, or room for sample_capacity >= tp_los_sample_count(...) profile samples.
 * Fails (*out untouched; samples too, except on a callback error mid-way) with
 * TP_ERR_INVALID_ARG for non-finite positions, a
 * non-finite, rotated or zero-spacing geotransform, options outside their ranges (negative or
 * NaN heights or coefficient, step_px outside (0, 1]); TP_ERR_BAD_DATA when the observer or
 * the target stands in a void; or the callback's error. Reentrant, allocates nothing. */
tp_status tp_los_compute(const double geotransform[6], double from_x, double from_y, double to_x,
                         double to_y, const tp_los_options* options, tp_los_height_fn height,
                         void* user, tp_los_sample* samples, size_t sample_capacity,
                         tp_los_result* out, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Error-bounded TIN (tin.c, issue 14; docs/tin.md): a triangulated irregular network over a
 * height grid whose vertical error is at most max_error_m at every valid sample
 *
 * Greedy insertion of the worst sample into a Delaunay triangulation (Garland & Heckbert 1995,
 * "Fast polygonal approximation of terrains and height fields", algorithm III; as mapbox's
 * delatin): start from the grid's four corners (two triangles), find each triangle's worst
 * sample by rasterising it over the grid, keep the triangles above the bound in a max-heap and
 * insert the worst one's sample until none is left above it; each insertion re-rasterises only
 * the triangles it created (split and Lawson-flipped). O(s) per rasterised triangle of s
 * samples, O(log t) per heap operation: about O(samples x log) in practice.
 *
 * The bound: the error at a valid sample is |sample height - the linear interpolation of the
 * triangle that contains it (closed) at the sample|; the build measures it at every valid sample
 * of every output triangle (exact integer inside tests, double interpolation) and returns only
 * when every one is <= max_error_m. A sample on a shared edge interpolates the same from both
 * sides (up to double rounding, about 1e-12 m).
 *
 * Grid coordinates as everywhere in this header: vertex (x, y) is sample (column, row); x, y are
 * integers (exact in the floats below up to 2^24). Triangles are counter-clockwise seen from
 * above on a north-up grid, rows running south: (b - a) x (c - a) < 0 in (column, row), i.e.
 * positive area in (column, -row). Every vertex is distinct; the triangles tile the rectangle
 * [0, width-1] x [0, height-1] exactly (watertight: each interior edge in two triangles, the
 * boundary is the grid's outline).
 *
 * Voids (NaN samples): ignored by the bound (no error is measured there) and never inserted, so
 * triangles span voids; a corner vertex that falls in a void takes the height of the nearest
 * valid sample (Chebyshev rings around the corner, the first found in row order). With
 * TP_TIN_CUT_VOIDS the TIN instead covers exactly the cells the full-resolution mesh draws (a
 * cell = four samples (x, y) .. (x+1, y+1), drawn when all four are valid): every corner of a
 * valid cell that touches (by an edge or a corner) a cell with a void is inserted first, which
 * triangulates those cells on their own, and the triangles over invalid cells are then dropped
 * with the vertices only they used. Without voids the flag changes nothing.
 *
 * Degenerate grids: width or height 1 has no area: no triangles, and every valid sample is a
 * vertex (a polyline, lossless). A grid with no valid sample gives no vertex and no triangle.
 */
typedef struct tp_tin {
    size_t vertex_count;
    float* vertices;          /* vertex_count * 3: grid x, grid y, height (m) */
    size_t triangle_count;
    uint32_t* triangles;      /* triangle_count * 3 vertex indices, counter-clockwise from above */
    float* triangle_error_m;  /* triangle_count: max error over the valid samples it covers */
    double max_error_m;       /* max of triangle_error_m (0 with no triangle) */
    size_t samples_rasterised; /* work done: samples visited measuring errors (for benches) */
} tp_tin;

/* Builds the TIN of a width x height row-major grid (NaN = void) with error <= max_error_m at
 * every valid sample (flags: 0 or TP_TIN_CUT_VOIDS), into *out (free with tp_tin_destroy). height_count must be width * height
 * (asserted). Fails (*out untouched) with TP_ERR_INVALID_ARG for width or height < 1, a grid of
 * 2^32 samples or more, max_error_m negative or not finite; TP_ERR_OUT_OF_MEMORY. Reentrant.
 * max_error_m = 0 inserts every sample that any interpolation misses (on random data every
 * sample: 2 (width-1)(height-1) triangles). */
enum { TP_TIN_CUT_VOIDS = 1u };

tp_status tp_tin_build(const float* heights, size_t height_count, int width, int height,
                       double max_error_m, unsigned flags, tp_tin** out, tp_error* err);

/* The same TIN built tile by tile (tin_tiles.c; docs/tin.md "Tiled build"), on several threads,
 * each tile with a working set of its own size: the basis for building one store node at a time.
 *
 * Tiles: tile_cells x tile_cells cells (tile_cells >= 1; larger than the grid: one tile), their
 * corners at multiples of tile_cells and at the grid's last row and column (so the last tile of a
 * row or column may be smaller, never below 1 cell); neighbouring tiles share their border
 * samples. Each tile side (the samples between two tile corners) is simplified on its own by a
 * 1-D greedy polyline: the worst valid sample is chosen until every valid sample of the side is
 * within max_error_m of the line between the chosen samples around it (the corners always
 * chosen; with TP_TIN_CUT_VOIDS the samples the void outline forces too). The tiles on both sides
 * compute the same polyline from the same samples, and inside a tile the other border samples are
 * neither measured nor inserted: each tile is then built as tp_tin_build builds a grid, without
 * reading its neighbours (but for the corners' heights, below, and two samples around the tile
 * for the void outline), and the tiles meet edge for edge.
 *
 * Output: one tp_tin with the conventions of tp_tin_build (counter-clockwise, the bound at every
 * valid sample, watertight, covering the rectangle or, with TP_TIN_CUT_VOIDS, exactly the valid
 * cells; each grid sample at most one vertex); triangle_error_m counts the border samples on a
 * triangle's edge; samples_rasterised is summed over the tiles. Vertices and triangles come in
 * tile order (rows of tiles from the top, left to right), so the output is the same whatever the
 * thread count. A corner of a tile in a void takes the nearest valid sample's height within
 * tile_cells (else the nearest such corner's), computed once on the whole grid, so all the tiles
 * around it agree. The triangles differ from tp_tin_build's near the tile borders (the borders
 * are polylines the Delaunay insertion cannot move): 0.99 to 1.03 times as many on the measured
 * DEMs (docs/PERFORMANCE.md, "Error-bounded TIN").
 *
 * threads: >= 1, or 0 for the online CPUs (at most 64); never more than the tiles. Memory: the
 * tiles' outputs until the merge, and per thread one tile's build. Grids of width or height 1 and
 * grids without a valid sample give tp_tin_build's answer. Fails (*out untouched) as tp_tin_build
 * does, and with TP_ERR_INVALID_ARG for tile_cells < 1, threads < 0 or over 2^30 tiles.
 * Reentrant. */
tp_status tp_tin_build_tiled(const float* heights, size_t height_count, int width, int height,
                             double max_error_m, unsigned flags, int tile_cells, int threads,
                             tp_tin** out, tp_error* err);

/* One tile of that tiling built on its own, from a window of the grid: what a caller that never
 * holds the whole grid (a store export, one window of leaves at a time) builds tile by tile.
 *
 * The tile is tile_w x tile_h samples (>= 2 each), its first sample at (tile_x, tile_y) of the
 * window; the window is the tile widened by 2 samples on each side, clipped to the grid only
 * (tile_x, tile_y in 0..2, and 0..2 samples right of and below it): the void outline rule reads
 * them, and a window clipped anywhere else than at the grid's edge gives another answer than the
 * whole grid. Rows are stride floats apart. corner_z: the heights of the tile's corners (top-left,
 * top-right, bottom-left, bottom-right) used where the corner sample is void and as the ends of
 * its sides' polylines, the same for every tile that shares the corner; required without
 * TP_TIN_CUT_VOIDS, NULL allowed with it (the corners' own samples are used: triangles touching
 * a void corner are cut anyway). Tiles built with the same corner heights (or none) from the
 * same samples meet edge for edge, as in tp_tin_build_tiled.
 *
 * Output: the tile's TIN in the tile's own coordinates (vertex (0, 0) is the tile's first
 * sample), or *out = NULL with TP_OK when the cut leaves nothing (no valid sample). Fails with
 * TP_ERR_INVALID_ARG for a tile that does not fit its window as above, a bound as tp_tin_build
 * refuses, or no corner heights without the cut; TP_ERR_OUT_OF_MEMORY. Reentrant. */
tp_status tp_tin_build_tile(const float* window, size_t stride, int win_w, int win_h, int tile_x,
                            int tile_y, int tile_w, int tile_h, const float corner_z[4],
                            double max_error_m, unsigned flags, tp_tin** out, tp_error* err);

/* Frees a TIN; NULL is allowed. */
void tp_tin_destroy(tp_tin* tin);

/* ---------------------------------------------------------------------------------------------
 * True error of a triangle mesh over a height grid (tin_measure.c, issue 14): the checker that
 * `bench --static` applies to every mesher's output (ours, delatin's, martini's), independent of
 * how the mesh was built (it shares no code with tin.c)
 *
 * The mesh: vertices at integer grid positions (x = column, y = row, as in "Error-bounded TIN"),
 * each with a height, and triangles of three vertex indices, of either orientation. Every
 * triangle is rasterised row by row over the grid: the span of each row is solved exactly from
 * the integer edge equations (the closed triangle: samples on an edge or a vertex are inside),
 * and each valid sample inside gets the barycentric interpolation of the three vertex heights,
 * with weights from exact int64 orientations. A sample inside several triangles (on shared
 * edges, or where a broken mesh overlaps) counts with its largest error. NaN samples (voids) are
 * ignored. Triangles of zero area cover nothing (counted apart).
 */
typedef struct tp_tin_measure_result {
    double max_error_m;          /* max |sample height - interpolation| over covered valid samples
                                    (0 when none is covered) */
    int worst_x, worst_y;        /* a sample where max_error_m is reached (-1, -1 when none) */
    double rms_error_m;          /* over covered valid samples, each once (its largest error) */
    size_t covered_samples;      /* valid samples inside at least one triangle */
    size_t uncovered_samples;    /* valid samples no triangle covers (0 for a mesh of the whole
                                    valid grid) */
    size_t degenerate_triangles; /* triangles of zero area (skipped) */
} tp_tin_measure_result;

/* Measures the mesh (vertices: vertex_count * 3 floats x, y, height; triangles: triangle_count
 * * 3 indices) against the width x height row-major grid heights (height_count = width *
 * height). Fails (*out untouched) with TP_ERR_INVALID_ARG for a grid below 1x1 or of 2^32
 * samples or more, height_count != width * height, a vertex whose x or y is not an integer
 * inside the grid or whose height is not finite, a triangle index >= vertex_count, NULL arrays
 * with a non-zero count; TP_ERR_OUT_OF_MEMORY (4 bytes per sample are allocated). Reentrant.
 * Takes O(samples covered) time plus O(rows spanned) per triangle. */
tp_status tp_tin_measure(const float* heights, size_t height_count, int width, int height,
                         const float* vertices, size_t vertex_count, const uint32_t* triangles,
                         size_t triangle_count, tp_tin_measure_result* out, tp_error* err);


/* ---------------------------------------------------------------------------------------------
 * Clip windows over an image pyramid (clipmap.c, issue 15; Luo & Duan, "Clipmap texture
 * streaming", sections 3.2-3.5) and per-polygon texture levels (Blow, "Terrain rendering at
 * high levels of detail", Part I)
 *
 * Each level l of a pyramid (level 0 finest, level l + 1 half as many texels a side) is cut into
 * square blocks of `block` texels. A clip region holds, per level, the s x s blocks of a window
 * (s even) in one texture layer of s * block texels a side: block (bx, by) lives in slot
 * (bx mod s, by mod s) of the layer, so moving the window by one block column reuses every slot
 * but that column's (a toroidal update: only newly covered blocks are uploaded). Coordinates
 * here are level texels (x east, y south, (0, 0) the level's top-left corner) and block indices
 * (int64: windows may lie partly outside the image).
 */
typedef struct tp_clip_window {
    int64_t bx0, by0; /* first block column and row; the window is [bx0, bx0 + s) x [by0, by0 + s) */
    int s;            /* blocks a side */
} tp_clip_window;

/* The window of s x s blocks (s even, 2..1024) whose centre is nearest the point (cx, cy)
 * (level texels): bx0 = round(cx / block - s / 2), so the point lies at least s / 2 - 1/2
 * blocks inside every edge. block >= 1. */
tp_clip_window tp_clip_window_centred(double cx, double cy, int block, int s);

/* Slot of block index b in a window of s blocks a side: b mod s, in 0..s-1 for any b. */
int tp_clip_slot(int64_t b, int s);

/* 1 if block (bx, by) is in the window. */
int tp_clip_window_contains(const tp_clip_window* w, int64_t bx, int64_t by);

/* Whether block (bx, by) of the window holds its own texels in its slot (loaded and uploaded). */
typedef int (*tp_clip_resident_fn)(void* user, int64_t bx, int64_t by);

/* The valid region of a level: the rectangle of blocks around the block holding (cx, cy), grown
 * one block row or column at a time (east, south, west, north in turn) while the whole new row
 * or column is inside the window and resident, so that a sampler restricted to it (less half a
 * texel at each edge for bilinear filtering) never reads a slot that holds another block's or
 * stale texels (Luo & Duan section 3.5). Writes rect = {bx0, by0, bx1, by1} (exclusive ends)
 * and returns 1; returns 0 (rect untouched) when the centre block is outside the window or not
 * resident. O(s^3) resident calls at most. */
int tp_clip_valid_rect(const tp_clip_window* w, double cx, double cy, int block,
                       tp_clip_resident_fn resident, void* user, int64_t rect[4]);

/* Blow's texture level: floor(log2(texels_per_pixel)) clamped to 0..max_level, read from the
 * IEEE 754 exponent bits of the float (no log2: one shift and one subtraction); a ratio below
 * 1, zero, negative or NaN gives 0, +infinity max_level. Exact for every float (a power of two
 * is its own level). */
int tp_texture_level(float texels_per_pixel, int max_level);

/* The level a patch needs: texels of level 0 per pixel at its nearest point, distance_m from the
 * eye (metres), for level-0 texels of texel_m metres and focal_px pixels per unit tangent
 * (tp_camera_frame.focal_px): distance / (focal * texel). Frame coherence (Blow): previous is
 * the level the patch used last frame (-1: none); the level goes finer at once but coarser only
 * once the ratio is 1/8 past the boundary, so a patch at a boundary does not flip every frame. */
int tp_patch_texture_level(double distance_m, double focal_px, double texel_m, int previous,
                           int max_level);

/* ---------------------------------------------------------------------------------------------
 * Shadows (shadow.c, light_day.c; issue 15, docs/light.md): which samples the sun lights
 *
 * Terrain self-shadowing on a height grid: heights (width * height floats, row 0 first = north,
 * column 0 = west, NaN = void), posts dx_m apart along a row (east) and dy_m along a column
 * (south), the ground between posts the bilinear surface. The sun is a direction: azimuth_deg
 * clockwise from GRID north (the grid's -row axis; a caller with a true azimuth subtracts the
 * meridian convergence, tp_ground_sample.convergence_deg), elevation_deg above the grid's
 * horizontal plane (for refraction, pass the apparent elevation).
 *
 * Assumptions: a flat earth within the grid and one sun direction for all of it: the sun's
 * elevation is the one at the place the caller computed it for (the centre); the earth's
 * curvature (which tilts the local horizontal by 0.009 degree per km, 0.27 degree across 30 km)
 * and the drop of distant ground (d^2 / 2R: 70 m at 30 km) are left out. Voids block no light
 * (a ray passes over them at the shadow height it carries) and are never lit. Nothing outside
 * the grid casts a shadow.
 *
 * A sample is lit when no ground between it and the sun along the sun's direction stands above
 * the ray from the sample's height toward the sun; its margin is its height less the height of
 * the shadowing sight line above it (the top of the shadow volume): > 0 lit (how much lower it
 * could be and still be lit), < 0 in shadow (how far it would have to rise). A margin of exactly
 * 0 counts as lit. A lit sample's margin measures the nearest sight line (often the ground just
 * beside it), not the peak whose shadow may come: to move shadows in time, tp_light_day_*
 * interpolate horizons instead.
 *
 * tp_shadow_compute is one sweep over the grid from the sun's side (O(samples *
 * TP_SHADOW_EXACT_LINES); docs/light.md has the timings beside a per-sample ray cast's), exact
 * for the ground along a ray's first TP_SHADOW_EXACT_LINES grid lines and interpolated (linearly
 * between two posts) for the shadow volume carried from further away; docs/light.md gives its
 * measured agreement with a ray cast on real DEMs (>= 99% of samples, tests/test_shadow.c).
 */
#define TP_SHADOW_LIT 1
#define TP_SHADOW_SHADOWED 0
/* A ray's ground is taken exactly over the first this many grid lines it crosses (at each
 * crossing and halfway between two), the shadow volume carried from beyond interpolated only
 * there: 8 keeps the agreement with the ray cast >= 99.3% on Mt Hood and N42E001 (a plain sweep
 * interpolating at every line, without the halfway points: 98.5%). */
#define TP_SHADOW_EXACT_LINES 8

/* Writes into lit (out_count >= width * height bytes, or NULL) TP_SHADOW_LIT or
 * TP_SHADOW_SHADOWED per sample (voids TP_SHADOW_SHADOWED), and into margin_m (out_count
 * floats, or NULL) the margin in metres: +INFINITY where no ground of the grid lies toward the
 * sun, NaN on voids. At least one of lit and margin_m is not NULL. The sun below or on the
 * horizon (elevation_deg <= 0): every sample shadowed, margins -INFINITY; at the zenith
 * (elevation_deg = 90): every valid sample lit, margins +INFINITY. Fails (outputs untouched)
 * with TP_ERR_INVALID_ARG for height_count != width * height or a grid below 1x1, spacings not
 * finite and > 0, a non-finite azimuth (any finite value is taken modulo 360) or an elevation
 * outside -90 .. 90; TP_ERR_OUT_OF_MEMORY (three floats per sample of scratch).
 * Reentrant. */
tp_status tp_shadow_compute(const float* heights, size_t height_count, int width, int height,
                            double dx_m, double dy_m, double azimuth_deg, double elevation_deg,
                            uint8_t* lit, float* margin_m, size_t out_count, tp_error* err);

/* The direct sunlight on the ground as a byte per sample: round(255 * cos(incidence)) where
 * the surface faces the sun, 0 where it faces away, lies in a shadow (lit[i] == 0; lit may be
 * NULL: no cast shadows) or is a void, all 0 with the sun on or below the horizon. The normal
 * is from central differences of the posts (one-sided at the grid's edge and beside voids, flat
 * where a sample has no neighbour), as gdaldem hillshade's. Same grid and sun conventions and
 * failures as tp_shadow_compute (out untouched on failure). */
tp_status tp_shadow_illumination(const float* heights, size_t height_count, int width,
                                 int height, double dx_m, double dy_m, double azimuth_deg,
                                 double elevation_deg, const uint8_t* lit, uint8_t* out,
                                 size_t out_count, tp_error* err);

/* The sun over a day (Blow, "Two Advanced Terrain Rendering Systems", Part II: 64 illumination
 * maps across the day, interpolated in time so that a peak's shadow crawls smoothly): the
 * shadows of count sun positions (times increasing, e.g. TP_LIGHT_DAY_MAPS from sunrise to
 * sunset), one int16 per sample per map (2 bytes; a float would be 4): 0 where the sample is
 * lit; where it is in shadow, minus the excess of its horizon over the sun, tan(h) - tan(e) in
 * units of TP_LIGHT_DAY_TAN_STEP (at least 1, at most 32767: deep shadow), h the elevation of
 * the ground that shadows it seen from the sample (tp_shadow_compute's sweep carries the
 * distance to that ground); with the sun on or below the horizon, h = 0.
 *
 * At a time between maps k and k+1 (weight w from k) a sample lit (or shadowed) in both is lit
 * (shadowed); one that changes is lit until (or from) the time the sun's tan(e), interpolated
 * linearly between the maps' tan(e), passes its horizon tan(h) from the map where it is in
 * shadow: so a shadow lengthening or shortening with the sun's elevation moves smoothly and
 * monotonically, its end where the horizon puts it. Where the change is not the elevation's
 * doing (the sun turning past a peak at nearly constant elevation), the sample changes at
 * w = 1/2. Height margins would not do: a lit sample's margin measures the ground next to it,
 * not the peak whose shadow is coming (docs/light.md). */
#define TP_LIGHT_DAY_MAPS 64
#define TP_LIGHT_DAY_TAN_STEP 1e-4 /* tan(h) - tan(e) per unit: 0.006 degree at 5 degrees */
#define TP_LIGHT_DAY_VOID INT16_MIN /* the stored code of a void */

typedef struct tp_light_day {
    int width, height, count;
    double* times_s;       /* count, strictly increasing (any time axis: Unix seconds) */
    double* azimuth_deg;   /* count, the sun (grid azimuth) of each map */
    double* elevation_deg; /* count */
    int16_t* codes;        /* count * width * height: map k's samples from k * width * height;
                              0 lit, < 0 shadowed (above), TP_LIGHT_DAY_VOID on voids */
} tp_light_day;

/* Computes the count maps of the grid (conventions of tp_shadow_compute). All of *out is owned
 * by it: tp_light_day_destroy. Fails (*out untouched) as tp_shadow_compute for the grid and
 * each sun, and with TP_ERR_INVALID_ARG for count < 2 or times not finite and strictly
 * increasing; TP_ERR_OUT_OF_MEMORY (2 * count bytes per sample, 17 more during the build). */
tp_status tp_light_day_build(const float* heights, size_t height_count, int width, int height,
                             double dx_m, double dy_m, const double* times_s,
                             const double* azimuth_deg, const double* elevation_deg, int count,
                             tp_light_day** out, tp_error* err);
void tp_light_day_destroy(tp_light_day* day); /* accepts NULL */

/* The shadows at time_s (times_s[0] <= time_s <= times_s[count - 1]) into lit (out_count >=
 * width * height bytes; TP_SHADOW_LIT or TP_SHADOW_SHADOWED, voids shadowed), interpolated as
 * above. Fails (lit untouched) with TP_ERR_INVALID_ARG for a time outside the maps' (the
 * message gives their range) or NaN. */
tp_status tp_light_day_at(const tp_light_day* day, double time_s, uint8_t* lit,
                          size_t out_count, tp_error* err);

/* The sun over a day as each sample's lit intervals ("light times"; issue 15): Blow's maps
 * (tp_light_day) compressed to four bytes a sample that a GPU samples and filters like
 * imagery, so that a light map of any size streams through the viewer's clipmap and the time
 * moves with one uniform. Each sample's day, times_s[0] .. times_s[count - 1], holds at most two
 * intervals in which it is lit; each end is where tp_light_day_at's interpolation between two
 * maps changes the sample (where the sun's elevation passes its horizon), quantised to
 *     tau = TP_LIGHT_TIMES_STEPS * (t - times_s[0]) / (times_s[count - 1] - times_s[0])
 * rounded to the nearest step. A texel is (r1, s1, r2, s2) with r1 <= s1 <= r2 <= s2: lit at
 * tau when r1 <= tau < s1 or r2 <= tau < s2 (tp_light_times_lit); only one interval: r2 = s2 =
 * s1; never lit (voids too): all 0. Bilinear filtering of the four bytes between samples moves
 * a shadow's edge continuously in time. A sample lit over more than two intervals keeps the
 * two that lose least: the shorter of its shortest shadow gap (bridged) and its shortest lit
 * interval (dropped) is given up, repeatedly; stats count those samples and the longest time
 * given up. */
#define TP_LIGHT_TIMES_STEPS 255

typedef struct tp_light_times_stats {
    size_t samples;          /* width * height */
    size_t simplified;       /* samples with more than two lit intervals */
    double given_up_max_s;   /* the longest time one simplification changed, seconds */
    size_t lit_any;          /* samples lit at some time of the day */
} tp_light_times_stats;

/* Writes 4 * width * height bytes into out (out_count >= that), row-major, a texel per
 * sample as above; stats may be NULL. Computes the maps one after another (memory: the
 * heights, out, and about 40 bytes a sample; not tp_light_day's 2 * count). progress may be
 * NULL: called after each map with (k + 1) / count. Same grid and sun conventions and failures
 * as tp_light_day_build (out untouched on failure). Reentrant. */
tp_status tp_light_times_build(const float* heights, size_t height_count, int width, int height,
                               double dx_m, double dy_m, const double* times_s,
                               const double* azimuth_deg, const double* elevation_deg,
                               int count, uint8_t* out, size_t out_count,
                               tp_light_times_stats* stats,
                               void (*progress)(void* user, double fraction), void* user,
                               tp_error* err);

/* tau in steps for time_s in the day t_first .. t_last (may be < 0 or > 255: outside it). */
double tp_light_times_tau(double t_first_s, double t_last_s, double time_s);

/* 1 when the texel is lit at tau (steps), else 0: as the viewer's shader decides at a post. */
int tp_light_times_lit(const uint8_t texel[4], double tau);

/* The texel of a coarser level: the rounded mean of each byte of the (up to) four texels of
 * the finer one (n = 1..4 of them; the order r1 <= s1 <= r2 <= s2 is kept). */
void tp_light_times_mean(const uint8_t* const* texels, int n, uint8_t out[4]);


/* ---------------------------------------------------------------------------------------------
 * Persistent Grid Mapping (pgm.c, pgm_error.c; Livny, Kogan & El-Sana, seeds/001; issue 16)
 *
 * A grid of cols x rows vertices fixed in screen space, cached on the GPU once. Each frame,
 * vertex (i, j) (i = 0..cols-1 left to right, j = 0..rows-1 top to bottom) is the pixel
 * (i * w / (cols - 1), j * h / (rows - 1)) of the auxiliary camera (Eq. 2); the ray from the eye
 * through it meets the base plane h = base_m at P (Eq. 1); the vertex is drawn at P's E and N
 * and the height read from the elevation pyramid at P, at the level the distance r to its
 * farthest neighbour asks for (Eq. 3), blended with the parent level (Eq. 4). Cell (i, j) is the
 * two triangles (i,j) (i+1,j) (i,j+1) and (i+1,j) (i+1,j+1) (i,j+1) (split along (i+1,j)-(i,j+1));
 * a triangle with a vertex off the terrain is not drawn. The viewer's vertex shader and
 * tp_pgm_map_vertex compute the same numbers (the shader in floats, eye-relative).
 */
#define TP_PGM_MAX_LEVELS 24
#define TP_PGM_DEFAULT_COLS 300
#define TP_PGM_DEFAULT_ROWS 300

/* The elevation pyramid: level 0 is the given grid; level l has posts i = 0..width[l]-1 evenly
 * spaced at level-0 grid x = i * 2^l (the same in y), each holding the level-0 height of post
 * min(i * 2^l, width[0] - 1) (point sampling: every level's posts are source posts; the last
 * post may lie past the edge and then repeats the edge's height, so that every level reaches
 * the whole extent). width[l] = width[l-1] / 2 + 1 (integer division; = ceil((width[0] - 1) /
 * 2^l) + 1), height likewise: 1201 -> 601 -> 301 -> 151 -> 76 -> 39 ..., 1000 -> 501 -> 251.
 * Levels stop when both sides are <= 2 posts or at TP_PGM_MAX_LEVELS (a 1 x 1 or 2 x 2 grid
 * has 1 level). A shader samples level l at texel (x / 2^l, y / 2^l) (+ 0.5 for texel
 * centres) with clamp-to-edge, after clamping x, y to the level-0 extent as below. */
typedef struct tp_pgm_pyramid {
    int levels;
    int width[TP_PGM_MAX_LEVELS], height[TP_PGM_MAX_LEVELS];
    float* z[TP_PGM_MAX_LEVELS]; /* row-major, top row first; owned (tp_pgm_pyramid_free) */
    double geotransform[6];      /* of level 0: post (x, y) at E = gt[0] + (x + 0.5) * gt[1],
                                    N = gt[3] + (y + 0.5) * gt[5] (north-up: gt[2] = gt[4] = 0) */
    double min_m, max_m;         /* of level 0 */
} tp_pgm_pyramid;

/* Builds the pyramid of a width x height grid (no NaN: fill voids first; width, height >= 1).
 * Returns TP_OK and fills *out (free with tp_pgm_pyramid_free); TP_ERR_INVALID_ARG (a NaN
 * height, a size < 1 or a rotated or zero geotransform), TP_ERR_OUT_OF_MEMORY; *out is then
 * zeroed. */
tp_status tp_pgm_pyramid_build(const float* heights, int width, int height, const double gt[6],
                               tp_pgm_pyramid* out, tp_error* err);
void tp_pgm_pyramid_free(tp_pgm_pyramid* p); /* accepts NULL and a zeroed pyramid */

/* The bilinear height of level `level` (0..levels-1) at level-0 grid coordinates (x, y) (post
 * units, post (0, 0) at (0, 0)): x, y are first clamped to [0, width[0] - 1] x
 * [0, height[0] - 1], then level l is interpolated at (x / 2^l, y / 2^l) between its posts.
 * Cannot fail. */
double tp_pgm_pyramid_sample(const tp_pgm_pyramid* p, int level, double x, double y);

/* Eq. 2: the auxiliary camera. Same eye, yaw, field of view, viewport and near/far planes as
 * main; its pitch is min(main's pitch, -(fov_y / 2 + epsilon_rad)) (pitch < 0 looks down), so
 * that every ray of its image goes down and meets the base plane. It is main itself when main
 * already looks down that far (for a camera rolled about its axis, as tp_camera_from_pose never
 * makes, only when its four corner rays go down too; else it is levelled: no roll, the same
 * pitch). Its yaw is the heading 90 degrees left of main's right vector (main's yaw, and
 * defined looking straight up or down as well). Cannot fail. */
void tp_pgm_aux_camera(const tp_camera* main, double epsilon_rad, tp_camera* aux);

/* Everything one frame's mapping needs, set up once per frame (the shader's uniforms). */
typedef struct tp_pgm_frame {
    int cols, rows;
    tp_camera aux;          /* tp_pgm_aux_camera(main, 1e-3 rad) */
    tp_camera_frame aux_frame;
    double base_m;          /* the base plane's height: the pyramid's min_m */
    double eye_above_base_m; /* h in Eq. 3: eye height - base_m, at least 1 m. The rays meet
                                the plane at height eye - eye_above_base_m (base_m unless the
                                eye is less than 1 m above it) */
    double sin_alpha, cos_alpha; /* alpha: the larger angle between adjacent rays at the
                                    image centre, rows or cols: atan(max(w / (cols - 1),
                                    h / (rows - 1)) / focal_px) */
    double post_m;          /* level-0 post spacing: min(|gt[1]|, |gt[5]|) */
} tp_pgm_frame;

/* Sets up *out for main (fov, viewport and pose), the grid size (cols, rows >= 2; asserted) and
 * the pyramid. Cannot fail. */
void tp_pgm_frame_setup(const tp_camera* main, int cols, int rows, const tp_pgm_pyramid* p,
                        tp_pgm_frame* out);

/* Maps grid vertex (i, j): writes world[3] (E, N, height) and *lod, the continuous level
 * l + W_p (l = floor(log2(r / post_m)) clamped to [0, levels - 1], W_p = r / (post_m * 2^l) - 1
 * clamped to [0, 1], 0 at the last level; r from Eq. 3 with d = |P - eye|, q its horizontal
 * part, h = eye_above_base_m; r is infinite (last level) where h cos(alpha) <= q sin(alpha)),
 * the height being (1 - W_p) * sample(l) + W_p * sample(l + 1). W_p reaches 1 where l steps
 * up, so heights and lod are continuous in r. Returns 1 when P lies on the terrain (inside
 * the level-0 extent: 0 <= x <= width - 1, 0 <= y <= height - 1 in grid coordinates), else 0
 * (world and lod are written anyway, the height clamped to the edge). */
int tp_pgm_map_vertex(const tp_pgm_frame* f, const tp_pgm_pyramid* p, int i, int j,
                      double world[3], double* lod);

/* The error of one frame's PGM surface by the bench's definition: every level-0 post that the
 * main camera sees inside its viewport (projected inside, edges included, in front of the near
 * plane and not past a far plane; occlusion ignored) is compared with the drawn surface
 * vertically above or below it (the drawn triangle of the mapped grid, frame f, that covers
 * its E, N; linear interpolation): vertical error |drawn - post| in metres and screen error,
 * the on-screen distance between the projections of the two points, in pixels (infinite when
 * only the drawn point is behind the eye), as tp_selection_measure_screen_error. A post on an
 * edge two triangles share is counted once. Posts no drawn triangle covers (beyond the
 * terrain's edge triangles, which are not drawn, or outside the aux camera's footprint) are
 * counted in `uncovered`, not in the error; rms are 0 without samples. Scratch memory: about
 * 25 bytes per grid vertex and 5 per post of a band of 64 rows (tp_pgm_measure_error_source
 * over the pyramid). Returns TP_OK and writes *out;
 * TP_ERR_OUT_OF_MEMORY (*out zeroed). */
typedef struct tp_pgm_error {
    double max_m, rms_m;   /* vertical */
    double max_px, rms_px; /* screen */
    size_t samples;        /* posts in view that a triangle covers */
    size_t uncovered;      /* posts in view that none covers */
} tp_pgm_error;
tp_status tp_pgm_measure_error(const tp_pgm_frame* f, const tp_pgm_pyramid* p,
                               const tp_camera* main, tp_pgm_error* out);

/* ---- PGM over a store: the elevation clipmap's bookkeeping (pgm_clip.c; seeds/001 section 4)
 *
 * For a terrain larger than texture memory, level l of the elevation pyramid (the posts
 * tp_pgm_pyramid would hold for the store's source grid: post (i, j) of level l is level-0 post
 * (min(i 2^l, width[0] - 1), min(j 2^l, height[0] - 1))) is kept as a window of w x w posts
 * (w a power of two) around the eye: posts origin_x <= i < origin_x + w, likewise in y, each at
 * texel (i mod w, j mod w) of its level's w x w texture (toroidal addressing). When the eye
 * moves, only the posts the window gains are written: at most two rectangles (the paper's L- or
 * F-shaped strips), the whole window after a jump of w posts or more. */
typedef struct tp_pgm_rect {
    int x0, y0, x1, y1; /* posts x0 <= x < x1, y0 <= y < y1 (empty when x1 <= x0 or y1 <= y0) */
} tp_pgm_rect;

/* The window's origin along one axis of a level with `posts` posts there, for a centre at
 * level-post coordinate `centre` (any value; NaN counts as 0): floor(centre) - w / 2, clamped to
 * [0, posts - w] so that the window stays on the terrain (0 when posts <= w: the whole axis
 * fits, the window never moves). w >= 1. Cannot fail. */
int tp_pgm_clip_origin(double centre, int posts, int w);

/* The posts a w x w window gains when its origin moves from (old_x, old_y) to (new_x, new_y)
 * (any integers, negative ones included, with |origin| + w < 2^31): written to out as at most 2 disjoint, non-empty
 * rectangles; returns how many (0 when it did not move). has_old = 0 (the window held nothing
 * yet) or a move of w or more posts along either axis: one rectangle, the whole new window.
 * Else the strip of columns the window gains (its whole height) and the strip of rows it gains
 * over the columns it kept. Every post of the new window that the old one did not hold is in
 * exactly one rectangle; no other post is. w >= 1 (asserted). */
int tp_pgm_clip_update(int w, int has_old, int old_x, int old_y, int new_x, int new_y,
                       tp_pgm_rect out[2]);

/* The smallest window (a power of two, at least 16) that holds the coarsest level of the
 * pyramid of a width x height grid whole (width, height >= 1; asserted), as a clipmap's
 * coarsest window must (the shader falls back to it everywhere). Levels stop at
 * TP_PGM_MAX_LEVELS, so a side of more than 2^24 + 1 posts keeps ceil((side - 1) / 2^23) + 1 > 2
 * at level 23: a window w holds it while side <= (w - 1) 2^23 + 1 (16: up to 125,829,121 posts);
 * else the coarsest level has at most 2 posts and this is 16. Cannot fail. */
int tp_pgm_clip_min_window(int width, int height);

/* Where a store holds level-0 post (x, y) (0 <= x < src_width, 0 <= y < src_height; asserted)
 * for level `level` of the pyramid: the node of the coarsest scale s <= level (and < g->scales)
 * whose lattice holds it (x and y multiples of 2^s, inside the nodes of that scale, which
 * exist only as whole quadtree nodes; the node's column min(x >> (n + s), node_cols[s] - 1),
 * row likewise, so that posts on the far edge of the last node column are found too), and the
 * sample's index in that node's (2^n + 1)^2 samples. Reading coarse levels
 * from coarse nodes keeps the nodes a window touches about w^2 / 4^n whatever the level. Every
 * node holding a sample holds the same height (tp_tree_samples), so the choice only matters for
 * speed. Returns the node id and writes *sample. Cannot fail. */
int64_t tp_pgm_store_post(const tp_tree_geometry* g, int level, int x, int y, size_t* sample);

/* ---- the error of a PGM surface whose heights are not one tp_pgm_pyramid's (pgm_error.c)
 *
 * What a renderer draws and the level-0 posts it is compared with, for
 * tp_pgm_measure_error_source: a whole pyramid (tp_pgm_measure_error), or a store's clipmap
 * (the viewer's app/view/pgm_clip_error.c: its windows' posts, level-0 posts read from nodes). */
typedef struct tp_pgm_source {
    void* ctx;
    /* The height drawn at level-0 grid coordinates (x, y) when level `level` (0 .. levels - 1)
     * is read there, as tp_pgm_pyramid_sample reads a whole pyramid; NaN where nothing is drawn
     * (the vertex then counts as off the terrain). */
    double (*sample)(void* ctx, int level, double x, double y);
    /* The level-0 posts x0 <= x < x1 of rows y0 <= y < y1 into out (row-major, x1 - x0 a row),
     * NaN where a post has no height (then neither compared nor counted). 1, or 0 when they
     * cannot be read (the measure fails with TP_ERR_IO; the source keeps its own message). */
    int (*posts)(void* ctx, int x0, int y0, int x1, int y1, float* out);
    int band_rows; /* rows asked for at once, in bands aligned to its multiples; 0: 64 */
} tp_pgm_source;

/* A rectangle of level-0 posts (inside shape's level-0 extent) that holds every post main can
 * see at a height between shape->min_m and max_m (a superset: the bounding box of the view's
 * part of that slab, two posts of room); empty (x1 <= x0 or y1 <= y0) when there is none. The
 * whole extent along an axis when a corner ray of the view does not go down (the view reaches
 * the horizon) and no far plane bounds it. Cannot fail. */
void tp_pgm_view_region(const tp_pgm_pyramid* shape, const tp_camera* main, tp_pgm_rect* out);

/* tp_pgm_measure_error over a source: the same definition and results, the drawn heights
 * src->sample's (Eq. 4's blend of a level and its parent as tp_pgm_map_vertex blends them; a
 * NaN in either voids the vertex), the posts compared those of region (NULL: the whole level-0
 * extent; tp_pgm_view_region bounds them) read with src->posts band by band. shape gives the
 * levels, sizes, geotransform and min_m (the base plane, as for tp_pgm_frame_setup); its z are
 * not read. Memory: about 25 bytes a grid vertex and 5 bytes a post of one band (region's width
 * x band_rows). Time: every triangle per band, and every post of the region. TP_OK and *out;
 * TP_ERR_IO (src->posts failed) or TP_ERR_OUT_OF_MEMORY with *out zeroed. */
tp_status tp_pgm_measure_error_source(const tp_pgm_frame* f, const tp_pgm_pyramid* shape,
                                      const tp_pgm_source* src, const tp_pgm_rect* region,
                                      const tp_camera* main, tp_pgm_error* out);

#ifdef __cplusplus
}
#endif
#endif /* TP_CORE_H */
