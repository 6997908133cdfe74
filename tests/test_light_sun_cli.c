/*
 * test_light_sun_cli.c - `terrapatch light DEM --sun AZ,EL -o OUT.tif` (app/commands/cmd_light.c)
 * run as a child on Mt Hood (lf_elev_220_mt_hood_utm.tif: a UTM grid, its own render grid,
 * integer heights the store keeps exactly), its GeoTIFF read with GDAL and compared with what
 * is worked out here, not by the code under test:
 *   - the grid azimuth it prints is the true one less the meridian convergence by GDAL/PROJ at
 *     the printed post, and the lit mask agrees with a ray cast per post written here
 *     (tp_test_sun_ray.h: quarter-post steps over the bilinear surface) at that azimuth;
 *   - --values illumination is GDAL's hillshade (GDALDEMProcessing "hillshade", -alg
 *     ZevenbergenThorne: the central differences tp_shadow_illumination uses, -az the grid
 *     azimuth, -alt EL) mapped from 1 + 254 cos(i) to 255 cos(i), where lit;
 *   - --date/--time and --sun with the azimuth and elevation the date's run prints write the
 *     same raster;
 *   - bad --sun values, and --sun with --date or --day: exit 2, one line, no file.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"

#include "tp_test_child.h"
#include "tp_test_gdal.h"
#include "tp_test_sun_ray.h"

#include <gdal.h>
#include <gdal_utils.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TESTS(X)                                                                                   \
    X(sun_lit_mask_agrees_with_a_ray_cast_on_mt_hood)                                              \
    X(sun_illumination_is_gdal_hillshade_where_lit)                                                \
    X(sun_from_the_date_gives_the_date_s_raster)                                                   \
    X(bad_sun_exits_2_with_one_line_and_no_file)

static const char* tmp_dir(void)
{
    return tp_test_child_dir("light_sun");
}

static void hood_path(char* path, size_t cap)
{
    if (!tp_test_data_path(path, cap, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif"))
        SKIP("lf_elev_220_mt_hood_utm.tif not found (set TP_SHARED_DATA_DIR)");
}

/* The numbers the command prints. */
typedef struct printed {
    double post_x, post_y, true_az, grid_az, elevation;
} printed;

static printed parse_stdout(const char* out)
{
    printed p;
    const char* place = strstr(out, "place      ");
    const char* sun = strstr(out, "sun        azimuth ");
    double lat, lon;
    if (!place || !sun ||
        sscanf(place, "place %lf %lf (post %lf, %lf", &lat, &lon, &p.post_x, &p.post_y) != 4 ||
        sscanf(sun, "sun azimuth %lf deg true, %lf deg grid; elevation %lf", &p.true_az, &p.grid_az,
               &p.elevation) != 3)
        FAIL("unexpected output: %s", out);
    return p;
}

/* Runs light with args (NULL-ended, after the DEM); asserts exit 0; returns what it printed. */
static printed run_ok(const char* dem, const char* const* args)
{
    const char* argv[24] = {dem};
    int n = 1;
    while (args[n - 1] && n < 23) {
        argv[n] = args[n - 1];
        n++;
    }
    argv[n] = NULL;
    static char so[8192], se[8192];
    const int rc = tp_test_run_terrapatch_out("light", argv, so, sizeof so, se, sizeof se);
    if (rc != 0)
        FAIL("light exited %d: %s", rc, se);
    return parse_stdout(so);
}

/* The byte raster written, checked against the DEM's size and geotransform. */
static uint8_t* read_bytes(const char* path, const tp_test_grid* dem)
{
    tp_test_grid g;
    tp_test_grid_read(path, &g);
    EXPECT_EQ_INT(GDT_Byte, g.type);
    ASSERT_EQ_INT(dem->w, g.w);
    ASSERT_EQ_INT(dem->h, g.h);
    for (int k = 0; k < 6; ++k)
        EXPECT_NEAR(dem->gt[k], g.gt[k], 1e-6);
    uint8_t* v = malloc((size_t)g.w * g.h);
    ASSERT_TRUE(v != NULL);
    for (size_t i = 0; i < (size_t)g.w * g.h; ++i)
        v[i] = (uint8_t)g.z[i];
    free(g.z);
    return v;
}

