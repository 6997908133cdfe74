/*
 * bench.h - the parts of `terrapatch bench`: its command line (bench_options.c), the frame loop
 * (cmd_bench.c), camera paths (bench_path.c), the table, JSON and CSV it writes
 * (bench_report.c), the static meshes of `export --max-error` (bench_static.c), the sweep's
 * configurations and families (bench_sweep.c), its store families (bench_sweep_store.c) and
 * plot (bench_plot.c), PGM's frames (bench_pgm.c), vertex adding's error (render/stitch_add_error.c) and the medians of both
 * benches' frames (bench_stats.c).
 */
#ifndef TP_APP_BENCH_H
#define TP_APP_BENCH_H

#include <stdint.h>

#include "gl_context.h"
#include "scene.h"
#include "view_options.h"

typedef struct bench_options {
    tp_scene_options scene;
    tp_view_setup vs; /* LoD parameters for the LoD modes, size, field of view; --camera or
                         --camera-geo makes a path of one camera */
    const char* path_name;
    const char* path_file;
    int frames;
    const char* json;
    const char* csv;
    int no_error;      /* skip the (slow) error measurement */
    int stitch_add;    /* --stitch add: Brodersen's vertex-adding crack fix */
    int stitch_add_draw; /* --stitch-add-draw: 0 the renderer's default, 1 sets, 2 five, 3 both
                            (each --stitch add configuration twice: sets, then five) */
    double speed_mps;  /* path flights: a lead-in frame 1/30 s earlier at this speed; 0: none */
    int sweep;         /* a grid of LoD parameters instead of the three default configurations */
    const char* plot;  /* --sweep: the plot (PNG); default: the CSV's name with .png */
    char plot_buf[4096];
    int is_static;     /* --static: meshes of export --max-error for max_errors */
    double max_errors[16];
    int max_error_count;
    const char* dem;
    /* stores (.tpt, bench_store.c) */
    int memory_mb;     /* --memory: the stream's budget of decoded nodes; default 1024 */
    int segments;      /* --segments: stretches of continuous flight; default 4 */
    int error_every;   /* --error-every N: measure the error on every N-th frame; default 1 */
    double error_posts; /* --error-posts N: a store's measured frame compares the leaves of at
                           most about N posts (tp_cut_measure_error's sampling); 0: every leaf */
    int realtime;      /* --realtime: the camera moves by the time that really passed */
    int no_prefetch;   /* --no-prefetch: the stream gets no prefetch cut (what it costs) */
    int no_cut_thread; /* --no-cut-thread: each frame's cut selected on the render thread */
    const char* imagery; /* --imagery FILE.tpi: a configuration with imagery (bench_store.c) */
    int clip_blocks;   /* --clip-blocks */
    int imagery_mode;  /* --imagery-mode: 0 clipmap, 1 blocks (tp_imagery_mode), 2 both */
    const char* light; /* --light FILE.tpl: a configuration with the day's streamed light */
    /* --static */
    int compare;       /* --compare: delatin and martini from npm beside the TIN */
    int runs;          /* --runs: timed runs per TIN (median); default 3 */
    int runs_given;
} bench_options;

/* `terrapatch bench`'s command line into *o (defaults first; o->dem borrows argv): -1 to run,
 * else the exit status to return at once, after the help (--help: TP_EXIT_OK) or one message
 * (TP_EXIT_USAGE for a bad option, a missing or extra operand, or options that do not go
 * together). */
int tp_bench_parse_options(int argc, char** argv, bench_options* o);

typedef struct frame_row {
    double select_ms, upload_ms, draw_ms, frame_ms;
    size_t triangles, gpu_bytes;
    int draw_calls, patches, uploads;
    int draws;               /* the draws submitted, each of a multi-draw's counted */
    size_t index_gpu_bytes, index_cpu_bytes; /* tp_render_stats' */
    double max_m, rms_m, max_px, rms_px;
    double uncovered_share;  /* PGM, measured frames: posts in view no drawn triangle covers, as
                                a share of the posts in view (tp_pgm_error); NaN on PGM's
                                unmeasured frames; 0 for the patch renderer (it covers them) */
    size_t oracle_triangles; /* error mode: triangles if every patch were at its coarsest level
                                that measures <= tau (see oracle_triangles()) */
    int oracle_patches;      /* patches that could be coarser */
    int tin_nodes;           /* --sweep's store+tin family: drawn nodes that drew a TIN */
    int substituted;         /* --sweep's store families: nodes drawn in place of finer ones */
} frame_row;

