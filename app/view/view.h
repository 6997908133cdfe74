/*
 * view.h - the parts of `terrapatch view` that its files share: the parsed options, one frame
 * (select, upload, draw) and its statistics, and the two ways to run it.
 *
 *   cmd_view.c   the entry point: which DEM, store or drawn whole, the run on the open scene
 *   view_args.c  the options read and checked (view_args.h); view_help.c its --help
 *   headless.c   the headless run: the frames offscreen, then what they leave
 *   window.c     the interactive frame loop (input.c, navigate.c, pick.c, overlay.c)
 *   frame.c      one frame, screenshots, the statistics JSON, the texture
 *   render/      patches to the GPU (renderer.h; hud.c draws text, gl_context.h owns the context)
 */
#ifndef TP_APP_VIEW_H
#define TP_APP_VIEW_H

#include "gl_context.h"
#include "navigate.h"
#include "renderer.h"
#include "scene.h"
#include "view_options.h"
#include "view_scene.h"
#include "clipmap.h"
#include "sun_view.h"

/* The first picture of a view (cmd_view.c): when it was drawn, and from what. A DEM whose store
 * the cache must build first draws a preview of it (a coarser store, store_cache.h) while the
 * store is built on a thread, then the store once it lands. */
typedef struct tp_view_first {
    int known;         /* a frame was drawn: the fields below are set */
    double ms;         /* it was finished (glFinish), ms since the process started */
    int preview;       /* drawn from the preview store, every coarsen-th post */
    int dem;           /* drawn from a DEM drawn whole (else a store) */
    int coarsen;
    int build_running; /* the store's build had not ended when it was drawn */
    double store_ms;   /* the store's build ended (< 0: no build ran after the first frame) */
} tp_view_first;

struct tp_store_cache_job;

typedef struct view_options {
    tp_scene_options scene;
    tp_view_setup vs; /* level of detail, camera, field of view, size */
    tp_render_settings render;
    int headless, frames, no_hud, hud;
    int hud_details; /* --hud-details: the HUD's engineering lines (F4) */
    const char* screenshot;
    const char* texture;
    const char* imagery;             /* --imagery FILE.tpi (stores) */
    int no_imagery;                  /* --no-imagery */
    int clip_blocks;                 /* --clip-blocks N (0: the clipmap's default) */
    const char* sun_date;            /* --sun-date YYYY-MM-DD */
    const char* sun_time;            /* --sun-time HH:MM[:SS][zone] */
    tp_sun_time sun_when;            /* both parsed */
    tp_view_sun sun;                 /* the sun once the georeference is there */
    int no_cast_shadows;             /* --no-cast-shadows */
    const char* light;               /* --light FILE.tpl (stores; view_shadows.h) */
    int imagery_mode;                /* --imagery-mode: a tp_imagery_mode (imagery_view.h) */
    int has_measure;
    double measure[4]; /* E1, N1, E2, N2 */
    double pick[16][2]; /* --pick X,Y pixels */
    int pick_count;
    const char* stats_json;
    const char* path;
    size_t memory_mb, gpu_memory_mb; /* --memory, --gpu-memory (stores) */
    const char* cache_dir;           /* --cache-dir */
    int old_path;                    /* the DEM is drawn whole (see --help) */
    int patch_given;
    const char* bookmark;            /* --bookmark NAME: start from that view */
    const char* save_bookmark;       /* --save-bookmark NAME: save the start view as NAME */
    const char* bookmarks_path;      /* --bookmarks FILE (default: view_bookmarks.h) */
    /* the planner's layers (layers.h) */
    const char* overlays[8];         /* --overlay FILE, repeatable */
    int overlay_count;
    int contours;                    /* --contours M given */
    double contours_m;               /* its interval (0: chosen from the relief) */
    struct tp_view_layers* layers;   /* loaded before the frames (run_view), or NULL */
    struct tp_ground* ground;        /* the layers' ground (run_view owns it), or NULL */
    /* a preview drawn while the store is built (cmd_view.c, view_progressive) */
    struct tp_store_cache_job* job;  /* the store's build: started after the first frame */
    int preview;                     /* this run draws the preview: headless, one frame and no
                                        outputs; a window, until the job has ended */
    int refine;                      /* set by a preview's run: go on with the store */
    int resume;                      /* the run starts from resume_cam (the preview's camera) */
    tp_camera resume_cam;
    tp_gl_context* ctx;              /* a context kept from the preview's run to the store's */
    int keep_ctx;
    struct {                         /* the window's state kept from the preview's run */
        int set, shots, exports, frozen, show_hud, show_details, show_help;
        tp_nav nav;                  /* orbit or flight, and the view Home returns to */
    } window_keep;
    tp_view_first first;
} view_options;

