/*
 * imagery_cache.h - blocks of an image pyramid in memory as the clipmap needs them (issue 15;
 * Luo & Duan sections 3.3-3.4).
 *
 * A loader thread reads and decodes blocks (the source's read: for a .tpi, pread + CRC32 +
 * zstd) into a fixed pool of block buffers (the budget); the render thread tells it once per
 * frame which blocks it wants, most urgent first (tp_imagery_cache_want: the blocks the clip
 * windows lack, then the prefetch for where the windows will be), takes finished ones
 * (tp_imagery_cache_get) and, when the pool runs short, frees the blocks least worth keeping
 * (tp_imagery_cache_collect: by the score the clipmap gives, which is the direction of the clip
 * centre's motion, not plain LRU). Only the render thread frees buffers, so a pointer from
 * tp_imagery_cache_get stays valid until its next tp_imagery_cache_collect. A block whose read
 * fails is reported once (tp_imagery_cache_take_failure) and then reads as transparent.
 */
#ifndef TP_APP_VIEW_IMAGERY_CACHE_H
#define TP_APP_VIEW_IMAGERY_CACHE_H

#include "tp_core.h"

#include <stddef.h>
#include <stdint.h>

#define TP_CLIP_MAX_LEVELS 32

/* One block of a level: bx, by in 0 .. 2^28 - 1, level in 0 .. 31. */
typedef struct tp_block_key {
    int level;
    int64_t bx, by;
} tp_block_key;

/* Where blocks come from (a .tpi, or a test's pattern). */
typedef struct tp_block_source {
    int block;                                /* texels a side */
    int levels;
    int64_t width[TP_CLIP_MAX_LEVELS], height[TP_CLIP_MAX_LEVELS]; /* texels per level */
    /* Reads block k into rgba (block * block * 4 bytes, top row first); 1, or 0 with a message
     * in err (which may be NULL). Called on the loader thread and on the caller's by
     * tp_imagery_cache_load_now: must be thread-safe. */
    int (*read)(void* user, tp_block_key k, uint8_t* rgba, tp_error* err);
    /* 1 when block k is wholly transparent (no read needed); NULL: never. */
    int (*is_empty)(void* user, tp_block_key k);
    void* user;
} tp_block_source;

typedef struct tp_imagery_cache tp_imagery_cache;

typedef struct tp_imagery_cache_stats {
    size_t capacity_blocks, resident_blocks, block_bytes;
    size_t loads;       /* blocks read, in total */
    size_t evictions;   /* blocks freed by tp_imagery_cache_collect, in total */
    int pending;        /* wanted and not read yet (queued or being read) */
    int failed;         /* blocks whose read failed, in total */
} tp_imagery_cache_stats;

/* budget_bytes: the pool (at least 16 blocks); no_loader: tests, nothing is read in the
 * background (only tp_imagery_cache_load_now). NULL with a message in err on failure. */
tp_imagery_cache* tp_imagery_cache_create(const tp_block_source* src, size_t budget_bytes,
                                          int no_loader, tp_error* err);
void tp_imagery_cache_destroy(tp_imagery_cache* c); /* stops the loader; accepts NULL */

/* Replaces the loader's queue with keys (most urgent first); keys already in memory or being
 * read are skipped. Render thread. */
void tp_imagery_cache_want(tp_imagery_cache* c, const tp_block_key* keys, size_t count);

/* The block's texels when in memory (transparent zeros for a failed read), else NULL. */
const uint8_t* tp_imagery_cache_get(tp_imagery_cache* c, tp_block_key k);

/* Reads k now on the calling thread if it is not in memory (waits when the loader is reading
 * it). NULL when the pool is full of blocks being read (cannot happen between frames). */
const uint8_t* tp_imagery_cache_load_now(tp_imagery_cache* c, tp_block_key k);

/* Frees blocks until at least a quarter of the pool is free, lowest score first, never one
 * whose score is >= keep_score (the clip windows' own blocks). Render thread. */
void tp_imagery_cache_collect(tp_imagery_cache* c, double (*score)(void* user, tp_block_key k),
                              void* user, double keep_score);

/* Waits until the loader has read every wanted block (tests, headless runs), at most
 * timeout_s. Returns 1 when nothing is pending. */
int tp_imagery_cache_wait(tp_imagery_cache* c, double timeout_s);

/* The first read failure not reported yet (one line naming the file and block), or NULL. */
const char* tp_imagery_cache_take_failure(tp_imagery_cache* c);

void tp_imagery_cache_get_stats(const tp_imagery_cache* c, tp_imagery_cache_stats* out);

#endif /* TP_APP_VIEW_IMAGERY_CACHE_H */
