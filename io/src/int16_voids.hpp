/*
 * int16_voids.hpp - an Int16 raster without a nodata tag, its two void values as one. Private
 * to io/.
 *
 * tp_dem_read takes both -32768 (SRTM) and -32767 (DTED) of such a raster as nodata. GDAL's
 * warp and VRT mosaic take one nodata value per band, so the rasters they read go through a VRT
 * that maps -32767 onto -32768 (a ComplexSource <LUT>, int16_voids_lut) and tags -32768 as its
 * nodata; every other value reads as itself.
 */
#pragma once

#include "gdal_util.hpp"

#include <string>

namespace tpio {

/* The VRT's LUT: -32768 and -32767 to -32768, -32766 .. 32767 to themselves (one segment of
 * slope exactly 1: GDAL's interpolation gives every integer back exactly). */
extern const char* const int16_voids_lut;

/* Writes to vrt_name (a /vsimem/ name; the caller unlinks it once nothing refers to it) a VRT
 * of band 1 of the raster at path (w x h samples, read as Int16) in which -32767 reads as
 * -32768, its nodata; with the geotransform gt when has_gt and the CRS srs when not null (the
 * caller's: an override of the file's own is taken as it is). Opens it read-only and returns it;
 * null when GDAL cannot (gdal_message() says why). path is referred to by name, as given
 * (a relative name is taken from the working folder). */
Dataset int16_voids_vrt(const std::string& path, int w, int h, const double gt[6], bool has_gt,
                        const OGRSpatialReference* srs, const std::string& vrt_name);

} // namespace tpio
