/*
 * tp_test_gdal.h - answers worked out here with GDAL/PROJ, independently of the code under
 * test, for the tests of the planner commands (test_los_cli.c, test_point.c). Include after
 * tp_test.h (uses ASSERT_TRUE).
 */
#ifndef TP_TEST_GDAL_H
#define TP_TEST_GDAL_H

#include <ogr_srs_api.h>

/* Latitude, longitude (WGS84, degrees) of (e, n) in the CRS wkt, by GDAL/PROJ. */
static inline void tp_test_gdal_lat_lon(const char* wkt, double e, double n, double* lat,
                                        double* lon)
{
    OGRSpatialReferenceH src = OSRNewSpatialReference(wkt);
    OGRSpatialReferenceH dst = OSRNewSpatialReference(NULL);
    OSRImportFromEPSG(dst, 4326);
    OSRSetAxisMappingStrategy(src, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy(dst, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(src, dst);
    ASSERT_TRUE(ct != NULL);
    double x = e, y = n, z = 0;
    ASSERT_TRUE(OCTTransform(ct, 1, &x, &y, &z));
    *lon = x;
    *lat = y;
    OCTDestroyCoordinateTransformation(ct);
    OSRDestroySpatialReference(src);
    OSRDestroySpatialReference(dst);
}

#endif /* TP_TEST_GDAL_H */
