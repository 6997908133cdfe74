/* gdaldem.cpp - slope, aspect and hillshade of an in-memory grid by GDALDEMProcessing (the
 * library form of gdaldem), and the product written as a raster (tp_io.h, "gdaldem"). The grid
 * goes to GDAL as a Float32 MEM dataset whose voids hold a finite nodata value (-FLT_MAX: no
 * height is that, and GDAL's nodata tests need no NaN rule); the product comes back as the MEM
 * dataset gdaldem makes (its Float32 or Byte band, its nodata value), read into floats or
 * written as it is by tpio::raster_write (byte_raster.cpp). */
#include "byte_raster.hpp"
#include "gdal_util.hpp"
#include "output_format.hpp"
#include "tp_io.h"

#include <gdal_utils.h>

#include <algorithm>
#include <chrono>

#include <cfloat>
#include <cmath>
#include <string>
#include <vector>

using tpio::fail;

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0)
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/* The voids' nodata value in the dataset handed to GDAL. */
const float k_void = -FLT_MAX;

std::string number(double v)
{
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.17g", v);
    return buf;
}

/* gdaldem's arguments for o, as `gdaldem PRODUCT ... -of MEM` takes them. */
std::vector<std::string> arguments(const tp_gdaldem_options& o)
{
    std::vector<std::string> a = {
        "-of", "MEM",  "-b",
        "1",   "-alg", o.method == TP_GDALDEM_ZEVENBERGEN ? "ZevenbergenThorne" : "Horn"};
    if (o.compute_edges)
        a.push_back("-compute_edges");
    switch (o.product) {
    case TP_GDALDEM_SLOPE:
        a.insert(a.end(), {"-s", "1"});
        if (o.slope_percent)
            a.push_back("-p");
        break;
    case TP_GDALDEM_ASPECT:
        if (o.zero_for_flat)
            a.push_back("-zero_for_flat");
        break;
    case TP_GDALDEM_HILLSHADE:
        a.insert(a.end(), {"-s", "1", "-az", number(o.azimuth_deg), "-alt", number(o.altitude_deg),
                           "-z", number(o.z_factor)});
        break;
    }
    return a;
}

/* The checks every entry point makes; TP_OK or TP_ERR_INVALID_ARG with the reason. */
tp_status check(const float* heights, size_t height_count, int width, int height, const double* gt,
                const tp_gdaldem_options* o, tp_error* err)
{
    if (!heights || !gt || !o || width < 1 || height < 1 ||
        height_count != (size_t)width * (size_t)height)
        return fail(err, TP_ERR_INVALID_ARG, "gdaldem: bad arguments");
    if (gt[2] != 0.0 || gt[4] != 0.0 || !(gt[1] != 0.0) || !(gt[5] != 0.0) ||
        !std::isfinite(gt[1]) || !std::isfinite(gt[5]))
        return fail(err, TP_ERR_INVALID_ARG,
                    "gdaldem: the grid's geotransform is rotated or has a zero or non-finite "
                    "step (%g, %g)",
                    gt[1], gt[5]);
    if ((int)o->product < TP_GDALDEM_SLOPE || (int)o->product > TP_GDALDEM_HILLSHADE ||
        (int)o->method < TP_GDALDEM_HORN || (int)o->method > TP_GDALDEM_ZEVENBERGEN)
        return fail(err, TP_ERR_INVALID_ARG, "gdaldem: unknown product %d or method %d",
                    (int)o->product, (int)o->method);
    if (o->product == TP_GDALDEM_HILLSHADE &&
        (!std::isfinite(o->azimuth_deg) || !(std::fabs(o->altitude_deg) <= 90.0) ||
         !std::isfinite(o->z_factor) || o->z_factor == 0.0))
        return fail(err, TP_ERR_INVALID_ARG,
                    "gdaldem: hillshade azimuth %g, altitude %g (-90 .. 90), z factor %g (not 0)",
                    o->azimuth_deg, o->altitude_deg, o->z_factor);
    return TP_OK;
}

/* The grid as a Float32 MEM dataset with srs (may be null), voids k_void. */
tpio::Dataset source(const float* heights, int w, int h, const double gt[6],
                     const OGRSpatialReference* srs)
{
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    if (!mem)
        return nullptr;
    tpio::Dataset ds(mem->Create("", w, h, 1, GDT_Float32, nullptr));
    if (!ds)
        return nullptr;
    ds->SetGeoTransform(const_cast<double*>(gt));
    if (srs)
        ds->SetSpatialRef(srs);
    GDALRasterBand* b = ds->GetRasterBand(1);
    b->SetNoDataValue(k_void);
    std::vector<float> row((size_t)w);
    for (int y = 0; y < h; ++y) {
        const float* in = heights + (size_t)y * w;
        for (int x = 0; x < w; ++x)
            row[x] = std::isnan(in[x]) ? k_void : in[x];
        if (b->RasterIO(GF_Write, 0, y, w, 1, row.data(), w, 1, GDT_Float32, 0, 0, nullptr) !=
            CE_None)
            return nullptr;
    }
    return ds;
}

