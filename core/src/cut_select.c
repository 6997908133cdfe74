/* cut_select.c - the cut: which tree nodes are drawn, at which level, for one view.
 *
 * From the roots down, each node visited is culled (area box outside the frustum), refined
 * (the mode asks for more detail than its level n gives, or its holes would be too wide, and
 * its children are resident) or drawn at the coarsest level the mode allows. The error mode
 * uses lod.c's projection bound on the node's area box, so tau holds anywhere on screen; the
 * distance mode generalises Vanek & Jezek's formula to vertex strides (see tp_cut in tp_cut.h).
 * Then cut_stitch.c makes neighbours stitchable, and cut.c writes the output. Cost: O(1) per
 * visited node (cut.c's hash of node ids instead of per-node arrays), and no allocation once the
 * arrays have grown to the view.
 */
#include "cut_int.h"

#include <string.h>

static const int no_nb[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};

/* Child q of record i: its id, column and row (scale rec[i].s - 1), without a search of the
 * node's scale as tp_tree_node_child does. */
static int64_t kid(const tp_cut* c, int i, int q, int* cc, int* rr)
{
    const tp__cut_rec* r = &c->rec[i];
    int s = r->s - 1;
    *cc = 2 * r->c + (q & 1), *rr = 2 * r->r + (q >> 1);
    return c->g.first_node[s] + (int64_t)*rr * c->g.node_cols[s] + *cc;
}

/* ---- boxes and the modes ---- */

static void node_box(const tp_cut* c, int s, int cc, int rr, int32_t qlo, int32_t qhi,
                     double bmin[3], double bmax[3])
{
    int64_t span = (int64_t)1 << (c->n + s);
    double x0 = (double)(cc * span), x1 = (double)((cc + 1) * span);
    double y0 = (double)(rr * span), y1 = (double)((rr + 1) * span);
    double e0 = c->gt[0] + (x0 + 0.5) * c->gt[1], e1 = c->gt[0] + (x1 + 0.5) * c->gt[1];
    double n0 = c->gt[3] + (y0 + 0.5) * c->gt[5], n1 = c->gt[3] + (y1 + 0.5) * c->gt[5];
    /* not fmin/fmax: finite values, and those are calls into libm here */
    bmin[0] = e0 < e1 ? e0 : e1, bmax[0] = e0 < e1 ? e1 : e0;
    bmin[1] = n0 < n1 ? n0 : n1, bmax[1] = n0 < n1 ? n1 : n0;
    bmin[2] = qlo * c->step * c->zscale, bmax[2] = qhi * c->step * c->zscale;
}

void tp__cut_node_box(const tp_cut* c, int s, int cc, int rr, int32_t qlo, int32_t qhi,
                      double bmin[3], double bmax[3])
{
    node_box(c, s, cc, rr, qlo, qhi, bmin, bmax);
}

int tp__cut_box(const tp_cut* c, int i, int area, double bmin[3], double bmax[3])
{
    const tp__cut_rec* r = &c->rec[i];
    const tp_node_meta* m = tp_tree_meta(c->t, r->node);
    int32_t lo = area ? m->area_qmin : m->qmin, hi = area ? m->area_qmax : m->qmax;
    if (lo > hi)
        return 0;
    node_box(c, r->s, r->c, r->r, lo, hi, bmin, bmax);
    return 1;
}

double tp__cut_box_distance(const double pos[3], const double bmin[3], const double bmax[3])
{
    double d2 = 0;
    for (int a = 0; a < 3; a++) {
        double d = pos[a] < bmin[a] ? bmin[a] - pos[a] : pos[a] > bmax[a] ? pos[a] - bmax[a] : 0;
        d2 += d * d;
    }
    return sqrt(d2);
}

double tp__cut_bound_m(const tp_cut* c, int i, int k, const int nb[4])
{
    const tp_node_meta* m = tp_tree_meta(c->t, c->rec[i].node);
    return (tp_node_error_bound(m, c->n, k, nb, c->step, c->err_unit) + c->quant) * c->zscale;
}

