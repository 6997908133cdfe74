/*
 * cmd_point.c - `terrapatch point DEM|STORE POS`: what is here? The position in every form a
 * planner reads (decimal degrees, DMS, MGRS with spaces, UTM), the ground's height as stored
 * with what is known of its vertical datum, and the slope and aspect there (issue 13, section
 * 1). Positions are read by position.c, the ground by ground.c; the same readout is the
 * viewer's pick (view/point_pick.c) through tp_point_readout.
 */
#include "terrapatch.h"
#include "cli.h"
#include "planner_cli.h"
#include "point_readout.h"

#include "tp_geo.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define DEFAULT_PRECISION 5

typedef struct point_options {
    tp_planner_source src; /* the DEM or store, --cache-dir and the DEM options */
    char* pos_args[8];
    int pos_count;
    int precision;
    const char* slope_method; /* --slope-method horn|central */
    const char* json;
} point_options;

static void print_help(void)
{
    tp_planner_help(
        "usage: terrapatch point DEM|STORE POS [--precision N] [--slope-method horn|central]\n"
        "                        [--json F] [--cache-dir DIR]\n"
        "\n"
        "What is here: the position POS on the ground of DEM (any raster GDAL reads, built\n"
        "into the store cache first as 'terrapatch view' does) or of a store (.tpt). Prints\n"
        "the position as latitude/longitude (decimal degrees and degrees-minutes-seconds),\n"
        "MGRS with spaces, UTM/UPS, the elevation as stored (with the vertical datum as the\n"
        "file states it, else 'unknown'), and the slope and aspect of the ground there.\n"
        "\n"
        "POS, in any form 'terrapatch coord' reads (one argument or several):\n"
        "  45.373 -121.696            decimal degrees, latitude first\n"
        "  45.373,-121.696            the same with a comma\n"
        "  45d22'23\"N 121d41'45\"W     degrees-minutes-seconds (GeographicLib's DMS rules:\n"
        "  45:22:23N 121:41:45W       d ' \" or : separators, N S E W before or after;\n"
        "                             with hemisphere letters either order works)\n"
        "  55 28 41.88 N 2 08 44.16 W the same with spaces (letters end each coordinate)\n"
        "  10n 601000 5026000         UTM zone and hemisphere, easting, northing (metres);\n"
        "                             also as printed here (10n 601000.0 E 5026000.0 N)\n"
        "  10T 601000 5026000         UTM zone and latitude band, as maps and GPS units\n"
        "                             write it (a band S that may be the southern\n"
        "                             hemisphere: the reading on the DEM, with a note)\n"
        "  10TER0100026000            MGRS, any precision (the centre of its square),\n"
        "                             also with spaces (10T ER 01000 26000)\n"
        "\n"
        "The height is that of the full-resolution surface at POS (the store's triangulated\n"
        "posts: exact at a post, as stored). Slope (degrees from horizontal) and aspect (the\n"
        "direction the slope faces, downhill, degrees clockwise from true north; also from\n"
        "grid north, with the meridian convergence between them) come from Horn's 3x3\n"
        "window of that surface one post around POS, as gdaldem, GRASS and ArcGIS compute\n"
        "them (central differences where a post of the window has no height).\n"
        "\n"
        "options:\n"
        "  --precision N    MGRS digits per coordinate, 0..11 (default 5 = 1 m)\n"
        "  --slope-method horn|central\n"
        "                   slope and aspect by Horn's 3x3 window (the default, as gdaldem)\n"
        "                   or by central differences of the four neighbours\n"
        "  --json F         also write the readout as JSON to F ('-' for stdout, instead of\n"
        "                   the text)\n"
        "  -h, --help       show this help\n",
        "example:\n"
        "  $ terrapatch point lf_elev_220_mt_hood_utm.tif 45.3736 -121.6959\n"
        "\n"
        "Exit status: 0 done; 1 the DEM cannot be read, or POS is outside the DEM or in a\n"
        "void (no height there); 2 usage error (a position that cannot be read included).\n");
}

