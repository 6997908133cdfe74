/* camera.c - the camera's maths, once: pose to frame, projection and its inverse (pick rays),
 * the view-projection matrix the renderer uploads, and view-frustum culling of patch AABBs
 * (Vanek & Jezek section 3; plane tests with the n- and p-vertex of the box). All in doubles,
 * in world coordinates. */
#include "camera_int.h"

#include <assert.h>
#include <string.h>

static void normalize(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    if (l > 0)
        for (int i = 0; i < 3; i++)
            v[i] /= l;
}

static void cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

void tp__view_from_camera(const tp_camera* cam, tp__view* v)
{
    for (int i = 0; i < 3; i++) {
        v->pos[i] = cam->position[i];
        v->fwd[i] = cam->forward[i];
        v->up[i] = cam->up[i];
    }
    if (v->fwd[0] == 0 && v->fwd[1] == 0 && v->fwd[2] == 0)
        v->fwd[1] = 1; /* north, level */
    if (v->up[0] == 0 && v->up[1] == 0 && v->up[2] == 0)
        v->up[2] = 1;
    normalize(v->fwd);
    cross(v->fwd, v->up, v->right);
    if (v->right[0] == 0 && v->right[1] == 0 && v->right[2] == 0) {
        /* up parallel to forward (looking straight down with up = z): take north as up. */
        double alt[3] = {0, 1, 0};
        if (fabs(v->fwd[1]) > 0.9) {
            alt[1] = 0;
            alt[2] = 1;
        }
        cross(v->fwd, alt, v->right);
    }
    normalize(v->right);
    cross(v->right, v->fwd, v->up);
    double fov = cam->fov_y_rad > 0 ? cam->fov_y_rad : 60.0 * 3.14159265358979323846 / 180.0;
    v->w_px = cam->viewport_w_px > 0 ? cam->viewport_w_px : 1280;
    v->h_px = cam->viewport_h_px > 0 ? cam->viewport_h_px : 720;
    v->tan_y = tan(fov / 2);
    v->tan_x = v->tan_y * v->w_px / v->h_px;
    v->f_px = (v->h_px / 2) / v->tan_y;
    v->near_m = cam->near_m > 0 ? cam->near_m : 1.0;
    v->far_m = cam->far_m > 0 ? cam->far_m : 0;
}

static void set_plane(double pl[4], const double n[3], const double point[3])
{
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int i = 0; i < 3; i++)
        pl[i] = n[i] / l;
    pl[3] = -(pl[0] * point[0] + pl[1] * point[1] + pl[2] * point[2]);
}

void tp_frustum_from_camera(const tp_camera* cam, tp_frustum* out)
{
    assert(cam && out);
    tp__view v;
    tp__view_from_camera(cam, &v);
    double n[3], p[3];
    /* Side planes through the eye: |x| <= tan_x * z and |y| <= tan_y * z in camera space. */
    for (int i = 0; i < 3; i++)
        n[i] = v.right[i] + v.tan_x * v.fwd[i];
    set_plane(out->planes[0], n, v.pos);
    for (int i = 0; i < 3; i++)
        n[i] = -v.right[i] + v.tan_x * v.fwd[i];
    set_plane(out->planes[1], n, v.pos);
    for (int i = 0; i < 3; i++)
        n[i] = v.up[i] + v.tan_y * v.fwd[i];
    set_plane(out->planes[2], n, v.pos);
    for (int i = 0; i < 3; i++)
        n[i] = -v.up[i] + v.tan_y * v.fwd[i];
    set_plane(out->planes[3], n, v.pos);
    for (int i = 0; i < 3; i++)
        p[i] = v.pos[i] + v.near_m * v.fwd[i];
    set_plane(out->planes[4], v.fwd, p);
    out->plane_count = 5;
    if (v.far_m > 0) {
        for (int i = 0; i < 3; i++) {
            p[i] = v.pos[i] + v.far_m * v.fwd[i];
            n[i] = -v.fwd[i];
        }
        set_plane(out->planes[5], n, p);
        out->plane_count = 6;
    }
}

tp_cull tp_frustum_test_aabb(const tp_frustum* f, const double mn[3], const double mx[3])
{
    assert(f && mn && mx);
    tp_cull result = TP_CULL_INSIDE;
    for (int i = 0; i < f->plane_count; i++) {
        const double* pl = f->planes[i];
        double pv = pl[3], nv = pl[3]; /* the box corner furthest along / against the normal */
        for (int a = 0; a < 3; a++) {
            pv += pl[a] * (pl[a] >= 0 ? mx[a] : mn[a]);
            nv += pl[a] * (pl[a] >= 0 ? mn[a] : mx[a]);
        }
        if (pv < 0)
            return TP_CULL_OUTSIDE;
        if (nv < 0)
            result = TP_CULL_INTERSECTS;
    }
    return result;
}

#define DEG (3.14159265358979323846 / 180.0)

