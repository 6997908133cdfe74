/*
 * store_tin.h - the error-bounded TIN of `export --max-error M` on a store (.tpt), built tile by
 * tile (tp_tin_build_tile, tiles of TP_TIN_EXPORT_TILE_CELLS cells) from windows of the store's
 * full-resolution samples read through the leaf cache: the grid is never in memory whole, and
 * the tiles meet edge for edge (their shared borders are the same polylines on both sides).
 */
#ifndef TP_APP_STORE_TIN_H
#define TP_APP_STORE_TIN_H

#include "store_mesh.h"

typedef struct tp_store_tin_stats {
    size_t tiles;          /* tiles built (with a triangle or not) */
    double sum_sq;         /* squared errors over the covered samples, each once */
    size_t samples;        /* those samples */
    size_t peak_window;    /* largest window, in samples */
} tp_store_tin_stats;

/* Builds the TIN of the store's width x height full-resolution samples (the tree geometry's
 * src_width, src_height) whose vertical error is <= m at every drawn sample, cut at voids (the
 * cells of four drawn samples, as --full), into m_out: points merged by grid position with
 * their decoded heights and filled bits, triangles with max_error_m measured against the window's
 * samples (tp_triangle_rasterize), patch_id and lod left 0 (not written for a TIN). Stops with
 * 0 and a message in err on a read failure (naming the store through the cache's error), out of
 * memory, more than max_triangles triangles, or an interrupt (tp_interrupted()). */
int tp_store_tin_mesh(leaf_cache* lc, int width, int height, double m, size_t max_triangles,
                      mesh_build* m_out, tp_store_tin_stats* stats, tp_error* err);

#endif
