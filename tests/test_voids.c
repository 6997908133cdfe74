/*
 * test_voids.c - interior voids filled whatever their size, by interpolation or from a coarser
 * second source shifted onto the ground (--fill-from), on holes punched into a real DEM:
 * N42E001.hgt warped to UTM 31N at 90 m, 667 x 1000 samples inside the tile (GDALWarp here, so that the holes' samples are the
 * render grid's: a projected DEM in metres is used on its own grid), holes of 1x1 to 100x90
 * samples and one touching the grid's edge, written as a GeoTIFF with nodata; the truth is the
 * DEM before punching. The coarse copy is the truth averaged to 270 m (3x coarser) by GDALWarp.
 * Both the in-memory path (tp_render_grid_build) and the band reader (tp_mosaic, terrapatch
 * build) are checked, and `terrapatch build --fill-from` with bad files.
 */
#define _GNU_SOURCE
#include "tp_test.h"
#include "tp_io.h"

#include "tp_test_child.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <gdal_utils.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TP_TMP_PREFIX "tp_voids_"
#include "tp_test_tmp.h"

/* The holes: x, y, width, height (samples of the 90 m grid). The places are where the search
 * in setup() starts: each hole goes to the first place from there whose samples and rim (2
 * samples) are all valid and away from the other holes. */
typedef struct { int x, y, w, h; } hole;
static hole HOLES[] = {
    {300, 500, 1, 1},    /* 1x1 */
    {420, 640, 10, 10},  /* small */
    {100, 150, 40, 25},  /* below the old 64 */
    {380, 280, 100, 90}, /* beyond the old 64 */
};
#define HOLE_COUNT (int)(sizeof HOLES / sizeof HOLES[0])
static hole EDGE = {0, 0, 30, 20}; /* touches column 0: outside, never filled */

#define COARSE_BIAS_M 50.0f

typedef struct fixture {
    char truth[512], holes[512], coarse[512], text[512];
    int w, h;
    double gt[6];
    float* z;        /* the truth, NaN = nodata */
    char* wkt;
} fixture;

static fixture F;

static void warp(const char* src_path, const char* dst, const char* const* args)
{
    GDALDatasetH src = GDALOpen(src_path, GA_ReadOnly);
    ASSERT_TRUE(src != NULL);
    GDALWarpAppOptions* o = GDALWarpAppOptionsNew((char**)args, NULL);
    ASSERT_TRUE(o != NULL);
    int usage = 0;
    GDALDatasetH out = GDALWarp(dst, NULL, 1, &src, o, &usage);
    GDALWarpAppOptionsFree(o);
    ASSERT_TRUE(out != NULL);
    GDALClose(out);
    GDALClose(src);
}

