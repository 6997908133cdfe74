/*
 * terrain_open.h - the one way every command opens the ground it works on (issue 29, part 1).
 * app/scene/terrain_open.c.
 *
 * A path given to any command (info, build, view, bench, export, point, los, viewshed, light,
 * profile, contours, imagery) is one of:
 *   - a terrapatch store (.tpt), known by its magic bytes;
 *   - a damaged store: named .tpt, or starting like one, without the whole magic. Refused as
 *     such ("not a terrapatch store, or its header is damaged"), never handed to GDAL, whose
 *     two lines about an unknown raster format would only confuse;
 *   - a DEM: anything GDAL (or, for heightmap images, OpenImageIO) reads, GDAL's virtual paths
 *     (/vsizip/, /vsigzip/, /vsitar/, /vsicurl/) included.
 * The DEM options (scene.h: --patch, --fit, --crs, --resampling, --fill-max, --fill-from,
 * --spacing, --zscale, --origin) are parsed by one parser and printed by one help text in
 * every command. Given with a store they are refused the same way by every command: a store
 * keeps the options it was built with. Commands that query or draw the ground read a DEM
 * through its store in the cache (store_cache.h), built with the DEM options.
 */
#ifndef TP_APP_TERRAIN_OPEN_H
#define TP_APP_TERRAIN_OPEN_H

#include "scene.h"
#include "store_cache.h"

#include <stddef.h>

typedef enum tp_terrain_kind {
    TP_TERRAIN_DEM = 0,
    TP_TERRAIN_STORE = 1,
} tp_terrain_kind;

/* What path names. TP_TERRAIN_STORE or TP_TERRAIN_DEM; -1 after one line for a damaged store
 * ("terrapatch CMD: PATH: not a terrapatch store, or its header is damaged (...)") or a store
 * inside a GDAL virtual path (stores are read from local files): the command exits with 1. A path
 * that cannot be read is a DEM here: its reader says why. */
int tp_terrain_kind_of(const char* path);

/* For a store: when any DEM option was given (o->given), "terrapatch CMD: PATH is a store: OPTS
 * shape a DEM when it is read or built; a store keeps those it was built with (rebuild it from
 * the DEM with terrapatch build)" and TP_EXIT_USAGE. Returns -1 (go on) otherwise. */
int tp_terrain_refuse_store_options(const char* cmd, const char* path, const tp_scene_options* o);

/* The two above in one call, as every command begins: -1 to go on, with *is_store (1 for a
 * store, whose DEM options were refused, 0 for a DEM); else the exit code after one line (a
 * damaged store: 1; DEM options given with a store: 2). */
int tp_terrain_classify(const char* cmd, const char* path, const tp_scene_options* o,
                        int* is_store);

/* The store that a command reading the ground through a store (point, los, viewshed, light,
 * profile, contours, view, bench) reads for path: path itself when it is a store (with the DEM
 * options refused as above), or a DEM's store from the cache, built with o's --patch (the
 * store's node size; default: o->patch_size as the command set it), --crs, --resampling,
 * --fill-max and --fill-from. --fit does not apply to a store (it takes any size) and is
 * refused, exit 2. The store's path into out (cap bytes); *temporary set when it was built in
 * a temporary folder (tp_store_cache_remove_temporary after use). Returns TP_EXIT_OK, or the
 * exit code after one line. */
int tp_terrain_store(const char* cmd, const char* path, const tp_scene_options* o,
                     const char* cache_dir, char* out, size_t cap, int* temporary);

/* tp_terrain_store for the viewer's first picture: a DEM whose store must be built and whose
 * grid has more than preview_samples samples gets a preview store first (its path in preview,
 * pcap bytes) and *job, the store's build to start and finish (tp_store_cache_begin); else as
 * tp_terrain_store, *job NULL. */
int tp_terrain_store_begin(const char* cmd, const char* path, const tp_scene_options* o,
                           const char* cache_dir, double preview_samples, char* out, size_t cap,
                           int* temporary, char* preview, size_t pcap, tp_store_cache_job** job);

#endif /* TP_APP_TERRAIN_OPEN_H */
