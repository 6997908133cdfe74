/*
 * test_info.c - reading DEMs through tp_io (tp_dem_read) and checking them against the
 * numbers recorded in data/PROVENANCE.md (dimensions, elevation range, void counts,
 * georeferencing), plus bad input: missing, non-raster, truncated and all-nodata files.
 */
#include "tp_test.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#ifdef TP_TEST_NO_IO
#define REQUIRE_IO() SKIP("built without tp_io")
#else
#define REQUIRE_IO() ((void)0)

typedef struct dem_spec {
    const char* env;
    const char* file;
    int width, height;
    double min_m, max_m;
    size_t voids;
    const char* driver;
    const char* data_type;
    int epsg;     /* -1: not checked */
    double gt[6]; /* gt[1] == 0: not checked */
    int warn;     /* 1: a warning is expected, 0: none, -1: not checked */
} dem_spec;

static tp_dem* read_or_skip(const char* env, const char* file)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err;
    tp_status s;
    REQUIRE_DATA_FILE(path, env, file);
    memset(&err, 0, sizeof err);
    s = tp_dem_read(path, &dem, &err);
    if (s != TP_OK || !dem)
        FAIL("tp_dem_read(%s): %s: %s", path, tp_test_status_name_(s), err.message);
    return dem;
}

static void check_dem(const dem_spec* sp)
{
    tp_dem* dem = read_or_skip(sp->env, sp->file);
    size_t i, n, nan_count = 0;
    double lo = INFINITY, hi = -INFINITY;
    EXPECT_EQ_INT(sp->width, dem->width);
    EXPECT_EQ_INT(sp->height, dem->height);
    EXPECT_EQ_INT(sp->voids, dem->void_count);
    EXPECT_EQ_DBL(sp->min_m, dem->min_m);
    EXPECT_EQ_DBL(sp->max_m, dem->max_m);
    if (sp->driver)
        EXPECT_TRUE(strcmp(sp->driver, dem->driver) == 0);
    if (sp->driver && strcmp(sp->driver, dem->driver) != 0)
        tp_test_note("driver \"%s\", expected \"%s\"", dem->driver, sp->driver);
    if (sp->data_type)
        EXPECT_TRUE(strcmp(sp->data_type, dem->data_type) == 0);
    if (sp->data_type && strcmp(sp->data_type, dem->data_type) != 0)
        tp_test_note("data type \"%s\", expected \"%s\"", dem->data_type, sp->data_type);
    EXPECT_EQ_INT(1, dem->is_integer_type);
    if (sp->epsg >= 0)
        EXPECT_EQ_INT(sp->epsg, dem->epsg);
    if (sp->gt[1] != 0.0) {
        EXPECT_EQ_INT(1, dem->has_geotransform);
        for (i = 0; i < 6; ++i)
            /* PROVENANCE.md prints projected origins to the millimetre, degrees to 8 decimals */
            EXPECT_NEAR(sp->gt[i], dem->geotransform[i],
                        fabs(sp->gt[i]) < 0.01   ? 1e-10
                        : fabs(sp->gt[i]) < 1000 ? 1e-7
                                                 : 1e-3);
    }
    ASSERT_TRUE(dem->warnings != NULL);
    ASSERT_TRUE(dem->crs_wkt != NULL);
    if (sp->warn == 1)
        EXPECT_TRUE(dem->warnings[0] != '\0');
    if (sp->warn == 0 && dem->warnings[0] != '\0')
        ADD_FAILURE("unexpected warning: %s", dem->warnings);
    /* the reported numbers agree with the heights array itself */
    n = (size_t)dem->width * dem->height;
    for (i = 0; i < n; ++i) {
        double v = dem->heights[i];
        if (isnan(v)) {
            nan_count++;
            continue;
        }
        if (v < lo)
            lo = v;
        if (v > hi)
            hi = v;
    }
    EXPECT_EQ_INT(dem->void_count, nan_count);
    EXPECT_EQ_DBL(lo, dem->min_m);
    EXPECT_EQ_DBL(hi, dem->max_m);
    tp_dem_destroy(dem);
}
#endif

#ifdef TP_TEST_NO_IO
#define CHECK_SPEC_(...) ((void)0)
#else
#define CHECK_SPEC_(...)                                                                           \
    do {                                                                                           \
        static const dem_spec sp_ = {__VA_ARGS__};                                                 \
        check_dem(&sp_);                                                                           \
    } while (0)
#endif

#define ARCSEC3 (3.0 / 3600.0)

/* PROVENANCE.md: 1201 x 1201 Int16, 349 to 3100, 7652 voids, origin (0.99958333, 43.00041667). */
TEST(n42e001_hgt_matches_provenance)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SHARED_DATA_DIR", "N42E001.hgt", 1201, 1201, 349, 3100, 7652, "SRTMHGT",
                "Int16", 4326, {1.0 - ARCSEC3 / 2, ARCSEC3, 0, 43.0 + ARCSEC3 / 2, 0, -ARCSEC3}, 0);
}