static float* read_band(const char* path, int* w, int* h, double gt[6], char** wkt)
{
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    *w = GDALGetRasterXSize(ds), *h = GDALGetRasterYSize(ds);
    if (gt)
        GDALGetGeoTransform(ds, gt);
    if (wkt)
        *wkt = CPLStrdup(GDALGetProjectionRef(ds));
    float* z = malloc((size_t)*w * *h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    int has = 0;
    double nd = GDALGetRasterNoDataValue(b, &has);
    ASSERT_EQ_INT(CE_None, GDALRasterIO(b, GF_Read, 0, 0, *w, *h, z, *w, *h, GDT_Float32, 0, 0));
    for (size_t i = 0; i < (size_t)*w * *h; i++)
        if (has && (z[i] == (float)nd || isnan(z[i])))
            z[i] = NAN;
    GDALClose(ds);
    return z;
}

static int in_hole(const hole* q, int x, int y)
{
    return x >= q->x && x < q->x + q->w && y >= q->y && y < q->y + q->h;
}

/* Writes the truth, the punched copy and the coarse copy once per process. */
static void setup(void)
{
    if (F.z)
        return;
    char hgt[1024];
    REQUIRE_DATA_FILE(hgt, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    GDALAllRegister();
    const char* dir = make_tmp_dir();
    snprintf(F.truth, sizeof F.truth, "%s/truth.tif", dir);
    snprintf(F.holes, sizeof F.holes, "%s/holes.tif", dir);
    snprintf(F.coarse, sizeof F.coarse, "%s/coarse.tif", dir);
    snprintf(F.text, sizeof F.text, "%s/notes.tif", dir);
    /* 60 x 90 km inside the tile: no wedges at the grid's edges, only SRTM's own voids */
    const char* a1[] = {"-t_srs", "EPSG:32631", "-te", "345000", "4660000", "405000", "4750000",
                        "-tr", "90", "90", "-r", "bilinear", "-ot", "Float32", "-dstnodata",
                        "-9999", "-of", "GTiff", NULL};
    warp(hgt, F.truth, a1);
    const char* a2[] = {"-tr", "270", "270", "-r", "average", "-dstnodata", "-9999", "-of",
                        "GTiff", NULL};
    warp(F.truth, F.coarse, a2);
    { /* 50 m higher: a second source on another vertical reference (the geoid is about 50 m
       * above the WGS84 ellipsoid here), the step the delta fill must remove */
        GDALDatasetH c = GDALOpen(F.coarse, GA_Update);
        ASSERT_TRUE(c != NULL);
        const int cw = GDALGetRasterXSize(c), ch = GDALGetRasterYSize(c);
        float* cz = malloc((size_t)cw * ch * sizeof *cz);
        ASSERT_TRUE(cz != NULL);
        GDALRasterBandH b = GDALGetRasterBand(c, 1);
        ASSERT_EQ_INT(CE_None, GDALRasterIO(b, GF_Read, 0, 0, cw, ch, cz, cw, ch, GDT_Float32, 0, 0));
        for (size_t i = 0; i < (size_t)cw * ch; i++)
            if (cz[i] != -9999.0f)
                cz[i] += COARSE_BIAS_M;
        ASSERT_EQ_INT(CE_None, GDALRasterIO(b, GF_Write, 0, 0, cw, ch, cz, cw, ch, GDT_Float32, 0, 0));
        GDALClose(c);
        free(cz);
    }
    F.z = read_band(F.truth, &F.w, &F.h, F.gt, &F.wkt);
    /* every hole and its rim (2 samples) on valid ground, the errors are measured there; the
     * edge hole on valid ground against the grid's first column */
    for (int k = 0; k <= HOLE_COUNT; k++) {
        hole* q = k < HOLE_COUNT ? &HOLES[k] : &EDGE;
        const int rim = k < HOLE_COUNT ? 2 : 0;
        int found = 0;
        for (int step = 0; step < 400 && !found; step++) {
            const int y0 = k < HOLE_COUNT ? q->y + (step / 20) * 7 : step * 3;
            const int x0 = k < HOLE_COUNT ? q->x + (step % 20) * 7 : 0;
            if (y0 - rim < 0 || x0 - rim < 0 || y0 + q->h + rim > F.h || x0 + q->w + rim > F.w)
                continue;
            int ok = 1;
            for (int y = y0 - rim - 3; ok && y < y0 + q->h + rim + 3; y++)
                for (int x = x0 - rim - 3; ok && x < x0 + q->w + rim + 3; x++) {
                    if (y < 0 || x < 0 || y >= F.h || x >= F.w)
                        continue;
                    const int inner = y >= y0 - rim && y < y0 + q->h + rim && x >= x0 - rim &&
                                      x < x0 + q->w + rim;
                    if (inner && isnan(F.z[(size_t)y * F.w + x]))
                        ok = 0;
                    for (int j = 0; j < k; j++)
                        if (in_hole(&HOLES[j], x, y))
                            ok = 0;
                }
            if (ok)
                q->x = x0, q->y = y0, found = 1;
        }
        ASSERT_TRUE(found);
    }
    /* the punched copy */
    GDALDatasetH src = GDALOpen(F.truth, GA_ReadOnly);
    GDALDatasetH dst = GDALCreateCopy(GDALGetDriverByName("GTiff"), F.holes, src, FALSE, NULL,
                                      NULL, NULL);
    GDALClose(src);
    ASSERT_TRUE(dst != NULL);
    float* z = malloc((size_t)F.w * F.h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    for (size_t i = 0; i < (size_t)F.w * F.h; i++)
        z[i] = isnan(F.z[i]) ? -9999.0f : F.z[i];
    for (int y = 0; y < F.h; y++)
        for (int x = 0; x < F.w; x++) {
            int punch = in_hole(&EDGE, x, y);
            for (int k = 0; k < HOLE_COUNT; k++)
                punch |= in_hole(&HOLES[k], x, y);
            if (punch)
                z[(size_t)y * F.w + x] = -9999.0f;
        }
    ASSERT_EQ_INT(CE_None, GDALRasterIO(GDALGetRasterBand(dst, 1), GF_Write, 0, 0, F.w, F.h, z,
                                        F.w, F.h, GDT_Float32, 0, 0));
    GDALClose(dst);
    free(z);
    FILE* f = fopen(F.text, "w");
    ASSERT_TRUE(f != NULL);
    fputs("not a raster\n", f);
    fclose(f);
}

static tp_render_grid* grid_of(const char* path, int fill_max_px, const char* fill_from)
{
    tp_error err = {0};
    tp_dem* dem = NULL;
    ASSERT_EQ_INT(TP_OK, tp_dem_read(path, &dem, &err));
    tp_grid_options o = {.fill_max_px = fill_max_px, .fill_from = fill_from};
    tp_render_grid* g = NULL;
    tp_status st = tp_render_grid_build(dem, &o, &g, &err);
    if (st != TP_OK)
        fprintf(stderr, "%s\n", err.message);
    ASSERT_EQ_INT(TP_OK, st);
    tp_dem_destroy(dem);
    ASSERT_EQ_INT(F.w, g->width);
    ASSERT_EQ_INT(F.h, g->height);
    return g;
}

/* Errors against the truth over the samples of the holes (k < 0: all of them). */
typedef struct { double rmse, max; size_t n; } errors;
static errors hole_errors(const float* z, int k)
{
    errors e = {0, 0, 0};
    double sum = 0;
    for (int i = k < 0 ? 0 : k; i < (k < 0 ? HOLE_COUNT : k + 1); i++)
        for (int y = HOLES[i].y; y < HOLES[i].y + HOLES[i].h; y++)
            for (int x = HOLES[i].x; x < HOLES[i].x + HOLES[i].w; x++) {
                const size_t j = (size_t)y * F.w + x;
                ASSERT_FALSE(isnan(z[j])); /* filled */
                const double d = fabs(z[j] - F.z[j]);
                sum += d * d, e.max = fmax(e.max, d), e.n++;
            }
    e.rmse = sqrt(sum / (double)e.n);
    return e;
}

/* The step at the rims: over every filled sample of a hole next to a sample outside it, RMS of
 * (filled - neighbour) - (truth - truth's neighbour): 0 when the fill meets the ground as the
 * ground itself does. */
static double rim_step_rms(const float* z)
{
    double sum = 0;
    size_t n = 0;
    for (int k = 1; k < HOLE_COUNT; k++) {
        const hole* q = &HOLES[k];
        for (int y = q->y; y < q->y + q->h; y++)
            for (int x = q->x; x < q->x + q->w; x++) {
                const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
                for (int d = 0; d < 4; d++) {
                    if (in_hole(q, nx[d], ny[d]))
                        continue;
                    const size_t i = (size_t)y * F.w + x, j = (size_t)ny[d] * F.w + nx[d];
                    const double s = (z[i] - z[j]) - (F.z[i] - F.z[j]);
                    sum += s * s, n++;
                }
            }
    }
    return sqrt(sum / (double)n);
}

/* The coarse copy as the fill would use it unshifted: GDALWarp bilinear onto the grid. */
static float* coarse_on_grid(void)
{
    char dst[600];
    snprintf(dst, sizeof dst, "%s.ongrid.tif", F.coarse);
    char te[4][40], ts[2][16];
    snprintf(te[0], 40, "%.17g", F.gt[0]), snprintf(te[1], 40, "%.17g", F.gt[3] + F.h * F.gt[5]);
    snprintf(te[2], 40, "%.17g", F.gt[0] + F.w * F.gt[1]), snprintf(te[3], 40, "%.17g", F.gt[3]);
    snprintf(ts[0], 16, "%d", F.w), snprintf(ts[1], 16, "%d", F.h);
    const char* a[] = {"-te", te[0], te[1], te[2], te[3], "-ts", ts[0], ts[1], "-r", "bilinear",
                       "-dstnodata", "-9999", "-of", "GTiff", NULL};
    warp(F.coarse, dst, a);
    int w, h;
    return read_band(dst, &w, &h, NULL, NULL);
}

/* Interpolation fills every interior hole, 1x1 to 100x90 (beyond the old 64), and leaves the one
 * touching the edge. */
TEST(interpolation_fills_holes_of_any_size)
{
    setup();
    tp_render_grid* g = grid_of(F.holes, 0, NULL);
    errors all = hole_errors(g->heights, -1), big = hole_errors(g->heights, 3);
    fprintf(stderr, "interpolation: RMSE %.2f m, max %.2f m over %zu samples (100x90: RMSE %.2f, "
                    "max %.2f); filled %zu\n",
            all.rmse, all.max, all.n, big.rmse, big.max, g->filled_samples);
    for (int k = 0; k < HOLE_COUNT; k++)
        for (int y = HOLES[k].y; y < HOLES[k].y + HOLES[k].h; y++)
            for (int x = HOLES[k].x; x < HOLES[k].x + HOLES[k].w; x++)
                EXPECT_EQ_INT(1, g->filled[(size_t)y * F.w + x]);
    for (int y = EDGE.y; y < EDGE.y + EDGE.h; y++)
        for (int x = EDGE.x; x < EDGE.x + EDGE.w; x++)
            EXPECT_TRUE(isnan(g->heights[(size_t)y * F.w + x]));
    EXPECT_TRUE(g->filled_samples >= all.n);
    EXPECT_EQ_INT(0, (long long)g->filled_from_samples);
    /* the 1x1 hole: between its four neighbours */
    const size_t c = (size_t)HOLES[0].y * F.w + HOLES[0].x;
    const float n4[4] = {F.z[c - 1], F.z[c + 1], F.z[c - F.w], F.z[c + F.w]};
    float lo = n4[0], hi = n4[0];
    for (int i = 1; i < 4; i++)
        lo = fminf(lo, n4[i]), hi = fmaxf(hi, n4[i]);
    EXPECT_TRUE(g->heights[c] >= lo && g->heights[c] <= hi);
    tp_render_grid_destroy(g);
}

/* The delta-surface fill from the 3x coarser copy, 50 m off, beats interpolation in every hole
 * larger than a few samples and removes the offset: the fill is OTHER + delta, delta the
 * residual DEM - OTHER at the rim carried inward, so its error is the coarse copy's own
 * residual inside minus a weighted mean of its residuals at the rim: for residuals independent
 * of each other about sqrt(2) times the coarse copy's RMSE (bound asserted: 1.5x), and never more
 * than twice its largest residual (the weights are a convex combination). At the rim the step the
 * unshifted copy makes (its offset) is gone. */
TEST(fill_from_coarse_copy_beats_interpolation)
{
    setup();
    tp_render_grid* gi = grid_of(F.holes, 0, NULL);
    tp_render_grid* gd = grid_of(F.holes, 0, F.coarse);
    float* raw = coarse_on_grid();
    errors ei = hole_errors(gi->heights, -1), ed = hole_errors(gd->heights, -1);
    errors er = hole_errors(raw, -1);
    for (size_t i = 0; i < (size_t)F.w * F.h; i++)
        raw[i] -= COARSE_BIAS_M;
    errors eu = hole_errors(raw, -1); /* the coarse copy's own residual, offset removed */
    /* the copy pasted unshifted into the holes: the DEM around them */
    for (int y = 0; y < F.h; y++)
        for (int x = 0; x < F.w; x++) {
            const size_t i = (size_t)y * F.w + x;
            int in = 0;
            for (int k = 0; k < HOLE_COUNT; k++)
                in |= in_hole(&HOLES[k], x, y);
            raw[i] = in ? raw[i] + COARSE_BIAS_M : F.z[i];
        }
    const double si = rim_step_rms(gi->heights), sd = rim_step_rms(gd->heights),
                 sr = rim_step_rms(raw);
    fprintf(stderr,
            "holes (%zu samples): interpolation RMSE %.2f m max %.2f m; delta fill RMSE %.2f m "
            "max %.2f m; coarse unshifted RMSE %.2f m max %.2f m (without its offset %.2f m, "
            "max %.2f m)\n"
            "rim step RMS: interpolation %.2f m, delta %.2f m, coarse unshifted %.2f m\n",
            ei.n, ei.rmse, ei.max, ed.rmse, ed.max, er.rmse, er.max, eu.rmse, eu.max, si, sd, sr);
    for (int k = 2; k < HOLE_COUNT; k++) {
        errors a = hole_errors(gi->heights, k), b = hole_errors(gd->heights, k);
        fprintf(stderr, "hole %dx%d: interpolation RMSE %.2f, delta %.2f\n", HOLES[k].w,
                HOLES[k].h, a.rmse, b.rmse);
        EXPECT_TRUE(b.rmse < a.rmse);
    }
    EXPECT_TRUE(ed.rmse < ei.rmse);
    EXPECT_TRUE(ed.rmse <= 1.5 * eu.rmse);
    EXPECT_TRUE(ed.max <= 2 * eu.max);
    EXPECT_TRUE(ed.rmse < 0.75 * er.rmse); /* better than the copy as it is */
    EXPECT_TRUE(sd < 0.5 * sr);            /* the step at the rim is gone */
    EXPECT_TRUE(gd->filled_from_samples >= ed.n);
    EXPECT_EQ_INT((long long)gi->filled_samples, (long long)gd->filled_samples);
    for (int y = EDGE.y; y < EDGE.y + EDGE.h; y++)
        for (int x = EDGE.x; x < EDGE.x + EDGE.w; x++)
            EXPECT_TRUE(isnan(gd->heights[(size_t)y * F.w + x]));
    free(raw);
    tp_render_grid_destroy(gi);
    tp_render_grid_destroy(gd);
}

/* fill_max_px still caps: 64 leaves the 100x90 hole and fills the 40x25; negative fills none. */
TEST(fill_max_still_caps)
{
    setup();
    tp_render_grid* g = grid_of(F.holes, 64, F.coarse);
    EXPECT_TRUE(isnan(g->heights[(size_t)(HOLES[3].y + 45) * F.w + HOLES[3].x + 50]));
    EXPECT_EQ_INT(1, g->filled[(size_t)(HOLES[2].y + 12) * F.w + HOLES[2].x + 20]);
    EXPECT_TRUE(g->large_void_samples >= 100 * 90);
    tp_render_grid_destroy(g);
    g = grid_of(F.holes, -1, F.coarse);
    EXPECT_EQ_INT(0, (long long)g->filled_samples);
    EXPECT_TRUE(isnan(g->heights[(size_t)HOLES[0].y * F.w + HOLES[0].x]));
    tp_render_grid_destroy(g);
}

/* The band reader (65 rows at a time, as terrapatch build reads) gives the in-memory grid's
 * heights, sample for sample, with and without the second source. */
static void check_streamed(int from_coarse)
{
    setup();
    const char* fill_from = from_coarse ? F.coarse : NULL;
    tp_render_grid* g = grid_of(F.holes, 0, fill_from);
    const char* paths[] = {F.holes};
    tp_mosaic_options mo = {.fill_max = TP_FILL_MAX_ANY, .fill_from = fill_from};
    tp_mosaic* m = NULL;
    tp_error err = {0};
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, &mo, &m, &err));
    float* z = malloc((size_t)F.w * 65 * sizeof *z);
    ASSERT_TRUE(z != NULL);
    size_t differ = 0;
    for (int y = 0; y < F.h; y += 65) {
        const int n = F.h - y < 65 ? F.h - y : 65;
        ASSERT_EQ_INT(TP_OK, tp_mosaic_read_rows(m, y, n, z, (size_t)n * F.w, &err));
        for (size_t i = 0; i < (size_t)n * F.w; i++) {
            const float a = z[i], b = g->heights[(size_t)y * F.w + i];
            differ += !(isnan(a) && isnan(b)) && a != b;
        }
    }
    tp_mosaic_voids v;
    tp_mosaic_get_voids(m, &v);
    EXPECT_EQ_INT(0, (long long)differ);
    EXPECT_EQ_INT((long long)g->filled_samples, (long long)v.filled_samples);
    EXPECT_EQ_INT((long long)g->filled_from_samples, (long long)v.filled_from_samples);
    EXPECT_EQ_INT(0, (long long)v.too_large_samples);
    free(z);
    tp_mosaic_close(m);
    tp_render_grid_destroy(g);
}

TEST(streamed_equals_in_memory_interpolated) { check_streamed(0); }
TEST(streamed_equals_in_memory_fill_from) { check_streamed(1); }

/* A window too small for the 40x25 and 100x90 holes' crops (3 MB: about 45 rows of this grid;
 * their crops are 107 and 292 rows): those stay and are counted; the 1x1 and 10x10 (crop 32
 * rows) are filled. */
TEST(streamed_window_cap_leaves_tall_void)
{
    setup();
    const char* paths[] = {F.holes};
    tp_mosaic_options mo = {.fill_max = TP_FILL_MAX_ANY, .fill_window_mb = 3};
    tp_mosaic* m = NULL;
    tp_error err = {0};
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, &mo, &m, &err));
    float* z = malloc((size_t)F.w * F.h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    for (int y = 0; y < F.h; y += 65) {
        const int n = F.h - y < 65 ? F.h - y : 65;
        ASSERT_EQ_INT(TP_OK, tp_mosaic_read_rows(m, y, n, z + (size_t)y * F.w, (size_t)n * F.w, &err));
    }
    tp_mosaic_voids v;
    tp_mosaic_get_voids(m, &v);
    fprintf(stderr, "window of %d rows: %zu samples left\n", v.max_void_rows, v.too_large_samples);
    EXPECT_TRUE(v.max_void_rows >= 32 && v.max_void_rows < 107);
    EXPECT_TRUE(v.too_large_samples >= 100 * 90 + 40 * 25);
    EXPECT_TRUE(isnan(z[(size_t)(HOLES[2].y + 12) * F.w + HOLES[2].x + 20]));
    EXPECT_TRUE(isnan(z[(size_t)(HOLES[3].y + 45) * F.w + HOLES[3].x + 50]));
    EXPECT_FALSE(isnan(z[(size_t)HOLES[0].y * F.w + HOLES[0].x]));
    EXPECT_FALSE(isnan(z[(size_t)(HOLES[1].y + 5) * F.w + HOLES[1].x + 5]));
    free(z);
    tp_mosaic_close(m);
}