/* -1 when fine, else the exit code. Options may come anywhere; an argument starting with '-'
 * and then a digit or '.' is a position (-121.7), not an option. */
static int parse_options(int argc, char** argv, point_options* o)
{
    memset(o, 0, sizeof *o);
    tp_planner_source_init(&o->src);
    o->precision = DEFAULT_PRECISION;
    const tp_option options[] = {
        TP_OPT_INTEGER("--precision", &o->precision, 0, 11, "an integer from 0 to 11"),
        TP_OPT_TEXT("--json", NULL, &o->json),
        TP_OPT_TEXT("--slope-method", NULL, &o->slope_method),
        };
    tp_options p;
    tp_options_init(&p, "point", argc, argv, print_help);
    p.negative_operands = 1;
    tp_options_add(&p, options, TP_OPTIONS_COUNT(options), NULL, NULL);
    tp_planner_source_add(&p, &o->src);
    for (int c; (c = tp_options_next(&p)) != TP_OPTIONS_END;) {
        if (c == TP_OPTIONS_EXIT)
            return p.exit;
        if (!o->src.path)
            o->src.path = p.value;
        else if (o->pos_count == (int)(sizeof o->pos_args / sizeof o->pos_args[0]))
            return tp_cli_usage("point", "too many arguments for a position");
        else
            o->pos_args[o->pos_count++] = (char*)p.value;
    }
    if (o->slope_method && strcmp(o->slope_method, "horn") && strcmp(o->slope_method, "central"))
        return tp_option_error("point", "--slope-method", "horn or central", o->slope_method),
               TP_EXIT_USAGE;
    if (!o->src.path)
        return tp_cli_usage("point", "missing DEM and position");
    if (!o->pos_count)
        return tp_cli_usage("point",
                                "missing position (e.g. 45.37 -121.69, or 10n 601000 5026000)");
    return -1;
}

/* The readout as text, and as JSON (tp_planner_write_fn). */
static void write_text(FILE* f, void* readout)
{
    char buf[2048];
    tp_point_readout_text(readout, buf, sizeof buf);
    fputs(buf, f);
}

static void write_json(FILE* f, void* readout)
{
    tp_point_readout_json(readout, f);
}

int tp_cli_point(int argc, char** argv)
{
    point_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    char text[1024];
    tp_error err = {{0}};
    if (!tp_position_join(o.pos_args, o.pos_count, text, sizeof text))
        return tp_cli_usage("point", "the position is too long");
    tp_position_readings readings;
    if (!tp_planner_position("point", "position", text, &readings))
        return TP_EXIT_USAGE;
    if (!tp_planner_check_outputs(&o.json, 1))
        return TP_EXIT_FAILURE;

    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("point", &o.src, &g)) != TP_EXIT_OK)
        return code;
    if (o.slope_method && !strcmp(o.slope_method, "central"))
        tp_ground_set_slope_method(g, TP_SLOPE_CENTRAL);
    tp_point_readout r;
    tp_position pos;
    char hint[256];
    if (!tp_planner_choose("point", o.src.path, g, &readings, text, &pos)) {
        code = TP_EXIT_FAILURE;
    } else if (!tp_point_readout_at_position(g, o.src.path, &pos, text, o.precision, &r, &err)) {
        tp_planner_swap_hint(g, &pos, hint, sizeof hint);
        tp_cli_error("%s: %s%s", o.src.path, tp_cli_unprefixed(o.src.path, err.message), hint);
        code = TP_EXIT_FAILURE;
    } else {
        const tp_planner_outputs out = {.json = o.json, .write_text = write_text,
                                        .write_json = write_json};
        code = tp_planner_write_outputs("point", &out, &r) ? TP_EXIT_OK : TP_EXIT_FAILURE;
    }
    tp_ground_destroy(g);
    /* no interruption check: nothing after the ground's opening waits on a signal */
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
