/* cut_worker.c - the cut selected on a thread of its own (cut_worker.h). */
#define _POSIX_C_SOURCE 200809L
#include "cut_worker.h"
#include "clock.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A kept cut's figures are kept again from the new camera when more than 1 in KEEP_RENEW of
 * its drawn nodes needed a test from scratch. */
enum { KEEP_RENEW = 32 };

/* A cut that wants nodes it found missing is kept for this many jobs at most (a quarter of a
 * second at 30 Hz): its requests are those of its own camera. */
enum { KEEP_WANTING = 8 };

/* A cut is carried to another camera (tp_cut_repair) this many times at most before it is
 * selected from the roots again: a carried cut keeps the levels of what it did not select
 * again, finer than needed where the camera moved away. */
enum { CARRY_RENEW = 16 };

/* What a cut's last selection was made with: whether it may be kept for another camera. */
typedef struct selected {
    int valid;
    tp_camera cam;
    tp_cut_worker_params params;
    uint64_t detaches;           /* the tree's count when it was selected (or last found
                                    resident) */
    int figures;                 /* tp_cut_holds_for's figures are kept (prepare, keep_for) */
    int kept;                    /* jobs it was kept for since */
    int carried;                 /* times it was carried (tp_cut_repair) since the roots */
} selected;

struct tp_cut_worker {
    const tp_tree* tree;
    tp_cut* cut[2];  /* cut[front]: the frame's; the other: the worker's */
    selected sel[2]; /* of each cut */
    int front;
    int have_front;
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    /* under mu */
    int busy;        /* a selection was asked for and has not finished */
    int done;        /* a finished job for job: the back cut, or the front one kept */
    int kept;        /* the job kept the front cut for job_cam (no selection) */
    int carried;     /* the job carried the front cut to job_cam (tp_cut_repair) */
    int quit;
    tp_camera job_cam;
    tp_cut_worker_params job;
    int job_front;       /* the frame's cut when the job was given (-1: none yet) */
    tp_cut* job_pre;     /* the prefetch cut to select after the cut, or NULL */
    tp_camera job_ahead;
    uint64_t job_detaches; /* tp_tree_detaches when the job was given (nothing detaches while
                              the worker selects) */
    int job_stopped;     /* job_cam is the last frame's camera: the camera has stopped */
    tp_camera frame_cam; /* the last frame's camera (render thread) */
    double job_ms, job_cpu_ms;
    int frames, frames_reused, frames_kept, frames_carried;
    int may_keep;        /* TP_CUT_KEEP (cut_worker.h) */
    int may_carry;       /* TP_CUT_CARRY (cut_worker.h) */
};

static void apply(tp_cut* c, const tp_cut_worker_params* p)
{
    tp_cut_set_vertical_scale(c, p->vertical_scale > 0 ? p->vertical_scale : 1);
    tp_cut_set_stitch_add(c, p->stitch_add);
    tp_cut_set_tins(c, p->tins);
}

int tp_cut_tins_build(tp_tin_cache* tins, const tp_cut* cut, double budget_ms)
{
    size_t count;
    const tp_cut_tin_request* rq = tp_cut_tin_requests(cut, &count);
    double t0 = tp_clock_ms();
    int built = 0;
    for (size_t i = 0; i < count; i++) {
        if (budget_ms > 0 && tp_clock_ms() - t0 >= budget_ms)
            break;
        tp_error err;
        built += tp_tin_cache_build(tins, rq[i].node, rq[i].level, &err) == TP_OK;
    }
    return built;
}

static int same_params(const tp_cut_worker_params* a, const tp_cut_worker_params* b);
static int resident(const tp_cut_worker* w, const tp_cut* c);

static int same_camera(const tp_camera* a, const tp_camera* b)
{
    for (int k = 0; k < 3; k++)
        if (a->position[k] != b->position[k] || a->forward[k] != b->forward[k] ||
            a->up[k] != b->up[k])
            return 0;
    return a->fov_y_rad == b->fov_y_rad && a->viewport_w_px == b->viewport_w_px &&
           a->viewport_h_px == b->viewport_h_px && a->near_m == b->near_m && a->far_m == b->far_m;
}

