/*
 * cmd_viewshed.c - `terrapatch viewshed DEM|STORE --observer POS -o OUT.tif`: which samples of
 * the render grid an observer sees (issue 13, section 3). The window of the render grid the
 * radius reaches (the whole grid without a radius, as gdal_viewshed's default -md 0) is read
 * at its posts through the ground module (the stored samples, as `point` reads them), the core's
 * tp_viewshed_compute sweeps it, and tp_viewshed_write writes it on the render grid's
 * georeference in the format OUT's extension names (output_check.h), atomically.
 * Several --observer: the window covers all their radii, each is swept over it, and OUT counts
 * the observers that see each post. --azimuth keeps a sector (true azimuths at each observer).
 */
#define _POSIX_C_SOURCE 200809L
#include "terrapatch.h"
#include "cli.h"
#include "clock.h"
#include "ground_locate.h"
#include "output_check.h"
#include "planner_cli.h"

#include "tp_core.h"
#include "tp_io.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A count of observers fits a byte, 0 kept for none. */
#define VIEWSHED_MAX_OBSERVERS 254

enum { OPT_OBSERVER = 1, OPT_AZIMUTH, OPT_VALUES };

typedef struct viewshed_cli {
    tp_planner_source src; /* the DEM or store, --cache-dir and the DEM options */
    const char* observers[VIEWSHED_MAX_OBSERVERS];
    int observer_count;
    const char* out;
    double observer_height_m, target_height_m, radius_m, curvature_coeff;
    int has_sector;
    double sector[2]; /* --azimuth FROM,TO: degrees clockwise from true north */
    tp_viewshed_values values; /* --values: NONE for visible */
} viewshed_cli;

/* An observer: where it stands (posts), and grid north's bearing from true north there. */
typedef struct viewshed_observer {
    int x, y;
    double convergence_deg;
} viewshed_observer;

static void print_help(void)
{
    tp_planner_help(
        "usage: terrapatch viewshed DEM|STORE --observer POS [--observer POS ...] -o OUT.tif\n"
        "                           [--values visible|angle|clearance] [--observer-height M]\n"
        "                           [--target-height M] [--radius M] [--azimuth FROM,TO]\n"
        "                           [--curvature-coeff C] [--cache-dir DIR]\n"
        "\n"
        "What an observer at POS sees of the ground of DEM (any raster GDAL reads, built into\n"
        "the store cache first as 'terrapatch view' does) or of a store (.tpt): a one-band Byte\n"
        "raster on the render grid (the DEM's own grid, or a geographic DEM warped to the\n"
        "UTM/UPS zone of its centre), 255 where a target on the ground is seen, 0 where it is\n"
        "not, 0 beyond the radius (gdal_viewshed's values). It covers the window of the grid\n"
        "the radius reaches around the observer (the whole grid without --radius, as\n"
        "gdal_viewshed's default) with the grid's georeference. The observer stands on the\n"
        "nearest post. The algorithm and its agreement with GDAL's are in docs/field.md.\n"
        "\n"
        "Several observers (--observer again and again, up to 254: 'which ground do our posts\n"
        "cover'): the raster counts the observers that see each post (0 .. N) over the window\n"
        "all their radii reach.\n"
        "\n"
        "Conventions are gdal_viewshed's: heights above the ground, every height lowered by\n"
        "C * d^2 / (2 * 6378137 m) at distance d from the observer (0.85714: curvature with\n"
        "standard refraction; 1: curvature without refraction; 0: a flat earth).\n"
        "\n"
        "options:\n"
        "  --observer POS         where the observer stands (required; any form 'terrapatch\n"
        "                         coord' reads, one argument: quote it when it has spaces);\n"
        "                         again for more observers\n"
        "  -o, --output OUT.tif   the raster to write (required), in the format its extension\n"
        "                         names: .tif GeoTIFF, .png PNG (with a .wld world file and\n"
        "                         the CRS in .png.aux.xml), .gpkg, .jp2 (lossless), .img,\n"
        "                         .asc, .bmp\n"
        "  --observer-height M    eye above the ground (default 2)\n"
        "  --target-height M      target above the ground (default 0)\n"
        "  --radius M             how far to look, metres (default 0: the whole grid)\n"
        "  --values visible       255 seen, 0 not (default; several observers: their count)\n"
        "  --values angle         Float32: the vertical angle from the eye to the target,\n"
        "                         degrees, as r.viewshed (0 down, 90 level, 180 up); nodata\n"
        "                         (-9999) where not seen\n"
        "  --values clearance     Float32: metres the target stands above the sight line over\n"
        "                         its horizon; below 0 where hidden, minus the height it would\n"
        "                         need (gdal_viewshed -om GROUND's value there); one observer\n"
        "  --azimuth FROM,TO      only the sector clockwise from FROM to TO, degrees from true\n"
        "                         north at the observer (350,10 looks north; equal: all round);\n"
        "                         posts outside it are 0, as beyond the radius\n"
        "  --curvature-coeff C    curvature and refraction coefficient (default 0.85714)\n"
        "  -h, --help             show this help\n",
        "example:\n"
        "  $ terrapatch viewshed N42E001.hgt --observer 42.5,1.5 --radius 20000 -o seen.tif\n"
        "  $ terrapatch viewshed N42E001.hgt --observer 42.5,1.5 --observer 42.55,1.45 \\\n"
        "        --radius 10000 --azimuth 270,90 -o covered.tif\n"
        "\n"
        "Exit status: 0 written; 1 the DEM cannot be read, the observer is outside it or in a\n"
        "void, OUT.tif cannot be written (nothing is left behind); 2 usage error (OUT's\n"
        "extension naming no format written included).\n");
}

