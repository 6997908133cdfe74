/*
 * test_ground.c - full-resolution ground queries (app/scene/ground.c) on a store built from a real DEM
 * (Mt Hood, NAD83 / UTM 10N: the store keeps the DEM's grid and its Int16 heights exactly):
 * heights at posts (corners included) against GDAL's own reading of the DEM; a cache of 4 leaves
 * answers exactly as a large one while reading more; positions off the DEM are refused with the
 * output left alone; slope and aspect by Horn's method against gdaldem's on the same grid.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"
#include "tp_io.h"

#include "tp_test_child.h"

#include "ground.h"
#include "store_scene.h"

#include <gdal.h>
#include <gdal_utils.h>

#include <math.h>

#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define HOOD "lf_elev_220_mt_hood_utm.tif"
#define HOOD_NODATA 32767

typedef struct fixture {
    char dem[1024], store[256], dir[64];
    tp_store_scene sc;
    GDALDatasetH ds;
    int w, h;
} fixture;

static void fixture_open(fixture* f)
{
    memset(f, 0, sizeof *f);
    if (!tp_test_data_path(f->dem, sizeof f->dem, "TP_SHARED_DATA_DIR", HOOD))
        SKIP("%s not found (set TP_SHARED_DATA_DIR)", HOOD);
    strcpy(f->dir, "/tmp/tp_test_groundXXXXXX");
    ASSERT_TRUE(mkdtemp(f->dir) != NULL);
    snprintf(f->store, sizeof f->store, "%s/hood.tpt", f->dir);
    char err[4096];
    const char* args[] = {f->dem, "-o", f->store, "--quiet", NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("build", args, err, sizeof err));
    ASSERT_EQ_INT(0, tp_store_scene_open(f->store, &f->sc));
    GDALAllRegister();
    f->ds = GDALOpen(f->dem, GA_ReadOnly);
    ASSERT_TRUE(f->ds != NULL);
    f->w = GDALGetRasterXSize(f->ds);
    f->h = GDALGetRasterYSize(f->ds);
}

static void fixture_close(fixture* f)
{
    GDALClose(f->ds);
    tp_store_scene_close(&f->sc);
    remove(f->store);
    rmdir(f->dir);
}

static double gdal_sample(GDALDatasetH ds, int c, int r)
{
    float v;
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, c, r, 1, 1, &v, 1, 1,
                             GDT_Float32, 0, 0) == CE_None);
    return v == HOOD_NODATA ? NAN : v;
}

TEST(posts_and_corners_equal_gdal)
{
    fixture f;
    fixture_open(&f);
    tp_ground* g = NULL;
    ASSERT_OK(tp_ground_create(&f.sc, NULL, &g, NULL));
    tp_rng rng = tp_rng_seed(13);
    int checked = 0, voids = 0;
    for (int i = 0; i < 400; ++i) {
        int c = i < 4 ? (i & 1) * (f.w - 1) : tp_rng_int(&rng, 0, f.w - 1);
        int r = i < 4 ? (i >> 1) * (f.h - 1) : tp_rng_int(&rng, 0, f.h - 1);
        double want = gdal_sample(f.ds, c, r), got = -1;
        ASSERT_OK(tp_ground_height(g, c, r, &got, NULL));
        if (isnan(want)) {
            /* a nodata post of the collar: no drawn triangle touches it... unless filled */
            voids += isnan(got);
            continue;
        }
        EXPECT_EQ_DBL(want, got);
        ++checked;
    }
    EXPECT_GE_INT(checked, 300);
    EXPECT_GE_INT(voids, 1); /* the corners are nodata in this DEM */
    tp_ground_destroy(g);
    fixture_close(&f);
}

