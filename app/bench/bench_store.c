/*
 * bench_store.c - `terrapatch bench X.tpt`: flights over a built store through the hierarchy
 * (issue 12). Every frame: tp_cut_update (the error or the distance mode), tp_stream_frame
 * (with a prefetch cut), tp_renderer_draw_cut, timed as the DEM bench times its frames; then,
 * outside the timed part, the process's memory (/proc/self/status) and the measured screen
 * error (tp_store_scene_measure: the leaves under the drawn nodes read from the store where the
 * stream does not hold them, sampled to --error-posts; frames drawn with substitution apart).
 *
 * A flight is `segments` stretches of continuous flight at --speed spread evenly along a line
 * across the map (low: the middle row, 60 m above the ground, west to east; high: along the
 * south edge, 0.35 x the map's size above its highest point, 35 degrees down), so that a few
 * hundred frames sample the whole map and still fly as a viewer flies: the camera advances
 * speed / 30 m per frame (a 30 Hz flight). Before each stretch the camera jumps there, waits
 * until the stream has loaded what the view asks for (untimed: a viewer flying continuously
 * would have been loading on the way) and flies 5 untimed frames into the stretch, so the
 * prefetch knows the motion. With --realtime the camera instead moves by speed x the time
 * that really passed since the stretch began (what a viewer does), so a slow frame is a jump
 * and the loader gets only real time.
 */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"
#include "clock.h"
#include "cli.h"
#include "cut_worker.h"
#include "gl_context.h"
#include "imagery_view.h"
#include "light_view.h"
#include "memory.h"
#include "normal_map.h"
#include "pgm_clip.h"
#include "pgm_render.h"
#include "renderer.h"
#include "store_scene.h"
#include "bench_store.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

#define WARMUP_FRAMES 5
#define SETTLE_MAX_MS 20000.0

#define ROWS_OF(expr) TP_BENCH_COLUMN(v, store_row, c->rows, n, expr)
#define MEDIAN_OF(dst, expr)                                                                      \
    do {                                                                                           \
        ROWS_OF(expr);                                                                             \
        dst = tp_bench_median(v, n);                                                               \
    } while (0)

static void summarize(store_result* c, int n)
{
    double* v = malloc((size_t)n * sizeof *v);
    if (!v)
        return;
    MEDIAN_OF(c->frame_ms, r->frame_ms);
    c->frame_ms_p99 = tp_bench_p99(v, n);
    c->fps_median = 1000 / c->frame_ms;
    MEDIAN_OF(c->cpu_ms, r->cpu_ms);
    MEDIAN_OF(c->cut_ms, r->cut_ms);
    MEDIAN_OF(c->cut_worker_ms, r->cut_worker_ms);
    MEDIAN_OF(c->cut_wait_ms, r->cut_wait_ms);
    ROWS_OF(r->cut_worker_cpu_ms);
    c->cut_worker_cpu_ms_mean = tp_bench_mean(v, n);
    c->cut_worker_cpu_ms = tp_bench_median(v, n);
    ROWS_OF(r->cut_ms + r->cut_worker_cpu_ms);
    c->cut_total_cpu_ms_mean = tp_bench_mean(v, n);
    c->cut_total_cpu_ms = tp_bench_median(v, n);
    MEDIAN_OF(c->cut_scratch, r->cut_scratch);
    c->cut_reused_share = c->cut_kept_share = c->cut_carried_share = c->tin_share = c->tin_mb = 0;
    double drawn = 0;
    for (int i = 0; i < n; i++) {
        const store_row* r = &c->rows[i];
        c->cut_reused_share += (double)r->cut_reused / n;
        c->cut_kept_share += (double)r->cut_kept / n;
        c->cut_carried_share += (double)r->cut_carried / n;
        c->tin_share += r->tin_nodes, drawn += r->nodes;
        c->tin_mb = fmax(c->tin_mb, r->tin_bytes / 1e6);
    }
    c->tin_share /= drawn > 0 ? drawn : 1;
    tp_bench_store_tin_summary(c, n);
    MEDIAN_OF(c->stream_ms, r->stream_ms);
    MEDIAN_OF(c->upload_ms, r->upload_ms);
    MEDIAN_OF(c->draw_ms, r->draw_ms);
    MEDIAN_OF(c->page_faults, r->page_faults);
    MEDIAN_OF(c->triangles, r->triangles);
    MEDIAN_OF(c->nodes, r->nodes);
    MEDIAN_OF(c->visited, r->visited);
    MEDIAN_OF(c->uploads, r->uploads);
    MEDIAN_OF(c->draw_calls, r->draw_calls);
    MEDIAN_OF(c->img_ms, r->img_ms);
    MEDIAN_OF(c->img_upload_ms, r->img_upload_ms);
    c->img_upload_ms_p99 = tp_bench_p99(v, n);
    MEDIAN_OF(c->img_uploads, r->img_uploads);
    MEDIAN_OF(c->nrm_ms, r->nrm_ms);
    MEDIAN_OF(c->nrm_upload_ms, r->nrm_upload_ms);
    MEDIAN_OF(c->pgm_fill_ms, r->pgm_fill_ms);
    c->pgm_fill_ms_p99 = tp_bench_p99(v, n);
    MEDIAN_OF(c->pgm_upload_ms, r->pgm_upload_ms);
    c->pgm_upload_ms_p99 = tp_bench_p99(v, n);
    MEDIAN_OF(c->pgm_posts, r->pgm_posts);
    MEDIAN_OF(c->pgm_node_reads, r->pgm_node_reads);
    for (int i = 0; i < n; i++) {
        const store_row* r = &c->rows[i];
        c->substituted_max = r->substituted > c->substituted_max ? r->substituted : c->substituted_max;
        c->frames_with_substitution += r->substituted > 0;
        c->dropped_max = r->dropped > c->dropped_max ? r->dropped : c->dropped_max;
        c->pending_max = r->pending > c->pending_max ? r->pending : c->pending_max;
        c->rss_mb = fmax(c->rss_mb, r->rss_mb);
        c->rss_anon_mb = fmax(c->rss_anon_mb, r->rss_anon_mb);
        c->resident_mb = fmax(c->resident_mb, r->resident_bytes / 1e6);
        c->gpu_mb = fmax(c->gpu_mb, r->gpu_bytes / 1e6);
        c->img_gpu_mb = fmax(c->img_gpu_mb, r->img_gpu_bytes / 1e6);
        c->img_cache_mb = fmax(c->img_cache_mb, r->img_cache_bytes / 1e6);
        c->img_missing_max = r->img_missing > c->img_missing_max ? r->img_missing : c->img_missing_max;
        c->img_frames_missing += r->img_missing > 0;
        c->img_uploads_total += r->img_uploads;
        c->nrm_gpu_mb = fmax(c->nrm_gpu_mb, r->nrm_gpu_bytes / 1e6);
        c->nrm_uploads_total += r->nrm_uploads;
        c->nrm_frames_missing += r->nrm_missing > 0;
    }
    tp_bench_store_error_summary(c, n, v);
    free(v);
}

