/* pgm_error.c - the error of one frame's Persistent Grid Mapping surface (pgm.c) against the
 * level-0 posts, as the bench measures every method: each drawn triangle of the mapped grid
 * is rasterised over the integer post lattice in float coordinates (an edge-function test,
 * closed; a post on an edge shared by two triangles is taken by the first that visits it, so
 * each post is counted once), the drawn height interpolated linearly, and the posts the main
 * camera sees compared vertically and on screen (tp__screen_error_px, as the selection's
 * screen-error measure). Posts in view that no drawn triangle covers are counted apart. The
 * heights come from a source (a whole pyramid, or a store's clipmap in the viewer); the posts
 * are visited band by band of rows, so that memory stays one band of the region measured. */
#include "camera_int.h"
#include "pgm_int.h"

#include <stdlib.h>
#include <string.h>

#define DEFAULT_BAND_ROWS 64

typedef struct pgm_measure {
    const tp_pgm_pyramid* p;
    tp__view view;
    const double *gx, *gy, *gz; /* mapped vertices: level-0 grid coordinates, drawn height */
    /* the band of posts x0 <= x < x1, y0 <= y < y1 being measured */
    int x0, y0, x1, y1;
    const float* truth; /* its level-0 heights (NaN: none) */
    uint8_t* covered;   /* per post of the band: taken by a triangle */
    double max_m, sum_m2, max_px, sum_px2;
    size_t samples;
} pgm_measure;

/* The edge function of the directed edge m -> n at (x, y), always evaluated with the endpoints
 * in index order, so that the two triangles sharing the edge get bitwise equal values of
 * opposite meaning and a post exactly on it is inside (0) for both. */
static double edge(const pgm_measure* m, size_t a, size_t b, double x, double y)
{
    size_t lo = a < b ? a : b, hi = a < b ? b : a;
    double v =
        (m->gx[hi] - m->gx[lo]) * (y - m->gy[lo]) - (m->gy[hi] - m->gy[lo]) * (x - m->gx[lo]);
    return a < b ? v : -v;
}

static void post_error(pgm_measure* m, int x, int y, double truth_z, double drawn_z)
{
    const double* gt = m->p->geotransform;
    double truth[3], drawn[3];
    truth[0] = drawn[0] = gt[0] + (x + 0.5) * gt[1];
    truth[1] = drawn[1] = gt[3] + (y + 0.5) * gt[5];
    truth[2] = truth_z;
    drawn[2] = drawn_z;
    double px = tp__screen_error_px(&m->view, truth, drawn);
    if (isnan(px))
        return; /* not in view */
    double e = fabs(drawn_z - truth_z);
    m->max_m = e > m->max_m ? e : m->max_m;
    m->sum_m2 += e * e;
    m->max_px = px > m->max_px ? px : m->max_px;
    m->sum_px2 += px * px;
    m->samples++;
}

/* Visits the posts of the band inside triangle (a, b, c) (vertex indices) that no earlier one
 * took. */
static void raster(pgm_measure* m, size_t a, size_t b, size_t c)
{
    const size_t v[3] = {a, b, c};
    double x0 = m->gx[a], x1 = x0, y0 = m->gy[a], y1 = y0;
    for (int k = 1; k < 3; k++) {
        x0 = fmin(x0, m->gx[v[k]]);
        x1 = fmax(x1, m->gx[v[k]]);
        y0 = fmin(y0, m->gy[v[k]]);
        y1 = fmax(y1, m->gy[v[k]]);
    }
    if (!(y1 >= m->y0 && y0 < m->y1 && x1 >= m->x0 && x0 < m->x1))
        return; /* not in the band (NaN corners never are) */
    double ea = edge(m, b, c, m->gx[a], m->gy[a]); /* twice the signed area, three ways */
    double eb = edge(m, c, a, m->gx[b], m->gy[b]);
    double ec = edge(m, a, b, m->gx[c], m->gy[c]);
    if (!(ea != 0 && eb != 0 && ec != 0) || (ea > 0) != (eb > 0) || (ea > 0) != (ec > 0))
        return; /* degenerate (or so thin that rounding cannot orient it) */
    int ix0 = (int)fmax(ceil(x0), m->x0), ix1 = (int)fmin(floor(x1), m->x1 - 1);
    int iy0 = (int)fmax(ceil(y0), m->y0), iy1 = (int)fmin(floor(y1), m->y1 - 1);
    const int bw = m->x1 - m->x0;
    double za = m->gz[a], zb = m->gz[b], zc = m->gz[c];
    for (int y = iy0; y <= iy1; y++) {
        for (int x = ix0; x <= ix1; x++) {
            size_t k = (size_t)(y - m->y0) * bw + (x - m->x0);
            if (m->covered[k])
                continue;
            double wa = edge(m, b, c, x, y) / ea;
            double wb = edge(m, c, a, x, y) / eb;
            double wc = edge(m, a, b, x, y) / ec;
            if (wa < 0 || wb < 0 || wc < 0)
                continue;
            m->covered[k] = 1;
            if (isnan(m->truth[k]))
                continue; /* a post without a height: not compared */
            /* relative to za, so that a flat triangle gives its height exactly */
            post_error(m, x, y, m->truth[k], za + wb * (zb - za) + wc * (zc - za));
        }
    }
}

