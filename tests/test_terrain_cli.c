/*
 * test_terrain_cli.c - `terrapatch terrain` (app/commands/cmd_terrain.c) run as a child, its
 * rasters read back with GDAL's C API and compared with an independent computation:
 *   - Mt Hood (NAD83 / UTM 10N, Int16: its render grid is the file's own grid and the store
 *     keeps its heights exactly): slope, aspect and hillshade with each option equal
 *     GDALDEMProcessing (`gdaldem`) run here on the file itself, at every post where gdaldem
 *     has a value (but beside a lone post amid voids, which the ground has not: compare), and
 *     are nodata where it has none; the file has the DEM's size, geotransform and
 *     CRS, gdaldem's type and nodata value; the float formats (.img, .asc, .gpkg) and the
 *     hillshade's .png hold the same values; a window --around a position is that part of the
 *     grid, with gdaldem's values inside it;
 *   - N42E001 (geographic, warped to UTM 31N): the rasters lie on the render grid
 *     (tp_render_grid_build), agree with gdaldem on that grid within what the store's height
 *     step moves, and their slope and aspect at posts equal `terrapatch point --json`'s (Horn)
 *     at the same positions;
 *   - bad input (an unknown --what, an option of another product, an extension naming no
 *     raster format or one that holds no Float32, a folder that does not exist): exit 2 or 1,
 *     no file, an older file untouched.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_io.h"
#include "tp_test.h"

#include "tp_test_child.h"

#include <gdal.h>
#include <gdal_utils.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

#define TESTS(X)                                                                                   \
    X(mt_hood_products_equal_gdaldem_on_the_file)                                                  \
    X(mt_hood_formats_hold_the_same_values)                                                        \
    X(mt_hood_window_around_a_position)                                                            \
    X(n42e001_matches_point_and_gdaldem_on_the_render_grid)                                        \
    X(bad_input_exits_2_or_1_and_writes_nothing)

#define HOOD "lf_elev_220_mt_hood_utm.tif"
#define N42 "N42E001.hgt"

static const char* tmp_dir(void)
{
    return tp_test_child_dir("terrain");
}

static int run_terrain(const char* const* args, char* out, size_t out_cap, char* err,
                       size_t err_cap)
{
    return tp_test_run_terrapatch_out("terrain", args, out, out_cap, err, err_cap);
}

static GDALDatasetH open_or_fail(const char* path)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    if (!ds)
        FAIL("GDAL cannot open %s", path);
    return ds;
}

/* Band 1 of ds as floats, its nodata as NaN. */
static float* read_band(GDALDatasetH ds)
{
    const int w = GDALGetRasterXSize(ds), h = GDALGetRasterYSize(ds);
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    float* v = malloc((size_t)w * h * sizeof *v);
    ASSERT_TRUE(v != NULL);
    ASSERT_TRUE(GDALRasterIO(b, GF_Read, 0, 0, w, h, v, w, h, GDT_Float32, 0, 0) == CE_None);
    int has = 0;
    const double nodata = GDALGetRasterNoDataValue(b, &has);
    if (has)
        for (size_t i = 0; i < (size_t)w * h; ++i)
            if (v[i] == (float)nodata)
                v[i] = NAN;
    return v;
}

/* gdaldem PROCESSING ARGS... -of MEM on src (GDALDEMProcessing, GDAL's own). */
static GDALDatasetH gdaldem(GDALDatasetH src, const char* processing, const char* const* args)
{
    char* argv[24];
    int n = 0;
    argv[n++] = (char*)"-of";
    argv[n++] = (char*)"MEM";
    for (int i = 0; args[i] && n < 22; ++i)
        argv[n++] = (char*)args[i];
    argv[n] = NULL;
    GDALDEMProcessingOptions* o = GDALDEMProcessingOptionsNew(argv, NULL);
    ASSERT_TRUE(o != NULL);
    int usage = 0;
    GDALDatasetH out = GDALDEMProcessing("", src, processing, NULL, o, &usage);
    GDALDEMProcessingOptionsFree(o);
    ASSERT_TRUE(out != NULL);
    return out;
}

