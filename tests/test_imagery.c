/*
 * test_imagery.c - imagery pyramids (.tpi; io/src/imagery_*.cpp, tp_imagery.h, docs/imagery.md).
 *
 * Georeference: markers at known coordinates of a geographic (EPSG:4326) GeoTIFF land on the
 * level-0 texel of a UTM grid that GDAL/PROJ's own transformation (tp_test_gdal.h) and the
 * grid's geotransform put them at, within half a texel, at texel shifts -1, 0 and 2; the real
 * craterlake imagery over its DEM's render grid matches the source pixel found the same way.
 * Pyramid: every level is the alpha-weighted 2x2 mean of the one below (recomputed here from
 * the documented rule), sizes that are not multiples of the block, shifts from -3 to 3, empty
 * blocks, a mosaic of two sources (the later one on top where it has alpha), the same bytes
 * from one thread or three, a memory budget too small refused up front, four threads reading
 * one open pyramid at once. Damage: a flipped
 * byte in a block (that block only, named), in the header or the table, files cut short, a
 * newer version, another file type; bad sources and outputs leave no file. The damage tests
 * read the file with their own parser of docs/imagery.md's layout and their own CRC32.
 */
#define _GNU_SOURCE
#include "tp_imagery.h"
#include "tp_io.h"
#include "tp_test.h"
#include "tp_test_gdal.h"

#include <cpl_conv.h>
#include <dirent.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TP_TMP_PREFIX "tp_imagery_"
#include "tp_test_tmp.h"

#define B TP_IMAGERY_BLOCK

/* ---------------------------------------------------------------------------------------------
 * Helpers
 */
static uint8_t* slurp(const char* path, size_t* size);

/* A UTM zone 10N grid near Crater Lake: w x h pixels of px metres from (e0, n0), north up. */
static tp_imagery_target utm_target(int w, int h, double px, double e0, double n0, char* wkt_buf,
                                    size_t cap)
{
    OGRSpatialReferenceH s = OSRNewSpatialReference(NULL);
    char* wkt = NULL;
    ASSERT_TRUE(OSRImportFromEPSG(s, 32610) == OGRERR_NONE);
    ASSERT_TRUE(OSRExportToWkt(s, &wkt) == OGRERR_NONE);
    snprintf(wkt_buf, cap, "%s", wkt);
    CPLFree(wkt);
    OSRDestroySpatialReference(s);
    tp_imagery_target t;
    t.crs_wkt = wkt_buf;
    t.geotransform[0] = e0, t.geotransform[1] = px, t.geotransform[2] = 0;
    t.geotransform[3] = n0, t.geotransform[4] = 0, t.geotransform[5] = -px;
    t.width = w, t.height = h;
    return t;
}

/* (lon, lat) of (e, n) in UTM 10N, by GDAL/PROJ; and back. */
static void utm_to_lonlat(const char* wkt, double e, double n, double* lon, double* lat)
{
    tp_test_gdal_lat_lon(wkt, e, n, lat, lon);
}

typedef void (*pixel_fn)(int x, int y, uint8_t* rgba, void* user);

/* A GeoTIFF in EPSG:4326 of w x h pixels (gt in degrees), bands 3 or 4 (alpha). */
static void write_tif(const char* path, int w, int h, const double gt[6], int bands, pixel_fn fn,
                      void* user)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path, w, h, bands, GDT_Byte, NULL);
    ASSERT_TRUE(ds != NULL);
    OGRSpatialReferenceH s = OSRNewSpatialReference(NULL);
    OSRImportFromEPSG(s, 4326);
    GDALSetSpatialRef(ds, s);
    OSRDestroySpatialReference(s);
    GDALSetGeoTransform(ds, (double*)gt);
    uint8_t* px = calloc((size_t)w * h * 4, 1);
    ASSERT_TRUE(px != NULL);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            fn(x, y, px + ((size_t)y * w + x) * 4, user);
    const GDALColorInterp ci[4] = {GCI_RedBand, GCI_GreenBand, GCI_BlueBand, GCI_AlphaBand};
    for (int c = 0; c < bands; c++) {
        GDALRasterBandH b = GDALGetRasterBand(ds, c + 1);
        GDALSetRasterColorInterpretation(b, ci[c]);
        ASSERT_TRUE(GDALRasterIO(b, GF_Write, 0, 0, w, h, px + c, w, h, GDT_Byte, 4, w * 4) ==
                    CE_None);
    }
    free(px);
    GDALClose(ds);
}

/* Level l of a pyramid as one RGBA image (*w x *h, malloc'd). */
static uint8_t* read_level(const tp_imagery* im, int l, int64_t* w, int64_t* h)
{
    int cols, rows;
    tp_error err = {0};
    tp_imagery_level_size(im, l, w, h, &cols, &rows);
    uint8_t* img = calloc((size_t)*w * *h * 4, 1);
    uint8_t* blk = malloc((size_t)B * B * 4);
    ASSERT_TRUE(img && blk);
    for (int by = 0; by < rows; by++)
        for (int bx = 0; bx < cols; bx++) {
            ASSERT_OK(tp_imagery_read_block(im, l, bx, by, blk, &err));
            for (int y = 0; y < B; y++)
                for (int x = 0; x < B; x++) {
                    const int64_t u = (int64_t)bx * B + x, v = (int64_t)by * B + y;
                    const uint8_t* s = blk + ((size_t)y * B + x) * 4;
                    if (u < *w && v < *h)
                        memcpy(img + ((size_t)v * *w + u) * 4, s, 4);
                    else if (s[3] != 0) /* beyond the level: transparent */
                        ADD_FAILURE("level %d texel (%lld, %lld) beyond %lldx%lld has alpha %d", l,
                                    (long long)u, (long long)v, (long long)*w, (long long)*h, s[3]);
                }
        }
    free(blk);
    return img;
}

