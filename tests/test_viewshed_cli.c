/*
 * test_viewshed_cli.c - `terrapatch viewshed` with several observers, a sector and values
 * (app/commands/cmd_viewshed.c; issue 31), run as a child, its raster read back with GDAL and
 * checked against what is worked out here independently:
 *   - several --observer: each post's count equals the number of observers whose exact ray test
 *     (R3, tp_test_r3.h, on the render grid built here) sees it within their radius;
 *   - --values clearance: a Float32 raster, nodata -9999 tagged, equal to the core's
 *     clearance on the render grid built here but for the store's 1/16 m step;
 *   - --azimuth FROM,TO: posts whose true azimuth from the observer (PROJ/OGR for latitude and
 *     longitude, the spherical initial bearing here) lies inside the sector are as without it,
 *     those outside are 0.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"
#include "tp_io.h"

#include "tp_test_child.h"
#include "tp_test_gdal.h"
#include "tp_test_grid.h"
#include "tp_test_r3.h"

#include <gdal.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define RADIUS_M 3000.0
#define EYE_M 150.0

static const char* tmp_dir(void) { return tp_test_child_dir("viewshed_cli"); }

static tp_render_grid* n42_grid(char* path, size_t cap)
{
    return tp_test_render_grid("N42E001.hgt", path, cap);
}

static void post_lat_lon(const tp_render_grid* g, int c, int r, double* lat, double* lon)
{
    tp_test_gdal_lat_lon(g->crs_wkt, g->geotransform[0] + (c + 0.5) * g->geotransform[1],
                         g->geotransform[3] + (r + 0.5) * g->geotransform[5], lat, lon);
}

/* A raster written by the command: its values as bytes, its origin as a post of g. */
typedef struct raster {
    uint8_t* v;
    int w, h, x0, y0;
} raster;

static raster read_raster(const char* path, const tp_render_grid* g)
{
    raster r = {0};
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    double gt[6];
    ASSERT_TRUE(GDALGetGeoTransform(ds, gt) == CE_None);
    r.w = GDALGetRasterXSize(ds);
    r.h = GDALGetRasterYSize(ds);
    r.x0 = (int)lround((gt[0] - g->geotransform[0]) / g->geotransform[1]);
    r.y0 = (int)lround((gt[3] - g->geotransform[3]) / g->geotransform[5]);
    r.v = malloc((size_t)r.w * r.h);
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, r.w, r.h, r.v, r.w, r.h,
                             GDT_Byte, 0, 0) == CE_None);
    GDALClose(ds);
    return r;
}

/* R3 from post (ox, oy) of g to (x, y) within RADIUS_M, the command's conventions (eye EYE_M,
 * target on the ground, 0.85714); the observer's eight neighbours always seen. */
static int r3_sees(const tp_render_grid* g, int ox, int oy, int x, int y)
{
    const double* gt = g->geotransform;
    if (hypot((x - ox) * gt[1], (y - oy) * gt[5]) > RADIUS_M)
        return 0;
    if (abs(x - ox) <= 1 && abs(y - oy) <= 1)
        return 1;
    const tp_test_r3 r3 = {EYE_M, 0.0, 0.85714, 6378137.0, 0};
    return tp_test_r3_clearance(g->heights, g->width, gt, ox, oy, x, y, &r3) >= 0.0;
}

/* Three observers 10-20 posts apart on N42E001: each post counts those that see it, as R3 says
 * (the store's heights are the render grid's to 3 cm and the viewshed's to R3's but for 0.05%:
 * 99.5% asserted). */
