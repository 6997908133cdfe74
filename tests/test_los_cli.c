/*
 * test_los_cli.c - `terrapatch los` and `terrapatch viewshed` (app/commands/cmd_los.c, cmd_viewshed.c)
 * run as children, their outputs read back independently:
 *   - los over a ridge written here with GDAL (UTM 33N, integer heights: the store keeps them
 *     exactly): visible or not and by how much, worked out from the geometry; the obstruction's
 *     latitude/longitude by GDAL/PROJ here;
 *   - los on real pairs of N42E001 against the viewshed core's answer for the target's sample
 *     of the render grid (tp_render_grid_build, not the store);
 *   - viewshed: the GeoTIFF opened with GDAL has the render grid's georeference and agrees with
 *     tp_viewshed_compute run here on the same window;
 *   - bad input: outside the DEM, in a void, an unwritable output: exit 1, nothing written;
 *     no gnuplot: a clear message, and none of the outputs written (all or none);
 *   - los says every file it wrote; viewshed writes the format its -o names (GDAL reads each
 *     back: driver, georeference, values), and counts the disc of its radius.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"
#include "tp_io.h"

#include "tp_test_child.h"
#include "tp_test_gdal.h"
#include "tp_test_grid.h"
#include "tp_test_r3.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define RIDGE_E0 500000.0
#define RIDGE_N0 4700000.0
#define STEP_M 30.0

/* The test folder (tp_test_child.h). */
static const char* tmp_dir(void) { return tp_test_child_dir("los"); }

/* Runs `terrapatch los DEM --from A --to B [extra...] --json F`: exit status, JSON, stderr. */
static int run_los(const char* dem, const char* from, const char* to, const char* const* extra,
                   char* json, size_t json_cap, char* err, size_t err_cap)
{
    char out[256];
    snprintf(out, sizeof out, "%s/los.json", tmp_dir());
    remove(out);
    const char* args[24] = {dem, "--from", from, "--to", to, "--json", out};
    int n = 7;
    for (int i = 0; extra && extra[i]; ++i)
        args[n++] = extra[i];
    args[n] = NULL;
    int rc = tp_test_run_terrapatch("los", args, err, err_cap);
    json[0] = '\0';
    if (access(out, F_OK) == 0)
        tp_test_read_text(out, json, json_cap);
    return rc;
}

static char* utm33_wkt(void)
{
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    ASSERT_TRUE(OSRImportFromEPSG(srs, 32633) == OGRERR_NONE);
    char* wkt = NULL;
    OSRExportToWkt(srs, &wkt);
    OSRDestroySpatialReference(srs);
    return wkt;
}

/* 101 x 21 posts 30 m apart at 1000 m, a tent ridge across the rows at column 50: 10 m at the
 * crest, 2 m lower per post to the foot 5 posts away (integers, stored exactly). */
static void write_ridge(const char* path)
{
    const int w = 101, h = 21;
    GDALAllRegister();
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path, w, h, 1, GDT_Float32, NULL);
    ASSERT_TRUE(ds != NULL);
    double gt[6] = {RIDGE_E0, STEP_M, 0, RIDGE_N0, 0, -STEP_M};
    GDALSetGeoTransform(ds, gt);
    char* wkt = utm33_wkt();
    GDALSetProjection(ds, wkt);
    CPLFree(wkt);
    float* z = malloc(sizeof(float) * (size_t)w * h);
    ASSERT_TRUE(z != NULL);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c)
            z[(size_t)r * w + c] = (float)(1000.0 + fmax(0.0, 10.0 - 2.0 * abs(c - 50)));
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, w, h, z, w, h,
                             GDT_Float32, 0, 0) == CE_None);
    free(z);
    GDALClose(ds);
}

/* "33n E N" of the post (c, r) of the ridge DEM. */
static void ridge_post(int c, int r, char* out, size_t cap)
{
    snprintf(out, cap, "33n %.3f %.3f", RIDGE_E0 + (c + 0.5) * STEP_M,
             RIDGE_N0 - (r + 0.5) * STEP_M);
}

/* Observer on column 10, target on column 90 of row 10, flat earth: the line passes the crest
 * (column 50, halfway) at 1000 + (2 + t) / 2, so a target t m up is hidden by
 * 10 - (2 + t) / 2 m at 1200 m while t < 18. */
