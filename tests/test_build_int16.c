/*
 * test_build_int16.c - `terrapatch build` (io/src/mosaic.cpp) on Int16 rasters without a nodata
 * tag: both -32768 (SRTM) and -32767 (DTED) are voids on every path of the mosaic, as
 * tp_dem_read takes them. craterlake-elev-16bit-30m.tif (EPSG:4326, warped; 39489 samples of
 * -32767): the store's heights lie within the file's TIFFTAG_MIN/MAXSAMPLEVALUE and its nodata
 * are tp_render_grid_build's, sample for sample. Synthetic GeoTIFFs written here with GDAL (a
 * smooth surface of the geographic position, voids of both values in blocks, a border strip and
 * single samples): projected (no warp) and geographic (warped), alone, as two-tile mosaics, in
 * two CRSs at once, and as the --fill-from source (of the build and of tp_render_grid_build):
 * no sample outside the surface's range, and
 * the void blocks are nodata. And --crs leaves the sources' folder as it was.
 */
#define _GNU_SOURCE
#include "tp_io.h"
#include "tp_test.h"

#include <cpl_conv.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#define TP_TMP_PREFIX "tp_int16_"
#include "tp_test_tmp.h"

static const char* terrapatch(void)
{
    const char* exe = getenv("TP_TERRAPATCH");
    if (!exe || access(exe, X_OK) != 0)
        SKIP("TP_TERRAPATCH not set: the terrapatch binary is not built");
    return exe;
}

static int run_build(const char* args)
{
    char cmd[8192];
    snprintf(cmd, sizeof cmd, "'%s' build --quiet %s >/dev/null 2>&1", terrapatch(), args);
    int st = system(cmd);
    return WIFEXITED(st) ? WEXITSTATUS(st) : 128 + WTERMSIG(st);
}

/* A store's leaves as its render grid (src_width x src_height, NaN = nodata). */
typedef struct grid {
    int w, h;
    double gt[6], step;
    char wkt[8192], notes[4096];
    size_t nodata_header;
    float* z;
} grid;

static void read_store(const char* path, grid* g)
{
    tp_error err = {0};
    tp_store* s = NULL;
    ASSERT_EQ_INT(TP_OK, tp_store_open(path, &s, &err));
    tp_store_info si;
    tp_store_get_info(s, &si);
    const tp_tree_geometry* geo = &si.header.geometry;
    g->w = geo->src_width, g->h = geo->src_height;
    memcpy(g->gt, si.header.geotransform, sizeof g->gt);
    g->step = si.header.height_step_m;
    snprintf(g->wkt, sizeof g->wkt, "%s", si.header.crs_wkt);
    snprintf(g->notes, sizeof g->notes, "%s", si.header.notes);
    g->nodata_header = si.header.nodata_samples;
    g->z = malloc((size_t)g->w * g->h * sizeof *g->z);
    ASSERT_TRUE(g->z != NULL);
    const int patch = (1 << geo->n) + 1, ps = patch - 1;
    size_t count;
    const tp_node_meta* metas = tp_store_metas(s, &count);
    uint16_t* block = malloc((size_t)patch * patch * sizeof *block);
    ASSERT_TRUE(block != NULL);
    for (int r = 0; r < geo->rows; r++)
        for (int c = 0; c < geo->cols; c++) {
            int64_t id = tp_tree_node_id(geo, 0, c, r);
            ASSERT_EQ_INT(TP_OK, tp_store_read_node(s, id, block, (size_t)patch * patch, &err));
            for (int j = 0; j <= ps; j++)
                for (int i = 0; i <= ps; i++) {
                    const int x = c * ps + i, y = r * ps + j;
                    if (x >= g->w || y >= g->h)
                        continue;
                    uint16_t v = block[j * patch + i];
                    g->z[(size_t)y * g->w + x] =
                        v == TP_TREE_NO_HEIGHT ? NAN
                                               : (float)((v + (double)metas[id].qmin) * g->step);
                }
        }
    free(block);
    tp_store_close(s);
}

static size_t nan_count(const float* z, size_t n)
{
    size_t k = 0;
    for (size_t i = 0; i < n; i++)
        k += isnan(z[i]) != 0;
    return k;
}

/* Every valid sample of g within lo .. hi (and at least one): the count outside. */
static size_t outside(const grid* g, double lo, double hi, double* got_lo, double* got_hi)
{
    size_t out = 0, valid = 0;
    *got_lo = INFINITY, *got_hi = -INFINITY;
    for (size_t i = 0; i < (size_t)g->w * g->h; i++) {
        const float v = g->z[i];
        if (isnan(v))
            continue;
        valid++;
        out += v < lo || v > hi;
        *got_lo = v < *got_lo ? v : *got_lo;
        *got_hi = v > *got_hi ? v : *got_hi;
    }
    EXPECT_TRUE(valid > 0);
    return out;
}

