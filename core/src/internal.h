/* internal.h - private types and helpers shared by the core's .c files. Not installed. */
#ifndef TP_CORE_INTERNAL_H
#define TP_CORE_INTERNAL_H

#include "tp_core.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>

/* Stored height of a sample that is not drawn (nodata). Padding is never stored at all. */
#define TP__NO_HEIGHT 0xFFFFu
/* Error tables are uint16 in units of err_unit steps (step/16, or coarser when a patch's height
 * range would not fit), rounded up. TP__ERR_SAT means "at least this large": the bound then
 * falls back to the patch's height range, which bounds any error inside the patch. */
#define TP__ERR_SAT 0xFFFFu

typedef struct tp__patch {
    int32_t offset;     /* global quantised height = stored + offset, for samples it owns */
    int32_t qmin, qmax; /* global quantised range over all drawn samples of the patch */
    uint8_t complete;   /* every sample drawn */
    uint8_t has_drawn;  /* at least one drawn sample */
} tp__patch;

struct tp_terrain {
    tp_terrain_info info;
    tp_allocator alloc; /* always set (malloc / free by default) */
    int n, ps;          /* finest level, patch span 2^n (patch size - 1) */
    int w, h;           /* fitted grid */
    int sw, sh;         /* stored region: samples with x >= sw or y >= sh are padding */
    double gt[6];       /* geotransform of the fitted grid */
    double step;        /* quantisation step (m) */
    double quant_err;   /* max |source - decoded| (m) */
    uint16_t* q;        /* sw * sh stored heights, relative to the owner patch's offset */
    uint8_t* filled;    /* NULL, or one bit per stored sample: filled void */
    tp__patch* patches;
    /* Error tables, per patch: delta[k] for k = 0..n, then eps[side][kn] for side 0..3 and
     * neighbour level kn = 0..n-1. See patch_error.c. */
    uint16_t* err_tab;
    int err_stride;
    /* Vertex adding's table, NULL until tp_terrain_prepare_stitch_add (a terrain drawn by
     * vertex moving does not hold it): per patch 4 n^2 entries eta[side][k][kn - 1] for side
     * 0..3, k = 0..n-1 and kn = 1..n (only k < kn used). See patch_error.c. */
    uint16_t* add_tab;
    double err_unit; /* table unit, in steps: 1/16 .. 1 */
};

/* The terrain's allocator (status.c). tp__alloc and tp__calloc return NULL on failure, also
 * when count * size overflows; tp__calloc zeroes. tp__free accepts NULL. */
void* tp__alloc(const tp_allocator* a, size_t count, size_t size);
void* tp__calloc(const tp_allocator* a, size_t count, size_t size);
void tp__free(const tp_allocator* a, void* p);

/* The core's name for tp_error_set. */
#define tp__fail tp_error_set

/* The patch that stores sample x (columns) or y (rows): the last patch owns the far border. */
static inline int tp__owner(int coord, int n, int patches)
{
    int p = coord >> n;
    return p < patches ? p : patches - 1;
}

/* Global quantised height of sample (x, y), or INT32_MIN if it is not drawn / outside. */
static inline int32_t tp__q(const tp_terrain* t, int x, int y)
{
    if (x < 0 || y < 0 || x >= t->sw || y >= t->sh)
        return INT32_MIN;
    uint16_t s = t->q[(size_t)y * (size_t)t->sw + (size_t)x];
    if (s == TP__NO_HEIGHT)
        return INT32_MIN;
    int p = tp__owner(y, t->n, t->info.patch_rows) * t->info.patch_cols +
            tp__owner(x, t->n, t->info.patch_cols);
    return (int32_t)s + t->patches[p].offset;
}

/* ---- the split-cell surface (terrain.c's tp_terrain_height_at, surface.c's tp_grid_height_at) ----
 *
 * Every cell (c, r)-(c+1, r+1) is split along the diagonal from (c+1, r) to (c, r+1), as the
 * strips draw it. height(grid, x, y) gives a sample's height, NaN where none (outside, nodata).
 * Inline, so that each caller gets its own copy with the sampler inlined. */
