/* pgm_error.c - the error of one frame's Persistent Grid Mapping surface (pgm.c) against the
 * level-0 posts, as the bench measures every method: each drawn triangle of the mapped grid
 * is rasterised over the integer post lattice in float coordinates (an edge-function test,
 * closed; a post on an edge shared by two triangles is taken by the first that visits it, so
 * each post is counted once), the drawn height interpolated linearly, and the posts the main
 * camera sees compared vertically and on screen (tp__screen_error_px, as the selection's
 * screen-error measure). Posts in view that no drawn triangle covers are counted apart. */
#include "internal.h"

#include <stdlib.h>
#include <string.h>

typedef struct pgm_measure {
    const tp_pgm_pyramid* p;
    tp__view view;
    const double *gx, *gy, *gz; /* mapped vertices: level-0 grid coordinates, drawn height */
    uint8_t* covered;           /* per level-0 post: taken by a triangle */
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

static void post_error(pgm_measure* m, int x, int y, double drawn_z)
{
    const tp_pgm_pyramid* p = m->p;
    const double* gt = p->geotransform;
    double truth[3], drawn[3];
    truth[0] = drawn[0] = gt[0] + (x + 0.5) * gt[1];
    truth[1] = drawn[1] = gt[3] + (y + 0.5) * gt[5];
    truth[2] = p->z[0][(size_t)y * p->width[0] + x];
    drawn[2] = drawn_z;
    double px = tp__screen_error_px(&m->view, truth, drawn);
    if (isnan(px))
        return; /* not in view */
    double e = fabs(drawn_z - truth[2]);
    m->max_m = e > m->max_m ? e : m->max_m;
    m->sum_m2 += e * e;
    m->max_px = px > m->max_px ? px : m->max_px;
    m->sum_px2 += px * px;
    m->samples++;
}

/* Visits the posts inside triangle (a, b, c) (vertex indices) that no earlier one took. */
static void raster(pgm_measure* m, size_t a, size_t b, size_t c)
{
    const size_t v[3] = {a, b, c};
    double ea = edge(m, b, c, m->gx[a], m->gy[a]); /* twice the signed area, three ways */
    double eb = edge(m, c, a, m->gx[b], m->gy[b]);
    double ec = edge(m, a, b, m->gx[c], m->gy[c]);
    if (!(ea != 0 && eb != 0 && ec != 0) || (ea > 0) != (eb > 0) || (ea > 0) != (ec > 0))
        return; /* degenerate (or so thin that rounding cannot orient it) */
    double x0 = m->gx[a], x1 = x0, y0 = m->gy[a], y1 = y0;
    for (int k = 1; k < 3; k++) {
        x0 = fmin(x0, m->gx[v[k]]);
        x1 = fmax(x1, m->gx[v[k]]);
        y0 = fmin(y0, m->gy[v[k]]);
        y1 = fmax(y1, m->gy[v[k]]);
    }
    int w = m->p->width[0], h = m->p->height[0];
    int ix0 = (int)fmax(ceil(x0), 0), ix1 = (int)fmin(floor(x1), w - 1);
    int iy0 = (int)fmax(ceil(y0), 0), iy1 = (int)fmin(floor(y1), h - 1);
    double za = m->gz[a], zb = m->gz[b], zc = m->gz[c];
    for (int y = iy0; y <= iy1; y++) {
        for (int x = ix0; x <= ix1; x++) {
            size_t k = (size_t)y * w + x;
            if (m->covered[k])
                continue;
            double wa = edge(m, b, c, x, y) / ea;
            double wb = edge(m, c, a, x, y) / eb;
            double wc = edge(m, a, b, x, y) / ec;
            if (wa < 0 || wb < 0 || wc < 0)
                continue;
            m->covered[k] = 1;
            /* relative to za, so that a flat triangle gives its height exactly */
            post_error(m, x, y, za + wb * (zb - za) + wc * (zc - za));
        }
    }
}

tp_status tp_pgm_measure_error(const tp_pgm_frame* f, const tp_pgm_pyramid* p,
                               const tp_camera* main, tp_pgm_error* out)
{
    assert(f && p && main && out && p->levels > 0 && f->cols >= 2 && f->rows >= 2);
    memset(out, 0, sizeof *out);
    const int cols = f->cols, rows = f->rows, w = p->width[0], h = p->height[0];
    const size_t nv = (size_t)cols * (size_t)rows, np = (size_t)w * (size_t)h;
    double* g = malloc(3 * nv * sizeof *g);
    uint8_t* on = malloc(nv);
    uint8_t* covered = calloc(np, 1);
    if (!g || !on || !covered) {
        free(g);
        free(on);
        free(covered);
        return TP_ERR_OUT_OF_MEMORY;
    }
    pgm_measure m;
    memset(&m, 0, sizeof m);
    m.p = p;
    m.gx = g;
    m.gy = g + nv;
    m.gz = g + 2 * nv;
    m.covered = covered;
    tp__view_from_camera(main, &m.view);
    const double* gt = p->geotransform;
    for (int j = 0; j < rows; j++)
        for (int i = 0; i < cols; i++) {
            size_t k = (size_t)j * cols + i;
            double world[3], lod;
            on[k] = (uint8_t)tp_pgm_map_vertex(f, p, i, j, world, &lod);
            g[k] = (world[0] - gt[0]) / gt[1] - 0.5;
            g[nv + k] = (world[1] - gt[3]) / gt[5] - 0.5;
            g[2 * nv + k] = world[2];
        }
    for (int j = 0; j + 1 < rows; j++)
        for (int i = 0; i + 1 < cols; i++) {
            size_t a = (size_t)j * cols + i, b = a + 1, c = a + cols, d = c + 1;
            if (on[a] && on[b] && on[c])
                raster(&m, a, b, c);
            if (on[b] && on[d] && on[c])
                raster(&m, b, d, c);
        }
    /* Posts in view that no triangle took. */
    size_t uncovered = 0;
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            if (covered[(size_t)y * w + x])
                continue;
            double pt[3] = {gt[0] + (x + 0.5) * gt[1], gt[3] + (y + 0.5) * gt[5],
                            p->z[0][(size_t)y * w + x]};
            if (!isnan(tp__screen_error_px(&m.view, pt, pt)))
                uncovered++;
        }
    free(g);
    free(on);
    free(covered);
    out->max_m = m.max_m;
    out->max_px = m.max_px;
    out->samples = m.samples;
    out->uncovered = uncovered;
    if (m.samples) {
        out->rms_m = sqrt(m.sum_m2 / (double)m.samples);
        out->rms_px = sqrt(m.sum_px2 / (double)m.samples);
    }
    return TP_OK;
}
