/*
 * tp_test_r3.h - exact visibility (R3, Franklin & Ray) for the tests of line of sight and
 * viewsheds (test_los.c, test_los_cli.c, test_viewshed.c). Written from the geometry, not from
 * the code under test (core/src/los.c, viewshed.c): the sight line from the eye over the
 * observer's sample to the target over the target's sample, against the ground where the line
 * crosses every column line x = ox + i (0 < |i| < |dx|) and every row line y = oy + j between
 * the two, the ground there linear between the two samples on that line; every height lowered
 * by curvature_coeff * d^2 / (2 * earth_radius_m) at horizontal distance d from the observer.
 * Void samples (NaN) are skipped: they block nothing.
 */
#ifndef TP_TEST_R3_H
#define TP_TEST_R3_H

#include <math.h>
#include <stddef.h>

typedef struct tp_test_r3 {
    double observer_height_m, target_height_m; /* above the ground at either end */
    double curvature_coeff;
    double earth_radius_m;                     /* 0: WGS84's 6378137 m */
    int skip_end_posts; /* 1: crossings within one post of either end are not tested (where
                           tp_los_compute says the observer and target stand) */
} tp_test_r3;

/* The smallest clearance of the sight line over the crossings tested (metres; negative:
 * hidden there); +INFINITY when none is tested. z: w samples a row, gt the grid's
 * geotransform (its steps give the distances). */
static inline double tp_test_r3_clearance(const float* z, int w, const double gt[6], int ox,
                                          int oy, int tx, int ty, const tp_test_r3* o)
{
    const double k =
        o->curvature_coeff / (2.0 * (o->earth_radius_m > 0 ? o->earth_radius_m : 6378137.0));
    const double sx = fabs(gt[1]), sy = fabs(gt[5]);
    const double eye = z[(size_t)oy * w + ox] + o->observer_height_m;
    const double dx = tx - ox, dy = ty - oy;
    const double dt2 = dx * dx * sx * sx + dy * dy * sy * sy;
    const double target = z[(size_t)ty * w + tx] - k * dt2 + o->target_height_m;
    const double span = fmax(fabs(dx), fabs(dy));
    double best = INFINITY;
    /* column lines x = ox + i, then row lines y = oy + j */
    for (int axis = 0; axis < 2; ++axis) {
        const double along = axis == 0 ? dx : dy, across = axis == 0 ? dy : dx;
        const int steps = (int)fabs(along);
        for (int i = 1; i < steps; ++i) {
            const double f = (double)i / steps;
            if (o->skip_end_posts && (f * span < 1.0 || (1.0 - f) * span < 1.0))
                continue;
            const double c = across * f; /* offset on the crossed line */
            const int c0 = (int)floor(c);
            const double t = c - c0;
            double zs[2];
            for (int e = 0; e < 2; ++e) {
                const int a = (int)(along > 0 ? i : -i), b = c0 + e;
                const int x = axis == 0 ? ox + a : ox + b, y = axis == 0 ? oy + b : oy + a;
                zs[e] = (e == 1 && t == 0.0) ? zs[0] : z[(size_t)y * w + x];
            }
            if (zs[0] != zs[0] || zs[1] != zs[1])
                continue;
            const double ground = zs[0] + t * (zs[1] - zs[0]) - k * f * f * dt2;
            best = fmin(best, eye + f * (target - eye) - ground);
        }
    }
    return best;
}

#endif /* TP_TEST_R3_H */
