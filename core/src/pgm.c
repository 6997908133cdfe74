/* pgm.c - Persistent Grid Mapping (Livny, Kogan & El-Sana, seeds/001, section 3): the
 * elevation pyramid (point-sampled levels), the auxiliary camera (Eq. 2), one frame's set-up
 * and the mapping of one grid vertex: the ray through it meets the base plane (Eq. 1), the
 * distance r to its farthest neighbour (Eq. 3) picks the level, blended with the parent
 * (Eq. 4 as W_p). The viewer's vertex shader computes the same numbers; the error measure is
 * pgm_error.c. */
#include "pgm_int.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* ---- the pyramid ---- */

tp_status tp_pgm_pyramid_build(const float* heights, int width, int height, const double gt[6],
                               tp_pgm_pyramid* out, tp_error* err)
{
    assert(out);
    memset(out, 0, sizeof *out);
    if (!heights || !gt)
        return tp__fail(err, TP_ERR_INVALID_ARG, "pgm pyramid: NULL heights or geotransform");
    if (width < 1 || height < 1)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "pgm pyramid: grid size %d x %d, expected at least 1 x 1", width, height);
    for (int k = 0; k < 6; k++)
        if (!isfinite(gt[k]))
            return tp__fail(err, TP_ERR_INVALID_ARG, "pgm pyramid: geotransform[%d] is not finite",
                            k);
    if (gt[2] != 0 || gt[4] != 0 || gt[1] == 0 || gt[5] == 0)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "pgm pyramid: geotransform (%g, %g, %g, %g, %g, %g) is rotated or has a "
                        "zero post spacing; expected north-up",
                        gt[0], gt[1], gt[2], gt[3], gt[4], gt[5]);
    size_t n = (size_t)width * (size_t)height;
    double mn = INFINITY, mx = -INFINITY;
    for (size_t k = 0; k < n; k++) {
        double z = heights[k];
        if (!isfinite(z))
            return tp__fail(err, TP_ERR_INVALID_ARG,
                            "pgm pyramid: height at post (%d, %d) is %g; fill voids first",
                            (int)(k % (size_t)width), (int)(k / (size_t)width), z);
        mn = z < mn ? z : mn;
        mx = z > mx ? z : mx;
    }
    int w = width, h = height, levels = 0;
    for (;;) {
        out->width[levels] = w;
        out->height[levels] = h;
        size_t cells = (size_t)w * (size_t)h;
        float* z = malloc(cells * sizeof *z);
        if (!z) {
            tp_pgm_pyramid_free(out);
            return tp__fail(err, TP_ERR_OUT_OF_MEMORY,
                            "pgm pyramid: out of memory for level %d (%d x %d)", levels, w, h);
        }
        out->z[levels] = z;
        levels++;
        out->levels = levels;
        int step = 1 << (levels - 1);
        for (int j = 0; j < h; j++) {
            long long sy = (long long)j * step;
            const float* row = heights + (size_t)(sy < height - 1 ? sy : height - 1) * width;
            for (int i = 0; i < w; i++) {
                long long sx = (long long)i * step;
                z[(size_t)j * w + i] = row[sx < width - 1 ? sx : width - 1];
            }
        }
        if ((w <= 2 && h <= 2) || levels == TP_PGM_MAX_LEVELS)
            break;
        w = w / 2 + 1;
        h = h / 2 + 1;
    }
    memcpy(out->geotransform, gt, sizeof out->geotransform);
    out->min_m = mn;
    out->max_m = mx;
    return TP_OK;
}

void tp_pgm_pyramid_free(tp_pgm_pyramid* p)
{
    if (!p)
        return;
    for (int l = 0; l < TP_PGM_MAX_LEVELS; l++)
        free(p->z[l]);
    memset(p, 0, sizeof *p);
}

double tp_pgm_pyramid_sample(const tp_pgm_pyramid* p, int level, double x, double y)
{
    assert(p && p->levels > 0 && level >= 0 && level < p->levels);
    x = fmin(fmax(x, 0), p->width[0] - 1); /* fmax also turns NaN into 0 */
    y = fmin(fmax(y, 0), p->height[0] - 1);
    double s = ldexp(1.0, -level), u = x * s, v = y * s;
    int w = p->width[level], h = p->height[level];
    int i = (int)u, j = (int)v;
    i = i > w - 2 ? w - 2 : i;
    j = j > h - 2 ? h - 2 : j;
    i = i < 0 ? 0 : i;
    j = j < 0 ? 0 : j;
    double fx = u - i, fy = v - j;
    const float* z = p->z[level];
    int i1 = i + 1 < w ? i + 1 : i, j1 = j + 1 < h ? j + 1 : j;
    double z00 = z[(size_t)j * w + i], z10 = z[(size_t)j * w + i1];
    double z01 = z[(size_t)j1 * w + i], z11 = z[(size_t)j1 * w + i1];
    double top = z00 + fx * (z10 - z00), bottom = z01 + fx * (z11 - z01);
    return top + fy * (bottom - top);
}

/* ---- the cameras ---- */

