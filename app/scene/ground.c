/*
 * ground.c - the full-resolution ground at a position (ground.h): a tree of its own over a
 * store's node table, leaves read on demand into a direct-mapped cache (the pattern of the leaf
 * cache in export/store_export.c), heights from tp_tree_height_at, slope and aspect from
 * central differences of that surface.
 */
#define _POSIX_C_SOURCE 200809L
#include "ground.h"

#include "cli.h"

#include "tp_geo.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

#define DEFAULT_CACHE_BYTES ((size_t)16 << 20)
#define MIN_SLOTS 4
#define CONVERGENCE_STEP_M 10.0 /* up the grid's N axis, for the azimuth of grid north */
#define DEG_PER_RAD 57.29577951308232

struct tp_ground {
    const tp_store_scene* sc;
    tp_tree* tree;                  /* ours: leaves attached from the cache below */
    const tp_tree_geometry* geom;
    size_t block_samples;           /* (2^n+1)^2 */
    size_t slot_count;
    int64_t* key;                   /* leaf in each slot, -1 when empty */
    uint16_t** slot;                /* allocated on first use */
    size_t reads;
    tp_slope_method slope_method;
    /* tp_ground_open only: what owns the scene, released after the ground */
    void (*release)(void* owner);
    void* owner;
};

void tp__ground_set_owner(tp_ground* g, void (*release)(void* owner), void* owner)
{
    g->release = release;
    g->owner = owner;
}

tp_status tp_ground_create(const tp_store_scene* sc, const tp_ground_options* o,
                           tp_ground** out, tp_error* err)
{
    assert(sc && sc->store && out);
    tp_ground* g = calloc(1, sizeof *g);
    if (!g)
        return tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    g->sc = sc;
    /* a tree of its own over the store's metas, as the scene's (never the viewer's tree) */
    tp_status s = tp_tree_create_from_store(sc->store, &g->tree, err);
    if (s != TP_OK) {
        free(g);
        return s;
    }
    g->geom = tp_tree_get_geometry(g->tree);
    size_t v = ((size_t)1 << g->geom->n) + 1;
    g->block_samples = v * v;
    size_t bytes = o && o->cache_bytes ? o->cache_bytes : DEFAULT_CACHE_BYTES;
    g->slot_count = bytes / (g->block_samples * sizeof(uint16_t));
    if (g->slot_count < MIN_SLOTS)
        g->slot_count = MIN_SLOTS;
    g->key = malloc(g->slot_count * sizeof *g->key);
    g->slot = calloc(g->slot_count, sizeof *g->slot);
    if (!g->key || !g->slot) {
        tp_ground_destroy(g);
        return tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    }
    for (size_t i = 0; i < g->slot_count; ++i)
        g->key[i] = -1;
    *out = g;
    return TP_OK;
}

void tp_ground_destroy(tp_ground* g)
{
    if (!g)
        return;
    tp_tree_destroy(g->tree); /* detaches nothing of ours: the blocks go below */
    if (g->slot)
        for (size_t i = 0; i < g->slot_count; ++i)
            free(g->slot[i]);
    free(g->slot);
    free(g->key);
    void (*release)(void*) = g->release;
    void* owner = g->owner;
    free(g);
    if (release)
        release(owner);
}

const tp_store_scene* tp_ground_scene(const tp_ground* g)
{
    return g->sc;
}

size_t tp_ground_reads(const tp_ground* g)
{
    return g->reads;
}

/* Makes the leaf holding grid (x, y) resident. */
static tp_status ensure_leaf(tp_ground* g, double x, double y, tp_error* err)
{
    int64_t leaf = tp_tree_leaf_at(g->tree, x, y);
    if (leaf < 0 || tp_tree_samples(g->tree, leaf))
        return TP_OK;
    size_t s = (size_t)leaf % g->slot_count;
    if (!g->slot[s] && !(g->slot[s] = malloc(g->block_samples * sizeof(uint16_t))))
        return tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    if (g->key[s] >= 0) {
        tp_tree_detach(g->tree, g->key[s]);
        g->key[s] = -1;
    }
    tp_status st = tp_store_read_node(g->sc->store, leaf, g->slot[s], g->block_samples, err);
    if (st != TP_OK)
        return st;
    g->key[s] = leaf;
    g->reads++;
    tp_tree_attach(g->tree, leaf, g->slot[s]);
    return TP_OK;
}

