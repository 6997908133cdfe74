/*
 * ground.h - the full-resolution ground under a position, for every command and tool that
 * asks "what is the ground here?" (`terrapatch point`, the viewer's point readout; line of
 * sight, viewsheds and profiles next). app/scene/ground.c; tp_ground_open in app/scene/ground_open.c.
 *
 * A tp_ground answers on a built store (.tpt): a DEM is first built into the store cache as
 * `terrapatch view` builds it (store_cache.c, the same cached file), so that every command
 * sees the same surface: the render grid (a geographic DEM warped to the UTM/UPS zone of its
 * centre, small interior voids filled), heights quantised to the store's step.
 *
 * Heights are those of tp_tree_height_at: the full-resolution surface (split cells over the
 * decoded samples), exact at grid posts (the stored sample). The leaves a query needs are read
 * with tp_store_read_node into a direct-mapped cache of at most cache_bytes and attached to
 * the ground's own tp_tree (never the viewer's: the stream owns that one's residency).
 *
 * Slope and aspect come from the gradient of that surface by central differences one post
 * either side of the point (x +- 1, y +- 1 grid steps), one-sided where a neighbour is void or
 * off the grid, as tp_tree_node_normal and gdaldem do at posts; on a plane they are exact.
 *
 * Positions: grid (x, y) is the render grid's (column, row), sample centres at integers;
 * world (E, N) is the render CRS, metres. A position is on the DEM when 0 <= x <= width - 1 and
 * 0 <= y <= height - 1 of the source grid (the store's padding is not the DEM).
 *
 * Not thread-safe: one tp_ground per thread (each reads the store with pread; the store is
 * shared).
 */
#ifndef TP_APP_GROUND_H
#define TP_APP_GROUND_H

#include "scene.h"
#include "store_scene.h"

#include "tp_io.h"

#include <stddef.h>

typedef struct tp_ground tp_ground;

typedef struct tp_ground_options {
    size_t cache_bytes;    /* leaves kept decoded; 0 means 16 MiB (at least 4 leaves) */
    const char* cache_dir; /* the store cache (a DEM): NULL for the environment's, as view */
    const char* cmd;       /* for messages: "point" */
    const tp_scene_options* dem; /* the DEM options (terrain_open.h): a DEM's store is built
                                    with them, a store refuses them; NULL: the defaults */
} tp_ground_options;

/* How slope and aspect are taken from the posts around a position. */
typedef enum tp_slope_method {
    TP_SLOPE_HORN = 0, /* Horn (1981): the 3x3 window, weighted 1-2-1 across each axis, as
                          gdaldem, GRASS r.slope.aspect and ArcGIS by default (the default) */
    TP_SLOPE_CENTRAL,  /* central differences of the four neighbours one post away */
} tp_slope_method;

/* What the ground is at one position. */
typedef struct tp_ground_sample {
    double x, y;                /* grid */
    double e_m, n_m;            /* render CRS */
    double height_m;            /* full-resolution surface, as stored; NaN in a void */
    double normal[3];           /* unit (east, north, up); (0, 0, 1) and NaN slope when unknown */
    double slope_deg;           /* 0 flat .. 90; NaN when no neighbour has a height */
    /* Aspect: the direction the slope faces (downhill), degrees clockwise, in [0, 360); NaN on
     * flat ground (gradient exactly 0) and where the slope is unknown. */
    double aspect_grid_deg;     /* from grid north (the render CRS's +N axis) */
    double aspect_true_deg;     /* from true north: aspect_grid_deg + convergence_deg; NaN
                                   without a geographic position */
    double convergence_deg;     /* bearing of grid north, clockwise from true north, at the point
                                   (the geodesic azimuth from it to a point 10 m up the grid's
                                   N axis); NaN without a CRS */
    /* The method slope and aspect came from: the ground's (tp_ground_set_slope_method), or
     * central differences where Horn's window has a post without a height (a void, the DEM's
     * edge), as gdaldem -compute_edges does not: there gdaldem gives nodata. */
    tp_slope_method slope_method;
} tp_ground_sample;

/* Opens path, a .tpt or a DEM (built into the cache first, progress on stderr as view), for
 * queries, through tp_terrain_store (terrain_open.h): o->dem's options, refused for a store. Prints
 * one line naming the file and returns TP_EXIT_FAILURE (or the build's code) on failure, *out
 * untouched; TP_EXIT_OK with *out on success. */
int tp_ground_open(const char* path, const tp_ground_options* o, tp_ground** out);

/* Queries over an open store scene (borrowed: it must outlive the ground): the viewer's. The
 * ground builds its own tree over the scene's node table. TP_ERR_OUT_OF_MEMORY, or the tree's
 * errors; *out written only on success. */
tp_status tp_ground_create(const tp_store_scene* sc, const tp_ground_options* o,
                           tp_ground** out, tp_error* err);
void tp_ground_destroy(tp_ground* g); /* accepts NULL */

/* The scene queried (its georeference, store info and path). Valid while g lives. */
const tp_store_scene* tp_ground_scene(const tp_ground* g);

/* Height (m) of the full-resolution surface at grid (x, y), as stored. TP_OK with *height_m
 * (NaN in a void); TP_ERR_INVALID_ARG ("grid (x, y) is outside the DEM (0..w-1, 0..h-1)") off
 * the DEM or for NaN; TP_ERR_BAD_DATA / TP_ERR_IO when a leaf cannot be read (the store's
 * message names the file and the node). *height_m written only on TP_OK. */
tp_status tp_ground_height(tp_ground* g, double x, double y, double* height_m, tp_error* err);

/* The method of the slopes and aspects g's queries give (TP_SLOPE_HORN until set). */
void tp_ground_set_slope_method(tp_ground* g, tp_slope_method m);

/* "horn" or "central". */
const char* tp_slope_method_name(tp_slope_method m);

/* Everything above at grid (x, y). Errors as tp_ground_height (a void is TP_OK: height NaN);
 * *out written only on TP_OK. */
tp_status tp_ground_query_grid(tp_ground* g, double x, double y, tp_ground_sample* out,
                               tp_error* err);
/* The same at render-CRS (E, N). */
tp_status tp_ground_query_world(tp_ground* g, double e_m, double n_m, tp_ground_sample* out,
                                tp_error* err);

/* For tp_ground_open (ground_open.c): release(owner) runs when g is destroyed, after g is
 * gone (it closes the scene g borrowed). */
void tp__ground_set_owner(tp_ground* g, void (*release)(void* owner), void* owner);

/* Leaves read from the store so far (cache misses). */
size_t tp_ground_reads(const tp_ground* g);

/* Windows of at least this many posts show their reading's progress. */
#define TP_GROUND_PROGRESS_POSTS ((size_t)4 << 20)

/* Reads the ground's heights (tp_ground_height: NaN in a void) at the w x h posts from grid
 * (x0, y0) into z (w * h floats, row by row). With progress (not NULL: the command's name) and
 * a window of TP_GROUND_PROGRESS_POSTS or more, "terrapatch CMD: reading the ground NN%" every
 * 10% on stderr (one line rewritten on a terminal). tp_ground_height's errors. */
tp_status tp_ground_read_posts(tp_ground* g, int x0, int y0, int w, int h, float* z,
                              const char* progress, tp_error* err);

#endif /* TP_APP_GROUND_H */
