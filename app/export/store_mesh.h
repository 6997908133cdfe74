/*
 * store_mesh.h - what a store export builds its mesh from: nodes read synchronously and owned
 * here (attached to the tree while the cut needs them), full-resolution samples read through a
 * direct-mapped cache of leaves, and the mesh itself (points merged by grid position, triangles
 * with their cell data).
 */
#ifndef TP_APP_STORE_MESH_H
#define TP_APP_STORE_MESH_H

#include "store_scene.h"

#include <stdint.h>

/* ---- nodes read synchronously, owned here, attached to the tree while needed ---- */
typedef struct residency {
    tp_store_scene* sc;
    size_t block_samples;
    uint16_t** block;        /* per node id; NULL when not resident */
    int64_t* ids;            /* resident node ids (order of loading) */
    size_t count, cap;
    size_t bytes, peak_bytes;
    tp_error err;            /* the first read failure */
} residency;

/* Reads node (if not resident) and attaches it to the tree; 0 on failure (r->err says why). */
int tp_res_load(residency* r, int64_t node);

/* Releases every resident node for which keep[node] is 0 (keep NULL: all). */
void tp_res_release_except(residency* r, const uint8_t* keep);

/* ---- full-resolution samples, read through a direct-mapped cache of leaves ---- */

#define LEAF_CACHE_SLOTS 4096

typedef struct leaf_cache {
    residency* res;
    const tp_tree_geometry* g;
    double step_m;
    const tp_node_meta* metas;
    int64_t key[LEAF_CACHE_SLOTS];
    uint16_t* slot[LEAF_CACHE_SLOTS];
    size_t reads;
    int failed;
} leaf_cache;

/* Decoded height of full-resolution sample (x, y), NaN where none is drawn (or a read failed:
 * then failed is set and res->err holds the message). */
double tp_leaf_sample(leaf_cache* lc, int x, int y);

/* tp_leaf_sample, and *filled (when not NULL) 1 where the build filled that sample (a void
 * filled by interpolation or from a second source: the store's filled bits), else 0. */
double tp_leaf_sample_filled(leaf_cache* lc, int x, int y, int* filled);

/* Decoded height of sample (i, j) (column, row within the leaf, 0 .. 2^n) of a leaf's block q
 * as tp_store_read_node returns it, NaN where none is drawn; *filled (when not NULL) as
 * tp_leaf_sample_filled. */
double tp_leaf_block_sample(const uint16_t* q, const tp_node_meta* meta, int n, double step_m,
                            int i, int j, int* filled);

/* ---- the mesh: points merged by grid position (open addressing), triangles ---- */

typedef struct mesh_build {
    uint64_t* key;           /* (x << 32 | y) + 1; 0 = empty */
    uint64_t* val;
    size_t hcap;
    int32_t *px, *py;
    double* pz;
    uint8_t* pf;             /* 1: a filled void sample (the store's filled bits) */
    size_t points, cap_x, cap_y, cap_z, cap_f;
    uint64_t* tri;
    int32_t* patch;
    uint8_t* lod;
    double* err;
    size_t tris, cap_tri, cap_patch, cap_lod, cap_err;
} mesh_build;

/* Index of the point at grid (x, y), added with height z if new; UINT64_MAX when out of memory. */
uint64_t tp_mesh_point(mesh_build* m, int32_t x, int32_t y, double z, int filled);

/* Appends a triangle of points p with its cell data; 0 when out of memory. */
int tp_mesh_add_triangle(mesh_build* m, const uint64_t p[3], int32_t patch, uint8_t lod, double e);

void tp_mesh_build_free(mesh_build* m);

/* Grows *p (of *cap elements of size bytes, doubling from 4096) to hold need; 0 when out of
 * memory (*p untouched). */
int tp_array_grow(void** p, size_t* cap, size_t need, size_t size);

#endif
