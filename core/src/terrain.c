/* terrain.c - the resident height grid: fitting, quantisation, queries.
 *
 * Storage (Brodersen section 4 asks for < 2.5 bytes per sample): one uint16 per stored sample,
 * quantised with ONE global step and an integer offset per patch. A sample is stored once and
 * decoded through the offset of the patch that owns it (tp__owner), so a border sample shared
 * by two patches decodes to the same value in both. Padding samples are not stored at all: they
 * are the region x >= sw or y >= sh. Filled-void flags cost one bit per sample and only exist
 * when the source has filled samples.
 */
#include "step.h"
#include "surface.h"
#include "terrain_int.h"

#include <float.h>
#include <stdlib.h>
#include <string.h>

static int patch_n(int patch_size)
{
    for (int n = 4; n <= TP_MAX_N; n++)
        if (patch_size == (1 << n) + 1)
            return n;
    return -1;
}

static void fill_info(tp_terrain* t, int src_w, int src_h, tp_fit fit)
{
    tp_terrain_info* in = &t->info;
    in->src_width = src_w;
    in->src_height = src_h;
    in->width = t->w;
    in->height = t->h;
    in->patch_size = t->ps + 1;
    in->n = t->n;
    in->levels = t->n + 1;
    in->patch_count = in->patch_cols * in->patch_rows;
    in->fit = fit;
    memcpy(in->geotransform, t->gt, sizeof t->gt);
    in->height_step_m = t->step;
    in->quant_max_error_m = t->quant_err;
    in->error_unit_m = t->err_unit * t->step;
    in->heights_bytes = (size_t)t->sw * (size_t)t->sh * sizeof(uint16_t);
    in->mask_bytes = t->filled ? ((size_t)t->sw * (size_t)t->sh + 7) / 8 : 0;
    in->patch_table_bytes = (size_t)in->patch_count *
                            (sizeof(tp__patch) + (size_t)t->err_stride * sizeof(uint16_t));
    in->resident_bytes = sizeof *t + in->heights_bytes + in->mask_bytes + in->patch_table_bytes;
    in->bytes_per_source_sample = (double)in->resident_bytes / ((double)src_w * (double)src_h);

    double lo = INFINITY, hi = -INFINITY;
    size_t valid = 0, filled = 0, nodata = 0;
    for (int y = 0; y < t->sh; y++)
        for (int x = 0; x < t->sw; x++) {
            int32_t q = tp__q(t, x, y);
            if (q == INT32_MIN) {
                nodata++;
                continue;
            }
            double z = q * t->step;
            lo = z < lo ? z : lo;
            hi = z > hi ? z : hi;
            size_t i = (size_t)y * t->sw + x;
            if (t->filled && (t->filled[i >> 3] >> (i & 7) & 1))
                filled++;
            else
                valid++;
        }
    in->min_height_m = lo;
    in->max_height_m = hi;
    in->valid_samples = valid;
    in->filled_samples = filled;
    in->nodata_samples = nodata;
    in->padding_samples = (size_t)t->w * t->h - (size_t)t->sw * t->sh;
}

/* Error of the rendered full-resolution surface at the original posts (resample only). */
static void fit_error(tp_terrain* t, const float* src, int w, int h)
{
    double mx = 0, sum = 0;
    size_t count = 0;
    double sx = (double)(t->w - 1) / (w - 1), sy = (double)(t->h - 1) / (h - 1);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            float s = src[(size_t)y * w + x];
            if (!isfinite(s))
                continue;
            double z = tp_terrain_height_at(t, x * sx, y * sy);
            if (isnan(z))
                continue;
            double e = fabs(z - s);
            mx = e > mx ? e : mx;
            sum += e * e;
            count++;
        }
    t->info.fit_max_error_m = mx;
    t->info.fit_rms_error_m = count ? sqrt(sum / count) : 0;
}

/* The checks of tp_terrain_create, in its order: TP_OK with the finest level, the fit and the
 * geotransform (all zeros: 1 m north-up); else the failure, nothing allocated. */
