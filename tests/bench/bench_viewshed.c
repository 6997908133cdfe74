/* bench_viewshed.c - the core's viewshed (tp_viewshed_compute) against GDAL's
 * (tp_gdal_viewshed, GDALViewshedGenerate) on the same grid in the same run, alternated,
 * medians of N runs each: a 20 km radius on 30 m posts (docs/PERFORMANCE.md, "Viewshed").
 *
 *   tp_bench_viewshed DEM [RADIUS_M [RUNS]]
 *
 * Ours twice: as it runs by default (exact within TP_VIEWSHED_EXACT_RADIUS_PX posts of the
 * observer) and interpolated everywhere (exact_radius_px 0: GDAL's GVM_Edge, which "agree" is
 * measured with). Two grids: the DEM's render grid with the observer at its centre, and a 3601 x 3601 grid
 * (an SRTM1 tile's size) made of the render grid mirrored again and again (real relief,
 * continuous at the seams) with the same post spacing, observer at its centre. */
#include "bench_util.h"
#include "tp_io.h"

#include <stdio.h>
#include <string.h>

static void run(const char* name, const float* z, int w, int h, const double gt[6], int ox,
                int oy, double radius_m, int runs)
{
    tp_viewshed_options o = tp_viewshed_options_default();
    o.radius_m = radius_m;
    const size_t n = (size_t)w * h;
    uint8_t* a = malloc(n);
    uint8_t* b = malloc(n);
    uint8_t* c = malloc(n);
    double* ta = malloc(sizeof(double) * runs);
    double* tb = malloc(sizeof(double) * runs);
    double* tc = malloc(sizeof(double) * runs);
    tp_viewshed_options edge = o;
    edge.exact_radius_px = 0;
    tp_error err;
    size_t in_disk = 0, exact_changed = 0;
    for (int r = 0; r < runs; ++r) {
        double t0 = bench_now_ms();
        if (tp_viewshed_compute(z, n, w, h, gt, ox, oy, &o, a, n, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            exit(1);
        }
        double t1 = bench_now_ms();
        if (tp_gdal_viewshed(z, n, w, h, gt, ox, oy, &o, b, n, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            exit(1);
        }
        double t2 = bench_now_ms();
        if (tp_viewshed_compute(z, n, w, h, gt, ox, oy, &edge, c, n, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            exit(1);
        }
        double t3 = bench_now_ms();
        ta[r] = t1 - t0;
        tb[r] = t2 - t1;
        tc[r] = t3 - t2;
    }
    size_t agree = 0;
    const double r2 = radius_m > 0 ? radius_m * radius_m : 1e300;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            const double dx = (x - ox) * gt[1], dy = (y - oy) * gt[5];
            const size_t i = (size_t)y * w + x;
            if (dx * dx + dy * dy <= r2 && z[i] == z[i]) {
                in_disk++;
                agree += c[i] == b[i];
                exact_changed += a[i] != c[i];
            }
        }
    const double ma = bench_median(ta, runs), mb = bench_median(tb, runs),
                 mc = bench_median(tc, runs);
    printf("%-28s %5dx%-5d obs (%d,%d) radius %.0f m: %zu samples in range; ours %.2f ms "
           "(interpolated everywhere %.2f ms; the exact square changes %zu samples), GDAL %.2f ms "
           "(x%.1f); interpolated agrees with GDAL on %.3f%% (medians of %d)\n",
           name, w, h, ox, oy, radius_m, in_disk, ma, mc, exact_changed, mb, mb / ma,
           100.0 * agree / in_disk, runs);
    free(a);
    free(b);
    free(c);
    free(ta);
    free(tb);
    free(tc);
}

int main(int argc, char** argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: tp_bench_viewshed DEM [RADIUS_M [RUNS]]\n");
        return 2;
    }
    const double radius_m = argc > 2 ? atof(argv[2]) : 20000.0;
    const int runs = argc > 3 ? atoi(argv[3]) : 5;
    tp_error err;
    tp_dem* dem = NULL;
    tp_render_grid* g = NULL;
    if (tp_dem_read(argv[1], &dem, &err) != TP_OK ||
        tp_render_grid_build(dem, NULL, &g, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    tp_dem_destroy(dem);
    printf("%s: %dx%d, %.1f m posts\n", argv[1], g->width, g->height, g->spacing_m);
    int ox = g->width / 2, oy = g->height / 2;
    run("render grid", g->heights, g->width, g->height, g->geotransform, ox, oy, radius_m, runs);

    /* 3601 x 3601 mirrored: sample (x, y) is source (m(x, w), m(y, h)), m folding back and
     * forth over 0 .. w-1 */
    enum { S = 3601 };
    float* big = malloc(sizeof(float) * S * S);
    for (int y = 0; y < S; ++y) {
        int p = 2 * (g->height - 1), j = y % p;
        j = j < g->height ? j : p - j;
        for (int x = 0; x < S; ++x) {
            int q = 2 * (g->width - 1), i = x % q;
            i = i < g->width ? i : q - i;
            float v = g->heights[(size_t)j * g->width + i];
            big[(size_t)y * S + x] = v == v ? v : 1000.0f; /* voids: flat ground */
        }
    }
    run("3601^2 mirrored", big, S, S, g->geotransform, S / 2, S / 2, radius_m, runs);
    /* the same radius, observer near a corner: the window is a quarter */
    run("3601^2 mirrored, corner", big, S, S, g->geotransform, 300, 300, radius_m, runs);
    free(big);
    tp_render_grid_destroy(g);
    return 0;
}