static double bound_px(const tp_cut* c, int i, int k, const int nb[4])
{
    return tp__projected_px(&c->rec[i].pb, c->v.fwd[2], tp__cut_bound_m(c, i, k, nb));
}

/* Error mode: the largest unstitched error (height steps, before quantisation) that projects
 * to tau or less through pb, by inverting tp__projected_px once: d num / (zmin - d |vz|) <= tau
 * iff d <= tau zmin / (num + tau |vz|). Negative when only a zero bound passes (the box
 * reaches the near plane, or the quantisation alone is too much). A level then passes when
 * level_passes says so: an integer comparison per level instead of a projection. */
static double max_steps(const tp_cut* c, const tp__proj_bound* pb)
{
    if (!(pb->num < INFINITY))
        return -1;
    double tau = c->lp.tau_px, d = tau * pb->zmin / (pb->num + tau * fabs(c->v.fwd[2]));
    return (d / c->zscale - c->quant) / c->step;
}

/* Whether node m's unstitched level-k bound (tp_node_error_bound's steps: its delta table
 * clamped to its area range) is within lim steps (max_steps), or is exactly zero. */
static int level_passes(const tp_cut* c, const tp_node_meta* m, int k, double lim)
{
    unsigned units = m->delta[k];
    double range = m->area_qmax >= m->area_qmin ? (double)m->area_qmax - m->area_qmin : 0;
    double steps = units >= TP_NODE_ERR_SAT ? range : units * c->err_unit;
    steps = steps < range ? steps : range;
    return steps <= lim || (steps == 0 && c->quant == 0);
}

/* Distance mode: log2 of the vertex stride (grid samples) the leaf formula asks for at
 * distance d; beyond maxdist one more for every doubling of the distance. */
static int wanted_stride_log(const tp_cut* c, double d)
{
    const tp_lod_params* p = &c->lp;
    if (!(d >= 0))
        return 0; /* NaN eye: full resolution */
    if (d <= p->maxdist_m || p->maxdist_m <= 0) {
        int k = c->n;
        tp_lod_level_distance(c->n, d, p->mindist_m, p->maxdist_m, p->exponent, &k, NULL);
        return c->n - k;
    }
    double e = floor(log2(d / p->maxdist_m));
    return c->n + (e > 60 ? 60 : (int)e);
}

static int64_t kid_in_view(tp_cut* c, int i, int q, int* in);

/* Error mode: whether a node of scale s at level k keeps the holes it may leave within
 * hole_px. Only incomplete nodes leave holes (not whole: !(COMPLETE) with something drawn), and
 * not a leaf at level n (its triangles follow its samples): one level-k cell, 2^(n-k+s)
 * samples wide, at most (tp_node_mask_from_q). A horizontal length w at distance >= R from the
 * eye spans at most about w / R radians, and at most twice that many focal lengths of pixels
 * anywhere in a view up to 90 degrees wide: 2 f w / R. R is the eye's distance to the node's
 * area box (0 inside it: any hole is too wide). */
int tp__cut_hole_ok(const tp_cut* c, double f_px, int s, int whole, double R, int k)
{
    if (whole || (s == 0 && k == c->n))
        return 1;
    if (!(R > 0))
        return 0;
    double w = (double)((int64_t)1 << (c->n - k + s)) * c->cell_m;
    return 2 * f_px * w / R <= c->lp.hole_px;
}

static int hole_ok(const tp_cut* c, int s, int whole, double R, int k)
{
    return tp__cut_hole_ok(c, c->v.f_px, s, whole, R, k);
}

int tp__cut_whole(const tp_node_meta* m)
{
    return (m->flags & TP_NODE_COMPLETE) || !(m->flags & TP_NODE_HAS_DRAWN);
}

