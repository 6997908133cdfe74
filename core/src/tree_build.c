/* tree_build.c - building a tree's metas one band of leaf rows at a time, and a whole tree in
 * memory from a float grid (tp_tree_create_from_grid).
 *
 * The builder keeps, for every scale s >= 1, the 2^n + 1 decimated rows (every 2^s-th row and
 * column) of the band of scale-s nodes being filled, and two rows of metas per scale (the
 * children of the next row of parents). A scale-s node row r' is complete when leaf band
 * (r'+1) 2^s - 1 arrives (its last row is that band's last row), which is also when its children
 * are complete: so within one band, leaves are computed first, then each coarser scale, and
 * every node comes after its 4 children. Nothing depends on the number of rows.
 */
#include "step.h"
#include "tree_int.h"

#include <stdio.h>
#include <string.h>

struct tp_tree_builder {
    tp_tree_builder_desc d;
    tp_allocator a;
    int n, ps, side, width;
    int next_band, failed;
    int32_t* rows[TP_TREE_MAX_SCALES];     /* scale s >= 1: side rows of rw[s] samples */
    uint8_t* frows[TP_TREE_MAX_SCALES];    /* their filled flags (allocated with the first
                                              flags given; until then none is filled) */
    int rw[TP_TREE_MAX_SCALES];            /* node_cols[s] * 2^n + 1 */
    tp_node_meta* metas[TP_TREE_MAX_SCALES]; /* 2 rows (by row parity) of node_cols[s] */
    uint16_t* masks[TP_TREE_MAX_SCALES];     /* their cell masks, mask_words each */
    size_t mask_words;
    int32_t* scratch;                       /* cols blocks of side^2: one node's q per item */
    uint16_t* fscratch;                     /* cols blocks of filled_words: their filled bits */
    size_t filled_words;
    int flagged;                            /* frows exist: flags were given */
    /* the row of nodes being computed by the parallel_for */
    int cur_s, cur_r;
    const int32_t* cur_src; /* scale 0: the band; else rows[cur_s] */
    const uint8_t* cur_fsrc; /* its filled flags, or NULL */
    int cur_src_w;
};

static void destroy(tp_tree_builder* b)
{
    tp_allocator a = b->a;
    for (int s = 0; s < TP_TREE_MAX_SCALES; s++) {
        tp__free(&a, b->rows[s]);
        tp__free(&a, b->frows[s]);
        tp__free(&a, b->metas[s]);
        tp__free(&a, b->masks[s]);
    }
    tp__free(&a, b->scratch);
    tp__free(&a, b->fscratch);
    tp__free(&a, b);
}

tp_status tp_tree_builder_create(const tp_tree_builder_desc* desc, tp_tree_builder** out,
                                 tp_error* err)
{
    assert(desc && out);
    const tp_tree_geometry* g = &desc->geometry;
    if (!desc->allocator.alloc != !desc->allocator.free)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree builder: allocator: expected both alloc and free, or neither");
    if (g->n < 4 || g->n > TP_MAX_N || g->cols < 1 || g->rows < 1 || g->scales < 1 ||
        g->scales > TP_TREE_MAX_SCALES || g->width != g->cols * (1 << g->n) + 1)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree builder: geometry not initialised (n %d, %dx%d leaves)", g->n,
                        g->cols, g->rows);
    if (!desc->emit && !desc->emit_filled)
        return tp__fail(err, TP_ERR_INVALID_ARG, "tree builder: expected an emit callback");
    if (!(desc->err_unit_steps > 0) || !isfinite(desc->err_unit_steps))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree builder: expected an error unit > 0, got %g", desc->err_unit_steps);
    tp_allocator a = desc->allocator;
    tp_tree_builder* b = tp__calloc(&a, 1, sizeof *b);
    if (!b)
        goto oom;
    b->d = *desc;
    b->a = a;
    b->n = g->n;
    b->ps = 1 << g->n;
    b->side = b->ps + 1;
    b->width = g->width;
    b->mask_words = tp_node_mask_words(g->n);
    b->filled_words = tp_node_filled_words(g->n);
    for (int s = 0; s < g->scales; s++) {
        if (s >= 1) {
            b->rw[s] = g->node_cols[s] * b->ps + 1;
            b->rows[s] = tp__alloc(&a, (size_t)b->side * (size_t)b->rw[s], sizeof(int32_t));
            if (!b->rows[s])
                goto oom;
        }
        b->metas[s] = tp__calloc(&a, 2 * (size_t)g->node_cols[s], sizeof(tp_node_meta));
        b->masks[s] = tp__calloc(&a, 2 * (size_t)g->node_cols[s] * b->mask_words,
                                 sizeof(uint16_t));
        if (!b->metas[s] || !b->masks[s])
            goto oom;
    }
    b->scratch = tp__alloc(&a, (size_t)g->cols * (size_t)b->side * (size_t)b->side,
                           sizeof(int32_t));
    b->fscratch = tp__calloc(&a, (size_t)g->cols * b->filled_words, sizeof(uint16_t));
    if (!b->scratch || !b->fscratch)
        goto oom;
    *out = b;
    return TP_OK;
