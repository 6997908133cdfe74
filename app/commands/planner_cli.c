/* planner_cli.c - what the planner commands share (see planner_cli.h). */
#define _POSIX_C_SOURCE 200809L
#include "planner_cli.h"
#include "clock.h"

#include "atomic_file.h"
#include "cli.h"
#include "ground_locate.h"

#include "tp_io.h"

#include <ctype.h>
#include <math.h>
#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

int tp_planner_argument(const char* cmd, int argc, char** argv, int i, void (*print_help)(void),
                        const char** path, const char* hint)
{
    const char* a = argv[i];
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
        print_help();
        return tp_cli_finish(TP_EXIT_OK);
    }
    if (a[0] == '-' && a[1])
        return TP_PLANNER_OPTION;
    if (*path)
        return tp_planner_stray(cmd, argc, argv, i, hint);
    *path = a;
    return TP_PLANNER_NEXT;
}

/* The planner commands' options that take a position. */
static const char* const position_options[] = {"--from", "--to", "--observer", "--at", "--around"};

/* 1 when a may be a piece of a position typed without quotes: a number, or a short token of
 * digits, DMS marks and letters ("41.88", "28'", "N", "33n", "W002", "10TFR"), not a file. */
static int position_piece(const char* a)
{
    double v;
    if (tp_position_decimal(a, &v) == 1)
        return 1;
    size_t len = strlen(a), digits = 0;
    if (!len || len > 24)
        return 0;
    for (const char* c = a; *c; ++c) {
        const unsigned char u = (unsigned char)*c;
        if (isdigit(u))
            ++digits;
        else if (u == '.' && isalpha((unsigned char)c[1]))
            return 0; /* a file name's extension */
        else if (!isalpha(u) && !strchr(".:'\"+-", u) && u < 0x80)
            return 0;
    }
    return digits || len == 1;
}

/* The value of position option argv[j] ("--from" then its value, or "--from=VALUE"), or NULL
 * when argv[j] is no position option. */
static const char* position_option_value(int argc, char** argv, int j)
{
    for (size_t k = 0; k < TP_PLANNER_COUNT(position_options); ++k) {
        const size_t len = strlen(position_options[k]);
        if (strncmp(argv[j], position_options[k], len))
            continue;
        if (argv[j][len] == '=')
            return argv[j] + len + 1;
        if (!argv[j][len] && j + 1 < argc)
            return argv[j + 1];
    }
    return NULL;
}

int tp_planner_stray(const char* cmd, int argc, char** argv, int i, const char* hint)
{
    const char* a = argv[i];
    char own[512] = "";
    /* back from argv[i] over pieces of a position to the option that took the first one */
    for (int j = i - 1; j >= 1; --j) {
        const char* v = position_option_value(argc, argv, j);
        const int first = v == argv[j + 1] ? j + 2 : j + 1; /* the pieces after v */
        int end = position_piece(a) ? i : i - 1;            /* and on after argv[i] */
        if (v && end >= first && position_piece(v)) {
            for (const int on = end == i; on && end + 1 < argc && position_piece(argv[end + 1]);)
                ++end;
            size_t at =
                (size_t)snprintf(own, sizeof own, " (quote a position with spaces: %.*s \"%s",
                                 (int)strcspn(argv[j], "="), argv[j], v);
            for (int k = first; k <= end && at < sizeof own; ++k)
                at += (size_t)snprintf(own + at, sizeof own - at, " %s", argv[k]);
            if (at < sizeof own)
                snprintf(own + at, sizeof own - at, "\")");
            hint = own;
            break;
        }
        if (!position_piece(argv[j]))
            break;
    }
    if (a[0] == '-' && a[1])
        return tp_cli_usage(cmd, "unknown option '%s'%s", a, hint);
    return tp_cli_usage(cmd, "more than one DEM given%s", hint);
}

int tp_planner_is_option(const char* arg, const char* name)
{
    size_t len = strlen(name);
    return !strncmp(arg, name, len) && (arg[len] == '\0' || arg[len] == '=');
}

const char* tp_planner_option_value(int argc, char** argv, int* i, const char* name)
{
    size_t len = strlen(name);
    if (strncmp(argv[*i], name, len) == 0 && argv[*i][len] == '=')
        return argv[*i] + len + 1;
    if (*i + 1 >= argc)
        return NULL;
    return argv[++*i];
}

int tp_planner_text_options(const char* cmd, int argc, char** argv, int* i,
                            const char* const* names, const char** const* slots, size_t count)
{
    for (size_t k = 0; k < count; ++k) {
        if (!tp_planner_is_option(argv[*i], names[k]))
            continue;
        if (!(*slots[k] = tp_planner_option_value(argc, argv, i, names[k])))
            return tp_cli_usage(cmd, "missing value for %s", names[k]), -1;
        return 1;
    }
    return 0;
}