TEST(ridge_pairs_worked_out_by_hand)
{
    char dem[256], from[64], to[64], json[8192], err[2048];
    snprintf(dem, sizeof dem, "%s/ridge.tif", tmp_dir());
    write_ridge(dem);
    ridge_post(10, 10, from, sizeof from);
    ridge_post(90, 10, to, sizeof to);
    const char* heights[] = {"0", "10", "16", "18", "25"};
    for (size_t i = 0; i < sizeof heights / sizeof heights[0]; ++i) {
        const double t = atof(heights[i]);
        const char* extra[] = {"--curvature-coeff", "0", "--to-height", heights[i], NULL};
        ASSERT_EQ_INT(0, run_los(dem, from, to, extra, json, sizeof json, err, sizeof err));
        EXPECT_NEAR(tp_test_json_number_after(json, NULL, "distance_m"), 2400.0, 1e-6);
        EXPECT_NEAR(tp_test_json_number_after(json, "\"from\"", "eye_m"), 1002.0, 1e-6);
        const double blocking = 10.0 - (2.0 + t) / 2.0;
        if (blocking > 0.0) {
            EXPECT_CONTAINS(json, "\"visible\": false");
            EXPECT_NEAR(tp_test_json_number_after(json, "\"obstruction\"", "distance_m"), 1200.0, 1e-3);
            EXPECT_NEAR(tp_test_json_number_after(json, "\"obstruction\"", "blocking_m"), blocking, 1e-3);
            EXPECT_NEAR(tp_test_json_number_after(json, NULL, "min_clearance_m"), -blocking, 1e-3);
            /* where: the crest post of row 10, by PROJ here */
            double lat, lon;
            char* wkt = utm33_wkt();
            tp_test_gdal_lat_lon(wkt, RIDGE_E0 + 50.5 * STEP_M, RIDGE_N0 - 10.5 * STEP_M, &lat,
                                 &lon);
            CPLFree(wkt);
            EXPECT_NEAR(tp_test_json_number_after(json, "\"obstruction\"", "lat"), lat, 1e-7);
            EXPECT_NEAR(tp_test_json_number_after(json, "\"obstruction\"", "lon"), lon, 1e-7);
        } else {
            EXPECT_CONTAINS(json, "\"visible\": true");
            EXPECT_CONTAINS(json, "\"obstruction\": null");
            /* the smallest clearance: at the crest, or one post from the observer */
            const double expect = fmin(-blocking, 2.0 + (t - 2.0) / 80.0);
            EXPECT_NEAR(tp_test_json_number_after(json, NULL, "min_clearance_m"), expect, 1e-3);
        }
    }
    /* the default curvature: a 0.85714 / (2 R) * d^2 drop, 0.39 m at the target, 0.1 m at
     * the crest: the line there is lower by 0.1 - 0.39 / 2, i.e. higher by 0.097 m */
    const char* extra[] = {"--to-height", "16", NULL};
    ASSERT_EQ_INT(0, run_los(dem, from, to, extra, json, sizeof json, err, sizeof err));
    const double k = 0.85714 / (2.0 * 6378137.0);
    const double line = 1000.0 + 9.0 - k * 2400.0 * 2400.0 / 2.0 + k * 1200.0 * 1200.0;
    EXPECT_NEAR(tp_test_json_number_after(json, "\"obstruction\"", "blocking_m"), 1010.0 - line, 1e-3);
}

/* The profile: CSV rows and a PNG from gnuplot; without gnuplot a clear message, exit 1, and
 * neither the JSON nor the CSV written (all or none: an older CSV as it was). */
