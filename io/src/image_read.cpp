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
#include <cctype>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <cstdio>
#include <exception>
#include <vector>

namespace {

using tpio::fail;
namespace OIIO = OIIO_NAMESPACE;

/* Heights beyond this (metres, either sign) are not terrain: Everest is 8849 m, the Mariana
 * Trench -10994 m; a height of 1e5 m means a wrong --zscale. */
constexpr double max_height_m = TP_IMAGE_HEIGHT_MAX_M;

/* counts * z into out; returns the largest |height| among finite ones (in double, before the
 * cast to float, so that a scale pushing counts past the float range is seen, not turned into
 * infinities taken as nodata). */
template <typename T>
double counts_to_heights(const void* src, size_t n, size_t stride, double z, float* out)
{
    const T* p = static_cast<const T*>(src);
    double top = 0;
    for (size_t i = 0; i < n; i++) {
        const double raw = static_cast<double>(p[i * stride]);
        /* +-Inf and +-FLT_MAX are float grids' nodata (as tp_dem_read takes them), not heights
         * for the --zscale check */
        if (!(std::fabs(raw) < FLT_MAX)) {
            out[i] = NAN;
            continue;
        }
        const double v = raw * z;
        if (std::isfinite(v))
            top = std::max(top, std::fabs(v));
        out[i] = std::fabs(v) <= max_height_m ? static_cast<float>(v) : NAN;
    }
    return top;
}

using tpio::QuietStderr;

void human_bytes(double b, char* out, size_t cap)
{
    if (b >= 1e9)
        std::snprintf(out, cap, "%.1f GB", b / 1e9);
    else if (b >= 1e6)
        std::snprintf(out, cap, "%.1f MB", b / 1e6);
    else
        std::snprintf(out, cap, "%.0f bytes", b);
}

uint32_t be32(const unsigned char* p)
{
    return (uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3];
}

uint32_t crc32_update(uint32_t crc, const unsigned char* p, size_t n)
{
    static uint32_t table[256];
    if (!table[1])
        for (uint32_t i = 0; i < 256; i++) {
            uint32_t c = i;
            for (int k = 0; k < 8; k++)
                c = c & 1 ? 0xedb88320u ^ (c >> 1) : c >> 1;
            table[i] = c;
        }
    for (size_t i = 0; i < n; i++)
        crc = table[(crc ^ p[i]) & 0xff] ^ (crc >> 8);
    return crc;
}

/* A PNG's chunks, walked before the decoder sees them (lengths, CRCs, IHDR, IEND), so that a
 * cut or damaged file is refused with one message saying where, and a header claiming more
 * pixels than the file can hold is refused before anything that size is allocated: deflate
 * expands at most 1032:1, so N bytes of IDAT hold at most 1032 N bytes of rows. Files that do
 * not start with the PNG signature are left to OpenImageIO. */
} // namespace

tp_status tpio::check_png(const char* path, tp_error* err)
{
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    std::unique_ptr<FILE, int (*)(FILE*)> f(std::fopen(path, "rb"), &std::fclose);
    if (!f)
        return TP_OK; /* OpenImageIO says why */
    unsigned char head[8];
    if (std::fread(head, 1, 8, f.get()) != 8 || std::memcmp(head, sig, 8) != 0)
        return TP_OK;
    std::fseek(f.get(), 0, SEEK_END);
    const long long size = std::ftell(f.get());
    std::fseek(f.get(), 8, SEEK_SET);
    long long at = 8;
    uint32_t w = 0, h = 0;
    int depth = 0, ctype = -1;
    double idat = 0;
    std::vector<unsigned char> buf(1 << 16);
    for (int n = 0;; n++) {
        unsigned char ch[8];
        if (at == size || std::fread(ch, 1, 8, f.get()) != 8)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: PNG is truncated: it ends at byte %lld without its IEND chunk", path,
                        size);
        const uint32_t len = be32(ch);
        char type[5] = {(char)ch[4], (char)ch[5], (char)ch[6], (char)ch[7], 0};
        for (int i = 0; i < 4; i++)
            if (!std::isalpha((unsigned char)type[i]))
                std::snprintf(type, sizeof type, "????");
        if (len > 0x7fffffffu || at + 12 + (long long)len > size)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: PNG is truncated: chunk %s at byte %lld claims %u bytes, the file "
                        "ends %lld bytes later",
                        path, type, at, len, size - at - 8);
        if (n == 0 && std::strcmp(type, "IHDR") != 0)
            return fail(err, TP_ERR_BAD_DATA, "%s: PNG starts with chunk %s, expected IHDR",
                        path, type);
        uint32_t crc = crc32_update(0xffffffffu, ch + 4, 4);
        unsigned char ihdr[13] = {0};
        for (uint32_t left = len; left > 0;) {
            const size_t take = std::min<size_t>(left, buf.size());
            if (std::fread(buf.data(), 1, take, f.get()) != take)
                return fail(err, TP_ERR_IO, "%s: cannot read chunk %s at byte %lld", path, type,
                            at);
            if (n == 0 && left == len)
                std::memcpy(ihdr, buf.data(), std::min<size_t>(take, 13));
            crc = crc32_update(crc, buf.data(), take);
            left -= (uint32_t)take;
        }
        unsigned char stored[4];
        if (std::fread(stored, 1, 4, f.get()) != 4)
            return fail(err, TP_ERR_IO, "%s: cannot read chunk %s at byte %lld", path, type, at);
        if ((crc ^ 0xffffffffu) != be32(stored))
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: PNG chunk %s at byte %lld is corrupt: CRC 0x%08x in the file, "
                        "0x%08x computed",
                        path, type, at, be32(stored), crc ^ 0xffffffffu);
        if (n == 0) {
            if (len != 13)
                return fail(err, TP_ERR_BAD_DATA, "%s: PNG IHDR has %u bytes, expected 13",
                            path, len);
            w = be32(ihdr);
            h = be32(ihdr + 4);
            depth = ihdr[8];
            ctype = ihdr[9];
        }
        if (!std::strcmp(type, "IDAT"))
            idat += len;
        at += 12 + (long long)len;
        if (!std::strcmp(type, "IEND"))
            break;
    }
    const int channels = ctype == 2 ? 3 : ctype == 4 ? 2 : ctype == 6 ? 4 : 1;
    const char* kind = ctype == 0 ? "grey" : ctype == 2 ? "RGB" : ctype == 3 ? "palette"
                       : ctype == 4 ? "grey+alpha" : "RGBA";
    const double rows = (double)h * std::ceil((double)w * channels * depth / 8.0);
    if (rows > idat * 1032.0 + 1032.0) {
        char need[32], can[32];
        human_bytes(rows, need, sizeof need);
        human_bytes(idat * 1032.0, can, sizeof can);
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: PNG header claims %ux%u %d-bit %s pixels (%s), but its %.0f bytes of "
                    "compressed image data can hold at most %s (deflate expands at most "
                    "1032:1): truncated or corrupt",
                    path, w, h, depth, kind, need, idat, can);
    }
    return TP_OK;
}

