/*
 * cmd_los.c - `terrapatch los DEM|STORE --from POS --to POS`: does the observer at POS see the
 * target, and if not what is in the way (issue 13, section 2). Positions are read by
 * position.c, the ground by ground.c (full resolution, as `point`), the line by the core's
 * tp_los_compute (gdal_viewshed's conventions); the profile is drawn by gnuplot (gnuplot.c).
 */
#include "terrapatch.h"
#include "cli.h"
#include "ground_locate.h"
#include "json.h"
#include "output_check.h"
#include "planner_cli.h"

#include "tp_core.h"
#include "tp_geo.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct los_options {
    tp_planner_source src; /* the DEM or store, --cache-dir and the DEM options */
    const char* from;
    const char* to;
    double from_height_m, to_height_m, curvature_coeff;
    const char* json;
    const char* profile;
    const char* csv;
} los_options;

static void print_help(void)
{
    tp_planner_help(
        "usage: terrapatch los DEM|STORE --from POS --to POS [--from-height M] [--to-height M]\n"
        "                      [--curvature-coeff C] [--json F] [--profile F.png] [--csv F]\n"
        "                      [--cache-dir DIR]\n"
        "\n"
        "Line of sight: whether an observer at --from sees a target at --to over the ground of\n"
        "DEM (any raster GDAL reads, built into the store cache first as 'terrapatch view' does)\n"
        "or of a store (.tpt), the first obstruction (where, how far, by how many metres its\n"
        "ground rises above the sight line) and the smallest clearance along the line.\n"
        "\n"
        "The ground is the full-resolution surface ('terrapatch point' reads the same), sampled\n"
        "every quarter post along the straight line on the render grid; the ground within one\n"
        "post of either end is where observer and target stand and is not tested; voids block\n"
        "nothing. Conventions are gdal_viewshed's: heights above the ground, every height\n"
        "lowered by C * d^2 / (2 * 6378137 m) at distance d from the observer (0.85714: the\n"
        "earth's curvature with standard refraction; 1: curvature without refraction; 0: a\n"
        "flat earth), distances horizontal on the render grid (metres).\n"
        "\n"
        "POS: one argument, in any form 'terrapatch coord' reads (quote it when it has\n"
        "spaces): \"45.373 -121.696\", 45.373,-121.696, \"10n 601000 5026000\", 10TER0100026000,\n"
        "\"45d22'23\\\"N 121d41'45\\\"W\".\n"
        "\n"
        "options:\n"
        "  --from POS             the observer (required)\n"
        "  --to POS               the target (required)\n"
        "  --from-height M        eye above the ground at --from (default 2)\n"
        "  --to-height M          target above the ground at --to (default 0)\n"
        "  --curvature-coeff C    curvature and refraction coefficient (default 0.85714)\n"
        "  --json F               also write the result as JSON to F ('-' for stdout, instead\n"
        "                         of the text)\n"
        "  --profile F.png        draw the ground profile with the sight line (gnuplot)\n"
        "  --csv F                write the profile samples as CSV\n"
        "  -h, --help             show this help\n",
        "example:\n"
        "  $ terrapatch los N42E001.hgt --from 42.5,1.5 --to 42.6,1.6 --profile los.png\n"
        "\n"
        "The files given (--json, --csv, --profile) are written all or none: when one cannot\n"
        "be (a full disk, gnuplot missing), none is, and older files stay as they were.\n"
        "\n"
        "Exit status: 0 done (seen or not); 1 the DEM cannot be read, a position is outside it\n"
        "or in a void, an output cannot be written (then none is); 2 usage error (a position\n"
        "that cannot be read, a --profile not .png included).\n");
}

