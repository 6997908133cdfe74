/* test_light_times.c - the sun over a day as each sample's lit intervals
 * (core/src/light_times.c): the four bytes a post against tp_light_day_at's interpolation of
 * the same 64 maps on Mt Hood (2026-06-21, sunrise to sunset) at many times; a cliff's shadow
 * end at the time its analytic length gives; a pillar giving a post two lit intervals, and two
 * pillars three (simplified as documented); voids; the mean of a coarser level; the errors. */
#define _POSIX_C_SOURCE 200809L
#include "tp_io.h"
#include "tp_sun.h"
#include "tp_test.h"

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define TESTS(X)                                                                                   \
    X(times_agree_with_the_interpolated_day_on_mt_hood)                                            \
    X(cliff_shadow_reaches_a_post_when_its_length_says)                                            \
    X(a_pillar_south_gives_two_lit_intervals)                                                      \
    X(three_lit_intervals_keep_the_two_that_lose_least)                                            \
    X(voids_are_never_lit_and_coarser_levels_keep_the_order)                                       \
    X(bad_days_are_refused_and_out_is_untouched)

static tp_error err_;

static void build_ok(const float* z, int w, int h, double dx, const double* t,
                     const double* az, const double* el, int count, uint8_t* out,
                     tp_light_times_stats* st)
{
    memset(&err_, 0, sizeof err_);
    tp_status s = tp_light_times_build(z, (size_t)w * h, w, h, dx, dx, t, az, el, count, out,
                                       4 * (size_t)w * h, st, NULL, NULL, &err_);
    if (s != TP_OK)
        FAIL("tp_light_times_build: %s", err_.message);
}

#ifdef TP_TEST_NO_IO
static void test_times_agree_with_the_interpolated_day_on_mt_hood(void)
{
    SKIP("built without tp_io");
}
#else
static void count_progress(void* user, double f)
{
    double* last = user;
    if (f > *last)
        *last = f;
}

/* At times halfway between maps and at odd times, the post's bytes say what the 64 maps
 * interpolated say, except within half a step (1/510 of the day) of a change. */
TEST(times_agree_with_the_interpolated_day_on_mt_hood)
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
    enum { K = TP_LIGHT_DAY_MAPS };
    double t[K], az[K], el[K];
    ASSERT_OK(tp_sun_day_times(lat, lon, day.rise_unix_s, day.set_unix_s, K, t, &err));
    for (int k = 0; k < K; ++k) {
        tp_sun_pos p;
        ASSERT_OK(tp_sun_position(lat, lon, t[k], &p, &err));
        az[k] = p.azimuth_deg;
        el[k] = p.apparent_elevation_deg;
    }
    tp_light_day* d = NULL;
    ASSERT_OK(tp_light_day_build(g->heights, n, w, h, dx, dy, t, az, el, K, &d, &err));
    uint8_t* times = malloc(4 * n);
    uint8_t* lit = malloc(n);
    uint8_t* before = malloc(n);
    uint8_t* after = malloc(n);
    ASSERT_TRUE(times && lit && before && after);
    tp_light_times_stats st;
    double progress = 0.0;
    ASSERT_OK(tp_light_times_build(g->heights, n, w, h, dx, dy, t, az, el, K, times, 4 * n, &st,
                                   count_progress, &progress, &err));
    EXPECT_NEAR(progress, 1.0, 1e-12);
    EXPECT_EQ_INT((int)n, (int)st.samples);
    tp_test_note("%dx%d posts, %d maps: %zu posts lit at some time, %zu with more than two lit "
                 "intervals (%.3f%%), at most %.1f min given up",
                 w, h, K, st.lit_any, st.simplified, 100.0 * st.simplified / n,
                 st.given_up_max_s / 60.0);
    EXPECT_LE((double)st.simplified, 0.001 * n);
    const double day_s = t[K - 1] - t[0], step_s = day_s / TP_LIGHT_TIMES_STEPS;
    double worst = 100.0;
    size_t unexplained = 0;
    for (int q = 0; q < 40; ++q) {
        /* 40 times: halfway between maps 1, 2, ... and a few off the steps */
        const double tm = q < 30 ? 0.5 * (t[2 * q + 1] + t[2 * q + 2])
                                 : t[0] + day_s * (0.013 + 0.097 * (q - 30));
        ASSERT_OK(tp_light_day_at(d, tm, lit, n, &err));
        /* the day says the post changes within a step around tm: quantisation may disagree */
        ASSERT_OK(tp_light_day_at(d, fmax(t[0], tm - 0.51 * step_s), before, n, &err));
        ASSERT_OK(tp_light_day_at(d, fmin(t[K - 1], tm + 0.51 * step_s), after, n, &err));
        const double tau = tp_light_times_tau(t[0], t[K - 1], tm);
        size_t valid = 0, agree = 0;
        for (size_t i = 0; i < n; ++i) {
            if (g->heights[i] != g->heights[i])
                continue;
            valid++;
            const int same = tp_light_times_lit(times + 4 * i, tau) == (lit[i] == TP_SHADOW_LIT);
            agree += same;
            unexplained += !same && before[i] == lit[i] && after[i] == lit[i];
        }
        const double pct = 100.0 * agree / valid;
        if (pct < worst)
            worst = pct;
        EXPECT_GE(pct, 99.0);
    }
    tp_test_note("the bytes agree with tp_light_day_at on >= %.3f%% of valid posts at 40 times "
                 "(%.1f min a step); %zu disagreements not within half a step of a change",
                 worst, step_s / 60.0, unexplained);
    /* the simplified posts (more than two lit intervals) may disagree anywhere */
    EXPECT_LE((double)unexplained, 40.0 * st.simplified);
    free(before);
    free(after);
    free(times);
    free(lit);
    tp_light_day_destroy(d);
    tp_render_grid_destroy(g);
}
#endif /* TP_TEST_NO_IO */

