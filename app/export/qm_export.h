/*
 * qm_export.h - `terrapatch export STORE|DEM --tiles quantized-mesh -o DIR` (issue 34;
 * docs/quantized_mesh.md): a Cesium terrain tile set (layer.json, z/x/y.terrain gzip-compressed
 * quantized-mesh-1.0 tiles with oct-encoded normals, errors.json) in the geographic tiling
 * scheme, each tile an error-bounded TIN (qm_tile.c) whose true error against the store's
 * full-resolution posts is measured and written. Resumable: DIR/export.txt holds the options,
 * DIR/tiles.log one line per tile written (after its atomic rename); a rerun with the same
 * options skips the tiles the log names, one with other options is refused.
 */
#ifndef TP_APP_QM_EXPORT_H
#define TP_APP_QM_EXPORT_H

#include "scene.h"

typedef struct tp_qm_request {
    const char* path;             /* store or DEM */
    const char* out_dir;
    const tp_scene_options* dem;  /* the DEM options (a store refuses them) */
    int max_zoom;                 /* -1: from the store's post spacing */
    int has_bounds;
    double bounds[4];             /* west, south, east, north (degrees) */
    int ellipsoid;                /* 1: heights above the WGS84 ellipsoid (EGM96 added) */
    double max_error_m;           /* < 0: Cesium's geometric error per level */
    int threads;                  /* >= 1: a level's tiles built on this many (qm_workers.h);
                                     the output is the same bytes for any count */
} tp_qm_request;

/* Runs the export; TP_EXIT_* after its messages (the wrote line on stdout). */
int tp_export_qm(const tp_qm_request* r);

/* The TIN bound of level z of a tile set whose deepest level is max_zoom: Cesium's geometric
 * error of the level (tp_qmesh_level_error_m), or with max_error_m >= 0 that bound at max_zoom
 * doubled per level above it. */
double tp_qm_level_bound(int z, int max_zoom, double max_error_m);

#endif
