/*
 * test_light_day_cli.c - `terrapatch light ... --day` (app/commands/light_day.c) run as a child, its
 * light map (.tpl) read back with tp_imagery.h:
 *   - N42E001 (1239 x 1657 posts on its UTM grid: 2 x 2 tiles of 1024 with their margins): the
 *     map's level-0 texels, evaluated with tp_light_times_lit at three times of the day, agree
 *     with `terrapatch light --time T` (the one-moment GeoTIFF over the whole grid, read with
 *     GDAL) on >= 99% of the posts with a height (the shadows' share printed); the file has
 *     the kind, the day (sunrise to sunset as the one-moment run prints them) and the maps
 *     asked;
 *   - a store (Mt Hood): the default output beside it (.tpl for .tpt), `info` on the map and
 *     on the store, the JSON summary;
 *   - bad input: exit 1, nothing written.
 * Usage errors are tp_cli_test lines in tests/CMakeLists.txt.
 */
#define _GNU_SOURCE

#include "tp_imagery.h"
#include "tp_io.h"
#include "tp_test.h"

#include "tp_test_child.h"

#include <gdal.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define TESTS(X)                                                                                   \
    X(day_map_agrees_with_the_moments_on_n42e001)                                                  \
    X(store_gets_its_map_beside_it_and_info_describes_it)                                          \
    X(bad_input_exits_1_and_writes_nothing)

static const char* tmp_dir(void)
{
    return tp_test_child_dir("light_day");
}

static int run_light(const char* const* args, char* out, size_t out_cap, char* err, size_t err_cap)
{
    return tp_test_run_terrapatch_out("light", args, out, out_cap, err, err_cap);
}

/* Level 0 of a pyramid, whole (w x h texels, 4 bytes each). */
static uint8_t* read_level0(const tp_imagery* im, int64_t* w, int64_t* h)
{
    int cols, rows;
    tp_imagery_level_size(im, 0, w, h, &cols, &rows);
    const int B = TP_IMAGERY_BLOCK;
    uint8_t* img = malloc((size_t)*w * *h * 4);
    uint8_t* blk = malloc((size_t)B * B * 4);
    ASSERT_TRUE(img && blk);
    tp_error err;
    for (int by = 0; by < rows; ++by)
        for (int bx = 0; bx < cols; ++bx) {
            ASSERT_OK(tp_imagery_read_block(im, 0, bx, by, blk, &err));
            for (int y = 0; y < B && (int64_t)by * B + y < *h; ++y) {
                const int64_t x0 = (int64_t)bx * B, n = *w - x0 < B ? *w - x0 : B;
                memcpy(img + 4 * (((int64_t)by * B + y) * *w + x0), blk + 4 * (size_t)y * B,
                       4 * (size_t)n);
            }
        }
    free(blk);
    return img;
}

static uint8_t* read_byte_tif(const char* path, int w, int h)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    ASSERT_EQ_INT(w, GDALGetRasterXSize(ds));
    ASSERT_EQ_INT(h, GDALGetRasterYSize(ds));
    uint8_t* v = malloc((size_t)w * h);
    ASSERT_TRUE(v != NULL);
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, 0, 0, w, h, v, w, h, GDT_Byte, 0,
                             0) == CE_None);
    GDALClose(ds);
    return v;
}

/* Unix seconds of "YYYY-MM-DD HH:MM:SS UTC" as the command prints them; NaN if absent. */
static double printed_time(const char* out, const char* label)
{
    const char* p = strstr(out, label);
    int Y, M, D, h, m, s;
    if (!p || sscanf(p + strlen(label), " %d-%d-%d %d:%d:%d UTC", &Y, &M, &D, &h, &m, &s) != 6)
        return NAN;
    struct tm t;
    memset(&t, 0, sizeof t);
    t.tm_year = Y - 1900, t.tm_mon = M - 1, t.tm_mday = D;
    t.tm_hour = h, t.tm_min = m, t.tm_sec = s;
    return (double)timegm(&t);
}