/* gdaldem -zero_for_flat writes 0 on flat ground, but also in voids and where the 3x3 window
 * is not whole, and no nodata value (GDAL 3.6): band (its aspect) gets -9999 there back, as
 * without -zero_for_flat, the voids staying nodata. A post has no window when it is a void or,
 * without compute_edges, when a post of its 3x3 window is a void or off the grid. */
bool keep_voids(GDALRasterBand* band, const float* heights, int w, int h, bool compute_edges)
{
    band->SetNoDataValue(TP_GDALDEM_FLOAT_NODATA);
    std::vector<float> row((size_t)w);
    auto no_height = [&](int x, int y) {
        return x < 0 || y < 0 || x >= w || y >= h || std::isnan(heights[(size_t)y * w + x]);
    };
    for (int y = 0; y < h; ++y) {
        if (band->RasterIO(GF_Read, 0, y, w, 1, row.data(), w, 1, GDT_Float32, 0, 0, nullptr) !=
            CE_None)
            return false;
        for (int x = 0; x < w; ++x) {
            bool none = no_height(x, y);
            for (int k = 0; !compute_edges && !none && k < 9; ++k)
                none = no_height(x + k % 3 - 1, y + k / 3 - 1);
            if (none)
                row[x] = (float)TP_GDALDEM_FLOAT_NODATA;
        }
        if (band->RasterIO(GF_Write, 0, y, w, 1, row.data(), w, 1, GDT_Float32, 0, 0, nullptr) !=
            CE_None)
            return false;
    }
    return true;
}

/* gdaldem's product of the grid, as the MEM dataset GDALDEMProcessing made, into *out. */
tp_status run(const float* heights, int w, int h, const double gt[6],
              const OGRSpatialReference* srs, const tp_gdaldem_options& o, tpio::Dataset* out,
              tp_error* err)
{
    tpio::register_drivers();
    tpio::Dataset src = source(heights, w, h, gt, srs);
    if (!src)
        return fail(err, TP_ERR_BACKEND, "gdaldem: GDAL cannot hold the %dx%d grid in memory: %s",
                    w, h, tpio::gdal_message().c_str());
    const std::vector<std::string> args = arguments(o);
    std::vector<char*> argv;
    for (const std::string& s : args)
        argv.push_back(const_cast<char*>(s.c_str()));
    argv.push_back(nullptr);
    GDALDEMProcessingOptions* po = GDALDEMProcessingOptionsNew(argv.data(), nullptr);
    if (!po)
        return fail(err, TP_ERR_BACKEND, "gdaldem: GDAL refuses the options: %s",
                    tpio::gdal_message().c_str());
    int usage = 0;
    GDALDatasetH made = GDALDEMProcessing("", GDALDataset::ToHandle(src.get()),
                                          tp_gdaldem_product_name(o.product), nullptr, po, &usage);
    GDALDEMProcessingOptionsFree(po);
    if (!made)
        return fail(err, TP_ERR_BACKEND, "gdaldem %s: GDAL cannot compute it: %s",
                    tp_gdaldem_product_name(o.product), tpio::gdal_message().c_str());
    out->reset(GDALDataset::FromHandle(made));
    if (o.product == TP_GDALDEM_ASPECT && o.zero_for_flat &&
        !keep_voids((*out)->GetRasterBand(1), heights, w, h, o.compute_edges))
        return fail(err, TP_ERR_BACKEND, "gdaldem aspect: GDAL cannot rewrite its result: %s",
                    tpio::gdal_message().c_str());
    return TP_OK;
}

/* Reads band's row y as floats (its nodata as NaN) into row. */
bool read_row(GDALRasterBand* band, int y, std::vector<float>& row)
{
    const int w = (int)row.size();
    if (band->RasterIO(GF_Read, 0, y, w, 1, row.data(), w, 1, GDT_Float32, 0, 0, nullptr) !=
        CE_None)
        return false;
    int has = 0;
    const double nodata = band->GetNoDataValue(&has);
    if (has)
        for (float& v : row)
            if (v == (float)nodata)
                v = NAN;
    return true;
}

/* What the band description says of o. */
std::string description(const tp_gdaldem_options& o)
{
    const std::string how =
        std::string(o.method == TP_GDALDEM_HORN ? "Horn" : "Zevenbergen-Thorne") +
        (o.compute_edges ? ", edges computed" : "") + "; gdaldem";
    char buf[256];
    switch (o.product) {
    case TP_GDALDEM_SLOPE:
        std::snprintf(buf, sizeof buf, "slope: %s from horizontal (%s); -9999 nodata",
                      o.slope_percent ? "percent" : "degrees", how.c_str());
        break;
    case TP_GDALDEM_ASPECT:
        std::snprintf(buf, sizeof buf,
                      "aspect: degrees clockwise from grid north, the way the slope faces (%s); "
                      "%s",
                      how.c_str(),
                      o.zero_for_flat ? "0 flat, -9999 nodata" : "-9999 flat or nodata");
        break;
    default:
        std::snprintf(
            buf, sizeof buf,
            "hillshade: 1..255 lit from azimuth %g deg, altitude %g deg, z factor %g (%s); "
            "0 nodata",
            o.azimuth_deg, o.altitude_deg, o.z_factor, how.c_str());
        break;
    }
    return buf;
}

} // namespace

