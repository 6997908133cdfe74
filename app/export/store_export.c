/* store_export.c - `terrapatch export` on a store (see store_export.h). */
#include "store_export.h"
#include "full_export.h"
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

/* ---- the export ---- */

typedef struct store_export {
    const tp_store_export_request* r;
    tp_store_scene sc;
    const tp_tree_geometry* g;
    const tp_node_meta* metas;
    residency res;
    leaf_cache* cache;
    tp_cut* cut;
    double step_m, unit, quant_m;
    int n;
    size_t tris_cut;        /* triangles of the final cut (for the size check) */
    size_t drawn;           /* nodes of the final cut */
    tp_store_tin_stats tin; /* r->tin: the tiles built */
} store_export;

static int fail(store_export* x, const char* what)
{
    if (strstr(what, x->r->store_path)) /* the store's messages name the file */
        tp_cli_error("%s", what);
    else
        tp_cli_error("%s: %s", x->r->store_path, what);
    return TP_EXIT_FAILURE;
}

static int too_many(store_export* x, size_t tris, const char* how)
{
    tp_cli_error(
        "%s: %s %zu triangles, over the export limit of %zu (%s); "
        "export a coarser mesh: --max-error M, or a camera (--camera/--camera-geo) in error "
        "or distance mode",
        x->r->store_path, how, tris, TP_STORE_EXPORT_MAX_TRIANGLES,
        "TP_STORE_EXPORT_MAX_TRIANGLES, app/export/store_export.h");
    return TP_EXIT_FAILURE; /* as the DEM path's --full over the memory available */
}

/* Bytes of memory a mesh takes per triangle while it is built, copied into VTK and written
 * (about 60 in the mesh, 80 in VTK's copy, the compressed file in memory; .vtk/.vtm and the
 * camera and --max-error modes, which build it whole). */
#define MESH_BYTES_PER_TRIANGLE 200
/* Memory that must stay free while the cut's nodes are read. */
#define NODE_READ_MARGIN_BYTES ((uint64_t)64 << 20)

/* 1 if `more` bytes fit in what the process may still use (TP_MEMORY_LIMIT, ulimit -v, the
 * cgroup, MemAvailable), else 0 after one line saying what needs them. */
static int room_for(store_export* x, uint64_t more, const char* what)
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

/* The camera's cut with every node it draws resident: update, read what it requests, again,
 * until it requests nothing (then nothing is substituted). */
