/* lod_int.h - the error mode's projection bound (lod.c), for the selection and the cut. */
#ifndef TP_CORE_LOD_INT_H
#define TP_CORE_LOD_INT_H

#include "camera_int.h"
#include "tp_lod.h"

/* The error-mode bound of one patch for the current view (see lod.c): a vertical error of d
 * metres anywhere in the patch's AABB projects to at most d * num / (zmin - d * |vz|) pixels. */
typedef struct tp__proj_bound {
    double num; /* f * sqrt(Amax^2 + Bmax^2) / zmin; INFINITY when the box reaches the near plane */
    double zmin; /* smallest depth of the box's corners */
} tp__proj_bound;

/* The bound for the box bmin..bmax (drawn space) seen from v, and the pixels a vertical error
 * of d metres (drawn space) inside that box projects to at most: 0 for d = 0, INFINITY when
 * the box reaches the near plane (lod.c). */
tp__proj_bound tp__proj_bound_box(const tp__view* v, const double bmin[3], const double bmax[3]);
double tp__projected_px(const tp__proj_bound* pb, double vz, double d);
/* The bound over what is drawn of a box: points in front of the near plane and inside the view's
 * sides whose counterpart (moved by d) is in front of the near plane too (what is clipped is
 * not on screen). Never above tp__projected_px, and finite for every finite d where that is
 * INFINITY: at most f d sqrt((1 + tan_x)^2 + (1 + tan_y)^2) / near. *near says whether the near
 * plane bounds it: d > 0 and zmin - d |vz| < near (the box reaches the near plane, or d could
 * carry a point of it there). For reports: the selection keeps tp__projected_px and refines such
 * a box as far as it can. */
double tp__projected_px_drawn(const tp__view* v, const tp__proj_bound* pb, double d, int* near);

#endif
