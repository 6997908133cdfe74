/*
 * test_point.c - `terrapatch point` (app/commands/cmd_point.c over app/scene/ground.c) run as a child, its
 * JSON read back, against values computed here independently:
 *   - heights at grid posts of a real DEM read with GDAL's C API (Mt Hood, NAD83 / UTM 10N:
 *     the store keeps the DEM's own grid, Int16 heights in 1 m steps, so exactly the sample);
 *     the position is the post's centre turned into latitude/longitude by GDAL/PROJ here;
 *   - a warped DEM (N42E001.hgt): the height at a source post lies within the range of the
 *     source posts around it;
 *   - slope and aspect on synthetic planes written here with GDAL (known gradient: slope
 *     atan|g|, aspect the bearing of -g), convergence by the spherical formula;
 *   - positions outside the DEM and in a void (the DEM's nodata collar; a synthetic hole too
 *     large to be filled): exit 1, one message naming the file and the position.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"
#include "tp_io.h"

#include "tp_test_child.h"
#include "tp_test_gdal.h"

#include <gdal.h>
#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define DEG (180.0 / 3.14159265358979323846)
#define HOOD "lf_elev_220_mt_hood_utm.tif"
#define HOOD_NODATA 32767

/* ---- helpers ---- */

/* The test folder (tp_test_child.h). */
static const char* tmp_dir(void) { return tp_test_child_dir("point"); }

/* Runs `terrapatch point DEM POS --json F`; returns the exit status, the JSON in json (on 0)
 * and stderr in err. */
static int run_point(const char* dem, const char* pos, char* json, size_t json_cap, char* err,
                     size_t err_cap)
{
    char out[256];
    snprintf(out, sizeof out, "%s/point.json", tmp_dir());
    remove(out);
    const char* args[] = {dem, pos, "--json", out, NULL};
    int rc = tp_test_run_terrapatch("point", args, err, err_cap);
    if (rc == 0)
        tp_test_read_text(out, json, json_cap);
    else
        EXPECT_TRUE(access(out, F_OK) != 0); /* nothing written on failure */
    return rc;
}

/* Latitude, longitude of (e, n) in the CRS of ds, by GDAL/PROJ. */
static void to_lat_lon(GDALDatasetH ds, double e, double n, double* lat, double* lon)
{
    tp_test_gdal_lat_lon(GDALGetProjectionRef(ds), e, n, lat, lon);
}

static double sample(GDALDatasetH ds, int c, int r)
{
    float v;
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, c, r, 1, 1, &v, 1, 1,
                             GDT_Float32, 0, 0) == CE_None);
    return v;
}

static GDALDatasetH open_shared(const char* file, char* path, size_t cap)
{
    if (!tp_test_data_path(path, cap, "TP_SHARED_DATA_DIR", file))
        SKIP("%s not found (set TP_SHARED_DATA_DIR)", file);
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    return ds;
}

/* ---- heights at posts ---- */

TEST(post_height_equals_gdal_sample)
{
    char path[1024], json[8192], err[2048], pos[128];
    GDALDatasetH ds = open_shared(HOOD, path, sizeof path);
    double gt[6];
    ASSERT_TRUE(GDALGetGeoTransform(ds, gt) == CE_None);
    const int posts[][2] = {{501, 400}, {100, 100}, {900, 700}, {37, 612}, {640, 33}};
    int checked = 0;
    for (size_t i = 0; i < sizeof posts / sizeof posts[0]; ++i) {
        int c = posts[i][0], r = posts[i][1];
        double want = sample(ds, c, r);
        if (want == HOOD_NODATA)
            continue;
        double lat, lon;
        to_lat_lon(ds, gt[0] + (c + 0.5) * gt[1], gt[3] + (r + 0.5) * gt[5], &lat, &lon);
        snprintf(pos, sizeof pos, "%.17g,%.17g", lat, lon);
        ASSERT_EQ_INT(0, run_point(path, pos, json, sizeof json, err, sizeof err));
        EXPECT_NEAR(tp_test_json_number_after(json, NULL, "x"), c, 1e-4);
        EXPECT_NEAR(tp_test_json_number_after(json, NULL, "y"), r, 1e-4);
        /* the post itself, up to the round trip through latitude/longitude (micrometres):
         * its neighbours differ by metres, the store's step is 1 m */
        EXPECT_NEAR(tp_test_json_number_after(json, NULL, "elevation_m"), want, 1e-3);
        EXPECT_NEAR(tp_test_json_number_after(json, NULL, "lat_deg"), lat, 1e-12);
        ++checked;
    }
    EXPECT_GE_INT(checked, 4);
    GDALClose(ds);
}

