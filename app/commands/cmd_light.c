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
        "       terrapatch light DEM|STORE --sun AZ,EL -o OUT.tif [--values ...] [--radius M\n"
        "                        --at POS] [--cache-dir DIR]\n"
        "       terrapatch light DEM|STORE --day --date YYYY-MM-DD [--maps N] [--margin M]\n"
        "                        [-o OUT.tpl] [--json FILE|-] [--quiet] [--cache-dir DIR]\n"
        "       terrapatch light DEM|STORE --day --date YYYY-MM-DD -o HOURS.tif [--radius M\n"
        "                        --at POS] [--maps N] [--margin M] [--json FILE|-] [--quiet]\n"
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
        "(1010 mbar, 10 C); or --sun gives it. One direction serves the whole window (a flat\n"
        "earth: the sun's elevation changes by 0.009 degree per km across it). Voids are 0 and\n"
        "cast nothing.\n"
        "\n"
        "options:\n"
        "  --date YYYY-MM-DD      the date (required but with --sun; its sunrise and sunset\n"
        "                         are printed, for the day of local mean solar time at the\n"
        "                         centre)\n"
        "  --time HH:MM[:SS][ZONE] the time (required but with --sun or --day); ZONE: Z, UTC,\n"
        "                         +HH:MM, -HHMM, +HH, after the time or one space; no zone:\n"
        "                         UTC\n"
        "  --sun AZ,EL            the sun given instead of --date and --time: azimuth AZ\n"
        "                         degrees clockwise from true north (0 .. 360; turned to grid\n"
        "                         north by the convergence at the centre or --at, as for a\n"
        "                         date), elevation EL degrees above the horizon (-90 .. 90, as\n"
        "                         seen: no refraction added; EL <= 0: everything in shadow)\n"
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
        "  -o, --output HOURS.tif with --day: instead of the map, a one-band Float32 raster of\n"
        "                         the hours of direct sunlight at each post over the day (the\n"
        "                         map's lit intervals, to 1/255 of the day each end; voids\n"
        "                         -9999, nodata): .tif, .gpkg, .img or .asc; takes --radius M\n"
        "                         --at POS (the sun computed at POS; the margin around the\n"
        "                         window still shadows it)\n"
        "  --json FILE|-          the summary as JSON (\"-\": on stdout instead of the text)\n"
        "  --quiet                no progress on stderr\n",
        "examples:\n"
        "  $ terrapatch light mt_hood.tif --date 2026-06-21 --time '18:30 -07:00' -o sun.tif\n"
        "  $ terrapatch light mt_hood.tif --sun 135,30 -o sun.tif\n"
        "  $ terrapatch light mt_hood.tpt --day --date 2026-06-21     # writes mt_hood.tpl\n"
        "  $ terrapatch light mt_hood.tif --day --date 2026-06-21 -o hours.tif\n"
        "\n"
        "Exit status: 0 written (also with the sun below the horizon: all 0); 1 the DEM cannot\n"
        "be read, has no CRS, --at is outside it or in a void, the output cannot be written\n"
        "(nothing is left behind); 2 usage error (OUT's extension naming no format written\n"
        "included).\n");
}

