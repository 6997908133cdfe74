/* cut_stitch.c - crack removal between drawn tree nodes of any size and level: the stitching
 * pass (what the stitched cut then draws is cut_draw.c's).
 *
 * Vertex strides are powers of two of grid samples: 2^(s+n-k) for a node of scale s at level
 * k, and every node's vertices lie on multiples of its stride. Two drawn nodes A and B share
 * part of an edge; say stride(B) > stride(A). A's side vertices can move onto B's vertices
 * (lattice.c's snapping on A's lattice, relative level kn = level(B) - (scale(B) - scale(A)))
 * when
 *   1. stride(B) <= side(A) = 2^(n+scale(A)): A's corners are vertices of B, so A's moved side
 *      is exactly B's vertex-to-vertex segments (kn >= 0);
 *   2. scale(B) >= scale(A): a side carries one relative level, so only a side with a single
 *      neighbour (the smaller or equal node's) may move; the larger node's side never moves.
 * Levels are raised (only up) until both hold; 1 can fail only when scale(B) - scale(A) > n,
 * and then B is split into its children when they are resident, else A's ancestor of scale
 * scale(B) - n is drawn instead (at level n, frozen: never split again in this update), which
 * is always resident since the update went through it. Each node is frozen at most once and
 * splits only go down, so the pass ends. Only if A has no such ancestor (a forest whose
 * adjacent roots differ by more than n scales, and B's children are not resident) does a
 * crack remain: counted in tp_cut's `unresolved`.
 * The pass runs over a work list: every drawn node once, then only nodes whose neighbourhood
 * changed (a node whose level changed, and its neighbours of its size or smaller).
 * In error mode a coarser neighbour is also raised while the finer node's stitched bound (its
 * eps table) projects above tau, as tp_selection_update does; one already at level n (so
 * larger than the finer node) is split when its children are resident.
 */
#include "cut_int.h"

#include <string.h>

static const int dcol[4] = {0, 1, 0, -1}, drow[4] = {-1, 0, 1, 0};

int tp__cut_neighbor(const tp_cut* c, int i, int side)
{
    const tp__cut_rec* a = &c->rec[i];
    int64_t cc = (int64_t)a->c + dcol[side], rr = (int64_t)a->r + drow[side];
    if (cc < 0 || rr < 0)
        return -1;
    for (int s = a->s; s < c->g.scales; s++, cc >>= 1, rr >>= 1) {
        if (cc >= c->g.node_cols[s] || rr >= c->g.node_rows[s])
            return -1; /* no node there at this scale, so none above */
        int j = tp__cut_find(c, tp_tree_node_id(&c->g, s, (int)cc, (int)rr));
        if (j < 0 || c->rec[j].state == TP__CUT_REMOVED)
            continue;
        return c->rec[j].state == TP__CUT_DRAWN ? j : -1; /* INTERIOR: smaller nodes there */
    }
    return -1;
}

static int node_complete(const tp_cut* c, int i)
{
    return (tp_tree_meta(c->t, c->rec[i].node)->flags & TP_NODE_COMPLETE) != 0;
}

static int stride_log(const tp__cut_rec* r, int n)
{
    return r->s + n - r->level;
}

/* Drawn record i's seam with its drawn neighbour j (of its scale or larger) on one side: the
 * relative level i's side moves to (*nb) and, --stitch add, the level whose vertices it takes
 * (*add); TP_NO_NEIGHBOR each when none. */
static void seam(const tp_cut* c, int i, int j, int* nb, int* add)
{
    const tp__cut_rec *a = &c->rec[i], *b = &c->rec[j];
    *nb = *add = TP_NO_NEIGHBOR;
    if (c->stitch_add && b->s == a->s) {
        /* the coarser of two same-size nodes takes the finer one's vertices when it is complete
           (every sample of the shared side is then drawn); else the finer one moves */
        if (b->level > a->level) {
            if (node_complete(c, i))
                *add = b->level;
            return;
        }
        if (b->level < a->level && node_complete(c, j))
            return;
    }
    int kn = b->level - (b->s - a->s);
    if (stride_log(b, c->n) > stride_log(a, c->n) && kn >= 0)
        *nb = kn;
}

int tp__cut_seams(const tp_cut* c, int i, int nb[4], int add[4])
{
    const tp__cut_rec* a = &c->rec[i];
    int cracks = 0;
    for (int side = 0; side < 4; side++) {
        nb[side] = add[side] = TP_NO_NEIGHBOR;
        int j = tp__cut_neighbor(c, i, side);
        if (j < 0)
            continue;
        cracks += c->rec[j].s - a->s > c->n;
        seam(c, i, j, &nb[side], &add[side]);
    }
    return cracks;
}

