/* cut_measure.c - the screen error of the drawn cut against the full-resolution samples
 * (tp_cut_measure_error in tp_cut.h): node by node, the node's drawn triangles (cut_draw.c,
 * cut_stitch_add.c) rasterised over each of its measured leaves' samples, a leaf from the tree
 * when resident, else through the caller's reader.
 *
 * Each sample once, by the surface tp_cut_drawn_height_at reads there: a leaf (lc, lr) owns the
 * samples lc 2^n <= x < (lc + 1) 2^n (the last leaf column also x = width - 1), likewise in y,
 * and the node drawn over it measures them; a sample on a leaf's border that the owner's node
 * does not draw (a culled or empty neighbour, a void's hole in an incomplete node) is measured
 * by the node of the leaf left, above or above-left that draws it, in that order; a sample two
 * triangles of a node share is counted once.
 *
 * Before issue 32 only resident leaves were measured, and a sample once per triangle holding
 * it: a view from far above holds none of the leaves under its coarse nodes, and those it does
 * hold are leaves the cut itself draws (along a void's edge), so the error came out 0 there.
 */
#include "camera_int.h"
#include "cut_int.h"

#include <string.h>

typedef struct tri {
    int32_t pos[3][2];
    double q[3];
    int32_t box[4]; /* x0, y0, x1, y1 */
} tri;

typedef struct measure {
    const tp_cut* c;
    const tp_cut_measure_options* o;
    tp__view v;
    tp_frustum f;
    tri* tris; /* the node being measured */
    size_t ntris, tris_cap;
    int oom;
    uint16_t* buf; /* a leaf read through o->read_leaf */
    uint8_t* seen; /* the leaf's samples measured already: a sample on an edge two of the
                      node's triangles share is rasterised by both, and counted once */
    /* the leaf being measured: its samples (NULL: not to be had) and offset; the samples it
     * owns end at (x1, y1); past them, on the next leaves' first column and row, those it
     * measures in their place (taken()) */
    const uint16_t* q;
    int32_t qmin;
    int lc, lr;
    int32_t x1, y1;
    int node;           /* the drawn node's output index, its first leaf, leaves a side */
    int node_lc, node_lr, node_w;
    int8_t next[2][2];  /* the leaves right, below, below-right: 1 when they are this node's
                           (measured as its own, or not sampled) or a complete node is drawn
                           over them (it draws every sample of them), else 0 */
    double max, sum;
    tp_cut_error* out;
} measure;

static void add_tri(const int32_t pos[3][2], const double q[3], void* user)
{
    measure* m = user;
    if (m->ntris == m->tris_cap) {
        size_t cap = m->tris_cap ? 2 * m->tris_cap : 512;
        tri* t = tp__alloc(&m->c->alloc, cap, sizeof *t);
        if (!t) {
            m->oom = 1;
            return;
        }
        if (m->ntris)
            memcpy(t, m->tris, m->ntris * sizeof *t);
        tp__free(&m->c->alloc, m->tris);
        m->tris = t;
        m->tris_cap = cap;
    }
    tri* t = &m->tris[m->ntris++];
    memcpy(t->pos, pos, sizeof t->pos);
    memcpy(t->q, q, sizeof t->q);
    t->box[0] = t->box[2] = pos[0][0];
    t->box[1] = t->box[3] = pos[0][1];
    for (int v = 1; v < 3; v++) {
        t->box[0] = pos[v][0] < t->box[0] ? pos[v][0] : t->box[0];
        t->box[1] = pos[v][1] < t->box[1] ? pos[v][1] : t->box[1];
        t->box[2] = pos[v][0] > t->box[2] ? pos[v][0] : t->box[2];
        t->box[3] = pos[v][1] > t->box[3] ? pos[v][1] : t->box[3];
    }
}

/* Whether a sample past the leaf's own (on the first column or row of the leaf after it) is
 * this leaf's to measure: when tp_cut_drawn_height_at takes it from this leaf (not when the
 * leaf holding it is this node's, or under a complete node: those measure it). */
static int taken(const measure* m, int x, int y)
{
    if (m->next[y > m->y1][x > m->x1])
        return 0;
    int leaf[2];
    return tp__cut_sample_node(m->c, x, y, NULL, leaf) == m->node && leaf[0] == m->lc &&
           leaf[1] == m->lr;
}

