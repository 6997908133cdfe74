/* light_int.h - the shadow sweep with horizons (shadow.c) and the day's maps (light_day.c),
 * shared by shadow.c, light_day.c and light_times.c. */
#ifndef TP_CORE_LIGHT_INT_H
#define TP_CORE_LIGHT_INT_H

#include "internal.h"
#include "tp_light.h"

/* shadow.c: tp_shadow_compute with one more optional output: horizon_tan (out_count floats),
 * for a shadowed sample the tangent of the elevation angle of the ground that shadows it seen
 * from the sample (the sun must rise above it to light the sample; 0 with the sun on or below
 * the horizon), NaN for lit samples and voids. lit, margin_m, horizon_tan may each be NULL
 * (not all three). */
tp_status tp__shadow_sweep(const float* heights, size_t height_count, int width, int height,
                           double dx_m, double dy_m, double azimuth_deg, double elevation_deg,
                           uint8_t* lit, float* margin_m, float* horizon_tan, size_t out_count,
                           tp_error* err);

/* light_day.c, shared with light_times.c: the argument checks of tp_light_day_build; one map's
 * codes (0 lit, < 0 the horizon's excess, TP_LIGHT_DAY_VOID) with scratch lit (n bytes) and
 * horizon (n floats); the weight between two maps (tan(e) ta, tb) at which a sample whose
 * horizon tangent is th changes (rising_needed: it turns lit, so the sun must rise; 0.5 when
 * the elevation does not explain the change). */
tp_status tp__light_day_check(size_t height_count, int width, int height, const double* times_s,
                              int count, tp_error* err);
tp_status tp__light_day_codes(const float* heights, int width, int height, double dx_m, double dy_m,
                              double azimuth_deg, double elevation_deg, uint8_t* lit,
                              float* horizon, int16_t* codes, tp_error* err);
double tp__light_day_crossing(double ta, double tb, double th, int rising_needed);

#endif
