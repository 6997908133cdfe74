/* viewshed_gdal.cpp - GDAL's viewshed of an in-memory grid (for comparing with the core's
 * tp_viewshed_compute) and a viewshed written as a GeoTIFF (see tp_io.h, "Viewsheds through
 * GDAL"). */
#include "gdal_util.hpp"
#include "tp_io.h"

#include <gdal_alg.h>

#include <atomic>
#include <cmath>
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

extern "C" tp_status tp_gdal_viewshed(const float* heights, size_t height_count, int width,
                                      int height, const double geotransform[6], int observer_x,
                                      int observer_y, const tp_viewshed_options* options,
                                      uint8_t* out, size_t out_count, tp_error* err)
{
    if (!heights || !geotransform || !options || !out || width < 1 || height < 1 ||
        height_count != (size_t)width * (size_t)height || out_count < height_count)
        return fail(err, TP_ERR_INVALID_ARG, "gdal viewshed: bad arguments");
    if (observer_x < 0 || observer_x >= width || observer_y < 0 || observer_y >= height)
        return fail(err, TP_ERR_INVALID_ARG,
                    "gdal viewshed: observer at sample (%d, %d), outside the %dx%d grid",
                    observer_x, observer_y, width, height);
    if (std::isnan(heights[(size_t)observer_y * width + observer_x]))
        return fail(err, TP_ERR_BAD_DATA,
                    "gdal viewshed: observer at sample (%d, %d) stands on nodata", observer_x,
                    observer_y);
    try {
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
            options->radius_m, nullptr, nullptr, GVOT_NORMAL, nullptr);
        if (!h)
            return fail(err, TP_ERR_BACKEND, "gdal viewshed: GDALViewshedGenerate failed: %s",
                        tpio::gdal_message().c_str());
        tpio::Dataset dst(GDALDataset::FromHandle(h));
        double dgt[6];
        dst->GetGeoTransform(dgt);
        const int x0 = (int)std::lround((dgt[0] - gt[0]) / gt[1]);
        const int y0 = (int)std::lround((dgt[3] - gt[3]) / gt[5]);
        const int w = dst->GetRasterXSize(), hh = dst->GetRasterYSize();
        if (x0 < 0 || y0 < 0 || x0 + w > width || y0 + hh > height)
            return fail(err, TP_ERR_BACKEND,
                        "gdal viewshed: window %dx%d at (%d, %d) outside the %dx%d grid", w, hh,
                        x0, y0, width, height);
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

extern "C" tp_status tp_viewshed_write_geotiff(const char* path, const uint8_t* values,
                                               size_t value_count, int width, int height,
                                               const double geotransform[6], const char* crs_wkt,
                                               tp_error* err)
{
    if (!path || !*path || !values || !geotransform || width < 1 || height < 1 ||
        value_count != (size_t)width * (size_t)height)
        return fail(err, TP_ERR_INVALID_ARG, "%s: viewshed: bad arguments", path ? path : "");
    static std::atomic<unsigned> counter{0};
    std::string mem;
    try {
        tpio::register_drivers();
        tpio::QuietGdal quiet;
        OGRSpatialReference srs;
        const bool has_crs = crs_wkt && *crs_wkt;
        if (has_crs && srs.SetFromUserInput(crs_wkt) != OGRERR_NONE)
            return fail(err, TP_ERR_BAD_DATA, "%s: viewshed: GDAL cannot read the CRS: %s", path,
                        tpio::gdal_message().c_str());
        char name[96];
        std::snprintf(name, sizeof name, "/vsimem/tp_viewshed_%p_%u.tif", (const void*)values,
                      counter++);
        mem = name;
        GDALDriver* gtiff = GetGDALDriverManager()->GetDriverByName("GTiff");
        if (!gtiff)
            return fail(err, TP_ERR_BACKEND, "%s: viewshed: GDAL has no GTiff driver", path);
        const char* co[] = {"COMPRESS=DEFLATE", "TILED=YES", nullptr};
        tp_status s = TP_OK;
        {
            tpio::Dataset ds(gtiff->Create(mem.c_str(), width, height, 1, GDT_Byte,
                                           const_cast<char**>(co)));
            if (!ds) {
                s = fail(err, TP_ERR_BACKEND, "%s: viewshed: cannot encode a GeoTIFF: %s", path,
                         tpio::gdal_message().c_str());
                VSIUnlink(mem.c_str());
                return s;
            }
            ds->SetGeoTransform(const_cast<double*>(geotransform));
            if (has_crs)
                ds->SetSpatialRef(&srs);
            GDALRasterBand* b = ds->GetRasterBand(1);
            b->SetDescription("visibility: 255 seen, 0 not seen or beyond the radius");
            if (b->RasterIO(GF_Write, 0, 0, width, height, const_cast<uint8_t*>(values), width,
                            height, GDT_Byte, 0, 0, nullptr) != CE_None)
                s = fail(err, TP_ERR_BACKEND, "%s: viewshed: cannot encode a GeoTIFF: %s", path,
                         tpio::gdal_message().c_str());
            if (s == TP_OK) {
                ds->FlushCache();
                if (CPLGetLastErrorType() == CE_Failure)
                    s = fail(err, TP_ERR_BACKEND, "%s: viewshed: cannot encode a GeoTIFF: %s",
                             path, tpio::gdal_message().c_str());
            }
        } /* closed: the file is complete in memory */
        if (s == TP_OK) {
            vsi_l_offset size = 0;
            GByte* bytes = VSIGetMemFileBuffer(mem.c_str(), &size, FALSE);
            s = bytes ? tp_file_write(path, bytes, (size_t)size, err)
                      : fail(err, TP_ERR_BACKEND, "%s: viewshed: GDAL kept no GeoTIFF", path);
        }
        VSIUnlink(mem.c_str());
        return s;
    } catch (...) {
        if (!mem.empty())
            VSIUnlink(mem.c_str());
        return tpio::caught(err, path);
    }
}
