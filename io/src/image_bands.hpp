/* image_bands.hpp - which bands of a GDAL raster make an image's colour and alpha, shared by
 * the draped texture (texture.cpp) and the imagery pyramids (imagery_build.cpp). Private to io/. */
#pragma once

#include "gdal_util.hpp"

#include <string>
#include <vector>

namespace tpio {

/* The bands that make colour and alpha, 1-based: Red/Green/Blue by their colour interpretation
 * wherever they are, else the first three (a NAIP RGB + near-infrared image has a fourth band
 * that is not alpha), else one grey band; alpha only from a band GDAL calls alpha (0: none). */
struct Bands {
    int colour[3];
    int colour_count;
    int alpha;
};
Bands choose_bands(GDALDataset* ds);

/* gdal_translate of src with opts (GDAL's command-line options) into an in-memory dataset
 * (e.g. "-of VRT"); null when GDAL fails (the reason in gdal_message()). */
Dataset translate(GDALDataset* src, const std::vector<std::string>& opts);

/* A palette band (band 1 with a colour table) expanded through its table into red, green,
 * blue and alpha (a VRT over src, kept in *holder; src then points at it); other rasters are
 * left as they are. TP_ERR_BACKEND naming path when GDAL fails. */
tp_status expand_palette(const char* path, GDALDataset** src, Dataset* holder, tp_error* err);

} // namespace tpio
