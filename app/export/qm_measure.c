/* qm_measure.c - a quantized-mesh tile's true error against the store's full-resolution posts
 * inside it (see qm_tile.h): each post placed on the tile's lattice, the tile's triangle around
 * it found through an index over the lattice cells, the difference of heights taken. */
#include "qm_tile.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct qm_index {
    int n;
    uint32_t last;   /* the triangle the last query found: the next post is mostly in it too */
    uint32_t* start; /* n * n + 1 */
    uint32_t* tri;
};

void tp_qm_index_free(qm_index* ix)
{
    if (!ix)
        return;
    free(ix->start);
    free(ix->tri);
    free(ix);
}

/* The cells a triangle's bounding box covers. */
static void cells_of(const qm_mesh* m, size_t t, int* i0, int* i1, int* j0, int* j1)
{
    double lo_i = INFINITY, hi_i = -INFINITY, lo_j = INFINITY, hi_j = -INFINITY;
    for (int c = 0; c < 3; c++) {
        const double* p = m->ij + 2 * m->tris[3 * t + c];
        lo_i = fmin(lo_i, p[0]);
        hi_i = fmax(hi_i, p[0]);
        lo_j = fmin(lo_j, p[1]);
        hi_j = fmax(hi_j, p[1]);
    }
    /* vertices off the lattice (the refinement's): every cell the box touches */
    *i0 = (int)floor(lo_i);
    *j0 = (int)floor(lo_j);
    *i1 = (int)ceil(hi_i) - 1 < *i0 ? *i0 : (int)ceil(hi_i) - 1;
    *j1 = (int)ceil(hi_j) - 1 < *j0 ? *j0 : (int)ceil(hi_j) - 1;
    *i1 = *i1 > m->n - 1 ? m->n - 1 : *i1;
    *j1 = *j1 > m->n - 1 ? m->n - 1 : *j1;
}

static qm_index* index_build(const qm_mesh* m)
{
    qm_index* ix = calloc(1, sizeof *ix);
    if (!ix)
        return NULL;
    ix->n = m->n;
    const size_t cells = (size_t)m->n * m->n;
    ix->start = calloc(cells + 1, sizeof *ix->start);
    if (!ix->start) {
        tp_qm_index_free(ix);
        return NULL;
    }
    size_t total = 0;
    for (size_t t = 0; t < m->triangle_count; t++) {
        int i0, i1, j0, j1;
        cells_of(m, t, &i0, &i1, &j0, &j1);
        for (int j = j0; j <= j1; j++)
            for (int i = i0; i <= i1; i++)
                ix->start[(size_t)j * m->n + i + 1]++;
        total += (size_t)(i1 - i0 + 1) * (size_t)(j1 - j0 + 1);
    }
    for (size_t c = 0; c < cells; c++)
        ix->start[c + 1] += ix->start[c];
    ix->tri = malloc((total ? total : 1) * sizeof *ix->tri);
    uint32_t* fill = malloc(cells * sizeof *fill);
    if (!ix->tri || !fill) {
        free(fill);
        tp_qm_index_free(ix);
        return NULL;
    }
    memcpy(fill, ix->start, cells * sizeof *fill);
    for (size_t t = 0; t < m->triangle_count; t++) {
        int i0, i1, j0, j1;
        cells_of(m, t, &i0, &i1, &j0, &j1);
        for (int j = j0; j <= j1; j++)
            for (int i = i0; i <= i1; i++)
                ix->tri[fill[(size_t)j * m->n + i]++] = (uint32_t)t;
    }
    free(fill);
    return ix;
}

/* Barycentric weights of (fi, fj) in triangle t; the smallest in *lo, the height returned. */
static double in_triangle(const qm_mesh* m, uint32_t t, double fi, double fj, double* lo)
{
    const uint32_t* v = m->tris + 3 * (size_t)t;
    const double *a = m->ij + 2 * v[0], *b = m->ij + 2 * v[1], *c = m->ij + 2 * v[2];
    const double bx = b[0] - a[0], by = b[1] - a[1];
    const double cx = c[0] - a[0], cy = c[1] - a[1];
    const double det = bx * cy - cx * by;
    if (det == 0) {
        *lo = -INFINITY;
        return 0;
    }
    const double px = fi - a[0], py = fj - a[1];
    const double wb = (px * cy - cx * py) / det, wc = (bx * py - px * by) / det;
    const double wa = 1.0 - wb - wc;
    double l = wa < wb ? wa : wb;
    *lo = l < wc ? l : wc;
    return wa * m->z[v[0]] + wb * m->z[v[1]] + wc * m->z[v[2]];
}

