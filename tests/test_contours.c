/*
 * test_contours.c - contour lines (io/src/contours.cpp, app/commands/cmd_contours.c):
 *   - tp_contours_generate on real ground (N42E001) against GDALContourGenerate run here
 *     directly on the file's own band (its Int16 samples, its own nodata), line by line, and
 *     every vertex checked independently: it lies on a grid edge where the linear interpolation
 *     of the two posts gives the line's level;
 *   - voids: no line enters a void punched into real ground (and without the void, lines do);
 *   - flat, 1x1 and 2x2 grids; bad arguments with *out untouched;
 *   - tp_contours_write: GeoPackage read back with OGR (layer, fields, every vertex, CRS), the
 *     other formats by extension, a Shapefile's sidecars, unknown extensions and unwritable
 *     places (nothing written, older files intact, no temporary left);
 *   - `terrapatch contours` on mt_hood against GDALContourGenerate on the render grid built here
 *     (tp_render_grid_build), and its bad input.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"
#include "tp_io.h"
#include "tp_vector.h"

#include "tp_test_child.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <gdal_alg.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TP_TMP_PREFIX "tp_contours_"
#include "tp_test_tmp.h"

static const char* g_dir;

static const char* tmp_dir(void) /* one per test process, removed at exit */
{
    if (!g_dir)
        g_dir = make_tmp_dir();
    return g_dir;
}

/* Entries of dir whose name contains ".tmp" (temporaries of the writers). */
static int temporaries_in(const char* dir)
{
    int n = 0;
    DIR* d = opendir(dir);
    ASSERT_TRUE(d != NULL);
    struct dirent* e;
    while ((e = readdir(d)))
        n += strstr(e->d_name, ".tmp") != NULL;
    closedir(d);
    return n;
}

/* ---- grids ---- */

typedef struct grid {
    float* z;
    int w, h;
    double gt[6];
} grid;

/* A window of N42E001.hgt (the whole tile for w = 0), voids NaN. */
static grid n42_window(int x0, int y0, int w, int h)
{
    char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    grid g;
    if (w == 0) {
        w = GDALGetRasterXSize(ds);
        h = GDALGetRasterYSize(ds);
    }
    g.w = w, g.h = h;
    g.z = malloc((size_t)w * h * sizeof *g.z);
    ASSERT_TRUE(g.z != NULL);
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    ASSERT_TRUE(GDALRasterIO(b, GF_Read, x0, y0, w, h, g.z, w, h, GDT_Float32, 0, 0) == CE_None);
    int has_nd = 0;
    const double nd = GDALGetRasterNoDataValue(b, &has_nd);
    for (size_t i = 0; i < (size_t)w * h; ++i)
        if (has_nd && g.z[i] == (float)nd)
            g.z[i] = NAN;
    double gt[6];
    GDALGetGeoTransform(ds, gt);
    g.gt[0] = gt[0] + x0 * gt[1], g.gt[1] = gt[1], g.gt[2] = 0.0;
    g.gt[3] = gt[3] + y0 * gt[5], g.gt[4] = 0.0, g.gt[5] = gt[5];
    GDALClose(ds);
    return g;
}

/* ---- GDAL's own contours, run here ---- */

typedef struct ref_line {
    double value;
    int n;
    double* xy;
} ref_line;

typedef struct ref_set {
    ref_line* lines;
    int count;
} ref_set;

static void ref_free(ref_set* r)
{
    for (int i = 0; i < r->count; ++i)
        free(r->lines[i].xy);
    free(r->lines);
}

/* GDALContourGenerate (the classic API, as gdal_contour -i) over band into a Memory layer. */
static ref_set gdal_contours(GDALRasterBandH band, double interval, double base, int use_nd,
                             double nd)
{
    GDALDatasetH mem = GDALCreate(GDALGetDriverByName("Memory"), "", 0, 0, 0, GDT_Unknown, NULL);
    ASSERT_TRUE(mem != NULL);
    OGRLayerH l = GDALDatasetCreateLayer(mem, "ref", NULL, wkbLineString, NULL);
    OGRFieldDefnH id = OGR_Fld_Create("id", OFTInteger), el = OGR_Fld_Create("elev", OFTReal);
    OGR_L_CreateField(l, id, 1);
    OGR_L_CreateField(l, el, 1);
    OGR_Fld_Destroy(id);
    OGR_Fld_Destroy(el);
    ASSERT_TRUE(GDALContourGenerate(band, interval, base, 0, NULL, use_nd, nd, l, 0, 1, NULL,
                                    NULL) == CE_None);
    ref_set r = {NULL, 0};
    r.lines = calloc((size_t)OGR_L_GetFeatureCount(l, 1) + 1, sizeof *r.lines);
    OGR_L_ResetReading(l);
    OGRFeatureH f;
    while ((f = OGR_L_GetNextFeature(l))) {
        OGRGeometryH g = OGR_F_GetGeometryRef(f);
        ref_line* rl = &r.lines[r.count++];
        rl->value = OGR_F_GetFieldAsDouble(f, 1);
        rl->n = OGR_G_GetPointCount(g);
        rl->xy = malloc(2 * sizeof(double) * (size_t)(rl->n + 1));
        for (int k = 0; k < rl->n; ++k) {
            rl->xy[2 * k] = OGR_G_GetX(g, k);
            rl->xy[2 * k + 1] = OGR_G_GetY(g, k);
        }
        OGR_F_Destroy(f);
    }
    GDALClose(mem);
    return r;
}