/* Whether cut i, selected earlier, may be drawn for cam with p instead of a new selection: it
 * holds for cam (tp_cut_keep_for: tau and coverage; it also keeps its figures from cam for the
 * frame's own check), and a selection for cam could differ only where the camera moved:
 *   - the error mode (tau is what a cut keeps; the distance mode's levels follow the distance
 *     itself) and the same parameters;
 *   - no node it wanted and found missing (tp_cut_requests) has arrived: a selection refines a
 *     node only when all its children in view are resident and asks for every one missing, so
 *     while none arrives it refines the same nodes. What it asks the stream for is that of its
 *     selection, though (a child coming into view is not asked for): a cut that wants nodes is
 *     kept for KEEP_WANTING jobs at most;
 *   - no TIN level it asked for is waiting (the worker builds them after selecting);
 *   - every node it draws is still resident;
 *   - the camera has not stopped: a camera equal to the last frame's gets the cut selected
 *     for it from the roots, so that a still view settles on the cut from the roots.
 * Runs on the worker while the frame draws cut i: it reads it, and writes only the figures that
 * tp_cut_holds_for reads, which the render thread calls after waiting for the worker. */
static int may_keep(tp_cut_worker* w, int i, const tp_camera* cam, const tp_cut_worker_params* p,
                    int stopped)
{
    selected* s = &w->sel[i];
    tp_cut* c = w->cut[i];
    size_t wanted, tins = 0;
    if (!s->valid || p->lod.mode != TP_LOD_ERROR || !same_params(&s->params, p) ||
        (stopped && (!same_camera(cam, &s->cam) || s->carried)))
        return 0;
    const int64_t* want = tp_cut_requests(c, &wanted);
    if (p->tins)
        tp_cut_tin_requests(c, &tins);
    if (tins || (wanted && s->kept >= KEEP_WANTING))
        return 0;
    for (size_t k = 0; k < wanted; k++)
        if (tp_tree_samples(w->tree, want[k]))
            return 0;
    uint64_t detaches = tp_tree_detaches(w->tree);
    if (detaches != s->detaches) {
        if (!resident(w, c))
            return 0;
        s->detaches = detaches;
    }
    /* The figures the frame's own check used, from the camera they were kept for, settle most
     * nodes in a few operations (and their answer is the test's: a refusal is final); when too
     * many need a test from scratch, they are kept again from cam (one projection a node), for
     * this test and the frame's. */
    size_t drawn, scratch;
    tp_cut_nodes(c, &drawn);
    if (s->figures) {
        if (!tp_cut_holds_for(c, cam, NULL, &scratch))
            return 0;
        if (scratch * KEEP_RENEW <= drawn)
            return 1;
    }
    s->figures = 1;
    return tp_cut_keep_for(c, cam);
}

static void selected_now(tp_cut_worker* w, int i, const tp_camera* cam,
                         const tp_cut_worker_params* p, uint64_t detaches, int figures,
                         int carried)
{
    w->sel[i] = (selected){1, *cam, *p, detaches, figures, 0, carried};
}

/* Whether the job may carry cut i to its camera with p instead of selecting from the roots (it
 * was not kept): the same parameters, error mode, lattices only with vertex moving (as
 * tp_cut_repair asks), a camera that has not stopped (a still view gets the cut from the
 * roots), and fewer than CARRY_RENEW carries since the roots. tp_cut_repair itself selects
 * again where the cut does not hold, takes in what arrived, and refuses what changed too much
 * or a node no longer resident. */
static int may_carry(const tp_cut_worker* w, int i, const tp_cut_worker_params* p, int stopped)
{
    const selected* s = &w->sel[i];
    return s->valid && p->lod.mode == TP_LOD_ERROR && same_params(&s->params, p) && !stopped &&
           s->carried < CARRY_RENEW && !p->tins && !p->stitch_add;
}

