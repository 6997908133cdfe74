/* qm_refine.c - a quantized-mesh tile's TIN refined until the given points (the store's posts and
 * the lattice posts a measure found above the bound) are within it (see qm_tile.h): greedy, the
 * worst point first, each inserted as a vertex at its own u, v code, Delaunay flips around it;
 * the tile's sides are never touched, so the neighbours' shared edges stay as they were. */
#include "qm_tile.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define NONE UINT32_MAX
#define CODES_PER_CELL (TP_QMESH_MAX_CODE / TP_QM_CELLS)

typedef struct heap_item {
    double e;
    uint32_t t, stamp;
} heap_item;

typedef struct rf {
    qm_work* w;
    size_t cap_t;
    int32_t* adj;        /* 3 per triangle: the triangle across edge k (v[k] -> v[k+1]), -1 none */
    uint32_t* head;      /* per triangle: its first point, NONE */
    uint32_t* stamp;     /* per triangle: bumped when it changes (stale heap items) */
    uint8_t* in_set;     /* per triangle: in the current operation's set */
    const qm_point* pts;
    size_t np;
    uint32_t* next;      /* per point: the next of its triangle */
    uint8_t* dead;       /* per point: inserted or stuck */
    heap_item* heap;
    size_t nh, cap_h;
    uint32_t* set;       /* the triangles an insertion changed */
    size_t nset, cap_set;
    uint32_t* gathered;  /* their points */
    size_t ng, cap_g;
    uint32_t* stack;     /* edges to legalise: triangle ids (their edge 0) */
    size_t ns, cap_s;
    double bound, step;
    qm_height_fn height;
    void* ctx;
    int sgn;             /* the triangles' orientation in (u, v) */
    double stuck_max;
} rf;

static int grow(void** p, size_t* cap, size_t need, size_t size)
{
    if (need <= *cap)
        return 1;
    size_t n = *cap ? *cap : 64;
    while (n < need)
        n *= 2;
    void* q = realloc(*p, n * size);
    if (!q)
        return 0;
    *p = q;
    *cap = n;
    return 1;
}

static long long px_(const rf* r, uint32_t v) { return r->w->u[v]; }
static long long py_(const rf* r, uint32_t v) { return r->w->v[v]; }

/* Orientation of (a, b) -> (c) in codes, signed by the mesh's: > 0 left of the mesh's sense. */
static long long orient(const rf* r, uint32_t a, uint32_t b, long long cx, long long cy)
{
    const long long ax = px_(r, a), ay = py_(r, a), bx = px_(r, b), by = py_(r, b);
    return r->sgn * ((bx - ax) * (cy - ay) - (by - ay) * (cx - ax));
}

/* Whether d lies strictly inside the circle through triangle t's vertices (exact). */
static int in_circle(const rf* r, const uint32_t* t, uint32_t d)
{
    const long long dx = px_(r, d), dy = py_(r, d);
    long long x[3], y[3];
    for (int k = 0; k < 3; k++) {
        x[k] = px_(r, t[k]) - dx;
        y[k] = py_(r, t[k]) - dy;
    }
    __int128 det = 0;
    for (int k = 0; k < 3; k++) {
        const int a = (k + 1) % 3, b = (k + 2) % 3;
        det += (__int128)(x[k] * x[k] + y[k] * y[k]) * (x[a] * y[b] - x[b] * y[a]);
    }
    return r->sgn * det > 0;
}

/* Point k's barycentric weights in triangle t: the smallest in *lo, its error returned. */
static double point_in(const rf* r, uint32_t t, uint32_t k, double* lo)
{
    const uint32_t* v = r->w->tris + 3 * (size_t)t;
    const double x = r->pts[k].fi * CODES_PER_CELL;
    const double y = TP_QMESH_MAX_CODE - r->pts[k].fj * CODES_PER_CELL;
    const double ax = px_(r, v[0]), ay = py_(r, v[0]);
    const double bx = px_(r, v[1]) - ax, by = py_(r, v[1]) - ay;
    const double cx = px_(r, v[2]) - ax, cy = py_(r, v[2]) - ay;
    const double det = bx * cy - cx * by, qx = x - ax, qy = y - ay;
    const double wb = (qx * cy - cx * qy) / det, wc = (bx * qy - qx * by) / det, wa = 1 - wb - wc;
    *lo = fmin(wa, fmin(wb, wc));
    const double z = (wa * (double)r->w->hq[v[0]] + wb * (double)r->w->hq[v[1]] +
                      wc * (double)r->w->hq[v[2]]) * r->step;
    return fabs(z - r->pts[k].h);
}

