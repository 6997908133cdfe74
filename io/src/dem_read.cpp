/*
 * dem_read.cpp - tp_dem_read: band 1 of any raster GDAL opens, copied into a plain C struct.
 *
 * GDAL's own error printing is silenced (a quiet handler is pushed for the duration of each
 * call); its last message is put into tp_error behind the file name instead, so the caller
 * decides what the user sees. No GDAL type leaves this file.
 *
 * Bad input is refused with a status and a message naming the file, before anything large is
 * allocated where the file allows: a missing file or a directory (TP_ERR_IO); an empty file,
 * one GDAL cannot open, a geotransform that is not finite, rotated, of zero pixel size or with
 * columns running west, a geographic raster whose rows reach beyond +-90 degrees, a read that
 * fails part way (a truncated strip), a band with no valid height (TP_ERR_BAD_DATA); a raster
 * whose heights would not fit in this machine's memory (TP_ERR_OUT_OF_MEMORY, with the size).
 * The checks of the georeference and of ASCII grids' text are in dem_check.cpp.
 */
#include "tp_io.h"

#include <cpl_conv.h>
#include <cpl_error.h>
#include <cpl_vsi.h>
#include <gdal.h>
#include <gdal_priv.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cctype>
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
#include <vector>

#include <unistd.h>

#include "crs.hpp"
#include "dem_check.hpp"
#include "gdal_util.hpp"

