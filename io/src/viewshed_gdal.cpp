/* viewshed_gdal.cpp - GDAL's viewshed of an in-memory grid (for comparing with the core's
 * tp_viewshed_compute) and a viewshed written as a raster (see tp_io.h, "Viewsheds through
 * GDAL"). */
#include "gdal_util.hpp"
#include "tp_io.h"

#include <gdal_alg.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <vector>

using tpio::fail;

namespace {

/* A projected CRS on a sphere of radius r: GDALViewshedGenerate reads the earth's size for
 * its curvature term from the CRS's semi-major axis, and nothing else from it. */
bool sphere_srs(double r, OGRSpatialReference* srs)
{
    char proj[128];
    std::snprintf(proj, sizeof proj, "+proj=eqc +a=%.17g +b=%.17g +units=m +no_defs", r, r);
    return srs->importFromProj4(proj) == OGRERR_NONE;
}

} // namespace

/* GDALViewshedGenerate on the grid in output mode mode: its result dataset and the sample of
 * the grid at its origin, or TP_ERR_* with err. */
static tp_status run_gdal(const float* heights, size_t height_count, int width, int height,
                          const double geotransform[6], int observer_x, int observer_y,
                          const tp_viewshed_options* options, GDALViewshedOutputType mode,
                          tpio::Dataset* dst, int* x0, int* y0, tp_error* err)
{
    if (!heights || !geotransform || !options || width < 1 || height < 1 ||
        height_count != (size_t)width * (size_t)height)
        return fail(err, TP_ERR_INVALID_ARG, "gdal viewshed: bad arguments");
    if (observer_x < 0 || observer_x >= width || observer_y < 0 || observer_y >= height)
        return fail(err, TP_ERR_INVALID_ARG,
                    "gdal viewshed: observer at sample (%d, %d), outside the %dx%d grid",
                    observer_x, observer_y, width, height);
    if (std::isnan(heights[(size_t)observer_y * width + observer_x]))
        return fail(err, TP_ERR_BAD_DATA,
                    "gdal viewshed: observer at sample (%d, %d) stands on nodata", observer_x,
                    observer_y);
    tpio::register_drivers();
    tpio::QuietGdal quiet;
    OGRSpatialReference srs;
    const double earth = options->earth_radius_m > 0 ? options->earth_radius_m : 6378137.0;
    if (!sphere_srs(earth, &srs))
        return fail(err, TP_ERR_BACKEND, "gdal viewshed: cannot make a sphere CRS: %s",
                    tpio::gdal_message().c_str());
    tpio::Dataset src = tpio::mem_dataset(heights, width, height, geotransform, &srs);
    if (!src)
        return fail(err, TP_ERR_BACKEND, "gdal viewshed: cannot make a MEM dataset: %s",
                    tpio::gdal_message().c_str());
    const double* gt = geotransform;
    const double e = gt[0] + (observer_x + 0.5) * gt[1];
    const double n = gt[3] + (observer_y + 0.5) * gt[5];
    GDALDatasetH h = GDALViewshedGenerate(
        GDALGetRasterBand(GDALDataset::ToHandle(src.get()), 1), "MEM", "", nullptr, e, n,
        options->observer_height_m, options->target_height_m, TP_VIEWSHED_VISIBLE,
        TP_VIEWSHED_HIDDEN, TP_VIEWSHED_OUTSIDE, -1.0, options->curvature_coeff, GVM_Edge,
        options->radius_m, nullptr, nullptr, mode, nullptr);
    if (!h)
        return fail(err, TP_ERR_BACKEND, "gdal viewshed: GDALViewshedGenerate failed: %s",
                    tpio::gdal_message().c_str());
    dst->reset(GDALDataset::FromHandle(h));
    double dgt[6];
    (*dst)->GetGeoTransform(dgt);
    *x0 = (int)std::lround((dgt[0] - gt[0]) / gt[1]);
    *y0 = (int)std::lround((dgt[3] - gt[3]) / gt[5]);
    const int w = (*dst)->GetRasterXSize(), hh = (*dst)->GetRasterYSize();
    if (*x0 < 0 || *y0 < 0 || *x0 + w > width || *y0 + hh > height)
        return fail(err, TP_ERR_BACKEND,
                    "gdal viewshed: window %dx%d at (%d, %d) outside the %dx%d grid", w, hh, *x0,
                    *y0, width, height);
    return TP_OK;
}

