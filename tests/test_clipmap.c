/*
 * test_clipmap.c - clip windows and texture levels (core/src/clipmap.c) and the imagery block
 * cache (app/render/imagery_cache.c) without a GPU. The GPU side (toroidal uploads, the valid
 * regions after long flights) is test_clipmap_gl.c.
 */
#define _POSIX_C_SOURCE 200809L
#include "imagery_cache.h"
#include "tp_core.h"
#include "tp_test.h"

#include <math.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

TEST(slot_is_the_positive_remainder)
{
    for (int s = 2; s <= 16; s += 2)
        for (int64_t b = -100; b <= 100; b++) {
            int k = tp_clip_slot(b, s);
            EXPECT_TRUE(k >= 0 && k < s);
            EXPECT_EQ_INT((int)((b - k) % s), 0); /* b = k (mod s) */
        }
    EXPECT_EQ_INT(tp_clip_slot(INT64_C(1) << 40, 8), 0);
    EXPECT_EQ_INT(tp_clip_slot(-(INT64_C(1) << 40) - 3, 8), 5);
}

/* The centre lies at least s/2 - 1/2 blocks inside every edge, for points anywhere, negative
 * and huge included; and a window holds exactly its s x s blocks. */
TEST(window_is_centred_on_the_point)
{
    srand(7);
    for (int i = 0; i < 20000; i++) {
        int block = 1 << (rand() % 9), s = 2 * (1 + rand() % 8);
        double cx = (rand() / (double)RAND_MAX - 0.5) * 1e9, cy = (rand() % 5000) - 2500.25;
        tp_clip_window w = tp_clip_window_centred(cx, cy, block, s);
        EXPECT_EQ_INT(w.s, s);
        double margin = (s / 2.0 - 0.5) * block - 1e-6 * fabs(cx) - 1e-9;
        EXPECT_GE(cx - (double)w.bx0 * block, margin);
        EXPECT_GE((double)(w.bx0 + s) * block - cx, margin);
        EXPECT_GE(cy - (double)w.by0 * block, margin);
        EXPECT_GE((double)(w.by0 + s) * block - cy, margin);
        EXPECT_TRUE(tp_clip_window_contains(&w, w.bx0, w.by0));
        EXPECT_TRUE(tp_clip_window_contains(&w, w.bx0 + s - 1, w.by0 + s - 1));
        EXPECT_FALSE(tp_clip_window_contains(&w, w.bx0 + s, w.by0));
        EXPECT_FALSE(tp_clip_window_contains(&w, w.bx0, w.by0 - 1));
        ASSERT_NO_FAILURE();
    }
}

/* Two windows s/2 blocks apart share exactly the blocks of their overlap, in the same slots:
 * a toroidal update uploads only the blocks that are new. */
TEST(moving_a_window_keeps_the_slots_of_blocks_still_in_it)
{
    int s = 8;
    tp_clip_window a = tp_clip_window_centred(1000, 1000, 256, s);
    tp_clip_window b = tp_clip_window_centred(1000 + 3 * 256, 1000 - 256, 256, s);
    int shared = 0, new_blocks = 0;
    for (int64_t by = b.by0; by < b.by0 + s; by++)
        for (int64_t bx = b.bx0; bx < b.bx0 + s; bx++) {
            if (tp_clip_window_contains(&a, bx, by))
                shared++;
            else
                new_blocks++;
        }
    EXPECT_EQ_INT(shared, (s - 3) * (s - 1));
    EXPECT_EQ_INT(new_blocks, s * s - (s - 3) * (s - 1));
    /* the s x s blocks of any window fill the s x s slots once each */
    int used[64] = {0};
    for (int64_t by = b.by0; by < b.by0 + s; by++)
        for (int64_t bx = b.bx0; bx < b.bx0 + s; bx++)
            used[tp_clip_slot(by, s) * s + tp_clip_slot(bx, s)]++;
    for (int i = 0; i < s * s; i++)
        EXPECT_EQ_INT(used[i], 1);
}

typedef struct holes {
    int64_t x0, y0;
    uint8_t missing[32][32];
} holes;

static int hole_resident(void* user, int64_t bx, int64_t by)
{
    holes* h = user;
    return !h->missing[by - h->y0][bx - h->x0];
}

/* The valid rectangle holds only resident blocks of the window, contains the centre block and
 * cannot grow by any row or column (each side is blocked by the window's edge or a missing
 * block). Checked on random holes against a brute force of those three properties. */
