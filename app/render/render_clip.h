/*
 * render_clip.h - the uniforms of a clipmap the terrain shader samples (renderer.c's imagery,
 * set 0, its streamed light, set 1, and the terrain's normals, set 2; terrain_shaders.c's
 * clip_sample): each set has its
 * own sampler and texture unit and its entries in the shader's per-set uniform arrays. Shared
 * by the patch renderer only (renderer.c finds them, renderer_draw.c sets them; tp__ names).
 * app/render/render_clip.c.
 */
#ifndef TP_APP_VIEW_RENDER_CLIP_H
#define TP_APP_VIEW_RENDER_CLIP_H

#include "renderer.h"

#include <epoxy/gl.h>

#define TP__CLIP_SET_IMAGERY 0
#define TP__CLIP_SET_LIGHT 1
#define TP__CLIP_SET_NORMALS 2
#define TP__CLIP_SETS 3

typedef struct tp__clip_uniforms {
    int set, unit; /* the shader's set; the texture unit its sampler reads */
    GLint sampler, levels, first, size, per_m, lod_k, rect, cam;
} tp__clip_uniforms;

/* Looks up set's uniforms in prog; sampler: the name of its sampler2DArray. */
void tp__clip_uniforms_find(GLuint prog, int set, const char* sampler, int unit,
                            tp__clip_uniforms* u);

/* Sets them for clip c seen from cam (the program in use); on 0 or c->texture 0: the set is
 * off (the shader samples nothing). Binds the texture to u->unit, leaves unit 0 active. */
void tp__clip_uniforms_set(const tp__clip_uniforms* u, const tp_render_clip* c,
                           const tp_camera* cam, int on);

#endif /* TP_APP_VIEW_RENDER_CLIP_H */