TEST(tiny_cache_answers_as_a_large_one)
{
    fixture f;
    fixture_open(&f);
    tp_ground *tiny = NULL, *large = NULL;
    ASSERT_OK(tp_ground_create(&f.sc, &(tp_ground_options){.cache_bytes = 1}, &tiny, NULL));
    ASSERT_OK(tp_ground_create(&f.sc, &(tp_ground_options){.cache_bytes = 64 << 20}, &large, NULL));
    tp_rng rng = tp_rng_seed(7);
    for (int i = 0; i < 3000; ++i) {
        double x = tp_rng_range(&rng, 0, f.w - 1), y = tp_rng_range(&rng, 0, f.h - 1);
        if (i % 3 == 0) /* on a leaf border (node size 17: every 16 posts) */
            x = 16.0 * (int)(x / 16.0);
        tp_ground_sample a, b;
        ASSERT_OK(tp_ground_query_grid(tiny, x, y, &a, NULL));
        ASSERT_OK(tp_ground_query_grid(large, x, y, &b, NULL));
        if (isnan(b.height_m)) {
            EXPECT_NAN(a.height_m);
            continue;
        }
        EXPECT_EQ_DBL(b.height_m, a.height_m);
        if (!isnan(b.slope_deg))
            EXPECT_EQ_DBL(b.slope_deg, a.slope_deg);
    }
    /* 4 slots for thousands of scattered points: most queries read again */
    EXPECT_GT(tp_ground_reads(tiny), 2 * tp_ground_reads(large));
    EXPECT_LE(tp_ground_reads(large), (double)f.sc.info.header.geometry.cols *
                                          f.sc.info.header.geometry.rows);
    tp_ground_destroy(tiny);
    tp_ground_destroy(large);
    fixture_close(&f);
}

TEST(off_the_dem_is_refused_and_output_untouched)
{
    fixture f;
    fixture_open(&f);
    tp_ground* g = NULL;
    ASSERT_OK(tp_ground_create(&f.sc, NULL, &g, NULL));
    const double xy[][2] = {{-0.01, 10}, {10, -0.01}, {f.w - 1 + 0.01, 10}, {10, f.h - 1 + 0.01},
                            {NAN, 10}, {1e12, 1e12}};
    for (size_t i = 0; i < sizeof xy / sizeof xy[0]; ++i) {
        double h = -7;
        tp_ground_sample s;
        memset(&s, 0x55, sizeof s);
        tp_ground_sample before = s;
        tp_error err = {{0}};
        EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_ground_height(g, xy[i][0], xy[i][1], &h, &err));
        EXPECT_CONTAINS(err.message, "outside the DEM");
        EXPECT_EQ_DBL(-7.0, h);
        EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_ground_query_grid(g, xy[i][0], xy[i][1], &s, &err));
        EXPECT_TRUE(memcmp(&s, &before, sizeof s) == 0);
    }
    /* the far corner itself is on the DEM */
    double h = -7;
    EXPECT_OK(tp_ground_height(g, f.w - 1, f.h - 1, &h, NULL));
    tp_ground_destroy(g);
    fixture_close(&f);
}

/* gdaldem's processing ("slope" or "aspect": degrees, Horn's method, its defaults) of src, in
 * memory: the independent answer (GDALDEMProcessing, as `gdaldem slope|aspect`). */
static GDALDatasetH gdaldem(GDALDatasetH src, const char* processing)
{
    char of[] = "-of", mem[] = "MEM";
    char* argv[] = {of, mem, NULL};
    GDALDEMProcessingOptions* o = GDALDEMProcessingOptionsNew(argv, NULL);
    ASSERT_TRUE(o != NULL);
    int usage = 0;
    GDALDatasetH out = GDALDEMProcessing("", src, processing, NULL, o, &usage);
    GDALDEMProcessingOptionsFree(o);
    ASSERT_TRUE(out != NULL);
    return out;
}

/* Value at (c, r) of a gdaldem output, NaN for its nodata (-9999: an edge, a void, flat). */
static double dem_output(GDALDatasetH ds, int c, int r)
{
    float v;
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, c, r, 1, 1, &v, 1, 1,
                             GDT_Float32, 0, 0) == CE_None);
    return v == -9999.0f ? NAN : v;
}