/* The .hgt is warped to UTM 31N: a source post is not a render post, but the surface there
 * stays within the range of the 3x3 source posts around it. */
TEST(warped_dem_height_within_source_neighbourhood)
{
    char path[1024], json[8192], err[2048], pos[128];
    GDALDatasetH ds = open_shared("N42E001.hgt", path, sizeof path);
    const int posts[][2] = {{600, 600}, {200, 900}, {1000, 300}};
    for (size_t i = 0; i < 3; ++i) {
        int c = posts[i][0], r = posts[i][1];
        double lo = INFINITY, hi = -INFINITY;
        for (int dy = -1; dy <= 1; ++dy)
            for (int dx = -1; dx <= 1; ++dx) {
                double v = sample(ds, c + dx, r + dy);
                lo = fmin(lo, v);
                hi = fmax(hi, v);
            }
        /* SRTM3: posts at 43 - r/1200 N, 1 + c/1200 E (pixel-is-point) */
        snprintf(pos, sizeof pos, "%.10f %.10f", 43.0 - r / 1200.0, 1.0 + c / 1200.0);
        ASSERT_EQ_INT(0, run_point(path, pos, json, sizeof json, err, sizeof err));
        double h = tp_test_json_number_after(json, NULL, "elevation_m");
        EXPECT_TRUE(h >= lo - 0.5 && h <= hi + 0.5);
        if (!(h >= lo - 0.5 && h <= hi + 0.5))
            tp_test_note("post (%d, %d): %g not in [%g, %g]", c, r, h, lo, hi);
    }
    GDALClose(ds);
}

/* ---- slope and aspect on planes ---- */

#define PLANE_W 64
#define PLANE_H 48
#define PLANE_STEP_M 10.0
#define PLANE_E0 500000.0
#define PLANE_N0 4650000.0

/* Writes a GeoTIFF (WGS 84 / UTM 33N, 10 m posts, north-up) of z = 1000 + a (E - E0) +
 * b (N - N0), with a hole of hole x hole posts of nodata in the middle when hole > 0. */
static const char* g_plane_crs = "EPSG:32633"; /* what write_plane tags the plane with */

static void write_plane(const char* path, double a, double b, int w, int h, int hole)
{
    GDALAllRegister();
    GDALDriverH drv = GDALGetDriverByName("GTiff");
    ASSERT_TRUE(drv != NULL);
    GDALDatasetH ds = GDALCreate(drv, path, w, h, 1, GDT_Float32, NULL);
    ASSERT_TRUE(ds != NULL);
    double gt[6] = {PLANE_E0, PLANE_STEP_M, 0, PLANE_N0, 0, -PLANE_STEP_M};
    GDALSetGeoTransform(ds, gt);
    if (g_plane_crs[0]) { /* "": no CRS at all */
        OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
        ASSERT_TRUE(OSRSetFromUserInput(srs, g_plane_crs) == OGRERR_NONE);
        char* wkt = NULL;
        OSRExportToWkt(srs, &wkt);
        GDALSetProjection(ds, wkt);
        CPLFree(wkt);
        OSRDestroySpatialReference(srs);
    }
    GDALRasterBandH band = GDALGetRasterBand(ds, 1);
    GDALSetRasterNoDataValue(band, -9999.0);
    float* z = malloc(sizeof(float) * (size_t)w * (size_t)h);
    ASSERT_TRUE(z != NULL);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            double e = gt[0] + (c + 0.5) * gt[1], n = gt[3] + (r + 0.5) * gt[5];
            int in_hole = hole > 0 && abs(c - w / 2) < hole / 2 && abs(r - h / 2) < hole / 2;
            z[(size_t)r * w + c] =
                in_hole ? -9999.0f : (float)(1000.0 + a * (e - PLANE_E0) + b * (n - PLANE_N0));
        }
    ASSERT_TRUE(GDALRasterIO(band, GF_Write, 0, 0, w, h, z, w, h, GDT_Float32, 0, 0) == CE_None);
    free(z);
    GDALClose(ds);
}

