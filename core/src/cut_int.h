/* cut_int.h - the cut's private state and the functions its files share (cut_*.c). */
#ifndef TP_CORE_CUT_INT_H
#define TP_CORE_CUT_INT_H

#include "lattice.h"
#include "lod_int.h"
#include "tp_cut.h"
#include "tree_int.h"

/* ---- the cut: selection over a tree (cut.c, cut_select.c, cut_stitch.c, cut_draw.c) ----
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
    uint8_t redo;        /* tp_cut_repair: to be selected again or culled (cut_repair.c) */
    uint8_t touched;     /* queued for the stitching pass at least once since it began */
    int8_t nb[4];        /* drawn: its seams' relative neighbour levels, as last output */
    uint8_t cracks;      /* ... and its sides left with a crack */
    float bound_px;
    double bound_m;    /* drawn, error mode: the bound bound_px projects (m, drawn space) */
    int32_t out;       /* index in the output (tp_cut_nodes) when drawn */
    int32_t tris;      /* drawn: its triangles (finish); else -1 */
    uint8_t view;      /* 0: not tested yet; else 1 + whether its area box is in view */
    uint8_t pb_known;  /* pb is computed (error mode) */
    tp__proj_bound pb; /* error mode, visible nodes: of the node's area box */
    int32_t sph;       /* sphere tree: the node's entry (cut_spheres.c), or -1 */
} tp__cut_rec;

typedef struct tp__cut_slot {
    int64_t key;  /* node id */
    int32_t val;  /* record index; -2: requested, not visited */
    uint32_t gen; /* the update that wrote it; other generations are empty slots */
} tp__cut_slot;

typedef struct tp__cut_tris {
    int64_t node; /* -1: empty */
    int32_t nb;   /* the neighbour levels it was counted with, packed */
    int32_t tris;
} tp__cut_tris;
enum { TP__CUT_TRIS_CACHE = 4096 };

/* --stitch add: a node's add table (cut_stitch_add.c): tab[(side * (n+1) + k) * (n+1) + a],
 * the largest offset (height steps) of the side's samples at level a from its level-k edge. */
typedef struct tp__cut_addtab {
    int64_t node; /* -1: empty; entries < 0 are not computed yet */
    float tab[4 * TP_MAX_LEVELS * TP_MAX_LEVELS];
} tp__cut_addtab;
enum { TP__CUT_ADD_CACHE = 2048 };

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
    double output_zscale; /* the vertical scale of the last output (tp_cut_repair refuses a
                             cut whose scale changed since: its records are for the other) */
    tp__view v;
    tp_frustum f;
    /* What was learnt about the children of record kid_rec while classifying it (in view:
     * -1 unknown, 0, 1; error mode: their area boxes' projection bounds), handed to their
     * records when it is refined: each is computed once per update. */
    int kid_rec;
    int8_t kid_in[4];
    uint8_t kid_pb_known[4];
    tp__proj_bound kid_pb[4];
    double kid_dist[4]; /* eye to each child's area box (incomplete children only) */
    double cell_m;      /* the larger grid spacing (m): hole widths */
    int32_t* tri_memo;  /* triangles of a complete node by level and neighbour levels (-1:
                           not counted yet; cut_draw.c), tri_memo_count entries */
    size_t tri_memo_count;
    tp__cut_tris* tri_cache; /* triangles of incomplete drawn nodes, direct-mapped by node,
                                kept across updates (a node's samples never change) */
    int32_t* work;           /* the stitching pass's work list */
    size_t work_count, work_cap;
    int visited, unresolved;
    int oom;
    int requests_only;       /* tp_cut_update_requests: no stitching, no output */
    int has_output;          /* the last update was stitched and output (not requests only) */
    int carrying;            /* tp_cut_repair's output: a drawn record never queued keeps the
                                seams (and triangles) it was output with */
    int stitch_add;          /* tp_cut_set_stitch_add */
    tp__cut_addtab* add_cache; /* add tables, direct-mapped by node, kept across updates (NULL
                                  until --stitch add is first set, or without memory) */
    const tp_tin_cache* tins;   /* tp_cut_set_tins; NULL: lattices only */
    const tp_node_tin** out_tin; /* per drawn node: the rung it draws, or NULL (cut_tin.c) */
    size_t out_tin_cap;
    tp_cut_tin_request* tin_req; /* levels found unbuilt, and their projected bounds */
    float* tin_prio;
    size_t tin_req_count, tin_req_cap, tin_prio_cap;
    int decisions;           /* distance decisions computed by the update (tp_cut_stats) */
    int sph_on;              /* this update reads distance decisions from the sphere tree */
    struct tp__spheres* sph; /* cut_spheres.c; NULL until the first sphere-tree update */
    struct tp__cut_reuse* reuse; /* tp_cut_prepare_reuse (cut_reuse.c): per record */
    size_t reuse_cap;
    uint32_t reuse_gen;      /* the update (gen) it was prepared for; 0: none */
    int32_t* fix;            /* tp__cut_select_below's queue */
    size_t fix_cap;
    tp__view reuse_v;        /* the camera the kept figures are from (the update's, or
                                tp_cut_keep_for's) */
};

