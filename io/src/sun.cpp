/*
 * sun.cpp - tp_sun.h over libnova: the sun's position, rise and set. The astronomy is
 * libnova's; what is ours is the correction of its solar longitude from the J2000 ecliptic to
 * the equinox of date and of the sign of its latitude (tp_sun.h says why), the azimuth counted
 * from north, and the checks.
 */
#include "io_util.hpp"
#include "tp_sun.h"

#include <libnova/dynamical_time.h>
#include <libnova/julian_day.h>
#include <libnova/nutation.h>
#include <libnova/refraction.h>
#include <libnova/rise_set.h>
#include <libnova/sidereal_time.h>
#include <libnova/solar.h>
#include <libnova/transform.h>

#include <algorithm>
#include <cmath>
#include <vector>

namespace {

using tpio::fail;

constexpr double kUnixEpochJd = 2440587.5; /* 1970-01-01 00:00 UTC */
constexpr double kJ2000 = 2451545.0;
/* Years 1000 .. 3000 as Unix seconds (VSOP87 as truncated in libnova, and Delta T beyond the
 * tables, are good for a few millennia around 2000; this range is well inside). */
constexpr double kMinUnix = -30610224000.0; /* 1000-01-01 */
constexpr double kMaxUnix = 32503680000.0;  /* 3000-01-01 */

double jd_from_unix(double unix_s) { return kUnixEpochJd + unix_s / 86400.0; }
double unix_from_jd(double jd) { return (jd - kUnixEpochJd) * 86400.0; }

/* The sun's apparent geocentric RA and declination at jd_ut: libnova's
 * ln_get_solar_equ_coords with the precession from J2000 to the date that it leaves out. */
void apparent_equ(double jd_ut, ln_equ_posn* out)
{
    const double jde = ln_get_jde(jd_ut);
    ln_helio_posn geom;
    ln_get_solar_geom_coords(jde, &geom); /* L on the J2000 ecliptic (VSOP87), R in AU */
    const double t = (jde - kJ2000) / 36525.0;
    const double precession_deg = (5029.0966 * t + 1.11113 * t * t) / 3600.0; /* Meeus 21.5 */
    ln_nutation nut;
    ln_get_nutation(jde, &nut);
    ln_lnlat_posn ecl;
    ecl.lng = geom.L + precession_deg + nut.longitude - (20.4898 / 3600.0) / geom.R;
    ecl.lat = -geom.B; /* libnova gives the Earth's heliocentric B: the sun's is -B */
    ln_get_equ_from_ecl(&ecl, jde, out); /* with the true obliquity of date */
}

tp_status check_place(double lat_deg, double lon_deg, tp_error* err)
{
    if (!(lat_deg >= -90.0 && lat_deg <= 90.0))
        return fail(err, TP_ERR_INVALID_ARG, "sun: latitude %g is outside -90 .. 90", lat_deg);
    if (!(lon_deg >= -180.0 && lon_deg <= 360.0))
        return fail(err, TP_ERR_INVALID_ARG, "sun: longitude %g is outside -180 .. 360",
                    lon_deg);
    return TP_OK;
}

tp_status check_time(double unix_s, tp_error* err)
{
    if (!(unix_s >= kMinUnix && unix_s < kMaxUnix))
        return fail(err, TP_ERR_INVALID_ARG,
                    "sun: time %g s is not between the years 1000 and 3000", unix_s);
    return TP_OK;
}

ln_lnlat_posn observer(double lat_deg, double lon_deg)
{
    ln_lnlat_posn o;
    o.lat = lat_deg;
    o.lng = lon_deg > 180.0 ? lon_deg - 360.0 : lon_deg; /* libnova: east positive */
    return o;
}

} // namespace

extern "C" double tp_sun_refraction_deg(double elevation_deg, double pressure_mbar,
                                        double temperature_c)
{
    if (std::isnan(elevation_deg) || std::isnan(pressure_mbar) || std::isnan(temperature_c))
        return NAN;
    if (elevation_deg >= -1.0)
        return ln_get_refraction_adj(elevation_deg, pressure_mbar, temperature_c);
    /* the formula turns over below about -1.5 degrees: faded out linearly to 0 at -5 */
    if (elevation_deg <= -5.0)
        return 0.0;
    return ln_get_refraction_adj(-1.0, pressure_mbar, temperature_c) * (elevation_deg + 5.0) / 4.0;
}

extern "C" tp_status tp_sun_position(double lat_deg, double lon_deg, double unix_utc_s,
                                     tp_sun_pos* out, tp_error* err)
{
    tp_status s = check_place(lat_deg, lon_deg, err);
    if (s == TP_OK)
        s = check_time(unix_utc_s, err);
    if (s != TP_OK)
        return s;
    const double jd = jd_from_unix(unix_utc_s);
    ln_equ_posn equ;
    apparent_equ(jd, &equ);
    ln_lnlat_posn obs = observer(lat_deg, lon_deg);
    ln_hrz_posn hrz;
    /* the apparent RA with the apparent sidereal time (ln_get_hrz_from_equ takes the mean one:
     * the equation of the equinoxes, up to 0.005 degree of hour angle, would be left out) */
    ln_get_hrz_from_equ_sidereal_time(&equ, &obs, ln_get_apparent_sidereal_time(jd), &hrz);
    tp_sun_pos r;
    r.azimuth_deg = std::fmod(hrz.az + 180.0, 360.0); /* libnova: from the south */
    if (r.azimuth_deg < 0.0)
        r.azimuth_deg += 360.0;
    if (r.azimuth_deg >= 360.0)
        r.azimuth_deg = 0.0;
    r.elevation_deg = hrz.alt;
    r.apparent_elevation_deg =
        hrz.alt + tp_sun_refraction_deg(hrz.alt, TP_SUN_PRESSURE_MBAR, TP_SUN_TEMPERATURE_C);
    r.ra_deg = equ.ra;
    r.dec_deg = equ.dec;
    r.jd_ut = jd;
    r.delta_t_s = ln_get_dynamical_time_diff(jd);
    *out = r;
    return TP_OK;
}

