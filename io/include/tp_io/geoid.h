/*
 * tp_io/geoid.h - the geoid's undulation (io/src/geoid.cpp): EGM96 heights <-> WGS84 ellipsoidal
 * heights, for tiles that state their heights above the ellipsoid (Cesium's quantized mesh).
 * Part of tp_io.h, which includes it; the error conventions stated there hold here. C11.
 *
 * The model: EGM96 as PROJ's grid us_nga_egm96_15 (15 arc-minutes, bilinear between its posts,
 * PROJ's vgridshift), found by PROJ where it keeps grids (Debian's proj-data ships it as
 * /usr/share/proj/egm96_15.gtx), through the operation PROJ picks from EPSG:4979 to
 * EPSG:4326+5773 (WGS 84 + EGM96 height). GeographicLib's own Geoid class would be the first
 * choice, but Debian ships none of its model files (geographiclib-tools only has the script that
 * downloads them): see docs/quantized_mesh.md.
 */
#ifndef TP_IO_GEOID_H
#define TP_IO_GEOID_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct tp_geoid tp_geoid;

/* Opens the model. TP_ERR_BACKEND (naming the grid and where PROJ looks) when PROJ has no
 * operation that uses a geoid grid (the grid missing: PROJ would silently shift by nothing). */
tp_status tp_geoid_open(tp_geoid** out, tp_error* err);
void tp_geoid_close(tp_geoid* g); /* accepts NULL */

/* The model's name, e.g. "EGM96 (PROJ grid us_nga_egm96_15, 15')"; owned by g. */
const char* tp_geoid_name(const tp_geoid* g);

/* The undulation N (m) at n positions (lat_deg[i], lon_deg[i]): ellipsoidal height = EGM96
 * height + N. TP_ERR_INVALID_ARG for a position PROJ cannot convert. Not thread-safe (one
 * tp_geoid per thread). */
tp_status tp_geoid_undulation(tp_geoid* g, size_t n, const double* lat_deg, const double* lon_deg,
                              double* n_m, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif
