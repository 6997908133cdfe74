/*
 * pgm_render.h - Persistent Grid Mapping on the GPU (Livny, Kogan & El-Sana, section 3; the
 * core's tp_pgm_* in tp_core.h): a grid of cols x rows vertices fixed in screen space, made
 * once (its index buffer; the vertices are gl_VertexID), and the elevation pyramid uploaded once
 * as one R32F texture atlas (level 0, then every coarser level stacked beside it: the paper's
 * section 4 atlas). Each frame the vertex shader maps vertex (i, j) exactly as
 * tp_pgm_map_vertex documents: the ray from the eye through the auxiliary camera's pixel (Eq. 2)
 * meets the base plane (Eq. 1), the level comes from r (Eq. 3), the height is blended with the
 * parent level (Eq. 4), read with texelFetch and a manual bilinear (tp_pgm_pyramid_sample);
 * then the main camera projects it. All in eye-relative floats (the eye is subtracted on the
 * CPU). Triangles with a vertex off the terrain are discarded.
 */
#ifndef TP_APP_PGM_RENDER_H
#define TP_APP_PGM_RENDER_H

#include "renderer.h"
#include "tp_core.h"

#include <stddef.h>

typedef struct tp_pgm_renderer tp_pgm_renderer;

typedef struct tp_pgm_render_stats {
    int cols, rows;
    size_t triangles;     /* 2 * (cols - 1) * (rows - 1): every frame the same */
    size_t gpu_bytes;     /* the index buffer and the atlas (or the clipmap's texture array) */
    double setup_ms;      /* tp_pgm_frame_setup and the uniforms (a clipmap's update included) */
    double fill_ms;       /* over a clipmap: reading the posts its windows gained (0 else) */
    double upload_ms;     /* and uploading them */
    size_t posts_updated; /* those posts */
    size_t node_reads;    /* store nodes read for them (the clipmap's cache missed) */
    double draw_ms;       /* submitting and finishing the draw (glFinish when asked) */
    double near_m, far_m; /* the depth range drawn with */
} tp_pgm_render_stats;

/* Creates the grid and uploads the pyramid (borrowed: it must outlive the renderer) for a
 * current GL context; cols, rows >= 2. valid (NULL: every post) is width[0] x height[0] bytes,
 * non-zero where level 0 has a height: a vertex whose level-0 cell touches a post without one
 * counts as off the terrain (its triangles are not drawn), as the patch renderer draws no
 * triangle with a nodata corner. NULL with a message in err when the atlas exceeds
 * GL_MAX_TEXTURE_SIZE (naming both sizes), a shader fails or memory runs out. */
tp_pgm_renderer* tp_pgm_renderer_create(const tp_pgm_pyramid* p, const uint8_t* valid, int cols,
                                        int rows, tp_error* err);
void tp_pgm_renderer_destroy(tp_pgm_renderer* r); /* accepts NULL */

/* Clears and draws one frame for cam (its viewport replaced by the current GL viewport's
 * size), shaded with s's sun, clear colour, wireframe and color_lod (colour by pyramid level);
 * the exaggeration is not applied (PGM draws the pyramid's heights). frame_out (may be NULL)
 * gets the tp_pgm_frame the shader drew with (for tp_pgm_measure_error). finish: glFinish. */
void tp_pgm_renderer_draw(tp_pgm_renderer* r, const tp_camera* cam, const tp_render_settings* s,
                          int finish, tp_pgm_frame* frame_out, tp_pgm_render_stats* stats);

/* Creates the grid over a store's clipmap (pgm_clip.h; borrowed: it must outlive the
 * renderer), for stores of any size: each draw first moves the clipmap's windows to the eye
 * (tp_pgm_clipmap_update; a read failure is printed once and its posts are not drawn; until a
 * first fill succeeds, out of memory, the frame is only cleared), and the
 * shader reads each level from its window, or where the bilinear footprint lies outside it,
 * from the first coarser level whose window holds it (so no vertex reads a stale texel). A
 * texel without a height (nodata) counts as off the terrain. Fails as tp_pgm_renderer_create. */
typedef struct tp_pgm_clipmap tp_pgm_clipmap;
tp_pgm_renderer* tp_pgm_renderer_create_clipmap(tp_pgm_clipmap* clip, int cols, int rows,
                                                tp_error* err);

/* The error of the surface drawn for cam (its own viewport) by the bench's definition:
 * tp_pgm_measure_error over the whole pyramid, or over a clipmap tp_pgm_clipmap_measure (the
 * windows as they stand: call it after the draw it measures, before the next; max_posts, 0 for
 * none, bounds the posts it visits: a larger region is sampled by bands, out->post_share).
 * TP_OK and *out; else *out zeroed and a message in err (out of memory; over a store, a node
 * that cannot be read). */
tp_status tp_pgm_renderer_measure(const tp_pgm_renderer* r, const tp_camera* cam, size_t max_posts,
                                  tp_pgm_error* out, tp_error* err);

/* The grid size. */
void tp_pgm_renderer_grid(const tp_pgm_renderer* r, int* cols, int* rows);

/* The pyramid of a render grid's heights for PGM, which has no holes: a NaN height (not drawn)
 * takes the nearest height of its row, else of its column, else the lowest drawn height, so
 * that coarse levels near a void's edge read heights like the edge's. *valid gets a malloc'ed
 * width x height mask (1 where the height was drawn) for tp_pgm_renderer_create, or NULL when
 * every height is. Returns TP_OK or the tp_pgm_pyramid_build status with err (nothing to
 * free then). */
tp_status tp_pgm_pyramid_from_grid(const float* heights, int width, int height, const double gt[6],
                                   tp_pgm_pyramid* out, uint8_t** valid, tp_error* err);

#endif
