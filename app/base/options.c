/* options.c - the one command-line parser (see options.h). */
#include "options.h"

#include "cli.h"
#include "position.h"

#include <ctype.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void tp_options_init(tp_options* p, const char* cmd, int argc, char** argv, void (*help)(void))
{
    memset(p, 0, sizeof *p);
    p->cmd = cmd;
    p->argc = argc;
    p->argv = argv;
    p->help = help;
    p->next = 1;
}

void tp_options_add(tp_options* p, const tp_option* options, size_t count,
                    tp_option_handler handler, void* ctx)
{
    if (p->table_count == TP_OPTIONS_MAX_TABLES) {
        fprintf(stderr, "terrapatch: internal error: more than %d option tables\n",
                TP_OPTIONS_MAX_TABLES);
        abort();
    }
    p->tables[p->table_count++] = (tp_option_table){options, count, handler, ctx};
}

static int usage(tp_options* p, const char* fmt, const char* a, const char* b)
{
    tp_cli_usage(p->cmd, fmt, a, b);
    p->exit = TP_EXIT_USAGE;
    return TP_OPTIONS_EXIT;
}

/* ---- the hint for a position typed with spaces ---- */

/* The options that take a position. */
static const char* const position_options[] = {"--from", "--to",     "--observer",
                                               "--at",   "--around", "--through"};

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
    for (size_t k = 0; k < TP_OPTIONS_COUNT(position_options); ++k) {
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

/* Into own: " (quote a position with spaces: --from \"42.5 -2.1\")" when argv[i] is part of a
 * position left unquoted after a position option; else "". */
static void position_hint(int argc, char** argv, int i, char* own, size_t cap)
{
    const char* a = argv[i];
    own[0] = '\0';
    /* back from argv[i] over pieces of a position to the option that took the first one */
    for (int j = i - 1; j >= 1; --j) {
        const char* v = position_option_value(argc, argv, j);
        const int first = v == argv[j + 1] ? j + 2 : j + 1; /* the pieces after v */
        int end = position_piece(a) ? i : i - 1;            /* and on after argv[i] */
        if (v && end >= first && position_piece(v)) {
            for (const int on = end == i; on && end + 1 < argc && position_piece(argv[end + 1]);)
                ++end;
            size_t at = (size_t)snprintf(own, cap, " (quote a position with spaces: %.*s \"%s",
                                         (int)strcspn(argv[j], "="), argv[j], v);
            for (int k = first; k <= end && at < cap; ++k)
                at += (size_t)snprintf(own + at, cap - at, " %s", argv[k]);
            if (at < cap)
                snprintf(own + at, cap - at, "\")");
            return;
        }
        if (!position_piece(argv[j]))
            return;
    }
}

int tp_options_stray(tp_options* p, const char* what, const char* hint)
{
    char own[512];
    position_hint(p->argc, p->argv, p->at, own, sizeof own);
    const char* a = p->argv[p->at];
    if (own[0])
        hint = own;
    if (a[0] == '-' && a[1] && !p->options_ended) {
        tp_cli_usage(p->cmd, "unknown option '%s'%s", a, hint ? hint : "");
    } else {
        tp_cli_usage(p->cmd, "more than one %s given%s", what ? what : "DEM", hint ? hint : "");
    }
    p->exit = TP_EXIT_USAGE;
    return TP_OPTIONS_EXIT;
}

void tp_options_keep(tp_options* p, int* count)
{
    p->argv[1 + (*count)++] = (char*)p->value; /* 1 + *count <= p->at: read already */
}

/* ---- values ---- */

int tp_option_number(const char* cmd, const char* name, const char* value, double lo, double hi,
                     int open, const char* expected, double* out)
{
    double d;
    if (!value || tp_position_decimal(value, &d) != 1 || !isfinite(d) || d < lo || d > hi ||
        (open && d == lo))
        return tp_option_error(cmd, name, expected, value ? value : ""), 0;
    *out = d;
    return 1;
}

int tp_option_pair(const char* cmd, const char* name, const char* value, double lo, double hi,
                   const char* expected, double out[2])
{
    const char* comma = value ? strchr(value, ',') : NULL;
    char first[64];
    double a, b;
    char* end = NULL;
    if (comma && !strchr(comma + 1, ',') && (size_t)(comma - value) < sizeof first) {
        memcpy(first, value, (size_t)(comma - value));
        first[comma - value] = '\0';
        a = strtod(first, &end);
        if (end != first && !*end && isfinite(a) && a >= lo && a <= hi) {
            b = strtod(comma + 1, &end);
            if (end != comma + 1 && !*end && isfinite(b) && b >= lo && b <= hi) {
                out[0] = a;
                out[1] = b;
                return 1;
            }
        }
    }
    return tp_option_error(cmd, name, expected, value ? value : ""), 0;
}

int tp_option_integer(const char* cmd, const char* name, const char* value, long lo, long hi,
                      const char* expected, long* out)
{
    char* end = NULL;
    long n = value ? strtol(value, &end, 10) : 0;
    /* out of long's range, strtol gives LONG_MIN or LONG_MAX: outside lo .. hi unless hi is
     * LONG_MAX ("an integer >= 1" takes any large number) */
    if (!value || !*value || *end || n < lo || n > hi)
        return tp_option_error(cmd, name, expected, value ? value : ""), 0;
    *out = n;
    return 1;
}

int tp_options_bad_value(tp_options* p, const char* expected)
{
    tp_option_error(p->cmd, p->option ? p->option->name : p->argv[p->at], expected,
                    p->value ? p->value : "");
    p->exit = TP_EXIT_USAGE;
    return TP_OPTIONS_EXIT;
}

/* Fills o's slot from value; 1, or 0 after the message. */
static int fill_slot(const tp_options* p, const tp_option* o, const char* value)
{
    switch (o->kind) {
    case TP_OPTION_FLAG: *(int*)o->slot = 1; return 1;
    case TP_OPTION_TEXT: *(const char**)o->slot = value; return 1;
    case TP_OPTION_NUMBER:
        return tp_option_number(p->cmd, o->name, value, o->lo, o->hi, o->open, o->expected,
                                (double*)o->slot);
    case TP_OPTION_INTEGER: {
        long n;
        if (!tp_option_integer(p->cmd, o->name, value, (long)o->lo, (long)o->hi, o->expected, &n))
            return 0;
        *(int*)o->slot = (int)n;
        return 1;
    }
    case TP_OPTION_CODE: break;
    }
    return 0;
}

/* ---- finding an option ---- */

/* 1 when name (len bytes) is exactly n. */
static int same(const char* n, const char* name, size_t len)
{
    return n && strlen(n) == len && !strncmp(n, name, len);
}

/* The option named by name (len bytes, "--rad" or "-o"): the one of that exact name, else the
 * only long option it begins; *table its table. NULL with *ambiguous set when it begins
 * several (names listed into list), NULL alone when none. */
static const tp_option* find_option(const tp_options* p, const char* name, size_t len,
                                    const tp_option_table** table, int* ambiguous, char* list,
                                    size_t cap)
{
    const tp_option* found = NULL;
    int matches = 0;
    size_t at = 0;
    list[0] = '\0';
    for (int t = 0; t < p->table_count; ++t)
        for (size_t k = 0; k < p->tables[t].count; ++k) {
            const tp_option* o = &p->tables[t].options[k];
            if (same(o->name, name, len) || same(o->alias, name, len)) {
                *table = &p->tables[t];
                return o;
            }
        }
    if (len < 3 || name[1] != '-') /* a prefix of long names only: "--x" */
        return NULL;
    for (int t = 0; t < p->table_count; ++t)
        for (size_t k = 0; k < p->tables[t].count; ++k) {
            const tp_option* o = &p->tables[t].options[k];
            const char* n = !strncmp(o->name, name, len)                   ? o->name
                            : o->alias && !strncmp(o->alias, name, len) ? o->alias
                                                                           : NULL;
            if (!n || (found && !strcmp(found->name, o->name)))
                continue; /* found again, or shadowed by an earlier table's of its name */
            if (at < cap)
                at += (size_t)snprintf(list + at, cap - at, "%s%s", matches ? ", " : "", n);
            ++matches;
            found = o;
            *table = &p->tables[t];
        }
    if (matches > 1) {
        *ambiguous = 1;
        return NULL;
    }
    return found;
}

/* 1 when a is an operand: not starting with '-', "-" alone, or a negative number where those
 * are operands. */
static int is_operand(const tp_options* p, const char* a)
{
    if (a[0] != '-' || !a[1] || p->options_ended)
        return 1;
    return p->negative_operands && (isdigit((unsigned char)a[1]) || a[1] == '.');
}

/* What read_option returns for an option it filled or handed to its table's handler. */
#define READ_ON (-100)

/* Reads the option at argv[p->at] (its name and value): fills it or hands it to its table's
 * handler (READ_ON), or returns its code, or TP_OPTIONS_EXIT. */
static int read_option(tp_options* p)
{
    const char* a = p->argv[p->at];
    const int is_long = a[1] == '-';
    /* the name: "--name" up to '=', or "-x" (its value may follow at once: "-oFILE") */
    const size_t len = is_long ? strcspn(a, "=") : 2;
    const char* attached = is_long ? (a[len] == '=' ? a + len + 1 : NULL) : (a[2] ? a + 2 : NULL);
    if ((same("--help", a, len) || same("-h", a, len)) && p->help && !attached) {
        p->help();
        p->exit = tp_cli_finish(TP_EXIT_OK);
        return TP_OPTIONS_EXIT;
    }
    const tp_option_table* table = NULL;
    int ambiguous = 0;
    char list[256];
    const tp_option* o = find_option(p, a, len, &table, &ambiguous, list, sizeof list);
    if (ambiguous) {
        char name[128];
        snprintf(name, sizeof name, "%.*s", (int)len, a);
        return usage(p, "option '%s' is ambiguous: %s", name, list);
    }
    if (!o)
        return tp_options_stray(p, NULL, "");
    const int takes_value = o->kind == TP_OPTION_CODE ? o->value : o->kind != TP_OPTION_FLAG;
    const char* value = NULL;
    if (takes_value) {
        if (attached)
            value = attached;
        else if (p->next < p->argc)
            value = p->argv[p->next++];
        else
            return usage(p, "missing value for %s%s", o->name, "");
    } else if (attached) {
        return usage(p, "%s takes no value%s", o->name, "");
    }
    p->option = o;
    p->value = value;
    if (o->kind != TP_OPTION_CODE) {
        if (fill_slot(p, o, value))
            return READ_ON;
    } else if (!table->handler) {
        return o->code;
    } else if (table->handler(table->ctx, o->code, value, p->cmd) >= 0) {
        return READ_ON;
    }
    p->exit = TP_EXIT_USAGE;
    return TP_OPTIONS_EXIT;
}

int tp_options_next(tp_options* p)
{
    p->option = NULL;
    p->value = NULL;
    while (p->next < p->argc) {
        p->at = p->next++;
        const char* a = p->argv[p->at];
        if (!p->options_ended && !strcmp(a, "--")) {
            p->options_ended = 1;
            continue;
        }
        if (is_operand(p, a)) {
            p->value = a;
            return TP_OPTIONS_OPERAND;
        }
        const int r = read_option(p);
        if (r != READ_ON)
            return r;
        p->option = NULL;
        p->value = NULL;
    }
    return TP_OPTIONS_END;
}