/* -1 when fine, else the exit code. */
static int parse_options(int argc, char** argv, los_options* o)
{
    memset(o, 0, sizeof *o);
    tp_planner_source_init(&o->src);
    o->from_height_m = TP_VIEWSHED_OBSERVER_HEIGHT_M;
    o->to_height_m = TP_VIEWSHED_TARGET_HEIGHT_M;
    o->curvature_coeff = TP_VIEWSHED_CURVATURE_COEFF;
    const tp_option options[] = {
        TP_OPT_TEXT("--from", NULL, &o->from),
        TP_OPT_TEXT("--to", NULL, &o->to),
        TP_OPT_TEXT("--json", NULL, &o->json),
        TP_OPT_TEXT("--profile", NULL, &o->profile),
        TP_OPT_TEXT("--csv", NULL, &o->csv),
        TP_OPT_NUMBER("--from-height", &o->from_height_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_NUMBER("--to-height", &o->to_height_m, 0.0, HUGE_VAL, "a number >= 0"),
        TP_OPT_NUMBER("--curvature-coeff", &o->curvature_coeff, 0.0, HUGE_VAL, "a number >= 0"),
    };
    const tp_option_table own = {options, TP_OPTIONS_COUNT(options), NULL, NULL};
    const int code = tp_planner_parse("los", argc, argv, print_help, own, &o->src,
                                      " (quote a position with spaces: --from "
                                      "\"45.37 -121.69\")");
    if (code >= 0)
        return code;
    if (!o->from)
        return tp_cli_usage("los", "missing --from POS (the observer)");
    if (!o->to)
        return tp_cli_usage("los", "missing --to POS (the target)");
    return -1;
}

static tp_status ground_height(void* user, double x, double y, double* h, tp_error* err)
{
    return tp_ground_height((tp_ground*)user, x, y, h, err);
}

/* Everything the outputs print. */
typedef struct los_report {
    const los_options* o;
    tp_ground* g;
    tp_los_result r;
    tp_los_sample* samples;
    double from_lat, from_lon, to_lat, to_lon;
    double from_ground_m, to_ground_m;
    double obs_lat, obs_lon, min_lat, min_lon;
    double geodesic_m; /* from -> to on the WGS84 ellipsoid (NaN without a geographic CRS) */
} los_report;

static void write_text(FILE* f, void* report)
{
    const los_report* p = report;
    const tp_los_result* r = &p->r;
    fprintf(f, "from        %.6f %.6f  ground %.1f m, eye %.1f m (%.1f m above)\n", p->from_lat,
            p->from_lon, p->from_ground_m, r->eye_m, p->o->from_height_m);
    fprintf(f, "to          %.6f %.6f  ground %.1f m, target %.1f m (%.1f m above)\n", p->to_lat,
            p->to_lon, p->to_ground_m, r->target_m, p->o->to_height_m);
    fprintf(f, "distance    %.1f m on the grid, %.1f m on the ellipsoid (curvature coefficient "
               "%g: %.2f m of drop at the target)\n",
            r->distance_m, p->geodesic_m, p->o->curvature_coeff, r->drop_m);
    fprintf(f, "visible     %s\n", r->visible ? "yes" : "no");
    if (r->obstructed)
        fprintf(f, "obstruction %.6f %.6f at %.1f m: the ground is %.1f m above the sight line\n",
                p->obs_lat, p->obs_lon, r->obstruction_distance_m, r->obstruction_blocking_m);
    else
        fprintf(f, "obstruction none\n");
    if (isnan(r->min_clearance_m))
        fprintf(f, "clearance   none tested (the two are within a post of each other)\n");
    else
        fprintf(f, "clearance   %.1f m at least, at %.1f m (%.6f %.6f)\n", r->min_clearance_m,
                r->min_clearance_distance_m, p->min_lat, p->min_lon);
    if (r->void_count)
        fprintf(f, "voids       %zu of %zu samples along the line have no height (seen over)\n",
                r->void_count, r->void_count + r->tested_count);
}

static void write_json(FILE* f, void* report)
{
    const los_report* p = report;
    const tp_los_result* r = &p->r;
    tp_json j;
    tp_json_init(&j, f);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "source", p->o->src.path);
    tp_json_member_bool(&j, "visible", r->visible);
    tp_json_member_number(&j, "distance_m", r->distance_m);
    tp_json_member_number(&j, "geodesic_distance_m", p->geodesic_m);
    tp_json_key(&j, "from");
    tp_json_object_begin(&j);
    tp_json_member_number(&j, "lat", p->from_lat);
    tp_json_member_number(&j, "lon", p->from_lon);
    tp_json_member_number(&j, "ground_m", p->from_ground_m);
    tp_json_member_number(&j, "eye_m", r->eye_m);
    tp_json_object_end(&j);
    tp_json_key(&j, "to");
    tp_json_object_begin(&j);
    tp_json_member_number(&j, "lat", p->to_lat);
    tp_json_member_number(&j, "lon", p->to_lon);
    tp_json_member_number(&j, "ground_m", p->to_ground_m);
    tp_json_member_number(&j, "target_m", r->target_m);
    tp_json_object_end(&j);
    tp_json_key(&j, "obstruction");
    if (r->obstructed) {
        tp_json_object_begin(&j);
        tp_json_member_number(&j, "lat", p->obs_lat);
        tp_json_member_number(&j, "lon", p->obs_lon);
        tp_json_member_number(&j, "distance_m", r->obstruction_distance_m);
        tp_json_member_number(&j, "blocking_m", r->obstruction_blocking_m);
        tp_json_object_end(&j);
    } else {
        tp_json_null(&j);
    }
    tp_json_member_number(&j, "min_clearance_m", r->min_clearance_m);
    tp_json_member_number(&j, "min_clearance_distance_m", r->min_clearance_distance_m);
    tp_json_member_number(&j, "from_height_m", p->o->from_height_m);
    tp_json_member_number(&j, "to_height_m", p->o->to_height_m);
    tp_json_member_number(&j, "curvature_coeff", p->o->curvature_coeff);
    tp_json_member_number(&j, "curvature_drop_m", r->drop_m);
    tp_json_member_size(&j, "samples", r->sample_count);
    tp_json_member_size(&j, "void_samples", r->void_count);
    tp_json_object_end(&j);
}