static int whole(const tp_node_meta* m)
{
    return tp__cut_whole(m);
}

/* Error mode: drawing record i at level k puts its whole area at one vertex density, set by
 * its roughest part (and its bound adds its children's on top of its own). Its 4 children,
 * each at the coarsest level its own bound allows, culled ones not at all, may draw fewer
 * triangles: then refine. Only complete children whose level n already meets tau are counted
 * (others would refine further: no estimate), so the cut stays within tau either way.
 * Each node also costs NODE_COST_TRIANGLES triangles' worth: a node is visited, stitched,
 * streamed, drawn with its own call and held in a vertex slot whatever its level, so without
 * it the cut splits far terrain into thousands of nodes of 2-32 triangles.
 * Measured (N42E001, default view, tau 1, 17-sample nodes): 324k triangles in 1054 nodes
 * without this test, 103k in 5139 with it (the DEM path: 95k in 7254 patches). The node cost
 * (docs/PERFORMANCE.md, "Node cost"): 20481² real-relief store, high path, 0 -> 64: nodes drawn
 * 9,844 -> 1,777, cut 40 -> 6.6 ms, GPU vertex data 1,074 -> 138 MB, triangles 194k -> 315k,
 * fps +30%; on the 1201² tile (17-sample nodes) triangles +7%, nodes -14%. */
enum { NODE_COST_TRIANGLES = 64 };

static int children_cheaper(tp_cut* c, int i, int k)
{
    const tp__cut_rec* r = &c->rec[i];
    int n = c->n;
    double parent = 2.0 * (double)((int64_t)1 << (2 * k)) + NODE_COST_TRIANGLES, kids = 0;
    for (int q = 0; q < 4; q++) {
        int in;
        int64_t ch = kid_in_view(c, i, q, &in);
        if (!in)
            continue;
        const tp_node_meta* m = tp_tree_meta(c->t, ch);
        if (m->area_qmin > m->area_qmax)
            return 0;
        int w = whole(m);
        if (!c->kid_pb_known[q]) {
            double bmin[3], bmax[3];
            node_box(c, r->s - 1, 2 * r->c + (q & 1), 2 * r->r + (q >> 1), m->area_qmin,
                     m->area_qmax, bmin, bmax);
            c->kid_pb[q] = tp__proj_bound_box(&c->v, bmin, bmax);
            c->kid_dist[q] = w ? 0 : tp__cut_box_distance(c->v.pos, bmin, bmax);
            c->kid_pb_known[q] = 1;
        }
        const double lim = max_steps(c, &c->kid_pb[q]);
        int kc = n;
        for (; kc >= 0; kc--)
            if (!level_passes(c, m, kc, lim) || !hole_ok(c, r->s - 1, w, c->kid_dist[q], kc))
                break;
        if (kc == n)
            return 0; /* even level n is above tau: the child would refine */
        kids += 2.0 * (double)((int64_t)1 << (2 * (kc + 1))) + NODE_COST_TRIANGLES;
        if (kids >= parent)
            return 0;
    }
    return kids < parent;
}

int tp__cut_distance_decision(const tp_cut* c, int s, int whole, double d)
{
    int n = c->n, want = wanted_stride_log(c, d);
    if (want < s)
        return s > 0 ? -1 : n;
    int k = n + s - want;
    k = k < 0 ? 0 : k;
    double R = whole ? 0 : d;
    while (k < n && !hole_ok(c, s, whole, R, k))
        k++;
    return s > 0 && !hole_ok(c, s, whole, R, k) ? -1 : k;
}

