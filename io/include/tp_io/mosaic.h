/*
 * tp_io/mosaic.h - any number of sources as one render grid, read in bands of rows.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_MOSAIC_H
#define TP_IO_MOSAIC_H

#include "tp_core.h"
#include "tp_io/render_grid.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Mosaics read in bands (io/src/mosaic.cpp): any number of sources as one render grid, for
 * grids larger than memory (terrapatch build)
 *
 * Sources GDAL opens (tiles of any format mix, a .vrt) become one terrain through GDAL's VRT
 * machinery: sources that share CRS and post spacing are mosaicked with GDALBuildVRT; sources
 * of different CRSs or spacings are each warped (GDALWarp to a VRT) onto one grid and those are
 * mosaicked. Where sources overlap, the later one wins (as GDAL's VRT does); gaps are nodata.
 * The render grid is chosen as tp_render_grid_build chooses it for one DEM (the UTM/UPS zone of
 * the centre for geographic sources, the sources' own projected CRS in metres, options->crs
 * overriding the sources' CRS; the finest post spacing among the sources; north-up, square
 * posts), and one DEM gives the same grid and, sample for sample, the same heights as
 * tp_dem_read + tp_render_grid_build with the same fill_max (voids filled in windows of rows:
 * see tp_mosaic_options.fill_max).
 * Nothing is read whole: tp_mosaic_read_rows reads a window of rows through GDAL's block cache
 * (sized from options->memory_mb), so memory follows the window, not the grid.
 */
typedef struct tp_mosaic tp_mosaic;

typedef struct tp_mosaic_options {
    const char* crs;          /* as tp_grid_options.crs: overrides every source's CRS */
    tp_resampling resampling; /* for warps */
    int memory_mb;            /* budget of the whole process; GDAL's block cache gets a quarter.
                                 0 means 1024 */
    /* Voids filled as tp_render_grid_build fills them (the same regions, crops and
     * GDALFillNodata, so the same heights), read in bands: largest void side filled, in
     * samples; TP_FILL_MAX_ANY: any size; 0 (or less) fills nothing (unlike tp_grid_options,
     * 0 is not "any"). The window of rows read grows until it holds whole, with its crop, every
     * void reaching the rows asked for; a void whose crop (its rows and its reach, the bounding
     * box's longer side + 1, above and below) is taller than fill_window_mb holds at about 60
     * bytes a sample of a row stays a void (tp_mosaic_get_voids counts it). The per-sample
     * "filled" marks come with tp_mosaic_read_rows_filled. */
    int fill_max;
    const char* fill_from;    /* as tp_grid_options.fill_from (warped VRT, read in bands) */
    const char* z_unit;       /* the sources' height unit ("m", "ft", "us-ft"), overriding
                                 theirs; NULL: each source's (as tp_dem_read_z), which must
                                 agree. Heights are read in metres */
    int fill_window_mb;       /* memory for the void window; 0: memory_mb / 8, taken from GDAL's
                                 block cache (which then gets an eighth, not a quarter) */
    /* A bound of the grid's heights (metres) the caller knows: tp_mosaic_info.has_range with
     * it, and neither statistics nor the files a VRT repeats are read for one (a build in parts
     * gives every part the same: docs/distribution.md). 0: found as has_range says. */
    int range_given;
    double range_min_m, range_max_m;
    int coarsen;              /* > 1: a coarse grid for a preview: the render grid's posts this
                                 many times farther apart (the same extent and CRS), every
                                 source resampled onto it by the warp (its filter widened to the
                                 spacing, as GDALWarp does when it shrinks); 0 or 1: the grid */
} tp_mosaic_options;

#define TP_FILL_MAX_ANY 0x7fffffff /* tp_mosaic_options.fill_max: voids of any size */

