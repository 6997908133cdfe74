/*
 * fuzz_coord_line.c - libFuzzer entry point for the `terrapatch coord` line parser
 * (app/base/coord_line.c: numbers, zones, MGRS, through GeographicLib) and for tp_mgrs_reverse,
 * the MGRS reader, which takes any string (io/src/geo.cpp).
 *
 * The first byte picks what is done with the rest, one line of text:
 *   byte % 6: 0..3 convert the line --to geo, utm, mgrs, ecef; 4 --geodesic;
 *             5 tp_mgrs_reverse on it, and tp_mgrs_forward back when it reads;
 *   byte / 6 % 12: the MGRS precision (0..11) for --to mgrs.
 */
#include "coord_line.h"
#include "fuzz_util.h"
#include "tp_geo.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static void mgrs_reverse(const char* text, int centerp)
{
    int zone = -7, northp = -7, precision = -7;
    double e = -1.5, n = -1.5;
    tp_error err = {{0}};
    tp_status s = tp_mgrs_reverse(text, centerp, &zone, &northp, &e, &n, &precision, &err);
    /* GeographicLib 2.1.2 overflows an int on 10 or more leading digits (UBSan at its
     * src/MGRS.cpp:185), which this build cannot see (the library is not instrumented):
     * tp_mgrs_reverse must refuse more than 2 before calling it
     * (regressions/fuzz_coord_line/mgrs_long_zone). */
    if (strspn(text, "0123456789") > 2)
        TP_FUZZ_CHECK(s == TP_ERR_INVALID_ARG && (strstr(err.message, "zone of 1 or 2 digits") ||
                                                  strstr(err.message, "is too long")),
                      "'%s' was handed to GeographicLib: %s", text, err.message);
    if (s != TP_OK) {
        TP_FUZZ_CHECK(zone == -7 && northp == -7 && precision == -7 && e == -1.5 && n == -1.5,
                      "status %d wrote an output", (int)s);
        TP_FUZZ_CHECK(err.message[0] != '\0', "status %d without a message", (int)s);
        return;
    }
    TP_FUZZ_CHECK(zone >= 0 && zone <= 60 && isfinite(e) && isfinite(n) && precision >= -1 &&
                      precision <= 11,
                  "'%s' read as zone %d, %g %g, precision %d", text, zone, e, n, precision);
    char again[TP_MGRS_SIZE];
    if (precision >= 0)
        tp_mgrs_forward(zone, northp, e, n, NAN, precision, again, sizeof again, &err);
}

int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
        return 0;
    int kind = data[0] % 6, precision = data[0] / 6 % 12;
    size_t len = size - 1;
    char* line = malloc(len + 1);
    if (!line)
        return 0;
    memcpy(line, data + 1, len);
    line[len] = '\0';
    if (kind == 5) {
        mgrs_reverse(line, precision & 1);
    } else {
        tp_coord_request req = {.to = (tp_coord_to)(kind < 4 ? kind : 0),
                                .precision = precision,
                                .geodesic = kind == 4};
        char out[TP_COORD_TEXT_SIZE];
        tp_error err;
        memset(out, 0x55, sizeof out);
        memset(&err, 0x55, sizeof err);
        if (tp_coord_line_convert(&req, line, len, out, sizeof out, &err)) {
            TP_FUZZ_CHECK(memchr(out, '\0', sizeof out) != NULL, "output not terminated");
            TP_FUZZ_CHECK(out[0] != '\0', "empty output");
        } else {
            TP_FUZZ_CHECK(memchr(err.message, '\0', sizeof err.message) != NULL,
                          "message not terminated");
            TP_FUZZ_CHECK(err.message[0] != '\0', "empty message");
        }
    }
    free(line);
    return 0;
}
