/*
 * test_gdaldem.c - tp_gdaldem_compute and tp_gdaldem_write (io/src/gdaldem.cpp) on grids whose
 * answer is known without GDAL: a tilted plane, whose slope is atan(|gradient|) and whose
 * aspect is the bearing of the way down at every post; a void in it, nodata with its 3x3 ring
 * and without -compute_edges the grid's edge; flat ground with a void, where --zero-for-flat's
 * 0 must not spread into the void (gdaldem -zero_for_flat writes 0 there); bad arguments and a
 * path naming no format refused with nothing written.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_io.h"
#include "tp_test.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define TESTS(X)                                                                                   \
    X(plane_slope_and_aspect_are_the_gradients)                                                    \
    X(voids_and_edges_are_nodata_unless_computed)                                                  \
    X(zero_for_flat_leaves_voids_nodata)                                                           \
    X(bad_arguments_are_refused_and_nothing_written)

#define W 40
#define H 30
#define STEP 30.0

static const double k_gt[6] = {500000.0, STEP, 0.0, 4000000.0, 0.0, -STEP};

/* z = 1000 + a * east + b * north (metres from the grid's corner) at every post. */
static void plane(float* z, double a, double b)
{
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x)
            z[y * W + x] = (float)(1000.0 + a * (x + 0.5) * STEP - b * (y + 0.5) * STEP);
}

static void run(const float* z, tp_gdaldem_options o, float* out)
{
    tp_error err = {{0}};
    if (tp_gdaldem_compute(z, W * H, W, H, k_gt, &o, out, W * H, &err) != TP_OK)
        FAIL("tp_gdaldem_compute: %s", err.message);
}

TEST(plane_slope_and_aspect_are_the_gradients)
{
    static float z[W * H], s[W * H], p[W * H], asp[W * H];
    const double a = 0.3, b = -0.4; /* rising east, falling north: |gradient| 0.5 */
    plane(z, a, b);
    tp_gdaldem_options o = tp_gdaldem_options_default(TP_GDALDEM_SLOPE);
    run(z, o, s);
    o.slope_percent = 1;
    o.method = TP_GDALDEM_ZEVENBERGEN;
    run(z, o, p);
    run(z, tp_gdaldem_options_default(TP_GDALDEM_ASPECT), asp);
    /* the way down is (-a, -b): east -0.3, north 0.4, its bearing from north clockwise */
    const double want_slope = atan(hypot(a, b)) * 180.0 / M_PI;
    const double want_aspect = fmod(atan2(-a, -b) * 180.0 / M_PI + 360.0, 360.0);
    int inside = 0;
    for (int y = 1; y < H - 1; ++y)
        for (int x = 1; x < W - 1; ++x, ++inside) {
            EXPECT_NEAR(want_slope, s[y * W + x], 1e-3);
            EXPECT_NEAR(100.0 * hypot(a, b), p[y * W + x], 1e-3);
            EXPECT_NEAR(want_aspect, asp[y * W + x], 1e-3);
        }
    EXPECT_EQ_INT((W - 2) * (H - 2), inside);
    tp_test_note("plane: slope %.4f deg, aspect %.4f deg at every inner post", want_slope,
                 want_aspect);
}

TEST(voids_and_edges_are_nodata_unless_computed)
{
    static float z[W * H], s[W * H], e[W * H];
    plane(z, 0.1, 0.2);
    z[10 * W + 20] = NAN;
    tp_gdaldem_options o = tp_gdaldem_options_default(TP_GDALDEM_SLOPE);
    run(z, o, s);
    o.compute_edges = 1;
    run(z, o, e);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int edge = x == 0 || y == 0 || x == W - 1 || y == H - 1;
            const int ring = abs(x - 20) <= 1 && abs(y - 10) <= 1;
            EXPECT_EQ_INT(edge || ring, (int)isnan(s[y * W + x]));
            EXPECT_EQ_INT(x == 20 && y == 10, (int)isnan(e[y * W + x]));
        }
}

