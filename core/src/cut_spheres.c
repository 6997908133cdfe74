/* cut_spheres.c - Blow's isosurface LoD for the cut's distance mode (tp_lod_params.sphere_tree).
 *
 * In distance mode a node's fate depends only on d, the eye's distance to its area box: the
 * decision F(d) (refine, or the level it is drawn at; tp__cut_distance_decision) is a step
 * function of d, and it never gets finer as d grows. So each decision holds on an interval
 * [lo, hi] of d: its merge and refine distances. Around the node's box these are offset
 * surfaces ("spheres" in the box metric: boxes with rounded corners); the eye changes the
 * decision only by crossing one of them.
 *
 * This file keeps the distance cut over the WHOLE terrain (no frustum, no residency): every
 * node the distance rule reaches from the roots, with its decision and interval. The hierarchy
 * of the spheres is the emergent one: a child's refine surface lies inside its parent's (its
 * box is inside, its threshold no larger), so a child is only looked at while its parent is
 * refined. Each subtree also keeps a ball around the eye position where it was last checked,
 * of radius the distance to the nearest threshold surface in the subtree (d is 1-Lipschitz in
 * the eye position): while the eye stays inside that ball, nothing in the subtree can change
 * and the subtree is not visited. Every node has 4 children, so the one level that can get
 * crowded is the roots' (a forest along the far edges: 1 root for 65537² in 65-sample nodes,
 * 10 for 20481², more for other sizes): it is clustered, CLUSTER consecutive roots sharing one
 * more ball (Blow's "fake" spheres, standing for no node).
 *
 * The cut's frame (cut_select.c) still traverses from the roots with frustum culling and
 * residency, and runs the stitching pass, but reads each node's distance decision from here
 * instead of computing it: the same cut as the plain traversal (tests/test_spheres.c).
 * The intervals: F's level sets are intervals independent of the node (they depend on its scale,
 * whether it is whole, and the parameters), found once per parameters by bisection on F itself
 * and kept as the closed intervals KNOWN to give the value (conservative by a few ulps).
 */
#include "cut_int.h"

#include <string.h>

enum { CLUSTER = 16, VALS = TP_MAX_N + 2 /* refine, levels 0..n */ };

typedef struct sph_entry {
    int64_t node;
    int32_t c, r;
    int32_t kid[4]; /* refined: the children's entries; else kid[0] links the free list */
    int8_t s, whole, dec, empty;
    double bmin[3], bmax[3]; /* area box, drawn space */
    double lo, hi;           /* the decision holds for lo <= d <= hi */
    double p[3], gap;        /* nothing in the subtree changes while |eye - p| < gap */
} sph_entry;

typedef struct sph_range {
    uint8_t known;
    double lo, hi;
} sph_range;

typedef struct tp__spheres tp__spheres;
struct tp__spheres {
    /* what the decisions were made with: another value rebuilds everything */
    double mindist, maxdist, exponent, hole_px, f_px, zscale;
    int built;
    sph_entry* e;
    size_t count, cap;
    int32_t free_head;
    int64_t roots;   /* entries 0 .. roots-1 are the roots, in c->roots order */
    double (*cl)[4]; /* per cluster of CLUSTER roots: ball centre and radius */
    size_t clusters;
    sph_range range[TP_TREE_MAX_SCALES][2][VALS];
    int visited, decided, live;
};

static double dist3(const double a[3], const double b[3])
{
    double x = a[0] - b[0], y = a[1] - b[1], z = a[2] - b[2];
    return sqrt(x * x + y * y + z * z);
}

static double box_dist(const double pos[3], const double bmin[3], const double bmax[3])
{
    double d2 = 0; /* as cut_select.c's box_distance, to the bit */
    for (int a = 0; a < 3; a++) {
        double d = pos[a] < bmin[a] ? bmin[a] - pos[a] : pos[a] > bmax[a] ? pos[a] - bmax[a] : 0;
        d2 += d * d;
    }
    return sqrt(d2);
}

/* The interval of d over which F(s, whole, .) keeps the value it has at d (F never increases
 * with d: refine > n > ... > 0, so each value's set is an interval). */
