/*
 * map_grid.h - what the viewer's grid labels say (overlay.c draws them): on a UTM or UPS render
 * grid the MGRS of each intersection, as a military map reads ("31T CH" for the 100 km square,
 * then the principal digits "76 00"); on any other render CRS the plain kilometres of the render
 * grid ("4501.5E 4722N"). No GL.
 *
 * Which: the render CRS counts as UTM zone Z (or UPS) when the DEM's centre, taken to latitude
 * and longitude through the georeference and back to UTM/UPS in zone Z (GeographicLib), lands
 * within TP_MAP_GRID_MATCH_M of where it was: a WGS84 UTM render grid (the default for a
 * geographic DEM) matches to nanometres, NAD83 UTM to about a metre; a local CRS, a Lambert or a
 * State Plane grid do not match and keep the plain labels. The letters come from GeographicLib's
 * MGRS (tp_mgrs_forward), never from here.
 */
#ifndef TP_APP_MAP_GRID_H
#define TP_APP_MAP_GRID_H

#include "tp_io.h"

#define TP_MAP_GRID_MATCH_M 50.0

typedef enum tp_map_grid_kind {
    TP_MAP_GRID_PLAIN = 0, /* render CRS kilometres */
    TP_MAP_GRID_MGRS,      /* UTM zone or UPS: MGRS */
} tp_map_grid_kind;

typedef struct tp_map_grid {
    tp_map_grid_kind kind;
    int zone, northp; /* MGRS: zone 1..60, 0 = UPS */
    int digits;       /* MGRS: digits per coordinate the spacing needs (1000 m: 2) */
    int decimals;     /* plain: decimals of the kilometres */
} tp_map_grid;

/* Decides the labels of a grid of spacing_m (> 0) on a render grid (georef, its geotransform gt
 * and its size in samples). Cannot fail: without a geographic position it is PLAIN. */
void tp_map_grid_init(tp_map_grid* g, const tp_georef* georef, const double gt[6], int width,
                      int height, double spacing_m);

/* The label of the grid intersection (e, n) of the render CRS: square (cap 16) the grid zone
 * designator and 100 km square ("31T CH", "Z AH"; "" for PLAIN), digits (cap 32) the principal
 * digits ("76 00") or plain kilometres ("4501.5E 4722N"). An MGRS label outside the MGRS range
 * of its zone falls back to the plain text. */
void tp_map_grid_label(const tp_map_grid* g, double e, double n, char* square, char* digits);

#endif
