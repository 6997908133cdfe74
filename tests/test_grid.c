/*
 * test_grid.c - the resident terrain: creation, fitting, quantisation, per-patch tables
 * (AABB, delta_k), sample access, height queries, normals and georeferencing.
 *
 * Expected values come from hand-made grids (planes, spikes, flat ground) with known answers,
 * or from brute force over tp_terrain_sample with the documented triangle split.
 */
#include "tp_test_geom.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

static tp_terrain_info info_of(const tp_terrain* t)
{
    tp_terrain_info ti;
    memset(&ti, 0xCD, sizeof ti);
    tp_terrain_get_info(t, &ti);
    return ti;
}

static tp_terrain_desc desc_of(const float* h, int w, int ht, int patch_size)
{
    tp_terrain_desc d;
    memset(&d, 0, sizeof d);
    d.heights = h;
    d.height_count = (size_t)w * ht;
    d.width = w;
    d.height = ht;
    d.patch_size = patch_size;
    return d;
}

/* Creation must fail with `expected`, write a message, and leave *out alone. */
static void expect_create_fails(const tp_terrain_desc* d, tp_status expected, const char* what)
{
    tp_terrain* sentinel = (tp_terrain*)&sentinel; /* any non-NULL value that is not a terrain */
    tp_terrain* out = sentinel;
    tp_error err;
    tp_status s;
    memset(&err, 0, sizeof err);
    s = tp_terrain_create(d, &out, &err);
    if (s != expected)
        ADD_FAILURE("%s: expected %s, got %s (%s)", what, tp_test_status_name_(expected),
                    tp_test_status_name_(s), err.message);
    if (out != sentinel) {
        ADD_FAILURE("%s: *out was written on failure", what);
        if (s == TP_OK)
            tp_terrain_destroy(out);
    }
    if (s != TP_OK && err.message[0] == '\0')
        ADD_FAILURE("%s: no error message", what);
    out = sentinel;
    s = tp_terrain_create(d, &out, NULL); /* NULL error pointer accepted */
    if (s != expected)
        ADD_FAILURE("%s (err NULL): got %s", what, tp_test_status_name_(s));
    if (s == TP_OK && out != sentinel)
        tp_terrain_destroy(out);
}

/* ---------------------------------------------------------------------------------------------
 * Brute-force delta_k
 */
typedef struct brute_delta {
    double vs_decoded, vs_source;
} brute_delta;

/* Max error of the unstitched level-k surface of patch p (documented split on the level-k
 * vertices, heights decoded by tp_terrain_sample) against the decoded and the source heights.
 * src is the source grid (width src_w), or NULL. */
static brute_delta level_error(const tp_terrain* t, int p, int k, const float* src, int src_w)
{
    tp_terrain_info ti = info_of(t);
    brute_delta r = {0.0, 0.0};
    int s = 1 << (ti.n - k), x0 = (p % ti.patch_cols) << ti.n, y0 = (p / ti.patch_cols) << ti.n;
    int x, y, last = 1 << ti.n;
    for (y = 0; y <= last; ++y) {
        for (x = 0; x <= last; ++x) {
            int c = x / s, rr = y / s;
            double fx, fy, surf, dec;
            if (c == (1 << k))
                c--;
            if (rr == (1 << k))
                rr--;
            fx = (x - c * s) / (double)s;
            fy = (y - rr * s) / (double)s;
            {
                double h00 = tp_terrain_sample(t, x0 + c * s, y0 + rr * s);
                double h10 = tp_terrain_sample(t, x0 + (c + 1) * s, y0 + rr * s);
                double h01 = tp_terrain_sample(t, x0 + c * s, y0 + (rr + 1) * s);
                double h11 = tp_terrain_sample(t, x0 + (c + 1) * s, y0 + (rr + 1) * s);
                if (fx + fy <= 1.0)
                    surf = h00 + fx * (h10 - h00) + fy * (h01 - h00);
                else
                    surf = h11 + (1 - fx) * (h01 - h11) + (1 - fy) * (h10 - h11);
            }
            dec = tp_terrain_sample(t, x0 + x, y0 + y);
            if (fabs(surf - dec) > r.vs_decoded)
                r.vs_decoded = fabs(surf - dec);
            if (src) {
                double sv = src[(size_t)(y0 + y) * src_w + (x0 + x)];
                if (fabs(surf - sv) > r.vs_source)
                    r.vs_source = fabs(surf - sv);
            }
        }
    }
    return r;
}

/* delta_m[k] of every complete patch lies between the error against the source and the error
 * against the decoded grid plus the quantisation error (equal when quantisation is exact). */
static void check_deltas(const tp_terrain* t, const float* src, int src_w, const char* what)
{
    tp_terrain_info ti = info_of(t);
    int p, k, checked = 0;
    for (p = 0; p < ti.patch_count; ++p) {
        tp_patch_info pi;
        tp_patch_get_info(t, p, &pi);
        if (!pi.complete)
            continue;
        checked++;
        for (k = 0; k <= ti.n; ++k) {
            brute_delta b = level_error(t, p, k, src, src_w);
            /* the tables round up to error_unit_m */
            double lo = src ? b.vs_source : 0.0,
                   hi = b.vs_decoded + ti.quant_max_error_m + ti.error_unit_m;
            if (!(pi.delta_m[k] >= lo - 1e-6 && pi.delta_m[k] <= hi + 1e-6)) {
                ADD_FAILURE("%s: patch %d level %d: delta_m %.9g, brute force: %.9g vs source, "
                            "%.9g vs decoded (+ quant %.3g)",
                            what, p, k, pi.delta_m[k], b.vs_source, b.vs_decoded,
                            ti.quant_max_error_m);
                return;
            }
        }
    }
    EXPECT_GE_INT(checked, 1);
}

/* ---------------------------------------------------------------------------------------------
 * Tests
 */
TEST(status_str_names_every_status)
{
    tp_status s;
    for (s = TP_OK; s <= TP_ERR_BACKEND; s = (tp_status)(s + 1)) {
        const char* a = tp_status_str(s);
        tp_status u;
        ASSERT_TRUE(a != NULL);
        EXPECT_TRUE(a[0] != '\0');
        for (u = TP_OK; u < s; u = (tp_status)(u + 1))
            EXPECT_TRUE(strcmp(a, tp_status_str(u)) != 0);
    }
    EXPECT_TRUE(tp_status_str((tp_status)99) != NULL);
}

/* A message longer than tp_error's buffer keeps its start and its end ("PATH: reason" keeps its
 * reason), the cut marked "..." and never inside a UTF-8 character. */
TEST(error_set_keeps_the_reason_of_a_long_message)
{
    char path[701];
    for (size_t i = 0; i + 2 < sizeof path; i += 2)
        path[i] = (char)0xC3, path[i + 1] = (char)0xA9; /* "é" x 350 */
    path[sizeof path - 1] = '\0';
    tp_error err;
    ASSERT_TRUE(tp_error_set(&err, TP_ERR_IO, "/data/%s.tif: No such file or directory", path) ==
                TP_ERR_IO);
    size_t n = strlen(err.message);
    const char* reason = ".tif: No such file or directory";
    EXPECT_TRUE(n < sizeof err.message && n > sizeof err.message - 8);
    EXPECT_TRUE(strncmp(err.message, "/data/", 6) == 0);
    EXPECT_TRUE(strstr(err.message, "...") != NULL);
    EXPECT_TRUE(n > strlen(reason) && strcmp(err.message + n - strlen(reason), reason) == 0);
    for (size_t i = 0; i < n; i++) { /* every continuation byte follows a lead or another */
        unsigned char c = (unsigned char)err.message[i];
        if ((c & 0xC0) == 0x80) {
            ASSERT_TRUE(i > 0);
            EXPECT_TRUE(((unsigned char)err.message[i - 1] & 0x80) != 0);
        }
        if (c == 0xC3)
            EXPECT_TRUE(i + 1 < n && ((unsigned char)err.message[i + 1] & 0xC0) == 0x80);
    }
    /* a short message is untouched */
    tp_error_set(&err, TP_ERR_IO, "%s: %s", "a.tif", "gone");
    EXPECT_TRUE(strcmp(err.message, "a.tif: gone") == 0);
}

