/* test_tin.c - the error-bounded TIN (tp_tin_build) checked by tp_test_tin.h's checker, written
 * apart from tin.c. */
#include "tp_io.h"
#include "tp_test.h"

#define TESTS(X)                                                                                   \
    X(single_spike_becomes_a_vertex)                                                               \
    X(cliff_holds_the_bound)                                                                       \
    X(plane_is_two_triangles)                                                                      \
    X(constant_grid_is_two_triangles)                                                              \
    X(two_by_two)                                                                                  \
    X(one_by_n_and_n_by_one_have_no_triangles)                                                     \
    X(one_by_one)                                                                                  \
    X(all_void_is_empty)                                                                           \
    X(voids_are_ignored_and_void_corners_take_the_nearest_height)                                  \
    X(zero_error_on_random_data_inserts_every_sample)                                              \
    X(random_grids_hold_the_bound)                                                                 \
    X(bad_arguments_are_refused)                                                                   \
    X(wide_grid_takes_the_double_incircle_path)                                                    \
    X(mt_hood_holds_the_bound)                                                                     \
    X(n42e001_holds_the_bound)                                                                     \
    X(crater_lake_holds_the_bound)                                                                 \
    X(cut_without_voids_changes_nothing)                                                           \
    X(cut_covers_exactly_the_valid_cells)                                                          \
    X(cut_single_void_in_a_plane)                                                                  \
    X(cut_checkerboard_and_edge_voids)                                                             \
    X(cut_all_void_and_no_valid_cell_are_empty)                                                    \
    X(cut_mt_hood_with_holes_holds_the_bound)

#include "tp_test_tin.h"

static tp_tin* build_flags(const float* z, int w, int h, double e, unsigned flags)
{
    tp_tin* t = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    tp_status s = tp_tin_build(z, (size_t)w * h, w, h, e, flags, &t, &err);
    if (s != TP_OK)
        FAIL("tp_tin_build %dx%d e=%g: %s: %s", w, h, e, tp_test_status_name_(s), err.message);
    return t;
}

static tp_tin* build_ok(const float* z, int w, int h, double e)
{
    return build_flags(z, w, h, e, 0);
}

static tp_tin* build_cut_checked(const float* z, int w, int h, double e)
{
    tp_tin* t = build_flags(z, w, h, e, TP_TIN_CUT_VOIDS);
    check_tin_mode(t, z, w, h, e, 1);
    return t;
}

static tp_tin* build_checked(const float* z, int w, int h, double e)
{
    tp_tin* t = build_ok(z, w, h, e);
    check_tin(t, z, w, h, e);
    return t;
}

static float* grid_new(int w, int h, float v)
{
    float* z = (float*)malloc(sizeof(float) * (size_t)w * h);
    ASSERT_TRUE(z != NULL);
    for (size_t i = 0; i < (size_t)w * h; ++i)
        z[i] = v;
    return z;
}

static int has_vertex(const tp_tin* t, int x, int y)
{
    for (size_t i = 0; i < t->vertex_count; ++i)
        if (t->vertices[3 * i] == (float)x && t->vertices[3 * i + 1] == (float)y)
            return 1;
    return 0;
}

TEST(single_spike_becomes_a_vertex)
{
    const int w = 33, h = 17;
    float* z = grid_new(w, h, 100.0f);
    z[7 * w + 10] = 250.0f;
    tp_tin* t = build_checked(z, w, h, 1.0);
    EXPECT_TRUE(has_vertex(t, 10, 7));
    EXPECT_EQ_DBL(0.0, t->max_error_m);
    EXPECT_LE_INT((int)t->triangle_count, 12); /* the spike and what its base needs */
    tp_tin_destroy(t);
    free(z);
}

