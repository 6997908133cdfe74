/*
 * cmd_bench.c - `terrapatch bench DEM [options]`: speed against error, measured the same way for
 * every configuration in one run: headless (EGL) frames along a deterministic camera path, for
 * full resolution (frustum-culled) and each LoD mode, with per-frame CPU stages, draw time,
 * triangles, draw calls, GPU bytes and the measured error of the frame's geometry.
 */
#define _POSIX_C_SOURCE 200809L
#include "terrapatch.h"
#include "atomic_file.h"
#include "clock.h"
#include "bench.h"
#include "stitch_add_error.h"
#include "camera_pose.h"
#include "cli.h"
#include "gl_context.h"
#include "json.h"
#include "memory.h"
#include "renderer.h"
#include "scene.h"
#include "store_scene.h"
#include "terrain_open.h"
#include "view_options.h"

#include <epoxy/gl.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum {
    OPT_PATH = 256,
    OPT_PATH_FILE,
    OPT_FRAMES,
    OPT_JSON,
    OPT_CSV,
    OPT_NO_ERROR,
    OPT_STITCH,
    OPT_STITCH_ADD_DRAW,
    OPT_SPEED,
    OPT_SWEEP,
    OPT_PLOT,
    OPT_STATIC,
    OPT_MAX_ERROR,
    OPT_MEMORY,
    OPT_SEGMENTS,
    OPT_ERROR_EVERY,
    OPT_REALTIME,
    OPT_NO_PREFETCH,
    OPT_IMAGERY,
    OPT_CLIP_BLOCKS,
    OPT_IMAGERY_MODE,
    OPT_LIGHT,
    OPT_COMPARE,
    OPT_RUNS,
};

#define COUNT(a) ((int)(sizeof(a) / sizeof *(a)))
#define FRAME_HZ 30.0 /* the lead-in frame is 1 / FRAME_HZ s earlier along the path */

