/*
 * test_build.c - the mosaic read in bands (tp_mosaic, io/src/mosaic.cpp) and `terrapatch build`
 * (app/scene/store_build.c) on the real DEMs: one DEM gives the single-DEM pipeline's grid and heights;
 * two adjacent SRTM tiles give one seamless grid, the same store as their .vrt; bad sources and
 * signals, a full disk and a memory budget too small leave nothing behind.
 */
#define _GNU_SOURCE
#include "tp_io.h"
#include "tp_test.h"
#include "tp_test_child.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <sys/inotify.h>
#include <sys/resource.h>
#include <time.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define TP_TMP_PREFIX "tp_build_"
#include "tp_test_tmp.h"

static const char* terrapatch(void)
{
    const char* exe = getenv("TP_TERRAPATCH");
    if (!exe || access(exe, X_OK) != 0)
        SKIP("TP_TERRAPATCH not set: the terrapatch binary is not built");
    return exe;
}

/* The whole render grid through the mosaic, band by band (65 rows at a time). */
static float* mosaic_grid(tp_mosaic* m, int* w, int* h)
{
    tp_mosaic_info mi;
    tp_mosaic_get_info(m, &mi);
    *w = mi.width, *h = mi.height;
    float* z = malloc((size_t)mi.width * mi.height * sizeof *z);
    ASSERT_TRUE(z != NULL);
    for (int y = 0; y < mi.height; y += 65) {
        int n = mi.height - y < 65 ? mi.height - y : 65;
        tp_error err = {0};
        ASSERT_EQ_INT(TP_OK, tp_mosaic_read_rows(m, y, n, z + (size_t)y * mi.width,
                                                 (size_t)n * mi.width, &err));
    }
    return z;
}

/* One DEM: the mosaic's grid is tp_render_grid_build's (voids not filled), sample for sample. */
static void check_single(const char* file)
{
    char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", file);
    tp_error err = {0};
    tp_dem* dem = NULL;
    ASSERT_EQ_INT(TP_OK, tp_dem_read(path, &dem, &err));
    tp_render_grid* g = NULL;
    tp_grid_options go = {.fill_max_px = -1};
    ASSERT_EQ_INT(TP_OK, tp_render_grid_build(dem, &go, &g, &err));
    tp_mosaic* m = NULL;
    const char* paths[1] = {path};
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, NULL, &m, &err));
    tp_mosaic_info mi;
    tp_mosaic_get_info(m, &mi);
    ASSERT_EQ_INT(g->width, mi.width);
    ASSERT_EQ_INT(g->height, mi.height);
    for (int i = 0; i < 6; i++)
        EXPECT_NEAR(g->geotransform[i], mi.geotransform[i], 1e-6);
    EXPECT_EQ_INT(g->epsg, mi.epsg);
    EXPECT_EQ_INT(g->warped, mi.warped);
    int w, h;
    float* z = mosaic_grid(m, &w, &h);
    size_t differ = 0, nan_differ = 0, valid = 0;
    double worst = 0;
    for (size_t i = 0; i < (size_t)w * h; i++) {
        float a = g->heights[i], b = z[i];
        if (isnan(a) != isnan(b)) {
            nan_differ++;
            continue;
        }
        if (isnan(a))
            continue;
        valid++;
        if (a != b) {
            differ++;
            worst = fabs(a - b) > worst ? fabs(a - b) : worst;
        }
    }
    EXPECT_TRUE(valid > 0);
    EXPECT_EQ_INT(0, (long long)nan_differ);
    EXPECT_EQ_INT(0, (long long)differ);
    if (differ)
        fprintf(stderr, "%s: %zu samples differ, worst by %g m\n", file, differ, worst);
    free(z);
    tp_mosaic_close(m);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
}

TEST(single_hgt_same_grid_as_render_grid) { check_single("N42E001.hgt"); }
TEST(single_dt1_same_grid_as_render_grid) { check_single("N42E001.dt1"); }
TEST(single_geotiff_same_grid_as_render_grid) { check_single("mt_rainier_90m.tif"); }
TEST(single_utm_nodata_same_grid_as_render_grid) { check_single("lf_elev_220_mt_hood_utm.tif"); }
TEST(single_asc_same_grid_as_render_grid) { check_single("front_range_srtmgl3_144.asc"); }
/* untagged Int16, geographic: its -32767 voids are nodata before the warp on both paths */
TEST(single_untagged_int16_same_grid_as_render_grid)
{
    check_single("craterlake-elev-16bit-30m.tif");
}

/* Two adjacent SRTM tiles: the union, warped to UTM 31N; the shared row reported; no nodata row
 * and no step at the 42N seam. */
