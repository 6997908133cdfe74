/* tp_viewshed.h - which samples an observer sees (viewshed.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_VIEWSHED_H
#define TP_VIEWSHED_H

#include "tp_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Viewshed (viewshed.c): which samples an observer sees
 *
 * One pass over the grid outwards from the observer carrying a horizon height per sample
 * (Wang, Robinson & White 2000; GDAL's GVM_Edge mode of GDALViewshedGenerate), O(samples) in
 * the radius' window plus an exact ray test where a sight line grazes: 5-30 ms for a 10-15 km
 * radius (docs/PERFORMANCE.md).
 * docs/field.md states its error behaviour and where it differs from gdal_viewshed.
 *
 * Conventions are gdal_viewshed's: heights above the ground (observer 2 m, target 0 m); a
 * sample's height is lowered by curvature_coeff * d^2 / (2 * earth_radius_m) at horizontal
 * distance d from the observer (0.85714 = curvature with standard refraction, 1 = curvature
 * without refraction, 0 = a flat earth: as GDAL's -cc, which "1" does NOT turn off); distances
 * are between sample centres, in the units of the geotransform (metres on a render grid), and
 * use |gt[1]| and |gt[5]| (rotated grids are refused). A target at a sample is seen when its
 * corrected height plus target_height_m reaches the horizon there (equal counts as seen).
 * Values: TP_VIEWSHED_VISIBLE (255), TP_VIEWSHED_HIDDEN (0), TP_VIEWSHED_OUTSIDE (0: beyond
 * the radius), as GDALViewshedGenerate's defaults; a nodata sample (NaN) is never seen (0) and
 * does not block the view (a sight line passes over it at the horizon it inherits). The
 * observer's sample and its eight neighbours are always seen (no sample lies between).
 */
#define TP_VIEWSHED_VISIBLE 255
#define TP_VIEWSHED_HIDDEN 0
#define TP_VIEWSHED_OUTSIDE 0
#define TP_VIEWSHED_OBSERVER_HEIGHT_M 2.0
#define TP_VIEWSHED_TARGET_HEIGHT_M 0.0
#define TP_VIEWSHED_CURVATURE_COEFF 0.85714
/* Within this many posts of the observer (Chebyshev) a sample gets the exact horizon of its
 * sight line instead of the interpolated one, and the sweep carries on from those: XDraw's
 * interpolation errs most where the rings are short (a ridge a few posts away smeared across a
 * whole sector behind it). With the grazing check (below) beyond it, 16 posts are as accurate
 * as the 64 used before it (docs/field.md "Grazing sight lines") at 1/64 of the cost. */
#define TP_VIEWSHED_EXACT_RADIUS_PX 16

typedef struct tp_viewshed_options {
    double observer_height_m; /* eye above the ground at the observer's sample, >= 0 */
    double target_height_m;   /* target above the ground at each sample, >= 0 */
    double curvature_coeff;   /* >= 0; see above */
    double radius_m;          /* samples further than this are TP_VIEWSHED_OUTSIDE; 0: no limit */
    double earth_radius_m;    /* the sphere of the curvature term (GDAL: the CRS's semi-major
                                 axis); 0 means WGS84's 6378137 m */
    int exact_radius_px;      /* >= 0: samples within this many posts (Chebyshev) get the exact
                                 horizon (R3: the ground linear between the posts where the
                                 sight line crosses each grid line); 0: interpolated everywhere,
                                 exactly GDAL's GVM_Edge */
    int grazing_check;        /* 1: beyond that square, a sample whose target is within the
                                 interpolated horizon's error bound of it (a grazing sight
                                 line) gets the exact horizon too (viewshed.c, docs/field.md);
                                 0: interpolated (with exact_radius_px 0: GDAL's GVM_Edge) */
    int threads;              /* 0: the halves north and south of the observer's row on two
                                 threads when each has 64 rows or more (as GDAL's viewshed);
                                 1: one thread. The answer is the same. */
} tp_viewshed_options;

/* gdal_viewshed's defaults: 2 m, 0 m, 0.85714, no radius limit, WGS84's semi-major axis; exact
 * within TP_VIEWSHED_EXACT_RADIUS_PX and where sight lines graze. (A zeroed struct is valid too:
 * an eye on the ground, a flat earth, GDAL's interpolation everywhere.) */
tp_viewshed_options tp_viewshed_options_default(void);

/* Computes the viewshed of an observer standing on sample (observer_x, observer_y) (column,
 * row) of heights (width * height floats, row 0 first, NaN = nodata; height_count = width *
 * height) into out (out_count >= width * height bytes, one per sample, the values above). Every
 * byte of out is written, those outside the radius' window too (0). The georeference is the
 * GDAL geotransform of the grid (only its post spacings matter).
 * Fails (out untouched) with TP_ERR_INVALID_ARG for an observer outside the grid, a non-finite
 * or rotated geotransform, a zero post spacing, options outside their ranges (negative or NaN
 * heights, radius or coefficient); TP_ERR_BAD_DATA for an observer on a nodata sample;
 * TP_ERR_OUT_OF_MEMORY (fourteen rows of doubles of scratch). Reentrant: no state between calls. */
tp_status tp_viewshed_compute(const float* heights, size_t height_count, int width, int height,
                              const double geotransform[6], int observer_x, int observer_y,
                              const tp_viewshed_options* options, uint8_t* out,
                              size_t out_count, tp_error* err);

/* Values per sample besides visibility (as r.viewshed's and gdal_viewshed's outputs). */
typedef enum tp_viewshed_values {
    TP_VIEWSHED_VALUES_NONE = 0,
    /* The vertical angle from the eye to the target, degrees, as GRASS's r.viewshed: 0 straight
     * down, 90 level, 180 straight up (the target's height corrected for curvature, as the
     * visibility); NaN where the target is not seen, at the observer's post, beyond the radius
     * and on nodata. */
    TP_VIEWSHED_VALUES_ANGLE,
    /* How far the target stands above the sight line that grazes the horizon in front of it,
     * metres (own + target height - horizon, all corrected, at the sample): >= 0 where seen;
     * below 0 where hidden, minus the height the target would need to be raised by to be seen
     * (gdal_viewshed -om GROUND's value there). NaN where nothing lies between (the observer's
     * post and its eight neighbours), beyond the radius and on nodata. */
    TP_VIEWSHED_VALUES_CLEARANCE,
} tp_viewshed_values;

/* tp_viewshed_compute, and for kind != TP_VIEWSHED_VALUES_NONE also the value kind names for
 * each sample into values (out_count floats, every one written: NaN where there is none). */
tp_status tp_viewshed_compute_values(const float* heights, size_t height_count, int width,
                                     int height, const double geotransform[6], int observer_x,
                                     int observer_y, const tp_viewshed_options* options,
                                     tp_viewshed_values kind, uint8_t* out, float* values,
                                     size_t out_count, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_VIEWSHED_H */
