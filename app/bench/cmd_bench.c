/*
 * cmd_bench.c - `terrapatch bench DEM [options]`: speed against error, measured the same way for
 * every configuration in one run: headless (EGL) frames along a deterministic camera path, for
 * full resolution (frustum-culled) and each LoD mode, with per-frame CPU stages, draw time,
 * triangles, draw calls, GPU bytes and the measured error of the frame's geometry. The command
 * line is bench_options.c's; a store's flights are bench_store.c's.
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
#include "normal_map.h"
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

#define MEDIAN_OF(expr) TP_BENCH_COLUMN(v, frame_row, c->rows, n, expr)

void tp_bench_summarize(config_result* c, int n)
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
    if (c->store)
        return tp_bench_sweep_store_frames(b, c, progress);
    if (c->pgm_cols) {
        int code = tp_bench_pgm_frames(b, c, progress);
        if (code == TP_EXIT_OK) {
            tp_bench_summarize(c, b->frames);
            tp_bench_pgm_errors(c, b->frames);
        }
        return code;
    }
    tp_error err = {{0}};
    int frames = b->frames;
    c->rows = calloc((size_t)frames, sizeof *c->rows);
    tp_renderer* r = tp_renderer_create(b->sc->terrain, &err);
    tp_selection* sel = NULL;
    tp_normal_source* src = r ? tp_normal_source_terrain(b->sc->terrain, &err) : NULL;
    /* shaded from the normal map as the viewer shades (normal_map.h) */
    tp_normal_map* nm = src ? tp_normal_map_create(src, NULL, &err) : NULL;
    if (!c->rows || !nm || tp_selection_create(b->sc->terrain, &sel, &err) != TP_OK) {
        tp_cli_error("%s", nm ? "out of memory" : err.message);
        tp_normal_map_destroy(nm);
        tp_renderer_destroy(r);
        return TP_EXIT_FAILURE;
    }
    double zr[2] = {b->sc->info.min_height_m, b->sc->info.max_height_m};
    tp_render_settings rs;
    tp_render_settings_default(&rs);
    rs.stitch_add = c->stitch_add;
    rs.stitch_add_five = c->stitch_add && c->stitch_add_five;
    if (c->stitch_add && tp_terrain_prepare_stitch_add(b->sc->terrain, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        tp_selection_destroy(sel);
        tp_normal_map_destroy(nm);
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
            tp_normal_map_frame(nm, r, &lead, zr[0], zr[1], 0, NULL);
            tp_renderer_draw(r, sel, &lead, &rs, 1, &st);
            tp_gl_context_end_frame(b->ctx);
        }
        frame_row* row = &c->rows[i];
        tp_gl_context_begin_frame(b->ctx);
        double t0 = tp_clock_ms();
        tp_selection_update(sel, &cam, &c->lod, &err);
        tp_normal_map_frame(nm, r, &cam, zr[0], zr[1], 0, NULL);
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
                tp_normal_map_destroy(nm);
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
    tp_bench_summarize(c, frames);
    tp_selection_destroy(sel);
    tp_normal_map_destroy(nm);
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
    int code = tp_bench_parse_options(argc, argv, &o);
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
        b.lead_da = o.speed_mps / TP_BENCH_FRAME_HZ / tp_bench_path_length(&sc, &o);
    tp_error err = {{0}};
    if (!tp_gl_context_create_headless(o.vs.w, o.vs.h, &b.ctx, &err)) {
        tp_cli_error("%s", err.message);
        free(cams);
        tp_scene_free(&sc);
        return TP_EXIT_FAILURE;
    }
    int samples = o.vs.msaa >= 0 ? o.vs.msaa : tp_gl_context_default_msaa();
    if ((b.msaa = tp_gl_context_set_msaa(b.ctx, samples, &err)) < 0) {
        tp_cli_warning("--msaa %d: %s", samples, err.message);
        b.msaa = 0;
    }
    const char* renderer_name = (const char*)glGetString(GL_RENDERER);
    renderer_name = renderer_name ? renderer_name : "?";
    int nc = 0, best = 0;
    config_result* c = make_configs(&b, &nc, &best);
    code = c ? TP_EXIT_OK : TP_EXIT_FAILURE;
    if (!c)
        tp_cli_error("out of memory");
    else if (o.sweep) /* the store families' store, built before the first frame */
        code = tp_bench_sweep_store_open(&o, &sc, &b.store);
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
    tp_bench_sweep_store_close(b.store);
    tp_gl_context_destroy(b.ctx);
    tp_scene_free(&sc);
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
