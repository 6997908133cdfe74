/*
 * test_image.c - heightmap images through OpenImageIO (tp_dem_read_image): raw counts, not
 * normalised; --spacing, --zscale, --origin; checked on the Puget Sound heightmap of
 * data/ (1025x1025 16-bit PNG, 160 m posts, 0.1 m per count: PROVENANCE.md) against the
 * same file read through GDAL.
 */
#define _GNU_SOURCE /* mkdtemp, lstat (tp_test_tmp.h) */
#include "tp_io.h"
#include "tp_test.h"

#include <float.h>
#include <math.h>

#define TP_TMP_PREFIX "tp_image_"
#include "tp_test_tmp.h"

static tp_dem* read_image(const char* file, const tp_image_options* o)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err;
    tp_status s;
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", file);
    memset(&err, 0, sizeof err);
    s = tp_dem_read_image(path, o, &dem, &err);
    if (s != TP_OK || !dem)
        FAIL("tp_dem_read_image(%s): %s", path, err.message);
    return dem;
}

TEST(png_counts_are_raw_and_scaled)
{
    /* PROVENANCE: raw 0 to 43798, i.e. 0 to 4379.8 m at 0.1 m per count */
    tp_image_options o = {.spacing_m = 160, .zscale = 0.1};
    tp_dem* dem = read_image("ps_height_1k.png", &o);
    EXPECT_EQ_INT(1025, dem->width);
    EXPECT_EQ_INT(1025, dem->height);
    EXPECT_EQ_INT(0, dem->void_count);
    EXPECT_NEAR(0.0, dem->min_m, 1e-9);
    EXPECT_NEAR(4379.8, dem->max_m, 1e-3);
    EXPECT_EQ_DBL(160.0, dem->geotransform[1]);
    EXPECT_EQ_DBL(-160.0, dem->geotransform[5]);
    EXPECT_TRUE(dem->crs_wkt[0] == '\0');
    EXPECT_TRUE(dem->warnings[0] == '\0'); /* spacing given: nothing to warn about */
    tp_dem_destroy(dem);
}

TEST(png_matches_gdal_sample_for_sample)
{
    /* GDAL reads the same PNG as UInt16 counts: every sample must be count * zscale. */
    char path[1024];
    tp_dem *g = NULL, *o = NULL;
    tp_error err;
    tp_image_options opt = {.spacing_m = 160, .zscale = 0.1};
    size_t i, n, bad = 0;
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "ps_height_1k.png");
    ASSERT_OK(tp_dem_read(path, &g, &err));
    o = read_image("ps_height_1k.png", &opt);
    ASSERT_EQ_INT(g->width, o->width);
    ASSERT_EQ_INT(g->height, o->height);
    n = (size_t)g->width * g->height;
    for (i = 0; i < n; i++)
        if (fabs((double)(float)(g->heights[i] * 0.1) - o->heights[i]) > 1e-3)
            bad++;
    EXPECT_EQ_INT(0, bad);
    tp_dem_destroy(g);
    tp_dem_destroy(o);
}

TEST(png_without_spacing_warns_and_takes_1m)
{
    tp_image_options o = {0};
    tp_dem* dem = read_image("ps_height_1k.png", &o);
    EXPECT_EQ_DBL(1.0, dem->geotransform[1]);
    EXPECT_CONTAINS(dem->warnings, "spacing");
    EXPECT_NEAR(43798.0, dem->max_m, 1e-9); /* zscale 1: raw counts */
    tp_dem_destroy(dem);
}

