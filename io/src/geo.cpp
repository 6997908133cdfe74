/*
 * geo.cpp - tp_geo.h over GeographicLib: UTM/UPS, MGRS, geocentric, exact transverse Mercator
 * and inverse geodesics on WGS84.
 *
 * This work is based on:
 *  - C. F. F. Karney, "Transverse Mercator with an accuracy of a few nanometers",
 *    J. Geodesy 85(8), 475-485 (2011): the Krueger series behind UTMUPS, and the exact
 *    projection (TransverseMercatorExact) after L. P. Lee, "Conformal projections based on
 *    elliptic functions", Cartographica 13, monograph 16 (1976).
 *  - C. F. F. Karney, "Algorithms for geodesics", J. Geodesy 87(1), 43-55 (2013) (Geodesic).
 *  - H. Vermeille, "An analytical method to transform geocentric into geodetic coordinates",
 *    J. Geodesy 85, 105-117 (2011) (Geocentric::Reverse).
 * No projection is written here: each function checks its arguments (so that the user gets
 * "latitude 91 is outside [-90, 90]" rather than a NaN or a crash), calls GeographicLib, and
 * copies the results out only on success.
 *
 * Every exported function runs its body inside try { } catch (...) { return failed(...); }:
 * failed() rethrows the exception to sort it (GeographicErr -> TP_ERR_INVALID_ARG,
 * std::bad_alloc -> TP_ERR_OUT_OF_MEMORY, any other exception -> TP_ERR_BACKEND), so no C++
 * exception leaves this file.
 */
#include "io_util.hpp"
#include "tp_geo.h"

#include <GeographicLib/Constants.hpp>
#include <GeographicLib/Geocentric.hpp>
#include <GeographicLib/Geodesic.hpp>
#include <GeographicLib/MGRS.hpp>
#include <GeographicLib/Math.hpp>
#include <GeographicLib/TransverseMercatorExact.hpp>
#include <GeographicLib/UTMUPS.hpp>

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <string>