static int on_dem(const tp_ground* g, double x, double y)
{
    return x >= 0.0 && y >= 0.0 && x <= (double)(g->geom->src_width - 1) &&
           y <= (double)(g->geom->src_height - 1);
}

tp_status tp_ground_height(tp_ground* g, double x, double y, double* height_m, tp_error* err)
{
    assert(g && height_m);
    if (!on_dem(g, x, y))
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "grid (%.3f, %.3f) is outside the DEM (0..%d, 0..%d)", x, y,
                            g->geom->src_width - 1, g->geom->src_height - 1);
    tp_status s = ensure_leaf(g, x, y, err);
    if (s != TP_OK)
        return s;
    *height_m = tp_tree_height_at(g->tree, x, y);
    return TP_OK;
}

/* Height one post away, NaN off the DEM or on a read failure (then *failed and err). */
static double neighbour(tp_ground* g, double x, double y, tp_status* failed, tp_error* err)
{
    double h = NAN;
    if (!on_dem(g, x, y))
        return NAN;
    tp_status s = tp_ground_height(g, x, y, &h, err);
    if (s != TP_OK) {
        *failed = s;
        return NAN;
    }
    return h;
}

/* d height / d grid step along one axis from heights at -1, 0, +1: central where both
 * neighbours are known, else one-sided; NaN when neither is. */
static double derivative(double hm, double h0, double hp)
{
    if (!isnan(hm) && !isnan(hp))
        return (hp - hm) / 2.0;
    if (!isnan(hp) && !isnan(h0))
        return hp - h0;
    if (!isnan(hm) && !isnan(h0))
        return h0 - hm;
    return NAN;
}

void tp_ground_set_slope_method(tp_ground* g, tp_slope_method m)
{
    g->slope_method = m;
}

const char* tp_slope_method_name(tp_slope_method m)
{
    return m == TP_SLOPE_CENTRAL ? "central" : "horn";
}

/* d height / d grid step along x and y by Horn's 3x3 window around (x, y): 1 with both, 0 when
 * a post of the window has no height (a void, off the DEM). */
static int horn(tp_ground* g, double x, double y, double* dhdx, double* dhdy, tp_status* failed,
                tp_error* err)
{
    double z[3][3]; /* z[j][i]: the height at (x + i - 1, y + j - 1) */
    for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
            z[j][i] = neighbour(g, x + i - 1.0, y + j - 1.0, failed, err);
            if (isnan(z[j][i]))
                return 0;
        }
    *dhdx = ((z[0][2] + 2.0 * z[1][2] + z[2][2]) - (z[0][0] + 2.0 * z[1][0] + z[2][0])) / 8.0;
    *dhdy = ((z[2][0] + 2.0 * z[2][1] + z[2][2]) - (z[0][0] + 2.0 * z[0][1] + z[0][2])) / 8.0;
    return 1;
}

static double wrap360(double a)
{
    a = fmod(a, 360.0);
    if (a < 0.0)
        a += 360.0;
    return a >= 360.0 ? 0.0 : a;
}

/* Bearing of grid north, clockwise from true north, at render (e, n). */
static double convergence_deg(const tp_ground* g, double e, double n)
{
    const tp_georef* geo = g->sc->georef;
    if (!geo || !tp_georef_has_geo(geo))
        return NAN;
    double lat1, lon1, lat2, lon2, azi1, azi2, s12;
    if (tp_georef_proj_to_geo(geo, e, n, &lat1, &lon1, NULL) != TP_OK ||
        tp_georef_proj_to_geo(geo, e, n + CONVERGENCE_STEP_M, &lat2, &lon2, NULL) != TP_OK ||
        tp_geodesic_inverse(lat1, lon1, lat2, lon2, &azi1, &azi2, &s12, NULL) != TP_OK)
        return NAN;
    return azi1;
}

