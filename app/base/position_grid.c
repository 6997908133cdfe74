/*
 * position_grid.c - positions on a grid read from the command line (position.h): UTM and UPS as
 * ZONE E N (labelled or not; a latitude band S kept as both readings where it is ambiguous) and
 * MGRS references, spaced or not. Conversions are GeographicLib's (io/include/tp_geo.h).
 */
#include "position.h"
#include "position_int.h"

#include "tp_core.h"
#include "tp_geo.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* a and b equal but for the case of ASCII letters */
int tp__position_same_word(const char* a, const char* b)
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
 * -1 (err set) if it has but the zone is outside 1..60. */
static int parse_zone(const char* token, zone_text* z, tp_error* err)
{
    size_t ndigits = 0;
    while (isdigit((unsigned char)token[ndigits]))
        ++ndigits;
    const char* r = token + ndigits;
    if (ndigits > 2 || !*r)
        return 0;
    zone_text t = {0};
    if (!strcmp(r, "n") || !strcmp(r, "N") || tp__position_same_word(r, "north")) {
        t.northp = 1;
    } else if (!strcmp(r, "s") || tp__position_same_word(r, "south")) {
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
        tp_error_set(err, TP_ERR_INVALID_ARG, "UTM zone %d is outside [1, 60]", n);
        return -1;
    }
    t.zone = ndigits ? n : TP_ZONE_UPS;
    *z = t;
    return 1;
}

/* MGRS by shape: digits (the zone; none for UPS), a letter, then letters and digits only.
 * Whether it is a legal reference is tp_mgrs_reverse's to say. */
int tp__position_looks_like_mgrs(const char* token)
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

static int position_from_grid(int zone, int northp, double e, double n, tp_position* pos,
                              tp_error* err)
{
    double lat, lon;
    tp_status s = tp_geo_from_utmups(zone, northp, e, n, &lat, &lon, err);
    if (s != TP_OK)
        return tp__position_failed(s, err);
    *pos = (tp_position){.lat_deg = lat,
                         .lon_deg = lon,
                         .has_grid = 1,
                         .zone = zone,
                         .northp = northp,
                         .easting_m = e,
                         .northing_m = n};
    return 1;
}

/* What a message about a reference that is not MGRS ends with: the forms that are read. */
#define MGRS_FORMS                                                                                 \
    "; positions are LAT LON, ZONE E N or MGRS: a zone and band, the 100 km square's two "         \
    "letters and an even number of digits (33TWN0000049776, 33T WN 00000 49776)"

int tp__position_from_mgrs(const char* token, tp_position* pos, tp_error* err)
{
    tp_error why = {{0}};
    int zone, northp, precision;
    double e, n;
    tp_status s = tp_mgrs_reverse(token, 1, &zone, &northp, &e, &n, &precision, &why);
    if (s != TP_OK) {
        tp_error_set(err, s, "%s%s", why.message[0] ? why.message : tp_status_str(s), MGRS_FORMS);
        return 0;
    }
    if (precision < 0) {
        /* GeographicLib returns "some suitable (but essentially arbitrary) point" of the zone */
        char q[QUOTE_LIMIT + 8];
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "MGRS %s is a grid zone designator, not a position: add the 100 km square "
                     "letters and digits (e.g. 33TWN0000049776)",
                     tp__position_quoted(token, q));
        return 0;
    }
    return position_from_grid(zone, northp, e, n, pos, err);
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
 * hemisphere's, or both of an `either` zone ("33S"). 1 with *out (for two, err says why that is
 * ambiguous); 0 with err. */
