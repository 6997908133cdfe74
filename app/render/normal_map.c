/* normal_map.c - full-resolution normals through a clipmap (see normal_map.h). */
#define _POSIX_C_SOURCE 200809L
#include "normal_map.h"

#include "pyramid_view.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define B TP_NORMAL_MAP_BLOCK
#define ZW (B + 2) /* a block's posts: one more on each side */

struct tp_normal_source {
    int width, height, levels; /* level-0 posts (the source grid), pyramid levels */
    double gt[6];
    double lo, hi;             /* the height range the hypsometric colours span */
    const tp_terrain* terrain; /* one of the two */
    const tp_store* store;
    tp_tree_geometry geom; /* the store's */
    const tp_tree_geometry* g;
    const tp_node_meta* metas;
    double step;
    int remote;           /* the store is read over HTTP: a block's nodes read ahead */
    pthread_mutex_t lock; /* the buffers below: one block at a time */
    double* z;            /* ZW x ZW posts: heights (NaN: none) */
    uint8_t* f;           /* and whether each is a filled void */
    /* nodes read, direct-mapped by id: their samples as stored (a height is made from one as
     * it is read: 2 bytes a post in the cache, not 8) and their qmin */
    int64_t* cache_node;
    uint16_t* cache_q;
    double* cache_qmin;
    uint8_t* cache_f;
    uint16_t* raw;        /* a node's block: samples, cell mask, filled bits */
    size_t samples, filled_at;
    int cache_count;
};

static tp_normal_source* source_new(int width, int height, const double gt[6], double lo,
                                    double hi, tp_error* err)
{
    tp_normal_source* s = calloc(1, sizeof *s);
    if (s && (!(s->z = malloc((size_t)ZW * ZW * sizeof *s->z)) || !(s->f = malloc((size_t)ZW * ZW)))) {
        free(s->z);
        free(s);
        s = NULL;
    }
    if (!s) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    pthread_mutex_init(&s->lock, NULL);
    s->width = width;
    s->height = height;
    memcpy(s->gt, gt, sizeof s->gt);
    s->lo = isnan(lo) ? 0 : lo;
    s->hi = isnan(hi) ? 0 : hi;
    s->levels = 1;
    while (s->levels < TP_RENDER_CLIP_LEVELS &&
           (((width - 1) >> (s->levels - 1)) + 1 > B || ((height - 1) >> (s->levels - 1)) + 1 > B))
        s->levels++;
    return s;
}

tp_normal_source* tp_normal_source_terrain(const tp_terrain* t, tp_error* err)
{
    tp_terrain_info in;
    tp_terrain_get_info(t, &in);
    tp_normal_source* s = source_new(in.width, in.height, in.geotransform, in.min_height_m,
                                     in.max_height_m, err);
    if (s)
        s->terrain = t;
    return s;
}

