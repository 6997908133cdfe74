/*
 * store_scene.h - what every command that draws or measures a built store (.tpt) opens: the
 * store, the tree over its node table, the georeference, and the stream that loads nodes as
 * the view needs them (issue 12).
 */
#ifndef TP_APP_STORE_SCENE_H
#define TP_APP_STORE_SCENE_H

#include "tp_core.h"
#include "tp_io.h"

#include "stream.h"

#include <pthread.h>

typedef struct tp_store_scene {
    const char* path;        /* borrowed from the caller */
    tp_store* store;
    tp_store_info info;      /* header strings owned by the store */
    tp_tree* tree;           /* metas from the store; samples attached by the stream */
    tp_tree_info tree_info;
    tp_georef* georef;       /* grid <-> render CRS <-> WGS84 (see tp_store_scene_open_deferred) */
    tp_stream* stream;       /* NULL until tp_store_scene_stream */
    tp_tin_cache* tins;      /* NULL until tp_store_scene_tins (--mesh tin) */
    /* private */
    struct tp_store_georef_job* georef_job; /* the georeference being made on a thread */
    pthread_t* prefetch_job; /* over HTTP: the top nodes being read ahead (deferred open) */
} tp_store_scene;

/* 1 if path names a terrapatch store (its first bytes are the store's magic). */
int tp_is_store_path(const char* path);

/* Reads the first n bytes of path into head when it is a regular file of at least n bytes
 * (a FIFO or a device is never opened: it could block) or an http(s) URL whose server has
 * them (tp_input_url_head): 1, else 0. */
int tp_file_head(const char* path, unsigned char* head, size_t n);

/* Opens the store, its tree and georeference. Prints one error line naming the file and returns
 * TP_EXIT_FAILURE on failure (the scene then holds nothing), TP_EXIT_OK on success. */
int tp_store_scene_open(const char* path, tp_store_scene* sc);

/* tp_store_scene_open with the georeference made on a thread: resolving the CRS (GDAL, PROJ's
 * database) takes 50-250 ms, which a viewer spends creating its GL context meanwhile
 * (docs/PERFORMANCE.md, "First frame"). sc->georef is NULL until tp_store_scene_georef_wait.
 * A store over HTTP also has its roots and coarse scales (at most 512 nodes) read ahead on a
 * thread, in one batch of concurrent requests (tp_store_prefetch), joined by
 * tp_store_scene_stream. */
int tp_store_scene_open_deferred(const char* path, tp_store_scene* sc);

/* Waits for the georeference of tp_store_scene_open_deferred and sets sc->georef: TP_EXIT_OK,
 * or one error line naming the file and TP_EXIT_FAILURE (sc->georef stays NULL). TP_EXIT_OK at
 * once when sc->georef is already there. */
int tp_store_scene_georef_wait(tp_store_scene* sc);

/* Starts streaming (loads the roots now; over HTTP from the top nodes read ahead, in one batch
 * of requests: tp_store_scene_open_deferred). TP_EXIT_FAILURE with one line on failure. */
int tp_store_scene_stream(tp_store_scene* sc, const tp_stream_options* o);

/* The cache of the nodes' TINs (--mesh tin: tp_cut_set_tins draws from it). TP_EXIT_FAILURE
 * with one line without memory. */
int tp_store_scene_tins(tp_store_scene* sc);

void tp_store_scene_close(tp_store_scene* sc); /* accepts a zeroed scene */

/* The screen error of cut (over sc's tree) seen from cam, every leaf it needs that the stream
 * does not hold read from the store on this thread (tp_cut_measure_error with a reader over
 * sc->store; the stream's residency is not touched): the leaves of at most about max_posts
 * full-resolution posts (max_posts / 4^n leaves; 0: every leaf), sampled as
 * tp_cut_measure_error says, seed choosing which. A leaf that cannot be read is counted in
 * out->leaves_skipped and its message put in err (the first one); the measure goes on. TP_OK
 * with *out, or TP_ERR_OUT_OF_MEMORY. Time: about 50 ns a post on llvmpipe's machine. */
#define TP_STORE_MEASURE_POSTS ((size_t)1 << 24)     /* --stats-json: ~1 s */
#define TP_STORE_MEASURE_POSTS_HUD ((size_t)1 << 19) /* the HUD, once a second: ~30 ms */
tp_status tp_store_scene_measure(const tp_store_scene* sc, const tp_cut* cut,
                                 const tp_camera* cam, size_t max_posts, uint32_t seed,
                                 tp_cut_error* out, tp_error* err);

#endif /* TP_APP_STORE_SCENE_H */
