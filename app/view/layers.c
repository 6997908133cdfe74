/* layers.c - the viewer's vector overlays and contours (layers.h). */
#define _POSIX_C_SOURCE 200809L
#include "layers.h"
#include "clock.h"

#include "tp_vector.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Overlay colours, one per file in order: magenta, cyan, yellow, blue, orange, white, lime,
 * red (the contours are brown). */
static const unsigned char overlay_rgba[TP_VIEW_MAX_OVERLAYS][4] = {
    {255, 40, 220, 255}, {0, 220, 255, 255}, {255, 230, 0, 255}, {40, 80, 255, 255},
    {255, 140, 0, 255},  {255, 255, 255, 255}, {120, 255, 60, 255}, {255, 30, 30, 255}};
static const char* overlay_colour_name[TP_VIEW_MAX_OVERLAYS] = {
    "magenta", "cyan", "yellow", "blue", "orange", "white", "lime", "red"};

int tp_view_layers_add_overlay(tp_view_layers* l, tp_ground* g, const char* path, tp_error* err)
{
    if (l->overlay_count == TP_VIEW_MAX_OVERLAYS) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "%s: at most %d --overlay files", path,
                     TP_VIEW_MAX_OVERLAYS);
        return 0;
    }
    tp_features* f = NULL;
    if (tp_vector_read(path, tp_ground_scene(g)->info.header.crs_wkt, &f, err) != TP_OK)
        return 0;
    tp_drape d;
    tp_error why = {{0}};
    if (!tp_drape_build(&d, f, g, 0, &why)) {
        tp_error_set(err, TP_ERR_IO, "%s: %s", path, why.message);
        tp_features_destroy(f);
        return 0;
    }
    size_t lines = 0, rings = 0, points = 0;
    for (size_t i = 0; i < f->count; i++) {
        lines += f->items[i].kind == TP_FEATURE_LINE;
        rings += f->items[i].kind == TP_FEATURE_RING;
        points += f->items[i].kind == TP_FEATURE_POINT;
    }
    tp_features_destroy(f);
    const size_t k = l->overlay_count++;
    l->overlays[k] = d;
    l->overlay_paths[k] = path;
    printf("overlay %s (%s): %zu lines, %zu polygon rings, %zu points", path,
           overlay_colour_name[k], lines, rings, points);
    if (d.dropped)
        printf("; %zu vertices off the DEM or over voids not drawn", d.dropped);
    printf("\n");
    fflush(stdout);
    return 1;
}

/* 1, 2 or 5 times a power of ten, the smallest >= x (at least 1). */
static double round_interval(double x)
{
    if (!(x > 1))
        return 1;
    double p = pow(10, floor(log10(x)));
    return x <= p ? p : x <= 2 * p ? 2 * p : x <= 5 * p ? 5 * p : 10 * p;
}

