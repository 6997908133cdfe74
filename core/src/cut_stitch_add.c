/* cut_stitch_add.c - crack removal by adding vertices over a tree (tp_core.h,
 * tp_cut_set_stitch_add; Brodersen, section 4, on patches of one size).
 *
 * Between two drawn nodes of the same size the coarser one's side takes the finer one's
 * vertices (tp_cut_node.add; triangulated by tp_patch_triangles_add); both hold every sample
 * of the shared side at their scale, so the vertices added are the node's own samples. Between
 * nodes of different sizes, and next to an incomplete node, vertex moving stays (cut_stitch.c:
 * the smaller or finer node's side moves). tp_patch_triangles_add re-triangulates a grid
 * triangle inside itself; the upper-left triangle of the first cell holds the TOP and LEFT
 * edges, the lower-right one of the last cell BOTTOM and RIGHT. A moved vertex next to a corner
 * collapses onto it (lattice.c), which would fold such a triangle's added vertices away while
 * the neighbour draws them: a node never takes vertices on one and moves them on the other of
 * those two sides. It is raised to the finer neighbour's level instead (cut_stitch.c's check).
 */
#include "cut_int.h"

#include <math.h>
#include <stdlib.h>

void tp_cut_set_stitch_add(tp_cut* c, int add)
{
    assert(c);
    c->stitch_add = add != 0;
    if (c->stitch_add && !c->add_cache) {
        /* without memory add_bound_m falls back on the area range: larger, still a bound */
        c->add_cache = tp__alloc(&c->alloc, TP__CUT_ADD_CACHE, sizeof *c->add_cache);
        for (size_t i = 0; c->add_cache && i < TP__CUT_ADD_CACHE; i++)
            c->add_cache[i].node = -1;
    }
}

int tp_cut_stitch_add(const tp_cut* c)
{
    assert(c);
    return c->stitch_add;
}

int tp__cut_add_corner_level(const tp_cut* c, int i, const int nb[4], const int add[4])
{
    static const int pair[4][2] = {{TP_SIDE_TOP, TP_SIDE_LEFT},
                                   {TP_SIDE_LEFT, TP_SIDE_TOP},
                                   {TP_SIDE_BOTTOM, TP_SIDE_RIGHT},
                                   {TP_SIDE_RIGHT, TP_SIDE_BOTTOM}};
    int k = c->rec[i].level;
    for (int p = 0; p < 4; p++) {
        const int adds = add[pair[p][0]], moves = nb[pair[p][1]];
        if (adds != TP_NO_NEIGHBOR && moves != TP_NO_NEIGHBOR && moves < c->rec[i].level &&
            adds > k)
            k = adds;
    }
    return k;
}

/* Quantised height (steps, global) of sample u (0 .. 2^n) along side `side` of a node's
 * samples q. */
static double side_q(const uint16_t* q, int32_t qmin, int n, int side, int u)
{
    const size_t full = (size_t)1 << n, v = full + 1;
    size_t at;
    switch (side) {
    case TP_SIDE_TOP: at = (size_t)u; break;
    case TP_SIDE_RIGHT: at = (size_t)u * v + full; break;
    case TP_SIDE_BOTTOM: at = full * v + (size_t)u; break;
    default: at = (size_t)u * v; break;
    }
    return (double)q[at] + qmin;
}

/* Entry (side, k, a) of a node's add table (tp__cut_addtab): the largest offset (steps) of the
 * side's samples at stride 2^(n-a) from its level-k edge, rounded up to a float. */
static float add_entry(const tp_cut* c, int64_t node, int side, int k, int a)
{
    const int n = c->n;
    const tp_node_meta* m = tp_tree_meta(c->t, node);
    const uint16_t* q = tp_tree_samples(c->t, node);
    assert(q); /* drawn nodes are resident */
    double worst = 0;
    const int seg = 1 << (n - k), stride = 1 << (n - a);
    for (int lo = 0; lo < (1 << n); lo += seg) {
        const double za = side_q(q, m->qmin, n, side, lo),
                     zb = side_q(q, m->qmin, n, side, lo + seg);
        for (int u = lo + stride; u < lo + seg; u += stride) {
            const double d =
                fabs(side_q(q, m->qmin, n, side, u) - (za + (zb - za) * (u - lo) / seg));
            worst = d > worst ? d : worst;
        }
    }
    float f = (float)worst;
    return (double)f < worst ? nextafterf(f, INFINITY) : f; /* a bound: rounded up */
}

