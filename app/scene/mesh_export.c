/* mesh_export.c - a selection's drawn geometry as one mesh (see mesh_export.h). */
#include "mesh_export.h"

#include "tp_geo.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The source height of sample (x, y) of the tiled grid: the render grid's value (quantisation
 * counts against the mesh), or the decoded height where the fit resampled the grid. */
static double source_height(const tp_scene* sc, int x, int y)
{
    const tp_render_grid* g = sc->grid;
    if (sc->info.fit == TP_FIT_RESAMPLE)
        return tp_terrain_sample(sc->terrain, x, y);
    if (x < 0 || y < 0 || x >= g->width || y >= g->height)
        return NAN;
    return g->heights[(size_t)y * g->width + x];
}

typedef struct tri_error {
    const tp_scene* sc;
    double max, sum;
    size_t count;
    uint8_t* seen; /* optional: count each sample once for the RMS */
} tri_error;

static void error_at(int x, int y, double z, void* user)
{
    tri_error* e = user;
    double s = source_height(e->sc, x, y);
    if (isnan(s))
        return;
    double d = fabs(z - s);
    e->max = d > e->max ? d : e->max;
    if (e->seen) {
        size_t i = (size_t)y * e->sc->info.width + x;
        if (e->seen[i >> 3] >> (i & 7) & 1)
            return;
        e->seen[i >> 3] |= (uint8_t)(1u << (i & 7));
        e->sum += d * d;
        e->count++;
    }
}

/* Drawn triangles of patch p (vertices into v, index triples into t); returns their count. */
static size_t patch_triangles(const tp_scene* sc, const tp_selection* sel, int p, tp_vertex* v,
                              uint32_t* t, size_t vcap, size_t tcap)
{
    int nb[4], k = tp_selection_level(sel, p);
    tp_selection_neighbor_levels(sel, p, nb);
    tp_patch_vertices(sc->terrain, p, k, nb, v, vcap);
    return tp_patch_triangles(v, k, t, tcap);
}

static double triangle_error(const tp_scene* sc, const tp_vertex* a, const tp_vertex* b,
                             const tp_vertex* c, uint8_t* seen, tri_error* acc)
{
    int32_t pa[2] = {a->x, a->y}, pb[2] = {b->x, b->y}, pc[2] = {c->x, c->y};
    tri_error e = {sc, 0, 0, 0, seen};
    tp_triangle_rasterize(pa, pb, pc, a->z_m, b->z_m, c->z_m, error_at, &e);
    if (acc) {
        acc->sum += e.sum;
        acc->count += e.count;
    }
    return e.max;
}

tp_status tp_select_max_error(const tp_scene* sc, tp_selection* sel, double m, tp_error* err)
{
    tp_lod_params lp = {.mode = TP_LOD_MAX_ERROR, .max_error_m = m};
    if (sc->info.fit != TP_FIT_RESAMPLE) { /* the render grid is the terrain's source */
        lp.reference_heights = sc->grid->heights;
        lp.reference_height_count = (size_t)sc->grid->width * (size_t)sc->grid->height;
    }
    return tp_selection_update(sel, NULL, &lp, err);
}

#define NO_POINT UINT64_MAX

static int full_cell(const tp_scene* sc, const tp_vertex* a, const tp_vertex* b,
                     const tp_vertex* c)
{
    int x0 = a->x, y0 = a->y, x1 = a->x, y1 = a->y;
    const tp_vertex* v[2] = {b, c};
    for (int i = 0; i < 2; i++) {
        x0 = v[i]->x < x0 ? v[i]->x : x0, x1 = v[i]->x > x1 ? v[i]->x : x1;
        y0 = v[i]->y < y0 ? v[i]->y : y0, y1 = v[i]->y > y1 ? v[i]->y : y1;
    }
    for (int y = y0; y <= y1; y++)
        for (int x = x0; x <= x1; x++)
            if (isnan(tp_terrain_sample(sc->terrain, x, y)))
                return 0;
    return 1;
}

/* The points at grid posts (pt_x, pt_y) in the render CRS less origin (xyz), their heights
 * (elev) and whether each is a filled void sample. */
