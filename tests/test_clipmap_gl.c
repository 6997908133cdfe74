/*
 * test_clipmap_gl.c - the clipmap on a GPU (app/render/clipmap.c through Mesa llvmpipe, EGL
 * without a display): after long flights (fast, turning, reversing, jumping, with the upload cap
 * and a real loader thread) every texel the shader may sample (each level's valid region) holds
 * exactly its own texel of the pyramid: no stale strips, no block in the wrong slot, no seam at
 * the toroidal wrap. The pyramid is a pattern whose every texel is a function of (level, u, v),
 * so the texture array read back from the GPU is compared with the direct value of every texel.
 */
#define _POSIX_C_SOURCE 200809L
#include "clipmap.h"
#include "gl_context.h"
#include "tp_test.h"
#include "tp_test_pattern.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define BLOCK TP_PATTERN_BLOCK
#define PI 3.14159265358979323846

/* Reads the array back and checks every texel of every valid region; returns the texels
 * checked. */
static size_t check_valid_regions(tp_clipmap* m, const tp_block_source* src)
{
    tp_render_clip rc;
    tp_clipmap_render_clip(m, &rc);
    size_t layer = (size_t)rc.size * rc.size;
    uint32_t* px = malloc(layer * rc.levels * 4);
    if (!px)
        FAIL("out of memory");
    glBindTexture(GL_TEXTURE_2D_ARRAY, rc.texture);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTexImage(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
    size_t checked = 0;
    int bad = 0;
    for (int l = 0; l < rc.levels && !bad; l++) {
        const double* r = rc.rect[l];
        if (r[2] <= r[0])
            continue;
        /* inside the level, whole texels */
        if (r[0] < 0 || r[1] < 0 || r[2] > src->width[l] || r[3] > src->height[l]) {
            ADD_FAILURE("level %d: valid region %g..%g x %g..%g outside the level's %lldx%lld", l,
                        r[0], r[2], r[1], r[3], (long long)src->width[l], (long long)src->height[l]);
            break;
        }
        for (int64_t v = (int64_t)r[1]; v < (int64_t)r[3] && !bad; v++)
            for (int64_t u = (int64_t)r[0]; u < (int64_t)r[2]; u++) {
                tp_block_key k = {l, u / BLOCK, v / BLOCK};
                uint32_t want = tp_test_pattern_empty(NULL, k) ? 0 : tp_test_texel_hash(l, u, v);
                uint32_t got = px[(size_t)l * layer + (size_t)(v % rc.size) * rc.size + (u % rc.size)];
                checked++;
                if (got != want) {
                    ADD_FAILURE("level %d texel (%lld, %lld): 0x%08x in the GPU, 0x%08x in the pyramid",
                                l, (long long)u, (long long)v, got, want);
                    bad = 1;
                    break;
                }
            }
    }
    free(px);
    return checked;
}

static void camera_at(double e, double n, double h, double yaw, tp_camera* cam)
{
    double p[3] = {e, n, h};
    tp_camera_from_pose(p, yaw, -30, 60, 1280, 720, cam);
}

typedef struct flight_leg {
    double speed_mps, yaw_deg, seconds;
    int jump;           /* teleport by speed * seconds first, no frames in between */
} flight_leg;

/* Flies the legs at 30 frames a second (the clipmap's clock steps 1/30 s a frame), checking the
 * valid regions every check_every frames; settles at the end and checks that every window is
 * whole. */
static void fly(const tp_clipmap_options* o, const flight_leg* legs, int leg_count,
                int check_every, int expect_evictions)
{
    tp_gl_context* ctx = tp_test_gl_context_or_skip();
    tp_test_pattern p; /* 9 levels; not a multiple of the block */
    tp_block_source src = tp_test_pattern_source(&p, 40000, 30011);
    double gt[6] = {500000, 1, 0, 5030011, 0, -1}; /* 1 m texels */
    tp_error err = {{0}};
    tp_clipmap* m = tp_clipmap_create(&src, gt, o, &err);
    ASSERT_TRUE(m != NULL);
    double e = 510000, n = 5010000;
    tp_camera cam;
    int frame = 0;
    size_t checked = 0, gpu_bytes = 0;
    tp_clipmap_stats st;
    for (int i = 0; i < leg_count; i++) {
        double a = legs[i].yaw_deg * PI / 180;
        if (legs[i].jump) {
            e += sin(a) * legs[i].speed_mps * legs[i].seconds;
            n += cos(a) * legs[i].speed_mps * legs[i].seconds;
            continue;
        }
        int frames = (int)(legs[i].seconds * 30);
        for (int f = 0; f < frames; f++, frame++) {
            e += sin(a) * legs[i].speed_mps / 30;
            n += cos(a) * legs[i].speed_mps / 30;
            camera_at(e, n, 400, legs[i].yaw_deg, &cam);
            tp_clipmap_update(m, &cam, 0, &st);
            if (gpu_bytes == 0)
                gpu_bytes = st.gpu_bytes;
            EXPECT_EQ_INT((int)st.gpu_bytes, (int)gpu_bytes);
            EXPECT_LE_INT((int)st.upload_bytes, (int)(o->upload_cap_bytes ? o->upload_cap_bytes
                                                                          : 8u * BLOCK * BLOCK * 4));
            if (frame % check_every == 0)
                checked += check_valid_regions(m, &src);
            ASSERT_NO_FAILURE();
        }
    }
    tp_clipmap_settle(m, &cam, 0, 30, &st);
    EXPECT_EQ_INT(st.missing, 0);
    checked += check_valid_regions(m, &src);
    /* settled: every level's valid region is its whole window, cut at the image */
    tp_render_clip rc;
    tp_clipmap_render_clip(m, &rc);
    double u = (e - gt[0]) / gt[1], v = (n - gt[3]) / gt[5];
    for (int l = 0; l < rc.levels; l++) {
        const double* r = rc.rect[l];
        double ul = ldexp(u, -l), vl = ldexp(v, -l);
        if (ul >= 0 && vl >= 0 && ul < src.width[l] && vl < src.height[l]) {
            EXPECT_TRUE(r[0] <= ul && ul < r[2] && r[1] <= vl && vl < r[3]);
            EXPECT_GE(fmin(r[2], (double)src.width[l]) - r[0],
                      fmin((double)rc.size, (double)src.width[l]) - BLOCK); /* not shrunk */
        }
    }
    EXPECT_GT((double)checked, 1e6);
    EXPECT_EQ_INT((int)gpu_bytes, rc.size * rc.size * 4 * src.levels); /* whatever the image size */
    if (expect_evictions)
        EXPECT_GT((double)st.evictions, 0);
    tp_clipmap_destroy(m);
    tp_gl_context_destroy(ctx);
}

TEST(long_fast_flight_never_shows_stale_texels)
{
    flight_leg legs[] = {
        {1500, 90, 4, 0},   /* east, 6 km */
        {1500, 30, 3, 0},   /* turning */
        {2500, 200, 3, 0},  /* back south-west, faster than the cap keeps up with */
        {0, 0, 1, 0},       /* hovering */
        {9000, 135, 1, 1},  /* a jump of 9 km */
        {800, 315, 4, 0},
    };
    tp_clipmap_options o = {0};
    fly(&o, legs, 6, 9, 0);
}

/* A pool of 16 blocks (4 MiB) for 9 levels of 16-block windows: blocks are collected and read
 * again all the time, and what the GPU holds is still exact. */
TEST(small_cache_collects_and_stays_exact)
{
    flight_leg legs[] = {{1200, 60, 5, 0}, {1200, 240, 5, 0}, {1200, 150, 3, 0}};
    tp_clipmap_options o = {.cache_bytes = 16 * BLOCK * BLOCK * 4, .upload_cap_bytes = 4 * BLOCK * BLOCK * 4};
    fly(&o, legs, 3, 15, 1);
}

/* Windows of 8 x 8 blocks (2048 texels), one block uploaded a frame at most. */
TEST(wide_windows_with_one_block_a_frame)
{
    flight_leg legs[] = {{600, 0, 4, 0}, {600, 100, 4, 0}};
    tp_clipmap_options o = {.clip_blocks = 8, .upload_cap_bytes = BLOCK * BLOCK * 4};
    fly(&o, legs, 2, 20, 0);
}

#define TESTS(X)                                                                                   \
    X(long_fast_flight_never_shows_stale_texels)                                                   \
    X(small_cache_collects_and_stays_exact)                                                        \
    X(wide_windows_with_one_block_a_frame)

TP_TEST_MAIN(TESTS)
