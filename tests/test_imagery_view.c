/*
 * test_imagery_view.c - imagery in the viewer (app/render/imagery_view.c, clipmap.c, the
 * renderer's sampling), end to end: `terrapatch build` a store from the Crater Lake DEM,
 * `terrapatch imagery` a pyramid for it, `terrapatch view --headless` and `terrapatch bench`
 * as children, their screenshots and JSON read back.
 *
 *   - georeferencing: a marker at a known latitude and longitude (an EPSG:4326 GeoTIFF written
 *     here with GDAL) shows on the screen where `view --pick` finds the ground point that
 *     GeographicLib's UTM gives for that latitude and longitude, within half a texel;
 *   - toroidal updates: after a fast flight with small clip windows the last frame equals the
 *     one a fresh clipmap draws at the same place (bench's imagery_final_diff_pixels);
 *   - GPU memory is the clip layers' whatever the image size;
 *   - bad pyramids: one made for another store is refused; a damaged block is reported and the
 *     frame drawn without it;
 *   - the sun of --sun-date/--sun-time: cast shadows only darken (the same frame without them
 *     is nowhere darker) and darken more with a low sun; bad dates are usage errors; --light
 *     refuses an imagery pyramid; without a light map the shadows are the computed window's;
 *     with the day's light map beside the store they are streamed within its day (only
 *     darkening), computed outside it.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"
#include "tp_geo.h"
#include "tp_io.h"

#include "tp_test_child.h"

#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The marker image: 400 x 300 pixels of grey over this lon/lat box, pixel (MX, MY) red. */
#define LON0 (-122.15)
#define LAT0 42.97
#define DLON 0.000225
#define DLAT 0.0002
#define MX 200
#define MY 150

static void path_in(char* buf, size_t cap, const char* name)
{
    snprintf(buf, cap, "%s/%s", tp_test_child_dir("imagery_view"), name);
}

/* The Crater Lake store (once per test process). */
static const char* store(void)
{
    static char tpt[512];
    if (!tpt[0]) {
        char dem[1024], err[4096];
        REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif");
        path_in(tpt, sizeof tpt, "cl.tpt");
        const char* args[] = {"--patch", "17", dem, "-o", tpt, NULL};
        if (tp_test_run_terrapatch("build", args, err, sizeof err) != 0)
            FAIL("build: %s", err);
    }
    return tpt;
}

static void write_marker_image(const char* path)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path, 400, 300, 3, GDT_Byte, NULL);
    ASSERT_TRUE(ds != NULL);
    double gt[6] = {LON0, DLON, 0, LAT0, 0, -DLAT};
    GDALSetGeoTransform(ds, gt);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    OSRImportFromEPSG(srs, 4326);
    OSRSetAxisMappingStrategy(srs, OAMS_TRADITIONAL_GIS_ORDER);
    GDALSetSpatialRef(ds, srs);
    OSRDestroySpatialReference(srs);
    unsigned char* px = malloc(400 * 300);
    ASSERT_TRUE(px != NULL);
    for (int b = 1; b <= 3; b++) {
        memset(px, 128, 400 * 300);
        px[MY * 400 + MX] = b == 1 ? 255 : 0;
        EXPECT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, b), GF_Write, 0, 0, 400, 300, px, 400, 300,
                                 GDT_Byte, 0, 0) == CE_None);
    }
    free(px);
    GDALClose(ds);
}

/* Builds the pyramid of image for the store with 2^shift texels a post. */
static void imagery(const char* image, const char* tpi, const char* shift)
{
    char err[4096];
    const char* args[] = {"--quiet", "--texel-shift", shift, store(), image, "-o", tpi, NULL};
    if (tp_test_run_terrapatch("imagery", args, err, sizeof err) != 0)
        FAIL("imagery: %s", err);
}