static void sample(int x, int y, double z, void* user)
{
    measure* m = user;
    const tp_cut* c = m->c;
    if ((x > m->x1 || y > m->y1) && !taken(m, x, y))
        return;
    int v = (1 << c->n) + 1;
    if (!m->q) { /* each sample once here too */
        size_t at = (size_t)(y - (m->lr << c->n)) * v + (size_t)(x - (m->lc << c->n));
        if (!(m->seen[at >> 3] & (1u << (at & 7))))
            m->out->skipped++;
        m->seen[at >> 3] |= (uint8_t)(1u << (at & 7));
        return;
    }
    size_t at = (size_t)(y - (m->lr << c->n)) * v + (size_t)(x - (m->lc << c->n));
    if (m->seen[at >> 3] & (1u << (at & 7)))
        return;
    m->seen[at >> 3] |= (uint8_t)(1u << (at & 7));
    uint16_t st = m->q[at];
    if (st == TP_TREE_NO_HEIGHT)
        return;
    double ws[3], wd[3];
    ws[0] = wd[0] = c->gt[0] + (x + 0.5) * c->gt[1];
    ws[1] = wd[1] = c->gt[3] + (y + 0.5) * c->gt[5];
    ws[2] = ((int32_t)st + m->qmin) * c->step * c->zscale;
    wd[2] = z * c->step * c->zscale;
    double e = tp__screen_error_px(&m->v, ws, wd);
    if (isnan(e))
        return;
    m->max = e > m->max ? e : m->max;
    m->sum += e * e;
    m->out->samples++;
}

/* Whether leaf (lc, lr) has something to measure: a drawn sample, its box in the view. */
static int leaf_in_view(const measure* m, int lc, int lr)
{
    const tp_cut* c = m->c;
    const tp_node_meta* meta = tp_tree_meta(c->t, tp_tree_node_id(&c->g, 0, lc, lr));
    if (!(meta->flags & TP_NODE_HAS_DRAWN))
        return 0;
    double bmin[3], bmax[3];
    tp__cut_node_box(c, 0, lc, lr, meta->area_qmin, meta->area_qmax, bmin, bmax);
    for (int a = 0; a < 3; a++) { /* a millimetre of room: the samples' own test decides */
        bmin[a] -= 1e-3;
        bmax[a] += 1e-3;
    }
    return tp_frustum_test_aabb(&m->f, bmin, bmax) != TP_CULL_OUTSIDE;
}

/* Leaf (lc, lr)'s samples for the measure: m->q and m->qmin; 0 when it has nothing to measure
 * (no drawn sample, or its box outside the view). */
static int leaf_begin(measure* m, int lc, int lr)
{
    const tp_cut* c = m->c;
    int64_t leaf = tp_tree_node_id(&c->g, 0, lc, lr);
    const tp_node_meta* meta = tp_tree_meta(c->t, leaf);
    if (!leaf_in_view(m, lc, lr))
        return 0;
    m->lc = lc, m->lr = lr;
    m->qmin = meta->qmin;
    m->q = tp_tree_samples(c->t, leaf);
    if (!m->q && m->o && m->o->read_leaf) {
        if (!m->buf) {
            size_t v = ((size_t)1 << c->n) + 1;
            m->buf = tp__alloc(&c->alloc, v * v, sizeof *m->buf);
            if (!m->buf) {
                m->oom = 1;
                return 0;
            }
        }
        if (m->o->read_leaf(m->o->user, leaf, m->buf)) {
            m->q = m->buf;
            m->out->leaves_read++;
        }
    }
    if (m->q)
        m->out->leaves_measured++;
    else
        m->out->leaves_skipped++;
    size_t v = ((size_t)1 << c->n) + 1;
    memset(m->seen, 0, (v * v + 7) / 8);
    return 1;
}

/* 1 when leaf (lc, lr) is under the node being measured or a complete node is drawn over it. */
static int8_t next_done(const measure* m, int lc, int lr)
{
    const tp_cut* c = m->c;
    if (lc - m->node_lc < m->node_w && lr - m->node_lr < m->node_w)
        return 1;
    if (lc >= c->g.cols || lr >= c->g.rows)
        return 0;
    int o = tp__cut_drawn_at_leaf(c, lc, lr);
    return o >= 0 && (tp_tree_meta(c->t, c->out[o].node)->flags & TP_NODE_COMPLETE);
}

