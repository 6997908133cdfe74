/*
 * cmd_contours.c - `terrapatch contours DEM|STORE --interval M|--levels L,L,... -o OUT`: contour
 * lines of the full-resolution ground (issue 13, section 4; the levels and lines chosen as
 * GRASS and gdal_contour choose them: issue 31). The window of the render grid (the whole grid,
 * an --area in render-CRS metres, or a square --around a position) is read at its posts through
 * the ground module (the stored samples, as `point` and `viewshed` read them), GDAL's contour
 * generator draws the lines (tp_contours_generate_ex) and tp_contours_write writes them in the
 * OGR format the output's extension names (output_check.h), in the render CRS, atomically.
 */
#define _POSIX_C_SOURCE 200809L
#include "terrapatch.h"
#include "cli.h"
#include "clock.h"
#include "ground_locate.h"
#include "memory.h"
#include "output_check.h"
#include "planner_cli.h"

#include "tp_core.h"
#include "tp_io.h"
#include "tp_vector.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The most posts one run reads: 64 Mi posts (8192 x 8192) take 768 MiB in three float copies
 * (ours, the void-marked copy, GDAL's MEM dataset) before any line is drawn. */
#define CONTOURS_MAX_POSTS ((size_t)64 << 20)
#define CONTOURS_BYTES_PER_POST 12

typedef struct contours_cli {
    tp_planner_source src; /* the DEM or store, --cache-dir and the DEM options */
    const char* out;
    const char* around;
    double interval_m, base_m, radius_m; /* base_m NaN until --base is given */
    double* levels;                      /* --levels, as given (malloc'd), or NULL */
    size_t level_count;
    double min_m, max_m; /* --min-level, --max-level; -HUGE_VAL, HUGE_VAL when not given */
    int min_vertices;    /* --min-vertices; 0: every line */
    double area[4];      /* E0, N0, E1, N1 */
    int has_area, has_radius, index_every;
} contours_cli;

enum { OPT_AREA = 1, OPT_LEVELS = 2 };

static void print_help(void)
{
    tp_planner_help(
        "usage: terrapatch contours DEM|STORE (--interval M [--base M] | --levels L,L,...)\n"
        "                           -o OUT [--min-level M] [--max-level M] [--min-vertices N]\n"
        "                           [--index-every K]\n"
        "                           [--area E0,N0,E1,N1 | --around POS --radius M]\n"
        "                           [--cache-dir DIR]\n"
        "\n"
        "Contour lines of the ground of DEM (any raster GDAL reads, built into the store cache\n"
        "first as 'terrapatch view' does) or of a store (.tpt), drawn by GDAL's contour\n"
        "generator (GDALContourGenerate, as gdal_contour) over the stored samples of the\n"
        "render grid (the DEM's own grid, or a geographic DEM warped to the UTM/UPS zone of\n"
        "its centre). Levels are BASE + k * INTERVAL, or those --levels lists (as\n"
        "gdal_contour -fl); no line crosses a void.\n"
        "\n"
        "OUT is any OGR vector format, chosen by its extension: .gpkg, .shp, .geojson, .kml,\n"
        ".gml, .csv (WKT geometry), .fgb, .sqlite, ... One LINESTRING layer 'contours' in the\n"
        "render CRS with the fields elevation_m (Real; 'elevation_' in a Shapefile) and index\n"
        "(Integer: 1 on every K-th level, the index contours). Closed contours are closed\n"
        "lines. Flat ground (no level inside the heights' range) gives a valid file with an\n"
        "empty layer, and says so.\n"
        "\n"
        "options:\n"
        "  --interval M           metres between levels (> 0; this or --levels is required)\n"
        "  --base M               a level every INTERVAL from this one (default 0)\n"
        "  --levels L,L,...       these levels instead: metres ('.' the decimal mark)\n"
        "                         separated by commas, in any order, a level given twice\n"
        "                         drawn once (100,250,500)\n"
        "  -o, --output OUT       the vector file to write (required)\n"
        "  --min-level M          only the levels at M metres or above\n"
        "  --max-level M          only the levels at M metres or below\n"
        "  --min-vertices N       leave out the lines of fewer than N vertices, counted as\n"
        "                         written (a closed line's first vertex again at its end), as\n"
        "                         GRASS's r.contour cut=N (default 0: every line)\n"
        "  --index-every K        every K-th level is an index contour (default 5; 0: none):\n"
        "                         with --interval, the levels BASE + a multiple of K * INTERVAL;\n"
        "                         with --levels, the 1st, (K+1)th, (2K+1)th, ... of the levels\n"
        "                         listed, the lowest first (among all of them, whichever\n"
        "                         --min-level and --max-level keep)\n"
        "  --area E0,N0,E1,N1     only the posts inside this rectangle of the render CRS\n"
        "                         (metres; 'terrapatch info' gives the render CRS)\n"
        "  --around POS           only the posts within --radius M (a square) of POS (any\n"
        "                         form 'terrapatch coord' reads; quote it when it has spaces)\n"
        "  --radius M             half the side of that square, metres (> 0)\n"
        "  -h, --help             show this help\n"
        "\n"
        "By default the whole DEM; a window of more than 67108864 posts (8192 x 8192) is\n"
        "refused (use --area or --around), as is one that does not fit the memory left\n"
        "(12 bytes a post).\n",
        "example:\n"
        "  $ terrapatch contours N42E001.hgt --interval 20 -o contours.gpkg\n"
        "  $ terrapatch contours N42E001.hgt --levels 1000,1500,2000,2500 --min-vertices 10 \\\n"
        "        -o contours.geojson\n"
        "\n"
        "Exit status: 0 written; 1 the DEM cannot be read, the area or position is outside\n"
        "it, the window is too big, OUT cannot be written (nothing is left behind, an older\n"
        "OUT stays); 2 usage error (OUT's extension naming no OGR format included).\n");
}

static int compare_doubles(const void* a, const void* b)
{
    const double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

/* value of --levels ("100,250,500": decimal numbers, '.' the decimal mark, separated by commas,
 * blanks around each allowed) into a new array, ascending, each level once: the count; or 0
 * with why (why_cap bytes) for anything else: an empty list or field, a field that is no
 * number, more than TP_CONTOURS_MAX_LEVELS. */
static size_t parse_levels(const char* value, double** out, char* why, size_t why_cap)
{
    size_t n = 1;
    for (const char* c = value; *c; ++c)
        n += *c == ',';
    if (n > TP_CONTOURS_MAX_LEVELS) {
        snprintf(why, why_cap, " (%zu levels: at most %d)", n, TP_CONTOURS_MAX_LEVELS);
        return 0;
    }
    double* v = malloc(n * sizeof *v);
    if (!v) {
        snprintf(why, why_cap, " (out of memory)");
        return 0;
    }
    const char* at = value;
    for (size_t i = 0; i < n; ++i) {
        const char* end = strchr(at, ',');
        size_t len = end ? (size_t)(end - at) : strlen(at);
        while (len && (*at == ' ' || *at == '\t'))
            ++at, --len;
        while (len && (at[len - 1] == ' ' || at[len - 1] == '\t'))
            --len;
        char field[64];
        if (len == 0 || len >= sizeof field) {
            snprintf(why, why_cap, len ? " (level %zu is too long)" : " (level %zu is empty)",
                     i + 1);
            free(v);
            return 0;
        }
        memcpy(field, at, len);
        field[len] = '\0';
        if (tp_position_decimal(field, &v[i]) != 1 || !isfinite(v[i])) {
            snprintf(why, why_cap, " ('%s' is not a number)", field);
            free(v);
            return 0;
        }
        at = end ? end + 1 : at + len;
    }
    qsort(v, n, sizeof *v, compare_doubles);
    size_t k = 1;
    for (size_t i = 1; i < n; ++i)
        if (v[i] != v[k - 1])
            v[k++] = v[i];
    *out = v;
    return k;
}

/* --area E0,N0,E1,N1 and --levels L,L,... (tp_option_handler): the options of contours that are
 * no plain slot. */
static int contours_option(void* ctx, int code, const char* value, const char* cmd)
{
    contours_cli* o = ctx;
    if (code == OPT_LEVELS) {
        char why[96] = "";
        free(o->levels);
        o->levels = NULL;
        if (!(o->level_count = parse_levels(value, &o->levels, why, sizeof why))) {
            (void)cmd; /* the prefix names the command main() dispatched to */
            tp_cli_error("--levels: expected levels in metres separated by commas (100,250,500), "
                         "got '%s'%s",
                         value, why);
            return -1;
        }
        return 1;
    }
    if (!tp_parse_numbers(value, o->area, 4) || !(o->area[0] < o->area[2]) ||
        !(o->area[1] < o->area[3]))
        return tp_option_error(cmd, "--area", "E0,N0,E1,N1 with E0 < E1, N0 < N1", value);
    o->has_area = 1;
    return 1;
}

/* The usage errors of the levels' options (after the parse): 0 when they are fine. */
static int check_levels(const contours_cli* o)
{
    if (o->interval_m > 0.0 && o->levels)
        return tp_cli_usage("contours", "--interval and --levels exclude each other");
    if (!(o->interval_m > 0.0) && !o->levels)
        return tp_cli_usage("contours", "missing --interval M (or --levels L,L,...)");
    if (o->levels && !isnan(o->base_m))
        return tp_cli_usage("contours", "--base shifts the levels of --interval; --levels "
                                        "gives the levels themselves");
    if (o->min_m > o->max_m)
        return tp_cli_usage("contours", "--min-level %g is above --max-level %g", o->min_m,
                            o->max_m);
    char bounds[96];
    if (isfinite(o->min_m) && isfinite(o->max_m))
        snprintf(bounds, sizeof bounds, "--min-level %g .. --max-level %g", o->min_m, o->max_m);
    else
        snprintf(bounds, sizeof bounds, isfinite(o->min_m) ? "--min-level %g" : "--max-level %g",
                 isfinite(o->min_m) ? o->min_m : o->max_m);
    size_t kept = 0;
    for (size_t i = 0; i < o->level_count; ++i)
        kept += o->levels[i] >= o->min_m && o->levels[i] <= o->max_m;
    if (o->levels && !kept)
        return tp_cli_usage("contours",
                            "none of the %zu levels of --levels (%g .. %g m) lies "
                            "within %s",
                            o->level_count, o->levels[0], o->levels[o->level_count - 1], bounds);
    const double base = isnan(o->base_m) ? 0.0 : o->base_m;
    if (!o->levels && isfinite(o->min_m) && isfinite(o->max_m) &&
        ceil((o->min_m - base) / o->interval_m - 1e-9) >
            floor((o->max_m - base) / o->interval_m + 1e-9))
        return tp_cli_usage("contours", "no level %g + k * %g m lies within %s", base,
                            o->interval_m, bounds);
    return 0;
}

static int parse_options(int argc, char** argv, contours_cli* o)
{
    memset(o, 0, sizeof *o);
    tp_planner_source_init(&o->src);
    o->index_every = 5;
    o->base_m = NAN;
    o->min_m = -HUGE_VAL;
    o->max_m = HUGE_VAL;
    const tp_option options[] = {
        TP_OPT_NUMBER_ABOVE("--interval", &o->interval_m, 0.0, HUGE_VAL, "a number > 0"),
        TP_OPT_NUMBER("--base", &o->base_m, -HUGE_VAL, HUGE_VAL, "a number"),
        TP_OPT_NUMBER_ABOVE("--radius", &o->radius_m, 0.0, HUGE_VAL, "a number > 0"),
        TP_OPT_INTEGER("--index-every", &o->index_every, 0, 1000000, "an integer >= 0"),
        TP_OPT_NUMBER("--min-level", &o->min_m, -HUGE_VAL, HUGE_VAL, "a number"),
        TP_OPT_NUMBER("--max-level", &o->max_m, -HUGE_VAL, HUGE_VAL, "a number"),
        TP_OPT_INTEGER("--min-vertices", &o->min_vertices, 0, INT_MAX, "an integer >= 0"),
        TP_OPT_CODE("--area", NULL, OPT_AREA, 1),
        TP_OPT_CODE("--levels", NULL, OPT_LEVELS, 1),
        TP_OPT_TEXT("--around", NULL, &o->around),
        TP_OPT_TEXT("--output", "-o", &o->out),
    };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), contours_option, o};
    int code = tp_planner_parse("contours", argc, argv, print_help, own, &o->src,
                                " (quote a position with spaces: --around "
                                "\"45.37 -121.69\")");
    if (code >= 0)
        return code;
    o->has_radius = o->radius_m > 0.0;
    if ((code = check_levels(o)) != 0)
        return code;
    if (isnan(o->base_m))
        o->base_m = 0.0;
    if (!o->out)
        return tp_cli_usage("contours", "missing -o OUT");
    if (o->has_area && o->around)
        return tp_cli_usage("contours", "--area and --around exclude each other");
    if (!!o->around != o->has_radius)
        return tp_cli_usage("contours", "%s",
                                o->around ? "--around needs --radius M"
                                          : "--radius needs --around POS");
    return -1;
}

