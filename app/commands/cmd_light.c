/*
 * cmd_light.c - `terrapatch light DEM|STORE --date YYYY-MM-DD --time HH:MM[zone] -o OUT.tif`:
 * where the sun shines on the ground at a moment, with the terrain's own shadows (issue 15,
 * part 2; docs/light.md). The window of the render grid (the whole grid, or --radius around
 * --at) is read at its posts through the ground module as `viewshed` reads it; the sun's
 * position at the window's centre comes from tp_sun.h (libnova), its azimuth turned from true
 * to grid north by the meridian convergence there; the core's tp_shadow_compute sweeps the
 * shadows (tp_shadow_illumination adds the slope's cosine for --values illumination); and
 * tp_byte_raster_write writes the result on the render grid's georeference in the format OUT's
 * extension names (output_check.h), atomically.
 */
#define _POSIX_C_SOURCE 200809L
#include "terrapatch.h"
#include "light.h"
#include "clock.h"
#include "cli.h"
#include "ground_locate.h"
#include "output_check.h"
#include "planner_cli.h"
#include "sun_time.h"

#include "tp_core.h"
#include "tp_io.h"
#include "tp_sun.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void print_help(void)
{
    tp_planner_help(
        "usage: terrapatch light DEM|STORE --date YYYY-MM-DD --time HH:MM[:SS][ZONE]\n"
        "                        -o OUT.tif [--values lit|illumination] [--radius M --at POS]\n"
        "                        [--cache-dir DIR]\n"
        "       terrapatch light DEM|STORE --day --date YYYY-MM-DD [--maps N] [--margin M]\n"
        "                        [-o OUT.tpl] [--json FILE|-] [--quiet] [--cache-dir DIR]\n"
        "\n"
        "Where the sun shines on the ground of DEM (any raster GDAL reads, built into the\n"
        "store cache first as 'terrapatch view' does) or of a store (.tpt) at one moment, with\n"
        "the shadows the terrain casts on itself: a one-band Byte raster on the render grid\n"
        "(the DEM's own grid, or a geographic DEM warped to the UTM/UPS zone of its centre),\n"
        "covering the whole grid or the window --radius reaches around --at.\n"
        "\n"
        "The sun's position is libnova's (VSOP87; checked against Meeus and the NREL SPA,\n"
        "docs/light.md) for the window's centre: its azimuth from true north less the meridian\n"
        "convergence there gives the grid azimuth, its elevation includes refraction\n"
        "(1010 mbar, 10 C). One direction serves the whole window (a flat earth: the sun's\n"
        "elevation changes by 0.009 degree per km across it). Voids are 0 and cast nothing.\n"
        "\n"
        "options:\n"
        "  --date YYYY-MM-DD      the date (required; its sunrise and sunset are printed, for\n"
        "                         the day of local mean solar time at the centre)\n"
        "  --time HH:MM[:SS][ZONE] the time (required); ZONE: Z, UTC, +HH:MM, -HHMM, +HH,\n"
        "                         after the time or one space; no zone: UTC\n"
        "  -o, --output OUT.tif   the raster to write (required), in the format its extension\n"
        "                         names: .tif GeoTIFF, .png PNG (with a .wld world file and\n"
        "                         the CRS in .png.aux.xml), .gpkg, .jp2 (lossless), .img,\n"
        "                         .asc, .bmp\n"
        "  --values lit           255 in sunlight, 0 in shadow (default)\n"
        "  --values illumination  the direct sunlight, 255 * cos(incidence): 0 in shadow and on\n"
        "                         slopes facing away from the sun\n"
        "  --radius M             only the window of posts within M metres (east and north) of\n"
        "                         --at (a square); needs --at\n"
        "  --at POS               the window's centre and the place the sun is computed for\n"
        "                         (alone: the whole grid, the sun at POS; any form\n"
        "                         'terrapatch coord' reads)\n"
        "  -h, --help             show this help\n"
        "\n"
        "The day (--day): the light map of the whole grid from sunrise to sunset of --date\n"
        "(at the grid's centre; a polar day or night: its 24 hours from local mean midnight)\n"
        "as an imagery pyramid (.tpl, docs/light.md) the viewer streams: each post's lit\n"
        "intervals in 255 steps of the day, found from N sun positions (more where the sun is\n"
        "low and shadows move fast), the grid cut into tiles of 1024x1024 posts, each computed\n"
        "with the ground within --margin around it (which may cast shadows into it).\n"
        "  --day                  the day's light map instead of one moment (no --time)\n"
        "  --maps N               sun positions, 2 .. 1024 (default 64)\n"
        "  --margin M             metres of ground beyond each tile that may shadow it\n"
        "                         (default 10000: shadows up to 10 km long; at most 1024\n"
        "                         posts)\n"
        "  -o, --output OUT.tpl   the light map (default: the store's path with .tpl for .tpt;\n"
        "                         for a DEM, its store's in the store cache)\n"
        "  --json FILE|-          the summary as JSON (\"-\": on stdout instead of the text)\n"
        "  --quiet                no progress on stderr\n",
        "examples:\n"
        "  $ terrapatch light mt_hood.tif --date 2026-06-21 --time '18:30 -07:00' -o sun.tif\n"
        "  $ terrapatch light mt_hood.tpt --day --date 2026-06-21     # writes mt_hood.tpl\n"
        "\n"
        "Exit status: 0 written (also with the sun below the horizon: all 0); 1 the DEM cannot\n"
        "be read, has no CRS, --at is outside it or in a void, the output cannot be written\n"
        "(nothing is left behind); 2 usage error (OUT's extension naming no format written\n"
        "included).\n");
}