static const sph_range* range_of(tp_cut* c, int s, int whole, double d)
{
    tp__spheres* S = c->sph;
    int v = tp__cut_distance_decision(c, s, whole, d);
    sph_range* r = &S->range[s][whole][v + 1];
    if (r->known)
        return r;
    /* hi: double until F changes, then bisect; lo: bisect between 0 and d */
    double a = d, b = d > 1 ? 2 * d : 2;
    while (b < 1e300 && tp__cut_distance_decision(c, s, whole, b) == v)
        a = b, b *= 2;
    if (b >= 1e300)
        r->hi = INFINITY;
    else {
        for (int it = 0; it < 200; it++) {
            double m = a + (b - a) / 2;
            if (m <= a || m >= b)
                break;
            if (tp__cut_distance_decision(c, s, whole, m) == v)
                a = m;
            else
                b = m;
        }
        r->hi = a;
    }
    if (tp__cut_distance_decision(c, s, whole, 0) == v)
        r->lo = -INFINITY;
    else {
        a = 0, b = d; /* F(a) != v, F(b) == v */
        for (int it = 0; it < 200; it++) {
            double m = a + (b - a) / 2;
            if (m <= a || m >= b)
                break;
            if (tp__cut_distance_decision(c, s, whole, m) == v)
                b = m;
            else
                a = m;
        }
        r->lo = b;
    }
    r->known = 1;
    return r;
}

/* A new entry for node (scale s, column cc, row rr), or -1 without memory. */
static int32_t entry_new(tp_cut* c, int64_t node, int s, int cc, int rr)
{
    tp__spheres* S = c->sph;
    int32_t i = S->free_head;
    if (i >= 0)
        S->free_head = S->e[i].kid[0];
    else {
        if (!tp__cut_grow(c, (void**)&S->e, &S->cap, S->count + 1, sizeof *S->e))
            return -1;
        i = (int32_t)S->count++;
    }
    sph_entry* e = &S->e[i];
    memset(e, 0, sizeof *e);
    e->node = node, e->s = (int8_t)s, e->c = cc, e->r = rr;
    e->kid[0] = e->kid[1] = e->kid[2] = e->kid[3] = -1;
    const tp_node_meta* m = tp_tree_meta(c->t, node);
    e->empty = !(m->flags & TP_NODE_HAS_DRAWN) || m->area_qmin > m->area_qmax;
    e->whole = (m->flags & TP_NODE_COMPLETE) || !(m->flags & TP_NODE_HAS_DRAWN);
    if (!e->empty)
        tp__cut_node_box(c, s, cc, rr, m->area_qmin, m->area_qmax, e->bmin, e->bmax);
    e->dec = (int8_t)c->n;               /* an empty node is never asked */
    e->lo = INFINITY, e->hi = -INFINITY; /* decide at the first visit */
    e->p[0] = e->p[1] = e->p[2] = NAN;
    S->live++;
    return i;
}

static void subtree_free(tp__spheres* S, int32_t i)
{
    for (int q = 0; q < 4; q++) {
        int32_t k = S->e[i].kid[q];
        if (k < 0)
            continue;
        subtree_free(S, k);
        S->e[k].kid[0] = S->free_head;
        S->free_head = k;
        S->live--;
        S->e[i].kid[q] = -1;
    }
}

/* Brings entry i's subtree up to date for eye position pos; returns the radius of a ball
 * around pos inside which nothing in it changes (0 without memory: c->oom is set). */
static double refresh(tp_cut* c, int32_t i, const double pos[3])
{
    tp__spheres* S = c->sph;
    sph_entry* e = &S->e[i];
    double moved = dist3(pos, e->p);
    if (moved < e->gap) /* NaN p (new): not taken */
        return e->gap - moved;
    S->visited++;
    if (e->empty) {
        e->gap = INFINITY;
        memcpy(e->p, pos, sizeof e->p);
        return INFINITY;
    }
    double d = box_dist(pos, e->bmin, e->bmax);
    if (!(d >= e->lo && d <= e->hi)) {
        S->decided++;
        int v = tp__cut_distance_decision(c, e->s, e->whole, d);
        const sph_range* r = range_of(c, e->s, e->whole, d);
        e = &S->e[i];
        e->dec = (int8_t)v, e->lo = r->lo, e->hi = r->hi;
        if (v < 0 && e->kid[0] < 0) {
            int s = e->s - 1, cc = 2 * e->c, rr = 2 * e->r;
            for (int q = 0; q < 4; q++) {
                int kc = cc + (q & 1), kr = rr + (q >> 1);
                int64_t ch = c->g.first_node[s] + (int64_t)kr * c->g.node_cols[s] + kc;
                int32_t k = entry_new(c, ch, s, kc, kr);
                if (k < 0)
                    return 0;
                S->e[i].kid[q] = k;
            }
            e = &S->e[i];
        } else if (v >= 0 && e->kid[0] >= 0)
            subtree_free(S, i);
    }
    /* margin: box_dist's rounding, a few ulps of d */
    double gap = fmin(d - e->lo, e->hi - d) - (1e-9 * d + 1e-6);
    for (int q = 0; q < 4 && e->dec < 0; q++) {
        double g = refresh(c, e->kid[q], pos);
        if (c->oom)
            return 0;
        e = &S->e[i];
        gap = fmin(gap, g);
    }
    e->gap = gap > 0 ? gap : 0;
    memcpy(e->p, pos, sizeof e->p);
    return e->gap;
}

