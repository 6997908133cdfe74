/*
 * cli.h - the helpers every subcommand uses (cli.c): exit codes, the lines on stderr, number
 * lists. The subcommands themselves are declared in app/terrapatch.h.
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
/* msg without its leading "path: " (an io message names its file; a caller that names the file
 * itself does not say it twice); msg itself when it does not start so. */
const char* tp_cli_unprefixed(const char* path, const char* msg);
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

/* Prints "terrapatch CMD: WHAT (see 'terrapatch CMD --help')" (what as printf's format; CMD
 * is cmd, the command whose help to read) and returns TP_EXIT_USAGE. */
int tp_cli_usage(const char* cmd, const char* what, ...) TP_CLI_PRINTF(2, 3);

/* The same for "WHAT 'DETAIL'", an argument quoted after the problem ("unknown option '-x'");
 * just WHAT when detail is "". */
int tp_cli_usage_at(const char* cmd, const char* what, const char* detail);

/* s (base 10, nothing after it) as an integer in lo .. hi: 1 with *v, else 0 (*v untouched). */
int tp_parse_int(const char* s, int lo, int hi, int* v);

/* Parses "a,b,c" into n finite numbers; 1 on success. */
int tp_parse_numbers(const char* s, double* v, int n);

/* Prints "terrapatch CMD: OPT: expected EXPECTED, got 'GOT'" (tp_cli_error) and returns -1. */
int tp_option_error(const char* cmd, const char* opt, const char* expected, const char* got);

#endif /* TP_APP_CLI_H */
