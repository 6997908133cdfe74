/* stream.c - the loader thread and the node budget (see stream.h). */
#define _POSIX_C_SOURCE 200809L
#include "stream.h"
#include "clock.h"
#include "prefetch.h"

#include <assert.h>
#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

enum { ST_NONE = 0, ST_QUEUED, ST_LOADING, ST_RESIDENT, ST_FAILED };

/* A resident node. */
typedef struct resident {
    int64_t node;
    uint16_t* block;
    uint64_t used;       /* last frame it was drawn or was an ancestor of a drawn node */
    int children;        /* resident children: only childless nodes are released */
    int root;
    double score;        /* release order, filled when releasing */
} resident;

/* A finished read, handed from the loader to the render thread. */
typedef struct done {
    int64_t node;
    uint16_t* block;     /* NULL when the read failed */
    int transient;       /* the read failed on the way (TP_ERR_IO, the store unchanged): retried */
    char msg[sizeof(((tp_error*)0)->message)];
} done;

/* A node whose read failed on the way (an HTTP error, a reset, a stall): asked for again after
 * a backoff of 0.5 s doubling with each attempt up to 30 s. */
typedef struct retry {
    int64_t node;
    double at_ms;        /* on the stream's clock */
    int attempts;
} retry;

enum { MAX_LOADERS = 16 };

struct tp_stream {
    const tp_store* store;
    tp_tree* tree;
    tp_store_info info;
    const tp_tree_geometry* g;
    size_t block_samples, block_bytes, budget;
    double prefetch_s;
    uint8_t* state;      /* per node, ST_* (render thread; the loader only reads ST_QUEUED) */
    int32_t* res_index;  /* per node: index into res, or -1 */
    resident* res;
    size_t res_count, res_cap;
    uint64_t frame;
    double last_pos[3];
    double last_time_ms;
    int have_last;
    double frame_s;      /* > 0: the clock advances by this much per frame (tp_stream_options) */
    double clock_ms;     /* that clock */

    /* The prefetch cut of the last update (its requests stay valid until the next one). */
    const tp_cut* pre_cut;
    double pre_at[3];    /* where its camera stood */
    double pre_fwd[3];   /* and looked */
    int pre_async;       /* tp_stream_set_prefetch_async */
    int pre_job;         /* async: the prefetch cut is to be selected for pre_job_cam */
    tp_camera pre_job_cam;

    /* shared with the loader, under mu */
    pthread_mutex_t mu;
    pthread_cond_t cv;
    int64_t* queue;      /* node ids, most urgent first */
    size_t queue_len, queue_head, queue_cap;
    done* done_list;
    size_t done_len, done_cap;
    int in_flight;
    size_t bytes_total;  /* resident + being read */
    int stop;
    pthread_t threads[MAX_LOADERS];
    int threads_started;

    retry* retries;      /* render thread */
    size_t retry_len, retry_cap;

    char failure[sizeof(((tp_error*)0)->message)];
    int failure_pending;
    int failed;
    tp_stream_stats last;
};

static int push_done(tp_stream* s, int64_t node, uint16_t* block, const char* msg,
                     int transient)
{
    if (s->done_len == s->done_cap) {
        size_t cap = s->done_cap ? 2 * s->done_cap : 64;
        done* d = realloc(s->done_list, cap * sizeof *d);
        if (!d)
            return 0;
        s->done_list = d;
        s->done_cap = cap;
    }
    done* d = &s->done_list[s->done_len++];
    d->node = node;
    d->block = block;
    d->transient = transient;
    d->msg[0] = '\0';
    if (msg)
        snprintf(d->msg, sizeof d->msg, "%s", msg);
    return 1;
}

/* Over HTTP a loader takes up to this many queued nodes at a time and reads them ahead in one
 * batch of concurrent requests (tp_store_prefetch: neighbours in the file merged), then decodes
 * them one by one: many more requests in flight than loaders. */
