/*
 * cmd_viewshed.c - `terrapatch viewshed DEM|STORE --observer POS -o OUT.tif`: which samples of
 * the render grid an observer sees (issue 13, section 3). The window of the render grid the
 * radius reaches (the whole grid without a radius, as gdal_viewshed's default -md 0) is read
 * at its posts through the ground module (the stored samples, as `point` reads them), the core's
 * tp_viewshed_compute sweeps it, and tp_viewshed_write writes it on the render grid's
 * georeference in the format OUT's extension names (output_check.h), atomically.
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

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct viewshed_cli {
    tp_planner_source src; /* the DEM or store, --cache-dir and the DEM options */
    const char* observer;
    const char* out;
    double observer_height_m, target_height_m, radius_m, curvature_coeff;
} viewshed_cli;

static void print_help(void)
{
    tp_planner_help(
        "usage: terrapatch viewshed DEM|STORE --observer POS -o OUT.tif [--observer-height M]\n"
        "                           [--target-height M] [--radius M] [--curvature-coeff C]\n"
        "                           [--cache-dir DIR]\n"
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
        "Conventions are gdal_viewshed's: heights above the ground, every height lowered by\n"
        "C * d^2 / (2 * 6378137 m) at distance d from the observer (0.85714: curvature with\n"
        "standard refraction; 1: curvature without refraction; 0: a flat earth).\n"
        "\n"
        "options:\n"
        "  --observer POS         where the observer stands (required; any form 'terrapatch\n"
        "                         coord' reads, one argument: quote it when it has spaces)\n"
        "  -o, --output OUT.tif   the raster to write (required), in the format its extension\n"
        "                         names: .tif GeoTIFF, .png PNG (with a .wld world file and\n"
        "                         the CRS in .png.aux.xml), .gpkg, .jp2 (lossless), .img,\n"
        "                         .asc, .bmp\n"
        "  --observer-height M    eye above the ground (default 2)\n"
        "  --target-height M      target above the ground (default 0)\n"
        "  --radius M             how far to look, metres (default 0: the whole grid)\n"
        "  --curvature-coeff C    curvature and refraction coefficient (default 0.85714)\n"
        "  -h, --help             show this help\n",
        "example:\n"
        "  $ terrapatch viewshed N42E001.hgt --observer 42.5,1.5 --radius 20000 -o seen.tif\n"
        "\n"
        "Exit status: 0 written; 1 the DEM cannot be read, the observer is outside it or in a\n"
        "void, OUT.tif cannot be written (nothing is left behind); 2 usage error (OUT's\n"
        "extension naming no format written included).\n");
}