/* Untimed frames at cam without drawing until the cut asks for nothing and the stream has
 * nothing pending (or SETTLE_MAX_MS passed: 0 is returned then). */
static int settle(store_bench* b, tp_cut* cut, tp_cut* pre, const tp_camera* cam,
                  const tp_lod_params* lod)
{
    double t0 = tp_clock_ms();
    tp_error err;
    for (;;) {
        if (tp_cut_update(cut, cam, lod, &err) != TP_OK)
            return 0;
        tp_stream_stats ss;
        tp_stream_frame(b->sc.stream, cut, b->o->no_prefetch ? NULL : pre, cam, lod, &ss);
        size_t nreq = 0;
        tp_cut_requests(cut, &nreq);
        /* and every TIN level the view asks for: once built, cut again (it then draws them;
         * returning 0 there counted every TIN flight's jumps as settle timeouts) */
        if (b->sc.tins) { /* the levels of before the jump go first, as in the frames */
            tp_tin_cache_mark_drawn(b->sc.tins, cut);
            tp_tin_cache_prune(b->sc.tins, TP_CUT_WORKER_TIN_AGE, TP_CUT_WORKER_TIN_BYTES);
        }
        if (nreq == 0 && ss.pending == 0 &&
            (!b->sc.tins || tp_cut_tins_build(b->sc.tins, cut, 0) == 0))
            return 1;
        if (tp_clock_ms() - t0 > SETTLE_MAX_MS)
            return 0;
        nanosleep(&(struct timespec){0, 1000000}, NULL);
    }
}

/* The most level-0 posts one PGM frame's error visits over a store (a view towards the horizon
 * over a 65537^2 store would visit all 4.3e9, minutes a frame): 2^28, a few seconds; of a
 * larger region every k-th band of node rows (tp_pgm_clipmap_measure, post_share). */
#define PGM_MEASURE_MAX_POSTS ((size_t)1 << 28)

/* A PGM configuration: a fresh clipmap and grid (cold), the same flight; each frame's time
 * includes the clipmap's update (reading and uploading the strips its windows gain: synchronous,
 * so a jump's whole refill is in the stretch's first warm-up frame, untimed). The error, every
 * --error-every frames outside the timed part, is tp_pgm_clipmap_measure's: the surface the
 * windows drew against the store's level-0 posts in view (bands of them where the view's region
 * holds more than PGM_MEASURE_MAX_POSTS). Returns TP_EXIT_*. */