/* A 100 m cliff (columns 0 .. 10), posts 10 m apart, the afternoon sun in the west sinking
 * from 40 to 5 degrees over 8 maps an hour apart. A post D m beyond the edge turns shadowed
 * when the interpolated tan(e) falls to 100 / D: its s1 is that time in steps, within one. */
TEST(cliff_shadow_reaches_a_post_when_its_length_says)
{
    enum { W = 200, H = 2, C = 10, K = 8 };
    static float z[W * H];
    static uint8_t out[4 * W * H];
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c)
            z[r * W + c] = c <= C ? 100.0f : 0.0f;
    double t[K], az[K], el[K];
    for (int k = 0; k < K; ++k)
        t[k] = 3600.0 * k, az[k] = 270.0, el[k] = 40.0 - 5.0 * k;
    tp_light_times_stats st;
    build_ok(z, W, H, 10.0, t, az, el, K, out, &st);
    int checked = 0;
    double worst = 0.0;
    for (int c = C + 1; c < W; ++c) {
        const uint8_t* p = out + 4 * c;
        const double tan_h = 100.0 / ((c - C) * 10.0);
        if (tan_h >= tan(40.0 * M_PI / 180.0)) { /* shadowed from the first map */
            EXPECT_EQ_INT(0, p[3]);
            continue;
        }
        if (tan_h <= tan(5.0 * M_PI / 180.0)) { /* lit all day */
            EXPECT_EQ_INT(0, p[0]);
            EXPECT_EQ_INT(255, p[1]);
            continue;
        }
        int k = 0; /* the interval of maps where tan(e) passes tan_h */
        while (tan((40.0 - 5.0 * (k + 1)) * M_PI / 180.0) > tan_h)
            ++k;
        const double ta = tan((40.0 - 5.0 * k) * M_PI / 180.0);
        const double tb = tan((40.0 - 5.0 * (k + 1)) * M_PI / 180.0);
        const double hours = k + (tan_h - ta) / (tb - ta);
        const double steps = 255.0 * hours / (K - 1);
        EXPECT_EQ_INT(0, p[0]);
        EXPECT_NEAR(p[1], steps, 1.0);
        EXPECT_EQ_INT(p[1], p[2]); /* one interval: r2 = s2 = s1 */
        EXPECT_EQ_INT(p[1], p[3]);
        if (fabs(p[1] - steps) > worst)
            worst = fabs(p[1] - steps);
        checked++;
    }
    tp_test_note("%d posts turn shadowed within %.2f step of the analytic time", checked, worst);
    EXPECT_GE(checked, 90);
    EXPECT_EQ_INT(0, (int)st.simplified);
}

/* A 100 m pillar 50 m south of a post, the sun at 10 degrees going round from east to west
 * (azimuths 90, 135, 180, 225, 270, maps an hour apart): lit, lit, shadowed, lit, lit. The
 * elevation does not explain the change, so the post changes halfway between maps: lit over
 * [0, 1.5 h) and [2.5 h, 4 h]. */
TEST(a_pillar_south_gives_two_lit_intervals)
{
    enum { W = 101, H = 101, K = 5 };
    static float z[W * H];
    static uint8_t out[4 * W * H];
    z[55 * W + 50] = 100.0f;
    double t[K], az[K], el[K];
    for (int k = 0; k < K; ++k)
        t[k] = 3600.0 * k, az[k] = 90.0 + 45.0 * k, el[k] = 10.0;
    tp_light_times_stats st;
    build_ok(z, W, H, 10.0, t, az, el, K, out, &st);
    const uint8_t* p = out + 4 * (50 * W + 50);
    EXPECT_EQ_INT(0, p[0]);
    EXPECT_EQ_INT(96, p[1]);  /* 255 * 1.5 / 4 = 95.6 */
    EXPECT_EQ_INT(159, p[2]); /* 255 * 2.5 / 4 = 159.4 */
    EXPECT_EQ_INT(255, p[3]);
    EXPECT_TRUE(tp_light_times_lit(p, 95.0));
    EXPECT_FALSE(tp_light_times_lit(p, 96.0));
    EXPECT_FALSE(tp_light_times_lit(p, 127.5));
    EXPECT_TRUE(tp_light_times_lit(p, 159.0));
    EXPECT_FALSE(tp_light_times_lit(p, 255.0)); /* the end is open */
    EXPECT_FALSE(tp_light_times_lit(p, -1.0));
    EXPECT_EQ_INT(0, (int)st.simplified);
    const uint8_t* far = out + 4 * (5 * W + 5); /* nothing around it: lit all day */
    EXPECT_EQ_INT(0, far[0]);
    EXPECT_EQ_INT(255, far[1]);
    EXPECT_EQ_INT(255, far[3]);
}

