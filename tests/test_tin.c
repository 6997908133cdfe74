/* test_tin.c - the error-bounded TIN (tp_tin_build) checked by a checker written here, not
 * taken from tin.c: every triangle rasterised over its bounding box with barycentric weights
 * from exact integer areas; every sample must be covered, and every valid sample's error
 * |height - interpolation| must be <= the bound. The triangulation is checked to tile the grid's
 * rectangle: positive area seen from above (north-up), each directed edge once, every edge
 * without a twin on the outline, areas summing to the rectangle's, no duplicated vertex. */
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
    X(crater_lake_holds_the_bound)

/* Float rounding of the interpolation (doubles of float heights up to a few km) */
#define TOL_M 1e-6

static int64_t orient_xy(const float* a, const float* b, const float* c)
{
    int64_t ax = (int64_t)a[0], ay = (int64_t)a[1], bx = (int64_t)b[0], by = (int64_t)b[1];
    int64_t cx = (int64_t)c[0], cy = (int64_t)c[1];
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

static int cmp_u64(const void* a, const void* b)
{
    uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
    return (x > y) - (x < y);
}

static int on_outline(const float* a, const float* b, int w, int h)
{
    float X = (float)(w - 1), Y = (float)(h - 1);
    return (a[0] == 0 && b[0] == 0) || (a[0] == X && b[0] == X) || (a[1] == 0 && b[1] == 0) ||
           (a[1] == Y && b[1] == Y);
}

/* Checks the triangulation and the bound; returns the measured max error. */
static double check_tin(const tp_tin* t, const float* z, int w, int h, double bound_m)
{
    const size_t n = (size_t)w * h;
    /* vertices: integer grid positions inside the grid, distinct; height = the sample's where
     * the sample is valid */
    uint8_t* seen = (uint8_t*)calloc(n, 1);
    ASSERT_TRUE(seen != NULL);
    for (size_t i = 0; i < t->vertex_count; ++i) {
        const float* v = t->vertices + 3 * i;
        ASSERT_TRUE(v[0] == floorf(v[0]) && v[1] == floorf(v[1]));
        ASSERT_TRUE(v[0] >= 0 && v[0] < w && v[1] >= 0 && v[1] < h);
        size_t s = (size_t)v[1] * w + (size_t)v[0];
        ASSERT_EQ_INT(0, seen[s]);
        seen[s] = 1;
        if (z[s] == z[s])
            ASSERT_TRUE(v[2] == z[s]);
        ASSERT_TRUE(v[2] == v[2]);
    }
    free(seen);
    if (w < 2 || h < 2) {
        EXPECT_EQ_INT(0, (int)t->triangle_count);
        return 0.0;
    }
    /* triangles: positive area on the map (negative in (column, row)), directed edges once,
     * twins or the outline, areas summing to the rectangle */
    const size_t m = t->triangle_count;
    uint64_t* edges = (uint64_t*)malloc(sizeof(uint64_t) * (3 * m + 1));
    ASSERT_TRUE(edges != NULL);
    int64_t area2 = 0;
    for (size_t i = 0; i < m; ++i) {
        const uint32_t* tr = t->triangles + 3 * i;
        for (int k = 0; k < 3; ++k)
            ASSERT_TRUE(tr[k] < t->vertex_count);
        const float *a = t->vertices + 3 * tr[0], *b = t->vertices + 3 * tr[1],
                    *c = t->vertices + 3 * tr[2];
        int64_t o = orient_xy(a, b, c);
        if (o >= 0)
            FAIL("triangle %zu is not counter-clockwise on the map (orient %lld)", i, (long long)o);
        area2 += -o;
        for (int k = 0; k < 3; ++k)
            edges[3 * i + k] = ((uint64_t)tr[k] << 32) | tr[(k + 1) % 3];
    }
    EXPECT_EQ_INT(2 * (int64_t)(w - 1) * (h - 1), area2);
    qsort(edges, 3 * m, sizeof *edges, cmp_u64);
    int64_t outline_len = 0;
    for (size_t i = 0; i < 3 * m; ++i) {
        if (i > 0 && edges[i] == edges[i - 1])
            FAIL("directed edge %llx twice", (unsigned long long)edges[i]);
        uint32_t u = (uint32_t)(edges[i] >> 32), v = (uint32_t)edges[i];
        uint64_t rev = ((uint64_t)v << 32) | u;
        if (!bsearch(&rev, edges, 3 * m, sizeof *edges, cmp_u64)) {
            const float *a = t->vertices + 3 * u, *b = t->vertices + 3 * v;
            if (!on_outline(a, b, w, h))
                FAIL("edge (%g,%g)-(%g,%g) has one triangle but is not on the outline", a[0],
                     a[1], b[0], b[1]);
            outline_len += (int64_t)(fabsf(a[0] - b[0]) + fabsf(a[1] - b[1]));
        }
    }
    EXPECT_EQ_INT(2 * (int64_t)(w - 1) + 2 * (int64_t)(h - 1), outline_len);
    free(edges);

    /* the bound, sample by sample, by barycentric weights */
    double* worst = (double*)malloc(sizeof(double) * n);
    ASSERT_TRUE(worst != NULL);
    for (size_t i = 0; i < n; ++i)
        worst[i] = -1.0;
    for (size_t i = 0; i < m; ++i) {
        const uint32_t* tr = t->triangles + 3 * i;
        const float *a = t->vertices + 3 * tr[0], *b = t->vertices + 3 * tr[1],
                    *c = t->vertices + 3 * tr[2];
        const double area = (double)orient_xy(a, b, c);
        int x0 = (int)fminf(a[0], fminf(b[0], c[0])), x1 = (int)fmaxf(a[0], fmaxf(b[0], c[0]));
        int y0 = (int)fminf(a[1], fminf(b[1], c[1])), y1 = (int)fmaxf(a[1], fmaxf(b[1], c[1]));
        double tri_worst = 0.0;
        for (int y = y0; y <= y1; ++y)
            for (int x = x0; x <= x1; ++x) {
                float p[2] = {(float)x, (float)y};
                int64_t la = orient_xy(p, b, c), lb = orient_xy(a, p, c), lc = orient_xy(a, b, p);
                if (la > 0 || lb > 0 || lc > 0)
                    continue; /* outside (inside has all <= 0, as the area) */
                double zi = (la * (double)a[2] + lb * (double)b[2] + lc * (double)c[2]) / area;
                size_t s = (size_t)y * w + x;
                double e = z[s] == z[s] ? fabs(z[s] - zi) : 0.0;
                worst[s] = e > worst[s] ? e : worst[s];
                tri_worst = e > tri_worst ? e : tri_worst;
            }
        /* the error the TIN reports for the triangle is what it covers */
        EXPECT_NEAR(tri_worst, t->triangle_error_m[i], 1e-4);
    }
    double mx = 0.0;
    size_t uncovered = 0, over = 0;
    for (size_t s = 0; s < n; ++s) {
        if (worst[s] < 0)
            uncovered++;
        else if (worst[s] > bound_m + TOL_M)
            over++;
        mx = worst[s] > mx ? worst[s] : mx;
    }
    free(worst);
    EXPECT_EQ_INT(0, (int)uncovered);
    if (over)
        FAIL("%zu samples above the bound %g m (max %g m)", over, bound_m, mx);
    EXPECT_NEAR(mx, t->max_error_m, 1e-4);
    return mx;
}

static tp_tin* build_ok(const float* z, int w, int h, double e)
{
    tp_tin* t = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    tp_status s = tp_tin_build(z, (size_t)w * h, w, h, e, &t, &err);
    if (s != TP_OK)
        FAIL("tp_tin_build %dx%d e=%g: %s: %s", w, h, e, tp_test_status_name_(s), err.message);
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
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tin_build(z, 4, 2, 2, -1.0, &t, &err));
    EXPECT_CONTAINS(err.message, "max error");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tin_build(z, 4, 2, 2, NAN, &t, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tin_build(z, 4, 2, 2, INFINITY, &t, NULL));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tin_build(z, 0, 0, 2, 1.0, &t, &err));
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
    }
    tp_render_grid_destroy(g);
}
#endif

TEST(mt_hood_holds_the_bound) { real_dem("lf_elev_220_mt_hood_utm.tif"); }
TEST(n42e001_holds_the_bound) { real_dem("N42E001.hgt"); }
TEST(crater_lake_holds_the_bound) { real_dem("craterlake-elev-16bit-30m.tif"); }

TP_TEST_MAIN(TESTS)
