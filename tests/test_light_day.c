/* test_light_day.c - the sun over a day (core/src/light_day.c): shadows interpolated between
 * stored maps against shadows computed directly (tp_shadow_compute) at the sun of that
 * moment, on Mt Hood over 2026-06-21 with the sun from tp_sun.h (64 maps, sunrise to sunset);
 * a cliff's shadow edge moving monotonically and following its analytic length; the stored
 * horizons against the cliff's geometry; the errors. */
#define _POSIX_C_SOURCE 200809L
#include "tp_io.h"
#include "tp_sun.h"
#include "tp_test.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define TESTS(X)                                                                                   \
    X(interpolated_day_agrees_with_direct_shadows_on_mt_hood)                                      \
    X(cliff_shadow_edge_moves_monotonically)                                                       \
    X(stored_horizons_are_the_cliff_edge)                                                    \
    X(bad_days_and_times_are_refused)

#ifdef TP_TEST_NO_IO
#define TP_LIGHT_DAY_STUB_(name)                                                                   \
    static void test_##name(void) { SKIP("built without tp_io"); }
TESTS(TP_LIGHT_DAY_STUB_)
#else

static tp_light_day* build_ok(const float* z, int w, int h, double dx, double dy,
                              const double* t, const double* az, const double* el, int count)
{
    tp_light_day* d = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    tp_status s = tp_light_day_build(z, (size_t)w * h, w, h, dx, dy, t, az, el, count, &d, &err);
    if (s != TP_OK)
        FAIL("tp_light_day_build: %s", err.message);
    return d;
}

/* Mt Hood's grid; the sun seen from its centre (45.37 N, 121.70 W) on 2026-06-21, its grid
 * azimuth taken as the true one (the grid is UTM 10N near its central meridian; the
 * convergence is irrelevant to a comparison of two computations with the same sun). */
TEST(interpolated_day_agrees_with_direct_shadows_on_mt_hood)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_render_grid* g = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    ASSERT_OK(tp_render_grid_build(dem, NULL, &g, &err));
    tp_dem_destroy(dem);
    const int w = g->width, h = g->height;
    const size_t n = (size_t)w * h;
    const double dx = fabs(g->geotransform[1]), dy = fabs(g->geotransform[5]);
    const double lat = 45.37, lon = -121.70;
    tp_sun_day day;
    ASSERT_OK(tp_sun_rise_set(lat, lon, tp_sun_local_day_start(2026, 6, 21, lon), &day, &err));
    ASSERT_EQ_INT(TP_SUN_RISES_AND_SETS, (int)day.kind);
    enum { K = TP_LIGHT_DAY_MAPS };
    double t[K], az[K], el[K];
    ASSERT_OK(tp_sun_day_times(lat, lon, day.rise_unix_s, day.set_unix_s, K, t, &err));
    for (int k = 0; k < K; ++k) {
        tp_sun_pos p;
        ASSERT_OK(tp_sun_position(lat, lon, t[k], &p, &err));
        az[k] = p.azimuth_deg;
        el[k] = p.apparent_elevation_deg;
    }
    tp_light_day* d = build_ok(g->heights, w, h, dx, dy, t, az, el, K);
    uint8_t* got = malloc(n);
    uint8_t* want = malloc(n);
    ASSERT_TRUE(got && want);
    /* halfway between maps (where interpolation errs most), from early morning to evening */
    const int between[] = {1, 2, 4, 8, 16, 31, 45, 55, 59, 61, 62};
    for (size_t b = 0; b < sizeof between / sizeof between[0]; ++b) {
        const int k = between[b];
        const double tm = 0.5 * (t[k] + t[k + 1]);
        tp_sun_pos p;
        ASSERT_OK(tp_sun_position(lat, lon, tm, &p, &err));
        ASSERT_OK(tp_light_day_at(d, tm, got, n, &err));
        ASSERT_OK(tp_shadow_compute(g->heights, n, w, h, dx, dy, p.azimuth_deg,
                                    p.apparent_elevation_deg, want, NULL, n, &err));
        size_t valid = 0, agree = 0, shadowed = 0;
        for (size_t i = 0; i < n; ++i) {
            if (g->heights[i] != g->heights[i])
                continue;
            valid++;
            agree += got[i] == want[i];
            shadowed += !want[i];
        }
        const double pct = 100.0 * agree / valid;
        tp_test_note("between maps %d and %d, %.1f min apart (sun %.1f/%.1f): interpolated "
                     "agrees with direct on %.3f%% (%.1f%% shadowed)",
                     k, k + 1, (t[k + 1] - t[k]) / 60.0, p.azimuth_deg,
                     p.apparent_elevation_deg, pct, 100.0 * shadowed / valid);
        EXPECT_GE(pct, 99.0);
    }
    /* at a map's own time: the stored map itself */
    ASSERT_OK(tp_light_day_at(d, t[20], got, n, &err));
    ASSERT_OK(tp_shadow_compute(g->heights, n, w, h, dx, dy, az[20], el[20], want, NULL, n, &err));
    size_t same = 0;
    for (size_t i = 0; i < n; ++i)
        same += got[i] == want[i];
    EXPECT_EQ_INT((int)n, (int)same);
    tp_test_note("%d maps of %dx%d: %.1f MB", K, w, h,
                 (double)K * n * sizeof(int16_t) / 1e6);
    free(got);
    free(want);
    tp_light_day_destroy(d);
    tp_render_grid_destroy(g);
}

