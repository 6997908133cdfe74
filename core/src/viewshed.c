/* viewshed.c - which samples of a height grid an observer sees: one pass over the grid from
 * the observer outwards, carrying a "horizon" height per sample (Wang, Robinson & White; XDraw).
 *
 * This work is based on:
 *   J. Wang, G. J. Robinson, K. White, "Generating Viewsheds without Using Sightlines",
 *     Photogrammetric Engineering & Remote Sensing 66(1), 2000, pp. 87-90
 *   W. R. Franklin, C. Ray, "Higher isn't Necessarily Better: Visibility Algorithms and
 *     Experiments", 6th Int. Symposium on Spatial Data Handling, 1994 (R3, R2, XDraw)
 *
 * Every sample stores H, the height (relative to the eye, corrected for curvature) that a
 * target there must reach to be seen from beyond it: the larger of its own height and the
 * horizon projected onto it. A sample's horizon is the H of the two samples of the previous
 * ring that the sight line passes between, interpolated linearly where the line crosses the
 * segment between them and scaled from that distance to the sample's own (similar triangles:
 * H is a height on a cone through the eye). Rows are swept outwards from the observer's row,
 * each row from the observer's column outwards, so both samples are ready when needed: a
 * sample nearer the row axis (|dx| < |dy|) uses two samples of the previous row, one nearer the
 * column axis (|dx| >= |dy|) the previous sample of its own row and the one diagonal to it.
 * This is GDAL's GVM_Edge mode (gdal_viewshed's default); docs/field.md gives the error
 * behaviour and where this differs from GDAL (nodata, the eight neighbours).
 *
 * Grazing sight lines (options->grazing_check): the interpolated horizon is not the sight
 * line's own, and where a target clears it or falls short of it by less than the
 * interpolation can be wrong by, the answer is a coin toss (a sea or a plain seen at a grazing
 * angle). So each sample also carries E, a bound on how far its H may be from the exact one:
 * zero where H is exact (its own ground above the horizon by more than the horizon's bound, an
 * exact horizon, the axes), else its parents' E interpolated and scaled like H, plus what
 * linear interpolation between the two parents can miss: an eighth of the second difference
 * of H across the parents' ring (how much the horizon bends between the sight lines; a quarter
 * of the first difference where the ring has no third sample), plus 1 cm. Where the target is
 * within E of the horizon, the sample gets the exact horizon of its own sight line (R3, as near
 * the observer), walked from the observer out: a crossing that already hides the target ends
 * the walk, and the horizon carried on is then what that crossing proves and the bound allows;
 * a whole walk makes H exact (E = 0).
 *
 * The rows north and south of the observer's row depend only on it: the two halves run on two
 * threads (options->threads), as GDAL's own viewshed runs its scans up and down.
 */
#include "internal.h"
#include "tp_viewshed.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h>

#define WGS84_SEMI_MAJOR_M 6378137.0
#define PI 3.14159265358979323846
/* H of a sample that constrains nothing (a nodata sample next to the observer): a sight line
 * falling a million metres per sample, far below any terrain, still finite after scaling. */
#define NO_HORIZON_SLOPE (-1e6)
/* The grazing check's bound (see the top): shares of the second and first differences of H
 * across the parents' ring, plus 1 cm a ring. Measured against R3 on summit, valley and coast
 * observers (docs/field.md "Exact near the observer, and where sight lines graze"): these
 * leave <= 0.08% of the samples wrong; a quarter more, <= 0.04% at 1.3x the time. */
#define GRAZING_BEND_SHARE 0.125
#define GRAZING_SPREAD_SHARE 0.25
#define GRAZING_FLOOR_M 0.01
/* Rows each half needs for the north half to get a thread of its own (a thread costs tens of
 * microseconds; 64 rows of a 20 km disc take a millisecond). */
#define HALF_THREAD_MIN_ROWS 64

tp_viewshed_options tp_viewshed_options_default(void)
{
    tp_viewshed_options o;
    memset(&o, 0, sizeof o);
    o.observer_height_m = TP_VIEWSHED_OBSERVER_HEIGHT_M;
    o.target_height_m = TP_VIEWSHED_TARGET_HEIGHT_M;
    o.curvature_coeff = TP_VIEWSHED_CURVATURE_COEFF;
    o.radius_m = 0.0;
    o.earth_radius_m = WGS84_SEMI_MAJOR_M;
    o.exact_radius_px = TP_VIEWSHED_EXACT_RADIUS_PX;
    o.grazing_check = 1;
    return o;
}

