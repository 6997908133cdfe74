/*
 * texture.cpp - tp_texture_build: an orthophoto or colour image on the render grid.
 *
 * Georeferenced images go through GDALWarp onto the render grid's CRS and pixel extent (so a
 * geographic image follows the same UTM warp as its DEM); others through OpenImageIO, resized
 * by OpenImageIO's ImageBufAlgo when larger than max_size.
 */
#include "crs.hpp"
#include "gdal_util.hpp"
#include "image_bands.hpp"
#include "tp_io.h"

#include <OpenImageIO/imagebuf.h>
#include <OpenImageIO/imagebufalgo.h>
#include <gdal_utils.h>

#include <algorithm>
#include <cerrno>
#include <cpl_vsi.h>
#include <cmath>
#include <exception>
#include <vector>

namespace {

using tpio::fail;
namespace OIIO = OIIO_NAMESPACE;

/* Texture size: the grid's, times up to 4 for imagery finer than the DEM, within max_size. */
void texture_size(const tp_render_grid* g, int img_w, int img_h, int max_size, int* w, int* h)
{
    double f = std::min(4.0, std::max(1.0, std::max((double)img_w / g->width, (double)img_h / g->height)));
    double tw = g->width * f, th = g->height * f;
    double s = std::min(1.0, max_size / std::max(tw, th));
    *w = std::max(1, (int)std::lround(tw * s));
    *h = std::max(1, (int)std::lround(th * s));
}

tp_texture* alloc_texture(int w, int h)
{
    auto* t = static_cast<tp_texture*>(std::calloc(1, sizeof(tp_texture)));
    if (!t)
        return nullptr;
    t->width = w;
    t->height = h;
    t->rgba = static_cast<uint8_t*>(std::calloc((size_t)w * h, 4));
    if (!t->rgba) {
        std::free(t);
        return nullptr;
    }
    return t;
}

using tpio::Bands;
using tpio::choose_bands;
using tpio::translate;

tp_status warp_georeferenced(const char* path, GDALDataset* src, const tp_render_grid* g,
                             int max_size, tp_texture** out, tp_error* err)
{
    int w, h;
    texture_size(g, src->GetRasterXSize(), src->GetRasterYSize(), max_size, &w, &h);
    const double* gt = g->geotransform;
    double x0 = gt[0], x1 = gt[0] + g->width * gt[1];
    double y0 = gt[3] + g->height * gt[5], y1 = gt[3];
    std::string te[4] = {CPLSPrintf("%.17g", std::min(x0, x1)), CPLSPrintf("%.17g", std::min(y0, y1)),
                         CPLSPrintf("%.17g", std::max(x0, x1)), CPLSPrintf("%.17g", std::max(y0, y1))};
    std::string ts[2] = {std::to_string(w), std::to_string(h)};
    /* A palette band becomes red, green, blue and alpha through its colour table. */
    tpio::Dataset expanded;
    if (tp_status s = tpio::expand_palette(path, &src, &expanded, err))
        return s;
    /* Only the chosen bands go to the warp, alpha last (GDALWarp takes a last alpha band as
     * the source's alpha); -dstalpha makes texels outside the image transparent. */
    Bands b = choose_bands(src);
    std::vector<std::string> pick = {"-of", "VRT"};
    for (int c = 0; c < b.colour_count; c++)
        pick.insert(pick.end(), {"-b", std::to_string(b.colour[c])});
    if (b.alpha)
        pick.insert(pick.end(), {"-b", std::to_string(b.alpha)});
    tpio::Dataset picked = translate(src, pick);
    if (!picked)
        return fail(err, TP_ERR_BACKEND, "%s: cannot select the colour bands: %s", path,
                    tpio::gdal_message().c_str());
    const char* args[] = {"-t_srs", g->crs_wkt, "-te", te[0].c_str(), te[1].c_str(),
                          te[2].c_str(), te[3].c_str(), "-ts", ts[0].c_str(), ts[1].c_str(),
                          "-r", "bilinear", "-of", "MEM", "-ot", "Byte",
                          b.alpha ? nullptr : "-dstalpha", nullptr};
    GDALWarpAppOptions* wo = GDALWarpAppOptionsNew(const_cast<char**>(args), nullptr);
    GDALDatasetH in = GDALDataset::ToHandle(picked.get());
    int usage = 0;
    tpio::Dataset warped(GDALDataset::FromHandle(GDALWarp("", nullptr, 1, &in, wo, &usage)));
    GDALWarpAppOptionsFree(wo);
    if (!warped)
        return fail(err, TP_ERR_BACKEND, "%s: cannot warp onto the render grid: %s", path,
                    tpio::gdal_message().c_str());
    tp_texture* t = alloc_texture(w, h);
    if (!t)
        return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    /* warped: the colour bands (grey repeated), then alpha */
    int grey = b.colour_count == 1;
    int map[4] = {1, grey ? 1 : 2, grey ? 1 : 3, b.colour_count + 1};
    for (int c = 0; c < 4; c++) {
        CPLErr e = warped->GetRasterBand(map[c])->RasterIO(GF_Read, 0, 0, w, h, t->rgba + c, w, h,
                                                           GDT_Byte, 4, (GSpacing)w * 4, nullptr);
        if (e != CE_None) {
            tp_texture_destroy(t);
            return fail(err, TP_ERR_BACKEND, "%s: %s", path, tpio::gdal_message().c_str());
        }
    }
    /* an image that covers none of the DEM (another place, a wrong CRS): refused as
     * `terrapatch imagery` refuses it, not drawn as a bare grey DEM */
    bool any = false;
    for (size_t i = 3; i < (size_t)w * h * 4 && !any; i += 4)
        any = t->rgba[i] != 0;
    if (!any) {
        tp_texture_destroy(t);
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: does not overlap the DEM: none of it falls on the render grid (check "
                    "that both are of the same place, and the image's CRS)",
                    path);
    }
    t->georeferenced = 1;
    *out = t;
    return TP_OK;
}

tp_status read_plain(const char* path, const tp_render_grid* g, int max_size, tp_texture** out,
                     tp_error* err)
{
    if (tp_status s = tpio::check_png(path, err))
        return s;
    OIIO::ImageBuf src(path);
    {
        tpio::QuietStderr quiet;
        const OIIO::ImageSpec& spec = src.spec(); /* the header only */
        if (src.has_error())
            return fail(err, TP_ERR_IO, "%s: cannot read as an image: %s", path,
                        src.geterror().c_str());
        /* the decoder's copy of the pixels and our 8-bit one */
        if (tp_status s = tpio::check_fits_in_memory(
                path, spec.width, spec.height,
                (double)spec.nchannels * (spec.format.size() + 1), "for the pixels", err))
            return s;
    }
    {
        tpio::QuietStderr quiet; /* libpng's own "libpng error: ..." line; its text is in ours */
        if (!src.read(0, 0, true, OIIO::TypeDesc::UINT8))
            return fail(err, TP_ERR_IO, "%s: cannot read as an image: %s", path,
                        src.geterror().c_str());
    }
    int w, h;
    texture_size(g, src.spec().width, src.spec().height, max_size, &w, &h);
    OIIO::ImageBuf sized = OIIO::ImageBufAlgo::resize(src, "", 0, OIIO::ROI(0, w, 0, h, 0, 1, 0, src.nchannels()));
    if (sized.has_error())
        return fail(err, TP_ERR_BACKEND, "%s: %s", path, sized.geterror().c_str());
    tp_texture* t = alloc_texture(w, h);
    if (!t)
        return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    int ch = sized.nchannels(), alpha = src.spec().alpha_channel; /* -1: none */
    std::vector<uint8_t> px((size_t)w * h * ch);
    sized.get_pixels(OIIO::ROI(0, w, 0, h, 0, 1, 0, ch), OIIO::TypeDesc::UINT8, px.data());
    for (size_t i = 0; i < (size_t)w * h; i++) {
        const uint8_t* s = &px[i * ch];
        t->rgba[4 * i + 0] = s[0];
        t->rgba[4 * i + 1] = ch >= 3 ? s[1] : s[0];
        t->rgba[4 * i + 2] = ch >= 3 ? s[2] : s[0];
        t->rgba[4 * i + 3] = alpha >= 0 && alpha < ch ? s[alpha] : 255;
    }
    *out = t;
    return TP_OK;
}

tp_status build(const char* path, const tp_render_grid* g, int max_size, tp_texture** out,
                tp_error* err)
{
    VSIStatBufL st;
    if (VSIStatL(path, &st) != 0)
        return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, std::strerror(ENOENT));
    /* a FIFO would block GDAL's or OpenImageIO's open */
    if (tp_status s = tpio::check_input_file(path, "an image", false, err))
        return s;
    if (!tp_is_heightmap_image(path)) {
        tpio::register_drivers();
        tpio::QuietGdal quiet;
        tpio::Dataset ds(GDALDataset::FromHandle(GDALOpenEx(path, GDAL_OF_RASTER, nullptr, nullptr, nullptr)));
        if (!ds)
            return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, tpio::gdal_message().c_str());
        if (ds->GetRasterCount() < 1) /* e.g. a container of subdatasets */
            return fail(err, TP_ERR_BAD_DATA, "%s: has no raster bands to drape", path);
        double gt[6];
        const OGRSpatialReference* srs = ds->GetSpatialRef();
        if (ds->GetGeoTransform(gt) == CE_None && tpio::crs_present(srs) && g->crs_wkt[0])
            return warp_georeferenced(path, ds.get(), g, max_size, out, err);
    }
    return read_plain(path, g, max_size, out, err);
}

} // namespace

extern "C" tp_status tp_texture_build(const char* path, const tp_render_grid* grid, int max_size,
                                      tp_texture** out, tp_error* err)
{
    if (!path || !grid || !out || max_size < 1)
        return fail(err, TP_ERR_INVALID_ARG, "texture: bad arguments");
    try {
        return build(path, grid, max_size, out, err);
    } catch (...) {
        return tpio::caught(err, path);
    }
}

/* Only free(): nothing can throw. */
extern "C" void tp_texture_destroy(tp_texture* tex)
{
    if (!tex)
        return;
    std::free(tex->rgba);
    std::free(tex);
}