/* A 100 m cliff facing east (columns 0 .. 10 at 100 m, the rest at 0, posts 10 m apart), the
 * afternoon sun in the west sinking from 40 to 5 degrees over 8 maps an hour apart, its
 * elevation linear in time between them. The shadow's end D(t) (posts in shadow along a row)
 * never moves back, and stays within a post of 100 / tan(elevation(t)) with tan(elevation(t))
 * linear between the maps, as tp_light_day_at interpolates it (the elevation itself, linear
 * in time here, differs from that by tan's curvature: up to 2 posts at 7.5 degrees). */
TEST(cliff_shadow_edge_moves_monotonically)
{
    enum { W = 200, H = 2, C = 10, K = 8 };
    static float z[W * H];
    static uint8_t lit[W * H];
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = c <= C ? 100.0f : 0.0f;
    double t[K], az[K], el[K];
    for (int k = 0; k < K; ++k) {
        t[k] = 3600.0 * k;
        az[k] = 270.0;
        el[k] = 40.0 - 5.0 * k;
    }
    tp_light_day* d = build_ok(z, W, H, 10.0, 10.0, t, az, el, K);
    int last = 0, worst_back = 0;
    double worst_off = 0.0;
    tp_error err;
    memset(&err, 0, sizeof err);
    for (int s = 0; s <= 700; ++s) {
        const double tm = t[K - 1] * s / 700.0;
        ASSERT_OK(tp_light_day_at(d, tm, lit, (size_t)W * H, &err));
        int shadowed = 0;
        for (int c = C + 1; c < W; ++c)
            shadowed += !lit[c];
        if (shadowed < last)
            worst_back = last - shadowed > worst_back ? last - shadowed : worst_back;
        last = shadowed;
        const double u = 7.0 * s / 700.0; /* hours = maps from the first */
        const int k = u >= K - 1 ? K - 2 : (int)u;
        const double ta = tan((40.0 - 5.0 * k) * M_PI / 180.0);
        const double tb = tan((40.0 - 5.0 * (k + 1)) * M_PI / 180.0);
        const double tan_e = ta + (tb - ta) * (u - k);
        const double expect = ceil(100.0 / tan_e / 10.0) - 1.0; /* posts with 10 c < L */
        if (fabs(shadowed - expect) > worst_off)
            worst_off = fabs(shadowed - expect);
    }
    tp_test_note("shadow end: never back (worst %d), within %.0f post(s) of 100 / tan(e(t))",
                 worst_back, worst_off);
    EXPECT_EQ_INT(0, worst_back);
    EXPECT_LE(worst_off, 1.0);
    EXPECT_EQ_INT(114, last); /* 100 / tan(5 degrees) = 1143 m: 114 posts */
    tp_light_day_destroy(d);
}

