/* tp_cut.h - the cut: the selection over a tp_tree that is drawn, and the queries on the tree
 * and the cut (cut_select.c, cut_stitch.c, cut_stitch_add.c, cut_spheres.c, cut_query.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_CUT_H
#define TP_CUT_H

#include "tp_camera.h"
#include "tp_lod.h"
#include "tp_selection.h"
#include "tp_tree.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- selection over the tree: the drawn cut (cut_select.c, cut_stitch.c) ----
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
    int8_t tin;         /* tp_cut_set_tins: the rung of its level's TIN ladder it draws, or -1:
                           its lattice */
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
    int tin_nodes;      /* drawn nodes that draw a TIN (tp_cut_set_tins) */
    int tin_requests;   /* levels it would have drawn as TINs but found unbuilt */
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
 *     level n exceed hole_px (see hole_ok in cut_select.c); else it is drawn at the coarsest
 *     level k such that k and every finer level meet both.
 *   - Distance mode (Vanek & Jezek over strides): at distance d (eye to the area box) the leaf
 *     formula's level kl asks for vertex stride 2^(n-kl) grid samples; beyond maxdist the
 *     stride doubles with every doubling of d (2^(n + floor(log2(d / maxdist))))), so far
 *     terrain collapses into large nodes. A node of scale s (strides 2^s .. 2^(s+n)) is
 *     refined when that stride is below 2^s, else drawn at the level giving that stride
 *     (level 0 when the stride is coarser still). mindist = maxdist = 0: 1 and 24 LEAF widths.
 *   - Sphere tree (distance mode with params->sphere_tree; cut_spheres.c): the same
 *     decisions, kept from one update to the next with the distance interval over which each
 *     holds, over the whole map's distance cut; an update re-decides only the nodes whose
 *     interval the eye's distance left, skipping every subtree whose nearest threshold is
 *     farther than the eye moved. The cut is the same; the first update, and any update after
 *     a change of mindist, maxdist, exponent, hole_px, focal length or vertical scale, builds
 *     the distance cut of the whole map (tp_cut_stats.sphere_nodes entries).
 *   - Full mode: every visible leaf at level n.
 *   - Stitching (cut_stitch.c): levels only go up; where two drawn neighbours differ by more
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
 * tp_patch_vertices writes them (a node drawing a TIN: its tp_cut_vertex_count vertices, the
 * rung's, in its order, moved as the lattice's side vertices move) (global grid coordinates, decoded heights; cls is VALID,
 * FILLED, NODATA or PADDING). FILLED where the node's filled bits (TP_NODE_HAS_FILLED) mark
 * the sample the vertex stands on: a vertex that crack removal moves onto a coarser
 * neighbour's lattice vertex takes that sample's height and so its flag; drawn or not is the
 * original vertex's, as before. */
void tp_cut_vertices(const tp_cut* c, size_t i, tp_vertex* vertices, size_t vertex_capacity);
/* The triangles drawn node i draws, from its vertex data (tp_cut_vertices): as
 * tp_patch_triangles (strip order and winding, index triples, returns the count, writes the
 * first triangle_capacity), by the cell mask's rule for an incomplete node below a leaf's level
 * n (tp_node_mask_from_q); a TIN's, less those its crack removal collapses. What the viewer and
 * the export draw of an incomplete node or a TIN. */
size_t tp_cut_triangles(const tp_cut* c, size_t i, const tp_vertex* vertices,
                        uint32_t* triangles, size_t triangle_capacity);
/* Height (m) of the surface the cut draws at grid (x, y); NaN where nothing is drawn. */
double tp_cut_drawn_height_at(const tp_cut* c, double x, double y);
/* ---- the screen error of the drawn cut (cut_measure.c) ----
 *
 * Against the full-resolution samples of the drawn nodes' areas that are in view, as
 * tp_selection_measure_screen_error defines it: each sample's on-screen distance to the drawn
 * surface vertically above or below it (--stitch add: the triangles drawn, added vertices
 * included), each sample once (the samples tp_cut_drawn_height_at finds a height for, each
 * measured on the node that height comes from). Those samples are the leaves': a leaf resident in the cut's tree
 * is read there, any other through o->read_leaf (a store's reader: a viewer far from the ground
 * draws coarse nodes and holds none of the leaves under them). A leaf whose box is outside the
 * view, or that has no drawn sample, is not read.
 *
 * Sampling (o->max_leaves > 0): at most m x m leaves of each drawn node, m the largest power of
 * two for which the leaves so chosen over the whole cut number <= max_leaves (m = 1, one leaf a
 * node, when even that is more): a node 2^s leaves wide with 2^s > m has every (2^s / m)-th
 * leaf column and row measured, at an offset drawn from the node's id and o->seed; smaller
 * nodes are measured whole. Every drawn node is measured, the small near ones whole. */
