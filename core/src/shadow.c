/*
 * shadow.c - terrain self-shadowing (tp_core.h, "Shadows"): one sweep over the grid from the
 * side the sun shines from, carrying the height of the shadow volume's top (Blow's "shadow
 * terrain") from one grid line to the next.
 *
 * The sun's horizontal direction u crosses either every column line or every row line first:
 * the lines are the columns when |du/dcolumn| >= |du/drow| in grid steps, else the rows. A ray
 * from a post toward the sun meets the previous line (one line nearer the sun) at a fractional
 * position, a horizontal distance s further, s * tan(elevation) higher. There the top of the
 * shadow volume H = max(ground, shadow height) is interpolated linearly between the line's two
 * posts: exact for the ground (the bilinear surface is linear along a grid line), an
 * approximation for the shadow height carried from beyond (as XDraw's for viewsheds). Repeated
 * at every line, that interpolation smears a narrow peak's shadow line and shortens its shadow;
 * so the ray's first TP_SHADOW_EXACT_LINES crossings take the ground itself (at each crossing,
 * and halfway between two, where a ridge along the cell's other diagonal stands highest), and
 * only the shadow volume beyond them is interpolated: once per that many lines instead of at
 * every line. O(samples * TP_SHADOW_EXACT_LINES), three floats per sample of scratch. Beside
 * the shadow height the sweep carries the distance to the ground that makes it, which gives a
 * shadowed sample's horizon: the tangent of the angle up to that ground (light_day.c).
 */
#include "light_int.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
/* A crossing this close to a post (in posts) is the post itself: axis-aligned and diagonal
 * suns cross exactly at posts, up to the rounding of sin and cos. */
#define AT_POST 1e-9

/* Lines over which a ray's ground is taken exactly (at each line crossing and halfway between
 * them) before the carried, interpolated shadow volume: tp_core.h's TP_SHADOW_EXACT_LINES. */
#define SHADOW_EXACT_LINES TP_SHADOW_EXACT_LINES

/* The grid seen as lines (columns or rows) of posts. */
typedef struct lines {
    const float* z;
    float* s;   /* shadow height per sample (-inf: no shadow line reaches it) */
    float* top; /* top of the shadow volume per sample: max(ground, s); -inf where neither */
    float* dist; /* horizontal distance from the sample to the ground that makes its top (0:
                    its own ground) */
    int nlines, npos;
    size_t line_stride, pos_stride;
} lines;

static double lerp(double a, double b, double f) { return a + (b - a) * f; }

static size_t at(const lines* g, int line, int pos)
{
    return (size_t)line * g->line_stride + (size_t)pos * g->pos_stride;
}

/* The ground (bilinear: linear along the line) at (line, a + f); NaN on a void segment. */
static double ground(const lines* g, int line, int a, double f)
{
    const double za = g->z[at(g, line, a)];
    return f == 0.0 ? za : lerp(za, g->z[at(g, line, a + 1)], f);
}

/* The bilinear ground halfway between lines `line` and `line - toward` at position a + f (0 <=
 * f < 1; the middle of a ray's run across a cell, where a ridge along the other diagonal stands
 * highest); NaN off the grid or in a cell with a void corner. */
static double ground_between(const lines* g, int line, int toward, int a, double f)
{
    if (a < 0 || a > g->npos - 1)
        return NAN;
    if (a == g->npos - 1) {
        if (f > 0.0)
            return NAN;
        if (a == 0)
            return 0.5 * (g->z[at(g, line, 0)] + g->z[at(g, line - toward, 0)]);
        a -= 1;
        f = 1.0;
    }
    const double z0 = lerp(g->z[at(g, line, a)], g->z[at(g, line, a + 1)], f);
    const double z1 = lerp(g->z[at(g, line - toward, a)], g->z[at(g, line - toward, a + 1)], f);
    return 0.5 * (z0 + z1);
}

/* The top of the shadow volume at (line, a + f), interpolated between the two posts, and the
 * distance from there to the ground that makes it (*dist). */
static double top(const lines* g, int line, int a, double f, double* dist)
{
    const size_t ia = at(g, line, a);
    if (f == 0.0) {
        *dist = g->dist[ia];
        return g->top[ia];
    }
    const size_t ib = at(g, line, a + 1);
    if (g->z[ia] == g->z[ia] && g->z[ib] == g->z[ib]) {
        *dist = lerp(g->dist[ia], g->dist[ib], f);
        return lerp(g->top[ia], g->top[ib], f);
    }
    /* a void at either end: no ground on the segment (voids block no light); the shadow
     * line carried from beyond, where there is one */
    const double sa = g->s[ia], sb = g->s[ib];
    if (sa > -INFINITY && sb > -INFINITY) {
        *dist = lerp(g->dist[ia], g->dist[ib], f);
        return lerp(sa, sb, f);
    }
    *dist = sa > sb ? g->dist[ia] : g->dist[ib];
    return sa > sb ? sa : sb;
}