/* GDAL's contours of a float grid (NaN void -> nodata -99999) in a MEM dataset made here. */
static ref_set gdal_contours_grid(const grid* g, double interval, double base)
{
    GDALDatasetH ds =
        GDALCreate(GDALGetDriverByName("MEM"), "", g->w, g->h, 1, GDT_Float32, NULL);
    ASSERT_TRUE(ds != NULL);
    GDALSetGeoTransform(ds, (double*)g->gt);
    float* z = malloc((size_t)g->w * g->h * sizeof *z);
    for (size_t i = 0; i < (size_t)g->w * g->h; ++i)
        z[i] = isnan(g->z[i]) ? -99999.0f : g->z[i];
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    ASSERT_TRUE(GDALRasterIO(b, GF_Write, 0, 0, g->w, g->h, z, g->w, g->h, GDT_Float32, 0, 0) ==
                CE_None);
    free(z);
    ref_set r = gdal_contours(b, interval, base, 1, -99999.0);
    GDALClose(ds);
    return r;
}

/* Ours equal GDAL's line for line: the level, the vertices (a ring is GDAL's closed line
 * without its repeated last vertex), within tol (map units). */
static void expect_same_lines(const tp_features* f, const ref_set* r, double tol)
{
    ASSERT_EQ_INT((long long)r->count, (long long)f->count);
    size_t bad = 0;
    for (int i = 0; i < r->count; ++i) {
        const tp_feature* it = &f->items[i];
        const ref_line* rl = &r->lines[i];
        EXPECT_EQ_DBL(rl->value, it->value);
        const int ring = it->kind == TP_FEATURE_RING;
        EXPECT_EQ_INT(rl->n, (long long)it->count + ring);
        if (rl->n != (int)it->count + ring)
            continue;
        for (size_t k = 0; k < (size_t)rl->n; ++k) {
            const size_t v = it->first + (k == it->count ? 0 : k);
            bad += fabs(f->xy[2 * v] - rl->xy[2 * k]) > tol ||
                   fabs(f->xy[2 * v + 1] - rl->xy[2 * k + 1]) > tol;
        }
        if (ring) /* GDAL's line closes exactly on itself */
            EXPECT_TRUE(rl->xy[0] == rl->xy[2 * rl->n - 2] && rl->xy[1] == rl->xy[2 * rl->n - 1]);
    }
    EXPECT_EQ_INT(0, (long long)bad);
}

/* Total length (map units) of the lines at level value. */
static double length_at(const tp_features* f, double value)
{
    double sum = 0.0;
    for (size_t i = 0; i < f->count; ++i) {
        const tp_feature* it = &f->items[i];
        if (it->value != value)
            continue;
        const size_t n = it->count + (it->kind == TP_FEATURE_RING);
        for (size_t k = 1; k < n; ++k) {
            const size_t a = it->first + k - 1, b = it->first + (k == it->count ? 0 : k);
            sum += hypot(f->xy[2 * b] - f->xy[2 * a], f->xy[2 * b + 1] - f->xy[2 * a + 1]);
        }
    }
    return sum;
}

static double ref_length_at(const ref_set* r, double value)
{
    double sum = 0.0;
    for (int i = 0; i < r->count; ++i)
        if (r->lines[i].value == value)
            for (int k = 1; k < r->lines[i].n; ++k)
                sum += hypot(r->lines[i].xy[2 * k] - r->lines[i].xy[2 * k - 2],
                             r->lines[i].xy[2 * k + 1] - r->lines[i].xy[2 * k - 1]);
    return sum;
}

/* ---- tp_contours_generate ---- */

