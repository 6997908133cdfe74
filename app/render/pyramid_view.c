/* pyramid_view.c - a store's pyramid as a clipmap's source (see pyramid_view.h). */
#define _POSIX_C_SOURCE 200809L
#include "pyramid_view.h"

#include "cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int tp_view_pyramid_beside(const char* store_path, const char* ext, char* out, size_t cap)
{
    size_t n = strlen(store_path);
    int tpt = n >= 4 && strcmp(store_path + n - 4, ".tpt") == 0;
    int w = tpt ? snprintf(out, cap, "%.*s%s", (int)(n - 4), store_path, ext)
                : snprintf(out, cap, "%s%s", store_path, ext);
    struct stat sb;
    unsigned char head[8];
    if (w <= 0 || (size_t)w >= cap)
        return 0;
    if (tp_input_is_url(out)) /* one HEAD request: 404 when there is none */
        return tp_input_url_head(out, head, sizeof head, NULL) == TP_OK;
    return stat(out, &sb) == 0 && S_ISREG(sb.st_mode);
}

static int read_block(void* user, tp_block_key k, uint8_t* rgba, tp_error* err)
{
    return tp_imagery_read_block(user, k.level, (int)k.bx, (int)k.by, rgba, err) == TP_OK;
}

static int block_empty(void* user, tp_block_key k)
{
    return tp_imagery_block_is_empty(user, k.level, (int)k.bx, (int)k.by);
}

void tp_view_pyramid_source(tp_imagery* im, tp_block_source* out)
{
    tp_imagery_info in;
    tp_imagery_get_info(im, &in);
    memset(out, 0, sizeof *out);
    out->block = in.block;
    out->levels = in.levels < TP_CLIP_MAX_LEVELS ? in.levels : TP_CLIP_MAX_LEVELS;
    out->read = read_block;
    out->is_empty = block_empty;
    out->user = im;
    for (int l = 0; l < out->levels; l++)
        tp_imagery_level_size(im, l, &out->width[l], &out->height[l], NULL, NULL);
}

/* The pyramid's grid is the store's: the same size (the source grid's, or the fitted one) and
 * geotransform (to a millionth of a post: both are the same doubles, written and read back
 * exactly). */
static int same_grid(const tp_imagery_info* in, const tp_store_scene* st)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(st->tree);
    const double* gt = st->tree_info.geotransform;
    if ((in->grid_width != g->width || in->grid_height != g->height) &&
        (in->grid_width != g->src_width || in->grid_height != g->src_height))
        return 0;
    for (int i = 0; i < 6; i++)
        if (fabs(in->grid_geotransform[i] - gt[i]) > 1e-6 * fmax(fabs(gt[1]), fabs(gt[5])))
            return 0;
    return 1;
}

static const char* kind_name(int kind)
{
    return kind == TP_IMAGERY_KIND_LIGHT_TIMES ? "a light map over a day (.tpl)"
                                               : "an imagery pyramid (.tpi)";
}

tp_imagery* tp_view_pyramid_open(const char* path, const tp_store_scene* st, int kind,
                                 const char* remake, tp_imagery_info* info)
{
    tp_imagery* im = NULL;
    tp_error err;
    if (tp_imagery_open(path, &im, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return NULL;
    }
    tp_imagery_get_info(im, info);
    const tp_tree_geometry* g = tp_tree_get_geometry(st->tree);
    if (info->kind != kind) {
        tp_cli_error("%s: is %s, not %s", path, kind_name(info->kind), kind_name(kind));
    } else if (!same_grid(info, st)) {
        tp_cli_error("%s: made for another grid (%dx%d posts from %.3f, %.3f; the store's "
                     "is %dx%d from %.3f, %.3f): build it again with %s",
                     path, info->grid_width, info->grid_height, info->grid_geotransform[0],
                     info->grid_geotransform[3], g->width, g->height, st->tree_info.geotransform[0],
                     st->tree_info.geotransform[3], remake);
    } else {
        return im;
    }
    tp_imagery_close(im);
    return NULL;
}

/* The smallest distance from the eye to a drawn node's box (its footprint, the store's height
 * range); INFINITY when nothing is drawn. The finest level is that of the nearest node:
 * tp_clipmap_finest_level's levels never fall as the distance grows. */
static double nearest_node(const tp_store_scene* st, const tp_cut* cut, double zscale,
                           const tp_camera* cam)
{
    size_t count = 0;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    const tp_tree_geometry* g = tp_tree_get_geometry(st->tree);
    const double* gt = st->tree_info.geotransform;
    double z0 = st->tree_info.min_height_m * zscale, z1 = st->tree_info.max_height_m * zscale;
    const double* p = cam->position;
    double dz = z0 <= z1 ? fmax(0, fmax(z0 - p[2], p[2] - z1)) : 0, nearest2 = INFINITY;
    for (size_t i = 0; i < count; i++) {
        int sc, c, r;
        tp_tree_node_locate(g, nodes[i].node, &sc, &c, &r);
        double span = ldexp(1.0, g->n + sc);
        double e0 = gt[0] + c * span * gt[1], e1 = e0 + span * gt[1];
        double n0 = gt[3] + r * span * gt[5], n1 = n0 + span * gt[5];
        double dx = fmax(0, fmax(fmin(e0, e1) - p[0], p[0] - fmax(e0, e1)));
        double dy = fmax(0, fmax(fmin(n0, n1) - p[1], p[1] - fmax(n0, n1)));
        double d2 = dx * dx + dy * dy;
        nearest2 = d2 < nearest2 ? d2 : nearest2;
    }
    return sqrt(nearest2 + dz * dz);
}

void tp_view_clip_frame(tp_view_clip_state* s, tp_clipmap* m, const tp_store_scene* st,
                        const tp_cut* cut, double zscale, const tp_camera* cam, int settle,
                        tp_clipmap_stats* stats, tp_render_clip* out)
{
    double nearest = nearest_node(st, cut, zscale, cam);
    s->finest = isfinite(nearest) ? tp_clipmap_finest_level(m, cam, &nearest, 1, s->finest) : 0;
    if (settle)
        tp_clipmap_settle(m, cam, s->finest, 60, stats);
    else
        tp_clipmap_update(m, cam, s->finest, stats);
    tp_clipmap_render_clip(m, out);
}

void tp_view_clip_state_free(tp_view_clip_state* s)
{
    s->finest = -1;
}