/* A copy of the coarse source with its heights in another unit: each valid height times
 * per_m (units per metre), band 1's unit type set to unit. */
static void write_coarse_in(const char* path, double per_m, const char* unit)
{
    GDALDatasetH src = GDALOpen(F.coarse, GA_ReadOnly);
    ASSERT_TRUE(src != NULL);
    GDALDatasetH dst =
        GDALCreateCopy(GDALGetDriverByName("GTiff"), path, src, FALSE, NULL, NULL, NULL);
    GDALClose(src);
    ASSERT_TRUE(dst != NULL);
    const int cw = GDALGetRasterXSize(dst), ch = GDALGetRasterYSize(dst);
    float* cz = malloc((size_t)cw * ch * sizeof *cz);
    ASSERT_TRUE(cz != NULL);
    GDALRasterBandH b = GDALGetRasterBand(dst, 1);
    ASSERT_EQ_INT(CE_None, GDALRasterIO(b, GF_Read, 0, 0, cw, ch, cz, cw, ch, GDT_Float32, 0, 0));
    for (size_t i = 0; i < (size_t)cw * ch; i++)
        if (cz[i] != -9999.0f)
            cz[i] = (float)(cz[i] * per_m);
    ASSERT_EQ_INT(CE_None, GDALRasterIO(b, GF_Write, 0, 0, cw, ch, cz, cw, ch, GDT_Float32, 0, 0));
    ASSERT_EQ_INT(CE_None, GDALSetRasterUnitType(b, unit));
    GDALClose(dst);
    free(cz);
}

