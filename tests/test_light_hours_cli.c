/*
 * test_light_hours_cli.c - `terrapatch light DEM --day --date D -o HOURS.tif`
 * (app/commands/light_day.c): the hours of direct sunlight per post over the day, a Float32
 * raster, run as a child and read with GDAL, against what is worked out here:
 *   - a made-up DEM written here (UTM 10N, 30 m posts: a plain, a hill in the north, a closed
 *     trench 300 m deep, a void): posts of the plain that no ground can shadow (due south of
 *     the hill, whose shadow never points south of east-south-east or west-south-west on a
 *     June day at 45 N) are lit from sunrise to sunset as the command prints them, to the
 *     map's step (1/255 of the day); the trench's floor gets hours fewer, and fewer still by
 *     its southern wall, which hides the noon sun; the void is nodata; and every post's hours equal
 * the sum over the day's N suns (the JSON lists them) of a ray cast written here
 * (tp_test_sun_ray.h), each sun's lit state weighted by half the time to the suns before and after
 * it, within the bound that sum has;
 *   - Mt Hood: the same sum on a sample of posts of real terrain, and a --radius/--at window
 *     that is the whole grid's hours at the same posts on the window's georeference.
 */
#define _GNU_SOURCE

#include "tp_test.h"

#include "tp_test_child.h"
#include "tp_test_gdal.h"
#include "tp_test_sun_ray.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define TESTS(X)                                                                                   \
    X(made_up_ground_plain_trench_void_and_the_sum_of_the_suns)                                    \
    X(mt_hood_hours_are_the_sum_of_the_suns_and_a_window_is_the_grid_s)                            \
    X(every_float_format_holds_the_same_hours_and_failures_write_nothing)

static const char* tmp_dir(void)
{
    return tp_test_child_dir("light_hours");
}

/* ---- the made-up ground ---- */

enum { W = 241, H = 241 };
#define PLAIN 500.0
#define HILL_COL 120
#define HILL_ROW 50
#define TRENCH_ROW0 150 /* floor rows 150 .. 159, columns 80 .. 160, 300 m below the plain */
#define TRENCH_ROW1 159
#define TRENCH_COL0 80
#define TRENCH_COL1 160
#define VOID_ROW 200
#define VOID_COL 0 /* on the west edge: the store fills interior voids */

static double made_up_height(int c, int r)
{
    if (r >= VOID_ROW && r < VOID_ROW + 3 && c >= VOID_COL && c < VOID_COL + 3)
        return NAN;
    if (r >= TRENCH_ROW0 && r <= TRENCH_ROW1 && c >= TRENCH_COL0 && c <= TRENCH_COL1)
        return PLAIN - 300.0;
    const double d2 =
        (double)(c - HILL_COL) * (c - HILL_COL) + (double)(r - HILL_ROW) * (r - HILL_ROW);
    return round(PLAIN + 900.0 * exp(-d2 / (2.0 * 25.0 * 25.0)));
}

/* Writes the made-up DEM as an Int16 GeoTIFF (nodata -32768) in UTM zone 10N. */
static void write_made_up(const char* path)
{
    GDALAllRegister();
    GDALDriverH drv = GDALGetDriverByName("GTiff");
    ASSERT_TRUE(drv != NULL);
    GDALDatasetH ds = GDALCreate(drv, path, W, H, 1, GDT_Int16, NULL);
    ASSERT_TRUE(ds != NULL);
    double gt[6] = {590000.0, 30.0, 0.0, 5030000.0, 0.0, -30.0};
    GDALSetGeoTransform(ds, gt);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    OSRImportFromEPSG(srs, 32610);
    char* wkt = NULL;
    OSRExportToWkt(srs, &wkt);
    GDALSetProjection(ds, wkt);
    CPLFree(wkt);
    OSRDestroySpatialReference(srs);
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    GDALSetRasterNoDataValue(b, -32768.0);
    static int16_t z[W * H];
    for (int r = 0; r < H; ++r)
        for (int c = 0; c < W; ++c) {
            const double v = made_up_height(c, r);
            z[r * W + c] = v == v ? (int16_t)v : (int16_t)-32768;
        }
    ASSERT_TRUE(GDALRasterIO(b, GF_Write, 0, 0, W, H, z, W, H, GDT_Int16, 0, 0) == CE_None);
    GDALClose(ds);
}

