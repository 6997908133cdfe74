/* imagery_view.c - the viewer's imagery through a clipmap (see imagery_view.h). */
#define _POSIX_C_SOURCE 200809L
#include "imagery_view.h"

#include "cli.h"
#include "pyramid_view.h"
#include "tp_imagery.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

struct tp_view_imagery {
    tp_imagery* im;
    tp_clipmap* clip;
    tp_imagery_blocks* blocks; /* instead of clip in blocks mode */
    char path[4096];
    tp_view_clip_state cs;
};

int tp_view_imagery_beside(const char* store_path, char* out, size_t cap)
{
    return tp_view_pyramid_beside(store_path, ".tpi", out, cap);
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
        tp_cli_error("%s: out of memory", path);
        return 0;
    }
    snprintf(vi->path, sizeof vi->path, "%s", path);
    vi->cs.finest = -1;
    tp_imagery_info in;
    vi->im = tp_view_pyramid_open(path, st, TP_IMAGERY_KIND_IMAGE, "terrapatch imagery", &in);
    if (!vi->im) {
        free(vi);
        return 0;
    }
    const tp_tree_geometry* g = tp_tree_get_geometry(st->tree);
    tp_block_source src;
    tp_view_pyramid_source(vi->im, &src);
    tp_error err = {{0}};
    if (mode == TP_IMAGERY_BLOCKS) {
        tp_imagery_blocks_options bo = {.cache_bytes = o ? o->cache_bytes : 0,
                                        .no_loader = o ? o->no_loader : 0};
        vi->blocks = tp_imagery_blocks_create(&src, in.texel_shift, in.geotransform, g, &bo, &err);
    } else {
        vi->clip = tp_clipmap_create(&src, in.geotransform, o, &err);
    }
    if (!vi->clip && !vi->blocks) {
        tp_cli_error("%s: %s", path, err.message);
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
    tp_view_clip_state_free(&vi->cs);
    free(vi);
}

void tp_view_imagery_frame(tp_view_imagery* vi, const tp_store_scene* st, const tp_cut* cut,
                           double zscale, tp_renderer* r, const tp_camera* cam, int settle,
                           tp_clipmap_stats* stats)
{
    if (vi->blocks) {
        tp_imagery_blocks_frame(vi->blocks, cut, r, cam, settle, 60, stats);
        return;
    }
    tp_render_clip rc;
    tp_view_clip_frame(&vi->cs, vi->clip, st, cut, zscale, cam, settle, stats, &rc);
    tp_renderer_set_clip(r, &rc);
}

void tp_view_imagery_report_failures(tp_view_imagery* vi)
{
    const char* f;
    while (vi && (f = vi->blocks ? tp_imagery_blocks_take_failure(vi->blocks)
                                 : tp_clipmap_take_failure(vi->clip)))
        tp_cli_error("%s (drawn without imagery there)", f);
}