TEST(horn_slope_and_aspect_equal_gdaldem)
{
    fixture f;
    fixture_open(&f);
    GDALDatasetH slope = gdaldem(f.ds, "slope"), aspect = gdaldem(f.ds, "aspect");
    tp_ground* g = NULL;
    ASSERT_OK(tp_ground_create(&f.sc, NULL, &g, NULL));
    tp_rng rng = tp_rng_seed(31);
    int checked = 0, aspects = 0, differ = 0;
    double worst_central = 0.0, worst_horn = 0.0, worst_aspect = 0.0;
    for (int i = 0; i < 4000 && checked < 400; ++i) {
        const int c = tp_rng_int(&rng, 0, f.w - 1), r = tp_rng_int(&rng, 0, f.h - 1);
        const double want = dem_output(slope, c, r);
        tp_ground_sample a, b;
        ASSERT_OK(tp_ground_query_grid(g, c, r, &a, NULL));
        if (isnan(want)) { /* gdaldem has no Horn window there: nor have we */
            if (!isnan(a.height_m))
                EXPECT_EQ_INT(TP_SLOPE_CENTRAL, a.slope_method);
            continue;
        }
        EXPECT_EQ_INT(TP_SLOPE_HORN, a.slope_method);
        EXPECT_NEAR(a.slope_deg, want, 1e-3);
        worst_horn = fmax(worst_horn, fabs(a.slope_deg - want));
        const double want_aspect = dem_output(aspect, c, r);
        if (!isnan(want_aspect)) {
            const double d = fabs(fmod(a.aspect_grid_deg - want_aspect + 540.0, 360.0) - 180.0);
            EXPECT_LE(d, 1e-3);
            worst_aspect = fmax(worst_aspect, d);
            ++aspects;
        }
        /* central differences answer otherwise: the test tells the two apart */
        tp_ground_set_slope_method(g, TP_SLOPE_CENTRAL);
        ASSERT_OK(tp_ground_query_grid(g, c, r, &b, NULL));
        tp_ground_set_slope_method(g, TP_SLOPE_HORN);
        EXPECT_EQ_INT(TP_SLOPE_CENTRAL, b.slope_method);
        differ += fabs(b.slope_deg - want) > 0.01;
        worst_central = fmax(worst_central, fabs(b.slope_deg - want));
        ++checked;
    }
    tp_test_note("%d posts, %d aspects equal gdaldem's (up to %.1e and %.1e deg); central "
                 "differences differ at %d (up to %.2f deg of slope)",
                 checked, aspects, worst_horn, worst_aspect, differ, worst_central);
    EXPECT_GE_INT(checked, 400);
    EXPECT_GE_INT(aspects, 300);
    EXPECT_GE_INT(differ, 100);
    /* the DEM's edge: no window, central (one-sided) differences */
    tp_ground_sample e;
    ASSERT_OK(tp_ground_query_grid(g, 0, f.h / 2, &e, NULL));
    if (!isnan(e.height_m))
        EXPECT_EQ_INT(TP_SLOPE_CENTRAL, e.slope_method);
    tp_ground_destroy(g);
    GDALClose(slope);
    GDALClose(aspect);
    fixture_close(&f);
}

/* A warped integer DEM (N42E001, geographic SRTM, bilinear to UTM 31N) keeps the warp's
 * heights to half its step (issue 31): the store's heights at posts against GDAL's own warp of
 * the file onto the store's grid (gdalwarp -r bilinear -et 0, run here), where the old 1 m step
 * moved them by up to 0.5 m. */