/* The state of one sweep. */
typedef struct {
    const float* heights;
    int width;
    int ox, oy;          /* observer sample */
    int x0, x1;          /* window columns (inclusive) */
    double eye_m;        /* observer's ground + observer height */
    double target_m;
    double k_curv;       /* curvature_coeff / earth diameter (1/m) */
    double r2;           /* radius squared (m^2); DBL_MAX when unlimited */
    double sx2, sy2;     /* squared post spacings */
    int exact;           /* samples with max(|dx|, |dy|) <= exact get the exact horizon */
    int grazing;         /* options->grazing_check */
    uint8_t* out;
    float* values;       /* NULL, or the values asked for (tp_viewshed_values) */
    tp_viewshed_values kind;
} sweep;

/* The rows of H and of its error bound E (see the top), indexed by column - x0. */
typedef struct {
    double* h;
    double* e;
} sweep_row_state;

/* The exact horizon of the sight line from the observer to sample (x, y), at distance^2 d2:
 * the highest of the ground (relative to the eye, curvature-corrected) where the line crosses
 * each grid line between them, linear between the two posts there, scaled to the sample's
 * distance (a height on the cone through the eye, as H). Crossings next to nodata block
 * nothing (nodata is seen through). -DBL_MAX when no crossing has ground. The walk stops at
 * the first crossing above limit and returns its height (DBL_MAX: the whole line). */
static double exact_horizon(const sweep* s, int x, int y, double d2, double limit)
{
    const int dx = x - s->ox, dy = y - s->oy;
    const int ax = dx < 0 ? -dx : dx, ay = dy < 0 ? -dy : dy;
    const ptrdiff_t sx = dx < 0 ? -1 : 1, sy = dy < 0 ? -(ptrdiff_t)s->width : s->width;
    const float* o = s->heights + (size_t)s->oy * s->width + s->ox;
    const double kd2 = s->k_curv * d2;
    double best = -DBL_MAX;
    /* axis 0: the column lines x = ox + i (the line passes between two rows there);
     * axis 1: the row lines y = oy + i (between two columns) */
    for (int axis = 0; axis < 2; ++axis) {
        const int along = axis == 0 ? ax : ay, across = axis == 0 ? ay : ax;
        const ptrdiff_t step_along = axis == 0 ? sx : sy, step_across = axis == 0 ? sy : sx;
        /* walk the crossings: i * across = j * along + rem, the line at j + rem / along */
        const double inv = 1.0 / along;
        const float* a = o; /* the post (i, j) */
        int rem = 0;
        for (int i = 1; i < along; ++i) {
            a += step_along;
            rem += across;
            while (rem >= along) { /* more than once only when across > along */
                rem -= along;
                a += step_across;
            }
            const double f = rem * inv;
            const double t = i * inv;
            const double za = a[0], zb = f > 0.0 ? a[step_across] : za;
            if (za != za || zb != zb)
                continue;
            const double h = za + f * (zb - za) - s->eye_m - kd2 * t * t;
            if (h > best * t) { /* h / t > best, without a division per crossing */
                best = h / t;
                if (best > limit)
                    return best;
            }
        }
    }
    return best;
}

/* Where the interpolated horizon leaves the target's answer in doubt (see the top): the
 * sample's exact horizon with its bound E back to 0; or, when a crossing already hides the
 * target, the middle of what it proves (at least its height) and the bound allows, and half
 * that range as the new bound. doubt: what the interpolation may miss here (see the top). */
static double grazing_horizon(const sweep* s, int x, int y, double d2, double own,
                              double horizon, double doubt, double* e)
{
    *e += doubt + GRAZING_FLOOR_M;
    const double seen_up_to = own + s->target_m;
    const double margin = seen_up_to - horizon;
    if (margin > *e || margin < -*e)
        return horizon;
    const double found = exact_horizon(s, x, y, d2, seen_up_to);
    if (found <= seen_up_to) { /* the whole line walked: exact */
        *e = 0.0;
        return found;
    }
    double lo = horizon - *e, hi = horizon + *e;
    lo = found > lo ? found : lo;
    hi = hi > lo ? hi : lo + *e;
    *e = 0.5 * (hi - lo);
    return 0.5 * (lo + hi);
}

/* The answer for sample x of row y, whose own height is own and horizon horizon (both relative
 * to the eye, corrected), at distance^2 d2: out, and the value asked for. */