TEST(two_tiles_one_seamless_grid)
{
    char a[1024], b[1024];
    REQUIRE_DATA_FILE(a, "TP_SHARED_DATA_DIR", "N41E001.hgt");
    REQUIRE_DATA_FILE(b, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    const char* paths[2] = {a, b};
    tp_error err = {0};
    tp_mosaic* m = NULL;
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 2, NULL, &m, &err));
    tp_mosaic_info mi;
    tp_mosaic_get_info(m, &mi);
    EXPECT_EQ_INT(32631, mi.epsg);
    EXPECT_TRUE(mi.warped);
    EXPECT_TRUE(strstr(mi.notes, "N41E001.hgt and N42E001.hgt overlap by one row") != NULL);
    EXPECT_TRUE(strstr(mi.notes, "SRTM tiles share their edge") != NULL);
    /* 2401 rows of 3" = 2 degrees of latitude, about 222 km; posts of ~68 m at 41-43N */
    const double north_south_m = mi.height * fabs(mi.geotransform[5]);
    EXPECT_TRUE(north_south_m > 221000 && north_south_m < 225000);
    int w, h;
    float* z = mosaic_grid(m, &w, &h);
    /* The row nearest 42N at the grid's middle column: 42N, 1.5E in UTM 31N is N ~ 4650 km. */
    tp_georef* geo = NULL;
    ASSERT_EQ_INT(TP_OK, tp_georef_create(mi.crs_wkt, mi.geotransform, &geo, &err));
    double e, n, x, y;
    ASSERT_EQ_INT(TP_OK, tp_georef_geo_to_proj(geo, 42.0, 1.5, &e, &n, &err));
    tp_georef_proj_to_grid(geo, e, n, &x, &y);
    tp_georef_destroy(geo);
    const int seam = (int)floor(y);
    ASSERT_TRUE(seam > 100 && seam < h - 100);
    /* every row near the seam has many valid samples */
    for (int r = seam - 3; r <= seam + 3; r++) {
        int valid = 0;
        for (int c = 0; c < w; c++)
            valid += !isnan(z[(size_t)r * w + c]);
        EXPECT_TRUE(valid > w / 2);
    }
    /* the largest difference between adjacent rows: at the seam, as inside the tiles */
    double seam_step = 0, inside_step = 0;
    for (int r = 1; r < h; r++) {
        double mx = 0;
        for (int c = 0; c < w; c++) {
            float p = z[(size_t)(r - 1) * w + c], q = z[(size_t)r * w + c];
            if (!isnan(p) && !isnan(q) && fabs(p - q) > mx)
                mx = fabs(p - q);
        }
        if (r >= seam - 2 && r <= seam + 3)
            seam_step = mx > seam_step ? mx : seam_step;
        else if (abs(r - seam) > 50)
            inside_step = mx > inside_step ? mx : inside_step;
    }
    EXPECT_TRUE(inside_step > 0);
    EXPECT_LE(seam_step, inside_step);
    free(z);
    tp_mosaic_close(m);
}