oom:
    if (b)
        destroy(b);
    return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tree builder: out of memory for %d leaf columns",
                    g->cols);
}

void tp_tree_builder_destroy(tp_tree_builder* b)
{
    if (b)
        destroy(b);
}

static int32_t* item_q(const tp_tree_builder* b, int c)
{
    return b->scratch + (size_t)c * (size_t)b->side * (size_t)b->side;
}

static uint16_t* item_filled(const tp_tree_builder* b, int c)
{
    return b->fscratch + (size_t)c * b->filled_words;
}

static tp_node_meta* meta_at(const tp_tree_builder* b, int s, int c, int r)
{
    return &b->metas[s][(size_t)(r & 1) * (size_t)b->d.geometry.node_cols[s] + (size_t)c];
}

static uint16_t* mask_at(const tp_tree_builder* b, int s, int c, int r)
{
    size_t i = (size_t)(r & 1) * (size_t)b->d.geometry.node_cols[s] + (size_t)c;
    return b->masks[s] + i * b->mask_words;
}

/* One node of the current row: gather its samples, compute its meta. Items touch only their
 * own scratch block and meta slot, so any order and any threads give the same result. */
static void node_item(int c, void* ctx)
{
    tp_tree_builder* b = ctx;
    int side = b->side, ps = b->ps, s = b->cur_s, r = b->cur_r;
    int32_t* q = item_q(b, c);
    for (int j = 0; j < side; j++)
        memcpy(q + (size_t)j * side, b->cur_src + (size_t)j * b->cur_src_w + (size_t)c * ps,
               sizeof(int32_t) * (size_t)side);
    const tp_node_meta* children[4] = {NULL, NULL, NULL, NULL};
    const uint16_t* kid_masks[4] = {NULL, NULL, NULL, NULL};
    uint16_t* mask = mask_at(b, s, c, r);
    if (s > 0) {
        for (int k = 0; k < 4; k++) {
            children[k] = meta_at(b, s - 1, 2 * c + (k & 1), 2 * r + (k >> 1));
            kid_masks[k] = mask_at(b, s - 1, 2 * c + (k & 1), 2 * r + (k >> 1));
        }
        tp_node_mask_from_children(b->n, kid_masks, mask);
    } else {
        tp_node_mask_from_q(b->n, q, mask);
    }
    tp_node_meta* m = meta_at(b, s, c, r);
    tp_node_meta_compute(b->n, s, q, mask, s > 0 ? children : NULL, b->d.err_unit_steps, m);
    /* filled bits: the flags of the node's own drawn samples */
    uint16_t* fb = item_filled(b, c);
    memset(fb, 0, b->filled_words * sizeof *fb);
    if (b->cur_fsrc) {
        int any = 0;
        for (int j = 0; j < side; j++) {
            const uint8_t* f = b->cur_fsrc + (size_t)j * b->cur_src_w + (size_t)c * ps;
            const int32_t* qq = q + (size_t)j * side;
            for (int i = 0; i < side; i++)
                if (f[i] && qq[i] != INT32_MIN) {
                    size_t k = (size_t)j * side + (size_t)i;
                    fb[k >> 4] |= (uint16_t)(1u << (k & 15));
                    any = 1;
                }
        }
        if (any)
            m->flags |= TP_NODE_HAS_FILLED;
    }
}

