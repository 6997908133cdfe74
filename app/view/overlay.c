/* overlay.c - the overlay's layout and drawing (see overlay.h). */
#include "overlay.h"

#include "hud_text.h"
#include "map_grid.h"
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

/* The on-screen size of the grid cell at intersection p (E, N, true height): the shorter of its
 * two sides from p, in pixels (0 when a corner is behind the eye). Far cells are small: their
 * labels would cover the lines and each other. */
static double cell_px(const tp_view_scene* v, const tp_camera* cam, const double p[3],
                      double spacing)
{
    double zs = tp_view_scene_vertical_scale(v), a[2], b[2], c[2];
    double q0[3] = {p[0], p[1], p[2] * zs}, q1[3] = {p[0] + spacing, p[1], p[2] * zs},
           q2[3] = {p[0], p[1] + spacing, p[2] * zs};
    if (!tp_camera_project(cam, q0, a, NULL) || !tp_camera_project(cam, q1, b, NULL) ||
        !tp_camera_project(cam, q2, c, NULL))
        return 0;
    return fmin(hypot(b[0] - a[0], b[1] - a[1]), hypot(c[0] - a[0], c[1] - a[1]));
}

/* Labels the grid intersections around the point the camera looks at, nearest the centre of
 * the view first, where they cover nothing else and where the intersection itself is seen (a
 * ridge between the eye and the line hides its label; a cell smaller on screen than two
 * lines of text is left unlabelled): on a UTM/UPS render grid as a military
 * map does, the principal digits of easting and northing ("76 00", MGRS truncation) with the
 * grid zone and 100 km square ("31T CH 76 00") on the first label of each square; on any other
 * CRS its kilometres (map_grid.h). */
static void grid_labels(tp_hud* hud, layout* l, const tp_view_scene* v, const tp_camera* cam,
                        double spacing, float scale)
{
    double g[3];
    if (spacing <= 0 || !tp_view_pick_centre(v, cam, g))
        return;
    tp_map_grid mg;
    tp_map_grid_init(&mg, v->georef, v->gt, v->src_width, v->src_height, spacing);
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    double zs = tp_view_scene_vertical_scale(v);
    double e0 = floor(g[0] / spacing) * spacing, n0 = floor(g[1] / spacing) * spacing;
    enum { R = 6, N = (2 * R) * (2 * R) };
    struct cand {
        double p[3], px[2], d2;
    } c[N];
    int count = 0;
    for (int j = -R + 1; j <= R; j++)
        for (int i = -R + 1; i <= R; i++) {
            struct cand* k = &c[count];
            double x, y;
            k->p[0] = e0 + i * spacing;
            k->p[1] = n0 + j * spacing;
            tp_view_scene_world_to_grid(v, k->p[0], k->p[1], &x, &y);
            k->p[2] = tp_view_scene_drawn_height(v, x, y);
            double q[3] = {k->p[0], k->p[1], k->p[2] * zs};
            if (isnan(k->p[2]) || !tp_camera_project(cam, q, k->px, NULL) || k->px[0] < 0 ||
                k->px[1] < 0 || k->px[0] >= w || k->px[1] >= h)
                continue;
            k->d2 = pow(k->px[0] - w / 2.0, 2) + pow(k->px[1] - h / 2.0, 2);
            count++;
        }
    /* nearest the centre first (insertion sort: at most 144) */
    for (int i = 1; i < count; i++)
        for (int k = i; k > 0 && c[k].d2 < c[k - 1].d2; k--) {
            struct cand t = c[k];
            c[k] = c[k - 1];
            c[k - 1] = t;
        }
    char squares[8][16]; /* the squares named on a label already */
    int named = 0;
    for (int i = 0; i < count; i++) {
        char square[16], digits[32], text[64];
        tp_map_grid_label(&mg, c[i].p[0], c[i].p[1], square, digits);
        int known = !square[0];
        for (int k = 0; k < named && !known; k++)
            known = strcmp(squares[k], square) == 0;
        if (known)
            snprintf(text, sizeof text, "%s", digits[0] ? digits : square);
        else
            snprintf(text, sizeof text, "%s%s%s", square, digits[0] ? " " : "", digits);
        float tw, th, x0 = (float)c[i].px[0] + 3, y0 = (float)c[i].px[1] + 3;
        tp_hud_measure(text, &tw, &th);
        float x1 = x0 + tw * scale, y1 = y0 + th * scale;
        if (x1 > w || y1 > h || !is_free(l, x0 - 4, y0 - 2, x1 + 4, y1 + 2) ||
            cell_px(v, cam, c[i].p, spacing) < 2 * th * scale ||
            !tp_view_ground_visible(v, cam, c[i].p))
            continue;
        tp_hud_text(hud, w, h, x0, y0, scale, text);
        occupy(l, x0 - 4, y0 - 2, x1 + 4, y1 + 2);
        if (!known && named < 8)
            snprintf(squares[named++], sizeof squares[0], "%s", square);
    }
}