namespace {

using GeographicLib::GeographicErr;

/* Longitudes accepted at the API (see tp_geo.h). */
constexpr double kMaxLonDeg = 540.0;

/* The longest MGRS string worth reading (the longest legal one has 27 characters; leading
 * zeros and the like are left to GeographicLib, but a whole paragraph is not). */
constexpr size_t kMaxMgrsInput = 64;

using tpio::set_error;

/* The shortest decimal text that reads back as v: "91", "1100000", "90.000000000000014",
 * "1e-20", "nan". Used in messages, so that an out-of-range value is shown as the user wrote
 * it, not rounded to something that looks in range. */
struct Num {
    char text[48];
    explicit Num(double v)
    {
        if (!std::isfinite(v)) {
            std::snprintf(text, sizeof text, "%s", std::isnan(v) ? "nan" : v > 0 ? "inf" : "-inf");
            return;
        }
        if (std::fabs(v) < 1e15) { /* plain decimals when they are short enough */
            for (int decimals = 0; decimals <= 17; ++decimals) {
                std::snprintf(text, sizeof text, "%.*f", decimals, v);
                if (std::strtod(text, nullptr) == v)
                    return;
            }
        }
        for (int digits = 1; digits <= 17; ++digits) {
            std::snprintf(text, sizeof text, "%.*g", digits, v);
            if (std::strtod(text, nullptr) == v)
                return;
        }
    }
};

/* Checks one angle; name is "latitude", "lat1", ... */
bool check_lat(const char* name, double lat_deg, tp_error* err)
{
    if (!std::isfinite(lat_deg)) {
        set_error(err, "%s %s is not a finite number", name, Num(lat_deg).text);
        return false;
    }
    if (!(lat_deg >= -90.0 && lat_deg <= 90.0)) {
        set_error(err, "%s %s is outside [-90, 90]", name, Num(lat_deg).text);
        return false;
    }
    return true;
}

bool check_lon(const char* name, double lon_deg, tp_error* err)
{
    if (!std::isfinite(lon_deg)) {
        set_error(err, "%s %s is not a finite number", name, Num(lon_deg).text);
        return false;
    }
    if (!(lon_deg >= -kMaxLonDeg && lon_deg <= kMaxLonDeg)) {
        set_error(err, "%s %s is outside [-540, 540]", name, Num(lon_deg).text);
        return false;
    }
    return true;
}

bool check_finite(const char* name, double v, tp_error* err)
{
    if (!std::isfinite(v)) {
        set_error(err, "%s %s is not a finite number", name, Num(v).text);
        return false;
    }
    return true;
}

bool check_zone(int zone, tp_error* err)
{
    if (zone < GeographicLib::UTMUPS::UPS || zone > GeographicLib::UTMUPS::MAXUTMZONE) {
        set_error(err, "zone %d is outside [1, 60] (or 0 for UPS)", zone);
        return false;
    }
    return true;
}

/* "33n", "01s", "n" (UPS), as GeoConvert writes zones; for messages, so "?" if out of range. */
std::string zone_text(int zone, int northp)
{
    char buf[TP_ZONE_TEXT_SIZE];
    if (tp_zone_format(zone, northp, TP_ZONE_STYLE_GEOCONVERT, buf, sizeof buf, nullptr) != TP_OK)
        return "?";
    return buf;
}

/* Must be called inside a catch handler: sorts the exception in flight into a status and a
 * message starting with `what` (the function or the input it was working on). */
tp_status failed(tp_error* err, const std::string& what)
{
    try {
        throw;
    } catch (const GeographicErr& e) {
        set_error(err, "%s: %s", what.c_str(), e.what());
        return TP_ERR_INVALID_ARG;
    } catch (const std::bad_alloc&) {
        set_error(err, "%s: out of memory", what.c_str());
        return TP_ERR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        set_error(err, "%s: GeographicLib/C++ failure (%s)", what.c_str(), e.what());
        return TP_ERR_BACKEND;
    } catch (...) {
        set_error(err, "%s: GeographicLib/C++ failure (unknown exception)", what.c_str());
        return TP_ERR_BACKEND;
    }
}

tp_status missing_output(tp_error* err, const char* function)
{
    set_error(err, "%s: expected non-NULL output pointers, got NULL", function);
    return TP_ERR_INVALID_ARG;
}

/* The exact transverse Mercator for one k0 on WGS84. UTM's k0 has a ready-made global
 * instance; other scales build one per call (an elliptic-integral set-up, microseconds). */
template <typename F> void with_exact_tm(double k0, F&& f)
{
    if (k0 == GeographicLib::Constants::UTM_k0()) {
        f(GeographicLib::TransverseMercatorExact::UTM());
    } else {
        const GeographicLib::TransverseMercatorExact tm(GeographicLib::Constants::WGS84_a(),
                                                        GeographicLib::Constants::WGS84_f(), k0);
        f(tm);
    }
}

bool check_k0(double k0, tp_error* err)
{
    if (!std::isfinite(k0) || !(k0 > 0.0)) {
        set_error(err, "scale factor k0 %s is not a positive finite number", Num(k0).text);
        return false;
    }
    return true;
}

} // namespace

extern "C" tp_status tp_geo_normalize(double lat_deg, double lon_deg, double* lat_out_deg,
                                      double* lon_out_deg, tp_error* err)
{
    if (!lat_out_deg || !lon_out_deg)
        return missing_output(err, "tp_geo_normalize");
    if (!check_lat("latitude", lat_deg, err) || !check_lon("longitude", lon_deg, err))
        return TP_ERR_INVALID_ARG;
    try {
        double lon = GeographicLib::Math::AngNormalize(lon_deg);
        *lat_out_deg = lat_deg;
        *lon_out_deg = lon;
        return TP_OK;
    } catch (...) {
        return failed(err, "tp_geo_normalize");
    }
}

extern "C" tp_status tp_geo_to_utmups(double lat_deg, double lon_deg, int* zone, int* northp,
                                      double* easting_m, double* northing_m, tp_error* err)
{
    if (!zone || !northp || !easting_m || !northing_m)
        return missing_output(err, "tp_geo_to_utmups");
    if (!check_lat("latitude", lat_deg, err) || !check_lon("longitude", lon_deg, err))
        return TP_ERR_INVALID_ARG;
    try {
        int z;
        bool north;
        double x, y;
        GeographicLib::UTMUPS::Forward(lat_deg, lon_deg, z, north, x, y);
        *zone = z;
        *northp = north ? 1 : 0;
        *easting_m = x;
        *northing_m = y;
        return TP_OK;
    } catch (...) {
        return failed(err, "latitude " + std::string(Num(lat_deg).text) + " longitude " +
                               Num(lon_deg).text);
    }
}

