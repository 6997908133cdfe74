/* bench_tin_nodes.c - what TIN nodes (tp_node_tins_build, issue 32 item 2) save on a store's
 * cuts, without a GL context (not a test; not run by ctest): every node of the store resident,
 * the low flight of tp_bench_cut (60 m above the ground along the middle row, 10 degrees down,
 * 1280x720, 60 degrees), and per frame the drawn nodes' triangles as lattices (2 4^k) against
 * the same nodes and levels drawn as the coarsest rung of the level's TIN ladder whose bound
 * (with the node's neighbour levels) fits what the view allows the node, the lattice where none
 * does. What the view allows: the node's lattice bound scaled by tau / bound_px (the projection
 * is linear in the bound but for d |vz| against the depth, negligible here). Also the time to
 * build the TINs of a drawn level (built once per node and level, as a view would build them
 * lazily) and their bytes.
 *
 *   build/tp_bench_tin_nodes STORE.tpt [frames] [tau_px]
 */
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

static void camera(const tp_tree* t, const double gt[6], double x, double y, tp_camera* cam)
{
    double z = tp_tree_sample(t, (int)x, (int)y);
    double pos[3] = {gt[0] + x * gt[1], gt[3] + y * gt[5], (isnan(z) ? 0 : z) + 60};
    tp_camera_from_pose(pos, 90, -10, 60, 1280, 720, cam);
}

