/* tin.c - error-bounded TIN by greedy insertion into a Delaunay triangulation (Garland &
 * Heckbert 1995; the half-edge layout and the split/flip steps follow mapbox/delatin).
 *
 * Triangle t owns half-edges 3t, 3t+1, 3t+2; half-edge e runs from tri[e] to tri[next(e)] and
 * he[e] is its twin (-1 on the grid's outline). Triangles are never deleted: a split reuses the
 * split triangle's slot, a flip the two slots it replaces, so every slot is live at the end.
 * Internally triangles have orient(a, b, c) < 0 in (column, row), as delatin's.
 *
 * After each insertion the triangles it created (pending) are rasterised (tin_raster.c) once the
 * flips have settled: each gets its worst valid sample (the candidate) and its error; those
 * above the bound go into a max-heap by error. The build ends when the heap is empty.
 *
 * Forced samples (classes, tp__tin_build) are inserted before any error counts: a triangle's
 * first forced sample in scan order is found through per-row lists of them, and while some are
 * left, a triangle without one is deferred rather than scanned (it would mostly be split again
 * before its error counts; a tiled build forces whole tile borders). TP_TIN_CUT_VOIDS' classes and
 * cut are tin_voids.c's. */
#include "tin_int.h"

#include <stdlib.h>
#include <string.h>

#define TV(b, e) ((b)->T[(e) / 3].v[(e) % 3])
#define HE(b, e) ((b)->T[(e) / 3].he[(e) % 3])

/* ---- growth ---- */

static int grow(void** p, size_t* cap, size_t need, size_t elem)
{
    if (need <= *cap)
        return 1;
    size_t c = *cap ? *cap : 64;
    while (c < need)
        c *= 2;
    void* q = realloc(*p, c * elem);
    if (!q)
        return 0;
    *p = q;
    *cap = c;
    return 1;
}

static int reserve_triangles(tin_build* b, size_t need)
{
    if (need <= b->cap_t)
        return 1;
    size_t c = b->cap_t ? b->cap_t : 64;
    while (c < need)
        c *= 2;
    void* p;
    if (!(p = realloc(b->T, c * sizeof *b->T)))
        return 0;
    b->T = p;
    /* the pending list holds at most one entry per triangle */
    if (!(p = realloc(b->pending, c * sizeof *b->pending)))
        return 0;
    b->pending = p;
    b->cap_t = c;
    return 1;
}

/* ---- exact predicates on integer coordinates ---- */

/* > 0 when d lies strictly inside the circumcircle of (a, b, c) taken with orient > 0; the
 * sign flips for orient < 0. Exact in int64 for coordinates below 2^14 (each term is below
 * 2^14 * 2^14 * 2^29); doubles above (the flip is then also guarded by a convexity test). */
static inline double incircle(const tin_build* bd, const int32_t* a, const int32_t* b,
                              const int32_t* c, const int32_t* d)
{
    if (bd->exact64) {
        int64_t adx = a[0] - d[0], ady = a[1] - d[1];
        int64_t bdx = b[0] - d[0], bdy = b[1] - d[1];
        int64_t cdx = c[0] - d[0], cdy = c[1] - d[1];
        int64_t ad = adx * adx + ady * ady, bdd = bdx * bdx + bdy * bdy, cd = cdx * cdx + cdy * cdy;
        int64_t r = adx * (bdy * cd - bdd * cdy) - ady * (bdx * cd - bdd * cdx) +
                    ad * (bdx * cdy - bdy * cdx);
        return r > 0 ? 1.0 : r < 0 ? -1.0 : 0.0;
    }
    double adx = a[0] - d[0], ady = a[1] - d[1];
    double bdx = b[0] - d[0], bdy = b[1] - d[1];
    double cdx = c[0] - d[0], cdy = c[1] - d[1];
    double ad = adx * adx + ady * ady, bdd = bdx * bdx + bdy * bdy, cd = cdx * cdx + cdy * cdy;
    return adx * (bdy * cd - bdd * cdy) - ady * (bdx * cd - bdd * cdx) +
           ad * (bdx * cdy - bdy * cdx);
}

/* ---- heap (max error at the top) ---- */

