/* tin_node.c - a tree node's error-bounded TINs, a ladder per level (tp_tree.h, "a node's
 * error-bounded TINs"; issue 32 item 2; docs/tin.md "TIN nodes").
 *
 * Each level k >= 1 of a complete node: one greedy insertion of tin.c over the node's
 * (2^n+1)^2 samples with the level-k side vertices forced and every other side sample skipped
 * (so the outline is the lattice's), stopped at each rung of the level's ladder
 * (tp__tin_build_rungs); then each rung's triangles are measured against full resolution
 * (tin_node_bound.c: exactly against the node's level-n surface, plus the carry of the regions
 * they touch): unmoved, and under every combination of neighbour levels on the sides their
 * vertices lie on (turned over: the side's level is refused).
 */
#include "lattice.h"
#include "tin_int.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

struct tp_node_tins {
    size_t bytes;
    int rungs;
    int first[TP_MAX_LEVELS + 1]; /* level k's rungs: rung[first[k] .. first[k+1]-1] */
    tp_node_tin rung[];           /* the rungs built (a level: up to TP_NODE_TIN_RUNGS), then
                                     their ij and triangles, in rung order */
};

/* What measuring one level's rungs needs. */
typedef struct level_check {
    int k, side, stride;
    const int32_t* q;
    tp__tin_node_bound bound; /* a triangle's bound against full resolution */
} level_check;

static int64_t orient(const int32_t p[3][2])
{
    return ((int64_t)p[1][0] - p[0][0]) * ((int64_t)p[2][1] - p[0][1]) -
           ((int64_t)p[1][1] - p[0][1]) * ((int64_t)p[2][0] - p[0][0]);
}

/* The side a non-corner outline vertex lies on (as tp__lattice_vertex decides), else -1. */
static int movable_side(int i, int j, int last)
{
    int on_x = i == 0 || i == last, on_y = j == 0 || j == last;
    if (on_x && on_y)
        return -1;
    return j == 0 ? TP_SIDE_TOP : i == last ? TP_SIDE_RIGHT : j == last ? TP_SIDE_BOTTOM
         : i == 0 ? TP_SIDE_LEFT : -1;
}

static double tri_error(const level_check* c, const int32_t pos[3][2])
{
    return tp__tin_node_tri_bound(&c->bound, pos);
}

/* Triangle p (orientation o) with its vertices moved by neighbour levels nb: its error, 0 when
 * it collapses onto an edge (not drawn), INFINITY when it turns over or flattens onto three
 * distinct points of a line (a triangle a vertex of the adjacent side's snapped into line with
 * two of this side's: dropping it would leave a crack along the side, drawing it a wall). */
static double moved_error(const level_check* c, const int32_t p[3][2], int64_t o, const int nb[4])
{
    int32_t m[3][2];
    for (int v = 0; v < 3; v++) {
        m[v][0] = p[v][0], m[v][1] = p[v][1];
        /* only outline vertices move, and they are all level-k lattice vertices */
        if (p[v][0] % c->stride == 0 && p[v][1] % c->stride == 0) {
            int mi, mj;
            tp__lattice_vertex(c->k, nb, p[v][0] / c->stride, p[v][1] / c->stride, &mi, &mj);
            m[v][0] = mi * c->stride, m[v][1] = mj * c->stride;
        }
    }
    int64_t om = orient(m);
    if (om == 0) { /* two vertices snapped together: degenerate in 3-D too, not drawn */
        for (int v = 0; v < 3; v++)
            if (m[v][0] == m[(v + 1) % 3][0] && m[v][1] == m[(v + 1) % 3][1])
                return 0;
        return INFINITY; /* three distinct points on a line: a wall the outline would need */
    }
    if ((om > 0) != (o > 0))
        return INFINITY;
    return tri_error(c, m);
}

/* Every combination of neighbour levels (none, 0..k-1) on the sides in mask with at least one
 * set: the error folded into eps[s][kn] of each side s the combination moves. */
