/* test_sun_time.c - the dates and times of `terrapatch light` (app/base/sun_time.c): every zone
 * form, the calendar's edges and the errors. Expected Unix seconds from Python's datetime
 * (e.g. (datetime(2026,6,21,12,30) - datetime(1970,1,1)).total_seconds() = 1782045000). */
#include "sun_time.h"
#include "tp_sun.h"
#include "tp_test.h"

#define TESTS(X)                                                                                   \
    X(utc_by_default_and_by_name)                                                                  \
    X(offsets_in_every_form)                                                                       \
    X(seconds_and_calendar_edges)                                                                  \
    X(bad_dates_say_why)                                                                           \
    X(bad_times_and_zones_say_why)                                                                 \
    X(format_round_trips)

static double parse_ok(const char* date, const char* time, tp_sun_time* t)
{
    tp_error why = {{0}};
    if (!tp_sun_time_parse(date, time, t, &why))
        FAIL("'%s' '%s': %s", date, time, why.message);
    return t->unix_s;
}

/* The message for a refused date/time, which must leave *out untouched. */
static const char* refused(const char* date, const char* time)
{
    static tp_error why;
    tp_sun_time t;
    memset(&t, 0x5a, sizeof t);
    why.message[0] = '\0';
    if (tp_sun_time_parse(date, time, &t, &why))
        FAIL("'%s' '%s' accepted", date, time);
    tp_sun_time before;
    memset(&before, 0x5a, sizeof before);
    EXPECT_TRUE(!memcmp(&t, &before, sizeof t));
    EXPECT_TRUE(why.message[0] != '\0');
    return why.message;
}

TEST(utc_by_default_and_by_name)
{
    tp_sun_time t;
    EXPECT_EQ_DBL(1782045000.0, parse_ok("2026-06-21", "12:30", &t));
    EXPECT_EQ_INT(0, t.zone_given);
    EXPECT_EQ_INT(0, t.zone_offset_s);
    const char* utc[] = {"12:30Z", "12:30 Z", "12:30UTC", "12:30 utc", "12:30 GMT", "12:30z"};
    for (size_t i = 0; i < sizeof utc / sizeof utc[0]; ++i) {
        EXPECT_EQ_DBL(1782045000.0, parse_ok("2026-06-21", utc[i], &t));
        EXPECT_EQ_INT(1, t.zone_given);
    }
}

TEST(offsets_in_every_form)
{
    tp_sun_time t;
    /* 14:30 at +02:00 is 12:30 UTC */
    const char* plus2[] = {"14:30+02:00", "14:30 +02:00", "14:30+0200", "14:30+02"};
    for (size_t i = 0; i < sizeof plus2 / sizeof plus2[0]; ++i) {
        EXPECT_EQ_DBL(1782045000.0, parse_ok("2026-06-21", plus2[i], &t));
        EXPECT_EQ_INT(7200, t.zone_offset_s);
    }
    /* 14:30 at -05:00 is 19:30 UTC */
    EXPECT_EQ_DBL(1782070200.0, parse_ok("2026-06-21", "14:30-0500", &t));
    EXPECT_EQ_INT(-18000, t.zone_offset_s);
    EXPECT_EQ_DBL(1782070200.0, parse_ok("2026-06-21", "14:30 -05:00", &t));
    /* half hours: 18:00 at +05:30 is 12:30 UTC */
    EXPECT_EQ_DBL(1782045000.0, parse_ok("2026-06-21", "18:00+05:30", &t));
    /* the day changes: 00:30 at +01:00 on 1970-01-01 is 23:30 UTC the day before */
    EXPECT_EQ_DBL(-1800.0, parse_ok("1970-01-01", "00:30+01:00", &t));
    EXPECT_EQ_DBL(0.0, parse_ok("1970-01-01", "00:00 +00:00", &t));
}

TEST(seconds_and_calendar_edges)
{
    tp_sun_time t;
    EXPECT_EQ_DBL(951868799.0, parse_ok("2000-02-29", "23:59:59", &t)); /* 2000 is leap */
    EXPECT_EQ_INT(59, t.second);
    EXPECT_EQ_DBL(-3600.0, parse_ok("1969-12-31", "23:00", &t));
    EXPECT_EQ_DBL(-30610224000.0, parse_ok("1000-01-01", "00:00", &t));
    EXPECT_EQ_DBL(32503679999.0, parse_ok("2999-12-31", "23:59:59Z", &t));
    EXPECT_EQ_DBL(1796192107.0, parse_ok("2026-12-02", "06:15:07", &t));
    EXPECT_EQ_INT(2026, t.year);
    EXPECT_EQ_INT(12, t.month);
    EXPECT_EQ_INT(2, t.day);
    long days = tp_sun_days_from_civil(2026, 12, 2);
    EXPECT_EQ_INT(20789, (int)days); /* 1796192107 // 86400 */
}

