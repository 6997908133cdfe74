/*
 * view_shadows.h - which cast shadows `terrapatch view` draws with a sun (issue 15, part 2):
 * the day's light map streamed through a clipmap (light_view.h: --light FILE.tpl, or STORE.tpl
 * beside the store with --sun-date) while the sun's time lies in the file's day, PgUp/PgDn
 * then moving only its time; else (another date, or no light map) the shadows computed over a
 * window around the view (shadow_view.h), after one line on stderr saying why. --light without
 * --sun-date starts at the middle of the file's day. --no-cast-shadows: neither.
 * app/view/view_shadows.c.
 */
#ifndef TP_APP_VIEW_VIEW_SHADOWS_H
#define TP_APP_VIEW_VIEW_SHADOWS_H

#include "shadow_view.h"
#include "view.h"

/* After the georeference is taken: the sun (o->sun_when, or the light map's mid-day) put in
 * o->render, the light map opened (st: a store, else NULL), the ground of the window's
 * shadows made. shadow: the window's state, owned by the caller (run_view), used for the
 * fallback. TP_EXIT_OK, or a message on stderr and TP_EXIT_FAILURE (an unreadable or
 * mismatched light map, a sun that cannot be placed) / TP_EXIT_USAGE (--light on a DEM drawn
 * whole). */
int tp_view_shadows_open(tp_view_scene* v, view_options* o, const tp_store_scene* st,
                         tp_view_shadow* shadow);

/* Once a frame after the cut is selected, before drawing: the streamed light (its clipmap's
 * update and tau) or the window's shadows, as above, handed to r; out's light fields set. */
void tp_view_shadows_frame(tp_view_scene* v, tp_renderer* r, const tp_camera* cam,
                           const tp_render_settings* render, frame_result* out);

/* "shadows: streamed day map (tau 97.3 of 255)" / "shadows: computed window (1025 x 1025
 * posts around the view, 84 ms)" / "" for the HUD. */
void tp_view_shadows_text(const frame_result* f, char* out, size_t cap);

/* Closes the light map and frees the window's shadows (v's fields cleared). */
void tp_view_shadows_close(tp_view_scene* v, tp_view_shadow* shadow);

#endif /* TP_APP_VIEW_VIEW_SHADOWS_H */