/* Queues drawn record i for (re)checking (and marks it touched: its seams may change). */
static void push(tp_cut* c, int i)
{
    if (c->rec[i].state != TP__CUT_DRAWN)
        return;
    c->rec[i].touched = 1;
    if (c->rec[i].queued ||
        !tp__cut_grow(c, (void**)&c->work, &c->work_cap, c->work_count + 1, sizeof *c->work))
        return;
    c->rec[i].queued = 1;
    c->work[c->work_count++] = i;
}

static const int side_quads[4][2] = {{0, 1}, {1, 3}, {2, 3}, {0, 2}}; /* children on a side */

/* Queues the drawn nodes under record j that touch side `side` of j's square. */
static void push_along(tp_cut* c, int j, int side)
{
    if (c->rec[j].state == TP__CUT_DRAWN) {
        push(c, j);
        return;
    }
    if (c->rec[j].state != TP__CUT_INTERIOR || c->rec[j].s == 0)
        return;
    for (int q = 0; q < 2; q++) {
        int k = tp__cut_find(c, tp_tree_node_child(&c->g, c->rec[j].node, side_quads[side][q]));
        if (k >= 0)
            push_along(c, k, side);
    }
}

/* The same for the square (s, cc, rr), which need not be a node: past the last whole node
 * (a forest's far edges) its smaller parts are. */
static void push_square(tp_cut* c, int s, int64_t cc, int64_t rr, int side)
{
    if ((cc << s) >= c->g.cols || (rr << s) >= c->g.rows)
        return; /* outside the map */
    if (cc < c->g.node_cols[s] && rr < c->g.node_rows[s]) {
        int j = tp__cut_find(c, tp_tree_node_id(&c->g, s, (int)cc, (int)rr));
        if (j >= 0)
            push_along(c, j, side);
        return;
    }
    for (int q = 0; s > 0 && q < 2; q++) {
        int quad = side_quads[side][q];
        push_square(c, s - 1, 2 * cc + (quad & 1), 2 * rr + (quad >> 1), side);
    }
}

/* Queues the drawn neighbours of record i's square of its scale or smaller (those that check
 * their relation with i, or with what replaced it). */
static void push_smaller(tp_cut* c, int i)
{
    for (int side = 0; side < 4; side++) {
        int64_t cc = (int64_t)c->rec[i].c + dcol[side], rr = (int64_t)c->rec[i].r + drow[side];
        if (cc >= 0 && rr >= 0)
            push_square(c, c->rec[i].s, cc, rr, (side + 2) % 4); /* their side facing i */
    }
}

/* A record's level changed: it and its smaller neighbours are checked again. */
static void changed(tp_cut* c, int i)
{
    push(c, i);
    push_smaller(c, i);
}

void tp__cut_changed(tp_cut* c, int i)
{
    changed(c, i);
}

/* Marks every record under record i (exclusive) removed. */
static void remove_below(tp_cut* c, int i)
{
    if (c->rec[i].s == 0)
        return;
    for (int q = 0; q < 4; q++) {
        int j = tp__cut_find(c, tp_tree_node_child(&c->g, c->rec[i].node, q));
        if (j < 0 || c->rec[j].state == TP__CUT_REMOVED)
            continue;
        if (c->rec[j].state == TP__CUT_INTERIOR)
            remove_below(c, j);
        c->rec[j].state = TP__CUT_REMOVED;
    }
}

/* Replaces drawn record i by its children; 0 if they are not all ready (or it is frozen). */
static int split(tp_cut* c, int i)
{
    if (c->rec[i].frozen || !tp__cut_children_ready(c, i))
        return 0;
    int64_t node = c->rec[i].node;
    int k = c->rec[i].level;
    for (int q = 0; q < 4; q++) {
        int64_t ch = tp_tree_node_child(&c->g, node, q);
        int j = tp__cut_find(c, ch);
        if (j < 0)
            j = tp__cut_add(c, ch);
        if (j < 0)
            return 1; /* out of memory: the update fails */
        c->rec[j].level = 0;
        c->rec[j].substituted = 0;
        c->rec[j].queued = 0;
        tp__cut_settle(c, j);
        if (!c->have_view && c->rec[j].state == TP__CUT_DRAWN) {
            /* An installed cut: the children keep the parent's stride where they can. */
            c->rec[j].level = (int8_t)(k > 0 ? k - 1 : c->n);
        }
        push(c, j);
    }
    c->rec[i].state = TP__CUT_INTERIOR;
    push_smaller(c, i);
    return 1;
}

/* Draws the ancestor of record i at scale s instead of everything under it; 0 if there is none
 * (or it is not resident). */
