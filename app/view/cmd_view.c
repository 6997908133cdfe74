/*
 * cmd_view.c - `terrapatch view [options] [DEM]`: the entry point. Which DEM (the one given, else
 * the bundled sample), which path it takes (a store, built in the cache for a DEM, or a DEM drawn
 * whole), and the run on the open scene: its start camera, the GL context, the renderer (the
 * patches, or PGM's grid), what is draped and lit, then the frames, headless (headless.c) or in a
 * window (window.c). Its options and help are view_args.c and view_help.c.
 *
 * Each frame: select levels and cull (core), upload the vertex data that changed and draw
 * (renderer.c). Headless frames are complete and deterministic: everything is loaded before the
 * first frame and there is no multisampling.
 */
#define _POSIX_C_SOURCE 200809L
#define _XOPEN_SOURCE 700 /* realpath */
#include "terrapatch.h"
#include "view.h"

#include "imagery_view.h"
#include "view_args.h"
#include "view_shadows.h"

#include "atomic_file.h"
#include "camera_pose.h"
#include "cli.h"
#include "clock.h"
#include "layers.h"
#include "memory.h"
#include "normal_map.h"
#include "output_check.h"
#include "pgm_clip.h"
#include "pgm_render.h"
#include "store_cache.h"
#include "terrain_open.h"
#include "view_bookmarks.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

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

/* --msaa (default: 4 on a GPU, none in software) and the normal map the terrain is shaded from
 * (not PGM's, which shades per vertex), each with a warning when it cannot be had. */
static void open_shading(tp_view_scene* v, const view_options* o, tp_gl_context* ctx,
                         const tp_store_scene* st)
{
    tp_error err = {{0}};
    int samples = o->vs.msaa >= 0 ? o->vs.msaa : tp_gl_context_default_msaa();
    if (tp_gl_context_set_msaa(ctx, samples, &err) < 0)
        tp_cli_warning("--msaa %d: %s", samples, err.message);
    if (o->vs.pgm)
        return;
    tp_normal_source* src = st ? tp_normal_source_store(st->store, v->min_height_m,
                                                         v->max_height_m, &err)
                               : tp_normal_source_terrain(v->dem->terrain, &err);
    v->normals = src ? tp_normal_map_create(src, NULL, &err) : NULL;
    v->normals_settle = o->headless;
    if (!v->normals)
        tp_cli_warning("%s: no normal map (%s): shaded from the vertex normals", v->path,
                       err.message);
}

/* The start view: --camera or --camera-geo, else the default over the whole extent, then
 * --bookmark instead, and --save-bookmark saves it (printing what it did). TP_EXIT_OK, or
 * TP_EXIT_FAILURE after a message. */
static int start_camera(tp_view_scene* v, const view_options* o, tp_store_scene* st, tp_camera* cam)
{
    if (o->resume) { /* the store after its preview: where the preview's view was */
        *cam = o->resume_cam;
        return TP_EXIT_OK;
    }
    if (o->vs.has_camera && !take_georef(v, st)) /* --camera-geo */
        return TP_EXIT_FAILURE;
    if (o->vs.has_camera) {
        if (tp_camera_refuse_degrees("view", v->georef, o->vs.camera_geo, o->vs.camera, v->gt,
                                     v->src_width, v->src_height))
            return TP_EXIT_FAILURE;
        if (!tp_camera_from_option_georef(v->georef, o->vs.camera_geo, o->vs.camera, o->vs.fov_deg,
                                          o->vs.w, o->vs.h, cam, "view"))
            return TP_EXIT_FAILURE;
    } else {
        tp_camera_default_extent(v->gt, v->src_width, v->src_height, v->min_height_m,
                                 v->max_height_m, o->vs.fov_deg, o->vs.w, o->vs.h,
                                 o->vs.vertical_scale, cam);
    }
    if (o->bookmark && (!take_georef(v, st) || !tp_view_bookmark_camera(v, o, o->bookmark, cam)))
        return TP_EXIT_FAILURE;
    /* saved once: by a window's preview (whose start the store's view goes on from), by the
     * store's run of headless frames (whose start is a warm cache's) */
    if (o->save_bookmark && !(o->preview && o->headless)) {
        char line[1024];
        tp_error err = {{0}};
        if (!take_georef(v, st) ||
            !tp_view_bookmark_save(v, o, cam, o->save_bookmark, line, sizeof line, &err)) {
            tp_cli_error("--save-bookmark: %s", err.message);
            return TP_EXIT_FAILURE;
        }
        printf("%s\n", line);
    }
    return TP_EXIT_OK;
}

/* --renderer pgm: v->pgm, the persistent grid over the store's clipmap (*clip; st given) or over
 * the pyramid of a DEM drawn whole (*pyr: its render grid is level 0), drawing instead of the
 * patch renderer. 0 after a message, with nothing of either left to free. */