TEST(plane_has_zero_delta_at_every_level)
{
    static float h[65 * 49];
    int x, y, pass;
    for (pass = 0; pass < 2; ++pass) {
        tp_terrain* t;
        tp_terrain_info ti;
        int p, k;
        for (y = 0; y < 49; ++y)
            for (x = 0; x < 65; ++x)
                h[y * 65 + x] = pass == 0 ? (float)(200 + 2 * x - 3 * y)            /* integers */
                                          : (float)(1000.125 + 0.25 * x + 0.5 * y); /* dyadic */
        t = tpt_terrain_create(h, 65, 49, 17, TP_FIT_PAD, NULL);
        ti = info_of(t);
        EXPECT_EQ_DBL(0.0, ti.quant_max_error_m);
        for (p = 0; p < ti.patch_count; ++p) {
            tp_patch_info pi;
            tp_patch_get_info(t, p, &pi);
            EXPECT_EQ_INT(1, pi.complete);
            for (k = 0; k <= ti.n; ++k)
                if (!(fabs(pi.delta_m[k]) <= 1e-9))
                    ADD_FAILURE("%s plane: patch %d level %d delta %.9g, expected 0",
                                pass ? "dyadic" : "integer", p, k, pi.delta_m[k]);
        }
        tp_terrain_destroy(t);
    }
}

/* 3 x 3 patches of 17 at 100 m with one spike of +64 m at (sx, sy). */
static tp_terrain* spike_terrain(int sx, int sy)
{
    static float h[49 * 49];
    int i;
    for (i = 0; i < 49 * 49; ++i)
        h[i] = 100.0f;
    h[sy * 49 + sx] = 164.0f;
    return tpt_terrain_create(h, 49, 49, 17, TP_FIT_PAD, NULL);
}

static void expect_deltas(const tp_terrain* t, int p, const double want[5], const char* what)
{
    tp_patch_info pi;
    int k;
    tp_patch_get_info(t, p, &pi);
    for (k = 0; k <= 4; ++k)
        if (!(fabs(pi.delta_m[k] - want[k]) <= 1e-9))
            ADD_FAILURE("%s: patch %d level %d: delta %.9g, expected %g", what, p, k, pi.delta_m[k],
                        want[k]);
}

TEST(spike_between_coarse_vertices_gives_full_height_delta)
{
    /* the spike at local (3,5) of the middle patch is a vertex of level 4 only: every coarser
     * level misses all of it, level 4 draws it exactly; the other patches are flat */
    static const double want[5] = {64, 64, 64, 64, 0}, flat[5] = {0, 0, 0, 0, 0};
    tp_terrain* t = spike_terrain(16 + 3, 16 + 5);
    int p;
    expect_deltas(t, 4, want, "spike at (3,5)");
    for (p = 0; p < 9; ++p)
        if (p != 4)
            expect_deltas(t, p, flat, "flat patch next to the spike");
    tp_terrain_destroy(t);
}

TEST(spike_on_a_level_2_vertex_gives_hat_function_deltas)
{
    /* at local (4,4) the spike is a vertex from level 2 on; the level-k surface is then a hat
     * of radius 2^(4-k) cells, which misses its direct neighbours by (1 - 2^(k-4)) * 64 */
    static const double want[5] = {64, 64, 48, 32, 0};
    tp_terrain* t = spike_terrain(16 + 4, 16 + 4);
    expect_deltas(t, 4, want, "spike at (4,4)");
    tp_terrain_destroy(t);
}

TEST(spike_on_shared_border_counts_in_both_patches)
{
    static const double want[5] = {64, 64, 48, 32, 0};
    tp_terrain* t = spike_terrain(16, 16 + 4); /* left border of patch 4, right border of 3 */
    expect_deltas(t, 3, want, "border spike, left patch");
    expect_deltas(t, 4, want, "border spike, right patch");
    tp_terrain_destroy(t);
}

TEST(delta_matches_brute_force_synthetic)
{
    int w = 97, h = 65, ps;
    float* src = (float*)malloc(sizeof(float) * w * h);
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 201, 700.0, 250.0, 12.0, 0);
    for (ps = 17; ps <= 33; ps = 2 * ps - 1) {
        tp_terrain* t = tpt_terrain_create(src, w, h, ps, TP_FIT_PAD, NULL);
        char what[32];
        snprintf(what, sizeof what, "synthetic patch %d", ps);
        check_deltas(t, src, w, what);
        tp_terrain_destroy(t);
    }
    free(src);
}

#ifndef TP_TEST_NO_IO
static tp_dem* read_dem(const char* env_var, const char* file)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err;
    tp_status s;
    REQUIRE_DATA_FILE(path, env_var, file);
    s = tp_dem_read(path, &dem, &err);
    if (s != TP_OK)
        FAIL("tp_dem_read(%s): %s: %s", path, tp_test_status_name_(s), err.message);
    return dem;
}
#endif

TEST(delta_matches_brute_force_real_dem)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    tp_dem* dem = read_dem("TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif");
    int ps;
    for (ps = 17; ps <= 33; ps = 2 * ps - 1) { /* at 65 no patch of storml is complete */
        tp_terrain_desc d = tp_dem_terrain_desc(dem, ps, TP_FIT_PAD);
        tp_terrain* t = NULL;
        tp_error err;
        char what[32];
        float* src;
        tp_terrain_info ti;
        int x, y;
        ASSERT_OK(tp_terrain_create(&d, &t, &err));
        ti = info_of(t);
        /* the source on the fitted grid (padding = NaN, never compared: incomplete patches) */
        src = (float*)malloc(sizeof(float) * ti.width * ti.height);
        ASSERT_TRUE(src != NULL);
        for (y = 0; y < ti.height; ++y)
            for (x = 0; x < ti.width; ++x)
                src[(size_t)y * ti.width + x] = x < dem->width && y < dem->height
                                                    ? dem->heights[(size_t)y * dem->width + x]
                                                    : NAN;
        snprintf(what, sizeof what, "storml patch %d", ps);
        check_deltas(t, src, ti.width, what);
        free(src);
        tp_terrain_destroy(t);
    }
    tp_dem_destroy(dem);
#endif
}

TEST(shared_border_samples_decode_identically)
{
    /* 600 m of relief across 4 x 3 patches: the per-patch offsets differ */
    int w = 65, h = 49, p;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_terrain_info ti;
    static tp_vertex a[17 * 17], b[17 * 17];
    int nb[4];
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 211, 1200.0, 600.0, 3.0, 0);
    for (p = 0; p < w * h; ++p)
        src[p] += (float)(p % w) * 9.0f; /* a steep tilt as well */
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL);
    ti = info_of(t);
    tpt_fill4(nb, 4);
    for (p = 0; p < ti.patch_count; ++p) {
        int col = p % ti.patch_cols, row = p / ti.patch_cols, i;
        tp_patch_vertices(t, p, 4, nb, a, 17 * 17);
        if (col + 1 < ti.patch_cols) {
            tp_patch_vertices(t, p + 1, 4, nb, b, 17 * 17);
            for (i = 0; i < 17; ++i) {
                const tp_vertex *l = &a[i * 17 + 16], *r = &b[i * 17];
                if (l->x != r->x || l->y != r->y || memcmp(&l->z_m, &r->z_m, sizeof(float)) != 0)
                    ADD_FAILURE("patches %d|%d row %d: (%d,%d,%.9g) vs (%d,%d,%.9g)", p, p + 1, i,
                                l->x, l->y, l->z_m, r->x, r->y, r->z_m);
            }
        }
        if (row + 1 < ti.patch_rows) {
            tp_patch_vertices(t, p + ti.patch_cols, 4, nb, b, 17 * 17);
            for (i = 0; i < 17; ++i) {
                const tp_vertex *u = &a[16 * 17 + i], *d = &b[i];
                if (u->x != d->x || u->y != d->y || memcmp(&u->z_m, &d->z_m, sizeof(float)) != 0)
                    ADD_FAILURE("patches %d/%d column %d: (%d,%d,%.9g) vs (%d,%d,%.9g)", p,
                                p + ti.patch_cols, i, u->x, u->y, u->z_m, d->x, d->y, d->z_m);
            }
        }
    }
    tp_terrain_destroy(t);
    free(src);
}

