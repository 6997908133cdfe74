/*
 * test_profile_cli.c - `terrapatch profile` (app/commands/cmd_profile.c) run as a child on stores
 * it builds, its figures measured again here:
 *   - the GPX track of data/vectors over N42E001: the track's latitude/longitude read here
 *     with OGR's C API, put into UTM 31N with GeographicLib (tp_geo_to_utmups, not OGR/PROJ),
 *     every leg split into equal pieces no longer than the grid spacing, the heights asked of
 *     the ground (app/scene/ground.c on the same store); lengths 2D and 3D, climb, descent, lowest,
 *     highest, steepest from those; the ellipsoidal length from GeographicLib's geodesics; the
 *     start against GDAL's own reading of the .hgt;
 *   - bad input: an unreadable file, an empty GPX, a file without a line, a --feature beyond
 *     the lines, a route across a void (N42E001's warp collar), a route leaving the DEM
 *     (storml_elev.tif, which has no collar): exit 1, a message naming the file, nothing written;
 *   - --through (issue 31): the GPX track's vertices typed on the command line (repeated and
 *     ';'-separated) give the profile the file gives, figure for figure and sample for sample;
 *     on mt_hood (UTM, its render grid its own grid, integer heights kept exactly) a route
 *     through four post centres typed in three forms (decimal degrees, DMS, UTM), placed here
 *     with OGR/PROJ from the file's geotransform: the samples every 30 m or less, their
 *     positions and distances, and their heights against the file's posts read with GDAL (at
 *     the vertices the post itself; between them within the four posts around); positions off
 *     the DEM or in a void: exit 1, nothing written.
 */
#define _POSIX_C_SOURCE 200809L

#include "tp_test.h"
#include "tp_geo.h"
#include "tp_io.h"

#include "tp_test_child.h"

#include "ground.h"
#include "store_scene.h"

#include <gdal.h>
#include <ogr_api.h>
#include <ogr_srs_api.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

/* The test folder (tp_test_child.h). */
static const char* tmp_dir(void) { return tp_test_child_dir("profile"); }

/* Builds dem (from data/) into a store in the temporary folder; its path in store. */
static void build_store(const char* dem_file, char* dem, size_t dem_cap, char* store,
                        size_t store_cap)
{
    if (!tp_test_data_path(dem, dem_cap, "TP_SHARED_DATA_DIR", dem_file))
        SKIP("%s not found (set TP_SHARED_DATA_DIR)", dem_file);
    snprintf(store, store_cap, "%s/%s.tpt", tmp_dir(), dem_file);
    char err[4096];
    const char* args[] = {dem, "-o", store, "--quiet", NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("build", args, err, sizeof err));
}

/* Runs `terrapatch profile store --route route [extra] --json J --csv C --png P` in the
 * temporary folder (out.json, out.csv, out.png). */
static int run_profile(const char* store, const char* route, const char* const* extra, char* err,
                       size_t err_cap)
{
    char json[256], csv[256], png[256];
    snprintf(json, sizeof json, "%s/out.json", tmp_dir());
    snprintf(csv, sizeof csv, "%s/out.csv", tmp_dir());
    snprintf(png, sizeof png, "%s/out.png", tmp_dir());
    remove(json);
    remove(csv);
    remove(png);
    const char* args[24] = {store, "--route", route, "--json", json, "--csv", csv};
    int n = 7;
    for (int i = 0; extra && extra[i]; ++i)
        args[n++] = extra[i];
    args[n] = NULL;
    return tp_test_run_terrapatch("profile", args, err, err_cap);
}

/* The track's vertices (lat, lon) as typed in the GPX, read with OGR here. */
static size_t gpx_track(const char* path, double* lat, double* lon, size_t cap)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpenEx(path, GDAL_OF_VECTOR, NULL, NULL, NULL);
    ASSERT_TRUE(ds != NULL);
    OGRLayerH layer = GDALDatasetGetLayerByName(ds, "tracks");
    ASSERT_TRUE(layer != NULL);
    OGRFeatureH f = OGR_L_GetNextFeature(layer);
    ASSERT_TRUE(f != NULL);
    OGRGeometryH ml = OGR_F_GetGeometryRef(f);
    ASSERT_EQ_INT(1, OGR_G_GetGeometryCount(ml));
    OGRGeometryH line = OGR_G_GetGeometryRef(ml, 0);
    size_t n = (size_t)OGR_G_GetPointCount(line);
    ASSERT_TRUE(n <= cap);
    for (size_t i = 0; i < n; ++i) {
        lon[i] = OGR_G_GetX(line, (int)i);
        lat[i] = OGR_G_GetY(line, (int)i);
    }
    OGR_F_Destroy(f);
    GDALClose(ds);
    return n;
}

