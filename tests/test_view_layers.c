/*
 * test_view_layers.c - the viewer's planning layers (app/view/layers.c, drape.c, overlay.c),
 * rendered headless: `terrapatch view --headless` runs as a child on N42E001 (Andorra) with the
 * vector files of data/vectors, and the test reads the screenshots back (tp_image_read_rgba):
 *
 *   - a GPX track (--overlay) is drawn in its colour (magenta) where the camera sees it;
 *   - the same track seen from a valley floor with a mountain in between is not drawn at all,
 *     although its vertices project inside the picture (computed here with the core's camera
 *     and GeographicLib's UTM, not by the viewer): what is draped is hidden behind the terrain;
 *   - contours (--contours M) add brown lines, more for a smaller interval;
 *   - bad input: a file OGR cannot open, an empty GPX, a heightmap image without georeference:
 *     exit 1, one line naming the file, no screenshot written.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"
#include "tp_geo.h"
#include "tp_io.h"

#include "tp_test_child.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define DEG (3.14159265358979323846 / 180.0)

/* The track's vertices as typed in data/vectors/coma_pedrosa.gpx (lat, lon, its <ele>). */
static const double TRACK[][3] = {
    {42.57220, 1.48400, 1560}, {42.57650, 1.47600, 1720}, {42.58100, 1.46800, 1950},
    {42.58400, 1.46000, 2150}, {42.58700, 1.45400, 2280}, {42.59000, 1.44900, 2600},
    {42.59306, 1.44417, 2942}};
#define TRACK_COUNT (sizeof TRACK / sizeof TRACK[0])

static void shot_path(char* buf, size_t cap, const char* name)
{
    snprintf(buf, cap, "/tmp/tp_view_layers_%ld_%s", (long)getpid(), name);
}

/* Renders N42E001 from --camera-geo cam (W x H) with extra options; returns the exit status,
 * stderr in err. */
static int render(const char* cam, const char* const* extra, const char* png, char* err,
                  size_t cap)
{
    char dem[1024];
    REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    const char* args[32];
    int n = 0;
    args[n++] = "--headless";
    args[n++] = "--size";
    args[n++] = "640x360";
    args[n++] = "--camera-geo";
    args[n++] = cam;
    for (int i = 0; extra && extra[i]; i++)
        args[n++] = extra[i];
    args[n++] = "--screenshot";
    args[n++] = png;
    args[n++] = dem;
    args[n] = NULL;
    return tp_test_run_terrapatch("view", args, err, cap);
}

/* Pixels of png within tol of rgb. */
static size_t count_colour(const char* png, const unsigned char rgb[3], int tol)
{
    int w = 0, h = 0;
    uint8_t* px = NULL;
    tp_error e;
    memset(&e, 0, sizeof e);
    if (tp_image_read_rgba(png, &w, &h, &px, &e) != TP_OK)
        FAIL("reading %s: %s", png, e.message);
    size_t n = 0;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        int ok = 1;
        for (int c = 0; c < 3; c++)
            ok &= abs(px[4 * i + c] - rgb[c]) <= tol;
        n += ok;
    }
    free(px);
    return n;
}

static const unsigned char MAGENTA[3] = {255, 40, 220}; /* the first overlay's colour */

TEST(overlay_track_is_drawn_where_seen)
{
    char gpx[1024], png[1024], err[4096];
    REQUIRE_DATA_FILE(gpx, "TP_SAMPLE_DATA_DIR", "vectors/coma_pedrosa.gpx");
    shot_path(png, sizeof png, "seen.png");
    const char* extra[] = {"--overlay", gpx, NULL};
    /* from 5.5 km up over the south, looking north-north-east at Coma Pedrosa */
    ASSERT_EQ_INT(0, render("42.48,1.47,5500,20,-32", extra, png, err, sizeof err));
    size_t seen = count_colour(png, MAGENTA, 12);
    tp_test_note("GPX track from above: %zu magenta pixels of 640x360", seen);
    EXPECT_GT((double)seen, 100.0);
    remove(png);
    /* without the overlay, nothing of that colour */
    ASSERT_EQ_INT(0, render("42.48,1.47,5500,20,-32", NULL, png, err, sizeof err));
    EXPECT_EQ_INT(0, (int)count_colour(png, MAGENTA, 12));
    remove(png);
}

