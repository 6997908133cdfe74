/*
 * pgm_clip.h - Persistent Grid Mapping over a store: the elevation clipmap on the GPU
 * (Livny, Kogan & El-Sana, seeds/001, section 4; the bookkeeping is the core's tp_pgm_clip_*).
 *
 * Level l of the store's elevation pyramid (the posts tp_pgm_pyramid_build would make of the
 * store's source grid, tp_core.h) is kept as a window of w x w posts centred on the eye, in
 * layer l of one R32F GL_TEXTURE_2D_ARRAY of w x w texels (post (i, j) at texel (i mod w,
 * j mod w)). Each frame the windows follow the eye: the posts a window gains (the L- or
 * F-shaped strips of tp_pgm_clip_update) are read from the store's nodes (the coarsest node
 * holding each post, tp_pgm_store_post; decoded nodes kept in a small cache) and uploaded with
 * glTexSubImage3D; nothing else is. GPU memory: levels x w x w x 4 bytes whatever the store's
 * size (levels grows by one per doubling of its side). Posts without a height (nodata) are
 * TP_PGM_CLIP_VOID, which the shader treats as off the terrain. Synchronous by default (the
 * reads happen in tp_pgm_clipmap_update, on the render thread); with tp_pgm_clipmap_set_async a
 * loader thread reads them and a later update uploads them together with the windows' new
 * origins, so the windows the shader reads always hold their own posts (meanwhile it reads
 * coarser levels where the eye has left a window).
 */
#ifndef TP_APP_PGM_CLIP_H
#define TP_APP_PGM_CLIP_H

#include "tp_io.h"

#include <stddef.h>

#define TP_PGM_CLIP_DEFAULT_WINDOW 512
#define TP_PGM_CLIP_VOID (-3.0e38f) /* a texel without a height; the shader tests z < -1e30 */

typedef struct tp_pgm_clipmap tp_pgm_clipmap;

typedef struct tp_pgm_clip_stats {
    double fill_ms;    /* reading and decoding the gained posts (node reads included) */
    double upload_ms;  /* glTexSubImage3D of them */
    size_t posts;      /* posts written this update */
    size_t node_reads; /* nodes read from the store (cache misses) */
    size_t buffer_posts; /* the most posts held in CPU memory at once: on the render thread a
                            band of rows at a time, at most 2^18 (1 MiB) whatever the window;
                            through the loader thread a whole move's */
} tp_pgm_clip_stats;

/* Creates the clipmap of an open store (borrowed: it must outlive the clipmap) for the current
 * GL context: window w (a power of two, 16 .. 8192; 0: TP_PGM_CLIP_DEFAULT_WINDOW), the texture
 * array allocated, nothing filled yet (the first tp_pgm_clipmap_update fills every window, on
 * the render thread, through a buffer of 1 MiB: tp_pgm_clip_stats.buffer_posts).
 * NULL with a message in err for a bad w, a window smaller than the coarsest level
 * (tp_pgm_clip_min_window: a side of more than (w - 1) 2^23 + 1 posts), a window larger
 * than GL_MAX_TEXTURE_SIZE, too many levels for GL_MAX_ARRAY_TEXTURE_LAYERS, a store without a
 * drawn height, out of memory, or a GL error allocating the texture array (errors left by
 * earlier calls are cleared first). */
tp_pgm_clipmap* tp_pgm_clipmap_create(const tp_store* store, int w, tp_error* err);
void tp_pgm_clipmap_destroy(tp_pgm_clipmap* c); /* accepts NULL */

/* The pyramid's shape for tp_pgm_frame_setup and the shader: levels, width, height,
 * geotransform, min_m and max_m (from the roots' area ranges) as tp_pgm_pyramid_build would give
 * them for the store's grid; z[] are NULL (the heights are only in the windows). */
const tp_pgm_pyramid* tp_pgm_clipmap_shape(const tp_pgm_clipmap* c);

/* Moves every level's window to centre on level-0 grid coordinates (x, y) (the eye's ground
 * position; any value: the windows stay on the terrain, tp_pgm_clip_origin) and reads and
 * uploads the posts they gain (async: uploads the last move read, starts the next). Returns 1, or 0
 * with a message in err naming the store and the node when a node cannot be read (its posts are
 * then TP_PGM_CLIP_VOID: not drawn, and the window counts as filled). stats may be NULL. */
int tp_pgm_clipmap_update(tp_pgm_clipmap* c, double x, double y, tp_pgm_clip_stats* stats,
                          tp_error* err);

/* 1 once the windows hold their posts (a first fill done); 0 before, and after a first fill
 * that ran out of memory (draw nothing then: the texels are uninitialised). */
int tp_pgm_clipmap_filled(const tp_pgm_clipmap* c);

/* Starts the loader thread: from now on an update uploads what the loader has read since the
 * last one and hands it the next move (the first fill is still done at once: there is nothing
 * to draw before it). 1, or 0 with a message in err when no thread can be made (the clipmap stays
 * synchronous). */
int tp_pgm_clipmap_set_async(tp_pgm_clipmap* c, tp_error* err);
/* 1 while the loader has a move to read or to hand back (async only; else 0). */
int tp_pgm_clipmap_pending(const tp_pgm_clipmap* c);

/* The window size, each level's origin (origin[2 l], origin[2 l + 1]: level-l posts), the
 * texture array (layer l = level l) and its bytes. */
int tp_pgm_clipmap_window(const tp_pgm_clipmap* c);
void tp_pgm_clipmap_origins(const tp_pgm_clipmap* c, int* origin);
unsigned tp_pgm_clipmap_texture(const tp_pgm_clipmap* c);
size_t tp_pgm_clipmap_gpu_bytes(const tp_pgm_clipmap* c);
const tp_store* tp_pgm_clipmap_store(const tp_pgm_clipmap* c); /* the store it was made for */

/* The error of the surface drawn over the clipmap for frame f (tp_pgm_frame_setup on its shape)
 * seen by main, by the bench's definition (tp_pgm_measure_error_source; pgm_clip_error.c): the
 * drawn heights those the shader reads from the windows as they stand now (each level's posts
 * read from the store as the filler writes them, the level falling back to the first coarser
 * window holding the bilinear footprint, void posts voiding the vertex), compared with the
 * level-0 posts of tp_pgm_view_region(shape, main) read from the store's scale-0 nodes (posts
 * without a height are not compared). Call it after the draw it measures, before the next
 * update (the windows' origins are read now). No GL; reads the store on the calling thread
 * with its own cache of about 16 MiB of decoded nodes; memory besides: one band of the region
 * (its width x 2^n posts, 5 bytes each) and 25 bytes a grid vertex; time: every post of the
 * region (the whole store for a view reaching the horizon), so max_posts (0: no limit) bounds
 * it: of a larger region only every ceil(posts / max_posts)-th band of 2^n rows is compared
 * (out->post_share says what share of the region that was). TP_OK and *out; else *out zeroed
 * and a message in err: TP_ERR_IO (a node cannot be read; the store and node named),
 * TP_ERR_OUT_OF_MEMORY. */
tp_status tp_pgm_clipmap_measure(const tp_pgm_clipmap* c, const tp_pgm_frame* f,
                                 const tp_camera* main, size_t max_posts, tp_pgm_error* out,
                                 tp_error* err);

#endif