static int run_store_pgm(store_bench* b, store_result* c, const char* progress)
{
    int frames = b->segments * b->per_segment;
    tp_error err = {{0}};
    tp_pgm_clipmap* clip = tp_pgm_clipmap_create(b->sc.store, c->pgm_window, &err);
    tp_pgm_renderer* r =
        clip ? tp_pgm_renderer_create_clipmap(clip, c->pgm_cols, c->pgm_rows, &err) : NULL;
    if (!r) {
        tp_cli_error("%s: %s", b->o->dem, err.message);
        tp_pgm_clipmap_destroy(clip);
        return TP_EXIT_FAILURE;
    }
    c->pgm_window = tp_pgm_clipmap_window(clip);
    tp_render_settings rs;
    tp_render_settings_default(&rs);
    tp_pgm_render_stats ps;
    tp_camera cam;
    for (int seg = 0; seg < b->segments; seg++)
        for (int i = -WARMUP_FRAMES; i < b->per_segment; i++) {
            tp_bench_store_camera(b, seg, i * b->step_m, &cam);
            tp_pgm_frame f;
            tp_gl_context_begin_frame(b->ctx);
            double t0 = tp_clock_ms();
            tp_pgm_renderer_draw(r, &cam, &rs, 1, &f, &ps);
            tp_gl_context_end_frame(b->ctx);
            double t1 = tp_clock_ms();
            if (i < 0)
                continue;
            int k = seg * b->per_segment + i;
            store_row* row = &c->rows[k];
            row->frame_ms = t1 - t0;
            row->cpu_ms = ps.setup_ms;
            row->stream_ms = row->pgm_fill_ms = ps.fill_ms;
            row->upload_ms = row->pgm_upload_ms = ps.upload_ms;
            row->pgm_posts = ps.posts_updated;
            row->pgm_node_reads = ps.node_reads;
            row->draw_ms = ps.draw_ms;
            row->draw_calls = 1;
            row->triangles = ps.triangles;
            row->gpu_bytes = ps.gpu_bytes;
            row->max_px = row->rms_px = NAN;
            if (!b->o->no_error && k % b->o->error_every == 0) { /* untimed */
                tp_pgm_error e;
                tp_camera mc = cam; /* the viewport the frame was drawn at */
                mc.viewport_w_px = b->o->vs.w;
                mc.viewport_h_px = b->o->vs.h;
                double t_m = tp_clock_ms();
                tp_status ms =
                    tp_pgm_clipmap_measure(clip, &f, &mc, PGM_MEASURE_MAX_POSTS, &e, &err);
                row->measure_ms = tp_clock_ms() - t_m;
                if (ms != TP_OK) {
                    tp_bench_progress_end();
                    tp_cli_error("%s: frame %d: %s", progress, k + 1, err.message);
                    tp_pgm_renderer_destroy(r);
                    tp_pgm_clipmap_destroy(clip);
                    return TP_EXIT_FAILURE;
                } else {
                    row->measured = 1;
                    row->max_px = e.samples ? e.max_px : NAN;
                    row->rms_px = e.samples ? e.rms_px : NAN;
                    row->samples = e.samples, row->uncovered = e.uncovered;
                    row->post_share = e.post_share;
                }
            }
            tp_bench_read_rss(&row->rss_mb, &row->rss_anon_mb);
            char what[96];
            snprintf(what, sizeof what, "%.1f ms, %zu posts updated", row->frame_ms,
                     row->pgm_posts);
            tp_bench_progress(progress, k + 1, frames, what);
        }
    tp_bench_progress_end();
    summarize(c, frames);
    tp_pgm_renderer_destroy(r);
    tp_pgm_clipmap_destroy(clip);
    return TP_EXIT_OK;
}

/* What one configuration's flight draws with, made fresh for it (cold, as a viewer starts) and
 * released after it (close_draw): the renderer, the cut and the prefetch cut, and --imagery's
 * or --light's clipmap. */
typedef struct store_draw {
    tp_renderer* r;
    tp_cut *cut, *pre;
    tp_cut_worker* worker; /* NULL: --no-cut-thread */
    tp_view_imagery* im;
    tp_view_light* lt;
    tp_normal_map* nm; /* the normals the terrain is shaded from (NULL: the vertices') */
    tp_render_settings rs;
    double day[2]; /* the light map's: the sun's time sweeps it over the flight */
} store_draw;

/* The store's stream, with the --memory budget (first: its creation timed in b); 0 when it
 * cannot be made. */
