/* tree.c - the hierarchy's geometry (node ids, parents, children, roots) and the tree at run
 * time: every node's meta, and the samples of the resident nodes (attached by the caller).
 *
 * Ids run from the top scale down, row-major within a scale, so the coarsest nodes come first
 * and a scale's nodes are one contiguous range.
 */
#include "tree_int.h"
#include "tp_terrain.h" /* tp_slope3 */

#include <string.h>

static int patch_n(int patch_size)
{
    for (int n = 4; n <= TP_MAX_N; n++)
        if (patch_size == (1 << n) + 1)
            return n;
    return -1;
}

tp_status tp_tree_geometry_init(int src_width, int src_height, int patch_size,
                                tp_tree_geometry* out, tp_error* err)
{
    assert(out);
    if (src_width < 1 || src_height < 1 || src_width > (1 << 30) || src_height > (1 << 30))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree: expected a grid of 1 to 2^30 samples per side, got %dx%d",
                        src_width, src_height);
    int n = patch_n(patch_size);
    if (n < 0)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree: expected a patch size of 17, 33, 65, 129 or 257, got %d",
                        patch_size);
    tp_tree_geometry g;
    memset(&g, 0, sizeof g);
    int ps = 1 << n;
    g.n = n;
    g.src_width = src_width;
    g.src_height = src_height;
    /* ceil((src - 1) / 2^n), at least 1 (TP_FIT_PAD) */
    g.cols = src_width > 1 ? (src_width - 2) / ps + 1 : 1;
    g.rows = src_height > 1 ? (src_height - 2) / ps + 1 : 1;
    if ((int64_t)g.cols * ps + 1 > INT32_MAX || (int64_t)g.rows * ps + 1 > INT32_MAX)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree: the fitted grid of %dx%d samples would exceed 2^31 per side",
                        src_width, src_height);
    g.width = g.cols * ps + 1;
    g.height = g.rows * ps + 1;
    /* Scales above TP_TREE_MAX_SCALES - 1 are not built (their nodes do not exist): it takes
     * a grid of 2^23 leaves per side to reach that. */
    while (g.scales < TP_TREE_MAX_SCALES && (g.cols >> g.scales) >= 1 && (g.rows >> g.scales) >= 1)
        g.scales++;
    for (int s = 0; s < g.scales; s++) {
        g.node_cols[s] = g.cols >> s;
        g.node_rows[s] = g.rows >> s;
    }
    int64_t id = 0;
    for (int s = g.scales - 1; s >= 0; s--) {
        g.first_node[s] = id;
        id += (int64_t)g.node_cols[s] * g.node_rows[s];
    }
    g.node_count = id;
    /* Every node of scale s+1 has exactly 4 children; the rest of scale s are roots. */
    g.root_count = (int64_t)g.node_cols[g.scales - 1] * g.node_rows[g.scales - 1];
    for (int s = 0; s + 1 < g.scales; s++)
        g.root_count += (int64_t)g.node_cols[s] * g.node_rows[s] -
                        4 * (int64_t)g.node_cols[s + 1] * g.node_rows[s + 1];
    *out = g;
    return TP_OK;
}

int64_t tp_tree_node_id(const tp_tree_geometry* g, int s, int c, int r)
{
    assert(g && s >= 0 && s < g->scales && c >= 0 && c < g->node_cols[s] && r >= 0 &&
           r < g->node_rows[s]);
    return g->first_node[s] + (int64_t)r * g->node_cols[s] + c;
}

void tp_tree_node_locate(const tp_tree_geometry* g, int64_t id, int* s, int* c, int* r)
{
    assert(g && s && c && r && id >= 0 && id < g->node_count);
    int sc = g->scales - 1;
    while (sc > 0 && id >= g->first_node[sc - 1]) /* first_node decreases with the scale */
        sc--;
    int64_t local = id - g->first_node[sc];
    *s = sc;
    *c = (int)(local % g->node_cols[sc]);
    *r = (int)(local / g->node_cols[sc]);
}

int64_t tp_tree_node_parent(const tp_tree_geometry* g, int64_t id)
{
    int s, c, r;
    tp_tree_node_locate(g, id, &s, &c, &r);
    if (s + 1 >= g->scales || c / 2 >= g->node_cols[s + 1] || r / 2 >= g->node_rows[s + 1])
        return -1;
    return tp_tree_node_id(g, s + 1, c / 2, r / 2);
}

