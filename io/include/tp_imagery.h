/*
 * tp_imagery.h - imagery pyramids (.tpi): orthophotos and scanned maps of any size, warped onto
 * a store's render grid and cut into a mip pyramid of fixed-size blocks, for the viewer to
 * stream (issue 15; docs/imagery.md). C interface; io/src/imagery_*.cpp. A day's light map
 * (.tpl, `terrapatch light --day`) is the same file of another kind (TP_IMAGERY_KIND_LIGHT_TIMES
 * below), its level 0 made by the caller (tp_imagery_build_rows).
 *
 * Geometry. A pyramid belongs to one render grid (a store's fitted grid: its CRS, geotransform,
 * width and height; pixel-is-area: post (x, y) lies at the centre of grid pixel (x, y)). Level 0
 * has 2^texel_shift texels per grid pixel along each axis (texel_shift in -8..8; negative: one
 * texel spans several posts), so level-0 texel (u, v) covers the render-CRS rectangle
 *     E in [gt[0] + u * gt[1], gt[0] + (u + 1) * gt[1]),  N likewise with gt[3], gt[5]
 * of the pyramid's own geotransform gt (the grid's, with pixel sizes divided by 2^texel_shift),
 * and the level-0 image is width x height texels = the grid's width and height times
 * 2^texel_shift (rounded up for a negative shift). Level l + 1 halves level l (texel (u, v) of
 * level l + 1 is the mean of texels (2u .. 2u + 1, 2v .. 2v + 1) of level l, weighted by alpha;
 * its size is ceil(size_l / 2)); the last level fits in one block.
 *
 * Blocks. Each level is cut into blocks of block x block texels (256), block (bx, by) holding
 * texels (bx * block .. , by * block ..), RGBA8, top row first; alpha is 0 where no source
 * image covers the texel (and beyond the level's width and height in the last row and column
 * of blocks), 255 where one does (a source's own alpha in between).
 */
#ifndef TP_IMAGERY_H
#define TP_IMAGERY_H

#include "tp_core.h" /* tp_status, tp_error */

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define TP_IMAGERY_BLOCK 256        /* texels per block side */
#define TP_IMAGERY_MAX_LEVELS 32
#define TP_IMAGERY_SHIFT_MIN (-8)
#define TP_IMAGERY_SHIFT_MAX 8

typedef struct tp_imagery tp_imagery;

typedef struct tp_imagery_info {
    int block;                   /* TP_IMAGERY_BLOCK */
    int levels;                  /* 1 .. TP_IMAGERY_MAX_LEVELS */
    int texel_shift;             /* level-0 texels per grid pixel = 2^texel_shift */
    int64_t width, height;       /* level-0 texels */
    double geotransform[6];      /* of level 0, render CRS */
    int grid_width, grid_height; /* the render grid it was built for */
    double grid_geotransform[6];
    const char* crs_wkt;         /* render CRS (WKT; "" for local metres); owned by the pyramid */
    const char* notes;           /* sources and decisions, '\n'-separated; owned */
    uint64_t file_bytes;
    uint64_t nonempty_blocks;    /* blocks stored with data (the rest are wholly transparent) */
    int kind;                    /* TP_IMAGERY_KIND_* */
    /* TP_IMAGERY_KIND_LIGHT_TIMES: the day its texels' times span (Unix seconds) and the
       number of sun positions (maps) they were found from; 0 for imagery */
    double time_first_s, time_last_s;
    int maps;
} tp_imagery_info;

/* What a pyramid's texels are. */
#define TP_IMAGERY_KIND_IMAGE 0       /* RGBA colour, alpha coverage (all of the above) */
#define TP_IMAGERY_KIND_LIGHT_TIMES 1 /* a light map over a day (a .tpl): each texel the
                                         (r1, s1, r2, s2) lit intervals of tp_core.h's
                                         tp_light_times_build; a coarser level's texel the
                                         tp_light_times_mean of four (not alpha-weighted);
                                         texel_shift 0 (a texel per post) */

/* Opens a pyramid (.tpi or .tpl; format 2, and format 1, which is imagery without a day):
 * checks the magic, the header's and the block table's checksums, the geometry against the one
 * the header's sizes define, the kind and its day, and that every block lies inside the file.
 * TP_ERR_BAD_DATA (damaged, truncated, not a pyramid, a newer format, an unknown kind, imagery
 * with a day, a light map whose day does not run forward, of fewer than 2 maps or at a texel
 * shift other than 0) / TP_ERR_IO with a message naming path; *out written only on success. */
