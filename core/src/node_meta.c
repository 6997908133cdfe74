/* node_meta.c - the metas of a tree's nodes (tp_node_meta): each node's error tables, measured
 * on its own samples by lattice_error.c as for a patch, carried up from its children by nested
 * decimation (tp_node_meta_compute), and the bound read from them (tp_node_error_bound).
 *
 * A leaf of a tree (and a patch) holds every full-resolution sample of its area, so measuring
 * at its own samples is exact. A node of scale s >= 1 holds every 2^s-th sample only; its
 * bounds against the full resolution come from nested decimation (see tp_node_meta_compute).
 */
#include "lattice.h"

#include <string.h>

double tp_tree_err_unit_steps(double range_steps)
{
    double u = 1.0 / 16;
    while (u < 1 && range_steps / u > (double)(TP_NODE_ERR_SAT - 1))
        u *= 2;
    return u;
}

static uint16_t add_units(unsigned a, unsigned b, unsigned cap)
{
    unsigned s = a + b;
    s = s > cap ? cap : s;
    return (uint16_t)s;
}

/* For a node of scale s >= 1 (nested decimation): the node's level-n surface S_n is,
 * geometrically, its 4 children's level n-1 surfaces (vertex stride 2^s in both), and each
 * level's triangulation refines the coarser ones with the same diagonal everywhere. So for a
 * full-resolution sample p under a level-k triangle,
 *   |S_k(p) - f(p)| <= |S_k(p) - S_n(p)| + |S_n(p) - f(p)| <= delta_own(k) + carry,
 * where S_k - S_n is linear on each S_n triangle (so its maximum is at the node's own samples:
 * delta_own, measured as for a leaf) and carry = max over children of child.delta[n-1], which
 * already holds against full resolution (induction from the leaves, where it is exact).
 * delta[n] = carry. Stitched triangles use the cell bound (cell_bound above) plus carry.
 * Incomplete nodes: S_n is missing where a sample is not drawn, so only the triangles the cell
 * mask draws are measured (tp_node_mask_from_q): each lies in set lattice cells, which are the
 * children's whole level n-1 cells, where S_n exists and the children's delta[n-1] (measured
 * the same way) holds, so the sum holds for every triangle drawn. Every
 * bound is clamped to the area range (area_qmax - area_qmin). With err_unit_steps from
 * tp_tree_err_unit_steps of the global range, that range fits 65534 units, so TP_NODE_ERR_SAT
 * is never stored then (it can be only when the global range exceeds 65534 steps). */
void tp_node_meta_compute(int n, int scale, const int32_t* q, const uint16_t* mask,
                          const tp_node_meta* const children[4], double err_unit_steps,
                          tp_node_meta* out)
{
    assert(n >= 1 && n <= TP_MAX_N && scale >= 0 && scale < TP_TREE_MAX_SCALES && q && out);
    assert(scale == 0 || (children && children[0] && children[1] && children[2] && children[3]));
    assert(mask);
    assert(err_unit_steps > 0);
    int side = (1 << n) + 1;
    tp_node_meta m;
    memset(&m, 0, sizeof m);
    int32_t lo = INT32_MAX, hi = INT32_MIN;
    int all = 1;
    for (int i = 0; i < side * side; i++) {
        int32_t v = q[i];
        if (v == INT32_MIN) {
            all = 0;
            continue;
        }
        lo = v < lo ? v : lo;
        hi = v > hi ? v : hi;
    }
    int own = lo <= hi;
    m.qmin = own ? lo : 0;
    m.qmax = own ? hi : -1;
    if (scale == 0) {
        m.area_qmin = m.qmin;
        m.area_qmax = m.qmax;
        m.flags = (uint8_t)((all ? TP_NODE_COMPLETE : 0) | (own ? TP_NODE_HAS_DRAWN : 0));
    } else {
        int32_t alo = INT32_MAX, ahi = INT32_MIN;
        int complete = 1, any = 0;
        for (int c = 0; c < 4; c++) {
            const tp_node_meta* ch = children[c];
            complete &= (ch->flags & TP_NODE_COMPLETE) != 0;
            if (!(ch->flags & TP_NODE_HAS_DRAWN))
                continue;
            any = 1;
            alo = ch->area_qmin < alo ? ch->area_qmin : alo;
            ahi = ch->area_qmax > ahi ? ch->area_qmax : ahi;
        }
        m.area_qmin = any ? alo : 0;
        m.area_qmax = any ? ahi : -1;
        m.flags = (uint8_t)((complete ? TP_NODE_COMPLETE : 0) | (any ? TP_NODE_HAS_DRAWN : 0));
    }
    if (!(m.flags & TP_NODE_HAS_DRAWN)) { /* nothing drawn: no error anywhere */
        *out = m;
        return;
    }
    unsigned range = tp__err_units((double)m.area_qmax - m.area_qmin, err_unit_steps);
    unsigned carry = 0;
    if (scale > 0)
        for (int c = 0; c < 4; c++) {
            unsigned d = children[c]->delta[n - 1];
            carry = d > carry ? d : carry;
        }
    /* A complete node's mask is all set: the vertex rule draws the same triangles, faster. */
    const uint16_t* mk = (m.flags & TP_NODE_COMPLETE) ? NULL : mask;
    for (int k = 0; k <= n; k++) {
        unsigned own_units =
            k < n || scale == 0
                ? tp__err_units(tp__lattice_level_error(n, q, mk, k), err_unit_steps)
                : 0;
        m.delta[k] = add_units(own_units, carry, range);
    }
    double eps[4][TP_MAX_N];
    tp__lattice_eps(n, q, mk, scale > 0, eps);
    for (int s = 0; s < 4; s++)
        for (int kn = 0; kn < n; kn++)
            /* Interpolation at moved vertices is not exact: round up generously. */
            m.eps[s][kn] = add_units(tp__err_units(eps[s][kn] + 1e-6, err_unit_steps), carry, range);
    *out = m;
}

double tp_node_error_bound(const tp_node_meta* m, int n, int k, const int neighbor_levels[4],
                           double step_m, double err_unit_steps)
{
    assert(m && n >= 1 && n <= TP_MAX_N && k >= 0 && k <= n);
    (void)n; /* only asserted */
    unsigned units = m->delta[k];
    for (int s = 0; neighbor_levels && s < 4; s++) {
        int kn = neighbor_levels[s];
        if (kn >= 0 && kn < k) {
            unsigned e = m->eps[s][kn];
            units = e > units ? e : units;
        }
    }
    double range = m->area_qmax >= m->area_qmin ? (double)m->area_qmax - m->area_qmin : 0;
    /* A saturated entry falls back to the area range, which bounds any error. */
    double steps = units >= TP_NODE_ERR_SAT ? range : units * err_unit_steps;
    return (steps < range ? steps : range) * step_m;
}
