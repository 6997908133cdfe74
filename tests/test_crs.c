/*
 * test_crs.c - tp_crs_describe (io/src/crs.cpp): a CRS's name, EPSG code and kind read through
 * GDAL's OGR, from WKT as the DEM reader writes it, from "EPSG:N", and from WKT without an
 * authority; "" as no CRS; text that is no CRS refused with the output left alone.
 */
#include "tp_test.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#ifdef TP_TEST_NO_IO
#define REQUIRE_IO() SKIP("built without tp_io")
#else
#define REQUIRE_IO() ((void)0)

static tp_crs_info describe_ok(const char* crs)
{
    tp_crs_info info;
    tp_error err = {{0}};
    memset(&info, 0xCD, sizeof info);
    tp_status s = tp_crs_describe(crs, &info, &err);
    if (s != TP_OK)
        FAIL("tp_crs_describe(%.60s): %s: %s", crs, tp_test_status_name_(s), err.message);
    return info;
}
#endif

TEST(epsg_codes_give_name_code_and_kind)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    tp_crs_info wgs84 = describe_ok("EPSG:4326");
    EXPECT_EQ_STR("WGS 84", wgs84.name);
    EXPECT_EQ_INT(4326, wgs84.epsg);
    EXPECT_EQ_INT(1, wgs84.geographic);
    tp_crs_info hood = describe_ok("EPSG:26910");
    EXPECT_EQ_STR("NAD83 / UTM zone 10N", hood.name);
    EXPECT_EQ_INT(26910, hood.epsg);
    EXPECT_EQ_INT(0, hood.geographic);
    tp_crs_info ups = describe_ok("EPSG:32761");
    EXPECT_CONTAINS(ups.name, "UPS South");
    EXPECT_EQ_INT(0, ups.geographic);
#endif
}

/* The WKT the DEM reader stores describes the CRS it read: same EPSG code, geographic. */
TEST(dem_wkt_matches_the_dem)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err = {{0}};
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    tp_crs_info info = describe_ok(dem->crs_wkt);
    EXPECT_EQ_STR("WGS 84", info.name);
    EXPECT_EQ_INT(dem->epsg, info.epsg);
    EXPECT_EQ_INT(1, info.geographic);
    tp_dem_destroy(dem);
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    info = describe_ok(dem->crs_wkt);
    EXPECT_EQ_STR("NAD83 / UTM zone 10N", info.name);
    EXPECT_EQ_INT(26910, info.epsg);
    EXPECT_EQ_INT(0, info.geographic);
    tp_dem_destroy(dem);
#endif
}

/* A geographic CRS with a datum shift (TOWGS84) is exported as a WKT2 BOUNDCRS: still
 * geographic (text parsing by the first keyword took it for projected). */
TEST(wkt_without_authority_is_read_through_ogr)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    tp_crs_info bound = describe_ok(
        "GEOGCS[\"Custom Hayford\",DATUM[\"Custom_datum\",SPHEROID[\"International 1924\","
        "6378388,297],TOWGS84[-87,-98,-121,0,0,0,0]],PRIMEM[\"Greenwich\",0],"
        "UNIT[\"degree\",0.0174532925199433]]");
    EXPECT_EQ_STR("Custom Hayford", bound.name);
    EXPECT_EQ_INT(1, bound.geographic);
    tp_crs_info lcc = describe_ok("+proj=lcc +lat_1=49 +lat_2=44 +lat_0=46.5 +lon_0=3 "
                                  "+x_0=700000 +y_0=6600000 +ellps=GRS80 +units=m +no_defs");
    EXPECT_EQ_INT(0, lcc.geographic);
#endif
}

TEST(empty_text_is_no_crs)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    tp_crs_info none = describe_ok("");
    EXPECT_EQ_STR("", none.name);
    EXPECT_EQ_INT(0, none.epsg);
    EXPECT_EQ_INT(0, none.geographic);
#endif
}

TEST(text_that_is_no_crs_is_refused_and_out_left_alone)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
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
#endif
}

#define TESTS(X)                                                                                   \
    X(epsg_codes_give_name_code_and_kind)                                                          \
    X(dem_wkt_matches_the_dem)                                                                     \
    X(wkt_without_authority_is_read_through_ogr)                                                   \
    X(empty_text_is_no_crs)                                                                        \
    X(text_that_is_no_crs_is_refused_and_out_left_alone)
TP_TEST_MAIN(TESTS)