TEST(day_map_agrees_with_the_moments_on_n42e001)
{
    char dem_path[1024], tpl[256], so[16384], se[8192];
    if (!tp_test_data_path(dem_path, sizeof dem_path, "TP_SHARED_DATA_DIR", "N42E001.hgt"))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    snprintf(tpl, sizeof tpl, "%s/n42.tpl", tmp_dir());
    const char* args[] = {dem_path, "--day", "--date", "2026-06-21", "-o", tpl, "--quiet", NULL};
    ASSERT_EQ_INT(0, run_light(args, so, sizeof so, se, sizeof se));
    const double rise = printed_time(so, "sunrise    "), set = printed_time(so, "sunset     ");
    ASSERT_TRUE(rise == rise && set == set);

    /* the render grid's heights: which posts have one */
    tp_dem* dem = NULL;
    tp_render_grid* g = NULL;
    tp_error err;
    ASSERT_OK(tp_dem_read(dem_path, &dem, &err));
    ASSERT_OK(tp_render_grid_build(dem, NULL, &g, &err));
    tp_dem_destroy(dem);

    tp_imagery* im = NULL;
    ASSERT_OK(tp_imagery_open(tpl, &im, &err));
    tp_imagery_info in;
    tp_imagery_get_info(im, &in);
    EXPECT_EQ_INT(TP_IMAGERY_KIND_LIGHT_TIMES, in.kind);
    EXPECT_EQ_INT(64, in.maps);
    EXPECT_EQ_INT(g->width, in.grid_width);
    EXPECT_EQ_INT(g->height, in.grid_height);
    EXPECT_EQ_INT(0, in.texel_shift);
    /* sunrise to sunset, to the second the text rounds to */
    EXPECT_NEAR(rise, in.time_first_s, 1.0);
    EXPECT_NEAR(set, in.time_last_s, 1.0);
    int64_t w, h;
    uint8_t* day = read_level0(im, &w, &h);
    ASSERT_EQ_INT(g->width, (int)w);
    ASSERT_EQ_INT(g->height, (int)h);

    /* early (the sun about 7 degrees up: shadows of a 1000 m ridge 8 km long, within the
     * tiles' 10 km margin), mid-morning and late */
    const double fractions[] = {0.06, 0.3, 0.94};
    for (int k = 0; k < 3; ++k) {
        /* a whole second of the day, as --time reads it */
        const time_t t =
            (time_t)floor(in.time_first_s + fractions[k] * (in.time_last_s - in.time_first_s));
        struct tm u;
        gmtime_r(&t, &u);
        char date[16], clock[16], tif[256];
        strftime(date, sizeof date, "%Y-%m-%d", &u);
        strftime(clock, sizeof clock, "%H:%M:%S", &u);
        snprintf(tif, sizeof tif, "%s/moment%d.tif", tmp_dir(), k);
        const char* moment[] = {dem_path, "--date", date, "--time", clock, "-o", tif, NULL};
        ASSERT_EQ_INT(0, run_light(moment, so, sizeof so, se, sizeof se));
        uint8_t* lit = read_byte_tif(tif, g->width, g->height);
        const double tau = tp_light_times_tau(in.time_first_s, in.time_last_s, (double)t);
        size_t valid = 0, agree = 0, lit_moment = 0;
        for (size_t i = 0; i < (size_t)w * h; ++i) {
            if (g->heights[i] != g->heights[i])
                continue;
            const int a = lit[i] == 255, b = tp_light_times_lit(day + 4 * i, tau);
            valid++;
            agree += a == b;
            lit_moment += a;
        }
        const double f = valid ? (double)agree / valid : 0.0;
        tp_test_note("%s %s UTC (tau %.1f): %zu of %zu posts agree (%.3f%%), %.1f%% in shadow",
                     date, clock, tau, agree, valid, 100.0 * f, 100.0 - 100.0 * lit_moment / valid);
        if (f < 0.99)
            FAIL("%s %s UTC: the day's map agrees with the moment on %.3f%% of %zu posts "
                 "(< 99%%)",
                 date, clock, 100.0 * f, valid);
        EXPECT_GT((double)valid, 0.9 * (double)w * h);
        free(lit);
    }
    free(day);
    tp_imagery_close(im);
    tp_render_grid_destroy(g);
}

