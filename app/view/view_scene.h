/*
 * view_scene.h - what the viewer looks at, behind one set of questions: a built store drawn
 * through its hierarchy (tp_cut over a streamed tp_tree: every DEM goes this way, built into a
 * cached store first, store_cache.c) or, for heightmap images only, a DEM loaded whole
 * (tp_selection over a tp_terrain, the old path). Picking, collision, measuring, the overlay
 * and the HUD ask these functions and never which of the two it is.
 */
#ifndef TP_APP_VIEW_SCENE_H
#define TP_APP_VIEW_SCENE_H

#include "renderer.h"
#include "scene.h"
#include "store_scene.h"

typedef struct tp_view_scene {
    const char* path;
    /* exactly one of the two */
    tp_scene* dem;            /* heightmap images: the old path */
    tp_selection* sel;
    tp_store_scene* store;    /* a store */
    tp_cut* cut;              /* the drawn cut: cut_own, or the cut thread's */
    tp_cut* cut_own;          /* selected on this thread (settling; --no-cut-thread) */
    tp_cut* prefetch;         /* the stream's look-ahead cut */
    struct tp_cut_worker* worker; /* the cut thread (cut_worker.h), or NULL */
    tp_camera worker_prev;    /* the camera of the frame before (the worker's prediction) */
    int worker_have_prev;
    tp_georef* georef;
    double gt[6];             /* of the fitted grid */
    int src_width, src_height, n;
    double min_height_m, max_height_m;
    int failures;             /* damaged nodes reported */
    int store_changed;        /* the store over HTTP was replaced on its server: the view ends */
    uint64_t reported[32];    /* hashes of the read failures said (tp_view_scene_say_once) */
    int reported_count;
    struct tp_view_imagery* imagery; /* imagery_view.h: a store's imagery, or NULL */
    int imagery_hidden;       /* F3: not drawn (still open) */
    int imagery_settle;       /* headless: every clip window whole before the frame */
    struct tp_ground* shadow_ground; /* cast shadows (--sun-date): the ground they are read
                                        from (owned by the caller), or NULL for none */
    struct tp_view_shadow* shadow;   /* their state (shadow_view.h) */
    struct tp_view_light* light;     /* the day's light map (light_view.h), or NULL */
    const struct tp_view_sun* sun;   /* the sun whose time it is drawn at (sun_view.h) */
    int light_settle;                /* headless: every clip window whole before the frame */
    int light_outside;               /* the sun's time left the light map's day (said once) */
    struct tp_normal_map* normals;   /* the terrain's normals (normal_map.h), or NULL: shaded from
                                        the vertex normals */
    int normals_settle;              /* headless: every clip window whole before the frame */
    struct tp_pgm_renderer* pgm;     /* --renderer pgm (a DEM drawn whole): draws instead of the
                                        patches (pgm_render.h; owned by the caller), or NULL */
} tp_view_scene;

void tp_view_scene_from_dem(tp_view_scene* v, tp_scene* sc, tp_selection* sel);
/* Creates the cuts and the cut thread; 0 after a message. */
int tp_view_scene_from_store(tp_view_scene* v, tp_store_scene* st);
void tp_view_scene_release(tp_view_scene* v); /* the cuts (the scenes belong to the caller) */

void tp_view_scene_world_to_grid(const tp_view_scene* v, double e, double n, double* x, double* y);
/* Height (true metres) of the drawn surface at grid (x, y); NaN where nothing is drawn. */
double tp_view_scene_drawn_height(const tp_view_scene* v, double x, double y);
/* Height of the full-resolution surface; a store reads the leaf there first if needed (on this
 * thread: "a query may wait for its own node only"). */
double tp_view_scene_ground_height(tp_view_scene* v, double x, double y);
int tp_view_scene_ray_cast(const tp_view_scene* v, const double o[3], const double d[3],
                           tp_ray_hit* hit);
/* Collision (drawn space), the leaf under the eye made resident first. */
void tp_view_scene_keep_above(tp_view_scene* v, double position[3], double clearance_m);
void tp_view_scene_set_vertical_scale(tp_view_scene* v, double scale);
double tp_view_scene_vertical_scale(const tp_view_scene* v);
/* How tp_view_scene_measure measured: a store's cut (its counts: what share of the leaves
 * under it was compared, tp_cut_error), or PGM (the share of the view's posts compared). */
typedef struct tp_view_measured_how {
    int cut;                 /* 1: a store's cut, cut_error below */
    tp_cut_error cut_error;
    double post_share;       /* PGM: 1, or less where the view's region was sampled; NaN else */
    double ms;               /* the measure's time */
} tp_view_measured_how;

/* The drawn surface's screen error for cam (px); metres where the path measures them (NaN
 * else); PGM's by tp_pgm_renderer_measure (over a store too: bands of the view's posts past
 * 2^26 of them; NaN px when not measured, the reason printed once). A store's cut:
 * tp_store_scene_measure over the leaves of at most about max_posts posts (0: every one); px
 * NaN when no sample could be measured (none in view, or none to be read: never 0 for that),
 * a leaf that cannot be read left out (counted in how->cut_error.leaves_skipped; the stream
 * reports the nodes it loads). how (may be NULL) says what was measured. */
void tp_view_scene_measure(const tp_view_scene* v, const tp_camera* cam, size_t max_posts,
                           double* max_m, double* rms_m, double* max_px, double* rms_px,
                           tp_view_measured_how* how);

/* A store: selects and streams without drawing until nothing is pending (headless frames are
 * complete), at most timeout_s. Returns the iterations. */
int tp_view_scene_settle(tp_view_scene* v, const tp_camera* cam, const tp_lod_params* lod,
                         double timeout_s);

/* Prints each damaged node's message once (stderr). */
void tp_view_scene_report_failures(tp_view_scene* v);

/* 1 when message (a read failure: the stream's, the normal map's) was not said yet, which it
 * now is: a damaged node that both read is reported once. */
int tp_view_scene_say_once(tp_view_scene* v, const char* message);

#endif