typedef double (*tp__height_fn)(const void* grid, int x, int y);

/* One triangle of cell (cx, cy) at offsets fx, fy in [0, 1]; NaN if a vertex has no height. */
static inline double tp__half_cell(tp__height_fn height, const void* grid, int cx, int cy,
                                   double fx, double fy, int upper)
{
    if (cx < 0 || cy < 0)
        return NAN;
    double a, b, c;
    if (!upper) {
        a = height(grid, cx, cy), b = height(grid, cx + 1, cy), c = height(grid, cx, cy + 1);
        if (isnan(a) || isnan(b) || isnan(c))
            return NAN;
        return a + fx * (b - a) + fy * (c - a);
    }
    a = height(grid, cx + 1, cy + 1), b = height(grid, cx, cy + 1), c = height(grid, cx + 1, cy);
    if (isnan(a) || isnan(b) || isnan(c))
        return NAN;
    return a + (1 - fx) * (b - a) + (1 - fy) * (c - a);
}

/* Either triangle of the cell that contains the point (both on the diagonal). */
static inline double tp__cell_height(tp__height_fn height, const void* grid, int cx, int cy,
                                     double fx, double fy)
{
    double z = fx + fy <= 1 ? tp__half_cell(height, grid, cx, cy, fx, fy, 0) : NAN;
    return isnan(z) && fx + fy >= 1 ? tp__half_cell(height, grid, cx, cy, fx, fy, 1) : z;
}

/* Height of the surface of a w x h grid at (x, y); NaN outside the grid or where no triangle
 * with three heights contains the point (a point on an edge or a vertex lies on every triangle
 * that touches it, so one drawn triangle there is enough). */
static inline double tp__split_height(tp__height_fn height, const void* grid, int w, int h,
                                      double x, double y)
{
    if (!(x >= 0 && y >= 0 && x <= w - 1 && y <= h - 1))
        return NAN; /* also NaN inputs */
    int cx = (int)x, cy = (int)y;
    cx = cx > w - 2 ? w - 2 : cx;
    cy = cy > h - 2 ? h - 2 : cy;
    double fx = x - cx, fy = y - cy;
    double z = tp__cell_height(height, grid, cx, cy, fx, fy);
    if (isnan(z) && fx == 0)
        z = tp__cell_height(height, grid, cx - 1, cy, 1, fy);
    if (isnan(z) && fy == 0)
        z = tp__cell_height(height, grid, cx, cy - 1, fx, 1);
    if (isnan(z) && fx == 0 && fy == 0)
        z = tp__cell_height(height, grid, cx - 1, cy - 1, 1, 1);
    return z;
}

static inline const uint16_t* tp__delta_tab(const tp_terrain* t, int patch)
{
    return t->err_tab + (size_t)patch * (size_t)t->err_stride;
}
static inline const uint16_t* tp__eps_tab(const tp_terrain* t, int patch, int side)
{
    return t->err_tab + (size_t)patch * (size_t)t->err_stride + (size_t)(t->n + 1) +
           (size_t)side * (size_t)t->n;
}

/* eta[side][k][kn - 1] (k < kn; t->add_tab must be there): see patch_error.c. */
static inline const uint16_t* tp__eta_tab(const tp_terrain* t, int patch, int side, int k)
{
    const size_t n = (size_t)t->n;
    return t->add_tab + (size_t)patch * 4 * n * n + ((size_t)side * n + (size_t)k) * n;
}

/* tp_patch_error_bound_add less the quantisation error (metres; patch_error.c). */
double tp__patch_add_bound_m(const tp_terrain* t, int patch, int k, const int neighbor_levels[4]);

/* Computes the delta and eps tables of every patch (patch_error.c). */
tp_status tp__patch_errors_compute(tp_terrain* t, tp_error* err);

