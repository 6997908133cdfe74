/* tin_node_bound.c - the bound of one triangle of a node's TIN against every full-resolution
 * sample under it (tin_node.c measures its rungs with it; issue 32 item 2, docs/tin.md "TIN
 * nodes").
 *
 * Two parts, added: |T - S_n| over the triangle T, where S_n is the node's level-n surface (its
 * samples, every lattice cell split by its anti-diagonal as every level of the lattice is), and
 * |S_n - f| over the part of the node T covers, f the full resolution (the carry).
 *
 * |T - S_n|, exactly: T - S_n is linear on each piece of T cut by the lattice's edges, so its
 * largest magnitude is at a corner of a piece: a vertex of T (a sample: 0), a lattice sample
 * inside or on T (the samples tp__lattice_triangle_error covers), or a point where an edge of T
 * crosses a lattice edge (vertical, horizontal or anti-diagonal), where S_n interpolates the
 * two samples of that lattice edge. Measured in integers, exactly. (The cell bound the node's
 * eps tables use, every corner of every cell T touches with T's plane extended there, is a bound
 * too but a loose one for large cells: T's plane a cell beyond its edge.)
 *
 * The carry: descendant D at depth d of a node of scale s >= d holds, in its level n - d
 * lattice, exactly the node's level-n samples over D's area with the same split, so D's
 * delta[n - d] bounds |S_n - f| there. tp_node_carry_regions reads them (d = min(s, 3): 64
 * regions of 8x8 cells for n = 6) and a triangle adds the largest over the regions its bounding
 * box touches (closed regions: a sample on a region's border is in both). d = 0 is the node's own
 * delta[n], the carry every bound of the node's metas adds.
 */
#include "lattice.h"
#include "tin_int.h"

#include <math.h>

int tp_node_carry_depth(int scale) { return scale < TP_NODE_CARRY_DEPTH ? scale : TP_NODE_CARRY_DEPTH; }

void tp_node_carry_regions(const tp_tree* t, int64_t node, uint16_t* carry)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int s, c, r;
    tp_tree_node_locate(g, node, &s, &c, &r);
    int d = tp_node_carry_depth(s), nr = 1 << d;
    uint16_t own = tp_tree_meta(t, node)->delta[g->n];
    for (int ry = 0; ry < nr; ry++)
        for (int rx = 0; rx < nr; rx++) {
            int64_t id = node;
            for (int l = d - 1; l >= 0; l--) /* quadrant q: bit 0 right, bit 1 bottom */
                id = tp_tree_node_child(g, id, (ry >> l & 1) * 2 + (rx >> l & 1));
            uint16_t v = tp_tree_meta(t, id)->delta[g->n - d];
            carry[ry * nr + rx] = v < own ? v : own; /* both bound it: the smaller */
        }
}

static inline int64_t floor_div64(int64_t a, int64_t b) /* b > 0 */
{
    int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

static inline int64_t sq(const tp__tin_node_bound* b, int64_t i, int64_t j)
{
    return b->q[(size_t)j * (size_t)b->side + (size_t)i];
}

/* The largest |T - S_n| (steps) where edge a -> b (heights za, zb) crosses a lattice edge of
 * family f: 0 vertical lines x = c, 1 horizontal y = c, 2 anti-diagonals x + y = c. With u the
 * family's coordinate (x, y or x + y) and D = u(b) - u(a) > 0, the crossing at u = c lies at
 * parameter (c - u(a)) / D along the edge; v = the other coordinate (y, x, x) there times D is an
 * integer V, the lattice edge's two samples are at floor(V / D) and one more, weighted by the
 * remainder. Everything times D: exact in int64 (D <= 2^(n+1), heights < 2^31). */
static double crossings(const tp__tin_node_bound* b, const int32_t a[2], const int32_t e[2],
                        int64_t za, int64_t zb, int f)
{
    int64_t ua = f == 0 ? a[0] : f == 1 ? a[1] : (int64_t)a[0] + a[1];
    int64_t ub = f == 0 ? e[0] : f == 1 ? e[1] : (int64_t)e[0] + e[1];
    int64_t va = f == 1 ? a[0] : f == 0 ? a[1] : a[0], vb = f == 1 ? e[0] : f == 0 ? e[1] : e[0];
    if (ua == ub)
        return 0;
    if (ua > ub) { /* walk from the lower u */
        int64_t t;
        t = ua, ua = ub, ub = t;
        t = va, va = vb, vb = t;
        t = za, za = zb, zb = t;
    }
    int64_t D = ub - ua, mx = 0;
    for (int64_t c = ua + 1; c < ub; c++) {
        int64_t V = va * D + (c - ua) * (vb - va);
        int64_t v0 = floor_div64(V, D), r = V - v0 * D;
        if (r == 0)
            continue; /* a lattice sample: measured with the samples T covers */
        int64_t s0, s1; /* S_n's two samples on the crossed lattice edge, weights D - r and r */
        if (f == 0) /* x = c, between rows v0 and v0 + 1 */
            s0 = sq(b, c, v0), s1 = sq(b, c, v0 + 1);
        else if (f == 1) /* y = c, between columns v0 and v0 + 1 */
            s0 = sq(b, v0, c), s1 = sq(b, v0 + 1, c);
        else /* x + y = c at x = v0 + r / D: from (v0, c - v0) to (v0 + 1, c - v0 - 1) */
            s0 = sq(b, v0, c - v0), s1 = sq(b, v0 + 1, c - v0 - 1);
        int64_t tz = za * D + (c - ua) * (zb - za), sz = s0 * (D - r) + s1 * r;
        int64_t err = tz > sz ? tz - sz : sz - tz;
        mx = err > mx ? err : mx;
    }
    return (double)mx / (double)D;
}

double tp__tin_node_tri_bound(const tp__tin_node_bound* b, const int32_t pos[3][2])
{
    int64_t z[3];
    for (int v = 0; v < 3; v++)
        z[v] = sq(b, pos[v][0], pos[v][1]);
    double e = tp__lattice_triangle_error(b->q, b->side, pos, z, 0); /* the samples it covers */
    if (b->scale > 0) /* between the samples: S_n is not the full resolution */
        for (int v = 0; v < 3; v++)
            for (int f = 0; f < 3; f++) {
                double x = crossings(b, pos[v], pos[(v + 1) % 3], z[v], z[(v + 1) % 3], f);
                e = x > e ? x : e;
            }
    /* the carry of every region the bounding box touches */
    int32_t box[4];
    tp__tri_box(pos, box);
    int sh = b->n - b->depth, nr = 1 << b->depth;
    int rx0 = box[0] >> sh, ry0 = box[1] >> sh;
    int rx1 = (box[2] - 1) >> sh, ry1 = (box[3] - 1) >> sh; /* cells box[0] .. box[2] - 1 */
    rx1 = rx1 < rx0 ? rx0 : rx1 >= nr ? nr - 1 : rx1;
    ry1 = ry1 < ry0 ? ry0 : ry1 >= nr ? nr - 1 : ry1;
    unsigned carry = 0;
    for (int ry = ry0; ry <= ry1; ry++)
        for (int rx = rx0; rx <= rx1; rx++)
            carry = b->carry[ry * nr + rx] > carry ? b->carry[ry * nr + rx] : carry;
    if (carry >= TP__ERR_SAT)
        return INFINITY;
    return e + carry * b->unit;
}
