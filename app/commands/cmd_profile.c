/*
 * cmd_profile.c - `terrapatch profile DEM|STORE --route FILE|--through POS ...`: the elevation
 * profile of a route (issue 13, section 5). The route is read by io's tp_vector_read (any vector
 * file OGR opens, reprojected into the render CRS), or given as positions on the command line
 * (--through, repeated or ';'-separated, issue 31: planner_cli.h's list of positions, placed on
 * the ground as `los` places its ends); one line is sampled on the full-resolution ground
 * (ground.c, as `point` and `los` read it) and measured: lengths along the ground, on the map
 * and on the ellipsoid, climb and descent, the steepest piece, the lowest and highest points.
 * Outputs as `los`: text, --json, --csv (atomic_file.c), --png (gnuplot.c).
 */
#include "terrapatch.h"
#include "cli.h"
#include "json.h"
#include "output_check.h"
#include "planner_cli.h"

#include "tp_core.h"
#include "tp_geo.h"
#include "tp_io.h"
#include "tp_vector.h"

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* More samples than this is a --step too small for the route (8 doubles each: 640 MB). */
#define PROFILE_MAX_SAMPLES 10000000u

typedef struct profile_options {
    tp_planner_source src; /* the DEM or store, --cache-dir and the DEM options */
    const char* route;
    const char** through; /* the values of --through, in order (argv's; malloc'd array) */
    size_t through_count;
    tp_planner_positions positions; /* read from them */
    const char* label;              /* for messages: the route's file, or "--through" */
    const char* png;
    const char* csv;
    const char* json;
    double step_m;   /* 0: the grid spacing */
    int feature;     /* 1-based among the lines; 0: the first */
} profile_options;

static void print_help(void)
{
    tp_planner_help(
        "usage: terrapatch profile DEM|STORE --route FILE [--feature N] [--step M]\n"
        "                          [--json F] [--csv F] [--png F] [--cache-dir DIR]\n"
        "       terrapatch profile DEM|STORE --through POS --through POS [--through POS ...]\n"
        "                          [--step M] [--json F] [--csv F] [--png F] ...\n"
        "\n"
        "The elevation profile of a route over the ground of DEM (any raster GDAL reads, built\n"
        "into the store cache first as 'terrapatch view' does) or of a store (.tpt).\n"
        "\n"
        "FILE: any vector file OGR reads (GPX, KML, GeoJSON, Shapefile, GeoPackage, ...),\n"
        "reprojected into the DEM's render CRS. The route is one line of it: its lines are\n"
        "numbered in file order (every layer; a GPX file's routes and tracks, each track\n"
        "segment a line of its own); the first is taken unless --feature N names another.\n"
        "Points and polygons are not routes (they are overlays for 'terrapatch view').\n"
        "\n"
        "Or the route is the positions given with --through, in the order given: one\n"
        "position each time the option is given (--through 45.37,-121.69 --through\n"
        "\"45.40 -121.70\"), or several in one value, separated by ';' (--through\n"
        "\"45.37,-121.69; 45.40,-121.70\"), 2 or more in all; each in any form 'terrapatch\n"
        "coord' reads (quote one with spaces; a value may start with '-'), on the DEM and\n"
        "not in a void.\n"
        "\n"
        "The line is sampled on the full-resolution ground ('terrapatch point' reads the same)\n"
        "at every vertex and between them every --step metres or less (each leg split into\n"
        "equal pieces). Reported: length along the ground (3D: the samples joined by straight\n"
        "pieces), on the map (2D: the render grid's plane) and on the WGS84 ellipsoid\n"
        "(geodesics between the vertices), total climb and descent (sums of the rises and\n"
        "falls between samples, unsmoothed), the steepest piece between two samples (grade in\n"
        "per cent, signed in the direction of travel), the lowest and highest points.\n"
        "Heights are as stored (SRTM: above the EGM96 geoid).\n"
        "\n"
        "options:\n"
        "  --route FILE     the route (this or --through is required)\n"
        "  --feature N      the Nth line of FILE (default 1)\n"
        "  --through POS    a position of the route (repeated; or POS;POS;...)\n"
        "  --step M         largest distance between samples, metres (default: the grid\n"
        "                   spacing)\n"
        "  --json F         also write the figures as JSON to F ('-' for stdout, instead of\n"
        "                   the text)\n"
        "  --csv F          write the samples as CSV: distance_m, e_m, n_m, lat, lon,\n"
        "                   elevation_m, grade_pct (of the piece ending there)\n"
        "  --png F          draw the profile (gnuplot), the steepest piece marked\n"
        "  -h, --help       show this help\n",
        "example:\n"
        "  $ terrapatch profile N42E001.hgt --route coma_pedrosa.gpx --png profile.png\n"
        "  $ terrapatch profile N42E001.hgt --through 42.5722,1.4840 --through 42.5931,1.4442\n"
        "\n"
        "The files given (--json, --csv, --png) are written all or none: when one cannot be\n"
        "(a full disk, gnuplot missing), none is, and older files stay as they were.\n"
        "\n"
        "Exit status: 0 done; 1 the DEM or FILE cannot be read, FILE has no line (or no Nth),\n"
        "a --through position is off the DEM or in a void, the route leaves the DEM or\n"
        "crosses a void (nothing is written then), an output cannot be written (then none\n"
        "is); 2 usage error (a --png not .png, a position that cannot be read included).\n");
}

