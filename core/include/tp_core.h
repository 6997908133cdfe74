/*
 * tp_core.h - the terrapatch core: a quantised height grid tiled into overlapping
 * (2^n+1)^2 patches, per-patch level of detail, shared degenerate triangle strips,
 * crack removal by moving vertices, AABB frustum culling and O(1) height queries.
 *
 * Pure C11 over libc and libm. This header is the documentation of the core.
 *
 * Based on:
 *   J. Vanek, B. Jezek, "Real-Time Terrain Visualization on PC", WSCG 2004
 *     (patches, levels, distance LoD, degenerate strips, moving vertices, AABB culling)
 *   A. Brodersen, "Real-Time Visualization of Large Textured Terrains", 2005
 *     (per-level maximum error delta_k, screen-space error threshold tau, < 2.5 bytes per sample)
 *
 * Conventions used everywhere in this header:
 *   - Grid coordinates (x, y) are (column, row) of the fitted grid; integer values are sample
 *     centres. Row 0 is the first row of the raster (north for a north-up DEM).
 *   - World coordinates are the DEM's projected CRS: easting, northing (metres for a projected
 *     DEM) and height in metres, as doubles. Sample (x, y) lies at
 *     E = gt[0] + (x + 0.5) * gt[1],  N = gt[3] + (y + 0.5) * gt[5]   (GDAL geotransform).
 *   - Levels: k = n is full resolution, k = 0 is the 2x2 patch (as in Vanek & Jezek).
 *   - Heights of samples that are not drawn (nodata, padding) and queries outside the grid are NaN.
 *
 * Failure: one convention for every function below (STYLE.md section 4).
 *   - Caller bugs are assert()ed at the top of the function, not reported: a NULL pointer where
 *     the function's comment does not allow NULL, a patch index outside 0..patch_count-1, a
 *     level k outside 0..n (0..TP_MAX_N where no terrain is involved), a capacity smaller than
 *     the size the comment gives. Check these before the call; under NDEBUG they are undefined.
 *   - Bad data and invalid values that can come from a user or a file (a number outside its
 *     documented range, NaN where a number is needed, a malformed grid) and running out of
 *     memory are reported: such a function returns tp_status, TP_OK on success, and delivers
 *     its results through out-parameters that it writes ONLY on success. On failure its inputs
 *     and outputs are left as they were and nothing is leaked. A trailing tp_error* err, where
 *     there is one, receives a one-line message on failure; err may be NULL.
 *   - A function that returns anything else (void, a count, a height, a class, a 1/0 answer)
 *     cannot fail once its arguments pass the asserts.
 *   - Queries return NaN for "no surface here" (nodata, padding, outside the grid, nothing
 *     drawn there), and tp_terrain_sample_class returns TP_SAMPLE_OUTSIDE outside the grid;
 *     that is an answer, not a failure. So is the 0 of a yes/no function (tp_camera_project,
 *     tp_selection_visible, tp_selection_dirty, tp_selection_keep_above answer 1 or 0).
 * Each comment below says what the function returns and what makes it fail; it repeats none of
 * this, only what differs (a pointer that may be NULL, a further condition).
 */
#ifndef TP_CORE_H
#define TP_CORE_H

/* The declarations live in one header per concept beside this one (as libuv's uv.h includes
 * those of uv/), each compiling on its own and including the concepts it builds on; callers
 * include this header, which includes them all:
 *   tp_base.h       version, limits, status and errors, the allocator
 *   tp_terrain.h    triangle strips, the resident terrain and its queries, patches, crack removal
 *   tp_lod.h        level of detail: modes, parameters, the distance formula
 *   tp_camera.h     camera maths and frustum culling
 *   tp_selection.h  a terrain's levels, visibility, measures and queries per frame
 *   tp_tree.h       the hierarchy: tree geometry, node metas and masks, builder, run time
 *   tp_cut.h        the drawn cut over a tree, and queries on the tree and the cut
 *   tp_viewshed.h   viewsheds
 *   tp_los.h        line of sight
 *   tp_tin.h        the error-bounded TIN (whole, tiled) and the mesh error checker
 *   tp_qmesh.h      Cesium quantized-mesh tiles: the geographic scheme, the encoder
 *   tp_clipmap.h    clip windows over image pyramids, texture levels
 *   tp_light.h      shadows, the sun over a day, light times
 *   tp_pgm.h        Persistent Grid Mapping
 */
#include "tp_base.h"
#include "tp_terrain.h"
#include "tp_lod.h"
#include "tp_camera.h"
#include "tp_selection.h"
#include "tp_tree.h"
#include "tp_cut.h"
#include "tp_viewshed.h"
#include "tp_los.h"
#include "tp_tin.h"
#include "tp_qmesh.h"
#include "tp_clipmap.h"
#include "tp_light.h"
#include "tp_pgm.h"

#endif /* TP_CORE_H */