TEST(valid_rect_is_resident_and_cannot_grow)
{
    srand(11);
    for (int trial = 0; trial < 3000; trial++) {
        int s = 2 * (1 + rand() % 8);
        tp_clip_window w = tp_clip_window_centred(rand() % 4000, rand() % 4000, 16, s);
        holes h;
        h.x0 = w.bx0 - 1, h.y0 = w.by0 - 1;
        int p = rand() % 30;
        for (int y = 0; y < 32; y++)
            for (int x = 0; x < 32; x++)
                h.missing[y][x] = rand() % 100 < p;
        double cx = (w.bx0 + s / 2) * 16.0 - 3, cy = (w.by0 + s / 2) * 16.0 + 5;
        int64_t r[4];
        int64_t cbx = (int64_t)floor(cx / 16), cby = (int64_t)floor(cy / 16);
        int ok = tp_clip_valid_rect(&w, cx, cy, 16, hole_resident, &h, r);
        if (h.missing[cby - h.y0][cbx - h.x0]) {
            EXPECT_FALSE(ok);
            continue;
        }
        ASSERT_TRUE(ok);
        EXPECT_TRUE(r[0] <= cbx && cbx < r[2] && r[1] <= cby && cby < r[3]);
        for (int64_t by = r[1]; by < r[3]; by++)
            for (int64_t bx = r[0]; bx < r[2]; bx++) {
                EXPECT_TRUE(tp_clip_window_contains(&w, bx, by));
                EXPECT_FALSE(h.missing[by - h.y0][bx - h.x0]);
            }
        /* each side: the next column / row has a block outside the window or missing */
        int64_t side[4][3] = {{r[2], 1, 0}, {r[3], 0, 0}, {r[0] - 1, 1, 0}, {r[1] - 1, 0, 0}};
        for (int k = 0; k < 4; k++) {
            int blocked = 0;
            int64_t c = side[k][0];
            int vertical = (int)side[k][1];
            for (int64_t i = vertical ? r[1] : r[0]; i < (vertical ? r[3] : r[2]); i++) {
                int64_t bx = vertical ? c : i, by = vertical ? i : c;
                if (!tp_clip_window_contains(&w, bx, by) || h.missing[by - h.y0][bx - h.x0])
                    blocked = 1;
            }
            EXPECT_TRUE(blocked);
        }
        ASSERT_NO_FAILURE();
    }
}

/* floor(log2(x)) from the exponent bits, against the libm definition on every power of two and
 * its neighbours, and on a million random ratios. */
TEST(texture_level_is_floor_log2)
{
    for (int e = 0; e < 40; e++) {
        float p = ldexpf(1.0f, e);
        EXPECT_EQ_INT(tp_texture_level(p, 100), e);
        EXPECT_EQ_INT(tp_texture_level(nextafterf(p, 0.0f), 100), e > 0 ? e - 1 : 0);
        EXPECT_EQ_INT(tp_texture_level(nextafterf(p, INFINITY), 100), e);
    }
    srand(3);
    for (int i = 0; i < 1000000; i++) {
        float x = (float)ldexp(1.0 + rand() / (RAND_MAX + 1.0), rand() % 60 - 10);
        int want = x < 1 ? 0 : (int)floor(log2((double)x));
        if (want > 30)
            want = 30;
        if (tp_texture_level(x, 30) != want) {
            ADD_FAILURE("level of %.9g: %d, floor(log2) %d", x, tp_texture_level(x, 30), want);
            break;
        }
    }
    EXPECT_EQ_INT(tp_texture_level(0.5f, 10), 0);
    EXPECT_EQ_INT(tp_texture_level(0.0f, 10), 0);
    EXPECT_EQ_INT(tp_texture_level(-8.0f, 10), 0);
    EXPECT_EQ_INT(tp_texture_level(NAN, 10), 0);
    EXPECT_EQ_INT(tp_texture_level(1e-40f, 10), 0); /* subnormal */
    EXPECT_EQ_INT(tp_texture_level(INFINITY, 10), 10);
    EXPECT_EQ_INT(tp_texture_level(3e38f, 7), 7);
}

/* A patch's level: distance / (focal * texel) texels per pixel; finer at once, coarser only
 * 1/8 past the boundary. */
TEST(patch_level_has_hysteresis)
{
    double focal = 623.5, texel = 2.5; /* texels per pixel = d / 1558.75 */
    EXPECT_EQ_INT(tp_patch_texture_level(1000, focal, texel, -1, 12), 0);
    EXPECT_EQ_INT(tp_patch_texture_level(4 * 1558.75, focal, texel, -1, 12), 2);
    EXPECT_EQ_INT(tp_patch_texture_level(4.1 * 1558.75, focal, texel, 1, 12), 1);  /* held */
    EXPECT_EQ_INT(tp_patch_texture_level(4.6 * 1558.75, focal, texel, 1, 12), 2);  /* past 1/8 */
    EXPECT_EQ_INT(tp_patch_texture_level(1.5 * 1558.75, focal, texel, 3, 12), 0);  /* finer at once */
    EXPECT_EQ_INT(tp_patch_texture_level(1e12, focal, texel, -1, 12), 12);
}

