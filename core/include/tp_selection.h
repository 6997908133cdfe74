/* tp_selection.h - a selection over a tp_terrain: one frame's levels, visibility and statistics,
 * its measures and queries (selection.c, selection_measure.c, selection_query.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_SELECTION_H
#define TP_SELECTION_H

#include "tp_camera.h"
#include "tp_lod.h"
#include "tp_terrain.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Selection: one frame's levels, visibility and statistics
 */
typedef struct tp_selection tp_selection;

/* Creates a selection of terrain t, every patch at level n, visible and dirty; t must outlive
 * it. Returns TP_OK and sets *out; fails only with TP_ERR_OUT_OF_MEMORY. */
tp_status tp_selection_create(const tp_terrain* t, tp_selection** out, tp_error* err);
void tp_selection_destroy(tp_selection* s); /* accepts NULL */

/* Selects a level for every patch (visible or not: culled patches still stitch their visible
 * neighbours) with params (NULL: the defaults; resolved by tp_lod_params_resolve), then, in
 * error mode, raises the coarser neighbour of any stitched side whose
 * bound projects above tau until none does (levels only go up, so it ends; with
 * tp_selection_set_stitch_add, the patches that take vertices instead), and culls.
 * Incomplete patches are always at level n.
 * TP_LOD_MAX_ERROR ignores cam (it may be NULL) and marks every patch visible: each patch
 * starts at the coarsest level whose delta_m is <= max_error_m; then, in rounds, each patch
 * whose own or a neighbour's level changed in the previous round (every patch in the first) is
 * measured (its stitched triangles against the reference heights of every sample they cover)
 * and, above the bound, its coarser neighbours go up to one level finer than they were, or, if
 * none is coarser, the patch itself goes up one level, until no patch measures above the
 * bound (a patch at level n above it, possible when the bound is below quant_max_error_m,
 * stays there). It allocates scratch: TP_ERR_OUT_OF_MEMORY, levels unchanged, if that fails.
 * Every other mode needs cam (asserted). Fails with tp_lod_params_resolve's TP_ERR_INVALID_ARG
 * for invalid params; on any failure levels, visibility and dirty flags are unchanged. */
tp_status tp_selection_update(tp_selection* s, const tp_camera* cam, const tp_lod_params* params,
                              tp_error* err);

/* Sets one patch's level (0..n) by hand (tests, export, frozen views). Incomplete patches stay
 * at n. All patches are marked visible until the next tp_selection_update or tp_selection_cull.
 * Cannot fail. (It used to return TP_ERR_INVALID_ARG for a bad patch or k; those are now
 * asserted: no user value reaches it unchecked.) */
void tp_selection_set_level(tp_selection* s, int patch, int k);
/* Re-runs culling only, keeping levels. Cannot fail. */
void tp_selection_cull(tp_selection* s, const tp_camera* cam);

/* Returns the patch's current level (0..n). */
int tp_selection_level(const tp_selection* s, int patch);
/* Answers whether the patch passed the last culling: 1 visible, 0 culled. */
int tp_selection_visible(const tp_selection* s, int patch);
/* Writes the neighbour levels of a patch, indexed by tp_side (TP_NO_NEIGHBOR at the terrain
 * border). Cannot fail. */
void tp_selection_neighbor_levels(const tp_selection* s, int patch, int out[4]);
/* Answers 1 if the patch's level or a neighbour's level changed since the previous call to
 * tp_selection_clear_dirty (initially every patch is dirty): its vertex data must be rebuilt. */
int tp_selection_dirty(const tp_selection* s, int patch);
/* Marks every patch clean (after their vertex data was rebuilt). Cannot fail. */
void tp_selection_clear_dirty(tp_selection* s);

typedef struct tp_frame_stats {
    int patches_per_level[TP_MAX_LEVELS]; /* visible patches only */
    int visible_patches, culled_patches;
    size_t triangles;                     /* non-degenerate drawn triangles of visible patches */
    /* The delta-bound (quantisation included) over visible patches: max, and RMS of the bound
     * weighted by the samples each patch owns. */
    double bound_max_error_m, bound_rms_error_m;
} tp_frame_stats;

/* Writes the statistics of the current levels into *out. Cannot fail. Not const: it fills the
 * selection's cache of drawn-triangle counts (and uses its scratch), so it must not run at the
 * same time as any other call on the same selection. (It used to take a const pointer and
 * write through it.) */
void tp_selection_stats(tp_selection* s, tp_frame_stats* out);

/* Threads: the functions below take a const selection and write nothing in it; each call
 * allocates its own scratch and frees it before returning. Several threads may call them on
 * one selection at once, as long as no thread changes the selection meanwhile (update,
 * set_level, cull, clear_dirty, stats). The measures fail only with TP_ERR_OUT_OF_MEMORY
 * (scratch); tp_selection_ray_cast also with TP_ERR_INVALID_ARG. */

/* Exact vertical error of the drawn (stitched) geometry of visible patches against every drawn
 * sample they own, measured against the decoded grid (add quant_max_error_m for the source).
 * Each sample is counted once. Returns TP_OK and writes *out; TP_ERR_OUT_OF_MEMORY. */
typedef struct tp_error_measure {
    double max_error_m, rms_error_m;
    size_t samples;
} tp_error_measure;
tp_status tp_selection_measure_error(const tp_selection* s, tp_error_measure* out);

