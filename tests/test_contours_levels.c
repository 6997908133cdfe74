/*
 * test_contours_levels.c - the levels and lines `terrapatch contours` chooses (issue 31:
 * --levels, --min-level, --max-level, --min-vertices; tp_contours_generate_ex), each against
 * GDAL's own `gdal_contour` (gdal-bin) run here on the DEM file itself: mt_hood is a UTM DEM
 * whose render grid is its own grid (30 m posts, integer heights the store keeps exactly, the
 * file's nodata voids NaN), so gdal_contour on the file is the same computation done
 * independently of terrapatch's ground, store and options. Both outputs are read back with
 * OGR's C API and compared level by level: the number of lines, their total length, and for
 * --min-vertices every line's vertex count.
 *   - --levels given out of order and with a repeat (and a level between posts' integers)
 *     against `gdal_contour -fl` with the same levels ascending, each once; the index contours
 *     every K-th of them;
 *   - --min-level/--max-level with --interval against `gdal_contour -i` with every level, the
 *     levels outside the range left out here; with --levels against `gdal_contour -fl` of the
 *     levels inside;
 *   - --min-vertices N: no line written has fewer than N points, and the lines are exactly
 *     gdal_contour's of N points or more (per level), the rest said to be left out;
 *   - tp_contours_generate_ex's options out of range: each its error, *out untouched; levels in
 *     any order equal to the same levels ascending, on a grid in memory.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_io.h"
#include "tp_test.h"
#include "tp_vector.h"

#include "tp_test_child.h"

#include <gdal.h>
#include <ogr_api.h>

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define TP_TMP_PREFIX "tp_contours_levels_"
#include "tp_test_tmp.h"

static const char* g_dir;

static const char* tmp_dir(void) /* one per test process, removed at exit */
{
    if (!g_dir)
        g_dir = make_tmp_dir();
    return g_dir;
}

#define MAX_LEVELS 200

/* What a contour file holds, level by level (ascending). */
typedef struct level_sum {
    double value;
    int lines, index;
    double length;    /* map units (metres here) */
    int fewest, most; /* points of its shortest and longest line */
} level_sum;

typedef struct file_sum {
    level_sum level[MAX_LEVELS];
    int count; /* levels */
    int lines;
    int* points; /* each line's point count, in file order */
} file_sum;

static level_sum* level_of(file_sum* s, double v)
{
    int i = 0;
    while (i < s->count && s->level[i].value < v)
        ++i;
    if (i < s->count && s->level[i].value == v)
        return &s->level[i];
    ASSERT_TRUE(s->count < MAX_LEVELS);
    memmove(&s->level[i + 1], &s->level[i], (size_t)(s->count - i) * sizeof s->level[0]);
    ++s->count;
    s->level[i] = (level_sum){v, 0, 0, 0.0, 1 << 30, 0};
    return &s->level[i];
}

/* Reads layer (NULL: the first) of the vector file path: the lines with at least min_points
 * points, level by level (field elev_field), and the index field's 1s when index_field. */
static file_sum read_contours(const char* path, const char* elev_field, const char* index_field,
                              int min_points)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_VECTOR, NULL, NULL, NULL);
    if (!ds)
        FAIL("OGR cannot open %s", path);
    OGRLayerH l = GDALDatasetGetLayer(ds, 0);
    ASSERT_TRUE(l != NULL);
    const int ie = OGR_FD_GetFieldIndex(OGR_L_GetLayerDefn(l), elev_field);
    const int ii = index_field ? OGR_FD_GetFieldIndex(OGR_L_GetLayerDefn(l), index_field) : -1;
    ASSERT_TRUE(ie >= 0);
    ASSERT_TRUE(!index_field || ii >= 0);
    file_sum s;
    memset(&s, 0, sizeof s);
    s.points = malloc(((size_t)OGR_L_GetFeatureCount(l, 1) + 1) * sizeof *s.points);
    OGR_L_ResetReading(l);
    OGRFeatureH f;
    while ((f = OGR_L_GetNextFeature(l))) {
        OGRGeometryH g = OGR_F_GetGeometryRef(f);
        EXPECT_EQ_INT(wkbLineString, wkbFlatten(OGR_G_GetGeometryType(g)));
        const int n = OGR_G_GetPointCount(g);
        if (n >= min_points) {
            level_sum* ls = level_of(&s, OGR_F_GetFieldAsDouble(f, ie));
            ls->lines++;
            ls->length += OGR_G_Length(g);
            ls->fewest = n < ls->fewest ? n : ls->fewest;
            ls->most = n > ls->most ? n : ls->most;
            if (ii >= 0)
                ls->index += OGR_F_GetFieldAsInteger(f, ii);
            s.points[s.lines++] = n;
        }
        OGR_F_Destroy(f);
    }
    GDALClose(ds);
    return s;
}

