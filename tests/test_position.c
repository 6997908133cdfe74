/*
 * test_position.c - positions as the command line reads them (app/position.c: every command
 * that takes a position) and the DMS reader and writer behind them (tp_geo.h, GeographicLib's
 * DMS class).
 *
 * Expected values are worked out by hand (40d26'46" = 40 + 26/60 + 46/3600 degrees) or taken
 * from GeographicLib's own GeoConvert tests (data/coord/geoconvert_ctest_cases.tsv:
 * GeoConvert1, GeoConvert2), never from this code.
 */
#include "tp_test.h"
#include "tp_geo.h"

#include "position.h"

#include <string.h>

#define LAT_PITTSBURGH (40.0 + 26.0 / 60.0 + 46.0 / 3600.0)   /* 40d26'46"N */
#define LON_PITTSBURGH (-(79.0 + 58.0 / 60.0 + 56.0 / 3600.0)) /* 79d58'56"W */
#define TOL_DEG 1e-12

static tp_position parse_ok(const char* text)
{
    tp_position p;
    char msg[TP_POSITION_MSG_SIZE] = "";
    int ok = tp_position_parse(text, strlen(text), 0, &p, msg, sizeof msg);
    if (!ok)
        FAIL("'%s' not read: %s", text, msg);
    return p;
}

/* Parses text expecting failure; the message must contain `needle`; out left alone. */
static void parse_fails(const char* text, int allow_height, const char* needle)
{
    tp_position p;
    memset(&p, 0x5A, sizeof p);
    tp_position before = p;
    char msg[TP_POSITION_MSG_SIZE] = "";
    EXPECT_FALSE(tp_position_parse(text, strlen(text), allow_height, &p, msg, sizeof msg));
    EXPECT_CONTAINS(msg, needle);
    EXPECT_TRUE(memcmp(&p, &before, sizeof p) == 0);
}

TEST(dms_with_symbols_and_hemispheres)
{
    tp_position p = parse_ok("40d26'46\"N 79d58'56\"W");
    EXPECT_NEAR(p.lat_deg, LAT_PITTSBURGH, TOL_DEG);
    EXPECT_NEAR(p.lon_deg, LON_PITTSBURGH, TOL_DEG);
    EXPECT_FALSE(p.has_grid);
    /* hemisphere letters before the number, and the Unicode degree, prime, double prime */
    p = parse_ok("N40d26'46\" W79d58'56\"");
    EXPECT_NEAR(p.lat_deg, LAT_PITTSBURGH, TOL_DEG);
    EXPECT_NEAR(p.lon_deg, LON_PITTSBURGH, TOL_DEG);
    p = parse_ok("40\xC2\xB0" "26\xE2\x80\xB2" "46\xE2\x80\xB3N 79\xC2\xB0" "58\xE2\x80\xB2"
                 "56\xE2\x80\xB3W");
    EXPECT_NEAR(p.lat_deg, LAT_PITTSBURGH, TOL_DEG);
    EXPECT_NEAR(p.lon_deg, LON_PITTSBURGH, TOL_DEG);
}

TEST(dms_with_colons_and_signs)
{
    tp_position p = parse_ok("40:26:46N 79:58:56W");
    EXPECT_NEAR(p.lat_deg, LAT_PITTSBURGH, TOL_DEG);
    EXPECT_NEAR(p.lon_deg, LON_PITTSBURGH, TOL_DEG);
    p = parse_ok("-40:26:46 -79:58:56"); /* signs instead of letters: 40d26'46"S 79d58'56"W */
    EXPECT_NEAR(p.lat_deg, -LAT_PITTSBURGH, TOL_DEG);
    EXPECT_NEAR(p.lon_deg, LON_PITTSBURGH, TOL_DEG);
    p = parse_ok("40d26.5'S 079d58.25'E"); /* decimal minutes */
    EXPECT_NEAR(p.lat_deg, -(40.0 + 26.5 / 60.0), TOL_DEG);
    EXPECT_NEAR(p.lon_deg, 79.0 + 58.25 / 60.0, TOL_DEG);
}

TEST(hemisphere_letters_allow_longitude_first)
{
    tp_position p = parse_ok("79:58:56W 40:26:46N");
    EXPECT_NEAR(p.lat_deg, LAT_PITTSBURGH, TOL_DEG);
    EXPECT_NEAR(p.lon_deg, LON_PITTSBURGH, TOL_DEG);
}

TEST(lat_comma_lon_as_geoconvert)
{
    const char* forms[] = {"45.5,-122.68", "45.5, -122.68", "45.5 ,-122.68", " 45.5,,-122.68 "};
    for (size_t i = 0; i < sizeof forms / sizeof forms[0]; ++i) {
        tp_position p = parse_ok(forms[i]);
        EXPECT_NEAR(p.lat_deg, 45.5, TOL_DEG);
        EXPECT_NEAR(p.lon_deg, -122.68, TOL_DEG);
    }
    tp_position p = parse_ok("40d26'46\"N,79d58'56\"W");
    EXPECT_NEAR(p.lat_deg, LAT_PITTSBURGH, TOL_DEG);
}