/* ---- the block cache ---- */

typedef struct counting_source {
    pthread_mutex_t mu;
    tp_block_key order[4096];
    int reads;
    int fail_level;            /* a block of this level fails to read */
    unsigned delay_us;
} counting_source;

static uint8_t texel_value(tp_block_key k, int c)
{
    return (uint8_t)(k.level * 31 + k.bx * 7 + k.by * 13 + c);
}

static int counting_read(void* user, tp_block_key k, uint8_t* rgba, tp_error* err)
{
    counting_source* s = user;
    if (s->delay_us) {
        struct timespec ts = {0, (long)s->delay_us * 1000};
        nanosleep(&ts, NULL);
    }
    pthread_mutex_lock(&s->mu);
    if (s->reads < 4096)
        s->order[s->reads] = k;
    s->reads++;
    pthread_mutex_unlock(&s->mu);
    if (k.level == s->fail_level) {
        tp_error_set(err, TP_ERR_BAD_DATA,
                     "test.tpi: block %lld,%lld of level %d fails its checksum", (long long)k.bx,
                     (long long)k.by, k.level);
        return 0;
    }
    for (int i = 0; i < 16 * 16 * 4; i++)
        rgba[i] = texel_value(k, i % 4);
    return 1;
}

static tp_block_source small_source(counting_source* cs)
{
    tp_block_source src = {.block = 16, .levels = 4, .read = counting_read, .user = cs};
    for (int l = 0; l < 4; l++)
        src.width[l] = src.height[l] = 1024 >> l;
    return src;
}

TEST(cache_reads_in_the_order_wanted_and_once)
{
    counting_source cs = {.mu = PTHREAD_MUTEX_INITIALIZER, .fail_level = -1};
    tp_block_source src = small_source(&cs);
    tp_error err = {{0}};
    tp_imagery_cache* c = tp_imagery_cache_create(&src, 64 * 1024, 0, &err);
    ASSERT_TRUE(c != NULL);
    tp_block_key want[20];
    for (int i = 0; i < 20; i++)
        want[i] = (tp_block_key){i % 3, 19 - i, i};
    tp_imagery_cache_want(c, want, 20);
    ASSERT_TRUE(tp_imagery_cache_wait(c, 10));
    tp_imagery_cache_want(c, want, 20); /* all in memory: nothing read again */
    ASSERT_TRUE(tp_imagery_cache_wait(c, 10));
    ASSERT_EQ_INT(cs.reads, 20);
    for (int i = 0; i < 20; i++) {
        EXPECT_EQ_INT(cs.order[i].level, want[i].level);
        EXPECT_EQ_INT((int)cs.order[i].bx, (int)want[i].bx);
        const uint8_t* px = tp_imagery_cache_get(c, want[i]);
        ASSERT_TRUE(px != NULL);
        EXPECT_EQ_INT(px[16 * 16 * 4 - 2], texel_value(want[i], 2));
    }
    tp_block_key other = {3, 1, 1};
    EXPECT_TRUE(tp_imagery_cache_get(c, other) == NULL);
    tp_imagery_cache_stats st;
    tp_imagery_cache_get_stats(c, &st);
    EXPECT_EQ_INT((int)st.resident_blocks, 20);
    EXPECT_EQ_INT((int)st.loads, 20);
    EXPECT_EQ_INT(st.pending, 0);
    tp_imagery_cache_destroy(c);
}

/* A new want list replaces the old one: blocks no longer wanted are not read. */
TEST(cache_want_replaces_the_queue)
{
    counting_source cs = {.mu = PTHREAD_MUTEX_INITIALIZER, .fail_level = -1, .delay_us = 2000};
    tp_block_source src = small_source(&cs);
    tp_error err = {{0}};
    tp_imagery_cache* c = tp_imagery_cache_create(&src, 1 << 20, 0, &err);
    ASSERT_TRUE(c != NULL);
    tp_block_key a[200], b[3] = {{0, 60, 60}, {0, 61, 60}, {0, 62, 60}};
    for (int i = 0; i < 200; i++)
        a[i] = (tp_block_key){0, i % 50, i / 50};
    tp_imagery_cache_want(c, a, 200);
    tp_imagery_cache_want(c, b, 3);
    ASSERT_TRUE(tp_imagery_cache_wait(c, 10));
    EXPECT_LE_INT(cs.reads, 5); /* the 3, and at most what was being read from a */
    for (int i = 0; i < 3; i++)
        EXPECT_TRUE(tp_imagery_cache_get(c, b[i]) != NULL);
    tp_imagery_cache_destroy(c);
}

