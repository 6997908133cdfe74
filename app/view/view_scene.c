/* view_scene.c - the viewer's questions to a store or a DEM (see view_scene.h). */
#define _POSIX_C_SOURCE 200809L
#include "view_scene.h"
#include "clock.h"
#include "cut_worker.h"

#include "stitch_add_error.h"
#include "cli.h"
#include "pgm_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void tp_view_scene_from_dem(tp_view_scene* v, tp_scene* sc, tp_selection* sel)
{
    memset(v, 0, sizeof *v);
    v->path = sc->path;
    v->dem = sc;
    v->sel = sel;
    v->georef = sc->georef;
    memcpy(v->gt, sc->info.geotransform, sizeof v->gt);
    v->src_width = sc->info.src_width;
    v->src_height = sc->info.src_height;
    v->n = sc->info.n;
    v->min_height_m = sc->info.min_height_m;
    v->max_height_m = sc->info.max_height_m;
}

int tp_view_scene_from_store(tp_view_scene* v, tp_store_scene* st)
{
    memset(v, 0, sizeof *v);
    v->path = st->path;
    v->store = st;
    v->georef = st->georef;
    memcpy(v->gt, st->tree_info.geotransform, sizeof v->gt);
    const tp_tree_geometry* g = tp_tree_get_geometry(st->tree);
    v->src_width = g->src_width;
    v->src_height = g->src_height;
    v->n = g->n;
    v->min_height_m = isnan(st->tree_info.min_height_m) ? 0 : st->tree_info.min_height_m;
    v->max_height_m = isnan(st->tree_info.max_height_m) ? 0 : st->tree_info.max_height_m;
    tp_error err = {{0}};
    if (tp_cut_create(st->tree, &v->cut_own, &err) != TP_OK ||
        tp_cut_create(st->tree, &v->prefetch, &err) != TP_OK ||
        !(v->worker = tp_cut_worker_create(st->tree, &err))) {
        tp_cli_error("%s: %s", st->path, err.message);
        tp_view_scene_release(v);
        return 0;
    }
    v->cut = v->cut_own;
    if (st->stream) /* the prefetch cut is the cut thread's too (frame.c) */
        tp_stream_set_prefetch_async(st->stream, 1);
    return 1;
}

void tp_view_scene_release(tp_view_scene* v)
{
    tp_cut_worker_destroy(v->worker);
    tp_cut_destroy(v->cut_own);
    tp_cut_destroy(v->prefetch);
    v->worker = NULL;
    v->cut = v->cut_own = v->prefetch = NULL;
}

void tp_view_scene_world_to_grid(const tp_view_scene* v, double e, double n, double* x, double* y)
{
    *x = (e - v->gt[0]) / v->gt[1] - 0.5;
    *y = (n - v->gt[3]) / v->gt[5] - 0.5;
}

double tp_view_scene_drawn_height(const tp_view_scene* v, double x, double y)
{
    return v->store ? tp_cut_drawn_height_at(v->cut, x, y) : tp_selection_drawn_height_at(v->sel, x, y);
}

/* Makes the leaf under grid (x, y) resident (a store); 0 when it cannot be read. */
static int require_leaf(tp_view_scene* v, double x, double y)
{
    int64_t leaf = tp_tree_leaf_at(v->store->tree, x, y);
    if (leaf < 0 || tp_tree_samples(v->store->tree, leaf))
        return 1;
    tp_cut_worker_idle(v->worker); /* it reads the tree the stream is about to change */
    if (tp_stream_require(v->store->stream, leaf, NULL))
        return 1;
    tp_view_scene_report_failures(v); /* the stream reports it once */
    return 0;
}

double tp_view_scene_ground_height(tp_view_scene* v, double x, double y)
{
    if (!v->store)
        return tp_terrain_height_at(v->dem->terrain, x, y);
    require_leaf(v, x, y);
    double z = tp_tree_height_at(v->store->tree, x, y);
    return isnan(z) ? tp_cut_drawn_height_at(v->cut, x, y) : z;
}

int tp_view_scene_ray_cast(const tp_view_scene* v, const double o[3], const double d[3],
                           tp_ray_hit* hit)
{
    tp_status s = v->store ? tp_cut_ray_cast(v->cut, o, d, hit) : tp_selection_ray_cast(v->sel, o, d, hit);
    return s == TP_OK && hit->hit;
}

void tp_view_scene_keep_above(tp_view_scene* v, double position[3], double clearance_m)
{
    if (!v->store) {
        tp_selection_keep_above(v->sel, position, clearance_m);
        return;
    }
    double x, y;
    tp_view_scene_world_to_grid(v, position[0], position[1], &x, &y);
    require_leaf(v, x, y);
    tp_cut_keep_above(v->cut, position, clearance_m);
}

void tp_view_scene_set_vertical_scale(tp_view_scene* v, double scale)
{
    /* the options and keys keep it in the core's range */
    if (v->store) { /* the cut thread's cuts take it with each selection */
        tp_cut_worker_idle(v->worker); /* its prefetch cut's setting */
        tp_cut_set_vertical_scale(v->cut_own, scale);
        tp_cut_set_vertical_scale(v->prefetch, scale);
    } else {
        tp_selection_set_vertical_scale(v->sel, scale);
    }
}

double tp_view_scene_vertical_scale(const tp_view_scene* v)
{
    return v->store ? tp_cut_vertical_scale(v->cut) : tp_selection_vertical_scale(v->sel);
}