/* ---- the view's region ---- */

void tp_pgm_view_region(const tp_pgm_pyramid* shape, const tp_camera* main, tp_pgm_rect* out)
{
    assert(shape && main && out && shape->levels > 0);
    const int w = shape->width[0], h = shape->height[0];
    *out = (tp_pgm_rect){0, 0, w, h};
    tp__view v;
    tp__view_from_camera(main, &v);
    const double* gt = shape->geotransform;
    const double zmin = shape->min_m, zmax = shape->max_m;
    /* E, N bounds of what the view holds between the heights zmin and zmax */
    double e0 = -INFINITY, e1 = INFINITY, n0 = -INFINITY, n1 = INFINITY;
    double d[4][3], top = -INFINITY;
    for (int c = 0; c < 4; c++) {
        double a = (c & 1) ? v.tan_x : -v.tan_x, b = (c & 2) ? v.tan_y : -v.tan_y;
        for (int k = 0; k < 3; k++)
            d[c][k] = v.fwd[k] + a * v.right[k] + b * v.up[k];
        top = fmax(top, d[c][2]);
    }
    if (top < 0) {
        /* Every ray of the view goes down (the corners' are the extremes of a linear z): each
         * meets the slab between t at zmax (or the eye, inside it) and t at zmin; the view's
         * part of the slab is the convex hull of those points. */
        if (v.pos[2] < zmin) {
            out->x1 = out->x0, out->y1 = out->y0; /* below the terrain, looking down */
            return;
        }
        e0 = n0 = INFINITY, e1 = n1 = -INFINITY;
        for (int c = 0; c < 4; c++) {
            double t_lo = v.pos[2] > zmax ? (zmax - v.pos[2]) / d[c][2] : 0;
            double t_hi = (zmin - v.pos[2]) / d[c][2];
            double ts[2] = {t_lo, t_hi};
            for (int k = 0; k < 2; k++) {
                double e = v.pos[0] + ts[k] * d[c][0], n = v.pos[1] + ts[k] * d[c][1];
                e0 = fmin(e0, e), e1 = fmax(e1, e), n0 = fmin(n0, n), n1 = fmax(n1, n);
            }
        }
    }
    if (v.far_m > 0) { /* depth <= far: at most far times the longest corner ray away */
        double reach = v.far_m * sqrt(1 + v.tan_x * v.tan_x + v.tan_y * v.tan_y);
        e0 = fmax(e0, v.pos[0] - reach), e1 = fmin(e1, v.pos[0] + reach);
        n0 = fmax(n0, v.pos[1] - reach), n1 = fmin(n1, v.pos[1] + reach);
    }
    /* to level-0 grid coordinates (either sign of spacing), two posts of room for rounding */
    double xa = (e0 - gt[0]) / gt[1] - 0.5, xb = (e1 - gt[0]) / gt[1] - 0.5;
    double ya = (n0 - gt[3]) / gt[5] - 0.5, yb = (n1 - gt[3]) / gt[5] - 0.5;
    double gx0 = fmin(xa, xb) - 2, gx1 = fmax(xa, xb) + 3;
    double gy0 = fmin(ya, yb) - 2, gy1 = fmax(ya, yb) + 3;
    if (gx0 > 0)
        out->x0 = gx0 < w ? (int)gx0 : w;
    if (gx1 < w)
        out->x1 = gx1 > out->x0 ? (int)gx1 : out->x0;
    if (gy0 > 0)
        out->y0 = gy0 < h ? (int)gy0 : h;
    if (gy1 < h)
        out->y1 = gy1 > out->y0 ? (int)gy1 : out->y0;
}

/* ---- the measure ---- */

