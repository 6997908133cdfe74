/*
 * cmd_contours.c - `terrapatch contours DEM|STORE --interval M -o OUT`: contour lines of the
 * full-resolution ground (issue 13, section 4). The window of the render grid (the whole grid,
 * an --area in render-CRS metres, or a square --around a position) is read at its posts through
 * the ground module (the stored samples, as `point` and `viewshed` read them), GDAL's contour
 * generator draws the lines (tp_contours_generate) and tp_contours_write writes them in the
 * OGR format the output's extension names (output_check.h), in the render CRS, atomically.
 */
#define _POSIX_C_SOURCE 200809L
#include "cli.h"
#include "clock.h"
#include "memory.h"
#include "output_check.h"
#include "planner_cli.h"
#include "terrapatch.h"

#include "tp_core.h"
#include "tp_io.h"
#include "tp_vector.h"

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
    double interval_m, base_m, radius_m;
    double area[4]; /* E0, N0, E1, N1 */
    int has_area, has_radius, index_every;
} contours_cli;

static void print_help(void)
{
    tp_planner_help(
        "usage: terrapatch contours DEM|STORE --interval M -o OUT [--base M] [--index-every K]\n"
        "                           [--area E0,N0,E1,N1 | --around POS --radius M]\n"
        "                           [--cache-dir DIR]\n"
        "\n"
        "Contour lines of the ground of DEM (any raster GDAL reads, built into the store cache\n"
        "first as 'terrapatch view' does) or of a store (.tpt), drawn by GDAL's contour\n"
        "generator (GDALContourGenerate, as gdal_contour) over the stored samples of the\n"
        "render grid (the DEM's own grid, or a geographic DEM warped to the UTM/UPS zone of\n"
        "its centre). Levels are BASE + k * INTERVAL; no line crosses a void.\n"
        "\n"
        "OUT is any OGR vector format, chosen by its extension: .gpkg, .shp, .geojson, .kml,\n"
        ".gml, .csv (WKT geometry), .fgb, .sqlite, ... One LINESTRING layer 'contours' in the\n"
        "render CRS with the fields elevation_m (Real; 'elevation_' in a Shapefile) and index\n"
        "(Integer: 1 on every K-th level, the index contours). Closed contours are closed\n"
        "lines. Flat ground (no level inside the heights' range) gives a valid file with an\n"
        "empty layer, and says so.\n"
        "\n"
        "options:\n"
        "  --interval M           metres between levels (required, > 0)\n"
        "  -o, --output OUT       the vector file to write (required)\n"
        "  --base M               a level every INTERVAL from this one (default 0)\n"
        "  --index-every K        every K-th level is an index contour (default 5; 0: none)\n"
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
        "\n"
        "Exit status: 0 written; 1 the DEM cannot be read, the area or position is outside\n"
        "it, the window is too big, OUT cannot be written (nothing is left behind, an older\n"
        "OUT stays); 2 usage error (OUT's extension naming no OGR format included).\n");
}

/* --area E0,N0,E1,N1 (tp_option_handler): the only option of contours that is no plain slot. */
static int area_option(void* ctx, int code, const char* value, const char* cmd)
{
    (void)code;
    contours_cli* o = ctx;
    if (!tp_parse_numbers(value, o->area, 4) || !(o->area[0] < o->area[2]) ||
        !(o->area[1] < o->area[3]))
        return tp_option_error(cmd, "--area", "E0,N0,E1,N1 with E0 < E1, N0 < N1", value);
    o->has_area = 1;
    return 1;
}

static int parse_options(int argc, char** argv, contours_cli* o)
{
    memset(o, 0, sizeof *o);
    tp_planner_source_init(&o->src);
    o->index_every = 5;
    const tp_option options[] = {
        TP_OPT_NUMBER_ABOVE("--interval", &o->interval_m, 0.0, HUGE_VAL, "a number > 0"),
        TP_OPT_NUMBER("--base", &o->base_m, -HUGE_VAL, HUGE_VAL, "a number"),
        TP_OPT_NUMBER_ABOVE("--radius", &o->radius_m, 0.0, HUGE_VAL, "a number > 0"),
        TP_OPT_INTEGER("--index-every", &o->index_every, 0, 1000000, "an integer >= 0"),
        TP_OPT_CODE("--area", NULL, 1, 1),
        TP_OPT_TEXT("--around", NULL, &o->around),
        TP_OPT_TEXT("--output", "-o", &o->out),
        };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), area_option, o};
    const int code = tp_planner_parse("contours", argc, argv, print_help, own, &o->src,
                                      " (quote a position with spaces: --around "
                                      "\"45.37 -121.69\")");
    if (code >= 0)
        return code;
    o->has_radius = o->radius_m > 0.0;
    if (!(o->interval_m > 0.0))
        return tp_cli_usage("contours", "missing --interval M");
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

