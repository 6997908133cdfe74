/*
 * cmd_info.c - `terrapatch info [options] DEM`: reads a DEM, builds the render grid and the
 * resident terrain exactly as the viewer will, and prints them: the raster as read (band 1),
 * the metric render grid (CRS, zone, warp, voids) and the patches (fit, levels, strips,
 * quantisation, memory).
 */
#include "info.h"
#include "terrapatch.h"
#include "cli.h"
#include "extent.h"
#include "json.h"
#include "options.h"
#include "point_readout.h"
#include "scene.h"
#include "store_scene.h"
#include "terrain_open.h"

#include "tp_core.h"
#include "tp_geo.h"
#include "tp_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct info_options {
    tp_scene_options scene;
    int json;
    const char* path;
} info_options;

static void print_help(void)
{
    fputs("usage: terrapatch info [options] DEM|STORE.tpt|IMAGERY.tpi|LIGHT.tpl\n"
          "\n"
          "Reads band 1 of DEM (any raster GDAL opens), puts it on the metric grid the viewer\n"
          "draws (geographic DEMs are warped to the UTM/UPS zone of their centre), tiles it\n"
          "into patches, and describes each stage. Given a store (.tpt, made by 'terrapatch\n"
          "build'), reads and checks every node and describes the store (the DEM options do\n"
          "not apply to it), and the imagery pyramid (.tpi) and light map (.tpl) beside it if\n"
          "there are. Given an imagery pyramid (.tpi, made by 'terrapatch imagery') or a day's\n"
          "light map (.tpl, made by 'terrapatch light --day'), reads and checks every block\n"
          "and describes its levels (and a light map's day).\n"
          "\n"
          "options:\n",
          stdout);
    tp_scene_options_help(stdout);
    fputs("  --json              print one JSON object instead of text\n"
          "  -h, --help          show this help\n"
          "\n"
          "Heights are in metres: a DEM in feet or US survey feet (its band unit, else its\n"
          "vertical CRS; --z-unit overrides) is converted, and info says so. The vertical\n"
          "datum is the one the file states (SRTM and DTED: assumed EGM96, their\n"
          "specification), else unknown; heights are never made ellipsoidal.\n"
          "Exit status: 0 success, 1 the DEM could not be read or tiled or the store has a\n"
          "damaged node, 2 usage error.\n",
          stdout);
}

/* Returns -1 when the options are fine, else the exit code to return (help, usage error). */
static int parse_options(int argc, char** argv, info_options* o)
{
    *o = (info_options){0};
    tp_scene_options_default(&o->scene);
    const tp_option options[] = {TP_OPT_FLAG("--json", &o->json)};
    tp_options p;
    tp_options_init(&p, "info", argc, argv, print_help);
    tp_options_add(&p, options, TP_OPTIONS_COUNT(options), NULL, NULL);
    tp_scene_options_add(&p, &o->scene);
    const char* extra = NULL;
    for (int c; (c = tp_options_next(&p)) != TP_OPTIONS_END;) {
        if (c == TP_OPTIONS_EXIT)
            return p.exit;
        if (!o->path) /* an operand: the DEM, then the first one too many */
            o->path = p.value;
        else if (!extra)
            extra = p.value;
    }
    if (!o->path)
        return tp_cli_usage_at("info", "missing DEM file", "");
    if (extra)
        return tp_cli_usage_at("info", "expected one DEM file, got extra argument", extra);
    return -1;
}

static const char* fit_name(tp_fit fit)
{
    return fit == TP_FIT_RESAMPLE ? "resample" : "pad";
}

/* The render grid's UTM/UPS zone ("31n", "UPS north"); 0 (and "") when it is in none. */
static int zone_text(const tp_render_grid* g, char* out, size_t cap)
{
    out[0] = '\0';
    return g->utm_zone >= 0 &&
           tp_zone_format(g->utm_zone, g->northp, TP_ZONE_STYLE_LONG, out, cap, NULL) == TP_OK;
}

