/*
 * mesh_export.h - the geometry a selection draws, as one connected triangle mesh for ParaView:
 * shared vertices merged, degenerate triangles dropped, per-triangle error measured against the
 * source samples. Used by `terrapatch export` and the viewer's export key.
 */
#ifndef TP_APP_MESH_EXPORT_H
#define TP_APP_MESH_EXPORT_H

#include "scene.h"
#include "tp_geo.h"

typedef struct tp_export_options {
    int include_culled;   /* every patch, not only the visible ones */
    int full_cells_only;  /* --full: two triangles per cell of four drawn samples, nothing else */
    int origin_local;     /* subtract a scene origin (written to the field data) */
    tp_mesh_format format;
    const char* camera_text;
    const char* lod_text;
} tp_export_options;

typedef struct tp_export_result {
    size_t points, triangles;
    double max_error_m, rms_error_m; /* measured against the source samples */
} tp_export_result;

/* Builds the mesh of sel's current levels and writes it to path (NULL: builds and measures it,
 * writes nothing). On failure err holds a one-line message naming path (or the DEM): nothing to
 * export (TP_ERR_INVALID_ARG), out of memory, or tp_mesh_write's status. */
tp_status tp_export_selection(const tp_scene* sc, const tp_selection* sel,
                              const tp_export_options* o, const char* path,
                              tp_export_result* result, tp_error* err);

/* Static error-bounded levels for `export --max-error M` (every patch, no camera): the core's
 * TP_LOD_MAX_ERROR mode, measured against the source samples (the render grid) unless the fit
 * resampled them (then against the decoded grid). */
tp_status tp_select_max_error(const tp_scene* sc, tp_selection* sel, double m, tp_error* err);

/* The frame every mesh of a DEM is written in: origin (0, or with origin_local the grid origin
 * rounded down to whole kilometres, subtracted from every point) and the UTM/UPS zone text ("" for
 * another CRS). */
void tp_export_frame(const tp_scene* sc, int origin_local, double origin[3],
                     char zone[TP_ZONE_TEXT_SIZE]);

/* Triangles of the full mesh (`export --full`): two per cell of four drawn samples. */
size_t tp_full_mesh_triangles(const tp_scene* sc);

#endif