typedef struct config_result {
    tp_lod_params lod;  /* resolved */
    char label[64];
    frame_row* rows;
    double fps_median, frame_ms, cpu_ms, draw_ms, triangles, draw_calls, uploads;
    double oracle_triangles, oracle_patches; /* medians; error mode with the error measured */
    size_t gpu_bytes;
    double max_px, rms_px, max_m, rms_m; /* over all frames: max of maxima, RMS of RMS */
    int pareto;                          /* --sweep: on its family's fps/max-error Pareto front */
    int pgm_cols, pgm_rows;              /* --renderer pgm: a persistent grid (bench_pgm.c); 0:
                                            the patch renderer at lod */
    int stitch_add;                      /* the patch renderer with --stitch add */
    int stitch_add_five;                 /* drawn as five regions (--stitch-add-draw five) */
    double draws;                        /* median of frame_row's */
    size_t index_gpu_bytes, index_cpu_bytes; /* maxima over the frames */
    double uncovered_share;              /* PGM: mean of the measured frames' shares; 0 for
                                            the patch renderer (it covers every post) */
    int store;                           /* --sweep: 1 the DEM's store drawn through its cut
                                            (lattice nodes), 2 the same with TIN nodes (--mesh
                                            tin); 0 the DEM drawn whole (the other families) */
    double tin_share;                    /* store 2: drawn nodes that drew a TIN, share */
} config_result;

/* Both benches' flight clock (frames a second): a path flight's lead-in frame is
 * 1 / TP_BENCH_FRAME_HZ s before its timed one; a store's flight advances speed /
 * TP_BENCH_FRAME_HZ metres a frame, and its stream and clipmaps estimate motion on that clock. */
#define TP_BENCH_FRAME_HZ 30.0

/* What every configuration of a run shares. */
typedef struct bench_run {
    const bench_options* o;
    tp_scene* sc;
    tp_gl_context* ctx;
    const tp_camera* cams; /* --path-file, or NULL */
    const tp_camera* fixed; /* --camera, or NULL */
    int frames;
    double lead_da; /* path parameter from the lead-in frame to the timed one; 0: none */
    int msaa;       /* samples a pixel (--msaa; 0: none) */
    struct tp_bench_sweep_store* store; /* --sweep: the DEM's store (its store families) */
} bench_run;

struct tp_view_imagery;
struct tp_store_scene;
struct tp_cut;
struct tp_renderer;
/* The last frame of a flight with imagery (bench_store.c), drawn with the flown clipmap (or
 * blocks, mode: a tp_imagery_mode) settled at cam and again with a fresh one opened from path
 * and settled there: the pixels that differ (0 when the updates left nothing stale), or -1
 * when the fresh one cannot be made (bench_imagery.c). */
long tp_bench_imagery_diff(struct tp_view_imagery* flown, const char* path,
                           const struct tp_store_scene* sc, const struct tp_cut* cut,
                           struct tp_renderer* r, tp_gl_context* ctx, const tp_camera* cam,
                           int mode, int clip_blocks);

/* Length (metres) of the named path (low, high, orbit). */
double tp_bench_path_length(const tp_scene* sc, const bench_options* o);

/* Camera of timed frame i of the run; returns 1 and writes *lead, the lead-in camera 1/30 s
 * earlier, when there is one. */
int tp_bench_frame_camera(const bench_run* b, int i, tp_camera* cam, tp_camera* lead);

/* Cameras from --path-file: "LAT,LON,H,YAW,PITCH" per line (or "proj E,N,H,YAW,PITCH"); 0
 * after a message naming the file and line. *out is malloc'ed. */
int tp_bench_read_path_file(const tp_scene* sc, const bench_options* o, tp_camera** out,
                            int* count);

/* The table on stdout; best is the error-mode configuration at the run's tau. */
void tp_bench_print_table(const bench_run* b, const char* renderer_name, const config_result* c,
                          int nc, int best);

/* The JSON summary: the headline keys are those of the error mode at the run's tau (best),
 * with the full-resolution baseline and every configuration. Atomic; 0 after a message. */
int tp_bench_write_json(const bench_run* b, const char* renderer_name, const config_result* c,
                        int nc, const config_result* best);

/* One CSV row per frame and configuration / per --sweep configuration. Atomic; 0 after a
 * message. */
int tp_bench_write_frames_csv(const bench_options* o, const config_result* c, int nc, int frames);
int tp_bench_write_sweep_csv(const bench_options* o, const config_result* c, int nc);

