/* cut_draw.c - what the stitched cut draws (cut_stitch.c made its nodes stitchable): each drawn
 * node's vertex data and triangles after crack removal, their counts and the cut's statistics,
 * the heights of the drawn surface, and its screen error.
 */
#include "cut_int.h"

#include <string.h>

/* ---- the drawn geometry of one node ---- */

typedef struct node_view {
    const tp_cut* c;
    const uint16_t* q;      /* its samples */
    const uint16_t* filled; /* its filled bits, NULL when it has none */
    int32_t qmin;
    int64_t x0, y0;  /* grid position of sample (0, 0) */
    int s, k, shift; /* scale, level, n - k */
    int nb[4];
    tp__node_draw draw;
} node_view;

void tp__cut_node_draw(const tp_cut* c, size_t i, tp__node_draw* d)
{
    const tp_cut_node* o = &c->out[i];
    int s, cc, rr;
    tp_tree_node_locate(&c->g, o->node, &s, &cc, &rr);
    const uint16_t* q = tp_tree_samples(c->t, o->node);
    assert(q); /* drawn nodes are resident until the next update */
    int side = (1 << c->n) + 1;
    int vertex_rule =
        (tp_tree_meta(c->t, o->node)->flags & TP_NODE_COMPLETE) || (s == 0 && o->level == c->n);
    d->mask = vertex_rule ? NULL : q + (size_t)side * side;
    d->n = c->n, d->s = s;
    d->x0 = (int64_t)cc << (c->n + s);
    d->y0 = (int64_t)rr << (c->n + s);
}

int tp__tri_drawn(const tp__node_draw* d, const int32_t pos[3][2], int vertices_drawn)
{
    if (!d->mask)
        return vertices_drawn;
    int32_t b[4];
    tp__tri_box(pos, b);
    /* positions lie on the node's lattice: 2^s grid samples per lattice cell */
    return tp_node_mask_all(d->mask, d->n, (int)((b[0] - d->x0) >> d->s),
                            (int)((b[1] - d->y0) >> d->s), (int)((b[2] - d->x0) >> d->s),
                            (int)((b[3] - d->y0) >> d->s));
}

static void node_view_init(const tp_cut* c, size_t i, node_view* nv)
{
    const tp_cut_node* o = &c->out[i];
    int s, cc, rr;
    tp_tree_node_locate(&c->g, o->node, &s, &cc, &rr);
    nv->c = c;
    nv->q = tp_tree_samples(c->t, o->node);
    assert(nv->q); /* drawn nodes are resident until the next update */
    const tp_node_meta* m = tp_tree_meta(c->t, o->node);
    nv->qmin = m->qmin;
    size_t side = ((size_t)1 << c->n) + 1;
    nv->filled =
        (m->flags & TP_NODE_HAS_FILLED) ? nv->q + side * side + tp_node_mask_words(c->n) : NULL;
    nv->x0 = (int64_t)cc << (c->n + s);
    nv->y0 = (int64_t)rr << (c->n + s);
    nv->s = s;
    nv->k = o->level;
    nv->shift = c->n - o->level;
    for (int side = 0; side < 4; side++)
        nv->nb[side] = o->nb[side];
    tp__cut_node_draw(c, i, &nv->draw);
}

/* Vertex (i, j) after crack removal: grid position, global quantised height (INT32_MIN when
 * none) and whether the ORIGINAL vertex is drawn; *filled (when not NULL): the filled bit of
 * the sample the vertex stands on (after the move: the one whose height it takes). */
