/* sun_view.c - the viewer's sun at a date and time (see sun_view.h). */
#include "sun_view.h"

#include <math.h>
#include <stdio.h>

#define DEG (3.14159265358979323846 / 180.0)

static int locate(tp_view_sun* s, tp_error* err)
{
    return tp_sun_position(s->lat_deg, s->lon_deg, s->unix_s, &s->pos, err) == TP_OK;
}

int tp_view_sun_init(tp_view_sun* s, const tp_sun_time* t, const tp_georef* g, double e, double n,
                     tp_error* err)
{
    tp_view_sun z = {0};
    *s = z;
    if (!tp_georef_has_geo(g)) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "the map is in local metres (no CRS): no latitude and longitude for the "
                     "sun");
        return 0;
    }
    double e2, n2;
    if (tp_georef_proj_to_geo(g, e, n, &s->lat_deg, &s->lon_deg, err) != TP_OK ||
        tp_georef_geo_to_proj(g, s->lat_deg + (s->lat_deg < 89 ? 1e-3 : -1e-3), s->lon_deg, &e2,
                              &n2, err) != TP_OK)
        return 0;
    /* grid north is where a step north along the meridian goes on the grid */
    double sign = s->lat_deg < 89 ? 1 : -1;
    s->convergence_deg = -atan2(sign * (e2 - e), sign * (n2 - n)) / DEG;
    s->unix_s = t->unix_s;
    s->zone_offset_s = t->zone_offset_s;
    s->on = 1;
    return locate(s, err);
}

void tp_view_sun_apply(const tp_view_sun* s, tp_render_settings* rs)
{
    if (!s->on)
        return;
    double az = fmod(s->pos.azimuth_deg - s->convergence_deg + 720, 360);
    rs->sun_azimuth_deg = az;
    rs->sun_elevation_deg = s->pos.apparent_elevation_deg;
}

void tp_view_sun_step(tp_view_sun* s, double seconds, tp_render_settings* rs)
{
    if (!s->on)
        return;
    double before = s->unix_s;
    s->unix_s += seconds;
    if (!locate(s, NULL)) { /* outside libnova's years: stay */
        s->unix_s = before;
        locate(s, NULL);
    }
    tp_view_sun_apply(s, rs);
}

void tp_view_sun_text(const tp_view_sun* s, char* out, size_t cap)
{
    if (!s->on) {
        snprintf(out, cap, "%s", "");
        return;
    }
    char when[64];
    tp_sun_time_format(s->unix_s, s->zone_offset_s, when, sizeof when);
    snprintf(out, cap, "sun %s: azimuth %.1f deg (true), elevation %.1f deg%s", when,
             s->pos.azimuth_deg, s->pos.apparent_elevation_deg,
             s->pos.apparent_elevation_deg < 0 ? " (below the horizon)" : "");
}