/* ---- what the command prints and lists ---- */

/* Unix seconds of "LABEL YYYY-MM-DD HH:MM:SS UTC" in the text; NaN if absent. */
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

#define MAX_SUNS 128
typedef struct day_suns {
    int n;
    double t[MAX_SUNS], az[MAX_SUNS], el[MAX_SUNS]; /* grid azimuth, apparent elevation */
} day_suns;

static double number_after(const char** at, const char* key)
{
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char* p = strstr(*at, pat);
    if (!p)
        FAIL("no %s in the JSON", key);
    *at = p + strlen(pat);
    return strtod(*at, NULL);
}

/* The suns the JSON lists. */
static void read_suns(const char* json_path, day_suns* s)
{
    static char text[1 << 16];
    tp_test_read_text(json_path, text, sizeof text);
    const int maps = (int)tp_test_json_number_after(text, NULL, "maps");
    ASSERT_TRUE(maps >= 2 && maps <= MAX_SUNS);
    const char* at = strstr(text, "\"suns\": [");
    ASSERT_TRUE(at != NULL);
    s->n = maps;
    for (int k = 0; k < maps; ++k) {
        s->t[k] = number_after(&at, "time_s");
        s->az[k] = number_after(&at, "azimuth_grid_deg");
        s->el[k] = number_after(&at, "elevation_deg");
    }
}

/* Runs light --day on dem with the extra args (NULL-ended): exit 0, its stdout in so. */
static void run_day(const char* dem, const char* const* extra, char* so, size_t cap)
{
    const char* argv[24] = {dem, "--day", "--date", "2026-06-21", "--quiet"};
    int n = 5;
    for (int k = 0; extra[k] && n < 23; ++k)
        argv[n++] = extra[k];
    argv[n] = NULL;
    static char se[8192];
    const int rc = tp_test_run_terrapatch_out("light", argv, so, cap, se, sizeof se);
    if (rc != 0)
        FAIL("light --day exited %d: %s", rc, se);
}

/* ---- the sum over the suns ---- */

typedef struct sum_result {
    size_t posts, within, simplified_guess;
    double mean_abs_h, worst_h, bound_mean_h;
} sum_result;

/* Compares the hours at every step-th post (the grid g, hours as written) with the sum over the
 * suns of the ray cast: sun k's lit state weighted by half the time to suns k - 1 and k + 1 (the
 * trapezoid). Where the lit state changes between two suns the command places the change inside
 * the interval, anywhere: half of the interval either way; each of at most four interval ends
 * is rounded to the nearest of 255 steps of the day: two steps in all. */
static sum_result sum_of_suns(const tp_test_grid* g, const float* hours, const day_suns* s,
                              int step)
{
    const double dx = fabs(g->gt[1]), dy = fabs(g->gt[5]), zmax = tp_test_grid_max(g);
    const double day_h = (s->t[s->n - 1] - s->t[0]) / 3600.0, step_h = day_h / 255.0;
    sum_result out = {0};
    for (int r = 0; r < g->h; r += step)
        for (int c = 0; c < g->w; c += step) {
            const size_t i = (size_t)r * g->w + c;
            if (g->z[i] != g->z[i])
                continue;
            double sum = 0.0, bound = 2.0 * step_h;
            int prev = 0;
            for (int k = 0; k < s->n; ++k) {
                const int lit =
                    tp_test_sun_ray_lit(g->z, g->w, g->h, dx, dy, s->az[k], s->el[k], c, r, zmax);
                if (k > 0) {
                    const double dt = (s->t[k] - s->t[k - 1]) / 3600.0;
                    sum += 0.5 * dt * (prev + lit);
                    bound += prev != lit ? 0.5 * dt : 0.0;
                }
                prev = lit;
            }
            const double d = fabs(hours[i] - sum);
            out.posts++;
            out.within += d <= bound + 1e-4;
            out.mean_abs_h += d;
            out.bound_mean_h += bound;
            out.worst_h = d > out.worst_h ? d : out.worst_h;
        }
    out.mean_abs_h /= out.posts;
    out.bound_mean_h /= out.posts;
    return out;
}

