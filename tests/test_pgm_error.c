/* test_pgm_error.c - PGM's error measure over a source (core/src/pgm_error.c:
 * tp_pgm_measure_error_source, tp_pgm_view_region) on a crop of the real SRTM tile N42E001:
 * measured band by band (odd bands, not aligned with anything) over the view's region, it gives
 * the whole-grid measure's samples, uncovered posts and errors for cameras looking down, towards
 * the horizon, with a far plane, straight down from high up and from below the terrain (an
 * empty region, nothing in view); the region is a part of the grid where the view allows. */
#define _POSIX_C_SOURCE 200809L
#include "tp_core.h"
#include "tp_test.h"
#include "tp_test_hgt.h"

#include <math.h>
#include <string.h>

#define TESTS(X) X(region_and_bands_change_nothing_measured)

enum { CW = 600, CH = 500 };

static double pyr_sample(void* ctx, int level, double x, double y)
{
    return tp_pgm_pyramid_sample(ctx, level, x, y);
}

static int pyr_posts(void* ctx, int x0, int y0, int x1, int y1, float* out)
{
    const tp_pgm_pyramid* p = ctx;
    for (int y = y0; y < y1; y++)
        memcpy(out + (size_t)(y - y0) * (x1 - x0), p->z[0] + (size_t)y * p->width[0] + x0,
               (size_t)(x1 - x0) * sizeof *out);
    return 1;
}

TEST(region_and_bands_change_nothing_measured)
{
    float* z = load_hgt(300, 400, CW, CH);
    if (!z)
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    for (size_t k = 0; k < (size_t)CW * CH; k++) /* the crop's few voids: a low height */
        z[k] = isnan(z[k]) ? 300.0f : z[k];
    const double gt[6] = {400000, 90, 0, 4700000, 0, -90}; /* 90 m posts, north up */
    tp_pgm_pyramid p;
    tp_error err = {{0}};
    ASSERT_OK(tp_pgm_pyramid_build(z, CW, CH, gt, &p, &err));
    free(z);
    /* eye post x, y (fractions), height above the highest post (< 0: below the lowest), yaw,
     * pitch, far plane (0: none) */
    const double pose[5][6] = {{0.5, 0.5, 3000, 30, -60, 0},
                               {0.5, 0.95, 200, 10, -8, 0},
                               {0.5, 0.95, 200, 10, -8, 8000},
                               {0.3, 0.6, 20000, 0, -89, 0},
                               {0.5, 0.5, -100, 0, -80, 0}};
    for (int k = 0; k < 5; k++) {
        double eye[3] = {gt[0] + (pose[k][0] * CW + 0.5) * gt[1],
                         gt[3] + (pose[k][1] * CH + 0.5) * gt[5],
                         pose[k][2] >= 0 ? p.max_m + pose[k][2] : p.min_m + pose[k][2]};
        tp_camera cam;
        tp_camera_from_pose(eye, pose[k][3], pose[k][4], 60, 640, 360, &cam);
        cam.far_m = pose[k][5];
        tp_pgm_frame f;
        tp_pgm_frame_setup(&cam, 200, 150, &p, &f);
        tp_pgm_error a, b;
        ASSERT_OK(tp_pgm_measure_error(&f, &p, &cam, &a));
        tp_pgm_rect r;
        tp_pgm_view_region(&p, &cam, &r);
        tp_pgm_source src = {&p, pyr_sample, pyr_posts, 7, 0, 0};
        ASSERT_OK(tp_pgm_measure_error_source(&f, &p, &src, &r, &cam, &b));
        double share = r.x1 > r.x0 && r.y1 > r.y0
                           ? (double)(r.x1 - r.x0) * (r.y1 - r.y0) / ((double)CW * CH)
                           : 0;
        tp_test_note("camera %d: %zu + %zu posts in view, max %.3f px RMS %.3f px; region "
                     "[%d, %d) x [%d, %d), %.0f %% of the posts",
                     k, a.samples, a.uncovered, a.max_px, a.rms_px, r.x0, r.x1, r.y0, r.y1,
                     100 * share);
        EXPECT_EQ_INT((long long)a.samples, (long long)b.samples);
        EXPECT_EQ_INT((long long)a.uncovered, (long long)b.uncovered);
        EXPECT_EQ_DBL(a.max_px, b.max_px);
        EXPECT_EQ_DBL(a.max_m, b.max_m);
        EXPECT_NEAR(a.rms_px, b.rms_px, 1e-12 * a.rms_px);
        EXPECT_NEAR(a.rms_m, b.rms_m, 1e-12 * a.rms_m);
        if (k < 4)
            EXPECT_GT(a.samples, (size_t)1000);
        if (k == 0 || k == 2 || k == 3) /* down, within a far plane, down from high up */
            EXPECT_LT(share, 0.7);
        if (k == 1) /* towards the horizon without a far plane: everything */
            EXPECT_EQ_DBL(1.0, share);
        if (k == 4) { /* below the terrain looking down: nothing in view, an empty region */
            EXPECT_EQ_DBL(0.0, share);
            EXPECT_EQ_INT(0, (long long)(a.samples + a.uncovered));
        }
        EXPECT_EQ_DBL(1.0, b.post_share);
        /* Sampled by bands (every 3rd band of 7 rows): the three phases partition the posts,
         * so together they give the whole measure's counts and maximum, each a third or so. */
        size_t samples = 0, uncovered = 0;
        double max_px = 0, shares = 0;
        for (int ph = 0; ph < 3; ph++) {
            tp_pgm_source part = {&p, pyr_sample, pyr_posts, 7, 3, ph};
            tp_pgm_error e;
            ASSERT_OK(tp_pgm_measure_error_source(&f, &p, &part, &r, &cam, &e));
            samples += e.samples, uncovered += e.uncovered, shares += e.post_share;
            max_px = e.samples && e.max_px > max_px ? e.max_px : max_px;
            if (share > 0 && r.y1 - r.y0 > 100)
                EXPECT_NEAR(1.0 / 3, e.post_share, 0.05);
        }
        EXPECT_EQ_INT((long long)a.samples, (long long)samples);
        EXPECT_EQ_INT((long long)a.uncovered, (long long)uncovered);
        EXPECT_EQ_DBL(a.max_px, max_px);
        if (share > 0)
            EXPECT_NEAR(1.0, shares, 1e-12);
    }
    tp_pgm_pyramid_free(&p);
}

TP_TEST_MAIN(TESTS)
