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

/* Grid lines at the view's centre stay at least this many pixels apart (tp_map_grid_spacing):
 * the 1 km grid of the whole Pyrenees tile at the default view (180 m a pixel) was a line every
 * 5.5 pixels, a dark mesh over the terrain; 40 px leave the ground readable between lines and
 * room for a label ("31T CH 76 07" is about 50 px wide at scale 1, the labels skip where they
 * would cover each other). */
#define TP_MAP_GRID_MIN_PX 40.0
/* The coarsest spacing, in steps of ten over the finest: 1, 10, 100 km for the 1 km grid (the
 * MGRS grid's: 100 km is a square). */
#define TP_MAP_GRID_MAX_STEPS 2

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

/* The spacing drawn for a grid whose finest spacing is base_m (> 0, --grid M; 1000 for G) when
 * the ground at the view's centre is m_per_px metres a pixel: base_m x 10^k, the smallest that
 * puts lines TP_MAP_GRID_MIN_PX pixels apart there, k at most TP_MAP_GRID_MAX_STEPS (1, 10,
 * 100 km). m_per_px not finite or not > 0 (no ground at the centre): the coarsest. */
double tp_map_grid_spacing(double base_m, double m_per_px);

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