/* mode: --imagery-mode (clipmap or blocks) */
static void marker_shows(const char* mode)
{
    char tif[512], tpi[512], png[512], err[4096], out[4096], name[64];
    snprintf(name, sizeof name, "marker-%s.tif", mode);
    path_in(tif, sizeof tif, name);
    snprintf(name, sizeof name, "marker-%s.tpi", mode);
    path_in(tpi, sizeof tpi, name);
    snprintf(name, sizeof name, "marker-%s.png", mode);
    path_in(png, sizeof png, name);
    write_marker_image(tif);
    imagery(tif, tpi, "3"); /* 22.0 m posts: 2.75 m texels */
    double lat = LAT0 - (MY + 0.5) * DLAT, lon = LON0 + (MX + 0.5) * DLON;
    int zone, northp;
    double e, n;
    ASSERT_OK(tp_geo_to_utmups(lat, lon, &zone, &northp, &e, &n, NULL));
    ASSERT_EQ_INT(zone, 10);
    /* straight down from 700 m above the highest ground: about 2 m a pixel */
    char cam[128];
    snprintf(cam, sizeof cam, "%.3f,%.3f,2580,0,-90", e, n);
    const char* args[] = {"--headless", "--size", "400x400", "--no-hud", "--camera", cam,
                          "--imagery", tpi, "--imagery-mode", mode, "--screenshot", png,
                          store(), NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("view", args, err, sizeof err), 0);
    int w, h;
    uint8_t* rgba;
    ASSERT_OK(tp_image_read_rgba(png, &w, &h, &rgba, NULL));
    /* the marker: red over the grey (hillshade scales r, g and b alike) */
    double sx = 0, sy = 0, count = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            const uint8_t* p = rgba + ((size_t)y * w + x) * 4;
            if (p[0] > 40 && p[0] > 1.5 * p[1] && p[0] > 1.5 * p[2])
                sx += x + 0.5, sy += y + 0.5, count++;
        }
    free(rgba);
    ASSERT_GT(count, 20); /* 18 x 22 m at about 2 m a pixel */
    EXPECT_LT(count, 400);
    char pick[64];
    snprintf(pick, sizeof pick, "%.3f,%.3f", sx / count, sy / count);
    const char* pargs[] = {"--headless", "--size", "400x400", "--no-hud", "--no-imagery",
                           "--camera", cam, "--pick", pick, store(), NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch_out("view", pargs, out, sizeof out, err, sizeof err), 0);
    double pe, pn;
    const char* at = strstr(out, ": E ");
    ASSERT_TRUE(at != NULL);
    ASSERT_EQ_INT(sscanf(at, ": E %lf N %lf", &pe, &pn), 2);
    double texel = 22.0131 / 8;
    EXPECT_NEAR(pe, e, texel / 2);
    EXPECT_NEAR(pn, n, texel / 2);
}

TEST(marker_shows_on_its_ground_point_within_half_a_texel)
{
    marker_shows("clipmap");
}

/* The same through Brodersen's texture per node (imagery_blocks.c): the node under the camera
 * samples its own window of the pyramid. */
TEST(blocks_mode_marker_shows_on_its_ground_point_within_half_a_texel)
{
    marker_shows("blocks");
}

/* A flight in blocks mode: the texture array stays within its budget (96 MiB: 384 layers of
 * 256 x 256 RGBA), layers are uploaded as nodes come into view, one draw call per node, and the
 * last frame equals the one a fresh pool draws at the same place. */
TEST(blocks_mode_flight_stays_within_the_gpu_budget)
{
    char img[1024], tpi[512], json[512], err[4096], text[16384];
    REQUIRE_DATA_FILE(img, "TP_SHARED_DATA_DIR", "craterlake-imagery-30m.tif");
    path_in(tpi, sizeof tpi, "blocks.tpi");
    path_in(json, sizeof json, "blocks.json");
    imagery(img, tpi, "3");
    const char* args[] = {"--frames", "60", "--segments", "1", "--speed", "3000", "--no-error",
                          "--size", "320x180", "--imagery", tpi, "--imagery-mode", "blocks",
                          "--json", json, store(), NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("bench", args, err, sizeof err), 0);
    tp_test_read_text(json, text, sizeof text);
    const char* with = strstr(text, "\"imagery_mode\": \"blocks\"");
    ASSERT_TRUE(with != NULL);
    double gpu_mb = tp_test_json_number_after(text, with, "imagery_gpu_mb");
    EXPECT_GT(gpu_mb, 0);
    EXPECT_LE(gpu_mb, 96 * 1048576 / 1e6);
    /* nodes came into view: layers were uploaded during the timed frames (9 on this flight) */
    EXPECT_GT(tp_test_json_number_after(text, with, "imagery_uploads_total"), 0);
    EXPECT_EQ_DBL(tp_test_json_number_after(text, with, "imagery_final_diff_pixels"), 0);
    /* one draw per node (these come before "imagery_mode" in its configuration, which begins
     * with "lod_mode"): nodes wholly in voids (this DEM's corners) draw nothing, so about as
     * many calls as nodes, against the few multi-draws of the configuration without imagery
     * (the headline, first in the file) */
    const char* cfg = with;
    while (cfg > text && strncmp(cfg, "\"lod_mode\"", 10) != 0)
        cfg--;
    double calls = tp_test_json_number_after(text, cfg, "draw_calls_median");
    EXPECT_GE(calls, 0.8 * tp_test_json_number_after(text, cfg, "nodes_drawn_median"));
    EXPECT_GT(calls, 10 * tp_test_json_number_after(text, NULL, "draw_calls_median"));
    EXPECT_GT(tp_test_json_number_after(text, cfg, "nodes_drawn_median"), 2);
}

