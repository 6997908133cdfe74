/*
 * test_terrain_open.c - one way to open the ground (app/scene/terrain_open.c, issue 29 part 1): every
 * command reads GDAL's virtual paths, takes the DEM options, refuses them the same way for a
 * store, and says a damaged store is one. `terrapatch` is run as a child on the real tile
 * N42E001 (SRTM, Andorra) and the Mt Hood sample; the oracle for heights is the same command on
 * the plain file, and for the files GDAL's own virtual file system.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"
#include "tp_test_child.h"

#include "tp_io.h"

#include <cpl_vsi.h>
#include <gdal.h>
#include <ogr_srs_api.h>

#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define TILE "N42E001.hgt"
#define HOOD "lf_elev_220_mt_hood_utm.tif"

static const char* tmp_dir(void)
{
    return tp_test_child_dir("terrain_open");
}

/* Copies the file at from into GDAL's virtual path to (e.g. "/vsizip/DIR/x.zip/N42E001.hgt"),
 * written through GDAL's own zip/gzip writers: the archive is GDAL's, not ours. */
static void vsi_copy(const char* from, const char* to)
{
    FILE* f = fopen(from, "rb");
    ASSERT_TRUE(f != NULL);
    VSILFILE* v = VSIFOpenL(to, "wb");
    ASSERT_TRUE(v != NULL);
    char buf[1 << 16];
    size_t n;
    while ((n = fread(buf, 1, sizeof buf, f)) > 0)
        ASSERT_TRUE(VSIFWriteL(buf, 1, n, v) == n);
    fclose(f);
    ASSERT_EQ_INT(0, VSIFCloseL(v));
}

/* `terrapatch point [OPT VAL] DEM LAT LON --json F`: the elevation; fails the test on another
 * exit status than 0. */
static double point_height_at(const char* dem, const char* lat, const char* lon, const char* opt,
                              const char* val, char* err, size_t err_cap)
{
    char out[256], json[8192];
    snprintf(out, sizeof out, "%s/point.json", tmp_dir());
    remove(out);
    const char* with[] = {opt, val, dem, lat, lon, "--json", out, NULL};
    const char* without[] = {dem, lat, lon, "--json", out, NULL};
    int rc = tp_test_run_terrapatch("point", opt ? with : without, err, err_cap);
    if (rc != 0)
        FAIL("point %s: exit %d: %s", dem, rc, err);
    tp_test_read_text(out, json, sizeof json);
    return tp_test_json_number_after(json, NULL, "elevation_m");
}

/* The same at (42.5, 1.5), on N42E001. */
static double point_height(const char* dem, const char* opt, const char* val, char* err,
                           size_t err_cap)
{
    return point_height_at(dem, "42.5", "1.5", opt, val, err, err_cap);
}

/* A place on a DEM: its centre (latitude, longitude). */
typedef struct place {
    double lat, lon;
} place;

static const place ANDORRA = {42.5, 1.5};         /* N42E001 */
static const place FRONT_RANGE = {40.15, -105.5}; /* front_range_srtmgl3_144.asc */

/* A GeoJSON route from p to 0.005 degrees north-east of it. */
static void write_route(place p, char* path, size_t cap)
{
    snprintf(path, cap, "%s/route.geojson", tmp_dir());
    FILE* f = fopen(path, "w");
    ASSERT_TRUE(f != NULL);
    fprintf(
        f,
        "{\"type\":\"FeatureCollection\",\"features\":[{\"type\":\"Feature\",\"properties\":"
        "{},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[[%.4f,%.4f],[%.4f,%.4f]]}}]}\n",
        p.lon, p.lat, p.lon + 0.005, p.lat + 0.005);
    fclose(f);
}

/* Runs every command that reads the ground on dem around p (with two extra arguments before
 * the DEM when opt is set); asserts each exit status is want and its stderr holds expect (NULL:
 * anything). */
static void every_command_with(const char* dem, place p, const char* opt, const char* val,
                               const char* opt2, const char* val2, int want, const char* expect);

static void every_command(const char* dem, place p, const char* opt, const char* val, int want,
                          const char* expect)
{
    every_command_with(dem, p, opt, val, NULL, NULL, want, expect);
}

