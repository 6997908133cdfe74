/* tp_light.h - terrain shadows, the sun over a day and its light times (shadow.c, light_day.c,
 * light_times.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_LIGHT_H
#define TP_LIGHT_H

#include "tp_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Shadows (shadow.c, light_day.c; issue 15, docs/light.md): which samples the sun lights
 *
 * Terrain self-shadowing on a height grid: heights (width * height floats, row 0 first = north,
 * column 0 = west, NaN = void), posts dx_m apart along a row (east) and dy_m along a column
 * (south), the ground between posts the bilinear surface. The sun is a direction: azimuth_deg
 * clockwise from GRID north (the grid's -row axis; a caller with a true azimuth subtracts the
 * meridian convergence, tp_ground_sample.convergence_deg), elevation_deg above the grid's
 * horizontal plane (for refraction, pass the apparent elevation).
 *
 * Assumptions: a flat earth within the grid and one sun direction for all of it: the sun's
 * elevation is the one at the place the caller computed it for (the centre); the earth's
 * curvature (which tilts the local horizontal by 0.009 degree per km, 0.27 degree across 30 km)
 * and the drop of distant ground (d^2 / 2R: 70 m at 30 km) are left out. Voids block no light
 * (a ray passes over them at the shadow height it carries) and are never lit. Nothing outside
 * the grid casts a shadow.
 *
 * A sample is lit when no ground between it and the sun along the sun's direction stands above
 * the ray from the sample's height toward the sun; its margin is its height less the height of
 * the shadowing sight line above it (the top of the shadow volume): > 0 lit (how much lower it
 * could be and still be lit), < 0 in shadow (how far it would have to rise). A margin of exactly
 * 0 counts as lit. A lit sample's margin measures the nearest sight line (often the ground just
 * beside it), not the peak whose shadow may come: to move shadows in time, tp_light_day_*
 * interpolate horizons instead.
 *
 * tp_shadow_compute is one sweep over the grid from the sun's side (O(samples *
 * TP_SHADOW_EXACT_LINES); docs/light.md has the timings beside a per-sample ray cast's), exact
 * for the ground along a ray's first TP_SHADOW_EXACT_LINES grid lines and interpolated (linearly
 * between two posts) for the shadow volume carried from further away; docs/light.md gives its
 * measured agreement with a ray cast on real DEMs (>= 99% of samples, tests/test_shadow.c).
 */
#define TP_SHADOW_LIT 1
#define TP_SHADOW_SHADOWED 0
/* A ray's ground is taken exactly over the first this many grid lines it crosses (at each
 * crossing and halfway between two), the shadow volume carried from beyond interpolated only
 * there: 8 keeps the agreement with the ray cast >= 99.3% on Mt Hood and N42E001 (a plain sweep
 * interpolating at every line, without the halfway points: 98.5%). */
#define TP_SHADOW_EXACT_LINES 8

/* Writes into lit (out_count >= width * height bytes, or NULL) TP_SHADOW_LIT or
 * TP_SHADOW_SHADOWED per sample (voids TP_SHADOW_SHADOWED), and into margin_m (out_count
 * floats, or NULL) the margin in metres: +INFINITY where no ground of the grid lies toward the
 * sun, NaN on voids. At least one of lit and margin_m is not NULL. The sun below or on the
 * horizon (elevation_deg <= 0): every sample shadowed, margins -INFINITY; at the zenith
 * (elevation_deg = 90): every valid sample lit, margins +INFINITY. Fails (outputs untouched)
 * with TP_ERR_INVALID_ARG for height_count != width * height or a grid below 1x1, spacings not
 * finite and > 0, a non-finite azimuth (any finite value is taken modulo 360) or an elevation
 * outside -90 .. 90; TP_ERR_OUT_OF_MEMORY (three floats per sample of scratch).
 * Reentrant. */
tp_status tp_shadow_compute(const float* heights, size_t height_count, int width, int height,
                            double dx_m, double dy_m, double azimuth_deg, double elevation_deg,
                            uint8_t* lit, float* margin_m, size_t out_count, tp_error* err);

/* The direct sunlight on the ground as a byte per sample: round(255 * cos(incidence)) where
 * the surface faces the sun, 0 where it faces away, lies in a shadow (lit[i] == 0; lit may be
 * NULL: no cast shadows) or is a void, all 0 with the sun on or below the horizon. The normal
 * is from central differences of the posts (one-sided at the grid's edge and beside voids, flat
 * where a sample has no neighbour), as gdaldem hillshade's. Same grid and sun conventions and
 * failures as tp_shadow_compute (out untouched on failure). */
tp_status tp_shadow_illumination(const float* heights, size_t height_count, int width,
                                 int height, double dx_m, double dy_m, double azimuth_deg,
                                 double elevation_deg, const uint8_t* lit, uint8_t* out,
                                 size_t out_count, tp_error* err);

/* The sun over a day (Blow, "Two Advanced Terrain Rendering Systems", Part II: 64 illumination
 * maps across the day, interpolated in time so that a peak's shadow crawls smoothly): the
 * shadows of count sun positions (times increasing, e.g. TP_LIGHT_DAY_MAPS from sunrise to
 * sunset), one int16 per sample per map (2 bytes; a float would be 4): 0 where the sample is
 * lit; where it is in shadow, minus the excess of its horizon over the sun, tan(h) - tan(e) in
 * units of TP_LIGHT_DAY_TAN_STEP (at least 1, at most 32767: deep shadow), h the elevation of
 * the ground that shadows it seen from the sample (tp_shadow_compute's sweep carries the
 * distance to that ground); with the sun on or below the horizon, h = 0.
 *
 * At a time between maps k and k+1 (weight w from k) a sample lit (or shadowed) in both is lit
 * (shadowed); one that changes is lit until (or from) the time the sun's tan(e), interpolated
 * linearly between the maps' tan(e), passes its horizon tan(h) from the map where it is in
 * shadow: so a shadow lengthening or shortening with the sun's elevation moves smoothly and
 * monotonically, its end where the horizon puts it. Where the change is not the elevation's
 * doing (the sun turning past a peak at nearly constant elevation), the sample changes at
 * w = 1/2. Height margins would not do: a lit sample's margin measures the ground next to it,
 * not the peak whose shadow is coming (docs/light.md). */