/* --through POS (tp_option_handler): kept in order, read once the parse is done. */
static int through_option(void* ctx, int code, const char* value, const char* cmd)
{
    (void)code, (void)cmd;
    profile_options* o = ctx;
    const char** more = realloc(o->through, (o->through_count + 1) * sizeof *more);
    if (!more) {
        tp_cli_error("out of memory for --through");
        return -1;
    }
    o->through = more;
    o->through[o->through_count++] = value;
    return 1;
}

/* -1 when fine, else the exit code. */
static int parse_options(int argc, char** argv, profile_options* o)
{
    memset(o, 0, sizeof *o);
    tp_planner_source_init(&o->src);
    const tp_option options[] = {
        TP_OPT_CODE("--through", NULL, 1, 1),
        TP_OPT_TEXT("--route", NULL, &o->route),
        TP_OPT_TEXT("--png", NULL, &o->png),
        TP_OPT_TEXT("--csv", NULL, &o->csv),
        TP_OPT_TEXT("--json", NULL, &o->json),
        TP_OPT_NUMBER_ABOVE("--step", &o->step_m, 0.0, HUGE_VAL, "a number of metres > 0"),
        TP_OPT_INTEGER("--feature", &o->feature, 1, INT_MAX, "an integer >= 1"),
    };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), through_option, o};
    const int code = tp_planner_parse("profile", argc, argv, print_help, own, &o->src,
                                      " (quote a position with spaces: --through "
                                      "\"45.37 -121.69\")");
    if (code >= 0)
        return code;
    if (o->route && o->through)
        return tp_cli_usage("profile", "--route and --through exclude each other");
    if (!o->route && !o->through)
        return tp_cli_usage("profile", "missing --route FILE (or --through POS --through POS)");
    if (o->through && o->feature)
        return tp_cli_usage("profile", "--feature N picks a line of --route FILE; --through "
                                       "gives the route itself");
    o->label = o->route ? o->route : "--through";
    if (o->through) {
        if (!tp_planner_positions_read("profile", "--through", o->through, o->through_count,
                                       &o->positions))
            return TP_EXIT_USAGE;
        if (o->positions.count < 2)
            return tp_cli_usage("profile",
                                "--through: a route needs 2 positions or more, got "
                                "one ('%s')",
                                o->positions.text[0]);
    }
    return -1;
}

typedef struct profile_sample {
    double d_m;       /* along the map (2D) from the start */
    double e_m, n_m;  /* render CRS */
    double lat, lon;
    double h_m;       /* ground, as stored */
} profile_sample;

/* Everything the outputs print. */
typedef struct profile_report {
    const profile_options* o;
    const tp_features* f;
    const tp_georef* georef;
    const tp_feature* line;
    size_t line_number, line_count;
    double step_m;
    profile_sample* s;
    size_t n;
    double length_2d_m, length_3d_m, length_geodesic_m;
    double climb_m, descent_m;
    size_t lo, hi;           /* samples of the lowest and highest ground */
    size_t steep;            /* the steepest piece runs from sample steep - 1 to steep; 0: none */
    double steep_grade_pct;  /* signed: + uphill in the direction of travel */
} profile_report;