/* every_command with a second option and value (opt2 NULL: none). */
static void every_command_with(const char* dem, place p, const char* opt, const char* val,
                               const char* opt2, const char* val2, int want, const char* expect)
{
    char route[256], vs[256], li[256], co[256], js[256], at[64], to[64], lat[32], lon[32];
    write_route(p, route, sizeof route);
    snprintf(vs, sizeof vs, "%s/vs.tif", tmp_dir());
    snprintf(li, sizeof li, "%s/light.tif", tmp_dir());
    snprintf(co, sizeof co, "%s/contours.gpkg", tmp_dir());
    snprintf(js, sizeof js, "%s/los.json", tmp_dir());
    snprintf(at, sizeof at, "%.4f,%.4f", p.lat, p.lon);
    snprintf(to, sizeof to, "%.4f,%.4f", p.lat + 0.005, p.lon + 0.005);
    snprintf(lat, sizeof lat, "%.4f", p.lat);
    snprintf(lon, sizeof lon, "%.4f", p.lon);
    const char* cmds[] = {"point", "los", "viewshed", "light", "profile", "contours"};
    const char* const argv[][16] = {
        {dem, lat, lon, NULL},
        {dem, "--from", at, "--to", to, "--json", js, NULL},
        {dem, "--observer", at, "--radius", "1000", "-o", vs, NULL},
        {dem, "--date", "2026-06-21", "--time", "12:00Z", "--at", at, "--radius", "1000", "-o", li,
         NULL},
        {dem, "--route", route, NULL},
        {dem, "--interval", "100", "--around", at, "--radius", "1000", "-o", co, NULL},
    };
    for (size_t c = 0; c < sizeof cmds / sizeof cmds[0]; ++c) {
        const char* args[20];
        int n = 0;
        if (opt) {
            args[n++] = opt;
            args[n++] = val;
        }
        if (opt2) {
            args[n++] = opt2;
            args[n++] = val2;
        }
        for (int k = 0; argv[c][k]; ++k)
            args[n++] = argv[c][k];
        args[n] = NULL;
        char err[8192];
        int rc = tp_test_run_terrapatch(cmds[c], args, err, sizeof err);
        if (rc != want)
            FAIL("%s %s %s %s: exit %d, expected %d: %s", cmds[c], opt ? opt : "", opt ? val : "",
                 dem, rc, want, err);
        if (expect && !strstr(err, expect))
            FAIL("%s: stderr lacks '%s': %s", cmds[c], expect, err);
    }
}

/* 1.1: a tile inside a zip (GDAL's /vsizip/), a gzip (/vsigzip/) and a tar (/vsitar/) is read
 * by every command that reads the ground, with the same heights as the plain file. */
TEST(virtual_paths_work_in_every_command)
{
    char tile[1024], grid[1024], zip[1024], gz[1024], tar[1024], err[8192];
    REQUIRE_DATA_FILE(tile, "TP_SHARED_DATA_DIR", TILE);
    /* gzip and tar hold the small ASCII grid (two builds of the tile fewer) */
    REQUIRE_DATA_FILE(grid, "TP_SHARED_DATA_DIR", "front_range_srtmgl3_144.asc");
    snprintf(zip, sizeof zip, "/vsizip/%s/n42.zip/" TILE, tmp_dir());
    snprintf(gz, sizeof gz, "/vsigzip/%s/front.asc.gz", tmp_dir());
    vsi_copy(tile, zip);
    vsi_copy(grid, gz);
    /* a tar written by tar(1), from the grid's folder so that the member is the bare name */
    char cmd[3072], dir[1024];
    snprintf(dir, sizeof dir, "%s", grid);
    *strrchr(dir, '/') = '\0';
    snprintf(cmd, sizeof cmd, "tar -cf '%s/front.tar' -C '%s' front_range_srtmgl3_144.asc",
             tmp_dir(), dir);
    ASSERT_EQ_INT(0, system(cmd));
    snprintf(tar, sizeof tar, "/vsitar/%s/front.tar/front_range_srtmgl3_144.asc", tmp_dir());

    const double plain = point_height(tile, NULL, NULL, err, sizeof err);
    ASSERT_TRUE(plain > 500 && plain < 3000);
    EXPECT_NEAR(plain, point_height(zip, NULL, NULL, err, sizeof err), 0.0);
    const double front = point_height_at(grid, "40.15", "-105.5", NULL, NULL, err, sizeof err);
    ASSERT_TRUE(front > 1500 && front < 4500);
    EXPECT_NEAR(front, point_height_at(gz, "40.15", "-105.5", NULL, NULL, err, sizeof err), 0.0);
    EXPECT_NEAR(front, point_height_at(tar, "40.15", "-105.5", NULL, NULL, err, sizeof err), 0.0);
    every_command(zip, ANDORRA, NULL, NULL, 0, NULL);

    /* a relative path inside the archive's prefix names the same cached store from elsewhere */
    char here[1024];
    ASSERT_TRUE(getcwd(here, sizeof here) != NULL);
    ASSERT_EQ_INT(0, chdir(tmp_dir()));
    EXPECT_NEAR(plain, point_height("/vsizip/n42.zip/" TILE, NULL, NULL, err, sizeof err), 0.0);
    EXPECT_TRUE(strstr(err, "building a store") == NULL); /* the absolute one's, reused */
    ASSERT_EQ_INT(0, chdir(here));

    /* a missing member is one clear line, exit 1 */
    char missing[1024];
    snprintf(missing, sizeof missing, "/vsizip/%s/n42.zip/nothing.hgt", tmp_dir());
    const char* args[] = {missing, "42.5", "1.5", NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch("point", args, err, sizeof err));
    EXPECT_CONTAINS(err, "nothing.hgt: cannot open: no such file");
}

