/* cli.c - what every subcommand's command line shares (see cli.h). */
#include "cli.h"

#include "tp_io.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int tp_cli_finish(int code)
{
    if (fflush(stdout) != 0 || ferror(stdout)) {
        fprintf(stderr, "terrapatch: cannot write to standard output: %s\n", strerror(errno));
        return TP_EXIT_FAILURE;
    }
    return code;
}

int tp_cli_interrupted(void)
{
    static int said;
    if (!said++)
        fputs("terrapatch: interrupted\n", stderr);
    return 128 + tp_interrupted();
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
    fprintf(stderr, "terrapatch %s: %s: expected %s, got '%s'\n", cmd, opt, expected, got);
    return -1;
}