/* Checks the readout at the plane's post (c, r) against the gradient (a, b). */
static void check_plane(double a, double b, const char* name)
{
    char path[256], json[8192], err[2048], pos[128];
    snprintf(path, sizeof path, "%s/%s.tif", tmp_dir(), name);
    write_plane(path, a, b, PLANE_W, PLANE_H, 0);
    int c = 20, r = 30;
    double e = PLANE_E0 + (c + 0.5) * PLANE_STEP_M, n = PLANE_N0 - (r + 0.5) * PLANE_STEP_M;
    snprintf(pos, sizeof pos, "33n %.3f %.3f", e, n);
    ASSERT_EQ_INT(0, run_point(path, pos, json, sizeof json, err, sizeof err));
    EXPECT_NEAR(tp_test_json_number_after(json, NULL, "elevation_m"), 1000.0 + a * (e - PLANE_E0) + b * (n - PLANE_N0),
                0.01);
    double slope = atan(hypot(a, b)) * DEG;
    EXPECT_NEAR(tp_test_json_number_after(json, NULL, "slope_deg"), slope, 0.02);
    if (a == 0 && b == 0) {
        EXPECT_NAN(tp_test_json_number_after(json, NULL, "aspect_grid_deg"));
        EXPECT_NAN(tp_test_json_number_after(json, NULL, "aspect_deg"));
        return;
    }
    double aspect = atan2(-a, -b) * DEG; /* downhill, clockwise from north */
    if (aspect < 0)
        aspect += 360;
    double got = tp_test_json_number_after(json, NULL, "aspect_grid_deg");
    EXPECT_NEAR(fmod(got - aspect + 540.0, 360.0) - 180.0, 0.0, 0.05);
    /* grid north's bearing from true north in UTM: atan(tan(lon - lon0) sin(lat)) on the
     * sphere (good to ~1e-5 deg this near the central meridian, 15 E) */
    double lat = tp_test_json_number_after(json, NULL, "lat_deg"), lon = tp_test_json_number_after(json, NULL, "lon_deg");
    double gamma = atan(tan((lon - 15.0) / DEG) * sin(lat / DEG)) * DEG;
    EXPECT_NEAR(tp_test_json_number_after(json, NULL, "convergence_deg"), gamma, 1e-3);
    double true_aspect = fmod(aspect + gamma + 360.0, 360.0);
    got = tp_test_json_number_after(json, NULL, "aspect_deg");
    EXPECT_NEAR(fmod(got - true_aspect + 540.0, 360.0) - 180.0, 0.0, 0.05);
}

TEST(plane_slope_and_aspect)
{
    check_plane(0.1, -0.2, "plane_nnw");  /* downhill towards 333.4 deg */
    check_plane(-0.5, 0.0, "plane_east"); /* faces east: 90 deg, 26.57 deg steep */
    check_plane(0.0, 0.3, "plane_south"); /* faces south: 180 deg */
    check_plane(0.0, 0.0, "plane_flat");  /* no aspect */
}