static tp_imagery* build_open(const char* const* src, int n, const tp_imagery_target* t, int shift,
                              const char* out)
{
    tp_error err = {0};
    tp_imagery_build_options o = {0};
    o.texel_shift = shift;
    o.threads = 2;
    ASSERT_OK(tp_imagery_build(src, n, t, &o, out, &err));
    tp_imagery* im = NULL;
    ASSERT_OK(tp_imagery_open(out, &im, &err));
    return im;
}

/* ---------------------------------------------------------------------------------------------
 * Georeference: markers
 */

/* Grey everywhere, red at marker pixel (mx[0], my[0]) and blue at (mx[1], my[1]). */
typedef struct markers {
    int mx[2], my[2];
} markers;

static void marker_pixel(int x, int y, uint8_t* p, void* user)
{
    const markers* m = user;
    p[0] = p[1] = p[2] = 100;
    p[3] = 255;
    if (x == m->mx[0] && y == m->my[0])
        p[0] = 255, p[1] = p[2] = 0;
    if (x == m->mx[1] && y == m->my[1])
        p[2] = 255, p[0] = p[1] = 0;
}

/* The centroid (in level-0 texel coordinates, texel (u, v) spanning u..u+1) of how much more
 * of channel c than of the grey background each texel has. */
static void centroid(const uint8_t* img, int64_t w, int64_t h, int c, double* cu, double* cv)
{
    double sw = 0, su = 0, sv = 0;
    for (int64_t v = 0; v < h; v++)
        for (int64_t u = 0; u < w; u++) {
            const uint8_t* p = img + ((size_t)v * w + u) * 4;
            const int other = c == 0 ? p[2] : p[0];
            const double wgt = p[c] > other + 20 ? (double)(p[c] - other) : 0;
            sw += wgt, su += wgt * (u + 0.5), sv += wgt * (v + 0.5);
        }
    ASSERT_GT(sw, 0);
    *cu = su / sw, *cv = sv / sw;
}

static void marker_case(int shift)
{
    const char* dir = make_tmp_dir();
    char wkt[4096], tif[600], out[600];
    /* 60 x 40 km grid of 200 m pixels in UTM 10N */
    const tp_imagery_target t = utm_target(300, 200, 200.0, 540000.0, 4780000.0, wkt, sizeof wkt);
    /* the image: 0.002 degree pixels over the grid and more (geographic) */
    double lon0, lat0, lon1, lat1;
    utm_to_lonlat(wkt, 535000.0, 4785000.0, &lon0, &lat0);
    utm_to_lonlat(wkt, 605000.0, 4735000.0, &lon1, &lat1);
    const double d = 0.002;
    const double gt[6] = {lon0, d, 0, lat0, 0, -d};
    const int w = (int)ceil((lon1 - lon0) / d), h = (int)ceil((lat0 - lat1) / d);
    const markers m = {{w / 3, (2 * w) / 3 + 1}, {h / 4, (3 * h) / 5}};
    snprintf(tif, sizeof tif, "%s/markers.tif", dir);
    snprintf(out, sizeof out, "%s/markers.tpi", dir);
    write_tif(tif, w, h, gt, 3, marker_pixel, (void*)&m);
    const char* src[1] = {tif};
    tp_imagery* im = build_open(src, 1, &t, shift, out);
    tp_imagery_info info;
    tp_imagery_get_info(im, &info);
    EXPECT_EQ_INT(shift, info.texel_shift);
    /* level 0's geotransform: the grid's with pixels 2^shift times smaller */
    const double f = ldexp(1.0, -shift);
    double g0[6] = {t.geotransform[0],    t.geotransform[1] * f, 0, t.geotransform[3], 0,
                    t.geotransform[5] * f};
    for (int i = 0; i < 6; i++)
        EXPECT_EQ_DBL(g0[i], info.geotransform[i]);
    int64_t lw, lh;
    uint8_t* img = read_level(im, 0, &lw, &lh);
    for (int k = 0; k < 2; k++) {
        /* the marker pixel's centre in degrees, then in UTM by PROJ, then in texels */
        const double lon = gt[0] + (m.mx[k] + 0.5) * d, lat = gt[3] - (m.my[k] + 0.5) * d;
        OGRSpatialReferenceH s4326 = OSRNewSpatialReference(NULL),
                             sutm = OSRNewSpatialReference(wkt);
        OSRImportFromEPSG(s4326, 4326);
        OSRSetAxisMappingStrategy(s4326, OAMS_TRADITIONAL_GIS_ORDER);
        OSRSetAxisMappingStrategy(sutm, OAMS_TRADITIONAL_GIS_ORDER);
        OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(s4326, sutm);
        double e = lon, n = lat, z = 0;
        ASSERT_TRUE(OCTTransform(ct, 1, &e, &n, &z));
        OCTDestroyCoordinateTransformation(ct);
        OSRDestroySpatialReference(s4326);
        OSRDestroySpatialReference(sutm);
        const double eu = (e - g0[0]) / g0[1], ev = (n - g0[3]) / g0[5];
        double cu, cv;
        centroid(img, lw, lh, k == 0 ? 0 : 2, &cu, &cv);
        tp_test_note("shift %d marker %d: expected texel (%.3f, %.3f), found (%.3f, %.3f)", shift,
                     k, eu, ev, cu, cv);
        EXPECT_NEAR(eu, cu, 0.5);
        EXPECT_NEAR(ev, cv, 0.5);
    }
    free(img);
    tp_imagery_close(im);
}

