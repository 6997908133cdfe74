/* navigate.c - flying, orbiting and the home view (see navigate.h). */
#include "navigate.h"

#include <math.h>

#define DEG (3.14159265358979323846 / 180.0)

void tp_nav_init(tp_nav* nav, const tp_camera* cam, double extent_m)
{
    *nav = (tp_nav){.extent_m = extent_m, .home = *cam};
    tp_camera_get_pose(cam, &nav->yaw_deg, &nav->pitch_deg);
}

double tp_nav_fly_speed(double agl_m, double extent_m)
{
    double h = isnan(agl_m) ? 1000 : fmax(agl_m, 0);
    double top = fmax(extent_m / 20, 5);
    return fmin(fmax(0.5 * h, 5), top);
}

void tp_nav_home(tp_nav* nav, tp_camera* cam)
{
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    *cam = nav->home;
    cam->viewport_w_px = w;
    cam->viewport_h_px = h;
    nav->orbit = 0;
    tp_camera_get_pose(cam, &nav->yaw_deg, &nav->pitch_deg);
}

void tp_nav_toggle_orbit(tp_nav* nav, const tp_camera* cam, const double g[3])
{
    if (nav->orbit || !g) {
        nav->orbit = 0;
        return;
    }
    nav->orbit = 1;
    double d2 = 0;
    for (int i = 0; i < 3; i++) {
        nav->target[i] = g[i];
        d2 += (g[i] - cam->position[i]) * (g[i] - cam->position[i]);
    }
    nav->distance_m = sqrt(d2);
}

static void pose(const tp_camera* old, const double pos[3], double yaw, double pitch,
                 tp_camera* cam)
{
    int w = old->viewport_w_px, h = old->viewport_h_px;
    double fov = old->fov_y_rad > 0 ? old->fov_y_rad / DEG : 60;
    tp_camera_from_pose(pos, yaw, pitch, fov, w, h, cam);
}

void tp_nav_step(tp_nav* nav, const tp_nav_controls* c, double dt, double ground_z,
                 tp_camera* cam)
{
    nav->yaw_deg = fmod(nav->yaw_deg + 0.2 * c->look_dx + 360, 360);
    nav->pitch_deg = fmax(-89.9, fmin(89.9, nav->pitch_deg - 0.2 * c->look_dy));
    double sy = sin(nav->yaw_deg * DEG), cy = cos(nav->yaw_deg * DEG);
    double factor = c->speed_factor > 0 ? c->speed_factor : 1;
    tp_camera old = *cam;
    if (nav->orbit) {
        /* wheel or W/S zoom, A/D/Q/E pan the target over the ground */
        double zoom = pow(0.85, c->zoom_steps) * pow(0.3, c->forward * dt * factor);
        nav->distance_m = fmax(20, nav->distance_m * zoom);
        double pan = 0.8 * nav->distance_m * dt * factor;
        nav->target[0] += pan * (c->right * cy + c->up * sy);
        nav->target[1] += pan * (-c->right * sy + c->up * cy);
        double cp = cos(nav->pitch_deg * DEG);
        double pos[3] = {nav->target[0] - nav->distance_m * cp * sy,
                         nav->target[1] - nav->distance_m * cp * cy,
                         nav->target[2] - nav->distance_m * sin(nav->pitch_deg * DEG)};
        nav->speed_mps = 0;
        pose(&old, pos, nav->yaw_deg, nav->pitch_deg, cam);
        return;
    }
    nav->speed_mps = tp_nav_fly_speed(cam->position[2] - ground_z, nav->extent_m) * factor;
    double step = nav->speed_mps * dt;
    double pos[3] = {cam->position[0] + step * (c->forward * sy + c->right * cy),
                     cam->position[1] + step * (c->forward * cy - c->right * sy),
                     cam->position[2] + step * c->up};
    pose(&old, pos, nav->yaw_deg, nav->pitch_deg, cam);
}
