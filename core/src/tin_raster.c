/* tin_raster.c - the error-bounded TIN's measure of one triangle (tin.c's insertion calls it for
 * every triangle it creates): the triangle's rows solved exactly from its integer edge
 * functions, and its worst valid sample, the next to insert, with that sample's error. Forced
 * samples (a tiled build's borders, a void's outline) come first, found through their per-row
 * lists without scanning the free ones. */
#include "tin_int.h"

/* The interpolation at a triangle's own corner may round away from the corner's height: the
 * corners are never candidates (their error is 0 by construction). */
static inline int is_corner(const int32_t* const p[3], int32_t x, int32_t y)
{
    return (p[0][0] == x && p[0][1] == y) || (p[1][0] == x && p[1][1] == y) ||
           (p[2][0] == x && p[2][1] == y);
}

/* The columns xl..xr of row y inside triangle p (orient < 0), clipped to the grid's w columns;
 * 0 when none. Inside: every edge function (b - a) x (s - a) <= 0; each is A x + B, solved for
 * the row's span exactly. */
static inline int row_span(const int32_t* const p[3], int32_t y, int w, int64_t* xl_out,
                           int64_t* xr_out)
{
    int64_t xl = INT64_MIN, xr = INT64_MAX;
    for (int i = 0; i < 3; ++i) {
        const int32_t* a = p[i];
        const int32_t* c = p[(i + 1) % 3];
        /* E(x) = (cx-ax)(y-ay) - (cy-ay)(x-ax) <= 0
         *   <=>  (cy-ay) x >= (cx-ax)(y-ay) + (cy-ay) ax */
        int64_t A = (int64_t)c[1] - a[1];
        int64_t B = ((int64_t)c[0] - a[0]) * ((int64_t)y - a[1]) + A * a[0];
        if (A > 0) {
            int64_t lo = -tp__tin_floor_div(-B, A); /* ceil(B / A) */
            xl = lo > xl ? lo : xl;
        } else if (A < 0) {
            int64_t hi = tp__tin_floor_div(-B, -A); /* x <= B / A, A < 0: floor(-B / -A) */
            xr = hi < xr ? hi : xr;
        } else if (B > 0) {
            xl = 1, xr = 0; /* 0 >= B fails: empty row */
        }
    }
    *xl_out = xl < 0 ? 0 : xl;
    *xr_out = xr > w - 1 ? w - 1 : xr;
    return *xl_out <= *xr_out;
}

/* The triangle's candidate and error. While forced samples are left (b->forced_left), only its
 * forced samples are looked at: returns 0, writing nothing, when it has none. */
int tp__tin_rasterise(tin_build* b, uint32_t t)
{
    const uint32_t* v = b->T[t].v;
    const int32_t* p[3] = {b->vx + 2 * v[0], b->vx + 2 * v[1], b->vx + 2 * v[2]};
    const double za = b->vz[v[0]], zb = b->vz[v[1]], zc = b->vz[v[2]];
    const int64_t det = tp__tin_orient(p[0], p[1], p[2]); /* < 0 */
    assert(det < 0);
    const double bx = p[1][0] - p[0][0], by = p[1][1] - p[0][1];
    const double cx = p[2][0] - p[0][0], cy = p[2][1] - p[0][1];
    const double inv = 1.0 / (double)det;
    const double dzdx = ((zb - za) * cy - (zc - za) * by) * inv;
    const double dzdy = ((zc - za) * bx - (zb - za) * cx) * inv;
    int32_t y0 = p[0][1], y1 = p[0][1];
    for (int i = 1; i < 3; ++i) {
        y0 = p[i][1] < y0 ? p[i][1] : y0;
        y1 = p[i][1] > y1 ? p[i][1] : y1;
    }
    double best = -1.0;
    uint32_t best_i = 0;
    size_t visited = 0;
    /* forced samples (rows of b->fx): the first in scan order is the candidate (nothing beats
     * FORCED_ERR and a full scan keeps the first), found without scanning the free ones */
    for (int32_t y = y0; b->forced_left > 0 && y <= y1; ++y) {
        int64_t xl, xr;
        if (!row_span(p, y, b->w, &xl, &xr))
            continue;
        uint32_t lo = b->frow[y], hi = b->frow[y + 1];
        while (lo < hi) { /* first forced column >= xl */
            uint32_t mid = lo + (hi - lo) / 2;
            if (b->fx[mid] < xl)
                lo = mid + 1;
            else
                hi = mid;
        }
        for (; lo < b->frow[y + 1] && b->fx[lo] <= xr; ++lo) {
            int32_t x = b->fx[lo];
            size_t i = (size_t)y * b->w + (size_t)x;
            if (b->h[i] == b->h[i] && !is_corner(p, x, y)) {
                best = FORCED_ERR;
                best_i = (uint32_t)i;
                goto scanned;
            }
        }
    }
    if (b->forced_left > 0)
        return 0;
    for (int32_t y = y0; y <= y1; ++y) {
        int64_t xl, xr;
        if (!row_span(p, y, b->w, &xl, &xr))
            continue;
        const float* row = b->h + (size_t)y * b->w;
        const double zrow = za + dzdy * (y - p[0][1]);
        visited += (size_t)(xr - xl + 1);
        if (b->cls) { /* forced and skipped samples */
            const uint8_t* crow = b->cls + (size_t)y * b->w;
            for (int64_t x = xl; x <= xr; ++x) {
                float s = row[x];
                if (s != s || crow[x] == TIN_SKIP)
                    continue;
                double d = crow[x] == TIN_FORCE
                               ? FORCED_ERR
                               : fabs((double)s - (zrow + dzdx * (double)(x - p[0][0])));
                if (d > best && !is_corner(p, (int32_t)x, y)) {
                    best = d;
                    best_i = (uint32_t)((size_t)y * b->w + (size_t)x);
                }
            }
            continue;
        }
        for (int64_t x = xl; x <= xr; ++x) {
            float s = row[x];
            if (s != s)
                continue;
            double d = fabs((double)s - (zrow + dzdx * (double)(x - p[0][0])));
            if (d > best && !is_corner(p, (int32_t)x, y)) {
                best = d;
                best_i = (uint32_t)((size_t)y * b->w + (size_t)x);
            }
        }
    }
scanned:
    b->visited += visited;
    /* stored as a float rounded up, so a float comparison with the bound (rounded down) never
     * lets a double error above it through */
    float f = best < 0 ? 0.0f : (float)best;
    if ((double)f < best)
        f = nextafterf(f, INFINITY);
    b->T[t].err = f;
    b->T[t].cand = best_i;
    return 1;
}
