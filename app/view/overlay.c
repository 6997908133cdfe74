/* overlay.c - the overlay's layout and drawing (see overlay.h). */
#include "overlay.h"

#include "hud_text.h"
#include "pick.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#define MAX_RECTS 160

typedef struct layout {
    float r[MAX_RECTS][4]; /* x0, y0, x1, y1 of what is drawn already */
    int n;
} layout;

static void occupy(layout* l, float x0, float y0, float x1, float y1)
{
    if (l->n < MAX_RECTS) {
        float* r = l->r[l->n++];
        r[0] = x0, r[1] = y0, r[2] = x1, r[3] = y1;
    }
}

static int is_free(const layout* l, float x0, float y0, float x1, float y1)
{
    for (int i = 0; i < l->n; i++)
        if (x0 < l->r[i][2] && x1 > l->r[i][0] && y0 < l->r[i][3] && y1 > l->r[i][1])
            return 0;
    return 1;
}

/* Draws text at (x, y), wrapped to max_w pixels, with the lines that do not fit in max_h
 * pixels left out, and marks its box taken; returns the box's height. */
static float block(tp_hud* hud, layout* l, int w, int h, float x, float y, float max_w,
                   float max_h, float s, const char* text)
{
    char wrapped[4096];
    tp_hud_wrap(text, max_w / s, wrapped, sizeof wrapped);
    float tw, th;
    tp_hud_measure(wrapped, &tw, &th);
    while (th * s > max_h) {
        char* last = strrchr(wrapped, '\n');
        if (!last)
            return 0; /* not even one line fits */
        *last = '\0';
        tp_hud_measure(wrapped, &tw, &th);
    }
    tp_hud_text(hud, w, h, x, y, s, wrapped);
    occupy(l, x - 2, y - 2, x + tw * s + 2, y + th * s + 2);
    return th * s;
}

float tp_overlay_scale(int w, int h)
{
    return w >= 1000 && h >= 500 ? 2.0f : 1.0f;
}

/* Labels the grid intersections around the point the camera looks at with their grid values
 * (kilometres of easting and northing, as read off a map), where they cover nothing else. */
static void grid_labels(tp_hud* hud, layout* l, const tp_view_scene* v, const tp_camera* cam,
                        double spacing, float scale)
{
    double g[3];
    if (spacing <= 0 || !tp_view_pick_centre(v, cam, g))
        return;
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    double zs = tp_view_scene_vertical_scale(v);
    double e0 = floor(g[0] / spacing) * spacing, n0 = floor(g[1] / spacing) * spacing;
    /* kilometres with as many decimals as the spacing needs (1500 m: 4501.5, 250 m: 5023.25) */
    int decimals = 0;
    while (decimals < 3 && fmod(spacing, 1000 / pow(10, decimals)) != 0)
        decimals++;
    for (int j = -4; j <= 5; j++)
        for (int i = -4; i <= 5; i++) {
            double p[3] = {e0 + i * spacing, n0 + j * spacing, 0}, x, y, px[2];
            tp_view_scene_world_to_grid(v, p[0], p[1], &x, &y);
            p[2] = tp_view_scene_drawn_height(v, x, y) * zs;
            if (isnan(p[2]) || !tp_camera_project(cam, p, px, NULL) || px[0] < 0 || px[1] < 0 ||
                px[0] >= w || px[1] >= h)
                continue;
            char text[64];
            snprintf(text, sizeof text, "%.*fE %.*fN", decimals, p[0] / 1000, decimals,
                     p[1] / 1000);
            float tw, th, x0 = (float)px[0] + 3, y0 = (float)px[1] + 3;
            tp_hud_measure(text, &tw, &th);
            float x1 = x0 + tw * scale, y1 = y0 + th * scale;
            if (x1 > w || y1 > h || !is_free(l, x0 - 4, y0 - 2, x1 + 4, y1 + 2))
                continue;
            tp_hud_text(hud, w, h, x0, y0, scale, text);
            occupy(l, x0 - 4, y0 - 2, x1 + 4, y1 + 2);
        }
}

/* North arrow and scale bar at the bottom right, measured at the ground point the camera
 * looks at: "N" sits where grid north points on screen, the bar spans a round distance. */
