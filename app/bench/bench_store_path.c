/*
 * bench_store_path.c - where the camera of a flight over a store is (bench_store.c describes the
 * flight): d metres along one of its stretches, which lie evenly along a line across the map;
 * the low path's height follows the ground, read from the store's leaves outside the timed part
 * of a frame.
 */
#include "bench_store.h"
#include "camera_pose.h"

#include <math.h>
#include <string.h>

/* The highest sample of leaf (c, r)'s area (m), or the map's lowest where it draws nothing. */
static double leaf_top_m(const store_bench* b, int c, int r)
{
    const tp_node_meta* m = tp_tree_meta(b->sc.tree, tp_tree_node_id(b->g, 0, c, r));
    return m->flags & TP_NODE_HAS_DRAWN ? m->area_qmax * b->sc.tree_info.height_step_m
                                        : b->sc.tree_info.min_height_m;
}

/* Ground height (m) at grid (x, y): bilinear between the full-resolution samples of the leaf
 * under it, read from the store into the bench's own buffer (outside the stream and the
 * timed part of a frame: a height query); where the leaf has undrawn samples there, or cannot
 * be read, the highest sample of its area. */
static double ground_m(store_bench* b, double x, double y)
{
    const tp_tree_geometry* g = b->g;
    int w = 1 << g->n, v = w + 1;
    int c = (int)fmin(fmax(floor(x / w), 0), g->cols - 1);
    int r = (int)fmin(fmax(floor(y / w), 0), g->rows - 1);
    int64_t id = tp_tree_node_id(g, 0, c, r);
    if (id != b->leaf_id) {
        tp_error err;
        b->leaf_id =
            tp_store_read_node(b->sc.store, id, b->leaf, (size_t)v * v, &err) == TP_OK ? id : -1;
        if (b->leaf_id < 0)
            return leaf_top_m(b, c, r);
    }
    double lx = fmin(fmax(x - (double)c * w, 0), w), ly = fmin(fmax(y - (double)r * w, 0), w);
    int i = (int)fmin(floor(lx), w - 1), j = (int)fmin(floor(ly), w - 1);
    double tx = lx - i, ty = ly - j, q[4];
    for (int k = 0; k < 4; k++) {
        uint16_t s = b->leaf[(size_t)(j + k / 2) * v + (size_t)(i + k % 2)];
        if (s == TP_TREE_NO_HEIGHT)
            return leaf_top_m(b, c, r);
        q[k] = s;
    }
    double qmin = tp_tree_meta(b->sc.tree, id)->qmin;
    double s = (1 - ty) * ((1 - tx) * q[0] + tx * q[1]) + ty * ((1 - tx) * q[2] + tx * q[3]);
    return (s + qmin) * b->sc.tree_info.height_step_m;
}

void tp_bench_store_camera(store_bench* b, int seg, double d, tp_camera* cam)
{
    const bench_options* o = b->o;
    const tp_tree_geometry* g = b->g;
    const double* gt = b->sc.tree_info.geotransform;
    double w = g->src_width - 1, hgt = g->src_height - 1;
    double size_m = fmax(w, hgt) * b->spacing_m;
    int high = !strcmp(o->path_name, "high");
    double a0 = high ? 0.1 : 0.05, a1 = high ? 0.9 : 0.95; /* fractions of the width */
    double len_px = b->per_segment * b->step_m / b->spacing_m;
    if (o->realtime) /* a stretch lasts as long as its frames take: leave room for 10 s */
        len_px = fmax(len_px, 10 * o->speed_mps / b->spacing_m);
    double room = fmax((a1 - a0) * w - len_px, 0);
    double x = a0 * w + (b->segments > 1 ? room * seg / (b->segments - 1) : 0) + d / b->spacing_m;
    double e = gt[0] + x * gt[1];
    if (high) {
        double n = fmin(gt[3], gt[3] + hgt * gt[5]) - 0.15 * size_m;
        tp_camera_pose(e, n, b->sc.tree_info.max_height_m + 0.35 * size_m, 0, -35, o->vs.fov_deg,
                       o->vs.w, o->vs.h, cam);
    } else {
        double y = hgt / 2, n = gt[3] + y * gt[5];
        tp_camera_pose(e, n, ground_m(b, x, y) + 60, 90, -10, o->vs.fov_deg, o->vs.w, o->vs.h, cam);
    }
}
