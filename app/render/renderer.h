/*
 * renderer.h - draws a tp_selection with OpenGL 3.3 core, Direct3D-style buffers as in
 * Vanek & Jezek: one index buffer per level shared by every patch (a triangle strip with
 * degenerate triangles), per-patch vertex data carrying the crack fix, uploaded only when the
 * patch's or a neighbour's level changed, into pools of vertex slots reused least-recently-used
 * (Brodersen section 5): one buffer per level k whose slots hold (2^k+1)^2 vertices, so an item
 * takes the room its level needs (vertex_pool.h), and all visible patches of a level draw with
 * one glMultiDrawElementsBaseVertex call (plus one for patches next to nodata, which use their
 * own triangle lists).
 *
 * Precision: vertices carry global integer grid coordinates; the vertex shader subtracts the
 * camera's integer cell in integers, so every patch goes through the same camera-rebased
 * transform from bit-identical inputs and shared border vertices land on the same clip-space
 * position whatever the size of the projected coordinates.
 */
#ifndef TP_APP_RENDERER_H
#define TP_APP_RENDERER_H

#include "tp_core.h"

#include <stddef.h>

typedef struct tp_renderer tp_renderer;

typedef struct tp_render_settings {
    double sun_azimuth_deg;   /* clockwise from grid north; default 315 (north-west) */
    double sun_elevation_deg; /* default 45 */
    double exaggeration;      /* vertical; default 1 (the frame hands it to the selection,
                                 whose scale the renderer draws with) */
    int wireframe;
    int color_lod;            /* colour patches by level */
    int hide_filled;          /* draw filled voids untinted */
    float clear_rgb[3];
    int one_draw_per_patch;   /* instead of multi-draw (for measuring the difference) */
    int stitch_add;           /* remove cracks by adding the finer neighbour's vertices to the
                                 coarser patch's border (tp_patch_triangles_add, `--stitch
                                 add`) instead of moving the finer patch's (the default); a
                                 store's cut must have been updated with tp_cut_set_stitch_add */
    int stitch_add_five;      /* with stitch_add: draw a patch that takes vertices as up to
                                 five draws of per-level index sets (stitch_add_five.h,
                                 `--stitch-add-draw five`; 1 by default) instead of its own
                                 triangle list from an index set per neighbour configuration
                                 (0, "sets") */
    double grid_m;            /* grid lines every grid_m metres of the render CRS (UTM: the
                                 UTM/MGRS grid); 0 for none */
} tp_render_settings;

void tp_render_settings_default(tp_render_settings* s);

typedef struct tp_render_stats {
    int draw_calls;
    int patches_drawn;
    int uploads;              /* patches whose vertex data was (re)uploaded this frame */
    size_t gpu_bytes;         /* resident GPU buffers */
    double upload_ms;         /* building and uploading vertex data */
    double draw_ms;           /* submitting and finishing the draw (glFinish) */
    long page_faults;         /* minor page faults of the process while drawing (getrusage):
                                 memory the GL driver maps in; ~0 once frames repeat */
    double near_m, far_m;     /* the depth range the terrain was drawn with (what the overlay's
                                 draped lines must match to be hidden by it) */
    int dropped;              /* items not drawn: their level's vertex pool is at
                                 TP_RENDER_POOL_MAX_BYTES and every slot is drawn this frame (or
                                 memory ran out) */
    size_t triangles;         /* --stitch add only (else 0: the core counts them): the
                                 triangles drawn, 2 * 4^k for a level-k strip (nothing moves) */
    int draws;                /* draws submitted, each of a multi-draw's counted */
    size_t index_gpu_bytes;   /* of gpu_bytes, the index buffers (strips, triangle-list
                                 regions, --stitch-add-draw five's sets) */
    size_t index_cpu_bytes;   /* --stitch add: the CPU memory its index sets' cache holds */
} tp_render_stats;

/* No level's vertex pool grows past this, whatever a frame asks for: llvmpipe (Mesa 22.3) crashes
 * drawing from a buffer past 2 GiB (bench over a 20481^2 store at tau = 1), and no frame that
 * needs more can be interactive. Items beyond it are dropped (counted in tp_render_stats). */
#define TP_RENDER_POOL_MAX_BYTES ((size_t)1 << 30)

/* Each level's vertex pool starts with the slots that fit in this (at least one): a view draws
 * a few levels, and a pool grows by a quarter when a frame needs more (vertex_pool.h; a TIN
 * node's data goes in the pool of the smallest level whose slot and region hold it). 64 slots a level were 5.9 MB for
 * 65-sample nodes whatever the view drew (docs/PERFORMANCE.md, "Per-level vertex pools"). */
#define TP_RENDER_POOL_INITIAL_BYTES ((size_t)64 << 10)

