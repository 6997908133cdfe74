/*
 * tp_io/render_grid.h - a DEM on a metric grid: the warp to a UTM/UPS zone and the void filling.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_RENDER_GRID_H
#define TP_IO_RENDER_GRID_H

#include "tp_core.h"
#include "tp_io/dem.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * The render grid: a DEM on a metric grid (io/src/render_grid.cpp)
 *
 * Projected DEMs in metres are used on their own grid. Geographic DEMs (and projected ones in
 * other units) are warped with GDAL to the WGS84 UTM zone of the DEM's centre (UPS north of 84N
 * or south of 80S): one zone for the whole scene, bilinear (or cubic) resampling, square posts
 * at the finest source spacing found at the extent's corners and centre (so the source is
 * never undersampled), source nodata passed as NaN. A DEM without a CRS (and no options->crs)
 * whose geotransform is plainly geographic (north-up, cells under 0.1, every edge within +-180
 * / +-90: an ASCII grid in degrees without its .prj) is taken as EPSG:4326; any other as
 * metres. Both with a warning.
 *
 * Voids. Nodata is classified on the render grid into connected regions (4-neighbour): a
 * region that touches the grid's border (its first or last row or column) is outside the data (a
 * collar, a warp's wedges) and is never filled; a region that does not is an interior void,
 * filled whatever its size unless fill_max_px caps it (bounding box at most fill_max_px samples
 * wide and high), and marked as filled. Each void is filled on its own crop, its bounding box
 * grown on every side by its reach (the box's longer side + 1): by GDALFillNodata
 * (inverse-distance interpolation from the valid samples around it, search distance the reach, no
 * smoothing), or, with fill_from, from that second source (any GDAL raster, any CRS and
 * resolution, warped bilinearly onto the render grid) shifted onto the surrounding ground: delta
 * = DEM - OTHER on the valid samples around the void is interpolated across it as above, and
 * the void gets OTHER + delta (no step at its rim); where OTHER has no data the void's samples
 * are interpolated. Outside voids and capped ones stay NaN: never drawn, never fabricated.
 */
typedef enum tp_resampling {
    TP_RESAMPLING_DEFAULT = 0, /* = bilinear */
    TP_RESAMPLING_BILINEAR,
    TP_RESAMPLING_CUBIC
} tp_resampling;

typedef struct tp_grid_options {
    const char* crs;        /* overrides the DEM's CRS ("EPSG:4326", WKT, ...); NULL: the file's */
    tp_resampling resampling;
    int fill_max_px;        /* 0: any size; > 0: voids up to N x N samples; negative: none */
    /* Fill voids from this raster (--fill-from), shifted onto the DEM (above); NULL or "":
     * interpolate. Errors name the file: TP_ERR_IO (missing), TP_ERR_BAD_DATA (not a raster,
     * no georeference or CRS, no overlap with the DEM or no data over it). */
    const char* fill_from;
} tp_grid_options;

typedef struct tp_render_grid {
    int width, height;
    float* heights;          /* width * height; NaN = not drawn */
    uint8_t* filled;         /* width * height; 1 = interior void filled (see "Voids") */
    double geotransform[6];  /* render CRS */
    char* crs_wkt;           /* render CRS as WKT2; "" for local metres (no CRS). Owned */
    int epsg;                /* of the render CRS when known, else 0 */
    char crs_name[160];      /* "WGS 84 / UTM zone 31N", or "local metres (no CRS)" */
    int utm_zone;            /* 1..60 when the render CRS is a UTM zone, 0 for UPS, -1 otherwise */
    int northp;              /* hemisphere of utm_zone */
    int wgs84;               /* 1 if the render CRS's datum is WGS84 (GeographicLib applies exactly) */
    int warped;              /* 1 if resampled from the DEM's own CRS */
    double warp_max_error_m, warp_rms_error_m; /* warp: rendered surface vs the source posts */
    size_t warp_posts;       /* source posts the warp error was measured at */
    double spacing_m;        /* |geotransform[1]| when square, else the smaller spacing */
    size_t filled_samples;   /* interior voids filled */
    size_t large_void_samples, outside_samples; /* not drawn */
    char* warnings;          /* '\n'-separated lines for the user, "" when none. Owned */
    size_t filled_from_samples; /* of filled_samples, those from options->fill_from */
} tp_render_grid;

/* Builds the render grid of a DEM. A warped grid keeps only samples inside the hull of the
 * source posts (GDAL's output reaches half a post further, where it would only repeat the edge).
 * Errors: TP_ERR_INVALID_ARG for an unknown options->crs or geographic posts beyond +-90
 * degrees; TP_ERR_BAD_DATA for an unreadable dem->crs_wkt or a DEM one UTM/UPS zone cannot
 * hold (see tp_render_grid_plan); TP_ERR_BACKEND when GDAL or PROJ
 * fails. *out is untouched on failure. */
tp_status tp_render_grid_build(const tp_dem* dem, const tp_grid_options* options,
                               tp_render_grid** out, tp_error* err);
void tp_render_grid_destroy(tp_render_grid* grid); /* accepts NULL */

/* The width and height tp_render_grid_build would give dem with these options, without warping
 * (cheap: the warp is planned from the DEM's edges), for checking memory before building. Fails
 * as tp_render_grid_build does for a DEM no zone can hold (below).
 *
 * Warps are bounded by the source: a geographic DEM whose posts the zone of its centre would
 * scale by more than 5% (UTM keeps within 0.1%: a DEM many zones wide, or one reaching from a
 * pole far into UTM latitudes) is TP_ERR_BAD_DATA, with a message naming the extent and a CRS to
 * reproject to first; and a warp whose finest post spacing would give more than 4x the source's
 * samples (posts converging near a pole, very anisotropic cells) uses posts as many as the
 * source's over the warped extent instead, with a warning saying so. */
tp_status tp_render_grid_plan(const tp_dem* dem, const tp_grid_options* options, int* width,
                              int* height, tp_error* err);

/* A tp_terrain_desc pointing into grid (valid while grid lives); grid NULL as for
 * tp_dem_terrain_desc. */
tp_terrain_desc tp_render_grid_terrain_desc(const tp_render_grid* grid, int patch_size,
                                            tp_fit fit);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_RENDER_GRID_H */
