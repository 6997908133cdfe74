/*
 * view_args.h - the command line of `terrapatch view`: its options read into view_options and
 * checked together (view_args.c), and its --help (view_help.c).
 */
#ifndef TP_APP_VIEW_ARGS_H
#define TP_APP_VIEW_ARGS_H

#include "view.h"

/* The sample scene the help names: where it lies in the source tree (cmd_view.c finds it from the
 * binary's own location). */
#define TP_SAMPLE_SCENE "data/lf_elev_220_mt_hood_utm.tif"

/* Reads argv into o (o's earlier contents are ignored; its strings point into argv) and checks
 * the options together. Returns -1 when the view is to run, else the exit code to return at
 * once: TP_EXIT_USAGE after one line on stderr, or --help's (after printing it). o->path is the
 * DEM or store given, or NULL for none (the sample scene). */
int tp_view_parse_options(int argc, char** argv, view_options* o);

/* Prints `terrapatch view --help` on stdout. */
void tp_view_print_help(void);

#endif