static void reset(tp_cut* c)
{
    tp__spheres* S = c->sph;
    S->count = 0, S->free_head = -1, S->live = 0, S->built = 0;
    memset(S->range, 0, sizeof S->range);
}

int tp__spheres_update(tp_cut* c)
{
    if (!c->sph) {
        c->sph = tp__calloc(&c->alloc, 1, sizeof *c->sph);
        if (!c->sph)
            return 0;
        c->sph->free_head = -1;
    }
    tp__spheres* S = c->sph;
    const tp_lod_params* p = &c->lp;
    if (!S->built || S->mindist != p->mindist_m || S->maxdist != p->maxdist_m ||
        S->exponent != p->exponent || S->hole_px != p->hole_px || S->f_px != c->v.f_px ||
        S->zscale != c->zscale) {
        reset(c);
        S->mindist = p->mindist_m, S->maxdist = p->maxdist_m, S->exponent = p->exponent;
        S->hole_px = p->hole_px, S->f_px = c->v.f_px, S->zscale = c->zscale;
        S->roots = c->g.root_count;
        for (int64_t ri = 0; ri < S->roots; ri++) {
            int s, cc, rr;
            tp_tree_node_locate(&c->g, c->roots[ri], &s, &cc, &rr);
            if (entry_new(c, c->roots[ri], s, cc, rr) < 0)
                return 0;
        }
        S->clusters = (size_t)(S->roots + CLUSTER - 1) / CLUSTER;
        tp__free(&c->alloc, S->cl);
        S->cl = tp__alloc(&c->alloc, S->clusters ? S->clusters : 1, sizeof *S->cl);
        if (!S->cl)
            return 0;
        for (size_t k = 0; k < S->clusters; k++)
            S->cl[k][0] = S->cl[k][1] = S->cl[k][2] = NAN, S->cl[k][3] = 0;
        S->built = 1;
    }
    S->visited = S->decided = 0;
    const double* pos = c->v.pos;
    for (size_t k = 0; k < S->clusters; k++) {
        double* cl = S->cl[k];
        double moved = dist3(pos, cl);
        if (moved < cl[3])
            continue;
        S->visited++;
        double gap = INFINITY;
        for (int64_t ri = (int64_t)k * CLUSTER; ri < S->roots && ri < (int64_t)(k + 1) * CLUSTER;
             ri++) {
            gap = fmin(gap, refresh(c, (int32_t)ri, pos));
            if (c->oom) {
                S->built = 0; /* half updated: start again next time */
                return 0;
            }
        }
        memcpy(cl, pos, 3 * sizeof *cl);
        cl[3] = gap;
    }
    return 1;
}

int32_t tp__spheres_kid(const tp_cut* c, int32_t i, int q)
{
    return i >= 0 && c->sph->e[i].dec < 0 ? c->sph->e[i].kid[q] : -1;
}

int tp__spheres_decision(const tp_cut* c, int32_t i)
{
    return c->sph->e[i].dec;
}

void tp__spheres_stats(const tp_cut* c, int* visited, int* decided, int* live)
{
    const tp__spheres* S = c->sph;
    *visited = S ? S->visited : 0;
    *decided = S ? S->decided : 0;
    *live = S ? S->live : 0;
}

void tp__spheres_destroy(tp_cut* c)
{
    if (!c->sph)
        return;
    tp__free(&c->alloc, c->sph->e);
    tp__free(&c->alloc, c->sph->cl);
    tp__free(&c->alloc, c->sph);
    c->sph = NULL;
}