static void print_help(void)
{
    fputs("usage: terrapatch bench [options] DEM|X.tpt\n"
          "\n"
          "Renders headless frames (EGL) along a deterministic camera path for full resolution\n"
          "(frustum-culled), the distance LoD and the error LoD, in one run, and reports per\n"
          "configuration the median frame rate, CPU time (select + stitch + cull + upload), draw\n"
          "time (glFinish), triangles, draw calls, GPU bytes, and the measured error of the\n"
          "drawn geometry: vertical (m) and screen-space (px; for every full-resolution sample in\n"
          "view, the on-screen length between it and the drawn surface above or below it).\n"
          "\n"
          "options:\n"
          "  --path low|high|orbit  low: 60 m above the ground across the DEM's middle, looking\n"
          "                         ahead 10 deg down (default); high: a high oblique pass;\n"
          "                         orbit: around the centre\n"
          "  --path-file F          one --camera-geo LAT,LON,H,YAW,PITCH (or E,N,H,YAW,PITCH\n"
          "                         with a leading 'proj ') per line\n"
          "  --camera E,N,H,YAW,PITCH, --camera-geo LAT,LON,H,YAW,PITCH\n"
          "                         every frame from this one camera instead of a path\n"
          "  --frames N             frames per configuration (default 60)\n"
          "  --size WxH             default 1280x720; --fov DEG default 60\n"
          "  --tau PX, --mindist METRES, --maxdist METRES, --exp E   the LoD parameters (as\n"
          "                         for view; --lod is ignored: every mode is measured; a\n"
          "                         store: --lod spheres adds the distance mode through the\n"
          "                         sphere tree, same cut, its own cut ms)\n"
          "  --speed M/S            path flights move at this speed (default 100): before each\n"
          "                         timed frame, an untimed frame 1/30 s earlier along the path,\n"
          "                         so the timed one costs what a frame of a real flight costs;\n"
          "                         0: no lead-in (every frame a jump, uploads from cold)\n"
          "  --json FILE            summary; --csv FILE: one row per frame and configuration\n"
          "  --no-error             skip the error measurement (faster)\n"
          "  --stitch move|add      crack removal: move the finer patch's border vertices\n"
          "                         (default) or add them to the coarser patch's (Brodersen\n"
          "                         section 4); its error measured on its own geometry. A\n"
          "                         store runs error and distance both ways (+add rows)\n"
          "  --stitch-add-draw sets|five|both\n"
          "                         how --stitch add draws a patch that takes vertices: its\n"
          "                         own triangle list from an index set per neighbour\n"
          "                         configuration (sets), or up to five draws of per-level\n"
          "                         region sets (five; the default); both (a DEM): every\n"
          "                         --stitch add configuration twice, sets then five (same\n"
          "                         path and frames; a second table gives draws, index bytes\n"
          "                         on GPU and CPU)\n"
          "  --renderer pgm         also Persistent Grid Mapping (Livny, Kogan & El-Sana): one\n"
          "                         configuration per grid after the patch ones, the same path;\n"
          "                         a DEM: drawn whole, error by tp_pgm_measure_error (every post\n"
          "                         in view against the mapped grid's surface) on every\n"
          "                         --error-every-th frame; a store: through its clipmap\n"
          "                         (--pgm-window N posts a level, default 512; default grid\n"
          "                         300x300), fill/upload ms per frame, error not measured\n"
          "  --pgm-grid COLSxROWS[,COLSxROWS...]   the grids (default 150x600,300x300,600x600,\n"
          "                         from the paper's Table 1; --sweep: 150x600,200x800,300x900,\n"
          "                         600x600,400x1600 (Table 1), 300x300,430x430; at most 8)\n"
          "  --sweep                every renderer and crack fix on the same path and frames,\n"
          "                         each family with its own Pareto front: full resolution;\n"
          "                         distance mode with mindist {1,4} x maxdist {12,24,48,96}\n"
          "                         patch widths x exp {0.5,1,2} and error mode with tau\n"
          "                         {0.5,1,2,4,8,16} (and --tau), vertex moving; --stitch add\n"
          "                         at the run's distance parameters and at each tau; PGM per\n"
          "                         grid (--renderer pgm is implied). --csv FILE (required) gets\n"
          "                         one row per configuration (family, fps, CPU ms, triangles,\n"
          "                         GPU MiB, max and RMS px and m, PGM's uncovered share), and\n"
          "                         a plot of fps against measured max and RMS screen error goes\n"
          "                         to --plot FILE.png (default: FILE with .png; needs\n"
          "                         gnuplot). No --stitch, --no-error; the sphere tree (--lod\n"
          "                         spheres) is a store's cut: see the store bench\n"
          "  --static --max-error M1,M2,...\n"
          "                         no frames: builds the static mesh of 'export --max-error M'\n"
          "                         for each bound and reports triangles, points, build time and\n"
          "                         the measured maximum and RMS error against the source\n"
          "                         (\"patches\": the whole render grid), and terrapatch's\n"
          "                         error-bounded TIN (\"terrapatch tin\", as export builds it:\n"
          "                         tiles of 256 cells on every CPU, void outlines cut) on the\n"
          "                         same grid: triangles, points, median wall\n"
          "                         build time, true max and RMS error (tp_tin_measure, every\n"
          "                         valid sample), and the peak memory the build adds (each run\n"
          "                         in a forked child, its peak RSS reset via /proc/self/clear_refs)\n"
          "  --runs N               --static: timed runs per TIN, the median reported (default 3)\n"
          "  --compare              --static: also delatin 0.2.0 and martini 0.2.0 (npm; RTIN),\n"
          "                         and martini with its threshold lowered (e x 1, 0.9, .., 0.1,\n"
          "                         0.05, 0.02) to the largest one whose true error is <= e, each\n"
          "                         run in its own node process (peak memory: that process's peak\n"
          "                         RSS less its RSS before meshing); every TIN then runs on one\n"
          "                         window: the largest (2^k+1)^2 square centred in the render\n"
          "                         grid that holds no void (martini's grid shape).\n"
          "                         tools/tin_compare.sh installs the npm packages into\n"
          "                         ${XDG_CACHE_HOME:-~/.cache}/terrapatch/npm (needs node, npm\n"
          "                         and, once, the network; TP_TIN_COMPARE=PATH runs another copy\n"
          "                         of the script); every mesh is checked by tp_tin_measure.\n"
          "                         Missing node, npm or network: exit 1, no rows\n"
          "\n"
          "A built store (X.tpt, see 'terrapatch build') is flown through its hierarchy with\n"
          "streaming instead: the error mode at --tau, then the distance mode, each from a cold\n"
          "start; --path low|high; the flight is --segments stretches of continuous flight at\n"
          "--speed (30 frames a second) spread across the map, each reached by a jump, the\n"
          "stream then left to load what the view asks for, and 5 untimed frames of flight.\n"
          "  --memory MB            the stream's budget of decoded nodes (default 1024)\n"
          "  --segments N           stretches of flight (default 4); --frames are split among them\n"
          "  --realtime             the camera moves by speed x the time that really passed\n"
          "                         (a slow frame is a jump, as in the viewer), not speed / 30\n"
          "                         per frame\n"
          "  --no-prefetch          no prefetch cut (to measure what the prefetch costs)\n"
          "  --imagery FILE.tpi     a third configuration: the error mode with this imagery\n"
          "                         pyramid draped through the clipmap or blocks (upload ms,\n"
          "                         GPU and RAM of the imagery per frame, draw calls; the last\n"
          "                         frame compared with a fresh clipmap's or pool's:\n"
          "                         imagery_final_diff_pixels)\n"
          "  --clip-blocks N        the clipmap's window in blocks a side (even, 2..32; default 4)\n"
          "  --imagery-mode M       clipmap (default); blocks: Brodersen's texture per drawn node\n"
          "                         (a pool of 384 layers of 256x256, 96 MiB; one draw call per\n"
          "                         node); both: one configuration each, to compare them\n"
          "  --light FILE.tpl       one more configuration: the error mode with the day's light\n"
          "                         map made for the store streamed through its clipmap, the\n"
          "                         sun's time sweeping the day over the flight (light ms, GPU\n"
          "                         and RAM, uploads per frame: light_* in the JSON)\n"
          "  --error-every N        measure the screen error on every N-th frame (default 1),\n"
          "                         only frames drawn without substitution, only samples whose\n"
          "                         leaf is resident (the JSON says how many were skipped)\n"
          "--json adds rss_mb, rss_anon_mb (/proc/self/status VmRSS, RssAnon; max over the\n"
          "timed frames), resident_mb (the stream's accounting), gpu_mb, first_frame_ms (from\n"
          "the process's start to the end of the first drawn frame) and its parts\n"
          "(startup_to_bench_ms, store_open_ms, gl_context_ms, renderer_create_ms,\n"
          "stream_create_ms, georef_wait_ms, first_cut_stream_ms, first_draw_ms),\n"
          "frame_ms_p99, nodes_drawn_median, substituted_nodes_max, frames_with_substitution.\n"
          "\n"
          "DEM:\n",
          stdout);
    tp_scene_options_help(stdout);
    fputs("\nExit status: 0 success, 1 failure, 2 usage error.\n", stdout);
}