/* The Float32 hours written, checked against the grid's size and (moved by x0, y0) its
 * geotransform and CRS; nodata -9999 as NaN. */
static float* read_hours(const char* path, const tp_test_grid* dem, int x0, int y0, int w, int h)
{
    tp_test_grid g;
    tp_test_grid_read(path, &g);
    EXPECT_EQ_INT(GDT_Float32, g.type);
    EXPECT_TRUE(g.has_nodata);
    EXPECT_EQ_DBL(-9999.0, g.nodata);
    ASSERT_EQ_INT(w, g.w);
    ASSERT_EQ_INT(h, g.h);
    EXPECT_NEAR(dem->gt[0] + x0 * dem->gt[1], g.gt[0], 1e-6);
    EXPECT_NEAR(dem->gt[3] + y0 * dem->gt[5], g.gt[3], 1e-6);
    EXPECT_NEAR(dem->gt[1], g.gt[1], 1e-9);
    EXPECT_NEAR(dem->gt[5], g.gt[5], 1e-9);
    OGRSpatialReferenceH a = OSRNewSpatialReference(g.wkt);
    OGRSpatialReferenceH b = OSRNewSpatialReference(dem->wkt);
    EXPECT_TRUE(OSRIsSame(a, b));
    OSRDestroySpatialReference(a);
    OSRDestroySpatialReference(b);
    return g.z;
}