void tp_pgm_aux_camera(const tp_camera* main, double epsilon_rad, tp_camera* aux)
{
    assert(main && aux);
    tp_camera_frame fr;
    tp_camera_get_frame(main, &fr);
    double fov = main->fov_y_rad > 0 ? main->fov_y_rad : 60 * PI / 180;
    double limit = -(fov / 2 + epsilon_rad);
    double pitch = asin(fmax(-1, fmin(1, fr.forward[2])));
    *aux = *main;
    if (pitch <= limit) {
        /* Without roll every corner ray then goes down; a rolled camera's may not. */
        double tx = fr.focal_px > 0 ? 0.5 * fr.width_px / fr.focal_px : 0;
        double ty = fr.focal_px > 0 ? 0.5 * fr.height_px / fr.focal_px : 0;
        double highest = -INFINITY;
        for (int c = 0; c < 4; c++) {
            double a = (c & 1) ? tx : -tx, b = (c & 2) ? ty : -ty;
            double d[3];
            for (int k = 0; k < 3; k++)
                d[k] = fr.forward[k] + a * fr.right[k] + b * fr.up[k];
            highest = fmax(highest, d[2] / sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]));
        }
        if (highest < 0)
            return;
        limit = pitch; /* level the rolled camera at its own pitch */
    }
    /* The heading: up x right is horizontal for a camera without roll, and defined for
     * every pitch (forward alone has none straight up or down). */
    double hx = -fr.right[1], hy = fr.right[0];
    double yaw_deg = (hx == 0 && hy == 0) ? 0 : atan2(hx, hy) * 180 / PI;
    tp_camera pose;
    tp_camera_from_pose(main->position, yaw_deg, limit * 180 / PI, fov * 180 / PI,
                        main->viewport_w_px, main->viewport_h_px, &pose);
    for (int k = 0; k < 3; k++) {
        aux->forward[k] = pose.forward[k];
        aux->up[k] = pose.up[k];
    }
}

void tp_pgm_frame_setup(const tp_camera* main, int cols, int rows, const tp_pgm_pyramid* p,
                        tp_pgm_frame* out)
{
    assert(main && p && out && cols >= 2 && rows >= 2 && p->levels > 0);
    memset(out, 0, sizeof *out);
    out->cols = cols;
    out->rows = rows;
    tp_pgm_aux_camera(main, 1e-3, &out->aux);
    tp_camera_get_frame(&out->aux, &out->aux_frame);
    out->base_m = p->min_m;
    double above = main->position[2] - p->min_m;
    out->eye_above_base_m = above > 1 ? above : 1;
    double dx = (double)out->aux_frame.width_px / (cols - 1);
    double dy = (double)out->aux_frame.height_px / (rows - 1);
    double alpha = atan((dx > dy ? dx : dy) / out->aux_frame.focal_px);
    out->sin_alpha = sin(alpha);
    out->cos_alpha = cos(alpha);
    out->post_m = fmin(fabs(p->geotransform[1]), fabs(p->geotransform[5]));
}

/* ---- one vertex ---- */

void tp__pgm_map_ground(const tp_pgm_frame* f, const tp_pgm_pyramid* p, int i, int j,
                        double ground[4], int* level, double* wp_out)
{
    const tp_camera_frame* a = &f->aux_frame;
    double x_px = (double)i * a->width_px / (f->cols - 1);
    double y_px = (double)j * a->height_px / (f->rows - 1);
    double dir[3];
    tp_camera_pixel_ray(&f->aux, x_px, y_px, dir);
    /* Eq. 1: the aux camera's rays all go down; guard rounding all the same. */
    double dz = dir[2] < -1e-12 ? dir[2] : -1e-12;
    double h = f->eye_above_base_m, t = h / -dz;
    const double* eye = a->position;
    double e = eye[0] + t * dir[0], n = eye[1] + t * dir[1];
    /* Eq. 3 with d = t (dir is unit) and q its horizontal part. */
    double q = t * sqrt(dir[0] * dir[0] + dir[1] * dir[1]);
    double den = h * f->cos_alpha - q * f->sin_alpha;
    double r = den > 0 ? t * t * f->sin_alpha / den : INFINITY;
    double ratio = r / f->post_m;
    int l = 0, last = p->levels - 1;
    if (ratio >= 1) {
        int ex;
        if (isfinite(ratio)) {
            frexp(ratio, &ex); /* ratio = m 2^ex, m in [0.5, 1): floor(log2) = ex - 1 */
            l = ex - 1;
        } else {
            l = last;
        }
    }
    l = l > last ? last : l;
    double wp = 0;
    if (l < last) {
        wp = ldexp(ratio, -l) - 1;
        wp = wp < 0 ? 0 : (wp > 1 ? 1 : wp);
    }
    const double* gt = p->geotransform;
    ground[0] = e;
    ground[1] = n;
    ground[2] = (e - gt[0]) / gt[1] - 0.5;
    ground[3] = (n - gt[3]) / gt[5] - 0.5;
    *level = l;
    *wp_out = wp;
}

int tp_pgm_map_vertex(const tp_pgm_frame* f, const tp_pgm_pyramid* p, int i, int j, double world[3],
                      double* lod)
{
    assert(f && p && world && lod && p->levels > 0);
    double ground[4], wp;
    int l;
    tp__pgm_map_ground(f, p, i, j, ground, &l, &wp);
    double x = ground[2], y = ground[3];
    double z = tp_pgm_pyramid_sample(p, l, x, y);
    if (wp > 0)
        z = (1 - wp) * z + wp * tp_pgm_pyramid_sample(p, l + 1, x, y);
    world[0] = ground[0];
    world[1] = ground[1];
    world[2] = z;
    *lod = l + wp;
    return x >= 0 && x <= p->width[0] - 1 && y >= 0 && y <= p->height[0] - 1;
}