int main(int argc, char** argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s STORE.tpt [frames] [tau_px]\n", argv[0]);
        return 2;
    }
    int frames = argc > 2 ? atoi(argv[2]) : 8;
    double tau = argc > 3 ? atof(argv[3]) : 1;
    tp_error err;
    tp_store* store;
    tp_tree* tree;
    if (tp_store_open(argv[1], &store, &err) != TP_OK ||
        tp_tree_create_from_store(store, &tree, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    const tp_tree_geometry* g = tp_tree_get_geometry(tree);
    uint16_t* blocks = bench_attach_all(store, tree);
    /* built lazily, one level of one node at a time: what a view would build */
    size_t lv = (size_t)g->n + 1;
    tp_node_tins** tins = calloc((size_t)g->node_count * lv, sizeof *tins);
    uint8_t* built = calloc((size_t)g->node_count * lv, 1);
    if (!blocks || !tins || !built)
        return 1;
    tp_tree_info ti;
    tp_tree_get_info(tree, &ti);
    tp_cut* cut;
    if (tp_cut_create(tree, &cut, &err) != TP_OK)
        return 1;
    tp_lod_params lod = {.mode = TP_LOD_ERROR, .tau_px = tau};
    const double* gt = ti.geotransform;
    double w = g->src_width - 1, y = (g->src_height - 1) / 2.0;
    double lat_sum = 0, tin_sum = 0, build_ms = 0, bytes = 0;
    long nodes_built = 0, rung_total = 0;
    double lvl_lat[TP_MAX_LEVELS] = {0}, lvl_tin[TP_MAX_LEVELS] = {0}, lvl_n[TP_MAX_LEVELS] = {0};
    long drawn = 0, drawn_tin = 0, moved = 0;
    double* per_node_ms = malloc((size_t)g->node_count * lv * sizeof *per_node_ms);
    for (int f = 0; f < frames; f++) {
        double x = 0.05 * w + (frames > 1 ? 0.9 * w * f / (frames - 1) : 0);
        tp_camera cam;
        camera(tree, gt, x, y, &cam);
        if (tp_cut_update(cut, &cam, &lod, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
        size_t count;
        const tp_cut_node* o = tp_cut_nodes(cut, &count);
        double lat = 0, tin = 0;
        for (size_t i = 0; i < count; i++) {
            int64_t id = o[i].node;
            int s, c, r, k = o[i].level;
            tp_tree_node_locate(g, id, &s, &c, &r);
            size_t slot = (size_t)id * lv + (size_t)k;
            if (!built[slot]) {
                double t0 = bench_now_ms();
                uint16_t carry[1 << (2 * TP_NODE_CARRY_DEPTH)];
                tp_node_carry_regions(tree, id, carry);
                if (tp_node_tins_build(g->n, s, tp_tree_samples(tree, id), tp_tree_meta(tree, id),
                                       carry, ti.err_unit_steps, 1u << k, &tins[slot],
                                       &err) != TP_OK) {
                    fprintf(stderr, "%s\n", err.message);
                    return 1;
                }
                double ms = bench_now_ms() - t0;
                per_node_ms[nodes_built] = ms;
                build_ms += ms;
                built[slot] = 1;
                nodes_built++;
                bytes += (double)tp_node_tins_bytes(tins[slot]);
                rung_total += tp_node_tins_rungs(tins[slot]);
            }
            double lt = 2.0 * (double)(1u << (2 * k));
            /* what the view allows the node (the projection is close to linear in the bound) */
            int nb[4] = {o[i].nb[0], o[i].nb[1], o[i].nb[2], o[i].nb[3]};
            const tp_node_meta* m = tp_tree_meta(tree, id);
            double bm = tp_node_error_bound(m, g->n, k, nb, ti.height_step_m, ti.err_unit_steps) +
                        ti.quant_max_error_m;
            double lim = o[i].bound_px > 0 ? (bm * tau / o[i].bound_px - ti.quant_max_error_m) /
                                                     ti.height_step_m
                                           : 0; /* steps, carry included */
            int rc;
            const tp_node_tin* rg = tp_node_tins_level(tins[slot], k, &rc);
            const tp_node_tin* use = NULL;
            for (int j = 0; j < rc && !use; j++)
                if (tp_node_tin_bound_steps(&rg[j], o[i].nb) <= lim)
                    use = &rg[j];
            double tt = use ? use->triangle_count : lt;
            lat += lt, tin += tt;
            lvl_lat[k] += lt, lvl_tin[k] += tt, lvl_n[k]++;
            drawn_tin += use != NULL;
            moved += (nb[0] >= 0 && nb[0] < k) || (nb[1] >= 0 && nb[1] < k) ||
                     (nb[2] >= 0 && nb[2] < k) || (nb[3] >= 0 && nb[3] < k);
            drawn++;
        }
        printf("frame %d: %zu nodes, lattice %.0f triangles, with TIN nodes %.0f (%.1f%%)\n", f,
               count, lat, tin, 100 * tin / lat);
        lat_sum += lat, tin_sum += tin;
    }
    printf("%s, tau %.2f px, %d frames: lattice %.0f, TIN nodes %.0f triangles per frame (%.1f%%); "
           "%.1f%% of drawn nodes as TINs\n",
           argv[1], tau, frames, lat_sum / frames, tin_sum / frames, 100 * tin_sum / lat_sum,
           100.0 * drawn_tin / drawn);
    printf("built %ld levels of drawn nodes: %.3f ms median, %.3f ms mean per level; %.1f rungs, "
           "%.0f bytes per level\n",
           nodes_built, nodes_built ? bench_median(per_node_ms, (size_t)nodes_built) : 0,
           nodes_built ? build_ms / nodes_built : 0, nodes_built ? (double)rung_total / nodes_built : 0,
           nodes_built ? bytes / nodes_built : 0);
    for (int k = 0; k <= g->n; k++)
        if (lvl_n[k])
            printf("level %d: %.0f nodes drawn, lattice %.0f, TIN %.0f triangles (%.1f%%)\n", k,
                   lvl_n[k], lvl_lat[k], lvl_tin[k], 100 * lvl_tin[k] / lvl_lat[k]);
    printf("drawn nodes with a moved side: %.1f%%\n", 100.0 * moved / drawn);
    for (size_t i = 0; i < (size_t)g->node_count * lv; i++)
        tp_node_tins_destroy(tins[i]);
    free(per_node_ms);
    free(tins);
    free(built);
    tp_cut_destroy(cut);
    tp_tree_destroy(tree);
    free(blocks);
    tp_store_close(store);
    return 0;
}