typedef struct measured {
    size_t samples;
    double len2, len3, climb, descent, lo, hi, steep_pct, steep_from_m, geodesic;
} measured;

/* The route measured on the ground here (see the file's comment). */
static measured measure_here(tp_ground* g, const double* lat, const double* lon, size_t nv)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const double step = fabs(sc->info.header.geotransform[1]);
    measured m = {0};
    m.lo = INFINITY;
    m.hi = -INFINITY;
    double e[64], n[64];
    ASSERT_TRUE(nv <= 64);
    for (size_t i = 0; i < nv; ++i) {
        int zone, northp;
        ASSERT_OK(tp_geo_to_utmups(lat[i], lon[i], &zone, &northp, &e[i], &n[i], NULL));
        ASSERT_EQ_INT(31, zone);
        if (i) {
            double a1, a2, s;
            ASSERT_OK(tp_geodesic_inverse(lat[i - 1], lon[i - 1], lat[i], lon[i], &a1, &a2, &s,
                                          NULL));
            m.geodesic += s;
        }
    }
    double prev_h = NAN, prev_d = 0.0, d0 = 0.0, best = -1.0;
    for (size_t i = 0; i + 1 < nv; ++i) {
        double len = hypot(e[i + 1] - e[i], n[i + 1] - n[i]);
        int pieces = (int)ceil(len / step);
        if (pieces < 1)
            pieces = 1;
        for (int j = 0; j <= pieces; ++j) {
            if (j == pieces && i + 2 < nv)
                break; /* the next leg starts there */
            double t = (double)j / pieces;
            double x, y, h, d = d0 + t * len;
            tp_tree_world_to_grid(sc->tree, e[i] + t * (e[i + 1] - e[i]),
                                  n[i] + t * (n[i + 1] - n[i]), &x, &y);
            ASSERT_OK(tp_ground_height(g, x, y, &h, NULL));
            ASSERT_FALSE(isnan(h));
            m.samples++;
            m.lo = fmin(m.lo, h);
            m.hi = fmax(m.hi, h);
            if (!isnan(prev_h)) {
                double dd = d - prev_d, dh = h - prev_h;
                m.len2 += dd;
                m.len3 += sqrt(dd * dd + dh * dh);
                m.climb += fmax(0.0, dh);
                m.descent += fmax(0.0, -dh);
                if (fabs(dh) / dd > best) {
                    best = fabs(dh) / dd;
                    m.steep_pct = 100.0 * dh / dd;
                    m.steep_from_m = prev_d;
                }
            }
            prev_h = h;
            prev_d = d;
        }
        d0 += len;
    }
    return m;
}

/* measure_here on the ground of store. */
static measured measure_store(const char* store, const double* lat, const double* lon, size_t nv)
{
    tp_store_scene sc;
    ASSERT_EQ_INT(0, tp_store_scene_open(store, &sc));
    tp_ground* g = NULL;
    ASSERT_OK(tp_ground_create(&sc, NULL, &g, NULL));
    measured m = measure_here(g, lat, lon, nv);
    tp_ground_destroy(g);
    tp_store_scene_close(&sc);
    return m;
}