static void print_text(const tp_scene* sc, const char* path)
{
    const tp_dem* dem = sc->dem;
    const tp_render_grid* g = sc->grid;
    const tp_terrain_info* in = &sc->info;
    const double* gt = dem->geotransform;
    char zone[TP_ZONE_TEXT_SIZE];
    tp_crs_info crs = {0}; /* stays zero (no name, not geographic) if GDAL cannot read it */
    tp_crs_describe(dem->crs_wkt, &crs, NULL);

    printf("file           %s\n", path);
    printf("driver         %s\n", dem->driver);
    printf("data type      %s%s%s\n", dem->data_type, dem->units[0] ? ", units " : "", dem->units);
    if (dem->z_to_m != 1.0)
        printf("heights unit   %s (%s): converted to metres (x %.10g)\n", dem->z_unit,
               dem->z_unit_from, dem->z_to_m);
    else if (dem->z_unit_from[0])
        printf("heights unit   metres (%s)\n", dem->z_unit_from);
    else
        printf(
            "heights unit   not stated by the file: taken as metres (--z-unit says otherwise)\n");
    printf("size           %d x %d samples\n", dem->width, dem->height);
    if (dem->epsg)
        printf("CRS            EPSG:%d (%s)\n", dem->epsg, crs.name);
    else if (dem->crs_wkt[0])
        printf("CRS            %s (no EPSG code)\n", crs.name[0] ? crs.name : dem->crs_wkt);
    else
        printf("CRS            none in the file\n");
    if (dem->has_geotransform) {
        printf("geotransform   %.17g, %.17g, %.17g, %.17g, %.17g, %.17g\n", gt[0], gt[1], gt[2],
               gt[3], gt[4], gt[5]);
        printf("pixel size     %.10g x %.10g %s\n", fabs(gt[1]), fabs(gt[5]),
               crs.geographic ? "degrees" : "CRS units");
    } else {
        printf("geotransform   none in the file: %.10g m posts, north-west corner at (0, 0)\n",
               fabs(gt[1]));
    }
    printf("band 1         min %.10g, max %.10g m, %zu voids", dem->min_m, dem->max_m,
           dem->void_count);
    if (dem->has_nodata)
        printf(" (nodata tag %.10g)\n", dem->nodata_value);
    else
        printf(" (no nodata tag)\n");
    char datum[256];
    tp_heights_datum(dem->driver, dem->vertical_datum, datum, sizeof datum);
    printf("heights        vertical datum: %s;\n"
           "               never converted to ellipsoidal heights\n",
           datum);

    printf("\nrender grid\n");
    printf("  CRS          %s%s\n", g->crs_name, g->epsg ? "" : "");
    if (g->epsg)
        printf("  EPSG         %d\n", g->epsg);
    printf("  UTM zone     %s\n", zone_text(g, zone, sizeof zone) ? zone : "none");
    printf("  to WGS84     %s", tp_georef_datum_note(sc->georef));
    double acc = tp_georef_datum_accuracy_m(sc->georef);
    if (acc > 0)
        printf(" (accuracy %.3g m)\n", acc);
    else if (acc < 0 && tp_georef_has_geo(sc->georef))
        printf(" (ballpark: datum grids missing, expect a metre or more)\n");
    else
        printf("\n");
    printf("  size         %d x %d samples, spacing %.6g m\n", g->width, g->height, g->spacing_m);
    if (g->warped)
        printf("  warp         from the DEM's CRS; error at %zu source posts: max %.4g m, RMS "
               "%.4g m\n",
               g->warp_posts, g->warp_max_error_m, g->warp_rms_error_m);
    else
        printf("  warp         none (the DEM's own grid)\n");
    printf("  voids        %zu filled (interior), %zu in large voids, %zu outside the data\n",
           g->filled_samples, g->large_void_samples, g->outside_samples);
    double ext[4];
    tp_proj_extent(sc->georef, sc->grid->width, sc->grid->height, ext);
    printf("  extent       E %.3f .. %.3f, N %.3f .. %.3f\n", ext[0], ext[2], ext[1], ext[3]);
    int crosses = 0;
    tp_error why;
    int geo = tp_geo_extent(sc->georef, sc->grid->width, sc->grid->height, ext, &crosses, &why);
    if (geo > 0)
        printf("  geographic   lat %.6f .. %.6f, lon %.6f .. %.6f%s\n", ext[0], ext[2], ext[1],
               ext[3], crosses ? " (crosses the antimeridian)" : "");
    else if (geo < 0)
        printf("  geographic   not available: an edge post of the render grid is outside what "
               "the zone converts (%s)\n", why.message);

    printf("\npatches\n");
    printf("  fitted size  %d x %d samples (%s", in->width, in->height, fit_name(in->fit));
    if (in->fit == TP_FIT_RESAMPLE)
        printf(" from %d x %d", in->src_width, in->src_height);
    printf(")\n");
    printf("  fit error    max %.6g m, RMS %.6g m\n", in->fit_max_error_m, in->fit_rms_error_m);
    printf("  patch size   %d x %d samples (n = %d)\n", in->patch_size, in->patch_size, in->n);
    printf("  patches      %d x %d = %d\n", in->patch_cols, in->patch_rows, in->patch_count);
    printf("  levels       %d (k = 0..%d, k = %d is full resolution)\n", in->levels, in->n, in->n);
    printf("  strip indices");
    for (int k = 0; k <= in->n; ++k)
        printf("%s k=%d: %zu", k ? "," : "", k, tp_strip_index_count(k));
    printf("\n");
    printf("  height step  %.10g m (max quantisation error %.6g m)\n", in->height_step_m,
           in->quant_max_error_m);
    printf("  drawn range  %.10g to %.10g m\n", in->min_height_m, in->max_height_m);
    printf("  samples      %zu valid, %zu filled, %zu nodata, %zu padding\n", in->valid_samples,
           in->filled_samples, in->nodata_samples, in->padding_samples);
    printf("  resident     %zu bytes (%.3f bytes per source sample)\n", in->resident_bytes,
           in->bytes_per_source_sample);
}

