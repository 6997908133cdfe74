/* store_scene.c - a built store opened for drawing (see store_scene.h). */
#define _POSIX_C_SOURCE 200809L
#include "store_scene.h"

#include "cli.h"

#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int tp_file_head(const char* path, unsigned char* head, size_t n)
{
    if (tp_input_is_url(path))
        return tp_input_url_head(path, head, n, NULL) == TP_OK;
    struct stat st;
    /* never open a FIFO or a device to look: it could block; the readers refuse those */
    if (stat(path, &st) != 0 || !S_ISREG(st.st_mode))
        return 0;
    FILE* f = fopen(path, "rb");
    if (!f)
        return 0;
    size_t got = fread(head, 1, n, f);
    fclose(f);
    return got == n;
}

int tp_is_store_path(const char* path)
{
    static const unsigned char magic[8] = {0x89, 'T', 'P', 'T', '\r', '\n', 0x1A, '\n'};
    unsigned char head[8];
    return tp_file_head(path, head, sizeof head) && memcmp(head, magic, sizeof magic) == 0;
}

/* One error line naming the file; the store's messages name it, the others do not. */
static void report(const char* path, tp_status s, const tp_error* err)
{
    if (strstr(err->message, path))
        tp_cli_error("%s", err->message);
    else
        tp_cli_error("%s: %s", path, err->message[0] ? err->message : tp_status_str(s));
}

/* The store and the tree over its node table. */
static tp_status open_store_tree(const char* path, tp_store_scene* sc, tp_error* err)
{
    tp_status s = tp_store_open(path, &sc->store, err);
    if (s != TP_OK)
        return s;
    tp_store_get_info(sc->store, &sc->info);
    s = tp_tree_create_from_store(sc->store, &sc->tree, err);
    if (s == TP_OK)
        tp_tree_get_info(sc->tree, &sc->tree_info);
    return s;
}

/* The georeference made on its own thread: reads the store's header (not changed after open),
 * writes only its own fields; joined by tp_store_scene_georef_wait or tp_store_scene_close. */
struct tp_store_georef_job {
    pthread_t thread;
    const char* crs_wkt;
    const double* geotransform;
    tp_georef* georef;
    tp_status status;
    tp_error err;
};

static void* georef_thread(void* arg)
{
    struct tp_store_georef_job* job = arg;
    job->status = tp_georef_create(job->crs_wkt, job->geotransform, &job->georef, &job->err);
    return NULL;
}

/* Starts the georeference's thread; 0 when it cannot be started (nothing left behind). */
static int start_georef_job(tp_store_scene* sc)
{
    struct tp_store_georef_job* job = calloc(1, sizeof *job);
    if (!job)
        return 0;
    job->crs_wkt = sc->info.header.crs_wkt;
    job->geotransform = sc->info.header.geotransform;
    if (pthread_create(&job->thread, NULL, georef_thread, job) != 0) {
        free(job);
        return 0;
    }
    sc->georef_job = job;
    return 1;
}

/* Over HTTP, before the stream loads the roots one at a time: the roots and every node of the
 * coarse scales (at most TOP_PREFETCH_NODES: the scales whose nodes, with those above, number
 * no more) read ahead in one batch of concurrent requests (tp_store_prefetch). The roots are
 * then loaded from memory, and what a first frame, its normal map's coarse levels and the
 * stream's first requests ask for is mostly there already. */
#define TOP_PREFETCH_NODES 512
static void* prefetch_top(void* arg)
{
    const tp_store_scene* sc = arg;
    const tp_tree_geometry* g = &sc->info.header.geometry;
    int64_t top = 0; /* ids 0 .. top-1: every node of the scales kept (ids run from the top) */
    for (int s = g->scales - 1; s >= 0; s--) {
        int64_t upto = s > 0 ? g->first_node[s - 1] : g->node_count;
        if (upto > TOP_PREFETCH_NODES)
            break;
        top = upto;
    }
    size_t roots = (size_t)g->root_count;
    int64_t* ids = malloc(((size_t)top + roots) * sizeof *ids);
    if (!ids)
        return NULL; /* read one at a time */
    for (int64_t i = 0; i < top; i++)
        ids[i] = i;
    tp_tree_roots(g, ids + top, roots);
    tp_store_prefetch(sc->store, ids, (size_t)top + roots);
    free(ids);
    return NULL;
}

/* A deferred open over HTTP reads the top nodes ahead on a thread of its own, while the viewer
 * creates its GL context; tp_store_scene_stream (or close) joins it. */
static void start_prefetch_top(tp_store_scene* sc)
{
    pthread_t* t = malloc(sizeof *t);
    if (t && pthread_create(t, NULL, prefetch_top, sc) == 0)
        sc->prefetch_job = t;
    else
        free(t); /* tp_store_scene_stream reads them itself */
}