/* The largest difference between a and b over the holes' samples. */
static double hole_diff_max(const float* a, const float* b)
{
    double d = 0;
    for (int k = 0; k < HOLE_COUNT; k++)
        for (int y = HOLES[k].y; y < HOLES[k].y + HOLES[k].h; y++)
            for (int x = HOLES[k].x; x < HOLES[k].x + HOLES[k].w; x++) {
                const size_t i = (size_t)y * F.w + x;
                d = fmax(d, isnan(a[i]) || isnan(b[i]) ? INFINITY : fabs(a[i] - b[i]));
            }
    return d;
}

/* --fill-from a raster in feet (band unit "ft") or US survey feet ("ftUS") is converted to
 * metres as a DEM in those units is (z_unit_of): the voids are filled with the heights the
 * metre source gives, in memory and in the band reader (build); a unit terrapatch does not know
 * is a warning naming the file and the unit, its heights taken as metres. (The fill used to
 * take the feet as metres: 3.28 times the relief inside each hole.) */
TEST(fill_from_in_feet_is_converted_to_metres)
{
    setup();
    char ft[600], usft[600], odd[600];
    snprintf(ft, sizeof ft, "%s.ft.tif", F.coarse);
    snprintf(usft, sizeof usft, "%s.usft.tif", F.coarse);
    snprintf(odd, sizeof odd, "%s.furlong.tif", F.coarse);
    write_coarse_in(ft, 1 / 0.3048, "ft");
    write_coarse_in(usft, 3937.0 / 1200.0, "ftUS");
    write_coarse_in(odd, 1.0, "furlong");
    tp_render_grid* gm = grid_of(F.holes, 0, F.coarse);
    const char* sources[] = {ft, usft};
    for (int s = 0; s < 2; s++) {
        tp_render_grid* g = grid_of(F.holes, 0, sources[s]);
        const double d = hole_diff_max(g->heights, gm->heights);
        fprintf(stderr, "%s: largest difference from the metre source's fill %.4f m\n", sources[s],
                d);
        EXPECT_TRUE(d < 0.01);
        EXPECT_EQ_INT((long long)gm->filled_from_samples, (long long)g->filled_from_samples);
        EXPECT_TRUE(strstr(g->warnings, "unit") == NULL);
        tp_render_grid_destroy(g);

        /* the band reader, as terrapatch build reads */
        const char* paths[] = {F.holes};
        tp_mosaic_options mo = {.fill_max = TP_FILL_MAX_ANY, .fill_from = sources[s]};
        tp_mosaic* m = NULL;
        tp_error err = {0};
        ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, &mo, &m, &err));
        float* z = malloc((size_t)F.w * F.h * sizeof *z);
        ASSERT_TRUE(z != NULL);
        for (int y = 0; y < F.h; y += 65) {
            const int n = F.h - y < 65 ? F.h - y : 65;
            ASSERT_EQ_INT(TP_OK,
                          tp_mosaic_read_rows(m, y, n, z + (size_t)y * F.w, (size_t)n * F.w, &err));
        }
        EXPECT_TRUE(hole_diff_max(z, gm->heights) < 0.01);
        tp_mosaic_info mi;
        tp_mosaic_get_info(m, &mi);
        EXPECT_CONTAINS(mi.notes, s == 0 ? "international foot" : "US survey foot");
        free(z);
        tp_mosaic_close(m);
    }
    /* an unknown unit: warned, named, taken as metres (the metre source's fill) */
    tp_render_grid* g = grid_of(F.holes, 0, odd);
    EXPECT_CONTAINS(g->warnings, odd);
    EXPECT_CONTAINS(g->warnings, "band 1's unit 'furlong' is not one terrapatch knows");
    EXPECT_TRUE(hole_diff_max(g->heights, gm->heights) < 0.01);
    tp_render_grid_destroy(g);
    const char* paths[] = {F.holes};
    tp_mosaic_options mo = {.fill_max = TP_FILL_MAX_ANY, .fill_from = odd};
    tp_mosaic* m = NULL;
    tp_error err = {0};
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, &mo, &m, &err));
    tp_mosaic_info mi;
    tp_mosaic_get_info(m, &mi);
    EXPECT_CONTAINS(mi.notes, "warning: ");
    EXPECT_CONTAINS(mi.notes, "band 1's unit 'furlong' is not one terrapatch knows");
    tp_mosaic_close(m);
    tp_render_grid_destroy(gm);
}

