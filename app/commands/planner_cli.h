/*
 * planner_cli.h - the prologue and outputs every planner command shares (`point`, `los`,
 * `viewshed`, `contours`, `profile`): the pieces their option parsers are made of, a position
 * read from the command line and placed on the ground (with the messages), the ground opened,
 * the posts of a window read, and the outputs written (the text or JSON on stdout, JSON and CSV
 * files atomically, a gnuplot PNG). Each command keeps its own options, computation and report
 * in its cmd_*.c. app/commands/planner_cli.c.
 *
 * Messages are those of cli.h: "terrapatch CMD: ..." on stderr, cmd naming the command ("los").
 */
#ifndef TP_APP_PLANNER_CLI_H
#define TP_APP_PLANNER_CLI_H

#include "gnuplot.h"
#include "ground.h"
#include "position.h"

#include "tp_core.h"

#include <stddef.h>
#include <stdio.h>

/* ---- the command line ---- */

/* What a planner command's parser does first with each argument a = argv[i]: -h or --help
 * prints the help (print_help) and ends the parse with tp_cli_finish(TP_EXIT_OK); an argument
 * that is no option (not starting with '-', or "-" alone) is the DEM, into *path, and a second
 * one is the usage error "more than one DEM given" (tp_planner_stray). Returns the exit code
 * that ends the parse, TP_PLANNER_NEXT when a was the DEM, or TP_PLANNER_OPTION when a is an
 * option for the command to read. */
#define TP_PLANNER_NEXT (-1)
#define TP_PLANNER_OPTION (-2)
int tp_planner_argument(const char* cmd, int argc, char** argv, int i, void (*print_help)(void),
                        const char** path, const char* hint);

/* The usage error for argv[i], an argument the parser cannot place: "unknown option 'A'" (A
 * starting with '-') or "more than one DEM given", then, when A is part of a position left
 * unquoted after a position option (--from, --to, --observer, --at, --around: "--from 42.5
 * -2.1"), " (quote a position with spaces: --from \"42.5 -2.1\")", else hint (e.g. light's
 * about a time zone, or ""). Returns TP_EXIT_USAGE. */
int tp_planner_stray(const char* cmd, int argc, char** argv, int i, const char* hint);

/* 1 when arg is the option name, alone or as "NAME=VALUE". */
int tp_planner_is_option(const char* arg, const char* name);

/* The value of the option name at argv[*i]: after '=', else the next argument (*i moves on to
 * it); NULL when there is none. */
const char* tp_planner_option_value(int argc, char** argv, int* i, const char* name);

/* Tables of options: names[k] (count of them) puts its value into *slots[k]. When argv[*i] is
 * one of them (tp_planner_is_option), reads its value (tp_planner_option_value) and returns 1;
 * 0 when it is none of them; -1 after one line (a usage error): a text option without a value
 * ("missing value for NAME", as tp_cli_usage), a number that is missing or not >= 0
 * (tp_planner_number's "expected a number >= 0"). TP_PLANNER_COUNT(names) gives count. */
#define TP_PLANNER_COUNT(a) (sizeof(a) / sizeof((a)[0]))
int tp_planner_text_options(const char* cmd, int argc, char** argv, int* i,
                            const char* const* names, const char** const* slots, size_t count);
int tp_planner_number_options(const char* cmd, int argc, char** argv, int* i,
                              const char* const* names, double* const* slots, size_t count);

/* Which numbers an option takes. */
typedef enum tp_planner_range {
    TP_PLANNER_ANY = 0,   /* any finite number */
    TP_PLANNER_AT_LEAST_0, /* >= 0 */
    TP_PLANNER_ABOVE_0,    /* > 0 */
} tp_planner_range;

/* The value v of option opt (NULL: it was missing) as a decimal number (tp_position_decimal)
 * in range. 1 with *out; else 0 after tp_option_error's line ("expected EXPECTED, got 'V'"),
 * *out untouched. */
int tp_planner_number(const char* cmd, const char* opt, const char* v, tp_planner_range range,
                      const char* expected, double* out);

/* The same for an integer (strtol, base 10, nothing after it) in lo .. hi. */
int tp_planner_integer(const char* cmd, const char* opt, const char* v, long lo, long hi,
                       const char* expected, long* out);