/* Computes and emits row r of scale s (its samples in src, rows of src_w). */
static tp_status node_row(tp_tree_builder* b, int s, int r, const int32_t* src,
                          const uint8_t* fsrc, int src_w, tp_error* err)
{
    const tp_tree_geometry* g = &b->d.geometry;
    int count = g->node_cols[s];
    b->cur_s = s;
    b->cur_r = r;
    b->cur_src = src;
    b->cur_fsrc = fsrc;
    b->cur_src_w = src_w;
    if (b->d.parallel_for)
        b->d.parallel_for(count, node_item, b, b->d.user);
    else
        for (int c = 0; c < count; c++)
            node_item(c, b);
    for (int c = 0; c < count; c++) {
        int64_t id = tp_tree_node_id(g, s, c, r);
        tp_error e;
        snprintf(e.message, sizeof e.message, "tree builder: the emit callback stopped the "
                 "build at node %lld", (long long)id);
        const tp_node_meta* m = meta_at(b, s, c, r);
        int stop = b->d.emit_filled
                       ? b->d.emit_filled(id, m, item_q(b, c), mask_at(b, s, c, r),
                                          (m->flags & TP_NODE_HAS_FILLED) ? item_filled(b, c)
                                                                          : NULL,
                                          b->d.user, &e)
                       : b->d.emit(id, m, item_q(b, c), mask_at(b, s, c, r), b->d.user, &e);
        if (stop) {
            b->failed = 1;
            if (err)
                *err = e;
            return TP_ERR_IO;
        }
    }
    return TP_OK;
}

/* Keeps decimated row y (full-resolution row, its samples in `row`) for every scale that uses
 * it. The row that closes a scale-s band goes to its last slot; it starts the next band once
 * that band's nodes are computed (tp_tree_builder_add_band). */
static void keep_row(tp_tree_builder* b, int y, const int32_t* row, const uint8_t* frow)
{
    const tp_tree_geometry* g = &b->d.geometry;
    for (int s = 1; s < g->scales && (y & ((1 << s) - 1)) == 0; s++) {
        int ys = y >> s, bs = ys >> b->n, jj = ys & (b->ps - 1), slot;
        if (jj == 0 && bs > 0) {
            if (bs - 1 >= g->node_rows[s])
                continue;
            slot = b->ps;
        } else {
            if (bs >= g->node_rows[s])
                continue;
            slot = jj;
        }
        int32_t* dst = b->rows[s] + (size_t)slot * (size_t)b->rw[s];
        for (int xs = 0; xs < b->rw[s]; xs++)
            dst[xs] = row[(size_t)xs << s];
        if (b->flagged) {
            uint8_t* fdst = b->frows[s] + (size_t)slot * (size_t)b->rw[s];
            for (int xs = 0; xs < b->rw[s]; xs++)
                fdst[xs] = frow ? frow[(size_t)xs << s] : 0;
        }
    }
}

tp_status tp_tree_builder_add_band(tp_tree_builder* b, int r, const int32_t* q, size_t q_count,
                                   tp_error* err)
{
    return tp_tree_builder_add_band_filled(b, r, q, NULL, q_count, err);
}

tp_status tp_tree_builder_add_band_filled(tp_tree_builder* b, int r, const int32_t* q,
                                          const uint8_t* filled, size_t q_count, tp_error* err)
{
    assert(b && q && q_count == (size_t)b->side * (size_t)b->width);
    (void)q_count; /* only asserted */
    const tp_tree_geometry* g = &b->d.geometry;
    if (b->failed)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree builder: band %d refused: the build was stopped", r);
    if (r != b->next_band)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree builder: expected band %d (bands go in order, 0 .. %d), got %d",
                        b->next_band, g->rows - 1, r);
    if (filled && !b->flagged) { /* the first flags: rows of flags, none filled so far */
        for (int s = 1; s < g->scales; s++) {
            b->frows[s] = tp__calloc(&b->a, (size_t)b->side * (size_t)b->rw[s], 1);
            if (!b->frows[s]) {
                b->failed = 1;
                return tp__fail(err, TP_ERR_OUT_OF_MEMORY,
                                "tree builder: out of memory for the filled flags");
            }
        }
        b->flagged = 1;
    }
    /* row 0 of band r > 0 is the last row of band r-1, already kept */
    for (int j = r == 0 ? 0 : 1; j <= b->ps; j++)
        keep_row(b, r * b->ps + j, q + (size_t)j * (size_t)b->width,
                 filled ? filled + (size_t)j * (size_t)b->width : NULL);
    tp_status st = node_row(b, 0, r, q, filled, b->width, err);
    if (st != TP_OK)
        return st;
    for (int s = 1; s < g->scales && ((r + 1) & ((1 << s) - 1)) == 0; s++) {
        int rs = ((r + 1) >> s) - 1;
        if (rs >= g->node_rows[s])
            break; /* no node of this scale (or above) ends here */
        st = node_row(b, s, rs, b->rows[s], b->flagged ? b->frows[s] : NULL, b->rw[s], err);
        if (st != TP_OK)
            return st;
        memcpy(b->rows[s], b->rows[s] + (size_t)b->ps * (size_t)b->rw[s],
               sizeof(int32_t) * (size_t)b->rw[s]);
        if (b->flagged)
            memcpy(b->frows[s], b->frows[s] + (size_t)b->ps * (size_t)b->rw[s],
                   (size_t)b->rw[s]);
    }
    b->next_band++;
    return TP_OK;
}

