/*
 * ground_locate.h - a typed position (position.h) placed on the ground (ground.h) for the
 * field commands that take positions (`los`, `viewshed`), with the messages `point` gives:
 * no CRS, outside the DEM, in a void. And back: a grid position as latitude/longitude.
 * app/scene/ground_locate.c.
 */
#ifndef TP_APP_GROUND_LOCATE_H
#define TP_APP_GROUND_LOCATE_H

#include "ground.h"
#include "position.h"

#include <stddef.h>

/* The grid position (x, y) of pos on g's render grid and the ground's height there. Returns 1;
 * or 0 with err naming the position as typed (input) and why: the DEM has no CRS, the position
 * is outside the DEM, in a void (tp_ground_void_hint after it), or a leaf cannot be read. */
int tp_ground_locate(tp_ground* g, const tp_position* pos, const char* input, double* x, double* y,
                     double* height_m, tp_error* err);

/* Where pos lies on g: 1 on the DEM (a height there or a void), with its grid (x, y); 0 off it,
 * without a CRS, or when a leaf cannot be read. No message. */
int tp_ground_on_dem(tp_ground* g, const tp_position* pos, double* x, double* y);

/* Whether the void at grid (x, y) reaches the DEM's edge through void posts (4-connected), as
 * a void that no interpolation fills does (only --fill-from fills it): 1 it does, 0 it does not
 * or (x, y) is no void, -1 unknown (more than max_posts void posts looked at, or a leaf cannot
 * be read). */
int tp_ground_void_reaches_edge(tp_ground* g, double x, double y, size_t max_posts);

/* Void posts tp_ground_void_hint looks at, at most (a few seconds' reading). */
#define TP_GROUND_VOID_WALK_POSTS ((size_t)1 << 20)

/* What a message about a position in the void at grid (x, y) ends with: "; the void reaches
 * the DEM's edge, ...: --fill-from OTHER fills it ..." when it does (tp_ground_void_reaches_edge),
 * else "". tp_ground_locate's message has it. */
void tp_ground_void_hint(tp_ground* g, double x, double y, char* out, size_t cap);

/* Latitude/longitude (WGS84, degrees) of grid (x, y); 0 without a CRS (then NaN). */
int tp_ground_grid_latlon(const tp_ground* g, double x, double y, double* lat_deg,
                          double* lon_deg);

#endif /* TP_APP_GROUND_LOCATE_H */
