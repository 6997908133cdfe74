/*
 * position.c - positions read from the command line and MGRS written with spaces (position.h).
 *
 * Fields are split here and numbers and zones read strictly; degrees-minutes-seconds are
 * GeographicLib's (tp_dms_decode_latlon), and every conversion too (io/include/tp_geo.h).
 */
#include "position.h"
#include "position_int.h"

#include "tp_core.h"
#include "tp_geo.h"

#include <assert.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

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
const char* tp__position_quoted(const char* token, char* buf)
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

int tp__position_read_number(const char* token, const char* name, double* v, tp_error* err)
{
    char q[QUOTE_LIMIT + 8];
    int r = tp_position_decimal(token, v);
    if (r == 1)
        return 1;
    if (r < 0)
        tp_error_set(err, TP_ERR_INVALID_ARG, "%s %s is too large", name,
                     tp__position_quoted(token, q));
    else
        tp_error_set(err, TP_ERR_INVALID_ARG, "%s: expected a decimal number, got %s", name,
                     tp__position_quoted(token, q));
    return 0;
}

int tp__position_failed(tp_status s, tp_error* err)
{
    if (err && !err->message[0])
        tp_error_set(err, s, "%s", tp_status_str(s));
    return 0;
}

int tp__position_from_geo(double lat, double lon, tp_position* pos, tp_error* err)
{
    double lat_n, lon_n;
    tp_status s = tp_geo_normalize(lat, lon, &lat_n, &lon_n, err);
    if (s != TP_OK)
        return tp__position_failed(s, err);
    *pos = (tp_position){.lat_deg = lat_n, .lon_deg = lon_n};
    return 1;
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
static int parse_lat_lon(char* a, char* b, tp_position* pos, tp_error* err)
{
    char q[QUOTE_LIMIT + 8];
    double lat, lon;
    int ra = tp_position_decimal(a, &lat), rb = tp_position_decimal(b, &lon);
    if (ra == 1 && rb == 1)
        return tp__position_from_geo(lat, lon, pos, err);
    if (ra < 0)
        return tp__position_read_number(a, "latitude", &lat, err);
    if (rb < 0)
        return tp__position_read_number(b, "longitude", &lon, err);
    if (!has_digit(a) || !has_digit(b)) {
        int first = !has_digit(a);
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "%s: expected decimal degrees or degrees-minutes-seconds, got %s",
                     first ? "latitude" : "longitude", tp__position_quoted(first ? a : b, q));
        return 0;
    }
    tp_status s = tp_dms_decode_latlon(a, b, &lat, &lon, err);
    if (s != TP_OK)
        return tp__position_failed(s, err);
    return tp__position_from_geo(lat, lon, pos, err);
}

/* f without a leading "UTM" or "MGRS", the label `point` prints before those forms. */
static fields without_label(const fields* f)
{
    fields g = *f;
    /* more fields than are kept: the one after the last kept is not there to shift in (and
     * the text is refused for its length anyway) */
    if (f->count < 2 || f->count > MAX_FIELDS ||
        !(tp__position_same_word(f->field[0], "UTM") ||
          tp__position_same_word(f->field[0], "MGRS")))
        return g;
    --g.count;
    for (int i = 0; i + 1 < MAX_FIELDS; ++i)
        g.field[i] = f->field[i + 1];
    g.field[MAX_FIELDS - 1] = NULL;
    return g;
}

