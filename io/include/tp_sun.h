/*
 * tp_sun.h - where the sun is: its position in the sky at a place and time, and when it rises
 * and sets there (io/src/sun.cpp, over libnova; `terrapatch light`, docs/light.md).
 *
 * The astronomy is libnova's (Debian's libnova-dev 0.16): the sun's geometric position from
 * VSOP87 (ln_get_solar_geom_coords), nutation (ln_get_nutation), the ecliptic-to-equatorial
 * and equatorial-to-horizontal transforms (ln_get_equ_from_ecl, ln_get_hrz_from_equ, with
 * the apparent sidereal time), Delta T (ln_get_jde), refraction (ln_get_refraction_adj) and
 * rise/set/transit (ln_get_body_next_rst_horizon). Two corrections are ours, for errors of
 * libnova 0.16's ln_get_solar_equ_coords: it leaves the VSOP87 longitude on the ecliptic and
 * equinox of J2000 (0.10 degree of RA off in 1992, 0.40 on 2026-06-21: the "0.39 degree" of
 * Stellarium issue 672), so we add the general precession in longitude
 * p = 5029.0966" T + 1.11113" T^2 (Meeus, Astronomical Algorithms, 2nd ed., eq. 21.5; T in
 * Julian centuries of TD from J2000); and it takes the Earth's heliocentric latitude B as the
 * sun's geocentric one, whose sign is the opposite (1.3" of declination in 1992). Nutation and
 * aberration (-20.4898" / R) are added as libnova does, and the horizontal position uses the
 * apparent sidereal time (ln_get_hrz_from_equ would use the mean one). tests/test_sun.c checks
 * the result against Meeus' examples 25.a and 25.b and the NREL SPA worked example (Reda &
 * Andreas 2004).
 *
 * Accuracy (measured in tests/test_sun.c): apparent RA and declination within 0.1" of Meeus'
 * VSOP87 example 25.b and 0.4" / 0.7" of the SPA's; azimuth within 0.001 degree and elevation
 * within 0.003 degree of the SPA's topocentric values (the position is geocentric: the sun's
 * parallax, at most 8.8", is left out); sunrise within 2 s of the SPA's.
 *
 * Angles are degrees; latitude north positive, longitude east positive (WGS84, geodetic);
 * times are Unix seconds, UTC (POSIX: no leap seconds), as doubles.
 */
#ifndef TP_SUN_H
#define TP_SUN_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The standard atmosphere of the apparent elevation: 1010 mbar, 10 degrees C (libnova's and
 * the SPA's defaults). */
#define TP_SUN_PRESSURE_MBAR 1010.0
#define TP_SUN_TEMPERATURE_C 10.0
/* The altitude of the sun's centre at rise and set: -0.8333 degree (34' of refraction at the
 * horizon and 16' of semidiameter: the upper limb touches the horizon; libnova's
 * LN_SOLAR_STANDART_HORIZON, the SPA's h0'). */
#define TP_SUN_RISE_SET_ALTITUDE_DEG (-0.8333)

typedef struct tp_sun_pos {
    double azimuth_deg;   /* clockwise from TRUE north, [0, 360): 90 east, 180 south. (libnova's
                             ln_hrz_posn.az counts from the south; converted here.) */
    double elevation_deg; /* geometric (airless) elevation of the centre above the horizon,
                             geocentric, -90 .. 90 */
    double apparent_elevation_deg; /* elevation_deg plus refraction at TP_SUN_PRESSURE_MBAR and
                                      TP_SUN_TEMPERATURE_C (tp_sun_refraction_deg) */
    double ra_deg;        /* apparent geocentric right ascension, equinox of date, [0, 360) */
    double dec_deg;       /* apparent geocentric declination, equinox of date */
    double jd_ut;         /* the Julian day (UT) of the time given */
    double delta_t_s;     /* TD - UT used (libnova's table and formula) */
} tp_sun_pos;