/* --sun AZ,EL: 1 with the true azimuth and the elevation, else 0 after one line. */
static int parse_sun(const char* value, double out[2])
{
    static const char expected[] = "AZ,EL: an azimuth 0 .. 360 (degrees clockwise from true "
                                   "north) and an elevation -90 .. 90 (degrees above the horizon)";
    if (!tp_option_pair("light", "--sun", value, -90.0, 360.0, expected, out))
        return 0;
    if (out[1] > 90.0 || out[0] < 0.0)
        return tp_option_error("light", "--sun", expected, value), 0;
    return 1;
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
        TP_OPT_TEXT("--sun", NULL, &o->sun),
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
    if (o->sun && (o->date || o->time || o->day))
        return tp_cli_usage("light", "--sun AZ,EL gives the sun at one moment: no --date, --time "
                                     "or --day");
    if (o->sun && !parse_sun(o->sun, o->sun_deg))
        return TP_EXIT_USAGE;
    if (!o->sun && !o->date)
        return tp_cli_usage("light", "missing --date YYYY-MM-DD (or --sun AZ,EL)");
    if (o->day) {
        long n = o->maps;
        if (maps && !tp_option_integer("light", "--maps", maps, 2, TP_LIGHT_DAY_MAPS_MAX,
                                       "an integer 2 .. 1024", &n))
            return TP_EXIT_USAGE;
        o->maps = (int)n;
        if (o->time)
            return tp_cli_usage("light", "--day makes the whole day's map: no --time");
        o->hours = o->out && !tp_light_is_map(o->out);
        if (o->values)
            return tp_cli_usage("light", "--day writes %s: no --values",
                                o->hours ? "the hours of sunlight" : "the light map");
        if (!o->hours && (o->at || o->radius_m > 0.0))
            return tp_cli_usage("light", "--day's light map (.tpl) covers the whole grid: no "
                                         "--at or --radius (a raster -o OUT.tif takes them)");
        if (o->radius_m > 0.0 && !o->at)
            return tp_cli_usage("light", "--radius needs --at POS");
        return -1;
    }
    if (maps || o->json || o->quiet || o->margin_m != TP_LIGHT_DAY_MARGIN_M)
        return tp_cli_usage("light", "--maps, --margin, --json and --quiet go with --day");
    if (!o->time && !o->sun)
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

/* Where the sun is for the one-moment raster: from --sun, or from libnova at --date --time over
 * the place (with the day's sunrise and sunset). */
typedef struct moment_sun {
    tp_sun_time when; /* not with --sun */
    tp_sun_pos pos;   /* the date's: true azimuth, elevations */
    tp_sun_day day;
    double true_az, grid_az, elevation; /* what lights the ground */
} moment_sun;

static tp_status moment_sun_at(const tp_light_cli* o, const tp_light_place* here, moment_sun* m,
                               tp_error* err)
{
    if (o->sun) {
        m->true_az = o->sun_deg[0];
        m->grid_az = tp_light_grid_azimuth(here, m->true_az);
        m->elevation = o->sun_deg[1];
        return TP_OK;
    }
    tp_status s = tp_light_sun(here, m->when.unix_s, &m->pos, &m->grid_az, err);
    if (s == TP_OK)
        s = tp_sun_rise_set(
            here->lat_deg, here->lon_deg,
            tp_sun_local_day_start(m->when.year, m->when.month, m->when.day, here->lon_deg),
            &m->day, err);
    m->true_az = m->pos.azimuth_deg;
    m->elevation = m->pos.apparent_elevation_deg;
    return s;
}

/* The summary on stdout (README's example). */
static void print_moment(const tp_light_cli* o, const tp_light_place* here, const moment_sun* m,
                         const tp_planner_window* win, size_t sunlit, size_t valid, double shadow_s)
{
    printf("place      %.6f %.6f (post %.0f, %.0f: where the sun is %s); grid north is %.3f deg "
           "%s of true north\n",
           here->lat_deg, here->lon_deg, here->x, here->y,
           o->sun ? "turned to grid north" : "computed", fabs(here->convergence_deg),
           here->convergence_deg >= 0.0 ? "east" : "west");
    if (o->sun) {
        printf("sun        azimuth %.3f deg true, %.3f deg grid; elevation %.3f deg (given by "
               "--sun: no date or time, no refraction added)\n",
               m->true_az, m->grid_az, m->elevation);
    } else {
        char local[48], utc[48];
        const int zone = m->when.zone_offset_s;
        tp_sun_time_format(m->when.unix_s, zone, local, sizeof local);
        tp_sun_time_format(m->when.unix_s, 0, utc, sizeof utc);
        printf("time       %s%s%s\n", local, zone ? " = " : "", zone ? utc : "");
        printf("sun        azimuth %.3f deg true, %.3f deg grid; elevation %.3f deg (%.3f deg "
               "without refraction)\n",
               m->true_az, m->grid_az, m->elevation, m->pos.elevation_deg);
        tp_light_print_day(&m->day, zone);
    }
    if (m->elevation <= 0.0)
        printf("note       the sun is %s the horizon: everything is in shadow\n",
               m->elevation < 0.0 ? "below" : "on");
    printf("window     %dx%d posts from (%d, %d)%s\n", win->w, win->h, win->x0, win->y0,
           o->radius_m > 0.0 ? "" : ": the whole grid");
    printf("sunlit     %zu of %zu posts with a height (%.1f%%)\n", sunlit, valid,
           valid ? 100.0 * sunlit / valid : 0.0);
    printf("time       %.1f ms reading the ground, %.1f ms for the shadows\n", 1e3 * win->read_s,
           1e3 * shadow_s);
}

int tp_cli_light(int argc, char** argv)
{
    tp_light_cli o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    if (o.day)
        return tp_light_day_run(&o);
    moment_sun m;
    memset(&m, 0, sizeof m);
    tp_error why = {{0}};
    if (!o.sun && !tp_sun_time_parse(o.date, o.time, &m.when, &why)) {
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
    tp_status s = moment_sun_at(&o, &here, &m, &err);
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
        s = tp_shadow_compute(z, n, w, h, dx, dy, m.grid_az, m.elevation, lit, NULL, n, &err);
    if (s == TP_OK && o.illumination)
        s = tp_shadow_illumination(z, n, w, h, dx, dy, m.grid_az, m.elevation, lit, out, n, &err);
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
    print_moment(&o, &here, &m, &win, sunlit, valid, t2 - t1);
    tp_cli_note("wrote %s", o.out);
    tp_planner_window_free(&win);
    free(lit);
    free(out);
    tp_ground_destroy(g);
    return tp_cli_finish(TP_EXIT_OK);
}