static void fold_moved(const level_check* c, const int32_t p[3][2], unsigned mask,
                       float eps[4][TP_MAX_N])
{
    int sides[4], ns = 0;
    for (int s = 0; s < 4; s++)
        if (mask >> s & 1)
            sides[ns++] = s;
    int total = 1, o = c->k + 1;
    for (int a = 0; a < ns; a++)
        total *= o;
    int64_t or = orient(p);
    for (int combo = 1; combo < total; combo++) {
        int nb[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
        for (int a = 0, rest = combo; a < ns; a++, rest /= o)
            nb[sides[a]] = rest % o - 1;
        float e = (float)moved_error(c, p, or, nb);
        for (int a = 0; a < ns; a++) {
            int kn = nb[sides[a]];
            if (kn >= 0 && e > eps[sides[a]][kn])
                eps[sides[a]][kn] = e;
        }
    }
}

/* Measures rung t's own and stitched bounds into r (rounded up to floats). */
static void measure(const level_check* c, const tp_tin* t, tp_node_tin* r)
{
    int last = c->side - 1;
    double own = 0;
    memset(r->eps_steps, 0, sizeof r->eps_steps);
    for (size_t i = 0; i < t->triangle_count; i++) {
        int32_t p[3][2];
        unsigned mask = 0;
        for (int v = 0; v < 3; v++) {
            const float* xy = t->vertices + 3 * (size_t)t->triangles[3 * i + v];
            p[v][0] = (int32_t)xy[0], p[v][1] = (int32_t)xy[1];
            int s = movable_side(p[v][0], p[v][1], last);
            mask |= s >= 0 ? 1u << s : 0u;
        }
        double e = tri_error(c, p);
        own = e > own ? e : own;
        if (mask)
            fold_moved(c, p, mask, r->eps_steps);
    }
    float f = (float)own;
    r->own_steps = (double)f < own ? nextafterf(f, INFINITY) : f;
    for (int s = 0; s < 4; s++) /* folded as floats: round the finite ones up once more */
        for (int kn = 0; kn < c->k; kn++)
            if (isfinite(r->eps_steps[s][kn]) && r->eps_steps[s][kn] > 0)
                r->eps_steps[s][kn] = nextafterf(r->eps_steps[s][kn], INFINITY);
}

static double part_steps(unsigned units, unsigned carry, double unit)
{
    if (units >= TP__ERR_SAT)
        return HUGE_VAL;
    return units > carry ? (units - carry) * unit : 0.0;
}

/* Level k's ladder of tolerances (steps, the insertion's against the node's samples), coarsest
 * first: sqrt(2) apart from the own part of delta[k-1] (a node drawn at level k for its
 * neighbours' sake may be allowed that much: on the real-relief stores, starting at twice it or
 * at sqrt(2) times it drew 0.2-0.4% fewer triangles with 25-50% more rungs to build), down to the
 * own part of delta[k] (level n: down to an eighth of delta[n-1]'s). */
static int ladder(const tp_node_meta* m, int n, int k, double unit, double tol[TP_NODE_TIN_RUNGS])
{
    unsigned carry = m->delta[n];
    double hi = part_steps(m->delta[k - 1], carry, unit), lo = part_steps(m->delta[k], carry, unit);
    if (!isfinite(hi) || !isfinite(lo))
        return 0;
    int count = 0;
    double r = hi;
    for (; count < TP_NODE_TIN_RUNGS - (k < n) && r > lo * 1.05 && r > hi / 8.5; r /= sqrt(2.0))
        tol[count++] = r;
    if (k < n)
        tol[count++] = lo;
    return count;
}

/* Level k's rungs into tins[0..*kept-1] (the others freed), measured into rungs. */
static tp_status build_level(const level_check* c, const float* h, uint8_t* cls, const double* tol,
                             int count, tp_tin** tins, tp_node_tin* rungs, int* kept, tp_error* err)
{
    int side = c->side, last = side - 1;
    for (int j = 0; j < side; j++)
        for (int i = 0; i < side; i++) {
            int border = i == 0 || j == 0 || i == last || j == last;
            int lattice = i % c->stride == 0 && j % c->stride == 0;
            cls[(size_t)j * side + i] = !border ? TIN_FREE : lattice ? TIN_FORCE : TIN_SKIP;
        }
    /* the lattice vertex diagonally in from each corner: with it the triangles at a corner
     * rarely join two vertices of one side to one of the other, which snapping the latter into
     * the corner flattens (moved_error) */
    if (c->k >= 2)
        for (int q = 0; q < 4; q++) {
            int i = q & 1 ? last - c->stride : c->stride, j = q & 2 ? last - c->stride : c->stride;
            cls[(size_t)j * side + i] = TIN_FORCE;
        }
    tp_status st = tp__tin_build_rungs(h, side, side, tol, count, cls, tins, err);
    if (st != TP_OK)
        return st;
    size_t max_tris = (size_t)2 << (2 * c->k);
    int o = 0;
    for (int j = 0; j < count; j++) {
        if (tins[j]->triangle_count >= max_tris) { /* no better than the lattice */
            tp_tin_destroy(tins[j]);
            continue;
        }
        tins[o] = tins[j];
        rungs[o].level = c->k;
        measure(c, tins[o], &rungs[o]);
        o++;
    }
    for (int j = o; j < count; j++)
        tins[j] = NULL;
    *kept = o;
    return TP_OK;
}

/* Morton code of a triangle's centroid (times 3: integers), for drawing order. */
static uint32_t tri_morton(const tp_tin* t, size_t i)
{
    uint32_t x = 0, y = 0, code = 0;
    for (int v = 0; v < 3; v++) {
        const float* p = t->vertices + 3 * (size_t)t->triangles[3 * i + v];
        x += (uint32_t)p[0], y += (uint32_t)p[1];
    }
    for (int b = 0; b < 11; b++)
        code |= (x >> b & 1u) << (2 * b) | (y >> b & 1u) << (2 * b + 1);
    return code;
}

typedef struct keyed_tri {
    uint32_t key, i;
} keyed_tri;

static int cmp_keyed(const void* a, const void* b)
{
    const keyed_tri *x = a, *y = b;
    return (x->key > y->key) - (x->key < y->key) + (x->key == y->key) * ((x->i > y->i) - (x->i < y->i));
}

/* Writes t's triangles in Morton order of their centroids: neighbours follow each other, so a
 * renderer's vertex cache (llvmpipe's above all) reuses their shared vertices as it does a
 * strip's. 0 without memory (then in the insertion's order). */
static int write_triangles(const tp_tin* t, uint16_t* w)
{
    keyed_tri* k = malloc(t->triangle_count * sizeof *k + 1);
    if (k)
        for (size_t i = 0; i < t->triangle_count; i++)
            k[i] = (keyed_tri){tri_morton(t, i), (uint32_t)i};
    if (k)
        qsort(k, t->triangle_count, sizeof *k, cmp_keyed);
    for (size_t i = 0; i < t->triangle_count; i++)
        for (int v = 0; v < 3; v++)
            *w++ = (uint16_t)t->triangles[3 * (k ? k[i].i : i) + v];
    free(k);
    return k != NULL;
}

/* One allocation: the header, then each level's vertices (its rungs are stops of one insertion,
 * so each rung's vertices are the first vertex_count of its finest rung's) and each rung's
 * triangles. */
static tp_node_tins* pack(tp_tin* const* tins, const tp_node_tin* rungs, const int* first, int n)
{
    int total = first[n + 1];
    size_t words = 0;
    for (int k = 0; k <= n; k++)
        if (first[k + 1] > first[k])
            words += 2 * tins[first[k + 1] - 1]->vertex_count;
    for (int r = 0; r < total; r++)
        words += 3 * tins[r]->triangle_count;
    size_t bytes = sizeof(tp_node_tins) + (size_t)total * sizeof(tp_node_tin) +
                   words * sizeof(uint16_t);
    tp_node_tins* o = malloc(bytes); /* every field is written below */
    if (!o)
        return NULL;
    o->bytes = bytes;
    o->rungs = total;
    memcpy(o->first, first, sizeof o->first);
    uint16_t* w = (uint16_t*)(o->rung + total);
    for (int k = 0; k <= n; k++) {
        if (first[k + 1] == first[k])
            continue;
        const tp_tin* finest = tins[first[k + 1] - 1];
        const uint16_t* ij = w;
        for (size_t v = 0; v < finest->vertex_count; v++) {
            *w++ = (uint16_t)finest->vertices[3 * v];
            *w++ = (uint16_t)finest->vertices[3 * v + 1];
        }
        for (int r = first[k]; r < first[k + 1]; r++) {
            const tp_tin* t = tins[r];
            tp_node_tin* l = &o->rung[r];
            assert(t->vertex_count <= finest->vertex_count &&
                   (t->vertex_count == 0 || (t->vertices[3 * (t->vertex_count - 1)] ==
                                                 finest->vertices[3 * (t->vertex_count - 1)])));
            *l = rungs[r];
            l->vertex_count = (uint32_t)t->vertex_count;
            l->triangle_count = (uint32_t)t->triangle_count;
            l->ij = ij;
            l->triangles = w;
            write_triangles(t, w);
            w += 3 * t->triangle_count;
        }
    }
    return o;
}

tp_status tp_node_tins_build(int n, int scale, const uint16_t* samples, const tp_node_meta* meta,
                             const uint16_t* carry, double err_unit_steps, unsigned levels,
                             tp_node_tins** out, tp_error* err)
{
    assert(n >= 1 && n <= TP_MAX_N && scale >= 0 && samples && meta && out && err_unit_steps > 0);
    *out = NULL;
    int side = (1 << n) + 1;
    size_t count = (size_t)side * side;
    for (size_t i = 0; i < count; i++)
        if (samples[i] == TP_TREE_NO_HEIGHT)
            return TP_OK; /* incomplete: the lattice and its cell mask */
    int32_t* q = malloc(count * sizeof *q);
    float* h = malloc(count * sizeof *h);
    uint8_t* cls = malloc(count);
    tp_tin* tins[TP_MAX_LEVELS * TP_NODE_TIN_RUNGS] = {0};
    static tp_node_tin rungs_zero[TP_MAX_LEVELS * TP_NODE_TIN_RUNGS];
    tp_node_tin rungs[TP_MAX_LEVELS * TP_NODE_TIN_RUNGS];
    memcpy(rungs, rungs_zero, sizeof rungs);
    int first[TP_MAX_LEVELS + 1] = {0};
    tp_status st = TP_OK;
    if (!q || !h || !cls) {
        st = tp__fail(err, TP_ERR_OUT_OF_MEMORY, "node TINs: out of memory");
        goto done;
    }
    for (size_t i = 0; i < count; i++)
        q[i] = samples[i], h[i] = (float)samples[i];
    int total = 0;
    for (int k = 0; k <= n && st == TP_OK; k++) {
        first[k] = total;
        double tol[TP_NODE_TIN_RUNGS];
        int nt = k >= 1 && (levels >> k & 1) ? ladder(meta, n, k, err_unit_steps, tol) : 0;
        if (nt == 0)
            continue;
        level_check c = {.k = k, .side = side, .stride = 1 << (n - k), .q = q,
                         .bound = {.q = q, .side = side, .n = n, .scale = scale,
                                   .depth = carry ? tp_node_carry_depth(scale) : 0,
                                   .carry = carry ? carry : &meta->delta[n],
                                   .unit = err_unit_steps}};
        int kept = 0;
        st = build_level(&c, h, cls, tol, nt, tins + total, rungs + total, &kept, err);
        total += kept;
    }
    first[n + 1] = total;
    if (st == TP_OK) {
        *out = pack(tins, rungs, first, n);
        if (!*out)
            st = tp__fail(err, TP_ERR_OUT_OF_MEMORY, "node TINs: out of memory");
    }
done:
    for (int r = 0; r < TP_MAX_LEVELS * TP_NODE_TIN_RUNGS; r++)
        tp_tin_destroy(tins[r]);
    free(q);
    free(h);
    free(cls);
    return st;
}

const tp_node_tin* tp_node_tins_level(const tp_node_tins* tins, int k, int* count)
{
    *count = 0;
    if (!tins || k < 0 || k >= TP_MAX_LEVELS)
        return NULL;
    *count = tins->first[k + 1] - tins->first[k];
    return *count ? &tins->rung[tins->first[k]] : NULL;
}

double tp_node_tin_bound_steps(const tp_node_tin* t, const int8_t nb[4])
{
    double b = t->own_steps;
    for (int s = 0; s < 4; s++)
        if (nb[s] >= 0 && nb[s] < t->level && t->eps_steps[s][nb[s]] > b)
            b = t->eps_steps[s][nb[s]];
    return b;
}

size_t tp_node_tins_bytes(const tp_node_tins* tins) { return tins ? tins->bytes : 0; }

void tp_node_tins_destroy(tp_node_tins* tins) { free(tins); }

int tp_node_tins_rungs(const tp_node_tins* tins) { return tins ? tins->rungs : 0; }