extern "C" tp_status tp_geo_from_utmups(int zone, int northp, double easting_m, double northing_m,
                                        double* lat_deg, double* lon_deg, tp_error* err)
{
    if (!lat_deg || !lon_deg)
        return missing_output(err, "tp_geo_from_utmups");
    if (!check_zone(zone, err) || !check_finite("easting", easting_m, err) ||
        !check_finite("northing", northing_m, err))
        return TP_ERR_INVALID_ARG;
    try {
        double lat, lon;
        GeographicLib::UTMUPS::Reverse(zone, northp != 0, easting_m, northing_m, lat, lon);
        *lat_deg = lat;
        *lon_deg = lon;
        return TP_OK;
    } catch (...) {
        return failed(err, (zone == TP_ZONE_UPS ? "UPS " : "UTM ") + zone_text(zone, northp) + " " +
                               Num(easting_m).text + " " + Num(northing_m).text);
    }
}

extern "C" tp_status tp_utmups_to_standard(int zone, int northp, double easting_m,
                                           double northing_m, int* std_zone, int* std_northp,
                                           double* std_easting_m, double* std_northing_m,
                                           tp_error* err)
{
    if (!std_zone || !std_northp || !std_easting_m || !std_northing_m)
        return missing_output(err, "tp_utmups_to_standard");
    try { /* the two conversions catch everything themselves; this is for what comes later */
        double lat, lon, e, n;
        int z, north;
        tp_status s = tp_geo_from_utmups(zone, northp, easting_m, northing_m, &lat, &lon, err);
        if (s == TP_OK)
            s = tp_geo_to_utmups(lat, lon, &z, &north, &e, &n, err);
        if (s != TP_OK)
            return s;
        /* tp_geo_to_utmups puts latitude +0 north; the equator belongs to both hemispheres */
        if (z == zone && (north == (northp != 0) || lat == 0)) {
            north = northp != 0;
            e = easting_m;
            n = northing_m;
        }
        *std_zone = z;
        *std_northp = north;
        *std_easting_m = e;
        *std_northing_m = n;
        return TP_OK;
    } catch (...) {
        return failed(err, "tp_utmups_to_standard");
    }
}

extern "C" tp_status tp_mgrs_forward(int zone, int northp, double easting_m, double northing_m,
                                     double lat_deg, int precision, char* out, size_t out_size,
                                     tp_error* err)
{
    if (!out)
        return missing_output(err, "tp_mgrs_forward");
    if (precision < -1 || precision > 11) {
        set_error(err, "MGRS precision %d is outside [-1, 11]", precision);
        return TP_ERR_INVALID_ARG;
    }
    if (!check_zone(zone, err) || !check_finite("easting", easting_m, err) ||
        !check_finite("northing", northing_m, err))
        return TP_ERR_INVALID_ARG;
    if (!std::isnan(lat_deg) && !check_lat("latitude", lat_deg, err))
        return TP_ERR_INVALID_ARG;
    try {
        std::string mgrs;
        if (std::isnan(lat_deg))
            GeographicLib::MGRS::Forward(zone, northp != 0, easting_m, northing_m, precision, mgrs);
        else
            GeographicLib::MGRS::Forward(zone, northp != 0, easting_m, northing_m, lat_deg,
                                         precision, mgrs);
        if (mgrs.size() + 1 > out_size) {
            set_error(err, "MGRS %s needs %zu bytes, the buffer has %zu", mgrs.c_str(),
                      mgrs.size() + 1, out_size);
            return TP_ERR_INVALID_ARG;
        }
        std::memcpy(out, mgrs.c_str(), mgrs.size() + 1);
        return TP_OK;
    } catch (...) {
        return failed(err, "MGRS of " + zone_text(zone, northp) + " " + Num(easting_m).text + " " +
                               Num(northing_m).text);
    }
}

