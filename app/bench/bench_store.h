/*
 * bench_store.h - what bench_store.c (the flights over a store), bench_store_path.c (their
 * camera) and bench_store_report.c (their table, JSON and CSV) share: a frame's row, a
 * configuration's result, the bench's state.
 */
#ifndef TP_APP_BENCH_STORE_H
#define TP_APP_BENCH_STORE_H

#include "bench.h"
#include "gl_context.h"
#include "store_scene.h"

#include <stddef.h>
#include <stdint.h>

typedef struct store_row {
    double cut_ms, stream_ms, upload_ms, draw_ms, frame_ms, cpu_ms;
    /* the cut thread (cut_worker.h): cut_ms is the render thread's part (the check, or the
     * cut selected there); the wait for the thread is in frame_ms only */
    double cut_wait_ms, cut_worker_ms;
    double cut_worker_cpu_ms; /* the thread's CPU time for the job this frame was offered */
    int cut_reused, cut_kept, cut_carried;
    double cut_scratch; /* nodes the render thread's check tested from scratch */
    long page_faults;           /* minor page faults during the draw */
    size_t triangles, gpu_bytes, resident_bytes;
    int dropped, draw_calls;
    int nodes, visited, substituted, requests, uploads, pending;
    int tin_nodes;              /* --mesh tin: drawn nodes that draw a TIN */
    size_t tin_bytes;           /* --mesh tin: the TINs held */
    int tin_builds;             /* --mesh tin: TIN levels built since the frame before */
    double tin_build_ms;        /* ... and the time they took (on the cut thread) */
    double substitution_px;
    double rss_mb, rss_anon_mb;
    int measured;               /* error measured: 1 a frame without substitution, 2 with */
    double max_px, rms_px;      /* NaN when no sample was measured */
    size_t samples, skipped;
    tp_cut_error cut;           /* the cut's measure: leaves under it, sampled, read */
    double measure_ms;          /* the measure's time (outside the timed part) */
    double post_share;          /* --renderer pgm: share of the region's posts compared */
    size_t uncovered;           /* --renderer pgm: posts in view no drawn triangle covers */
    /* --imagery: the clipmap's part of the frame (in frame_ms) */
    double img_ms, img_upload_ms;
    int img_uploads, img_missing, img_pending;
    size_t img_gpu_bytes, img_cache_bytes;
    /* the normal map's part of the frame (in frame_ms and cpu_ms; normal_map.h) */
    double nrm_ms, nrm_upload_ms;
    int nrm_uploads, nrm_missing;
    size_t nrm_gpu_bytes;
    /* --renderer pgm: the clipmap's update (in frame_ms and cpu_ms; stream_ms and upload_ms
     * hold the same two figures) */
    double pgm_fill_ms, pgm_upload_ms;
    size_t pgm_posts, pgm_node_reads;
} store_row;

typedef struct store_result {
    tp_lod_params lod;
    char label[64];
    store_row* rows;
    double fps_median, frame_ms, frame_ms_p99, cpu_ms, cut_ms, stream_ms, upload_ms, draw_ms;
    int cut_thread;                       /* the cut was selected on its own thread */
    double cut_worker_ms, cut_wait_ms;    /* medians: the thread's selection; the wait for it */
    double cut_reused_share;              /* frames that drew the thread's cut */
    double cut_kept_share;                /* ... that was the frame before's, kept */
    double cut_carried_share;             /* ... or the frame before's carried (tp_cut_repair) */
    double cut_worker_cpu_ms, cut_worker_cpu_ms_mean; /* the thread's CPU time: median, mean */
    double cut_total_cpu_ms, cut_total_cpu_ms_mean; /* the render thread's part + the thread's:
                                                       median, mean */
    double cut_scratch;                   /* median: nodes its check tested from scratch */
    int mesh_tin;                         /* --mesh tin */
    double tin_share, tin_mb;             /* drawn nodes that drew a TIN; the TINs held (max) */
    double tin_builds, tin_build_ms, tin_build_ms_max; /* per frame: mean, mean, max */
    double triangles, nodes, visited, uploads, page_faults;
    int substituted_max, frames_with_substitution, pending_max;
    int dropped_max; /* items the renderer could not hold (TP_RENDER_POOL_MAX_BYTES) */
    double rss_mb, rss_anon_mb, resident_mb, gpu_mb; /* max over timed frames */
    int error_frames;           /* frames measured without substitution */
    double max_px, rms_px;      /* over them */
    double samples, skipped;    /* totals over them */
    int error_frames_subst;     /* frames measured that were drawn with substitution */
    double max_px_subst, rms_px_subst; /* over those (NaN when none) */
    /* over every measured frame: leaves under the cut, sampled, measured, read, not to be had;
     * the smallest leaves-per-node side of the sampling (0: every leaf on every frame); the
     * measure's median time; PGM: the mean share of the posts compared */
    double leaves, leaves_sampled, leaves_measured, leaves_read, leaves_skipped;
    int per_node_min;
    double measure_ms;
    double post_share;
    double uncovered_share;     /* --renderer pgm: the mean over measured frames of the share of
                                   the posts in view no drawn triangle covers */
    double settle_ms;           /* first stretch: open... until nothing is missing */
    int settle_timeouts;
    int imagery;                /* drapes o->imagery through the clipmap or blocks: */
    int imagery_mode;           /* a tp_imagery_mode */
    double draw_calls;          /* median */
    double img_ms, img_upload_ms, img_upload_ms_p99, img_uploads, img_gpu_mb, img_cache_mb;
    double img_uploads_total;   /* blocks uploaded over the timed frames */
    int img_missing_max, img_frames_missing;
    long img_final_diff;        /* tp_bench_imagery_diff */
    double nrm_ms, nrm_upload_ms, nrm_gpu_mb, nrm_uploads_total; /* the normal map (medians, */
    int nrm_frames_missing;                                       /* the most, the total) */
    int stitch_add;             /* --stitch add: the cut adds vertices (tp_cut_set_stitch_add) */
    int light;                  /* instead of imagery: o->light, the day's streamed light (its
                                   clipmap's figures in the img_ fields) */
    int pgm_cols, pgm_rows;     /* > 0: Persistent Grid Mapping over the store's clipmap
                                   (app/render/pgm_clip.h), no cut, no stream; error by
                                   tp_pgm_clipmap_measure */
    int pgm_window;
    double pgm_fill_ms, pgm_fill_ms_p99, pgm_upload_ms, pgm_upload_ms_p99, pgm_posts,
        pgm_node_reads; /* medians (and p99) over the timed frames */
} store_result;

