/*
 * test_coord.c - coordinate conversions of io/include/tp_geo.h (GeographicLib behind C)
 * against the reference data in data/coord (see its README.md):
 *
 *   GeodTest-short.first2000.dat          Karney's geodesic test set, first 2000 rows
 *   TMcoords_lite.first2000.txt           Karney's exact transverse Mercator test set
 *   mgrs_sample_geoconvert212.txt         MGRS strings from GeoConvert 2.1.2 (-m -p 0)
 *   utm_mgrs_edgecases_geoconvert212.txt  Norway, Svalbard, 84N/80S, antimeridian, equator
 *   mgrs_boundary84_disagreements.txt     points just south of 84N: GeographicLib vs another
 *   geoconvert_ctest_cases.tsv            GeographicLib's own GeoConvert ctest expectations
 *
 * plus bad input (latitude 91, malformed MGRS, NaN, NULL outputs), each checked for its
 * specific message and for outputs left alone. The command line (`terrapatch coord`) is
 * tested in tests/CMakeLists.txt (cli.coord_*).
 */
#define _POSIX_C_SOURCE 200809L /* regex.h */

#include "tp_test.h"
#ifndef TP_TEST_NO_IO
#include "tp_geo.h"
#endif

#include <ctype.h>
#include <regex.h>

#ifdef TP_TEST_NO_IO
#define REQUIRE_IO() SKIP("built without tp_io")
#else
#define REQUIRE_IO() ((void)0)

#define DATA_ENV "TP_SHARED_DATA_DIR"
#define UTM_K0 0.9996
#define SENTINEL -12345.0 /* an output that must stay untouched */

/* Opens data/coord/<file>, or skips the test when it is missing. */
static FILE* open_coord_data(const char* file, char* path, size_t cap)
{
    char rel[256];
    FILE* f;
    snprintf(rel, sizeof rel, "coord/%s", file);
    if (!tp_test_data_path(path, cap, DATA_ENV, rel))
        SKIP("data file %s not found (set %s)", path, DATA_ENV);
    f = fopen(path, "r");
    if (!f)
        FAIL("cannot open %s", path);
    return f;
}

/* Reads the next data line (skipping blank and '#' lines), without its newline. */
static int next_data_line(FILE* f, char* line, size_t cap)
{
    while (fgets(line, (int)cap, f)) {
        size_t len = strlen(line);
        while (len && (line[len - 1] == '\n' || line[len - 1] == '\r'))
            line[--len] = '\0';
        if (len == 0 || line[0] == '#')
            continue;
        return 1;
    }
    return 0;
}

/* Difference of two azimuths in degrees, across the +-180 seam. */
static double angle_diff(double a, double b)
{
    return fabs(remainder(a - b, 360.0));
}

static void expect_geo_to_mgrs(double lat, double lon, int precision, const char* expected,
                               const char* where)
{
    int zone = -1, northp = -1;
    double e, n;
    char mgrs[TP_MGRS_SIZE];
    tp_error err = {{0}};
    tp_status s = tp_geo_to_utmups(lat, lon, &zone, &northp, &e, &n, &err);
    if (s != TP_OK) {
        ADD_FAILURE("%s: tp_geo_to_utmups(%.17g, %.17g): %s", where, lat, lon, err.message);
        return;
    }
    s = tp_mgrs_forward(zone, northp, e, n, lat, precision, mgrs, sizeof mgrs, &err);
    if (s != TP_OK) {
        ADD_FAILURE("%s: tp_mgrs_forward(%.17g, %.17g): %s", where, lat, lon, err.message);
        return;
    }
    if (strcmp(mgrs, expected) != 0)
        ADD_FAILURE("%s: %.17g %.17g: MGRS %s, expected %s", where, lat, lon, mgrs, expected);
}

/* Reads MGRS (centre of the square) to geographic. */
static int mgrs_to_geo(const char* mgrs, double* lat, double* lon)
{
    int zone, northp;
    double e, n;
    tp_error err = {{0}};
    if (tp_mgrs_reverse(mgrs, 1, &zone, &northp, &e, &n, NULL, &err) != TP_OK) {
        ADD_FAILURE("tp_mgrs_reverse(%s): %s", mgrs, err.message);
        return 0;
    }
    if (tp_geo_from_utmups(zone, northp, e, n, lat, lon, &err) != TP_OK) {
        ADD_FAILURE("tp_geo_from_utmups(MGRS %s): %s", mgrs, err.message);
        return 0;
    }
    return 1;
}

/* Geodesic distance in metres (for "lies within the square" checks). */
static double distance_m(double lat1, double lon1, double lat2, double lon2)
{
    double a1, a2, s12 = NAN;
    tp_error err = {{0}};
    if (tp_geodesic_inverse(lat1, lon1, lat2, lon2, &a1, &a2, &s12, &err) != TP_OK)
        ADD_FAILURE("tp_geodesic_inverse: %s", err.message);
    return s12;
}
#endif

/* ---------------------------------------------------------------------------------------------
 * Geodesics: GeodTest-short, columns lat1 lon1 azi1 lat2 lon2 azi2 s12 a12 m12 S12 (WGS84).
 */
TEST(geodesic_inverse_matches_geodtest_first2000)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[1024], line[512];
    FILE* f = open_coord_data("GeodTest-short.first2000.dat", path, sizeof path);
    int rows = 0;
    double max_ds = 0, max_da = 0;
    while (next_data_line(f, line, sizeof line)) {
        double lat1, lon1, azi1, lat2, lon2, azi2, s12, a12, m12, S12;
        double got_azi1, got_azi2, got_s12;
        tp_error err = {{0}};
        ++rows;
        if (sscanf(line, "%lf %lf %lf %lf %lf %lf %lf %lf %lf %lf", &lat1, &lon1, &azi1, &lat2,
                   &lon2, &azi2, &s12, &a12, &m12, &S12) != 10) {
            ADD_FAILURE("%s row %d: expected 10 numbers: %s", path, rows, line);
            continue;
        }
        if (tp_geodesic_inverse(lat1, lon1, lat2, lon2, &got_azi1, &got_azi2, &got_s12, &err) !=
            TP_OK) {
            ADD_FAILURE("row %d: %s", rows, err.message);
            continue;
        }
        if (fabs(got_s12 - s12) > 1.5e-8 || angle_diff(got_azi1, azi1) > 1e-8 ||
            angle_diff(got_azi2, azi2) > 1e-8)
            ADD_FAILURE("row %d: azi1 %.15g azi2 %.15g s12 %.12f, expected %.15g %.15g %.12f", rows,
                        got_azi1, got_azi2, got_s12, azi1, azi2, s12);
        if (fabs(got_s12 - s12) > max_ds)
            max_ds = fabs(got_s12 - s12);
        if (angle_diff(got_azi1, azi1) > max_da)
            max_da = angle_diff(got_azi1, azi1);
        if (angle_diff(got_azi2, azi2) > max_da)
            max_da = angle_diff(got_azi2, azi2);
    }
    fclose(f);
    EXPECT_EQ_INT(rows, 2000);
    tp_test_note("2000 geodesics: max |ds12| %.3g m, max |dazi| %.3g deg", max_ds, max_da);
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Transverse Mercator: TMcoords, columns lat lon x y gamma k; central meridian 0, k0 0.9996,
 * no false easting or northing. Longitudes go to 50 degrees from the central meridian, where
 * only the exact projection (tp_tm_*) holds nanometres.
 */