extern "C" tp_status tp_mgrs_reverse(const char* mgrs, int centerp, int* zone, int* northp,
                                     double* easting_m, double* northing_m, int* precision,
                                     tp_error* err)
{
    if (!mgrs) {
        set_error(err, "tp_mgrs_reverse: expected an MGRS string, got NULL");
        return TP_ERR_INVALID_ARG;
    }
    if (!zone || !northp || !easting_m || !northing_m)
        return missing_output(err, "tp_mgrs_reverse");
    size_t len = std::strlen(mgrs);
    if (len == 0) {
        set_error(err, "expected an MGRS reference, got an empty string");
        return TP_ERR_INVALID_ARG;
    }
    if (len > kMaxMgrsInput) {
        set_error(err, "MGRS reference of %zu characters is too long (at most 27)", len);
        return TP_ERR_INVALID_ARG;
    }
    /* The zone is at most 2 digits. GeographicLib (2.1.2, MGRS::Reverse) reads every leading
     * digit into an int before it checks their count, so that 10 or more of them overflow it
     * (undefined behaviour, found by tests/fuzz/fuzz_coord_line: "110087268780A"). */
    size_t zone_digits = 0;
    while (mgrs[zone_digits] >= '0' && mgrs[zone_digits] <= '9')
        ++zone_digits;
    if (zone_digits > 2) {
        set_error(err, "MGRS %s: expected a zone of 1 or 2 digits (1..60), got %zu digits", mgrs,
                  zone_digits);
        return TP_ERR_INVALID_ARG;
    }
    try {
        int z, prec;
        bool north;
        double x, y;
        GeographicLib::MGRS::Reverse(mgrs, z, north, x, y, prec, centerp != 0);
        /* "INV..." is GeographicLib's placeholder for a NaN position; it decodes to zone
         * INVALID and NaN coordinates instead of failing. */
        if (z < GeographicLib::UTMUPS::UPS || !std::isfinite(x) || !std::isfinite(y)) {
            set_error(err, "MGRS %s: not a grid reference (GeographicLib's INVALID marker)", mgrs);
            return TP_ERR_INVALID_ARG;
        }
        *zone = z;
        *northp = north ? 1 : 0;
        *easting_m = x;
        *northing_m = y;
        if (precision)
            *precision = prec;
        return TP_OK;
    } catch (...) {
        return failed(err, "MGRS " + std::string(mgrs));
    }
}

extern "C" tp_status tp_geo_to_ecef(double lat_deg, double lon_deg, double h_m, double* x_m,
                                    double* y_m, double* z_m, tp_error* err)
{
    if (!x_m || !y_m || !z_m)
        return missing_output(err, "tp_geo_to_ecef");
    if (!check_lat("latitude", lat_deg, err) || !check_lon("longitude", lon_deg, err) ||
        !check_finite("height", h_m, err))
        return TP_ERR_INVALID_ARG;
    try {
        double x, y, z;
        GeographicLib::Geocentric::WGS84().Forward(lat_deg, lon_deg, h_m, x, y, z);
        *x_m = x;
        *y_m = y;
        *z_m = z;
        return TP_OK;
    } catch (...) {
        return failed(err, "tp_geo_to_ecef");
    }
}

extern "C" tp_status tp_geo_from_ecef(double x_m, double y_m, double z_m, double* lat_deg,
                                      double* lon_deg, double* h_m, tp_error* err)
{
    if (!lat_deg || !lon_deg || !h_m)
        return missing_output(err, "tp_geo_from_ecef");
    if (!check_finite("X", x_m, err) || !check_finite("Y", y_m, err) ||
        !check_finite("Z", z_m, err))
        return TP_ERR_INVALID_ARG;
    try {
        double lat, lon, h;
        GeographicLib::Geocentric::WGS84().Reverse(x_m, y_m, z_m, lat, lon, h);
        *lat_deg = lat;
        *lon_deg = lon;
        *h_m = h;
        return TP_OK;
    } catch (...) {
        return failed(err, "tp_geo_from_ecef");
    }
}

extern "C" tp_status tp_tm_forward(double lon0_deg, double k0, double lat_deg, double lon_deg,
                                   double* x_m, double* y_m, double* gamma_deg, double* k,
                                   tp_error* err)
{
    if (!x_m || !y_m)
        return missing_output(err, "tp_tm_forward");
    if (!check_lon("central meridian", lon0_deg, err) || !check_k0(k0, err) ||
        !check_lat("latitude", lat_deg, err) || !check_lon("longitude", lon_deg, err))
        return TP_ERR_INVALID_ARG;
    try {
        double x, y, g, kk;
        with_exact_tm(k0, [&](const GeographicLib::TransverseMercatorExact& tm) {
            tm.Forward(lon0_deg, lat_deg, lon_deg, x, y, g, kk);
        });
        *x_m = x;
        *y_m = y;
        if (gamma_deg)
            *gamma_deg = g;
        if (k)
            *k = kk;
        return TP_OK;
    } catch (...) {
        return failed(err, "tp_tm_forward");
    }
}

