/*
 * pyramid_view.h - what the viewer's imagery (imagery_view.h) and streamed light
 * (light_view.h) share: a pyramid (.tpi or .tpl, tp_imagery.h) opened for the store being
 * drawn, its kind and grid checked, as a clipmap's block source (imagery_cache.h), and each
 * frame's clipmap work (Blow's finest level from the cut's nodes, the update, what the
 * renderer samples). app/render/pyramid_view.c.
 */
#ifndef TP_APP_VIEW_PYRAMID_VIEW_H
#define TP_APP_VIEW_PYRAMID_VIEW_H

#include "clipmap.h"
#include "store_scene.h"
#include "tp_core.h"
#include "tp_imagery.h"

#include <stddef.h>

/* The pyramid beside a store: STORE with its .tpt replaced by ext (".tpi", ".tpl"), or ext
 * appended, when that file exists; else 0. */
int tp_view_pyramid_beside(const char* store_path, const char* ext, char* out, size_t cap);

/* Opens path for the store st and checks it: its kind (TP_IMAGERY_KIND_*) is kind, its grid the
 * store's (the same size, the source grid's or the fitted one, and geotransform). remake: the
 * command that makes one ("terrapatch imagery", "terrapatch light"), named in the message.
 * Returns the pyramid (close with tp_imagery_close) with its info in *info, or NULL after one
 * line on stderr naming the file (unreadable, damaged, another kind, "made for another grid
 * (1201x1201 posts from ...; the store's is ...)"). */
tp_imagery* tp_view_pyramid_open(const char* path, const tp_store_scene* st, int kind,
                                 const char* remake, tp_imagery_info* info);

/* The block source over an open pyramid (levels beyond TP_CLIP_MAX_LEVELS left out); reads are
 * tp_imagery_read_block (thread-safe), empty blocks from its table. im must outlive it. */
void tp_view_pyramid_source(tp_imagery* im, tp_block_source* out);

/* A clipmap drawn over a store's cut: the state kept from frame to frame. */
typedef struct tp_view_clip_state {
    int finest;   /* last frame's finest level (frame coherence); -1 at first */
} tp_view_clip_state;

/* Once a frame after the cut is selected: the finest level the cut's nodes need (their
 * distances from cam, heights times zscale as drawn; Blow), the clipmap's update (settle:
 * every window complete, for headless frames) and what the renderer is to sample into *out. */
void tp_view_clip_frame(tp_view_clip_state* s, tp_clipmap* m, const tp_store_scene* st,
                        const tp_cut* cut, double zscale, const tp_camera* cam, int settle,
                        tp_clipmap_stats* stats, tp_render_clip* out);

void tp_view_clip_state_free(tp_view_clip_state* s); /* s stays usable */

#endif /* TP_APP_VIEW_PYRAMID_VIEW_H */