TEST(tm_exact_matches_tmcoords_first2000)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[1024], line[512];
    FILE* f = open_coord_data("TMcoords_lite.first2000.txt", path, sizeof path);
    int rows = 0;
    double max_d = 0, max_g = 0, max_k = 0, max_lon = 0;
    while (next_data_line(f, line, sizeof line)) {
        double lat, lon, x, y, gamma, k, gx, gy, gg, gk, d;
        tp_error err = {{0}};
        ++rows;
        if (sscanf(line, "%lf %lf %lf %lf %lf %lf", &lat, &lon, &x, &y, &gamma, &k) != 6) {
            ADD_FAILURE("%s row %d: expected 6 numbers: %s", path, rows, line);
            continue;
        }
        if (tp_tm_forward(0.0, UTM_K0, lat, lon, &gx, &gy, &gg, &gk, &err) != TP_OK) {
            ADD_FAILURE("row %d: %s", rows, err.message);
            continue;
        }
        d = hypot(gx - x, gy - y);
        if (d > 2e-8 || fabs(gg - gamma) > 1e-12 || fabs(gk - k) > 1e-13)
            ADD_FAILURE("row %d (%.12f %.12f): x %.9f y %.9f gamma %.15g k %.15g, expected "
                        "%.9f %.9f %.15g %.15g (distance %.3g m)",
                        rows, lat, lon, gx, gy, gg, gk, x, y, gamma, k, d);
        if (d > max_d)
            max_d = d;
        if (fabs(gg - gamma) > max_g)
            max_g = fabs(gg - gamma);
        if (fabs(gk - k) > max_k)
            max_k = fabs(gk - k);
        if (lon > max_lon)
            max_lon = lon;
    }
    fclose(f);
    EXPECT_EQ_INT(rows, 2000);
    EXPECT_GT(max_lon, 45.0); /* the set does reach far from the central meridian */
    tp_test_note("2000 points to lon %.1f: max distance %.3g m, gamma %.3g deg, k %.3g", max_lon,
                 max_d, max_g, max_k);
#endif
}

TEST(tm_exact_reverse_matches_tmcoords_first2000)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[1024], line[512];
    FILE* f = open_coord_data("TMcoords_lite.first2000.txt", path, sizeof path);
    const double m_per_deg = 111320.0; /* enough to express angle errors as ground metres */
    int rows = 0;
    double max_d = 0;
    while (next_data_line(f, line, sizeof line)) {
        double lat, lon, x, y, gamma, k, glat, glon, d;
        tp_error err = {{0}};
        ++rows;
        if (sscanf(line, "%lf %lf %lf %lf %lf %lf", &lat, &lon, &x, &y, &gamma, &k) != 6) {
            ADD_FAILURE("%s row %d: expected 6 numbers: %s", path, rows, line);
            continue;
        }
        if (tp_tm_reverse(0.0, UTM_K0, x, y, &glat, &glon, NULL, NULL, &err) != TP_OK) {
            ADD_FAILURE("row %d: %s", rows, err.message);
            continue;
        }
        d = m_per_deg * hypot(glat - lat, (glon - lon) * cos(lat * acos(-1.0) / 180.0));
        if (d > 2e-8)
            ADD_FAILURE("row %d: %.15g %.15g, expected %.15g %.15g (%.3g m)", rows, glat, glon, lat,
                        lon, d);
        if (d > max_d)
            max_d = d;
    }
    fclose(f);
    EXPECT_EQ_INT(rows, 2000);
    tp_test_note("2000 points: max ground error of the reverse %.3g m", max_d);
#endif
}

TEST(tm_rejects_bad_input)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    double x = SENTINEL, y = SENTINEL;
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tm_forward(0, UTM_K0, 91, 0, &x, &y, NULL, NULL, &err));
    EXPECT_CONTAINS(err.message, "latitude 91 is outside [-90, 90]");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tm_forward(0, 0.0, 10, 0, &x, &y, NULL, NULL, &err));
    EXPECT_CONTAINS(err.message, "k0");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tm_reverse(0, UTM_K0, NAN, 0, &x, &y, NULL, NULL, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tm_forward(0, UTM_K0, 0, 0, NULL, &y, NULL, NULL, &err));
    EXPECT_EQ_DBL(x, SENTINEL);
    EXPECT_EQ_DBL(y, SENTINEL);
    /* another scale factor: at the central meridian, y = k0 * meridian distance */
    {
        double x1, y1, x2, y2;
        ASSERT_OK(tp_tm_forward(0, 1.0, 45, 0, &x1, &y1, NULL, NULL, &err));
        ASSERT_OK(tp_tm_forward(0, 0.5, 45, 0, &x2, &y2, NULL, NULL, &err));
        EXPECT_NEAR(y2, 0.5 * y1, 1e-9);
        EXPECT_NEAR(x1, 0.0, 1e-9);
    }
#endif
}

/* ---------------------------------------------------------------------------------------------
 * MGRS: columns lat lon MGRS(1 m).
 */
TEST(mgrs_sample_matches_geoconvert_exactly)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[1024], line[512];
    FILE* f = open_coord_data("mgrs_sample_geoconvert212.txt", path, sizeof path);
    int rows = 0, ups = 0;
    double max_d = 0;
    while (next_data_line(f, line, sizeof line)) {
        double lat, lon, back_lat, back_lon, d;
        char expected[64], where[32];
        ++rows;
        if (sscanf(line, "%lf %lf %63s", &lat, &lon, expected) != 3) {
            ADD_FAILURE("%s row %d: expected lat lon MGRS: %s", path, rows, line);
            continue;
        }
        snprintf(where, sizeof where, "row %d", rows);
        expect_geo_to_mgrs(lat, lon, 5, expected, where);
        ups += isalpha((unsigned char)expected[0]) != 0;
        /* and back: the point lies in the 1 m square, within half its diagonal of the centre */
        if (!mgrs_to_geo(expected, &back_lat, &back_lon))
            continue;
        d = distance_m(lat, lon, back_lat, back_lon);
        if (!(d <= 0.7072))
            ADD_FAILURE("row %d: %s is %.3f m from the point", rows, expected, d);
        if (d > max_d)
            max_d = d;
    }
    fclose(f);
    EXPECT_EQ_INT(rows, 2009);
    EXPECT_GT(ups, 100); /* the sample includes the polar (UPS) regions */
    tp_test_note("2009 MGRS strings (%d UPS); farthest square centre %.3f m", ups, max_d);
