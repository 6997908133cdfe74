/* imagery_cache.c - blocks of an image pyramid in memory (see imagery_cache.h). */
#define _POSIX_C_SOURCE 200809L
#include "imagery_cache.h"

#include <errno.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { E_FREE, E_LOADING, E_READY, E_FAILED };

typedef struct entry {
    uint64_t key;
    int state;
    int next; /* hash chain, -1 ends */
} entry;

struct tp_imagery_cache {
    tp_block_source src;
    size_t block_bytes;
    int cap;
    uint8_t* pool;       /* cap buffers of block_bytes */
    entry* e;
    int* bucket;         /* heads of the chains, -1 empty */
    unsigned bits;
    int* free_list;
    int free_count;

    pthread_mutex_t mu;
    pthread_cond_t cv;   /* the loader waits for work or a free buffer */
    pthread_cond_t done; /* a read finished */
    tp_block_key* queue;
    size_t queue_len, queue_head, queue_cap;
    int in_flight;
    int stop;
    pthread_t thread;
    int thread_started;

    size_t loads, evictions;
    int failed;
    char failure[512];
    int failure_pending;
    char failure_out[512];
};

static uint64_t pack(tp_block_key k)
{
    return ((uint64_t)k.level << 58) | ((uint64_t)k.bx << 29) | (uint64_t)k.by;
}

static unsigned hash(const tp_imagery_cache* c, uint64_t key)
{
    return (unsigned)((key * 0x9E3779B97F4A7C15ull) >> (64 - c->bits));
}

static int find(const tp_imagery_cache* c, uint64_t key)
{
    for (int i = c->bucket[hash(c, key)]; i >= 0; i = c->e[i].next)
        if (c->e[i].key == key)
            return i;
    return -1;
}

/* A free buffer for key, in the table as LOADING; -1 when none is free. */
static int take(tp_imagery_cache* c, uint64_t key)
{
    if (c->free_count == 0)
        return -1;
    int i = c->free_list[--c->free_count];
    unsigned h = hash(c, key);
    c->e[i].key = key;
    c->e[i].state = E_LOADING;
    c->e[i].next = c->bucket[h];
    c->bucket[h] = i;
    return i;
}

static void give_back(tp_imagery_cache* c, int i)
{
    int* p = &c->bucket[hash(c, c->e[i].key)];
    while (*p != i)
        p = &c->e[*p].next;
    *p = c->e[i].next;
    c->e[i].state = E_FREE;
    c->free_list[c->free_count++] = i;
}

/* Reads into buffer i (the lock not held); back under the lock, marks it read or failed. */
static void read_into(tp_imagery_cache* c, int i, tp_block_key k)
{
    c->in_flight++;
    pthread_mutex_unlock(&c->mu);
    tp_error err = {{0}};
    uint8_t* px = c->pool + (size_t)i * c->block_bytes;
    int ok = c->src.read(c->src.user, k, px, &err);
    if (!ok)
        memset(px, 0, c->block_bytes); /* a damaged block shows as no imagery */
    pthread_mutex_lock(&c->mu);
    c->in_flight--;
    c->loads++;
    c->e[i].state = ok ? E_READY : E_FAILED;
    if (!ok) {
        c->failed++;
        if (!c->failure_pending) {
            snprintf(c->failure, sizeof c->failure, "%s", err.message);
            c->failure_pending = 1;
        }
    }
    pthread_cond_broadcast(&c->done);
}

static tp_block_key unpack(uint64_t key)
{
    tp_block_key k = {(int)(key >> 58), (int64_t)((key >> 29) & 0x1FFFFFFF),
                      (int64_t)(key & 0x1FFFFFFF)};
    return k;
}