enum { REMOTE_BATCH = 8 };

/* Reads and decodes node (taken from the queue, counted in flight) and hands it over; called
 * and returns with s->mu held. */
static void load_taken(tp_stream* s, int64_t node)
{
    pthread_mutex_unlock(&s->mu);
    tp_error err;
    uint16_t* block = malloc(s->block_bytes);
    const char* msg = NULL;
    int transient = 0;
    tp_status st = TP_OK;
    if (!block)
        msg = "out of memory for a node";
    else if ((st = tp_store_read_node(s->store, node, block, s->block_samples, &err)) != TP_OK) {
        free(block);
        block = NULL;
        msg = err.message;
        transient = st == TP_ERR_IO && !tp_store_changed(s->store);
    }
    pthread_mutex_lock(&s->mu);
    s->in_flight--;
    if (!block)
        s->bytes_total -= s->block_bytes;
    if (!push_done(s, node, block, msg, transient)) {
        free(block);
        if (block)
            s->bytes_total -= s->block_bytes;
    }
}

static void* loader_main(void* arg)
{
    tp_stream* s = arg;
    const int batch = s->info.remote ? REMOTE_BATCH : 1;
    int64_t taken[REMOTE_BATCH];
    pthread_mutex_lock(&s->mu);
    for (;;) {
        while (!s->stop && (s->queue_head == s->queue_len || s->bytes_total + s->block_bytes > s->budget))
            pthread_cond_wait(&s->cv, &s->mu);
        if (s->stop)
            break;
        int k = 0;
        while (k < batch && s->queue_head < s->queue_len &&
               s->bytes_total + s->block_bytes <= s->budget) {
            taken[k++] = s->queue[s->queue_head++];
            s->in_flight++;
            s->bytes_total += s->block_bytes;
        }
        if (k > 1) {
            pthread_mutex_unlock(&s->mu);
            tp_store_prefetch(s->store, taken, (size_t)k);
            pthread_mutex_lock(&s->mu);
        }
        for (int i = 0; i < k; i++)
            load_taken(s, taken[i]);
    }
    pthread_mutex_unlock(&s->mu);
    return NULL;
}

static int add_resident(tp_stream* s, int64_t node, uint16_t* block, int root)
{
    if (s->res_count == s->res_cap) {
        size_t cap = s->res_cap ? 2 * s->res_cap : 256;
        resident* r = realloc(s->res, cap * sizeof *r);
        if (!r)
            return 0;
        s->res = r;
        s->res_cap = cap;
    }
    resident* r = &s->res[s->res_count];
    r->node = node;
    r->block = block;
    r->used = s->frame;
    r->children = 0;
    r->root = root;
    s->res_index[node] = (int32_t)s->res_count++;
    s->state[node] = ST_RESIDENT;
    int64_t parent = tp_tree_node_parent(s->g, node);
    if (parent >= 0 && s->res_index[parent] >= 0)
        s->res[s->res_index[parent]].children++;
    tp_tree_attach(s->tree, node, block);
    return 1;
}

/* Releases resident entry i (childless, not a root). */
static void release(tp_stream* s, size_t i)
{
    resident* r = &s->res[i];
    int64_t node = r->node;
    tp_tree_detach(s->tree, node);
    free(r->block);
    int64_t parent = tp_tree_node_parent(s->g, node);
    if (parent >= 0 && s->res_index[parent] >= 0)
        s->res[s->res_index[parent]].children--;
    s->res_index[node] = -1;
    s->state[node] = ST_NONE;
    s->res[i] = s->res[--s->res_count];
    if (i < s->res_count)
        s->res_index[s->res[i].node] = (int32_t)i;
}