#endif
}

TEST(mgrs_reverse_then_forward_is_stable)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const char* const refs[] = {
        "33TWN0000049776", "38SMB4488",       "01NAA6602100000",
        "60NZF3397800000", "ZAA0000033272",   "BAN0000000000",
        "32VJM9345864167", "37XEG6728260035", "38NNF0000000000063811"};
    size_t i;
    for (i = 0; i < sizeof refs / sizeof refs[0]; ++i) {
        int zone, northp, prec;
        double e, n, lat, lon;
        char again[TP_MGRS_SIZE];
        tp_error err = {{0}};
        ASSERT_OK(tp_mgrs_reverse(refs[i], 1, &zone, &northp, &e, &n, &prec, &err));
        ASSERT_OK(tp_geo_from_utmups(zone, northp, e, n, &lat, &lon, &err));
        ASSERT_OK(tp_mgrs_forward(zone, northp, e, n, lat, prec, again, sizeof again, &err));
        if (strcmp(again, refs[i]) != 0)
            ADD_FAILURE("%s came back as %s", refs[i], again);
    }
#endif
}

TEST(mgrs_truncates_rather_than_rounds)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char mgrs[TP_MGRS_SIZE];
    tp_error err = {{0}};
    /* GeographicLib's example: 38n [444, 445) km x [3688, 3689) km is 38SMB4488 at 1 km */
    ASSERT_OK(tp_mgrs_forward(38, 1, 444999.9, 3688999.9, NAN, 2, mgrs, sizeof mgrs, &err));
    EXPECT_CONTAINS(mgrs, "38SMB4488");
    EXPECT_EQ_INT(strlen(mgrs), 9);
    ASSERT_OK(tp_mgrs_forward(38, 1, 444999.9, 3688999.9, NAN, 5, mgrs, sizeof mgrs, &err));
    EXPECT_CONTAINS(mgrs, "38SMB4499988999");
    ASSERT_OK(tp_mgrs_forward(38, 1, 444999.9, 3688999.9, NAN, -1, mgrs, sizeof mgrs, &err));
    EXPECT_CONTAINS(mgrs, "38S");
    EXPECT_EQ_INT(strlen(mgrs), 3);
    ASSERT_OK(tp_mgrs_forward(60, 1, 833978.445, 9000000, NAN, 11, mgrs, sizeof mgrs, &err));
    EXPECT_EQ_INT(strlen(mgrs), 27); /* the longest: TP_MGRS_SIZE holds it */
#endif
}

TEST(mgrs_forward_rejects_bad_input)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char mgrs[TP_MGRS_SIZE];
    char small[8] = "keep";
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_mgrs_forward(33, 1, 500000, 4649776.22, NAN, 12, mgrs, sizeof mgrs, &err));
    EXPECT_CONTAINS(err.message, "precision 12 is outside [-1, 11]");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_mgrs_forward(33, 1, 500000, 4649776.22, NAN, -2, mgrs, sizeof mgrs, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_mgrs_forward(61, 1, 500000, 4649776.22, NAN, 5, mgrs, sizeof mgrs, &err));
    EXPECT_CONTAINS(err.message, "zone 61");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_mgrs_forward(33, 1, NAN, 4649776.22, NAN, 5, mgrs, sizeof mgrs, &err));
    /* UTM allows 0..1000 km eastings, MGRS only 100..900 km: GeographicLib's message */
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_mgrs_forward(33, 1, 50000, 4649776.22, NAN, 5, mgrs, sizeof mgrs, &err));
    EXPECT_CONTAINS(err.message, "Easting");
    /* a latitude that does not match the northing (42N given as 80N) */
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_mgrs_forward(33, 1, 500000, 4649776.22, 80, 5, mgrs, sizeof mgrs, &err));
    EXPECT_CONTAINS(err.message, "inconsistent");
    /* too small a buffer: an error, and the buffer untouched */
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_mgrs_forward(33, 1, 500000, 4649776.22, NAN, 5, small, sizeof small, &err));
    EXPECT_CONTAINS(err.message, "needs 16 bytes");
    EXPECT_CONTAINS(small, "keep");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_mgrs_forward(33, 1, 500000, 4649776.22, NAN, 5, NULL, 0, &err));
#endif
}

/* GeographicLib 2.1.2 reads every leading digit of an MGRS string into an int before it counts
 * them: 10 or more overflow it (UBSan at its src/MGRS.cpp:185; found by fuzz_coord_line, the
 * input is tests/fuzz/regressions/coord_line/mgrs_long_zone). The zone is refused first. */
TEST(mgrs_zone_of_more_than_two_digits_is_refused_before_geographiclib)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const char* const bad[] = {"110087268780A", "333TWN00", "010TWN00",
                                      "99999999999999999999999999TWN00"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        int zone = -7, northp = -7, prec = -7;
        double e = SENTINEL, n = SENTINEL;
        tp_error err = {{0}};
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_mgrs_reverse(bad[i], 1, &zone, &northp, &e, &n, &prec, &err));
        EXPECT_CONTAINS(err.message, "expected a zone of 1 or 2 digits (1..60)");
        EXPECT_CONTAINS(err.message, bad[i]);
        if (zone != -7 || northp != -7 || prec != -7 || e != SENTINEL || n != SENTINEL)
            ADD_FAILURE("'%s': outputs written on failure", bad[i]);
    }
#endif
}