/* GeographicLib's ctest GeoConvert2: input 30d30'30" 30.50833, expected 30.508 30.508 at -p -2
 * (3 decimals). */
TEST(geoconvert2_mixed_dms_and_decimal)
{
    tp_position p = parse_ok("30d30'30\" 30.50833");
    EXPECT_NEAR(p.lat_deg, 30.508, 0.0005);
    EXPECT_NEAR(p.lon_deg, 30.508, 0.0005);
    EXPECT_NEAR(p.lat_deg, 30.5 + 30.0 / 3600.0, TOL_DEG);
}

/* GeographicLib's ctest GeoConvert1: GeoConvert -d on 38smb prints 32d59'14.1"N 044d27'53.4"E
 * (DMS to 0.1"). */
TEST(geoconvert1_mgrs_written_as_dms)
{
    tp_position p = parse_ok("38smb");
    char lat[TP_DMS_TEXT_SIZE], lon[TP_DMS_TEXT_SIZE];
    ASSERT_OK(tp_dms_encode(p.lat_deg, TP_DMS_LATITUDE, 1, lat, sizeof lat, NULL));
    ASSERT_OK(tp_dms_encode(p.lon_deg, TP_DMS_LONGITUDE, 1, lon, sizeof lon, NULL));
    EXPECT_EQ_STR("32d59'14.1\"N", lat);
    EXPECT_EQ_STR("044d27'53.4\"E", lon);
}

TEST(dms_encode_rounds_and_signs)
{
    char out[TP_DMS_TEXT_SIZE];
    ASSERT_OK(tp_dms_encode(LAT_PITTSBURGH, TP_DMS_LATITUDE, 0, out, sizeof out, NULL));
    EXPECT_EQ_STR("40d26'46\"N", out);
    ASSERT_OK(tp_dms_encode(LON_PITTSBURGH, TP_DMS_LONGITUDE, 0, out, sizeof out, NULL));
    EXPECT_EQ_STR("079d58'56\"W", out);
    ASSERT_OK(tp_dms_encode(-0.5, TP_DMS_PLAIN, 0, out, sizeof out, NULL));
    EXPECT_EQ_STR("-0d30'00\"", out);
    /* bad input leaves out alone */
    strcpy(out, "keep");
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dms_encode(91.0, TP_DMS_LATITUDE, 0, out, sizeof out, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dms_encode(NAN, TP_DMS_PLAIN, 0, out, sizeof out, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dms_encode(10.0, TP_DMS_PLAIN, 0, out, 4, &err));
    EXPECT_EQ_STR("keep", out);
}

TEST(decimal_forms_kept)
{
    tp_position p = parse_ok("45.5 -122.68");
    EXPECT_NEAR(p.lat_deg, 45.5, TOL_DEG);
    EXPECT_NEAR(p.lon_deg, -122.68, TOL_DEG);
    p = parse_ok("0 540"); /* reduced to [-180, 180] */
    EXPECT_NEAR(p.lon_deg, 180.0, TOL_DEG);
    p = parse_ok("33n 500000 4649776.22");
    EXPECT_TRUE(p.has_grid);
    EXPECT_EQ_INT(33, p.zone);
    EXPECT_EQ_INT(1, p.northp);
    EXPECT_EQ_DBL(500000.0, p.easting_m);
    /* E N ZONE, as GeoConvert also reads it */
    p = parse_ok("500000 4649776.22 33n");
    EXPECT_TRUE(p.has_grid);
    EXPECT_EQ_INT(33, p.zone);
    EXPECT_EQ_DBL(4649776.22, p.northing_m);
    EXPECT_NEAR(p.lat_deg, 42.0, 1e-6); /* coord's documented example: 41.999999957 15 */
    EXPECT_NEAR(p.lon_deg, 15.0, 1e-9);
    p = parse_ok("33TWN0000049776");
    EXPECT_TRUE(p.has_grid);
    EXPECT_EQ_INT(33, p.zone);
    EXPECT_TRUE(p.lat_deg >= 40.0 && p.lat_deg < 48.0); /* band T */
}

TEST(bad_positions_say_why)
{
    parse_fails("40N 41N", 0, "Both 40N and 41N interpreted as latitudes");
    parse_fails("91d 0", 0, "91");
    parse_fails("91 0", 0, "latitude 91 is outside [-90, 90]");
    parse_fails("garbage here", 0, "latitude: expected decimal degrees or degrees-minutes");
    parse_fails("nan 3", 0, "got 'nan'");
    parse_fails("inf 0d", 0, "");
    parse_fails("40d61'N 3", 0, "");
    /* GeographicLib 2.1.2 writes past its arrays on a ':' after the seconds (found by
     * tests/fuzz/fuzz_position): refused before it is called */
    parse_fails("7\"9:58:56W 40:26:46N", 0, "more than 3 components");
    parse_fails("1:2:3:4 5", 0, "more than 3 components");
    parse_fails("1`41:2:3:4.3424%5 52n", 0, "more than 3 components"); /* fuzz_position */
    parse_fails("40d26:46 79:58:56W", 0, "more than 3 components"); /* marks and colons */
    tp_position ok = parse_ok("40:26:46N 79:58:56W");
    EXPECT_NEAR(ok.lat_deg, LAT_PITTSBURGH, TOL_DEG);
    parse_fails("1''2:3 5", 0, "more than 3 components");
    parse_fails("", 0, "got an empty line");
    parse_fails("1 2 3 4", 0, "got 4 fields");
    parse_fails("45 7 100", 0, "are not a position here");
    parse_fails("33T", 0, "grid zone designator");
    parse_fails("61n 500000 0", 0, "UTM zone 61 is outside [1, 60]");
    tp_position p;
    char msg[TP_POSITION_MSG_SIZE];
    EXPECT_FALSE(tp_position_parse("45\0 7", 5, 0, &p, msg, sizeof msg));
    EXPECT_CONTAINS(msg, "NUL");
    /* LAT LON H where heights are allowed */
    ASSERT_TRUE(tp_position_parse("45 7 100", 8, 1, &p, msg, sizeof msg));
    EXPECT_TRUE(p.has_h);
    EXPECT_EQ_DBL(100.0, p.h_m);
}

TEST(dms_decode_rejects_nan_and_long_text)
{
    double lat = -7, lon = -7;
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dms_decode_latlon("nan", "0", &lat, &lon, &err));
    char longtext[100];
    memset(longtext, '1', sizeof longtext - 1);
    longtext[sizeof longtext - 1] = '\0';
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dms_decode_latlon(longtext, "0", &lat, &lon, &err));
    EXPECT_CONTAINS(err.message, "too long");
    EXPECT_EQ_DBL(-7.0, lat);
    EXPECT_EQ_DBL(-7.0, lon);
}

