/*
 * imagery_blocks.h - imagery on the GPU the way Brodersen draws it ("Real-time visualization of
 * large textured terrains", section 5): every drawn node of the cut owns one texture, the
 * comparison for the clipmap (clipmap.h; issue 15, `--imagery-mode blocks`).
 *
 * Which texture. A node (s, c, r) of a tree with nodes of 2^n + 1 posts spans 2^(n+s) grid
 * posts a side; at pyramid level l = n + s + texel_shift - 8 that is exactly 256 texels (one
 * block's width). Its texture is the 256 x 256 texel window of level l that starts at texel
 * (c * 256 + f, r * 256 + f), f = floor(h), h = half a post in level-l texels: the node's
 * posts lie in texels [c * 256 + h, (c + 1) * 256 + h] (pixel-is-area: post x is at level-0
 * texel (x + 0.5) * 2^texel_shift), so the window holds the node, every texel at its own
 * place; only the outermost half texel along a node's edge is clamped (CLAMP_TO_EDGE), as with
 * any per-tile texture (where h < 1, f = 0: the last h texels of the node, under half a
 * texel, lie past the window's east and south edges and repeat its last texel). The window is assembled from the (at most 2 x 2) pyramid blocks it
 * overlaps. A node finer than level 0 (l < 0) uses the window of its ancestor at level 0 (a
 * sub-rectangle of it); a node coarser than the coarsest level, the coarsest level's single
 * window at (0, 0) (the whole image), which is read at creation and never evicted, so every
 * node has an ancestor with a texture and nothing is ever drawn without imagery.
 *
 * Where. The windows are the layers of one GL_TEXTURE_2D_ARRAY of K layers of 256 x 256 RGBA8
 * (K = the GPU budget / 256 KiB; the default 96 MiB holds 384), handed out least recently
 * drawn first (Brodersen's pools). Blocks come from imagery_cache.h's loader thread; a node
 * whose window is not on the GPU yet (not read, or over the frame's upload cap) is drawn with
 * its nearest ancestor's layer that is (a sub-rectangle at half, quarter... the resolution).
 *
 * Drawing: tp_renderer_set_item_textures (renderer.h), one draw per node.
 */
#ifndef TP_APP_VIEW_IMAGERY_BLOCKS_H
#define TP_APP_VIEW_IMAGERY_BLOCKS_H

#include "clipmap.h" /* tp_clipmap_stats: the same statistics */
#include "imagery_cache.h"
#include "renderer.h"
#include "tp_core.h"

typedef struct tp_imagery_blocks tp_imagery_blocks;

#define TP_BLOCKS_LAYER 256                          /* texels a side of a layer */
#define TP_BLOCKS_DEFAULT_GPU_BYTES ((size_t)96 << 20) /* 384 layers */

typedef struct tp_imagery_blocks_options {
    size_t gpu_bytes;        /* the texture array; 0: TP_BLOCKS_DEFAULT_GPU_BYTES (at least 8
                                layers, at most the GPU's GL_MAX_ARRAY_TEXTURE_LAYERS) */
    size_t cache_bytes;      /* the loader's pool of blocks in RAM; 0: 64 MiB */
    int upload_cap_layers;   /* layers uploaded per frame at most; 0: 8 (2 MiB, the clipmap's
                                cap) */
    int no_loader;           /* tests: nothing read in the background */
} tp_imagery_blocks_options;

/* The layer and mapping of one drawn node (what tp_renderer_set_item_textures takes). */
typedef struct tp_blocks_assignment {
    int layer;               /* -1: the node's window is wholly transparent (no layer) */
    int level;               /* pyramid level of the layer's window (or of the empty one) */
    int64_t origin[2];       /* the window's first texel of that level */
    int own;                 /* 1: the node's own window; 0: an ancestor's */
} tp_blocks_assignment;

/* Creates the texture array (a current GL context is needed) and reads and uploads the
 * coarsest level's window synchronously. src: the pyramid's blocks; texel_shift: level-0
 * texels per grid post = 2^texel_shift; gt: level 0's geotransform (tp_imagery_info; for the
 * RAM pool's garbage collection by distance); g: the tree drawn (copied). NULL with a message
 * in err on failure (the GPU's layers or memory, the read of the coarsest block). */
tp_imagery_blocks* tp_imagery_blocks_create(const tp_block_source* src, int texel_shift,
                                            const double gt[6], const tp_tree_geometry* g,
                                            const tp_imagery_blocks_options* o, tp_error* err);
void tp_imagery_blocks_destroy(tp_imagery_blocks* b); /* accepts NULL */

/* Once per frame before drawing the cut: assigns each drawn node (tp_cut_nodes order) its
 * layer (uploading ready windows, at most the cap unless settle), queues the blocks of the
 * windows missing, collects the RAM pool, and hands the per-node textures to r (NULL: none,
 * tests). settle: wait (up to timeout_s) until every node has its own window, or no layer is
 * left for one (more nodes drawn than layers), without the cap (headless frames, tests). */
void tp_imagery_blocks_frame(tp_imagery_blocks* b, const tp_cut* cut, tp_renderer* r,
                             const tp_camera* cam, int settle, double timeout_s,
                             tp_clipmap_stats* st);

/* The last frame's assignment of each drawn node and what it handed the renderer (tests), the
 * texture array's name and its layers. */
const tp_blocks_assignment* tp_imagery_blocks_assignment(const tp_imagery_blocks* b, size_t* count);
const tp_render_item_texture* tp_imagery_blocks_item_textures(const tp_imagery_blocks* b,
                                                              size_t* count);
unsigned tp_imagery_blocks_texture(const tp_imagery_blocks* b);
int tp_imagery_blocks_layers(const tp_imagery_blocks* b);

/* The first block read failure not reported yet, or NULL. */
const char* tp_imagery_blocks_take_failure(tp_imagery_blocks* b);

#endif /* TP_APP_VIEW_IMAGERY_BLOCKS_H */