TEST(quantised_heights_within_half_step_of_source)
{
    int w = 81, h = 49, x, y;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_terrain_info ti;
    double worst = 0;
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 221, 300.0, 1500.0, 7.0, 0);
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL);
    ti = info_of(t);
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) {
            double d = fabs(tp_terrain_sample(t, x, y) - src[y * w + x]);
            if (!(d <= ti.height_step_m / 2 + 1e-9))
                ADD_FAILURE("sample (%d,%d): |decoded - source| = %.9g > step/2 = %.9g", x, y, d,
                            ti.height_step_m / 2);
            if (d > worst)
                worst = d;
        }
    EXPECT_NEAR(worst, ti.quant_max_error_m, 1e-9);
    /* the error tables resolve step/16 .. step */
    EXPECT_GE(ti.error_unit_m, ti.height_step_m / 16 - 1e-15);
    EXPECT_LE(ti.error_unit_m, ti.height_step_m + 1e-15);
    tp_terrain_destroy(t);
    free(src);
}

TEST(integer_source_gets_unit_step_and_exact_heights)
{
    int w = 49, h = 33, x, y;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_terrain_info ti;
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 231, -50.0, 3000.0, 40.0, 1); /* integers, some negative */
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL);
    ti = info_of(t);
    EXPECT_EQ_DBL(1.0, ti.height_step_m);
    EXPECT_EQ_DBL(0.0, ti.quant_max_error_m);
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x)
            if (tp_terrain_sample(t, x, y) != src[y * w + x]) {
                ADD_FAILURE("sample (%d,%d) decodes to %.9g, source %.9g", x, y,
                            tp_terrain_sample(t, x, y), src[y * w + x]);
                break;
            }
    tp_terrain_destroy(t);
    free(src);
}

/* A float terrain whose every patch spans about `range` metres. */
static tp_terrain* ramp_terrain(double range, float** out_src)
{
    int w = 49, h = 33, x, y;
    float* src = (float*)malloc(sizeof(float) * w * h);
    ASSERT_TRUE(src != NULL);
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) /* a ramp of `range` per 16 columns, plus a fractional wiggle */
            src[y * w + x] = (float)(1234.567 + range * x / 16.0 + 0.3 * sin(x * 1.7 + y));
    *out_src = src;
    return tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL);
}

TEST(float_source_gets_finest_power_of_two_step)
{
    float* src;
    tp_terrain* t;
    tp_terrain_info ti;
    /* ~41 m per patch: 41 * 1024 < 65536, so the finest allowed step 2^-10 fits */
    t = ramp_terrain(40.0, &src);
    ti = info_of(t);
    EXPECT_EQ_DBL(1.0 / 1024.0, ti.height_step_m);
    EXPECT_LE(ti.quant_max_error_m, ti.height_step_m / 2 + 1e-12);
    EXPECT_GT(ti.quant_max_error_m, 0.0);
    tp_terrain_destroy(t);
    free(src);
    /* ~3000 m per patch: 3000 * 16 = 48000 fits, 3000 * 32 does not -> 1/16 m */
    t = ramp_terrain(3000.0, &src);
    ti = info_of(t);
    EXPECT_EQ_DBL(1.0 / 16.0, ti.height_step_m);
    EXPECT_LE(ti.quant_max_error_m, ti.height_step_m / 2 + 1e-12);
    tp_terrain_destroy(t);
    free(src);
}

TEST(explicit_step_is_used_or_rejected_when_too_fine)
{
    float* src;
    tp_terrain* t;
    tp_terrain_info ti;
    tp_terrain_desc d;
    t = ramp_terrain(3000.0, &src);
    tp_terrain_destroy(t);
    d = desc_of(src, 49, 33, 17);
    d.height_step_m = 0.5;
    t = NULL;
    ASSERT_OK(tp_terrain_create(&d, &t, NULL));
    ti = info_of(t);
    EXPECT_EQ_DBL(0.5, ti.height_step_m);
    EXPECT_LE(ti.quant_max_error_m, 0.25 + 1e-12);
    tp_terrain_destroy(t);
    d.height_step_m = 1.0 / 1024.0; /* 3000 m in steps of 1 mm does not fit 16 bits */
    expect_create_fails(&d, TP_ERR_INVALID_ARG, "step 2^-10 over 3000 m");
    free(src);
}

TEST(height_at_matches_documented_split)
{
    /* 65 x 49 fits 4 x 3 patches exactly: the last row and column are the grid's own */
    int w = 65, h = 49, i;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_terrain_info ti;
    tp_rng rng = tp_rng_seed(241);
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 242, 500.0, 200.0, 30.0, 0);
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL);
    ti = info_of(t);
    ASSERT_EQ_INT(w, ti.width);
    ASSERT_EQ_INT(h, ti.height);
    for (i = 0; i < 20000; ++i) {
        double x = tp_rng_range(&rng, 0, w - 1), y = tp_rng_range(&rng, 0, h - 1);
        double want, got;
        if (i % 5 == 0)
            x = floor(x); /* on grid lines too */
        if (i % 7 == 0)
            y = floor(y);
        if (i % 11 == 0) { /* on the cell diagonal */
            double f = y - floor(y);
            x = floor(x) + 1.0 - f;
            if (x > w - 1)
                continue;
        }
        if (i % 13 == 0)
            x = w - 1; /* on the last column and row */
        if (i % 17 == 0)
            y = h - 1;
        want = tpt_split_height(tpt_terrain_sample_cb, t, ti.width, ti.height, x, y);
        got = tp_terrain_height_at(t, x, y);
        if (!(fabs(want - got) <= 1e-9 * (fabs(want) + 1))) {
            ADD_FAILURE("height_at(%.9g, %.9g) = %.12g, the split gives %.12g", x, y, got, want);
            break;
        }
    }
    /* at samples, including the grid's corners */
    EXPECT_EQ_DBL(tp_terrain_sample(t, 0, 0), tp_terrain_height_at(t, 0, 0));
    EXPECT_EQ_DBL(tp_terrain_sample(t, w - 1, h - 1), tp_terrain_height_at(t, w - 1, h - 1));
    EXPECT_EQ_DBL(tp_terrain_sample(t, w - 1, 0), tp_terrain_height_at(t, w - 1, 0));
    EXPECT_EQ_DBL(tp_terrain_sample(t, 0, h - 1), tp_terrain_height_at(t, 0, h - 1));
    EXPECT_EQ_DBL(tp_terrain_sample(t, w - 1, 7), tp_terrain_height_at(t, w - 1, 7));
    EXPECT_EQ_DBL(tp_terrain_sample(t, 9, h - 1), tp_terrain_height_at(t, 9, h - 1));
    tp_terrain_destroy(t);
    free(src);
}

static double lerp_samples(const tp_terrain* t, int x0, int y0, int x1, int y1, double f)
{
    double a = tp_terrain_sample(t, x0, y0), b = tp_terrain_sample(t, x1, y1);
    return a + f * (b - a);
}

TEST(height_at_on_edge_of_drawn_area_is_drawn)
{
    /* A point on the boundary between a drawn triangle and an undrawn one (padding or
     * nodata) is on the rendered surface: its height is the drawn edge's, not NaN. */
    int w = 57, h = 41, i;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 243, 500.0, 200.0, 30.0, 0);
    src[10 * w + 10] = NAN;
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL); /* padded to 65 x 49 */
    for (i = 0; i <= 4 * (h - 1); ++i) { /* the last source column, next to padding */
        double y = i / 4.0, f = y - floor(y);
        int r = (int)floor(y) < h - 1 ? (int)floor(y) : h - 2;
        f = y - r;
        EXPECT_NEAR(lerp_samples(t, w - 1, r, w - 1, r + 1, f), tp_terrain_height_at(t, w - 1, y),
                    1e-9);
    }
    for (i = 0; i <= 4 * (w - 1); ++i) { /* the last source row */
        double x = i / 4.0, f;
        int c = (int)floor(x) < w - 1 ? (int)floor(x) : w - 2;
        f = x - c;
        EXPECT_NEAR(lerp_samples(t, c, h - 1, c + 1, h - 1, f), tp_terrain_height_at(t, x, h - 1),
                    1e-9);
    }
    /* the rim of the hole at (10,10): cell diagonals whose other side is drawn */
    EXPECT_NEAR(lerp_samples(t, 11, 10, 10, 11, 0.5), tp_terrain_height_at(t, 10.5, 10.5), 1e-9);
    EXPECT_NEAR(lerp_samples(t, 10, 9, 9, 10, 0.5), tp_terrain_height_at(t, 9.5, 9.5), 1e-9);
    EXPECT_NEAR(lerp_samples(t, 10, 11, 11, 11, 0.25), tp_terrain_height_at(t, 10.25, 11.0), 1e-9);
    /* an edge with the hole as an end point is not drawn */
    EXPECT_NAN(tp_terrain_height_at(t, 10.0, 9.5));
    tp_terrain_destroy(t);
    free(src);
}

