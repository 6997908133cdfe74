/*
 * test_texture.c - tp_texture_build: which bands of an orthophoto become colour and alpha.
 *
 * The render grid is a real DEM's (data/storml_elev_orig.tif, NAD83 / UTM 12N, 143 x 107,
 * 30 m posts, not warped). Each image is written at test time into a temporary directory: raw
 * bytes (band-sequential) plus a GDAL VRT (the raw file by absolute path: GDAL resolves a
 * relative one against the working directory when it copies the band into another VRT) that gives
 * them the grid's CRS and extent and a colour interpretation per band (<ColorInterp>, as GDAL
 * reports it for a GeoTIFF: a NAIP RGB+NIR orthophoto has Red, Green, Blue, Undefined; an RGBA one
 * Red, Green, Blue, Alpha). Every band holds one value in the image's left half and one in its
 * right half, so the texels far from the middle have exact colours.
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include "tp_test.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#define TP_TMP_PREFIX "tp_texture_"
#include "tp_test_tmp.h"

#ifdef TP_TEST_NO_IO
#define REQUIRE_IO() SKIP("built without tp_io")
#else
#define REQUIRE_IO() ((void)0)

#define IMG_W 8
#define IMG_H 6

typedef struct band_spec {
    const char* interp;   /* GDAL colour interpretation name: Red, Gray, Alpha, Undefined, ... */
    uint8_t left, right;  /* the band's value in the left and right half */
} band_spec;

typedef struct scene {
    tp_dem* dem;
    tp_render_grid* grid;
} scene;

static void scene_load(scene* s)
{
    char path[1024];
    tp_error err;
    memset(s, 0, sizeof *s);
    memset(&err, 0, sizeof err);
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "storml_elev_orig.tif");
    ASSERT_OK(tp_dem_read(path, &s->dem, &err));
    ASSERT_OK(tp_render_grid_build(s->dem, NULL, &s->grid, &err));
    ASSERT_EQ_INT(26912, s->grid->epsg);
}

static void scene_free(scene* s)
{
    tp_render_grid_destroy(s->grid);
    tp_dem_destroy(s->dem);
}

/* Writes dir/name.vrt (and dir/name.raw): band_count bands over the grid's extent, or with
 * georef 0 no CRS and no geotransform. palette: band 1 has a two-entry colour table. */
static void write_image(const char* dir, const char* name, const tp_render_grid* g, int georef,
                        const band_spec* bands, int band_count, int palette, char* vrt_path,
                        size_t cap)
{
    char raw_path[1024];
    uint8_t px[IMG_W * IMG_H];
    FILE* f;
    int b, x, y;
    snprintf(raw_path, sizeof raw_path, "%s/%s.raw", dir, name);
    snprintf(vrt_path, cap, "%s/%s.vrt", dir, name);
    f = fopen(raw_path, "wb");
    ASSERT_TRUE(f != NULL);
    for (b = 0; b < band_count; ++b) {
        for (y = 0; y < IMG_H; ++y)
            for (x = 0; x < IMG_W; ++x)
                px[y * IMG_W + x] = x < IMG_W / 2 ? bands[b].left : bands[b].right;
        ASSERT_EQ_INT(sizeof px, fwrite(px, 1, sizeof px, f));
    }
    ASSERT_EQ_INT(0, fclose(f));
    f = fopen(vrt_path, "w");
    ASSERT_TRUE(f != NULL);
    fprintf(f, "<VRTDataset rasterXSize=\"%d\" rasterYSize=\"%d\">\n", IMG_W, IMG_H);
    if (georef)
        fprintf(f, "  <SRS>EPSG:%d</SRS>\n  <GeoTransform>%.17g, %.17g, 0, %.17g, 0, %.17g</GeoTransform>\n",
                g->epsg, g->geotransform[0], g->width * g->geotransform[1] / IMG_W,
                g->geotransform[3], g->height * g->geotransform[5] / IMG_H);
    for (b = 0; b < band_count; ++b) {
        fprintf(f, "  <VRTRasterBand dataType=\"Byte\" band=\"%d\" subClass=\"VRTRawRasterBand\">\n",
                b + 1);
        fprintf(f, "    <ColorInterp>%s</ColorInterp>\n", bands[b].interp);
        if (palette && b == 0)
            fprintf(f, "    <ColorTable><Entry c1=\"255\" c2=\"0\" c3=\"0\" c4=\"255\"/>"
                       "<Entry c1=\"0\" c2=\"0\" c3=\"255\" c4=\"255\"/></ColorTable>\n");
        fprintf(f,
                "    <SourceFilename relativeToVRT=\"0\">%s</SourceFilename>\n"
                "    <ImageOffset>%d</ImageOffset><PixelOffset>1</PixelOffset>"
                "<LineOffset>%d</LineOffset>\n  </VRTRasterBand>\n",
                raw_path, b * IMG_W * IMG_H, IMG_W);
    }
    fprintf(f, "</VRTDataset>\n");
    ASSERT_EQ_INT(0, fclose(f));
}

/* Builds the texture of the image and checks every texel at least 2 texels from the border
 * and 10% of the width from the middle: left[4] / right[4] are the RGBA expected there. */
