/*
 * qm_tile.h - one Cesium quantized-mesh tile of a store (`export --tiles quantized-mesh`,
 * docs/quantized_mesh.md): the store's surface sampled on the tile's regular lon/lat lattice,
 * the error-bounded TIN of that lattice with its sides shared with the neighbours, heights on
 * the export's common height step, the tile encoded (tp_qmesh_encode), and its true error
 * measured against the store's full-resolution posts inside it (qm_measure.c).
 */
#ifndef TP_APP_QM_TILE_H
#define TP_APP_QM_TILE_H

#include "ground.h"

#include "tp_io.h"

#include <stddef.h>
#include <stdint.h>

/* Lattice cells per tile side: 217 = 7 x 31 divides 32767 (= 7 x 31 x 151), so every lattice
 * post is exactly on a u, v code (151 codes a cell) and the TIN's vertices are not moved. */
#define TP_QM_CELLS 217
/* Lattice posts between two exact projections (the others interpolated): a divisor of
 * TP_QM_CELLS. */
#define TP_QM_COARSE 7

/* What every tile of an export shares. */
typedef struct qm_source {
    tp_ground* ground;         /* the store's full-resolution surface (tp_ground_height) */
    const tp_georef* georef;   /* grid <-> render CRS <-> WGS84 */
    int width, height;         /* the source grid (posts) */
    tp_geoid* geoid;           /* NULL: heights as stored (--heights geoid) */
    double lat_lo, lat_hi, lon_lo, lon_hi; /* the store's extent in WGS84, padded */
    double height_step_m;      /* every vertex height is a multiple of it (a power of two) */
    double interp_max_m;       /* interpolate the projection over coarse cells up to this size */
} qm_source;

/* One tile's result. */
typedef struct qm_tile_result {
    uint8_t* gz;               /* the gzip-compressed tile (free()) */
    size_t gz_size, raw_size;
    size_t vertices, triangles;
    double bound_m;            /* the bound: the TIN's on the lattice, then the refinement's */
    double measured_m;         /* max |tile - store| over the store's posts in the tile and the
                                  lattice posts with a height (decoded heights, as Cesium) */
    size_t posts_measured;
    size_t inserted;           /* vertices the refinement added (posts off the lattice) */
    size_t side_vertices;      /* vertices added on the sides (posts on a side's line) */
    int passes;                /* refinement passes (0: the TIN was within its bound) */
    double stuck_m;            /* the largest error of a point the refinement could not insert
                                  (its code held a vertex already), last pass */
    double proj_interp_m;      /* largest gap between the interpolated and the exact grid
                                  position at the coarse cells' centres checked (grid units x
                                  spacing: metres) */
    uint64_t edge_hash[4];     /* west, south, east, north: the side's (code, height) list */
} qm_tile_result;

/* Builds tile (z, x, y) with the TIN bound bound_m into r (zeroed first). 0 with a message in
 * err on failure (a read error names the store; out of memory). */
int tp_qm_tile_build(const qm_source* s, int z, int x, int y, double bound_m, qm_tile_result* r,
                     tp_error* err);

/* ---- qm_measure.c ---- */

/* A tile's TIN as the measure sees it: vertices at lattice (column i from the west, row j from
 * the north) with decoded heights, triangles. */
typedef struct qm_mesh {
    int n;                    /* lattice cells a side */
    size_t vertex_count, triangle_count;
    const double* ij;         /* vertex_count * 2: column, row (fractions: u, v codes / 151) */
    const double* z;          /* vertex_count: decoded height (m) */
    const uint32_t* tris;
} qm_mesh;

/* The mesh's height at lattice position (fi, fj) (0..n each): the triangle containing it,
 * barycentric. A point-location index over the lattice cells is built on the first call and
 * kept in *index (free with tp_qm_index_free). NAN when out of memory. */
typedef struct qm_index qm_index;
double tp_qm_mesh_height(const qm_mesh* m, qm_index** index, double fi, double fj);
/* The triangle containing (fi, fj) (the nearest to containing it at a rounding's distance);
 * UINT32_MAX when out of memory. */
uint32_t tp_qm_mesh_triangle(const qm_mesh* m, qm_index** index, double fi, double fj);
void tp_qm_index_free(qm_index* ix);

/* A point the tile must hold within its bound: lattice position (column from the west, row from
 * the north, fractions allowed) and height (m, converted as the tile's are). */
