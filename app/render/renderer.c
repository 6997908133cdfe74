/* renderer.c - the patch renderer (see renderer.h). */
#define _POSIX_C_SOURCE 200112L
#include "renderer.h"
#include "clock.h"

#include "gl_context.h"
#include "render_clip.h"
#include "stitch_add_draw.h"
#include "stitch_add_five.h"
#include "terrain_shaders.h"
#include "vertex_pool.h"

#include <epoxy/gl.h>

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <sys/resource.h>

/* One vertex on the GPU: 16 bytes. */
typedef struct gpu_vertex {
    int32_t x, y;    /* global grid coordinates (after crack removal) */
    float z;         /* height, metres */
    int8_t n[3];     /* unit normal * 127, world frame (east, north, up) */
    uint8_t flags;   /* bits 0-3: level, bit 4: filled void */
} gpu_vertex;

struct tp_renderer {
    tp_render_grid_desc grid;
    GLuint prog, vao, ibo;
    GLenum index_type;
    size_t level_offset[TP_MAX_LEVELS], level_count[TP_MAX_LEVELS];
    size_t slot_verts; /* (2^n+1)^2: the finest level's item */
    tp_vertex_pool* pool; /* the items' vertex data and triangle lists */
    int* draw_level;   /* per drawn item: its group (level, strip or triangle list) */
    tp_vertex* vtmp;
    float (*ntmp)[3];
    uint8_t* ftmp;
    gpu_vertex* gtmp;
    uint32_t* ttmp;
    GLsizei* counts;   /* per drawn item, in item order; then grouped by level */
    void** offsets;
    GLint* bases;
    GLsizei* gcounts;
    void** goffsets;
    GLint* gbases;
    size_t draw_cap;
    GLint u_cell, u_frac, u_spacing, u_cam_z, u_exag, u_viewproj, u_sun, u_color_lod,
        u_hide_filled, u_hrange, u_textured, u_tex, u_tex_scale, u_tex_offset, u_grid,
        u_grid_origin, u_shadow, u_shadow_on, u_shadow_win, u_blk, u_blk_layer, u_blk_cell,
        u_blk_scale, u_blk_offset, u_light_tau;
    tp__clip_uniforms clip_u, light_u; /* the imagery's clipmap (unit 1), the light's (4) */
    GLuint shadow_tex;
    int shadow_win[4];
    GLuint tex;
    /* tp_renderer_set_item_textures: a texture per item (imagery_blocks.h) */
    GLuint blk_tex;
    tp_render_item_texture* blk;
    size_t blk_count, blk_cap;
    size_t* ditem;     /* per drawn item: its index in items; then grouped as the draws */
    size_t* gitem;
    tp_render_clip clip;
    tp_render_clip light;  /* tp_renderer_set_light */
    double light_tau;
    float tex_scale[2], tex_offset[2];
    /* tp_renderer_create / tp_renderer_draw: the terrain whose patches it draws */
    const tp_terrain* terrain;
    tp_render_item* items;
    size_t item_cap;
    uint8_t* complete; /* per patch */
    /* tp_renderer_draw_cut: what fill_node reads */
    const tp_tree* tree;
    const tp_cut* cut;
    /* tp_renderer_draw in --stitch add mode: its neighbour sets (made on first use) */
    int stitch_add, stitch_add_five;
    tp__stitch_add* add;
    tp__stitch_five* five; /* --stitch-add-draw five: the per-level region sets */
};

static long minor_faults(void)
{
    struct rusage u;
    return getrusage(RUSAGE_SELF, &u) == 0 ? u.ru_minflt : 0;
}


/* Points the vertex attributes at one pool's buffer (the array buffer binding is not part of
 * the vertex array's state: the attribute pointers are). */
static void setup_vertex_format(tp_renderer* r, GLuint vbo)
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