TEST(marker_lands_on_its_texel_shift_0)
{
    marker_case(0);
}
TEST(marker_lands_on_its_texel_shift_2)
{
    marker_case(2);
}
TEST(marker_lands_on_its_texel_shift_minus_1)
{
    marker_case(-1);
}

/* ---------------------------------------------------------------------------------------------
 * Real imagery over its DEM's render grid
 */

typedef struct real_scene {
    tp_dem* dem;
    tp_render_grid* grid;
    tp_imagery_target t;
    char image[1024];
} real_scene;

static void real_load(real_scene* s)
{
    char path[1024];
    tp_error err = {0};
    memset(s, 0, sizeof *s);
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif");
    REQUIRE_DATA_FILE(s->image, "TP_SHARED_DATA_DIR", "craterlake-imagery-30m.tif");
    ASSERT_OK(tp_dem_read(path, &s->dem, &err));
    ASSERT_OK(tp_render_grid_build(s->dem, NULL, &s->grid, &err));
    s->t.crs_wkt = s->grid->crs_wkt;
    memcpy(s->t.geotransform, s->grid->geotransform, sizeof s->t.geotransform);
    s->t.width = s->grid->width;
    s->t.height = s->grid->height;
}

static void real_free(real_scene* s)
{
    tp_render_grid_destroy(s->grid);
    tp_dem_destroy(s->dem);
}

/* Each level-0 texel against the source pixels around the point PROJ maps its centre to:
 * alpha 255 where the 4 x 4 nearest source pixels are opaque, 0 where all are transparent, and
 * the colour inside their range (bilinear weights the 2 x 2 nearest; the ring around them
 * allows for GDAL's approximate transformer, within 1/8 of a texel). */
