/* selection.c - one frame: a level per patch, culling and statistics. The exact error of what
 * a selection draws is measured in selection_measure.c, heights of the drawn surface queried in
 * selection_query.c.
 *
 * Based on: Vanek & Jezek (WSCG 2004) section 3 for distance LoD and AABB culling; Brodersen
 * (2005) section 3 for the error-driven selection. Formulas are in lod.c.
 */
#include "selection_int.h"

#include <assert.h>

#include <stdlib.h>
#include <string.h>

int tp__neighbor(const tp_terrain* t, int p, int side)
{
    int pc = t->info.patch_cols, pr = t->info.patch_rows, c = p % pc, r = p / pc;
    switch (side) {
    case TP_SIDE_TOP: return r > 0 ? p - pc : -1;
    case TP_SIDE_RIGHT: return c + 1 < pc ? p + 1 : -1;
    case TP_SIDE_BOTTOM: return r + 1 < pr ? p + pc : -1;
    default: return c > 0 ? p - 1 : -1;
    }
}

static void mark_dirty(tp_selection* s, int p)
{
    s->dirty[p] = 1;
    s->tris[p] = TP__STALE_TRIS;
    for (int side = 0; side < 4; side++) {
        int q = tp__neighbor(s->t, p, side);
        if (q >= 0) {
            s->dirty[q] = 1;
            s->tris[q] = TP__STALE_TRIS;
        }
    }
}

tp_status tp_selection_create(const tp_terrain* t, tp_selection** out, tp_error* err)
{
    assert(t && out);
    const tp_allocator* a = &t->alloc;
    tp_selection* s = tp__calloc(a, 1, sizeof *s);
    if (!s)
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "selection: out of memory");
    int count = t->info.patch_count;
    size_t v = ((size_t)1 << t->n) + 1;
    s->t = t;
    s->count = count;
    s->level = tp__alloc(a, (size_t)count, 1);
    s->next = tp__alloc(a, (size_t)count, 1);
    s->visible = tp__alloc(a, (size_t)count, 1);
    s->dirty = tp__alloc(a, (size_t)count, 1);
    s->proj = tp__calloc(a, (size_t)count, sizeof *s->proj);
    s->tris = tp__alloc(a, (size_t)count, sizeof *s->tris);
    s->vbuf = tp__alloc(a, v * v, sizeof *s->vbuf);
    if (!s->level || !s->next || !s->visible || !s->dirty || !s->proj || !s->tris || !s->vbuf) {
        tp_selection_destroy(s);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "selection: out of memory for %d patches",
                        count);
    }
    memset(s->level, t->n, (size_t)count);
    memset(s->visible, 1, (size_t)count);
    memset(s->dirty, 1, (size_t)count);
    for (int p = 0; p < count; p++)
        s->tris[p] = TP__STALE_TRIS;
    s->zscale = 1;
    *out = s;
    return TP_OK;
}

void tp_selection_destroy(tp_selection* s)
{
    if (!s)
        return;
    const tp_allocator* a = &s->t->alloc;
    tp__free(a, s->level);
    tp__free(a, s->next);
    tp__free(a, s->visible);
    tp__free(a, s->dirty);
    tp__free(a, s->proj);
    tp__free(a, s->tris);
    tp__free(a, s->vbuf);
    tp__free(a, s);
}

int tp_selection_level(const tp_selection* s, int patch)
{
    assert(s && patch >= 0 && patch < s->count);
    return s->level[patch];
}

int tp_selection_visible(const tp_selection* s, int patch)
{
    assert(s && patch >= 0 && patch < s->count);
    return s->visible[patch];
}

void tp_selection_neighbor_levels(const tp_selection* s, int patch, int out[4])
{
    assert(s && patch >= 0 && patch < s->count && out);
    for (int side = 0; side < 4; side++) {
        int q = tp__neighbor(s->t, patch, side);
        out[side] = q >= 0 ? s->level[q] : TP_NO_NEIGHBOR;
    }
}

int tp_selection_dirty(const tp_selection* s, int patch)
{
    assert(s && patch >= 0 && patch < s->count);
    return s->dirty[patch];
}

void tp_selection_clear_dirty(tp_selection* s)
{
    assert(s);
    memset(s->dirty, 0, (size_t)s->count);
}