/* WGS 84 as tp_vector_read takes a CRS (WKT; longitude first, as it reads every CRS). */
#define WGS84_WKT                                                                                  \
    "GEOGCS[\"WGS 84\",DATUM[\"WGS_1984\",SPHEROID[\"WGS 84\",6378137,298.257223563]],"            \
    "PRIMEM[\"Greenwich\",0],UNIT[\"degree\",0.0174532925199433]]"

/* Where sample q is, for messages: "LAT LON; render CRS E .. N .." (without the latitude and
 * longitude where they cannot be had: far outside the render CRS's zone). */
static void describe_place(const profile_sample* q, char* out, size_t cap)
{
    if (isfinite(q->lat) && isfinite(q->lon))
        snprintf(out, cap, "%.6f %.6f; render CRS E %.1f N %.1f", q->lat, q->lon, q->e_m, q->n_m);
    else
        snprintf(out, cap, "render CRS E %.1f N %.1f", q->e_m, q->n_m);
}

/* The message for a route whose sample q is off the DEM (the first one when first). */
static void report_outside(tp_ground* g, const profile_report* p, const profile_sample* q,
                           int first)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const double* gt = sc->info.header.geotransform;
    const int w = sc->info.header.geometry.src_width, h = sc->info.header.geometry.src_height;
    char where[200];
    describe_place(q, where, sizeof where);
    tp_features* wgs84 = NULL;
    if (first && p->o->route && !(isfinite(q->lat) && isfinite(q->lon)) &&
        tp_vector_read(p->o->route, WGS84_WKT, &wgs84, NULL) == TP_OK &&
        wgs84->count == p->f->count) {
        /* too far from the render CRS's zone to go back: the route's own latitude/longitude */
        const double* ll = wgs84->xy + 2 * wgs84->items[p->line - p->f->items].first;
        snprintf(where, sizeof where, "%.6f %.6f; render CRS E %.1f N %.1f", ll[1], ll[0], q->e_m,
                 q->n_m);
    }
    tp_features_destroy(wgs84);
    if (!first) {
        tp_cli_error("%s: the route (%s) leaves the DEM at %.1f m along it "
                     "(%s): nothing written",
                     p->o->src.path, p->o->label, q->d_m, where);
        return;
    }
    /* does any vertex lie on the DEM? */
    const double* v = p->f->xy + 2 * p->line->first;
    int inside = 0;
    for (size_t i = 0; i < p->line->count && !inside; ++i) {
        double x, y;
        tp_tree_world_to_grid(sc->tree, v[2 * i], v[2 * i + 1], &x, &y);
        inside = x >= 0.0 && y >= 0.0 && x <= w - 1.0 && y <= h - 1.0;
    }
    tp_cli_error("%s: the route (%s) %s the DEM: its start is at %s, and the "
                 "DEM covers E %.1f .. %.1f, N %.1f .. %.1f (render CRS): nothing written",
                 p->o->src.path, p->o->label, inside ? "starts outside" : "lies outside", where,
                 gt[0] + 0.5 * gt[1], gt[0] + (w - 0.5) * gt[1], gt[3] + (h - 0.5) * gt[5],
                 gt[3] + 0.5 * gt[5]);
}

