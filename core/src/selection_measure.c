/* selection_measure.c - the exact error of what a selection draws: its stitched triangles
 * rasterised over the sample lattice and compared, sample by sample, with the decoded grid
 * (vertically, or as projected on screen).
 *
 * These functions take a const selection and write nothing in it: their scratch (vertex and
 * triangle buffers, the visited-sample bitmap) belongs to each call, so that several threads
 * may measure one selection at once.
 */
#include "selection_int.h"

#include <string.h>

typedef struct {
    const tp_terrain* t;
    uint8_t* seen; /* one bit per grid sample; NULL when measuring one patch */
    const tp__view* view;
    double zscale; /* screen measures: the drawn surface's vertical exaggeration */
    double max, sum;
    size_t count;
    tp_vertex* vbuf; /* one patch at level n */
    uint32_t* tbuf;  /* its triangles */
} measure;

static void measure_free(measure* m)
{
    tp__free(&m->t->alloc, m->vbuf);
    tp__free(&m->t->alloc, m->tbuf);
    tp__free(&m->t->alloc, m->seen);
}

/* Allocates the per-call scratch of m (the seen bitmap too when dedup is set). */
static tp_status measure_init(measure* m, const tp_terrain* t, int dedup)
{
    size_t v = ((size_t)1 << t->n) + 1;
    m->t = t;
    m->vbuf = tp__alloc(&t->alloc, v * v, sizeof *m->vbuf);
    m->tbuf = tp__alloc(&t->alloc, 3 * 2 * (v - 1) * (v - 1), sizeof *m->tbuf);
    m->seen = dedup ? tp__calloc(&t->alloc, ((size_t)t->w * t->h + 7) / 8, 1) : NULL;
    if (!m->vbuf || !m->tbuf || (dedup && !m->seen)) {
        measure_free(m);
        return TP_ERR_OUT_OF_MEMORY;
    }
    return TP_OK;
}


static int first_visit(measure* m, int x, int y)
{
    if (!m->seen) /* one patch: a maximum needs no deduplication */
        return 1;
    size_t i = (size_t)y * m->t->w + x;
    if (m->seen[i >> 3] >> (i & 7) & 1)
        return 0;
    m->seen[i >> 3] |= (uint8_t)(1u << (i & 7));
    return 1;
}

static void vertical_sample(int x, int y, double z, void* user)
{
    measure* m = user;
    int32_t q = tp__q(m->t, x, y);
    if (q == INT32_MIN || !first_visit(m, x, y))
        return;
    double e = fabs(z - q) * m->t->step;
    m->max = e > m->max ? e : m->max;
    m->sum += e * e;
    m->count++;
}

static void screen_sample(int x, int y, double z, void* user)
{
    measure* m = user;
    const tp__view* v = m->view;
    int32_t q = tp__q(m->t, x, y);
    if (q == INT32_MIN)
        return;
    double ws[3], wd[3];
    tp_terrain_grid_to_world(m->t, x, y, &ws[0], &ws[1]);
    wd[0] = ws[0];
    wd[1] = ws[1];
    ws[2] = q * m->t->step * m->zscale;
    wd[2] = z * m->t->step * m->zscale;
    /* Only samples inside the view and in front of the near plane count. */
    double e = tp__screen_error_px(v, ws, wd);
    if (isnan(e) || !first_visit(m, x, y))
        return;
    m->max = e > m->max ? e : m->max;
    m->sum += e * e;
    m->count++;
}

/* Rasterises patch p's triangles at level k (neighbour levels nb) through fn. */
static void measure_patch(measure* m, tp__sample_fn fn, int p, int k, const int nb[4])
{
    const tp_terrain* t = m->t;
    size_t v = ((size_t)1 << t->n) + 1, vcap = v * v, tcap = 2 * (v - 1) * (v - 1);
    tp_patch_vertices(t, p, k, nb, m->vbuf, vcap);
    size_t nt = tp_patch_triangles(m->vbuf, k, m->tbuf, tcap);
    for (size_t i = 0; i < nt; i++) {
        const tp_vertex* a = &m->vbuf[m->tbuf[3 * i]];
        const tp_vertex* b = &m->vbuf[m->tbuf[3 * i + 1]];
        const tp_vertex* c = &m->vbuf[m->tbuf[3 * i + 2]];
        int32_t pa[2] = {a->x, a->y}, pb[2] = {b->x, b->y}, pcv[2] = {c->x, c->y};
        tp__raster_triangle(pa, pb, pcv, tp__q(t, a->x, a->y), tp__q(t, b->x, b->y),
                            tp__q(t, c->x, c->y), fn, m);
    }
}

