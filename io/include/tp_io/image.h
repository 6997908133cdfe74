/*
 * tp_io/image.h - heightmap images without georeference and RGBA pictures, through OpenImageIO.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_IMAGE_H
#define TP_IO_IMAGE_H

#include "tp_core.h"
#include "tp_io/dem.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Heightmap images without georeference (io/src/image_read.cpp, through OpenImageIO)
 */
/* The ranges of tp_image_options' spacing_m and zscale (besides 0, the default), and the
 * heights the scaled counts may reach (either sign): beyond them tp_dem_read_image refuses the
 * options with TP_ERR_INVALID_ARG. */
#define TP_IMAGE_SPACING_MIN_M TP_PIXEL_SIZE_MIN_M
#define TP_IMAGE_SPACING_MAX_M TP_PIXEL_SIZE_MAX_M
#define TP_IMAGE_ZSCALE_MIN 1e-6
#define TP_IMAGE_ZSCALE_MAX 1e5
#define TP_IMAGE_HEIGHT_MAX_M 1e5

typedef struct tp_image_options {
    double spacing_m;        /* post spacing, TP_IMAGE_SPACING_MIN_M .. _MAX_M; 0 means 1 m
                                (with a warning) */
    double zscale;           /* metres per count of channel 0, TP_IMAGE_ZSCALE_MIN .. _MAX; 0
                                means 1 */
    int has_origin;          /* place the image's centre at (origin_lat, origin_lon) in the */
    double origin_lat_deg;   /* WGS84 UTM/UPS zone of that point; otherwise the grid is in */
    double origin_lon_deg;   /* local metres with its north-west corner at (0, 0) */
} tp_image_options;

/* 1 when path names an image format read through OpenImageIO rather than GDAL (by extension:
 * .png .jpg .jpeg .exr .pgm .ppm .tga .bmp .hdr .webp). */
int tp_is_heightmap_image(const char* path);

/* Reads channel 0 of an image (8/16/32-bit integer or float samples, taken as raw counts, not
 * normalised) as heights = count * zscale. North-up: row 0 is north. Only for rasters without
 * georeference: a file that is not a heightmap image by extension and that GDAL reads with a
 * CRS or a geotransform (a GeoTIFF, an .hgt) is refused with TP_ERR_INVALID_ARG ("FILE is
 * georeferenced (CRS ...); --spacing/--zscale apply only to ..."); read it with tp_dem_read.
 * So are spacing_m and zscale outside their ranges, and heights beyond +-TP_IMAGE_HEIGHT_MAX_M
 * after scaling. Before decoding: a path that is not a regular file is TP_ERR_IO; a PNG whose
 * chunks are cut short or fail their CRC, or whose header claims more pixels than its
 * compressed data can hold, TP_ERR_BAD_DATA; an image that would not fit in memory,
 * TP_ERR_OUT_OF_MEMORY. The codecs' own messages (libpng's "libpng error: ...") are kept off
 * stderr: their text is in err. Errors name the file; *out is untouched on failure. */
tp_status tp_dem_read_image(const char* path, const tp_image_options* options, tp_dem** out,
                            tp_error* err);

/* Writes d as a Float32 GeoTIFF (DEFLATE, tiled; NaN nodata; band unit "metre"; its
 * geotransform and CRS) at path, through a temporary file beside it renamed when complete:
 * a heightmap image placed with tp_image_options, made a DEM GDAL reads, so that a store can
 * be built from it (the store cache, app/scene/store_cache.c). TP_ERR_IO naming path on failure. */
tp_status tp_dem_write_geotiff(const tp_dem* d, const char* path, tp_error* err);

/* Writes an RGBA8 image (w x h, top row first) to path through OpenImageIO, the format from the
 * extension (.png, .jpg, .tif, ...). The image is encoded in memory and written with
 * tp_file_write: a failure (full disk, signal) leaves nothing behind and an older file as it
 * was. TP_ERR_INVALID_ARG for an extension OpenImageIO cannot encode in memory. */
tp_status tp_image_write_rgba(const char* path, int w, int h, const uint8_t* rgba, tp_error* err);
/* tp_output_check, and that path's extension names a format tp_image_write_rgba can write: for
 * a screenshot path, before the rendering. Writes nothing. */
tp_status tp_image_output_check(const char* path, tp_error* err);

/* Reads an image as RGBA8 (w x h, top row first; grey and RGB are expanded, alpha 255).
 * *rgba is malloc'd: free() it. */
tp_status tp_image_read_rgba(const char* path, int* w, int* h, uint8_t** rgba, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_IMAGE_H */
