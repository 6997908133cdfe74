/*
 * pick.h - what lies under a pixel: the ground point where the pixel's ray meets the surface
 * that is drawn (levels, crack removal and vertical exaggeration as on screen), and the
 * measuring tool's two points.
 */
#ifndef TP_APP_PICK_H
#define TP_APP_PICK_H

#include "view_scene.h"

/* The ground point under pixel (x, y) of cam: out = E, N and the true (unexaggerated) height
 * of the drawn surface there. Returns 0 when the ray meets no drawn ground. */
int tp_view_pick(const tp_view_scene* v, const tp_camera* cam, double x_px, double y_px,
                 double out[3]);

/* The ground point at the centre of the view. */
int tp_view_pick_centre(const tp_view_scene* v, const tp_camera* cam, double out[3]);

/* Measures between two ground points given by E, N (render CRS) at their drawn heights; writes
 * one line of text (the result, or why not) and returns 1 on success, 0 off the data. */
int tp_view_measure_points(tp_view_scene* v, const double e[2], const double n[2], char* text,
                           size_t cap);

#endif
