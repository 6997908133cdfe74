/*
 * tp_test_observers.h - observers on real render grids for the viewshed's tests and bench
 * (test_viewshed.c, bench/bench_viewshed_grazing.c): a summit, a valid post near a place, a
 * coast and a plain, found by simple rules on the heights so that tests and bench agree on them.
 * Each returns 1 and sets (*x, *y), or 0 when the grid has no such post.
 */
#ifndef TP_TEST_OBSERVERS_H
#define TP_TEST_OBSERVERS_H

#include "tp_io.h"

#include <math.h>

/* The highest valid post. */
static inline int tp_test_summit(const tp_render_grid* g, int* x, int* y)
{
    float best = -INFINITY;
    for (int j = 0; j < g->height; ++j)
        for (int i = 0; i < g->width; ++i) {
            const float v = g->heights[(size_t)j * g->width + i];
            if (v == v && v > best) {
                best = v;
                *x = i;
                *y = j;
            }
        }
    return best > -INFINITY;
}

/* A valid post near (*x, *y), searching outwards along the row, then the next rows. */
static inline int tp_test_valid_near(const tp_render_grid* g, int* x, int* y)
{
    for (int r = 0; r < g->width; ++r)
        for (int d = -r; d <= r; ++d) {
            const int i = *x + d, j = *y + r;
            if (i >= 0 && i < g->width && j >= 0 && j < g->height &&
                g->heights[(size_t)j * g->width + i] == g->heights[(size_t)j * g->width + i]) {
                *x = i;
                *y = j;
                return 1;
            }
        }
    return 0;
}

/* A land post 20-80 m high with at least 10 sea posts (height exactly 0, as SRTM's sea) within
 * 3 posts; of those, the one with the most sea within 100 posts: a coastal observer. */
static inline int tp_test_coast(const tp_render_grid* g, int* ox, int* oy)
{
    const int w = g->width, h = g->height;
    int best = -1;
    for (int y = 3; y < h - 3; ++y)
        for (int x = 3; x < w - 3; ++x) {
            const float z = g->heights[(size_t)y * w + x];
            if (!(z >= 20.0f && z <= 80.0f))
                continue;
            int near = 0, far = 0;
            for (int j = -3; j <= 3; ++j)
                for (int i = -3; i <= 3; ++i)
                    near += g->heights[(size_t)(y + j) * w + x + i] == 0.0f;
            if (near < 10)
                continue;
            for (int j = -100; j <= 100; j += 10)
                for (int i = -100; i <= 100; i += 10)
                    far += x + i >= 0 && x + i < w && y + j >= 0 && y + j < h &&
                           g->heights[(size_t)(y + j) * w + x + i] == 0.0f;
            if (far > best) {
                best = far;
                *ox = x;
                *oy = y;
            }
        }
    return best > 0;
}

/* The lowest post above 1 m at least 150 posts from the edges: on N41E001 the coastal plain. */
static inline int tp_test_plain(const tp_render_grid* g, int* ox, int* oy)
{
    float best = INFINITY;
    for (int y = 150; y < g->height - 150; ++y)
        for (int x = 150; x < g->width - 150; ++x) {
            const float z = g->heights[(size_t)y * g->width + x];
            if (z == z && z > 1.0f && z < best) {
                best = z;
                *ox = x;
                *oy = y;
            }
        }
    return best < INFINITY;
}

#endif /* TP_TEST_OBSERVERS_H */
