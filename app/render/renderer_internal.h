/*
 * renderer_internal.h - the patch renderer's state and the stages its files share (tp__ names;
 * renderer.h is what the rest of the app sees):
 *
 *   renderer.c         the GPU resources: program, uniforms, strip index buffer, vertex pools;
 *                      what is draped and lit (textures, clipmaps, shadows)
 *   renderer_upload.c  the items' vertex data into pool slots, each item's draws recorded
 *   renderer_draw.c    tp_renderer_draw_items: the draws grouped, the camera and light set as
 *                      uniforms, the draws submitted, the frame's statistics
 *   render_patches.c   the items of a resident terrain's selection and of a store's cut
 */
#ifndef TP_APP_RENDERER_INTERNAL_H
#define TP_APP_RENDERER_INTERNAL_H

#include "renderer.h"

#include "render_clip.h"
#include "stitch_add_draw.h"
#include "stitch_add_five.h"
#include "terrain_shaders.h"
#include "vertex_pool.h"

#include <epoxy/gl.h>

/* One vertex on the GPU: 16 bytes. */
typedef struct gpu_vertex {
    int32_t x, y;  /* global grid coordinates (after crack removal) */
    float z;       /* height, metres */
    int8_t n[3];   /* unit normal * 127, world frame (east, north, up) */
    uint8_t flags; /* bits 0-3: level, bit 4: filled void */
} gpu_vertex;

/* The terrain program with some features (terrain_shaders.h, TP_SHADE_*) and its uniforms;
 * prog 0 until first used. */
typedef struct tp__program {
    GLuint prog;
    GLint u_cell, u_frac, u_spacing, u_cam_z, u_exag, u_viewproj, u_sun, u_color_lod, u_hide_filled,
        u_hrange, u_tex, u_tex_scale, u_tex_offset, u_grid, u_grid_origin, u_shadow, u_shadow_win,
        u_blk, u_blk_layer, u_blk_cell, u_blk_scale, u_blk_offset, u_light_tau;
    tp__clip_uniforms clip_u, light_u, normal_u; /* the imagery's clipmap (unit 1), the
                                                    light's (4), the normals' (5) */
} tp__program;

struct tp_renderer {
    tp_render_grid_desc grid;
    tp__program progs[TP_SHADE_ALL + 1]; /* by features, made as draws need them */
    const tp__program* p;                /* the one the draw uses */
    GLuint vao, ibo;
    GLenum index_type;
    size_t level_offset[TP_MAX_LEVELS], level_count[TP_MAX_LEVELS];
    size_t slot_verts;    /* (2^n+1)^2: the finest level's item */
    tp_vertex_pool* pool; /* the items' vertex data and triangle lists */
    int* draw_level;      /* per drawn item: its group (level, strip or triangle list) */
    tp_vertex* vtmp;
    float (*ntmp)[3];
    uint8_t* ftmp;
    gpu_vertex* gtmp;
    uint32_t* ttmp;
    GLsizei* counts; /* per drawn item, in item order; then grouped by level */
    void** offsets;
    GLint* bases;
    GLsizei* gcounts;
    void** goffsets;
    GLint* gbases;
    size_t draw_cap;
    GLuint shadow_tex;
    int shadow_win[4];
    GLuint tex;
    /* tp_renderer_set_item_textures: a texture per item (imagery_blocks.h) */
    GLuint blk_tex;
    tp_render_item_texture* blk;
    size_t blk_count, blk_cap;
    size_t* ditem; /* per drawn item: its index in items; then grouped as the draws */
    size_t* gitem;
    tp_render_clip clip;
    tp_render_clip light; /* tp_renderer_set_light */
    tp_render_clip normals; /* tp_renderer_set_normals */
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
    /* A software rasteriser's binned triangles are drained (glFinish) every sync_indices
     * indices submitted; 0 on a GPU (renderer_draw.c, submit_draws) */
    size_t sync_indices;
};

/* renderer.c: the program with features (TP_SHADE_*), compiled on first use; NULL with a
 * message in err when it does not compile. */
const tp__program* tp__renderer_program(tp_renderer* r, unsigned features, tp_error* err);

/* renderer.c: points the vertex attributes at one pool's buffer (the array buffer binding is not
 * part of the vertex array's state: the attribute pointers are). Leaves r's vertex array bound. */
void tp__renderer_vertex_format(tp_renderer* r, GLuint vbo);

/* renderer_upload.c: makes room for count draws (r->counts and the arrays beside them); 0 when
 * out of memory (r->draw_cap draws still fit). */
int tp__renderer_grow_draws(tp_renderer* r, size_t count);

/* renderer_upload.c: takes a pool slot for each of the count items (as many draws as
 * tp__renderer_grow_draws made room for), (re)builds the vertex data of those whose level or
 * neighbours changed (fill writes it; --stitch add: the neighbour sets), and records each item's
 * draws in r->draw_level, counts, offsets, bases and ditem. Counts uploads, items drawn and
 * dropped, and --stitch add's triangles in stats. Returns the number of draws recorded. */
size_t tp__renderer_upload(tp_renderer* r, const tp_render_item* items, size_t count,
                           tp_render_fill_fn fill, void* user, tp_render_stats* stats);

#endif