/* The triangle around (fi, fj) and its height there: the last one found first, then those of
 * the lattice cell; the one nearest to holding it when none does (a rounding's distance).
 * UINT32_MAX when out of memory. */
static uint32_t locate(const qm_mesh* m, qm_index** index, double fi, double fj, double* z_out)
{
    if (!*index && !(*index = index_build(m)))
        return UINT32_MAX;
    qm_index* ix = *index;
    double lo, z = in_triangle(m, ix->last, fi, fj, &lo);
    *z_out = z;
    if (lo >= 0)
        return ix->last;
    int ci = (int)floor(fi), cj = (int)floor(fj);
    ci = ci < 0 ? 0 : ci > m->n - 1 ? m->n - 1 : ci;
    cj = cj < 0 ? 0 : cj > m->n - 1 ? m->n - 1 : cj;
    const size_t c = (size_t)cj * m->n + ci;
    double best = -INFINITY;
    for (uint32_t k = ix->start[c]; k < ix->start[c + 1]; k++) {
        z = in_triangle(m, ix->tri[k], fi, fj, &lo);
        if (lo > best) {
            best = lo;
            *z_out = z;
            ix->last = ix->tri[k];
            if (lo >= 0)
                break;
        }
    }
    return ix->last;
}

double tp_qm_mesh_height(const qm_mesh* m, qm_index** index, double fi, double fj)
{
    double z;
    return locate(m, index, fi, fj, &z) == UINT32_MAX ? NAN : z;
}

uint32_t tp_qm_mesh_triangle(const qm_mesh* m, qm_index** index, double fi, double fj)
{
    double z;
    return locate(m, index, fi, fj, &z);
}

int tp_qm_points_add(qm_points* c, double fi, double fj, double h, double err)
{
    /* those between `above` and the bound while n < limit, those above the bound up to 4 limit */
    if (!(err > c->above) || c->n >= 4 * c->limit || (!(err > c->bound) && c->n >= c->limit))
        return 1;
    if (c->n == c->cap) {
        const size_t cap = c->cap ? 2 * c->cap : 1024;
        qm_point* p = realloc(c->p, cap * sizeof *p);
        if (!p)
            return 0;
        c->p = p;
        c->cap = cap;
    }
    c->p[c->n++] = (qm_point){fi, fj, h};
    return 1;
}

/* Posts between two exact grid -> WGS84 conversions along each axis of the store's grid. */
#define G 16

typedef struct geo_node {
    double lat, lon, und;
} geo_node;

static geo_node exact_geo(const qm_source* s, double x, double y)
{
    geo_node r = {NAN, NAN, 0};
    double e, n;
    tp_georef_grid_to_proj(s->georef, x, y, &e, &n);
    if (tp_georef_proj_to_geo(s->georef, e, n, &r.lat, &r.lon, NULL) != TP_OK)
        return (geo_node){NAN, NAN, NAN};
    if (s->geoid && tp_geoid_undulation(s->geoid, 1, &r.lat, &r.lon, &r.und, NULL) != TP_OK)
        r.und = NAN;
    return r;
}