/* Runs `terrapatch build ARGS` with stderr to err_path (may be NULL); returns the exit status. */
static int run_build(const char* args, const char* err_path)
{
    char cmd[4096];
    snprintf(cmd, sizeof cmd, "'%s' build %s 2>'%s' >/dev/null", terrapatch(), args,
             err_path ? err_path : "/dev/null");
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

static char* slurp(const char* path)
{
    FILE* f = fopen(path, "rb");
    if (!f)
        return NULL;
    static char buf[65536];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    buf[n] = 0;
    fclose(f);
    return buf;
}

static int dir_entries(const char* dir)
{
    DIR* d = opendir(dir);
    int n = 0;
    for (struct dirent* e; d && (e = readdir(d));)
        n += strcmp(e->d_name, ".") && strcmp(e->d_name, "..");
    if (d)
        closedir(d);
    return n;
}

/* The two tiles, and a .vrt of them (gdalbuildvrt), give the same store: metas and samples. */
TEST(two_tiles_and_their_vrt_give_the_same_store)
{
    char a[1024], b[1024], args[4096], p1[1024], p2[1024], vrt[1024];
    REQUIRE_DATA_FILE(a, "TP_SHARED_DATA_DIR", "N41E001.hgt");
    REQUIRE_DATA_FILE(b, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    if (system("gdalbuildvrt --version >/dev/null 2>&1") != 0)
        SKIP("gdalbuildvrt (gdal-bin) is not installed");
    const char* dir = make_tmp_dir();
    snprintf(p1, sizeof p1, "%s/tiles.tpt", dir);
    snprintf(p2, sizeof p2, "%s/vrt.tpt", dir);
    snprintf(vrt, sizeof vrt, "%s/tiles.vrt", dir);
    snprintf(args, sizeof args, "gdalbuildvrt -q '%s' '%s' '%s'", vrt, a, b);
    ASSERT_EQ_INT(0, system(args));
    snprintf(args, sizeof args, "'%s' '%s' -o '%s' --patch 33", a, b, p1);
    ASSERT_EQ_INT(0, run_build(args, NULL));
    snprintf(args, sizeof args, "'%s' -o '%s' --patch 33 --threads 1", vrt, p2);
    ASSERT_EQ_INT(0, run_build(args, NULL));
    tp_error err = {0};
    tp_store *s1 = NULL, *s2 = NULL;
    ASSERT_EQ_INT(TP_OK, tp_store_open(p1, &s1, &err));
    ASSERT_EQ_INT(TP_OK, tp_store_open(p2, &s2, &err));
    tp_store_info i1, i2;
    tp_store_get_info(s1, &i1);
    tp_store_get_info(s2, &i2);
    EXPECT_TRUE(strstr(i1.header.notes, "overlap by one row") != NULL);
    ASSERT_EQ_INT(i1.header.geometry.src_width, i2.header.geometry.src_width);
    ASSERT_EQ_INT(i1.header.geometry.src_height, i2.header.geometry.src_height);
    EXPECT_EQ_DBL(i1.header.height_step_m, i2.header.height_step_m);
    size_t c1, c2;
    const tp_node_meta* m1 = tp_store_metas(s1, &c1);
    const tp_node_meta* m2 = tp_store_metas(s2, &c2);
    ASSERT_EQ_INT((long long)c1, (long long)c2);
    EXPECT_TRUE(memcmp(m1, m2, c1 * sizeof *m1) == 0);
    const size_t ns = 33 * 33;
    uint16_t *d1 = malloc(ns * 2), *d2 = malloc(ns * 2);
    size_t differ = 0;
    for (size_t i = 0; i < c1; i++) {
        ASSERT_EQ_INT(TP_OK, tp_store_read_node(s1, (int64_t)i, d1, ns, &err));
        ASSERT_EQ_INT(TP_OK, tp_store_read_node(s2, (int64_t)i, d2, ns, &err));
        differ += memcmp(d1, d2, ns * 2) != 0;
    }
    EXPECT_EQ_INT(0, (long long)differ);
    free(d1), free(d2);
    tp_store_close(s1);
    tp_store_close(s2);
}

/* The store's leaves hold tp_terrain's decoded heights of the same render grid and step, voids
 * filled by the build (--fill-max fill_arg) as tp_render_grid_build fills them (fill_max_px):
 * exactly, since the build's window reaches fill_max + 1 rows beyond each band and
 * GDALFillNodata looks no further than fill_max samples. Returns the nodata samples. */
static size_t check_store_leaves(const char* file, int patch, const char* fill_arg,
                                 int fill_max_px)
{
    char a[1024], args[4096], out[1024];
    REQUIRE_DATA_FILE(a, "TP_SHARED_DATA_DIR", file);
    const char* dir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/leaves.tpt", dir);
    snprintf(args, sizeof args, "'%s' -o '%s' --patch %d %s", a, out, patch, fill_arg);
    ASSERT_EQ_INT(0, run_build(args, NULL));
    tp_error err = {0};
    tp_store* s = NULL;
    ASSERT_EQ_INT(TP_OK, tp_store_open(out, &s, &err));
    tp_store_info si;
    tp_store_get_info(s, &si);
    tp_dem* dem = NULL;
    ASSERT_EQ_INT(TP_OK, tp_dem_read(a, &dem, &err));
    tp_render_grid* g = NULL;
    tp_grid_options go = {.fill_max_px = fill_max_px};
    ASSERT_EQ_INT(TP_OK, tp_render_grid_build(dem, &go, &g, &err));
    /* the notes say how many were filled: the single-DEM path's count */
    char said[128];
    if (g->filled_samples)
        snprintf(said, sizeof said, "(GDALFillNodata): %zu samples", g->filled_samples);
    else
        snprintf(said, sizeof said, "%s", fill_max_px < 0 ? "voids are not filled" : ": 0 samples");
    EXPECT_TRUE(strstr(si.header.notes, said) != NULL);
    if (!strstr(si.header.notes, said))
        fprintf(stderr, "notes: %s\nwanted: %s\n", si.header.notes, said);
    tp_terrain_desc td = tp_render_grid_terrain_desc(g, patch, TP_FIT_PAD);
    td.height_step_m = si.header.height_step_m;
    tp_terrain* t = NULL;
    ASSERT_EQ_INT(TP_OK, tp_terrain_create(&td, &t, &err));
    const tp_tree_geometry* geo = &si.header.geometry;
    size_t count;
    const tp_node_meta* metas = tp_store_metas(s, &count);
    const int ps = patch - 1;
    uint16_t* block = malloc((size_t)patch * patch * sizeof *block);
    ASSERT_TRUE(block != NULL);
    size_t compared = 0, differ = 0, nodata = 0;
    for (int r = 0; r < geo->rows; r++)
        for (int c = 0; c < geo->cols; c++) {
            int64_t id = tp_tree_node_id(geo, 0, c, r);
            ASSERT_EQ_INT(TP_OK, tp_store_read_node(s, id, block, (size_t)patch * patch, &err));
            for (int j = 0; j <= ps; j++)
                for (int i = 0; i <= ps; i++) {
                    uint16_t v = block[j * patch + i];
                    double stored = v == TP_TREE_NO_HEIGHT
                                        ? NAN
                                        : (v + (double)metas[id].qmin) * si.header.height_step_m;
                    double want = tp_terrain_sample(t, c * ps + i, r * ps + j);
                    compared++;
                    if (c * ps + i < g->width && r * ps + j < g->height && isnan(stored))
                        nodata++;
                    if (!(isnan(stored) && isnan(want)) && stored != want)
                        differ++;
                }
        }
    EXPECT_TRUE(compared >= (size_t)g->width * g->height);
    EXPECT_EQ_INT(0, (long long)differ);
    free(block);
    tp_terrain_destroy(t);
    tp_render_grid_destroy(g);
    tp_dem_destroy(dem);
    tp_store_close(s);
    return nodata;
}

TEST(store_leaves_equal_terrain_heights)
{
    check_store_leaves("lf_elev_220_mt_hood_utm.tif", 33, "--fill-max 0", -1);
}

/* SRTM voids: filled by default as the single-DEM path fills them; --fill-max 0 leaves them;
 * a small --fill-max fills the small ones only, larger voids stay nodata. */
TEST(store_voids_filled_as_single_dem)
{
    size_t none = check_store_leaves("N42E001.hgt", 65, "--fill-max 0", -1);
    size_t all = check_store_leaves("N42E001.hgt", 65, "", 0); /* default: any size */
    size_t small = check_store_leaves("N42E001.hgt", 65, "--fill-max 3", 3);
    /* N42E001 has voids, some wider than 3 samples, all on a warped grid's interior */
    EXPECT_TRUE(none > all);
    EXPECT_TRUE(small > all && small < none);
    if (!(small > all && small < none && none > all))
        fprintf(stderr, "nodata: --fill-max 0 %zu, 3 %zu, any %zu\n", none, small, all);
    check_store_leaves("lf_elev_220_mt_hood_utm.tif", 33, "--fill-max 64", 64);
    check_store_leaves("lf_elev_220_mt_hood_utm.tif", 65, "--fill-max 5", 5);
}

/* The mosaic's filled grid, read in bands of 65 rows, is tp_render_grid_build's float for float. */
TEST(mosaic_filled_grid_equals_render_grid)
{
    const char* files[2] = {"N42E001.hgt", "lf_elev_220_mt_hood_utm.tif"};
    for (int f = 0; f < 2; f++) {
        char path[1024];
        REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", files[f]);
        tp_error err = {0};
        tp_dem* dem = NULL;
        ASSERT_EQ_INT(TP_OK, tp_dem_read(path, &dem, &err));
        tp_render_grid* g = NULL;
        tp_grid_options go = {.fill_max_px = 64};
        ASSERT_EQ_INT(TP_OK, tp_render_grid_build(dem, &go, &g, &err));
        tp_mosaic* m = NULL;
        const char* paths[1] = {path};
        tp_mosaic_options mo = {.fill_max = 64};
        ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, &mo, &m, &err));
        int w, h;
        float* z = mosaic_grid(m, &w, &h);
        ASSERT_EQ_INT(g->width, w);
        ASSERT_EQ_INT(g->height, h);
        size_t differ = 0;
        for (size_t i = 0; i < (size_t)w * h; i++)
            differ += !(isnan(z[i]) && isnan(g->heights[i])) && z[i] != g->heights[i];
        EXPECT_EQ_INT(0, (long long)differ);
        EXPECT_EQ_INT((long long)g->filled_samples, (long long)tp_mosaic_filled_samples(m));
        if (f == 0)
            EXPECT_TRUE(g->filled_samples > 1000); /* the test sees voids */
        free(z);
        tp_mosaic_close(m);
        tp_render_grid_destroy(g);
        tp_dem_destroy(dem);
    }
}

