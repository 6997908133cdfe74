/*
 * imagery_view.h - the viewer's imagery (issue 15): an imagery pyramid (.tpi, tp_imagery.h)
 * made for the store being drawn, opened and handed to the renderer each frame through a
 * clipmap (clipmap.h) or, for comparison, Brodersen's texture per drawn node
 * (imagery_blocks.h; --imagery-mode blocks). Checks that the pyramid belongs to the store's
 * grid.
 */
#ifndef TP_APP_VIEW_IMAGERY_VIEW_H
#define TP_APP_VIEW_IMAGERY_VIEW_H

#include "clipmap.h"
#include "imagery_blocks.h"
#include "renderer.h"
#include "store_scene.h"
#include "tp_core.h"

#include <stddef.h>

typedef struct tp_view_imagery tp_view_imagery;

/* The pyramid beside a store: STORE with its .tpt replaced by .tpi (or .tpi appended) when that
 * file exists; else 0. */
int tp_view_imagery_beside(const char* store_path, char* out, size_t cap);

/* How the imagery reaches the GPU. */
typedef enum tp_imagery_mode {
    TP_IMAGERY_CLIPMAP = 0, /* clipmap.h (the default) */
    TP_IMAGERY_BLOCKS = 1   /* imagery_blocks.h: a texture per drawn node */
} tp_imagery_mode;

/* "clipmap" / "blocks" -> *mode; 0 for another name. */
int tp_imagery_mode_parse(const char* name, tp_imagery_mode* mode);

/* Opens path for the store st and creates the clipmap (o) or the blocks' texture array (the
 * defaults of tp_imagery_blocks_options; o->cache_bytes and o->no_loader apply) as mode says
 * (a current GL context is needed). One line on stderr naming the file and 0 on failure:
 * unreadable or damaged, or made for another grid ("made for another grid (1201x1201 posts
 * from ...; the store's is ...)"). */
int tp_view_imagery_open(const char* path, const tp_store_scene* st, tp_imagery_mode mode,
                         const tp_clipmap_options* o, tp_view_imagery** out);
void tp_view_imagery_close(tp_view_imagery* im); /* accepts NULL */

/* Once a frame after the cut is selected and before drawing: the finest level the cut's nodes
 * need (Blow; heights times zscale as drawn), the clipmap's update (settle: every window
 * complete, for headless frames), the renderer's clip. Blocks mode: each drawn node's texture
 * (settle: every node its own) handed to the renderer (tp_renderer_set_item_textures); stats
 * then count layers as uploads and nodes drawn with an ancestor's layer as missing. */
void tp_view_imagery_frame(tp_view_imagery* im, const tp_store_scene* st, const tp_cut* cut,
                           double zscale, tp_renderer* r, const tp_camera* cam, int settle,
                           tp_clipmap_stats* stats);

/* Prints a block read failure not reported yet (once each). */
void tp_view_imagery_report_failures(tp_view_imagery* im);

#endif /* TP_APP_VIEW_IMAGERY_VIEW_H */
