/* bench_cut.c - the CPU side of a store's frame without a GL context (not a test; not run by
 * ctest): every node of the store resident, a low flight along the map's middle row as
 * `terrapatch bench --segments F --frames F` flies it (60 m above the ground, west to east, 10
 * degrees down, 1280x720, 60 degrees; one timed frame per stretch after 5 untimed ones of
 * flight at 30 Hz), and per timed frame the median time of tp_cut_update (error mode, tau), of
 * tp_cut_update_requests for the camera 0.5 s ahead (what the stream's prefetch runs; binaries
 * built before that function existed ran tp_cut_update there), and of
 * tp_cut_get_stats, and of tp_cut_repair carrying the cut to the next frame's camera (1/30 s
 * on; the cut worker's frames that are not kept) and to the prefetch camera (what the worker
 * does for the prefetch cut before it selects one), with how many it carried. Also the checksum
 * of the cuts (nodes, levels, neighbours), to compare builds.
 *
 *   build/tp_bench_cut STORE.tpt [frames] [tau_px] [speed_mps] [repeats] [add]
 *
 * add = 1: both cuts with --stitch add (tp_cut_set_stitch_add).
 *
 * Made to be run under callgrind or perf too (everything resident: no loader thread). */
#define _POSIX_C_SOURCE 200809L
#include "tp_core.h"
#include "tp_io.h"
#include "bench_resident.h"
#include "bench_util.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static void camera(const tp_tree* t, const double gt[6], double x, double y, tp_camera* cam)
{
    double z = tp_tree_sample(t, (int)x, (int)y);
    double pos[3] = {gt[0] + x * gt[1], gt[3] + y * gt[5], (isnan(z) ? 0 : z) + 60};
    tp_camera_from_pose(pos, 90, -10, 60, 1280, 720, cam);
}

static uint64_t cut_hash(const tp_cut* c)
{
    size_t count;
    const tp_cut_node* o = tp_cut_nodes(c, &count);
    uint64_t h = 1469598103934665603ull;
    for (size_t i = 0; i < count; i++) {
        uint64_t v[3] = {(uint64_t)o[i].node, (uint64_t)o[i].level,
                         (uint64_t)(uint8_t)o[i].nb[0] | (uint64_t)(uint8_t)o[i].nb[1] << 8 |
                             (uint64_t)(uint8_t)o[i].nb[2] << 16 | (uint64_t)(uint8_t)o[i].nb[3] << 24};
        for (int k = 0; k < 3; k++)
            h = (h ^ v[k]) * 1099511628211ull;
    }
    return h;
}