/* ---- the sphere tree (cut_spheres.c; cut_select.c's distance mode with sphere_tree) ---- */
/* The distance mode's decision for a node of scale s (whole: complete or nothing drawn) at
 * distance d (m) from the eye to its area box: -1 refine, else the level it is drawn at
 * (cut_select.c; every distance-mode decision of the cut is this function). */
int tp__cut_distance_decision(const tp_cut* c, int s, int whole, double d);
/* Error mode (cut_select.c): whether a node of scale s drawn at level k, R metres from the eye
 * (to its area box), keeps the holes it may leave within hole_px for a focal length of f_px;
 * whole: complete, or nothing drawn (no holes). And whether a node is whole. */
int tp__cut_hole_ok(const tp_cut* c, double f_px, int s, int whole, double R, int k);
int tp__cut_whole(const tp_node_meta* m);
/* The distance from pos to the box bmin..bmax (0 inside it). */
double tp__cut_box_distance(const double pos[3], const double bmin[3], const double bmax[3]);
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

/* Index in the drawn output of the node covering leaf (lc, lr), or -1 (cut_draw.c). */
int tp__cut_drawn_at_leaf(const tp_cut* c, int lc, int lr);
/* The drawn node tp_cut_drawn_height_at takes grid (x, y) from (the one over the leaf holding
 * it, else, on a leaf's border, the first of the leaves left, above and above-left of it whose
 * node draws a triangle there): its output index, the height there (steps) and that leaf
 * (column, row; each may be NULL), or -1. */
int tp__cut_sample_node(const tp_cut* c, double x, double y, double* z_steps, int leaf[2]);

/* Which triangles drawn node i (output index) draws (tp_node_mask_from_q's rule). */
typedef struct tp__node_draw {
    const uint16_t* mask; /* NULL: a triangle is drawn when its vertices are (a complete node,
                             a leaf at level n) */
    int n, s;
    int64_t x0, y0; /* grid position of the node's sample (0, 0) */
} tp__node_draw;
void tp__cut_node_draw(const tp_cut* c, size_t i, tp__node_draw* d);
/* Whether the triangle with (stitched) grid positions pos is drawn; vertices_drawn: whether
 * its vertices, original and moved, are. */
int tp__tri_drawn(const tp__node_draw* d, const int32_t pos[3][2], int vertices_drawn);
/* Grows the array *p of *cap elements of size bytes to at least need (doubling); 0, c->oom
 * set, without memory (cut.c, as the records, the requests and the update's start and end). */
int tp__cut_grow(tp_cut* c, void** p, size_t* cap, size_t need, size_t size);
/* Slot of key in a hash of cap (a power of two) slots: MurmurHash3's finaliser (node ids are
 * dense). */
static inline size_t tp__cut_hash_slot(int64_t key, size_t cap)
{
    uint64_t h = (uint64_t)key;
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return (size_t)h & (cap - 1);
}

/* The value of key in this update's generation (a record index, or -2: requested), or -1. */
static inline int32_t tp__cut_hash_get(const tp_cut* c, int64_t key)
{
    if (!c->hcap)
        return -1;
    for (size_t i = tp__cut_hash_slot(key, c->hcap);; i = (i + 1) & (c->hcap - 1)) {
        const tp__cut_slot* sl = &c->hash[i];
        if (sl->gen != c->gen)
            return -1;
        if (sl->key == key)
            return sl->val;
    }
}

