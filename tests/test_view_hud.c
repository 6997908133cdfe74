/*
 * test_view_hud.c - what `terrapatch view` shows and tells (issue 29, 4.4 - 4.6), run headless
 * as a child:
 *
 *  - 4.4: a camera 2 m over a warped DEM's ground (heights stored in 1 m steps until issue 31: half a metre of
 *    quantisation error under the eye) reported "bound_max_px": null in --stats-json and
 *    "error bound max inf px" on the HUD: the full-resolution leaves around the eye reach the
 *    near plane, where the projection bound of their box is infinite. The bound is finite, at
 *    least what is measured on screen, and the stats count the nodes at the eye.
 *  - 4.5: the map grid at the default view of the Pyrenees tile (about 188 m a pixel) was a 1 km
 *    line every 5 pixels, a dark mesh over a third of the ground (34% of its pixels darkened by
 *    a quarter or more); its spacing follows the scale (10 km there: 8.7%) and the stats say
 *    which.
 *  - 4.6: the default HUD is three lines at the top of a 1280x720 picture (it was nine, over
 *    a third of its height); the engineering lines come with --hud-details (F4 in the window)
 *    and every figure of them is in --stats-json.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"
#include "tp_test_child.h"

#include "tp_io.h"

#include <unistd.h>

static const char* tmp_dir(void)
{
    return tp_test_child_dir("view_hud");
}

/* Removes what the tests wrote and the folder (a failed test leaves them to look at). */
static void cleanup(void)
{
    static const char* const names[] = {"stats.json", "hud.png", "grid.png", "plain.png"};
    char path[512];
    for (size_t i = 0; i < sizeof names / sizeof names[0]; i++) {
        snprintf(path, sizeof path, "%s/%s", tmp_dir(), names[i]);
        remove(path);
    }
    rmdir(tmp_dir());
}

typedef struct image {
    int w, h;
    uint8_t* px;
} image;

static void image_read(const char* path, image* im)
{
    tp_error err = {{0}};
    memset(im, 0, sizeof *im);
    if (tp_image_read_rgba(path, &im->w, &im->h, &im->px, &err) != TP_OK)
        FAIL("tp_image_read_rgba(%s): %s", path, err.message);
}

/* Runs `terrapatch view --headless ARGS... DEM` with --stats-json into json (cap bytes). */
static void view(const char* const* args, const char* dem, char* json, size_t cap)
{
    char stats[256], err[8192];
    snprintf(stats, sizeof stats, "%s/stats.json", tmp_dir());
    remove(stats);
    const char* argv[40];
    int n = 0;
    argv[n++] = "--headless";
    argv[n++] = "--stats-json";
    argv[n++] = stats;
    for (int i = 0; args[i] && n < 36; i++)
        argv[n++] = args[i];
    argv[n++] = dem;
    argv[n] = NULL;
    if (tp_test_run_terrapatch("view", argv, err, sizeof err) != 0)
        FAIL("view %s: %s", dem, err);
    tp_test_read_text(stats, json, cap);
}

/* ---- 4.4: the error bound at a camera on the ground ---- */

/* The ground's elevation at UTM position (zone, e, n) of dem, by `terrapatch point`. */
static double elevation(const char* dem, const char* zone, double e, double n)
{
    char es[32], ns[32], out[8192], err[4096];
    snprintf(es, sizeof es, "%.1f", e);
    snprintf(ns, sizeof ns, "%.1f", n);
    const char* args[] = {dem, zone, es, ns, "--json", "-", NULL};
    if (tp_test_run_terrapatch_out("point", args, out, sizeof out, err, sizeof err) != 0)
        FAIL("point %s %s %s %s: %s", dem, zone, es, ns, err);
    return tp_test_json_number_after(out, NULL, "elevation_m");
}

