/*
 * position.c - positions read from the command line and MGRS written with spaces (position.h).
 *
 * Fields are split here and numbers and zones read strictly; degrees-minutes-seconds are
 * GeographicLib's (tp_dms_decode_latlon), and every conversion too (io/include/tp_geo.h).
 */
#include "position.h"

#include "tp_core.h"
#include "tp_geo.h"

#include <assert.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FIELDS TP__POSITION_MAX_FIELDS
#define QUOTE_LIMIT 40 /* characters of a bad token echoed back */

typedef tp__fields fields;

/* A separator: white space, and a comma where commas (a comma is a space, as in
 * GeographicLib's GeoCoords::Reset: "45.5,-122.68"). */
static int is_separator(unsigned char c, int commas)
{
    return isspace(c) || (commas && c == ',');
}

tp__fields tp__position_split(char* line, int commas)
{
    fields f = {0};
    char* p = line;
    for (;;) {
        while (*p && is_separator((unsigned char)*p, commas))
            ++p;
        if (!*p)
            break;
        if (f.count < MAX_FIELDS)
            f.field[f.count] = p;
        ++f.count;
        while (*p && !is_separator((unsigned char)*p, commas))
            ++p;
        if (*p)
            *p++ = '\0';
    }
    return f;
}

/* 'token' for a message: at most QUOTE_LIMIT characters, unprintable bytes as '?'. */
static const char* quoted(const char* token, char* buf)
{
    size_t n = 0, len = strlen(token);
    size_t keep = len > QUOTE_LIMIT ? QUOTE_LIMIT : len;
    buf[n++] = '\'';
    for (size_t i = 0; i < keep; ++i)
        buf[n++] = isprint((unsigned char)token[i]) ? token[i] : '?';
    if (keep < len) {
        memcpy(buf + n, "...", 3);
        n += 3;
    }
    buf[n++] = '\'';
    buf[n] = '\0';
    return buf;
}

int tp_position_decimal(const char* s, double* v)
{
    const char* p = s;
    int digits = 0;
    if (*p == '+' || *p == '-')
        ++p;
    while (isdigit((unsigned char)*p))
        ++p, ++digits;
    if (*p == '.') {
        ++p;
        while (isdigit((unsigned char)*p))
            ++p, ++digits;
    }
    if (!digits)
        return 0;
    if (*p == 'e' || *p == 'E') {
        ++p;
        if (*p == '+' || *p == '-')
            ++p;
        if (!isdigit((unsigned char)*p))
            return 0;
        while (isdigit((unsigned char)*p))
            ++p;
    }
    if (*p)
        return 0;
    char* end;
    double x = strtod(s, &end);
    if (end != p)
        return 0;
    if (!isfinite(x))
        return -1;
    *v = x;
    return 1;
}

int tp__position_read_number(const char* token, const char* name, double* v, char* msg)
{
    char q[QUOTE_LIMIT + 8];
    int r = tp_position_decimal(token, v);
    if (r == 1)
        return 1;
    if (r < 0)
        snprintf(msg, TP_POSITION_MSG_SIZE, "%s %s is too large", name, quoted(token, q));
    else
        snprintf(msg, TP_POSITION_MSG_SIZE, "%s: expected a decimal number, got %s", name,
                 quoted(token, q));
    return 0;
}

/* A UTM zone with hemisphere ("33n", "3S", "01n") or a UPS hemisphere ("n", "s").
 * Returns 1 with *zone (0 = UPS) and *northp; 0 if token has not that shape; -1 (msg set) if
 * it has the shape but the zone is outside 1..60. */
static int parse_zone(const char* token, int* zone, int* northp, char* msg)
{
    size_t len = strlen(token), ndigits = 0;
    while (ndigits < len && isdigit((unsigned char)token[ndigits]))
        ++ndigits;
    if (len != ndigits + 1 || ndigits > 2)
        return 0;
    char h = (char)tolower((unsigned char)token[ndigits]);
    if (h != 'n' && h != 's')
        return 0;
    int z = 0;
    for (size_t i = 0; i < ndigits; ++i)
        z = 10 * z + (token[i] - '0');
    if (ndigits && (z < 1 || z > 60)) {
        snprintf(msg, TP_POSITION_MSG_SIZE, "UTM zone %d is outside [1, 60]", z);
        return -1;
    }
    *zone = ndigits ? z : TP_ZONE_UPS;
    *northp = h == 'n';
    return 1;
}