/* `bench --static --max-error M1,M2,...`: for each bound, the static mesh of
 * `export --max-error` (levels selected, mesh built and measured, nothing written): triangles,
 * points, build time, measured maximum and RMS error against the source samples; then the
 * error-bounded TIN (tp_tin_build) on the render grid, and with o->compare delatin, martini and
 * martini lowered (tools/tin_compare.sh) beside it on the largest void-free (2^k+1)^2 window,
 * every TIN measured by tp_tin_measure. Prints a table; o->json / o->csv outputs when non-NULL.
 * Returns TP_EXIT_*. */
int tp_bench_static(const tp_scene* sc, const bench_options* o);

/* The npm meshers of `bench --static --compare` (bench_npm.c), through tools/tin_compare.sh
 * ($TP_TIN_COMPARE, else the source tree's tools/, compiled in as TP_TOOLS_DIR). */
typedef struct tp_npm {
    char script[4096];
    char dir[4096];  /* a private temporary folder (mkdtemp under $TMPDIR or /tmp) */
    char grid[4200]; /* dir/grid.f32: the heights the meshers read */
    const float* z;  /* borrowed: w x h, no void */
    int w, h;
} tp_npm;

typedef struct tp_npm_mesh {
    double median_ms, tile_ms; /* the meshing's median over the runs; martini's createTile part */
    double peak_mib, base_mib; /* the node process's peak RSS; its RSS before the first run */
    size_t vertex_count, triangle_count;
    float* vertices;           /* x, y, height (from the grid) per vertex */
    uint32_t* triangles;
} tp_npm_mesh;

/* Finds the script, runs its install step (node, npm, the network once) and writes the grid;
 * 0 after messages naming what is missing (and nothing left behind). */
int tp_npm_open(tp_npm* n, const float* z, int w, int h);
/* Runs mesher ("delatin" or "martini") at threshold_m, runs times in one node process, and
 * reads its mesh back; 0 after a message. */
int tp_npm_run(tp_npm* n, const char* mesher, double threshold_m, int runs, tp_npm_mesh* out);
void tp_npm_mesh_free(tp_npm_mesh* m);
/* Removes the grid file and the folder. */
void tp_npm_close(tp_npm* n);

/* `bench X.tpt`: flights over a built store through the hierarchy with streaming (the error
 * mode at --tau, then the distance mode), a table, --json and --csv. Returns TP_EXIT_*. */
int tp_bench_store(const bench_options* o);

/* bench_sweep.c: the families a --sweep compares, each with its own Pareto front: the patch
 * renderer's distance and error modes with vertex moving, both with --stitch add, PGM, and the
 * error mode over the DEM's store with lattice and with TIN nodes. */
typedef enum tp_bench_family {
    TP_FAMILY_FULL,         /* full resolution (the baseline; no front) */
    TP_FAMILY_DISTANCE,     /* distance mode, vertex moving */
    TP_FAMILY_ERROR,        /* error mode, vertex moving */
    TP_FAMILY_DISTANCE_ADD, /* distance mode, --stitch add */
    TP_FAMILY_ERROR_ADD,    /* error mode, --stitch add */
    TP_FAMILY_PGM,          /* Persistent Grid Mapping, one configuration per grid */
    TP_FAMILY_STORE,        /* the DEM's store, error mode, lattice nodes (vertex moving) */
    TP_FAMILY_STORE_TIN,    /* the same with TIN nodes (--mesh tin) */
    TP_FAMILY_COUNT
} tp_bench_family;

/* The family of a configuration, and its name in the CSV, JSON and plot ("full", "distance",
 * "error", "distance+add", "error+add", "pgm", "store", "store+tin"). */
tp_bench_family tp_bench_family_of(const config_result* c);
const char* tp_bench_family_name(tp_bench_family f);

/* The configurations of a --sweep (calloc'ed; NULL when out of memory): full resolution; the
 * distance grid (mindist x maxdist in patch widths x exp) and the error mode's taus (with
 * base's tau added when off the grid: *best, the headline) with vertex moving; the same taus
 * and the default distance configuration with --stitch add; PGM with --pgm-grid's grids, else
 * the sweep's list; then the grid's taus over the DEM's store, lattice nodes, and again with
 * TIN nodes. Labels filled. */
config_result* tp_bench_sweep_configs(const bench_run* b, const tp_lod_params* base, int* count,
                                      int* best);

/* A configuration's label for the table ("error tau=1", "distance+add 480/11520/1",
 * "pgm 150x600", "store+tin tau=1"). */
void tp_bench_label(config_result* c);

/* Marks the configurations no other configuration of the same family beats in both fps and
 * measured maximum screen error (c[0], full resolution, is never on a front). */
void tp_bench_mark_pareto(config_result* c, int nc);

/* Plots the sweep's configurations c[1..nc-1] (c[0]: full resolution, a line) into png (see
 * tp_bench_plot). Returns 1, or 0 after a message. */
