/*
 * mosaic.hpp - the state of a tp_mosaic (tp_io.h), shared by its opening (mosaic.cpp: the
 * sources, the VRT or warp, the grid) and its reading (mosaic_read.cpp: windows of rows, voids
 * filled).
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

#endif /* TP_IO_MOSAIC_HPP */
