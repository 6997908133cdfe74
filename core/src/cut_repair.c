/* cut_repair.c - a cut carried to another camera by selecting again only where it no longer
 * holds (tp_cut_repair): the cut worker's frames between selections from the roots.
 *
 * The carried cut is the last update's records, hash, requests and stitched levels, copied.
 * A record still holds for the new camera when tp__cut_holds_node says so (culled: still
 * outside the frustum; drawn: its bound, as stitched, within tau, its holes within hole_px),
 * and a substituted node holds while some child it stands for is still missing. Below every
 * record that does not, the selection runs again as from a root (tp__cut_select_below); the
 * stitching pass then checks only what changed and its neighbours (tp__cut_constrain_queued),
 * the other pairs of neighbours being stitched already, and the output is made as an update
 * makes it, but for the records that pass never queued: their seams, bounds in metres and
 * triangles are those they were output with (only the projection is new). The nodes the hold
 * test leaves alone because they could not be finer (leaves at level n, substituted nodes)
 * are queued for that pass when a side moved onto a coarser neighbour now projects above tau:
 * the pass raises the neighbour, as in an update. Roots missing at the update have no record:
 * one arrived since refuses the carry, the others in view are asked for. So every drawn node
 * projects within tau, as after an update; what is not re-selected keeps its level, which may
 * be finer than a selection from the roots would choose where the camera moved away (the
 * worker selects from the roots now and then, and when the camera stops).
 */
#include "cut_int.h"

#include <math.h>

/* Selecting again more than 1 in REPAIR_SHARE of the records the cut had (a jump, a fast
 * turn): a selection from the roots costs less. */
enum { REPAIR_SHARE = 4 };

/* Whether record i, a drawn node in place of children that were missing, now has every child
 * in view resident (requesting those that are not). */
static int arrived(tp_cut* c, int i)
{
    return c->rec[i].substituted && tp__cut_children_ready(c, i);
}

/* Whether drawn record i's own box is in view. */
static int in_view(const tp_cut* c, int i)
{
    double bmin[3], bmax[3];
    return tp__cut_box(c, i, 0, bmin, bmax) &&
           tp_frustum_test_aabb(&c->f, bmin, bmax) != TP_CULL_OUTSIDE;
}

static const int no_nb[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};

/* Whether drawn record i, which holds, is to be queued for the stitching pass: a node
 * tp__cut_holds_node does not test (a leaf at level n, a substituted node: they could not be
 * finer) with a side moved onto a coarser neighbour that adds to its bound, which now projects
 * above tau: the pass raises (or splits) that neighbour, as in an update. */
static int seams_again(const tp_cut* c, int i)
{
    const tp__cut_rec* r = &c->rec[i];
    /* the projection first: it settles most nodes without computing their unstitched bound */
    return ((r->s == 0 && r->level == c->n) || r->substituted) && r->pb_known &&
           tp__projected_px(&r->pb, c->v.fwd[2], r->bound_m) > c->lp.tau_px &&
           r->bound_m > tp__cut_bound_m(c, i, r->level, no_nb);
}

/* What tp_cut_repair does with a record (tp__cut_rec.redo): SEAMS, queued for the stitching
 * pass (seams_again). */
enum { KEEP = 0, SELECT, CULL, SEAMS };

/* Marks (redo) the records that no longer hold for c's view (SELECT) and the drawn ones now
 * outside it (CULL), and gives the drawn ones their projection bounds from it; returns how
 * many are to be selected again, or -1 when a node drawn or to be selected again is not
 * resident. */