/* Checks height_at over one lone drawn triangle (a, b, c) (grid positions, heights from the
 * terrain): its vertices, edge midpoints and centroid are on the rendered surface. */
static void expect_lone_triangle(const tp_terrain* t, const int p[3][2], const char* what)
{
    double z[3], pts[7][3];
    int i;
    for (i = 0; i < 3; ++i)
        z[i] = tp_terrain_sample(t, p[i][0], p[i][1]);
    for (i = 0; i < 3; ++i) { /* vertices and edge midpoints */
        int j = (i + 1) % 3;
        pts[i][0] = p[i][0];
        pts[i][1] = p[i][1];
        pts[i][2] = z[i];
        pts[3 + i][0] = (p[i][0] + p[j][0]) / 2.0;
        pts[3 + i][1] = (p[i][1] + p[j][1]) / 2.0;
        pts[3 + i][2] = (z[i] + z[j]) / 2.0;
    }
    pts[6][0] = (p[0][0] + p[1][0] + p[2][0]) / 3.0;
    pts[6][1] = (p[0][1] + p[1][1] + p[2][1]) / 3.0;
    pts[6][2] = (z[0] + z[1] + z[2]) / 3.0;
    for (i = 0; i < 7; ++i) {
        double got = tp_terrain_height_at(t, pts[i][0], pts[i][1]);
        if (!(fabs(got - pts[i][2]) <= 1e-9))
            ADD_FAILURE("%s: height_at(%g, %g) = %.9g, the lone drawn triangle gives %.9g", what,
                        pts[i][0], pts[i][1], got, pts[i][2]);
    }
}

TEST(height_at_on_a_lone_drawn_triangle)
{
    /* Every sample is nodata except the three corners of one triangle: each point of that
     * triangle, its vertices included, is on the rendered surface; points off it are NaN. */
    static float h[33 * 33];
    static const int ul[3][2] = {{10, 10}, {11, 10}, {10, 11}}; /* upper-left half of (10,10) */
    static const int lr[3][2] = {{21, 20}, {20, 21}, {21, 21}}; /* lower-right half of (20,20) */
    tp_terrain* t;
    int i;
    for (i = 0; i < 33 * 33; ++i)
        h[i] = NAN;
    for (i = 0; i < 3; ++i) {
        h[ul[i][1] * 33 + ul[i][0]] = (float)(100 + 7 * i);
        h[lr[i][1] * 33 + lr[i][0]] = (float)(200 - 5 * i);
    }
    t = tpt_terrain_create(h, 33, 33, 17, TP_FIT_PAD, NULL);
    expect_lone_triangle(t, ul, "upper-left half");
    expect_lone_triangle(t, lr, "lower-right half");
    EXPECT_NAN(tp_terrain_height_at(t, 10.6, 10.6)); /* the other half of cell (10,10) */
    EXPECT_NAN(tp_terrain_height_at(t, 20.4, 20.4)); /* the other half of cell (20,20) */
    EXPECT_NAN(tp_terrain_height_at(t, 9.5, 10.5));
    tp_terrain_destroy(t);
}

TEST(nan_outside_grid_and_over_nodata)
{
    static float h[33 * 33];
    tp_terrain* t;
    int i;
    for (i = 0; i < 33 * 33; ++i)
        h[i] = 50.0f + (float)(i % 7);
    h[10 * 33 + 10] = NAN;
    t = tpt_terrain_create(h, 33, 33, 17, TP_FIT_PAD, NULL);
    EXPECT_NAN(tp_terrain_sample(t, -1, 0));
    EXPECT_NAN(tp_terrain_sample(t, 0, -1));
    EXPECT_NAN(tp_terrain_sample(t, 33, 0));
    EXPECT_NAN(tp_terrain_sample(t, 0, 33));
    EXPECT_EQ_INT(TP_SAMPLE_OUTSIDE, tp_terrain_sample_class(t, -1, 0));
    EXPECT_EQ_INT(TP_SAMPLE_OUTSIDE, tp_terrain_sample_class(t, 5, 33));
    EXPECT_NAN(tp_terrain_sample(t, 10, 10));
    EXPECT_EQ_INT(TP_SAMPLE_NODATA, tp_terrain_sample_class(t, 10, 10));
    EXPECT_EQ_INT(TP_SAMPLE_VALID, tp_terrain_sample_class(t, 11, 10));
    EXPECT_NAN(tp_terrain_height_at(t, -0.01, 5.0));
    EXPECT_NAN(tp_terrain_height_at(t, 5.0, -0.01));
    EXPECT_NAN(tp_terrain_height_at(t, 32.01, 5.0));
    EXPECT_NAN(tp_terrain_height_at(t, 5.0, 32.0001));
    EXPECT_NAN(tp_terrain_height_at(t, NAN, 5.0));
    /* the six triangles around (10,10) each have it as a vertex */
    EXPECT_NAN(tp_terrain_height_at(t, 10.2, 10.3)); /* upper-left half of cell (10,10) */
    EXPECT_NAN(tp_terrain_height_at(t, 9.8, 9.9));   /* lower-right half of cell (9,9) */
    EXPECT_NAN(tp_terrain_height_at(t, 9.2, 10.3));  /* cell (9,10), both halves touch it */
    EXPECT_NAN(tp_terrain_height_at(t, 9.8, 10.6));
    EXPECT_NAN(tp_terrain_height_at(t, 10.3, 9.8));
    /* the lower-right half of cell (10,10) does not touch (10,10) */
    EXPECT_FALSE(isnan(tp_terrain_height_at(t, 10.8, 10.7)));
    EXPECT_FALSE(isnan(tp_terrain_height_at(t, 20.5, 20.25)));
    tp_terrain_destroy(t);
}

TEST(grid_height_at_equals_terrain_height_at_on_random_points)
{
    /* Integer heights are stored exactly (unit step), so the plain grid's surface and the
     * terrain's are the same numbers: voids, the padded edge and points outside included. */
    int w = 57, h = 41, i, compared = 0, nans = 0;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_rng rng = tp_rng_seed(907);
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 908, 500.0, 200.0, 30.0, 1);
    for (i = 0; i < 40; ++i) /* scattered voids */
        src[(size_t)tp_rng_range(&rng, 0, h - 1) * w + (size_t)tp_rng_range(&rng, 0, w - 1)] = NAN;
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL); /* padded to 65 x 49 */
    for (i = 0; i < 50000; ++i) {
        double x = tp_rng_range(&rng, -1, w + 1), y = tp_rng_range(&rng, -1, h + 1);
        if (i % 3 == 0)
            x = floor(x); /* on grid lines and vertices too */
        if (i % 4 == 0)
            y = floor(y);
        if (i % 7 == 0) /* on a cell diagonal */
            x = floor(x) + 1.0 - (y - floor(y));
        double want = tp_terrain_height_at(t, x, y);
        double got = tp_grid_height_at(src, (size_t)w * h, w, h, x, y);
        if (isnan(want) != isnan(got) || (!isnan(want) && want != got)) {
            ADD_FAILURE("(%.9g, %.9g): grid %.12g, terrain %.12g", x, y, got, want);
            break;
        }
        compared++;
        nans += isnan(want);
    }
    EXPECT_GT(nans, 1000); /* outside and over voids: both NaN */
    EXPECT_GT(compared - nans, 30000);
    tp_terrain_destroy(t);
    free(src);
}