tp_renderer* tp_renderer_create_desc(const tp_render_grid_desc* d, char* msg, size_t msg_size)
{
    tp_renderer* r = calloc(1, sizeof *r);
    if (!r) {
        snprintf(msg, msg_size, "out of memory");
        return NULL;
    }
    r->grid = *d;
    int n = d->n;
    size_t v = ((size_t)1 << n) + 1;
    r->slot_verts = v * v;

    r->prog = tp_gl_program(tp_terrain_vertex_shader, tp_terrain_fragment_shader(), msg,
                           msg_size);
    if (!r->prog) {
        free(r);
        return NULL;
    }
#define TP_UNIFORM(name) r->name = glGetUniformLocation(r->prog, #name)
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
    TP_UNIFORM(u_textured);
    TP_UNIFORM(u_tex);
    TP_UNIFORM(u_tex_scale);
    TP_UNIFORM(u_tex_offset);
    TP_UNIFORM(u_grid);
    TP_UNIFORM(u_grid_origin);
    TP_UNIFORM(u_shadow);
    TP_UNIFORM(u_shadow_on);
    TP_UNIFORM(u_shadow_win);
    TP_UNIFORM(u_blk);
    TP_UNIFORM(u_blk_layer);
    TP_UNIFORM(u_blk_cell);
    TP_UNIFORM(u_blk_scale);
    TP_UNIFORM(u_blk_offset);
    TP_UNIFORM(u_light_tau);
#undef TP_UNIFORM
    tp__clip_uniforms_find(r->prog, TP__CLIP_SET_IMAGERY, "u_clip", 1, &r->clip_u);
    tp__clip_uniforms_find(r->prog, TP__CLIP_SET_LIGHT, "u_light", 4, &r->light_u);

    /* The strips of every level, one after the other, in one index buffer. */
    r->index_type = n <= 7 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    size_t isize = n <= 7 ? 2 : 4, total = 0;
    for (int k = 0; k <= n; k++)
        total += tp_strip_index_count(k);
    void* idx = malloc(total * isize);
    r->vtmp = malloc(r->slot_verts * sizeof *r->vtmp);
    r->ntmp = malloc(r->slot_verts * sizeof *r->ntmp);
    r->ftmp = malloc(r->slot_verts);
    r->gtmp = malloc(r->slot_verts * sizeof *r->gtmp);
    r->pool = tp_vertex_pool_create(n, sizeof(gpu_vertex), d->pool_budget_bytes,
                                    TP_RENDER_POOL_MAX_BYTES, TP_RENDER_POOL_INITIAL_BYTES, msg,
                                    msg_size);
    if (!r->pool) {
        free(idx);
        tp_renderer_destroy(r);
        return NULL;
    }
    r->ttmp = malloc(tp_vertex_pool_region_indices(r->pool, n) * sizeof *r->ttmp);
    if (!idx || !r->vtmp || !r->ntmp || !r->ftmp || !r->gtmp || !r->ttmp) {
        free(idx);
        snprintf(msg, msg_size, "out of memory");
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
    setup_vertex_format(r, tp_vertex_pool_vertex_buffer(r->pool, n));
    return r;
}

void tp_renderer_destroy(tp_renderer* r)
{
    if (!r)
        return;
    glDeleteProgram(r->prog);
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

/* Writes count vertices of vtmp, ntmp, ftmp (a level-k item's) into slot h. */
static void write_vertices(tp_renderer* r, int h, int k, int count)
{
    for (int j = 0; j < count; j++) {
        const tp_vertex* src = &r->vtmp[j];
        gpu_vertex* g = &r->gtmp[j];
        g->x = src->x;
        g->y = src->y;
        g->z = isnan(src->z_m) ? 0.0f : src->z_m;
        for (int a = 0; a < 3; a++)
            g->n[a] = (int8_t)lrintf(r->ntmp[j][a] * 127.0f);
        g->flags = (uint8_t)(k | ((r->ftmp[j] ? 1 : 0) << 4));
    }
    tp_vertex_pool_write(r->pool, h, r->gtmp, (size_t)count);
}

/* Builds item i's vertex data (and its triangle list if it is incomplete) into slot h; in
 * --stitch add mode with set, the set's samples and triangles (stitch_add_draw.h), with lay,
 * the five-region layout's samples (stitch_add_five.h). tag: what the slot then holds. */
static void upload(tp_renderer* r, const tp_render_item* it, size_t i, tp_render_fill_fn fill,
                   void* user, int h, const tp__stitch_add_set* set,
                   const tp__five_layout* lay, const int8_t tag[4])
{
    tp_pool_slot* sl = tp_vertex_pool_slot(r->pool, h);
    int k = it->level, v = (1 << k) + 1, count = v * v;
    if (lay) {
        if (r->cut)
            tp__stitch_five_fill_node(r->five, lay, r->tree, r->cut, i, r->vtmp, r->ntmp, r->ftmp);
        else
            tp__stitch_five_fill(r->five, lay, r->terrain, (int)it->key, r->vtmp, r->ntmp,
                                 r->ftmp);
        write_vertices(r, h, k, (int)lay->vertex_count);
        tp_vertex_pool_drop_triangles(r->pool, h);
        sl->level = it->level;
        memcpy(sl->nb, tag, sizeof sl->nb);
        return;
    }
    if (set) {
        if (r->cut)
            tp__stitch_add_fill_node(r->add, set, r->tree, r->cut, i, r->vtmp, r->ntmp, r->ftmp);
        else
            tp__stitch_add_fill(r->add, set, r->terrain, (int)it->key, r->vtmp, r->ntmp,
                                r->ftmp);
        write_vertices(r, h, k, (int)set->vertex_count);
        tp_vertex_pool_write_triangles(r->pool, h, set->triangles, 3 * set->triangle_count);
        sl->level = it->level;
        memcpy(sl->nb, it->nb, sizeof sl->nb);
        return;
    }
    assert(k == tp_vertex_pool_level(h));
    fill(user, i, r->vtmp, r->ntmp, r->ftmp);
    write_vertices(r, h, k, count);
    if (it->incomplete) {
        size_t cap = tp_vertex_pool_region_indices(r->pool, k) / 3;
        size_t nt = r->cut ? tp_cut_triangles(r->cut, i, r->vtmp, r->ttmp, cap)
                           : tp_patch_triangles(r->vtmp, k, r->ttmp, cap);
        tp_vertex_pool_write_triangles(r->pool, h, r->ttmp, 3 * (nt < cap ? nt : cap));
    } else {
        tp_vertex_pool_drop_triangles(r->pool, h);
    }
    sl->level = it->level;
    memcpy(sl->nb, it->nb, sizeof sl->nb);
}

static int grow_draws(tp_renderer* r, size_t count)
{
    if (count <= r->draw_cap)
        return 1;
    size_t cap = r->draw_cap ? r->draw_cap : 256;
    while (cap < count)
        cap *= 2;
    GLsizei* c = realloc(r->counts, cap * sizeof *c);
    if (c)
        r->counts = c;
    void** o = realloc(r->offsets, cap * sizeof *o);
    if (o)
        r->offsets = o;
    GLint* b = realloc(r->bases, cap * sizeof *b);
    if (b)
        r->bases = b;
    GLsizei* gc = realloc(r->gcounts, cap * sizeof *gc);
    if (gc)
        r->gcounts = gc;
    void** go = realloc(r->goffsets, cap * sizeof *go);
    if (go)
        r->goffsets = go;
    GLint* gb = realloc(r->gbases, cap * sizeof *gb);
    if (gb)
        r->gbases = gb;
    int* dl = realloc(r->draw_level, cap * sizeof *dl);
    if (dl)
        r->draw_level = dl;
    size_t* di = realloc(r->ditem, cap * sizeof *di);
    if (di)
        r->ditem = di;
    size_t* gi = realloc(r->gitem, cap * sizeof *gi);
    if (gi)
        r->gitem = gi;
    if (!c || !o || !b || !gc || !go || !gb || !dl || !di || !gi)
        return 0;
    r->draw_cap = cap;
    return 1;
}

void tp_renderer_draw_items(tp_renderer* r, const tp_render_item* items, size_t count,
                            tp_render_fill_fn fill, void* user, const tp_camera* cam,
                            const tp_render_settings* st, double exag, int finish,
                            tp_render_stats* stats)
{
    memset(stats, 0, sizeof *stats);
    tp_vertex_pool_begin_frame(r->pool);
    /* Element-buffer bindings belong to the bound vertex array: bind ours before any upload. */
    glBindVertexArray(r->vao);
    double t0 = tp_clock_ms();
    int five = r->stitch_add && r->stitch_add_five, per = five ? 5 : 1; /* draws an item takes */
    if (!grow_draws(r, per * count))
        count = r->draw_cap / per; /* draw what fits; the next frame tries again */
    size_t drawn = 0;
    for (size_t i = 0; i < count; i++) {
        const tp_render_item* it = &items[i];
        int fresh;
        const tp__stitch_add_set* set = NULL;
        const tp__five_layout* lay = NULL;
        tp__five_draws fd;
        if (r->stitch_add && !it->incomplete && tp__stitch_add_needed(it->level, it->nb) &&
            (five ? !(lay = tp__stitch_five_layout(r->five, it->level, it->nb)) ||
                        !tp__stitch_five_draws(r->five, it->level, it->nb, &fd)
                  : !(set = tp__stitch_add_get(r->add, it->level, it->nb)))) {
            stats->dropped++; /* out of memory */
            continue;
        }
        int h = tp_vertex_pool_take(r->pool, it->key,
                                    set ? set->level : lay ? lay->level : it->level, &fresh);
        if (h < 0) {
            stats->dropped++;
            continue;
        }
        /* a five-region layout's vertices depend on (level, D) and the sides that move (a
         * store's) only: its tag says so */
        int8_t tag[4] = {it->nb[0], it->nb[1], it->nb[2], it->nb[3]};
        for (int s = 0; lay && s < 4; s++)
            if (tag[s] > it->level)
                tag[s] = (int8_t)(-2 - lay->D);
        const tp_pool_slot* sl = tp_vertex_pool_slot(r->pool, h);
        if (fresh || sl->level != it->level || memcmp(sl->nb, tag, sizeof sl->nb) ||
            (it->incomplete || set) != (sl->region >= 0)) {
            upload(r, it, i, fill, user, h, set, lay, tag);
            stats->uploads++;
        }
        stats->patches_drawn++;
        if (lay) { /* its regions, each a draw of the shared sets (none empty) */
            for (int d = 0; d < fd.count; d++, drawn++) {
                r->draw_level[drawn] = 3 * tp_vertex_pool_level(h) + 2;
                r->counts[drawn] = (GLsizei)fd.index_count[d];
                r->offsets[drawn] = (void*)(fd.first[d] * sizeof(uint32_t));
                r->bases[drawn] = tp_vertex_pool_base_vertex(r->pool, h);
                r->ditem[drawn] = i;
            }
            stats->triangles += fd.triangles;
            continue;
        }
        int c = sl->region;
        if (it->incomplete && c < 0)
            continue; /* no region could be made */
        size_t list_offset = 0, list_count = tp_vertex_pool_triangles(r->pool, h, &list_offset);
        /* An item of nodata only has no triangles. It must not become a zero-count draw: Mesa
         * 22.3 (llvmpipe) applies the wrong base vertex to the draws after a zero-count one in
         * glMultiDrawElementsBaseVertex, which dropped border patches. */
        if (c >= 0 && list_count == 0)
            continue;
        int k = tp_vertex_pool_level(h); /* its pool's level (an added-vertex set's) */
        if (r->stitch_add) /* strips: the level-k grid, nothing moved */
            stats->triangles += c >= 0 ? list_count / 3 : (size_t)2 << (2 * it->level);
        r->draw_level[drawn] = 3 * k + (c >= 0); /* the group: level, strip or triangle list */
        r->counts[drawn] = (GLsizei)(c < 0 ? r->level_count[k] : list_count);
        r->offsets[drawn] = (void*)(c < 0 ? r->level_offset[k] : list_offset);
        r->bases[drawn] = tp_vertex_pool_base_vertex(r->pool, h);
        r->ditem[drawn] = i;
        drawn++;
    }
    /* One multi-draw per group (each level's pool is its own buffer; strips, triangle lists,
     * five-region sets): group the draws. */
    size_t group_at[3 * TP_MAX_LEVELS + 1] = {0};
    for (size_t j = 0; j < drawn; j++)
        group_at[r->draw_level[j] + 1]++;
    for (int g = 0; g < 3 * TP_MAX_LEVELS; g++)
        group_at[g + 1] += group_at[g];
    size_t group_end[3 * TP_MAX_LEVELS];
    memcpy(group_end, group_at, sizeof group_end);
    for (size_t j = 0; j < drawn; j++) {
        size_t at = group_end[r->draw_level[j]]++;
        r->gcounts[at] = r->counts[j];
        r->goffsets[at] = r->offsets[j];
        r->gbases[at] = r->bases[j];
        r->gitem[at] = r->ditem[j];
    }
    size_t five_bytes = 0; /* the sets made this frame go to the GPU with the upload */
    GLuint five_ibo = five ? tp__stitch_five_gl_buffer(r->five, &five_bytes) : 0;
    double t1 = tp_clock_ms();
    stats->upload_ms = t1 - t0;
    long faults0 = minor_faults();

    GLint vp[4];
    glGetIntegerv(GL_VIEWPORT, vp);
    int w = vp[2], h = vp[3];
    const double* gt = r->grid.geotransform;
    /* Far plane: the farthest corner of the terrain's box, with room. */
    double far_m = cam->far_m;
    if (far_m <= 0) {
        double e0 = gt[0] + 0.5 * gt[1], n0 = gt[3] + 0.5 * gt[5];
        double e1 = gt[0] + (r->grid.width - 0.5) * gt[1],
               n1 = gt[3] + (r->grid.height - 0.5) * gt[5];
        double dx = fmax(fabs(e0 - cam->position[0]), fabs(e1 - cam->position[0]));
        double dy = fmax(fabs(n0 - cam->position[1]), fabs(n1 - cam->position[1]));
        double dz = fmax(fabs(r->grid.max_height_m * exag - cam->position[2]),
                         fabs(r->grid.min_height_m * exag - cam->position[2]));
        far_m = 1.1 * sqrt(dx * dx + dy * dy + dz * dz) + 10;
    }
    tp_camera view = *cam;
    view.viewport_w_px = w;
    view.viewport_h_px = h;
    double vpd[16];
    float vpm[16];
    tp_camera_view_projection(&view, far_m, vpd);
    stats->near_m = cam->near_m > 0 ? cam->near_m : 1.0; /* as tp_camera_view_projection */
    stats->far_m = far_m;
    for (int i = 0; i < 16; i++)
        vpm[i] = (float)vpd[i];
    /* grid coordinates of the camera (the inverse of sample (x, y) at gt0 + (x + 0.5) * gt1) */
    double cx = (cam->position[0] - gt[0]) / gt[1] - 0.5;
    double cy = (cam->position[1] - gt[3]) / gt[5] - 0.5;
    double fx = floor(cx), fy = floor(cy);

    glClearColor(st->clear_rgb[0], st->clear_rgb[1], st->clear_rgb[2], 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    /* The strips are clockwise in (column, row): counter-clockwise from above when north-up. */
    glFrontFace(gt[1] * gt[5] < 0 ? GL_CCW : GL_CW);
    glPolygonMode(GL_FRONT_AND_BACK, st->wireframe ? GL_LINE : GL_FILL);
    glUseProgram(r->prog);
    glUniform2i(r->u_cell, (GLint)fx, (GLint)fy);
    glUniform2f(r->u_frac, (float)((cx - fx) * gt[1]), (float)((cy - fy) * gt[5]));
    glUniform2f(r->u_spacing, (float)gt[1], (float)gt[5]);
    glUniform1f(r->u_cam_z, (float)cam->position[2]);
    glUniform1f(r->u_exag, (float)exag);
    glUniformMatrix4fv(r->u_viewproj, 1, GL_FALSE, vpm);
    double az = st->sun_azimuth_deg * 3.14159265358979323846 / 180,
           el = st->sun_elevation_deg * 3.14159265358979323846 / 180;
    glUniform3f(r->u_sun, (float)(sin(az) * cos(el)), (float)(cos(az) * cos(el)), (float)sin(el));
    glUniform1i(r->u_color_lod, st->color_lod);
    glUniform1i(r->u_hide_filled, st->hide_filled);
    glUniform2f(r->u_hrange, (float)r->grid.min_height_m, (float)r->grid.max_height_m);
    glUniform1i(r->u_textured, r->tex != 0 && !st->color_lod);
    glUniform1f(r->u_grid, (float)st->grid_m);
    if (st->grid_m > 0)
        glUniform2f(r->u_grid_origin, (float)fmod(cam->position[0], st->grid_m),
                    (float)fmod(cam->position[1], st->grid_m));
    glUniform1i(r->u_tex, 0);
    glUniform2f(r->u_tex_scale, r->tex_scale[0], r->tex_scale[1]);
    glUniform2f(r->u_tex_offset, r->tex_offset[0], r->tex_offset[1]);
    if (r->tex) {
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, r->tex);
    }
    /* a texture per item: one draw each, its layer and mapping as uniforms */
    int blocks = r->blk_tex && r->blk_count == count && !st->color_lod;
    tp__clip_uniforms_set(&r->clip_u, &r->clip, cam, !st->color_lod && !blocks);
    tp__clip_uniforms_set(&r->light_u, &r->light, cam, 1);
    glUniform1f(r->u_light_tau, (float)r->light_tau);
    glUniform1i(r->u_shadow, 3);
    glUniform1i(r->u_shadow_on, r->shadow_tex != 0 && !r->light.texture);
    glUniform4f(r->u_shadow_win, (float)r->shadow_win[0], (float)r->shadow_win[1],
                (float)r->shadow_win[2], (float)r->shadow_win[3]);
    if (r->shadow_tex) {
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, r->shadow_tex);
        glActiveTexture(GL_TEXTURE0);
    }
    glUniform1i(r->u_blk, 2);
    glUniform1i(r->u_blk_layer, -1);
    if (blocks) {
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D_ARRAY, r->blk_tex);
        glActiveTexture(GL_TEXTURE0);
    }
    for (int k = 0; k <= r->grid.n; k++) {
        if (group_at[3 * k] == group_at[3 * k + 3])
            continue;
        setup_vertex_format(r, tp_vertex_pool_vertex_buffer(r->pool, k));
        for (int list = 0; list < 3; list++) { /* strips, triangle lists, five-region sets */
            size_t a = group_at[3 * k + list], b = group_at[3 * k + list + 1];
            GLuint ebo = list == 0 ? r->ibo
                         : list == 1 ? tp_vertex_pool_index_buffer(r->pool, k)
                                     : five_ibo;
            if (a == b || !ebo)
                continue;
            stats->draws += (int)(b - a);
            GLenum mode = list ? GL_TRIANGLES : GL_TRIANGLE_STRIP;
            GLenum type = list ? GL_UNSIGNED_INT : r->index_type;
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
            if (blocks) {
                for (size_t j = a; j < b; j++) {
                    const tp_render_item_texture* t = &r->blk[r->gitem[j]];
                    glUniform1i(r->u_blk_layer, t->layer);
                    glUniform2i(r->u_blk_cell, t->cell[0], t->cell[1]);
                    glUniform2f(r->u_blk_scale, t->scale[0], t->scale[1]);
                    glUniform2f(r->u_blk_offset, t->offset[0], t->offset[1]);
                    glDrawElementsBaseVertex(mode, r->gcounts[j], type, r->goffsets[j],
                                             r->gbases[j]);
                }
                stats->draw_calls += (int)(b - a);
            } else if (st->one_draw_per_patch) {
                for (size_t j = a; j < b; j++)
                    glDrawElementsBaseVertex(mode, r->gcounts[j], type, r->goffsets[j],
                                             r->gbases[j]);
                stats->draw_calls += (int)(b - a);
            } else {
                glMultiDrawElementsBaseVertex(mode, r->gcounts + a, type,
                                              (const void* const*)(r->goffsets + a),
                                              (GLsizei)(b - a), r->gbases + a);
                stats->draw_calls++;
            }
        }
    }
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    if (finish)
        glFinish();
    stats->draw_ms = tp_clock_ms() - t1;
    stats->page_faults = minor_faults() - faults0;
    stats->gpu_bytes = tp_vertex_pool_gpu_bytes(r->pool) + five_bytes;
    stats->index_gpu_bytes = tp_vertex_pool_index_bytes(r->pool) + five_bytes;
    for (int k = 0; k <= r->grid.n; k++) {
        size_t b = r->level_count[k] * (r->index_type == GL_UNSIGNED_SHORT ? 2 : 4);
        stats->gpu_bytes += b;
        stats->index_gpu_bytes += b;
    }
    if (r->stitch_add)
        stats->index_cpu_bytes = five ? tp__stitch_five_cpu_bytes(r->five)
                                      : tp__stitch_add_cpu_bytes(r->add);
}