/* Crack removal on the level-k vertex lattice (0..2^k per side) of a patch or tree node:
 * writes where vertex (i, j) goes against the given neighbour levels (NULL: nowhere), in
 * level-k vertex units. Returns 1 if it was moved (patch_stitch.c). */
int tp__lattice_vertex(int k, const int nb[4], int i, int j, int* mi, int* mj);

/* Position (global grid coordinates) of vertex (i, j) of patch p at level k after crack
 * removal against the given neighbour levels (patch_stitch.c). Returns 1 if it was moved. */
int tp__vertex_position(const tp_terrain* t, int patch, int k, const int nb[4], int i, int j,
                        int32_t* gx, int32_t* gy);

/* The same for node `node` of a tree geometry (vertex stride 2^(n-k+s) grid samples), for the
 * tree's selection and its tests (patch_stitch.c). */
int tp__node_vertex_position(const tp_tree_geometry* g, int64_t node, int k, const int nb[4],
                             int i, int j, int32_t* gx, int32_t* gy);

/* ---- error tables over one lattice of (2^n+1)^2 samples (node_meta.c) ----
 *
 * The lattice is a patch's samples, or a tree node's (every 2^s-th sample); q holds their
 * global quantised heights row-major, INT32_MIN where a sample is not drawn. Errors are in
 * steps. Both tp_terrain's patch tables (patch_error.c) and tree nodes' metas use these. */

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

/* tp_patch_triangles with another rule: keep(a, b, c, user) says whether the strip's
 * triangle (a, b, c) is drawn (NULL: when its three vertices are). Zero-area triangles are
 * skipped either way (patch_stitch.c). */
typedef int (*tp__tri_keep)(const tp_vertex* a, const tp_vertex* b, const tp_vertex* c,
                            void* user);
size_t tp__strip_triangles(const tp_vertex* vertices, int k, tp__tri_keep keep, void* user,
                           uint32_t* triangles, size_t triangle_capacity);

/* Largest |S_k - q| over the lattice samples under the drawn triangles of the unstitched
 * level-k triangulation (delta_k of the lattice). mask NULL: a triangle is drawn when its
 * vertices are (a patch); else by the cell mask's rule (tp_node_mask_from_q: a node). */
double tp__lattice_level_error(int n, const int32_t* q, const uint16_t* mask, int k);

/* eps[side][kn], kn = 0..n-1: the largest error of any triangle with a vertex moved by a
 * neighbour at level kn on that side, over every level k > kn. cells = 0: measured at the lattice
 * samples the triangle covers (exact against the lattice samples: a patch, a leaf); cells = 1:
 * at every corner of every lattice cell the triangle touches, with the triangle's plane extended
 * there (a bound against the lattice's full-resolution surface S_n, see node_meta.c). */
/* mask: as tp__lattice_level_error (with a mask, a leaf's level-n triangles still follow
 * their vertices: cells = 0 and k = n). */
void tp__lattice_eps(int n, const int32_t* q, const uint16_t* mask, int cells,
                     double eps[4][TP_MAX_N]);

/* An error of `steps` in table units of unit_steps, rounded up; TP__ERR_SAT when it does not
 * fit. */
static inline uint16_t tp__err_units(double steps, double unit_steps)
{
    double u = ceil(steps / unit_steps - 1e-9);
    return u >= TP__ERR_SAT ? (uint16_t)TP__ERR_SAT : (uint16_t)(u < 0 ? 0 : u);
}

/* The tree at run time (tree.c). Core code (the cut) reads desc for the step, quantisation
 * error, err_unit and metas. */
struct tp_tree {
    tp_tree_desc desc;          /* metas borrowed (or owned, below) */
    tp_allocator alloc;         /* always set */
    const uint16_t** samples;   /* node_count pointers, NULL when not resident */
    tp_node_meta* owned_metas;  /* tp_tree_create_from_grid: metas and samples owned */
    uint16_t* owned_samples;
};

/* The tree takes ownership of metas and samples (tree.c; for tp_tree_create_from_grid). */
void tp__tree_own(tp_tree* t, tp_node_meta* metas, uint16_t* samples);

