/* los.c - line of sight between two grid positions over a ground given by a callback
 * (tp_core.h, "Line of sight"). One pass along the line: the endpoints first (the eye and the
 * target's top fix the sight line), then every sample against it. The first run of blocking
 * samples is the first obstruction; its highest point above the line is the one reported. */
#include "internal.h"
#include "tp_los.h"
#include "tp_viewshed.h"

#include <string.h>

#define WGS84_SEMI_MAJOR_M 6378137.0

tp_los_options tp_los_options_default(void)
{
    tp_los_options o;
    memset(&o, 0, sizeof o);
    o.observer_height_m = TP_VIEWSHED_OBSERVER_HEIGHT_M;
    o.target_height_m = TP_VIEWSHED_TARGET_HEIGHT_M;
    o.curvature_coeff = TP_VIEWSHED_CURVATURE_COEFF;
    o.earth_radius_m = WGS84_SEMI_MAJOR_M;
    o.step_px = TP_LOS_STEP_PX;
    return o;
}

static int finite_d(double v) { return v == v && v - v == 0.0; }

static double step_of(const tp_los_options* o)
{
    return o->step_px > 0.0 ? o->step_px : TP_LOS_STEP_PX;
}

size_t tp_los_sample_count(double from_x, double from_y, double to_x, double to_y,
                           const tp_los_options* options)
{
    assert(options);
    const double span = fmax(fabs(to_x - from_x), fabs(to_y - from_y));
    const double steps = ceil(span / step_of(options));
    return (size_t)(steps > 1.0 ? steps : 1.0) + 1;
}

/* The ground at an endpoint: TP_ERR_BAD_DATA in a void. */
static tp_status endpoint(tp_los_height_fn height, void* user, double x, double y,
                          const char* what, double* h, tp_error* err)
{
    tp_status s = height(user, x, y, h, err);
    if (s != TP_OK)
        return s;
    if (*h != *h)
        return tp_error_set(err, TP_ERR_BAD_DATA,
                            "line of sight: the %s at grid (%.2f, %.2f) stands in a void (no "
                            "ground height there)",
                            what, x, y);
    return TP_OK;
}

/* tp_los_compute's argument checks, in its order: TP_OK, or TP_ERR_INVALID_ARG with a message. */
static tp_status check_args(const double gt[6], double from_x, double from_y, double to_x,
                            double to_y, const tp_los_options* o, tp_error* err)
{
    for (int i = 0; i < 6; ++i)
        if (!finite_d(gt[i]))
            return tp_error_set(err, TP_ERR_INVALID_ARG,
                                "line of sight: geotransform[%d] is %g, expected a finite number",
                                i, gt[i]);
    if (gt[1] == 0.0 || gt[5] == 0.0 || gt[2] != 0.0 || gt[4] != 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "line of sight: expected a north-up grid with non-zero posts, got "
                            "geotransform (%g, %g, %g, %g, %g, %g)",
                            gt[0], gt[1], gt[2], gt[3], gt[4], gt[5]);
    if (!finite_d(from_x) || !finite_d(from_y) || !finite_d(to_x) || !finite_d(to_y))
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "line of sight: grid positions (%g, %g) -> (%g, %g), expected finite",
                            from_x, from_y, to_x, to_y);
    if (!finite_d(o->observer_height_m) || o->observer_height_m < 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "line of sight: observer height %g m, expected a finite height >= 0",
                            o->observer_height_m);
    if (!finite_d(o->target_height_m) || o->target_height_m < 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "line of sight: target height %g m, expected a finite height >= 0",
                            o->target_height_m);
    if (!finite_d(o->curvature_coeff) || o->curvature_coeff < 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "line of sight: curvature coefficient %g, expected a finite value "
                            ">= 0 (0.85714 with refraction, 1 without, 0 for a flat earth)",
                            o->curvature_coeff);
    if (!finite_d(o->earth_radius_m) || o->earth_radius_m < 0.0)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "line of sight: earth radius %g m, expected a finite radius > 0 "
                            "(0: WGS84)",
                            o->earth_radius_m);
    if (!(o->step_px >= 0.0 && o->step_px <= 1.0))
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "line of sight: step %g posts, expected (0, 1] (0: %g)", o->step_px,
                            TP_LOS_STEP_PX);
    return TP_OK;
}

