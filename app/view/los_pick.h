/*
 * los_pick.h - the viewer's line-of-sight mode (R, then two right clicks: observer, target):
 * tp_los_compute over the full-resolution ground (ground.h) between the two picked points,
 * kept as the ground track the overlay draws green where seen and red where hidden, with the
 * first obstruction marked (overlay.h's tp_overlay_los). app/view/los_pick.c.
 */
#ifndef TP_APP_VIEW_LOS_PICK_H
#define TP_APP_VIEW_LOS_PICK_H

#include "ground.h"
#include "overlay.h"

#include <stddef.h>

typedef struct tp_view_los {
    int picked;           /* 1 after the observer's click */
    double observer[2];   /* E, N of the observer (render CRS) */
    double* enh;          /* the last line's samples (E, N, ground height) */
    unsigned char* seen;
    size_t count;
    tp_overlay_los overlay; /* what tp_view_overlay_draw draws; count 0 before a line */
} tp_view_los;

/* A click on the ground at render (e, n): the observer the first time, the target the second
 * (then the line is computed with gdal_viewshed's defaults: eye 2 m, target 0 m, coefficient
 * 0.85714). line (cap bytes) gets the HUD's line; on the second click the full result is also
 * printed to stdout. Returns 1 when a line was computed, 0 otherwise (line says why or what is
 * next). */
int tp_view_los_click(tp_view_los* l, tp_ground* g, double e_m, double n_m, char* line,
                      size_t cap);

void tp_view_los_free(tp_view_los* l); /* the arrays; l stays usable (zeroed) */

#endif /* TP_APP_VIEW_LOS_PICK_H */
