/*
 * view_args.c - `terrapatch view`'s options (see view_args.h): the table getopt reads, one
 * function per group of options (what the run leaves, how the terrain is drawn, its light and
 * imagery, the planner's layers and bookmarks, stores), and the checks of the options together.
 */
#include "view_args.h"

#include "cli.h"
#include "imagery_view.h"

#include <getopt.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum {
    OPT_HEADLESS = 256,
    OPT_FRAMES,
    OPT_SCREENSHOT,
    OPT_CLEAR,
    OPT_WIREFRAME,
    OPT_COLOR_LOD,
    OPT_STATS,
    OPT_NO_HUD,
    OPT_EXAG,
    OPT_ONE_DRAW,
    OPT_STITCH,
    OPT_STITCH_ADD_DRAW,
    OPT_HUD,
    OPT_HIDE_FILLED,
    OPT_TEXTURE,
    OPT_GRID,
    OPT_MEASURE,
    OPT_SUN,
    OPT_PICK,
    OPT_MEMORY,
    OPT_GPU_MEMORY,
    OPT_CACHE_DIR,
    OPT_WHOLE,
    /* bookmarks (view_bookmarks.h) */
    OPT_BOOKMARK,
    OPT_SAVE_BOOKMARK,
    OPT_BOOKMARKS,
    /* planning layers (layers.h) */
    OPT_OVERLAY,
    OPT_CONTOURS,
    OPT_IMAGERY,
    OPT_NO_IMAGERY,
    OPT_CLIP_BLOCKS,
    OPT_SUN_DATE,
    OPT_SUN_TIME,
    OPT_NO_CAST_SHADOWS,
    OPT_LIGHT,
    OPT_IMAGERY_MODE,
    OPT_HUD_DETAILS,
};

static const struct option longs[] = {
    TP_SCENE_LONG_OPTIONS,
    TP_VIEW_LONG_OPTIONS,
    TP_VIEW_PGM_LONG_OPTIONS,
    {"headless", no_argument, NULL, OPT_HEADLESS},
    {"frames", required_argument, NULL, OPT_FRAMES},
    {"screenshot", required_argument, NULL, OPT_SCREENSHOT},
    {"clear-color", required_argument, NULL, OPT_CLEAR},
    {"wireframe", no_argument, NULL, OPT_WIREFRAME},
    {"color-lod", no_argument, NULL, OPT_COLOR_LOD},
    {"stats-json", required_argument, NULL, OPT_STATS},
    {"no-hud", no_argument, NULL, OPT_NO_HUD},
    {"hud", no_argument, NULL, OPT_HUD},
    {"hud-details", no_argument, NULL, OPT_HUD_DETAILS},
    {"hide-filled", no_argument, NULL, OPT_HIDE_FILLED},
    {"texture", required_argument, NULL, OPT_TEXTURE},
    {"grid", required_argument, NULL, OPT_GRID},
    {"measure", required_argument, NULL, OPT_MEASURE},
    {"sun", required_argument, NULL, OPT_SUN},
    {"pick", required_argument, NULL, OPT_PICK},
    {"memory", required_argument, NULL, OPT_MEMORY},
    {"gpu-memory", required_argument, NULL, OPT_GPU_MEMORY},
    {"cache-dir", required_argument, NULL, OPT_CACHE_DIR},
    {"whole", no_argument, NULL, OPT_WHOLE},
    {"exaggeration", required_argument, NULL, OPT_EXAG},
    {"one-draw-per-patch", no_argument, NULL, OPT_ONE_DRAW},
    {"stitch", required_argument, NULL, OPT_STITCH},
    {"stitch-add-draw", required_argument, NULL, OPT_STITCH_ADD_DRAW},
    {"overlay", required_argument, NULL, OPT_OVERLAY},
    {"contours", required_argument, NULL, OPT_CONTOURS},
    {"bookmark", required_argument, NULL, OPT_BOOKMARK},
    {"save-bookmark", required_argument, NULL, OPT_SAVE_BOOKMARK},
    {"bookmarks", required_argument, NULL, OPT_BOOKMARKS},
    {"imagery", required_argument, NULL, OPT_IMAGERY},
    {"no-imagery", no_argument, NULL, OPT_NO_IMAGERY},
    {"clip-blocks", required_argument, NULL, OPT_CLIP_BLOCKS},
    {"sun-date", required_argument, NULL, OPT_SUN_DATE},
    {"sun-time", required_argument, NULL, OPT_SUN_TIME},
    {"no-cast-shadows", no_argument, NULL, OPT_NO_CAST_SHADOWS},
    {"light", required_argument, NULL, OPT_LIGHT},
    {"imagery-mode", required_argument, NULL, OPT_IMAGERY_MODE},
    {"help", no_argument, NULL, 'h'},
    {NULL, 0, NULL, 0},
};