tp_status tp_los_compute(const double geotransform[6], double from_x, double from_y, double to_x,
                         double to_y, const tp_los_options* options, tp_los_height_fn height,
                         void* user, tp_los_sample* samples, size_t sample_capacity,
                         tp_los_result* out, tp_error* err)
{
    assert(geotransform && options && height && out);
    const double* gt = geotransform;
    const tp_los_options* o = options;
    tp_status s = check_args(gt, from_x, from_y, to_x, to_y, o, err);
    if (s != TP_OK)
        return s;
    const size_t count = tp_los_sample_count(from_x, from_y, to_x, to_y, o);
    assert(!samples || sample_capacity >= count);
    (void)sample_capacity;

    double g0, g1;
    s = endpoint(height, user, from_x, from_y, "observer", &g0, err);
    if (s == TP_OK)
        s = endpoint(height, user, to_x, to_y, "target", &g1, err);
    if (s != TP_OK)
        return s;

    const double earth = o->earth_radius_m > 0.0 ? o->earth_radius_m : WGS84_SEMI_MAJOR_M;
    const double k = o->curvature_coeff / (2.0 * earth);
    const double dx = to_x - from_x, dy = to_y - from_y;
    const double span = fmax(fabs(dx), fabs(dy)); /* posts, Chebyshev */
    const double total_m = hypot(dx * gt[1], dy * gt[5]);
    tp_los_result r;
    memset(&r, 0, sizeof r);
    r.distance_m = total_m;
    r.eye_m = g0 + o->observer_height_m;
    r.target_m = g1 + o->target_height_m;
    r.drop_m = k * total_m * total_m;
    r.sample_count = count;
    r.min_clearance_m = r.min_clearance_x = r.min_clearance_y = r.min_clearance_distance_m = NAN;
    const double target_c = r.target_m - r.drop_m; /* the target's top, corrected */

    /* The profile goes straight into samples: a callback failing mid-way leaves them partly
     * written (the header says so); *out is written only at the end. */
    int in_run = 0, run_done = 0;
    /* For each sample's seen: the steepest corrected ground (slope from the eye) over the
     * samples at least one post past the observer and one post before it; lag is that post in
     * samples. */
    const double last_i = (double)(count - 1);
    size_t lag = 1;
    while (span > 0.0 && (double)lag * span / last_i < 1.0)
        lag++;
    double horizon = -INFINITY; /* only with samples: it looks back at them */
    for (size_t i = 0; i < count; ++i) {
        const double f = (double)i / (double)(count - 1);
        const double x = i + 1 == count ? to_x : from_x + f * dx;
        const double y = i + 1 == count ? to_y : from_y + f * dy;
        const double d = f * total_m;
        const double drop = k * d * d;
        double ground;
        if (i == 0) {
            ground = g0;
        } else if (i + 1 == count) {
            ground = g1;
        } else if ((s = height(user, x, y, &ground, err)) != TP_OK) {
            return s;
        }
        const double line = r.eye_m + f * (target_c - r.eye_m) + drop;
        const double clearance = line - ground; /* NaN in a void */
        /* posts from either end, without rounding at exactly one post */
        const int tested =
            (double)i * span / last_i >= 1.0 && (last_i - (double)i) * span / last_i >= 1.0;
        if (samples) {
            tp_los_sample* p = &samples[i];
            p->x = x;
            p->y = y;
            p->distance_m = d;
            p->ground_m = ground;
            p->line_m = line;
            p->clearance_m = clearance;
            p->tested = tested;
            if (i >= lag) { /* sample i - lag is now a post behind: it may hide this one */
                const size_t j = i - lag;
                const tp_los_sample* q = &samples[j];
                if ((double)j * span / last_i >= 1.0 && q->ground_m == q->ground_m)
                    horizon = fmax(horizon, (q->ground_m - k * q->distance_m * q->distance_m -
                                             r.eye_m) / q->distance_m);
            }
            if ((double)i * span / last_i < 1.0)
                p->seen = 1; /* the observer's own neighbourhood */
            else
                p->seen = ground == ground &&
                          (ground - drop + o->target_height_m - r.eye_m) / d >= horizon;
        }
        if (!tested)
            continue;
        if (clearance != clearance) {
            r.void_count++;
            continue;
        }
        r.tested_count++;
        if (!(clearance >= r.min_clearance_m)) { /* NaN at first */
            r.min_clearance_m = clearance;
            r.min_clearance_x = x;
            r.min_clearance_y = y;
            r.min_clearance_distance_m = d;
        }
        if (clearance < 0.0) {
            if (!run_done && (!in_run || -clearance > r.obstruction_blocking_m)) {
                r.obstruction_x = x;
                r.obstruction_y = y;
                r.obstruction_distance_m = d;
                r.obstruction_blocking_m = -clearance;
                r.obstruction_ground_m = ground;
            }
            in_run = 1;
            r.obstructed = 1;
        } else if (in_run) {
            in_run = 0;
            run_done = 1;
        }
    }
    r.visible = !r.obstructed;
    *out = r;
    return TP_OK;
}
