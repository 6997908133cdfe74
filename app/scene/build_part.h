/*
 * build_part.h - a store built in parts (docs/distribution.md, "A build in parts"): what
 * `terrapatch build --part I/N` (store_build.c) and `terrapatch merge` (store_merge.c) share:
 * the split of the hierarchy, the part's record in its store's notes, and the store's notes.
 *
 * The split: at a scale S, the rows of scale-S nodes are cut into N runs; part I holds the
 * leaf rows of its run (the last part also the rows below the last whole scale-S node) over the
 * whole width, so every node of scale <= S lies in exactly one part, and a part is itself a
 * store: the strip of the grid from its first leaf row to its last (sharing its first sample
 * row with the part above), built as any grid is. Its nodes of scale <= S are, meta and bytes,
 * those of the whole grid's build; merge computes the nodes above S from the parts' scale-S
 * nodes, as the band builder does, and copies the rest.
 */
#ifndef TP_APP_BUILD_PART_H
#define TP_APP_BUILD_PART_H

#include "store_build.h"

#include <stddef.h>
#include <stdint.h>

/* One part of a split. */
typedef struct tp_build_part {
    int index, count;     /* 1 .. count */
    int split_scale;      /* S */
    int band0, band1;     /* its leaf rows: band0 .. band1 - 1 of the whole tree */
} tp_build_part;

/* Part index of count over the whole tree g: S is the coarsest scale with at least 4 count
 * rows of nodes (for parts within a quarter of each other's size), else with count. 1, or 0
 * with err's message when g has fewer leaf rows than count. */
int tp_build_part_plan(const tp_tree_geometry* g, int index, int count, tp_build_part* out,
                       tp_error* err);

/* The part's strip of the grid: its geometry (the whole width, from the part's first sample row
 * to its last) into *strip; returns its first sample row in the whole grid. */
int tp_build_part_strip(const tp_tree_geometry* g, const tp_build_part* p,
                        tp_tree_geometry* strip);

/* What a part must share with the others to be merged with them: the sources (absolute path,
 * size, modification time), --fill-from likewise, and every option that changes a height or a
 * node (patch, CRS, resampling, memory, void filling, unit, step, range, gaps), hashed (FNV-1a, 64
 * bits). 1, or 0 with err naming a source that cannot be found. */
int tp_build_part_key(const tp_build_options* o, uint64_t* key, tp_error* err);

/* The part's record, the first lines of its store's notes. */
typedef struct tp_build_part_record {
    tp_build_part part;
    int width, height, patch; /* the whole grid, its node size */
    uint64_t key;
    size_t filled;                    /* filled samples of the part's rows */
    size_t first_valid, first_filled; /* of its first row, shared with the part above */
} tp_build_part_record;

/* The record's lines (fixed length whatever the counts) followed by the notes; NULL when out of
 * memory. */
char* tp_build_part_notes(const tp_build_part_record* r, const char* notes);
/* Reads the record at the start of notes into *r, and where the notes after it begin; 0 when
 * notes do not start with a part's record. */
int tp_build_part_parse(const char* notes, tp_build_part_record* r, const char** rest);

/* A store's notes: the sources, the mosaic's notes, then the void filling with `filled` samples,
 * its count padded to a fixed length (tp_store_writer_set_notes replaces them at commit). NULL
 * when out of memory. */
char* tp_build_notes(const tp_build_options* o, const char* mosaic_notes, size_t filled);
/* A copy of notes made by tp_build_notes with the count of filled samples set to `filled` (the
 * same length); NULL when out of memory. */
char* tp_build_notes_refill(const char* notes, size_t filled);

#endif /* TP_APP_BUILD_PART_H */