tp_status tp_selection_patch_screen_error(const tp_selection* s, const tp_camera* cam, int patch,
                                          int k, double* out_px)
{
    assert(s && cam && out_px && patch >= 0 && patch < s->count && k >= 0 && k <= s->t->n);
    tp__view v;
    tp__view_from_camera(cam, &v);
    measure m = {0};
    m.view = &v;
    m.zscale = s->zscale;
    tp_status st = measure_init(&m, s->t, 0);
    if (st != TP_OK)
        return st;
    int nb[4];
    tp_selection_neighbor_levels(s, patch, nb);
    measure_patch(&m, screen_sample, patch, k, nb);
    measure_free(&m);
    *out_px = m.max;
    return TP_OK;
}

static tp_status measure_drawn(const tp_selection* s, measure* m, tp__sample_fn fn)
{
    tp_status st = measure_init(m, s->t, 1);
    if (st != TP_OK)
        return st;
    for (int p = 0; p < s->count; p++) {
        if (!s->visible[p])
            continue;
        int nb[4];
        tp_selection_neighbor_levels(s, p, nb);
        measure_patch(m, fn, p, s->level[p], nb);
    }
    measure_free(m);
    return TP_OK;
}

tp_status tp_selection_measure_error(const tp_selection* s, tp_error_measure* out)
{
    assert(s && out);
    measure m = {0};
    tp_status st = measure_drawn(s, &m, vertical_sample);
    if (st != TP_OK)
        return st;
    out->max_error_m = m.max;
    out->rms_error_m = m.count ? sqrt(m.sum / m.count) : 0;
    out->samples = m.count;
    return TP_OK;
}

tp_status tp_selection_measure_screen_error(const tp_selection* s, const tp_camera* cam,
                                            double* max_px, double* rms_px, size_t* samples)
{
    assert(s && cam);
    tp__view v;
    tp__view_from_camera(cam, &v);
    measure m = {0};
    m.view = &v;
    m.zscale = s->zscale;
    tp_status st = measure_drawn(s, &m, screen_sample);
    if (st != TP_OK)
        return st;
    if (max_px)
        *max_px = m.max;
    if (rms_px)
        *rms_px = m.count ? sqrt(m.sum / m.count) : 0;
    if (samples)
        *samples = m.count;
    return TP_OK;
}

/* ---- one patch against reference heights (the max-error LoD mode) ---- */

typedef struct {
    const tp_terrain* t;
    const float* ref; /* src_width x src_height, or NULL for the decoded grid */
    double max;
} ref_error;

static void ref_sample(int x, int y, double z, void* user)
{
    ref_error* r = user;
    const tp_terrain_info* in = &r->t->info;
    double s = !r->ref                                   ? tp_terrain_sample(r->t, x, y)
             : x < in->src_width && y < in->src_height ? r->ref[(size_t)y * in->src_width + x]
                                                       : NAN;
    if (isnan(s))
        return;
    double d = fabs(z - s);
    r->max = d > r->max ? d : r->max;
}

double tp__patch_vertical_error(const tp_terrain* t, int p, int k, const int nb[4],
                                const float* ref, tp_vertex* vbuf, uint32_t* tbuf)
{
    size_t v = ((size_t)1 << t->n) + 1, vcap = v * v, tcap = 2 * (v - 1) * (v - 1);
    tp_patch_vertices(t, p, k, nb, vbuf, vcap);
    size_t nt = tp_patch_triangles(vbuf, k, tbuf, tcap);
    ref_error r = {t, ref, 0};
    for (size_t i = 0; i < nt; i++) {
        const tp_vertex* a = &vbuf[tbuf[3 * i]];
        const tp_vertex* b = &vbuf[tbuf[3 * i + 1]];
        const tp_vertex* c = &vbuf[tbuf[3 * i + 2]];
        int32_t pa[2] = {a->x, a->y}, pb[2] = {b->x, b->y}, pc[2] = {c->x, c->y};
        /* The heights the vertex data carries (what an exported mesh holds), in metres. */
        tp__raster_triangle(pa, pb, pc, a->z_m, b->z_m, c->z_m, ref_sample, &r);
    }
    return r.max;
}