/* GDAL's own nearest sample of the .hgt at (lat, lon). */
static double hgt_sample(const char* hgt, double lat, double lon)
{
    GDALDatasetH ds = GDALOpen(hgt, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    double gt[6];
    GDALGetGeoTransform(ds, gt);
    int c = (int)floor((lon - gt[0]) / gt[1]), r = (int)floor((lat - gt[3]) / gt[5]);
    float v;
    ASSERT_TRUE(GDALRasterIO(GDALGetRasterBand(ds, 1), GF_Read, c, r, 1, 1, &v, 1, 1,
                             GDT_Float32, 0, 0) == CE_None);
    GDALClose(ds);
    return v;
}

TEST(gpx_track_figures_match_an_independent_measure)
{
    char dem[1024], store[256], gpx[1024], err[4096], json[8192], path[256];
    build_store("N42E001.hgt", dem, sizeof dem, store, sizeof store);
    REQUIRE_DATA_FILE(gpx, "TP_SAMPLE_DATA_DIR", "vectors/coma_pedrosa.gpx");
    const char* png_args[] = {"--png", NULL, NULL};
    char png[256];
    snprintf(png, sizeof png, "%s/out.png", tmp_dir());
    png_args[1] = png;
    int have_gnuplot = access("/usr/bin/gnuplot", X_OK) == 0;
    ASSERT_EQ_INT(0, run_profile(store, gpx, have_gnuplot ? png_args : NULL, err, sizeof err));
    snprintf(path, sizeof path, "%s/out.json", tmp_dir());
    tp_test_read_text(path, json, sizeof json);

    double lat[64], lon[64];
    size_t nv = gpx_track(gpx, lat, lon, 64);
    ASSERT_EQ_INT(7, (int)nv);
    measured m = measure_store(store, lat, lon, nv);

    EXPECT_EQ_INT((int)m.samples, (int)tp_test_json_number_after(json, NULL, "samples"));
    EXPECT_EQ_INT(7, (int)tp_test_json_number_after(json, NULL, "vertices"));
    EXPECT_NEAR(m.len2, tp_test_json_number_after(json, NULL, "length_2d_m"), 1e-3);
    EXPECT_NEAR(m.len3, tp_test_json_number_after(json, NULL, "length_3d_m"), 1e-3);
    EXPECT_NEAR(m.geodesic, tp_test_json_number_after(json, NULL, "length_geodesic_m"), 1e-3);
    EXPECT_NEAR(m.climb, tp_test_json_number_after(json, NULL, "climb_m"), 1e-3);
    EXPECT_NEAR(m.descent, tp_test_json_number_after(json, NULL, "descent_m"), 1e-3);
    EXPECT_NEAR(m.lo, tp_test_json_number_after(json, NULL, "min_elevation_m"), 1e-3);
    EXPECT_NEAR(m.hi, tp_test_json_number_after(json, NULL, "max_elevation_m"), 1e-3);
    EXPECT_NEAR(m.steep_pct, tp_test_json_number_after(json, "\"steepest\"", "grade_pct"), 1e-3);
    EXPECT_NEAR(m.steep_from_m, tp_test_json_number_after(json, "\"steepest\"", "from_distance_m"), 1e-3);
    /* the map's length is the ellipsoid's times the UTM scale near lon 1.46 (0.99977 at 1.54
     * degrees from the central meridian) */
    EXPECT_NEAR(m.len2 / m.geodesic, 0.9996 * (1.0 + pow(1.54 * 3.14159265358979 / 180.0 * 0.7365, 2) / 2),
                2e-5);
    /* climb minus descent is the height gained end to end */
    EXPECT_NEAR(m.climb - m.descent,
                tp_test_json_number_after(json, "\"end\"", "elevation_m") -
                    tp_test_json_number_after(json, "\"start\"", "elevation_m"),
                1e-6);
    /* the start on the ground, and against GDAL's nearest post of the .hgt (3" posts) */
    EXPECT_NEAR(lat[0], tp_test_json_number_after(json, "\"start\"", "lat"), 1e-7);
    EXPECT_NEAR(lon[0], tp_test_json_number_after(json, "\"start\"", "lon"), 1e-7);
    EXPECT_NEAR(hgt_sample(dem, lat[0], lon[0]),
                tp_test_json_number_after(json, "\"start\"", "elevation_m"), 20.0);
    tp_test_note("Arinsal -> Coma Pedrosa: %.1f m 3D, %.1f m 2D, %.1f m ellipsoid, +%.1f / -%.1f "
                 "m, %.1f..%.1f m, steepest %+.1f %%, %zu samples",
                 m.len3, m.len2, m.geodesic, m.climb, m.descent, m.lo, m.hi, m.steep_pct,
                 m.samples);
    EXPECT_GT(m.climb, 1000.0);
    /* the CSV: a header and one row per sample, the last at the 2D length */
    char csv[65536];
    snprintf(path, sizeof path, "%s/out.csv", tmp_dir());
    tp_test_read_text(path, csv, sizeof csv);
    size_t rows = 0;
    for (const char* c = csv; *c; ++c)
        rows += *c == '\n';
    EXPECT_EQ_INT((int)m.samples + 1, (int)rows);
    EXPECT_CONTAINS(csv, "distance_m,e_m,n_m,lat,lon,elevation_m,grade_pct\n0.000,");
    const char* last = csv + strlen(csv) - 2;
    while (last > csv && *last != '\n')
        --last;
    EXPECT_NEAR(m.len2, strtod(last + 1, NULL), 1e-3);
    if (have_gnuplot) {
        char head[8] = {0};
        FILE* f = fopen(png, "rb");
        ASSERT_TRUE(f != NULL);
        ASSERT_EQ_INT(8, (int)fread(head, 1, 8, f));
        fclose(f);
        EXPECT_TRUE(!memcmp(head, "\x89PNG", 4));
    }
}

/* Writes a GeoJSON LineString (lat, lon pairs) as name in the temporary folder. */
static void write_line(const char* name, const double* lat, const double* lon, int n,
                       char* path, size_t cap)
{
    snprintf(path, cap, "%s/%s", tmp_dir(), name);
    FILE* f = fopen(path, "w");
    ASSERT_TRUE(f != NULL);
    fputs("{\"type\":\"FeatureCollection\",\"features\":[{\"type\":\"Feature\",\"properties\":"
          "{\"name\":\"test\"},\"geometry\":{\"type\":\"LineString\",\"coordinates\":[",
          f);
    for (int i = 0; i < n; ++i)
        fprintf(f, "%s[%.9f,%.9f]", i ? "," : "", lon[i], lat[i]);
    fputs("]}}]}\n", f);
    fclose(f);
}

TEST(bad_routes_exit_1_and_write_nothing)
{
    char dem[1024], store[256], err[4096], path[1024], route[256];
    build_store("N42E001.hgt", dem, sizeof dem, store, sizeof store);
    const char* files[] = {"vectors/empty.gpx", "vectors/tristaina.geojson"};
    const char* says[] = {"no features", "has no line to follow (0 points, 2 polygon rings)"};
    for (int i = 0; i < 2; ++i) {
        REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", files[i]);
        EXPECT_EQ_INT(1, run_profile(store, path, NULL, err, sizeof err));
        EXPECT_CONTAINS(err, path);
        EXPECT_CONTAINS(err, says[i]);
        EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "out."));
    }
    /* not a vector file */
    EXPECT_EQ_INT(1, run_profile(store, dem, NULL, err, sizeof err));
    EXPECT_CONTAINS(err, "OGR cannot open it as a vector file");
    EXPECT_CONTAINS(err, "N42E001.hgt");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "out."));
    /* the second line of a file with one */
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", "vectors/coma_pedrosa.gpx");
    const char* second[] = {"--feature", "2", NULL};
    EXPECT_EQ_INT(1, run_profile(store, path, second, err, sizeof err));
    EXPECT_CONTAINS(err, "--feature 2");
    EXPECT_CONTAINS(err, "has 1 line");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "out."));

    /* across a void: from the tile's centre to the collar the warp leaves south-west of it
     * (the render grid's corner post, outside the tile: no height, found on the ground here) */
    tp_store_scene sc;
    ASSERT_EQ_INT(0, tp_store_scene_open(store, &sc));
    tp_ground* g = NULL;
    ASSERT_OK(tp_ground_create(&sc, NULL, &g, NULL));
    const int w = sc.info.header.geometry.src_width, h = sc.info.header.geometry.src_height;
    double corner_h, e, n, lat[2] = {42.5, 0}, lon[2] = {1.5, 0};
    ASSERT_OK(tp_ground_height(g, 0.0, h - 1.0, &corner_h, NULL));
    ASSERT_NAN(corner_h);
    tp_tree_grid_to_world(sc.tree, 0.0, h - 1.0, &e, &n);
    ASSERT_OK(tp_georef_proj_to_geo(sc.georef, e, n, &lat[1], &lon[1], NULL));
    EXPECT_LT(lat[1], 42.0); /* south of the tile */
    tp_ground_destroy(g);
    tp_store_scene_close(&sc);
    write_line("void.geojson", lat, lon, 2, route, sizeof route);
    EXPECT_EQ_INT(1, run_profile(store, route, NULL, err, sizeof err));
    EXPECT_CONTAINS(err, "void.geojson");
    EXPECT_CONTAINS(err, "crosses a void at");
    EXPECT_CONTAINS(err, "nothing written");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "out."));
    (void)w;
}

