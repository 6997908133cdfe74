/* mesh_export.c - a selection's drawn geometry as one mesh (see mesh_export.h). */
#include "mesh_export.h"

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
    if (tp_patch_vertices(sc->terrain, p, k, nb, v, vcap) != TP_OK)
        return 0;
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

double tp_patch_measured_error(const tp_scene* sc, const tp_selection* sel, int p)
{
    size_t v = (size_t)sc->info.patch_size, vcap = v * v, tcap = 2 * (v - 1) * (v - 1);
    tp_vertex* vb = malloc(vcap * sizeof *vb);
    uint32_t* tb = malloc(3 * tcap * sizeof *tb);
    double mx = 0;
    if (vb && tb) {
        size_t nt = patch_triangles(sc, sel, p, vb, tb, vcap, tcap);
        for (size_t i = 0; i < nt; i++) {
            double e = triangle_error(sc, &vb[tb[3 * i]], &vb[tb[3 * i + 1]], &vb[tb[3 * i + 2]],
                                      NULL, NULL);
            mx = e > mx ? e : mx;
        }
    }
    free(vb);
    free(tb);
    return mx;
}

/* Is the fourth corner of the full-resolution cell of this triangle drawn too? */
static int neighbor(const tp_terrain_info* in, int p, int side)
{
    int c = p % in->patch_cols, r = p / in->patch_cols;
    switch (side) {
    case TP_SIDE_TOP: return r > 0 ? p - in->patch_cols : -1;
    case TP_SIDE_RIGHT: return c + 1 < in->patch_cols ? p + 1 : -1;
    case TP_SIDE_BOTTOM: return r + 1 < in->patch_rows ? p + in->patch_cols : -1;
    default: return c > 0 ? p - 1 : -1;
    }
}

/* Static error-bounded levels: start from the delta bound, then raise levels where the
 * measured error of the stitched triangles exceeds M (the coarser neighbours that moved the
 * patch's border, else the patch itself). Levels only go up, so this ends. */
void tp_select_max_error(const tp_scene* sc, tp_selection* sel, double m)
{
    const tp_terrain_info* in = &sc->info;
    for (int p = 0; p < in->patch_count; p++) {
        tp_patch_info pi;
        tp_patch_get_info(sc->terrain, p, &pi);
        int k = in->n;
        while (k > 0 && pi.delta_m[k - 1] <= m)
            k--;
        tp_selection_set_level(sel, p, k);
    }
    int* todo = malloc((size_t)in->patch_count * sizeof *todo);
    if (!todo)
        return;
    for (int round = 0;; round++) {
        int count = 0;
        for (int p = 0; p < in->patch_count; p++)
            if (tp_selection_dirty(sel, p))
                todo[count++] = p;
        tp_selection_clear_dirty(sel);
        if (count == 0)
            break;
        for (int i = 0; i < count; i++) {
            int p = todo[i];
            if (tp_patch_measured_error(sc, sel, p) <= m)
                continue;
            int k = tp_selection_level(sel, p), nb[4], raised = 0;
            tp_selection_neighbor_levels(sel, p, nb);
            for (int s = 0; s < 4; s++)
                if (nb[s] >= 0 && nb[s] < k) {
                    tp_selection_set_level(sel, neighbor(in, p, s), nb[s] + 1);
                    raised = 1;
                }
            if (!raised && k < in->n)
                tp_selection_set_level(sel, p, k + 1);
        }
        if (round % 4 == 3)
            fprintf(stderr, "terrapatch: max-error mesh: refining levels, %d patches re-measured\n", count);
    }
    free(todo);
}

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

