/* triangle_raster.c - rasterises triangles onto the sample lattice: visits the grid samples
 * covered by a triangle (closed), with the linearly interpolated height there. Used to measure
 * errors exactly: grid positions are integers, so the inside test uses exact integer edge
 * functions and only the interpolation is floating. */
#include "lattice.h"

static int64_t edge(const int32_t a[2], const int32_t b[2], int64_t x, int64_t y)
{
    return ((int64_t)b[0] - a[0]) * (y - a[1]) - ((int64_t)b[1] - a[1]) * (x - a[0]);
}

void tp__raster_triangle(const int32_t a[2], const int32_t b[2], const int32_t c[2], double za,
                         double zb, double zc, tp__sample_fn fn, void* user)
{
    const int32_t all[4] = {INT32_MIN, INT32_MIN, INT32_MAX, INT32_MAX};
    tp__raster_triangle_clip(a, b, c, za, zb, zc, all, fn, user);
}

void tp__raster_triangle_clip(const int32_t a[2], const int32_t b[2], const int32_t c[2],
                              double za, double zb, double zc, const int32_t clip[4],
                              tp__sample_fn fn, void* user)
{
    assert(a && b && c && clip && fn);
    int64_t area = edge(a, b, c[0], c[1]);
    if (area == 0)
        return;
    int32_t x0 = a[0], x1 = a[0], y0 = a[1], y1 = a[1];
    const int32_t* v[2] = {b, c};
    for (int i = 0; i < 2; i++) {
        x0 = v[i][0] < x0 ? v[i][0] : x0;
        x1 = v[i][0] > x1 ? v[i][0] : x1;
        y0 = v[i][1] < y0 ? v[i][1] : y0;
        y1 = v[i][1] > y1 ? v[i][1] : y1;
    }
    x0 = x0 > clip[0] ? x0 : clip[0];
    y0 = y0 > clip[1] ? y0 : clip[1];
    x1 = x1 < clip[2] ? x1 : clip[2];
    y1 = y1 < clip[3] ? y1 : clip[3];
    double inv = 1.0 / (double)area;
    /* Barycentric weights times the signed area; inside when all share its sign. Each edge
     * function changes by a constant per step in x. */
    int64_t sa = -((int64_t)c[1] - b[1]), sb = -((int64_t)a[1] - c[1]), sc = -((int64_t)b[1] - a[1]);
    int64_t sign = area > 0 ? 1 : -1;
    for (int32_t y = y0; y <= y1; y++) {
        int64_t wa = edge(b, c, x0, y), wb = edge(c, a, x0, y), wc = edge(a, b, x0, y);
        for (int32_t x = x0; x <= x1; x++, wa += sa, wb += sb, wc += sc) {
            if (wa * sign < 0 || wb * sign < 0 || wc * sign < 0)
                continue;
            double z = ((double)wa * za + (double)wb * zb + (double)wc * zc) * inv;
            fn(x, y, z, user);
        }
    }
}

void tp_triangle_rasterize(const int32_t a[2], const int32_t b[2], const int32_t c[2], double za,
                           double zb, double zc, tp_sample_visitor visit, void* user)
{
    tp__raster_triangle(a, b, c, za, zb, zc, visit, user);
}
