/* bench_viewshed_grazing.c - the viewshed's accuracy against the exact ray test (R3) and its
 * time, on summit, valley, plain and coast observers of real render grids (docs/PERFORMANCE.md,
 * "Viewshed: grazing sight lines"; issue 31). Per case, alternated in one run, medians of RUNS:
 *   - ours as it runs now (exact within TP_VIEWSHED_EXACT_RADIUS_PX, the grazing check beyond,
 *     the two halves of the sweep on two threads), and the same on one thread;
 *   - ours as it ran before the grazing check (exact within 64 posts, interpolated beyond, one
 *     thread);
 *   - ours interpolated everywhere (GDAL's GVM_Edge propagation), one thread;
 *   - GDAL's own GDALViewshedGenerate (tp_gdal_viewshed: gdal_viewshed's library form);
 *   - R3 itself on every sample of the disc (tp_test_r3.h: one sight line per sample).
 * and for each, the samples of the disc (valid, not the observer's eight neighbours) where it
 * and R3 disagree.
 *
 *   tp_bench_viewshed_grazing [DATA_DIR [RUNS]]   (DATA_DIR: the repository's data/, the default)
 */
#include "bench_util.h"
#include "../tp_test_observers.h"
#include "../tp_test_r3.h"

#include <stdio.h>
#include <string.h>

enum { OURS, OURS_ONE, BEFORE, INTERPOLATED, GDAL, R3, KINDS };
static const char* const KIND_NAMES[KINDS] = {"ours now", "ours now on one thread",
                                              "ours before (one thread, as it ran)",
                                              "interpolated (one thread)", "GDAL 3.6",
                                              "R3 (exact)"};

static void compute(int kind, const tp_render_grid* g, int ox, int oy, double radius_m,
                    uint8_t* out)
{
    const int w = g->width, h = g->height;
    const size_t n = (size_t)w * h;
    tp_viewshed_options o = tp_viewshed_options_default();
    o.radius_m = radius_m;
    if (kind == BEFORE || kind == INTERPOLATED) {
        o.exact_radius_px = kind == BEFORE ? 64 : 0;
        o.grazing_check = 0;
    }
    if (kind != OURS)
        o.threads = 1;
    tp_error err;
    tp_status s = TP_OK;
    if (kind == GDAL) {
        s = tp_gdal_viewshed(g->heights, n, w, h, g->geotransform, ox, oy, &o, out, n, &err);
    } else if (kind == R3) {
        const tp_test_r3 r3 = {o.observer_height_m, o.target_height_m, o.curvature_coeff, 0, 0};
        const int rx = (int)(radius_m / fabs(g->geotransform[1])) + 1;
        const int ry = (int)(radius_m / fabs(g->geotransform[5])) + 1;
        memset(out, 0, n);
        for (int y = oy - ry > 0 ? oy - ry : 0; y < h && y <= oy + ry; ++y)
            for (int x = ox - rx > 0 ? ox - rx : 0; x < w && x <= ox + rx; ++x)
                out[(size_t)y * w + x] =
                    tp_test_r3_clearance(g->heights, w, g->geotransform, ox, oy, x, y, &r3) >=
                            -1e-9
                        ? TP_VIEWSHED_VISIBLE
                        : TP_VIEWSHED_HIDDEN;
    } else {
        s = tp_viewshed_compute(g->heights, n, w, h, g->geotransform, ox, oy, &o, out, n, &err);
    }
    if (s != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        exit(1);
    }
}

static void run(const char* name, const tp_render_grid* g, int ox, int oy, double radius_m,
                int runs)
{
    const size_t n = (size_t)g->width * g->height;
    uint8_t* out[KINDS];
    double* t[KINDS];
    for (int k = 0; k < KINDS; ++k) {
        out[k] = malloc(n);
        t[k] = malloc(sizeof(double) * runs);
    }
    for (int r = 0; r < runs; ++r)
        for (int k = 0; k < KINDS; ++k) {
            const double t0 = bench_now_ms();
            compute(k, g, ox, oy, radius_m, out[k]);
            t[k][r] = bench_now_ms() - t0;
        }
    size_t samples = 0, wrong[KINDS] = {0};
    for (int y = 0; y < g->height; ++y)
        for (int x = 0; x < g->width; ++x) {
            const size_t i = (size_t)y * g->width + x;
            const int ax = abs(x - ox), ay = abs(y - oy);
            if (g->heights[i] != g->heights[i] || (ax <= 1 && ay <= 1) ||
                hypot(ax * g->geotransform[1], ay * g->geotransform[5]) > radius_m)
                continue;
            samples++;
            for (int k = 0; k < KINDS; ++k)
                wrong[k] += (out[k][i] == TP_VIEWSHED_VISIBLE) != (out[R3][i] == TP_VIEWSHED_VISIBLE);
        }
    printf("| %s, %.0f m, %.0f km | %zu |", name, g->heights[(size_t)oy * g->width + ox],
           radius_m / 1000, samples);
    for (int k = 0; k < KINDS; ++k) {
        if (k == R3)
            printf(" %.0f ms |", bench_median(t[k], runs));
        else
            printf(" %.1f ms, %.3f%% |", bench_median(t[k], runs), 100.0 * wrong[k] / samples);
        free(out[k]);
        free(t[k]);
    }
    printf("\n");
    fflush(stdout);
}

static tp_render_grid* grid(const char* dir, const char* file)
{
    char path[1024];
    snprintf(path, sizeof path, "%s/%s", dir, file);
    tp_error err;
    tp_dem* dem = NULL;
    tp_render_grid* g = NULL;
    if (tp_dem_read(path, &dem, &err) != TP_OK ||
        tp_render_grid_build(dem, NULL, &g, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        exit(1);
    }
    tp_dem_destroy(dem);
    return g;
}

int main(int argc, char** argv)
{
    const char* dir = argc > 1 ? argv[1] : "data";
    const int runs = argc > 2 ? atoi(argv[2]) : 5;
    if (runs < 1) {
        fprintf(stderr, "usage: tp_bench_viewshed_grazing [DATA_DIR [RUNS]] (RUNS >= 1)\n");
        return 2;
    }
    printf("| observer, ground, radius | samples | ");
    for (int k = 0; k < KINDS; ++k)
        printf("%s%s |", KIND_NAMES[k], k == R3 ? "" : ": time, wrong");
    printf("\n|---|---:|---:|---:|---:|---:|---:|---:|\n");
    int x = 0, y = 0;
    tp_render_grid* g = grid(dir, "N41E001.hgt");
    if (tp_test_coast(g, &x, &y))
        run("N41E001 coast", g, x, y, 15000.0, runs);
    if (tp_test_plain(g, &x, &y))
        run("N41E001 coastal plain (valley floor)", g, x, y, 15000.0, runs);
    tp_test_summit(g, &x, &y);
    run("N41E001 summit", g, x, y, 15000.0, runs);
    tp_render_grid_destroy(g);
    g = grid(dir, "N42E001.hgt");
    x = g->width / 2, y = g->height / 2;
    tp_test_valid_near(g, &x, &y);
    run("N42E001 centre (valley side)", g, x, y, 15000.0, runs);
    tp_test_summit(g, &x, &y);
    run("N42E001 summit", g, x, y, 15000.0, runs);
    tp_render_grid_destroy(g);
    g = grid(dir, "lf_elev_220_mt_hood_utm.tif");
    tp_test_summit(g, &x, &y);
    run("Mt Hood summit", g, x, y, 10000.0, runs);
    tp_render_grid_destroy(g);
    return 0;
}
