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

#define TESTS(X)                                                                                   \
    X(interpolation_fills_holes_of_any_size)                                                       \
    X(fill_from_coarse_copy_beats_interpolation)                                                   \
    X(fill_max_still_caps)                                                                         \
    X(streamed_equals_in_memory_interpolated)                                                      \
    X(streamed_equals_in_memory_fill_from)                                                         \
    X(streamed_window_cap_leaves_tall_void)                                                        \
    X(build_fill_from_notes_and_bad_sources)
TP_TEST_MAIN(TESTS)