static void place_points(const tp_scene* sc, size_t points, const int32_t* pt_x,
                         const int32_t* pt_y, const double origin[3], double* xyz, double* elev,
                         uint8_t* filled)
{
    for (size_t i = 0; i < points; i++) {
        double e, n;
        tp_georef_grid_to_proj(sc->georef, pt_x[i], pt_y[i], &e, &n);
        elev[i] = tp_terrain_sample(sc->terrain, pt_x[i], pt_y[i]);
        xyz[3 * i + 0] = e - origin[0];
        xyz[3 * i + 1] = n - origin[1];
        xyz[3 * i + 2] = elev[i] - origin[2];
        filled[i] = tp_terrain_sample_class(sc->terrain, pt_x[i], pt_y[i]) == TP_SAMPLE_FILLED;
    }
}

tp_status tp_export_selection(const tp_scene* sc, const tp_selection* sel,
                              const tp_export_options* o, const char* path,
                              tp_export_result* result, tp_error* err)
{
    const char* name = path ? path : sc->path;
    const tp_terrain_info* in = &sc->info;
    size_t v = (size_t)in->patch_size, vcap = v * v, tcap = 2 * (v - 1) * (v - 1);
    size_t cells = (size_t)in->width * in->height;
    /* grid sample -> point, NO_POINT when unused; 64-bit: a mesh may pass 2^32 points */
    uint64_t* index = malloc(cells * sizeof *index);
    uint8_t* seen = calloc((cells + 7) / 8, 1);
    tp_vertex* vb = malloc(vcap * sizeof *vb);
    uint32_t* tb = malloc(3 * tcap * sizeof *tb);
    /* first pass counts, second fills (sizes known before allocating the mesh) */
    size_t points = 0, tris = 0;
    tri_error acc = {sc, 0, 0, 0, NULL}; /* RMS over every covered sample, each once */
    int oom = 1;
    double *xyz = NULL, *elev = NULL, *tri_err = NULL;
    uint8_t *filled = NULL, *lod = NULL;
    int32_t *patch = NULL, *pt_x = NULL, *pt_y = NULL;
    uint64_t* tri = NULL;
    tp_status st = TP_ERR_OUT_OF_MEMORY;
    if (!index || !seen || !vb || !tb)
        goto done;
    oom = 0;
    for (size_t i = 0; i < cells; i++)
        index[i] = NO_POINT;
    for (int pass = 0; pass < 2; pass++) {
        points = tris = 0;
        for (int p = 0; p < in->patch_count; p++) {
            if (!o->include_culled && !tp_selection_visible(sel, p))
                continue;
            size_t nt = patch_triangles(sc, sel, p, vb, tb, vcap, tcap);
            for (size_t i = 0; i < nt; i++) {
                const tp_vertex* t3[3] = {&vb[tb[3 * i]], &vb[tb[3 * i + 1]], &vb[tb[3 * i + 2]]};
                if (o->full_cells_only && !full_cell(sc, t3[0], t3[1], t3[2]))
                    continue;
                for (int c = 0; c < 3; c++) {
                    size_t g = (size_t)t3[c]->y * in->width + t3[c]->x;
                    if (index[g] == NO_POINT) {
                        if (pass == 1) {
                            pt_x[points] = t3[c]->x;
                            pt_y[points] = t3[c]->y;
                        }
                        index[g] = points++;
                    }
                    if (pass == 1)
                        tri[3 * tris + c] = index[g];
                }
                if (pass == 1) {
                    patch[tris] = p;
                    lod[tris] = (uint8_t)tp_selection_level(sel, p);
                    tri_err[tris] = triangle_error(sc, t3[0], t3[1], t3[2], seen, &acc);
                }
                tris++;
            }
        }
        if (pass == 0) {
            /* refuse what the file could not hold before allocating for it */
            tp_error size_err;
            if (path && tp_mesh_check_size(o->format, points, tris, &size_err) != TP_OK) {
                st = tp_error_set(err, TP_ERR_INVALID_ARG, "%s: %s", path, size_err.message);
                goto done;
            }
            xyz = malloc(3 * points * sizeof *xyz);
            elev = malloc(points * sizeof *elev);
            filled = malloc(points ? points : 1);
            pt_x = malloc(points * sizeof *pt_x);
            pt_y = malloc(points * sizeof *pt_y);
            tri = malloc(3 * tris * sizeof *tri);
            patch = malloc(tris * sizeof *patch);
            lod = malloc(tris ? tris : 1);
            tri_err = malloc(tris * sizeof *tri_err);
            if ((points && (!xyz || !elev || !pt_x || !pt_y)) || !filled ||
                (tris && (!tri || !patch || !tri_err)) || !lod) {
                oom = 1;
                goto done;
            }
            for (size_t i = 0; i < cells; i++)
                index[i] = NO_POINT;
        }
    }
    if (tris == 0) {
        st = tp_error_set(err, TP_ERR_INVALID_ARG,
                         "%s: nothing to export (no drawn triangle in the selection)", name);
        goto done;
    }

    /* Points in the render CRS, in doubles; a local origin on request. */
    double origin[3];
    char zone[TP_ZONE_TEXT_SIZE];
    tp_export_frame(sc, o->origin_local, origin, zone);
    place_points(sc, points, pt_x, pt_y, origin, xyz, elev, filled);
    /* The strips are clockwise in (column, row); ParaView expects counter-clockwise from
     * above in (east, north): that is the same order for a north-up grid, reversed otherwise. */
    if (!(in->geotransform[1] * in->geotransform[5] < 0))
        for (size_t t = 0; t < tris; t++) {
            uint64_t s = tri[3 * t + 1];
            tri[3 * t + 1] = tri[3 * t + 2];
            tri[3 * t + 2] = s;
        }

    tp_mesh mesh = {
        .point_count = points, .xyz = xyz, .elevation_m = elev, .void_filled = filled,
        .triangle_count = tris, .triangles = tri, .patch_id = patch, .lod = lod,
        .max_error_m = tri_err, .crs_wkt = sc->grid->crs_wkt, .epsg = sc->grid->epsg,
        .utm_zone = zone, .source_file = NULL, .camera = o->camera_text,
        .lod_params = o->lod_text, .program_version = "terrapatch " TP_VERSION,
        .origin = {origin[0], origin[1], origin[2]},
    };
    mesh.source_file = sc->path;
    if (path) {
        st = tp_mesh_write(path, o->format, &mesh, err);
        if (st != TP_OK)
            goto done;
    }
    if (result) {
        double mx = 0;
        for (size_t t = 0; t < tris; t++)
            mx = tri_err[t] > mx ? tri_err[t] : mx;
        result->points = points;
        result->triangles = tris;
        result->max_error_m = mx;
        result->rms_error_m = acc.count ? sqrt(acc.sum / acc.count) : 0;
    }
    st = TP_OK;
done:
    if (oom)
        st = tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory building the mesh", name);
    free(index);
    free(seen);
    free(vb);
    free(tb);
    free(xyz);
    free(elev);
    free(filled);
    free(pt_x);
    free(pt_y);
    free(tri);
    free(patch);
    free(lod);
    free(tri_err);
    return st;
}