typedef struct tp_cut_measure_options {
    /* Writes leaf's (2^n+1)^2 samples as tp_store_read_node decodes them (relative to the
     * leaf's qmin, TP_TREE_NO_HEIGHT where not drawn; the cell mask after them is not needed)
     * into samples; 1, or 0 when it cannot (the leaf's samples are then counted in skipped).
     * NULL: only resident leaves are measured. May be called from the measuring thread only. */
    int (*read_leaf)(void* user, int64_t leaf, uint16_t* samples);
    void* user;
    size_t max_leaves; /* 0: every leaf under the drawn nodes */
    uint32_t seed;     /* which leaves the sampling takes (vary it per frame to cover more) */
    /* May be NULL. Called once before the measure with every leaf it will then ask read_leaf
     * for (sampled, in view with a drawn sample, not resident), in that order: a reader over
     * HTTP fetches them all at once, concurrently (tp_store_prefetch), instead of a round trip
     * a leaf. read_leaf is still asked for each and decides. */
    void (*prefetch)(void* user, const int64_t* leaves, size_t count);
} tp_cut_measure_options;

typedef struct tp_cut_error {
    double max_px, rms_px; /* NaN when no sample was measured (never 0 for "nothing seen") */
    size_t samples;        /* samples in view measured */
    size_t skipped;        /* samples of leaves that could not be had (not resident, no or a
                              failed read_leaf) */
    size_t leaves;         /* leaves under the drawn nodes (their areas) */
    size_t leaves_sampled; /* of those, chosen by the sampling (= leaves without it) */
    size_t leaves_measured;/* of those, in view with a drawn sample, and measured */
    size_t leaves_read;    /* of those, read through read_leaf */
    size_t leaves_skipped; /* in view with a drawn sample, but not to be had */
    int per_node;          /* m: at most m x m leaves a node; 0 when every leaf is measured */
} tp_cut_error;

/* The screen error of the last update's cut seen from cam (normally the camera of the update).
 * o NULL: every resident leaf, none read. TP_OK and *out; TP_ERR_OUT_OF_MEMORY (*out: NaN
 * errors, zero counts). */
tp_status tp_cut_measure_error(const tp_cut* c, const tp_camera* cam,
                               const tp_cut_measure_options* o, tp_cut_error* out);

/* tp_cut_measure_error over the resident leaves only (o NULL), its figures: max and RMS 0 when
 * no sample was measured (test that *samples > 0). Any of the outputs may be NULL. */
tp_status tp_cut_measure_screen_error(const tp_cut* c, const tp_camera* cam, double* max_px,
                                      double* rms_px, size_t* samples, size_t* skipped);

/* Whether the cut of the last update may be drawn from camera cam instead of the camera it
 * was selected for (cut_reuse.c): a cut selected on another thread while the frame before was
 * drawn, for where the camera was predicted to be. It may when
 *   - every node the update culled (its area box, or its own box when only that was tested)
 *     is still outside cam's frustum: nothing in view is missing; one culled for having no
 *     own samples while its area was in view (data smaller than its sample stride among
 *     voids), error mode: outside, or its bound at its level within tau and its holes within
 *     hole_px from cam, as if drawn (else the selection would refine it); and
 *   - error mode: every drawn node's bound as drawn (tp_cut_node.bound_px's metres, projected
 *     from cam over what is drawn of its box) is within the update's tau, and not carried to
 *     the near plane (as the selection asks: only a zero bound there), and an incomplete
 *     node's holes stay within hole_px as the selection's test says; except nodes that could
 *     not be finer in this update either: substituted ones (their children are not resident)
 *     and leaves drawing their samples at level n (only quantisation is left; a leaf drawing a
 *     TIN rung is tested).
 * The distance and full modes have no error to keep: only the first test. O(drawn + culled
 * nodes); no allocation. *max_bound_px (may be NULL): the largest bound_px from cam, as
 * tp_cut_stats.max_bound_px (error mode; 0 otherwise). An installed cut (tp_cut_set_nodes)
 * culls nothing and keeps no error: 1. *scratch (may be NULL): the nodes projected or tested
 * against the frustum from scratch (all of them unless tp_cut_prepare_reuse ran and
 * max_bound_px is NULL). */