static tp_status check_desc(const tp_terrain_desc* desc, int* n_out, tp_fit* fit_out, double gt[6],
                            tp_error* err)
{
    int w = desc->width, h = desc->height;
    if (w < 1 || h < 1 || w > (1 << 24) || h > (1 << 24) || (double)w * h > 4e9)
        return tp__fail(err, TP_ERR_INVALID_ARG, "terrain: expected a grid of 1x1 to 2^24 per "
                        "side, got %dx%d", w, h);
    if (!desc->allocator.alloc != !desc->allocator.free)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "terrain: allocator: expected both alloc and free, or neither");
    if (!desc->heights || desc->height_count != (size_t)w * (size_t)h)
        return tp__fail(err, TP_ERR_INVALID_ARG, "terrain: expected %zu heights for %dx%d, got %zu",
                        (size_t)w * h, w, h, desc->heights ? desc->height_count : 0);
    if (desc->filled && desc->filled_count != (size_t)w * (size_t)h)
        return tp__fail(err, TP_ERR_INVALID_ARG, "terrain: expected %zu filled flags, got %zu",
                        (size_t)w * h, desc->filled_count);
    int patch_size = desc->patch_size ? desc->patch_size : TP_DEFAULT_PATCH_SIZE;
    int n = patch_n(patch_size);
    if (n < 0)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "terrain: expected a patch size of 17, 33, 65, 129 or 257, got %d",
                        patch_size);
    tp_fit fit = desc->fit ? desc->fit : TP_FIT_PAD;
    if (fit != TP_FIT_PAD && fit != TP_FIT_RESAMPLE)
        return tp__fail(err, TP_ERR_INVALID_ARG, "terrain: unknown fit mode %d", (int)fit);
    memcpy(gt, desc->geotransform, 6 * sizeof *gt);
    if (gt[1] == 0 && gt[5] == 0 && gt[2] == 0 && gt[4] == 0) {
        gt[1] = 1;
        gt[5] = -1;
    }
    for (int i = 0; i < 6; i++)
        if (!isfinite(gt[i]))
            return tp__fail(err, TP_ERR_INVALID_ARG, "terrain: geotransform[%d] is not finite", i);
    if (gt[2] != 0 || gt[4] != 0)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "terrain: rotated geotransforms are not supported (gt[2]=%g, gt[4]=%g)",
                        gt[2], gt[4]);
    if (gt[1] == 0 || gt[5] == 0)
        return tp__fail(err, TP_ERR_INVALID_ARG, "terrain: zero pixel size in geotransform");
    double step_req = desc->height_step_m;
    if (step_req < 0 || !isfinite(step_req))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "terrain: expected a height step > 0 (or 0 for automatic), got %g",
                        step_req);
    *n_out = n;
    *fit_out = fit;
    return TP_OK;
}

/* TP_FIT_RESAMPLE: the grid resampled to the nearest multiple of patches (*pc, *pr, patch span
 * ps) into *out and *out_filled (the caller frees them), and gt rescaled so that the first and
 * last post centres stay put. */
static tp_status fit_resample(const tp_terrain_desc* desc, int ps, int* pc, int* pr, double gt[6],
                              float** out, uint8_t** out_filled, tp_error* err)
{
    int w = desc->width, h = desc->height;
    *pc = (int)floor((double)(w - 1) / ps + 0.5);
    *pr = (int)floor((double)(h - 1) / ps + 0.5);
    *pc = *pc < 1 ? 1 : *pc;
    *pr = *pr < 1 ? 1 : *pr;
    tp_status s = tp__fit_resample(&desc->allocator, desc->heights, desc->filled, w, h,
                                   *pc * ps + 1, *pr * ps + 1, out, out_filled, err);
    if (s != TP_OK)
        return s;
    /* Same first and last post centres, new spacing. */
    double nsx = gt[1] * (w - 1) / (*pc * ps), nsy = gt[5] * (h - 1) / (*pr * ps);
    double cx = gt[0] + 0.5 * gt[1], cy = gt[3] + 0.5 * gt[5];
    gt[1] = nsx;
    gt[5] = nsy;
    gt[0] = cx - 0.5 * nsx;
    gt[3] = cy - 0.5 * nsy;
    return TP_OK;
}

