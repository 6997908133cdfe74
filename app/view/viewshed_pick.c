/* viewshed_pick.c - the viewer's viewshed overlay (viewshed_pick.h). */
#define _POSIX_C_SOURCE 200809L
#include "viewshed_pick.h"
#include "clock.h"

#include "tp_core.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

void tp_view_viewshed_free(tp_view_viewshed* vs)
{
    free(vs->enh);
    memset(vs, 0, sizeof *vs);
}

int tp_view_viewshed_at(tp_view_viewshed* vs, tp_ground* g, double e_m, double n_m,
                        double radius_m, char* line, size_t cap)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    const double* gt = sc->info.header.geotransform;
    double fx, fy;
    tp_tree_world_to_grid(sc->tree, e_m, n_m, &fx, &fy);
    const int ox = (int)lround(fx), oy = (int)lround(fy);
    if (ox < 0 || oy < 0 || ox >= geom->src_width || oy >= geom->src_height) {
        snprintf(line, cap, "viewshed: the observer is outside the DEM");
        return 0;
    }
    const int rx = (int)floor(radius_m / fabs(gt[1])), ry = (int)floor(radius_m / fabs(gt[5]));
    const int x0 = ox - rx > 0 ? ox - rx : 0, y0 = oy - ry > 0 ? oy - ry : 0;
    const int x1 = ox + rx < geom->src_width - 1 ? ox + rx : geom->src_width - 1;
    const int y1 = oy + ry < geom->src_height - 1 ? oy + ry : geom->src_height - 1;
    const int w = x1 - x0 + 1, h = y1 - y0 + 1;
    const size_t n = (size_t)w * h;
    float* z = malloc(n * sizeof *z);
    uint8_t* seen = malloc(n);
    tp_error err = {{0}};
    tp_status st = z && seen ? TP_OK : tp_error_set(&err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    const double t0 = tp_clock_s();
    for (int y = 0; y < h && st == TP_OK; ++y)
        for (int x = 0; x < w && st == TP_OK; ++x) {
            double v;
            st = tp_ground_height(g, x0 + x, y0 + y, &v, &err);
            z[(size_t)y * w + x] = (float)v;
        }
    const double wgt[6] = {gt[0] + x0 * gt[1], gt[1], 0.0, gt[3] + y0 * gt[5], 0.0, gt[5]};
    tp_viewshed_options o = tp_viewshed_options_default();
    o.radius_m = radius_m;
    if (st == TP_OK)
        st = tp_viewshed_compute(z, n, w, h, wgt, ox - x0, oy - y0, &o, seen, n, &err);
    const double t1 = tp_clock_s();
    if (st != TP_OK) {
        snprintf(line, cap, "viewshed: %.400s", err.message);
        free(z);
        free(seen);
        return 0;
    }
    /* the hidden posts with a height within the radius, thinned on a stride grid */
    size_t hidden = 0, valid = 0;
    for (int y = 0; y < h; ++y)
        for (int x = 0; x < w; ++x) {
            size_t i = (size_t)y * w + x;
            if (z[i] != z[i] ||
                hypot((x + x0 - ox) * gt[1], (y + y0 - oy) * gt[5]) > radius_m)
                continue;
            valid++;
            hidden += seen[i] != TP_VIEWSHED_VISIBLE;
        }
    int stride = 1;
    while (hidden / ((size_t)stride * stride) > TP_VIEW_VIEWSHED_MAX_DOTS)
        stride++;
    /* at most every post of the stride grid */
    const size_t bound = (size_t)((w + stride - 1) / stride) * (size_t)((h + stride - 1) / stride);
    double* enh = malloc(3 * bound * sizeof *enh);
    size_t kept = 0;
    for (int y = 0; enh && y < h; y += stride)
        for (int x = 0; x < w; x += stride) {
            size_t i = (size_t)y * w + x;
            if (z[i] != z[i] || seen[i] == TP_VIEWSHED_VISIBLE ||
                hypot((x + x0 - ox) * gt[1], (y + y0 - oy) * gt[5]) > radius_m)
                continue;
            tp_tree_grid_to_world(sc->tree, x0 + x, y0 + y, &enh[3 * kept], &enh[3 * kept + 1]);
            enh[3 * kept + 2] = z[i];
            kept++;
        }
    const double ground = z[(size_t)(oy - y0) * w + (ox - x0)];
    free(z);
    free(seen);
    if (!enh) {
        snprintf(line, cap, "viewshed: out of memory");
        return 0;
    }
    free(vs->enh);
    vs->enh = enh;
    vs->overlay = (tp_overlay_viewshed){.enh = enh, .count = kept,
                                        .spacing_m = stride * fabs(gt[1])};
    tp_tree_grid_to_world(sc->tree, ox, oy, &vs->overlay.observer_enh[0],
                          &vs->overlay.observer_enh[1]);
    vs->overlay.observer_enh[2] = ground;
    snprintf(line, cap,
             "viewshed from E %.0f N %.0f (eye 2 m, %.0f km): %.1f%% of %zu posts hidden (tinted), "
             "%.0f ms; B again: off",
             vs->overlay.observer_enh[0], vs->overlay.observer_enh[1], radius_m / 1000.0,
             valid ? 100.0 * hidden / valid : 0.0, valid, 1e3 * (t1 - t0));
    printf("%s\n", line);
    fflush(stdout);
    return 1;
}