/* ---- the patches of a resident terrain ---- */

tp_renderer* tp_renderer_create(const tp_terrain* t, char* msg, size_t msg_size)
{
    tp_terrain_info in;
    tp_terrain_get_info(t, &in);
    tp_render_grid_desc d = {.n = in.n, .width = in.width, .height = in.height,
                             .min_height_m = in.min_height_m, .max_height_m = in.max_height_m};
    memcpy(d.geotransform, in.geotransform, sizeof d.geotransform);
    tp_renderer* r = tp_renderer_create_desc(&d, msg, msg_size);
    if (!r)
        return NULL;
    r->terrain = t;
    r->complete = malloc((size_t)in.patch_count);
    if (!r->complete) {
        snprintf(msg, msg_size, "out of memory");
        tp_renderer_destroy(r);
        return NULL;
    }
    for (int p = 0; p < in.patch_count; p++) {
        tp_patch_info pi;
        tp_patch_get_info(t, p, &pi);
        r->complete[p] = (uint8_t)pi.complete;
    }
    return r;
}

/* The next draw's --stitch add mode (s) and what it needs; 0 when out of memory. */
static int set_stitch_add(tp_renderer* r, const tp_render_settings* s)
{
    r->stitch_add = s->stitch_add;
    r->stitch_add_five = s->stitch_add_five;
    if (s->stitch_add && s->stitch_add_five)
        return r->five || (r->five = tp__stitch_five_create(r->grid.n));
    return !s->stitch_add || r->add || (r->add = tp__stitch_add_create(r->grid.n));
}

