/* image_bands.cpp - the colour and alpha bands of a GDAL raster (image_bands.hpp): what
 * tp_texture_build and tp_imagery_build take from an orthophoto or a scanned map. */
#include "image_bands.hpp"

#include <gdal_utils.h>

#include <algorithm>

namespace tpio {

Bands choose_bands(GDALDataset* ds)
{
    Bands b{{0, 0, 0}, 0, 0};
    int rgb[3] = {0, 0, 0}, n = ds->GetRasterCount();
    for (int i = n; i >= 1; i--) {
        switch (ds->GetRasterBand(i)->GetColorInterpretation()) {
        case GCI_RedBand: rgb[0] = i; break;
        case GCI_GreenBand: rgb[1] = i; break;
        case GCI_BlueBand: rgb[2] = i; break;
        case GCI_AlphaBand: b.alpha = i; break;
        default: break;
        }
    }
    std::vector<int> rest; /* the bands that are not alpha */
    for (int i = 1; i <= n; i++)
        if (i != b.alpha)
            rest.push_back(i);
    if (rest.empty()) { /* one band, called alpha: show it as grey */
        rest.push_back(b.alpha);
        b.alpha = 0;
    }
    if (rgb[0] && rgb[1] && rgb[2]) {
        std::copy(rgb, rgb + 3, b.colour);
        b.colour_count = 3;
    } else {
        b.colour_count = rest.size() >= 3 ? 3 : 1;
        std::copy(rest.begin(), rest.begin() + b.colour_count, b.colour);
    }
    return b;
}

Dataset translate(GDALDataset* src, const std::vector<std::string>& opts)
{
    std::vector<const char*> args;
    for (const std::string& o : opts)
        args.push_back(o.c_str());
    args.push_back(nullptr);
    GDALTranslateOptions* to = GDALTranslateOptionsNew(const_cast<char**>(args.data()), nullptr);
    int usage = 0;
    Dataset out(GDALDataset::FromHandle(GDALTranslate("", GDALDataset::ToHandle(src), to, &usage)));
    GDALTranslateOptionsFree(to);
    return out;
}

tp_status expand_palette(const char* path, GDALDataset** src, Dataset* holder, tp_error* err)
{
    GDALRasterBand* b1 = (*src)->GetRasterBand(1);
    if (!b1 || b1->GetColorInterpretation() != GCI_PaletteIndex || !b1->GetColorTable())
        return TP_OK;
    *holder = translate(*src, {"-of", "VRT", "-b", "1", "-expand", "rgba"});
    if (!*holder)
        return fail(err, TP_ERR_BACKEND, "%s: cannot expand the colour table: %s", path,
                    gdal_message().c_str());
    *src = holder->get();
    return TP_OK;
}

} // namespace tpio
