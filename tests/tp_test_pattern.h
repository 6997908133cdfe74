/*
 * tp_test_pattern.h - a pattern image pyramid for the GPU imagery tests (test_clipmap_gl.c,
 * test_imagery_blocks_gl.c): every texel of level l at (u, v) is a hash of (l, u, v), opaque;
 * every 7th block of a level is empty (transparent and never read); outside a level's size
 * texels are 0. A texture read back from the GPU can so be checked texel by texel against the
 * value it must hold, computed here without the code under test. Also the headless GL context
 * those tests need (skipped where there is none).
 */
#ifndef TP_TEST_PATTERN_H
#define TP_TEST_PATTERN_H

#include "gl_context.h"
#include "imagery_cache.h"
#include "tp_test.h"

#include <stdint.h>
#include <string.h>

#define TP_PATTERN_BLOCK 256

typedef struct tp_test_pattern {
    int64_t w[TP_CLIP_MAX_LEVELS], h[TP_CLIP_MAX_LEVELS]; /* texels per level */
} tp_test_pattern;

static inline uint32_t tp_test_texel_hash(int l, int64_t u, int64_t v)
{
    uint64_t x = (uint64_t)l * 0x9E3779B97F4A7C15ull ^ (uint64_t)u * 0xC2B2AE3D27D4EB4Full ^
                 (uint64_t)v * 0x165667B19E3779F9ull;
    x ^= x >> 29;
    x *= 0xBF58476D1CE4E5B9ull;
    x ^= x >> 32;
    return (uint32_t)x | 0xFF000000u; /* opaque */
}

static inline int tp_test_pattern_empty(void* user, tp_block_key k)
{
    (void)user;
    return (k.bx * 3 + k.by * 5 + k.level) % 7 == 3;
}

/* The pyramid's texel (level, u, v) as RGBA8 in memory order. */
static inline uint32_t tp_test_pattern_texel(const tp_test_pattern* p, int l, int64_t u, int64_t v)
{
    if (u < 0 || v < 0 || u >= p->w[l] || v >= p->h[l])
        return 0;
    tp_block_key k = {l, u / TP_PATTERN_BLOCK, v / TP_PATTERN_BLOCK};
    return tp_test_pattern_empty(NULL, k) ? 0 : tp_test_texel_hash(l, u, v);
}

static inline int tp_test_pattern_read(void* user, tp_block_key k, uint8_t* rgba, tp_error* err)
{
    (void)err;
    const tp_test_pattern* p = user;
    for (int y = 0; y < TP_PATTERN_BLOCK; y++)
        for (int x = 0; x < TP_PATTERN_BLOCK; x++) {
            uint32_t c = tp_test_pattern_texel(p, k.level, k.bx * TP_PATTERN_BLOCK + x,
                                               k.by * TP_PATTERN_BLOCK + y);
            memcpy(rgba + ((size_t)y * TP_PATTERN_BLOCK + x) * 4, &c, 4);
        }
    return 1;
}

/* A pyramid of w x h texels at level 0, halved (rounding up) down to one block. */
static inline tp_block_source tp_test_pattern_source(tp_test_pattern* p, int64_t w, int64_t h)
{
    tp_block_source s = {.block = TP_PATTERN_BLOCK, .read = tp_test_pattern_read,
                         .is_empty = tp_test_pattern_empty, .user = p};
    for (s.levels = 0;; s.levels++) {
        s.width[s.levels] = p->w[s.levels] = w;
        s.height[s.levels] = p->h[s.levels] = h;
        if (w <= TP_PATTERN_BLOCK && h <= TP_PATTERN_BLOCK)
            break;
        w = (w + 1) / 2, h = (h + 1) / 2;
    }
    s.levels++;
    return s;
}

static inline tp_gl_context* tp_test_gl_context_or_skip(void)
{
    tp_gl_context* ctx = NULL;
    tp_error err = {{0}};
    if (!tp_gl_context_create_headless(64, 64, &ctx, &err))
        SKIP("no headless OpenGL here: %s", err.message);
    return ctx;
}

#endif /* TP_TEST_PATTERN_H */
