/*
 * view_args.c - `terrapatch view`'s options (see view_args.h): their table (options.h), grouped
 * as the help groups them (what the run leaves, how the terrain is drawn, its light and imagery,
 * the planner's layers and bookmarks, stores), the values read by code, and the checks of the
 * options together.
 */
#include "view_args.h"

#include "cli.h"
#include "imagery_view.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The options whose values are read by code_option. */
enum {
    OPT_MEASURE = 1,
    OPT_PICK,
    OPT_EXAG,
    OPT_CLEAR,
    OPT_GRID,
    OPT_STITCH,
    OPT_STITCH_ADD_DRAW,
    OPT_SUN,
    OPT_CLIP_BLOCKS,
    OPT_IMAGERY_MODE,
    OPT_OVERLAY,
    OPT_MEMORY,
    OPT_GPU_MEMORY,
};

/* "OPT: expected EXPECTED, got 'GOT'" (tp_option_error); the usage error's exit status. */
static int bad(const char* opt, const char* expected, const char* got)
{
    tp_option_error("view", opt, expected, got);
    return TP_EXIT_USAGE;
}

/* The value arg of option c (a code above); -1 when read into o, else the exit status. */
static int code_option(int c, const char* arg, view_options* o)
{
    double v[3];
    char* end;
    switch (c) {
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
    case OPT_GRID: /* the finest spacing: drawn 1, 10 or 100 times it by the scale */
        if (strcmp(arg, "auto") == 0)
            v[0] = 1000;
        else if (!tp_parse_numbers(arg, v, 1) || v[0] < 0 || (v[0] > 0 && v[0] < 1))
            return bad("--grid", "a line spacing in metres >= 1 (0: none), or auto", arg);
        o->render.grid_m = v[0];
        break;
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
    case OPT_SUN:
        if (!tp_parse_numbers(arg, v, 2) || v[1] < 0 || v[1] > 90)
            return bad("--sun", "AZIMUTH,ELEVATION in degrees (elevation 0..90)", arg);
        o->render.sun_azimuth_deg = v[0];
        o->render.sun_elevation_deg = v[1];
        break;
    case OPT_CLIP_BLOCKS:
        if (!tp_parse_int(arg, 2, 32, &o->clip_blocks) || o->clip_blocks % 2)
            return bad("--clip-blocks", "an even number from 2 to 32", arg);
        break;
    case OPT_IMAGERY_MODE: {
        tp_imagery_mode m;
        if (!tp_imagery_mode_parse(arg, &m))
            return bad("--imagery-mode", "clipmap or blocks", arg);
        o->imagery_mode = (int)m;
        break;
    }
    case OPT_OVERLAY:
        if (o->overlay_count == (int)(sizeof o->overlays / sizeof o->overlays[0]))
            return bad("--overlay", "at most 8 --overlay files", arg);
        o->overlays[o->overlay_count++] = arg;
        break;
    case OPT_MEMORY:
    case OPT_GPU_MEMORY: {
        long n = strtol(arg, &end, 10);
        if (*end || n < 16 || n > (1L << 24))
            return bad(c == OPT_MEMORY ? "--memory" : "--gpu-memory", "megabytes, 16 or more", arg);
        *(c == OPT_MEMORY ? &o->memory_mb : &o->gpu_memory_mb) = (size_t)n;
        break;
    }
    }
    return -1;
}