static void heap_push(rf* r, heap_item it)
{
    size_t i = r->nh++;
    while (i > 0) {
        size_t p = (i - 1) / 2;
        if (r->heap[p].e >= it.e)
            break;
        r->heap[i] = r->heap[p];
        i = p;
    }
    r->heap[i] = it;
}

static heap_item heap_pop(rf* r)
{
    heap_item top = r->heap[0], last = r->heap[--r->nh];
    size_t i = 0;
    for (;;) {
        size_t c = 2 * i + 1;
        if (c >= r->nh)
            break;
        if (c + 1 < r->nh && r->heap[c + 1].e > r->heap[c].e)
            c++;
        if (r->heap[c].e <= last.e)
            break;
        r->heap[i] = r->heap[c];
        i = c;
    }
    if (r->nh)
        r->heap[i] = last;
    return top;
}

/* Triangle t's worst live point: pushed when above the bound. 0: out of memory. */
static int rate(rf* r, uint32_t t)
{
    double worst = -1, lo;
    for (uint32_t k = r->head[t]; k != NONE; k = r->next[k])
        if (!r->dead[k])
            worst = fmax(worst, point_in(r, t, k, &lo));
    r->stamp[t]++;
    if (!(worst > r->bound))
        return 1;
    if (!grow((void**)&r->heap, &r->cap_h, r->nh + 1, sizeof *r->heap))
        return 0;
    heap_push(r, (heap_item){worst, t, r->stamp[t]});
    return 1;
}

/* Adds t to the operation's set, taking its points. */
static int take(rf* r, uint32_t t)
{
    if (r->in_set[t])
        return 1;
    if (!grow((void**)&r->set, &r->cap_set, r->nset + 1, sizeof *r->set))
        return 0;
    r->in_set[t] = 1;
    r->set[r->nset++] = t;
    for (uint32_t k = r->head[t]; k != NONE; k = r->next[k]) {
        if (r->dead[k])
            continue;
        if (!grow((void**)&r->gathered, &r->cap_g, r->ng + 1, sizeof *r->gathered))
            return 0;
        r->gathered[r->ng++] = k;
    }
    r->head[t] = NONE;
    return 1;
}

/* A new triangle id (its slot grown), taken into the set. NONE when out of memory. */
static uint32_t new_tri(rf* r)
{
    qm_work* w = r->w;
    const size_t t = w->nt;
    if (t + 1 >= NONE)
        return NONE;
    if (t + 1 > r->cap_t) {
        size_t cap = r->cap_t * 2, c3 = w->cap_t;
        if (!grow((void**)&w->tris, &c3, 3 * cap, sizeof *w->tris))
            return NONE;
        w->cap_t = c3;
        int32_t* adj = realloc(r->adj, 3 * cap * sizeof *adj);
        if (adj)
            r->adj = adj;
        uint32_t* head = realloc(r->head, cap * sizeof *head);
        if (head)
            r->head = head;
        uint32_t* st = realloc(r->stamp, cap * sizeof *st);
        if (st)
            r->stamp = st;
        uint8_t* in = realloc(r->in_set, cap);
        if (in)
            r->in_set = in;
        if (!adj || !head || !st || !in)
            return NONE;
        r->cap_t = cap;
    }
    w->nt++;
    r->head[t] = NONE;
    r->stamp[t] = 0;
    r->in_set[t] = 0;
    return take(r, (uint32_t)t) ? (uint32_t)t : NONE;
}

static void set_tri(rf* r, uint32_t t, uint32_t a, uint32_t b, uint32_t c, int32_t na, int32_t nb,
                    int32_t nc)
{
    uint32_t* v = r->w->tris + 3 * (size_t)t;
    v[0] = a, v[1] = b, v[2] = c;
    r->adj[3 * t] = na, r->adj[3 * t + 1] = nb, r->adj[3 * t + 2] = nc;
}

