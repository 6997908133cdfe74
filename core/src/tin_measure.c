/* tin_measure.c - the true vertical error of a triangle mesh over a height grid (tp_tin_measure,
 * documented in tp_core.h, "True error of a triangle mesh"): each triangle rasterised row by row
 * with spans solved exactly from its integer edge equations, each valid sample inside (closed)
 * compared with the barycentric interpolation of the vertex heights, weights from exact int64
 * orientations. Shares nothing with tin.c, whose output it checks. */
#include "internal.h"
#include "tp_tin.h"

#include <math.h>
#include <stdlib.h>

/* orient(u, v, p) = (v - u) x (p - u); exact for grids under 2^32 samples (|dx| < width,
 * |dy| < height, so each product is below 2^32). */
static int64_t orient(int64_t ux, int64_t uy, int64_t vx, int64_t vy, int64_t px, int64_t py)
{
    return (vx - ux) * (py - uy) - (vy - uy) * (px - ux);
}

static int64_t floor_div(int64_t n, int64_t d) /* d > 0 */
{
    int64_t q = n / d;
    return (n % d != 0 && n < 0) ? q - 1 : q;
}

/* Narrows [*x0, *x1] to the x where the edge u -> v has p = (x, y) on its left or on it
 * (orient(u, v, p) >= 0): a linear function A x + B of x on row y. */
static void clip_span(int64_t ux, int64_t uy, int64_t vx, int64_t vy, int64_t y, int64_t* x0,
                      int64_t* x1)
{
    int64_t a = -(vy - uy), b = (vx - ux) * (y - uy) + (vy - uy) * ux;
    if (a > 0) { /* x >= ceil(-b / a) */
        int64_t lo = -floor_div(b, a);
        *x0 = lo > *x0 ? lo : *x0;
    } else if (a < 0) { /* x <= floor(b / -a) */
        int64_t hi = floor_div(b, -a);
        *x1 = hi < *x1 ? hi : *x1;
    } else if (b < 0) {
        *x1 = *x0 - 1; /* the row is outside this edge */
    }
}

tp_status tp_tin_measure(const float* heights, size_t height_count, int width, int height,
                         const float* vertices, size_t vertex_count, const uint32_t* triangles,
                         size_t triangle_count, tp_tin_measure_result* out, tp_error* err)
{
    if (width < 1 || height < 1)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tin measure: expected a grid of at least 1x1, got %dx%d", width, height);
    const uint64_t n = (uint64_t)width * (uint64_t)height;
    if (n >= ((uint64_t)1 << 32))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tin measure: a %dx%d grid has 2^32 samples or more", width, height);
    if (height_count != n || !heights || !out)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tin measure: expected %llu heights for a %dx%d grid, got %zu",
                        (unsigned long long)n, width, height, height_count);
    if ((vertex_count && !vertices) || (triangle_count && !triangles))
        return tp__fail(err, TP_ERR_INVALID_ARG, "tin measure: NULL vertex or triangle array");
    for (size_t i = 0; i < vertex_count; i++) {
        const float* v = vertices + 3 * i;
        if (!(v[0] >= 0 && v[0] <= width - 1 && v[0] == floorf(v[0]) && v[1] >= 0 &&
              v[1] <= height - 1 && v[1] == floorf(v[1]) && isfinite(v[2])))
            return tp__fail(err, TP_ERR_INVALID_ARG,
                            "tin measure: vertex %zu (%g, %g, %g) is not at an integer sample "
                            "of the %dx%d grid with a finite height",
                            i, v[0], v[1], v[2], width, height);
    }
    for (size_t i = 0; i < 3 * triangle_count; i++)
        if (triangles[i] >= vertex_count)
            return tp__fail(err, TP_ERR_INVALID_ARG,
                            "tin measure: triangle %zu names vertex %u of %zu", i / 3,
                            triangles[i], vertex_count);
    /* each sample's largest error; -1: not covered */
    float* worst = malloc((size_t)n * sizeof *worst);
    if (!worst)
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tin measure: out of memory (%llu samples)",
                        (unsigned long long)n);
    for (size_t s = 0; s < n; s++)
        worst[s] = -1.0f;
    tp_tin_measure_result r = {.worst_x = -1, .worst_y = -1};
    double mx = -1.0;
    for (size_t t = 0; t < triangle_count; t++) {
        const float* pa = vertices + 3 * (size_t)triangles[3 * t];
        const float* pb = vertices + 3 * (size_t)triangles[3 * t + 1];
        const float* pc = vertices + 3 * (size_t)triangles[3 * t + 2];
        int64_t ax = (int64_t)pa[0], ay = (int64_t)pa[1], bx = (int64_t)pb[0],
                by = (int64_t)pb[1], cx = (int64_t)pc[0], cy = (int64_t)pc[1];
        double za = pa[2], zb = pb[2], zc = pc[2];
        int64_t area = orient(ax, ay, bx, by, cx, cy);
        if (area == 0) {
            r.degenerate_triangles++;
            continue;
        }
        if (area < 0) { /* make it counter-clockwise in (column, row): inside = all >= 0 */
            int64_t tx = bx, ty = by;
            double tz = zb;
            bx = cx, by = cy, zb = zc;
            cx = tx, cy = ty, zc = tz;
            area = -area;
        }
        int64_t ylo = ay < by ? (ay < cy ? ay : cy) : (by < cy ? by : cy);
        int64_t yhi = ay > by ? (ay > cy ? ay : cy) : (by > cy ? by : cy);
        int64_t xlo = ax < bx ? (ax < cx ? ax : cx) : (bx < cx ? bx : cx);
        int64_t xhi = ax > bx ? (ax > cx ? ax : cx) : (bx > cx ? bx : cx);
        const double inv = 1.0 / (double)area;
        for (int64_t y = ylo; y <= yhi; y++) {
            int64_t x0 = xlo, x1 = xhi;
            clip_span(bx, by, cx, cy, y, &x0, &x1); /* weight of a */
            clip_span(cx, cy, ax, ay, y, &x0, &x1); /* of b */
            clip_span(ax, ay, bx, by, y, &x0, &x1); /* of c */
            for (int64_t x = x0; x <= x1; x++) {
                int64_t la = orient(bx, by, cx, cy, x, y), lb = orient(cx, cy, ax, ay, x, y);
                int64_t lc = area - la - lb;
                if (la < 0 || lb < 0 || lc < 0)
                    continue; /* cannot happen with exact spans; kept as a guard */
                size_t s = (size_t)y * (size_t)width + (size_t)x;
                float h = heights[s];
                if (h != h)
                    continue;
                double zi = ((double)la * za + (double)lb * zb + (double)lc * zc) * inv;
                double e = fabs((double)h - zi);
                if ((float)e > worst[s])
                    worst[s] = (float)e;
                if (e > mx) {
                    mx = e;
                    r.worst_x = (int)x;
                    r.worst_y = (int)y;
                }
            }
        }
    }
    double sum2 = 0.0;
    for (size_t s = 0; s < n; s++) {
        if (heights[s] != heights[s])
            continue;
        if (worst[s] < 0) {
            r.uncovered_samples++;
        } else {
            r.covered_samples++;
            sum2 += (double)worst[s] * worst[s];
        }
    }
    free(worst);
    r.max_error_m = mx > 0 ? mx : 0.0;
    r.rms_error_m = r.covered_samples ? sqrt(sum2 / (double)r.covered_samples) : 0.0;
    *out = r;
    return TP_OK;
}