TEST(malformed_mgrs_is_rejected_with_reason)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const struct {
        const char* mgrs;
        const char* reason;
    } bad[] = {
        {"33TWN000004977", "even number of digits"},
        {"33TWI00", "Row letter I"},
        {"33IWN00", "Band letter I"},
        {"99XAA", "Zone 99"},
        {"ZZZ", "Column letter Z"},
        {"33TWN 00", "33TWN 00"},
        {"33TWN0000049776000000000000000000", "More than 22 digits"},
        {"38VMS", "38VMS"}, /* a square wholly outside its latitude band */
        {"INV", "INVALID"},
        {"INVALID", "INVALID"},
        {"", "empty"},
        {"33TWN00000000000000000000000000000000000000000000000000000000000000", "too long"},
        {"3", "3"},
        {"-33TWN00", "-33TWN00"},
    };
    size_t i;
    for (i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        int zone = -7, northp = -7, prec = -7;
        double e = SENTINEL, n = SENTINEL;
        tp_error err = {{0}};
        tp_status s = tp_mgrs_reverse(bad[i].mgrs, 1, &zone, &northp, &e, &n, &prec, &err);
        if (s != TP_ERR_INVALID_ARG) {
            ADD_FAILURE("'%s': status %s, expected TP_ERR_INVALID_ARG", bad[i].mgrs,
                        tp_test_status_name_(s));
            continue;
        }
        if (!strstr(err.message, bad[i].reason))
            ADD_FAILURE("'%s': message \"%s\" lacks \"%s\"", bad[i].mgrs, err.message,
                        bad[i].reason);
        if (zone != -7 || northp != -7 || prec != -7 || e != SENTINEL || n != SENTINEL)
            ADD_FAILURE("'%s': outputs written on failure", bad[i].mgrs);
    }
    {
        int zone, northp;
        double e, n;
        tp_error err = {{0}};
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_mgrs_reverse(NULL, 1, &zone, &northp, &e, &n, NULL, &err));
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_mgrs_reverse("33TWN00", 1, NULL, &northp, &e, &n, NULL, &err));
        /* lower case is fine, and a zone designator alone is legal (precision -1) */
        int prec = 99;
        EXPECT_OK(tp_mgrs_reverse("38smb4488", 1, &zone, &northp, &e, &n, &prec, &err));
        EXPECT_EQ_INT(prec, 2);
        EXPECT_NEAR(e, 444500.0, 1e-9); /* centre of the 1 km square */
        EXPECT_NEAR(n, 3688500.0, 1e-9);
        EXPECT_OK(tp_mgrs_reverse("38smb4488", 0, &zone, &northp, &e, &n, &prec, &err));
        EXPECT_NEAR(e, 444000.0, 1e-9); /* south-west corner */
        EXPECT_OK(tp_mgrs_reverse("33T", 1, &zone, &northp, &e, &n, &prec, &err));
        EXPECT_EQ_INT(prec, -1);
        EXPECT_EQ_INT(zone, 33);
    }
#endif
}

/* ---------------------------------------------------------------------------------------------
 * UTM/UPS edge cases: columns lat lon zone(n/s) easting northing MGRS, from GeoConvert -u -p 3
 * and -m -p 0.
 */
TEST(utm_mgrs_edge_cases_match_geoconvert)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[1024], line[512];
    FILE* f = open_coord_data("utm_mgrs_edgecases_geoconvert212.txt", path, sizeof path);
    int rows = 0;
    while (next_data_line(f, line, sizeof line)) {
        double lat, lon, e, n;
        char zone_s[8], east_s[32], north_s[32], mgrs_s[32], got[96], want[96], where[32];
        int zone, northp;
        tp_error err = {{0}};
        ++rows;
        if (sscanf(line, "%lf %lf %7s %31s %31s %31s", &lat, &lon, zone_s, east_s, north_s,
                   mgrs_s) != 6) {
            ADD_FAILURE("%s row %d: expected 6 fields: %s", path, rows, line);
            continue;
        }
        if (tp_geo_to_utmups(lat, lon, &zone, &northp, &e, &n, &err) != TP_OK) {
            ADD_FAILURE("row %d: %s", rows, err.message);
            continue;
        }
        /* as GeoConvert -u -p 3 prints it */
        char zone_text[TP_ZONE_TEXT_SIZE] = "?";
        EXPECT_OK(tp_zone_format(zone, northp, TP_ZONE_STYLE_GEOCONVERT, zone_text,
                                 sizeof zone_text, &err));
        snprintf(got, sizeof got, "%s %.3f %.3f", zone_text, e, n);
        snprintf(want, sizeof want, "%s %s %s", zone_s, east_s, north_s);
        if (strcmp(got, want) != 0)
            ADD_FAILURE("row %d (%.9g %.9g): UTM/UPS '%s', expected '%s'", rows, lat, lon, got,
                        want);
        snprintf(where, sizeof where, "row %d", rows);
        expect_geo_to_mgrs(lat, lon, 5, mgrs_s, where);
    }
    fclose(f);
    EXPECT_EQ_INT(rows, 23);
#endif
}

/* The same rules spelled out, independent of the file. */
TEST(standard_zone_rules)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const struct {
        double lat, lon;
        int zone, northp;
    } cases[] = {
        {60, 3.5, 32, 1},        /* Norway: 32V is widened west to 3E */
        {60, 2.9, 31, 1},        /* ... but not past it */
        {78, 9.1, 33, 1},        /* Svalbard: 33X spans 9E..21E, there is no 32X */
        {78, 8.9, 31, 1},        /* 31X spans 0..9E */
        {83.999999, 0, 31, 1},   /* UTM up to 84N */
        {84, 0, TP_ZONE_UPS, 1}, /* 84N itself is UPS */
        {-80, 0, 31, 0},         /* UTM down to 80S inclusive */
        {-80.000001, 0, TP_ZONE_UPS, 0},
        {0, 180, 1, 1}, /* the antimeridian is zone 1 from both sides */
        {0, -180, 1, 1},
        {0, 179.999999, 60, 1},
        {0, 540, 1, 1},   /* longitudes are reduced */
        {0.0, 0, 31, 1},  /* the equator is north */
        {-0.0, 0, 31, 0}, /* ... but GeographicLib follows the sign bit: -0 is south */
        {90, 0, TP_ZONE_UPS, 1},
        {-90, 0, TP_ZONE_UPS, 0},
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        int zone, northp;
        double e, n;
        tp_error err = {{0}};
        EXPECT_OK(tp_geo_to_utmups(cases[i].lat, cases[i].lon, &zone, &northp, &e, &n, &err));
        if (zone != cases[i].zone || northp != cases[i].northp)
            ADD_FAILURE("%.9g %.9g: zone %d%s, expected %d%s", cases[i].lat, cases[i].lon, zone,
                        northp ? "n" : "s", cases[i].zone, cases[i].northp ? "n" : "s");
    }
    /* -0: northing 10000 km, which MGRS pulls 4 nm back into band M (as GeoConvert does) */
    expect_geo_to_mgrs(-0.0, 0, 5, "31MAV6602199999", "latitude -0");
    expect_geo_to_mgrs(0.0, 0, 5, "31NAA6602100000", "latitude 0");
#endif
}

/* Grid input in its own standard zone comes back exactly as given; on the equator either
 * hemisphere is standard (GeographicLib's GeoCoords allows both there), so 4s E 10000000 stays
 * south, as `GeoConvert -u` and `-m` (2.1.2) keep it: 04s ... 10000000.000, 04MEE2006899999. */
