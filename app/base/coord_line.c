/*
 * coord_line.c - one line of `terrapatch coord` input parsed and converted (coord_line.h).
 *
 * A position line is read by tp_position_parse (position.c, shared with every command that
 * takes a position: decimal degrees, DMS, LAT,LON, ZONE E N, MGRS); --geodesic lines are read
 * here, strictly (whole-token numbers, nothing left over). Every conversion is GeographicLib's,
 * through io/include/tp_geo.h.
 */
#include "coord_line.h"
#include "position_int.h"

#include "tp_core.h"
#include "tp_geo.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---------------------------------------------------------------------------------------------
 * Converting
 */

/* -0.0 prints as "-0.000"; a computed exact zero should not. */
static double unsigned_zero(double v)
{
    return v + 0.0;
}

/* The standard UTM/UPS zone of pos and its coordinates there. Grid input already in that zone
 * keeps its own easting and northing, exactly as given, and on the equator its own hemisphere
 * (as GeoConvert does; see tp_utmups_to_standard). */
static int standard_grid(const tp_position* pos, int* zone, int* northp, double* e, double* n,
                         tp_error* err)
{
    tp_status s = pos->has_grid
                      ? tp_utmups_to_standard(pos->zone, pos->northp, pos->easting_m,
                                              pos->northing_m, zone, northp, e, n, err)
                      : tp_geo_to_utmups(pos->lat_deg, pos->lon_deg, zone, northp, e, n, err);
    return s == TP_OK ? 1 : tp__position_failed(s, err);
}

/* Converts one parsed position and writes the output line into out (TP_COORD_TEXT_SIZE bytes).
 * Returns 1, or 0 with the reason in err. */
static int convert_position(const tp_coord_request* o, const tp_position* pos, char* out,
                            tp_error* err)
{
    tp_status s;
    int zone, northp;
    double e, n;
    if (pos->has_h && o->to != TP_COORD_TO_ECEF) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "a height (LAT LON H) is only used with --to ecef");
        return 0;
    }
    switch (o->to) {
    case TP_COORD_TO_GEO:
        snprintf(out, TP_COORD_TEXT_SIZE, "%.9f %.9f", unsigned_zero(pos->lat_deg),
                 unsigned_zero(pos->lon_deg));
        return 1;
    case TP_COORD_TO_UTM: {
        if (!standard_grid(pos, &zone, &northp, &e, &n, err))
            return 0;
        char zone_name[TP_ZONE_TEXT_SIZE];
        s = tp_zone_format(zone, northp, TP_ZONE_STYLE_GEOCONVERT, zone_name, sizeof zone_name,
                           err);
        if (s != TP_OK)
            return tp__position_failed(s, err);
        snprintf(out, TP_COORD_TEXT_SIZE, "%s %.3f %.3f", zone_name, unsigned_zero(e),
                 unsigned_zero(n));
        return 1;
    }
    case TP_COORD_TO_MGRS: {
        char mgrs[TP_MGRS_SIZE];
        if (!standard_grid(pos, &zone, &northp, &e, &n, err))
            return 0;
        s = tp_mgrs_forward(zone, northp, e, n, pos->lat_deg, o->precision, mgrs, sizeof mgrs, err);
        if (s != TP_OK)
            return tp__position_failed(s, err);
        snprintf(out, TP_COORD_TEXT_SIZE, "%s", mgrs);
        return 1;
    }
    case TP_COORD_TO_ECEF: {
        double x, y, z;
        s = tp_geo_to_ecef(pos->lat_deg, pos->lon_deg, pos->h_m, &x, &y, &z, err);
        if (s != TP_OK)
            return tp__position_failed(s, err);
        snprintf(out, TP_COORD_TEXT_SIZE, "%.6f %.6f %.6f", unsigned_zero(x), unsigned_zero(y),
                 unsigned_zero(z));
        return 1;
    }
    }
    tp_error_set(err, TP_ERR_INVALID_ARG, "unknown output kind %d", (int)o->to);
    return 0;
}

static int convert_geodesic(const fields* f, char* out, tp_error* err)
{
    char* const* field = f->field;
    static const char* const names[4] = {"lat1", "lon1", "lat2", "lon2"};
    double v[4];
    if (f->count != 4) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "expected LAT1 LON1 LAT2 LON2 (4 numbers), got %d field%s", f->count,
                     f->count == 1 ? "" : "s");
        return 0;
    }
    for (int i = 0; i < 4; ++i)
        if (!tp__position_read_number(field[i], names[i], &v[i], err))
            return 0;
    double azi1, azi2, s12;
    tp_status s = tp_geodesic_inverse(v[0], v[1], v[2], v[3], &azi1, &azi2, &s12, err);
    if (s != TP_OK)
        return tp__position_failed(s, err);
    snprintf(out, TP_COORD_TEXT_SIZE, "%.12f %.12f %.9f", unsigned_zero(azi1), unsigned_zero(azi2),
             unsigned_zero(s12));
    return 1;
}

int tp_coord_line_convert(const tp_coord_request* req, char* line, size_t len, char* out,
                          size_t out_size, tp_error* err)
{
    assert(req && line && out && out_size >= TP_COORD_TEXT_SIZE);
    (void)out_size;
    if (strlen(line) != len) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "the line contains a NUL byte");
        return 0;
    }
    if (req->geodesic) {
        fields f = tp__position_split(line, 0);
        return convert_geodesic(&f, out, err);
    }
    tp_position pos;
    return tp_position_parse(line, len, 1, &pos, err) && convert_position(req, &pos, out, err);
}
