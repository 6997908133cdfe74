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

/* a and b equal but for the case of ASCII letters */
static int same_word(const char* a, const char* b)
{
    for (; *a && *b; ++a, ++b)
        if (tolower((unsigned char)*a) != tolower((unsigned char)*b))
            return 0;
    return !*a && !*b;
}

/* A latitude band letter of UTM (C..X without I and O) or, for UPS, A, B, Y, Z (either case). */
static int is_band(char c, int ups)
{
    c = (char)toupper((unsigned char)c);
    if (ups)
        return c == 'A' || c == 'B' || c == 'Y' || c == 'Z';
    return c >= 'C' && c <= 'X' && c != 'I' && c != 'O';
}

/* A zone as typed (zone.h's forms, position.h): UTM digits or none (UPS), then a hemisphere or
 * a latitude band. */
typedef struct zone_text {
    int zone;   /* 1..60, or TP_ZONE_UPS */
    int northp; /* the hemisphere: given, or the band's */
    char band;  /* the band letter (upper case) to check the position against; 0: none */
    int either; /* "33S": band S or GeographicLib's southern hemisphere, both to be tried */
} zone_text;

/* Reads token as a zone: digits (none for UPS; up to 2), then n, s, north or south (the
 * hemisphere, GeographicLib's UTMUPS::DecodeZone) or a band letter (N reads as north either way;
 * S after digits is band S or south: either). Returns 1 with *z; 0 if token has not that shape;
 * -1 (msg set) if it has but the zone is outside 1..60. */