/* 1.2: the DEM options are taken by every command that reads the ground (they were unknown
 * options, exit 2, in point, los, viewshed, light, profile and contours). */
TEST(dem_options_are_accepted_by_every_command)
{
    char tile[1024], err[8192];
    REQUIRE_DATA_FILE(tile, "TP_SHARED_DATA_DIR", "front_range_srtmgl3_144.asc");
    every_command(tile, FRONT_RANGE, "--crs", "EPSG:4326", 0, NULL);
    every_command(tile, FRONT_RANGE, "--fill-max", "0", 0, NULL);
    every_command(tile, FRONT_RANGE, "--resampling=cubic", "--patch=33", 0, NULL);
    /* a value is checked by the one parser, with the same words in every command */
    every_command(tile, FRONT_RANGE, "--patch", "20", 2,
                  "--patch: expected 17, 33, 65, 129 or 257, got 20");
    /* --fit shapes a DEM drawn whole; these commands read a store */
    every_command(tile, FRONT_RANGE, "--fit", "resample", 2, "--fit shapes a DEM drawn whole");
    /* cubic resampling is another surface: the same position, another store, another height */
    char tile42[1024];
    REQUIRE_DATA_FILE(tile42, "TP_SHARED_DATA_DIR", TILE);
    const double bilinear = point_height(tile42, NULL, NULL, err, sizeof err);
    const double cubic = point_height(tile42, "--resampling", "cubic", err, sizeof err);
    EXPECT_TRUE(fabs(cubic - bilinear) > 1e-6 && fabs(cubic - bilinear) < 20);
}

/* 1.2: a heightmap image placed with --origin and --spacing (--zscale alike) is read by every
 * command that reads the ground, through a georeferenced GeoTIFF made once in the cache (they
 * refused those options, exit 2); the height at a place is the image read on its own, count x
 * zscale, interpolated there. */
TEST(heightmap_options_are_accepted_by_every_command)
{
    char png[1024], err[8192];
    REQUIRE_DATA_FILE(png, "TP_SHARED_DATA_DIR", "ps_height_1k.png");
    const place centre = {47.5, -122.5};
    every_command_with(png, centre, "--origin", "47.5,-122.5", "--spacing", "4", 0, NULL);
    const double got =
        point_height_at(png, "47.5003", "-122.5004", "--origin", "47.5,-122.5", err, sizeof err);
    tp_image_options io = {.spacing_m = 1,
                           .zscale = 1,
                           .has_origin = 1,
                           .origin_lat_deg = 47.5,
                           .origin_lon_deg = -122.5};
    tp_dem* d = NULL;
    tp_georef* g = NULL;
    tp_error e;
    ASSERT_OK(tp_dem_read_image(png, &io, &d, &e));
    ASSERT_OK(tp_georef_create(d->crs_wkt, d->geotransform, &g, &e));
    double east, north, x, y;
    ASSERT_OK(tp_georef_geo_to_proj(g, 47.5003, -122.5004, &east, &north, &e));
    tp_georef_proj_to_grid(g, east, north, &x, &y);
    const double want =
        tp_grid_height_at(d->heights, (size_t)d->width * d->height, d->width, d->height, x, y);
    tp_test_note("ps_height_1k.png at 47.5003, -122.5004: point %.3f m, the image %.3f m", got,
                 want);
    EXPECT_TRUE(!isnan(want) && want > 10);
    EXPECT_NEAR(want, got, 0.5); /* the store's quantisation */
    tp_georef_destroy(g);
    tp_dem_destroy(d);
}

/* 1.2: an ASCII grid in degrees without a .prj is read with --crs by the planner commands. */
TEST(ascii_grid_without_prj_takes_crs)
{
    char grid[1024], err[8192];
    REQUIRE_DATA_FILE(grid, "TP_SHARED_DATA_DIR", "front_range_srtmgl3_144.asc");
    char out[256], json[8192];
    snprintf(out, sizeof out, "%s/front.json", tmp_dir());
    const char* args[] = {"--crs", "EPSG:4326", grid, "40.15", "-105.5", "--json", out, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("point", args, err, sizeof err));
    EXPECT_TRUE(strstr(err, "taken as EPSG:4326") == NULL); /* no guess: the CRS was given */
    tp_test_read_text(out, json, sizeof json);
    const double h = tp_test_json_number_after(json, NULL, "elevation_m");
    EXPECT_TRUE(h > 1500 && h < 4500); /* the Front Range foothills */
}