tp_normal_source* tp_normal_source_store(const tp_store* st, double min_m, double max_m,
                                         tp_error* err)
{
    tp_store_info in;
    tp_store_get_info(st, &in);
    const tp_tree_geometry* g = &in.header.geometry;
    tp_normal_source* s =
        source_new(g->src_width, g->src_height, in.header.geotransform, min_m, max_m, err);
    if (!s)
        return NULL;
    s->store = st;
    s->geom = *g;
    s->g = &s->geom;
    size_t count;
    s->metas = tp_store_metas(st, &count);
    s->step = in.header.height_step_m;
    s->remote = in.remote;
    s->samples = (size_t)((1 << g->n) + 1) * (size_t)((1 << g->n) + 1);
    /* a block's posts span ZW / 2^n + 2 nodes a side: twice that many entries */
    int side = ZW / (1 << g->n) + 2;
    s->cache_count = 2 * side * side;
    s->cache_node = malloc((size_t)s->cache_count * sizeof *s->cache_node);
    s->cache_q = malloc((size_t)s->cache_count * s->samples * sizeof *s->cache_q);
    s->cache_qmin = malloc((size_t)s->cache_count * sizeof *s->cache_qmin);
    s->cache_f = malloc((size_t)s->cache_count * s->samples);
    s->filled_at = s->samples + tp_node_mask_words(g->n);
    s->raw = malloc(tp_tree_block_words(g->n) * sizeof *s->raw);
    if (!s->cache_node || !s->cache_q || !s->cache_qmin || !s->cache_f || !s->raw) {
        tp_normal_source_destroy(s);
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    for (int i = 0; i < s->cache_count; i++)
        s->cache_node[i] = -1;
    return s;
}

void tp_normal_source_destroy(tp_normal_source* s)
{
    if (!s)
        return;
    pthread_mutex_destroy(&s->lock);
    free(s->z);
    free(s->f);
    free(s->cache_node);
    free(s->cache_q);
    free(s->cache_qmin);
    free(s->cache_f);
    free(s->raw);
    free(s);
}

/* The cache entry of node (its samples, TP_TREE_NO_HEIGHT where not drawn, its qmin, and filled
 * flags), read on a miss; -1 when it cannot be. */
static int node_entry(tp_normal_source* s, int64_t node, tp_error* err)
{
    int e = (int)(node % s->cache_count);
    if (s->cache_node[e] == node)
        return e;
    s->cache_node[e] = -1;
    const tp_tree_geometry* g = s->g;
    if (tp_store_read_node(s->store, node, s->raw, tp_tree_block_words(g->n), err) != TP_OK)
        return -1;
    uint8_t* f = s->cache_f + (size_t)e * s->samples;
    memcpy(s->cache_q + (size_t)e * s->samples, s->raw, s->samples * sizeof *s->raw);
    s->cache_qmin[e] = s->metas[node].qmin;
    const uint16_t* bits = s->raw + s->filled_at;
    for (size_t k = 0; k < s->samples; k++)
        f[k] = (uint8_t)((bits[k / 16] >> (k % 16)) & 1);
    s->cache_node[e] = node;
    return e;
}

/* The ZW x ZW posts of level l from post (x0, y0) of that level (posts (x0 + i) << l) into s->z
 * and s->f; 0 with err when a node cannot be read. */
static int read_posts(tp_normal_source* s, int l, int64_t x0, int64_t y0, tp_error* err)
{
    for (int j = 0; j < ZW; j++) {
        int64_t y = (y0 + j) * ((int64_t)1 << l);
        double* row = s->z + (size_t)j * ZW;
        uint8_t* frow = s->f + (size_t)j * ZW;
        int64_t last = -1;
        int e = -1;
        for (int i = 0; i < ZW; i++) {
            int64_t x = (x0 + i) * ((int64_t)1 << l);
            row[i] = NAN;
            frow[i] = 0;
            if (x < 0 || y < 0 || x >= s->width || y >= s->height)
                continue;
            if (s->terrain) {
                row[i] = tp_terrain_sample(s->terrain, (int)x, (int)y);
                frow[i] = tp_terrain_sample_class(s->terrain, (int)x, (int)y) == TP_SAMPLE_FILLED;
                continue;
            }
            size_t sample;
            int64_t node = tp_pgm_store_post(s->g, l, (int)x, (int)y, &sample);
            if (node != last) {
                e = node_entry(s, node, err);
                last = node;
                if (e < 0)
                    return 0;
            }
            uint16_t q = s->cache_q[(size_t)e * s->samples + sample];
            row[i] = q == TP_TREE_NO_HEIGHT ? NAN : ((double)q + s->cache_qmin[e]) * s->step;
            frow[i] = s->cache_f[(size_t)e * s->samples + sample];
        }
    }
    return 1;
}

/* Over HTTP: the nodes read_posts will read for the same block and are not in the cache, read
 * ahead in one batch of concurrent requests (tp_store_prefetch) instead of a round trip each
 * (docs/PERFORMANCE.md, "Stores over HTTP"). */
#define PREFETCH_MAX 256
static void prefetch_posts(tp_normal_source* s, int l, int64_t x0, int64_t y0)
{
    int64_t ids[PREFETCH_MAX];
    size_t k = 0;
    for (int j = 0; j < ZW && k < PREFETCH_MAX; j++) {
        int64_t y = (y0 + j) * ((int64_t)1 << l), last = -1;
        for (int i = 0; i < ZW && y >= 0 && y < s->height && k < PREFETCH_MAX; i++) {
            int64_t x = (x0 + i) * ((int64_t)1 << l);
            if (x < 0 || x >= s->width)
                continue;
            size_t sample;
            int64_t node = tp_pgm_store_post(s->g, l, (int)x, (int)y, &sample);
            if (node == last || s->cache_node[node % s->cache_count] == node)
                continue;
            last = node;
            size_t m = 0;
            while (m < k && ids[m] != node)
                m++;
            if (m == k)
                ids[k++] = node;
        }
    }
    tp_store_prefetch(s->store, ids, k);
}

/* The mean of the known differences b0 - a0, b1 - a1 over spacing; NaN when neither is. */
static double slope2(double a0, double b0, double a1, double b1, double spacing)
{
    double d0 = b0 - a0, d1 = b1 - a1;
    if (!isnan(d0) && !isnan(d1))
        return (d0 + d1) / (2 * spacing);
    return (isnan(d0) ? d1 : d0) / spacing;
}

/* A texel: (nx, ny) of the normal of slopes gx, gy as the vertex path quantises them (a float
 * normal, x 127, rounded: renderer_upload.c), stored 128 + that (1 .. 255: llvmpipe filters
 * unsigned bytes on its fast path, and the shader's (255 t - 128) / 127 is exact); the height z
 * as its share of the range (0 .. 255); the filled share (alpha 255 measured, 128 filled). */
static void put_texel(const tp_normal_source* s, uint8_t* t, double gx, double gy, double z,
                      double filled)
{
    double len = sqrt(gx * gx + gy * gy + 1);
    float n[2] = {(float)(-gx / len), (float)(-gy / len)};
    t[0] = (uint8_t)(128 + lrintf(n[0] * 127.0f));
    t[1] = (uint8_t)(128 + lrintf(n[1] * 127.0f));
    double h = (z - s->lo) / fmax(s->hi - s->lo, 1.0);
    h = isnan(h) ? 0 : h < 0 ? 0 : h > 1 ? 1 : h;
    t[2] = (uint8_t)lrint(h * 255);
    t[3] = (uint8_t)lrint(255 - 127 * filled);
}

/* The mean of the known values of v[0..count-1]; NaN when none is. */
static double mean_known(const double* v, int count)
{
    double sum = 0;
    int n = 0;
    for (int k = 0; k < count; k++)
        if (!isnan(v[k]))
            sum += v[k], n++;
    return n ? sum / n : NAN;
}

/* Texel (i, j) of a level-l block from s->z (post (i, j) of the block at z[(j + 1) ZW + i + 1]):
 * level 0 the post's normal and height; level >= 1 the cell's from (i, j) to (i + 1, j + 1) (its
 * mean slopes, height and filled share), the cell before it along an axis where that one has
 * no slope. */
static void texel(const tp_normal_source* s, int l, int i, int j, uint8_t* t)
{
    size_t at = (size_t)(j + 1) * ZW + (i + 1);
    const double* z = s->z + at;
    const uint8_t* f = s->f + at;
    double sx = s->gt[1] * (double)((int64_t)1 << l), sy = s->gt[5] * (double)((int64_t)1 << l);
    double gx, gy;
    if (l == 0) {
        gx = tp_slope3(z[-1], z[0], z[1], sx);
        gy = tp_slope3(z[-ZW], z[0], z[ZW], sy);
        put_texel(s, t, gx, gy, z[0], f[0]);
        return;
    }
    {
        gx = slope2(z[0], z[1], z[ZW], z[ZW + 1], sx);
        if (isnan(gx))
            gx = slope2(z[-1], z[0], z[ZW - 1], z[ZW], sx);
        gy = slope2(z[0], z[ZW], z[1], z[ZW + 1], sy);
        if (isnan(gy))
            gy = slope2(z[-ZW], z[0], z[1 - ZW], z[1], sy);
        gx = isnan(gx) ? 0 : gx;
        gy = isnan(gy) ? 0 : gy;
    }
    const double corners[4] = {z[0], z[1], z[ZW], z[ZW + 1]};
    double filled = 0;
    int known = 0;
    for (int k = 0; k < 4; k++)
        if (!isnan(corners[k])) {
            filled += f[k == 0 ? 0 : k == 1 ? 1 : k == 2 ? ZW : ZW + 1];
            known++;
        }
    put_texel(s, t, gx, gy, mean_known(corners, 4), known ? filled / known : 0);
}

static int read_block(void* user, tp_block_key k, uint8_t* rgba, tp_error* err)
{
    tp_normal_source* s = user;
    pthread_mutex_lock(&s->lock);
    if (s->remote)
        prefetch_posts(s, k.level, k.bx * B - 1, k.by * B - 1);
    int ok = read_posts(s, k.level, k.bx * B - 1, k.by * B - 1, err);
    int64_t w = ((s->width - 1) >> k.level) + 1, h = ((s->height - 1) >> k.level) + 1;
    for (int j = 0; j < B; j++)
        for (int i = 0; i < B; i++) {
            uint8_t* t = rgba + ((size_t)j * B + i) * 4;
            if (!ok || k.bx * B + i >= w || k.by * B + j >= h)
                memset(t, 0, 4);
            else
                texel(s, k.level, i, j, t);
        }
    pthread_mutex_unlock(&s->lock);
    return ok;
}

void tp_normal_source_blocks(tp_normal_source* s, tp_block_source* out, double gt[6])
{
    memset(out, 0, sizeof *out);
    out->block = B;
    out->levels = s->levels;
    out->read = read_block;
    out->user = s;
    for (int l = 0; l < s->levels; l++) {
        out->width[l] = ((s->width - 1) >> l) + 1;
        out->height[l] = ((s->height - 1) >> l) + 1;
    }
    memcpy(gt, s->gt, 6 * sizeof *gt);
}

struct tp_normal_map {
    tp_normal_source* src;
    tp_clipmap* clip;
    tp_view_clip_state cs;
};

tp_normal_map* tp_normal_map_create(tp_normal_source* src, const tp_clipmap_options* o,
                                    tp_error* err)
{
    tp_normal_map* nm = calloc(1, sizeof *nm);
    if (!nm) {
        tp_normal_source_destroy(src);
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    nm->src = src;
    nm->cs.finest = -1;
    tp_clipmap_options co = {0};
    if (o)
        co = *o;
    if (!co.clip_blocks)
        co.clip_blocks = TP_NORMAL_MAP_BLOCKS;
    if (!co.cache_bytes) /* blocks are computed, not read: a small pool (32 blocks) will do */
        co.cache_bytes = TP_NORMAL_MAP_CACHE_BYTES;
    tp_block_source bs;
    double gt[6];
    tp_normal_source_blocks(src, &bs, gt);
    nm->clip = tp_clipmap_create(&bs, gt, &co, err);
    if (!nm->clip) {
        tp_normal_map_destroy(nm);
        return NULL;
    }
    return nm;
}

void tp_normal_map_destroy(tp_normal_map* nm)
{
    if (!nm)
        return;
    tp_clipmap_destroy(nm->clip); /* stops the loader before the source goes */
    tp_normal_source_destroy(nm->src);
    tp_view_clip_state_free(&nm->cs);
    free(nm);
}

void tp_normal_map_frame_cut(tp_normal_map* nm, const tp_store_scene* st, const tp_cut* cut,
                             double zscale, tp_renderer* r, const tp_camera* cam, int settle,
                             tp_clipmap_stats* stats)
{
    tp_clipmap_stats local;
    tp_render_clip rc;
    tp_view_clip_frame(&nm->cs, nm->clip, st, cut, zscale, cam, settle, stats ? stats : &local,
                       &rc);
    tp_renderer_set_normals(r, &rc);
}

void tp_normal_map_frame(tp_normal_map* nm, tp_renderer* r, const tp_camera* cam, double min_m,
                         double max_m, int settle, tp_clipmap_stats* stats)
{
    tp_clipmap_stats local;
    if (!stats)
        stats = &local;
    const double* gt = nm->src->gt;
    const double* p = cam->position;
    double e0 = gt[0], e1 = gt[0] + nm->src->width * gt[1];
    double n0 = gt[3], n1 = gt[3] + nm->src->height * gt[5];
    double dx = fmax(0, fmax(fmin(e0, e1) - p[0], p[0] - fmax(e0, e1)));
    double dy = fmax(0, fmax(fmin(n0, n1) - p[1], p[1] - fmax(n0, n1)));
    double dz = min_m <= max_m ? fmax(0, fmax(min_m - p[2], p[2] - max_m)) : 0;
    double d = sqrt(dx * dx + dy * dy + dz * dz);
    nm->cs.finest = tp_clipmap_finest_level(nm->clip, cam, &d, 1, nm->cs.finest);
    if (settle)
        tp_clipmap_settle(nm->clip, cam, nm->cs.finest, 60, stats);
    else
        tp_clipmap_update(nm->clip, cam, nm->cs.finest, stats);
    tp_render_clip rc;
    tp_clipmap_render_clip(nm->clip, &rc);
    tp_renderer_set_normals(r, &rc);
}

const char* tp_normal_map_take_failure(tp_normal_map* nm)
{
    return nm ? tp_clipmap_take_failure(nm->clip) : NULL;
}
