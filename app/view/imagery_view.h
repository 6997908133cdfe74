/*
 * imagery_view.h - the viewer's imagery (issue 15): an imagery pyramid (.tpi, tp_imagery.h)
 * made for the store being drawn, opened and handed to the renderer each frame through a
 * clipmap (clipmap.h). Checks that the pyramid belongs to the store's grid.
 */
#ifndef TP_APP_VIEW_IMAGERY_VIEW_H
#define TP_APP_VIEW_IMAGERY_VIEW_H

#include "clipmap.h"
#include "renderer.h"
#include "store_scene.h"
#include "tp_core.h"

#include <stddef.h>

typedef struct tp_view_imagery tp_view_imagery;

/* The pyramid beside a store: STORE with its .tpt replaced by .tpi (or .tpi appended) when that
 * file exists; else 0. */
int tp_view_imagery_beside(const char* store_path, char* out, size_t cap);

/* Opens path for the store st and creates the clipmap (a current GL context is needed). One
 * line on stderr naming the file and 0 on failure: unreadable or damaged, or made for another
 * grid ("made for another grid (1201x1201 posts from ...; the store's is ...)"). */
int tp_view_imagery_open(const char* path, const tp_store_scene* st, const tp_clipmap_options* o,
                         tp_view_imagery** out);
void tp_view_imagery_close(tp_view_imagery* im); /* accepts NULL */

/* Once a frame after the cut is selected and before drawing: the finest level the cut's nodes
 * need (Blow; heights times zscale as drawn), the clipmap's update (settle: every window
 * complete, for headless frames), the renderer's clip. */
void tp_view_imagery_frame(tp_view_imagery* im, const tp_store_scene* st, const tp_cut* cut,
                           double zscale, tp_renderer* r, const tp_camera* cam, int settle,
                           tp_clipmap_stats* stats);

/* Prints a block read failure not reported yet (once each). */
void tp_view_imagery_report_failures(tp_view_imagery* im);

#endif /* TP_APP_VIEW_IMAGERY_VIEW_H */