TEST(grid_on_the_equator_keeps_its_hemisphere)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const struct {
        int zone, northp;
        double e, n;
        int std_zone, std_northp;
        const char* mgrs; /* of the standard grid, precision 5 */
    } cases[] = {
        {4, 0, 520068.7185275841, 10000000, 4, 0, "04MEE2006899999"},
        {4, 1, 520068.7185275841, 0, 4, 1, "04NEF2006800000"},
        {4, 0, 520068.7185275841, 9999999.9, 4, 0, "04MEE2006899999"}, /* just south */
        {31, 0, 441867.785, 1116915.044, TP_ZONE_UPS, 0, "BAZ0000012951"}, /* past 80S: UPS */
        {TP_ZONE_UPS, 0, 2000000, 3112951.025, TP_ZONE_UPS, 0, "BAZ0000012951"},
        {31, 1, 500000, 4649776.22, 31, 1, "31TEG0000049776"},
        {32, 1, 500000, 4649776.22, 32, 1, "32TNM0000049776"},
        {33, 1, 166021.443, 0, 32, 1, "32NRF3397800000"}, /* not its standard zone: converted */
    };
    size_t i;
    for (i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        int zone = -7, northp = -7;
        double e = SENTINEL, n = SENTINEL, lat, lon;
        char mgrs[TP_MGRS_SIZE];
        tp_error err = {{0}};
        EXPECT_OK(tp_utmups_to_standard(cases[i].zone, cases[i].northp, cases[i].e, cases[i].n,
                                        &zone, &northp, &e, &n, &err));
        if (zone != cases[i].std_zone || northp != cases[i].std_northp)
            ADD_FAILURE("case %d: zone %d%s, expected %d%s", (int)i, zone, northp ? "n" : "s",
                        cases[i].std_zone, cases[i].std_northp ? "n" : "s");
        if (zone == cases[i].zone && northp == cases[i].northp) {
            EXPECT_EQ_DBL(e, cases[i].e); /* exactly as given */
            EXPECT_EQ_DBL(n, cases[i].n);
        }
        EXPECT_OK(tp_geo_from_utmups(zone, northp, e, n, &lat, &lon, &err));
        EXPECT_OK(tp_mgrs_forward(zone, northp, e, n, lat, 5, mgrs, sizeof mgrs, &err));
        if (strcmp(mgrs, cases[i].mgrs) != 0)
            ADD_FAILURE("case %d: MGRS %s, expected %s", (int)i, mgrs, cases[i].mgrs);
    }
#endif
}

/* ---------------------------------------------------------------------------------------------
 * 84N boundary: columns lat lon MGRS_GeographicLib MGRS_geoconvert-rs. Every point is a hair
 * south of 84N, where UTM still applies (UTM covers 80S..84N; UPS starts at 84N), so the
 * authority (GeographicLib) gives UTM band X (01X.. to 60X..); the other tool gives UPS
 * (Y.. or Z..), all around the pole. The points
 * are the centres of those UPS squares, so the UPS strings name the right place too: the
 * disagreement is the zone choice, not the location.
 */
TEST(mgrs_84n_boundary_geographiclib_is_authority)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[1024], line[512];
    FILE* f = open_coord_data("mgrs_boundary84_disagreements.txt", path, sizeof path);
    int rows = 0;
    double max_utm = 0, max_ups = 0;
    while (next_data_line(f, line, sizeof line)) {
        double lat, lon, la, lo, d;
        char glib[32], other[32], where[32];
        ++rows;
        if (sscanf(line, "%lf %lf %31s %31s", &lat, &lon, glib, other) != 4) {
            ADD_FAILURE("%s row %d: expected 4 fields: %s", path, rows, line);
            continue;
        }
        if (!(lat < 84.0))
            ADD_FAILURE("row %d: latitude %.17g is not south of 84N", rows, lat);
        /* UTM band X (zone 1..60) against UPS north (Y west of 0E, Z east) */
        if (!isdigit((unsigned char)glib[0]) || glib[2] != 'X' ||
            (other[0] != 'Y' && other[0] != 'Z'))
            ADD_FAILURE("row %d: expected ..X.. vs Y.. or Z.., got %s vs %s", rows, glib, other);
        snprintf(where, sizeof where, "row %d", rows);
        expect_geo_to_mgrs(lat, lon, 5, glib, where); /* GeographicLib's answer, exactly */
        /* both references are legal and name the point's 1 m square */
        if (mgrs_to_geo(glib, &la, &lo)) {
            d = distance_m(lat, lon, la, lo);
            if (!(d <= 0.7072))
                ADD_FAILURE("row %d: %s is %.3f m away", rows, glib, d);
            if (d > max_utm)
                max_utm = d;
        }
        if (mgrs_to_geo(other, &la, &lo)) {
            d = distance_m(lat, lon, la, lo);
            if (!(d <= 0.7072))
                ADD_FAILURE("row %d: %s is %.3f m away", rows, other, d);
            if (d > max_ups)
                max_ups = d;
        }
    }
    fclose(f);
    EXPECT_EQ_INT(rows, 376);
    tp_test_note("376 points: UTM square centres up to %.3f m away, UPS ones %.2g m", max_utm,
                 max_ups);
#endif
}

/* ---------------------------------------------------------------------------------------------
 * GeographicLib's own GeoConvert tests: name, args, input, expected regex. GeoConvert's output
 * formats are rebuilt here from tp_geo results with its precision rules (-p P: geographic
 * P+5 decimals, UTM P decimals, MGRS P+5 digits, DMS 0.1" at P = 0), and the output must match
 * the regex as ctest's PASS_REGULAR_EXPRESSION would.
 */
#ifndef TP_TEST_NO_IO
/* 30d30'30" or 30.50833 */
static int parse_angle(const char* s, double* deg)
{
    double d = 0, m = 0, sec = 0;
    char* end;
    d = strtod(s, &end);
    if (end == s)
        return 0;
    if (*end == 'd') {
        const char* p = end + 1;
        m = strtod(p, &end);
        if (*end != '\'')
            return 0;
        p = end + 1;
        sec = strtod(p, &end);
        if (*end != '"')
            return 0;
        ++end;
    }
    if (*end)
        return 0;
    *deg = d + m / 60 + sec / 3600;
    return 1;
}

/* GeoConvert -d at precision 0: 32d59'14.1"N 044d27'53.4"E */
static void format_dms(double deg, int is_lat, char* out, size_t cap)
{
    char hemi = is_lat ? (deg < 0 ? 'S' : 'N') : (deg < 0 ? 'W' : 'E');
    long tenths = lround(fabs(deg) * 36000.0); /* tenths of an arc second */
    long d = tenths / 36000, m = (tenths / 600) % 60;
    double s = (double)(tenths % 600) / 10.0;
    snprintf(out, cap, is_lat ? "%02ldd%02ld'%04.1f\"%c" : "%03ldd%02ld'%04.1f\"%c", d, m, s, hemi);
}