static int node_vertex_f(const node_view* nv, int i, int j, int32_t* gx, int32_t* gy, int32_t* q,
                         int* filled)
{
    int mi, mj, v = (1 << nv->c->n) + 1;
    tp__lattice_vertex(nv->k, nv->nb, i, j, &mi, &mj);
    *gx = (int32_t)(nv->x0 + ((int64_t)mi << (nv->shift + nv->s)));
    *gy = (int32_t)(nv->y0 + ((int64_t)mj << (nv->shift + nv->s)));
    size_t at = (size_t)(mj << nv->shift) * v + (size_t)(mi << nv->shift);
    uint16_t st = nv->q[at];
    if (filled)
        *filled = nv->filled ? nv->filled[at >> 4] >> (at & 15) & 1 : 0;
    *q = st == TP_TREE_NO_HEIGHT ? INT32_MIN : (int32_t)st + nv->qmin;
    return nv->q[(size_t)(j << nv->shift) * v + (size_t)(i << nv->shift)] != TP_TREE_NO_HEIGHT;
}

static int node_vertex(const node_view* nv, int i, int j, int32_t* gx, int32_t* gy, int32_t* q)
{
    return node_vertex_f(nv, i, j, gx, gy, q, NULL);
}

size_t tp_cut_vertex_count(const tp_cut* c, size_t i)
{
    assert(c && i < c->out_count);
    if (c->out_tin[i])
        return c->out_tin[i]->vertex_count;
    size_t v = ((size_t)1 << c->out[i].level) + 1;
    return v * v;
}

void tp_cut_vertices(const tp_cut* c, size_t i, tp_vertex* vertices, size_t vertex_capacity)
{
    assert(c && i < c->out_count);
    if (c->out_tin[i]) {
        assert(vertex_capacity >= c->out_tin[i]->vertex_count);
        tp__cut_tin_view tv;
        tp__cut_tin_view_init(c, i, &tv);
        tp__cut_tin_vertices(c, &tv, vertices);
        return;
    }
    tp_cut_vertices_at_level(c, i, c->out[i].level, vertices, vertex_capacity);
}

void tp_cut_vertices_at_level(const tp_cut* c, size_t i, int m, tp_vertex* vertices,
                              size_t vertex_capacity)
{
    assert(c && i < c->out_count && vertices && m >= c->out[i].level && m <= c->n);
    node_view nv;
    node_view_init(c, i, &nv);
    /* the moved sides' kn are absolute levels: on the level-m lattice they snap the node's own
       level-k vertices exactly where tp__lattice_vertex snaps them at level k */
    nv.k = m;
    nv.shift = c->n - m;
    int v = (1 << nv.k) + 1;
    assert(vertex_capacity >= (size_t)v * v);
    (void)vertex_capacity;
    for (int j = 0; j < v; j++)
        for (int ii = 0; ii < v; ii++) {
            tp_vertex* o = &vertices[j * v + ii];
            int32_t q;
            int filled;
            int drawn = node_vertex_f(&nv, ii, j, &o->x, &o->y, &q, &filled);
            o->z_m = q == INT32_MIN ? NAN : (float)(q * c->step);
            if (drawn)
                o->cls = filled ? TP_SAMPLE_FILLED : TP_SAMPLE_VALID;
            else {
                int64_t ox = nv.x0 + ((int64_t)ii << (nv.shift + nv.s));
                int64_t oy = nv.y0 + ((int64_t)j << (nv.shift + nv.s));
                o->cls = ox >= c->g.src_width || oy >= c->g.src_height ? TP_SAMPLE_PADDING
                                                                       : TP_SAMPLE_NODATA;
            }
        }
}

/* Triangle h (0, 1) of cell (cx, cy) as drawn: 0 if it is not (tp__tri_drawn, zero area). */
static int cell_triangle(const node_view* nv, int cx, int cy, int h, int32_t pos[3][2], double q[3])
{
    static const int tri[2][3][2] = {{{0, 0}, {0, 1}, {1, 0}}, {{1, 0}, {0, 1}, {1, 1}}};
    int ok = 1;
    for (int v = 0; v < 3; v++) {
        int32_t qq;
        ok &= node_vertex(nv, cx + tri[h][v][0], cy + tri[h][v][1], &pos[v][0], &pos[v][1], &qq);
        ok &= qq != INT32_MIN;
        q[v] = qq;
    }
    int64_t area = (int64_t)(pos[1][0] - pos[0][0]) * (pos[2][1] - pos[0][1]) -
                   (int64_t)(pos[1][1] - pos[0][1]) * (pos[2][0] - pos[0][0]);
    return area != 0 && tp__tri_drawn(&nv->draw, pos, ok);
}

