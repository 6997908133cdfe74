/*
 * cmd_info.c - `terrapatch info [options] DEM`: reads a DEM, builds the resident terrain
 * exactly as the viewer will, and prints both: the raster as read (band 1) and the grid that
 * is rendered from it (fit, patches, levels, strips, quantisation, memory).
 */
#include "cli.h"
#include "json.h"

#include "tp_core.h"
#include "tp_io.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct info_options {
    int patch_size;
    tp_fit fit;
    int json;
    const char* path;
} info_options;

enum { OPT_PATCH = 256, OPT_FIT, OPT_JSON };

static void print_help(void)
{
    fputs("usage: terrapatch info [options] DEM\n"
          "\n"
          "Reads band 1 of DEM (any raster GDAL opens), builds the patch grid the viewer would\n"
          "draw, and describes both.\n"
          "\n"
          "options:\n"
          "  --patch N           patch size in samples: 17, 33, 65, 129 or 257 (default 17)\n"
          "  --fit pad|resample  fit the grid to whole patches by padding the right and bottom\n"
          "                      edges (exact, the default) or by bilinear resampling\n"
          "  --json              print one JSON object instead of text\n"
          "  -h, --help          show this help\n"
          "\n"
          "Exit status: 0 success, 1 the DEM could not be read or tiled, 2 usage error.\n",
          stdout);
}

/* One stderr line naming the problem; `detail` (an argument) is quoted when not empty. */
static int usage_error(const char* what, const char* detail)
{
    if (detail[0])
        fprintf(stderr, "terrapatch info: %s '%s' (see 'terrapatch info --help')\n", what, detail);
    else
        fprintf(stderr, "terrapatch info: %s (see 'terrapatch info --help')\n", what);
    return TP_EXIT_USAGE;
}

/* Returns -1 when the options are fine, else the exit code to return (help, usage error). */
static int parse_options(int argc, char** argv, info_options* o)
{
    static const struct option longs[] = {
        {"patch", required_argument, NULL, OPT_PATCH},
        {"fit", required_argument, NULL, OPT_FIT},
        {"json", no_argument, NULL, OPT_JSON},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    *o = (info_options){.patch_size = TP_DEFAULT_PATCH_SIZE, .fit = TP_FIT_PAD};
    opterr = 0; /* getopt's own messages would make a second stderr line */
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":h", longs, NULL)) != -1) {
        switch (c) {
        case OPT_PATCH: {
            char* end;
            long v = strtol(optarg, &end, 10);
            if (*optarg == '\0' || *end != '\0' ||
                (v != 17 && v != 33 && v != 65 && v != 129 && v != 257)) {
                fprintf(stderr,
                        "terrapatch info: --patch: expected 17, 33, 65, 129 or 257, got %s\n",
                        optarg);
                return TP_EXIT_USAGE;
            }
            o->patch_size = (int)v;
            break;
        }
        case OPT_FIT:
            if (!strcmp(optarg, "pad")) {
                o->fit = TP_FIT_PAD;
            } else if (!strcmp(optarg, "resample")) {
                o->fit = TP_FIT_RESAMPLE;
            } else {
                fprintf(stderr, "terrapatch info: --fit: expected pad or resample, got %s\n",
                        optarg);
                return TP_EXIT_USAGE;
            }
            break;
        case OPT_JSON: o->json = 1; break;
        case 'h': print_help(); return tp_cli_finish(TP_EXIT_OK);
        case ':': return usage_error("missing value for option", argv[optind - 1]);
        default: /* '?' */
            if (optopt > 0 && optopt < 256) {
                char name[3] = {'-', (char)optopt, '\0'};
                return usage_error("unknown option", name);
            }
            if (optopt >= 256) /* a long option given a value it does not take: --json=1 */
                return usage_error("option takes no value:", argv[optind - 1]);
            return usage_error("unknown option", argv[optind - 1]);
        }
    }
    if (optind >= argc)
        return usage_error("missing DEM file", "");
    if (argc - optind > 1)
        return usage_error("expected one DEM file, got extra argument", argv[optind + 1]);
    o->path = argv[optind];
    return -1;
}

static const char* fit_name(tp_fit fit)
{
    return fit == TP_FIT_RESAMPLE ? "resample" : "pad";
}

/* The CRS's name from its WKT: the first quoted string, as in PROJCRS["NAD83 / UTM zone 10N",
 * ...]. Writes "" if there is none. */
static void crs_name(const char* wkt, char* out, size_t cap)
{
    out[0] = '\0';
    const char* a = strchr(wkt, '"');
    const char* b = a ? strchr(a + 1, '"') : NULL;
    if (b)
        snprintf(out, cap, "%.*s", (int)(b - a - 1), a + 1);
}

/* WKT2 geographic CRSs start with GEOGCRS (GEODCRS for geocentric, never a DEM's). */
static int crs_is_geographic(const tp_dem* dem)
{
    return !strncmp(dem->crs_wkt, "GEOGCRS", 7) || !strncmp(dem->crs_wkt, "GEODCRS", 7);
}

