/*
 * tp_io.h - terrapatch input/output behind plain C: DEM rasters (GDAL), heightmap and RGBA
 * images (OpenImageIO), CRS descriptions (GDAL's OGR), the metric render grid (GDAL, PROJ),
 * textures draped on it, triangle meshes for ParaView (VTK), and the georeference between grid,
 * render CRS and WGS84 (PROJ, GeographicLib). Conversions between geographic, UTM/UPS, MGRS and
 * other WGS84 coordinates are in tp_geo.h.
 *
 * C11 header; the C++17 implementation lives in io/src, and no GDAL, PROJ, VTK, OpenImageIO or
 * GeographicLib type appears here.
 *
 * Errors: every function that returns a tp_status checks its arguments (a NULL pointer not
 * documented as allowed is TP_ERR_INVALID_ARG), catches every C++ exception inside it
 * (std::bad_alloc becomes TP_ERR_OUT_OF_MEMORY, any other exception TP_ERR_BACKEND with the
 * exception's message, unless the function says otherwise), and leaves its out-parameters
 * untouched on failure; with an err, the message says what went wrong. The functions that
 * return anything else (the _destroy functions, which accept NULL; the _terrain_desc copies;
 * tp_is_heightmap_image; the tp_georef accessors and grid <-> CRS arithmetic) call nothing that
 * throws, and take valid pointers unless they say otherwise.
 */
#ifndef TP_IO_H
#define TP_IO_H

#include "tp_core.h"

/* One header per concept, in io/include/tp_io/; each compiles on its own, but callers include
 * this one. */

/* Reading: DEM files, heightmap images, the checks made on every input, CRSs. */
#include "tp_io/crs.h"
#include "tp_io/dem.h"
#include "tp_io/image.h"
#include "tp_io/input.h"

/* On the metric render grid: the grid of one DEM, mosaics read in bands, draped textures, and
 * the georeference between grid, render CRS and WGS84. */
#include "tp_io/georef.h"
#include "tp_io/mosaic.h"
#include "tp_io/render_grid.h"
#include "tp_io/texture.h"

/* Writing: files whole or not at all, output formats and byte rasters, meshes, viewsheds,
 * gdaldem's slope, aspect and hillshade. */
#include "tp_io/file.h"
#include "tp_io/gdaldem.h"
#include "tp_io/mesh.h"
#include "tp_io/output.h"
#include "tp_io/viewshed.h"

/* Web terrain tiles: gzip in memory, the geoid's undulation. */
#include "tp_io/geoid.h"
#include "tp_io/gzip.h"

/* Terrain stores (.tpt): a built tree on disk. */
#include "tp_io/store.h"

#endif /* TP_IO_H */