/* A fast flight (3 km/s) with 2 x 2-block windows (512 texels) at 2.75 m texels: the windows are
 * moved dozens of times; the last frame equals a fresh clipmap's. */
TEST(fast_flight_leaves_nothing_stale)
{
    char img[1024], tpi[512], json[512], err[4096], text[16384];
    REQUIRE_DATA_FILE(img, "TP_SHARED_DATA_DIR", "craterlake-imagery-30m.tif");
    path_in(tpi, sizeof tpi, "real.tpi");
    path_in(json, sizeof json, "flight.json");
    imagery(img, tpi, "3");
    const char* args[] = {"--frames", "60", "--segments", "1", "--speed", "3000", "--no-error",
                          "--size", "320x180", "--clip-blocks", "2", "--imagery", tpi,
                          "--json", json, store(), NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("bench", args, err, sizeof err), 0);
    tp_test_read_text(json, text, sizeof text);
    const char* with = strstr(text, "\"imagery\": true");
    ASSERT_TRUE(with != NULL);
    EXPECT_EQ_DBL(tp_test_json_number_after(text, with, "imagery_final_diff_pixels"), 0);
    /* 2 x 2 blocks of 256^2 RGBA a level, 5 levels (3472 x 3072 texels down to one block) */
    EXPECT_NEAR(tp_test_json_number_after(text, with, "imagery_gpu_mb"), 5 * 512 * 512 * 4 / 1e6,
                1e-6);
    /* the windows did move: blocks were uploaded during the timed frames */
    EXPECT_GT(tp_test_json_number_after(text, with, "imagery_uploads_total"), 10);
}

TEST(pyramid_of_another_store_is_refused)
{
    char img[1024], dem[1024], other[512], tpi[512], png[512], err[4096];
    REQUIRE_DATA_FILE(img, "TP_SHARED_DATA_DIR", "craterlake-imagery-30m.tif");
    REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif");
    path_in(other, sizeof other, "other.tpt");
    path_in(tpi, sizeof tpi, "other.tpi");
    path_in(png, sizeof png, "other.png");
    /* the DEM cut 10 pixels in from its north-west corner: another grid */
    char crop[512];
    path_in(crop, sizeof crop, "crop.tif");
    GDALAllRegister();
    GDALDatasetH src = GDALOpen(dem, GA_ReadOnly);
    ASSERT_TRUE(src != NULL);
    char* targv[] = {"-srcwin", "10", "10", "300", "200", NULL};
    GDALTranslateOptions* to = GDALTranslateOptionsNew(targv, NULL);
    GDALDatasetH cropped = GDALTranslate(crop, src, to, NULL);
    GDALTranslateOptionsFree(to);
    ASSERT_TRUE(cropped != NULL);
    GDALClose(cropped);
    GDALClose(src);
    const char* bargs[] = {"--patch", "17", crop, "-o", other, NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("build", bargs, err, sizeof err), 0);
    const char* iargs[] = {"--quiet", other, img, "-o", tpi, NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("imagery", iargs, err, sizeof err), 0);
    const char* args[] = {"--headless", "--imagery", tpi, "--screenshot", png, store(), NULL};
    EXPECT_EQ_INT(tp_test_run_terrapatch("view", args, err, sizeof err), 1);
    EXPECT_CONTAINS(err, "other.tpi: made for another grid");
    FILE* f = fopen(png, "rb");
    EXPECT_TRUE(f == NULL);
    if (f)
        fclose(f);
}