static void write_csv(FILE* f, void* report)
{
    const los_report* p = report;
    fputs("distance_m,lat,lon,ground_m,line_m,clearance_m,blocks\n", f);
    for (size_t i = 0; i < p->r.sample_count; ++i) {
        const tp_los_sample* s = &p->samples[i];
        double lat, lon;
        tp_ground_grid_latlon(p->g, s->x, s->y, &lat, &lon);
        fprintf(f, "%.3f,%.8f,%.8f,", s->distance_m, lat, lon);
        if (isnan(s->ground_m))
            fprintf(f, ",%.3f,,0\n", s->line_m);
        else
            fprintf(f, "%.3f,%.3f,%.3f,%d\n", s->ground_m, s->line_m, s->clearance_m,
                    s->tested && s->clearance_m < 0.0);
    }
}

/* gnuplot: the ground (filled), the sight line, blocked ground red, the obstruction marked. */
static void write_plot(FILE* f, void* user)
{
    const los_report* p = user;
    const tp_los_result* r = &p->r;
    const double km = 0.001;
    fputs("$ground << EOD\n", f);
    for (size_t i = 0; i < r->sample_count; ++i) {
        const tp_los_sample* s = &p->samples[i];
        if (isnan(s->ground_m))
            fputs("\n", f); /* a gap in the line */
        else
            fprintf(f, "%.6f %.3f %.3f %d\n", s->distance_m * km, s->ground_m, s->line_m,
                    s->tested && s->clearance_m < 0.0);
    }
    fputs("EOD\n$line << EOD\n", f);
    for (size_t i = 0; i < r->sample_count; ++i)
        fprintf(f, "%.6f %.3f\n", p->samples[i].distance_m * km, p->samples[i].line_m);
    fputs("EOD\n", f);
    char title[1024];
    snprintf(title, sizeof title,
             "Line of sight %.5f %.5f -> %.5f %.5f: %s (%.0f m; eye %.1f m, target %.1f m above "
             "the ground; curvature coefficient %g)",
             p->from_lat, p->from_lon, p->to_lat, p->to_lon,
             r->visible ? "VISIBLE" : "HIDDEN", r->distance_m, p->o->from_height_m,
             p->o->to_height_m, p->o->curvature_coeff);
    fputs("set title ", f);
    tp_gnuplot_quoted(f, title);
    fputs(" noenhanced\n"
          "set xlabel 'distance from the observer (km)'\n"
          "set ylabel 'height (m, as stored)'\n"
          "set grid lc rgb '#dddddd'\n"
          "set key below horizontal\n"
          "set style fill solid 1.0 noborder\n",
          f);
    if (r->obstructed) {
        char label[256];
        snprintf(label, sizeof label, "obstruction: %.1f m above the line at %.2f km",
                 r->obstruction_blocking_m, r->obstruction_distance_m * km);
        fprintf(f, "set label 1 at %.6f,%.3f point pt 7 ps 1.5 lc rgb '#c00000' offset 1,1 ",
                r->obstruction_distance_m * km, r->obstruction_ground_m);
        tp_gnuplot_quoted(f, label);
        fputs(" tc rgb '#c00000' front\n", f);
    }
    double lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < r->sample_count; ++i) {
        const tp_los_sample* s = &p->samples[i];
        lo = fmin(lo, fmin(isnan(s->ground_m) ? s->line_m : s->ground_m, s->line_m));
        hi = fmax(hi, fmax(isnan(s->ground_m) ? s->line_m : s->ground_m, s->line_m));
    }
    const double pad = fmax(1.0, 0.08 * (hi - lo));
    fprintf(f, "set yrange [%.3f:%.3f]\nset xrange [0:%.6f]\n", lo - pad, hi + pad,
            r->distance_m * km);
    fprintf(f, "plot $ground using 1:2 with filledcurves y=%.3f lc rgb '#d8c8a8' notitle, \\\n",
            lo - pad);
    fputs(
          "  $ground using 1:2 with lines lw 1.5 lc rgb '#6b4f2a' title 'ground (full "
          "resolution)', \\\n"
          "  $ground using 1:($4 > 0 ? $2 : 1/0) with points pt 7 ps 0.4 lc rgb '#c00000' "
          "title 'ground above the sight line', \\\n"
          "  $line using 1:2 with lines lw 2 lc rgb '#0070c0' title 'sight line (eye to target, "
          "curvature applied)'\n",
          f);
}