/* The tile's rectangle clipped to the store's extent, as a box of grid posts; 0 when empty. */
static int post_box(const qm_source* s, double w, double so, double e, double no, int box[4])
{
    w = fmax(w, s->lon_lo);
    e = fmin(e, s->lon_hi);
    so = fmax(so, s->lat_lo);
    no = fmin(no, s->lat_hi);
    if (!(w < e && so < no))
        return 0;
    double x0 = INFINITY, x1 = -INFINITY, y0 = INFINITY, y1 = -INFINITY;
    for (int k = 0; k <= 64; k++) {
        const double f = k / 64.0;
        const double pts[4][2] = {{so, w + f * (e - w)}, {no, w + f * (e - w)},
                                  {so + f * (no - so), w}, {so + f * (no - so), e}};
        for (int q = 0; q < 4; q++) {
            double pe, pn, gx, gy;
            if (tp_georef_geo_to_proj(s->georef, pts[q][0], pts[q][1], &pe, &pn, NULL) != TP_OK)
                continue;
            tp_georef_proj_to_grid(s->georef, pe, pn, &gx, &gy);
            x0 = fmin(x0, gx);
            x1 = fmax(x1, gx);
            y0 = fmin(y0, gy);
            y1 = fmax(y1, gy);
        }
    }
    /* a box a post wider all round: the edges between the 65 points bow a little */
    box[0] = (int)fmax(0, floor(x0) - 1);
    box[1] = (int)fmax(0, floor(y0) - 1);
    box[2] = (int)fmin(s->width - 1, ceil(x1) + 1);
    box[3] = (int)fmin(s->height - 1, ceil(y1) + 1);
    return box[0] <= box[2] && box[1] <= box[3];
}

int tp_qm_measure_posts(const qm_source* s, const qm_mesh* m, qm_index** index, double west,
                        double south, double east, double north, double* max_err, size_t* posts,
                        qm_points* collect, tp_error* err)
{
    *max_err = 0;
    *posts = 0;
    int box[4];
    if (!post_box(s, west, south, east, north, box))
        return 1;
    const int bw = box[2] - box[0] + 1;
    const int na = (bw - 1 + G - 1) / G + 1; /* nodes a row */
    const double d = (east - west) / m->n;
    geo_node* row0 = malloc((size_t)na * sizeof *row0);
    geo_node* row1 = malloc((size_t)na * sizeof *row1);
    float* z = malloc((size_t)bw * (G + 1) * sizeof *z);
    int ok = 0;
    if (!row0 || !row1 || !z) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        goto done;
    }
    for (int y0 = box[1]; y0 <= box[3]; y0 += G) {
        const int y1 = y0 + G < box[3] ? y0 + G : box[3];
        for (int a = 0; a < na; a++) {
            const int x = box[0] + a * G < box[2] ? box[0] + a * G : box[2];
            row0[a] = exact_geo(s, x, y0);
            row1[a] = exact_geo(s, x, y1);
        }
        const int rows = y1 == y0 ? 1 : (y1 + (y1 == box[3]) - y0); /* the last band: its row */
        if (tp_ground_read_posts(s->ground, box[0], y0, bw, rows, z, NULL, err) != TP_OK)
            goto done;
        for (int r = 0; r < rows; r++) {
            const double ty = y1 == y0 ? 0 : (double)r / (y1 - y0);
            for (int c = 0; c < bw; c++) {
                const float h = z[(size_t)r * bw + c];
                if (h != h)
                    continue;
                const int a = c / G;
                const int xa = box[0] + a * G, xb = xa + G < box[2] ? xa + G : box[2];
                const double tx = xb == xa ? 0 : (double)(box[0] + c - xa) / (xb - xa);
                const int a1 = a + 1 < na ? a + 1 : a;
                const geo_node p00 = row0[a], p10 = row0[a1], p01 = row1[a], p11 = row1[a1];
                const double lat = (1 - ty) * ((1 - tx) * p00.lat + tx * p10.lat) +
                                   ty * ((1 - tx) * p01.lat + tx * p11.lat);
                const double lon = (1 - ty) * ((1 - tx) * p00.lon + tx * p10.lon) +
                                   ty * ((1 - tx) * p01.lon + tx * p11.lon);
                const double und = (1 - ty) * ((1 - tx) * p00.und + tx * p10.und) +
                                   ty * ((1 - tx) * p01.und + tx * p11.und);
                if (!(lon >= west && lon <= east && lat >= south && lat <= north) || und != und)
                    continue;
                const double fi = (lon - west) / d, fj = (north - lat) / d;
                const double mh = tp_qm_mesh_height(m, index, fi, fj);
                const double e = fabs(mh - (h + und));
                if (mh != mh || (collect && !tp_qm_points_add(collect, fi, fj, h + und, e))) {
                    tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
                    goto done;
                }
                *max_err = e > *max_err ? e : *max_err;
                (*posts)++;
            }
        }
        if (y1 == box[3])
            break;
    }
    ok = 1;
done:
    free(row0);
    free(row1);
    free(z);
    return ok;
}