static void join_prefetch_top(tp_store_scene* sc)
{
    if (!sc->prefetch_job)
        return;
    pthread_join(*sc->prefetch_job, NULL);
    free(sc->prefetch_job);
    sc->prefetch_job = NULL;
}



/* The store, its tree, and the georeference: on a thread of its own when deferred (made here
 * when no thread can be started). */
static int open_scene(const char* path, tp_store_scene* sc, int deferred)
{
    memset(sc, 0, sizeof *sc);
    sc->path = path;
    tp_error err = {{0}};
    tp_status s = open_store_tree(path, sc, &err);
    if (s == TP_OK && deferred && sc->info.remote)
        start_prefetch_top(sc);
    if (s == TP_OK && deferred && start_georef_job(sc))
        return TP_EXIT_OK;
    if (s == TP_OK)
        s = tp_georef_create(sc->info.header.crs_wkt, sc->info.header.geotransform, &sc->georef,
                             &err);
    if (s != TP_OK) {
        report(path, s, &err);
        tp_store_scene_close(sc);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

int tp_store_scene_open(const char* path, tp_store_scene* sc)
{
    return open_scene(path, sc, 0);
}

int tp_store_scene_open_deferred(const char* path, tp_store_scene* sc)
{
    return open_scene(path, sc, 1);
}

/* Joins the job (if any) and takes its georeference; its status (TP_OK without a job). */
static tp_status join_georef(tp_store_scene* sc, tp_error* err)
{
    struct tp_store_georef_job* job = sc->georef_job;
    if (!job)
        return TP_OK;
    pthread_join(job->thread, NULL);
    sc->georef_job = NULL;
    tp_status s = job->status;
    if (s == TP_OK)
        sc->georef = job->georef;
    else if (err)
        *err = job->err;
    free(job);
    return s;
}

int tp_store_scene_georef_wait(tp_store_scene* sc)
{
    tp_error err = {{0}};
    tp_status s = join_georef(sc, &err);
    if (s != TP_OK) {
        report(sc->path, s, &err);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

int tp_store_scene_stream(tp_store_scene* sc, const tp_stream_options* o)
{
    tp_error err = {{0}};
    if (sc->prefetch_job)
        join_prefetch_top(sc);
    else if (sc->info.remote)
        prefetch_top(sc);
    sc->stream = tp_stream_create(sc->store, sc->tree, o, &err);
    if (!sc->stream) {
        if (strstr(err.message, sc->path))
            tp_cli_error("%s", err.message);
        else
            tp_cli_error("%s: %s", sc->path, err.message);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

int tp_store_scene_tins(tp_store_scene* sc)
{
    tp_error err = {{0}};
    if (!sc->tins && tp_tin_cache_create(sc->tree, &sc->tins, &err) != TP_OK) {
        tp_cli_error("%s: %s", sc->path, err.message);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

void tp_store_scene_close(tp_store_scene* sc)
{
    join_georef(sc, NULL);         /* a georeference still being made: taken, then freed */
    join_prefetch_top(sc);         /* before the store it reads goes */
    tp_tin_cache_destroy(sc->tins); /* its users (cuts, their threads) are gone */
    tp_stream_destroy(sc->stream); /* detaches every block before the tree goes */
    tp_georef_destroy(sc->georef);
    tp_tree_destroy(sc->tree);
    tp_store_close(sc->store);
    memset(sc, 0, sizeof *sc);
}

typedef struct leaf_reader {
    const tp_store* store;
    size_t samples;
    tp_error* err;
    int failed;
} leaf_reader;

static int read_leaf(void* user, int64_t leaf, uint16_t* samples)
{
    leaf_reader* r = user;
    tp_error e;
    if (tp_store_read_node(r->store, leaf, samples, r->samples, &e) == TP_OK)
        return 1;
    if (!r->failed++ && r->err)
        *r->err = e;
    return 0;
}

/* Over HTTP: the leaves the measure will read, fetched at once (tp_store_prefetch). */
static void prefetch_leaves(void* user, const int64_t* leaves, size_t count)
{
    leaf_reader* r = user;
    tp_store_prefetch(r->store, leaves, count);
}

tp_status tp_store_scene_measure(const tp_store_scene* sc, const tp_cut* cut,
                                 const tp_camera* cam, size_t max_posts, uint32_t seed,
                                 tp_cut_error* out, tp_error* err)
{
    int n = sc->info.header.geometry.n;
    size_t v = ((size_t)1 << n) + 1, max_leaves = max_posts >> (2 * n);
    if (max_posts && !max_leaves)
        max_leaves = 1;
    leaf_reader r = {sc->store, v * v, err, 0};
    tp_cut_measure_options o = {read_leaf, &r, max_leaves, seed,
                                sc->info.remote ? prefetch_leaves : NULL};
    tp_status st = tp_cut_measure_error(cut, cam, &o, out);
    if (st != TP_OK)
        tp_error_set(err, st, "measuring the screen error: out of memory");
    return st;
}