static void* worker_main(void* arg)
{
    tp_cut_worker* w = arg;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while (!w->busy && !w->quit)
            pthread_cond_wait(&w->cv, &w->mu);
        if (w->quit)
            break;
        int fi = w->job_front, bi = fi < 0 ? 1 : !fi;
        tp_cut* back = w->cut[bi];
        tp_camera cam = w->job_cam, ahead = w->job_ahead;
        tp_cut_worker_params p = w->job;
        tp_cut* pre = w->job_pre;
        int stopped = w->job_stopped;
        pthread_mutex_unlock(&w->mu);
        double t0 = tp_clock_ms(), c0 = tp_clock_thread_cpu_ms();
        int kept = fi >= 0 && w->may_keep && may_keep(w, fi, &cam, &p, stopped), ok = 1;
        int carried = 0;
        w->sel[fi < 0 ? 0 : fi].kept += kept;
        if (!kept) {
            apply(back, &p);
            carried = fi >= 0 && w->may_carry && may_carry(w, fi, &p, stopped) &&
                      tp_cut_repair(back, w->cut[fi], &cam);
            tp_error err;
            if (!carried)
                ok = tp_cut_update(back, &cam, &p.lod, &err) == TP_OK;
            int carries = carried ? w->sel[fi].carried + 1 : 0;
            w->sel[bi].valid = 0;
            if (ok) { /* the render thread's tp_cut_holds_for, from the figures kept here */
                int figures = tp_cut_prepare_reuse(back);
                selected_now(w, bi, &cam, &p, tp_tree_detaches(w->tree), figures, carries);
            }
        }
        if (pre) { /* carried from the cut for cam when it can be, as the cut itself is */
            tp_error err;
            const tp_cut* now = kept ? w->cut[fi] : back;
            int carried_pre = ok && w->may_carry && p.lod.mode == TP_LOD_ERROR && !p.tins &&
                              !p.stitch_add && tp_cut_repair(pre, now, &ahead);
            if (!carried_pre)
                tp_cut_update_requests(pre, &ahead, &p.lod, &err);
        }
        if (ok && !kept && p.tins)
            tp_cut_tins_build(p.tins, back, TP_CUT_WORKER_TIN_MS);
        double ms = tp_clock_ms() - t0, cpu = tp_clock_thread_cpu_ms() - c0;
        pthread_mutex_lock(&w->mu);
        w->busy = 0;
        w->done = ok;
        w->kept = kept;
        w->carried = carried;
        w->job_ms = ms, w->job_cpu_ms = cpu;
        pthread_cond_broadcast(&w->cv);
    }
    pthread_mutex_unlock(&w->mu);
    return NULL;
}

tp_cut_worker* tp_cut_worker_create(const tp_tree* tree, tp_error* err)
{
    tp_cut_worker* w = calloc(1, sizeof *w);
    if (!w) {
        snprintf(err->message, sizeof err->message, "cut worker: out of memory");
        return NULL;
    }
    w->tree = tree;
    const char* keep = getenv("TP_CUT_KEEP");
    w->may_keep = !(keep && strcmp(keep, "0") == 0);
    const char* carry = getenv("TP_CUT_CARRY");
    w->may_carry = w->may_keep && !(carry && strcmp(carry, "0") == 0);
    if (tp_cut_create(tree, &w->cut[0], err) != TP_OK ||
        tp_cut_create(tree, &w->cut[1], err) != TP_OK) {
        tp_cut_destroy(w->cut[0]);
        free(w);
        return NULL;
    }
    pthread_mutex_init(&w->mu, NULL);
    pthread_cond_init(&w->cv, NULL);
    if (pthread_create(&w->thread, NULL, worker_main, w) != 0) {
        snprintf(err->message, sizeof err->message, "cut worker: cannot start a thread");
        pthread_mutex_destroy(&w->mu);
        pthread_cond_destroy(&w->cv);
        tp_cut_destroy(w->cut[0]);
        tp_cut_destroy(w->cut[1]);
        free(w);
        return NULL;
    }
    return w;
}

void tp_cut_worker_destroy(tp_cut_worker* w)
{
    if (!w)
        return;
    pthread_mutex_lock(&w->mu);
    w->quit = 1;
    pthread_cond_broadcast(&w->cv);
    pthread_mutex_unlock(&w->mu);
    pthread_join(w->thread, NULL);
    pthread_mutex_destroy(&w->mu);
    pthread_cond_destroy(&w->cv);
    tp_cut_destroy(w->cut[0]);
    tp_cut_destroy(w->cut[1]);
    free(w);
}

static int same_params(const tp_cut_worker_params* a, const tp_cut_worker_params* b)
{
    const tp_lod_params *x = &a->lod, *y = &b->lod;
    return x->mode == y->mode && x->mindist_m == y->mindist_m && x->maxdist_m == y->maxdist_m &&
           x->exponent == y->exponent && x->tau_px == y->tau_px && x->hole_px == y->hole_px &&
           x->sphere_tree == y->sphere_tree && a->vertical_scale == b->vertical_scale &&
           a->stitch_add == b->stitch_add && a->tins == b->tins;
}

/* Waits until the worker is idle; returns whether it finished a job for p (and, take, hands
 * it over: it is offered once; *kept: the job kept the front cut). */
