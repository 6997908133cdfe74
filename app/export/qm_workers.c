/* qm_workers.c - a level's tiles built on N threads, handed back in order (qm_workers.h). */
#include "qm_workers.h"

#include <pthread.h>
#include <stdlib.h>
#include <string.h>

#define WINDOW_PER_THREAD 4

typedef struct slot {
    int ready, ok;
    qm_tile_result r;
    tp_error err;
} slot;

struct qm_workers {
    int threads;
    qm_source* src;   /* threads sources: [0] a copy of the caller's, the others their own */
    /* one run (tp_qm_workers_run) */
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int z;
    const int* xy;
    size_t count, next, taken, window; /* next: the first tile not claimed; taken: delivered */
    double bound_m;
    int stop;
    slot* slots;      /* window of them: tile i in slots[i % window] */
};

int tp_qm_workers_threads(const qm_workers* w)
{
    return w->threads;
}

static int fail_oom(tp_error* err)
{
    tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    return 0;
}

int tp_qm_workers_create(const qm_source* s, int threads, qm_workers** out, tp_error* err)
{
    qm_workers* w = calloc(1, sizeof *w);
    if (!w || threads < 1)
        return free(w), fail_oom(err);
    w->src = calloc((size_t)threads, sizeof *w->src);
    w->slots = calloc((size_t)threads * WINDOW_PER_THREAD, sizeof *w->slots);
    if (!w->src || !w->slots) {
        free(w->src), free(w->slots), free(w);
        return fail_oom(err);
    }
    pthread_mutex_init(&w->mu, NULL);
    pthread_cond_init(&w->cv, NULL);
    w->src[0] = *s;
    w->threads = 1;
    const tp_store_scene* sc = tp_ground_scene(s->ground);
    for (int t = 1; t < threads; t++) {
        qm_source* c = &w->src[t];
        *c = *s;
        c->ground = NULL, c->geoid = NULL, c->georef = NULL;
        tp_georef* g = NULL;
        int ok = tp_ground_create(sc, NULL, &c->ground, err) == TP_OK &&
                 tp_georef_create(sc->info.header.crs_wkt, sc->info.header.geotransform, &g,
                                  err) == TP_OK &&
                 (!s->geoid || tp_geoid_open(&c->geoid, err) == TP_OK);
        c->georef = g;
        w->threads++; /* freed by destroy, whole or not */
        if (!ok) {
            tp_qm_workers_destroy(w);
            return 0;
        }
    }
    *out = w;
    return 1;
}

void tp_qm_workers_destroy(qm_workers* w)
{
    if (!w)
        return;
    for (int t = 1; t < w->threads; t++) {
        tp_ground_destroy(w->src[t].ground);
        tp_georef_destroy((tp_georef*)w->src[t].georef);
        tp_geoid_close(w->src[t].geoid);
    }
    pthread_mutex_destroy(&w->mu);
    pthread_cond_destroy(&w->cv);
    free(w->src);
    free(w->slots);
    free(w);
}

typedef struct worker_arg {
    qm_workers* w;
    const qm_source* src;
} worker_arg;

/* Claims the next tile while the window has room for it; builds it; puts it in its slot. */
static void* worker(void* p)
{
    const worker_arg* a = p;
    qm_workers* w = a->w;
    for (;;) {
        pthread_mutex_lock(&w->mu);
        while (!w->stop && w->next < w->count && w->next >= w->taken + w->window)
            pthread_cond_wait(&w->cv, &w->mu);
        if (w->stop || w->next >= w->count) {
            pthread_mutex_unlock(&w->mu);
            return NULL;
        }
        const size_t i = w->next++;
        pthread_mutex_unlock(&w->mu);
        slot s;
        memset(&s, 0, sizeof s);
        s.ok = tp_qm_tile_build(a->src, w->z, w->xy[2 * i], w->xy[2 * i + 1], w->bound_m, &s.r,
                                &s.err);
        s.ready = 1;
        pthread_mutex_lock(&w->mu);
        w->slots[i % w->window] = s;
        pthread_cond_broadcast(&w->cv);
        pthread_mutex_unlock(&w->mu);
    }
}

int tp_qm_workers_run(qm_workers* w, int z, const int* xy, size_t count, double bound_m,
                      qm_deliver_fn deliver, void* ctx, tp_error* err)
{
    if (!count)
        return 1;
    w->z = z, w->xy = xy, w->count = count, w->bound_m = bound_m;
    w->next = w->taken = 0, w->stop = 0;
    w->window = (size_t)w->threads * WINDOW_PER_THREAD;
    memset(w->slots, 0, w->window * sizeof *w->slots);
    pthread_t tid[1024];
    worker_arg args[1024];
    int started = 0;
    for (int t = 0; t < w->threads && t < 1024; t++) {
        args[t] = (worker_arg){w, &w->src[t]};
        if (pthread_create(&tid[t], NULL, worker, &args[t]) != 0)
            break;
        started++;
    }
    int result = 1;
    if (!started) {
        tp_error_set(err, TP_ERR_BACKEND, "cannot start a thread");
        return -1;
    }
    for (size_t i = 0; i < count; i++) {
        slot* s = &w->slots[i % w->window];
        pthread_mutex_lock(&w->mu);
        while (!s->ready)
            pthread_cond_wait(&w->cv, &w->mu);
        slot got = *s;
        s->ready = 0;
        pthread_mutex_unlock(&w->mu);
        const int go_on = deliver(ctx, i, got.ok, &got.r, &got.err);
        pthread_mutex_lock(&w->mu);
        w->taken = i + 1;
        w->stop = !go_on;
        pthread_cond_broadcast(&w->cv);
        pthread_mutex_unlock(&w->mu);
        if (!go_on) {
            result = 0;
            break;
        }
    }
    for (int t = 0; t < started; t++)
        pthread_join(tid[t], NULL);
    if (!result) /* the tiles built ahead of the stop: dropped */
        for (size_t k = 0; k < w->window; k++)
            if (w->slots[k].ready && w->slots[k].ok) {
                free(w->slots[k].r.gz);
                w->slots[k].ready = 0;
            }
    return result;
}
