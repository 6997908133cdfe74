/* cli.c - what every subcommand's command line shares (see cli.h). */
#include "cli.h"

#include "tp_io.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char* command;
static char prefix[64] = "terrapatch: ";

void tp_cli_set_command(const char* name)
{
    command = name;
    if (name && *name)
        snprintf(prefix, sizeof prefix, "terrapatch %.40s: ", name);
    else
        snprintf(prefix, sizeof prefix, "terrapatch: ");
}

const char* tp_cli_command(void)
{
    return command;
}

const char* tp_cli_prefix(void)
{
    return prefix;
}

void tp_cli_vline(const char* what, const char* fmt, va_list ap)
{
    /* formatted whole and written with one call, so that lines of threads and children do not
     * mix */
    char local[2048];
    const size_t head = strlen(prefix) + strlen(what);
    char* line = local;
    va_list aq;
    va_copy(aq, ap);
    int n = vsnprintf(local + head, sizeof local - head - 1, fmt, aq);
    va_end(aq);
    if (n < 0)
        n = 0;
    if ((size_t)n >= sizeof local - head - 1) {
        char* big = malloc(head + (size_t)n + 2);
        if (big) {
            line = big;
            vsnprintf(line + head, (size_t)n + 1, fmt, ap);
        } else {
            n = (int)(sizeof local - head - 2); /* cut short rather than lost */
        }
    }
    memcpy(line, prefix, strlen(prefix));
    memcpy(line + strlen(prefix), what, strlen(what));
    line[head + (size_t)n] = '\n';
    fwrite(line, 1, head + (size_t)n + 1, stderr);
    if (line != local)
        free(line);
}

void tp_cli_error(const char* fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    tp_cli_vline("", fmt, ap);
    va_end(ap);
}

void tp_cli_warning(const char* fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    tp_cli_vline("warning: ", fmt, ap);
    va_end(ap);
}

void tp_cli_note(const char* fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    tp_cli_vline("", fmt, ap);
    va_end(ap);
}

int tp_cli_finish(int code)
{
    if (fflush(stdout) != 0 || ferror(stdout)) {
        tp_cli_error("cannot write to standard output: %s", strerror(errno));
        return TP_EXIT_FAILURE;
    }
    return code;
}

int tp_cli_interrupted(void)
{
    static atomic_int said; /* once: a store's build on a thread may say it too */
    if (atomic_fetch_add(&said, 1) == 0)
        tp_cli_error("interrupted");
    return 128 + tp_interrupted();
}

int tp_cli_usage(const char* cmd, const char* what, ...)
{
    char text[1024];
    va_list ap;
    va_start(ap, what);
    vsnprintf(text, sizeof text, what, ap);
    va_end(ap);
    tp_cli_error("%s (see 'terrapatch %s --help')", text, cmd);
    return TP_EXIT_USAGE;
}

int tp_cli_usage_at(const char* cmd, const char* what, const char* detail)
{
    if (detail[0])
        return tp_cli_usage(cmd, "%s '%s'", what, detail);
    return tp_cli_usage(cmd, "%s", what);
}

int tp_parse_int(const char* s, int lo, int hi, int* v)
{
    char* end;
    long x = strtol(s, &end, 10);
    if (end == s || *end || x < lo || x > hi)
        return 0;
    *v = (int)x;
    return 1;
}

int tp_parse_numbers(const char* s, double* v, int n)
{
    char* end;
    for (int i = 0; i < n; i++) {
        v[i] = strtod(s, &end);
        if (end == s || !isfinite(v[i]))
            return 0;
        s = end;
        if (i + 1 < n) {
            if (*s != ',')
                return 0;
            s++;
        }
    }
    return *s == '\0';
}

int tp_option_error(const char* cmd, const char* opt, const char* expected, const char* got)
{
    (void)cmd; /* the prefix names the command main() dispatched to */
    tp_cli_error("%s: expected %s, got '%s'", opt, expected, got);
    return -1;
}

const char* tp_cli_unprefixed(const char* path, const char* msg)
{
    const size_t n = strlen(path);
    return strncmp(msg, path, n) == 0 && msg[n] == ':' && msg[n + 1] == ' ' ? msg + n + 2 : msg;
}