/* -20 to 1204, 134 voids; directly south of N42E001. */
TEST(n41e001_hgt_matches_provenance)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SHARED_DATA_DIR", "N41E001.hgt", 1201, 1201, -20, 1204, 134, "SRTMHGT", "Int16",
                4326, {1.0 - ARCSEC3 / 2, ARCSEC3, 0, 42.0 + ARCSEC3 / 2, 0, -ARCSEC3}, 0);
}

/* DTED conversion of N42E001: 7652 voids (-32767). */
TEST(n42e001_dt1_matches_provenance)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SHARED_DATA_DIR", "N42E001.dt1", 1201, 1201, 349, 3100, 7652, "DTED", "Int16",
                4326, {1.0 - ARCSEC3 / 2, ARCSEC3, 0, 43.0 + ARCSEC3 / 2, 0, -ARCSEC3}, -1);
}

/* 429 x 279, 1289 to 1880, 39489 cells of -32767 without a nodata tag: voids, with a warning. */
TEST(craterlake_untagged_voids_are_nodata_with_warning)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif", 429, 279, 1289, 1880, 39489,
                "GTiff", "Int16", 4326,
                {-122.16558269, 0.000269966, 0, 42.97945163, 0, -0.000269966}, 1);
}

/* 1013 x 799, 553 to 3421, 26820 nodata (32767), UTM 10N, 30 m. */
TEST(mt_hood_matches_provenance)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif", 1013, 799, 553, 3421, 26820,
                "GTiff", "Int16", 26910, {587049.617, 30, 0, 5037312.407, 0, -30}, 0);
}

/* 143 x 107, 2438 to 3046, 876 nodata edge cells, UTM 12N. */
TEST(storml_orig_matches_provenance)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif", 143, 107, 2438, 3046, 876, "GTiff",
                "Int16", 26912, {323476.072, 30, 0, 5105081.983, 0, -30}, 0);
}

/* The filled version: no nodata cells. */
TEST(storml_filled_has_no_voids)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SHARED_DATA_DIR", "storml_elev.tif", 143, 107, 2438, 3046, 0, "GTiff", "Int16",
                26912, {323476.072, 30, 0, 5105081.983, 0, -30}, 0);
}

/* 1201 x 1201, 263 to 4371, 9033 voids (-32768, tagged). */
TEST(mt_rainier_matches_provenance)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SHARED_DATA_DIR", "mt_rainier_90m.tif", 1201, 1201, 263, 4371, 9033, "GTiff",
                "Int16", 4326, {-122.0 - ARCSEC3 / 2, ARCSEC3, 0, 47.0 + ARCSEC3 / 2, 0, -ARCSEC3},
                0);
}

/* ESRI ASCII grids: 758 x 758, 1547 to 4320 and 144 x 144, 2186 to 3345; NODATA 0 unused.
 * The origins are the files' lower-left corners moved to the top edge (GDAL's numbers). */
TEST(front_range_758_asc_matches_provenance)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SHARED_DATA_DIR", "front_range_srtmgl3_758.asc", 758, 758, 1547, 4320, 0,
                "AAIGrid", NULL, -1, {-105.81625, ARCSEC3, 0, 40.46625, 0, -ARCSEC3}, 0);
}

TEST(front_range_144_asc_matches_provenance)
{
    REQUIRE_IO();
    CHECK_SPEC_("TP_SHARED_DATA_DIR", "front_range_srtmgl3_144.asc", 144, 144, 2186, 3345, 0,
                "AAIGrid", NULL, -1, {-105.5604167, ARCSEC3, 0, 40.21041667, 0, -ARCSEC3}, 0);
}

/* A 16-bit PNG height map without georeferencing: raw 0 to 43798. */
TEST(png_heightmap_without_georeference)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        static const dem_spec sp = {"TP_SHARED_DATA_DIR",
                                    "ps_height_1k.png",
                                    1025,
                                    1025,
                                    0,
                                    43798,
                                    0,
                                    "PNG",
                                    "UInt16",
                                    -1,
                                    {0, 0, 0, 0, 0, 0},
                                    -1};
        tp_dem* dem;
        check_dem(&sp);
        dem = read_or_skip(sp.env, sp.file);
        EXPECT_EQ_INT(0, dem->has_geotransform);
        EXPECT_EQ_DBL(0.0, dem->geotransform[0]);
        EXPECT_EQ_DBL(1.0, dem->geotransform[1]);
        EXPECT_EQ_DBL(0.0, dem->geotransform[3]);
        EXPECT_EQ_DBL(-1.0, dem->geotransform[5]);
        tp_dem_destroy(dem);
    }
#endif
}