void tp_export_frame(const tp_scene* sc, int origin_local, double origin[3],
                     char zone[TP_ZONE_TEXT_SIZE])
{
    origin[0] = origin[1] = origin[2] = 0;
    if (origin_local) {
        double e, n;
        tp_georef_grid_to_proj(sc->georef, 0, 0, &e, &n);
        origin[0] = floor(e / 1000) * 1000;
        origin[1] = floor(n / 1000) * 1000;
    }
    zone[0] = '\0'; /* stays "" when the render CRS is no UTM/UPS zone */
    if (sc->grid->utm_zone >= 0)
        tp_zone_format(sc->grid->utm_zone, sc->grid->northp, TP_ZONE_STYLE_SHORT, zone,
                       TP_ZONE_TEXT_SIZE, NULL);
}

size_t tp_full_mesh_triangles(const tp_scene* sc)
{
    const tp_terrain_info* in = &sc->info;
    size_t cells = 0;
    for (int y = 0; y + 1 < in->height; y++)
        for (int x = 0; x + 1 < in->width; x++)
            cells += !isnan(tp_terrain_sample(sc->terrain, x, y)) &&
                     !isnan(tp_terrain_sample(sc->terrain, x + 1, y)) &&
                     !isnan(tp_terrain_sample(sc->terrain, x, y + 1)) &&
                     !isnan(tp_terrain_sample(sc->terrain, x + 1, y + 1));
    return 2 * cells;
}
