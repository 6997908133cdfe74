/*
 * test_vector.c - tp_vector_read (io/src/vector_read.cpp) on the small files of data/vectors
 * (Andorra, inside N42E001) and on files written here with OGR's C API. Coordinates are checked
 * against GeographicLib's UTM (tp_geo_to_utmups, not OGR/PROJ) of the latitude/longitude typed
 * in the files; the target is WGS 84 / UTM zone 31N, the render CRS of N42E001.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"
#include "tp_geo.h"
#include "tp_io.h"
#include "tp_vector.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static char g_dir[64];

static const char* tmp_dir(void)
{
    if (!g_dir[0]) {
        strcpy(g_dir, "/tmp/tp_test_vectorXXXXXX");
        if (!mkdtemp(g_dir))
            FAIL("mkdtemp failed");
    }
    return g_dir;
}

/* WKT of EPSG:code (the caller frees it with CPLFree). */
static char* epsg_wkt(int code)
{
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    ASSERT_TRUE(OSRImportFromEPSG(srs, code) == OGRERR_NONE);
    char* wkt = NULL;
    OSRExportToWkt(srs, &wkt);
    OSRDestroySpatialReference(srs);
    return wkt;
}

static tp_features* read_ok(const char* file, int epsg)
{
    char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", file);
    char* wkt = epsg_wkt(epsg);
    tp_features* f = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    tp_status s = tp_vector_read(path, wkt, &f, &err);
    CPLFree(wkt);
    if (s != TP_OK)
        FAIL("tp_vector_read(%s): %s", path, err.message);
    ASSERT_TRUE(f != NULL);
    return f;
}

/* Vertex i of feature k is (lat, lon) in UTM 31N, to a millimetre (GeographicLib vs PROJ). */
static void expect_vertex(const tp_features* f, size_t k, size_t i, double lat, double lon)
{
    int zone, northp;
    double e, n;
    ASSERT_OK(tp_geo_to_utmups(lat, lon, &zone, &northp, &e, &n, NULL));
    ASSERT_EQ_INT(31, zone); /* the standard zone of the whole of N42E001's east half too */
    ASSERT_TRUE(i < f->items[k].count);
    const double* v = f->xy + 2 * (f->items[k].first + i);
    EXPECT_NEAR(e, v[0], 1e-3);
    EXPECT_NEAR(n, v[1], 1e-3);
}

static void expect_name(const tp_feature* it, const char* name)
{
    if (!name) {
        EXPECT_TRUE(it->name == NULL);
        return;
    }
    ASSERT_TRUE(it->name != NULL);
    EXPECT_EQ_STR(name, it->name);
}

TEST(gpx_waypoint_and_track)
{
    tp_features* f = read_ok("vectors/coma_pedrosa.gpx", 32631);
    /* waypoints, then tracks; route_points and track_points skipped (else 2 + 7 points) */
    ASSERT_EQ_INT(2, (int)f->count);
    EXPECT_EQ_INT(TP_FEATURE_POINT, f->items[0].kind);
    EXPECT_EQ_INT(1, (int)f->items[0].count);
    expect_name(&f->items[0], "Pic de Coma Pedrosa");
    expect_vertex(f, 0, 0, 42.59306, 1.44417);
    EXPECT_EQ_INT(TP_FEATURE_LINE, f->items[1].kind);
    EXPECT_EQ_INT(7, (int)f->items[1].count);
    expect_name(&f->items[1], "Arinsal to Coma Pedrosa");
    expect_vertex(f, 1, 0, 42.57220, 1.48400);
    expect_vertex(f, 1, 3, 42.58400, 1.46000);
    expect_vertex(f, 1, 6, 42.59306, 1.44417);
    EXPECT_EQ_INT(8, (int)f->vertex_count);
    EXPECT_NAN(f->items[1].value);
    EXPECT_EQ_INT(0, f->items[1].index);
    tp_features_destroy(f);
}

TEST(kml_placemark_and_line)
{
    tp_features* f = read_ok("vectors/andorra.kml", 32631);
    ASSERT_EQ_INT(2, (int)f->count);
    EXPECT_EQ_INT(TP_FEATURE_POINT, f->items[0].kind);
    expect_name(&f->items[0], "Andorra la Vella");
    expect_vertex(f, 0, 0, 42.50630, 1.52180);
    EXPECT_EQ_INT(TP_FEATURE_LINE, f->items[1].kind);
    EXPECT_EQ_INT(4, (int)f->items[1].count);
    expect_name(&f->items[1], "Port d'Envalira road");
    expect_vertex(f, 1, 0, 42.54200, 1.63500);
    expect_vertex(f, 1, 3, 42.54000, 1.71900);
    tp_features_destroy(f);
}