extern "C" tp_status tp_sun_rise_set(double lat_deg, double lon_deg, double day_start_unix_s,
                                     tp_sun_day* out, tp_error* err)
{
    tp_status s = check_place(lat_deg, lon_deg, err);
    if (s == TP_OK)
        s = check_time(day_start_unix_s, err);
    if (s != TP_OK)
        return s;
    ln_lnlat_posn obs = observer(lat_deg, lon_deg);
    const double jd0 = jd_from_unix(day_start_unix_s);
    ln_rst_time rst;
    const int rc = ln_get_body_next_rst_horizon(jd0, &obs, apparent_equ,
                                                TP_SUN_RISE_SET_ALTITUDE_DEG, &rst);
    tp_sun_day d;
    d.rise_unix_s = d.set_unix_s = d.transit_unix_s = NAN;
    if (rc == 1) {
        d.kind = TP_SUN_UP_ALL_DAY;
        d.transit_unix_s = unix_from_jd(rst.transit);
    } else if (rc != 0) {
        d.kind = TP_SUN_DOWN_ALL_DAY;
    } else {
        d.kind = TP_SUN_RISES_AND_SETS;
        d.rise_unix_s = unix_from_jd(rst.rise);
        d.set_unix_s = unix_from_jd(rst.set);
        d.transit_unix_s = unix_from_jd(rst.transit);
        if (d.set_unix_s < d.rise_unix_s) {
            /* the day started in daylight: the set that follows this rise */
            ln_rst_time next;
            if (ln_get_body_next_rst_horizon(rst.rise, &obs, apparent_equ,
                                             TP_SUN_RISE_SET_ALTITUDE_DEG, &next) == 0)
                d.set_unix_s = unix_from_jd(next.set);
        }
    }
    *out = d;
    return TP_OK;
}

extern "C" tp_status tp_sun_day_times(double lat_deg, double lon_deg, double start_unix_s,
                                      double end_unix_s, int count, double* times,
                                      tp_error* err)
{
    tp_status s = check_place(lat_deg, lon_deg, err);
    if (s == TP_OK)
        s = check_time(start_unix_s, err);
    if (s == TP_OK)
        s = check_time(end_unix_s, err);
    if (s != TP_OK)
        return s;
    if (count < 2 || !(end_unix_s > start_unix_s))
        return fail(err, TP_ERR_INVALID_ARG, "sun: %d times from %.0f to %.0f s", count,
                    start_unix_s, end_unix_s);
    try {
        /* the cumulative density 1 / sqrt(tan(max(e, 2 degrees))), a step a minute or less */
        const int steps = std::max(64, (int)std::ceil((end_unix_s - start_unix_s) / 60.0));
        const double dt = (end_unix_s - start_unix_s) / steps;
        std::vector<double> cum(steps + 1, 0.0);
        const double floor_tan = std::tan(2.0 * M_PI / 180.0);
        double prev = 0.0;
        for (int i = 0; i <= steps; ++i) {
            tp_sun_pos p;
            s = tp_sun_position(lat_deg, lon_deg, start_unix_s + i * dt, &p, err);
            if (s != TP_OK)
                return s;
            const double e = std::tan(p.apparent_elevation_deg * M_PI / 180.0);
            const double density = 1.0 / std::sqrt(std::max(e, floor_tan));
            if (i > 0)
                cum[i] = cum[i - 1] + 0.5 * (prev + density) * dt;
            prev = density;
        }
        int j = 0;
        for (int k = 0; k < count; ++k) {
            const double target = cum[steps] * k / (count - 1);
            while (j + 1 < steps && cum[j + 1] < target)
                ++j;
            const double span = cum[j + 1] - cum[j];
            const double f = span > 0.0 ? (target - cum[j]) / span : 0.0;
            times[k] = start_unix_s + (j + std::min(1.0, std::max(0.0, f))) * dt;
        }
        times[0] = start_unix_s;
        times[count - 1] = end_unix_s;
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, "sun");
    }
}

extern "C" long tp_sun_days_from_civil(int year, int month, int day)
{
    /* H. Hinnant, "chrono-Compatible Low-Level Date Algorithms", days_from_civil */
    const long y = (long)year - (month <= 2);
    const long era = (y >= 0 ? y : y - 399) / 400;
    const long yoe = y - era * 400;
    const long mp = (month + 9) % 12;
    const long doy = (153 * mp + 2) / 5 + day - 1;
    const long doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    return era * 146097 + doe - 719468;
}

extern "C" double tp_sun_local_day_start(int year, int month, int day, double lon_deg)
{
    return (double)tp_sun_days_from_civil(year, month, day) * 86400.0 - lon_deg * 240.0;
}