/* Record of node, or -1 when it was not visited this update (inline: the stitching pass
 * looks neighbours up several times per drawn node). */
static inline int tp__cut_find(const tp_cut* c, int64_t node)
{
    int32_t v = tp__cut_hash_get(c, node);
    return v >= 0 ? v : -1;
}
/* Adds a record for node (state 0) and returns its index, or -1 (c->oom set) without memory. */
int tp__cut_add(tp_cut* c, int64_t node);
/* tp__cut_add for node at scale s, column cc, row rr. */
int tp__cut_add_at(tp_cut* c, int64_t node, int s, int cc, int rr);
/* Decides record i as a terminal without refining it: EMPTY, CULLED, or DRAWN at the level the
 * mode asks (n if it is incomplete or wants refining). */
void tp__cut_settle(tp_cut* c, int i);
/* Box of record i's area (area = 1) or own samples, drawn space; 0 if it has none. */
int tp__cut_box(const tp_cut* c, int i, int area, double bmin[3], double bmax[3]);
/* Lists node as a request (once per update) with priority prio. */
void tp__cut_request(tp_cut* c, int64_t node, double prio);
/* The start of an update: a new generation of the hash (every slot empty), no records, requests
 * or output, the counters at 0. */
void tp__cut_begin(tp_cut* c);
/* The end of an update (tp_cut_update, tp_cut_set_nodes): the stitching pass, then the output
 * arrays (the drawn nodes with their seams, bounds and triangles; the requests, most urgent
 * first). TP_ERR_OUT_OF_MEMORY leaves the cut empty. */
tp_status tp__cut_finish(tp_cut* c, tp_error* err);
/* Record i of the last update from scratch (cut_reuse.c): whether it keeps the cut from view
 * v (frustum f): culled, still outside; drawn (error mode), its bound within tau, a box at the
 * near plane only with a zero bound, its holes within hole_px (substituted nodes and leaves
 * drawn at level n are not tested). *px: its bound when drawn; *pb_out (may be NULL): the
 * projection bound of its area box when it computed one (drawn, error mode), else NaNs. */
int tp__cut_holds_node(const tp_cut* c, size_t i, const tp__view* v, const tp_frustum* f,
                       double* px, tp__proj_bound* pb_out);
/* tp__cut_finish after its stitching pass: the output arrays only. */
tp_status tp__cut_output(tp_cut* c, tp_error* err);
/* Makes c a copy of from's last update (records, hash, requests, output, view; the caches
 * are c's own): 0 without memory (c->oom set). Both cuts are over the same tree. */
int tp__cut_copy(tp_cut* c, const tp_cut* from);
/* Selects below record i as tp_cut_update does below a root: i and what it refines into are
 * classified again (their records found or added), and each is queued for the stitching pass
 * (tp__cut_changed). For a cut carried to another camera (cut_repair.c). Returns the records
 * classified; 0 without memory. */
int tp__cut_select_below(tp_cut* c, int i);
/* Bound (m, drawn space, quantisation included) of record i at level k with neighbours nb
 * (cut_select.c). */
double tp__cut_bound_m(const tp_cut* c, int i, int k, const int nb[4]);
/* Whether every child of record i that has something to draw in view is resident (requesting
 * those that are not). */
int tp__cut_children_ready(tp_cut* c, int i);
/* The stitching pass: splits, collapses and raised levels until every pair of drawn
 * neighbours can be stitched (cut_stitch.c). */
void tp__cut_constrain(tp_cut* c);
/* The same pass over the records queued by tp__cut_changed only: the others are taken as
 * stitched already (a cut carried to another camera, cut_repair.c). */
void tp__cut_constrain_queued(tp_cut* c);
/* Queues record i, whose state or level changed, and its drawn neighbours of its size or
 * smaller for tp__cut_constrain_queued. */
void tp__cut_changed(tp_cut* c, int i);
/* The drawn neighbour on a side of drawn record i, of equal or larger scale; -1 if none
 * (border, culled, or smaller nodes there) (cut_stitch.c). */
