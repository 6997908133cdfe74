/* tp_lod.h - level of detail: modes, parameters, the distance formula (lod.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_LOD_H
#define TP_LOD_H

#include "tp_terrain.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Level of detail
 */
typedef enum tp_lod_mode {
    TP_LOD_DEFAULT = 0, /* = TP_LOD_ERROR */
    TP_LOD_DISTANCE,    /* Vanek & Jezek: mindist, maxdist, exponent */
    TP_LOD_ERROR,       /* Brodersen / de Boer: coarsest level whose error projects to <= tau px */
    TP_LOD_FULL,        /* every patch at level n (the full-resolution baseline) */
    TP_LOD_MAX_ERROR    /* static, no camera: coarsest levels whose measured vertical error is
                           <= max_error_m everywhere (see tp_selection_update) */
} tp_lod_mode;

/* The default widest hole along a void's edge (tp_lod_params.hole_px): docs/hierarchy.md,
 * "Voids", says how it was chosen. */
#define TP_DEFAULT_HOLE_PX 4.0

typedef struct tp_lod_params {
    tp_lod_mode mode;
    /* distance mode. mindist and maxdist BOTH zero mean defaults derived from the terrain:
     * mindist = 1 patch width, maxdist = 24 patch widths; otherwise they are used as given
     * (mindist 0 is valid). exponent 0 means 1. */
    double mindist_m, maxdist_m, exponent;
    double tau_px; /* error mode: screen-space error threshold in pixels; 0 means 1 */
    /* error mode over a tree (tp_cut_update): the widest hole, in pixels, that an incomplete
     * node drawn below its finest level may leave along a void's edge (valid samples in cells
     * that are not whole, see tp_node_mask_from_q); 0 means TP_DEFAULT_HOLE_PX. Infinity: no
     * limit; a tiny value keeps every such node at full resolution (what an export wants). */
    double hole_px;
    /* max-error mode: the bound (metres, finite, > 0; no default). The error is measured
     * against reference_heights when given: the source grid as given to tp_terrain_create
     * (src_width * src_height values, row-major, NaN = none; padded fits only), so that
     * quantisation counts; else against the decoded grid. The array is read only during
     * tp_selection_update. */
    double max_error_m;
    const float* reference_heights;
    size_t reference_height_count;
    /* distance mode over a tree (tp_cut_update; `--lod spheres`): nonzero selects through a
     * sphere tree (Blow, "Terrain rendering at high levels of detail", Part II; cut_spheres.c):
     * each node's refine and merge distances are surfaces around its area box, and a frame
     * re-decides only the nodes whose surfaces the eye crossed since the last update of the
     * same cut. The cut is exactly the plain traversal's (same nodes, levels, neighbours,
     * requests): frustum culling, residency and stitching run every frame as before. Ignored
     * by the other modes and by tp_selection_update. */
    int sphere_tree;
} tp_lod_params;

/* The distance formula (Vanek & Jezek section 3) for a patch with finest level n (0..TP_MAX_N):
 *   dist <= mindist: n;   dist > maxdist: 0;
 *   else k = ceil(n * (1 - ((dist - mindist) / (maxdist - mindist))^exponent)),
 * rounded UP so that a patch is never coarser than the formula asks. With mindist == maxdist
 * it is a step: n up to mindist, 0 beyond. exponent 0 gives 0 beyond mindist; a huge exponent
 * gives n up to maxdist (an infinite exponent too). A negative dist is clamped to 0.
 * Returns TP_OK and writes the level (0..n) to *out_level. TP_ERR_INVALID_ARG, with a message,
 * for a NaN dist, a negative or NaN mindist or maxdist, maxdist < mindist, or a negative or NaN
 * exponent (the parameters may come from the command line; unlike tp_lod_params_resolve this
 * applies no defaults). (It used to return the level, or -1 for invalid parameters.) */
tp_status tp_lod_level_distance(int n, double dist_m, double mindist_m, double maxdist_m,
                                double exponent, int* out_level, tp_error* err);

/* Validates params and fills in defaults for terrain t: returns TP_OK and writes the resolved
 * parameters to *out (which may be `in`). `in` may be NULL (all defaults); t may be NULL (the
 * distance defaults then assume 1 m patches). TP_ERR_INVALID_ARG with a message for an unknown
 * mode, negative / NaN / infinite values, maxdist < mindist, or tau below 0 (tau = 0 is the
 * default 1; use TP_LOD_FULL for an exact surface); in max-error mode also for max_error_m not
 * > 0 and for reference heights of the wrong count or with a resampled fit (these need t). */
tp_status tp_lod_params_resolve(const tp_terrain* t, const tp_lod_params* in, tp_lod_params* out,
                                tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_LOD_H */
