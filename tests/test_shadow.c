/* test_shadow.c - terrain self-shadowing (core/src/shadow.c, tp_shadow_compute) against
 * geometry worked out here (flat ground, a cliff's shadow length, walls, voids) and against an
 * independent ray cast written here (march from each sample toward the sun in quarter-post
 * steps over the bilinear surface) on real DEMs: Mt Hood (UTM, 30 m) and N42E001 (SRTM warped
 * to UTM 31N by the render grid), at low (5 degree), medium (15) and high (45) suns from
 * axis-aligned, diagonal and other azimuths. */
#define _POSIX_C_SOURCE 200809L
#include "tp_io.h"
#include "tp_test.h"

#include <time.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define TESTS(X)                                                                                   \
    X(flat_ground_is_all_lit)                                                                      \
    X(cliff_casts_its_analytic_shadow)                                                             \
    X(oblique_sun_on_a_cliff)                                                                      \
    X(sun_below_the_horizon_and_at_the_zenith)                                                     \
    X(voids_block_no_light_and_are_not_lit)                                                        \
    X(one_by_one_and_two_by_two_grids)                                                             \
    X(wall_along_the_sun_direction)                                                                \
    X(bad_arguments_are_refused)                                                                   \
    X(illumination_of_a_plane)                                                                     \
    X(agrees_with_a_ray_cast_on_mt_hood)                                                           \
    X(agrees_with_a_ray_cast_on_n42e001)

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void shadow_ok(const float* z, int w, int h, double dx, double dy, double az, double el,
                      uint8_t* lit, float* margin)
{
    tp_error err;
    memset(&err, 0, sizeof err);
    tp_status s = tp_shadow_compute(z, (size_t)w * h, w, h, dx, dy, az, el, lit, margin,
                                    (size_t)w * h, &err);
    if (s != TP_OK)
        FAIL("tp_shadow_compute: %s", err.message);
}

/* ---- the independent ray cast ---- */

/* The bilinear surface at grid (x, y) (column, row); NaN outside the grid or in a cell with a
 * void corner. */
static double bilinear(const float* z, int w, int h, double x, double y)
{
    if (!(x >= 0.0 && y >= 0.0 && x <= w - 1 && y <= h - 1))
        return NAN;
    int c = (int)floor(x), r = (int)floor(y);
    if (c > w - 2)
        c = w > 1 ? w - 2 : 0;
    if (r > h - 2)
        r = h > 1 ? h - 2 : 0;
    const double fx = x - c, fy = y - r;
    const int c1 = w > 1 ? c + 1 : c, r1 = h > 1 ? r + 1 : r;
    const double z00 = z[(size_t)r * w + c], z10 = z[(size_t)r * w + c1];
    const double z01 = z[(size_t)r1 * w + c], z11 = z[(size_t)r1 * w + c1];
    return (z00 * (1 - fx) + z10 * fx) * (1 - fy) + (z01 * (1 - fx) + z11 * fx) * fy;
}

/* 1 when the ray from post (c, r) toward the sun clears the surface: marched in steps of
 * step_m metres until it leaves the grid or rises above zmax. */
static int ray_lit(const float* z, int w, int h, double dx, double dy, double az_deg,
                   double el_deg, int c, int r, double zmax, double step_m)
{
    const double az = az_deg * M_PI / 180.0, t = tan(el_deg * M_PI / 180.0);
    const double ux = sin(az) / dx, uy = -cos(az) / dy;
    const double z0 = z[(size_t)r * w + c];
    for (double d = step_m;; d += step_m) {
        const double x = c + ux * d, y = r + uy * d;
        if (x < 0.0 || y < 0.0 || x > w - 1 || y > h - 1)
            return 1;
        const double ray = z0 + d * t;
        if (ray > zmax)
            return 1;
        const double g = bilinear(z, w, h, x, y);
        if (g == g && g > ray)
            return 0;
    }
}

/* ---- made-up ground ---- */