/* Screen-space error (pixels) for cam: for every drawn sample of a visible patch that is inside
 * the view and in front of the near plane, the on-screen length between the projections of
 * the sample and of the drawn surface vertically above/below it. Occlusion is ignored.
 * Returns TP_OK and writes the maximum, the RMS and the number of samples to those of max_px,
 * rms_px and samples that are not NULL; TP_ERR_OUT_OF_MEMORY. */
tp_status tp_selection_measure_screen_error(const tp_selection* s, const tp_camera* cam,
                                            double* max_px, double* rms_px, size_t* samples);

/* The same measure for one patch as if it alone were drawn at level k (0..n; its neighbours at
 * their current levels, its border stitched to them): returns TP_OK and writes to *out_px the
 * largest screen error (px) of the samples its triangles cover, 0 when none is in view. Used
 * to ask how far the error LoD's bound is from the coarsest level each patch could really
 * have. Fails only with TP_ERR_OUT_OF_MEMORY. (It used to return TP_ERR_INVALID_ARG for a NULL
 * cam or out_px or a bad patch or k; those are now asserted.) */
tp_status tp_selection_patch_screen_error(const tp_selection* s, const tp_camera* cam, int patch,
                                          int k, double* out_px);

/* How the drawn geometry removes cracks: 0 (the default) by moving vertices (tp_patch_vertices:
 * the error mode raises the coarser neighbour of a stitched side, as tp_selection_update says),
 * nonzero by adding them (tp_patch_triangles_add, `--stitch add`): the error mode then raises,
 * instead, each visible patch that takes a finer neighbour's vertices until its
 * tp_patch_error_bound_add projects <= tau (levels only go up, so it ends), and
 * tp_frame_stats' bound is tp_patch_error_bound_add. The measures and queries below still
 * describe vertex moving's geometry. Takes effect at the next update. Cannot fail; the max-error
 * mode, which measures vertex moving's geometry, then refuses to update (TP_ERR_INVALID_ARG). */
void tp_selection_set_stitch_add(tp_selection* s, int add);
int tp_selection_stitch_add(const tp_selection* s); /* 1 when adding */

/* The vertical scales a selection accepts: below 1/1000 a drawn height loses its metres to
 * rounding (the ray cast divides by the scale), above 1000 nothing is terrain any more. */
#define TP_VERTICAL_SCALE_MIN 1e-3
#define TP_VERTICAL_SCALE_MAX 1e3

/* Vertical exaggeration: the surface is drawn with heights times scale (> 0; 1 by default).
 * Everything that depends on the drawn geometry follows it: culling boxes, the error LoD's
 * projection (tau holds on screen), the screen-error measures, tp_selection_keep_above and
 * tp_selection_ray_cast, whose positions are in drawn space (E, N, height * scale). Errors
 * in metres (tp_frame_stats, tp_selection_measure_error) and tp_selection_drawn_height_at stay
 * true heights. Returns TP_OK; TP_ERR_INVALID_ARG, scale unchanged, for a scale that is not a
 * number in [TP_VERTICAL_SCALE_MIN, TP_VERTICAL_SCALE_MAX] (it comes from the command line). */
tp_status tp_selection_set_vertical_scale(tp_selection* s, double scale);
/* Returns the current vertical scale. */
double tp_selection_vertical_scale(const tp_selection* s);

/* Query: returns the height (metres) of the surface actually drawn at grid coordinates (x, y)
 * under the current levels (stitching included); NaN where nothing is drawn, outside the grid
 * or for NaN coordinates. O(1) inside a patch, O(2^k) along a stitched border. */
double tp_selection_drawn_height_at(const tp_selection* s, double x, double y);

/* Camera collision: raises position[2] (drawn space) so the eye is at least clearance_m (finite,
 * >= 0) above both the full-resolution surface and the drawn surface at its (E, N), heights
 * times the vertical scale. Answers whether it moved the eye: 1, or 0 when the eye is already
 * high enough or there is no surface below it (outside the terrain, nodata, a NaN position),
 * position then unchanged. Cannot fail. */
int tp_selection_keep_above(const tp_selection* s, double position[3], double clearance_m);

/* Where a ray meets the drawn surface. */
typedef struct tp_ray_hit {
    int hit;            /* 1 if the ray meets a drawn triangle */
    double position[3]; /* E, N and the TRUE height of the drawn surface there */
    double distance_m;  /* from the origin along the ray, in drawn space */
    int patch;          /* the patch hit; -1 if none (and for tp_cut_ray_cast) */
    int64_t node;       /* tp_cut_ray_cast: the tree node hit; -1 if none (and for a selection) */
} tp_ray_hit;

/* Casts the ray origin + t * dir (t >= 0; drawn space: heights times the vertical scale; dir
 * need not be unit) against the triangles the selection draws (levels and crack removal as
 * drawn), culled patches included, and writes the nearest hit (out->hit = 0 if none). Exact up
 * to rounding: the hit lies on a drawn triangle. Walks only the patches the ray's ground track
 * crosses, nearest first, skipping those whose box it passes above or below.
 * Returns TP_OK also when nothing is hit. TP_ERR_INVALID_ARG for a zero or NaN direction or a
 * NaN origin (they may come from a mouse position), TP_ERR_OUT_OF_MEMORY; *out is untouched. */
tp_status tp_selection_ray_cast(const tp_selection* s, const double origin[3],
                                const double dir[3], tp_ray_hit* out);

#ifdef __cplusplus
}
#endif
#endif /* TP_SELECTION_H */
