/*
 * extent.h - the extents of a w x h render grid in its CRS and in latitude and longitude, for
 * `info` on a DEM and on a store.
 */
#ifndef TP_APP_EXTENT_H
#define TP_APP_EXTENT_H

#include "tp_io.h"

/* Geographic extent of the grid: south, west, north, east (degrees), from every edge
 * sample (an extent in UTM/UPS bends: corners and midpoints miss where it reaches furthest).
 * When the grid holds a pole, that latitude is +-90 and the longitudes are -180 .. 180. The
 * longitudes are the shortest interval holding every edge sample: west > east when it crosses
 * the antimeridian (*crosses set to 1). Returns 1, 0 when the grid has no CRS, -1 (with *why)
 * when an edge post is outside what the zone converts (a grid far wider than its zone). */
int tp_geo_extent(const tp_georef* g, int w, int h, double out[4], int* crosses, tp_error* why);

/* Projected extent of the grid's sample centres: min E, min N, max E, max N. */
void tp_proj_extent(const tp_georef* g, int w, int h, double out[4]);

#endif /* TP_APP_EXTENT_H */