/* Samples the line on the ground. 1, or 0 after one line naming the file and where. */
static int sample_route(tp_ground* g, profile_report* p)
{
    const tp_store_scene* sc = tp_ground_scene(g);
    const double* v = p->f->xy + 2 * p->line->first;
    const size_t nv = p->line->count;
    size_t n = 1;
    for (size_t i = 1; i < nv; ++i) {
        double len = hypot(v[2 * i] - v[2 * i - 2], v[2 * i + 1] - v[2 * i - 1]);
        double pieces = fmax(1.0, ceil(len / p->step_m));
        if (pieces > PROFILE_MAX_SAMPLES || n + (size_t)pieces > PROFILE_MAX_SAMPLES) {
            tp_cli_error("%s: the route needs more than %u samples at --step "
                         "%g m: give a larger --step",
                         p->o->label, PROFILE_MAX_SAMPLES, p->step_m);
            return 0;
        }
        n += (size_t)pieces;
    }
    p->s = malloc(n * sizeof *p->s);
    if (!p->s) {
        tp_cli_error("out of memory for %zu samples", n);
        return 0;
    }
    size_t k = 0;
    double d = 0.0;
    for (size_t i = 0; i < nv; ++i) {
        size_t pieces = 1;
        double len = 0.0;
        if (i + 1 < nv) {
            len = hypot(v[2 * i + 2] - v[2 * i], v[2 * i + 3] - v[2 * i + 1]);
            pieces = (size_t)fmax(1.0, ceil(len / p->step_m));
        }
        /* the vertex, then the inner samples of the leg after it (the last vertex alone) */
        for (size_t j = 0; j < (i + 1 < nv ? pieces : 1); ++j) {
            double t = (double)j / (double)pieces;
            profile_sample* q = &p->s[k++];
            q->e_m = i + 1 < nv ? v[2 * i] + t * (v[2 * i + 2] - v[2 * i]) : v[2 * i];
            q->n_m = i + 1 < nv ? v[2 * i + 1] + t * (v[2 * i + 3] - v[2 * i + 1]) : v[2 * i + 1];
            q->d_m = d + t * len;
            q->lat = q->lon = NAN;
            tp_georef_proj_to_geo(sc->georef, q->e_m, q->n_m, &q->lat, &q->lon, NULL);
            double x, y;
            tp_tree_world_to_grid(sc->tree, q->e_m, q->n_m, &x, &y);
            tp_error err = {{0}};
            tp_status st = tp_ground_height(g, x, y, &q->h_m, &err);
            if (st == TP_ERR_INVALID_ARG) {
                report_outside(g, p, q, k == 1);
                return 0;
            }
            if (st != TP_OK) {
                tp_cli_error("%s: %s", p->o->src.path, err.message);
                return 0;
            }
            if (isnan(q->h_m)) {
                tp_cli_error(
                    "%s: the route (%s) crosses a void at %.1f m along "
                    "it (%.6f %.6f): the DEM has no height there, so its profile cannot be "
                    "measured: nothing written",
                    p->o->src.path, p->o->label, q->d_m, q->lat, q->lon);
                return 0;
            }
        }
        d += len;
    }
    p->n = k;
    return 1;
}

static void measure(profile_report* p)
{
    const profile_sample* s = p->s;
    p->lo = p->hi = 0;
    double steep = -1.0;
    for (size_t i = 0; i < p->n; ++i) {
        if (s[i].h_m < s[p->lo].h_m)
            p->lo = i;
        if (s[i].h_m > s[p->hi].h_m)
            p->hi = i;
        if (i == 0)
            continue;
        double dd = s[i].d_m - s[i - 1].d_m, dh = s[i].h_m - s[i - 1].h_m;
        p->length_2d_m += dd;
        p->length_3d_m += sqrt(dd * dd + dh * dh);
        if (dh > 0)
            p->climb_m += dh;
        else
            p->descent_m -= dh;
        if (dd > 0 && fabs(dh) / dd > steep) {
            steep = fabs(dh) / dd;
            p->steep = i;
            p->steep_grade_pct = 100.0 * dh / dd;
        }
    }
    /* the ellipsoid: geodesics between the vertices (NaN when one has no lat/lon) */
    const double* v = p->f->xy + 2 * p->line->first;
    double lat0 = NAN, lon0 = NAN;
    p->length_geodesic_m = 0.0;
    for (size_t i = 0; i < p->line->count; ++i) {
        double lat = NAN, lon = NAN, a1, a2, len = NAN;
        tp_georef_proj_to_geo(p->georef, v[2 * i], v[2 * i + 1], &lat, &lon, NULL);
        if (i && tp_geodesic_inverse(lat0, lon0, lat, lon, &a1, &a2, &len, NULL) != TP_OK)
            len = NAN;
        if (i)
            p->length_geodesic_m += len;
        lat0 = lat;
        lon0 = lon;
    }
}