TEST(route_leaving_the_dem_exits_1)
{
    char dem[1024], store[256], err[4096], route[256];
    build_store("storml_elev.tif", dem, sizeof dem, store, sizeof store);
    tp_store_scene sc;
    ASSERT_EQ_INT(0, tp_store_scene_open(store, &sc));
    const int w = sc.info.header.geometry.src_width, h = sc.info.header.geometry.src_height;
    double lat[2], lon[2], e, n;
    /* from the centre post to 20 posts east of the last column */
    tp_tree_grid_to_world(sc.tree, w / 2, h / 2, &e, &n);
    ASSERT_OK(tp_georef_proj_to_geo(sc.georef, e, n, &lat[0], &lon[0], NULL));
    tp_tree_grid_to_world(sc.tree, w + 20.0, h / 2, &e, &n);
    ASSERT_OK(tp_georef_proj_to_geo(sc.georef, e, n, &lat[1], &lon[1], NULL));
    tp_store_scene_close(&sc);
    write_line("east.geojson", lat, lon, 2, route, sizeof route);
    EXPECT_EQ_INT(1, run_profile(store, route, NULL, err, sizeof err));
    EXPECT_CONTAINS(err, "east.geojson");
    EXPECT_CONTAINS(err, "leaves the DEM at");
    EXPECT_CONTAINS(err, "storml_elev.tif.tpt");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "out."));
    /* the same line the other way round leaves at once */
    double rlat[2] = {lat[1], lat[0]}, rlon[2] = {lon[1], lon[0]};
    write_line("west.geojson", rlat, rlon, 2, route, sizeof route);
    EXPECT_EQ_INT(1, run_profile(store, route, NULL, err, sizeof err));
    EXPECT_CONTAINS(err, "west.geojson) starts outside the DEM: its start is at ");
    EXPECT_CONTAINS(err, "and the DEM covers E ");
    EXPECT_TRUE(strstr(err, "nan") == NULL);
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "out."));
    /* a route 20 degrees east of the store's UTM zone (13N): no latitude or longitude back from
     * the render CRS there, so those of the route itself */
    double flat[2] = {40.0, 40.1}, flon[2] = {-85.0, -85.1};
    write_line("far.geojson", flat, flon, 2, route, sizeof route);
    EXPECT_EQ_INT(1, run_profile(store, route, NULL, err, sizeof err));
    EXPECT_CONTAINS(err, "far.geojson) lies outside the DEM: its start is at 40.000000 -85.000000");
    EXPECT_TRUE(strstr(err, "nan") == NULL);
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "out."));
}

