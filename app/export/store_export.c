/* store_export.c - `terrapatch export` on a store (see store_export.h): the store opened, the
 * cut chosen (store_cut.c, store_cut_max_error.c) or the TIN built (store_tin.c), the mesh of
 * the cut built with each triangle's measured error, and written. */
#include "store_export.h"
#include "full_export.h"
#include "store_cut.h"
#include "store_mesh.h"
#include "store_tin.h"
#include "tin_export.h"

#include "camera_pose.h"
#include "cli.h"
#include "memory.h"
#include "store_scene.h"
#include "tp_geo.h"

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the export's failures (store_cut.h) ---- */

int tp_store_export_fail(store_export* x, const char* what)
{
    if (strstr(what, x->r->store_path)) /* the store's messages name the file */
        tp_cli_error("%s", what);
    else
        tp_cli_error("%s: %s", x->r->store_path, what);
    return TP_EXIT_FAILURE;
}

int tp_store_export_too_many(store_export* x, size_t tris, const char* how)
{
    tp_cli_error(
        "%s: %s %zu triangles, over the export limit of %zu (%s); "
        "export a coarser mesh: --max-error M, or a camera (--camera/--camera-geo) in error "
        "or distance mode",
        x->r->store_path, how, tris, TP_STORE_EXPORT_MAX_TRIANGLES,
        "TP_STORE_EXPORT_MAX_TRIANGLES, app/export/store_export.h");
    return TP_EXIT_FAILURE; /* as the DEM path's --full over the memory available */
}

int tp_store_export_room_for(store_export* x, uint64_t more, const char* what)
{
    tp_memory_room room;
    tp_memory_room_now(&room);
    if (more <= room.bytes)
        return 1;
    tp_cli_error(
        "%s: %s needs about %.0f MiB more, but only %.0f MiB is available "
        "(%s); export a coarser mesh (--max-error M, a camera farther off), or --full to a "
        ".vtp (written a piece at a time)",
        x->r->store_path, what, more / 1048576.0, room.bytes / 1048576.0, room.bound);
    return 0;
}

/* ---- the mesh of the cut ---- */

/* A triangle's measured error against the full-resolution samples it covers. */
typedef struct tri_error {
    leaf_cache* lc;
    double max, sum;
    size_t count;
} tri_error;

static void error_at(int x, int y, double z, void* user)
{
    tri_error* e = user;
    double s = tp_leaf_sample(e->lc, x, y);
    if (isnan(s))
        return;
    double d = fabs(z - s);
    e->max = d > e->max ? d : e->max;
    e->sum += d * d;
    e->count++;
}

/* Whether the cell of triangle t (level n: one grid cell) has four drawn samples. */
static int full_cell(leaf_cache* lc, const tp_vertex* t[3])
{
    int x0 = t[0]->x, y0 = t[0]->y;
    for (int i = 1; i < 3; i++) {
        x0 = t[i]->x < x0 ? t[i]->x : x0;
        y0 = t[i]->y < y0 ? t[i]->y : y0;
    }
    for (int y = y0; y <= y0 + 1; y++)
        for (int xx = x0; xx <= x0 + 1; xx++)
            if (isnan(tp_leaf_sample(lc, xx, y)))
                return 0;
    return 1;
}

/* The drawn nodes' triangles into m, each with its measured error; only drawn nodes stay
 * resident meanwhile. */
