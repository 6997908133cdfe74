/*
 * tin_export.h - the error-bounded TIN of `export --max-error M` (--mesh tin, the default):
 * tp_tin_build_tiled on the source samples, cut at the voids, written as the same mesh as the other
 * modes (points in the render CRS, elevation_m, void_filled, max_error_m per triangle, field
 * data), without patch_id and lod (a TIN has neither).
 */
#ifndef TP_APP_TIN_EXPORT_H
#define TP_APP_TIN_EXPORT_H

#include "mesh_export.h"

/* The TIN is built in tiles of this many cells a side on every online CPU (tp_tin_build_tiled:
 * a tile's samples and triangles stay in cache; docs/tin.md "Tiled build"). */
#define TP_TIN_EXPORT_TILE_CELLS 256

/* Builds the TIN whose vertical error is <= m at every valid source sample (the render grid,
 * or the decoded grid where the fit resampled it) and which covers exactly the cells the full
 * mesh draws (four valid samples), and writes it to path (NULL: builds and measures only).
 * Per triangle max_error_m is measured again here, apart from the build (tp_triangle_rasterize
 * against the source samples); result->max_error_m is their maximum and result->rms_error_m
 * the RMS over the covered samples, each once. On failure err holds one line naming path (or
 * the DEM): TP_ERR_INVALID_ARG when no triangle is left (a DEM of voids), out of memory, or
 * tp_mesh_write's status. */
tp_status tp_export_tin(const tp_scene* sc, double m, const tp_export_options* o,
                        const char* path, tp_export_result* result, tp_error* err);

#endif