static void* loader_main(void* arg)
{
    tp_imagery_cache* c = arg;
    pthread_mutex_lock(&c->mu);
    for (;;) {
        while (!c->stop && (c->queue_head == c->queue_len || c->free_count == 0))
            pthread_cond_wait(&c->cv, &c->mu);
        if (c->stop)
            break;
        uint64_t key = pack(c->queue[c->queue_head++]);
        if (find(c, key) >= 0)
            continue;
        read_into(c, take(c, key), unpack(key));
    }
    pthread_mutex_unlock(&c->mu);
    return NULL;
}

tp_imagery_cache* tp_imagery_cache_create(const tp_block_source* src, size_t budget_bytes,
                                          int no_loader, tp_error* err)
{
    tp_imagery_cache* c = calloc(1, sizeof *c);
    if (!c) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    c->src = *src;
    c->block_bytes = (size_t)src->block * src->block * 4;
    size_t n = budget_bytes / c->block_bytes;
    c->cap = (int)(n < 16 ? 16 : n > (1u << 20) ? (1u << 20) : n);
    c->bits = 1;
    while ((1u << c->bits) < 2u * (unsigned)c->cap)
        c->bits++;
    c->pool = malloc((size_t)c->cap * c->block_bytes);
    c->e = calloc((size_t)c->cap, sizeof *c->e);
    c->bucket = malloc(sizeof *c->bucket << c->bits);
    c->free_list = malloc((size_t)c->cap * sizeof *c->free_list);
    if (!c->pool || !c->e || !c->bucket || !c->free_list) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory for %d imagery blocks (%.0f MB)",
                     c->cap, c->cap * (double)c->block_bytes / 1e6);
        free(c->pool), free(c->e), free(c->bucket), free(c->free_list), free(c);
        return NULL;
    }
    memset(c->bucket, 0xff, sizeof *c->bucket << c->bits);
    for (int i = 0; i < c->cap; i++)
        c->free_list[i] = c->cap - 1 - i;
    c->free_count = c->cap;
    pthread_mutex_init(&c->mu, NULL);
    pthread_cond_init(&c->cv, NULL);
    pthread_cond_init(&c->done, NULL);
    if (!no_loader) {
        if (pthread_create(&c->thread, NULL, loader_main, c) != 0) {
            tp_error_set(err, TP_ERR_BACKEND, "cannot start the imagery loader thread");
            tp_imagery_cache_destroy(c);
            return NULL;
        }
        c->thread_started = 1;
    }
    return c;
}

void tp_imagery_cache_destroy(tp_imagery_cache* c)
{
    if (!c)
        return;
    if (c->thread_started) {
        pthread_mutex_lock(&c->mu);
        c->stop = 1;
        pthread_cond_broadcast(&c->cv);
        pthread_mutex_unlock(&c->mu);
        pthread_join(c->thread, NULL);
    }
    pthread_mutex_destroy(&c->mu);
    pthread_cond_destroy(&c->cv);
    pthread_cond_destroy(&c->done);
    free(c->queue);
    free(c->pool);
    free(c->e);
    free(c->bucket);
    free(c->free_list);
    free(c);
}

void tp_imagery_cache_want(tp_imagery_cache* c, const tp_block_key* keys, size_t count)
{
    pthread_mutex_lock(&c->mu);
    if (count > c->queue_cap) {
        tp_block_key* q = realloc(c->queue, count * sizeof *q);
        if (q) {
            c->queue = q;
            c->queue_cap = count;
        } else {
            count = c->queue_cap; /* out of memory: want fewer */
        }
    }
    c->queue_len = c->queue_head = 0;
    for (size_t i = 0; i < count; i++)
        if (find(c, pack(keys[i])) < 0)
            c->queue[c->queue_len++] = keys[i];
    pthread_cond_signal(&c->cv);
    pthread_mutex_unlock(&c->mu);
}

const uint8_t* tp_imagery_cache_get(tp_imagery_cache* c, tp_block_key k)
{
    pthread_mutex_lock(&c->mu);
    int i = find(c, pack(k));
    int ready = i >= 0 && (c->e[i].state == E_READY || c->e[i].state == E_FAILED);
    pthread_mutex_unlock(&c->mu);
    return ready ? c->pool + (size_t)i * c->block_bytes : NULL;
}

