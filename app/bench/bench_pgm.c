/* bench_pgm.c - the frames of a Persistent Grid Mapping configuration (see bench.h). */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"
#include "clock.h"

#include "cli.h"
#include "pgm_render.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int tp_bench_pgm_frames(const bench_run* b, config_result* c, const char* progress)
{
    int frames = b->frames;
    const tp_render_grid* g = b->sc->grid;
    tp_pgm_pyramid p;
    tp_error err = {{0}};
    c->rows = calloc((size_t)frames, sizeof *c->rows);
    if (!c->rows) {
        tp_cli_error("out of memory");
        return TP_EXIT_FAILURE;
    }
    uint8_t* valid = NULL;
    if (tp_pgm_pyramid_from_grid(g->heights, g->width, g->height, g->geotransform, &p, &valid,
                                 &err) != TP_OK) {
        tp_cli_error("%s: the PGM pyramid: %s", b->sc->path, err.message);
        return TP_EXIT_FAILURE;
    }
    tp_pgm_renderer* r = tp_pgm_renderer_create(&p, valid, c->pgm_cols, c->pgm_rows, &err);
    free(valid); /* uploaded */
    if (!r) {
        tp_cli_error("%s: %s", b->sc->path, err.message);
        tp_pgm_pyramid_free(&p);
        return TP_EXIT_FAILURE;
    }
    tp_render_settings rs;
    tp_render_settings_default(&rs);
    tp_pgm_render_stats st;
    int every = b->o->error_every > 0 ? b->o->error_every : 1;
    for (int i = 0; i < frames; i++) {
        tp_camera cam, lead;
        if (tp_bench_frame_camera(b, i, &cam, &lead)) { /* untimed, as the patch frames' */
            tp_gl_context_begin_frame(b->ctx);
            tp_pgm_renderer_draw(r, &lead, &rs, 1, NULL, &st);
            tp_gl_context_end_frame(b->ctx);
        }
        frame_row* row = &c->rows[i];
        tp_pgm_frame f;
        tp_gl_context_begin_frame(b->ctx);
        double t0 = tp_clock_ms();
        tp_pgm_renderer_draw(r, &cam, &rs, 1, &f, &st);
        tp_gl_context_end_frame(b->ctx);
        row->frame_ms = tp_clock_ms() - t0;
        row->select_ms = st.setup_ms; /* the frame's CPU work: its uniforms */
        row->draw_ms = st.draw_ms;
        row->triangles = st.triangles;
        row->draw_calls = 1;
        row->gpu_bytes = st.gpu_bytes;
        row->max_m = row->rms_m = row->max_px = row->rms_px = row->uncovered_share = NAN;
        if (!b->o->no_error && i % every == 0) { /* outside the timed part */
            tp_pgm_error e;
            tp_camera mc = cam; /* the viewport the frame was drawn at */
            mc.viewport_w_px = b->o->vs.w;
            mc.viewport_h_px = b->o->vs.h;
            if (tp_pgm_measure_error(&f, &p, &mc, &e) != TP_OK) {
                tp_bench_progress_end();
                tp_cli_error("%s: measuring the error of frame %d: out of memory", progress, i + 1);
                tp_pgm_renderer_destroy(r);
                tp_pgm_pyramid_free(&p);
                return TP_EXIT_FAILURE;
            }
            row->max_m = e.max_m, row->rms_m = e.rms_m;
            row->max_px = e.max_px, row->rms_px = e.rms_px;
            size_t in_view = e.samples + e.uncovered;
            row->uncovered_share = in_view ? (double)e.uncovered / (double)in_view : 0;
        }
        char what[96];
        snprintf(what, sizeof what, "%.1f ms, %zu triangles", row->frame_ms, row->triangles);
        tp_bench_progress(progress, i + 1, frames, what);
    }
    tp_bench_progress_end();
    tp_pgm_renderer_destroy(r);
    tp_pgm_pyramid_free(&p);
    return TP_EXIT_OK;
}

void tp_bench_pgm_errors(config_result* c, int frames)
{
    double max_m = 0, max_px = 0, sum_m = 0, sum_px = 0, sum_uncovered = 0;
    int n = 0;
    for (int i = 0; i < frames; i++) {
        const frame_row* r = &c->rows[i];
        if (isnan(r->max_m))
            continue;
        max_m = fmax(max_m, r->max_m);
        max_px = fmax(max_px, r->max_px);
        sum_m += r->rms_m * r->rms_m;
        sum_px += r->rms_px * r->rms_px;
        sum_uncovered += r->uncovered_share;
        n++;
    }
    c->max_m = n ? max_m : NAN;
    c->max_px = n ? max_px : NAN;
    c->rms_m = n ? sqrt(sum_m / n) : NAN;
    c->rms_px = n ? sqrt(sum_px / n) : NAN;
    c->uncovered_share = n ? sum_uncovered / n : NAN;
}