TEST(grid_height_at_splits_along_the_documented_diagonal)
{
    /* (0,0)=0 (1,0)=1 / (0,1)=2 (1,1)=4: the diagonal runs from (1,0) to (0,1) */
    static const float z[4] = {0, 1, 2, 4};
    EXPECT_NEAR(0.75, tp_grid_height_at(z, 4, 2, 2, 0.25, 0.25), 1e-12);
    EXPECT_NEAR(2.75, tp_grid_height_at(z, 4, 2, 2, 0.75, 0.75), 1e-12);
    EXPECT_NEAR(1.5, tp_grid_height_at(z, 4, 2, 2, 0.5, 0.5), 1e-12); /* on the diagonal */
    EXPECT_EQ_DBL(4.0, tp_grid_height_at(z, 4, 2, 2, 1, 1));
    EXPECT_NAN(tp_grid_height_at(z, 4, 2, 2, 1.0001, 0.5));
    EXPECT_NAN(tp_grid_height_at(z, 4, 2, 2, NAN, 0.5));
    /* too small to hold a triangle */
    EXPECT_NAN(tp_grid_height_at(z, 2, 2, 1, 0.5, 0));
    EXPECT_NAN(tp_grid_height_at(z, 1, 1, 1, 0, 0));
    EXPECT_NAN(tp_grid_height_at(NULL, 0, 0, 0, 0, 0));
}

TEST(flat_ground_is_flat)
{
    static float h[40 * 30];
    tp_terrain* t;
    tp_terrain_info ti;
    int i, p, k;
    tp_rng rng = tp_rng_seed(251);
    for (i = 0; i < 40 * 30; ++i)
        h[i] = 321.0f;
    t = tpt_terrain_create(h, 40, 30, 17, TP_FIT_PAD, NULL);
    ti = info_of(t);
    EXPECT_EQ_DBL(321.0, ti.min_height_m);
    EXPECT_EQ_DBL(321.0, ti.max_height_m);
    for (p = 0; p < ti.patch_count; ++p) {
        tp_patch_info pi;
        tp_patch_get_info(t, p, &pi);
        EXPECT_EQ_DBL(321.0, pi.aabb_min[2]);
        EXPECT_EQ_DBL(321.0, pi.aabb_max[2]);
        for (k = 0; k <= ti.n && pi.complete; ++k)
            EXPECT_EQ_DBL(0.0, pi.delta_m[k]);
    }
    for (i = 0; i < 1000; ++i) {
        double x = tp_rng_range(&rng, 0, 39), y = tp_rng_range(&rng, 0, 29);
        EXPECT_EQ_DBL(321.0, tp_terrain_height_at(t, x, y));
    }
    {
        float nrm[3];
        tp_terrain_normal(t, 5, 5, nrm);
        EXPECT_NEAR(0.0, nrm[0], 1e-6);
        EXPECT_NEAR(0.0, nrm[1], 1e-6);
        EXPECT_NEAR(1.0, nrm[2], 1e-6);
    }
    tp_terrain_destroy(t);
}

/* Fitted size for TP_FIT_PAD: at least one patch, enough to hold the source. */
static int padded(int n_src, int cells)
{
    int patches = (n_src - 1 + cells - 1) / cells;
    return (patches < 1 ? 1 : patches) * cells + 1;
}

TEST(small_and_thin_grids_are_padded_and_padding_never_drawn)
{
    static const int sizes[][2] = {{1, 1},   {2, 2},   {3, 3},   {1, 40}, {40, 1},
                                   {17, 17}, {18, 17}, {20, 37}, {2, 19}};
    size_t s;
    static tp_vertex v[17 * 17];
    static uint32_t tri[3 * 512];
    for (s = 0; s < sizeof sizes / sizeof sizes[0]; ++s) {
        int w = sizes[s][0], h = sizes[s][1], x, y, p, nb[4];
        float* src = (float*)malloc(sizeof(float) * w * h);
        tp_terrain* t;
        tp_terrain_info ti;
        size_t drawn = 0;
        ASSERT_TRUE(src != NULL);
        for (x = 0; x < w * h; ++x)
            src[x] = (float)(10 + x % 13);
        t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL);
        ti = info_of(t);
        EXPECT_EQ_INT(w, ti.src_width);
        EXPECT_EQ_INT(h, ti.src_height);
        EXPECT_EQ_INT(padded(w, 16), ti.width);
        EXPECT_EQ_INT(padded(h, 16), ti.height);
        EXPECT_EQ_INT((ti.width - 1) / 16, ti.patch_cols);
        EXPECT_EQ_INT((ti.height - 1) / 16, ti.patch_rows);
        EXPECT_EQ_INT(ti.patch_cols * ti.patch_rows, ti.patch_count);
        EXPECT_EQ_INT(17, ti.patch_size);
        EXPECT_EQ_INT(4, ti.n);
        EXPECT_EQ_INT(5, ti.levels);
        EXPECT_EQ_INT(TP_FIT_PAD, ti.fit);
        EXPECT_EQ_INT((size_t)w * h, ti.valid_samples);
        EXPECT_EQ_INT((size_t)ti.width * ti.height - (size_t)w * h, ti.padding_samples);
        EXPECT_EQ_INT(0, ti.nodata_samples);
        EXPECT_EQ_DBL(0.0, ti.fit_max_error_m);
        for (y = 0; y < ti.height; ++y)
            for (x = 0; x < ti.width; ++x) {
                int pad = x >= w || y >= h;
                tp_sample_class c = tp_terrain_sample_class(t, x, y);
                if (c != (pad ? TP_SAMPLE_PADDING : TP_SAMPLE_VALID) ||
                    isnan(tp_terrain_sample(t, x, y)) != pad) {
                    ADD_FAILURE("%dx%d: sample (%d,%d) class %d, height %g", w, h, x, y, (int)c,
                                tp_terrain_sample(t, x, y));
                    y = ti.height;
                    break;
                }
            }
        /* drawn at full resolution, exactly the cells of the source are drawn */
        tpt_fill4(nb, 4);
        for (p = 0; p < ti.patch_count; ++p) {
            tp_patch_info pi;
            size_t tc, i;
            tp_patch_get_info(t, p, &pi);
            tc = tpt_patch_geometry(t, p, 4, nb, v, 17 * 17, tri, 512);
            for (i = 0; i < 3 * tc; ++i)
                if (v[tri[i]].cls == TP_SAMPLE_PADDING) {
                    ADD_FAILURE("%dx%d: patch %d draws padding sample (%d,%d)", w, h, p,
                                v[tri[i]].x, v[tri[i]].y);
                    break;
                }
            drawn += tc;
            if (pi.complete != (pi.x0 + 16 < w && pi.y0 + 16 < h))
                ADD_FAILURE("%dx%d: patch %d complete = %d", w, h, p, pi.complete);
        }
        EXPECT_EQ_INT(2 * (size_t)(w - 1) * (h - 1), drawn);
        tp_terrain_destroy(t);
        free(src);
    }
}

TEST(pad_keeps_geotransform)
{
    static float h[20 * 37];
    double gt[6] = {323476.072, 30.0, 0.0, 5105081.983, 0.0, -30.0};
    tp_terrain* t;
    tp_terrain_info ti;
    int i;
    for (i = 0; i < 20 * 37; ++i)
        h[i] = (float)(i % 17);
    t = tpt_terrain_create(h, 20, 37, 17, TP_FIT_PAD, gt);
    ti = info_of(t);
    for (i = 0; i < 6; ++i)
        EXPECT_EQ_DBL(gt[i], ti.geotransform[i]);
    tp_terrain_destroy(t);
}