/* What compare found. */
typedef struct agreement {
    size_t compared, both_nodata;  /* posts with a value in both; with nodata in both */
    size_t lone, beside_lone;      /* posts the ground has not though the DEM has (below);
                                      posts beside them, not compared */
    size_t missing, extra, differ; /* ours nodata where gdaldem has a value; the other way;
                                      values further apart than tol */
    size_t edges;                  /* compared on the DEM's edge or beside a void: values only
                                      with -compute_edges */
    double worst;
} agreement;

/* A post of the DEM (W x H, NaN void) none of whose four cells has four heights: a lone post
 * amid voids. The ground's surface is made of the cells' triangles (app/scene/ground.h), so it
 * has no height at such a post unless a triangle of a cell of three heights holds it (which
 * depends on the cell's diagonal). */
static int lone_post(const float* dem, int W, int H, int x, int y)
{
    if (isnan(dem[(size_t)y * W + x]))
        return 0;
    for (int c = 0; c < 4; ++c) {
        const int cx = x + c % 2 - 1, cy = y + c / 2 - 1;
        if (cx < 0 || cy < 0 || cx + 1 >= W || cy + 1 >= H)
            continue;
        const float* r = dem + (size_t)cy * W + cx;
        if (!isnan(r[0]) && !isnan(r[1]) && !isnan(r[W]) && !isnan(r[W + 1]))
            return 0;
    }
    return 1;
}

/* Ours (w x h, from post (x0, y0) of the DEM) against gdaldem's ref (W x H) at every post of
 * ours whose 3x3 window lies inside ours (or at the DEM's edge, which ours shares); the
 * DEM's heights dem (W x H, NaN void) tell the posts beside a void. angle: values in degrees on
 * a circle (aspect). Where the ground has no height at a lone post (lone_post) that gdaldem
 * reads, only -compute_edges gives either a value there or beside it: such posts and their
 * neighbours are counted, not compared. */
static agreement compare(const float* ours, int w, int h, int x0, int y0, const float* ref,
                         const float* dem, int W, int H, double tol, int angle)
{
    agreement a = {0};
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const int X = x0 + x, Y = y0 + y;
            /* a post on our window's edge that is not the DEM's has gdaldem's neighbours but
             * not ours */
            if ((x == 0 && X > 0) || (y == 0 && Y > 0) || (x == w - 1 && X < W - 1) ||
                (y == h - 1 && Y < H - 1))
                continue;
            int beside_void = 0, beside_lone = 0;
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    const int u = X + dx, v = Y + dy, i = (v - y0) * w + (u - x0);
                    if (u < 0 || u >= W || v < 0 || v >= H)
                        continue;
                    beside_void |= isnan(dem[(size_t)v * W + u]);
                    beside_lone |= u >= x0 && u < x0 + w && v >= y0 && v < y0 + h &&
                                   isnan(ours[i]) && !isnan(ref[(size_t)v * W + u]) &&
                                   lone_post(dem, W, H, u, v);
                }
            const double o = ours[(size_t)y * w + x], r = ref[(size_t)Y * W + X];
            if (beside_lone) {
                const int here = isnan(o) && !isnan(r) && lone_post(dem, W, H, X, Y);
                a.lone += here;
                a.beside_lone += !here;
                continue;
            }
            if (isnan(r)) {
                a.both_nodata += isnan(o);
                a.extra += !isnan(o);
                continue;
            }
            if (isnan(o)) {
                ++a.missing;
                continue;
            }
            double d = fabs(o - r);
            if (angle)
                d = fabs(fmod(o - r + 540.0, 360.0) - 180.0);
            a.worst = fmax(a.worst, d);
            a.differ += d > tol;
            a.edges += beside_void || X == 0 || Y == 0 || X == W - 1 || Y == H - 1;
            ++a.compared;
        }
    return a;
}