/* Quantises the stored region of src into t: the ranges each patch owns (ranges: scratch of
 * patch_count), the step (step_req, or automatic), the patches' offsets, the stored heights
 * and filled flags, the quantisation error. w, h: the source's size, for the messages. */
static tp_status quantise(tp_terrain* t, const float* src, const uint8_t* src_filled,
                          double step_req, tp__range* ranges, int w, int h, tp_error* err)
{
    const tp_allocator* a = &t->alloc;
    int n = t->n, pc = t->info.patch_cols, pr = t->info.patch_rows, count = pc * pr;
    size_t stored = (size_t)t->sw * (size_t)t->sh;
    /* Owned ranges per patch, and whether every valid height is an integer. */
    int integral = 1, any_filled = 0;
    size_t valid = 0;
    for (int p = 0; p < count; p++)
        ranges[p] = (tp__range){INFINITY, -INFINITY};
    for (int y = 0; y < t->sh; y++)
        for (int x = 0; x < t->sw; x++) {
            float s = src[(size_t)y * t->sw + x];
            if (!isfinite(s))
                continue;
            valid++;
            tp__range* r = &ranges[tp__owner(y, n, pr) * pc + tp__owner(x, n, pc)];
            r->lo = s < r->lo ? s : r->lo;
            r->hi = s > r->hi ? s : r->hi;
            if (s != floorf(s))
                integral = 0;
            if (src_filled && src_filled[(size_t)y * t->sw + x])
                any_filled = 1;
        }
    if (valid == 0)
        return tp__fail(err, TP_ERR_BAD_DATA, "terrain: no valid height among %dx%d samples", w, h);
    if (step_req > 0) {
        if (!tp__step_fits(ranges, count, step_req))
            return tp__fail(err, TP_ERR_INVALID_ARG,
                            "terrain: height step %g m is too fine: a patch spans more than "
                            "65534 steps",
                            step_req);
        t->step = step_req;
    } else {
        t->step = tp__choose_step(ranges, count, integral);
        if (t->step == 0)
            return tp__fail(err, TP_ERR_BAD_DATA, "terrain: heights out of range (%g .. %g)",
                            ranges[0].lo, ranges[0].hi);
    }
    for (int p = 0; p < count; p++)
        t->patches[p].offset =
            ranges[p].lo <= ranges[p].hi ? (int32_t)floor(ranges[p].lo / t->step + 0.5) : 0;

    if (any_filled) {
        t->filled = tp__calloc(a, (stored + 7) / 8, 1);
        if (!t->filled)
            return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "terrain: out of memory for %dx%d samples",
                            w, h);
    }
    double qerr = 0;
    for (int y = 0; y < t->sh; y++)
        for (int x = 0; x < t->sw; x++) {
            size_t i = (size_t)y * t->sw + x;
            float s = src[i];
            if (!isfinite(s)) {
                t->q[i] = TP__NO_HEIGHT;
                continue;
            }
            int p = tp__owner(y, n, pr) * pc + tp__owner(x, n, pc);
            double qd = floor(s / t->step + 0.5);
            t->q[i] = (uint16_t)((int64_t)qd - t->patches[p].offset);
            double e = fabs(qd * t->step - s);
            qerr = e > qerr ? e : qerr;
            if (t->filled && src_filled[i])
                t->filled[i >> 3] |= (uint8_t)(1u << (i & 7));
        }
    t->quant_err = qerr;
    return TP_OK;
}

/* Per patch: range over all its drawn samples (shared borders included), completeness. */
static void patch_ranges(tp_terrain* t)
{
    int pc = t->info.patch_cols, ps = t->ps, count = pc * t->info.patch_rows;
    for (int p = 0; p < count; p++) {
        tp__patch* P = &t->patches[p];
        int x0 = (p % pc) * ps, y0 = (p / pc) * ps;
        int32_t lo = INT32_MAX, hi = INT32_MIN;
        P->complete = 1;
        for (int y = y0; y <= y0 + ps; y++)
            for (int x = x0; x <= x0 + ps; x++) {
                int32_t q = tp__q(t, x, y);
                if (q == INT32_MIN) {
                    P->complete = 0;
                    continue;
                }
                lo = q < lo ? q : lo;
                hi = q > hi ? q : hi;
            }
        P->has_drawn = lo <= hi;
        P->qmin = P->has_drawn ? lo : 0;
        P->qmax = P->has_drawn ? hi : 0;
    }
}

