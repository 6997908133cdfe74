/*
 * layers.h - the planner's layers in the viewer, draped on the ground (drape.h) and drawn by the
 * overlay (overlay.h's tp_overlay_drape): vector files given with --overlay (GPX, KML, GeoJSON,
 * Shapefile, GeoPackage: read through OGR by tp_vector_read, reprojected to the render CRS), each
 * in its own colour, and contour lines (GDAL's contour generator, tp_contours_generate) over the
 * posts within TP_VIEW_CONTOURS_RADIUS_M of a ground point (F2 at the point looked at, or
 * --contours M at the first frame's), index contours every fifth, thicker and labelled.
 * app/view/layers.c.
 */
#ifndef TP_APP_VIEW_LAYERS_H
#define TP_APP_VIEW_LAYERS_H

#include "drape.h"
#include "ground.h"
#include "overlay.h"

#include <stddef.h>

#define TP_VIEW_MAX_OVERLAYS 8
#define TP_VIEW_CONTOURS_RADIUS_M 10000.0
/* At most this many posts of the window are read for contours (a window of coarse posts
 * reaches the radius; of fine posts, a smaller square). */
#define TP_VIEW_CONTOURS_MAX_POSTS (2048 * 2048)

typedef struct tp_view_layers {
    tp_drape overlays[TP_VIEW_MAX_OVERLAYS];
    const char* overlay_paths[TP_VIEW_MAX_OVERLAYS];
    size_t overlay_count;
    tp_drape contours;            /* part_count 0: none */
    double contour_interval_m;
    tp_overlay_drape drawn[TP_VIEW_MAX_OVERLAYS + 1];
} tp_view_layers;

/* Reads path (any vector file OGR opens), reprojects it into the ground's render CRS and drapes
 * it. Returns 1 (and prints what was read), else 0 with err naming the file and why (OGR cannot
 * open it, no features, a CRS that does not transform, more than TP_VIEW_MAX_OVERLAYS). */
int tp_view_layers_add_overlay(tp_view_layers* l, tp_ground* g, const char* path, tp_error* err);

/* Contours every interval_m metres (<= 0: a round interval for about 25 lines over the
 * window's relief: 1, 2 or 5 times a power of ten, at least 1 m) around render (e, n). line
 * gets the HUD's line (also printed). Returns 1 (the contours replaced), else 0 with line
 * saying why (the old ones kept). */
int tp_view_layers_contours_at(tp_view_layers* l, tp_ground* g, double e_m, double n_m,
                               double interval_m, char* line, size_t cap);

/* The HUD's legend: "overlays: coma_pedrosa.gpx magenta, andorra.kml cyan   contours every
 * 50 m (index 250 m, F2: off)"; "" without layers. */
void tp_view_layers_legend(const tp_view_layers* l, char* out, size_t cap);

/* What the overlay draws: contours first, then the overlays in their order. */
size_t tp_view_layers_drawn(tp_view_layers* l, const tp_overlay_drape** out);

void tp_view_layers_free(tp_view_layers* l); /* l stays usable (zeroed) */

#endif /* TP_APP_VIEW_LAYERS_H */