TEST(resample_fits_nearest_multiple_and_keeps_a_plane)
{
    /* a plane in world coordinates: resampling it bilinearly is exact wherever the new posts
     * fall inside the source's posts */
    int w = 20, h = 37, x, y, checked = 0;
    double gt[6] = {1000.0, 5.0, 0.0, 3000.0, 0.0, -5.0};
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_terrain_info ti;
    ASSERT_TRUE(src != NULL);
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x) {
            double e = gt[0] + (x + 0.5) * gt[1], n = gt[3] + (y + 0.5) * gt[5];
            src[y * w + x] = (float)(0.01 * e + 0.02 * n - 40.0);
        }
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_RESAMPLE, gt);
    ti = info_of(t);
    EXPECT_EQ_INT(TP_FIT_RESAMPLE, ti.fit);
    EXPECT_EQ_INT(17, ti.width);  /* 20 is nearer 17 than 33 */
    EXPECT_EQ_INT(33, ti.height); /* 37 is nearer 33 than 49 */
    EXPECT_EQ_INT(0, ti.padding_samples);
    EXPECT_GE(ti.fit_max_error_m, 0.0);
    EXPECT_LE(ti.fit_rms_error_m, ti.fit_max_error_m + 1e-12);
    EXPECT_LE(ti.fit_max_error_m, ti.height_step_m / 2 + 1e-4);
    EXPECT_EQ_DBL(0.0, ti.geotransform[2]);
    EXPECT_EQ_DBL(0.0, ti.geotransform[4]);
    for (y = 0; y < ti.height; ++y)
        for (x = 0; x < ti.width; ++x) {
            double e, n, sx, sy, want, got;
            tp_terrain_grid_to_world(t, x, y, &e, &n);
            /* the post must lie within the source extent */
            EXPECT_TRUE(e >= gt[0] - 1e-6 && e <= gt[0] + w * gt[1] + 1e-6);
            EXPECT_TRUE(n <= gt[3] + 1e-6 && n >= gt[3] + h * gt[5] - 1e-6);
            sx = (e - gt[0]) / gt[1] - 0.5;
            sy = (n - gt[3]) / gt[5] - 0.5;
            if (sx < -1e-9 || sy < -1e-9 || sx > w - 1 + 1e-9 || sy > h - 1 + 1e-9)
                continue;
            want = 0.01 * e + 0.02 * n - 40.0;
            got = tp_terrain_sample(t, x, y);
            checked++;
            if (!(fabs(want - got) <= ti.height_step_m / 2 + 1e-4))
                ADD_FAILURE("resampled post (%d,%d) at E %.3f N %.3f: %.6f, the plane is %.6f", x,
                            y, e, n, got, want);
        }
    EXPECT_GE_INT(checked, 17 * 33 / 2);
    tp_terrain_destroy(t);
    free(src);
}

TEST(resample_of_tiny_and_thin_grids)
{
    /* A constant surface stays constant whatever the fitted size; the fitted size is the
     * nearest r * 16 + 1 with r >= 1 (no ties among these sizes). A grid one sample wide has
     * nothing to interpolate between: it may be refused as a bad size (TP_ERR_INVALID_ARG with
     * a message, *out untouched) - the header does not say which. */
    static const int sizes[][4] = {{1, 1, 17, 17},  {2, 2, 17, 17},  {3, 3, 17, 17},
                                   {1, 40, 17, 33}, {40, 1, 33, 17}, {2, 19, 17, 17}};
    size_t i;
    for (i = 0; i < sizeof sizes / sizeof sizes[0]; ++i) {
        int w = sizes[i][0], h = sizes[i][1], x, y;
        float* src = (float*)malloc(sizeof(float) * w * h);
        tp_terrain* t;
        tp_terrain_desc d;
        tp_terrain_info ti;
        tp_error err;
        tp_status st;
        ASSERT_TRUE(src != NULL);
        for (x = 0; x < w * h; ++x)
            src[x] = 77.0f;
        d = desc_of(src, w, h, 17);
        d.fit = TP_FIT_RESAMPLE;
        t = (tp_terrain*)&d; /* a sentinel */
        memset(&err, 0, sizeof err);
        st = tp_terrain_create(&d, &t, &err);
        if (st != TP_OK && (w == 1 || h == 1)) {
            EXPECT_STATUS(TP_ERR_INVALID_ARG, st);
            EXPECT_TRUE(t == (tp_terrain*)&d);
            EXPECT_TRUE(err.message[0] != '\0');
            tp_test_note("%dx%d: %s", w, h, err.message);
            free(src);
            continue;
        }
        ASSERT_OK(st);
        ti = info_of(t);
        EXPECT_EQ_INT(sizes[i][2], ti.width);
        EXPECT_EQ_INT(sizes[i][3], ti.height);
        EXPECT_TRUE(ti.fit_max_error_m >= 0 && ti.fit_max_error_m <= 1e-9);
        for (y = 0; y < ti.height; ++y)
            for (x = 0; x < ti.width; ++x)
                if (tp_terrain_sample(t, x, y) != 77.0) {
                    ADD_FAILURE("%dx%d resampled to %dx%d: sample (%d,%d) = %g, expected 77", w, h,
                                ti.width, ti.height, x, y, tp_terrain_sample(t, x, y));
                    y = ti.height;
                    break;
                }
        tp_terrain_destroy(t);
        free(src);
    }
}

TEST(resample_of_rough_terrain_reports_fit_error)
{
    int w = 40, h = 23;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_terrain_info ti;
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 261, 100.0, 50.0, 20.0, 0);
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_RESAMPLE, NULL);
    ti = info_of(t);
    EXPECT_EQ_INT(33, ti.width);
    EXPECT_EQ_INT(17, ti.height);
    EXPECT_GT(ti.fit_max_error_m, 0.0); /* 20 m of noise cannot survive resampling exactly */
    EXPECT_TRUE(isfinite(ti.fit_max_error_m));
    EXPECT_LE(ti.fit_rms_error_m, ti.fit_max_error_m);
    EXPECT_GE(ti.fit_rms_error_m, 0.0);
    tp_terrain_destroy(t);
    free(src);
}

TEST(resample_of_fitting_size_changes_nothing)
{
    int w = 33, h = 17, x, y;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_terrain_info ti;
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 271, 100.0, 50.0, 20.0, 1);
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_RESAMPLE, NULL);
    ti = info_of(t);
    EXPECT_EQ_INT(33, ti.width);
    EXPECT_EQ_INT(17, ti.height);
    EXPECT_NEAR(0.0, ti.fit_max_error_m, 1e-9);
    for (y = 0; y < h; ++y)
        for (x = 0; x < w; ++x)
            EXPECT_EQ_DBL(src[y * w + x], tp_terrain_sample(t, x, y));
    tp_terrain_destroy(t);
    free(src);
}

TEST(grid_world_conversion_follows_geotransform)
{
    static float h[17 * 17];
    double gt[6] = {587049.617, 30.0, 0.0, 5037312.407, 0.0, -30.0};
    tp_terrain* t;
    double e, n, x, y;
    t = tpt_terrain_create(h, 17, 17, 17, TP_FIT_PAD, gt);
    tp_terrain_grid_to_world(t, 0, 0, &e, &n);
    EXPECT_NEAR(587049.617 + 15.0, e, 1e-6);
    EXPECT_NEAR(5037312.407 - 15.0, n, 1e-6);
    tp_terrain_grid_to_world(t, 3.25, 7.5, &e, &n);
    EXPECT_NEAR(587049.617 + 3.75 * 30.0, e, 1e-6);
    EXPECT_NEAR(5037312.407 - 8.0 * 30.0, n, 1e-6);
    tp_terrain_world_to_grid(t, e, n, &x, &y);
    EXPECT_NEAR(3.25, x, 1e-9);
    EXPECT_NEAR(7.5, y, 1e-9);
    tp_terrain_destroy(t);
    /* all-zero geotransform: 1 m north-up, (0, 1, 0, 0, 0, -1) */
    t = tpt_terrain_create(h, 17, 17, 17, TP_FIT_PAD, NULL);
    tp_terrain_grid_to_world(t, 4, 6, &e, &n);
    EXPECT_NEAR(4.5, e, 1e-12);
    EXPECT_NEAR(-6.5, n, 1e-12);
    tp_terrain_destroy(t);
}