TEST(profile_csv_and_png)
{
    char dem[256], from[64], to[64], json[8192], err[4096], csv[256], png[256];
    snprintf(dem, sizeof dem, "%s/ridge.tif", tmp_dir());
    write_ridge(dem);
    ridge_post(10, 10, from, sizeof from);
    ridge_post(90, 10, to, sizeof to);
    snprintf(csv, sizeof csv, "%s/p.csv", tmp_dir());
    snprintf(png, sizeof png, "%s/p.png", tmp_dir());
    remove(png);
    const char* extra[] = {"--csv", csv, "--profile", png, NULL};
    ASSERT_EQ_INT(0, run_los(dem, from, to, extra, json, sizeof json, err, sizeof err));
    char text[200000];
    tp_test_read_text(csv, text, sizeof text);
    EXPECT_TRUE(!strncmp(text, "distance_m,lat,lon,ground_m,line_m,clearance_m,blocks\n", 54));
    int rows = 0;
    for (const char* p = text; *p; ++p)
        rows += *p == '\n';
    EXPECT_EQ_INT(1 + 321, rows); /* 80 posts every quarter post, both ends */
    EXPECT_CONTAINS(text, "\n1200.000,"); /* the crest's sample */
    FILE* f = fopen(png, "rb");
    ASSERT_TRUE(f != NULL);
    unsigned char sig[8];
    EXPECT_EQ_INT(8, (int)fread(sig, 1, 8, f));
    fclose(f);
    EXPECT_TRUE(!memcmp(sig, "\x89PNG\r\n\x1a\n", 8));

    remove(png);
    FILE* old = fopen(csv, "w");
    ASSERT_TRUE(old != NULL);
    fputs("older\n", old);
    fclose(old);
    const char* path = getenv("PATH");
    char saved[4096];
    snprintf(saved, sizeof saved, "%s", path ? path : "/usr/bin:/bin");
    setenv("PATH", "/nonexistent", 1);
    int rc = run_los(dem, from, to, extra, json, sizeof json, err, sizeof err);
    setenv("PATH", saved, 1);
    EXPECT_EQ_INT(1, rc);
    EXPECT_CONTAINS(err, "cannot run gnuplot");
    EXPECT_CONTAINS(err, "p.png");
    /* all or none: neither the JSON nor the CSV without the plot, the older CSV as it was */
    EXPECT_CONTAINS(err, "written (all or none");
    EXPECT_EQ_INT(0, (int)strlen(json));
    EXPECT_TRUE(access(png, F_OK) != 0);
    tp_test_read_text(csv, text, sizeof text);
    EXPECT_EQ_STR("older\n", text);
}

/* Every file los writes is named on stderr, once: the JSON and CSV as well as the plot. */
TEST(los_says_every_file_it_wrote)
{
    char dem[256], from[64], to[64], json[8192], err[4096], csv[256], png[256], line[400];
    snprintf(dem, sizeof dem, "%s/ridge.tif", tmp_dir());
    write_ridge(dem);
    ridge_post(10, 10, from, sizeof from);
    ridge_post(90, 10, to, sizeof to);
    snprintf(csv, sizeof csv, "%s/w.csv", tmp_dir());
    snprintf(png, sizeof png, "%s/w.png", tmp_dir());
    const char* extra[] = {"--csv", csv, "--profile", png, NULL};
    ASSERT_EQ_INT(0, run_los(dem, from, to, extra, json, sizeof json, err, sizeof err));
    const char* files[] = {"los.json", "w.csv", "w.png"};
    for (int i = 0; i < 3; ++i) {
        snprintf(line, sizeof line, "terrapatch los: wrote %s/%s\n", tmp_dir(), files[i]);
        EXPECT_CONTAINS(err, line);
        EXPECT_TRUE(!strstr(err, line) || !strstr(strstr(err, line) + strlen(line), line));
        snprintf(line, sizeof line, "%s/%s", tmp_dir(), files[i]);
        EXPECT_EQ_INT(0, access(line, F_OK));
    }
}

/* ---- real ground ---- */

static tp_render_grid* n42_grid(char* path, size_t cap)
{
    return tp_test_render_grid("N42E001.hgt", path, cap);
}

static void post_lat_lon(const tp_render_grid* g, int c, int r, char* out, size_t cap)
{
    double lat, lon;
    tp_test_gdal_lat_lon(g->crs_wkt, g->geotransform[0] + (c + 0.5) * g->geotransform[1],
                         g->geotransform[3] + (r + 0.5) * g->geotransform[5], &lat, &lon);
    snprintf(out, cap, "%.12f,%.12f", lat, lon);
}

/* Exact visibility (R3, tp_test_r3.h) on the render grid, as in test_los.c: lines within one
 * post of either end not tested. The smallest clearance (negative: hidden). */
static double r3_clearance(const float* z, int w, const double gt[6], int ox, int oy, int tx,
                           int ty, const tp_los_options* o)
{
    const tp_test_r3 r3 = {o->observer_height_m, o->target_height_m, o->curvature_coeff,
                           6378137.0, 1};
    return tp_test_r3_clearance(z, w, gt, ox, oy, tx, ty, &r3);
}