static void decide(const sweep* s, int x, int y, double own, double horizon, double d2)
{
    const size_t i = (size_t)y * s->width + x;
    const double clearance = own + s->target_m - horizon;
    s->out[i] = clearance >= 0.0 ? TP_VIEWSHED_VISIBLE : TP_VIEWSHED_HIDDEN;
    if (!s->values)
        return;
    if (s->kind == TP_VIEWSHED_VALUES_CLEARANCE)
        s->values[i] = horizon == -DBL_MAX ? NAN : (float)clearance;
    else if (clearance >= 0.0)
        s->values[i] = (float)(90.0 + atan2(own + s->target_m, sqrt(d2)) * (180.0 / PI));
}

/* Fills row y (|y - oy| = ay) of cur from prev (the row one step nearer the observer; unused
 * when ay == 0). */
static void sweep_row(const sweep* s, int y, int ay, const sweep_row_state* before,
                      const sweep_row_state* prev, const sweep_row_state* cur)
{
    const double* bh = before ? before->h : NULL; /* two rows nearer: the bend's third row */
    const int nw = s->x1 - s->x0 + 1;
    const float* z = s->heights + (size_t)y * s->width;
    uint8_t* out = s->out + (size_t)y * s->width;
    const int oi = s->ox - s->x0;
    const double dy2 = (double)ay * ay * s->sy2;
    if (dy2 > s->r2) /* the whole row is beyond the radius (its corner of the window) */
        return;
    double *h = cur->h, *e = cur->e;
    const double *ph = prev ? prev->h : NULL, *pe = prev ? prev->e : NULL;

    /* the observer's column: a line along the column axis, through the posts (exact) */
    e[oi] = 0.0;
    if (ay == 0) {
        h[oi] = z[s->ox] - s->eye_m; /* the observer's own ground */
        out[s->ox] = TP_VIEWSHED_VISIBLE;
    } else {
        const double own = (double)z[s->ox] - s->eye_m - s->k_curv * dy2;
        double horizon = ay == 1 ? -DBL_MAX : ph[oi] * ay / (ay - 1);
        if (ay == 1 && own != own)
            horizon = NO_HORIZON_SLOPE;
        if (own == own) { /* not nodata */
            decide(s, s->ox, y, own, horizon, dy2);
            h[oi] = own > horizon ? own : horizon;
        } else {
            h[oi] = horizon;
        }
    }

    /* both halves of the row, outwards: dir -1 (west) then +1 (east) */
    for (int dir = -1; dir <= 1; dir += 2) {
        const int end = dir < 0 ? s->x0 - 1 : s->x1 + 1;
        for (int x = s->ox + dir, ax = 1; x != end; x += dir, ++ax) {
            const double d2 = (double)ax * ax * s->sx2 + dy2;
            if (d2 > s->r2)
                break; /* the rest of this half is further still: left at 0 */
            const int i = x - s->x0;
            const double own = (double)z[x] - s->eye_m - s->k_curv * d2;
            double horizon, bound = 0.0, doubt = -1.0;
            if (ax <= 1 && ay <= 1) {
                /* a neighbour: the sight line crosses no other sample */
                horizon = own == own ? -DBL_MAX : NO_HORIZON_SLOPE;
            } else if (ay == 0) {
                horizon = h[i - dir] * ax / (ax - 1);
            } else if (ax <= s->exact && ay <= s->exact) {
                horizon = exact_horizon(s, x, y, d2, DBL_MAX);
                if (horizon == -DBL_MAX && own != own)
                    horizon = NO_HORIZON_SLOPE;
            } else if (ax >= ay) {
                /* crosses the previous column between the diagonal and the row neighbour */
                const double a = ph[i - dir], b = h[i - dir], scale = (double)ax / (ax - 1);
                horizon = (a * ay + b * (ax - ay)) / (ax - 1);
                bound = (pe[i - dir] * ay + e[i - dir] * (ax - ay)) / (ax - 1);
                doubt = scale * (bh && ay >= 2
                                     ? GRAZING_BEND_SHARE * fabs(bh[i - dir] - 2 * a + b)
                                     : GRAZING_SPREAD_SHARE * fabs(a - b));
            } else {
                /* crosses the previous row between the diagonal and the column neighbour */
                const double a = ph[i - dir], b = ph[i], scale = (double)ay / (ay - 1);
                horizon = (a * ax + b * (ay - ax)) / (ay - 1);
                bound = (pe[i - dir] * ax + pe[i] * (ay - ax)) / (ay - 1);
                double bend = -1.0; /* the larger second difference at either parent */
                if (ax >= 2)
                    bend = fabs(ph[i - 2 * dir] - 2 * a + b);
                if (i + dir >= 0 && i + dir < nw && fabs(a - 2 * b + ph[i + dir]) > bend)
                    bend = fabs(a - 2 * b + ph[i + dir]);
                doubt = scale * (bend >= 0.0 ? GRAZING_BEND_SHARE * bend
                                             : GRAZING_SPREAD_SHARE * fabs(a - b));
            }
            if (own == own) {
                if (doubt >= 0.0 && s->grazing)
                    horizon = grazing_horizon(s, x, y, d2, own, horizon, doubt, &bound);
                decide(s, x, y, own, horizon, d2);
                h[i] = own > horizon ? own : horizon;
                e[i] = own > horizon + bound ? 0.0 : bound; /* its own ground: exact */
            } else {
                h[i] = horizon; /* nodata: seen through, never seen */
                e[i] = bound;
            }
        }
    }
}