TEST(png_with_origin_is_centred_in_its_utm_zone)
{
    tp_image_options o = {.spacing_m = 160, .zscale = 0.1, .has_origin = 1,
                          .origin_lat_deg = 47.5, .origin_lon_deg = -122.5};
    tp_dem* dem = read_image("ps_height_1k.png", &o);
    tp_render_grid* g = NULL;
    tp_georef* ref = NULL;
    tp_error err;
    double e, n, lat, lon;
    EXPECT_EQ_INT(32610, dem->epsg); /* 122.5W is in UTM zone 10 */
    ASSERT_OK(tp_render_grid_build(dem, NULL, &g, &err));
    EXPECT_EQ_INT(0, g->warped);     /* already metric: used as is */
    EXPECT_EQ_INT(10, g->utm_zone);
    EXPECT_EQ_INT(1, g->northp);
    ASSERT_OK(tp_georef_create(g->crs_wkt, g->geotransform, &ref, &err));
    /* the image's centre (post 512, 512 of 1025: its middle) is at the origin */
    tp_georef_grid_to_proj(ref, 512, 512, &e, &n);
    ASSERT_OK(tp_georef_proj_to_geo(ref, e, n, &lat, &lon, &err));
    EXPECT_NEAR(47.5, lat, 1e-9);
    EXPECT_NEAR(-122.5, lon, 1e-9);
    tp_georef_destroy(ref);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

TEST(bad_image_options_and_files_are_refused)
{
    char path[1024];
    tp_dem* dem = (tp_dem*)(uintptr_t)0x1;
    tp_error err;
    tp_image_options bad_origin = {.spacing_m = 10, .has_origin = 1, .origin_lat_deg = 91};
    tp_image_options bad_spacing = {.spacing_m = -5};
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "ps_height_1k.png");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dem_read_image(path, &bad_origin, &dem, &err));
    EXPECT_CONTAINS(err.message, "ps_height_1k.png");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dem_read_image(path, &bad_spacing, &dem, &err));
    EXPECT_STATUS(TP_ERR_IO, tp_dem_read_image("/nonexistent/heights.png", NULL, &dem, &err));
    EXPECT_CONTAINS(err.message, "/nonexistent/heights.png");
    EXPECT_TRUE(dem == (tp_dem*)(uintptr_t)0x1); /* untouched */
}

/* tp_io.h's ranges: spacing 0.001 .. 1e6 m, zscale 1e-6 .. 1e5, heights within +-1e5 m after
 * scaling (a zscale of 1e38 gave "heights out of range (inf .. -inf)" in the core). */
TEST(image_options_outside_their_ranges_are_refused)
{
    char path[1024];
    tp_dem* dem = (tp_dem*)(uintptr_t)0x1;
    tp_error err;
    const tp_image_options tiny = {.spacing_m = 1e-300}, huge = {.spacing_m = 1e300};
    const tp_image_options zbig = {.spacing_m = 160, .zscale = 1e38};
    const tp_image_options tall = {.spacing_m = 160, .zscale = 100}; /* 43798 counts: 4380 km */
    const tp_image_options edge = {.spacing_m = 1e6, .zscale = 2}; /* 87.6 km: read */
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "ps_height_1k.png");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dem_read_image(path, &tiny, &dem, &err));
    EXPECT_CONTAINS(err.message, "--spacing 1e-300 m is outside 0.001 .. 1e+06 m");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dem_read_image(path, &huge, &dem, &err));
    EXPECT_CONTAINS(err.message, "--spacing 1e+300 m is outside");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dem_read_image(path, &zbig, &dem, &err));
    EXPECT_CONTAINS(err.message, "--zscale 1e+38 is outside 1e-06 .. 100000 m per count");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dem_read_image(path, &tall, &dem, &err));
    EXPECT_CONTAINS(err.message, "ps_height_1k.png: heights reach 4.3798e+06 m at --zscale 100");
    EXPECT_TRUE(dem == (tp_dem*)(uintptr_t)0x1); /* untouched */
    dem = NULL;
    EXPECT_STATUS(TP_OK, tp_dem_read_image(path, &edge, &dem, &err));
    if (dem)
        EXPECT_NEAR(87596.0, dem->max_m, 1e-3);
    tp_dem_destroy(dem);
}

/* A float heightmap's nodata, +-FLT_MAX or +-Inf, is nodata: not a height that fails the
 * +-1e5 m check with "check --zscale" (a PFM: "Pf", width height, -1 for little-endian, rows
 * bottom-up). */
TEST(float_heightmap_nodata_is_not_a_height)
{
    char path[600];
    const float vals[16] = {100, 200, -FLT_MAX, 300, 100, 200, FLT_MAX,   300,
                            100, 200, -INFINITY, 300, 100, 200, INFINITY, 300};
    const tp_image_options o = {.spacing_m = 10};
    tp_dem* dem = NULL;
    tp_error err;
    FILE* f;
    snprintf(path, sizeof path, "%s/nodata.pfm", make_tmp_dir());
    f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    fputs("Pf\n4 4\n-1.0\n", f);
    ASSERT_EQ_INT(16, (int)fwrite(vals, sizeof vals[0], 16, f));
    ASSERT_EQ_INT(0, fclose(f));
    if (tp_dem_read_image(path, &o, &dem, &err) != TP_OK)
        FAIL("tp_dem_read_image(%s): %s", path, err.message);
    EXPECT_EQ_INT(4, (int)dem->void_count);
    EXPECT_EQ_DBL(100.0, dem->min_m);
    EXPECT_EQ_DBL(300.0, dem->max_m);
    tp_dem_destroy(dem);
}

