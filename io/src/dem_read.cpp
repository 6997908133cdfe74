/*
 * dem_read.cpp - tp_dem_read: band 1 of any raster GDAL opens, copied into a plain C struct.
 *
 * GDAL's own error printing is silenced (a quiet handler is pushed for the duration of each
 * call); its last message is put into tp_error behind the file name instead, so the caller
 * decides what the user sees. No GDAL type leaves this file.
 */
#include "tp_io.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <cerrno>
#include <cfloat>
#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <memory>
#include <mutex>
#include <string>

namespace {

/* Writes a one-line message: GDAL messages may hold newlines, the user sees one line. */
void set_error(tp_error* err, const char* fmt, ...)
{
    if (!err)
        return;
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(err->message, sizeof err->message, fmt, ap);
    va_end(ap);
    for (char* c = err->message; *c; ++c)
        if (*c == '\n' || *c == '\r')
            *c = ' ';
}

/* Pushes a quiet handler so GDAL prints nothing; CPLGetLastErrorMsg still records the
 * message. The handler stack is per thread, so this is safe with concurrent readers. */
struct QuietGdal {
    QuietGdal()
    {
        CPLPushErrorHandler(CPLQuietErrorHandler);
        CPLErrorReset();
    }
    ~QuietGdal()
    {
        CPLPopErrorHandler();
    }
    QuietGdal(const QuietGdal&) = delete;
    QuietGdal& operator=(const QuietGdal&) = delete;
};

std::string gdal_message()
{
    const char* m = CPLGetLastErrorMsg();
    return (m && *m) ? std::string(m) : std::string("GDAL gave no detail");
}

void register_drivers()
{
    static std::once_flag once;
    std::call_once(once, [] { GDALAllRegister(); });
}

struct DatasetCloser {
    void operator()(GDALDataset* ds) const
    {
        GDALClose(GDALDataset::ToHandle(ds));
    }
};
struct SrsDeleter {
    void operator()(OGRSpatialReference* srs) const
    {
        OGRSpatialReference::DestroySpatialReference(srs);
    }
};
struct DemDeleter {
    void operator()(tp_dem* dem) const
    {
        tp_dem_destroy(dem);
    }
};

/* malloc'd copy, so that tp_dem_destroy can free every field with free(). */
char* dup_c(const std::string& s)
{
    char* p = static_cast<char*>(std::malloc(s.size() + 1));
    if (p)
        std::memcpy(p, s.c_str(), s.size() + 1);
    return p;
}

void copy_name(char* dst, size_t cap, const char* src)
{
    std::snprintf(dst, cap, "%s", src ? src : "");
}

/* WKT2 of the CRS ("" when the file has none) and its EPSG code when one can be found. */
bool read_crs(const GDALDataset& ds, tp_dem* dem)
{
    std::string wkt;
    int epsg = 0;
    const OGRSpatialReference* srs = ds.GetSpatialRef();
    if (srs && !srs->IsEmpty()) {
        char* text = nullptr;
        const char* const options[] = {"FORMAT=WKT2", nullptr};
        if (srs->exportToWkt(&text, options) == OGRERR_NONE && text)
            wkt = text;
        CPLFree(text);

        /* Most GeoTIFFs carry the code already; otherwise let GDAL recognise common CRSs
         * (UTM, WGS84, ...) on a copy, since AutoIdentifyEPSG modifies its object. */
        const char* auth = srs->GetAuthorityName(nullptr);
        const char* code = srs->GetAuthorityCode(nullptr);
        if (auth && code && EQUAL(auth, "EPSG")) {
            epsg = std::atoi(code);
        } else {
            std::unique_ptr<OGRSpatialReference, SrsDeleter> copy(srs->Clone());
            if (copy && copy->AutoIdentifyEPSG() == OGRERR_NONE) {
                auth = copy->GetAuthorityName(nullptr);
                code = copy->GetAuthorityCode(nullptr);
                if (auth && code && EQUAL(auth, "EPSG"))
                    epsg = std::atoi(code);
            }
        }
    }
    dem->crs_wkt = dup_c(wkt);
    dem->epsg = epsg;
    return dem->crs_wkt != nullptr;
}

/* The value GDAL writes into a Float32 buffer for the nodata tag: GDAL clamps finite values
 * outside the float range to +-FLT_MAX (and a plain cast would be undefined behaviour). */
float nodata_as_float(double v)
{
    if (std::isnan(v) || std::isinf(v))
        return static_cast<float>(v);
    if (v > FLT_MAX)
        return FLT_MAX;
    if (v < -FLT_MAX)
        return -FLT_MAX;
    return static_cast<float>(v);
}

tp_status read_dem(const char* path, tp_dem** out, tp_error* err)
{
    register_drivers();
    QuietGdal quiet;

    /* Tell "no such file" (an I/O problem) apart from "a file GDAL does not understand". */
    VSIStatBufL st;
    errno = 0;
    if (VSIStatExL(path, &st, VSI_STAT_EXISTS_FLAG) != 0) {
        set_error(err, "%s: cannot open: %s", path, std::strerror(errno ? errno : ENOENT));
        return TP_ERR_IO;
    }
    if (VSILFILE* f = VSIFOpenL(path, "rb")) {
        VSIFCloseL(f);
    } else {
        set_error(err, "%s: cannot open: %s", path, std::strerror(errno ? errno : EACCES));
        return TP_ERR_IO;
    }

    std::unique_ptr<GDALDataset, DatasetCloser> ds(
        GDALDataset::Open(path, GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, nullptr,
                          nullptr, nullptr));
    if (!ds) {
        set_error(err, "%s: not a raster GDAL can open (%s)", path, gdal_message().c_str());
        return TP_ERR_BAD_DATA;
    }
    if (ds->GetRasterCount() < 1) {
        set_error(err, "%s: expected at least 1 raster band, got 0", path);
        return TP_ERR_BAD_DATA;
    }
    GDALRasterBand* band = ds->GetRasterBand(1);
    const int w = ds->GetRasterXSize(), h = ds->GetRasterYSize();
    if (w < 1 || h < 1) {
        set_error(err, "%s: expected a raster of at least 1x1, got %dx%d", path, w, h);
        return TP_ERR_BAD_DATA;
    }
    const size_t count = static_cast<size_t>(w) * static_cast<size_t>(h);
    if (count > SIZE_MAX / sizeof(float)) {
        set_error(err, "%s: %dx%d raster is too large for this machine", path, w, h);
        return TP_ERR_OUT_OF_MEMORY;
    }

    std::unique_ptr<tp_dem, DemDeleter> dem(static_cast<tp_dem*>(std::calloc(1, sizeof(tp_dem))));
    if (!dem) {
        set_error(err, "%s: out of memory", path);
        return TP_ERR_OUT_OF_MEMORY;
    }
    dem->width = w;
    dem->height = h;
    dem->heights = static_cast<float*>(std::malloc(count * sizeof(float)));
    if (!dem->heights) {
        set_error(err, "%s: out of memory for %dx%d heights", path, w, h);
        return TP_ERR_OUT_OF_MEMORY;
    }

    CPLErrorReset();
    if (band->RasterIO(GF_Read, 0, 0, w, h, dem->heights, w, h, GDT_Float32, 0, 0, nullptr) !=
        CE_None) {
        set_error(err, "%s: cannot read band 1 (%s)", path, gdal_message().c_str());
        return TP_ERR_BAD_DATA;
    }

    const GDALDataType type = band->GetRasterDataType();
    copy_name(dem->driver, sizeof dem->driver,
              ds->GetDriver() ? ds->GetDriver()->GetDescription() : "");
    copy_name(dem->data_type, sizeof dem->data_type, GDALGetDataTypeName(type));
    dem->is_integer_type = GDALDataTypeIsInteger(type) ? 1 : 0;
    copy_name(dem->units, sizeof dem->units, band->GetUnitType());

    int has_nodata = 0;
    const double nodata = band->GetNoDataValue(&has_nodata);
    dem->has_nodata = has_nodata ? 1 : 0;
    dem->nodata_value = has_nodata ? nodata : 0.0;

    /* Everything that is not a height becomes NaN: the tag, NaN, +-inf, and for untagged Int16
     * the two values SRTM (-32768) and DTED (-32767) use for voids. */
    const float nd = nodata_as_float(nodata);
    const bool nd_is_nan = has_nodata && std::isnan(nodata);
    const bool int16_guess = !has_nodata && type == GDT_Int16;
    const float nan = std::nanf("");
    size_t guessed_32768 = 0, guessed_32767 = 0, voids = 0;
    float lo = 0.0f, hi = 0.0f;
    for (size_t i = 0; i < count; ++i) {
        float v = dem->heights[i];
        if (has_nodata && (v == nd || (nd_is_nan && std::isnan(v)))) {
            v = nan;
        } else if (int16_guess && (v == -32768.0f || v == -32767.0f)) {
            if (v == -32768.0f)
                ++guessed_32768;
            else
                ++guessed_32767;
            v = nan;
        } else if (!std::isfinite(v)) {
            v = nan;
        }
        dem->heights[i] = v;
        if (std::isnan(v)) {
            ++voids;
        } else if (voids == i) { /* first valid sample */
            lo = hi = v;
        } else {
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
        }
    }
    if (voids == count) {
        set_error(err, "%s: no valid sample in band 1", path);
        return TP_ERR_BAD_DATA;
    }
    dem->void_count = voids;
    dem->min_m = lo;
    dem->max_m = hi;

    std::string warnings;
    if (guessed_32768 || guessed_32767) {
        char line[1024];
        if (guessed_32768 && guessed_32767)
            std::snprintf(line, sizeof line,
                          "%s: Int16 band has no nodata tag; %zu samples of -32768 and %zu of "
                          "-32767 taken as nodata",
                          path, guessed_32768, guessed_32767);
        else
            std::snprintf(line, sizeof line,
                          "%s: Int16 band has no nodata tag; %zu samples of %d taken as nodata",
                          path, guessed_32768 ? guessed_32768 : guessed_32767,
                          guessed_32768 ? -32768 : -32767);
        warnings += line;
    }
    dem->warnings = dup_c(warnings);

    /* GDAL has already moved pixel-is-point origins to the corner of the first pixel. */
    double gt[6];
    if (ds->GetGeoTransform(gt) == CE_None) {
        dem->has_geotransform = 1;
        std::memcpy(dem->geotransform, gt, sizeof gt);
    } else {
        const double unit[6] = {0.0, 1.0, 0.0, 0.0, 0.0, -1.0};
        dem->has_geotransform = 0;
        std::memcpy(dem->geotransform, unit, sizeof unit);
    }

    if (!read_crs(*ds, dem.get()) || !dem->warnings) {
        set_error(err, "%s: out of memory", path);
        return TP_ERR_OUT_OF_MEMORY;
    }

    *out = dem.release();
    return TP_OK;
}

} // namespace

