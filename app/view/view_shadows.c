/* view_shadows.c - the viewer's cast shadows: streamed or computed (see view_shadows.h). */
#define _POSIX_C_SOURCE 200809L
#include "view_shadows.h"

#include "cli.h"
#include "ground.h"
#include "light_view.h"
#include "pick.h"
#include "sun_time.h"

#include <stdio.h>
#include <string.h>

int tp_view_shadows_open(tp_view_scene* v, view_options* o, const tp_store_scene* st,
                         tp_view_shadow* shadow)
{
    v->sun = &o->sun;
    v->shadow = shadow;
    if (o->light && !st) {
        tp_cli_error("--light shadows stores; %s is drawn whole", v->path);
        return TP_EXIT_USAGE;
    }
    if (!o->sun_date && (!o->light || o->preview)) /* a light map is made for the store */
        return TP_EXIT_OK;
    char beside[4096];
    const char* path = o->preview ? NULL : o->light;
    if (!path && st && !o->no_cast_shadows && tp_view_light_beside(st->path, beside, sizeof beside))
        path = beside;
    if (path) {
        tp_clipmap_options co = {.clip_blocks = o->clip_blocks};
        if (!tp_view_light_open(path, st, &co, &v->light))
            return TP_EXIT_FAILURE;
        v->light_settle = o->headless;
    }
    tp_sun_time when = o->sun_when;
    if (!o->sun_date) { /* --light alone: the middle of its day, shown in UTC */
        double t0, t1;
        tp_view_light_day(v->light, &t0, &t1, NULL);
        memset(&when, 0, sizeof when);
        when.unix_s = 0.5 * (t0 + t1);
    }
    if (o->no_cast_shadows) { /* the light map gave the time, no more */
        tp_view_light_close(v->light);
        v->light = NULL;
    }
    double e = v->gt[0] + 0.5 * v->src_width * v->gt[1];
    double n = v->gt[3] + 0.5 * v->src_height * v->gt[5];
    tp_error err = {{0}};
    if (!tp_view_sun_init(&o->sun, &when, v->georef, e, n, &err)) {
        tp_cli_error("%s: %s", o->sun_date ? "--sun-date" : "--light", err.message);
        return TP_EXIT_FAILURE;
    }
    tp_view_sun_apply(&o->sun, &o->render);
    tp_error gerr;
    if (st && !o->no_cast_shadows && !o->ground &&
        tp_ground_create(st, NULL, &o->ground, &gerr) != TP_OK)
        tp_cli_error("no cast shadows: %s", gerr.message);
    v->shadow_ground = o->no_cast_shadows ? NULL : o->ground;
    char line[256];
    tp_view_sun_text(&o->sun, line, sizeof line);
    if (!o->preview) /* said once, by the store's run */
        tp_cli_note("%s", line);
    if (v->light) {
        double t0, t1;
        int maps;
        char a[64], b[64];
        tp_view_light_day(v->light, &t0, &t1, &maps);
        tp_sun_time_format(t0, o->sun.zone_offset_s, a, sizeof a);
        tp_sun_time_format(t1, o->sun.zone_offset_s, b, sizeof b);
        tp_cli_note("cast shadows from the day's light map %s (%s .. %s, "
                    "%d sun positions)",
                    path, a, b, maps);
    }
    return TP_EXIT_OK;
}

/* One line when the sun's time leaves the light map's day (and when it comes back). */
static void say_outside(tp_view_scene* v, int outside)
{
    if (outside == v->light_outside)
        return;
    v->light_outside = outside;
    double t0, t1;
    char now[64], a[64], b[64];
    tp_view_light_day(v->light, &t0, &t1, NULL);
    tp_sun_time_format(v->sun->unix_s, v->sun->zone_offset_s, now, sizeof now);
    tp_sun_time_format(t0, v->sun->zone_offset_s, a, sizeof a);
    tp_sun_time_format(t1, v->sun->zone_offset_s, b, sizeof b);
    if (outside)
        tp_cli_note("%s lies outside the light map's day (%s .. %s): cast "
                    "shadows computed over the %d x %d posts around the view instead",
                    now, a, b, TP_VIEW_SHADOW_POSTS, TP_VIEW_SHADOW_POSTS);
    else
        tp_cli_note("%s lies in the light map's day: cast shadows "
                    "streamed again",
                    now);
}

void tp_view_shadows_frame(tp_view_scene* v, tp_renderer* r, const tp_camera* cam,
                           const tp_render_settings* render, frame_result* out)
{
    out->light_source = TP_VIEW_LIGHT_NONE;
    int sun = v->sun && v->sun->on;
    if (v->light && sun) {
        int inside = tp_view_light_covers(v->light, v->sun->unix_s);
        say_outside(v, !inside);
        if (inside) {
            tp_view_light_frame(v->light, v->store, v->cut, render->exaggeration, r, cam,
                                v->sun->unix_s, v->light_settle, &out->light_clip);
            tp_view_light_report_failures(v->light);
            double t0, t1;
            tp_view_light_day(v->light, &t0, &t1, NULL);
            out->light_source = TP_VIEW_LIGHT_STREAMED;
            out->light_tau = tp_light_times_tau(t0, t1, v->sun->unix_s);
            return;
        }
    }
    tp_renderer_set_light(r, NULL, 0);
    if (!v->shadow_ground)
        return;
    /* cast shadows around the point looked at */
    double p[3], x, y;
    if (!tp_view_pick_centre(v, cam, p))
        p[0] = cam->position[0], p[1] = cam->position[1];
    tp_view_scene_world_to_grid(v, p[0], p[1], &x, &y);
    tp_error err = {{0}};
    if (!tp_view_shadow_update(v->shadow, v->shadow_ground, render, x, y, r, &err)) {
        tp_cli_error("%s", err.message);
        return;
    }
    out->light_source = TP_VIEW_LIGHT_WINDOW;
    out->shadow_ms = v->shadow->compute_ms;
    out->shadow_posts = v->shadow->w;
}

void tp_view_shadows_text(const frame_result* f, char* out, size_t cap)
{
    if (f->light_source == TP_VIEW_LIGHT_STREAMED)
        snprintf(out, cap, "shadows: streamed day map (tau %.1f of %d)", f->light_tau,
                 TP_LIGHT_TIMES_STEPS);
    else if (f->light_source == TP_VIEW_LIGHT_WINDOW)
        snprintf(out, cap, "shadows: computed window (%d x %d posts around the view, %.0f ms)",
                 f->shadow_posts, f->shadow_posts, f->shadow_ms);
    else
        snprintf(out, cap, "%s", "");
}

void tp_view_shadows_close(tp_view_scene* v, tp_view_shadow* shadow)
{
    tp_view_light_close(v->light);
    v->light = NULL;
    tp_view_shadow_free(shadow);
    v->shadow = NULL;
    v->shadow_ground = NULL;
    v->sun = NULL;
}
