/* stitch_add_error.c - the measured error of `--stitch add` (stitch_add_error.h). */
#include "stitch_add_error.h"

#include <math.h>
#include <stdlib.h>

typedef struct add_error {
    const tp_terrain* t;
    int w, h;
    uint8_t* seen; /* per sample: counted already (shared edges are rasterised twice) */
    double max_m, sum_sq;
    size_t samples;
    /* the screen measure (cam given): the camera's frame, tangents of the half angles */
    int screen;
    tp_camera_frame f;
    double tan_x, tan_y, zscale;
    double max_px, sum_px;
    size_t samples_px;
} add_error;

static void to_camera(const tp_camera_frame* f, const double w[3], double c[3])
{
    double d[3] = {w[0] - f->position[0], w[1] - f->position[1], w[2] - f->position[2]};
    c[0] = d[0] * f->right[0] + d[1] * f->right[1] + d[2] * f->right[2];
    c[1] = d[0] * f->up[0] + d[1] * f->up[1] + d[2] * f->up[2];
    c[2] = d[0] * f->forward[0] + d[1] * f->forward[1] + d[2] * f->forward[2];
}

/* The screen error of one sample as tp_selection_measure_screen_error counts it: NaN when the
 * sample (truth) is outside the view or before the near plane (past a far plane), infinite when
 * only the drawn point is behind the eye, else the distance between the two projections (px). */
static double screen_px(const add_error* e, int x, int y, double truth_m, double drawn_m)
{
    double ws[3], wd[3], cs[3], cd[3];
    tp_terrain_grid_to_world(e->t, x, y, &ws[0], &ws[1]);
    wd[0] = ws[0], wd[1] = ws[1];
    ws[2] = truth_m * e->zscale;
    wd[2] = drawn_m * e->zscale;
    to_camera(&e->f, ws, cs);
    if (cs[2] < e->f.near_m || (e->f.far_m > 0 && cs[2] > e->f.far_m) ||
        fabs(cs[0]) > e->tan_x * cs[2] || fabs(cs[1]) > e->tan_y * cs[2])
        return NAN;
    if (wd[2] == ws[2])
        return 0;
    to_camera(&e->f, wd, cd);
    if (cd[2] <= 0)
        return INFINITY;
    double du = e->f.focal_px * (cd[0] / cd[2] - cs[0] / cs[2]);
    double dv = e->f.focal_px * (cd[1] / cd[2] - cs[1] / cs[2]);
    return sqrt(du * du + dv * dv);
}

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
    if (e->screen) {
        double px = screen_px(e, x, y, s, z);
        if (!isnan(px)) {
            e->max_px = fmax(e->max_px, px);
            e->sum_px += px * px;
            e->samples_px++;
        }
    }
}

tp_status tp_stitch_add_error(const tp_terrain* t, const tp_selection* sel,
                                    const tp_camera* cam, tp_error_measure* out, double* max_px,
                                    double* rms_px)
{
    tp_terrain_info in;
    tp_terrain_get_info(t, &in);
    int n = in.n;
    size_t side = ((size_t)1 << n) + 1, cap = 0;
    add_error e = {.t = t, .w = in.width, .h = in.height, .screen = cam != NULL};
    if (cam) {
        tp_camera_get_frame(cam, &e.f);
        e.tan_x = 0.5 * e.f.width_px / e.f.focal_px;
        e.tan_y = 0.5 * e.f.height_px / e.f.focal_px;
        e.zscale = tp_selection_vertical_scale(sel);
    }
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
    if (cam) {
        *max_px = e.max_px;
        *rms_px = e.samples_px ? sqrt(e.sum_px / (double)e.samples_px) : 0;
    }
done:
    free(e.seen);
    free(v);
    free(tri);
    return status;
}