/* The automatic quantisation step (terrain.c): 1 m for integral heights, else the finest power
 * of two 2^-p m (p <= 10), coarser where a range would not fit 65534 steps; 0 if none fits. */
typedef struct tp__range {
    double lo, hi; /* lo > hi when empty */
} tp__range;
int tp__step_fits(const tp__range* r, int count, double step);
double tp__choose_step(const tp__range* r, int count, int integral);

/* Bilinear resample of a float grid (NaN = nodata) to a new size (fit.c). */
tp_status tp__fit_resample(const tp_allocator* a, const float* src, const uint8_t* src_filled,
                           int w, int h, int nw, int nh, float** out, uint8_t** out_filled,
                           tp_error* err);

/* Rasterises triangle (a, b, c) in grid coordinates over the integer sample lattice: calls
 * fn(x, y, z_interp, user) for each sample inside or on the triangle, z interpolated linearly
 * from za, zb, zc (any units). Degenerate triangles are skipped. (triangle_raster.c) */
typedef void (*tp__sample_fn)(int x, int y, double z, void* user);
void tp__raster_triangle(const int32_t a[2], const int32_t b[2], const int32_t c[2], double za,
                         double zb, double zc, tp__sample_fn fn, void* user);

/* Camera frame: orthonormal basis and the pixel focal length (camera.c). */
typedef struct tp__view {
    double pos[3], fwd[3], right[3], up[3];
    double f_px;          /* pixels per unit of tan(angle) */
    double tan_x, tan_y;  /* half-extents of the view at depth 1 */
    double w_px, h_px, near_m, far_m;
} tp__view;
void tp__view_from_camera(const tp_camera* cam, tp__view* v);

/* Screen error (px) between a sample's true position and the drawn surface's point vertically
 * above or below it (world, drawn space), as the screen-error measures define it: NaN when the
 * true position is outside the view (behind the near plane, past the far plane, outside the
 * frustum's sides), INFINITY when only the drawn point is behind the eye (camera.c). */
double tp__screen_error_px(const tp__view* v, const double truth[3], const double drawn[3]);

/* Persistent Grid Mapping (pgm.c): where grid vertex (i, j) of frame f meets the base plane,
 * ground[0..1] (E, N) and ground[2..3] (level-0 grid x, y), the level l and parent weight W_p
 * tp_pgm_map_vertex reads its height with (the height itself is left to the caller). */
void tp__pgm_map_ground(const tp_pgm_frame* f, const tp_pgm_pyramid* p, int i, int j,
                        double ground[4], int* level, double* wp);

/* ---- selections (selection.c, selection_measure.c, selection_query.c) ---- */

/* The error-mode bound of one patch for the current view (see lod.c): a vertical error of d
 * metres anywhere in the patch's AABB projects to at most d * num / (zmin - d * |vz|) pixels. */
typedef struct tp__proj_bound {
    double num;  /* f * sqrt(Amax^2 + Bmax^2) / zmin; INFINITY when the box reaches the near plane */
    double zmin; /* smallest depth of the box's corners */
} tp__proj_bound;

/* The bound for the box bmin..bmax (drawn space) seen from v, and the pixels a vertical error
 * of d metres (drawn space) inside that box projects to at most: 0 for d = 0, INFINITY when
 * the box reaches the near plane (lod.c). */
tp__proj_bound tp__proj_bound_box(const tp__view* v, const double bmin[3], const double bmax[3]);
double tp__projected_px(const tp__proj_bound* pb, double vz, double d);
/* The bound over what is drawn of a box: points in front of the near plane and inside the view's
 * sides whose counterpart (moved by d) is in front of the near plane too (what is clipped is
 * not on screen). Never above tp__projected_px, and finite for every finite d where that is
 * INFINITY: at most f d sqrt((1 + tan_x)^2 + (1 + tan_y)^2) / near. *near says whether the near
 * plane bounds it: d > 0 and zmin - d |vz| < near (the box reaches the near plane, or d could
 * carry a point of it there). For reports: the selection keeps tp__projected_px and refines such
 * a box as far as it can. */