tp_status tp_terrain_create(const tp_terrain_desc* desc, tp_terrain** out, tp_error* err)
{
    assert(desc && out);
    int n = 0;
    tp_fit fit = TP_FIT_PAD;
    double gt[6];
    tp_status status = check_desc(desc, &n, &fit, gt, err);
    if (status != TP_OK)
        return status;
    int w = desc->width, h = desc->height;
    const tp_allocator* a = &desc->allocator;

    int ps = 1 << n;
    int pc = w > 1 ? (w - 2) / ps + 1 : 1, pr = h > 1 ? (h - 2) / ps + 1 : 1; /* ceil((w-1)/ps) */
    const float* src = desc->heights;
    const uint8_t* src_filled = desc->filled;
    float* resampled = NULL;
    uint8_t* resampled_filled = NULL;
    if (fit == TP_FIT_RESAMPLE) {
        status = fit_resample(desc, ps, &pc, &pr, gt, &resampled, &resampled_filled, err);
        if (status != TP_OK)
            return status;
        src = resampled;
        src_filled = resampled_filled;
    }

    tp_terrain* t = tp__calloc(a, 1, sizeof *t);
    tp__range* ranges = NULL;
    if (!t)
        goto oom;
    t->alloc = *a;
    t->n = n;
    t->ps = ps;
    t->w = pc * ps + 1;
    t->h = pr * ps + 1;
    t->sw = fit == TP_FIT_RESAMPLE ? t->w : w;
    t->sh = fit == TP_FIT_RESAMPLE ? t->h : h;
    memcpy(t->gt, gt, sizeof gt);
    t->info.patch_cols = pc;
    t->info.patch_rows = pr;
    int count = pc * pr;
    size_t stored = (size_t)t->sw * (size_t)t->sh;
    t->q = tp__alloc(a, stored, sizeof *t->q);
    t->patches = tp__calloc(a, (size_t)count, sizeof *t->patches);
    t->err_stride = (n + 1) + 4 * n;
    t->err_tab = tp__calloc(a, (size_t)count * t->err_stride, sizeof *t->err_tab);
    ranges = tp__alloc(a, (size_t)count, sizeof *ranges);
    if (!t->q || !t->patches || !t->err_tab || !ranges)
        goto oom;

    status = quantise(t, src, src_filled, desc->height_step_m, ranges, w, h, err);
    if (status != TP_OK)
        goto fail;
    patch_ranges(t);
    status = tp__patch_errors_compute(t, err);
    if (status != TP_OK)
        goto fail;
    fill_info(t, w, h, fit);
    if (fit == TP_FIT_RESAMPLE)
        fit_error(t, desc->heights, w, h);
    tp__free(a, ranges);
    tp__free(a, resampled);
    tp__free(a, resampled_filled);
    *out = t;
    return TP_OK;

oom:
    status = tp__fail(err, TP_ERR_OUT_OF_MEMORY, "terrain: out of memory for %dx%d samples", w, h);
fail:
    tp__free(a, ranges);
    tp__free(a, resampled);
    tp__free(a, resampled_filled);
    tp_terrain_destroy(t);
    return status;
}

void tp_terrain_destroy(tp_terrain* t)
{
    if (!t)
        return;
    tp_allocator a = t->alloc;
    tp__free(&a, t->q);
    tp__free(&a, t->filled);
    tp__free(&a, t->patches);
    tp__free(&a, t->err_tab);
    tp__free(&a, t->add_tab);
    tp__free(&a, t);
}

void tp_terrain_get_info(const tp_terrain* t, tp_terrain_info* out)
{
    assert(t && out);
    *out = t->info;
}

double tp_terrain_sample(const tp_terrain* t, int x, int y)
{
    assert(t);
    int32_t q = tp__q(t, x, y);
    return q == INT32_MIN ? NAN : q * t->step;
}