/* What a group's function returns for option c: */
#define NOT_MINE 0 /* not one of its group's */
#define TAKEN 1    /* read into o */
#define BAD (-1)   /* a bad value: said on stderr (bad) */

static int bad(const char* opt, const char* expected, const char* got)
{
    tp_option_error("view", opt, expected, got);
    return BAD;
}

/* What the run leaves: headless frames, files, picks and measures, the HUD. */
static int output_option(int c, char* arg, view_options* o)
{
    char* end;
    switch (c) {
    case OPT_HEADLESS: o->headless = 1; break;
    case OPT_FRAMES: {
        long n = strtol(arg, &end, 10);
        if (*end || n < 1 || n > 1000000)
            return bad("--frames", "a count >= 1", arg);
        o->frames = (int)n;
        break;
    }
    case OPT_SCREENSHOT: o->screenshot = arg; break;
    case OPT_STATS: o->stats_json = arg; break;
    case OPT_NO_HUD: o->no_hud = 1; break;
    case OPT_HUD: o->hud = 1; break;
    case OPT_HUD_DETAILS: o->hud = o->hud_details = 1; break;
    case OPT_MEASURE:
        if (!tp_parse_numbers(arg, o->measure, 4))
            return bad("--measure", "E1,N1,E2,N2", arg);
        o->has_measure = 1;
        break;
    case OPT_PICK:
        if (o->pick_count == (int)(sizeof o->pick / sizeof o->pick[0]) ||
            !tp_parse_numbers(arg, o->pick[o->pick_count], 2))
            return bad("--pick", "X,Y pixel coordinates (at most 16 --pick)", arg);
        o->pick_count++;
        break;
    default: return NOT_MINE;
    }
    return TAKEN;
}

/* How the terrain is drawn: o->render's settings but the light. */
static int drawing_option(int c, char* arg, view_options* o)
{
    double v[3];
    switch (c) {
    case OPT_EXAG:
        if (!tp_parse_numbers(arg, v, 1) ||
            !(v[0] >= TP_VERTICAL_SCALE_MIN && v[0] <= TP_VERTICAL_SCALE_MAX))
            return bad("--exaggeration", "a number from 0.001 to 1000", arg);
        o->render.exaggeration = v[0];
        o->vs.vertical_scale = v[0];
        break;
    case OPT_CLEAR:
        if (!tp_parse_numbers(arg, v, 3) || v[0] < 0 || v[0] > 1 || v[1] < 0 || v[1] > 1 ||
            v[2] < 0 || v[2] > 1)
            return bad("--clear-color", "R,G,B in 0..1", arg);
        for (int i = 0; i < 3; i++)
            o->render.clear_rgb[i] = (float)v[i];
        break;
    case OPT_WIREFRAME: o->render.wireframe = 1; break;
    case OPT_COLOR_LOD: o->render.color_lod = 1; break;
    case OPT_HIDE_FILLED: o->render.hide_filled = 1; break;
    case OPT_GRID: /* the finest spacing: drawn 1, 10 or 100 times it by the scale */
        if (strcmp(arg, "auto") == 0)
            v[0] = 1000;
        else if (!tp_parse_numbers(arg, v, 1) || v[0] < 0 || (v[0] > 0 && v[0] < 1))
            return bad("--grid", "a line spacing in metres >= 1 (0: none), or auto", arg);
        o->render.grid_m = v[0];
        break;
    case OPT_ONE_DRAW: o->render.one_draw_per_patch = 1; break;
    case OPT_STITCH:
        if (strcmp(arg, "move") && strcmp(arg, "add"))
            return bad("--stitch", "move or add", arg);
        o->render.stitch_add = strcmp(arg, "add") == 0;
        break;
    case OPT_STITCH_ADD_DRAW:
        if (strcmp(arg, "sets") && strcmp(arg, "five"))
            return bad("--stitch-add-draw", "sets or five", arg);
        o->render.stitch_add_five = strcmp(arg, "five") == 0;
        break;
    default: return NOT_MINE;
    }
    return TAKEN;
}