/* The neighbour o, which pointed to old across one edge, now points to now. */
static void repoint(rf* r, int32_t o, uint32_t old, uint32_t now)
{
    if (o < 0)
        return;
    for (int k = 0; k < 3; k++)
        if (r->adj[3 * o + k] == (int32_t)old) {
            r->adj[3 * o + k] = (int32_t)now;
            return;
        }
}

static int push_edge(rf* r, uint32_t t)
{
    if (!grow((void**)&r->stack, &r->cap_s, r->ns + 1, sizeof *r->stack))
        return 0;
    r->stack[r->ns++] = t;
    return 1;
}

/* Lawson's flips: every triangle on the stack has the new vertex at 2 and the edge to test at 0. */
static int legalise(rf* r)
{
    while (r->ns) {
        const uint32_t t = r->stack[--r->ns];
        const int32_t o = r->adj[3 * t];
        if (o < 0)
            continue;
        uint32_t* tv = r->w->tris + 3 * (size_t)t;
        const uint32_t* ov = r->w->tris + 3 * (size_t)o;
        int g = 0;
        while (g < 3 && r->adj[3 * o + g] != (int32_t)t)
            g++;
        if (g == 3)
            continue;
        const uint32_t a = tv[0], b = tv[1], p = tv[2], q = ov[(g + 2) % 3];
        if (!in_circle(r, tv, q) || orient(r, a, q, px_(r, p), py_(r, p)) <= 0 ||
            orient(r, q, b, px_(r, p), py_(r, p)) <= 0)
            continue;
        if (!take(r, (uint32_t)o))
            return 0;
        const int32_t o_aq = r->adj[3 * o + (g + 1) % 3], o_qb = r->adj[3 * o + (g + 2) % 3];
        const int32_t t_bp = r->adj[3 * t + 1], t_pa = r->adj[3 * t + 2];
        set_tri(r, t, a, q, p, o_aq, o, t_pa);
        set_tri(r, (uint32_t)o, q, b, p, o_qb, t_bp, (int32_t)t);
        repoint(r, o_aq, (uint32_t)o, t);
        repoint(r, t_bp, t, (uint32_t)o);
        if (!push_edge(r, t) || !push_edge(r, (uint32_t)o))
            return 0;
    }
    return 1;
}

/* Splits t (a, b, c) at the new vertex p inside it. */
static int split_inside(rf* r, uint32_t t, uint32_t p)
{
    const uint32_t n1 = new_tri(r), n2 = n1 == NONE ? NONE : new_tri(r);
    if (n2 == NONE)
        return 0;
    const uint32_t* v = r->w->tris + 3 * (size_t)t;
    const uint32_t a = v[0], b = v[1], c = v[2];
    const int32_t ab = r->adj[3 * t], bc = r->adj[3 * t + 1], ca = r->adj[3 * t + 2];
    set_tri(r, t, a, b, p, ab, (int32_t)n1, (int32_t)n2);
    set_tri(r, n1, b, c, p, bc, (int32_t)n2, (int32_t)t);
    set_tri(r, n2, c, a, p, ca, (int32_t)t, (int32_t)n1);
    repoint(r, bc, t, n1);
    repoint(r, ca, t, n2);
    return push_edge(r, t) && push_edge(r, n1) && push_edge(r, n2) && legalise(r);
}

/* Splits the edge e of t at the new vertex p on it: t and its neighbour in two each, or t
 * alone on the tile's outline (a side vertex). */