/* Sum of the lengths of the lines (rings closed), metres. */
static double total_length_m(const tp_features* f)
{
    double sum = 0.0;
    for (size_t i = 0; i < f->count; ++i) {
        const tp_feature* it = &f->items[i];
        const double* p = f->xy + 2 * it->first;
        for (size_t k = 1; k < it->count; ++k)
            sum += hypot(p[2 * k] - p[2 * k - 2], p[2 * k + 1] - p[2 * k - 1]);
        if (it->kind == TP_FEATURE_RING && it->count > 1)
            sum += hypot(p[0] - p[2 * it->count - 2], p[1] - p[2 * it->count - 1]);
    }
    return sum;
}

/* The range --min-level/--max-level give, in the summary's words: " from 1000 to 2000 m",
 * " from 1000 m up", " up to 2000 m", or "". */
static void describe_range(const contours_cli* o, char* buf, size_t cap)
{
    if (isfinite(o->min_m) && isfinite(o->max_m))
        snprintf(buf, cap, " from %g to %g m", o->min_m, o->max_m);
    else if (isfinite(o->min_m))
        snprintf(buf, cap, " from %g m up", o->min_m);
    else if (isfinite(o->max_m))
        snprintf(buf, cap, " up to %g m", o->max_m);
    else if (cap)
        buf[0] = '\0';
}

