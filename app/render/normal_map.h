/*
 * normal_map.h - the terrain's full-resolution normals on the GPU through a clipmap (issue 32,
 * item 3), so that the terrain is shaded per pixel from the same normals whatever level of
 * detail its geometry is drawn at: adjacent nodes at different levels, and a node changing
 * level, shade alike.
 *
 * The normals are a pyramid that exists nowhere whole: level 0 holds a texel per post, the
 * post's unit normal (east, north, up) by the rule of tp_terrain_normal and tp_tree_node_normal
 * (central differences of the full-resolution posts, one-sided next to undrawn ones), quantised
 * as the vertex path quantises its own (x 127, rounded; stored as 128 + that in GL_RGBA8, with
 * the post's height's share of the range and alpha 1, 1/2 for a filled void): at full
 * resolution the picture is the one per-vertex normals gave. Level l >= 1 holds a texel per
 * 2^l posts: the normal of the cell between lattice posts (i, j) and (i + 1, j + 1) of stride
 * 2^l (the mean of its two rows' and two columns' slopes: the surface's mean slope over the
 * texel's footprint, so a far view is shaded from prefiltered normals, not from whichever post a
 * pixel happens to hit). Blocks of 256 x 256 texels are computed on the clipmap's loader thread
 * (clipmap.h, imagery_cache.h: Luo's toroidal update, the prefetch, the garbage collection by
 * motion), from the posts of the store's nodes of scale l (tp_store_read_node; a small cache of
 * decoded nodes) or of a DEM drawn whole (tp_terrain_sample). A block that cannot be read is
 * transparent (alpha 0): the shader falls back to the vertex normals there.
 *
 * GPU memory: the clipmap's, (256 s)^2 x 4 bytes a level (s = TP_NORMAL_MAP_BLOCKS: 4 MiB a
 * level), levels = 1 + the levels until one block holds the grid (a 1201^2 tile: 4, 16 MiB; a
 * 65537^2 store: 10, 40 MiB). app/render/normal_map.c.
 */
#ifndef TP_APP_VIEW_NORMAL_MAP_H
#define TP_APP_VIEW_NORMAL_MAP_H

#include "clipmap.h"
#include "renderer.h"
#include "store_scene.h"
#include "tp_core.h"
#include "tp_io.h"

#define TP_NORMAL_MAP_BLOCK 256 /* texels a side of a block */
#define TP_NORMAL_MAP_BLOCKS 4  /* default window: blocks a side (1024 texels) */
#define TP_NORMAL_MAP_CACHE_BYTES ((size_t)8 << 20) /* default pool of blocks in RAM (32) */

/* Where the normals' posts come from: a store (its nodes read as needed; s must outlive it) or a
 * terrain drawn whole (t must outlive it). NULL with a message in err (out of memory). */
typedef struct tp_normal_source tp_normal_source;
tp_normal_source* tp_normal_source_store(const tp_store* s, double min_m, double max_m,
                                         tp_error* err);
tp_normal_source* tp_normal_source_terrain(const tp_terrain* t, tp_error* err);
void tp_normal_source_destroy(tp_normal_source* src); /* accepts NULL */

/* The clipmap's block source over src (blocks of RGBA8 texels (128 + 127 nx, 128 + 127 ny,
 * 255 h, 255 - 127 filled), h the height's share of the range, top row first; a texel past the
 * grid's edge is 0) and the geotransform of its level-0 texels (the grid's: a texel per post).
 * src must outlive what uses it. */
void tp_normal_source_blocks(tp_normal_source* src, tp_block_source* out, double gt[6]);

typedef struct tp_normal_map tp_normal_map;

/* Creates the clipmap of src (owned from now on, also on failure) with o (NULL: the defaults,
 * TP_NORMAL_MAP_BLOCKS a window, TP_NORMAL_MAP_CACHE_BYTES of blocks in RAM): the coarsest
 * levels a window holds are computed at once (a current GL context is needed). NULL with a
 * message in err. */
tp_normal_map* tp_normal_map_create(tp_normal_source* src, const tp_clipmap_options* o,
                                    tp_error* err);
void tp_normal_map_destroy(tp_normal_map* nm); /* accepts NULL */

/* Once a frame over a store's cut, before drawing: the finest level the cut's nodes need (Blow,
 * heights times zscale), the clipmap's update (settle: every window whole, headless frames) and
 * the renderer's normals (tp_renderer_set_normals). stats may be NULL. */
void tp_normal_map_frame_cut(tp_normal_map* nm, const tp_store_scene* st, const tp_cut* cut,
                             double zscale, tp_renderer* r, const tp_camera* cam, int settle,
                             tp_clipmap_stats* stats);

/* The same for a DEM drawn whole: the finest level from the distance between the eye and the
 * grid's box (heights min_m .. max_m, as drawn). */
void tp_normal_map_frame(tp_normal_map* nm, tp_renderer* r, const tp_camera* cam, double min_m,
                         double max_m, int settle, tp_clipmap_stats* stats);

/* The first block read failure not reported yet (one line), or NULL. */
const char* tp_normal_map_take_failure(tp_normal_map* nm);

#endif /* TP_APP_VIEW_NORMAL_MAP_H */
