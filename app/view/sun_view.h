/*
 * sun_view.h - the viewer's sun at a date and time (issue 15, part 2): `view --sun-date
 * YYYY-MM-DD --sun-time HH:MM[zone]` puts the hillshade's light where the sun is (libnova,
 * tp_sun.h) over the centre of the map, and [ / ] move the time (15 minutes; with Shift an
 * hour). The sun's true azimuth becomes a grid azimuth (less the meridian convergence at the
 * centre), its apparent elevation (refraction included) the light's; with the sun below the
 * horizon only the ambient term lights the ground. app/view/sun_view.c.
 */
#ifndef TP_APP_VIEW_SUN_VIEW_H
#define TP_APP_VIEW_SUN_VIEW_H

#include "renderer.h"
#include "sun_time.h"
#include "tp_io.h"
#include "tp_sun.h"

#include <stddef.h>

typedef struct tp_view_sun {
    int on;                  /* a date and time were given */
    double unix_s;           /* the time shown, UTC */
    int zone_offset_s;       /* the zone it was given in (shown in it) */
    double lat_deg, lon_deg; /* where the sun is computed: the map's centre */
    double convergence_deg;  /* bearing of grid north, clockwise from true north, there */
    tp_sun_pos pos;
} tp_view_sun;

/* The sun at t over the render-CRS point (e, n) of georeference g. 1, or 0 with one line in
 * err (a grid without geographic coordinates: local metres; a time outside libnova's range). */
int tp_view_sun_init(tp_view_sun* s, const tp_sun_time* t, const tp_georef* g, double e, double n,
                     tp_error* err);

/* Moves the time by seconds (the position recomputed) and puts the light in rs. */
void tp_view_sun_step(tp_view_sun* s, double seconds, tp_render_settings* rs);

/* Puts the light of the current time in rs: grid azimuth, apparent elevation (below the
 * horizon: the light's elevation is the sun's, and the shader's max(dot, 0) leaves the ambient
 * term only). */
void tp_view_sun_apply(const tp_view_sun* s, tp_render_settings* rs);

/* "sun 2026-06-21 14:30:00 +02:00: azimuth 231.4 deg (true), elevation 52.3 deg" */
void tp_view_sun_text(const tp_view_sun* s, char* out, size_t cap);

#endif /* TP_APP_VIEW_SUN_VIEW_H */
