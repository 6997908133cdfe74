/*
 * options.h - the one command-line parser every terrapatch command uses (options.c).
 *
 * A command describes its options in tables of tp_option and walks its arguments with
 * tp_options_next. The rules are GNU getopt_long's, the same for every command:
 *   - options and operands in any order; "--" ends the options;
 *   - "--name VALUE" or "--name=VALUE"; a value may start with '-' ("--from -2.1,40");
 *   - a long name may be shortened to any prefix that names one option ("--rad 500");
 *   - short forms "-o FILE" and "-oFILE" where a table gives one;
 *   - "-h" and "--help" print the command's help and end the parse with exit 0;
 *   - "-" alone is an operand (stdin), and so is "-121.7" where the parser is told that
 *     operands may be negative numbers (a position: `point DEM 45.37 -121.69`).
 * Every usage error is one line through cli.h, "terrapatch CMD: WHAT (see 'terrapatch CMD
 * --help')", and exit 2; a bad value is "terrapatch CMD: --NAME: expected WHAT, got 'V'"
 * (tp_option_error).
 *
 * An option either fills a slot itself (a flag, a text, a number or an integer in a range) or
 * hands its value to code: to the table's handler (a group of options shared by several
 * commands, such as the DEM options of scene.h) or back to the caller's loop, by its code.
 */
#ifndef TP_APP_OPTIONS_H
#define TP_APP_OPTIONS_H

#include <stddef.h>

/* What an option does with its value. */
typedef enum tp_option_kind {
    TP_OPTION_CODE = 0, /* handed on with its code: to the table's handler, else returned by
                           tp_options_next; takes a value when .value is 1 */
    TP_OPTION_FLAG,     /* no value: *(int *)slot = 1 */
    TP_OPTION_TEXT,     /* *(const char **)slot = the value (borrowed from argv); a repeat
                           replaces it */
    TP_OPTION_NUMBER,   /* *(double *)slot = a finite decimal number (tp_position_decimal: '.'
                           or ',' as the decimal mark) from lo to hi; above lo when .open */
    TP_OPTION_INTEGER,  /* *(int *)slot = a base-10 integer from lo to hi */
} tp_option_kind;

typedef struct tp_option {
    const char* name;     /* "--radius" (or a short "-o" alone) */
    const char* alias;    /* another name, e.g. "-o" beside "--output"; NULL for none */
    tp_option_kind kind;
    void* slot;           /* where FLAG, TEXT, NUMBER and INTEGER put what they read */
    double lo, hi;        /* NUMBER and INTEGER: the range; open: lo itself is refused */
    int open;
    const char* expected; /* NUMBER and INTEGER: what the message says is expected, e.g. "a
                             number >= 0" ("--radius: expected a number >= 0, got 'x'") */
    int code;             /* CODE: > 0, unique among the tables of one parse */
    int value;            /* CODE: 1 when the option takes a value */
} tp_option;

/* Table entries, shortest first. TP_OPTION_ABOVE(0) as lo, open: "> 0". */
#define TP_OPT_FLAG(name, slot) {(name), NULL, TP_OPTION_FLAG, (slot), 0, 0, 0, NULL, 0, 0}
#define TP_OPT_TEXT(name, alias, slot) {(name), (alias), TP_OPTION_TEXT, (slot), 0, 0, 0, NULL, 0, 1}
#define TP_OPT_NUMBER(name, slot, lo, hi, expected)                                                \
    {(name), NULL, TP_OPTION_NUMBER, (slot), (lo), (hi), 0, (expected), 0, 1}
#define TP_OPT_NUMBER_ABOVE(name, slot, lo, hi, expected)                                          \
    {(name), NULL, TP_OPTION_NUMBER, (slot), (lo), (hi), 1, (expected), 0, 1}
#define TP_OPT_INTEGER(name, slot, lo, hi, expected)                                               \
    {(name), NULL, TP_OPTION_INTEGER, (slot), (lo), (hi), 0, (expected), 0, 1}
#define TP_OPT_CODE(name, alias, code, takes_value)                                                \
    {(name), (alias), TP_OPTION_CODE, NULL, 0, 0, 0, NULL, (code), (takes_value)}

/* A group's handler: reads value (NULL for an option without one) for the option code of its
 * table into ctx. 1 when done; -1 after one line (a bad value: tp_option_error); the parse
 * then ends with exit 2. cmd names the command in messages. */
typedef int (*tp_option_handler)(void* ctx, int code, const char* value, const char* cmd);

typedef struct tp_option_table {
    const tp_option* options;
    size_t count;
    tp_option_handler handler; /* NULL: its CODE options are returned to the caller */
    void* ctx;
} tp_option_table;

