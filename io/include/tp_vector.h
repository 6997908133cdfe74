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

/* ---------------------------------------------------------------------------------------------
 * Contours (io/src/contours.cpp): GDAL's contour generator over a grid of heights, and contour
 * lines written as an OGR vector file.
 */

/* How tp_contours_generate_ex chooses the levels it draws and the lines it keeps. */
typedef struct tp_contours_options {
    /* The levels: base_m + k * interval_m for every integer k when interval_m > 0 (GDAL's
     * LEVEL_INTERVAL and LEVEL_BASE, as gdal_contour -i -off); with interval_m 0, the
     * level_count values of levels (GDAL's FIXED_LEVELS, as gdal_contour -fl) in any order,
     * each drawn once: they are sorted and a repeated value dropped here, because GDAL 3.6
     * needs them ascending (given out of order, it silently draws only some of them) and draws
     * a level given twice twice. */
    double interval_m;
    double base_m;
    const double* levels; /* borrowed for the call */
    size_t level_count;
    /* Only the levels in [min_m, max_m] are drawn (-HUGE_VAL and HUGE_VAL: every one). GDAL is
     * then given those levels alone (FIXED_LEVELS; with an interval, those of its levels inside
     * both this range and the heights'), which draws at each level the lines it draws there
     * among all the levels. */
    double min_m, max_m;
    /* Index contours (tp_feature.index = 1): with an interval, the levels where (value -
     * base_m) is a multiple of index_every * interval_m; with levels, every index_every-th of
     * them in ascending order counted from the lowest (the 1st, the (K+1)th, ...), among all
     * of them, min_m and max_m notwithstanding. 0: none. */
    int index_every;
    /* Lines with fewer vertices than this are dropped, counted as GDAL writes them (a closed
     * line's first vertex again at its end), as GRASS's r.contour cut=N; 0: none is. */
    size_t min_vertices;
} tp_contours_options;

/* An interval of 10 m from 0, every level, every fifth an index contour, every line. */
tp_contours_options tp_contours_options_default(void);

/* Contour lines of a grid of heights, computed by GDAL's contour generator
 * (GDALContourGenerateEx, the library form of gdal_contour), not by us.
 *
 * heights: width * height floats (= height_count), row 0 first, metres; NaN is a void. They
 * are given to GDAL as a Float32 MEM dataset with geotransform (GDAL's: corner of the top-left
 * sample, sample (x, y) centred at gt[0] + (x + 0.5) gt[1], gt[3] + (y + 0.5) gt[5]), voids as
 * its nodata: no contour crosses a void (GDAL ends a line at the void's edge; see docs/field.md
 * for where exactly). The levels, the index contours and the lines kept are options' (above).
 * Vertices are in the geotransform's CRS (the render CRS when it is the render grid's).
 *
 * *out gets one feature per line kept: value = its elevation (m), index = 1 on an index
 * contour, else 0, name NULL. A line that closes on itself (GDAL repeats its first vertex at
 * its end) is a TP_FEATURE_RING, the repeated vertex dropped; any other is a TP_FEATURE_LINE
 * (it ends on the grid's border or on a void). Lines come in GDAL's order. A grid with no
 * level inside its range (flat ground, all void, 1x1), or no level left in [min_m, max_m],
 * gives an empty set (count 0): TP_OK. dropped (NULL: not wanted) gets the number of lines
 * dropped for options->min_vertices.
 *
 * TP_ERR_INVALID_ARG for NULL pointers, width or height < 1, height_count != width * height, a
 * geotransform that is not finite or has gt[1] or gt[5] == 0, options out of their ranges:
 * interval_m not finite or < 0, interval_m 0 without levels ("an interval > 0"), an interval
 * and levels both, a level or base_m not finite, min_m or max_m NaN or min_m > max_m,
 * index_every < 0; more than TP_CONTOURS_MAX_LEVELS levels (given, or an interval's over the
 * heights' range within [min_m, max_m]), or more than TP_CONTOURS_MAX_VERTICES vertices
 * (counted before any line is made: one per level crossing each grid edge between two valid
 * samples; the message suggests an interval that fits); TP_ERR_BAD_DATA for an infinite
 * height; TP_ERR_OUT_OF_MEMORY; TP_ERR_BACKEND when GDAL fails (its message). *out (and
 * *dropped) are written only on TP_OK; free *out with tp_features_destroy. */
#define TP_CONTOURS_MAX_LEVELS 100000
#define TP_CONTOURS_MAX_VERTICES 20000000 /* about 0.5 GB of lines, a minute of GDAL's work */
tp_status tp_contours_generate_ex(const float* heights, size_t height_count, int width, int height,
                                  const double geotransform[6], const tp_contours_options* options,
                                  tp_features** out, size_t* dropped, tp_error* err);

/* tp_contours_generate_ex with the levels base_m + k * interval_m, index contours every
 * index_every-th level (0: none), every level and every line (as gdal_contour -i INTERVAL -off
 * BASE). */
tp_status tp_contours_generate(const float* heights, size_t height_count, int width, int height,
                               const double geotransform[6], double interval_m, double base_m,
                               int index_every, tp_features** out, tp_error* err);

/* Writes contour lines as a vector file in the OGR format that path's extension names (case
 * ignored): .gpkg GeoPackage, .shp ESRI Shapefile, .geojson/.json GeoJSON, .kml KML, .gml GML,
 * .csv CSV (geometry as a WKT column), .fgb FlatGeobuf, .sqlite SQLite, .gpx, .dxf, or any other
 * extension an OGR driver that creates vector files declares. One LINESTRING layer named
 * "contours" (a Shapefile's layer is named after its file) with the fields elevation_m (Real;
 * "elevation_" in a Shapefile, whose field names hold 10 characters) and index (Integer: 1 on an
 * index contour). A TP_FEATURE_RING is written as a closed LINESTRING (its first vertex repeated
 * at the end); points are not written. crs_wkt (WKT or anything OGRSpatialReference's
 * SetFromUserInput reads; NULL or "" for none) is the layer's CRS; formats bound to WGS 84 (KML,
 * GPX) reproject to it as their OGR driver does (GDAL's KML driver also makes the two fields
 * each placemark's name and description). An empty set gives a valid file with an empty layer.
 *
 * The format is the one tp_output_format_for (tp_io.h, TP_OUTPUT_VECTOR) decides.
 *
 * Atomic: the file (and every sidecar of it a driver writes: a Shapefile's .shx, .dbf, .prj,
 * .cpg) is made in a new temporary folder beside path, then put in place all or none when
 * complete (tp_file_set_* in tp_io.h); sidecars of an older Shapefile of the same name that the
 * new one lacks (.prj, .cpg, .qix, .sbn, .sbx) are removed with it. On any failure nothing is
 * left behind and older files stay as they were (SIGINT/SIGTERM after tp_interrupt_install as
 * tp_file_write).
 *
 * TP_ERR_INVALID_ARG for NULL f or path, "" or an extension no OGR driver writes (the message
 * names the file and the extensions above); TP_ERR_BAD_DATA for a crs_wkt GDAL cannot read;
 * TP_ERR_IO when path's folder cannot be written; TP_ERR_BACKEND when the driver fails (its
 * message). */
tp_status tp_contours_write(const char* path, const tp_features* f, const char* crs_wkt,
                            tp_error* err);

/* Checks, before long work that ends in tp_contours_write(path, ...), that an OGR driver writes
 * path's extension and that path can be written (tp_output_check). Writes nothing; the errors
 * are tp_contours_write's. */
tp_status tp_contours_check_output(const char* path, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_VECTOR_H */
