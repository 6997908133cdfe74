/*
 * tp_io/dem.h - DEM rasters read through GDAL (io/src/dem_read.cpp, dem_check.cpp,
 * int16_voids.cpp, vertical_datum.cpp): band 1 in metres, the georeference ranges a DEM may
 * have, the vertical datum a file states.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_DEM_H
#define TP_IO_DEM_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Band 1 of a raster, as read: the transient input to tp_terrain_create. */
typedef struct tp_dem {
    int width, height;
    float* heights;          /* width * height, row-major, row 0 first; NaN = nodata */
    double geotransform[6];  /* GDAL geotransform (pixel-is-point already turned into corners) */
    int has_geotransform;    /* 0 if the file had none (then (0,1,0,0,0,-1) is filled in) */
    char* crs_wkt;           /* WKT2 of the CRS, or "" if the file has none; owned */
    int epsg;                /* EPSG code of the CRS when known, else 0 */
    char driver[32];         /* GDAL driver short name: "GTiff", "SRTMHGT", "AAIGrid", ... */
    char data_type[16];      /* GDAL data type of band 1: "Int16", "Float32", ... */
    int is_integer_type;     /* 1 for integer band types */
    int has_nodata;          /* 1 if the band has a nodata tag */
    double nodata_value;     /* the tag's value when has_nodata */
    size_t void_count;       /* samples that are nodata (tag, NaN, or untagged -32768/-32767) */
    double min_m, max_m;     /* over valid samples; NaN if none */
    char units[32];          /* band unit type as the file states it ("metre", "ft", "") */
    /* Heights are in metres: read in z_unit and multiplied by z_to_m (1 for metres and for an
     * unknown unit, which is taken as metres with a warning). z_unit: "metre", "international
     * foot", "US survey foot", "" when the file states none; z_unit_from: how it is known
     * ("band unit 'ft'", "vertical CRS 'NAVD88 height (ftUS)'", "--z-unit ft"), "" when not. */
    double z_to_m;
    char z_unit[48];
    char z_unit_from[200];
    char vertical_datum[160]; /* the vertical CRS's name, as the file states it; "" when none */
    /* Warnings worth showing the user (one per line, '\n'-separated), e.g. untagged Int16
     * -32768/-32767 taken as nodata. "" when none. Owned. */
    char* warnings;
} tp_dem;

/* The georeference a DEM may have. Outside these ranges a geotransform is damage (a pixel of
 * 1e-300 m, an extent of 1e300 m), not a place on the Earth: tp_dem_read refuses it, saying
 * which value is outside which range. Pixel sizes in metres apply to projected CRSs (in their
 * own linear unit converted to metres), those in degrees to geographic ones; a DEM without a CRS
 * may have either (its units are unknown). Corner coordinates: projected within
 * +-TP_COORD_MAX_M, geographic longitudes within +-TP_LON_MAX_DEG (a grid in 0 .. 360 may reach
 * past 360: 355 .. 365 is a place) spanning at most 360 degrees plus one wrap-around column
 * (latitudes: sample centres within +-90). */
#define TP_PIXEL_SIZE_MIN_M 1e-3
#define TP_PIXEL_SIZE_MAX_M 1e6
#define TP_PIXEL_SIZE_MIN_DEG 1e-8
#define TP_PIXEL_SIZE_MAX_DEG 10.0
#define TP_COORD_MAX_M 1e8
#define TP_LON_MAX_DEG 540.0

/* Reads band 1 of any raster GDAL opens. Int16 rasters without a nodata tag have -32768 and
 * -32767 taken as nodata, with a warning; +-Inf and +-FLT_MAX heights are nodata too (with a
 * warning). Also warned about: a .prj beside the file that GDAL cannot read as a CRS, and a
 * raster with neither CRS nor geotransform (taken as 1 m posts). DTED checksums are verified
 * (GDAL's DTED_VERIFY_CHECKSUM, unless the environment sets it), and ESRI ASCII grids get a
 * pass over their text (GDAL reads "307x" as 307 and ignores values past nrows x ncols).
 * Errors name the file and what was wrong; on failure *out is untouched:
 *   TP_ERR_IO             missing file, a directory GDAL cannot open, a FIFO, device or socket
 *                         (refused before opening: reading one could block forever);
 *   TP_ERR_BAD_DATA       empty or unreadable files, non-finite, rotated or zero-size
 *                         geotransforms, gt[1] < 0, pixel sizes or corners outside the ranges
 *                         above, geographic rows beyond +-90 degrees, a read that fails part
 *                         way, a DTED column whose checksum does not match, an ASCII grid with
 *                         a token that is not a number or more or fewer values than nrows x
 *                         ncols (the message gives the line), no valid sample;
 *   TP_ERR_OUT_OF_MEMORY  heights that would not fit in this machine's memory (refused before
 *                         allocating; the message says how much they would need);
 *   TP_ERR_INVALID_ARG    a NULL or empty path, a NULL out. */
tp_status tp_dem_read(const char* path, tp_dem** out, tp_error* err);
/* tp_dem_read with the unit of the heights given (--z-unit: "m", "ft" or "us-ft"), overriding
 * what the file says; NULL: the file's (band 1's unit type, else its vertical CRS's unit).
 * TP_ERR_INVALID_ARG for another z_unit. */
tp_status tp_dem_read_z(const char* path, const char* z_unit, tp_dem** out, tp_error* err);
void tp_dem_destroy(tp_dem* dem); /* accepts NULL */

/* What a DEM file states about its heights' datum (io/src/vertical_datum.cpp). Heights are
 * never converted; this only reports. */
typedef struct tp_vertical_info {
    char datum[160]; /* the name of the file's vertical CRS ("EGM96 height", "NAVD88 height"),
                        "" when the file states none (then the datum is unknown to us) */
    char units[32];  /* band 1's unit type ("metre", "m", "" when unknown) */
    char driver[32]; /* GDAL driver short name ("SRTMHGT", "GTiff", ...) */
} tp_vertical_info;

/* Opens path with GDAL (no heights read) and writes what its CRS says of the vertical datum.
 * TP_ERR_IO for a missing file or one that is not regular (a FIFO would block),
 * TP_ERR_BAD_DATA for one GDAL cannot open; *out written only on success. */
tp_status tp_dem_vertical_info(const char* path, tp_vertical_info* out, tp_error* err);

/* A tp_terrain_desc pointing into dem (valid while dem lives), with the given patch size/fit.
 * dem NULL gives a desc without heights, which tp_terrain_create refuses. */
tp_terrain_desc tp_dem_terrain_desc(const tp_dem* dem, int patch_size, tp_fit fit);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_DEM_H */