/* Pillars south-east and south-west of the post: lit, shadowed, lit, shadowed, lit, changing
 * halfway between maps: [0, 0.5 h), [1.5, 2.5 h), [3.5, 4 h]. The shortest loss is dropping a
 * half-hour interval (bridging a gap would light it for an hour); the first of the two
 * shortest goes. */
TEST(three_lit_intervals_keep_the_two_that_lose_least)
{
    enum { W = 101, H = 101, K = 5 };
    static float z[W * H];
    static uint8_t out[4 * W * H];
    z[55 * W + 55] = 100.0f;
    z[55 * W + 45] = 100.0f;
    double t[K], az[K], el[K];
    for (int k = 0; k < K; ++k)
        t[k] = 3600.0 * k, az[k] = 90.0 + 45.0 * k, el[k] = 10.0;
    tp_light_times_stats st;
    build_ok(z, W, H, 10.0, t, az, el, K, out, &st);
    const uint8_t* p = out + 4 * (50 * W + 50);
    EXPECT_EQ_INT(96, p[0]);
    EXPECT_EQ_INT(159, p[1]);
    EXPECT_EQ_INT(223, p[2]); /* 255 * 3.5 / 4 = 223.1 */
    EXPECT_EQ_INT(255, p[3]);
    EXPECT_GE((int)st.simplified, 1);
    EXPECT_NEAR(st.given_up_max_s, 1800.0, 1.0);
}

TEST(voids_are_never_lit_and_coarser_levels_keep_the_order)
{
    enum { W = 8, H = 8, K = 3 };
    float z[W * H];
    uint8_t out[4 * W * H];
    for (int i = 0; i < W * H; ++i)
        z[i] = (float)(i % 5);
    z[9] = NAN;
    const double t[K] = {0, 100, 200}, az[K] = {90, 180, 270}, el[K] = {30, 60, 30};
    build_ok(z, W, H, 10.0, t, az, el, K, out, NULL);
    for (int c = 0; c < 4; ++c)
        EXPECT_EQ_INT(0, out[4 * 9 + c]);
    const uint8_t a[4] = {0, 10, 200, 255}, b[4] = {3, 3, 3, 3}, c[4] = {0, 0, 0, 0},
                  dd[4] = {0, 100, 100, 100};
    const uint8_t* four[4] = {a, b, c, dd};
    uint8_t m[4];
    tp_light_times_mean(four, 4, m);
    EXPECT_EQ_INT(1, m[0]);  /* 3 / 4 rounded */
    EXPECT_EQ_INT(28, m[1]); /* 113 / 4 = 28.25 */
    EXPECT_EQ_INT(76, m[2]); /* 303 / 4 = 75.75 */
    EXPECT_EQ_INT(90, m[3]); /* 358 / 4 = 89.5: up */
    EXPECT_TRUE(m[0] <= m[1] && m[1] <= m[2] && m[2] <= m[3]);
    tp_light_times_mean(four, 1, m);
    EXPECT_EQ_INT(200, m[2]);
    EXPECT_NEAR(tp_light_times_tau(100.0, 200.0, 150.0), 127.5, 1e-12);
}

TEST(bad_days_are_refused_and_out_is_untouched)
{
    float z[4] = {1, 2, 3, 4};
    uint8_t out[16];
    memset(out, 7, sizeof out);
    double t[3] = {0.0, 10.0, 5.0}, az[3] = {90, 90, 90}, el[3] = {10, 10, 10};
    tp_error err;
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_light_times_build(z, 4, 2, 2, 10, 10, t, az, el, 1,
                                                           out, 16, NULL, NULL, NULL, &err));
    EXPECT_CONTAINS(err.message, "at least 2");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_light_times_build(z, 4, 2, 2, 10, 10, t, az, el, 3,
                                                           out, 16, NULL, NULL, NULL, &err));
    EXPECT_CONTAINS(err.message, "time 2");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_light_times_build(z, 3, 2, 2, 10, 10, t, az, el, 2,
                                                           out, 16, NULL, NULL, NULL, &err));
    el[1] = 95.0;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_light_times_build(z, 4, 2, 2, 10, 10, t, az, el, 2,
                                                           out, 16, NULL, NULL, NULL, &err));
    EXPECT_CONTAINS(err.message, "elevation 95");
    for (int i = 0; i < 16; ++i)
        EXPECT_EQ_INT(7, out[i]);
}

TP_TEST_MAIN(TESTS)
