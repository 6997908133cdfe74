/* planner_cli.c - what the planner commands share (see planner_cli.h). */
#define _POSIX_C_SOURCE 200809L
#include "planner_cli.h"

#include "atomic_file.h"
#include "cli.h"
#include "ground_locate.h"

#include "tp_io.h"

#include <stdarg.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

int tp_planner_usage(const char* cmd, const char* what, ...)
{
    va_list ap;
    va_start(ap, what);
    fprintf(stderr, "terrapatch %s: ", cmd);
    vfprintf(stderr, what, ap);
    fprintf(stderr, " (see 'terrapatch %s --help')\n", cmd);
    va_end(ap);
    return TP_EXIT_USAGE;
}

int tp_planner_argument(const char* cmd, const char* a, void (*print_help)(void),
                        const char** path, const char* hint)
{
    if (!strcmp(a, "-h") || !strcmp(a, "--help")) {
        print_help();
        return tp_cli_finish(TP_EXIT_OK);
    }
    if (a[0] == '-' && a[1])
        return TP_PLANNER_OPTION;
    if (*path)
        return tp_planner_usage(cmd, "more than one DEM given%s", hint);
    *path = a;
    return TP_PLANNER_NEXT;
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
            return tp_planner_usage(cmd, "missing value for %s", names[k]), -1;
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

int tp_planner_position(const char* cmd, const char* what, const char* text, tp_position* pos)
{
    char msg[TP_POSITION_MSG_SIZE];
    if (tp_position_parse(text, strlen(text), 0, pos, msg, sizeof msg))
        return 1;
    fprintf(stderr, "terrapatch %s: %s '%s': %s\n", cmd, what, text, msg);
    return 0;
}

int tp_planner_check_outputs(const char* const* paths, int count)
{
    for (int i = 0; i < count; ++i)
        if (paths[i] && strcmp(paths[i], "-") && !tp_atomic_check_dir(paths[i]))
            return 0;
    return 1;
}

int tp_planner_ground_open(const char* cmd, const char* path, const char* cache_dir,
                           tp_ground** g)
{
    tp_ground_options go = {.cache_dir = cache_dir, .cmd = cmd};
    return tp_ground_open(path, &go, g);
}

int tp_planner_locate(const char* cmd, const char* path, tp_ground* g, const tp_position* pos,
                      const char* input, double* x, double* y, double* height_m)
{
    char msg[1024];
    if (tp_ground_locate(g, pos, input, x, y, height_m, msg, sizeof msg))
        return 1;
    fprintf(stderr, "terrapatch %s: %s: %s\n", cmd, path, msg);
    return 0;
}

tp_status tp_planner_read_posts(tp_ground* g, int x0, int y0, int w, int h, float* z,
                                const char* progress, tp_error* err)
{
    const int show = progress && (size_t)w * h >= TP_PLANNER_PROGRESS_POSTS;
    const int tty = show && isatty(STDERR_FILENO);
    int shown = -1;
    tp_status s = TP_OK;
    for (int y = 0; y < h && s == TP_OK; ++y) {
        if (show) {
            const int pct = (int)(100.0 * y / h) / 10 * 10;
            if (pct != shown) {
                fprintf(stderr, "terrapatch: %s: reading the ground %3d%%%s", progress, pct,
                        tty ? "\r" : "\n");
                shown = pct;
            }
        }
        for (int x = 0; x < w && s == TP_OK; ++x) {
            double v;
            s = tp_ground_height(g, x0 + x, y0 + y, &v, err);
            z[(size_t)y * w + x] = (float)v;
        }
    }
    return s;
}

double tp_planner_now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + 1e-9 * ts.tv_nsec;
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
        fprintf(stderr, "terrapatch %s: %s\n", cmd, err.message);
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
        fprintf(stderr, "terrapatch %s: %s\n", cmd, err.message);
    if (ok && o->json && !json_stdout)
        ok = add_printed(set, o->json, o->write_json, report);
    if (ok && o->csv)
        ok = add_printed(set, o->csv, o->write_csv, report);
    if (ok && o->png)
        ok = add_plot(set, cmd, o, report);
    if (ok) {
        ok = tp_file_set_commit(set, &err) == TP_OK;
        if (!ok && !tp_interrupted())
            fprintf(stderr, "terrapatch %s: %s\n", cmd, err.message);
    } else {
        tp_file_set_abort(set);
    }
    if (ok) {
        tp_interrupt_finished();
        for (int i = 0; i < count; ++i)
            fprintf(stderr, "terrapatch: wrote %s\n", files[i]);
    } else if (count > 1 && !tp_interrupted()) {
        fprintf(stderr, "terrapatch %s: none of ", cmd);
        for (int i = 0; i < count; ++i)
            fprintf(stderr, "%s%s", i ? ", " : "", files[i]);
        fputs(" written (all or none: older files as they were)\n", stderr);
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