TEST(several_observers_count_what_the_exact_ray_test_sees)
{
    char path[1024], out[256], err[4096], text[8192], pos[3][64], radius[32], eye[32];
    tp_render_grid* g = n42_grid(path, sizeof path);
    const int ox[3] = {g->width / 2, g->width / 2 + 15, g->width / 2 - 10};
    const int oy[3] = {g->height / 2, g->height / 2 + 5, g->height / 2 + 15};
    for (int k = 0; k < 3; ++k) {
        double lat, lon;
        post_lat_lon(g, ox[k], oy[k], &lat, &lon);
        snprintf(pos[k], sizeof pos[k], "%.10f,%.10f", lat, lon);
    }
    snprintf(out, sizeof out, "%s/count.tif", tmp_dir());
    snprintf(radius, sizeof radius, "%g", RADIUS_M);
    snprintf(eye, sizeof eye, "%g", EYE_M);
    const char* args[] = {path,   "--observer", pos[0],     "--observer", pos[1],
                          "--observer", pos[2], "--radius", radius,       "--observer-height",
                          eye,    "-o",         out,        NULL};
    ASSERT_EQ_INT(0,
                  tp_test_run_terrapatch_out("viewshed", args, text, sizeof text, err, sizeof err));
    EXPECT_CONTAINS(text, "observer 3 ");
    EXPECT_CONTAINS(text, "covered    ");
    raster r = read_raster(out, g);
    size_t posts = 0, same = 0, counted[4] = {0};
    for (int y = 0; y < r.h; ++y)
        for (int x = 0; x < r.w; ++x) {
            const int gx = x + r.x0, gy = y + r.y0;
            const float z = g->heights[(size_t)gy * g->width + gx];
            if (z != z)
                continue;
            int want = 0;
            for (int k = 0; k < 3; ++k)
                want += r3_sees(g, ox[k], oy[k], gx, gy);
            const int got = r.v[(size_t)y * r.w + x];
            EXPECT_LE_INT(got, 3);
            posts++;
            same += got == want;
            counted[want]++;
        }
    tp_test_note("%zu posts: %.3f%% counted as R3 says (R3: %zu seen by none, %zu by one, %zu "
                 "by two, %zu by all three)",
                 posts, 100.0 * same / posts, counted[0], counted[1], counted[2], counted[3]);
    EXPECT_GT(counted[3], 500);
    EXPECT_GT(counted[1], 500);
    EXPECT_GE((double)same, 0.995 * (double)posts);
    free(r.v);
    tp_render_grid_destroy(g);
}

/* The initial bearing from (lat1, lon1) to (lat2, lon2) on a sphere, degrees clockwise from
 * true north in [0, 360): within 0.2 degree of the ellipsoid's over 3 km. */
static double bearing_deg(double lat1, double lon1, double lat2, double lon2)
{
    const double d = 3.14159265358979323846 / 180.0;
    const double y = sin((lon2 - lon1) * d) * cos(lat2 * d);
    const double x = cos(lat1 * d) * sin(lat2 * d) - sin(lat1 * d) * cos(lat2 * d) *
                                                        cos((lon2 - lon1) * d);
    return fmod(atan2(y, x) / d + 360.0, 360.0);
}

/* --azimuth 300,60 (a sector through north) against the same run without it. */
TEST(sector_keeps_what_lies_between_its_azimuths)
{
    char path[1024], all[256], part[256], err[4096], pos[64];
    tp_render_grid* g = n42_grid(path, sizeof path);
    const int ox = g->width / 2, oy = g->height / 2;
    double olat, olon;
    post_lat_lon(g, ox, oy, &olat, &olon);
    snprintf(pos, sizeof pos, "%.10f,%.10f", olat, olon);
    snprintf(all, sizeof all, "%s/all.tif", tmp_dir());
    snprintf(part, sizeof part, "%s/sector.tif", tmp_dir());
    const char* a1[] = {path, "--observer", pos, "--radius", "3000", "--observer-height", "150", "-o", all, NULL};
    const char* a2[] = {path,      "--observer", pos, "--radius", "3000",
                        "--observer-height", "150", "--azimuth", "300,60", "-o", part, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("viewshed", a1, err, sizeof err));
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("viewshed", a2, err, sizeof err));
    raster ra = read_raster(all, g), rs = read_raster(part, g);
    ASSERT_EQ_INT(ra.w, rs.w);
    ASSERT_EQ_INT(ra.h, rs.h);
    size_t inside = 0, outside = 0, wrong = 0, seen_inside = 0;
    for (int y = 0; y < ra.h; ++y)
        for (int x = 0; x < ra.w; ++x) {
            const int gx = x + ra.x0, gy = y + ra.y0;
            if (abs(gx - ox) < 3 && abs(gy - oy) < 3)
                continue; /* too near for a bearing to 0.2 degree */
            double lat, lon;
            post_lat_lon(g, gx, gy, &lat, &lon);
            const double b = bearing_deg(olat, olon, lat, lon);
            const double from300 = fmod(b - 300.0 + 360.0, 360.0); /* 0 .. 120 inside */
            const size_t i = (size_t)y * ra.w + x;
            if (from300 > 1.0 && from300 < 119.0) {
                inside++;
                wrong += rs.v[i] != ra.v[i];
                seen_inside += ra.v[i] == 255;
            } else if (from300 > 121.0 && from300 < 359.0) {
                outside++;
                wrong += rs.v[i] != 0;
            }
        }
    tp_test_note("%zu posts inside the sector (%zu seen), %zu outside; %zu wrong", inside,
                 seen_inside, outside, wrong);
    EXPECT_GT(seen_inside, 200);
    EXPECT_GT(outside, inside);
    EXPECT_EQ_INT(0, (int)wrong);
    free(ra.v);
    free(rs.v);
    tp_render_grid_destroy(g);
}

