/*
 * measure.h - the measuring tool: two points on the ground, the geodesic between them.
 */
#ifndef TP_APP_MEASURE_H
#define TP_APP_MEASURE_H

#include "tp_io.h"

typedef struct tp_measurement {
    double lat_deg[2], lon_deg[2]; /* WGS84 */
    double height_m[2];            /* drawn ground heights, as in the DEM */
    double distance_m;             /* geodesic on the WGS84 ellipsoid (GeographicLib) */
    double true_bearing_deg;       /* azimuth at point 1, clockwise from true north, 0..360 */
    double grid_bearing_deg;       /* the same from the render grid's north (easting, northing) */
    double height_diff_m;          /* point 2 minus point 1 */
    double grid_distance_m;        /* straight line on the render grid, for comparison */
} tp_measurement;

/* Measures between (e, n) points of the render CRS with their ground heights. Without a CRS
 * (local metres) the distance and bearings are planar and lat/lon are NaN. Returns 0 when a
 * point has no geographic position. */
int tp_measure(const tp_georef* g, const double e[2], const double n[2], const double h[2],
               tp_measurement* out);

/* One line: "distance 1234.567 m (geodesic), bearing 45.12 deg true / 44.30 deg grid, height
 * difference +123.4 m". */
void tp_measurement_text(const tp_measurement* m, char* out, size_t cap);

#endif