static void run_geoconvert_case(const char* name, const char* args, const char* input,
                                const char* pattern)
{
    int prec = 0, mode = 'g'; /* g: geographic, u: UTM/UPS, m: MGRS, d: DMS */
    char argbuf[128], inbuf[128], out[160];
    char* tok[4];
    int ntok = 0;
    int zone, northp;
    double lat, lon, e, n;
    tp_error err = {{0}};
    regex_t re;
    char* p;

    snprintf(argbuf, sizeof argbuf, "%s", args);
    for (p = strtok(argbuf, " "); p; p = strtok(NULL, " ")) {
        if (!strcmp(p, "-p")) {
            p = strtok(NULL, " ");
            prec = p ? atoi(p) : 0;
        } else if (!strcmp(p, "-m") || !strcmp(p, "-u") || !strcmp(p, "-d")) {
            mode = p[1];
        } else {
            ADD_FAILURE("%s: GeoConvert option %s is not emulated", name, p);
            return;
        }
    }
    snprintf(inbuf, sizeof inbuf, "%s", input);
    for (p = strtok(inbuf, " "); p && ntok < 4; p = strtok(NULL, " "))
        tok[ntok++] = p;

    /* input: MGRS, ZONE E N, or LAT LON; grid inputs keep their zone, as GeoConvert does */
    if (ntok == 1) {
        if (tp_mgrs_reverse(tok[0], 1, &zone, &northp, &e, &n, NULL, &err) != TP_OK ||
            tp_geo_from_utmups(zone, northp, e, n, &lat, &lon, &err) != TP_OK) {
            ADD_FAILURE("%s: %s", name, err.message);
            return;
        }
    } else if (ntok == 3) {
        northp = tolower((unsigned char)tok[0][strlen(tok[0]) - 1]) == 'n';
        zone = isdigit((unsigned char)tok[0][0]) ? atoi(tok[0]) : TP_ZONE_UPS;
        e = strtod(tok[1], NULL);
        n = strtod(tok[2], NULL);
        if (tp_geo_from_utmups(zone, northp, e, n, &lat, &lon, &err) != TP_OK) {
            ADD_FAILURE("%s: %s", name, err.message);
            return;
        }
    } else if (ntok == 2 && parse_angle(tok[0], &lat) && parse_angle(tok[1], &lon)) {
        if (tp_geo_to_utmups(lat, lon, &zone, &northp, &e, &n, &err) != TP_OK) {
            ADD_FAILURE("%s: %s", name, err.message);
            return;
        }
    } else {
        ADD_FAILURE("%s: cannot read input '%s'", name, input);
        return;
    }

    switch (mode) {
    case 'g': snprintf(out, sizeof out, "%.*f %.*f", prec + 5, lat, prec + 5, lon); break;
    case 'u':
        if (zone == TP_ZONE_UPS)
            snprintf(out, sizeof out, "%s %.*f %.*f", northp ? "n" : "s", prec, e, prec, n);
        else
            snprintf(out, sizeof out, "%02d%s %.*f %.*f", zone, northp ? "n" : "s", prec, e, prec,
                     n);
        break;
    case 'm':
        if (tp_mgrs_forward(zone, northp, e, n, lat, prec + 5, out, sizeof out, &err) != TP_OK) {
            ADD_FAILURE("%s: %s", name, err.message);
            return;
        }
        break;
    default: {
        char a[40], b[40];
        format_dms(lat, 1, a, sizeof a);
        format_dms(lon, 0, b, sizeof b);
        snprintf(out, sizeof out, "%s %s", a, b);
    }
    }

    if (regcomp(&re, pattern, REG_EXTENDED | REG_NOSUB) != 0) {
        ADD_FAILURE("%s: bad regex %s", name, pattern);
        return;
    }
    if (regexec(&re, out, 0, NULL, 0) != 0)
        ADD_FAILURE("%s: GeoConvert %s <<< '%s' gives '%s' here, expected /%s/", name, args, input,
                    out, pattern);
    regfree(&re);
}
#endif

TEST(geoconvert_ctest_cases_pass)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char path[1024], line[512];
    FILE* f = open_coord_data("geoconvert_ctest_cases.tsv", path, sizeof path);
    int rows = 0;
    while (next_data_line(f, line, sizeof line)) {
        char* col[4];
        int ncol = 0;
        char* p = line;
        ++rows;
        while (ncol < 4) {
            col[ncol++] = p;
            p = strchr(p, '\t');
            if (!p)
                break;
            *p++ = '\0';
        }
        if (ncol != 4) {
            ADD_FAILURE("%s row %d: expected 4 tab-separated fields", path, rows);
            continue;
        }
        run_geoconvert_case(col[0], col[1], col[2], col[3]);
    }
    fclose(f);
    EXPECT_EQ_INT(rows, 12);
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Round trips and known values
 */
TEST(utmups_round_trip_random_points)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    tp_rng rng = tp_rng_seed(20240601);
    int i;
    double max_err = 0;
    for (i = 0; i < 4000; ++i) {
        double lat = tp_rng_range(&rng, -90.0, 90.0), lon = tp_rng_range(&rng, -180.0, 180.0);
        double e, n, back_lat, back_lon, d;
        int zone, northp;
        tp_error err = {{0}};
        if (i % 4 == 0)
            lat = tp_rng_range(&rng, 83.0, 90.0) * (i % 8 ? 1 : -1); /* near UPS */
        ASSERT_OK(tp_geo_to_utmups(lat, lon, &zone, &northp, &e, &n, &err));
        ASSERT_OK(tp_geo_from_utmups(zone, northp, e, n, &back_lat, &back_lon, &err));
        EXPECT_EQ_INT(zone == TP_ZONE_UPS, lat >= 84.0 || lat < -80.0);
        d = distance_m(lat, lon, back_lat, back_lon);
        if (!(d < 1e-8))
            ADD_FAILURE("%.17g %.17g came back %.3g m away", lat, lon, d);
        if (d > max_err)
            max_err = d;
    }
    tp_test_note("4000 points: max round-trip error %.3g m", max_err);
#endif
}

