/* bench_ground.c - the cost of a full-resolution ground query (app/scene/ground.c), the building
 * block of `terrapatch point` now and of line of sight, viewsheds and profiles next (not a
 * test; not run by ctest).
 *
 *   build/tp_bench_ground STORE.tpt [cache_mb]
 *
 * Three patterns, each run 3 times alternated on a fresh tp_ground (cold cache), medians
 * printed in microseconds per query:
 *   line    heights one post apart along a straight line across the grid (a sight line);
 *   random  heights at uniformly random positions (every query a different leaf: the store
 *           read and decode dominate);
 *   full    tp_ground_query_grid along the same line (height, slope, aspect, convergence). */
#define _POSIX_C_SOURCE 200809L
#include "ground.h"
#include "store_scene.h"
#include "bench_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

enum { LINE, RANDOM, FULL, PATTERNS };
static const char* names[PATTERNS] = {"line", "random", "full"};

static double run(const tp_store_scene* sc, size_t cache_bytes, int pattern, int count,
                  size_t* reads)
{
    tp_ground* g = NULL;
    if (tp_ground_create(sc, &(tp_ground_options){.cache_bytes = cache_bytes}, &g, NULL) != TP_OK)
        exit(1);
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    double w = geom->src_width - 1, h = geom->src_height - 1, sum = 0;
    unsigned seed = 12345;
    double t0 = bench_now_ms();
    for (int i = 0; i < count; ++i) {
        double x, y, v = 0;
        if (pattern == RANDOM) {
            seed = seed * 1103515245u + 12345u;
            x = (seed >> 8) % 65536 / 65535.0 * w;
            seed = seed * 1103515245u + 12345u;
            y = (seed >> 8) % 65536 / 65535.0 * h;
        } else { /* the diagonal, one post apart (wrapping) */
            double t = fmod(i * 0.7071, fmin(w, h));
            x = t + 0.25;
            y = t + 0.25;
        }
        if (pattern == FULL) {
            tp_ground_sample s;
            if (tp_ground_query_grid(g, x, y, &s, NULL) == TP_OK)
                v = s.slope_deg;
        } else {
            tp_ground_height(g, x, y, &v, NULL);
        }
        sum += isnan(v) ? 0 : v;
    }
    double us = (bench_now_ms() - t0) * 1000.0 / count;
    *reads = tp_ground_reads(g);
    tp_ground_destroy(g);
    if (sum == 12345.678)
        printf("!"); /* keep the loop */
    return us;
}

int main(int argc, char** argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: tp_bench_ground STORE.tpt [cache_mb]\n");
        return 2;
    }
    size_t cache_bytes = (size_t)(argc > 2 ? atof(argv[2]) : 16) << 20;
    tp_store_scene sc;
    if (tp_store_scene_open(argv[1], &sc) != 0)
        return 1;
    const int count = 20000;
    double t[PATTERNS][3];
    size_t reads[PATTERNS] = {0};
    for (int rep = 0; rep < 3; ++rep)
        for (int p = 0; p < PATTERNS; ++p)
            t[p][rep] = run(&sc, cache_bytes, p, count, &reads[p]);
    printf("%s: %dx%d, leaves of %d, cache %zu MiB, %d queries per run\n", argv[1],
           sc.info.header.geometry.src_width, sc.info.header.geometry.src_height,
           (1 << sc.info.header.geometry.n) + 1, cache_bytes >> 20, count);
    for (int p = 0; p < PATTERNS; ++p)
        printf("  %-7s %8.3f us/query (median of 3), %zu leaves read per run\n", names[p],
               bench_median(t[p], 3), reads[p]);
    tp_store_scene_close(&sc);
    return 0;
}