/* view's CODE options (tp_option_handler): code_option. */
static int own_option(void* ctx, int code, const char* value, const char* cmd)
{
    (void)cmd;
    return code_option(code, value, ctx) >= 0 ? -1 : 1;
}

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
    o->contours_m = -1; /* no --contours */
    const tp_option options[] = {
        /* what the run leaves: headless frames, files, picks and measures, the HUD */
        TP_OPT_FLAG("--headless", &o->headless),
        TP_OPT_INTEGER("--frames", &o->frames, 1, 1000000, "a count >= 1"),
        TP_OPT_TEXT("--screenshot", NULL, &o->screenshot),
        TP_OPT_TEXT("--stats-json", NULL, &o->stats_json),
        TP_OPT_FLAG("--no-hud", &o->no_hud),
        TP_OPT_FLAG("--hud", &o->hud),
        TP_OPT_FLAG("--hud-details", &o->hud_details),
        TP_OPT_CODE("--measure", NULL, OPT_MEASURE, 1),
        TP_OPT_CODE("--pick", NULL, OPT_PICK, 1),
        /* how the terrain is drawn */
        TP_OPT_CODE("--exaggeration", NULL, OPT_EXAG, 1),
        TP_OPT_CODE("--clear-color", NULL, OPT_CLEAR, 1),
        TP_OPT_FLAG("--wireframe", &o->render.wireframe),
        TP_OPT_FLAG("--color-lod", &o->render.color_lod),
        TP_OPT_FLAG("--hide-filled", &o->render.hide_filled),
        TP_OPT_CODE("--grid", NULL, OPT_GRID, 1),
        TP_OPT_FLAG("--one-draw-per-patch", &o->render.one_draw_per_patch),
        TP_OPT_CODE("--stitch", NULL, OPT_STITCH, 1),
        TP_OPT_CODE("--stitch-add-draw", NULL, OPT_STITCH_ADD_DRAW, 1),
        /* the light and what is draped */
        TP_OPT_CODE("--sun", NULL, OPT_SUN, 1),
        TP_OPT_TEXT("--sun-date", NULL, &o->sun_date),
        TP_OPT_TEXT("--sun-time", NULL, &o->sun_time),
        TP_OPT_FLAG("--no-cast-shadows", &o->no_cast_shadows),
        TP_OPT_TEXT("--light", NULL, &o->light),
        TP_OPT_TEXT("--texture", NULL, &o->texture),
        TP_OPT_TEXT("--imagery", NULL, &o->imagery),
        TP_OPT_FLAG("--no-imagery", &o->no_imagery),
        TP_OPT_CODE("--clip-blocks", NULL, OPT_CLIP_BLOCKS, 1),
        TP_OPT_CODE("--imagery-mode", NULL, OPT_IMAGERY_MODE, 1),
        /* the planner's layers (layers.h) and the bookmarks (view_bookmarks.h) */
        TP_OPT_CODE("--overlay", NULL, OPT_OVERLAY, 1),
        TP_OPT_NUMBER("--contours", &o->contours_m, 0, 100000,
                      "an interval in metres, 0 to 100000 (0: chosen from the relief)"),
        TP_OPT_TEXT("--bookmark", NULL, &o->bookmark),
        TP_OPT_TEXT("--save-bookmark", NULL, &o->save_bookmark),
        TP_OPT_TEXT("--bookmarks", NULL, &o->bookmarks_path),
        /* stores: the memory budgets, the cache, or none (--whole) */
        TP_OPT_CODE("--memory", NULL, OPT_MEMORY, 1),
        TP_OPT_CODE("--gpu-memory", NULL, OPT_GPU_MEMORY, 1),
        TP_OPT_TEXT("--cache-dir", NULL, &o->cache_dir),
        TP_OPT_FLAG("--whole", &o->old_path),
    };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), own_option, o};
    const char* extra;
    const int code = tp_view_command_parse("view", argc, argv, tp_view_print_help, own, &o->scene,
                                           &o->vs, 1, &o->path, &extra);
    if (code >= 0)
        return code;
    if (extra) {
        tp_cli_error("expected one DEM, got extra argument '%s'", extra);
        return TP_EXIT_USAGE;
    }
    o->patch_given = !!(o->scene.given & TP_SCENE_GIVEN(TP_OPT_PATCH));
    o->old_path |= !!(o->scene.given & TP_SCENE_GIVEN(TP_OPT_FIT));
    o->hud |= o->hud_details;
    o->contours = o->contours_m >= 0;
    o->contours_m = fmax(o->contours_m, 0);
    return check_options(o);
}
