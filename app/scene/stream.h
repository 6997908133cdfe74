/*
 * stream.h - the nodes of a store in memory as the view needs them (issue 12, section 3).
 *
 * A loader thread reads and decodes nodes (tp_store_read_node: pread, CRC32, zstd) into blocks
 * of its own; the render thread attaches finished blocks to the tree once per frame
 * (tp_stream_frame), so the tree and the cut are only ever touched by the render thread. What
 * is loaded, in order:
 *   1. the roots, at once and before the first frame (tp_stream_create): every frame can then
 *      draw something everywhere, and a node that is not loaded yet is drawn as its loaded
 *      ancestor, never as a hole (tp_cut_update does the substitution);
 *   2. the nodes the current cut asked for (tp_cut_requests), most urgent first;
 *   3. prefetch along the camera's motion: the requests of a second cut selected for where the
 *      camera will be a moment later (Luo & Duan section 3.3 predicts from the shift of the
 *      clip centre between frames; this is the same idea applied to geometry). That cut is
 *      selected again only when the predicted camera drifted by a quarter of the look-ahead
 *      distance or turned by 5 degrees (every 4th frame of a straight flight at 30 Hz); its
 *      requests stay queued on the frames in between.
 * When the decoded nodes exceed the memory budget, the ones not drawn this frame (nor an
 * ancestor of a drawn one, nor a root) are released farthest-behind-first: projected on the
 * direction of motion, the most negative first (Luo & Duan section 3.4), by distance when the
 * camera stands still. A node whose data fails its checksum is reported once, and its ancestor
 * keeps being drawn in its place. A read that failed on the way (TP_ERR_IO: an HTTP error, a
 * reset, a stall, the store unchanged) is asked for again after a backoff (0.5 s doubling to
 * 30 s), its ancestor drawn meanwhile; its failure is reported once, not at every retry. A store over HTTP is read by several loader threads at
 * once (tp_stream_options.loaders), each taking up to 8 queued nodes at a time and reading them
 * in one batch of concurrent range requests (tp_store_prefetch), then decoding them in turn.
 */
#ifndef TP_APP_STREAM_H
#define TP_APP_STREAM_H

#include "tp_core.h"
#include "tp_io.h"

#include <stddef.h>
#include <stdint.h>

typedef struct tp_stream tp_stream;

typedef struct tp_stream_options {
    size_t memory_bytes;     /* budget of decoded node samples; 0: 1 GiB */
    double prefetch_s;       /* how far ahead the motion is extrapolated; 0: 0.5 s (1.5 s for a
                                store over HTTP, whose nodes take a round trip each) */
    int no_loader;           /* tests: load nothing in the background (only tp_stream_require) */
    int loaders;             /* loader threads, each with one read (over HTTP a batch of up
                                to 8 nodes' requests) in flight; 0: the
                                environment's TP_STREAM_LOADERS if set (to measure), else 8 for
                                a store over HTTP (tp_store_info.remote), 1 for a local file; at
                                most 16 */
    double frame_s;          /* > 0: each tp_stream_frame is this much later than the last, for
                                the motion estimate (a bench flying a fixed-rate flight faster
                                than it draws); 0: the real clock */
} tp_stream_options;

typedef struct tp_stream_stats {
    size_t resident_nodes, resident_bytes; /* decoded samples in RAM, own accounting */
    size_t budget_bytes;
    int pending;             /* queued or being read */
    int attached;            /* nodes attached this frame */
    int released;            /* nodes released this frame */
    int failed;              /* nodes that failed to read (in total) */
    int prefetch_updated;    /* 1 if the prefetch cut was selected this frame */
    double frame_ms;         /* time spent in tp_stream_frame */
} tp_stream_stats;

/* Creates the stream and loads the roots (synchronously). The store and the tree must outlive
 * it; the tree must have been created from the store's metas. NULL and err (naming the store
 * file and the node) on failure. */
tp_stream* tp_stream_create(const tp_store* store, tp_tree* tree, const tp_stream_options* o,
                            tp_error* err);
/* Stops the loader, detaches and frees every block. Accepts NULL. */
void tp_stream_destroy(tp_stream* s);

/* Once per frame, on the render thread, after tp_cut_update(cut, cam): attaches what the loader
 * finished, queues the cut's requests and the prefetch (prefetch_cut: a second cut the stream
 * updates itself for the extrapolated camera, not every frame, and reads between its updates:
 * the caller must not update it; may be NULL for none), and releases blocks over budget. lod:
 * the parameters the cut was selected with. */
void tp_stream_frame(tp_stream* s, const tp_cut* cut, tp_cut* prefetch_cut, const tp_camera* cam,
                     const tp_lod_params* lod, tp_stream_stats* stats);

/* on: tp_stream_frame no longer selects the prefetch cut itself (the render thread's longest
 * step on a large map): when it is due, tp_stream_prefetch_wanted says for which camera, and
 * the caller selects it (tp_cut_update_requests on the same prefetch cut, e.g. on the cut
 * thread, cut_worker.h) before the next tp_stream_frame, which reads its requests; until then
 * the requests of its last selection stand. */
void tp_stream_set_prefetch_async(tp_stream* s, int on);
/* Async prefetch: 1 (once) when the last tp_stream_frame wants the prefetch cut selected for
 * *ahead; 0 when it does not. */
int tp_stream_prefetch_wanted(tp_stream* s, tp_camera* ahead);

/* Whether node waits for the loader (queued or being read). */
int tp_stream_is_queued(const tp_stream* s, int64_t node);

/* Makes node and all its ancestors resident now (reading on the calling thread: the render
 * thread, as for a height query that needs full resolution). Returns 0 with err when a read
 * fails. */
int tp_stream_require(tp_stream* s, int64_t node, tp_error* err);

/* The first read failure not reported yet (one line naming the file, node and offset), or
 * NULL; each failure is returned once. */
const char* tp_stream_take_failure(tp_stream* s);

void tp_stream_get_stats(const tp_stream* s, tp_stream_stats* out);

#endif /* TP_APP_STREAM_H */