/* One line per entry of a '\n'-separated list (the DEM's warnings). */
static void json_lines(tp_json* j, const char* text)
{
    tp_json_array_begin(j);
    while (*text) {
        const char* nl = strchr(text, '\n');
        size_t len = nl ? (size_t)(nl - text) : strlen(text);
        char line[1024];
        snprintf(line, sizeof line, "%.*s", (int)len, text);
        tp_json_string(j, line);
        text += len + (nl ? 1 : 0);
    }
    tp_json_array_end(j);
}

/* key: value pairs of the JSON object. */
static void key_string(tp_json* j, const char* key, const char* v)
{
    tp_json_member_string(j, key, v);
}
static void key_int(tp_json* j, const char* key, long long v)
{
    tp_json_member_int(j, key, v);
}
static void key_number(tp_json* j, const char* key, double v)
{
    tp_json_member_number(j, key, v);
}
static void key_size(tp_json* j, const char* key, size_t v)
{
    tp_json_member_size(j, key, v);
}
static void key_bool(tp_json* j, const char* key, int v)
{
    tp_json_member_bool(j, key, v);
}
static void key_numbers(tp_json* j, const char* key, const double* v, int count)
{
    tp_json_key(j, key);
    tp_json_array_begin(j);
    for (int i = 0; i < count; ++i)
        tp_json_number(j, v[i]);
    tp_json_array_end(j);
}

