/* terrain_int.h - tp_terrain's private state: the quantised grid, its patches and their error
 * tables (terrain.c, fit.c, patch_error.c, patch_stitch.c), read by the selection (selection*.c)
 * and lod.c. */
#ifndef TP_CORE_TERRAIN_INT_H
#define TP_CORE_TERRAIN_INT_H

#include "internal.h"
#include "lattice.h"
#include "tp_terrain.h"

/* Stored height of a sample that is not drawn (nodata). Padding is never stored at all. */
#define TP__NO_HEIGHT 0xFFFFu

typedef struct tp__patch {
    int32_t offset;     /* global quantised height = stored + offset, for samples it owns */
    int32_t qmin, qmax; /* global quantised range over all drawn samples of the patch */
    uint8_t complete;   /* every sample drawn */
    uint8_t has_drawn;  /* at least one drawn sample */
} tp__patch;

struct tp_terrain {
    tp_terrain_info info;
    tp_allocator alloc; /* always set (malloc / free by default) */
    int n, ps;          /* finest level, patch span 2^n (patch size - 1) */
    int w, h;           /* fitted grid */
    int sw, sh;         /* stored region: samples with x >= sw or y >= sh are padding */
    double gt[6];       /* geotransform of the fitted grid */
    double step;        /* quantisation step (m) */
    double quant_err;   /* max |source - decoded| (m) */
    uint16_t* q;        /* sw * sh stored heights, relative to the owner patch's offset */
    uint8_t* filled;    /* NULL, or one bit per stored sample: filled void */
    tp__patch* patches;
    /* Error tables, per patch: delta[k] for k = 0..n, then eps[side][kn] for side 0..3 and
     * neighbour level kn = 0..n-1. See patch_error.c. */
    uint16_t* err_tab;
    int err_stride;
    /* Vertex adding's table, NULL until tp_terrain_prepare_stitch_add (a terrain drawn by
     * vertex moving does not hold it): per patch 4 n^2 entries eta[side][k][kn - 1] for side
     * 0..3, k = 0..n-1 and kn = 1..n (only k < kn used). See patch_error.c. */
    uint16_t* add_tab;
    double err_unit; /* table unit, in steps: 1/16 .. 1 */
};

/* The patch that stores sample x (columns) or y (rows): the last patch owns the far border. */
static inline int tp__owner(int coord, int n, int patches)
{
    int p = coord >> n;
    return p < patches ? p : patches - 1;
}

/* Global quantised height of sample (x, y), or INT32_MIN if it is not drawn / outside. */
static inline int32_t tp__q(const tp_terrain* t, int x, int y)
{
    if (x < 0 || y < 0 || x >= t->sw || y >= t->sh)
        return INT32_MIN;
    uint16_t s = t->q[(size_t)y * (size_t)t->sw + (size_t)x];
    if (s == TP__NO_HEIGHT)
        return INT32_MIN;
    int p = tp__owner(y, t->n, t->info.patch_rows) * t->info.patch_cols +
            tp__owner(x, t->n, t->info.patch_cols);
    return (int32_t)s + t->patches[p].offset;
}

static inline const uint16_t* tp__delta_tab(const tp_terrain* t, int patch)
{
    return t->err_tab + (size_t)patch * (size_t)t->err_stride;
}
static inline const uint16_t* tp__eps_tab(const tp_terrain* t, int patch, int side)
{
    return t->err_tab + (size_t)patch * (size_t)t->err_stride + (size_t)(t->n + 1) +
           (size_t)side * (size_t)t->n;
}

/* eta[side][k][kn - 1] (k < kn; t->add_tab must be there): see patch_error.c. */
static inline const uint16_t* tp__eta_tab(const tp_terrain* t, int patch, int side, int k)
{
    const size_t n = (size_t)t->n;
    return t->add_tab + (size_t)patch * 4 * n * n + ((size_t)side * n + (size_t)k) * n;
}

/* tp_patch_error_bound_add less the quantisation error (metres; patch_error.c). */
double tp__patch_add_bound_m(const tp_terrain* t, int patch, int k, const int neighbor_levels[4]);

/* Computes the delta and eps tables of every patch (patch_error.c). */
tp_status tp__patch_errors_compute(tp_terrain* t, tp_error* err);

/* Position (global grid coordinates) of vertex (i, j) of patch p at level k after crack
 * removal against the given neighbour levels (patch_stitch.c). Returns 1 if it was moved. */
int tp__vertex_position(const tp_terrain* t, int patch, int k, const int nb[4], int i, int j,
                        int32_t* gx, int32_t* gy);

/* Bilinear resample of a float grid (NaN = nodata) to a new size (fit.c). */
tp_status tp__fit_resample(const tp_allocator* a, const float* src, const uint8_t* src_filled,
                           int w, int h, int nw, int nh, float** out, uint8_t** out_filled,
                           tp_error* err);

#endif