/* Reads a node on this thread and attaches it. */
static int load_now(tp_stream* s, int64_t node, int root, tp_error* err)
{
    uint16_t* block = malloc(s->block_bytes);
    if (!block) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory for a node");
        return 0;
    }
    if (tp_store_read_node(s->store, node, block, s->block_samples, err) != TP_OK) {
        free(block);
        s->state[node] = ST_FAILED;
        return 0;
    }
    pthread_mutex_lock(&s->mu);
    s->bytes_total += s->block_bytes;
    pthread_mutex_unlock(&s->mu);
    if (!add_resident(s, node, block, root)) {
        free(block);
        pthread_mutex_lock(&s->mu);
        s->bytes_total -= s->block_bytes;
        pthread_mutex_unlock(&s->mu);
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory for a node");
        return 0;
    }
    return 1;
}

tp_stream* tp_stream_create(const tp_store* store, tp_tree* tree, const tp_stream_options* o,
                            tp_error* err)
{
    tp_stream* s = calloc(1, sizeof *s);
    if (!s) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    s->store = store;
    s->tree = tree;
    tp_store_get_info(store, &s->info);
    s->g = tp_tree_get_geometry(tree);
    s->block_samples = tp_tree_block_words(s->g->n); /* samples and cell mask */
    s->block_bytes = s->block_samples * sizeof(uint16_t);
    s->budget = o && o->memory_bytes ? o->memory_bytes : (size_t)1 << 30;
    /* over HTTP a node takes a round trip and a queue: look further ahead */
    s->prefetch_s = o && o->prefetch_s > 0 ? o->prefetch_s : s->info.remote ? 1.5 : 0.5;
    s->frame_s = o && o->frame_s > 0 ? o->frame_s : 0;
    size_t count = (size_t)s->g->node_count;
    s->state = calloc(count, 1);
    s->res_index = malloc(count * sizeof *s->res_index);
    pthread_mutex_init(&s->mu, NULL);
    pthread_cond_init(&s->cv, NULL);
    if (!s->state || !s->res_index) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory for %zu nodes", count);
        tp_stream_destroy(s);
        return NULL;
    }
    memset(s->res_index, 0xFF, count * sizeof *s->res_index);
    /* The roots are always resident: whatever else is missing, they cover the map. */
    size_t roots = (size_t)s->g->root_count;
    if ((double)roots * (double)s->block_bytes > (double)s->budget) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "the %zu top nodes need %.1f MB, more than the memory budget of %.1f MB",
                     roots, roots * (double)s->block_bytes / 1e6, s->budget / 1e6);
        tp_stream_destroy(s);
        return NULL;
    }
    int64_t* ids = malloc(roots * sizeof *ids);
    if (!ids) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        tp_stream_destroy(s);
        return NULL;
    }
    tp_tree_roots(s->g, ids, roots);
    for (size_t i = 0; i < roots; i++)
        if (!load_now(s, ids[i], 1, err)) {
            free(ids);
            tp_stream_destroy(s);
            return NULL;
        }
    free(ids);
    /* Several loaders for a store over HTTP: each waits on its request, so that many are in
     * flight at once (a local disk answers in microseconds: one is enough). */
    const char* env = getenv("TP_STREAM_LOADERS"); /* measurements: docs/PERFORMANCE.md */
    int loaders = o && o->loaders > 0 ? o->loaders
                  : env && atoi(env) > 0 ? atoi(env)
                  : s->info.remote      ? 8
                                        : 1;
    loaders = loaders < MAX_LOADERS ? loaders : MAX_LOADERS;
    for (int i = 0; !(o && o->no_loader) && i < loaders; i++) {
        if (pthread_create(&s->threads[i], NULL, loader_main, s) != 0) {
            tp_error_set(err, TP_ERR_BACKEND, "cannot start the loader thread");
            tp_stream_destroy(s);
            return NULL;
        }
        s->threads_started++;
    }
    return s;
}