/* Whether lattice triangle h of cell (cx, cy) at level k keeps an area after stitching. */
static int lattice_triangle(int k, const int nb[4], int cx, int cy, int h)
{
    static const int tri[2][3][2] = {{{0, 0}, {0, 1}, {1, 0}}, {{1, 0}, {0, 1}, {1, 1}}};
    int p[3][2];
    for (int v = 0; v < 3; v++)
        tp__lattice_vertex(k, nb, cx + tri[h][v][0], cy + tri[h][v][1], &p[v][0], &p[v][1]);
    return (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[1][1] - p[0][1]) * (p[2][0] - p[0][0]) !=
           0;
}

/* Only side vertices move (tp__lattice_vertex), so every cell off the border keeps both its
 * triangles: counting the border ring once per (k, nb) makes a node's count O(1) afterwards. */
int32_t tp__cut_complete_triangles(tp_cut* c, int k, const int nb[4])
{
    assert(k >= 0 && k <= c->n);
    size_t at = 0, w = (size_t)k + 1;
    for (int l = 0; l < k; l++)
        at += (size_t)(l + 1) * (l + 1) * (l + 1) * (l + 1);
    int m[4];
    size_t idx = 0;
    for (int side = 0; side < 4; side++) {
        m[side] =
            nb[side] >= 0 && nb[side] < k ? nb[side] : TP_NO_NEIGHBOR; /* others move nothing */
        idx = idx * w + (size_t)(m[side] + 1);
    }
    at += idx;
    int32_t* e = &c->tri_memo[at];
    if (*e >= 0)
        return *e;
    int last = 1 << k;
    int32_t count = last > 2 ? 2 * (last - 2) * (last - 2) : 0;
    for (int cy = 0; cy < last; cy++)
        for (int cx = 0; cx < last; cx++) {
            if (cy > 0 && cy < last - 1 && cx > 0 && cx < last - 1)
                continue; /* inside: counted above */
            count += lattice_triangle(k, m, cx, cy, 0) + lattice_triangle(k, m, cx, cy, 1);
        }
    return *e = count;
}

/* Triangles of drawn output node o (incomplete): every cell's, by cell_triangle's rule. */
static int32_t incomplete_triangles(tp_cut* c, size_t o)
{
    node_view nv;
    node_view_init(c, o, &nv);
    int last = 1 << nv.k;
    int32_t count = 0;
    for (int cy = 0; cy < last; cy++)
        for (int cx = 0; cx < last; cx++)
            for (int h = 0; h < 2; h++) {
                int32_t pos[3][2];
                double q[3];
                count += cell_triangle(&nv, cx, cy, h, pos, q);
            }
    return count;
}

typedef struct keep_ctx {
    const tp__node_draw* d;
} keep_ctx;

static int keep_tri(const tp_vertex* a, const tp_vertex* b, const tp_vertex* c, void* user)
{
    const keep_ctx* k = user;
    const tp_vertex* v[3] = {a, b, c};
    int32_t pos[3][2];
    int ok = 1;
    for (int i = 0; i < 3; i++) {
        pos[i][0] = v[i]->x, pos[i][1] = v[i]->y;
        ok &= (v[i]->cls == TP_SAMPLE_VALID || v[i]->cls == TP_SAMPLE_FILLED) && !isnan(v[i]->z_m);
    }
    return tp__tri_drawn(k->d, pos, ok);
}

size_t tp_cut_triangles(const tp_cut* c, size_t i, const tp_vertex* vertices, uint32_t* triangles,
                        size_t triangle_capacity)
{
    assert(c && i < c->out_count && vertices);
    if (c->out_tin[i]) {
        tp__cut_tin_view tv;
        tp__cut_tin_view_init(c, i, &tv);
        return tp__cut_tin_triangles(c, &tv, triangles, triangle_capacity);
    }
    tp__node_draw d;
    tp__cut_node_draw(c, i, &d);
    keep_ctx k = {&d};
    return tp__strip_triangles(vertices, c->out[i].level, keep_tri, &k, triangles,
                               triangle_capacity);
}