namespace {

using tpio::check_png;

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
    /* a FIFO would block the open (GDAL's below, or OpenImageIO's) */
    if (tp_status s = tpio::check_input_file(path, "an image", false, err))
        return s;
    if (tp_status s = refuse_georeferenced(path, err))
        return s;
    if (!(o.spacing_m == 0 || (o.spacing_m >= TP_IMAGE_SPACING_MIN_M &&
                               o.spacing_m <= TP_IMAGE_SPACING_MAX_M)))
        return fail(err, TP_ERR_INVALID_ARG,
                    "%s: --spacing %g m is outside %g .. %g m", path, o.spacing_m,
                    TP_IMAGE_SPACING_MIN_M, TP_IMAGE_SPACING_MAX_M);
    if (!(o.zscale == 0 || (o.zscale >= TP_IMAGE_ZSCALE_MIN && o.zscale <= TP_IMAGE_ZSCALE_MAX)))
        return fail(err, TP_ERR_INVALID_ARG, "%s: --zscale %g is outside %g .. %g m per count",
                    path, o.zscale, TP_IMAGE_ZSCALE_MIN, TP_IMAGE_ZSCALE_MAX);
    double spacing = o.spacing_m > 0 ? o.spacing_m : 1.0, zscale = o.zscale != 0 ? o.zscale : 1.0;
    if (tp_status s = check_png(path, err))
        return s;
    QuietStderr quiet; /* the codecs' own lines; their text reaches us through geterror() */
    auto in = OIIO::ImageInput::open(path);
    if (!in)
        return fail(err, TP_ERR_IO, "%s: cannot open as an image: %s", path,
                    OIIO::geterror().c_str());
    const OIIO::ImageSpec& spec = in->spec();
    int w = spec.width, h = spec.height, ch = spec.nchannels;
    if (w < 1 || h < 1 || ch < 1)
        return fail(err, TP_ERR_BAD_DATA, "%s: empty image (%dx%d, %d channels)", path, w, h, ch);
    OIIO::TypeDesc type = spec.format;
    /* The decoded pixels twice (OpenImageIO's PNG reader keeps its own copy of the whole image,
     * we read into ours) and the heights: refused before any of it is allocated. */
    const double per_sample = 2.0 * ch * type.size() + sizeof(float);
    if (tp_status s = tpio::check_fits_in_memory(
            path, w, h, per_sample, "for the decoded pixels, a copy of them and the heights", err))
        return s;
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
    double top = 0; /* largest |height| */
    switch (type.basetype) {
    case OIIO::TypeDesc::UINT8: top = counts_to_heights<uint8_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::INT8: top = counts_to_heights<int8_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::UINT16: top = counts_to_heights<uint16_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::INT16: top = counts_to_heights<int16_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::UINT32: top = counts_to_heights<uint32_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::INT32: top = counts_to_heights<int32_t>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::FLOAT: top = counts_to_heights<float>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::DOUBLE: top = counts_to_heights<double>(raw.data(), n, ch, zscale, dem->heights); break;
    case OIIO::TypeDesc::HALF: {
        std::vector<float> f(n * ch);
        in = nullptr;
        auto again = OIIO::ImageInput::open(path);
        if (!again || !again->read_image(0, 0, 0, ch, OIIO::TypeDesc::FLOAT, f.data())) {
            tp_dem_destroy(dem);
            return fail(err, TP_ERR_BAD_DATA, "%s: cannot read the half-float pixels", path);
        }
        top = counts_to_heights<float>(f.data(), n, ch, zscale, dem->heights);
        break;
    }
    default:
        tp_dem_destroy(dem);
        return fail(err, TP_ERR_BAD_DATA, "%s: unsupported pixel type %s", path, type.c_str());
    }

    if (top > max_height_m) {
        tp_dem_destroy(dem);
        return fail(err, TP_ERR_INVALID_ARG,
                    "%s: heights reach %g m at --zscale %g m per count, beyond the +-%g m a "
                    "terrain can have; check --zscale",
                    path, top, zscale, max_height_m);
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
    /* counts times --zscale are metres already */
    dem->z_to_m = 1.0;
    std::snprintf(dem->z_unit, sizeof dem->z_unit, "%s", "metre");
    std::snprintf(dem->z_unit_from, sizeof dem->z_unit_from, "%s",
                  "counts times --zscale (a heightmap image)");

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
