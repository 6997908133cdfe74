/*
 * void_fill.hpp - filling the interior voids of a render grid (or of a window of its rows), by
 * interpolation or from a second source shifted onto the surrounding ground (the delta-surface
 * fill). Shared by tp_render_grid_build (the grid in memory) and the mosaic read in bands, so
 * that both fill every void the same way. Private to io/. The rules are in tp_io.h ("Voids").
 */
#pragma once

#include "gdal_util.hpp"
#include "tp_io.h"

#include <climits>
#include <cstdint>
#include <string>
#include <vector>

namespace tpio {

/* What to fill and from what. */
struct FillSpec {
    int fill_max = INT_MAX;        /* largest bounding box side filled (samples); <= 0: nothing */
    int max_rows = INT_MAX;        /* a region whose crop (fill_crop_rows) is taller stays a void
                                      (the band reader's memory cap) */
    const float* other = nullptr;  /* the second source on the same samples (NaN: none), or NULL */
    int rows_y0 = 0, rows_y1 = INT_MAX; /* only regions reaching rows rows_y0 .. rows_y1-1 are
                                           filled or counted (a band reader's rows) */
};

/* Nodata samples by what became of them (fill_voids). */
struct VoidCounts {
    size_t outside = 0;    /* in regions touching the grid's border */
    size_t large = 0;      /* in interior regions larger than fill_max (or max_rows) */
    size_t filled = 0;     /* filled (both kinds) */
    size_t from_other = 0; /* of those, from FillSpec::other (the rest interpolated) */
};

/* A region's search distance for GDALFillNodata: its bounding box's longer side + 1, so that
 * every sample of it can reach the ground on each side of it. */
inline int fill_reach(int box_w, int box_h) { return (box_w > box_h ? box_w : box_h) + 1; }

/* Rows of the crop a region of box_h rows is filled in (its rows and the reach above and
 * below). */
inline long long fill_crop_rows(int box_w, int box_h)
{
    return (long long)box_h + 2LL * fill_reach(box_w, box_h);
}

/* Fills the voids of z (w x h, row-major, NaN = nodata; geotransform gt). Connected
 * (4-neighbour) NaN regions that touch no border, whose bounding box is at most
 * spec.fill_max samples wide and high and whose crop is at most spec.max_rows tall are filled,
 * each on its own crop (its bounding box grown by fill_reach on every side, clipped to the
 * grid): with spec.other, other + delta where delta = z - other on the valid samples around it is
 * interpolated across the void by GDALFillNodata (search distance fill_reach, no smoothing),
 * else (and where other has no data) z itself is interpolated the same way. The rest stay NaN.
 * z may be a window of rows of a larger grid: its left and right columns are the grid's, its
 * first row is the grid's border iff top_is_border, its last iff bottom_is_border; a region
 * touching a window edge that is not the grid's reaches beyond the window and is neither filled
 * nor counted. The caller makes the window hold whole every region it means to have filled,
 * with its crop. filled: one byte per sample, 1 where filled; counts are added to.
 * TP_ERR_BACKEND when GDAL fails. */
tp_status fill_voids(float* z, int w, int h, const double gt[6], const FillSpec& spec,
                     bool top_is_border, bool bottom_is_border, std::vector<uint8_t>& filled,
                     VoidCounts* counts, tp_error* err);

/* The second source of --fill-from warped onto a render grid (w x h, geotransform gt, CRS
 * crs_wkt, "" for none: then path's own coordinates are taken as the grid's) with GDALWarp,
 * bilinear, nodata NaN, Float32, as a dataset of format "MEM" or "VRT" (vrt_name: the /vsimem/
 * name for a VRT). An Int16 source without a nodata tag has -32768 and -32767 taken as nodata
 * (int16_voids.hpp): for a VRT through a second one, named fill_source_int16_name(vrt_name), that
 * the caller unlinks with vrt_name. Its heights are as stored: *unit is their unit as a DEM's is
 * found (z_unit_of: band 1's unit type, else its vertical CRS's; --z-unit is the DEM's, not
 * this file's), the caller multiplies what it reads by unit->to_m; unit->warning, when not
 * empty, is the line to say for a unit terrapatch does not know ("--fill-from PATH: band 1's
 * unit 'X' is not one terrapatch knows ...: heights taken as metres"). Errors name the file:
 * TP_ERR_IO (missing, not a regular file), TP_ERR_BAD_DATA (not a raster GDAL opens, no
 * georeference, no overlap with the grid), TP_ERR_BACKEND. */
tp_status fill_source_open(const char* path, const double gt[6], int w, int h,
                           const std::string& crs_wkt, const char* format,
                           const std::string& vrt_name, Dataset* out, ZUnit* unit, tp_error* err);

/* Heights read from a fill source (n of them, NaN: none) in metres: times unit.to_m. */
void fill_source_to_metres(float* z, size_t n, const ZUnit& unit);

/* What the notes and info say of a fill source's unit: "" for metres or an unknown unit, else
 * "heights in international foot (band unit 'ft'), converted to metres". */
std::string fill_source_unit_note(const ZUnit& unit);

/* The name of fill_source_open's second VRT for vrt_name. */
std::string fill_source_int16_name(const std::string& vrt_name);

} // namespace tpio