/* tp_option_handler of --observer and --azimuth. */
static int viewshed_option(void* ctx, int code, const char* value, const char* cmd)
{
    viewshed_cli* o = ctx;
    if (code == OPT_VALUES) {
        if (!strcmp(value, "visible"))
            o->values = TP_VIEWSHED_VALUES_NONE;
        else if (!strcmp(value, "angle"))
            o->values = TP_VIEWSHED_VALUES_ANGLE;
        else if (!strcmp(value, "clearance"))
            o->values = TP_VIEWSHED_VALUES_CLEARANCE;
        else
            return tp_option_error(cmd, "--values", "visible, angle or clearance", value), -1;
        return 1;
    }
    if (code == OPT_AZIMUTH) {
        o->has_sector = 1;
        return tp_option_pair(cmd, "--azimuth", value, 0.0, 360.0,
                              "FROM,TO: two azimuths from 0 to 360 degrees", o->sector)
                   ? 1
                   : -1;
    }
    if (o->observer_count == VIEWSHED_MAX_OBSERVERS)
        return tp_cli_usage(cmd, "more than %d observers", VIEWSHED_MAX_OBSERVERS), -1;
    o->observers[o->observer_count++] = value;
    return 1;
}

static int parse_options(int argc, char** argv, viewshed_cli* o)
{
    memset(o, 0, sizeof *o);
    tp_planner_source_init(&o->src);
    o->observer_height_m = TP_VIEWSHED_OBSERVER_HEIGHT_M;
    o->target_height_m = TP_VIEWSHED_TARGET_HEIGHT_M;
    o->curvature_coeff = TP_VIEWSHED_CURVATURE_COEFF;
    const tp_option options[] = {
        TP_OPT_CODE("--observer", NULL, OPT_OBSERVER, 1),
        TP_OPT_CODE("--azimuth", NULL, OPT_AZIMUTH, 1),
        TP_OPT_CODE("--values", NULL, OPT_VALUES, 1),
        TP_OPT_TEXT("--output", "-o", &o->out),
        TP_OPT_NUMBER("--observer-height", &o->observer_height_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_NUMBER("--target-height", &o->target_height_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_NUMBER("--radius", &o->radius_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_NUMBER("--curvature-coeff", &o->curvature_coeff, 0.0, HUGE_VAL, "a number >= 0"),
    };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), viewshed_option, o};
    const int code = tp_planner_parse("viewshed", argc, argv, print_help, own, &o->src,
                                      " (quote a position with spaces: --observer "
                                      "\"45.37 -121.69\")");
    if (code >= 0)
        return code;
    if (!o->observer_count)
        return tp_cli_usage("viewshed", "missing --observer POS");
    if (!o->out)
        return tp_cli_usage("viewshed", "missing -o OUT.tif");
    if (o->values != TP_VIEWSHED_VALUES_NONE && o->observer_count > 1)
        return tp_cli_usage("viewshed", "--values angle and clearance take one observer (%d given)",
                            o->observer_count);
    return -1;
}

/* Reads and places every observer: TP_EXIT_OK with obs[]; else the exit code after one line. */
static int locate_observers(const viewshed_cli* o, tp_ground* g, viewshed_observer* obs)
{
    for (int k = 0; k < o->observer_count; ++k) {
        tp_position_readings pos;
        if (!tp_planner_position("viewshed", "--observer", o->observers[k], &pos))
            return TP_EXIT_USAGE;
        double fx, fy, fh;
        if (!tp_planner_locate("viewshed", o->src.path, g, &pos, o->observers[k], &fx, &fy,
                               &fh))
            return TP_EXIT_FAILURE;
        obs[k].x = (int)lround(fx);
        obs[k].y = (int)lround(fy);
        tp_ground_sample gs;
        tp_error err = {{0}};
        obs[k].convergence_deg =
            tp_ground_query_grid(g, obs[k].x, obs[k].y, &gs, &err) == TP_OK &&
                    gs.convergence_deg == gs.convergence_deg
                ? gs.convergence_deg
                : 0.0;
    }
    return TP_EXIT_OK;
}

/* The window every observer's radius reaches (their windows' union). */
static void observers_window(tp_ground* g, const viewshed_observer* obs, int count,
                             double radius_m, tp_planner_window* win)
{
    int x0 = INT_MAX, y0 = INT_MAX, x1 = INT_MIN, y1 = INT_MIN;
    for (int k = 0; k < count; ++k) {
        tp_planner_window one;
        tp_planner_window_around(g, obs[k].x, obs[k].y, radius_m, &one);
        x0 = one.x0 < x0 ? one.x0 : x0;
        y0 = one.y0 < y0 ? one.y0 : y0;
        x1 = one.x0 + one.w - 1 > x1 ? one.x0 + one.w - 1 : x1;
        y1 = one.y0 + one.h - 1 > y1 ? one.y0 + one.h - 1 : y1;
    }
    tp_planner_window_set(g, x0, y0, x1, y1, win);
}

/* Clears the posts of seen (the window's) outside the sector of --azimuth around ob (window
 * posts ox, oy): their true azimuth from the observer, grid bearing + convergence. */
static void keep_sector(const viewshed_cli* o, const tp_planner_window* win, int ox, int oy,
                        double convergence_deg, uint8_t* seen, float* values)
{
    double width = o->sector[1] - o->sector[0];
    if (width <= 0.0)
        width += 360.0; /* 350,10: 20 degrees through north; equal: all round */
    for (int y = 0; y < win->h; ++y)
        for (int x = 0; x < win->w; ++x) {
            if (x == ox && y == oy)
                continue;
            const double east = (x - ox) * win->gt[1], north = (y - oy) * win->gt[5];
            double from = atan2(east, north) * (180.0 / 3.14159265358979323846) +
                          convergence_deg - o->sector[0];
            from = fmod(fmod(from, 360.0) + 360.0, 360.0);
            if (from > width) {
                seen[(size_t)y * win->w + x] = TP_VIEWSHED_OUTSIDE;
                if (values)
                    values[(size_t)y * win->w + x] = NAN;
            }
        }
}

/* The posts within the radius of observer ob (the disc, as tp_viewshed_compute: not the
 * window's square) with a height: how many (*valid), how many of them seen (*visible), each
 * marked in reach. */
static void count_seen(const tp_planner_window* win, const viewshed_observer* ob,
                       double radius_m, const uint8_t* seen, size_t* visible, size_t* valid,
                       uint8_t* reach)
{
    const double r2 = radius_m > 0.0 ? radius_m * radius_m : INFINITY;
    *visible = *valid = 0;
    for (int y = 0; y < win->h; ++y)
        for (int x = 0; x < win->w; ++x) {
            const double dx = (double)(x + win->x0 - ob->x) * win->gt[1],
                         dy = (double)(y + win->y0 - ob->y) * win->gt[5];
            const size_t i = (size_t)y * win->w + x;
            if (dx * dx + dy * dy > r2 || win->z[i] != win->z[i])
                continue;
            *visible += seen[i] == TP_VIEWSHED_VISIBLE;
            *valid += 1;
            reach[i] = 1;
        }
}

/* Sweeps every observer over the window into seen (one observer: its visibility) and, with
 * several, count (the observers that see each post); each one's share into visible[k] /
 * valid[k], the posts any radius reaches marked in reach. */
static tp_status sweep_observers(const viewshed_cli* o, const tp_planner_window* win,
                                 const viewshed_observer* obs, uint8_t* seen, uint8_t* count,
                                 float* values, uint8_t* reach, size_t* visible, size_t* valid,
                                 tp_error* err)
{
    tp_viewshed_options vo = tp_viewshed_options_default();
    vo.observer_height_m = o->observer_height_m;
    vo.target_height_m = o->target_height_m;
    vo.curvature_coeff = o->curvature_coeff;
    vo.radius_m = o->radius_m;
    for (int k = 0; k < o->observer_count; ++k) {
        const int ox = obs[k].x - win->x0, oy = obs[k].y - win->y0;
        tp_status s = tp_viewshed_compute_values(win->z, win->n, win->w, win->h, win->gt, ox, oy,
                                                 &vo, o->values, seen, values, win->n, err);
        if (s != TP_OK)
            return s;
        if (o->has_sector)
            keep_sector(o, win, ox, oy, obs[k].convergence_deg, seen, values);
        count_seen(win, &obs[k], o->radius_m, seen, &visible[k], &valid[k], reach);
        if (count)
            for (size_t i = 0; i < win->n; ++i)
                count[i] += seen[i] == TP_VIEWSHED_VISIBLE;
    }
    return TP_OK;
}

static void print_summary(tp_ground* g, const viewshed_cli* o, const tp_planner_window* win,
                          const viewshed_observer* obs, const uint8_t* count,
                          const uint8_t* reach, const size_t* visible, const size_t* valid)
{
    const int several = o->observer_count > 1;
    for (int k = 0; k < o->observer_count; ++k) {
        double lat, lon;
        tp_ground_grid_latlon(g, obs[k].x, obs[k].y, &lat, &lon);
        const float z = win->z[(size_t)(obs[k].y - win->y0) * win->w + (obs[k].x - win->x0)];
        char label[32] = "observer";
        if (several)
            snprintf(label, sizeof label, "observer %d", k + 1);
        printf("%-10s %.6f %.6f on post (%d, %d), ground %.1f m, eye %.1f m\n", label, lat, lon,
               obs[k].x, obs[k].y, (double)z, z + o->observer_height_m);
    }
    if (o->radius_m > 0.0)
        printf("window     %dx%d posts from (%d, %d) (radius %.0f m)\n", win->w, win->h, win->x0,
               win->y0, o->radius_m);
    else
        printf("window     %dx%d posts: the whole grid (no radius)\n", win->w, win->h);
    for (int k = 0; k < o->observer_count; ++k) {
        char label[32] = "seen";
        if (several)
            snprintf(label, sizeof label, "seen by %d", k + 1);
        printf("%-10s %zu of %zu posts with a height%s (%.1f%%)\n", label, visible[k], valid[k],
               o->radius_m > 0.0 ? " within the radius" : "",
               valid[k] ? 100.0 * visible[k] / valid[k] : 0.0);
    }
    if (o->has_sector)
        printf("sector     %.1f to %.1f degrees clockwise from true north (posts outside it are "
               "not seen)\n",
               o->sector[0], o->sector[1]);
    if (!count)
        return;
    size_t reached = 0, any = 0, all = 0;
    for (size_t i = 0; i < win->n; ++i) {
        reached += reach[i];
        any += count[i] > 0;
        all += count[i] == o->observer_count;
    }
    printf("covered    %zu of %zu posts seen by at least one observer (%.1f%%), %zu by all %d\n",
           any, reached, reached ? 100.0 * any / reached : 0.0, all, o->observer_count);
}

/* What the raster's band says it holds. */
static const char* band_description(const viewshed_cli* o)
{
    if (o->observer_count > 1)
        return "observers that see the post (0 .. N)";
    if (o->values == TP_VIEWSHED_VALUES_ANGLE)
        return "vertical angle from the eye to the target, degrees (0 down, 90 level, 180 up); "
               "nodata where not seen";
    if (o->values == TP_VIEWSHED_VALUES_CLEARANCE)
        return "target above the sight line over the horizon, metres (below 0: hidden by so "
               "much)";
    return "visibility: 255 seen, 0 not seen or beyond the radius";
}

/* The values' range over the posts that have one. */
static void print_values(const viewshed_cli* o, const float* values, size_t n)
{
    double lo = INFINITY, hi = -INFINITY;
    size_t count = 0;
    for (size_t i = 0; i < n; ++i)
        if (values[i] == values[i]) {
            lo = values[i] < lo ? values[i] : lo;
            hi = values[i] > hi ? values[i] : hi;
            count++;
        }
    if (o->values == TP_VIEWSHED_VALUES_ANGLE)
        printf("angle      %.2f .. %.2f deg (90: level) at the %zu posts seen\n", lo, hi, count);
    else
        printf("clearance  %.2f .. %.2f m at %zu posts (below 0: hidden)\n", lo, hi, count);
}

int tp_cli_viewshed(int argc, char** argv)
{
    viewshed_cli o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    for (int k = 0; k < o.observer_count; ++k) { /* usage errors before any work */
        tp_position_readings pos;
        if (!tp_planner_position("viewshed", "--observer", o.observers[k], &pos))
            return TP_EXIT_USAGE;
    }
    const int floats = o.values != TP_VIEWSHED_VALUES_NONE;
    if ((code = tp_cli_output_check("viewshed", "-o", o.out,
                                    floats ? TP_OUTPUT_FLOAT_RASTER : TP_OUTPUT_BYTE_RASTER)) !=
        TP_EXIT_OK)
        return code;
    tp_error err = {{0}};
    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("viewshed", &o.src, &g)) != TP_EXIT_OK)
        return code;
    viewshed_observer obs[VIEWSHED_MAX_OBSERVERS];
    if ((code = locate_observers(&o, g, obs)) != TP_EXIT_OK) {
        tp_ground_destroy(g);
        return code;
    }
    const int several = o.observer_count > 1;
    tp_planner_window win;
    observers_window(g, obs, o.observer_count, o.radius_m, &win);
    uint8_t* seen = malloc(win.n);
    uint8_t* reach = calloc(win.n, 1);
    uint8_t* count = several ? calloc(win.n, 1) : NULL;
    float* values = floats ? malloc(win.n * sizeof *values) : NULL;
    size_t visible[VIEWSHED_MAX_OBSERVERS], valid[VIEWSHED_MAX_OBSERVERS];
    tp_status s = seen && reach && (count || !several) && (values || !floats)
                      ? tp_planner_window_read(g, &win, NULL, &err)
                      : tp_error_set(&err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    const double t1 = tp_clock_s();
    if (s == TP_OK)
        s = sweep_observers(&o, &win, obs, seen, count, values, reach, visible, valid, &err);
    const double t2 = tp_clock_s();
    if (s == TP_OK && floats)
        s = tp_planner_float_raster_write(g, o.out, values, &win, band_description(&o), &err);
    else if (s == TP_OK)
        s = tp_planner_raster_write(g, o.out, several ? count : seen, &win, band_description(&o),
                                    &err);
    if (s == TP_OK) {
        print_summary(g, &o, &win, obs, count, reach, visible, valid);
        if (floats)
            print_values(&o, values, win.n);
        printf("time       %.1f ms reading the ground, %.1f ms for the viewshed%s\n",
               1e3 * win.read_s, 1e3 * (t2 - t1), several ? "s" : "");
        tp_cli_note("wrote %s", o.out);
    } else if (!tp_interrupted()) {
        tp_cli_error("%s: %s", o.src.path, err.message);
    }
    tp_planner_window_free(&win);
    free(seen);
    free(reach);
    free(count);
    free(values);
    tp_ground_destroy(g);
    return s == TP_OK ? tp_cli_finish(TP_EXIT_OK) : tp_planner_finish(TP_EXIT_FAILURE);
}
