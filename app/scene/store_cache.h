/*
 * store_cache.h - `terrapatch view DEM` draws every DEM through a store: the DEM is built into
 * one once (terrapatch build), in a cache directory, and reused while the DEM and the options
 * that shape the store stay the same (issue 12, section 1: one code path).
 *
 * The directory: --cache-dir DIR, else $TP_CACHE_DIR, else $XDG_CACHE_HOME/terrapatch, else
 * ~/.cache/terrapatch. When it cannot be created or written, the store is built in a fresh
 * temporary directory (mkdtemp under $TMPDIR, else /tmp) and one line says so; that store is
 * removed after the view. The file is NAME-KEY.tpt, KEY a 64-bit FNV-1a hash of the DEM's absolute
 * path, size and modification time and of every build option that changes the store (patch size,
 * --crs, --resampling, --fill-max, --fill-from and that file's path, size and time) and the
 * store format's version; a cached file is used only if it opens
 * as a store and its header and notes match (the source path, the patch size), else it is
 * rebuilt.
 *
 * One build of a cached store at a time: the builder holds an flock on NAME-KEY.tpt.lock (an
 * empty file beside the store while it is built); a second process asking for the same store waits
 * ("another terrapatch is building ...: waiting for it") and then finds it built. The temporary
 * files of builds that were killed (kill -9: no handler ran) are removed by the next process that
 * uses the cache, when no live build holds their lock.
 */
#ifndef TP_APP_STORE_CACHE_H
#define TP_APP_STORE_CACHE_H

#include "tp_io.h"

#include <stddef.h>

typedef struct tp_store_cache_options {
    const char* cache_dir;    /* --cache-dir; NULL: the environment's */
    int patch_size;           /* 17 .. 257 */
    const char* crs;          /* NULL: the DEM's */
    tp_resampling resampling;
    int fill_max_px;          /* as tp_grid_options.fill_max_px: 0 any size, < 0 fills nothing */
    const char* fill_from;    /* --fill-from; NULL: interpolate. Its absolute path, size and
                                 modification time are part of the key */
    const char* z_unit;       /* --z-unit; NULL: the DEM's */
    const char* cmd;          /* for messages: "view" */
} tp_store_cache_options;

/* Writes into out (cap bytes) the path of a store of dem, building it first if the cache has
 * none that matches (one line "terrapatch CMD: building a store of DEM in DIR (once; reused next
 * time)" and the build's progress on stderr). Returns TP_EXIT_OK, or the build's exit code
 * after its message. */
int tp_store_cache_get(const char* dem, const tp_store_cache_options* o, char* out, size_t cap,
                       int* temporary);
/* A store being built on a thread while a viewer draws its preview (tp_store_cache_begin). */
typedef struct tp_store_cache_job tp_store_cache_job;

/* tp_store_cache_get for a viewer that draws a first picture while the store is built. When the
 * cache must build the store and the DEM's grid has more than preview_samples samples, a
 * preview store (the same build of the grid coarsened by a power of two to at most that many
 * samples: tp_build_options.preview_max_samples) is built first into NAME-KEY.preview.tpt
 * beside the store (its path into preview, pcap bytes; one line says how coarse), and *job is
 * set: the store's own build, holding the cache's lock, waits for tp_store_cache_job_start
 * (which runs it on a thread) and ends with tp_store_cache_job_finish. The store's path is in
 * out as with tp_store_cache_get; only a finished job makes it. Otherwise (a store found, or a
 * grid that small, or preview_samples <= 0) exactly tp_store_cache_get, *job NULL and preview
 * "". TP_EXIT_OK, or an exit code after one line. */
int tp_store_cache_begin(const char* dem, const tp_store_cache_options* o, double preview_samples,
                         char* out, size_t cap, int* temporary, char* preview, size_t pcap,
                         tp_store_cache_job** job);
/* The preview's coarsening: its posts are this many times farther apart than the store's. */
int tp_store_cache_job_coarsen(const tp_store_cache_job* job);
/* Starts the job's build on a thread (once; a job never started builds in finish). */
void tp_store_cache_job_start(tp_store_cache_job* job);
/* 1 once the job's build has ended, well or not (tp_store_cache_job_finish says which). */
int tp_store_cache_job_done(const tp_store_cache_job* job);
/* Waits for the build, releases the lock, removes the preview and frees the job: the build's
 * exit code (TP_EXIT_OK: the store is in the cache; else after its message, 130/143 after a
 * signal). Accepts NULL (TP_EXIT_OK). */
int tp_store_cache_job_finish(tp_store_cache_job* job);

/* Removes a temporary store (*temporary was set) and its directory. */
void tp_store_cache_remove_temporary(const char* path);

/* A heightmap image placed by io (--spacing, --zscale, --origin) as a georeferenced GeoTIFF in
 * the cache, named by the image's absolute path, size, time and the options, and made once
 * (one note line) from tp_dem_read_image: the DEM from which the commands that read the ground
 * through a store build it. Its path in out (cap bytes). TP_EXIT_OK, else the exit status
 * after one error line (TP_EXIT_USAGE for options the image refuses). */
int tp_store_cache_heightmap(const char* image, const tp_image_options* io, const char* cache_dir,
                             char* out, size_t cap);

/* The cache directory the options and environment name (not created). */
void tp_store_cache_dir(const char* cache_dir, char* out, size_t cap);

#endif