TEST(real_imagery_matches_its_source_pixels)
{
    real_scene s;
    real_load(&s);
    const char* dir = make_tmp_dir();
    char out[600];
    snprintf(out, sizeof out, "%s/crater.tpi", dir);
    const char* src[1] = {s.image};
    tp_imagery* im = build_open(src, 1, &s.t, 1, out);
    int64_t w, h;
    uint8_t* img = read_level(im, 0, &w, &h);
    tp_imagery_info info;
    tp_imagery_get_info(im, &info);
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(s.image, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    const int sw = GDALGetRasterXSize(ds), sh = GDALGetRasterYSize(ds);
    double sgt[6];
    GDALGetGeoTransform(ds, sgt);
    uint8_t* px = malloc((size_t)sw * sh * 4);
    ASSERT_TRUE(px != NULL);
    for (int c = 0; c < 4; c++)
        ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, c + 1), GF_Read, 0, 0, sw, sh, px + c, sw,
                                 sh, GDT_Byte, 4, sw * 4) == CE_None);
    GDALClose(ds);
    OGRSpatialReferenceH sutm = OSRNewSpatialReference(s.t.crs_wkt),
                         s4326 = OSRNewSpatialReference(NULL);
    OSRImportFromEPSG(s4326, 4326);
    OSRSetAxisMappingStrategy(s4326, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy(sutm, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(sutm, s4326);
    size_t opaque = 0, clear = 0, checked = 0;
    for (int64_t v = 1; v < h; v += 3)
        for (int64_t u = 1; u < w; u += 3) {
            double x = info.geotransform[0] + (u + 0.5) * info.geotransform[1];
            double y = info.geotransform[3] + (v + 0.5) * info.geotransform[5], z = 0;
            ASSERT_TRUE(OCTTransform(ct, 1, &x, &y, &z));
            const double fx = (x - sgt[0]) / sgt[1] - 0.5, fy = (y - sgt[3]) / sgt[5] - 0.5;
            const int x0 = (int)floor(fx), y0 = (int)floor(fy);
            if (x0 < 1 || y0 < 1 || x0 + 2 >= sw || y0 + 2 >= sh)
                continue;
            int amin = 255, amax = 0, lo[3] = {255, 255, 255}, hi[3] = {0, 0, 0};
            for (int j = -1; j < 3; j++)
                for (int i = -1; i < 3; i++) {
                    const uint8_t* p = px + ((size_t)(y0 + j) * sw + x0 + i) * 4;
                    amin = p[3] < amin ? p[3] : amin, amax = p[3] > amax ? p[3] : amax;
                    for (int c = 0; c < 3; c++)
                        lo[c] = p[c] < lo[c] ? p[c] : lo[c], hi[c] = p[c] > hi[c] ? p[c] : hi[c];
                }
            const uint8_t* t = img + ((size_t)v * w + u) * 4;
            checked++;
            if (amin == 255) {
                opaque++;
                EXPECT_EQ_INT(255, t[3]);
                for (int c = 0; c < 3; c++) {
                    EXPECT_LE_INT(lo[c] - 1, t[c]);
                    EXPECT_GE_INT(hi[c] + 1, t[c]);
                }
            } else if (amax == 0) {
                clear++;
                EXPECT_EQ_INT(0, t[3]);
            }
        }
    tp_test_note("%zu texels checked: %zu under opaque source pixels, %zu under transparent",
                 checked, opaque, clear);
    EXPECT_GT(opaque, 10000);
    EXPECT_GT(clear, 1000);
    OCTDestroyCoordinateTransformation(ct);
    OSRDestroySpatialReference(sutm);
    OSRDestroySpatialReference(s4326);
    free(px);
    free(img);
    tp_imagery_close(im);
    real_free(&s);
}

/* Every level l + 1 texel is the alpha-weighted mean of its 2x2 texels of level l (alpha 0
 * beyond level l), rounded half up; alpha their mean (docs/imagery.md). */
TEST(levels_are_alpha_weighted_2x2_means)
{
    real_scene s;
    real_load(&s);
    const char* dir = make_tmp_dir();
    char out[600];
    snprintf(out, sizeof out, "%s/crater.tpi", dir);
    const char* src[1] = {s.image};
    tp_imagery* im = build_open(src, 1, &s.t, 2, out);
    tp_imagery_info info;
    tp_imagery_get_info(im, &info);
    ASSERT_GE_INT(info.levels, 3);
    size_t partial = 0;
    for (int l = 0; l + 1 < info.levels; l++) {
        int64_t w, h, w1, h1;
        uint8_t* a = read_level(im, l, &w, &h);
        uint8_t* b = read_level(im, l + 1, &w1, &h1);
        EXPECT_EQ_INT((w + 1) / 2, w1);
        EXPECT_EQ_INT((h + 1) / 2, h1);
        int bad = 0;
        for (int64_t v = 0; v < h1; v++)
            for (int64_t u = 0; u < w1; u++) {
                unsigned sa = 0, sc[3] = {0, 0, 0};
                for (int j = 0; j < 2; j++)
                    for (int i = 0; i < 2; i++) {
                        const int64_t x = 2 * u + i, y = 2 * v + j;
                        if (x >= w || y >= h)
                            continue;
                        const uint8_t* p = a + ((size_t)y * w + x) * 4;
                        sa += p[3];
                        for (int c = 0; c < 3; c++)
                            sc[c] += p[c] * (unsigned)p[3];
                    }
                uint8_t e[4] = {0, 0, 0, 0};
                if (sa > 0) {
                    for (int c = 0; c < 3; c++)
                        e[c] = (uint8_t)((2 * sc[c] + sa) / (2 * sa));
                    e[3] = (uint8_t)((sa + 2) / 4);
                }
                partial += sa > 0 && sa < 4 * 255;
                const uint8_t* g = b + ((size_t)v * w1 + u) * 4;
                if (memcmp(e, g, 4) != 0 && bad++ < 5)
                    ADD_FAILURE("level %d texel (%lld, %lld): %d %d %d %d, expected %d %d %d %d",
                                l + 1, (long long)u, (long long)v, g[0], g[1], g[2], g[3], e[0],
                                e[1], e[2], e[3]);
            }
        free(a);
        free(b);
    }
    tp_test_note("%zu texels of levels >= 1 partly transparent below", partial);
    EXPECT_GT(partial, 100); /* the alpha weighting was exercised */
    tp_imagery_close(im);
    real_free(&s);
}

/* ---------------------------------------------------------------------------------------------
 * Geometry: sizes, shifts, empty blocks
 */

static void solid_pixel(int x, int y, uint8_t* p, void* user)
{
    (void)x, (void)y;
    const uint8_t* c = user;
    memcpy(p, c, 4);
}

/* An opaque image of colour rgba over UTM box (e0, n0)..(e1, n1) (approximately: its
 * geographic bounding box). */
static void write_box(const char* path, const char* wkt, double e0, double n0, double e1, double n1,
                      const uint8_t rgba[4])
{
    double lon0, lat0, lon1, lat1;
    utm_to_lonlat(wkt, e0, n0, &lon0, &lat0);
    utm_to_lonlat(wkt, e1, n1, &lon1, &lat1);
    const double d = 0.001;
    const double gt[6] = {lon0, d, 0, lat0, 0, -d};
    write_tif(path, (int)ceil((lon1 - lon0) / d), (int)ceil((lat0 - lat1) / d), gt, 4, solid_pixel,
              (void*)rgba);
}

TEST(sizes_shifts_and_empty_blocks)
{
    const char* dir = make_tmp_dir();
    char wkt[4096], tif[600], out[600];
    /* 301 x 203 pixels of 100 m: no side a multiple of the block at any shift */
    const tp_imagery_target t = utm_target(301, 203, 100.0, 540000.0, 4780000.0, wkt, sizeof wkt);
    snprintf(tif, sizeof tif, "%s/box.tif", dir);
    const uint8_t green[4] = {10, 200, 30, 255};
    /* the image covers the grid's western third only */
    write_box(tif, wkt, 538000.0, 4782000.0, 550000.0, 4758000.0, green);
    const char* src[1] = {tif};
    for (int shift = -3; shift <= 3; shift++) {
        snprintf(out, sizeof out, "%s/box%d.tpi", dir, shift + 3);
        tp_imagery* im = build_open(src, 1, &t, shift, out);
        tp_imagery_info info;
        tp_imagery_get_info(im, &info);
        /* level 0: the grid times 2^shift (rounded up), each level half (rounded up) down to
         * one block */
        int64_t w = shift >= 0 ? (int64_t)301 << shift : (301 + (1 << -shift) - 1) >> -shift;
        int64_t h = shift >= 0 ? (int64_t)203 << shift : (203 + (1 << -shift) - 1) >> -shift;
        EXPECT_EQ_INT(w, info.width);
        EXPECT_EQ_INT(h, info.height);
        EXPECT_EQ_DBL(100.0 / pow(2, shift), info.geotransform[1]);
        EXPECT_EQ_INT(301, info.grid_width);
        EXPECT_EQ_INT(203, info.grid_height);
        int levels = 0;
        uint64_t nonempty = 0;
        for (;;) {
            int64_t lw, lh;
            int cols, rows;
            tp_imagery_level_size(im, levels, &lw, &lh, &cols, &rows);
            EXPECT_EQ_INT(w, lw);
            EXPECT_EQ_INT(h, lh);
            EXPECT_EQ_INT((w + B - 1) / B, cols);
            EXPECT_EQ_INT((h + B - 1) / B, rows);
            /* the texels east of 550 km (with a texel of margin) are empty: so are the blocks
             * wholly east of it; the blocks over the west third are not */
            const double texel = 100.0 / pow(2, shift) * pow(2, levels);
            for (int by = 0; by < rows; by++)
                for (int bx = 0; bx < cols; bx++) {
                    const double e_west = 540000.0 + bx * B * texel;
                    const int empty = tp_imagery_block_is_empty(im, levels, bx, by);
                    nonempty += !empty;
                    if (e_west > 550000.0 + texel)
                        EXPECT_TRUE(empty);
                    if (e_west + texel < 549000.0 && by * B * texel < 20000.0)
                        EXPECT_FALSE(empty);
                }
            levels++;
            if (w <= B && h <= B)
                break;
            w = (w + 1) / 2, h = (h + 1) / 2;
        }
        EXPECT_EQ_INT(levels, info.levels);
        EXPECT_EQ_INT(nonempty, info.nonempty_blocks);
        /* out of range: empty and all zero */
        uint8_t blk[B * B * 4];
        memset(blk, 7, sizeof blk);
        tp_error err = {0};
        EXPECT_TRUE(tp_imagery_block_is_empty(im, levels, 0, 0));
        EXPECT_TRUE(tp_imagery_block_is_empty(im, 0, -1, 0));
        EXPECT_OK(tp_imagery_read_block(im, 0, 1000, 0, blk, &err));
        int zero = 1;
        for (size_t k = 0; k < sizeof blk; k++)
            zero = zero && blk[k] == 0;
        EXPECT_TRUE(zero);
        /* a texel in the middle of the covered part is the image's colour, opaque */
        int64_t lw, lh;
        uint8_t* img = read_level(im, 0, &lw, &lh);
        const int64_t u = (int64_t)(5000.0 / info.geotransform[1]);
        const int64_t v = (int64_t)(10000.0 / -info.geotransform[5]);
        EXPECT_EQ_INT(0, memcmp(img + ((size_t)v * lw + u) * 4, green, 4));
        EXPECT_EQ_INT(0, img[((size_t)v * lw + lw - 1) * 4 + 3]); /* the east: transparent */
        free(img);
        tp_imagery_close(im);
    }
}

TEST(shift_or_size_out_of_range_refused)
{
    const char* dir = make_tmp_dir();
    char wkt[4096], tif[600], out[600];
    const uint8_t red[4] = {255, 0, 0, 255};
    snprintf(tif, sizeof tif, "%s/box.tif", dir);
    snprintf(out, sizeof out, "%s/x.tpi", dir);
    tp_imagery_target t = utm_target(100, 100, 100.0, 540000.0, 4780000.0, wkt, sizeof wkt);
    write_box(tif, wkt, 540000.0, 4780000.0, 550000.0, 4770000.0, red);
    const char* src[1] = {tif};
    tp_error err = {0};
    tp_imagery_build_options o = {0};
    o.texel_shift = 9;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_imagery_build(src, 1, &t, &o, out, &err));
    o.texel_shift = -9;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_imagery_build(src, 1, &t, &o, out, &err));
    /* 2^24 posts at 2^8 texels each: a level 0 of 2^32 texels a side */
    t.width = 1 << 24;
    t.geotransform[1] = 0.01, t.geotransform[5] = -0.01;
    o.texel_shift = 8;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_imagery_build(src, 1, &t, &o, out, &err));
    EXPECT_CONTAINS(err.message, "2^31");
    EXPECT_TRUE(access(out, F_OK) != 0);
    /* 4000 posts at 2^6 texels each: a block row of level 0 alone is 1000 blocks, 256 MB */
    t.width = 4000;
    t.geotransform[1] = 2.5, t.geotransform[5] = -2.5;
    o.texel_shift = 6;
    o.memory_bytes = 64.0 * 1024 * 1024;
    EXPECT_STATUS(TP_ERR_OUT_OF_MEMORY, tp_imagery_build(src, 1, &t, &o, out, &err));
    EXPECT_CONTAINS(err.message, "give");
    EXPECT_TRUE(access(out, F_OK) != 0);
}