static int split_edge(rf* r, uint32_t t, int e, uint32_t p)
{
    const int32_t n = r->adj[3 * t + e];
    if (n < 0) {
        const uint32_t t2 = new_tri(r);
        if (t2 == NONE)
            return 0;
        const uint32_t* tv = r->w->tris + 3 * (size_t)t;
        const uint32_t a = tv[e], b = tv[(e + 1) % 3], c = tv[(e + 2) % 3];
        const int32_t bc = r->adj[3 * t + (e + 1) % 3], ca = r->adj[3 * t + (e + 2) % 3];
        set_tri(r, t, c, a, p, ca, -1, (int32_t)t2);
        set_tri(r, t2, b, c, p, bc, (int32_t)t, -1);
        repoint(r, bc, t, t2);
        return push_edge(r, t) && push_edge(r, t2) && legalise(r);
    }
    if (!take(r, (uint32_t)n))
        return 0;
    const uint32_t t2 = new_tri(r), n2 = t2 == NONE ? NONE : new_tri(r);
    if (n2 == NONE)
        return 0;
    const uint32_t* tv = r->w->tris + 3 * (size_t)t;
    const uint32_t* nv = r->w->tris + 3 * (size_t)n;
    int f = 0;
    while (f < 3 && r->adj[3 * n + f] != (int32_t)t)
        f++;
    const uint32_t a = tv[e], b = tv[(e + 1) % 3], c = tv[(e + 2) % 3], d = nv[(f + 2) % 3];
    const int32_t bc = r->adj[3 * t + (e + 1) % 3], ca = r->adj[3 * t + (e + 2) % 3];
    const int32_t ad = r->adj[3 * n + (f + 1) % 3], db = r->adj[3 * n + (f + 2) % 3];
    set_tri(r, t, c, a, p, ca, n, (int32_t)t2);
    set_tri(r, t2, b, c, p, bc, (int32_t)t, (int32_t)n2);
    set_tri(r, (uint32_t)n, a, d, p, ad, (int32_t)n2, (int32_t)t);
    set_tri(r, n2, d, b, p, db, (int32_t)t2, n);
    repoint(r, bc, t, t2);
    repoint(r, db, (uint32_t)n, n2);
    return push_edge(r, t) && push_edge(r, t2) && push_edge(r, (uint32_t)n) &&
           push_edge(r, n2) && legalise(r);
}

/* A vertex at code (x, y) with height hq (steps); its index, NONE when out of memory. */
static uint32_t new_vertex(rf* r, long long x, long long y, long long hq)
{
    qm_work* w = r->w;
    size_t cu = w->cap_v, cv = w->cap_v, ch = w->cap_v;
    if (w->nv + 1 >= NONE || !grow((void**)&w->u, &cu, w->nv + 1, sizeof *w->u) ||
        !grow((void**)&w->v, &cv, w->nv + 1, sizeof *w->v) ||
        !grow((void**)&w->hq, &ch, w->nv + 1, sizeof *w->hq))
        return NONE;
    w->cap_v = cu < cv ? (cu < ch ? cu : ch) : (cv < ch ? cv : ch);
    w->u[w->nv] = (uint16_t)x;
    w->v[w->nv] = (uint16_t)y;
    w->hq[w->nv] = hq;
    return (uint32_t)w->nv++;
}

/* Inserts point k (the worst of t). 1 done (or stuck: k marked dead), 0 out of memory, -1 the
 * surface's read failed (err set by the height function). */
