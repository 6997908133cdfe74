/*
 * test_pgm_clip_gl.c - Persistent Grid Mapping over a store (app/render/pgm_clip.c and
 * pgm_render.c's clipmap shader, through Mesa llvmpipe, EGL without a display), on stores
 * written in a temporary folder from Mt Hood (data/lf_elev_220_mt_hood_utm.tif, its voids
 * filled as tp_pgm_pyramid_from_grid fills them, so that both renderers draw every post):
 *
 *   - with windows holding every level whole, the store's frame is the DEM's (the whole
 *     pyramid, built from the store's own decoded heights) pixel for pixel, colour and depth;
 *   - after a flight of 300 frames with small windows (64 posts: every level but the coarsest
 *     moves, with steps, turns and jumps), the frame is the one a clipmap created at the final
 *     camera draws and its windows' texels are the fresh clipmap's: no stale strip;
 *   - a GL error left pending by other code fails neither the clipmap's nor the atlas's creation;
 *   - the first fill (every window) goes through a buffer of 2^18 posts, not levels x w^2;
 *   - GPU bytes: the index buffer and levels x w x w x 4, the same for a store of a third of
 *     the posts with as many levels, and the windows' posts updated per frame are strips, not
 *     windows.
 */
#define _POSIX_C_SOURCE 200809L
#include "gl_context.h"
#include "pgm_clip.h"
#include "pgm_render.h"
#include "tp_io.h"
#include "tp_test.h"
#define TP_TMP_PREFIX "tp_pgm_clip_"
#include "tp_test_tmp.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TESTS(X)                                                                                   \
    X(store_frame_is_the_dem_frame_when_the_windows_hold_everything)                               \
    X(long_flight_leaves_no_stale_strip)                                                           \
    X(async_flight_settles_to_the_fresh_clipmap)                                                   \
    X(small_windows_fall_back_to_coarser_levels)                                                   \
    X(gpu_bytes_do_not_grow_with_the_store)                                                        \
    X(void_posts_draw_nothing_and_no_curtain)                                                      \
    X(an_error_another_module_left_fails_no_creation)                                              \
    X(first_fill_reads_through_a_bounded_buffer)

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#include "tp_test_pgm_store.h"

/* Pixels whose colour differs by more than 1 in a channel or whose depth differs; terrain
 * pixels of a (depth < 1). */
static void compare(const uint8_t* a, const uint8_t* b, const float* da, const float* db,
                    size_t* differ, size_t* terrain)
{
    *differ = *terrain = 0;
    for (size_t k = 0; k < (size_t)W * H; k++) {
        int bad = da[k] != db[k];
        for (int c = 0; c < 3; c++)
            bad |= abs((int)a[4 * k + c] - (int)b[4 * k + c]) > 1;
        *differ += bad;
        *terrain += da[k] < 1;
    }
}