int tp__cut_neighbor(const tp_cut* c, int i, int side);
/* Non-degenerate triangles of drawn record i with neighbour levels nb: complete nodes from
 * tp__cut_complete_triangles, incomplete ones counted on their samples once and cached. */
int32_t tp__cut_triangles(tp_cut* c, int i, const int nb[4]);
/* Non-degenerate triangles of a complete node drawn at level k with relative neighbour levels
 * nb (every vertex drawn: only stitching removes triangles), from c->tri_memo (filled on first
 * use) (cut_draw.c). */
int32_t tp__cut_complete_triangles(tp_cut* c, int k, const int nb[4]);
/* Relative neighbour levels of drawn record i (nb: where its sides move to) and, --stitch add,
 * the finer same-size neighbours' levels whose vertices it takes (add; TP_NO_NEIGHBOR where
 * none); returns the number of its sides left with a crack (a neighbour more than n scales
 * larger that could be neither split nor collapsed against) (cut_stitch.c). */
int tp__cut_seams(const tp_cut* c, int i, int nb[4], int add[4]);
/* --stitch add (cut_stitch_add.c): the level record i must be raised to so that no corner
 * triangle both takes and moves vertices (its level when none); nb, add: tp__cut_seams'. */
int tp__cut_add_corner_level(const tp_cut* c, int i, const int nb[4], const int add[4]);
/* A triangle drawn: grid positions and global heights in steps (as stored: not scaled). */
typedef void (*tp__cut_tri_fn)(const int32_t pos[3][2], const double q[3], void* user);
/* Calls fn for each of drawn node i's --stitch add triangles (its add[] sides; cells whose
 * vertices are not all drawn left out); 0 when out of memory (cut_stitch_add.c). */
int tp__cut_add_tris(const tp_cut* c, size_t i, tp__cut_tri_fn fn, void* user);
/* Calls fn for each triangle drawn node i draws: with add[] sides tp__cut_add_tris', else its
 * cells' triangles as vertex moving stitches them (tp__tri_drawn's rule, zero areas left out).
 * 0 when out of memory (cut_draw.c). */
int tp__cut_node_tris(const tp_cut* c, size_t i, tp__cut_tri_fn fn, void* user);
/* ---- drawn nodes that draw a TIN (cut_tin.c) ---- */
typedef struct tp__cut_tin_view {
    const tp_node_tin* rung;
    const uint16_t* q;      /* the node's samples */
    const uint16_t* filled; /* its filled bits, NULL when it has none */
    int32_t qmin;
    int s;
    int64_t x0, y0; /* grid position of sample (0, 0) */
    int nb[4];
} tp__cut_tin_view;
/* Drawn node i (c->out_tin[i] set) as its rung draws it. */
void tp__cut_tin_view_init(const tp_cut* c, size_t i, tp__cut_tin_view* tv);
/* For drawn record ri (its output entry written, its lattice bound in bound_px/bound_m): the
 * rung it draws (c->out_tin, tp_cut_node.tin, bounds updated) and its triangles, or -1 (its
 * lattice; a level found unbuilt is listed as a request). */
int32_t tp__cut_pick_tin(tp_cut* c, int ri, const int nb[4]);
void tp__cut_tin_sort_requests(tp_cut* c);
/* Its tp_cut_node.vertex_count vertices, as tp_cut_vertices. */
void tp__cut_tin_vertices(const tp_cut* c, const tp__cut_tin_view* tv, tp_vertex* out);
/* Its drawn triangles (the first cap written as index triples into its vertices); the count. */
size_t tp__cut_tin_triangles(const tp_cut* c, const tp__cut_tin_view* tv, uint32_t* tris,
                             size_t cap);
/* fn for each triangle drawn node i's rung draws (as tp__cut_node_tris). */
void tp__cut_tin_tris(const tp_cut* c, size_t i, tp__cut_tri_fn fn, void* user);
/* Height (steps) at grid (x, y) of drawn node i's rung: 1 when a triangle holds the point. */
int tp__cut_tin_height(const tp_cut* c, size_t i, double x, double y, double* z_steps);

/* tp_cut_add_bound_m for record i at level k (m, quantisation not included). */
double tp__cut_add_bound_m(const tp_cut* c, int i, int k, const int add[4]);

#endif