/* From the centre of N42E001's render grid to 40 posts within 15 km (half of them near samples
 * the viewshed core sees), through the store (quantised to 1/16 m) and its full-resolution
 * surface: seen or not as the exact ray test (R3, on the render grid built here) says, up to
 * grazing pairs (the store's rounding, its triangulated cells). Against the viewshed core's
 * value for the target's sample: these pairs, chosen near seen samples, are where its
 * interpolated horizons (XDraw) err; R3 must side with los where the two differ. */
TEST(real_pairs_agree_with_the_viewshed_core)
{
    char path[1024], from[64], to[64], json[8192], err[2048];
    tp_render_grid* g = n42_grid(path, sizeof path);
    const int w = g->width, h = g->height, ox = w / 2, oy = h / 2;
    const size_t n = (size_t)w * h;
    uint8_t* vs = malloc(n);
    tp_viewshed_options vo = tp_viewshed_options_default();
    tp_error e;
    memset(&e, 0, sizeof e);
    ASSERT_OK(tp_viewshed_compute(g->heights, n, w, h, g->geotransform, ox, oy, &vo, vs, n, &e));
    post_lat_lon(g, ox, oy, from, sizeof from);
    unsigned seed = 777u;
    int pairs = 0, agree = 0, seen = 0, agree_r3 = 0, differ = 0, r3_sides_with_los = 0;
    const int rpx = (int)(15000.0 / g->geotransform[1]);
    while (pairs < 40) {
        seed = seed * 1103515245u + 12345u;
        int tx = ox - rpx + (int)((seed >> 8) % (unsigned)(2 * rpx + 1));
        seed = seed * 1103515245u + 12345u;
        int ty = oy - rpx + (int)((seed >> 8) % (unsigned)(2 * rpx + 1));
        /* half the pairs among the seen samples, or there would be few */
        if (pairs % 2 == 0) {
            int found = 0;
            for (int k = 0; k < 4 * rpx && !found; ++k) {
                int x = tx + k % 7 - 3, y = ty + k / 7 - 3;
                if (x >= 0 && y >= 0 && x < w && y < h && vs[(size_t)y * w + x]) {
                    tx = x, ty = y, found = 1;
                }
            }
            if (!found)
                continue;
        }
        if (tx < 0 || ty < 0 || tx >= w || ty >= h || (abs(tx - ox) <= 1 && abs(ty - oy) <= 1))
            continue;
        if (g->heights[(size_t)ty * w + tx] != g->heights[(size_t)ty * w + tx])
            continue;
        post_lat_lon(g, tx, ty, to, sizeof to);
        ASSERT_EQ_INT(0, run_los(path, from, to, NULL, json, sizeof json, err, sizeof err));
        const int visible = strstr(json, "\"visible\": true") != NULL;
        const int core = vs[(size_t)ty * w + tx] == TP_VIEWSHED_VISIBLE;
        tp_los_options lo = tp_los_options_default();
        const int r3 = r3_clearance(g->heights, w, g->geotransform, ox, oy, tx, ty, &lo) >= 0.0;
        seen += core;
        agree += visible == core;
        agree_r3 += visible == r3;
        if (visible != core) {
            differ++;
            r3_sides_with_los += visible == r3;
        }
        pairs++;
    }
    tp_test_note("N42E001 centre: terrapatch los agrees with R3 on the render grid on %d of %d "
                 "pairs, with the viewshed core on %d (%d seen by the core); where it differs "
                 "from the core, R3 sides with los on %d of %d",
                 agree_r3, pairs, agree, seen, r3_sides_with_los, differ);
    EXPECT_GE_INT(seen, 15);
    EXPECT_GE_INT(agree_r3, 38);
    EXPECT_GE_INT(agree, 30);
    EXPECT_GE_INT(r3_sides_with_los, differ - 1);
    free(vs);
    tp_render_grid_destroy(g);
}

/* ---- viewshed ---- */

static int run_viewshed(const char* dem, const char* observer, const char* out,
                        const char* const* extra, char* err, size_t cap)
{
    const char* args[16] = {dem, "--observer", observer, "-o", out};
    int n = 5;
    for (int i = 0; extra && extra[i]; ++i)
        args[n++] = extra[i];
    args[n] = NULL;
    return tp_test_run_terrapatch("viewshed", args, err, cap);
}