static int insert(rf* r, uint32_t t, uint32_t k, double e)
{
    const qm_point* pt = &r->pts[k];
    long long x = llround(pt->fi * CODES_PER_CELL);
    long long y = llround(TP_QMESH_MAX_CODE - pt->fj * CODES_PER_CELL);
    /* never on the tile's sides (the neighbours share them) */
    x = x < 1 ? 1 : x > TP_QMESH_MAX_CODE - 1 ? TP_QMESH_MAX_CODE - 1 : x;
    y = y < 1 ? 1 : y > TP_QMESH_MAX_CODE - 1 ? TP_QMESH_MAX_CODE - 1 : y;
    /* the code's triangle: t or a few steps across its edges (the rounding can leave t) */
    const uint32_t t0 = t;
    int where = -2; /* -1 inside t, 0..2 on that edge of t, -2 stuck */
    for (int steps = 0; steps < 8; steps++) {
        const uint32_t* v = r->w->tris + 3 * (size_t)t;
        int out = -1, zero = 0, on = -1;
        for (int s = 0; s < 3; s++) {
            const long long o = orient(r, v[s], v[(s + 1) % 3], x, y);
            if (o < 0 && out < 0)
                out = s;
            if (o == 0)
                zero++, on = s;
        }
        if (out >= 0) {
            if (r->adj[3 * t + out] < 0)
                break;
            t = (uint32_t)r->adj[3 * t + out];
            continue;
        }
        /* on a vertex, or on an edge of the tile's outline: stuck */
        if (zero < 2 && (on < 0 || r->adj[3 * t + on] >= 0))
            where = zero ? on : -1;
        break;
    }
    r->nset = r->ng = 0;
    if (where == -2) { /* a vertex is already there: the point stays as it is */
        r->dead[k] = 1;
        r->stuck_max = fmax(r->stuck_max, e);
        return rate(r, t0);
    }
    /* the vertex on the surface at its code (the post's own height where there is none) */
    double h = NAN;
    if (!r->height(r->ctx, x / (double)CODES_PER_CELL,
                   (TP_QMESH_MAX_CODE - y) / (double)CODES_PER_CELL, &h))
        return -1;
    const uint32_t p = new_vertex(r, x, y, llround((isfinite(h) ? h : pt->h) / r->step));
    if (p == NONE || !take(r, t))
        return 0;
    r->dead[k] = 1;
    if (!(where < 0 ? split_inside(r, t, p) : split_edge(r, t, where, p)))
        return 0;
    /* the set's points into its new triangles, which cover what the old ones covered */
    for (size_t g = 0; g < r->ng; g++) {
        const uint32_t q = r->gathered[g];
        double best = -INFINITY, lo;
        uint32_t at = r->set[0];
        for (size_t s = 0; s < r->nset; s++) {
            point_in(r, r->set[s], q, &lo);
            if (lo > best)
                best = lo, at = r->set[s];
        }
        r->next[q] = r->head[at];
        r->head[at] = q;
    }
    for (size_t s = 0; s < r->nset; s++) {
        r->in_set[r->set[s]] = 0;
        if (!rate(r, r->set[s]))
            return 0;
    }
    return 1;
}

/* The triangles' neighbours, from their shared edges (a hash of the edges). */
static int neighbours(rf* r)
{
    const size_t ne = 3 * r->w->nt;
    /* a hash of (lo, hi) -> half-edge: open addressing */
    size_t cap = 1;
    while (cap < 2 * ne)
        cap <<= 1;
    uint64_t* hk = malloc(cap * sizeof *hk);
    uint32_t* hv = malloc(cap * sizeof *hv);
    if (!hk || !hv) {
        free(hk), free(hv);
        return 0;
    }
    memset(hk, 0xff, cap * sizeof *hk);
    for (size_t h = 0; h < ne; h++) {
        const size_t t = h / 3;
        const int k = (int)(h % 3);
        const uint64_t a = r->w->tris[3 * t + k], b = r->w->tris[3 * t + (k + 1) % 3];
        const uint64_t key = a < b ? a << 32 | b : b << 32 | a;
        size_t s = (size_t)((key * 0x9E3779B97F4A7C15ull) >> 20) & (cap - 1);
        r->adj[h] = -1;
        while (hk[s] != UINT64_MAX && hk[s] != key)
            s = (s + 1) & (cap - 1);
        if (hk[s] == key) {
            const uint32_t o = hv[s];
            r->adj[h] = (int32_t)(o / 3);
            r->adj[o] = (int32_t)t;
            hk[s] = UINT64_MAX - 1; /* matched: a third use of the edge would be a broken mesh */
        } else {
            hk[s] = key;
            hv[s] = (uint32_t)h;
        }
    }
    free(hk), free(hv);
    return 1;
}

/* The refinement's state over w for n points: neighbours, orientation. 0 when out of memory. */
static int rf_init(rf* r, qm_work* w, size_t n)
{
    r->w = w;
    /* w->tris grows with the first new triangle (a mesh of the caller's may point to it) */
    r->cap_t = w->nt;
    r->adj = malloc(3 * r->cap_t * sizeof *r->adj);
    r->head = malloc(r->cap_t * sizeof *r->head);
    r->stamp = calloc(r->cap_t, sizeof *r->stamp);
    r->in_set = calloc(r->cap_t, 1);
    r->next = malloc((n ? n : 1) * sizeof *r->next);
    r->dead = calloc(n ? n : 1, 1);
    if (!r->adj || !r->head || !r->stamp || !r->in_set || !r->next || !r->dead || !neighbours(r))
        return 0;
    const uint32_t* v = w->tris;
    const long long o = (w->u[v[1]] - (long long)w->u[v[0]]) * (w->v[v[2]] - (long long)w->v[v[0]]) -
                        (w->v[v[1]] - (long long)w->v[v[0]]) * (w->u[v[2]] - (long long)w->u[v[0]]);
    r->sgn = o > 0 ? 1 : -1;
    for (size_t t = 0; t < w->nt; t++)
        r->head[t] = NONE;
    return 1;
}

