/* lod.c - level-of-detail rules.
 *
 * Distance mode: Vanek & Jezek section 3, k = n * (1 - ((dist - mindist) / (maxdist - mindist))^exp)
 * rounded up, with dist the distance from the eye to the nearest point of the patch's AABB.
 *
 * Error mode: Brodersen section 3 / de Boer: the coarsest level whose error bound projects to at
 * most tau pixels ANYWHERE on screen. A vertical error d at camera-space point (x, y, z) moves
 * the point by d * v, with v = (vx, vy, vz) the world's vertical in camera coordinates; both
 * ends projected, it moves on screen by exactly
 *     f * |d| * sqrt(A^2 + B^2) / (z * (z + d * vz)),   A = vx*z - x*vz,  B = vy*z - y*vz
 * pixels (f the focal length in pixels). The classic f * d / distance is too small off the view
 * axis (by up to 1/cos^2 of the off-axis angle for a level camera, 2.4x at the corners of a 16:9,
 * 60 degree view); the direction-free bound f * d * |P| / z^2 is too large for oblique and
 * top-down views, where vertical errors near the view axis barely move on screen. A and B are
 * linear in the world position, so over a patch's AABB |A| <= Amax, |B| <= Bmax (largest over
 * its 8 corners), z >= Zmin, and the error mode uses
 *     f * d * sqrt(Amax^2 + Bmax^2) / (Zmin * (Zmin - d * |vz|))
 * (infinite when Zmin - d * |vz| <= 0 or the box reaches the near plane: level n).
 */
#include "lod_int.h"
#include "terrain_int.h"

#include <assert.h>
#include <string.h>

tp_status tp_lod_level_distance(int n, double dist, double mindist, double maxdist,
                                double exponent, int* out_level, tp_error* err)
{
    assert(n >= 0 && n <= TP_MAX_N && out_level);
    if (isnan(dist))
        return tp__fail(err, TP_ERR_INVALID_ARG, "lod: expected a distance, got NaN");
    if (!(mindist >= 0) || !(maxdist >= 0))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "lod: expected mindist and maxdist >= 0, got %g and %g", mindist,
                        maxdist);
    if (!(maxdist >= mindist))
        return tp__fail(err, TP_ERR_INVALID_ARG, "lod: expected maxdist >= mindist, got %g < %g",
                        maxdist, mindist);
    if (!(exponent >= 0))
        return tp__fail(err, TP_ERR_INVALID_ARG, "lod: expected an exponent >= 0, got %g",
                        exponent);
    int level;
    if (dist <= mindist) {
        level = n;
    } else if (dist > maxdist) {
        level = 0;
    } else {
        /* here mindist < dist <= maxdist, so maxdist > mindist and 0 < t <= 1 */
        double t = (dist - mindist) / (maxdist - mindist);
        double k = n * (1.0 - pow(t, exponent));
        level = (int)ceil(k - 1e-12);
        level = level < 0 ? 0 : level > n ? n : level;
    }
    *out_level = level;
    return TP_OK;
}

static int finite_nonneg(double v)
{
    return isfinite(v) && v >= 0;
}

tp_status tp_lod_params_resolve(const tp_terrain* t, const tp_lod_params* in, tp_lod_params* out,
                                tp_error* err)
{
    assert(out);
    tp_lod_params p = in ? *in : (tp_lod_params){0};
    if (p.mode == TP_LOD_DEFAULT)
        p.mode = TP_LOD_ERROR;
    if (p.mode != TP_LOD_DISTANCE && p.mode != TP_LOD_ERROR && p.mode != TP_LOD_FULL &&
        p.mode != TP_LOD_MAX_ERROR)
        return tp__fail(err, TP_ERR_INVALID_ARG, "lod: unknown mode %d", (int)p.mode);
    if (p.mode == TP_LOD_MAX_ERROR) {
        if (!(isfinite(p.max_error_m) && p.max_error_m > 0))
            return tp__fail(err, TP_ERR_INVALID_ARG,
                            "lod: max-error mode: expected a finite max_error_m > 0 m, got %g",
                            p.max_error_m);
        if (p.reference_heights && !t)
            return tp__fail(err, TP_ERR_INVALID_ARG,
                            "lod: max-error mode: reference heights need the terrain");
        if (p.reference_heights && t->info.fit == TP_FIT_RESAMPLE)
            return tp__fail(err, TP_ERR_INVALID_ARG,
                            "lod: max-error mode: reference heights need a padded fit (the "
                            "resampled grid has no source samples to compare with)");
        size_t want = t ? (size_t)t->info.src_width * (size_t)t->info.src_height : 0;
        if (p.reference_heights && p.reference_height_count != want)
            return tp__fail(err, TP_ERR_INVALID_ARG,
                            "lod: max-error mode: expected %zu reference heights (%dx%d), got %zu",
                            want, t->info.src_width, t->info.src_height,
                            p.reference_height_count);
    }
    if (!finite_nonneg(p.mindist_m) || !finite_nonneg(p.maxdist_m))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "lod: expected finite mindist and maxdist >= 0, got %g and %g",
                        p.mindist_m, p.maxdist_m);
    if (!finite_nonneg(p.exponent))
        return tp__fail(err, TP_ERR_INVALID_ARG, "lod: expected a finite exponent >= 0, got %g",
                        p.exponent);
    if (!finite_nonneg(p.tau_px))
        return tp__fail(err, TP_ERR_INVALID_ARG, "lod: expected a finite tau >= 0 px, got %g",
                        p.tau_px);
    if (p.mindist_m == 0 && p.maxdist_m == 0) {
        double patch_m = t ? t->ps * fmax(fabs(t->gt[1]), fabs(t->gt[5])) : 1.0;
        p.mindist_m = patch_m;
        p.maxdist_m = 24 * patch_m;
    }
    if (p.maxdist_m < p.mindist_m)
        return tp__fail(err, TP_ERR_INVALID_ARG, "lod: expected maxdist >= mindist, got %g < %g",
                        p.maxdist_m, p.mindist_m);
    if (p.exponent == 0)
        p.exponent = 1;
    if (p.tau_px == 0)
        p.tau_px = 1;
    if (!(p.hole_px >= 0)) /* infinity is valid */
        return tp__fail(err, TP_ERR_INVALID_ARG, "lod: expected a hole width >= 0 px, got %g",
                        p.hole_px);
    if (p.hole_px == 0)
        p.hole_px = TP_DEFAULT_HOLE_PX;
    *out = p;
    return TP_OK;
}

