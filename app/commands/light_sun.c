/*
 * light_sun.c - the sun over a place of the ground for `terrapatch light` at a moment
 * (cmd_light.c) and over a day (light_day.c): the place's latitude, longitude and meridian
 * convergence, the sun's azimuth turned to grid north, the day's sunrise and sunset printed
 * (light.h).
 */
#define _POSIX_C_SOURCE 200809L
#include "light.h"

#include "cli.h"
#include "ground_locate.h"
#include "sun_time.h"

#include <math.h>
#include <stdio.h>

void tp_light_print_day(const tp_sun_day* d, int zone_s)
{
    char a[48], b[48], c[48];
    if (d->kind == TP_SUN_UP_ALL_DAY) {
        tp_sun_time_format(d->transit_unix_s, zone_s, b, sizeof b);
        printf("day        polar day: the sun does not set (highest at %s)\n", b);
    } else if (d->kind == TP_SUN_DOWN_ALL_DAY) {
        printf("day        polar night: the sun does not rise\n");
    } else {
        tp_sun_time_format(d->rise_unix_s, zone_s, a, sizeof a);
        tp_sun_time_format(d->set_unix_s, zone_s, c, sizeof c);
        tp_sun_time_format(d->transit_unix_s, zone_s, b, sizeof b);
        printf("sunrise    %s\nnoon       %s (the sun highest)\nsunset     %s\n", a, b, c);
    }
}

int tp_light_place_at(const char* path, tp_ground* g, double x, double y, tp_light_place* out)
{
    tp_error err = {{0}};
    tp_ground_sample here;
    out->x = x, out->y = y;
    if (!tp_ground_grid_latlon(g, x, y, &out->lat_deg, &out->lon_deg) ||
        tp_ground_query_grid(g, x, y, &here, &err) != TP_OK || isnan(here.convergence_deg)) {
        tp_cli_error("%s: %s", path,
                     err.message[0] ? err.message
                                    : "no CRS: the sun needs the ground's latitude and longitude "
                                      "(give the DEM a CRS, e.g. with --crs)");
        return 0;
    }
    out->convergence_deg = here.convergence_deg;
    return 1;
}

tp_status tp_light_sun(const tp_light_place* p, double unix_s, tp_sun_pos* sun,
                       double* grid_azimuth_deg, tp_error* err)
{
    tp_status s = tp_sun_position(p->lat_deg, p->lon_deg, unix_s, sun, err);
    if (s != TP_OK)
        return s;
    *grid_azimuth_deg = tp_light_grid_azimuth(p, sun->azimuth_deg);
    return TP_OK;
}

double tp_light_grid_azimuth(const tp_light_place* p, double true_azimuth_deg)
{
    const double az = fmod(true_azimuth_deg - p->convergence_deg, 360.0);
    return az < 0.0 ? az + 360.0 : az;
}
