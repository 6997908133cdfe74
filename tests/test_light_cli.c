/*
 * test_light_cli.c - `terrapatch light` (app/commands/cmd_light.c) run as a child, its GeoTIFF opened
 * with GDAL's C API:
 *   - Mt Hood (UTM 10N): the file has the DEM's grid and CRS; the sun it prints is tp_sun.h's
 *     at the printed place and time, its grid azimuth the true one less the convergence worked
 *     out here with GDAL/PROJ (the bearing of grid north between two points 100 m apart); its
 *     values agree with tp_shadow_compute run here on the render grid (the store the child
 *     reads keeps warped heights to 1/16 m);
 *   - N42E001 with --radius/--at and --values illumination: the window's georeference and
 *     tp_shadow_illumination's values;
 *   - the sun below the horizon: all 0; bad input: exit 1, nothing written.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"
#include "tp_io.h"
#include "tp_sun.h"

#include "tp_test_child.h"
#include "tp_test_gdal.h"
#include "tp_test_grid.h"

#include <gdal.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define TESTS(X)                                                                                   \
    X(mt_hood_geotiff_has_the_grid_the_sun_and_the_core_shadows)                                   \
    X(window_and_illumination_on_n42e001)                                                          \
    X(sun_below_the_horizon_writes_zeros)                                                          \
    X(bad_input_exits_1_and_writes_nothing)

static const char* tmp_dir(void) { return tp_test_child_dir("light"); }

static int run_light(const char* const* args, char* out, size_t out_cap, char* err,
                     size_t err_cap)
{
    return tp_test_run_terrapatch_out("light", args, out, out_cap, err, err_cap);
}

static tp_render_grid* grid_or_skip(const char* file, char* path, size_t cap)
{
    return tp_test_render_grid(file, path, cap);
}

/* The numbers the command prints. */
typedef struct printed {
    double lat, lon, post_x, post_y, true_az, grid_az, elevation;
} printed;

static printed parse_stdout(const char* out)
{
    printed p;
    const char* place = strstr(out, "place      ");
    const char* sun = strstr(out, "sun        azimuth ");
    if (!place || !sun ||
        sscanf(place, "place %lf %lf (post %lf, %lf", &p.lat, &p.lon, &p.post_x, &p.post_y) !=
            4 ||
        sscanf(sun, "sun azimuth %lf deg true, %lf deg grid; elevation %lf", &p.true_az,
               &p.grid_az, &p.elevation) != 3)
        FAIL("unexpected output: %s", out);
    return p;
}

/* The bearing of grid north (clockwise from true north) at (e, n), by GDAL/PROJ: the spherical
 * forward azimuth between (e, n) and (e, n + 100 m); the sphere's error over 100 m is far
 * below the tolerance. */
static double convergence_deg(const char* wkt, double e, double n)
{
    double lat1, lon1, lat2, lon2;
    tp_test_gdal_lat_lon(wkt, e, n, &lat1, &lon1);
    tp_test_gdal_lat_lon(wkt, e, n + 100.0, &lat2, &lon2);
    const double p1 = lat1 * M_PI / 180.0, p2 = lat2 * M_PI / 180.0;
    const double dl = (lon2 - lon1) * M_PI / 180.0;
    return atan2(sin(dl) * cos(p2), cos(p1) * sin(p2) - sin(p1) * cos(p2) * cos(dl)) * 180.0 /
           M_PI;
}

/* Opens path and checks size and georeference against the window (x0, y0, w, h) of g. */
static uint8_t* read_checked(const char* path, const tp_render_grid* g, int x0, int y0, int w,
                             int h)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    EXPECT_EQ_INT(w, GDALGetRasterXSize(ds));
    EXPECT_EQ_INT(h, GDALGetRasterYSize(ds));
    EXPECT_EQ_INT(1, GDALGetRasterCount(ds));
    EXPECT_TRUE(GDALGetRasterDataType(GDALGetRasterBand(ds, 1)) == GDT_Byte);
    double gt[6];
    ASSERT_TRUE(GDALGetGeoTransform(ds, gt) == CE_None);
    EXPECT_NEAR(gt[0], g->geotransform[0] + x0 * g->geotransform[1], 1e-6);
    EXPECT_NEAR(gt[3], g->geotransform[3] + y0 * g->geotransform[5], 1e-6);
    EXPECT_NEAR(gt[1], g->geotransform[1], 1e-9);
    EXPECT_NEAR(gt[5], g->geotransform[5], 1e-9);
    OGRSpatialReferenceH a = OSRNewSpatialReference(GDALGetProjectionRef(ds));
    OGRSpatialReferenceH b = OSRNewSpatialReference(g->crs_wkt);
    EXPECT_TRUE(OSRIsSame(a, b));
    OSRDestroySpatialReference(a);
    OSRDestroySpatialReference(b);
    uint8_t* v = malloc((size_t)w * h);
    ASSERT_TRUE(v != NULL);
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, w, h, v, w, h, GDT_Byte, 0,
                             0) == CE_None);
    GDALClose(ds);
    return v;
}