tp__proj_bound tp__proj_bound_box(const tp__view* v, const double bmin[3], const double bmax[3])
{
    /* The world's vertical in camera coordinates. */
    double vx = v->right[2], vy = v->up[2], vz = v->fwd[2];
    double zmin = INFINITY, amax = 0, bmax_ = 0;
    /* The products of each corner coordinate with each axis, once (18 instead of 72); summed
     * per corner in the same order as a dot product, so the results are the same bits. */
    double px[3][2], py[3][2], pz[3][2];
    for (int a = 0; a < 3; a++)
        for (int h = 0; h < 2; h++) {
            double d = (h ? bmax[a] : bmin[a]) - v->pos[a];
            px[a][h] = d * v->right[a], py[a][h] = d * v->up[a], pz[a][h] = d * v->fwd[a];
        }
    for (int c = 0; c < 8; c++) {
        int h0 = c & 1, h1 = (c >> 1) & 1, h2 = c >> 2;
        double x = px[0][h0] + px[1][h1] + px[2][h2];
        double y = py[0][h0] + py[1][h1] + py[2][h2];
        double z = pz[0][h0] + pz[1][h1] + pz[2][h2];
        double A = fabs(vx * z - x * vz), B = fabs(vy * z - y * vz);
        zmin = z < zmin ? z : zmin;
        amax = A > amax ? A : amax;
        bmax_ = B > bmax_ ? B : bmax_;
    }
    tp__proj_bound pb = {INFINITY, zmin};
    if (zmin > v->near_m)
        pb.num = v->f_px * sqrt(amax * amax + bmax_ * bmax_) / zmin;
    return pb;
}

double tp__projected_px(const tp__proj_bound* pb, double vz, double d)
{
    if (d == 0)
        return 0;
    double den = pb->zmin - d * fabs(vz);
    return den > 0 ? d * pb->num / den : INFINITY;
}

/* A vertical error d moves a point (x, z) of camera space to depth z' = z + d vz, and its
 * projection by f d (vx z - x vz) / (z z') across and f d (vy z - y vz) / (z z') up (the
 * numerators are A and B of tp__proj_bound_box). What is drawn of a box lies in front of the near
 * plane and inside the view's sides: there |x| <= tan_x z, so |A| / z <= |vx| + tan_x |vz| (and B
 * likewise), and z' >= near for a counterpart that is drawn too. Where the box starts in front
 * of the near plane num / f = sqrt(Amax^2 + Bmax^2) / zmin bounds the same ratio, and always
 * z' >= zmin - d |vz|: the smaller ratio over the larger depth holds. */
double tp__projected_px_drawn(const tp__view* v, const tp__proj_bound* pb, double d, int* near)
{
    double vx = fabs(v->right[2]), vy = fabs(v->up[2]), vz = fabs(v->fwd[2]);
    double z2 = pb->zmin - d * vz;
    *near = d > 0 && !(z2 >= v->near_m);
    if (d == 0)
        return 0;
    double a = vx + v->tan_x * vz, b = vy + v->tan_y * vz;
    double ratio = v->f_px * sqrt(a * a + b * b);
    if (pb->num < ratio)
        ratio = pb->num;
    return d * ratio / (z2 > v->near_m ? z2 : v->near_m);
}