/* Checks path's size, georeference, type and nodata against the DEM's window. */
static void expect_grid(GDALDatasetH ds, GDALDatasetH dem, int x0, int y0, int w, int h,
                        GDALDataType type, double nodata)
{
    EXPECT_EQ_INT(w, GDALGetRasterXSize(ds));
    EXPECT_EQ_INT(h, GDALGetRasterYSize(ds));
    EXPECT_EQ_INT(1, GDALGetRasterCount(ds));
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    EXPECT_EQ_INT((int)type, (int)GDALGetRasterDataType(b));
    int has = 0;
    EXPECT_EQ_DBL(nodata, GDALGetRasterNoDataValue(b, &has));
    EXPECT_TRUE(has);
    double a[6], g[6];
    ASSERT_TRUE(GDALGetGeoTransform(ds, a) == CE_None);
    ASSERT_TRUE(GDALGetGeoTransform(dem, g) == CE_None);
    EXPECT_NEAR(a[0], g[0] + x0 * g[1], 1e-6);
    EXPECT_NEAR(a[3], g[3] + y0 * g[5], 1e-6);
    EXPECT_NEAR(a[1], g[1], 1e-9);
    EXPECT_NEAR(a[5], g[5], 1e-9);
    OGRSpatialReferenceH sa = OSRNewSpatialReference(GDALGetProjectionRef(ds));
    OGRSpatialReferenceH sb = OSRNewSpatialReference(GDALGetProjectionRef(dem));
    EXPECT_TRUE(OSRIsSame(sa, sb));
    OSRDestroySpatialReference(sa);
    OSRDestroySpatialReference(sb);
}

/* One run of `terrain` on Mt Hood and gdaldem's answer for it. */
typedef struct hood_case {
    const char* name; /* the output file, in the test's folder */
    const char* args[12];
    const char* processing;
    const char* gdaldem_args[12];
    double tol;
    int angle, compute_edges;
    /* where gdaldem has no value: gdaldem slope's nodata with these arguments (gdaldem
     * -zero_for_flat writes 0 in voids too, where terrain keeps nodata); NULL: its own */
    const char* mask_args[4];
} hood_case;

static const hood_case k_hood[] = {
    {"slope.tif", {NULL}, "slope", {NULL}, 1e-4, 0, 0, {NULL}},
    {"slope_pct_zt_edges.tif",
     {"--percent", "--method", "zevenbergen", "--compute-edges", NULL},
     "slope",
     {"-p", "-alg", "ZevenbergenThorne", "-compute_edges", NULL},
     1e-4,
     0,
     1,
     {NULL}},
    {"aspect.tif", {"--what", "aspect", NULL}, "aspect", {NULL}, 1e-3, 1, 0, {NULL}},
    {"aspect_flat.tif",
     {"--what", "aspect", "--zero-for-flat", NULL},
     "aspect",
     {"-zero_for_flat", NULL},
     1e-3,
     1,
     0,
     {"", NULL}},
    {"aspect_flat_edges.tif",
     {"--what", "aspect", "--zero-for-flat", "--compute-edges", NULL},
     "aspect",
     {"-zero_for_flat", "-compute_edges", NULL},
     1e-3,
     1,
     1,
     {"-compute_edges", NULL}},
    {"aspect_zt.tif",
     {"--what", "aspect", "--method", "zevenbergen", NULL},
     "aspect",
     {"-alg", "ZevenbergenThorne", NULL},
     1e-3,
     1,
     0,
     {NULL}},
    {"shade.tif", {"--what", "hillshade", NULL}, "hillshade", {NULL}, 0.0, 0, 0, {NULL}},
    {"shade_opts.tif",
     {"--what", "hillshade", "--azimuth", "250", "--altitude", "30", "--z-factor", "2.5", NULL},
     "hillshade",
     {"-az", "250", "-alt", "30", "-z", "2.5", NULL},
     0.0,
     0,
     0,
     {NULL}},
};

/* Runs case c on dem_path into the test's folder and compares with gdaldem on the DEM;
 * returns the output's path in out_path. */