TEST(n42e001_matches_gdal_contour_generate)
{
    grid g = n42_window(0, 0, 0, 0);
    tp_features* f = NULL;
    tp_error err = {{0}};
    ASSERT_STATUS(TP_OK, tp_contours_generate(g.z, (size_t)g.w * g.h, g.w, g.h, g.gt, 20.0, 0.0,
                                              5, &f, &err));
    ASSERT_GT((double)f->count, 1000.0);

    /* GDAL on the file's own Int16 band and nodata, not on our copy */
    char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    int has_nd = 0;
    const double nd = GDALGetRasterNoDataValue(b, &has_nd);
    ref_set r = gdal_contours(b, 20.0, 0.0, has_nd, nd);
    GDALClose(ds);
    /* Same generator, same numbers (Int16 and Float32 hold the same integers): the vertices are
     * the same doubles; 1e-9 degree (0.1 mm) only allows for nothing at all going wrong. */
    expect_same_lines(f, &r, 1e-9);
    for (double level = 360.0; level <= 3080.0; level += 20.0) {
        const double a = length_at(f, level), bref = ref_length_at(&r, level);
        EXPECT_NEAR(bref, a, 1e-9 * (1.0 + bref));
    }

    /* Independently of GDAL: each vertex lies on an edge between two posts, where their linear
     * interpolation is the level (within 0.01 m: GDAL nudges a post exactly on a level by a
     * small fraction of the interval; ours are integer heights), or on the grid's border. */
    size_t on_edge = 0, off = 0, wrong = 0, rings = 0, index = 0;
    for (size_t i = 0; i < f->count; ++i) {
        const tp_feature* it = &f->items[i];
        rings += it->kind == TP_FEATURE_RING;
        const int want_index = fmod(it->value, 100.0) == 0.0;
        index += it->index;
        EXPECT_EQ_INT(want_index, it->index);
        for (size_t k = 0; k < it->count; ++k) {
            const double px = (f->xy[2 * (it->first + k)] - g.gt[0]) / g.gt[1] - 0.5;
            const double py = (f->xy[2 * (it->first + k) + 1] - g.gt[3]) / g.gt[5] - 0.5;
            const double rx = round(px), ry = round(py);
            double z;
            if (fabs(px - rx) < 1e-6 && py >= 0 && py <= g.h - 1 && rx >= 0 && rx <= g.w - 1) {
                const int y0 = (int)floor(py), y1 = y0 + 1 < g.h ? y0 + 1 : y0;
                const double t = py - y0;
                z = g.z[(size_t)y0 * g.w + (int)rx] * (1 - t) + g.z[(size_t)y1 * g.w + (int)rx] * t;
            } else if (fabs(py - ry) < 1e-6 && px >= 0 && px <= g.w - 1 && ry >= 0 &&
                       ry <= g.h - 1) {
                const int x0 = (int)floor(px), x1 = x0 + 1 < g.w ? x0 + 1 : x0;
                const double t = px - x0;
                z = g.z[(size_t)ry * g.w + x0] * (1 - t) + g.z[(size_t)ry * g.w + x1] * t;
            } else {
                ++off;
                continue;
            }
            if (isnan(z)) {
                ++off;
                continue;
            }
            ++on_edge;
            wrong += fabs(z - it->value) > 0.01;
        }
    }
    printf("N42E001 at 20 m: %zu lines (%zu closed, %zu index), %zu vertices on edges, %zu on "
           "the border or beside a void, %zu off their level\n",
           f->count, rings, index, on_edge, off, wrong);
    EXPECT_EQ_INT(0, (long long)wrong);
    /* the rest: GDAL carries lines on to the grid's outer edge (half a post beyond the border
     * posts) and to the middle between a post and a void one (1.03% of them here) */
    EXPECT_GT((double)on_edge, 0.98 * (double)(on_edge + off));
    EXPECT_GT((double)rings, 0.0);
    EXPECT_GT((double)index, 0.0);
    ref_free(&r);
    tp_features_destroy(f);
    free(g.z);
}

/* Void posts x in [vx0, vx1], y in [vy0, vy1] of a 200x200 window of real ground. */
TEST(no_contour_crosses_a_void)
{
    grid g = n42_window(500, 500, 200, 200);
    const int vx0 = 80, vx1 = 119, vy0 = 60, vy1 = 99;
    tp_error err = {{0}};
    tp_features* whole = NULL;
    ASSERT_OK(tp_contours_generate(g.z, 40000, 200, 200, g.gt, 10.0, 0.0, 5, &whole, &err));
    /* strictly inside the void, more than half a post from its edge posts */
    size_t inside_before = 0;
#define INSIDE(fs, v)                                                                              \
    (((fs)->xy[2 * (v)] - g.gt[0]) / g.gt[1] - 0.5 > vx0 - 0.5 + 1e-6 &&                         \
     ((fs)->xy[2 * (v)] - g.gt[0]) / g.gt[1] - 0.5 < vx1 + 0.5 - 1e-6 &&                         \
     ((fs)->xy[2 * (v) + 1] - g.gt[3]) / g.gt[5] - 0.5 > vy0 - 0.5 + 1e-6 &&                     \
     ((fs)->xy[2 * (v) + 1] - g.gt[3]) / g.gt[5] - 0.5 < vy1 + 0.5 - 1e-6)
    for (size_t v = 0; v < whole->vertex_count; ++v)
        inside_before += INSIDE(whole, v);
    ASSERT_GT((double)inside_before, 100.0); /* lines cross the place before it is a void */

    for (int y = vy0; y <= vy1; ++y)
        for (int x = vx0; x <= vx1; ++x)
            g.z[(size_t)y * 200 + x] = NAN;
    tp_features* f = NULL;
    ASSERT_OK(tp_contours_generate(g.z, 40000, 200, 200, g.gt, 10.0, 0.0, 5, &f, &err));
    size_t inside = 0, ends_at_void = 0;
    for (size_t v = 0; v < f->vertex_count; ++v)
        inside += INSIDE(f, v);
    /* segment midpoints too: a segment joins two vertices of one cell */
    for (size_t i = 0; i < f->count; ++i) {
        const tp_feature* it = &f->items[i];
        for (size_t k = 1; k < it->count; ++k) {
            const size_t a = it->first + k - 1, b = it->first + k;
            const double mx = 0.5 * (f->xy[2 * a] + f->xy[2 * b]);
            const double my = 0.5 * (f->xy[2 * a + 1] + f->xy[2 * b + 1]);
            const double px = (mx - g.gt[0]) / g.gt[1] - 0.5, py = (my - g.gt[3]) / g.gt[5] - 0.5;
            inside += px > vx0 - 0.5 + 1e-6 && px < vx1 + 0.5 - 1e-6 && py > vy0 - 0.5 + 1e-6 &&
                      py < vy1 + 0.5 - 1e-6;
        }
        if (it->kind != TP_FEATURE_LINE)
            continue;
        for (int end = 0; end < 2; ++end) {
            const size_t v = it->first + (end ? it->count - 1 : 0);
            const double px = (f->xy[2 * v] - g.gt[0]) / g.gt[1] - 0.5;
            const double py = (f->xy[2 * v + 1] - g.gt[3]) / g.gt[5] - 0.5;
            ends_at_void += px >= vx0 - 1.01 && px <= vx1 + 1.01 && py >= vy0 - 1.01 &&
                            py <= vy1 + 1.01;
        }
    }
    printf("void 40x40: %zu vertices inside before, %zu after; %zu line ends at its edge\n",
           inside_before, inside, ends_at_void);
    EXPECT_EQ_INT(0, (long long)inside);
    EXPECT_GT((double)ends_at_void, 10.0);
    /* and GDAL given the same void as its own nodata agrees line for line */
    ref_set r = gdal_contours_grid(&g, 10.0, 0.0);
    expect_same_lines(f, &r, 1e-9);
    ref_free(&r);
#undef INSIDE
    tp_features_destroy(whole);
    tp_features_destroy(f);
    free(g.z);
}