namespace {

using tpio::check_ascii_grid;
using tpio::check_geotransform;
using tpio::check_latitude;
using tpio::check_ranges;
using tpio::DatasetCloser;
using tpio::dup_c;
using tpio::QuietGdal;
using tpio::register_drivers;
using tpio::set_error;

/* GDAL's last message without the file name our message already starts with: GDAL writes
 * "`PATH' not recognized ...", "PATH: TIFFReadDirectory: ..." or "PATH, band 1: ...". */
std::string gdal_message(const char* path)
{
    std::string m = tpio::gdal_message();
    const std::string p = path;
    for (const std::string& form : {"`" + p + "' ", p + ": ", p + ", "}) {
        for (size_t at; (at = m.find(form)) != std::string::npos;)
            m.erase(at, form.size());
    }
    while (!m.empty() && (m.back() == '.' || m.back() == ' '))
        m.pop_back();
    return m.empty() ? std::string("GDAL gave no detail") : m;
}

struct DemDeleter {
    void operator()(tp_dem* dem) const
    {
        tp_dem_destroy(dem);
    }
};

void copy_name(char* dst, size_t cap, const char* src)
{
    std::snprintf(dst, cap, "%s", src ? src : "");
}

/* WKT2 of the CRS ("" when the file has none) and its EPSG code when one can be found: most
 * GeoTIFFs carry the code already; otherwise GDAL recognises common CRSs (UTM, WGS84, ...). */
bool read_crs(const GDALDataset& ds, tp_dem* dem)
{
    const OGRSpatialReference* srs = ds.GetSpatialRef();
    const bool has = tpio::crs_present(srs);
    dem->crs_wkt = dup_c(has ? tpio::crs_wkt2(*srs) : std::string());
    dem->epsg = has ? tpio::crs_epsg(*srs, true) : 0;
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

/* Bytes of memory this process can use: the smaller of physical RAM and what GDAL finds usable
 * (it knows cgroup limits and RLIMIT_AS); 0 if neither is known. */
uint64_t usable_memory_bytes()
{
    uint64_t best = 0;
    const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
    if (pages > 0 && page > 0)
        best = static_cast<uint64_t>(pages) * static_cast<uint64_t>(page);
    const GIntBig gdal = CPLGetUsablePhysicalRAM();
    if (gdal > 0 && (best == 0 || static_cast<uint64_t>(gdal) < best))
        best = static_cast<uint64_t>(gdal);
    return best;
}

double gib(double bytes)
{
    return bytes / (1024.0 * 1024.0 * 1024.0);
}

bool has_extension(const char* path, const char* ext)
{
    const size_t n = std::strlen(path), e = std::strlen(ext);
    return n >= e && EQUAL(path + n - e, ext);
}

/* GDAL says "not recognized as a supported file format" for anything it cannot place; for an
 * .hgt that is almost always a name or size the SRTMHGT driver does not accept, so say which. */
std::string open_hint(const char* path, const VSIStatBufL& st)
{
    if (!has_extension(path, ".hgt"))
        return "";
    char hint[256];
    std::snprintf(hint, sizeof hint,
                  "; an SRTM .hgt must be named like N42E001.hgt and hold 1201x1201 (%d bytes) or "
                  "3601x3601 (%d bytes) big-endian Int16 samples, this one has %lld bytes",
                  1201 * 1201 * 2, 3601 * 3601 * 2, static_cast<long long>(st.st_size));
    return hint;
}

/* DTED stores a checksum with every column; GDAL checks it only when DTED_VERIFY_CHECKSUM is
 * set when the file is opened. Corrupt elevations must not be used without a word, so ask,
 * unless the user has set the option (DTED_VERIFY_CHECKSUM=NO reads a damaged file anyway). */
struct VerifyDtedChecksums {
    bool set = false;
    VerifyDtedChecksums()
    {
        if (!CPLGetConfigOption("DTED_VERIFY_CHECKSUM", nullptr)) {
            CPLSetThreadLocalConfigOption("DTED_VERIFY_CHECKSUM", "YES");
            set = true;
        }
    }
    ~VerifyDtedChecksums()
    {
        if (set)
            CPLSetThreadLocalConfigOption("DTED_VERIFY_CHECKSUM", nullptr);
    }
    VerifyDtedChecksums(const VerifyDtedChecksums&) = delete;
    VerifyDtedChecksums& operator=(const VerifyDtedChecksums&) = delete;
};

/* The .prj among the dataset's files, "" when there is none. */
std::string prj_of(GDALDataset& ds)
{
    char** files = ds.GetFileList();
    std::string prj;
    for (char** f = files; f && *f; ++f)
        if (has_extension(*f, ".prj"))
            prj = *f;
    CSLDestroy(files);
    return prj;
}

/* What read_dem has found so far, shared by its steps. */
struct DemRead {
    const char* path = nullptr;
    std::unique_ptr<GDALDataset, DatasetCloser> ds;
    GDALRasterBand* band = nullptr;           /* band 1 */
    int w = 0, h = 0;
    double gt[6] = {0, 1, 0, 0, 0, -1};
    bool has_gt = false;
    const OGRSpatialReference* srs = nullptr; /* owned by ds */
    const char* driver = "";
    tpio::ZUnit zu;
    /* samples taken as nodata with a warning */
    size_t guessed_32768 = 0, guessed_32767 = 0, infinite = 0;
};

/* Checks path before anything opens it, then opens it with GDAL: r.st, r.ds, r.band, r.w, r.h. */
tp_status open_raster(DemRead& r, tp_error* err)
{
    const char* path = r.path;
    /* A FIFO or a device would block GDAL's open (or never end): refuse what is not a regular
     * file or a directory before anything opens it. */
    if (const tp_status s = tpio::check_input_file(path, "a raster", true, err))
        return s;

    /* Tell "no such file" and "a directory" (I/O problems) apart from "a file GDAL does not
     * understand", and an empty file from a corrupt one. */
    VSIStatBufL st;
    std::memset(&st, 0, sizeof st);
    errno = 0;
    if (VSIStatExL(path, &st, VSI_STAT_EXISTS_FLAG | VSI_STAT_NATURE_FLAG | VSI_STAT_SIZE_FLAG) !=
        0) {
        set_error(err, "%s: cannot open: %s", path, std::strerror(errno ? errno : ENOENT));
        return TP_ERR_IO;
    }
    const bool is_dir = VSI_ISDIR(st.st_mode);
    if (!is_dir) {
        if (VSILFILE* f = VSIFOpenL(path, "rb")) {
            VSIFCloseL(f);
        } else {
            set_error(err, "%s: cannot open: %s", path, std::strerror(errno ? errno : EACCES));
            return TP_ERR_IO;
        }
        if (VSI_ISREG(st.st_mode) && st.st_size == 0) {
            set_error(err, "%s: empty file (0 bytes), expected a raster", path);
            return TP_ERR_BAD_DATA;
        }
    }

    /* A directory can still be a raster (an ArcInfo binary grid is one), so GDAL has the first
     * word; if it cannot open it, the answer is that it is a directory. */
    r.ds.reset(
        GDALDataset::Open(path, GDAL_OF_RASTER | GDAL_OF_READONLY | GDAL_OF_VERBOSE_ERROR, nullptr,
                          nullptr, nullptr));
    if (!r.ds) {
        if (is_dir) {
            set_error(err, "%s: cannot open: %s, expected a raster file", path,
                      std::strerror(EISDIR));
            return TP_ERR_IO;
        }
        set_error(err, "%s: not a raster GDAL can open (%s)%s", path, gdal_message(path).c_str(),
                  open_hint(path, st).c_str());
        return TP_ERR_BAD_DATA;
    }
    if (r.ds->GetRasterCount() < 1) {
        set_error(err, "%s: expected at least 1 raster band, got 0", path);
        return TP_ERR_BAD_DATA;
    }
    r.band = r.ds->GetRasterBand(1);
    const int w = r.w = r.ds->GetRasterXSize(), h = r.h = r.ds->GetRasterYSize();
    if (w < 1 || h < 1) {
        set_error(err, "%s: expected a raster of at least 1x1, got %dx%d", path, w, h);
        return TP_ERR_BAD_DATA;
    }
    return TP_OK;
}

/* The georeference, checked before the heights are read (r.gt, r.has_gt, r.srs). */
tp_status check_georeference(DemRead& r, tp_error* err)
{
    const char* path = r.path;
    const int w = r.w, h = r.h;
    double* gt = r.gt;
    /* Georeferencing first: it is cheap, and a bad one is refused before the heights are read.
     * GDAL has already moved pixel-is-point origins to the corner of the first pixel. */
    const bool has_gt = r.has_gt = r.ds->GetGeoTransform(gt) == CE_None;
    if (has_gt) {
        const tp_status s = check_geotransform(path, gt, err);
        if (s != TP_OK)
            return s;
    } else {
        const double unit[6] = {0.0, 1.0, 0.0, 0.0, 0.0, -1.0};
        std::memcpy(gt, unit, sizeof unit);
    }
    const OGRSpatialReference* srs = r.srs = r.ds->GetSpatialRef();
    if (has_gt) {
        const tp_status s = check_ranges(path, srs, gt, w, h, err);
        if (s != TP_OK)
            return s;
    }
    if (has_gt && tpio::crs_present(srs)) {
        const tp_status s = check_latitude(path, *srs, gt, h, err);
        if (s != TP_OK)
            return s;
    }
    return TP_OK;
}

/* GDAL decodes whole blocks, and a pixel-interleaved block holds every band: a damaged header
 * (a strip far taller than the image, thousands of bands) can ask for gigabytes to read a few
 * samples. Refuses a block larger than four times the heights (need bytes; at least 256 MiB). */
tp_status check_block_size(const DemRead& r, double need, tp_error* err)
{
    const char* path = r.path;
    const int w = r.w, h = r.h;
    GDALDataset* ds = r.ds.get();
    GDALRasterBand* band = r.band;
    int bx = 0, by = 0;
    band->GetBlockSize(&bx, &by);
    const char* il = ds->GetMetadataItem("INTERLEAVE", "IMAGE_STRUCTURE");
    const int bands = il && EQUAL(il, "PIXEL") ? ds->GetRasterCount() : 1;
    const double block = static_cast<double>(bx) * by * bands *
                         GDALGetDataTypeSizeBytes(band->GetRasterDataType());
    if (block > std::max(4.0 * need, 256.0 * 1024 * 1024)) {
        set_error(err,
                  "%s: one block of this %dx%d raster is %dx%d samples%s and needs %.1f GiB to "
                  "decode: a damaged or unusual file (gdal_translate -co TILED=YES makes a "
                  "readable copy)",
                  path, w, h, bx, by,
                  bands > 1 ? (" of " + std::to_string(bands) + " interleaved bands").c_str()
                            : "",
                  gib(block));
        return TP_ERR_BAD_DATA;
    }
    return TP_OK;
}

/* Band 1 into dem->heights (w * h floats), as stored; a read that fails part way is refused. */
tp_status read_heights(const DemRead& r, tp_dem* dem, tp_error* err)
{
    const char* path = r.path;
    const int w = r.w, h = r.h;
    GDALRasterBand* band = r.band;
    const char* driver = r.driver;
    /* A read can fail part way (a strip cut off by a truncated copy). Some drivers report a
     * failure through CPLError but still return CE_None for the request, so both count; no
     * partial result is kept. */
    CPLErrorReset();
    const CPLErr io =
        band->RasterIO(GF_Read, 0, 0, w, h, dem->heights, w, h, GDT_Float32, 0, 0, nullptr);
    const CPLErr last = CPLGetLastErrorType();
    if ((io != CE_None || last != CE_None) && EQUAL(driver, "DTED") &&
        std::strstr(CPLGetLastErrorMsg(), "hecksum")) {
        /* GDAL: "... checksum that do not match at column 100. Computed 0x2871C, read
         * 0x2871B" behind its IReadBlock prefix: keep the part that says where */
        std::string m = gdal_message(path);
        const size_t at = m.find("at column");
        if (at != std::string::npos)
            m = m.substr(at);
        while (!m.empty() && std::isspace(static_cast<unsigned char>(m.back())))
            m.pop_back();
        set_error(err,
                  "%s: DTED checksum mismatch, the elevations are corrupt (%s); set "
                  "DTED_VERIFY_CHECKSUM=NO to read them anyway",
                  path, m.c_str());
        return TP_ERR_BAD_DATA;
    }
    if (io != CE_None || last == CE_Failure || last == CE_Fatal) {
        set_error(err,
                  "%s: reading the heights of band 1 failed, the file is truncated or "
                  "corrupt (%s)",
                  path, gdal_message(path).c_str());
        return TP_ERR_BAD_DATA;
    }
    return TP_OK;
}

/* Everything that is not a height made NaN, heights made metres (r.zu), the nodata tag, void
 * count and range into dem; the samples taken as nodata counted in r. */
tp_status mask_voids(DemRead& r, tp_dem* dem, tp_error* err)
{
    const char* path = r.path;
    const size_t count = (size_t)r.w * (size_t)r.h;
    GDALRasterBand* band = r.band;
    const GDALDataType type = band->GetRasterDataType();
    const tpio::ZUnit& zu = r.zu;
    DemRead& c = r;
    int has_nodata = 0;
    const double nodata = band->GetNoDataValue(&has_nodata);
    dem->has_nodata = has_nodata ? 1 : 0;
    dem->nodata_value = has_nodata ? nodata : 0.0;

    /* Everything that is not a height becomes NaN: the tag, NaN, +-inf, and for untagged Int16
     * the two values SRTM (-32768) and DTED (-32767) use for voids. +-FLT_MAX counts as
     * infinite: it is what GDAL stores for an infinity read from text (an ESRI ASCII grid's
     * "inf") and the float nodata of ArcGIS, never a height. */
    const float nd = nodata_as_float(nodata);
    const bool nd_is_nan = has_nodata && std::isnan(nodata);
    const bool int16_guess = !has_nodata && type == GDT_Int16;
    const float nan = std::nanf("");
    size_t& guessed_32768 = c.guessed_32768;
    size_t& guessed_32767 = c.guessed_32767;
    size_t& infinite = c.infinite;
    size_t tagged = 0, nans = 0, voids = 0;
    float lo = 0.0f, hi = 0.0f;
    for (size_t i = 0; i < count; ++i) {
        float v = dem->heights[i];
        if (has_nodata && (v == nd || (nd_is_nan && std::isnan(v)))) {
            ++tagged;
            v = nan;
        } else if (int16_guess && (v == -32768.0f || v == -32767.0f)) {
            if (v == -32768.0f)
                ++guessed_32768;
            else
                ++guessed_32767;
            v = nan;
        } else if (std::isnan(v)) {
            ++nans;
        } else if (std::isinf(v) || v == FLT_MAX || v == -FLT_MAX) {
            ++infinite;
            v = nan;
        }
        if (zu.to_m != 1.0)
            v = (float)(v * zu.to_m); /* NaN stays NaN */
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
        std::string why;
        char part[96];
        const auto add = [&](size_t n, const char* what) {
            if (!n)
                return;
            std::snprintf(part, sizeof part, "%s%zu %s", why.empty() ? "" : ", ", n, what);
            why += part;
        };
        add(tagged, "equal to the nodata tag");
        add(guessed_32768 + guessed_32767, "untagged Int16 voids (-32768/-32767)");
        add(nans, "NaN");
        add(infinite, "infinite (+-Inf or +-FLT_MAX)");
        set_error(err, "%s: no valid height in band 1: all %zu samples are nodata (%s)", path,
                  count, why.c_str());
        return TP_ERR_BAD_DATA;
    }
    dem->void_count = voids;
    dem->min_m = lo;
    dem->max_m = hi;
    return TP_OK;
}

/* The warnings for the user ('\n'-separated): nodata guessed, infinite samples, the height
 * unit, a .prj GDAL cannot read, no georeference at all. */
std::string dem_warnings(const DemRead& r)
{
    const char* path = r.path;
    const size_t guessed_32768 = r.guessed_32768, guessed_32767 = r.guessed_32767;
    const size_t infinite = r.infinite;
    const tpio::ZUnit& zu = r.zu;
    const OGRSpatialReference* srs = r.srs;
    const bool has_gt = r.has_gt;
    GDALDataset* ds = r.ds.get();
    std::string warnings;
    char line[1024];
    if (guessed_32768 || guessed_32767) {
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
    if (infinite) {
        std::snprintf(line, sizeof line,
                      "%s: %zu infinite samples (+-Inf or +-FLT_MAX) taken as nodata", path,
                      infinite);
        if (!warnings.empty())
            warnings += '\n';
        warnings += line;
    }
    if (!zu.warning.empty()) {
        if (!warnings.empty())
            warnings += '\n';
        warnings += std::string(path) + ": " + zu.warning;
    }
    const bool has_crs = tpio::crs_present(srs);
    if (!has_crs) {
        const std::string prj = prj_of(*ds);
        if (!prj.empty()) {
            std::snprintf(line, sizeof line,
                          "%s: %s could not be read as a CRS (GDAL/PROJ do not understand its "
                          "text): the DEM is read without a CRS",
                          path, prj.c_str());
            if (!warnings.empty())
                warnings += '\n';
            warnings += line;
        }
    }
    if (!has_crs && !has_gt) {
        std::snprintf(line, sizeof line,
                      "%s: no CRS and no geotransform: posts taken as 1 m apart in local "
                      "metres, north-west corner at (0, 0)",
                      path);
        if (!warnings.empty())
            warnings += '\n';
        warnings += line;
    }
    return warnings;
}

tp_status read_dem(const char* path, const char* z_unit, tp_dem** out, tp_error* err)
{
    register_drivers();
    QuietGdal quiet;
    DemRead r;
    r.path = path;
    VerifyDtedChecksums verify; /* from the open to the end of the read */
    if (const tp_status s = open_raster(r, err))
        return s;
    const int w = r.w, h = r.h;
    GDALDataset* ds = r.ds.get();
    GDALRasterBand* band = r.band;
    if (const tp_status s = check_georeference(r, err))
        return s;
    const double* gt = r.gt;
    const bool has_gt = r.has_gt;

    /* The heights are read whole as 32-bit floats: refuse a size this machine cannot hold
     * before asking for it. */
    if (const tp_status s =
            tpio::check_fits_in_memory(path, w, h, sizeof(float), "for the heights", err))
        return s;
    const size_t count = static_cast<size_t>(w) * static_cast<size_t>(h);
    const double need = static_cast<double>(w) * static_cast<double>(h) * sizeof(float);

    if (const tp_status s = check_block_size(r, need, err))
        return s;

    const char* driver = r.driver = ds->GetDriver() ? ds->GetDriver()->GetDescription() : "";
    if (EQUAL(driver, "AAIGrid")) {
        const tp_status s = check_ascii_grid(path, w, h, err);
        if (s != TP_OK)
            return s;
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
        set_error(err, "%s: out of memory: %dx%d samples need %.1f GiB for the heights", path, w, h,
                  gib(need));
        return TP_ERR_OUT_OF_MEMORY;
    }

    if (const tp_status s = read_heights(r, dem.get(), err))
        return s;

    const GDALDataType type = band->GetRasterDataType();
    copy_name(dem->driver, sizeof dem->driver,
              ds->GetDriver() ? ds->GetDriver()->GetDescription() : "");
    copy_name(dem->data_type, sizeof dem->data_type, GDALGetDataTypeName(type));
    dem->is_integer_type = GDALDataTypeIsInteger(type) ? 1 : 0;
    copy_name(dem->units, sizeof dem->units, band->GetUnitType());
    copy_name(dem->vertical_datum, sizeof dem->vertical_datum,
              tpio::vertical_datum_of(ds).c_str());
    tpio::ZUnit& zu = r.zu;
    if (const tp_status s = tpio::z_unit_of(ds, z_unit, &zu, err))
        return s;
    dem->z_to_m = zu.to_m;
    copy_name(dem->z_unit, sizeof dem->z_unit, zu.name.c_str());
    copy_name(dem->z_unit_from, sizeof dem->z_unit_from, zu.from.c_str());

    if (const tp_status s = mask_voids(r, dem.get(), err))
        return s;
    dem->warnings = dup_c(dem_warnings(r));

    dem->has_geotransform = has_gt ? 1 : 0;
    std::memcpy(dem->geotransform, gt, sizeof dem->geotransform);

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
    return tp_dem_read_z(path, nullptr, out, err);
}

extern "C" tp_status tp_dem_read_z(const char* path, const char* z_unit, tp_dem** out,
                                   tp_error* err)
{
    if (!path || !*path || !out) {
        set_error(err, "tp_dem_read: expected a file name and an output pointer, got %s",
                  !path    ? "a NULL path"
                  : !*path ? "an empty path"
                           : "a NULL output pointer");
        return TP_ERR_INVALID_ARG;
    }
    try {
        return read_dem(path, z_unit, out, err);
    } catch (...) {
        return tpio::caught(err, path);
    }
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

/* Declared in io_util.hpp; the one check of a raster's size against memory (tp_dem_read here,
 * heightmap images in image_read.cpp). */
tp_status tpio::check_fits_in_memory(const char* path, int w, int h, double bytes_per_sample,
                                     const char* what, tp_error* err)
{
    const double need = static_cast<double>(w) * static_cast<double>(h) * bytes_per_sample;
    const uint64_t have = usable_memory_bytes();
    if (need < static_cast<double>(SIZE_MAX) && (!have || need <= static_cast<double>(have)))
        return TP_OK;
    if (have)
        set_error(err,
                  "%s: %dx%d samples would need %.1f GiB %s (%g bytes each), more than the "
                  "%.1f GiB of memory this machine has",
                  path, w, h, gib(need), what, bytes_per_sample, gib(static_cast<double>(have)));
    else
        set_error(err,
                  "%s: %dx%d samples would need %.1f GiB %s, more than this machine can "
                  "address",
                  path, w, h, gib(need), what);
    return TP_ERR_OUT_OF_MEMORY;
}
