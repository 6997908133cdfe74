/* tp_camera.h - the camera: poses, frames, projection, pick rays, frustum culling (camera.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_CAMERA_H
#define TP_CAMERA_H

#include "tp_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Camera and frustum culling
 */
typedef struct tp_camera {
    double position[3];         /* world: E, N, height */
    double forward[3], up[3];   /* need not be unit; up must not be parallel to forward.
                                   All zero forward means looking north and level. */
    double fov_y_rad;           /* vertical field of view; 0 means 60 degrees */
    int viewport_w_px, viewport_h_px; /* 0 means 1280 x 720 */
    double near_m, far_m;       /* 0 near means 1 m; 0 far means no far plane */
} tp_camera;

/* Writes the camera of a pose: eye position (world), yaw in degrees clockwise from grid north, pitch
 * in degrees (-90 looks straight down, +90 straight up), vertical field of view in degrees (0
 * means 60), viewport in pixels (0 means 1280 x 720); near plane 1 m, no far plane. The up
 * vector is defined for every pitch (it is right x forward with right = (cos yaw, -sin yaw, 0)).
 * Cannot fail. */
void tp_camera_from_pose(const double position[3], double yaw_deg, double pitch_deg,
                         double fov_y_deg, int width_px, int height_px, tp_camera* out);

/* Writes the pose of a camera: yaw in [0, 360) clockwise from grid north, pitch in [-90, 90].
 * Cannot fail. */
void tp_camera_get_pose(const tp_camera* cam, double* yaw_deg, double* pitch_deg);

/* The camera's orthonormal frame and intrinsics, defaults applied. */
typedef struct tp_camera_frame {
    double position[3];
    double forward[3], right[3], up[3]; /* unit vectors, world frame */
    double focal_px;                    /* pixels per unit of tangent: (h/2) / tan(fov_y/2) */
    int width_px, height_px;
    double near_m, far_m;               /* far 0: none */
} tp_camera_frame;

/* Writes the frame of cam into *out. Cannot fail. */
void tp_camera_get_frame(const tp_camera* cam, tp_camera_frame* out);

/* Projects a world point to pixel coordinates (x to the right, y down, (0, 0) the top-left
 * corner of the image, (w/2, h/2) its centre). Answers whether the point is in front of the
 * near plane: 1, writing pixel[2] (and *depth_m, the distance along the view axis, if depth_m
 * is not NULL); else 0 (also for a NaN point), writing nothing. That 0 is an answer, not a
 * failure. The pixel may lie outside the viewport. */
int tp_camera_project(const tp_camera* cam, const double world[3], double pixel[2],
                      double* depth_m);

/* Writes the unit direction (world frame) of the ray from the eye through pixel (x, y), the
 * inverse of tp_camera_project. Cannot fail. */
void tp_camera_pixel_ray(const tp_camera* cam, double x_px, double y_px, double dir[3]);

/* Writes the column-major 4x4 projection * view matrix of the camera with its eye at the origin
 * (callers subtract the eye position from world positions first, so that floats keep their
 * precision), OpenGL clip conventions, depth range [near, far_m]; far_m must be > the camera's
 * near plane (asserted). Cannot fail. */
void tp_camera_view_projection(const tp_camera* cam, double far_m, double out[16]);

typedef struct tp_frustum {
    double planes[6][4]; /* a*E + b*N + c*h + d >= 0 inside; unit normals */
    int plane_count;     /* 5 without a far plane, else 6 */
} tp_frustum;

/* Writes the camera's frustum planes into *out. Cannot fail. */
void tp_frustum_from_camera(const tp_camera* cam, tp_frustum* out);

typedef enum tp_cull { TP_CULL_OUTSIDE = 0, TP_CULL_INTERSECTS, TP_CULL_INSIDE } tp_cull;

/* Query: returns where the AABB lies against the frustum planes (n/p-vertex test). OUTSIDE only
 * if the box is entirely on the outer side of some plane (conservative: a box outside but not
 * behind one plane is reported as INTERSECTS). Cannot fail. */
tp_cull tp_frustum_test_aabb(const tp_frustum* f, const double aabb_min[3], const double aabb_max[3]);

#ifdef __cplusplus
}
#endif
#endif /* TP_CAMERA_H */