TEST(store_frame_is_the_dem_frame_when_the_windows_hold_everything)
{
    tp_gl_context* ctx = context_or_skip();
    fixture fx;
    open_fixture(&fx, 0, 0, "hood");
    /* the DEM's pyramid from the store's own heights (quantised as stored) */
    float* z = malloc((size_t)fx.w * fx.h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    for (int y = 0; y < fx.h; y++)
        for (int x = 0; x < fx.w; x++)
            z[(size_t)y * fx.w + x] = (float)height_at(&fx, x, y);
    tp_pgm_pyramid p;
    tp_error err = {{0}};
    ASSERT_OK(tp_pgm_pyramid_build(z, fx.w, fx.h, fx.gt, &p, &err));
    free(z);
    tp_pgm_renderer* whole = tp_pgm_renderer_create(&p, NULL, 300, 300, &err);
    ASSERT_TRUE(whole != NULL);
    tp_pgm_clipmap* clip = tp_pgm_clipmap_create(fx.store, 1024, &err);
    if (!clip)
        FAIL("%s", err.message);
    const tp_pgm_pyramid* shape = tp_pgm_clipmap_shape(clip);
    ASSERT_EQ_INT(p.levels, shape->levels);
    for (int l = 0; l < p.levels; l++) {
        EXPECT_EQ_INT(p.width[l], shape->width[l]);
        EXPECT_EQ_INT(p.height[l], shape->height[l]);
    }
    EXPECT_NEAR(p.min_m, shape->min_m, 0.0);
    EXPECT_NEAR(p.max_m, shape->max_m, 0.0);
    tp_pgm_renderer* r = tp_pgm_renderer_create_clipmap(clip, 300, 300, &err);
    ASSERT_TRUE(r != NULL);
    static uint8_t ca[W * H * 4], cb[W * H * 4];
    static float da[W * H], db[W * H];
    /* three cameras: over the south-west slopes looking north-east, high above the summit
     * looking down, and low in the north looking south */
    const double pose[3][5] = {
        {0.25, 0.75, 700, 45, -20}, {0.5, 0.5, 4000, 10, -60}, {0.6, 0.15, 300, 190, -8}};
    for (int k = 0; k < 3; k++) {
        tp_camera cam = camera_at(&fx, pose[k][0] * fx.w, pose[k][1] * fx.h, pose[k][2], pose[k][3],
                                  pose[k][4]);
        tp_pgm_render_stats sa, sb;
        draw(ctx, whole, &cam, ca, da, &sa);
        draw(ctx, r, &cam, cb, db, &sb);
        size_t differ, terrain;
        compare(ca, cb, da, db, &differ, &terrain);
        tp_test_note("camera %d: %zu terrain pixels, %zu differ; first update %.1f ms fill, "
                     "%.1f ms upload, %zu posts, %zu nodes",
                     k, terrain, differ, sb.fill_ms, sb.upload_ms, sb.posts_updated, sb.node_reads);
        EXPECT_GT(terrain, (size_t)W * H / 4);
        EXPECT_EQ_INT(0, (long long)differ);
    }
    tp_pgm_renderer_destroy(r);
    tp_pgm_clipmap_destroy(clip);
    tp_pgm_renderer_destroy(whole);
    tp_pgm_pyramid_free(&p);
    close_fixture(&fx);
    tp_gl_context_destroy(ctx);
}

/* Texels of the windows' posts on the terrain that differ between two clipmaps of the same
 * store and window (read back from the GPU); the origins must agree. */
static size_t stale_texels(const tp_pgm_clipmap* a, const tp_pgm_clipmap* b, size_t* held)
{
    const tp_pgm_pyramid* p = tp_pgm_clipmap_shape(a);
    int w = tp_pgm_clipmap_window(a), oa[2 * TP_PGM_MAX_LEVELS], ob[2 * TP_PGM_MAX_LEVELS];
    tp_pgm_clipmap_origins(a, oa);
    tp_pgm_clipmap_origins(b, ob);
    size_t n = (size_t)w * w * p->levels, bad = 0;
    float* ta = malloc(n * sizeof *ta);
    float* tb = malloc(n * sizeof *tb);
    ASSERT_TRUE(ta && tb);
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glBindTexture(GL_TEXTURE_2D_ARRAY, tp_pgm_clipmap_texture(a));
    glGetTexImage(GL_TEXTURE_2D_ARRAY, 0, GL_RED, GL_FLOAT, ta);
    glBindTexture(GL_TEXTURE_2D_ARRAY, tp_pgm_clipmap_texture(b));
    glGetTexImage(GL_TEXTURE_2D_ARRAY, 0, GL_RED, GL_FLOAT, tb);
    glBindTexture(GL_TEXTURE_2D_ARRAY, 0);
    *held = 0;
    for (int l = 0; l < p->levels; l++) {
        EXPECT_EQ_INT(oa[2 * l], ob[2 * l]);
        EXPECT_EQ_INT(oa[2 * l + 1], ob[2 * l + 1]);
        for (int y = oa[2 * l + 1]; y < oa[2 * l + 1] + w && y < p->height[l]; y++)
            for (int x = oa[2 * l]; x < oa[2 * l] + w && x < p->width[l]; x++) {
                size_t t = ((size_t)l * w + (size_t)(y & (w - 1))) * w + (size_t)(x & (w - 1));
                bad += ta[t] != tb[t];
                (*held)++;
            }
    }
    free(ta);
    free(tb);
    return bad;
}

/* The flight of long_flight_leaves_no_stale_strip; async: through the loader thread, settled
 * at the final camera (updates until nothing is pending) before the comparison. */
static void fly(int async);

TEST(long_flight_leaves_no_stale_strip)
{
    fly(0);
}

/* The same flight with the loader thread: the windows move only when their posts are uploaded
 * (a frame or more late); settled at the final camera, frame and texels are a fresh
 * (synchronous) clipmap's. */
TEST(async_flight_settles_to_the_fresh_clipmap)
{
    fly(1);
}

static void fly(int async)
{
    tp_gl_context* ctx = context_or_skip();
    fixture fx;
    open_fixture(&fx, 0, 0, "hood");
    tp_error err = {{0}};
    const int win = 64;
    tp_pgm_clipmap* clip = tp_pgm_clipmap_create(fx.store, win, &err);
    if (!clip)
        FAIL("%s", err.message);
    tp_pgm_renderer* r = tp_pgm_renderer_create_clipmap(clip, 240, 135, &err);
    ASSERT_TRUE(r != NULL);
    if (async)
        ASSERT_TRUE(tp_pgm_clipmap_set_async(clip, &err));
    /* a loop at 250 m over the ground: 1.3 posts a frame, turning, with three jumps of more
     * than a window at level 0 and one off the terrain */
    double x = 0.2 * fx.w, y = 0.8 * fx.h, yaw = 30;
    size_t updated = 0, max_posts = 0;
    int frames = 300;
    for (int f = 0; f < frames; f++) {
        double a = yaw * M_PI / 180;
        x += 1.3 * sin(a), y -= 1.3 * cos(a);
        yaw += f < 150 ? 1.1 : -0.7;
        if (f == 60 || f == 200)
            x += 150, y -= 90;
        if (f == 120)
            x -= 400;
        if (f == 121)
            x += 400;
        x = fmin(fmax(x, -30), fx.w + 30);
        y = fmin(fmax(y, -30), fx.h + 30);
        tp_camera cam = camera_at(&fx, x, y, 250, yaw, -25);
        tp_pgm_render_stats st;
        draw(ctx, r, &cam, NULL, NULL, &st);
        if (f > 0) {
            updated += st.posts_updated;
            max_posts = st.posts_updated > max_posts ? st.posts_updated : max_posts;
        }
    }
    tp_camera last = camera_at(&fx, x, y, 250, yaw, -25);
    static uint8_t ca[W * H * 4], cb[W * H * 4];
    static float da[W * H], db[W * H];
    tp_pgm_render_stats st;
    for (int k = 0; async && k < 10000 && tp_pgm_clipmap_pending(clip); k++) {
        struct timespec ts = {0, 1000000};
        nanosleep(&ts, NULL);
        draw(ctx, r, &last, NULL, NULL, &st);
    }
    ASSERT_TRUE(!tp_pgm_clipmap_pending(clip));
    draw(ctx, r, &last, ca, da, &st);
    EXPECT_EQ_INT(0, (long long)st.posts_updated); /* the same camera: nothing moves */
    tp_pgm_clipmap* fresh = tp_pgm_clipmap_create(fx.store, win, &err);
    ASSERT_TRUE(fresh != NULL);
    tp_pgm_renderer* rf = tp_pgm_renderer_create_clipmap(fresh, 240, 135, &err);
    ASSERT_TRUE(rf != NULL);
    draw(ctx, rf, &last, cb, db, &st);
    size_t differ, terrain, held;
    compare(ca, cb, da, db, &differ, &terrain);
    size_t stale = stale_texels(clip, fresh, &held);
    size_t whole = (size_t)tp_pgm_clipmap_shape(clip)->levels * win * win;
    tp_test_note("%d frames: %zu posts updated (%.0f a frame, at most %zu; a fresh fill %zu); "
                 "final frame %zu terrain pixels, %zu differ; %zu of %zu texels stale",
                 frames, updated, (double)updated / (frames - 1), max_posts, st.posts_updated,
                 terrain, differ, stale, held);
    EXPECT_GT(terrain, (size_t)W * H / 4);
    EXPECT_EQ_INT(0, (long long)differ);
    EXPECT_EQ_INT(0, (long long)stale);
    /* strips, not windows: on average far less than a whole refill a frame */
    EXPECT_LT((double)updated / (frames - 1), 0.1 * (double)whole);
    tp_pgm_renderer_destroy(rf);
    tp_pgm_clipmap_destroy(fresh);
    tp_pgm_renderer_destroy(r);
    tp_pgm_clipmap_destroy(clip);
    close_fixture(&fx);
    tp_gl_context_destroy(ctx);
}

/* The eye's distance along the view axis of a depth-buffer value (the renderer's projection). */
static double eye_depth(float d, const tp_pgm_render_stats* st)
{
    double n = st->near_m, f = st->far_m, A = (f + n) / (n - f), B = 2 * f * n / (n - f);
    return B / ((2.0 * d - 1.0) + A);
}

/* Windows of 64 posts (Mt Hood's level 0 is 1013 posts wide): where a vertex's level does not
 * hold its footprint the shader reads a coarser level, never a wrapped texel of another post.
 * Against the DEM's frame (every level whole) the surface is the same or coarser: the same
 * pixels are terrain but for a few at edges and silhouettes, and the depths agree to a few
 * percent (a wrapped texel would be a post kilometres away: hundreds of metres off). */
TEST(small_windows_fall_back_to_coarser_levels)
{
    tp_gl_context* ctx = context_or_skip();
    fixture fx;
    open_fixture(&fx, 0, 0, "hood");
    float* z = malloc((size_t)fx.w * fx.h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    for (int y = 0; y < fx.h; y++)
        for (int x = 0; x < fx.w; x++)
            z[(size_t)y * fx.w + x] = (float)height_at(&fx, x, y);
    tp_pgm_pyramid p;
    tp_error err = {{0}};
    ASSERT_OK(tp_pgm_pyramid_build(z, fx.w, fx.h, fx.gt, &p, &err));
    free(z);
    tp_pgm_renderer* whole = tp_pgm_renderer_create(&p, NULL, 300, 300, &err);
    tp_pgm_clipmap* clip = tp_pgm_clipmap_create(fx.store, 64, &err);
    ASSERT_TRUE(whole && clip);
    tp_pgm_renderer* r = tp_pgm_renderer_create_clipmap(clip, 300, 300, &err);
    ASSERT_TRUE(r != NULL);
    static uint8_t ca[W * H * 4], cb[W * H * 4];
    static float da[W * H], db[W * H];
    tp_camera cam = camera_at(&fx, 0.25 * fx.w, 0.75 * fx.h, 700, 45, -20);
    tp_pgm_render_stats sa, sb;
    draw(ctx, whole, &cam, ca, da, &sa);
    draw(ctx, r, &cam, cb, db, &sb);
    size_t terrain = 0, status = 0, far_off = 0, same = 0;
    double worst = 0;
    for (size_t k = 0; k < (size_t)W * H; k++) {
        int ta = da[k] < 1, tb = db[k] < 1;
        terrain += ta;
        status += ta != tb;
        same += da[k] == db[k];
        if (ta && tb) {
            double a = eye_depth(da[k], &sa), b = eye_depth(db[k], &sb);
            double rel = fabs(a - b) / a;
            far_off += rel > 0.05;
            worst = fmax(worst, rel);
        }
    }
    tp_test_note("%zu terrain pixels: %zu terrain in one frame only, %zu off by more than 5%% in "
                 "depth (worst %.1f%%), %zu identical",
                 terrain, status, far_off, 100 * worst, same);
    EXPECT_GT(terrain, (size_t)W * H / 4);
    EXPECT_LT((double)status, 0.02 * terrain);
    EXPECT_LT((double)far_off, 0.01 * terrain);
    EXPECT_LT((double)same, 0.99 * W * H); /* the windows are smaller than what it sees */
    tp_pgm_renderer_destroy(r);
    tp_pgm_clipmap_destroy(clip);
    tp_pgm_renderer_destroy(whole);
    tp_pgm_pyramid_free(&p);
    close_fixture(&fx);
    tp_gl_context_destroy(ctx);
}

TEST(gpu_bytes_do_not_grow_with_the_store)
{
    tp_gl_context* ctx = context_or_skip();
    /* 1013 x 799 and 600 x 500 posts: both 11 levels */
    fixture big, small;
    open_fixture(&big, 0, 0, "big");
    open_fixture(&small, 600, 500, "small");
    tp_error err = {{0}};
    const int win = 128;
    size_t bytes[2];
    int levels[2];
    fixture* fxs[2] = {&small, &big};
    for (int k = 0; k < 2; k++) {
        tp_pgm_clipmap* clip = tp_pgm_clipmap_create(fxs[k]->store, win, &err);
        ASSERT_TRUE(clip != NULL);
        tp_pgm_renderer* r = tp_pgm_renderer_create_clipmap(clip, 200, 150, &err);
        ASSERT_TRUE(r != NULL);
        tp_camera cam = camera_at(fxs[k], 0.5 * fxs[k]->w, 0.5 * fxs[k]->h, 800, 0, -30);
        tp_pgm_render_stats st;
        draw(ctx, r, &cam, NULL, NULL, &st);
        levels[k] = tp_pgm_clipmap_shape(clip)->levels;
        bytes[k] = st.gpu_bytes;
        EXPECT_EQ_INT((long long)(6 * 199 * 149 * 4 + (size_t)levels[k] * win * win * 4),
                      (long long)st.gpu_bytes);
        tp_pgm_renderer_destroy(r);
        tp_pgm_clipmap_destroy(clip);
    }
    tp_test_note("%d x %d posts: %zu bytes; %d x %d posts: %zu bytes (%d levels each)", small.w,
                 small.h, bytes[0], big.w, big.h, bytes[1], levels[1]);
    EXPECT_EQ_INT(levels[0], levels[1]);
    EXPECT_EQ_INT((long long)bytes[0], (long long)bytes[1]);
    close_fixture(&small);
    close_fixture(&big);
    tp_gl_context_destroy(ctx);
}

/* Mt Hood with its voids (3.3 % of the posts, along its edges): from high above, every drawn
 * pixel, put back into the world from its depth, lies between the lowest and the highest
 * height (to the depth buffer's precision) (no curtain down to the base plane, no spike from
 * arithmetic on a void texel), and none lies over a post whose 9 x 9 neighbourhood has no height
 * (inside a void, more than a coarse cell from its edge). */
TEST(void_posts_draw_nothing_and_no_curtain)
{
    tp_gl_context* ctx = context_or_skip();
    fixture fx;
    open_fixture_voids(&fx, 0, 0, "hood_voids", 0);
    tp_error err = {{0}};
    tp_pgm_clipmap* clip = tp_pgm_clipmap_create(fx.store, 256, &err);
    ASSERT_TRUE(clip != NULL);
    tp_pgm_renderer* r = tp_pgm_renderer_create_clipmap(clip, 300, 300, &err);
    ASSERT_TRUE(r != NULL);
    const tp_pgm_pyramid* shape = tp_pgm_clipmap_shape(clip);
    static uint8_t rgba[W * H * 4];
    static float depth[W * H];
    size_t drawn = 0, outside = 0, in_void = 0, void_posts = 0;
    for (int y = 0; y < fx.h; y++)
        for (int x = 0; x < fx.w; x++)
            void_posts += isnan(tp_tree_sample(fx.full, x, y));
    /* two views: most of the map from 12 km up, and low over its south-west corner */
    const double pose[2][5] = {{0.5, 0.5, 12000, 0, -75}, {0.1, 0.9, 600, 30, -25}};
    for (int k = 0; k < 2; k++) {
        tp_camera cam = camera_at(&fx, pose[k][0] * fx.w, pose[k][1] * fx.h, pose[k][2], pose[k][3],
                                  pose[k][4]);
        tp_pgm_render_stats st;
        draw(ctx, r, &cam, rgba, depth, &st);
        tp_camera_frame cf;
        tp_camera_get_frame(&cam, &cf);
        for (int py = 0; py < H; py++)
            for (int px = 0; px < W; px++) {
                float d = depth[(size_t)(H - 1 - py) * W + px];
                if (d >= 1)
                    continue;
                drawn++;
                double dir[3];
                tp_camera_pixel_ray(&cam, px + 0.5, py + 0.5, dir);
                double along =
                    dir[0] * cf.forward[0] + dir[1] * cf.forward[1] + dir[2] * cf.forward[2];
                double t = eye_depth(d, &st) / along, p[3];
                for (int a = 0; a < 3; a++)
                    p[a] = cam.position[a] + t * dir[a];
                /* 8 steps of the 24-bit depth buffer there (32 m a step at 33 km) */
                double slack = 5 + 8 * t * t / (2 * st.near_m) * 0x1p-24;
                if (p[2] < shape->min_m - slack || p[2] > shape->max_m + slack) {
                    if (outside++ < 5)
                        tp_test_note("view %d pixel (%d, %d) at height %.1f m, %.0f m away", k, px,
                                     py, p[2], t);
                }
                int gx = (int)lround((p[0] - fx.gt[0]) / fx.gt[1] - 0.5);
                int gy = (int)lround((p[1] - fx.gt[3]) / fx.gt[5] - 0.5);
                int any = 0;
                for (int j = -4; j <= 4 && !any; j++)
                    for (int i = -4; i <= 4 && !any; i++)
                        any = !isnan(height_at(&fx, gx + i, gy + j));
                in_void += !any;
            }
    }
    tp_test_note("%zu void posts of %d; %zu pixels drawn: %zu off the height range, %zu deep in "
                 "a void",
                 void_posts, fx.w * fx.h, drawn, outside, in_void);
    EXPECT_GT(void_posts, (size_t)10000);
    EXPECT_GT(drawn, (size_t)W * H / 4);
    EXPECT_EQ_INT(0, (long long)outside);
    EXPECT_EQ_INT(0, (long long)in_void);
    tp_pgm_renderer_destroy(r);
    tp_pgm_clipmap_destroy(clip);
    close_fixture(&fx);
    tp_gl_context_destroy(ctx);
}

/* A GL error flag another module left set (here an invalid glEnable) is not the texture
 * allocation's: both creations clear it before the calls they check. */
TEST(an_error_another_module_left_fails_no_creation)
{
    tp_gl_context* ctx = context_or_skip();
    fixture fx;
    open_fixture(&fx, 200, 150, "crop");
    tp_pgm_pyramid p;
    store_pyramid(&fx, &p);
    glEnable(0xBEEF);
    ASSERT_EQ_INT(GL_INVALID_ENUM, (int)glGetError()); /* the flag is set... */
    glEnable(0xBEEF);                                  /* ...and set again for the creation */
    tp_error err = {{0}};
    tp_pgm_clipmap* clip = tp_pgm_clipmap_create(fx.store, 64, &err);
    if (!clip)
        FAIL("the clipmap: %s", err.message);
    glEnable(0xBEEF);
    tp_pgm_renderer* whole = tp_pgm_renderer_create(&p, NULL, 40, 30, &err);
    if (!whole)
        FAIL("the atlas: %s", err.message);
    tp_pgm_renderer_destroy(whole);
    tp_pgm_clipmap_destroy(clip);
    tp_pgm_pyramid_free(&p);
    close_fixture(&fx);
    tp_gl_context_destroy(ctx);
}

/* Windows of 1024 over Mt Hood: the first fill writes about a million posts (every level whole)
 * a band at a time through 2^18 posts of CPU memory; nothing counts as filled before it (the
 * renderer draws nothing then); the frame it fills is checked against the DEM's above. */
TEST(first_fill_reads_through_a_bounded_buffer)
{
    tp_gl_context* ctx = context_or_skip();
    fixture fx;
    open_fixture(&fx, 0, 0, "hood");
    tp_error err = {{0}};
    tp_pgm_clipmap* clip = tp_pgm_clipmap_create(fx.store, 1024, &err);
    ASSERT_TRUE(clip != NULL);
    EXPECT_EQ_INT(0, tp_pgm_clipmap_filled(clip));
    tp_pgm_clip_stats st;
    if (!tp_pgm_clipmap_update(clip, fx.w / 2.0, fx.h / 2.0, &st, &err))
        FAIL("%s", err.message);
    tp_test_note("first fill: %zu posts from %zu nodes through %zu posts of buffer, %.1f ms fill, "
                 "%.1f ms upload",
                 st.posts, st.node_reads, st.buffer_posts, st.fill_ms, st.upload_ms);
    EXPECT_EQ_INT(1, tp_pgm_clipmap_filled(clip));
    EXPECT_GT(st.posts, (size_t)1000000);
    EXPECT_LE(st.buffer_posts, (size_t)1 << 18);
    EXPECT_GT(st.buffer_posts, (size_t)0);
    tp_pgm_clipmap_destroy(clip);
    close_fixture(&fx);
    tp_gl_context_destroy(ctx);
}

TP_TEST_MAIN(TESTS)
