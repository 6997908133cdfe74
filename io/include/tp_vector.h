/*
 * tp_vector.h - vector features in terrapatch: contour lines (GDAL's contour generator) and the
 * planner's overlays and routes (GPX, KML, GeoJSON, Shapefile, GeoPackage read through OGR),
 * held in one plain C form that the viewer drapes on the terrain and the commands measure.
 *
 * Coordinates are those of the render CRS (the render grid's / store's projected CRS, metres):
 * whatever reads or makes features reprojects them there. Heights are not carried: the ground
 * gives them (features are draped).
 */
#ifndef TP_VECTOR_H
#define TP_VECTOR_H

#include "tp_core.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef enum tp_feature_kind {
    TP_FEATURE_POINT = 0, /* count 1: a waypoint, a placemark */
    TP_FEATURE_LINE = 1,  /* count >= 2: a track, a route, a contour line */
    TP_FEATURE_RING = 2   /* count >= 3, closed (last vertex not repeated): a polygon's outline */
} tp_feature_kind;

typedef struct tp_feature {
    tp_feature_kind kind;
    size_t first;      /* its vertices are xy[2 * first .. 2 * (first + count) - 1] */
    size_t count;
    double value;      /* a contour's elevation (m); NaN when the feature has none */
    int index;         /* a contour: 1 on an index contour (every fifth), else 0 */
    const char* name;  /* NULL or a name (a waypoint's, a placemark's); owned by the set */
} tp_feature;

typedef struct tp_features {
    tp_feature* items;
    size_t count;
    double* xy;          /* E, N pairs (render CRS, metres) */
    size_t vertex_count;
    char* strings;       /* the names' storage */
} tp_features;

/* Frees a set made by any function here (the set and its three arrays, each from malloc);
 * accepts NULL. */
void tp_features_destroy(tp_features* f);

#ifdef __cplusplus
}
#endif
#endif /* TP_VECTOR_H */
