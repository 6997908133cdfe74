/*
 * stitch_add_five.h - `--stitch add` drawn as five regions a patch (`--stitch-add-draw five`),
 * the other way Brodersen (section 4) names besides an index set per neighbour configuration
 * (stitch_add_draw.h): the triangles of tp_patch_triangles_add split into one region per side
 * that takes vertices (the level-k grid triangles with an edge on that side) and the interior
 * (every other grid triangle: the same for every configuration with the same sides taking
 * vertices, so 16 index sets a level). A side's set depends on its own finer neighbour only,
 * but for the two grid triangles with edges on two sides: cell (0, 0)'s upper-left one (TOP and
 * LEFT edges) is TOP's when TOP takes vertices (its set then depends on LEFT's level too), else
 * LEFT's; the last cell's lower-right one (BOTTOM and RIGHT) is BOTTOM's, else RIGHT's. A patch
 * is drawn as 1 + (its sides that take vertices) draws of these shared sets, at most five, so
 * nothing is written per patch but its vertices.
 *
 * For that a patch's vertex layout is fixed by (k, D), D the most levels any neighbour is finer
 * (1..n-k), not by the configuration: the level-k grid in lattice order ((2^k+1)^2, so the
 * level-k strip draws it as well), then per side (TP_SIDE_TOP, RIGHT, BOTTOM, LEFT) a block of
 * 2^k (2^D - 1) border samples that are not grid samples: those of level k+1 first, then k+2's,
 * .., each level's in increasing position along the side (a side d levels finer uses the first
 * 2^k (2^d - 1)). The layout's vertices change only when k or D does.
 *
 * Index sets are made on first use and appended to one list of uint32 indices (relative to the
 * layout's first vertex) whose offsets stay valid; the GL part (tp__stitch_five_gl_buffer) keeps
 * a copy of that list in an element buffer. Everything else is pure C over the core.
 */
#ifndef TP_APP_STITCH_ADD_FIVE_H
#define TP_APP_STITCH_ADD_FIVE_H

#include "tp_core.h"

#include <stddef.h>
#include <stdint.h>

/* The vertex layout of level-k patches whose finest neighbour is D levels finer. */
typedef struct tp__five_layout {
    int k, D;
    int level;           /* the vertex-pool level whose slots hold it ((2^level+1)^2 >= count) */
    size_t vertex_count; /* (2^k+1)^2 + 4 * 2^k * (2^D - 1) */
    uint32_t* samples;   /* per vertex its sample index (row * (2^n+1) + column) */
} tp__five_layout;

/* A patch's draws: the interior, then the regions of the sides that take vertices in tp_side
 * order, empty ones left out (a level-0 interior can be); indices into the list, relative to
 * the layout. */
typedef struct tp__five_draws {
    int count;
    size_t first[5];       /* first index of each draw in the list */
    size_t index_count[5]; /* 3 * its triangles */
    size_t triangles;      /* in all */
} tp__five_draws;

typedef struct tp__stitch_five tp__stitch_five;

/* For patches of (2^n+1)^2 samples (n in 0..TP_MAX_N). NULL: out of memory. */
tp__stitch_five* tp__stitch_five_create(int n);
/* Also deletes the element buffer, if one was made (its GL context must then be current).
 * Accepts NULL. */
void tp__stitch_five_destroy(tp__stitch_five* f);

/* The layout of a level-k patch with these neighbour levels (TP_NO_NEIGHBOR or any level), of
 * which at least one is finer than k (tp__stitch_add_needed); made on first use. NULL: out of
 * memory. */
const tp__five_layout* tp__stitch_five_layout(tp__stitch_five* f, int k, const int8_t nb[4]);

/* Its draws (index sets made on first use). Returns 0 when out of memory (nothing written). */
int tp__stitch_five_draws(tp__stitch_five* f, int k, const int8_t nb[4], tp__five_draws* out);

/* The list of every index set made so far (*count indices); valid until the next call that
 * makes a set. */
const uint32_t* tp__stitch_five_indices(const tp__stitch_five* f, size_t* count);

/* Bytes of CPU memory it holds (tables, layouts and sets). */
size_t tp__stitch_five_cpu_bytes(const tp__stitch_five* f);

/* Patch `patch` of t in layout lay: writes lay->vertex_count unmoved vertices (as
 * tp_patch_vertices writes them), their unit normals and whether each is a filled void. */
void tp__stitch_five_fill(tp__stitch_five* f, const tp__five_layout* lay, const tp_terrain* t,
                          int patch, tp_vertex* vertices, float (*normals)[3], uint8_t* filled);

/* tp__stitch_five_fill for drawn node i of cut over tree (tp_cut_vertices_at_level: a side
 * that moves onto a larger neighbour's vertices is moved; --stitch add over a store). */
void tp__stitch_five_fill_node(tp__stitch_five* f, const tp__five_layout* lay,
                               const tp_tree* tree, const tp_cut* cut, size_t i, tp_vertex* v,
                               float (*normals)[3], uint8_t* filled);

/* GL: the element buffer holding the list (uploaded again when sets were made since the last
 * call; needs the GL context current, and binds GL_ELEMENT_ARRAY_BUFFER in the bound vertex
 * array); 0 when out of memory. *bytes: its size. */
unsigned int tp__stitch_five_gl_buffer(tp__stitch_five* f, size_t* bytes);

#endif