static int bad(const char* opt, const char* expected, const char* got)
{
    tp_option_error("bench", opt, expected, got);
    return TP_EXIT_USAGE;
}

static int parse_options(int argc, char** argv, bench_options* o)
{
    static const struct option longs[] = {
        TP_SCENE_LONG_OPTIONS,
        {"path", required_argument, NULL, OPT_PATH},
        {"path-file", required_argument, NULL, OPT_PATH_FILE},
        {"frames", required_argument, NULL, OPT_FRAMES},
        TP_VIEW_LONG_OPTIONS,
        TP_VIEW_PGM_LONG_OPTIONS,
        {"json", required_argument, NULL, OPT_JSON},
        {"csv", required_argument, NULL, OPT_CSV},
        {"no-error", no_argument, NULL, OPT_NO_ERROR},
        {"stitch", required_argument, NULL, OPT_STITCH},
        {"stitch-add-draw", required_argument, NULL, OPT_STITCH_ADD_DRAW},
        {"speed", required_argument, NULL, OPT_SPEED},
        {"sweep", no_argument, NULL, OPT_SWEEP},
        {"plot", required_argument, NULL, OPT_PLOT},
        {"static", no_argument, NULL, OPT_STATIC},
        {"max-error", required_argument, NULL, OPT_MAX_ERROR},
        {"memory", required_argument, NULL, OPT_MEMORY},
        {"segments", required_argument, NULL, OPT_SEGMENTS},
        {"error-every", required_argument, NULL, OPT_ERROR_EVERY},
        {"realtime", no_argument, NULL, OPT_REALTIME},
        {"no-prefetch", no_argument, NULL, OPT_NO_PREFETCH},
        {"imagery", required_argument, NULL, OPT_IMAGERY},
        {"clip-blocks", required_argument, NULL, OPT_CLIP_BLOCKS},
        {"imagery-mode", required_argument, NULL, OPT_IMAGERY_MODE},
        {"light", required_argument, NULL, OPT_LIGHT},
        {"compare", no_argument, NULL, OPT_COMPARE},
        {"runs", required_argument, NULL, OPT_RUNS},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    memset(o, 0, sizeof *o);
    tp_scene_options_default(&o->scene);
    o->path_name = "low";
    o->frames = 60;
    o->speed_mps = 100;
    o->memory_mb = 1024;
    o->segments = 4;
    o->error_every = 1;
    o->runs = 3;
    tp_view_setup_default(&o->vs);
    opterr = 0;
    optind = 1;
    int c;
    char* end;
    while ((c = getopt_long(argc, argv, ":h", longs, NULL)) != -1) {
        int taken = c == '?' || c == ':' ? 0 : tp_scene_option(c, optarg, &o->scene, "bench");
        if (!taken && c != '?' && c != ':')
            taken = tp_view_option(c, optarg, &o->vs, "bench");
        if (taken < 0)
            return TP_EXIT_USAGE;
        if (taken)
            continue;
        switch (c) {
        case OPT_PATH:
            if (strcmp(optarg, "low") && strcmp(optarg, "high") && strcmp(optarg, "orbit"))
                return bad("--path", "low, high or orbit", optarg);
            o->path_name = optarg;
            break;
        case OPT_PATH_FILE: o->path_file = optarg; break;
        case OPT_FRAMES: {
            long n = strtol(optarg, &end, 10);
            if (*end || n < 1 || n > 100000)
                return bad("--frames", "a count >= 1", optarg);
            o->frames = (int)n;
            break;
        }
        case OPT_JSON: o->json = optarg; break;
        case OPT_CSV: o->csv = optarg; break;
        case OPT_NO_ERROR: o->no_error = 1; break;
        case OPT_STITCH:
            if (strcmp(optarg, "move") && strcmp(optarg, "add")) {
                tp_cli_error("--stitch: expected move or add, got '%s'", optarg);
                return TP_EXIT_USAGE;
            }
            o->stitch_add = strcmp(optarg, "add") == 0;
            break;
        case OPT_STITCH_ADD_DRAW:
            if (strcmp(optarg, "sets") && strcmp(optarg, "five") && strcmp(optarg, "both")) {
                tp_cli_error("--stitch-add-draw: expected sets, five or both, got "
                             "'%s'",
                             optarg);
                return TP_EXIT_USAGE;
            }
            o->stitch_add_draw = !strcmp(optarg, "sets") ? 1 : !strcmp(optarg, "five") ? 2 : 3;
            break;
        case OPT_SPEED: {
            double v = strtod(optarg, &end);
            if (*end || end == optarg || !(v >= 0) || !isfinite(v))
                return bad("--speed", "metres per second >= 0", optarg);
            o->speed_mps = v;
            break;
        }
        case OPT_SWEEP: o->sweep = 1; break;
        case OPT_PLOT: o->plot = optarg; break;
        case OPT_STATIC: o->is_static = 1; break;
        case OPT_MAX_ERROR: {
            const char* at = optarg;
            o->max_error_count = 0;
            for (;;) {
                double v = strtod(at, &end);
                if (end == at || !(v > 0) || !isfinite(v) ||
                    o->max_error_count == COUNT(o->max_errors) || (*end && *end != ','))
                    return bad("--max-error", "up to 16 bounds in metres > 0, comma-separated",
                               optarg);
                o->max_errors[o->max_error_count++] = v;
                if (!*end)
                    break;
                at = end + 1;
            }
            break;
        }
        case OPT_COMPARE: o->compare = 1; break;
        case OPT_MEMORY:
        case OPT_SEGMENTS:
        case OPT_RUNS:
        case OPT_ERROR_EVERY: {
            long n = strtol(optarg, &end, 10);
            long lo = c == OPT_MEMORY ? 16 : 1, hi = c == OPT_MEMORY ? 1 << 20 : 100000;
            if (*end || end == optarg || n < lo || n > hi)
                return bad(c == OPT_MEMORY     ? "--memory"
                           : c == OPT_SEGMENTS ? "--segments"
                           : c == OPT_RUNS     ? "--runs"
                                               : "--error-every",
                           c == OPT_MEMORY ? "megabytes, 16 or more" : "a count >= 1", optarg);
            if (c == OPT_MEMORY)
                o->memory_mb = (int)n;
            else if (c == OPT_SEGMENTS)
                o->segments = (int)n;
            else if (c == OPT_RUNS)
                o->runs = (int)n, o->runs_given = 1;
            else
                o->error_every = (int)n;
            break;
        }
        case OPT_REALTIME: o->realtime = 1; break;
        case OPT_NO_PREFETCH: o->no_prefetch = 1; break;
        case OPT_IMAGERY: o->imagery = optarg; break;
        case OPT_LIGHT: o->light = optarg; break;
        case OPT_CLIP_BLOCKS: {
            char* end;
            long n = strtol(optarg, &end, 10);
            if (*end || n < 2 || n > 32 || n % 2) {
                tp_option_error("bench", "--clip-blocks", "an even number from 2 to 32", optarg);
                return TP_EXIT_USAGE;
            }
            o->clip_blocks = (int)n;
            break;
        }
        case OPT_IMAGERY_MODE:
            if (!strcmp(optarg, "clipmap"))
                o->imagery_mode = 0;
            else if (!strcmp(optarg, "blocks"))
                o->imagery_mode = 1;
            else if (!strcmp(optarg, "both"))
                o->imagery_mode = 2;
            else {
                tp_option_error("bench", "--imagery-mode", "clipmap, blocks or both", optarg);
                return TP_EXIT_USAGE;
            }
            break;
        case 'h': print_help(); return tp_cli_finish(TP_EXIT_OK);
        case ':': tp_cli_error("missing value for %s", argv[optind - 1]); return TP_EXIT_USAGE;
        default:
            tp_cli_error("unknown option '%s' (see 'terrapatch bench --help')", argv[optind - 1]);
            return TP_EXIT_USAGE;
        }
    }
    if (optind >= argc) {
        tp_cli_error("missing DEM file");
        return TP_EXIT_USAGE;
    }
    o->dem = argv[optind];
    if (optind + 1 < argc) {
        tp_cli_error("expected one DEM, got extra argument '%s'", argv[optind + 1]);
        return TP_EXIT_USAGE;
    }
    if (tp_view_setup_check(&o->vs, "bench") < 0)
        return TP_EXIT_USAGE;
    if ((o->imagery || o->light) && !tp_is_store_path(o->dem)) {
        tp_cli_error("%s needs a store (%s is not one)", o->imagery ? "--imagery" : "--light",
                     o->dem);
        return TP_EXIT_USAGE;
    }
    if (o->vs.pgm_grid_count && !o->vs.pgm && !o->sweep) {
        tp_cli_error("--pgm-grid needs --renderer pgm (or --sweep)");
        return TP_EXIT_USAGE;
    }
    if (o->vs.pgm_window && (!o->vs.pgm || !tp_is_store_path(o->dem))) {
        tp_cli_error("--pgm-window is for --renderer pgm over a store (%s "
                     "is %s)",
                     o->dem, o->vs.pgm ? "a DEM, drawn whole" : "drawn by patches");
        return TP_EXIT_USAGE;
    }
    if (o->vs.pgm && o->is_static) {
        tp_cli_error("--renderer pgm: not with --static");
        return TP_EXIT_USAGE;
    }
    if (o->stitch_add_draw == 3 && tp_is_store_path(o->dem)) {
        tp_cli_error("--stitch-add-draw both: a DEM only (a store: give "
                     "sets or five)");
        return TP_EXIT_USAGE;
    }
    if (o->stitch_add_draw == 3 && o->sweep) {
        tp_cli_error("--stitch-add-draw both: not with --sweep (give sets "
                     "or five)");
        return TP_EXIT_USAGE;
    }
    if (o->stitch_add && o->sweep) {
        tp_cli_error("--sweep runs both crack fixes (move and add): it "
                     "takes no --stitch");
        return TP_EXIT_USAGE;
    }
    if (o->stitch_add && o->is_static) {
        tp_cli_error("--stitch add: not with --static");
        return TP_EXIT_USAGE;
    }
    if (tp_is_store_path(o->dem)) {
        const char* no = o->sweep ? "--sweep" : o->is_static ? "--static" : o->path_file ? "--path-file"
                         : o->vs.has_camera ? "--camera" : !strcmp(o->path_name, "orbit") ? "--path orbit"
                         : NULL;
        if (!no && o->realtime && o->speed_mps <= 0)
            no = "--realtime with --speed 0";
        if (no) {
            tp_cli_error("%s is not available for a store (%s)", no, o->dem);
            return TP_EXIT_USAGE;
        }
    }
    if (o->is_static != (o->max_error_count > 0)) {
        tp_cli_error("--static and --max-error go together "
                     "(e.g. --static --max-error 1,5,20)");
        return TP_EXIT_USAGE;
    }
    if ((o->compare || o->runs_given) && !o->is_static) {
        tp_cli_error("%s needs --static --max-error", o->compare ? "--compare" : "--runs");
        return TP_EXIT_USAGE;
    }
    if (o->is_static && o->sweep) {
        tp_cli_error("--static and --sweep exclude each other");
        return TP_EXIT_USAGE;
    }
    if (o->sweep && !o->csv) {
        tp_cli_error("--sweep needs --csv FILE (the plot goes beside it)");
        return TP_EXIT_USAGE;
    }
    if (o->plot && !o->sweep) {
        tp_cli_error("--plot needs --sweep");
        return TP_EXIT_USAGE;
    }
    if (o->sweep && o->no_error) {
        tp_cli_error("--sweep plots fps against the measured error: it "
                     "cannot take --no-error");
        return TP_EXIT_USAGE;
    }
    if (o->sweep) {
        if (!o->plot) { /* the CSV's name with .png */
            const char *dot = strrchr(o->csv, '.'), *slash = strrchr(o->csv, '/');
            int stem = dot && (!slash || dot > slash) ? (int)(dot - o->csv) : (int)strlen(o->csv);
            snprintf(o->plot_buf, sizeof o->plot_buf, "%.*s.png", stem, o->csv);
            o->plot = o->plot_buf;
        }
        if (!strcmp(o->plot, o->csv) || (o->json && !strcmp(o->plot, o->json))) {
            tp_cli_error("the plot would overwrite %s: give --plot FILE", o->plot);
            return TP_EXIT_USAGE;
        }
    }
    if (o->csv && o->json && !strcmp(o->csv, o->json)) {
        tp_cli_error("--csv and --json name the same file");
        return TP_EXIT_USAGE;
    }
    return -1;
}

#define MEDIAN_OF(expr) TP_BENCH_COLUMN(v, frame_row, c->rows, n, expr)

static void summarize(config_result* c, int n)
{
    double* v = malloc((size_t)n * sizeof *v);
    if (!v)
        return;
    MEDIAN_OF(r->frame_ms);
    c->frame_ms = tp_bench_median(v, n);
    c->fps_median = 1000 / c->frame_ms;
    MEDIAN_OF(r->select_ms + r->upload_ms);
    c->cpu_ms = tp_bench_median(v, n);
    MEDIAN_OF(r->draw_ms);
    c->draw_ms = tp_bench_median(v, n);
    MEDIAN_OF(r->triangles);
    c->triangles = tp_bench_median(v, n);
    MEDIAN_OF(r->draw_calls);
    c->draw_calls = tp_bench_median(v, n);
    MEDIAN_OF(r->uploads);
    c->uploads = tp_bench_median(v, n);
    MEDIAN_OF(r->draws);
    c->draws = tp_bench_median(v, n);
    MEDIAN_OF(r->oracle_triangles);
    c->oracle_triangles = tp_bench_median(v, n);
    MEDIAN_OF(r->oracle_patches);
    c->oracle_patches = tp_bench_median(v, n);
    double sum_m = 0, sum_px = 0;
    c->gpu_bytes = 0;
    for (int i = 0; i < n; i++) {
        const frame_row* r = &c->rows[i];
        c->max_m = fmax(c->max_m, r->max_m);
        c->max_px = fmax(c->max_px, r->max_px);
        sum_m += r->rms_m * r->rms_m;
        sum_px += r->rms_px * r->rms_px;
        c->gpu_bytes = r->gpu_bytes > c->gpu_bytes ? r->gpu_bytes : c->gpu_bytes;
        if (r->index_gpu_bytes > c->index_gpu_bytes)
            c->index_gpu_bytes = r->index_gpu_bytes;
        if (r->index_cpu_bytes > c->index_cpu_bytes)
            c->index_cpu_bytes = r->index_cpu_bytes;
    }
    c->rms_m = sqrt(sum_m / n);
    c->rms_px = sqrt(sum_px / n);
    free(v);
}

/* How far the error mode's bound is from what the measured error allows: each visible complete
 * patch is taken down one level at a time, alone (neighbours as they are), while its measured
 * screen error stays <= tau; *out is the frame's triangle count with every patch at that level
 * (2 * 4^k per complete patch), *coarser the number of patches that could go down. */
static tp_status oracle_triangles(const tp_scene* sc, const tp_selection* sel,
                                  const tp_camera* cam, double tau, size_t triangles, size_t* out,
                                  int* coarser)
{
    int down = 0;
    for (int p = 0; p < sc->info.patch_count; p++) {
        if (!tp_selection_visible(sel, p))
            continue;
        tp_patch_info pi;
        tp_patch_get_info(sc->terrain, p, &pi);
        int k = tp_selection_level(sel, p), kk = k;
        if (!pi.complete)
            continue;
        for (double px; kk > 0; kk--) {
            tp_status s = tp_selection_patch_screen_error(sel, cam, p, kk - 1, &px);
            if (s != TP_OK)
                return s;
            if (px > tau)
                break;
        }
        if (kk < k) {
            down++;
            triangles -= ((size_t)2 << (2 * k)) - ((size_t)2 << (2 * kk));
        }
    }
    *out = triangles;
    *coarser = down;
    return TP_OK;
}

/* Renders the run's frames for one configuration (fresh renderer and selection: each starts
 * cold, as a viewer would) and fills c->rows and the summary. Returns TP_EXIT_*. */
static int run_config(const bench_run* b, config_result* c, const char* progress)
{
    if (c->pgm_cols) {
        int code = tp_bench_pgm_frames(b, c, progress);
        if (code == TP_EXIT_OK) {
            summarize(c, b->frames);
            tp_bench_pgm_errors(c, b->frames);
        }
        return code;
    }
    char msg[512];
    int frames = b->frames;
    c->rows = calloc((size_t)frames, sizeof *c->rows);
    tp_renderer* r = tp_renderer_create(b->sc->terrain, msg, sizeof msg);
    tp_selection* sel = NULL;
    tp_error err;
    if (!c->rows || !r || tp_selection_create(b->sc->terrain, &sel, &err) != TP_OK) {
        tp_cli_error("%s", r ? "out of memory" : msg);
        tp_renderer_destroy(r);
        return TP_EXIT_FAILURE;
    }
    tp_render_settings rs;
    tp_render_settings_default(&rs);
    rs.stitch_add = c->stitch_add;
    rs.stitch_add_five = c->stitch_add && c->stitch_add_five;
    if (c->stitch_add && tp_terrain_prepare_stitch_add(b->sc->terrain, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        tp_selection_destroy(sel);
        tp_renderer_destroy(r);
        return TP_EXIT_FAILURE;
    }
    tp_selection_set_stitch_add(sel, c->stitch_add); /* the error mode bounds its geometry */
    tp_render_stats st;
    for (int i = 0; i < frames; i++) {
        tp_camera cam, lead;
        if (tp_bench_frame_camera(b, i, &cam, &lead)) { /* untimed */
            tp_gl_context_begin_frame(b->ctx);
            tp_selection_update(sel, &lead, &c->lod, &err);
            tp_renderer_draw(r, sel, &lead, &rs, 1, &st);
            tp_gl_context_end_frame(b->ctx);
        }
        frame_row* row = &c->rows[i];
        tp_gl_context_begin_frame(b->ctx);
        double t0 = tp_clock_ms();
        tp_selection_update(sel, &cam, &c->lod, &err);
        double t1 = tp_clock_ms();
        tp_renderer_draw(r, sel, &cam, &rs, 1, &st);
        tp_gl_context_end_frame(b->ctx);
        double t2 = tp_clock_ms();
        tp_frame_stats fs;
        tp_selection_stats(sel, &fs);
        row->select_ms = t1 - t0;
        row->upload_ms = st.upload_ms;
        row->draw_ms = st.draw_ms;
        row->frame_ms = t2 - t0;
        row->triangles = rs.stitch_add ? st.triangles : fs.triangles;
        row->draw_calls = st.draw_calls;
        row->patches = st.patches_drawn;
        row->uploads = st.uploads;
        row->gpu_bytes = st.gpu_bytes;
        row->draws = st.draws;
        row->index_gpu_bytes = st.index_gpu_bytes;
        row->index_cpu_bytes = st.index_cpu_bytes;
        if (!b->o->no_error) { /* outside the timed part of the frame */
            tp_error_measure em;
            tp_status ms;
            if (rs.stitch_add) { /* its own geometry: the core measures vertex moving's */
                ms = tp_stitch_add_error(b->sc->terrain, sel, &cam, &em, &row->max_px,
                                               &row->rms_px);
            } else {
                ms = tp_selection_measure_error(sel, &em);
            }
            if (ms == TP_OK && !rs.stitch_add)
                ms = tp_selection_measure_screen_error(sel, &cam, &row->max_px, &row->rms_px,
                                                       NULL);
            if (ms == TP_OK && c->lod.mode == TP_LOD_ERROR && !rs.stitch_add)
                ms = oracle_triangles(b->sc, sel, &cam, c->lod.tau_px, fs.triangles,
                                      &row->oracle_triangles, &row->oracle_patches);
            if (ms != TP_OK) {
                tp_bench_progress_end();
                tp_cli_error("%s: measuring the error of frame %d: %s", progress, i + 1,
                             tp_status_str(ms));
                tp_selection_destroy(sel);
                tp_renderer_destroy(r);
                return TP_EXIT_FAILURE;
            }
            row->max_m = em.max_error_m;
            row->rms_m = em.rms_error_m;
        }
        char what[96];
        snprintf(what, sizeof what, "%.1f ms, %zu triangles", row->frame_ms, row->triangles);
        tp_bench_progress(progress, i + 1, frames, what);
    }
    tp_bench_progress_end();
    summarize(c, frames);
    tp_selection_destroy(sel);
    tp_renderer_destroy(r);
    return TP_EXIT_OK;
}

/* The configurations of the run: full, distance, error (with --stitch's crack fix), then
 * --renderer pgm's grids; or the sweep's (bench_sweep.c). */
static config_result* make_configs(const bench_run* b, int* count, int* best)
{
    const bench_options* o = b->o;
    tp_lod_params base;
    tp_lod_params_resolve(b->sc->terrain, &o->vs.lod, &base, NULL);
    if (o->sweep)
        return tp_bench_sweep_configs(b, &base, count, best);
    int pgm = o->vs.pgm ? (o->vs.pgm_grid_count ? o->vs.pgm_grid_count : 3) : 0;
    config_result* c = calloc((size_t)(5 + pgm), sizeof *c);
    if (!c)
        return NULL;
    static const tp_lod_mode modes[3] = {TP_LOD_FULL, TP_LOD_DISTANCE, TP_LOD_ERROR};
    tp_render_settings rs;
    tp_render_settings_default(&rs);
    int both = o->stitch_add && o->stitch_add_draw == 3, k = 0;
    for (int m = 0; m < 3; m++) /* full resolution has no finer neighbour: once */
        for (int v = 0; v <= (both && modes[m] != TP_LOD_FULL); v++, k++) {
            c[k].lod = base;
            c[k].lod.mode = modes[m];
            c[k].stitch_add = o->stitch_add;
            c[k].stitch_add_five = both ? v : o->stitch_add_draw ? o->stitch_add_draw == 2
                                                                 : rs.stitch_add_five;
        }
    *best = both ? 3 : 2; /* the error mode (with both: sets) */
    /* --renderer pgm: the grids after the patch configurations (default: the paper's Table 1) */
    static const int table1[3][2] = {{150, 600}, {300, 300}, {600, 600}};
    for (int g = 0; g < pgm; g++, k++) {
        c[k].lod = base;
        c[k].pgm_cols = o->vs.pgm_grid_count ? o->vs.pgm_grid[g][0] : table1[g][0];
        c[k].pgm_rows = o->vs.pgm_grid_count ? o->vs.pgm_grid[g][1] : table1[g][1];
    }
    for (int i = 0; i < k; i++) {
        tp_bench_label(&c[i]);
        if (both && c[i].stitch_add && c[i].lod.mode != TP_LOD_FULL) /* which drawing */
            strncat(c[i].label, c[i].stitch_add_five ? " five" : " sets",
                    sizeof c[i].label - strlen(c[i].label) - 1);
    }
    *count = k;
    return c;
}

int tp_cli_bench(int argc, char** argv)
{
    bench_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    /* Outputs are written after the run: find an unwritable folder before it, not after. */
    const char* outputs[3] = {o.json, o.csv, o.plot};
    for (int i = 0; i < 3; i++)
        if (outputs[i] && !tp_atomic_check_dir(outputs[i]))
            return TP_EXIT_FAILURE;
    int is_store;
    if ((code = tp_terrain_classify("bench", o.dem, &o.scene, &is_store)) >= 0)
        return code;
    if (is_store) { /* the stream's budget within what the process may still use */
        uint64_t b = tp_memory_fit_budget("bench", o.dem, "the decoded terrain (--memory)",
                                          tp_memory_estimate(TP_MEMORY_USE_BENCH, 0),
                                          (uint64_t)o.memory_mb << 20, (uint64_t)16 << 20);
        if (!b)
            return TP_EXIT_FAILURE;
        o.memory_mb = (int)(b >> 20);
        return tp_bench_store(&o);
    }
    tp_scene sc;
    o.scene.use = TP_MEMORY_USE_BENCH;
    if ((code = tp_scene_load(o.dem, &o.scene, &sc)) != TP_EXIT_OK)
        return code;
    if (o.is_static) {
        code = tp_bench_static(&sc, &o);
        tp_scene_free(&sc);
        return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
    }
    bench_run b = {.o = &o, .sc = &sc, .frames = o.frames};
    tp_camera* cams = NULL;
    if (o.path_file && !tp_bench_read_path_file(&sc, &o, &cams, &b.frames)) {
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    b.cams = cams;
    tp_camera fixed;
    if (o.vs.has_camera) {
        if (!tp_view_setup_camera(&sc, &o.vs, &fixed, "bench")) {
            free(cams);
            tp_scene_free(&sc);
            return TP_EXIT_FAILURE;
        }
        b.fixed = &fixed;
    }
    if (!cams && !b.fixed && o.speed_mps > 0)
        b.lead_da = o.speed_mps / FRAME_HZ / tp_bench_path_length(&sc, &o);
    char msg[512];
    if (!tp_gl_context_create_headless(o.vs.w, o.vs.h, &b.ctx, msg, sizeof msg)) {
        tp_cli_error("%s", msg);
        free(cams);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    const char* renderer_name = (const char*)glGetString(GL_RENDERER);
    renderer_name = renderer_name ? renderer_name : "?";
    int nc = 0, best = 0;
    config_result* c = make_configs(&b, &nc, &best);
    code = c ? TP_EXIT_OK : TP_EXIT_FAILURE;
    if (!c)
        tp_cli_error("out of memory");
    for (int k = 0; k < nc && code == TP_EXIT_OK; k++) {
        char progress[96];
        snprintf(progress, sizeof progress, "%s (%d/%d)", c[k].label, k + 1, nc);
        code = run_config(&b, &c[k], progress);
    }
    if (code == TP_EXIT_OK) {
        if (o.sweep)
            tp_bench_mark_pareto(c, nc);
        tp_bench_print_table(&b, renderer_name, c, nc, best);
        if (o.json && !tp_bench_write_json(&b, renderer_name, c, nc, &c[best]))
            code = TP_EXIT_FAILURE;
        if (o.csv && !(o.sweep ? tp_bench_write_sweep_csv(&o, c, nc)
                               : tp_bench_write_frames_csv(&o, c, nc, b.frames)))
            code = TP_EXIT_FAILURE;
        if (code == TP_EXIT_OK && o.sweep) {
            char title[512];
            snprintf(title, sizeof title, "%s, %s path, %dx%d, %d frames per point, %s",
                     sc.path, o.path_file ? o.path_file : o.vs.has_camera ? "fixed" : o.path_name,
                     o.vs.w, o.vs.h, b.frames, renderer_name);
            if (!tp_bench_sweep_plot(c, nc, o.plot, title))
                code = TP_EXIT_FAILURE;
        }
    }
    for (int k = 0; k < nc; k++)
        free(c[k].rows);
    free(c);
    free(cams);
    tp_gl_context_destroy(b.ctx);
    tp_scene_free(&sc);
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