extern "C" tp_status tp_gdal_viewshed(const float* heights, size_t height_count, int width,
                                      int height, const double geotransform[6], int observer_x,
                                      int observer_y, const tp_viewshed_options* options,
                                      uint8_t* out, size_t out_count, tp_error* err)
{
    if (!out || out_count < height_count)
        return fail(err, TP_ERR_INVALID_ARG, "gdal viewshed: bad arguments");
    try {
        tpio::Dataset dst;
        int x0, y0;
        tp_status s = run_gdal(heights, height_count, width, height, geotransform, observer_x,
                               observer_y, options, GVOT_NORMAL, &dst, &x0, &y0, err);
        if (s != TP_OK)
            return s;
        const int w = dst->GetRasterXSize(), hh = dst->GetRasterYSize();
        std::vector<uint8_t> win((size_t)w * hh);
        if (dst->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, w, hh, win.data(), w, hh, GDT_Byte, 0,
                                            0, nullptr) != CE_None)
            return fail(err, TP_ERR_BACKEND, "gdal viewshed: cannot read the result: %s",
                        tpio::gdal_message().c_str());
        std::memset(out, TP_VIEWSHED_OUTSIDE, (size_t)width * height);
        for (int y = 0; y < hh; ++y)
            std::memcpy(out + (size_t)(y0 + y) * width + x0, win.data() + (size_t)y * w, w);
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, "gdal viewshed");
    }
}

extern "C" tp_status tp_gdal_viewshed_ground(const float* heights, size_t height_count,
                                             int width, int height, const double geotransform[6],
                                             int observer_x, int observer_y,
                                             const tp_viewshed_options* options, float* out,
                                             size_t out_count, tp_error* err)
{
    if (!out || out_count < height_count)
        return fail(err, TP_ERR_INVALID_ARG, "gdal viewshed: bad arguments");
    try {
        tpio::Dataset dst;
        int x0, y0;
        tp_status s = run_gdal(heights, height_count, width, height, geotransform, observer_x,
                               observer_y, options, GVOT_MIN_TARGET_HEIGHT_FROM_GROUND, &dst, &x0,
                               &y0, err);
        if (s != TP_OK)
            return s;
        const int w = dst->GetRasterXSize(), hh = dst->GetRasterYSize();
        std::vector<float> win((size_t)w * hh);
        if (dst->GetRasterBand(1)->RasterIO(GF_Read, 0, 0, w, hh, win.data(), w, hh,
                                            GDT_Float32, 0, 0, nullptr) != CE_None)
            return fail(err, TP_ERR_BACKEND, "gdal viewshed: cannot read the result: %s",
                        tpio::gdal_message().c_str());
        std::fill(out, out + (size_t)width * height, NAN);
        for (int y = 0; y < hh; ++y)
            std::memcpy(out + (size_t)(y0 + y) * width + x0, win.data() + (size_t)y * w,
                        sizeof(float) * w);
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, "gdal viewshed");
    }
}

extern "C" tp_status tp_viewshed_write(const char* path, const uint8_t* values, size_t value_count,
                                       int width, int height, const double geotransform[6],
                                       const char* crs_wkt, tp_error* err)
{
    return tp_byte_raster_write(path, values, value_count, width, height, geotransform, crs_wkt,
                                "visibility: 255 seen, 0 not seen or beyond the radius", err);
}
