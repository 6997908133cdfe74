/*
 * bench_store_error.c - the store bench's screen error (see bench_store.h): a frame's measure,
 * outside the timed part (tp_store_scene_measure: the leaves under the drawn nodes, read from
 * the store where the stream does not hold them, sampled to --error-posts), and its summary
 * over the flight (frames drawn with substitution apart; how much of the cut was measured);
 * and the stream's failure lines said once a run.
 */
#include "bench_store.h"
#include "cli.h"
#include "clock.h"

#include <math.h>

int tp_bench_store_measure(store_bench* b, const tp_cut* cut, const tp_camera* cam, int k,
                           store_row* row)
{
    static int told; /* a damaged leaf: once a run */
    tp_error err = {{0}};
    double t0 = tp_clock_ms();
    if (tp_store_scene_measure(&b->sc, cut, cam, (size_t)b->o->error_posts, (uint32_t)k,
                               &row->cut, &err) != TP_OK) {
        tp_bench_progress_end();
        tp_cli_error("%s: %s", b->o->dem, err.message);
        return 0;
    }
    row->measure_ms = tp_clock_ms() - t0;
    if (err.message[0] && !told++) {
        tp_bench_progress_end();
        tp_cli_warning("the screen error leaves out what cannot be read: %s", err.message);
    }
    row->measured = row->substituted ? 2 : 1;
    row->max_px = row->cut.max_px, row->rms_px = row->cut.rms_px;
    row->samples = row->cut.samples, row->skipped = row->cut.skipped;
    return 1;
}

void tp_bench_store_error_summary(store_result* c, int n, double* v)
{
    double sum_px = 0, share = 0, sum_subst = 0, post_share = 0;
    int measured = 0, timed = 0;
    c->max_px_subst = NAN;
    for (int i = 0; i < n; i++) {
        const store_row* r = &c->rows[i];
        if (!r->measured)
            continue;
        c->leaves += (double)r->cut.leaves; /* the cut's (0 for PGM), every measured frame */
        c->leaves_sampled += (double)r->cut.leaves_sampled;
        c->leaves_measured += (double)r->cut.leaves_measured;
        c->leaves_read += (double)r->cut.leaves_read;
        c->leaves_skipped += (double)r->cut.leaves_skipped;
        if (r->cut.per_node && (!c->per_node_min || r->cut.per_node < c->per_node_min))
            c->per_node_min = r->cut.per_node;
        v[timed++] = r->measure_ms;
        post_share += r->post_share;
        measured++;
        if (r->samples == 0) /* nothing in view to compare: no figure */
            continue;
        if (r->measured == 2) { /* drawn with substitution: not bounded by tau, apart */
            c->error_frames_subst++;
            c->max_px_subst = fmax(c->max_px_subst, r->max_px);
            sum_subst += r->rms_px * r->rms_px;
            continue;
        }
        c->error_frames++;
        c->max_px = fmax(c->max_px, r->max_px);
        sum_px += r->rms_px * r->rms_px;
        c->samples += (double)r->samples;
        c->skipped += (double)r->skipped;
        size_t in_view = r->samples + r->uncovered;
        share += in_view ? (double)r->uncovered / (double)in_view : 0;
    }
    c->rms_px = c->error_frames ? sqrt(sum_px / c->error_frames) : 0;
    c->rms_px_subst = c->error_frames_subst ? sqrt(sum_subst / c->error_frames_subst) : NAN;
    c->uncovered_share = c->error_frames ? share / c->error_frames : NAN;
    c->measure_ms = timed ? tp_bench_median(v, timed) : NAN;
    c->post_share = measured ? post_share / measured : NAN;
}

int tp_bench_store_said_before(store_bench* b, const char* line)
{
    uint64_t h = 1469598103934665603ull; /* FNV-1a */
    for (const char* p = line; *p; p++)
        h = (h ^ (unsigned char)*p) * 1099511628211ull;
    for (int i = 0; i < b->said_count; i++)
        if (b->said[i] == h)
            return 1;
    if (b->said_count < (int)(sizeof b->said / sizeof *b->said))
        b->said[b->said_count++] = h;
    return 0;
}