TEST(warped_dem_keeps_its_heights_to_half_its_step)
{
    char dem[1024], dir[64] = "/tmp/tp_test_groundXXXXXX", store[256], err[4096];
    if (!tp_test_data_path(dem, sizeof dem, "TP_SHARED_DATA_DIR", "N42E001.hgt"))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    ASSERT_TRUE(mkdtemp(dir) != NULL);
    snprintf(store, sizeof store, "%s/n42.tpt", dir);
    const char* args[] = {dem, "-o", store, "--quiet", NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("build", args, err, sizeof err));
    tp_store_scene sc;
    ASSERT_EQ_INT(0, tp_store_scene_open(store, &sc));
    const tp_store_header* hd = &sc.info.header;
    const int w = hd->geometry.src_width, h = hd->geometry.src_height;
    const double* gt = hd->geotransform;
    EXPECT_LE(hd->height_step_m, 0.0625);

    GDALAllRegister();
    GDALDatasetH src = GDALOpen(dem, GA_ReadOnly);
    ASSERT_TRUE(src != NULL);
    char te[4][32], ts[2][16];
    snprintf(te[0], sizeof te[0], "%.17g", gt[0]);
    snprintf(te[1], sizeof te[1], "%.17g", gt[3] + h * gt[5]);
    snprintf(te[2], sizeof te[2], "%.17g", gt[0] + w * gt[1]);
    snprintf(te[3], sizeof te[3], "%.17g", gt[3]);
    snprintf(ts[0], sizeof ts[0], "%d", w);
    snprintf(ts[1], sizeof ts[1], "%d", h);
    char* wargs[] = {"-of", "MEM", "-t_srs", (char*)hd->crs_wkt, "-te", te[0], te[1], te[2],
                     te[3], "-ts", ts[0], ts[1], "-r", "bilinear", "-et", "0", "-ot", "Float32",
                     "-dstnodata", "nan", NULL};
    GDALWarpAppOptions* wo = GDALWarpAppOptionsNew(wargs, NULL);
    ASSERT_TRUE(wo != NULL);
    GDALDatasetH warped = GDALWarp("", NULL, 1, &src, wo, NULL);
    GDALWarpAppOptionsFree(wo);
    ASSERT_TRUE(warped != NULL);

    tp_ground* g = NULL;
    ASSERT_OK(tp_ground_create(&sc, NULL, &g, NULL));
    tp_rng rng = tp_rng_seed(31);
    int checked = 0;
    double worst = 0.0, sum = 0.0;
    for (int i = 0; i < 4000; ++i) {
        const int c = tp_rng_int(&rng, 1, w - 2), r = tp_rng_int(&rng, 1, h - 2);
        float want;
        ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(warped, 1), GF_Read, c, r, 1, 1, &want, 1, 1,
                                 GDT_Float32, 0, 0) == CE_None);
        double got = NAN;
        ASSERT_OK(tp_ground_height(g, c, r, &got, NULL));
        if (want != want || got != got || want < -1000)
            continue;
        worst = fmax(worst, fabs(got - want));
        sum += fabs(got - want);
        ++checked;
    }
    tp_test_note("N42E001's store (step %g m): %d posts against gdalwarp -r bilinear: mean "
                 "|difference| %.4f m, worst %.4f m",
                 hd->height_step_m, checked, sum / checked, worst);
    EXPECT_GE_INT(checked, 3000);
    EXPECT_LE(worst, hd->height_step_m / 2 + 0.01);
    tp_ground_destroy(g);
    GDALClose(warped);
    GDALClose(src);
    tp_store_scene_close(&sc);
    remove(store);
    rmdir(dir);
}

#define TESTS(X)                                                                                   \
    X(posts_and_corners_equal_gdal)                                                                \
    X(tiny_cache_answers_as_a_large_one)                                                           \
    X(off_the_dem_is_refused_and_output_untouched)                                              \
    X(horn_slope_and_aspect_equal_gdaldem)                                                         \
    X(warped_dem_keeps_its_heights_to_half_its_step)
TP_TEST_MAIN(TESTS)