/* The warps of level 0's block rows run on several threads: the file is the same. */
TEST(same_bytes_whatever_the_threads)
{
    const char* dir = make_tmp_dir();
    char wkt[4096], tif[600], out[2][600];
    const tp_imagery_target t = utm_target(300, 200, 200.0, 540000.0, 4780000.0, wkt, sizeof wkt);
    double lon0, lat0;
    utm_to_lonlat(wkt, 535000.0, 4785000.0, &lon0, &lat0);
    const double gt[6] = {lon0, 0.002, 0, lat0, 0, -0.002};
    const markers m = {{100, 300}, {50, 150}};
    snprintf(tif, sizeof tif, "%s/m.tif", dir);
    write_tif(tif, 400, 300, gt, 3, marker_pixel, (void*)&m);
    const char* src[1] = {tif};
    for (int k = 0; k < 2; k++) {
        tp_error err = {0};
        tp_imagery_build_options o = {0};
        o.texel_shift = 2; /* 1200 x 800 texels: 4 block rows */
        o.threads = k == 0 ? 1 : 3;
        snprintf(out[k], sizeof out[k], "%s/t%d.tpi", dir, k);
        ASSERT_OK(tp_imagery_build(src, 1, &t, &o, out[k], &err));
    }
    size_t n0, n1;
    uint8_t* a = slurp(out[0], &n0);
    uint8_t* b = slurp(out[1], &n1);
    EXPECT_EQ_INT(n0, n1);
    EXPECT_TRUE(n0 == n1 && memcmp(a, b, n0) == 0);
    free(a);
    free(b);
}

