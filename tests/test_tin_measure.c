/* test_tin_measure.c - tp_tin_measure (core/src/tin_measure.c), the true-error checker of
 * `bench --static`: hand-made meshes whose errors are worked out here, holes (uncovered
 * samples), voids, either orientation, degenerate triangles, bad arguments, random triangles
 * against a brute-force bounding-box scan, and tp_tin_build's output against tests/tp_test_tin.h's
 * checker. */
#include "tp_test.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#define TESTS(X)                                                                                   \
    X(plane_has_no_error)                                                                          \
    X(spike_under_two_triangles)                                                                   \
    X(saddle_errors_worked_by_hand)                                                                \
    X(hole_leaves_its_sample_uncovered)                                                            \
    X(voids_are_neither_covered_nor_uncovered)                                                     \
    X(orientation_does_not_matter)                                                                 \
    X(degenerate_triangles_cover_nothing)                                                          \
    X(overlapping_triangles_count_the_larger_error)                                                \
    X(bad_arguments_are_refused)                                                                   \
    X(random_triangles_match_a_bounding_box_scan)                                                  \
    X(agrees_with_the_test_checker_on_tp_tin_build)                                                \
    X(agrees_with_the_test_checker_on_mt_hood)

#include "tp_test_tin.h"

/* A w x h grid's full mesh: every sample a vertex (height from z, 0 where void), two triangles
 * per cell. *tris gets 6 (w-1)(h-1) indices. */
static float* full_vertices(const float* z, int w, int h)
{
    float* v = (float*)malloc(sizeof(float) * 3 * (size_t)w * h);
    ASSERT_TRUE(v != NULL);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t s = (size_t)y * w + x;
            v[3 * s] = (float)x;
            v[3 * s + 1] = (float)y;
            v[3 * s + 2] = z[s] == z[s] ? z[s] : 0.0f;
        }
    return v;
}

static size_t full_triangles(int w, int h, uint32_t* tris)
{
    size_t k = 0;
    for (int y = 0; y + 1 < h; y++)
        for (int x = 0; x + 1 < w; x++) {
            uint32_t a = (uint32_t)(y * w + x), b = a + 1, c = a + (uint32_t)w, d = c + 1;
            uint32_t t[6] = {a, c, b, b, c, d};
            memcpy(tris + 6 * k, t, sizeof t);
            k++;
        }
    return 2 * k;
}

static tp_tin_measure_result measure(const float* z, int w, int h, const float* v, size_t nv,
                                     const uint32_t* t, size_t nt)
{
    tp_tin_measure_result r;
    tp_error err;
    memset(&err, 0, sizeof err);
    tp_status s = tp_tin_measure(z, (size_t)w * h, w, h, v, nv, t, nt, &r, &err);
    if (s != TP_OK)
        FAIL("tp_tin_measure %dx%d: %s: %s", w, h, tp_test_status_name_(s), err.message);
    return r;
}

/* The grid's two corner triangles: (0,0) (0,h-1) (w-1,0) and (w-1,0) (0,h-1) (w-1,h-1). */
static const uint32_t two_tris[6] = {0, 2, 1, 1, 2, 3};
static void corner_vertices(const float* z, int w, int h, float v[12])
{
    int xs[4] = {0, w - 1, 0, w - 1}, ys[4] = {0, 0, h - 1, h - 1};
    for (int i = 0; i < 4; i++) {
        v[3 * i] = (float)xs[i];
        v[3 * i + 1] = (float)ys[i];
        v[3 * i + 2] = z[ys[i] * w + xs[i]];
    }
}

TEST(plane_has_no_error)
{
    float z[7 * 5];
    for (int y = 0; y < 5; y++)
        for (int x = 0; x < 7; x++)
            z[y * 7 + x] = 3.0f * x - 2.0f * y + 100.0f;
    float v[12];
    corner_vertices(z, 7, 5, v);
    tp_tin_measure_result r = measure(z, 7, 5, v, 4, two_tris, 2);
    EXPECT_NEAR(0.0, r.max_error_m, 1e-9);
    EXPECT_NEAR(0.0, r.rms_error_m, 1e-9);
    EXPECT_EQ_INT(35, (int)r.covered_samples);
    EXPECT_EQ_INT(0, (int)r.uncovered_samples);
    EXPECT_EQ_INT(0, (int)r.degenerate_triangles);
}