/* terrapatch build --fill-from: the store says what filled its voids; a bad second source is
 * one line naming it, exit 1 and no store. */
static int run_build(const char* from, const char* out, char* err, size_t cap)
{
    const char* args[] = {F.holes, "-o", out, "--quiet", "--fill-from", from, NULL};
    return tp_test_run_terrapatch("build", args, err, cap);
}

TEST(build_fill_from_notes_and_bad_sources)
{
    setup();
    char out[600], err[4096], rainier[1024];
    snprintf(out, sizeof out, "%s.tpt", F.holes);
    ASSERT_EQ_INT(0, run_build(F.coarse, out, err, sizeof err));
    tp_store* s = NULL;
    tp_error e = {0};
    ASSERT_EQ_INT(TP_OK, tp_store_open(out, &s, &e));
    tp_store_info si;
    tp_store_get_info(s, &si);
    EXPECT_TRUE(strstr(si.header.notes, "voids of any size filled from ") != NULL);
    tp_store_close(s);
    unlink(out);

    REQUIRE_DATA_FILE(rainier, "TP_SHARED_DATA_DIR", "mt_rainier_90m.tif");
    char missing[600];
    snprintf(missing, sizeof missing, "%s.missing.tif", F.holes);
    const char* bad[] = {missing, rainier, F.text};
    const char* says[] = {"cannot open", "does not overlap", "not a raster"};
    for (int i = 0; i < 3; i++) {
        struct stat st;
        EXPECT_EQ_INT(1, run_build(bad[i], out, err, sizeof err));
        EXPECT_TRUE(strstr(err, bad[i]) != NULL);
        EXPECT_TRUE(strstr(err, says[i]) != NULL);
        EXPECT_TRUE(stat(out, &st) != 0);
        fprintf(stderr, "%s", err);
    }
}