/* ---------------------------------------------------------------------------------------------
 * Mosaics
 */

static void half_alpha_pixel(int x, int y, uint8_t* p, void* user)
{
    const uint8_t* c = user;
    memcpy(p, c, 4);
    (void)y;
    if (x % 40 < 20) /* stripes of transparency */
        p[3] = 0;
}

TEST(later_source_drawn_over_earlier)
{
    const char* dir = make_tmp_dir();
    char wkt[4096], a[600], b[600], c[600], out[600];
    const tp_imagery_target t = utm_target(200, 100, 100.0, 540000.0, 4780000.0, wkt, sizeof wkt);
    const uint8_t red[4] = {250, 0, 0, 255}, blue[4] = {0, 0, 250, 255};
    snprintf(a, sizeof a, "%s/red.tif", dir);
    snprintf(b, sizeof b, "%s/blue.tif", dir);
    snprintf(c, sizeof c, "%s/striped.tif", dir);
    write_box(a, wkt, 538000.0, 4782000.0, 552000.0, 4768000.0, red);  /* west */
    write_box(b, wkt, 546000.0, 4782000.0, 562000.0, 4768000.0, blue); /* overlaps 546..552 */
    const uint8_t green[4] = {0, 250, 0, 255};
    double lon0, lat0;
    utm_to_lonlat(wkt, 538000.0, 4782000.0, &lon0, &lat0);
    const double gt[6] = {lon0, 0.001, 0, lat0, 0, -0.001};
    write_tif(c, 300, 200, gt, 4, half_alpha_pixel, (void*)green);
    /* texel columns at 544 km (red only), 549 km (both), 556 km (blue only), row at 4775 km */
    const int64_t row = 50, west = 40, mid = 90, east = 160;
    for (int order = 0; order < 2; order++) {
        const char* src[2] = {order ? b : a, order ? a : b};
        snprintf(out, sizeof out, "%s/m%d.tpi", dir, order);
        tp_imagery* im = build_open(src, 2, &t, 0, out);
        int64_t w, h;
        uint8_t* img = read_level(im, 0, &w, &h);
        EXPECT_EQ_INT(0, memcmp(img + (row * w + west) * 4, red, 4));
        EXPECT_EQ_INT(0, memcmp(img + (row * w + east) * 4, blue, 4));
        EXPECT_EQ_INT(0, memcmp(img + (row * w + mid) * 4, order ? red : blue, 4));
        tp_imagery_info info;
        tp_imagery_get_info(im, &info);
        EXPECT_CONTAINS(info.notes, order ? b : a);
        free(img);
        tp_imagery_close(im);
    }
    /* a later source's transparent parts leave the earlier one visible */
    const char* src[2] = {a, c};
    snprintf(out, sizeof out, "%s/striped.tpi", dir);
    tp_imagery* im = build_open(src, 2, &t, 0, out);
    int64_t w, h;
    uint8_t* img = read_level(im, 0, &w, &h);
    size_t reds = 0, greens = 0;
    for (int64_t u = 0; u < 100; u++) {
        const uint8_t* p = img + (row * w + u) * 4;
        reds += memcmp(p, red, 4) == 0;
        greens += memcmp(p, green, 4) == 0;
    }
    tp_test_note("west 100 texels of row %lld: %zu red, %zu green", (long long)row, reds, greens);
    EXPECT_GT(reds, 20);
    EXPECT_GT(greens, 20);
    free(img);
    tp_imagery_close(im);
}

/* ---------------------------------------------------------------------------------------------
 * Damage, read with the documented layout (docs/imagery.md)
 */