/* --values clearance: Float32 with gdaldem's nodata, against tp_viewshed_compute_values on the
 * same window of the render grid built here (the store's heights are the grid's to 3 cm). */
TEST(clearance_raster_is_float_with_nodata_and_the_cores_values)
{
    char path[1024], out[256], err[4096], pos[64];
    tp_render_grid* g = n42_grid(path, sizeof path);
    const int ox = g->width / 2, oy = g->height / 2;
    double lat, lon;
    post_lat_lon(g, ox, oy, &lat, &lon);
    snprintf(pos, sizeof pos, "%.10f,%.10f", lat, lon);
    snprintf(out, sizeof out, "%s/clearance.tif", tmp_dir());
    const char* args[] = {path, "--observer", pos, "--radius", "3000", "--values", "clearance",
                          "-o", out, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("viewshed", args, err, sizeof err));
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(out, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    EXPECT_EQ_INT(GDT_Float32, GDALGetRasterDataType(b));
    int has_nodata = 0;
    EXPECT_EQ_DBL(-9999.0, GDALGetRasterNoDataValue(b, &has_nodata));
    EXPECT_TRUE(has_nodata);
    double gt[6];
    ASSERT_TRUE(GDALGetGeoTransform(ds, gt) == CE_None);
    const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
    const int x0 = (int)lround((gt[0] - g->geotransform[0]) / g->geotransform[1]);
    const int y0 = (int)lround((gt[3] - g->geotransform[3]) / g->geotransform[5]);
    float* got = malloc(sizeof(float) * (size_t)w * h);
    ASSERT_TRUE(GDALRasterIO(b, GF_Read, 0, 0, w, h, got, w, h, GDT_Float32, 0, 0) == CE_None);
    GDALClose(ds);
    float* z = malloc(sizeof(float) * (size_t)w * h);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[(size_t)y * w + x] = g->heights[(size_t)(y0 + y) * g->width + (x0 + x)];
    uint8_t* seen = malloc((size_t)w * h);
    float* want = malloc(sizeof(float) * (size_t)w * h);
    tp_viewshed_options vo = tp_viewshed_options_default();
    vo.radius_m = 3000.0;
    tp_error e;
    memset(&e, 0, sizeof e);
    ASSERT_OK(tp_viewshed_compute_values(z, (size_t)w * h, w, h, gt, ox - x0, oy - y0, &vo,
                                         TP_VIEWSHED_VALUES_CLEARANCE, seen, want,
                                         (size_t)w * h, &e));
    size_t compared = 0, close = 0, nodata_agree = 0, posts = (size_t)w * h;
    for (size_t i = 0; i < posts; ++i) {
        if (want[i] != want[i]) {
            nodata_agree += got[i] == -9999.0f;
            continue;
        }
        compared++;
        close += fabs(got[i] - want[i]) <= 0.1 + 0.001 * fabs(want[i]);
    }
    tp_test_note("%zu posts with a clearance: %zu within 10 cm of the core's on the render grid; "
                 "%zu of %zu without one are -9999",
                 compared, close, nodata_agree, posts - compared);
    EXPECT_GT(compared, 5000);
    EXPECT_GE((double)close, 0.99 * (double)compared);
    EXPECT_EQ_INT((int)(posts - compared), (int)nodata_agree);
    free(got);
    free(z);
    free(seen);
    free(want);
    tp_render_grid_destroy(g);
}

#define TESTS(X)                                                                                   \
    X(several_observers_count_what_the_exact_ray_test_sees)                                        \
    X(sector_keeps_what_lies_between_its_azimuths)                                                 \
    X(clearance_raster_is_float_with_nodata_and_the_cores_values)
TP_TEST_MAIN(TESTS)
