/*
 * test_pgm_clip_error_gl.c - the error of Persistent Grid Mapping over a store
 * (tp_pgm_clipmap_measure, app/render/pgm_clip_error.c, over the core's
 * tp_pgm_measure_error_source), through Mesa llvmpipe, on stores written from Mt Hood
 * (tp_test_pgm_store.h):
 *
 *   - with windows holding every level whole, the store's measured error (the windows' surface
 *     against the store's level-0 posts of the view's region) is the DEM path's
 *     (tp_pgm_measure_error over every post of the DEM's pyramid from the same heights);
 *   - with windows of 16 posts the surface drawn is coarser, and the measure sees it: larger
 *     errors over the same posts in view.
 */
#define _POSIX_C_SOURCE 200809L
#include "gl_context.h"
#include "pgm_clip.h"
#include "pgm_render.h"
#include "tp_io.h"
#include "tp_test.h"
#define TP_TMP_PREFIX "tp_pgm_clip_error_"
#include "tp_test_tmp.h"

#include "tp_test_pgm_store.h"

#include <math.h>
#include <string.h>

#define TESTS(X)                                                                                   \
    X(store_error_is_the_dem_error_when_the_windows_hold_everything)                               \
    X(small_windows_measure_the_coarser_levels_they_draw)

/* Windows of 1024 posts hold Mt Hood's every level whole: the store's surface is the DEM's, and
 * so is its measured error, although the store's measure reads only the view's region (from the
 * store's nodes) where the DEM's visits every post. */
TEST(store_error_is_the_dem_error_when_the_windows_hold_everything)
{
    tp_gl_context* ctx = context_or_skip();
    fixture fx;
    open_fixture(&fx, 0, 0, "hood");
    tp_pgm_pyramid p;
    store_pyramid(&fx, &p);
    tp_error err = {{0}};
    tp_pgm_renderer* whole = tp_pgm_renderer_create(&p, NULL, 300, 300, &err);
    tp_pgm_clipmap* clip = tp_pgm_clipmap_create(fx.store, 1024, &err);
    ASSERT_TRUE(whole && clip);
    tp_pgm_renderer* r = tp_pgm_renderer_create_clipmap(clip, 300, 300, &err);
    ASSERT_TRUE(r != NULL);
    const double pose[3][5] = {
        {0.25, 0.75, 700, 45, -20}, {0.5, 0.5, 4000, 10, -60}, {0.6, 0.15, 300, 190, -8}};
    for (int k = 0; k < 3; k++) {
        tp_camera cam = camera_at(&fx, pose[k][0] * fx.w, pose[k][1] * fx.h, pose[k][2], pose[k][3],
                                  pose[k][4]);
        tp_pgm_render_stats st;
        draw(ctx, r, &cam, NULL, NULL, &st);
        tp_pgm_error a, b;
        ASSERT_OK(tp_pgm_renderer_measure(whole, &cam, 0, &a, &err));
        if (tp_pgm_renderer_measure(r, &cam, 0, &b, &err) != TP_OK)
            FAIL("%s", err.message);
        tp_pgm_rect reg;
        tp_pgm_view_region(tp_pgm_clipmap_shape(clip), &cam, &reg);
        double share = (double)(reg.x1 - reg.x0) * (reg.y1 - reg.y0) / ((double)fx.w * fx.h);
        tp_test_note("camera %d: DEM max %.4f px RMS %.4f px (%zu samples, %zu uncovered); store "
                     "max %.4f px RMS %.4f px (%zu, %zu); region %.0f %% of the posts",
                     k, a.max_px, a.rms_px, a.samples, a.uncovered, b.max_px, b.rms_px, b.samples,
                     b.uncovered, 100 * share);
        EXPECT_GT(a.samples, (size_t)10000);
        EXPECT_GT(a.max_px, 0.0);
        EXPECT_EQ_INT((long long)a.samples, (long long)b.samples);
        EXPECT_EQ_INT((long long)a.uncovered, (long long)b.uncovered);
        EXPECT_NEAR(a.max_px, b.max_px, 1e-9 * a.max_px);
        EXPECT_NEAR(a.rms_px, b.rms_px, 1e-9 * a.rms_px);
        EXPECT_NEAR(a.max_m, b.max_m, 1e-9 * a.max_m);
        EXPECT_NEAR(a.rms_m, b.rms_m, 1e-9 * a.rms_m);
        if (k == 1) /* looking down from 4 km: the region is a part of the terrain */
            EXPECT_LT(share, 0.8);
        EXPECT_NEAR(1.0, b.post_share, 0.0);
        if (k == 0) { /* a bound on the posts visited (the viewer's): bands sampled, saying so */
            tp_pgm_error c;
            size_t posts = (size_t)(reg.x1 - reg.x0) * (size_t)(reg.y1 - reg.y0);
            ASSERT_OK(tp_pgm_renderer_measure(r, &cam, posts / 4, &c, &err));
            tp_test_note("sampled: %.3f of the region, %zu samples, max %.4f px RMS %.4f px",
                         c.post_share, c.samples, c.max_px, c.rms_px);
            EXPECT_GT(c.post_share, 0.1);
            EXPECT_LT(c.post_share, 0.35); /* every 4th or 5th band of 2^n rows, give or take one */
            EXPECT_GT(c.samples, (size_t)0);
            EXPECT_LT((double)c.samples, 0.5 * (double)b.samples); /* a subset of the posts */
            EXPECT_LE(c.max_px, b.max_px); /* of the same errors */
            EXPECT_GT(c.max_px, 0.0);
        }
    }
    tp_pgm_renderer_destroy(r);
    tp_pgm_clipmap_destroy(clip);
    tp_pgm_renderer_destroy(whole);
    tp_pgm_pyramid_free(&p);
    close_fixture(&fx);
    tp_gl_context_destroy(ctx);
}

