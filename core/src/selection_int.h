/* selection_int.h - a selection's private state (selection.c, selection_measure.c,
 * selection_query.c). */
#ifndef TP_CORE_SELECTION_INT_H
#define TP_CORE_SELECTION_INT_H

#include "lod_int.h"
#include "terrain_int.h"
#include "tp_selection.h"

/* Written only by the functions that take a non-const tp_selection*; the const ones
 * (selection_measure.c, selection_query.c) only read it, so that several threads may measure one
 * selection at once. */
struct tp_selection {
    const tp_terrain* t;
    int count;
    uint8_t* level;
    uint8_t* next; /* scratch of tp_selection_update: levels being selected */
    uint8_t* visible;
    uint8_t* dirty;
    tp__proj_bound* proj; /* error mode: each visible patch's projection bound */
    uint32_t* tris;       /* cached drawn-triangle count per patch, TP__STALE_TRIS when unknown */
    tp_vertex* vbuf;      /* scratch of tp_selection_stats: one patch at level n */
    double zscale;        /* vertical exaggeration of the drawn surface (1: none) */
    int stitch_add;       /* cracks removed by adding vertices (tp_selection_set_stitch_add) */
};

/* Patch p's AABB as drawn: heights times the selection's vertical scale (selection.c). */
void tp__drawn_box(const tp_selection* s, int p, tp_patch_info* pi);
#define TP__STALE_TRIS UINT32_MAX

/* The patch next to patch p on side `side`, or -1 at the terrain border (selection.c). */
int tp__neighbor(const tp_terrain* t, int p, int side);

/* Largest vertical distance (m) between patch p's drawn triangles at level k with neighbour
 * levels nb, interpolated from their vertices' z_m, and the heights of the samples they cover:
 * ref (src_width x src_height, NaN = none; padded fits only) or, when ref is NULL, the decoded
 * grid. vbuf and tbuf hold a patch at level n and its triangles (selection_measure.c). */
double tp__patch_vertical_error(const tp_terrain* t, int p, int k, const int nb[4],
                                const float* ref, tp_vertex* vbuf, uint32_t* tbuf);

#endif