/* The convergence at the post the command printed, by GDAL/PROJ. */
static double convergence_at(const tp_test_grid* dem, const printed* p)
{
    const double e = dem->gt[0] + (p->post_x + 0.5) * dem->gt[1];
    const double n = dem->gt[3] + (p->post_y + 0.5) * dem->gt[5];
    return tp_test_grid_convergence(dem->wkt, e, n);
}

TEST(sun_lit_mask_agrees_with_a_ray_cast_on_mt_hood)
{
    char dem_path[1024], out[256];
    hood_path(dem_path, sizeof dem_path);
    tp_test_grid dem;
    tp_test_grid_read(dem_path, &dem);
    const double zmax = tp_test_grid_max(&dem), dx = fabs(dem.gt[1]), dy = fabs(dem.gt[5]);
    /* a low sun across the grid's diagonal, a south-western afternoon sun, a high one */
    const struct {
        const char* arg;
        double az, el, min_agree;
    } suns[] = {{"45,10", 45.0, 10.0, 0.99},
                {"200,20", 200.0, 20.0, 0.993},
                {"300.5,40", 300.5, 40.0, 0.996}};
    for (size_t s = 0; s < sizeof suns / sizeof suns[0]; ++s) {
        snprintf(out, sizeof out, "%s/sun%zu.tif", tmp_dir(), s);
        const char* args[] = {"--sun", suns[s].arg, "-o", out, NULL};
        const printed p = run_ok(dem_path, args);
        const double conv = convergence_at(&dem, &p);
        EXPECT_NEAR(suns[s].az, p.true_az, 1e-9);
        EXPECT_NEAR(suns[s].el, p.elevation, 1e-9);
        /* the command's convergence (from its georeference) is within 0.003 degree of PROJ's
         * here, as tests/test_light_cli.c measures for --date */
        EXPECT_NEAR(suns[s].az - conv, p.grid_az, 0.01);
        const double grid_az = suns[s].az - conv; /* ours, not the printed one */
        uint8_t* got = read_bytes(out, &dem);
        size_t cast = 0, agree = 0, shadow = 0, only_cli = 0, only_ray = 0, bad = 0;
        for (int r = 0; r < dem.h; r += 2)
            for (int c = 0; c < dem.w; c += 2) {
                const size_t i = (size_t)r * dem.w + c;
                bad += got[i] != 0 && got[i] != 255;
                if (dem.z[i] != dem.z[i]) {
                    bad += got[i] != 0;
                    continue;
                }
                const int ray = tp_test_sun_ray_lit(dem.z, dem.w, dem.h, dx, dy, grid_az,
                                                    suns[s].el, c, r, zmax);
                cast++;
                agree += ray == (got[i] == 255);
                shadow += !ray;
                only_cli += ray && got[i] == 0;
                only_ray += !ray && got[i] == 255;
            }
        const double f = (double)agree / cast;
        tp_test_note("--sun %s (grid azimuth %.3f, convergence %.4f by PROJ): %.1f%% in shadow "
                     "by the ray cast, agreement %.3f%% of %zu posts (%zu shadowed only by the "
                     "command, %zu only by the ray cast)",
                     suns[s].arg, grid_az, conv, 100.0 * shadow / cast, 100.0 * f, cast, only_cli,
                     only_ray);
        EXPECT_EQ_INT(0, (int)bad);
        EXPECT_GE(f, suns[s].min_agree);
        EXPECT_GT((double)shadow, 0.001 * cast); /* the test sees shadows to agree on */
        free(got);
    }
    free(dem.z);
}

