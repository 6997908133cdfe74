/*
 * cmd_view.c - `terrapatch view [options] [DEM]`: its options and help, and the headless run
 * (the window's frame loop is window.c).
 *
 * Each frame: select levels and cull (core), upload the vertex data that changed and draw
 * (renderer.c). Headless frames are complete and deterministic: everything is loaded before the
 * first frame and there is no multisampling.
 */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700 /* realpath */
#include "terrapatch.h"
#include "view.h"
#include "clock.h"
#include "imagery_view.h"
#include "view_shadows.h"

#include "atomic_file.h"
#include "camera_pose.h"
#include "cli.h"
#include "hud.h"
#include "hud_text.h"
#include "layers.h"
#include "memory.h"
#include "output_check.h"
#include "overlay.h"
#include "pgm_clip.h"
#include "pgm_render.h"
#include "pick.h"
#include "store_cache.h"
#include "terrain_open.h"
#include "view_bookmarks.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define TP_SAMPLE_SCENE "data/lf_elev_220_mt_hood_utm.tif"

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

static void print_help(void)
{
    fputs("usage: terrapatch view [options] [DEM or STORE.tpt]\n"
          "\n"
          "Shows DEM (default: the sample " TP_SAMPLE_SCENE ") as shaded terrain through its\n"
          "hierarchy, each node at its own level of detail, loading nodes as the view needs them.\n"
          "A DEM is built into a store first (once, in the cache directory; reused next time).\n"
          "In a window when there is a display; --headless renders offscreen (EGL, no display\n"
          "needed) and writes --screenshot.\n"
          "\n",
          stdout);
    tp_view_options_help(stdout);
    tp_view_renderer_help(stdout, 0);
    fputs(
        "output:\n"
        "  --headless            render offscreen through EGL\n"
        "  --frames N            headless: frames to render (default 1); the last is kept\n"
        "  --screenshot FILE     write the last frame, in the format its extension names\n"
        "                        (.png, .tif, .jpg, .bmp, .tga, .webp, .exr; OpenImageIO)\n"
        "  --stats-json FILE     write the last frame's statistics\n"
        "  --clear-color R,G,B   background, 0..1 each\n"
        "  --wireframe, --color-lod   draw edges only / colour patches by level\n"
        "  --exaggeration X      vertical exaggeration, 0.001 to 1000 (default 1): the drawn\n"
        "                        surface everywhere (culling, LoD, picking); camera heights\n"
        "                        (--camera H, the default view, C) are in the drawn space\n"
        "  --sun AZ,EL           hillshade light: azimuth clockwise from grid north and\n"
        "                        elevation, degrees (default 315,45)\n"
        "  --sun-date YYYY-MM-DD, --sun-time HH:MM[:SS][ZONE]\n"
        "                        light from where the sun is then over the map's centre\n"
        "                        (libnova; ZONE: Z, UTC, +02:00, -0500; default UTC), both\n"
        "                        given; in the window PgUp and PgDn move the time by 15\n"
        "                        minutes (Shift: an hour); the ground casts shadows (stores):\n"
        "                        from STORE.tpl beside the store (--light) when the time lies\n"
        "                        in its day, else computed over the 1025 x 1025 posts around\n"
        "                        the point looked at; instead of --sun\n"
        "  --light FILE.tpl      the day's cast shadows from a light map made for the store by\n"
        "                        'terrapatch light STORE --day' (docs/light.md), streamed\n"
        "                        through a clipmap: the whole map's shadows, PgUp/PgDn\n"
        "                        instant; without --sun-date the sun starts at the middle\n"
        "                        of the file's day\n"
        "  --no-cast-shadows     the sun's light without cast shadows (neither of the above)\n"
        "  --hide-filled         draw filled voids like measured ground (default: tinted)\n"
        "  --pick X,Y            headless: print the ground point under pixel X,Y (from the\n"
        "                        top-left corner): E, N and the drawn surface's height;\n"
        "                        repeatable\n"
        "  --measure E1,N1,E2,N2 print the geodesic distance, true and grid bearing and height\n"
        "                        difference between two ground points (render CRS)\n"
        "  --grid M|auto         grid lines of the render CRS, labelled (for a UTM render\n"
        "                        grid: the UTM/MGRS grid), every M metres or 10 M or 100 M,\n"
        "                        the finest whose lines are 40 px apart or more at the view's\n"
        "                        centre (the HUD says which); auto: M = 1000 (1, 10, 100 km)\n"
        "  --texture FILE        drape an image: an orthophoto georeferenced through GDAL (warped\n"
        "                        onto the render grid), or any image covering the DEM's extent\n"
        "  --one-draw-per-patch  one draw call per patch instead of multi-draw\n"
        "imagery (stores; docs/imagery.md):\n"
        "  --imagery FILE.tpi    drape an imagery pyramid made for the store by\n"
        "                        'terrapatch imagery' (default: STORE.tpi beside the store,\n"
        "                        when there is one), streamed through a clipmap: any size, a\n"
        "                        fixed GPU memory (F3 in the window: on or off)\n"
        "  --no-imagery          do not drape STORE.tpi\n"
        "  --clip-blocks N       the clipmap's window: N x N blocks of 256 texels a level (even,\n"
        "                        2..32; default 4: 1024 texels, 4 MiB of GPU memory a level)\n"
        "  --imagery-mode M      clipmap (default), or blocks: Brodersen's texture per drawn\n"
        "                        node, for comparison (384 layers of 256x256 texels, 96 MiB)\n"
        "planning layers (docs/field.md):\n"
        "  --overlay FILE        drape a vector file on the terrain: GPX, KML, GeoJSON,\n"
        "                        Shapefile, GeoPackage or anything OGR reads, reprojected to\n"
        "                        the render CRS; lines, polygon outlines, points with their\n"
        "                        names; one colour per file; repeatable (8 at most)\n"
        "  --contours M          contour lines every M metres (0: a round interval for the\n"
        "                        relief) within 10 km of the point looked at, by GDAL's\n"
        "                        contour generator; every fifth thicker and labelled (F2 in\n"
        "                        the window: contours around the point looked at, or off)\n"
        "bookmarks (named views; docs/field.md, \"Map reading\"):\n"
        "  --bookmark NAME       start from bookmark NAME (instead of --camera)\n"
        "  --save-bookmark NAME  save the start view (--camera, --camera-geo or the default) as\n"
        "                        NAME, replacing one of that name\n"
        "  --bookmarks FILE      the bookmarks file (default: $XDG_CONFIG_HOME/terrapatch/\n"
        "                        bookmarks/DEMFILE.bookmarks, else ~/.config/...), one line a\n"
        "                        view: NAME --camera-geo LAT,LON,H,YAW,PITCH\n"
        "stores:\n"
        "  --memory MB           budget of decoded terrain in RAM (default 1024)\n"
        "  --gpu-memory MB       budget of the GPU vertex pool (default 256); a frame that\n"
        "                        needs more grows the pool past it (never a hole) and the\n"
        "                        HUD's GPU MB shows by how much\n"
        "  --cache-dir DIR       where DEMs are built into stores (default $TP_CACHE_DIR, else\n"
        "                        $XDG_CACHE_HOME/terrapatch, else ~/.cache/terrapatch)\n"
        "  --whole               draw the DEM whole, without a store (the old path: the DEM\n"
        "                        and its render grid in memory, patches selected every frame)\n"
        "  --stitch move|add     crack removal: move the finer patch's border vertices (move,\n"
        "                        the default) or add them to the coarser patch's border (add,\n"
        "                        Brodersen section 4; over a store between nodes of one size,\n"
        "                        a smaller node next to a larger one still moves its own)\n"
        "  --stitch-add-draw sets|five  how --stitch add draws a patch that takes vertices:\n"
        "                        its own triangle list from an index set per neighbour\n"
        "                        configuration (sets), or up to five draws of per-level\n"
        "                        region sets (five, the default: see docs/PERFORMANCE.md)\n"
        "  A DEM is drawn whole, without a store (the old path), when it is a heightmap image\n"
        "  (--spacing, --zscale, --origin or a PNG/JPEG/...), or --fit, --texture or --renderer\n"
        "  pgm is given: stores always pad and carry no texture (and PGM over a\n"
        "  DEM reads its whole pyramid). A store fills voids as --fill-max says\n"
        "  (passed to the build) and marks each filled sample: tinted (V) as a DEM drawn whole.\n"
        "  A DEM's store is built with the view's --patch (default 17, as a DEM drawn whole);\n"
        "  'terrapatch build' defaults to 65, for large maps.\n"
        "  --no-hud              no text overlay (by default three lines: the centre's MGRS,\n"
        "                        latitude/longitude and elevation; the eye's height,\n"
        "                        heading and pitch; scale, grid and mode)\n"
        "  --hud                 headless frames too get the overlay (off by default there,\n"
        "                        so that a headless image depends on the view alone)\n"
        "  --hud-details         the overlay with its engineering lines too (frame rate, CPU\n"
        "                        split, triangles, levels, error bound and measured error,\n"
        "                        full positions; F4 in the window): all of them are\n"
        "                        in --stats-json in any case\n"
        "DEM:\n",
        stdout);
    tp_scene_options_help(stdout);
    fputs(
        "\nWindow keys: W/S forward/back, A/D left/right, Q/E down/up (speed follows the height\n"
        "above ground; Shift x5, Ctrl x0.2), drag with the left mouse button to look around,\n"
        "Home (or 0) back to the start view, O orbit mode (drag rotates around the point looked\n"
        "at, wheel or W/S zoom, A/D/Q/E pan; the HUD says which mode), L colour by level,\n"
        "T wireframe, F freeze LoD and culling, M switch LoD mode, +/- tau (or maxdist), [ ]\n"
        "mindist, , . exp, X/Z vertical exaggeration, J/K sun azimuth, U/N sun elevation,\n"
        "V tint of filled voids, G grid (1, 10 or 100 km by the scale), P screenshot, Y export\n"
        "the view's mesh (.vtp), C print the camera as --camera-geo and --camera options,\n"
        "H hide the HUD, F4 the HUD's details (fps, CPU, triangles, levels, error bound),\n"
        "right-click twice to measure, ? key help, Esc quit. Keys are queued: a tap shorter than\n"
        "a frame still counts.\n"
        "Bookmarks: Ctrl+1..9 saves the view as \"view N\", 1..9 goes back to it, Tab and\n"
        "Shift+Tab step through every bookmark of the file.\n"
        "\nOutputs are checked before rendering and written whole or not at all (a full disk or\n"
        "SIGINT/SIGTERM leaves an older file as it was).\n"
        "Exit status: 0 success, 1 failure, 2 usage error, 130/143 after SIGINT/SIGTERM.\n",
        stdout);
}