tp_status tp__shadow_sweep(const float* heights, size_t height_count, int width, int height,
                           double dx_m, double dy_m, double azimuth_deg, double elevation_deg,
                           uint8_t* lit, float* margin_m, float* horizon_tan, size_t out_count,
                           tp_error* err)
{
    assert(heights && (lit || margin_m || horizon_tan));
    if (width < 1 || height < 1 || (size_t)width * (size_t)height != height_count)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "shadow: a %dx%d grid needs %zu heights, got %zu", width, height,
                            (size_t)(width > 0 ? width : 0) * (size_t)(height > 0 ? height : 0),
                            height_count);
    assert(out_count >= height_count);
    (void)out_count;
    if (!(dx_m > 0.0) || !(dy_m > 0.0) || !isfinite(dx_m) || !isfinite(dy_m))
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "shadow: post spacings must be finite and > 0, got %g x %g m", dx_m,
                            dy_m);
    if (!isfinite(azimuth_deg))
        return tp_error_set(err, TP_ERR_INVALID_ARG, "shadow: sun azimuth %g is not finite",
                            azimuth_deg);
    if (!(elevation_deg >= -90.0 && elevation_deg <= 90.0))
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "shadow: sun elevation %g is outside -90 .. 90 degrees",
                            elevation_deg);
    const size_t n = height_count;
    if (elevation_deg <= 0.0 || elevation_deg >= 90.0) {
        /* below the horizon: all in shadow; at the zenith: nothing is */
        const int up = elevation_deg >= 90.0;
        for (size_t i = 0; i < n; ++i) {
            const int valid = heights[i] == heights[i];
            if (lit)
                lit[i] = (uint8_t)(valid && up);
            if (margin_m)
                margin_m[i] = valid ? (up ? INFINITY : -INFINITY) : NAN;
            if (horizon_tan) /* below the horizon: the horizon is the one in the way */
                horizon_tan[i] = valid && !up ? 0.0f : NAN;
        }
        return TP_OK;
    }

    const double az = azimuth_deg * PI / 180.0;
    const double dcol = sin(az) / dx_m;  /* columns per metre toward the sun (east) */
    const double drow = -cos(az) / dy_m; /* rows per metre toward the sun (row 0 north) */
    const int col_lines = fabs(dcol) >= fabs(drow);
    lines g;
    g.z = heights;
    g.nlines = col_lines ? width : height;
    g.npos = col_lines ? height : width;
    g.line_stride = col_lines ? 1 : (size_t)width;
    g.pos_stride = col_lines ? (size_t)width : 1;
    const double dl = col_lines ? dcol : drow, dp = col_lines ? drow : dcol;
    const int toward = dl > 0.0 ? 1 : -1;  /* the line nearer the sun is line + toward */
    const double run = 1.0 / fabs(dl);      /* metres between lines along the ray */
    const double offset = dp * run;         /* posts along a line per line, |offset| <= 1 */
    const double rise = run * tan(elevation_deg * PI / 180.0);

    const double tan_e = tan(elevation_deg * PI / 180.0);
    g.s = malloc(n * sizeof *g.s);
    g.top = malloc(n * sizeof *g.top);
    g.dist = malloc(n * sizeof *g.dist);
    if (!g.s || !g.top || !g.dist) {
        free(g.s);
        free(g.top);
        free(g.dist);
        return tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "shadow: out of memory for a %dx%d grid",
                            width, height);
    }
    /* Where the ray from post p meets the j-th line: post p + da[j] and the fraction fa[j]
     * toward the next (0 at a post, within AT_POST of one); halfway to it: p + dm[j], fm[j].
     * The same for every p, offset being constant. */
    int da[SHADOW_EXACT_LINES + 1], dm[SHADOW_EXACT_LINES + 1];
    double fa[SHADOW_EXACT_LINES + 1], fm[SHADOW_EXACT_LINES + 1];
    for (int j = 1; j <= SHADOW_EXACT_LINES; ++j) {
        const double y = j * offset, ym = (j - 0.5) * offset;
        da[j] = (int)floor(y);
        fa[j] = y - floor(y);
        if (fa[j] > 1.0 - AT_POST) {
            da[j] += 1;
            fa[j] = 0.0;
        } else if (fa[j] < AT_POST) {
            fa[j] = 0.0;
        }
        dm[j] = (int)floor(ym);
        fm[j] = ym - floor(ym);
    }
    const int first = toward > 0 ? g.nlines - 1 : 0;
    for (int k = 0; k < g.nlines; ++k) {
        const int line = first - k * toward;
        for (int p = 0; p < g.npos; ++p) {
            /* the ground where the ray crosses the next SHADOW_EXACT_LINES lines, then the
             * shadow volume carried to the last of them */
            double s = -INFINITY, sd = 0.0; /* shadow height, distance to what makes it */
            for (int j = 1; j <= SHADOW_EXACT_LINES; ++j) {
                const int lj = line + j * toward;
                const int a = p + da[j];
                const double f = fa[j];
                if (lj < 0 || lj >= g.nlines || a < 0 || a >= g.npos ||
                    (f > 0.0 && a + 1 >= g.npos))
                    break; /* off the grid: nothing further */
                const double d = j * rise;
                const double gr = ground(&g, lj, a, f);
                if (gr - d > s) {
                    s = gr - d;
                    sd = j * run;
                }
                const double mid = ground_between(&g, lj, toward, p + dm[j], fm[j]);
                if (mid - (d - 0.5 * rise) > s) {
                    s = mid - (d - 0.5 * rise);
                    sd = (j - 0.5) * run;
                }
                if (j == SHADOW_EXACT_LINES) {
                    double td;
                    const double t = top(&g, lj, a, f, &td) - d;
                    if (t > s) {
                        s = t;
                        sd = j * run + td;
                    }
                }
            }
            const size_t i = at(&g, line, p);
            const float z = heights[i];
            const int valid = z == z;
            const int up = valid && (double)z >= s;
            g.s[i] = (float)s;
            g.top[i] = valid && z > s ? z : (float)s;
            g.dist[i] = valid && z > s ? 0.0f : (float)sd;
            if (lit)
                lit[i] = (uint8_t)up;
            if (margin_m)
                margin_m[i] = valid ? (float)((double)z - s) : NAN;
            if (horizon_tan) /* the ground that shadows it, s = g - sd tan e, seen from z */
                horizon_tan[i] = valid && !up ? (float)((s - z) / sd + tan_e) : NAN;
        }
    }
    free(g.s);
    free(g.top);
    free(g.dist);
    return TP_OK;
}

