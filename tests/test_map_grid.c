/*
 * test_map_grid.c - what the viewer's grid labels say (app/view/map_grid.c): MGRS on a UTM render
 * grid, WGS84 or NAD83, the 100 km square letters from GeographicLib; plain kilometres on a
 * local or non-UTM CRS.
 *
 * Expected letters worked out by hand from the MGRS lettering (zone 31 mod 3 = 1: columns A..H,
 * A for 100-200 km, so E 376000 is C; rows in odd zones start at A at the equator and repeat
 * every 2000 km, so N 4700000 is the 8th row, H), never from the code.
 */
#include "tp_test.h"
#include "tp_io.h"

#include "map_grid.h"

#include <cpl_conv.h>
#include <ogr_srs_api.h>

#include <string.h>

static tp_georef* georef_of(const char* crs)
{
    const double gt[6] = {300000, 30, 0, 4800000, 0, -30};
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    char* wkt = NULL;
    if (OSRImportFromEPSG(srs, atoi(crs + 5)) != OGRERR_NONE || OSRExportToWkt(srs, &wkt) != OGRERR_NONE)
        FAIL("%s: GDAL does not know it", crs);
    tp_georef* g = NULL;
    tp_error err;
    tp_status st = tp_georef_create(wkt, gt, &g, &err);
    CPLFree(wkt);
    OSRDestroySpatialReference(srs);
    if (st != TP_OK)
        FAIL("%s: %s", crs, err.message);
    return g;
}

TEST(wgs84_utm_labels_carry_square_letters_and_principal_digits)
{
    tp_georef* g = georef_of("EPSG:32631");
    const double gt[6] = {340000, 30, 0, 4740000, 0, -30};
    tp_map_grid mg;
    tp_map_grid_init(&mg, g, gt, 2000, 2000, 1000);
    ASSERT_EQ_INT(mg.kind, TP_MAP_GRID_MGRS);
    EXPECT_EQ_INT(mg.zone, 31);
    EXPECT_EQ_INT(mg.northp, 1);
    EXPECT_EQ_INT(mg.digits, 2);
    char square[16], digits[32];
    tp_map_grid_label(&mg, 376000, 4700000, square, digits);
    EXPECT_EQ_STR("31T CH", square);
    EXPECT_EQ_STR("76 00", digits);
    /* the line at E 400000 starts the next column (D), N 4699000 the row below (G, digits 99) */
    tp_map_grid_label(&mg, 400000, 4699000, square, digits);
    EXPECT_EQ_STR("31T DG", square);
    EXPECT_EQ_STR("00 99", digits);
    /* 100 m spacing: three digits; 10 km: one; 100 km: the square alone */
    tp_map_grid_init(&mg, g, gt, 2000, 2000, 100);
    tp_map_grid_label(&mg, 376500, 4700800, square, digits);
    EXPECT_EQ_STR("765 008", digits);
    tp_map_grid_init(&mg, g, gt, 2000, 2000, 10000);
    tp_map_grid_label(&mg, 370000, 4700000, square, digits);
    EXPECT_EQ_STR("7 0", digits);
    tp_map_grid_init(&mg, g, gt, 2000, 2000, 100000);
    tp_map_grid_label(&mg, 300000, 4700000, square, digits);
    EXPECT_EQ_STR("31T CH", square);
    EXPECT_EQ_STR("", digits);
    tp_georef_destroy(g);
}

TEST(nad83_utm_is_labelled_as_mgrs)
{
    /* Mount Hood's DEM: NAD83 / UTM 10N (about a metre from WGS84) */
    tp_georef* g = georef_of("EPSG:26910");
    const double gt[6] = {587000, 30, 0, 5036000, 0, -30};
    tp_map_grid mg;
    tp_map_grid_init(&mg, g, gt, 1013, 799, 1000);
    ASSERT_EQ_INT(mg.kind, TP_MAP_GRID_MGRS);
    EXPECT_EQ_INT(mg.zone, 10);
    char square[16], digits[32];
    /* columns: zone 10 mod 3 = 1 -> A..H, A for 100-200 km, so 600-700 km is F; rows: even
     * zones start at F, 5024000 mod 2000000 = 1024000 -> 10 rows after F, I and O skipped: R */
    tp_map_grid_label(&mg, 602000, 5024000, square, digits);
    EXPECT_EQ_STR("10T FR", square);
    EXPECT_EQ_STR("02 24", digits);
    tp_georef_destroy(g);
}