static void heap_up(tin_build* b, size_t i)
{
    heap_ent h = b->heap[i];
    while (i > 0) {
        size_t p = (i - 1) / 2;
        if (b->heap[p].err >= h.err)
            break;
        b->heap[i] = b->heap[p];
        i = p;
    }
    b->heap[i] = h;
}

static void heap_down(tin_build* b, size_t i)
{
    heap_ent h = b->heap[i];
    for (;;) {
        size_t l = 2 * i + 1;
        if (l >= b->nh)
            break;
        size_t r = l + 1, m = l;
        if (r < b->nh && b->heap[r].err > b->heap[l].err)
            m = r;
        if (b->heap[m].err <= h.err)
            break;
        b->heap[i] = b->heap[m];
        i = m;
    }
    b->heap[i] = h;
}

static int heap_push(tin_build* b, uint32_t t)
{
    if (b->nh == b->cap_h) {
        size_t c = b->cap_h ? 2 * b->cap_h : 1024;
        heap_ent* p = realloc(b->heap, c * sizeof *p);
        if (!p)
            return 0;
        b->heap = p;
        b->cap_h = c;
    }
    b->heap[b->nh] = (heap_ent){b->T[t].err, t, b->T[t].ver};
    heap_up(b, b->nh++);
    return 1;
}

static void heap_pop(tin_build* b)
{
    b->heap[0] = b->heap[--b->nh];
    if (b->nh > 0)
        heap_down(b, 0);
}

/* Drops stale entries from the top; returns 1 when a live triangle is on top. */
static int heap_live_top(tin_build* b)
{
    while (b->nh > 0 && b->heap[0].ver != b->T[b->heap[0].t].ver)
        heap_pop(b);
    return b->nh > 0;
}

/* ---- triangulation ---- */

static uint32_t add_vertex(tin_build* b, int32_t x, int32_t y, float z)
{
    if (b->nv == b->cap_v) {
        size_t c = b->cap_v ? 2 * b->cap_v : 64;
        int32_t* p = realloc(b->vx, c * 2 * sizeof *b->vx);
        if (p)
            b->vx = p;
        float* q = p ? realloc(b->vz, c * sizeof *b->vz) : NULL;
        if (!q) {
            b->oom = 1;
            return 0;
        }
        b->vz = q;
        b->cap_v = c;
    }
    b->vx[2 * b->nv] = x;
    b->vx[2 * b->nv + 1] = y;
    b->vz[b->nv] = z;
    return (uint32_t)b->nv++;
}

static void twin_link(tin_build* b, int32_t e, int32_t twin)
{
    HE(b, e) = twin;
    if (twin >= 0)
        HE(b, twin) = e;
}

/* Writes triangle (a, b, c) with twins (ab, bc, ca) into slot e (a multiple of 3), or a new
 * slot when e < 0; returns its first half-edge. The triangle goes to the pending list. */
static int32_t add_triangle(tin_build* b, uint32_t va, uint32_t vb, uint32_t vc, int32_t ab,
                            int32_t bc, int32_t ca, int32_t e)
{
    if (e < 0) {
        e = (int32_t)(3 * b->nt++); /* capacity reserved by the caller */
        b->T[e / 3].ver = 0;
        b->T[e / 3].pend = 0;
    }
    uint32_t t = (uint32_t)e / 3;
    TV(b, e) = va;
    TV(b, e + 1) = vb;
    TV(b, e + 2) = vc;
    twin_link(b, e, ab);
    twin_link(b, e + 1, bc);
    twin_link(b, e + 2, ca);
    b->T[t].ver++; /* its heap entry, if any, is stale */
    if (!b->T[t].pend) {
        b->T[t].pend = 1;
        b->pending[b->np++] = t;
    }
    return e;
}

static inline int32_t next_e(int32_t e) { return e - e % 3 + (e + 1) % 3; }
static inline int32_t prev_e(int32_t e) { return e - e % 3 + (e + 2) % 3; }

/* Lawson flips from the half-edges on the stack (each a new triangle's edge opposite the new
 * point), depth first as delatin's recursive _legalize. */