typedef struct qm_point {
    double fi, fj, h;
} qm_point;

/* The points a measure found above a threshold: those above `above` are appended while n <
 * limit, those above `bound` while n < 4 limit (the rest are found by the next measure, after
 * the refinement). */
typedef struct qm_points {
    qm_point* p;
    size_t n, cap, limit;
    double above, bound;
} qm_points;

/* Appends (fi, fj, h) when err > c->above and there is room; 0 when out of memory. */
int tp_qm_points_add(qm_points* c, double fi, double fj, double h, double err);

/* The largest |mesh - post| over the store's full-resolution posts inside the tile (west, south,
 * east, north; lattice step d degrees), their heights converted as the tile's are; the posts'
 * count in *posts; the posts above collect->above appended to collect (NULL: none). 0 on failure
 * (message in err). */
int tp_qm_measure_posts(const qm_source* s, const qm_mesh* m, qm_index** index, double west,
                        double south, double east, double north, double* max_err, size_t* posts,
                        qm_points* collect, tp_error* err);

/* ---- qm_refine.c ---- */

/* A tile's mesh as it is refined: vertices at u, v codes (0..32767, v from the south) with
 * heights in steps of the export's height step, triangles; capacities in elements (the arrays
 * are malloc'ed and grown by the refinement). */
typedef struct qm_work {
    uint16_t *u, *v;
    long long* hq;
    size_t nv, cap_v;
    uint32_t* tris;
    size_t nt, cap_t; /* cap_t: uint32_t elements of tris */
} qm_work;

/* A vertex added on a tile's side (u or v 0 or 32767), the same in both tiles of the side. */
typedef struct qm_side_vertex {
    uint16_t u, v;
    long long hq; /* height in steps */
} qm_side_vertex;

/* Adds the side vertices to w, each splitting the outline edge it lies on (Delaunay flips
 * around it); one where a vertex is already is skipped. 0 when out of memory (message in err). */
int tp_qm_insert_sides(qm_work* w, const qm_side_vertex* sv, size_t n, tp_error* err);

/* The surface's height (m, converted as the tile's are) at lattice position (fi, fj): NaN in *h
 * where there is none; 0 on a read failure (message in the function's own error). */
typedef int (*qm_height_fn)(void* ctx, double fi, double fj, double* h);

/* Refines w (whose mesh m, with its point index, is as the measure saw it) until each of the n
 * points is within bound_m of the mesh or stuck: greedy, the worst point first, inserted as a
 * vertex at its u, v code rounded (kept one code inside the tile: the sides, which the
 * neighbours share, are never touched) with the surface's height there (height(); the point's
 * own where it gives NaN) rounded to step_m, then Lawson's
 * Delaunay flips around it (exact arithmetic on the codes). A point whose code already holds a
 * vertex is stuck: its error stays, the largest such in *stuck_m. The count of vertices added in
 * *inserted. m and its index are stale afterwards. 0 when out of memory (message in err) or
 * when height() failed (its message). */
int tp_qm_refine(qm_work* w, const qm_mesh* m, qm_index** index, const qm_point* pts, size_t n,
                 double bound_m, double step_m, qm_height_fn height, void* ctx, size_t* inserted,
                 double* stuck_m, tp_error* err);

/* ---- qm_sides.c ---- */

/* The vertices tile (z, x, y)'s sides need so that the store's posts on them (those within 1.5
 * u, v codes of the side's line, which the inside's refinement cannot hold) are within half
 * of bound_m of the side's polyline: for each side, from the posts along its line (exact
 * projections) and the vertices w has on it, a 1-D greedy polyline, the worst post first,
 * each vertex at the post's code along the side with the surface's height there (height(), the
 * post's where NaN) rounded to the step; the lattice's posts on the side with a height
 * (lattice_h and valid: the tile's (TP_QM_CELLS + 1)^2 lattice, row 0 north) held too.
 * Everything it reads is a function of the side alone,
 * so both tiles add the same vertices. *out (free()) and *n; 0 on failure (message in err). */
int tp_qm_side_vertices(const qm_source* s, const qm_work* w, int z, int x, int y, double bound_m,
                        const float* lattice_h, const uint8_t* valid, qm_height_fn height,
                        void* ctx, qm_side_vertex** out, size_t* n, tp_error* err);

#endif
