/*
 * coord_line.c - one line of `terrapatch coord` input parsed and converted (coord_line.h).
 *
 * Lines are parsed here, strictly (whole-token numbers, nothing left over); every conversion
 * is GeographicLib's, through io/include/tp_geo.h.
 */
#include "coord_line.h"

#include "tp_core.h"
#include "tp_geo.h"

#include <assert.h>
#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAX_FIELDS 4 /* most fields a line may have (--geodesic); more are only counted */
#define MSG_SIZE TP_COORD_TEXT_SIZE /* one error message or output line */
#define QUOTE_LIMIT 40              /* characters of a bad token echoed back */

/* ---------------------------------------------------------------------------------------------
 * Parsing one line
 */

typedef struct fields {
    int count; /* all fields on the line */
    char* field[MAX_FIELDS];
} fields;

/* Splits line in place at white space. */
static fields split_fields(char* line)
{
    fields f = {0};
    char* p = line;
    for (;;) {
        while (*p && isspace((unsigned char)*p))
            ++p;
        if (!*p)
            break;
        if (f.count < MAX_FIELDS)
            f.field[f.count] = p;
        ++f.count;
        while (*p && !isspace((unsigned char)*p))
            ++p;
        if (*p)
            *p++ = '\0';
    }
    return f;
}

/* 'token' for a message: at most QUOTE_LIMIT characters, unprintable bytes as '?'. */
static const char* quoted(const char* token, char* buf, size_t cap)
{
    size_t n = 0, len = strlen(token);
    size_t keep = len > QUOTE_LIMIT ? QUOTE_LIMIT : len;
    if (cap < QUOTE_LIMIT + 8) {
        buf[0] = '\0';
        return buf;
    }
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

/* A decimal number and nothing else: [+-]digits[.digits][(e|E)[+-]digits], with at least
 * one digit before or after the point. strtod alone would also take "nan", "inf", hex and
 * leading blanks. Returns 1 and *v on success; 0 for text that is not such a number; -1 for
 * a number too large for a double. */
static int parse_number(const char* s, double* v)
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

/* Reads field `token` as the number called `name`; on failure writes msg. */
static int read_number(const char* token, const char* name, double* v, char* msg)
{
    char q[QUOTE_LIMIT + 8];
    int r = parse_number(token, v);
    if (r == 1)
        return 1;
    if (r < 0)
        snprintf(msg, MSG_SIZE, "%s %s is too large", name, quoted(token, q, sizeof q));
    else
        snprintf(msg, MSG_SIZE, "%s: expected a decimal number, got %s", name,
                 quoted(token, q, sizeof q));
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
        snprintf(msg, MSG_SIZE, "UTM zone %d is outside [1, 60]", z);
        return -1;
    }
    *zone = ndigits ? z : TP_ZONE_UPS;
    *northp = h == 'n';
    return 1;
}

/* MGRS by shape: digits (the zone; none for UPS), a letter, then letters and digits only.
 * Whether it is a legal reference is tp_mgrs_reverse's to say, a zone of more than 2 digits
 * included ("MGRS 110087268780A: expected a zone of 1 or 2 digits"). */
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

/* A position as read from one line: geographic always (once converted), and the grid
 * coordinates as given when the line was UTM/UPS or MGRS. */
typedef struct position {
    double lat_deg, lon_deg; /* lon in [-180, 180] */
    double h_m;              /* ellipsoidal height; 0 unless given */
    int has_h;
    int has_grid; /* zone, northp, easting_m, northing_m hold the input's grid coordinates */
    int zone, northp;
    double easting_m, northing_m;
} position;

/* Copies a tp_error message into msg (tp_status_str when the message is empty). */
static int geo_failed(tp_status s, const tp_error* err, char* msg)
{
    snprintf(msg, MSG_SIZE, "%s", err->message[0] ? err->message : tp_status_str(s));
    return 0;
}

/* From UTM/UPS grid coordinates (as given) to a position. */
static int position_from_grid(int zone, int northp, double e, double n, position* pos, char* msg)
{
    tp_error err = {{0}};
    double lat, lon;
    tp_status s = tp_geo_from_utmups(zone, northp, e, n, &lat, &lon, &err);
    if (s != TP_OK)
        return geo_failed(s, &err, msg);
    *pos = (position){.lat_deg = lat,
                      .lon_deg = lon,
                      .has_grid = 1,
                      .zone = zone,
                      .northp = northp,
                      .easting_m = e,
                      .northing_m = n};
    return 1;
}