/* The text's steepest piece says what its figures are: the distances along the route between
 * which it runs (the independent measure's start), then the elevations. */
TEST(steepest_piece_is_labelled)
{
    char dem[1024], store[256], gpx[1024], err[4096], text[8192];
    build_store("N42E001.hgt", dem, sizeof dem, store, sizeof store);
    REQUIRE_DATA_FILE(gpx, "TP_SAMPLE_DATA_DIR", "vectors/coma_pedrosa.gpx");
    const char* args[] = {store, "--route", gpx, NULL};
    ASSERT_EQ_INT(0,
                  tp_test_run_terrapatch_out("profile", args, text, sizeof text, err, sizeof err));
    double lat[64], lon[64];
    size_t nv = gpx_track(gpx, lat, lon, 64);
    measured m = measure_store(store, lat, lon, nv);
    char want[200];
    snprintf(want, sizeof want, "steepest    %+.1f %% (%s) between %.1f m and ", m.steep_pct,
             m.steep_pct >= 0 ? "up" : "down", m.steep_from_m);
    EXPECT_CONTAINS(text, want);
    EXPECT_CONTAINS(text, " m along the route, elevation ");
}

/* ---- --through ---- */

/* Runs `terrapatch profile store ARGS... --json DIR/NAME.json --csv DIR/NAME.csv`. */
static int run_profile_named(const char* store, const char* name, const char* const* extra,
                             char* err, size_t err_cap)
{
    char json[256], csv[256];
    snprintf(json, sizeof json, "%s/%s.json", tmp_dir(), name);
    snprintf(csv, sizeof csv, "%s/%s.csv", tmp_dir(), name);
    remove(json);
    remove(csv);
    const char* args[40] = {store};
    int n = 1;
    for (int i = 0; extra[i] && n < 34; ++i)
        args[n++] = extra[i];
    args[n++] = "--json", args[n++] = json, args[n++] = "--csv", args[n++] = csv;
    args[n] = NULL;
    return tp_test_run_terrapatch("profile", args, err, err_cap);
}

/* A profile's CSV: distance, E, N, elevation of each sample. */
typedef struct samples {
    size_t n;
    double *d, *e, *no, *h;
} samples;

static samples read_csv(const char* name)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s.csv", tmp_dir(), name);
    const size_t cap = 4u << 20;
    char* text = malloc(cap);
    ASSERT_TRUE(text != NULL);
    tp_test_read_text(path, text, cap);
    samples s = {0};
    size_t rows = 0;
    for (const char* c = text; *c; ++c)
        rows += *c == '\n';
    s.d = malloc(rows * sizeof *s.d), s.e = malloc(rows * sizeof *s.e);
    s.no = malloc(rows * sizeof *s.no), s.h = malloc(rows * sizeof *s.h);
    const char* line = strchr(text, '\n');
    ASSERT_TRUE(line != NULL);
    for (++line; *line; line = strchr(line, '\n') + 1) {
        double lat, lon;
        ASSERT_EQ_INT(6, sscanf(line, "%lf,%lf,%lf,%lf,%lf,%lf", &s.d[s.n], &s.e[s.n], &s.no[s.n],
                                &lat, &lon, &s.h[s.n]));
        ++s.n;
    }
    free(text);
    return s;
}

static void samples_free(samples* s)
{
    free(s->d), free(s->e), free(s->no), free(s->h);
}