TEST(hgt_and_dt1_valid_cells_identical)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        tp_dem* a = read_or_skip("TP_SHARED_DATA_DIR", "N42E001.hgt");
        tp_dem* b = read_or_skip("TP_SHARED_DATA_DIR", "N42E001.dt1");
        size_t i, n = (size_t)a->width * a->height, diff = 0;
        ASSERT_EQ_INT(a->width, b->width);
        ASSERT_EQ_INT(a->height, b->height);
        for (i = 0; i < n; ++i) {
            float x = a->heights[i], y = b->heights[i];
            if (isnan(x) != isnan(y) || (!isnan(x) && x != y))
                diff++;
        }
        EXPECT_EQ_INT(0, diff);
        tp_dem_destroy(a);
        tp_dem_destroy(b);
    }
#endif
}

TEST(storml_through_terrain_counts)
{
    /* the repository's fixture through tiling: 143 x 107 padded to 9 x 7 patches of 17 */
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        tp_dem* dem = read_or_skip("TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif");
        tp_terrain_desc d = tp_dem_terrain_desc(dem, 17, TP_FIT_PAD);
        tp_terrain* t = NULL;
        tp_terrain_info ti;
        tp_error err;
        ASSERT_OK(tp_terrain_create(&d, &t, &err));
        tp_terrain_get_info(t, &ti);
        EXPECT_EQ_INT(145, ti.width);
        EXPECT_EQ_INT(113, ti.height);
        EXPECT_EQ_INT(63, ti.patch_count);
        EXPECT_EQ_INT(143 * 107 - 876, ti.valid_samples);
        EXPECT_EQ_INT(876, ti.nodata_samples);
        EXPECT_EQ_INT(145 * 113 - 143 * 107, ti.padding_samples);
        EXPECT_EQ_DBL(2438.0, ti.min_height_m);
        EXPECT_EQ_DBL(3046.0, ti.max_height_m);
        EXPECT_EQ_DBL(1.0, ti.height_step_m);
        EXPECT_NEAR(323476.072, ti.geotransform[0], 1e-3);
        EXPECT_NEAR(5105081.983, ti.geotransform[3], 1e-3);
        tp_terrain_destroy(t);
        tp_dem_destroy(dem);
    }
#endif
}

TEST(terrain_desc_points_into_dem)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        tp_dem* dem = read_or_skip("TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif");
        tp_terrain_desc d = tp_dem_terrain_desc(dem, 33, TP_FIT_RESAMPLE);
        int i;
        EXPECT_TRUE(d.heights == dem->heights);
        EXPECT_EQ_INT((size_t)dem->width * dem->height, d.height_count);
        EXPECT_EQ_INT(dem->width, d.width);
        EXPECT_EQ_INT(dem->height, d.height);
        EXPECT_EQ_INT(33, d.patch_size);
        EXPECT_EQ_INT(TP_FIT_RESAMPLE, d.fit);
        for (i = 0; i < 6; ++i)
            EXPECT_EQ_DBL(dem->geotransform[i], d.geotransform[i]);
        tp_dem_destroy(dem);
    }
#endif
}

#ifndef TP_TEST_NO_IO
/* Reading must fail with a non-OK status, a message naming the file, and *out untouched. */
static void expect_read_fails(const char* path, const char* name, tp_status* got)
{
    tp_dem* sentinel = (tp_dem*)&sentinel;
    tp_dem* out = sentinel;
    tp_error err;
    tp_status s;
    memset(&err, 0, sizeof err);
    s = tp_dem_read(path, &out, &err);
    *got = s;
    EXPECT_TRUE(s != TP_OK);
    EXPECT_TRUE(out == sentinel);
    EXPECT_CONTAINS(err.message, name);
    if (s == TP_OK && out != sentinel)
        tp_dem_destroy(out);
    out = sentinel;
    s = tp_dem_read(path, &out, NULL); /* NULL error pointer accepted */
    EXPECT_TRUE(s != TP_OK);
    EXPECT_TRUE(out == sentinel);
}

static void write_file(const char* path, const void* data, size_t size)
{
    FILE* f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    ASSERT_EQ_INT(size, fwrite(data, 1, size, f));
    fclose(f);
}
#endif

TEST(missing_file_fails_naming_it)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        tp_status s;
        expect_read_fails("/nonexistent-dir/no_such_dem_42.tif", "no_such_dem_42.tif", &s);
    }
#endif
}

TEST(non_raster_file_fails_naming_it)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        static const char text[] = "this is not a raster\njust some text\n1 2 3\n";
        const char* path = "tp_test_info_not_a_raster.txt";
        tp_status s;
        write_file(path, text, sizeof text - 1);
        expect_read_fails(path, "tp_test_info_not_a_raster.txt", &s);
        remove(path);
    }
#endif
}