/* Builds a small store of the Mt Hood sample once; its path into path. */
static void hood_store(char* path, size_t cap)
{
    char hood[1024], err[8192];
    REQUIRE_DATA_FILE(hood, "TP_SAMPLE_DATA_DIR", HOOD);
    snprintf(path, cap, "%s/hood.tpt", tmp_dir());
    if (access(path, F_OK) == 0)
        return;
    const char* args[] = {hood, "-o", path, "--quiet", NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("build", args, err, sizeof err));
}

/* 1.2: a DEM option with a store is refused by every command with the same words (info
 * --patch 33 X.tpt was silently ignored). */
TEST(store_refuses_dem_options_the_same_way_everywhere)
{
    char store[256], err[8192], out[256], png[256];
    hood_store(store, sizeof store);
    snprintf(out, sizeof out, "%s/x.vtp", tmp_dir());
    snprintf(png, sizeof png, "%s/x.png", tmp_dir());
    const char* want = "is a store: --patch shapes a DEM when it is read or built";
    const char* cmds[] = {"info", "view", "bench", "export", "point"};
    const char* const argv[][8] = {
        {"--patch", "33", store, NULL},
        {"--patch", "33", "--headless", "--screenshot", png, store, NULL},
        {"--patch", "33", "--frames", "2", store, NULL},
        {"--patch", "33", store, "-o", out, NULL},
        {"--patch", "33", store, "45.37", "-121.69", NULL},
    };
    for (size_t c = 0; c < sizeof cmds / sizeof cmds[0]; ++c) {
        int rc = tp_test_run_terrapatch(cmds[c], argv[c], err, sizeof err);
        if (rc != 2 || !strstr(err, want))
            FAIL("%s --patch 33 STORE: exit %d: %s", cmds[c], rc, err);
    }
    const char* crs[] = {"--crs", "EPSG:4326", store, "45.37", "-121.69", NULL};
    EXPECT_EQ_INT(2, tp_test_run_terrapatch("point", crs, err, sizeof err));
    EXPECT_CONTAINS(err, "is a store: --crs shapes a DEM");
}

/* 1.6: a store whose header is damaged is said to be one, in one line, by every command; not
 * handed to GDAL as a raster. */
TEST(damaged_store_header_is_said_to_be_one)
{
    char store[256], bad[256], err[8192];
    hood_store(store, sizeof store);
    snprintf(bad, sizeof bad, "%s/bad.tpt", tmp_dir());
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "cp '%s' '%s'", store, bad);
    ASSERT_EQ_INT(0, system(cmd));
    FILE* f = fopen(bad, "r+b");
    ASSERT_TRUE(f != NULL);
    fseek(f, 5, SEEK_SET); /* the magic's "\r\n\x1a\n" */
    fputs("XX", f);
    fclose(f);
    const char* cmds[] = {"info", "point", "view", "export"};
    char out[256], png[256];
    snprintf(out, sizeof out, "%s/bad.vtp", tmp_dir());
    snprintf(png, sizeof png, "%s/bad.png", tmp_dir());
    const char* const argv[][8] = {{bad, NULL},
                                   {bad, "45.37", "-121.69", NULL},
                                   {"--headless", "--screenshot", png, bad, NULL},
                                   {bad, "-o", out, NULL}};
    for (size_t c = 0; c < sizeof cmds / sizeof cmds[0]; ++c) {
        int rc = tp_test_run_terrapatch(cmds[c], argv[c], err, sizeof err);
        if (rc != 1 || !strstr(err, "not a terrapatch store, or its header is damaged"))
            FAIL("%s on a damaged store: exit %d: %s", cmds[c], rc, err);
        EXPECT_TRUE(strchr(err, '\n') == err + strlen(err) - 1); /* one line */
        EXPECT_TRUE(strstr(err, "GDAL") == NULL && strstr(err, "not recognized") == NULL);
    }
    EXPECT_TRUE(access(out, F_OK) != 0 && access(png, F_OK) != 0);
}

/* 1.6: bytes appended after a valid footer (here: a second copy of the footer, which leaves a
 * valid footer at the end) are refused, as is garbage after it. */
