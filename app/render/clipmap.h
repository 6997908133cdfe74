/*
 * clipmap.h - imagery of any size on the GPU through a clipmap (issue 15; Luo & Duan, "Clipmap
 * texture streaming"; Tanner et al.'s clipmap): one texture array, one layer per pyramid level,
 * each layer holding the clip window of that level (tp_clip_window in tp_core.h: s x s blocks
 * around a clip centre a quarter window ahead of the camera), updated toroidally (only blocks
 * newly covered are uploaded, into the slots of those that left), at most a capped number of
 * bytes a frame (Luo & Duan section 3.3: a fast flight spreads its updates over frames; the
 * shader meanwhile samples a coarser level), from the blocks imagery_cache.h's loader thread
 * reads, with the prefetch of where the windows will be (the clip centre's shift between
 * frames, extrapolated) and garbage collection by the direction of that shift (section 3.4).
 * Levels finer than any drawn patch needs (Blow's per-polygon texture level,
 * tp_patch_texture_level) are neither updated nor sampled.
 *
 * GPU memory is (s * block)^2 * 4 bytes per level, whatever the image size: 4 MiB a level at
 * the default s = 4 (1024 texels), 8 levels for a 32768^2 image: 32 MiB.
 */
#ifndef TP_APP_VIEW_CLIPMAP_H
#define TP_APP_VIEW_CLIPMAP_H

#include "imagery_cache.h"
#include "renderer.h"
#include "tp_core.h"

typedef struct tp_clipmap tp_clipmap;

typedef struct tp_clipmap_options {
    int clip_blocks;          /* s: blocks a side of every level's window, even, 2..32; 0: 4 */
    size_t cache_bytes;       /* the loader's pool of blocks in RAM; 0: 64 MiB */
    size_t upload_cap_bytes;  /* texels uploaded per frame at most; 0: 8 blocks (2 MiB) */
    double prefetch_s;        /* how far ahead the clip centres are extrapolated; 0: 0.5 s */
    int no_loader;            /* tests: nothing read in the background */
    double frame_s;           /* > 0: each update is this much later than the last (a bench's
                                 fixed-rate flight); 0: the real clock */
} tp_clipmap_options;

typedef struct tp_clipmap_stats {
    int uploads;              /* blocks uploaded this frame */
    size_t upload_bytes;
    double upload_ms;         /* glTexSubImage3D calls this frame */
    int missing;              /* window blocks still not resident after this frame's uploads */
    int pending;              /* blocks the loader has yet to read */
    int first_level;          /* finest level kept (Blow) */
    int valid_levels;         /* levels with a valid region */
    size_t gpu_bytes;         /* the texture array */
    size_t cache_bytes;       /* blocks in RAM */
    size_t loads, evictions;  /* in total */
} tp_clipmap_stats;

/* Creates the texture array (a current GL context is needed) and loads the coarsest levels
 * that a window holds whole, synchronously, so that the first frame has imagery everywhere.
 * gt: the geotransform of level 0's texels (tp_imagery_info.geotransform). NULL with a message
 * in err on failure (the GPU's array layers or memory, a read of those first blocks). */
tp_clipmap* tp_clipmap_create(const tp_block_source* src, const double gt[6],
                              const tp_clipmap_options* o, tp_error* err);
void tp_clipmap_destroy(tp_clipmap* m); /* accepts NULL */

/* Once per frame before drawing: moves the windows for cam, uploads what is ready (within the
 * cap), queues what is missing and the prefetch, collects garbage. finest_level: the finest
 * level any drawn patch needs (tp_clipmap_finest_level), 0 for all. */
void tp_clipmap_update(tp_clipmap* m, const tp_camera* cam, int finest_level,
                       tp_clipmap_stats* st);

/* Headless frames: updates without the cap until every window is resident (or timeout_s). */
void tp_clipmap_settle(tp_clipmap* m, const tp_camera* cam, int finest_level, double timeout_s,
                       tp_clipmap_stats* st);

/* What the renderer samples this frame (tp_renderer_set_clip). */
void tp_clipmap_render_clip(const tp_clipmap* m, tp_render_clip* out);

/* The finest level drawn patches need (Blow): the level of each patch at its distance,
 * the finest over all. distances_m: eye to the nearest point of each drawn patch. The result
 * keeps the frame coherence of tp_patch_texture_level (previous: last frame's result). */
int tp_clipmap_finest_level(const tp_clipmap* m, const tp_camera* cam, const double* distances_m,
                            size_t count, int previous);

/* The first block read failure not reported yet, or NULL. */
const char* tp_clipmap_take_failure(tp_clipmap* m);

#endif /* TP_APP_VIEW_CLIPMAP_H */
