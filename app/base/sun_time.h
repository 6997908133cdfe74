/*
 * sun_time.h - the date and time of `terrapatch light` (and of the viewer's sun, later): a
 * calendar date "YYYY-MM-DD" and a clock time "HH:MM[:SS]" with an optional zone, read into
 * Unix seconds, and written back in a zone. app/base/sun_time.c, pure C.
 *
 * Zones: "Z", "UTC" or "GMT" (case-insensitive), or an offset from UTC "+HH", "+HH:MM",
 * "+HHMM" (or '-'), up to 14 hours; after the time directly or after one space ("14:30Z",
 * "14:30 +02:00", "07:15-0500"). No zone: UTC. Named zones ("CET", "Europe/Paris") are not
 * read: the offset says which of summer or winter time is meant.
 *
 * Dates are proleptic Gregorian, years 1000 .. 2999 (the sun's range in tp_sun.h); times
 * 00:00:00 .. 23:59:59 (no leap second, no 24:00). Unix seconds count from 1970-01-01 00:00 UTC
 * without leap seconds (POSIX).
 */
#ifndef TP_APP_SUN_TIME_H
#define TP_APP_SUN_TIME_H

#include "tp_core.h"

#include <stddef.h>

typedef struct tp_sun_time {
    int year, month, day;    /* the date as given */
    int hour, minute, second; /* the time as given (0 .. 23, 0 .. 59, 0 .. 59) */
    int zone_offset_s;       /* local time minus UTC, seconds (+7200 for "+02:00") */
    int zone_given;          /* 1 when the text named a zone, 0 for the UTC default */
    double unix_s;           /* the instant, UTC */
} tp_sun_time;

/* Reads text as "YYYY-MM-DD". 1 with *year, *month, *day; else 0 with err saying what was
 * expected ("expected YYYY-MM-DD", "month 13 is not 1 .. 12", "2026-02-29: February 2026 has
 * 28 days", ...); outputs untouched then. */
int tp_sun_date_parse(const char* text, int* year, int* month, int* day, tp_error* err);

/* Reads date ("YYYY-MM-DD") and time ("HH:MM[:SS][zone]", zone as above) into *out. 1 on
 * success; else 0 with err as tp_sun_date_parse ("expected HH:MM[:SS] with an optional zone
 * (Z, UTC, +02:00, -0500)", "hour 25 is not 0 .. 23", "zone offset +15:00 is beyond 14
 * hours", ...); *out untouched then. */
int tp_sun_time_parse(const char* date, const char* time, tp_sun_time* out, tp_error* err);

/* Writes unix_s as "YYYY-MM-DD HH:MM:SS" in the zone offset_s from UTC, followed by " UTC" for
 * 0 or " +HH:MM" / " -HH:MM" (seconds rounded to the nearest). "-" for NaN. */
void tp_sun_time_format(double unix_s, int offset_s, char* out, size_t cap);

#endif /* TP_APP_SUN_TIME_H */