/* Ours and GDAL's: the same levels, each with as many lines and the same total length (1 mm
 * over all its lines: the same generator on the same heights gives the same vertices). */
static void expect_same_levels(const file_sum* ours, const file_sum* gdal)
{
    ASSERT_EQ_INT(gdal->count, ours->count);
    for (int i = 0; i < gdal->count; ++i) {
        const level_sum *a = &ours->level[i], *b = &gdal->level[i];
        EXPECT_EQ_DBL(b->value, a->value);
        EXPECT_EQ_INT(b->lines, a->lines);
        EXPECT_NEAR(b->length, a->length, 1e-3);
    }
    EXPECT_EQ_INT(gdal->lines, ours->lines);
}

/* Runs `gdal_contour args...` (NULL-terminated, found on PATH) with its output to /dev/null;
 * 0 when it succeeded. */
static int run_gdal_contour(const char* const* args)
{
    const char* argv[32];
    int n = 0;
    argv[n++] = "gdal_contour";
    for (int i = 0; args[i] && n < 31; ++i)
        argv[n++] = args[i];
    argv[n] = NULL;
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    pid_t pid;
    const int rc = posix_spawnp(&pid, "gdal_contour", &fa, NULL, (char* const*)argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc == ENOENT)
        FAIL("gdal_contour not found: the GDAL command-line tools (gdal-bin) are missing; "
             "`make deps` installs them");
    ASSERT_EQ_INT(0, rc);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            FAIL("waitpid: %s", strerror(errno));
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/* `gdal_contour -q -a elev EXTRA... DEM OUT` into tmp_dir()/name, read back (lines of at least
 * min_points points). */
static file_sum gdal_contour(const char* dem, const char* const* extra, const char* name,
                             int min_points)
{
    char out[512];
    snprintf(out, sizeof out, "%s/%s", tmp_dir(), name);
    remove(out);
    const char* args[24] = {"-q", "-a", "elev"};
    int n = 3;
    for (int i = 0; extra[i]; ++i)
        args[n++] = extra[i];
    args[n++] = dem;
    args[n++] = out;
    args[n] = NULL;
    ASSERT_EQ_INT(0, run_gdal_contour(args));
    return read_contours(out, "elev", NULL, min_points);
}

/* `terrapatch contours DEM ARGS... -o tmp_dir()/name` (exit 0), stdout in out; read back. */
static file_sum terrapatch_contours(const char* dem, const char* const* extra, const char* name,
                                    char* out, size_t out_cap)
{
    char path[512], errs[8192];
    snprintf(path, sizeof path, "%s/%s", tmp_dir(), name);
    const char* args[24] = {dem};
    int n = 1;
    for (int i = 0; extra[i]; ++i)
        args[n++] = extra[i];
    args[n++] = "-o";
    args[n++] = path;
    args[n] = NULL;
    const int rc = tp_test_run_terrapatch_out("contours", args, out, out_cap, errs, sizeof errs);
    if (rc != 0)
        FAIL("terrapatch contours exit %d: %s", rc, errs);
    return read_contours(path, "elevation_m", "index", 0);
}

static void print_levels(const char* what, const file_sum* s)
{
    for (int i = 0; i < s->count; ++i)
        tp_test_note("%s: %g m: %d lines (%d index), %.1f m, %d..%d points", what,
                     s->level[i].value, s->level[i].lines, s->level[i].index, s->level[i].length,
                     s->level[i].fewest, s->level[i].most);
}

/* ---- `terrapatch contours` against gdal_contour ---- */

TEST(levels_match_gdal_contour_fixed_levels)
{
    char dem[1024], out[4096];
    REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    /* out of order, 1500 twice, 2750.5 between the posts' integer heights; index every 2nd:
     * 1000 and 2000 (the 1st and 3rd of 1000, 1500, 2000, 2750.5) */
    const char* ours_args[] = {"--levels", "2000, 1000,1500,2750.5,1500", "--index-every", "2",
                               NULL};
    file_sum ours = terrapatch_contours(dem, ours_args, "levels.gpkg", out, sizeof out);
    EXPECT_CONTAINS(out, "at the 4 levels given");
    const char* gdal_args[] = {"-fl", "1000", "1500", "2000", "2750.5", NULL};
    file_sum ref = gdal_contour(dem, gdal_args, "levels_gdal.gpkg", 0);
    print_levels("--levels", &ours);
    ASSERT_EQ_INT(4, ref.count);
    for (int i = 0; i < 4; ++i)
        EXPECT_GT((double)ref.level[i].lines, 0.0); /* every level drawn somewhere */
    expect_same_levels(&ours, &ref);
    for (int i = 0; i < ours.count; ++i) {
        const int index = ours.level[i].value == 1000.0 || ours.level[i].value == 2000.0;
        EXPECT_EQ_INT(index ? ours.level[i].lines : 0, ours.level[i].index);
    }
    /* why the levels are sorted here: gdal_contour -fl given them out of order draws only some
     * of them (GDAL 3.6 walks them as if ascending), and a level given twice twice */
    const char* unsorted[] = {"-fl", "2000", "1000", "1500", "2750.5", NULL};
    file_sum raw = gdal_contour(dem, unsorted, "levels_unsorted.gpkg", 0);
    tp_test_note("gdal_contour -fl 2000 1000 1500 2750.5: %d levels, %d lines (sorted: %d, %d)",
                 raw.count, raw.lines, ref.count, ref.lines);
    free(ours.points);
    free(ref.points);
    free(raw.points);
}

TEST(min_max_level_match_gdal_contour)
{
    char dem[1024], out[4096];
    REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    /* --interval 50 within 1000 .. 2000 m against gdal_contour -i 50, every level, the levels
     * outside left out here */
    const char* ours_args[] = {"--interval",  "50",   "--min-level", "1000",
                               "--max-level", "2000", NULL};
    file_sum ours = terrapatch_contours(dem, ours_args, "range.gpkg", out, sizeof out);
    EXPECT_CONTAINS(out, "every 50 m from 1000 to 2000 m");
    const char* all_args[] = {"-i", "50", NULL};
    file_sum all = gdal_contour(dem, all_args, "all_gdal.gpkg", 0);
    file_sum ref;
    memset(&ref, 0, sizeof ref);
    for (int i = 0; i < all.count; ++i)
        if (all.level[i].value >= 1000.0 && all.level[i].value <= 2000.0) {
            ref.level[ref.count++] = all.level[i];
            ref.lines += all.level[i].lines;
        }
    ASSERT_EQ_INT(21, ref.count); /* 1000, 1050, ..., 2000 */
    EXPECT_GT((double)all.count, (double)ref.count);
    expect_same_levels(&ours, &ref);
    /* index contours as without the range: the multiples of 250 m */
    for (int i = 0; i < ours.count; ++i)
        EXPECT_EQ_INT(fmod(ours.level[i].value, 250.0) == 0.0 ? ours.level[i].lines : 0,
                      ours.level[i].index);
    tp_test_note("--interval 50 --min-level 1000 --max-level 2000: %d levels, %d lines of "
                 "gdal_contour's %d",
                 ours.count, ours.lines, all.lines);

    /* only a lower bound, with --base: 25 + k * 100 from 3000 m up */
    const char* up_args[] = {"--interval", "100", "--base", "25", "--min-level", "3000", NULL};
    file_sum up = terrapatch_contours(dem, up_args, "up.gpkg", out, sizeof out);
    const char* off_args[] = {"-i", "100", "-off", "25", NULL};
    file_sum off = gdal_contour(dem, off_args, "off_gdal.gpkg", 0);
    file_sum want;
    memset(&want, 0, sizeof want);
    for (int i = 0; i < off.count; ++i)
        if (off.level[i].value >= 3000.0) {
            want.level[want.count++] = off.level[i];
            want.lines += off.level[i].lines;
        }
    ASSERT_GT((double)want.count, 0.0);
    expect_same_levels(&up, &want);

    /* --levels within a range: those inside, as gdal_contour -fl of those alone */
    const char* lv_args[] = {
        "--levels", "800,1000,1500,2000,2500", "--min-level", "900", "--max-level", "2000", NULL};
    file_sum lv = terrapatch_contours(dem, lv_args, "range_levels.gpkg", out, sizeof out);
    EXPECT_CONTAINS(out, "at 3 of the 5 levels given (those from 900 to 2000 m)");
    const char* fl_args[] = {"-fl", "1000", "1500", "2000", NULL};
    file_sum fl = gdal_contour(dem, fl_args, "range_levels_gdal.gpkg", 0);
    expect_same_levels(&lv, &fl);
    free(ours.points);
    free(all.points);
    free(up.points);
    free(off.points);
    free(lv.points);
    free(fl.points);
}

TEST(min_vertices_keeps_gdal_contours_lines_of_n_points_or_more)
{
    char dem[1024], out[4096];
    REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    const int n = 12;
    const char* ours_args[] = {"--interval", "50", "--min-vertices", "12", NULL};
    file_sum ours = terrapatch_contours(dem, ours_args, "short.gpkg", out, sizeof out);
    const char* gdal_args[] = {"-i", "50", NULL};
    file_sum all = gdal_contour(dem, gdal_args, "short_all.gpkg", 0);
    file_sum ref = gdal_contour(dem, gdal_args, "short_gdal.gpkg", n);
    /* no line written is shorter */
    int shorter = 0;
    for (int i = 0; i < ours.lines; ++i)
        shorter += ours.points[i] < n;
    EXPECT_EQ_INT(0, shorter);
    /* and they are gdal_contour's lines of 12 points or more, level by level */
    expect_same_levels(&ours, &ref);
    const int left_out = all.lines - ref.lines;
    EXPECT_GT((double)left_out, 0.0); /* the option does something on this ground */
    EXPECT_GT((double)ref.lines, 0.0);
    char said[128];
    snprintf(said, sizeof said, "; %d lines of fewer than 12 vertices left out", left_out);
    EXPECT_CONTAINS(out, said);
    tp_test_note("--min-vertices 12: %d of gdal_contour's %d lines kept, %d left out", ours.lines,
                 all.lines, left_out);

    /* a line of exactly N points stays, one of N - 1 goes: N the fewest points of a line */
    int fewest = 1 << 30;
    for (int i = 0; i < all.lines; ++i)
        fewest = all.points[i] < fewest ? all.points[i] : fewest;
    char at[16];
    snprintf(at, sizeof at, "%d", fewest);
    const char* edge_args[] = {"--interval", "50", "--min-vertices", at, NULL};
    file_sum edge = terrapatch_contours(dem, edge_args, "edge.gpkg", out, sizeof out);
    EXPECT_EQ_INT(all.lines, edge.lines);
    snprintf(at, sizeof at, "%d", fewest + 1);
    file_sum above = terrapatch_contours(dem, edge_args, "above.gpkg", out, sizeof out);
    EXPECT_LT((double)above.lines, (double)all.lines);
    free(ours.points);
    free(all.points);
    free(ref.points);
    free(edge.points);
    free(above.points);
}

/* ---- tp_contours_generate_ex ---- */

/* A 60 x 40 grid rising 3.7 m a post east and 1.3 m a post south, with a bump. */
static void slope_grid(float* z, int w, int h)
{
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[(size_t)y * w + x] =
                (float)(100.0 + 3.7 * x + 1.3 * y +
                        40.0 * exp(-((x - 30) * (x - 30) + (y - 20) * (y - 20)) / 60.0));
}

TEST(levels_in_any_order_draw_as_sorted)
{
    enum { W = 60, H = 40 };
    static float z[W * H];
    slope_grid(z, W, H);
    const double gt[6] = {500000, 10, 0, 4700000, 0, -10};
    tp_contours_options o = tp_contours_options_default();
    o.interval_m = 0.0;
    const double sorted[] = {150.0, 200.0, 250.5, 300.0};
    const double mixed[] = {300.0, 150.0, 250.5, 200.0, 150.0, 300.0};
    tp_error err = {{0}};
    tp_features *a = NULL, *b = NULL;
    size_t dropped = 99;
    o.levels = sorted, o.level_count = 4;
    ASSERT_OK(tp_contours_generate_ex(z, W * H, W, H, gt, &o, &a, &dropped, &err));
    EXPECT_EQ_INT(0, (long long)dropped);
    o.levels = mixed, o.level_count = 6;
    ASSERT_OK(tp_contours_generate_ex(z, W * H, W, H, gt, &o, &b, NULL, &err));
    ASSERT_GE((double)a->count, 4.0); /* each level at least once across the slope */
    ASSERT_EQ_INT((long long)a->count, (long long)b->count);
    ASSERT_EQ_INT((long long)a->vertex_count, (long long)b->vertex_count);
    for (size_t i = 0; i < a->count; ++i) {
        EXPECT_EQ_DBL(a->items[i].value, b->items[i].value);
        EXPECT_EQ_INT(a->items[i].index, b->items[i].index);
        /* index every 5th of the four: the lowest only */
        EXPECT_EQ_INT(a->items[i].value == 150.0, a->items[i].index);
    }
    EXPECT_TRUE(memcmp(a->xy, b->xy, a->vertex_count * 2 * sizeof(double)) == 0);
    /* each level once: 150 given twice draws its lines once */
    size_t at150 = 0;
    for (size_t i = 0; i < b->count; ++i)
        at150 += b->items[i].value == 150.0;
    EXPECT_EQ_INT(1, (long long)at150);
    tp_features_destroy(a);
    tp_features_destroy(b);
}

TEST(options_out_of_range_leave_out_untouched)
{
    float z[4] = {0, 10, 20, 30};
    const double gt[6] = {500000, 30, 0, 4700000, 0, -30};
    tp_features* const sentinel = (tp_features*)&z[0];
    tp_features* f = sentinel;
    size_t dropped = 7;
    tp_error err = {{0}};
    const double levels[] = {5.0, NAN};
    tp_contours_options o = tp_contours_options_default();
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate_ex(z, 4, 2, 2, gt, NULL, &f, &dropped, &err));
    o.levels = levels, o.level_count = 1; /* an interval and levels */
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate_ex(z, 4, 2, 2, gt, &o, &f, &dropped, &err));
    EXPECT_CONTAINS(err.message, "an interval or levels");
    o.interval_m = 0.0, o.level_count = 0; /* neither */
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate_ex(z, 4, 2, 2, gt, &o, &f, &dropped, &err));
    EXPECT_CONTAINS(err.message, "interval > 0");
    o.level_count = 2; /* a NaN level */
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate_ex(z, 4, 2, 2, gt, &o, &f, &dropped, &err));
    EXPECT_CONTAINS(err.message, "level 2 is not finite");
    o.level_count = 1, o.min_m = 20.0, o.max_m = 10.0;
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate_ex(z, 4, 2, 2, gt, &o, &f, &dropped, &err));
    EXPECT_CONTAINS(err.message, "min <= max");
    o.min_m = NAN, o.max_m = HUGE_VAL;
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate_ex(z, 4, 2, 2, gt, &o, &f, &dropped, &err));
    o.min_m = -HUGE_VAL, o.index_every = -1;
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate_ex(z, 4, 2, 2, gt, &o, &f, &dropped, &err));
    o.index_every = 5, o.level_count = TP_CONTOURS_MAX_LEVELS + 1;
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate_ex(z, 4, 2, 2, gt, &o, &f, &dropped, &err));
    EXPECT_TRUE(f == sentinel);
    EXPECT_EQ_INT(7, (long long)dropped);
    /* a range that keeps no level, on ground that has lines: an empty set, TP_OK */
    o.level_count = 1, o.min_m = 6.0;
    ASSERT_OK(tp_contours_generate_ex(z, 4, 2, 2, gt, &o, &f, &dropped, &err));
    EXPECT_EQ_INT(0, (long long)f->count);
    EXPECT_EQ_INT(0, (long long)dropped);
    tp_features_destroy(f);
}