TEST(spike_under_two_triangles)
{
    float z[9] = {0, 0, 0, 0, 7, 0, 0, 0, 0};
    float v[12];
    corner_vertices(z, 3, 3, v);
    tp_tin_measure_result r = measure(z, 3, 3, v, 4, two_tris, 2);
    EXPECT_NEAR(7.0, r.max_error_m, 1e-9);
    EXPECT_EQ_INT(1, r.worst_x);
    EXPECT_EQ_INT(1, r.worst_y);
    EXPECT_NEAR(sqrt(49.0 / 9.0), r.rms_error_m, 1e-6); /* one sample of 9 off by 7 */
    EXPECT_EQ_INT(9, (int)r.covered_samples);
}

/* z = x y on 5 x 5 under the diagonal (0,0)-(4,4): the triangle below it (y <= x) interpolates
 * z = 4 y (through (0,0,0), (4,0,0), (4,4,16)), the one above z = 4 x; so the error is
 * y (4 - x) where y <= x and x (4 - y) where x <= y: 4 at (2,2) at most. */
TEST(saddle_errors_worked_by_hand)
{
    float z[25];
    double sum2 = 0;
    for (int y = 0; y < 5; y++)
        for (int x = 0; x < 5; x++) {
            z[y * 5 + x] = (float)(x * y);
            double e = y <= x ? y * (4.0 - x) : x * (4.0 - y);
            sum2 += e * e;
        }
    float v[12];
    corner_vertices(z, 5, 5, v); /* 0 (0,0), 1 (4,0), 2 (0,4), 3 (4,4) */
    const uint32_t diag[6] = {0, 3, 1, 0, 2, 3};
    tp_tin_measure_result r = measure(z, 5, 5, v, 4, diag, 2);
    EXPECT_NEAR(4.0, r.max_error_m, 1e-9);
    EXPECT_EQ_INT(2, r.worst_x);
    EXPECT_EQ_INT(2, r.worst_y);
    EXPECT_NEAR(sqrt(sum2 / 25.0), r.rms_error_m, 1e-6);
    EXPECT_EQ_INT(25, (int)r.covered_samples);
    /* the other diagonal, (4,0)-(0,4): below-left z = 0 plane through (0,0), (4,0), (0,4) all
     * 0: the error is x y where x + y <= 4 (max 4 at (2,2)); above-right the plane through
     * (4,0,0), (0,4,0), (4,4,16) is z = 4 (x + y - 4): error |x y - 4 (x + y - 4)| =
     * (4 - x)(4 - y), max 4 at (2,2) again, 1 at (3,3) */
    const uint32_t anti[6] = {0, 2, 1, 1, 2, 3};
    r = measure(z, 5, 5, v, 4, anti, 2);
    EXPECT_NEAR(4.0, r.max_error_m, 1e-9);
    double s2 = 0;
    for (int y = 0; y < 5; y++)
        for (int x = 0; x < 5; x++) {
            double e = x + y <= 4 ? x * y : (4.0 - x) * (4.0 - y);
            s2 += e * e;
        }
    EXPECT_NEAR(sqrt(s2 / 25.0), r.rms_error_m, 1e-6);
}

/* The full mesh of 5 x 5 without the six triangles around (2, 2): that sample alone is
 * uncovered (its neighbours lie on the hole's edges, covered from outside). */
