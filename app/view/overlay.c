/* overlay.c - the overlay's layout and drawing (see overlay.h). */
#include "overlay.h"

#include "hud_text.h"
#include "pick.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
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

/* Projects ground point p (E, N, true height) to pixels and depth (x, y, z); 0 behind the
 * eye. Without a depth range the depth is the nearest (drawn over everything). */
static int project_draped(const tp_camera* cam, const tp_overlay* ov, double zs,
                          const double p[3], float out[3])
{
    double q[3] = {p[0], p[1], p[2] * zs}, px[2], depth;
    if (p[2] != p[2] || !tp_camera_project(cam, q, px, &depth))
        return 0;
    out[0] = (float)px[0];
    out[1] = (float)px[1];
    out[2] = ov->far_m > 0 ? tp_hud_depth(depth, ov->near_m, ov->far_m) : -1.0f;
    return 1;
}

#define RUN_MAX 4096

/* Draws the polyline through count ground points (enh triples), broken where a point is
 * behind the eye, in runs of at most RUN_MAX points. */
static void draped_line(tp_hud* hud, const tp_camera* cam, const tp_overlay* ov, double zs,
                        const double* enh, size_t count, float width, const unsigned char rgba[4])
{
    static float xyz[3 * RUN_MAX];
    int w = cam->viewport_w_px, h = cam->viewport_h_px, n = 0;
    for (size_t i = 0; i < count; i++) {
        const int keep = project_draped(cam, ov, zs, enh + 3 * i, xyz + 3 * n);
        n += keep;
        if (keep && n < RUN_MAX && i + 1 < count)
            continue;
        if (n >= 2)
            tp_hud_polyline_depth(hud, w, h, xyz, n, width, rgba);
        n = 0;
        if (keep && i + 1 < count) { /* full: the next run starts where this one ended */
            memmove(xyz, xyz + 3 * (RUN_MAX - 1), sizeof(float) * 3);
            n = 1;
        }
    }
}

/* The line of sight's ground track, green where a target there is seen and red where hidden,
 * on a dark outline, and the obstruction's "X". */
