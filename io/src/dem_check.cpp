/* dem_check.cpp - the checks of a DEM as GDAL read it (see dem_check.hpp). */
#include "dem_check.hpp"

#include "crs.hpp"
#include "gdal_util.hpp"

#include <cpl_conv.h>
#include <cpl_string.h>
#include <cpl_vsi.h>
#include <ogr_spatialref.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace tpio {

/* The geotransform the core can use: finite, north-up or south-up, not rotated, non-zero pixel
 * size, columns running east (a negative pixel width comes from a negative cell size in a
 * header, e.g. an ESRI ASCII grid's "cellsize -10"; no DEM format writes east-to-west
 * columns). Rows may run either way: gt[5] < 0 is the usual north-up, gt[5] > 0 a bottom-up
 * grid, which the core handles as it is. */
tp_status check_geotransform(const char* path, const double gt[6], tp_error* err)
{
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(gt[i])) {
            set_error(err, "%s: geotransform is not finite (gt[%d]=%g)", path, i, gt[i]);
            return TP_ERR_BAD_DATA;
        }
    if (gt[2] != 0.0 || gt[4] != 0.0) {
        set_error(err, "%s: rotated geotransform (gt[2]=%.17g, gt[4]=%.17g) is not supported", path,
                  gt[2], gt[4]);
        return TP_ERR_BAD_DATA;
    }
    if (gt[1] == 0.0 || gt[5] == 0.0) {
        set_error(err, "%s: pixel size must be non-zero, got %.17g x %.17g (gt[1] x gt[5])", path,
                  gt[1], gt[5]);
        return TP_ERR_BAD_DATA;
    }
    if (gt[1] < 0.0) {
        set_error(err,
                  "%s: pixel width must be positive (columns running east), got gt[1]=%.17g "
                  "(a negative cell size?)",
                  path, gt[1]);
        return TP_ERR_BAD_DATA;
    }
    return TP_OK;
}

/* A geographic raster's sample centres must lie within +-90 degrees of latitude. The outer
 * edge may pass the pole by half a pixel: grid-registered global grids (ETOPO1, GEBCO) have
 * their first and last rows of posts on the poles. GDAL gives datasets in GIS axis order, so
 * rows (gt[3], gt[5]) are latitude. */
tp_status check_latitude(const char* path, const OGRSpatialReference& srs, const double gt[6],
                         int h, tp_error* err)
{
    if (!srs.IsGeographic())
        return TP_OK;
    const double pi = 3.14159265358979323846;
    double to_deg = srs.GetAngularUnits(nullptr) * 180.0 / pi; /* 1 for degrees */
    if (!(to_deg > 0.0) || !std::isfinite(to_deg))
        to_deg = 1.0;
    const double first = (gt[3] + 0.5 * gt[5]) * to_deg;
    const double last = (gt[3] + (h - 0.5) * gt[5]) * to_deg;
    const double north = std::max(first, last), south = std::min(first, last);
    const double eps = 1e-9; /* degrees: rounding in the file's decimal origin */
    if (north > 90.0 + eps || south < -90.0 - eps) {
        const char* name = srs.GetName();
        set_error(err,
                  "%s: rows reach latitude %.10g%s, beyond %s90 in a geographic CRS (%s); "
                  "expected sample centres from -90 to 90",
                  path, north > 90.0 + eps ? north : south,
                  north > 90.0 + eps && south < -90.0 - eps ? " and beyond both poles" : "",
                  north > 90.0 + eps ? "+" : "-", name && *name ? name : "unnamed");
        return TP_ERR_BAD_DATA;
    }
    return TP_OK;
}

/* The georeference within the ranges tp_io.h gives (TP_PIXEL_SIZE_*, TP_COORD_MAX_M,
 * TP_LON_MAX_DEG): a pixel of 1e-300 m or a corner at 1e300 m is damage, not a place, and
 * would go on to print 300-digit extents or overflow the render grid. */