int64_t tp_tree_node_child(const tp_tree_geometry* g, int64_t id, int q)
{
    assert(q >= 0 && q < 4);
    int s, c, r;
    tp_tree_node_locate(g, id, &s, &c, &r);
    assert(s >= 1);
    return tp_tree_node_id(g, s - 1, 2 * c + (q & 1), 2 * r + (q >> 1));
}

void tp_tree_roots(const tp_tree_geometry* g, int64_t* roots, size_t root_capacity)
{
    assert(g && roots && root_capacity >= (size_t)g->root_count);
    (void)root_capacity; /* only asserted */
    size_t k = 0;
    for (int s = g->scales - 1; s >= 0; s--) {
        /* the children of scale s+1 cover columns < 2 * node_cols[s+1], rows < 2 * node_rows[s+1] */
        int pc = s + 1 < g->scales ? 2 * g->node_cols[s + 1] : 0;
        int pr = s + 1 < g->scales ? 2 * g->node_rows[s + 1] : 0;
        for (int r = 0; r < g->node_rows[s]; r++)
            for (int c = r < pr ? pc : 0; c < g->node_cols[s]; c++)
                roots[k++] = tp_tree_node_id(g, s, c, r);
    }
    assert(k == (size_t)g->root_count);
}

/* ---------------------------------------------------------------------------------------------
 * The tree at run time
 */
tp_status tp_tree_create(const tp_tree_desc* desc, tp_tree** out, tp_error* err)
{
    assert(desc && out);
    const tp_tree_geometry* g = &desc->geometry;
    if (!desc->allocator.alloc != !desc->allocator.free)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree: allocator: expected both alloc and free, or neither");
    if (g->n < 4 || g->n > TP_MAX_N || g->node_count < 1 || g->scales < 1 ||
        g->scales > TP_TREE_MAX_SCALES)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree: geometry not initialised (n %d, %lld nodes)", g->n,
                        (long long)g->node_count);
    if (!desc->metas || desc->meta_count != (size_t)g->node_count)
        return tp__fail(err, TP_ERR_INVALID_ARG, "tree: expected %lld node metas, got %zu",
                        (long long)g->node_count, desc->metas ? desc->meta_count : 0);
    if (!(desc->height_step_m > 0) || !isfinite(desc->height_step_m))
        return tp__fail(err, TP_ERR_INVALID_ARG, "tree: expected a height step > 0, got %g",
                        desc->height_step_m);
    if (!(desc->err_unit_steps > 0) || !isfinite(desc->err_unit_steps))
        return tp__fail(err, TP_ERR_INVALID_ARG, "tree: expected an error unit > 0, got %g",
                        desc->err_unit_steps);
    if (!(desc->quant_max_error_m >= 0))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree: expected a quantisation error >= 0, got %g",
                        desc->quant_max_error_m);
    tp_allocator a = desc->allocator;
    if (!a.alloc) {
        tp_allocator none = {0};
        a = none;
    }
    tp_tree* t = tp__calloc(&a, 1, sizeof *t);
    const uint16_t** samples = tp__calloc(&a, (size_t)g->node_count, sizeof *samples);
    if (!t || !samples) {
        tp__free(&a, t);
        tp__free(&a, samples);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tree: out of memory for %lld nodes",
                        (long long)g->node_count);
    }
    t->desc = *desc;
    t->alloc = a;
    t->samples = samples;
    *out = t;
    return TP_OK;
}

void tp_tree_destroy(tp_tree* t)
{
    if (!t)
        return;
    tp_allocator a = t->alloc;
    tp__free(&a, t->samples);
    tp__free(&a, t->owned_metas);
    tp__free(&a, t->owned_samples);
    tp__free(&a, t);
}

void tp__tree_own(tp_tree* t, tp_node_meta* metas, uint16_t* samples)
{
    assert(t);
    t->owned_metas = metas;
    t->owned_samples = samples;
}

const tp_tree_geometry* tp_tree_get_geometry(const tp_tree* t)
{
    assert(t);
    return &t->desc.geometry;
}

const tp_node_meta* tp_tree_meta(const tp_tree* t, int64_t node)
{
    assert(t && node >= 0 && node < t->desc.geometry.node_count);
    return &t->desc.metas[node];
}

void tp_tree_attach(tp_tree* t, int64_t node, const uint16_t* samples)
{
    assert(t && node >= 0 && node < t->desc.geometry.node_count && samples);
    t->samples[node] = samples;
}