TEST(viewshed_geotiff_has_the_grid_georeference_and_the_core_values)
{
    char path[1024], obs[64], out[256], err[2048];
    tp_render_grid* g = n42_grid(path, sizeof path);
    const int w = g->width, h = g->height;
    const int ox = w / 3, oy = h / 2;
    post_lat_lon(g, ox, oy, obs, sizeof obs);
    snprintf(out, sizeof out, "%s/seen.tif", tmp_dir());
    const char* extra[] = {"--radius", "10000", "--observer-height", "10", NULL};
    ASSERT_EQ_INT(0, run_viewshed(path, obs, out, extra, err, sizeof err));

    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(out, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    double gt[6];
    ASSERT_TRUE(GDALGetGeoTransform(ds, gt) == CE_None);
    const int vw = GDALGetRasterXSize(ds), vh = GDALGetRasterYSize(ds);
    /* the window the radius reaches: floor(10000 / post) posts either side */
    const int r = (int)floor(10000.0 / g->geotransform[1]);
    EXPECT_EQ_INT(2 * r + 1, vw);
    EXPECT_EQ_INT(2 * r + 1, vh);
    EXPECT_NEAR(gt[1], g->geotransform[1], 1e-9);
    EXPECT_NEAR(gt[5], g->geotransform[5], 1e-9);
    EXPECT_NEAR(gt[0], g->geotransform[0] + (ox - r) * g->geotransform[1], 1e-6);
    EXPECT_NEAR(gt[3], g->geotransform[3] + (oy - r) * g->geotransform[5], 1e-6);
    OGRSpatialReferenceH a = OSRNewSpatialReference(GDALGetProjectionRef(ds));
    OGRSpatialReferenceH b = OSRNewSpatialReference(g->crs_wkt);
    EXPECT_TRUE(OSRIsSame(a, b));
    OSRDestroySpatialReference(a);
    OSRDestroySpatialReference(b);
    uint8_t* got = malloc((size_t)vw * vh);
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, vw, vh, got, vw, vh,
                             GDT_Byte, 0, 0) == CE_None);
    GDALClose(ds);

    /* the core on the same window of the render grid built here */
    float* z = malloc(sizeof(float) * (size_t)vw * vh);
    for (int y = 0; y < vh; ++y)
        for (int x = 0; x < vw; ++x)
            z[(size_t)y * vw + x] = g->heights[(size_t)(oy - r + y) * w + (ox - r + x)];
    uint8_t* want = malloc((size_t)vw * vh);
    tp_viewshed_options vo = tp_viewshed_options_default();
    vo.radius_m = 10000.0;
    vo.observer_height_m = 10.0;
    tp_error e;
    memset(&e, 0, sizeof e);
    ASSERT_OK(tp_viewshed_compute(z, (size_t)vw * vh, vw, vh, gt, r, r, &vo, want,
                                  (size_t)vw * vh, &e));
    size_t same = 0, seen = 0, outside_seen = 0;
    for (int y = 0; y < vh; ++y)
        for (int x = 0; x < vw; ++x) {
            size_t i = (size_t)y * vw + x;
            same += got[i] == want[i];
            seen += got[i] == 255;
            if (hypot((x - r) * gt[1], (y - r) * gt[5]) > 10000.0)
                outside_seen += got[i] != 0;
        }
    tp_test_note("viewshed GeoTIFF %dx%d: %zu seen; agrees with tp_viewshed_compute on the "
                 "render grid here on %.3f%% (the store keeps the warped heights to 1/16 m)",
                 vw, vh, seen, 100.0 * same / ((double)vw * vh));
    EXPECT_GT(seen, 1000);
    EXPECT_EQ_INT(0, (int)outside_seen);
    EXPECT_GE((double)same / ((double)vw * vh), 0.995);
    free(z);
    free(want);
    free(got);
    tp_render_grid_destroy(g);
}

/* An observer who sees everything (an eye 20 km up) is told so: the disc of the radius is what
 * is counted, every post of the window within the radius with a height, worked out here on the
 * render grid, not the window's square (pi / 4 of which is the disc). */