/* --spacing/--zscale describe heightmaps without georeference: a georeferenced raster keeps its
 * CRS, geotransform and nodata, so these options are refused (read through OpenImageIO it
 * became raw counts, its 32767 nodata 32,767 m walls; an .hgt an OpenImageIO error). */
static void expect_georeferenced_refused(const char* file, const char* crs_name)
{
    char path[1024], needle[1400];
    tp_dem* dem = (tp_dem*)(uintptr_t)0x1;
    tp_error err;
    tp_image_options o = {.spacing_m = 30, .zscale = 2};
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", file);
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_dem_read_image(path, &o, &dem, &err));
    snprintf(needle, sizeof needle,
             "%s is georeferenced (CRS %s); --spacing/--zscale apply only to heightmap images "
             "without georeference",
             path, crs_name);
    EXPECT_CONTAINS(err.message, needle);
    EXPECT_TRUE(dem == (tp_dem*)(uintptr_t)0x1); /* untouched */
}

TEST(georeferenced_geotiff_is_refused_with_its_crs)
{
    expect_georeferenced_refused("storml_elev_orig.tif", "NAD83 / UTM zone 12N");
}

TEST(georeferenced_hgt_is_refused_with_its_crs)
{
    expect_georeferenced_refused("N42E001.hgt", "WGS 84");
}

TEST(image_extensions_are_recognised)
{
    EXPECT_EQ_INT(1, tp_is_heightmap_image("a/b/ps_height_1k.png"));
    EXPECT_EQ_INT(1, tp_is_heightmap_image("X.PNG"));
    EXPECT_EQ_INT(1, tp_is_heightmap_image("h.exr"));
    EXPECT_EQ_INT(0, tp_is_heightmap_image("N42E001.hgt"));
    EXPECT_EQ_INT(0, tp_is_heightmap_image("dem.tif"));
    EXPECT_EQ_INT(0, tp_is_heightmap_image("png"));
    EXPECT_EQ_INT(0, tp_is_heightmap_image(NULL));
}

/* Screenshots (issue 29, 3.1): the format follows the extension through tp_output_format_for
 * (TP_OUTPUT_SCREENSHOT), and every format it lists is written by tp_image_write_rgba and read
 * back (the lossless ones pixel for pixel); an extension it does not list is refused before
 * anything is encoded, whether OpenImageIO has a writer for it (.hdr, .ppm: three channels, so
 * they failed only after the frame was drawn) or not (.xyz). */
