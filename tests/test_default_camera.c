/*
 * test_default_camera.c - `terrapatch view` with no --camera frames the whole DEM (issue 29,
 * 4.3): for every DEM in data/, in a wide and a tall viewport, the eight corners of the DEM's
 * render grid (its extent at its lowest and highest drawn heights, as `terrapatch info --json`
 * reports them) project inside the picture of the camera the view says it used (its
 * --stats-json), by the core's projection.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"
#include "tp_test_child.h"

#include "tp_core.h"

#include <unistd.h>

static const char* tmp_dir(void)
{
    return tp_test_child_dir("default_camera");
}

/* The n numbers of the JSON array after "key": in json. */
static void json_array(const char* json, const char* key, double* v, int n)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\": [", key);
    const char* p = strstr(json, pat);
    if (!p)
        FAIL("no %s in %s", key, json);
    p += strlen(pat);
    for (int i = 0; i < n; ++i) {
        char* end;
        v[i] = strtod(p, &end);
        if (end == p)
            FAIL("%s: expected %d numbers", key, n);
        p = end + strspn(end, ", ");
    }
}

/* Runs the default view of dem in a w x h picture; asserts its eight corners are on screen. */
static void check_dem(const char* file, int w, int h)
{
    char dem[1024], stats[256], size[32], text[65536], err[8192];
    REQUIRE_DATA_FILE(dem, "TP_SAMPLE_DATA_DIR", file);
    /* the render grid's extent and heights */
    const char* info[] = {"--json", dem, NULL};
    if (tp_test_run_terrapatch_out("info", info, text, sizeof text, err, sizeof err) != 0)
        FAIL("info %s: %s", file, err);
    double ext[4];
    json_array(text, "extent_proj", ext, 4);
    const double lo = tp_test_json_number_after(text, NULL, "drawn_min_m");
    const double hi = tp_test_json_number_after(text, NULL, "drawn_max_m");
    /* the camera the view used */
    snprintf(stats, sizeof stats, "%s/stats.json", tmp_dir());
    snprintf(size, sizeof size, "%dx%d", w, h);
    remove(stats);
    const char* view[] = {"--headless", "--size", size, "--stats-json", stats, dem, NULL};
    if (tp_test_run_terrapatch("view", view, err, sizeof err) != 0)
        FAIL("view %s: %s", file, err);
    tp_test_read_text(stats, text, sizeof text);
    double c[5];
    json_array(text, "camera", c, 5);
    tp_camera cam;
    tp_camera_from_pose(c, c[3], c[4], tp_test_json_number_after(text, NULL, "fov_y_deg"), w, h,
                        &cam);
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int k = 0; k < 8; ++k) {
        const double p[3] = {k & 1 ? ext[2] : ext[0], k & 2 ? ext[3] : ext[1], k & 4 ? hi : lo};
        double px[2] = {NAN, NAN};
        const int front = tp_camera_project(&cam, p, px, NULL);
        x0 = fmin(x0, px[0]), x1 = fmax(x1, px[0]), y0 = fmin(y0, px[1]), y1 = fmax(y1, px[1]);
        if (!front || !(px[0] >= 0 && px[0] <= w && px[1] >= 0 && px[1] <= h))
            FAIL("%s in %dx%d: corner (E %.0f, N %.0f, %.0f m) is off the picture (pixel %.0f, "
                 "%.0f) of the default camera %.0f,%.0f,%.0f,%.0f,%.0f",
                 file, w, h, p[0], p[1], p[2], px[0], px[1], c[0], c[1], c[2], c[3], c[4]);
    }
    /* and not lost in the distance: the corners span half the picture's width or height */
    if (!(x1 - x0 >= 0.5 * w || y1 - y0 >= 0.5 * h))
        FAIL("%s in %dx%d: the DEM spans only %.0f x %.0f pixels", file, w, h, x1 - x0, y1 - y0);
}

static const char* const DEMS[] = {
    "N41E001.hgt",
    "N42E001.hgt",
    "N42E001.dt1",
    "craterlake-elev-16bit-30m.tif",
    "front_range_srtmgl3_144.asc",
    "front_range_srtmgl3_758.asc",
    "lf_elev_220_mt_hood_utm.tif",
    "mt_rainier_90m.tif",
    "storml_elev.tif",
    "storml_elev_orig.tif",
    "ps_height_1k.png",
};

TEST(every_dem_is_framed_whole_in_a_wide_picture)
{
    for (size_t i = 0; i < sizeof DEMS / sizeof DEMS[0]; ++i)
        check_dem(DEMS[i], 320, 180);
}

TEST(every_dem_is_framed_whole_in_a_tall_picture)
{
    for (size_t i = 0; i < sizeof DEMS / sizeof DEMS[0]; ++i)
        check_dem(DEMS[i], 180, 320);
}

#define TESTS(X)                                                                                   \
    X(every_dem_is_framed_whole_in_a_wide_picture)                                                 \
    X(every_dem_is_framed_whole_in_a_tall_picture)
TP_TEST_MAIN(TESTS)