typedef struct tp_mosaic_info {
    int width, height;          /* the render grid */
    double geotransform[6];     /* render CRS */
    const char* crs_wkt;        /* render CRS as WKT2; "" for local metres. Owned by the mosaic */
    char crs_name[160];
    int epsg;                   /* of the render CRS when known, else 0 */
    double spacing_m;           /* post spacing of the render grid */
    int source_count;
    int warped;                 /* 1 if any source is resampled onto the grid */
    int integer_sources;        /* 1 if every source's band 1 has an integer type */
    /* The share of the grid's extent that some source covers: the union of the sources'
     * footprints on a 1024 x 1024 raster over the extent (overlaps count once), 0 .. 1; 1 for
     * one source. The rest is gaps, nodata (terrapatch build refuses under a half without
     * --allow-gaps). */
    double covered_share;
    /* A bound of the grid's heights known without reading the grid: statistics every source
     * carries (exact ones, as GDAL writes them; resampling bilinear only, cubic overshoots), or,
     * for a grid read without resampling from files holding at most half its samples (a VRT
     * repeating a few small files), those files' exact min/max (read at open). 1 and the range,
     * else 0. A VRT that scales its sources can exceed it: check what is read. */
    int has_range;
    double min_m, max_m;
    /* What was decided, one line each ('\n'-separated): the sources, warps, CRS and spacing
     * differences, overlaps ("A and B overlap by one row (SRTM tiles share their edge); GDAL's
     * VRT takes the later one"), gaps, nodata guesses. Owned by the mosaic. */
    const char* notes;
} tp_mosaic_info;

/* Opens the sources (paths[0 .. path_count-1], path_count >= 1) and plans the grid; reads no
 * heights. Each source is checked as tp_dem_read checks a DEM before reading it (a FIFO or
 * device refused before opening, georeference within its ranges, DTED checksums verified on
 * read, an ASCII grid's text) and the errors name the file: TP_ERR_IO (missing, not a regular
 * file), TP_ERR_BAD_DATA (not a raster, bad georeference; with several sources, one without a
 * geotransform), TP_ERR_INVALID_ARG (an unknown options->crs), TP_ERR_BACKEND (GDAL fails to
 * mosaic or warp). */
tp_status tp_mosaic_open(const char* const* paths, size_t path_count,
                         const tp_mosaic_options* options, tp_mosaic** out, tp_error* err);
void tp_mosaic_close(tp_mosaic* m); /* accepts NULL */
void tp_mosaic_get_info(const tp_mosaic* m, tp_mosaic_info* out);

/* Reads rows y0 .. y0+rows-1 (within the grid) of the render grid into heights (rows * width
 * floats, row-major; height_count >= that): metres, NaN where nothing is drawn (nodata, gaps,
 * outside the warped sources; untagged Int16 -32768/-32767 and +-Inf/+-FLT_MAX as tp_dem_read).
 * Not thread-safe for one mosaic. TP_ERR_BAD_DATA (naming the source when GDAL says which) when
 * a read fails part way, e.g. a truncated tile or a DTED checksum mismatch. */
tp_status tp_mosaic_read_rows(tp_mosaic* m, int y0, int rows, float* heights, size_t height_count,
                              tp_error* err);
/* Samples filled so far (options->fill_max) in the rows above the furthest row read: each row
 * counted once, so reading the grid down, once or more, counts each filled sample once. */
size_t tp_mosaic_filled_samples(const tp_mosaic* m);
/* tp_mosaic_read_rows that also writes, for each sample read, 1 where it is a filled void
 * sample (options->fill_max), else 0 (filled: rows * width bytes; NULL: as tp_mosaic_read_rows).
 * The same samples tp_render_grid_build's `filled` marks for one DEM. */
tp_status tp_mosaic_read_rows_filled(tp_mosaic* m, int y0, int rows, float* heights,
                                     size_t height_count, uint8_t* filled, tp_error* err);

/* What became of the voids in the rows read so far (each row counted once, as above). */
typedef struct tp_mosaic_voids {
    size_t filled_samples;      /* = tp_mosaic_filled_samples */
    size_t filled_from_samples; /* of those, from options->fill_from */
    size_t too_large_samples;   /* interior voids within fill_max left because their crop is
                                   taller than max_void_rows */
    int max_void_rows;          /* the tallest crop the window may hold; 0 when not filling */
} tp_mosaic_voids;
void tp_mosaic_get_voids(const tp_mosaic* m, tp_mosaic_voids* out); /* m NULL: all 0 */

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_MOSAIC_H */