TEST(ecef_known_values_and_round_trip)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    const double a = 6378137.0, b = 6356752.314245179; /* WGS84 semi-axes */
    double x, y, z, lat, lon, h;
    tp_error err = {{0}};
    tp_rng rng = tp_rng_seed(7);
    int i;
    ASSERT_OK(tp_geo_to_ecef(0, 0, 0, &x, &y, &z, &err));
    EXPECT_NEAR(x, a, 1e-9);
    EXPECT_NEAR(y, 0, 1e-9);
    EXPECT_NEAR(z, 0, 1e-9);
    ASSERT_OK(tp_geo_to_ecef(90, 0, 0, &x, &y, &z, &err));
    EXPECT_NEAR(x, 0, 1e-9);
    EXPECT_NEAR(z, b, 1e-8);
    ASSERT_OK(tp_geo_to_ecef(0, 90, 100, &x, &y, &z, &err));
    EXPECT_NEAR(x, 0, 1e-9);
    EXPECT_NEAR(y, a + 100, 1e-9); /* the height is along the ellipsoid normal */
    ASSERT_OK(tp_geo_to_ecef(-90, 0, -100, &x, &y, &z, &err));
    EXPECT_NEAR(z, -(b - 100), 1e-8);
    for (i = 0; i < 1000; ++i) {
        double la = tp_rng_range(&rng, -90, 90), lo = tp_rng_range(&rng, -180, 180);
        double hh = tp_rng_range(&rng, -500, 9000);
        ASSERT_OK(tp_geo_to_ecef(la, lo, hh, &x, &y, &z, &err));
        ASSERT_OK(tp_geo_from_ecef(x, y, z, &lat, &lon, &h, &err));
        EXPECT_NEAR(lat, la, 1e-12);
        if (fabs(la) < 89.9)
            EXPECT_NEAR(angle_diff(lon, lo), 0, 1e-11);
        EXPECT_NEAR(h, hh, 1e-8);
    }
#endif
}

TEST(longitudes_are_normalised)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const double in[][2] = {{540, 180},   {-540, -180}, {360, 0},    {180, 180},
                                   {-180, -180}, {190, -170},  {-190, 170}, {359.5, -0.5}};
    size_t i;
    for (i = 0; i < sizeof in / sizeof in[0]; ++i) {
        double lat, lon;
        tp_error err = {{0}};
        EXPECT_OK(tp_geo_normalize(12.5, in[i][0], &lat, &lon, &err));
        EXPECT_EQ_DBL(lat, 12.5);
        EXPECT_EQ_DBL(lon, in[i][1]);
    }
    {
        double lat = SENTINEL, lon = SENTINEL;
        tp_error err = {{0}};
        EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_normalize(0, 541, &lat, &lon, &err));
        EXPECT_CONTAINS(err.message, "longitude 541 is outside [-540, 540]");
        EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_normalize(0, INFINITY, &lat, &lon, &err));
        EXPECT_CONTAINS(err.message, "longitude inf is not a finite number");
        EXPECT_EQ_DBL(lat, SENTINEL);
        EXPECT_EQ_DBL(lon, SENTINEL);
    }
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Bad input everywhere: latitude 91 (and friends), NaN, out-of-range grid coordinates, NULL.
 */
TEST(latitude_91_is_rejected_everywhere)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const struct {
        double lat;
        const char* text;
    } bad[] = {
        {91, "latitude 91 is outside [-90, 90]"},
        {-91, "latitude -91 is outside [-90, 90]"},
        {90.00000000000001, "latitude 90.00000000000001 is outside"}, /* not shown as 90 */
        {1e300, "is outside [-90, 90]"},
        {NAN, "latitude nan is not a finite number"},
        {-INFINITY, "latitude -inf is not a finite number"},
    };
    size_t i;
    for (i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        int zone = -7, northp = -7;
        double o1 = SENTINEL, o2 = SENTINEL, o3 = SENTINEL;
        tp_error err = {{0}};
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_geo_to_utmups(bad[i].lat, 10, &zone, &northp, &o1, &o2, &err));
        EXPECT_CONTAINS(err.message, bad[i].text);
        EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_normalize(bad[i].lat, 10, &o1, &o2, &err));
        EXPECT_CONTAINS(err.message, bad[i].text);
        EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_to_ecef(bad[i].lat, 10, 0, &o1, &o2, &o3, &err));
        EXPECT_CONTAINS(err.message, bad[i].text);
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_tm_forward(0, UTM_K0, bad[i].lat, 10, &o1, &o2, NULL, NULL, &err));
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_geodesic_inverse(0, 0, bad[i].lat, 10, &o1, &o2, &o3, &err));
        EXPECT_CONTAINS(err.message, "lat2");
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_geodesic_inverse(bad[i].lat, 0, 0, 10, &o1, &o2, &o3, &err));
        EXPECT_CONTAINS(err.message, "lat1");
        if (zone != -7 || northp != -7 || o1 != SENTINEL || o2 != SENTINEL || o3 != SENTINEL)
            ADD_FAILURE("latitude %s: outputs written on failure", bad[i].text);
    }
#endif
}

TEST(utm_input_out_of_range_is_rejected)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    double lat = SENTINEL, lon = SENTINEL;
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_geo_from_utmups(61, 1, 500000, 4649776.22, &lat, &lon, &err));
    EXPECT_CONTAINS(err.message, "zone 61");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_geo_from_utmups(-1, 1, 500000, 4649776.22, &lat, &lon, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_from_utmups(33, 1, 1100000, 0, &lat, &lon, &err));
    EXPECT_CONTAINS(err.message, "UTM 33n 1100000 0: Easting 1100km not in UTM range");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_geo_from_utmups(TP_ZONE_UPS, 1, 5000000, 0, &lat, &lon, &err));
    EXPECT_CONTAINS(err.message, "UPS n 5000000 0");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_from_utmups(33, 0, 500000, NAN, &lat, &lon, &err));
    EXPECT_CONTAINS(err.message, "northing nan");
    EXPECT_EQ_DBL(lat, SENTINEL);
    EXPECT_EQ_DBL(lon, SENTINEL);
    /* in range: the zone as given is used, not the standard one (33n at 9.5E is legal) */
    EXPECT_OK(tp_geo_from_utmups(33, 1, 193458.670, 6664167.679, &lat, &lon, &err));
    EXPECT_NEAR(lat, 60.0, 1e-7);
    EXPECT_NEAR(lon, 9.5, 1e-7);
#endif
}