TEST(flat_grid_gives_no_lines)
{
    float z[40 * 30];
    for (int i = 0; i < 40 * 30; ++i)
        z[i] = 105.0f;
    const double gt[6] = {500000, 30, 0, 4700000, 0, -30};
    tp_features* f = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_contours_generate(z, 1200, 40, 30, gt, 20.0, 0.0, 5, &f, &err));
    EXPECT_EQ_INT(0, (long long)f->count);
    EXPECT_EQ_INT(0, (long long)f->vertex_count);
    tp_features_destroy(f);
    /* all void */
    for (int i = 0; i < 40 * 30; ++i)
        z[i] = NAN;
    f = NULL;
    ASSERT_OK(tp_contours_generate(z, 1200, 40, 30, gt, 20.0, 0.0, 5, &f, &err));
    EXPECT_EQ_INT(0, (long long)f->count);
    tp_features_destroy(f);
}

TEST(one_by_one_and_two_by_two_grids)
{
    const double gt[6] = {500000, 30, 0, 4700000, 0, -30};
    tp_features* f = NULL;
    tp_error err = {{0}};
    const float one = 150.0f;
    ASSERT_OK(tp_contours_generate(&one, 1, 1, 1, gt, 20.0, 0.0, 5, &f, &err));
    EXPECT_EQ_INT(0, (long long)f->count);
    tp_features_destroy(f);

    /* a 2x2 slope 0, 10 / 20, 30: levels 5 .. 25 each cross the one cell */
    grid g = {(float[]){0, 10, 20, 30}, 2, 2, {500000, 30, 0, 4700000, 0, -30}};
    f = NULL;
    ASSERT_OK(tp_contours_generate(g.z, 4, 2, 2, g.gt, 5.0, 0.0, 2, &f, &err));
    ref_set r = gdal_contours_grid(&g, 5.0, 0.0);
    expect_same_lines(f, &r, 1e-6);
    ASSERT_GE((double)f->count, 5.0);
    for (size_t i = 0; i < f->count; ++i) {
        const double v = f->items[i].value;
        /* 0 and 30 too: GDAL draws a level that a corner post lies exactly on */
        EXPECT_TRUE(v >= 0 && v <= 30 && fmod(v, 5.0) == 0.0);
        EXPECT_EQ_INT(fmod(v, 10.0) == 0.0, f->items[i].index);
        EXPECT_EQ_INT(TP_FEATURE_LINE, f->items[i].kind);
        /* within the cell between the posts' centres... or GDAL's border half a post out */
        for (size_t k = 0; k < f->items[i].count; ++k) {
            const double e = f->xy[2 * (f->items[i].first + k)];
            const double n = f->xy[2 * (f->items[i].first + k) + 1];
            EXPECT_TRUE(e >= 500000 - 1e-6 && e <= 500060 + 1e-6);
            EXPECT_TRUE(n <= 4700000 + 1e-6 && n >= 4699940 - 1e-6);
        }
    }
    printf("2x2: %zu lines, 15 m line %.3f m long\n", f->count, length_at(f, 15.0));
    ref_free(&r);
    tp_features_destroy(f);
}

