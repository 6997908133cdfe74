/*
 * renderer.c - the patch renderer's GPU resources (see renderer.h, renderer_internal.h): the
 * terrain program and its uniforms, the strips' shared index buffer, the vertex pools and their
 * vertex format; what is draped and lit (a texture, clipmaps, per-item textures, shadows); the
 * default settings. Drawing is renderer_upload.c and renderer_draw.c; the items of a terrain or a
 * cut, render_patches.c.
 */
#include "renderer_internal.h"

#include "gl_context.h"
#include "terrain_shaders.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void tp__renderer_vertex_format(tp_renderer* r, GLuint vbo)
{
    glBindVertexArray(r->vao);
    glBindBuffer(GL_ARRAY_BUFFER, vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribIPointer(0, 2, GL_INT, sizeof(gpu_vertex), (void*)offsetof(gpu_vertex, x));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, sizeof(gpu_vertex), (void*)offsetof(gpu_vertex, z));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 3, GL_BYTE, GL_TRUE, sizeof(gpu_vertex), (void*)offsetof(gpu_vertex, n));
    glEnableVertexAttribArray(3);
    glVertexAttribIPointer(3, 1, GL_UNSIGNED_BYTE, sizeof(gpu_vertex),
                           (void*)offsetof(gpu_vertex, flags));
}

const tp__program* tp__renderer_program(tp_renderer* r, unsigned features, tp_error* err)
{
    tp__program* p = &r->progs[features & TP_SHADE_ALL];
    if (p->prog)
        return p;
    char vs[16384], fs[16384];
    if (!tp_terrain_shader_sources(features, vs, fs, sizeof vs)) {
        tp_error_set(err, TP_ERR_BACKEND, "the terrain shaders do not fit their buffers");
        return NULL;
    }
    GLuint prog = tp_gl_program(vs, fs, err);
    if (!prog)
        return NULL;
#define TP_UNIFORM(name) p->name = glGetUniformLocation(prog, #name)
    TP_UNIFORM(u_cell);
    TP_UNIFORM(u_frac);
    TP_UNIFORM(u_spacing);
    TP_UNIFORM(u_cam_z);
    TP_UNIFORM(u_exag);
    TP_UNIFORM(u_viewproj);
    TP_UNIFORM(u_sun);
    TP_UNIFORM(u_color_lod);
    TP_UNIFORM(u_hide_filled);
    TP_UNIFORM(u_hrange);
    TP_UNIFORM(u_tex);
    TP_UNIFORM(u_tex_scale);
    TP_UNIFORM(u_tex_offset);
    TP_UNIFORM(u_grid);
    TP_UNIFORM(u_grid_origin);
    TP_UNIFORM(u_shadow);
    TP_UNIFORM(u_shadow_win);
    TP_UNIFORM(u_blk);
    TP_UNIFORM(u_blk_layer);
    TP_UNIFORM(u_blk_cell);
    TP_UNIFORM(u_blk_scale);
    TP_UNIFORM(u_blk_offset);
    TP_UNIFORM(u_light_tau);
#undef TP_UNIFORM
    tp__clip_uniforms_find(prog, TP__CLIP_SET_IMAGERY, "u_clip", 1, &p->clip_u);
    tp__clip_uniforms_find(prog, TP__CLIP_SET_LIGHT, "u_light", 4, &p->light_u);
    tp__clip_uniforms_find(prog, TP__CLIP_SET_NORMALS, "u_normals", 5, &p->normal_u);
    p->prog = prog;
    return p;
}

tp_renderer* tp_renderer_create_desc(const tp_render_grid_desc* d, tp_error* err)
{
    tp_renderer* r = calloc(1, sizeof *r);
    if (!r) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    r->grid = *d;
    int n = d->n;
    size_t v = ((size_t)1 << n) + 1;
    r->slot_verts = v * v;

    /* every feature at once: the shaders are checked before any frame (the programs a frame
     * uses are made as they are first needed) */
    if (!tp__renderer_program(r, TP_SHADE_ALL, err)) {
        free(r);
        return NULL;
    }

    /* The strips of every level, one after the other, in one index buffer. */
    r->index_type = n <= 7 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    r->sync_indices = tp_gl_context_software() ? TP_RENDER_SOFTWARE_SYNC_INDICES : 0;
    const char* sync = getenv("TP_SOFTWARE_SYNC_INDICES"); /* renderer.h; 0: never wait */
    if (sync && r->sync_indices)
        r->sync_indices = (size_t)strtoull(sync, NULL, 10);
    size_t isize = n <= 7 ? 2 : 4, total = 0;
    for (int k = 0; k <= n; k++)
        total += tp_strip_index_count(k);
    void* idx = malloc(total * isize);
    r->vtmp = malloc(r->slot_verts * sizeof *r->vtmp);
    r->ntmp = malloc(r->slot_verts * sizeof *r->ntmp);
    r->ftmp = malloc(r->slot_verts);
    r->gtmp = malloc(r->slot_verts * sizeof *r->gtmp);
    r->pool = tp_vertex_pool_create(n, sizeof(gpu_vertex), d->pool_budget_bytes,
                                    TP_RENDER_POOL_MAX_BYTES, TP_RENDER_POOL_INITIAL_BYTES, err);
    if (!r->pool) {
        free(idx);
        tp_renderer_destroy(r);
        return NULL;
    }
    r->ttmp = malloc(tp_vertex_pool_region_indices(r->pool, n) * sizeof *r->ttmp);
    if (!idx || !r->vtmp || !r->ntmp || !r->ftmp || !r->gtmp || !r->ttmp) {
        free(idx);
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        tp_renderer_destroy(r);
        return NULL;
    }
    size_t at = 0;
    for (int k = 0; k <= n; k++) {
        size_t c = tp_strip_index_count(k);
        r->level_offset[k] = at * isize;
        r->level_count[k] = c;
        if (isize == 2)
            tp_strip_build_u16(k, (uint16_t*)idx + at, c);
        else
            tp_strip_build_u32(k, (uint32_t*)idx + at, c);
        at += c;
    }
    glGenVertexArrays(1, &r->vao);
    glBindVertexArray(r->vao);
    glGenBuffers(1, &r->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(total * isize), idx, GL_STATIC_DRAW);
    free(idx);
    tp__renderer_vertex_format(r, tp_vertex_pool_vertex_buffer(r->pool, n));
    return r;
}