TEST(screenshot_formats_follow_the_extension)
{
    static const struct {
        const char* ext;
        const char* name;
        int lossless;
    } ok[] = {{"png", "PNG", 1},   {"PNG", "PNG", 1},    {"tif", "TIFF", 1}, {"tiff", "TIFF", 1},
              {"jpg", "JPEG", 0},  {"jpeg", "JPEG", 0},  {"bmp", "BMP", 1},  {"tga", "Targa", 1},
              {"webp", "WebP", 0}, {"exr", "OpenEXR", 1}};
    enum { W = 37, H = 21 };
    uint8_t px[W * H * 4];
    for (int i = 0; i < W * H; i++) {
        px[4 * i + 0] = (uint8_t)(i * 7), px[4 * i + 1] = (uint8_t)(i / W * 11);
        px[4 * i + 2] = (uint8_t)(200 - i % W), px[4 * i + 3] = 255;
    }
    const char* dir = make_tmp_dir();
    char path[600], list[512];
    tp_output_formats(TP_OUTPUT_SCREENSHOT, list, sizeof list);
    EXPECT_EQ_STR("PNG (.png), TIFF (.tif, .tiff), JPEG (.jpg, .jpeg), BMP (.bmp), Targa (.tga), "
                  "WebP (.webp), OpenEXR (.exr)",
                  list);
    for (size_t k = 0; k < sizeof ok / sizeof ok[0]; k++) {
        snprintf(path, sizeof path, "%s/shot.%s", dir, ok[k].ext);
        tp_output_format f;
        tp_error err = {0};
        ASSERT_EQ_INT(TP_OK, tp_output_format_for(path, TP_OUTPUT_SCREENSHOT, &f, &err));
        EXPECT_EQ_STR(ok[k].name, f.name);
        EXPECT_EQ_INT(TP_OK, tp_image_output_check(path, &err));
        if (tp_image_write_rgba(path, W, H, px, &err) != TP_OK)
            FAIL("%s: %s", path, err.message);
        int w = 0, h = 0;
        uint8_t* back = NULL;
        if (tp_image_read_rgba(path, &w, &h, &back, &err) != TP_OK)
            FAIL("%s read back: %s", path, err.message);
        EXPECT_EQ_INT(W, w);
        EXPECT_EQ_INT(H, h);
        if (ok[k].lossless) {
            int differ = 0;
            for (int i = 0; i < W * H * 4; i++)
                differ += back[i] != px[i];
            if (differ)
                FAIL("%s: %d bytes differ from those written", path, differ);
        }
        free(back);
    }
    static const char* const refused[] = {"hdr", "ppm", "xyz", "jpe", "sgi"};
    for (size_t k = 0; k < sizeof refused / sizeof refused[0]; k++) {
        snprintf(path, sizeof path, "%s/refused.%s", dir, refused[k]);
        tp_output_format f;
        tp_error err = {0};
        EXPECT_EQ_INT(TP_ERR_INVALID_ARG,
                      tp_output_format_for(path, TP_OUTPUT_SCREENSHOT, &f, &err));
        EXPECT_CONTAINS(err.message, "unknown extension");
        EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_image_output_check(path, &err));
        EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_image_write_rgba(path, W, H, px, &err));
        EXPECT_CONTAINS(err.message, "pictures are written as PNG (.png), TIFF");
        EXPECT_EQ_INT(-1, access(path, F_OK));
    }
}

/* Meshes: export -o and the VTK writer take their format from the same decision. */
TEST(mesh_formats_follow_the_extension)
{
    static const struct {
        const char* path;
        tp_mesh_format format;
    } ok[] = {{"a.vtp", TP_MESH_VTP}, {"b.VTK", TP_MESH_VTK}, {"dir.x/c.vtm", TP_MESH_VTM}};
    for (size_t k = 0; k < sizeof ok / sizeof ok[0]; k++) {
        tp_output_format f;
        tp_error err = {0};
        ASSERT_EQ_INT(TP_OK, tp_output_format_for(ok[k].path, TP_OUTPUT_MESH, &f, &err));
        EXPECT_EQ_INT(ok[k].format, f.mesh);
    }
    static const char* const refused[] = {"a.obj", "a.ply", "a.stl", "vtp", "a.vtu"};
    for (size_t k = 0; k < sizeof refused / sizeof refused[0]; k++) {
        tp_output_format f;
        tp_error err = {0};
        EXPECT_EQ_INT(TP_ERR_INVALID_ARG,
                      tp_output_format_for(refused[k], TP_OUTPUT_MESH, &f, &err));
    }
    char list[256];
    tp_output_formats(TP_OUTPUT_MESH, list, sizeof list);
    EXPECT_EQ_STR("VTK XML PolyData (.vtp), legacy VTK (.vtk), VTK XML multiblock (.vtm)", list);
}

#define TESTS(X)                                                                                   \
    X(png_counts_are_raw_and_scaled)                                                               \
    X(png_matches_gdal_sample_for_sample)                                                          \
    X(png_without_spacing_warns_and_takes_1m)                                                      \
    X(png_with_origin_is_centred_in_its_utm_zone)                                                  \
    X(bad_image_options_and_files_are_refused)                                                     \
    X(image_options_outside_their_ranges_are_refused)                                              \
    X(float_heightmap_nodata_is_not_a_height)                                                      \
    X(georeferenced_geotiff_is_refused_with_its_crs)                                               \
    X(georeferenced_hgt_is_refused_with_its_crs)                                                   \
    X(image_extensions_are_recognised)                                                             \
    X(screenshot_formats_follow_the_extension)                                                     \
    X(mesh_formats_follow_the_extension)
TP_TEST_MAIN(TESTS)
