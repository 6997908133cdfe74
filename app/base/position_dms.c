/*
 * position_dms.c - latitude and longitude in degrees, minutes and seconds written with spaces
 * ("N 55 28 41.88 W 2 08 44.16"), joined and decoded by GeographicLib (tp_dms_decode_latlon).
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
 * the text starts with one). Returns 1 with *pos; 0 if f has not that shape; -1 with err
 * (GeographicLib's reason). */
int tp__position_parse_spaced_dms(const fields* f, tp_position* pos, tp_error* err)
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
    tp_status s = tp_dms_decode_latlon(a, b, &lat, &lon, err);
    if (s != TP_OK)
        return tp__position_failed(s, err), -1;
    return tp__position_from_geo(lat, lon, pos, err) ? 1 : -1;
}