static int mark(tp_cut* c)
{
    int marked = 0;
    for (size_t i = 0; i < c->rec_count; i++) {
        tp__cut_rec* r = &c->rec[i];
        r->redo = KEEP; /* frozen: by the last stitching pass, reset as a pass starts */
        r->frozen = r->touched = 0;
        if (r->state != TP__CUT_CULLED)
            r->view = 0; /* a culled record's says which box culled it (tp__cut_holds_node) */
        if (r->state != TP__CUT_DRAWN && r->state != TP__CUT_CULLED) {
            r->pb_known = 0;
            continue;
        }
        if (r->state == TP__CUT_DRAWN && !tp_tree_samples(c->t, r->node))
            return -1;
        double px;
        tp__proj_bound pb;
        int holds = tp__cut_holds_node(c, i, &c->v, &c->f, &px, &pb);
        r->pb_known = !isnan(pb.zmin);
        if (r->pb_known)
            r->pb = pb;
        if (!holds || (r->state == TP__CUT_DRAWN && arrived(c, (int)i))) {
            /* a culled node coming into view that is not resident (a child out of view needs
               not be): its parent would not have been refined */
            if (!tp_tree_samples(c->t, r->node))
                return -1;
            r->redo = SELECT;
            marked++;
        } else if (r->state == TP__CUT_DRAWN && !in_view(c, (int)i))
            r->redo = CULL;
        else if (r->state == TP__CUT_DRAWN && seams_again(c, (int)i))
            r->redo = SEAMS;
    }
    return marked;
}

/* The roots the last update found missing (it made no record for them): 0 when one has
 * arrived since (a selection from the roots draws it), else each in view is asked for, as
 * tp_cut_update asks. O(roots). */
static int roots_missing(tp_cut* c)
{
    for (int64_t ri = 0; ri < c->g.root_count; ri++) {
        int64_t root = c->roots[ri];
        if (tp__cut_find(c, root) >= 0)
            continue;
        if (tp_tree_samples(c->t, root))
            return 0;
        const tp_node_meta* m = tp_tree_meta(c->t, root);
        int s, cc, rr;
        double bmin[3], bmax[3];
        if (!(m->flags & TP_NODE_HAS_DRAWN) || m->area_qmin > m->area_qmax)
            continue;
        tp_tree_node_locate(&c->g, root, &s, &cc, &rr);
        tp__cut_node_box(c, s, cc, rr, m->area_qmin, m->area_qmax, bmin, bmax);
        if (tp_frustum_test_aabb(&c->f, bmin, bmax) != TP_CULL_OUTSIDE)
            tp__cut_request(c, root, INFINITY);
    }
    return 1;
}

int tp_cut_repair(tp_cut* c, const tp_cut* from, const tp_camera* cam)
{
    assert(c && from && cam && c->t == from->t);
    /* output_zscale: from's records are for the scale its output was made with */
    if (!from->have_view || !from->has_output || from->zscale != from->output_zscale ||
        from->lp.mode != TP_LOD_ERROR || from->stitch_add || from->tins || c->stitch_add ||
        c->tins || !tp__cut_copy(c, from))
        return 0;
    tp__view_from_camera(cam, &c->v);
    tp_frustum_from_camera(cam, &c->f);
    c->kid_rec = -1;
    c->work_count = 0;
    size_t kept = 0; /* the requests still missing */
    for (size_t k = 0; k < c->req_count; k++)
        if (!tp_tree_samples(c->t, c->req[k].node))
            c->req[kept++] = c->req[k];
    c->req_count = kept;
    if (!roots_missing(c))
        return 0;
    size_t records = c->rec_count, budget = records / REPAIR_SHARE, selected = 0;
    int marked = mark(c);
    if (marked < 0 || (size_t)marked > budget)
        return 0;
    for (size_t i = 0; i < records && !c->oom; i++) {
        int redo = c->rec[i].redo;
        c->rec[i].redo = KEEP;
        if (redo == CULL) { /* as the selection culls it, by its own box */
            c->rec[i].state = TP__CUT_CULLED;
            tp__cut_changed(c, (int)i); /* its neighbours' seams */
        } else if (redo == SEAMS)
            tp__cut_changed(c, (int)i);
        else if (redo == SELECT) {
            int k = tp__cut_select_below(c, (int)i);
            selected += k > 0 ? (size_t)k : 0;
            if (k <= 0 || selected > budget)
                return 0;
        }
    }
    tp__cut_constrain_queued(c);
    c->carrying = 1;
    int ok = !c->oom && tp__cut_output(c, NULL) == TP_OK;
    c->carrying = 0;
    return ok;
}