static void legalise(tin_build* b)
{
    while (b->ns > 0) {
        int32_t a = b->stack[--b->ns];
        int32_t bo = HE(b, a);
        if (bo < 0)
            continue;
        int32_t a0 = a - a % 3, b0 = bo - bo % 3;
        int32_t al = next_e(a), ar = prev_e(a);
        int32_t bl = prev_e(bo), br = next_e(bo);
        uint32_t p0 = TV(b, ar), pr = TV(b, a), pl = TV(b, al), p1 = TV(b, bl);
        const int32_t *c0 = b->vx + 2 * p0, *cr = b->vx + 2 * pr, *cl = b->vx + 2 * pl,
                      *c1 = b->vx + 2 * p1;
        /* (p0, pr, pl) has orient < 0: p1 inside its circumcircle when incircle < 0 */
        if (!(incircle(b, c0, cr, cl, c1) < 0))
            continue;
        /* the new pair must keep orient < 0 (always, when the test above is exact) */
        if (!(tp__tin_orient(c0, c1, cl) < 0 && tp__tin_orient(c1, c0, cr) < 0))
            continue;
        int32_t hal = HE(b, al), har = HE(b, ar), hbl = HE(b, bl), hbr = HE(b, br);
        int32_t t0 = add_triangle(b, p0, p1, pl, -1, hbl, hal, a0);
        int32_t t1 = add_triangle(b, p1, p0, pr, t0, har, hbr, b0);
        if (!grow((void**)&b->stack, &b->cap_s, b->ns + 2, sizeof *b->stack)) {
            b->oom = 1;
            return;
        }
        b->stack[b->ns++] = t1 + 2; /* popped second, as the recursion's second call */
        b->stack[b->ns++] = t0 + 1;
    }
}

static void push_legalise(tin_build* b, const int32_t* e, int n)
{
    if (!grow((void**)&b->stack, &b->cap_s, b->ns + (size_t)n, sizeof *b->stack)) {
        b->oom = 1;
        return;
    }
    for (int i = n - 1; i >= 0; --i) /* the first is legalised first */
        b->stack[b->ns++] = e[i];
    legalise(b);
}

/* Splits the edge a (of a triangle containing new vertex pn on it) into two, and its twin's
 * triangle too when there is one. */
static void split_edge(tin_build* b, uint32_t pn, int32_t a)
{
    int32_t a0 = a - a % 3, al = next_e(a), ar = prev_e(a);
    uint32_t p0 = TV(b, ar), pr = TV(b, a), pl = TV(b, al);
    int32_t hal = HE(b, al), har = HE(b, ar);
    int32_t bo = HE(b, a);
    if (bo < 0) {
        int32_t t0 = add_triangle(b, pn, p0, pr, -1, har, -1, a0);
        int32_t t1 = add_triangle(b, p0, pn, pl, t0, -1, hal, -1);
        int32_t e[2] = {t0 + 1, t1 + 2};
        push_legalise(b, e, 2);
        return;
    }
    int32_t b0 = bo - bo % 3, bl = prev_e(bo), br = next_e(bo);
    uint32_t p1 = TV(b, bl);
    int32_t hbl = HE(b, bl), hbr = HE(b, br);
    int32_t t0 = add_triangle(b, p0, pr, pn, har, -1, -1, a0);
    int32_t t1 = add_triangle(b, pr, p1, pn, hbr, -1, t0 + 1, b0);
    int32_t t2 = add_triangle(b, p1, pl, pn, hbl, -1, t1 + 1, -1);
    int32_t t3 = add_triangle(b, pl, p0, pn, hal, t0 + 2, t2 + 1, -1);
    int32_t e[4] = {t0, t1, t2, t3};
    push_legalise(b, e, 4);
}

/* Rasterises the pending triangles and queues those above the bound. */
static void flush(tin_build* b)
{
    for (size_t i = 0; i < b->np; ++i) {
        uint32_t t = b->pending[i];
        b->T[t].pend = 0;
        if (!tp__tin_rasterise(b, t)) { /* no forced sample, some left elsewhere: later */
            if (!grow((void**)&b->deferred, &b->cap_d, b->nd + 1, sizeof *b->deferred)) {
                b->oom = 1;
                continue;
            }
            b->deferred[b->nd++] = (heap_ent){0.0f, t, b->T[t].ver};
            continue;
        }
        if (b->T[t].err > b->bound && !heap_push(b, t))
            b->oom = 1;
    }
    b->np = 0;
}