static void expect_finite_bound_near_the_ground(const char* file, const char* zone, double e,
                                                double n)
{
    char dem[1024], json[16384], cam[128];
    REQUIRE_DATA_FILE(dem, "TP_SAMPLE_DATA_DIR", file);
    const double z = elevation(dem, zone, e, n);
    ASSERT_TRUE(isfinite(z));
    const double views[][2] = {{0, -5}, {90, 0}, {200, -20}};
    for (size_t i = 0; i < sizeof views / sizeof views[0]; i++) {
        snprintf(cam, sizeof cam, "%.1f,%.1f,%.1f,%.0f,%.0f", e, n, z + 2, views[i][0],
                 views[i][1]);
        const char* args[] = {"--size", "320x180", "--camera", cam, NULL};
        view(args, dem, json, sizeof json);
        const double bound = tp_test_json_number_after(json, NULL, "bound_max_px");
        const double measured = tp_test_json_number_after(json, NULL, "max_error_px");
        tp_test_note("%s --camera %s: bound %g px, measured %g px", file, cam, bound, measured);
        if (!isfinite(bound))
            FAIL("%s --camera %s: bound_max_px is %g (null in the JSON)", file, cam, bound);
        /* what is measured on screen stays within the bound; half a metre at the eye is more
         * than a pixel, and the stats say which nodes it comes from */
        EXPECT_GE(bound, measured);
        EXPECT_GT(bound, 1.0);
        EXPECT_GT(tp_test_json_number_after(json, NULL, "bound_near_plane_nodes"), 0);
    }
}

TEST(error_bound_is_finite_on_the_ground_of_a_warped_tile)
{
    expect_finite_bound_near_the_ground("N42E001.hgt", "31n", 376407.7, 4706523.4);
    cleanup();
}

TEST(error_bound_is_finite_on_the_ground_of_an_ascii_grid)
{
    expect_finite_bound_near_the_ground("front_range_srtmgl3_144.asc", "13n", 457300, 4444600);
    cleanup();
}

/* ---- 4.6: the default HUD is short; the details are on request and in the stats ---- */

static int is_magenta(const uint8_t* p)
{
    return p[0] > 200 && p[1] < 60 && p[2] > 200;
}

/* The last row of the picture's upper half with a HUD pixel (anything but the magenta sky),
 * left of the compass panel; -1 for none. */
static int hud_bottom(const image* im)
{
    int last = -1;
    for (int y = 0; y < im->h / 2; y++)
        for (int x = 0; x < im->w * 3 / 4; x++)
            if (!is_magenta(im->px + 4 * ((size_t)y * im->w + x))) {
                last = y;
                break;
            }
    return last;
}

/* The HUD over a magenta sky (Mt Hood's eye looking up), 1280x720 (the overlay's scale 2: a
 * text line is 24 px): the last row it reaches. */