extern "C" tp_status tp_tm_reverse(double lon0_deg, double k0, double x_m, double y_m,
                                   double* lat_deg, double* lon_deg, double* gamma_deg, double* k,
                                   tp_error* err)
{
    if (!lat_deg || !lon_deg)
        return missing_output(err, "tp_tm_reverse");
    if (!check_lon("central meridian", lon0_deg, err) || !check_k0(k0, err) ||
        !check_finite("x", x_m, err) || !check_finite("y", y_m, err))
        return TP_ERR_INVALID_ARG;
    try {
        double lat, lon, g, kk;
        with_exact_tm(k0, [&](const GeographicLib::TransverseMercatorExact& tm) {
            tm.Reverse(lon0_deg, x_m, y_m, lat, lon, g, kk);
        });
        *lat_deg = lat;
        *lon_deg = lon;
        if (gamma_deg)
            *gamma_deg = g;
        if (k)
            *k = kk;
        return TP_OK;
    } catch (...) {
        return failed(err, "tp_tm_reverse");
    }
}

extern "C" tp_status tp_geodesic_inverse(double lat1_deg, double lon1_deg, double lat2_deg,
                                         double lon2_deg, double* azi1_deg, double* azi2_deg,
                                         double* s12_m, tp_error* err)
{
    if (!azi1_deg || !azi2_deg || !s12_m)
        return missing_output(err, "tp_geodesic_inverse");
    if (!check_lat("lat1", lat1_deg, err) || !check_lon("lon1", lon1_deg, err) ||
        !check_lat("lat2", lat2_deg, err) || !check_lon("lon2", lon2_deg, err))
        return TP_ERR_INVALID_ARG;
    try {
        double s12, azi1, azi2;
        GeographicLib::Geodesic::WGS84().Inverse(lat1_deg, lon1_deg, lat2_deg, lon2_deg, s12, azi1,
                                                 azi2);
        *azi1_deg = azi1;
        *azi2_deg = azi2;
        *s12_m = s12;
        return TP_OK;
    } catch (...) {
        return failed(err, "tp_geodesic_inverse");
    }
}

extern "C" tp_status tp_zone_format(int zone, int northp, tp_zone_style style, char* out,
                                    size_t out_size, tp_error* err)
{
    if (!out)
        return missing_output(err, "tp_zone_format");
    if (!check_zone(zone, err))
        return TP_ERR_INVALID_ARG;
    try { /* snprintf only: nothing should throw, but nothing may escape */
        /* per style: digits of a UTM zone (at least), its hemisphere letters, the UPS texts */
        struct Style {
            int digits;
            char north, south;
            const char *ups_north, *ups_south;
        };
        static const Style styles[] = {
            {1, 'n', 's', "UPS n", "UPS s"},         /* TP_ZONE_STYLE_DEFAULT */
            {1, 'n', 's', "UPS n", "UPS s"},         /* TP_ZONE_STYLE_SHORT */
            {2, 'n', 's', "n", "s"},                 /* TP_ZONE_STYLE_GEOCONVERT */
            {1, 'N', 'S', "UPS N", "UPS S"},         /* TP_ZONE_STYLE_UPPER */
            {1, 'n', 's', "UPS north", "UPS south"}, /* TP_ZONE_STYLE_LONG */
        };
        const int index = (int)style;
        if (index < 0 || (size_t)index >= sizeof styles / sizeof styles[0]) {
            set_error(err, "tp_zone_format: unknown zone style %d", index);
            return TP_ERR_INVALID_ARG;
        }
        const Style& st = styles[index];
        char text[TP_ZONE_TEXT_SIZE];
        if (zone == TP_ZONE_UPS)
            std::snprintf(text, sizeof text, "%s", northp ? st.ups_north : st.ups_south);
        else
            std::snprintf(text, sizeof text, "%0*d%c", st.digits, zone,
                          northp ? st.north : st.south);
        size_t need = std::strlen(text) + 1;
        if (need > out_size) {
            set_error(err, "zone %s needs %zu bytes, the buffer has %zu", text, need, out_size);
            return TP_ERR_INVALID_ARG;
        }
        std::memcpy(out, text, need);
        return TP_OK;
    } catch (...) {
        return failed(err, "tp_zone_format");
    }
}
