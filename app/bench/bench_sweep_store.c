/*
 * bench_sweep_store.c - the store families of `bench DEM --sweep` (see bench.h): the DEM's
 * store, found in or built into the cache exactly as `view DEM` builds it (tp_terrain_store:
 * the same key, the same progress lines on stderr), drawn through its cut in the error mode with
 * lattice nodes ("store") and with TIN nodes ("store+tin", as `--mesh tin` draws them), on the
 * run's cameras and frames (lead-in frames included).
 *
 * Every frame first settles, untimed: the cut is selected and the stream left to load until the
 * cut asks for nothing and nothing is pending, and every TIN level the cut would draw is built
 * (as a viewer that has stopped there sees it; the DEM families hold the whole DEM too). The
 * timed frame is then the cut's selection on the render thread, the stream's frame, the normal
 * map's and the draw until glFinish (no cut thread: every family's selection is in its CPU
 * time). Its error, outside the timed part, is tp_store_scene_measure's: tp_cut_measure_error,
 * the definition of tp_selection_measure_screen_error (every post in view against the drawn
 * surface vertically above or below it), over the leaves of at most about --error-posts posts.
 */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

#include "clock.h"
#include "cli.h"
#include "cut_worker.h"
#include "normal_map.h"
#include "renderer.h"
#include "store_scene.h"
#include "terrain_open.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define SETTLE_MAX_MS 20000.0

struct tp_bench_sweep_store {
    tp_store_scene sc;
    char path[4096];
    int temporary; /* built in a temporary folder (the cache could not be written): removed */
};

int tp_bench_sweep_store_open(const bench_options* o, const tp_scene* scene,
                              tp_bench_sweep_store** out)
{
    *out = NULL;
    tp_bench_sweep_store* s = calloc(1, sizeof *s);
    if (!s) {
        tp_cli_error("out of memory");
        return TP_EXIT_FAILURE;
    }
    int code = tp_terrain_store("bench", o->dem, &o->scene, NULL, s->path, sizeof s->path,
                                &s->temporary);
    if (code == TP_EXIT_OK)
        code = tp_store_scene_open(s->path, &s->sc);
    if (code != TP_EXIT_OK) {
        tp_bench_sweep_store_close(s);
        return code;
    }
    /* the run's cameras are in the DEM's render grid: the store's must be the same grid */
    const double* a = scene->info.geotransform;
    const double* g = s->sc.tree_info.geotransform;
    double tol = 1e-6 * fabs(a[1]);
    for (int i = 0; i < 6; i++)
        if (fabs(a[i] - g[i]) > tol) {
            tp_cli_error("%s: its store %s has another grid (geotransform term %d: %.9g, the "
                         "DEM's %.9g): the sweep's store families need the DEM's",
                         o->dem, s->path, i, g[i], a[i]);
            tp_bench_sweep_store_close(s);
            return TP_EXIT_FAILURE;
        }
    *out = s;
    return TP_EXIT_OK;
}

void tp_bench_sweep_store_close(tp_bench_sweep_store* s)
{
    if (!s)
        return;
    tp_store_scene_close(&s->sc);
    if (s->temporary)
        tp_store_cache_remove_temporary(s->path);
    free(s);
}

/* What one configuration draws with, fresh for it (cold, as a viewer starts). */
typedef struct sweep_draw {
    tp_renderer* r;
    tp_cut* cut;
    tp_normal_map* nm;
    tp_render_settings rs;
} sweep_draw;

static void close_draw(tp_store_scene* sc, sweep_draw* d)
{
    tp_normal_map_destroy(d->nm);
    tp_cut_destroy(d->cut);
    tp_renderer_destroy(d->r);
    tp_tin_cache_destroy(sc->tins); /* the next configuration starts cold */
    sc->tins = NULL;
    tp_stream_destroy(sc->stream);
    sc->stream = NULL;
}

/* The stream, renderer, cut (with the TIN cache when tins) and normal map into *d; TP_EXIT_OK,
 * else TP_EXIT_FAILURE after a message (what was made stays in *d for close_draw). */