TEST(null_outputs_are_rejected_not_dereferenced)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    int zone, northp;
    double a, b, c;
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_to_utmups(1, 2, NULL, &northp, &a, &b, &err));
    EXPECT_CONTAINS(err.message, "tp_geo_to_utmups");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_from_utmups(33, 1, 5e5, 5e6, &a, NULL, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_to_ecef(1, 2, 3, &a, &b, NULL, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_from_ecef(1, 2, 3, &a, &b, NULL, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geodesic_inverse(1, 2, 3, 4, &a, &b, NULL, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_normalize(1, 2, NULL, &b, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tm_reverse(0, UTM_K0, 1, 2, &a, NULL, NULL, NULL, &err));
    /* err itself may be NULL */
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_geo_to_utmups(91, 2, &zone, &northp, &a, &b, NULL));
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_mgrs_reverse("33TWI00", 1, &zone, &northp, &a, &b, NULL, NULL));
    (void)c;
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Zone text
 */
TEST(zone_format_writes_every_zone_in_every_style)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    /* per style: the UTM zone's printf form, and UPS north, UPS south */
    static const struct {
        tp_zone_style style;
        const char *utm_n, *utm_s, *ups_n, *ups_s;
        int digits;
    } styles[] = {
        {TP_ZONE_STYLE_DEFAULT, "n", "s", "UPS n", "UPS s", 1},
        {TP_ZONE_STYLE_SHORT, "n", "s", "UPS n", "UPS s", 1},
        {TP_ZONE_STYLE_GEOCONVERT, "n", "s", "n", "s", 2},
        {TP_ZONE_STYLE_UPPER, "N", "S", "UPS N", "UPS S", 1},
        {TP_ZONE_STYLE_LONG, "n", "s", "UPS north", "UPS south", 1},
    };
    for (size_t i = 0; i < sizeof styles / sizeof styles[0]; ++i) {
        for (int zone = 0; zone <= 60; ++zone) {
            for (int northp = 0; northp <= 1; ++northp) {
                char got[TP_ZONE_TEXT_SIZE], want[TP_ZONE_TEXT_SIZE];
                tp_error err = {{0}};
                if (zone == TP_ZONE_UPS)
                    snprintf(want, sizeof want, "%s", northp ? styles[i].ups_n : styles[i].ups_s);
                else
                    snprintf(want, sizeof want, "%0*d%s", styles[i].digits, zone,
                             northp ? styles[i].utm_n : styles[i].utm_s);
                tp_status s = tp_zone_format(zone, northp, styles[i].style, got, sizeof got, &err);
                if (s != TP_OK || strcmp(got, want) != 0)
                    ADD_FAILURE("style %d zone %d northp %d: got '%s' (%s), expected '%s'",
                                (int)styles[i].style, zone, northp, s == TP_OK ? got : "",
                                err.message, want);
            }
        }
    }
#endif
}

TEST(zone_format_spot_checks)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char z[TP_ZONE_TEXT_SIZE];
    EXPECT_OK(tp_zone_format(4, 0, TP_ZONE_STYLE_GEOCONVERT, z, sizeof z, NULL));
    EXPECT_EQ_STR("04s", z);
    EXPECT_OK(tp_zone_format(31, 1, TP_ZONE_STYLE_SHORT, z, sizeof z, NULL));
    EXPECT_EQ_STR("31n", z);
    EXPECT_OK(tp_zone_format(10, 1, TP_ZONE_STYLE_UPPER, z, sizeof z, NULL));
    EXPECT_EQ_STR("10N", z);
    EXPECT_OK(tp_zone_format(TP_ZONE_UPS, 0, TP_ZONE_STYLE_LONG, z, sizeof z, NULL));
    EXPECT_EQ_STR("UPS south", z);
    EXPECT_OK(tp_zone_format(TP_ZONE_UPS, 1, TP_ZONE_STYLE_GEOCONVERT, z, sizeof z, NULL));
    EXPECT_EQ_STR("n", z);
    /* any non-zero northp is north */
    EXPECT_OK(tp_zone_format(60, 7, TP_ZONE_STYLE_DEFAULT, z, sizeof z, NULL));
    EXPECT_EQ_STR("60n", z);
    /* exactly enough room */
    char four[4];
    EXPECT_OK(tp_zone_format(33, 0, TP_ZONE_STYLE_GEOCONVERT, four, sizeof four, NULL));
    EXPECT_EQ_STR("33s", four);
#endif
}

TEST(zone_format_rejects_bad_input_and_leaves_out_alone)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    char z[TP_ZONE_TEXT_SIZE] = "keep";
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_zone_format(61, 1, TP_ZONE_STYLE_SHORT, z, sizeof z, &err));
    EXPECT_CONTAINS(err.message, "zone 61");
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_zone_format(-1, 1, TP_ZONE_STYLE_SHORT, z, sizeof z, &err));
    EXPECT_CONTAINS(err.message, "zone -1");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_zone_format(31, 1, (tp_zone_style)99, z, sizeof z, &err));
    EXPECT_CONTAINS(err.message, "style 99");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_zone_format(31, 1, (tp_zone_style)-1, z, sizeof z, &err));
    /* "UPS north" needs 10 bytes */
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_zone_format(TP_ZONE_UPS, 1, TP_ZONE_STYLE_LONG, z, 9, &err));
    EXPECT_CONTAINS(err.message, "needs 10 bytes");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_zone_format(31, 1, TP_ZONE_STYLE_SHORT, z, 0, NULL));
    EXPECT_EQ_STR("keep", z);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_zone_format(31, 1, TP_ZONE_STYLE_SHORT, NULL, 8, &err));
    EXPECT_CONTAINS(err.message, "tp_zone_format");
#endif
}

#define TESTS(X)                                                                                   \
    X(geodesic_inverse_matches_geodtest_first2000)                                                 \
    X(tm_exact_matches_tmcoords_first2000)                                                         \
    X(tm_exact_reverse_matches_tmcoords_first2000)                                                 \
    X(tm_rejects_bad_input)                                                                        \
    X(mgrs_sample_matches_geoconvert_exactly)                                                      \
    X(mgrs_reverse_then_forward_is_stable)                                                         \
    X(mgrs_truncates_rather_than_rounds)                                                           \
    X(mgrs_forward_rejects_bad_input)                                                              \
    X(mgrs_zone_of_more_than_two_digits_is_refused_before_geographiclib)                           \
    X(malformed_mgrs_is_rejected_with_reason)                                                      \
    X(utm_mgrs_edge_cases_match_geoconvert)                                                        \
    X(standard_zone_rules)                                                                         \
    X(grid_on_the_equator_keeps_its_hemisphere)                                                    \
    X(mgrs_84n_boundary_geographiclib_is_authority)                                                \
    X(geoconvert_ctest_cases_pass)                                                                 \
    X(utmups_round_trip_random_points)                                                             \
    X(ecef_known_values_and_round_trip)                                                            \
    X(longitudes_are_normalised)                                                                   \
    X(latitude_91_is_rejected_everywhere)                                                          \
    X(utm_input_out_of_range_is_rejected)                                                          \
    X(null_outputs_are_rejected_not_dereferenced)                                                  \
    X(zone_format_writes_every_zone_in_every_style)                                                \
    X(zone_format_spot_checks)                                                                     \
    X(zone_format_rejects_bad_input_and_leaves_out_alone)
TP_TEST_MAIN(TESTS)
