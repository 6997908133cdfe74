/* clipmap.c - imagery on the GPU through a clipmap (see clipmap.h). */
#define _POSIX_C_SOURCE 200809L
#include "clipmap.h"
#include "clock.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define NO_BLOCK UINT64_MAX
#define KEEP 1e300 /* blocks a window lacks: never collected */

typedef struct level {
    tp_clip_window w, pre;   /* the window, and where it will be (prefetch) */
    double cx, cy;           /* clip centre, level texels */
    uint64_t* tag;           /* per slot: the block it holds (packed key), NO_BLOCK */
    int valid;
    int64_t rect[4];         /* valid blocks */
} level;

struct tp_clipmap {
    tp_block_source src;
    tp_imagery_cache* cache;
    double gt[6];
    int levels, s, block, size;
    size_t upload_cap;
    double prefetch_s, frame_s;
    GLuint tex;
    level lv[TP_RENDER_CLIP_LEVELS];
    int first;
    uint8_t* zeros;          /* a transparent block */
    tp_block_key* want;
    size_t want_cap;
    /* motion of the camera in level-0 texels per second, from the last update */
    double last_u, last_v, last_t, vel_u, vel_v;
    int have_last;
    double clock_s;
};

static uint64_t key_of(int l, int64_t bx, int64_t by)
{
    return ((uint64_t)l << 58) | ((uint64_t)bx << 29) | (uint64_t)by;
}

static int in_extent(const tp_clipmap* m, int l, int64_t bx, int64_t by)
{
    int64_t b = m->block;
    return bx >= 0 && by >= 0 && bx * b < m->src.width[l] && by * b < m->src.height[l];
}

typedef struct resident_ctx {
    const tp_clipmap* m;
    int l;
} resident_ctx;

/* Outside the image a block counts as resident: the renderer's rectangle stops at the image. */
static int resident(void* user, int64_t bx, int64_t by)
{
    const resident_ctx* r = user;
    if (!in_extent(r->m, r->l, bx, by))
        return 1;
    const level* v = &r->m->lv[r->l];
    return v->tag[tp_clip_slot(by, v->w.s) * v->w.s + tp_clip_slot(bx, v->w.s)] ==
           key_of(r->l, bx, by);
}

static void upload(tp_clipmap* m, int l, int64_t bx, int64_t by, const uint8_t* px)
{
    level* v = &m->lv[l];
    int sx = tp_clip_slot(bx, m->s), sy = tp_clip_slot(by, m->s);
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, sx * m->block, sy * m->block, l, m->block, m->block,
                    1, GL_RGBA, GL_UNSIGNED_BYTE, px);
    v->tag[sy * m->s + sx] = key_of(l, bx, by);
}

void tp_clipmap_destroy(tp_clipmap* m)
{
    if (!m)
        return;
    tp_imagery_cache_destroy(m->cache);
    if (m->tex)
        glDeleteTextures(1, &m->tex);
    for (int l = 0; l < TP_RENDER_CLIP_LEVELS; l++)
        free(m->lv[l].tag);
    free(m->zeros);
    free(m->want);
    free(m);
}