/* MGRS by shape: digits (the zone; none for UPS), a letter, then letters and digits only.
 * Whether it is a legal reference is tp_mgrs_reverse's to say. */
static int looks_like_mgrs(const char* token)
{
    size_t i = 0;
    while (isdigit((unsigned char)token[i]))
        ++i;
    if (!isalpha((unsigned char)token[i]))
        return 0;
    for (; token[i]; ++i)
        if (!isalnum((unsigned char)token[i]))
            return 0;
    return 1;
}

int tp__position_failed(tp_status s, const tp_error* err, char* msg)
{
    snprintf(msg, TP_POSITION_MSG_SIZE, "%s", err->message[0] ? err->message : tp_status_str(s));
    return 0;
}

static int position_from_grid(int zone, int northp, double e, double n, tp_position* pos,
                              char* msg)
{
    tp_error err = {{0}};
    double lat, lon;
    tp_status s = tp_geo_from_utmups(zone, northp, e, n, &lat, &lon, &err);
    if (s != TP_OK)
        return tp__position_failed(s, &err, msg);
    *pos = (tp_position){.lat_deg = lat,
                         .lon_deg = lon,
                         .has_grid = 1,
                         .zone = zone,
                         .northp = northp,
                         .easting_m = e,
                         .northing_m = n};
    return 1;
}

static int position_from_geo(double lat, double lon, tp_position* pos, char* msg)
{
    tp_error err = {{0}};
    double lat_n, lon_n;
    tp_status s = tp_geo_normalize(lat, lon, &lat_n, &lon_n, &err);
    if (s != TP_OK)
        return tp__position_failed(s, &err, msg);
    *pos = (tp_position){.lat_deg = lat_n, .lon_deg = lon_n};
    return 1;
}

static int position_from_mgrs(const char* token, tp_position* pos, char* msg)
{
    tp_error err = {{0}};
    int zone, northp, precision;
    double e, n;
    tp_status s = tp_mgrs_reverse(token, 1, &zone, &northp, &e, &n, &precision, &err);
    if (s != TP_OK)
        return tp__position_failed(s, &err, msg);
    if (precision < 0) {
        /* GeographicLib returns "some suitable (but essentially arbitrary) point" of the zone */
        char q[QUOTE_LIMIT + 8];
        snprintf(msg, TP_POSITION_MSG_SIZE,
                 "MGRS %s is a grid zone designator, not a position: add the 100 km square "
                 "letters and digits (e.g. 33TWN0000049776)",
                 quoted(token, q));
        return 0;
    }
    return position_from_grid(zone, northp, e, n, pos, msg);
}

static int has_digit(const char* s)
{
    for (; *s; ++s)
        if (isdigit((unsigned char)*s))
            return 1;
    return 0;
}

/* Two fields: LAT LON, decimal or DMS. Plain decimals keep the strict reader's messages; the
 * rest is GeographicLib's DMS::DecodeLatLon. */
static int parse_lat_lon(char* a, char* b, tp_position* pos, char* msg)
{
    char q[QUOTE_LIMIT + 8];
    double lat, lon;
    int ra = tp_position_decimal(a, &lat), rb = tp_position_decimal(b, &lon);
    if (ra == 1 && rb == 1)
        return position_from_geo(lat, lon, pos, msg);
    if (ra < 0)
        return tp__position_read_number(a, "latitude", &lat, msg);
    if (rb < 0)
        return tp__position_read_number(b, "longitude", &lon, msg);
    if (!has_digit(a) || !has_digit(b)) {
        int first = !has_digit(a);
        snprintf(msg, TP_POSITION_MSG_SIZE,
                 "%s: expected decimal degrees or degrees-minutes-seconds, got %s",
                 first ? "latitude" : "longitude", quoted(first ? a : b, q));
        return 0;
    }
    tp_error err = {{0}};
    tp_status s = tp_dms_decode_latlon(a, b, &lat, &lon, &err);
    if (s != TP_OK)
        return tp__position_failed(s, &err, msg);
    return position_from_geo(lat, lon, pos, msg);
}