static void print_text(const tp_dem* dem, const char* path, const tp_terrain_info* in)
{
    const double* gt = dem->geotransform;
    char name[256];
    crs_name(dem->crs_wkt, name, sizeof name);

    printf("file           %s\n", path);
    printf("driver         %s\n", dem->driver);
    printf("data type      %s%s%s\n", dem->data_type, dem->units[0] ? ", units " : "", dem->units);
    printf("size           %d x %d samples\n", dem->width, dem->height);
    if (dem->epsg)
        printf("CRS            EPSG:%d (%s)\n", dem->epsg, name);
    else if (dem->crs_wkt[0])
        printf("CRS            %s (no EPSG code)\n", name[0] ? name : dem->crs_wkt);
    else
        printf("CRS            none (coordinates taken as metres)\n");
    if (dem->has_geotransform) {
        printf("geotransform   %.17g, %.17g, %.17g, %.17g, %.17g, %.17g\n", gt[0], gt[1], gt[2],
               gt[3], gt[4], gt[5]);
        printf("pixel size     %.10g x %.10g %s\n", fabs(gt[1]), fabs(gt[5]),
               crs_is_geographic(dem) ? "degrees" : "CRS units");
    } else {
        printf("geotransform   none (1 x 1 m pixels, origin 0, 0 taken)\n");
    }
    printf("band 1         min %.10g, max %.10g, %zu voids", dem->min_m, dem->max_m,
           dem->void_count);
    if (dem->has_nodata)
        printf(" (nodata tag %.10g)\n", dem->nodata_value);
    else
        printf(" (no nodata tag)\n");
    printf("heights        as stored in the DEM (no vertical datum or unit conversion)\n");
    if (crs_is_geographic(dem))
        printf("note           geographic CRS: east/north are degrees while heights are metres\n");

    printf("\nrendered grid\n");
    printf("  fitted size  %d x %d samples (%s", in->width, in->height, fit_name(in->fit));
    if (in->fit == TP_FIT_RESAMPLE)
        printf(" from %d x %d", in->src_width, in->src_height);
    printf(")\n");
    printf("  fit error    max %.6g m, RMS %.6g m\n", in->fit_max_error_m, in->fit_rms_error_m);
    printf("  pixel size   %.10g x %.10g\n", fabs(in->geotransform[1]), fabs(in->geotransform[5]));
    printf("  patch size   %d x %d samples (n = %d)\n", in->patch_size, in->patch_size, in->n);
    printf("  patches      %d x %d = %d\n", in->patch_cols, in->patch_rows, in->patch_count);
    printf("  levels       %d (k = 0..%d)\n", in->levels, in->n);
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
    tp_json_key(j, key);
    tp_json_string(j, v);
}
static void key_int(tp_json* j, const char* key, long long v)
{
    tp_json_key(j, key);
    tp_json_int(j, v);
}
static void key_number(tp_json* j, const char* key, double v)
{
    tp_json_key(j, key);
    tp_json_number(j, v);
}
static void key_size(tp_json* j, const char* key, size_t v)
{
    tp_json_key(j, key);
    tp_json_size(j, v);
}
static void key_bool(tp_json* j, const char* key, int v)
{
    tp_json_key(j, key);
    tp_json_bool(j, v);
}

static void print_json(const tp_dem* dem, const char* path, const tp_terrain_info* in)
{
    tp_json j;
    tp_json_init(&j, stdout);
    tp_json_object_begin(&j);

    /* The raster as read (band 1). */
    key_string(&j, "file", path);
    key_string(&j, "driver", dem->driver);
    key_string(&j, "data_type", dem->data_type);
    key_string(&j, "units", dem->units);
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
    tp_json_key(&j, "geotransform");
    tp_json_array_begin(&j);
    for (int i = 0; i < 6; ++i)
        tp_json_number(&j, dem->geotransform[i]);
    tp_json_array_end(&j);
    tp_json_key(&j, "warnings");
    json_lines(&j, dem->warnings);

    /* The rendered grid. */
    key_string(&j, "fit", fit_name(in->fit));
    tp_json_key(&j, "grid");
    tp_json_array_begin(&j);
    tp_json_int(&j, in->width);
    tp_json_int(&j, in->height);
    tp_json_array_end(&j);
    tp_json_key(&j, "grid_geotransform");
    tp_json_array_begin(&j);
    for (int i = 0; i < 6; ++i)
        tp_json_number(&j, in->geotransform[i]);
    tp_json_array_end(&j);
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

/* Prints each '\n'-separated warning as its own stderr line. */
static void print_warnings(const char* text)
{
    while (*text) {
        const char* nl = strchr(text, '\n');
        int len = nl ? (int)(nl - text) : (int)strlen(text);
        fprintf(stderr, "terrapatch: warning: %.*s\n", len, text);
        text += len + (nl ? 1 : 0);
    }
}

int tp_cli_info(int argc, char** argv)
{
    info_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;

    tp_dem* dem = NULL;
    tp_error err = {{0}};
    tp_status s = tp_dem_read(o.path, &dem, &err);
    if (s != TP_OK) {
        /* io messages already start with the file name */
        fprintf(stderr, "terrapatch: %s\n", err.message);
        return TP_EXIT_FAILURE;
    }
    print_warnings(dem->warnings);

    tp_terrain* t = NULL;
    tp_terrain_desc desc = tp_dem_terrain_desc(dem, o.patch_size, o.fit);
    s = tp_terrain_create(&desc, &t, &err);
    if (s != TP_OK) {
        fprintf(stderr, "terrapatch: %s: %s\n", o.path,
                err.message[0] ? err.message : tp_status_str(s));
        tp_dem_destroy(dem);
        return TP_EXIT_FAILURE;
    }
    tp_terrain_info info;
    tp_terrain_get_info(t, &info);

    if (o.json)
        print_json(dem, o.path, &info);
    else
        print_text(dem, o.path, &info);

    tp_terrain_destroy(t);
    tp_dem_destroy(dem);
    return tp_cli_finish(TP_EXIT_OK);
}