TEST(cliff_holds_the_bound)
{
    const int w = 40, h = 23;
    float* z = grid_new(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[y * w + x] = x + y / 3 >= 17 ? 80.0f : 2.0f;
    double es[3] = {0.0, 1.0, 20.0};
    for (int k = 0; k < 3; ++k) {
        tp_tin* t = build_checked(z, w, h, es[k]);
        EXPECT_LE(t->max_error_m, es[k]);
        tp_tin_destroy(t);
    }
    free(z);
}

TEST(plane_is_two_triangles)
{
    const int w = 65, h = 40;
    float* z = grid_new(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[y * w + x] = 7.0f + 3.0f * x - 2.0f * y;
    tp_tin* t = build_checked(z, w, h, 1e-3);
    EXPECT_EQ_INT(2, (int)t->triangle_count);
    EXPECT_EQ_INT(4, (int)t->vertex_count);
    tp_tin_destroy(t);
    free(z);
}

TEST(constant_grid_is_two_triangles)
{
    float* z = grid_new(300, 7, 1234.5f);
    tp_tin* t = build_checked(z, 300, 7, 0.0);
    EXPECT_EQ_INT(2, (int)t->triangle_count);
    EXPECT_EQ_INT(4, (int)t->vertex_count);
    EXPECT_EQ_DBL(0.0, t->max_error_m);
    tp_tin_destroy(t);
    free(z);
}

TEST(two_by_two)
{
    float z[4] = {10.0f, 25.0f, -3.0f, 7.5f};
    tp_tin* t = build_checked(z, 2, 2, 0.0);
    EXPECT_EQ_INT(2, (int)t->triangle_count);
    EXPECT_EQ_INT(4, (int)t->vertex_count);
    tp_tin_destroy(t);
    float v[4] = {10.0f, NAN, -3.0f, 7.5f}; /* a void corner takes the nearest height */
    t = build_checked(v, 2, 2, 0.0);
    EXPECT_EQ_INT(2, (int)t->triangle_count);
    ASSERT_EQ_INT(4, (int)t->vertex_count);
    for (int i = 0; i < 4; ++i)
        if (t->vertices[3 * i] == 1.0f && t->vertices[3 * i + 1] == 0.0f)
            EXPECT_EQ_DBL(10.0, t->vertices[3 * i + 2]); /* (0,0), first in row order */
    tp_tin_destroy(t);
}

TEST(one_by_n_and_n_by_one_have_no_triangles)
{
    float z[9] = {1, 2, NAN, 4, 5, 6, 7, 8, 9};
    tp_tin* t = build_checked(z, 9, 1, 1.0);
    EXPECT_EQ_INT(0, (int)t->triangle_count);
    EXPECT_EQ_INT(8, (int)t->vertex_count); /* every valid sample */
    tp_tin_destroy(t);
    t = build_checked(z, 1, 9, 1.0);
    EXPECT_EQ_INT(0, (int)t->triangle_count);
    EXPECT_EQ_INT(8, (int)t->vertex_count);
    EXPECT_EQ_DBL(1.0, t->vertices[1 * 3 + 1]); /* (0, 1), height 2 */
    EXPECT_EQ_DBL(2.0, t->vertices[1 * 3 + 2]);
    tp_tin_destroy(t);
}

TEST(one_by_one)
{
    float z = 42.0f;
    tp_tin* t = build_checked(&z, 1, 1, 5.0);
    EXPECT_EQ_INT(0, (int)t->triangle_count);
    ASSERT_EQ_INT(1, (int)t->vertex_count);
    EXPECT_EQ_DBL(42.0, t->vertices[2]);
    tp_tin_destroy(t);
    z = NAN;
    t = build_checked(&z, 1, 1, 5.0);
    EXPECT_EQ_INT(0, (int)t->vertex_count);
    tp_tin_destroy(t);
}

TEST(all_void_is_empty)
{
    float* z = grid_new(9, 5, NAN);
    tp_tin* t = build_ok(z, 9, 5, 1.0);
    EXPECT_EQ_INT(0, (int)t->triangle_count);
    EXPECT_EQ_INT(0, (int)t->vertex_count);
    EXPECT_EQ_DBL(0.0, t->max_error_m);
    tp_tin_destroy(t);
    free(z);
}

TEST(voids_are_ignored_and_void_corners_take_the_nearest_height)
{
    const int w = 50, h = 31;
    tp_rng r = tp_rng_seed(14);
    float* z = grid_new(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[y * w + x] = (float)(40.0 * sin(x * 0.2) * cos(y * 0.15) + tp_rng_range(&r, 0, 2));
    for (int y = 10; y < 20; ++y) /* a void block in the middle, spikes inside it ignored */
        for (int x = 15; x < 33; ++x)
            z[y * w + x] = NAN;
    for (int y = 0; y < 4; ++y) /* the top-left corner in a void */
        for (int x = 0; x < 3; ++x)
            z[y * w + x] = NAN;
    z[h * w - 1] = NAN; /* the bottom-right corner alone */
    const float corner_tl = z[0 * w + 3]; /* ring 3 reaches (3,0) first in row order */
    const float corner_br = z[(h - 2) * w + (w - 2)];
    double es[3] = {0.0, 0.5, 5.0};
    for (int k = 0; k < 3; ++k) {
        tp_tin* t = build_checked(z, w, h, es[k]);
        for (size_t i = 0; i < t->vertex_count; ++i) {
            const float* v = t->vertices + 3 * i;
            if (v[0] == 0 && v[1] == 0)
                EXPECT_EQ_DBL(corner_tl, v[2]);
            if (v[0] == w - 1 && v[1] == h - 1)
                EXPECT_EQ_DBL(corner_br, v[2]);
            /* no vertex inside the void block but the outline's */
            if (v[0] >= 15 && v[0] < 33 && v[1] >= 10 && v[1] < 20)
                FAIL("vertex (%g,%g) in the void", v[0], v[1]);
        }
        tp_tin_destroy(t);
    }
    free(z);
}

TEST(zero_error_on_random_data_inserts_every_sample)
{
    const int sizes[3][2] = {{20, 13}, {3, 2}, {17, 33}};
    tp_rng r = tp_rng_seed(7);
    for (int k = 0; k < 3; ++k) {
        const int w = sizes[k][0], h = sizes[k][1];
        float* z = grid_new(w, h, 0.0f);
        for (int i = 0; i < w * h; ++i)
            z[i] = (float)tp_rng_range(&r, 0.0, 1000.0);
        tp_tin* t = build_checked(z, w, h, 0.0);
        EXPECT_LE_INT((int)t->triangle_count, 2 * (w - 1) * (h - 1));
        EXPECT_EQ_INT(w * h, (int)t->vertex_count);
        EXPECT_LE(t->max_error_m, 0.0);
        tp_tin_destroy(t);
        free(z);
    }
}

TEST(random_grids_hold_the_bound)
{
    tp_rng r = tp_rng_seed(1995);
    for (int k = 0; k < 20; ++k) {
        const int w = tp_rng_int(&r, 2, 70), h = tp_rng_int(&r, 2, 70);
        float* z = grid_new(w, h, 0.0f);
        const double f = tp_rng_range(&r, 0.02, 0.5), a = tp_rng_range(&r, 1, 300);
        for (int y = 0; y < h; ++y)
            for (int x = 0; x < w; ++x)
                z[y * w + x] = (float)(a * sin(f * x + 0.3 * y) * cos(f * y) +
                                       tp_rng_range(&r, 0, a / 20) +
                                       (tp_rng_int(&r, 0, 50) == 0 ? NAN : 0.0f));
        double e = tp_rng_range(&r, 0.0, a / 10);
        tp_tin* t = build_checked(z, w, h, e);
        tp_tin_destroy(t);
        free(z);
    }
}

TEST(wide_grid_takes_the_double_incircle_path)
{
    /* wider than 2^14: the in-circle test runs in doubles, flips guarded by convexity */
    const int w = 17001, h = 4;
    tp_rng r = tp_rng_seed(16384);
    float* z = grid_new(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[y * w + x] = (float)(300.0 * sin(x * 0.003) + 20.0 * sin(x * 0.05 + y) +
                                   tp_rng_range(&r, 0, 1));
    tp_tin* t = build_checked(z, w, h, 3.0);
    EXPECT_TRUE(t->triangle_count > 100);
    tp_tin_destroy(t);
    free(z);
}

TEST(bad_arguments_are_refused)
{
    float z[4] = {1, 2, 3, 4};
    tp_tin* t = (tp_tin*)(uintptr_t)1; /* untouched on failure */
    tp_error err;
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tin_build(z, 4, 2, 2, -1.0, 0, &t, &err));
    EXPECT_CONTAINS(err.message, "max error");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tin_build(z, 4, 2, 2, NAN, 0, &t, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tin_build(z, 4, 2, 2, INFINITY, 0, &t, NULL));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tin_build(z, 0, 0, 2, 1.0, 0, &t, &err));
    EXPECT_TRUE(t == (tp_tin*)(uintptr_t)1);
    tp_tin_destroy(NULL);
}

/* ---------------------------------------------------------------------------------------------
 * Real DEMs on their render grids (as every command reads them), e = 1, 5, 20 m
 */
#ifdef TP_TEST_NO_IO
static void real_dem(const char* file) { SKIP("built without tp_io: %s", file); }
#else
static void real_dem(const char* file)
{
    tp_render_grid* g = tin_test_render_grid("TP_SHARED_DATA_DIR", file);
    const int w = g->width, h = g->height;
    size_t prev = (size_t)-1;
    const double es[3] = {1.0, 5.0, 20.0};
    for (int k = 0; k < 3; ++k) {
        tp_tin* t = build_ok(g->heights, w, h, es[k]);
        double mx = check_tin(t, g->heights, w, h, es[k]);
        printf("%s %dx%d e=%g: %zu triangles, %zu vertices, max error %.4f m\n", file, w, h,
               es[k], t->triangle_count, t->vertex_count, mx);
        /* a real relief needs refinement, and a looser bound fewer triangles */
        EXPECT_TRUE(t->triangle_count > 100);
        EXPECT_TRUE(t->triangle_count < prev);
        EXPECT_TRUE(t->triangle_count < 2 * (size_t)(w - 1) * (h - 1));
        prev = t->triangle_count;
        tp_tin_destroy(t);
        /* cut at the voids (the warp's margins, SRTM's holes): the full mesh's cells exactly
         * (at the loosest bound only: the checker's cost is in the big triangles) */
        if (k < 2)
            continue;
        t = build_cut_checked(g->heights, w, h, es[k]);
        printf("  cut at voids: %zu triangles, %zu vertices\n", t->triangle_count,
               t->vertex_count);
        tp_tin_destroy(t);
    }
    tp_render_grid_destroy(g);
}
#endif

TEST(mt_hood_holds_the_bound) { real_dem("lf_elev_220_mt_hood_utm.tif"); }
TEST(n42e001_holds_the_bound) { real_dem("N42E001.hgt"); }
TEST(crater_lake_holds_the_bound) { real_dem("craterlake-elev-16bit-30m.tif"); }

/* ---------------------------------------------------------------------------------------------
 * TP_TIN_CUT_VOIDS: the TIN covers exactly the cells the full-resolution mesh draws
 */
static int same_tin(const tp_tin* a, const tp_tin* b)
{
    return a->vertex_count == b->vertex_count && a->triangle_count == b->triangle_count &&
           !memcmp(a->vertices, b->vertices, a->vertex_count * 3 * sizeof(float)) &&
           !memcmp(a->triangles, b->triangles, a->triangle_count * 3 * sizeof(uint32_t));
}

static float* random_relief(int w, int h, unsigned seed)
{
    float* z = grid_new(w, h, 0.0f);
    srand(seed);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[(size_t)y * w + x] = 50.0f * sinf(x * 0.21f) * cosf(y * 0.17f) +
                                   (float)(rand() % 1000) / 100.0f;
    return z;
}

TEST(cut_without_voids_changes_nothing)
{
    const int w = 61, h = 45;
    float* z = random_relief(w, h, 3);
    tp_tin* a = build_ok(z, w, h, 2.0);
    tp_tin* b = build_cut_checked(z, w, h, 2.0);
    EXPECT_TRUE(same_tin(a, b));
    tp_tin_destroy(a);
    tp_tin_destroy(b);
    free(z);
}

TEST(cut_covers_exactly_the_valid_cells)
{
    /* random voids from single samples to blobs, sizes that are not 2^n + 1 */
    const int sizes[][2] = {{37, 29}, {64, 64}, {101, 57}};
    const int percent[] = {1, 10, 40};
    const double es[] = {0.0, 1.0, 5.0};
    for (int si = 0; si < 3; ++si)
        for (int pi = 0; pi < 3; ++pi) {
            int w = sizes[si][0], h = sizes[si][1];
            float* z = random_relief(w, h, (unsigned)(si * 7 + pi));
            for (int k = 0; k < w * h * percent[pi] / 100; ++k) {
                int cx = rand() % w, cy = rand() % h, r = rand() % 3;
                for (int y = cy - r; y <= cy + r; ++y)
                    for (int x = cx - r; x <= cx + r; ++x)
                        if (x >= 0 && y >= 0 && x < w && y < h && rand() % 4)
                            z[(size_t)y * w + x] = NAN;
            }
            for (int ei = 0; ei < 3; ++ei)
                tp_tin_destroy(build_cut_checked(z, w, h, es[ei]));
            free(z);
        }
}

TEST(cut_single_void_in_a_plane)
{
    /* a plane with one void: the four cells around it are gone, the ring of cells around them is
     * kept at full resolution, the rest of the plane stays coarse */
    const int w = 41, h = 33;
    float* z = grid_new(w, h, 0.0f);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[(size_t)y * w + x] = 3.0f * x - 2.0f * y + 100.0f;
    z[(size_t)16 * w + 20] = NAN;
    tp_tin* t = build_cut_checked(z, w, h, 0.5);
    /* 4 x 4 cells around the void minus its 4 = 12 cells at full resolution (24 triangles), the
     * rest of the rectangle in a handful */
    EXPECT_TRUE(t->triangle_count >= 24 && t->triangle_count <= 24 + 24);
    EXPECT_TRUE(!has_vertex(t, 20, 16));
    EXPECT_TRUE(has_vertex(t, 18, 14) && has_vertex(t, 22, 18));
    tp_tin_destroy(t);
    free(z);
}

TEST(cut_checkerboard_and_edge_voids)
{
    /* every other sample void (no valid cell at all), then voids on the outline and corners */
    const int w = 23, h = 19;
    float* z = random_relief(w, h, 11);
    float* c = grid_new(w, h, 0.0f);
    memcpy(c, z, sizeof(float) * w * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            if ((x + y) % 2)
                c[(size_t)y * w + x] = NAN;
    tp_tin* t = build_cut_checked(c, w, h, 1.0);
    EXPECT_EQ_INT(0, (int)t->triangle_count);
    tp_tin_destroy(t);
    z[0] = z[w - 1] = z[(size_t)(h - 1) * w] = z[(size_t)h * w - 1] = NAN; /* the 4 corners */
    for (int x = 5; x < 12; ++x)
        z[x] = NAN; /* a bite out of the top edge */
    for (int y = 3; y < h; ++y)
        z[(size_t)y * w + (w - 1)] = NAN; /* most of the right edge */
    for (int e = 0; e <= 8; e += 4)
        tp_tin_destroy(build_cut_checked(z, w, h, e));
    free(z);
    free(c);
}

TEST(cut_all_void_and_no_valid_cell_are_empty)
{
    const int w = 9, h = 7;
    float* z = grid_new(w, h, NAN);
    tp_tin* t = build_cut_checked(z, w, h, 1.0);
    EXPECT_EQ_INT(0, (int)t->triangle_count);
    EXPECT_EQ_INT(0, (int)t->vertex_count);
    tp_tin_destroy(t);
    z[3 * w + 4] = 5.0f; /* one valid sample, no valid cell */
    t = build_cut_checked(z, w, h, 1.0);
    EXPECT_EQ_INT(0, (int)t->triangle_count);
    tp_tin_destroy(t);
    free(z);
}

#ifdef TP_TEST_NO_IO
static void mt_hood_with_holes(void) { SKIP("built without tp_io"); }
#else
static void mt_hood_with_holes(void)
{
    tp_render_grid* g = tin_test_render_grid("TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    const int w = g->width, h = g->height;
    /* a lake-sized hole, a line of single-sample voids, a hole on the edge */
    for (int y = 100; y < 160; ++y)
        for (int x = 200; x < 290; ++x)
            if ((x - 245) * (x - 245) + 2 * (y - 130) * (y - 130) < 900)
                g->heights[(size_t)y * w + x] = NAN;
    for (int x = 20; x < w - 20; x += 9)
        g->heights[(size_t)(h / 2) * w + x] = NAN;
    for (int y = 0; y < 40; ++y)
        for (int x = 0; x < 30 - y / 2; ++x)
            g->heights[(size_t)y * w + x] = NAN;
    const double es[2] = {1.0, 20.0};
    for (int k = 0; k < 2; ++k) {
        tp_tin* t = build_cut_checked(g->heights, w, h, es[k]);
        printf("mt hood with holes e=%g: %zu triangles, %zu vertices\n", es[k], t->triangle_count,
               t->vertex_count);
        tp_tin_destroy(t);
    }
    tp_render_grid_destroy(g);
}
#endif

TEST(cut_mt_hood_with_holes_holds_the_bound) { mt_hood_with_holes(); }

TP_TEST_MAIN(TESTS)
