/*
 * overlay.h - everything drawn over the terrain: the HUD text (wrapped to the window), the key
 * help, the measuring tool's line, grid labels, the north arrow and the scale bar, laid out so
 * that none covers another.
 */
#ifndef TP_APP_OVERLAY_H
#define TP_APP_OVERLAY_H

#include "drape.h"
#include "hud.h"
#include "view.h"

/* The line of sight drawn on the ground (window.c's line-of-sight mode): the ground track
 * from the observer to the target, green where a target there is seen, red where hidden, the
 * first obstruction marked "X". */
typedef struct tp_overlay_los {
    const double* enh;          /* count points: E, N (render CRS), ground height (m) */
    const unsigned char* seen;  /* count flags */
    size_t count;
    int has_obstruction;
    double obstruction_enh[3];
} tp_overlay_los;

/* A viewshed (window.c's B): the posts the observer cannot see, tinted red. */
typedef struct tp_overlay_viewshed {
    const double* enh;      /* count posts: E, N, ground height (m) */
    size_t count;
    double spacing_m;       /* between the posts kept (the dots' size on screen) */
    double observer_enh[3];
} tp_overlay_viewshed;

/* Features draped on the ground (contours, --overlay files): lines and rings hidden where the
 * terrain in front hides them, points as dots with their names. */
typedef struct tp_overlay_drape {
    const tp_drape* drape;
    unsigned char rgba[4];
    float width_px;        /* at overlay scale 1; index contours twice; a dark outline under
                              lines 2.5 px wide or more, contours aside */
    int label_values;      /* label index contours with their elevation ("1500") */
} tp_overlay_drape;

typedef struct tp_overlay {
    const char* hud_text;     /* NULL: no HUD (nor north arrow and scale bar) */
    const char* help_text;    /* NULL: none */
    const char* measure_line; /* NULL or "": none */
    double grid_m;            /* grid label spacing (0: no labels) */
    int has_mark;             /* mark_enh: a ground point marked with "+" (the point readout) */
    double mark_enh[3];       /* E, N (render CRS) and true height (m) */
    const tp_overlay_los* los; /* NULL: no line of sight drawn */
    const tp_overlay_viewshed* viewshed; /* NULL: none */
    const tp_overlay_drape* drapes;      /* drape_count of them, drawn first to last */
    size_t drape_count;
    double near_m, far_m; /* the terrain's depth range (tp_render_stats): what is draped on the
                             ground is hidden behind it; far_m 0: drawn over everything */
} tp_overlay;

/* The text scale the overlay uses for a viewport: 2 from 1000 px wide, else 1. */
float tp_overlay_scale(int w, int h);

void tp_view_overlay_draw(tp_hud* hud, const tp_view_scene* v, const tp_camera* cam,
                          const tp_overlay* ov);

#endif