/* PGM over a store: the most level-0 posts a measure visits (a view towards the horizon over a
 * huge store would visit them all, seconds each time; 2^26 is about a DEM the whole-pyramid path
 * can hold, 8192 x 8192). */
#define PGM_MEASURE_MAX_POSTS ((size_t)1 << 26)

void tp_view_scene_measure(const tp_view_scene* v, const tp_camera* cam, size_t max_posts,
                           double* max_m, double* rms_m, double* max_px, double* rms_px,
                           tp_view_measured_how* how)
{
    *max_m = *rms_m = NAN;
    *max_px = *rms_px = 0;
    tp_view_measured_how h;
    memset(&h, 0, sizeof h);
    h.post_share = NAN;
    if (how)
        *how = h;
    double t0 = tp_clock_ms();
    if (v->pgm) {
        tp_pgm_error e;
        tp_error err = {{0}};
        static char told[600]; /* the HUD measures once a second: each message once in a row */
        if (tp_pgm_renderer_measure(v->pgm, cam, PGM_MEASURE_MAX_POSTS, &e, &err) != TP_OK) {
            if (strcmp(err.message, told))
                tp_cli_error("%s", err.message);
            snprintf(told, sizeof told, "%s", err.message);
            *max_px = *rms_px = NAN;
            return;
        }
        told[0] = '\0';
        *max_m = e.max_m, *rms_m = e.rms_m, *max_px = e.max_px, *rms_px = e.rms_px;
        if (how)
            how->post_share = e.post_share, how->ms = tp_clock_ms() - t0;
        return;
    }
    if (v->store) {
        /* A leaf that cannot be read is left out and counted (error_leaves_skipped): the
         * stream says so once for every node it loads, and the measure reads more of them. */
        tp_error err = {{0}};
        if (tp_store_scene_measure(v->store, v->cut, cam, max_posts, 0, &h.cut_error, &err) ==
            TP_OK) {
            *max_px = h.cut_error.max_px, *rms_px = h.cut_error.rms_px; /* NaN: none measured */
            h.cut = 1;
            h.ms = tp_clock_ms() - t0;
            if (how)
                *how = h;
        } else {
            tp_cli_error("%s", err.message); /* out of memory */
            *max_px = *rms_px = NAN;
        }
        return;
    }
    tp_error_measure em = {0};
    if (v->dem && tp_selection_stitch_add(v->sel)) { /* the selection measures vertex moving */
        if (tp_stitch_add_error(v->dem->terrain, v->sel, cam, &em, max_px, rms_px) ==
            TP_OK) {
            *max_m = em.max_error_m;
            *rms_m = em.rms_error_m;
        } else {
            *max_px = *rms_px = NAN;
        }
        return;
    }
    if (tp_selection_measure_error(v->sel, &em) == TP_OK) {
        *max_m = em.max_error_m;
        *rms_m = em.rms_error_m;
    }
    tp_selection_measure_screen_error(v->sel, cam, max_px, rms_px, NULL);
}

int tp_view_scene_settle(tp_view_scene* v, const tp_camera* cam, const tp_lod_params* lod,
                         double timeout_s)
{
    if (!v->store)
        return 0;
    double t0 = tp_clock_s();
    int it = 0, idle_before = 0;
    tp_cut_worker_forget(v->worker);
    for (;;) {
        tp_error err;
        tp_cut_update(v->cut, cam, lod, &err);
        tp_stream_stats st;
        tp_stream_frame(v->store->stream, v->cut, v->prefetch, cam, lod, &st);
        tp_view_scene_report_failures(v);
        it++;
        /* Done when nothing arrived after a frame that attached nothing (so its cut saw every
         * node there was) and left nothing loading: what the cut still requests then is a node
         * that failed (its ancestor is drawn) or one the budget cannot hold. A load that
         * finishes before the stats are taken is attached by the next frame. */
        if ((st.attached == 0 && idle_before) || tp_clock_s() - t0 > timeout_s)
            break;
        idle_before = st.pending == 0 && st.attached == 0;
        if (st.attached == 0) {
            struct timespec ts = {0, 1000000};
            nanosleep(&ts, NULL);
        }
    }
    for (int round = 0; v->store->tins && round < 8; round++) {
        /* every TIN level the view asks for (--mesh tin), so that its frame shows them */
        tp_error err;
        tp_cut_update(v->cut, cam, lod, &err);
        if (tp_cut_tins_build(v->store->tins, v->cut, 0) == 0)
            break;
    }
    return it;
}

int tp_view_scene_say_once(tp_view_scene* v, const char* message)
{
    uint64_t h = 1469598103934665603u; /* FNV-1a */
    for (const char* c = message; *c; c++)
        h = (h ^ (unsigned char)*c) * 1099511628211u;
    int n = v->reported_count < 32 ? v->reported_count : 32;
    for (int i = 0; i < n; i++)
        if (v->reported[i] == h)
            return 0;
    v->reported[v->reported_count++ % 32] = h;
    return 1;
}

void tp_view_scene_report_failures(tp_view_scene* v)
{
    if (!v->store)
        return;
    const char* m;
    while ((m = tp_stream_take_failure(v->store->stream)) != NULL) {
        v->store_changed = tp_store_changed(v->store->store);
        if (v->store_changed)
            tp_cli_error("%s: the view ends", m);
        else if (tp_view_scene_say_once(v, m))
            tp_cli_error("%s (drawing its ancestor instead)", m);
        v->failures++;
        if (v->store_changed)
            break;
    }
}