/* 2026-06-21 18:30 at UTC-7 = 2026-06-22 01:30 UTC (Unix 1782091800). */
TEST(mt_hood_geotiff_has_the_grid_the_sun_and_the_core_shadows)
{
    char path[1024], out[256], so[8192], se[4096];
    tp_render_grid* g = grid_or_skip("lf_elev_220_mt_hood_utm.tif", path, sizeof path);
    snprintf(out, sizeof out, "%s/hood.tif", tmp_dir());
    const char* args[] = {path, "--date", "2026-06-21", "--time", "18:30 -07:00", "-o", out,
                          NULL};
    ASSERT_EQ_INT(0, run_light(args, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(so, "2026-06-21 18:30:00 -07:00 = 2026-06-22 01:30:00 UTC");
    EXPECT_CONTAINS(so, "sunrise    2026-06-21 05:");
    EXPECT_CONTAINS(so, "sunset     2026-06-21 20:");
    const printed p = parse_stdout(so);
    tp_sun_pos sun;
    tp_error err;
    memset(&err, 0, sizeof err);
    ASSERT_OK(tp_sun_position(p.lat, p.lon, 1782091800.0, &sun, &err));
    EXPECT_NEAR(p.true_az, sun.azimuth_deg, 0.002);
    EXPECT_NEAR(p.elevation, sun.apparent_elevation_deg, 0.002);
    const double e = g->geotransform[0] + (p.post_x + 0.5) * g->geotransform[1];
    const double n = g->geotransform[3] + (p.post_y + 0.5) * g->geotransform[5];
    const double conv = convergence_deg(g->crs_wkt, e, n);
    tp_test_note("sun %.3f true, %.3f grid, elevation %.3f; convergence here %.4f", p.true_az,
                 p.grid_az, p.elevation, conv);
    EXPECT_NEAR(p.true_az - p.grid_az, conv, 0.01);

    const int w = g->width, h = g->height;
    const size_t cnt = (size_t)w * h;
    uint8_t* got = read_checked(out, g, 0, 0, w, h);
    uint8_t* want = malloc(cnt);
    ASSERT_OK(tp_shadow_compute(g->heights, cnt, w, h, fabs(g->geotransform[1]),
                                fabs(g->geotransform[5]), p.grid_az, p.elevation, want, NULL,
                                cnt, &err));
    size_t valid = 0, same = 0, shadowed = 0, bad = 0;
    for (size_t i = 0; i < cnt; ++i) {
        bad += got[i] != 0 && got[i] != 255;
        if (g->heights[i] != g->heights[i]) {
            EXPECT_EQ_INT(0, got[i]);
            continue;
        }
        valid++;
        same += (got[i] == 255) == (want[i] == TP_SHADOW_LIT);
        shadowed += got[i] == 0;
    }
    tp_test_note("GeoTIFF %dx%d: %.1f%% in shadow; agrees with tp_shadow_compute on the render "
                 "grid here on %.3f%%",
                 w, h, 100.0 * shadowed / valid, 100.0 * same / valid);
    EXPECT_EQ_INT(0, (int)bad);
    EXPECT_GE((double)same / valid, 0.99);
    EXPECT_GT(shadowed, valid / 50); /* an evening sun at 23 degrees: long shadows */
    free(got);
    free(want);
    tp_render_grid_destroy(g);
}

TEST(window_and_illumination_on_n42e001)
{
    char path[1024], out[256], so[8192], se[4096];
    tp_render_grid* g = grid_or_skip("N42E001.hgt", path, sizeof path);
    snprintf(out, sizeof out, "%s/n42.tif", tmp_dir());
    const char* args[] = {path,       "--date", "2026-12-02", "--time",   "09:00+01:00",
                          "--values", "illumination", "--radius", "5000", "--at",
                          "42.5,1.5", "-o",     out,          NULL};
    ASSERT_EQ_INT(0, run_light(args, so, sizeof so, se, sizeof se));
    const printed p = parse_stdout(so);
    const int r = (int)floor(5000.0 / g->geotransform[1]);
    const int x0 = (int)p.post_x - r, y0 = (int)p.post_y - r, w = 2 * r + 1;
    uint8_t* got = read_checked(out, g, x0, y0, w, w);
    float* z = malloc(sizeof(float) * (size_t)w * w);
    for (int y = 0; y < w; ++y)
        for (int x = 0; x < w; ++x)
            z[(size_t)y * w + x] = g->heights[(size_t)(y0 + y) * g->width + x0 + x];
    const size_t cnt = (size_t)w * w;
    uint8_t* lit = malloc(cnt);
    uint8_t* want = malloc(cnt);
    tp_error err;
    memset(&err, 0, sizeof err);
    const double dx = fabs(g->geotransform[1]), dy = fabs(g->geotransform[5]);
    ASSERT_OK(tp_shadow_compute(z, cnt, w, w, dx, dy, p.grid_az, p.elevation, lit, NULL, cnt,
                                &err));
    ASSERT_OK(tp_shadow_illumination(z, cnt, w, w, dx, dy, p.grid_az, p.elevation, lit, want,
                                     cnt, &err));
    size_t close = 0, lit_count = 0, in_shadow_lit = 0;
    for (size_t i = 0; i < cnt; ++i) {
        close += abs((int)got[i] - (int)want[i]) <= 8;
        lit_count += got[i] > 0;
        in_shadow_lit += got[i] > 0 && !lit[i] && want[i] == 0 && abs((int)got[i]) > 8;
    }
    tp_test_note("window %dx%d from (%d, %d): %.1f%% lit; within 8 of the core's illumination "
                 "on the render grid on %.2f%% (the store keeps the warped heights to 1/16 m)",
                 w, w, x0, y0, 100.0 * lit_count / cnt, 100.0 * close / cnt);
    EXPECT_GE((double)close / cnt, 0.98);
    EXPECT_GT(lit_count, cnt / 10);
    EXPECT_LE((double)in_shadow_lit, 0.01 * cnt);
    free(z);
    free(lit);
    free(want);
    free(got);
    tp_render_grid_destroy(g);
}

/* 03:00 at UTC-7 in June at Mt Hood is before sunrise. */
TEST(sun_below_the_horizon_writes_zeros)
{
    char path[1024], out[256], so[8192], se[4096];
    tp_render_grid* g = grid_or_skip("lf_elev_220_mt_hood_utm.tif", path, sizeof path);
    snprintf(out, sizeof out, "%s/night.tif", tmp_dir());
    const char* args[] = {path, "--date", "2026-06-21", "--time", "03:00-07:00", "-o", out,
                          "--radius", "3000", "--at", "45.37,-121.70", NULL};
    ASSERT_EQ_INT(0, run_light(args, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(so, "below the horizon");
    EXPECT_CONTAINS(so, "sunlit     0 of");
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(out, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    double mn = -1, mx = -1, mean, sd;
    ASSERT_TRUE(GDALComputeRasterStatistics(GDALGetRasterBand(ds, 1), FALSE, &mn, &mx, &mean, &sd,
                                            NULL, NULL) == CE_None);
    EXPECT_EQ_DBL(0.0, mx);
    GDALClose(ds);
    tp_render_grid_destroy(g);
}

TEST(bad_input_exits_1_and_writes_nothing)
{
    char path[1024], out[256], so[8192], se[4096];
    tp_render_grid* g = grid_or_skip("lf_elev_220_mt_hood_utm.tif", path, sizeof path);
    tp_render_grid_destroy(g);
    snprintf(out, sizeof out, "%s/bad.tif", tmp_dir());
    const char* outside[] = {path, "--date", "2026-06-21", "--time", "12:00", "-o", out,
                             "--radius", "1000", "--at", "44.0,-121.7", NULL};
    EXPECT_EQ_INT(1, run_light(outside, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(se, "outside the DEM");
    EXPECT_CONTAINS(se, "lf_elev_220_mt_hood_utm.tif");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "bad.tif"));
    const char* nodir[] = {path, "--date", "2026-06-21", "--time", "12:00", "-o",
                           "/nonexistent/dir/x.tif", NULL};
    EXPECT_EQ_INT(1, run_light(nodir, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(se, "/nonexistent/dir");
    const char* missing[] = {"/nonexistent/dem.tif", "--date", "2026-06-21", "--time", "12:00",
                             "-o", out, NULL};
    EXPECT_EQ_INT(1, run_light(missing, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(se, "/nonexistent/dem.tif");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "bad.tif"));
}

TP_TEST_MAIN(TESTS)