double tp__projected_px_drawn(const tp__view* v, const tp__proj_bound* pb, double d, int* near);

/* Written only by the functions that take a non-const tp_selection*; the const ones (selection_measure.c,
 * selection_query.c) only read it, so that several threads may measure one selection at once. */
struct tp_selection {
    const tp_terrain* t;
    int count;
    uint8_t* level;
    uint8_t* next;     /* scratch of tp_selection_update: levels being selected */
    uint8_t* visible;
    uint8_t* dirty;
    tp__proj_bound* proj; /* error mode: each visible patch's projection bound */
    uint32_t* tris;    /* cached drawn-triangle count per patch, TP__STALE_TRIS when unknown */
    tp_vertex* vbuf;   /* scratch of tp_selection_stats: one patch at level n */
    double zscale;     /* vertical exaggeration of the drawn surface (1: none) */
    int stitch_add;    /* cracks removed by adding vertices (tp_selection_set_stitch_add) */
};

/* Patch p's AABB as drawn: heights times the selection's vertical scale (selection.c). */
void tp__drawn_box(const tp_selection* s, int p, tp_patch_info* pi);
#define TP__STALE_TRIS UINT32_MAX

/* The patch next to patch p on side `side`, or -1 at the terrain border (selection.c). */
int tp__neighbor(const tp_terrain* t, int p, int side);

/* Largest vertical distance (m) between patch p's drawn triangles at level k with neighbour
 * levels nb, interpolated from their vertices' z_m, and the heights of the samples they cover:
 * ref (src_width x src_height, NaN = none; padded fits only) or, when ref is NULL, the decoded
 * grid. vbuf and tbuf hold a patch at level n and its triangles (selection_measure.c). */
double tp__patch_vertical_error(const tp_terrain* t, int p, int k, const int nb[4],
                                const float* ref, tp_vertex* vbuf, uint32_t* tbuf);

/* ---- the cut: selection over a tree (cut_select.c, cut_stitch.c) ----
 *
 * Every node the update visits gets a record, found again through a hash of node ids (open
 * addressing; a slot counts only in the generation of the current update, so nothing is
 * cleared per frame). A visited node is INTERIOR (refined: its 4 children have records too) or
 * a terminal: DRAWN (visible), CULLED (its box is outside the frustum) or EMPTY (nothing drawn
 * in its area). Every point of the map lies in exactly one terminal of a visited root. */
enum { TP__CUT_INTERIOR = 1, TP__CUT_DRAWN, TP__CUT_CULLED, TP__CUT_EMPTY, TP__CUT_REMOVED };

typedef struct tp__cut_rec {
    int64_t node;
    int32_t c, r;
    int8_t s, level, state;
    uint8_t substituted; /* drawn in place of children that are not resident */
    uint8_t frozen;      /* collapsed onto by the stitching pass: never split again */
    uint8_t queued;      /* in the stitching pass's work list */
    float bound_px;
    int32_t out;         /* index in the output (tp_cut_nodes) when drawn */
    int32_t tris;        /* drawn: its triangles (finish); else -1 */
    uint8_t view;        /* 0: not tested yet; else 1 + whether its area box is in view */
    uint8_t pb_known;    /* pb is computed (error mode) */
    tp__proj_bound pb;   /* error mode, visible nodes: of the node's area box */
    int32_t sph;         /* sphere tree: the node's entry (cut_spheres.c), or -1 */
} tp__cut_rec;

typedef struct tp__cut_slot {
    int64_t key;  /* node id */
    int32_t val;  /* record index; -2: requested, not visited */
    uint32_t gen; /* the update that wrote it; other generations are empty slots */
} tp__cut_slot;

typedef struct tp__cut_tris {
    int64_t node;  /* -1: empty */
    int32_t nb;    /* the neighbour levels it was counted with, packed */
    int32_t tris;
} tp__cut_tris;
enum { TP__CUT_TRIS_CACHE = 4096 };