static int build_mesh(store_export* x, mesh_build* m, double* sum, size_t* count)
{
    size_t nodes;
    const tp_cut_node* out = tp_cut_nodes(x->cut, &nodes);
    /* what the cut draws stays; ancestors read for the traversal go */
    uint8_t* keep = calloc((size_t)x->g->node_count, 1);
    size_t vcap = ((size_t)1 << x->n) + 1;
    vcap *= vcap;
    size_t tcap = (size_t)2 << (2 * x->n);
    tp_vertex* vb = malloc(vcap * sizeof *vb);
    uint32_t* tb = malloc(3 * tcap * sizeof *tb);
    int code = TP_EXIT_OK;
    if (!keep || !vb || !tb) {
        code = tp_store_export_fail(x, "out of memory");
        goto done;
    }
    x->drawn = nodes;
    for (size_t i = 0; i < nodes; i++)
        keep[out[i].node] = 1;
    tp_res_release_except(&x->res, keep);
    for (size_t i = 0; i < nodes && code == TP_EXIT_OK; i++) {
        tp_cut_vertices(x->cut, i, vb, vcap);
        size_t nt = tp_cut_triangles(x->cut, i, vb, tb, tcap);
        for (size_t t = 0; t < nt; t++) {
            const tp_vertex* v[3] = {&vb[tb[3 * t]], &vb[tb[3 * t + 1]], &vb[tb[3 * t + 2]]};
            if (x->r->mode == TP_STORE_EXPORT_FULL && !full_cell(x->cache, v)) {
                if (x->cache->failed) {
                    code = tp_store_export_fail(x, x->res.err.message);
                    goto done;
                }
                continue;
            }
            uint64_t p[3];
            for (int c = 0; c < 3; c++)
                if ((p[c] = tp_mesh_point(m, v[c]->x, v[c]->y, (double)v[c]->z_m,
                                          v[c]->cls == TP_SAMPLE_FILLED)) == UINT64_MAX) {
                    code = tp_store_export_fail(x, "out of memory building the mesh");
                    goto done;
                }
            int32_t a[2] = {v[0]->x, v[0]->y}, b[2] = {v[1]->x, v[1]->y},
                    cc[2] = {v[2]->x, v[2]->y};
            tri_error e = {x->cache, 0, 0, 0};
            tp_triangle_rasterize(a, b, cc, v[0]->z_m, v[1]->z_m, v[2]->z_m, error_at, &e);
            if (x->cache->failed) {
                code = tp_store_export_fail(x, x->res.err.message);
                goto done;
            }
            *sum += e.sum;
            *count += e.count;
            if (!tp_mesh_add_triangle(m, p, (int32_t)out[i].node, (uint8_t)out[i].level, e.max)) {
                code = tp_store_export_fail(x, "out of memory building the mesh");
                goto done;
            }
        }
        if (tp_interrupted()) {
            code = tp_cli_interrupted();
            goto done;
        }
    }
done:
    free(keep);
    free(vb);
    free(tb);
    return code;
}

/* Triangles of the full mesh (two per cell whose four samples are drawn: what --full writes) at
 * most, from the header alone: two per cell of the grid, and no more than two per drawn sample
 * (such a cell's top-left corner is one), so void and outside samples count for nothing. A
 * cut can draw a little more than the full mesh: at a void's edge a leaf draws the triangles
 * whose three vertices are drawn. */
static size_t full_mesh_bound(const store_export* x)
{
    size_t cells = (size_t)2 * (size_t)(x->g->src_width - 1) * (size_t)(x->g->src_height - 1);
    size_t drawn = (size_t)2 * x->sc.info.header.valid_samples;
    return drawn < cells ? drawn : cells;
}