tp_status check_ranges(const char* path, const OGRSpatialReference* srs, const double gt[6],
                       int w, int h, tp_error* err)
{
    const bool has = tpio::crs_present(srs);
    const bool geographic = has && srs->IsGeographic();
    double unit = 1.0; /* metres, or degrees, per CRS unit */
    const char* name = "m";
    double lo = TP_PIXEL_SIZE_MIN_M, hi = TP_PIXEL_SIZE_MAX_M;
    if (geographic) {
        unit = srs->GetAngularUnits(nullptr) * 180.0 / 3.14159265358979323846;
        name = "degrees";
        lo = TP_PIXEL_SIZE_MIN_DEG;
        hi = TP_PIXEL_SIZE_MAX_DEG;
    } else if (has) {
        unit = srs->GetLinearUnits(nullptr);
    } else {
        name = "(no CRS: degrees or metres)";
        lo = TP_PIXEL_SIZE_MIN_DEG;
    }
    if (!(unit > 0.0) || !std::isfinite(unit))
        unit = 1.0;
    const double px[2] = {std::fabs(gt[1]) * unit, std::fabs(gt[5]) * unit};
    for (int i = 0; i < 2; ++i)
        if (!(px[i] >= lo && px[i] <= hi)) {
            set_error(err, "%s: pixel %s %.6g%s%s (gt[%d]) is outside %g .. %g %s", path,
                      i ? "height" : "width", px[i], has ? " " : "", has ? name : "", i ? 5 : 1,
                      lo, hi, name);
            return TP_ERR_BAD_DATA;
        }
    const double xs[2] = {gt[0] * unit, (gt[0] + w * gt[1]) * unit};
    const double ys[2] = {gt[3] * unit, (gt[3] + h * gt[5]) * unit};
    for (int i = 0; i < 2; ++i) {
        if (geographic) {
            if (!(std::fabs(xs[i]) <= TP_LON_MAX_DEG)) {
                set_error(err, "%s: %s edge at longitude %.6g is outside -%g .. %g degrees", path,
                          i ? "east" : "west", xs[i], TP_LON_MAX_DEG, TP_LON_MAX_DEG);
                return TP_ERR_BAD_DATA;
            }
            /* a grid over the whole Earth may repeat its first column at the end */
            if (i == 1 && !(std::fabs(xs[1] - xs[0]) <= 360.0 + px[0] + 1e-9)) {
                set_error(err,
                          "%s: spans %.6g degrees of longitude (west edge %.6g, east edge %.6g), "
                          "more than the Earth's 360 and one wrap-around column",
                          path, std::fabs(xs[1] - xs[0]), xs[0], xs[1]);
                return TP_ERR_BAD_DATA;
            }
            continue; /* latitudes: check_latitude */
        }
        for (int axis = 0; axis < 2; ++axis) {
            const double v = axis ? ys[i] : xs[i];
            if (!(std::fabs(v) <= TP_COORD_MAX_M)) {
                set_error(err,
                          "%s: %s edge at %s = %.6g%s is outside -%g .. %g %s (more than twice "
                          "the Earth's circumference from the origin)",
                          path, axis ? (i ? "last row's" : "first row's") : (i ? "east" : "west"),
                          axis ? "y" : "x", v, has ? " m" : "", TP_COORD_MAX_M, TP_COORD_MAX_M,
                          has ? "m" : "(no CRS: degrees or metres)");
                return TP_ERR_BAD_DATA;
            }
        }
    }
    return TP_OK;
}

/* GDAL's AAIGrid driver is lenient: it reads "307x" as 307, and ignores values past nrows x
 * ncols (164 rows under "nrows 144"), so damaged text would be drawn without a word. One pass
 * over the text: after the header (known keys and their values, one or more to a line, as
 * GDAL takes them), every token must be a number in C syntax (strtod: decimals, signs,
 * exponents), a number with a decimal comma ("1,5", which GDAL reads as 1.5) or "null" (GDAL's
 * nodata token), and there must be exactly w x h of them. The message names the line of the
 * first bad token, or where the extra values start. */