/* The sun's position seen from (lat_deg, lon_deg) at unix_utc_s. TP_ERR_INVALID_ARG (message
 * naming the value) for a latitude outside -90 .. 90, a longitude outside -180 .. 360, a
 * non-finite time or one outside the years 1000 .. 3000 (VSOP87's and Delta T's range as
 * libnova uses them); *out written only on success. Thread-safe (libnova keeps no state). */
tp_status tp_sun_position(double lat_deg, double lon_deg, double unix_utc_s, tp_sun_pos* out,
                          tp_error* err);

/* The atmospheric refraction (degrees, >= 0) that lifts a body at geometric elevation_deg, at
 * pressure_mbar and temperature_c: libnova's ln_get_refraction_adj (Meeus' eq. 16.4,
 * Saemundsson's formula) from -1 degree up; below, where that formula turns over (it gives
 * 0.91 at -2 and -0.09 at -6 degrees), its value at -1 degree faded linearly to 0 at -5 degrees
 * and 0 below. Cannot fail; NaN in, NaN out. */
double tp_sun_refraction_deg(double elevation_deg, double pressure_mbar, double temperature_c);

/* What the sun does on one day at a place. */
typedef enum tp_sun_day_kind {
    TP_SUN_RISES_AND_SETS = 0,
    TP_SUN_UP_ALL_DAY = 1,  /* polar day: its centre stays above TP_SUN_RISE_SET_ALTITUDE_DEG */
    TP_SUN_DOWN_ALL_DAY = 2 /* polar night: it stays below */
} tp_sun_day_kind;

typedef struct tp_sun_day {
    tp_sun_day_kind kind;
    double rise_unix_s;    /* with TP_SUN_RISES_AND_SETS; NaN otherwise */
    double set_unix_s;     /* with TP_SUN_RISES_AND_SETS (after rise_unix_s); NaN otherwise */
    double transit_unix_s; /* the sun's upper transit (local noon), NaN in polar night */
} tp_sun_day;

/* Sunrise, transit and sunset of the local day that starts at day_start_unix_s (e.g. the
 * date's midnight in local mean solar time: date 00:00 UTC - lon_deg / 15 hours; see
 * tp_sun_local_day_start): the first rise, set and transit within 24 hours after it (libnova's
 * ln_get_body_next_rst_horizon over the corrected position, horizon
 * TP_SUN_RISE_SET_ALTITUDE_DEG). A day whose set comes before its rise (the day does not start
 * at night) gets the set after the rise. Errors as tp_sun_position; *out written only on
 * success. */
tp_status tp_sun_rise_set(double lat_deg, double lon_deg, double day_start_unix_s,
                          tp_sun_day* out, tp_error* err);

/* count times (count >= 2) from start_unix_s to end_unix_s (both included; e.g. a day's rise
 * and set) for the maps of a day (tp_light_day_build), closer where the sun is low, where
 * shadows are long and move fast: the spacing is proportional to sqrt(tan(max(e, 2 degrees)))
 * of the sun's apparent elevation e (with 64 maps over a June day at 45 N: about 4 minutes
 * apart at sunrise, 36 at noon), from the elevation every minute. Errors as tp_sun_position,
 * and TP_ERR_INVALID_ARG for count < 2 or end <= start; times written only on success. */
tp_status tp_sun_day_times(double lat_deg, double lon_deg, double start_unix_s,
                           double end_unix_s, int count, double* times, tp_error* err);

/* Days from 1970-01-01 to a proleptic Gregorian date (negative before; H. Hinnant's
 * days_from_civil). Cannot fail. */
long tp_sun_days_from_civil(int year, int month, int day);

/* The start of a date's day in local mean solar time at lon_deg: (days since 1970-01-01 of
 * the date) * 86400 - lon_deg * 240 seconds. Cannot fail. */
double tp_sun_local_day_start(int year, int month, int day, double lon_deg);

#ifdef __cplusplus
}
#endif
#endif /* TP_SUN_H */
