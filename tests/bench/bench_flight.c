/* bench_flight.c - a streamed flight over a store without a GL context (not a test; not run by
 * ctest): the viewer's CPU side per frame (tp_cut_update, then tp_stream_frame with its
 * prefetch) and how many frames draw substitutes, in real time at 30 Hz (each frame waits for
 * the rest of its 1/30 s, so the stream's loader and motion estimate see a real 30 Hz viewer;
 * the draw is what is left out). The flight is `terrapatch bench`'s low path: 60 m above the
 * ground along the map's middle row, west to east, 10 degrees down, 1280x720, 60 degrees,
 * starting at 5% of the width after the stream has loaded what the first view asks for.
 *
 *   build/tp_bench_flight STORE.tpt [frames] [speed_mps] [tau_px] [memory_mb] [no_prefetch]
 *
 * Prints the medians of cut, stream and their sum (ms), frames with substitution, and the
 * prefetch cut's selections. */
#define _POSIX_C_SOURCE 200809L
#include "tp_core.h"
#include "tp_io.h"

#include "stream.h"
#include "bench_util.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int main(int argc, char** argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s STORE.tpt [frames] [speed_mps] [tau_px] [memory_mb] [no_prefetch]\n",
                argv[0]);
        return 2;
    }
    int frames = argc > 2 ? atoi(argv[2]) : 300;
    double speed = argc > 3 ? atof(argv[3]) : 100;
    double tau = argc > 4 ? atof(argv[4]) : 1;
    size_t memory_mb = argc > 5 ? (size_t)atoi(argv[5]) : 256;
    int no_prefetch = argc > 6 && atoi(argv[6]);
    tp_error err;
    tp_store* store;
    if (tp_store_open(argv[1], &store, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    tp_tree* tree;
    if (tp_tree_create_from_store(store, &tree, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    tp_stream_options so = {.memory_bytes = memory_mb << 20};
    tp_stream* st = tp_stream_create(store, tree, &so, &err);
    if (!st) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    tp_cut *cut, *pre;
    if (tp_cut_create(tree, &cut, &err) != TP_OK || tp_cut_create(tree, &pre, &err) != TP_OK)
        return 1;
    tp_lod_params lod = {.mode = TP_LOD_ERROR, .tau_px = tau};
    const tp_tree_geometry* g = tp_tree_get_geometry(tree);
    tp_tree_info ti;
    tp_tree_get_info(tree, &ti);
    const double* gt = ti.geotransform;
    double w = g->src_width - 1, y = (g->src_height - 1) / 2.0, x0 = 0.05 * w;
    double step_px = speed / 30 / fabs(gt[1]);
    /* The ground under the camera from the leaf there, read now (the flight is known ahead). */
    double* ground = malloc((size_t)frames * sizeof *ground);
    for (int f = 0; f < frames; f++) {
        double x = fmin(x0 + f * step_px, w);
        int64_t leaf = tp_tree_node_id(g, 0, (int)x >> g->n, (int)y >> g->n);
        size_t v = ((size_t)1 << g->n) + 1;
        uint16_t* b = malloc(v * v * sizeof *b);
        ground[f] = 0;
        if (b && tp_store_read_node(store, leaf, b, v * v, &err) == TP_OK) {
            uint16_t q = b[(size_t)((int)y & ((1 << g->n) - 1)) * v + ((int)x & ((1 << g->n) - 1))];
            if (q != TP_TREE_NO_HEIGHT)
                ground[f] = (q + tp_tree_meta(tree, leaf)->qmin) * ti.height_step_m;
        }
        free(b);
    }
    tp_camera cam;
    double pos[3] = {gt[0] + x0 * gt[1], gt[3] + y * gt[5], ground[0] + 60};
    tp_camera_from_pose(pos, 90, -10, 60, 1280, 720, &cam);
    for (int i = 0; i < 20000; i++) { /* settle: load what the first view asks for */
        tp_cut_update(cut, &cam, &lod, &err);
        tp_stream_stats ss;
        tp_stream_frame(st, cut, NULL, &cam, &lod, &ss);
        size_t nreq;
        tp_cut_requests(cut, &nreq);
        if (nreq == 0 && ss.pending == 0)
            break;
        struct timespec ts = {0, 1000000};
        nanosleep(&ts, NULL);
    }
    double* t_cut = malloc((size_t)frames * sizeof *t_cut);
    double* t_stream = malloc((size_t)frames * sizeof *t_stream);
    double* t_cpu = malloc((size_t)frames * sizeof *t_cpu);
    int subst_frames = 0, subst_max = 0, overrun = 0;
    double start = bench_now_ms();
    for (int f = 0; f < frames; f++) {
        double x = fmin(x0 + f * step_px, w);
        pos[0] = gt[0] + x * gt[1];
        pos[2] = ground[f] + 60;
        tp_camera_from_pose(pos, 90, -10, 60, 1280, 720, &cam);
        double t0 = bench_now_ms();
        tp_cut_update(cut, &cam, &lod, &err);
        double t1 = bench_now_ms();
        tp_stream_stats ss;
        tp_stream_frame(st, cut, no_prefetch ? NULL : pre, &cam, &lod, &ss);
        double t2 = bench_now_ms();
        t_cut[f] = t1 - t0, t_stream[f] = t2 - t1, t_cpu[f] = t2 - t0;
        /* from the nodes, not tp_cut_get_stats: that counted triangles cell by cell before
         * (14-30 ms a frame here), which would leave no 30 Hz flight to compare with */
        size_t nn;
        const tp_cut_node* nodes = tp_cut_nodes(cut, &nn);
        int substituted = 0;
        for (size_t i = 0; i < nn; i++)
            substituted += nodes[i].substituted != 0;
        subst_frames += substituted > 0;
        subst_max = substituted > subst_max ? substituted : subst_max;
        double next = start + (f + 1) * 1000.0 / 30;
        double left = next - bench_now_ms();
        if (left > 0) {
            struct timespec ts = {0, (long)(left * 1e6)};
            nanosleep(&ts, NULL);
        } else {
            overrun++;
        }
    }
    printf("%s: %d frames at 30 Hz, %.0f m/s, tau %.2f, %zu MB%s: cut %.3f ms, stream %.3f ms, "
           "cut+stream %.3f ms (medians); %d frames with substitution (at most %d nodes); %d "
           "frames over 1/30 s\n",
           argv[1], frames, speed, tau, memory_mb, no_prefetch ? ", no prefetch" : "",
           bench_median(t_cut, (size_t)frames), bench_median(t_stream, (size_t)frames),
           bench_median(t_cpu, (size_t)frames), subst_frames, subst_max, overrun);
    free(t_cut);
    free(t_stream);
    free(t_cpu);
    free(ground);
    tp_cut_destroy(cut);
    tp_cut_destroy(pre);
    tp_stream_destroy(st);
    tp_tree_destroy(tree);
    tp_store_close(store);
    return 0;
}
