/*
 * store_build.h - a terrain store (.tpt, docs/store.md) built from DEM sources (store_build.c):
 * what `terrapatch build` runs once its options are read (commands/cmd_build.c), and what the
 * store cache runs for a DEM opened by another command (store_cache.c). One call, an options
 * struct in, a result struct out, as GDAL's utilities call GDALContourGenerateEx.
 *
 * Memory follows a band of rows, not the map (but for a grid that needs a range pass and fits a
 * quarter of the budget: build_rows.h holds it between the passes); the store is written
 * atomically (a temporary file renamed into place, removed on failure or SIGINT/SIGTERM).
 */
#ifndef TP_APP_STORE_BUILD_H
#define TP_APP_STORE_BUILD_H

#include "tp_io.h"

#include <stddef.h>
#include <stdint.h>

/* The smallest --memory accepted (MB): the program's fixed part alone is more than that. */
#define BUILD_MIN_MEMORY_MB 64

/* The least share of the mosaic the sources must cover without allow_gaps. */
#define TP_BUILD_MIN_COVERED 0.5

typedef struct tp_build_options {
    const char** sources; /* source_count DEMs (paths GDAL opens), later ones over earlier */
    int source_count;
    const char* out; /* NAME.tpt */
    int patch_size;  /* node size: 17, 33, 65 (default), 129 or 257 */
    const char* crs; /* the render grid's CRS (NULL: the sources' own or a UTM/UPS zone) */
    tp_resampling resampling;
    int memory_mb;         /* the whole process's budget (default 1024), fitted to what it may
                              use (tp_memory_fit_budget); at least BUILD_MIN_MEMORY_MB */
    int fill_max;          /* samples; 0 fills nothing; TP_FILL_MAX_ANY (the default) any size */
    const char* fill_from; /* fill voids from this raster, or NULL */
    const char* z_unit;    /* m, ft or us-ft; NULL: the sources' */
    int allow_gaps;        /* build even when the sources cover under TP_BUILD_MIN_COVERED */
    int height_range_given; /* the heights lie in height_range_m (metres): the step follows from
                              it, no range pass, nothing read for a bound; a height outside is
                              an error */
    double height_range_m[2];
    double height_step_m;  /* the quantisation step; 0 (the default): from the heights (1 m
                              where every height is whole, 1/16 m where resampled from whole
                              metres, else the finest power of two the range allows) */
    int part_index, part_count; /* > 0: part part_index (1 ..) of part_count of a build in
                              parts (build_part.h): the part's strip of the grid, its store
                              noting what merge needs; 0: the whole grid */
    int threads;           /* 0: every core */
    int quiet;             /* no notes or progress on stderr */
    /* > 0: a preview (the store cache's first picture of a large DEM): the render grid
     * coarsened (tp_mosaic_options.coarsen) by the smallest power of two that leaves at most
     * this many samples; nothing is written when the grid itself is no larger (the result's
     * coarsen is then 1). A preview store is a store like any other, of that coarser grid.
     * Its build says nothing of its own failures (the result's coarsen is then > 1: the store's
     * own build, which the caller runs next, reads the same sources) nor of voids left */
    double preview_max_samples;
} tp_build_options;

/* The defaults above (patch 65, memory 1024 MB, voids of any size filled); no sources. */
void tp_build_options_init(tp_build_options* o);

/* What a build made. */
typedef struct tp_build_result {
    int width, height; /* the render grid, samples */
    double samples;    /* width x height */
    size_t valid_samples;
    int patch_size;
    int64_t nodes;
    uint64_t bytes; /* the store's size */
    double step_m, quant_max_error_m;
    double min_m, max_m;
    char crs_name[160];
    int warped;
    int threads, memory_mb; /* as used */
    size_t filled_samples, filled_from_samples, void_samples_too_large;
    double seconds, rss_peak_mb;
    int coarsen; /* a preview's coarsening (1: none, nothing written) */
} tp_build_result;

/* Builds o->out from o->sources; notes and progress on stderr unless o->quiet, then a line of
 * figures. Returns an exit code (base/cli.h) after one line on stderr naming the file and what
 * was wrong (TP_EXIT_FAILURE), 128 + the signal after SIGINT/SIGTERM; *result (may be NULL) is
 * set on TP_EXIT_OK. */
int tp_store_build(const tp_build_options* o, tp_build_result* result);

#endif /* TP_APP_STORE_BUILD_H */
