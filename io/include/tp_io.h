/*
 * tp_io.h - terrapatch input/output behind plain C: DEM rasters through GDAL.
 *
 * C11 header; the C++17 implementation lives in io/src, and no GDAL, VTK, OpenImageIO or
 * GeographicLib type appears here. Every function catches C++ exceptions and turns them into a
 * tp_status with a message (TP_ERR_BACKEND).
 */
#ifndef TP_IO_H
#define TP_IO_H

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
    char units[32];          /* band unit type ("metre", "m", "" when unknown) */
    /* Warnings worth showing the user (one per line, '\n'-separated), e.g. untagged Int16
     * -32768/-32767 taken as nodata. "" when none. Owned. */
    char* warnings;
} tp_dem;

/* Reads band 1 of any raster GDAL opens. Int16 rasters without a nodata tag have -32768 and
 * -32767 taken as nodata, with a warning. A raster with no valid sample is TP_ERR_BAD_DATA.
 * Errors name the file and what was wrong. On failure *out is untouched. */
tp_status tp_dem_read(const char* path, tp_dem** out, tp_error* err);
void tp_dem_destroy(tp_dem* dem); /* accepts NULL */

/* A tp_terrain_desc pointing into dem (valid while dem lives), with the given patch size/fit. */
tp_terrain_desc tp_dem_terrain_desc(const tp_dem* dem, int patch_size, tp_fit fit);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_H */