static int grow_items(tp_renderer* r, size_t count)
{
    if (count <= r->item_cap)
        return 1;
    tp_render_item* items = realloc(r->items, count * sizeof *items);
    if (!items)
        return 0;
    r->items = items;
    r->item_cap = count;
    return 1;
}

static void fill_patch(void* user, size_t i, tp_vertex* v, float (*normals)[3], uint8_t* filled)
{
    const tp_renderer* r = user;
    const tp_render_item* it = &r->items[i];
    int nb[4] = {it->nb[0], it->nb[1], it->nb[2], it->nb[3]};
    int k = it->level, side = (1 << k) + 1;
    size_t count = (size_t)side * side;
    tp_patch_vertices(r->terrain, (int)it->key, k, nb, v, count);
    for (size_t j = 0; j < count; j++) {
        tp_terrain_normal(r->terrain, v[j].x, v[j].y, normals[j]);
        filled[j] = tp_terrain_sample_class(r->terrain, v[j].x, v[j].y) == TP_SAMPLE_FILLED;
    }
}

void tp_renderer_draw(tp_renderer* r, tp_selection* sel, const tp_camera* cam,
                      const tp_render_settings* s, int finish, tp_render_stats* stats)
{
    assert(r->terrain);
    tp_terrain_info in;
    tp_terrain_get_info(r->terrain, &in);
    if (!grow_items(r, (size_t)in.patch_count)) {
        memset(stats, 0, sizeof *stats);
        return;
    }
    size_t count = 0;
    for (int p = 0; p < in.patch_count; p++) {
        if (!tp_selection_visible(sel, p))
            continue;
        tp_render_item* it = &r->items[count++];
        int nb[4], k = tp_selection_level(sel, p);
        tp_selection_neighbor_levels(sel, p, nb);
        it->key = p;
        it->level = (int8_t)k;
        /* only a coarser neighbour moves vertices (a finer one adds them, --stitch add): others
         * need no new upload when they change */
        for (int side = 0; side < 4; side++)
            it->nb[side] = (int8_t)(nb[side] >= 0 && (s->stitch_add ? nb[side] > k : nb[side] < k)
                                        ? nb[side]
                                        : TP_NO_NEIGHBOR);
        it->incomplete = !r->complete[p];
    }
    tp_selection_clear_dirty(sel);
    if (!set_stitch_add(r, s))
        count = 0; /* out of memory: nothing to draw */
    tp_renderer_draw_items(r, r->items, count, fill_patch, r, cam, s,
                           tp_selection_vertical_scale(sel), finish, stats);
    r->stitch_add = 0;
}