int tp_cli_contours(int argc, char** argv)
{
    contours_cli o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    tp_position_readings around;
    if (o.around && !tp_planner_position("contours", "--around", o.around, &around))
        return TP_EXIT_USAGE;
    if ((code = tp_cli_output_check("contours", "-o", o.out, TP_OUTPUT_VECTOR)) != TP_EXIT_OK)
        return code;
    tp_error err = {{0}};
    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("contours", &o.src, &g)) != TP_EXIT_OK)
        return code;
    const tp_store_scene* sc = tp_ground_scene(g);
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    const int W = geom->src_width, H = geom->src_height;

    /* the window: the whole DEM, --area, or the square --around */
    tp_planner_window pw;
    if (!tp_planner_window_choose("contours", o.src.path, g, o.has_area ? o.area : NULL,
                                  o.around ? &around : NULL, o.around, o.radius_m, &pw)) {
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    const int x0 = pw.x0, y0 = pw.y0, w = pw.w, h = pw.h;
    const size_t n = pw.n;
    tp_memory_room room;
    tp_memory_room_now(&room);
    if (n > CONTOURS_MAX_POSTS || (uint64_t)n * CONTOURS_BYTES_PER_POST > room.bytes) {
        if (n > CONTOURS_MAX_POSTS)
            tp_cli_error("%s: a %dx%d window is %zu posts, more than one run "
                         "takes (%zu, 8192 x 8192); choose a part with --area or --around",
                         o.src.path, w, h, n, CONTOURS_MAX_POSTS);
        else
            tp_cli_error("%s: a %dx%d window needs about %.0f MiB, %.0f MiB "
                         "left (%s); choose a part with --area or --around",
                         o.src.path, w, h, n * (double)CONTOURS_BYTES_PER_POST / 1048576.0,
                         room.bytes / 1048576.0, room.bound);
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    tp_status s = tp_planner_window_read(g, &pw, "contours", &err);
    const float* z = pw.z;
    const double t1 = tp_clock_s();
    if (n >= TP_GROUND_PROGRESS_POSTS && s == TP_OK)
        tp_cli_note("reading the ground 100%%, drawing the lines");
    tp_features* f = NULL;
    if (s == TP_OK)
        s = tp_contours_generate(z, n, w, h, pw.gt, o.interval_m, o.base_m, o.index_every, &f,
                                 &err);
    const double t2 = tp_clock_s();
    tp_interrupt_hold(); /* a signal during the write is only recorded (tp_interrupt_finished) */
    if (s == TP_OK)
        s = tp_contours_write(o.out, f, sc->info.header.crs_wkt, &err);
    if (s == TP_OK)
        tp_interrupt_finished();
    tp_interrupt_release();
    const double t3 = tp_clock_s();
    if (s != TP_OK) {
        if (!tp_interrupted())
            tp_cli_error("%s: %s", o.src.path, err.message);
        tp_planner_window_free(&pw);
        tp_features_destroy(f);
        tp_ground_destroy(g);
        return tp_planner_finish(TP_EXIT_FAILURE);
    }
    float lo = INFINITY, hi = -INFINITY;
    size_t voids = 0;
    for (size_t i = 0; i < n; ++i) {
        if (z[i] != z[i]) {
            ++voids;
            continue;
        }
        lo = fminf(lo, z[i]);
        hi = fmaxf(hi, z[i]);
    }
    size_t rings = 0, index = 0;
    double elo = INFINITY, ehi = -INFINITY;
    for (size_t i = 0; i < f->count; ++i) {
        rings += f->items[i].kind == TP_FEATURE_RING;
        index += f->items[i].index != 0;
        elo = fmin(elo, f->items[i].value);
        ehi = fmax(ehi, f->items[i].value);
    }
    if (o.has_area || o.around)
        printf("window     %dx%d posts from (%d, %d) of %dx%d\n", w, h, x0, y0, W, H);
    else
        printf("window     %dx%d posts: the whole DEM\n", w, h);
    if (lo <= hi)
        printf("ground     %.1f .. %.1f m, %zu void posts\n", (double)lo, (double)hi, voids);
    else
        printf("ground     all %zu posts void\n", voids);
    if (f->count)
        printf("contours   %zu lines (%zu closed, %zu index), %zu vertices, %.1f km, "
               "elevation %.0f .. %.0f m every %g m\n",
               f->count, rings, index, f->vertex_count, total_length_m(f) / 1000.0, elo, ehi,
               o.interval_m);
    else
        printf("contours   none: no level %g + k * %g m inside the ground's heights (an empty "
               "layer written)\n",
               o.base_m, o.interval_m);
    printf("time       %.1f ms reading the ground, %.1f ms for the contours, %.1f ms writing\n",
           1e3 * pw.read_s, 1e3 * (t2 - t1), 1e3 * (t3 - t2));
    tp_cli_note("wrote %s", o.out);
    tp_planner_window_free(&pw);
    tp_features_destroy(f);
    tp_ground_destroy(g);
    return tp_cli_finish(TP_EXIT_OK);
}