int tp_planner_number_options(const char* cmd, int argc, char** argv, int* i,
                              const char* const* names, double* const* slots, size_t count)
{
    for (size_t k = 0; k < count; ++k) {
        if (!tp_planner_is_option(argv[*i], names[k]))
            continue;
        const char* v = tp_planner_option_value(argc, argv, i, names[k]);
        return tp_planner_number(cmd, names[k], v, TP_PLANNER_AT_LEAST_0, "a number >= 0",
                                 slots[k])
                   ? 1
                   : -1;
    }
    return 0;
}

int tp_planner_number(const char* cmd, const char* opt, const char* v, tp_planner_range range,
                      const char* expected, double* out)
{
    double d;
    int ok = v && tp_position_decimal(v, &d) == 1;
    if (ok && range == TP_PLANNER_AT_LEAST_0)
        ok = d >= 0.0;
    if (ok && range == TP_PLANNER_ABOVE_0)
        ok = d > 0.0;
    if (!ok)
        return tp_option_error(cmd, opt, expected, v ? v : ""), 0;
    *out = d;
    return 1;
}

int tp_planner_integer(const char* cmd, const char* opt, const char* v, long lo, long hi,
                       const char* expected, long* out)
{
    char* end = NULL;
    long n = v ? strtol(v, &end, 10) : 0;
    /* out of long's range, strtol gives LONG_MIN or LONG_MAX: outside lo .. hi unless hi is
     * LONG_MAX ("an integer >= 1" takes any large number) */
    if (!v || !*v || *end || n < lo || n > hi)
        return tp_option_error(cmd, opt, expected, v ? v : ""), 0;
    *out = n;
    return 1;
}

/* The hint that a position is latitude first, after the text of a message. */
#define LATITUDE_FIRST "a position is LAT LON, latitude first"

int tp_planner_position(const char* cmd, const char* what, const char* text,
                        tp_position_readings* pos)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    char hint[200] = "";
    tp_error err = {{0}};
    if (tp_position_parse_readings(text, strlen(text), 0, pos, &err))
        return 1;
    char swapped[128];
    if (tp_position_swapped(text, swapped, sizeof swapped)) /* "139.7 35.6" */
        snprintf(hint, sizeof hint, "; " LATITUDE_FIRST ": '%s'?", swapped);
    tp_cli_error("%s '%s': %s%s", what, text, err.message, hint);
    return 0;
}

int tp_planner_choose(const char* cmd, const char* path, tp_ground* g,
                      const tp_position_readings* pos, const char* input, tp_position* out)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    if (pos->count < 2) {
        *out = pos->reading[0];
        return 1;
    }
    char r0[128], r1[128];
    double x, y;
    int on0 = tp_ground_on_dem(g, &pos->reading[0], &x, &y);
    int on1 = tp_ground_on_dem(g, &pos->reading[1], &x, &y);
    tp_position_reading_text(pos, 0, r0, sizeof r0);
    tp_position_reading_text(pos, 1, r1, sizeof r1);
    if (on0 != on1) {
        tp_cli_note("note: read '%s' as %s; the other reading, %s, is off %s", input, on0 ? r0 : r1,
                    on0 ? r1 : r0, path);
        *out = pos->reading[on0 ? 0 : 1];
        return 1;
    }
    tp_cli_error("%s: '%s' is ambiguous: %s or %s, and %s on the DEM; write the "
                 "zone's hemisphere as %dnorth or %dsouth, or give the position in MGRS",
                 path, input, r0, r1, on0 ? "both are" : "neither is", pos->reading[0].zone,
                 pos->reading[0].zone);
    return 0;
}

void tp_planner_swap_hint(tp_ground* g, const tp_position* pos, char* out, size_t cap)
{
    tp_position swapped = {.lat_deg = pos->lon_deg, .lon_deg = pos->lat_deg};
    double x, y;
    if (cap)
        out[0] = '\0';
    if (!pos->has_grid && fabs(pos->lon_deg) <= 90.0 && !tp_ground_on_dem(g, pos, &x, &y) &&
        tp_ground_on_dem(g, &swapped, &x, &y))
        snprintf(
            out, cap,
            "; with latitude and longitude swapped (%.6f %.6f) it is on the DEM: " LATITUDE_FIRST,
            swapped.lat_deg, swapped.lon_deg);
}