static void write_point(tp_json* j, const char* key, const profile_sample* s)
{
    tp_json_key(j, key);
    tp_json_object_begin(j);
    tp_json_member_number(j, "distance_m", s->d_m);
    tp_json_member_number(j, "lat", s->lat);
    tp_json_member_number(j, "lon", s->lon);
    tp_json_member_number(j, "elevation_m", s->h_m);
    tp_json_object_end(j);
}

static void write_json(FILE* f, void* report)
{
    const profile_report* p = report;
    tp_json j;
    tp_json_init(&j, f);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "source", p->o->src.path);
    tp_json_member_string(&j, "route", p->o->route);
    tp_json_key(&j, "through");
    if (p->o->positions.count) {
        tp_json_array_begin(&j);
        for (size_t i = 0; i < p->o->positions.count; ++i)
            tp_json_string(&j, p->o->positions.text[i]);
        tp_json_array_end(&j);
    } else {
        tp_json_null(&j);
    }
    tp_json_member_size(&j, "feature", p->line_number);
    tp_json_member_size(&j, "lines", p->line_count);
    tp_json_member_string(&j, "name", p->line->name);
    tp_json_member_size(&j, "vertices", p->line->count);
    tp_json_member_size(&j, "samples", p->n);
    tp_json_member_number(&j, "step_m", p->step_m);
    tp_json_member_number(&j, "length_3d_m", p->length_3d_m);
    tp_json_member_number(&j, "length_2d_m", p->length_2d_m);
    tp_json_member_number(&j, "length_geodesic_m", p->length_geodesic_m);
    tp_json_member_number(&j, "climb_m", p->climb_m);
    tp_json_member_number(&j, "descent_m", p->descent_m);
    tp_json_member_number(&j, "min_elevation_m", p->s[p->lo].h_m);
    tp_json_member_number(&j, "max_elevation_m", p->s[p->hi].h_m);
    write_point(&j, "start", &p->s[0]);
    write_point(&j, "end", &p->s[p->n - 1]);
    write_point(&j, "lowest", &p->s[p->lo]);
    write_point(&j, "highest", &p->s[p->hi]);
    tp_json_key(&j, "steepest");
    if (p->steep) {
        const profile_sample* a = &p->s[p->steep - 1];
        const profile_sample* b = &p->s[p->steep];
        tp_json_object_begin(&j);
        tp_json_member_number(&j, "grade_pct", p->steep_grade_pct);
        tp_json_member_number(&j, "from_distance_m", a->d_m);
        tp_json_member_number(&j, "to_distance_m", b->d_m);
        tp_json_member_number(&j, "from_elevation_m", a->h_m);
        tp_json_member_number(&j, "to_elevation_m", b->h_m);
        tp_json_member_number(&j, "lat", a->lat);
        tp_json_member_number(&j, "lon", a->lon);
        tp_json_object_end(&j);
    } else {
        tp_json_null(&j);
    }
    tp_json_object_end(&j);
}

static void write_text(FILE* f, void* report)
{
    const profile_report* p = report;
    const profile_sample* s = p->s;
    if (p->o->route) {
        fprintf(f, "route       %s: line %zu of %zu", p->o->route, p->line_number, p->line_count);
        if (p->line->name)
            fprintf(f, " (\"%s\")", p->line->name);
        fprintf(f, ", %zu vertices", p->line->count);
    } else {
        fprintf(f, "route       %zu positions given with --through", p->line->count);
    }
    fprintf(f, ", %zu samples every %.1f m or less\n", p->n, p->step_m);
    fprintf(f, "start       %.6f %.6f  %.1f m\n", s[0].lat, s[0].lon, s[0].h_m);
    fprintf(f, "end         %.6f %.6f  %.1f m\n", s[p->n - 1].lat, s[p->n - 1].lon,
            s[p->n - 1].h_m);
    fprintf(f, "length      %.1f m along the ground (3D), %.1f m on the map (2D), %.1f m on the "
               "ellipsoid\n",
            p->length_3d_m, p->length_2d_m, p->length_geodesic_m);
    fprintf(f, "climb       %.1f m up, %.1f m down\n", p->climb_m, p->descent_m);
    fprintf(f, "lowest      %.1f m at %.1f m (%.6f %.6f)\n", s[p->lo].h_m, s[p->lo].d_m,
            s[p->lo].lat, s[p->lo].lon);
    fprintf(f, "highest     %.1f m at %.1f m (%.6f %.6f)\n", s[p->hi].h_m, s[p->hi].d_m,
            s[p->hi].lat, s[p->hi].lon);
    if (p->steep) {
        const profile_sample* a = &s[p->steep - 1];
        const profile_sample* b = &s[p->steep];
        fprintf(f,
                "steepest    %+.1f %% (%s) between %.1f m and %.1f m along the route, "
                "elevation %.1f m to %.1f m, from %.6f %.6f\n",
                p->steep_grade_pct, p->steep_grade_pct >= 0 ? "up" : "down", a->d_m, b->d_m, a->h_m,
                b->h_m, a->lat, a->lon);
    }
}