/* The bundled sample, found from the binary's own location (/proc/self/exe), so that it does not
 * matter where `view` is run from: installed, <bindir>/TP_INSTALL_DATA_REL (CMakeLists.txt:
 * ../share/terrapatch/data); in the build tree, the source tree's data/ (TP_SOURCE_DATA_DIR, or
 * ../data beside build/); else data/ of the working directory. */
#ifndef TP_INSTALL_DATA_REL
#define TP_INSTALL_DATA_REL "../share/terrapatch/data"
#endif
#define TP_SAMPLE_FILE "lf_elev_220_mt_hood_utm.tif"
static const char* sample_scene(void)
{
    char exe_dir[PATH_MAX];
    char installed[sizeof exe_dir + sizeof TP_INSTALL_DATA_REL + 1], beside[sizeof exe_dir + 16];
    static char path[sizeof installed + sizeof TP_SAMPLE_FILE + 1], canonical[PATH_MAX];
    const char* dirs[3] = {NULL, NULL, NULL};
    ssize_t n = readlink("/proc/self/exe", exe_dir, sizeof exe_dir - 1);
    char* slash = NULL;
    if (n > 0) {
        exe_dir[n] = '\0';
        slash = strrchr(exe_dir, '/');
    }
    if (slash) {
        *slash = '\0';
        snprintf(installed, sizeof installed, "%s/%s", exe_dir, TP_INSTALL_DATA_REL);
        snprintf(beside, sizeof beside, "%s/../data", exe_dir);
        dirs[0] = installed;
        dirs[1] = beside;
    }
#ifdef TP_SOURCE_DATA_DIR
    dirs[2] = TP_SOURCE_DATA_DIR;
#endif
    for (int i = 0; i < 3; i++)
        if (dirs[i] &&
            (size_t)snprintf(path, sizeof path, "%s/%s", dirs[i], TP_SAMPLE_FILE) < sizeof path &&
            access(path, R_OK) == 0)
            return realpath(path, canonical) ? canonical : path;
    return TP_SAMPLE_SCENE;
}