void tp_selection_set_level(tp_selection* s, int patch, int k)
{
    assert(s && patch >= 0 && patch < s->count && k >= 0 && k <= s->t->n);
    const tp_terrain* t = s->t;
    if (!t->patches[patch].complete)
        k = t->n;
    if (s->level[patch] != k) {
        s->level[patch] = (uint8_t)k;
        mark_dirty(s, patch);
    }
    memset(s->visible, 1, (size_t)s->count);
}

void tp_selection_set_stitch_add(tp_selection* s, int add)
{
    assert(s);
    s->stitch_add = add != 0;
}

int tp_selection_stitch_add(const tp_selection* s)
{
    assert(s);
    return s->stitch_add;
}

tp_status tp_selection_set_vertical_scale(tp_selection* s, double scale)
{
    assert(s);
    if (!(scale >= TP_VERTICAL_SCALE_MIN && scale <= TP_VERTICAL_SCALE_MAX))
        return TP_ERR_INVALID_ARG;
    s->zscale = scale;
    return TP_OK;
}

double tp_selection_vertical_scale(const tp_selection* s)
{
    assert(s);
    return s->zscale;
}

void tp__drawn_box(const tp_selection* s, int p, tp_patch_info* pi)
{
    tp_patch_get_info(s->t, p, pi);
    pi->aabb_min[2] *= s->zscale;
    pi->aabb_max[2] *= s->zscale;
}

void tp_selection_cull(tp_selection* s, const tp_camera* cam)
{
    assert(s && cam);
    tp_frustum f;
    tp_frustum_from_camera(cam, &f);
    for (int p = 0; p < s->count; p++) {
        tp_patch_info pi;
        tp__drawn_box(s, p, &pi);
        s->visible[p] = tp_frustum_test_aabb(&f, pi.aabb_min, pi.aabb_max) != TP_CULL_OUTSIDE;
    }
}

static tp__proj_bound projection_bound(const tp__view* v, const tp_patch_info* pi)
{
    return tp__proj_bound_box(v, pi->aabb_min, pi->aabb_max);
}

static double projected_px(const tp__proj_bound* pb, double vz, double d)
{
    return tp__projected_px(pb, vz, d);
}

static double aabb_distance(const double pos[3], const tp_patch_info* pi)
{
    double d2 = 0;
    for (int a = 0; a < 3; a++) {
        double d = pos[a] < pi->aabb_min[a] ? pi->aabb_min[a] - pos[a]
                 : pos[a] > pi->aabb_max[a] ? pos[a] - pi->aabb_max[a]
                 : 0;
        d2 += d * d;
    }
    return sqrt(d2);
}

/* Geometric part (metres, no quantisation) of the stitching bound of one side. */
static double side_bound_m(const tp_terrain* t, int p, int side, int kn)
{
    const tp__patch* P = &t->patches[p];
    unsigned e = tp__eps_tab(t, p, side)[kn];
    double range = (double)(P->qmax - P->qmin);
    double steps = e >= TP__ERR_SAT ? range : e * t->err_unit;
    return (steps < range ? steps : range) * t->step;
}

/* Sets next[q] to level k as tp_selection_set_level would (incomplete patches stay at n), and
 * flags q and its neighbours for re-measuring when it changed. */
static void raise_level(tp_selection* s, uint8_t* changed, int q, int k)
{
    if (!s->t->patches[q].complete)
        k = s->t->n;
    if (s->next[q] == k)
        return;
    s->next[q] = (uint8_t)k;
    changed[q] = 1;
    for (int side = 0; side < 4; side++) {
        int r = tp__neighbor(s->t, q, side);
        if (r >= 0)
            changed[r] = 1;
    }
}

/* TP_LOD_MAX_ERROR: each patch starts at the coarsest level whose delta is <= the bound; then,
 * in rounds, every patch whose own or a neighbour's level changed in the previous round (all
 * of them in the first) is measured under the levels as they are at that moment, and where its
 * measured error exceeds the bound the coarser neighbours that moved its border go up one
 * level past theirs, else the patch itself goes up one. Levels only go up, so this ends, with
 * every patch measuring <= the bound (level n measures 0 against the decoded grid). */