static int wait_idle(tp_cut_worker* w, const tp_cut_worker_params* p, int take,
                     tp_cut_worker_stats* st)
{
    pthread_mutex_lock(&w->mu);
    while (w->busy)
        pthread_cond_wait(&w->cv, &w->mu);
    int done = w->done && (!p || same_params(&w->job, p));
    if (take)
        w->done = 0;
    st->worker_ms = w->job_ms, st->worker_cpu_ms = w->job_cpu_ms;
    st->kept = done && w->kept;
    st->carried = done && w->carried;
    pthread_mutex_unlock(&w->mu);
    return done;
}

/* Whether every node cut c draws is resident (the stream may have released one since). */
static int resident(const tp_cut_worker* w, const tp_cut* c)
{
    size_t count;
    const tp_cut_node* nodes = tp_cut_nodes(c, &count);
    for (size_t i = 0; i < count; i++)
        if (!tp_tree_samples(w->tree, nodes[i].node))
            return 0;
    return 1;
}

tp_cut* tp_cut_worker_frame(tp_cut_worker* w, const tp_camera* cam, const tp_cut_worker_params* p,
                            tp_cut_worker_stats* stats, tp_error* err)
{
    tp_cut_worker_stats st = {0};
    double t0 = tp_clock_ms();
    int done = wait_idle(w, p, 1, &st);
    double t1 = tp_clock_ms();
    st.wait_ms = t1 - t0;
    int ci = st.kept ? w->front : !w->front; /* the cut the worker offers */
    const tp_cut* offered = w->cut[ci];
    /* every node it draws was resident when the job was given: still, unless one was
     * detached */
    int ok = done && (tp_tree_detaches(w->tree) == w->job_detaches || resident(w, offered));
    if (ok && tp_cut_holds_for(offered, cam, NULL, &st.check_scratch)) {
        w->front = ci;
        st.reused = 1;
    }
    st.kept &= st.reused;
    st.carried &= st.reused;
    w->frame_cam = *cam;
    double t2 = tp_clock_ms();
    st.check_ms = done ? t2 - t1 : 0;
    w->have_front = 1;
    if (!st.reused) {
        tp_cut* c = w->cut[w->front];
        apply(c, p);
        w->sel[w->front].valid = 0;
        if (tp_cut_update(c, cam, &p->lod, err) != TP_OK)
            return NULL;
        selected_now(w, w->front, cam, p, tp_tree_detaches(w->tree), 0, 0);
        st.select_ms = tp_clock_ms() - t2;
    }
    st.frames = ++w->frames;
    st.frames_reused = w->frames_reused += st.reused;
    st.frames_kept = w->frames_kept += st.kept;
    st.frames_carried = w->frames_carried += st.carried;
    if (stats)
        *stats = st;
    return w->cut[w->front];
}

void tp_cut_worker_next(tp_cut_worker* w, const tp_camera* next, const tp_cut_worker_params* p,
                        tp_cut* prefetch, const tp_camera* ahead)
{
    pthread_mutex_lock(&w->mu);
    w->job_cam = *next;
    w->job = *p;
    w->job_detaches = tp_tree_detaches(w->tree);
    w->job_front = w->have_front ? w->front : -1;
    w->job_stopped = w->have_front && same_camera(next, &w->frame_cam);
    w->job_pre = prefetch;
    if (prefetch)
        w->job_ahead = *ahead;
    w->busy = 1;
    w->done = 0;
    pthread_cond_broadcast(&w->cv);
    pthread_mutex_unlock(&w->mu);
}

void tp_cut_worker_idle(tp_cut_worker* w)
{
    tp_cut_worker_stats st;
    if (w)
        wait_idle(w, NULL, 0, &st);
}

void tp_cut_worker_forget(tp_cut_worker* w)
{
    tp_cut_worker_stats st;
    if (w)
        wait_idle(w, NULL, 1, &st);
}

tp_cut* tp_cut_worker_cut(const tp_cut_worker* w)
{
    return w->have_front ? w->cut[w->front] : NULL;
}

void tp_cut_worker_predict(const tp_camera* prev, const tp_camera* cur, tp_camera* next)
{
    *next = *cur;
    for (int a = 0; a < 3; a++) {
        next->position[a] += cur->position[a] - prev->position[a];
        next->forward[a] += cur->forward[a] - prev->forward[a];
        next->up[a] += cur->up[a] - prev->up[a];
    }
}