tp_clipmap* tp_clipmap_create(const tp_block_source* src, const double gt[6],
                              const tp_clipmap_options* o, tp_error* err)
{
    tp_clipmap_options d = {0};
    if (!o)
        o = &d;
    tp_clipmap* m = calloc(1, sizeof *m);
    if (!m) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    m->src = *src;
    memcpy(m->gt, gt, sizeof m->gt);
    m->s = o->clip_blocks > 0 ? o->clip_blocks : 4;
    m->block = src->block;
    m->size = m->s * m->block;
    m->levels = src->levels < TP_RENDER_CLIP_LEVELS ? src->levels : TP_RENDER_CLIP_LEVELS;
    size_t block_bytes = (size_t)m->block * m->block * 4;
    m->upload_cap = o->upload_cap_bytes ? o->upload_cap_bytes : 8 * block_bytes;
    m->prefetch_s = o->prefetch_s > 0 ? o->prefetch_s : 0.5;
    m->frame_s = o->frame_s;
    m->zeros = calloc(1, block_bytes);
    for (int l = 0; l < m->levels; l++) {
        m->lv[l].tag = malloc((size_t)m->s * m->s * sizeof *m->lv[l].tag);
        if (m->lv[l].tag)
            for (int i = 0; i < m->s * m->s; i++)
                m->lv[l].tag[i] = NO_BLOCK;
    }
    for (int l = 0; l < m->levels; l++)
        if (!m->lv[l].tag || !m->zeros) {
            tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
            tp_clipmap_destroy(m);
            return NULL;
        }
    GLint layers = 0, max_size = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &layers);
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max_size);
    if (layers < m->levels || max_size < m->size) {
        tp_error_set(
            err, TP_ERR_BACKEND,
            "the GPU holds %d texture layers of %d texels at most; the clipmap needs %d of %d",
            layers, max_size, m->levels, m->size);
        tp_clipmap_destroy(m);
        return NULL;
    }
    while (glGetError() != GL_NO_ERROR) {
    }
    glGenTextures(1, &m->tex);
    glBindTexture(GL_TEXTURE_2D_ARRAY, m->tex);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA8, m->size, m->size, m->levels, 0, GL_RGBA,
                 GL_UNSIGNED_BYTE, NULL);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_REPEAT);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, 0);
    if (glGetError() != GL_NO_ERROR) {
        tp_error_set(err, TP_ERR_BACKEND,
                     "the GPU cannot hold the clipmap (%d layers of %dx%d RGBA)", m->levels,
                     m->size, m->size);
        tp_clipmap_destroy(m);
        return NULL;
    }
    m->cache = tp_imagery_cache_create(src, o->cache_bytes ? o->cache_bytes : (size_t)64 << 20,
                                       o->no_loader, err);
    if (!m->cache) {
        tp_clipmap_destroy(m);
        return NULL;
    }
    /* The coarsest levels a window holds whole, now: every later frame has something to show. */
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    for (int l = m->levels - 1; l >= 0; l--) {
        int64_t bw = (m->src.width[l] + m->block - 1) / m->block;
        int64_t bh = (m->src.height[l] + m->block - 1) / m->block;
        if (bw > m->s || bh > m->s)
            break;
        level* v = &m->lv[l];
        v->w.s = m->s;
        v->w.bx0 = v->w.by0 = 0;
        v->cx = m->src.width[l] / 2.0;
        v->cy = m->src.height[l] / 2.0;
        for (int64_t by = 0; by < bh; by++)
            for (int64_t bx = 0; bx < bw; bx++) {
                tp_block_key k = {l, bx, by};
                int empty = m->src.is_empty && m->src.is_empty(m->src.user, k);
                const uint8_t* px = empty ? m->zeros : tp_imagery_cache_load_now(m->cache, k);
                upload(m, l, bx, by, px ? px : m->zeros);
            }
    }
    return m;
}

static int push_want(tp_clipmap* m, size_t* n, tp_block_key k)
{
    if (*n == m->want_cap) {
        size_t c = m->want_cap ? 2 * m->want_cap : 256;
        tp_block_key* w = realloc(m->want, c * sizeof *w);
        if (!w)
            return 0;
        m->want = w;
        m->want_cap = c;
    }
    m->want[(*n)++] = k;
    return 1;
}

typedef struct ranked {
    double d;
    tp_block_key k;
} ranked;

static int by_d(const void* a, const void* b)
{
    double x = ((const ranked*)a)->d, y = ((const ranked*)b)->d;
    return (x > y) - (x < y);
}

/* Appends the blocks of window w (level l) in the image and not resident (not_in: also not in
 * that window, for the prefetch), nearest the centre (cx, cy) first. */
static void want_window(tp_clipmap* m, int l, const tp_clip_window* w, double cx, double cy,
                        const tp_clip_window* not_in, size_t* n)
{
    ranked r[32 * 32];
    int count = 0;
    resident_ctx rc = {m, l};
    for (int64_t by = w->by0; by < w->by0 + w->s; by++)
        for (int64_t bx = w->bx0; bx < w->bx0 + w->s; bx++) {
            if (!in_extent(m, l, bx, by) || (not_in && tp_clip_window_contains(not_in, bx, by)) ||
                (!not_in && resident(&rc, bx, by)))
                continue;
            double dx = (bx + 0.5) * m->block - cx, dy = (by + 0.5) * m->block - cy;
            r[count++] = (ranked){dx * dx + dy * dy, {l, bx, by}};
        }
    qsort(r, (size_t)count, sizeof *r, by_d);
    for (int i = 0; i < count; i++)
        push_want(m, n, r[i].k);
}