#define TP_OPTIONS_COUNT(a) (sizeof(a) / sizeof((a)[0]))
#define TP_OPTIONS_MAX_TABLES 6

/* tp_options_next's results besides an option's code (> 0). */
#define TP_OPTIONS_END 0        /* every argument read */
#define TP_OPTIONS_OPERAND (-1) /* an operand, in .value */
#define TP_OPTIONS_EXIT (-2)    /* the parse ends with exit code .exit (help printed: 0; usage
                                   error printed: 2) */

typedef struct tp_options {
    /* set by tp_options_init */
    const char* cmd;
    int argc;
    char** argv;
    void (*help)(void);      /* prints the help on stdout ("-h", "--help") */
    int negative_operands;   /* 1: "-4", "-.5", "-121.7" are operands, not options */
    tp_option_table tables[TP_OPTIONS_MAX_TABLES];
    int table_count;
    /* the state */
    int next;                /* the next argument to read */
    int options_ended;       /* after "--" */
    const tp_option* option; /* the option just read (its code returned), else NULL */
    const char* value;       /* its value, or the operand; NULL for none */
    int at;                  /* the argument it came from (the option's, for a value) */
    int exit;                /* after TP_OPTIONS_EXIT */
} tp_options;

/* Starts a parse of argv[1 .. argc-1] for command cmd ("los"), with the command's help
 * printer. Add tables with tp_options_add before the first tp_options_next. */
void tp_options_init(tp_options* p, const char* cmd, int argc, char** argv, void (*help)(void));

/* Adds a table (borrowed: it must outlive the parse). handler NULL: its CODE options are
 * returned by tp_options_next. At most TP_OPTIONS_MAX_TABLES. An option named as one of an
 * earlier table is shadowed by it (export's own --origin before the DEM options' one). */
void tp_options_add(tp_options* p, const tp_option* options, size_t count,
                    tp_option_handler handler, void* ctx);

/* Reads the next argument (and its value): fills the slot of a FLAG, TEXT, NUMBER or INTEGER
 * option, or calls its table's handler, and goes on; returns the code of a CODE option whose
 * table has no handler (value in p->value), TP_OPTIONS_OPERAND with p->value, TP_OPTIONS_END,
 * or TP_OPTIONS_EXIT with p->exit after the help or a usage error's line: an unknown option
 * ("unknown option '--x'", with a hint to quote a position typed with spaces after a position
 * option), a shortened name that fits several ("option '--s' is ambiguous: --step, --size"),
 * a value missing ("missing value for --json") or given to an option that takes none ("--quiet
 * takes no value"), a value out of range. */
int tp_options_next(tp_options* p);

/* Keeps the operand just read (p->value) among the operands of a command that takes a list:
 * moves it to argv[1 + *count] and counts it, as getopt permuted argv (the argument it replaces
 * was read before). Once the parse ends, the operands kept are argv[1 .. *count], in order. */
void tp_options_keep(tp_options* p, int* count);

/* The usage error for the argument just read (p->at) when the caller cannot place it: "more
 * than one DEM given" for an operand (what, when not NULL, replaces "DEM"), else "unknown
 * option 'A'", each followed by the position hint when it applies, else by hint ("" for
 * none). Sets p->exit = 2 and returns TP_OPTIONS_EXIT. */
int tp_options_stray(tp_options* p, const char* what, const char* hint);

/* The usage error "--NAME: expected EXPECTED, got 'VALUE'" for the option just read (its
 * value), from the caller's own check. Sets p->exit = 2, returns TP_OPTIONS_EXIT. */
int tp_options_bad_value(tp_options* p, const char* expected);

/* value (NULL: missing) as a decimal number in [lo, hi] (above lo when open): 1 with *out;
 * else 0 after "NAME: expected EXPECTED, got 'V'". For the numbers inside a value ("--sun
 * AZ,EL") and the tables' NUMBER options. */
int tp_option_number(const char* cmd, const char* name, const char* value, double lo, double hi,
                     int open, const char* expected, double* out);

/* value as two decimal numbers "A,B" (a comma between, '.' as the decimal mark: "--sun
 * 135.5,30", "--azimuth 350,10"), each in [lo, hi]: 1 with out[0], out[1]; else 0 after "NAME:
 * expected EXPECTED, got 'V'". */
int tp_option_pair(const char* cmd, const char* name, const char* value, double lo, double hi,
                   const char* expected, double out[2]);

/* The same for a base-10 integer. */
int tp_option_integer(const char* cmd, const char* name, const char* value, long lo, long hi,
                      const char* expected, long* out);

#endif /* TP_APP_OPTIONS_H */