int32_t tp__cut_triangles(tp_cut* c, int i, const int nb[4])
{
    const tp__cut_rec* r = &c->rec[i];
    if (tp_tree_meta(c->t, r->node)->flags & TP_NODE_COMPLETE)
        return tp__cut_complete_triangles(c, r->level, nb);
    int32_t key = r->level;
    for (int side = 0; side < 4; side++)
        key = key * 16 + (nb[side] + 1); /* levels 0..TP_MAX_N fit 4 bits */
    tp__cut_tris* e = &c->tri_cache[(uint64_t)r->node % TP__CUT_TRIS_CACHE];
    if (e->node != r->node || e->nb != key)
        *e = (tp__cut_tris){r->node, key, incomplete_triangles(c, (size_t)r->out)};
    return e->tris;
}

void tp_cut_get_stats(const tp_cut* c, tp_cut_stats* out)
{
    assert(c && out);
    memset(out, 0, sizeof *out);
    out->visited = c->visited;
    out->requests = (int)c->req_count;
    out->tin_requests = (int)c->tin_req_count;
    int sph_decided = 0;
    if (c->sph_on)
        tp__spheres_stats(c, &out->sphere_visited, &sph_decided, &out->sphere_nodes);
    out->decisions = c->decisions + sph_decided;
    for (size_t i = 0; i < c->rec_count; i++) {
        const tp__cut_rec* r = &c->rec[i];
        out->culled += r->state == TP__CUT_CULLED;
        if (r->state != TP__CUT_DRAWN || r->out < 0) /* r->out < 0: tp_cut_update_requests */
            continue;
        const tp_cut_node* o = &c->out[r->out];
        out->drawn++;
        out->nodes_per_scale[r->s]++;
        out->substituted += o->substituted;
        out->tin_nodes += o->tin >= 0;
        out->near_plane_nodes += o->near_plane;
        if (o->bound_px > out->max_bound_px)
            out->max_bound_px = o->bound_px;
        if (o->substituted && o->bound_px > out->substitution_bound_px)
            out->substitution_bound_px = o->bound_px;
        out->triangles += (size_t)r->tris;
        for (int side = 0; side < 4; side++) {
            out->add_sides += o->add[side] != TP_NO_NEIGHBOR;
            out->moved_sides += o->nb[side] != TP_NO_NEIGHBOR && o->nb[side] < o->level;
        }
    }
}

/* ---- heights of the drawn surface ---- */

/* Height (steps) at (x, y) of triangle h of cell (cx, cy), if the triangle contains it. */
static int cell_height(const node_view* nv, int cx, int cy, double x, double y, double* z)
{
    for (int h = 0; h < 2; h++) {
        int32_t pos[3][2];
        double q[3];
        if (!cell_triangle(nv, cx, cy, h, pos, q))
            continue;
        double area = (double)(pos[1][0] - pos[0][0]) * (pos[2][1] - pos[0][1]) -
                      (double)(pos[1][1] - pos[0][1]) * (pos[2][0] - pos[0][0]);
        if (tp__tri_height(pos, q, area, x, y, z))
            return 1;
    }
    return 0;
}

static double node_drawn_height(const node_view* nv, double x, double y)
{
    int last = 1 << nv->k;
    double cell = (double)((int64_t)1 << (nv->shift + nv->s));
    double lx = (x - nv->x0) / cell, ly = (y - nv->y0) / cell;
    int cx = (int)lx < last ? (int)lx : last - 1, cy = (int)ly < last ? (int)ly : last - 1;
    double z;
    for (int dy = 0; dy <= (ly == cy && cy > 0); dy++)
        for (int dx = 0; dx <= (lx == cx && cx > 0); dx++)
            if (cell_height(nv, cx - dx, cy - dy, x, y, &z))
                return z;
    /* In a stitched border strip moved vertices shift the triangles along the side. */
    for (int side = 0; side < 4; side++) {
        if (nv->nb[side] < 0 || nv->nb[side] >= nv->k)
            continue;
        for (int i = 0; i < last; i++) {
            int ccx = side == TP_SIDE_LEFT ? 0 : side == TP_SIDE_RIGHT ? last - 1 : i;
            int ccy = side == TP_SIDE_TOP ? 0 : side == TP_SIDE_BOTTOM ? last - 1 : i;
            if (cell_height(nv, ccx, ccy, x, y, &z))
                return z;
        }
    }
    return NAN;
}