/* A second operand, or a piece of --time left unquoted ("--time 18:30 -07:00"): exit 2. */
static int light_stray(tp_options* p)
{
    const char* a = p->value;
    char hint[160] = " (quote a time with a zone after a space: --time \"18:30 -07:00\")";
    if (a[0] == '-' && a[1])
        snprintf(hint, sizeof hint,
                 " (a zone after a space must be quoted with the time: --time \"18:30 %s\")", a);
    return tp_options_stray(p, NULL, hint), p->exit;
}

static int parse_options(int argc, char** argv, tp_light_cli* o)
{
    memset(o, 0, sizeof *o);
    tp_planner_source_init(&o->src);
    o->maps = TP_LIGHT_DAY_MAPS;
    o->margin_m = TP_LIGHT_DAY_MARGIN_M;
    const char* maps = NULL;
    const tp_option options[] = {
        TP_OPT_NUMBER("--radius", &o->radius_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_NUMBER("--margin", &o->margin_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_TEXT("--date", NULL, &o->date),
        TP_OPT_TEXT("--time", NULL, &o->time),
        TP_OPT_TEXT("--output", "-o", &o->out),
        TP_OPT_TEXT("--at", NULL, &o->at),
        TP_OPT_TEXT("--values", NULL, &o->values),
        TP_OPT_TEXT("--maps", NULL, &maps),
        TP_OPT_TEXT("--json", NULL, &o->json),
        TP_OPT_FLAG("--day", &o->day),
        TP_OPT_FLAG("--quiet", &o->quiet),
    };
    tp_options p;
    tp_options_init(&p, "light", argc, argv, print_help);
    p.negative_operands = 1; /* "-07:00" comes back as an operand: light_stray's hint */
    tp_options_add(&p, options, TP_OPTIONS_COUNT(options), NULL, NULL);
    tp_planner_source_add(&p, &o->src);
    for (int c; (c = tp_options_next(&p)) != TP_OPTIONS_END;) {
        if (c == TP_OPTIONS_EXIT)
            return p.exit;
        if (o->src.path || (p.value[0] == '-' && p.value[1]))
            return light_stray(&p);
        o->src.path = p.value;
    }
    if (!o->src.path)
        return tp_cli_usage("light", "missing DEM");
    if (!o->date)
        return tp_cli_usage("light", "missing --date YYYY-MM-DD");
    if (o->day) {
        long n = o->maps;
        if (maps && !tp_option_integer("light", "--maps", maps, 2, TP_LIGHT_DAY_MAPS_MAX,
                                       "an integer 2 .. 1024", &n))
            return TP_EXIT_USAGE;
        o->maps = (int)n;
        if (o->time)
            return tp_cli_usage("light", "--day makes the whole day's map: no --time");
        if (o->at || o->radius_m > 0.0 || o->values)
            return tp_cli_usage("light", "--day makes the lit map of the whole grid: no "
                                             "--at, --radius or --values");
        return -1;
    }
    if (maps || o->json || o->quiet || o->margin_m != TP_LIGHT_DAY_MARGIN_M)
        return tp_cli_usage("light", "--maps, --margin, --json and --quiet go with --day");
    if (!o->time)
        return tp_cli_usage("light", "missing --time HH:MM");
    if (!o->out)
        return tp_cli_usage("light", "missing -o OUT.tif");
    if (o->values && strcmp(o->values, "lit") && strcmp(o->values, "illumination")) {
        tp_option_error("light", "--values", "lit or illumination", o->values);
        return TP_EXIT_USAGE;
    }
    o->illumination = o->values && !strcmp(o->values, "illumination");
    if (o->radius_m > 0.0 && !o->at)
        return tp_cli_usage("light", "--radius needs --at POS");
    return -1;
}

int tp_cli_light(int argc, char** argv)
{
    tp_light_cli o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    if (o.day)
        return tp_light_day_run(&o);
    tp_sun_time when;
    tp_error why = {{0}};
    if (!tp_sun_time_parse(o.date, o.time, &when, &why)) {
        tp_cli_error("--date %s --time %s: %s", o.date, o.time, why.message);
        return TP_EXIT_USAGE;
    }
    tp_position_readings at_pos;
    if (o.at && !tp_planner_position("light", "--at", o.at, &at_pos))
        return TP_EXIT_USAGE;
    if ((code = tp_cli_output_check("light", "-o", o.out, TP_OUTPUT_BYTE_RASTER)) != TP_EXIT_OK)
        return code;
    tp_error err = {{0}};
    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("light", &o.src, &g)) != TP_EXIT_OK)
        return code;
    const tp_tree_geometry* geom = &tp_ground_scene(g)->info.header.geometry;
    double cx = 0.5 * (geom->src_width - 1), cy = 0.5 * (geom->src_height - 1); /* the sun's place */
    if (o.at) {
        double fh;
        if (!tp_planner_locate("light", o.src.path, g, &at_pos, o.at, &cx, &cy, &fh)) {
            tp_ground_destroy(g);
            return TP_EXIT_FAILURE;
        }
        cx = (double)lround(cx);
        cy = (double)lround(cy);
    }
    tp_planner_window win;
    tp_planner_window_around(g, (int)cx, (int)cy, o.at ? o.radius_m : 0.0, &win);
    tp_light_place here;
    if (!tp_light_place_at(o.src.path, g, cx, cy, &here)) {
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    const double lat = here.lat_deg, lon = here.lon_deg;
    tp_sun_pos sun;
    tp_sun_day day;
    double grid_az = 0.0;
    tp_status s = tp_light_sun(&here, when.unix_s, &sun, &grid_az, &err);
    if (s == TP_OK)
        s = tp_sun_rise_set(lat, lon, tp_sun_local_day_start(when.year, when.month, when.day, lon),
                            &day, &err);
    if (s != TP_OK) {
        tp_cli_error("%s", err.message);
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }

    const int w = win.w, h = win.h;
    const size_t n = win.n;
    uint8_t* lit = malloc(n);
    uint8_t* out = malloc(n);
    s = lit && out ? tp_planner_window_read(g, &win, "light", &err)
                   : tp_error_set(&err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    const float* z = win.z;
    const double t1 = tp_clock_s();
    const double dx = fabs(win.gt[1]), dy = fabs(win.gt[5]);
    if (s == TP_OK)
        s = tp_shadow_compute(z, n, w, h, dx, dy, grid_az, sun.apparent_elevation_deg, lit, NULL,
                              n, &err);
    if (s == TP_OK && o.illumination)
        s = tp_shadow_illumination(z, n, w, h, dx, dy, grid_az, sun.apparent_elevation_deg, lit,
                                   out, n, &err);
    else if (s == TP_OK)
        for (size_t i = 0; i < n; ++i)
            out[i] = lit[i] ? 255 : 0;
    const double t2 = tp_clock_s();
    if (s == TP_OK)
        s = tp_planner_raster_write(g, o.out, out, &win,
                                    o.illumination
                                        ? "direct sunlight: 255 * cos(incidence), 0 in shadow"
                                        : "sunlight: 255 lit, 0 in shadow or a void",
                                    &err);
    if (s != TP_OK) {
        if (!tp_interrupted())
            tp_cli_error("%s: %s", o.src.path, err.message);
        tp_planner_window_free(&win);
        free(lit);
        free(out);
        tp_ground_destroy(g);
        return tp_planner_finish(TP_EXIT_FAILURE);
    }
    size_t valid = 0, sunlit = 0;
    for (size_t i = 0; i < n; ++i) {
        valid += z[i] == z[i];
        sunlit += lit[i] == TP_SHADOW_LIT;
    }
    char local[48], utc[48];
    tp_sun_time_format(when.unix_s, when.zone_offset_s, local, sizeof local);
    tp_sun_time_format(when.unix_s, 0, utc, sizeof utc);
    printf("place      %.6f %.6f (post %.0f, %.0f: where the sun is computed); grid north is %.3f deg "
           "%s of true north\n",
           lat, lon, cx, cy, fabs(here.convergence_deg),
           here.convergence_deg >= 0.0 ? "east" : "west");
    printf("time       %s%s%s\n", local, when.zone_offset_s ? " = " : "",
           when.zone_offset_s ? utc : "");
    printf("sun        azimuth %.3f deg true, %.3f deg grid; elevation %.3f deg (%.3f deg "
           "without refraction)\n",
           sun.azimuth_deg, grid_az, sun.apparent_elevation_deg, sun.elevation_deg);
    tp_light_print_day(&day, when.zone_offset_s);
    if (sun.apparent_elevation_deg <= 0.0)
        printf("note       the sun is below the horizon: everything is in shadow\n");
    printf("window     %dx%d posts from (%d, %d)%s\n", w, h, win.x0, win.y0,
           o.radius_m > 0.0 ? "" : ": the whole grid");
    printf("sunlit     %zu of %zu posts with a height (%.1f%%)\n", sunlit, valid,
           valid ? 100.0 * sunlit / valid : 0.0);
    printf("time       %.1f ms reading the ground, %.1f ms for the shadows\n", 1e3 * win.read_s,
           1e3 * (t2 - t1));
    tp_cli_note("wrote %s", o.out);
    tp_planner_window_free(&win);
    free(lit);
    free(out);
    tp_ground_destroy(g);
    return tp_cli_finish(TP_EXIT_OK);
}