TEST(through_equals_the_same_route_from_a_file)
{
    char dem[1024], store[256], gpx[1024], err[4096], path[256];
    build_store("N42E001.hgt", dem, sizeof dem, store, sizeof store);
    REQUIRE_DATA_FILE(gpx, "TP_SAMPLE_DATA_DIR", "vectors/coma_pedrosa.gpx");
    const char* file_args[] = {"--route", gpx, NULL};
    ASSERT_EQ_INT(0, run_profile_named(store, "file", file_args, err, sizeof err));

    /* the track's vertices as the GPX types them (OGR's reading), on the command line: the
     * first two with --through each, the rest in one value separated by ';' */
    double lat[64], lon[64];
    const size_t nv = gpx_track(gpx, lat, lon, 64);
    ASSERT_EQ_INT(7, (int)nv);
    char text[7][64], rest[512] = "";
    for (size_t i = 0; i < nv; ++i)
        snprintf(text[i], sizeof text[i], "%.17g,%.17g", lat[i], lon[i]);
    for (size_t i = 2; i < nv; ++i)
        snprintf(rest + strlen(rest), sizeof rest - strlen(rest), "%s%s", i > 2 ? "; " : "",
                 text[i]);
    const char* through_args[] = {"--through", text[0], "--through", text[1],
                                  "--through", rest,    NULL};
    const int rc = run_profile_named(store, "through", through_args, err, sizeof err);
    if (rc != 0)
        FAIL("exit %d: %s", rc, err);

    char a[8192], b[8192];
    snprintf(path, sizeof path, "%s/file.json", tmp_dir());
    tp_test_read_text(path, a, sizeof a);
    snprintf(path, sizeof path, "%s/through.json", tmp_dir());
    tp_test_read_text(path, b, sizeof b);
    EXPECT_CONTAINS(b, "\"route\": null");
    EXPECT_CONTAINS(b, "\"through\": [\"");
    EXPECT_CONTAINS(a, "\"through\": null");
    const char* keys[] = {"samples",         "vertices",          "step_m",  "length_3d_m",
                          "length_2d_m",     "length_geodesic_m", "climb_m", "descent_m",
                          "min_elevation_m", "max_elevation_m"};
    for (size_t i = 0; i < sizeof keys / sizeof keys[0]; ++i)
        EXPECT_NEAR(tp_test_json_number_after(a, NULL, keys[i]),
                    tp_test_json_number_after(b, NULL, keys[i]), 1e-6);
    const char* points[] = {"\"end\"", "\"lowest\"", "\"highest\"", "\"steepest\""};
    for (int i = 0; i < 4; ++i) {
        const char* k = i < 3 ? "distance_m" : "from_distance_m";
        EXPECT_NEAR(tp_test_json_number_after(a, points[i], k),
                    tp_test_json_number_after(b, points[i], k), 1e-6);
        EXPECT_NEAR(tp_test_json_number_after(a, points[i], "lat"),
                    tp_test_json_number_after(b, points[i], "lat"), 1e-9);
    }
    EXPECT_NEAR(tp_test_json_number_after(a, "\"steepest\"", "grade_pct"),
                tp_test_json_number_after(b, "\"steepest\"", "grade_pct"), 1e-6);
    /* sample for sample (the CSV's 1 mm digits) */
    samples sa = read_csv("file"), sb = read_csv("through");
    ASSERT_EQ_INT((long long)sa.n, (long long)sb.n);
    size_t apart = 0;
    for (size_t i = 0; i < sa.n; ++i)
        apart += fabs(sa.d[i] - sb.d[i]) > 0.0015 || fabs(sa.e[i] - sb.e[i]) > 0.0015 ||
                 fabs(sa.no[i] - sb.no[i]) > 0.0015 || fabs(sa.h[i] - sb.h[i]) > 0.0015;
    EXPECT_EQ_INT(0, (long long)apart);
    tp_test_note("--through 7 positions: %zu samples, %.3f m 2D, as --route", sb.n,
                 tp_test_json_number_after(b, NULL, "length_2d_m"));
    samples_free(&sa);
    samples_free(&sb);
}

/* mt_hood's posts read with GDAL: heights (NaN for nodata) and the geotransform. */
typedef struct dem_posts {
    int w, h;
    float* z;
    double gt[6];
    OGRSpatialReferenceH srs;
} dem_posts;

static dem_posts read_posts(const char* path)
{
    GDALAllRegister();
    GDALDatasetH ds = GDALOpen(path, GA_ReadOnly);
    ASSERT_TRUE(ds != NULL);
    dem_posts p;
    p.w = GDALGetRasterXSize(ds), p.h = GDALGetRasterYSize(ds);
    p.z = malloc((size_t)p.w * p.h * sizeof *p.z);
    GDALRasterBandH b = GDALGetRasterBand(ds, 1);
    ASSERT_TRUE(GDALRasterIO(b, GF_Read, 0, 0, p.w, p.h, p.z, p.w, p.h, GDT_Float32, 0, 0) ==
                CE_None);
    int has_nd = 0;
    const double nd = GDALGetRasterNoDataValue(b, &has_nd);
    for (size_t i = 0; i < (size_t)p.w * p.h; ++i)
        if (has_nd && p.z[i] == (float)nd)
            p.z[i] = NAN;
    GDALGetGeoTransform(ds, p.gt);
    p.srs = OSRNewSpatialReference(GDALGetProjectionRef(ds));
    OSRSetAxisMappingStrategy(p.srs, OAMS_TRADITIONAL_GIS_ORDER);
    GDALClose(ds);
    return p;
}