static void expect_texels(const band_spec* bands, int band_count, int palette,
                          const uint8_t left[4], const uint8_t right[4])
{
    scene s;
    char path[1024];
    tp_texture* t = NULL;
    tp_error err;
    long bad = 0;
    int x, y, c;
    scene_load(&s);
    write_image(make_tmp_dir(), "image", s.grid, 1, bands, band_count, palette, path, sizeof path);
    memset(&err, 0, sizeof err);
    ASSERT_OK(tp_texture_build(path, s.grid, 4096, &t, &err));
    EXPECT_EQ_INT(1, t->georeferenced);
    EXPECT_EQ_INT(s.grid->width, t->width);
    EXPECT_EQ_INT(s.grid->height, t->height);
    for (y = 2; y < t->height - 2; ++y)
        for (x = 2; x < t->width - 2; ++x) {
            const uint8_t* p = t->rgba + 4 * ((size_t)y * t->width + x);
            const uint8_t* want;
            if (x < 0.4 * t->width)
                want = left;
            else if (x > 0.6 * t->width)
                want = right;
            else
                continue;
            for (c = want[3] == 0 ? 3 : 0; c < 4; ++c) /* transparent: any colour */
                if (abs((int)p[c] - (int)want[c]) > 1) {
                    if (bad++ < 3)
                        ADD_FAILURE("texel (%d, %d): RGBA %d %d %d %d, expected %d %d %d %d", x, y,
                                    p[0], p[1], p[2], p[3], want[0], want[1], want[2], want[3]);
                    break;
                }
        }
    EXPECT_EQ_INT(0, bad);
    tp_texture_destroy(t);
    scene_free(&s);
}
#endif

/* NAIP-style RGB + near infrared: band 4 is not alpha, however dark (0 on the left) or bright. */
TEST(rgb_nir_is_opaque_rgb)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const band_spec b[] = {
        {"Red", 200, 20}, {"Green", 100, 120}, {"Blue", 50, 220}, {"Undefined", 0, 255}};
    static const uint8_t left[4] = {200, 100, 50, 255}, right[4] = {20, 120, 220, 255};
    expect_texels(b, 4, 0, left, right);
#endif
}

TEST(fourth_band_marked_alpha_is_alpha)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const band_spec b[] = {
        {"Red", 200, 20}, {"Green", 100, 120}, {"Blue", 50, 220}, {"Alpha", 0, 255}};
    static const uint8_t left[4] = {0, 0, 0, 0}, right[4] = {20, 120, 220, 255};
    expect_texels(b, 4, 0, left, right);
#endif
}

/* Bands labelled Red, Green, Blue are used wherever they are (here B, G, R, then NIR). */
TEST(rgb_labelled_bands_are_used_in_any_order)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const band_spec b[] = {
        {"Blue", 50, 220}, {"Green", 100, 120}, {"Red", 200, 20}, {"Undefined", 9, 9}};
    static const uint8_t left[4] = {200, 100, 50, 255}, right[4] = {20, 120, 220, 255};
    expect_texels(b, 4, 0, left, right);
#endif
}

/* Without R/G/B labels: the first three bands, opaque. */
TEST(unlabelled_bands_give_the_first_three)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const band_spec b[] = {
        {"Gray", 10, 110}, {"Undefined", 20, 120}, {"Undefined", 30, 130}, {"Undefined", 0, 0}};
    static const uint8_t left[4] = {10, 20, 30, 255}, right[4] = {110, 120, 130, 255};
    expect_texels(b, 4, 0, left, right);
#endif
}

/* Two bands: grey repeated; the second is alpha only when it says so. */
TEST(two_bands_are_grey_alpha_only_when_marked)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const band_spec plain[] = {{"Gray", 70, 140}, {"Undefined", 0, 255}};
    static const band_spec alpha[] = {{"Gray", 70, 140}, {"Alpha", 0, 255}};
    static const uint8_t opaque_l[4] = {70, 70, 70, 255}, opaque_r[4] = {140, 140, 140, 255};
    static const uint8_t clear_l[4] = {0, 0, 0, 0};
    expect_texels(plain, 2, 0, opaque_l, opaque_r);
    expect_texels(alpha, 2, 0, clear_l, opaque_r);
#endif
}

/* A palette band is expanded through its colour table (index 0 red, 1 blue). */
TEST(palette_band_expands_through_its_colour_table)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    static const band_spec b[] = {{"Palette", 0, 1}};
    static const uint8_t left[4] = {255, 0, 0, 255}, right[4] = {0, 0, 255, 255};
    expect_texels(b, 1, 1, left, right);
#endif
}

/* A raster without bands (a VRT, with or without georeference): a clear error, no crash. */
TEST(raster_without_bands_is_refused)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    scene s;
    const char* dir;
    char path[1024];
    int georef;
    scene_load(&s);
    dir = make_tmp_dir();
    for (georef = 0; georef < 2; ++georef) {
        tp_texture* t = (tp_texture*)(uintptr_t)0x1;
        tp_error err;
        memset(&err, 0, sizeof err);
        write_image(dir, georef ? "georef" : "plain", s.grid, georef, NULL, 0, 0, path,
                    sizeof path);
        /* GDAL 3.6 refuses to open a VRT without bands (TP_ERR_IO); drivers that do open one
         * (netCDF with only subdatasets, ...) get TP_ERR_BAD_DATA "has no raster bands" */
        EXPECT_TRUE(tp_texture_build(path, s.grid, 4096, &t, &err) != TP_OK);
        EXPECT_CONTAINS(err.message, path);
        EXPECT_CONTAINS(err.message, "bands");
        EXPECT_TRUE(t == (tp_texture*)(uintptr_t)0x1); /* untouched */
    }
    scene_free(&s);
#endif
}

#define TESTS(X)                                                                                   \
    X(rgb_nir_is_opaque_rgb)                                                                       \
    X(fourth_band_marked_alpha_is_alpha)                                                           \
    X(rgb_labelled_bands_are_used_in_any_order)                                                    \
    X(unlabelled_bands_give_the_first_three)                                                       \
    X(two_bands_are_grey_alpha_only_when_marked)                                                   \
    X(palette_band_expands_through_its_colour_table)                                               \
    X(raster_without_bands_is_refused)
TP_TEST_MAIN(TESTS)
