/*
 * light_times.c - the sun over a day as each sample's lit intervals (tp_core.h, "light
 * times"): Blow's maps computed one after another, each sample's changes between two maps
 * placed where tp_light_day_at's interpolation puts them, and the intervals in which it is lit
 * kept (at most two) and quantised to a byte each end.
 */
#include "light_int.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

/* tan(e) of a map as tp_light_day_at takes it (the zenith capped at 89 degrees) */
static double map_tan(double elevation_deg)
{
    return tan((elevation_deg >= 89.0 ? 89.0 : elevation_deg) * PI / 180.0);
}

/* A sample's day so far, times in seconds from the first map: the interval it is lit in now
 * (open >= 0) and at most two closed ones. */
typedef struct day_state {
    float open;
    float r[2], s[2];
} day_state;

typedef struct simplify_stats {
    size_t simplified;
    double given_up_max_s;
} simplify_stats;

/* Closes [state->open, t) and keeps the two intervals that lose least. */
static void close_interval(day_state* d, uint8_t* kept, float t, uint8_t* counted,
                           simplify_stats* st)
{
    const float r = d->open;
    d->open = -1.0f;
    if (!(t > r))
        return;
    if (*kept < 2) {
        d->r[*kept] = r, d->s[*kept] = t;
        ++*kept;
        return;
    }
    /* three intervals: bridge the shorter gap or drop the shortest interval */
    const float rr[3] = {d->r[0], d->r[1], r}, ss[3] = {d->s[0], d->s[1], t};
    double best = INFINITY;
    int how = 0; /* 0, 1: bridge gap after interval how; 2..4: drop interval how - 2 */
    for (int g = 0; g < 2; ++g)
        if (rr[g + 1] - ss[g] < best)
            best = rr[g + 1] - ss[g], how = g;
    for (int i = 0; i < 3; ++i)
        if (ss[i] - rr[i] < best)
            best = ss[i] - rr[i], how = 2 + i;
    float nr[2], ns[2];
    if (how < 2) {
        const int g = how;
        int j = 0;
        for (int i = 0; i < 3; ++i) {
            if (i == g + 1) {
                ns[j - 1] = ss[i];
                continue;
            }
            nr[j] = rr[i], ns[j] = ss[i], ++j;
        }
    } else {
        int j = 0;
        for (int i = 0; i < 3; ++i)
            if (i != how - 2)
                nr[j] = rr[i], ns[j] = ss[i], ++j;
    }
    memcpy(d->r, nr, sizeof nr);
    memcpy(d->s, ns, sizeof ns);
    if (!*counted) {
        *counted = 1;
        st->simplified++;
    }
    if (best > st->given_up_max_s)
        st->given_up_max_s = best;
}

static uint8_t quantise(double t, double span)
{
    const double tau = TP_LIGHT_TIMES_STEPS * t / span;
    return (uint8_t)(tau <= 0 ? 0 : tau >= TP_LIGHT_TIMES_STEPS ? TP_LIGHT_TIMES_STEPS
                                                                : (int)lround(tau));
}

static void encode(const day_state* d, int kept, double span, uint8_t out[4])
{
    uint8_t q[4] = {0, 0, 0, 0};
    int m = 0;
    for (int i = 0; i < kept; ++i) {
        const uint8_t a = quantise(d->r[i], span), b = quantise(d->s[i], span);
        if (b > a) /* shorter than a step: lit at no step */
            q[2 * m] = a, q[2 * m + 1] = b, ++m;
    }
    if (m == 1)
        q[2] = q[3] = q[1];
    memcpy(out, q, 4);
}