void tp_renderer_destroy(tp_renderer* r)
{
    if (!r)
        return;
    for (unsigned f = 0; f <= TP_SHADE_ALL; f++)
        if (r->progs[f].prog)
            glDeleteProgram(r->progs[f].prog);
    if (r->tex)
        glDeleteTextures(1, &r->tex);
    tp_vertex_pool_destroy(r->pool);
    tp__stitch_add_destroy(r->add);
    tp__stitch_five_destroy(r->five);
    glDeleteBuffers(1, &r->ibo);
    glDeleteVertexArrays(1, &r->vao);
    free(r->draw_level);
    free(r->gcounts);
    free(r->goffsets);
    free(r->gbases);
    free(r->vtmp);
    free(r->ntmp);
    free(r->ftmp);
    free(r->gtmp);
    free(r->ttmp);
    free(r->counts);
    free(r->offsets);
    free(r->bases);
    free(r->items);
    free(r->complete);
    free(r->blk);
    free(r->ditem);
    free(r->gitem);
    free(r);
}

void tp_renderer_set_shadow(tp_renderer* r, unsigned texture, int x0, int y0, int w, int h)
{
    r->shadow_tex = texture;
    r->shadow_win[0] = x0, r->shadow_win[1] = y0, r->shadow_win[2] = w, r->shadow_win[3] = h;
}

void tp_renderer_set_clip(tp_renderer* r, const tp_render_clip* clip)
{
    if (clip && clip->texture)
        r->clip = *clip;
    else
        memset(&r->clip, 0, sizeof r->clip);
    if (!clip)
        tp_renderer_set_item_textures(r, 0, NULL, 0);
}

void tp_renderer_set_light(tp_renderer* r, const tp_render_clip* clip, double tau)
{
    if (clip && clip->texture)
        r->light = *clip;
    else
        memset(&r->light, 0, sizeof r->light);
    r->light_tau = tau;
}

void tp_renderer_set_normals(tp_renderer* r, const tp_render_clip* clip)
{
    if (clip && clip->texture)
        r->normals = *clip;
    else
        memset(&r->normals, 0, sizeof r->normals);
}

void tp_renderer_set_item_textures(tp_renderer* r, unsigned texture,
                                   const tp_render_item_texture* items, size_t count)
{
    r->blk_tex = 0;
    r->blk_count = 0;
    if (!texture || !items || count == 0)
        return;
    if (count > r->blk_cap) {
        tp_render_item_texture* b = realloc(r->blk, count * sizeof *b);
        if (!b)
            return;
        r->blk = b;
        r->blk_cap = count;
    }
    memcpy(r->blk, items, count * sizeof *items);
    r->blk_tex = texture;
    r->blk_count = count;
}

int tp_renderer_set_texture(tp_renderer* r, const uint8_t* rgba, int w, int h,
                            const float scale[2], const float offset[2])
{
    GLint max = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max);
    if (w > max || h > max)
        return 0;
    if (!r->tex)
        glGenTextures(1, &r->tex);
    glBindTexture(GL_TEXTURE_2D, r->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    /* top row first, and v grows downward with the grid rows: no flip needed */
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    for (int i = 0; i < 2; i++) {
        r->tex_scale[i] = scale[i];
        r->tex_offset[i] = offset[i];
    }
    return glGetError() == GL_NO_ERROR;
}

void tp_render_settings_default(tp_render_settings* s)
{
    memset(s, 0, sizeof *s);
    s->sun_azimuth_deg = 315;
    s->sun_elevation_deg = 45;
    s->exaggeration = 1;
    s->stitch_add_five = 1; /* as fast, less memory (docs/PERFORMANCE.md, "Five regions") */
    s->clear_rgb[0] = 0.55f;
    s->clear_rgb[1] = 0.70f;
    s->clear_rgb[2] = 0.90f;
}