TEST(viewshed_counts_the_disc_of_its_radius)
{
    char path[1024], obs[64], out[256], err[4096], text[4096];
    tp_render_grid* g = n42_grid(path, sizeof path);
    const int ox = g->width / 2, oy = g->height / 2;
    post_lat_lon(g, ox, oy, obs, sizeof obs);
    snprintf(out, sizeof out, "%s/all.tif", tmp_dir());
    const char* args[] = {path,   "--observer",        obs,     "-o", out, "--radius",
                          "3000", "--observer-height", "20000", NULL};
    ASSERT_EQ_INT(0,
                  tp_test_run_terrapatch_out("viewshed", args, text, sizeof text, err, sizeof err));
    const double* gt = g->geotransform;
    size_t disc = 0;
    for (int y = 0; y < g->height; ++y)
        for (int x = 0; x < g->width; ++x) {
            const double dx = (x - ox) * gt[1], dy = (y - oy) * gt[5];
            const float z = g->heights[(size_t)y * g->width + x];
            disc += dx * dx + dy * dy <= 3000.0 * 3000.0 && z == z;
        }
    tp_test_note("%zu posts with a height within 3 km: %s", disc, strstr(text, "seen"));
    char want[160];
    snprintf(want, sizeof want,
             "seen       %zu of %zu posts with a height within the radius "
             "(100.0%%)\n",
             disc, disc);
    EXPECT_CONTAINS(text, want);
    tp_render_grid_destroy(g);
}

/* -o names the format: each raster format viewshed writes, read back by GDAL (its driver, the
 * render grid's georeference and CRS, the values of the GeoTIFF the same run writes); a JPEG is
 * refused (lossy) before any work, with the list of formats, and nothing is written. */
TEST(viewshed_writes_the_format_its_extension_names)
{
    char path[1024], obs[64], out[256], err[4096];
    tp_render_grid* g = n42_grid(path, sizeof path);
    const int ox = g->width / 3, oy = g->height / 2;
    post_lat_lon(g, ox, oy, obs, sizeof obs);
    const char* extra[] = {"--radius", "4000", NULL};
    snprintf(out, sizeof out, "%s/fmt.tif", tmp_dir());
    ASSERT_EQ_INT(0, run_viewshed(path, obs, out, extra, err, sizeof err));
    GDALAllRegister();
    GDALDatasetH ref = GDALOpen(out, GA_ReadOnly);
    ASSERT_TRUE(ref != NULL);
    const int w = GDALGetRasterXSize(ref), h = GDALGetRasterYSize(ref);
    double ref_gt[6];
    ASSERT_TRUE(GDALGetGeoTransform(ref, ref_gt) == CE_None);
    EXPECT_NEAR(g->geotransform[1], ref_gt[1], 1e-9);
    uint8_t* want = malloc((size_t)w * h);
    uint8_t* got = malloc((size_t)w * h);
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ref, 1), GF_Read, 0, 0, w, h, want, w, h, GDT_Byte,
                             0, 0) == CE_None);
    GDALClose(ref);
    size_t seen = 0;
    for (size_t i = 0; i < (size_t)w * h; ++i)
        seen += want[i] == 255;
    EXPECT_GT(seen, 100);

    static const struct {
        const char* name;
        const char* driver;
    } formats[] = {{"fmt.png", "PNG"},         {"FMT.PNG", "PNG"},   {"fmt.gpkg", "GPKG"},
                   {"fmt.jp2", "JP2OpenJPEG"}, {"fmt.img", "HFA"},   {"fmt.asc", "AAIGrid"},
                   {"fmt.bmp", "BMP"},         {"fmt.tiff", "GTiff"}};
    OGRSpatialReferenceH grid_srs = OSRNewSpatialReference(g->crs_wkt);
    for (size_t k = 0; k < sizeof formats / sizeof formats[0]; ++k) {
        snprintf(out, sizeof out, "%s/%s", tmp_dir(), formats[k].name);
        if (!GDALGetDriverByName(formats[k].driver)) {
            tp_test_note("GDAL has no %s driver here: %s not tried", formats[k].driver,
                         formats[k].name);
            continue;
        }
        EXPECT_EQ_INT(0, run_viewshed(path, obs, out, extra, err, sizeof err));
        GDALDatasetH ds = GDALOpen(out, GA_ReadOnly);
        ASSERT_TRUE(ds != NULL);
        EXPECT_EQ_STR(formats[k].driver, GDALGetDriverShortName(GDALGetDatasetDriver(ds)));
        EXPECT_EQ_INT(w, GDALGetRasterXSize(ds));
        EXPECT_EQ_INT(h, GDALGetRasterYSize(ds));
        double gt[6];
        EXPECT_TRUE(GDALGetGeoTransform(ds, gt) == CE_None);
        for (int i = 0; i < 6; ++i)
            EXPECT_NEAR(ref_gt[i], gt[i], 1e-6);
        OGRSpatialReferenceH srs = OSRNewSpatialReference(GDALGetProjectionRef(ds));
        EXPECT_TRUE(OSRIsSame(srs, grid_srs));
        OSRDestroySpatialReference(srs);
        memset(got, 1, (size_t)w * h);
        EXPECT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, w, h, got, w, h, GDT_Byte,
                                 0, 0) == CE_None);
        size_t differ = 0;
        for (size_t i = 0; i < (size_t)w * h; ++i)
            differ += got[i] != want[i];
        tp_test_note("%s: %s, %zu of %d values differ", formats[k].name, formats[k].driver, differ,
                     w * h);
        EXPECT_EQ_INT(0, (int)differ);
        GDALClose(ds);
    }
    OSRDestroySpatialReference(grid_srs);

    snprintf(out, sizeof out, "%s/lossy.jpg", tmp_dir());
    EXPECT_EQ_INT(2, run_viewshed(path, obs, out, extra, err, sizeof err));
    EXPECT_CONTAINS(err, "lossy.jpg: JPEG is lossy");
    EXPECT_CONTAINS(err, "viewshed writes GeoTIFF (.tif, .tiff), PNG (.png)");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "lossy"));
    free(want);
    free(got);
    tp_render_grid_destroy(g);
}