/* The levels asked for, in the summary's words: "every 20 m", "every 50 m from 1000 to 2000 m",
 * "at the 3 levels given", "at 2 of the 3 levels given (those from 1000 m up)". */
static void describe_levels(const contours_cli* o, char* buf, size_t cap)
{
    char range[96];
    describe_range(o, range, sizeof range);
    if (!o->levels) {
        snprintf(buf, cap, "every %g m%s", o->interval_m, range);
        return;
    }
    size_t kept = 0;
    for (size_t i = 0; i < o->level_count; ++i)
        kept += o->levels[i] >= o->min_m && o->levels[i] <= o->max_m;
    if (kept == o->level_count)
        snprintf(buf, cap, "at the %zu level%s given", kept, kept == 1 ? "" : "s");
    else
        snprintf(buf, cap, "at %zu of the %zu levels given (those%s)", kept, o->level_count, range);
}

/* The summary on stdout: the window, the ground's heights, the lines (without the time). */
static void print_summary(const contours_cli* o, const tp_planner_window* pw, int W, int H,
                          const tp_features* f, size_t dropped)
{
    size_t rings = 0, index = 0;
    double elo = INFINITY, ehi = -INFINITY;
    for (size_t i = 0; i < f->count; ++i) {
        rings += f->items[i].kind == TP_FEATURE_RING;
        index += f->items[i].index != 0;
        elo = fmin(elo, f->items[i].value);
        ehi = fmax(ehi, f->items[i].value);
    }
    tp_planner_print_ground(pw, W, H, o->has_area || o->around, 0.0);
    char levels[200], left_out[96] = "";
    describe_levels(o, levels, sizeof levels);
    if (o->min_vertices > 0)
        snprintf(left_out, sizeof left_out, "; %zu line%s of fewer than %d vertices left out",
                 dropped, dropped == 1 ? "" : "s", o->min_vertices);
    if (f->count)
        printf("contours   %zu lines (%zu closed, %zu index), %zu vertices, %.1f km, "
               "elevation %g .. %g m %s%s\n",
               f->count, rings, index, f->vertex_count, total_length_m(f) / 1000.0, elo, ehi,
               levels, left_out);
    else if (dropped)
        printf("contours   none: the %zu lines drawn %s all have fewer than %d vertices (an "
               "empty layer written)\n",
               dropped, levels, o->min_vertices);
    else if (o->levels)
        printf("contours   none: no line %s inside the ground's heights (an empty layer "
               "written)\n",
               levels);
    else {
        char range[96];
        describe_range(o, range, sizeof range);
        printf("contours   none: no level %g + k * %g m%s inside the ground's heights (an empty "
               "layer written)\n",
               o->base_m, o->interval_m, range);
    }
}