static tp_status select_max_error(tp_selection* s, const tp_lod_params* lp, tp_error* err)
{
    const tp_terrain* t = s->t;
    const tp_allocator* a = &t->alloc;
    int n = t->n, count = s->count;
    size_t v = ((size_t)1 << n) + 1;
    int* todo = tp__alloc(a, (size_t)count, sizeof *todo);
    uint8_t* changed = tp__alloc(a, (size_t)count, 1);
    uint32_t* tbuf = tp__alloc(a, 3 * 2 * (v - 1) * (v - 1), sizeof *tbuf);
    tp_status st = TP_OK;
    if (!todo || !changed || !tbuf) {
        st = tp__fail(err, TP_ERR_OUT_OF_MEMORY,
                      "selection: out of memory measuring the levels of %d patches (max-error "
                      "mode)",
                      count);
        goto done;
    }
    for (int p = 0; p < count; p++) {
        tp_patch_info pi;
        tp_patch_get_info(t, p, &pi);
        int k = n;
        while (k > 0 && pi.delta_m[k - 1] <= lp->max_error_m)
            k--;
        s->next[p] = (uint8_t)(t->patches[p].complete ? k : n);
        changed[p] = 1;
    }
    for (;;) {
        int todo_count = 0;
        for (int p = 0; p < count; p++) {
            if (changed[p])
                todo[todo_count++] = p;
            changed[p] = 0;
        }
        if (todo_count == 0)
            break;
        for (int i = 0; i < todo_count; i++) {
            int p = todo[i], k = s->next[p], nb[4], raised = 0;
            for (int side = 0; side < 4; side++) {
                int q = tp__neighbor(t, p, side);
                nb[side] = q >= 0 ? s->next[q] : TP_NO_NEIGHBOR;
            }
            if (tp__patch_vertical_error(t, p, k, nb, lp->reference_heights, s->vbuf, tbuf) <=
                lp->max_error_m)
                continue;
            for (int side = 0; side < 4; side++)
                if (nb[side] >= 0 && nb[side] < k) {
                    raise_level(s, changed, tp__neighbor(t, p, side), nb[side] + 1);
                    raised = 1;
                }
            if (!raised && k < n)
                raise_level(s, changed, p, k + 1);
        }
    }
    for (int p = 0; p < count; p++) {
        s->visible[p] = 1;
        if (s->next[p] != s->level[p]) {
            s->level[p] = s->next[p];
            mark_dirty(s, p);
        }
    }
done:
    tp__free(a, todo);
    tp__free(a, changed);
    tp__free(a, tbuf);
    return st;
}