static int parse_zone(const char* token, zone_text* z, char* msg)
{
    size_t ndigits = 0;
    while (isdigit((unsigned char)token[ndigits]))
        ++ndigits;
    const char* r = token + ndigits;
    if (ndigits > 2 || !*r)
        return 0;
    zone_text t = {0};
    if (!strcmp(r, "n") || !strcmp(r, "N") || same_word(r, "north")) {
        t.northp = 1;
    } else if (!strcmp(r, "s") || same_word(r, "south")) {
        t.northp = 0;
    } else if (!strcmp(r, "S")) {
        t.northp = 0;
        t.either = ndigits > 0; /* UPS has no band S */
    } else if (!r[1] && is_band(r[0], ndigits == 0)) {
        t.band = (char)toupper((unsigned char)r[0]);
        t.northp = ndigits ? t.band >= 'N' : t.band >= 'Y';
    } else {
        return 0;
    }
    int n = 0;
    for (size_t i = 0; i < ndigits; ++i)
        n = 10 * n + (token[i] - '0');
    if (ndigits && (n < 1 || n > 60)) {
        snprintf(msg, TP_POSITION_MSG_SIZE, "UTM zone %d is outside [1, 60]", n);
        return -1;
    }
    t.zone = ndigits ? n : TP_ZONE_UPS;
    *z = t;
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

/* What a message about a reference that is not MGRS ends with: the forms that are read. */
#define MGRS_FORMS                                                                                 \
    "; positions are LAT LON, ZONE E N or MGRS: a zone and band, the 100 km square's two "         \
    "letters and an even number of digits (33TWN0000049776, 33T WN 00000 49776)"

static int position_from_mgrs(const char* token, tp_position* pos, char* msg)
{
    tp_error err = {{0}};
    int zone, northp, precision;
    double e, n;
    tp_status s = tp_mgrs_reverse(token, 1, &zone, &northp, &e, &n, &precision, &err);
    if (s != TP_OK) {
        tp__position_failed(s, &err, msg);
        size_t len = strlen(msg);
        snprintf(msg + len, TP_POSITION_MSG_SIZE - len, "%s", MGRS_FORMS);
        return 0;
    }
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

/* 1 when grid position (zone, northp, e, n) lies in latitude band `band`, as GeographicLib's
 * MGRS reader checks a reference's band: the 100 km square of (e, n) written with that band
 * letter reads back as the same square (its row must meet the band: up to a square of slack;
 * row letters repeat every 2000 km, so the square read back must be the same one). */
static int in_band(int zone, int northp, double e, double n, char band)
{
    char mgrs[TP_MGRS_SIZE];
    if (tp_mgrs_forward(zone, northp, e, n, NAN, 0, mgrs, sizeof mgrs, NULL) != TP_OK)
        return 0;
    size_t i = 0;
    while (isdigit((unsigned char)mgrs[i]))
        ++i;
    mgrs[i] = band;
    int z, np;
    double e2, n2;
    return tp_mgrs_reverse(mgrs, 1, &z, &np, &e2, &n2, NULL, NULL) == TP_OK && z == zone &&
           np == northp && fabs(e2 - e) <= 1e5 && fabs(n2 - n) <= 1e5;
}

void tp_position_reading_text(const tp_position_readings* r, int k, char* out, size_t cap)
{
    const tp_position* p = &r->reading[k];
    if (k == 0)
        snprintf(out, cap, "band S (%.6f %.6f)", p->lat_deg, p->lon_deg);
    else
        snprintf(out, cap, "zone %d south (%.6f %.6f)", p->zone, p->lat_deg, p->lon_deg);
}

/* The readings of grid position (zone z as typed in token, e, n): the band's or the
 * hemisphere's, or both of an `either` zone ("33S"). 1 with *out (for two, msg says why that is
 * ambiguous); 0 with msg. */
static int grid_readings(const char* token, const zone_text* z, double e, double n,
                         tp_position_readings* out, char* msg)
{
    char q[QUOTE_LIMIT + 8];
    tp_position_readings r = {.count = 1};
    if (z->either) {
        char south_msg[TP_POSITION_MSG_SIZE];
        int band = position_from_grid(z->zone, 1, e, n, &r.reading[0], msg) &&
                   in_band(z->zone, 1, e, n, 'S');
        int south = position_from_grid(z->zone, 0, e, n, &r.reading[band], south_msg);
        if (!band && !south) {
            memcpy(msg, south_msg, TP_POSITION_MSG_SIZE);
            return 0;
        }
        if (band && south) {
            char a[128], b[128];
            r.count = 2;
            tp_position_reading_text(&r, 0, a, sizeof a);
            tp_position_reading_text(&r, 1, b, sizeof b);
            snprintf(msg, TP_POSITION_MSG_SIZE,
                     "%s is ambiguous: %s, as maps and GPS units write a latitude band, or %s, "
                     "as GeographicLib writes a hemisphere; write %dnorth or %dsouth for the "
                     "hemisphere, or give the position in MGRS",
                     quoted(token, q), a, b, z->zone, z->zone);
        }
        *out = r;
        return 1;
    }
    if (!position_from_grid(z->zone, z->northp, e, n, &r.reading[0], msg))
        return 0;
    if (z->band && !in_band(z->zone, z->northp, e, n, z->band)) {
        snprintf(msg, TP_POSITION_MSG_SIZE,
                 "E %.1f N %.1f in %s is at %.6f %.6f, not in band %c: check the band letter "
                 "and the coordinates",
                 e, n, quoted(token, q), r.reading[0].lat_deg, r.reading[0].lon_deg, z->band);
        return 0;
    }
    *out = r;
    return 1;
}

/* 1 when token is the label of a coordinate: the letter (E or N, either case), "m" before it
 * optional ("mE", as on maps). */
static int is_label(const char* token, char letter)
{
    if (tolower((unsigned char)token[0]) == 'm')
        ++token;
    return toupper((unsigned char)token[0]) == letter && !token[1];
}

/* Reads field *k as the coordinate called name, a label after it or in the next field
 * ("554001", "554001E", "554001mE", "554001 E"), and moves *k past both. 1 with *v; 0 with msg. */
static int read_labelled(const fields* f, int* k, char letter, const char* name, double* v,
                         char* msg)
{
    const char* token = f->field[(*k)++];
    size_t len = strlen(token), at = len;
    while (at > 0 && isalpha((unsigned char)token[at - 1]))
        --at;
    char number[64];
    if (at < len && at > 0 && at < sizeof number && is_label(token + at, letter)) {
        memcpy(number, token, at);
        number[at] = '\0';
        if (tp_position_decimal(number, v) == 1)
            goto label;
    }
    if (!tp__position_read_number(token, name, v, msg))
        return 0;
label:
    if (*k < f->count && is_label(f->field[*k], letter))
        ++*k;
    return 1;
}

/* ZONE E N in position.h's forms: [UPS] ZONE E [E] N [N] (labels attached or not), or E N ZONE
 * as GeoConvert reads it. Returns 1 with *out; 0 when f has not that shape (no zone first, nor
 * last after two numbers); -1 with msg. */
static int parse_grid(const fields* f, tp_position_readings* out, char* msg)
{
    if (f->count < 3 || f->count > MAX_FIELDS)
        return 0;
    const int ups = same_word(f->field[0], "UPS");
    int k = ups;
    zone_text z;
    double e, n;
    int r = parse_zone(f->field[k], &z, msg);
    if (r < 0)
        return -1;
    if (r == 0 || (ups && z.zone != TP_ZONE_UPS)) { /* E N ZONE, as GeoConvert */
        if (ups || f->count != 3 || tp_position_decimal(f->field[0], &e) != 1)
            return 0;
        if ((r = parse_zone(f->field[2], &z, msg)) <= 0)
            return r;
        if (!tp__position_read_number(f->field[1], "northing", &n, msg))
            return -1;
        return grid_readings(f->field[2], &z, e, n, out, msg) ? 1 : -1;
    }
    const char* zone = f->field[k++];
    if (!read_labelled(f, &k, 'E', "easting", &e, msg))
        return -1;
    if (k >= f->count) {
        snprintf(msg, TP_POSITION_MSG_SIZE, "ZONE E N: the northing is missing");
        return -1;
    }
    if (!read_labelled(f, &k, 'N', "northing", &n, msg))
        return -1;
    if (k < f->count) {
        char q[QUOTE_LIMIT + 8];
        snprintf(msg, TP_POSITION_MSG_SIZE, "ZONE E N: unexpected %s after the northing",
                 quoted(f->field[k], q));
        return -1;
    }
    return grid_readings(zone, &z, e, n, out, msg) ? 1 : -1;
}

static int is_hemisphere(char c)
{
    c = (char)toupper((unsigned char)c);
    return c == 'N' || c == 'S' || c == 'E' || c == 'W';
}

/* The length of the number of a DMS component typed alone, "41.88" or with its mark ("41.88\"",
 * 55d, 55 and the UTF-8 degree sign, prime or double prime); 0 if s (len bytes) is none. */
static size_t dms_component(const char* s, size_t len)
{
    size_t i = 0, digits = 0, points = 0;
    for (; i < len; ++i) {
        if (isdigit((unsigned char)s[i]))
            ++digits;
        else if (s[i] == '.' && !points)
            ++points;
        else
            break;
    }
    const char* m = s + i;
    const size_t rest = len - i;
    if (!digits)
        return 0;
    if (rest == 0 || (rest == 1 && (*m == 'd' || *m == '\'' || *m == '"')) ||
        (rest == 2 && !memcmp(m, "\xC2\xB0", 2)) ||
        (rest == 3 && (!memcmp(m, "\xE2\x80\xB2", 3) || !memcmp(m, "\xE2\x80\xB3", 3))))
        return i;
    return 0;
}

/* One coordinate of spaced DMS from its n fields, joined for DMS::Decode into out (cap bytes):
 * the hemisphere letter first (lead) or last, and 1 to 3 components, each with its own mark or
 * d, ' or " by its place. 1, or 0 if the fields are not that. */
static int dms_join(char* const* tok, int n, int lead, char* out, size_t cap)
{
    static const char marks[3] = {'d', '\'', '"'};
    const char* last = tok[n - 1];
    const char letter = lead ? tok[0][0] : last[strlen(last) - 1];
    size_t at = 0;
    int parts = 0;
    if (lead)
        out[at++] = letter;
    for (int i = 0; i < n; ++i) {
        const char* t = tok[i] + (lead && i == 0);
        size_t len = strlen(t) - (!lead && i == n - 1);
        if (!len)
            continue;
        size_t number = dms_component(t, len);
        if (!number || parts == 3 || at + len + 3 > cap)
            return 0;
        memcpy(out + at, t, len);
        at += len;
        if (number == len)
            out[at++] = marks[parts];
        ++parts;
    }
    if (!parts)
        return 0;
    if (!lead)
        out[at++] = letter;
    out[at] = '\0';
    return 1;
}

/* LAT LON in degrees, minutes and seconds separated by spaces, "55 28 41.88 N 2 08 44.16 W" or
 * "N 55 28.698 W 2 08.736": the hemisphere letters end each coordinate (or start each, when
 * the text starts with one). Returns 1 with *pos; 0 if f has not that shape; -1 with msg
 * (GeographicLib's reason). */
static int parse_spaced_dms(const fields* f, tp_position* pos, char* msg)
{
    const int n = f->count;
    if (n < 3 || n > MAX_FIELDS)
        return 0;
    char* const* t = f->field;
    const int lead = is_hemisphere(t[0][0]);
    int second = -1; /* the field the longitude (or latitude) starts at */
    for (int i = 0; i < n; ++i) {
        const size_t len = strlen(t[i]);
        if (!(lead ? is_hemisphere(t[i][0]) : is_hemisphere(t[i][len - 1])))
            continue;
        if (lead ? i == 0 : i == n - 1)
            continue;
        if (second >= 0)
            return 0; /* three letters */
        second = lead ? i : i + 1;
    }
    const char* last = t[n - 1];
    if (second < 0 || (!lead && !is_hemisphere(last[strlen(last) - 1])))
        return 0;
    char a[64], b[64];
    if (!dms_join(t, second, lead, a, sizeof a) ||
        !dms_join(t + second, n - second, lead, b, sizeof b))
        return 0;
    double lat, lon;
    tp_error err = {{0}};
    tp_status s = tp_dms_decode_latlon(a, b, &lat, &lon, &err);
    if (s != TP_OK)
        return tp__position_failed(s, &err, msg), -1;
    return position_from_geo(lat, lon, pos, msg) ? 1 : -1;
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

/* f without a leading "UTM" or "MGRS", the label `point` prints before those forms. */
static fields without_label(const fields* f)
{
    fields g = *f;
    /* more fields than are kept: the one after the last kept is not there to shift in (and
     * the text is refused for its length anyway) */
    if (f->count < 2 || f->count > MAX_FIELDS ||
        !(same_word(f->field[0], "UTM") || same_word(f->field[0], "MGRS")))
        return g;
    --g.count;
    for (int i = 0; i + 1 < MAX_FIELDS; ++i)
        g.field[i] = f->field[i + 1];
    g.field[MAX_FIELDS - 1] = NULL;
    return g;
}

static int parse_fields(const fields* all, int allow_height, tp_position_readings* out, char* msg)
{
    const fields f0 = without_label(all), *f = &f0;
    tp_position* pos = &out->reading[0];
    out->count = 1;
    char joined[64];
    if (join_spaced_mgrs(f, joined, sizeof joined))
        return position_from_mgrs(joined, pos, msg);
    /* grid forms, then spaced DMS: "N 55 E 2" is no UPS position but 55N 2E */
    const int grid = parse_grid(f, out, msg);
    if (grid > 0)
        return 1;
    char dms_msg[TP_POSITION_MSG_SIZE];
    const int dms = parse_spaced_dms(f, pos, grid ? dms_msg : msg);
    if (dms > 0) {
        out->count = 1;
        return 1;
    }
    if (grid < 0) { /* the grid's reason, unless the zone was a letter alone and DMS failed */
        if (dms < 0 && !isdigit((unsigned char)f->field[0][0]))
            memcpy(msg, dms_msg, TP_POSITION_MSG_SIZE);
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
        snprintf(msg, TP_POSITION_MSG_SIZE, "the position is empty: expected %s", forms);
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
        snprintf(msg, TP_POSITION_MSG_SIZE,
                 "expected %s, but %s is neither a number nor a zone (1n..60n, 1s..60s, a zone "
                 "and latitude band such as 30U, or n or s for UPS)",
                 allow_height ? "LAT LON H or ZONE E N" : "ZONE E N", quoted(field[0], q));
        return 0;
    default:
        snprintf(msg, TP_POSITION_MSG_SIZE, "expected %s, got %d fields", forms, f->count);
        return 0;
    }
}

int tp_position_parse_readings(const char* text, size_t len, int allow_height,
                               tp_position_readings* out, char* msg, size_t msg_size)
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
    tp_position_readings r;
    int ok = parse_fields(&f, allow_height, &r, msg);
    free(line);
    if (ok)
        *out = r;
    return ok;
}

int tp_position_parse(const char* text, size_t len, int allow_height, tp_position* out, char* msg,
                      size_t msg_size)
{
    tp_position_readings r;
    if (!tp_position_parse_readings(text, len, allow_height, &r, msg, msg_size) || r.count > 1)
        return 0; /* two readings: msg says why */
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
