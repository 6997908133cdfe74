/* bench_spheres.c - the selection's CPU time per frame, distance mode, plain traversal against
 * the sphere tree (tp_lod_params.sphere_tree, cut_spheres.c), on a store, without GL (not a
 * test; not run by ctest). Two cuts over one tree, one per way, see the same cameras; before
 * each timed frame the nodes the cut asks for are read and attached (untimed, until it asks
 * for nothing), so both select over the same resident nodes. Each frame is timed as the
 * thread's CPU time of one tp_cut_update (CLOCK_THREAD_CPUTIME_ID: the machine is shared), the
 * two ways alternating which goes first; the cuts are compared node by node (any difference
 * is reported and fails the run).
 *
 * Scenarios, 30 Hz, 1280x720, 60 degrees, 10 degrees down, eye 60 m above the ground at the
 * map's middle row unless said:
 *   still   F frames at one camera
 *   walk    F frames at 1.5 m/s eastwards
 *   fly     F frames at 100 m/s eastwards
 *   fast    F frames at 1000 m/s eastwards, 500 m above the ground
 *   turn    F frames turning on the spot, 3 degrees a frame
 *
 *   build/tp_bench_spheres STORE.tpt [frames] [mindist_m maxdist_m]
 *
 * Under callgrind, the inclusive instructions of update_plain and update_spheres compare the two
 * ways without the machine's load (docs/PERFORMANCE.md).
 *
 * Prints per scenario the median and mean CPU ms of each way, and the mean distance decisions,
 * sphere-tree entries visited, cut records visited and nodes drawn per frame. */
#define _POSIX_C_SOURCE 200809L
#include "bench_util.h"
#include "tp_core.h"
#include "tp_io.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static double cpu_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

typedef struct bench {
    tp_store* store;
    tp_tree* tree;
    size_t words;
    uint16_t** blocks; /* per node, NULL until read */
    size_t resident;
} bench;

static int make_resident(bench* b, int64_t id)
{
    if (b->blocks[id])
        return 1;
    tp_error err;
    uint16_t* blk = malloc(b->words * sizeof *blk);
    if (!blk || tp_store_read_node(b->store, id, blk, b->words, &err) != TP_OK) {
        fprintf(stderr, "node %lld: %s\n", (long long)id, blk ? err.message : "out of memory");
        free(blk);
        return 0;
    }
    b->blocks[id] = blk;
    tp_tree_attach(b->tree, id, blk);
    b->resident++;
    return 1;
}

/* The timed updates, one function per way: callgrind's inclusive costs of these two are the
 * instruction counts of each way (callgrind_annotate --inclusive=yes). */
static volatile int last_way; /* keeps the two functions apart (no identical code folding) */

__attribute__((noinline)) static tp_status update_plain(tp_cut* c, const tp_camera* cam,
                                                        const tp_lod_params* lp, tp_error* err)
{
    last_way = 1;
    return tp_cut_update(c, cam, lp, err);
}

__attribute__((noinline)) static tp_status update_spheres(tp_cut* c, const tp_camera* cam,
                                                          const tp_lod_params* lp, tp_error* err)
{
    last_way = 2;
    return tp_cut_update(c, cam, lp, err);
}

static int same_cut(const tp_cut* a, const tp_cut* b)
{
    size_t na, nb;
    const tp_cut_node* oa = tp_cut_nodes(a, &na);
    const tp_cut_node* ob = tp_cut_nodes(b, &nb);
    if (na != nb)
        return 0;
    for (size_t i = 0; i < na; i++)
        if (oa[i].node != ob[i].node || oa[i].level != ob[i].level ||
            memcmp(oa[i].nb, ob[i].nb, sizeof oa[i].nb) || oa[i].substituted != ob[i].substituted)
            return 0;
    return 1;
}