static uint32_t crc32_ref(const uint8_t* p, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}
static uint32_t le32(const uint8_t* p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static uint64_t le64(const uint8_t* p)
{
    return le32(p) | (uint64_t)le32(p + 4) << 32;
}
static void put32(uint8_t* p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

static uint8_t* slurp(const char* path, size_t* size)
{
    FILE* f = fopen(path, "rb");
    ASSERT_TRUE(f != NULL);
    fseek(f, 0, SEEK_END);
    *size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    uint8_t* d = malloc(*size);
    ASSERT_TRUE(d && fread(d, 1, *size, f) == *size);
    fclose(f);
    return d;
}
static void spill(const char* path, const uint8_t* d, size_t size)
{
    FILE* f = fopen(path, "wb");
    ASSERT_TRUE(f && fwrite(d, 1, size, f) == size);
    fclose(f);
}

/* A small real pyramid (the craterlake imagery, 2 levels) in dir; its path in out. */
static void small_pyramid(const char* dir, char* out, size_t cap)
{
    real_scene s;
    real_load(&s);
    snprintf(out, cap, "%s/crater.tpi", dir);
    const char* src[1] = {s.image};
    tp_imagery_close(build_open(src, 1, &s.t, 0, out));
    real_free(&s);
}

TEST(flipped_block_byte_fails_that_block_only)
{
    const char* dir = make_tmp_dir();
    char path[600], bad[600];
    small_pyramid(dir, path, sizeof path);
    size_t size;
    uint8_t* d = slurp(path, &size);
    ASSERT_EQ_INT(0, memcmp(d, "\x89TPI\r\n\x1a\n", 8));
    const uint32_t hb = le32(d + 12);
    const uint64_t table = (hb + 7) & ~(uint64_t)7;
    /* level 0's block (1, 0): table entry 1 */
    const uint8_t* e = d + table + 24;
    ASSERT_EQ_INT(1, e[16]); /* zstd */
    const uint64_t off = le64(e);
    d[off + le32(e + 8) / 2] ^= 0x40;
    snprintf(bad, sizeof bad, "%s/bad.tpi", dir);
    spill(bad, d, size);
    tp_imagery* im = NULL;
    tp_error err = {0};
    ASSERT_OK(tp_imagery_open(bad, &im, &err));
    uint8_t blk[B * B * 4];
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_read_block(im, 0, 1, 0, blk, &err));
    EXPECT_CONTAINS(err.message, bad);
    EXPECT_CONTAINS(err.message, "level 0, block (1, 0)");
    EXPECT_CONTAINS(err.message, "checksum");
    EXPECT_OK(tp_imagery_read_block(im, 0, 0, 0, blk, &err));
    EXPECT_OK(tp_imagery_read_block(im, 1, 0, 0, blk, &err));
    tp_imagery_close(im);
    /* the same damage with the block's CRC32 made to match: the decoder refuses it */
    put32(d + table + 24 + 12, crc32_ref(d + off, le32(e + 8)));
    uint32_t tcrc = crc32_ref(d + table, (size_t)le64(d + size - 40 + 8));
    put32(d + size - 40 + 16, tcrc);
    put32(d + size - 40 + 24, crc32_ref(d + size - 40, 24));
    spill(bad, d, size);
    ASSERT_OK(tp_imagery_open(bad, &im, &err));
    const tp_status st = tp_imagery_read_block(im, 0, 1, 0, blk, &err);
    if (st == TP_OK) /* zstd may decode the damaged frame: then it differs, and is still a block */
        tp_test_note("damaged frame with a matching CRC decoded");
    else
        EXPECT_CONTAINS(err.message, "level 0, block (1, 0)");
    tp_imagery_close(im);
    free(d);
}

TEST(damaged_header_table_or_footer_refused)
{
    const char* dir = make_tmp_dir();
    char path[600], bad[600];
    small_pyramid(dir, path, sizeof path);
    size_t size;
    uint8_t* d = slurp(path, &size);
    const uint32_t hb = le32(d + 12);
    const uint64_t table = (hb + 7) & ~(uint64_t)7;
    snprintf(bad, sizeof bad, "%s/bad.tpi", dir);
    const struct {
        size_t at;
        const char* says;
    } cases[] = {{40, "damaged header"},
                 {(size_t)table + 5, "damaged block table"},
                 {size - 40 + 3, "damaged footer"},
                 {size - 3, "truncated or damaged"}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        d[cases[k].at] ^= 0x10;
        spill(bad, d, size);
        d[cases[k].at] ^= 0x10;
        tp_imagery* im = NULL;
        tp_error err = {0};
        EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_open(bad, &im, &err));
        EXPECT_TRUE(im == NULL);
        EXPECT_CONTAINS(err.message, bad);
        EXPECT_CONTAINS(err.message, cases[k].says);
    }
    /* a newer version, with its CRC32 right */
    put32(d + 8, 3);
    put32(d + hb - 4, crc32_ref(d, hb - 4));
    spill(bad, d, size);
    tp_imagery* im = NULL;
    tp_error err = {0};
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_open(bad, &im, &err));
    EXPECT_CONTAINS(err.message, "newer");
    free(d);
}

TEST(truncated_files_and_other_files_refused)
{
    const char* dir = make_tmp_dir();
    char path[600], bad[600];
    small_pyramid(dir, path, sizeof path);
    size_t size;
    uint8_t* d = slurp(path, &size);
    snprintf(bad, sizeof bad, "%s/cut.tpi", dir);
    const size_t cuts[] = {0, 5, 100, 180, le32(d + 12), size / 2, size - 41, size - 1};
    for (size_t k = 0; k < sizeof cuts / sizeof cuts[0]; k++) {
        spill(bad, d, cuts[k]);
        tp_imagery* im = NULL;
        tp_error err = {0};
        EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_open(bad, &im, &err));
        EXPECT_CONTAINS(err.message, bad);
        if (cuts[k] >= 8)
            EXPECT_TRUE(strstr(err.message, "truncated") || strstr(err.message, "damaged"));
    }
    /* another file: a store's signature, a text file */
    memcpy(d, "\x89TPT\r\n\x1a\n", 8);
    spill(bad, d, size);
    tp_imagery* im = NULL;
    tp_error err = {0};
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_open(bad, &im, &err));
    EXPECT_CONTAINS(err.message, "not a terrapatch imagery pyramid");
    spill(bad, (const uint8_t*)"hello, world\n", 13);
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_imagery_open(bad, &im, &err));
    EXPECT_CONTAINS(err.message, "not a terrapatch imagery pyramid");
    snprintf(bad, sizeof bad, "%s/missing.tpi", dir);
    EXPECT_STATUS(TP_ERR_IO, tp_imagery_open(bad, &im, &err));
    EXPECT_STATUS(TP_ERR_IO, tp_imagery_open(dir, &im, &err));
    free(d);
}

/* ---------------------------------------------------------------------------------------------
 * Bad sources and outputs
 */
