/*
 * tp_io/georef.h - grid (x, y) <-> render CRS (E, N) <-> WGS84 (lat, lon).
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_GEOREF_H
#define TP_IO_GEOREF_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Georeference (io/src/georef.cpp): grid (x, y) <-> render CRS (E, N) <-> WGS84 (lat, lon).
 *
 * Grid coordinates are (column, row) with sample centres at integers, as GDAL's geotransform
 * defines them (pixel-is-point rasters already have a corner-based geotransform from GDAL, so
 * nothing is shifted twice): E = gt[0] + (x + 0.5) gt[1], N = gt[3] + (y + 0.5) gt[5].
 * When the render CRS is a WGS84 UTM zone or UPS, (E, N) <-> (lat, lon) is GeographicLib's
 * UTMUPS (exact to nanometres), in the scene's zone even outside its standard area. Any other
 * CRS goes through PROJ to WGS84; tp_georef_datum_accuracy_m says how accurate that step is.
 * Heights are never converted: they stay as in the DEM (orthometric for SRTM: EGM96).
 */
typedef struct tp_georef tp_georef;

/* crs_wkt "" or NULL: local metres (no geographic position). TP_ERR_BAD_DATA for unreadable
 * WKT, TP_ERR_BACKEND when PROJ has no operation to WGS84. The conversion functions below
 * write their outputs only on success. */
tp_status tp_georef_create(const char* crs_wkt, const double geotransform[6], tp_georef** out,
                           tp_error* err);
void tp_georef_destroy(tp_georef* g); /* accepts NULL */

/* 1 if positions can be turned into latitude and longitude. */
int tp_georef_has_geo(const tp_georef* g);

void tp_georef_grid_to_proj(const tp_georef* g, double x, double y, double* e_m, double* n_m);
void tp_georef_proj_to_grid(const tp_georef* g, double e_m, double n_m, double* x, double* y);

/* Render CRS (E, N) <-> WGS84 latitude, longitude (degrees; longitude in [-180, 180]).
 * TP_ERR_INVALID_ARG when there is no CRS, for coordinates that are not finite (or a latitude
 * beyond +-90), and when the point cannot be converted (outside the range of GeographicLib's
 * UTMUPS, for instance: its message is kept). */
tp_status tp_georef_proj_to_geo(const tp_georef* g, double e_m, double n_m, double* lat_deg,
                                double* lon_deg, tp_error* err);
tp_status tp_georef_geo_to_proj(const tp_georef* g, double lat_deg, double lon_deg, double* e_m,
                                double* n_m, tp_error* err);

/* Accuracy (metres) of the render CRS -> WGS84 step: 0 when exact (WGS84 itself), PROJ's stated
 * accuracy of the operation it uses, or -1 when PROJ gives none (a ballpark datum shift used
 * because the datum grids are missing: expect errors of a metre or more). */
double tp_georef_datum_accuracy_m(const tp_georef* g);
/* One line describing that step, e.g. "exact (WGS 84)" or the PROJ operation's name; owned by g,
 * valid while g lives. */
const char* tp_georef_datum_note(const tp_georef* g);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_GEOREF_H */