const uint8_t* tp_imagery_cache_load_now(tp_imagery_cache* c, tp_block_key k)
{
    uint64_t key = pack(k);
    pthread_mutex_lock(&c->mu);
    int i = find(c, key);
    if (i < 0 && (i = take(c, key)) >= 0)
        read_into(c, i, k);
    else
        while (i >= 0 && c->e[i].state == E_LOADING)
            pthread_cond_wait(&c->done, &c->mu);
    pthread_mutex_unlock(&c->mu);
    return i >= 0 ? c->pool + (size_t)i * c->block_bytes : NULL;
}

typedef struct scored {
    double score;
    int index;
} scored;

static int by_score(const void* a, const void* b)
{
    double x = ((const scored*)a)->score, y = ((const scored*)b)->score;
    return (x > y) - (x < y);
}

void tp_imagery_cache_collect(tp_imagery_cache* c, double (*score)(void* user, tp_block_key k),
                              void* user, double keep_score)
{
    pthread_mutex_lock(&c->mu);
    int target = c->cap / 4;
    if (c->free_count >= target) {
        pthread_mutex_unlock(&c->mu);
        return;
    }
    scored* s = malloc((size_t)c->cap * sizeof *s);
    size_t n = 0;
    for (int i = 0; s && i < c->cap; i++) {
        if (c->e[i].state != E_READY && c->e[i].state != E_FAILED)
            continue;
        double v = score(user, unpack(c->e[i].key));
        if (v < keep_score)
            s[n++] = (scored){v, i};
    }
    if (s) {
        qsort(s, n, sizeof *s, by_score);
        for (size_t j = 0; j < n && c->free_count < target; j++) {
            give_back(c, s[j].index);
            c->evictions++;
        }
        free(s);
    }
    pthread_cond_signal(&c->cv);
    pthread_mutex_unlock(&c->mu);
}

static int pending_locked(const tp_imagery_cache* c)
{
    return (int)(c->queue_len - c->queue_head) + c->in_flight;
}

int tp_imagery_cache_wait(tp_imagery_cache* c, double timeout_s)
{
    struct timespec until;
    clock_gettime(CLOCK_REALTIME, &until);
    double t = until.tv_sec + until.tv_nsec / 1e9 + timeout_s;
    until.tv_sec = (time_t)t;
    until.tv_nsec = (long)((t - (double)until.tv_sec) * 1e9);
    pthread_mutex_lock(&c->mu);
    int timed_out = 0;
    while (pending_locked(c) > 0 && !timed_out && (c->thread_started || c->in_flight > 0))
        timed_out = pthread_cond_timedwait(&c->done, &c->mu, &until) == ETIMEDOUT;
    int idle = pending_locked(c) == 0;
    pthread_mutex_unlock(&c->mu);
    return idle;
}

const char* tp_imagery_cache_take_failure(tp_imagery_cache* c)
{
    pthread_mutex_lock(&c->mu);
    const char* r = NULL;
    if (c->failure_pending) {
        memcpy(c->failure_out, c->failure, sizeof c->failure_out);
        c->failure_pending = 0;
        r = c->failure_out;
    }
    pthread_mutex_unlock(&c->mu);
    return r;
}

void tp_imagery_cache_get_stats(const tp_imagery_cache* c, tp_imagery_cache_stats* out)
{
    tp_imagery_cache* m = (tp_imagery_cache*)c; /* the lock only */
    pthread_mutex_lock(&m->mu);
    out->capacity_blocks = (size_t)c->cap;
    out->resident_blocks = (size_t)(c->cap - c->free_count);
    out->block_bytes = c->block_bytes;
    out->loads = c->loads;
    out->evictions = c->evictions;
    out->pending = pending_locked(c);
    out->failed = c->failed;
    pthread_mutex_unlock(&m->mu);
}
