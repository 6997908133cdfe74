/* cut_worker.c - the cut selected on a thread of its own (cut_worker.h). */
#define _POSIX_C_SOURCE 200809L
#include "cut_worker.h"
#include "clock.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>

struct tp_cut_worker {
    const tp_tree* tree;
    tp_cut* cut[2];  /* cut[front]: the frame's; the other: the worker's */
    int front;
    int have_front;
    pthread_t thread;
    pthread_mutex_t mu;
    pthread_cond_t cv;
    /* under mu */
    int busy;        /* a selection was asked for and has not finished */
    int done;        /* the back cut holds a finished selection for job */
    int quit;
    tp_camera job_cam;
    tp_cut_worker_params job;
    tp_cut* job_pre;     /* the prefetch cut to select after the cut, or NULL */
    tp_camera job_ahead;
    uint64_t job_detaches; /* tp_tree_detaches when the job was given (nothing detaches while
                              the worker selects) */
    double job_ms;
    int frames, frames_reused;
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

static void* worker_main(void* arg)
{
    tp_cut_worker* w = arg;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while (!w->busy && !w->quit)
            pthread_cond_wait(&w->cv, &w->mu);
        if (w->quit)
            break;
        tp_cut* back = w->cut[!w->front];
        tp_camera cam = w->job_cam, ahead = w->job_ahead;
        tp_cut_worker_params p = w->job;
        tp_cut* pre = w->job_pre;
        pthread_mutex_unlock(&w->mu);
        double t0 = tp_clock_ms();
        apply(back, &p);
        tp_error err;
        int ok = tp_cut_update(back, &cam, &p.lod, &err) == TP_OK;
        if (ok) /* the render thread's tp_cut_holds_for, from the figures kept here */
            tp_cut_prepare_reuse(back);
        if (pre)
            tp_cut_update_requests(pre, &ahead, &p.lod, &err);
        if (ok && p.tins)
            tp_cut_tins_build(p.tins, back, TP_CUT_WORKER_TIN_MS);
        double ms = tp_clock_ms() - t0;
        pthread_mutex_lock(&w->mu);
        w->busy = 0;
        w->done = ok;
        w->job_ms = ms;
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

/* Waits until the worker is idle; returns whether it finished a selection for p (and, take,
 * hands it over: it is offered once). */
static int wait_idle(tp_cut_worker* w, const tp_cut_worker_params* p, int take, double* worker_ms)
{
    pthread_mutex_lock(&w->mu);
    while (w->busy)
        pthread_cond_wait(&w->cv, &w->mu);
    int done = w->done && (!p || same_params(&w->job, p));
    if (take)
        w->done = 0;
    *worker_ms = w->job_ms;
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
    int done = wait_idle(w, p, 1, &st.worker_ms);
    double t1 = tp_clock_ms();
    st.wait_ms = t1 - t0;
    const tp_cut* back = w->cut[!w->front];
    /* every node it draws was resident when it was selected: still, unless one was detached */
    int kept = done && (tp_tree_detaches(w->tree) == w->job_detaches || resident(w, back));
    if (kept && tp_cut_holds_for(back, cam, NULL, &st.check_scratch)) {
        w->front = !w->front;
        st.reused = 1;
    }
    double t2 = tp_clock_ms();
    st.check_ms = done ? t2 - t1 : 0;
    w->have_front = 1;
    if (!st.reused) {
        tp_cut* c = w->cut[w->front];
        apply(c, p);
        if (tp_cut_update(c, cam, &p->lod, err) != TP_OK)
            return NULL;
        st.select_ms = tp_clock_ms() - t2;
    }
    st.frames = ++w->frames;
    st.frames_reused = w->frames_reused += st.reused;
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
    double ms;
    if (w)
        wait_idle(w, NULL, 0, &ms);
}

void tp_cut_worker_forget(tp_cut_worker* w)
{
    double ms;
    if (w)
        wait_idle(w, NULL, 1, &ms);
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