#define TP_LIGHT_DAY_MAPS 64
#define TP_LIGHT_DAY_TAN_STEP 1e-4 /* tan(h) - tan(e) per unit: 0.006 degree at 5 degrees */
#define TP_LIGHT_DAY_VOID INT16_MIN /* the stored code of a void */

typedef struct tp_light_day {
    int width, height, count;
    double* times_s;       /* count, strictly increasing (any time axis: Unix seconds) */
    double* azimuth_deg;   /* count, the sun (grid azimuth) of each map */
    double* elevation_deg; /* count */
    int16_t* codes;        /* count * width * height: map k's samples from k * width * height;
                              0 lit, < 0 shadowed (above), TP_LIGHT_DAY_VOID on voids */
} tp_light_day;

/* Computes the count maps of the grid (conventions of tp_shadow_compute). All of *out is owned
 * by it: tp_light_day_destroy. Fails (*out untouched) as tp_shadow_compute for the grid and
 * each sun, and with TP_ERR_INVALID_ARG for count < 2 or times not finite and strictly
 * increasing; TP_ERR_OUT_OF_MEMORY (2 * count bytes per sample, 17 more during the build). */
tp_status tp_light_day_build(const float* heights, size_t height_count, int width, int height,
                             double dx_m, double dy_m, const double* times_s,
                             const double* azimuth_deg, const double* elevation_deg, int count,
                             tp_light_day** out, tp_error* err);
void tp_light_day_destroy(tp_light_day* day); /* accepts NULL */

/* The shadows at time_s (times_s[0] <= time_s <= times_s[count - 1]) into lit (out_count >=
 * width * height bytes; TP_SHADOW_LIT or TP_SHADOW_SHADOWED, voids shadowed), interpolated as
 * above. Fails (lit untouched) with TP_ERR_INVALID_ARG for a time outside the maps' (the
 * message gives their range) or NaN. */
tp_status tp_light_day_at(const tp_light_day* day, double time_s, uint8_t* lit,
                          size_t out_count, tp_error* err);

/* The sun over a day as each sample's lit intervals ("light times"; issue 15): Blow's maps
 * (tp_light_day) compressed to four bytes a sample that a GPU samples and filters like
 * imagery, so that a light map of any size streams through the viewer's clipmap and the time
 * moves with one uniform. Each sample's day, times_s[0] .. times_s[count - 1], holds at most two
 * intervals in which it is lit; each end is where tp_light_day_at's interpolation between two
 * maps changes the sample (where the sun's elevation passes its horizon), quantised to
 *     tau = TP_LIGHT_TIMES_STEPS * (t - times_s[0]) / (times_s[count - 1] - times_s[0])
 * rounded to the nearest step. A texel is (r1, s1, r2, s2) with r1 <= s1 <= r2 <= s2: lit at
 * tau when r1 <= tau < s1 or r2 <= tau < s2 (tp_light_times_lit); only one interval: r2 = s2 =
 * s1; never lit (voids too): all 0. Bilinear filtering of the four bytes between samples moves
 * a shadow's edge continuously in time. A sample lit over more than two intervals keeps the
 * two that lose least: the shorter of its shortest shadow gap (bridged) and its shortest lit
 * interval (dropped) is given up, repeatedly; stats count those samples and the longest time
 * given up. */
#define TP_LIGHT_TIMES_STEPS 255

typedef struct tp_light_times_stats {
    size_t samples;          /* width * height */
    size_t simplified;       /* samples with more than two lit intervals */
    double given_up_max_s;   /* the longest time one simplification changed, seconds */
    size_t lit_any;          /* samples lit at some time of the day */
} tp_light_times_stats;

/* Writes 4 * width * height bytes into out (out_count >= that), row-major, a texel per
 * sample as above; stats may be NULL. Computes the maps one after another (memory: the
 * heights, out, and about 40 bytes a sample; not tp_light_day's 2 * count). progress may be
 * NULL: called after each map with (k + 1) / count. Same grid and sun conventions and failures
 * as tp_light_day_build (out untouched on failure). Reentrant. */
tp_status tp_light_times_build(const float* heights, size_t height_count, int width, int height,
                               double dx_m, double dy_m, const double* times_s,
                               const double* azimuth_deg, const double* elevation_deg,
                               int count, uint8_t* out, size_t out_count,
                               tp_light_times_stats* stats,
                               void (*progress)(void* user, double fraction), void* user,
                               tp_error* err);

/* tau in steps for time_s in the day t_first .. t_last (may be < 0 or > 255: outside it). */
double tp_light_times_tau(double t_first_s, double t_last_s, double time_s);

/* 1 when the texel is lit at tau (steps), else 0: as the viewer's shader decides at a post. */
int tp_light_times_lit(const uint8_t texel[4], double tau);

/* The texel of a coarser level: the rounded mean of each byte of the (up to) four texels of
 * the finer one (n = 1..4 of them; the order r1 <= s1 <= r2 <= s2 is kept). */
void tp_light_times_mean(const uint8_t* const* texels, int n, uint8_t out[4]);

#ifdef __cplusplus
}
#endif
#endif /* TP_LIGHT_H */