/* ---- the nodes of a cut over a tree ---- */

static void fill_node(void* user, size_t i, tp_vertex* v, float (*normals)[3], uint8_t* filled)
{
    const tp_renderer* r = user;
    const tp_render_item* it = &r->items[i];
    int side = (1 << it->level) + 1;
    size_t count = (size_t)side * side;
    tp_cut_vertices(r->cut, i, v, count);
    for (size_t j = 0; j < count; j++) {
        filled[j] = v[j].cls == TP_SAMPLE_FILLED; /* the store's filled bits (format 4) */
        if (isnan(v[j].z_m)) {
            normals[j][0] = normals[j][1] = 0;
            normals[j][2] = 1;
        } else {
            tp_tree_node_normal(r->tree, it->key, v[j].x, v[j].y, normals[j]);
        }
    }
}

void tp_renderer_draw_cut(tp_renderer* r, const tp_tree* tree, const tp_cut* cut,
                          const tp_camera* cam, const tp_render_settings* s, double zscale,
                          int finish, tp_render_stats* stats)
{
    size_t count = 0;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    if (!grow_items(r, count)) {
        memset(stats, 0, sizeof *stats);
        return;
    }
    for (size_t i = 0; i < count; i++) {
        tp_render_item* it = &r->items[i];
        it->key = nodes[i].node;
        it->level = nodes[i].level;
        /* a side moves (below the level) or, --stitch add, takes vertices (above it) */
        for (int side = 0; side < 4; side++)
            it->nb[side] = (int8_t)(s->stitch_add && nodes[i].add[side] > nodes[i].level
                                        ? nodes[i].add[side]
                                    : nodes[i].nb[side] >= 0 && nodes[i].nb[side] < nodes[i].level
                                        ? nodes[i].nb[side]
                                        : TP_NO_NEIGHBOR);
        it->incomplete = !(tp_tree_meta(tree, nodes[i].node)->flags & TP_NODE_COMPLETE);
    }
    if (!set_stitch_add(r, s))
        count = 0; /* out of memory: nothing to draw */
    r->tree = tree;
    r->cut = cut;
    tp_renderer_draw_items(r, r->items, count, fill_node, r, cam, s, zscale, finish, stats);
    r->stitch_add = 0;
    r->tree = NULL;
    r->cut = NULL;
}