TEST(made_up_ground_plain_trench_void_and_the_sum_of_the_suns)
{
    char dem_path[256], out[256], json[256], so[16384];
    snprintf(dem_path, sizeof dem_path, "%s/made_up.tif", tmp_dir());
    snprintf(out, sizeof out, "%s/made_up_hours.tif", tmp_dir());
    snprintf(json, sizeof json, "%s/made_up.json", tmp_dir());
    write_made_up(dem_path);
    const char* extra[] = {"-o", out, "--json", json, NULL};
    run_day(dem_path, extra, so, sizeof so);
    const double rise = printed_time(so, "sunrise    "), set = printed_time(so, "sunset     ");
    ASSERT_TRUE(rise == rise && set == set);
    const double day_h = (set - rise) / 3600.0, step_h = day_h / 255.0;
    tp_test_grid dem;
    tp_test_grid_read(dem_path, &dem);
    float* hours = read_hours(out, &dem, 0, 0, W, H);
    day_suns suns;
    read_suns(json, &suns);
    EXPECT_EQ_INT(64, suns.n);
    EXPECT_NEAR(rise, suns.t[0], 1.0);
    EXPECT_NEAR(set, suns.t[suns.n - 1], 1.0);

    /* the plain due south of the hill: the sunrise-to-sunset day, to one step (each end within
     * half a step, the sun's centre on the horizon a few seconds after the -0.83 degree of
     * sunrise); the printed times are to the second */
    double worst_plain = 0.0;
    for (int c = HILL_COL - 20; c <= HILL_COL + 20; ++c)
        for (int r = 225; r <= 235; r += 5) {
            const double d = fabs(hours[(size_t)r * W + c] - day_h);
            worst_plain = d > worst_plain ? d : worst_plain;
        }
    /* the trench's floor, in the middle of its length: 8 posts from the southern wall, whose
     * 300 m hide the sun below 51 degrees from the south, and beside that wall (the sun at 68
     * degrees at most would need 84); both see the sun along the trench in the morning and
     * evening (from 14 degrees up over its ends, 41 posts away) */
    const double north_h = hours[(size_t)(TRENCH_ROW0 + 2) * W + HILL_COL];
    const double south_h = hours[(size_t)TRENCH_ROW1 * W + HILL_COL];
    tp_test_note("day %.4f h (sunrise to sunset printed), step %.2f min: the plain within %.4f h "
                 "of it; the trench's floor %.2f h, %.2f h by its southern wall; the hill's top "
                 "%.2f h",
                 day_h, 60.0 * step_h, worst_plain, north_h, south_h,
                 hours[(size_t)HILL_ROW * W + HILL_COL]);
    EXPECT_LE(worst_plain, step_h + 2.0 / 3600.0);
    EXPECT_LT(north_h, day_h - 2.0);
    EXPECT_LT(south_h, north_h - 2.0);
    EXPECT_GT(south_h, 0.0);
    EXPECT_NAN(hours[(size_t)(VOID_ROW + 1) * W + VOID_COL + 1]); /* the void: nodata */

    const sum_result s = sum_of_suns(&dem, hours, &suns, 2);
    tp_test_note("sum over the %d suns at %zu posts: %.3f%% within the bound (mean %.3f h), "
                 "mean |difference| %.4f h, worst %.3f h",
                 suns.n, s.posts, 100.0 * s.within / s.posts, s.bound_mean_h, s.mean_abs_h,
                 s.worst_h);
    /* where a change is placed inside an interval the difference is spread over its half
     * either way: on the whole well below the bound */
    EXPECT_GE((double)s.within, 0.99 * s.posts);
    EXPECT_LT(s.mean_abs_h, 0.5 * s.bound_mean_h);
    free(hours);
    free(dem.z);
}

TEST(mt_hood_hours_are_the_sum_of_the_suns_and_a_window_is_the_grid_s)
{
    char dem_path[1024], out[256], win[256], json[256], so[16384];
    if (!tp_test_data_path(dem_path, sizeof dem_path, "TP_SHARED_DATA_DIR",
                           "lf_elev_220_mt_hood_utm.tif"))
        SKIP("lf_elev_220_mt_hood_utm.tif not found (set TP_SHARED_DATA_DIR)");
    snprintf(out, sizeof out, "%s/hood_hours.tif", tmp_dir());
    snprintf(win, sizeof win, "%s/hood_window.tif", tmp_dir());
    snprintf(json, sizeof json, "%s/hood.json", tmp_dir());
    /* 32 suns; the 10 km margin reaches past every edge of the 1013 x 799 grid (one tile):
     * every post is shadowed by the whole grid, as the ray cast here */
    const char* extra[] = {"-o", out, "--json", json, "--maps", "32", NULL};
    run_day(dem_path, extra, so, sizeof so);
    tp_test_grid dem;
    tp_test_grid_read(dem_path, &dem);
    float* hours = read_hours(out, &dem, 0, 0, dem.w, dem.h);
    day_suns suns;
    read_suns(json, &suns);
    EXPECT_EQ_INT(32, suns.n);
    const double step_h = (suns.t[suns.n - 1] - suns.t[0]) / 3600.0 / 255.0;
    const sum_result s = sum_of_suns(&dem, hours, &suns, 9);
    tp_test_note("Mt Hood, sum over the %d suns at %zu posts: %.3f%% within the bound (mean "
                 "%.3f h), mean |difference| %.4f h, worst %.3f h",
                 suns.n, s.posts, 100.0 * s.within / s.posts, s.bound_mean_h, s.mean_abs_h,
                 s.worst_h);
    /* the sweep and the ray cast differ on 0.1 - 0.8% of the posts at each sun (docs/light.md),
     * a whole interval each: posts beyond the bound */
    EXPECT_GE((double)s.within, 0.98 * s.posts);
    EXPECT_LT(s.mean_abs_h, 0.5 * s.bound_mean_h);

    /* a window of 3 km around a post: the same posts, the sun computed there */
    const char* extra_w[] = {"-o",       win,    "--maps", "32", "--at", "45.37,-121.70",
                             "--radius", "3000", NULL};
    run_day(dem_path, extra_w, so, sizeof so);
    int x0, y0, ww, wh;
    const char* line = strstr(so, "window     ");
    ASSERT_TRUE(line && sscanf(line, "window %dx%d posts from (%d, %d)", &ww, &wh, &x0, &y0) == 4);
    EXPECT_EQ_INT(201, ww); /* 3000 m / 30 m either side of the post */
    EXPECT_EQ_INT(201, wh);
    float* part = read_hours(win, &dem, x0, y0, ww, wh);
    size_t same = 0, n = 0;
    for (int r = 0; r < wh; ++r)
        for (int c = 0; c < ww; ++c) {
            const float a = part[(size_t)r * ww + c], b = hours[(size_t)(y0 + r) * dem.w + x0 + c];
            n++;
            same += (a != a && b != b) || fabs(a - b) <= 2.0 * step_h;
        }
    tp_test_note("window %dx%d from (%d, %d): %.3f%% of its posts within two steps of the whole "
                 "grid's hours",
                 ww, wh, x0, y0, 100.0 * same / n);
    EXPECT_GE((double)same, 0.99 * n);
    free(part);
    free(hours);
    free(dem.z);
}

