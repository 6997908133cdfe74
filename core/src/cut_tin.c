/* cut_tin.c - drawn nodes that draw a TIN instead of their lattice (tp_cut_set_tins; issue 32
 * item 2): which rung each draws, and its geometry after crack removal for the cut's drawing,
 * queries and measure (cut_draw.c, cut_query.c, cut_measure.c call in here for such nodes).
 *
 * A rung's outline vertices are its level's lattice side vertices, moved by tp__lattice_vertex
 * exactly as the lattice's; its other vertices never move. Triangles its crack removal
 * collapses (two vertices snapped together) are not drawn; tin_node.c refused (INFINITY) every
 * neighbour level that would turn one over or flatten it onto three distinct points.
 */
#include "cut_int.h"

#include <string.h>

void tp_cut_set_tins(tp_cut* c, const tp_tin_cache* tins)
{
    assert(c);
    c->tins = tins;
}

const tp_cut_tin_request* tp_cut_tin_requests(const tp_cut* c, size_t* count)
{
    assert(c && count);
    *count = c->tin_req_count;
    return c->tin_req;
}

/* Rung r's vertex v of drawn node i: grid position and global quantised height. */
static void rung_vertex(const tp_cut* c, const tp__cut_tin_view* tv, uint32_t v, int32_t* gx,
                        int32_t* gy, int32_t* q, size_t* at)
{
    const tp_node_tin* r = tv->rung;
    int i = r->ij[2 * v], j = r->ij[2 * v + 1];
    int st = 1 << (c->n - r->level);
    if (i % st == 0 && j % st == 0) { /* on the level's lattice: its outline may move */
        int mi, mj;
        tp__lattice_vertex(r->level, tv->nb, i / st, j / st, &mi, &mj);
        i = mi * st, j = mj * st;
    }
    *gx = (int32_t)(tv->x0 + ((int64_t)i << tv->s));
    *gy = (int32_t)(tv->y0 + ((int64_t)j << tv->s));
    *at = (size_t)j * (size_t)((1 << c->n) + 1) + (size_t)i;
    *q = (int32_t)tv->q[*at] + tv->qmin; /* complete: every sample drawn */
}

void tp__cut_tin_view_init(const tp_cut* c, size_t i, tp__cut_tin_view* tv)
{
    const tp_cut_node* o = &c->out[i];
    int s, cc, rr;
    tp_tree_node_locate(&c->g, o->node, &s, &cc, &rr);
    tv->rung = c->out_tin[i];
    tv->q = tp_tree_samples(c->t, o->node);
    const tp_node_meta* m = tp_tree_meta(c->t, o->node);
    tv->qmin = m->qmin;
    size_t side = ((size_t)1 << c->n) + 1;
    tv->filled =
        (m->flags & TP_NODE_HAS_FILLED) ? tv->q + side * side + tp_node_mask_words(c->n) : NULL;
    tv->s = s;
    tv->x0 = (int64_t)cc << (c->n + s);
    tv->y0 = (int64_t)rr << (c->n + s);
    for (int sd = 0; sd < 4; sd++)
        tv->nb[sd] = o->nb[sd];
}

/* Calls fn for each triangle of rung tv->rung as drawn (collapsed ones left out); stops and
 * returns 0 when fn returns 0. */
typedef int (*rung_tri_fn)(const int32_t pos[3][2], const int32_t q[3], const uint16_t idx[3],
                           void* user);
static int each_triangle(const tp_cut* c, const tp__cut_tin_view* tv, rung_tri_fn fn, void* user)
{
    const tp_node_tin* r = tv->rung;
    for (uint32_t t = 0; t < r->triangle_count; t++) {
        int32_t pos[3][2], q[3];
        const uint16_t* idx = r->triangles + 3 * (size_t)t;
        for (int v = 0; v < 3; v++) {
            size_t at;
            rung_vertex(c, tv, idx[v], &pos[v][0], &pos[v][1], &q[v], &at);
        }
        int64_t o = ((int64_t)pos[1][0] - pos[0][0]) * ((int64_t)pos[2][1] - pos[0][1]) -
                    ((int64_t)pos[1][1] - pos[0][1]) * ((int64_t)pos[2][0] - pos[0][0]);
        if (o == 0)
            continue; /* collapsed by crack removal */
        if (!fn((const int32_t(*)[2])pos, q, idx, user))
            return 0;
    }
    return 1;
}