tp_sample_class tp_terrain_sample_class(const tp_terrain* t, int x, int y)
{
    assert(t);
    if (x < 0 || y < 0 || x >= t->w || y >= t->h)
        return TP_SAMPLE_OUTSIDE;
    if (x >= t->sw || y >= t->sh)
        return TP_SAMPLE_PADDING;
    size_t i = (size_t)y * t->sw + x;
    if (t->q[i] == TP__NO_HEIGHT)
        return TP_SAMPLE_NODATA;
    if (t->filled && (t->filled[i >> 3] >> (i & 7) & 1))
        return TP_SAMPLE_FILLED;
    return TP_SAMPLE_VALID;
}

/* Quantised height (steps) of sample (x, y) for tp__split_height; NaN if it is not drawn. */
static double q_height(const void* grid, int x, int y)
{
    int32_t q = tp__q((const tp_terrain*)grid, x, y);
    return q == INT32_MIN ? NAN : (double)q;
}

double tp_terrain_height_at(const tp_terrain* t, double x, double y)
{
    assert(t);
    /* in steps, then metres: the same rounding as interpolating the decoded heights' integers */
    return tp__split_height(q_height, t, t->w, t->h, x, y) * t->step;
}

/* Slope along one axis from the decoded grid: central where both neighbours exist. */
double tp_slope3(double a, double c, double b, double spacing)
{
    if (!isnan(a) && !isnan(b))
        return (b - a) / (2 * spacing);
    if (!isnan(b) && !isnan(c))
        return (b - c) / spacing;
    if (!isnan(a) && !isnan(c))
        return (c - a) / spacing;
    return 0;
}

static double slope(const tp_terrain* t, int x, int y, int dx, int dy, double spacing)
{
    return tp_slope3(tp_terrain_sample(t, x - dx, y - dy), tp_terrain_sample(t, x, y),
                     tp_terrain_sample(t, x + dx, y + dy), spacing);
}

void tp_terrain_normal(const tp_terrain* t, int x, int y, float normal[3])
{
    assert(t && normal);
    /* dz/dE and dz/dN: a step in x moves gt[1] east, a step in y moves gt[5] north. */
    double gx = slope(t, x, y, 1, 0, t->gt[1]), gy = slope(t, x, y, 0, 1, t->gt[5]);
    double len = sqrt(gx * gx + gy * gy + 1);
    normal[0] = (float)(-gx / len);
    normal[1] = (float)(-gy / len);
    normal[2] = (float)(1 / len);
}

void tp_terrain_grid_to_world(const tp_terrain* t, double x, double y, double* e, double* n)
{
    assert(t && e && n);
    *e = t->gt[0] + (x + 0.5) * t->gt[1];
    *n = t->gt[3] + (y + 0.5) * t->gt[5];
}

void tp_terrain_world_to_grid(const tp_terrain* t, double e, double n, double* x, double* y)
{
    assert(t && x && y);
    *x = (e - t->gt[0]) / t->gt[1] - 0.5;
    *y = (n - t->gt[3]) / t->gt[5] - 0.5;
}

void tp_patch_get_info(const tp_terrain* t, int patch, tp_patch_info* out)
{
    assert(t && patch >= 0 && patch < t->info.patch_count && out);
    const tp__patch* P = &t->patches[patch];
    int pc = t->info.patch_cols;
    memset(out, 0, sizeof *out);
    out->col = patch % pc;
    out->row = patch / pc;
    out->x0 = out->col * t->ps;
    out->y0 = out->row * t->ps;
    double e0, n0, e1, n1;
    tp_terrain_grid_to_world(t, out->x0, out->y0, &e0, &n0);
    tp_terrain_grid_to_world(t, out->x0 + t->ps, out->y0 + t->ps, &e1, &n1);
    out->aabb_min[0] = fmin(e0, e1);
    out->aabb_max[0] = fmax(e0, e1);
    out->aabb_min[1] = fmin(n0, n1);
    out->aabb_max[1] = fmax(n0, n1);
    out->aabb_min[2] = P->qmin * t->step;
    out->aabb_max[2] = P->qmax * t->step;
    out->complete = P->complete;
    for (int k = 0; k <= t->n; k++)
        out->delta_m[k] = tp_patch_error_bound(t, patch, k, NULL);
}