/* GDAL's hillshade of the DEM file itself (the render grid: UTM, the same posts). */
static uint8_t* gdal_hillshade(const char* dem_path, double az, double alt, int w, int h)
{
    GDALAllRegister();
    GDALDatasetH src = GDALOpen(dem_path, GA_ReadOnly);
    ASSERT_TRUE(src != NULL);
    char a[32], e[32];
    snprintf(a, sizeof a, "%.9f", az);
    snprintf(e, sizeof e, "%.9f", alt);
    char* opts[] = {"-alg", "ZevenbergenThorne", "-az", a, "-alt", e, "-of", "MEM", NULL};
    GDALDEMProcessingOptions* o = GDALDEMProcessingOptionsNew(opts, NULL);
    ASSERT_TRUE(o != NULL);
    int usage = 0;
    GDALDatasetH hs = GDALDEMProcessing("", src, "hillshade", NULL, o, &usage);
    GDALDEMProcessingOptionsFree(o);
    ASSERT_TRUE(hs != NULL);
    ASSERT_EQ_INT(w, GDALGetRasterXSize(hs));
    uint8_t* v = malloc((size_t)w * h);
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(hs, 1), GF_Read, 0, 0, w, h, v, w, h, GDT_Byte, 0,
                             0) == CE_None);
    GDALClose(hs);
    GDALClose(src);
    return v;
}

TEST(sun_illumination_is_gdal_hillshade_where_lit)
{
    char dem_path[1024], ill[256], lit[256];
    hood_path(dem_path, sizeof dem_path);
    tp_test_grid dem;
    tp_test_grid_read(dem_path, &dem);
    snprintf(ill, sizeof ill, "%s/ill.tif", tmp_dir());
    snprintf(lit, sizeof lit, "%s/ill_lit.tif", tmp_dir());
    const char* a1[] = {"--sun", "160,35", "--values", "illumination", "-o", ill, NULL};
    const char* a2[] = {"--sun", "160,35", "-o", lit, NULL};
    const printed p = run_ok(dem_path, a1);
    run_ok(dem_path, a2);
    const double grid_az = 160.0 - convergence_at(&dem, &p);
    uint8_t* v = read_bytes(ill, &dem);
    uint8_t* m = read_bytes(lit, &dem);
    uint8_t* g = gdal_hillshade(dem_path, grid_az, 35.0, dem.w, dem.h);
    /* gdaldem writes round(1 + 254 cos i) (1 where cos i <= 0, 0 nodata at the edge and beside
     * voids); the command round(255 cos i): 255 (g - 1) / 254 from a rounded g is within
     * 255 / 254 / 2 of 255 cos i, so the two differ by at most 1 */
    size_t compared = 0, exact = 0, within1 = 0, away = 0, away_lit = 0, lit_dark = 0;
    int worst = 0;
    for (int r = 1; r + 1 < dem.h; ++r)
        for (int c = 1; c + 1 < dem.w; ++c) {
            const size_t i = (size_t)r * dem.w + c;
            if (g[i] == 0)
                continue;    /* gdaldem's nodata: a void in the 3x3 window */
            if (g[i] == 1) { /* facing away from the sun */
                away++;
                away_lit += v[i] > 1;
                continue;
            }
            if (m[i] != 255) {
                lit_dark += v[i] != 0; /* in shadow: 0 */
                continue;
            }
            const int want = (int)lround(255.0 * (g[i] - 1) / 254.0);
            const int d = abs((int)v[i] - want);
            compared++;
            exact += d == 0;
            within1 += d <= 1;
            worst = d > worst ? d : worst;
        }
    tp_test_note("sun 160/35 (grid %.3f): %zu lit posts compared with GDAL's hillshade "
                 "(ZevenbergenThorne): %.2f%% equal, %.3f%% within 1, worst %d; %zu facing away",
                 grid_az, compared, 100.0 * exact / compared, 100.0 * within1 / compared, worst,
                 away);
    EXPECT_GT((double)compared, 0.5 * dem.w * dem.h);
    EXPECT_EQ_INT((int)compared, (int)within1);
    EXPECT_EQ_INT(0, (int)away_lit);
    EXPECT_EQ_INT(0, (int)lit_dark);
    free(v);
    free(m);
    free(g);
    free(dem.z);
}

