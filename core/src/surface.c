/*
 * surface.c - tp_grid_height_at: the split-cell surface of a plain float grid, the same
 * triangles tp_terrain_height_at uses on a terrain (surface.h's tp__split_height), for code
 * that has heights before a terrain exists (io's render grid measures its warp error with it).
 */
#include "surface.h"
#include "tp_terrain.h"

#include <assert.h>

typedef struct float_grid {
    const float* z;
    int w, h;
} float_grid;

static double float_height(const void* grid, int x, int y)
{
    const float_grid* g = (const float_grid*)grid;
    if (x < 0 || y < 0 || x >= g->w || y >= g->h)
        return NAN;
    return g->z[(size_t)y * (size_t)g->w + (size_t)x];
}

double tp_grid_height_at(const float* heights, size_t height_count, int width, int height, double x,
                         double y)
{
    assert(width >= 0 && height >= 0 && height_count == (size_t)width * (size_t)height);
    assert(heights || height_count == 0);
    (void)height_count; /* only checked */
    float_grid g = {heights, width, height};
    return tp__split_height(float_height, &g, width, height, x, y);
}