/* MGRS written with spaces, as tp_position_mgrs_spaced writes it ("31T CH 76651 00831", also
 * "31TCH 76651 00831" or "31T CH7665100831"): 2 to 4 fields of letters and digits that start
 * with a zone (up to 2 digits and a band letter, or a UPS letter) followed by the 100 km square's
 * letters, in the first field or starting the second (so "n 2000000 2000000", a UPS grid
 * position, is not one), joined into out. */
static int join_spaced_mgrs(const fields* f, char* out, size_t cap)
{
    if (f->count < 2 || f->count > MAX_FIELDS)
        return 0;
    const char* z = f->field[0];
    size_t d = 0;
    while (isdigit((unsigned char)z[d]))
        ++d;
    if (d > 2 || !isalpha((unsigned char)z[d]) ||
        (d == 0 && !strchr("ABYZabyz", z[0]))) /* no digits: a UPS band */
        return 0;
    size_t e = d + 1; /* then the square's 2 letters and digits, or nothing */
    if (z[e]) {
        if (!isalpha((unsigned char)z[e]) || !isalpha((unsigned char)z[e + 1]))
            return 0;
        for (e += 2; isdigit((unsigned char)z[e]); ++e)
            ;
        if (z[e])
            return 0;
    } else if (!isalpha((unsigned char)f->field[1][0])) {
        return 0; /* no square letters: not MGRS */
    }
    size_t at = 0;
    for (int k = 0; k < f->count; ++k) {
        const char* p = f->field[k];
        for (const char* c = p; *c; ++c)
            if (!isalnum((unsigned char)*c))
                return 0;
        size_t len = strlen(p);
        if (at + len + 1 > cap)
            return 0;
        memcpy(out + at, p, len);
        at += len;
    }
    out[at] = '\0';
    return looks_like_mgrs(out);
}

static int parse_fields(const fields* f, int allow_height, tp_position* pos, char* msg)
{
    char joined[64];
    if (join_spaced_mgrs(f, joined, sizeof joined))
        return position_from_mgrs(joined, pos, msg);
    char* const* field = f->field;
    char q[QUOTE_LIMIT + 8];
    double a, b, c;
    int zone, northp;
    const char* forms = allow_height ? "LAT LON, LAT LON H, ZONE E N or an MGRS reference"
                                     : "LAT LON, ZONE E N or an MGRS reference";
    switch (f->count) {
    case 0:
        snprintf(msg, TP_POSITION_MSG_SIZE,
                 "expected LAT LON, ZONE E N or an MGRS reference, got an empty line");
        return 0;
    case 1:
        if (tp_position_decimal(field[0], &a) == 1) { /* before MGRS: "1e5" has its shape */
            snprintf(msg, TP_POSITION_MSG_SIZE, "expected LAT LON, got a single number %s",
                     quoted(field[0], q));
            return 0;
        }
        if (looks_like_mgrs(field[0]))
            return position_from_mgrs(field[0], pos, msg);
        snprintf(msg, TP_POSITION_MSG_SIZE, "expected %s, got %s", forms, quoted(field[0], q));
        return 0;
    case 2: return parse_lat_lon(field[0], field[1], pos, msg);
    case 3:
        if (tp_position_decimal(field[0], &a) == 1 &&
            parse_zone(field[2], &zone, &northp, msg) == 1) { /* E N ZONE, as GeoConvert */
            if (!tp__position_read_number(field[1], "northing", &b, msg))
                return 0;
            return position_from_grid(zone, northp, a, b, pos, msg);
        }
        if (tp_position_decimal(field[0], &a) == 1) { /* LAT LON H */
            if (!allow_height) {
                snprintf(msg, TP_POSITION_MSG_SIZE,
                         "expected %s; three numbers (LAT LON H) are not a position here",
                         forms);
                return 0;
            }
            if (!tp__position_read_number(field[1], "longitude", &b, msg) ||
                !tp__position_read_number(field[2], "height", &c, msg) ||
                !position_from_geo(a, b, pos, msg))
                return 0;
            pos->h_m = c;
            pos->has_h = 1;
            return 1;
        }
        switch (parse_zone(field[0], &zone, &northp, msg)) {
        case 1: break;
        case 0:
            snprintf(msg, TP_POSITION_MSG_SIZE,
                     "expected %s, but %s is neither a number nor a zone (1n..60n, 1s..60s, or n "
                     "or s for UPS)",
                     allow_height ? "LAT LON H or ZONE E N" : "ZONE E N", quoted(field[0], q));
            return 0;
        default: return 0;
        }
        if (!tp__position_read_number(field[1], "easting", &a, msg) ||
            !tp__position_read_number(field[2], "northing", &b, msg))
            return 0;
        return position_from_grid(zone, northp, a, b, pos, msg);
    default:
        snprintf(msg, TP_POSITION_MSG_SIZE, "expected %s, got %d fields", forms, f->count);
        return 0;
    }
}