/* Once every forced sample is a vertex: the deferred triangles not rewritten since, scanned. */
static void flush_deferred(tin_build* b)
{
    b->forced_left = 0;
    for (size_t i = 0; i < b->nd; ++i) {
        uint32_t t = b->deferred[i].t;
        if (b->deferred[i].ver != b->T[t].ver)
            continue; /* rewritten: scanned then, or deferred again */
        tp__tin_rasterise(b, t);
        if (b->T[t].err > b->bound && !heap_push(b, t))
            b->oom = 1;
    }
    b->nd = 0;
}

/* Inserts the worst sample of the worst triangle. */
static void step(tin_build* b)
{
    uint32_t t = b->heap[0].t;
    heap_pop(b);
    /* at most two new triangles per insertion (flips add none) */
    if (!reserve_triangles(b, b->nt + 2)) {
        b->oom = 1;
        return;
    }
    uint32_t s = b->T[t].cand;
    int32_t x = (int32_t)(s % (uint32_t)b->w), y = (int32_t)(s / (uint32_t)b->w);
    if (b->cls && b->cls[s] == TIN_FORCE && b->forced_left > 0)
        b->forced_left--;
    uint32_t pn = add_vertex(b, x, y, b->h[s]);
    if (b->oom)
        return;
    int32_t e0 = (int32_t)(3 * t), e1 = e0 + 1, e2 = e0 + 2;
    uint32_t v0 = TV(b, e0), v1 = TV(b, e1), v2 = TV(b, e2);
    const int32_t *a = b->vx + 2 * v0, *bb = b->vx + 2 * v1, *c = b->vx + 2 * v2,
                  *p = b->vx + 2 * pn;
    if (tp__tin_orient(a, bb, p) == 0)
        split_edge(b, pn, e0);
    else if (tp__tin_orient(bb, c, p) == 0)
        split_edge(b, pn, e1);
    else if (tp__tin_orient(c, a, p) == 0)
        split_edge(b, pn, e2);
    else {
        int32_t h0 = HE(b, e0), h1 = HE(b, e1), h2 = HE(b, e2);
        int32_t t0 = add_triangle(b, v0, v1, pn, h0, -1, -1, e0);
        int32_t t1 = add_triangle(b, v1, v2, pn, h1, -1, t0 + 1, -1);
        int32_t t2 = add_triangle(b, v2, v0, pn, h2, t0 + 2, t1 + 1, -1);
        int32_t e[3] = {t0, t1, t2};
        push_legalise(b, e, 3);
    }
    if (!b->oom)
        flush(b);
    if (!b->oom && b->forced_left == 0 && b->nd > 0)
        flush_deferred(b);
}

/* Height for a corner in a void: the nearest valid sample by Chebyshev rings, the first in row
 * order on the first ring that has one. The grid has at least one valid sample. */
static float corner_height(const float* h, int w, int hg, int cx, int cy)
{
    float v = h[(size_t)cy * w + cx];
    if (v == v)
        return v;
    int rmax = w > hg ? w : hg;
    for (int r = 1; r < rmax; ++r)
        for (int y = cy - r; y <= cy + r; ++y) {
            if (y < 0 || y >= hg)
                continue;
            int edge_row = y == cy - r || y == cy + r;
            for (int x = cx - r; x <= cx + r; x += edge_row ? 1 : 2 * r) {
                if (x < 0 || x >= w)
                    continue;
                float s = h[(size_t)y * w + x];
                if (s == s)
                    return s;
            }
        }
    return 0.0f; /* unreachable */
}

static void build_free(tin_build* b)
{
    free(b->vx);
    free(b->vz);
    free(b->T);
    free(b->heap);
    free(b->pending);
    free(b->stack);
    free(b->frow);
    free(b->fx);
    free(b->deferred);
}

void tp_tin_destroy(tp_tin* tin)
{
    if (!tin)
        return;
    free(tin->vertices);
    free(tin->triangles);
    free(tin->triangle_error_m);
    free(tin);
}