/* The node's triangles over the samples leaf (lc, lr) owns, and over the first column and row
 * of the leaves after it where these draw nothing (a culled node, a void, an incomplete node's
 * hole): each sample is measured by the node tp_cut_drawn_height_at takes it from, so the edges
 * of a drawn area are measured too. */
static void measure_leaf(measure* m, int lc, int lr)
{
    const tp_cut* c = m->c;
    if (!leaf_begin(m, lc, lr))
        return;
    int32_t clip[4] = {lc << c->n, lr << c->n, (lc + 1) << c->n, (lr + 1) << c->n};
    m->x1 = clip[2] - 1, m->y1 = clip[3] - 1;
    if (lc == c->g.cols - 1) /* the grid's last column and row: this leaf's own */
        m->x1++;
    if (lr == c->g.rows - 1)
        m->y1++;
    m->next[0][0] = 0;
    m->next[0][1] = next_done(m, lc + 1, lr);
    m->next[1][0] = next_done(m, lc, lr + 1);
    m->next[1][1] = next_done(m, lc + 1, lr + 1);
    for (size_t t = 0; t < m->ntris; t++) {
        const tri* tr = &m->tris[t];
        if (tr->box[0] > clip[2] || tr->box[2] < clip[0] || tr->box[1] > clip[3] ||
            tr->box[3] < clip[1])
            continue;
        tp__raster_triangle_clip(tr->pos[0], tr->pos[1], tr->pos[2], tr->q[0], tr->q[1],
                                 tr->q[2], clip, sample, m);
    }
}

static uint32_t mix(uint64_t h)
{
    h ^= h >> 33;
    h *= 0xff51afd7ed558ccdull;
    h ^= h >> 33;
    h *= 0xc4ceb9fe1a85ec53ull;
    h ^= h >> 33;
    return (uint32_t)h;
}

/* m: at most m x m leaves a node, the largest power of two whose choice over the cut stays
 * within max_leaves (1 when none does); 0 when max_leaves is 0 or every leaf fits. */
static int leaves_per_node(const tp_cut* c, size_t max_leaves, size_t* total)
{
    *total = 0;
    int smax = 0;
    for (size_t i = 0; i < c->out_count; i++) {
        int s, cc, rr;
        tp_tree_node_locate(&c->g, c->out[i].node, &s, &cc, &rr);
        *total += (size_t)1 << (2 * s);
        smax = s > smax ? s : smax;
    }
    if (!max_leaves || *total <= max_leaves)
        return 0;
    for (int e = smax - 1; e > 0; e--) {
        size_t chosen = 0, side = (size_t)1 << e;
        for (size_t i = 0; i < c->out_count; i++) {
            int s, cc, rr;
            tp_tree_node_locate(&c->g, c->out[i].node, &s, &cc, &rr);
            size_t w = (size_t)1 << s;
            chosen += w < side ? w * w : side * side;
        }
        if (chosen <= max_leaves)
            return 1 << e;
    }
    return 1;
}

/* The sampled leaves of drawn node i (per_node as leaves_per_node says): the first leaf
 * column and row (*lc0, *lr0), the offset (*ox, *oy), the stride and the node's width. */
static void node_sampling(const tp_cut* c, size_t i, int per_node, uint32_t seed, int* lc0,
                          int* lr0, int* ox, int* oy, int* stride, int* w)
{
    int s, cc, rr;
    tp_tree_node_locate(&c->g, c->out[i].node, &s, &cc, &rr);
    *w = 1 << s;
    *stride = per_node && *w > per_node ? *w / per_node : 1;
    *ox = *oy = 0;
    if (*stride > 1) {
        uint32_t h = mix((uint64_t)c->out[i].node * 0x9e3779b97f4a7c15ull + seed);
        *ox = (int)(h % (uint32_t)*stride);
        *oy = (int)((h >> 16) % (uint32_t)*stride);
    }
    *lc0 = cc << s, *lr0 = rr << s;
}