/* One half of the sweep, from the observer's row outwards: dir -1 north (up the rows), +1
 * south, to the row end (excluded), with three rows of its own in turn (the one filled, the
 * previous and the one before it). Writes only its own rows of out and values. */
typedef struct sweep_half {
    const sweep* s;
    const sweep_row_state* axis;
    sweep_row_state ring[3];
    int observer_y, dir, end;
} sweep_half;

static int sweep_half_run(void* arg)
{
    const sweep_half* h = arg;
    const sweep_row_state *prev = h->axis, *before = NULL;
    for (int y = h->observer_y + h->dir, ay = 1; y != h->end; y += h->dir, ++ay) {
        const sweep_row_state* cur = &h->ring[ay % 3];
        sweep_row(h->s, y, ay, before, prev, cur);
        before = prev;
        prev = cur;
    }
    return 0;
}

static int finite_d(double v) { return v == v && v - v == 0.0; }

tp_status tp_viewshed_compute(const float* heights, size_t height_count, int width, int height,
                              const double geotransform[6], int observer_x, int observer_y,
                              const tp_viewshed_options* options, uint8_t* out,
                              size_t out_count, tp_error* err)
{
    return tp_viewshed_compute_values(heights, height_count, width, height, geotransform,
                                      observer_x, observer_y, options, TP_VIEWSHED_VALUES_NONE,
                                      out, NULL, out_count, err);
}