void tp_stream_destroy(tp_stream* s)
{
    if (!s)
        return;
    pthread_mutex_lock(&s->mu);
    s->stop = 1;
    pthread_cond_broadcast(&s->cv);
    pthread_mutex_unlock(&s->mu);
    for (int i = 0; i < s->threads_started; i++)
        pthread_join(s->threads[i], NULL);
    for (size_t i = 0; i < s->res_count; i++) {
        tp_tree_detach(s->tree, s->res[i].node);
        free(s->res[i].block);
    }
    for (size_t i = 0; i < s->done_len; i++)
        free(s->done_list[i].block);
    pthread_mutex_destroy(&s->mu);
    pthread_cond_destroy(&s->cv);
    free(s->res);
    free(s->retries);
    free(s->done_list);
    free(s->queue);
    free(s->state);
    free(s->res_index);
    free(s);
}

/* Appends node to the next queue (render thread, under mu) unless it is known already. */
static void want(tp_stream* s, int64_t node)
{
    if (s->state[node] != ST_NONE)
        return;
    if (s->queue_len == s->queue_cap) {
        size_t cap = s->queue_cap ? 2 * s->queue_cap : 256;
        int64_t* q = realloc(s->queue, cap * sizeof *q);
        if (!q)
            return; /* asked again next frame */
        s->queue = q;
        s->queue_cap = cap;
    }
    s->queue[s->queue_len++] = node;
    s->state[node] = ST_QUEUED;
}

/* Node failed on the way: asked for again after its backoff (retry_due). Returns how many
 * times it failed so (0 when it cannot be retried: out of memory). */
static int retry_later(tp_stream* s, int64_t node)
{
    size_t i = 0;
    while (i < s->retry_len && s->retries[i].node != node)
        i++;
    if (i == s->retry_len) {
        if (s->retry_len == s->retry_cap) {
            size_t cap = s->retry_cap ? 2 * s->retry_cap : 16;
            retry* r = realloc(s->retries, cap * sizeof *r);
            if (!r)
                return 0; /* failed for good */
            s->retries = r;
            s->retry_cap = cap;
        }
        s->retries[s->retry_len++] = (retry){.node = node};
    }
    retry* r = &s->retries[i];
    const double backoff_ms = 500.0 * (double)(1 << (r->attempts < 6 ? r->attempts : 6));
    r->at_ms = tp_clock_ms() + (backoff_ms < 30000 ? backoff_ms : 30000);
    return ++r->attempts;
}

/* The failed nodes whose backoff is over may be asked for again; entries of nodes read since
 * are dropped. */
static void retry_due(tp_stream* s)
{
    const double now = tp_clock_ms();
    for (size_t i = 0; i < s->retry_len;) {
        retry* r = &s->retries[i];
        if (s->state[r->node] == ST_FAILED && r->at_ms <= now)
            s->state[r->node] = ST_NONE;
        if (s->state[r->node] == ST_RESIDENT)
            *r = s->retries[--s->retry_len];
        else
            i++;
    }
}

/* Marks node and its ancestors used this frame. */
static void mark_used(tp_stream* s, int64_t node)
{
    while (node >= 0 && s->res_index[node] >= 0) {
        resident* r = &s->res[s->res_index[node]];
        if (r->used == s->frame)
            break;
        r->used = s->frame;
        node = tp_tree_node_parent(s->g, node);
    }
}

static int by_score(const void* a, const void* b)
{
    double x = (*(resident* const*)a)->score, y = (*(resident* const*)b)->score;
    return x < y ? 1 : x > y ? -1 : 0;
}