tp_status check_ascii_grid(const char* path, int w, int h, tp_error* err)
{
    static const char* const keys[] = {"ncols",     "nrows",     "xllcorner", "yllcorner",
                                       "xllcenter", "yllcenter", "cellsize",  "dx",
                                       "dy",        "nodata_value", "nodata"};
    VSILFILE* f = VSIFOpenL(path, "rb");
    if (!f) {
        set_error(err, "%s: cannot open: %s", path, std::strerror(errno ? errno : EIO));
        return TP_ERR_IO;
    }
    std::unique_ptr<VSILFILE, int (*)(VSILFILE*)> closer(f, &VSIFCloseL);
    const uint64_t expected = static_cast<uint64_t>(w) * static_cast<uint64_t>(h);
    uint64_t values = 0, line = 1, extra_line = 0, last_value_line = 0;
    bool header = true, skip_value = false;
    std::string token;
    uint64_t token_line = 1;
    std::vector<char> buf(1 << 20);
    tp_status status = TP_OK;
    const auto finish_token = [&]() -> bool {
        if (token.empty())
            return true;
        if (header) {
            if (skip_value) {
                skip_value = false;
                token.clear();
                return true;
            }
            std::string lower = token;
            for (char& c : lower)
                c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
            for (const char* k : keys)
                if (lower == k) {
                    skip_value = true;
                    token.clear();
                    return true;
                }
            header = false;
        }
        /* GDAL reads values with CPLAtofM, which takes a decimal comma too ("1,5" is 1.5), and
         * "null" as nodata: both are values, not damage. */
        std::string number = token;
        std::replace(number.begin(), number.end(), ',', '.');
        char* end = nullptr;
        std::strtod(number.c_str(), &end);
        if (token != "null" && (end == number.c_str() || *end != '\0')) {
            std::string shown; /* bytes that do not print, as \xNN: the message stays readable */
            for (const char ch : token.substr(0, 40)) {
                if (std::isprint(static_cast<unsigned char>(ch)))
                    shown += ch;
                else
                    shown += CPLSPrintf("\\x%02x", static_cast<unsigned char>(ch));
            }
            set_error(err, "%s: line %llu: '%s' is not a number", path,
                      static_cast<unsigned long long>(token_line), shown.c_str());
            status = TP_ERR_BAD_DATA;
            return false;
        }
        if (++values == expected + 1)
            extra_line = token_line;
        last_value_line = token_line;
        token.clear();
        return true;
    };
    for (;;) {
        const size_t got = VSIFReadL(buf.data(), 1, buf.size(), f);
        for (size_t i = 0; i < got; ++i) {
            const char c = buf[i];
            /* 0x1a: the DOS end-of-file mark some old exporters put after the last row */
            if (c == ' ' || c == '\t' || c == '\r' || c == '\n' || c == '\f' || c == '\v' ||
                c == '\x1a') {
                if (!finish_token())
                    return status;
                if (c == '\n')
                    ++line;
            } else {
                if (token.empty())
                    token_line = line;
                if (token.size() < 512) /* longer than GDAL's own limit: still not a number */
                    token += c;
            }
        }
        if (got < buf.size())
            break;
    }
    if (!finish_token())
        return status;
    if (values > expected) {
        const uint64_t more = values - expected;
        char rows[64] = "";
        if (more % static_cast<uint64_t>(w) == 0)
            std::snprintf(rows, sizeof rows, " (%llu extra rows)",
                          static_cast<unsigned long long>(more / w));
        set_error(err,
                  "%s: %llu values where the header's nrows %d x ncols %d asks for %llu%s: the "
                  "extra values start on line %llu",
                  path, static_cast<unsigned long long>(values), h, w,
                  static_cast<unsigned long long>(expected), rows,
                  static_cast<unsigned long long>(extra_line));
        return TP_ERR_BAD_DATA;
    }
    if (values < expected) {
        set_error(err,
                  "%s: only %llu values where the header's nrows %d x ncols %d asks for %llu: "
                  "the last one is on line %llu",
                  path, static_cast<unsigned long long>(values), h, w,
                  static_cast<unsigned long long>(expected),
                  static_cast<unsigned long long>(last_value_line));
        return TP_ERR_BAD_DATA;
    }
    return TP_OK;
}

} // namespace tpio