/* craterlake: heights within the file's own TIFFTAG_MIN/MAXSAMPLEVALUE (1289 .. 1880); its
 * nodata those of tp_dem_read + tp_render_grid_build on the same grid (voids not filled on
 * either side), position for position; the note says both values. */
TEST(craterlake_heights_in_range_and_voids_as_dem_reader)
{
    char path[1024], args[4096], out[1024];
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif");
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    const char* mn = GDALGetMetadataItem(ds, "TIFFTAG_MINSAMPLEVALUE", NULL);
    const char* mx = GDALGetMetadataItem(ds, "TIFFTAG_MAXSAMPLEVALUE", NULL);
    ASSERT_TRUE(mn != NULL && mx != NULL);
    const double lo = atof(mn), hi = atof(mx);
    GDALClose(ds);

    const char* dir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/cl.tpt", dir);
    snprintf(args, sizeof args, "'%s' -o '%s' --fill-max 0", path, out);
    ASSERT_EQ_INT(0, run_build(args));
    grid g;
    read_store(out, &g);
    double got_lo, got_hi;
    /* quantised heights: within half a height step of the source's integers */
    EXPECT_EQ_INT(0, (long long)outside(&g, lo - g.step / 2, hi + g.step / 2, &got_lo, &got_hi));
    tp_test_note("store heights %.3f .. %.3f m (file's tags %g .. %g)", got_lo, got_hi, lo, hi);
    EXPECT_CONTAINS(g.notes, "-32768 and -32767 taken as nodata");

    tp_error err = {0};
    tp_dem* dem = NULL;
    ASSERT_EQ_INT(TP_OK, tp_dem_read(path, &dem, &err));
    EXPECT_EQ_INT(39489, (long long)dem->void_count); /* PROVENANCE.md */
    tp_render_grid* rg = NULL;
    tp_grid_options go = {.fill_max_px = -1};
    ASSERT_EQ_INT(TP_OK, tp_render_grid_build(dem, &go, &rg, &err));
    ASSERT_EQ_INT(rg->width, g.w);
    ASSERT_EQ_INT(rg->height, g.h);
    const size_t n = (size_t)g.w * g.h, want = nan_count(rg->heights, n);
    size_t differ = 0;
    for (size_t i = 0; i < n; i++)
        differ += isnan(rg->heights[i]) != isnan(g.z[i]);
    tp_test_note("nodata: store %zu (header %zu), render grid %zu", nan_count(g.z, n),
                 g.nodata_header, want);
    EXPECT_TRUE(want > 0);
    EXPECT_EQ_INT((long long)want, (long long)nan_count(g.z, n));
    EXPECT_EQ_INT((long long)want, (long long)g.nodata_header);
    EXPECT_EQ_INT(0, (long long)differ);
    tp_render_grid_destroy(rg);
    tp_dem_destroy(dem);
    free(g.z);
}

/* ---- synthetic tiles ---- */

enum { BLOCKS, DENSE };

/* What a tile holds: its void counts, the range of its heights and the largest step between
 * neighbouring valid samples. */
typedef struct tile {
    char path[512];
    int w, h, epsg;
    double gt[6];
    size_t v32768, v32767;
    double lo, hi, dmax;
} tile;

/* The surface: metres, a smooth function of the geographic position (about 1000 .. 1500 m). */
static double surface(double lon, double lat)
{
    return 1250.0 + 150.0 * sin((lon + 122.2) * 90.0) + 100.0 * cos((lat - 42.9) * 110.0);
}

static int void_at(int pattern, int x, int y)
{
    if (pattern == DENSE)
        return (x + 2 * y) % 5 == 0 ? -32767 : (x + 2 * y) % 5 == 2 ? -32768 : 0;
    if (y < 6)
        return -32767; /* a border strip, as craterlake's outside */
    if (x >= 30 && x < 60 && y >= 30 && y < 60)
        return -32768;
    if (x >= 100 && x < 130 && y >= 40 && y < 70)
        return -32767;
    if ((x * 7 + y * 13) % 97 == 0)
        return (x + y) % 2 ? -32767 : -32768;
    return 0;
}