static void write_csv(FILE* f, void* report)
{
    const profile_report* p = report;
    fputs("distance_m,e_m,n_m,lat,lon,elevation_m,grade_pct\n", f);
    for (size_t i = 0; i < p->n; ++i) {
        const profile_sample* s = &p->s[i];
        fprintf(f, "%.3f,%.3f,%.3f,%.8f,%.8f,%.3f,", s->d_m, s->e_m, s->n_m, s->lat, s->lon,
                s->h_m);
        double dd = i ? s->d_m - p->s[i - 1].d_m : 0.0;
        if (dd > 0)
            fprintf(f, "%.3f\n", 100.0 * (s->h_m - p->s[i - 1].h_m) / dd);
        else
            fputs("\n", f);
    }
}

static void write_plot(FILE* f, void* user)
{
    const profile_report* p = user;
    const double km = 0.001;
    fputs("$ground << EOD\n", f);
    for (size_t i = 0; i < p->n; ++i)
        fprintf(f, "%.6f %.3f\n", p->s[i].d_m * km, p->s[i].h_m);
    fputs("EOD\n", f);
    char title[1024];
    snprintf(title, sizeof title,
             "Profile of %s%s%s%s: %.2f km along the ground (%.2f km on the map), %.0f m up, "
             "%.0f m down",
             p->o->route ? p->o->route : "the positions given", p->line->name ? " (" : "",
             p->line->name ? p->line->name : "", p->line->name ? ")" : "", p->length_3d_m * km,
             p->length_2d_m * km, p->climb_m, p->descent_m);
    fputs("set title ", f);
    tp_gnuplot_quoted(f, title);
    fputs(" noenhanced\n"
          "set xlabel 'distance along the route, on the map (km)'\n"
          "set ylabel 'elevation (m, as stored)'\n"
          "set grid lc rgb '#dddddd'\n"
          "set key below horizontal\n"
          "set style fill solid 1.0 noborder\n",
          f);
    double lo = p->s[p->lo].h_m, hi = p->s[p->hi].h_m;
    const double pad = fmax(1.0, 0.08 * (hi - lo));
    if (p->steep) {
        const profile_sample* a = &p->s[p->steep - 1];
        const profile_sample* b = &p->s[p->steep];
        char label[256];
        snprintf(label, sizeof label, "steepest: %+.1f %%", p->steep_grade_pct);
        fprintf(f, "set arrow 1 from %.6f,%.3f to %.6f,%.3f nohead lw 4 lc rgb '#c00000' front\n",
                a->d_m * km, a->h_m, b->d_m * km, b->h_m);
        fprintf(f, "set label 1 at %.6f,%.3f offset 1,1 ", b->d_m * km, b->h_m);
        tp_gnuplot_quoted(f, label);
        fputs(" tc rgb '#c00000' front\n", f);
    }
    fprintf(f, "set yrange [%.3f:%.3f]\nset xrange [0:%.6f]\n", lo - pad, hi + pad,
            fmax(p->length_2d_m * km, 1e-6));
    fprintf(f, "plot $ground using 1:2 with filledcurves y=%.3f lc rgb '#d8c8a8' notitle, \\\n",
            lo - pad);
    fputs("  $ground using 1:2 with lines lw 1.5 lc rgb '#6b4f2a' title 'ground under the "
          "route (full resolution)'\n",
          f);
}