/* The vertex bound counts only the levels drawn: 1 mm levels over the 1000 x 1000 plane that
 * tests/test_contours.c refuses at 21,000 levels are drawn when --min-level/--max-level keep 3
 * of them (3 crossings of each of 999 x 1000 edges). */
TEST(vertex_bound_counts_only_the_levels_drawn)
{
    const int w = 1000, h = 1000;
    float* z = malloc((size_t)w * h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x)
            z[(size_t)y * w + x] = 0.021f * x + 0.0005f;
    const double gt[6] = {500000, 1, 0, 4700000, 0, -1};
    tp_contours_options o = tp_contours_options_default();
    o.interval_m = 0.001;
    tp_features* f = NULL;
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG,
                  tp_contours_generate_ex(z, (size_t)w * h, w, h, gt, &o, &f, NULL, &err));
    o.min_m = 10.0, o.max_m = 10.0025;
    ASSERT_OK(tp_contours_generate_ex(z, (size_t)w * h, w, h, gt, &o, &f, NULL, &err));
    /* 10.000, 10.001, 10.002: each one vertical line across the plane */
    EXPECT_EQ_INT(3, (long long)f->count);
    for (size_t i = 0; i < f->count; ++i)
        EXPECT_NEAR(10.0 + 0.001 * (double)i, f->items[i].value, 1e-9);
    tp_features_destroy(f);
    free(z);
}

#define TESTS(X)                                                                                   \
    X(levels_match_gdal_contour_fixed_levels)                                                      \
    X(min_max_level_match_gdal_contour)                                                            \
    X(min_vertices_keeps_gdal_contours_lines_of_n_points_or_more)                                  \
    X(levels_in_any_order_draw_as_sorted)                                                          \
    X(options_out_of_range_leave_out_untouched)                                                    \
    X(vertex_bound_counts_only_the_levels_drawn)
TP_TEST_MAIN(TESTS)
