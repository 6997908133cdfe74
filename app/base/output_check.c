/* output_check.c - see output_check.h. */
#include "output_check.h"

#include "cli.h"

#include <stdio.h>

int tp_cli_output_format(const char* cmd, const char* option, const char* path, tp_output_kind kind,
                         tp_output_format* out)
{
    tp_error err = {{0}};
    tp_output_format fmt;
    if (tp_output_format_for(path, kind, &fmt, &err) != TP_OK) {
        char list[1024];
        tp_output_formats(kind, list, sizeof list);
        tp_cli_error("%s %s; %s writes %s", option, err.message, cmd, list);
        return TP_EXIT_USAGE;
    }
    if (out)
        *out = fmt;
    return TP_EXIT_OK;
}

int tp_cli_output_check(const char* cmd, const char* option, const char* path, tp_output_kind kind)
{
    int code = tp_cli_output_format(cmd, option, path, kind, NULL);
    if (code != TP_EXIT_OK)
        return code;
    tp_error err = {{0}};
    if (tp_output_check(path, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}
