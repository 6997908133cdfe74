/*
 * full_export.h - `terrapatch export --full -o X.vtp`, streamed: the full-resolution mesh (two
 * triangles per cell whose four samples are drawn) written a piece at a time, so that memory
 * follows one piece, not the map (issue 29, 1.5).
 *
 * A DEM is read in bands of whole rows of its render grid through the mosaic reader (the same
 * grid and, sample for sample, the same heights as the viewer's: tp_mosaic_open), a store in
 * blocks of whole leaves (each leaf read once per pass). Two passes: the first counts the
 * points and triangles (the file's header holds the count), the second writes
 * (tp_mesh_write_pieces). Each piece is a PolyData of its own in the .vtp; points where two
 * pieces meet are repeated. Heights are the grid's own (a DEM's render grid, not quantised; a
 * store's decoded samples), so every triangle's max_error_m is 0.
 */
#ifndef TP_APP_FULL_EXPORT_H
#define TP_APP_FULL_EXPORT_H

#include "scene.h"
#include "tp_geo.h"

#include <stddef.h>

/* Samples in a piece at most: about 250 bytes each while it is built and written, so a piece
 * of this size needs ~130 MB (fewer when the memory left is smaller). */
#define TP_FULL_EXPORT_PIECE_SAMPLES ((size_t)1 << 19)

typedef struct tp_full_export_request {
    const char* path; /* the DEM or store (.tpt) */
    int is_store;
    const tp_scene_options* scene; /* a DEM's options (--crs, --fill-max, --patch, ...) */
    const char* out;               /* a .vtp */
    int origin_local;              /* subtract a scene origin (whole km of the grid origin) */
    size_t piece_samples;          /* 0: TP_FULL_EXPORT_PIECE_SAMPLES (tests make it small) */
} tp_full_export_request;

/* Whether export --full of this request streams: a .vtp of a georeferenced DEM (not a
 * heightmap image, not --fit resample) or of a store. The others build the mesh in memory. */
int tp_full_export_streams(const char* path, int is_store, const tp_scene_options* scene,
                           tp_mesh_format format);

/* Runs it: one "wrote ..." line on stdout, progress on stderr when it is long; one error line
 * naming the file and TP_EXIT_FAILURE (unreadable input, nothing drawn, no room for one piece
 * in the memory left, an unwritable output), or tp_cli_interrupted()'s status after a signal.
 * The output is written whole or not at all. */
int tp_export_full_streamed(const tp_full_export_request* r);

/* The EPSG code of a CRS (0 when GDAL knows none) and its zone as a mesh's field data says it:
 * "31n", "10n" (NAD83 / UTM zone 10N too), "UPS s"; "" for any other CRS. */
void tp_export_zone_of_crs(const char* crs_wkt, int* epsg, char zone[TP_ZONE_TEXT_SIZE]);

#endif
