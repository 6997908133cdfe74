/*
 * store_export.h - `terrapatch export` on a built store (.tpt): the meshes it writes for a DEM
 * (the camera's cut, a static --max-error cut, --full), built from nodes read as they are needed
 * and released when they are not (issue 12).
 *
 * Every node the mesh draws is read at full detail, synchronously, before anything is written:
 * an export never draws an ancestor in place of a node that is not loaded yet. Triangles come
 * from the cut's crack-free vertices (tp_cut_vertices), shared vertices are merged, and each
 * triangle's max_error_m is measured against the full-resolution samples it covers (the
 * leaves' decoded samples, read through a bounded cache).
 */
#ifndef TP_APP_STORE_EXPORT_H
#define TP_APP_STORE_EXPORT_H

#include "mesh_export.h"
#include "view_options.h"

/* The most triangles a store export builds in memory (--full to a .vtk or .vtm, --lod full, a
 * tiny --max-error; --full to a .vtp streams, full_export.h): above it
 * the export is refused before the nodes are read (--full, from the grid's size) or as soon as
 * the cut counts more (the other modes). 50 M triangles make a .vtp of about 1.5 GB and need
 * about 5 GB of memory while it is written. */
#define TP_STORE_EXPORT_MAX_TRIANGLES ((size_t)50 * 1000 * 1000)

typedef enum tp_store_export_mode {
    TP_STORE_EXPORT_VIEW = 0,  /* the cut of a camera (error, distance or full mode) */
    TP_STORE_EXPORT_FULL,      /* every full-resolution cell of four drawn samples */
    TP_STORE_EXPORT_MAX_ERROR  /* static crack-free cut, bound <= max_error_m everywhere */
} tp_store_export_mode;

typedef struct tp_store_export_request {
    const char* store_path;    /* the .tpt */
    const char* out;           /* the mesh file */
    tp_store_export_mode mode;
    double max_error_m;        /* TP_STORE_EXPORT_MAX_ERROR */
    int tin;                   /* with it: an error-bounded TIN (store_tin.h), not patches */
    int view_tins;             /* TP_STORE_EXPORT_VIEW, --mesh tin: the cut's complete nodes
                                  as the TINs `view --mesh tin` draws (tp_cut_set_tins) */
    const tp_view_setup* vs;   /* TP_STORE_EXPORT_VIEW: camera, LoD, field of view, size */
    tp_mesh_format format;
    int origin_local;
} tp_store_export_request;

/* Runs the export; prints one line on success ("wrote ...") or one error line naming the file
 * and returns the command's exit status: TP_EXIT_OK; TP_EXIT_FAILURE for an unreadable store
 * or node, an unwritable output, or a mesh over TP_STORE_EXPORT_MAX_TRIANGLES (the message
 * names the count and the limit and points to --max-error or a camera); TP_EXIT_USAGE for a
 * --max-error below the store's quantisation error; tp_cli_interrupted()'s after a signal. */
int tp_export_store(const tp_store_export_request* r);

#endif