typedef struct tp__cut_req {
    int64_t node;
    double prio;
} tp__cut_req;

struct tp_cut {
    const tp_tree* t;
    tp_allocator alloc;
    tp_tree_geometry g;
    int n;
    double gt[6], step, quant, err_unit, zscale;
    int64_t* roots;
    tp__cut_rec* rec;
    size_t rec_count, rec_cap;
    tp__cut_slot* hash;
    size_t hcap, hused;
    uint32_t gen;
    tp_cut_node* out;
    size_t out_count, out_cap;
    tp__cut_req* req;
    int64_t* req_ids;
    size_t req_count, req_cap, req_ids_cap;
    /* the last update */
    tp_lod_params lp;
    int have_view; /* 0 for a cut installed by tp_cut_set_nodes */
    tp__view v;
    tp_frustum f;
    /* What was learnt about the children of record kid_rec while classifying it (in view:
     * -1 unknown, 0, 1; error mode: their area boxes' projection bounds), handed to their
     * records when it is refined: each is computed once per update. */
    int kid_rec;
    int8_t kid_in[4];
    uint8_t kid_pb_known[4];
    tp__proj_bound kid_pb[4];
    double kid_dist[4];  /* eye to each child's area box (incomplete children only) */
    double cell_m;       /* the larger grid spacing (m): hole widths */
    int32_t* tri_memo;   /* triangles of a complete node by level and neighbour levels (-1:
                            not counted yet; cut_stitch.c), tri_memo_count entries */
    size_t tri_memo_count;
    tp__cut_tris* tri_cache; /* triangles of incomplete drawn nodes, direct-mapped by node,
                                kept across updates (a node's samples never change) */
    int32_t* work;       /* the stitching pass's work list */
    size_t work_count, work_cap;
    int visited, unresolved;
    int oom;
    int requests_only; /* tp_cut_update_requests: no stitching, no output */
    int stitch_add;    /* tp_cut_set_stitch_add */
    int decisions;     /* distance decisions computed by the update (tp_cut_stats) */
    int sph_on;        /* this update reads distance decisions from the sphere tree */
    struct tp__spheres* sph; /* cut_spheres.c; NULL until the first sphere-tree update */
};

/* ---- the sphere tree (cut_spheres.c; cut_select.c's distance mode with sphere_tree) ---- */
/* The distance mode's decision for a node of scale s (whole: complete or nothing drawn) at
 * distance d (m) from the eye to its area box: -1 refine, else the level it is drawn at
 * (cut_select.c; every distance-mode decision of the cut is this function). */
int tp__cut_distance_decision(const tp_cut* c, int s, int whole, double d);
/* A node's box in drawn space (cut_select.c's node_box). */
void tp__cut_node_box(const tp_cut* c, int s, int cc, int rr, int32_t qlo, int32_t qhi,
                      double bmin[3], double bmax[3]);
/* Brings the sphere tree up to date for the view c->v and parameters c->lp (rebuilt when the
 * parameters, the focal length or the vertical scale changed). Entry ri is root c->roots[ri].
 * 0 without memory (c->oom may be set; the tree is rebuilt at the next call). */
int tp__spheres_update(tp_cut* c);
/* Entry i's child q when i is refined, else -1 (also for i = -1). */
int32_t tp__spheres_kid(const tp_cut* c, int32_t i, int q);
/* Entry i's decision (tp__cut_distance_decision at the current eye). */
int tp__spheres_decision(const tp_cut* c, int32_t i);
/* The last update's entries visited and decisions recomputed, and the entries held. */
void tp__spheres_stats(const tp_cut* c, int* visited, int* decided, int* live);
void tp__spheres_destroy(tp_cut* c);

/* Index in the drawn output of the node covering leaf (lc, lr), or -1 (cut_stitch.c). */
int tp__cut_drawn_at_leaf(const tp_cut* c, int lc, int lr);

