/* camera.c - camera frame and view-frustum culling of patch AABBs (Vanek & Jezek section 3;
 * plane tests with the n- and p-vertex of the box). All in doubles, in world coordinates. */
#include "internal.h"

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