/* Releases nodes farthest behind the motion until the budget has room again. */
static int release_over_budget(tp_stream* s, const tp_camera* cam, const double motion[3])
{
    size_t target = s->budget - s->budget / 10; /* release in batches, down to 90 % */
    pthread_mutex_lock(&s->mu);
    size_t total = s->bytes_total;
    int starved = s->queue_head < s->queue_len;
    pthread_mutex_unlock(&s->mu);
    if (total + (starved ? s->block_bytes : 0) <= s->budget)
        return 0;
    const double* gt = s->info.header.geotransform;
    double mlen = sqrt(motion[0] * motion[0] + motion[1] * motion[1] + motion[2] * motion[2]);
    int released = 0;
    /* Childless nodes first; releasing one can make its parent childless: repeat. */
    for (int round = 0; round < 64 && total > target; round++) {
        size_t cand = 0;
        resident** list = malloc(s->res_count * sizeof *list);
        if (!list)
            break;
        for (size_t i = 0; i < s->res_count; i++) {
            resident* r = &s->res[i];
            if (r->root || r->children || r->used == s->frame)
                continue;
            int sc, c, rr;
            tp_tree_node_locate(s->g, r->node, &sc, &c, &rr);
            double span = (double)((int64_t)1 << (s->g->n + sc));
            double gx = (c + 0.5) * span, gy = (rr + 0.5) * span;
            double d[3] = {gt[0] + (gx + 0.5) * gt[1] - cam->position[0],
                           gt[3] + (gy + 0.5) * gt[5] - cam->position[1], 0};
            double dist = sqrt(d[0] * d[0] + d[1] * d[1]);
            /* Behind the motion first (most negative projection), then far before near. */
            r->score = mlen > 0 ? -(d[0] * motion[0] + d[1] * motion[1]) / mlen * 4 + dist : dist;
            list[cand++] = r;
        }
        if (!cand) {
            free(list);
            break;
        }
        qsort(list, cand, sizeof *list, by_score);
        /* Nodes to release, by id: releasing moves entries of s->res. */
        size_t need = (total - target + s->block_bytes - 1) / s->block_bytes, n = 0;
        int64_t* ids = malloc((need < cand ? need : cand) * sizeof *ids);
        for (size_t i = 0; ids && i < cand && n < need; i++)
            ids[n++] = list[i]->node;
        free(list);
        for (size_t i = 0; i < n; i++) {
            release(s, (size_t)s->res_index[ids[i]]);
            released++;
        }
        free(ids);
        if (!n)
            break;
        pthread_mutex_lock(&s->mu);
        s->bytes_total -= n * s->block_bytes;
        total = s->bytes_total;
        pthread_mutex_unlock(&s->mu);
    }
    return released;
}

/* Whether the prefetch cut must be selected again: the camera it would now be selected for
 * (ahead, looking along fwd) drifted from the last one's by more than a quarter of the
 * look-ahead distance (lead_m), or turned by more than 5 degrees. The prefetch looks 0.5 s
 * ahead: at 30 Hz in straight flight that is every 4th frame, at 60 Hz every 8th, and its
 * requests still reach at least 3/4 of the way ahead in between. Measured (docs/PERFORMANCE.md,
 * "The CPU side"): the second selection was half of the stream's frame time. */
static int prefetch_stale(const tp_stream* s, const tp_cut* prefetch_cut, const double ahead[3],
                          const double fwd[3], double lead_m)
{
    if (s->pre_cut != prefetch_cut)
        return 1;
    double d2 = 0, dot = 0;
    for (int a = 0; a < 3; a++) {
        double d = ahead[a] - s->pre_at[a];
        d2 += d * d;
        dot += fwd[a] * s->pre_fwd[a];
    }
    return d2 > 0.0625 * lead_m * lead_m || dot < 0.99619469809; /* cos 5 degrees */
}