tp_status tp_ground_query_grid(tp_ground* g, double x, double y, tp_ground_sample* out,
                               tp_error* err)
{
    assert(g && out);
    double h;
    tp_status s = tp_ground_height(g, x, y, &h, err);
    if (s != TP_OK)
        return s;
    tp_ground_sample r;
    memset(&r, 0, sizeof r);
    r.x = x;
    r.y = y;
    tp_tree_grid_to_world(g->tree, x, y, &r.e_m, &r.n_m);
    r.height_m = h;
    tp_status failed = TP_OK;
    double dhdx, dhdy;
    r.slope_method = TP_SLOPE_HORN;
    if (g->slope_method != TP_SLOPE_HORN || !horn(g, x, y, &dhdx, &dhdy, &failed, err)) {
        double hx0 = neighbour(g, x - 1.0, y, &failed, err);
        double hx1 = neighbour(g, x + 1.0, y, &failed, err);
        double hy0 = neighbour(g, x, y - 1.0, &failed, err);
        double hy1 = neighbour(g, x, y + 1.0, &failed, err);
        dhdx = derivative(hx0, h, hx1), dhdy = derivative(hy0, h, hy1);
        r.slope_method = TP_SLOPE_CENTRAL;
    }
    if (failed != TP_OK)
        return failed;
    const double* gt = g->sc->info.header.geotransform;
    /* per metre east and north: E grows with x by gt[1], N with y by gt[5] (< 0 north-up) */
    double dzde = dhdx / gt[1], dzdn = dhdy / gt[5];
    if (isnan(dzde) || isnan(dzdn)) {
        r.normal[2] = 1.0;
        r.slope_deg = r.aspect_grid_deg = r.aspect_true_deg = NAN;
    } else {
        double len = sqrt(dzde * dzde + dzdn * dzdn + 1.0);
        r.normal[0] = -dzde / len;
        r.normal[1] = -dzdn / len;
        r.normal[2] = 1.0 / len;
        r.slope_deg = atan(hypot(dzde, dzdn)) * DEG_PER_RAD;
        /* downhill is -gradient; its bearing from north, clockwise */
        r.aspect_grid_deg = (dzde == 0.0 && dzdn == 0.0)
                                ? NAN
                                : wrap360(atan2(-dzde, -dzdn) * DEG_PER_RAD);
    }
    r.convergence_deg = convergence_deg(g, r.e_m, r.n_m);
    r.aspect_true_deg = isnan(r.aspect_grid_deg) || isnan(r.convergence_deg)
                            ? NAN
                            : wrap360(r.aspect_grid_deg + r.convergence_deg);
    *out = r;
    return TP_OK;
}

tp_status tp_ground_query_world(tp_ground* g, double e_m, double n_m, tp_ground_sample* out,
                                tp_error* err)
{
    double x, y;
    tp_tree_world_to_grid(g->tree, e_m, n_m, &x, &y);
    return tp_ground_query_grid(g, x, y, out, err);
}

tp_status tp_ground_read_posts(tp_ground* g, int x0, int y0, int w, int h, float* z,
                              const char* progress, tp_error* err)
{
    const int show = progress && (size_t)w * h >= TP_GROUND_PROGRESS_POSTS;
    const int tty = show && isatty(STDERR_FILENO);
    int shown = -1;
    tp_status s = TP_OK;
    for (int y = 0; y < h && s == TP_OK; ++y) {
        if (show) {
            const int pct = (int)(100.0 * y / h) / 10 * 10;
            if (pct != shown) {
                if (tty)
                    fprintf(stderr, "%sreading the ground %3d%%\r", tp_cli_prefix(), pct);
                else
                    tp_cli_note("reading the ground %3d%%", pct);
                shown = pct;
            }
        }
        for (int x = 0; x < w && s == TP_OK; ++x) {
            double v = NAN;
            s = tp_ground_height(g, x0 + x, y0 + y, &v, err);
            z[(size_t)y * w + x] = (float)v;
        }
    }
    return s;
}