static int bad(const char* opt, const char* expected, const char* got)
{
    tp_option_error("view", opt, expected, got);
    return TP_EXIT_USAGE;
}

static int parse_options(int argc, char** argv, view_options* o)
{
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
    double v[5];
    char* end;
    while ((c = getopt_long(argc, argv, ":h", longs, NULL)) != -1) {
        int taken = c == '?' || c == ':' ? 0 : tp_scene_option(c, optarg, &o->scene, "view");
        if (taken > 0 && c == TP_OPT_PATCH)
            o->patch_given = 1;
        if (taken > 0 && c == TP_OPT_FIT)
            o->old_path = 1;
        if (!taken && c != '?' && c != ':')
            taken = tp_view_option(c, optarg, &o->vs, "view");
        if (taken < 0)
            return TP_EXIT_USAGE;
        if (taken)
            continue;
        switch (c) {
        case OPT_EXAG:
            if (!tp_parse_numbers(optarg, v, 1) ||
                !(v[0] >= TP_VERTICAL_SCALE_MIN && v[0] <= TP_VERTICAL_SCALE_MAX))
                return bad("--exaggeration", "a number from 0.001 to 1000", optarg);
            o->render.exaggeration = v[0];
            o->vs.vertical_scale = v[0];
            break;
        case OPT_HEADLESS: o->headless = 1; break;
        case OPT_MEMORY:
        case OPT_GPU_MEMORY: {
            long n = strtol(optarg, &end, 10);
            if (*end || n < 16 || n > (1L << 24))
                return bad(c == OPT_MEMORY ? "--memory" : "--gpu-memory", "megabytes, 16 or more",
                           optarg);
            *(c == OPT_MEMORY ? &o->memory_mb : &o->gpu_memory_mb) = (size_t)n;
            break;
        }
        case OPT_CACHE_DIR: o->cache_dir = optarg; break;
        case OPT_WHOLE: o->old_path = 1; break;
        case OPT_FRAMES: {
            long n = strtol(optarg, &end, 10);
            if (*end || n < 1 || n > 1000000)
                return bad("--frames", "a count >= 1", optarg);
            o->frames = (int)n;
            break;
        }
        case OPT_SCREENSHOT: o->screenshot = optarg; break;
        case OPT_STATS: o->stats_json = optarg; break;
        case OPT_CLEAR:
            if (!tp_parse_numbers(optarg, v, 3) || v[0] < 0 || v[0] > 1 || v[1] < 0 || v[1] > 1 ||
                v[2] < 0 || v[2] > 1)
                return bad("--clear-color", "R,G,B in 0..1", optarg);
            for (int i = 0; i < 3; i++)
                o->render.clear_rgb[i] = (float)v[i];
            break;
        case OPT_WIREFRAME: o->render.wireframe = 1; break;
        case OPT_COLOR_LOD: o->render.color_lod = 1; break;
        case OPT_NO_HUD: o->no_hud = 1; break;
        case OPT_HUD: o->hud = 1; break;
        case OPT_HUD_DETAILS: o->hud = o->hud_details = 1; break;
        case OPT_HIDE_FILLED: o->render.hide_filled = 1; break;
        case OPT_TEXTURE: o->texture = optarg; break;
        case OPT_IMAGERY: o->imagery = optarg; break;
        case OPT_NO_IMAGERY: o->no_imagery = 1; break;
        case OPT_SUN_DATE: o->sun_date = optarg; break;
        case OPT_SUN_TIME: o->sun_time = optarg; break;
        case OPT_NO_CAST_SHADOWS: o->no_cast_shadows = 1; break;
        case OPT_LIGHT: o->light = optarg; break;
        case OPT_CLIP_BLOCKS: {
            char* end;
            long n = strtol(optarg, &end, 10);
            if (*end || n < 2 || n > 32 || n % 2)
                return bad("--clip-blocks", "an even number from 2 to 32", optarg);
            o->clip_blocks = (int)n;
            break;
        }
        case OPT_IMAGERY_MODE: {
            tp_imagery_mode m;
            if (!tp_imagery_mode_parse(optarg, &m))
                return bad("--imagery-mode", "clipmap or blocks", optarg);
            o->imagery_mode = (int)m;
            break;
        }
        case OPT_SUN:
            if (!tp_parse_numbers(optarg, v, 2) || v[1] < 0 || v[1] > 90)
                return bad("--sun", "AZIMUTH,ELEVATION in degrees (elevation 0..90)", optarg);
            o->render.sun_azimuth_deg = v[0];
            o->render.sun_elevation_deg = v[1];
            break;
        case OPT_MEASURE:
            if (!tp_parse_numbers(optarg, o->measure, 4))
                return bad("--measure", "E1,N1,E2,N2", optarg);
            o->has_measure = 1;
            break;
        case OPT_PICK:
            if (o->pick_count == (int)(sizeof o->pick / sizeof o->pick[0]) ||
                !tp_parse_numbers(optarg, o->pick[o->pick_count], 2))
                return bad("--pick", "X,Y pixel coordinates (at most 16 --pick)", optarg);
            o->pick_count++;
            break;
        case OPT_GRID: /* the finest spacing: drawn 1, 10 or 100 times it by the scale */
            if (strcmp(optarg, "auto") == 0)
                v[0] = 1000;
            else if (!tp_parse_numbers(optarg, v, 1) || v[0] < 0 || (v[0] > 0 && v[0] < 1))
                return bad("--grid", "a line spacing in metres >= 1 (0: none), or auto", optarg);
            o->render.grid_m = v[0];
            break;
        case OPT_ONE_DRAW: o->render.one_draw_per_patch = 1; break;
        case OPT_STITCH:
            if (strcmp(optarg, "move") && strcmp(optarg, "add"))
                return bad("--stitch", "move or add", optarg);
            o->render.stitch_add = strcmp(optarg, "add") == 0;
            break;
        case OPT_STITCH_ADD_DRAW:
            if (strcmp(optarg, "sets") && strcmp(optarg, "five"))
                return bad("--stitch-add-draw", "sets or five", optarg);
            o->render.stitch_add_five = strcmp(optarg, "five") == 0;
            break;
        case OPT_OVERLAY:
            if (o->overlay_count == (int)(sizeof o->overlays / sizeof o->overlays[0]))
                return bad("--overlay", "at most 8 --overlay files", optarg);
            o->overlays[o->overlay_count++] = optarg;
            break;
        case OPT_CONTOURS:
            if (!tp_parse_numbers(optarg, v, 1) || !(v[0] >= 0 && v[0] <= 100000))
                return bad("--contours", "an interval in metres, 0 to 100000 (0: chosen from the "
                                         "relief)", optarg);
            o->contours = 1;
            o->contours_m = v[0];
            break;
        case OPT_BOOKMARK: o->bookmark = optarg; break;
        case OPT_SAVE_BOOKMARK: o->save_bookmark = optarg; break;
        case OPT_BOOKMARKS: o->bookmarks_path = optarg; break;
        case 'h': print_help(); return tp_cli_finish(TP_EXIT_OK);
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
    o->path = optind < argc ? argv[optind] : sample_scene();
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
    char why[160];
    if (o->sun_date && !tp_sun_time_parse(o->sun_date, o->sun_time, &o->sun_when, why, sizeof why)) {
        tp_cli_error("--sun-date %s --sun-time %s: %s", o->sun_date, o->sun_time, why);
        return TP_EXIT_USAGE;
    }
    return -1;
}

/* Says on stderr why a frame shows no terrain at all. */
static void warn_if_empty(const tp_view_scene* v, const frame_result* fr)
{
    if (fr->core.triangles > 0)
        return;
    const tp_scene* sc = v->dem;
    if (sc ? sc->info.valid_samples + sc->info.filled_samples < 4
           : v->store->info.header.valid_samples < 4)
        tp_cli_warning("%s: the frame shows no terrain: the DEM has no "
                       "2x2 block of valid samples to draw a triangle from",
                       v->path);
    else if (fr->core.visible_patches > 0)
        tp_cli_warning("%s: the frame shows no terrain: the %d %s "
                       "in view hold only nodata or padding (the camera may be inside or under "
                       "the surface)",
                       v->path, fr->core.visible_patches, fr->store ? "nodes" : "patches");
    else
        tp_cli_warning("%s: the frame shows no terrain: the camera "
                       "looks away from the DEM (all %d %s culled; try without --camera)",
                       v->path, fr->core.culled_patches, fr->store ? "nodes" : "patches");
}

/* Says on stderr when a camera given on the command line (--camera, --camera-geo, --bookmark)
 * is under the ground at its own position (its frame shows the terrain from below, or
 * nothing); 1 when it did. */
static int warn_if_below_ground(tp_view_scene* v, const tp_camera* cam, const view_options* o)
{
    if (!o->vs.has_camera && !o->bookmark)
        return 0;
    double x, y;
    tp_view_scene_world_to_grid(v, cam->position[0], cam->position[1], &x, &y);
    const double ground = tp_view_scene_ground_height(v, x, y) * o->render.exaggeration;
    if (!(cam->position[2] < ground))
        return 0; /* above it, or off the DEM or over a void (NaN) */
    tp_cli_warning("%s: the camera is below the ground: at %.1f m "
                   "(E %.1f N %.1f), where the ground is %.1f m%s; raise its height",
                   v->path, cam->position[2], cam->position[0], cam->position[1], ground,
                   o->render.exaggeration != 1 ? " as drawn" : "");
    return 1;
}

static int run_headless(tp_view_scene* v, tp_gl_context* ctx, tp_renderer* r,
                        const tp_camera* cam, view_options* o)
{
    int code = TP_EXIT_OK;
    frame_result fr = {0};
    int with_hud = o->hud && !o->no_hud;
    tp_hud* hud = with_hud || o->render.grid_m > 0 || o->layers ? tp_hud_create() : NULL;
    char measure_line[512] = "";
    int measured = 0;
    for (int i = 0; i < o->frames; i++) {
        /* a store: every node the view wants is loaded before the frame (complete and
         * deterministic, as a DEM's headless frames are) */
        tp_view_scene_set_vertical_scale(v, o->render.exaggeration);
        tp_view_scene_settle(v, cam, &o->vs.lod, 120);
        tp_gl_context_begin_frame(ctx);
        double t0 = tp_clock_ms();
        tp_render_settings rs = o->render; /* the grid's spacing follows the scale */
        rs.grid_m = tp_view_grid_spacing(v, cam, o->render.grid_m);
        tp_view_frame(v, r, cam, &rs, &o->vs.lod, 0, &fr);
        if (o->has_measure && !measured) {
            double e[2] = {o->measure[0], o->measure[2]}, n[2] = {o->measure[1], o->measure[3]};
            measured = tp_view_measure_points(v, e, n, measure_line, sizeof measure_line) ? 1 : -1;
        }
        char text[4096];
        if (i == 0 && o->contours && o->layers) {
            char line[600];
            tp_view_contours_at_centre(v, cam, o, o->contours_m, line, sizeof line);
        }
        tp_overlay ov = {.grid_m = rs.grid_m,
                         .measure_line = measure_line,
                         .near_m = fr.render.near_m,
                         .far_m = fr.render.far_m};
        if (o->layers)
            ov.drape_count = tp_view_layers_drawn(o->layers, &ov.drapes);
        if (with_hud) {
            tp_measured_error me = {0};
            if (o->hud_details) /* shown only there: it costs tens of ms */
                tp_view_measure_now(v, cam, &me);
            char legend[512] = "";
            if (o->layers)
                tp_view_layers_legend(o->layers, legend, sizeof legend);
            char sun[160];
            tp_view_sun_text(&o->sun, sun, sizeof sun);
            tp_hud_state hs = {.fps = 1000 / fmax(tp_clock_ms() - t0, 1e-6),
                               .exaggeration = o->render.exaggeration,
                               .layers = legend,
                               .sun = sun,
                               .grid_m = rs.grid_m,
                               .details = o->hud_details};
            tp_view_hud_text(v, cam, &o->vs.lod, &fr, &me, &hs, text, sizeof text);
            ov.hud_text = text;
        }
        tp_view_overlay_draw(hud, v, cam, &ov);
        tp_gl_context_end_frame(ctx);
    }
    tp_hud_destroy(hud);
    if (!warn_if_below_ground(v, cam, o))
        warn_if_empty(v, &fr);
    if (o->screenshot && !tp_view_screenshot(ctx, o->screenshot))
        code = TP_EXIT_FAILURE;
    if (o->has_measure) {
        if (measured > 0) {
            printf("%s\n", measure_line);
        } else {
            tp_cli_error("--measure: %s", measure_line);
            code = TP_EXIT_FAILURE;
        }
    }
    for (int i = 0; i < o->pick_count; i++) {
        double g[3];
        if (tp_view_pick(v, cam, o->pick[i][0], o->pick[i][1], g)) {
            printf("pick %.1f,%.1f: E %.3f N %.3f height %.3f m\n", o->pick[i][0],
                   o->pick[i][1], g[0], g[1], g[2]);
        } else {
            printf("pick %.1f,%.1f: no ground\n", o->pick[i][0], o->pick[i][1]);
        }
    }
    if (o->stats_json && code == TP_EXIT_OK) {
        double max_m, rms_m, max_px, rms_px;
        tp_view_scene_measure(v, cam, &max_m, &rms_m, &max_px, &rms_px);
        tp_error_measure em = {.max_error_m = max_m, .rms_error_m = rms_m};
        if (!tp_view_write_stats(o->stats_json, &fr, v->store && !v->pgm ? NULL : &em, max_px,
                                 rms_px, v->n + 1, cam))
            code = TP_EXIT_FAILURE;
    }
    return code;
}

/* A store's georeference, made on a thread since it was opened (tp_store_scene_open_deferred),
 * taken into v. */
static int take_georef(tp_view_scene* v, tp_store_scene* st)
{
    if (!st || st->georef)
        return 1;
    if (tp_store_scene_georef_wait(st) != TP_EXIT_OK)
        return 0;
    v->georef = st->georef;
    return 1;
}

/* The store's imagery: --imagery, else STORE.tpi beside it (unless --no-imagery). 0 after a
 * message when it cannot be drawn. */
static int open_imagery(tp_view_scene* v, const view_options* o, const tp_store_scene* st)
{
    char beside[4096];
    const char* path = o->imagery;
    if (!path && !o->no_imagery && tp_view_imagery_beside(st->path, beside, sizeof beside))
        path = beside;
    if (!path || o->no_imagery || o->vs.pgm) /* PGM drapes nothing yet (checked: no --imagery) */
        return 1;
    tp_clipmap_options co = {.clip_blocks = o->clip_blocks};
    v->imagery_settle = o->headless;
    return tp_view_imagery_open(path, st, (tp_imagery_mode)o->imagery_mode, &co, &v->imagery);
}

/* Runs the view on an open scene (either path; st: the store, whose georeference may still be
 * in the making): camera, context, renderer, the frames. */
static int run_view(tp_view_scene* v, view_options* o, tp_render_grid_desc* gd,
                    tp_store_scene* st)
{
    tp_camera cam;
    if (o->vs.has_camera && !take_georef(v, st)) /* --camera-geo */
        return TP_EXIT_FAILURE;
    if (o->vs.has_camera) {
        if (tp_camera_refuse_degrees("view", v->georef, o->vs.camera_geo, o->vs.camera, v->gt,
                                     v->src_width, v->src_height))
            return TP_EXIT_FAILURE;
        if (!tp_camera_from_option_georef(v->georef, o->vs.camera_geo, o->vs.camera, o->vs.fov_deg,
                                          o->vs.w, o->vs.h, &cam, "view"))
            return TP_EXIT_FAILURE;
    } else {
        tp_camera_default_extent(v->gt, v->src_width, v->src_height, v->min_height_m,
                                 v->max_height_m, o->vs.fov_deg, o->vs.w, o->vs.h,
                                 o->vs.vertical_scale, &cam);
    }
    if (o->bookmark && (!take_georef(v, st) || !tp_view_bookmark_camera(v, o, o->bookmark, &cam)))
        return TP_EXIT_FAILURE;
    if (o->save_bookmark) {
        char line[1024];
        if (!take_georef(v, st) ||
            !tp_view_bookmark_save(v, o, &cam, o->save_bookmark, line, sizeof line)) {
            tp_cli_error("--save-bookmark: %s", line);
            return TP_EXIT_FAILURE;
        }
        printf("%s\n", line);
    }
    char msg[512];
    tp_gl_context* ctx = NULL;
    int ok = o->headless ? tp_gl_context_create_headless(o->vs.w, o->vs.h, &ctx, msg, sizeof msg)
                         : tp_gl_context_create_window(o->vs.w, o->vs.h, "terrapatch", &ctx, msg,
                                                       sizeof msg);
    if (!ok) {
        tp_cli_error("%s", msg);
        return TP_EXIT_FAILURE;
    }
    tp_renderer* r = v->dem ? tp_renderer_create(v->dem->terrain, msg, sizeof msg)
                            : tp_renderer_create_desc(gd, msg, sizeof msg);
    if (!r) {
        tp_cli_error("%s", msg);
        tp_gl_context_destroy(ctx);
        return TP_EXIT_FAILURE;
    }
    /* --renderer pgm: the pyramid (a DEM drawn whole) or the clipmap (a store) and the
     * persistent grid draw instead of r */
    tp_pgm_pyramid pyr;
    memset(&pyr, 0, sizeof pyr);
    uint8_t* valid = NULL;
    tp_pgm_clipmap* pgm_clip = NULL;
    if (o->vs.pgm && st) {
        int cols = o->vs.pgm_grid_count ? o->vs.pgm_grid[0][0] : TP_PGM_DEFAULT_COLS;
        int rows = o->vs.pgm_grid_count ? o->vs.pgm_grid[0][1] : TP_PGM_DEFAULT_ROWS;
        pgm_clip = tp_pgm_clipmap_create(st->store, o->vs.pgm_window, msg, sizeof msg);
        /* a window reads on a loader thread (no frame waits for a jump's refill); headless
         * frames read at once, so that each frame is the camera's own */
        if (pgm_clip && !o->headless && !tp_pgm_clipmap_set_async(pgm_clip, msg, sizeof msg))
            tp_cli_error("%s (reading on the render thread)", msg);
        if (pgm_clip)
            v->pgm = tp_pgm_renderer_create_clipmap(pgm_clip, cols, rows, msg, sizeof msg);
        if (!v->pgm) {
            tp_cli_error("%s: %s", st->path, msg);
            tp_pgm_clipmap_destroy(pgm_clip);
            tp_renderer_destroy(r);
            tp_gl_context_destroy(ctx);
            return TP_EXIT_FAILURE;
        }
    } else if (o->vs.pgm) {
        tp_error err = {{0}};
        const tp_render_grid* g = v->dem->grid;
        int cols = o->vs.pgm_grid_count ? o->vs.pgm_grid[0][0] : TP_PGM_DEFAULT_COLS;
        int rows = o->vs.pgm_grid_count ? o->vs.pgm_grid[0][1] : TP_PGM_DEFAULT_ROWS;
        if (tp_pgm_pyramid_from_grid(g->heights, g->width, g->height, g->geotransform, &pyr,
                                     &valid, &err) != TP_OK)
            snprintf(msg, sizeof msg, "the PGM pyramid: %.400s", err.message);
        else
            v->pgm = tp_pgm_renderer_create(&pyr, valid, cols, rows, msg, sizeof msg);
        free(valid); /* uploaded */
        if (!v->pgm) {
            tp_cli_error("%s", msg);
            tp_pgm_pyramid_free(&pyr);
            tp_renderer_destroy(r);
            tp_gl_context_destroy(ctx);
            return TP_EXIT_FAILURE;
        }
    }
    int code = TP_EXIT_OK;
    tp_view_shadow shadow = {0};
    /* the frames need the georeference (the HUD, picking, measuring): made meanwhile */
    if (!take_georef(v, st))
        code = TP_EXIT_FAILURE;
    if (code == TP_EXIT_OK && o->texture && !tp_view_load_texture(v->dem, r, o->texture))
        code = TP_EXIT_FAILURE;
    if (code == TP_EXIT_OK && o->imagery && !st) {
        tp_cli_error("--imagery drapes stores; %s is drawn whole (use "
                     "--texture for an image over a DEM drawn whole)",
                     v->path);
        code = TP_EXIT_USAGE;
    }
    if (code == TP_EXIT_OK && st && !open_imagery(v, o, st))
        code = TP_EXIT_FAILURE;
    if (code == TP_EXIT_OK) /* the sun over the map's centre, its cast shadows */
        code = tp_view_shadows_open(v, o, st, &shadow);
    tp_view_layers layers;
    memset(&layers, 0, sizeof layers);
    /* a window always has them (F2); headless frames when asked */
    if (code == TP_EXIT_OK && (o->overlay_count || o->contours || (!o->headless && v->store)))
        code = tp_view_load_layers(v, o, &layers);
    if (code == TP_EXIT_OK)
        code = o->headless ? run_headless(v, ctx, r, &cam, o)
                           : tp_view_window_run(v, ctx, r, &cam, o);
    tp_view_layers_free(&layers);
    tp_ground_destroy(o->ground);
    o->ground = NULL;
    o->layers = NULL;
    tp_view_imagery_close(v->imagery);
    v->imagery = NULL;
    tp_view_shadows_close(v, &shadow);
    tp_pgm_renderer_destroy(v->pgm);
    v->pgm = NULL;
    tp_pgm_clipmap_destroy(pgm_clip);
    tp_pgm_pyramid_free(&pyr);
    tp_renderer_destroy(r);
    tp_gl_context_destroy(ctx);
    return code;
}

/* The old path: the DEM read whole into a tp_terrain (heightmap images, --fill-max, --fit,
 * --texture). */
static int view_dem(view_options* o)
{
    tp_scene sc;
    o->scene.use = TP_MEMORY_USE_VIEW;
    int code = tp_scene_load(o->path, &o->scene, &sc);
    if (code != TP_EXIT_OK)
        return code;
    tp_view_setup_warn(&sc, &o->vs, "view");
    tp_selection* sel = NULL;
    tp_error err;
    if (tp_selection_create(sc.terrain, &sel, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    if (o->render.stitch_add && tp_terrain_prepare_stitch_add(sc.terrain, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        tp_selection_destroy(sel);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    tp_selection_set_stitch_add(sel, o->render.stitch_add); /* the error mode bounds it */
    tp_view_scene v;
    tp_view_scene_from_dem(&v, &sc, sel);
    code = run_view(&v, o, NULL, NULL);
    tp_selection_destroy(sel);
    tp_scene_free(&sc);
    return code;
}

static int view_store(const char* path, view_options* o)
{
    tp_store_scene st;
    /* the georeference is made on a thread while the GL context is created (run_view) */
    int code = tp_store_scene_open_deferred(path, &st);
    if (code != TP_EXIT_OK)
        return code;
    /* the stream's budget within what the process may still use (TP_MEMORY_LIMIT, ulimit) */
    uint64_t budget = tp_memory_fit_budget("view", path, "the decoded terrain (--memory)",
                                           tp_memory_estimate(TP_MEMORY_USE_VIEW, 0),
                                           (uint64_t)o->memory_mb << 20, (uint64_t)16 << 20);
    if (!budget) {
        tp_store_scene_close(&st);
        return TP_EXIT_FAILURE;
    }
    tp_stream_options so = {.memory_bytes = (size_t)budget};
    if ((code = tp_store_scene_stream(&st, &so)) != TP_EXIT_OK) {
        tp_store_scene_close(&st);
        return code;
    }
    tp_view_scene v;
    if (!tp_view_scene_from_store(&v, &st)) {
        tp_store_scene_close(&st);
        return TP_EXIT_FAILURE;
    }
    v.path = o->path;
    tp_cut_set_stitch_add(v.cut, o->render.stitch_add);
    const tp_tree_geometry* g = tp_tree_get_geometry(st.tree);
    /* as tp_view_setup_warn says for a DEM drawn whole: one leaf is 2^n grid steps */
    double leaf_m = (double)(1 << g->n) * fmin(fabs(v.gt[1]), fabs(v.gt[5]));
    if (o->vs.lod.mode == TP_LOD_DISTANCE && o->vs.lod.maxdist_m > 0 &&
        o->vs.lod.maxdist_m < leaf_m)
        tp_cli_warning("--maxdist %g m is less than one patch width (%.0f m): "
                       "every node farther than %g m is drawn at its coarsest (distances are in "
                       "metres)",
                       o->vs.lod.maxdist_m, leaf_m, o->vs.lod.maxdist_m);
    tp_render_grid_desc gd = {.n = g->n, .width = g->width, .height = g->height,
                              .min_height_m = v.min_height_m, .max_height_m = v.max_height_m,
                              .pool_budget_bytes = o->gpu_memory_mb << 20};
    memcpy(gd.geotransform, v.gt, sizeof gd.geotransform);
    code = run_view(&v, o, &gd, &st);
    tp_view_scene_release(&v);
    tp_store_scene_close(&st);
    return code;
}

int tp_cli_view(int argc, char** argv)
{
    view_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    /* Every output can be written, or nothing is rendered and nothing written. */
    tp_error err;
    if (o.screenshot &&
        (code = tp_cli_output_check("view", "--screenshot", o.screenshot, TP_OUTPUT_SCREENSHOT)))
        return code;
    if (o.screenshot && tp_image_output_check(o.screenshot, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    if (o.stats_json && !tp_atomic_check_dir(o.stats_json))
        return TP_EXIT_FAILURE;
    /* the bookmarks file, where it will be read: named, asked for, or a window (keys 1..9) */
    if ((o.bookmarks_path || o.bookmark || o.save_bookmark || !o.headless) &&
        !tp_view_bookmarks_check(&o))
        return TP_EXIT_FAILURE;
    if (o.vs.pgm_window && (!o.vs.pgm || !tp_is_store_path(o.path))) {
        tp_cli_error("--pgm-window is for --renderer pgm over a store (%s is "
                     "%s)",
                     o.path, o.vs.pgm ? "a DEM, drawn whole" : "drawn by patches");
        return TP_EXIT_USAGE;
    }
    /* a store: its clipmap (pgm_clip.h); a DEM drawn whole: its render grid is the pyramid's
     * level 0 */
    if (o.vs.pgm && !tp_is_store_path(o.path))
        o.old_path = 1;
    int is_store;
    if ((code = tp_terrain_classify("view", o.path, &o.scene, &is_store)) >= 0)
        return code;
    if (is_store) {
        if (o.texture || o.old_path) {
            tp_cli_error("%s is a store: --texture and --whole apply to a "
                         "DEM only",
                         o.path);
            return TP_EXIT_USAGE;
        }
        code = view_store(o.path, &o);
    } else if (o.old_path || o.texture || o.scene.image_given || tp_is_heightmap_image(o.path)) {
        code = view_dem(&o);
    } else {
        /* every other DEM (GDAL's virtual paths too) through its store in the cache, built
         * with the view's --patch (17 unless given) */
        char store[4096];
        int temporary = 0;
        code = tp_terrain_store("view", o.path, &o.scene, o.cache_dir, store, sizeof store,
                                &temporary);
        if (code == TP_EXIT_OK)
            code = view_store(store, &o);
        if (temporary)
            tp_store_cache_remove_temporary(store);
    }
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
