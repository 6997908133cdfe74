/* pgm_clip_error.c - the error of the surface Persistent Grid Mapping draws over a store's
 * clipmap (see pgm_clip.h, tp_pgm_clipmap_measure): the core's tp_pgm_measure_error_source
 * over a source that reads what the windows hold (each level's posts from the store's nodes, as
 * pgm_clip.c's filler writes them, the level chosen as the clipmap shader chooses it from the
 * windows' origins) and the level-0 posts of the view's region (from the scale-0 nodes, band by
 * band of one node row). */
#include "pgm_clip.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A decoded node in the cache (direct-mapped by id). */
typedef struct cached {
    int64_t node; /* -1: empty */
    float* z;     /* (2^n+1)^2 heights, NaN where not drawn */
} cached;

typedef struct clip_source {
    const tp_store* store;
    tp_store_info info;
    const tp_tree_geometry* g;
    const tp_node_meta* metas;
    const tp_pgm_pyramid* shape;
    int w;
    int origin[2 * TP_PGM_MAX_LEVELS];
    size_t samples; /* (2^n + 1)^2 */
    uint16_t* raw;
    cached* cache;
    size_t cache_count;
    char failed[512]; /* the first read failure */
} clip_source;

/* The decoded heights of node (the clipmap filler's arithmetic, so the same floats); NULL when
 * the read fails (failed says why, the first time). */
static const float* node_heights(clip_source* s, int64_t node)
{
    cached* e = &s->cache[(size_t)node % s->cache_count];
    if (e->node == node)
        return e->z;
    if (!e->z && !(e->z = malloc(s->samples * sizeof *e->z))) {
        if (!s->failed[0])
            snprintf(s->failed, sizeof s->failed, "out of memory for a node's heights");
        return NULL;
    }
    tp_error err;
    memset(&err, 0, sizeof err);
    if (tp_store_read_node(s->store, node, s->raw, s->samples, &err) != TP_OK) {
        if (!s->failed[0])
            snprintf(s->failed, sizeof s->failed, "%.500s", err.message);
        e->node = -1;
        return NULL;
    }
    double step = s->info.header.height_step_m, qmin = s->metas[node].qmin;
    for (size_t k = 0; k < s->samples; k++)
        e->z[k] = s->raw[k] == TP_TREE_NO_HEIGHT ? NAN : (float)((s->raw[k] + qmin) * step);
    e->node = node;
    return e->z;
}

/* Level l's post (i, j) as its window holds it: level-0 post (min(i 2^l, W - 1), likewise);
 * NaN where it has no height or its node cannot be read (the filler's TP_PGM_CLIP_VOID). */
static double fetch(clip_source* s, int l, int i, int j)
{
    const tp_tree_geometry* g = s->g;
    long long xl = (long long)i << l, yl = (long long)j << l;
    int x = (int)(xl < g->src_width - 1 ? xl : g->src_width - 1);
    int y = (int)(yl < g->src_height - 1 ? yl : g->src_height - 1);
    size_t sample;
    const float* z = node_heights(s, tp_pgm_store_post(g, l, x, y, &sample));
    return z ? z[sample] : NAN;
}

/* The clipmap shader's sample_level (pgm_render.c): from level l0 up, the first level whose
 * window holds the four posts around (x, y) (the last level always), bilinear as
 * tp_pgm_pyramid_sample; NaN when one of them is void. */
static double clip_sample(void* ctx, int l0, double x, double y)
{
    clip_source* s = ctx;
    const tp_pgm_pyramid* p = s->shape;
    x = fmin(fmax(x, 0), p->width[0] - 1);
    y = fmin(fmax(y, 0), p->height[0] - 1);
    for (int l = l0; l < p->levels; l++) {
        int w = p->width[l], h = p->height[l];
        double u = fmin(ldexp(x, -l), w - 1), v = fmin(ldexp(y, -l), h - 1);
        int i = (int)u, j = (int)v;
        i = i > w - 2 ? w - 2 : i;
        j = j > h - 2 ? h - 2 : j;
        i = i < 0 ? 0 : i;
        j = j < 0 ? 0 : j;
        int i1 = i + 1 < w ? i + 1 : i, j1 = j + 1 < h ? j + 1 : j;
        const int ox = s->origin[2 * l], oy = s->origin[2 * l + 1];
        int held = i >= ox && j >= oy && i1 < ox + s->w && j1 < oy + s->w;
        if (l + 1 < p->levels && !held)
            continue;
        double fx = u - i, fy = v - j;
        double z00 = fetch(s, l, i, j), z10 = fetch(s, l, i1, j);
        double z01 = fetch(s, l, i, j1), z11 = fetch(s, l, i1, j1);
        if (isnan(z00) || isnan(z10) || isnan(z01) || isnan(z11))
            return NAN;
        double top = z00 + fx * (z10 - z00), bottom = z01 + fx * (z11 - z01);
        return top + fy * (bottom - top);
    }
    return 0; /* (no levels: not reached) */
}