/* Garbage collection (Luo & Duan section 3.4): a block a current window still lacks is kept;
 * a block of a predicted window comes next (it will be uploaded soon); of the rest (blocks
 * already on the GPU included: their copy in RAM only saves a read when the view returns), the
 * one farthest behind the motion goes first (the most negative projection of its offset from
 * the clip centre on the direction of motion), by distance when the camera stands still;
 * levels not kept at all (finer than first) before any. */
static double gc_score(void* user, tp_block_key k)
{
    const tp_clipmap* m = user;
    if (k.level >= m->levels || k.level < m->first)
        return -1e200;
    const level* v = &m->lv[k.level];
    resident_ctx rc = {m, k.level};
    if (tp_clip_window_contains(&v->w, k.bx, k.by) && !resident(&rc, k.bx, k.by))
        return KEEP;
    if (tp_clip_window_contains(&v->pre, k.bx, k.by) && !tp_clip_window_contains(&v->w, k.bx, k.by))
        return 1e200;
    double dx = ((k.bx + 0.5) * m->block - v->cx) / m->size;
    double dy = ((k.by + 0.5) * m->block - v->cy) / m->size;
    double speed = hypot(m->vel_u, m->vel_v);
    if (speed > 0)
        return (dx * m->vel_u + dy * m->vel_v) / speed;
    return -hypot(dx, dy);
}