/* A plane built into a store first: `point STORE` reads the same ground as `point DEM`. */
TEST(store_answers_as_its_dem)
{
    char dem[256], store[256], json[8192], err[2048];
    snprintf(dem, sizeof dem, "%s/plane_store.tif", tmp_dir());
    snprintf(store, sizeof store, "%s/plane_store.tpt", tmp_dir());
    write_plane(dem, 0.2, 0.1, PLANE_W, PLANE_H, 0);
    const char* args[] = {dem, "-o", store, "--quiet", NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("build", args, err, sizeof err));
    const char* pos = "33n 500205 4649695"; /* post (20, 30) */
    ASSERT_EQ_INT(0, run_point(store, pos, json, sizeof json, err, sizeof err));
    double h_store = tp_test_json_number_after(json, NULL, "elevation_m"), s_store = tp_test_json_number_after(json, NULL, "slope_deg");
    ASSERT_EQ_INT(0, run_point(dem, pos, json, sizeof json, err, sizeof err));
    EXPECT_EQ_DBL(h_store, tp_test_json_number_after(json, NULL, "elevation_m"));
    EXPECT_EQ_DBL(s_store, tp_test_json_number_after(json, NULL, "slope_deg"));
    EXPECT_NEAR(h_store, 1000.0 + 0.2 * 205 + 0.1 * (-305), 0.01);
}

/* ---- the vertical datum: what the file states, else unknown (SRTM: assumed EGM96) ---- */

static void datum_of(const char* dem, const char* pos, char* json, size_t cap)
{
    char err[2048];
    ASSERT_EQ_INT(0, run_point(dem, pos, json, cap, err, sizeof err));
}

TEST(vertical_datum_as_the_file_states)
{
    char path[1024], json[8192];
    /* a compound CRS: WGS 84 / UTM 33N + EGM96 height (EPSG:5773) */
    snprintf(path, sizeof path, "%s/plane_egm96.tif", tmp_dir());
    g_plane_crs = "EPSG:32633+5773";
    write_plane(path, 0.1, 0.1, PLANE_W, PLANE_H, 0);
    g_plane_crs = "EPSG:32633";
    datum_of(path, "33n 500205 4649695", json, sizeof json);
    EXPECT_CONTAINS(json, "\"vertical_datum\": \"EGM96 height (as the file states)\"");
    /* a plain projected CRS says nothing */
    snprintf(path, sizeof path, "%s/plane_nodatum.tif", tmp_dir());
    write_plane(path, 0.1, 0.1, PLANE_W, PLANE_H, 0);
    datum_of(path, "33n 500205 4649695", json, sizeof json);
    EXPECT_CONTAINS(json, "\"vertical_datum\": \"unknown (the file states none)\"");
    /* SRTM states none either: the assumption is named as one */
    if (!tp_test_data_path(path, sizeof path, "TP_SHARED_DATA_DIR", "N42E001.hgt"))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    datum_of(path, "42.5 1.5", json, sizeof json);
    EXPECT_CONTAINS(json, "assumed EGM96");
}

/* ---- bad positions ---- */

TEST(outside_dem_exits_1)
{
    char path[1024], json[64], err[2048];
    GDALDatasetH ds = open_shared(HOOD, path, sizeof path);
    GDALClose(ds);
    EXPECT_EQ_INT(1, run_point(path, "45.0 -110.0", json, sizeof json, err, sizeof err));
    EXPECT_CONTAINS(err, "outside the DEM");
    EXPECT_CONTAINS(err, HOOD);
    EXPECT_CONTAINS(err, "45.0 -110.0");
    /* one post beyond the east edge (NAD83 ~ WGS84 here: 1013 posts of 30 m from E 587049.6) */
    EXPECT_EQ_INT(1, run_point(path, "10n 617500 5025000", json, sizeof json, err, sizeof err));
    EXPECT_CONTAINS(err, "outside the DEM");
}