/* Garbage collection frees the lowest scores first, never a kept block, down to a quarter of
 * the pool free. */
static double score_by_bx(void* user, tp_block_key k)
{
    (void)user;
    return k.by == 0 ? 1e300 : (double)k.bx; /* row 0: kept */
}

TEST(cache_collects_lowest_scores_first_and_keeps_the_windows)
{
    counting_source cs = {.mu = PTHREAD_MUTEX_INITIALIZER, .fail_level = -1};
    tp_block_source src = small_source(&cs);
    tp_error err = {{0}};
    /* 32 blocks of 1 KiB */
    tp_imagery_cache* c = tp_imagery_cache_create(&src, 32 * 1024, 1, &err);
    ASSERT_TRUE(c != NULL);
    for (int i = 0; i < 32; i++) {
        tp_block_key k = {0, i % 16, i / 16}; /* rows 0 and 1 */
        ASSERT_TRUE(tp_imagery_cache_load_now(c, k) != NULL);
    }
    tp_block_key extra = {0, 5, 5};
    EXPECT_TRUE(tp_imagery_cache_load_now(c, extra) == NULL); /* full */
    tp_imagery_cache_collect(c, score_by_bx, NULL, 1e300);
    tp_imagery_cache_stats st;
    tp_imagery_cache_get_stats(c, &st);
    EXPECT_EQ_INT((int)st.resident_blocks, 24); /* a quarter freed */
    EXPECT_EQ_INT((int)st.evictions, 8);
    for (int bx = 0; bx < 16; bx++) {
        tp_block_key kept = {0, bx, 0}, row1 = {0, bx, 1};
        EXPECT_TRUE(tp_imagery_cache_get(c, kept) != NULL);
        EXPECT_TRUE((tp_imagery_cache_get(c, row1) != NULL) == (bx >= 8)); /* lowest bx went */
    }
    EXPECT_TRUE(tp_imagery_cache_load_now(c, extra) != NULL);
    tp_imagery_cache_destroy(c);
}

/* A block that fails to read is reported once and reads as transparent. */
TEST(cache_failed_block_is_transparent_and_reported_once)
{
    counting_source cs = {.mu = PTHREAD_MUTEX_INITIALIZER, .fail_level = 2};
    tp_block_source src = small_source(&cs);
    tp_error err = {{0}};
    tp_imagery_cache* c = tp_imagery_cache_create(&src, 64 * 1024, 0, &err);
    ASSERT_TRUE(c != NULL);
    tp_block_key k[2] = {{2, 3, 4}, {2, 4, 4}};
    tp_imagery_cache_want(c, k, 2);
    ASSERT_TRUE(tp_imagery_cache_wait(c, 10));
    const uint8_t* px = tp_imagery_cache_get(c, k[0]);
    ASSERT_TRUE(px != NULL);
    for (int i = 0; i < 16 * 16 * 4; i++)
        if (px[i] != 0) {
            ADD_FAILURE("texel byte %d of a failed block is %d", i, px[i]);
            break;
        }
    const char* f = tp_imagery_cache_take_failure(c);
    ASSERT_TRUE(f != NULL);
    EXPECT_CONTAINS(f, "test.tpi: block 3,4 of level 2");
    EXPECT_TRUE(tp_imagery_cache_take_failure(c) == NULL);
    tp_imagery_cache_stats st;
    tp_imagery_cache_get_stats(c, &st);
    EXPECT_EQ_INT(st.failed, 2);
    tp_imagery_cache_destroy(c);
}

#define TESTS(X)                                                                                   \
    X(slot_is_the_positive_remainder)                                                              \
    X(window_is_centred_on_the_point)                                                              \
    X(moving_a_window_keeps_the_slots_of_blocks_still_in_it)                                       \
    X(valid_rect_is_resident_and_cannot_grow)                                                      \
    X(texture_level_is_floor_log2)                                                                 \
    X(patch_level_has_hysteresis)                                                                  \
    X(cache_reads_in_the_order_wanted_and_once)                                                    \
    X(cache_want_replaces_the_queue)                                                               \
    X(cache_collects_lowest_scores_first_and_keeps_the_windows)                                    \
    X(cache_failed_block_is_transparent_and_reported_once)

TP_TEST_MAIN(TESTS)