/* GeoPackage, Erdas Imagine and ASCII Grid hold the GeoTIFF's hours (the ASCII Grid's text to
 * 1e-6 h); PNG cannot hold them (exit 2), a folder that is not there (exit 1): nothing written. */
TEST(every_float_format_holds_the_same_hours_and_failures_write_nothing)
{
    char dem_path[256], tif[256], other[256], so[16384], se[4096];
    snprintf(dem_path, sizeof dem_path, "%s/formats.tif", tmp_dir());
    write_made_up(dem_path);
    tp_test_grid dem;
    tp_test_grid_read(dem_path, &dem);
    snprintf(tif, sizeof tif, "%s/formats_hours.tif", tmp_dir());
    const char* extra[] = {"-o", tif, "--maps", "8", NULL};
    run_day(dem_path, extra, so, sizeof so);
    float* want = read_hours(tif, &dem, 0, 0, W, H);
    const char* exts[] = {"gpkg", "img", "asc"};
    for (size_t e = 0; e < sizeof exts / sizeof exts[0]; ++e) {
        snprintf(other, sizeof other, "%s/formats_hours.%s", tmp_dir(), exts[e]);
        const char* x[] = {"-o", other, "--maps", "8", NULL};
        run_day(dem_path, x, so, sizeof so);
        float* got = read_hours(other, &dem, 0, 0, W, H);
        size_t differ = 0;
        for (size_t i = 0; i < (size_t)W * H; ++i)
            differ += !((got[i] != got[i] && want[i] != want[i]) || fabs(got[i] - want[i]) <= 1e-6);
        EXPECT_EQ_INT(0, (int)differ);
        free(got);
    }
    const char* png[] = {dem_path, "--day", "--date", "2026-06-21", "-o", "never.png", NULL};
    EXPECT_EQ_INT(2, tp_test_run_terrapatch_out("light", png, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(se, "PNG holds no Float32 values");
    const char* nodir[] = {
        dem_path, "--day", "--date", "2026-06-21", "-o", "/nonexistent/dir/never.tif", NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch_out("light", nodir, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(se, "/nonexistent/dir");
    EXPECT_TRUE(tp_test_nothing_named(".", "never"));
    free(want);
    free(dem.z);
}

TP_TEST_MAIN(TESTS)
