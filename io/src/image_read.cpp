/*
 * image_read.cpp - tp_dem_read_image: a heightmap image (16-bit PNG and the like) through
 * OpenImageIO, as a tp_dem on a metric grid the user describes (--spacing, --zscale, --origin).
 *
 * Samples are taken as raw counts: OpenImageIO would otherwise normalise integer pixels to
 * [0, 1] when converting to float.
 */
#include "crs.hpp"
#include "gdal_util.hpp"
#include "tp_io.h"

#include <GeographicLib/UTMUPS.hpp>
#include <OpenImageIO/imageio.h>

#include <algorithm>
#include <cmath>
#include <exception>
#include <strings.h>
#include <vector>

namespace {

using tpio::fail;
namespace OIIO = OIIO_NAMESPACE;

template <typename T> void counts_to_heights(const void* src, size_t n, size_t stride, double z, float* out)
{
    const T* p = static_cast<const T*>(src);
    for (size_t i = 0; i < n; i++)
        out[i] = static_cast<float>(static_cast<double>(p[i * stride]) * z);
}

/* The image options describe a raster without georeference of its own. One that GDAL reads
 * with a CRS or a geotransform (a GeoTIFF, an .hgt) must keep them, and its nodata: read here
 * it would become raw counts in local metres. Heightmap extensions are OpenImageIO's alone. */
tp_status refuse_georeferenced(const char* path, tp_error* err)
{
    if (tp_is_heightmap_image(path))
        return TP_OK;
    tpio::register_drivers();
    tpio::QuietGdal quiet;
    tpio::Dataset ds(GDALDataset::FromHandle(GDALOpenEx(path, GDAL_OF_RASTER, nullptr, nullptr, nullptr)));
    if (!ds)
        return TP_OK; /* not GDAL's: OpenImageIO's to read or to refuse */
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    double gt[6];
    bool has_crs = tpio::crs_present(srs), has_gt = ds->GetGeoTransform(gt) == CE_None;
    if (!has_crs && !has_gt)
        return TP_OK;
    std::string what = has_crs ? std::string("CRS ") + srs->GetName() : "a geotransform, no CRS";
    return fail(err, TP_ERR_INVALID_ARG,
                "%s is georeferenced (%s); --spacing/--zscale apply only to heightmap images "
                "without georeference",
                path, what.c_str());
}

tp_status read(const char* path, const tp_image_options* opt, tp_dem** out, tp_error* err)
{
    tp_image_options o = opt ? *opt : tp_image_options{};
    if (tp_status s = refuse_georeferenced(path, err))
        return s;
    if (o.spacing_m < 0 || !std::isfinite(o.spacing_m) || !std::isfinite(o.zscale))
        return fail(err, TP_ERR_INVALID_ARG, "%s: --spacing must be > 0 and --zscale finite", path);
    double spacing = o.spacing_m > 0 ? o.spacing_m : 1.0, zscale = o.zscale != 0 ? o.zscale : 1.0;
    auto in = OIIO::ImageInput::open(path);
    if (!in)
        return fail(err, TP_ERR_IO, "%s: cannot open as an image: %s", path,
                    OIIO::geterror().c_str());
    const OIIO::ImageSpec& spec = in->spec();
    int w = spec.width, h = spec.height, ch = spec.nchannels;
    if (w < 1 || h < 1 || ch < 1)
        return fail(err, TP_ERR_BAD_DATA, "%s: empty image (%dx%d, %d channels)", path, w, h, ch);
    OIIO::TypeDesc type = spec.format;
    size_t n = (size_t)w * h;
    std::vector<unsigned char> raw(n * ch * type.size());
    if (!in->read_image(0, 0, 0, ch, type, raw.data()))
        return fail(err, TP_ERR_BAD_DATA, "%s: cannot read the pixels: %s", path,
                    in->geterror().c_str());
    in->close();

    tp_dem* dem = static_cast<tp_dem*>(std::calloc(1, sizeof(tp_dem)));
    if (!dem)
        return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    dem->width = w;
    dem->height = h;
    dem->heights = static_cast<float*>(std::malloc(n * sizeof(float)));
    if (!dem->heights) {
        tp_dem_destroy(dem);
        return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory for %dx%d samples", path, w, h);
    }
    switch (type.basetype) {
    case OIIO::TypeDesc::UINT8: counts_to_heights<uint8_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::INT8: counts_to_heights<int8_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::UINT16: counts_to_heights<uint16_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::INT16: counts_to_heights<int16_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::UINT32: counts_to_heights<uint32_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::INT32: counts_to_heights<int32_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::FLOAT: counts_to_heights<float>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::DOUBLE: counts_to_heights<double>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::HALF: {
        std::vector<float> f(n * ch);
        in = nullptr;
        auto again = OIIO::ImageInput::open(path);
        if (!again || !again->read_image(0, 0, 0, ch, OIIO::TypeDesc::FLOAT, f.data())) {
            tp_dem_destroy(dem);
            return fail(err, TP_ERR_BAD_DATA, "%s: cannot read the half-float pixels", path);
        }
        counts_to_heights<float>(f.data(), n, ch, zscale, dem->heights);
        break;
    }
    default:
        tp_dem_destroy(dem);
        return fail(err, TP_ERR_BAD_DATA, "%s: unsupported pixel type %s", path, type.c_str());
    }

    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < n; i++) {
        float v = dem->heights[i];
        if (!std::isfinite(v)) {
            dem->heights[i] = NAN;
            dem->void_count++;
            continue;
        }
        lo = std::min(lo, (double)v);
        hi = std::max(hi, (double)v);
    }
    dem->min_m = dem->void_count == n ? NAN : lo;
    dem->max_m = dem->void_count == n ? NAN : hi;
    std::snprintf(dem->driver, sizeof dem->driver, "OIIO:%s", in ? in->format_name() : "image");
    std::snprintf(dem->data_type, sizeof dem->data_type, "%s", type.c_str());
    dem->is_integer_type = !type.is_floating_point();
    std::snprintf(dem->units, sizeof dem->units, "%s", "m");