/* On a software rasteriser (tp_gl_context_software) the draws wait for the rasteriser
 * (glFinish) each time this many indices have been submitted since the last wait; the
 * environment's TP_SOFTWARE_SYNC_INDICES overrides it (0: never wait). llvmpipe bins a frame's
 * triangles into malloc'd scenes (~150 bytes a triangle) until it rasterises them: 110 MB of the
 * process's anonymous memory for a frame of 753 k triangles, growing with the triangles a frame
 * draws. Waiting every 128 Ki indices bounds it, at no measured cost in CPU or frame time
 * (docs/PERFORMANCE.md, "The software rasteriser's memory"). A GPU is never made to wait. */
#define TP_RENDER_SOFTWARE_SYNC_INDICES ((size_t)1 << 17)

/* What the renderer needs to know about the grid it draws. */
typedef struct tp_render_grid_desc {
    int n;                       /* items are (2^n+1)^2 at most (level n) */
    double geotransform[6];      /* of the full-resolution grid */
    int width, height;           /* full-resolution grid (for the far plane) */
    double min_height_m, max_height_m; /* for the far plane and the hypsometric colours */
    /* Budget of the vertex pools (--gpu-memory), shared evenly between the n+1 levels' pools; 0:
     * none. A pool grows (doubling) up to its share, then reuses its least-recently-used slots
     * not drawn this frame. A frame whose items alone need more slots than a share holds grows
     * that pool past it (every item is drawn, never a hole) and the pool stays that size:
     * gpu_bytes then exceeds the budget. */
    size_t pool_budget_bytes;
} tp_render_grid_desc;

/* Creates the GPU resources (a current GL context is needed). NULL with err on failure. */
tp_renderer* tp_renderer_create_desc(const tp_render_grid_desc* d, tp_error* err);
/* The same for a resident terrain (its patches). */
tp_renderer* tp_renderer_create(const tp_terrain* t, tp_error* err);
void tp_renderer_destroy(tp_renderer* r);

/* Drapes an RGBA8 image (w x h, top row first) over the terrain: grid sample (x, y) of the
 * tiled grid takes texture coordinates (x * scale[0] + offset[0], y * scale[1] + offset[1]).
 * Alpha blends the image over the shaded colour. Returns 0 if the GL texture can't be made. */
int tp_renderer_set_texture(tp_renderer* r, const uint8_t* rgba, int w, int h,
                            const float scale[2], const float offset[2]);

/* Imagery sampled through a clipmap (clipmap.h): a GL_TEXTURE_2D_ARRAY of one layer per level,
 * each size x size texels holding level texel (u, v) at (u mod size, v mod size) (wrapping
 * repeats); the shader picks per fragment the level from the screen derivatives of the level-0
 * texel coordinates (not finer than first) and falls back to coarser levels until the texel's
 * bilinear footprint lies inside that level's valid rectangle. */
#define TP_RENDER_CLIP_LEVELS 16
typedef struct tp_render_clip {
    unsigned texture;         /* 0: no imagery */
    int levels, size, first;
    double geotransform[6];   /* of level 0's texels, render CRS */
    double rect[TP_RENDER_CLIP_LEVELS][4]; /* per level: valid texels [x0, x1) x [y0, y1) as
                                              {x0, y0, x1, y1} of that level; empty: x1 <= x0 */
} tp_render_clip;

/* Cast shadows from the next draw on: texture (GL_R8, w x h texels, 255 lit, 0 shadowed) covers
 * grid posts x0 .. x0 + w - 1, y0 .. y0 + h - 1, texel centre on post; the direct sunlight of
 * a fragment in its shadow is taken away, the ambient term stays; outside the window nothing
 * changes. texture 0: none (shadow_view.h). */
void tp_renderer_set_shadow(tp_renderer* r, unsigned texture, int x0, int y0, int w, int h);

/* Cast shadows over a day from the next draw on (light_view.h): a clipmap as above of the
 * light times of the render grid's posts (texels (r1, s1, r2, s2), tp_core.h's
 * tp_light_times_build; level 0 a texel per post), sampled bilinearly at the finest valid level
 * the distance allows; the lit fraction of a fragment at tau (steps of the file's day, 0 ..
 * TP_LIGHT_TIMES_STEPS) is how much of [tau, tau + 1] lies in its lit intervals (the rule of
 * tp_light_times_lit at whole steps, a one-step ramp between them), and the direct sunlight
 * of the unlit fraction is taken away; where no level is valid nothing changes. While set it
 * replaces the shadow window (tp_renderer_set_shadow). NULL or texture 0: none. */
void tp_renderer_set_light(tp_renderer* r, const tp_render_clip* clip, double tau);

