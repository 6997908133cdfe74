/*
 * test_position.c - positions as the command line reads them (app/base/position.c: every command
 * that takes a position) and the DMS reader and writer behind them (tp_geo.h, GeographicLib's
 * DMS class).
 *
 * Expected values are worked out by hand (40d26'46" = 40 + 26/60 + 46/3600 degrees) or taken
 * from GeographicLib's own GeoConvert tests (data/coord/geoconvert_ctest_cases.tsv:
 * GeoConvert1, GeoConvert2), never from this code.
 */
#include "tp_geo.h"
#include "tp_test.h"

#include "coord_line.h"
#include "position.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define LAT_PITTSBURGH (40.0 + 26.0 / 60.0 + 46.0 / 3600.0)    /* 40d26'46"N */
#define LON_PITTSBURGH (-(79.0 + 58.0 / 60.0 + 56.0 / 3600.0)) /* 79d58'56"W */
#define TOL_DEG 1e-12

static tp_position parse_ok(const char* text)
{
    tp_position p;
    tp_error err = {{0}};
    int ok = tp_position_parse(text, strlen(text), 0, &p, &err);
    if (!ok)
        FAIL("'%s' not read: %s", text, err.message);
    return p;
}

/* Parses text expecting failure; the message must contain `needle`; out left alone. */
static void parse_fails(const char* text, int allow_height, const char* needle)
{
    tp_position p;
    memset(&p, 0x5A, sizeof p);
    tp_position before = p;
    tp_error err = {{0}};
    EXPECT_FALSE(tp_position_parse(text, strlen(text), allow_height, &p, &err));
    EXPECT_CONTAINS(err.message, needle);
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
    p = parse_ok("40\xC2\xB0"
                 "26\xE2\x80\xB2"
                 "46\xE2\x80\xB3N 79\xC2\xB0"
                 "58\xE2\x80\xB2"
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
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_dms_encode(91.0, TP_DMS_LATITUDE, 0, out, sizeof out, &err));
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
    parse_fails("40d26:46 79:58:56W", 0, "more than 3 components");    /* marks and colons */
    tp_position ok = parse_ok("40:26:46N 79:58:56W");
    EXPECT_NEAR(ok.lat_deg, LAT_PITTSBURGH, TOL_DEG);
    parse_fails("1''2:3 5", 0, "more than 3 components");
    parse_fails("", 0, "the position is empty");
    parse_fails(" ,  ", 0, "the position is empty");
    parse_fails("1 2 3 4", 0, "got 4 fields");
    parse_fails("45 7 100", 0, "are not a position here");
    parse_fails("33T", 0, "grid zone designator");
    parse_fails("61n 500000 0", 0, "UTM zone 61 is outside [1, 60]");
    tp_position p;
    tp_error err = {{0}};
    EXPECT_FALSE(tp_position_parse("45\0 7", 5, 0, &p, &err));
    EXPECT_CONTAINS(err.message, "NUL");
    /* LAT LON H where heights are allowed */
    ASSERT_TRUE(tp_position_parse("45 7 100", 8, 1, &p, &err));
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

/* ---- every form a command prints reads back (issue 29, section 2) ---- */

/* Reads text (one reading) and checks it is (lat, lon) within tol_m metres on the ground
 * (a degree of latitude is 111 km or more; longitude 180 is -180). */
static void reads_as(const char* text, double lat, double lon, double tol_m)
{
    tp_position p = parse_ok(text);
    const double dn = (p.lat_deg - lat) * 111000.0;
    const double de =
        remainder(p.lon_deg - lon, 360.0) * 111000.0 * cos(lat * 3.14159265358979323846 / 180.0);
    if (sqrt(dn * dn + de * de) > tol_m)
        FAIL("'%s' read as %.9f %.9f, expected %.9f %.9f (+- %g m)", text, p.lat_deg, p.lon_deg,
             lat, lon, tol_m);
}

/* `coord`'s output lines (tp_coord_line_convert, every --to but ecef) and `point`'s text
 * forms (built by the calls point_readout.c's describe() makes and printed with
 * tp_point_readout_text's formats: DMS to 0.01", "ZONE E.E E N.N N" with the zone as
 * TP_ZONE_STYLE_SHORT, MGRS spaced and not), for positions near a zone edge, in the southern
 * hemisphere (band S's rows: the ambiguous letter), at Norway's and Svalbard's exceptions and
 * in both UPS regions, each read back within the printed precision. */
TEST(every_printed_form_reads_back)
{
    static const double where[][2] = {
        {42.5, 1.5},   {45.0, 5.9999999},   {45.0, 6.0000001}, {-54.148, 15.0},
        {-33.9, 18.4}, {-0.0000001, -70.0}, {60.0, 3.5},       {78.0, 9.1},
        {85.0, 30.0},  {-85.0, -30.0},      {83.99, -179.5},   {-36.1447, 15.0},
    };
    for (size_t i = 0; i < sizeof where / sizeof where[0]; ++i) {
        const double lat = where[i][0], lon = where[i][1];
        char line[64], out[TP_COORD_TEXT_SIZE], text[256];
        /* coord --to geo, utm, mgrs (precision 5, and 11: micrometres) */
        static const tp_coord_request reqs[] = {{.to = TP_COORD_TO_GEO},
                                                {.to = TP_COORD_TO_UTM},
                                                {.to = TP_COORD_TO_MGRS, .precision = 5},
                                                {.to = TP_COORD_TO_MGRS, .precision = 11}};
        static const double tol[] = {1e-3, 2e-3, 1.0, 1e-5}; /* metres: 9 decimals of a degree,
                                                                 3 of a metre, MGRS's square */
        for (size_t k = 0; k < sizeof reqs / sizeof reqs[0]; ++k) {
            snprintf(line, sizeof line, "%.10f %.10f", lat, lon);
            ASSERT_TRUE(tp_coord_line_convert(&reqs[k], line, strlen(line), out, sizeof out, NULL));
            reads_as(out, lat, lon, tol[k]);
        }
        /* point: latitude/longitude in DMS, UTM with its labels, MGRS with spaces */
        char a[TP_DMS_TEXT_SIZE], b[TP_DMS_TEXT_SIZE], zone[TP_ZONE_TEXT_SIZE];
        char mgrs[TP_MGRS_SIZE], spaced[TP_POSITION_MGRS_SPACED_SIZE];
        int z, northp;
        double e, n;
        ASSERT_OK(tp_dms_encode(lat, TP_DMS_LATITUDE, 2, a, sizeof a, NULL));
        ASSERT_OK(tp_dms_encode(lon, TP_DMS_LONGITUDE, 2, b, sizeof b, NULL));
        snprintf(text, sizeof text, "%s  %s", a, b);
        reads_as(text, lat, lon, 0.32); /* 0.01" */
        ASSERT_OK(tp_geo_to_utmups(lat, lon, &z, &northp, &e, &n, NULL));
        ASSERT_OK(tp_zone_format(z, northp, TP_ZONE_STYLE_SHORT, zone, sizeof zone, NULL));
        snprintf(text, sizeof text, "%s %.1f E %.1f N", zone, e, n);
        reads_as(text, lat, lon, 0.11);
        snprintf(text, sizeof text, "UTM        %s %.1f E %.1f N", zone, e, n);
        reads_as(text, lat, lon, 0.11);
        snprintf(text, sizeof text, "UTM %s %.0f %.0f", zone, e, n); /* the viewer's HUD */
        reads_as(text, lat, lon, 1.0);
        ASSERT_OK(tp_mgrs_forward(z, northp, e, n, lat, 5, mgrs, sizeof mgrs, NULL));
        ASSERT_TRUE(tp_position_mgrs_spaced(mgrs, spaced, sizeof spaced));
        reads_as(spaced, lat, lon, 1.0);
        reads_as(mgrs, lat, lon, 1.0);
        snprintf(text, sizeof text, "MGRS       %s", spaced);
        reads_as(text, lat, lon, 1.0);
    }
}

/* `point`'s UTM line as it was printed before (upper-case hemisphere) and as GPS units and maps
 * label their numbers: the same grid position as "ZONE E N". */
TEST(utm_with_labels)
{
    tp_position plain = parse_ok("30n 554001.9 6148350.0");
    const char* forms[] = {"30N 554001.9 E 6148350.0 N", "30n 554001.9E 6148350.0N",
                           "30U 554001.9mE 6148350.0mN", "UTM 30n 554001.9 e 6148350.0 n",
                           "30north 554001.9 6148350.0", "554001.9 6148350.0 30U"};
    for (size_t i = 0; i < sizeof forms / sizeof forms[0]; ++i) {
        tp_position p = parse_ok(forms[i]);
        EXPECT_TRUE(p.has_grid);
        EXPECT_EQ_INT(30, p.zone);
        EXPECT_EQ_INT(1, p.northp);
        EXPECT_EQ_DBL(554001.9, p.easting_m);
        EXPECT_EQ_DBL(6148350.0, p.northing_m);
        EXPECT_EQ_DBL(plain.lat_deg, p.lat_deg);
    }
    /* the example: 55 28 41.88 N 2 08 44.16 W is that position (to 0.1 m) */
    EXPECT_NEAR(plain.lat_deg, 55.0 + 28.0 / 60.0 + 41.88 / 3600.0, 0.005 / 3600.0);
    EXPECT_NEAR(plain.lon_deg, -(2.0 + 8.0 / 60.0 + 44.16 / 3600.0), 0.01 / 3600.0);
    /* UPS as point prints it */
    tp_position u = parse_ok("UPS n 2000000.0 E 1333272.3 N");
    EXPECT_EQ_INT(TP_ZONE_UPS, u.zone);
    EXPECT_NEAR(u.lat_deg, 84.0, 1e-6); /* GeoConvert: 84 0 is n 2000000 1333272.296 */
    u = parse_ok("UPS S 2000000.0 E 3112951.0 N");
    EXPECT_NEAR(u.lat_deg, -80.0, 1e-5); /* -80.000001 0 is s 2000000 3112951.025 */
    parse_fails("33n 500000 E", 0, "northing is missing");
    parse_fails("33n 500000 E 4000000 N 7", 0, "unexpected '7' after the northing");
    parse_fails("33n 5000x0 4649776", 0, "easting: expected a decimal number, got '5000x0'");
}

/* The latitude band of a grid position, as maps and GPS units write it: each band C..X is in
 * its own hemisphere (C..M south, N..X north), the position must lie in the band, and S alone
 * (band S or GeographicLib's south) is refused where both readings are positions. */
TEST(every_band_letter)
{
    static const char bands[] = "CDEFGHJKLMNPQRSTUVWX";
    for (int k = 0; bands[k]; ++k) {
        const char band = bands[k];
        const double lat = band == 'X' ? 78.0 : -76.0 + 8.0 * k; /* the band's middle */
        int z, northp;
        double e, n;
        ASSERT_OK(tp_geo_to_utmups(lat, 15.0, &z, &northp, &e, &n, NULL));
        ASSERT_EQ_INT(33, z);
        EXPECT_EQ_INT(band >= 'N', northp);
        char text[96];
        tp_error err = {{0}};
        snprintf(text, sizeof text, "33%c %.3f %.3f", band, e, n);
        tp_position_readings r;
        ASSERT_TRUE(tp_position_parse_readings(text, strlen(text), 0, &r, &err));
        EXPECT_NEAR(r.reading[0].lat_deg, lat, 1e-7);
        EXPECT_NEAR(r.reading[0].lon_deg, 15.0, 1e-7);
        EXPECT_EQ_INT(band >= 'N', r.reading[0].northp);
        if (band == 'S') {
            /* and the southern hemisphere's reading: the northing 10000 km further south */
            ASSERT_EQ_INT(2, r.count);
            EXPECT_EQ_INT(0, r.reading[1].northp);
            double lat_s, lon_s;
            ASSERT_OK(tp_geo_from_utmups(33, 0, e, n, &lat_s, &lon_s, NULL));
            EXPECT_NEAR(r.reading[1].lat_deg, lat_s, 1e-7); /* E, N printed to 1 mm */
            EXPECT_TRUE(lat_s < -50.0);
            parse_fails(text, 0, "is ambiguous: band S (36.0");
        } else {
            EXPECT_EQ_INT(1, r.count);
            tp_position p = parse_ok(text);
            EXPECT_NEAR(p.lat_deg, lat, 1e-7);
            /* lower case reads as the band too, but n and s: GeographicLib's hemisphere */
            text[2] = (char)(band + ('a' - 'A'));
            p = parse_ok(text);
            EXPECT_NEAR(p.lat_deg, lat, 1e-7);
        }
        /* the next band's letter: not where the position lies */
        if (bands[k + 1] && band != 'M' && band != 'R') {
            snprintf(text, sizeof text, "33%c %.3f %.3f", bands[k + 1], e, n);
            parse_fails(text, 0, "not in band");
        }
    }
    /* the examples; a southern band reads south (19J: 32S..24S) */
    reads_as("30U 554001.9 6148350.0", 55.0 + 28.0 / 60.0 + 41.88 / 3600.0,
             -(2.0 + 8.0 / 60.0 + 44.16 / 3600.0), 0.32); /* the 55 28 41.88 N ... */
    tp_position j = parse_ok("19J 300000 6900000");
    EXPECT_EQ_INT(0, j.northp);
    EXPECT_TRUE(j.lat_deg >= -32.0 && j.lat_deg < -24.0);
    tp_position js = parse_ok("19s 300000 6900000");
    EXPECT_EQ_DBL(js.lat_deg, j.lat_deg);
    /* GeoConvert 2.1.2 (utm_mgrs_edgecases_geoconvert212.txt): the MGRS band with UTM E N */
    reads_as("32V 193458.670 6664167.679", 60.0, 3.5, 1e-3);
    reads_as("31X 636716.846 8665261.550", 78.0, 8.9, 1e-3);
    reads_as("31C 441867.779 1116915.156", -79.999999, 0.0, 1e-3);
    reads_as("01N 166021.443 0.000", 0.0, -180.0, 1e-3);
    reads_as("Z 2000000.000 1333272.296", 84.0, 0.0, 1e-3);       /* UPS bands: ZAA0000033272 */
    reads_as("B 2000000.000 3112951.025", -80.000001, 0.0, 1e-3); /* BAZ0000012951 */
    parse_fails("Y 2000000.000 1333272.296", 0, "not in band Y"); /* Y is west of 0 */
    /* S where only one reading is a position: 54N is no band S, so the south */
    tp_position s = parse_ok("33S 500000 6000000");
    EXPECT_EQ_INT(0, s.northp);
    EXPECT_TRUE(s.lat_deg < -36.0 && s.lat_deg > -37.0);
}

/* The example: 33S 500000 4000000 is 36.1N on a map, 54.1S in GeographicLib's notation;
 * refused naming both, and each written unambiguously reads. */
TEST(ambiguous_band_s_names_both)
{
    parse_fails("33S 500000 4000000", 0, "'33S' is ambiguous: band S (36.14");
    parse_fails("33S 500000 4000000", 0, "zone 33 south (-54.14");
    parse_fails("33S 500000 4000000", 0, "write 33north or 33south");
    reads_as("33north 500000 4000000", 36.144718, 15.0, 0.2);
    reads_as("33n 500000 4000000", 36.144718, 15.0, 0.2);
    reads_as("33south 500000 4000000", -54.148104, 15.0, 0.2);
    reads_as("33s 500000 4000000", -54.148104, 15.0, 0.2);
    /* MGRS names its band: no doubt (33S WA and 33F WA are those two squares) */
    reads_as("33SWA0000000000", 36.144718, 15.0, 1.0);
    reads_as("33FWA0000000000", -54.148104, 15.0, 1.0);
    /* both readings, for a command with a DEM to choose */
    tp_position_readings r;
    char name[128];
    tp_error err = {{0}};
    ASSERT_TRUE(tp_position_parse_readings("33S 500000 4000000", 18, 0, &r, &err));
    ASSERT_EQ_INT(2, r.count);
    EXPECT_CONTAINS(err.message, "ambiguous");
    tp_position_reading_text(&r, 0, name, sizeof name);
    EXPECT_EQ_STR("band S (36.144718 15.000000)", name);
    tp_position_reading_text(&r, 1, name, sizeof name);
    EXPECT_EQ_STR("zone 33 south (-54.148104 15.000000)", name);
}

/* Degrees, minutes and seconds with spaces between them; 55 28 41.88 N is
 * 55 + 28/60 + 41.88/3600 by hand. */
TEST(dms_with_spaces)
{
    const double lat = 55.0 + 28.0 / 60.0 + 41.88 / 3600.0;
    const double lon = -(2.0 + 8.0 / 60.0 + 44.16 / 3600.0);
    const char* forms[] = {"55 28 41.88 N 2 08 44.16 W",
                           "55 28 41.88N 2 08 44.16W",
                           "N 55 28 41.88 W 2 08 44.16",
                           "N55 28 41.88 W002 08 44.16",
                           "2 08 44.16 W 55 28 41.88 N",
                           "55\xC2\xB0 28\xE2\x80\xB2 41.88\xE2\x80\xB3 N 2\xC2\xB0 08\xE2\x80\xB2 "
                           "44.16\xE2\x80\xB3 W",
                           "55d 28' 41.88\" N, 2d 08' 44.16\" W"};
    for (size_t i = 0; i < sizeof forms / sizeof forms[0]; ++i)
        reads_as(forms[i], lat, lon, 1e-6);
    reads_as("N 55 28.698 W 2 08.736", 55.0 + 28.698 / 60.0, -(2.0 + 8.736 / 60.0), 1e-6);
    reads_as("N 55 E 2", 55.0, 2.0, 1e-6); /* no UPS position: degrees */
    reads_as("45N 7 30E", 45.0, 7.5, 1e-6);
    parse_fails("55 61 N 2 W", 0, "61"); /* GeographicLib's reason: minutes >= 60 */
}

TEST(garbled_mgrs_says_which_forms_are_read)
{
    parse_fails("31TCb", 0, "Block Cb not in zone/band 31T");
    parse_fails("31TCb", 0, "positions are LAT LON, ZONE E N or MGRS");
    parse_fails("ab", 0, "33T WN 00000 49776");
}

/* A leading "UTM" label before more fields than are kept (nine and more) is refused, not read
 * past the kept fields (the fuzzer's find: a NULL field reached strlen). */
TEST(label_before_too_many_fields_is_refused)
{
    const char* text = "UTM UPS34RRRRR280 28  41.:8 N 2 08A1,4. 272NW.N";
    tp_position p;
    tp_error err = {{0}};
    EXPECT_EQ_INT(0, tp_position_parse(text, strlen(text), 0, &p, &err));
    EXPECT_TRUE(err.message[0] != '\0');
    const char* nine = "MGRS 55 28 41.88 N 2 08 44.16 W";
    EXPECT_EQ_INT(0, tp_position_parse(nine, strlen(nine), 0, &p, &err));
}

#define TESTS(X)                                                                                   \
    X(label_before_too_many_fields_is_refused)                                                     \
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
    X(mgrs_with_spaces)                                                                            \
    X(every_printed_form_reads_back)                                                               \
    X(utm_with_labels)                                                                             \
    X(every_band_letter)                                                                           \
    X(ambiguous_band_s_names_both)                                                                 \
    X(dms_with_spaces)                                                                             \
    X(garbled_mgrs_says_which_forms_are_read)
TP_TEST_MAIN(TESTS)
