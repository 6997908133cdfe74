/*
 * tp_io/viewshed.h - GDAL's viewshed, for comparing with the core's, and the viewshed written as a
 * raster.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_VIEWSHED_H
#define TP_IO_VIEWSHED_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Viewsheds through GDAL (io/src/viewshed_gdal.cpp)
 *
 * The core computes viewsheds itself (tp_viewshed_compute); these are for comparing with GDAL
 * and for saving the result.
 */

/* GDAL's own viewshed (GDALViewshedGenerate, the library form of gdal_viewshed, mode GVM_Edge
 * as gdal_viewshed's default, values 255 / 0 / 0 outside the radius) of the same in-memory grid
 * and observer, with tp_viewshed_compute's arguments, into out (out_count >= width * height; the
 * samples outside GDAL's window are 0). The grid goes to GDAL as a Float32 MEM dataset (NaN =
 * nodata) whose CRS is a sphere of options->earth_radius_m (GDAL takes the curvature's earth
 * from the CRS's semi-major axis), and the observer as its sample's centre. Fails as
 * tp_viewshed_compute does for the observer (outside the grid: TP_ERR_INVALID_ARG; on nodata:
 * TP_ERR_BAD_DATA, checked here since GDAL would spread the NaN); TP_ERR_BACKEND when GDAL
 * fails. out is untouched on failure. */
tp_status tp_gdal_viewshed(const float* heights, size_t height_count, int width, int height,
                           const double geotransform[6], int observer_x, int observer_y,
                           const tp_viewshed_options* options, uint8_t* out, size_t out_count,
                           tp_error* err);

/* The same in GDAL's output mode GVOT_MIN_TARGET_HEIGHT_FROM_GROUND (gdal_viewshed -om GROUND):
 * per sample the height above its ground a target needs to be seen, 0 where it is seen
 * (options->target_height_m is not used: GDAL ignores it in this mode), as floats into out;
 * NaN outside GDAL's window. Fails as tp_gdal_viewshed. */
tp_status tp_gdal_viewshed_ground(const float* heights, size_t height_count, int width,
                                  int height, const double geotransform[6], int observer_x,
                                  int observer_y, const tp_viewshed_options* options, float* out,
                                  size_t out_count, tp_error* err);

/* Writes a viewshed as tp_byte_raster_write does (below), in the format path's extension names,
 * band description "visibility: 255 seen, 0 not seen or beyond the radius". No nodata tag: 0 is
 * "not seen". */
tp_status tp_viewshed_write(const char* path, const uint8_t* values, size_t value_count, int width,
                            int height, const double geotransform[6], const char* crs_wkt,
                            tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_VIEWSHED_H */