void tp_camera_from_pose(const double position[3], double yaw_deg, double pitch_deg,
                         double fov_y_deg, int width_px, int height_px, tp_camera* out)
{
    assert(position && out);
    double y = yaw_deg * DEG, p = pitch_deg * DEG;
    memset(out, 0, sizeof *out);
    for (int i = 0; i < 3; i++)
        out->position[i] = position[i];
    out->forward[0] = sin(y) * cos(p);
    out->forward[1] = cos(y) * cos(p);
    out->forward[2] = sin(p);
    double r[3] = {cos(y), -sin(y), 0};
    cross(r, out->forward, out->up);
    out->fov_y_rad = (fov_y_deg > 0 ? fov_y_deg : 60) * DEG;
    out->viewport_w_px = width_px;
    out->viewport_h_px = height_px;
    out->near_m = 1;
}

void tp_camera_get_pose(const tp_camera* cam, double* yaw_deg, double* pitch_deg)
{
    assert(cam && yaw_deg && pitch_deg);
    tp__view v;
    tp__view_from_camera(cam, &v);
    double yaw = atan2(v.fwd[0], v.fwd[1]) / DEG;
    *yaw_deg = yaw < 0 ? yaw + 360 : yaw;
    if (*yaw_deg >= 360)
        *yaw_deg = 0;
    *pitch_deg = asin(fmax(-1, fmin(1, v.fwd[2]))) / DEG;
}

void tp_camera_get_frame(const tp_camera* cam, tp_camera_frame* out)
{
    assert(cam && out);
    tp__view v;
    tp__view_from_camera(cam, &v);
    for (int i = 0; i < 3; i++) {
        out->position[i] = v.pos[i];
        out->forward[i] = v.fwd[i];
        out->right[i] = v.right[i];
        out->up[i] = v.up[i];
    }
    out->focal_px = v.f_px;
    out->width_px = (int)v.w_px;
    out->height_px = (int)v.h_px;
    out->near_m = v.near_m;
    out->far_m = v.far_m;
}

int tp_camera_project(const tp_camera* cam, const double world[3], double pixel[2],
                      double* depth_m)
{
    assert(cam && world && pixel);
    tp__view v;
    tp__view_from_camera(cam, &v);
    double d[3] = {world[0] - v.pos[0], world[1] - v.pos[1], world[2] - v.pos[2]};
    double z = d[0] * v.fwd[0] + d[1] * v.fwd[1] + d[2] * v.fwd[2];
    if (!(z >= v.near_m))
        return 0;
    pixel[0] = v.w_px / 2 + v.f_px * (d[0] * v.right[0] + d[1] * v.right[1] + d[2] * v.right[2]) / z;
    pixel[1] = v.h_px / 2 - v.f_px * (d[0] * v.up[0] + d[1] * v.up[1] + d[2] * v.up[2]) / z;
    if (depth_m)
        *depth_m = z;
    return 1;
}

void tp_camera_pixel_ray(const tp_camera* cam, double x_px, double y_px, double dir[3])
{
    assert(cam && dir);
    tp__view v;
    tp__view_from_camera(cam, &v);
    double a = (x_px - v.w_px / 2) / v.f_px, b = -(y_px - v.h_px / 2) / v.f_px;
    for (int i = 0; i < 3; i++)
        dir[i] = v.fwd[i] + a * v.right[i] + b * v.up[i];
    normalize(dir);
}

void tp_camera_view_projection(const tp_camera* cam, double far_m, double out[16])
{
    assert(cam && out);
    tp__view v;
    tp__view_from_camera(cam, &v);
    assert(!(far_m <= v.near_m)); /* a caller bug; a NaN far (a NaN eye) gives a NaN matrix */
    double t = 1 / v.tan_y, a = v.w_px / v.h_px, n = v.near_m;
    double A = (far_m + n) / (n - far_m), B = 2 * far_m * n / (n - far_m);
    /* rows of the view matrix: right, up, -forward; projection diag(t/a, t, A) and -1 in w */
    memset(out, 0, 16 * sizeof *out);
    for (int c = 0; c < 3; c++) {
        out[c * 4 + 0] = t / a * v.right[c];
        out[c * 4 + 1] = t * v.up[c];
        out[c * 4 + 2] = -A * v.fwd[c];
        out[c * 4 + 3] = v.fwd[c];
    }
    out[14] = B;
}

static void to_camera(const tp__view* v, const double w[3], double c[3])
{
    double d[3] = {w[0] - v->pos[0], w[1] - v->pos[1], w[2] - v->pos[2]};
    c[0] = d[0] * v->right[0] + d[1] * v->right[1] + d[2] * v->right[2];
    c[1] = d[0] * v->up[0] + d[1] * v->up[1] + d[2] * v->up[2];
    c[2] = d[0] * v->fwd[0] + d[1] * v->fwd[1] + d[2] * v->fwd[2];
}

double tp__screen_error_px(const tp__view* v, const double truth[3], const double drawn[3])
{
    double cs[3], cd[3];
    to_camera(v, truth, cs);
    if (cs[2] < v->near_m || (v->far_m > 0 && cs[2] > v->far_m) ||
        fabs(cs[0]) > v->tan_x * cs[2] || fabs(cs[1]) > v->tan_y * cs[2])
        return NAN;
    if (drawn[2] == truth[2])
        return 0;
    to_camera(v, drawn, cd);
    if (cd[2] <= 0)
        return INFINITY;
    double du = v->f_px * (cd[0] / cd[2] - cs[0] / cs[2]);
    double dv = v->f_px * (cd[1] / cd[2] - cs[1] / cs[2]);
    return sqrt(du * du + dv * dv);
}