/* Level-0 posts from the scale-0 nodes, a node's columns at a time. */
static int clip_posts(void* ctx, int x0, int y0, int x1, int y1, float* out)
{
    clip_source* s = ctx;
    const int node_posts = 1 << s->g->n, bw = x1 - x0;
    for (int xa = x0; xa < x1;) {
        int xb = (xa / node_posts + 1) * node_posts;
        xb = xb < x1 ? xb : x1;
        for (int y = y0; y < y1; y++) {
            float* row = out + (size_t)(y - y0) * bw;
            int64_t last = -1;
            const float* z = NULL;
            for (int x = xa; x < xb; x++) {
                size_t sample;
                int64_t node = tp_pgm_store_post(s->g, 0, x, y, &sample);
                if (node != last) {
                    z = node_heights(s, node);
                    last = node;
                    if (!z)
                        return 0;
                }
                row[x - x0] = z[sample];
            }
        }
        xa = xb;
    }
    return 1;
}

tp_status tp_pgm_clipmap_measure(const tp_pgm_clipmap* c, const tp_pgm_frame* f,
                                 const tp_camera* main, size_t max_posts, tp_pgm_error* out,
                                 tp_error* err)
{
    memset(out, 0, sizeof *out);
    tp_pgm_rect region;
    tp_pgm_view_region(tp_pgm_clipmap_shape(c), main, &region);
    size_t posts = region.x1 > region.x0 && region.y1 > region.y0
                       ? (size_t)(region.x1 - region.x0) * (size_t)(region.y1 - region.y0)
                       : 0;
    /* a region of more than max_posts posts: every band_every-th band of node rows only */
    int every = max_posts && posts > max_posts ? (int)((posts + max_posts - 1) / max_posts) : 1;
    clip_source s;
    memset(&s, 0, sizeof s);
    s.store = tp_pgm_clipmap_store(c);
    tp_store_get_info(s.store, &s.info);
    s.g = &s.info.header.geometry;
    size_t count = 0;
    s.metas = tp_store_metas(s.store, &count);
    s.shape = tp_pgm_clipmap_shape(c);
    s.w = tp_pgm_clipmap_window(c);
    tp_pgm_clipmap_origins(c, s.origin);
    size_t side = ((size_t)1 << s.g->n) + 1;
    s.samples = side * side;
    /* about 16 MiB of decoded nodes, at least 64 of them (the filler's cache) */
    s.cache_count = ((size_t)16 << 20) / (s.samples * sizeof(float));
    s.cache_count = s.cache_count < 64 ? 64 : s.cache_count;
    s.raw = malloc(s.samples * sizeof *s.raw);
    s.cache = calloc(s.cache_count, sizeof *s.cache);
    tp_status st = TP_ERR_OUT_OF_MEMORY;
    if (s.raw && s.cache) {
        for (size_t k = 0; k < s.cache_count; k++)
            s.cache[k].node = -1;
        tp_pgm_source src = {&s, clip_sample, clip_posts, 1 << s.g->n, every, 0};
        st = tp_pgm_measure_error_source(f, s.shape, &src, &region, main, out);
    }
    if (st == TP_ERR_IO)
        tp_error_set(err, st, "PGM error over a store: %s", s.failed);
    else if (st != TP_OK)
        tp_error_set(err, st, "PGM error over a store: out of memory");
    for (size_t k = 0; s.cache && k < s.cache_count; k++)
        free(s.cache[k].z);
    free(s.cache);
    free(s.raw);
    return st;
}