TEST(damaged_block_is_reported_and_drawn_without)
{
    char img[1024], tpi[512], png[512], err[4096];
    REQUIRE_DATA_FILE(img, "TP_SHARED_DATA_DIR", "craterlake-imagery-30m.tif");
    path_in(tpi, sizeof tpi, "damaged.tpi");
    path_in(png, sizeof png, "damaged.png");
    imagery(img, tpi, "0");
    /* flip a byte in the middle of the file: inside some block's data (the header and the
     * table are at the start and the end) */
    FILE* f = fopen(tpi, "r+b");
    ASSERT_TRUE(f != NULL);
    fseek(f, 0, SEEK_END);
    long size = ftell(f);
    fseek(f, size / 2, SEEK_SET);
    int c = fgetc(f);
    fseek(f, size / 2, SEEK_SET);
    fputc(c ^ 0x5a, f);
    fclose(f);
    const char* args[] = {"--headless", "--imagery", tpi, "--screenshot", png, store(), NULL};
    EXPECT_EQ_INT(tp_test_run_terrapatch("view", args, err, sizeof err), 0);
    EXPECT_CONTAINS(err, "damaged.tpi");
    EXPECT_CONTAINS(err, "drawn without imagery there");
}

/* The frame with cast shadows against the same sun without them: pixels darker (by more than
 * 2 levels of the sum of r, g, b) and brighter. */
static void shadow_difference(const char* time, size_t* darker, size_t* brighter)
{
    char a[512], b[512], err[4096];
    path_in(a, sizeof a, "sun_shadows.png");
    path_in(b, sizeof b, "sun_plain.png");
    const char* with[] = {"--headless", "--size", "480x270", "--no-hud", "--no-imagery",
                          "--camera-geo", "42.93,-122.13,2500,60,-25", "--sun-date", "2026-06-21",
                          "--sun-time", time, "--screenshot", a, store(), NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("view", with, err, sizeof err), 0);
    EXPECT_CONTAINS(err, "sun 2026-06-21");
    const char* without[] = {"--headless", "--size", "480x270", "--no-hud", "--no-imagery",
                             "--camera-geo", "42.93,-122.13,2500,60,-25", "--sun-date",
                             "2026-06-21", "--sun-time", time, "--no-cast-shadows",
                             "--screenshot", b, store(), NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("view", without, err, sizeof err), 0);
    int w, h, w2, h2;
    uint8_t *pa, *pb;
    ASSERT_OK(tp_image_read_rgba(a, &w, &h, &pa, NULL));
    ASSERT_OK(tp_image_read_rgba(b, &w2, &h2, &pb, NULL));
    ASSERT_TRUE(w == w2 && h == h2);
    *darker = *brighter = 0;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        int sa = pa[4 * i] + pa[4 * i + 1] + pa[4 * i + 2];
        int sb = pb[4 * i] + pb[4 * i + 1] + pb[4 * i + 2];
        *darker += sa < sb - 2;
        *brighter += sa > sb + 2;
    }
    free(pa);
    free(pb);
}

/* Crater Lake (42.9 N, 122.1 W) on the June solstice: at 06:00 PDT (13:00 UTC) the sun is
 * 4.1 degrees up at azimuth 61 (the viewer's own line; tp_sun is checked against published
 * positions in test_sun.c) and the crater's rim shades much of the lake; at 13:00 PDT it is
 * 70 degrees up and shades little. */
TEST(cast_shadows_only_darken_and_grow_with_a_low_sun)
{
    size_t low_dark, low_bright, high_dark, high_bright;
    shadow_difference("06:00-07:00", &low_dark, &low_bright);
    shadow_difference("13:00-07:00", &high_dark, &high_bright);
    EXPECT_EQ_INT((int)low_bright, 0);
    EXPECT_EQ_INT((int)high_bright, 0);
    EXPECT_GT((double)low_dark, 0.05 * 480 * 270);
    EXPECT_GT((double)low_dark, 3.0 * (double)high_dark);
}

