/* tin_int.h - the error-bounded TIN's private state: the insertion's working set (tin.c), which
 * its rasteriser (tin_raster.c) and the void cut (tin_voids.c) read, and the functions the tiled
 * build (tin_tiles.c) calls. */
#ifndef TP_CORE_TIN_INT_H
#define TP_CORE_TIN_INT_H

#include "internal.h"
#include "tp_tin.h"

/* ---- the insertion's working set (tin.c; tin.c's header describes the half-edges) ---- */

typedef struct tin_tri {
    uint32_t v[3]; /* vertices; half-edge 3t+i runs from v[i] to v[(i+1)%3] */
    int32_t he[3]; /* twin of half-edge 3t+i, -1 on the outline */
    uint32_t cand; /* worst valid sample's index */
    float err;     /* its error (rounded up) */
    uint32_t ver;  /* bumped on every rewrite: heap entries of older versions are stale */
    uint32_t pend; /* 1 while in the pending list */
} tin_tri;

typedef struct heap_ent {
    float err;
    uint32_t t, ver;
} heap_ent;

/* Sample classes (tin_build.cls): a forced sample is inserted before any error counts (its
 * error is FORCED_ERR while it is not a vertex); a skipped one is never measured nor inserted
 * (voids are skipped without a class). */
enum { TIN_FREE = 0, TIN_FORCE = 1, TIN_SKIP = 2 };
#define FORCED_ERR 1e30

typedef struct tin_build {
    const float* h;
    const uint8_t* cls; /* per sample TIN_FREE / TIN_FORCE / TIN_SKIP; NULL: all free */
    uint32_t* frow;     /* NULL, or hgt + 1 offsets into fx: the forced samples of each row */
    int32_t* fx;        /* their columns, increasing */
    size_t forced_left; /* forced samples not yet vertices: while any, a triangle without one is
                           deferred (deferred, nd) instead of scanned, as it will likely be
                           split again before its error counts */
    heap_ent* deferred;
    size_t nd, cap_d;
    int w, hgt;
    float bound; /* max_error_m as float: errors are compared as floats */
    double bound_d;
    /* vertices */
    int32_t* vx; /* 2 per vertex */
    float* vz;
    size_t nv, cap_v;
    /* triangles, one cache-friendly record each */
    tin_tri* T;
    size_t nt, cap_t;
    /* heap of triangles above the bound, max error first, keys kept in the entries; a rewritten
     * triangle's entry is left in place and skipped when it surfaces (lazy deletion: no sift for
     * the 4 to 8 triangles each insertion rewrites) */
    heap_ent* heap;
    size_t nh, cap_h;
    /* triangles to rasterise */
    uint32_t* pending;
    size_t np;
    /* half-edges to legalise (explicit stack: the recursion of delatin's _legalize) */
    int32_t* stack;
    size_t ns, cap_s;
    int exact64; /* coordinates small enough for the incircle test in int64 */
    int oom;
    size_t visited;
} tin_build;

/* Orientation of (a, b, c), exact: > 0 counter-clockwise in (column, row). */
static inline int64_t tp__tin_orient(const int32_t* a, const int32_t* b, const int32_t* c)
{
    return ((int64_t)b[0] - a[0]) * ((int64_t)c[1] - a[1]) -
           ((int64_t)b[1] - a[1]) * ((int64_t)c[0] - a[0]);
}

static inline int64_t tp__tin_floor_div(int64_t a, int64_t b) /* b > 0 */
{
    int64_t q = a / b;
    return (a % b != 0 && a < 0) ? q - 1 : q;
}

/* Triangle t's candidate and error (tin_raster.c). While forced samples are left
 * (b->forced_left), only its forced samples are looked at: returns 0, writing nothing, when it
 * has none. */
int tp__tin_rasterise(tin_build* b, uint32_t t);

/* Drops the triangles over invalid cells and the vertices no triangle uses (tin_voids.c); remap:
 * scratch of b->nv. */
void tp__tin_cut_voids(tin_build* b, uint32_t* remap);

/* ---- error-bounded TIN (tin.c) ---- */

/* Marks TIN_FORCE (1) in cls (width * height, zeroed by the caller) at every corner of a valid
 * cell that touches an invalid one (TP_TIN_CUT_VOIDS); returns whether it marked any
 * (tin_voids.c). */
int tp__tin_void_classes(const float* h, int w, int hg, uint8_t* cls);

/* The bound errors are compared with, as floats (each error rounded up to a float): the largest
 * float not above e, so that "err <= bound" means err <= e. An error of exactly e is allowed
 * (common on integer heights at e = 1: a margin below e cost 15% more triangles on Mt Hood);
 * another double formula may measure it 1e-12 m above e. */
float tp__tin_bound(double e);

/* tp_tin_build after its checks, on a grid of at least 2x2 with a valid sample: cls (NULL or
 * one byte per sample: 0 free, 1 forced, 2 skipped) says which samples are inserted first and
 * which are never measured; cut drops the triangles over invalid cells. */
tp_status tp__tin_build(const float* heights, int width, int height, double max_error_m,
                        const uint8_t* cls, int cut, tp_tin** out, tp_error* err);

/* tp__tin_build without the cut, at several bounds in one insertion: tol[0] > tol[1] > ... >
 * tol[count - 1] (count >= 1); rungs[j] is the triangulation as it stood when the worst error
 * first fell to tol[j] (each with its own errors), i.e. what tp__tin_build at tol[j] gives
 * (tin_node.c's ladder of levels). On failure every rungs[j] is NULL. */
tp_status tp__tin_build_rungs(const float* heights, int width, int height, const double* tol,
                              int count, const uint8_t* cls, tp_tin** rungs, tp_error* err);

/* ---- a node TIN triangle's bound against full resolution (tin_node_bound.c) ---- */

/* One node: its samples q (side = 2^n + 1 a row, steps), its scale, and its carry regions
 * (tp_node_carry_regions: 2^depth x 2^depth, in err units of `unit` steps). */
typedef struct tp__tin_node_bound {
    const int32_t* q;
    int side, n, scale, depth;
    const uint16_t* carry;
    double unit;
} tp__tin_node_bound;

/* The bound (steps) of triangle pos (lattice positions of the node's samples, the heights its
 * samples there) against every full-resolution sample under it: exactly |T - S_n| over T for a
 * node of scale >= 1 (the samples it covers for a leaf, whose samples are the full resolution),
 * plus the largest carry of the regions its bounding box touches; INFINITY where one is
 * saturated. */
double tp__tin_node_tri_bound(const tp__tin_node_bound* b, const int32_t pos[3][2]);

#endif