static int parse_fields(const fields* all, int allow_height, tp_position_readings* out,
                        tp_error* err)
{
    const fields f0 = without_label(all), *f = &f0;
    tp_position* pos = &out->reading[0];
    out->count = 1;
    char joined[64];
    if (tp__position_join_spaced_mgrs(f, joined, sizeof joined))
        return tp__position_from_mgrs(joined, pos, err);
    /* grid forms, then spaced DMS: "N 55 E 2" is no UPS position but 55N 2E */
    const int grid = tp__position_parse_grid(f, out, err);
    if (grid > 0)
        return 1;
    tp_error dms_err = {{0}};
    const int dms = tp__position_parse_spaced_dms(f, pos, grid ? &dms_err : err);
    if (dms > 0) {
        out->count = 1;
        return 1;
    }
    if (grid < 0) { /* the grid's reason, unless the zone was a letter alone and DMS failed */
        if (dms < 0 && !isdigit((unsigned char)f->field[0][0]) && err)
            *err = dms_err;
        return 0;
    }
    if (dms < 0)
        return 0;
    char* const* field = f->field;
    char q[QUOTE_LIMIT + 8];
    double a, b, c;
    const char* forms = allow_height ? "LAT LON, LAT LON H, ZONE E N or an MGRS reference"
                                     : "LAT LON, ZONE E N or an MGRS reference";
    switch (f->count) {
    case 0:
        tp_error_set(err, TP_ERR_INVALID_ARG, "the position is empty: expected %s", forms);
        return 0;
    case 1:
        if (tp_position_decimal(field[0], &a) == 1) { /* before MGRS: "1e5" has its shape */
            tp_error_set(err, TP_ERR_INVALID_ARG, "expected LAT LON, got a single number %s",
                         tp__position_quoted(field[0], q));
            return 0;
        }
        if (tp__position_looks_like_mgrs(field[0]))
            return tp__position_from_mgrs(field[0], pos, err);
        tp_error_set(err, TP_ERR_INVALID_ARG, "expected %s, got %s", forms,
                     tp__position_quoted(field[0], q));
        return 0;
    case 2: return parse_lat_lon(field[0], field[1], pos, err);
    case 3:
        if (tp_position_decimal(field[0], &a) == 1) { /* LAT LON H */
            if (!allow_height) {
                tp_error_set(err, TP_ERR_INVALID_ARG,
                             "expected %s; three numbers (LAT LON H) are not a position here",
                             forms);
                return 0;
            }
            if (!tp__position_read_number(field[1], "longitude", &b, err) ||
                !tp__position_read_number(field[2], "height", &c, err) ||
                !tp__position_from_geo(a, b, pos, err))
                return 0;
            pos->h_m = c;
            pos->has_h = 1;
            return 1;
        }
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "expected %s, but %s is neither a number nor a zone (1n..60n, 1s..60s, a zone "
                     "and latitude band such as 30U, or n or s for UPS)",
                     allow_height ? "LAT LON H or ZONE E N" : "ZONE E N",
                     tp__position_quoted(field[0], q));
        return 0;
    default:
        tp_error_set(err, TP_ERR_INVALID_ARG, "expected %s, got %d fields", forms, f->count);
        return 0;
    }
}

int tp_position_parse_readings(const char* text, size_t len, int allow_height,
                               tp_position_readings* out, tp_error* err)
{
    assert(text && out);
    if (memchr(text, '\0', len)) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "the position contains a NUL byte");
        return 0;
    }
    char* line = malloc(len + 1);
    if (!line) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return 0;
    }
    memcpy(line, text, len);
    line[len] = '\0';
    fields f = tp__position_split(line, 1);
    tp_position_readings r;
    int ok = parse_fields(&f, allow_height, &r, err);
    free(line);
    if (ok)
        *out = r;
    return ok;
}

int tp_position_parse(const char* text, size_t len, int allow_height, tp_position* out,
                      tp_error* err)
{
    tp_position_readings r;
    if (!tp_position_parse_readings(text, len, allow_height, &r, err) || r.count > 1)
        return 0; /* two readings: err says why */
    *out = r.reading[0];
    return 1;
}

int tp_position_join(char* const* argv, int count, char* buf, size_t cap)
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
    return 1;
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

int tp_position_swapped(const char* text, char* out, size_t cap)
{
    char copy[128];
    tp_position p;
    double a, b;
    if (strlen(text) >= sizeof copy)
        return 0;
    fields f = tp__position_split(strcpy(copy, text), 1);
    return f.count == 2 && tp_position_decimal(f.field[0], &a) == 1 &&
           tp_position_decimal(f.field[1], &b) == 1 &&
           snprintf(out, cap, "%s %s", f.field[1], f.field[0]) < (int)cap &&
           tp_position_parse(out, strlen(out), 0, &p, NULL);
}