static void rf_free(rf* r)
{
    free(r->adj), free(r->head), free(r->stamp), free(r->in_set), free(r->next), free(r->dead);
    free(r->heap), free(r->set), free(r->gathered), free(r->stack);
}

/* Whether code (x, y) lies strictly inside the outline edge e of t. */
static int on_outline_edge(const rf* r, uint32_t t, int e, long long x, long long y)
{
    if (r->adj[3 * t + e] >= 0)
        return 0;
    const uint32_t* v = r->w->tris + 3 * (size_t)t;
    const uint32_t a = v[e], b = v[(e + 1) % 3];
    if (orient(r, a, b, x, y) != 0)
        return 0;
    const long long ax = px_(r, a), ay = py_(r, a), bx = px_(r, b), by = py_(r, b);
    return (x - ax) * (x - bx) + (y - ay) * (y - by) < 0;
}

int tp_qm_insert_sides(qm_work* w, const qm_side_vertex* sv, size_t n, tp_error* err)
{
    rf r;
    memset(&r, 0, sizeof r);
    int ok = rf_init(&r, w, 0);
    for (size_t k = 0; k < n && ok; k++) {
        uint32_t t = NONE;
        int e = 0;
        for (size_t i = 0; i < w->nt && t == NONE; i++)
            for (e = 0; e < 3; e++)
                if (on_outline_edge(&r, (uint32_t)i, e, sv[k].u, sv[k].v)) {
                    t = (uint32_t)i;
                    break;
                }
        if (t == NONE) /* a vertex there already */
            continue;
        r.nset = r.ng = 0;
        const uint32_t p = new_vertex(&r, sv[k].u, sv[k].v, sv[k].hq);
        ok = p != NONE && take(&r, t) && split_edge(&r, t, e, p);
        for (size_t s = 0; s < r.nset; s++)
            r.in_set[r.set[s]] = 0;
    }
    if (!ok)
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory adding a tile's side vertices");
    rf_free(&r);
    return ok;
}

int tp_qm_refine(qm_work* w, const qm_mesh* m, qm_index** index, const qm_point* pts, size_t n,
                 double bound_m, double step_m, qm_height_fn height, void* ctx, size_t* inserted,
                 double* stuck_m, tp_error* err)
{
    rf r;
    memset(&r, 0, sizeof r);
    r.pts = pts, r.np = n, r.bound = bound_m, r.step = step_m;
    r.height = height, r.ctx = ctx;
    int read_failed = 0;
    *inserted = 0;
    *stuck_m = 0;
    const size_t nv0 = w->nv;
    int ok = 0;
    if (!rf_init(&r, w, n))
        goto done;
    for (size_t k = 0; k < n; k++) {
        const uint32_t t = tp_qm_mesh_triangle(m, index, pts[k].fi, pts[k].fj);
        if (t == NONE)
            goto done;
        r.next[k] = r.head[t];
        r.head[t] = (uint32_t)k;
    }
    for (size_t t = 0; t < w->nt; t++)
        if (!rate(&r, (uint32_t)t))
            goto done;
    while (r.nh) {
        const heap_item it = heap_pop(&r);
        if (it.stamp != r.stamp[it.t])
            continue;
        /* its worst point, again (the item says which triangle) */
        double worst = -1, lo;
        uint32_t k = NONE;
        for (uint32_t q = r.head[it.t]; q != NONE; q = r.next[q])
            if (!r.dead[q]) {
                const double e = point_in(&r, it.t, q, &lo);
                if (e > worst)
                    worst = e, k = q;
            }
        if (k == NONE || !(worst > bound_m))
            continue;
        const int got = insert(&r, it.t, k, worst);
        if (got != 1) {
            read_failed = got < 0;
            goto done;
        }
    }
    *inserted = w->nv - nv0;
    *stuck_m = r.stuck_max;
    ok = 1;
done:
    if (!ok && !read_failed)
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory refining a tile");
    rf_free(&r);
    return ok;
}