void tp_tree_detach(tp_tree* t, int64_t node)
{
    assert(t && node >= 0 && node < t->desc.geometry.node_count);
    t->samples[node] = NULL;
    t->detaches++;
}

uint64_t tp_tree_detaches(const tp_tree* t)
{
    assert(t);
    return t->detaches;
}

const uint16_t* tp_tree_samples(const tp_tree* t, int64_t node)
{
    assert(t && node >= 0 && node < t->desc.geometry.node_count);
    return t->samples[node];
}

double tp_tree_sample(const tp_tree* t, int x, int y)
{
    assert(t);
    const tp_tree_geometry* g = &t->desc.geometry;
    if (x < 0 || y < 0 || x >= g->width || y >= g->height)
        return NAN;
    int n = g->n, side = (1 << n) + 1;
    /* finest first: scale s holds (x, y) iff both are multiples of 2^s; a position on a node
     * border is held by up to 4 nodes of a scale (the same value in each) */
    for (int s = 0; s < g->scales; s++) {
        if ((x & ((1 << s) - 1)) || (y & ((1 << s) - 1)))
            break;
        int span = n + s;
        int cx = x >> span, cy = y >> span;
        for (int q = 0; q < 4; q++) {
            int c = cx - (q & 1), r = cy - (q >> 1);
            if (c < 0 || r < 0 || c >= g->node_cols[s] || r >= g->node_rows[s])
                continue;
            if ((q & 1) && (x & ((1 << span) - 1)))
                continue; /* not on this node's right border */
            if ((q >> 1) && (y & ((1 << span) - 1)))
                continue;
            int64_t id = tp_tree_node_id(g, s, c, r);
            const uint16_t* smp = t->samples[id];
            if (!smp)
                continue;
            int i = (x - (c << span)) >> s, j = (y - (r << span)) >> s;
            uint16_t v = smp[(size_t)j * side + i];
            if (v == TP_TREE_NO_HEIGHT)
                return NAN;
            return ((double)v + t->desc.metas[id].qmin) * t->desc.height_step_m;
        }
    }
    return NAN;
}

void tp_tree_get_info(const tp_tree* t, tp_tree_info* out)
{
    assert(t && out);
    memset(out, 0, sizeof *out);
    memcpy(out->geotransform, t->desc.geotransform, sizeof out->geotransform);
    out->height_step_m = t->desc.height_step_m;
    out->quant_max_error_m = t->desc.quant_max_error_m;
    out->err_unit_steps = t->desc.err_unit_steps;
    const tp_tree_geometry* g = &t->desc.geometry;
    int32_t lo = INT32_MAX, hi = INT32_MIN;
    for (int64_t id = 0; id < g->node_count; id++) {
        if (tp_tree_node_parent(g, id) >= 0)
            continue; /* roots only; they come first, but not only first (far-edge roots) */
        const tp_node_meta* m = &t->desc.metas[id];
        if (!(m->flags & TP_NODE_HAS_DRAWN))
            continue;
        lo = m->area_qmin < lo ? m->area_qmin : lo;
        hi = m->area_qmax > hi ? m->area_qmax : hi;
    }
    out->min_height_m = lo <= hi ? lo * t->desc.height_step_m : NAN;
    out->max_height_m = lo <= hi ? hi * t->desc.height_step_m : NAN;
}

/* Height (steps) of lattice sample (i, j) of a node, or NAN outside it or where not drawn. */
static double lattice_q(const uint16_t* smp, const tp_node_meta* m, int v, int i, int j)
{
    if (i < 0 || j < 0 || i >= v || j >= v)
        return NAN;
    uint16_t q = smp[(size_t)j * v + i];
    return q == TP_TREE_NO_HEIGHT ? NAN : (double)q + m->qmin;
}

static double lattice_slope(const uint16_t* smp, const tp_node_meta* m, int v, int i, int j,
                            int di, int dj, double spacing)
{
    return tp_slope3(lattice_q(smp, m, v, i - di, j - dj), lattice_q(smp, m, v, i, j),
                     lattice_q(smp, m, v, i + di, j + dj), spacing);
}

/* The last leaf tp_tree_sample would read (x, y) from, kept while the normals of one node's
 * vertices are computed: neighbouring vertices mostly read the same leaf. */
typedef struct leaf_cache {
    int64_t c, r;        /* the leaf's column and row; -1: none yet */
    const uint16_t* smp; /* its samples, NULL when not resident */
    double qmin;
} leaf_cache;