/* Which triangles drawn node i (output index) draws (tp_node_mask_from_q's rule). */
typedef struct tp__node_draw {
    const uint16_t* mask; /* NULL: a triangle is drawn when its vertices are (a complete node,
                             a leaf at level n) */
    int n, s;
    int64_t x0, y0;       /* grid position of the node's sample (0, 0) */
} tp__node_draw;
void tp__cut_node_draw(const tp_cut* c, size_t i, tp__node_draw* d);
/* Whether the triangle with (stitched) grid positions pos is drawn; vertices_drawn: whether
 * its vertices, original and moved, are. */
int tp__tri_drawn(const tp__node_draw* d, const int32_t pos[3][2], int vertices_drawn);
/* Grows the array *p of *cap elements of size bytes to at least need (doubling); 0, c->oom
 * set, without memory. */
int tp__cut_grow(tp_cut* c, void** p, size_t* cap, size_t need, size_t size);
/* Record of node, or -1 when it was not visited this update (cut_select.c). */
int tp__cut_find(const tp_cut* c, int64_t node);
/* Adds a record for node (state 0) and returns its index, or -1 (c->oom set) without memory. */
int tp__cut_add(tp_cut* c, int64_t node);
/* Decides record i as a terminal without refining it: EMPTY, CULLED, or DRAWN at the level the
 * mode asks (n if it is incomplete or wants refining). */
void tp__cut_settle(tp_cut* c, int i);
/* Box of record i's area (area = 1) or own samples, drawn space; 0 if it has none. */
int tp__cut_box(const tp_cut* c, int i, int area, double bmin[3], double bmax[3]);
/* Lists node as a request (once per update) with priority prio. */
void tp__cut_request(tp_cut* c, int64_t node, double prio);
/* Whether every child of record i that has something to draw in view is resident (requesting
 * those that are not). */
int tp__cut_children_ready(tp_cut* c, int i);
/* The stitching pass: splits, collapses and raised levels until every pair of drawn
 * neighbours can be stitched (cut_stitch.c). */
void tp__cut_constrain(tp_cut* c);
/* The drawn neighbour on a side of drawn record i, of equal or larger scale; -1 if none
 * (border, culled, or smaller nodes there) (cut_stitch.c). */
int tp__cut_neighbor(const tp_cut* c, int i, int side);
/* Non-degenerate triangles of drawn record i with neighbour levels nb: complete nodes from
 * tp__cut_complete_triangles, incomplete ones counted on their samples once and cached. */
int32_t tp__cut_triangles(tp_cut* c, int i, const int nb[4]);
/* Non-degenerate triangles of a complete node drawn at level k with relative neighbour levels
 * nb (every vertex drawn: only stitching removes triangles), from c->tri_memo (filled on first
 * use) (cut_stitch.c). */
int32_t tp__cut_complete_triangles(tp_cut* c, int k, const int nb[4]);
/* Relative neighbour levels of drawn record i (nb: where its sides move to) and, --stitch add,
 * the finer same-size neighbours' levels whose vertices it takes (add; TP_NO_NEIGHBOR where
 * none); returns the number of its sides left with a crack (a neighbour more than n scales
 * larger that could be neither split nor collapsed against) (cut_stitch.c). */
int tp__cut_seams(const tp_cut* c, int i, int nb[4], int add[4]);
/* --stitch add (cut_stitch_add.c): the level record i must be raised to so that no corner
 * triangle both takes and moves vertices (its level when none); nb, add: tp__cut_seams'. */
int tp__cut_add_corner_level(const tp_cut* c, int i, const int nb[4], const int add[4]);
/* Rasterises drawn node i's --stitch add triangles (its add[] sides) as tp__raster_triangle,
 * z in height steps; 0 when out of memory (cut_stitch_add.c). */
int tp__cut_raster_add(const tp_cut* c, size_t i, tp__sample_fn fn, void* user);
/* tp_cut_add_bound_m for record i at level k (m, quantisation not included). */
double tp__cut_add_bound_m(const tp_cut* c, int i, int k, const int add[4]);

/* ---- error-bounded TIN (tin.c) ---- */