static int collapse(tp_cut* c, int i, int s)
{
    int64_t p = c->rec[i].node;
    for (int k = c->rec[i].s; k < s && p >= 0; k++)
        p = tp_tree_node_parent(&c->g, p);
    if (p < 0 || !tp_tree_samples(c->t, p))
        return 0;
    int j = tp__cut_find(c, p);
    if (j < 0)
        return 0;
    remove_below(c, j);
    c->rec[j].frozen = 1;
    c->rec[j].substituted = 0; /* its own children may be resident: B's are not */
    c->rec[j].queued = 0;
    tp__cut_settle(c, j); /* drawn at n: it wants refining, or is culled */
    c->rec[j].level = (int8_t)c->n;
    changed(c, j);
    return 1;
}

/* Checks drawn record i against its neighbours of its scale or larger, changing what the rules
 * ask and queueing what that affects. */
static void check(tp_cut* c, int i)
{
    int n = c->n;
    int error = c->have_view && c->lp.mode == TP_LOD_ERROR;
    int nbj[4] = {-1, -1, -1, -1}, reshaped = 0; /* the neighbours; a split or collapse */
    for (int side = 0; side < 4 && c->rec[i].state == TP__CUT_DRAWN && !c->oom; side++) {
        int j = tp__cut_neighbor(c, i, side);
        nbj[side] = j;
        if (j < 0)
            continue;
        tp__cut_rec *a = &c->rec[i], *b = &c->rec[j];
        int ds = b->s - a->s;
        if (ds > n) {
            reshaped = 1;
            int bs = b->s;
            if (split(c, j))
                push(c, i);
            else
                collapse(c, i, bs - n); /* else unresolved: counted when the cut is output */
            continue;                   /* records may have moved; the state check ends the loop */
        }
        int la = a->s + n - a->level, lb = b->s + n - b->level;
        if (c->stitch_add && ds == 0 && lb != la && node_complete(c, lb > la ? j : i)) {
            /* --stitch add: the coarser one (i here, else j's own check) takes the vertices;
               in error mode it is raised while its bound with them projects above tau */
            if (lb > la || !error)
                continue;
            int add[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
            add[side] = b->level;
            double geo = tp__cut_add_bound_m(c, i, a->level, add);
            double d = (geo + c->quant) * c->zscale;
            if (geo > 0 && tp__projected_px(&a->pb, c->v.fwd[2], d) > c->lp.tau_px) {
                a->level++;
                changed(c, i);
                side--; /* check this side again */
            }
            continue;
        }
        if (lb > la) {
            if (b->level < ds) {
                b->level = (int8_t)ds;
                changed(c, j);
            }
            int kn = c->rec[j].level - ds;
            if (error && kn < c->rec[i].level) {
                int nb[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
                nb[side] = kn;
                const tp_node_meta* m = tp_tree_meta(c->t, c->rec[i].node);
                double geo = tp_node_error_bound(m, n, c->rec[i].level, nb, c->step, c->err_unit);
                double d = (geo + c->quant) * c->zscale;
                if (geo > 0 && tp__projected_px(&c->rec[i].pb, c->v.fwd[2], d) > c->lp.tau_px) {
                    /* Finer B, or at level n (so larger than A) its children. */
                    if (c->rec[j].level < n) {
                        c->rec[j].level++;
                        changed(c, j);
                        side--; /* check this side again */
                    } else if (split(c, j)) {
                        reshaped = 1;
                        push(c, i);
                    }
                }
            }
        } else if (la > lb && ds > 0) {
            a->level = (int8_t)(a->level + (la - lb));
            changed(c, i);
        }
    }
    if (c->stitch_add && c->rec[i].state == TP__CUT_DRAWN && !c->oom && !reshaped) {
        /* (after a split or collapse i is queued again: checked then) */
        int nb[4], add[4];
        for (int side = 0; side < 4; side++) {
            nb[side] = add[side] = TP_NO_NEIGHBOR;
            if (nbj[side] >= 0)
                seam(c, i, nbj[side], &nb[side], &add[side]);
        }
        int k = tp__cut_add_corner_level(c, i, nb, add);
        if (k > c->rec[i].level) {
            c->rec[i].level = (int8_t)k;
            changed(c, i);
        }
    }
}

void tp__cut_constrain(tp_cut* c)
{
    c->work_count = 0;
    for (size_t i = 0; i < c->rec_count; i++) {
        c->rec[i].queued = 0;
        push(c, (int)i);
    }
    tp__cut_constrain_queued(c);
}

void tp__cut_constrain_queued(tp_cut* c)
{
    while (c->work_count > 0 && !c->oom) {
        int i = c->work[--c->work_count];
        c->rec[i].queued = 0;
        check(c, i);
    }
}