/* A TIN of n vertices and m triangles with every array allocated (NULL on failure). */
static tp_tin* tin_alloc(size_t n, size_t m)
{
    tp_tin* t = calloc(1, sizeof *t);
    if (!t)
        return NULL;
    t->vertices = malloc((n ? n : 1) * 3 * sizeof(float));
    t->triangles = malloc((m ? m : 1) * 3 * sizeof(uint32_t));
    t->triangle_error_m = malloc((m ? m : 1) * sizeof(float));
    if (!t->vertices || !t->triangles || !t->triangle_error_m) {
        tp_tin_destroy(t);
        return NULL;
    }
    t->vertex_count = n;
    t->triangle_count = m;
    return t;
}

float tp__tin_bound(double e)
{
    float b = (float)e;
    return (double)b > e ? nextafterf(b, 0.0f) : b;
}

/* The triangulation as it stands, as a tp_tin (NULL when out of memory). */
static tp_tin* current_tin(const tin_build* b)
{
    tp_tin* t = tin_alloc(b->nv, b->nt);
    if (!t)
        return NULL;
    for (size_t i = 0; i < b->nv; ++i) {
        t->vertices[3 * i] = (float)b->vx[2 * i];
        t->vertices[3 * i + 1] = (float)b->vx[2 * i + 1];
        t->vertices[3 * i + 2] = b->vz[i];
    }
    double mx = 0.0;
    for (size_t i = 0; i < b->nt; ++i) {
        /* every slot is live; in tp_tin the order is as stored (orient < 0 in (column, row)) */
        t->triangles[3 * i] = b->T[i].v[0];
        t->triangles[3 * i + 1] = b->T[i].v[1];
        t->triangles[3 * i + 2] = b->T[i].v[2];
        t->triangle_error_m[i] = b->T[i].err;
        mx = b->T[i].err > mx ? b->T[i].err : mx;
    }
    t->max_error_m = mx;
    t->samples_rasterised = b->visited;
    return t;
}

/* tp__tin_build, and with rungs (count > 0, tol decreasing, max_error_m = tol[count - 1]) the
 * triangulation as it stood when the worst error first fell to each tol[j] into rungs[j]. */
static tp_status build(const float* heights, int width, int height, double max_error_m,
                       const uint8_t* cls, int cut, const double* tol, int count, tp_tin** rungs,
                       tp_tin** out, tp_error* err)
{

    tin_build b;
    memset(&b, 0, sizeof b);
    b.h = heights;
    b.cls = cls;
    b.w = width;
    b.hgt = height;
    b.bound_d = max_error_m;
    b.bound = tp__tin_bound(max_error_m);
    b.exact64 = width <= (1 << 14) && height <= (1 << 14);
    if (cls) { /* the forced samples by row (a tiled build forces whole tile borders) */
        size_t nf = 0, n = (size_t)width * (size_t)height;
        for (size_t i = 0; i < n; ++i)
            nf += cls[i] == TIN_FORCE;
        if (nf) {
            if (!(b.frow = malloc(sizeof *b.frow * ((size_t)height + 1))) ||
                !(b.fx = malloc(sizeof *b.fx * nf)))
                goto oom;
            uint32_t k = 0;
            for (int y = 0; y < height; ++y) {
                b.frow[y] = k;
                const uint8_t* row = cls + (size_t)y * width;
                for (int x = 0; x < width; ++x) {
                    if (row[x] != TIN_FORCE)
                        continue;
                    b.fx[k++] = x;
                    /* those that will be inserted: valid, not one of the 4 starting corners */
                    float z = heights[(size_t)y * width + x];
                    int corner = (x == 0 || x == width - 1) && (y == 0 || y == height - 1);
                    b.forced_left += z == z && !corner;
                }
            }
            b.frow[height] = k;
        }
    }

    const int32_t x1 = width - 1, y1 = height - 1;
    if (!reserve_triangles(&b, 64))
        goto oom;
    uint32_t p0 = add_vertex(&b, 0, 0, corner_height(heights, width, height, 0, 0));
    uint32_t p1 = add_vertex(&b, x1, 0, corner_height(heights, width, height, x1, 0));
    uint32_t p2 = add_vertex(&b, 0, y1, corner_height(heights, width, height, 0, y1));
    uint32_t p3 = add_vertex(&b, x1, y1, corner_height(heights, width, height, x1, y1));
    if (b.oom)
        goto oom;
    int32_t t0 = add_triangle(&b, p3, p0, p2, -1, -1, -1, -1);
    add_triangle(&b, p0, p3, p1, t0, -1, -1, -1);
    flush(&b);
    int next = 0; /* the next rung */
    for (;;) {
        while (!b.oom && heap_live_top(&b)) {
            while (next < count && b.forced_left == 0 && b.heap[0].err <= tp__tin_bound(tol[next]))
                if (!(rungs[next++] = current_tin(&b)))
                    b.oom = 1;
            if (!b.oom)
                step(&b);
        }
        if (b.oom || b.nd == 0)
            break;
        flush_deferred(&b); /* (not reached: a forced sample left is in a queued triangle) */
    }
    while (!b.oom && next < count) /* within every rung left */
        if (!(rungs[next++] = current_tin(&b)))
            b.oom = 1;
    if (b.oom)
        goto oom;
    if (count) {
        build_free(&b);
        return TP_OK;
    }
    if (cut) {
        uint32_t* remap = malloc(b.nv * sizeof *remap);
        if (!remap)
            goto oom;
        tp__tin_cut_voids(&b, remap);
        free(remap);
    }

    tp_tin* t = current_tin(&b);
    if (!t)
        goto oom;
    build_free(&b);
    *out = t;
    return TP_OK;
oom:
    build_free(&b);
    for (int j = 0; j < count; j++) {
        tp_tin_destroy(rungs[j]);
        rungs[j] = NULL;
    }
    return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tin: out of memory (%zu triangles)", b.nt);
}

