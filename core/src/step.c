/* step.c - the automatic quantisation step: one global step for the terrain (terrain.c) and
 * the tree (tree_build.c), 1 m for integral heights, else the finest power of two 2^-p m
 * (p <= 10) for which every range fits 16 bits. */
#include "step.h"

/* Does every range (owned by a patch) fit 16 bits (with 0xFFFF reserved) at this step? */
int tp__step_fits(const tp__range* r, int count, double step)
{
    for (int p = 0; p < count; p++) {
        if (r[p].lo > r[p].hi)
            continue;
        double a = floor(r[p].lo / step + 0.5), b = floor(r[p].hi / step + 0.5);
        if (fabs(a) > 2147483000.0 || fabs(b) > 2147483000.0 || b - a > 65534.0)
            return 0;
    }
    return 1;
}

double tp__choose_step(const tp__range* r, int count, int integral)
{
    /* Integer data: 1 m is exact. Otherwise the finest power of two down to 2^-10 m. */
    for (int e = integral ? 0 : -10; e <= 60; e++) {
        double step = ldexp(1.0, e);
        if (tp__step_fits(r, count, step))
            return step;
    }
    return 0;
}