extern "C" tp_status tp_dem_read(const char* path, tp_dem** out, tp_error* err)
{
    if (!path || !*path || !out) {
        set_error(err, "tp_dem_read: expected a file name and an output pointer, got %s",
                  !path    ? "a NULL path"
                  : !*path ? "an empty path"
                           : "a NULL output pointer");
        return TP_ERR_INVALID_ARG;
    }
    try {
        return read_dem(path, out, err);
    } catch (const std::exception& e) {
        set_error(err, "%s: reading failed in GDAL/C++ (%s)", path, e.what());
    } catch (...) {
        set_error(err, "%s: reading failed in GDAL/C++ (unknown exception)", path);
    }
    return TP_ERR_BACKEND;
}

/* Only free() below: nothing can throw. */
extern "C" void tp_dem_destroy(tp_dem* dem)
{
    if (!dem)
        return;
    std::free(dem->heights);
    std::free(dem->crs_wkt);
    std::free(dem->warnings);
    std::free(dem);
}

/* Plain field copies: nothing can throw. */
extern "C" tp_terrain_desc tp_dem_terrain_desc(const tp_dem* dem, int patch_size, tp_fit fit)
{
    tp_terrain_desc desc;
    std::memset(&desc, 0, sizeof desc);
    desc.patch_size = patch_size;
    desc.fit = fit;
    if (!dem)
        return desc;
    desc.heights = dem->heights;
    desc.height_count = static_cast<size_t>(dem->width) * static_cast<size_t>(dem->height);
    desc.width = dem->width;
    desc.height = dem->height;
    std::memcpy(desc.geotransform, dem->geotransform, sizeof desc.geotransform);
    return desc;
}