int tp_bench_sweep_plot(const config_result* c, int nc, const char* png, const char* title);

/* One configuration of a --sweep, as plotted. */
typedef struct tp_bench_point {
    tp_bench_family family;
    double tau_px;          /* the error families' label */
    int pgm_cols, pgm_rows; /* PGM's label */
    double fps, max_px, rms_px;
    int pareto; /* on its family's front of fps against measured maximum screen error */
} tp_bench_point;

/* Plots a --sweep with gnuplot into png: fps against measured maximum and RMS screen error
 * (log scales; an error of 0 px is drawn at 0.01 px; a point with a non-finite error is left
 * out), each family's configurations and Pareto front, full resolution as a line at full_fps.
 * gnuplot draws into a private temporary folder (mkdtemp) beside png, removed afterwards; the PNG
 * then goes through tp_file_write. Returns 1, or 0 after a one-line message. */
int tp_bench_plot(const tp_bench_point* pts, int count, const char* png, const char* title,
                  double full_fps);

/* bench_pgm.c: the run's frames drawn by Persistent Grid Mapping with c's grid (pgm_render.h,
 * a pyramid of the render grid made for it), the same cameras and lead-in frames as the patch
 * configurations; each row: frame time (setup + draw + glFinish), CPU ms (the frame's setup),
 * triangles, GPU bytes, and on every --error-every-th frame tp_pgm_measure_error's error (NaN
 * on the others). Returns TP_EXIT_*. */
int tp_bench_pgm_frames(const bench_run* b, config_result* c, const char* progress);
/* The errors of c's summary over its measured frames only (max of maxima, RMS of RMS, mean
 * uncovered share). */
void tp_bench_pgm_errors(config_result* c, int frames);

/* bench_sweep_store.c: the DEM's store for --sweep's store families, found in or built into
 * the cache as `view DEM` builds it (tp_terrain_store, its progress on stderr) and opened; its
 * grid must be the DEM's render grid (the run's cameras are in it). TP_EXIT_OK and *out, else
 * the exit status after one line. Close with tp_bench_sweep_store_close (accepts NULL). */
typedef struct tp_bench_sweep_store tp_bench_sweep_store;
int tp_bench_sweep_store_open(const bench_options* o, const tp_scene* scene,
                              tp_bench_sweep_store** out);
void tp_bench_sweep_store_close(tp_bench_sweep_store* s);
/* The run's frames (cameras, lead-in frames) for a store configuration c (c->store: 1 lattice
 * nodes, 2 TIN nodes; c->lod the error mode at its tau) over b->store, from a cold stream,
 * renderer and cut: each frame settled first (untimed: its nodes loaded, its TIN levels
 * built), then timed (the cut on the render thread, the stream's and normal map's frames, the
 * draw to glFinish), its screen error measured by tp_store_scene_measure (--error-posts; no
 * vertical error: NaN); c->rows and the summary filled. Returns TP_EXIT_*. */
int tp_bench_sweep_store_frames(const bench_run* b, config_result* c, const char* progress);

/* A configuration's medians and errors over its n rows (cmd_bench.c). */
void tp_bench_summarize(config_result* c, int n);

/* The median of v[0..n-1] (n >= 1); sorts v. */
double tp_bench_median(double* v, int n);
/* The mean of v[0..n) (NaN when n is 0). */
double tp_bench_mean(const double* v, int n);

/* VmRSS and RssAnon of this process, MB (10^6 bytes); NaN when not readable. */
void tp_bench_read_rss(double* rss_mb, double* anon_mb);

/* A run's progress on stderr (bench_stats.c), for both benches: frame (1-based) of frames and
 * what it measured ("12.3 ms, 4567 triangles"). On a terminal one line redrawn ('\r'); else
 * (a log, a pipe) one line at each tenth of the frames and at the last, never thousands of
 * '\r'-joined updates on one line. tp_bench_progress_end ends a terminal's line. */
void tp_bench_progress(const char* progress, int frame, int frames, const char* what);
void tp_bench_progress_end(void);
/* The 99th percentile (nearest rank) of v[0..n-1], sorted (n >= 1). */
double tp_bench_p99(const double* v, int n);
/* One column of a run's frames: v[i] = expr for i < n, with r = &rows[i] (of type row_type). */
#define TP_BENCH_COLUMN(v, row_type, rows, n, expr)                                                \
    do {                                                                                           \
        for (int i_ = 0; i_ < (n); i_++) {                                                         \
            const row_type* r = &(rows)[i_];                                                       \
            (v)[i_] = (double)(expr);                                                              \
        }                                                                                          \
    } while (0)

#endif
