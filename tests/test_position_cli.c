/*
 * test_position_cli.c - positions as the planner commands read them (app/base/position.c through
 * app/commands/planner_cli.c), run as children (issue 29, section 2):
 *   - every form `point` prints (DMS, UTM with its labels, MGRS with and without spaces) and
 *     `coord` prints (--to utm, --to mgrs) reads back in `point` and `coord`, at the printed
 *     precision;
 *   - "33S E N" (band S on a map, the southern hemisphere in GeographicLib's notation): two
 *     DEMs written here with GDAL, one at 36 N (UTM 33N) and one at 54 S (UTM 33S), each takes
 *     the reading on it and says so; `coord` refuses it; the position by GDAL/PROJ here;
 *   - latitude and longitude swapped: the same hint from point, los, viewshed, light, contours;
 *   - a void reaching the DEM's edge (Mt Hood's nodata collar) suggests --fill-from.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_io.h"
#include "tp_test.h"

#include "tp_test_child.h"
#include "tp_test_gdal.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char* tmp_dir(void)
{
    return tp_test_child_dir("position");
}

/* `point DEM POS --json -`: exit status, its stdout (the JSON on 0) and stderr. */
static int run_point_json(const char* dem, const char* pos, char* out, size_t cap, char* err,
                          size_t err_cap)
{
    const char* args[] = {dem, pos, "--json", "-", NULL};
    return tp_test_run_terrapatch_out("point", args, out, cap, err, err_cap);
}

/* The value after "label" at the start of a line of point's text, to the end of the line. */
static void printed(const char* text, const char* label, char* out, size_t cap)
{
    const char* p = strstr(text, label);
    if (!p)
        FAIL("no '%s' in:\n%s", label, text);
    p += strlen(label);
    while (*p == ' ')
        ++p;
    size_t len = strcspn(p, "\n");
    ASSERT_TRUE(len < cap);
    memcpy(out, p, len);
    out[len] = '\0';
}

/* Metres between two positions (small distances). */
static double metres_apart(double lat1, double lon1, double lat2, double lon2)
{
    const double dn = (lat1 - lat2) * 111000.0;
    const double de = remainder(lon1 - lon2, 360.0) * 111000.0 * cos(lat1 * 3.14159265 / 180.0);
    return sqrt(dn * dn + de * de);
}

/* `coord TEXT` read back within tol_m of (lat, lon), and `point DEM TEXT` too. */
static void reads_back(const char* dem, const char* text, double lat, double lon, double tol_m)
{
    char out[4096], err[4096];
    const char* args[] = {text, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("coord", args, out, sizeof out, err, sizeof err));
    double a, b;
    ASSERT_EQ_INT(2, sscanf(out, "%lf %lf", &a, &b));
    if (metres_apart(a, b, lat, lon) > tol_m)
        FAIL("coord '%s': %.9f %.9f, expected %.9f %.9f", text, a, b, lat, lon);
    if (run_point_json(dem, text, out, sizeof out, err, sizeof err) != 0)
        FAIL("point '%s': %s", text, err);
    a = tp_test_json_number_after(out, NULL, "lat_deg");
    b = tp_test_json_number_after(out, NULL, "lon_deg");
    if (metres_apart(a, b, lat, lon) > tol_m)
        FAIL("point '%s': %.9f %.9f, expected %.9f %.9f", text, a, b, lat, lon);
}

TEST(point_and_coord_output_reads_back)
{
    char dem[1024];
    if (!tp_test_data_path(dem, sizeof dem, "TP_SHARED_DATA_DIR", "N42E001.hgt"))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    static const char* const where[] = {"42.5 1.5", "42.0183 1.0021", "42.9 1.99"};
    for (size_t i = 0; i < sizeof where / sizeof where[0]; ++i) {
        char text[8192], err[4096], v[256], lat_s[64], lon_s[64], form[300];
        const char* args[] = {dem, where[i], NULL};
        ASSERT_EQ_INT(
            0, tp_test_run_terrapatch_out("point", args, text, sizeof text, err, sizeof err));
        double lat, lon;
        printed(text, "latitude", v, sizeof v);
        ASSERT_EQ_INT(2, sscanf(v, "%lf %63s", &lat, lat_s));
        printed(text, "longitude", v, sizeof v);
        ASSERT_EQ_INT(2, sscanf(v, "%lf %63s", &lon, lon_s));
        snprintf(form, sizeof form, "%s %s", lat_s, lon_s); /* DMS to 0.01" */
        reads_back(dem, form, lat, lon, 0.32);
        printed(text, "UTM", v, sizeof v); /* "31n 376749.5 E 4706383.2 N" */
        reads_back(dem, v, lat, lon, 0.11);
        snprintf(form, sizeof form, "UTM %s", v); /* the line as printed, label and all */
        reads_back(dem, form, lat, lon, 0.11);
        printed(text, "MGRS", v, sizeof v); /* "31T CH 76749 06383": 1 m squares */
        reads_back(dem, v, lat, lon, 1.0);
        size_t n = 0;
        for (const char* c = v; *c; ++c)
            if (*c != ' ')
                form[n++] = *c;
        form[n] = '\0';
        reads_back(dem, form, lat, lon, 1.0);
        /* coord's own forms */
        static const char* const tos[] = {"utm", "mgrs"};
        for (int k = 0; k < 2; ++k) {
            const char* cargs[] = {"--to", tos[k], where[i], NULL};
            ASSERT_EQ_INT(
                0, tp_test_run_terrapatch_out("coord", cargs, form, sizeof form, err, sizeof err));
            form[strcspn(form, "\n")] = '\0';
            reads_back(dem, form, lat, lon, k ? 1.0 : 0.01);
        }
    }
}