static int position_from_geo(double lat, double lon, position* pos, char* msg)
{
    tp_error err = {{0}};
    double lat_n, lon_n;
    tp_status s = tp_geo_normalize(lat, lon, &lat_n, &lon_n, &err);
    if (s != TP_OK)
        return geo_failed(s, &err, msg);
    *pos = (position){.lat_deg = lat_n, .lon_deg = lon_n};
    return 1;
}

static int position_from_mgrs(const char* token, position* pos, char* msg)
{
    tp_error err = {{0}};
    int zone, northp, precision;
    double e, n;
    tp_status s = tp_mgrs_reverse(token, 1, &zone, &northp, &e, &n, &precision, &err);
    if (s != TP_OK)
        return geo_failed(s, &err, msg);
    if (precision < 0) {
        /* GeographicLib returns "some suitable (but essentially arbitrary) point" of the zone */
        char q[QUOTE_LIMIT + 8];
        snprintf(msg, MSG_SIZE,
                 "MGRS %s is a grid zone designator, not a position: add the 100 km square "
                 "letters and digits (e.g. 33TWN0000049776)",
                 quoted(token, q, sizeof q));
        return 0;
    }
    return position_from_grid(zone, northp, e, n, pos, msg);
}

/* Reads one input line (not --geodesic) into pos. Returns 1, or 0 with msg set. */
static int parse_position(const fields* f, position* pos, char* msg)
{
    char* const* field = f->field;
    char q[QUOTE_LIMIT + 8];
    double a, b, c;
    int zone, northp;
    switch (f->count) {
    case 0:
        snprintf(msg, MSG_SIZE,
                 "expected LAT LON, ZONE E N or an MGRS reference, got an empty line");
        return 0;
    case 1:
        if (parse_number(field[0], &a) == 1) { /* before MGRS: "1e5" has its shape */
            snprintf(msg, MSG_SIZE, "expected LAT LON, got a single number %s",
                     quoted(field[0], q, sizeof q));
            return 0;
        }
        if (looks_like_mgrs(field[0]))
            return position_from_mgrs(field[0], pos, msg);
        snprintf(msg, MSG_SIZE, "expected LAT LON, ZONE E N or an MGRS reference, got %s",
                 quoted(field[0], q, sizeof q));
        return 0;
    case 2:
        if (!read_number(field[0], "latitude", &a, msg) ||
            !read_number(field[1], "longitude", &b, msg))
            return 0;
        return position_from_geo(a, b, pos, msg);
    case 3:
        if (parse_number(field[0], &a) == 1) { /* LAT LON H */
            if (!read_number(field[1], "longitude", &b, msg) ||
                !read_number(field[2], "height", &c, msg) || !position_from_geo(a, b, pos, msg))
                return 0;
            pos->h_m = c;
            pos->has_h = 1;
            return 1;
        }
        switch (parse_zone(field[0], &zone, &northp, msg)) {
        case 1: break;
        case 0:
            snprintf(msg, MSG_SIZE,
                     "expected LAT LON H or ZONE E N, but %s is neither a number nor a zone "
                     "(1n..60n, 1s..60s, or n or s for UPS)",
                     quoted(field[0], q, sizeof q));
            return 0;
        default: return 0;
        }
        if (!read_number(field[1], "easting", &a, msg) ||
            !read_number(field[2], "northing", &b, msg))
            return 0;
        return position_from_grid(zone, northp, a, b, pos, msg);
    default:
        snprintf(msg, MSG_SIZE,
                 "expected LAT LON, LAT LON H, ZONE E N or an MGRS reference, got %d fields",
                 f->count);
        return 0;
    }
}

/* ---------------------------------------------------------------------------------------------
 * Converting
 */

/* -0.0 prints as "-0.000"; a computed exact zero should not. */
static double unsigned_zero(double v)
{
    return v + 0.0;
}

/* The standard UTM/UPS zone of pos and its coordinates there. Grid input already in that zone
 * keeps its own easting and northing, exactly as given, and on the equator its own hemisphere
 * (as GeoConvert does; see tp_utmups_to_standard). */