int tp_export_selection(const tp_scene* sc, const tp_selection* sel, const tp_export_options* o,
                        const char* path, tp_export_result* result)
{
    const tp_terrain_info* in = &sc->info;
    size_t v = (size_t)in->patch_size, vcap = v * v, tcap = 2 * (v - 1) * (v - 1);
    size_t cells = (size_t)in->width * in->height;
    int32_t* index = malloc(cells * sizeof *index); /* grid sample -> point, -1 when unused */
    uint8_t* seen = calloc((cells + 7) / 8, 1);
    tp_vertex* vb = malloc(vcap * sizeof *vb);
    uint32_t* tb = malloc(3 * tcap * sizeof *tb);
    /* first pass counts, second fills (sizes known before allocating the mesh) */
    size_t points = 0, tris = 0;
    tri_error acc = {sc, 0, 0, 0, NULL}; /* RMS over every covered sample, each once */
    int oom = 1;
    double *xyz = NULL, *elev = NULL, *err = NULL;
    uint8_t *filled = NULL, *lod = NULL;
    int32_t *patch = NULL, *pt_x = NULL, *pt_y = NULL;
    uint32_t* tri = NULL;
    int ok = 0;
    if (!index || !seen || !vb || !tb)
        goto done;
    oom = 0;
    for (size_t i = 0; i < cells; i++)
        index[i] = -1;
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
                    if (index[g] < 0) {
                        if (pass == 1) {
                            pt_x[points] = t3[c]->x;
                            pt_y[points] = t3[c]->y;
                        }
                        index[g] = (int32_t)points++;
                    }
                    if (pass == 1)
                        tri[3 * tris + c] = (uint32_t)index[g];
                }
                if (pass == 1) {
                    patch[tris] = p;
                    lod[tris] = (uint8_t)tp_selection_level(sel, p);
                    err[tris] = triangle_error(sc, t3[0], t3[1], t3[2], seen, &acc);
                }
                tris++;
            }
        }
        if (pass == 0) {
            xyz = malloc(3 * points * sizeof *xyz);
            elev = malloc(points * sizeof *elev);
            filled = malloc(points ? points : 1);
            pt_x = malloc(points * sizeof *pt_x);
            pt_y = malloc(points * sizeof *pt_y);
            tri = malloc(3 * tris * sizeof *tri);
            patch = malloc(tris * sizeof *patch);
            lod = malloc(tris ? tris : 1);
            err = malloc(tris * sizeof *err);
            if ((points && (!xyz || !elev || !pt_x || !pt_y)) || !filled ||
                (tris && (!tri || !patch || !err)) || !lod) {
                oom = 1;
                goto done;
            }
            for (size_t i = 0; i < cells; i++)
                index[i] = -1;
        }
    }
    if (tris == 0) {
        fprintf(stderr, "terrapatch: %s: nothing to export (no drawn triangle in the selection)\n",
                path ? path : sc->path);
        goto done;
    }

    /* Points in the render CRS, in doubles; a local origin on request. */
    double origin[3] = {0, 0, 0};
    if (o->origin_local) {
        double e, n;
        tp_georef_grid_to_proj(sc->georef, 0, 0, &e, &n);
        origin[0] = floor(e / 1000) * 1000;
        origin[1] = floor(n / 1000) * 1000;
    }
    for (size_t i = 0; i < points; i++) {
        double e, n;
        tp_georef_grid_to_proj(sc->georef, pt_x[i], pt_y[i], &e, &n);
        elev[i] = tp_terrain_sample(sc->terrain, pt_x[i], pt_y[i]);
        xyz[3 * i + 0] = e - origin[0];
        xyz[3 * i + 1] = n - origin[1];
        xyz[3 * i + 2] = elev[i] - origin[2];
        filled[i] = tp_terrain_sample_class(sc->terrain, pt_x[i], pt_y[i]) == TP_SAMPLE_FILLED;
    }
    /* The strips are clockwise in (column, row); ParaView expects counter-clockwise from
     * above in (east, north): that is the same order for a north-up grid, reversed otherwise. */
    if (!(in->geotransform[1] * in->geotransform[5] < 0))
        for (size_t t = 0; t < tris; t++) {
            uint32_t s = tri[3 * t + 1];
            tri[3 * t + 1] = tri[3 * t + 2];
            tri[3 * t + 2] = s;
        }

    char zone[16] = "";
    if (sc->grid->utm_zone > 0)
        snprintf(zone, sizeof zone, "%d%c", sc->grid->utm_zone, sc->grid->northp ? 'n' : 's');
    else if (sc->grid->utm_zone == 0)
        snprintf(zone, sizeof zone, "UPS %s", sc->grid->northp ? "n" : "s");
    tp_mesh mesh = {
        .point_count = points, .xyz = xyz, .elevation_m = elev, .void_filled = filled,
        .triangle_count = tris, .triangles = tri, .patch_id = patch, .lod = lod,
        .max_error_m = err, .crs_wkt = sc->grid->crs_wkt, .epsg = sc->grid->epsg,
        .utm_zone = zone, .source_file = NULL, .camera = o->camera_text,
        .lod_params = o->lod_text, .program_version = "terrapatch " TP_VERSION,
        .origin = {origin[0], origin[1], origin[2]},
    };
    mesh.source_file = sc->path;
    tp_error e;
    if (path && tp_mesh_write(path, o->format, &mesh, &e) != TP_OK) {
        fprintf(stderr, "terrapatch: %s\n", e.message);
        goto done;
    }
    if (result) {
        double mx = 0;
        for (size_t t = 0; t < tris; t++)
            mx = err[t] > mx ? err[t] : mx;
        result->points = points;
        result->triangles = tris;
        result->max_error_m = mx;
        result->rms_error_m = acc.count ? sqrt(acc.sum / acc.count) : 0;
    }
    ok = 1;
done:
    if (oom)
        fprintf(stderr, "terrapatch: %s: out of memory building the mesh\n", path ? path : sc->path);
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
    free(err);
    return ok;
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
