/*
 * headless.c - `terrapatch view --headless` (see view.h): the frames drawn offscreen, complete
 * and deterministic (everything is loaded before each frame, no multisampling), then what they
 * leave: the screenshot, the measure, the picks, the statistics, and a warning when the frame
 * shows nothing.
 */
#include "view.h"

#include "clock.h"

#include "cli.h"
#include "hud.h"
#include "hud_text.h"
#include "layers.h"
#include "overlay.h"
#include "pick.h"
#include "store_cache.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>

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

/* The HUD's text of a frame drawn from t0 (tp_clock_ms) with the grid every grid_m metres. */
static void hud_text(tp_view_scene* v, const tp_camera* cam, const view_options* o,
                     const frame_result* fr, double t0, double grid_m, char* text, size_t cap)
{
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
                       .grid_m = grid_m,
                       .details = o->hud_details};
    tp_view_hud_text(v, cam, &o->vs.lod, fr, &me, &hs, text, cap);
}

/* What the last frame (fr) leaves: warnings, the screenshot, the measure (measured: 1 done, -1
 * failed, measure_line what it says), the picks, the statistics. An exit code. */
static int outputs(tp_view_scene* v, tp_gl_context* ctx, const tp_camera* cam,
                   const view_options* o, const frame_result* fr, int measured,
                   const char* measure_line)
{
    int code = TP_EXIT_OK;
    if (!warn_if_below_ground(v, cam, o))
        warn_if_empty(v, fr);
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
            printf("pick %.1f,%.1f: E %.3f N %.3f height %.3f m\n", o->pick[i][0], o->pick[i][1],
                   g[0], g[1], g[2]);
        } else {
            printf("pick %.1f,%.1f: no ground\n", o->pick[i][0], o->pick[i][1]);
        }
    }
    if (o->stats_json && code == TP_EXIT_OK) {
        double max_m, rms_m, max_px, rms_px;
        tp_view_measured_how how;
        tp_view_scene_measure(v, cam, TP_STORE_MEASURE_POSTS, &max_m, &rms_m, &max_px, &rms_px,
                              &how);
        tp_error_measure em = {.max_error_m = max_m, .rms_error_m = rms_m};
        if (!tp_view_write_stats(o->stats_json, fr, how.cut ? NULL : &em, max_px, rms_px, &how,
                                 v->n + 1, cam, &o->first))
            code = TP_EXIT_FAILURE;
    }
    return code;
}

/* Records the first picture, once drawn, into o->first: finished (glFinish), timed from the
 * process's start. */
static void first_drawn(const tp_view_scene* v, view_options* o, int coarsen)
{
    glFinish();
    o->first.known = 1;
    o->first.ms = tp_clock_ms_since_start();
    o->first.preview = o->preview;
    o->first.coarsen = coarsen;
    o->first.dem = v->dem != NULL;
    o->first.build_running = o->job && !tp_store_cache_job_done(o->job);
    if (!o->job)
        o->first.store_ms = -1;
}

int tp_view_headless_preview(tp_view_scene* v, tp_gl_context* ctx, tp_renderer* r,
                             const tp_camera* cam, view_options* o)
{
    frame_result fr = {0};
    tp_view_scene_set_vertical_scale(v, o->render.exaggeration);
    tp_view_scene_settle(v, cam, &o->vs.lod, 120);
    tp_gl_context_begin_frame(ctx);
    tp_render_settings rs = o->render;
    rs.grid_m = tp_view_grid_spacing(v, cam, o->render.grid_m);
    tp_view_frame(v, r, cam, &rs, &o->vs.lod, 0, &fr);
    tp_gl_context_end_frame(ctx);
    first_drawn(v, o, o->first.coarsen);
    tp_store_cache_job_start(o->job);
    o->resume_cam = *cam;
    o->refine = 1;
    return TP_EXIT_OK;
}

int tp_view_headless_run(tp_view_scene* v, tp_gl_context* ctx, tp_renderer* r, const tp_camera* cam,
                         view_options* o)
{
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
        fr.msaa = tp_gl_context_msaa(ctx);
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
            hud_text(v, cam, o, &fr, t0, rs.grid_m, text, sizeof text);
            ov.hud_text = text;
        }
        tp_view_overlay_draw(hud, v, cam, &ov);
        tp_gl_context_end_frame(ctx);
        if (!o->first.known) /* the view's first picture (a preview's run times its own) */
            first_drawn(v, o, 0);
    }
    tp_hud_destroy(hud);
    return outputs(v, ctx, cam, o, &fr, measured, measure_line);
}