/* A segment with a dark outline under it. */
static void outlined(tp_hud* hud, int w, int h, float x0, float y0, float x1, float y1,
                     float width, const unsigned char rgba[4], int pass)
{
    static const unsigned char dark[4] = {0, 0, 0, 255};
    if (pass == 0)
        tp_hud_line(hud, w, h, x0, y0, x1, y1, width + 4, dark);
    else
        tp_hud_line(hud, w, h, x0, y0, x1, y1, width, rgba);
}

/* North arrow and scale bar at the bottom right, drawn so that they read on any
 * ground (white strokes on a dark outline, no panel: the HUD's blending is not kept in
 * screenshots). The arrow shows grid north turned by the camera's heading (screen up is where
 * the camera faces, straight down as on a map, the same looking along the horizon), with true
 * north (a gold line, "TN") beside it when the two differ by more than half a degree (grid
 * convergence away from a UTM zone's central meridian; drawn at least 40 degrees apart, as a map's
 * declination diagram is, the true angle written under it, measured at the ground point the
 * camera looks at); the bar spans a round length (1, 2 or 5 x 10^k m) measured
 * across the screen at the look point, or says that there is no ground to measure at. */
static void compass_and_scale(tp_hud* hud, layout* l, const tp_view_scene* v,
                              const tp_camera* cam, float bottom, float scale)
{
    const float s = scale;
    static const unsigned char white[4] = {255, 255, 255, 255},
                               gold[4] = {255, 210, 60, 255}, grey[4] = {40, 40, 40, 255};
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    double g[3], c[2], yaw, pitch;
    tp_camera_get_pose(cam, &yaw, &pitch);
    int ground = tp_view_pick_centre(v, cam, g);
    double true_north_deg = 0; /* bearing of true north from grid north, at g */
    if (ground) {
        double lat, lon, e, n;
        if (tp_georef_proj_to_geo(v->georef, g[0], g[1], &lat, &lon, NULL) == TP_OK &&
            tp_georef_geo_to_proj(v->georef, fmin(lat + 0.01, 90), lon, &e, &n, NULL) == TP_OK)
            true_north_deg = atan2(e - g[0], n - g[1]) * 180 / 3.14159265358979323846;
        g[2] *= tp_view_scene_vertical_scale(v); /* drawn space */
        ground = tp_camera_project(cam, g, c, NULL);
    }
    /* the panel: compass on the right, scale bar left of it */
    float x1 = (float)w - 6 * s, y0 = bottom - 98 * s, y1 = bottom - 6 * s;
    float x0 = x1 - 250 * s;
    if (x0 < 0 || y0 < 0)
        return;
    occupy(l, x0, y0, x1, y1);

    /* north arrow */
    float cx = x1 - 44 * s, cy = y0 + 42 * s, r = 28 * s;
    /* from the heading: screen up is the way the camera faces, as on a map turned to it (a
     * ground vector projected at a grazing look point would point sideways) */
    const double rad = 3.14159265358979323846 / 180;
    double gn[2] = {-sin(yaw * rad), -cos(yaw * rad)}, tn[2] = {gn[0], gn[1]};
    int two = ground && fabs(true_north_deg) > 0.5;
    if (two) { /* drawn at least 40 degrees away, on its side */
        double t = (true_north_deg < 0 ? fmin(true_north_deg, -40) : fmax(true_north_deg, 40)) * rad;
        tn[0] = gn[0] * cos(t) - gn[1] * sin(t);
        tn[1] = gn[0] * sin(t) + gn[1] * cos(t);
    }
    for (int pass = 0; pass < 2; pass++) {
        float tx = cx + (float)gn[0] * r, ty = cy + (float)gn[1] * r;
        outlined(hud, w, h, cx - (float)gn[0] * r * 0.6f, cy - (float)gn[1] * r * 0.6f, tx, ty,
                 2.5f * s, white, pass);
        for (int side = -1; side <= 1; side += 2) { /* the head */
            double ca = cos(side * 2.6), sa = sin(side * 2.6);
            float hx = tx + (float)((gn[0] * ca - gn[1] * sa) * 11 * s),
                  hy = ty + (float)((gn[0] * sa + gn[1] * ca) * 11 * s);
            outlined(hud, w, h, tx, ty, hx, hy, 2.5f * s, white, pass);
        }
        if (two)
            outlined(hud, w, h, cx, cy, cx + (float)tn[0] * r * 0.8f,
                     cy + (float)tn[1] * r * 0.8f, 2.0f * s, gold, pass);
    }
    const char* nl = two ? "GN" : "N";
    float tw, th;
    tp_hud_measure(nl, &tw, &th);
    tp_hud_text(hud, w, h, cx + (float)gn[0] * (r + 9 * s) - tw * s / 2,
                cy + (float)gn[1] * (r + 9 * s) - th * s / 2, s, nl);
    if (two) {
        char tl[32];
        snprintf(tl, sizeof tl, "TN %.1f %s", fabs(true_north_deg), true_north_deg < 0 ? "W" : "E");
        tp_hud_measure("TN", &tw, &th);
        float tx = cx + (float)tn[0] * (r * 0.8f + 9 * s), ty = cy + (float)tn[1] * (r * 0.8f + 9 * s);
        tp_hud_text(hud, w, h, tx - tw * s / 2, ty - th * s / 2, s, "TN");
        tp_hud_measure(tl, &tw, &th);
        tp_hud_text(hud, w, h, cx - tw * s / 2, y1 - th * s, s, tl);
    }

    /* scale bar, measured across the screen at the look point */
    float bx1 = x1 - 96 * s, by = y1 - 26 * s;
    if (!ground) {
        tp_hud_text(hud, w, h, x0 + 6 * s, by - 10 * s, s, "no ground at the\ncentre: no scale");
        return;
    }
    double m_per_px = tp_view_metres_per_pixel(v, cam, w / 2.0, h / 2.0, NULL);
    if (isnan(m_per_px))
        return;
    /* a round length at most 130 px long: 1, 2 or 5 times a power of ten */
    double want = 130 * s * m_per_px, p10 = pow(10, floor(log10(want))), len = p10;
    if (5 * p10 <= want)
        len = 5 * p10;
    else if (2 * p10 <= want)
        len = 2 * p10;
    float bar = (float)(len / m_per_px), bx0 = bx1 - bar;
    for (int pass = 0; pass < 2; pass++) {
        for (int k = 0; k < 4; k++) /* four segments, alternately light and dark */
            outlined(hud, w, h, bx0 + bar * k / 4, by, bx0 + bar * (k + 1) / 4, by, 5 * s,
                     k % 2 ? grey : white, pass);
        for (int k = 0; k <= 2; k++) /* ticks at 0, half and the end */
            outlined(hud, w, h, bx0 + bar * k / 2, by - 9 * s, bx0 + bar * k / 2, by + 2 * s,
                     1.5f * s, white, pass);
    }
    char label[48];
    if (len >= 1000)
        snprintf(label, sizeof label, "%g km", len / 1000);
    else
        snprintf(label, sizeof label, "%g m", len);
    tp_hud_measure(label, &tw, &th);
    tp_hud_text(hud, w, h, bx1 - tw * s / 2, by - 12 * s - th * s, s, label);
    tp_hud_text(hud, w, h, bx0 - 3 * s, by - 12 * s - th * s, s, "0");
    if (pitch > -60) /* perspective: the scale holds at the centre only */
        tp_hud_text(hud, w, h, bx0, by + 6 * s, s, "at the centre");
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

/* Which side of the viewport (grown by m pixels) a projected point lies beyond: bits 1 left,
 * 2 right, 4 above, 8 below; 0 inside. */
static int outside(const float* p, int w, int h, float m)
{
    return (p[0] < -m) | (p[0] > w + m) << 1 | (p[1] < -m) << 2 | (p[1] > h + m) << 3;
}

/* Draws the polyline through count ground points (enh triples), broken where a point is
 * behind the eye, in runs of at most RUN_MAX points. What cannot show is left out: segments
 * whose ends both lie beyond the same side of the viewport, and points closer than a pixel to
 * the last one kept (far contours have many vertices a pixel). */
static void draped_line(tp_hud* hud, const tp_camera* cam, const tp_overlay* ov, double zs,
                        const double* enh, size_t count, float width, const unsigned char rgba[4])
{
    static float xyz[3 * RUN_MAX];
    const int w = cam->viewport_w_px, h = cam->viewport_h_px;
    const float margin = width + 2;
    int n = 0;
    for (size_t i = 0; i < count; i++) {
        float* p = xyz + 3 * n;
        const int keep = project_draped(cam, ov, zs, enh + 3 * i, p);
        const int last = i + 1 == count;
        if (keep && n > 0) {
            const float* q = p - 3;
            if (outside(q, w, h, margin) & outside(p, w, h, margin)) { /* off screen */
                if (n >= 2)
                    tp_hud_polyline_depth(hud, w, h, xyz, n, width, rgba);
                memmove(xyz, p, sizeof(float) * 3);
                n = 1;
                continue;
            }
            if (!last && fabsf(p[0] - q[0]) + fabsf(p[1] - q[1]) < 1.0f)
                continue; /* under a pixel from the last point kept */
        }
        n += keep;
        if (keep && n < RUN_MAX && !last)
            continue;
        if (n >= 2)
            tp_hud_polyline_depth(hud, w, h, xyz, n, width, rgba);
        n = 0;
        if (keep && !last) { /* full: the next run starts where this one ended */
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

/* Places text at pixel (x, y) (its top-left corner a little right of and above the point)
 * when it covers nothing drawn already and the ground point p is seen from the eye (the ray
 * cast last: it is the expensive test). */
static void label_at(tp_hud* hud, layout* l, const tp_view_scene* v, const tp_camera* cam,
                     const double p[3], double x, double y, float s, const char* text)
{
    const int w = cam->viewport_w_px, h = cam->viewport_h_px;
    float tw, th, x0 = (float)x + 5 * s, y0 = (float)y - 12 * s;
    tp_hud_measure(text, &tw, &th);
    float x1 = x0 + tw * s, y1 = y0 + th * s;
    if (x0 < 0 || y0 < 0 || x1 > w || y1 > h || !is_free(l, x0 - 3, y0 - 2, x1 + 3, y1 + 2) ||
        !tp_view_ground_visible(v, cam, p))
        return;
    tp_hud_text(hud, w, h, x0, y0, s, text);
    occupy(l, x0 - 3, y0 - 2, x1 + 3, y1 + 2);
}

/* Features draped on the ground: lines and rings (index contours thicker), points as dots
 * (pass 0, with the terrain); the points' names (pass 1) and the index contours' elevations at
 * the middle of each part (pass 2), each where its ground point is seen and the text covers
 * nothing laid out before it. */
static void drape_features(tp_hud* hud, layout* l, const tp_view_scene* v, const tp_camera* cam,
                           const tp_overlay* ov, const tp_overlay_drape* od, float s, int pass)
{
    const tp_drape* d = od->drape;
    const double zs = tp_view_scene_vertical_scale(v);
    int w = cam->viewport_w_px, h = cam->viewport_h_px;
    if (pass == 0) {
        for (size_t i = 0; i < d->part_count; i++) {
            const tp_drape_part* p = &d->parts[i];
            const double* e = d->enh + 3 * p->first;
            float width = od->width_px * s * (p->index ? 2.0f : 1.0f);
            if (!od->label_values && width >= 2.5f) { /* outlined: readable on any ground */
                const unsigned char dark[4] = {0, 0, 0, 200};
                draped_line(hud, cam, ov, zs, e, p->count, width + 2 * s, dark);
            }
            draped_line(hud, cam, ov, zs, e, p->count, width, od->rgba);
        }
        float* xyz = d->point_count ? malloc(sizeof(float) * 3 * d->point_count) : NULL;
        int n = 0;
        for (size_t i = 0; xyz && i < d->point_count; i++)
            n += project_draped(cam, ov, zs, d->points[i].enh, xyz + 3 * n);
        const unsigned char dark[4] = {0, 0, 0, 220};
        for (int k = 0; k < n; k += 20000) {
            int m = n - k < 20000 ? n - k : 20000;
            tp_hud_dots(hud, w, h, xyz + 3 * k, m, 9.0f * s, dark, ov->far_m > 0);
            tp_hud_dots(hud, w, h, xyz + 3 * k, m, 6.0f * s, od->rgba, ov->far_m > 0);
        }
        free(xyz);
        return;
    }
    for (size_t i = 0; pass == 1 && i < d->point_count; i++) {
        float q[3];
        if (d->points[i].name && project_draped(cam, ov, zs, d->points[i].enh, q))
            label_at(hud, l, v, cam, d->points[i].enh, q[0], q[1], s, d->points[i].name);
    }
    for (size_t i = 0; pass == 2 && od->label_values && i < d->part_count; i++) {
        const tp_drape_part* p = &d->parts[i];
        const double* at = d->enh + 3 * (p->first + p->count / 2);
        float q[3];
        if (!p->index || p->value != p->value || !project_draped(cam, ov, zs, at, q))
            continue;
        char text[32];
        snprintf(text, sizeof text, "%.0f", p->value);
        label_at(hud, l, v, cam, at, q[0], q[1], s, text);
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
        drape_features(hud, &l, v, cam, ov, &ov->drapes[i], s, 0);
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
    /* names of points, then contour elevations, then grid labels, where room is left */
    for (int pass = 1; pass <= 2; pass++)
        for (size_t i = 0; i < ov->drape_count; i++)
            drape_features(hud, &l, v, cam, ov, &ov->drapes[i], s, pass);
    if (ov->grid_m > 0)
        grid_labels(hud, &l, v, cam, ov->grid_m, s);
    tp_hud_flush(hud);
}
