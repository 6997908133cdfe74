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

/* ---------------------------------------------------------------------------------------------
 * Reading vector files (io/src/vector_read.cpp, through GDAL's OGR)
 *
 * tp_vector_read opens path with OGR (any vector format it reads: GPX, KML, GeoJSON, Shapefile,
 * GeoPackage, ...), reads every layer in file order and every feature in layer order, reprojects
 * the coordinates into target_crs_wkt (OGRCoordinateTransformation, both CRSs in the
 * traditional GIS order: E/longitude first) and flattens the geometries:
 *   - a point (and each point of a multipoint) is a TP_FEATURE_POINT, with the feature's "name"
 *     field (any case: KML's "Name") when the layer has one and it is set and not empty;
 *   - a line string (and each part of a multi line string: each segment of a GPX track) is a
 *     TP_FEATURE_LINE, unnamed parts too (names: as points). Parts of fewer than 2 vertices are
 *     dropped;
 *   - a polygon gives one TP_FEATURE_RING per ring, the outer first, then its holes (the
 *     repeated closing vertex is dropped; rings of fewer than 3 vertices are dropped);
 *   - curves are approximated by OGR's getLinearGeometry; collections are walked; Z and M are
 *     dropped (features are draped).
 * GPX: the "waypoints", "routes" and "tracks" layers are read; "route_points" and
 * "track_points" (the same vertices again, one feature each) are skipped.
 * A layer without a CRS is taken as WGS84 only for GPX, KML and GeoJSON files (WGS84 by their
 * specifications); any other is an error.
 * value is NaN and index 0 on every feature.
 *
 * Errors (the message names path): TP_ERR_IO when OGR cannot open path as a vector file (a
 * missing file, a raster, garbage: OGR's reason kept); TP_ERR_BAD_DATA for a file without any
 * point, line or polygon (an empty GPX), a layer without a CRS in a format that has none by
 * default, a coordinate that does not transform into the target CRS (or is not finite);
 * TP_ERR_INVALID_ARG for an empty or unreadable target_crs_wkt (a DEM without a CRS: features
 * cannot be placed on it); TP_ERR_BACKEND when OGR has no transformation between the two CRSs;
 * TP_ERR_OUT_OF_MEMORY. *out is written only on success (free it with tp_features_destroy). */
tp_status tp_vector_read(const char* path, const char* target_crs_wkt, tp_features** out,
                         tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_VECTOR_H */