TEST(bad_sources_and_outputs_leave_no_file)
{
    const char* dir = make_tmp_dir();
    char wkt[4096], tif[600], far[600], plain[600], out[600];
    const tp_imagery_target t = utm_target(100, 100, 100.0, 540000.0, 4780000.0, wkt, sizeof wkt);
    const uint8_t red[4] = {255, 0, 0, 255};
    snprintf(tif, sizeof tif, "%s/box.tif", dir);
    snprintf(far, sizeof far, "%s/far.tif", dir);
    snprintf(plain, sizeof plain, "%s/plain.tif", dir);
    snprintf(out, sizeof out, "%s/out.tpi", dir);
    write_box(tif, wkt, 540000.0, 4780000.0, 550000.0, 4770000.0, red);
    write_box(far, wkt, 740000.0, 4780000.0, 750000.0, 4770000.0, red); /* 200 km east */
    /* a TIFF without georeference */
    GDALAllRegister();
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), plain, 10, 10, 3, GDT_Byte, NULL);
    ASSERT_TRUE(ds != NULL);
    GDALClose(ds);
    tp_error err = {0};
    const struct {
        const char* src;
        tp_status st;
        const char* says;
    } cases[] = {{far, TP_ERR_BAD_DATA, "does not overlap"},
                 {plain, TP_ERR_BAD_DATA, "no georeference"},
                 {"/nonexistent/x.tif", TP_ERR_IO, "cannot open"}};
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; k++) {
        const char* src[2] = {tif, cases[k].src};
        EXPECT_STATUS(cases[k].st, tp_imagery_build(src, 2, &t, NULL, out, &err));
        EXPECT_CONTAINS(err.message, cases[k].src);
        EXPECT_CONTAINS(err.message, cases[k].says);
        EXPECT_TRUE(access(out, F_OK) != 0);
    }
    const char* src[1] = {tif};
    char nodir[700];
    snprintf(nodir, sizeof nodir, "%s/no/such/dir/out.tpi", dir);
    EXPECT_STATUS(TP_ERR_IO, tp_imagery_build(src, 1, &t, NULL, nodir, &err));
    EXPECT_CONTAINS(err.message, nodir);
    /* nothing else was left in dir: no temporary file */
    DIR* dd = opendir(dir);
    struct dirent* de;
    while ((de = readdir(dd)) != NULL)
        EXPECT_TRUE(strstr(de->d_name, ".tmp") == NULL);
    closedir(dd);
}

/* Any number of threads read one open pyramid at once (pread, per-thread zstd contexts): each
 * thread reads every block of every level many times and finds what one thread read first. */
typedef struct reader_job {
    const tp_imagery* im;
    const uint8_t* expect; /* every block of every level, in table order */
    int failures;
} reader_job;

static void* reader(void* arg)
{
    reader_job* j = arg;
    tp_imagery_info info;
    tp_imagery_get_info(j->im, &info);
    uint8_t* blk = malloc((size_t)B * B * 4);
    for (int round = 0; round < 8 && blk; round++) {
        size_t k = 0;
        for (int l = 0; l < info.levels; l++) {
            int cols, rows;
            tp_imagery_level_size(j->im, l, NULL, NULL, &cols, &rows);
            for (int by = 0; by < rows; by++)
                for (int bx = 0; bx < cols; bx++, k++) {
                    tp_error err = {0};
                    if (tp_imagery_read_block(j->im, l, bx, by, blk, &err) != TP_OK ||
                        memcmp(blk, j->expect + k * B * B * 4, (size_t)B * B * 4) != 0)
                        j->failures++;
                }
        }
    }
    free(blk);
    return NULL;
}

TEST(threads_read_one_pyramid_at_once)
{
    const char* dir = make_tmp_dir();
    char path[600];
    small_pyramid(dir, path, sizeof path);
    tp_imagery* im = NULL;
    tp_error err = {0};
    ASSERT_OK(tp_imagery_open(path, &im, &err));
    tp_imagery_info info;
    tp_imagery_get_info(im, &info);
    size_t blocks = 0;
    for (int l = 0; l < info.levels; l++) {
        int cols, rows;
        tp_imagery_level_size(im, l, NULL, NULL, &cols, &rows);
        blocks += (size_t)cols * rows;
    }
    uint8_t* expect = malloc(blocks * B * B * 4);
    ASSERT_TRUE(expect != NULL);
    size_t k = 0;
    for (int l = 0; l < info.levels; l++) {
        int cols, rows;
        tp_imagery_level_size(im, l, NULL, NULL, &cols, &rows);
        for (int by = 0; by < rows; by++)
            for (int bx = 0; bx < cols; bx++, k++)
                ASSERT_OK(tp_imagery_read_block(im, l, bx, by, expect + k * B * B * 4, &err));
    }
    pthread_t t[4];
    reader_job jobs[4];
    for (int i = 0; i < 4; i++) {
        jobs[i] = (reader_job){im, expect, 0};
        ASSERT_TRUE(pthread_create(&t[i], NULL, reader, &jobs[i]) == 0);
    }
    for (int i = 0; i < 4; i++) {
        pthread_join(t[i], NULL);
        EXPECT_EQ_INT(0, jobs[i].failures);
    }
    free(expect);
    tp_imagery_close(im);
}

#define TESTS(X)                                                                                   \
    X(marker_lands_on_its_texel_shift_0)                                                           \
    X(marker_lands_on_its_texel_shift_2)                                                           \
    X(marker_lands_on_its_texel_shift_minus_1)                                                     \
    X(real_imagery_matches_its_source_pixels)                                                      \
    X(levels_are_alpha_weighted_2x2_means)                                                         \
    X(sizes_shifts_and_empty_blocks)                                                               \
    X(shift_or_size_out_of_range_refused)                                                          \
    X(same_bytes_whatever_the_threads)                                                             \
    X(later_source_drawn_over_earlier)                                                             \
    X(flipped_block_byte_fails_that_block_only)                                                    \
    X(damaged_header_table_or_footer_refused)                                                      \
    X(truncated_files_and_other_files_refused)                                                     \
    X(threads_read_one_pyramid_at_once)                                                            \
    X(bad_sources_and_outputs_leave_no_file)
TP_TEST_MAIN(TESTS)
