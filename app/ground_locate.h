/*
 * ground_locate.h - a typed position (position.h) placed on the ground (ground.h) for the
 * field commands that take positions (`los`, `viewshed`), with the messages `point` gives:
 * no CRS, outside the DEM, in a void. And back: a grid position as latitude/longitude.
 * app/ground_locate.c.
 */
#ifndef TP_APP_GROUND_LOCATE_H
#define TP_APP_GROUND_LOCATE_H

#include "ground.h"
#include "position.h"

#include <stddef.h>

/* The grid position (x, y) of pos on g's render grid and the ground's height there. Returns 1;
 * or 0 with msg (cap bytes) naming the position as typed (input) and why: the DEM has no CRS,
 * the position is outside the DEM, in a void, or a leaf cannot be read. */
int tp_ground_locate(tp_ground* g, const tp_position* pos, const char* input, double* x,
                     double* y, double* height_m, char* msg, size_t cap);

/* Latitude/longitude (WGS84, degrees) of grid (x, y); 0 without a CRS (then NaN). */
int tp_ground_grid_latlon(const tp_ground* g, double x, double y, double* lat_deg,
                          double* lon_deg);

#endif /* TP_APP_GROUND_LOCATE_H */