TEST(normal_of_a_plane_in_world_frame)
{
    /* z = 2 x + 3 y on a 10 m grid, north-up: dz/dE = 0.2, dz/dN = -0.3 */
    static float h[33 * 33];
    double gt[6] = {1000.0, 10.0, 0.0, 2000.0, 0.0, -10.0};
    static const int at[][2] = {{5, 7}, {0, 0}, {32, 32}, {0, 20}, {16, 16}, {32, 3}};
    double want[3] = {-0.2, 0.3, 1.0}, l;
    tp_terrain* t;
    int x, y;
    size_t i;
    for (y = 0; y < 33; ++y)
        for (x = 0; x < 33; ++x)
            h[y * 33 + x] = (float)(2 * x + 3 * y);
    l = sqrt(want[0] * want[0] + want[1] * want[1] + 1.0);
    t = tpt_terrain_create(h, 33, 33, 17, TP_FIT_PAD, gt);
    for (i = 0; i < sizeof at / sizeof at[0]; ++i) {
        float nrm[3];
        tp_terrain_normal(t, at[i][0], at[i][1], nrm);
        EXPECT_NEAR(want[0] / l, nrm[0], 1e-5);
        EXPECT_NEAR(want[1] / l, nrm[1], 1e-5);
        EXPECT_NEAR(want[2] / l, nrm[2], 1e-5);
    }
    tp_terrain_destroy(t);
}

TEST(nan_and_infinite_heights_become_nodata)
{
    static float h[33 * 33];
    tp_terrain* t;
    tp_terrain_info ti;
    tp_patch_info pi;
    int i;
    for (i = 0; i < 33 * 33; ++i)
        h[i] = (float)(100 + i % 5);
    h[3] = NAN;
    h[40] = INFINITY;
    h[41] = -INFINITY;
    h[500] = 9999.0f; /* a valid maximum */
    t = tpt_terrain_create(h, 33, 33, 17, TP_FIT_PAD, NULL);
    ti = info_of(t);
    EXPECT_EQ_INT(3, ti.nodata_samples);
    EXPECT_EQ_INT(33 * 33 - 3, ti.valid_samples);
    EXPECT_EQ_INT(TP_SAMPLE_NODATA, tp_terrain_sample_class(t, 3, 0));
    EXPECT_EQ_INT(TP_SAMPLE_NODATA, tp_terrain_sample_class(t, 40 % 33, 40 / 33));
    EXPECT_EQ_INT(TP_SAMPLE_NODATA, tp_terrain_sample_class(t, 41 % 33, 41 / 33));
    EXPECT_NAN(tp_terrain_sample(t, 40 % 33, 40 / 33));
    EXPECT_EQ_DBL(100.0, ti.min_height_m);
    EXPECT_EQ_DBL(9999.0, ti.max_height_m);
    tp_patch_get_info(t, 0, &pi);
    EXPECT_EQ_INT(0, pi.complete);
    tp_patch_get_info(t, 3, &pi);
    EXPECT_EQ_INT(1, pi.complete);
    tp_terrain_destroy(t);
}

TEST(filled_flags_mark_filled_samples_which_are_drawn)
{
    static float h[17 * 17];
    static uint8_t filled[17 * 17];
    tp_terrain_desc d;
    tp_terrain* t = NULL;
    tp_terrain_info ti;
    tp_patch_info pi;
    int i;
    for (i = 0; i < 17 * 17; ++i)
        h[i] = (float)(i % 9);
    filled[5] = 1;
    filled[100] = 7;
    d = desc_of(h, 17, 17, 17);
    d.filled = filled;
    d.filled_count = 17 * 17;
    ASSERT_OK(tp_terrain_create(&d, &t, NULL));
    ti = info_of(t);
    EXPECT_EQ_INT(2, ti.filled_samples);
    EXPECT_EQ_INT(17 * 17 - 2, ti.valid_samples);
    EXPECT_EQ_INT(TP_SAMPLE_FILLED, tp_terrain_sample_class(t, 5, 0));
    EXPECT_EQ_INT(TP_SAMPLE_FILLED, tp_terrain_sample_class(t, 100 % 17, 100 / 17));
    EXPECT_EQ_DBL(5.0, tp_terrain_sample(t, 5, 0));
    tp_patch_get_info(t, 0, &pi);
    EXPECT_EQ_INT(1, pi.complete);
    tp_terrain_destroy(t);
}

TEST(sample_counts_and_height_range_match_brute_force)
{
    int w = 70, h = 45, x, y;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_terrain_info ti;
    size_t cnt[5] = {0, 0, 0, 0, 0};
    double lo = INFINITY, hi = -INFINITY;
    tp_rng rng = tp_rng_seed(281);
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 282, 900.0, 300.0, 10.0, 0);
    for (x = 0; x < 200; ++x)
        src[tp_rng_int(&rng, 0, w * h - 1)] = NAN;
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL);
    ti = info_of(t);
    for (y = 0; y < ti.height; ++y)
        for (x = 0; x < ti.width; ++x) {
            tp_sample_class c = tp_terrain_sample_class(t, x, y);
            ASSERT_TRUE(c <= TP_SAMPLE_PADDING);
            cnt[c]++;
            if (c <= TP_SAMPLE_FILLED) {
                double v = tp_terrain_sample(t, x, y);
                if (v < lo)
                    lo = v;
                if (v > hi)
                    hi = v;
            }
        }
    EXPECT_EQ_INT(cnt[TP_SAMPLE_VALID], ti.valid_samples);
    EXPECT_EQ_INT(cnt[TP_SAMPLE_FILLED], ti.filled_samples);
    EXPECT_EQ_INT(cnt[TP_SAMPLE_NODATA], ti.nodata_samples);
    EXPECT_EQ_INT(cnt[TP_SAMPLE_PADDING], ti.padding_samples);
    EXPECT_EQ_INT((size_t)ti.width * ti.height,
                  ti.valid_samples + ti.filled_samples + ti.nodata_samples + ti.padding_samples);
    EXPECT_EQ_DBL(lo, ti.min_height_m);
    EXPECT_EQ_DBL(hi, ti.max_height_m);
    tp_terrain_destroy(t);
    free(src);
}

TEST(patch_info_matches_its_samples)
{
    int w = 70, h = 45, p;
    float* src = (float*)malloc(sizeof(float) * w * h);
    double gt[6] = {500000.0, 25.0, 0.0, 4100000.0, 0.0, -25.0};
    tp_terrain* t;
    tp_terrain_info ti;
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 291, 900.0, 300.0, 10.0, 0);
    src[30 * w + 30] = NAN;
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, gt);
    ti = info_of(t);
    for (p = 0; p < ti.patch_count; ++p) {
        tp_patch_info pi;
        int x, y, all_drawn = 1;
        double lo = INFINITY, hi = -INFINITY, e0, n0, e1, n1;
        tp_patch_get_info(t, p, &pi);
        EXPECT_EQ_INT(p % ti.patch_cols, pi.col);
        EXPECT_EQ_INT(p / ti.patch_cols, pi.row);
        EXPECT_EQ_INT(pi.col * 16, pi.x0);
        EXPECT_EQ_INT(pi.row * 16, pi.y0);
        for (y = pi.y0; y <= pi.y0 + 16; ++y)
            for (x = pi.x0; x <= pi.x0 + 16; ++x) {
                double v = tp_terrain_sample(t, x, y);
                if (isnan(v)) {
                    all_drawn = 0;
                    continue;
                }
                if (v < lo)
                    lo = v;
                if (v > hi)
                    hi = v;
            }
        EXPECT_EQ_INT(all_drawn, pi.complete);
        if (lo <= hi) {
            EXPECT_LE(pi.aabb_min[2], lo);
            EXPECT_GE(pi.aabb_max[2], hi);
            EXPECT_LE(hi - lo, pi.aabb_max[2] - pi.aabb_min[2]);
            EXPECT_LE(pi.aabb_max[2] - pi.aabb_min[2], hi - lo + 2 * ti.height_step_m + 1e-9);
        }
        tp_terrain_grid_to_world(t, pi.x0, pi.y0, &e0, &n0);
        tp_terrain_grid_to_world(t, pi.x0 + 16, pi.y0 + 16, &e1, &n1);
        EXPECT_LE(pi.aabb_min[0], fmin(e0, e1) + 1e-6);
        EXPECT_GE(pi.aabb_max[0], fmax(e0, e1) - 1e-6);
        EXPECT_LE(pi.aabb_min[1], fmin(n0, n1) + 1e-6);
        EXPECT_GE(pi.aabb_max[1], fmax(n0, n1) - 1e-6);
        EXPECT_LE(pi.aabb_max[0] - pi.aabb_min[0], 17 * 25.0 + 1e-6); /* at most pixel edges */
        EXPECT_LE(pi.aabb_max[1] - pi.aabb_min[1], 17 * 25.0 + 1e-6);
    }
    tp_terrain_destroy(t);
    free(src);
}