static void los_track(tp_hud* hud, layout* l, const tp_view_scene* v, const tp_camera* cam,
                      const tp_overlay* ov, float s)
{
    const tp_overlay_los* los = ov->los;
    const unsigned char green[4] = {40, 220, 60, 255}, red[4] = {235, 40, 30, 255},
                        dark[4] = {0, 0, 0, 200};
    const double zs = tp_view_scene_vertical_scale(v);
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    draped_line(hud, cam, ov, zs, los->enh, los->count, 5.0f * s, dark);
    /* each colour over the segments that start at a point of its flag (and the next point) */
    for (size_t i = 0; i + 1 < los->count; i++) {
        size_t j = i;
        while (j + 1 < los->count && (los->seen[j + 1] != 0) == (los->seen[i] != 0))
            j++;
        size_t end = j + 1 < los->count ? j + 1 : j; /* through the first of the next run */
        draped_line(hud, cam, ov, zs, los->enh + 3 * i, end - i + 1, 3.0f * s,
                    los->seen[i] ? green : red);
        i = j;
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
 * (measured at the observer), hidden behind nearer terrain, the observer marked "O". */
static void viewshed_tint(tp_hud* hud, layout* l, const tp_view_scene* v, const tp_camera* cam,
                          const tp_overlay* ov, float s)
{
    static float xyz[3 * 20000];
    const tp_overlay_viewshed* vs = ov->viewshed;
    const double zs = tp_view_scene_vertical_scale(v);
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    const double* o = vs->observer_enh;
    double a[3] = {o[0], o[1], o[2] * zs}, b[3] = {o[0] + vs->spacing_m, o[1], o[2] * zs}, pa[2],
           pb[2];
    float side = 3.0f;
    if (tp_camera_project(cam, a, pa, NULL) && tp_camera_project(cam, b, pb, NULL))
        side = (float)fmin(fmax(hypot(pb[0] - pa[0], pb[1] - pa[1]), 2.0), 24.0);
    const unsigned char tint[4] = {220, 30, 30, 120};
    const int depth = ov->far_m > 0;
    int n = 0;
    for (size_t i = 0; i < vs->count; i++) {
        float* p = xyz + 3 * n;
        if (!project_draped(cam, ov, zs, vs->enh + 3 * i, p) || p[0] < -side || p[1] < -side ||
            p[0] > w + side || p[1] > h + side)
            continue;
        if (++n == 20000) {
            tp_hud_dots(hud, w, h, xyz, n, side, tint, depth);
            n = 0;
        }
    }
    tp_hud_dots(hud, w, h, xyz, n, side, tint, depth);
    if (tp_camera_project(cam, a, pa, NULL) && pa[0] >= 0 && pa[1] >= 0 && pa[0] < w && pa[1] < h) {
        float x0 = (float)pa[0] - 2.5f * s, y0 = (float)pa[1] - 3.5f * s;
        tp_hud_text(hud, w, h, x0, y0, s, "O");
        tp_hud_text(hud, w, h, x0 + 8 * s, y0 - 10 * s, s, "observer");
        occupy(l, x0 - 2, y0 - 12 * s, x0 + 60 * s, y0 + 9 * s);
    }
}

/* Text at pixel (x, y) (its top-left corner a little right of and above the point) where it
 * covers nothing drawn already. */
static void label_at(tp_hud* hud, layout* l, int w, int h, double x, double y, float s,
                     const char* text)
{
    float tw, th, x0 = (float)x + 5 * s, y0 = (float)y - 12 * s;
    tp_hud_measure(text, &tw, &th);
    float x1 = x0 + tw * s, y1 = y0 + th * s;
    if (x0 < 0 || y0 < 0 || x1 > w || y1 > h || !is_free(l, x0 - 3, y0 - 2, x1 + 3, y1 + 2))
        return;
    tp_hud_text(hud, w, h, x0, y0, s, text);
    occupy(l, x0 - 3, y0 - 2, x1 + 3, y1 + 2);
}

/* Features draped on the ground: lines and rings, index contours thicker and labelled with
 * their elevation at the middle of the part, points as dots with their names. */
static void drape_features(tp_hud* hud, layout* l, const tp_view_scene* v, const tp_camera* cam,
                           const tp_overlay* ov, const tp_overlay_drape* od, float s)
{
    const tp_drape* d = od->drape;
    const double zs = tp_view_scene_vertical_scale(v);
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    for (size_t i = 0; i < d->part_count; i++) {
        const tp_drape_part* p = &d->parts[i];
        float width = od->width_px * s * (p->index ? 2.5f : 1.0f);
        draped_line(hud, cam, ov, zs, d->enh + 3 * p->first, p->count, width, od->rgba);
    }
    if (od->label_values)
        for (size_t i = 0; i < d->part_count; i++) {
            const tp_drape_part* p = &d->parts[i];
            float px[3];
            if (!p->index || p->value != p->value ||
                !project_draped(cam, ov, zs, d->enh + 3 * (p->first + p->count / 2), px) ||
                px[0] < 0 || px[1] < 0 || px[0] >= w || px[1] >= h)
                continue;
            char text[32];
            snprintf(text, sizeof text, "%.0f", p->value);
            label_at(hud, l, w, h, px[0], px[1], s, text);
        }
    if (d->point_count) {
        float* xyz = malloc(sizeof(float) * 3 * d->point_count);
        int n = 0;
        for (size_t i = 0; xyz && i < d->point_count; i++)
            if (project_draped(cam, ov, zs, d->points[i].enh, xyz + 3 * n)) {
                const float* q = xyz + 3 * n++;
                if (d->points[i].name && q[0] >= 0 && q[1] >= 0 && q[0] < w && q[1] < h)
                    label_at(hud, l, w, h, q[0], q[1], s, d->points[i].name);
            }
        const unsigned char dark[4] = {0, 0, 0, 220};
        for (int k = 0; k < n; k += 20000) {
            int m = n - k < 20000 ? n - k : 20000;
            tp_hud_dots(hud, w, h, xyz + 3 * k, m, 9.0f * s, dark, ov->far_m > 0);
            tp_hud_dots(hud, w, h, xyz + 3 * k, m, 6.0f * s, od->rgba, ov->far_m > 0);
        }
        free(xyz);
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
    for (size_t i = 0; i < ov->drape_count; i++)
        drape_features(hud, &l, v, cam, ov, &ov->drapes[i], s);
    if (ov->viewshed && ov->viewshed->count)
        viewshed_tint(hud, &l, v, cam, ov, s);
    if (ov->los && ov->los->count > 1)
        los_track(hud, &l, v, cam, ov, s);
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