tp_status tp_shadow_compute(const float* heights, size_t height_count, int width, int height,
                            double dx_m, double dy_m, double azimuth_deg, double elevation_deg,
                            uint8_t* lit, float* margin_m, size_t out_count, tp_error* err)
{
    assert(heights && (lit || margin_m));
    return tp__shadow_sweep(heights, height_count, width, height, dx_m, dy_m, azimuth_deg,
                            elevation_deg, lit, margin_m, NULL, out_count, err);
}

tp_status tp_shadow_illumination(const float* heights, size_t height_count, int width,
                                 int height, double dx_m, double dy_m, double azimuth_deg,
                                 double elevation_deg, const uint8_t* lit, uint8_t* out,
                                 size_t out_count, tp_error* err)
{
    assert(heights && out);
    if (width < 1 || height < 1 || (size_t)width * (size_t)height != height_count)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "illumination: a %dx%d grid needs width * height heights, got %zu",
                            width, height, height_count);
    assert(out_count >= height_count);
    (void)out_count;
    if (!(dx_m > 0.0) || !(dy_m > 0.0) || !isfinite(dx_m) || !isfinite(dy_m) ||
        !isfinite(azimuth_deg) || !(elevation_deg >= -90.0 && elevation_deg <= 90.0))
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "illumination: bad spacing (%g x %g m) or sun (azimuth %g, "
                            "elevation %g)",
                            dx_m, dy_m, azimuth_deg, elevation_deg);
    const double az = azimuth_deg * PI / 180.0, el = elevation_deg * PI / 180.0;
    const double sx = cos(el) * sin(az), sy = cos(el) * cos(az), sz = sin(el); /* E, N, up */
    for (int r = 0; r < height; ++r)
        for (int c = 0; c < width; ++c) {
            const size_t i = (size_t)r * width + c;
            const float z = heights[i];
            if (z != z || (lit && !lit[i]) || elevation_deg <= 0.0) {
                out[i] = 0;
                continue;
            }
            /* the gradient by central differences, one-sided at edges and voids */
            const float zw = c > 0 ? heights[i - 1] : NAN, ze = c + 1 < width ? heights[i + 1] : NAN;
            const float zn = r > 0 ? heights[i - width] : NAN;
            const float zs = r + 1 < height ? heights[i + width] : NAN;
            double dzde = 0.0, dzdn = 0.0;
            if (zw == zw && ze == ze)
                dzde = ((double)ze - zw) / (2.0 * dx_m);
            else if (ze == ze)
                dzde = ((double)ze - z) / dx_m;
            else if (zw == zw)
                dzde = ((double)z - zw) / dx_m;
            if (zn == zn && zs == zs)
                dzdn = ((double)zn - zs) / (2.0 * dy_m);
            else if (zn == zn)
                dzdn = ((double)zn - z) / dy_m;
            else if (zs == zs)
                dzdn = ((double)z - zs) / dy_m;
            const double cosi = (-dzde * sx - dzdn * sy + sz) / sqrt(dzde * dzde + dzdn * dzdn + 1.0);
            out[i] = cosi > 0.0 ? (uint8_t)lround(255.0 * (cosi < 1.0 ? cosi : 1.0)) : 0;
        }
    return TP_OK;
}
