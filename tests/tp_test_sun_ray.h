/*
 * tp_test_sun_ray.h - sunlight worked out here from the geometry, independently of the code
 * under test (core/src/shadow.c, light_times.c, app/commands/cmd_light.c, light_day.c), for
 * the tests of `terrapatch light` (test_light_sun_cli.c, test_light_hours_cli.c): a one-band
 * raster read with GDAL as floats (nodata NaN), the bearing of grid north by GDAL/PROJ, and a
 * ray cast marching from a post toward the sun in quarter-post steps over the bilinear surface
 * between posts (as tests/test_shadow.c's). Include after tp_test.h and tp_test_gdal.h.
 */
#ifndef TP_TEST_SUN_RAY_H
#define TP_TEST_SUN_RAY_H

#include <gdal.h>

#include <math.h>
#include <stdlib.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

/* A raster's first band as floats, its nodata as NaN. */
typedef struct tp_test_grid {
    int w, h;
    double gt[6];
    char wkt[4096];
    float* z; /* w * h, row 0 north */
    int type; /* GDALDataType of the band */
    int has_nodata;
    double nodata;
} tp_test_grid;

static inline void tp_test_grid_read(const char* path, tp_test_grid* g)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    if (!ds)
        FAIL("GDAL cannot open %s", path);
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    g->w = GDALGetRasterXSize(ds), g->h = GDALGetRasterYSize(ds);
    ASSERT_TRUE(GDALGetGeoTransform(ds, g->gt) == CE_None);
    snprintf(g->wkt, sizeof g->wkt, "%s", GDALGetProjectionRef(ds));
    g->type = (int)GDALGetRasterDataType(b);
    g->nodata = GDALGetRasterNoDataValue(b, &g->has_nodata);
    g->z = malloc(sizeof(float) * (size_t)g->w * g->h);
    ASSERT_TRUE(g->z != NULL);
    ASSERT_TRUE(GDALRasterIO(b, GF_Read, 0, 0, g->w, g->h, g->z, g->w, g->h, GDT_Float32, 0, 0) ==
                CE_None);
    GDALClose(ds);
    if (g->has_nodata)
        for (size_t i = 0; i < (size_t)g->w * g->h; ++i)
            if (g->z[i] == (float)g->nodata)
                g->z[i] = NAN;
}

/* The bearing of grid north (clockwise from true north, degrees) at (e, n) of the CRS wkt, by
 * GDAL/PROJ: the spherical forward azimuth from (e, n) to (e, n + 100 m). */
static inline double tp_test_grid_convergence(const char* wkt, double e, double n)
{
    double lat1, lon1, lat2, lon2;
    tp_test_gdal_lat_lon(wkt, e, n, &lat1, &lon1);
    tp_test_gdal_lat_lon(wkt, e, n + 100.0, &lat2, &lon2);
    const double p1 = lat1 * M_PI / 180.0, p2 = lat2 * M_PI / 180.0;
    const double dl = (lon2 - lon1) * M_PI / 180.0;
    return atan2(sin(dl) * cos(p2), cos(p1) * sin(p2) - sin(p1) * cos(p2) * cos(dl)) * 180.0 / M_PI;
}

/* The bilinear surface at grid (x, y) (column, row); NaN in a cell with a void corner. */
static inline double tp_test_bilinear(const float* z, int w, int h, double x, double y)
{
    int c = (int)floor(x), r = (int)floor(y);
    if (c > w - 2)
        c = w - 2;
    if (r > h - 2)
        r = h - 2;
    const double fx = x - c, fy = y - r;
    const double z00 = z[(size_t)r * w + c], z10 = z[(size_t)r * w + c + 1];
    const double z01 = z[(size_t)(r + 1) * w + c], z11 = z[(size_t)(r + 1) * w + c + 1];
    return (z00 * (1 - fx) + z10 * fx) * (1 - fy) + (z01 * (1 - fx) + z11 * fx) * fy;
}

/* 1 when the ray from post (c, r) toward the sun (azimuth az_deg clockwise from GRID north,
 * elevation el_deg) clears the surface: marched in quarter-post steps until it leaves the grid
 * or rises above zmax. The sun on or below the horizon lights nothing; a void is never lit
 * and blocks nothing. Posts dx by dy metres apart (w, h >= 2). */
static inline int tp_test_sun_ray_lit(const float* z, int w, int h, double dx, double dy,
                                      double az_deg, double el_deg, int c, int r, double zmax)
{
    const double z0 = z[(size_t)r * w + c];
    if (z0 != z0 || el_deg <= 0.0)
        return 0;
    const double az = az_deg * M_PI / 180.0, t = tan(el_deg * M_PI / 180.0);
    const double step = 0.25 * (dx < dy ? dx : dy);
    const double ux = sin(az) / dx, uy = -cos(az) / dy;
    for (double d = step;; d += step) {
        const double x = c + ux * d, y = r + uy * d;
        if (x < 0.0 || y < 0.0 || x > w - 1 || y > h - 1)
            return 1;
        const double ray = z0 + d * t;
        if (ray > zmax)
            return 1;
        const double g = tp_test_bilinear(z, w, h, x, y);
        if (g == g && g > ray)
            return 0;
    }
}

/* The highest post of the grid. */
static inline double tp_test_grid_max(const tp_test_grid* g)
{
    double m = -INFINITY;
    for (size_t i = 0; i < (size_t)g->w * g->h; ++i)
        if (g->z[i] > m)
            m = g->z[i];
    return m;
}

#endif /* TP_TEST_SUN_RAY_H */
