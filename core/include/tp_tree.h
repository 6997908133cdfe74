/* tp_tree.h - the hierarchy: a tree of nodes over the patch grid by nested decimation, its node
 * metas and cell masks, the band builder and the tree at run time (tree.c, node_meta.c,
 * node_mask.c, tree_build.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_TREE_H
#define TP_TREE_H

#include "tp_base.h"
#include "tp_terrain.h" /* tp_vertex */

#ifdef __cplusplus
extern "C" {
#endif

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

/* ---- a node's error-bounded TINs, a ladder per level (tin_node.c; issue 32 item 2) ----
 *
 * A node drawn at level k may draw, instead of its level-k lattice, one of that level's TINs:
 * fewer triangles, with the same outline, within a bound the cut checks against what the view
 * allows the node (tp_cut_update picks nodes and levels on the lattice's bounds as before, then
 * the coarsest TIN of the level that fits). Only complete nodes have TINs.
 *
 * A level-k TIN's vertices are samples of the node (lattice positions (i, j), 0..2^n, of its
 * level-n samples); its outline is the level-k lattice's: every level-k vertex of the 4 sides and
 * no other sample of them, so crack removal moves its side vertices as it moves the lattice's
 * (tp_cut_node.nb: snapping onto the coarser neighbour's vertices) and shared edges stay
 * bit-identical with lattice and TIN neighbours alike. Inside: the greedy insertion of tp_tin
 * (tin.c) over the node's samples, stopped at a ladder of bounds ("rungs") between the level's
 * own part of delta[k] and of delta[k-1] (at most TP_NODE_TIN_RUNGS a level, a factor sqrt(2)
 * apart, coarsest first; the lattice's own bound last); a rung with as many
 * triangles as the lattice (2 * 4^k) is dropped. Levels 0 (2 triangles) have none.
 *
 * Each rung's bounds are against every full-resolution sample under its triangles, carry
 * included (tin_node_bound.c), in height steps: per triangle, |T - S_n| over T measured exactly
 * (S_n the node's level-n surface: the samples T covers, and for scale >= 1 every point where an
 * edge of T crosses a lattice edge) plus the carry |S_n - f| of the regions of the node it touches
 * (tp_node_carry_regions; the node's delta[n] everywhere without them):
 *   own_steps         every triangle, no vertex moved;
 *   eps_steps[s][kn]  every triangle with a vertex that a neighbour at relative level kn < k on
 *                     side s moves, under every combination of levels on the other sides its
 *                     vertices lie on; INFINITY when one of them turns over or flattens
 *                     onto three distinct points (two vertices snapped together is allowed:
 *                     not drawn, as the lattice's collapsed triangles).
 * Drawn with neighbour levels nb, a rung's bound is the largest of own_steps and eps_steps of
 * its moved sides (tp_node_tin_bound_steps). Triangles wind as the strips. */
#define TP_NODE_TIN_RUNGS 8
typedef struct tp_node_tin {
    int level;                  /* k, 1..n */
    uint32_t vertex_count;      /* <= (2^k+1)^2 */
    uint32_t triangle_count;    /* < 2 * 4^k */
    const uint16_t* ij;         /* vertex_count pairs: lattice position (i, j) of the level-n
                                   samples */
    const uint16_t* triangles;  /* triangle_count * 3 vertex indices */
    float own_steps;
    float eps_steps[4][TP_MAX_N];
} tp_node_tin;

typedef struct tp_node_tins tp_node_tins; /* every level of one node, one allocation */

/* A node's carry regions: the node's area cut into 2^d x 2^d regions, d = tp_node_carry_depth
 * (scale) (min(scale, TP_NODE_CARRY_DEPTH)), each the bound (err units, rounded up, as the metas)
 * of |S_n - f| there: the delta[n - d] of the descendant at depth d that covers it (its level
 * n - d lattice is the node's level-n surface over its area), or the node's delta[n] where that
 * is smaller. Row-major, 4^d values; reads only metas (every node's is kept). */
#define TP_NODE_CARRY_DEPTH 3
int tp_node_carry_depth(int scale);
/* (tp_node_carry_regions(tree, node, carry) is declared with the tree below.) */

/* Builds the TINs of the levels whose bit is set in `levels` (bit k for level k; ~0u: all) of a
 * node of `scale` from its block's samples (tp_tree_samples: (2^n+1)^2, TP_TREE_NO_HEIGHT where
 * not drawn), its meta, whose bounds are in err_unit_steps, and its carry regions (as
 * tp_node_carry_regions writes them; NULL: the meta's delta[n] everywhere, a looser bound). A
 * node with any sample not drawn gets none (*out = NULL, TP_OK): incomplete nodes keep their
 * lattices and cell masks. TP_ERR_OUT_OF_MEMORY. Reentrant (a thread may build them while the
 * frame draws). Cost: about 1 to 3 ms a level for n = 6 (docs/PERFORMANCE.md, "TIN nodes"). */
tp_status tp_node_tins_build(int n, int scale, const uint16_t* samples, const tp_node_meta* meta,
                             const uint16_t* carry, double err_unit_steps, unsigned levels,
                             tp_node_tins** out, tp_error* err);
/* Level k's rungs, coarsest (fewest triangles) first, *count of them (0: the lattice only;
 * tins NULL allowed). */
const tp_node_tin* tp_node_tins_level(const tp_node_tins* tins, int k, int* count);
/* A rung's bound (steps, carry included) drawn with neighbour levels nb (as tp_cut_node.nb). */
double tp_node_tin_bound_steps(const tp_node_tin* t, const int8_t nb[4]);
/* Bytes held (for the stream's accounting). */
size_t tp_node_tins_bytes(const tp_node_tins* tins);
void tp_node_tins_destroy(tp_node_tins* tins); /* accepts NULL */
/* Rungs kept over all levels, for benches. */
int tp_node_tins_rungs(const tp_node_tins* tins);

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

/* The node of scale >= 1 above 4 children, exactly as the band builder computes it (a build in
 * parts joins its parts' top nodes with this): its samples (every other sample of its
 * children's), its cell mask (tp_node_mask_from_children), its filled bits and its meta
 * (tp_node_meta_compute, TP_NODE_HAS_FILLED when one of its drawn samples is filled).
 * child_q[k]: the children's (2^n+1)^2 global quantised heights (INT32_MIN = not drawn),
 * child_mask[k] their masks, child_filled[k] their filled bits (NULL: none), children[k] their
 * metas, quadrants as tp_tree_node_child numbers them. Writes q ((2^n+1)^2), mask
 * (tp_node_mask_words(n)), filled (tp_node_filled_words(n), all 0 without the flag) and *out.
 * Cannot fail. */
void tp_tree_node_from_children(int n, int scale, const int32_t* const child_q[4],
                                const uint16_t* const child_mask[4],
                                const uint16_t* const child_filled[4],
                                const tp_node_meta* const children[4], double err_unit_steps,
                                int32_t* q, uint16_t* mask, uint16_t* filled, tp_node_meta* out);

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
/* A node's carry regions (see tp_node_carry_depth above): 4^tp_node_carry_depth(scale) values. */
void tp_node_carry_regions(const tp_tree* t, int64_t node, uint16_t* carry);

/* Residency: the caller owns node blocks (tp_tree_block_words(n) uint16: samples and cell
 * mask, see TP_TREE_NO_HEIGHT) and
 * attaches them while they are valid; the tree only reads them. Attach / detach from the
 * thread that selects and draws (a loader thread decodes into a block, the render thread
 * attaches it). */
void tp_tree_attach(tp_tree* t, int64_t node, const uint16_t* samples);
void tp_tree_detach(tp_tree* t, int64_t node);
const uint16_t* tp_tree_samples(const tp_tree* t, int64_t node); /* NULL when not resident */
/* How many times a node was detached since the tree was made. A cut selected while this read k
 * (it draws resident nodes only) still has every node it draws resident while it reads k. */
uint64_t tp_tree_detaches(const tp_tree* t);

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
/* tp_tree_node_normal at each of count vertices' (x, y) (their heights are not read), into
 * normals[k]: the same values, at a fraction of the cost for a node's vertices in order
 * (neighbouring vertices read the same leaf, found once). */
void tp_tree_node_normals(const tp_tree* t, int64_t node, const tp_vertex* vertices, size_t count,
                          float (*normals)[3]);

/* Query: decoded height of full-resolution sample (x, y) if a resident node holds it at that
 * position (the finest resident one), else NaN. */
double tp_tree_sample(const tp_tree* t, int x, int y);

/* ---- TINs built as the view needs them (tin_cache.c) ----
 *
 * A tree's node TINs, one level of one node at a time (tp_node_tins_build with one level bit):
 * what tp_cut_set_tins draws from. A cut lists the levels it would have drawn as TINs but found
 * unbuilt (tp_cut_tin_requests; it drew their lattices); the caller builds them, on any one
 * thread, while cuts read the cache on others: an entry is published once, whole, and never
 * changes until tp_tin_cache_prune frees it. Memory: a pointer per tree node, and the TINs. */
typedef struct tp_tin_cache tp_tin_cache;
tp_status tp_tin_cache_create(const tp_tree* t, tp_tin_cache** out, tp_error* err);
void tp_tin_cache_destroy(tp_tin_cache* c); /* accepts NULL */
/* Level k's TINs of node: *built says whether the level was built; NULL when it was not, or the
 * node has none there (incomplete, or no rung beats the lattice). Thread-safe against one
 * builder. */
const tp_node_tins* tp_tin_cache_get(const tp_tin_cache* c, int64_t node, int k, int* built);
/* Builds level k of node from its resident samples (nothing when not resident or already
 * built). One builder thread at a time. */
tp_status tp_tin_cache_build(tp_tin_cache* c, int64_t node, int k, tp_error* err);
/* Frees the TINs of nodes that are no longer resident and, max_age_frames > 0, of levels not
 * drawn in the last max_age_frames frames (tp_tin_cache_mark_drawn in tp_cut.h; a level just
 * built counts as drawn). Then, max_bytes > 0, while the cache holds more than max_bytes, the
 * levels drawn longest ago, but never one drawn or built in the last two marked frames (the
 * frame's cut, and what its next cut will draw: the cache may stay above max_bytes by that). Call when no build runs and no cut that may draw them
 * will be used (the viewer: after marking its frame's cut, its cut thread idle). */
void tp_tin_cache_prune(tp_tin_cache* c, unsigned max_age_frames, size_t max_bytes);
/* Bytes of TINs held, levels built, and TIN builds run so far. */
void tp_tin_cache_stats(const tp_tin_cache* c, size_t* bytes, size_t* levels, size_t* builds);
/* Milliseconds tp_tin_cache_build has spent building so far (wall clock, C11 timespec_get;
 * read it while no build runs). */
double tp_tin_cache_build_ms(const tp_tin_cache* c);

#ifdef __cplusplus
}
#endif
#endif /* TP_TREE_H */