/* (e, n) of the DEM's CRS into EPSG code epsg (traditional order: x/longitude first). */
static void transform_to(const dem_posts* p, int epsg, double e, double n, double* x, double* y)
{
    OGRSpatialReferenceH to = OSRNewSpatialReference(NULL);
    ASSERT_EQ_INT(OGRERR_NONE, OSRImportFromEPSG(to, epsg));
    OSRSetAxisMappingStrategy(to, OAMS_TRADITIONAL_GIS_ORDER);
    OGRCoordinateTransformationH ct = OCTNewCoordinateTransformation(p->srs, to);
    ASSERT_TRUE(ct != NULL);
    *x = e, *y = n;
    ASSERT_TRUE(OCTTransform(ct, 1, x, y, NULL));
    OCTDestroyCoordinateTransformation(ct);
    OSRDestroySpatialReference(to);
}

/* Degrees as D°M'S" with hemisphere letters, seconds to 1e-6 (0.03 mm). */
static void dms(double deg, char pos, char neg, char* out, size_t cap)
{
    const char h = deg < 0 ? neg : pos;
    deg = fabs(deg);
    int d = (int)floor(deg), m = (int)floor((deg - d) * 60.0);
    const double sec = (deg - d - m / 60.0) * 3600.0;
    snprintf(out, cap, "%dd%02d'%09.6f\"%c", d, m, sec, h);
}

TEST(through_heights_are_the_dems_posts)
{
    char dem[1024], store[256], err[4096];
    build_store("lf_elev_220_mt_hood_utm.tif", dem, sizeof dem, store, sizeof store);
    dem_posts p = read_posts(dem);
    /* four post centres, no void within the cells the legs cross (checked below) */
    const int col[4] = {150, 420, 700, 880}, row[4] = {120, 260, 180, 610};
    double e[4], n[4];
    char text[4][96];
    for (int i = 0; i < 4; ++i) {
        e[i] = p.gt[0] + (col[i] + 0.5) * p.gt[1];
        n[i] = p.gt[3] + (row[i] + 0.5) * p.gt[5];
        double lon, lat, ue, un;
        transform_to(&p, 4326, e[i], n[i], &lon, &lat);
        if (i == 0 || i == 3) {
            snprintf(text[i], sizeof text[i], "%.10f,%.10f", lat, lon);
        } else if (i == 1) {
            char a[40], b[40];
            dms(lat, 'N', 'S', a, sizeof a);
            dms(lon, 'E', 'W', b, sizeof b);
            snprintf(text[i], sizeof text[i], "%s %s", a, b);
        } else {
            transform_to(&p, 32610, e[i], n[i], &ue, &un); /* WGS 84 / UTM 10N */
            snprintf(text[i], sizeof text[i], "10n %.4f %.4f", ue, un);
        }
    }
    char two[200];
    snprintf(two, sizeof two, "%s;%s", text[1], text[2]);
    const char* args[] = {"--through", text[0], "--through", two, "--through", text[3], NULL};
    const int rc = run_profile_named(store, "hood", args, err, sizeof err);
    if (rc != 0)
        FAIL("exit %d: %s", rc, err);
    samples s = read_csv("hood");

    /* the samples: every leg in equal pieces of 30 m (the posts' spacing) or less */
    size_t want = 1, k = 0, at_vertex[4] = {0};
    double d0 = 0.0;
    for (int i = 0; i + 1 < 4; ++i) {
        const double len = hypot(e[i + 1] - e[i], n[i + 1] - n[i]);
        const size_t pieces = (size_t)ceil(len / 30.0);
        want += pieces;
        at_vertex[i + 1] = at_vertex[i] + pieces;
        for (size_t j = 0; j < pieces && k < s.n; ++j, ++k) {
            const double t = (double)j / (double)pieces;
            EXPECT_NEAR(d0 + t * len, s.d[k], 0.0015);
            EXPECT_NEAR(e[i] + t * (e[i + 1] - e[i]), s.e[k], 0.0015);
            EXPECT_NEAR(n[i] + t * (n[i + 1] - n[i]), s.no[k], 0.0015);
        }
        d0 += len;
    }
    ASSERT_EQ_INT((long long)want, (long long)s.n);
    EXPECT_NEAR(d0, s.d[s.n - 1], 0.0015);
    /* at each vertex the post's own height; between them within the four posts around */
    size_t outside = 0;
    for (int i = 0; i < 4; ++i)
        EXPECT_NEAR(p.z[(size_t)row[i] * p.w + col[i]], s.h[at_vertex[i]], 0.0015);
    for (size_t i = 0; i < s.n; ++i) {
        const double x = (s.e[i] - p.gt[0]) / p.gt[1] - 0.5,
                     y = (s.no[i] - p.gt[3]) / p.gt[5] - 0.5;
        const int x0 = (int)floor(x + 1e-6), y0 = (int)floor(y + 1e-6);
        double lo = INFINITY, hi = -INFINITY;
        for (int q = 0; q < 4; ++q) {
            const int cx = x0 + (q & 1) < p.w ? x0 + (q & 1) : p.w - 1;
            const int cy = y0 + (q >> 1) < p.h ? y0 + (q >> 1) : p.h - 1;
            const double zz = p.z[(size_t)cy * p.w + cx];
            ASSERT_FALSE(isnan(zz)); /* the legs cross no void */
            lo = fmin(lo, zz), hi = fmax(hi, zz);
        }
        outside += s.h[i] < lo - 0.0015 || s.h[i] > hi + 0.0015;
    }
    EXPECT_EQ_INT(0, (long long)outside);
    tp_test_note("mt_hood --through 4 posts: %zu samples, %.1f m, heights %.0f, %.0f, %.0f, %.0f "
                 "m at the vertices",
                 s.n, d0, s.h[at_vertex[0]], s.h[at_vertex[1]], s.h[at_vertex[2]],
                 s.h[at_vertex[3]]);
    samples_free(&s);
    OSRDestroySpatialReference(p.srs);
    free(p.z);
}