/* 2026-06-21 18:30 at UTC-7: the date's run prints the sun; --sun with those numbers (to the
 * 0.001 degree printed) writes the same raster. */
TEST(sun_from_the_date_gives_the_date_s_raster)
{
    char dem_path[1024], by_date[256], by_sun[256], sun[64];
    hood_path(dem_path, sizeof dem_path);
    tp_test_grid dem;
    tp_test_grid_read(dem_path, &dem);
    snprintf(by_date, sizeof by_date, "%s/by_date.tif", tmp_dir());
    snprintf(by_sun, sizeof by_sun, "%s/by_sun.tif", tmp_dir());
    const char* a1[] = {"--date", "2026-06-21", "--time", "18:30 -07:00", "-o", by_date, NULL};
    const printed d = run_ok(dem_path, a1);
    snprintf(sun, sizeof sun, "%.3f,%.3f", d.true_az, d.elevation);
    const char* a2[] = {"--sun", sun, "-o", by_sun, NULL};
    const printed s = run_ok(dem_path, a2);
    EXPECT_NEAR(d.grid_az, s.grid_az, 0.0011); /* the same convergence, at the same post */
    EXPECT_EQ_DBL(d.post_x, s.post_x);
    EXPECT_EQ_DBL(d.post_y, s.post_y);
    uint8_t* a = read_bytes(by_date, &dem);
    uint8_t* b = read_bytes(by_sun, &dem);
    size_t same = 0, shadow = 0;
    const size_t n = (size_t)dem.w * dem.h;
    for (size_t i = 0; i < n; ++i) {
        same += a[i] == b[i];
        shadow += a[i] == 0;
    }
    tp_test_note("--date 2026-06-21 --time '18:30 -07:00' and --sun %s: %zu of %zu posts equal "
                 "(%.1f%% in shadow)",
                 sun, same, n, 100.0 * shadow / n);
    EXPECT_GE((double)same, 0.9999 * n);
    EXPECT_GT((double)shadow, 0.02 * n);
    free(a);
    free(b);
    free(dem.z);
}

TEST(bad_sun_exits_2_with_one_line_and_no_file)
{
    char dem_path[1024], out[256], so[4096], se[4096];
    hood_path(dem_path, sizeof dem_path);
    snprintf(out, sizeof out, "%s/never.tif", tmp_dir());
    const struct {
        const char* a[8];
        const char* says;
    } cases[] = {
        {{"--sun", "10", "-o", out}, "--sun: expected AZ,EL"},
        {{"--sun", "abc,5", "-o", out}, "got 'abc,5'"},
        {{"--sun", "10,95", "-o", out}, "got '10,95'"},
        {{"--sun", "-5,30", "-o", out}, "got '-5,30'"},
        {{"--sun", "10,30", "--date", "2026-06-21", "-o", out}, "no --date, --time or --day"},
        {{"--sun", "10,30", "--time", "12:00", "-o", out}, "no --date, --time or --day"},
        {{"--sun", "10,30", "--day", "-o", out}, "no --date, --time or --day"},
        {{"--sun", "10,30"}, "missing -o OUT.tif"},
    };
    for (size_t k = 0; k < sizeof cases / sizeof cases[0]; ++k) {
        const char* argv[10] = {dem_path};
        for (int j = 0; j < 8 && cases[k].a[j]; ++j)
            argv[j + 1] = cases[k].a[j];
        EXPECT_EQ_INT(2, tp_test_run_terrapatch_out("light", argv, so, sizeof so, se, sizeof se));
        EXPECT_CONTAINS(se, cases[k].says);
        EXPECT_CONTAINS(se, "terrapatch light: ");
        const char* nl = strchr(se, '\n');
        EXPECT_TRUE(nl && nl[1] == '\0'); /* one line */
        EXPECT_EQ_STR("", so);
    }
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "never"));
}

TP_TEST_MAIN(TESTS)