static int open_pgm(tp_view_scene* v, const view_options* o, tp_store_scene* st,
                    tp_pgm_pyramid* pyr, tp_pgm_clipmap** clip)
{
    tp_error err = {{0}};
    int cols = o->vs.pgm_grid_count ? o->vs.pgm_grid[0][0] : TP_PGM_DEFAULT_COLS;
    int rows = o->vs.pgm_grid_count ? o->vs.pgm_grid[0][1] : TP_PGM_DEFAULT_ROWS;
    if (st) {
        tp_pgm_clipmap* pgm_clip = tp_pgm_clipmap_create(st->store, o->vs.pgm_window, &err);
        /* a window reads on a loader thread (no frame waits for a jump's refill); headless
         * frames read at once, so that each frame is the camera's own */
        if (pgm_clip && !o->headless && !tp_pgm_clipmap_set_async(pgm_clip, &err))
            tp_cli_error("%s (reading on the render thread)", err.message);
        if (pgm_clip)
            v->pgm = tp_pgm_renderer_create_clipmap(pgm_clip, cols, rows, &err);
        if (!v->pgm) {
            tp_cli_error("%s: %s", st->path, err.message);
            tp_pgm_clipmap_destroy(pgm_clip);
            return 0;
        }
        *clip = pgm_clip;
        return 1;
    }
    tp_error why = {{0}};
    uint8_t* valid = NULL;
    const tp_render_grid* g = v->dem->grid;
    tp_status s = tp_pgm_pyramid_from_grid(g->heights, g->width, g->height, g->geotransform, pyr,
                                           &valid, &why);
    if (s != TP_OK)
        tp_error_set(&err, s, "the PGM pyramid: %.400s", why.message);
    else
        v->pgm = tp_pgm_renderer_create(pyr, valid, cols, rows, &err);
    free(valid); /* uploaded */
    if (!v->pgm) {
        tp_cli_error("%s", err.message);
        tp_pgm_pyramid_free(pyr);
        return 0;
    }
    return 1;
}

/* Runs the view on an open scene (either path; st: the store, whose georeference may still be
 * in the making): camera, context, renderer, the frames. */