tp_status tp__tin_build(const float* heights, int width, int height, double max_error_m,
                        const uint8_t* cls, int cut, tp_tin** out, tp_error* err)
{
    return build(heights, width, height, max_error_m, cls, cut, NULL, 0, NULL, out, err);
}

tp_status tp__tin_build_rungs(const float* heights, int width, int height, const double* tol,
                              int count, const uint8_t* cls, tp_tin** rungs, tp_error* err)
{
    assert(count >= 1);
    for (int j = 0; j < count; j++)
        rungs[j] = NULL;
    return build(heights, width, height, tol[count - 1], cls, 0, tol, count, rungs, NULL, err);
}

tp_status tp_tin_build(const float* heights, size_t height_count, int width, int height,
                       double max_error_m, unsigned flags, tp_tin** out, tp_error* err)
{
    assert(out);
    if (width < 1 || height < 1)
        return tp__fail(err, TP_ERR_INVALID_ARG, "tin: expected a grid of at least 1x1, got %dx%d",
                        width, height);
    assert(heights && height_count == (size_t)width * (size_t)height);
    if ((uint64_t)width * (uint64_t)height >= ((uint64_t)1 << 32))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tin: expected fewer than 2^32 samples, got %dx%d", width, height);
    if (!(max_error_m >= 0.0) || !isfinite(max_error_m))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tin: expected a finite max error >= 0 m, got %g", max_error_m);

    size_t valid = 0;
    for (size_t i = 0; i < height_count; ++i)
        valid += heights[i] == heights[i];

    /* no area: every valid sample, no triangle; no valid sample: nothing */
    if (width == 1 || height == 1 || valid == 0) {
        size_t n = (width == 1 || height == 1) ? valid : 0;
        tp_tin* t = tin_alloc(n, 0);
        if (!t)
            return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tin: out of memory for %zu vertices", n);
        size_t k = 0;
        for (size_t i = 0; i < height_count && n; ++i)
            if (heights[i] == heights[i]) {
                t->vertices[3 * k] = (float)(i % (size_t)width);
                t->vertices[3 * k + 1] = (float)(i / (size_t)width);
                t->vertices[3 * k + 2] = heights[i];
                ++k;
            }
        *out = t;
        return TP_OK;
    }

    uint8_t* cls = NULL;
    int cut = (flags & TP_TIN_CUT_VOIDS) && valid < height_count;
    if (cut) {
        if (!(cls = calloc(height_count, 1)))
            return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tin: out of memory for %dx%d classes",
                            width, height);
        if (!tp__tin_void_classes(heights, width, height, cls)) {
            free(cls); /* no valid cell beside a void: nothing forced */
            cls = NULL;
        }
    }
    tp_status st = tp__tin_build(heights, width, height, max_error_m, cls, cut, out, err);
    free(cls);
    return st;
}
