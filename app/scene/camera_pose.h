/*
 * camera_pose.h - cameras as the command line gives them: position, yaw (clockwise from the
 * render grid's north) and pitch (-90 looks straight down), and the default "whole DEM in view".
 * Shared by `view` and `export` so both build exactly the same camera.
 */
#ifndef TP_APP_CAMERA_POSE_H
#define TP_APP_CAMERA_POSE_H

#include "scene.h"

void tp_camera_pose(double e, double n, double h, double yaw_deg, double pitch_deg, double fov_deg,
                    int width_px, int height_px, tp_camera* cam);

/* The whole DEM in view, from the south, 50 degrees down; vertical_scale (view's
 * --exaggeration; 1 elsewhere) is the drawn relief's, which the camera backs off from. */
void tp_camera_default(const tp_scene* sc, double fov_deg, int width_px, int height_px,
                       double vertical_scale,
                       tp_camera* cam);

/* The same from a grid's extent (the fitted grid's geotransform, its unpadded size, its
 * heights): a store has no tp_scene. The camera looks north, 50 degrees down, at the middle of
 * the extent, from far enough that its eight corners (at the lowest and highest heights, times
 * vertical_scale) are on screen with a margin of 2% of the viewport's smaller side. */
void tp_camera_default_extent(const double gt[6], int src_width, int src_height,
                              double min_height_m, double max_height_m, double fov_deg,
                              int width_px, int height_px, double vertical_scale, tp_camera* cam);

/* --camera E,N,H,YAW,PITCH (geo = 0) or --camera-geo LAT,LON,H,YAW,PITCH (geo = 1) to a camera;
 * prints a one-line message naming cmd and returns 0 when the position has no render-grid
 * coordinates, or when tp_camera_refuse_degrees refuses it (tp_camera_from_option only: the
 * georef alone does not know the DEM's extent). */
int tp_camera_from_option(const tp_scene* sc, int geo, const double v[5], double fov_deg,
                          int width_px, int height_px, tp_camera* cam, const char* cmd);

/* 1 after one line when --camera (geo = 0) on a georeferenced grid got what looks like latitude
 * and longitude: both values within +-180, and the point as metres far off the DEM (outside its
 * extent, from gt and width x height posts, grown by its own size each way). The message gives
 * the --camera-geo to use, latitude first. 0 otherwise (also for --camera-geo). */
int tp_camera_refuse_degrees(const char* cmd, const tp_georef* g, int geo, const double v[5],
                             const double gt[6], int width, int height);

int tp_camera_from_option_georef(const tp_georef* g, int geo, const double v[5], double fov_deg,
                                 int width_px, int height_px, tp_camera* cam, const char* cmd);

/* The camera as option strings, e.g. "--camera-geo 45.1,-121.7,3000.00,20.00,-30.00". */
void tp_camera_text(const tp_scene* sc, const tp_camera* cam, char* out, size_t cap);
void tp_camera_text_georef(const tp_georef* g, const tp_camera* cam, char* out, size_t cap);

#endif