TEST(bad_dates_say_why)
{
    EXPECT_CONTAINS(refused("2026-6-21", "12:00"), "expected a date YYYY-MM-DD");
    EXPECT_CONTAINS(refused("21/06/2026", "12:00"), "YYYY-MM-DD");
    EXPECT_CONTAINS(refused("2026-06-21x", "12:00"), "YYYY-MM-DD");
    EXPECT_CONTAINS(refused("", "12:00"), "YYYY-MM-DD");
    EXPECT_CONTAINS(refused("2026-13-01", "12:00"), "month 13 is not 1 .. 12");
    EXPECT_CONTAINS(refused("2026-00-01", "12:00"), "month 0");
    EXPECT_CONTAINS(refused("2026-02-29", "12:00"), "month 02 of 2026 has 28 days");
    EXPECT_CONTAINS(refused("1900-02-29", "12:00"), "has 28 days"); /* 1900: not leap */
    EXPECT_CONTAINS(refused("2026-04-31", "12:00"), "has 30 days");
    EXPECT_CONTAINS(refused("0999-12-31", "12:00"), "year 999 is not 1000 .. 2999");
    EXPECT_CONTAINS(refused("3000-01-01", "12:00"), "year 3000");
    int y = 7, m = 7, d = 7;
    tp_error why = {{0}};
    EXPECT_EQ_INT(1, tp_sun_date_parse("2024-02-29", &y, &m, &d, &why));
    EXPECT_EQ_INT(29, d);
    EXPECT_EQ_INT(0, tp_sun_date_parse(NULL, &y, &m, &d, &why));
}

TEST(bad_times_and_zones_say_why)
{
    EXPECT_CONTAINS(refused("2026-06-21", "12"), "expected a time HH:MM[:SS]");
    EXPECT_CONTAINS(refused("2026-06-21", "1:30"), "HH:MM");
    EXPECT_CONTAINS(refused("2026-06-21", "12.30"), "HH:MM");
    EXPECT_CONTAINS(refused("2026-06-21", "24:00"), "hour 24 is not 0 .. 23");
    EXPECT_CONTAINS(refused("2026-06-21", "12:60"), "minute 60 is not 0 .. 59");
    EXPECT_CONTAINS(refused("2026-06-21", "12:30:60"), "second 60");
    EXPECT_CONTAINS(refused("2026-06-21", "12:30 CET"), "expected a zone Z, UTC, +HH");
    EXPECT_CONTAINS(refused("2026-06-21", "12:30+2"), "expected a zone");
    EXPECT_CONTAINS(refused("2026-06-21", "12:30+02:0"), "expected a zone");
    EXPECT_CONTAINS(refused("2026-06-21", "12:30+02:00x"), "expected a zone");
    EXPECT_CONTAINS(refused("2026-06-21", "12:30  Z"), "expected a zone");
    EXPECT_CONTAINS(refused("2026-06-21", "12:30 ZULU"), "expected a zone");
    EXPECT_CONTAINS(refused("2026-06-21", "12:30+15:00"), "+15:00 is beyond 14 hours");
    EXPECT_CONTAINS(refused("2026-06-21", "12:30-02:75"), "minutes 75");
    EXPECT_CONTAINS(refused("2026-02-30", "12:30"), "has 28 days"); /* the date first */
    EXPECT_CONTAINS(refused("2026-06-21", NULL), "HH:MM");
}

TEST(format_round_trips)
{
    char out[64];
    tp_sun_time_format(1782045000.0, 0, out, sizeof out);
    EXPECT_EQ_STR("2026-06-21 12:30:00 UTC", out);
    tp_sun_time_format(1782045000.0, 7200, out, sizeof out);
    EXPECT_EQ_STR("2026-06-21 14:30:00 +02:00", out);
    tp_sun_time_format(1782045000.4, -18000 - 1800, out, sizeof out);
    EXPECT_EQ_STR("2026-06-21 07:00:00 -05:30", out);
    tp_sun_time_format(-1.0, 0, out, sizeof out);
    EXPECT_EQ_STR("1969-12-31 23:59:59 UTC", out);
    tp_sun_time_format(NAN, 0, out, sizeof out);
    EXPECT_EQ_STR("-", out);
    /* every minute of a leap day and of a new year's eve, both ways */
    const char* dates[] = {"2024-02-29", "1999-12-31"};
    for (int k = 0; k < 2; ++k)
        for (int m = 0; m < 24 * 60; m += 7) {
            char time[16], want[64];
            snprintf(time, sizeof time, "%02d:%02d-03:00", m / 60, m % 60);
            tp_sun_time t;
            parse_ok(dates[k], time, &t);
            tp_sun_time_format(t.unix_s, -10800, out, sizeof out);
            snprintf(want, sizeof want, "%s %02d:%02d:00 -03:00", dates[k], m / 60, m % 60);
            EXPECT_EQ_STR(want, out);
        }
}

TP_TEST_MAIN(TESTS)