/* The line the options name, or NULL after one line. */
static const tp_feature* pick_line(const profile_options* o, const tp_features* f,
                                   size_t* number, size_t* count)
{
    size_t lines = 0, points = 0, rings = 0;
    const tp_feature* pick = NULL;
    size_t want = o->feature ? (size_t)o->feature : 1;
    for (size_t i = 0; i < f->count; ++i) {
        const tp_feature* it = &f->items[i];
        if (it->kind == TP_FEATURE_LINE && ++lines == want)
            pick = it;
        points += it->kind == TP_FEATURE_POINT;
        rings += it->kind == TP_FEATURE_RING;
    }
    if (!lines) {
        tp_cli_error("%s has no line to follow (%zu points, %zu polygon rings): "
                     "a route is a track, a route or a line string",
                     o->route, points, rings);
        return NULL;
    }
    if (!pick) {
        tp_cli_error("--feature %d: %s has %zu line%s", o->feature, o->route, lines,
                     lines == 1 ? "" : "s");
        return NULL;
    }
    *number = want;
    *count = lines;
    return pick;
}

/* The --through positions placed on g as one line (render CRS) in a new *out: 1, or 0 after one
 * line. */
static int through_line(const profile_options* o, tp_ground* g, tp_features** out)
{
    const size_t n = o->positions.count;
    tp_features* f = calloc(1, sizeof *f);
    tp_feature* item = f ? calloc(1, sizeof *item) : NULL;
    double* xy = item ? malloc(2 * n * sizeof *xy) : NULL;
    if (!xy) {
        tp_cli_error("out of memory for %zu positions", n);
        free(item);
        free(f);
        return 0;
    }
    *item = (tp_feature){.kind = TP_FEATURE_LINE, .first = 0, .count = n, .value = NAN};
    f->items = item, f->count = 1, f->xy = xy, f->vertex_count = n;
    if (!tp_planner_positions_place("profile", o->src.path, g, "--through", &o->positions, xy)) {
        tp_features_destroy(f);
        return 0;
    }
    *out = f;
    return 1;
}

static int profile_main(int argc, char** argv, profile_options* o)
{
    int code = parse_options(argc, argv, o);
    if (code >= 0)
        return code;
    if (o->png &&
        (code = tp_cli_output_check("profile", "--png", o->png, TP_OUTPUT_PLOT)) != TP_EXIT_OK)
        return code;
    const char* outs[3] = {o->json, o->png, o->csv};
    if (!tp_planner_check_outputs(outs, 3))
        return TP_EXIT_FAILURE;

    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("profile", &o->src, &g)) != TP_EXIT_OK)
        return code;
    const tp_store_scene* sc = tp_ground_scene(g);
    if (!sc->georef || !tp_georef_has_geo(sc->georef)) {
        tp_cli_error("%s has no CRS: a route needs a georeferenced DEM", o->src.path);
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    tp_features* f = NULL;
    tp_error err = {{0}};
    if (o->route && tp_vector_read(o->route, sc->info.header.crs_wkt, &f, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    if (!o->route && !through_line(o, g, &f)) {
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    profile_report p;
    memset(&p, 0, sizeof p);
    p.o = o;
    p.f = f;
    p.georef = sc->georef;
    p.step_m = o->step_m > 0 ? o->step_m : fabs(sc->info.header.geotransform[1]);
    p.line = pick_line(o, f, &p.line_number, &p.line_count);
    code = TP_EXIT_FAILURE;
    if (p.line && sample_route(g, &p)) {
        measure(&p);
        const tp_planner_outputs out = {.json = o->json,
                                        .csv = o->csv,
                                        .png = o->png,
                                        .write_text = write_text,
                                        .write_json = write_json,
                                        .write_csv = write_csv,
                                        .write_plot = write_plot,
                                        .png_width_px = 1400,
                                        .png_height_px = 600};
        code = tp_planner_write_outputs("profile", &out, &p) ? TP_EXIT_OK : TP_EXIT_FAILURE;
    }
    free(p.s);
    tp_features_destroy(f);
    tp_ground_destroy(g);
    return tp_planner_finish(code);
}

int tp_cli_profile(int argc, char** argv)
{
    profile_options o;
    const int code = profile_main(argc, argv, &o);
    tp_planner_positions_free(&o.positions);
    free(o.through);
    return code;
}