TEST(bad_arguments_leave_out_untouched)
{
    float z[4] = {0, 10, 20, 30};
    const double gt[6] = {500000, 30, 0, 4700000, 0, -30};
    tp_features* const sentinel = (tp_features*)&z[0];
    tp_features* f = sentinel;
    tp_error err = {{0}};
    ASSERT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, 4, 2, 2, gt, 0.0, 0.0, 5, &f, &err));
    EXPECT_CONTAINS(err.message, "interval > 0");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, 4, 2, 2, gt, -5.0, 0.0, 5, &f, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, 4, 2, 2, gt, NAN, 0.0, 5, &f, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, 4, 2, 2, gt, 5.0, NAN, 5, &f, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, 4, 2, 2, gt, 5.0, 0.0, -1, &f, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, 3, 2, 2, gt, 5.0, 0.0, 5, &f, &err));
    EXPECT_CONTAINS(err.message, "2x2 and 3 heights");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, 0, 0, 0, gt, 5.0, 0.0, 5, &f, &err));
    const double flat_gt[6] = {500000, 0, 0, 4700000, 0, -30};
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, 4, 2, 2, flat_gt, 5.0, 0.0, 5, &f, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, 4, 2, 2, gt, 1e-5, 0.0, 5, &f, &err));
    EXPECT_CONTAINS(err.message, "levels");
    z[2] = INFINITY;
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_contours_generate(z, 4, 2, 2, gt, 5.0, 0.0, 5, &f, &err));
    EXPECT_CONTAINS(err.message, "infinite");
    EXPECT_TRUE(f == sentinel);
}

/* ---- tp_contours_write ---- */

static char* wkt_of_epsg(int epsg)
{
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    ASSERT_TRUE(OSRImportFromEPSG(srs, epsg) == OGRERR_NONE);
    char* wkt = NULL;
    OSRExportToWkt(srs, &wkt);
    OSRDestroySpatialReference(srs);
    return wkt;
}

/* Reads path back with OGR: the layer's features against f (count; with check_all, every
 * level, index and vertex). Returns the layer's feature count. */
static long long read_back(const char* path, const tp_features* f, int check_all,
                           const char* layer_name)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_VECTOR, NULL, NULL, NULL);
    if (!ds)
        FAIL("OGR cannot open %s", path);
    OGRLayerH l = layer_name ? GDALDatasetGetLayerByName(ds, layer_name)
                             : GDALDatasetGetLayer(ds, 0);
    ASSERT_TRUE(l != NULL);
    OGRFeatureDefnH d = OGR_L_GetLayerDefn(l);
    /* a Shapefile keeps 10 characters; KML (GDAL's KML driver) makes the first two
     * fields each placemark's name and description */
    int ie = OGR_FD_GetFieldIndex(d, "elevation_m"), ii = OGR_FD_GetFieldIndex(d, "index");
    if (ie < 0)
        ie = OGR_FD_GetFieldIndex(d, "elevation_");
    if (ie < 0 && ii < 0 && strstr(path, ".kml"))
        ie = OGR_FD_GetFieldIndex(d, "Name"), ii = OGR_FD_GetFieldIndex(d, "description");
    if (ie < 0 || ii < 0)
        FAIL("%s: no elevation_m or index field", path);
    const long long n = OGR_L_GetFeatureCount(l, 1);
    if (check_all) {
        ASSERT_EQ_INT(OFTReal, OGR_Fld_GetType(OGR_FD_GetFieldDefn(d, ie)));
        ASSERT_EQ_INT(OFTInteger, OGR_Fld_GetType(OGR_FD_GetFieldDefn(d, ii)));
        ASSERT_EQ_INT((long long)f->count, n);
        OGR_L_ResetReading(l);
        OGRFeatureH feat;
        size_t i = 0, bad = 0;
        while ((feat = OGR_L_GetNextFeature(l))) {
            const tp_feature* it = &f->items[i++];
            EXPECT_EQ_DBL(it->value, OGR_F_GetFieldAsDouble(feat, ie));
            EXPECT_EQ_INT(it->index, OGR_F_GetFieldAsInteger(feat, ii));
            OGRGeometryH g = OGR_F_GetGeometryRef(feat);
            EXPECT_EQ_INT(wkbLineString, wkbFlatten(OGR_G_GetGeometryType(g)));
            const int ring = it->kind == TP_FEATURE_RING;
            EXPECT_EQ_INT((long long)it->count + ring, OGR_G_GetPointCount(g));
            for (int k = 0; k < OGR_G_GetPointCount(g) && k <= (int)it->count; ++k) {
                const size_t v = it->first + ((size_t)k == it->count ? 0 : (size_t)k);
                bad += OGR_G_GetX(g, k) != f->xy[2 * v] || OGR_G_GetY(g, k) != f->xy[2 * v + 1];
            }
            OGR_F_Destroy(feat);
        }
        EXPECT_EQ_INT(0, (long long)bad);
    }
    GDALClose(ds);
    return n;
}

TEST(gpkg_reads_back_with_elevation_m)
{
    grid g = n42_window(300, 300, 300, 300);
    tp_features* f = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_contours_generate(g.z, 90000, 300, 300, g.gt, 20.0, 0.0, 5, &f, &err));
    ASSERT_GT((double)f->count, 10.0);
    char path[256];
    snprintf(path, sizeof path, "%s/n42.gpkg", tmp_dir());
    char* wkt = wkt_of_epsg(4326);
    ASSERT_OK(tp_contours_write(path, f, wkt, &err));
    read_back(path, f, 1, "contours");
    GDALAllRegister();
    /* the CRS */
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_VECTOR, NULL, NULL, NULL);
    OGRSpatialReferenceH srs = OGR_L_GetSpatialRef(GDALDatasetGetLayerByName(ds, "contours"));
    OGRSpatialReferenceH want = OSRNewSpatialReference(wkt);
    ASSERT_TRUE(srs != NULL);
    const char* same_opts[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES", NULL};
    EXPECT_TRUE(OSRIsSameEx(srs, want, same_opts));
    OSRDestroySpatialReference(want);
    GDALClose(ds);
    EXPECT_EQ_INT(0, temporaries_in(tmp_dir()));
    CPLFree(wkt);
    tp_features_destroy(f);
    free(g.z);
}