int32_t tp__cut_pick_tin(tp_cut* c, int ri, const int nb[4])
{
    tp__cut_rec* r = &c->rec[ri];
    c->out_tin[r->out] = NULL;
    c->out[r->out].tin = -1;
    /* an installed cut (tp_cut_set_nodes) has no view to bound: its coarsest rung that
     * stitches with its neighbours (what the adversarial tests of the outline draw) */
    int installed = !c->have_view;
    if (!c->tins || c->stitch_add || (!installed && c->lp.mode != TP_LOD_ERROR))
        return -1;
    const tp_node_meta* m = tp_tree_meta(c->t, r->node);
    if (!(m->flags & TP_NODE_COMPLETE) || r->level < 1)
        return -1;
    int built, count;
    const tp_node_tins* tins = tp_tin_cache_get(c->tins, r->node, r->level, &built);
    if (!built) {
        if (tp__cut_grow(c, (void**)&c->tin_req, &c->tin_req_cap, c->tin_req_count + 1,
                         sizeof *c->tin_req) &&
            tp__cut_grow(c, (void**)&c->tin_prio, &c->tin_prio_cap, c->tin_req_count + 1,
                         sizeof *c->tin_prio)) {
            c->tin_prio[c->tin_req_count] = r->bound_px;
            c->tin_req[c->tin_req_count++] = (tp_cut_tin_request){r->node, r->level};
        }
        return -1;
    }
    const tp_node_tin* rungs = tp_node_tins_level(tins, r->level, &count);
    int8_t nb8[4] = {(int8_t)nb[0], (int8_t)nb[1], (int8_t)nb[2], (int8_t)nb[3]};
    double allow = fmax(c->lp.tau_px, r->bound_px);
    for (int j = 0; j < count; j++) {
        double steps = tp_node_tin_bound_steps(&rungs[j], nb8);
        if (!isfinite(steps))
            continue;
        double d = (steps * c->step + c->quant) * c->zscale, px = 0; /* carry included */
        int near = 0;
        if (!installed && (px = tp__projected_px_drawn(&c->v, &r->pb, d, &near)) > allow)
            continue;
        c->out_tin[r->out] = &rungs[j];
        tp_cut_node* o = &c->out[r->out];
        o->tin = (int8_t)j;
        o->bound_px = r->bound_px = (float)px;
        o->near_plane = (uint8_t)near;
        r->bound_m = d;
        int moves = 0;
        for (int s = 0; s < 4; s++)
            moves |= nb[s] >= 0 && nb[s] < r->level;
        if (!moves) /* nothing collapses: no walk over its triangles on every update */
            return (int32_t)rungs[j].triangle_count;
        tp__cut_tin_view tv;
        tp__cut_tin_view_init(c, (size_t)r->out, &tv);
        return (int32_t)tp__cut_tin_triangles(c, &tv, NULL, 0);
    }
    return -1;
}

void tp__cut_tin_sort_requests(tp_cut* c)
{
    /* insertion sort by decreasing projected bound: a few dozen per update */
    for (size_t i = 1; i < c->tin_req_count; i++) {
        tp_cut_tin_request q = c->tin_req[i];
        float p = c->tin_prio[i];
        size_t j = i;
        for (; j > 0 && c->tin_prio[j - 1] < p; j--) {
            c->tin_req[j] = c->tin_req[j - 1];
            c->tin_prio[j] = c->tin_prio[j - 1];
        }
        c->tin_req[j] = q;
        c->tin_prio[j] = p;
    }
}

void tp__cut_tin_vertices(const tp_cut* c, const tp__cut_tin_view* tv, tp_vertex* out)
{
    const tp_node_tin* r = tv->rung;
    for (uint32_t v = 0; v < r->vertex_count; v++) {
        int32_t q;
        size_t at;
        rung_vertex(c, tv, v, &out[v].x, &out[v].y, &q, &at);
        out[v].z_m = (float)(q * c->step);
        int filled = tv->filled ? tv->filled[at >> 4] >> (at & 15) & 1 : 0;
        out[v].cls = filled ? TP_SAMPLE_FILLED : TP_SAMPLE_VALID;
    }
}

typedef struct tri_out {
    uint32_t* tris;
    size_t cap, count;
} tri_out;

static int put_tri(const int32_t pos[3][2], const int32_t q[3], const uint16_t idx[3], void* user)
{
    (void)pos, (void)q;
    tri_out* t = user;
    if (t->count < t->cap)
        for (int v = 0; v < 3; v++)
            t->tris[3 * t->count + v] = idx[v];
    t->count++;
    return 1;
}

size_t tp__cut_tin_triangles(const tp_cut* c, const tp__cut_tin_view* tv, uint32_t* tris,
                             size_t cap)
{
    tri_out t = {tris, cap, 0};
    each_triangle(c, tv, put_tri, &t);
    return t.count;
}

typedef struct tri_cb {
    tp__cut_tri_fn fn;
    void* user;
} tri_cb;

static int pass_tri(const int32_t pos[3][2], const int32_t q[3], const uint16_t idx[3], void* user)
{
    (void)idx;
    const tri_cb* cb = user;
    double qd[3] = {q[0], q[1], q[2]};
    cb->fn(pos, qd, cb->user);
    return 1;
}

void tp__cut_tin_tris(const tp_cut* c, size_t i, tp__cut_tri_fn fn, void* user)
{
    tp__cut_tin_view tv;
    tp__cut_tin_view_init(c, i, &tv);
    tri_cb cb = {fn, user};
    each_triangle(c, &tv, pass_tri, &cb);
}

typedef struct height_at {
    double x, y, z;
    int found;
} height_at;

static int height_tri(const int32_t pos[3][2], const int32_t q[3], const uint16_t idx[3],
                      void* user)
{
    (void)idx;
    height_at* h = user;
    double qd[3] = {q[0], q[1], q[2]};
    double area = (double)(pos[1][0] - pos[0][0]) * (pos[2][1] - pos[0][1]) -
                  (double)(pos[1][1] - pos[0][1]) * (pos[2][0] - pos[0][0]);
    h->found = tp__tri_height(pos, qd, area, h->x, h->y, &h->z);
    return !h->found;
}

int tp__cut_tin_height(const tp_cut* c, size_t i, double x, double y, double* z_steps)
{
    tp__cut_tin_view tv;
    tp__cut_tin_view_init(c, i, &tv);
    height_at h = {x, y, NAN, 0};
    each_triangle(c, &tv, height_tri, &h);
    if (h.found)
        *z_steps = h.z;
    return h.found;
}