extern "C" tp_gdaldem_options tp_gdaldem_options_default(tp_gdaldem_product product)
{
    tp_gdaldem_options o = {};
    o.product = product;
    o.method = TP_GDALDEM_HORN;
    o.azimuth_deg = 315.0;
    o.altitude_deg = 45.0;
    o.z_factor = 1.0;
    return o;
}

extern "C" const char* tp_gdaldem_product_name(tp_gdaldem_product p)
{
    return p == TP_GDALDEM_SLOPE ? "slope" : p == TP_GDALDEM_ASPECT ? "aspect" : "hillshade";
}

extern "C" const char* tp_gdaldem_method_name(tp_gdaldem_method m)
{
    return m == TP_GDALDEM_ZEVENBERGEN ? "zevenbergen" : "horn";
}

extern "C" tp_output_kind tp_gdaldem_output_kind(tp_gdaldem_product p)
{
    return p == TP_GDALDEM_HILLSHADE ? TP_OUTPUT_BYTE_RASTER : TP_OUTPUT_FLOAT_RASTER;
}

extern "C" tp_status tp_gdaldem_compute(const float* heights, size_t height_count, int width,
                                        int height, const double geotransform[6],
                                        const tp_gdaldem_options* options, float* out,
                                        size_t out_count, tp_error* err)
{
    tp_status s = check(heights, height_count, width, height, geotransform, options, err);
    if (s != TP_OK)
        return s;
    if (!out || out_count < height_count)
        return fail(err, TP_ERR_INVALID_ARG, "gdaldem: bad arguments (out)");
    try {
        tpio::QuietGdal quiet;
        tpio::Dataset made;
        s = run(heights, width, height, geotransform, nullptr, *options, &made, err);
        if (s != TP_OK)
            return s;
        GDALRasterBand* b = made->GetRasterBand(1);
        std::vector<float> all(height_count), row((size_t)width);
        for (int y = 0; y < height; ++y) {
            if (!read_row(b, y, row))
                return fail(err, TP_ERR_BACKEND, "gdaldem: GDAL cannot read its result: %s",
                            tpio::gdal_message().c_str());
            std::copy(row.begin(), row.end(), all.begin() + (size_t)y * width);
        }
        std::copy(all.begin(), all.end(), out);
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, "gdaldem");
    }
}

extern "C" tp_status tp_gdaldem_write(const char* path, const float* heights, size_t height_count,
                                      int width, int height, const double geotransform[6],
                                      const char* crs_wkt, const tp_gdaldem_options* options,
                                      tp_gdaldem_stats* stats, tp_error* err)
{
    tp_status s = check(heights, height_count, width, height, geotransform, options, err);
    if (s != TP_OK)
        return s;
    if (!path || !*path)
        return fail(err, TP_ERR_INVALID_ARG, "gdaldem: bad arguments (path)");
    try {
        GDALDriver* drv;
        const char* const* co;
        const tp_output_kind kind = tp_gdaldem_output_kind(options->product);
        if ((s = tpio::output_driver(path, kind, &drv, &co, err)) != TP_OK)
            return s;
        tpio::QuietGdal quiet;
        OGRSpatialReference srs;
        const bool has_crs = crs_wkt && *crs_wkt;
        if (has_crs && srs.SetFromUserInput(crs_wkt) != OGRERR_NONE)
            return fail(err, TP_ERR_BAD_DATA, "%s: GDAL cannot read the CRS: %s", path,
                        tpio::gdal_message().c_str());
        const auto t0 = std::chrono::steady_clock::now();
        tpio::Dataset made;
        s = run(heights, width, height, geotransform, has_crs ? &srs : nullptr, *options, &made,
                err);
        if (s != TP_OK)
            return s;
        GDALRasterBand* b = made->GetRasterBand(1);
        b->SetDescription(description(*options).c_str());
        tp_gdaldem_stats st = {0, 0, NAN, NAN, seconds_since(t0), 0.0};
        std::vector<float> row((size_t)width);
        for (int y = 0; y < height; ++y) {
            if (!read_row(b, y, row))
                return fail(err, TP_ERR_BACKEND, "gdaldem: GDAL cannot read its result: %s",
                            tpio::gdal_message().c_str());
            for (float v : row) {
                if (std::isnan(v)) {
                    ++st.nodata;
                    continue;
                }
                st.min = st.valid ? std::fmin(st.min, v) : v;
                st.max = st.valid ? std::fmax(st.max, v) : v;
                ++st.valid;
            }
        }
        const auto t1 = std::chrono::steady_clock::now();
        if ((s = tpio::raster_write(path, kind, made.get(), err)) != TP_OK)
            return s;
        st.write_s = seconds_since(t1);
        if (stats)
            *stats = st;
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}