/* Writes t (w, h, epsg, gt set) as an Int16 GeoTIFF without a nodata tag. */
static void write_tile(tile* t, const char* dir, const char* name, int pattern)
{
    snprintf(t->path, sizeof t->path, "%s/%s", dir, name);
    GDALAllRegister();
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL), wgs = OSRNewSpatialReference(NULL);
    ASSERT_EQ_INT(OGRERR_NONE, OSRImportFromEPSG(srs, t->epsg));
    ASSERT_EQ_INT(OGRERR_NONE, OSRImportFromEPSG(wgs, 4326));
    OSRSetAxisMappingStrategy(srs, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy(wgs, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(srs, wgs);
    ASSERT_TRUE(ct != NULL);
    int16_t* z = malloc((size_t)t->w * t->h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    t->v32768 = t->v32767 = 0;
    t->lo = INFINITY, t->hi = -INFINITY, t->dmax = 0;
    for (int y = 0; y < t->h; y++)
        for (int x = 0; x < t->w; x++) {
            double px = t->gt[0] + (x + 0.5) * t->gt[1], py = t->gt[3] + (y + 0.5) * t->gt[5];
            ASSERT_TRUE(OCTTransform(ct, 1, &px, &py, NULL));
            const int v = void_at(pattern, x, y);
            int16_t* s = &z[(size_t)y * t->w + x];
            *s = (int16_t)(v ? v : lround(surface(px, py)));
            if (v) {
                t->v32768 += v == -32768, t->v32767 += v == -32767;
                continue;
            }
            t->lo = *s < t->lo ? *s : t->lo, t->hi = *s > t->hi ? *s : t->hi;
            if (x > 0 && !void_at(pattern, x - 1, y))
                t->dmax = fmax(t->dmax, fabs((double)*s - s[-1]));
            if (y > 0 && !void_at(pattern, x, y - 1))
                t->dmax = fmax(t->dmax, fabs((double)*s - s[-t->w]));
        }
    GDALDriverH gtiff = GDALGetDriverByName("GTiff");
    ASSERT_TRUE(gtiff != NULL);
    GDALDatasetH ds = GDALCreate(gtiff, t->path, t->w, t->h, 1, GDT_Int16, NULL);
    ASSERT_TRUE(ds != NULL);
    GDALSetGeoTransform(ds, t->gt);
    GDALSetSpatialRef(ds, srs);
    ASSERT_EQ_INT(CE_None, GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, 0, t->w, t->h, z,
                                        t->w, t->h, GDT_Int16, 0, 0));
    GDALClose(ds);
    free(z);
    OCTDestroyCoordinateTransformation(ct);
    OSRDestroySpatialReference(srs);
    OSRDestroySpatialReference(wgs);
    ASSERT_TRUE(t->v32768 > 0 && t->v32767 > 0);
}

/* Projected tiles: UTM 10N, 30 m posts, 160 x 100; column x0 of one grid (adjacent tiles). */
static void projected(tile* t, const char* dir, const char* name, int x0)
{
    *t = (tile){.w = 160, .h = 100, .epsg = 32610,
                .gt = {570000.0 + x0 * 30.0, 30.0, 0.0, 4759500.0, 0.0, -30.0}};
    write_tile(t, dir, name, BLOCKS);
}

/* Geographic tiles: WGS84, posts 0.0003 degrees, 160 x 120; column x0 of one grid. */
static void geographic(tile* t, const char* dir, const char* name, int x0, int w, int pattern)
{
    *t = (tile){.w = w, .h = 120, .epsg = 4326,
                .gt = {-122.16 + x0 * 0.0003, 0.0003, 0.0, 42.99, 0.0, -0.0003}};
    write_tile(t, dir, name, pattern);
}

/* The store's sample nearest to sample (x, y) of t: NaN for nodata. */
static float store_at(const grid* g, const tile* t, double x, double y)
{
    OGRSpatialReferenceH src = OSRNewSpatialReference(NULL), dst = OSRNewSpatialReference(g->wkt);
    ASSERT_EQ_INT(OGRERR_NONE, OSRImportFromEPSG(src, t->epsg));
    OSRSetAxisMappingStrategy(src, OAMS_TRADITIONAL_GIS_ORDER);
    OSRSetAxisMappingStrategy(dst, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(src, dst);
    ASSERT_TRUE(ct != NULL);
    double e = t->gt[0] + (x + 0.5) * t->gt[1], n = t->gt[3] + (y + 0.5) * t->gt[5];
    ASSERT_TRUE(OCTTransform(ct, 1, &e, &n, NULL));
    OCTDestroyCoordinateTransformation(ct);
    OSRDestroySpatialReference(src);
    OSRDestroySpatialReference(dst);
    const long gx = lround((e - g->gt[0]) / g->gt[1] - 0.5), gy = lround((n - g->gt[3]) / g->gt[5] - 0.5);
    ASSERT_TRUE(gx >= 0 && gx < g->w && gy >= 0 && gy < g->h);
    return g->z[(size_t)gy * g->w + gx];
}

/* Builds the tiles (--fill-max 0: voids stay) and checks the store: every height within the
 * tiles' range (a warp interpolates between posts, never beyond them; half a height step of
 * quantisation), the centres of each tile's two void blocks nodata. Returns its nodata count. */
static size_t build_tiles(const tile* const* t, int count)
{
    char args[8192], out[1024];
    const char* dir = make_tmp_dir();
    snprintf(out, sizeof out, "%s/out.tpt", dir);
    int at = snprintf(args, sizeof args, "-o '%s' --patch 33 --fill-max 0", out);
    double lo = INFINITY, hi = -INFINITY;
    for (int i = 0; i < count; i++) {
        at += snprintf(args + at, sizeof args - at, " '%s'", t[i]->path);
        lo = fmin(lo, t[i]->lo), hi = fmax(hi, t[i]->hi);
    }
    ASSERT_EQ_INT(0, run_build(args));
    grid g;
    read_store(out, &g);
    double got_lo, got_hi;
    const size_t bad = outside(&g, lo - g.step / 2, hi + g.step / 2, &got_lo, &got_hi);
    EXPECT_EQ_INT(0, (long long)bad);
    tp_test_note("%d tile(s): heights %.3f .. %.3f m (tiles %g .. %g), %zu outside", count,
                 got_lo, got_hi, lo, hi, bad);
    EXPECT_CONTAINS(g.notes, "-32768 and -32767 taken as nodata");
    for (int i = 0; i < count; i++) {
        EXPECT_NAN(store_at(&g, t[i], 45, 45));  /* the -32768 block */
        EXPECT_NAN(store_at(&g, t[i], 115, 55)); /* the -32767 block */
    }
    const size_t nodata = nan_count(g.z, (size_t)g.w * g.h);
    EXPECT_EQ_INT((long long)nodata, (long long)g.nodata_header);
    free(g.z);
    return nodata;
}

/* Projected, on its own grid (no warp): every void written is nodata, nothing else is. */
TEST(projected_alone_and_mosaic_no_sample_below_the_minimum)
{
    const char* dir = make_tmp_dir();
    tile a, b;
    projected(&a, dir, "a.tif", 0);
    projected(&b, dir, "b.tif", 160);
    const tile* one[1] = {&a};
    const tile* two[2] = {&a, &b};
    EXPECT_EQ_INT((long long)(a.v32768 + a.v32767), (long long)build_tiles(one, 1));
    EXPECT_EQ_INT((long long)(a.v32768 + a.v32767 + b.v32768 + b.v32767),
                  (long long)build_tiles(two, 2));
}

/* Geographic, warped to UTM 10N (bilinear): alone and as a mosaic. */
TEST(geographic_alone_and_mosaic_no_sample_below_the_minimum)
{
    const char* dir = make_tmp_dir();
    tile a, b;
    geographic(&a, dir, "a.tif", 0, 160, BLOCKS);
    geographic(&b, dir, "b.tif", 160, 160, BLOCKS);
    const tile* one[1] = {&a};
    const tile* two[2] = {&a, &b};
    build_tiles(one, 1);
    build_tiles(two, 2);
}

/* A projected and a geographic tile: each warped onto one grid, then mosaicked (they overlap
 * east of the projected tile's void blocks). */
TEST(two_crs_mosaic_no_sample_below_the_minimum)
{
    const char* dir = make_tmp_dir();
    tile a, b;
    projected(&a, dir, "a.tif", 0);
    geographic(&b, dir, "b.tif", 250, 160, BLOCKS);
    const tile* two[2] = {&a, &b};
    build_tiles(two, 2);
}

/* --fill-from an untagged Int16 raster with voids of both values every few samples: the voids
 * of the DEM are filled from its valid samples only. The fill is the second surface shifted to
 * meet the DEM around each void; both sample one smooth surface, so a filled height lies within
 * the two tiles' range widened by their largest step between neighbouring samples. */
TEST(fill_from_untagged_int16_leaves_its_voids_out)
{
    char args[8192], out[1024];
    const char* dir = make_tmp_dir();
    tile a, f;
    projected(&a, dir, "a.tif", 0);
    geographic(&f, dir, "fill.tif", -20, 400, DENSE);
    snprintf(out, sizeof out, "%s/out.tpt", dir);
    snprintf(args, sizeof args, "'%s' -o '%s' --patch 33 --fill-from '%s'", a.path, out, f.path);
    ASSERT_EQ_INT(0, run_build(args));
    grid g;
    read_store(out, &g);
    const double lo = fmin(a.lo, f.lo), hi = fmax(a.hi, f.hi), d = fmax(a.dmax, f.dmax);
    double got_lo, got_hi;
    const size_t bad = outside(&g, lo - d - g.step / 2, hi + d + g.step / 2, &got_lo, &got_hi);
    tp_test_note("filled from %s: heights %.3f .. %.3f m (tiles %g .. %g, step %g)", f.path,
                 got_lo, got_hi, lo, hi, d);
    EXPECT_EQ_INT(0, (long long)bad);
    EXPECT_TRUE(isfinite(store_at(&g, &a, 45, 45))); /* interior blocks filled */
    EXPECT_TRUE(isfinite(store_at(&g, &a, 115, 55)));
    free(g.z);

    /* the viewer's in-memory path (tp_render_grid_build: the fill source warped into memory) */
    tp_error err = {0};
    tp_dem* dem = NULL;
    ASSERT_EQ_INT(TP_OK, tp_dem_read(a.path, &dem, &err));
    tp_render_grid* rg = NULL;
    tp_grid_options go = {.fill_from = f.path};
    ASSERT_EQ_INT(TP_OK, tp_render_grid_build(dem, &go, &rg, &err));
    grid m = {.w = rg->width, .h = rg->height, .z = rg->heights};
    EXPECT_TRUE(rg->filled_from_samples > 0);
    EXPECT_EQ_INT(0, (long long)outside(&m, lo - d, hi + d, &got_lo, &got_hi));
    tp_test_note("in memory: heights %.3f .. %.3f m, %zu filled from it", got_lo, got_hi,
                 rg->filled_from_samples);
    tp_render_grid_destroy(rg);
    tp_dem_destroy(dem);
}

/* No file appears beside the sources: --crs is given to GDAL's VRT or warp, never set on a
 * source's own dataset (GDAL would save it into a .aux.xml beside the file, and every later
 * reader of the file would take its CRS from there). One source on its own grid, a warped one,
 * and two of different spacings, one of them tagged (not read through the Int16 VRT). */
TEST(crs_override_writes_nothing_beside_the_sources)
{
    const char* dir = make_tmp_dir();
    const char* odir = make_tmp_dir();
    tile a, c, g;
    projected(&a, dir, "a.tif", 0);
    c = (tile){.w = 80, .h = 50, .epsg = 32610, .gt = {574800.0, 60.0, 0.0, 4759500.0, 0.0, -60.0}};
    write_tile(&c, dir, "c.tif", BLOCKS);
    GDALDatasetH ds = GDALOpen(c.path, GA_Update);
    ASSERT_TRUE(ds != NULL);
    ASSERT_EQ_INT(CE_None, GDALSetRasterNoDataValue(GDALGetRasterBand(ds, 1), -32768));
    GDALClose(ds);
    geographic(&g, dir, "g.tif", 0, 160, BLOCKS);
    const char* runs[][2] = {{a.path, ""}, {g.path, ""}, {a.path, c.path}};
    const char* crs[] = {"EPSG:32611", "EPSG:4326", "EPSG:32610"};
    for (int i = 0; i < 3; i++) {
        char args[4096];
        snprintf(args, sizeof args, "--crs %s -o '%s/o%d.tpt' '%s' %s%s%s", crs[i], odir, i,
                 runs[i][0], *runs[i][1] ? "'" : "", runs[i][1], *runs[i][1] ? "'" : "");
        EXPECT_EQ_INT(0, run_build(args));
        DIR* d = opendir(dir);
        ASSERT_TRUE(d != NULL);
        int files = 0;
        for (struct dirent* e; (e = readdir(d));)
            if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
                files++;
                EXPECT_FALSE(strstr(e->d_name, ".aux.xml") != NULL);
            }
        closedir(d);
        EXPECT_EQ_INT(3, files); /* a.tif, c.tif, g.tif */
    }
}

#define TESTS(X)                                                                                   \
    X(craterlake_heights_in_range_and_voids_as_dem_reader)                                         \
    X(projected_alone_and_mosaic_no_sample_below_the_minimum)                                      \
    X(geographic_alone_and_mosaic_no_sample_below_the_minimum)                                     \
    X(two_crs_mosaic_no_sample_below_the_minimum)                                                  \
    X(fill_from_untagged_int16_leaves_its_voids_out)                                               \
    X(crs_override_writes_nothing_beside_the_sources)
TP_TEST_MAIN(TESTS)