/* ---- positions and the ground ---- */

/* Reads text (NUL-terminated) as one position, without a height: both readings of an ambiguous
 * band letter S (position.h) are kept for tp_planner_choose to take the one on the DEM. 1 with
 * *pos; else 0 after "terrapatch CMD: WHAT 'TEXT': why" (what names it: "--from", "position"),
 * with "; a position is LAT LON, latitude first: 'B A'?" when the two numbers swapped would
 * read; the caller exits with TP_EXIT_USAGE. */
int tp_planner_position(const char* cmd, const char* what, const char* text,
                        tp_position_readings* pos);

/* The reading of pos to put on g: the only one; of two, the one on the DEM, after "terrapatch
 * CMD: note: read 'INPUT' as band S (...); the other reading, zone Z south (...), is off PATH"
 * on stderr. 1 with *out; 0 after "terrapatch CMD: PATH: 'INPUT' is ambiguous ..." when both
 * readings or neither are on the DEM (the caller exits with TP_EXIT_FAILURE). */
int tp_planner_choose(const char* cmd, const char* path, tp_ground* g,
                      const tp_position_readings* pos, const char* input, tp_position* out);

/* What a message about pos off the DEM ends with: "; with latitude and longitude swapped (LON
 * LAT) it is on the DEM: a position is LAT LON, latitude first" when that is so (pos typed as
 * latitude/longitude), else "". */
void tp_planner_swap_hint(tp_ground* g, const tp_position* pos, char* out, size_t cap);

/* Checks that each of the count paths can be written (tp_atomic_check_dir), NULL and "-"
 * (stdout) passed over; 0 after the first one's message. */
int tp_planner_check_outputs(const char* const* paths, int count);

/* tp_ground_open with the command's options (dem: the DEM options it parsed with
 * tp_scene_option_arg, NULL for the defaults): the exit code, *g on TP_EXIT_OK. */
int tp_planner_ground_open(const char* cmd, const char* path, const char* cache_dir,
                           const tp_scene_options* dem, tp_ground** g);

/* The help of the DEM options every planner command takes (scene.h's, with the store's
 * rule): printed by each command's --help. */
void tp_planner_dem_options_help(void);

/* tp_planner_choose, then tp_ground_locate: 1 with grid (x, y) and the ground's height; else
 * 0 after "terrapatch CMD: PATH: why" (input is the position as typed; off the DEM with
 * tp_planner_swap_hint, in a void with tp_ground_void_hint). */
int tp_planner_locate(const char* cmd, const char* path, tp_ground* g,
                      const tp_position_readings* pos, const char* input, double* x, double* y,
                      double* height_m);

/* ---- the outputs ---- */

/* Writes one output of report to f. */
typedef void (*tp_planner_write_fn)(FILE* f, void* report);

typedef struct tp_planner_outputs {
    const char* json; /* a JSON file; "-": the JSON on stdout instead of the text; NULL: none */
    const char* csv;  /* a CSV file, or NULL */
    const char* png;  /* a gnuplot PNG, or NULL */
    tp_planner_write_fn write_text, write_json, write_csv;
    tp_gnuplot_script_fn write_plot; /* with png: png_width_px x png_height_px */
    int png_width_px, png_height_px;
} tp_planner_outputs;

/* Prints the text (the JSON for json "-") on stdout, then writes the JSON file, the CSV file
 * (each printed through atomic_file.h) and the PNG (tp_gnuplot_draw) that o names, all or
 * none (tp_file_set_* in tp_io.h): 1 when all were written, after "terrapatch CMD: wrote PATH" on
 * stderr for each, with SIGINT/SIGTERM ignored from then on (tp_interrupt_finished: the command
 * ends with its outputs written); 0 after a line saying what failed and that nothing was
 * written (every older file as it was). */
int tp_planner_write_outputs(const char* cmd, const tp_planner_outputs* o, void* report);

/* The exit after the work: after SIGINT/SIGTERM tp_cli_interrupted(); else code, stdout
 * flushed (tp_cli_finish) when it is TP_EXIT_OK. */
int tp_planner_finish(int code);

#endif /* TP_APP_PLANNER_CLI_H */
