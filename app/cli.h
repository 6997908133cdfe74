/*
 * cli.h - the terrapatch command line: one function per subcommand, and the helpers every
 * subcommand's parser uses (cli.c).
 *
 * Exit codes shared by every subcommand. Results go to stdout; every line on stderr (errors,
 * warnings, notes, progress, "wrote PATH") starts "terrapatch CMD: ", CMD the subcommand main()
 * dispatched to (tp_cli_set_command), "terrapatch: " before one is known: tp_cli_error and the
 * others below print them (docs/cli.md, "Messages").
 */
#ifndef TP_APP_CLI_H
#define TP_APP_CLI_H

#include <stdarg.h>

#define TP_EXIT_OK 0
#define TP_EXIT_FAILURE 1 /* the work failed: unreadable DEM, bad data, ... */
#define TP_EXIT_USAGE 2   /* bad command line */
/* SIGINT or SIGTERM during a write: 128 + the signal (130, 143), as a shell reports a process
 * the signal killed; tp_cli_interrupted() returns it. */

/* `terrapatch info [options] DEM`. argv[0] is "info"; returns an exit code. */
int tp_cli_info(int argc, char** argv);

/* `terrapatch info [--json] STORE.tpt` (cmd_info_store.c): called by tp_cli_info for a store. */
int tp_info_store(const char* path, int json);

/* `terrapatch info [--json] PYRAMID.tpi` (cmd_info_imagery.c): called by tp_cli_info for an
 * imagery pyramid; every block read and checked (exit 1 naming the first damaged one). */
int tp_info_imagery(const char* path, int json);
/* One line about the imagery pyramid (its path with .tpi) and one about the light map (.tpl)
 * beside a store, for each there is. */
void tp_info_imagery_beside(const char* store_path);

/* `terrapatch coord [options] [INPUT ...]`. argv[0] is "coord"; returns an exit code. */
int tp_cli_coord(int argc, char** argv);

/* `terrapatch point DEM|STORE POS [options]`: what is here. argv[0] is "point". */
int tp_cli_point(int argc, char** argv);

/* `terrapatch los DEM|STORE --from POS --to POS [options]` (cmd_los.c): line of sight. */
int tp_cli_los(int argc, char** argv);

/* `terrapatch viewshed DEM|STORE --observer POS -o OUT.tif [options]` (cmd_viewshed.c). */
int tp_cli_viewshed(int argc, char** argv);

/* `terrapatch light DEM|STORE --date D --time T -o OUT.tif [options]` (cmd_light.c): sunlight
 * and the terrain's shadows at a moment. */
int tp_cli_light(int argc, char** argv);

/* `terrapatch profile DEM|STORE --route FILE [options]` (cmd_profile.c): a route's profile. */
int tp_cli_profile(int argc, char** argv);
/* `terrapatch contours DEM|STORE --interval M -o OUT [options]` (cmd_contours.c). */
int tp_cli_contours(int argc, char** argv);

/* `terrapatch view [options] [DEM]`. argv[0] is "view"; returns an exit code. */
int tp_cli_view(int argc, char** argv);

/* `terrapatch export [options] DEM -o OUT`. argv[0] is "export"; returns an exit code. */
int tp_cli_export(int argc, char** argv);

/* `terrapatch bench [options] DEM`. argv[0] is "bench"; returns an exit code. */
int tp_cli_bench(int argc, char** argv);

/* `terrapatch build [options] SOURCE... -o NAME.tpt`. argv[0] is "build"; returns an exit code. */
int tp_cli_build(int argc, char** argv);

/* `terrapatch imagery STORE.tpt IMAGE... [-o OUT.tpi]` (cmd_imagery.c): an imagery pyramid. */
int tp_cli_imagery(int argc, char** argv);

/* The subcommand main() dispatched to ("info", "view", ...), named in the prefix of every line
 * on stderr; name is borrowed (argv), NULL for none. Set once, by main(). */
void tp_cli_set_command(const char* name);
/* The name set by tp_cli_set_command, NULL before. */
const char* tp_cli_command(void);
/* "terrapatch CMD: ", or "terrapatch: " before a command is known: for the lines the functions
 * below cannot print whole (a progress bar redrawn after '\r'). */
const char* tp_cli_prefix(void);

#if defined(__GNUC__)
#define TP_CLI_PRINTF(f, a) __attribute__((format(printf, f, a)))
#else
#define TP_CLI_PRINTF(f, a)
#endif
/* One line on stderr: the prefix, the text (printf's format, without the newline), '\n'; written
 * in one piece. For failures and usage errors. */
void tp_cli_error(const char* fmt, ...) TP_CLI_PRINTF(1, 2);
/* The same, "warning: " after the prefix: something the user should know, the work goes on. */
void tp_cli_warning(const char* fmt, ...) TP_CLI_PRINTF(1, 2);
/* The same as tp_cli_error, for what is neither a failure nor a warning: notes, progress lines,
 * "wrote PATH". */
void tp_cli_note(const char* fmt, ...) TP_CLI_PRINTF(1, 2);
/* A line from a va_list: prefix, then `what` (e.g. "warning: ", or ""), then the text. */
void tp_cli_vline(const char* what, const char* fmt, va_list ap) TP_CLI_PRINTF(2, 0);

/* Flushes stdout; on a write error prints one line and returns TP_EXIT_FAILURE, else code. */
int tp_cli_finish(int code);

/* After SIGINT/SIGTERM (tp_interrupted() in tp_io.h, installed by main): prints
 * "terrapatch CMD: interrupted" (once per process) and returns 128 + the signal. */
int tp_cli_interrupted(void);

/* Parses "a,b,c" into n finite numbers; 1 on success. */
int tp_parse_numbers(const char* s, double* v, int n);

/* Prints "terrapatch CMD: OPT: expected EXPECTED, got 'GOT'" (tp_cli_error) and returns -1. */
int tp_option_error(const char* cmd, const char* opt, const char* expected, const char* got);

#endif /* TP_APP_CLI_H */