int tp_cli_los(int argc, char** argv)
{
    los_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;
    tp_position_readings from, to;
    if (!tp_planner_position("los", "--from", o.from, &from) ||
        !tp_planner_position("los", "--to", o.to, &to))
        return TP_EXIT_USAGE;
    if (o.profile &&
        (code = tp_cli_output_check("los", "--profile", o.profile, TP_OUTPUT_PLOT)) != TP_EXIT_OK)
        return code;
    const char* outs[3] = {o.json, o.profile, o.csv};
    if (!tp_planner_check_outputs(outs, 3))
        return TP_EXIT_FAILURE;

    tp_ground* g = NULL;
    if ((code = tp_planner_ground_open("los", &o.src, &g)) != TP_EXIT_OK)
        return code;
    los_report p;
    memset(&p, 0, sizeof p);
    p.o = &o;
    p.g = g;
    double fx, fy, tx, ty;
    if (!tp_planner_locate("los", o.src.path, g, &from, o.from, &fx, &fy, &p.from_ground_m) ||
        !tp_planner_locate("los", o.src.path, g, &to, o.to, &tx, &ty, &p.to_ground_m)) {
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    tp_los_options lo = tp_los_options_default();
    lo.observer_height_m = o.from_height_m;
    lo.target_height_m = o.to_height_m;
    lo.curvature_coeff = o.curvature_coeff;
    size_t n = tp_los_sample_count(fx, fy, tx, ty, &lo);
    p.samples = malloc(n * sizeof *p.samples);
    tp_error err = {{0}};
    tp_status s = p.samples ? tp_los_compute(tp_ground_scene(g)->info.header.geotransform, fx, fy,
                                             tx, ty, &lo, ground_height, g, p.samples, n, &p.r,
                                             &err)
                            : tp_error_set(&err, TP_ERR_OUT_OF_MEMORY,
                                           "out of memory for %zu profile samples", n);
    if (s != TP_OK) {
        tp_cli_error("%s: %s", o.src.path, err.message);
        free(p.samples);
        tp_ground_destroy(g);
        return TP_EXIT_FAILURE;
    }
    tp_ground_grid_latlon(g, fx, fy, &p.from_lat, &p.from_lon);
    tp_ground_grid_latlon(g, tx, ty, &p.to_lat, &p.to_lon);
    double azi1, azi2;
    if (isnan(p.from_lat) || isnan(p.to_lat) ||
        tp_geodesic_inverse(p.from_lat, p.from_lon, p.to_lat, p.to_lon, &azi1, &azi2,
                            &p.geodesic_m, NULL) != TP_OK)
        p.geodesic_m = NAN;
    if (p.r.obstructed)
        tp_ground_grid_latlon(g, p.r.obstruction_x, p.r.obstruction_y, &p.obs_lat, &p.obs_lon);
    if (!isnan(p.r.min_clearance_m))
        tp_ground_grid_latlon(g, p.r.min_clearance_x, p.r.min_clearance_y, &p.min_lat,
                              &p.min_lon);

    const tp_planner_outputs out = {.json = o.json, .csv = o.csv, .png = o.profile,
                                    .write_text = write_text, .write_json = write_json,
                                    .write_csv = write_csv, .write_plot = write_plot,
                                    .png_width_px = 1400, .png_height_px = 600};
    code = tp_planner_write_outputs("los", &out, &p) ? TP_EXIT_OK : TP_EXIT_FAILURE;
    free(p.samples);
    tp_ground_destroy(g);
    return tp_planner_finish(code);
}