static int cut_for_camera(store_export* x, const tp_camera* cam, const tp_lod_params* lod)
{
    int64_t* roots = malloc((size_t)x->g->root_count * sizeof *roots);
    if (!roots)
        return fail(x, "out of memory");
    tp_tree_roots(x->g, roots, (size_t)x->g->root_count);
    for (int64_t i = 0; i < x->g->root_count; i++)
        if (!tp_res_load(&x->res, roots[i])) {
            free(roots);
            return fail(x, x->res.err.message);
        }
    free(roots);
    tp_error err;
    for (int it = 0;; it++) {
        if (tp_cut_update(x->cut, cam, lod, &err) != TP_OK)
            return fail(x, err.message);
        tp_cut_stats st;
        tp_cut_get_stats(x->cut, &st);
        if (st.triangles > TP_STORE_EXPORT_MAX_TRIANGLES)
            return too_many(x, st.triangles, "the camera's cut draws at least");
        size_t nr;
        const int64_t* req = tp_cut_requests(x->cut, &nr);
        if (nr == 0) {
            if (st.substituted != 0) /* cannot happen: a substituted node requests */
                return fail(x, "the cut still substitutes nodes with nothing left to read");
            x->tris_cut = st.triangles;
            break;
        }
        /* the requests are valid until the next update: copy them before reading */
        int64_t* ids = malloc(nr * sizeof *ids);
        if (!ids)
            return fail(x, "out of memory");
        memcpy(ids, req, nr * sizeof *ids);
        for (size_t i = 0; i < nr; i++)
            if (!tp_res_load(&x->res, ids[i])) {
                free(ids);
                return fail(x, x->res.err.message);
            }
        free(ids);
        if (tp_interrupted())
            return tp_cli_interrupted();
        if (!room_for(x, NODE_READ_MARGIN_BYTES, "reading the camera's cut at full detail"))
            return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

/* ---- --max-error: a static cut chosen on the node table ---- */

static double bound_m(const store_export* x, int64_t node, int k, const int nb[4])
{
    return tp_node_error_bound(&x->metas[node], x->n, k, nb, x->step_m, x->unit) + x->quant_m;
}

/* The coarsest level k of node whose bound (no stitching) stays <= M at k and every finer
 * level, or -1 when the node is to be replaced by its children. */
static int static_level(const store_export* x, int64_t node, int scale)
{
    const tp_node_meta* m = &x->metas[node];
    double M = x->r->max_error_m;
    if (scale > 0 && (!(m->flags & TP_NODE_COMPLETE) || bound_m(x, node, x->n, NULL) > M))
        return -1;
    if (!(m->flags & TP_NODE_COMPLETE))
        return x->n; /* an incomplete leaf: only drawn at n */
    int k = x->n;
    while (k > 0 && bound_m(x, node, k - 1, NULL) <= M)
        k--;
    return k;
}

typedef struct choice {
    int8_t* level; /* per node: drawn level, -1 when not chosen */
    int64_t* ids;  /* chosen ids (may hold stale ones: level -1) */
    size_t count, cap;
} choice;

/* Chooses node, or the nodes under it, at their static levels. */
static int choose(store_export* x, choice* ch, int64_t node)
{
    int64_t stack[4 * TP_TREE_MAX_SCALES + 4];
    int top = 0;
    stack[top++] = node;
    while (top > 0) {
        int64_t id = stack[--top];
        if (!(x->metas[id].flags & TP_NODE_HAS_DRAWN))
            continue;
        int s, c, r;
        tp_tree_node_locate(x->g, id, &s, &c, &r);
        int k = static_level(x, id, s);
        if (k < 0) {
            for (int q = 0; q < 4; q++)
                stack[top++] = tp_tree_node_child(x->g, id, q);
            continue;
        }
        if (!tp_array_grow((void**)&ch->ids, &ch->cap, ch->count + 1, sizeof *ch->ids))
            return 0;
        ch->level[id] = (int8_t)k;
        ch->ids[ch->count++] = id;
    }
    return 1;
}

/* The chosen node of scale >= the scale of `node` that borders it on side (0 top, 1 right,
 * 2 bottom, 3 left), or -1 (smaller nodes there, or the map's edge). */
static int64_t chosen_neighbor(const store_export* x, const choice* ch, int64_t node, int side)
{
    static const int dc[4] = {0, 1, 0, -1}, dr[4] = {-1, 0, 1, 0};
    int s, c, r;
    tp_tree_node_locate(x->g, node, &s, &c, &r);
    int64_t cc = (int64_t)c + dc[side], rr = (int64_t)r + dr[side];
    if (cc < 0 || rr < 0)
        return -1;
    for (; s < x->g->scales; s++, cc >>= 1, rr >>= 1) {
        if (cc >= x->g->node_cols[s] || rr >= x->g->node_rows[s])
            return -1;
        int64_t id = tp_tree_node_id(x->g, s, (int)cc, (int)rr);
        if (ch->level[id] >= 0)
            return id;
    }
    return -1;
}

/* Replaces chosen node b by its children at their static levels. */
static int split_choice(store_export* x, choice* ch, int64_t b)
{
    ch->level[b] = -1;
    for (int q = 0; q < 4; q++)
        if (!choose(x, ch, tp_tree_node_child(x->g, b, q)))
            return 0;
    return 1;
}

/* No two chosen neighbours more than n scales apart (the stitching could not join them without
 * drawing an ancestor at level n, whose error is not bounded by M): the larger one is split. */
static int balance(store_export* x, choice* ch)
{
    for (int changed = 1; changed;) {
        changed = 0;
        for (size_t i = 0; i < ch->count; i++) {
            int64_t a = ch->ids[i];
            if (ch->level[a] < 0)
                continue;
            int sa, c, r;
            tp_tree_node_locate(x->g, a, &sa, &c, &r);
            for (int side = 0; side < 4; side++) {
                int64_t b = chosen_neighbor(x, ch, a, side);
                int sb;
                if (b < 0)
                    continue;
                tp_tree_node_locate(x->g, b, &sb, &c, &r);
                if (sb - sa > x->n) {
                    if (!split_choice(x, ch, b))
                        return 0;
                    changed = 1;
                }
            }
        }
    }
    size_t w = 0; /* drop the stale ids */
    for (size_t i = 0; i < ch->count; i++)
        if (ch->level[ch->ids[i]] >= 0)
            ch->ids[w++] = ch->ids[i];
    ch->count = w;
    return 1;
}

/* Installs the chosen nodes as the cut (tp_cut_set_nodes stitches them) with them resident and
 * nothing else. */
static int install(store_export* x, choice* ch, uint8_t* keep)
{
    int* levels = malloc((ch->count ? ch->count : 1) * sizeof *levels);
    if (!levels)
        return fail(x, "out of memory");
    for (size_t i = 0; i < ch->count; i++) {
        levels[i] = ch->level[ch->ids[i]];
        keep[ch->ids[i]] = 1;
    }
    tp_res_release_except(&x->res, keep);
    for (size_t i = 0; i < ch->count; i++) {
        keep[ch->ids[i]] = 0;
        if (!tp_res_load(&x->res, ch->ids[i])) {
            free(levels);
            return fail(x, x->res.err.message);
        }
    }
    tp_error err;
    tp_status st = tp_cut_set_nodes(x->cut, ch->ids, levels, ch->count, &err);
    free(levels);
    return st == TP_OK ? TP_EXIT_OK : fail(x, err.message);
}

/* --max-error M: chosen on the node table, stitched, and where a stitched node's bound (its
 * eps table for the neighbour levels it really has) passes M, the coarser neighbour that moves
 * its vertices is raised one level (split at level n), until no drawn node passes M. */
static int cut_max_error(store_export* x)
{
    double M = x->r->max_error_m;
    choice ch = {0};
    uint8_t* keep = calloc((size_t)x->g->node_count, 1);
    ch.level = malloc((size_t)x->g->node_count);
    int64_t* roots = malloc((size_t)x->g->root_count * sizeof *roots);
    int code = TP_EXIT_OK;
    if (!keep || !ch.level || !roots) {
        code = fail(x, "out of memory");
        goto done;
    }
    memset(ch.level, -1, (size_t)x->g->node_count);
    tp_tree_roots(x->g, roots, (size_t)x->g->root_count);
    for (int64_t i = 0; i < x->g->root_count; i++)
        if (!choose(x, &ch, roots[i])) {
            code = fail(x, "out of memory");
            goto done;
        }
    for (int round = 0;; round++) {
        if (!balance(x, &ch)) {
            code = fail(x, "out of memory");
            goto done;
        }
        size_t tris = 0;
        for (size_t i = 0; i < ch.count; i++)
            tris += (size_t)2 << (2 * ch.level[ch.ids[i]]);
        if (tris > TP_STORE_EXPORT_MAX_TRIANGLES) {
            code = too_many(x, tris, "--max-error's cut draws up to");
            goto done;
        }
        if ((code = install(x, &ch, keep)) != TP_EXIT_OK)
            goto done;
        size_t count;
        const tp_cut_node* out = tp_cut_nodes(x->cut, &count);
        for (size_t i = 0; i < count; i++) /* the stitching only raises levels */
            ch.level[out[i].node] = out[i].level;
        int raised = 0;
        for (size_t i = 0; i < count; i++) {
            int nb[4];
            memcpy(nb, (int[4]){out[i].nb[0], out[i].nb[1], out[i].nb[2], out[i].nb[3]}, sizeof nb);
            if (bound_m(x, out[i].node, out[i].level, nb) <= M)
                continue;
            for (int side = 0; side < 4; side++) {
                int one[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
                one[side] = nb[side];
                if (nb[side] == TP_NO_NEIGHBOR || bound_m(x, out[i].node, out[i].level, one) <= M)
                    continue;
                int64_t b = chosen_neighbor(x, &ch, out[i].node, side);
                if (b < 0 || b == out[i].node)
                    continue;
                if (ch.level[b] < x->n) {
                    ch.level[b]++;
                } else {
                    int sb, c, r;
                    tp_tree_node_locate(x->g, b, &sb, &c, &r);
                    if (sb == 0)
                        continue; /* a leaf at n moves nothing of a node of its size */
                    if (!split_choice(x, &ch, b)) {
                        code = fail(x, "out of memory");
                        goto done;
                    }
                }
                raised++;
            }
        }
        if (!raised)
            break;
        if (round > 64 * (x->n + x->g->scales)) {
            code = fail(x, "--max-error: the stitched cut does not settle (a bug)");
            goto done;
        }
    }
    {
        tp_cut_stats st;
        tp_cut_get_stats(x->cut, &st);
        x->tris_cut = st.triangles;
    }
done:
    free(keep);
    free(ch.level);
    free(ch.ids);
    free(roots);
    return code;
}

/* --full: every leaf at level n (the size was checked before). */
static int cut_full(store_export* x)
{
    choice ch = {0};
    uint8_t* keep = calloc((size_t)x->g->node_count, 1);
    ch.level = malloc((size_t)x->g->node_count);
    int code = TP_EXIT_OK;
    if (!keep || !ch.level) {
        code = fail(x, "out of memory");
        goto done;
    }
    memset(ch.level, -1, (size_t)x->g->node_count);
    for (int r = 0; r < x->g->rows; r++)
        for (int c = 0; c < x->g->cols; c++) {
            int64_t id = tp_tree_node_id(x->g, 0, c, r);
            if (!(x->metas[id].flags & TP_NODE_HAS_DRAWN))
                continue;
            if (!tp_array_grow((void**)&ch.ids, &ch.cap, ch.count + 1, sizeof *ch.ids)) {
                code = fail(x, "out of memory");
                goto done;
            }
            ch.level[id] = (int8_t)x->n;
            ch.ids[ch.count++] = id;
        }
    code = install(x, &ch, keep);
done:
    free(keep);
    free(ch.level);
    free(ch.ids);
    return code;
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
        code = fail(x, "out of memory");
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
                    code = fail(x, x->res.err.message);
                    goto done;
                }
                continue;
            }
            uint64_t p[3];
            for (int c = 0; c < 3; c++)
                if ((p[c] = tp_mesh_point(m, v[c]->x, v[c]->y, (double)v[c]->z_m,
                                          v[c]->cls == TP_SAMPLE_FILLED)) == UINT64_MAX) {
                    code = fail(x, "out of memory building the mesh");
                    goto done;
                }
            int32_t a[2] = {v[0]->x, v[0]->y}, b[2] = {v[1]->x, v[1]->y},
                    cc[2] = {v[2]->x, v[2]->y};
            tri_error e = {x->cache, 0, 0, 0};
            tp_triangle_rasterize(a, b, cc, v[0]->z_m, v[1]->z_m, v[2]->z_m, error_at, &e);
            if (x->cache->failed) {
                code = fail(x, x->res.err.message);
                goto done;
            }
            *sum += e.sum;
            *count += e.count;
            if (!tp_mesh_add_triangle(m, p, (int32_t)out[i].node, (uint8_t)out[i].level, e.max)) {
                code = fail(x, "out of memory building the mesh");
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
        return fail(x, "out of memory building the mesh");
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
        code = fail(&x, "out of memory");
        goto done;
    }
    x.cache->res = &x.res;
    x.cache->g = x.g;
    x.cache->step_m = x.step_m;
    x.cache->metas = x.metas;
    for (int i = 0; i < LEAF_CACHE_SLOTS; i++)
        x.cache->key[i] = -1;
    if (tp_cut_create(x.sc.tree, &x.cut, &err) != TP_OK) {
        code = fail(&x, err.message);
        goto done;
    }
    if (r->mode == TP_STORE_EXPORT_FULL) {
        size_t full = full_mesh_bound(&x);
        if (full > TP_STORE_EXPORT_MAX_TRIANGLES) {
            code = too_many(&x, full, "--full would write up to");
            goto done;
        }
        snprintf(lod_text, sizeof lod_text, "mode=full");
        code = cut_full(&x);
    } else if (r->mode == TP_STORE_EXPORT_MAX_ERROR && r->tin) {
        snprintf(lod_text, sizeof lod_text, "mode=max-error mesh=tin max_error_m=%g",
                 r->max_error_m);
        if (!tp_store_tin_mesh(x.cache, x.g->src_width, x.g->src_height, r->max_error_m,
                               TP_STORE_EXPORT_MAX_TRIANGLES, &m, &x.tin, &err)) {
            if (tp_interrupted())
                code = tp_cli_interrupted();
            else if (m.tris > TP_STORE_EXPORT_MAX_TRIANGLES)
                code = too_many(&x, m.tris, "the TIN passes");
            else
                code = fail(&x, err.message);
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
        code = cut_max_error(&x);
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
        code = cut_for_camera(&x, &cam, &exact);
    }
    if (code == TP_EXIT_OK && !r->tin &&
        !room_for(&x, (uint64_t)x.tris_cut * MESH_BYTES_PER_TRIANGLE, "the mesh of the cut"))
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
    if (x.res.block)
        tp_res_release_except(&x.res, NULL);
    free(x.res.block);
    free(x.res.ids);
    tp_store_scene_close(&x.sc);
    return code;
}