tp_status tp_light_times_build(const float* heights, size_t height_count, int width, int height,
                               double dx_m, double dy_m, const double* times_s,
                               const double* azimuth_deg, const double* elevation_deg, int count,
                               uint8_t* out, size_t out_count, tp_light_times_stats* stats,
                               void (*progress)(void* user, double fraction), void* user,
                               tp_error* err)
{
    assert(heights && times_s && azimuth_deg && elevation_deg && out);
    tp_status s = tp__light_day_check(height_count, width, height, times_s, count, err);
    if (s != TP_OK)
        return s;
    const size_t n = height_count;
    assert(out_count >= 4 * n);
    (void)out_count;
    int16_t* codes[2] = {malloc(n * sizeof(int16_t)), malloc(n * sizeof(int16_t))};
    float* horizon = malloc(n * sizeof *horizon);
    uint8_t* lit = malloc(n);
    uint8_t* kept = calloc(n, 1);    /* closed intervals kept: 0..2 */
    uint8_t* counted = calloc(n, 1); /* simplified at least once */
    day_state* day = malloc(n * sizeof *day);
    if (!codes[0] || !codes[1] || !horizon || !lit || !kept || !counted || !day) {
        s = tp_error_set(err, TP_ERR_OUT_OF_MEMORY,
                         "light times: out of memory for a %dx%d grid", width, height);
        goto done;
    }
    simplify_stats st = {0, 0.0};
    const double t0 = times_s[0];
    for (int k = 0; k < count; ++k) {
        int16_t* b = codes[k & 1];
        const int16_t* a = codes[(k + 1) & 1];
        s = tp__light_day_codes(heights, width, height, dx_m, dy_m, azimuth_deg[k],
                                elevation_deg[k], lit, horizon, b, err);
        if (s != TP_OK)
            goto done;
        if (k == 0) {
            for (size_t i = 0; i < n; ++i)
                day[i].open = b[i] == 0 ? 0.0f : -1.0f;
        } else {
            const double ta = map_tan(elevation_deg[k - 1]), tb = map_tan(elevation_deg[k]);
            const double ts = times_s[k - 1] - t0, span = times_s[k] - times_s[k - 1];
            for (size_t i = 0; i < n; ++i) {
                if (b[i] == TP_LIGHT_DAY_VOID || (a[i] == 0) == (b[i] == 0))
                    continue;
                if (a[i] == 0) { /* the sun sinks past a horizon tb + excess */
                    const double th = tb - b[i] * TP_LIGHT_DAY_TAN_STEP;
                    const double w = tp__light_day_crossing(ta, tb, th, 0);
                    close_interval(&day[i], &kept[i], (float)(ts + w * span), &counted[i],
                                   &st);
                } else { /* it rises past ta + excess */
                    const double th = ta - a[i] * TP_LIGHT_DAY_TAN_STEP;
                    day[i].open = (float)(ts + tp__light_day_crossing(ta, tb, th, 1) * span);
                }
            }
        }
        if (progress)
            progress(user, (k + 1.0) / count);
    }
    const double day_s = times_s[count - 1] - t0;
    size_t lit_any = 0;
    for (size_t i = 0; i < n; ++i) {
        if (day[i].open >= 0.0f)
            close_interval(&day[i], &kept[i], (float)day_s, &counted[i], &st);
        encode(&day[i], kept[i], day_s, out + 4 * i);
        lit_any += out[4 * i + 3] != 0;
    }
    if (stats) {
        stats->samples = n;
        stats->simplified = st.simplified;
        stats->given_up_max_s = st.given_up_max_s;
        stats->lit_any = lit_any;
    }
done:
    free(horizon);
    free(lit);
    free(codes[0]);
    free(codes[1]);
    free(kept);
    free(counted);
    free(day);
    return s;
}

double tp_light_times_tau(double t_first_s, double t_last_s, double time_s)
{
    return TP_LIGHT_TIMES_STEPS * (time_s - t_first_s) / (t_last_s - t_first_s);
}

int tp_light_times_lit(const uint8_t texel[4], double tau)
{
    return (texel[0] <= tau && tau < texel[1]) || (texel[2] <= tau && tau < texel[3]);
}

void tp_light_times_mean(const uint8_t* const* texels, int n, uint8_t out[4])
{
    assert(n >= 1 && n <= 4);
    for (int c = 0; c < 4; ++c) {
        int sum = 0;
        for (int i = 0; i < n; ++i)
            sum += texels[i][c];
        out[c] = (uint8_t)((sum + n / 2) / n);
    }
}
