/* ray.h - ray casting's exact tests and the camera collision, inline (selection_query.c,
 * cut_query.c). */
#ifndef TP_CORE_RAY_H
#define TP_CORE_RAY_H

#include "internal.h"

/* ---- ray casting (selection_query.c for selections, cut_query.c for cuts) ---- */

/* Clips [*t0, *t1] to the t where o + t d lies in [lo, hi]; 0 if empty. */
static inline int tp__slab(double o, double d, double lo, double hi, double* t0, double* t1)
{
    if (d == 0)
        return o >= lo && o <= hi;
    double a = (lo - o) / d, b = (hi - o) / d;
    if (a > b) {
        double c = a;
        a = b;
        b = c;
    }
    *t0 = a > *t0 ? a : *t0;
    *t1 = b < *t1 ? b : *t1;
    return *t0 <= *t1;
}

/* Nearest t >= 0 where the ray (origin at 0, direction d) meets triangle (a, b, c), or -1
 * (Moller & Trumbore). Edges and vertices count, so a ray through a shared edge hits one of its
 * triangles. */
static inline double tp__ray_triangle(const double d[3], const double a[3], const double b[3],
                                      const double c[3])
{
    double e1[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    double e2[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    double p[3] = {d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
                   d[0] * e2[1] - d[1] * e2[0]};
    double det = e1[0] * p[0] + e1[1] * p[1] + e1[2] * p[2];
    if (det == 0)
        return -1;
    double s[3] = {-a[0], -a[1], -a[2]};
    double u = (s[0] * p[0] + s[1] * p[1] + s[2] * p[2]) / det;
    double q[3] = {s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
                   s[0] * e1[1] - s[1] * e1[0]};
    double v = (d[0] * q[0] + d[1] * q[1] + d[2] * q[2]) / det;
    const double eps = 1e-12;
    if (u < -eps || v < -eps || u + v > 1 + eps)
        return -1;
    double t = (e2[0] * q[0] + e2[1] * q[1] + e2[2] * q[2]) / det;
    return t >= 0 ? t : -1;
}

/* Camera collision (tp_selection_keep_above, tp_cut_keep_above): raises position[2] (drawn
 * space) to clearance_m above the higher of the full-resolution height full_m and the drawn
 * height drawn_m (true metres, NaN: none) times zscale; 1 if it moved the eye. */
static inline int tp__keep_above(double position[3], double full_m, double drawn_m, double zscale,
                                 double clearance_m)
{
    double a = full_m, b = drawn_m;
    double ground = (isnan(a) ? b : isnan(b) ? a : (a > b ? a : b)) * zscale;
    if (isnan(ground) || position[2] >= ground + clearance_m)
        return 0;
    position[2] = ground + clearance_m;
    return 1;
}

#endif