TEST(flat_ground_is_all_lit)
{
    enum { W = 37, H = 23 };
    static float z[W * H];
    static uint8_t lit[W * H];
    static float margin[W * H];
    for (int i = 0; i < W * H; ++i)
        z[i] = 812.5f;
    const double azs[] = {0, 45, 90, 135, 180, 225, 270, 315, 17.3, 301.9, -90, 720};
    const double els[] = {0.5, 5, 15, 45, 89.9};
    for (size_t a = 0; a < sizeof azs / sizeof azs[0]; ++a)
        for (size_t e = 0; e < sizeof els / sizeof els[0]; ++e) {
            shadow_ok(z, W, H, 10.0, 12.5, azs[a], els[e], lit, margin);
            int shadowed = 0;
            for (int i = 0; i < W * H; ++i) {
                shadowed += lit[i] != TP_SHADOW_LIT;
                EXPECT_GT(margin[i], 0.0);
            }
            EXPECT_EQ_INT(0, shadowed);
        }
}

/* A plateau H m high west of a north-south cliff (columns 0 .. C at H, C+1 .. at 0), the sun
 * in the west (azimuth 270) at elevation e: a post D m east of the cliff's top edge is in
 * shadow while D < H / tan(e) (the ray from it meets the edge below H). The spacings make
 * H / tan(e) fall between posts. */
TEST(cliff_casts_its_analytic_shadow)
{
    enum { W = 200, H = 5, C = 20 };
    static float z[W * H];
    static uint8_t lit[W * H];
    const double top = 100.0, dx = 7.0;
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = c <= C ? (float)top : 0.0f;
    const double els[] = {5.0, 10.0, 15.0, 30.0, 45.0, 60.0, 80.0};
    for (size_t e = 0; e < sizeof els / sizeof els[0]; ++e) {
        shadow_ok(z, W, H, dx, 30.0, 270.0, els[e], lit, NULL);
        const double length = top / tan(els[e] * M_PI / 180.0);
        for (int r = 0; r < H; ++r)
            for (int c = 0; c < W; ++c) {
                const int expect = c <= C || (c - C) * dx >= length;
                if (lit[r * W + c] != expect)
                    FAIL("elevation %g: post (%d, %d) %s, shadow %.1f m long", els[e], c, r,
                         expect ? "should be lit" : "should be in shadow", length);
            }
    }
}

/* The same cliff with the sun from azimuth 250 or 290: the ray from a post dE m east of the
 * edge meets it after dE / |sin(azimuth)|, so the shadow reaches H |sin(azimuth)| / tan(e)
 * east of it. Rows away from the grid's north/south edges (the ray must meet the cliff inside). */
TEST(oblique_sun_on_a_cliff)
{
    enum { W = 120, H = 120, C = 10 };
    static float z[W * H];
    static uint8_t lit[W * H];
    const double top = 50.0, dx = 10.0, dy = 10.0;
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = c <= C ? (float)top : 0.0f;
    const double azs[] = {250.0, 290.0, 240.0};
    const double els[] = {10.0, 20.0};
    for (size_t a = 0; a < 3; ++a)
        for (size_t e = 0; e < 2; ++e) {
            shadow_ok(z, W, H, dx, dy, azs[a], els[e], lit, NULL);
            const double reach =
                top * fabs(sin(azs[a] * M_PI / 180.0)) / tan(els[e] * M_PI / 180.0);
            int wrong = 0, checked = 0;
            for (int r = 60; r < 62; ++r)
                for (int c = C + 1; c < W; ++c) {
                    const double d = (c - C) * dx;
                    if (fabs(d - reach) < 0.5)
                        continue; /* grazing */
                    checked++;
                    wrong += lit[r * W + c] != (d >= reach);
                }
            EXPECT_EQ_INT(0, wrong);
            EXPECT_GT(checked, 100);
        }
}

TEST(sun_below_the_horizon_and_at_the_zenith)
{
    enum { W = 9, H = 7 };
    float z[W * H];
    uint8_t lit[W * H];
    float margin[W * H];
    for (int i = 0; i < W * H; ++i)
        z[i] = (float)(i % 5) * 3.0f;
    z[10] = NAN;
    const double below[] = {0.0, -0.27, -45.0, -90.0};
    for (int k = 0; k < 4; ++k) {
        shadow_ok(z, W, H, 30.0, 30.0, 100.0, below[k], lit, margin);
        for (int i = 0; i < W * H; ++i) {
            EXPECT_EQ_INT(TP_SHADOW_SHADOWED, lit[i]);
            if (i != 10)
                EXPECT_TRUE(isinf(margin[i]) && margin[i] < 0);
        }
        EXPECT_NAN(margin[10]);
    }
    shadow_ok(z, W, H, 30.0, 30.0, 100.0, 90.0, lit, margin);
    for (int i = 0; i < W * H; ++i)
        EXPECT_EQ_INT(i == 10 ? TP_SHADOW_SHADOWED : TP_SHADOW_LIT, lit[i]);
}