/* The terrain's normals from the next draw on (normal_map.h): a clipmap as above of RGBA8 texels
 * (128 + 127 nx, 128 + 127 ny, 255 h, 255 - 127 filled) of the render grid's posts (level 0 a
 * texel per post; h the height's share of the range), sampled bilinearly at the finest valid
 * level the distance allows; the hillshade (the normal exaggerated as the vertex normals are),
 * the hypsometric colour and the filled-void tint are then computed per fragment, so that the
 * shading does not depend on the level the geometry is drawn at. Where no level is valid, or a
 * texel's alpha is under 1/4 (a block not read), the vertices shade as before. NULL or texture
 * 0: none. */
void tp_renderer_set_normals(tp_renderer* r, const tp_render_clip* clip);

/* The clipmap to sample from the next draw on (copied); NULL or texture 0: none (NULL also
 * clears the item textures below: no imagery at all). */
void tp_renderer_set_clip(tp_renderer* r, const tp_render_clip* clip);

/* Imagery with a texture per drawn item (imagery_blocks.h, Brodersen's blocks): layer `layer`
 * of the GL_TEXTURE_2D_ARRAY texture, sampled (bilinear, clamped to the layer's edge) at
 * normalised layer coordinates (a_grid - cell) * scale + offset for the vertex at global grid
 * post a_grid (cell: a post near the item, so the floats stay small). Layer -1: no imagery on
 * that item. */
typedef struct tp_render_item_texture {
    int layer;
    int32_t cell[2];
    float scale[2], offset[2];
} tp_render_item_texture;

/* The next tp_renderer_draw_cut's per-item textures, in tp_cut_nodes order (copied); drawn one
 * draw call per item (as one_draw_per_patch). Ignored by a draw whose item count differs from
 * count; NULL, 0 or texture 0: none. The clipmap (tp_renderer_set_clip) is not sampled while
 * they are set. */
void tp_renderer_set_item_textures(tp_renderer* r, unsigned texture,
                                   const tp_render_item_texture* items, size_t count);

/* One thing to draw: a patch of a terrain or a node of a tree, at one level, with the
 * neighbour levels its crack removal used. The vertex data held for a key is rebuilt only when
 * its level or neighbour levels change (or it was evicted from the pool). */
typedef struct tp_render_item {
    int64_t key;
    int8_t level;      /* 0..n */
    int8_t nb[4];
    uint8_t incomplete;/* has undrawn samples: drawn as its own triangle list */
    int8_t tin;        /* a cut's node that draws a TIN (tp_cut_node.tin): that rung, drawn as
                          its own triangle list over its tp_cut_vertex_count vertices (v, held
                          in the pool of the smallest level m with 4^m >= v); -1: none */
} tp_render_item;

/* Writes item i's vertex data: (2^level+1)^2 vertices (as tp_patch_vertices; a TIN item: its
 * rung's), their unit normals (east, north, up) and whether each is a filled void; returns how
 * many it wrote. */
typedef size_t (*tp_render_fill_fn)(void* user, size_t i, tp_vertex* vertices,
                                    float (*normals)[3], uint8_t* filled);

/* The far plane for cam over a grid's box when cam sets none: the distance from the camera to
 * the farthest corner of the box of the posts of a width x height grid (geotransform gt; post
 * (x, y) at gt[0] + (x + 0.5) * gt[1], gt[3] + (y + 0.5) * gt[5]) between heights min_m and
 * max_m (as drawn), times 1.1, plus 10 m; metres (renderer_draw.c; PGM's too). */
double tp_render_far_box(const tp_camera* cam, const double gt[6], int width, int height,
                         double min_m, double max_m);

/* Uploads what changed, then draws the items for cam with heights times zscale. finish: wait
 * for the GPU (glFinish) so that draw_ms is the real draw time. */
void tp_renderer_draw_items(tp_renderer* r, const tp_render_item* items, size_t count,
                            tp_render_fill_fn fill, void* user, const tp_camera* cam,
                            const tp_render_settings* s, double zscale, int finish,
                            tp_render_stats* stats);

/* The visible patches of a selection (render_patches.c): items from its levels, vertex data
 * from the terrain the renderer was created for (tp_renderer_create); clears dirty flags. */
void tp_renderer_draw(tp_renderer* r, tp_selection* sel, const tp_camera* cam,
                      const tp_render_settings* s, int finish, tp_render_stats* stats);

/* The nodes of a cut over a tree (keys: node ids), heights times zscale. */
void tp_renderer_draw_cut(tp_renderer* r, const tp_tree* tree, const tp_cut* cut,
                          const tp_camera* cam, const tp_render_settings* s, double zscale,
                          int finish, tp_render_stats* stats);

#endif