TEST(through_positions_off_the_dem_exit_1)
{
    char dem[1024], store[256], err[4096];
    build_store("N42E001.hgt", dem, sizeof dem, store, sizeof store);
    /* off the DEM (with the swapped reading on it), and in the warp collar's void */
    const char* off[] = {"--through", "42.5,1.5", "--through", "1.6,42.6", NULL};
    EXPECT_EQ_INT(1, run_profile_named(store, "off", off, err, sizeof err));
    EXPECT_CONTAINS(err, "--through: position '1.6,42.6'");
    EXPECT_CONTAINS(err, "is outside the DEM");
    EXPECT_CONTAINS(err, "with latitude and longitude swapped");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "off."));
    /* a post of the render grid's corner, outside the tile: no height (as
     * bad_routes_exit_1_and_write_nothing finds it; three posts in, so that rounding keeps it
     * on the grid) */
    tp_store_scene sc;
    ASSERT_EQ_INT(0, tp_store_scene_open(store, &sc));
    tp_ground* g = NULL;
    ASSERT_OK(tp_ground_create(&sc, NULL, &g, NULL));
    const int h = sc.info.header.geometry.src_height;
    double corner_h, e, n, lat, lon;
    ASSERT_OK(tp_ground_height(g, 3.0, h - 4.0, &corner_h, NULL));
    ASSERT_NAN(corner_h);
    tp_tree_grid_to_world(sc.tree, 3.0, h - 4.0, &e, &n);
    ASSERT_OK(tp_georef_proj_to_geo(sc.georef, e, n, &lat, &lon, NULL));
    tp_ground_destroy(g);
    tp_store_scene_close(&sc);
    char in_void[160], two[200];
    snprintf(in_void, sizeof in_void, "%.9f,%.9f", lat, lon);
    snprintf(two, sizeof two, "42.5,1.5; %s", in_void);
    const char* void_[] = {"--through", two, NULL};
    EXPECT_EQ_INT(1, run_profile_named(store, "void", void_, err, sizeof err));
    char said[200];
    snprintf(said, sizeof said, "--through: position '%s'", in_void);
    EXPECT_CONTAINS(err, said);
    EXPECT_CONTAINS(err, "is in a void");
    EXPECT_TRUE(tp_test_nothing_named(tmp_dir(), "void."));
    /* a position that cannot be read, and one alone: usage, before the ground is opened */
    const char* bad[] = {"--through", "42.5,1.5", "--through", "42.5,x", NULL};
    EXPECT_EQ_INT(2, run_profile_named(store, "bad", bad, err, sizeof err));
    EXPECT_CONTAINS(err, "--through '42.5,x'");
    const char* one[] = {"--through", "42.5,1.5", NULL};
    EXPECT_EQ_INT(2, run_profile_named(store, "one", one, err, sizeof err));
    EXPECT_CONTAINS(err, "a route needs 2 positions or more, got one ('42.5,1.5')");
}

#define TESTS(X)                                                                                   \
    X(gpx_track_figures_match_an_independent_measure)                                              \
    X(bad_routes_exit_1_and_write_nothing)                                                         \
    X(route_leaving_the_dem_exits_1)                                                               \
    X(steepest_piece_is_labelled)                                                                  \
    X(through_equals_the_same_route_from_a_file)                                                   \
    X(through_heights_are_the_dems_posts)                                                          \
    X(through_positions_off_the_dem_exit_1)
TP_TEST_MAIN(TESTS)