/* A 95 m wall at column 10 on flat ground, posts 10 m apart, sun in the west at 45 degrees:
 * the shadow reaches 95 m east (columns 11 .. 19). Columns 11 and 12 are voids: they are not
 * lit, and the shadow passes over them to 13 .. 19 as before. A void ridge casts nothing. */
TEST(voids_block_no_light_and_are_not_lit)
{
    enum { W = 40, H = 3 };
    float z[W * H];
    uint8_t lit[W * H];
    float margin[W * H];
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = c == 10 ? 95.0f : (c == 11 || c == 12) ? NAN : 0.0f;
    shadow_ok(z, W, H, 10.0, 10.0, 270.0, 45.0, lit, margin);
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c) {
            const int expect = !(c >= 11 && c <= 19);
            EXPECT_EQ_INT(expect, lit[r * W + c]);
            if (c == 11 || c == 12)
                EXPECT_NAN(margin[r * W + c]);
        }
    EXPECT_NEAR(margin[15], (15 - 10) * 10.0 - 95.0, 1e-3); /* 45 m below the line */
    /* the ground between: voids everywhere but one low row, a tall void in between */
    for (int i = 0; i < W * H; ++i)
        z[i] = NAN;
    for (int c = 0; c < W; ++c)
        z[1 * W + c] = 5.0f;
    shadow_ok(z, W, H, 10.0, 10.0, 270.0, 1.0, lit, NULL);
    for (int c = 0; c < W; ++c) {
        EXPECT_EQ_INT(TP_SHADOW_LIT, lit[1 * W + c]);
        EXPECT_EQ_INT(TP_SHADOW_SHADOWED, lit[0 * W + c]);
    }
    /* a diagonal sun across a void stripe: nothing casts, nothing is shadowed */
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = c % 4 == 0 ? NAN : 0.0f;
    shadow_ok(z, W, H, 10.0, 10.0, 225.0, 3.0, lit, NULL);
    for (int i = 0; i < W * H; ++i)
        EXPECT_EQ_INT(z[i] == z[i], lit[i]);
}

TEST(one_by_one_and_two_by_two_grids)
{
    float one = 1234.0f;
    uint8_t lit1;
    float m1;
    shadow_ok(&one, 1, 1, 30.0, 30.0, 123.0, 10.0, &lit1, &m1);
    EXPECT_EQ_INT(TP_SHADOW_LIT, lit1);
    EXPECT_TRUE(isinf(m1) && m1 > 0);
    /* 2x2, 10 m posts: the north-east post 20 m up, the rest at 0; sun in the north-east
     * (azimuth 45) at 30 degrees: the south-west post is 14.14 m from it along the diagonal,
     * where its ray is 8.2 m up: in shadow, 11.8 m below the line. From the north-west and
     * south-east posts the sun's direction leaves the grid at once: lit. */
    float z[4] = {0.0f, 20.0f, 0.0f, 0.0f}; /* row 0: NW, NE; row 1: SW, SE */
    uint8_t lit[4];
    float m[4];
    shadow_ok(z, 2, 2, 10.0, 10.0, 45.0, 30.0, lit, m);
    EXPECT_EQ_INT(TP_SHADOW_LIT, lit[0]);
    EXPECT_EQ_INT(TP_SHADOW_LIT, lit[1]);
    EXPECT_EQ_INT(TP_SHADOW_SHADOWED, lit[2]);
    EXPECT_EQ_INT(TP_SHADOW_LIT, lit[3]);
    EXPECT_NEAR(m[2], 0.0 - (20.0 - sqrt(200.0) * tan(M_PI / 6.0)), 1e-4);
    /* at 60 degrees the ray clears it: 14.14 * tan 60 = 24.5 m > 20 m */
    shadow_ok(z, 2, 2, 10.0, 10.0, 45.0, 60.0, lit, NULL);
    EXPECT_EQ_INT(TP_SHADOW_LIT, lit[2]);
    /* 2x2 with a void: never lit there */
    z[1] = NAN;
    shadow_ok(z, 2, 2, 10.0, 10.0, 45.0, 30.0, lit, NULL);
    EXPECT_EQ_INT(TP_SHADOW_SHADOWED, lit[1]);
    EXPECT_EQ_INT(TP_SHADOW_LIT, lit[2]);
}

