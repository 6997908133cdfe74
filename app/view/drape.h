/*
 * drape.h - vector features (tp_features: contour lines, overlays, routes) laid on the ground
 * for the overlay to draw (overlay.h's tp_overlay_drape): each line and ring resampled at the
 * grid's post spacing and every vertex given the full-resolution ground height (tp_ground),
 * broken where the ground is void or off the DEM; a contour keeps its own elevation (it lies
 * on the ground at that height by construction) and its vertices as GDAL made them (one or
 * two per cell already). Points keep their names. Done once when features are loaded; the
 * overlay then only projects. app/view/drape.c.
 */
#ifndef TP_APP_VIEW_DRAPE_H
#define TP_APP_VIEW_DRAPE_H

#include "ground.h"
#include "tp_vector.h"

#include <stddef.h>

/* A run of vertices drawn as one polyline. */
typedef struct tp_drape_part {
    size_t first, count; /* enh[3 * first ..] */
    double value;        /* a contour's elevation (NaN: none) */
    int index;           /* an index contour (drawn thicker, labelled) */
} tp_drape_part;

typedef struct tp_drape_point {
    double enh[3];
    const char* name; /* NULL or into names */
} tp_drape_point;

typedef struct tp_drape {
    double* enh;          /* E, N (render CRS), height (true metres) */
    size_t vertex_count;
    tp_drape_part* parts;
    size_t part_count;
    tp_drape_point* points;
    size_t point_count;
    char* names;
    size_t dropped;       /* vertices on no ground (voids, off the DEM): not drawn */
} tp_drape;

/* Lays f on the ground g (contours: at their values, contours = 1). Returns 1 with *d filled
 * (free with tp_drape_free), else 0 with err saying why (out of memory, a leaf that cannot be
 * read) and *d untouched. */
int tp_drape_build(tp_drape* d, const tp_features* f, tp_ground* g, int contours, tp_error* err);

void tp_drape_free(tp_drape* d); /* d stays usable (zeroed) */

#endif /* TP_APP_VIEW_DRAPE_H */