void tp_tree_node_from_children(int n, int scale, const int32_t* const child_q[4],
                                const uint16_t* const child_mask[4],
                                const uint16_t* const child_filled[4],
                                const tp_node_meta* const children[4], double err_unit_steps,
                                int32_t* q, uint16_t* mask, uint16_t* filled, tp_node_meta* out)
{
    assert(n >= 4 && n <= TP_MAX_N && scale >= 1 && child_q && child_mask && children && q &&
           mask && filled && out);
    const int ps = 1 << n, side = ps + 1, half = ps >> 1;
    const size_t fwords = tp_node_filled_words(n);
    memset(filled, 0, fwords * sizeof *filled);
    int any = 0;
    /* sample i of the node is sample 2i of the left child, or 2i - 2^n of the right one */
    for (int j = 0; j < side; j++) {
        const int qy = j > half, cj = qy ? 2 * j - ps : 2 * j;
        for (int i = 0; i < side; i++) {
            const int qx = i > half, ci = qx ? 2 * i - ps : 2 * i, k = qy * 2 + qx;
            const size_t at = (size_t)cj * side + (size_t)ci, to = (size_t)j * side + (size_t)i;
            q[to] = child_q[k][at];
            const uint16_t* f = child_filled ? child_filled[k] : NULL;
            if (f && q[to] != INT32_MIN && (f[at >> 4] >> (at & 15) & 1)) {
                filled[to >> 4] |= (uint16_t)(1u << (to & 15));
                any = 1;
            }
        }
    }
    tp_node_mask_from_children(n, child_mask, mask);
    tp_node_meta_compute(n, scale, q, mask, children, err_unit_steps, out);
    if (any)
        out->flags |= TP_NODE_HAS_FILLED;
}

/* ---------------------------------------------------------------------------------------------
 * A whole tree from a float grid
 */
typedef struct {
    tp_node_meta* metas;
    uint16_t* samples;
    size_t count, block; /* samples per node, words per block (samples, mask, filled bits) */
    int n;
} grid_sink;

static int keep_node(int64_t node, const tp_node_meta* meta, const int32_t* q,
                     const uint16_t* mask, void* user, tp_error* err)
{
    (void)err;
    grid_sink* k = user;
    k->metas[node] = *meta;
    uint16_t* dst = k->samples + (size_t)node * k->block;
    for (size_t i = 0; i < k->count; i++)
        dst[i] = q[i] == INT32_MIN ? (uint16_t)TP_TREE_NO_HEIGHT : (uint16_t)(q[i] - meta->qmin);
    size_t mw = tp_node_mask_words(k->n);
    memcpy(dst + k->count, mask, mw * sizeof *mask);
    memset(dst + k->count + mw, 0, (k->block - k->count - mw) * sizeof *dst); /* none filled */
    return 0;
}

