/*
 * point_readout.h - "what is here?": one position on the ground described as `terrapatch point`
 * prints it and the viewer's pick shows it (app/scene/point_readout.c, over ground.h).
 */
#ifndef TP_APP_POINT_READOUT_H
#define TP_APP_POINT_READOUT_H

#include "ground.h"
#include "position.h"

#include "tp_geo.h"

#include <stdio.h>

typedef struct tp_point_readout {
    char source[512];          /* the DEM or store, as given */
    double lat_deg, lon_deg;   /* WGS84 */
    char lat_dms[TP_DMS_TEXT_SIZE], lon_dms[TP_DMS_TEXT_SIZE]; /* 0.01" */
    int mgrs_precision;
    char mgrs[TP_POSITION_MGRS_SPACED_SIZE]; /* "31T CH 76651 00831" */
    int zone, northp;          /* standard UTM zone (0 = UPS) */
    char zone_text[TP_ZONE_TEXT_SIZE]; /* "31n", "UPS s": the hemisphere in lower case, as
                                        * GeographicLib writes it ("33S" is band S) */
    double easting_m, northing_m;
    tp_ground_sample ground;   /* height, slope, aspect, grid and render position */
    char vertical_datum[256];  /* what the source says, or that it says nothing */
} tp_point_readout;

/* Describes the ground at pos (input text for messages: as typed). Returns 1 with *out, or 0
 * with err saying why: the DEM has no CRS, the position is outside the DEM or in a void
 * (naming the position and the grid), a leaf cannot be read. */
int tp_point_readout_at_position(tp_ground* g, const char* source, const tp_position* pos,
                                 const char* input, int mgrs_precision, tp_point_readout* out,
                                 tp_error* err);

/* The same at render-CRS (E, N) (the viewer's pick). */
int tp_point_readout_at_world(tp_ground* g, const char* source, double e_m, double n_m,
                              int mgrs_precision, tp_point_readout* out, tp_error* err);

/* The readout as text: several lines, each ending in '\n' (the command's stdout). */
void tp_point_readout_text(const tp_point_readout* r, char* out, size_t cap);
/* A short form for the HUD (4 lines). */
void tp_point_readout_hud(const tp_point_readout* r, char* out, size_t cap);
/* As a JSON object (keys in docs and README: lat_deg, lon_deg, lat_dms, lon_dms, mgrs,
 * utm {zone, easting_m, northing_m}, elevation_m, vertical_datum, slope_deg, aspect_deg
 * (true north), aspect_grid_deg, convergence_deg, grid {x, y}, render {e_m, n_m}). */
void tp_point_readout_json(const tp_point_readout* r, FILE* f);

/* What is known of the datum of a DEM's heights, from its GDAL driver ("SRTMHGT", "DTED", ...)
 * and the vertical CRS the file states ("" for none), into out (cap bytes): "NAME (as the file
 * states)"; for SRTM and DTED, which state none, "not stated by the file; assumed EGM96 geoid
 * (SRTM's and DTED's specification)"; else "unknown (the file states none)". Said only where
 * it is known: never the EGM96 geoid for a lidar GeoTIFF. */
void tp_heights_datum(const char* driver, const char* vertical_datum, char* out, size_t cap);

#endif /* TP_APP_POINT_READOUT_H */