/* A 30 m wall one row thick along row 10 from column 5 to 30, posts 10 m apart, the sun exactly
 * along it from the west at 5 degrees: its own posts see the sun over the next post of the
 * wall; the rows beside it are never crossed by a ray through it. East of its end the row is in
 * its shadow for 30 / tan(5 degrees) = 342.9 m. */
TEST(wall_along_the_sun_direction)
{
    enum { W = 80, H = 21 };
    static float z[W * H];
    static uint8_t lit[W * H];
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = r == 10 && c >= 5 && c <= 30 ? 30.0f : 0.0f;
    shadow_ok(z, W, H, 10.0, 10.0, 270.0, 5.0, lit, NULL);
    const double length = 30.0 / tan(5.0 * M_PI / 180.0);
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c) {
            const int expect = !(r == 10 && c > 30 && (c - 30) * 10.0 < length);
            if (lit[r * W + c] != expect)
                FAIL("post (%d, %d) %s", c, r, expect ? "should be lit" : "should be in shadow");
        }
    /* the same wall along a column, sun from the north */
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = c == 40 && r <= 5 ? 30.0f : 0.0f;
    shadow_ok(z, W, H, 10.0, 10.0, 0.0, 10.0, lit, NULL);
    const double l2 = 30.0 / tan(10.0 * M_PI / 180.0); /* 170.1 m: rows 6 .. 20, to the grid's end */
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c) {
            const int expect = !(c == 40 && r > 5 && (r - 5) * 10.0 < l2);
            EXPECT_EQ_INT(expect, lit[r * W + c]);
        }
}

TEST(bad_arguments_are_refused)
{
    float z[6] = {0};
    uint8_t lit[6] = {7, 7, 7, 7, 7, 7};
    tp_error err;
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_shadow_compute(z, 6, 2, 2, 10, 10, 0, 10, lit, NULL, 6, &err));
    EXPECT_CONTAINS(err.message, "2x2 grid needs 4 heights, got 6");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_shadow_compute(z, 6, 3, 2, 0.0, 10, 0, 10, lit, NULL, 6, &err));
    EXPECT_CONTAINS(err.message, "spacings");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_shadow_compute(z, 6, 3, 2, 10, 10, NAN, 10, lit, NULL, 6, &err));
    EXPECT_CONTAINS(err.message, "azimuth");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_shadow_compute(z, 6, 3, 2, 10, 10, 0, 91, lit, NULL, 6, &err));
    EXPECT_CONTAINS(err.message, "elevation 91");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_shadow_compute(z, 6, 3, 2, 10, 10, 0, NAN, lit, NULL, 6, &err));
    for (int i = 0; i < 6; ++i)
        EXPECT_EQ_INT(7, lit[i]);
    uint8_t out[6];
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_shadow_illumination(z, 6, 3, 2, 10, -1, 0, 10, NULL, out, 6, &err));
}

/* A plane rising east by a m per m, sun at azimuth az, elevation e: cos(incidence) =
 * (-a sin(az) cos(e) + sin(e)) / sqrt(1 + a^2) (the normal (-a, 0, 1) normalised). */