void tp_stream_frame(tp_stream* s, const tp_cut* cut, tp_cut* prefetch_cut, const tp_camera* cam,
                     const tp_lod_params* lod, tp_stream_stats* stats)
{
    double t0 = tp_clock_ms();
    s->frame++;
    int attached = 0;

    /* 1. What the loader finished. */
    pthread_mutex_lock(&s->mu);
    size_t nd = s->done_len;
    done* list = s->done_list;
    s->done_list = NULL;
    s->done_len = s->done_cap = 0;
    pthread_mutex_unlock(&s->mu);
    for (size_t i = 0; i < nd; i++) {
        done* d = &list[i];
        if (!d->block) {
            s->state[d->node] = ST_FAILED;
            s->failed++;
            const int again = d->transient && retry_later(s, d->node) > 1; /* said once */
            if (!again && !s->failure_pending && d->msg[0]) {
                snprintf(s->failure, sizeof s->failure, "%s", d->msg);
                s->failure_pending = 1;
            }
            continue;
        }
        int64_t parent = tp_tree_node_parent(s->g, d->node);
        int stale = s->state[d->node] == ST_RESIDENT || (parent >= 0 && s->res_index[parent] < 0);
        if (stale || !add_resident(s, d->node, d->block, 0)) {
            free(d->block);
            if (s->state[d->node] != ST_RESIDENT)
                s->state[d->node] = ST_NONE;
            pthread_mutex_lock(&s->mu);
            s->bytes_total -= s->block_bytes;
            pthread_mutex_unlock(&s->mu);
            continue;
        }
        attached++;
    }
    free(list);

    /* 2. Used this frame: the drawn nodes and their ancestors (their entries asked of memory
     * 16 and 8 nodes ahead: thousands of misses side by side, not one after another). */
    size_t count = 0;
    const tp_cut_node* drawn = tp_cut_nodes(cut, &count);
    for (size_t i = 0; i < count; i++) {
        if (i + 16 < count)
            TP_PREFETCH(&s->res_index[drawn[i + 16].node]);
        if (i + 8 < count && s->res_index[drawn[i + 8].node] >= 0)
            TP_PREFETCH(&s->res[s->res_index[drawn[i + 8].node]]);
        mark_used(s, drawn[i].node);
    }

    /* 3. The next queue: this frame's requests, then the prefetch. Requests still queued from
     * the last frame and not asked for again are dropped; the prefetch cut's requests are asked
     * for again on every frame until it is next selected. */
    double motion[3] = {0, 0, 0};
    double t = s->frame_s > 0 ? (s->clock_ms += s->frame_s * 1e3) : tp_clock_ms();
    if (s->have_last && t > s->last_time_ms)
        for (int a = 0; a < 3; a++)
            motion[a] = (cam->position[a] - s->last_pos[a]) / (t - s->last_time_ms) * 1e3; /* m/s */
    memcpy(s->last_pos, cam->position, sizeof s->last_pos);
    s->last_time_ms = t;
    s->have_last = 1;

    size_t nreq = 0;
    const int64_t* req = tp_cut_requests(cut, &nreq);
    size_t npre = 0;
    const int64_t* pre = NULL;
    double speed = sqrt(motion[0] * motion[0] + motion[1] * motion[1] + motion[2] * motion[2]);
    int pre_updated = 0;
    if (prefetch_cut && speed > 0) {
        tp_camera ahead = *cam;
        for (int a = 0; a < 3; a++)
            ahead.position[a] += motion[a] * s->prefetch_s;
        tp_camera_frame fr;
        tp_camera_get_frame(cam, &fr);
        if (s->pre_async &&
            prefetch_stale(s, prefetch_cut, ahead.position, fr.forward, speed * s->prefetch_s)) {
            /* the caller selects it (tp_stream_prefetch_wanted); until then the requests of
             * its last selection stand */
            s->pre_job = 1;
            s->pre_job_cam = ahead;
            s->pre_cut = prefetch_cut;
            memcpy(s->pre_at, ahead.position, sizeof s->pre_at);
            memcpy(s->pre_fwd, fr.forward, sizeof s->pre_fwd);
            pre_updated = 1;
        } else if (prefetch_stale(s, prefetch_cut, ahead.position, fr.forward,
                                  speed * s->prefetch_s)) {
            tp_error err;
            s->pre_cut = NULL;
            if (tp_cut_update_requests(prefetch_cut, &ahead, lod, &err) == TP_OK) {
                s->pre_cut = prefetch_cut;
                memcpy(s->pre_at, ahead.position, sizeof s->pre_at);
                memcpy(s->pre_fwd, fr.forward, sizeof s->pre_fwd);
            }
            pre_updated = 1;
        }
        if (s->pre_cut)
            pre = tp_cut_requests(prefetch_cut, &npre);
    } else {
        s->pre_cut = NULL; /* standing still (or no prefetch): nothing ahead to load */
    }
    retry_due(s);
    pthread_mutex_lock(&s->mu);
    for (size_t i = s->queue_head; i < s->queue_len; i++)
        if (s->state[s->queue[i]] == ST_QUEUED)
            s->state[s->queue[i]] = ST_NONE;
    s->queue_head = s->queue_len = 0;
    for (size_t i = 0; i < nreq; i++)
        want(s, req[i]);
    for (size_t i = 0; i < npre; i++)
        want(s, pre[i]);
    pthread_cond_broadcast(&s->cv);
    pthread_mutex_unlock(&s->mu);

    /* 4. Over budget: release what is farthest behind. */
    int released = release_over_budget(s, cam, motion);
    if (released) {
        pthread_mutex_lock(&s->mu);
        pthread_cond_broadcast(&s->cv);
        pthread_mutex_unlock(&s->mu);
    }

    tp_stream_get_stats(s, &s->last);
    s->last.prefetch_updated = pre_updated;
    s->last.attached = attached;
    s->last.released = released;
    s->last.frame_ms = tp_clock_ms() - t0;
    if (stats)
        *stats = s->last;
}

