/*
 * qm_workers.h - the tiles of one level of a quantized-mesh export (qm_export.c) built on N
 * threads and handed back in their order (`export --tiles quantized-mesh --threads N`).
 *
 * A tile depends only on its own (z, x, y), its level's bound and the source (its sides too:
 * qm_sides.c reads the side alone), so the tiles of a level are built independently. Each
 * thread has its own copy of the source's mutable parts: a tp_ground (its leaf cache; not
 * thread-safe, ground.h), a tp_georef (a non-UTM CRS converts through a PROJ object, which is
 * not thread-safe) and a tp_geoid (not thread-safe, tp_io/geoid.h); the store itself is read
 * with pread by all of them (tp_store_read_node is thread-safe). Thread 0 uses the caller's
 * source as it is.
 *
 * The results come back to the calling thread in the tiles' order, however the threads finish,
 * so what the caller writes (tiles, tiles.log, notes) is the same as on one thread. At most
 * 4 N results wait at once (built ahead of the one the caller waits for): memory stays bounded.
 */
#ifndef TP_APP_QM_WORKERS_H
#define TP_APP_QM_WORKERS_H

#include "qm_tile.h"

typedef struct qm_workers qm_workers;

/* threads >= 1 sources over s (thread 0's is s itself: borrowed, it must outlive the workers).
 * 0 with a message in err (out of memory, a ground, georeference or geoid that cannot be made). */
int tp_qm_workers_create(const qm_source* s, int threads, qm_workers** out, tp_error* err);
void tp_qm_workers_destroy(qm_workers* w); /* accepts NULL */
int tp_qm_workers_threads(const qm_workers* w);

/* Called on the calling thread for tile i (0, 1, ... in order): ok 1 with the built tile in *r
 * (the callee owns r->gz), ok 0 with tp_qm_tile_build's message in err (r holds nothing).
 * Returns 1 to go on, 0 to stop (the tiles being built are finished and dropped). */
typedef int (*qm_deliver_fn)(void* ctx, size_t i, int ok, qm_tile_result* r, const tp_error* err);

/* Builds the count tiles (xy[2 i], xy[2 i + 1]) of level z with bound_m on the workers'
 * threads, each handed to deliver in order. 1 when every tile was delivered and deliver went
 * on; 0 when deliver stopped; -1 with a message in err when no thread could be started. */
int tp_qm_workers_run(qm_workers* w, int z, const int* xy, size_t count, double bound_m,
                      qm_deliver_fn deliver, void* ctx, tp_error* err);

#endif