/* ---- stores mark their filled samples (format 4) ---- */

static uint32_t crc32_ref(const uint8_t* p, size_t n) /* zlib's CRC32, as docs/store.md says */
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1)));
    }
    return ~c;
}
static uint32_t le32(const uint8_t* p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static uint64_t le64(const uint8_t* p) { return le32(p) | (uint64_t)le32(p + 4) << 32; }
static void put32(uint8_t* p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

/* The punched DEM built into a store (once per process; --patch 17: 5 scales). */
static const char* filled_store(void)
{
    static char out[600];
    if (out[0])
        return out;
    setup();
    char err[4096];
    snprintf(out, sizeof out, "%s.filled.tpt", F.holes);
    const char* args[] = {F.holes, "-o", out, "--quiet", "--patch", "17", NULL};
    int code = tp_test_run_terrapatch("build", args, err, sizeof err);
    if (code != 0)
        fprintf(stderr, "%s", err);
    ASSERT_EQ_INT(0, code);
    return out;
}

/* Every node's filled bits, at every scale, are tp_render_grid_build's `filled` at the samples
 * the node holds (its vertices: full-resolution samples every 2^scale), and only nodes holding
 * one carry TP_NODE_HAS_FILLED; the mosaic's per-sample flags are the same. */
TEST(store_marks_exactly_the_filled_samples)
{
    const char* path = filled_store();
    tp_render_grid* g = grid_of(F.holes, 0, NULL);
    ASSERT_TRUE(g->filled_samples > 100 * 90); /* the punched holes and SRTM's own voids */
    tp_error err = {0};
    tp_store* s = NULL;
    ASSERT_EQ_INT(TP_OK, tp_store_open(path, &s, &err));
    tp_store_info si;
    tp_store_get_info(s, &si);
    EXPECT_TRUE(strstr(si.header.notes, "(marked per sample)") != NULL);
    const tp_tree_geometry* geo = &si.header.geometry;
    size_t count;
    const tp_node_meta* metas = tp_store_metas(s, &count);
    const int n = geo->n, side = (1 << n) + 1;
    const size_t samples = (size_t)side * side, words = tp_tree_block_words(n);
    const size_t fat = samples + tp_node_mask_words(n);
    uint16_t* block = malloc(words * sizeof *block);
    ASSERT_TRUE(block != NULL);
    size_t differ = 0, flagged_nodes = 0, bad_flags = 0, leaf_marked = 0;
    size_t flagged_by_scale[TP_TREE_MAX_SCALES] = {0};
    for (int64_t id = 0; id < (int64_t)count; id++) {
        int sc, c, r;
        tp_tree_node_locate(geo, id, &sc, &c, &r);
        memset(block, 0xAB, words * sizeof *block); /* the read must write the bits */
        ASSERT_EQ_INT(TP_OK, tp_store_read_node(s, id, block, words, &err));
        size_t here = 0;
        for (int j = 0; j < side; j++)
            for (int i = 0; i < side; i++) {
                const long x = ((long)c << (n + sc)) + ((long)i << sc);
                const long y = ((long)r << (n + sc)) + ((long)j << sc);
                const int want = x < g->width && y < g->height && g->filled[(size_t)y * g->width + x];
                const size_t k = (size_t)j * side + i;
                const int got = block[fat + (k >> 4)] >> (k & 15) & 1;
                differ += want != got;
                here += got;
                if (sc == 0 && got && i < side - 1 && j < side - 1)
                    leaf_marked++; /* each sample once: leaves share their last row and column */
            }
        const int has = (metas[id].flags & TP_NODE_HAS_FILLED) != 0;
        bad_flags += has != (here > 0);
        flagged_nodes += has;
        flagged_by_scale[sc] += has;
    }
    EXPECT_EQ_INT(0, (long long)differ);
    EXPECT_EQ_INT(0, (long long)bad_flags);
    /* the leaves' own rows and columns: all but the grid's last row and column, none filled */
    EXPECT_EQ_INT((long long)g->filled_samples, (long long)leaf_marked);
    EXPECT_TRUE(flagged_nodes > 0 && flagged_nodes < count);
    for (int sc = 0; sc < geo->scales; sc++)
        fprintf(stderr, "scale %d: %zu nodes with filled samples\n", sc, flagged_by_scale[sc]);
    EXPECT_TRUE(flagged_by_scale[1] > 0 && flagged_by_scale[2] > 0); /* coarser nodes too */
    fprintf(stderr, "%zu of %zu nodes hold filled samples (%zu samples)\n", flagged_nodes, count,
            g->filled_samples);

    /* tp_mosaic_read_rows_filled: the same flags, sample for sample */
    const char* paths[] = {F.holes};
    tp_mosaic_options mo = {.fill_max = TP_FILL_MAX_ANY};
    tp_mosaic* m = NULL;
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, &mo, &m, &err));
    float* z = malloc((size_t)F.w * 65 * sizeof *z);
    uint8_t* f = malloc((size_t)F.w * 65);
    ASSERT_TRUE(z && f);
    size_t fdiffer = 0;
    for (int y = 0; y < F.h; y += 65) {
        const int rows = F.h - y < 65 ? F.h - y : 65;
        ASSERT_EQ_INT(TP_OK, tp_mosaic_read_rows_filled(m, y, rows, z, (size_t)rows * F.w, f, &err));
        for (size_t i = 0; i < (size_t)rows * F.w; i++)
            fdiffer += (f[i] != 0) != (g->filled[(size_t)y * F.w + i] != 0);
    }
    EXPECT_EQ_INT(0, (long long)fdiffer);
    free(z), free(f), free(block);
    tp_mosaic_close(m);
    tp_store_close(s);
    tp_render_grid_destroy(g);
}