int main(int argc, char** argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s STORE.tpt [frames] [mindist_m maxdist_m]\n", argv[0]);
        return 2;
    }
    int frames = argc > 2 ? atoi(argv[2]) : 120;
    tp_lod_params lod = {.mode = TP_LOD_DISTANCE};
    if (argc > 4)
        lod.mindist_m = atof(argv[3]), lod.maxdist_m = atof(argv[4]);
    bench b = {0};
    tp_error err;
    if (tp_store_open(argv[1], &b.store, &err) != TP_OK ||
        tp_tree_create_from_store(b.store, &b.tree, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    const tp_tree_geometry* g = tp_tree_get_geometry(b.tree);
    b.words = tp_tree_block_words(g->n);
    b.blocks = calloc((size_t)g->node_count, sizeof *b.blocks);
    int64_t* roots = malloc((size_t)g->root_count * sizeof *roots);
    if (!b.blocks || !roots)
        return 1;
    tp_tree_roots(g, roots, (size_t)g->root_count);
    for (int64_t i = 0; i < g->root_count; i++)
        if (!make_resident(&b, roots[i]))
            return 1;
    tp_cut *plain, *sph;
    if (tp_cut_create(b.tree, &plain, &err) != TP_OK || tp_cut_create(b.tree, &sph, &err) != TP_OK)
        return 1;
    tp_tree_info ti;
    tp_tree_get_info(b.tree, &ti);
    const double* gt = ti.geotransform;
    double w = g->src_width - 1, y = (g->src_height - 1) / 2.0, cell = fabs(gt[1]);
    printf("%s: %dx%d, %lld nodes in %d-sample nodes, %lld roots; distance mode, mindist %g m, "
           "maxdist %g m (0 0: 1 and 24 leaf widths)\n",
           argv[1], g->src_width, g->src_height, (long long)g->node_count, (1 << g->n) + 1,
           (long long)g->root_count, lod.mindist_m, lod.maxdist_m);
    printf("%-6s %7s | %9s %9s | %9s %9s | %10s %10s %10s | %8s %7s\n", "", "frames", "plain med",
           "sph med", "plain avg", "sph avg", "dec plain", "dec sph", "sph visit", "records",
           "drawn");
    static const char* names[] = {"still", "walk", "fly", "fast", "turn"};
    double* tp = malloc((size_t)frames * sizeof *tp);
    double* ts = malloc((size_t)frames * sizeof *ts);
    int failures = 0;
    for (int sc = 0; sc < 5; sc++) {
        double speed = sc == 1 ? 1.5 : sc == 2 ? 100 : sc == 3 ? 1000 : 0;
        double above = sc == 3 ? 500 : 60;
        double x0 = 0.3 * w, z0 = tp_tree_sample(b.tree, (int)x0, (int)y);
        z0 = isnan(z0) ? 0 : z0;
        double dec_p = 0, dec_s = 0, visit = 0, records = 0, drawn = 0, sum_p = 0, sum_s = 0;
        for (int f = 0; f < frames; f++) {
            double x = x0 + f * speed / 30 / cell;
            /* a level flight at `above` over the start's ground (as resident now) */
            double pos[3] = {gt[0] + (x + 0.5) * gt[1], gt[3] + (y + 0.5) * gt[5], z0 + above};
            tp_camera cam;
            tp_camera_from_pose(pos, 90 + (sc == 4 ? 3.0 * f : 0), -10, 60, 1280, 720, &cam);
            tp_lod_params lp = lod, ls = lod;
            ls.sphere_tree = 1;
            for (int it = 0; it < 64; it++) { /* residency, untimed */
                if (tp_cut_update(plain, &cam, &lp, &err) != TP_OK) {
                    fprintf(stderr, "%s\n", err.message);
                    return 1;
                }
                size_t nr;
                const int64_t* req = tp_cut_requests(plain, &nr);
                if (!nr)
                    break;
                for (size_t k = 0; k < nr; k++)
                    if (!make_resident(&b, req[k]))
                        return 1;
            }
            double t0, t1, t2;
            if (f % 2) {
                t0 = cpu_ms();
                update_plain(plain, &cam, &lp, &err);
                t1 = cpu_ms();
                update_spheres(sph, &cam, &ls, &err);
                t2 = cpu_ms();
                tp[f] = t1 - t0, ts[f] = t2 - t1;
            } else {
                t0 = cpu_ms();
                update_spheres(sph, &cam, &ls, &err);
                t1 = cpu_ms();
                update_plain(plain, &cam, &lp, &err);
                t2 = cpu_ms();
                ts[f] = t1 - t0, tp[f] = t2 - t1;
            }
            sum_p += tp[f], sum_s += ts[f];
            if (!same_cut(plain, sph)) {
                fprintf(stderr, "%s frame %d: the cuts differ\n", names[sc], f);
                failures++;
            }
            tp_cut_stats sp, ss;
            tp_cut_get_stats(plain, &sp);
            tp_cut_get_stats(sph, &ss);
            dec_p += sp.decisions, dec_s += ss.decisions, visit += ss.sphere_visited;
            records += sp.visited, drawn += sp.drawn;
        }
        printf("%-6s %7d | %9.4f %9.4f | %9.4f %9.4f | %10.0f %10.1f %10.1f | %8.0f %7.0f\n",
               names[sc], frames, bench_median(tp, (size_t)frames),
               bench_median(ts, (size_t)frames), sum_p / frames, sum_s / frames, dec_p / frames,
               dec_s / frames, visit / frames, records / frames, drawn / frames);
    }
    tp_cut_stats ss;
    tp_cut_get_stats(sph, &ss);
    printf("(CPU ms of one tp_cut_update per frame; dec: distance decisions a frame; sph visit: "
           "sphere-tree entries visited; records: cut nodes visited (both ways); sphere tree "
           "held at the end: %d entries; %zu nodes resident; %d frames with different cuts)\n",
           ss.sphere_nodes, b.resident, failures);
    free(tp);
    free(ts);
    tp_cut_destroy(plain);
    tp_cut_destroy(sph);
    int64_t node_count = g->node_count;
    tp_tree_destroy(b.tree);
    for (int64_t i = 0; i < node_count; i++)
        free(b.blocks[i]);
    free(b.blocks);
    free(roots);
    tp_store_close(b.store);
    return failures ? 1 : 0;
}