TEST(truncated_geotiff_fails_naming_it)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        char path[1024];
        const char* cut = "tp_test_info_truncated.tif";
        unsigned char* buf;
        size_t size, keep;
        FILE* f;
        tp_status s;
        REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif");
        f = fopen(path, "rb");
        ASSERT_TRUE(f != NULL);
        buf = (unsigned char*)malloc(1 << 16);
        ASSERT_TRUE(buf != NULL);
        size = fread(buf, 1, 1 << 16, f);
        fclose(f);
        ASSERT_TRUE(size > 20000);
        for (keep = 16; keep < size; keep = keep * 3 + 1000) { /* several cut points */
            write_file(cut, buf, keep);
            expect_read_fails(cut, cut, &s);
            if (tp_test_state_.failures) {
                tp_test_note("cut at %zu of %zu bytes", keep, size);
                break;
            }
        }
        remove(cut);
        free(buf);
    }
#endif
}

TEST(ascii_grid_values_and_georeference)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        static const char asc[] = "ncols 4\nnrows 3\nxllcorner 100\nyllcorner 200\ncellsize 10\n"
                                  "NODATA_value -9999\n"
                                  "1 2 3 4\n5 -9999 7 8\n9 10 11 12.5\n";
        static const float want[12] = {1, 2, 3, 4, 5, NAN, 7, 8, 9, 10, 11, 12.5f};
        const char* path = "tp_test_info_small.asc";
        tp_dem* dem = NULL;
        tp_error err;
        int i;
        write_file(path, asc, sizeof asc - 1);
        ASSERT_OK(tp_dem_read(path, &dem, &err));
        remove(path);
        ASSERT_EQ_INT(4, dem->width);
        ASSERT_EQ_INT(3, dem->height);
        for (i = 0; i < 12; ++i) {
            if (isnan(want[i]))
                EXPECT_NAN(dem->heights[i]);
            else
                EXPECT_EQ_DBL(want[i], dem->heights[i]);
        }
        EXPECT_EQ_INT(1, dem->void_count);
        EXPECT_EQ_DBL(1.0, dem->min_m);
        EXPECT_EQ_DBL(12.5, dem->max_m);
        EXPECT_EQ_INT(1, dem->has_geotransform);
        EXPECT_NEAR(100.0, dem->geotransform[0], 1e-9);
        EXPECT_NEAR(10.0, dem->geotransform[1], 1e-9);
        EXPECT_NEAR(230.0, dem->geotransform[3], 1e-9); /* top edge: 200 + 3 rows of 10 */
        EXPECT_NEAR(-10.0, dem->geotransform[5], 1e-9);
        EXPECT_TRUE(strcmp(dem->driver, "AAIGrid") == 0);
        EXPECT_EQ_INT(0, dem->epsg);
        tp_dem_destroy(dem);
    }
#endif
}

TEST(all_nodata_raster_is_bad_data)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        static const char asc[] = "ncols 3\nnrows 2\nxllcorner 0\nyllcorner 0\ncellsize 1\n"
                                  "NODATA_value -9999\n-9999 -9999 -9999\n-9999 -9999 -9999\n";
        const char* path = "tp_test_info_all_nodata.asc";
        tp_status s;
        write_file(path, asc, sizeof asc - 1);
        expect_read_fails(path, "tp_test_info_all_nodata.asc", &s);
        EXPECT_STATUS(TP_ERR_BAD_DATA, s);
        remove(path);
    }
#endif
}

TEST(dem_destroy_accepts_null)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    tp_dem_destroy(NULL);
#endif
}

#define TESTS(X)                                                                                   \
    X(n42e001_hgt_matches_provenance)                                                              \
    X(n41e001_hgt_matches_provenance)                                                              \
    X(n42e001_dt1_matches_provenance)                                                              \
    X(craterlake_untagged_voids_are_nodata_with_warning)                                           \
    X(mt_hood_matches_provenance)                                                                  \
    X(storml_orig_matches_provenance)                                                              \
    X(storml_filled_has_no_voids)                                                                  \
    X(mt_rainier_matches_provenance)                                                               \
    X(front_range_758_asc_matches_provenance)                                                      \
    X(front_range_144_asc_matches_provenance)                                                      \
    X(png_heightmap_without_georeference)                                                          \
    X(hgt_and_dt1_valid_cells_identical)                                                           \
    X(storml_through_terrain_counts)                                                               \
    X(terrain_desc_points_into_dem)                                                                \
    X(missing_file_fails_naming_it)                                                                \
    X(non_raster_file_fails_naming_it)                                                             \
    X(truncated_geotiff_fails_naming_it)                                                           \
    X(ascii_grid_values_and_georeference)                                                          \
    X(all_nodata_raster_is_bad_data)                                                               \
    X(dem_destroy_accepts_null)
TP_TEST_MAIN(TESTS)