static int write_mesh(store_export* x, mesh_build* m, const char* camera_text, const char* lod_text,
                      double sum, size_t count)
{
    const tp_store_header* h = &x->sc.info.header;
    if (m->tris == 0) {
        tp_cli_error("%s: nothing to export (no drawn triangle in the cut)", x->r->store_path);
        return TP_EXIT_FAILURE;
    }
    tp_error err;
    if (tp_mesh_check_size(x->r->format, m->points, m->tris, &err) != TP_OK) {
        tp_cli_error("%s: %s", x->r->out, err.message);
        return TP_EXIT_FAILURE;
    }
    double* xyz = malloc(3 * m->points * sizeof *xyz);
    if (!xyz)
        return tp_store_export_fail(x, "out of memory building the mesh");
    double origin[3] = {0, 0, 0};
    if (x->r->origin_local) {
        double e, nn;
        tp_georef_grid_to_proj(x->sc.georef, 0, 0, &e, &nn);
        origin[0] = floor(e / 1000) * 1000;
        origin[1] = floor(nn / 1000) * 1000;
    }
    for (size_t i = 0; i < m->points; i++) {
        double e, nn;
        tp_georef_grid_to_proj(x->sc.georef, m->px[i], m->py[i], &e, &nn);
        xyz[3 * i + 0] = e - origin[0];
        xyz[3 * i + 1] = nn - origin[1];
        xyz[3 * i + 2] = m->pz[i] - origin[2];
    }
    /* clockwise in (column, row) as the DEM path's strips: reversed unless north-up */
    if (!(h->geotransform[1] * h->geotransform[5] < 0))
        for (size_t t = 0; t < m->tris; t++) {
            uint64_t s = m->tri[3 * t + 1];
            m->tri[3 * t + 1] = m->tri[3 * t + 2];
            m->tri[3 * t + 2] = s;
        }
    int epsg;
    char zone[TP_ZONE_TEXT_SIZE];
    tp_export_zone_of_crs(h->crs_wkt, &epsg, zone);
    /* format 4 keeps which samples the build filled (tp_cut_vertices' TP_SAMPLE_FILLED) */
    const char* note = "from the store's filled bits: 1 where the build filled an interior void";
    tp_mesh mesh = {
        .point_count = m->points,
        .xyz = xyz,
        .elevation_m = m->pz,
        .void_filled = m->pf,
        .triangle_count = m->tris,
        .triangles = m->tri,
        .patch_id = x->r->tin ? NULL : m->patch,
        .lod = x->r->tin ? NULL : m->lod,
        .max_error_m = m->err,
        .crs_wkt = h->crs_wkt,
        .epsg = epsg,
        .utm_zone = zone,
        .source_file = x->r->store_path,
        .camera = camera_text,
        .lod_params = lod_text,
        .program_version = "terrapatch " TP_VERSION,
        .origin = {origin[0], origin[1], origin[2]},
        .void_filled_note = note,
    };
    tp_status st = tp_mesh_write(x->r->out, x->r->format, &mesh, &err);
    free(xyz);
    if (st != TP_OK) {
        if (tp_interrupted())
            return tp_cli_interrupted();
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    double mx = 0;
    for (size_t t = 0; t < m->tris; t++)
        mx = m->err[t] > mx ? m->err[t] : mx;
    /* --full writes the full mesh: its count is exact; the other modes give a bound from the
     * drawn samples (reading every leaf to count would cost the whole store) */
    int exact = x->r->mode == TP_STORE_EXPORT_FULL;
    size_t full = exact ? m->tris : full_mesh_bound(x);
    if (x->r->tin) {
        printf("wrote %s: %zu points, %zu triangles (%.2f%% of the at most %zu of the full "
               "mesh), measured error (against the store's full-resolution samples) max %.3f m, "
               "RMS %.3f m; %zu tiles of %d cells built one window at a time, %zu leaves read\n",
               x->r->out, m->points, m->tris, 100.0 * m->tris / (full ? full : 1), full, mx,
               count ? sqrt(sum / count) : 0.0, x->tin.tiles, TP_TIN_EXPORT_TILE_CELLS,
               x->cache->reads);
        return TP_EXIT_OK;
    }
    printf("wrote %s: %zu points, %zu triangles (%.2f%% of the %s%zu of the full mesh), "
           "measured error (against the store's full-resolution samples) max %.3f m, RMS %.3f m; "
           "%zu nodes drawn, %zu resident at most (%.1f MiB), %zu more leaves read for the "
           "error\n",
           x->r->out, m->points, m->tris, 100.0 * m->tris / (full ? full : 1),
           exact ? "" : "at most ", full, mx, count ? sqrt(sum / count) : 0.0, x->drawn,
           x->res.peak_bytes / (x->res.block_samples * 2), x->res.peak_bytes / 1048576.0,
           x->cache->reads);
    return TP_EXIT_OK;
}

/* ---- the export ---- */

/* Bytes of memory a mesh takes per triangle while it is built, copied into VTK and written
 * (about 60 in the mesh, 80 in VTK's copy, the compressed file in memory; .vtk/.vtm and the
 * camera and --max-error modes, which build it whole). */
#define MESH_BYTES_PER_TRIANGLE 200

int tp_export_store(const tp_store_export_request* r)
{
    store_export x;
    memset(&x, 0, sizeof x);
    x.r = r;
    int code = tp_store_scene_open(r->store_path, &x.sc);
    if (code != TP_EXIT_OK)
        return code;
    x.g = tp_tree_get_geometry(x.sc.tree);
    size_t count;
    x.metas = tp_store_metas(x.sc.store, &count);
    x.n = x.g->n;
    x.step_m = x.sc.info.header.height_step_m;
    x.unit = x.sc.info.header.err_unit_steps;
    x.quant_m = x.sc.info.header.quant_max_error_m;
    x.res.sc = &x.sc;
    x.res.block_samples = tp_tree_block_words(x.n); /* samples and cell mask */
    x.res.block = calloc((size_t)x.g->node_count, sizeof *x.res.block);
    x.cache = calloc(1, sizeof *x.cache);
    mesh_build m = {0};
    char camera_text[256] = "", lod_text[200] = "";
    double sum = 0;
    size_t samples = 0;
    tp_error err;
    if (!x.res.block || !x.cache) {
        code = tp_store_export_fail(&x, "out of memory");
        goto done;
    }
    x.cache->res = &x.res;
    x.cache->g = x.g;
    x.cache->step_m = x.step_m;
    x.cache->metas = x.metas;
    for (int i = 0; i < LEAF_CACHE_SLOTS; i++)
        x.cache->key[i] = -1;
    if (tp_cut_create(x.sc.tree, &x.cut, &err) != TP_OK) {
        code = tp_store_export_fail(&x, err.message);
        goto done;
    }
    if (r->mode == TP_STORE_EXPORT_FULL) {
        size_t full = full_mesh_bound(&x);
        if (full > TP_STORE_EXPORT_MAX_TRIANGLES) {
            code = tp_store_export_too_many(&x, full, "--full would write up to");
            goto done;
        }
        snprintf(lod_text, sizeof lod_text, "mode=full");
        code = tp_store_cut_full(&x);
    } else if (r->mode == TP_STORE_EXPORT_MAX_ERROR && r->tin) {
        snprintf(lod_text, sizeof lod_text, "mode=max-error mesh=tin max_error_m=%g",
                 r->max_error_m);
        if (!tp_store_tin_mesh(x.cache, x.g->src_width, x.g->src_height, r->max_error_m,
                               TP_STORE_EXPORT_MAX_TRIANGLES, &m, &x.tin, &err)) {
            if (tp_interrupted())
                code = tp_cli_interrupted();
            else if (m.tris > TP_STORE_EXPORT_MAX_TRIANGLES)
                code = tp_store_export_too_many(&x, m.tris, "the TIN passes");
            else
                code = tp_store_export_fail(&x, err.message);
            goto done;
        }
        sum = x.tin.sum_sq;
        samples = x.tin.samples;
    } else if (r->mode == TP_STORE_EXPORT_MAX_ERROR) {
        if (r->max_error_m < x.quant_m) {
            tp_cli_error("--max-error %g m is below the quantisation error of this "
                         "store (%g m, half of its %g m height step at most)",
                         r->max_error_m, x.quant_m, x.step_m);
            code = TP_EXIT_USAGE;
            goto done;
        }
        snprintf(lod_text, sizeof lod_text, "mode=max-error max_error_m=%g", r->max_error_m);
        code = tp_store_cut_max_error(&x);
    } else {
        const tp_view_setup* vs = r->vs;
        tp_camera cam;
        if (vs->has_camera) {
            if (!tp_camera_from_option_georef(x.sc.georef, vs->camera_geo, vs->camera, vs->fov_deg,
                                              vs->w, vs->h, &cam, "export")) {
                code = TP_EXIT_FAILURE;
                goto done;
            }
        } else {
            const tp_tree_info* ti = &x.sc.tree_info;
            tp_camera_default_extent(ti->geotransform, x.g->src_width, x.g->src_height,
                                     isnan(ti->min_height_m) ? 0 : ti->min_height_m,
                                     isnan(ti->max_height_m) ? 0 : ti->max_height_m, vs->fov_deg,
                                     vs->w, vs->h, 1, &cam);
        }
        tp_camera_text_georef(x.sc.georef, &cam, camera_text, sizeof camera_text);
        const tp_lod_params* lp = &vs->lod;
        snprintf(lod_text, sizeof lod_text,
                 "mode=%s tau_px=%g mindist_m=%g maxdist_m=%g exp=%g fov_deg=%g size=%dx%d "
                 "(store cut; 0 = default)",
                 lp->mode == TP_LOD_DISTANCE ? "distance"
                 : lp->mode == TP_LOD_FULL   ? "full"
                                             : "error",
                 lp->tau_px, lp->mindist_m, lp->maxdist_m, lp->exponent, vs->fov_deg, vs->w, vs->h);
        /* An export keeps every drawn sample: no holes along voids (incomplete nodes at full
         * resolution), so its outline is the data's, at any camera. */
        tp_lod_params exact = *lp;
        exact.hole_px = 1e-300;
        if (r->view_tins) {
            strncat(lod_text, " mesh=tin", sizeof lod_text - strlen(lod_text) - 1);
            if (tp_tin_cache_create(x.sc.tree, &x.tins, &err) != TP_OK) {
                code = tp_store_export_fail(&x, err.message);
                goto done;
            }
            tp_cut_set_tins(x.cut, x.tins);
        }
        code = tp_store_cut_camera(&x, &cam, &exact);
    }
    if (code == TP_EXIT_OK && !r->tin &&
        !tp_store_export_room_for(&x, (uint64_t)x.tris_cut * MESH_BYTES_PER_TRIANGLE,
                                  "the mesh of the cut"))
        code = TP_EXIT_FAILURE;
    if (code == TP_EXIT_OK && !r->tin)
        code = build_mesh(&x, &m, &sum, &samples);
    if (code == TP_EXIT_OK) {
        /* the nodes are no longer needed: release them before the writer allocates */
        tp_res_release_except(&x.res, NULL);
        code = write_mesh(&x, &m, camera_text, lod_text, sum, samples);
    }
done:
    tp_mesh_build_free(&m);
    if (x.cache)
        for (int i = 0; i < LEAF_CACHE_SLOTS; i++)
            free(x.cache->slot[i]);
    free(x.cache);
    tp_cut_destroy(x.cut);
    tp_tin_cache_destroy(x.tins);
    if (x.res.block)
        tp_res_release_except(&x.res, NULL);
    free(x.res.block);
    free(x.res.ids);
    tp_store_scene_close(&x.sc);
    return code;
}