TEST(formats_by_extension)
{
    grid g = n42_window(600, 600, 120, 120);
    tp_features* f = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_contours_generate(g.z, 14400, 120, 120, g.gt, 25.0, 0.0, 4, &f, &err));
    ASSERT_GT((double)f->count, 5.0);
    char* wkt = wkt_of_epsg(4326);
    const char* exts[] = {"shp", "geojson", "kml", "gml", "csv", "GPKG"};
    for (size_t i = 0; i < sizeof exts / sizeof exts[0]; ++i) {
        char path[256];
        snprintf(path, sizeof path, "%s/fmt.%s", tmp_dir(), exts[i]);
        tp_status s = tp_contours_write(path, f, wkt, &err);
        if (s != TP_OK)
            FAIL("%s: %s", exts[i], err.message);
        const long long n = read_back(path, f, 0, NULL);
        if (n != (long long)f->count)
            FAIL("%s: %lld features read back, %zu written", exts[i], n, f->count);
    }
    char side[256];
    const char* shp_parts[] = {"shp", "shx", "dbf", "prj"};
    for (int i = 0; i < 4; ++i) {
        snprintf(side, sizeof side, "%s/fmt.%s", tmp_dir(), shp_parts[i]);
        EXPECT_TRUE(access(side, F_OK) == 0);
    }
    /* every vertex survives a Shapefile (doubles) and a GeoJSON (15 significant digits) */
    snprintf(side, sizeof side, "%s/fmt.shp", tmp_dir());
    read_back(side, f, 1, NULL);
    EXPECT_EQ_INT(0, temporaries_in(tmp_dir()));
    CPLFree(wkt);
    tp_features_destroy(f);
    free(g.z);
}

TEST(shapefile_rewrite_drops_stale_prj)
{
    grid g = n42_window(700, 700, 60, 60);
    tp_features* f = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_contours_generate(g.z, 3600, 60, 60, g.gt, 20.0, 0.0, 5, &f, &err));
    char path[256], prj[256];
    snprintf(path, sizeof path, "%s/stale.shp", tmp_dir());
    snprintf(prj, sizeof prj, "%s/stale.prj", tmp_dir());
    char* wkt = wkt_of_epsg(4326);
    ASSERT_OK(tp_contours_write(path, f, wkt, &err));
    ASSERT_TRUE(access(prj, F_OK) == 0);
    ASSERT_OK(tp_contours_write(path, f, NULL, &err)); /* no CRS: no .prj */
    EXPECT_TRUE(access(prj, F_OK) != 0);
    EXPECT_EQ_INT((long long)f->count, read_back(path, f, 0, NULL));
    EXPECT_EQ_INT(0, temporaries_in(tmp_dir()));
    CPLFree(wkt);
    tp_features_destroy(f);
    free(g.z);
}

static size_t file_size(const char* path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (size_t)st.st_size : 0;
}

TEST(bad_outputs_write_nothing)
{
    float z[4] = {0, 10, 20, 30};
    const double gt[6] = {500000, 30, 0, 4700000, 0, -30};
    tp_features* f = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_contours_generate(z, 4, 2, 2, gt, 5.0, 0.0, 5, &f, &err));
    char path[256];
    snprintf(path, sizeof path, "%s/lines.xyz", tmp_dir());
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_contours_write(path, f, NULL, &err));
    EXPECT_CONTAINS(err.message, path);
    EXPECT_CONTAINS(err.message, "'.xyz'");
    EXPECT_TRUE(access(path, F_OK) != 0);
    snprintf(path, sizeof path, "%s/noext", tmp_dir());
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_contours_write(path, f, NULL, &err));
    EXPECT_CONTAINS(err.message, "no extension");
    EXPECT_STATUS(TP_ERR_IO, tp_contours_write("/nonexistent/dir/c.gpkg", f, NULL, &err));
    EXPECT_CONTAINS(err.message, "/nonexistent/dir/c.gpkg");
    EXPECT_STATUS(TP_ERR_IO, tp_contours_check_output("/nonexistent/dir/c.gpkg", &err));
    /* an older file stays as it was when the new one fails */
    snprintf(path, sizeof path, "%s/old.gpkg", tmp_dir());
    FILE* o = fopen(path, "w");
    fputs("older contents", o);
    fclose(o);
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_contours_write(path, f, "not a CRS at all", &err));
    EXPECT_EQ_INT(14, (long long)file_size(path));
    EXPECT_EQ_INT(0, temporaries_in(tmp_dir()));
    tp_features_destroy(f);
}

/* ---- terrapatch contours ---- */

static int run_contours(const char* const* args, char* out, size_t out_cap, char* err,
                        size_t err_cap)
{
    return tp_test_run_terrapatch_out("contours", args, out, out_cap, err, err_cap);
}

