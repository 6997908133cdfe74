/*
 * test_ground.c - full-resolution ground queries (app/scene/ground.c) on a store built from a real DEM
 * (Mt Hood, NAD83 / UTM 10N: the store keeps the DEM's grid and its Int16 heights exactly):
 * heights at posts (corners included) against GDAL's own reading of the DEM; a cache of 4 leaves
 * answers exactly as a large one while reading more; positions off the DEM are refused with the
 * output left alone.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"
#include "tp_io.h"

#include "tp_test_child.h"

#include "ground.h"
#include "store_scene.h"

#include <gdal.h>

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

#define TESTS(X)                                                                                   \
    X(posts_and_corners_equal_gdal)                                                                \
    X(tiny_cache_answers_as_a_large_one)                                                           \
    X(off_the_dem_is_refused_and_output_untouched)
TP_TEST_MAIN(TESTS)