/* The offset bound of node's side at level k with level a added (steps): from the cut's cache
 * of add tables (direct-mapped by node id, kept across updates: a node's samples never change;
 * an entry is computed when first asked for). Without the cache, the area range (any offset). */
static double add_offset(const tp_cut* c, int64_t node, int side, int k, int a)
{
    tp__cut_addtab* cache = c->add_cache;
    if (!cache) {
        const tp_node_meta* m = tp_tree_meta(c->t, node);
        return (double)m->area_qmax - m->area_qmin;
    }
    const int w = c->n + 1;
    tp__cut_addtab* e = &cache[(uint64_t)node % TP__CUT_ADD_CACHE];
    if (e->node != node) {
        e->node = node;
        for (int i = 0; i < 4 * w * w; i++)
            e->tab[i] = -1; /* not computed */
    }
    float* v = &e->tab[((size_t)side * w + k) * w + a];
    if (*v < 0)
        *v = add_entry(c, node, side, k, a);
    return *v;
}

static double add_bound_m(const tp_cut* c, int64_t node, int k, const int add[4])
{
    const int n = c->n;
    const tp_node_meta* m = tp_tree_meta(c->t, node);
    double worst = 0; /* steps */
    for (int side = 0; side < 4; side++) {
        if (add[side] == TP_NO_NEIGHBOR || add[side] <= k)
            continue;
        const double d = add_offset(c, node, side, k, add[side] > n ? n : add[side]);
        worst = d > worst ? d : worst;
    }
    return tp_node_error_bound(m, n, k, NULL, c->step, c->err_unit) + worst * c->step;
}

double tp__cut_add_bound_m(const tp_cut* c, int i, int k, const int add[4])
{
    return add_bound_m(c, c->rec[i].node, k, add);
}

double tp_cut_add_bound_m(const tp_cut* c, size_t i, const int add[4])
{
    assert(c && i < c->out_count && add);
    return add_bound_m(c, c->out[i].node, c->out[i].level, add);
}

int tp__cut_raster_add(const tp_cut* c, size_t i, tp__sample_fn fn, void* user)
{
    const tp_cut_node* o = &c->out[i];
    const int n = c->n, k = o->level;
    int add[4], m = k;
    for (int s = 0; s < 4; s++) {
        add[s] = o->add[s];
        if (add[s] != TP_NO_NEIGHBOR && add[s] > m)
            m = add[s] > n ? n : add[s];
    }
    const size_t side = ((size_t)1 << n) + 1, mside = ((size_t)1 << m) + 1;
    const size_t count = tp_patch_triangles_add(n, k, add, NULL, 0);
    tp_vertex* v = malloc(mside * mside * sizeof *v);
    uint32_t* tri = malloc(3 * count * sizeof *tri);
    if (!v || !tri) {
        free(v);
        free(tri);
        return 0;
    }
    tp_cut_vertices_at_level(c, i, m, v, mside * mside);
    tp_patch_triangles_add(n, k, add, tri, count);
    for (size_t t = 0; t < count; t++) {
        int32_t pos[3][2];
        double z[3];
        int drawn = 1;
        for (int a = 0; a < 3; a++) {
            const size_t row = tri[3 * t + a] / side, col = tri[3 * t + a] % side;
            const tp_vertex* p = &v[(row >> (n - m)) * mside + (col >> (n - m))];
            pos[a][0] = p->x;
            pos[a][1] = p->y;
            z[a] = p->z_m / c->step;
            drawn &= p->cls == TP_SAMPLE_VALID || p->cls == TP_SAMPLE_FILLED;
        }
        if (drawn)
            tp__raster_triangle(pos[0], pos[1], pos[2], z[0], z[1], z[2], fn, user);
    }
    free(v);
    free(tri);
    return 1;
}