/* What the mode asks of record i (visible, complete or not): 1 to refine; else *level. */
static int mode_wants(tp_cut* c, int i, int* level)
{
    tp__cut_rec* r = &c->rec[i];
    const tp_node_meta* m = tp_tree_meta(c->t, r->node);
    int n = c->n;
    *level = n;
    if (!c->have_view) /* an installed cut: nothing to ask */
        return 0;
    switch (c->lp.mode) {
    case TP_LOD_FULL: return r->s > 0;
    case TP_LOD_DISTANCE: {
        int k;
        if (c->sph_on && r->sph >= 0)
            k = tp__spheres_decision(c, r->sph);
        else {
            double bmin[3], bmax[3];
            tp__cut_box(c, i, 1, bmin, bmax);
            k = tp__cut_distance_decision(c, r->s, whole(m),
                                          tp__cut_box_distance(c->v.pos, bmin, bmax));
            c->decisions++;
        }
        if (k < 0)
            return 1; /* *level = n */
        *level = k;
        return 0;
    }
    default: {
        int w = whole(m);
        double R = 0;
        if (!w) {
            double bmin[3], bmax[3];
            tp__cut_box(c, i, 1, bmin, bmax);
            R = tp__cut_box_distance(c->v.pos, bmin, bmax);
        }
        const double lim = max_steps(c, &r->pb);
        if (!level_passes(c, m, n, lim) || !hole_ok(c, r->s, w, R, n))
            return r->s > 0;
        int k = n;
        while (k > 0 && level_passes(c, m, k - 1, lim) && hole_ok(c, r->s, w, R, k - 1))
            k--;
        *level = k;
        return r->s > 0 && k > 0 && children_cheaper(c, i, k);
    }
    }
}

/* Priority of a request for a child of record i: its projected error (error mode), else
 * nearness. */
static double request_prio(const tp_cut* c, int i, int64_t child)
{
    if (c->have_view && c->lp.mode == TP_LOD_ERROR)
        return bound_px(c, i, c->n, no_nb);
    int s, cc, rr;
    tp_tree_node_locate(&c->g, child, &s, &cc, &rr);
    const tp_node_meta* m = tp_tree_meta(c->t, child);
    double bmin[3], bmax[3];
    node_box(c, s, cc, rr, m->area_qmin, m->area_qmax, bmin, bmax);
    return c->have_view ? 1.0 / (1.0 + tp__cut_box_distance(c->v.pos, bmin, bmax)) : 0;
}

/* Whether node (scale s, column cc, row rr) has something to draw in view (its area box in
 * the frustum): 0 no, 1 partly, 2 wholly inside the frustum. */
static int in_view_at(const tp_cut* c, int64_t node, int s, int cc, int rr)
{
    const tp_node_meta* m = tp_tree_meta(c->t, node);
    if (!(m->flags & TP_NODE_HAS_DRAWN) || m->area_qmin > m->area_qmax)
        return 0;
    if (!c->have_view)
        return 1;
    double bmin[3], bmax[3];
    node_box(c, s, cc, rr, m->area_qmin, m->area_qmax, bmin, bmax);
    tp_cull v = tp_frustum_test_aabb(&c->f, bmin, bmax);
    return v == TP_CULL_OUTSIDE ? 0 : v == TP_CULL_INSIDE ? 2 : 1;
}

/* in_view_at for record i. */
static int rec_in_view(tp_cut* c, int i)
{
    tp__cut_rec* r = &c->rec[i];
    if (!r->view)
        r->view = (uint8_t)(1 + in_view_at(c, r->node, r->s, r->c, r->r));
    return r->view - 1;
}

/* Child q of record i, and whether it is in view (computed once per record and update). */
static int64_t kid_in_view(tp_cut* c, int i, int q, int* in)
{
    if (c->kid_rec != i) {
        c->kid_rec = i;
        memset(c->kid_in, -1, sizeof c->kid_in);
        memset(c->kid_pb_known, 0, sizeof c->kid_pb_known);
    }
    int cc, rr;
    int64_t ch = kid(c, i, q, &cc, &rr);
    if (c->kid_in[q] < 0)
        c->kid_in[q] = (int8_t)in_view_at(c, ch, c->rec[i].s - 1, cc, rr);
    *in = c->kid_in[q];
    return ch;
}

