/*
 * sun_time.c - dates and clock times with a zone, to Unix seconds and back (sun_time.h).
 */
#include "sun_time.h"

#include "tp_sun.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MIN_YEAR 1000
#define MAX_YEAR 2999
#define MAX_ZONE_S (14 * 3600)

static int say(tp_error* err, const char* text)
{
    tp_error_set(err, TP_ERR_INVALID_ARG, "%s", text);
    return 0;
}

/* Exactly n decimal digits at *p (advanced past them) into *v. */
static int digits(const char** p, int n, int* v)
{
    int r = 0;
    for (int i = 0; i < n; ++i) {
        if (!isdigit((unsigned char)(*p)[i]))
            return 0;
        r = r * 10 + ((*p)[i] - '0');
    }
    *p += n;
    *v = r;
    return 1;
}

static int leap(int y) { return (y % 4 == 0 && y % 100 != 0) || y % 400 == 0; }

static int days_in_month(int y, int m)
{
    static const int d[12] = {31, 28, 31, 30, 31, 30, 31, 31, 30, 31, 30, 31};
    return m == 2 && leap(y) ? 29 : d[m - 1];
}

/* The inverse (Hinnant's civil_from_days). */
static void civil_from_days(long z, int* year, int* month, int* day)
{
    z += 719468;
    const long era = (z >= 0 ? z : z - 146096) / 146097;
    const long doe = z - era * 146097;
    const long yoe = (doe - doe / 1460 + doe / 36524 - doe / 146096) / 365;
    const long doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    const long mp = (5 * doy + 2) / 153;
    const int d = (int)(doy - (153 * mp + 2) / 5 + 1);
    const int m = (int)(mp < 10 ? mp + 3 : mp - 9);
    *year = (int)(yoe + era * 400 + (m <= 2));
    *month = m;
    *day = d;
}

int tp_sun_date_parse(const char* text, int* year, int* month, int* day, tp_error* err)
{
    const char* p = text;
    int y, m, d;
    if (!p || !digits(&p, 4, &y) || *p++ != '-' || !digits(&p, 2, &m) || *p++ != '-' ||
        !digits(&p, 2, &d) || *p)
        return say(err, "expected a date YYYY-MM-DD");
    if (y < MIN_YEAR || y > MAX_YEAR) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "year %d is not %d .. %d", y, MIN_YEAR, MAX_YEAR);
        return 0;
    }
    if (m < 1 || m > 12) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "month %d is not 1 .. 12", m);
        return 0;
    }
    if (d < 1 || d > days_in_month(y, m)) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "day %d: month %02d of %d has %d days", d, m, y,
                     days_in_month(y, m));
        return 0;
    }
    *year = y;
    *month = m;
    *day = d;
    return 1;
}

/* A zone at p (the rest of the text): 1 with the offset; 0 when it is not one. */
static int zone(const char* p, int* offset_s, tp_error* err)
{
    static const char* const utc[] = {"Z", "UTC", "GMT"};
    for (size_t i = 0; i < sizeof utc / sizeof utc[0]; ++i) {
        size_t n = strlen(utc[i]), k = 0;
        while (k < n && p[k] && toupper((unsigned char)p[k]) == utc[i][k])
            ++k;
        if (k == n && !p[n]) {
            *offset_s = 0;
            return 1;
        }
    }
    const char* const bad = "expected a zone Z, UTC, +HH, +HH:MM or +HHMM (or -) after the time";
    if (*p != '+' && *p != '-')
        return say(err, bad);
    const int sign = *p++ == '-' ? -1 : 1;
    int hh, mm = 0;
    if (!digits(&p, 2, &hh))
        return say(err, bad);
    if (*p == ':')
        ++p;
    if (*p && !digits(&p, 2, &mm))
        return say(err, bad);
    if (*p)
        return say(err, bad);
    if (mm > 59) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "zone offset minutes %d are not 0 .. 59", mm);
        return 0;
    }
    if (hh * 3600 + mm * 60 > MAX_ZONE_S) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "zone offset %c%02d:%02d is beyond 14 hours",
                     sign < 0 ? '-' : '+', hh, mm);
        return 0;
    }
    *offset_s = sign * (hh * 3600 + mm * 60);
    return 1;
}

int tp_sun_time_parse(const char* date, const char* time, tp_sun_time* out, tp_error* err)
{
    tp_sun_time t;
    memset(&t, 0, sizeof t);
    if (!tp_sun_date_parse(date, &t.year, &t.month, &t.day, err))
        return 0;
    const char* p = time;
    const char* const bad = "expected a time HH:MM[:SS] with an optional zone (Z, UTC, +02:00, "
                            "-0500)";
    if (!p || !digits(&p, 2, &t.hour) || *p++ != ':' || !digits(&p, 2, &t.minute))
        return say(err, bad);
    if (*p == ':' && isdigit((unsigned char)p[1])) {
        ++p;
        if (!digits(&p, 2, &t.second))
            return say(err, bad);
    }
    if (t.hour > 23) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "hour %d is not 0 .. 23", t.hour);
        return 0;
    }
    if (t.minute > 59 || t.second > 59) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "%s %d is not 0 .. 59",
                     t.minute > 59 ? "minute" : "second", t.minute > 59 ? t.minute : t.second);
        return 0;
    }
    if (*p == ' ')
        ++p;
    if (*p) {
        if (!zone(p, &t.zone_offset_s, err))
            return 0;
        t.zone_given = 1;
    }
    t.unix_s = (double)tp_sun_days_from_civil(t.year, t.month, t.day) * 86400.0 +
               t.hour * 3600.0 + t.minute * 60.0 + t.second - t.zone_offset_s;
    *out = t;
    return 1;
}

void tp_sun_time_format(double unix_s, int offset_s, char* out, size_t cap)
{
    if (isnan(unix_s)) {
        snprintf(out, cap, "-");
        return;
    }
    const double local = floor(unix_s + offset_s + 0.5);
    const long days = (long)floor(local / 86400.0);
    const long sec = (long)(local - days * 86400.0);
    int y, m, d;
    civil_from_days(days, &y, &m, &d);
    char zone_text[16];
    if (offset_s == 0)
        snprintf(zone_text, sizeof zone_text, "UTC");
    else
        snprintf(zone_text, sizeof zone_text, "%c%02d:%02d", offset_s < 0 ? '-' : '+',
                 abs(offset_s) / 3600, abs(offset_s) % 3600 / 60);
    snprintf(out, cap, "%04d-%02d-%02d %02ld:%02ld:%02ld %s", y, m, d, sec / 3600,
             sec % 3600 / 60, sec % 60, zone_text);
}