TEST(sun_date_errors_are_usage_errors)
{
    char err[4096];
    const char* only_date[] = {"--headless", "--stats-json", "/tmp/tp-never.json",
                               "--sun-date", "2026-06-21",   store(),
                               NULL};
    EXPECT_EQ_INT(tp_test_run_terrapatch("view", only_date, err, sizeof err), 2);
    EXPECT_CONTAINS(err, "--sun-date and --sun-time go together");
    const char* bad_day[] = {"--headless", "--stats-json", "/tmp/tp-never.json",
                             "--sun-date", "2026-02-29",   "--sun-time",
                             "12:00",      store(),        NULL};
    EXPECT_EQ_INT(tp_test_run_terrapatch("view", bad_day, err, sizeof err), 2);
    EXPECT_CONTAINS(err, "2026-02-29");
    const char* bad_zone[] = {"--headless",  "--stats-json", "/tmp/tp-never.json",
                              "--sun-date",  "2026-06-21",   "--sun-time",
                              "12:00+15:00", store(),        NULL};
    EXPECT_EQ_INT(tp_test_run_terrapatch("view", bad_zone, err, sizeof err), 2);
}

/* --light takes a light map (.tpl) only: an imagery pyramid is refused, naming the file, and
 * a DEM drawn whole is a usage error; with
 * --sun-date and no light map beside the store the shadows are the computed window's, as the
 * statistics say. */
TEST(light_option_refuses_an_imagery_pyramid)
{
    char img[1024], tpi[512], json[512], err[4096], text[4096];
    REQUIRE_DATA_FILE(img, "TP_SHARED_DATA_DIR", "craterlake-imagery-30m.tif");
    path_in(tpi, sizeof tpi, "not_light.tpi");
    path_in(json, sizeof json, "window.json");
    imagery(img, tpi, "0");
    const char* args[] = {
        "--headless", "--stats-json", json,         "--size", "160x90", "--light", tpi,
        "--sun-date", "2026-06-21",   "--sun-time", "12:00",  store(),  NULL};
    EXPECT_EQ_INT(tp_test_run_terrapatch("view", args, err, sizeof err), 1);
    EXPECT_CONTAINS(err, "not_light.tpi");
    EXPECT_CONTAINS(err, "not a light map");
    char dem[1024];
    REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif");
    const char* whole[] = {"--headless", "--stats-json", json, "--size", "160x90",
                           "--whole",    "--light",      tpi,  dem,      NULL};
    EXPECT_EQ_INT(tp_test_run_terrapatch("view", whole, err, sizeof err), 2);
    EXPECT_CONTAINS(err, "--light shadows stores");
    const char* window[] = {"--headless", "--size", "160x90", "--no-imagery", "--sun-date",
                            "2026-06-21", "--sun-time", "12:00", "--stats-json", json, store(),
                            NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("view", window, err, sizeof err), 0);
    tp_test_read_text(json, text, sizeof text);
    EXPECT_CONTAINS(text, "\"light_source\": \"window\"");
    EXPECT_GT(tp_test_json_number_after(text, NULL, "light_window_posts"), 100);
}

static void copy_file(const char* from, const char* to)
{
    FILE* in = fopen(from, "rb");
    FILE* out = fopen(to, "wb");
    ASSERT_TRUE(in != NULL && out != NULL);
    char buf[65536];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, in)) > 0)
        ASSERT_EQ_INT((int)fwrite(buf, 1, n, out), (int)n);
    fclose(in);
    ASSERT_EQ_INT(fclose(out), 0);
}

/* The day's light map (`terrapatch light STORE --day`, beside the store as STORE.tpl) is used
 * when the sun's time lies in its day: shadows streamed (the statistics say so, at tau in the
 * day), and they only darken (the frame with --no-cast-shadows is nowhere darker) and darken a
 * real share of the frame at 06:00 PDT; another date falls back to the window with one line
 * saying why; --light without --sun-date starts at the middle of the day (tau 127.5). */
