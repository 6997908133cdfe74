/*
 * light_view.h - the terrain's cast shadows over a whole day, streamed (issue 15, part 2): a
 * light map (.tpl, tp_imagery.h's TP_IMAGERY_KIND_LIGHT_TIMES: each post's lit intervals of
 * the day as (r1, s1, r2, s2), tp_core.h's light times) made for the store being drawn, on the
 * GPU through a clipmap (clipmap.h, the imagery's) and handed to the renderer each frame with
 * the sun's time as tau (tp_renderer_set_light): moving the time is one uniform, and the
 * shadows are those of the whole map, not of a window around the view (shadow_view.h, the
 * fallback for a time outside the file's day). app/render/light_view.c.
 */
#ifndef TP_APP_VIEW_LIGHT_VIEW_H
#define TP_APP_VIEW_LIGHT_VIEW_H

#include "clipmap.h"
#include "renderer.h"
#include "store_scene.h"
#include "tp_core.h"

#include <stddef.h>

typedef struct tp_view_light tp_view_light;

/* The light map beside a store: STORE with its .tpt replaced by .tpl (or .tpl appended) when
 * that file exists; else 0. */
int tp_view_light_beside(const char* store_path, char* out, size_t cap);

/* Opens path for the store st (a light map made for its grid) and creates its clipmap (o may
 * be NULL: the defaults; a current GL context is needed). One line on stderr naming the file
 * and 0 on failure: unreadable or damaged, an imagery pyramid, or made for another grid. */
int tp_view_light_open(const char* path, const tp_store_scene* st, const tp_clipmap_options* o,
                       tp_view_light** out);

/* The same over any block source of light times (tests: texels from tp_light_times_build in
 * memory): gt the geotransform of level 0's texels (the store's grid: a texel per post), the
 * day first_s .. last_s (Unix seconds, first < last). NULL with a message in err on
 * failure. */
tp_view_light* tp_view_light_create(const tp_block_source* src, const double gt[6], double first_s,
                                    double last_s, const tp_clipmap_options* o, tp_error* err);
void tp_view_light_close(tp_view_light* l); /* accepts NULL */

/* The file's day (Unix seconds) and the number of sun positions it was made from (0 when not
 * known: tp_view_light_create). */
void tp_view_light_day(const tp_view_light* l, double* first_s, double* last_s, int* maps);

/* 1 when unix_s lies in the day (tau 0 .. TP_LIGHT_TIMES_STEPS). */
int tp_view_light_covers(const tp_view_light* l, double unix_s);

/* Once a frame after the cut is selected: the clipmap's finest level for the cut (Blow), its
 * update (settle: every window complete, headless frames) and the renderer's light at
 * tau = tp_light_times_tau(first, last, unix_s). stats may be NULL. */
void tp_view_light_frame(tp_view_light* l, const tp_store_scene* st, const tp_cut* cut,
                         double zscale, tp_renderer* r, const tp_camera* cam, double unix_s,
                         int settle, tp_clipmap_stats* stats);

/* Prints a block read failure not reported yet (once each). */
void tp_view_light_report_failures(tp_view_light* l);

#endif /* TP_APP_VIEW_LIGHT_VIEW_H */