/* o->prefetch with every leaf the measure will ask o->read_leaf for (sampled, in view with a
 * drawn sample, not resident), in the order it will ask; 0 when out of memory. */
static int prefetch_leaves(measure* m, int per_node)
{
    const tp_cut* c = m->c;
    int64_t* ids = NULL;
    size_t n = 0, cap = 0;
    for (size_t i = 0; i < c->out_count; i++) {
        int lc0, lr0, ox, oy, stride, w;
        node_sampling(c, i, per_node, m->o->seed, &lc0, &lr0, &ox, &oy, &stride, &w);
        for (int j = oy; j < w; j += stride)
            for (int k = ox; k < w; k += stride) {
                int64_t leaf = tp_tree_node_id(&c->g, 0, lc0 + k, lr0 + j);
                if (tp_tree_samples(c->t, leaf) || !leaf_in_view(m, lc0 + k, lr0 + j))
                    continue;
                if (n == cap) {
                    size_t grow = cap ? 2 * cap : 256;
                    int64_t* more = tp__alloc(&c->alloc, grow, sizeof *more);
                    if (!more) {
                        tp__free(&c->alloc, ids);
                        return 0;
                    }
                    if (n)
                        memcpy(more, ids, n * sizeof *ids);
                    tp__free(&c->alloc, ids);
                    ids = more, cap = grow;
                }
                ids[n++] = leaf;
            }
    }
    if (n)
        m->o->prefetch(m->o->user, ids, n);
    tp__free(&c->alloc, ids);
    return 1;
}

tp_status tp_cut_measure_error(const tp_cut* c, const tp_camera* cam,
                               const tp_cut_measure_options* o, tp_cut_error* out)
{
    assert(c && cam && out);
    memset(out, 0, sizeof *out);
    measure m;
    memset(&m, 0, sizeof m);
    m.c = c;
    m.o = o;
    m.out = out;
    tp__view_from_camera(cam, &m.v);
    tp_frustum_from_camera(cam, &m.f);
    out->per_node = leaves_per_node(c, o ? o->max_leaves : 0, &out->leaves);
    size_t side = ((size_t)1 << c->n) + 1;
    m.seen = tp__alloc(&c->alloc, (side * side + 7) / 8, 1);
    m.oom = !m.seen;
    if (!m.oom && o && o->read_leaf && o->prefetch)
        m.oom = !prefetch_leaves(&m, out->per_node);
    for (size_t i = 0; i < c->out_count && !m.oom; i++) {
        m.ntris = 0;
        if (!tp__cut_node_tris(c, i, add_tri, &m) || m.oom) {
            m.oom = 1;
            break;
        }
        int lc0, lr0, ox, oy, stride, w;
        node_sampling(c, i, out->per_node, o ? o->seed : 0, &lc0, &lr0, &ox, &oy, &stride, &w);
        m.node = (int)i;
        m.node_lc = lc0, m.node_lr = lr0, m.node_w = w;
        for (int j = oy; j < w; j += stride)
            for (int k = ox; k < w; k += stride) {
                out->leaves_sampled++;
                measure_leaf(&m, lc0 + k, lr0 + j);
            }
    }
    tp__free(&c->alloc, m.tris);
    tp__free(&c->alloc, m.buf);
    tp__free(&c->alloc, m.seen);
    if (m.oom) {
        memset(out, 0, sizeof *out);
        out->max_px = out->rms_px = NAN;
        return TP_ERR_OUT_OF_MEMORY;
    }
    out->max_px = out->samples ? m.max : NAN;
    out->rms_px = out->samples ? sqrt(m.sum / (double)out->samples) : NAN;
    return TP_OK;
}

tp_status tp_cut_measure_screen_error(const tp_cut* c, const tp_camera* cam, double* max_px,
                                      double* rms_px, size_t* samples, size_t* skipped)
{
    tp_cut_error e;
    tp_status st = tp_cut_measure_error(c, cam, NULL, &e);
    if (max_px)
        *max_px = e.samples ? e.max_px : 0;
    if (rms_px)
        *rms_px = e.samples ? e.rms_px : 0;
    if (samples)
        *samples = e.samples;
    if (skipped)
        *skipped = e.skipped;
    return st;
}