int tp_planner_check_outputs(const char* const* paths, int count)
{
    for (int i = 0; i < count; ++i)
        if (paths[i] && strcmp(paths[i], "-") && !tp_atomic_check_dir(paths[i]))
            return 0;
    return 1;
}

int tp_planner_ground_open(const char* cmd, const char* path, const char* cache_dir,
                           const tp_scene_options* dem, tp_ground** g)
{
    tp_ground_options go = {.cache_dir = cache_dir, .cmd = cmd, .dem = dem};
    return tp_ground_open(path, &go, g);
}

void tp_planner_dem_options_help(void)
{
    fputs("\nDEM options (as every command that opens a DEM takes them; a DEM is read through\n"
          "its store in the cache, built with --patch, --crs, --resampling, --fill-max and\n"
          "--fill-from; a store keeps those it was built with and refuses them):\n",
          stdout);
    tp_scene_options_help(stdout);
}

int tp_planner_locate(const char* cmd, const char* path, tp_ground* g,
                      const tp_position_readings* pos, const char* input, double* x, double* y,
                      double* height_m)
{
    char hint[256];
    tp_error err = {{0}};
    tp_position p;
    if (!tp_planner_choose(cmd, path, g, pos, input, &p))
        return 0;
    if (tp_ground_locate(g, &p, input, x, y, height_m, &err))
        return 1;
    tp_planner_swap_hint(g, &p, hint, sizeof hint);
    tp_cli_error("%s: %s%s", path, err.message, hint);
    return 0;
}

/* What write prints, added to set as path; 1, or 0 after the writer's message. */
static int add_printed(tp_file_set* set, const char* path, tp_planner_write_fn write, void* report)
{
    tp_atomic_file af;
    if (!tp_atomic_open(&af, path))
        return 0;
    write(af.f, report);
    return tp_atomic_add_to_set(&af, set);
}

/* The gnuplot PNG added to set as png; 1, or 0 after a line. */
static int add_plot(tp_file_set* set, const char* cmd, const tp_planner_outputs* o, void* report)
{
    size_t size = 0;
    unsigned char* bytes = tp_gnuplot_draw(o->png, o->png_width_px, o->png_height_px, o->write_plot,
                                           report, cmd, &size);
    tp_error err;
    int ok = bytes && tp_file_set_add(set, o->png, bytes, size, &err) == TP_OK;
    if (bytes && !ok && !tp_interrupted())
        tp_cli_error("%s", err.message);
    free(bytes);
    return ok;
}

int tp_planner_write_outputs(const char* cmd, const tp_planner_outputs* o, void* report)
{
    const int json_stdout = o->json && !strcmp(o->json, "-");
    if (json_stdout)
        o->write_json(stdout, report);
    else
        o->write_text(stdout, report);
    const char* files[3];
    int count = 0;
    if (o->json && !json_stdout)
        files[count++] = o->json;
    if (o->csv)
        files[count++] = o->csv;
    if (o->png)
        files[count++] = o->png;
    if (!count)
        return 1;
    /* every file to its temporary first, then all renamed or none (tp_file_set_*); held until
     * tp_interrupt_finished, so a signal after the renames cannot undo the "wrote" lines */
    tp_interrupt_hold();
    tp_file_set* set = NULL;
    tp_error err;
    int ok = tp_file_set_begin(&set, &err) == TP_OK;
    if (!ok)
        tp_cli_error("%s", err.message);
    if (ok && o->json && !json_stdout)
        ok = add_printed(set, o->json, o->write_json, report);
    if (ok && o->csv)
        ok = add_printed(set, o->csv, o->write_csv, report);
    if (ok && o->png)
        ok = add_plot(set, cmd, o, report);
    if (ok) {
        ok = tp_file_set_commit(set, &err) == TP_OK;
        if (!ok && !tp_interrupted())
            tp_cli_error("%s", err.message);
    } else {
        tp_file_set_abort(set);
    }
    if (ok) {
        tp_interrupt_finished();
        for (int i = 0; i < count; ++i)
            tp_cli_note("wrote %s", files[i]);
    } else if (count > 1 && !tp_interrupted()) {
        char names[2048] = "";
        for (int i = 0; i < count; ++i)
            snprintf(names + strlen(names), sizeof names - strlen(names), "%s%s", i ? ", " : "",
                     files[i]);
        tp_cli_error("none of %s written (all or none: older files as they were)", names);
    }
    tp_interrupt_release();
    return ok;
}

int tp_planner_finish(int code)
{
    if (tp_interrupted())
        return tp_cli_interrupted();
    return code == TP_EXIT_OK ? tp_cli_finish(code) : code;
}