tp_status tp_viewshed_compute_values(const float* heights, size_t height_count, int width,
                                     int height, const double geotransform[6], int observer_x,
                                     int observer_y, const tp_viewshed_options* options,
                                     tp_viewshed_values kind, uint8_t* out, float* values,
                                     size_t out_count, tp_error* err)
{
    assert(heights && geotransform && options && out);
    assert(kind == TP_VIEWSHED_VALUES_NONE || values);
    assert(width > 0 && height > 0);
    assert(height_count == (size_t)width * (size_t)height);
    assert(out_count >= height_count);
    (void)height_count;
    (void)out_count;

    const double* gt = geotransform;
    for (int i = 0; i < 6; ++i)
        if (!finite_d(gt[i]))
            return tp_error_set(err, TP_ERR_INVALID_ARG,
                                "viewshed: geotransform[%d] is %g, expected a finite number", i,
                                gt[i]);
    if (gt[1] == 0.0 || gt[5] == 0.0 || gt[2] != 0.0 || gt[4] != 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "viewshed: expected a north-up grid with non-zero posts, got "
                            "geotransform (%g, %g, %g, %g, %g, %g)",
                            gt[0], gt[1], gt[2], gt[3], gt[4], gt[5]);
    const tp_viewshed_options* o = options;
    if (!finite_d(o->observer_height_m) || o->observer_height_m < 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "viewshed: observer height %g m, expected a finite height >= 0",
                            o->observer_height_m);
    if (!finite_d(o->target_height_m) || o->target_height_m < 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "viewshed: target height %g m, expected a finite height >= 0",
                            o->target_height_m);
    if (!finite_d(o->curvature_coeff) || o->curvature_coeff < 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "viewshed: curvature coefficient %g, expected a finite value >= 0 "
                            "(0.85714 with refraction, 1 without, 0 for a flat earth)",
                            o->curvature_coeff);
    if (!finite_d(o->radius_m) || o->radius_m < 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "viewshed: radius %g m, expected a finite distance >= 0 (0: no limit)",
                            o->radius_m);
    if (o->threads < 0 || o->threads > 2)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "viewshed: %d threads, expected 0 (automatic), 1 or 2", o->threads);
    if (o->exact_radius_px < 0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "viewshed: exact radius %d posts, expected >= 0 (0: interpolated "
                            "everywhere)",
                            o->exact_radius_px);
    if (!finite_d(o->earth_radius_m) || o->earth_radius_m < 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "viewshed: earth radius %g m, expected a finite radius > 0 (0: WGS84)",
                            o->earth_radius_m);
    if (observer_x < 0 || observer_x >= width || observer_y < 0 || observer_y >= height)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "viewshed: observer at sample (%d, %d), outside the %dx%d grid",
                            observer_x, observer_y, width, height);
    const float ground = heights[(size_t)observer_y * width + observer_x];
    if (ground != ground)
        return tp_error_set(err, TP_ERR_BAD_DATA,
                            "viewshed: observer at sample (%d, %d) stands on nodata (no ground "
                            "height there)",
                            observer_x, observer_y);

    sweep s;
    s.heights = heights;
    s.width = width;
    s.ox = observer_x;
    s.oy = observer_y;
    s.eye_m = (double)ground + o->observer_height_m;
    s.target_m = o->target_height_m;
    const double earth = o->earth_radius_m > 0.0 ? o->earth_radius_m : WGS84_SEMI_MAJOR_M;
    s.k_curv = o->curvature_coeff / (2.0 * earth);
    s.sx2 = gt[1] * gt[1];
    s.sy2 = gt[5] * gt[5];
    s.r2 = o->radius_m > 0.0 ? o->radius_m * o->radius_m : DBL_MAX;
    s.exact = o->exact_radius_px;
    s.grazing = o->grazing_check != 0;
    s.out = out;
    s.kind = kind;
    s.values = kind == TP_VIEWSHED_VALUES_NONE ? NULL : values;

    /* the window the radius reaches (samples within it may still be beyond the radius) */
    int y0 = 0, y1 = height - 1;
    s.x0 = 0;
    s.x1 = width - 1;
    if (o->radius_m > 0.0) {
        const double rx = floor(o->radius_m / fabs(gt[1])), ry = floor(o->radius_m / fabs(gt[5]));
        if (rx < observer_x)
            s.x0 = observer_x - (int)rx;
        if (rx < width - 1 - observer_x)
            s.x1 = observer_x + (int)rx;
        if (ry < observer_y)
            y0 = observer_y - (int)ry;
        if (ry < height - 1 - observer_y)
            y1 = observer_y + (int)ry;
    }
    const size_t ww = (size_t)(s.x1 - s.x0 + 1);
    double* rows = malloc(14 * ww * sizeof *rows);
    if (!rows)
        return tp_error_set(err, TP_ERR_OUT_OF_MEMORY,
                            "viewshed: out of memory for 14 rows of %zu samples", ww);
    const sweep_row_state axis = {rows, rows + ww}; /* the observer's row, start of both */

    memset(out, TP_VIEWSHED_OUTSIDE, (size_t)width * height);
    if (s.values)
        for (size_t i = 0; i < (size_t)width * height; ++i)
            s.values[i] = NAN;
    sweep_row(&s, observer_y, 0, NULL, NULL, &axis);
    /* north and south of the observer's row are independent: the north half on a second
     * thread when both have rows enough to pay for one (as GDAL's viewshed does) */
    sweep_half north = {&s, &axis, {{rows + 2 * ww, rows + 3 * ww},
                                    {rows + 4 * ww, rows + 5 * ww},
                                    {rows + 6 * ww, rows + 7 * ww}},
                        observer_y, -1, y0 - 1};
    sweep_half south = {&s, &axis, {{rows + 8 * ww, rows + 9 * ww},
                                    {rows + 10 * ww, rows + 11 * ww},
                                    {rows + 12 * ww, rows + 13 * ww}},
                        observer_y, 1, y1 + 1};
    thrd_t th;
    const int threaded = o->threads != 1 && observer_y - y0 >= HALF_THREAD_MIN_ROWS &&
                         y1 - observer_y >= HALF_THREAD_MIN_ROWS &&
                         thrd_create(&th, sweep_half_run, &north) == thrd_success;
    if (!threaded)
        sweep_half_run(&north);
    sweep_half_run(&south);
    if (threaded)
        thrd_join(th, NULL);
    free(rows);
    return TP_OK;
}
