/* los_pick.c - the viewer's line-of-sight mode (los_pick.h). */
#include "los_pick.h"

#include "ground_locate.h"

#include "tp_core.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static tp_status height_at(void* user, double x, double y, double* h, tp_error* err)
{
    return tp_ground_height((tp_ground*)user, x, y, h, err);
}

void tp_view_los_free(tp_view_los* l)
{
    free(l->enh);
    free(l->seen);
    memset(l, 0, sizeof *l);
}

int tp_view_los_click(tp_view_los* l, tp_ground* g, double e_m, double n_m, char* line,
                      size_t cap)
{
    if (!l->picked) {
        l->picked = 1;
        l->observer[0] = e_m;
        l->observer[1] = n_m;
        snprintf(line, cap,
                 "line of sight: observer at E %.1f N %.1f (2 m up); right-click the target",
                 e_m, n_m);
        return 0;
    }
    l->picked = 0;
    const tp_store_scene* sc = tp_ground_scene(g);
    double fx, fy, tx, ty;
    tp_tree_world_to_grid(sc->tree, l->observer[0], l->observer[1], &fx, &fy);
    tp_tree_world_to_grid(sc->tree, e_m, n_m, &tx, &ty);
    tp_los_options o = tp_los_options_default();
    size_t n = tp_los_sample_count(fx, fy, tx, ty, &o);
    tp_los_sample* s = malloc(n * sizeof *s);
    double* enh = malloc(3 * n * sizeof *enh);
    unsigned char* seen = malloc(n);
    tp_los_result r;
    tp_error err = {{0}};
    tp_status st = s && enh && seen ? tp_los_compute(sc->info.header.geotransform, fx, fy, tx,
                                                     ty, &o, height_at, g, s, n, &r, &err)
                                    : tp_error_set(&err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    if (st != TP_OK) {
        snprintf(line, cap, "line of sight: %.400s", err.message);
        printf("los: %s\n", err.message);
        fflush(stdout);
        free(s);
        free(enh);
        free(seen);
        return 0;
    }
    for (size_t i = 0; i < n; ++i) {
        tp_tree_grid_to_world(sc->tree, s[i].x, s[i].y, &enh[3 * i], &enh[3 * i + 1]);
        enh[3 * i + 2] = s[i].ground_m;
        seen[i] = (unsigned char)s[i].seen;
    }
    free(l->enh);
    free(l->seen);
    l->enh = enh;
    l->seen = seen;
    l->count = n;
    l->overlay = (tp_overlay_los){.enh = enh, .seen = seen, .count = n,
                                  .has_obstruction = r.obstructed};
    double olat = NAN, olon = NAN;
    if (r.obstructed) {
        tp_tree_grid_to_world(sc->tree, r.obstruction_x, r.obstruction_y,
                              &l->overlay.obstruction_enh[0], &l->overlay.obstruction_enh[1]);
        l->overlay.obstruction_enh[2] = r.obstruction_ground_m;
        tp_ground_grid_latlon(g, r.obstruction_x, r.obstruction_y, &olat, &olon);
    }
    double alat, alon, blat, blon;
    tp_ground_grid_latlon(g, fx, fy, &alat, &alon);
    tp_ground_grid_latlon(g, tx, ty, &blat, &blon);
    if (r.obstructed)
        snprintf(line, cap,
                 "line of sight %.0f m: HIDDEN, obstruction %.1f m above the line at %.0f m "
                 "(%.5f %.5f)",
                 r.distance_m, r.obstruction_blocking_m, r.obstruction_distance_m, olat, olon);
    else
        snprintf(line, cap, "line of sight %.0f m: VISIBLE, clearance %.1f m at least",
                 r.distance_m, r.min_clearance_m);
    printf("los: from %.6f %.6f (eye %.1f m) to %.6f %.6f (%.1f m): %s\n", alat, alon, r.eye_m,
           blat, blon, r.target_m, line);
    fflush(stdout);
    free(s);
    return 1;
}
