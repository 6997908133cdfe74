/* ground_locate.c - typed positions on the ground and back (ground_locate.h). */
#include "ground_locate.h"

#include "tp_geo.h"

#include <math.h>
#include <stdio.h>

int tp_ground_locate(tp_ground* g, const tp_position* pos, const char* input, double* x,
                     double* y, double* height_m, char* msg, size_t cap)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    if (!sc->georef || !tp_georef_has_geo(sc->georef)) {
        snprintf(msg, cap, "has no CRS: a position on its ground needs a georeferenced DEM");
        return 0;
    }
    double e, n, gx, gy, h;
    tp_error err = {{0}};
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    if (tp_georef_geo_to_proj(sc->georef, pos->lat_deg, pos->lon_deg, &e, &n, &err) != TP_OK) {
        snprintf(msg, cap, "position '%s' (%.6f %.6f) is outside the DEM (%s)", input,
                 pos->lat_deg, pos->lon_deg, err.message);
        return 0;
    }
    tp_tree_world_to_grid(sc->tree, e, n, &gx, &gy);
    tp_status s = tp_ground_height(g, gx, gy, &h, &err);
    if (s == TP_ERR_INVALID_ARG) {
        snprintf(msg, cap,
                 "position '%s' (%.6f %.6f) is outside the DEM (render CRS E %.1f N %.1f; the "
                 "DEM covers %d x %d posts)",
                 input, pos->lat_deg, pos->lon_deg, e, n, geom->src_width, geom->src_height);
        return 0;
    }
    if (s != TP_OK) {
        snprintf(msg, cap, "%s", err.message);
        return 0;
    }
    if (isnan(h)) {
        snprintf(msg, cap,
                 "position '%s' (%.6f %.6f) is in a void: the DEM has no height there (grid x "
                 "%.2f, y %.2f)",
                 input, pos->lat_deg, pos->lon_deg, gx, gy);
        return 0;
    }
    *x = gx;
    *y = gy;
    *height_m = h;
    return 1;
}

int tp_ground_grid_latlon(const tp_ground* g, double x, double y, double* lat_deg,
                          double* lon_deg)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    double e, n;
    *lat_deg = *lon_deg = NAN;
    if (!sc->georef || !tp_georef_has_geo(sc->georef))
        return 0;
    tp_tree_grid_to_world(sc->tree, x, y, &e, &n);
    return tp_georef_proj_to_geo(sc->georef, e, n, lat_deg, lon_deg, NULL) == TP_OK;
}