/* Sources in different CRSs (geographic + UTM) are warped onto one grid, and said so. */
TEST(different_crs_warped_and_reported)
{
    char a[1024], b[1024], args[4096], out[1024], errp[1024];
    REQUIRE_DATA_FILE(a, "TP_SHARED_DATA_DIR", "mt_rainier_90m.tif");
    REQUIRE_DATA_FILE(b, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    const char* dir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/mixed.tpt", dir);
    snprintf(errp, sizeof errp, "%s/err.txt", dir);
    snprintf(args, sizeof args, "'%s' '%s' -o '%s' --patch 33", a, b, out);
    ASSERT_EQ_INT(0, run_build(args, errp));
    const char* e = slurp(errp);
    ASSERT_TRUE(e != NULL);
    EXPECT_TRUE(strstr(e, "differ in CRS or post spacing") != NULL);
    EXPECT_TRUE(strstr(e, "mt_rainier_90m.tif: WGS 84") != NULL);
    EXPECT_TRUE(strstr(e, "warped onto") != NULL);
    struct stat st;
    EXPECT_TRUE(stat(out, &st) == 0 && st.st_size > 1000);
}

/* Missing, not-a-raster and FIFO sources: exit 1 naming the file, nothing written. */
TEST(bad_sources_exit_1_and_write_nothing)
{
    char a[1024], args[4096], out[1024], errp[1024], bad[1024], fifo[1024];
    REQUIRE_DATA_FILE(a, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    const char* dir = make_tmp_dir();
    const char* odir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/x.tpt", odir);
    snprintf(errp, sizeof errp, "%s/err.txt", dir);
    snprintf(bad, sizeof bad, "%s/notes.txt", dir);
    FILE* f = fopen(bad, "w");
    ASSERT_TRUE(f != NULL);
    fputs("not a raster\n", f);
    fclose(f);
    snprintf(fifo, sizeof fifo, "%s/pipe.hgt", dir);
    ASSERT_EQ_INT(0, mkfifo(fifo, 0600));
    const char* cases[3][2] = {{"/nonexistent-dir/no_such_tile.hgt", "no_such_tile.hgt"},
                               {bad, "notes.txt: not a raster"},
                               {fifo, "pipe.hgt: cannot open: it is a FIFO"}};
    for (int i = 0; i < 3; i++) {
        snprintf(args, sizeof args, "'%s' '%s' -o '%s'", a, cases[i][0], out);
        EXPECT_EQ_INT(1, run_build(args, errp));
        const char* e = slurp(errp);
        EXPECT_TRUE(e && strstr(e, cases[i][1]) != NULL);
        EXPECT_EQ_INT(0, dir_entries(odir));
    }
}

/* An output folder that cannot be written: a clear error before any work. */
TEST(unwritable_output_folder_fails_first)
{
    char a[1024], args[4096], errp[1024];
    REQUIRE_DATA_FILE(a, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    const char* dir = make_tmp_dir();
    snprintf(errp, sizeof errp, "%s/err.txt", dir);
    /* a missing source too: the output is checked before the sources are opened */
    snprintf(args, sizeof args, "/nonexistent-src.hgt -o /nonexistent-dir/x.tpt");
    EXPECT_EQ_INT(1, run_build(args, errp));
    const char* e = slurp(errp);
    EXPECT_TRUE(e && strstr(e, "/nonexistent-dir/x.tpt") != NULL);
    EXPECT_TRUE(e && strstr(e, "nonexistent-src") == NULL);
}

/* --json: the keys, with sane values. */
TEST(json_keys_present_and_sane)
{
    char a[1024], args[4096], out[1024], js[1024];
    REQUIRE_DATA_FILE(a, "TP_SHARED_DATA_DIR", "storml_elev.tif");
    const char* dir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/s.tpt", dir);
    snprintf(js, sizeof js, "%s/s.json", dir);
    snprintf(args, sizeof args, "'%s' -o '%s' --patch 17 --json '%s' --quiet", a, out, js);
    ASSERT_EQ_INT(0, run_build(args, NULL));
    const char* j = slurp(js);
    ASSERT_TRUE(j != NULL);
    const char* keys[] = {"\"samples\": 15301", "\"nodes\": ", "\"bytes\": ",
                          "\"bytes_per_sample\": ", "\"seconds\": ", "\"rss_peak_mb\": ",
                          "\"width\": 143", "\"height\": 107", "\"patch_size\": 17", "\"step\": "};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; i++)
        EXPECT_TRUE(strstr(j, keys[i]) != NULL);
    struct stat st;
    ASSERT_TRUE(stat(out, &st) == 0);
    char want[64];
    snprintf(want, sizeof want, "\"bytes\": %lld", (long long)st.st_size);
    EXPECT_TRUE(strstr(j, want) != NULL);
    const char* r = strstr(j, "\"rss_peak_mb\": ");
    EXPECT_TRUE(r && atof(r + 15) > 1 && atof(r + 15) < 1024);
}

/* A VRT whose second source is scaled (ComplexSource ScaleRatio 7.3, ScaleOffset 1000.5) breaks
 * the bound the mosaic takes from its files' min/max (storml_elev.tif, ~1.4 .. 2 km): the build
 * sees heights outside it, says so, builds again after a range pass, and the store has the step
 * of the true range and the header totals of the grid as read (valid samples, nodata, the
 * quantisation error: counted while building, given at commit). */
TEST(vrt_scaling_beyond_its_files_bound_builds_again_right)
{
    char t[1024], vrt[1024], out[1024], errp[1024], args[4096];
    REQUIRE_DATA_FILE(t, "TP_SHARED_DATA_DIR", "storml_elev.tif");
    const char* dir = make_tmp_dir();
    snprintf(vrt, sizeof vrt, "%s/scaled.vrt", dir);
    snprintf(out, sizeof out, "%s/scaled.tpt", dir);
    snprintf(errp, sizeof errp, "%s/err.txt", dir);
    FILE* f = fopen(vrt, "w");
    ASSERT_TRUE(f != NULL);
    fprintf(f,
            "<VRTDataset rasterXSize=\"286\" rasterYSize=\"107\">\n"
            "  <SRS>EPSG:26912</SRS>\n"
            "  <GeoTransform>323476.071970862976741, 30, 0, 5105081.98303137999028, 0, "
            "-30</GeoTransform>\n"
            "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n"
            "    <NoDataValue>-99999</NoDataValue>\n");
    for (int i = 0; i < 2; i++)
        fprintf(f,
                "    <ComplexSource>\n"
                "      <SourceFilename relativeToVRT=\"0\">%s</SourceFilename>\n"
                "      <SourceBand>1</SourceBand>\n"
                "      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"143\" ySize=\"107\"/>\n"
                "      <DstRect xOff=\"%d\" yOff=\"0\" xSize=\"143\" ySize=\"107\"/>\n"
                "      <NODATA>32767</NODATA>\n%s"
                "    </ComplexSource>\n",
                t, 143 * i, i ? "      <ScaleOffset>1000.5</ScaleOffset>\n"
                                "      <ScaleRatio>7.3</ScaleRatio>\n" : "");
    fprintf(f, "  </VRTRasterBand>\n</VRTDataset>\n");
    fclose(f);

    /* the grid as the mosaic reads it, and the bound it gives beforehand */
    const char* paths[1] = {vrt};
    tp_error err = {0};
    tp_mosaic* m = NULL;
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, NULL, &m, &err));
    tp_mosaic_info mi;
    tp_mosaic_get_info(m, &mi);
    EXPECT_EQ_INT(0, mi.warped);
    EXPECT_EQ_INT(1, mi.has_range); /* the tif's min/max: 15301 samples, half the grid */
    int w, h;
    float* z = mosaic_grid(m, &w, &h);
    double lo = INFINITY, hi = -INFINITY;
    size_t valid = 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        if (!isnan(z[i])) {
            valid++;
            lo = z[i] < lo ? z[i] : lo;
            hi = z[i] > hi ? z[i] : hi;
        }
    ASSERT_TRUE(valid > 0);
    EXPECT_TRUE(hi > mi.max_m + 1000); /* the bound does not hold */
    tp_mosaic_close(m);

    snprintf(args, sizeof args, "'%s' -o '%s' --patch 17", vrt, out);
    ASSERT_EQ_INT(0, run_build(args, errp));
    const char* e = slurp(errp);
    EXPECT_TRUE(e && strstr(e, "outside the bound") != NULL);
    tp_store* st = NULL;
    ASSERT_EQ_INT(TP_OK, tp_store_open(out, &st, &err));
    tp_store_info info;
    tp_store_get_info(st, &info);
    /* the finest 2^-p m whose quantised true range fits 65534 steps */
    double want = 1;
    for (int p = 10; p >= 0; p--) {
        double sp = ldexp(1.0, -p);
        if (floor(hi / sp + 0.5) - floor(lo / sp + 0.5) <= 65534) {
            want = sp;
            break;
        }
    }
    EXPECT_EQ_DBL(want, info.header.height_step_m);
    EXPECT_EQ_INT((long long)valid, (long long)info.header.valid_samples);
    EXPECT_EQ_INT((long long)((size_t)w * h - valid), (long long)info.header.nodata_samples);
    double qerr = 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        if (!isnan(z[i])) {
            double e2 = fabs(floor(z[i] / want + 0.5) * want - z[i]);
            qerr = e2 > qerr ? e2 : qerr;
        }
    EXPECT_TRUE(qerr > 0);
    EXPECT_EQ_DBL(qerr, info.header.quant_max_error_m);
    /* the nodes' range is the grid's */
    size_t count;
    const tp_node_meta* metas = tp_store_metas(st, &count);
    int32_t qlo = INT32_MAX, qhi = INT32_MIN;
    for (size_t i = 0; i < count; i++)
        if (metas[i].flags & TP_NODE_HAS_DRAWN) {
            qlo = metas[i].area_qmin < qlo ? metas[i].area_qmin : qlo;
            qhi = metas[i].area_qmax > qhi ? metas[i].area_qmax : qhi;
        }
    EXPECT_EQ_INT((long long)floor(lo / want + 0.5), qlo);
    EXPECT_EQ_INT((long long)floor(hi / want + 0.5), qhi);
    tp_store_close(st);
    free(z);
}

