/* tp_tin.h - the error-bounded TIN, built whole or by tiles, and the true error of any triangle
 * mesh over a grid (tin.c, tin_tiles.c, tin_measure.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_TIN_H
#define TP_TIN_H

#include "tp_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Error-bounded TIN (tin.c, issue 14; docs/tin.md): a triangulated irregular network over a
 * height grid whose vertical error is at most max_error_m at every valid sample
 *
 * Greedy insertion of the worst sample into a Delaunay triangulation (Garland & Heckbert 1995,
 * "Fast polygonal approximation of terrains and height fields", algorithm III; as mapbox's
 * delatin): start from the grid's four corners (two triangles), find each triangle's worst
 * sample by rasterising it over the grid, keep the triangles above the bound in a max-heap and
 * insert the worst one's sample until none is left above it; each insertion re-rasterises only
 * the triangles it created (split and Lawson-flipped). O(s) per rasterised triangle of s
 * samples, O(log t) per heap operation: about O(samples x log) in practice.
 *
 * The bound: the error at a valid sample is |sample height - the linear interpolation of the
 * triangle that contains it (closed) at the sample|; the build measures it at every valid sample
 * of every output triangle (exact integer inside tests, double interpolation) and returns only
 * when every one is <= max_error_m. A sample on a shared edge interpolates the same from both
 * sides (up to double rounding, about 1e-12 m).
 *
 * Grid coordinates as everywhere in this header: vertex (x, y) is sample (column, row); x, y are
 * integers (exact in the floats below up to 2^24). Triangles are counter-clockwise seen from
 * above on a north-up grid, rows running south: (b - a) x (c - a) < 0 in (column, row), i.e.
 * positive area in (column, -row). Every vertex is distinct; the triangles tile the rectangle
 * [0, width-1] x [0, height-1] exactly (watertight: each interior edge in two triangles, the
 * boundary is the grid's outline).
 *
 * Voids (NaN samples): ignored by the bound (no error is measured there) and never inserted, so
 * triangles span voids; a corner vertex that falls in a void takes the height of the nearest
 * valid sample (Chebyshev rings around the corner, the first found in row order). With
 * TP_TIN_CUT_VOIDS the TIN instead covers exactly the cells the full-resolution mesh draws (a
 * cell = four samples (x, y) .. (x+1, y+1), drawn when all four are valid): every corner of a
 * valid cell that touches (by an edge or a corner) a cell with a void is inserted first, which
 * triangulates those cells on their own, and the triangles over invalid cells are then dropped
 * with the vertices only they used. Without voids the flag changes nothing.
 *
 * Degenerate grids: width or height 1 has no area: no triangles, and every valid sample is a
 * vertex (a polyline, lossless). A grid with no valid sample gives no vertex and no triangle.
 */
typedef struct tp_tin {
    size_t vertex_count;
    float* vertices;          /* vertex_count * 3: grid x, grid y, height (m) */
    size_t triangle_count;
    uint32_t* triangles;      /* triangle_count * 3 vertex indices, counter-clockwise from above */
    float* triangle_error_m;  /* triangle_count: max error over the valid samples it covers */
    double max_error_m;       /* max of triangle_error_m (0 with no triangle) */
    size_t samples_rasterised; /* work done: samples visited measuring errors (for benches) */
} tp_tin;

/* Builds the TIN of a width x height row-major grid (NaN = void) with error <= max_error_m at
 * every valid sample (flags: 0 or TP_TIN_CUT_VOIDS), into *out (free with tp_tin_destroy). height_count must be width * height
 * (asserted). Fails (*out untouched) with TP_ERR_INVALID_ARG for width or height < 1, a grid of
 * 2^32 samples or more, max_error_m negative or not finite; TP_ERR_OUT_OF_MEMORY. Reentrant.
 * max_error_m = 0 inserts every sample that any interpolation misses (on random data every
 * sample: 2 (width-1)(height-1) triangles). */
enum { TP_TIN_CUT_VOIDS = 1u };

tp_status tp_tin_build(const float* heights, size_t height_count, int width, int height,
                       double max_error_m, unsigned flags, tp_tin** out, tp_error* err);

/* The same TIN built tile by tile (tin_tiles.c; docs/tin.md "Tiled build"), on several threads,
 * each tile with a working set of its own size: the basis for building one store node at a time.
 *
 * Tiles: tile_cells x tile_cells cells (tile_cells >= 1; larger than the grid: one tile), their
 * corners at multiples of tile_cells and at the grid's last row and column (so the last tile of a
 * row or column may be smaller, never below 1 cell); neighbouring tiles share their border
 * samples. Each tile side (the samples between two tile corners) is simplified on its own by a
 * 1-D greedy polyline: the worst valid sample is chosen until every valid sample of the side is
 * within max_error_m of the line between the chosen samples around it (the corners always
 * chosen; with TP_TIN_CUT_VOIDS the samples the void outline forces too). The tiles on both sides
 * compute the same polyline from the same samples, and inside a tile the other border samples are
 * neither measured nor inserted: each tile is then built as tp_tin_build builds a grid, without
 * reading its neighbours (but for the corners' heights, below, and two samples around the tile
 * for the void outline), and the tiles meet edge for edge.
 *
 * Output: one tp_tin with the conventions of tp_tin_build (counter-clockwise, the bound at every
 * valid sample, watertight, covering the rectangle or, with TP_TIN_CUT_VOIDS, exactly the valid
 * cells; each grid sample at most one vertex); triangle_error_m counts the border samples on a
 * triangle's edge; samples_rasterised is summed over the tiles. Vertices and triangles come in
 * tile order (rows of tiles from the top, left to right), so the output is the same whatever the
 * thread count. A corner of a tile in a void takes the nearest valid sample's height within
 * tile_cells (else the nearest such corner's), computed once on the whole grid, so all the tiles
 * around it agree. The triangles differ from tp_tin_build's near the tile borders (the borders
 * are polylines the Delaunay insertion cannot move): 0.99 to 1.03 times as many on the measured
 * DEMs (docs/PERFORMANCE.md, "Error-bounded TIN").
 *
 * threads: >= 1, or 0 for the online CPUs (at most 64); never more than the tiles. Memory: the
 * tiles' outputs until the merge, and per thread one tile's build. Grids of width or height 1 and
 * grids without a valid sample give tp_tin_build's answer. Fails (*out untouched) as tp_tin_build
 * does, and with TP_ERR_INVALID_ARG for tile_cells < 1, threads < 0 or over 2^30 tiles.
 * Reentrant. */