TEST(hole_leaves_its_sample_uncovered)
{
    float z[25];
    for (int i = 0; i < 25; i++)
        z[i] = (float)(i % 7);
    float* v = full_vertices(z, 5, 5);
    uint32_t t[96], kept[96];
    size_t nt = full_triangles(5, 5, t), nk = 0;
    for (size_t i = 0; i < nt; i++)
        if (t[3 * i] != 12 && t[3 * i + 1] != 12 && t[3 * i + 2] != 12) {
            memcpy(kept + 3 * nk, t + 3 * i, 3 * sizeof *t);
            nk++;
        }
    EXPECT_EQ_INT(32 - 6, (int)nk);
    tp_tin_measure_result r = measure(z, 5, 5, v, 25, kept, nk);
    EXPECT_EQ_INT(1, (int)r.uncovered_samples);
    EXPECT_EQ_INT(24, (int)r.covered_samples);
    EXPECT_NEAR(0.0, r.max_error_m, 1e-9); /* every covered sample is a vertex */
    /* the full mesh covers everything */
    r = measure(z, 5, 5, v, 25, t, nt);
    EXPECT_EQ_INT(0, (int)r.uncovered_samples);
    /* no triangle at all: every valid sample uncovered */
    r = measure(z, 5, 5, v, 25, NULL, 0);
    EXPECT_EQ_INT(25, (int)r.uncovered_samples);
    EXPECT_EQ_INT(-1, r.worst_x);
    free(v);
}

TEST(voids_are_neither_covered_nor_uncovered)
{
    float z[25];
    for (int i = 0; i < 25; i++)
        z[i] = 1.0f;
    z[12] = NAN; /* the hole's sample */
    z[0] = NAN;  /* a covered void: ignored, whatever the interpolation there */
    float* v = full_vertices(z, 5, 5);
    v[2] = 1000.0f; /* vertex (0,0): far off, but only void samples see it at full weight */
    uint32_t t[96], kept[96];
    size_t nt = full_triangles(5, 5, t), nk = 0;
    for (size_t i = 0; i < nt; i++)
        if (t[3 * i] != 12 && t[3 * i + 1] != 12 && t[3 * i + 2] != 12) {
            memcpy(kept + 3 * nk, t + 3 * i, 3 * sizeof *t);
            nk++;
        }
    tp_tin_measure_result r = measure(z, 5, 5, v, 25, kept, nk);
    EXPECT_EQ_INT(0, (int)r.uncovered_samples);
    EXPECT_EQ_INT(23, (int)r.covered_samples);
    EXPECT_NEAR(0.0, r.max_error_m, 1e-9); /* (0,0)'s triangles touch no other sample inside */
    free(v);
}

TEST(orientation_does_not_matter)
{
    float z[25];
    for (int y = 0; y < 5; y++)
        for (int x = 0; x < 5; x++)
            z[y * 5 + x] = (float)(x * y);
    float v[12];
    corner_vertices(z, 5, 5, v);
    const uint32_t ccw[6] = {0, 3, 1, 0, 2, 3}, cw[6] = {0, 1, 3, 0, 3, 2};
    tp_tin_measure_result a = measure(z, 5, 5, v, 4, ccw, 2);
    tp_tin_measure_result b = measure(z, 5, 5, v, 4, cw, 2);
    EXPECT_EQ_DBL(a.max_error_m, b.max_error_m);
    EXPECT_EQ_DBL(a.rms_error_m, b.rms_error_m);
    EXPECT_EQ_INT((int)a.covered_samples, (int)b.covered_samples);
    EXPECT_EQ_INT(25, (int)b.covered_samples);
}

TEST(degenerate_triangles_cover_nothing)
{
    float z[9] = {0, 0, 0, 5, 5, 5, 0, 0, 0};
    /* three collinear vertices along the middle row, and a repeated vertex */
    float v[9] = {0, 1, 0, 1, 1, 0, 2, 1, 0};
    const uint32_t t[6] = {0, 1, 2, 0, 0, 1};
    tp_tin_measure_result r = measure(z, 3, 3, v, 3, t, 2);
    EXPECT_EQ_INT(2, (int)r.degenerate_triangles);
    EXPECT_EQ_INT(0, (int)r.covered_samples);
    EXPECT_EQ_INT(9, (int)r.uncovered_samples);
}