static int run_view(tp_view_scene* v, view_options* o, tp_render_grid_desc* gd, tp_store_scene* st)
{
    tp_camera cam;
    int code = start_camera(v, o, st, &cam);
    if (code != TP_EXIT_OK)
        return code;
    tp_error err = {{0}};
    tp_gl_context* ctx = o->ctx; /* kept from a preview's run */
    o->ctx = NULL;
    int ok = ctx || (o->headless
                         ? tp_gl_context_create_headless(o->vs.w, o->vs.h, &ctx, &err)
                         : tp_gl_context_create_window(o->vs.w, o->vs.h, "terrapatch", &ctx, &err));
    if (!ok) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    tp_renderer* r =
        v->dem ? tp_renderer_create(v->dem->terrain, &err) : tp_renderer_create_desc(gd, &err);
    if (!r) {
        tp_cli_error("%s", err.message);
        tp_gl_context_destroy(ctx);
        return TP_EXIT_FAILURE;
    }
    /* --renderer pgm: the pyramid (a DEM drawn whole) or the clipmap (a store) and the
     * persistent grid draw instead of r */
    tp_pgm_pyramid pyr;
    memset(&pyr, 0, sizeof pyr);
    tp_pgm_clipmap* pgm_clip = NULL;
    if (o->vs.pgm && !open_pgm(v, o, st, &pyr, &pgm_clip)) {
        tp_renderer_destroy(r);
        tp_gl_context_destroy(ctx);
        return TP_EXIT_FAILURE;
    }
    open_shading(v, o, ctx, st);
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
    /* a preview drapes nothing: imagery, light maps and layers are made for the store */
    if (code == TP_EXIT_OK && st && !o->preview && !open_imagery(v, o, st))
        code = TP_EXIT_FAILURE;
    if (code == TP_EXIT_OK) /* the sun over the map's centre, its cast shadows */
        code = tp_view_shadows_open(v, o, st, &shadow);
    tp_view_layers layers;
    memset(&layers, 0, sizeof layers);
    /* a window always has them (F2); headless frames when asked */
    if (code == TP_EXIT_OK && !o->preview &&
        (o->overlay_count || o->contours || (!o->headless && v->store)))
        code = tp_view_load_layers(v, o, &layers);
    if (code == TP_EXIT_OK)
        code = o->headless && o->preview ? tp_view_headless_preview(v, ctx, r, &cam, o)
               : o->headless             ? tp_view_headless_run(v, ctx, r, &cam, o)
                                         : tp_view_window_run(v, ctx, r, &cam, o);
    tp_view_layers_free(&layers);
    tp_ground_destroy(o->ground);
    o->ground = NULL;
    o->layers = NULL;
    tp_view_imagery_close(v->imagery);
    v->imagery = NULL;
    tp_normal_map_destroy(v->normals);
    v->normals = NULL;
    tp_view_shadows_close(v, &shadow);
    tp_pgm_renderer_destroy(v->pgm);
    v->pgm = NULL;
    tp_pgm_clipmap_destroy(pgm_clip);
    tp_pgm_pyramid_free(&pyr);
    tp_renderer_destroy(r);
    if (o->keep_ctx && code == TP_EXIT_OK)
        o->ctx = ctx; /* the store's run draws in the same window */
    else
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
    if ((code = tp_store_scene_stream(&st, &so)) != TP_EXIT_OK ||
        (o->vs.mesh_tin && (code = tp_store_scene_tins(&st)) != TP_EXIT_OK)) {
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
    tp_cut_set_tins(v.cut, st.tins);
    const tp_tree_geometry* g = tp_tree_get_geometry(st.tree);
    /* as tp_view_setup_warn says for a DEM drawn whole: one leaf is 2^n grid steps */
    double leaf_m = (double)(1 << g->n) * fmin(fabs(v.gt[1]), fabs(v.gt[5]));
    if (o->vs.lod.mode == TP_LOD_DISTANCE && o->vs.lod.maxdist_m > 0 &&
        o->vs.lod.maxdist_m < leaf_m)
        tp_cli_warning("--maxdist %g m is less than one patch width (%.0f m): "
                       "every node farther than %g m is drawn at its coarsest (distances are in "
                       "metres)",
                       o->vs.lod.maxdist_m, leaf_m, o->vs.lod.maxdist_m);
    tp_render_grid_desc gd = {.n = g->n,
                              .width = g->width,
                              .height = g->height,
                              .min_height_m = v.min_height_m,
                              .max_height_m = v.max_height_m,
                              .pool_budget_bytes = o->gpu_memory_mb << 20};
    memcpy(gd.geotransform, v.gt, sizeof gd.geotransform);
    code = run_view(&v, o, &gd, &st);
    tp_view_scene_release(&v);
    tp_store_scene_close(&st);
    return code;
}

/* A DEM's grid of more samples than this is built after a preview of at most as many
 * (store_cache.h, tp_store_cache_begin): docs/PERFORMANCE.md, "First picture of a new DEM". */
#define VIEW_PREVIEW_SAMPLES 300000.0

/* The preview's size: VIEW_PREVIEW_SAMPLES, or TP_VIEW_PREVIEW_SAMPLES (tests draw previews of
 * small DEMs; 0: never a preview). -1 after a message when that is not a number >= 0. */
static double preview_samples(void)
{
    const char* env = getenv("TP_VIEW_PREVIEW_SAMPLES");
    if (!env || !*env)
        return VIEW_PREVIEW_SAMPLES;
    char* end = NULL;
    const double v = strtod(env, &end);
    if (*end != '\0' || !(v >= 0)) {
        tp_cli_error("TP_VIEW_PREVIEW_SAMPLES=%s: expected a number of samples >= 0", env);
        return -1;
    }
    return v;
}

/* A DEM whose store the cache is building (job): the preview store drawn first (headless: one
 * frame; a window: until the store lands), then the store, in the same context (a window from
 * the preview's camera, headless frames as from a warm cache). A window closed during the
 * preview leaves the build to finish first. */
static int view_progressive(const char* store, const char* preview, tp_store_cache_job* job,
                            view_options* o)
{
    o->job = job;
    o->preview = o->keep_ctx = 1;
    o->first.coarsen = tp_store_cache_job_coarsen(job);
    int code = view_store(preview, o);
    if (code == TP_EXIT_OK && !o->refine && !tp_interrupted() && !tp_store_cache_job_done(job))
        tp_cli_note("finishing the store's build (Ctrl-C stops it; it is built again next time)");
    const int built = tp_store_cache_job_finish(job); /* after its message, if it failed */
    o->first.store_ms = tp_clock_ms_since_start();
    o->job = NULL;
    o->preview = o->keep_ctx = 0;
    if (built != TP_EXIT_OK || code != TP_EXIT_OK || !o->refine) {
        tp_gl_context_destroy(o->ctx);
        o->ctx = NULL;
        return built != TP_EXIT_OK ? built : code;
    }
    /* a window goes on from where the preview's view was; headless frames are a warm
     * cache's, from the store's own start camera */
    o->resume = !o->headless;
    return view_store(store, o);
}

int tp_cli_view(int argc, char** argv)
{
    view_options o;
    int code = tp_view_parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    if (!o.path)
        o.path = sample_scene();
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
        char store[4096], preview[4096];
        int temporary = 0;
        tp_store_cache_job* job = NULL;
        const double samples = preview_samples();
        if (samples < 0)
            return TP_EXIT_USAGE;
        code = tp_terrain_store_begin("view", o.path, &o.scene, o.cache_dir, samples, store,
                                      sizeof store, &temporary, preview, sizeof preview, &job);
        if (code == TP_EXIT_OK)
            code = job ? view_progressive(store, preview, job, &o) : view_store(store, &o);
        if (temporary)
            tp_store_cache_remove_temporary(store);
    }
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