/* The cliff of the test above at 10 degrees: a shadowed post D m from the edge stores the
 * horizon tan(h) = 100 / D (the edge seen from it) less tan(10 degrees), in units of
 * TP_LIGHT_DAY_TAN_STEP rounded up, at most 32767 of them; lit posts store 0, voids
 * TP_LIGHT_DAY_VOID. */
TEST(stored_horizons_are_the_cliff_edge)
{
    enum { W = 120, H = 3, C = 10 };
    static float z[W * H];
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = c <= C ? 100.0f : 0.0f;
    z[W + 30] = NAN;
    const double t[2] = {0.0, 1.0}, az[2] = {270.0, 270.0}, el[2] = {10.0, 9.0};
    tp_light_day* d = build_ok(z, W, H, 10.0, 10.0, t, az, el, 2);
    int shadowed = 0;
    for (int c = 0; c < W; ++c) {
        const int16_t code = d->codes[W + c];
        if (c == 30) {
            EXPECT_EQ_INT(TP_LIGHT_DAY_VOID, code);
            continue;
        }
        const double D = (c - C) * 10.0;
        if (c <= C || D * tan(10.0 * M_PI / 180.0) >= 100.0) {
            EXPECT_EQ_INT(0, code);
            continue;
        }
        shadowed++;
        const double excess = 100.0 / D - tan(10.0 * M_PI / 180.0);
        if (excess >= 32767 * TP_LIGHT_DAY_TAN_STEP)
            EXPECT_EQ_INT(-32767, code);
        else
            EXPECT_NEAR(-code * TP_LIGHT_DAY_TAN_STEP, excess, TP_LIGHT_DAY_TAN_STEP + 1e-6);
    }
    EXPECT_EQ_INT(55, shadowed); /* 100 / tan(10 degrees) = 567 m: 56 posts, one a void */
    tp_light_day_destroy(d);
}

TEST(bad_days_and_times_are_refused)
{
    float z[4] = {1, 2, 3, 4};
    double t[3] = {0.0, 10.0, 5.0}, az[3] = {90, 90, 90}, el[3] = {10, 10, 10};
    tp_light_day* d = (tp_light_day*)&z; /* must stay as it is */
    tp_light_day* const before = d;
    tp_error err;
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_light_day_build(z, 4, 2, 2, 10, 10, t, az, el, 1, &d, &err));
    EXPECT_CONTAINS(err.message, "at least 2");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_light_day_build(z, 4, 2, 2, 10, 10, t, az, el, 3, &d, &err));
    EXPECT_CONTAINS(err.message, "time 2");
    el[1] = 95.0;
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_light_day_build(z, 4, 2, 2, 10, 10, t, az, el, 2, &d, &err));
    EXPECT_CONTAINS(err.message, "elevation 95");
    EXPECT_TRUE(d == before);
    el[1] = 10.0;
    ASSERT_OK(tp_light_day_build(z, 4, 2, 2, 10, 10, t, az, el, 2, &d, &err));
    uint8_t lit[4] = {9, 9, 9, 9};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_light_day_at(d, 10.5, lit, 4, &err));
    EXPECT_CONTAINS(err.message, "outside the maps' 0 .. 10");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_light_day_at(d, NAN, lit, 4, &err));
    EXPECT_EQ_INT(9, lit[0]);
    ASSERT_OK(tp_light_day_at(d, 10.0, lit, 4, &err));
    tp_light_day_destroy(d);
    tp_light_day_destroy(NULL);
}

#endif /* TP_TEST_NO_IO */

TP_TEST_MAIN(TESTS)
