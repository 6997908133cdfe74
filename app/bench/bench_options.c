/*
 * bench_options.c - the command line of `terrapatch bench` (see bench.h): its help, its options'
 * table (options.h) in groups (the flight and what it draws, the outputs, --static, a store's
 * stream) and the checks of how they combine, in the order the messages are given.
 */
#include "bench.h"
#include "cli.h"
#include "store_scene.h"
#include "view_options.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The options whose values are read by code_option. */
enum { OPT_PATH = 1, OPT_STITCH, OPT_STITCH_ADD_DRAW, OPT_MAX_ERROR, OPT_CLIP_BLOCKS, OPT_IMAGERY_MODE };

#define COUNT(a) ((int)(sizeof(a) / sizeof *(a)))
static void print_help(void)
{
    fputs(
        "usage: terrapatch bench [options] DEM|X.tpt\n"
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
        "                         300x300), fill/upload ms per frame, error against the\n"
        "                         store's posts in view (bands of them past 2^28 posts)\n"
        "  --pgm-grid COLSxROWS[,COLSxROWS...]   the grids (default 150x600,300x300,600x600,\n"
        "                         from the paper's Table 1; --sweep: 150x600,200x800,300x900,\n"
        "                         600x600,400x1600 (Table 1), 300x300,430x430; at most 8)\n"
        "  --sweep                every renderer and crack fix on the same path and frames,\n"
        "                         each family with its own Pareto front: full resolution;\n"
        "                         distance mode with mindist {1,4} x maxdist {12,24,48,96}\n"
        "                         patch widths x exp {0.5,1,2} and error mode with tau\n"
        "                         {0.5,1,2,4,8,16} (and --tau), vertex moving; --stitch add\n"
        "                         at the run's distance parameters and at each tau; PGM per\n"
        "                         grid (--renderer pgm is implied); the error mode at each tau\n"
        "                         over the DEM's store (found in or built into the cache as\n"
        "                         view builds it) with lattice nodes (store) and TIN nodes\n"
        "                         (store+tin), each frame settled first (nodes loaded, TINs\n"
        "                         built), its error over --error-posts posts. --csv FILE\n"
        "                         (required) gets one row per configuration (family, fps, CPU\n"
        "                         ms, triangles, GPU MiB, max and RMS px and m, PGM's uncovered\n"
        "                         share, the store's mesh and TIN share), and\n"
        "                         a plot of fps against measured max and RMS screen error goes\n"
        "                         to --plot FILE.png (default: FILE with .png; needs\n"
        "                         gnuplot). No --stitch, --no-error, --fit; the sphere tree (--lod\n"
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
        "                         in a forked child, its peak RSS reset via "
        "/proc/self/clear_refs)\n"
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
        "  --no-cut-thread        select each frame's cut on the render thread (by default a\n"
        "                         thread selects it for the predicted camera while the frame\n"
        "                         before draws; the frame checks it holds, else selects it)\n"
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
        "  --error-every N        measure the screen error on every N-th frame (default 1);\n"
        "                         frames drawn with substitution are reported apart; leaves\n"
        "                         the stream does not hold are read from the store\n"
        "  --error-posts N        a store: compare the posts of at most about N/4^n leaves a\n"
        "                         measured frame (default 4194304; 0: every leaf under the\n"
        "                         cut): each drawn node's leaves, every k-th column and row of\n"
        "                         the large ones, chosen anew each frame (error_leaf_share)\n"
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

/* What an option's reader or a check returns when it gives no exit status: the option was
 * taken (or the check passed), parsing goes on. */
enum { GO_ON = -1 };

/* "OPT: expected EXPECTED, got 'GOT'" (tp_option_error); the usage error's exit status. */
static int bad(const char* opt, const char* expected, const char* got)
{
    tp_option_error("bench", opt, expected, got);
    return TP_EXIT_USAGE;
}

/* The index of arg in words[0..n-1], or -1. */
static int keyword(const char* arg, const char* const* words, int n)
{
    for (int i = 0; i < n; i++)
        if (!strcmp(arg, words[i]))
            return i;
    return -1;
}

/* --max-error M1,M2,...: up to COUNT(o->max_errors) bounds in metres > 0. */
static int max_error_option(const char* arg, bench_options* o)
{
    const char* at = arg;
    char* end;
    o->max_error_count = 0;
    for (;;) {
        double v = strtod(at, &end);
        if (end == at || !(v > 0) || !isfinite(v) || o->max_error_count == COUNT(o->max_errors) ||
            (*end && *end != ','))
            return bad("--max-error", "up to 16 bounds in metres > 0, comma-separated", arg);
        o->max_errors[o->max_error_count++] = v;
        if (!*end)
            return GO_ON;
        at = end + 1;
    }
}

/* The value arg of option c (a code above): GO_ON when read into o, else the exit status. */
static int code_option(int c, const char* arg, bench_options* o)
{
    static const char* const paths[] = {"low", "high", "orbit"};
    static const char* const stitches[] = {"move", "add"};       /* stitch_add 0, 1 */
    static const char* const draws[] = {"sets", "five", "both"}; /* stitch_add_draw 1, 2, 3 */
    static const char* const modes[] = {"clipmap", "blocks", "both"}; /* imagery_mode 0, 1, 2 */
    int k;
    switch (c) {
    case OPT_PATH:
        if (keyword(arg, paths, COUNT(paths)) < 0)
            return bad("--path", "low, high or orbit", arg);
        o->path_name = arg;
        return GO_ON;
    case OPT_STITCH:
        if ((k = keyword(arg, stitches, COUNT(stitches))) < 0)
            return bad("--stitch", "move or add", arg);
        o->stitch_add = k;
        return GO_ON;
    case OPT_STITCH_ADD_DRAW:
        if ((k = keyword(arg, draws, COUNT(draws))) < 0)
            return bad("--stitch-add-draw", "sets, five or both", arg);
        o->stitch_add_draw = k + 1;
        return GO_ON;
    case OPT_MAX_ERROR: return max_error_option(arg, o);
    case OPT_CLIP_BLOCKS:
        if (!tp_parse_int(arg, 2, 32, &o->clip_blocks) || o->clip_blocks % 2)
            return bad("--clip-blocks", "an even number from 2 to 32", arg);
        return GO_ON;
    case OPT_IMAGERY_MODE:
        if ((k = keyword(arg, modes, COUNT(modes))) < 0)
            return bad("--imagery-mode", "clipmap, blocks or both", arg);
        o->imagery_mode = k;
        return GO_ON;
    }
    return GO_ON;
}

/* bench's CODE options (tp_option_handler): code_option. */
static int own_option(void* ctx, int code, const char* value, const char* cmd)
{
    (void)cmd;
    return code_option(code, value, ctx) == GO_ON ? 1 : -1;
}

static void set_defaults(bench_options* o)
{
    memset(o, 0, sizeof *o);
    tp_scene_options_default(&o->scene);
    o->path_name = "low";
    o->frames = 60;
    o->speed_mps = 100;
    o->memory_mb = 1024;
    o->segments = 4;
    o->error_every = 1;
    o->error_posts = 1 << 22;
    o->runs = 0; /* --runs not given: 3 */
    tp_view_setup_default(&o->vs);
}

/* The operands: one DEM or store (extra: the first one too many, or NULL). */
static int check_operand(const bench_options* o, const char* extra)
{
    if (!o->dem) {
        tp_cli_error("missing DEM file");
        return TP_EXIT_USAGE;
    }
    if (extra) {
        tp_cli_error("expected one DEM, got extra argument '%s'", extra);
        return TP_EXIT_USAGE;
    }
    return GO_ON;
}

/* What draws: --imagery and --light need a store; --renderer pgm's options; --stitch. */
static int check_drawing(const bench_options* o)
{
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
        tp_cli_error("--pgm-window is for --renderer pgm over a store (%s is %s)", o->dem,
                     o->vs.pgm ? "a DEM, drawn whole" : "drawn by patches");
        return TP_EXIT_USAGE;
    }
    if (o->vs.pgm && o->is_static) {
        tp_cli_error("--renderer pgm: not with --static");
        return TP_EXIT_USAGE;
    }
    if (o->stitch_add_draw == 3 && tp_is_store_path(o->dem)) {
        tp_cli_error("--stitch-add-draw both: a DEM only (a store: give sets or five)");
        return TP_EXIT_USAGE;
    }
    if (o->stitch_add_draw == 3 && o->sweep) {
        tp_cli_error("--stitch-add-draw both: not with --sweep (give sets or five)");
        return TP_EXIT_USAGE;
    }
    if (o->stitch_add && o->sweep) {
        tp_cli_error("--sweep runs both crack fixes (move and add): it takes no --stitch");
        return TP_EXIT_USAGE;
    }
    if (o->stitch_add && o->is_static) {
        tp_cli_error("--stitch add: not with --static");
        return TP_EXIT_USAGE;
    }
    return GO_ON;
}

/* What a store's flight cannot do. */
static int check_store(const bench_options* o)
{
    if (!tp_is_store_path(o->dem))
        return GO_ON;
    const char* no = o->sweep                         ? "--sweep"
                     : o->is_static                   ? "--static"
                     : o->path_file                   ? "--path-file"
                     : o->vs.has_camera               ? "--camera"
                     : !strcmp(o->path_name, "orbit") ? "--path orbit"
                                                      : NULL;
    if (!no && o->realtime && o->speed_mps <= 0)
        no = "--realtime with --speed 0";
    if (no) {
        tp_cli_error("%s is not available for a store (%s)", no, o->dem);
        return TP_EXIT_USAGE;
    }
    return GO_ON;
}

/* The run's kind: --static with --max-error (and --compare, --runs), or --sweep with --csv
 * (and --plot, the measured error), not both. */
static int check_modes(const bench_options* o)
{
    if (o->is_static != (o->max_error_count > 0)) {
        tp_cli_error("--static and --max-error go together (e.g. --static --max-error 1,5,20)");
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
    if (o->sweep && (o->scene.given & TP_SCENE_GIVEN(TP_OPT_FIT))) {
        tp_cli_error("--sweep: --fit shapes a DEM drawn whole, and the sweep also draws the DEM "
                     "through its store (built as view builds it), which takes any size: leave "
                     "--fit out");
        return TP_EXIT_USAGE;
    }
    if (o->sweep && o->no_error) {
        tp_cli_error("--sweep plots fps against the measured error: it cannot take --no-error");
        return TP_EXIT_USAGE;
    }
    return GO_ON;
}

/* The files written: --sweep's plot (default: the CSV's name with .png), the CSV and the JSON,
 * no two of them the same file. */
static int check_outputs(bench_options* o)
{
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
    return GO_ON;
}

int tp_bench_parse_options(int argc, char** argv, bench_options* o)
{
    set_defaults(o);
    const tp_option options[] = {
        /* the flight and what it draws */
        TP_OPT_CODE("--path", NULL, OPT_PATH, 1),
        TP_OPT_TEXT("--path-file", NULL, &o->path_file),
        TP_OPT_INTEGER("--frames", &o->frames, 1, 100000, "a count >= 1"),
        TP_OPT_NUMBER("--speed", &o->speed_mps, 0, DBL_MAX, "metres per second >= 0"),
        TP_OPT_FLAG("--no-error", &o->no_error),
        TP_OPT_CODE("--stitch", NULL, OPT_STITCH, 1),
        TP_OPT_CODE("--stitch-add-draw", NULL, OPT_STITCH_ADD_DRAW, 1),
        TP_OPT_FLAG("--sweep", &o->sweep),
        /* the files written */
        TP_OPT_TEXT("--json", NULL, &o->json),
        TP_OPT_TEXT("--csv", NULL, &o->csv),
        TP_OPT_TEXT("--plot", NULL, &o->plot),
        /* the static meshes */
        TP_OPT_FLAG("--static", &o->is_static),
        TP_OPT_CODE("--max-error", NULL, OPT_MAX_ERROR, 1),
        TP_OPT_FLAG("--compare", &o->compare),
        TP_OPT_INTEGER("--runs", &o->runs, 1, 100000, "a count >= 1"),
        /* a store's flight */
        TP_OPT_INTEGER("--memory", &o->memory_mb, 16, 1 << 20, "megabytes, 16 or more"),
        TP_OPT_INTEGER("--segments", &o->segments, 1, 100000, "a count >= 1"),
        TP_OPT_INTEGER("--error-every", &o->error_every, 1, 100000, "a count >= 1"),
        TP_OPT_NUMBER("--error-posts", &o->error_posts, 0, 1e15, "a count >= 0"),
        TP_OPT_FLAG("--realtime", &o->realtime),
        TP_OPT_FLAG("--no-prefetch", &o->no_prefetch),
        TP_OPT_FLAG("--no-cut-thread", &o->no_cut_thread),
        TP_OPT_TEXT("--imagery", NULL, &o->imagery),
        TP_OPT_CODE("--clip-blocks", NULL, OPT_CLIP_BLOCKS, 1),
        TP_OPT_CODE("--imagery-mode", NULL, OPT_IMAGERY_MODE, 1),
        TP_OPT_TEXT("--light", NULL, &o->light),
    };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), own_option, o};
    const char* extra;
    const int parsed = tp_view_command_parse("bench", argc, argv, print_help, own, &o->scene,
                                             &o->vs, 1, &o->dem, &extra);
    if (parsed >= 0)
        return parsed;
    o->runs_given = o->runs > 0;
    o->runs = o->runs_given ? o->runs : 3;
    /* the checks, in the order their messages are given */
    int code = check_operand(o, extra);
    if (code == GO_ON && tp_view_setup_check(&o->vs, "bench") < 0)
        code = TP_EXIT_USAGE;
    if (code == GO_ON)
        code = check_drawing(o);
    if (code == GO_ON)
        code = check_store(o);
    if (code == GO_ON)
        code = check_modes(o);
    if (code == GO_ON)
        code = check_outputs(o);
    return code;
}