static int open_draw(const bench_options* o, tp_store_scene* sc, int tins, sweep_draw* d)
{
    tp_stream_options so = {.memory_bytes = (size_t)o->memory_mb << 20,
                            .frame_s = 1.0 / TP_BENCH_FRAME_HZ};
    if (tp_store_scene_stream(sc, &so) != TP_EXIT_OK)
        return TP_EXIT_FAILURE;
    const tp_tree_geometry* g = tp_tree_get_geometry(sc->tree);
    tp_render_grid_desc rd = {.n = g->n,
                              .width = g->width,
                              .height = g->height,
                              .min_height_m = sc->tree_info.min_height_m,
                              .max_height_m = sc->tree_info.max_height_m};
    memcpy(rd.geotransform, sc->tree_info.geotransform, sizeof rd.geotransform);
    tp_error err = {{0}};
    if (!(d->r = tp_renderer_create_desc(&rd, &err)) ||
        tp_cut_create(sc->tree, &d->cut, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    if (tins && tp_store_scene_tins(sc) != TP_EXIT_OK)
        return TP_EXIT_FAILURE;
    tp_cut_set_tins(d->cut, sc->tins);
    tp_render_settings_default(&d->rs);
    tp_normal_source* src = tp_normal_source_store(sc->store, sc->tree_info.min_height_m,
                                                   sc->tree_info.max_height_m, &err);
    tp_clipmap_options co = {.frame_s = 1.0 / TP_BENCH_FRAME_HZ};
    if (!src || !(d->nm = tp_normal_map_create(src, &co, &err))) {
        tp_cli_error("the normal map: %s", err.message);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

/* Untimed: cuts at cam until the cut asks for nothing, the stream has nothing pending and every
 * TIN level the cut would draw is built (then the normal map's blocks for it are loaded). 1, or
 * 0 when the cut fails or SETTLE_MAX_MS passed. */
static int settle(tp_store_scene* sc, sweep_draw* d, const tp_camera* cam,
                  const tp_lod_params* lod)
{
    double t0 = tp_clock_ms();
    tp_error err;
    for (;;) {
        if (tp_cut_update(d->cut, cam, lod, &err) != TP_OK)
            return 0;
        tp_stream_stats ss;
        tp_stream_frame(sc->stream, d->cut, NULL, cam, lod, &ss);
        size_t nreq = 0;
        tp_cut_requests(d->cut, &nreq);
        if (nreq == 0 && ss.pending == 0 && (!sc->tins || tp_cut_tins_build(sc->tins, d->cut, 0) == 0))
            break;
        if (tp_clock_ms() - t0 > SETTLE_MAX_MS)
            return 0;
        nanosleep(&(struct timespec){0, 1000000}, NULL);
    }
    tp_normal_map_frame_cut(d->nm, sc, d->cut, 1, d->r, cam, 1, NULL);
    return 1;
}

/* One frame at cam: the cut, the stream's and the normal map's frames, the draw (finished);
 * the times into row when it is given (else untimed). */
static int draw_frame(const bench_run* b, tp_store_scene* sc, sweep_draw* d, const tp_camera* cam,
                      const tp_lod_params* lod, frame_row* row)
{
    tp_error err;
    tp_stream_stats ss;
    tp_render_stats st;
    tp_gl_context_begin_frame(b->ctx);
    double t0 = tp_clock_ms();
    if (tp_cut_update(d->cut, cam, lod, &err) != TP_OK) {
        tp_gl_context_end_frame(b->ctx);
        return 0;
    }
    tp_stream_frame(sc->stream, d->cut, NULL, cam, lod, &ss);
    tp_normal_map_frame_cut(d->nm, sc, d->cut, 1, d->r, cam, 0, NULL);
    double t1 = tp_clock_ms();
    tp_renderer_draw_cut(d->r, sc->tree, d->cut, cam, &d->rs, 1, 1, &st);
    tp_gl_context_end_frame(b->ctx);
    double t2 = tp_clock_ms();
    if (sc->tins) { /* the viewer's render thread after its frame: stamp, prune */
        tp_tin_cache_mark_drawn(sc->tins, d->cut);
        tp_tin_cache_prune(sc->tins, TP_CUT_WORKER_TIN_AGE, TP_CUT_WORKER_TIN_BYTES);
    }
    if (!row)
        return 1;
    tp_cut_stats cs;
    tp_cut_get_stats(d->cut, &cs);
    row->select_ms = t1 - t0;
    row->upload_ms = st.upload_ms;
    row->draw_ms = st.draw_ms;
    row->frame_ms = t2 - t0;
    row->triangles = cs.triangles;
    row->draw_calls = st.draw_calls;
    row->patches = cs.drawn;
    row->uploads = st.uploads;
    row->gpu_bytes = st.gpu_bytes;
    row->draws = st.draws;
    row->tin_nodes = cs.tin_nodes;
    row->substituted = cs.substituted;
    return 1;
}

/* Ends the progress line, says what failed; TP_EXIT_FAILURE. */
static int failed(const char* progress, int frame, const char* what)
{
    tp_bench_progress_end();
    tp_cli_error("%s: frame %d: %s", progress, frame, what);
    return TP_EXIT_FAILURE;
}

int tp_bench_sweep_store_frames(const bench_run* b, config_result* c, const char* progress)
{
    tp_store_scene* sc = &b->store->sc;
    const bench_options* o = b->o;
    int frames = b->frames, code = TP_EXIT_OK;
    sweep_draw d;
    memset(&d, 0, sizeof d);
    c->rows = calloc((size_t)frames, sizeof *c->rows);
    if (!c->rows) {
        tp_cli_error("out of memory");
        return TP_EXIT_FAILURE;
    }
    if (open_draw(o, sc, c->store == 2, &d) != TP_EXIT_OK) {
        close_draw(sc, &d);
        return TP_EXIT_FAILURE;
    }
    for (int i = 0; i < frames && code == TP_EXIT_OK; i++) {
        tp_camera cam, lead;
        frame_row* row = &c->rows[i];
        if (tp_bench_frame_camera(b, i, &cam, &lead) && /* untimed */
            (!settle(sc, &d, &lead, &c->lod) || !draw_frame(b, sc, &d, &lead, &c->lod, NULL))) {
            code = failed(progress, i + 1, "the lead-in frame's cut could not be selected or "
                                           "its nodes not loaded (20 s)");
            break;
        }
        if (!settle(sc, &d, &cam, &c->lod) || !draw_frame(b, sc, &d, &cam, &c->lod, row)) {
            code = failed(progress, i + 1, "the cut could not be selected or its nodes not "
                                           "loaded (20 s)");
            break;
        }
        tp_cut_error ce;
        tp_error err = {{0}};
        if (tp_store_scene_measure(sc, d.cut, &cam, (size_t)o->error_posts, (uint32_t)i, &ce,
                                   &err) != TP_OK) {
            code = failed(progress, i + 1, err.message[0] ? err.message : "out of memory");
            break;
        }
        if (err.message[0] || ce.skipped) { /* every leaf is in the cache's store */
            code = failed(progress, i + 1, err.message[0] ? err.message : "leaves not read");
            break;
        }
        /* nothing in view to compare: 0 (as the DEM's selection measures it), not NaN */
        row->max_px = ce.samples ? ce.max_px : 0;
        row->rms_px = ce.samples ? ce.rms_px : 0;
        row->max_m = row->rms_m = NAN; /* the cut measures on screen only */
        char what[96];
        snprintf(what, sizeof what, "%.1f ms, %zu triangles", row->frame_ms, row->triangles);
        tp_bench_progress(progress, i + 1, frames, what);
    }
    tp_bench_progress_end();
    close_draw(sc, &d);
    if (code != TP_EXIT_OK)
        return code;
    tp_bench_summarize(c, frames);
    double tin = 0, drawn = 0, subst = 0;
    for (int i = 0; i < frames; i++)
        tin += c->rows[i].tin_nodes, drawn += c->rows[i].patches, subst += c->rows[i].substituted;
    c->tin_share = drawn > 0 ? tin / drawn : 0;
    c->max_m = c->rms_m = NAN;
    if (subst > 0) /* settled frames draw no substitute; one would not be bounded by tau */
        tp_cli_warning("%s: %.0f nodes drawn in place of finer ones not loaded (--memory %d MB)",
                       progress, subst, o->memory_mb);
    return TP_EXIT_OK;
}
