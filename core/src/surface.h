/* surface.h - the split-cell surface over any grid of heights, inline (terrain.c, surface.c,
 * cut_query.c). */
#ifndef TP_CORE_SURFACE_H
#define TP_CORE_SURFACE_H

#include "internal.h"

/* ---- the split-cell surface (terrain.c's tp_terrain_height_at, surface.c's tp_grid_height_at)
 * ----
 *
 * Every cell (c, r)-(c+1, r+1) is split along the diagonal from (c+1, r) to (c, r+1), as the
 * strips draw it. height(grid, x, y) gives a sample's height, NaN where none (outside, nodata).
 * Inline, so that each caller gets its own copy with the sampler inlined. */
typedef double (*tp__height_fn)(const void* grid, int x, int y);

/* One triangle of cell (cx, cy) at offsets fx, fy in [0, 1]; NaN if a vertex has no height. */
static inline double tp__half_cell(tp__height_fn height, const void* grid, int cx, int cy,
                                   double fx, double fy, int upper)
{
    if (cx < 0 || cy < 0)
        return NAN;
    double a, b, c;
    if (!upper) {
        a = height(grid, cx, cy), b = height(grid, cx + 1, cy), c = height(grid, cx, cy + 1);
        if (isnan(a) || isnan(b) || isnan(c))
            return NAN;
        return a + fx * (b - a) + fy * (c - a);
    }
    a = height(grid, cx + 1, cy + 1), b = height(grid, cx, cy + 1), c = height(grid, cx + 1, cy);
    if (isnan(a) || isnan(b) || isnan(c))
        return NAN;
    return a + (1 - fx) * (b - a) + (1 - fy) * (c - a);
}

/* Either triangle of the cell that contains the point (both on the diagonal). */
static inline double tp__cell_height(tp__height_fn height, const void* grid, int cx, int cy,
                                     double fx, double fy)
{
    double z = fx + fy <= 1 ? tp__half_cell(height, grid, cx, cy, fx, fy, 0) : NAN;
    return isnan(z) && fx + fy >= 1 ? tp__half_cell(height, grid, cx, cy, fx, fy, 1) : z;
}

/* Height of the surface of a w x h grid at (x, y); NaN outside the grid or where no triangle
 * with three heights contains the point (a point on an edge or a vertex lies on every triangle
 * that touches it, so one drawn triangle there is enough). */
static inline double tp__split_height(tp__height_fn height, const void* grid, int w, int h,
                                      double x, double y)
{
    if (!(x >= 0 && y >= 0 && x <= w - 1 && y <= h - 1))
        return NAN; /* also NaN inputs */
    int cx = (int)x, cy = (int)y;
    cx = cx > w - 2 ? w - 2 : cx;
    cy = cy > h - 2 ? h - 2 : cy;
    double fx = x - cx, fy = y - cy;
    double z = tp__cell_height(height, grid, cx, cy, fx, fy);
    if (isnan(z) && fx == 0)
        z = tp__cell_height(height, grid, cx - 1, cy, 1, fy);
    if (isnan(z) && fy == 0)
        z = tp__cell_height(height, grid, cx, cy - 1, fx, 1);
    if (isnan(z) && fx == 0 && fy == 0)
        z = tp__cell_height(height, grid, cx - 1, cy - 1, 1, 1);
    return z;
}

#endif
