/* step.h - the automatic quantisation step of the terrain (terrain.c) and the tree
 * (tree_build.c): step.c. */
#ifndef TP_CORE_STEP_H
#define TP_CORE_STEP_H

#include "internal.h"

/* The automatic quantisation step (terrain.c): 1 m for integral heights, else the finest power
 * of two 2^-p m (p <= 10), coarser where a range would not fit 65534 steps; 0 if none fits. */
typedef struct tp__range {
    double lo, hi; /* lo > hi when empty */
} tp__range;
int tp__step_fits(const tp__range* r, int count, double step);
double tp__choose_step(const tp__range* r, int count, int integral);

#endif
