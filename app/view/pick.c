/* pick.c - ground picking and the measuring tool's points (see pick.h). */
#include "pick.h"

#include "map_grid.h"
#include "measure.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

int tp_view_pick(const tp_view_scene* v, const tp_camera* cam, double x_px, double y_px,
                 double out[3])
{
    double dir[3];
    tp_camera_pixel_ray(cam, x_px, y_px, dir);
    tp_ray_hit hit;
    if (!tp_view_scene_ray_cast(v, cam->position, dir, &hit))
        return 0;
    for (int i = 0; i < 3; i++)
        out[i] = hit.position[i];
    return 1;
}

int tp_view_pick_centre(const tp_view_scene* v, const tp_camera* cam, double out[3])
{
    tp_camera_frame f;
    tp_camera_get_frame(cam, &f);
    return tp_view_pick(v, cam, f.width_px / 2.0, f.height_px / 2.0, out);
}

double tp_view_metres_per_pixel(const tp_view_scene* v, const tp_camera* cam, double x_px,
                                double y_px, double ground[3])
{
    double g[3], c[2], q[3], pq[2];
    if (!tp_view_pick(v, cam, x_px, y_px, g))
        return NAN;
    if (ground)
        memcpy(ground, g, sizeof g);
    g[2] *= tp_view_scene_vertical_scale(v); /* drawn space */
    tp_camera_frame f;
    tp_camera_get_frame(cam, &f);
    double rx = f.right[0], ry = f.right[1], rl = hypot(rx, ry);
    if (!(rl > 1e-9)) {
        rx = 1, ry = 0, rl = 1;
    }
    q[0] = g[0] + 100 * rx / rl, q[1] = g[1] + 100 * ry / rl, q[2] = g[2];
    if (!tp_camera_project(cam, g, c, NULL) || !tp_camera_project(cam, q, pq, NULL))
        return NAN;
    return 100 / fmax(hypot(pq[0] - c[0], pq[1] - c[1]), 1e-6);
}

double tp_view_grid_spacing(const tp_view_scene* v, const tp_camera* cam, double base_m)
{
    if (!(base_m > 0))
        return base_m;
    tp_camera_frame f;
    tp_camera_get_frame(cam, &f);
    double m = tp_view_metres_per_pixel(v, cam, f.width_px / 2.0, f.height_px / 2.0, NULL);
    if (isnan(m)) /* sky at the centre: the ground at the bottom (nearest the eye) */
        m = tp_view_metres_per_pixel(v, cam, f.width_px / 2.0, f.height_px * 0.9, NULL);
    return tp_map_grid_spacing(base_m, m);
}

int tp_view_measure_points(tp_view_scene* v, const double e[2], const double n[2], char* text,
                           size_t cap)
{
    double h[2];
    for (int i = 0; i < 2; i++) {
        double x, y;
        tp_view_scene_world_to_grid(v, e[i], n[i], &x, &y);
        h[i] = tp_view_scene_drawn_height(v, x, y);
        if (isnan(h[i]))
            h[i] = tp_view_scene_ground_height(v, x, y);
        if (isnan(h[i])) {
            snprintf(text, cap, "point %d (E %.3f, N %.3f) is not on the terrain", i + 1, e[i], n[i]);
            return 0;
        }
    }
    tp_measurement m;
    if (!tp_measure(v->georef, e, n, h, &m)) {
        snprintf(text, cap, "the points have no geographic position");
        return 0;
    }
    tp_measurement_text(&m, text, cap);
    return 1;
}

int tp_view_ground_visible(const tp_view_scene* v, const tp_camera* cam, const double p[3])
{
    const double zs = tp_view_scene_vertical_scale(v);
    const double* o = cam->position;
    double d[3] = {p[0] - o[0], p[1] - o[1], p[2] * zs - o[2]};
    double dist = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
    if (!(dist > 0))
        return 0; /* NaN or the eye itself */
    tp_ray_hit hit;
    if (!tp_view_scene_ray_cast(v, o, d, &hit))
        return 1; /* the ray misses the surface (p just off a drawn triangle's edge) */
    double h[3] = {hit.position[0] - o[0], hit.position[1] - o[1], hit.position[2] * zs - o[2]};
    double at = sqrt(h[0] * h[0] + h[1] * h[1] + h[2] * h[2]);
    return at >= dist - TP_VIEW_VISIBLE_TOLERANCE * dist - 1.0;
}