/* A VRT whose only source lies outside its grid: the files' min/max bound the heights (so no
 * range pass), but the grid has none: exit 1, "no valid height", no store left. */
TEST(bounded_grid_without_any_height_writes_nothing)
{
    char t[1024], vrt[1024], out[1024], errp[1024], args[4096];
    REQUIRE_DATA_FILE(t, "TP_SHARED_DATA_DIR", "storml_elev.tif");
    const char* dir = make_tmp_dir();
    const char* odir = make_tmp_dir();
    snprintf(vrt, sizeof vrt, "%s/empty.vrt", dir);
    snprintf(out, sizeof out, "%s/empty.tpt", odir);
    snprintf(errp, sizeof errp, "%s/err.txt", dir);
    FILE* f = fopen(vrt, "w");
    ASSERT_TRUE(f != NULL);
    fprintf(f,
            "<VRTDataset rasterXSize=\"300\" rasterYSize=\"300\">\n"
            "  <SRS>EPSG:26912</SRS>\n"
            "  <GeoTransform>323476.0, 30, 0, 5105082.0, 0, -30</GeoTransform>\n"
            "  <VRTRasterBand dataType=\"Float32\" band=\"1\">\n"
            "    <NoDataValue>-99999</NoDataValue>\n"
            "    <ComplexSource>\n"
            "      <SourceFilename relativeToVRT=\"0\">%s</SourceFilename>\n"
            "      <SourceBand>1</SourceBand>\n"
            "      <SrcRect xOff=\"0\" yOff=\"0\" xSize=\"143\" ySize=\"107\"/>\n"
            "      <DstRect xOff=\"1000\" yOff=\"0\" xSize=\"143\" ySize=\"107\"/>\n"
            "      <NODATA>32767</NODATA>\n"
            "    </ComplexSource>\n"
            "  </VRTRasterBand>\n</VRTDataset>\n",
            t);
    fclose(f);
    const char* paths[1] = {vrt};
    tp_error err = {0};
    tp_mosaic* m = NULL;
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, NULL, &m, &err));
    tp_mosaic_info mi;
    tp_mosaic_get_info(m, &mi);
    EXPECT_EQ_INT(1, mi.has_range); /* the case under test: no range pass */
    tp_mosaic_close(m);
    snprintf(args, sizeof args, "'%s' -o '%s' --patch 17", vrt, out);
    EXPECT_EQ_INT(1, run_build(args, errp));
    const char* e = slurp(errp);
    EXPECT_TRUE(e && strstr(e, "no valid height in the 300x300 grid") != NULL);
    EXPECT_EQ_INT(0, dir_entries(odir));
}