tp_status tp_imagery_open(const char* path, tp_imagery** out, tp_error* err);
void tp_imagery_close(tp_imagery* im); /* accepts NULL */
void tp_imagery_get_info(const tp_imagery* im, tp_imagery_info* out);

/* Level l's size in texels and in blocks (0 for a level out of range). */
void tp_imagery_level_size(const tp_imagery* im, int level, int64_t* width, int64_t* height,
                           int* block_cols, int* block_rows);

/* 1 when block (level, bx, by) holds no texel with alpha > 0 (cheap: from the table; also for
 * a block out of range), so a reader need not load it. */
int tp_imagery_block_is_empty(const tp_imagery* im, int level, int bx, int by);

/* Reads, checks (CRC32) and decodes block (level, bx, by) into rgba (block * block * 4 bytes,
 * top row first); an empty block or one out of range is all zero. Thread-safe: any number of
 * threads may read one open pyramid at once (pread). TP_ERR_BAD_DATA for a block that fails its
 * checksum or does not decode (the message names the file, level, block and byte offset). */
tp_status tp_imagery_read_block(const tp_imagery* im, int level, int bx, int by, uint8_t* rgba,
                                tp_error* err);

/* The render grid a pyramid is built for (a store's fitted grid). */
typedef struct tp_imagery_target {
    const char* crs_wkt;     /* "" for local metres */
    double geotransform[6];
    int width, height;
} tp_imagery_target;

typedef struct tp_imagery_build_options {
    int texel_shift;         /* -8..8, or TP_IMAGERY_SHIFT_AUTO: from the finest source's
                                resolution on the render grid (the nearest power of two) */
    double memory_bytes;     /* budget (0: 1 GiB) */
    int threads;             /* 0: all cores */
    /* progress 0..1, may be NULL; called from the building thread */
    void (*progress)(void* user, double fraction);
    void* progress_user;
} tp_imagery_build_options;

#define TP_IMAGERY_SHIFT_AUTO (-1000)

/* Builds a pyramid at out_path (written whole or not at all, as every output) from count
 * georeferenced rasters (any GDAL format and CRS; RGB(A), grey or paletted as
 * tp_texture_build chooses bands; several are mosaicked, a later one winning where both have
 * alpha), warped by GDAL onto target. TP_ERR_IO for a source that cannot be opened, TP_ERR_BAD_DATA
 * for one without georeference or not overlapping the grid, TP_ERR_INVALID_ARG for a texel
 * shift out of range or a level-0 image over 2^31 texels a side, TP_ERR_OUT_OF_MEMORY when one
 * block row of every level (what the build holds) does not fit in options->memory_bytes. */
tp_status tp_imagery_build(const char* const* sources, int count, const tp_imagery_target* target,
                           const tp_imagery_build_options* options, const char* out_path,
                           tp_error* err);

/* A pyramid whose level 0 the caller makes (a light map: TP_IMAGERY_KIND_LIGHT_TIMES). */
typedef struct tp_imagery_rows {
    int kind;                       /* TP_IMAGERY_KIND_* */
    int texel_shift;                /* as tp_imagery_build_options (no AUTO) */
    double time_first_s, time_last_s; /* LIGHT_TIMES: the day (first < last) */
    int maps;                       /* LIGHT_TIMES: sun positions, >= 2 */
    const char* notes;              /* stored as the pyramid's notes; may be NULL */
    /* Fills level-0 texel rows row0 .. row0 + count - 1 (each width texels * 4 bytes, RGBA,
       rows one after another) in increasing row0 order, count <= block; TP_OK or a status with
       err set (the build then fails with it). Called from the building thread. */
    tp_status (*rows)(void* user, int64_t row0, int count, uint8_t* rgba, tp_error* err);
    void* user;
} tp_imagery_rows;

/* Builds a pyramid at out_path (whole or not at all) from rows on target's grid; the coarser
 * levels halve level 0 as kind says. Fails as tp_imagery_build (no sources), TP_ERR_INVALID_ARG
 * for a bad kind, shift or day (as tp_imagery_open would refuse them), or with what rows
 * returned (its message; nothing written). options (may be NULL): memory_bytes (what the build
 * holds: one block row of every level and one of level 0 for rows), threads (compressing),
 * progress (after each level-0 block row). */
tp_status tp_imagery_build_rows(const tp_imagery_target* target, const tp_imagery_rows* rows,
                                const tp_imagery_build_options* options, const char* out_path,
                                tp_error* err);

#ifdef __cplusplus
}
#endif

#endif /* TP_IMAGERY_H */
