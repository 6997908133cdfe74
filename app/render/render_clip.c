/* render_clip.c - a clipmap's shader uniforms (see render_clip.h). */
#include "render_clip.h"

#include <math.h>
#include <stdio.h>

/* The location of name[index] (array elements are looked up one by one: GL promises nothing
 * about the locations of the others). */
static GLint element(GLuint prog, const char* name, int index)
{
    char s[64];
    snprintf(s, sizeof s, "%s[%d]", name, index);
    return glGetUniformLocation(prog, s);
}

void tp__clip_uniforms_find(GLuint prog, int set, const char* sampler, int unit,
                            tp__clip_uniforms* u)
{
    u->set = set;
    u->unit = unit;
    u->sampler = glGetUniformLocation(prog, sampler);
    u->levels = element(prog, "u_clip_levels", set);
    u->first = element(prog, "u_clip_first", set);
    u->size = element(prog, "u_clip_size", set);
    u->per_m = element(prog, "u_clip_per_m", set);
    u->lod_k = element(prog, "u_clip_lod_k", set);
    /* a set's levels are consecutive elements: glUniform*v from the first loads them all */
    u->rect = element(prog, "u_clip_rect", set * TP_RENDER_CLIP_LEVELS);
    u->cam = element(prog, "u_clip_cam", set * TP_RENDER_CLIP_LEVELS);
}

/* Everything relative to the camera's texel position (doubles here), so that floats in the
 * shader stay small; the level per vertex from its distance (Blow's per-polygon texture level:
 * texels per pixel = distance / (focal * texel)), as log2 of the set's factor. */
void tp__clip_uniforms_set(const tp__clip_uniforms* u, const tp_render_clip* c,
                           const tp_camera* cam, int on)
{
    glUniform1i(u->sampler, u->unit);
    glUniform1i(u->levels, c->texture && on ? c->levels : 0);
    if (!c->texture || !on)
        return;
    double e = cam->position[0], n = cam->position[1];
    tp_camera_frame f;
    tp_camera_get_frame(cam, &f);
    double texel_m = fmin(fabs(c->geotransform[1]), fabs(c->geotransform[5]));
    glUniform1f(u->lod_k, (float)log2(1 / (f.focal_px * texel_m)));
    glUniform1i(u->first, c->first);
    glUniform1f(u->size, (float)c->size);
    glUniform2f(u->per_m, (float)(1 / c->geotransform[1]), (float)(1 / c->geotransform[5]));
    float rect[TP_RENDER_CLIP_LEVELS][4], at[TP_RENDER_CLIP_LEVELS][2];
    double u0 = (e - c->geotransform[0]) / c->geotransform[1];
    double v0 = (n - c->geotransform[3]) / c->geotransform[5];
    for (int l = 0; l < TP_RENDER_CLIP_LEVELS; l++) {
        double x = ldexp(u0, -l), y = ldexp(v0, -l);
        const double* q = c->rect[l];
        int valid = l < c->levels && q[2] - q[0] >= 1 && q[3] - q[1] >= 1;
        /* half a texel in from each edge: the bilinear footprint stays inside */
        rect[l][0] = valid ? (float)(q[0] + 0.5 - x) : 1;
        rect[l][1] = valid ? (float)(q[1] + 0.5 - y) : 1;
        rect[l][2] = valid ? (float)(q[2] - 0.5 - x) : 0;
        rect[l][3] = valid ? (float)(q[3] - 0.5 - y) : 0;
        at[l][0] = (float)(x - floor(x / c->size) * c->size);
        at[l][1] = (float)(y - floor(y / c->size) * c->size);
    }
    glUniform4fv(u->rect, TP_RENDER_CLIP_LEVELS, &rect[0][0]);
    glUniform2fv(u->cam, TP_RENDER_CLIP_LEVELS, &at[0][0]);
    glActiveTexture(GL_TEXTURE0 + u->unit);
    glBindTexture(GL_TEXTURE_2D_ARRAY, c->texture);
    glActiveTexture(GL_TEXTURE0);
}