TEST(bytes_after_the_footer_are_refused)
{
    char store[256], grown[256], err[8192];
    hood_store(store, sizeof store);
    snprintf(grown, sizeof grown, "%s/grown.tpt", tmp_dir());
    char cmd[1200];
    snprintf(cmd, sizeof cmd, "cp '%s' '%s' && tail -c 56 '%s' >> '%s'", store, grown, store,
             grown);
    ASSERT_EQ_INT(0, system(cmd));
    const char* args[] = {grown, NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch("info", args, err, sizeof err));
    EXPECT_CONTAINS(err, "56 bytes between the last node's data and the footer");

    snprintf(cmd, sizeof cmd, "cp '%s' '%s' && printf 'appended' >> '%s'", store, grown, grown);
    ASSERT_EQ_INT(0, system(cmd));
    EXPECT_EQ_INT(1, tp_test_run_terrapatch("info", args, err, sizeof err));
    EXPECT_CONTAINS(err, "bytes appended after the footer?");
    /* the store itself still opens */
    const char* ok[] = {store, NULL};
    EXPECT_EQ_INT(0, tp_test_run_terrapatch("info", ok, err, sizeof err));
}

/* 1.4: an input that is not a regular file is refused in one line on every input path (a FIFO
 * hung --route, --overlay, --bookmarks and bench --path-file; /dev/zero as --bookmarks spun at
 * 100% CPU). */
TEST(non_regular_inputs_are_refused_on_every_path)
{
    char store[256], fifo[256], png[256], err[8192], hood[1024];
    hood_store(store, sizeof store);
    REQUIRE_DATA_FILE(hood, "TP_SAMPLE_DATA_DIR", HOOD);
    snprintf(fifo, sizeof fifo, "%s/fifo", tmp_dir());
    remove(fifo);
    ASSERT_EQ_INT(0, mkfifo(fifo, 0600));
    snprintf(png, sizeof png, "%s/never.png", tmp_dir());
    const char* cmds[] = {"profile", "view", "view", "view", "bench"};
    const char* const argv[][10] = {
        {store, "--route", fifo, NULL},
        {"--headless", "--screenshot", png, "--overlay", fifo, store, NULL},
        {"--headless", "--screenshot", png, "--bookmarks", fifo, store, NULL},
        {"--headless", "--screenshot", png, "--bookmarks", "/dev/zero", store, NULL},
        {"--frames", "2", "--path-file", fifo, hood, NULL},
    };
    const char* what[] = {fifo, fifo, fifo, "/dev/zero", fifo};
    for (size_t c = 0; c < sizeof cmds / sizeof cmds[0]; ++c) {
        int rc = tp_test_run_terrapatch(cmds[c], argv[c], err, sizeof err);
        if (rc != 1 || !strstr(err, what[c]) || !strstr(err, "not a regular file"))
            FAIL("%s with %s: exit %d: %s", cmds[c], what[c], rc, err);
    }
    EXPECT_TRUE(access(png, F_OK) != 0);
    remove(fifo);
}

/* 1.7: sources that leave most of their mosaic empty (Crater Lake and Mt Rainier, 450 km
 * apart: about four fifths of the box around them is no source's) are refused, naming the share,
 * unless --allow-gaps; nothing is written. */
TEST(build_refuses_sources_far_apart)
{
    char crater[1024], rainier[1024], out[256], err[8192];
    REQUIRE_DATA_FILE(crater, "TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif");
    REQUIRE_DATA_FILE(rainier, "TP_SHARED_DATA_DIR", "mt_rainier_90m.tif");
    snprintf(out, sizeof out, "%s/apart.tpt", tmp_dir());
    const char* args[] = {crater, rainier, "-o", out, NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch("build", args, err, sizeof err));
    EXPECT_CONTAINS(err, "add --allow-gaps");
    /* the share: Rainier's 1 x 1 degree and Crater Lake's 0.12 x 0.08 in a box of about
     * 1.17 x 4.1 degrees, about 21% (in UTM metres the box is a little wider at the south) */
    const char* p = strstr(err, "cover about ");
    ASSERT_TRUE(p != NULL);
    const double share = strtod(p + strlen("cover about "), NULL);
    EXPECT_TRUE(share > 15 && share < 27);
    EXPECT_TRUE(access(out, F_OK) != 0);
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "apart.tpt"));
    /* overlapping sources count their ground once: three of the same tile cover all of it (a
     * sum less pairwise overlaps would say 0%) */
    char tile[1024];
    REQUIRE_DATA_FILE(tile, "TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif");
    snprintf(out, sizeof out, "%s/thrice.tpt", tmp_dir());
    const char* thrice[] = {tile, tile, tile, "-o", out, "--quiet", NULL};
    EXPECT_EQ_INT(0, tp_test_run_terrapatch("build", thrice, err, sizeof err));
    EXPECT_TRUE(access(out, F_OK) == 0);
}

/* A copy of the Mt Hood sample (UTM 10N, metres, Int16) with its heights divided by to_m
 * (Float32, voids NaN), band unit unit ("" for none) and CRS crs (NULL: the sample's). */