tp_status tp_tree_create_from_grid(const float* heights, size_t height_count, int width,
                                   int height, const double geotransform[6], int patch_size,
                                   double height_step_m, tp_tree** out, tp_error* err)
{
    assert(out);
    if (!heights || width < 1 || height < 1 || height_count != (size_t)width * (size_t)height)
        return tp__fail(err, TP_ERR_INVALID_ARG, "tree: expected %zu heights for %dx%d, got %zu",
                        (size_t)(width > 0 ? width : 0) * (size_t)(height > 0 ? height : 0),
                        width, height, heights ? height_count : 0);
    tp_tree_geometry g;
    tp_status st = tp_tree_geometry_init(width, height, patch_size ? patch_size
                                                                   : TP_DEFAULT_PATCH_SIZE,
                                         &g, err);
    if (st != TP_OK)
        return st;
    double gt[6] = {0, 1, 0, 0, 0, -1};
    if (geotransform && !(geotransform[1] == 0 && geotransform[5] == 0))
        memcpy(gt, geotransform, sizeof gt);
    for (int i = 0; i < 6; i++)
        if (!isfinite(gt[i]))
            return tp__fail(err, TP_ERR_INVALID_ARG, "tree: geotransform[%d] is not finite", i);
    if (gt[2] != 0 || gt[4] != 0 || gt[1] == 0 || gt[5] == 0)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree: expected a north-up geotransform with non-zero pixel sizes");
    if (height_step_m < 0 || !isfinite(height_step_m))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tree: expected a height step > 0 (or 0 for automatic), got %g",
                        height_step_m);

    /* Quantisation as tp_terrain_create, with one range: every node up to the root must fit
     * its samples in 16 bits, i.e. the global range must fit 65534 steps. */
    tp__range range = {INFINITY, -INFINITY};
    int integral = 1;
    size_t valid = 0;
    for (size_t i = 0; i < height_count; i++) {
        float s = heights[i];
        if (!isfinite(s))
            continue;
        valid++;
        range.lo = s < range.lo ? s : range.lo;
        range.hi = s > range.hi ? s : range.hi;
        integral &= s == floorf(s);
    }
    if (valid == 0)
        return tp__fail(err, TP_ERR_BAD_DATA, "tree: no valid height among %dx%d samples", width,
                        height);
    double step = height_step_m;
    if (step > 0) {
        if (!tp__step_fits(&range, 1, step))
            return tp__fail(err, TP_ERR_INVALID_ARG,
                            "tree: height step %g m is too fine: the heights (%g .. %g m) span "
                            "more than 65534 steps",
                            step, range.lo, range.hi);
    } else {
        step = tp__choose_step(&range, 1, integral);
        if (step == 0)
            return tp__fail(err, TP_ERR_BAD_DATA, "tree: heights out of range (%g .. %g)",
                            range.lo, range.hi);
    }
    double qerr = 0;
    for (size_t i = 0; i < height_count; i++)
        if (isfinite(heights[i])) {
            double e = fabs(floor(heights[i] / step + 0.5) * step - heights[i]);
            qerr = e > qerr ? e : qerr;
        }
    double unit = tp_tree_err_unit_steps(floor(range.hi / step + 0.5) -
                                         floor(range.lo / step + 0.5));

    tp_allocator a = {0};
    int side = (1 << g.n) + 1;
    grid_sink sink = {0};
    sink.count = (size_t)side * (size_t)side;
    sink.block = tp_tree_block_words(g.n);
    sink.n = g.n;
    sink.metas = tp__calloc(&a, (size_t)g.node_count, sizeof(tp_node_meta));
    sink.samples = tp__alloc(&a, (size_t)g.node_count, sink.block * sizeof(uint16_t));
    int32_t* band = tp__alloc(&a, (size_t)side * (size_t)g.width, sizeof(int32_t));
    tp_tree_builder* b = NULL;
    tp_tree* t = NULL;
    if (!sink.metas || !sink.samples || !band) {
        st = tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tree: out of memory for %lld nodes",
                      (long long)g.node_count);
        goto done;
    }
    tp_tree_builder_desc bd = {0};
    bd.geometry = g;
    bd.err_unit_steps = unit;
    bd.emit = keep_node;
    bd.user = &sink;
    st = tp_tree_builder_create(&bd, &b, err);
    for (int r = 0; st == TP_OK && r < g.rows; r++) {
        for (int j = 0; j < side; j++) {
            int y = r * (side - 1) + j;
            int32_t* dst = band + (size_t)j * (size_t)g.width;
            for (int x = 0; x < g.width; x++) {
                float s = x < width && y < height ? heights[(size_t)y * width + x] : NAN;
                dst[x] = isfinite(s) ? (int32_t)floor(s / step + 0.5) : INT32_MIN;
            }
        }
        st = tp_tree_builder_add_band(b, r, band, (size_t)side * (size_t)g.width, err);
    }
    if (st != TP_OK)
        goto done;
    tp_tree_desc td = {0};
    td.geometry = g;
    memcpy(td.geotransform, gt, sizeof gt);
    /* the fitted grid keeps the source's origin and spacing (padding goes right and down) */
    td.height_step_m = step;
    td.quant_max_error_m = qerr;
    td.err_unit_steps = unit;
    td.metas = sink.metas;
    td.meta_count = (size_t)g.node_count;
    st = tp_tree_create(&td, &t, err);
    if (st != TP_OK)
        goto done;
    for (int64_t id = 0; id < g.node_count; id++)
        tp_tree_attach(t, id, sink.samples + (size_t)id * sink.block);
    tp__tree_own(t, sink.metas, sink.samples);
    sink.metas = NULL;
    sink.samples = NULL;
    *out = t;
done:
    tp_tree_builder_destroy(b);
    tp__free(&a, band);
    tp__free(&a, sink.metas);
    tp__free(&a, sink.samples);
    return st;
}
