/* light_view.c - the day's cast shadows through a clipmap (see light_view.h). */
#define _POSIX_C_SOURCE 200809L
#include "light_view.h"

#include "cli.h"
#include "pyramid_view.h"
#include "tp_imagery.h"

#include <stdio.h>
#include <stdlib.h>

struct tp_view_light {
    tp_imagery* im; /* NULL for tp_view_light_create */
    tp_clipmap* clip;
    double first_s, last_s;
    int maps;
    tp_view_clip_state cs;
};

int tp_view_light_beside(const char* store_path, char* out, size_t cap)
{
    return tp_view_pyramid_beside(store_path, ".tpl", out, cap);
}

tp_view_light* tp_view_light_create(const tp_block_source* src, const double gt[6], double first_s,
                                    double last_s, const tp_clipmap_options* o, tp_error* err)
{
    if (!(first_s < last_s)) {
        tp_error_set(err, TP_ERR_BAD_DATA, "the light map's day is empty (%.0f .. %.0f s)", first_s,
                     last_s);
        return NULL;
    }
    tp_view_light* l = calloc(1, sizeof *l);
    if (!l) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    l->first_s = first_s;
    l->last_s = last_s;
    l->cs.finest = -1;
    l->clip = tp_clipmap_create(src, gt, o, err);
    if (!l->clip) {
        free(l);
        return NULL;
    }
    return l;
}

int tp_view_light_open(const char* path, const tp_store_scene* st, const tp_clipmap_options* o,
                       tp_view_light** out)
{
    tp_imagery_info in;
    tp_imagery* im =
        tp_view_pyramid_open(path, st, TP_IMAGERY_KIND_LIGHT_TIMES, "terrapatch light --day", &in);
    if (!im)
        return 0;
    tp_block_source src;
    tp_view_pyramid_source(im, &src);
    tp_error err = {{0}};
    tp_view_light* l = NULL;
    if (in.texel_shift != 0) /* the renderer samples a texel per post */
        tp_error_set(&err, TP_ERR_BAD_DATA, "a light map has a texel per post (this one 2^%d)",
                     in.texel_shift);
    else
        l = tp_view_light_create(&src, in.geotransform, in.time_first_s, in.time_last_s, o, &err);
    if (!l) {
        tp_cli_error("%s: %s", path, err.message);
        tp_imagery_close(im);
        return 0;
    }
    l->im = im;
    l->maps = in.maps;
    *out = l;
    return 1;
}

void tp_view_light_close(tp_view_light* l)
{
    if (!l)
        return;
    tp_clipmap_destroy(l->clip); /* stops the loader before the file closes */
    tp_imagery_close(l->im);
    tp_view_clip_state_free(&l->cs);
    free(l);
}

void tp_view_light_day(const tp_view_light* l, double* first_s, double* last_s, int* maps)
{
    if (first_s)
        *first_s = l->first_s;
    if (last_s)
        *last_s = l->last_s;
    if (maps)
        *maps = l->maps;
}

int tp_view_light_covers(const tp_view_light* l, double unix_s)
{
    return unix_s >= l->first_s && unix_s <= l->last_s;
}

void tp_view_light_frame(tp_view_light* l, const tp_store_scene* st, const tp_cut* cut,
                         double zscale, tp_renderer* r, const tp_camera* cam, double unix_s,
                         int settle, tp_clipmap_stats* stats)
{
    tp_clipmap_stats local;
    tp_render_clip rc;
    tp_view_clip_frame(&l->cs, l->clip, st, cut, zscale, cam, settle, stats ? stats : &local, &rc);
    tp_renderer_set_light(r, &rc, tp_light_times_tau(l->first_s, l->last_s, unix_s));
}

void tp_view_light_report_failures(tp_view_light* l)
{
    const char* f;
    while (l && (f = tp_clipmap_take_failure(l->clip)))
        tp_cli_error("%s (its posts drawn in shadow there)", f);
}