tp_status tp_tin_build_tiled(const float* heights, size_t height_count, int width, int height,
                             double max_error_m, unsigned flags, int tile_cells, int threads,
                             tp_tin** out, tp_error* err);

/* One tile of that tiling built on its own, from a window of the grid: what a caller that never
 * holds the whole grid (a store export, one window of leaves at a time) builds tile by tile.
 *
 * The tile is tile_w x tile_h samples (>= 2 each), its first sample at (tile_x, tile_y) of the
 * window; the window is the tile widened by 2 samples on each side, clipped to the grid only
 * (tile_x, tile_y in 0..2, and 0..2 samples right of and below it): the void outline rule reads
 * them, and a window clipped anywhere else than at the grid's edge gives another answer than the
 * whole grid. Rows are stride floats apart. corner_z: the heights of the tile's corners (top-left,
 * top-right, bottom-left, bottom-right) used where the corner sample is void and as the ends of
 * its sides' polylines, the same for every tile that shares the corner; required without
 * TP_TIN_CUT_VOIDS, NULL allowed with it (the corners' own samples are used: triangles touching
 * a void corner are cut anyway). Tiles built with the same corner heights (or none) from the
 * same samples meet edge for edge, as in tp_tin_build_tiled.
 *
 * Output: the tile's TIN in the tile's own coordinates (vertex (0, 0) is the tile's first
 * sample), or *out = NULL with TP_OK when the cut leaves nothing (no valid sample). Fails with
 * TP_ERR_INVALID_ARG for a tile that does not fit its window as above, a bound as tp_tin_build
 * refuses, or no corner heights without the cut; TP_ERR_OUT_OF_MEMORY. Reentrant. */
tp_status tp_tin_build_tile(const float* window, size_t stride, int win_w, int win_h, int tile_x,
                            int tile_y, int tile_w, int tile_h, const float corner_z[4],
                            double max_error_m, unsigned flags, tp_tin** out, tp_error* err);

/* Frees a TIN; NULL is allowed. */
void tp_tin_destroy(tp_tin* tin);

/* ---------------------------------------------------------------------------------------------
 * True error of a triangle mesh over a height grid (tin_measure.c, issue 14): the checker that
 * `bench --static` applies to every mesher's output (ours, delatin's, martini's), independent of
 * how the mesh was built (it shares no code with tin.c)
 *
 * The mesh: vertices at integer grid positions (x = column, y = row, as in "Error-bounded TIN"),
 * each with a height, and triangles of three vertex indices, of either orientation. Every
 * triangle is rasterised row by row over the grid: the span of each row is solved exactly from
 * the integer edge equations (the closed triangle: samples on an edge or a vertex are inside),
 * and each valid sample inside gets the barycentric interpolation of the three vertex heights,
 * with weights from exact int64 orientations. A sample inside several triangles (on shared
 * edges, or where a broken mesh overlaps) counts with its largest error. NaN samples (voids) are
 * ignored. Triangles of zero area cover nothing (counted apart).
 */
typedef struct tp_tin_measure_result {
    double max_error_m;          /* max |sample height - interpolation| over covered valid samples
                                    (0 when none is covered) */
    int worst_x, worst_y;        /* a sample where max_error_m is reached (-1, -1 when none) */
    double rms_error_m;          /* over covered valid samples, each once (its largest error) */
    size_t covered_samples;      /* valid samples inside at least one triangle */
    size_t uncovered_samples;    /* valid samples no triangle covers (0 for a mesh of the whole
                                    valid grid) */
    size_t degenerate_triangles; /* triangles of zero area (skipped) */
} tp_tin_measure_result;

/* Measures the mesh (vertices: vertex_count * 3 floats x, y, height; triangles: triangle_count
 * * 3 indices) against the width x height row-major grid heights (height_count = width *
 * height). Fails (*out untouched) with TP_ERR_INVALID_ARG for a grid below 1x1 or of 2^32
 * samples or more, height_count != width * height, a vertex whose x or y is not an integer
 * inside the grid or whose height is not finite, a triangle index >= vertex_count, NULL arrays
 * with a non-zero count; TP_ERR_OUT_OF_MEMORY (4 bytes per sample are allocated). Reentrant.
 * Takes O(samples covered) time plus O(rows spanned) per triangle. */
tp_status tp_tin_measure(const float* heights, size_t height_count, int width, int height,
                         const float* vertices, size_t vertex_count, const uint32_t* triangles,
                         size_t triangle_count, tp_tin_measure_result* out, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_TIN_H */
