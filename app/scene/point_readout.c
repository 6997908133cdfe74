/* point_readout.c - one position on the ground, described (point_readout.h). */
#include "point_readout.h"

#include "ground_locate.h"
#include "json.h"
#include "store_scene.h"

#include "tp_io.h"

#include <math.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>

/* What the source says of its vertical datum. A store names its sources in its notes
 * ("source: PATH" lines); the first one still on disk is asked. */
static void vertical_datum(const tp_ground* g, const char* source, char* out, size_t cap)
{
    char path[4096];
    snprintf(path, sizeof path, "%s", source);
    if (tp_is_store_path(source)) {
        const char* notes = tp_ground_scene(g)->info.header.notes;
        const char* s = notes ? strstr(notes, "source: ") : NULL;
        path[0] = '\0';
        if (s) {
            s += 8;
            size_t len = strcspn(s, "\n");
            if (len < sizeof path) {
                memcpy(path, s, len);
                path[len] = '\0';
            }
        }
    }
    tp_vertical_info v;
    if (!path[0] || tp_dem_vertical_info(path, &v, NULL) != TP_OK) {
        snprintf(out, cap, "unknown (the source is not at hand to say)");
        return;
    }
    tp_heights_datum(v.driver, v.datum, out, cap);
}

void tp_heights_datum(const char* driver, const char* vertical_datum, char* out, size_t cap)
{
    if (vertical_datum && vertical_datum[0])
        snprintf(out, cap, "%s (as the file states)", vertical_datum);
    else if (!strcmp(driver, "SRTMHGT") || !strcmp(driver, "DTED"))
        snprintf(out, cap, "not stated by the file; assumed EGM96 geoid (%s's specification)",
                 strcmp(driver, "DTED") ? "SRTM" : "DTED");
    else
        snprintf(out, cap, "unknown (the file states none)");
}

static int describe(tp_ground* g, const char* source, double lat, double lon,
                    const tp_ground_sample* gs, int precision, tp_point_readout* out, tp_error* err)
{
    tp_point_readout r;
    memset(&r, 0, sizeof r);
    snprintf(r.source, sizeof r.source, "%s", source);
    r.lat_deg = lat;
    r.lon_deg = lon;
    r.ground = *gs;
    r.mgrs_precision = precision;
    char mgrs[TP_MGRS_SIZE];
    if (tp_dms_encode(lat, TP_DMS_LATITUDE, 2, r.lat_dms, sizeof r.lat_dms, err) != TP_OK ||
        tp_dms_encode(lon, TP_DMS_LONGITUDE, 2, r.lon_dms, sizeof r.lon_dms, err) != TP_OK ||
        tp_geo_to_utmups(lat, lon, &r.zone, &r.northp, &r.easting_m, &r.northing_m, err) != TP_OK ||
        tp_zone_format(r.zone, r.northp, TP_ZONE_STYLE_SHORT, r.zone_text, sizeof r.zone_text,
                       err) != TP_OK ||
        tp_mgrs_forward(r.zone, r.northp, r.easting_m, r.northing_m, lat, precision, mgrs,
                        sizeof mgrs, err) != TP_OK)
        return 0;
    if (!tp_position_mgrs_spaced(mgrs, r.mgrs, sizeof r.mgrs))
        snprintf(r.mgrs, sizeof r.mgrs, "%s", mgrs);
    vertical_datum(g, source, r.vertical_datum, sizeof r.vertical_datum);
    *out = r;
    return 1;
}

/* Queries (e, n); writes err naming `where` for a position off the DEM or in a void. */
static int query(tp_ground* g, double e, double n, const char* where, tp_ground_sample* gs,
                 tp_error* err)
{
    tp_status s = tp_ground_query_world(g, e, n, gs, err);
    const tp_tree_geometry* geom = &tp_ground_scene(g)->info.header.geometry;
    if (s == TP_ERR_INVALID_ARG) {
        tp_error_set(err, s,
                     "position %s is outside the DEM (render CRS E %.1f N %.1f; the DEM covers "
                     "%d x %d posts)",
                     where, e, n, geom->src_width, geom->src_height);
        return 0;
    }
    if (s != TP_OK)
        return 0;
    if (isnan(gs->height_m)) {
        char hint[256];
        tp_ground_void_hint(g, gs->x, gs->y, hint, sizeof hint);
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "position %s is in a void: the DEM has no height there (grid x %.2f, y "
                     "%.2f)%s",
                     where, gs->x, gs->y, hint);
        return 0;
    }
    return 1;
}

int tp_point_readout_at_position(tp_ground* g, const char* source, const tp_position* pos,
                                 const char* input, int precision, tp_point_readout* out,
                                 tp_error* err)
{
    const tp_georef* geo = tp_ground_scene(g)->georef;
    if (!geo || !tp_georef_has_geo(geo)) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "has no CRS: a position on its ground needs a georeferenced DEM");
        return 0;
    }
    char where[600];
    snprintf(where, sizeof where, "'%s' (%.6f %.6f)", input, pos->lat_deg, pos->lon_deg);
    double e, n;
    tp_error why = {{0}};
    tp_status s = tp_georef_geo_to_proj(geo, pos->lat_deg, pos->lon_deg, &e, &n, &why);
    if (s != TP_OK) {
        tp_error_set(err, s, "position %s is outside the DEM (%s)", where, why.message);
        return 0;
    }
    tp_ground_sample gs;
    if (!query(g, e, n, where, &gs, err))
        return 0;
    return describe(g, source, pos->lat_deg, pos->lon_deg, &gs, precision, out, err);
}