static void compass_and_scale(tp_hud* hud, layout* l, const tp_view_scene* v,
                              const tp_camera* cam, float bottom, float scale)
{
    double g[3], c[2], pn[2], pe[2];
    if (!tp_view_pick_centre(v, cam, g))
        return;
    g[2] *= tp_view_scene_vertical_scale(v); /* drawn space */
    if (!tp_camera_project(cam, g, c, NULL))
        return;
    double north[3] = {g[0], g[1] + 100, g[2]}, east[3] = {g[0] + 100, g[1], g[2]};
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    float cx = (float)w - 70 * scale, cy = bottom - 60 * scale;
    occupy(l, cx - 45 * scale, cy - 45 * scale, (float)w, bottom);
    if (tp_camera_project(cam, north, pn, NULL)) {
        double vx = pn[0] - c[0], vy = pn[1] - c[1], len = hypot(vx, vy);
        if (len > 1e-6) {
            tp_hud_text(hud, w, h, cx - 2 * scale, cy - 3 * scale, scale, "+");
            for (int i = 1; i <= 4; i++) /* a dotted shaft toward north */
                tp_hud_text(hud, w, h, cx + (float)(vx / len * 7 * i) * scale - 1 * scale,
                            cy + (float)(vy / len * 7 * i) * scale - 4 * scale, scale, ".");
            tp_hud_text(hud, w, h, cx + (float)(vx / len * 36) * scale - 2 * scale,
                        cy + (float)(vy / len * 36) * scale - 3 * scale, scale, "N");
        }
    }
    if (tp_camera_project(cam, east, pe, NULL)) {
        double m_per_px = 100 / fmax(hypot(pe[0] - c[0], pe[1] - c[1]), 1e-6);
        /* a round length about 120 px long: 1, 2 or 5 times a power of ten */
        double want = 120 * scale * m_per_px, p10 = pow(10, floor(log10(want))), len = p10;
        if (5 * p10 <= want)
            len = 5 * p10;
        else if (2 * p10 <= want)
            len = 2 * p10;
        float fw, fh;
        tp_hud_measure("-", &fw, &fh);
        int chars = (int)(len / m_per_px / (fw * scale) + 0.5);
        char bar[160];
        int at = snprintf(bar, sizeof bar, "|");
        for (int i = 0; i < chars && at < (int)sizeof bar - 40; i++)
            bar[at++] = '-';
        if (len >= 1000)
            snprintf(bar + at, sizeof bar - at, "| %g km", len / 1000);
        else
            snprintf(bar + at, sizeof bar - at, "| %g m", len);
        float bw, bh;
        tp_hud_measure(bar, &bw, &bh);
        float x = (float)w - bw * scale - 130 * scale, y = bottom - 20 * scale;
        if (x > 0) {
            tp_hud_text(hud, w, h, x, y, scale, bar);
            occupy(l, x - 2, y - 2, x + bw * scale, bottom);
        }
    }
}

/* The line of sight's ground track, a segment per pair of samples coloured by the nearer
 * one's flag, and the obstruction's "X". */
static void los_track(tp_hud* hud, layout* l, const tp_view_scene* v, const tp_camera* cam,
                      const tp_overlay_los* los, float s)
{
    const unsigned char green[4] = {40, 220, 60, 255}, red[4] = {235, 40, 30, 255},
                        dark[4] = {0, 0, 0, 200};
    const double zs = tp_view_scene_vertical_scale(v);
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    double prev[2];
    int have_prev = 0;
    for (int pass = 0; pass < 2; pass++) { /* a dark outline under the colours */
        have_prev = 0;
        for (size_t i = 0; i < los->count; i++) {
            const double* p = los->enh + 3 * i;
            double q[3] = {p[0], p[1], p[2] * zs}, px[2];
            if (isnan(p[2]) || !tp_camera_project(cam, q, px, NULL)) {
                have_prev = 0;
                continue;
            }
            if (have_prev)
                tp_hud_line(hud, w, h, (float)prev[0], (float)prev[1], (float)px[0],
                            (float)px[1], pass == 0 ? 5.0f * s : 3.0f * s,
                            pass == 0 ? dark : los->seen[i] ? green : red);
            prev[0] = px[0];
            prev[1] = px[1];
            have_prev = 1;
        }
    }
    if (los->has_obstruction) {
        const double* p = los->obstruction_enh;
        double q[3] = {p[0], p[1], p[2] * zs}, px[2];
        if (tp_camera_project(cam, q, px, NULL) && px[0] >= 0 && px[1] >= 0 && px[0] < w &&
            px[1] < h) {
            float x0 = (float)px[0] - 2.5f * s, y0 = (float)px[1] - 3.5f * s;
            tp_hud_text(hud, w, h, x0, y0, s, "X");
            tp_hud_text(hud, w, h, x0 + 8 * s, y0 - 10 * s, s, "obstruction");
            occupy(l, x0 - 2, y0 - 12 * s, x0 + 70 * s, y0 + 9 * s);
        }
    }
}