static int hud_rows(const char* hud_option)
{
    char dem[1024], json[16384], shot[256];
    REQUIRE_DATA_FILE(dem, "TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    snprintf(shot, sizeof shot, "%s/hud.png", tmp_dir());
    const char* args[] = {"--size",
                          "1280x720",
                          "--camera",
                          "600000,5012000,3600,0,60",
                          "--clear-color",
                          "1,0,1",
                          hud_option,
                          "--screenshot",
                          shot,
                          NULL};
    view(args, dem, json, sizeof json);
    image im;
    image_read(shot, &im);
    const int bottom = hud_bottom(&im);
    free(im.px);
    tp_test_note("%s: the HUD reaches row %d of 720", hud_option, bottom);
    return bottom;
}

TEST(default_hud_is_a_few_lines_and_details_come_on_request)
{
    const int short_hud = hud_rows("--hud");
    const int details = hud_rows("--hud-details");
    ASSERT_GT(short_hud, 10); /* there is a HUD */
    /* at most four lines of 24 px below the 10 px margin (three, and a legend) */
    EXPECT_LE(short_hud, 10 + 4 * 24);
    /* the details add at least their five lines */
    EXPECT_GE(details, short_hud + 5 * 24);
    cleanup();
}

TEST(engineering_figures_are_in_the_stats)
{
    char dem[1024], json[16384];
    REQUIRE_DATA_FILE(dem, "TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    const char* args[] = {"--size", "320x180", NULL};
    view(args, dem, json, sizeof json);
    static const char* const keys[] = {"fps",
                                       "cpu_ms",
                                       "select_ms",
                                       "upload_ms",
                                       "draw_ms",
                                       "triangles",
                                       "draw_calls",
                                       "patches_drawn",
                                       "gpu_bytes",
                                       "max_error_px",
                                       "rms_error_px",
                                       "bound_max_px",
                                       "bound_near_plane_nodes",
                                       "grid_m"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        EXPECT_TRUE(isfinite(tp_test_json_number_after(json, NULL, keys[i])));
    EXPECT_GT(tp_test_json_number_after(json, NULL, "fps"), 0);
    if (!strstr(json, "\"levels\": ["))
        FAIL("no levels in %s", json);
    cleanup();
}

/* ---- 4.5: the grid's spacing at the default view ---- */

/* Share of the ground's pixels that the grid darkens (by a quarter or more) in with against
 * without; the sky (the clear colour) left out. */
static double darkened(const image* with, const image* without)
{
    long ground = 0, dark = 0;
    for (size_t i = 0; i < (size_t)with->w * with->h; i++) {
        const uint8_t *a = with->px + 4 * i, *b = without->px + 4 * i;
        if (is_magenta(b))
            continue;
        ground++;
        dark += (a[0] + a[1] + a[2]) * 4 < (b[0] + b[1] + b[2]) * 3;
    }
    return ground ? (double)dark / ground : 0;
}

TEST(grid_at_the_default_view_follows_the_scale)
{
    char dem[1024], json[16384], with[256], without[256];
    REQUIRE_DATA_FILE(dem, "TP_SAMPLE_DATA_DIR", "N42E001.hgt");
    snprintf(with, sizeof with, "%s/grid.png", tmp_dir());
    snprintf(without, sizeof without, "%s/plain.png", tmp_dir());
    const char* plain[] = {"--clear-color", "1,0,1", "--screenshot", without, NULL};
    view(plain, dem, json, sizeof json);
    EXPECT_EQ_DBL(0, tp_test_json_number_after(json, NULL, "grid_m"));
    const char* grid[] = {"--clear-color", "1,0,1", "--grid", "1000", "--screenshot", with, NULL};
    view(grid, dem, json, sizeof json);
    /* about 188 m a pixel at the centre: 1 km lines would be 5 px apart, 10 km 53 px */
    EXPECT_EQ_DBL(10000, tp_test_json_number_after(json, NULL, "grid_m"));
    image a, b;
    image_read(with, &a);
    image_read(without, &b);
    ASSERT_EQ_INT(a.w, b.w);
    const double share = darkened(&a, &b);
    tp_test_note("the grid darkens %.1f%% of the ground", 100 * share);
    EXPECT_GT(share, 0.005); /* it is drawn */
    EXPECT_LT(share, 0.15);  /* and no mesh: the 1 km grid darkened 34% (10 km: 8.7%) */
    free(a.px);
    free(b.px);
    /* closer, the 1 km grid itself (Mt Hood's west flank, about 6 m a pixel) */
    REQUIRE_DATA_FILE(dem, "TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    const char* close[] = {
        "--size", "640x360", "--grid", "auto", "--camera", "598000,5016000,3200,10,-30", NULL};
    view(close, dem, json, sizeof json);
    EXPECT_EQ_DBL(1000, tp_test_json_number_after(json, NULL, "grid_m"));
    cleanup();
}

#define TESTS(X)                                                                                   \
    X(error_bound_is_finite_on_the_ground_of_a_warped_tile)                                        \
    X(error_bound_is_finite_on_the_ground_of_an_ascii_grid)                                        \
    X(default_hud_is_a_few_lines_and_details_come_on_request)                                      \
    X(engineering_figures_are_in_the_stats)                                                        \
    X(grid_at_the_default_view_follows_the_scale)
TP_TEST_MAIN(TESTS)