static void run_hood_case(const hood_case* c, const char* dem_path, GDALDatasetH dem,
                          const float* heights, char* out_path, size_t cap)
{
    const int W = GDALGetRasterXSize(dem), H = GDALGetRasterYSize(dem);
    snprintf(out_path, cap, "%s/%s", tmp_dir(), c->name);
    const char* args[24];
    int n = 0;
    args[n++] = dem_path;
    args[n++] = "-o";
    args[n++] = out_path;
    for (int i = 0; c->args[i]; ++i)
        args[n++] = c->args[i];
    args[n] = NULL;
    char so[4096], se[8192];
    ASSERT_EQ_INT(0, run_terrain(args, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(so, "window     1013x799 posts: the whole DEM");
    EXPECT_CONTAINS(se, "wrote ");
    GDALDatasetH ds = open_or_fail(out_path);
    const int hill = !strcmp(c->processing, "hillshade");
    expect_grid(ds, dem, 0, 0, W, H, hill ? GDT_Byte : GDT_Float32, hill ? 0.0 : -9999.0);
    GDALDatasetH ref = gdaldem(dem, c->processing, c->gdaldem_args);
    float *ours = read_band(ds), *theirs = read_band(ref);
    if (c->mask_args[0]) {
        const char* const* margs = c->mask_args[0][0] ? c->mask_args : c->mask_args + 1;
        GDALDatasetH mask = gdaldem(dem, "slope", margs);
        float* m = read_band(mask);
        size_t zeros = 0;
        for (size_t i = 0; i < (size_t)W * H; ++i) {
            zeros += theirs[i] == 0.0f;
            if (isnan(m[i]))
                theirs[i] = NAN;
        }
        EXPECT_GE_INT((int)zeros, 1000); /* -zero_for_flat has work to do: flat ground */
        free(m);
        GDALClose(mask);
    }
    agreement a = compare(ours, W, H, 0, 0, theirs, heights, W, H, c->tol, c->angle);
    tp_test_note("%s: %zu posts equal (worst %.2g; %zu of them beside a void or on the edge), "
                 "%zu nodata in both; %zu lone posts the ground has not, %zu beside them",
                 c->name, a.compared, a.worst, a.edges, a.both_nodata, a.lone, a.beside_lone);
    EXPECT_LE_INT((int)a.lone, c->compute_edges ? 5 : 0); /* one on Mt Hood */
    EXPECT_LE_INT((int)a.beside_lone, 8 * (int)a.lone);
    EXPECT_GE_INT((int)a.compared, 700000); /* of 809387 posts, 26821 void */
    EXPECT_EQ_INT(0, (int)a.missing);
    EXPECT_EQ_INT(0, (int)a.extra);
    EXPECT_EQ_INT(0, (int)a.differ);
    if (!c->compute_edges)
        EXPECT_EQ_INT(0, (int)a.edges); /* gdaldem has no value there */
    else
        EXPECT_GE_INT((int)a.edges, 1000); /* -compute_edges: values there, compared */
    free(ours);
    free(theirs);
    GDALClose(ref);
    GDALClose(ds);
}

static GDALDatasetH open_hood(char* path, size_t cap, float** heights)
{
    if (!tp_test_data_path(path, cap, "TP_SHARED_DATA_DIR", HOOD))
        SKIP("%s not found (set TP_SHARED_DATA_DIR)", HOOD);
    GDALDatasetH dem = open_or_fail(path);
    *heights = read_band(dem);
    return dem;
}

TEST(mt_hood_products_equal_gdaldem_on_the_file)
{
    char path[1024], out[1024];
    float* heights;
    GDALDatasetH dem = open_hood(path, sizeof path, &heights);
    for (size_t i = 0; i < sizeof k_hood / sizeof k_hood[0]; ++i)
        run_hood_case(&k_hood[i], path, dem, heights, out, sizeof out);
    free(heights);
    GDALClose(dem);
}

/* The float formats and the hillshade's PNG: the same values as gdaldem's. */
TEST(mt_hood_formats_hold_the_same_values)
{
    char path[1024], out[1024];
    float* heights;
    GDALDatasetH dem = open_hood(path, sizeof path, &heights);
    const hood_case cases[] = {
        {"slope.img", {NULL}, "slope", {NULL}, 1e-4, 0, 0, {NULL}},
        {"slope.asc", {NULL}, "slope", {NULL}, 1e-4, 0, 0, {NULL}},
        {"aspect.gpkg", {"--what", "aspect", NULL}, "aspect", {NULL}, 1e-3, 1, 0, {NULL}},
        {"shade.png", {"--what", "hillshade", NULL}, "hillshade", {NULL}, 0.0, 0, 0, {NULL}},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i)
        run_hood_case(&cases[i], path, dem, heights, out, sizeof out);
    free(heights);
    GDALClose(dem);
}

/* --around POS --radius M: the square of posts around POS's post, with gdaldem's values. */
TEST(mt_hood_window_around_a_position)
{
    char path[1024], out[1024], so[4096], se[8192];
    float* heights;
    GDALDatasetH dem = open_hood(path, sizeof path, &heights);
    const int W = GDALGetRasterXSize(dem), H = GDALGetRasterYSize(dem);
    double g[6];
    ASSERT_TRUE(GDALGetGeoTransform(dem, g) == CE_None);
    /* a quarter post east and south of post (500, 400)'s centre (grid 500.25, 400.25), in the
     * file's CRS (UTM 10N), typed as a UTM position: the posts whose centres are within 3000 m
     * (100 posts) of it along each axis are columns 401 .. 600, rows 301 .. 500 */
    const int px = 500, py = 400;
    char pos[128];
    snprintf(pos, sizeof pos, "10n %.3f %.3f", g[0] + (px + 0.75) * g[1],
             g[3] + (py + 0.75) * g[5]);
    snprintf(out, sizeof out, "%s/around.tif", tmp_dir());
    const char* args[] = {path, "--around", pos, "--radius", "3000", "-o", out, NULL};
    ASSERT_EQ_INT(0, run_terrain(args, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(so, "window     200x200 posts from (401, 301) of 1013x799");
    GDALDatasetH ds = open_or_fail(out);
    expect_grid(ds, dem, 401, 301, 200, 200, GDT_Float32, -9999.0);
    const char* none[] = {NULL};
    GDALDatasetH ref = gdaldem(dem, "slope", none);
    float *ours = read_band(ds), *theirs = read_band(ref);
    agreement a = compare(ours, 200, 200, 401, 301, theirs, heights, W, H, 1e-4, 0);
    EXPECT_EQ_INT(198 * 198, (int)(a.compared + a.both_nodata));
    EXPECT_GE_INT((int)a.compared, 198 * 198 / 2);
    EXPECT_EQ_INT(0, (int)(a.missing + a.extra + a.differ));
    /* the window's own edge: no 3x3 window there, nodata (gdaldem's rule on the window) */
    for (int i = 0; i < 200; ++i) {
        EXPECT_NAN(ours[i]);
        EXPECT_NAN(ours[199 * 200 + i]);
        EXPECT_NAN(ours[i * 200]);
        EXPECT_NAN(ours[i * 200 + 199]);
    }
    free(ours);
    free(theirs);
    GDALClose(ref);
    GDALClose(ds);
    free(heights);
    GDALClose(dem);
}

/* The value after "key": in point's JSON. */
static double json_number(const char* json, const char* key)
{
    return tp_test_json_number_after(json, NULL, key);
}

TEST(n42e001_matches_point_and_gdaldem_on_the_render_grid)
{
    char path[1024], slope_path[1024], aspect_path[1024], so[4096], se[8192];
    if (!tp_test_data_path(path, sizeof path, "TP_SHARED_DATA_DIR", N42))
        SKIP("%s not found (set TP_SHARED_DATA_DIR)", N42);
    snprintf(slope_path, sizeof slope_path, "%s/n42_slope.tif", tmp_dir());
    snprintf(aspect_path, sizeof aspect_path, "%s/n42_aspect.tif", tmp_dir());
    const char* a1[] = {path, "-o", slope_path, NULL};
    ASSERT_EQ_INT(0, run_terrain(a1, so, sizeof so, se, sizeof se));
    /* the step the store rounds heights to, as the summary states it */
    const char* ground = strstr(so, "(stored in steps of ");
    ASSERT_TRUE(ground != NULL);
    const double step = strtod(ground + strlen("(stored in steps of "), NULL);
    ASSERT_GT(step, 0.0);
    const char* a2[] = {path, "--what", "aspect", "-o", aspect_path, NULL};
    ASSERT_EQ_INT(0, run_terrain(a2, so, sizeof so, se, sizeof se));

    /* the render grid: the DEM warped to UTM 31N (tp_render_grid_build), as the store holds it */
    tp_dem* d = NULL;
    tp_render_grid* rg = NULL;
    ASSERT_OK(tp_dem_read(path, &d, NULL));
    ASSERT_OK(tp_render_grid_build(d, NULL, &rg, NULL));
    tp_dem_destroy(d);
    EXPECT_EQ_INT(31, rg->utm_zone);
    GDALDatasetH sds = open_or_fail(slope_path), ads = open_or_fail(aspect_path);
    const int W = rg->width, H = rg->height;
    EXPECT_EQ_INT(W, GDALGetRasterXSize(sds));
    EXPECT_EQ_INT(H, GDALGetRasterYSize(sds));
    double gt[6];
    ASSERT_TRUE(GDALGetGeoTransform(sds, gt) == CE_None);
    for (int i = 0; i < 6; ++i)
        EXPECT_NEAR(gt[i], rg->geotransform[i], 1e-6);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(GDALGetProjectionRef(sds));
    int north = 0;
    EXPECT_EQ_INT(31, OSRGetUTMZone(srs, &north));
    EXPECT_TRUE(north);
    OSRDestroySpatialReference(srs);
    float *slope = read_band(sds), *aspect = read_band(ads);

    /* gdaldem on the render grid (a MEM dataset of its heights). The store rounds each height
     * to its step (by up to step / 2), which moves each of Horn's two differences, 8 heights
     * with weights 1 2 1 over 8 * spacing, by up to step / (2 * spacing): the gradient by
     * sqrt(2) times that, and the slope (atan of the gradient) by no more in radians */
    GDALDriverH mem = GDALGetDriverByName("MEM");
    GDALDatasetH grid = GDALCreate(mem, "", W, H, 1, GDT_Float32, NULL);
    GDALSetGeoTransform(grid, rg->geotransform);
    GDALSetRasterNoDataValue(GDALGetRasterBand(grid, 1), -32768.0);
    float* hz = malloc((size_t)W * H * sizeof *hz);
    ASSERT_TRUE(hz != NULL);
    for (size_t i = 0; i < (size_t)W * H; ++i)
        hz[i] = isnan(rg->heights[i]) ? -32768.0f : rg->heights[i];
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(grid, 1), GF_Write, 0, 0, W, H, hz, W, H,
                             GDT_Float32, 0, 0) == CE_None);
    for (size_t i = 0; i < (size_t)W * H; ++i)
        hz[i] = rg->heights[i];
    const char* none[] = {NULL};
    GDALDatasetH ref = gdaldem(grid, "slope", none);
    float* theirs = read_band(ref);
    const double bound = sqrt(2.0) * step / (2.0 * gt[1]) * 180.0 / M_PI + 1e-4;
    agreement a = compare(slope, W, H, 0, 0, theirs, hz, W, H, bound, 0);
    tp_test_note("N42E001 slope against gdaldem on the render grid (heights in steps of %g m): "
                 "%zu posts, worst %.4f deg (bound %.4f)",
                 step, a.compared, a.worst, bound);
    EXPECT_GE_INT((int)a.compared, 1900000);
    EXPECT_EQ_INT(0, (int)(a.missing + a.extra + a.differ));

    /* point's Horn slope and aspect at posts, typed as UTM positions of their centres */
    tp_rng rng = tp_rng_seed(31);
    int checked = 0;
    double worst_slope = 0.0, worst_aspect = 0.0;
    for (int tries = 0; tries < 1000 && checked < 16; ++tries) {
        const int x = tp_rng_int(&rng, 2, W - 3), y = tp_rng_int(&rng, 2, H - 3);
        const float s = slope[(size_t)y * W + x], as = aspect[(size_t)y * W + x];
        if (isnan(s))
            continue;
        char pos[128], json[8192];
        snprintf(pos, sizeof pos, "31n %.4f %.4f", gt[0] + (x + 0.5) * gt[1],
                 gt[3] + (y + 0.5) * gt[5]);
        const char* pa[] = {path, pos, "--json", "-", NULL};
        ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("point", pa, json, sizeof json, se, sizeof se));
        EXPECT_CONTAINS(json, "\"slope_method\": \"horn\"");
        EXPECT_NEAR(x, json_number(json, "x"), 1e-4);
        EXPECT_NEAR(y, json_number(json, "y"), 1e-4);
        const double ps = json_number(json, "slope_deg");
        EXPECT_NEAR(s, ps, 1e-3);
        worst_slope = fmax(worst_slope, fabs(s - ps));
        if (!isnan(as)) {
            const double pa_deg = json_number(json, "aspect_grid_deg");
            const double dd = fabs(fmod(as - pa_deg + 540.0, 360.0) - 180.0);
            EXPECT_LE(dd, 1e-2);
            worst_aspect = fmax(worst_aspect, dd);
        }
        ++checked;
    }
    tp_test_note("N42E001: %d posts equal point's Horn slope within %.2g deg, aspect within "
                 "%.2g deg",
                 checked, worst_slope, worst_aspect);
    EXPECT_EQ_INT(16, checked);
    free(theirs);
    free(hz);
    free(slope);
    free(aspect);
    GDALClose(ref);
    GDALClose(grid);
    GDALClose(sds);
    GDALClose(ads);
    tp_render_grid_destroy(rg);
}

static int exists(const char* path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

TEST(bad_input_exits_2_or_1_and_writes_nothing)
{
    char path[1024], out[1024], so[4096], se[8192];
    if (!tp_test_data_path(path, sizeof path, "TP_SHARED_DATA_DIR", HOOD))
        SKIP("%s not found (set TP_SHARED_DATA_DIR)", HOOD);
    const char* dir = tmp_dir();
    struct {
        const char* name; /* in dir; NULL: out is "/nonexistent-dir/x.tif" */
        const char* extra[4];
        int rc;
        const char* message;
    } cases[] = {
        {"bad_what.tif",
         {"--what", "curvature", NULL},
         2,
         "--what: expected slope, aspect or hillshade, got 'curvature'"},
        {"bad_method.tif",
         {"--method", "fd8", NULL},
         2,
         "--method: expected horn or zevenbergen, got 'fd8'"},
        {"pct_aspect.tif",
         {"--what", "aspect", "--percent", NULL},
         2,
         "--percent is for --what slope, not aspect"},
        {"az_slope.tif", {"--azimuth", "90", NULL}, 2, "--azimuth is for --what hillshade"},
        {"slope.png",
         {NULL},
         2,
         "PNG holds no Float32 values; terrain --what slope writes GeoTIFF"},
        {"slope.xyz", {NULL}, 2, "'.xyz' is GDAL's XYZ driver, not one of the raster formats"},
        {"shade.foo", {"--what", "hillshade", NULL}, 2, "unknown extension '.foo'"},
        {"shade.jpg", {"--what", "hillshade", NULL}, 2, "JPEG is lossy"},
        {NULL, {NULL}, 1, "/nonexistent-dir/x.tif"},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        if (cases[i].name)
            snprintf(out, sizeof out, "%s/%s", dir, cases[i].name);
        else
            snprintf(out, sizeof out, "/nonexistent-dir/x.tif");
        const char* args[12] = {path, "-o", out};
        int n = 3;
        for (int k = 0; cases[i].extra[k]; ++k)
            args[n++] = cases[i].extra[k];
        args[n] = NULL;
        EXPECT_EQ_INT(cases[i].rc, run_terrain(args, so, sizeof so, se, sizeof se));
        EXPECT_CONTAINS(se, cases[i].message);
        EXPECT_FALSE(exists(out));
        EXPECT_EQ_STR("", so);
    }
    /* an older file stays as it was when the run fails, and so does an area off the DEM */
    snprintf(out, sizeof out, "%s/old.tif", dir);
    FILE* f = fopen(out, "w");
    ASSERT_TRUE(f != NULL);
    fputs("older", f);
    fclose(f);
    const char* off[] = {path, "--area", "0,0,1000,1000", "-o", out, NULL};
    EXPECT_EQ_INT(1, run_terrain(off, so, sizeof so, se, sizeof se));
    EXPECT_CONTAINS(se, "is outside the DEM");
    const char* bad[] = {path, "--what", "relief", "-o", out, NULL};
    EXPECT_EQ_INT(2, run_terrain(bad, so, sizeof so, se, sizeof se));
    char text[64];
    tp_test_read_text(out, text, sizeof text);
    EXPECT_EQ_STR("older", text);
    EXPECT_TRUE(tp_test_nothing_named(dir, "old.tif.")); /* no temporary file beside it */
}

TP_TEST_MAIN(TESTS)
