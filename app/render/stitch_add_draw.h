/*
 * stitch_add_draw.h - what the renderer draws for a patch in `--stitch add` mode (Brodersen,
 * section 4; tp_patch_triangles_add): per neighbour configuration (k, the finer neighbours'
 * levels), the samples the added-vertex triangulation uses, in lattice order, and its
 * triangles as indices into that compact list; computed once per configuration and kept.
 * A patch drawn this way takes a vertex-pool slot of the smallest level whose slot holds its
 * samples and whose triangle region holds its triangles (`level`), writes the samples'
 * vertex data (unmoved) into it and the configuration's triangles into its region.
 * Pure C over the core (no GL).
 */
#ifndef TP_APP_STITCH_ADD_DRAW_H
#define TP_APP_STITCH_ADD_DRAW_H

#include "tp_core.h"

#include <stddef.h>
#include <stdint.h>

/* One neighbour configuration. */
typedef struct tp__stitch_add_set {
    int level;  /* the vertex-pool level whose slots and regions hold it */
    int finest; /* the finest level among the patch's and its neighbours' */
    size_t vertex_count;
    uint32_t* samples; /* vertex_count sample indices (row * (2^n+1) + column), ascending */
    size_t triangle_count;
    uint32_t* triangles; /* 3 * triangle_count indices into samples, wound as the strips */
} tp__stitch_add_set;

typedef struct tp__stitch_add tp__stitch_add;

/* The configurations of patches of (2^n+1)^2 samples (n in 0..TP_MAX_N). NULL: out of memory. */
tp__stitch_add* tp__stitch_add_create(int n);
void tp__stitch_add_destroy(tp__stitch_add* s); /* accepts NULL */

/* 1 if a level-k patch with these neighbour levels (TP_NO_NEIGHBOR or any level) takes added
 * vertices (some neighbour is finer than k): only then does it need a set. */
int tp__stitch_add_needed(int k, const int8_t nb[4]);

/* The set of a level-k patch with these neighbour levels (made on first use). NULL: out of
 * memory. */
const tp__stitch_add_set* tp__stitch_add_get(tp__stitch_add* s, int k, const int8_t nb[4]);

/* Bytes of CPU memory it holds (its table, the sets made and their scratch). */
size_t tp__stitch_add_cpu_bytes(const tp__stitch_add* s);

/* Patch `patch` of t drawn with set: writes set->vertex_count unmoved vertices (as
 * tp_patch_vertices writes them), their unit normals and whether each is a filled void.
 * vertices, normals and filled hold (2^finest+1)^2 entries (the level-finest lattice is read
 * into them, then compacted in place). */
void tp__stitch_add_fill(const tp__stitch_add* s, const tp__stitch_add_set* set,
                         const tp_terrain* t, int patch, tp_vertex* vertices, float (*normals)[3],
                         uint8_t* filled);

/* tp__stitch_add_fill for drawn node i of cut over tree (tp_cut_vertices_at_level: a side
 * that moves onto a larger neighbour's vertices is moved; --stitch add over a store). */
void tp__stitch_add_fill_node(const tp__stitch_add* s, const tp__stitch_add_set* set,
                              const tp_tree* tree, const tp_cut* cut, size_t i, tp_vertex* v,
                              float (*normals)[3], uint8_t* filled);

#endif
