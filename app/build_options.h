/*
 * build_options.h - the options of `terrapatch build` (its --help, and their parsing into
 * build_options); cmd_build.c runs the build they describe.
 */
#ifndef TP_APP_BUILD_OPTIONS_H
#define TP_APP_BUILD_OPTIONS_H

#include "cmd_imagery.h"

#include "tp_io.h"

/* The smallest --memory accepted (MB): the program's fixed part alone is more than that. */
#define BUILD_MIN_MEMORY_MB 64

/* The least share of the mosaic the sources must cover without --allow-gaps. */
#define TP_BUILD_MIN_COVERED 0.5

typedef struct build_options {
    const char** sources;
    int source_count;
    const char* out;
    int patch_size;
    const char* crs;
    tp_resampling resampling;
    int memory_mb;
    int fill_max;             /* samples; 0 fills nothing; TP_FILL_MAX_ANY (the default) any size */
    const char* fill_from;    /* --fill-from: fill voids from this raster */
    const char* z_unit;       /* --z-unit m|ft|us-ft; NULL: the sources' */
    const char* imagery[256]; /* --imagery: a pyramid NAME.tpi of these, after the store */
    int imagery_count;
    tp_imagery_cli imagery_cli; /* --imagery-texel-shift, --imagery-resolution */
    int imagery_shift_given;
    int allow_gaps; /* --allow-gaps: build even when the sources cover under
                       TP_BUILD_MIN_COVERED of their mosaic */
    int threads;
    const char* json; /* NULL, "-" or a path */
    int quiet;
} build_options;

/* Parses argv (getopt_long; --help prints the help and finishes the command). Returns -1 when
 * the options are fine and *o holds them (sources and strings borrowed from argv), else the
 * exit code to return after the message on stderr naming the option (2, usage). */
int tp_build_parse_options(int argc, char** argv, build_options* o);

#endif