TEST(illumination_of_a_plane)
{
    enum { W = 9, H = 6 };
    float z[W * H];
    uint8_t out[W * H];
    const double a = 0.3, dx = 20.0;
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = (float)(a * c * dx);
    const double azs[] = {90.0, 270.0, 180.0, 300.0};
    for (int k = 0; k < 4; ++k) {
        const double az = azs[k] * M_PI / 180.0, e = 35.0 * M_PI / 180.0;
        double want = (-a * sin(az) * cos(e) + sin(e)) / sqrt(1.0 + a * a);
        want = want > 0 ? 255.0 * want : 0.0;
        tp_error err;
        memset(&err, 0, sizeof err);
        ASSERT_OK(tp_shadow_illumination(z, W * H, W, H, dx, 15.0, azs[k], 35.0, NULL, out,
                                         W * H, &err));
        for (int i = 0; i < W * H; ++i)
            EXPECT_NEAR(out[i], want, 0.5 + 1e-9);
    }
    uint8_t lit[W * H];
    memset(lit, 0, sizeof lit);
    lit[5] = 1;
    tp_error err;
    memset(&err, 0, sizeof err);
    ASSERT_OK(tp_shadow_illumination(z, W * H, W, H, dx, 15.0, 270.0, 35.0, lit, out, W * H,
                                     &err));
    for (int i = 0; i < W * H; ++i)
        EXPECT_EQ_INT(i == 5, out[i] > 0);
}

/* ---- real DEMs against the ray cast ---- */

static tp_render_grid* grid_or_skip(const char* file)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_render_grid* g = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", file);
    if (tp_dem_read(path, &dem, &err) != TP_OK)
        FAIL("tp_dem_read(%s): %s", path, err.message);
    tp_status s = tp_render_grid_build(dem, NULL, &g, &err);
    tp_dem_destroy(dem);
    if (s != TP_OK)
        FAIL("tp_render_grid_build(%s): %s", path, err.message);
    return g;
}

/* For each sun: the sweep over the whole grid, the ray cast at every `every`-th post of every
 * `every`-th row (all of them for every = 1); agreement over the valid posts cast. */
static void check_dem(const char* file, int every)
{
    tp_render_grid* g = grid_or_skip(file);
    const int w = g->width, h = g->height;
    const size_t n = (size_t)w * h;
    const double dx = fabs(g->geotransform[1]), dy = fabs(g->geotransform[5]);
    double zmax = -INFINITY;
    for (size_t i = 0; i < n; ++i)
        if (g->heights[i] > zmax)
            zmax = g->heights[i];
    uint8_t* lit = malloc(n);
    ASSERT_TRUE(lit != NULL);
    const struct {
        double az, el;
    } suns[] = {{270.0, 5.0}, {135.0, 5.0}, {200.0, 15.0}, {90.0, 15.0},
                {45.0, 15.0}, {180.0, 45.0}, {315.0, 45.0}, {123.4, 30.0}};
    for (size_t k = 0; k < sizeof suns / sizeof suns[0]; ++k) {
        const double t0 = now_s();
        shadow_ok(g->heights, w, h, dx, dy, suns[k].az, suns[k].el, lit, NULL);
        const double t1 = now_s();
        size_t cast = 0, agree = 0, shadowed = 0, sweep_only = 0, ray_only = 0;
        for (int r = 0; r < h; r += every)
            for (int c = 0; c < w; c += every) {
                const size_t i = (size_t)r * w + c;
                if (g->heights[i] != g->heights[i])
                    continue;
                const int ray = ray_lit(g->heights, w, h, dx, dy, suns[k].az, suns[k].el, c, r,
                                        zmax, 0.25 * (dx < dy ? dx : dy));
                cast++;
                agree += ray == lit[i];
                shadowed += !ray;
                sweep_only += !lit[i] && ray;
                ray_only += lit[i] && !ray;
            }
        const double t2 = now_s();
        const double pct = 100.0 * agree / cast;
        tp_test_note("%s %dx%d sun %5.1f/%4.1f: agree %.3f%% of %zu posts cast (%.1f%% shadowed; "
                     "%zu only the sweep shadows, %zu only the ray cast); sweep %.1f ms for the "
                     "grid, ray cast %.0f ms for %zu posts",
                     file, w, h, suns[k].az, suns[k].el, pct, cast, 100.0 * shadowed / cast,
                     sweep_only, ray_only, 1e3 * (t1 - t0), 1e3 * (t2 - t1), cast);
        EXPECT_GE(pct, 99.0);
        EXPECT_GT(shadowed, cast / 500); /* the case has shadows to get right */
    }
    free(lit);
    tp_render_grid_destroy(g);
}

TEST(agrees_with_a_ray_cast_on_mt_hood) { check_dem("lf_elev_220_mt_hood_utm.tif", 2); }

TEST(agrees_with_a_ray_cast_on_n42e001) { check_dem("N42E001.hgt", 3); }

TP_TEST_MAIN(TESTS)
