/*
 * viewshed_pick.h - the viewer's viewshed overlay (B: from the ground under the cursor; B
 * again: off): the posts of the render grid within a radius read through the ground module,
 * tp_viewshed_compute (gdal_viewshed's defaults: eye 2 m, target 0 m, coefficient 0.85714), and
 * the posts the observer cannot see kept for the overlay to tint (overlay.h's
 * tp_overlay_viewshed), thinned to at most TP_VIEW_VIEWSHED_MAX_DOTS. app/view/viewshed_pick.c.
 */
#ifndef TP_APP_VIEW_VIEWSHED_PICK_H
#define TP_APP_VIEW_VIEWSHED_PICK_H

#include "ground.h"
#include "overlay.h"

#include <stddef.h>

#define TP_VIEW_VIEWSHED_RADIUS_M 10000.0
#define TP_VIEW_VIEWSHED_MAX_DOTS 20000

typedef struct tp_view_viewshed {
    double* enh;                 /* hidden posts kept: E, N, ground height */
    tp_overlay_viewshed overlay; /* count 0: nothing drawn */
} tp_view_viewshed;

/* The viewshed of an observer on the ground at render (e, n) within radius_m. line (cap bytes)
 * gets the HUD's line (also printed). Returns 1 on success (the overlay replaced), else 0 with
 * line saying why (the old overlay kept). */
int tp_view_viewshed_at(tp_view_viewshed* vs, tp_ground* g, double e_m, double n_m,
                        double radius_m, char* line, size_t cap);

void tp_view_viewshed_free(tp_view_viewshed* vs); /* vs stays usable (zeroed) */

#endif /* TP_APP_VIEW_VIEWSHED_PICK_H */
