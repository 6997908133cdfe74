/*
 * tp_io/gdaldem.h - slope, aspect and hillshade of a grid by GDAL's gdaldem algorithms
 * (GDALDEMProcessing), and the result written as a raster.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_GDALDEM_H
#define TP_IO_GDALDEM_H

#include "tp_core.h"
#include "tp_io/output.h"

#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * gdaldem (io/src/gdaldem.cpp)
 *
 * The grid (heights in metres on a metric grid, as the render grid: GDAL's scale -s 1) goes to
 * GDAL as a Float32 MEM dataset, its voids (NaN) as nodata, and GDALDEMProcessing computes
 * what `gdaldem slope|aspect|hillshade` would on a file holding the same grid, with the same
 * options. Its conventions: slope in degrees from horizontal (or percent), aspect in degrees
 * clockwise from the grid's north (the +N axis of its CRS) that the slope faces (downhill),
 * hillshade 1..255. Where the 3x3 window of a post has a void or leaves the grid (its edge) the
 * result is nodata, unless compute_edges (gdaldem -compute_edges) fills the missing neighbours;
 * on flat ground the aspect is nodata (or 0 with zero_for_flat). One difference: gdaldem
 * -zero_for_flat (GDAL 3.6) writes 0 in voids and where the window is not whole too, with no
 * nodata value; here those posts stay nodata (-9999) and only flat ground is 0.
 */

typedef enum tp_gdaldem_product {
    TP_GDALDEM_SLOPE = 0, /* Float32, nodata -9999 */
    TP_GDALDEM_ASPECT,    /* Float32, nodata -9999 */
    TP_GDALDEM_HILLSHADE, /* Byte 1..255, nodata 0 */
} tp_gdaldem_product;

typedef enum tp_gdaldem_method {
    TP_GDALDEM_HORN = 0,    /* Horn (1981), gdaldem's default (-alg Horn) */
    TP_GDALDEM_ZEVENBERGEN, /* Zevenbergen & Thorne (1987) (-alg ZevenbergenThorne) */
} tp_gdaldem_method;

/* The nodata values gdaldem writes. */
#define TP_GDALDEM_FLOAT_NODATA (-9999.0)
#define TP_GDALDEM_HILLSHADE_NODATA 0.0

typedef struct tp_gdaldem_options {
    tp_gdaldem_product product;
    tp_gdaldem_method method;
    int compute_edges;   /* -compute_edges */
    int slope_percent;   /* slope: -p, percent instead of degrees */
    int zero_for_flat;   /* aspect: -zero_for_flat, 0 instead of nodata where flat */
    double azimuth_deg;  /* hillshade: -az, the light's direction, clockwise from grid north */
    double altitude_deg; /* hillshade: -alt, the light's elevation above the horizon */
    double z_factor;     /* hillshade: -z, heights multiplied by it */
} tp_gdaldem_options;

/* gdaldem's defaults for product: Horn, no edges, degrees, nodata where flat, azimuth 315,
 * altitude 45, z factor 1. */
tp_gdaldem_options tp_gdaldem_options_default(tp_gdaldem_product product);

/* "slope", "aspect", "hillshade" (gdaldem's names); "horn", "zevenbergen". */
const char* tp_gdaldem_product_name(tp_gdaldem_product p);
const char* tp_gdaldem_method_name(tp_gdaldem_method m);

/* The output kind product is written as: TP_OUTPUT_FLOAT_RASTER, or TP_OUTPUT_BYTE_RASTER for
 * the hillshade. */
tp_output_kind tp_gdaldem_output_kind(tp_gdaldem_product p);

/* The product of the width x height grid heights (height_count = width * height, row 0 first,
 * NaN in a void) on geotransform into out (out_count >= height_count): the value at each post,
 * NaN where gdaldem gives nodata. TP_ERR_INVALID_ARG for NULL pointers, a size mismatch, a
 * geotransform that is rotated or has a zero step, options out of range (azimuth, altitude
 * and z factor not finite, altitude outside -90..90, z factor 0); TP_ERR_BACKEND when GDAL
 * fails. out is untouched on failure. */
tp_status tp_gdaldem_compute(const float* heights, size_t height_count, int width, int height,
                             const double geotransform[6], const tp_gdaldem_options* options,
                             float* out, size_t out_count, tp_error* err);

/* What tp_gdaldem_write wrote: its posts with a value, those with nodata, the values' range
 * (NaN, NaN when none has one), and the seconds GDAL took to compute the product and to encode
 * and write it. */
typedef struct tp_gdaldem_stats {
    size_t valid, nodata;
    double min, max;
    double compute_s, write_s;
} tp_gdaldem_stats;

/* Computes the product as tp_gdaldem_compute does and writes it to path in the format its
 * extension names for the product's kind (tp_gdaldem_output_kind), as tp_byte_raster_write
 * writes (output.h: GDAL's driver encodes it in memory, the file and its sidecars are written all
 * or none, older sidecars removed), with geotransform, crs_wkt ("" or NULL: none), gdaldem's
 * nodata value (-9999 for slope and aspect, 0 for the hillshade) and a band description naming
 * the product and its options. *stats (may be NULL) on success. Errors: tp_gdaldem_compute's,
 * tp_byte_raster_write's. */
tp_status tp_gdaldem_write(const char* path, const float* heights, size_t height_count, int width,
                           int height, const double geotransform[6], const char* crs_wkt,
                           const tp_gdaldem_options* options, tp_gdaldem_stats* stats,
                           tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_GDALDEM_H */