/* The file's bytes, read whole. */
static uint8_t* slurp(const char* path, size_t* size)
{
    FILE* fp = fopen(path, "rb");
    ASSERT_TRUE(fp != NULL);
    fseek(fp, 0, SEEK_END);
    *size = (size_t)ftell(fp);
    fseek(fp, 0, SEEK_SET);
    uint8_t* b = malloc(*size);
    ASSERT_TRUE(b != NULL);
    ASSERT_EQ_INT(1, (long long)fread(b, *size, 1, fp));
    fclose(fp);
    return b;
}
static void spill(const char* path, const uint8_t* b, size_t size)
{
    FILE* fp = fopen(path, "wb");
    ASSERT_TRUE(fp != NULL);
    ASSERT_EQ_INT(1, (long long)fwrite(b, size, 1, fp));
    fclose(fp);
}

/* A node whose filled table is damaged (its frame's size past the node, the node's and the
 * tables' checksums made to match, as a writer bug would leave it): that node fails, naming
 * the file and the node; the others read. */
TEST(damaged_filled_table_fails_naming_file_and_node)
{
    const char* path = filled_store();
    size_t size;
    uint8_t* b = slurp(path, &size);
    const uint32_t header_bytes = le32(b + 12);
    const uint64_t count = le64(b + 48);
    const uint64_t meta_at = (header_bytes + 7) & ~(uint64_t)7, loc_at = meta_at + 104 * count;
    int64_t victim = -1, other = -1;
    for (uint64_t id = 0; id < count && (victim < 0 || other < 0); id++) {
        if (b[meta_at + 104 * id + 16] & TP_NODE_HAS_FILLED)
            victim = victim < 0 ? (int64_t)id : victim;
        else
            other = other < 0 ? (int64_t)id : other;
    }
    ASSERT_TRUE(victim >= 0 && other >= 0);
    uint8_t* loc = b + loc_at + 24 * (uint64_t)victim;
    const uint64_t off = le64(loc);
    const uint32_t bytes = le32(loc + 8);
    put32(b + off + bytes - 4, bytes); /* the frame's size: more than the node holds */
    put32(loc + 12, crc32_ref(b + off, bytes));
    /* the location table's CRC32 in the footer, then the footer's own */
    uint8_t* foot = b + size - 56;
    put32(foot + 36, crc32_ref(b + loc_at, 24 * count));
    put32(foot + 44, crc32_ref(foot, 44));
    char bad[700];
    snprintf(bad, sizeof bad, "%s.damaged.tpt", F.holes);
    spill(bad, b, size);
    free(b);
    tp_error err = {0};
    tp_store* s = NULL;
    ASSERT_EQ_INT(TP_OK, tp_store_open(bad, &s, &err));
    const size_t words = tp_tree_block_words(4);
    uint16_t* block = malloc(words * sizeof *block);
    ASSERT_TRUE(block != NULL);
    EXPECT_EQ_INT(TP_ERR_BAD_DATA, tp_store_read_node(s, victim, block, words, &err));
    char node[64];
    snprintf(node, sizeof node, "node %lld (", (long long)victim);
    fprintf(stderr, "%s\n", err.message);
    EXPECT_TRUE(strstr(err.message, bad) != NULL);
    EXPECT_TRUE(strstr(err.message, node) != NULL);
    EXPECT_TRUE(strstr(err.message, "damaged filled table") != NULL);
    EXPECT_EQ_INT(TP_OK, tp_store_read_node(s, other, block, words, &err));
    free(block);
    tp_store_close(s);
}