int tp_view_layers_contours_at(tp_view_layers* l, tp_ground* g, double e_m, double n_m,
                               double interval_m, char* line, size_t cap)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    const double* gt = sc->info.header.geotransform;
    double fx, fy;
    tp_tree_world_to_grid(sc->tree, e_m, n_m, &fx, &fy);
    const int cx = (int)lround(fx), cy = (int)lround(fy);
    if (cx < 0 || cy < 0 || cx >= geom->src_width || cy >= geom->src_height) {
        snprintf(line, cap, "contours: the point looked at is outside the DEM");
        return 0;
    }
    int r = (int)floor(TP_VIEW_CONTOURS_RADIUS_M / fmin(fabs(gt[1]), fabs(gt[5])));
    while ((size_t)(2 * r + 1) * (size_t)(2 * r + 1) > TP_VIEW_CONTOURS_MAX_POSTS)
        r = r * 9 / 10;
    const int x0 = cx - r > 0 ? cx - r : 0, y0 = cy - r > 0 ? cy - r : 0;
    const int x1 = cx + r < geom->src_width - 1 ? cx + r : geom->src_width - 1;
    const int y1 = cy + r < geom->src_height - 1 ? cy + r : geom->src_height - 1;
    const int w = x1 - x0 + 1, h = y1 - y0 + 1;
    const size_t n = (size_t)w * h;
    float* z = malloc(n * sizeof *z);
    tp_error err = {{0}};
    tp_status st = z ? TP_OK : tp_error_set(&err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    const double t0 = tp_clock_s();
    float lo = INFINITY, hi = -INFINITY;
    for (int y = 0; y < h && st == TP_OK; ++y)
        for (int x = 0; x < w && st == TP_OK; ++x) {
            double v;
            st = tp_ground_height(g, x0 + x, y0 + y, &v, &err);
            z[(size_t)y * w + x] = (float)v;
            if (v == v) {
                lo = fminf(lo, (float)v);
                hi = fmaxf(hi, (float)v);
            }
        }
    if (st == TP_OK && !(hi >= lo))
        st = tp_error_set(&err, TP_ERR_BAD_DATA, "no ground within %.0f km",
                          TP_VIEW_CONTOURS_RADIUS_M / 1000);
    const double interval = interval_m > 0 ? interval_m : round_interval((hi - lo) / 25.0);
    const double wgt[6] = {gt[0] + x0 * gt[1], gt[1], 0.0, gt[3] + y0 * gt[5], 0.0, gt[5]};
    tp_features* f = NULL;
    const double t1 = tp_clock_s();
    if (st == TP_OK)
        st = tp_contours_generate(z, n, w, h, wgt, interval, 0.0, 5, &f, &err);
    free(z);
    tp_drape d;
    tp_error why = {{0}};
    int ok = st == TP_OK && tp_drape_build(&d, f, g, 1, &why);
    const double t2 = tp_clock_s();
    if (!ok) {
        snprintf(line, cap, "contours: %.400s", st != TP_OK ? err.message : why.message);
        tp_features_destroy(f);
        return 0;
    }
    const size_t count = f->count;
    tp_features_destroy(f);
    tp_drape_free(&l->contours);
    l->contours = d;
    l->contour_interval_m = interval;
    snprintf(line, cap,
             "contours every %g m (index every %g m, labelled) over %.0f x %.0f km around E %.0f "
             "N %.0f: %zu lines, %.0f ms reading, %.0f ms GDAL; F2 again: off",
             interval, 5 * interval, w * fabs(gt[1]) / 1000, h * fabs(gt[5]) / 1000, e_m, n_m,
             count, 1e3 * (t1 - t0), 1e3 * (t2 - t1));
    printf("%s\n", line);
    fflush(stdout);
    return 1;
}

void tp_view_layers_legend(const tp_view_layers* l, char* out, size_t cap)
{
    size_t at = 0;
    out[0] = '\0';
    for (size_t i = 0; i < l->overlay_count && at < cap; i++) {
        const char* slash = strrchr(l->overlay_paths[i], '/');
        int n = snprintf(out + at, cap - at, "%s%s %s", i ? ", " : "overlays: ",
                         slash ? slash + 1 : l->overlay_paths[i], overlay_colour_name[i]);
        at += n > 0 ? (size_t)n : 0;
    }
    if (l->contours.part_count && at < cap)
        snprintf(out + at, cap - at, "%scontours every %g m (index %g m; F2: off)",
                 at ? "   " : "", l->contour_interval_m, 5 * l->contour_interval_m);
}

size_t tp_view_layers_drawn(tp_view_layers* l, const tp_overlay_drape** out)
{
    size_t n = 0;
    if (l->contours.part_count)
        l->drawn[n++] = (tp_overlay_drape){.drape = &l->contours, .rgba = {140, 80, 30, 235},
                                           .width_px = 1.2f, .label_values = 1};
    for (size_t i = 0; i < l->overlay_count; i++) {
        tp_overlay_drape* d = &l->drawn[n++];
        *d = (tp_overlay_drape){.drape = &l->overlays[i], .width_px = 3.0f};
        memcpy(d->rgba, overlay_rgba[i], 4);
    }
    *out = l->drawn;
    return n;
}

void tp_view_layers_free(tp_view_layers* l)
{
    for (size_t i = 0; i < l->overlay_count; i++)
        tp_drape_free(&l->overlays[i]);
    tp_drape_free(&l->contours);
    memset(l, 0, sizeof *l);
}