/* 41 x 41 posts 30 m apart at 100 m, north-up, in EPSG:epsg from (e0, n0) at the top left. */
static void write_flat(const char* path, int epsg, double e0, double n0, char** wkt)
{
    const int w = 41, h = 41;
    GDALAllRegister();
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path, w, h, 1, GDT_Float32, NULL);
    ASSERT_TRUE(ds != NULL);
    double gt[6] = {e0, 30.0, 0, n0, 0, -30.0};
    GDALSetGeoTransform(ds, gt);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    ASSERT_TRUE(OSRImportFromEPSG(srs, epsg) == OGRERR_NONE);
    OSRExportToWkt(srs, wkt);
    OSRDestroySpatialReference(srs);
    GDALSetProjection(ds, *wkt);
    float z[41 * 41];
    for (int i = 0; i < w * h; ++i)
        z[i] = 100.0f;
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, w, h, z, w, h, GDT_Float32,
                             0, 0) == CE_None);
    GDALClose(ds);
}

/* "33S 500600 4000600": band S (36.15 N) on a DEM in UTM 33N there, zone 33 south (54.14 S) on
 * one in UTM 33S there; each command takes the reading on its DEM and says which. */
TEST(band_s_takes_the_reading_on_the_dem)
{
    static const char* const pos = "33S 500600 4000600";
    const double e = 500600.0, n = 4000600.0;
    char north[256], south[256], out[8192], err[4096];
    char *wkt_n = NULL, *wkt_s = NULL;
    snprintf(north, sizeof north, "%s/band_s_north.tif", tmp_dir());
    snprintf(south, sizeof south, "%s/band_s_south.tif", tmp_dir());
    write_flat(north, 32633, 500000.0, 4001200.0, &wkt_n);
    write_flat(south, 32733, 500000.0, 4001200.0, &wkt_s);
    double lat_n, lon_n, lat_s, lon_s;
    tp_test_gdal_lat_lon(wkt_n, e, n, &lat_n, &lon_n);
    tp_test_gdal_lat_lon(wkt_s, e, n, &lat_s, &lon_s);
    CPLFree(wkt_n);
    CPLFree(wkt_s);
    ASSERT_TRUE(lat_n > 32.0 && lat_n < 40.0); /* band S */
    ASSERT_TRUE(lat_s < -54.0);

    ASSERT_EQ_INT(0, run_point_json(north, pos, out, sizeof out, err, sizeof err));
    EXPECT_NEAR(tp_test_json_number_after(out, NULL, "lat_deg"), lat_n, 1e-7);
    EXPECT_NEAR(tp_test_json_number_after(out, NULL, "lon_deg"), lon_n, 1e-7);
    EXPECT_CONTAINS(err, "terrapatch point: note: read '33S 500600 4000600' as band S");
    EXPECT_CONTAINS(err, "the other reading, zone 33 south");
    EXPECT_CONTAINS(err, "is off");

    ASSERT_EQ_INT(0, run_point_json(south, pos, out, sizeof out, err, sizeof err));
    EXPECT_NEAR(tp_test_json_number_after(out, NULL, "lat_deg"), lat_s, 1e-7);
    EXPECT_NEAR(tp_test_json_number_after(out, NULL, "lon_deg"), lon_s, 1e-7);
    EXPECT_CONTAINS(err, "note: read '33S 500600 4000600' as zone 33 south");

    /* los and viewshed choose alike (each end on its own) */
    char json[256];
    snprintf(json, sizeof json, "%s/los.json", tmp_dir());
    const char* los[] = {south, "--from", pos, "--to", "33s 500900 4000300", "--json", json, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("los", los, err, sizeof err));
    EXPECT_CONTAINS(err, "terrapatch los: note: read '33S 500600 4000600' as zone 33 south");
    tp_test_read_text(json, out, sizeof out);
    EXPECT_NEAR(tp_test_json_number_after(out, "\"from\"", "lat"), lat_s, 1e-6);
    char tif[256];
    snprintf(tif, sizeof tif, "%s/seen.tif", tmp_dir());
    const char* vs[] = {north, "--observer", pos, "-o", tif, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("viewshed", vs, err, sizeof err));
    EXPECT_CONTAINS(err, "terrapatch viewshed: note: read '33S 500600 4000600' as band S");

    /* coord has no DEM to tell: refused, both named */
    const char* cargs[] = {pos, NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch_out("coord", cargs, out, sizeof out, err, sizeof err));
    EXPECT_CONTAINS(out, "ERROR: '33S' is ambiguous: band S (36.15");
    EXPECT_CONTAINS(out, "zone 33 south (-54.14");
    /* and a reading on neither DEM is refused naming both */
    char n42[1024];
    if (tp_test_data_path(n42, sizeof n42, "TP_SHARED_DATA_DIR", "N42E001.hgt")) {
        EXPECT_EQ_INT(1, run_point_json(n42, pos, out, sizeof out, err, sizeof err));
        EXPECT_CONTAINS(err, "is ambiguous: band S (36.15");
        EXPECT_CONTAINS(err, "neither is on the DEM");
    }
}