TEST(mgrs_with_spaces)
{
    char out[TP_POSITION_MGRS_SPACED_SIZE];
    ASSERT_TRUE(tp_position_mgrs_spaced("31TCH7665100831", out, sizeof out));
    EXPECT_EQ_STR("31T CH 76651 00831", out);
    ASSERT_TRUE(tp_position_mgrs_spaced("4QFJ12345678", out, sizeof out));
    EXPECT_EQ_STR("4Q FJ 1234 5678", out);
    ASSERT_TRUE(tp_position_mgrs_spaced("ZAA0000033272", out, sizeof out));
    EXPECT_EQ_STR("Z AA 00000 33272", out);
    ASSERT_TRUE(tp_position_mgrs_spaced("38SMB", out, sizeof out));
    EXPECT_EQ_STR("38S MB", out);
    strcpy(out, "keep");
    EXPECT_FALSE(tp_position_mgrs_spaced("31TCH766510083", out, sizeof out)); /* odd digits */
    EXPECT_FALSE(tp_position_mgrs_spaced("31T", out, sizeof out));
    EXPECT_FALSE(tp_position_mgrs_spaced("31TCH7665100831", out, 10));
    EXPECT_EQ_STR("keep", out);
    /* and read back in every spacing, as the one-token form */
    tp_position a = parse_ok("31TCH7665100831");
    const char* spaced[] = {"31T CH 76651 00831", "31TCH 76651 00831", "31T CH7665100831",
                            "31t ch 76651 00831"};
    for (int i = 0; i < 4; i++) {
        tp_position b = parse_ok(spaced[i]);
        EXPECT_EQ_DBL(a.lat_deg, b.lat_deg);
        EXPECT_EQ_DBL(a.lon_deg, b.lon_deg);
    }
    tp_position u = parse_ok("Z AA 00000 33272"); /* UPS north */
    EXPECT_TRUE(u.lat_deg > 83.0);
    tp_position g = parse_ok("n 2000000 2000000"); /* a UPS grid position, not MGRS */
    EXPECT_TRUE(g.has_grid);
    EXPECT_EQ_DBL(90.0, g.lat_deg);
    parse_fails("31T CH 7665 00831", 0, "MGRS"); /* easting and northing of different lengths */
}

#define TESTS(X)                                                                                   \
    X(dms_with_symbols_and_hemispheres)                                                            \
    X(dms_with_colons_and_signs)                                                                   \
    X(hemisphere_letters_allow_longitude_first)                                                    \
    X(lat_comma_lon_as_geoconvert)                                                                 \
    X(geoconvert2_mixed_dms_and_decimal)                                                           \
    X(geoconvert1_mgrs_written_as_dms)                                                             \
    X(dms_encode_rounds_and_signs)                                                                 \
    X(decimal_forms_kept)                                                                          \
    X(bad_positions_say_why)                                                                       \
    X(dms_decode_rejects_nan_and_long_text)                                                        \
    X(mgrs_with_spaces)
TP_TEST_MAIN(TESTS)
