/*
 * tp_test_geom.h - independent geometry for the core tests: exact orientation tests on grid
 * positions, the documented full-resolution triangle split, a rasteriser for the triangles a
 * patch draws, and small terrain builders. Everything here is computed from the header's
 * definitions, never from the implementation's internals.
 */
#ifndef TP_TEST_GEOM_H
#define TP_TEST_GEOM_H

#include "tp_test.h"

/* Twice the signed area of (a, b, c) in (column, row) coordinates: < 0 is clockwise there, the
 * orientation tp_core.h documents for every real triangle. */
static inline int64_t tpt_orient(int64_t ax, int64_t ay, int64_t bx, int64_t by, int64_t cx,
                                 int64_t cy)
{
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

/* Height at (x, y) of the full-resolution surface through the four samples around it, with the
 * documented split of cell (c, r)-(c+1, r+1) along the diagonal (c+1, r)-(c, r+1).
 * h(c, r) is given by the callback. */
typedef double (*tpt_sample_fn)(const void* user, int x, int y);
static inline double tpt_split_height(tpt_sample_fn h, const void* user, int width, int height,
                                      double x, double y)
{
    int c = (int)floor(x), r = (int)floor(y);
    double fx, fy;
    if (c >= width - 1)
        c = width - 2; /* the last column/row belongs to the cell before it */
    if (r >= height - 1)
        r = height - 2;
    if (c < 0)
        c = 0;
    if (r < 0)
        r = 0;
    fx = x - c;
    fy = y - r;
    if (fx + fy <= 1.0) { /* upper-left half: (c, r), (c+1, r), (c, r+1) */
        double h00 = h(user, c, r), h10 = h(user, c + 1, r), h01 = h(user, c, r + 1);
        return h00 + fx * (h10 - h00) + fy * (h01 - h00);
    } else { /* lower-right half: (c+1, r+1), (c, r+1), (c+1, r) */
        double h11 = h(user, c + 1, r + 1), h01 = h(user, c, r + 1), h10 = h(user, c + 1, r);
        return h11 + (1.0 - fx) * (h01 - h11) + (1.0 - fy) * (h10 - h11);
    }
}

static inline double tpt_terrain_sample_cb(const void* user, int x, int y)
{
    return tp_terrain_sample((const tp_terrain*)user, x, y);
}

/* Heights of the drawn triangles of one patch at every sample of the patch square.
 * x0, y0: the patch's first sample; side = 2^n + 1. out[(y - y0) * side + (x - x0)] is the
 * barycentric interpolation of the vertex heights (as float z_m) of a triangle containing the
 * sample (boundary included), NaN where no triangle covers it. Where several triangles cover a
 * sample they must agree (the surface is continuous); the largest disagreement is returned, so a
 * caller can check it is ~0. cover[] (optional) counts the triangles containing each sample. */
static inline double tpt_patch_surface(const tp_vertex* v, const uint32_t* tri, size_t tri_count,
                                       int x0, int y0, int side, double* out, int* cover)
{
    size_t i;
    int j;
    double worst = 0.0;
    for (j = 0; j < side * side; ++j) {
        out[j] = NAN;
        if (cover)
            cover[j] = 0;
    }
    for (i = 0; i < tri_count; ++i) {
        const tp_vertex *a = &v[tri[3 * i]], *b = &v[tri[3 * i + 1]], *c = &v[tri[3 * i + 2]];
        int64_t area = tpt_orient(a->x, a->y, b->x, b->y, c->x, c->y);
        int minx, maxx, miny, maxy, x, y;
        if (area == 0)
            continue; /* reported by the callers' own checks */
        minx = a->x < b->x ? a->x : b->x;
        minx = minx < c->x ? minx : c->x;
        maxx = a->x > b->x ? a->x : b->x;
        maxx = maxx > c->x ? maxx : c->x;
        miny = a->y < b->y ? a->y : b->y;
        miny = miny < c->y ? miny : c->y;
        maxy = a->y > b->y ? a->y : b->y;
        maxy = maxy > c->y ? maxy : c->y;
        if (minx < x0)
            minx = x0;
        if (miny < y0)
            miny = y0;
        if (maxx > x0 + side - 1)
            maxx = x0 + side - 1;
        if (maxy > y0 + side - 1)
            maxy = y0 + side - 1;
        for (y = miny; y <= maxy; ++y) {
            for (x = minx; x <= maxx; ++x) {
                /* barycentric weights as exact integer areas */
                int64_t wa = tpt_orient(x, y, b->x, b->y, c->x, c->y);
                int64_t wb = tpt_orient(a->x, a->y, x, y, c->x, c->y);
                int64_t wc = tpt_orient(a->x, a->y, b->x, b->y, x, y);
                double z;
                int idx = (y - y0) * side + (x - x0);
                if (area < 0 ? (wa > 0 || wb > 0 || wc > 0) : (wa < 0 || wb < 0 || wc < 0))
                    continue;
                z = ((double)wa * a->z_m + (double)wb * b->z_m + (double)wc * c->z_m) /
                    (double)area;
                if (cover)
                    cover[idx]++;
                if (isnan(out[idx])) {
                    out[idx] = z;
                } else {
                    double d = fabs(out[idx] - z);
                    if (d > worst)
                        worst = d;
                }
            }
        }
    }
    return worst;
}

/* ---------------------------------------------------------------------------------------------
 * Terrain builders
 */

/* A seeded rough surface: a few smooth waves plus white noise of amplitude `noise`, around
 * `base`. With integer_valued, every height is rounded to a whole metre. */
static inline void tpt_rough_heights(float* h, int w, int ht, uint64_t seed, double base,
                                     double relief, double noise, int integer_valued)
{
    tp_rng rng = tp_rng_seed(seed);
    double f1 = tp_rng_range(&rng, 0.05, 0.2), f2 = tp_rng_range(&rng, 0.05, 0.2);
    double p1 = tp_rng_range(&rng, 0, 6.28), p2 = tp_rng_range(&rng, 0, 6.28);
    int x, y;
    for (y = 0; y < ht; ++y) {
        for (x = 0; x < w; ++x) {
            double z = base + relief * (0.5 * sin(f1 * x + p1) * cos(f2 * y + p2) +
                                        0.3 * sin(0.037 * x - 0.023 * y + p2) +
                                        0.2 * cos(0.07 * (x - y) + p1));
            z += noise * (tp_rng_unit(&rng) - 0.5);
            h[(size_t)y * w + x] = (float)(integer_valued ? floor(z + 0.5) : z);
        }
    }
}

/* Creates a terrain from heights (the zero geotransform = 1 m north-up unless gt is given),
 * failing the test if creation fails. */
static inline tp_terrain* tpt_terrain_create(const float* heights, int w, int h, int patch_size,
                                             tp_fit fit, const double* gt)
{
    tp_terrain_desc d;
    tp_terrain* t = NULL;
    tp_error err;
    tp_status s;
    memset(&d, 0, sizeof d);
    memset(&err, 0, sizeof err);
    d.heights = heights;
    d.height_count = (size_t)w * h;
    d.width = w;
    d.height = h;
    d.patch_size = patch_size;
    d.fit = fit;
    if (gt)
        memcpy(d.geotransform, gt, sizeof d.geotransform);
    s = tp_terrain_create(&d, &t, &err);
    if (s != TP_OK || !t)
        FAIL("tp_terrain_create(%dx%d, patch %d) failed: %s: %s", w, h, patch_size,
             tp_test_status_name_(s), err.message);
    return t;
}

/* The levels of a patch's four neighbours in a selection-free setting: all the same. */
static inline void tpt_fill4(int out[4], int level)
{
    out[0] = out[1] = out[2] = out[3] = level;
}

/* Vertices and drawn triangles of one patch, into caller buffers sized for level n (the
 * largest): vertices (2^n+1)^2, triangles 3 * 2 * 4^n. Returns the triangle count. */
static inline size_t tpt_patch_geometry(const tp_terrain* t, int patch, int k, const int nb[4],
                                        tp_vertex* v, size_t v_cap, uint32_t* tri, size_t tri_cap)
{
    tp_patch_vertices(t, patch, k, nb, v, v_cap);
    return tp_patch_triangles(v, k, tri, tri_cap);
}

#endif /* TP_TEST_GEOM_H */