/* The command on mt_hood (UTM, integer heights the store keeps exactly, voids) against GDAL's
 * generator run here on the render grid that tp_render_grid_build makes of the same file. */
TEST(cli_mt_hood_matches_gdal_on_render_grid)
{
    char dem_path[1024];
    REQUIRE_DATA_FILE(dem_path, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    char out_path[256];
    snprintf(out_path, sizeof out_path, "%s/hood.gpkg", tmp_dir());
    char out[4096], errs[8192];
    const char* args[] = {dem_path, "--interval", "50", "-o", out_path, NULL};
    const int rc = run_contours(args, out, sizeof out, errs, sizeof errs);
    if (rc != 0)
        FAIL("exit %d: %s", rc, errs);
    EXPECT_CONTAINS(out, "the whole DEM");
    EXPECT_CONTAINS(out, "every 50 m");

    tp_dem* dem = NULL;
    tp_render_grid* rg = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_dem_read(dem_path, &dem, &err));
    ASSERT_OK(tp_render_grid_build(dem, NULL, &rg, &err));
    tp_dem_destroy(dem);
    grid g = {rg->heights, rg->width, rg->height, {0}};
    memcpy(g.gt, rg->geotransform, sizeof g.gt);
    ref_set r = gdal_contours_grid(&g, 50.0, 0.0);

    /* the file against GDAL: the same lines, each closed line closed, the same levels */
    GDALDatasetH ds = GDALOpenEx(out_path, GDAL_OF_VECTOR, NULL, NULL, NULL);
    ASSERT_TRUE(ds != NULL);
    OGRLayerH l = GDALDatasetGetLayerByName(ds, "contours");
    ASSERT_TRUE(l != NULL);
    ASSERT_EQ_INT(r.count, OGR_L_GetFeatureCount(l, 1));
    const int ie = OGR_FD_GetFieldIndex(OGR_L_GetLayerDefn(l), "elevation_m");
    ASSERT_TRUE(ie >= 0);
    OGR_L_ResetReading(l);
    OGRFeatureH feat;
    int i = 0;
    size_t bad = 0, vertices = 0;
    while ((feat = OGR_L_GetNextFeature(l))) {
        const ref_line* rl = &r.lines[i++];
        EXPECT_EQ_DBL(rl->value, OGR_F_GetFieldAsDouble(feat, ie));
        OGRGeometryH geom = OGR_F_GetGeometryRef(feat);
        EXPECT_EQ_INT(rl->n, OGR_G_GetPointCount(geom));
        for (int k = 0; k < rl->n && k < OGR_G_GetPointCount(geom); ++k) {
            /* 1 mm: the same generator on the same heights (the store keeps integers
             * exactly); anything more is a different grid or a lost vertex */
            bad += fabs(OGR_G_GetX(geom, k) - rl->xy[2 * k]) > 1e-3 ||
                   fabs(OGR_G_GetY(geom, k) - rl->xy[2 * k + 1]) > 1e-3;
            ++vertices;
        }
        OGR_F_Destroy(feat);
    }
    printf("mt_hood at 50 m: %d lines, %zu vertices, %zu apart from GDAL's\n", r.count, vertices,
           bad);
    EXPECT_EQ_INT(0, (long long)bad);
    GDALClose(ds);
    ref_free(&r);
    tp_render_grid_destroy(rg);
}

