/* bench_imagery.c - the imagery check of `terrapatch bench STORE --imagery` (see bench.h). */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"
#include "imagery_view.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* Draws the frame of cam with vi settled (the render thread only reads what vi holds) into
 * px. */
static void draw_settled(tp_view_imagery* vi, const tp_store_scene* sc, const tp_cut* cut,
                         tp_renderer* r, tp_gl_context* ctx, const tp_camera* cam, uint8_t* px)
{
    tp_render_settings rs;
    tp_render_settings_default(&rs);
    tp_render_stats st;
    tp_clipmap_stats cs;
    tp_view_imagery_frame(vi, sc, cut, 1, r, cam, 1, &cs);
    tp_gl_context_begin_frame(ctx);
    tp_renderer_draw_cut(r, sc->tree, cut, cam, &rs, 1, 1, &st);
    tp_gl_context_end_frame(ctx);
    tp_gl_context_read_rgba(ctx, px);
}

long tp_bench_imagery_diff(tp_view_imagery* flown, const char* path, const tp_store_scene* sc,
                           const tp_cut* cut, tp_renderer* r, tp_gl_context* ctx,
                           const tp_camera* cam, int mode, int clip_blocks)
{
    int w, h;
    tp_gl_context_size(ctx, &w, &h);
    size_t n = (size_t)w * h * 4;
    uint8_t* a = malloc(n);
    uint8_t* b = malloc(n);
    tp_view_imagery* fresh = NULL;
    tp_clipmap_options co = {.clip_blocks = clip_blocks};
    long diff = -1;
    if (a && b && tp_view_imagery_open(path, sc, (tp_imagery_mode)mode, &co, &fresh)) {
        draw_settled(flown, sc, cut, r, ctx, cam, a);
        draw_settled(fresh, sc, cut, r, ctx, cam, b); /* twice: the same frame coherence */
        draw_settled(fresh, sc, cut, r, ctx, cam, b);
        diff = 0;
        for (size_t i = 0; i < n; i += 4)
            diff += memcmp(a + i, b + i, 4) != 0;
        tp_view_imagery_frame(flown, sc, cut, 1, r, cam, 0, &(tp_clipmap_stats){0});
    }
    tp_view_imagery_close(fresh);
    free(a);
    free(b);
    return diff;
}
