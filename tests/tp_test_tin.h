/* tp_test_tin.h - an independent checker of error-bounded TINs (tp_tin_build), written here and
 * not taken from tin.c: every triangle rasterised over its bounding box with barycentric weights
 * from exact integer areas; every sample must be covered, and every valid sample's error
 * |height - interpolation| must be <= the bound. The triangulation is checked to tile the grid's
 * rectangle: positive area seen from above (north-up), each directed edge once, every edge
 * without a twin on the outline, areas summing to the rectangle's, no duplicated vertex. With
 * cut (TP_TIN_CUT_VOIDS) it must instead tile exactly the valid cells: their area, every valid
 * cell's centre and corners covered, no void sample and no invalid cell's centre covered. */
#ifndef TP_TEST_TIN_H
#define TP_TEST_TIN_H

#include "tp_core.h"
#include "tp_test.h"

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
static int tin_cell_valid(const float* z, int w, int cx, int cy)
{
    const float* r = z + (size_t)cy * w + cx;
    return r[0] == r[0] && r[1] == r[1] && r[w] == r[w] && r[w + 1] == r[w + 1];
}

/* Checks the triangulation and the bound; returns the measured max error. cut: the TIN of
 * TP_TIN_CUT_VOIDS, which must cover exactly the valid cells (four valid corners) instead of
 * the rectangle. */
static double check_tin_mode(const tp_tin* t, const float* z, int w, int h, double bound_m, int cut)
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
    int64_t cells = (int64_t)(w - 1) * (h - 1);
    if (cut) {
        cells = 0;
        for (int cy = 0; cy + 1 < h; ++cy)
            for (int cx = 0; cx + 1 < w; ++cx)
                cells += tin_cell_valid(z, w, cx, cy);
    }
    EXPECT_EQ_INT(2 * cells, area2);
    qsort(edges, 3 * m, sizeof *edges, cmp_u64);
    int64_t outline_len = 0;
    for (size_t i = 0; i < 3 * m; ++i) {
        if (i > 0 && edges[i] == edges[i - 1])
            FAIL("directed edge %llx twice", (unsigned long long)edges[i]);
        uint32_t u = (uint32_t)(edges[i] >> 32), v = (uint32_t)edges[i];
        uint64_t rev = ((uint64_t)v << 32) | u;
        if (!bsearch(&rev, edges, 3 * m, sizeof *edges, cmp_u64)) {
            const float *a = t->vertices + 3 * u, *b = t->vertices + 3 * v;
            if (cut)
                continue; /* the outline of the valid cells: checked by the cell centres */
            if (!on_outline(a, b, w, h))
                FAIL("edge (%g,%g)-(%g,%g) has one triangle but is not on the outline", a[0],
                     a[1], b[0], b[1]);
            outline_len += (int64_t)(fabsf(a[0] - b[0]) + fabsf(a[1] - b[1]));
        }
    }
    if (!cut)
        EXPECT_EQ_INT(2 * (int64_t)(w - 1) + 2 * (int64_t)(h - 1), outline_len);
    free(edges);

    /* the bound, sample by sample, by barycentric weights */
    double* worst = (double*)malloc(sizeof(double) * n);
    ASSERT_TRUE(worst != NULL);
    for (size_t i = 0; i < n; ++i)
        worst[i] = -1.0;
    /* cut: cell centres covered (closed test on doubled coordinates), each cell's count */
    uint8_t* centre = cut ? (uint8_t*)calloc(n, 1) : NULL;
    ASSERT_TRUE(!cut || centre != NULL);
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
                if (cut && z[s] != z[s])
                    FAIL("a triangle of the cut TIN covers the void sample (%d, %d)", x, y);
                double e = z[s] == z[s] ? fabs(z[s] - zi) : 0.0;
                worst[s] = e > worst[s] ? e : worst[s];
                tri_worst = e > tri_worst ? e : tri_worst;
            }
        for (int y = y0; cut && y < y1; ++y)
            for (int x = x0; x < x1; ++x) {
                float q[2] = {(float)(2 * x + 1), (float)(2 * y + 1)};
                float a2[2] = {2 * a[0], 2 * a[1]}, b2[2] = {2 * b[0], 2 * b[1]},
                      c2[2] = {2 * c[0], 2 * c[1]};
                if (orient_xy(q, b2, c2) > 0 || orient_xy(a2, q, c2) > 0 ||
                    orient_xy(a2, b2, q) > 0)
                    continue;
                if (!tin_cell_valid(z, w, x, y))
                    FAIL("a triangle of the cut TIN covers the centre of cell (%d, %d), which "
                         "has a void corner", x, y);
                centre[(size_t)y * w + x] = 1;
            }
        /* the error the TIN reports for the triangle is what it covers */
        EXPECT_NEAR(tri_worst, t->triangle_error_m[i], 1e-4);
    }
    double mx = 0.0;
    size_t uncovered = 0, over = 0;
    if (cut) /* every valid cell's centre, and every corner of one, is covered */
        for (int cy = 0; cy + 1 < h; ++cy)
            for (int cx = 0; cx + 1 < w; ++cx) {
                size_t s = (size_t)cy * w + cx;
                if (!tin_cell_valid(z, w, cx, cy))
                    continue;
                uncovered += !centre[s];
                uncovered += (worst[s] < 0) + (worst[s + 1] < 0) + (worst[s + w] < 0) +
                             (worst[s + w + 1] < 0);
            }
    free(centre);
    for (size_t s = 0; s < n; ++s) {
        if (!cut && worst[s] < 0)
            uncovered++; /* cut: a valid sample of no valid cell is not covered */
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


static inline double check_tin(const tp_tin* t, const float* z, int w, int h, double bound_m)
{
    return check_tin_mode(t, z, w, h, bound_m, 0);
}

#ifndef TP_TEST_NO_IO
#include "tp_io.h"

/* The render grid of DEM file (found through env_var, else skipped), as every command reads it;
 * free with tp_render_grid_destroy. */
static tp_render_grid* tin_test_render_grid(const char* env_var, const char* file)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_render_grid* g = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    REQUIRE_DATA_FILE(path, env_var, file);
    if (tp_dem_read(path, &dem, &err) != TP_OK)
        FAIL("tp_dem_read(%s): %s", path, err.message);
    tp_status s = tp_render_grid_build(dem, NULL, &g, &err);
    tp_dem_destroy(dem);
    if (s != TP_OK)
        FAIL("tp_render_grid_build(%s): %s", path, err.message);
    return g;
}
#endif

#endif