TEST(geojson_polygon_outer_and_inner_ring)
{
    tp_features* f = read_ok("vectors/tristaina.geojson", 32631);
    ASSERT_EQ_INT(2, (int)f->count);
    EXPECT_EQ_INT(TP_FEATURE_RING, f->items[0].kind);
    EXPECT_EQ_INT(4, (int)f->items[0].count); /* 5 in the file: the closing vertex dropped */
    EXPECT_EQ_INT(TP_FEATURE_RING, f->items[1].kind);
    EXPECT_EQ_INT(3, (int)f->items[1].count);
    expect_name(&f->items[0], "Tristaina cirque");
    expect_vertex(f, 0, 0, 42.6350, 1.4750);
    expect_vertex(f, 0, 2, 42.6500, 1.4950);
    expect_vertex(f, 1, 1, 42.6400, 1.4880);
    tp_features_destroy(f);
}

/* Writes a one-point layer (lon, lat in the traditional order) in driver's format. */
static void write_point_file(const char* driver, const char* path, int epsg, double x, double y,
                             const char* name)
{
    OGRRegisterAll();
    GDALDriverH drv = GDALGetDriverByName(driver);
    ASSERT_TRUE(drv != NULL);
    GDALDatasetH ds = GDALCreate(drv, path, 0, 0, 0, GDT_Unknown, NULL);
    ASSERT_TRUE(ds != NULL);
    OGRSpatialReferenceH srs = NULL;
    if (epsg) {
        srs = OSRNewSpatialReference(NULL);
        OSRImportFromEPSG(srs, epsg);
        OSRSetAxisMappingStrategy(srs, OAMS_TRADITIONAL_GIS_ORDER);
    }
    OGRLayerH layer = GDALDatasetCreateLayer(ds, "places", srs, wkbPoint, NULL);
    ASSERT_TRUE(layer != NULL);
    OGRFieldDefnH fd = OGR_Fld_Create("NAME", OFTString);
    OGR_L_CreateField(layer, fd, TRUE);
    OGR_Fld_Destroy(fd);
    OGRFeatureH feat = OGR_F_Create(OGR_L_GetLayerDefn(layer));
    OGR_F_SetFieldString(feat, 0, name);
    OGRGeometryH pt = OGR_G_CreateGeometry(wkbPoint);
    OGR_G_SetPoint_2D(pt, 0, x, y);
    OGR_F_SetGeometryDirectly(feat, pt);
    ASSERT_TRUE(OGR_L_CreateFeature(layer, feat) == OGRERR_NONE);
    OGR_F_Destroy(feat);
    GDALClose(ds);
    if (srs)
        OSRDestroySpatialReference(srs);
}

/* EPSG:4326 is latitude-first by its definition; a GeoPackage stores longitude first. Read
 * without the traditional GIS order on both CRSs, the point lands at (lat, lon) swapped. */
TEST(geopackage_epsg4326_axis_order)
{
    char path[256];
    snprintf(path, sizeof path, "%s/places.gpkg", tmp_dir());
    write_point_file("GPKG", path, 4326, 1.52180, 42.50630, "Andorra la Vella");
    char* wkt = epsg_wkt(32631);
    tp_features* f = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    ASSERT_OK(tp_vector_read(path, wkt, &f, &err));
    CPLFree(wkt);
    ASSERT_EQ_INT(1, (int)f->count);
    expect_name(&f->items[0], "Andorra la Vella"); /* the field is "NAME": any case */
    expect_vertex(f, 0, 0, 42.50630, 1.52180);
    tp_features_destroy(f);
    /* a latitude-first target (EPSG:4326 itself): still E (longitude) first in xy. OGR's
     * drivers already give their layers the traditional order, so only the target's setting
     * is seen here (the source's is kept for layers that come without it) */
    wkt = epsg_wkt(4326);
    ASSERT_OK(tp_vector_read(path, wkt, &f, &err));
    CPLFree(wkt);
    EXPECT_NEAR(1.52180, f->xy[0], 1e-9);
    EXPECT_NEAR(42.50630, f->xy[1], 1e-9);
    tp_features_destroy(f);
}

/* A projected source: ETRS89 / UTM 31N to WGS 84 / UTM 31N (the same numbers within a metre:
 * PROJ's ETRS89 -> WGS 84 is a null or ballpark shift). */