int tp_position_parse(const char* text, size_t len, int allow_height, tp_position* out,
                      char* msg, size_t msg_size)
{
    assert(text && out && msg && msg_size >= TP_POSITION_MSG_SIZE);
    (void)msg_size;
    if (memchr(text, '\0', len)) {
        snprintf(msg, TP_POSITION_MSG_SIZE, "the position contains a NUL byte");
        return 0;
    }
    char* line = malloc(len + 1);
    if (!line) {
        snprintf(msg, TP_POSITION_MSG_SIZE, "out of memory");
        return 0;
    }
    memcpy(line, text, len);
    line[len] = '\0';
    fields f = tp__position_split(line, 1);
    tp_position pos;
    int ok = parse_fields(&f, allow_height, &pos, msg);
    free(line);
    if (ok)
        *out = pos;
    return ok;
}

size_t tp_position_join(char* const* argv, int count, char* buf, size_t cap)
{
    size_t n = 0;
    if (count <= 0 || cap == 0)
        return 0;
    for (int i = 0; i < count; ++i) {
        size_t len = strlen(argv[i]);
        if (n + len + (i > 0) + 1 > cap)
            return 0;
        if (i > 0)
            buf[n++] = ' ';
        memcpy(buf + n, argv[i], len);
        n += len;
    }
    buf[n] = '\0';
    return n;
}

int tp_position_mgrs_spaced(const char* mgrs, char* out, size_t cap)
{
    size_t len = strlen(mgrs), i = 0;
    while (i < len && i < 2 && isdigit((unsigned char)mgrs[i]))
        ++i;
    if (i >= len || !isalpha((unsigned char)mgrs[i]))
        return 0;
    size_t gzd = i + 1; /* zone digits and the band letter (UPS: the letter alone) */
    if (len < gzd + 2 || !isalpha((unsigned char)mgrs[gzd]) ||
        !isalpha((unsigned char)mgrs[gzd + 1]))
        return 0;
    size_t digits = len - gzd - 2;
    if (digits % 2)
        return 0;
    for (size_t k = gzd + 2; k < len; ++k)
        if (!isdigit((unsigned char)mgrs[k]))
            return 0;
    char buf[TP_POSITION_MGRS_SPACED_SIZE];
    if (len + 4 > sizeof buf || len + 4 > cap)
        return 0;
    if (digits)
        snprintf(buf, sizeof buf, "%.*s %.2s %.*s %.*s", (int)gzd, mgrs, mgrs + gzd,
                 (int)(digits / 2), mgrs + gzd + 2, (int)(digits / 2), mgrs + gzd + 2 + digits / 2);
    else
        snprintf(buf, sizeof buf, "%.*s %.2s", (int)gzd, mgrs, mgrs + gzd);
    memcpy(out, buf, strlen(buf) + 1);
    return 1;
}