static void update(tp_clipmap* m, const tp_camera* cam, int finest_level, int capped,
                   tp_clipmap_stats* st)
{
    memset(st, 0, sizeof *st);
    double t = m->frame_s > 0 ? (m->clock_s += m->frame_s) : tp_clock_s();
    /* the camera in level-0 texels, and where it looks (horizontally) */
    double u = (cam->position[0] - m->gt[0]) / m->gt[1];
    double v = (cam->position[1] - m->gt[3]) / m->gt[5];
    double fu = cam->forward[0] * (m->gt[1] > 0 ? 1 : -1);
    double fv = cam->forward[1] * (m->gt[5] > 0 ? 1 : -1);
    double fl = hypot(fu, fv);
    if (fl > 1e-9)
        fu /= fl, fv /= fl;
    else
        fu = fv = 0;
    if (m->have_last && t > m->last_t) {
        m->vel_u = (u - m->last_u) / (t - m->last_t);
        m->vel_v = (v - m->last_v) / (t - m->last_t);
    }
    m->last_u = u, m->last_v = v, m->last_t = t, m->have_last = 1;
    m->first = finest_level < 0 ? 0 : finest_level >= m->levels ? m->levels - 1 : finest_level;

    size_t n = 0;
    for (int l = m->levels - 1; l >= m->first; l--) {
        level* lv = &m->lv[l];
        double scale = ldexp(1.0, -l);
        lv->cx = u * scale + fu * m->size / 4.0;
        lv->cy = v * scale + fv * m->size / 4.0;
        lv->w = tp_clip_window_centred(lv->cx, lv->cy, m->block, m->s);
        want_window(m, l, &lv->w, lv->cx, lv->cy, NULL, &n);
    }
    size_t current = n;
    for (int l = m->levels - 1; l >= m->first; l--) {
        level* lv = &m->lv[l];
        double scale = ldexp(1.0, -l);
        double px = lv->cx + m->vel_u * scale * m->prefetch_s;
        double py = lv->cy + m->vel_v * scale * m->prefetch_s;
        lv->pre = tp_clip_window_centred(px, py, m->block, m->s);
        want_window(m, l, &lv->pre, px, py, &lv->w, &n);
    }
    for (int l = 0; l < m->first; l++)
        m->lv[l].pre = m->lv[l].w = (tp_clip_window){0, 0, 0};

    /* uploads: the current windows' missing blocks in order, within the cap */
    glBindTexture(GL_TEXTURE_2D_ARRAY, m->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    double t0 = tp_clock_s();
    size_t block_bytes = (size_t)m->block * m->block * 4;
    for (size_t i = 0; i < current; i++) {
        if (capped && st->upload_bytes + block_bytes > m->upload_cap) {
            st->missing += (int)(current - i);
            break;
        }
        tp_block_key k = m->want[i];
        int empty = m->src.is_empty && m->src.is_empty(m->src.user, k);
        const uint8_t* px = empty ? m->zeros : tp_imagery_cache_get(m->cache, k);
        if (!px) {
            st->missing++;
            continue;
        }
        upload(m, k.level, k.bx, k.by, px);
        st->uploads++;
        st->upload_bytes += block_bytes;
    }
    st->upload_ms = (tp_clock_s() - t0) * 1e3;
    tp_imagery_cache_want(m->cache, m->want, n);

    /* each level's valid region, grown from its clip centre */
    for (int l = 0; l < m->levels; l++) {
        level* lv = &m->lv[l];
        resident_ctx rc = {m, l};
        lv->valid = l >= m->first &&
                    tp_clip_valid_rect(&lv->w, lv->cx, lv->cy, m->block, resident, &rc, lv->rect);
        st->valid_levels += lv->valid;
    }
    tp_imagery_cache_collect(m->cache, gc_score, m, KEEP);

    tp_imagery_cache_stats cs;
    tp_imagery_cache_get_stats(m->cache, &cs);
    st->pending = cs.pending;
    st->first_level = m->first;
    st->gpu_bytes = (size_t)m->size * m->size * 4 * m->levels;
    st->cache_bytes = cs.resident_blocks * cs.block_bytes;
    st->loads = cs.loads;
    st->evictions = cs.evictions;
}

void tp_clipmap_update(tp_clipmap* m, const tp_camera* cam, int finest_level,
                       tp_clipmap_stats* st)
{
    update(m, cam, finest_level, 1, st);
}

void tp_clipmap_settle(tp_clipmap* m, const tp_camera* cam, int finest_level, double timeout_s,
                       tp_clipmap_stats* st)
{
    double until = tp_clock_s() + timeout_s;
    double frame_s = m->frame_s;
    m->frame_s = 0; /* the camera does not move while settling */
    update(m, cam, finest_level, 0, st);
    while (st->missing > 0 && tp_clock_s() < until) {
        tp_imagery_cache_wait(m->cache, 0.05);
        update(m, cam, finest_level, 0, st);
    }
    m->frame_s = frame_s;
}

void tp_clipmap_render_clip(const tp_clipmap* m, tp_render_clip* out)
{
    memset(out, 0, sizeof *out);
    out->texture = m->tex;
    out->levels = m->levels;
    out->size = m->size;
    out->first = m->first;
    memcpy(out->geotransform, m->gt, sizeof out->geotransform);
    for (int l = 0; l < m->levels; l++) {
        const level* v = &m->lv[l];
        double* r = out->rect[l];
        if (!v->valid) {
            r[0] = r[1] = r[2] = r[3] = 0;
            continue;
        }
        /* blocks to texels, cut at the level's edge */
        r[0] = fmax(0.0, (double)(v->rect[0] * m->block));
        r[1] = fmax(0.0, (double)(v->rect[1] * m->block));
        r[2] = fmin((double)m->src.width[l], (double)(v->rect[2] * m->block));
        r[3] = fmin((double)m->src.height[l], (double)(v->rect[3] * m->block));
    }
}

int tp_clipmap_finest_level(const tp_clipmap* m, const tp_camera* cam, const double* distances_m,
                            size_t count, int previous)
{
    tp_camera_frame f;
    tp_camera_get_frame(cam, &f);
    double texel_m = fmin(fabs(m->gt[1]), fabs(m->gt[5]));
    int finest = m->levels - 1;
    for (size_t i = 0; i < count; i++) {
        int l = tp_texture_level((float)(distances_m[i] / (f.focal_px * texel_m)), m->levels - 1);
        if (l < finest)
            finest = l;
    }
    /* frame coherence: coarser than last frame only when clearly so */
    if (previous >= 0 && finest > previous) {
        int relaxed = m->levels - 1;
        for (size_t i = 0; i < count; i++) {
            int l = tp_patch_texture_level(distances_m[i], f.focal_px, texel_m, previous,
                                           m->levels - 1);
            if (l < relaxed)
                relaxed = l;
        }
        finest = relaxed;
    }
    return finest;
}

const char* tp_clipmap_take_failure(tp_clipmap* m)
{
    return tp_imagery_cache_take_failure(m->cache);
}