static int open_stream(store_bench* b, int first)
{
    const bench_options* o = b->o;
    /* The stream's motion estimate follows the flight's own clock (TP_BENCH_FRAME_HZ), not the
     * draw's: frames that take 0.1-3 s here would otherwise make a 300 m/s flight look like
     * 3-30 m/s. */
    tp_stream_options so = {.memory_bytes = (size_t)o->memory_mb << 20,
                            .frame_s = o->realtime ? 0 : 1.0 / TP_BENCH_FRAME_HZ};
    double t_setup = tp_clock_ms();
    if (tp_store_scene_stream(&b->sc, &so) != TP_EXIT_OK)
        return 0;
    if (first)
        b->stream_create_ms = tp_clock_ms() - t_setup;
    return 1;
}

/* The renderer (first: its creation timed in b), the cuts and c's imagery or light into *d.
 * TP_EXIT_FAILURE after a message; what was made stays in *d for close_draw either way. */
static int open_draw(store_bench* b, const store_result* c, int first, store_draw* d)
{
    const bench_options* o = b->o;
    const tp_tree_geometry* g = b->g;
    tp_render_grid_desc rd = {.n = g->n,
                              .width = g->width,
                              .height = g->height,
                              .min_height_m = b->sc.tree_info.min_height_m,
                              .max_height_m = b->sc.tree_info.max_height_m};
    memcpy(rd.geotransform, b->sc.tree_info.geotransform, sizeof rd.geotransform);
    tp_error err = {{0}};
    double t_setup = tp_clock_ms();
    d->r = tp_renderer_create_desc(&rd, &err);
    if (first)
        b->renderer_ms = tp_clock_ms() - t_setup;
    if (!d->r) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    if (tp_cut_create(b->sc.tree, &d->cut, &err) != TP_OK ||
        tp_cut_create(b->sc.tree, &d->pre, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    tp_cut_set_stitch_add(d->cut, c->stitch_add);
    if (o->vs.mesh_tin && tp_store_scene_tins(&b->sc) != TP_EXIT_OK)
        return TP_EXIT_FAILURE;
    tp_cut_set_tins(d->cut, b->sc.tins);
    if (!o->no_cut_thread && !(d->worker = tp_cut_worker_create(b->sc.tree, &err))) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    tp_render_settings_default(&d->rs);
    d->rs.stitch_add = c->stitch_add;
    if (o->stitch_add_draw) /* --stitch-add-draw sets|five (both: a DEM only) */
        d->rs.stitch_add_five = o->stitch_add_draw == 2;
    tp_clipmap_options co = {.clip_blocks = o->clip_blocks,
                             .frame_s = o->realtime ? 0 : 1.0 / TP_BENCH_FRAME_HZ};
    if (c->imagery &&
        !tp_view_imagery_open(o->imagery, &b->sc, (tp_imagery_mode)c->imagery_mode, &co, &d->im))
        return TP_EXIT_FAILURE;
    d->day[0] = 0;
    d->day[1] = 1;
    if (c->light && !tp_view_light_open(o->light, &b->sc, &co, &d->lt))
        return TP_EXIT_FAILURE;
    if (d->lt)
        tp_view_light_day(d->lt, &d->day[0], &d->day[1], NULL);
    if (c->pgm_cols)
        return TP_EXIT_OK;
    co.clip_blocks = 0; /* the normal map's own window */
    tp_normal_source* src = tp_normal_source_store(b->sc.store, b->sc.tree_info.min_height_m,
                                                   b->sc.tree_info.max_height_m, &err);
    if (!src || !(d->nm = tp_normal_map_create(src, &co, &err))) {
        tp_cli_error("the normal map: %s", err.message);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

/* Releases what open_draw made, and the stream. */
static void close_draw(store_bench* b, store_draw* d)
{
    tp_view_imagery_close(d->im);
    tp_view_light_close(d->lt);
    tp_normal_map_destroy(d->nm);
    tp_cut_worker_destroy(d->worker);
    tp_cut_destroy(d->pre);
    tp_cut_destroy(d->cut);
    tp_renderer_destroy(d->r);
    tp_tin_cache_destroy(b->sc.tins); /* the next configuration starts cold */
    b->sc.tins = NULL;
    tp_stream_destroy(b->sc.stream);
    b->sc.stream = NULL;
}

/* Ends the progress line and says the cut could not be selected; TP_EXIT_FAILURE. */
static int cut_failed(const tp_error* err)
{
    tp_bench_progress_end();
    tp_cli_error("selecting the cut: %s", err->message[0] ? err->message : "failed");
    return TP_EXIT_FAILURE;
}

/* The first frame of the first configuration, at cam: what a viewer shows right after start.
 * Its parts go to b (waiting for the georeference, the cut and stream, the draw), with its time
 * since the process started and since the store was opened. Returns TP_EXIT_*. */
static int first_frame(store_bench* b, const store_result* c, store_draw* d, const tp_camera* cam,
                       tp_render_stats* st, tp_stream_stats* ss)
{
    const bench_options* o = b->o;
    tp_error err;
    double t0 = tp_clock_ms();
    if (tp_store_scene_georef_wait(&b->sc) != TP_EXIT_OK)
        return TP_EXIT_FAILURE;
    b->georef_wait_ms = tp_clock_ms() - t0;
    t0 = tp_clock_ms();
    tp_gl_context_begin_frame(b->ctx);
    if (tp_cut_update(d->cut, cam, &c->lod, &err) != TP_OK)
        return cut_failed(&err);
    tp_stream_frame(b->sc.stream, d->cut, o->no_prefetch ? NULL : d->pre, cam, &c->lod, ss);
    if (d->nm)
        tp_normal_map_frame_cut(d->nm, &b->sc, d->cut, 1, d->r, cam, 0, NULL);
    double t1 = tp_clock_ms();
    tp_renderer_draw_cut(d->r, b->sc.tree, d->cut, cam, &d->rs, 1, 1, st);
    tp_gl_context_end_frame(b->ctx);
    b->first_cut_ms = t1 - t0;
    b->first_draw_ms = tp_clock_ms() - t1;
    b->first_frame_ms = tp_clock_ms_since_start();
    b->first_frame_open_ms = tp_clock_ms() - b->t_open_ms;
    return TP_EXIT_OK;
}

/* A timed frame's row from its figures, outside the timed part: t, the clock (ms) at the frame's
 * start, after the cut, after the stream, after the imagery or light (draped: the frame has
 * one; its clipmap's figures in is), after the draw and after the normal map (its clipmap's
 * figures in ns; between the stream and the imagery). */
static void fill_row(store_row* row, const double t[6], const tp_cut_stats* cs,
                     const tp_render_stats* st, const tp_stream_stats* ss,
                     const tp_clipmap_stats* is, int draped, const tp_clipmap_stats* ns)
{
    row->cut_ms = t[1] - t[0];
    row->stream_ms = t[2] - t[1];
    row->nrm_ms = t[5] - t[2];
    row->nrm_upload_ms = ns->upload_ms;
    row->nrm_uploads = ns->uploads;
    row->nrm_missing = ns->missing;
    row->nrm_gpu_bytes = ns->gpu_bytes;
    row->upload_ms = st->upload_ms;
    row->draw_ms = st->draw_ms;
    row->draw_calls = st->draw_calls;
    row->page_faults = st->page_faults;
    row->frame_ms = t[4] - t[0];
    row->cpu_ms = row->cut_ms + row->stream_ms + row->nrm_ms + row->upload_ms;
    if (draped) {
        row->img_ms = t[3] - t[5];
        row->img_upload_ms = is->upload_ms;
        row->img_uploads = is->uploads;
        row->img_missing = is->missing;
        row->img_pending = is->pending;
        row->img_gpu_bytes = is->gpu_bytes;
        row->img_cache_bytes = is->cache_bytes;
        row->cpu_ms += row->img_ms;
    }
    row->triangles = cs->triangles;
    row->nodes = cs->drawn;
    row->visited = cs->visited;
    row->substituted = cs->substituted;
    row->substitution_px = cs->substitution_bound_px;
    row->requests = cs->requests;
    row->uploads = st->uploads;
    row->gpu_bytes = st->gpu_bytes;
    row->dropped = st->dropped;
    row->resident_bytes = ss->resident_bytes;
    row->pending = ss->pending;
}

/* The flight with d: each stretch reached by a jump (the first configuration's first frame
 * there timed by first_frame) and settled, then WARMUP_FRAMES untimed frames and per_segment
 * timed ones into c->rows, each with the process's memory and, outside the timed part, the
 * measured screen error of every --error-every-th frame (those drawn with substitution kept
 * apart); then the
 * summary and --imagery's last frame against a fresh clipmap's. Returns TP_EXIT_*. */
static int fly(store_bench* b, store_result* c, int first, store_draw* d, const char* progress)
{
    const bench_options* o = b->o;
    int frames = b->segments * b->per_segment;
    tp_render_stats st;
    tp_stream_stats ss;
    tp_clipmap_stats is = {0}, ns = {0};
    tp_error err;
    tp_camera cam, prev;
    tp_cut* cut = d->cut; /* the frame's: d->cut, or the cut thread's */
    size_t tin_builds = 0; double tin_ms = 0; /* TIN builds, their time: a frame's, the change */
    const tp_cut_worker_params wp = {
        .lod = c->lod, .vertical_scale = 1, .stitch_add = c->stitch_add, .tins = b->sc.tins};
    for (int seg = 0; seg < b->segments; seg++) {
        tp_cut_worker_forget(d->worker); /* a jump, whose frames change the tree */
        tp_stream_set_prefetch_async(b->sc.stream, 0);
        tp_bench_store_camera(b, seg, -WARMUP_FRAMES * b->step_m, &cam);
        int code = first && seg == 0 ? first_frame(b, c, d, &cam, &st, &ss) : TP_EXIT_OK;
        if (code != TP_EXIT_OK)
            return code;
        double t_settle = tp_clock_ms();
        if (!settle(b, d->cut, d->pre, &cam, &c->lod))
            c->settle_timeouts++;
        if (d->im) /* the imagery the jump's view needs, as the terrain's */
            tp_view_imagery_frame(d->im, &b->sc, d->cut, 1, d->r, &cam, 1, &is);
        if (d->lt)
            tp_view_light_frame(d->lt, &b->sc, d->cut, 1, d->r, &cam, d->day[0], 1, &is);
        if (d->nm)
            tp_normal_map_frame_cut(d->nm, &b->sc, d->cut, 1, d->r, &cam, 1, &ns);
        if (seg == 0)
            c->settle_ms = tp_clock_ms() - t_settle;
        if (b->sc.tins) /* the settle's builds are not a frame's */
            tp_tin_cache_stats(b->sc.tins, NULL, NULL, &tin_builds), tin_ms = tp_tin_cache_build_ms(b->sc.tins);
        double t_fly = tp_clock_ms();
        tp_stream_set_prefetch_async(b->sc.stream, d->worker != NULL);
        for (int i = -WARMUP_FRAMES; i < b->per_segment; i++) {
            /* --realtime: where the camera is after the time that really passed */
            double at =
                o->realtime
                    ? (-WARMUP_FRAMES * b->step_m + o->speed_mps * (tp_clock_ms() - t_fly) / 1e3)
                    : i * b->step_m;
            tp_bench_store_camera(b, seg, at, &cam);
            store_row* row = i >= 0 ? &c->rows[seg * b->per_segment + i] : NULL;
            double t[6];
            tp_cut_worker_stats ws = {0};
            tp_gl_context_begin_frame(b->ctx);
            t[0] = tp_clock_ms();
            if (d->worker ? !(cut = tp_cut_worker_frame(d->worker, &cam, &wp, &ws, &err))
                          : tp_cut_update(cut, &cam, &c->lod, &err) != TP_OK)
                return cut_failed(&err);
            t[1] = tp_clock_ms();
            tp_stream_frame(b->sc.stream, cut, o->no_prefetch ? NULL : d->pre, &cam, &c->lod, &ss);
            size_t tin_bytes = 0, tin_builds0 = tin_builds;
            double tin_ms0 = tin_ms;
            if (b->sc.tins) { /* the cut thread is idle: prune, or build here without it */
                tp_tin_cache_mark_drawn(b->sc.tins, cut);
                tp_tin_cache_prune(b->sc.tins, TP_CUT_WORKER_TIN_AGE, TP_CUT_WORKER_TIN_BYTES);
                if (!d->worker)
                    tp_cut_tins_build(b->sc.tins, cut, TP_CUT_WORKER_TIN_MS);
                tp_tin_cache_stats(b->sc.tins, &tin_bytes, NULL, &tin_builds);
                tin_ms = tp_tin_cache_build_ms(b->sc.tins);
            }
            t[2] = tp_clock_ms();
            if (d->nm) /* the frame's cut's nodes: the normal map's finest level */
                tp_normal_map_frame_cut(d->nm, &b->sc, cut, 1, d->r, &cam, 0, &ns);
            t[5] = tp_clock_ms();
            if (d->worker) { /* the next frame's cut (and prefetch), selected while this draws */
                tp_camera next, ahead;
                tp_cut_worker_predict(i > -WARMUP_FRAMES ? &prev : &cam, &cam, &next);
                int pre = tp_stream_prefetch_wanted(b->sc.stream, &ahead);
                tp_cut_worker_next(d->worker, &next, &wp, pre ? d->pre : NULL, &ahead);
            }
            prev = cam;
            if (d->im)
                tp_view_imagery_frame(d->im, &b->sc, cut, 1, d->r, &cam, 0, &is);
            int k = seg * b->per_segment + (i > 0 ? i : 0);
            if (d->lt)
                tp_view_light_frame(d->lt, &b->sc, cut, 1, d->r, &cam,
                                    d->day[0] + (d->day[1] - d->day[0]) * (k + 0.5) / frames, 0,
                                    &is);
            t[3] = tp_clock_ms();
            tp_renderer_draw_cut(d->r, b->sc.tree, cut, &cam, &d->rs, 1, 1, &st);
            tp_gl_context_end_frame(b->ctx);
            t[4] = tp_clock_ms();
            if (!row)
                continue;
            /* outside the timed part */
            tp_cut_stats cs;
            tp_cut_get_stats(cut, &cs);
            fill_row(row, t, &cs, &st, &ss, &is, d->im || d->lt, &ns);
            row->cut_ms -= ws.wait_ms; /* waiting is not the render thread's CPU */
            row->cpu_ms -= ws.wait_ms;
            row->cut_wait_ms = ws.wait_ms;
            row->cut_worker_ms = ws.worker_ms;
            row->cut_reused = ws.reused;
            row->cut_kept = ws.kept;
            row->cut_carried = ws.carried;
            row->cut_worker_cpu_ms = ws.worker_cpu_ms;
            row->cut_scratch = (double)ws.check_scratch;
            row->tin_nodes = cs.tin_nodes;
            row->tin_bytes = tin_bytes;
            row->tin_builds = (int)(tin_builds - tin_builds0), row->tin_build_ms = tin_ms - tin_ms0;
            tp_bench_read_rss(&row->rss_mb, &row->rss_anon_mb);
            if (!o->no_error && k % o->error_every == 0 && !tp_bench_store_measure(b, cut, &cam, k, row))
                return TP_EXIT_FAILURE;
            const char* failure = tp_stream_take_failure(b->sc.stream);
            if (failure && !tp_bench_store_said_before(b, failure)) {
                tp_bench_progress_end();
                tp_cli_error("%s", failure);
                if (tp_store_changed(b->sc.store)) /* never measured against a mix of two */
                    return TP_EXIT_FAILURE;
            }
            char what[96];
            snprintf(what, sizeof what, "%.1f ms, %d nodes", row->frame_ms, row->nodes);
            tp_bench_progress(progress, k + 1, frames, what);
        }
    }
    tp_bench_progress_end();
    tp_cut_worker_forget(d->worker);
    summarize(c, frames);
    c->cut_thread = d->worker != NULL;
    c->mesh_tin = b->sc.tins != NULL;
    if (d->im) /* the last frame against a fresh clipmap's: nothing stale after the flight */
        c->img_final_diff = tp_bench_imagery_diff(d->im, o->imagery, &b->sc, cut, d->r, b->ctx,
                                                  &cam, c->imagery_mode, o->clip_blocks);
    return TP_EXIT_OK;
}

/* One configuration: a fresh stream, renderer and cuts (cold, as a viewer starts), the flight's
 * frames. Returns TP_EXIT_*. */
static int run_store_config(store_bench* b, store_result* c, int first, const char* progress)
{
    c->rows = calloc((size_t)(b->segments * b->per_segment), sizeof *c->rows);
    if (c->pgm_cols)
        return c->rows ? run_store_pgm(b, c, progress) : TP_EXIT_FAILURE;
    if (!c->rows || !open_stream(b, first))
        return TP_EXIT_FAILURE;
    store_draw d;
    memset(&d, 0, sizeof d);
    int code = open_draw(b, c, first, &d);
    if (code == TP_EXIT_OK)
        code = fly(b, c, first, &d, progress);
    close_draw(b, &d);
    return code;
}

int tp_bench_store(const bench_options* o)
{
    store_bench b;
    memset(&b, 0, sizeof b);
    b.o = o;
    b.entered_ms = tp_clock_ms_since_start();
    b.t_open_ms = tp_clock_ms();
    /* as the viewer opens a store: the georeference is made on a thread meanwhile, and waited
     * for before the first frame (the bench itself does not use it) */
    if (tp_store_scene_open_deferred(o->dem, &b.sc) != TP_EXIT_OK)
        return TP_EXIT_FAILURE;
    b.open_ms = tp_clock_ms() - b.t_open_ms;
    b.g = tp_tree_get_geometry(b.sc.tree);
    b.leaf_id = -1;
    b.leaf = malloc(((size_t)1 << b.g->n | 1) * (((size_t)1 << b.g->n) + 1) * sizeof *b.leaf);
    if (!b.leaf) {
        tp_cli_error("out of memory");
        tp_store_scene_close(&b.sc);
        return TP_EXIT_FAILURE;
    }
    b.spacing_m = fabs(b.sc.tree_info.geotransform[1]);
    b.segments = o->segments < o->frames ? o->segments : o->frames;
    b.per_segment = o->frames / b.segments;
    b.step_m = o->speed_mps / TP_BENCH_FRAME_HZ;
    tp_error err = {{0}};
    if (!tp_gl_context_create_headless(o->vs.w, o->vs.h, &b.ctx, &err)) {
        tp_cli_error("%s", err.message);
        free(b.leaf);
        tp_store_scene_close(&b.sc);
        return TP_EXIT_FAILURE;
    }
    b.context_ms = tp_clock_ms() - b.t_open_ms - b.open_ms;
    int samples = o->vs.msaa >= 0 ? o->vs.msaa : tp_gl_context_default_msaa();
    if ((b.msaa = tp_gl_context_set_msaa(b.ctx, samples, &err)) < 0) {
        tp_cli_warning("--msaa %d: %s", samples, err.message);
        b.msaa = 0;
    }
    tp_bench_read_rss(&b.base_rss_mb, &b.base_anon_mb);
    const char* renderer_name = (const char*)glGetString(GL_RENDERER);
    renderer_name = renderer_name ? renderer_name : "?";
    store_result c[8 + 8]; /* error, distance, spheres, two imagery modes, light, error+add,
                              distance+add; PGM grids */
    memset(c, 0, sizeof c);
    c[0].lod = o->vs.lod;
    c[0].lod.mode = TP_LOD_ERROR;
    c[1].lod = o->vs.lod;
    c[1].lod.mode = TP_LOD_DISTANCE;
    c[0].lod.sphere_tree = c[1].lod.sphere_tree = 0;
    snprintf(c[0].label, sizeof c[0].label, "error tau=%g", o->vs.lod.tau_px > 0 ? o->vs.lod.tau_px : 1);
    snprintf(c[1].label, sizeof c[1].label, "distance");
    int nc = 2, code = TP_EXIT_OK;
    if (o->vs.lod.sphere_tree) { /* --lod spheres: the distance mode again, through the spheres */
        c[nc] = c[1];
        c[nc].lod.sphere_tree = 1;
        snprintf(c[nc].label, sizeof c[nc].label, "spheres");
        nc++;
    }
    if (o->imagery) { /* the error mode again, with imagery: fps with / fps without */
        for (int m = 0; m < 2; m++) {
            if (o->imagery_mode != 2 && o->imagery_mode != m)
                continue;
            c[nc] = c[0];
            c[nc].imagery = 1;
            c[nc].imagery_mode = m;
            snprintf(c[nc].label, sizeof c[nc].label, "%.40s+%s", c[0].label,
                     m == TP_IMAGERY_BLOCKS ? "blocks" : "imagery");
            nc++;
        }
    }
    if (o->light) { /* the error mode again, with the day's light: fps with / without */
        c[nc] = c[0];
        c[nc].light = 1;
        snprintf(c[nc].label, sizeof c[nc].label, "%.40s+light", c[0].label);
        nc++;
    }
    if (o->stitch_add) { /* --stitch add: both modes again, adding vertices */
        for (int m = 0; m < 2; m++) {
            char base[sizeof c[m].label];
            memcpy(base, c[m].label, sizeof base);
            c[nc] = c[m];
            c[nc].stitch_add = 1;
            snprintf(c[nc].label, sizeof c[nc].label, "%.40s+add", base);
            nc++;
        }
    }
    /* --renderer pgm: a configuration per grid (default TP_PGM_DEFAULT_COLS x _ROWS) */
    for (int k = 0; o->vs.pgm && k < (o->vs.pgm_grid_count ? o->vs.pgm_grid_count : 1); k++) {
        c[nc].lod = c[0].lod;
        c[nc].pgm_cols = o->vs.pgm_grid_count ? o->vs.pgm_grid[k][0] : TP_PGM_DEFAULT_COLS;
        c[nc].pgm_rows = o->vs.pgm_grid_count ? o->vs.pgm_grid[k][1] : TP_PGM_DEFAULT_ROWS;
        c[nc].pgm_window = o->vs.pgm_window;
        snprintf(c[nc].label, sizeof c[nc].label, "pgm %dx%d", c[nc].pgm_cols, c[nc].pgm_rows);
        nc++;
    }
    for (int k = 0; k < nc && code == TP_EXIT_OK; k++) {
        char progress[96];
        snprintf(progress, sizeof progress, "%s (%d/%d)", c[k].label, k + 1, nc);
        code = run_store_config(&b, &c[k], k == 0, progress);
    }
    if (code == TP_EXIT_OK) {
        tp_bench_store_print(&b, renderer_name, c, nc);
        if (o->json && !tp_bench_store_write_json(&b, renderer_name, c, nc))
            code = TP_EXIT_FAILURE;
        if (o->csv && !tp_bench_store_write_csv(&b, c, nc))
            code = TP_EXIT_FAILURE;
    }
    for (int k = 0; k < nc; k++)
        free(c[k].rows);
    free(b.leaf);
    tp_gl_context_destroy(b.ctx);
    tp_store_scene_close(&b.sc);
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