typedef struct store_bench {
    const bench_options* o;
    tp_store_scene sc;
    const tp_tree_geometry* g;
    double spacing_m;
    tp_gl_context* ctx;
    int segments, per_segment;
    double step_m; /* per frame */
    double t_open_ms;
    double first_frame_ms, first_frame_open_ms; /* from process start / from opening */
    int msaa;                   /* samples a pixel (--msaa; 0: none) */
    double open_ms, context_ms; /* opening the store (metas, tree); the GL context */
    /* the first frame's parts (ms): process start to this command (the dynamic loader, the
     * libraries' initialisers, main); the renderer (shaders) and the stream (loader thread);
     * the first cut and stream frame; the first draw until glFinish */
    double entered_ms, renderer_ms, stream_create_ms, first_cut_ms, first_draw_ms;
    double georef_wait_ms; /* waiting for the georeference made on a thread since the open */
    double base_rss_mb, base_anon_mb; /* after opening the store and the GL context */
    uint16_t* leaf;             /* the leaf ground_m read last */
    int64_t leaf_id;
    /* the stream's failure lines said so far (hashes): each once a run, not once a
     * configuration's stream */
    uint64_t said[64];
    int said_count;
} store_bench;

/* Whether line was said already this run (each configuration's stream says a failure once;
 * a node failing in every configuration is said once a run); remembers it (bench_store_error.c). */
int tp_bench_store_said_before(store_bench* b, const char* line);

/* The camera d metres along stretch seg of the flight (negative: before its start;
 * bench_store_path.c). The low path reads the ground under it into b->leaf. */
void tp_bench_store_camera(store_bench* b, int seg, double d, tp_camera* cam);

/* The screen error of frame k (cam, the cut drawn) into row, untimed: the leaves of at most
 * about --error-posts posts, chosen anew each frame, read from the store where the stream does
 * not hold them (tp_store_scene_measure); one that cannot be read is said once and left out.
 * 0 after a message (out of memory). bench_store_error.c. */
int tp_bench_store_measure(store_bench* b, const tp_cut* cut, const tp_camera* cam, int k,
                           store_row* row);
/* The error's part of c's summary over its n rows (v: n doubles of scratch): frames measured
 * without and with substitution, their max and RMS, how much of the cut was measured. */
void tp_bench_store_error_summary(store_result* c, int n, double* v);
/* bench_store_report.c: the TIN build figures of c's n timed frames (mean count and time a
 * frame, the longest frame's time). */
void tp_bench_store_tin_summary(store_result* c, int n);

/* The summary table on stdout. */
void tp_bench_store_print(const store_bench* b, const char* renderer_name, const store_result* c,
                          int nc);
/* --json, --csv (written whole or not at all); 0 after a message naming the file. */
int tp_bench_store_write_json(const store_bench* b, const char* renderer_name,
                              const store_result* c, int nc);
int tp_bench_store_write_csv(const store_bench* b, const store_result* c, int nc);

#endif /* TP_APP_BENCH_STORE_H */