static int standard_grid(const position* pos, int* zone, int* northp, double* e, double* n,
                         char* msg)
{
    tp_error err = {{0}};
    tp_status s = pos->has_grid
                      ? tp_utmups_to_standard(pos->zone, pos->northp, pos->easting_m,
                                              pos->northing_m, zone, northp, e, n, &err)
                      : tp_geo_to_utmups(pos->lat_deg, pos->lon_deg, zone, northp, e, n, &err);
    return s == TP_OK ? 1 : geo_failed(s, &err, msg);
}

/* Converts one parsed position and writes the output line into msg. Returns 1, or 0 with
 * the reason in msg. */
static int convert_position(const tp_coord_request* o, const position* pos, char* msg)
{
    tp_error err = {{0}};
    tp_status s;
    int zone, northp;
    double e, n;
    if (pos->has_h && o->to != TP_COORD_TO_ECEF) {
        snprintf(msg, MSG_SIZE, "a height (LAT LON H) is only used with --to ecef");
        return 0;
    }
    switch (o->to) {
    case TP_COORD_TO_GEO:
        snprintf(msg, MSG_SIZE, "%.9f %.9f", unsigned_zero(pos->lat_deg),
                 unsigned_zero(pos->lon_deg));
        return 1;
    case TP_COORD_TO_UTM: {
        if (!standard_grid(pos, &zone, &northp, &e, &n, msg))
            return 0;
        char zone_name[TP_ZONE_TEXT_SIZE];
        s = tp_zone_format(zone, northp, TP_ZONE_STYLE_GEOCONVERT, zone_name, sizeof zone_name,
                           &err);
        if (s != TP_OK)
            return geo_failed(s, &err, msg);
        snprintf(msg, MSG_SIZE, "%s %.3f %.3f", zone_name, unsigned_zero(e), unsigned_zero(n));
        return 1;
    }
    case TP_COORD_TO_MGRS: {
        char mgrs[TP_MGRS_SIZE];
        if (!standard_grid(pos, &zone, &northp, &e, &n, msg))
            return 0;
        s = tp_mgrs_forward(zone, northp, e, n, pos->lat_deg, o->precision, mgrs, sizeof mgrs,
                            &err);
        if (s != TP_OK)
            return geo_failed(s, &err, msg);
        snprintf(msg, MSG_SIZE, "%s", mgrs);
        return 1;
    }
    case TP_COORD_TO_ECEF: {
        double x, y, z;
        s = tp_geo_to_ecef(pos->lat_deg, pos->lon_deg, pos->h_m, &x, &y, &z, &err);
        if (s != TP_OK)
            return geo_failed(s, &err, msg);
        snprintf(msg, MSG_SIZE, "%.6f %.6f %.6f", unsigned_zero(x), unsigned_zero(y),
                 unsigned_zero(z));
        return 1;
    }
    }
    snprintf(msg, MSG_SIZE, "unknown output kind %d", (int)o->to);
    return 0;
}

static int convert_geodesic(const fields* f, char* msg)
{
    char* const* field = f->field;
    static const char* const names[4] = {"lat1", "lon1", "lat2", "lon2"};
    double v[4];
    if (f->count != 4) {
        snprintf(msg, MSG_SIZE, "expected LAT1 LON1 LAT2 LON2 (4 numbers), got %d field%s",
                 f->count, f->count == 1 ? "" : "s");
        return 0;
    }
    for (int i = 0; i < 4; ++i)
        if (!read_number(field[i], names[i], &v[i], msg))
            return 0;
    tp_error err = {{0}};
    double azi1, azi2, s12;
    tp_status s = tp_geodesic_inverse(v[0], v[1], v[2], v[3], &azi1, &azi2, &s12, &err);
    if (s != TP_OK)
        return geo_failed(s, &err, msg);
    snprintf(msg, MSG_SIZE, "%.12f %.12f %.9f", unsigned_zero(azi1), unsigned_zero(azi2),
             unsigned_zero(s12));
    return 1;
}

int tp_coord_line_convert(const tp_coord_request* req, char* line, size_t len, char* out,
                          size_t out_size)
{
    assert(req && line && out && out_size >= TP_COORD_TEXT_SIZE);
    (void)out_size;
    if (strlen(line) != len) {
        snprintf(out, MSG_SIZE, "the line contains a NUL byte");
        return 0;
    }
    fields f = split_fields(line);
    if (req->geodesic)
        return convert_geodesic(&f, out);
    position pos;
    return parse_position(&f, &pos, out) && convert_position(req, &pos, out);
}
