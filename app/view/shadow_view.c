/* shadow_view.c - cast shadows in the viewer (see shadow_view.h). */
#define _POSIX_C_SOURCE 200809L
#include "shadow_view.h"
#include "clock.h"

#include "ground.h"
#include "store_scene.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int clampi(int v, int lo, int hi)
{
    return v < lo ? lo : v > hi ? hi : v;
}

int tp_view_shadow_update(tp_view_shadow* s, tp_ground* g, const tp_render_settings* rs, double cx,
                          double cy, tp_renderer* r, tp_error* err)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const tp_tree_geometry* geo = tp_tree_get_geometry(sc->tree);
    const double* gt = sc->tree_info.geotransform;
    int inside = s->w > 0 && fabs(cx - (s->x0 + s->w / 2.0)) < s->w / 4.0 &&
                 fabs(cy - (s->y0 + s->h / 2.0)) < s->h / 4.0;
    int moved_sun = s->az_deg != rs->sun_azimuth_deg || s->el_deg != rs->sun_elevation_deg;
    if (inside && !moved_sun && s->texture) {
        tp_renderer_set_shadow(r, s->texture, s->x0, s->y0, s->w, s->h);
        return 1;
    }
    double t0 = tp_clock_s();
    int w = geo->src_width < TP_VIEW_SHADOW_POSTS ? geo->src_width : TP_VIEW_SHADOW_POSTS;
    int h = geo->src_height < TP_VIEW_SHADOW_POSTS ? geo->src_height : TP_VIEW_SHADOW_POSTS;
    int x0 = clampi((int)lround(cx) - w / 2, 0, geo->src_width - w);
    int y0 = clampi((int)lround(cy) - h / 2, 0, geo->src_height - h);
    size_t n = (size_t)w * h;
    if (!s->z) {
        s->z = malloc((size_t)TP_VIEW_SHADOW_POSTS * TP_VIEW_SHADOW_POSTS * sizeof *s->z);
        s->lit = malloc((size_t)TP_VIEW_SHADOW_POSTS * TP_VIEW_SHADOW_POSTS);
    }
    tp_error why;
    tp_status st = s->z && s->lit ? TP_OK
                                  : tp_error_set(&why, TP_ERR_OUT_OF_MEMORY,
                                                 "out of memory for the shadow window");
    if (st == TP_OK && (!inside || !s->w || s->x0 != x0 || s->y0 != y0))
        st = tp_ground_read_posts(g, x0, y0, w, h, s->z, NULL, &why);
    if (st == TP_OK)
        st = tp_shadow_compute(s->z, n, w, h, fabs(gt[1]), fabs(gt[5]), rs->sun_azimuth_deg,
                               rs->sun_elevation_deg, s->lit, NULL, n, &why);
    if (st != TP_OK) {
        tp_error_set(err, st, "cast shadows: %s", why.message);
        tp_renderer_set_shadow(r, 0, 0, 0, 0, 0);
        s->w = 0;
        return 0;
    }
    for (size_t i = 0; i < n; i++) /* GL_R8: 0 shadowed, 255 lit (voids: lit, not drawn) */
        s->lit[i] = s->lit[i] == TP_SHADOW_LIT || s->z[i] != s->z[i] ? 255 : 0;
    if (!s->texture) {
        GLuint t;
        glGenTextures(1, &t);
        s->texture = t;
    }
    glBindTexture(GL_TEXTURE_2D, s->texture);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, w, h, 0, GL_RED, GL_UNSIGNED_BYTE, s->lit);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    s->x0 = x0, s->y0 = y0, s->w = w, s->h = h;
    s->az_deg = rs->sun_azimuth_deg;
    s->el_deg = rs->sun_elevation_deg;
    s->compute_ms = (tp_clock_s() - t0) * 1e3;
    tp_renderer_set_shadow(r, s->texture, x0, y0, w, h);
    return 1;
}

void tp_view_shadow_free(tp_view_shadow* s)
{
    if (s->texture) {
        GLuint t = s->texture;
        glDeleteTextures(1, &t);
    }
    free(s->z);
    free(s->lit);
    memset(s, 0, sizeof *s);
}