/* A nodata post of the render grid whose 5x5 neighbourhood is nodata too (the collar the warp
 * leaves around the tile), as "LAT,LON". */
static void void_post(const tp_render_grid* g, char* out, size_t cap)
{
    for (int r = 2; r < g->height - 2; ++r)
        for (int c = 2; c < g->width - 2; ++c) {
            int all = 1;
            for (int dy = -2; dy <= 2 && all; ++dy)
                for (int dx = -2; dx <= 2 && all; ++dx) {
                    float v = g->heights[(size_t)(r + dy) * g->width + c + dx];
                    all = v != v;
                }
            if (all) {
                post_lat_lon(g, c, r, out, cap);
                return;
            }
        }
    FAIL("no void post in N42E001's render grid");
}

TEST(viewshed_bad_input_exits_1_and_writes_nothing)
{
    char path[1024], out[256], err[2048], hole[64];
    tp_render_grid* g = n42_grid(path, sizeof path);
    void_post(g, hole, sizeof hole);
    tp_render_grid_destroy(g);
    snprintf(out, sizeof out, "%s/bad.tif", tmp_dir());
    /* outside: a degree south of the tile */
    EXPECT_EQ_INT(1, run_viewshed(path, "41.5,1.5", out, NULL, err, sizeof err));
    EXPECT_CONTAINS(err, "outside the DEM");
    EXPECT_CONTAINS(err, "N42E001.hgt");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "bad.tif"));
    /* an output folder that does not exist */
    EXPECT_EQ_INT(1, run_viewshed(path, "42.5,1.5", "/nonexistent/dir/x.tif", NULL, err,
                                  sizeof err));
    EXPECT_CONTAINS(err, "/nonexistent/dir");
    /* in a void */
    EXPECT_EQ_INT(1, run_viewshed(path, hole, out, NULL, err, sizeof err));
    EXPECT_CONTAINS(err, "in a void");
    EXPECT_CONTAINS(err, hole);
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "bad.tif"));
    /* los: the same refusals, no JSON */
    char json[256];
    EXPECT_EQ_INT(1, run_los(path, "42.5,1.5", "41.5,1.5", NULL, json, sizeof json, err,
                             sizeof err));
    EXPECT_CONTAINS(err, "'41.5,1.5'");
    EXPECT_EQ_INT(0, (int)strlen(json));
    EXPECT_EQ_INT(1, run_los(path, hole, "42.5,1.5", NULL, json, sizeof json, err, sizeof err));
    EXPECT_CONTAINS(err, "in a void");
    EXPECT_EQ_INT(0, (int)strlen(json));
}

#define TESTS(X)                                                                                   \
    X(ridge_pairs_worked_out_by_hand)                                                              \
    X(profile_csv_and_png)                                                                         \
    X(real_pairs_agree_with_the_viewshed_core)                                                     \
    X(viewshed_geotiff_has_the_grid_georeference_and_the_core_values)                              \
    X(viewshed_bad_input_exits_1_and_writes_nothing)                                               \
    X(los_says_every_file_it_wrote)                                                                \
    X(viewshed_counts_the_disc_of_its_radius)                                                      \
    X(viewshed_writes_the_format_its_extension_names)
TP_TEST_MAIN(TESTS)