/* Latitude and longitude swapped: every command that puts a position on a DEM says so. */
TEST(swapped_lat_lon_same_hint_in_every_command)
{
    char dem[1024], err[4096], out[256];
    if (!tp_test_data_path(dem, sizeof dem, "TP_SHARED_DATA_DIR", "N42E001.hgt"))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    static const char* const hint =
        "with latitude and longitude swapped (42.500000 1.500000) it is on the DEM: a position "
        "is LAT LON, latitude first";
    snprintf(out, sizeof out, "%s/swapped.tif", tmp_dir());
    char gpkg[256];
    snprintf(gpkg, sizeof gpkg, "%s/swapped.gpkg", tmp_dir());
    const char* point[] = {dem, "1.5", "42.5", NULL};
    const char* los[] = {dem, "--from", "1.5,42.5", "--to", "42.6,1.6", NULL};
    const char* viewshed[] = {dem, "--observer", "1.5,42.5", "-o", out, NULL};
    const char* light[] = {dem,      "--at",  "1.5,42.5", "--date", "2026-06-21",
                           "--time", "12:00", "-o",       out,      NULL};
    const char* contours[] = {dem,          "--around", "1.5,42.5", "--radius", "1000",
                              "--interval", "100",      "-o",       gpkg,       NULL};
    const char* const* runs[] = {point, los, viewshed, light, contours};
    static const char* const cmds[] = {"point", "los", "viewshed", "light", "contours"};
    for (int k = 0; k < 5; ++k) {
        EXPECT_EQ_INT(1, tp_test_run_terrapatch(cmds[k], runs[k], err, sizeof err));
        EXPECT_CONTAINS(err, "is outside the DEM");
        EXPECT_CONTAINS(err, hint);
    }
    /* not swapped, only outside: no hint */
    const char* far[] = {dem, "45", "7", NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch("point", far, err, sizeof err));
    EXPECT_TRUE(strstr(err, "swapped") == NULL);
    EXPECT_TRUE(strstr(err, "--fill-from") == NULL);
}

/* Mt Hood's nodata collar reaches the DEM's edge: no interpolation fills it, --fill-from can. */
TEST(void_at_the_edge_suggests_fill_from)
{
    char dem[1024], out[256], err[4096];
    if (!tp_test_data_path(dem, sizeof dem, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif"))
        SKIP("lf_elev_220_mt_hood_utm.tif not found (set TP_SHARED_DATA_DIR)");
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(dem, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    double gt[6], lat, lon;
    ASSERT_TRUE(GDALGetGeoTransform(ds, gt) == CE_None);
    /* post (3, 3): inside the collar (test_point.c's void_in_nodata_collar_exits_1) */
    float z = 0;
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 3, 3, 1, 1, &z, 1, 1, GDT_Float32,
                             0, 0) == CE_None);
    ASSERT_EQ_DBL(32767.0, z);
    tp_test_gdal_lat_lon(GDALGetProjectionRef(ds), gt[0] + 3.5 * gt[1], gt[3] + 3.5 * gt[5], &lat,
                         &lon);
    GDALClose(ds);
    char pos[128];
    snprintf(pos, sizeof pos, "%.9f %.9f", lat, lon);
    EXPECT_EQ_INT(1, run_point_json(dem, pos, out, sizeof out, err, sizeof err));
    EXPECT_CONTAINS(err, "in a void");
    EXPECT_CONTAINS(err, "the void reaches the DEM's edge");
    EXPECT_CONTAINS(err, "--fill-from OTHER");
    snprintf(out, sizeof out, "%s/void.tif", tmp_dir());
    const char* vs[] = {dem, "--observer", pos, "-o", out, NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch("viewshed", vs, err, sizeof err));
    EXPECT_CONTAINS(err, "--fill-from OTHER");
}

#define TESTS(X)                                                                                   \
    X(point_and_coord_output_reads_back)                                                           \
    X(band_s_takes_the_reading_on_the_dem)                                                         \
    X(swapped_lat_lon_same_hint_in_every_command)                                                  \
    X(void_at_the_edge_suggests_fill_from)
TP_TEST_MAIN(TESTS)