TEST(cli_bad_input)
{
    char dem_path[1024];
    REQUIRE_DATA_FILE(dem_path, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    char out[4096], errs[8192], path[256];
    /* interval 0 or negative: a usage error, nothing written */
    snprintf(path, sizeof path, "%s/bad.gpkg", tmp_dir());
    const char* zero[] = {dem_path, "--interval", "0", "-o", path, NULL};
    EXPECT_EQ_INT(2, run_contours(zero, out, sizeof out, errs, sizeof errs));
    EXPECT_CONTAINS(errs, "--interval: expected a number > 0, got '0'");
    const char* neg[] = {dem_path, "--interval", "-10", "-o", path, NULL};
    EXPECT_EQ_INT(2, run_contours(neg, out, sizeof out, errs, sizeof errs));
    EXPECT_TRUE(access(path, F_OK) != 0);
    /* an unknown extension: a usage error listing what is written, the older file of that
     * name intact */
    snprintf(path, sizeof path, "%s/old.xyz", tmp_dir());
    FILE* o = fopen(path, "w");
    fputs("older", o);
    fclose(o);
    const char* ext[] = {dem_path, "--interval", "20", "-o", path, NULL};
    EXPECT_EQ_INT(2, run_contours(ext, out, sizeof out, errs, sizeof errs));
    EXPECT_CONTAINS(errs, "old.xyz: unknown extension '.xyz'");
    EXPECT_CONTAINS(errs, "contours writes GeoPackage (.gpkg), Shapefile (.shp)");
    EXPECT_EQ_INT(5, (long long)file_size(path));
    /* an unwritable place */
    const char* dir[] = {dem_path, "--interval", "20", "-o", "/nonexistent/dir/c.gpkg", NULL};
    EXPECT_EQ_INT(1, run_contours(dir, out, sizeof out, errs, sizeof errs));
    EXPECT_CONTAINS(errs, "/nonexistent/dir/c.gpkg");
    /* a position outside the DEM */
    snprintf(path, sizeof path, "%s/around.gpkg", tmp_dir());
    const char* far[] = {dem_path, "--interval", "20", "--around", "45,7", "--radius", "1000",
                         "-o", path, NULL};
    EXPECT_EQ_INT(1, run_contours(far, out, sizeof out, errs, sizeof errs));
    EXPECT_CONTAINS(errs, "outside the DEM");
    EXPECT_TRUE(access(path, F_OK) != 0);
    /* an area outside the DEM */
    const char* area[] = {dem_path, "--interval", "20", "--area", "0,0,1000,1000", "-o", path,
                          NULL};
    EXPECT_EQ_INT(1, run_contours(area, out, sizeof out, errs, sizeof errs));
    EXPECT_CONTAINS(errs, "is outside the DEM");
    EXPECT_TRUE(access(path, F_OK) != 0);
    EXPECT_EQ_INT(0, temporaries_in(tmp_dir()));
}

TEST(cli_around_a_position_and_flat_ground)
{
    char dem_path[1024];
    REQUIRE_DATA_FILE(dem_path, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    char out[4096], errs[8192], path[256];
    snprintf(path, sizeof path, "%s/around.geojson", tmp_dir());
    const char* a[] = {dem_path, "--interval", "20", "--around", "42.5,1.5", "--radius", "3000",
                       "-o", path, NULL};
    const int rc = run_contours(a, out, sizeof out, errs, sizeof errs);
    if (rc != 0)
        FAIL("exit %d: %s", rc, errs);
    /* 3 km either side of a post on 67.93 m posts: 2 * 44 + 1 posts */
    EXPECT_CONTAINS(out, "window     89x89 posts");
    EXPECT_CONTAINS(out, "lines (");
    EXPECT_GT((double)read_back(path, NULL, 0, NULL), 10.0);

    /* flat ground (a GeoTIFF written here, UTM 33N, 100.5 m everywhere): an empty layer */
    GDALAllRegister();
    char flat[256];
    snprintf(flat, sizeof flat, "%s/flat.tif", tmp_dir());
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), flat, 40, 30, 1, GDT_Float32, NULL);
    ASSERT_TRUE(ds != NULL);
    double gt[6] = {500000, 30, 0, 4700000, 0, -30};
    GDALSetGeoTransform(ds, gt);
    char* wkt = wkt_of_epsg(32633);
    GDALSetProjection(ds, wkt);
    CPLFree(wkt);
    GDALFillRaster(GDALGetRasterBand(ds, 1), 100.5, 0);
    GDALClose(ds);
    snprintf(path, sizeof path, "%s/flat.gpkg", tmp_dir());
    const char* fl[] = {flat, "--interval", "10", "-o", path, NULL};
    EXPECT_EQ_INT(0, run_contours(fl, out, sizeof out, errs, sizeof errs));
    EXPECT_CONTAINS(out, "contours   none");
    EXPECT_EQ_INT(0, read_back(path, NULL, 0, "contours"));
}

/* A tiny interval over a modest range is refused by the vertices it would draw, counted before
 * GDAL runs (issue 29, 4.11: --interval 0.001 ran past two minutes): a plane rising 0.021 m a
 * post over 1000 x 1000 posts crosses 21 levels of 1 mm on each of its 999 x 1000 horizontal
 * edges, 20,979,000 vertices (21,000 levels: under the level bound), and none on the vertical
 * ones; at 1.1 mm it is 19,071,000, under the bound, and counted the same way. */
TEST(interval_bounded_by_the_vertices_it_would_draw)
{
    const int w = 1000, h = 1000;
    float* z = malloc((size_t)w * h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[(size_t)y * w + x] = 0.021f * x + 0.0005f; /* levels never on a post */
    const double gt[6] = {500000, 1, 0, 4700000, 0, -1};
    tp_features* f = NULL;
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate(z, (size_t)w * h, w, h, gt, 0.001, 0.0, 0, &f, &err));
    EXPECT_CONTAINS(err.message, "would draw about 2.1e+07 vertices");
    EXPECT_CONTAINS(err.message, "choose an interval of about 0.001");
    EXPECT_TRUE(f == NULL);
    free(z);
}

#define TESTS(X)                                                                                   \
    X(interval_bounded_by_the_vertices_it_would_draw)                                              \
    X(n42e001_matches_gdal_contour_generate)                                                       \
    X(no_contour_crosses_a_void)                                                                   \
    X(flat_grid_gives_no_lines)                                                                    \
    X(one_by_one_and_two_by_two_grids)                                                             \
    X(bad_arguments_leave_out_untouched)                                                           \
    X(gpkg_reads_back_with_elevation_m)                                                            \
    X(formats_by_extension)                                                                        \
    X(shapefile_rewrite_drops_stale_prj)                                                           \
    X(bad_outputs_write_nothing)                                                                   \
    X(cli_mt_hood_matches_gdal_on_render_grid)                                                     \
    X(cli_bad_input)                                                                               \
    X(cli_around_a_position_and_flat_ground)
TP_TEST_MAIN(TESTS)