static int parse_options(int argc, char** argv, viewshed_cli* o)
{
    memset(o, 0, sizeof *o);
    tp_planner_source_init(&o->src);
    o->observer_height_m = TP_VIEWSHED_OBSERVER_HEIGHT_M;
    o->target_height_m = TP_VIEWSHED_TARGET_HEIGHT_M;
    o->curvature_coeff = TP_VIEWSHED_CURVATURE_COEFF;
    const tp_option options[] = {
        TP_OPT_TEXT("--observer", NULL, &o->observer),
        TP_OPT_TEXT("--output", "-o", &o->out),
        TP_OPT_NUMBER("--observer-height", &o->observer_height_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_NUMBER("--target-height", &o->target_height_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_NUMBER("--radius", &o->radius_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_NUMBER("--curvature-coeff", &o->curvature_coeff, 0.0, HUGE_VAL, "a number >= 0"),
    };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), NULL, NULL};
    const int code = tp_planner_parse("viewshed", argc, argv, print_help, own, &o->src,
                                      " (quote a position with spaces: --observer "
                                      "\"45.37 -121.69\")");
    if (code >= 0)
        return code;
    if (!o->observer)
        return tp_cli_usage("viewshed", "missing --observer POS");
    if (!o->out)
        return tp_cli_usage("viewshed", "missing -o OUT.tif");
    return -1;
}

int tp_cli_viewshed(int argc, char** argv)
{
    viewshed_cli o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    tp_position_readings pos;
    if (!tp_planner_position("viewshed", "--observer", o.observer, &pos))
        return TP_EXIT_USAGE;
    if ((code = tp_cli_output_check("viewshed", "-o", o.out, TP_OUTPUT_BYTE_RASTER)) != TP_EXIT_OK)
        return code;
    tp_error err = {{0}};
    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("viewshed", &o.src, &g)) != TP_EXIT_OK)
        return code;
    double fx, fy, fh;
    if (!tp_planner_locate("viewshed", o.src.path, g, &pos, o.observer, &fx, &fy, &fh)) {
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    /* the window the radius reaches, as tp_viewshed_compute clips it, on the DEM's posts */
    const int ox = (int)lround(fx), oy = (int)lround(fy);
    tp_planner_window win;
    tp_planner_window_around(g, ox, oy, o.radius_m, &win);
    const int x0 = win.x0, y0 = win.y0, w = win.w, h = win.h;
    uint8_t* seen = malloc(win.n);
    tp_status s = seen ? tp_planner_window_read(g, &win, NULL, &err)
                       : tp_error_set(&err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    const float* z = win.z;
    tp_viewshed_options vo = tp_viewshed_options_default();
    vo.observer_height_m = o.observer_height_m;
    vo.target_height_m = o.target_height_m;
    vo.curvature_coeff = o.curvature_coeff;
    vo.radius_m = o.radius_m;
    const double t1 = tp_clock_s();
    if (s == TP_OK)
        s = tp_viewshed_compute(z, win.n, w, h, win.gt, ox - x0, oy - y0, &vo, seen, win.n, &err);
    const double t2 = tp_clock_s();
    if (s == TP_OK)
        s = tp_planner_raster_write(g, o.out, seen, &win,
                                    "visibility: 255 seen, 0 not seen or beyond the radius", &err);
    if (s != TP_OK) {
        if (!tp_interrupted())
            tp_cli_error("%s: %s", o.src.path, err.message);
        tp_planner_window_free(&win);
        free(seen);
        tp_ground_destroy(g);
        return tp_planner_finish(TP_EXIT_FAILURE);
    }
    /* the posts the sweep looked at: the disc of the radius (as tp_viewshed_compute), not the
     * window's square */
    const double* gt = win.gt;
    const double r2 = o.radius_m > 0.0 ? o.radius_m * o.radius_m : INFINITY;
    size_t visible = 0, valid = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double dx = (double)(x + x0 - ox) * gt[1], dy = (double)(y + y0 - oy) * gt[5];
            const size_t i = (size_t)y * w + x;
            if (dx * dx + dy * dy > r2)
                continue;
            visible += seen[i] == TP_VIEWSHED_VISIBLE;
            valid += z[i] == z[i];
        }
    double lat, lon;
    tp_ground_grid_latlon(g, ox, oy, &lat, &lon);
    printf("observer   %.6f %.6f on post (%d, %d), ground %.1f m, eye %.1f m\n", lat, lon, ox,
           oy, (double)z[(size_t)(oy - y0) * w + (ox - x0)],
           z[(size_t)(oy - y0) * w + (ox - x0)] + o.observer_height_m);
    if (o.radius_m > 0.0)
        printf("window     %dx%d posts from (%d, %d) (radius %.0f m)\n", w, h, x0, y0,
               o.radius_m);
    else
        printf("window     %dx%d posts: the whole grid (no radius)\n", w, h);
    printf("seen       %zu of %zu posts with a height%s (%.1f%%)\n", visible, valid,
           o.radius_m > 0.0 ? " within the radius" : "", valid ? 100.0 * visible / valid : 0.0);
    printf("time       %.1f ms reading the ground, %.1f ms for the viewshed\n",
           1e3 * win.read_s, 1e3 * (t2 - t1));
    tp_cli_note("wrote %s", o.out);
    tp_planner_window_free(&win);
    free(seen);
    tp_ground_destroy(g);
    return tp_cli_finish(TP_EXIT_OK);
}