typedef struct frame_result {
    tp_frame_stats core;      /* a cut: drawn nodes per level, triangles, culled nodes */
    tp_render_stats render;
    double select_ms;
    double grid_m;            /* the map grid's spacing drawn (tp_view_grid_spacing; 0: none) */
    int store;                /* the frame of a store: the fields below are set */
    int nodes_drawn, substituted;
    int nodes_per_scale[TP_TREE_MAX_SCALES]; /* drawn nodes by scale (0: leaves) */
    int add_sides, moved_sides; /* tp_cut_stats: sides taking / moving vertices */
    int mesh_tin;               /* --mesh tin: the fields below are set */
    int tin_nodes;              /* drawn nodes that draw a TIN */
    size_t tin_bytes, tin_levels; /* the TINs held (tp_tin_cache_stats) */
    double bound_max_px;        /* largest projected bound of a drawn node (error mode) */
    int bound_near_nodes;       /* drawn nodes at the eye: their bound covers what is drawn of
                                   them, in front of the near plane (tp_cut_node.near_plane) */
    tp_stream_stats stream;   /* resident MB, pending loads */
    int imagery;              /* imagery drawn: clip is set */
    tp_clipmap_stats clip;
    int light_source;         /* cast shadows drawn: TP_VIEW_LIGHT_* */
    double light_tau;         /* streamed: the time in the file's day, steps (0 .. 255) */
    tp_clipmap_stats light_clip; /* streamed: the light's clipmap */
    int normals;              /* shaded from the normal map (normal_map.h): its clipmap's */
    tp_clipmap_stats normal_clip;
    int msaa;                 /* samples a pixel (0: none) */
    double shadow_ms;         /* window: its last computation */
    int shadow_posts;         /* window: posts a side */
    int pgm_cols, pgm_rows;   /* --renderer pgm: the persistent grid (0: the patch renderer) */
} frame_result;

#define TP_VIEW_LIGHT_NONE 0
#define TP_VIEW_LIGHT_STREAMED 1 /* the day's light map (light_view.h) */
#define TP_VIEW_LIGHT_WINDOW 2   /* computed over a window (shadow_view.h) */

/* view_layers.c: the --overlay files read and draped on the full-resolution ground of the
 * store (o->ground, o->layers set to layers). TP_EXIT_OK, or one line naming the file and
 * TP_EXIT_FAILURE. */
struct tp_view_layers;
int tp_view_load_layers(tp_view_scene* v, view_options* o, struct tp_view_layers* layers);

/* Contours (layers.h) around the point cam looks at (else the DEM's centre) into o->layers:
 * --contours at the first frame, F2 in the window. line gets what happened. */
void tp_view_contours_at_centre(tp_view_scene* v, const tp_camera* cam, view_options* o,
                                double interval_m, char* line, size_t cap);

/* One frame: select levels and cull (unless frozen), upload, draw, statistics. */
void tp_view_frame(tp_view_scene* v, tp_renderer* r, const tp_camera* cam,
                   const tp_render_settings* render, const tp_lod_params* lod, int frozen,
                   frame_result* out);

/* Writes the frame as a PNG; 0 after a message naming the path. */
int tp_view_screenshot(tp_gl_context* ctx, const char* path);

/* Writes the statistics JSON (atomically); 0 after a message. */
int tp_view_write_stats(const char* path, const frame_result* f, const tp_error_measure* em,
                        double max_px, double rms_px, const tp_view_measured_how* how,
                        int levels, const tp_camera* cam, const tp_view_first* first);
/* em NULL: no metre errors (a store's frame). how (may be NULL): what the measure covered (a
 * store's cut: error_samples, error_leaves..., error_leaf_share; PGM: error_post_share).
 * first: the view's first picture ("first_frame"), or NULL. */

/* headless.c: the preview's first frame (o->preview): drawn once for cam, finished, timed into
 * o->first; then the store's build is started. Returns an exit code. */
int tp_view_headless_preview(tp_view_scene* v, tp_gl_context* ctx, tp_renderer* r,
                             const tp_camera* cam, view_options* o);

/* Builds the texture of --texture for the render grid and hands it to the renderer; 0 after a
 * message. */
int tp_view_load_texture(const tp_scene* sc, tp_renderer* r, const char* path);

/* headless.c: o->frames frames drawn offscreen for cam (each store node the view wants loaded
 * first), then what the last one leaves: --screenshot, --measure, --pick, --stats-json, and a
 * warning when it shows no terrain. Returns an exit code. */
int tp_view_headless_run(tp_view_scene* v, tp_gl_context* ctx, tp_renderer* r,
                         const tp_camera* cam, view_options* o);

/* The interactive viewer: the frame loop of a window until Esc or close. Returns an exit code. */
int tp_view_window_run(tp_view_scene* v, tp_gl_context* ctx, tp_renderer* r, tp_camera* cam,
                       view_options* o);

#endif
