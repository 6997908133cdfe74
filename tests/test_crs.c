/*
 * test_crs.c - tp_crs_describe (io/src/crs.cpp): a CRS's name, EPSG code and kind read through
 * GDAL's OGR, from WKT as the DEM reader writes it, from "EPSG:N", and from WKT without an
 * authority; "" as no CRS; text that is no CRS refused with the output left alone.
 */
#include "tp_test.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#define TESTS(X)                                                                                   \
    X(epsg_codes_give_name_code_and_kind)                                                          \
    X(dem_wkt_matches_the_dem)                                                                     \
    X(wkt_without_authority_is_read_through_ogr)                                                   \
    X(empty_text_is_no_crs)                                                                        \
    X(text_that_is_no_crs_is_refused_and_out_left_alone)

#ifdef TP_TEST_NO_IO
#define TP_CRS_STUB_(name)                                                                         \
    static void test_##name(void)                                                                  \
    {                                                                                              \
        SKIP("built without tp_io");                                                               \
    }
TESTS(TP_CRS_STUB_)
#else

/* Describes crs and checks every field; name NULL: any name. */
static void expect_crs(const char* crs, const char* name, int epsg, int geographic)
{
    tp_crs_info info;
    tp_error err = {{0}};
    memset(&info, 0xCD, sizeof info);
    tp_status s = tp_crs_describe(crs, &info, &err);
    if (s != TP_OK) {
        ADD_FAILURE("tp_crs_describe(%.60s): %s: %s", crs, tp_test_status_name_(s), err.message);
        return;
    }
    if (name)
        EXPECT_EQ_STR(name, info.name);
    EXPECT_EQ_INT(epsg, info.epsg);
    EXPECT_EQ_INT(geographic, info.geographic);
}

TEST(epsg_codes_give_name_code_and_kind)
{
    expect_crs("EPSG:4326", "WGS 84", 4326, 1);
    expect_crs("EPSG:26910", "NAD83 / UTM zone 10N", 26910, 0);
    expect_crs("EPSG:32761", "WGS 84 / UPS South (N,E)", 32761, 0);
}

/* The WKT the DEM reader stores describes the CRS it read. */
static void expect_dem_crs(const char* file, const char* name, int epsg, int geographic)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err = {{0}};
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", file);
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    EXPECT_EQ_INT(epsg, dem->epsg);
    expect_crs(dem->crs_wkt, name, epsg, geographic);
    tp_dem_destroy(dem);
}

TEST(dem_wkt_matches_the_dem)
{
    expect_dem_crs("N42E001.hgt", "WGS 84", 4326, 1);
    expect_dem_crs("lf_elev_220_mt_hood_utm.tif", "NAD83 / UTM zone 10N", 26910, 0);
}

/* A geographic CRS with a datum shift (TOWGS84) is exported as a WKT2 BOUNDCRS: still
 * geographic (reading the first WKT keyword took it for something else). */
TEST(wkt_without_authority_is_read_through_ogr)
{
    expect_crs("GEOGCS[\"Custom Hayford\",DATUM[\"Custom_datum\",SPHEROID[\"International 1924\","
               "6378388,297],TOWGS84[-87,-98,-121,0,0,0,0]],PRIMEM[\"Greenwich\",0],"
               "UNIT[\"degree\",0.0174532925199433]]",
               "Custom Hayford", 0, 1);
    expect_crs("+proj=lcc +lat_1=49 +lat_2=44 +lat_0=46.5 +lon_0=3 +x_0=700000 +y_0=6600000 "
               "+ellps=GRS80 +units=m +no_defs",
               NULL, 0, 0);
}

TEST(empty_text_is_no_crs)
{
    expect_crs("", "", 0, 0);
}

TEST(text_that_is_no_crs_is_refused_and_out_left_alone)
{
    tp_crs_info info, before;
    tp_error err = {{0}};
    memset(&info, 0xCD, sizeof info);
    before = info;
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_crs_describe("PROJCRS[broken", &info, &err));
    EXPECT_CONTAINS(err.message, "PROJCRS[broken");
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_crs_describe("EPSG:999999", &info, NULL));
    EXPECT_TRUE(memcmp(&info, &before, sizeof info) == 0);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_crs_describe(NULL, &info, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_crs_describe("EPSG:4326", NULL, &err));
    EXPECT_CONTAINS(err.message, "tp_crs_describe");
}

#endif /* TP_TEST_NO_IO */

TP_TEST_MAIN(TESTS)