/* Index in the output of the drawn node covering leaf (lc, lr), or -1. */
int tp__cut_drawn_at_leaf(const tp_cut* c, int lc, int lr)
{
    for (int s = 0; s < c->g.scales; s++, lc >>= 1, lr >>= 1) {
        if (lc >= c->g.node_cols[s] || lr >= c->g.node_rows[s])
            return -1;
        int j = tp__cut_find(c, tp_tree_node_id(&c->g, s, lc, lr));
        if (j < 0 || c->rec[j].state == TP__CUT_REMOVED)
            continue;
        return c->rec[j].state == TP__CUT_DRAWN ? c->rec[j].out : -1;
    }
    return -1;
}

int tp__cut_sample_node(const tp_cut* c, double x, double y, double* z_steps, int leaf[2])
{
    if (!(x >= 0 && y >= 0 && x <= c->g.width - 1 && y <= c->g.height - 1))
        return -1;
    int span = 1 << c->n;
    int lc = (int)x >> c->n, lr = (int)y >> c->n;
    lc = lc < c->g.cols ? lc : c->g.cols - 1;
    lr = lr < c->g.rows ? lr : c->g.rows - 1;
    int bx = lc > 0 && x == (double)lc * span, by = lr > 0 && y == (double)lr * span;
    for (int dy = 0; dy <= by; dy++)
        for (int dx = 0; dx <= bx; dx++) {
            int o = tp__cut_drawn_at_leaf(c, lc - dx, lr - dy);
            if (o < 0)
                continue;
            double z = NAN;
            if (c->out_tin[o]) {
                if (!tp__cut_tin_height(c, (size_t)o, x, y, &z))
                    z = NAN;
            } else {
                node_view nv;
                node_view_init(c, (size_t)o, &nv);
                z = node_drawn_height(&nv, x, y);
            }
            if (!isnan(z)) {
                if (z_steps)
                    *z_steps = z;
                if (leaf)
                    leaf[0] = lc - dx, leaf[1] = lr - dy;
                return o;
            }
        }
    return -1;
}

double tp_cut_drawn_height_at(const tp_cut* c, double x, double y)
{
    assert(c);
    double z;
    return tp__cut_sample_node(c, x, y, &z, NULL) >= 0 ? z * c->step : NAN;
}

/* ---- the triangles drawn, one at a time (the screen error: cut_measure.c) ---- */

int tp__cut_node_tris(const tp_cut* c, size_t i, tp__cut_tri_fn fn, void* user)
{
    assert(c && i < c->out_count && fn);
    const int8_t* add = c->out[i].add;
    if (add[0] != TP_NO_NEIGHBOR || add[1] != TP_NO_NEIGHBOR || add[2] != TP_NO_NEIGHBOR ||
        add[3] != TP_NO_NEIGHBOR)
        return tp__cut_add_tris(c, i, fn, user);
    if (c->out_tin[i]) {
        tp__cut_tin_tris(c, i, fn, user);
        return 1;
    }
    node_view nv;
    node_view_init(c, i, &nv);
    int last = 1 << nv.k;
    for (int cy = 0; cy < last; cy++)
        for (int cx = 0; cx < last; cx++)
            for (int h = 0; h < 2; h++) {
                int32_t pos[3][2];
                double q[3];
                if (cell_triangle(&nv, cx, cy, h, pos, q))
                    fn((const int32_t(*)[2])pos, q, user);
            }
    return 1;
}
