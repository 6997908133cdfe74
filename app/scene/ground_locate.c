/* ground_locate.c - typed positions on the ground and back (ground_locate.h). */
#include "ground_locate.h"

#include "tp_geo.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

int tp_ground_locate(tp_ground* g, const tp_position* pos, const char* input, double* x, double* y,
                     double* height_m, tp_error* err)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    if (!sc->georef || !tp_georef_has_geo(sc->georef)) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "has no CRS: a position on its ground needs a georeferenced DEM");
        return 0;
    }
    double e, n, gx, gy, h;
    tp_error why = {{0}};
    const tp_tree_geometry* geom = &sc->info.header.geometry;
    tp_status s = tp_georef_geo_to_proj(sc->georef, pos->lat_deg, pos->lon_deg, &e, &n, &why);
    if (s != TP_OK) {
        tp_error_set(err, s, "position '%s' (%.6f %.6f) is outside the DEM (%s)", input,
                     pos->lat_deg, pos->lon_deg, why.message);
        return 0;
    }
    tp_tree_world_to_grid(sc->tree, e, n, &gx, &gy);
    s = tp_ground_height(g, gx, gy, &h, err);
    if (s == TP_ERR_INVALID_ARG) {
        tp_error_set(err, s,
                     "position '%s' (%.6f %.6f) is outside the DEM (render CRS E %.1f N %.1f; "
                     "the DEM covers %d x %d posts)",
                     input, pos->lat_deg, pos->lon_deg, e, n, geom->src_width, geom->src_height);
        return 0;
    }
    if (s != TP_OK)
        return 0;
    if (isnan(h)) {
        char hint[256];
        tp_ground_void_hint(g, gx, gy, hint, sizeof hint);
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "position '%s' (%.6f %.6f) is in a void: the DEM has no height there (grid "
                     "x %.2f, y %.2f)%s",
                     input, pos->lat_deg, pos->lon_deg, gx, gy, hint);
        return 0;
    }
    *x = gx;
    *y = gy;
    *height_m = h;
    return 1;
}

int tp_ground_on_dem(tp_ground* g, const tp_position* pos, double* x, double* y)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    double e, n, h;
    if (!sc->georef || !tp_georef_has_geo(sc->georef) ||
        tp_georef_geo_to_proj(sc->georef, pos->lat_deg, pos->lon_deg, &e, &n, NULL) != TP_OK)
        return 0;
    tp_tree_world_to_grid(sc->tree, e, n, x, y);
    return tp_ground_height(g, *x, *y, &h, NULL) == TP_OK;
}

/* A breadth-first walk over void posts: seen (a bit per post) and the queue of posts to visit. */
typedef struct void_walk {
    tp_ground* g;
    int w, h;
    uint8_t* seen;
    int32_t* queue; /* x, y pairs */
    size_t count, cap;
} void_walk;

/* Queues post (x, y) when it is a new void. 1 when it did, 0 when it did not, -1 when it cannot
 * be read or the queue cannot grow. */
static int walk_add(void_walk* v, int x, int y)
{
    if (x < 0 || y < 0 || x >= v->w || y >= v->h)
        return 0;
    const size_t i = (size_t)y * v->w + x;
    if (v->seen[i / 8] & (1u << (i % 8)))
        return 0;
    v->seen[i / 8] |= (uint8_t)(1u << (i % 8));
    double z;
    if (tp_ground_height(v->g, x, y, &z, NULL) != TP_OK)
        return -1;
    if (!isnan(z))
        return 0;
    if (v->count == v->cap) {
        size_t cap = v->cap ? 2 * v->cap : 1024;
        int32_t* q = realloc(v->queue, cap * 2 * sizeof *q);
        if (!q)
            return -1;
        v->queue = q, v->cap = cap;
    }
    v->queue[2 * v->count] = x, v->queue[2 * v->count + 1] = y;
    ++v->count;
    return 1;
}

int tp_ground_void_reaches_edge(tp_ground* g, double x, double y, size_t max_posts)
{
    const tp_tree_geometry* geom = &tp_ground_scene(g)->info.header.geometry;
    void_walk v = {.g = g, .w = geom->src_width, .h = geom->src_height};
    if (v.w < 1 || v.h < 1 || !(x >= 0.0 && y >= 0.0 && x <= v.w - 1.0 && y <= v.h - 1.0))
        return 0;
    if (!(v.seen = calloc(((size_t)v.w * v.h + 7) / 8, 1)))
        return -1;
    int result = 0;
    /* the posts of the cell around (x, y) that are voids, then their void neighbours */
    const int x0 = (int)floor(x), y0 = (int)floor(y);
    for (int k = 0; k < 4 && result == 0; ++k)
        result = walk_add(&v, x0 + (k & 1), y0 + (k >> 1)) < 0 ? -1 : 0;
    for (size_t head = 0; head < v.count && result == 0; ++head) {
        const int px = v.queue[2 * head], py = v.queue[2 * head + 1];
        if (px == 0 || py == 0 || px == v.w - 1 || py == v.h - 1) {
            result = 1;
            break;
        }
        if (v.count > max_posts) {
            result = -1;
            break;
        }
        static const int dx[4] = {1, -1, 0, 0}, dy[4] = {0, 0, 1, -1};
        for (int k = 0; k < 4 && result == 0; ++k)
            if (walk_add(&v, px + dx[k], py + dy[k]) < 0)
                result = -1;
    }
    free(v.seen);
    free(v.queue);
    return result;
}

void tp_ground_void_hint(tp_ground* g, double x, double y, char* out, size_t cap)
{
    if (tp_ground_void_reaches_edge(g, x, y, TP_GROUND_VOID_WALK_POSTS) == 1)
        snprintf(out, cap,
                 "; the void reaches the DEM's edge, where no interpolation fills voids: "
                 "--fill-from OTHER fills it from a second raster");
    else if (cap)
        out[0] = '\0';
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