/* tp_tree_sample(t, x, y), from lc's leaf when it holds (x, y) and is resident: every resident
 * node holding a position has the same height there, so the value is the same. */
static double cached_sample(const tp_tree* t, leaf_cache* lc, int x, int y)
{
    const tp_tree_geometry* g = &t->desc.geometry;
    if (x < 0 || y < 0 || x >= g->width || y >= g->height)
        return NAN;
    int n = g->n, side = (1 << n) + 1;
    int64_t c = x >> n, r = y >> n;
    c = c < g->node_cols[0] ? c : g->node_cols[0] - 1; /* the last post of the last leaf */
    r = r < g->node_rows[0] ? r : g->node_rows[0] - 1;
    if (c != lc->c || r != lc->r) {
        int64_t id = tp_tree_node_id(g, 0, (int)c, (int)r);
        lc->c = c, lc->r = r;
        lc->smp = t->samples[id];
        lc->qmin = t->desc.metas[id].qmin;
    }
    if (!lc->smp)
        return tp_tree_sample(t, x, y);
    uint16_t v = lc->smp[(size_t)(y - (r << n)) * side + (size_t)(x - (c << n))];
    return v == TP_TREE_NO_HEIGHT ? NAN : ((double)v + lc->qmin) * t->desc.height_step_m;
}

/* Slope (m/m) along one axis from resident full-resolution samples, central where both
 * neighbours are known, else one-sided; NaN when neither neighbour is (not resident or not
 * drawn). */
static double full_slope(const tp_tree* t, leaf_cache* lc, int x, int y, int dx, int dy,
                         double spacing)
{
    double a = cached_sample(t, lc, x - dx, y - dy), b = cached_sample(t, lc, x + dx, y + dy);
    if (!isnan(a) && !isnan(b))
        return (b - a) / (2 * spacing);
    double c = cached_sample(t, lc, x, y);
    if (!isnan(b) && !isnan(c))
        return (b - c) / spacing;
    if (!isnan(a) && !isnan(c))
        return (c - a) / spacing;
    return NAN;
}

void tp_tree_node_normals(const tp_tree* t, int64_t node, const tp_vertex* vertices, size_t count,
                          float (*normals)[3])
{
    assert(t && (vertices || !count) && (normals || !count));
    const uint16_t* smp = tp_tree_samples(t, node);
    assert(smp);
    const tp_tree_geometry* g = &t->desc.geometry;
    int s, c, r;
    tp_tree_node_locate(g, node, &s, &c, &r);
    int v = (1 << g->n) + 1;
    int64_t x0 = (int64_t)c << (g->n + s), y0 = (int64_t)r << (g->n + s);
    const tp_node_meta* m = &t->desc.metas[node];
    double step = t->desc.height_step_m, stride = (double)((int64_t)1 << s);
    const double* gt = t->desc.geotransform;
    leaf_cache lc = {-1, -1, NULL, 0};
    for (size_t k = 0; k < count; k++) {
        int32_t x = vertices[k].x, y = vertices[k].y;
        int i = (int)((x - x0) >> s), j = (int)((y - y0) >> s);
        assert(i >= 0 && j >= 0 && i < v && j < v);
        /* Full resolution where the leaves around the vertex are resident: the normals of a
         * terrain's grid, the same for every node that has the vertex, so nodes of different
         * scales shade alike across their borders (from each node's own lattice, the borders
         * of coarse nodes showed as squares). Else, far away and not loaded, the node's
         * lattice. */
        double gx = full_slope(t, &lc, x, y, 1, 0, gt[1]);
        double gy = full_slope(t, &lc, x, y, 0, 1, gt[5]);
        if (isnan(gx) || isnan(gy)) {
            /* dz/dE and dz/dN: a lattice step moves stride * gt[1] east, stride * gt[5] north */
            gx = lattice_slope(smp, m, v, i, j, 1, 0, stride * gt[1]) * step;
            gy = lattice_slope(smp, m, v, i, j, 0, 1, stride * gt[5]) * step;
        }
        double len = sqrt(gx * gx + gy * gy + 1);
        normals[k][0] = (float)(-gx / len);
        normals[k][1] = (float)(-gy / len);
        normals[k][2] = (float)(1 / len);
    }
}

void tp_tree_node_normal(const tp_tree* t, int64_t node, int32_t x, int32_t y, float normal[3])
{
    assert(t && normal);
    tp_vertex vx = {x, y, 0, 0};
    tp_tree_node_normals(t, node, &vx, 1, (float(*)[3])normal);
}
