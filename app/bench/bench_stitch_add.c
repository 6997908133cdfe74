/* bench_stitch_add.c - the measured error of `--stitch add` (see bench.h). */
#include "bench.h"

#include <math.h>
#include <stdlib.h>

typedef struct add_error {
    const tp_terrain* t;
    int w, h;
    uint8_t* seen; /* per sample: counted already (shared edges are rasterised twice) */
    double max_m, sum_sq;
    size_t samples;
} add_error;

static void visit(int x, int y, double z, void* user)
{
    add_error* e = user;
    if (x < 0 || y < 0 || x >= e->w || y >= e->h || e->seen[(size_t)y * e->w + x])
        return;
    double s = tp_terrain_sample(e->t, x, y);
    if (isnan(s))
        return; /* not drawn */
    e->seen[(size_t)y * e->w + x] = 1;
    double d = fabs(z - s);
    e->max_m = fmax(e->max_m, d);
    e->sum_sq += d * d;
    e->samples++;
}

tp_status tp_bench_stitch_add_error(const tp_terrain* t, const tp_selection* sel,
                                    tp_error_measure* out)
{
    tp_terrain_info in;
    tp_terrain_get_info(t, &in);
    int n = in.n;
    size_t side = ((size_t)1 << n) + 1, cap = 0;
    add_error e = {.t = t, .w = in.width, .h = in.height};
    e.seen = calloc((size_t)in.width * in.height, 1);
    tp_vertex* v = malloc(side * side * sizeof *v);
    uint32_t* tri = NULL;
    tp_status status = TP_OK;
    if (!e.seen || !v) {
        status = TP_ERR_OUT_OF_MEMORY;
        goto done;
    }
    for (int p = 0; p < in.patch_count; p++) {
        if (!tp_selection_visible(sel, p))
            continue;
        int nb[4], k = tp_selection_level(sel, p);
        tp_selection_neighbor_levels(sel, p, nb);
        tp_patch_info pi;
        tp_patch_get_info(t, p, &pi);
        /* every sample of the patch, unmoved: the triangles index them (as the renderer's sets) */
        tp_patch_vertices(t, p, n, NULL, v, side * side);
        size_t nt = pi.complete ? tp_patch_triangles_add(n, k, nb, NULL, 0)
                                : tp_patch_triangles(v, n, NULL, 0);
        if (nt > cap) {
            uint32_t* grown = realloc(tri, 3 * nt * sizeof *tri);
            if (!grown) {
                status = TP_ERR_OUT_OF_MEMORY;
                goto done;
            }
            tri = grown;
            cap = nt;
        }
        if (pi.complete)
            tp_patch_triangles_add(n, k, nb, tri, nt);
        else
            tp_patch_triangles(v, n, tri, nt);
        for (size_t i = 0; i < nt; i++) {
            const tp_vertex *a = &v[tri[3 * i]], *b = &v[tri[3 * i + 1]], *c = &v[tri[3 * i + 2]];
            int32_t pa[2] = {a->x, a->y}, pb[2] = {b->x, b->y}, pc[2] = {c->x, c->y};
            tp_triangle_rasterize(pa, pb, pc, a->z_m, b->z_m, c->z_m, visit, &e);
        }
    }
    out->max_error_m = e.max_m;
    out->rms_error_m = e.samples ? sqrt(e.sum_sq / (double)e.samples) : 0;
    out->samples = e.samples;
done:
    free(e.seen);
    free(v);
    free(tri);
    return status;
}
