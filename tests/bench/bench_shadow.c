/* bench_shadow.c - the core's shadow sweep (tp_shadow_compute) against a per-sample ray cast
 * (march from every post toward the sun in quarter-post steps over the bilinear surface, as in
 * tests/test_shadow.c, stopping when the ray leaves the grid or rises above its highest
 * post), on the whole render grid of a DEM, for a few suns: times (the sweep's median of RUNS,
 * the ray cast's one run) and agreement over the valid posts; then the sun over a day
 * (tp_light_day_build of 64 maps, tp_light_day_at) on the same grid (docs/light.md).
 *
 *   tp_bench_shadow DEM [RUNS]
 */
#include "bench_util.h"
#include "tp_io.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define PI 3.14159265358979323846

static double bilinear(const float* z, int w, int h, double x, double y)
{
    if (!(x >= 0.0 && y >= 0.0 && x <= w - 1 && y <= h - 1))
        return NAN;
    int c = (int)floor(x), r = (int)floor(y);
    if (c > w - 2)
        c = w - 2;
    if (r > h - 2)
        r = h - 2;
    const double fx = x - c, fy = y - r;
    const double z00 = z[(size_t)r * w + c], z10 = z[(size_t)r * w + c + 1];
    const double z01 = z[(size_t)(r + 1) * w + c], z11 = z[(size_t)(r + 1) * w + c + 1];
    return (z00 * (1 - fx) + z10 * fx) * (1 - fy) + (z01 * (1 - fx) + z11 * fx) * fy;
}

static void ray_cast(const float* z, int w, int h, double dx, double dy, double az_deg,
                     double el_deg, double zmax, uint8_t* lit)
{
    const double az = az_deg * PI / 180.0, t = tan(el_deg * PI / 180.0);
    const double ux = sin(az) / dx, uy = -cos(az) / dy, step = 0.25 * (dx < dy ? dx : dy);
    for (int r = 0; r < h; ++r)
        for (int c = 0; c < w; ++c) {
            const size_t i = (size_t)r * w + c;
            const double z0 = z[i];
            if (z0 != z0) {
                lit[i] = 0;
                continue;
            }
            int up = 1;
            for (double d = step;; d += step) {
                const double x = c + ux * d, y = r + uy * d, ray = z0 + d * t;
                if (x < 0.0 || y < 0.0 || x > w - 1 || y > h - 1 || ray > zmax)
                    break;
                const double g = bilinear(z, w, h, x, y);
                if (g == g && g > ray) {
                    up = 0;
                    break;
                }
            }
            lit[i] = (uint8_t)up;
        }
}

int main(int argc, char** argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: tp_bench_shadow DEM [RUNS]\n");
        return 2;
    }
    const int runs = argc > 2 ? atoi(argv[2]) : 5;
    tp_error err;
    tp_dem* dem = NULL;
    tp_render_grid* g = NULL;
    if (tp_dem_read(argv[1], &dem, &err) != TP_OK ||
        tp_render_grid_build(dem, NULL, &g, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    tp_dem_destroy(dem);
    const int w = g->width, h = g->height;
    const size_t n = (size_t)w * h;
    const double dx = fabs(g->geotransform[1]), dy = fabs(g->geotransform[5]);
    float zmax = -INFINITY;
    size_t valid = 0;
    for (size_t i = 0; i < n; ++i)
        if (g->heights[i] == g->heights[i]) {
            valid++;
            zmax = g->heights[i] > zmax ? g->heights[i] : zmax;
        }
    printf("%s: %dx%d, %.1f m posts, %zu with a height\n", argv[1], w, h, g->spacing_m, valid);
    uint8_t* a = malloc(n);
    uint8_t* b = malloc(n);
    double* t = malloc(sizeof(double) * runs);
    const struct {
        double az, el;
    } suns[] = {{270.0, 5.0}, {135.0, 5.0}, {200.0, 15.0}, {45.0, 15.0}, {123.4, 30.0},
                {315.0, 45.0}};
    for (size_t k = 0; k < sizeof suns / sizeof suns[0]; ++k) {
        for (int r = 0; r < runs; ++r) {
            const double t0 = bench_now_ms();
            if (tp_shadow_compute(g->heights, n, w, h, dx, dy, suns[k].az, suns[k].el, a, NULL,
                                  n, &err) != TP_OK) {
                fprintf(stderr, "%s\n", err.message);
                return 1;
            }
            t[r] = bench_now_ms() - t0;
        }
        const double t1 = bench_now_ms();
        ray_cast(g->heights, w, h, dx, dy, suns[k].az, suns[k].el, zmax, b);
        const double t2 = bench_now_ms();
        size_t agree = 0, shadowed = 0;
        for (size_t i = 0; i < n; ++i)
            if (g->heights[i] == g->heights[i]) {
                agree += a[i] == b[i];
                shadowed += !b[i];
            }
        printf("sun %5.1f/%4.1f: sweep %7.1f ms (median of %d), ray cast %8.1f ms (x%.0f); agree "
               "%.3f%%, %.1f%% in shadow\n",
               suns[k].az, suns[k].el, bench_median(t, runs), runs, t2 - t1,
               (t2 - t1) / bench_median(t, runs), 100.0 * agree / valid, 100.0 * shadowed / valid);
    }
    /* a day: 64 maps over 12 hours, the sun from 2 to 60 degrees and back, east to west */
    enum { K = TP_LIGHT_DAY_MAPS };
    double times[K], az[K], el[K];
    for (int k = 0; k < K; ++k) {
        times[k] = 43200.0 * k / (K - 1);
        az[k] = 80.0 + 200.0 * k / (K - 1);
        el[k] = 2.0 + 58.0 * sin(PI * k / (K - 1));
    }
    tp_light_day* day = NULL;
    const double t3 = bench_now_ms();
    if (tp_light_day_build(g->heights, n, w, h, dx, dy, times, az, el, K, &day, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    const double t4 = bench_now_ms();
    for (int r = 0; r < runs; ++r) {
        const double t0 = bench_now_ms();
        tp_light_day_at(day, 1234.5 + 1000.0 * r, a, n, &err);
        t[r] = bench_now_ms() - t0;
    }
    printf("day of %d maps: build %.0f ms, %.1f MB; shadows at a time %.1f ms (median of %d)\n",
           K, t4 - t3, (double)K * n * sizeof(int16_t) / 1e6, bench_median(t, runs), runs);
    tp_light_day_destroy(day);
    free(a);
    free(b);
    free(t);
    tp_render_grid_destroy(g);
    return 0;
}
