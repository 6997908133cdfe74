/*
 * shadow_view.h - cast shadows in the viewer (issue 15, part 2): with a sun (sun_view.h), the
 * ground of a window of full-resolution posts around the point looked at (1025 x 1025 posts,
 * read through tp_ground) is shadowed by the core's sweep (tp_shadow_compute) for the sun's
 * grid azimuth and elevation, and the lit/shadowed mask handed to the renderer as a texture
 * over that window (tp_renderer_set_shadow): the direct sunlight of a shadowed fragment is
 * taken away, the ambient term stays. Recomputed when the sun moves (PgUp/PgDn) or the view
 * leaves the window's middle half; outside the window the ground is lit without cast shadows.
 * Only ground inside the window casts shadows into it. app/view/shadow_view.c.
 */
#ifndef TP_APP_VIEW_SHADOW_VIEW_H
#define TP_APP_VIEW_SHADOW_VIEW_H

#include "ground.h"
#include "renderer.h"
#include "sun_view.h"

#define TP_VIEW_SHADOW_POSTS 1025 /* the window's posts a side */

typedef struct tp_view_shadow {
    int x0, y0, w, h;          /* the window (grid posts); w = 0: none yet */
    double az_deg, el_deg;     /* the sun it was computed for */
    unsigned texture;          /* GL_R8, w x h */
    double compute_ms;         /* reading the posts and the sweep, last time */
    float* z;
    uint8_t* lit;
} tp_view_shadow;

/* Recomputes the shadows if the sun moved or (cx, cy) (grid coordinates of the point looked
 * at) left the window's middle half, and hands them to r. 1, or 0 with err (a read failed, out
 * of memory): the frame is then drawn without cast shadows. A GL context must be current. */
int tp_view_shadow_update(tp_view_shadow* s, tp_ground* g, const tp_render_settings* rs, double cx,
                          double cy, tp_renderer* r, tp_error* err);

void tp_view_shadow_free(tp_view_shadow* s); /* s stays usable (zeroed) */

#endif /* TP_APP_VIEW_SHADOW_VIEW_H */
