/*
 * output_check.h - an output path checked before a command does any work: its extension names a
 * format the output is written in (tp_output_format_for in tp_io.h, the one module deciding
 * it) and its folder can be written (tp_output_check). app/base/output_check.c.
 */
#ifndef TP_APP_OUTPUT_CHECK_H
#define TP_APP_OUTPUT_CHECK_H

#include "tp_io.h"

/* TP_EXIT_OK when path can be written as an output of kind. Otherwise one line on stderr and
 * the exit code: for a format that is not written, TP_EXIT_USAGE after
 * "terrapatch CMD: OPTION PATH: why; CMD writes GeoTIFF (.tif, .tiff), PNG (.png), ..."; for a
 * folder that cannot be written, TP_EXIT_FAILURE after "terrapatch CMD: PATH: cannot write: ...".
 * option is the option as the command line names it ("-o", "--profile"). */
int tp_cli_output_check(const char* cmd, const char* option, const char* path, tp_output_kind kind);

/* The first half of tp_cli_output_check, for a parser: TP_EXIT_OK with *out (when not NULL) the
 * format path is written in, else TP_EXIT_USAGE after the same line listing what cmd writes.
 * The folder is not looked at. */
int tp_cli_output_format(const char* cmd, const char* option, const char* path, tp_output_kind kind,
                         tp_output_format* out);

#endif /* TP_APP_OUTPUT_CHECK_H */
