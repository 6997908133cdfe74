/*
 * dem_check.hpp - the checks tp_dem_read makes of what GDAL read, before the heights are used:
 * the georeference (finite, north-up, within the ranges tp_io.h gives, latitudes on the Earth)
 * and, for ESRI ASCII grids, the text GDAL's lenient reader would accept damaged. Each returns
 * TP_OK or TP_ERR_BAD_DATA with a message naming path and what was wrong.
 */
#ifndef TP_IO_DEM_CHECK_HPP
#define TP_IO_DEM_CHECK_HPP

#include "tp_io.h"

class OGRSpatialReference;

namespace tpio {

/* Finite, not rotated, non-zero pixel size, columns running east (rows either way). */
tp_status check_geotransform(const char* path, const double gt[6], tp_error* err);
/* A geographic raster's rows within +-90 degrees. */
tp_status check_latitude(const char* path, const OGRSpatialReference& srs, const double gt[6],
                         int h, tp_error* err);
/* Pixel size, corners and longitudes within TP_PIXEL_SIZE_*, TP_COORD_MAX_M, TP_LON_MAX_DEG
 * (srs may be NULL: no CRS). */
tp_status check_ranges(const char* path, const OGRSpatialReference* srs, const double gt[6],
                       int w, int h, tp_error* err);
/* An ESRI ASCII grid's text: every value a number, exactly w x h of them. */
tp_status check_ascii_grid(const char* path, int w, int h, tp_error* err);

} // namespace tpio

#endif