tp_status tp_pgm_measure_error_source(const tp_pgm_frame* f, const tp_pgm_pyramid* shape,
                                      const tp_pgm_source* src, const tp_pgm_rect* region,
                                      const tp_camera* main, tp_pgm_error* out)
{
    assert(f && shape && src && src->sample && src->posts && main && out);
    assert(shape->levels > 0 && f->cols >= 2 && f->rows >= 2);
    memset(out, 0, sizeof *out);
    const int cols = f->cols, rows = f->rows, w = shape->width[0], h = shape->height[0];
    tp_pgm_rect r = {0, 0, w, h};
    if (region) { /* clipped to the extent */
        r.x0 = region->x0 > 0 ? region->x0 : 0, r.y0 = region->y0 > 0 ? region->y0 : 0;
        r.x1 = region->x1 < w ? region->x1 : w, r.y1 = region->y1 < h ? region->y1 : h;
    }
    const int band = src->band_rows > 0 ? src->band_rows : DEFAULT_BAND_ROWS;
    const size_t nv = (size_t)cols * (size_t)rows;
    const size_t bw = r.x1 > r.x0 && r.y1 > r.y0 ? (size_t)(r.x1 - r.x0) : 0; /* 0: empty */
    const size_t bp = bw * (size_t)band;
    double* g = malloc(3 * nv * sizeof *g);
    uint8_t* on = malloc(nv);
    float* truth = bp ? malloc(bp * sizeof *truth) : NULL;
    uint8_t* covered = bp ? malloc(bp) : NULL;
    if (!g || !on || (bp && (!truth || !covered))) {
        free(g), free(on), free(truth), free(covered);
        return TP_ERR_OUT_OF_MEMORY;
    }
    pgm_measure m;
    memset(&m, 0, sizeof m);
    m.p = shape;
    m.gx = g;
    m.gy = g + nv;
    m.gz = g + 2 * nv;
    m.truth = truth;
    m.covered = covered;
    tp__view_from_camera(main, &m.view);
    for (int j = 0; j < rows; j++)
        for (int i = 0; i < cols; i++) {
            size_t k = (size_t)j * cols + i;
            double ground[4], wp;
            int l;
            tp__pgm_map_ground(f, shape, i, j, ground, &l, &wp);
            double x = ground[2], y = ground[3];
            double z = src->sample(src->ctx, l, x, y);
            if (wp > 0) { /* tp_pgm_map_vertex's blend; nothing drawn when either is */
                double zp = src->sample(src->ctx, l + 1, x, y);
                z = isnan(zp) ? NAN : (1 - wp) * z + wp * zp;
            }
            on[k] = (uint8_t)(x >= 0 && x <= w - 1 && y >= 0 && y <= h - 1 && !isnan(z));
            g[k] = x;
            g[nv + k] = y;
            g[2 * nv + k] = z;
        }
    size_t uncovered = 0;
    tp_status status = TP_OK;
    const double* gt = shape->geotransform;
    const int every = src->band_every > 1 ? src->band_every : 1;
    const int phase = ((src->band_phase % every) + every) % every;
    size_t rows_all = 0, rows_done = 0;
    for (int by = r.y0 - r.y0 % band; bw && by < r.y1; by += band) {
        m.x0 = r.x0, m.x1 = r.x1;
        m.y0 = by > r.y0 ? by : r.y0;
        m.y1 = by + band < r.y1 ? by + band : r.y1;
        rows_all += (size_t)(m.y1 - m.y0);
        if ((by / band) % every != phase)
            continue;
        rows_done += (size_t)(m.y1 - m.y0);
        if (!src->posts(src->ctx, m.x0, m.y0, m.x1, m.y1, truth)) {
            status = TP_ERR_IO;
            break;
        }
        memset(covered, 0, bw * (size_t)(m.y1 - m.y0));
        for (int j = 0; j + 1 < rows; j++)
            for (int i = 0; i + 1 < cols; i++) {
                size_t a = (size_t)j * cols + i, b = a + 1, c = a + cols, d = c + 1;
                if (on[a] && on[b] && on[c])
                    raster(&m, a, b, c);
                if (on[b] && on[d] && on[c])
                    raster(&m, b, d, c);
            }
        /* Posts in view that no triangle took. */
        for (int y = m.y0; y < m.y1; y++)
            for (int x = m.x0; x < m.x1; x++) {
                size_t k = (size_t)(y - m.y0) * bw + (x - m.x0);
                if (covered[k] || isnan(truth[k]))
                    continue;
                double pt[3] = {gt[0] + (x + 0.5) * gt[1], gt[3] + (y + 0.5) * gt[5], truth[k]};
                if (!isnan(tp__screen_error_px(&m.view, pt, pt)))
                    uncovered++;
            }
    }
    free(g), free(on), free(truth), free(covered);
    if (status != TP_OK)
        return status;
    out->max_m = m.max_m;
    out->max_px = m.max_px;
    out->samples = m.samples;
    out->uncovered = uncovered;
    out->post_share = rows_all ? (double)rows_done / (double)rows_all : 1;
    if (m.samples) {
        out->rms_m = sqrt(m.sum_m2 / (double)m.samples);
        out->rms_px = sqrt(m.sum_px2 / (double)m.samples);
    }
    return TP_OK;
}

/* ---- over a whole pyramid ---- */

static double pyramid_sample(void* ctx, int level, double x, double y)
{
    return tp_pgm_pyramid_sample(ctx, level, x, y);
}

static int pyramid_posts(void* ctx, int x0, int y0, int x1, int y1, float* out)
{
    const tp_pgm_pyramid* p = ctx;
    for (int y = y0; y < y1; y++)
        memcpy(out + (size_t)(y - y0) * (x1 - x0), p->z[0] + (size_t)y * p->width[0] + x0,
               (size_t)(x1 - x0) * sizeof *out);
    return 1;
}

tp_status tp_pgm_measure_error(const tp_pgm_frame* f, const tp_pgm_pyramid* p,
                               const tp_camera* main, tp_pgm_error* out)
{
    assert(f && p && main && out && p->levels > 0 && f->cols >= 2 && f->rows >= 2);
    tp_pgm_source src = {(void*)p, pyramid_sample, pyramid_posts, 0, 0, 0};
    return tp_pgm_measure_error_source(f, p, &src, NULL, main, out);
}