/* ---------------------------------------------------------------------------------------------
 * Faults: signals, a full disk, a budget too small
 */

/* Starts `terrapatch build args...` (NULL-terminated) with stderr to err_path, SIGINT/SIGTERM
 * at their defaults and, if fsize_limit, a "full disk" (RLIMIT_FSIZE, SIGXFSZ ignored: write()
 * fails with EFBIG as on ENOSPC, as tests/test_writes.c does). */
static pid_t start_build(const char* const* args, rlim_t fsize_limit, const char* err_path)
{
    const char* exe = terrapatch();
    const char* argv[64];
    int n = 0;
    argv[n++] = exe;
    argv[n++] = "build";
    for (int i = 0; args[i] && n < 62; i++)
        argv[n++] = args[i];
    argv[n] = NULL;
    static char asan[512];
    char** envp = tp_test_child_environment(asan, sizeof asan);
    fflush(NULL);
    pid_t pid = fork();
    ASSERT_TRUE(pid >= 0);
    if (pid == 0) {
        int null = open("/dev/null", O_RDWR);
        int err = open(err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
        if (null < 0 || err < 0)
            _exit(98);
        dup2(null, 0);
        dup2(null, 1);
        dup2(err, 2);
        signal(SIGINT, SIG_DFL);
        signal(SIGTERM, SIG_DFL);
        if (fsize_limit) {
            struct rlimit rl = {fsize_limit, fsize_limit};
            signal(SIGXFSZ, SIG_IGN);
            if (setrlimit(RLIMIT_FSIZE, &rl) != 0)
                _exit(97);
        }
        execve(exe, (char* const*)argv, envp);
        _exit(96);
    }
    return pid;
}

/* The exit status; 128 + the signal for a child a signal killed (as a shell says). */
static int finish_child(pid_t pid)
{
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            FAIL("waitpid: %s", strerror(errno));
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/* Waits (up to 120 s) until a name holding ".tmp" is created in the folder inotify fd watches:
 * 1; 0 if the child exited first or time ran out. */
static int wait_for_temp(int fd, pid_t child)
{
    char buf[4096] __attribute__((aligned(__alignof__(struct inotify_event))));
    for (int waited_ms = 0; waited_ms < 120000; waited_ms += 50) {
        struct pollfd p = {.fd = fd, .events = POLLIN};
        if (poll(&p, 1, 50) > 0) {
            ssize_t n = read(fd, buf, sizeof buf);
            for (char* q = buf; n > 0 && q < buf + n;) {
                struct inotify_event* ev = (struct inotify_event*)q;
                if ((ev->mask & IN_CREATE) && ev->len && strstr(ev->name, ".tmp"))
                    return 1;
                q += sizeof *ev + ev->len;
            }
        }
        siginfo_t info = {0};
        if (waitid(P_PID, (id_t)child, &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid)
            return 0;
    }
    return 0;
}

/* The names in dir, sorted, each followed by one space. */
static void names_in(const char* dir, char* out, size_t cap)
{
    struct dirent** list = NULL;
    int n = scandir(dir, &list, NULL, alphasort);
    ASSERT_TRUE(n >= 0);
    out[0] = 0;
    for (int i = 0; i < n; i++) {
        if (strcmp(list[i]->d_name, ".") && strcmp(list[i]->d_name, ".."))
            snprintf(out + strlen(out), cap - strlen(out), "%s ", list[i]->d_name);
        free(list[i]);
    }
    free(list);
}

static void put_text(const char* path, const char* text)
{
    FILE* f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    fputs(text, f);
    fclose(f);
}

/* A build of the two SRTM tiles (a range pass, then some seconds of building) gets sig as soon
 * as its temporary file appears: it must stop (exit 128 + sig, "interrupted"), leave no store
 * and no temporary file, and an older store at the path as it was. A build that ignored the
 * signal would finish: exit 0 and the old file replaced. */
static void build_killed(int sig)
{
    char a[1024], b[1024], out[1024], errp[1024], list[1024];
    REQUIRE_DATA_FILE(a, "TP_SHARED_DATA_DIR", "N41E001.hgt");
    REQUIRE_DATA_FILE(b, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    const char* dir = make_tmp_dir();
    const char* edir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/tiles.tpt", dir);
    snprintf(errp, sizeof errp, "%s/err.txt", edir);
    const char old[] = "an older store\n";
    put_text(out, old);
    int fd = inotify_init1(IN_CLOEXEC);
    ASSERT_TRUE(fd >= 0);
    ASSERT_TRUE(inotify_add_watch(fd, dir, IN_CREATE) >= 0);
    const char* args[] = {a, b, "-o", out, "--patch", "17", "--threads", "2", NULL};
    pid_t pid = start_build(args, 0, errp);
    int seen = wait_for_temp(fd, pid);
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    if (seen)
        kill(pid, sig);
    close(fd);
    int rc = finish_child(pid);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    ASSERT_TRUE(seen); /* else the build never wrote a temporary file */
    const char* e = slurp(errp);
    EXPECT_EQ_INT(128 + sig, rc);
    EXPECT_TRUE(e && strstr(e, "interrupted") != NULL);
    if (e && !strstr(e, "interrupted"))
        fprintf(stderr, "stderr: %s\n", e);
    const char* now = slurp(out);
    EXPECT_TRUE(now && !strcmp(now, old)); /* the older store, as it was */
    names_in(dir, list, sizeof list);
    EXPECT_EQ_STR("tiles.tpt ", list); /* no temporary file */
    /* it stopped at once (the next band), not after building everything */
    double waited = (t1.tv_sec - t0.tv_sec) + (t1.tv_nsec - t0.tv_nsec) * 1e-9;
    EXPECT_TRUE(waited < 10);
}

TEST(sigterm_during_build_leaves_nothing) { build_killed(SIGTERM); }
TEST(sigint_during_build_leaves_nothing) { build_killed(SIGINT); }

/* A disk that takes 256 KiB (the store is about 2.5 MB): exit 1, the reason named, no store, no
 * temporary file, an older store as it was. */
TEST(full_disk_exit_1_and_leaves_nothing)
{
    char a[1024], out[1024], errp[1024], list[1024];
    REQUIRE_DATA_FILE(a, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    const char* dir = make_tmp_dir();
    const char* edir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/tile.tpt", dir);
    snprintf(errp, sizeof errp, "%s/err.txt", edir);
    const char old[] = "an older store\n";
    put_text(out, old);
    const char* args[] = {a, "-o", out, "--quiet", NULL};
    EXPECT_EQ_INT(1, finish_child(start_build(args, 256 * 1024, errp)));
    const char* e = slurp(errp);
    EXPECT_TRUE(e && strstr(e, "tile.tpt: cannot write: File too large") != NULL);
    if (e && !strstr(e, "File too large"))
        fprintf(stderr, "stderr: %s\n", e);
    const char* now = slurp(out);
    EXPECT_TRUE(now && !strcmp(now, old));
    names_in(dir, list, sizeof list);
    EXPECT_EQ_STR("tile.tpt ", list);
    /* the same build with room: it fits (the failure above was the disk) */
    EXPECT_EQ_INT(0, finish_child(start_build(args, 0, errp)));
    struct stat st;
    EXPECT_TRUE(stat(out, &st) == 0 && st.st_size > 256 * 1024);
}

/* A 40000 x 40000 grid (a VRT with one small UTM tile in it, the rest nodata) with --memory 64:
 * one band, the builder and the node table do not fit three quarters of 64 MB, so the build
 * refuses before reading anything, saying what would do; with enough memory the same grid
 * gets past that check (it is then interrupted: building 1.6 billion nodata samples is not the
 * point). */
TEST(memory_too_small_for_one_band_fails_up_front)
{
    char t[1024], vrt[1024], out[1024], errp[1024], cmd[4096], list[1024];
    REQUIRE_DATA_FILE(t, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    if (system("gdalbuildvrt --version >/dev/null 2>&1") != 0)
        SKIP("gdalbuildvrt (gdal-bin) is not installed");
    const char* dir = make_tmp_dir();
    const char* odir = make_tmp_dir();
    snprintf(vrt, sizeof vrt, "%s/big.vrt", dir);
    snprintf(out, sizeof out, "%s/big.tpt", odir);
    snprintf(errp, sizeof errp, "%s/err.txt", dir);
    /* the tile's corner is near (590000, 5020000) in UTM 10N; 1 m posts, 40 km square */
    snprintf(cmd, sizeof cmd,
             "gdalbuildvrt -q -tr 1 1 -te 560000 4990000 600000 5030000 '%s' '%s'", vrt, t);
    ASSERT_EQ_INT(0, system(cmd));
    const char* args[] = {vrt, "-o", out, "--memory", "64", NULL};
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    EXPECT_EQ_INT(1, finish_child(start_build(args, 0, errp)));
    clock_gettime(CLOCK_MONOTONIC, &t1);
    const char* e = slurp(errp);
    EXPECT_TRUE(e && strstr(e, "--memory 64 MB is too small for a 40000x40000 grid") != NULL);
    EXPECT_TRUE(e && strstr(e, "give --memory ") != NULL);
    if (e && !strstr(e, "too small"))
        fprintf(stderr, "stderr: %s\n", e);
    names_in(odir, list, sizeof list);
    EXPECT_EQ_STR("", list);
    EXPECT_TRUE((t1.tv_sec - t0.tv_sec) < 20); /* up front, not after reading 6 GB */
    /* the figure it gives is enough: the build starts (its temporary file appears) */
    int need = e && strstr(e, "give --memory ") ? atoi(strstr(e, "give --memory ") + 14) : 0;
    ASSERT_TRUE(need > 64);
    char mem[32];
    snprintf(mem, sizeof mem, "%d", need);
    const char* enough[] = {vrt, "-o", out, "--memory", mem, "--quiet", NULL};
    int fd = inotify_init1(IN_CLOEXEC);
    ASSERT_TRUE(fd >= 0);
    ASSERT_TRUE(inotify_add_watch(fd, odir, IN_CREATE) >= 0);
    pid_t pid = start_build(enough, 0, errp);
    int seen = wait_for_temp(fd, pid);
    kill(pid, SIGTERM);
    close(fd);
    EXPECT_EQ_INT(128 + SIGTERM, finish_child(pid));
    EXPECT_TRUE(seen);
    names_in(odir, list, sizeof list);
    EXPECT_EQ_STR("", list);
}

/* With --fill-max 0 a 60000 x 40000 grid (the same kind of VRT) does not fit --memory 64 in
 * 65-sample nodes but fits in 17-sample ones, in less than 64 MB: the message used to suggest
 * "--memory 27 with --patch 17", which --memory refuses. Every --memory it names is one the
 * option accepts (64 or more), and the suggested node size is given with it. */
TEST(memory_suggestions_are_never_below_the_options_floor)
{
    char t[1024], vrt[1024], out[1024], errp[1024], cmd[4096], list[1024];
    REQUIRE_DATA_FILE(t, "TP_SHARED_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    if (system("gdalbuildvrt --version >/dev/null 2>&1") != 0)
        SKIP("gdalbuildvrt (gdal-bin) is not installed");
    const char* dir = make_tmp_dir();
    const char* odir = make_tmp_dir();
    snprintf(vrt, sizeof vrt, "%s/wide.vrt", dir);
    snprintf(out, sizeof out, "%s/wide.tpt", odir);
    snprintf(errp, sizeof errp, "%s/err.txt", dir);
    snprintf(cmd, sizeof cmd,
             "gdalbuildvrt -q -tr 1 1 -te 560000 4990000 620000 5030000 '%s' '%s'", vrt, t);
    ASSERT_EQ_INT(0, system(cmd));
    const char* args[] = {vrt, "-o", out, "--memory", "64", "--fill-max", "0", NULL};
    EXPECT_EQ_INT(1, finish_child(start_build(args, 0, errp)));
    const char* e = slurp(errp);
    ASSERT_TRUE(e != NULL);
    if (!strstr(e, "too small"))
        fprintf(stderr, "stderr: %s\n", e);
    EXPECT_TRUE(strstr(e, "--memory 64 MB is too small for a 60000x40000 grid in 65x65") != NULL);
    EXPECT_TRUE(strstr(e, " with --patch 17)") != NULL); /* smaller nodes need least here */
    int suggestions = 0;
    for (const char* p = strstr(e, "--memory "); p; p = strstr(p + 1, "--memory ")) {
        int mb = atoi(p + 9);
        tp_test_note("suggests --memory %d", mb);
        EXPECT_GE_INT(mb, 64);
        suggestions++;
    }
    EXPECT_EQ_INT(3, suggestions); /* the one given, "give --memory N", the alternative */
    names_in(odir, list, sizeof list);
    EXPECT_EQ_STR("", list);
}

/* A preview's grid (tp_mosaic_options.coarsen, issue 32 item 4): the same CRS and extent, posts
 * f times apart, the same share of it drawn as the grid's (the hull's mask was once taken from
 * the decimated source's size and drew a sixteenth of it), for a warped SRTM tile, an untagged
 * Int16 one and a grid in metres that needs no warp. */
static void check_coarse(const char* file, int f)
{
    char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", file);
    const char* paths[1] = {path};
    tp_error err = {0};
    tp_mosaic *fine = NULL, *coarse = NULL;
    tp_mosaic_options fo = {.fill_max = 0}, co = {.fill_max = 0, .coarsen = f};
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, &fo, &fine, &err));
    ASSERT_EQ_INT(TP_OK, tp_mosaic_open(paths, 1, &co, &coarse, &err));
    tp_mosaic_info a, b;
    tp_mosaic_get_info(fine, &a);
    tp_mosaic_get_info(coarse, &b);
    EXPECT_EQ_INT(a.epsg, b.epsg);
    EXPECT_EQ_STR(a.crs_wkt, b.crs_wkt);
    EXPECT_NEAR(f * a.spacing_m, b.spacing_m, 1e-6 * b.spacing_m);
    EXPECT_TRUE(abs(b.width - (a.width + f - 1) / f) <= 2);
    EXPECT_TRUE(abs(b.height - (a.height + f - 1) / f) <= 2);
    EXPECT_NEAR(a.geotransform[0], b.geotransform[0], 2 * b.spacing_m);
    EXPECT_NEAR(a.geotransform[3], b.geotransform[3], 2 * b.spacing_m);
    EXPECT_TRUE(strstr(b.notes, "a preview: posts") != NULL);
    int w, h, cw, ch;
    float* z = mosaic_grid(fine, &w, &h);
    float* c = mosaic_grid(coarse, &cw, &ch);
    size_t valid = 0, cvalid = 0;
    for (size_t i = 0; i < (size_t)w * h; i++)
        valid += !isnan(z[i]);
    for (size_t i = 0; i < (size_t)cw * ch; i++)
        cvalid += !isnan(c[i]);
    const double share = (double)valid / ((double)w * h);
    const double cshare = (double)cvalid / ((double)cw * ch);
    fprintf(stderr, "%s: coarsened %d: %dx%d -> %dx%d, drawn %.4f -> %.4f\n", file, f, w, h, cw,
            ch, share, cshare);
    EXPECT_NEAR(share, cshare, 0.03);
    free(z);
    free(c);
    tp_mosaic_close(coarse);
    tp_mosaic_close(fine);
}

TEST(preview_grid_is_coarser_over_the_same_ground)
{
    check_coarse("N42E001.hgt", 4);
    check_coarse("craterlake-elev-16bit-30m.tif", 2);
    check_coarse("lf_elev_220_mt_hood_utm.tif", 4);
}

#define TESTS(X)                                                                                   \
    X(single_hgt_same_grid_as_render_grid)                                                         \
    X(single_dt1_same_grid_as_render_grid)                                                         \
    X(single_geotiff_same_grid_as_render_grid)                                                     \
    X(single_utm_nodata_same_grid_as_render_grid)                                                  \
    X(single_asc_same_grid_as_render_grid)                                                         \
    X(single_untagged_int16_same_grid_as_render_grid)                                              \
    X(two_tiles_one_seamless_grid)                                                                 \
    X(two_tiles_and_their_vrt_give_the_same_store)                                                 \
    X(store_leaves_equal_terrain_heights)                                                          \
    X(store_voids_filled_as_single_dem)                                                            \
    X(mosaic_filled_grid_equals_render_grid)                                                       \
    X(different_crs_warped_and_reported)                                                           \
    X(bad_sources_exit_1_and_write_nothing)                                                        \
    X(unwritable_output_folder_fails_first)                                                        \
    X(json_keys_present_and_sane)                                                                  \
    X(vrt_scaling_beyond_its_files_bound_builds_again_right)                                       \
    X(bounded_grid_without_any_height_writes_nothing)                                              \
    X(sigterm_during_build_leaves_nothing)                                                         \
    X(sigint_during_build_leaves_nothing)                                                          \
    X(full_disk_exit_1_and_leaves_nothing)                                                         \
    X(memory_too_small_for_one_band_fails_up_front)                                                \
    X(memory_suggestions_are_never_below_the_options_floor)                                        \
    X(preview_grid_is_coarser_over_the_same_ground)
TP_TEST_MAIN(TESTS)