static int grid_readings(const char* token, const zone_text* z, double e, double n,
                         tp_position_readings* out, tp_error* err)
{
    char q[QUOTE_LIMIT + 8];
    tp_position_readings r = {.count = 1};
    if (z->either) {
        tp_error south_err = {{0}};
        int band = position_from_grid(z->zone, 1, e, n, &r.reading[0], err) &&
                   in_band(z->zone, 1, e, n, 'S');
        int south = position_from_grid(z->zone, 0, e, n, &r.reading[band], &south_err);
        if (!band && !south) {
            if (err)
                *err = south_err;
            return 0;
        }
        if (band && south) {
            char a[128], b[128];
            r.count = 2;
            tp_position_reading_text(&r, 0, a, sizeof a);
            tp_position_reading_text(&r, 1, b, sizeof b);
            tp_error_set(err, TP_ERR_INVALID_ARG,
                         "%s is ambiguous: %s, as maps and GPS units write a latitude band, or "
                         "%s, as GeographicLib writes a hemisphere; write %dnorth or %dsouth for "
                         "the hemisphere, or give the position in MGRS",
                         tp__position_quoted(token, q), a, b, z->zone, z->zone);
        }
        *out = r;
        return 1;
    }
    if (!position_from_grid(z->zone, z->northp, e, n, &r.reading[0], err))
        return 0;
    if (z->band && !in_band(z->zone, z->northp, e, n, z->band)) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "E %.1f N %.1f in %s is at %.6f %.6f, not in band %c: check the band letter "
                     "and the coordinates",
                     e, n, tp__position_quoted(token, q), r.reading[0].lat_deg,
                     r.reading[0].lon_deg, z->band);
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
 * ("554001", "554001E", "554001mE", "554001 E"), and moves *k past both. 1 with *v; 0 with err. */
static int read_labelled(const fields* f, int* k, char letter, const char* name, double* v,
                         tp_error* err)
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
    if (!tp__position_read_number(token, name, v, err))
        return 0;
label:
    if (*k < f->count && is_label(f->field[*k], letter))
        ++*k;
    return 1;
}

/* ZONE E N in position.h's forms: [UPS] ZONE E [E] N [N] (labels attached or not), or E N ZONE
 * as GeoConvert reads it. Returns 1 with *out; 0 when f has not that shape (no zone first, nor
 * last after two numbers); -1 with err. */
int tp__position_parse_grid(const fields* f, tp_position_readings* out, tp_error* err)
{
    if (f->count < 3 || f->count > MAX_FIELDS)
        return 0;
    const int ups = tp__position_same_word(f->field[0], "UPS");
    int k = ups;
    zone_text z;
    double e, n;
    int r = parse_zone(f->field[k], &z, err);
    if (r < 0)
        return -1;
    if (r == 0 || (ups && z.zone != TP_ZONE_UPS)) { /* E N ZONE, as GeoConvert */
        if (ups || f->count != 3 || tp_position_decimal(f->field[0], &e) != 1)
            return 0;
        if ((r = parse_zone(f->field[2], &z, err)) <= 0)
            return r;
        if (!tp__position_read_number(f->field[1], "northing", &n, err))
            return -1;
        return grid_readings(f->field[2], &z, e, n, out, err) ? 1 : -1;
    }
    const char* zone = f->field[k++];
    if (!read_labelled(f, &k, 'E', "easting", &e, err))
        return -1;
    if (k >= f->count) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "ZONE E N: the northing is missing");
        return -1;
    }
    if (!read_labelled(f, &k, 'N', "northing", &n, err))
        return -1;
    if (k < f->count) {
        char q[QUOTE_LIMIT + 8];
        tp_error_set(err, TP_ERR_INVALID_ARG, "ZONE E N: unexpected %s after the northing",
                     tp__position_quoted(f->field[k], q));
        return -1;
    }
    return grid_readings(zone, &z, e, n, out, err) ? 1 : -1;
}

/* MGRS written with spaces, as tp_position_mgrs_spaced writes it ("31T CH 76651 00831", also
 * "31TCH 76651 00831" or "31T CH7665100831"): 2 to 4 fields of letters and digits that start
 * with a zone (up to 2 digits and a band letter, or a UPS letter) followed by the 100 km square's
 * letters, in the first field or starting the second (so "n 2000000 2000000", a UPS grid
 * position, is not one), joined into out. */
int tp__position_join_spaced_mgrs(const fields* f, char* out, size_t cap)
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
    return tp__position_looks_like_mgrs(out);
}