/* The contours of the window of the ground (read here) written to o->out: the exit code. */
static int draw_and_write(const contours_cli* o, tp_ground* g, tp_planner_window* pw)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    tp_error err = {{0}};
    tp_status s = tp_planner_window_read(g, pw, "contours", &err);
    const double t1 = tp_clock_s();
    if (pw->n >= TP_GROUND_PROGRESS_POSTS && s == TP_OK)
        tp_cli_note("reading the ground 100%%, drawing the lines");
    tp_features* f = NULL;
    size_t dropped = 0;
    tp_contours_options co = tp_contours_options_default();
    co.interval_m = o->levels ? 0.0 : o->interval_m;
    co.base_m = o->base_m;
    co.levels = o->levels;
    co.level_count = o->level_count;
    co.min_m = o->min_m;
    co.max_m = o->max_m;
    co.index_every = o->index_every;
    co.min_vertices = (size_t)o->min_vertices;
    if (s == TP_OK)
        s = tp_contours_generate_ex(pw->z, pw->n, pw->w, pw->h, pw->gt, &co, &f, &dropped, &err);
    const double t2 = tp_clock_s();
    tp_interrupt_hold(); /* a signal during the write is only recorded (tp_interrupt_finished) */
    if (s == TP_OK)
        s = tp_contours_write(o->out, f, sc->info.header.crs_wkt, &err);
    if (s == TP_OK)
        tp_interrupt_finished();
    tp_interrupt_release();
    const double t3 = tp_clock_s();
    if (s != TP_OK) {
        if (!tp_interrupted())
            tp_cli_error("%s: %s", o->src.path, err.message);
        tp_features_destroy(f);
        return tp_planner_finish(TP_EXIT_FAILURE);
    }
    print_summary(o, pw, geom->src_width, geom->src_height, f, dropped);
    printf("time       %.1f ms reading the ground, %.1f ms for the contours, %.1f ms writing\n",
           1e3 * pw->read_s, 1e3 * (t2 - t1), 1e3 * (t3 - t2));
    tp_cli_note("wrote %s", o->out);
    tp_features_destroy(f);
    return tp_cli_finish(TP_EXIT_OK);
}

static int contours_main(int argc, char** argv, contours_cli* o)
{
    int code = parse_options(argc, argv, o);
    if (code >= 0)
        return code;
    tp_position_readings around;
    if (o->around && !tp_planner_position("contours", "--around", o->around, &around))
        return TP_EXIT_USAGE;
    if ((code = tp_cli_output_check("contours", "-o", o->out, TP_OUTPUT_VECTOR)) != TP_EXIT_OK)
        return code;
    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("contours", &o->src, &g)) != TP_EXIT_OK)
        return code;

    /* the window: the whole DEM, --area, or the square --around */
    tp_planner_window pw;
    if (!tp_planner_window_choose("contours", o->src.path, g, o->has_area ? o->area : NULL,
                                  o->around ? &around : NULL, o->around, o->radius_m, &pw)) {
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    if (!tp_planner_window_fits(o->src.path, &pw, CONTOURS_MAX_POSTS, CONTOURS_BYTES_PER_POST)) {
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    code = draw_and_write(o, g, &pw);
    tp_planner_window_free(&pw);
    tp_ground_destroy(g);
    return code;
}

int tp_cli_contours(int argc, char** argv)
{
    contours_cli o;
    const int code = contours_main(argc, argv, &o);
    free(o.levels);
    return code;
}
