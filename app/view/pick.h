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

/* Ground metres a pixel at pixel (x, y): the ground point under it and one 100 m beside it
 * along the screen's horizontal (the camera's right vector on the map), projected; ground
 * writes the point (E, N, true height; may be NULL). NaN where no ground is under the pixel or
 * the second point is behind the eye. What the scale bar shows at the centre. */
double tp_view_metres_per_pixel(const tp_view_scene* v, const tp_camera* cam, double x_px,
                                double y_px, double ground[3]);

/* The grid spacing to draw for a grid of finest spacing base_m (> 0; 0: none, returned as is)
 * in this view: tp_map_grid_spacing at the scale of the ground at the centre, or where the
 * centre is sky, of the ground near the bottom of the picture. */
double tp_view_grid_spacing(const tp_view_scene* v, const tp_camera* cam, double base_m);

/* Share of the eye's distance to a point by which the surface may come before it and the point
 * still count as seen (the drawn surface near a grazing ray, rounding). */
#define TP_VIEW_VISIBLE_TOLERANCE 0.01

/* Whether the drawn ground point p (E, N and its TRUE height, as tp_view_pick writes it) is seen
 * from cam: the ray from the eye to p (drawn space: heights times the exaggeration) meets the
 * drawn surface no sooner than 1% of the distance plus 1 m before p (TP_VIEW_VISIBLE_TOLERANCE).
 * A ridge between the eye and p hides it. Points behind the eye are not checked here (project
 * them first). 0 for a NaN point. */
int tp_view_ground_visible(const tp_view_scene* v, const tp_camera* cam, const double p[3]);

/* Measures between two ground points given by E, N (render CRS) at their drawn heights; writes
 * one line of text (the result, or why not) and returns 1 on success, 0 off the data. */
int tp_view_measure_points(tp_view_scene* v, const double e[2], const double n[2], char* text,
                           size_t cap);

#endif