TEST(overlay_track_behind_a_mountain_is_hidden)
{
    /* 12 m above the valley floor at 42.52 N 1.53 E (ground 1318 m), looking at the track
     * 8 km to the north-west over the ridges between */
    const double lat = 42.52, lon = 1.53, h = 1330, yaw = 300, pitch = 3;
    char gpx[1024], png[1024], err[4096], cam_text[128];
    REQUIRE_DATA_FILE(gpx, "TP_SAMPLE_DATA_DIR", "vectors/coma_pedrosa.gpx");
    /* the track lies in the picture: the camera built here from the same pose (the render grid
     * is UTM 31N, yaw from its north) projects its vertices inside 640x360 */
    int zone, northp;
    double e, n;
    tp_error er;
    memset(&er, 0, sizeof er);
    ASSERT_OK(tp_geo_to_utmups(lat, lon, &zone, &northp, &e, &n, &er));
    ASSERT_EQ_INT(31, zone);
    double eye[3] = {e, n, h};
    tp_camera cam;
    tp_camera_from_pose(eye, yaw, pitch, 60, 640, 360, &cam);
    int inside = 0;
    for (size_t i = 0; i < TRACK_COUNT; i++) {
        int z, np;
        double p[3], px[2];
        ASSERT_OK(tp_geo_to_utmups(TRACK[i][0], TRACK[i][1], &z, &np, &p[0], &p[1], &er));
        p[2] = TRACK[i][2];
        inside += tp_camera_project(&cam, p, px, NULL) && px[0] >= 0 && px[0] < 640 &&
                  px[1] >= 0 && px[1] < 360;
    }
    tp_test_note("track vertices inside the picture (without terrain): %d of %zu", inside,
                 TRACK_COUNT);
    ASSERT_GE_INT(inside, 4);
    snprintf(cam_text, sizeof cam_text, "%.2f,%.2f,%.0f,%.0f,%.0f", lat, lon, h, yaw, pitch);
    shot_path(png, sizeof png, "hidden.png");
    const char* extra[] = {"--overlay", gpx, NULL};
    ASSERT_EQ_INT(0, render(cam_text, extra, png, err, sizeof err));
    size_t shown = count_colour(png, MAGENTA, 12);
    tp_test_note("GPX track behind the mountain: %zu magenta pixels", shown);
    EXPECT_EQ_INT(0, (int)shown);
    remove(png);
}

TEST(contours_add_brown_lines_more_for_a_smaller_interval)
{
    const unsigned char brown[3] = {140, 80, 30};
    const char* cam = "42.555,1.50,3300,300,-30";
    char png[1024], err[4096];
    shot_path(png, sizeof png, "contours.png");
    ASSERT_EQ_INT(0, render(cam, NULL, png, err, sizeof err));
    size_t none = count_colour(png, brown, 6);
    remove(png);
    const char* c100[] = {"--contours", "100", NULL};
    ASSERT_EQ_INT(0, render(cam, c100, png, err, sizeof err));
    size_t coarse = count_colour(png, brown, 6);
    remove(png);
    const char* c25[] = {"--contours", "25", NULL};
    ASSERT_EQ_INT(0, render(cam, c25, png, err, sizeof err));
    size_t fine = count_colour(png, brown, 6);
    remove(png);
    tp_test_note("contour-brown pixels: none %zu, every 100 m %zu, every 25 m %zu", none, coarse,
                 fine);
    EXPECT_GT((double)coarse, (double)none + 2000);
    EXPECT_GT((double)fine, 1.5 * (double)coarse);
}

/* An --overlay that cannot be drawn: exit 1, a line naming the file, no screenshot. */
static void expect_refused(const char* overlay, const char* dem_file, const char* want)
{
    char png[1024], err[4096], dem[1024];
    shot_path(png, sizeof png, "refused.png");
    remove(png);
    REQUIRE_DATA_FILE(dem, "TP_SAMPLE_DATA_DIR", dem_file);
    const char* args[] = {"--headless", "--size", "320x180", "--overlay", overlay,
                          "--screenshot", png, dem, NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch("view", args, err, sizeof err));
    tp_test_note("%s", err);
    EXPECT_TRUE(strstr(err, want) != NULL);
    EXPECT_TRUE(strstr(err, "--overlay") != NULL);
    EXPECT_TRUE(access(png, F_OK) != 0);
}

TEST(overlay_ogr_cannot_open_exits_1)
{
    char path[1024];
    shot_path(path, sizeof path, "garbage.gpx");
    FILE* f = fopen(path, "w");
    ASSERT_TRUE(f != NULL);
    fputs("this is not a GPX file\n", f);
    fclose(f);
    expect_refused(path, "lf_elev_220_mt_hood_utm.tif", path);
    remove(path);
}

TEST(overlay_empty_gpx_exits_1)
{
    char gpx[1024];
    REQUIRE_DATA_FILE(gpx, "TP_SAMPLE_DATA_DIR", "vectors/empty.gpx");
    expect_refused(gpx, "lf_elev_220_mt_hood_utm.tif", "empty.gpx");
}

TEST(overlay_on_a_heightmap_image_exits_1)
{
    char gpx[1024];
    REQUIRE_DATA_FILE(gpx, "TP_SAMPLE_DATA_DIR", "vectors/coma_pedrosa.gpx");
    char png_dem[1024];
    REQUIRE_DATA_FILE(png_dem, "TP_SHARED_DATA_DIR", "ps_height_1k.png");
    char png[1024], err[4096];
    shot_path(png, sizeof png, "refused_image.png");
    const char* args[] = {"--headless", "--size", "320x180", "--overlay", gpx,
                          "--screenshot", png, png_dem, NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch("view", args, err, sizeof err));
    tp_test_note("%s", err);
    EXPECT_TRUE(strstr(err, "ps_height_1k.png") != NULL);
    EXPECT_TRUE(access(png, F_OK) != 0);
}

#define TP_TEST_LIST(X)                                                                            \
    X(overlay_track_is_drawn_where_seen)                                                           \
    X(overlay_track_behind_a_mountain_is_hidden)                                                   \
    X(contours_add_brown_lines_more_for_a_smaller_interval)                                        \
    X(overlay_ogr_cannot_open_exits_1)                                                             \
    X(overlay_empty_gpx_exits_1)                                                                   \
    X(overlay_on_a_heightmap_image_exits_1)
TP_TEST_MAIN(TP_TEST_LIST)
