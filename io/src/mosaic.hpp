/*
 * mosaic.hpp - the state of a tp_mosaic (tp_io/mosaic.h), shared by its opening (mosaic.cpp: the
 * VRT or warp, the grid; mosaic_source.cpp: the sources) and its reading (mosaic_read.cpp:
 * windows of rows, voids filled).
 */
#ifndef TP_IO_MOSAIC_HPP
#define TP_IO_MOSAIC_HPP

#include "gdal_util.hpp"
#include "tp_io.h"

#include <ogr_spatialref.h>

#include <climits>
#include <memory>
#include <string>
#include <vector>

struct tp_mosaic {
    std::vector<std::string> vsimem; /* files to unlink on close */
    tpio::Dataset ds;                /* what is read: a source, a mosaic VRT or a warped VRT */
    int w = 0, h = 0;
    double gt[6] = {0, 1, 0, 0, 0, -1};
    std::string crs_wkt, notes;
    char crs_name[160] = "";
    int epsg = 0;
    double spacing_m = 0;
    int source_count = 0;
    bool warped = false, integer = true;
    double covered_share = 1.0; /* tp_mosaic_info.covered_share */
    double z_to_m = 1.0;        /* metres per unit of the sources' heights */
    bool has_range = false;
    double min_m = 0, max_m = 0;
    /* nodata of what is read */
    bool has_nodata = false;
    float nodata = 0;
    bool int16_guess = false; /* what is read is an untagged Int16 source: -32767 too */
    bool int16_voids = false; /* some source is an untagged Int16 one (-32768, -32767 voids) */
    /* warp of one geographic mosaic: the rim outside its posts' hull is not drawn */
    std::unique_ptr<OGRCoordinateTransformation> back;
    bool back_geographic = false;
    double sgt[6] = {0, 1, 0, 0, 0, -1};
    int sw = 0, sh = 0;
    std::string last_source_error;
    /* void filling (fill_max > 0): a window of rows win_y0 .. win_y0+win_rows-1 as read
     * (converted and masked, not filled), and of the --fill-from source (other) when there is
     * one, kept between reads; filled samples counted in rows below counted_to. A void whose
     * crop is taller than fill_max_rows stays (too_large counts its samples). */
    int fill_max = 0;
    int fill_max_rows = INT_MAX;
    tpio::Dataset other;
    tpio::ZUnit other_unit; /* of other's heights: what is read is multiplied by its to_m */
    std::vector<float> win, win_other;
    int win_y0 = 0, win_rows = 0;
    /* rows read, as read_raw left them (and of other), kept in a ring of rc_cap rows (row y in
     * slot y % rc_cap, rc_row[slot] = y or -1): a window that shrinks to the next band and
     * grows again over a void's crop takes them from here instead of GDAL (the warp and the
     * hull's transforms again). The same values as a read. */
    std::vector<float> rc, rc_other;
    std::vector<int> rc_row;
    int rc_cap = 0;
    int counted_to = 0;
    size_t filled = 0, from_other = 0, too_large = 0;
    std::vector<uint8_t> filled_mask;

    ~tp_mosaic()
    {
        back.reset();
        other.reset();
        ds.reset();
        for (auto it = vsimem.rbegin(); it != vsimem.rend(); ++it)
            VSIUnlink(it->c_str());
    }
};

namespace tpio {
namespace mosaic {

/* One source of a mosaic, opened and checked (mosaic_source.cpp). */
struct Source {
    std::string path, name; /* name: the file name without folders, for notes */
    int w = 0, h = 0;
    double gt[6] = {0, 1, 0, 0, 0, -1};
    bool has_gt = false;
    OGRSpatialReference srs;
    bool has_crs = false;
    GDALDataType type = GDT_Unknown;
    bool has_nodata = false;
    double nodata = 0;
    std::string driver;
    bool has_stats = false;
    double stat_min = 0, stat_max = 0;
    tpio::ZUnit z; /* its heights' unit */
    /* Int16 without a nodata tag: -32768 (SRTM) and -32767 (DTED) are voids, as tp_dem_read
     * takes them */
    bool int16_voids() const { return type == GDT_Int16 && !has_nodata; }
};

struct Rect {
    double x0, y0, x1, y1;
}; /* [x0, x1) x [y0, y1) */

inline void add_note(std::string& notes, const std::string& line)
{
    if (!notes.empty())
        notes += '\n';
    notes += line;
}

inline std::string base_name(const std::string& p)
{
    size_t at = p.find_last_of('/');
    return at == std::string::npos ? p : p.substr(at + 1);
}

/* Opens path and checks it as tp_dem_read checks a DEM before reading it (a FIFO or device
 * refused before opening, its georeference within its ranges, an ASCII grid's text), into s:
 * its size, georeference, CRS, band type, nodata, statistics and height unit (z_unit
 * overriding the file's). Errors name the file. */
tp_status open_source(const char* path, const char* z_unit, Source* s, tp_error* err);

/* The share of the whole rectangle that the union of the rectangles r covers, in [0, 1]: cells
 * of a 1024 x 1024 raster over whole, each counted once when its centre lies in some rectangle
 * (so three footprints over one place count it once; good to about a cell along each edge). */
double covered_share(const std::vector<Rect>& r, const Rect& whole);

/* Overlaps and gaps of sources sharing one grid (same CRS and spacing): notes, and the share
 * of the mosaic they cover. */
double note_overlaps(const std::vector<Source>& src, const double mgt[6], int mw, int mh,
                     std::string& notes);

/* A grid read without resampling from raster files that hold at most half its samples (a VRT
 * that repeats a few small files, as tools/make_mirror_dem.py's): the exact minimum and maximum
 * of every band of those files (GDAL skips each file's nodata) bound its heights, for a fraction
 * of a read of the grid. Not when a bound touches the grid's nodata value (a file without the
 * tag whose voids the VRT masks) or GDAL cannot say. A VRT that scales its sources breaks the
 * bound: the caller checks it against what it reads (terrapatch build does). */
void range_of_files(tp_mosaic* m);

} // namespace mosaic
} // namespace tpio

#endif /* TP_IO_MOSAIC_HPP */
