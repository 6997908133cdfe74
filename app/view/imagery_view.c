/* imagery_view.c - the viewer's imagery through a clipmap (see imagery_view.h). */
#define _POSIX_C_SOURCE 200809L
#include "imagery_view.h"

#include "tp_imagery.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

struct tp_view_imagery {
    tp_imagery* im;
    tp_clipmap* clip;
    tp_imagery_blocks* blocks; /* instead of clip in blocks mode */
    char path[4096];
    int finest;        /* last frame's finest level (frame coherence) */
    double* dist;      /* per cut node */
    size_t dist_cap;
};

int tp_view_imagery_beside(const char* store_path, char* out, size_t cap)
{
    size_t n = strlen(store_path);
    int tpt = n >= 4 && strcmp(store_path + n - 4, ".tpt") == 0;
    int w = tpt ? snprintf(out, cap, "%.*s.tpi", (int)(n - 4), store_path)
                : snprintf(out, cap, "%s.tpi", store_path);
    struct stat sb;
    return w > 0 && (size_t)w < cap && stat(out, &sb) == 0 && S_ISREG(sb.st_mode);
}

static int read_block(void* user, tp_block_key k, uint8_t* rgba, char* msg, size_t cap)
{
    tp_error err;
    if (tp_imagery_read_block(user, k.level, (int)k.bx, (int)k.by, rgba, &err) == TP_OK)
        return 1;
    snprintf(msg, cap, "%s", err.message);
    return 0;
}

static int block_empty(void* user, tp_block_key k)
{
    return tp_imagery_block_is_empty(user, k.level, (int)k.bx, (int)k.by);
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

int tp_imagery_mode_parse(const char* name, tp_imagery_mode* mode)
{
    if (strcmp(name, "clipmap") == 0)
        *mode = TP_IMAGERY_CLIPMAP;
    else if (strcmp(name, "blocks") == 0)
        *mode = TP_IMAGERY_BLOCKS;
    else
        return 0;
    return 1;
}

int tp_view_imagery_open(const char* path, const tp_store_scene* st, tp_imagery_mode mode,
                         const tp_clipmap_options* o, tp_view_imagery** out)
{
    tp_view_imagery* vi = calloc(1, sizeof *vi);
    if (!vi) {
        fprintf(stderr, "terrapatch: %s: out of memory\n", path);
        return 0;
    }
    snprintf(vi->path, sizeof vi->path, "%s", path);
    vi->finest = -1;
    tp_error err;
    if (tp_imagery_open(path, &vi->im, &err) != TP_OK) {
        fprintf(stderr, "terrapatch: %s\n", err.message);
        free(vi);
        return 0;
    }
    tp_imagery_info in;
    tp_imagery_get_info(vi->im, &in);
    const tp_tree_geometry* g = tp_tree_get_geometry(st->tree);
    if (!same_grid(&in, st)) {
        fprintf(stderr,
                "terrapatch: %s: made for another grid (%dx%d posts from %.3f, %.3f; the store's "
                "is %dx%d from %.3f, %.3f): build it again with terrapatch imagery\n",
                path, in.grid_width, in.grid_height, in.grid_geotransform[0],
                in.grid_geotransform[3], g->width, g->height, st->tree_info.geotransform[0],
                st->tree_info.geotransform[3]);
        tp_view_imagery_close(vi);
        return 0;
    }
    tp_block_source src = {.block = in.block, .levels = in.levels, .read = read_block,
                           .is_empty = block_empty, .user = vi->im};
    if (src.levels > TP_CLIP_MAX_LEVELS)
        src.levels = TP_CLIP_MAX_LEVELS;
    for (int l = 0; l < src.levels; l++)
        tp_imagery_level_size(vi->im, l, &src.width[l], &src.height[l], NULL, NULL);
    char msg[512];
    if (mode == TP_IMAGERY_BLOCKS) {
        tp_imagery_blocks_options bo = {.cache_bytes = o ? o->cache_bytes : 0,
                                        .no_loader = o ? o->no_loader : 0};
        vi->blocks = tp_imagery_blocks_create(&src, in.texel_shift, in.geotransform, g, &bo, msg,
                                              sizeof msg);
    } else {
        vi->clip = tp_clipmap_create(&src, in.geotransform, o, msg, sizeof msg);
    }
    if (!vi->clip && !vi->blocks) {
        fprintf(stderr, "terrapatch: %s: %s\n", path, msg);
        tp_view_imagery_close(vi);
        return 0;
    }
    *out = vi;
    return 1;
}

void tp_view_imagery_close(tp_view_imagery* vi)
{
    if (!vi)
        return;
    tp_clipmap_destroy(vi->clip);
    tp_imagery_blocks_destroy(vi->blocks);
    tp_imagery_close(vi->im);
    free(vi->dist);
    free(vi);
}

/* Distance from the eye to each drawn node's box (its footprint, the store's height range). */
static size_t node_distances(tp_view_imagery* vi, const tp_store_scene* st, const tp_cut* cut,
                             double zscale, const tp_camera* cam)
{
    size_t count = 0;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    if (count > vi->dist_cap) {
        double* d = realloc(vi->dist, count * sizeof *d);
        if (!d)
            return 0;
        vi->dist = d;
        vi->dist_cap = count;
    }
    const tp_tree_geometry* g = tp_tree_get_geometry(st->tree);
    const double* gt = st->tree_info.geotransform;
    double z0 = st->tree_info.min_height_m * zscale, z1 = st->tree_info.max_height_m * zscale;
    const double* p = cam->position;
    for (size_t i = 0; i < count; i++) {
        int s, c, r;
        tp_tree_node_locate(g, nodes[i].node, &s, &c, &r);
        double span = ldexp(1.0, g->n + s);
        double e0 = gt[0] + c * span * gt[1], e1 = e0 + span * gt[1];
        double n0 = gt[3] + r * span * gt[5], n1 = n0 + span * gt[5];
        double dx = fmax(0, fmax(fmin(e0, e1) - p[0], p[0] - fmax(e0, e1)));
        double dy = fmax(0, fmax(fmin(n0, n1) - p[1], p[1] - fmax(n0, n1)));
        double dz = z0 <= z1 ? fmax(0, fmax(z0 - p[2], p[2] - z1)) : 0;
        vi->dist[i] = sqrt(dx * dx + dy * dy + dz * dz);
    }
    return count;
}

void tp_view_imagery_frame(tp_view_imagery* vi, const tp_store_scene* st, const tp_cut* cut,
                           double zscale, tp_renderer* r, const tp_camera* cam, int settle,
                           tp_clipmap_stats* stats)
{
    if (vi->blocks) {
        tp_imagery_blocks_frame(vi->blocks, cut, r, cam, settle, 60, stats);
        return;
    }
    size_t count = node_distances(vi, st, cut, zscale, cam);
    vi->finest = count ? tp_clipmap_finest_level(vi->clip, cam, vi->dist, count, vi->finest) : 0;
    if (settle)
        tp_clipmap_settle(vi->clip, cam, vi->finest, 60, stats);
    else
        tp_clipmap_update(vi->clip, cam, vi->finest, stats);
    tp_render_clip rc;
    tp_clipmap_render_clip(vi->clip, &rc);
    tp_renderer_set_clip(r, &rc);
}

void tp_view_imagery_report_failures(tp_view_imagery* vi)
{
    const char* f;
    while (vi && (f = vi->blocks ? tp_imagery_blocks_take_failure(vi->blocks)
                                 : tp_clipmap_take_failure(vi->clip)))
        fprintf(stderr, "terrapatch: %s (drawn without imagery there)\n", f);
}