/* The light (the sun, its time, cast shadows) and what is draped (a texture, imagery). */
static int light_imagery_option(int c, char* arg, view_options* o)
{
    double v[2];
    switch (c) {
    case OPT_SUN:
        if (!tp_parse_numbers(arg, v, 2) || v[1] < 0 || v[1] > 90)
            return bad("--sun", "AZIMUTH,ELEVATION in degrees (elevation 0..90)", arg);
        o->render.sun_azimuth_deg = v[0];
        o->render.sun_elevation_deg = v[1];
        break;
    case OPT_SUN_DATE: o->sun_date = arg; break;
    case OPT_SUN_TIME: o->sun_time = arg; break;
    case OPT_NO_CAST_SHADOWS: o->no_cast_shadows = 1; break;
    case OPT_LIGHT: o->light = arg; break;
    case OPT_TEXTURE: o->texture = arg; break;
    case OPT_IMAGERY: o->imagery = arg; break;
    case OPT_NO_IMAGERY: o->no_imagery = 1; break;
    case OPT_CLIP_BLOCKS: {
        char* end;
        long n = strtol(arg, &end, 10);
        if (*end || n < 2 || n > 32 || n % 2)
            return bad("--clip-blocks", "an even number from 2 to 32", arg);
        o->clip_blocks = (int)n;
        break;
    }
    case OPT_IMAGERY_MODE: {
        tp_imagery_mode m;
        if (!tp_imagery_mode_parse(arg, &m))
            return bad("--imagery-mode", "clipmap or blocks", arg);
        o->imagery_mode = (int)m;
        break;
    }
    default: return NOT_MINE;
    }
    return TAKEN;
}

/* The planner's layers (layers.h) and the bookmarks (view_bookmarks.h). */
static int planner_option(int c, char* arg, view_options* o)
{
    double v[1];
    switch (c) {
    case OPT_OVERLAY:
        if (o->overlay_count == (int)(sizeof o->overlays / sizeof o->overlays[0]))
            return bad("--overlay", "at most 8 --overlay files", arg);
        o->overlays[o->overlay_count++] = arg;
        break;
    case OPT_CONTOURS:
        if (!tp_parse_numbers(arg, v, 1) || !(v[0] >= 0 && v[0] <= 100000))
            return bad("--contours",
                       "an interval in metres, 0 to 100000 (0: chosen from the "
                       "relief)",
                       arg);
        o->contours = 1;
        o->contours_m = v[0];
        break;
    case OPT_BOOKMARK: o->bookmark = arg; break;
    case OPT_SAVE_BOOKMARK: o->save_bookmark = arg; break;
    case OPT_BOOKMARKS: o->bookmarks_path = arg; break;
    default: return NOT_MINE;
    }
    return TAKEN;
}

/* Stores: the memory budgets, the cache, or none (--whole). */
static int store_option(int c, char* arg, view_options* o)
{
    char* end;
    switch (c) {
    case OPT_MEMORY:
    case OPT_GPU_MEMORY: {
        long n = strtol(arg, &end, 10);
        if (*end || n < 16 || n > (1L << 24))
            return bad(c == OPT_MEMORY ? "--memory" : "--gpu-memory", "megabytes, 16 or more", arg);
        *(c == OPT_MEMORY ? &o->memory_mb : &o->gpu_memory_mb) = (size_t)n;
        break;
    }
    case OPT_CACHE_DIR: o->cache_dir = arg; break;
    case OPT_WHOLE: o->old_path = 1; break;
    default: return NOT_MINE;
    }
    return TAKEN;
}

