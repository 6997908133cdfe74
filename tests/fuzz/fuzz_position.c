/*
 * fuzz_position.c - libFuzzer entry point for the position parser every command uses
 * (app/position.c: decimal degrees, DMS through GeographicLib's DMS::DecodeLatLon, LAT,LON,
 * ZONE E N, MGRS) and for MGRS written with spaces.
 *
 * The first byte picks: bit 0 allow LAT LON H; bit 1 also feed the text to
 * tp_position_mgrs_spaced; bit 2 also read it with tp_position_parse_readings (both readings
 * of a band letter S). The rest is the position text (any bytes, NULs included).
 * Checks: a result is a real position (latitude in [-90, 90], longitude in [-180, 180],
 * finite); a failure leaves the output alone and says why; DMS written back reads back.
 */
#include "fuzz_util.h"
#include "position.h"
#include "tp_geo.h"

#include <math.h>
#include <string.h>

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
        return 0;
    int allow_height = data[0] & 1, spaced = data[0] & 2;
    const char* text = (const char*)data + 1;
    size_t len = size - 1;
    tp_position p;
    memset(&p, 0x55, sizeof p);
    tp_position before = p;
    tp_error err;
    memset(&err, 0x55, sizeof err);
    if (tp_position_parse(text, len, allow_height, &p, &err)) {
        TP_FUZZ_CHECK(isfinite(p.lat_deg) && isfinite(p.lon_deg) && p.lat_deg >= -90.0 &&
                          p.lat_deg <= 90.0 && p.lon_deg >= -180.0 && p.lon_deg <= 180.0,
                      "read as %g %g", p.lat_deg, p.lon_deg);
        TP_FUZZ_CHECK(allow_height || !p.has_h, "a height where none is allowed");
        char a[TP_DMS_TEXT_SIZE], b[TP_DMS_TEXT_SIZE];
        double lat, lon;
        TP_FUZZ_CHECK(tp_dms_encode(p.lat_deg, TP_DMS_LATITUDE, 9, a, sizeof a, NULL) == TP_OK &&
                          tp_dms_encode(p.lon_deg, TP_DMS_LONGITUDE, 9, b, sizeof b, NULL) ==
                              TP_OK,
                      "cannot write %g %g as DMS", p.lat_deg, p.lon_deg);
        TP_FUZZ_CHECK(tp_dms_decode_latlon(a, b, &lat, &lon, NULL) == TP_OK &&
                          fabs(lat - p.lat_deg) < 1e-9 && fabs(lon - p.lon_deg) < 1e-9,
                      "%s %s does not read back as %g %g", a, b, p.lat_deg, p.lon_deg);
    } else {
        TP_FUZZ_CHECK(memcmp(&p, &before, sizeof p) == 0, "a failure wrote the output");
        TP_FUZZ_CHECK(memchr(err.message, '\0', sizeof err.message) && err.message[0],
                      "no message");
    }
    if (data[0] & 4) {
        tp_position_readings r;
        if (tp_position_parse_readings(text, len, allow_height, &r, &err)) {
            TP_FUZZ_CHECK(r.count == 1 || r.count == 2, "%d readings", r.count);
            for (int k = 0; k < r.count; ++k)
                TP_FUZZ_CHECK(isfinite(r.reading[k].lat_deg) &&
                                  fabs(r.reading[k].lat_deg) <= 90.0 &&
                                  fabs(r.reading[k].lon_deg) <= 180.0,
                              "reading %d: %g %g", k, r.reading[k].lat_deg, r.reading[k].lon_deg);
            TP_FUZZ_CHECK(r.count == 1 || (r.reading[0].northp && !r.reading[1].northp),
                          "two readings of one hemisphere");
        }
    }
    if (spaced && len < 64 && !memchr(text, '\0', len)) {
        char in[64], out[TP_POSITION_MGRS_SPACED_SIZE];
        memcpy(in, text, len);
        in[len] = '\0';
        if (tp_position_mgrs_spaced(in, out, sizeof out))
            TP_FUZZ_CHECK(strlen(out) < sizeof out && strlen(out) >= len, "spaced '%s'", out);
    }
    return 0;
}
