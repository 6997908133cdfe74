/*
 * light_day.c - the sun over a day (tp_core.h, "Shadows"): the shadows of a series of sun
 * positions, each shadowed sample stored with its horizon's excess over the sun, and the
 * shadows at any time between two maps, where a sample that changes changes when the sun's
 * elevation passes its horizon (Blow's 64 illumination maps, interpolated in time).
 */
#include "light_int.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define CODE_MAX 32767

static double tan_deg(double deg) { return tan(deg * PI / 180.0); }

void tp_light_day_destroy(tp_light_day* day)
{
    if (!day)
        return;
    free(day->times_s);
    free(day->azimuth_deg);
    free(day->elevation_deg);
    free(day->codes);
    free(day);
}

tp_status tp__light_day_check(size_t height_count, int width, int height,
                              const double* times_s, int count, tp_error* err)
{
    if (count < 2)
        return tp_error_set(err, TP_ERR_INVALID_ARG, "light day: %d maps, at least 2 needed",
                            count);
    for (int k = 0; k < count; ++k)
        if (!isfinite(times_s[k]) || (k > 0 && !(times_s[k] > times_s[k - 1])))
            return tp_error_set(err, TP_ERR_INVALID_ARG,
                                "light day: time %d (%g) is not finite and after the one "
                                "before",
                                k, times_s[k]);
    if (width < 1 || height < 1 || (size_t)width * (size_t)height != height_count)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "light day: a %dx%d grid needs width * height heights, got %zu",
                            width, height, height_count);
    return TP_OK;
}

tp_status tp__light_day_codes(const float* heights, int width, int height, double dx_m,
                              double dy_m, double azimuth_deg, double elevation_deg,
                              uint8_t* lit, float* horizon, int16_t* codes, tp_error* err)
{
    const size_t n = (size_t)width * height;
    tp_status s = tp__shadow_sweep(heights, n, width, height, dx_m, dy_m, azimuth_deg,
                                   elevation_deg, lit, NULL, horizon, n, err);
    if (s != TP_OK)
        return s;
    const double te = elevation_deg >= 90.0 ? INFINITY : tan_deg(elevation_deg);
    for (size_t i = 0; i < n; ++i) {
        if (heights[i] != heights[i]) {
            codes[i] = TP_LIGHT_DAY_VOID;
        } else if (lit[i]) {
            codes[i] = 0;
        } else {
            const double units = ceil((horizon[i] - te) / TP_LIGHT_DAY_TAN_STEP);
            codes[i] = (int16_t)-(units < 1.0 ? 1 : units > CODE_MAX ? CODE_MAX : (int)units);
        }
    }
    return TP_OK;
}

tp_status tp_light_day_build(const float* heights, size_t height_count, int width, int height,
                             double dx_m, double dy_m, const double* times_s,
                             const double* azimuth_deg, const double* elevation_deg, int count,
                             tp_light_day** out, tp_error* err)
{
    assert(heights && times_s && azimuth_deg && elevation_deg && out);
    tp_status checked = tp__light_day_check(height_count, width, height, times_s, count, err);
    if (checked != TP_OK)
        return checked;
    const size_t n = height_count;
    tp_light_day* d = calloc(1, sizeof *d);
    float* horizon = malloc(n * sizeof *horizon);
    uint8_t* lit = malloc(n);
    if (d) {
        d->times_s = malloc((size_t)count * sizeof(double));
        d->azimuth_deg = malloc((size_t)count * sizeof(double));
        d->elevation_deg = malloc((size_t)count * sizeof(double));
        d->codes = malloc((size_t)count * n * sizeof(int16_t));
    }
    if (!d || !horizon || !lit || !d->times_s || !d->azimuth_deg || !d->elevation_deg ||
        !d->codes) {
        tp_light_day_destroy(d);
        free(horizon);
        free(lit);
        return tp_error_set(err, TP_ERR_OUT_OF_MEMORY,
                            "light day: out of memory for %d maps of %dx%d", count, width,
                            height);
    }
    d->width = width;
    d->height = height;
    d->count = count;
    for (int k = 0; k < count; ++k) {
        tp_status s = tp__light_day_codes(heights, width, height, dx_m, dy_m, azimuth_deg[k],
                                          elevation_deg[k], lit, horizon,
                                          d->codes + (size_t)k * n, err);
        if (s != TP_OK) {
            tp_light_day_destroy(d);
            free(horizon);
            free(lit);
            return s;
        }
        d->times_s[k] = times_s[k];
        d->azimuth_deg[k] = azimuth_deg[k];
        d->elevation_deg[k] = elevation_deg[k];
    }
    free(horizon);
    free(lit);
    *out = d;
    return TP_OK;
}

/* The weight (0 .. 1 from map a to map b) at which a sample shadowed in one map, with horizon
 * tangent th, and lit in the other changes: where the interpolated tan(e) passes th. 0.5 when
 * the elevation does not explain the change. */
double tp__light_day_crossing(double ta, double tb, double th, int rising_needed)
{
    if (rising_needed ? !(tb > ta) : !(ta > tb))
        return 0.5;
    const double w = (th - ta) / (tb - ta);
    return w < 0.0 ? 0.0 : w > 1.0 ? 1.0 : w;
}

tp_status tp_light_day_at(const tp_light_day* day, double time_s, uint8_t* lit,
                          size_t out_count, tp_error* err)
{
    assert(day && lit);
    const size_t n = (size_t)day->width * day->height;
    assert(out_count >= n);
    (void)out_count;
    const double t0 = day->times_s[0], t1 = day->times_s[day->count - 1];
    if (!(time_s >= t0 && time_s <= t1))
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "light day: time %.0f is outside the maps' %.0f .. %.0f", time_s, t0,
                            t1);
    int k = 0;
    while (k + 2 < day->count && day->times_s[k + 1] <= time_s)
        ++k;
    const double w = (time_s - day->times_s[k]) / (day->times_s[k + 1] - day->times_s[k]);
    const double ea = day->elevation_deg[k], eb = day->elevation_deg[k + 1];
    /* tan(e) of the maps; the zenith's infinity capped (no shadow there anyway) */
    const double ta = ea >= 89.0 ? tan_deg(89.0) : tan_deg(ea);
    const double tb = eb >= 89.0 ? tan_deg(89.0) : tan_deg(eb);
    const int16_t* a = day->codes + (size_t)k * n;
    const int16_t* b = a + n;
    for (size_t i = 0; i < n; ++i) {
        if (a[i] == TP_LIGHT_DAY_VOID) {
            lit[i] = TP_SHADOW_SHADOWED;
        } else if ((a[i] == 0) == (b[i] == 0)) {
            lit[i] = a[i] == 0 ? TP_SHADOW_LIT : TP_SHADOW_SHADOWED;
        } else if (a[i] == 0) {
            /* lit, then shadowed under a horizon tan(h) = tb + excess: the sun sinks past it */
            const double th = tb - b[i] * TP_LIGHT_DAY_TAN_STEP;
            lit[i] = w < tp__light_day_crossing(ta, tb, th, 0) ? TP_SHADOW_LIT : TP_SHADOW_SHADOWED;
        } else {
            /* shadowed under tan(h) = ta + excess, then lit: the sun rises past it */
            const double th = ta - a[i] * TP_LIGHT_DAY_TAN_STEP;
            lit[i] = w >= tp__light_day_crossing(ta, tb, th, 1) ? TP_SHADOW_LIT : TP_SHADOW_SHADOWED;
        }
    }
    return TP_OK;
}