TEST(zero_for_flat_leaves_voids_nodata)
{
    static float z[W * H], plain[W * H], zero[W * H], edges[W * H];
    for (int i = 0; i < W * H; ++i)
        z[i] = 500.0f;
    z[10 * W + 20] = NAN;
    tp_gdaldem_options o = tp_gdaldem_options_default(TP_GDALDEM_ASPECT);
    run(z, o, plain);
    o.zero_for_flat = 1;
    run(z, o, zero);
    o.compute_edges = 1;
    run(z, o, edges);
    for (int y = 0; y < H; ++y)
        for (int x = 0; x < W; ++x) {
            const int i = y * W + x;
            const int edge = x == 0 || y == 0 || x == W - 1 || y == H - 1;
            const int ring = abs(x - 20) <= 1 && abs(y - 10) <= 1;
            EXPECT_NAN(plain[i]); /* flat: no aspect */
            if (edge || ring)
                EXPECT_NAN(zero[i]);
            else
                EXPECT_EQ_DBL(0.0, zero[i]);
            if (x == 20 && y == 10)
                EXPECT_NAN(edges[i]);
            else
                EXPECT_EQ_DBL(0.0, edges[i]);
        }
}

TEST(bad_arguments_are_refused_and_nothing_written)
{
    static float z[W * H], out[W * H];
    plane(z, 0.1, 0.1);
    for (int i = 0; i < W * H; ++i)
        out[i] = 7.0f;
    tp_error err = {{0}};
    tp_gdaldem_options o = tp_gdaldem_options_default(TP_GDALDEM_HILLSHADE);
    const double rotated[6] = {0, STEP, 0.5, 0, 0, -STEP};
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_gdaldem_compute(z, W * H, W, H, rotated, &o, out, W * H, &err));
    EXPECT_CONTAINS(err.message, "rotated");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_gdaldem_compute(z, W * H - 1, W, H, k_gt, &o, out, W * H, &err));
    o.z_factor = 0.0;
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_gdaldem_compute(z, W * H, W, H, k_gt, &o, out, W * H, &err));
    o = tp_gdaldem_options_default(TP_GDALDEM_HILLSHADE);
    o.altitude_deg = 91.0;
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_gdaldem_compute(z, W * H, W, H, k_gt, &o, out, W * H, &err));
    for (int i = 0; i < W * H; ++i)
        ASSERT_EQ_DBL(7.0, out[i]); /* untouched */

    /* a path whose extension is no format of the product's kind: refused, no file */
    char dir[] = "/tmp/tp_test_gdaldemXXXXXX", path[128];
    ASSERT_TRUE(mkdtemp(dir) != NULL);
    struct stat st;
    o = tp_gdaldem_options_default(TP_GDALDEM_SLOPE);
    snprintf(path, sizeof path, "%s/slope.png", dir);
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_gdaldem_write(path, z, W * H, W, H, k_gt, "EPSG:32631", &o, NULL, &err));
    EXPECT_CONTAINS(err.message, "PNG holds no Float32 values");
    EXPECT_TRUE(stat(path, &st) != 0);
    /* the hillshade is bytes: a PNG is fine, with its world file; a slope GeoTIFF too */
    o = tp_gdaldem_options_default(TP_GDALDEM_HILLSHADE);
    tp_gdaldem_stats stats;
    EXPECT_OK(tp_gdaldem_write(path, z, W * H, W, H, k_gt, "EPSG:32631", &o, &stats, &err));
    EXPECT_TRUE(stat(path, &st) == 0);
    EXPECT_EQ_INT((W - 2) * (H - 2), (int)stats.valid);
    EXPECT_EQ_INT(W * H - (W - 2) * (H - 2), (int)stats.nodata);
    EXPECT_TRUE(stats.min >= 1.0 && stats.max <= 255.0 && stats.min == stats.max); /* a plane */
    char side[160];
    snprintf(side, sizeof side, "%s/slope.wld", dir);
    EXPECT_TRUE(stat(side, &st) == 0);
    remove(side);
    snprintf(side, sizeof side, "%s/slope.png.aux.xml", dir);
    remove(side);
    remove(path);
    rmdir(dir);
}

TP_TEST_MAIN(TESTS)