int main(int argc, char** argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s STORE.tpt [frames] [tau_px] [speed_mps] [repeats] [add]\n",
                argv[0]);
        return 2;
    }
    int frames = argc > 2 ? atoi(argv[2]) : 60;
    double tau = argc > 3 ? atof(argv[3]) : 1;
    double speed = argc > 4 ? atof(argv[4]) : 100;
    int repeats = argc > 5 ? atoi(argv[5]) : 3;
    int add = argc > 6 ? atoi(argv[6]) : 0;
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
    const tp_tree_geometry* g = tp_tree_get_geometry(tree);
    uint16_t* blocks = bench_attach_all(store, tree);
    if (!blocks)
        return 1;
    tp_cut *cut, *pre, *carried, *carried_pre;
    if (tp_cut_create(tree, &cut, &err) != TP_OK || tp_cut_create(tree, &pre, &err) != TP_OK ||
        tp_cut_create(tree, &carried, &err) != TP_OK ||
        tp_cut_create(tree, &carried_pre, &err) != TP_OK)
        return 1;
    tp_cut_set_stitch_add(cut, add);
    tp_cut_set_stitch_add(pre, add);
    tp_lod_params lod = {.mode = TP_LOD_ERROR, .tau_px = tau};
    tp_tree_info ti;
    tp_tree_get_info(tree, &ti);
    const double* gt = ti.geotransform;
    double w = g->src_width - 1, y = (g->src_height - 1) / 2.0;
    double* t_cut = malloc((size_t)frames * repeats * sizeof *t_cut);
    double* t_pre = malloc((size_t)frames * repeats * sizeof *t_pre);
    double* t_stats = malloc((size_t)frames * repeats * sizeof *t_stats);
    double* t_carry = malloc((size_t)frames * repeats * sizeof *t_carry);
    double* t_carry_pre = malloc((size_t)frames * repeats * sizeof *t_carry_pre);
    double visited = 0, drawn = 0, tris = 0;
    int carries = 0, carries_pre = 0;
    uint64_t h = 0;
    for (int rep = 0; rep < repeats; rep++)
        for (int f = 0; f < frames; f++) {
            /* spread along the row as `bench --segments frames` spreads its stretches */
            double x = 0.05 * w + (frames > 1 ? 0.9 * w * f / (frames - 1) : 0);
            tp_camera cam, ahead;
            for (int j = 5; j > 0; j--) { /* untimed lead-in frames of a 30 Hz flight */
                camera(tree, gt, x - j * speed / 30 / fabs(gt[1]), y, &cam);
                tp_cut_update(cut, &cam, &lod, &err);
            }
            camera(tree, gt, x, y, &cam);
            ahead = cam;
            ahead.position[0] += speed * 0.5 * (gt[1] > 0 ? 1 : -1);
            double t0 = bench_now_ms();
            if (tp_cut_update(cut, &cam, &lod, &err) != TP_OK) {
                fprintf(stderr, "%s\n", err.message);
                return 1;
            }
            double t1 = bench_now_ms();
            tp_cut_update_requests(pre, &ahead, &lod, &err);
            double t2 = bench_now_ms();
            tp_cut_stats cs;
            tp_cut_get_stats(cut, &cs);
            double t3 = bench_now_ms();
            tp_camera next;
            camera(tree, gt, x + speed / 30 / fabs(gt[1]), y, &next);
            int ok = tp_cut_repair(carried, cut, &next);
            double t4 = bench_now_ms();
            int ok_pre = tp_cut_repair(carried_pre, cut, &ahead); /* the worker's prefetch */
            double t5 = bench_now_ms();
            size_t k = (size_t)rep * frames + f;
            t_cut[k] = t1 - t0, t_pre[k] = t2 - t1, t_stats[k] = t3 - t2, t_carry[k] = t4 - t3;
            t_carry_pre[k] = t5 - t4;
            carries += ok, carries_pre += ok_pre;
            if (rep == 0) {
                visited += cs.visited, drawn += cs.drawn, tris += (double)cs.triangles;
                h = h * 31 + cut_hash(cut);
            }
        }
    size_t n = (size_t)frames * repeats;
    printf("%s: %d frames x %d, tau %.2f, %.0f m/s: cut %.4f ms, prefetch cut %.4f ms, stats "
           "%.4f ms, carried to the next frame %.4f ms (%d of %zu carried), carried to the "
           "prefetch camera %.4f ms (%d carried) (medians)%s; mean visited %.0f, drawn %.0f, "
           "triangles %.0f; cuts %016llx\n",
           argv[1], frames, repeats, tau, speed, bench_median(t_cut, n), bench_median(t_pre, n),
           bench_median(t_stats, n), bench_median(t_carry, n), carries, n,
           bench_median(t_carry_pre, n), carries_pre,
           add ? ", --stitch add" : "", visited / frames, drawn / frames, tris / frames,
           (unsigned long long)h);
    free(t_cut);
    free(t_pre);
    free(t_stats);
    free(t_carry);
    free(t_carry_pre);
    tp_cut_destroy(carried);
    tp_cut_destroy(carried_pre);
    tp_cut_destroy(cut);
    tp_cut_destroy(pre);
    tp_tree_destroy(tree);
    free(blocks);
    tp_store_close(store);
    return 0;
}
