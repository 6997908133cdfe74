/*
 * tp_io/crs.h - a coordinate reference system described (name, EPSG code, UTM zone).
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_CRS_H
#define TP_IO_CRS_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Coordinate reference systems (io/src/crs.cpp, through GDAL's OGR)
 */
typedef struct tp_crs_info {
    char name[160]; /* the CRS's own name, e.g. "NAD83 / UTM zone 10N"; "" when it has none */
    int epsg;       /* its EPSG code, or the one GDAL recognises (AutoIdentifyEPSG); else 0 */
    int geographic; /* 1 for a geographic CRS (latitude and longitude), 0 otherwise */
    int utm_zone;   /* 1..60 for a UTM zone (any datum: "NAD83 / UTM zone 10N" too), 0
                       (TP_ZONE_UPS) for UPS, -1 otherwise (and for no CRS) */
    int northp;     /* the hemisphere of utm_zone */
} tp_crs_info;

/* Describes a CRS given as GDAL/PROJ read it: WKT (a tp_dem's crs_wkt), "EPSG:N", a PROJ
 * string. "" means no CRS: TP_OK with every field zero but utm_zone (-1). TP_ERR_BAD_DATA for text
 * GDAL cannot read as a CRS; *out is untouched on failure. */
tp_status tp_crs_describe(const char* crs, tp_crs_info* out, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_CRS_H */