/* A sound store of format 3 (before the filled bits): refused, saying to rebuild it. */
TEST(format_3_store_refused_rebuild_it)
{
    const char* path = filled_store();
    size_t size;
    uint8_t* b = slurp(path, &size);
    const uint32_t header_bytes = le32(b + 12);
    put32(b + 8, 3);
    put32(b + header_bytes - 4, crc32_ref(b, header_bytes - 4));
    char old[700];
    snprintf(old, sizeof old, "%s.v3.tpt", F.holes);
    spill(old, b, size);
    free(b);
    tp_error err = {0};
    tp_store* s = NULL;
    EXPECT_EQ_INT(TP_ERR_BAD_DATA, tp_store_open(old, &s, &err));
    EXPECT_TRUE(strstr(err.message, "written by an older terrapatch (format 3; this one reads "
                                    "format 4): rebuild it with terrapatch build") != NULL);
    fprintf(stderr, "%s\n", err.message);
}

/* Pixels of the filled-void tint (mix(ground, (0.85, 0.25, 0.75), 0.65), shaded): red and
 * blue well above green, which neither the hypsometric ground nor the sky has. */
static long tint_pixels(const char* png, long* total)
{
    int w, h;
    uint8_t* px = NULL;
    tp_error err = {0};
    ASSERT_EQ_INT(TP_OK, tp_image_read_rgba(png, &w, &h, &px, &err));
    long n = 0;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const uint8_t* p = px + 4 * i;
        n += p[0] > p[1] + 40 && p[2] > p[1] + 40;
    }
    *total = (long)w * h;
    free(px);
    return n;
}

/* The viewer tints a store's filled samples (the 100 x 90 hole, seen from above), and
 * --hide-filled draws them as ground. */
TEST(view_of_store_tints_filled_voids)
{
    const char* path = filled_store();
    const hole* q = &HOLES[3];
    const double e = F.gt[0] + (q->x + q->w / 2.0) * F.gt[1];
    const double nn = F.gt[3] + (q->y + q->h / 2.0) * F.gt[5];
    char cam[160], shot[2][700];
    snprintf(cam, sizeof cam, "%.3f,%.3f,14000,0,-90", e, nn);
    long tinted[2], total = 0;
    for (int hide = 0; hide < 2; hide++) {
        snprintf(shot[hide], sizeof shot[hide], "%s.view%d.png", F.holes, hide);
        const char* args[] = {"--headless", "--no-hud", "--size", "320x240", "--lod", "full",
                              "--camera", cam, "--screenshot", shot[hide], path,
                              hide ? "--hide-filled" : NULL, NULL};
        char err[4096];
        int code = tp_test_run_terrapatch("view", args, err, sizeof err);
        if (code != 0)
            fprintf(stderr, "%s", err);
        ASSERT_EQ_INT(0, code);
        tinted[hide] = tint_pixels(shot[hide], &total);
    }
    fprintf(stderr, "tinted pixels: %ld of %ld, with --hide-filled %ld\n", tinted[0], total,
            tinted[1]);
    /* the hole is 100 x 90 of about 9 x 8 km in a view about 16 km wide: a good part of it */
    EXPECT_TRUE(tinted[0] > total / 20);
    EXPECT_EQ_INT(0, tinted[1]);
}

#define TESTS(X)                                                                                   \
    X(store_marks_exactly_the_filled_samples)                                                      \
    X(damaged_filled_table_fails_naming_file_and_node)                                             \
    X(format_3_store_refused_rebuild_it)                                                           \
    X(view_of_store_tints_filled_voids)                                                            \
    X(interpolation_fills_holes_of_any_size)                                                       \
    X(fill_from_coarse_copy_beats_interpolation)                                                   \
    X(fill_max_still_caps)                                                                         \
    X(streamed_equals_in_memory_interpolated)                                                      \
    X(streamed_equals_in_memory_fill_from)                                                         \
    X(streamed_window_cap_leaves_tall_void)                                                        \
    X(build_fill_from_notes_and_bad_sources)                                                       \
    X(fill_from_in_feet_is_converted_to_metres)
TP_TEST_MAIN(TESTS)