    std::string warnings, wkt;
    if (o.spacing_m <= 0)
        warnings = std::string(path) + ": no --spacing given: 1 m between posts taken";
    double gt[6] = {0, spacing, 0, 0, 0, -spacing};
    if (o.has_origin) {
        if (!(std::fabs(o.origin_lat_deg) <= 90) || !std::isfinite(o.origin_lon_deg)) {
            tp_dem_destroy(dem);
            return fail(err, TP_ERR_INVALID_ARG, "%s: --origin %g,%g is not a position", path,
                        o.origin_lat_deg, o.origin_lon_deg);
        }
        int zone;
        bool northp;
        double e, nn;
        GeographicLib::UTMUPS::Forward(o.origin_lat_deg, o.origin_lon_deg, zone, northp, e, nn);
        int epsg = tpio::utmups_epsg(zone, northp);
        OGRSpatialReference srs;
        srs.importFromEPSG(epsg);
        wkt = tpio::crs_wkt2(srs);
        dem->epsg = epsg;
        /* the image's centre at the origin */
        gt[0] = e - w / 2.0 * spacing;
        gt[3] = nn + h / 2.0 * spacing;
        dem->has_geotransform = 1;
    }
    std::memcpy(dem->geotransform, gt, sizeof gt);
    dem->crs_wkt = tpio::dup_c(wkt);
    dem->warnings = tpio::dup_c(warnings);
    if (!dem->crs_wkt || !dem->warnings) {
        tp_dem_destroy(dem);
        return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
    }
    if (dem->void_count == n) {
        tp_dem_destroy(dem);
        return fail(err, TP_ERR_BAD_DATA, "%s: no valid sample in the image", path);
    }
    *out = dem;
    return TP_OK;
}

} // namespace

/* C string functions only: nothing can throw; NULL is not an image. */
extern "C" int tp_is_heightmap_image(const char* path)
{
    static const char* const exts[] = {".png", ".jpg", ".jpeg", ".exr", ".pgm", ".ppm",
                                       ".tga", ".bmp", ".hdr", ".webp"};
    size_t len = path ? std::strlen(path) : 0;
    for (const char* e : exts) {
        size_t el = std::strlen(e);
        if (len > el && strcasecmp(path + len - el, e) == 0)
            return 1;
    }
    return 0;
}

extern "C" tp_status tp_dem_read_image(const char* path, const tp_image_options* options,
                                       tp_dem** out, tp_error* err)
{
    if (!path || !out)
        return fail(err, TP_ERR_INVALID_ARG, "image: path and out must not be NULL");
    try {
        return read(path, options, out, err);
    } catch (...) {
        return tpio::caught(err, path);
    }
}
