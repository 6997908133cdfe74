/*
 * dms.cpp - tp_geo.h's degrees-minutes-seconds reader and writer over GeographicLib's DMS class
 * (the rules GeoConvert reads positions by: DMS::DecodeLatLon, DMS::Encode).
 *
 * Nothing is parsed here: the strings are checked for length, handed to GeographicLib, and
 * its results checked (it returns NaN for "nan" rather than failing) and copied out only on
 * success. No C++ exception leaves this file.
 */
#include "io_util.hpp"
#include "tp_geo.h"

#include <GeographicLib/DMS.hpp>

#include <cmath>
#include <cstring>
#include <exception>
#include <new>
#include <string>

namespace {

using tpio::set_error;

/* A DMS string worth reading: "179d59'59.999999999\"W" is 22 bytes; leading zeros and spaces
 * may make it longer, but not a paragraph. */
constexpr size_t kMaxDmsInput = 64;

tp_status failed(tp_error* err, const char* what)
{
    try {
        throw;
    } catch (const GeographicLib::GeographicErr& e) {
        set_error(err, "%s: %s", what, e.what());
        return TP_ERR_INVALID_ARG;
    } catch (const std::bad_alloc&) {
        set_error(err, "%s: out of memory", what);
        return TP_ERR_OUT_OF_MEMORY;
    } catch (const std::exception& e) {
        set_error(err, "%s: GeographicLib/C++ failure (%s)", what, e.what());
        return TP_ERR_BACKEND;
    } catch (...) {
        set_error(err, "%s: GeographicLib/C++ failure (unknown exception)", what);
        return TP_ERR_BACKEND;
    }
}

/* GeographicLib 2.1.2's DMS::InternalDecode takes a ':' as "the next component" without
 * checking that there is one: past 3 components the next ':' writes beyond its 3-element
 * arrays and reads components_[3] (a crash, found by tests/fuzz/fuzz_position: 7"9:58:56W,
 * then 1`41:2:3:4). Refused here before the call, by a rule that does not need to know how
 * GeographicLib counts: colons only in the pure colon form, at most two of them (d:m:s). Any
 * symbol it reads as a degree, minute or second mark (d D ' ` " * and every non-ASCII byte,
 * since it maps UTF-8 marks to those) next to a ':' is refused, as are 3 or more colons. */
bool colon_past_seconds(const char* s)
{
    int colons = 0, marks = 0;
    for (const unsigned char* p = (const unsigned char*)s; *p; ++p) {
        unsigned char c = *p;
        colons += c == ':';
        marks += c >= 0x80 || std::strchr("dD'`\"*", c) != nullptr;
    }
    return colons > 2 || (colons > 0 && marks > 0);
}

} // namespace

extern "C" tp_status tp_dms_decode_latlon(const char* a, const char* b, double* lat_deg,
                                          double* lon_deg, tp_error* err)
{
    if (!a || !b || !lat_deg || !lon_deg) {
        set_error(err, "tp_dms_decode_latlon: expected non-NULL arguments, got NULL");
        return TP_ERR_INVALID_ARG;
    }
    for (const char* s : {a, b}) {
        size_t len = std::strlen(s);
        if (len == 0) {
            set_error(err, "expected an angle, got an empty string");
            return TP_ERR_INVALID_ARG;
        }
        if (len > kMaxDmsInput) {
            set_error(err, "angle of %zu characters is too long (at most %zu)", len, kMaxDmsInput);
            return TP_ERR_INVALID_ARG;
        }
        if (colon_past_seconds(s)) {
            set_error(err, "%s: more than 3 components (degrees, minutes, seconds), or colons "
                           "mixed with degree, minute or second marks", s);
            return TP_ERR_INVALID_ARG;
        }
    }
    try {
        double lat, lon;
        GeographicLib::DMS::DecodeLatLon(a, b, lat, lon, false);
        /* DMS::Decode reads "nan" and "inf" as numbers; a position needs finite ones */
        if (!std::isfinite(lat) || !std::isfinite(lon)) {
            set_error(err, "%s %s: not a finite position", a, b);
            return TP_ERR_INVALID_ARG;
        }
        if (!(lat >= -90.0 && lat <= 90.0) || !(lon >= -540.0 && lon <= 540.0)) {
            set_error(err, "%s %s: latitude %.9g or longitude %.9g out of range", a, b, lat, lon);
            return TP_ERR_INVALID_ARG;
        }
        *lat_deg = lat;
        *lon_deg = lon;
        return TP_OK;
    } catch (...) {
        std::string what = std::string(a) + " " + b;
        return failed(err, what.c_str());
    }
}

extern "C" tp_status tp_dms_encode(double angle_deg, tp_dms_kind kind, int seconds_decimals,
                                   char* out, size_t out_size, tp_error* err)
{
    if (!out) {
        set_error(err, "tp_dms_encode: expected an output buffer, got NULL");
        return TP_ERR_INVALID_ARG;
    }
    if (!std::isfinite(angle_deg) || seconds_decimals < 0 || seconds_decimals > 9 ||
        (kind == TP_DMS_LATITUDE && !(angle_deg >= -90.0 && angle_deg <= 90.0)) ||
        (kind != TP_DMS_PLAIN && kind != TP_DMS_LATITUDE && kind != TP_DMS_LONGITUDE)) {
        set_error(err, "tp_dms_encode: angle %.17g, kind %d, %d decimals: out of range",
                  angle_deg, (int)kind, seconds_decimals);
        return TP_ERR_INVALID_ARG;
    }
    try {
        GeographicLib::DMS::flag flag = kind == TP_DMS_LATITUDE    ? GeographicLib::DMS::LATITUDE
                                        : kind == TP_DMS_LONGITUDE ? GeographicLib::DMS::LONGITUDE
                                                                   : GeographicLib::DMS::NONE;
        /* Encode's precision counts from the trailing component: seconds with N decimals */
        std::string s = GeographicLib::DMS::Encode(angle_deg, GeographicLib::DMS::SECOND,
                                                   (unsigned)seconds_decimals, flag);
        if (s.size() + 1 > out_size) {
            set_error(err, "tp_dms_encode: %zu bytes needed, the buffer has %zu", s.size() + 1,
                      out_size);
            return TP_ERR_INVALID_ARG;
        }
        std::memcpy(out, s.c_str(), s.size() + 1);
        return TP_OK;
    } catch (...) {
        return failed(err, "tp_dms_encode");
    }
}