int tp__cut_children_ready(tp_cut* c, int i)
{
    if (c->rec[i].s == 0)
        return 0;
    int ready = 1;
    for (int q = 0; q < 4; q++) {
        int in;
        int64_t ch = kid_in_view(c, i, q, &in);
        if (in && !tp_tree_samples(c->t, ch)) {
            tp__cut_request(c, ch, request_prio(c, i, ch));
            ready = 0;
        }
    }
    return ready;
}

/* Classifies record i; returns 1 if it is to be refined (its children are ready). */
static int classify(tp_cut* c, int i, int may_refine)
{
    const tp_node_meta* m = tp_tree_meta(c->t, c->rec[i].node);
    if (!rec_in_view(c, i)) {
        c->rec[i].state = (m->flags & TP_NODE_HAS_DRAWN) ? TP__CUT_CULLED : TP__CUT_EMPTY;
        return 0;
    }
    if (c->have_view && c->lp.mode == TP_LOD_ERROR && !c->rec[i].pb_known) {
        double bmin[3], bmax[3];
        tp__cut_box(c, i, 1, bmin, bmax);
        c->rec[i].pb = tp__proj_bound_box(&c->v, bmin, bmax);
        c->rec[i].pb_known = 1;
    }
    int k, refine = mode_wants(c, i, &k);
    if (refine && may_refine) {
        if (tp__cut_children_ready(c, i)) {
            c->rec[i].state = TP__CUT_INTERIOR;
            return 1;
        }
        c->rec[i].substituted = 1;
    }
    if (refine)
        k = c->n;
    c->rec[i].level = (int8_t)k;
    /* Drawn only if its own samples' box is in view: surely so when that box lies in its area
     * box and the area box is wholly inside. */
    double bmin[3], bmax[3];
    int inside = rec_in_view(c, i) == 2 && m->qmin <= m->qmax && m->qmin >= m->area_qmin &&
                 m->qmax <= m->area_qmax;
    int vis = inside || (tp__cut_box(c, i, 0, bmin, bmax) &&
                         (!c->have_view ||
                          tp_frustum_test_aabb(&c->f, bmin, bmax) != TP_CULL_OUTSIDE));
    c->rec[i].state = vis ? TP__CUT_DRAWN : TP__CUT_CULLED;
    return 0;
}

void tp__cut_settle(tp_cut* c, int i)
{
    classify(c, i, 0);
}

/* What classifying record i (the last one classified) learnt about its child q goes with the
 * child's record j: each figure is computed once per update. */
static void hand_down(tp_cut* c, int i, int q, int j)
{
    if (c->kid_rec != i)
        return;
    if (c->kid_in[q] >= 0)
        c->rec[j].view = (uint8_t)(1 + c->kid_in[q]);
    if (c->kid_pb_known[q]) {
        c->rec[j].pb = c->kid_pb[q];
        c->rec[j].pb_known = 1;
    }
}

/* A record for node (scale s, column cc, row rr) as if newly visited: found again (one the
 * stitching pass removed, or the record itself) or added. */
static int fresh_rec(tp_cut* c, int64_t node, int s, int cc, int rr)
{
    int j = tp__cut_find(c, node);
    if (j < 0)
        return tp__cut_add_at(c, node, s, cc, rr);
    tp__cut_rec* r = &c->rec[j];
    memset(r, 0, sizeof *r);
    r->node = node;
    r->s = (int8_t)s, r->c = cc, r->r = rr;
    r->sph = -1;
    return j;
}

/* Adds record j to the queue of tp__cut_select_below (fix[0..*count)). */
static int fix_push(tp_cut* c, size_t* count, int j)
{
    if (j < 0 || !tp__cut_grow(c, (void**)&c->fix, &c->fix_cap, *count + 1, sizeof *c->fix))
        return 0;
    c->fix[(*count)++] = j;
    return 1;
}