tp_status tp_selection_update(tp_selection* s, const tp_camera* cam, const tp_lod_params* params,
                              tp_error* err)
{
    assert(s);
    const tp_terrain* t = s->t;
    tp_lod_params lp;
    tp_status st = tp_lod_params_resolve(t, params, &lp, err);
    if (st != TP_OK)
        return st;
    if (lp.mode == TP_LOD_MAX_ERROR && s->stitch_add)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "selection: the max-error mode measures vertex moving's geometry: not "
                        "with vertex adding (tp_selection_set_stitch_add)");
    if (lp.mode == TP_LOD_MAX_ERROR)
        return select_max_error(s, &lp, err);
    assert(cam); /* only the max-error mode works without a camera */
    tp__view v;
    tp__view_from_camera(cam, &v);
    tp_frustum f;
    tp_frustum_from_camera(cam, &f);
    int n = t->n;

    /* Everything in drawn space: boxes and errors scaled by the vertical exaggeration. */
    double zs = s->zscale;
    for (int p = 0; p < s->count; p++) {
        tp_patch_info pi;
        tp__drawn_box(s, p, &pi);
        int vis = tp_frustum_test_aabb(&f, pi.aabb_min, pi.aabb_max) != TP_CULL_OUTSIDE;
        s->visible[p] = (uint8_t)vis;
        int k = n;
        s->proj[p] = (tp__proj_bound){0, 0};
        if (lp.mode == TP_LOD_DISTANCE) {
            /* The parameters are resolved, so only a NaN distance (a NaN eye) fails: such a
             * patch is drawn at n, below. */
            if (tp_lod_level_distance(n, aabb_distance(v.pos, &pi), lp.mindist_m, lp.maxdist_m,
                                      lp.exponent, &k, NULL) != TP_OK)
                k = -1;
        } else if (lp.mode == TP_LOD_ERROR) {
            /* A culled patch has no error of its own to show; the stitching pass below
             * raises it where a visible neighbour needs that. */
            k = 0;
            if (vis) {
                tp__proj_bound pb = projection_bound(&v, &pi);
                s->proj[p] = pb;
                /* Coarsest level such that it and every finer level project to <= tau, so that
                 * raising the patch later never breaks its own bound. */
                k = n;
                while (k > 0 && (pi.delta_m[k - 1] == 0 ||
                                 projected_px(&pb, v.fwd[2], zs * pi.delta_m[k - 1]) <= lp.tau_px))
                    k--;
            }
        }
        if (!t->patches[p].complete || k < 0)
            k = n;
        s->next[p] = (uint8_t)k;
    }

    if (lp.mode == TP_LOD_ERROR && s->stitch_add) {
        /* Vertex adding: a finer neighbour re-triangulates this patch's border triangles on
         * that side, whose bound (tp_patch_error_bound_add) can exceed delta: raise the patch
         * itself until it projects <= tau (at its neighbours' levels nothing is added). Raising
         * it can make it finer than a neighbour, which is checked in the next round; levels
         * only go up, so this ends. */
        for (int changed = 1; changed;) {
            changed = 0;
            for (int p = 0; p < s->count; p++) {
                if (s->proj[p].num == 0 || s->next[p] >= n)
                    continue;
                int nb[4], adds = 0;
                for (int side = 0; side < 4; side++) {
                    int q = tp__neighbor(t, p, side);
                    nb[side] = q >= 0 && s->next[q] > s->next[p] ? s->next[q] : TP_NO_NEIGHBOR;
                    adds |= nb[side] != TP_NO_NEIGHBOR;
                }
                if (!adds)
                    continue;
                double geo = tp__patch_add_bound_m(t, p, s->next[p], nb);
                if (projected_px(&s->proj[p], v.fwd[2], zs * (geo + t->quant_err)) > lp.tau_px) {
                    s->next[p]++;
                    changed = 1;
                }
            }
        }
    } else if (lp.mode == TP_LOD_ERROR) {
        /* Stitched border triangles of a patch next to a coarser neighbour can exceed both
         * patches' delta: raise that neighbour until every stitched side projects <= tau.
         * Levels only go up, so this ends. */
        for (int changed = 1; changed;) {
            changed = 0;
            for (int p = 0; p < s->count; p++) {
                if (s->proj[p].num == 0)
                    continue;
                for (int side = 0; side < 4; side++) {
                    int q = tp__neighbor(t, p, side);
                    if (q < 0 || s->next[q] >= s->next[p])
                        continue;
                    double geo = side_bound_m(t, p, side, s->next[q]);
                    if (geo > 0 && projected_px(&s->proj[p], v.fwd[2], zs * (geo + t->quant_err)) >
                                       lp.tau_px) {
                        s->next[q]++;
                        changed = 1;
                    }
                }
            }
        }
    }

    for (int p = 0; p < s->count; p++)
        if (s->next[p] != s->level[p]) {
            s->level[p] = s->next[p];
            mark_dirty(s, p);
        }
    return TP_OK;
}

static uint32_t patch_triangle_count(tp_selection* s, int p)
{
    if (s->tris[p] == TP__STALE_TRIS) {
        int nb[4], k = s->level[p];
        tp_selection_neighbor_levels(s, p, nb);
        size_t v = ((size_t)1 << s->t->n) + 1;
        tp_patch_vertices(s->t, p, k, nb, s->vbuf, v * v);
        s->tris[p] = (uint32_t)tp_patch_triangles(s->vbuf, k, NULL, 0);
    }
    return s->tris[p];
}

/* Samples a patch owns (each grid sample belongs to exactly one patch). */
static double owned_samples(const tp_terrain* t, int p)
{
    int pc = t->info.patch_cols, pr = t->info.patch_rows, c = p % pc, r = p / pc;
    return (double)(c + 1 == pc ? t->ps + 1 : t->ps) * (double)(r + 1 == pr ? t->ps + 1 : t->ps);
}

void tp_selection_stats(tp_selection* s, tp_frame_stats* out)
{
    assert(s && out);
    memset(out, 0, sizeof *out);
    double sum = 0, weight = 0;
    for (int p = 0; p < s->count; p++) {
        if (!s->visible[p]) {
            out->culled_patches++;
            continue;
        }
        out->visible_patches++;
        out->patches_per_level[s->level[p]]++;
        out->triangles += patch_triangle_count(s, p);
        int nb[4];
        tp_selection_neighbor_levels(s, p, nb);
        double b = s->stitch_add ? tp_patch_error_bound_add(s->t, p, s->level[p], nb)
                                 : tp_patch_error_bound(s->t, p, s->level[p], nb);
        double w = owned_samples(s->t, p);
        out->bound_max_error_m = b > out->bound_max_error_m ? b : out->bound_max_error_m;
        sum += w * b * b;
        weight += w;
    }
    out->bound_rms_error_m = weight > 0 ? sqrt(sum / weight) : 0;
}