/* The groups, each asked in turn. */
static int (*const groups[])(int c, char* arg, view_options* o) = {
    output_option, drawing_option, light_imagery_option, planner_option, store_option,
};

/* The options that do not go together, or need another; TP_EXIT_USAGE after a message, else
 * -1. */
static int check_options(view_options* o)
{
    if (o->bookmark && o->vs.has_camera) {
        tp_cli_error("--bookmark and --camera/--camera-geo both give the "
                     "start view: give one");
        return TP_EXIT_USAGE;
    }
    if (tp_view_setup_check(&o->vs, "view") < 0)
        return TP_EXIT_USAGE;
    if (o->vs.pgm_grid_count && !o->vs.pgm) {
        tp_cli_error("--pgm-grid needs --renderer pgm");
        return TP_EXIT_USAGE;
    }
    if (o->vs.pgm_grid_count > 1) {
        tp_cli_error("--pgm-grid: one grid for view (several are for "
                     "bench)");
        return TP_EXIT_USAGE;
    }
    if (o->vs.pgm && o->imagery) {
        tp_cli_error("--renderer pgm drapes no --imagery yet (hillshade "
                     "only)");
        return TP_EXIT_USAGE;
    }
    if (o->vs.pgm && o->texture) {
        tp_cli_error("--renderer pgm drapes no --texture yet (hillshade "
                     "only)");
        return TP_EXIT_USAGE;
    }
    if (o->vs.pgm && o->render.exaggeration != 1) {
        tp_cli_error("--renderer pgm draws the heights as they are: no "
                     "--exaggeration");
        return TP_EXIT_USAGE;
    }
    if (o->headless && !o->screenshot && !o->stats_json && !o->pick_count && !o->has_measure &&
        !o->save_bookmark) {
        tp_cli_error("--headless draws offscreen and shows nothing: give "
                     "--screenshot FILE.png (or --stats-json FILE, --pick X,Y) for what to "
                     "keep (see 'terrapatch view --help')");
        return TP_EXIT_USAGE;
    }
    if (!o->sun_date != !o->sun_time) {
        tp_cli_error("--sun-date and --sun-time go together: give both");
        return TP_EXIT_USAGE;
    }
    tp_error why = {{0}};
    if (o->sun_date && !tp_sun_time_parse(o->sun_date, o->sun_time, &o->sun_when, &why)) {
        tp_cli_error("--sun-date %s --sun-time %s: %s", o->sun_date, o->sun_time, why.message);
        return TP_EXIT_USAGE;
    }
    return -1;
}

int tp_view_parse_options(int argc, char** argv, view_options* o)
{
    memset(o, 0, sizeof *o);
    tp_scene_options_default(&o->scene);
    tp_render_settings_default(&o->render);
    tp_view_setup_default(&o->vs);
    o->frames = 1;
    o->memory_mb = 1024;
    o->gpu_memory_mb = 256;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":h", longs, NULL)) != -1) {
        int taken = c == '?' || c == ':' ? 0 : tp_scene_option(c, optarg, &o->scene, "view");
        if (taken > 0 && c == TP_OPT_PATCH)
            o->patch_given = 1;
        if (taken > 0 && c == TP_OPT_FIT)
            o->old_path = 1;
        if (!taken && c != '?' && c != ':')
            taken = tp_view_option(c, optarg, &o->vs, "view");
        for (size_t g = 0; !taken && g < sizeof groups / sizeof groups[0]; g++)
            taken = groups[g](c, optarg, o);
        if (taken < 0)
            return TP_EXIT_USAGE;
        if (taken)
            continue;
        switch (c) {
        case 'h': tp_view_print_help(); return tp_cli_finish(TP_EXIT_OK);
        case ':': tp_cli_error("missing value for %s", argv[optind - 1]); return TP_EXIT_USAGE;
        default:
            tp_cli_error("unknown option '%s' (see 'terrapatch view --help')", argv[optind - 1]);
            return TP_EXIT_USAGE;
        }
    }
    if (argc - optind > 1) {
        tp_cli_error("expected one DEM, got extra argument '%s'", argv[optind + 1]);
        return TP_EXIT_USAGE;
    }
    o->path = optind < argc ? argv[optind] : NULL;
    return check_options(o);
}