TEST(store_gets_its_map_beside_it_and_info_describes_it)
{
    char dem[1024], store[256], tpl[256], json[256], so[16384], se[8192];
    if (!tp_test_data_path(dem, sizeof dem, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif"))
        SKIP("lf_elev_220_mt_hood_utm.tif not found (set TP_SHARED_DATA_DIR)");
    snprintf(store, sizeof store, "%s/hood.tpt", tmp_dir());
    snprintf(tpl, sizeof tpl, "%s/hood.tpl", tmp_dir());
    snprintf(json, sizeof json, "%s/hood.json", tmp_dir());
    const char* build[] = {dem, "-o", store, "--quiet", NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("build", build, se, sizeof se));
    const char* args[] = {store,      "--day", "--date", "2026-12-21", "--maps", "8",
                          "--margin", "3000",  "--json", json,         NULL};
    ASSERT_EQ_INT(0, run_light(args, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(se, "terrapatch light: wrote ");
    EXPECT_CONTAINS(se, tpl);
    EXPECT_CONTAINS(so, "margin 100 x 100 posts (3000 m)");
    EXPECT_TRUE(access(tpl, R_OK) == 0);
    char text[4096];
    tp_test_read_text(json, text, sizeof text);
    EXPECT_EQ_DBL(8.0, tp_test_json_number_after(text, NULL, "maps"));
    EXPECT_EQ_DBL(100.0, tp_test_json_number_after(text, NULL, "margin_posts"));
    tp_imagery* im = NULL;
    tp_error err;
    ASSERT_OK(tp_imagery_open(tpl, &im, &err));
    tp_imagery_info in;
    tp_imagery_get_info(im, &in);
    EXPECT_EQ_DBL((double)in.file_bytes, tp_test_json_number_after(text, NULL, "bytes"));
    EXPECT_EQ_INT(8, in.maps);
    /* a December day at 45 N: under nine hours between sunrise and sunset */
    EXPECT_GT(in.time_last_s - in.time_first_s, 8.0 * 3600);
    EXPECT_LT(in.time_last_s - in.time_first_s, 9.0 * 3600);
    tp_imagery_close(im);

    const char* info_tpl[] = {tpl, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("info", info_tpl, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(so, "kind:           light times");
    EXPECT_CONTAINS(so, "day:            2026-12-21 ");
    EXPECT_CONTAINS(so, "maps:           8 sun positions");
    EXPECT_CONTAINS(so, "0 damaged");
    const char* info_json[] = {"--json", tpl, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("info", info_json, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(so, "\"kind\": \"light times\"");
    EXPECT_EQ_DBL(8.0, tp_test_json_number_after(so, NULL, "maps"));
    const char* info_store[] = {store, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("info", info_store, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(so, "light map:      ");
    EXPECT_CONTAINS(so, tpl);
}

TEST(bad_input_exits_1_and_writes_nothing)
{
    char so[8192], se[8192];
    const char* missing[] = {"/nonexistent/dem.tif", "--day", "--date", "2026-06-21", "-o",
                             "/tmp/never.tpl",       NULL};
    EXPECT_EQ_INT(1, run_light(missing, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(se, "/nonexistent/dem.tif");
    char dem[1024];
    if (!tp_test_data_path(dem, sizeof dem, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif"))
        SKIP("lf_elev_220_mt_hood_utm.tif not found (set TP_SHARED_DATA_DIR)");
    const char* nodir[] = {dem, "--day", "--date", "2026-06-21", "-o", "/nonexistent/dir/x.tpl",
                           NULL};
    EXPECT_EQ_INT(1, run_light(nodir, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(se, "/nonexistent/dir");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "x.tpl"));
}

TP_TEST_MAIN(TESTS)
