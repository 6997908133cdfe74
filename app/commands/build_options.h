/*
 * build_options.h - the options of `terrapatch build` (its --help, and their parsing into
 * build_options); cmd_build.c runs the build they describe (tp_store_build, then the imagery).
 */
#ifndef TP_APP_BUILD_OPTIONS_H
#define TP_APP_BUILD_OPTIONS_H

#include "cmd_imagery.h"
#include "store_build.h"

#include "tp_io.h"

typedef struct build_options {
    tp_build_options build;   /* the store (store_build.h): sources and strings borrowed from argv */
    const char* imagery[256]; /* --imagery: a pyramid NAME.tpi of these, after the store */
    int imagery_count;
    tp_imagery_cli imagery_cli; /* --imagery-texel-shift, --imagery-resolution */
    const char* json; /* NULL, "-" or a path */
} build_options;

/* Parses argv (options.h; --help prints the help and finishes the command). Returns -1 when
 * the options are fine and *o holds them (sources and strings borrowed from argv, the sources
 * moved to argv[1 ..]), else the exit code to return after the message on stderr (2, usage). */
int tp_build_parse_options(int argc, char** argv, build_options* o);

#endif
