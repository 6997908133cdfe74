/* tin_export.c - `export --max-error M --mesh tin` (see tin_export.h). */
#include "tin_export.h"

#include "tp_geo.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The source samples as one row-major grid: the render grid's heights (borrowed), or the decoded
 * terrain where the fit resampled them (*owned is then the copy to free). */
static const float* source_grid(const tp_scene* sc, int* w, int* h, float** owned)
{
    *owned = NULL;
    if (sc->info.fit != TP_FIT_RESAMPLE) {
        *w = sc->grid->width;
        *h = sc->grid->height;
        return sc->grid->heights;
    }
    *w = sc->info.width;
    *h = sc->info.height;
    float* z = malloc((size_t)*w * (size_t)*h * sizeof *z);
    if (!z)
        return NULL;
    for (int y = 0; y < *h; y++)
        for (int x = 0; x < *w; x++)
            z[(size_t)y * *w + x] = (float)tp_terrain_sample(sc->terrain, x, y);
    *owned = z;
    return z;
}

typedef struct measure {
    const float* z;
    int w;
    double max, sum;
    size_t count;
    uint8_t* seen; /* each sample once in the RMS */
} measure;

static void error_at(int x, int y, double zi, void* user)
{
    measure* m = user;
    size_t i = (size_t)y * m->w + x;
    float s = m->z[i];
    if (s != s)
        return;
    double d = fabs(zi - s);
    m->max = d > m->max ? d : m->max;
    if (m->seen[i >> 3] >> (i & 7) & 1)
        return;
    m->seen[i >> 3] |= (uint8_t)(1u << (i & 7));
    m->sum += d * d;
    m->count++;
}

tp_status tp_export_tin(const tp_scene* sc, double m, const tp_export_options* o,
                        const char* path, tp_export_result* result, tp_error* err)
{
    const char* name = path ? path : sc->path;
    int w, h;
    float* owned;
    const float* z = source_grid(sc, &w, &h, &owned);
    if (!z)
        return tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory for the source grid",
                            name);
    tp_tin* tin = NULL;
    tp_error terr;
    tp_status st = tp_tin_build_tiled(z, (size_t)w * h, w, h, m, TP_TIN_CUT_VOIDS,
                                      TP_TIN_EXPORT_TILE_CELLS, 0, &tin, &terr);
    if (st != TP_OK) {
        free(owned);
        return tp_error_set(err, st, "%s: %s", name, terr.message);
    }
    size_t np = tin->vertex_count, nt = tin->triangle_count;
    double* xyz = malloc(3 * (np ? np : 1) * sizeof *xyz);
    double* elev = malloc((np ? np : 1) * sizeof *elev);
    uint8_t* filled = malloc(np ? np : 1);
    uint64_t* tri = malloc(3 * (nt ? nt : 1) * sizeof *tri);
    double* tri_err = malloc((nt ? nt : 1) * sizeof *tri_err);
    uint8_t* seen = calloc(((size_t)w * h + 7) / 8, 1);
    measure acc = {z, w, 0, 0, 0, seen};
    tp_error size_err;
    if (!xyz || !elev || !filled || !tri || !tri_err || !seen) {
        st = tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory for a TIN of %zu "
                          "triangles", name, nt);
        goto done;
    }
    if (nt == 0) {
        st = tp_error_set(err, TP_ERR_INVALID_ARG,
                          "%s: nothing to export (no cell of four valid samples)", name);
        goto done;
    }
    if (path && (st = tp_mesh_check_size(o->format, np, nt, &size_err)) != TP_OK) {
        st = tp_error_set(err, st, "%s: %s", path, size_err.message);
        goto done;
    }

    double origin[3];
    char zone[TP_ZONE_TEXT_SIZE];
    tp_export_frame(sc, o->origin_local, origin, zone);
    for (size_t i = 0; i < np; i++) {
        const float* v = tin->vertices + 3 * i;
        int x = (int)v[0], y = (int)v[1];
        double e, n;
        tp_georef_grid_to_proj(sc->georef, x, y, &e, &n);
        elev[i] = v[2];
        xyz[3 * i + 0] = e - origin[0];
        xyz[3 * i + 1] = n - origin[1];
        xyz[3 * i + 2] = elev[i] - origin[2];
        filled[i] = tp_terrain_sample_class(sc->terrain, x, y) == TP_SAMPLE_FILLED;
    }
    /* Measured again, apart from the build, with the rasteriser the other modes use. */
    for (size_t t = 0; t < nt; t++) {
        const uint32_t* k = tin->triangles + 3 * t;
        const float *a = tin->vertices + 3 * k[0], *b = tin->vertices + 3 * k[1],
                    *c = tin->vertices + 3 * k[2];
        int32_t pa[2] = {(int32_t)a[0], (int32_t)a[1]}, pb[2] = {(int32_t)b[0], (int32_t)b[1]},
                pc[2] = {(int32_t)c[0], (int32_t)c[1]};
        double before = acc.max;
        acc.max = 0;
        tp_triangle_rasterize(pa, pb, pc, a[2], b[2], c[2], error_at, &acc);
        tri_err[t] = acc.max;
        acc.max = acc.max > before ? acc.max : before;
        /* tp_tin is counter-clockwise from above on a north-up grid: reversed otherwise */
        int flip = !(sc->info.geotransform[1] * sc->info.geotransform[5] < 0);
        tri[3 * t] = k[0];
        tri[3 * t + 1] = k[flip ? 2 : 1];
        tri[3 * t + 2] = k[flip ? 1 : 2];
    }

    tp_mesh mesh = {
        .point_count = np, .xyz = xyz, .elevation_m = elev, .void_filled = filled,
        .triangle_count = nt, .triangles = tri, .max_error_m = tri_err,
        .crs_wkt = sc->grid->crs_wkt, .epsg = sc->grid->epsg, .utm_zone = zone,
        .source_file = sc->path, .camera = o->camera_text, .lod_params = o->lod_text,
        .program_version = "terrapatch " TP_VERSION,
        .origin = {origin[0], origin[1], origin[2]},
    };
    if (path && (st = tp_mesh_write(path, o->format, &mesh, err)) != TP_OK)
        goto done;
    if (result) {
        result->points = np;
        result->triangles = nt;
        result->max_error_m = acc.max;
        result->rms_error_m = acc.count ? sqrt(acc.sum / acc.count) : 0;
    }
    st = TP_OK;
done:
    tp_tin_destroy(tin);
    free(owned);
    free(xyz);
    free(elev);
    free(filled);
    free(tri);
    free(tri_err);
    free(seen);
    return st;
}
