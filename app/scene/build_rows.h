/*
 * build_rows.h - the rows of the render grid as a store build reads them (store_build.c): band
 * by band from the mosaic, and the range pass that reads them first when the height range is
 * not known beforehand (the step, written in the store's header first, follows from it).
 *
 * The range pass reads the grid in the build pass's own bands (the same calls to the mosaic, so
 * the same heights and filled flags) and, when the grid fits in a quarter of the build's memory
 * (5 bytes a sample: the height and its flag), keeps it: the build pass then takes its bands
 * from memory instead of warping, masking and filling every row again. A 3601x3601 tile warped
 * to UTM holds 92 MB there. Larger grids are read twice, as before.
 */
#ifndef TP_APP_BUILD_ROWS_H
#define TP_APP_BUILD_ROWS_H

#include "tp_io.h"

#include <stddef.h>
#include <stdint.h>

typedef struct tp_build_rows {
    tp_mosaic* m;
    int width, height; /* the mosaic's grid */
    int ps;            /* 2^n: band r holds rows r*ps .. (r+1)*ps */
    int fill;          /* voids are filled: flags are read beside the heights */
    /* the grid held by the range pass (NULL: read from the mosaic) */
    float* held;
    uint8_t* held_filled;
} tp_build_rows;

/* The rows band r (0 .. rows-1 of the tree geometry) reads from the source grid: *y0 and *count
 * (0 when the band lies wholly in the padding). The first row of band r > 0 is the last of band
 * r - 1, kept, so each source row is read once. */
void tp_build_rows_band(const tp_build_rows* br, int r, int* y0, int* count);

/* Rows y0 .. y0+count-1: heights (count * width floats, NaN not drawn) and, when voids are
 * filled, their flags (count * width bytes; filled may be NULL otherwise), from the held grid or
 * the mosaic. */
tp_status tp_build_rows_read(tp_build_rows* br, int y0, int count, float* heights,
                             uint8_t* filled, tp_error* err);

/* What the range pass saw. */
typedef struct tp_build_range {
    double lo, hi; /* heights, metres (NaN skipped) */
    size_t valid;
    int integral;  /* every height a whole number */
} tp_build_range;

/* The range pass over bands of bands rows of the tree (tp_build_rows_band), with progress
 * ("range") on stderr unless quiet; holds the grid when hold_bytes allows (5 bytes a sample,
 * 4 without void filling). rows and filled: one band's buffers ((ps + 1) * width). */
tp_status tp_build_rows_range(tp_build_rows* br, int bands, size_t hold_bytes, int quiet,
                              float* rows, uint8_t* filled, tp_build_range* out, tp_error* err);

/* Frees the held grid. */
void tp_build_rows_release(tp_build_rows* br);

#endif /* TP_APP_BUILD_ROWS_H */