void tp_stream_set_prefetch_async(tp_stream* s, int on)
{
    s->pre_async = on != 0;
    s->pre_job = 0;
}

int tp_stream_prefetch_wanted(tp_stream* s, tp_camera* ahead)
{
    if (!s->pre_job)
        return 0;
    s->pre_job = 0;
    *ahead = s->pre_job_cam;
    return 1;
}

int tp_stream_is_queued(const tp_stream* s, int64_t node)
{
    assert(s && node >= 0 && node < s->g->node_count);
    return s->state[node] == ST_QUEUED;
}

int tp_stream_require(tp_stream* s, int64_t node, tp_error* err)
{
    if (s->res_index[node] >= 0)
        return 1;
    if (s->state[node] == ST_FAILED) {
        tp_error_set(err, TP_ERR_IO, "node %lld could not be read", (long long)node);
        return 0;
    }
    if (s->info.remote) { /* the missing chain in one batch of requests, not one at a time */
        int64_t chain[TP_TREE_MAX_SCALES];
        size_t k = 0;
        for (int64_t a = node; a >= 0 && k < TP_TREE_MAX_SCALES && s->res_index[a] < 0;
             a = tp_tree_node_parent(s->g, a))
            chain[k++] = a;
        tp_store_prefetch(s->store, chain, k);
    }
    int64_t parent = tp_tree_node_parent(s->g, node);
    if (parent >= 0 && !tp_stream_require(s, parent, err))
        return 0;
    /* A copy the loader is reading is dropped as stale when it arrives. */
    return load_now(s, node, 0, err);
}

const char* tp_stream_take_failure(tp_stream* s)
{
    if (!s->failure_pending)
        return NULL;
    s->failure_pending = 0;
    return s->failure;
}

void tp_stream_get_stats(const tp_stream* s, tp_stream_stats* out)
{
    memset(out, 0, sizeof *out);
    out->resident_nodes = s->res_count;
    out->resident_bytes = s->res_count * s->block_bytes;
    out->budget_bytes = s->budget;
    pthread_mutex_t* mu = (pthread_mutex_t*)&s->mu; /* the lock, not the state, changes */
    pthread_mutex_lock(mu);
    out->pending = (int)(s->queue_len - s->queue_head) + s->in_flight;
    pthread_mutex_unlock(mu);
    out->failed = s->failed;
    out->attached = s->last.attached;
    out->released = s->last.released;
    out->frame_ms = s->last.frame_ms;
}
