/*
 * light.h - what `terrapatch light` at one moment (cmd_light.c) and over a day
 * (light_day.c, --day) share: the command line, the place the sun is computed for, the sun
 * turned to grid north, the day's sunrise and sunset printed.
 */
#ifndef TP_APP_CMD_LIGHT_H
#define TP_APP_CMD_LIGHT_H

#include "ground.h"
#include "planner_cli.h"
#include "scene.h"

#include "tp_sun.h"

typedef struct tp_light_cli {
    tp_planner_source src; /* the DEM or store, --cache-dir and the DEM options */
    const char* date;
    const char* time;
    const char* out;
    const char* at;
    const char* values;
    const char* json; /* --day: a JSON file or "-" */
    const char* sun;  /* --sun AZ,EL as given */
    double sun_deg[2]; /* --sun: the true azimuth and the elevation, degrees */
    double radius_m;
    int illumination; /* --values illumination */
    int day;          /* --day: the light map of the day (.tpl) */
    int maps;         /* --day: sun positions (2 ..) */
    double margin_m;  /* --day: ground beyond a tile that may shadow it */
    int quiet;        /* --day: no progress */
    int hours;        /* --day with a raster -o (not .tpl): the hours of sunlight per post */
} tp_light_cli;

/* --day's defaults */
#define TP_LIGHT_DAY_MAPS 64
#define TP_LIGHT_DAY_MAPS_MAX 1024
#define TP_LIGHT_DAY_MARGIN_M 10000.0

/* 1 when path names a light map (.tpl: --day's default output), 0 for any other output. */
int tp_light_is_map(const char* path);

/* Where the sun is computed: grid post (x, y), its latitude and longitude, the meridian
 * convergence there (grid north's bearing from true north, degrees). */
typedef struct tp_light_place {
    double x, y, lat_deg, lon_deg, convergence_deg;
} tp_light_place;

/* The place at grid (x, y) of g (opened from path): 1, or 0 after one line naming path (no
 * CRS, a read error). */
int tp_light_place_at(const char* path, tp_ground* g, double x, double y, tp_light_place* out);

/* A true azimuth (clockwise from true north) turned to grid north at the place: in [0, 360),
 * the true one less the convergence (what tp_light_sun does with the sun's). */
double tp_light_grid_azimuth(const tp_light_place* p, double true_azimuth_deg);

/* The sun at unix_s over the place: *sun (true azimuth) and the azimuth from grid north in
 * [0, 360) (the true one less the convergence). tp_sun_position's errors. */
tp_status tp_light_sun(const tp_light_place* p, double unix_s, tp_sun_pos* sun,
                       double* grid_azimuth_deg, tp_error* err);

/* The sunrise, transit and sunset lines (or the polar day's or night's) on stdout. */
void tp_light_print_day(const tp_sun_day* d, int zone_s);

/* `terrapatch light ... --day` once the command line is read (light_day.c): the light map
 * (.tpl), or with o->hours the raster of the hours of sunlight; the exit code. */
int tp_light_day_run(const tp_light_cli* o);

#endif /* TP_APP_CMD_LIGHT_H */