int tp__cut_select_below(tp_cut* c, int i)
{
    const tp__cut_rec* r = &c->rec[i];
    size_t count = 0;
    if (!fix_push(c, &count, fresh_rec(c, r->node, r->s, r->c, r->r)))
        return 0;
    size_t head = 0;
    for (; head < count && !c->oom; head++) {
        int j = c->fix[head];
        int refine = classify(c, j, 1);
        tp__cut_changed(c, j);
        if (!refine)
            continue;
        for (int q = 0; q < 4; q++) {
            int cc, rr;
            int64_t ch = kid(c, j, q, &cc, &rr);
            int k = fresh_rec(c, ch, c->rec[j].s - 1, cc, rr);
            if (!fix_push(c, &count, k))
                return 0;
            hand_down(c, j, q, k);
        }
    }
    return c->oom ? 0 : (int)head;
}

/* ---- the update ---- */

tp_status tp_cut_update(tp_cut* c, const tp_camera* cam, const tp_lod_params* params, tp_error* err)
{
    assert(c && cam);
    tp_lod_params lp;
    tp_status st = tp_lod_params_resolve(NULL, params, &lp, err);
    if (st != TP_OK)
        return st;
    if (lp.mode == TP_LOD_MAX_ERROR)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "cut: the max-error mode is not available over a tree (use error, "
                        "distance or full)");
    if (!params || (params->mindist_m == 0 && params->maxdist_m == 0)) {
        /* The defaults in leaf widths, as tp_lod_params_resolve does with patch widths. */
        double leaf_m = (double)(1 << c->n) * fmax(fabs(c->gt[1]), fabs(c->gt[5]));
        lp.mindist_m = leaf_m;
        lp.maxdist_m = 24 * leaf_m;
    }
    tp__cut_begin(c);
    c->lp = lp;
    c->have_view = 1;
    tp__view_from_camera(cam, &c->v);
    tp_frustum_from_camera(cam, &c->f);
    if (lp.mode == TP_LOD_DISTANCE && lp.sphere_tree) {
        if (!tp__spheres_update(c))
            c->oom = 1;
        c->sph_on = 1;
    }
    /* Breadth first from each root: the children of a refined node are appended to the
     * records, so the queue is the records not yet classified. */
    for (int64_t ri = 0; ri < c->g.root_count && !c->oom; ri++) {
        int64_t root = c->roots[ri];
        if (!tp_tree_samples(c->t, root)) {
            int s, cc, rr;
            tp_tree_node_locate(&c->g, root, &s, &cc, &rr);
            if (in_view_at(c, root, s, cc, rr))
                tp__cut_request(c, root, INFINITY);
            continue; /* a hole: roots are to stay resident */
        }
        size_t first = c->rec_count;
        int rootrec = tp__cut_add(c, root);
        if (rootrec < 0)
            break;
        if (c->sph_on)
            c->rec[rootrec].sph = (int32_t)ri;
        for (size_t i = first; i < c->rec_count && !c->oom; i++) {
            if (!classify(c, (int)i, 1))
                continue;
            for (int q = 0; q < 4; q++) {
                int cc, rr;
                int64_t ch = kid(c, (int)i, q, &cc, &rr);
                int j = tp__cut_add_at(c, ch, c->rec[i].s - 1, cc, rr);
                if (j < 0)
                    break;
                if (c->sph_on)
                    c->rec[j].sph = tp__spheres_kid(c, c->rec[i].sph, q);
                hand_down(c, (int)i, q, j);
            }
        }
    }
    return tp__cut_finish(c, err);
}

tp_status tp_cut_update_requests(tp_cut* c, const tp_camera* cam, const tp_lod_params* params,
                                 tp_error* err)
{
    assert(c && cam);
    c->requests_only = 1;
    tp_status st = tp_cut_update(c, cam, params, err);
    c->requests_only = 0;
    return st;
}