/* The viewshed's hidden posts as translucent red squares the size of their spacing on screen
 * (measured at the observer), the observer marked "O". */
static void viewshed_tint(tp_hud* hud, layout* l, const tp_view_scene* v, const tp_camera* cam,
                          const tp_overlay_viewshed* vs, float s)
{
    static float xy[2 * 20000];
    const double zs = tp_view_scene_vertical_scale(v);
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    const double* o = vs->observer_enh;
    double a[3] = {o[0], o[1], o[2] * zs}, b[3] = {o[0] + vs->spacing_m, o[1], o[2] * zs}, pa[2],
           pb[2];
    float side = 3.0f;
    if (tp_camera_project(cam, a, pa, NULL) && tp_camera_project(cam, b, pb, NULL))
        side = (float)fmin(fmax(hypot(pb[0] - pa[0], pb[1] - pa[1]), 2.0), 24.0);
    const unsigned char tint[4] = {220, 30, 30, 120};
    int n = 0;
    for (size_t i = 0; i < vs->count; i++) {
        const double* p = vs->enh + 3 * i;
        double q[3] = {p[0], p[1], p[2] * zs}, px[2];
        if (!tp_camera_project(cam, q, px, NULL) || px[0] < -side || px[1] < -side ||
            px[0] > w + side || px[1] > h + side)
            continue;
        xy[2 * n] = (float)px[0];
        xy[2 * n + 1] = (float)px[1];
        if (++n == 20000) {
            tp_hud_dots(hud, w, h, xy, n, side, tint);
            n = 0;
        }
    }
    tp_hud_dots(hud, w, h, xy, n, side, tint);
    if (tp_camera_project(cam, a, pa, NULL) && pa[0] >= 0 && pa[1] >= 0 && pa[0] < w && pa[1] < h) {
        float x0 = (float)pa[0] - 2.5f * s, y0 = (float)pa[1] - 3.5f * s;
        tp_hud_text(hud, w, h, x0, y0, s, "O");
        tp_hud_text(hud, w, h, x0 + 8 * s, y0 - 10 * s, s, "observer");
        occupy(l, x0 - 2, y0 - 12 * s, x0 + 60 * s, y0 + 9 * s);
    }
}

void tp_view_overlay_draw(tp_hud* hud, const tp_view_scene* v, const tp_camera* cam,
                          const tp_overlay* ov)
{
    if (!hud)
        return;
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    float s = tp_overlay_scale(w, h);
    layout l = {0};
    /* what must be seen first (measure line at the bottom, north arrow and scale bar above
     * it, the HUD), then grid labels where room is left */
    float bottom = (float)h;
    if (ov->measure_line && ov->measure_line[0]) {
        char wrapped[1024];
        float tw, th;
        tp_hud_wrap(ov->measure_line, (w - 16) / s, wrapped, sizeof wrapped);
        tp_hud_measure(wrapped, &tw, &th);
        bottom = (float)h - 10 * s - th * s;
        block(hud, &l, w, h, 10, bottom, w - 16, th * s, s, ov->measure_line);
        bottom -= 4 * s;
    }
    if (ov->viewshed && ov->viewshed->count)
        viewshed_tint(hud, &l, v, cam, ov->viewshed, s);
    if (ov->los && ov->los->count > 1)
        los_track(hud, &l, v, cam, ov->los, s);
    if (ov->has_mark) {
        /* drawn space: heights times the exaggeration, as the terrain is drawn */
        double p[3] = {ov->mark_enh[0], ov->mark_enh[1],
                       ov->mark_enh[2] * tp_view_scene_vertical_scale(v)},
               px[2];
        if (tp_camera_project(cam, p, px, NULL) && px[0] >= 0 && px[1] >= 0 && px[0] < w &&
            px[1] < h) {
            float x0 = (float)px[0] - 2.5f * s, y0 = (float)px[1] - 3.5f * s;
            tp_hud_text(hud, w, h, x0, y0, s, "+");
            occupy(&l, x0 - 2, y0 - 2, x0 + 7 * s, y0 + 9 * s);
        }
    }
    if (ov->hud_text) {
        compass_and_scale(hud, &l, v, cam, bottom, s);
        /* the HUD and the help end above the north arrow (about 105 px at scale 1) */
        float room = bottom - 105 * s - 10;
        float y = 10 + block(hud, &l, w, h, 10, 10, w - 16, room, s, ov->hud_text);
        if (ov->help_text)
            block(hud, &l, w, h, 10, y + 12 * s, w - 16, room - (y + 2 * s), s, ov->help_text);
    }
    if (ov->grid_m > 0)
        grid_labels(hud, &l, v, cam, ov->grid_m, s);
}