TEST(local_and_non_utm_crs_keep_plain_kilometres)
{
    const double gt[6] = {4500000, 30, 0, 4800000, 0, -30};
    tp_map_grid mg;
    char square[16], digits[32];
    tp_map_grid_init(&mg, NULL, gt, 100, 100, 1500);
    EXPECT_EQ_INT(mg.kind, TP_MAP_GRID_PLAIN);
    tp_map_grid_label(&mg, 4501500, 4722000, square, digits);
    EXPECT_EQ_STR("", square);
    EXPECT_EQ_STR("4501.5E 4722.0N", digits);
    /* ETRS89 / LAEA Europe: has a geographic position, but is no UTM zone */
    tp_georef* g = georef_of("EPSG:3035");
    tp_map_grid_init(&mg, g, gt, 1000, 1000, 1000);
    EXPECT_EQ_INT(mg.kind, TP_MAP_GRID_PLAIN);
    tp_map_grid_label(&mg, 4501000, 4722000, square, digits);
    EXPECT_EQ_STR("4501E 4722N", digits);
    tp_georef_destroy(g);
}

TEST(ups_north_is_labelled_with_its_band_letter)
{
    tp_georef* g = georef_of("EPSG:32661"); /* WGS 84 / UPS North (N,E) */
    const double gt[6] = {2050000, 100, 0, 2150000, 0, -100};
    tp_map_grid mg;
    tp_map_grid_init(&mg, g, gt, 1000, 1000, 1000);
    ASSERT_EQ_INT(mg.kind, TP_MAP_GRID_MGRS);
    EXPECT_EQ_INT(mg.zone, 0);
    char square[16], digits[32];
    tp_map_grid_label(&mg, 2100000, 2100000, square, digits);
    /* east of the pole: band Z; the square is two letters after it */
    EXPECT_EQ_INT((int)strlen(square), 4);
    EXPECT_TRUE(square[0] == 'Z' && square[1] == ' ');
    EXPECT_EQ_STR("00 00", digits);
    tp_georef_destroy(g);
}

/* The spacing drawn follows the scale at the view's centre (issue 29, 4.5): 1, 10 or 100 km for
 * the 1 km grid, the finest whose lines are at least TP_MAP_GRID_MIN_PX (40) pixels apart, so
 * that the grid never turns into a dark mesh (the whole N42E001 tile at its default view is about
 * 188 m a pixel: 1 km lines were 5 px apart). */
TEST(spacing_follows_the_scale)
{
    struct {
        double base, m_per_px, want;
    } cases[] = {
        {1000, 0.01, 1000},       /* on the ground */
        {1000, 5.8, 1000},        /* a low oblique view of Mt Hood: 172 px apart */
        {1000, 25, 1000},         /* exactly 40 px */
        {1000, 25.01, 10000},     /* just under 40 px: 10 km (400 px) */
        {1000, 39.6, 10000},      /* Mt Hood's default view: 25 px -> 253 px */
        {1000, 188, 10000},       /* N42E001's default view: 5.3 px -> 53 px */
        {1000, 250, 10000},       /* 40 px */
        {1000, 300, 100000},      /* 33 px -> 333 px */
        {1000, 1e4, 100000},      /* the coarsest: 100 km, however far */
        {1000, NAN, 100000},      /* no ground at the centre: the coarsest */
        {1000, 0, 100000},        /* ... nor a scale */
        {1000, INFINITY, 100000}, /* ... */
        {100, 3, 1000},           /* --grid 100: 100 m, 1 km, 10 km */
        {100, 2.5, 100},          /* 40 px */
        {250, 7, 2500},           /* any finest spacing, times ten */
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        double got = tp_map_grid_spacing(cases[i].base, cases[i].m_per_px);
        if (got != cases[i].want)
            FAIL("--grid %g at %g m/px: spacing %g, expected %g", cases[i].base, cases[i].m_per_px,
                 got, cases[i].want);
        /* lines at least 40 px apart whenever the coarsest allows it */
        if (cases[i].m_per_px > 0 && got < cases[i].base * 100)
            EXPECT_GE(got / cases[i].m_per_px, TP_MAP_GRID_MIN_PX);
    }
    /* never coarser than needed: a tenth of the spacing would be too close */
    for (double m = 0.5; m < 400; m *= 1.37) {
        double got = tp_map_grid_spacing(1000, m);
        if (got > 1000)
            EXPECT_LT(got / 10 / m, TP_MAP_GRID_MIN_PX);
    }
}

#define TESTS(X)                                                                                   \
    X(spacing_follows_the_scale)                                                                   \
    X(wgs84_utm_labels_carry_square_letters_and_principal_digits)                                  \
    X(nad83_utm_is_labelled_as_mgrs)                                                               \
    X(local_and_non_utm_crs_keep_plain_kilometres)                                                 \
    X(ups_north_is_labelled_with_its_band_letter)
TP_TEST_MAIN(TESTS)
