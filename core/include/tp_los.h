/* tp_los.h - line of sight between two grid positions (los.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_LOS_H
#define TP_LOS_H

#include "tp_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Line of sight (los.c): does an observer see a target, and what is in the way
 *
 * Conventions are the viewshed's (above; gdal_viewshed's): the eye observer_height_m above the
 * ground at the observer, the target target_height_m above the ground at the target, every
 * height lowered by curvature_coeff * d^2 / (2 * earth_radius_m) at horizontal distance d from
 * the observer (0.85714 default, 1 curvature without refraction, 0 a flat earth), distances
 * between grid positions in the geotransform's units (|gt[1]| per column, |gt[5]| per row:
 * metres on a render grid; not geodesic).
 *
 * The ground is asked for through a callback at fractional grid positions (column, row; sample
 * centres at integers), so any surface works: the app's full-resolution ground (ground.h), a
 * float grid interpolated by a test. It is sampled along the straight line in the grid at
 * equal steps of at most step_px posts in x and in y (0: 0.25), endpoints included.
 *
 * The sight line runs straight (in the curvature-corrected frame) from the eye to the target's
 * top. A sample blocks when its corrected ground is above the line (on the line counts as
 * seen). Samples within one post of either end (max(|dx|, |dy|) < 1 in grid units) are where
 * observer and target stand and are not tested, as the viewshed always sees the observer's
 * eight neighbours and takes a target's horizon from the ring one post nearer. Void samples
 * (NaN from the callback) block nothing and are counted. The target is visible when no tested
 * sample blocks.
 *
 * The obstruction reported is the highest point above the line (most negative clearance) of
 * the first run of consecutive blocking samples from the observer: the first ridge in the way;
 * blocking_m is how far its ground rises above the sight line there. Clearance at a sample is
 * line - ground (both corrected, so the same as uncorrected line + drop - ground); the
 * smallest over the tested samples is negative exactly when the target is hidden (then minus
 * the worst blocking along the whole line).
 */
#define TP_LOS_STEP_PX 0.25

typedef struct tp_los_options {
    double observer_height_m; /* >= 0 */
    double target_height_m;   /* >= 0 */
    double curvature_coeff;   /* >= 0 */
    double earth_radius_m;    /* 0 means WGS84's 6378137 m */
    double step_px;           /* > 0, at most 1 post; 0 means TP_LOS_STEP_PX */
} tp_los_options;

/* gdal_viewshed's defaults: 2 m, 0 m, 0.85714, WGS84, step 0.25 posts. */
tp_los_options tp_los_options_default(void);

/* The ground at grid (x, y): TP_OK with *height_m (NaN: a void), or an error (with err) that
 * tp_los_compute returns as it is. */
typedef tp_status (*tp_los_height_fn)(void* user, double x, double y, double* height_m,
                                      tp_error* err);

/* One sample along the line (the profile). */
typedef struct tp_los_sample {
    double x, y;        /* grid */
    double distance_m;  /* horizontal, from the observer */
    double ground_m;    /* as the callback gave it; NaN in a void */
    double line_m;      /* the sight line's height above the uncorrected ground's datum:
                           corrected line + drop, so that it plots against ground_m */
    double clearance_m; /* line_m - ground_m; NaN in a void */
    int tested;         /* 0 within one post of either end */
    int seen;           /* only when samples are asked for: a target target_height_m above
                           the ground here would be seen from the eye over the samples at
                           least one post from the observer and one post before this one (its
                           slope from the eye against theirs): the line seen / hidden along the
                           ground. The last sample's equals the result's visible. Always 1
                           within one post of the observer; 0 in a void. */
} tp_los_sample;

typedef struct tp_los_result {
    int visible;                 /* 1: no tested sample blocks */
    double distance_m;           /* observer to target, horizontal */
    double eye_m;                /* observer's ground + observer_height_m */
    double target_m;             /* target's ground + target_height_m (uncorrected) */
    double drop_m;               /* curvature correction at the target */
    int obstructed;              /* !visible; then the obstruction_* fields are set */
    double obstruction_x, obstruction_y, obstruction_distance_m, obstruction_blocking_m;
    double obstruction_ground_m; /* the ground there, as the callback gave it */
    double min_clearance_m;      /* NaN when no sample was tested (endpoints a post apart) */
    double min_clearance_x, min_clearance_y, min_clearance_distance_m;
    size_t sample_count;         /* samples along the line, endpoints included */
    size_t tested_count;         /* samples tested (not near the ends, not void) */
    size_t void_count;           /* tested positions in a void */
} tp_los_result;

/* Samples tp_los_compute takes between these grid positions with these options (>= 2). */
size_t tp_los_sample_count(double from_x, double from_y, double to_x, double to_y,
                           const tp_los_options* options);

/* Line of sight from grid (from_x, from_y) to (to_x, to_y) over the ground height() gives.
 * samples: NULL, or room for sample_capacity >= tp_los_sample_count(...) profile samples.
 * Fails (*out untouched; samples too, except on a callback error mid-way) with
 * TP_ERR_INVALID_ARG for non-finite positions, a
 * non-finite, rotated or zero-spacing geotransform, options outside their ranges (negative or
 * NaN heights or coefficient, step_px outside (0, 1]); TP_ERR_BAD_DATA when the observer or
 * the target stands in a void; or the callback's error. Reentrant, allocates nothing. */
tp_status tp_los_compute(const double geotransform[6], double from_x, double from_y, double to_x,
                         double to_y, const tp_los_options* options, tp_los_height_fn height,
                         void* user, tp_los_sample* samples, size_t sample_capacity,
                         tp_los_result* out, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_LOS_H */