TEST(overlapping_triangles_count_the_larger_error)
{
    /* 3 x 3 of zeros; two copies of the same triangle, one with a raised vertex: the samples
     * they share take the larger error */
    float z[9] = {0};
    float v[12] = {0, 0, 0, 2, 0, 0, 0, 2, 0, 0, 2, 4};
    const uint32_t t[6] = {0, 2, 1, 0, 3, 1}; /* vertex 3 = (0,2) at height 4 */
    tp_tin_measure_result r = measure(z, 3, 3, v, 4, t, 2);
    EXPECT_NEAR(4.0, r.max_error_m, 1e-9); /* at (0,2) itself */
    EXPECT_EQ_INT(0, r.worst_x);
    EXPECT_EQ_INT(2, r.worst_y);
    EXPECT_EQ_INT(6, (int)r.covered_samples); /* x + y <= 2 */
    EXPECT_EQ_INT(3, (int)r.uncovered_samples);
    /* errors per sample: (0,0) 0, (1,0) 0, (2,0) 0, (0,1) 2, (1,1) 2, (0,2) 4 */
    EXPECT_NEAR(sqrt((4.0 + 4.0 + 16.0) / 6.0), r.rms_error_m, 1e-6);
}

TEST(bad_arguments_are_refused)
{
    float z[9] = {0};
    float v[9] = {0, 0, 0, 2, 0, 0, 0, 2, 0};
    const uint32_t t[3] = {0, 2, 1};
    tp_tin_measure_result r;
    tp_error err;
    EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_tin_measure(z, 9, 0, 3, v, 3, t, 1, &r, &err));
    EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_tin_measure(z, 8, 3, 3, v, 3, t, 1, &r, &err));
    const uint32_t bad_index[3] = {0, 3, 1};
    EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_tin_measure(z, 9, 3, 3, v, 3, bad_index, 1, &r, &err));
    EXPECT_CONTAINS(err.message, "vertex 3");
    float off[9] = {0, 0, 0, 3, 0, 0, 0, 2, 0}; /* x = 3 on a 3-wide grid */
    EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_tin_measure(z, 9, 3, 3, off, 3, t, 1, &r, &err));
    float frac[9] = {0, 0, 0, 1.5f, 0, 0, 0, 2, 0};
    EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_tin_measure(z, 9, 3, 3, frac, 3, t, 1, &r, &err));
    float nan_h[9] = {0, 0, NAN, 2, 0, 0, 0, 2, 0};
    EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_tin_measure(z, 9, 3, 3, nan_h, 3, t, 1, &r, &err));
    EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_tin_measure(z, 9, 3, 3, NULL, 3, t, 1, &r, &err));
    EXPECT_EQ_INT(TP_OK, tp_tin_measure(z, 9, 3, 3, v, 3, t, 1, &r, &err));
}

static uint32_t lcg(uint32_t* s)
{
    *s = *s * 1664525u + 1013904223u;
    return *s >> 8;
}

/* Random (often thin) triangles over random heights: the result equals a scan of each
 * triangle's bounding box with the three orientation signs (the per-row spans must be exact). */
TEST(random_triangles_match_a_bounding_box_scan)
{
    enum { W = 37, H = 23, NV = 40, NT = 60 };
    uint32_t seed = 12345;
    for (int round = 0; round < 50; round++) {
        float z[W * H], v[3 * NV];
        for (int i = 0; i < W * H; i++)
            z[i] = (lcg(&seed) % 1000) / 10.0f - 50.0f;
        for (int i = 0; i < NV; i++) {
            v[3 * i] = (float)(lcg(&seed) % W);
            v[3 * i + 1] = (float)(lcg(&seed) % H);
            v[3 * i + 2] = (lcg(&seed) % 1000) / 10.0f - 50.0f;
        }
        uint32_t t[3 * NT];
        for (int i = 0; i < 3 * NT; i++)
            t[i] = lcg(&seed) % NV;
        double worst[W * H];
        for (int i = 0; i < W * H; i++)
            worst[i] = -1;
        size_t degenerate = 0;
        for (int i = 0; i < NT; i++) {
            const float *a = v + 3 * t[3 * i], *b = v + 3 * t[3 * i + 1], *c = v + 3 * t[3 * i + 2];
            int64_t area = orient_xy(a, b, c);
            if (area == 0) {
                degenerate++;
                continue;
            }
            for (int y = 0; y < H; y++)
                for (int x = 0; x < W; x++) {
                    float p[2] = {(float)x, (float)y};
                    int64_t la = orient_xy(p, b, c), lb = orient_xy(a, p, c),
                            lc = orient_xy(a, b, p);
                    int inside = area > 0 ? (la >= 0 && lb >= 0 && lc >= 0)
                                          : (la <= 0 && lb <= 0 && lc <= 0);
                    if (!inside)
                        continue;
                    double zi = (la * (double)a[2] + lb * (double)b[2] + lc * (double)c[2]) /
                                (double)area;
                    double e = fabs(z[y * W + x] - zi);
                    worst[y * W + x] = e > worst[y * W + x] ? e : worst[y * W + x];
                }
        }
        double mx = 0;
        size_t covered = 0;
        for (int i = 0; i < W * H; i++) {
            covered += worst[i] >= 0;
            mx = worst[i] > mx ? worst[i] : mx;
        }
        tp_tin_measure_result r = measure(z, W, H, v, NV, t, NT);
        EXPECT_NEAR(mx, r.max_error_m, 1e-9);
        EXPECT_EQ_INT((int)covered, (int)r.covered_samples);
        EXPECT_EQ_INT(W * H - (int)covered, (int)r.uncovered_samples);
        EXPECT_EQ_INT((int)degenerate, (int)r.degenerate_triangles);
    }
}