TEST(void_in_nodata_collar_exits_1)
{
    char path[1024], json[64], err[2048], pos[128];
    GDALDatasetH ds = open_shared(HOOD, path, sizeof path);
    double gt[6];
    ASSERT_TRUE(GDALGetGeoTransform(ds, gt) == CE_None);
    /* a nodata post whose 5x5 neighbourhood is all nodata (the collar at the corners) */
    int found = 0, fc = 0, fr = 0;
    for (int r = 2; r < 40 && !found; ++r)
        for (int c = 2; c < 40 && !found; ++c) {
            int all = 1;
            for (int dy = -2; dy <= 2 && all; ++dy)
                for (int dx = -2; dx <= 2 && all; ++dx)
                    all = sample(ds, c + dx, r + dy) == HOOD_NODATA;
            if (all)
                found = 1, fc = c, fr = r;
        }
    ASSERT_TRUE(found);
    double lat, lon;
    to_lat_lon(ds, gt[0] + (fc + 0.5) * gt[1], gt[3] + (fr + 0.5) * gt[5], &lat, &lon);
    GDALClose(ds);
    snprintf(pos, sizeof pos, "%.9f %.9f", lat, lon);
    EXPECT_EQ_INT(1, run_point(path, pos, json, sizeof json, err, sizeof err));
    EXPECT_CONTAINS(err, "in a void");
    EXPECT_CONTAINS(err, HOOD);
    EXPECT_CONTAINS(err, pos);
}

/* A hole of 80 x 80 posts open on the DEM's edge: outside the data, not filled, a void. */
TEST(void_in_large_hole_exits_1)
{
    char path[256], json[8192], err[2048];
    snprintf(path, sizeof path, "%s/plane_hole.tif", tmp_dir());
    write_plane(path, 0.1, 0.1, 120, 120, 80);
    /* interior voids of any size are filled: a hole stays a void only where it opens on the
     * edge, so a channel 3 posts wide joins this one to the top edge */
    {
        GDALDatasetH ds = GDALOpen(path, GA_Update);
        ASSERT_TRUE(ds != NULL);
        float nd[3 * 60];
        for (int i = 0; i < 3 * 60; i++)
            nd[i] = -9999.0f;
        ASSERT_EQ_INT(CE_None, GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 59, 0, 3, 60, nd,
                                            3, 60, GDT_Float32, 0, 0));
        GDALClose(ds);
    }
    /* the centre post (60, 60) */
    const char* pos = "33n 500605 4649395";
    EXPECT_EQ_INT(1, run_point(path, pos, json, sizeof json, err, sizeof err));
    EXPECT_CONTAINS(err, "in a void");
    EXPECT_CONTAINS(err, "plane_hole.tif");
    /* and outside the hole the plane is there */
    EXPECT_EQ_INT(0, run_point(path, "33n 500055 4649945", json, sizeof json, err, sizeof err));
    EXPECT_NEAR(tp_test_json_number_after(json, NULL, "elevation_m"), 1000.0 + 0.1 * 55 - 0.1 * 55, 0.01);
}

/* A DEM without a CRS has no latitude or longitude: no position can be put on it. */
TEST(dem_without_crs_exits_1)
{
    char path[256], json[64], err[2048];
    snprintf(path, sizeof path, "%s/plane_nocrs.tif", tmp_dir());
    g_plane_crs = "";
    write_plane(path, 0.1, 0.1, PLANE_W, PLANE_H, 0);
    g_plane_crs = "EPSG:32633";
    EXPECT_EQ_INT(1, run_point(path, "45 7", json, sizeof json, err, sizeof err));
    EXPECT_CONTAINS(err, "plane_nocrs.tif: has no CRS");
}

TEST(unreadable_position_exits_2)
{
    char path[1024], json[64], err[2048];
    GDALDatasetH ds = open_shared(HOOD, path, sizeof path);
    GDALClose(ds);
    EXPECT_EQ_INT(2, run_point(path, "40N 41N", json, sizeof json, err, sizeof err));
    EXPECT_CONTAINS(err, "Both 40N and 41N interpreted as latitudes");
}

#define TESTS(X)                                                                                   \
    X(post_height_equals_gdal_sample)                                                              \
    X(warped_dem_height_within_source_neighbourhood)                                               \
    X(plane_slope_and_aspect)                                                                      \
    X(store_answers_as_its_dem)                                                                    \
    X(vertical_datum_as_the_file_states)                                                           \
    X(outside_dem_exits_1)                                                                         \
    X(void_in_nodata_collar_exits_1)                                                               \
    X(void_in_large_hole_exits_1)                                                                  \
    X(dem_without_crs_exits_1)                                                                     \
    X(unreadable_position_exits_2)
TP_TEST_MAIN(TESTS)
