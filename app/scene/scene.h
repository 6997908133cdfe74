/*
 * scene.h - what every command that opens a DEM does the same way: the DEM options, and the
 * pipeline DEM file -> tp_dem (as read) -> tp_render_grid (metric) -> tp_terrain (patches),
 * with its georeference.
 */
#ifndef TP_APP_SCENE_H
#define TP_APP_SCENE_H

#include "tp_core.h"
#include "tp_io.h"

#include "memory.h"
#include "options.h"

#include <stdio.h>

typedef struct tp_scene_options {
    int patch_size;          /* 17 .. 257 */
    tp_fit fit;
    tp_grid_options grid;    /* --crs, --resampling, --fill-max, --fill-from */
    tp_image_options image;  /* --spacing, --zscale, --origin (heightmap images) */
    int image_given;         /* one of those was given: read through OpenImageIO */
    const char* z_unit;      /* --z-unit m|ft|us-ft: the heights' unit, overriding the file's;
                                NULL: the file's (tp_dem_read_z) */
    tp_memory_use use;       /* the command, for the up-front memory check (memory.h) */
    unsigned given;          /* the DEM options given: bit (TP_OPT_x - TP_OPT_PATCH) of each */
} tp_scene_options;

/* The codes of the DEM options (tp_scene_option; their table: tp_scene_options_add). */
enum {
    TP_OPT_PATCH = 1000,
    TP_OPT_FIT,
    TP_OPT_CRS,
    TP_OPT_RESAMPLING,
    TP_OPT_FILL_MAX,
    TP_OPT_SPACING,
    TP_OPT_ZSCALE,
    TP_OPT_ORIGIN,
    TP_OPT_FILL_FROM,
    TP_OPT_Z_UNIT,
};

void tp_scene_options_default(tp_scene_options* o);

/* Reads arg for DEM option opt (a code above): returns 1 (taken), 0 (not a DEM option) or -1
 * (bad value; a one-line message naming cmd was printed). */
int tp_scene_option(int opt, const char* arg, tp_scene_options* o, const char* cmd);

/* Adds the DEM options to a command's parse (options.h): each read into o through
 * tp_scene_option. */
void tp_scene_options_add(tp_options* p, tp_scene_options* o);


/* Writes into out (cap bytes) the names of the DEM options in mask (a tp_scene_options.given),
 * as "--crs, --fill-max"; "" for none. */
void tp_scene_options_names(unsigned mask, char* out, size_t cap);

/* The bit of TP_OPT_x in tp_scene_options.given. */
#define TP_SCENE_GIVEN(opt) (1u << ((opt)-TP_OPT_PATCH))
/* The DEM options that shape a DEM's store (passed to its build); the others (--fit and the
 * heightmap options) shape a DEM drawn whole. */
#define TP_SCENE_STORE_OPTIONS                                                                     \
    (TP_SCENE_GIVEN(TP_OPT_PATCH) | TP_SCENE_GIVEN(TP_OPT_CRS) |                                   \
     TP_SCENE_GIVEN(TP_OPT_RESAMPLING) | TP_SCENE_GIVEN(TP_OPT_FILL_MAX) |                         \
     TP_SCENE_GIVEN(TP_OPT_FILL_FROM) | TP_SCENE_GIVEN(TP_OPT_Z_UNIT))

/* The help lines of the DEM options. */
void tp_scene_options_help(FILE* f);

typedef struct tp_scene {
    const char* path;        /* the DEM file (borrowed from the caller) */
    tp_dem* dem;             /* band 1 as read */
    tp_render_grid* grid;    /* the metric render grid */
    tp_terrain* terrain;     /* patches, levels, error tables */
    tp_georef* georef;       /* grid <-> render CRS <-> WGS84 */
    tp_terrain_info info;
} tp_scene;

/* Render grids of at least this many samples take seconds to warp and tile: tp_scene_load
 * says each step on stderr as it starts and ends. */
#define TP_SCENE_PROGRESS_SAMPLES ((double)(2048 * 2048))

/* Loads path through the whole pipeline. Once the DEM is read, the render grid is planned and
 * o->use of it checked against the memory left (memory.h): one line and TP_EXIT_FAILURE when it
 * would not fit, before the warp, the terrain or the command's own buffers are allocated. Prints
 * warnings ("terrapatch CMD: warning: ...") and, on failure, one error line naming the file;
 * returns TP_EXIT_OK, TP_EXIT_FAILURE, or TP_EXIT_USAGE when the heightmap options do not fit the
 * file (--spacing on a georeferenced raster). On failure the scene holds nothing. */
int tp_scene_load(const char* path, const tp_scene_options* o, tp_scene* scene);
void tp_scene_free(tp_scene* scene);

/* Prints each '\n'-separated line of text as its own "terrapatch CMD: warning: " line. */
void tp_print_warnings(const char* path, const char* text);

#endif /* TP_APP_SCENE_H */