TEST(light_map_beside_the_store_is_streamed_within_its_day)
{
    char tpt[512], tpl[512], a[512], b[512], json[512], err[4096], text[8192];
    path_in(tpt, sizeof tpt, "lit.tpt");
    path_in(tpl, sizeof tpl, "lit.tpl");
    copy_file(store(), tpt); /* a store of its own: STORE.tpl beside it */
    const char* light[] = {"--day", "--quiet", "--date", "2026-06-21", tpt, NULL};
    if (tp_test_run_terrapatch("light", light, err, sizeof err) != 0)
        FAIL("light --day (the day's light map, issue 15): %s", err);
    path_in(a, sizeof a, "lit_streamed.png");
    path_in(b, sizeof b, "lit_plain.png");
    path_in(json, sizeof json, "lit.json");
    const char* with[] = {"--headless", "--size", "480x270", "--no-hud", "--no-imagery",
                          "--camera-geo", "42.93,-122.13,2500,60,-25", "--sun-date", "2026-06-21",
                          "--sun-time", "06:00-07:00", "--screenshot", a, "--stats-json", json,
                          tpt, NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("view", with, err, sizeof err), 0);
    EXPECT_CONTAINS(err, "lit.tpl");
    tp_test_read_text(json, text, sizeof text);
    EXPECT_CONTAINS(text, "\"light_source\": \"streamed\"");
    double tau = tp_test_json_number_after(text, NULL, "light_tau");
    EXPECT_GT(tau, 0);
    EXPECT_LT(tau, 255);
    EXPECT_GT(tp_test_json_number_after(text, NULL, "light_gpu_mb"), 0);
    const char* without[] = {"--headless", "--size", "480x270", "--no-hud", "--no-imagery",
                             "--camera-geo", "42.93,-122.13,2500,60,-25", "--sun-date",
                             "2026-06-21", "--sun-time", "06:00-07:00", "--no-cast-shadows",
                             "--screenshot", b, tpt, NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("view", without, err, sizeof err), 0);
    int w, h, w2, h2;
    uint8_t *pa, *pb;
    ASSERT_OK(tp_image_read_rgba(a, &w, &h, &pa, NULL));
    ASSERT_OK(tp_image_read_rgba(b, &w2, &h2, &pb, NULL));
    ASSERT_TRUE(w == w2 && h == h2);
    size_t darker = 0, brighter = 0;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        int sa = pa[4 * i] + pa[4 * i + 1] + pa[4 * i + 2];
        int sb = pb[4 * i] + pb[4 * i + 1] + pb[4 * i + 2];
        darker += sa < sb - 2;
        brighter += sa > sb + 2;
    }
    free(pa);
    free(pb);
    EXPECT_EQ_INT((int)brighter, 0);
    EXPECT_GT((double)darker, 0.05 * 480 * 270);
    const char* other_day[] = {"--headless", "--size", "160x90", "--sun-date", "2026-06-22",
                               "--sun-time", "06:00-07:00", "--stats-json", json, tpt, NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("view", other_day, err, sizeof err), 0);
    EXPECT_CONTAINS(err, "outside the light map's day");
    tp_test_read_text(json, text, sizeof text);
    EXPECT_CONTAINS(text, "\"light_source\": \"window\"");
    const char* mid[] = {"--headless", "--size", "160x90", "--light", tpl, "--stats-json", json,
                         tpt, NULL};
    ASSERT_EQ_INT(tp_test_run_terrapatch("view", mid, err, sizeof err), 0);
    tp_test_read_text(json, text, sizeof text);
    EXPECT_CONTAINS(text, "\"light_source\": \"streamed\"");
    EXPECT_NEAR(tp_test_json_number_after(text, NULL, "light_tau"), 127.5, 0.01);
}

#define TESTS(X)                                                                                   \
    X(marker_shows_on_its_ground_point_within_half_a_texel)                                        \
    X(blocks_mode_marker_shows_on_its_ground_point_within_half_a_texel)                            \
    X(blocks_mode_flight_stays_within_the_gpu_budget)                                              \
    X(fast_flight_leaves_nothing_stale)                                                            \
    X(pyramid_of_another_store_is_refused)                                                         \
    X(damaged_block_is_reported_and_drawn_without)                                                 \
    X(cast_shadows_only_darken_and_grow_with_a_low_sun)                                            \
    X(sun_date_errors_are_usage_errors)                                                            \
    X(light_option_refuses_an_imagery_pyramid)                                                     \
    X(light_map_beside_the_store_is_streamed_within_its_day)

TP_TEST_MAIN(TESTS)