TEST(all_nan_input_fails_with_bad_data)
{
    static float h[20 * 20];
    tp_terrain_desc d;
    int i;
    for (i = 0; i < 20 * 20; ++i)
        h[i] = i % 2 ? NAN : INFINITY;
    d = desc_of(h, 20, 20, 17);
    expect_create_fails(&d, TP_ERR_BAD_DATA, "all nodata");
}

TEST(invalid_patch_sizes_rejected)
{
    static float h[40 * 40];
    static const int bad[] = {16, 18, 1, 2, 3, 5, 9, 32, 34, 256, 258, 513, -17};
    tp_terrain_desc d;
    tp_terrain* t = NULL;
    size_t i;
    for (i = 0; i < 40 * 40; ++i)
        h[i] = (float)(i % 10);
    for (i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        char what[32];
        d = desc_of(h, 40, 40, bad[i]);
        snprintf(what, sizeof what, "patch_size %d", bad[i]);
        expect_create_fails(&d, TP_ERR_INVALID_ARG, what);
    }
    d = desc_of(h, 40, 40, 0); /* default */
    ASSERT_OK(tp_terrain_create(&d, &t, NULL));
    EXPECT_EQ_INT(TP_DEFAULT_PATCH_SIZE, info_of(t).patch_size);
    tp_terrain_destroy(t);
    for (i = 17; i <= 257; i = 2 * i - 1) {
        t = NULL;
        d = desc_of(h, 40, 40, (int)i);
        ASSERT_OK(tp_terrain_create(&d, &t, NULL));
        EXPECT_EQ_INT(i, info_of(t).patch_size);
        tp_terrain_destroy(t);
    }
}

TEST(bad_grid_sizes_and_rotation_rejected)
{
    static float h[16];
    tp_terrain_desc d;
    d = desc_of(h, 0, 5, 17);
    expect_create_fails(&d, TP_ERR_INVALID_ARG, "width 0");
    d = desc_of(h, 4, 0, 17);
    expect_create_fails(&d, TP_ERR_INVALID_ARG, "height 0");
    d = desc_of(h, 4, 4, 17);
    d.width = -4;
    d.height = -4; /* height_count 16 = (-4)(-4): still not a grid */
    expect_create_fails(&d, TP_ERR_INVALID_ARG, "negative sizes");
    d = desc_of(h, 4, 4, 17);
    d.geotransform[1] = 30.0;
    d.geotransform[5] = -30.0;
    d.geotransform[2] = 0.5;
    expect_create_fails(&d, TP_ERR_INVALID_ARG, "rotated geotransform (gt[2])");
    d.geotransform[2] = 0.0;
    d.geotransform[4] = -0.25;
    expect_create_fails(&d, TP_ERR_INVALID_ARG, "rotated geotransform (gt[4])");
}

TEST(destroy_accepts_null)
{
    tp_terrain_destroy(NULL);
    tp_selection_destroy(NULL);
}

TEST(bytes_per_source_sample_at_most_2_5_on_real_dems)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    static const struct {
        const char *env, *file;
    } dems[] = {{"TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif"},
                {"TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif"},
                {"TP_SHARED_DATA_DIR", "N42E001.hgt"}};
    size_t i;
    int found = 0;
    for (i = 0; i < sizeof dems / sizeof dems[0]; ++i) {
        char path[1024];
        tp_dem* dem = NULL;
        tp_terrain* t = NULL;
        tp_terrain_desc d;
        tp_terrain_info ti;
        tp_error err;
        if (!tp_test_data_path(path, sizeof path, dems[i].env, dems[i].file)) {
            tp_test_note("%s: not found, not measured", path);
            continue;
        }
        ASSERT_OK(tp_dem_read(path, &dem, &err));
        d = tp_dem_terrain_desc(dem, 0, TP_FIT_DEFAULT);
        ASSERT_OK(tp_terrain_create(&d, &t, &err));
        ti = info_of(t);
        tp_test_note("%s: %dx%d, patch %d: %.3f bytes per source sample (%zu resident: heights "
                     "%zu, mask %zu, patch table %zu)",
                     dems[i].file, ti.src_width, ti.src_height, ti.patch_size,
                     ti.bytes_per_source_sample, ti.resident_bytes, ti.heights_bytes, ti.mask_bytes,
                     ti.patch_table_bytes);
        EXPECT_NEAR((double)ti.resident_bytes / ((double)ti.src_width * ti.src_height),
                    ti.bytes_per_source_sample, 1e-9);
        EXPECT_LE(ti.bytes_per_source_sample, 2.5);
        EXPECT_GE_INT(ti.resident_bytes, ti.heights_bytes);
        EXPECT_EQ_DBL(1.0, ti.height_step_m); /* Int16 sources */
        EXPECT_EQ_DBL(0.0, ti.quant_max_error_m);
        EXPECT_EQ_INT(dem->void_count, ti.nodata_samples);
        found++;
        tp_terrain_destroy(t);
        tp_dem_destroy(dem);
    }
    if (!found)
        SKIP("no DEM found");
#endif
}

#define TESTS(X)                                                                                   \
    X(status_str_names_every_status)                                                               \
    X(error_set_keeps_the_reason_of_a_long_message)                                                \
    X(plane_has_zero_delta_at_every_level)                                                         \
    X(spike_between_coarse_vertices_gives_full_height_delta)                                       \
    X(spike_on_a_level_2_vertex_gives_hat_function_deltas)                                         \
    X(spike_on_shared_border_counts_in_both_patches)                                               \
    X(delta_matches_brute_force_synthetic)                                                         \
    X(delta_matches_brute_force_real_dem)                                                          \
    X(shared_border_samples_decode_identically)                                                    \
    X(quantised_heights_within_half_step_of_source)                                                \
    X(integer_source_gets_unit_step_and_exact_heights)                                             \
    X(float_source_gets_finest_power_of_two_step)                                                  \
    X(explicit_step_is_used_or_rejected_when_too_fine)                                             \
    X(height_at_matches_documented_split)                                                          \
    X(height_at_on_edge_of_drawn_area_is_drawn)                                                    \
    X(height_at_on_a_lone_drawn_triangle)                                                          \
    X(nan_outside_grid_and_over_nodata)                                                            \
    X(grid_height_at_equals_terrain_height_at_on_random_points)                                    \
    X(grid_height_at_splits_along_the_documented_diagonal)                                         \
    X(flat_ground_is_flat)                                                                         \
    X(small_and_thin_grids_are_padded_and_padding_never_drawn)                                     \
    X(pad_keeps_geotransform)                                                                      \
    X(resample_fits_nearest_multiple_and_keeps_a_plane)                                            \
    X(resample_of_tiny_and_thin_grids)                                                             \
    X(resample_of_rough_terrain_reports_fit_error)                                                 \
    X(resample_of_fitting_size_changes_nothing)                                                    \
    X(grid_world_conversion_follows_geotransform)                                                  \
    X(normal_of_a_plane_in_world_frame)                                                            \
    X(nan_and_infinite_heights_become_nodata)                                                      \
    X(filled_flags_mark_filled_samples_which_are_drawn)                                            \
    X(sample_counts_and_height_range_match_brute_force)                                            \
    X(patch_info_matches_its_samples)                                                              \
    X(all_nan_input_fails_with_bad_data)                                                           \
    X(invalid_patch_sizes_rejected)                                                                \
    X(bad_grid_sizes_and_rotation_rejected)                                                        \
    X(destroy_accepts_null)                                                                        \
    X(bytes_per_source_sample_at_most_2_5_on_real_dems)
TP_TEST_MAIN(TESTS)
