/*
 * cut_worker.h - a store's cut selected on a thread of its own while the frame before is drawn
 * (issue 32: the render thread's CPU per frame should not grow with the map).
 *
 * A frame on the render thread:
 *   1. tp_cut_worker_frame: waits for the worker (it selects while the previous frame draws),
 *      and takes its cut when it holds for this frame's camera (tp_cut_holds_for: nothing in
 *      view culled, every bound within tau). Else, or at the first frame, or after a jump, the
 *      cut is selected here, on the render thread, as without a worker. Either way the cut
 *      returned is this frame's, valid until the next call.
 *   2. Anything that changes the tree's residency (tp_stream_frame, tp_stream_require) or the
 *      prefetch cut happens between tp_cut_worker_frame and tp_cut_worker_next, or after
 *      tp_cut_worker_idle: the worker only runs between tp_cut_worker_next and the next of
 *      those calls, and reads the tree meanwhile.
 *   3. tp_cut_worker_next: the worker starts selecting the next frame's cut for a camera
 *      predicted from the last two (tp_cut_worker_predict), while this frame draws.
 * So a frame draws a cut selected for where the camera was predicted to be, checked against
 * where it is: tau and coverage hold as for a cut selected at once (tests/test_cut.c), at the
 * cost of tp_cut_holds_for (O(drawn + culled nodes)) on the render thread instead of the cut.
 * The worker keeps, after selecting, what that check needs from its own camera
 * (tp_cut_prepare_reuse), so that the check settles a node in a few operations instead of a
 * projection (tests/test_cut_reuse.c: the same answers).
 *
 * Frame coherence (error mode): before selecting, the worker asks whether the frame's own cut
 * may simply be drawn again from the next camera (tp_cut_keep_for: tau and coverage hold there, and
 * nothing a selection reads has changed but the camera: see may_keep in cut_worker.c). Then it
 * selects nothing: a cut is selected again only when one of its nodes' bounds crosses tau,
 * something culled comes into view, a node it wanted arrives, or the camera stops (a still
 * camera gets the cut selected for it, so a still view is the cut from the roots, node for
 * node). The cost of a frame then follows what changed in the view, not the map's size
 * (docs/PERFORMANCE.md, "A cut kept while it holds"). When the cut does not hold, it is
 * carried to the next camera (tp_cut_repair: selected again only below the nodes that no
 * longer hold, stitched again only around them) unless too much changed, the camera stopped,
 * or it was carried CARRY_RENEW times since its selection from the roots (cut_worker.c).
 * TP_CUT_KEEP=0 in the environment selects every frame, as before (to measure the difference);
 * TP_CUT_CARRY=0 keeps cuts but selects from the roots whenever one is not kept.
 */
#ifndef TP_APP_CUT_WORKER_H
#define TP_APP_CUT_WORKER_H

#include "tp_core.h"

typedef struct tp_cut_worker tp_cut_worker;

/* What a cut is selected with, besides the camera. */
typedef struct tp_cut_worker_params {
    tp_lod_params lod;
    double vertical_scale; /* tp_cut_set_vertical_scale; 0 means 1 */
    int stitch_add;        /* tp_cut_set_stitch_add */
    tp_tin_cache* tins;    /* tp_cut_set_tins (NULL: lattices only); the worker builds the TIN
                              levels its cut asks for after selecting it, for up to
                              TP_CUT_WORKER_TIN_MS (they show from the next frames on) */
} tp_cut_worker_params;
#define TP_CUT_WORKER_TIN_MS 8.0
/* A TIN level not drawn for this many frames is freed (tp_tin_cache_prune); beyond
 * TP_CUT_WORKER_TIN_BYTES, those drawn longest ago are, down to what the frame draws (the
 * 20481^2 low flight held 73 MB of TINs with the age limit alone, 20 MB drawn a frame). */
#define TP_CUT_WORKER_TIN_AGE 90
#define TP_CUT_WORKER_TIN_BYTES ((size_t)32 << 20)

/* Builds the TIN levels cut asked for (tp_cut_tin_requests, most urgent first) into tins until
 * budget_ms is spent (<= 0: all of them); returns how many it built. The thread that calls it
 * is the cache's one builder; the tree's residency must not change meanwhile (cut_worker.h's
 * step 2). A level that fails to build (out of memory) is left for later. */
int tp_cut_tins_build(tp_tin_cache* tins, const tp_cut* cut, double budget_ms);

typedef struct tp_cut_worker_stats {
    int reused;        /* the frame draws the worker's cut */
    int kept;          /* ... and that is the frame before's, kept (no selection was made) */
    int carried;       /* ... or the frame before's carried to this camera (tp_cut_repair) */
    double wait_ms;    /* render thread: waiting for the worker to finish */
    double check_ms;   /* render thread: tp_cut_holds_for */
    size_t check_scratch; /* the nodes it tested from scratch (the rest were settled by the
                             figures the worker kept: tp_cut_prepare_reuse) */
    double select_ms;  /* render thread: the cut selected here (0 when reused) */
    double worker_ms;  /* the worker's job for the cut this frame was offered: its wall time */
    double worker_cpu_ms; /* ... and its thread's CPU time (the keep test or the selection, the
                             prefetch cut when asked for, TIN builds) */
    int frames, frames_reused, frames_kept, frames_carried; /* since the worker was created */
} tp_cut_worker_stats;

/* Two cuts over tree and the thread (started at once, idle until tp_cut_worker_next). NULL and
 * err without memory or without a thread. */
tp_cut_worker* tp_cut_worker_create(const tp_tree* tree, tp_error* err);
/* Stops the thread (after its selection) and frees the cuts. Accepts NULL. */
void tp_cut_worker_destroy(tp_cut_worker* w);

/* Step 1 above: the cut to draw from cam (the worker's or one selected now with p). NULL with
 * err when a selection failed (tp_cut_update's errors); the worker is idle afterwards. */
tp_cut* tp_cut_worker_frame(tp_cut_worker* w, const tp_camera* cam, const tp_cut_worker_params* p,
                            tp_cut_worker_stats* stats, tp_error* err);
/* Step 3: starts selecting for next (the camera the next frame is expected to have) and then,
 * when prefetch is not NULL, the stream's prefetch cut's requests for ahead
 * (tp_stream_prefetch_wanted): the cut for next carried there (tp_cut_repair: what it still
 * wants and what the view ahead adds), else tp_cut_update_requests. The prefetch cut is the
 * worker's until the next tp_cut_worker_frame or tp_cut_worker_idle. */
void tp_cut_worker_next(tp_cut_worker* w, const tp_camera* next, const tp_cut_worker_params* p,
                        tp_cut* prefetch, const tp_camera* ahead);
/* Waits until the worker is idle (before something outside step 2 changes the tree or a
 * setting of the prefetch cut); what it selected is still offered to the next frame, which
 * takes it only if every node it draws is still resident. Accepts NULL. */
void tp_cut_worker_idle(tp_cut_worker* w);
/* tp_cut_worker_idle, and what it selected is dropped (a jump: the next frame selects its own).
 * Accepts NULL. */
void tp_cut_worker_forget(tp_cut_worker* w);
/* The cut of the last tp_cut_worker_frame (NULL before the first). */
tp_cut* tp_cut_worker_cut(const tp_cut_worker* w);

/* The camera one frame after cur, moving as it moved from prev: positions and view vectors
 * extrapolated linearly (exact for a steady flight; tp_cut_holds_for judges the rest). */
void tp_cut_worker_predict(const tp_camera* prev, const tp_camera* cur, tp_camera* next);

#endif /* TP_APP_CUT_WORKER_H */