static void write_scaled_hood(const char* dst, double to_m, const char* unit, const char* crs)
{
    char hood[1024];
    REQUIRE_DATA_FILE(hood, "TP_SAMPLE_DATA_DIR", HOOD);
    GDALAllRegister();
    GDALDatasetH in = GDALOpen(hood, GA_ReadOnly);
    ASSERT_TRUE(in != NULL);
    const int w = GDALGetRasterXSize(in), h = GDALGetRasterYSize(in);
    float* z = malloc((size_t)w * h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    GDALRasterBandH b = GDALGetRasterBand(in, 1);
    ASSERT_TRUE(GDALRasterIO(b, GF_Read, 0, 0, w, h, z, w, h, GDT_Float32, 0, 0) == CE_None);
    int has_nd = 0;
    const double nd = GDALGetRasterNoDataValue(b, &has_nd);
    for (size_t i = 0; i < (size_t)w * h; ++i)
        z[i] = has_nd && z[i] == (float)nd ? NAN : (float)(z[i] / to_m);
    GDALDatasetH out = GDALCreate(GDALGetDriverByName("GTiff"), dst, w, h, 1, GDT_Float32, NULL);
    ASSERT_TRUE(out != NULL);
    double gt[6];
    GDALGetGeoTransform(in, gt);
    GDALSetGeoTransform(out, gt);
    if (crs) {
        OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
        ASSERT_TRUE(OSRSetFromUserInput(srs, crs) == OGRERR_NONE);
        GDALSetSpatialRef(out, srs);
        OSRDestroySpatialReference(srs);
    } else {
        GDALSetProjection(out, GDALGetProjectionRef(in));
    }
    GDALRasterBandH ob = GDALGetRasterBand(out, 1);
    GDALSetRasterNoDataValue(ob, NAN);
    if (unit[0])
        GDALSetRasterUnitType(ob, unit);
    ASSERT_TRUE(GDALRasterIO(ob, GF_Write, 0, 0, w, h, z, w, h, GDT_Float32, 0, 0) == CE_None);
    GDALClose(out);
    GDALClose(in);
    free(z);
}

/* point's elevation and slope at POS ("10n E N") on dem, with one DEM option (opt NULL: none). */
static void point_at(const char* dem, const char* pos, const char* opt, const char* val,
                     double* elevation, double* slope)
{
    char out[256], json[8192], err[8192];
    snprintf(out, sizeof out, "%s/at.json", tmp_dir());
    remove(out);
    const char* with[] = {opt, val, dem, pos, "--json", out, NULL};
    const char* without[] = {dem, pos, "--json", out, NULL};
    int rc = tp_test_run_terrapatch("point", opt ? with : without, err, sizeof err);
    if (rc != 0)
        FAIL("point %s %s: exit %d: %s", dem, pos, rc, err);
    tp_test_read_text(out, json, sizeof json);
    *elevation = tp_test_json_number_after(json, NULL, "elevation_m");
    *slope = tp_test_json_number_after(json, NULL, "slope_deg");
}

/* 1.3: a DEM in feet (band unit "ft") or US survey feet (a vertical CRS in ftUS, no band unit)
 * is converted to metres: the same heights and slopes as the sample in metres it was made from
 * (today: heights x3.28, slopes steeper); info says so; --z-unit overrides; an unknown unit is
 * a warning naming it. */
TEST(heights_in_feet_are_converted_to_metres)
{
    char hood[1024], ft[256], usft[256], odd[256], err[8192], text[16384];
    REQUIRE_DATA_FILE(hood, "TP_SAMPLE_DATA_DIR", HOOD);
    snprintf(ft, sizeof ft, "%s/hood_ft.tif", tmp_dir());
    snprintf(usft, sizeof usft, "%s/hood_usft.tif", tmp_dir());
    snprintf(odd, sizeof odd, "%s/hood_odd.tif", tmp_dir());
    write_scaled_hood(ft, 0.3048, "ft", NULL);
    /* WGS 84 / UTM 10N + NAVD88 height (ftUS) */
    write_scaled_hood(usft, 1200.0 / 3937.0, "", "EPSG:32610+6360");
    write_scaled_hood(odd, 1.0, "furlong", NULL);
    /* three posts on the mountain's flank (UTM 10N, metres) */
    const char* pos[] = {"10n 601000 5026000", "10n 598500 5023500", "10n 603900 5029100"};
    for (int k = 0; k < 3; ++k) {
        double h_m, s_m, h, s;
        point_at(hood, pos[k], NULL, NULL, &h_m, &s_m);
        ASSERT_TRUE(h_m > 1000 && h_m < 3500);
        point_at(ft, pos[k], NULL, NULL, &h, &s);
        EXPECT_NEAR(h, h_m, 0.06); /* the stores' height steps: 1 m source, fine float one */
        EXPECT_NEAR(s, s_m, 0.1);
        point_at(usft, pos[k], NULL, NULL, &h, &s);
        EXPECT_NEAR(h, h_m, 0.06); /* (1200/3937 m: info's factor is checked below) */
        EXPECT_NEAR(s, s_m, 0.1);
        /* --z-unit m: the file's feet read as metres, on purpose */
        point_at(ft, pos[k], "--z-unit", "m", &h, &s);
        EXPECT_NEAR(h, h_m / 0.3048, 0.1);
    }
    const char* info[] = {ft, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("info", info, text, sizeof text, err, sizeof err));
    EXPECT_CONTAINS(text, "international foot (band unit 'ft'): converted to metres (x 0.3048)");
    const char* info_us[] = {"--json", usft, NULL};
    ASSERT_EQ_INT(0,
                  tp_test_run_terrapatch_out("info", info_us, text, sizeof text, err, sizeof err));
    EXPECT_NEAR(tp_test_json_number_after(text, NULL, "z_to_m"), 1200.0 / 3937.0, 1e-12);
    EXPECT_CONTAINS(text, "NAVD88 height (ftUS) (as the file states)");
    const char* info_odd[] = {odd, NULL};
    ASSERT_EQ_INT(0,
                  tp_test_run_terrapatch_out("info", info_odd, text, sizeof text, err, sizeof err));
    EXPECT_CONTAINS(err, "warning: ");
    EXPECT_CONTAINS(err, "unit 'furlong' is not one terrapatch knows");
    const char* bad[] = {"--z-unit", "yards", ft, NULL};
    EXPECT_EQ_INT(2, tp_test_run_terrapatch("info", bad, err, sizeof err));
    EXPECT_CONTAINS(err, "--z-unit: expected m, ft or us-ft, got yards");
}

/* 1.3: the vertical datum is said only where it is known: the Mt Hood sample (a lidar-derived
 * GeoTIFF that states none) is not "metres above the EGM96 geoid"; SRTM's is assumed, and said
 * to be. */
TEST(vertical_datum_said_only_where_known)
{
    char hood[1024], tile[1024], text[16384], err[8192];
    REQUIRE_DATA_FILE(hood, "TP_SAMPLE_DATA_DIR", HOOD);
    REQUIRE_DATA_FILE(tile, "TP_SHARED_DATA_DIR", TILE);
    const char* a[] = {hood, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("info", a, text, sizeof text, err, sizeof err));
    EXPECT_TRUE(strstr(text, "EGM96") == NULL);
    EXPECT_CONTAINS(text, "vertical datum: unknown (the file states none)");
    const char* b[] = {tile, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("info", b, text, sizeof text, err, sizeof err));
    EXPECT_CONTAINS(text, "assumed EGM96 geoid (SRTM's specification)");
}

/* Runs sh -c script with $T the terrapatch binary; its exit status. */
static int sh(const char* script)
{
    const char* exe = getenv("TP_TERRAPATCH");
    if (!exe)
        SKIP("TP_TERRAPATCH not set");
    char cmd[10240];
    snprintf(cmd, sizeof cmd, "T='%s'; %s", exe, script);
    int rc = system(cmd);
    return WIFEXITED(rc) ? WEXITSTATUS(rc) : 128 + WTERMSIG(rc);
}

/* 3.3: the temporary file of a cached store's build killed with -9 (no handler runs) is removed
 * by the next run that uses the cache, which then builds the store. */
TEST(temporary_files_of_a_killed_cache_build_are_swept)
{
    char tile[1024], cache[256], script[8192], err[8192];
    REQUIRE_DATA_FILE(tile, "TP_SHARED_DATA_DIR", TILE);
    snprintf(cache, sizeof cache, "%s/killed-cache", tmp_dir());
    /* start a build, wait for its temporary file, kill -9 it */
    snprintf(script, sizeof script,
             "mkdir -p '%s' && { \"$T\" point --cache-dir '%s' '%s' 42.5 1.5 >/dev/null 2>&1 & "
             "pid=$!; i=0; while [ $i -lt 600 ] && ! ls '%s'/*.tpt.tmp* >/dev/null 2>&1; do "
             "sleep 0.05; i=$((i+1)); done; kill -9 $pid; wait $pid; "
             "ls '%s'/*.tpt.tmp* >/dev/null 2>&1; }",
             cache, cache, tile, cache, cache);
    ASSERT_EQ_INT(0, sh(script)); /* the killed build left its temporary file */
    const char* args[] = {"--cache-dir", cache, tile, "42.5", "1.5", NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("point", args, err, sizeof err));
    EXPECT_CONTAINS(err, "that a killed build left in");
    /* the store is there: N42E001-KEY.tpt, not only a lock file */
    snprintf(script, sizeof script, "ls '%s'/N42E001-*.tpt >/dev/null 2>&1", cache);
    EXPECT_EQ_INT(0, sh(script));
    snprintf(script, sizeof script, "! ls '%s'/*.tmp* >/dev/null 2>&1", cache);
    EXPECT_EQ_INT(0, sh(script));
}

/* 3.3: two processes asking for the same cached store share one build: one builds, the other
 * waits for it and reads the same store. */
TEST(two_processes_share_one_cache_build)
{
    char tile[1024], cache[256], script[8192], e1[256], e2[256], t1[8192], t2[8192];
    REQUIRE_DATA_FILE(tile, "TP_SHARED_DATA_DIR", TILE);
    snprintf(cache, sizeof cache, "%s/shared-cache", tmp_dir());
    snprintf(e1, sizeof e1, "%s/one.err", tmp_dir());
    snprintf(e2, sizeof e2, "%s/two.err", tmp_dir());
    snprintf(script, sizeof script,
             "mkdir -p '%s' && { \"$T\" point --cache-dir '%s' '%s' 42.5 1.5 >/dev/null 2>'%s' & "
             "a=$!; \"$T\" point --cache-dir '%s' '%s' 42.5 1.5 >/dev/null 2>'%s' & b=$!; "
             "wait $a && wait $b; }",
             cache, cache, tile, e1, cache, tile, e2);
    ASSERT_EQ_INT(0, sh(script));
    tp_test_read_text(e1, t1, sizeof t1);
    tp_test_read_text(e2, t2, sizeof t2);
    const int built =
        (strstr(t1, "building a store") != NULL) + (strstr(t2, "building a store") != NULL);
    EXPECT_EQ_INT(1, built);
    EXPECT_TRUE(strstr(t1, "waiting for it") || strstr(t2, "waiting for it"));
}

/* 4.8: info of a grid that takes seconds (here 2100 x 2100 posts, over the 2048^2 at which
 * the steps are said) says each step on stderr, a line each (it was silent for 20 s on a 3601^2
 * tile); a small one says nothing. */
TEST(info_of_a_large_grid_says_its_steps)
{
    char path[256], out[65536], err[8192];
    snprintf(path, sizeof path, "%s/large.tif", tmp_dir());
    const int n = 2100;
    GDALAllRegister();
    GDALDatasetH ds = GDALCreate(GDALGetDriverByName("GTiff"), path, n, n, 1, GDT_Float32, NULL);
    ASSERT_TRUE(ds != NULL);
    const double gt[6] = {500000, 10, 0, 4500000, 0, -10};
    GDALSetGeoTransform(ds, (double*)gt);
    OGRSpatialReferenceH srs = OSRNewSpatialReference(NULL);
    ASSERT_TRUE(OSRImportFromEPSG(srs, 32633) == OGRERR_NONE);
    GDALSetSpatialRef(ds, srs);
    OSRDestroySpatialReference(srs);
    float* row = malloc((size_t)n * sizeof *row);
    ASSERT_TRUE(row != NULL);
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x)
            row[x] = (float)(100.0 + 0.5 * x + 0.25 * y);
        ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Write, 0, y, n, 1, row, n, 1,
                                 GDT_Float32, 0, 0) == CE_None);
    }
    free(row);
    GDALClose(ds);
    const char* args[] = {path, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("info", args, out, sizeof out, err, sizeof err));
    EXPECT_CONTAINS(err, "putting 2100x2100 samples on the 2100x2100 render grid ...\n");
    EXPECT_CONTAINS(err, "render grid done (");
    EXPECT_CONTAINS(err, "patches done (");
    EXPECT_TRUE(strchr(err, '\r') == NULL);
    char hood[1024];
    REQUIRE_DATA_FILE(hood, "TP_SAMPLE_DATA_DIR", HOOD);
    const char* small[] = {hood, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch_out("info", small, out, sizeof out, err, sizeof err));
    EXPECT_TRUE(strstr(err, "render grid done") == NULL);
}

#define TESTS(X)                                                                                   \
    X(virtual_paths_work_in_every_command)                                                         \
    X(dem_options_are_accepted_by_every_command)                                                   \
    X(heightmap_options_are_accepted_by_every_command)                                             \
    X(ascii_grid_without_prj_takes_crs)                                                            \
    X(store_refuses_dem_options_the_same_way_everywhere)                                           \
    X(damaged_store_header_is_said_to_be_one)                                                      \
    X(bytes_after_the_footer_are_refused)                                                          \
    X(non_regular_inputs_are_refused_on_every_path)                                                \
    X(build_refuses_sources_far_apart)                                                             \
    X(heights_in_feet_are_converted_to_metres)                                                     \
    X(vertical_datum_said_only_where_known)                                                        \
    X(temporary_files_of_a_killed_cache_build_are_swept)                                           \
    X(two_processes_share_one_cache_build)                                                         \
    X(info_of_a_large_grid_says_its_steps)
TP_TEST_MAIN(TESTS)