TEST(shapefile_projected_and_without_crs)
{
    char path[256], path2[256];
    snprintf(path, sizeof path, "%s/utm.shp", tmp_dir());
    write_point_file("ESRI Shapefile", path, 25831, 375578.3, 4714423.8, "start");
    char* wkt = epsg_wkt(32631);
    tp_features* f = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    ASSERT_OK(tp_vector_read(path, wkt, &f, &err));
    ASSERT_EQ_INT(1, (int)f->count);
    EXPECT_NEAR(375578.3, f->xy[0], 1.0);
    EXPECT_NEAR(4714423.8, f->xy[1], 1.0);
    tp_features_destroy(f);
    /* no .prj: not placed by guess */
    snprintf(path2, sizeof path2, "%s/nocrs.shp", tmp_dir());
    write_point_file("ESRI Shapefile", path2, 0, 375578.3, 4714423.8, "start");
    f = (tp_features*)(void*)&err; /* a sentinel: must stay as it is */
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_vector_read(path2, wkt, &f, &err));
    EXPECT_TRUE(f == (tp_features*)(void*)&err);
    EXPECT_CONTAINS(err.message, path2);
    EXPECT_CONTAINS(err.message, "has no CRS");
    CPLFree(wkt);
}

TEST(bad_files_are_clear_errors)
{
    char empty[1024], path[256];
    REQUIRE_DATA_FILE(empty, "TP_SAMPLE_DATA_DIR", "vectors/empty.gpx");
    char* wkt = epsg_wkt(32631);
    tp_features* sentinel = (tp_features*)(void*)empty;
    tp_features* f = sentinel;
    tp_error err;
    memset(&err, 0, sizeof err);
    /* an empty GPX: OGR opens it (five empty layers) */
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_vector_read(empty, wkt, &f, &err));
    EXPECT_CONTAINS(err.message, empty);
    EXPECT_CONTAINS(err.message, "no features");
    EXPECT_TRUE(f == sentinel);
    /* garbage */
    snprintf(path, sizeof path, "%s/garbage.gpx", tmp_dir());
    FILE* g = fopen(path, "w");
    ASSERT_TRUE(g != NULL);
    fputs("this is not a track\n\x01\x02\x03", g);
    fclose(g);
    EXPECT_STATUS(TP_ERR_IO, tp_vector_read(path, wkt, &f, &err));
    EXPECT_CONTAINS(err.message, path);
    EXPECT_CONTAINS(err.message, "OGR cannot open it");
    EXPECT_TRUE(f == sentinel);
    /* missing */
    snprintf(path, sizeof path, "%s/missing.kml", tmp_dir());
    EXPECT_STATUS(TP_ERR_IO, tp_vector_read(path, wkt, &f, &err));
    EXPECT_CONTAINS(err.message, "missing.kml: cannot open: No such file or directory");
    /* a raster is not a vector file */
    char dem[1024];
    if (tp_test_data_path(dem, sizeof dem, "TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif")) {
        EXPECT_STATUS(TP_ERR_IO, tp_vector_read(dem, wkt, &f, &err));
        EXPECT_CONTAINS(err.message, "storml_elev_orig.tif");
    }
    /* a latitude beyond the pole does not transform */
    snprintf(path, sizeof path, "%s/pole.geojson", tmp_dir());
    g = fopen(path, "w");
    ASSERT_TRUE(g != NULL);
    fputs("{\"type\":\"FeatureCollection\",\"features\":[{\"type\":\"Feature\",\"properties\":{},"
          "\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[1.5,42.5],[1.5,95.0]]}}]}\n",
          g);
    fclose(g);
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_vector_read(path, wkt, &f, &err));
    EXPECT_CONTAINS(err.message, "pole.geojson");
    EXPECT_CONTAINS(err.message, "do not transform");
    EXPECT_TRUE(f == sentinel);
    /* a DEM without a CRS */
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_vector_read(empty, "", &f, &err));
    EXPECT_CONTAINS(err.message, "no CRS");
    EXPECT_TRUE(f == sentinel);
    CPLFree(wkt);
}

#define TESTS(X)                                                                                   \
    X(gpx_waypoint_and_track)                                                                     \
    X(kml_placemark_and_line)                                                                     \
    X(geojson_polygon_outer_and_inner_ring)                                                       \
    X(geopackage_epsg4326_axis_order)                                                             \
    X(shapefile_projected_and_without_crs)                                                        \
    X(bad_files_are_clear_errors)
TP_TEST_MAIN(TESTS)