int tp_point_readout_at_world(tp_ground* g, const char* source, double e_m, double n_m,
                              int precision, tp_point_readout* out, tp_error* err)
{
    const tp_georef* geo = tp_ground_scene(g)->georef;
    double lat, lon;
    tp_error why = {{0}};
    if (!geo || !tp_georef_has_geo(geo) ||
        tp_georef_proj_to_geo(geo, e_m, n_m, &lat, &lon, &why) != TP_OK) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "no geographic position at E %.1f N %.1f%s%s", e_m,
                     n_m, why.message[0] ? ": " : " (no CRS)", why.message);
        return 0;
    }
    char where[128];
    snprintf(where, sizeof where, "(%.6f %.6f)", lat, lon);
    tp_ground_sample gs;
    if (!query(g, e_m, n_m, where, &gs, err))
        return 0;
    return describe(g, source, lat, lon, &gs, precision, out, err);
}

/* "123.4 deg" or "flat" / "unknown". */
static const char* angle_text(double a, const char* none, char* buf, size_t cap)
{
    if (isnan(a))
        return none;
    snprintf(buf, cap, "%.1f deg", a);
    return buf;
}

void tp_point_readout_text(const tp_point_readout* r, char* out, size_t cap)
{
    const tp_ground_sample* s = &r->ground;
    char a1[32], a2[32], sl[32];
    const char* flat = isnan(s->slope_deg) ? "unknown" : "none (flat)";
    snprintf(out, cap,
             "latitude   %.8f  %s\n"
             "longitude  %.8f  %s\n"
             "MGRS       %s\n"
             "UTM        %s %.1f E %.1f N\n"
             "elevation  %.2f m (as stored; vertical datum: %s)\n"
             "slope      %s (%s)\n"
             "aspect     %s from true north (%s from grid north; convergence %.3f deg)\n"
             "grid       x %.2f y %.2f (render CRS E %.2f N %.2f)\n",
             r->lat_deg, r->lat_dms, r->lon_deg, r->lon_dms, r->mgrs, r->zone_text,
             r->easting_m, r->northing_m, s->height_m, r->vertical_datum,
             angle_text(s->slope_deg, "unknown (no neighbouring heights)", sl, sizeof sl),
             s->slope_method == TP_SLOPE_HORN
                 ? "Horn's 3x3 window, as gdaldem"
                 : "central differences, one post either side",
             angle_text(s->aspect_true_deg, flat, a1, sizeof a1),
             angle_text(s->aspect_grid_deg, flat, a2, sizeof a2), s->convergence_deg, s->x, s->y,
             s->e_m, s->n_m);
}

void tp_point_readout_hud(const tp_point_readout* r, char* out, size_t cap)
{
    const tp_ground_sample* s = &r->ground;
    char a1[32], sl[32];
    snprintf(out, cap,
             "here: %.6f %.6f  %s %s\n"
             "MGRS %s   UTM %s %.0f %.0f\n"
             "elevation %.1f m   slope %s   aspect %s true\n",
             r->lat_deg, r->lon_deg, r->lat_dms, r->lon_dms, r->mgrs, r->zone_text,
             r->easting_m, r->northing_m, s->height_m,
             angle_text(s->slope_deg, "unknown", sl, sizeof sl),
             angle_text(s->aspect_true_deg, "flat", a1, sizeof a1));
}

void tp_point_readout_json(const tp_point_readout* r, FILE* f)
{
    const tp_ground_sample* s = &r->ground;
    tp_json j;
    tp_json_init(&j, f);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "source", r->source);
    tp_json_member_number(&j, "lat_deg", r->lat_deg);
    tp_json_member_number(&j, "lon_deg", r->lon_deg);
    tp_json_member_string(&j, "lat_dms", r->lat_dms);
    tp_json_member_string(&j, "lon_dms", r->lon_dms);
    tp_json_member_string(&j, "mgrs", r->mgrs);
    tp_json_member_int(&j, "mgrs_precision", r->mgrs_precision);
    tp_json_key(&j, "utm");
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "zone", r->zone_text);
    tp_json_member_number(&j, "easting_m", r->easting_m);
    tp_json_member_number(&j, "northing_m", r->northing_m);
    tp_json_object_end(&j);
    tp_json_member_number(&j, "elevation_m", s->height_m);
    tp_json_member_string(&j, "vertical_datum", r->vertical_datum);
    tp_json_member_number(&j, "slope_deg", s->slope_deg);
    tp_json_member_string(&j, "slope_method", tp_slope_method_name(s->slope_method));
    tp_json_member_number(&j, "aspect_deg", s->aspect_true_deg);
    tp_json_member_number(&j, "aspect_grid_deg", s->aspect_grid_deg);
    tp_json_member_number(&j, "convergence_deg", s->convergence_deg);
    tp_json_key(&j, "grid");
    tp_json_object_begin(&j);
    tp_json_member_number(&j, "x", s->x);
    tp_json_member_number(&j, "y", s->y);
    tp_json_object_end(&j);
    tp_json_key(&j, "render");
    tp_json_object_begin(&j);
    tp_json_member_number(&j, "e_m", s->e_m);
    tp_json_member_number(&j, "n_m", s->n_m);
    tp_json_object_end(&j);
    tp_json_object_end(&j);
}