/* Windows of 16 posts, looking down on the summit from 4 km: where a level's window does not
 * hold a vertex's footprint the shader reads a coarser level, and the measure must see that
 * surface (a measure reading the whole pyramid, or ignoring the windows' origins, would not):
 * larger errors than with windows holding everything, over the same posts in view. */
TEST(small_windows_measure_the_coarser_levels_they_draw)
{
    tp_gl_context* ctx = context_or_skip();
    fixture fx;
    open_fixture(&fx, 0, 0, "hood");
    tp_error err = {{0}};
    tp_pgm_clipmap* big = tp_pgm_clipmap_create(fx.store, 1024, &err);
    tp_pgm_clipmap* small = tp_pgm_clipmap_create(fx.store, 16, &err);
    ASSERT_TRUE(big && small);
    tp_pgm_renderer* rb = tp_pgm_renderer_create_clipmap(big, 300, 300, &err);
    tp_pgm_renderer* rs = tp_pgm_renderer_create_clipmap(small, 300, 300, &err);
    ASSERT_TRUE(rb && rs);
    tp_camera cam = camera_at(&fx, 0.5 * fx.w, 0.5 * fx.h, 4000, 10, -60);
    tp_pgm_render_stats st;
    draw(ctx, rb, &cam, NULL, NULL, &st);
    draw(ctx, rs, &cam, NULL, NULL, &st);
    tp_pgm_error a, b;
    ASSERT_OK(tp_pgm_renderer_measure(rb, &cam, 0, &a, &err));
    ASSERT_OK(tp_pgm_renderer_measure(rs, &cam, 0, &b, &err));
    tp_test_note("windows of 1024: max %.3f px RMS %.3f px, %.2f m RMS; of 16: max %.3f px RMS "
                 "%.3f px, %.2f m RMS (%zu + %zu and %zu + %zu posts in view)",
                 a.max_px, a.rms_px, a.rms_m, b.max_px, b.rms_px, b.rms_m, a.samples, a.uncovered,
                 b.samples, b.uncovered);
    EXPECT_GT(a.samples, (size_t)10000);
    /* the posts in view are the camera's, whatever the surface drawn */
    EXPECT_EQ_INT((long long)(a.samples + a.uncovered), (long long)(b.samples + b.uncovered));
    EXPECT_GT(b.rms_m, 1.5 * a.rms_m);
    EXPECT_GT(b.rms_px, 1.5 * a.rms_px);
    tp_pgm_renderer_destroy(rs);
    tp_pgm_renderer_destroy(rb);
    tp_pgm_clipmap_destroy(small);
    tp_pgm_clipmap_destroy(big);
    close_fixture(&fx);
    tp_gl_context_destroy(ctx);
}

TP_TEST_MAIN(TESTS)
