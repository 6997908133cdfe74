/* tp_clipmap.h - clip windows over an image pyramid and per-polygon texture levels (clipmap.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_CLIPMAP_H
#define TP_CLIPMAP_H

#include "tp_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Clip windows over an image pyramid (clipmap.c, issue 15; Luo & Duan, "Clipmap texture
 * streaming", sections 3.2-3.5) and per-polygon texture levels (Blow, "Terrain rendering at
 * high levels of detail", Part I)
 *
 * Each level l of a pyramid (level 0 finest, level l + 1 half as many texels a side) is cut into
 * square blocks of `block` texels. A clip region holds, per level, the s x s blocks of a window
 * (s even) in one texture layer of s * block texels a side: block (bx, by) lives in slot
 * (bx mod s, by mod s) of the layer, so moving the window by one block column reuses every slot
 * but that column's (a toroidal update: only newly covered blocks are uploaded). Coordinates
 * here are level texels (x east, y south, (0, 0) the level's top-left corner) and block indices
 * (int64: windows may lie partly outside the image).
 */
typedef struct tp_clip_window {
    int64_t bx0, by0; /* first block column and row; the window is [bx0, bx0 + s) x [by0, by0 + s) */
    int s;            /* blocks a side */
} tp_clip_window;

/* The window of s x s blocks (s even, 2..1024) whose centre is nearest the point (cx, cy)
 * (level texels): bx0 = round(cx / block - s / 2), so the point lies at least s / 2 - 1/2
 * blocks inside every edge. block >= 1. */
tp_clip_window tp_clip_window_centred(double cx, double cy, int block, int s);

/* Slot of block index b in a window of s blocks a side: b mod s, in 0..s-1 for any b. */
int tp_clip_slot(int64_t b, int s);

/* 1 if block (bx, by) is in the window. */
int tp_clip_window_contains(const tp_clip_window* w, int64_t bx, int64_t by);

/* Whether block (bx, by) of the window holds its own texels in its slot (loaded and uploaded). */
typedef int (*tp_clip_resident_fn)(void* user, int64_t bx, int64_t by);

/* The valid region of a level: the rectangle of blocks around the block holding (cx, cy), grown
 * one block row or column at a time (east, south, west, north in turn) while the whole new row
 * or column is inside the window and resident, so that a sampler restricted to it (less half a
 * texel at each edge for bilinear filtering) never reads a slot that holds another block's or
 * stale texels (Luo & Duan section 3.5). Writes rect = {bx0, by0, bx1, by1} (exclusive ends)
 * and returns 1; returns 0 (rect untouched) when the centre block is outside the window or not
 * resident. O(s^3) resident calls at most. */
int tp_clip_valid_rect(const tp_clip_window* w, double cx, double cy, int block,
                       tp_clip_resident_fn resident, void* user, int64_t rect[4]);

/* Blow's texture level: floor(log2(texels_per_pixel)) clamped to 0..max_level, read from the
 * IEEE 754 exponent bits of the float (no log2: one shift and one subtraction); a ratio below
 * 1, zero, negative or NaN gives 0, +infinity max_level. Exact for every float (a power of two
 * is its own level). */
int tp_texture_level(float texels_per_pixel, int max_level);

/* The level a patch needs: texels of level 0 per pixel at its nearest point, distance_m from the
 * eye (metres), for level-0 texels of texel_m metres and focal_px pixels per unit tangent
 * (tp_camera_frame.focal_px): distance / (focal * texel). Frame coherence (Blow): previous is
 * the level the patch used last frame (-1: none); the level goes finer at once but coarser only
 * once the ratio is 1/8 past the boundary, so a patch at a boundary does not flip every frame. */
int tp_patch_texture_level(double distance_m, double focal_px, double texel_m, int previous,
                           int max_level);

#ifdef __cplusplus
}
#endif
#endif /* TP_CLIPMAP_H */