static void agree_on(const float* z, int w, int h, double e, unsigned flags)
{
    tp_tin* t = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    if (tp_tin_build(z, (size_t)w * h, w, h, e, flags, &t, &err) != TP_OK)
        FAIL("tp_tin_build: %s", err.message);
    double mx = flags ? check_tin_mode(t, z, w, h, e, 1) : check_tin(t, z, w, h, e);
    tp_tin_measure_result r = measure(z, w, h, t->vertices, t->vertex_count, t->triangles,
                                      t->triangle_count);
    tp_test_note("%dx%d e=%g: %zu triangles, checker %.6f m, tp_tin_measure %.6f m", w, h, e,
                 t->triangle_count, mx, r.max_error_m);
    EXPECT_NEAR(mx, r.max_error_m, 1e-6);
    EXPECT_LE(r.max_error_m, e + TOL_M);
    /* cut: the TIN covers the valid cells (four valid corners) only, so a valid sample that is
     * the corner of no valid cell is uncovered; without the flag, nothing is */
    size_t lone = 0;
    for (int y = 0; flags && y < h; y++)
        for (int x = 0; x < w; x++) {
            int in_cell = 0;
            for (int cy = y - 1; cy <= y; cy++)
                for (int cx = x - 1; cx <= x; cx++)
                    in_cell |= cx >= 0 && cy >= 0 && cx + 1 < w && cy + 1 < h &&
                               tin_cell_valid(z, w, cx, cy);
            lone += z[(size_t)y * w + x] == z[(size_t)y * w + x] && !in_cell;
        }
    tp_test_note("  %zu valid samples in no valid cell", lone);
    EXPECT_EQ_INT((int)lone, (int)r.uncovered_samples);
    EXPECT_EQ_INT(0, (int)r.degenerate_triangles);
    tp_tin_destroy(t);
}

TEST(agrees_with_the_test_checker_on_tp_tin_build)
{
    enum { W = 65, H = 49 };
    static float z[W * H];
    uint32_t seed = 7;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++)
            z[y * W + x] = (float)(20 * sin(x * 0.21) * cos(y * 0.17) + (lcg(&seed) % 100) / 25.0);
    agree_on(z, W, H, 0.5, 0);
    agree_on(z, W, H, 3, 0);
    for (int i = 0; i < 60; i++) /* voids, cut out */
        z[(lcg(&seed) % H) * W + lcg(&seed) % W] = NAN;
    agree_on(z, W, H, 1, TP_TIN_CUT_VOIDS);
}

TEST(agrees_with_the_test_checker_on_mt_hood)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    tp_render_grid* g = tin_test_render_grid("TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    agree_on(g->heights, g->width, g->height, 5, TP_TIN_CUT_VOIDS);
    tp_render_grid_destroy(g);
#endif
}

TP_TEST_MAIN(TESTS)
