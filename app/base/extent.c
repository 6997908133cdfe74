/* extent.c - the extents of a render grid (see extent.h). */
#include "extent.h"

#include <math.h>
#include <stdlib.h>

static int cmp_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

int tp_geo_extent(const tp_georef* g, int w, int h, double out[4], int* crosses, tp_error* why)
{
    *crosses = 0;
    if (!tp_georef_has_geo(g))
        return 0;
    size_t cap = 2 * (size_t)w + 2 * (size_t)h, n = 0;
    double* lons = malloc(cap * sizeof *lons);
    if (!lons)
        return 0;
    out[0] = INFINITY, out[2] = -INFINITY;
    for (size_t i = 0; i < cap; i++) {
        double x, y; /* the bottom and top rows, then the left and right columns */
        if (i < 2 * (size_t)w)
            x = (double)(i % w), y = i < (size_t)w ? 0 : h - 1;
        else
            x = (i - 2 * (size_t)w) < (size_t)h ? 0 : w - 1, y = (double)((i - 2 * (size_t)w) % h);
        double e, nn, lat, lon;
        tp_georef_grid_to_proj(g, x, y, &e, &nn);
        if (tp_georef_proj_to_geo(g, e, nn, &lat, &lon, why) != TP_OK) {
            free(lons);
            return -1;
        }
        out[0] = fmin(out[0], lat), out[2] = fmax(out[2], lat);
        lons[n++] = remainder(lon, 360.0);
    }
    /* A pole inside the grid: the latitudes reach it and every longitude is covered. */
    for (int pole = -1; pole <= 1; pole += 2) {
        double e, nn, x, y;
        if (tp_georef_geo_to_proj(g, 90.0 * pole, 0, &e, &nn, NULL) != TP_OK)
            continue;
        tp_georef_proj_to_grid(g, e, nn, &x, &y);
        if (x >= 0 && y >= 0 && x <= w - 1 && y <= h - 1) {
            out[pole < 0 ? 0 : 2] = 90.0 * pole;
            out[1] = -180, out[3] = 180;
            free(lons);
            return 1;
        }
    }
    /* The longitudes: the complement of the widest gap between neighbours on the circle. */
    qsort(lons, n, sizeof *lons, cmp_double);
    double gap = lons[0] + 360.0 - lons[n - 1]; /* the gap across the antimeridian */
    out[1] = lons[0], out[3] = lons[n - 1];
    for (size_t i = 1; i < n; i++) {
        if (lons[i] - lons[i - 1] > gap) {
            gap = lons[i] - lons[i - 1];
            out[1] = lons[i], out[3] = lons[i - 1];
            *crosses = 1;
        }
    }
    free(lons);
    return 1;
}

/* Projected extent of the drawn grid's sample centres: min E, min N, max E, max N. */
void tp_proj_extent(const tp_georef* g, int w, int h, double out[4])
{
    double e0, n0, e1, n1;
    tp_georef_grid_to_proj(g, 0, 0, &e0, &n0);
    tp_georef_grid_to_proj(g, w - 1, h - 1, &e1, &n1);
    out[0] = fmin(e0, e1), out[1] = fmin(n0, n1), out[2] = fmax(e0, e1), out[3] = fmax(n0, n1);
}