/* Marks TIN_FORCE (1) in cls (width * height, zeroed by the caller) at every corner of a valid
 * cell that touches an invalid one (TP_TIN_CUT_VOIDS); returns whether it marked any. */
int tp__tin_void_classes(const float* h, int w, int hg, uint8_t* cls);

/* The bound errors are compared with, as floats (each error rounded up to a float): the largest
 * float not above e, so that "err <= bound" means err <= e. An error of exactly e is allowed
 * (common on integer heights at e = 1: a margin below e cost 15% more triangles on Mt Hood);
 * another double formula may measure it 1e-12 m above e. */
float tp__tin_bound(double e);

/* tp_tin_build after its checks, on a grid of at least 2x2 with a valid sample: cls (NULL or
 * one byte per sample: 0 free, 1 forced, 2 skipped) says which samples are inserted first and
 * which are never measured; cut drops the triangles over invalid cells. */
tp_status tp__tin_build(const float* heights, int width, int height, double max_error_m,
                        const uint8_t* cls, int cut, tp_tin** out, tp_error* err);

/* ---- ray casting (selection_query.c for selections, cut_query.c for cuts) ---- */

/* Clips [*t0, *t1] to the t where o + t d lies in [lo, hi]; 0 if empty. */
static inline int tp__slab(double o, double d, double lo, double hi, double* t0, double* t1)
{
    if (d == 0)
        return o >= lo && o <= hi;
    double a = (lo - o) / d, b = (hi - o) / d;
    if (a > b) {
        double c = a;
        a = b;
        b = c;
    }
    *t0 = a > *t0 ? a : *t0;
    *t1 = b < *t1 ? b : *t1;
    return *t0 <= *t1;
}

/* Nearest t >= 0 where the ray (origin at 0, direction d) meets triangle (a, b, c), or -1
 * (Moller & Trumbore). Edges and vertices count, so a ray through a shared edge hits one of its
 * triangles. */
static inline double tp__ray_triangle(const double d[3], const double a[3], const double b[3],
                                      const double c[3])
{
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                   d[0] * e2[1] - d[1] * e2[0]};
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0)
        return -1;
    double s[3] = {-a[0], -a[1], -a[2]};
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                   s[0] * e1[1] - s[1] * e1[0]};
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    const double eps = 1e-12;
    if (u < -eps || v < -eps || u + v > 1 + eps)
        return -1;
    double t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    return t >= 0 ? t : -1;
}

/* shadow.c: tp_shadow_compute with one more optional output: horizon_tan (out_count floats),
 * for a shadowed sample the tangent of the elevation angle of the ground that shadows it seen
 * from the sample (the sun must rise above it to light the sample; 0 with the sun on or below
 * the horizon), NaN for lit samples and voids. lit, margin_m, horizon_tan may each be NULL
 * (not all three). */
tp_status tp__shadow_sweep(const float* heights, size_t height_count, int width, int height,
                           double dx_m, double dy_m, double azimuth_deg, double elevation_deg,
                           uint8_t* lit, float* margin_m, float* horizon_tan, size_t out_count,
                           tp_error* err);

/* light_day.c, shared with light_times.c: the argument checks of tp_light_day_build; one map's
 * codes (0 lit, < 0 the horizon's excess, TP_LIGHT_DAY_VOID) with scratch lit (n bytes) and
 * horizon (n floats); the weight between two maps (tan(e) ta, tb) at which a sample whose
 * horizon tangent is th changes (rising_needed: it turns lit, so the sun must rise; 0.5 when
 * the elevation does not explain the change). */
tp_status tp__light_day_check(size_t height_count, int width, int height,
                              const double* times_s, int count, tp_error* err);
tp_status tp__light_day_codes(const float* heights, int width, int height, double dx_m,
                              double dy_m, double azimuth_deg, double elevation_deg,
                              uint8_t* lit, float* horizon, int16_t* codes, tp_error* err);
double tp__light_day_crossing(double ta, double tb, double th, int rising_needed);

#endif