static void print_json(const tp_scene* sc, const char* path)
{
    const tp_dem* dem = sc->dem;
    const tp_render_grid* g = sc->grid;
    const tp_terrain_info* in = &sc->info;
    tp_json j;
    tp_json_init(&j, stdout);
    tp_json_object_begin(&j);

    /* The raster as read (band 1). */
    key_string(&j, "file", path);
    key_string(&j, "driver", dem->driver);
    key_string(&j, "data_type", dem->data_type);
    key_string(&j, "units", dem->units);
    key_string(&j, "z_unit", dem->z_unit);
    key_number(&j, "z_to_m", dem->z_to_m);
    key_int(&j, "width", dem->width);
    key_int(&j, "height", dem->height);
    key_number(&j, "min", dem->min_m);
    key_number(&j, "max", dem->max_m);
    key_size(&j, "voids", dem->void_count);
    tp_json_key(&j, "nodata_value");
    if (dem->has_nodata)
        tp_json_number(&j, dem->nodata_value);
    else
        tp_json_null(&j);
    tp_json_key(&j, "epsg");
    if (dem->epsg)
        tp_json_int(&j, dem->epsg);
    else
        tp_json_null(&j);
    key_string(&j, "crs_wkt", dem->crs_wkt);
    key_bool(&j, "has_geotransform", dem->has_geotransform);
    key_numbers(&j, "geotransform", dem->geotransform, 6);
    char datum[256];
    tp_heights_datum(dem->driver, dem->vertical_datum, datum, sizeof datum);
    key_string(&j, "vertical_datum", datum);
    tp_json_key(&j, "warnings");
    json_lines(&j, dem->warnings);

    /* The metric render grid. */
    tp_json_key(&j, "crs");
    if (g->epsg)
        tp_json_int(&j, g->epsg);
    else
        tp_json_string(&j, g->crs_name);
    key_string(&j, "render_crs_name", g->crs_name);
    tp_json_key(&j, "utm_zone");
    char zone[TP_ZONE_TEXT_SIZE];
    if (zone_text(g, zone, sizeof zone))
        tp_json_string(&j, zone);
    else
        tp_json_null(&j);
    key_string(&j, "datum_to_wgs84", tp_georef_datum_note(sc->georef));
    key_number(&j, "datum_accuracy_m", tp_georef_datum_accuracy_m(sc->georef));
    tp_json_key(&j, "render_grid");
    tp_json_array_begin(&j);
    tp_json_int(&j, g->width);
    tp_json_int(&j, g->height);
    tp_json_array_end(&j);
    key_numbers(&j, "render_geotransform", g->geotransform, 6);
    key_number(&j, "spacing_m", g->spacing_m);
    key_bool(&j, "warped", g->warped);
    key_number(&j, "warp_max_error_m", g->warp_max_error_m);
    key_number(&j, "warp_rms_error_m", g->warp_rms_error_m);
    key_size(&j, "void_filled", g->filled_samples);
    key_size(&j, "large_void_samples", g->large_void_samples);
    key_size(&j, "outside_samples", g->outside_samples);
    double ext[4];
    tp_proj_extent(sc->georef, sc->grid->width, sc->grid->height, ext);
    key_numbers(&j, "extent_proj", ext, 4);
    tp_json_key(&j, "extent_geo");
    int crosses = 0;
    tp_error why;
    if (tp_geo_extent(sc->georef, sc->grid->width, sc->grid->height, ext, &crosses, &why) > 0) {
        tp_json_array_begin(&j); /* south, west, north, east: west > east across the antimeridian */
        for (int i = 0; i < 4; ++i)
            tp_json_number(&j, ext[i]);
        tp_json_array_end(&j);
    } else {
        tp_json_null(&j);
    }
    key_bool(&j, "extent_crosses_antimeridian", crosses);
    tp_json_key(&j, "render_warnings");
    json_lines(&j, g->warnings);

    /* The patches. */
    key_string(&j, "fit", fit_name(in->fit));
    tp_json_key(&j, "grid");
    tp_json_array_begin(&j);
    tp_json_int(&j, in->width);
    tp_json_int(&j, in->height);
    tp_json_array_end(&j);
    key_numbers(&j, "grid_geotransform", in->geotransform, 6);
    key_number(&j, "fit_max_error_m", in->fit_max_error_m);
    key_number(&j, "fit_rms_error_m", in->fit_rms_error_m);
    key_int(&j, "patch", in->patch_size);
    tp_json_key(&j, "patches");
    tp_json_array_begin(&j);
    tp_json_int(&j, in->patch_cols);
    tp_json_int(&j, in->patch_rows);
    tp_json_array_end(&j);
    key_int(&j, "levels", in->levels);
    tp_json_key(&j, "strip_indices");
    tp_json_array_begin(&j);
    for (int k = 0; k <= in->n; ++k)
        tp_json_size(&j, tp_strip_index_count(k));
    tp_json_array_end(&j);
    key_number(&j, "height_step_m", in->height_step_m);
    key_number(&j, "quant_max_error_m", in->quant_max_error_m);
    key_number(&j, "drawn_min_m", in->min_height_m);
    key_number(&j, "drawn_max_m", in->max_height_m);
    key_size(&j, "valid_samples", in->valid_samples);
    key_size(&j, "filled_samples", in->filled_samples);
    key_size(&j, "nodata_samples", in->nodata_samples);
    key_size(&j, "padding_samples", in->padding_samples);
    key_size(&j, "resident_bytes", in->resident_bytes);
    key_number(&j, "bytes_per_sample", in->bytes_per_source_sample);

    tp_json_object_end(&j);
}

int tp_cli_info(int argc, char** argv)
{
    info_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    const size_t len = strlen(o.path);
    if (len > 4 && (!strcmp(o.path + len - 4, ".tpi") || !strcmp(o.path + len - 4, ".tpl")))
        return tp_info_imagery(o.path, o.json); /* a file or a URL */
    int is_store;
    if ((code = tp_terrain_classify("info", o.path, &o.scene, &is_store)) >= 0)
        return code;
    if (is_store)
        return tp_info_store(o.path, o.json);
    tp_scene sc;
    if ((code = tp_scene_load(o.path, &o.scene, &sc)) != TP_EXIT_OK)
        return code;
    if (o.json)
        print_json(&sc, o.path);
    else
        print_text(&sc, o.path);
    tp_scene_free(&sc);
    return tp_cli_finish(TP_EXIT_OK);
}