int tp_cut_holds_for(const tp_cut* c, const tp_camera* cam, double* max_bound_px,
                     size_t* scratch);

/* Keeps, per node of the last update, what tp_cut_holds_for needs from the update's own camera
 * (each box's distance outside the frustum, depth, projection numerator and farthest corner),
 * so that it answers for a camera near that one in a few operations a node instead of a
 * projection, testing from scratch only the nodes the bounds do not settle (cut_reuse.c says
 * how; the answer is the same). Called on the thread that selected the cut, after
 * tp_cut_update; the next update drops it. O(drawn + culled nodes). Returns 0 (nothing kept:
 * tp_cut_holds_for tests from scratch) without memory or for an installed cut. */
int tp_cut_prepare_reuse(tp_cut* c);
/* Whether the cut of the last update holds for cam (tp_cut_holds_for's answer, from scratch),
 * keeping tp_cut_prepare_reuse's figures from cam instead of the update's camera: the test of
 * a cut kept for another frame (app/scene/cut_worker.c), after which tp_cut_holds_for near
 * cam settles nodes from the figures again. One pass, O(drawn + culled nodes); without
 * memory nothing is kept (the answer is the same). */
int tp_cut_keep_for(tp_cut* c, const tp_camera* cam);
/* Carries from's last update to cam into c, selecting again only below the nodes where it no
 * longer holds for cam (cut_repair.c): a drawn node whose bound as stitched projects above tau
 * (or whose box reaches the near plane, or whose holes exceed hole_px), a culled node that
 * comes into view, a substituted node whose missing children have all arrived; a drawn node
 * now outside the frustum is culled. The stitching pass then checks only what changed and its
 * neighbours. The result holds for cam as an update's does (tau, hole_px, coverage,
 * watertight); where the camera moved away it may draw finer than an update would. Requests:
 * from's still missing, those the new selections make, and the missing roots in view. Returns
 * 1 when c holds the carried cut; 0 when it was not carried, c then to be updated
 * (tp_cut_update) before use: from is not an update in error mode (tp_cut_update_requests'
 * neither: it is not stitched), its vertical scale changed since its update, it draws TIN nodes or uses --stitch add
 * (nor may c), a node it draws is no longer resident, a root missing at its update has arrived,
 * the selections would classify more than a quarter as many records as from has (a jump: a
 * selection from the roots costs less), or without memory. c's parameters (tau, vertical
 * scale) are from's. O(records + roots) plus the selections. */
int tp_cut_repair(tp_cut* c, const tp_cut* from, const tp_camera* cam);

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
/* TIN nodes (issue 32 item 2; tp_tree.h, "a node's error-bounded TINs"): with a cache set, each
 * drawn complete node of error mode whose level was built draws, instead of its lattice, the
 * coarsest rung of that level's ladder whose bound (with its neighbour levels, the node's carry,
 * quantisation and vertical scale) projects within tau, or within what the lattice's bound
 * projects to where that is more (never worse than the lattice: a node drawn in place of
 * missing ones, a box at the near plane). Levels, neighbours and stitching are the lattice's,
 * so the outline and its crack removal are too. Levels found unbuilt draw their lattices and
 * are listed by tp_cut_tin_requests (nearest first: the cut's output order is not, so in
 * order of decreasing projected bound). NULL (the default) draws lattices only; --stitch add
 * (tp_cut_set_stitch_add) draws lattices only. A cut installed by tp_cut_set_nodes has no view:
 * its nodes draw their level's coarsest rung that stitches with their neighbours' levels. The
 * cache must outlive the cut's use of it. */
void tp_cut_set_tins(tp_cut* c, const tp_tin_cache* tins);
typedef struct tp_cut_tin_request {
    int64_t node;
    int level;
} tp_cut_tin_request;
const tp_cut_tin_request* tp_cut_tin_requests(const tp_cut* c, size_t* count);
/* Stamps the levels cut draws as drawn in a new frame, for tp_tin_cache_prune's age limit (on
 * the thread that prunes). */
void tp_tin_cache_mark_drawn(tp_tin_cache* c, const tp_cut* cut);
/* How many vertices tp_cut_vertices writes for drawn node i: (2^level+1)^2, or its TIN's. */
size_t tp_cut_vertex_count(const tp_cut* c, size_t i);

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

#ifdef __cplusplus
}
#endif
#endif /* TP_CUT_H */
