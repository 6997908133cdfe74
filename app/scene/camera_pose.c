/* camera_pose.c - cameras from the command line (see camera_pose.h). */
#include "camera_pose.h"

#include "cli.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define DEG (3.14159265358979323846 / 180.0)

void tp_camera_pose(double e, double n, double h, double yaw_deg, double pitch_deg, double fov_deg,
                    int width_px, int height_px, tp_camera* cam)
{
    double pos[3] = {e, n, h};
    tp_camera_from_pose(pos, yaw_deg, pitch_deg, fov_deg, width_px, height_px, cam);
}

void tp_camera_default(const tp_scene* sc, double fov_deg, int width_px, int height_px,
                       double vertical_scale, tp_camera* cam)
{
    const tp_terrain_info* in = &sc->info;
    tp_camera_default_extent(in->geotransform, in->src_width, in->src_height, in->min_height_m,
                             in->max_height_m, fov_deg, width_px, height_px, vertical_scale, cam);
}

void tp_camera_default_extent(const double gt[6], int src_width, int src_height,
                              double min_height_m, double max_height_m, double fov_deg,
                              int width_px, int height_px, double vertical_scale, tp_camera* cam)
{
    double e0 = gt[0] + 0.5 * gt[1], n0 = gt[3] + 0.5 * gt[5];
    double e1 = gt[0] + (src_width - 0.5) * gt[1], n1 = gt[3] + (src_height - 0.5) * gt[5];
    double size = fmax(fabs(e1 - e0), fabs(n1 - n0));
    /* exaggerated relief: aim at its middle and back off by the extra height */
    double zs = vertical_scale > 0 ? vertical_scale : 1;
    double extra = fmax(zs - 1, 0) * (max_height_m - min_height_m);
    double pitch = -50, d = (0.45 * size + extra) / tan(fov_deg * DEG / 2);
    double target[3] = {(e0 + e1) / 2, (n0 + n1) / 2, zs * (min_height_m + max_height_m) / 2};
    /* back off until the DEM's eight corners (its extent at its lowest and highest drawn
     * heights) are on screen with a margin: a long DEM, a wide one or a tall viewport would
     * otherwise lose its near or side corners */
    const double lo = isfinite(min_height_m) ? zs * min_height_m : 0;
    const double hi = isfinite(max_height_m) ? zs * max_height_m : 0;
    for (int tries = 0; tries < 60; tries++) {
        tp_camera_pose(target[0], target[1] - d * cos(pitch * DEG),
                       target[2] - d * sin(pitch * DEG), 0, pitch, fov_deg, width_px, height_px,
                       cam);
        const double w = cam->viewport_w_px > 0 ? cam->viewport_w_px : 1280;
        const double h = cam->viewport_h_px > 0 ? cam->viewport_h_px : 720;
        const double m = 0.02 * fmin(w, h);
        int inside = 1;
        for (int c = 0; c < 8 && inside; c++) {
            const double p[3] = {c & 1 ? e1 : e0, c & 2 ? n1 : n0, c & 4 ? hi : lo};
            double px[2];
            inside = tp_camera_project(cam, p, px, NULL) && px[0] >= m && px[0] <= w - m &&
                     px[1] >= m && px[1] <= h - m;
        }
        if (inside)
            return;
        d *= 1.1;
    }
}

int tp_camera_refuse_degrees(const char* cmd, const tp_georef* g, int geo, const double v[5],
                             const double gt[6], int width, int height)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    if (geo || !tp_georef_has_geo(g) || !(fabs(v[0]) <= 180 && fabs(v[1]) <= 180))
        return 0;
    /* the DEM's extent, grown by its own size each way: a camera there is a place (a polar
     * stereographic grid holds the pole at 0, 0) */
    const double e0 = gt[0], e1 = gt[0] + width * gt[1];
    const double n0 = gt[3] + height * gt[5], n1 = gt[3];
    const double de = fabs(e1 - e0), dn = fabs(n1 - n0);
    if (v[0] >= fmin(e0, e1) - de && v[0] <= fmax(e0, e1) + de && v[1] >= fmin(n0, n1) - dn &&
        v[1] <= fmax(n0, n1) + dn)
        return 0;
    /* latitude first in the suggestion, whichever order was typed */
    const int swap = fabs(v[0]) > 90 && fabs(v[1]) <= 90;
    tp_cli_error("--camera %g,%g,...: those look like latitude and longitude, but "
                 "--camera takes metres of the render CRS (E,N,H,YAW,PITCH); use --camera-geo "
                 "%g,%g,%g,%g,%g",
                 v[0], v[1], swap ? v[1] : v[0], swap ? v[0] : v[1], v[2], v[3], v[4]);
    return 1;
}

int tp_camera_from_option(const tp_scene* sc, int geo, const double v[5], double fov_deg,
                          int width_px, int height_px, tp_camera* cam, const char* cmd)
{
    if (tp_camera_refuse_degrees(cmd, sc->georef, geo, v, sc->info.geotransform, sc->info.src_width,
                                 sc->info.src_height))
        return 0;
    return tp_camera_from_option_georef(sc->georef, geo, v, fov_deg, width_px, height_px, cam, cmd);
}

int tp_camera_from_option_georef(const tp_georef* g, int geo, const double v[5], double fov_deg,
                                 int width_px, int height_px, tp_camera* cam, const char* cmd)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    double e = v[0], n = v[1];
    if (geo) {
        tp_error err;
        if (tp_georef_geo_to_proj(g, v[0], v[1], &e, &n, &err) != TP_OK) {
            tp_cli_error("--camera-geo: %s", err.message);
            return 0;
        }
    }
    tp_camera_pose(e, n, v[2], v[3], v[4], fov_deg, width_px, height_px, cam);
    return 1;
}

void tp_camera_text(const tp_scene* sc, const tp_camera* cam, char* out, size_t cap)
{
    tp_camera_text_georef(sc->georef, cam, out, cap);
}

void tp_camera_text_georef(const tp_georef* g, const tp_camera* cam, char* out, size_t cap)
{
    double yaw, pitch, lat, lon;
    tp_camera_get_pose(cam, &yaw, &pitch);
    int at = snprintf(out, cap, "--camera %.3f,%.3f,%.2f,%.2f,%.2f", cam->position[0],
                      cam->position[1], cam->position[2], yaw, pitch);
    if (at > 0 && (size_t)at < cap &&
        tp_georef_proj_to_geo(g, cam->position[0], cam->position[1], &lat, &lon, NULL) == TP_OK)
        snprintf(out + at, cap - at, " --camera-geo %.9f,%.9f,%.2f,%.2f,%.2f", lat, lon,
                 cam->position[2], yaw, pitch);
}
