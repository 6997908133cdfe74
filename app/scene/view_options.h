/*
 * view_options.h - the options every command that looks at the terrain through a camera takes
 * (view, export, bench): level of detail, camera, field of view and image size, parsed one way.
 */
#ifndef TP_APP_VIEW_OPTIONS_H
#define TP_APP_VIEW_OPTIONS_H

#include "scene.h"

#include <stdio.h>

typedef struct tp_view_setup {
    tp_lod_params lod;      /* mode defaults to error; zeros mean the core's defaults */
    int has_camera, camera_geo;
    double camera[5];       /* E or lat, N or lon, H, yaw, pitch */
    double fov_deg;         /* default 60 */
    double vertical_scale;  /* view --exaggeration: the default camera looks at the drawn
                               (exaggerated) terrain; default 1 */
    int w, h;               /* default 1280 x 720 */
    /* --renderer pgm and --pgm-grid (view and bench only: tp_view_options_add's renderer) */
    int pgm;                /* Persistent Grid Mapping instead of the patches */
    int pgm_grid[8][2];     /* cols, rows; default one TP_PGM_DEFAULT_COLS x _ROWS */
    int pgm_grid_count;     /* grids given (0: the default) */
    int pgm_window;         /* --pgm-window: a store's clipmap window, posts a side (0: the
                               default, TP_PGM_CLIP_DEFAULT_WINDOW in app/render/pgm_clip.h) */
    int msaa;               /* --msaa N (view and bench): samples a pixel, 0 none; -1 (the
                               default, auto): 4 on a GPU, none on a software renderer
                               (tp_gl_context_default_msaa in app/render/gl_context.h) */
    int mesh_tin;           /* --mesh tin (view and bench): a store's complete nodes draw
                               error-bounded TINs where they have fewer triangles at the same
                               bound (tp_cut_set_tins); 0: --mesh lattice, the default */
} tp_view_setup;

void tp_view_setup_default(tp_view_setup* v);

/* Adds the LoD and camera options to a command's parse (options.h), read into v; with renderer,
 * also --renderer, --pgm-grid, --pgm-window, --msaa and --mesh (view and bench: export draws
 * nothing). */
void tp_view_options_add(tp_options* p, tp_view_setup* v, int renderer);

/* Parses the arguments of a command that looks at the terrain through a camera (view, bench,
 * export): its own options (own: CODE options go to own.handler), the DEM options into dem, the
 * camera and LoD options into v (tp_view_options_add, renderer as there), the DEM into *path
 * and the first operand too many into *extra (NULL when none: the command says what it was).
 * Returns -1 when every argument was read, else the exit code (0 after the help, 2 after a
 * usage error). */
int tp_view_command_parse(const char* cmd, int argc, char** argv, void (*help)(void),
                          tp_option_table own, tp_scene_options* dem, tp_view_setup* v,
                          int renderer, const char** path, const char** extra);

/* Checks the LoD parameters once all options are read; -1 after a message, else 0. */
int tp_view_setup_check(const tp_view_setup* v, const char* cmd);

/* The camera of the options, or the default camera (the whole DEM in view); 0 after a message
 * when a --camera-geo position has no render-grid coordinates. */
int tp_view_setup_camera(const tp_scene* sc, const tp_view_setup* v, tp_camera* cam,
                         const char* cmd);

/* Prints the LoD and camera options' help (one text for view, export and bench). */
void tp_view_options_help(FILE* out);

/* Prints the help of --renderer and --pgm-grid (view; bench: several grids). */
void tp_view_renderer_help(FILE* out, int bench);

/* Once the scene is loaded: warns on stderr (naming cmd) about LoD parameters that are valid
 * but almost surely not meant, such as a --maxdist shorter than one patch width. */
void tp_view_setup_warn(const tp_scene* sc, const tp_view_setup* v, const char* cmd);

#endif
