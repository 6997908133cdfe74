/*
 * terrapatch.h - the subcommands of `terrapatch`, one function each, which main.c's table
 * dispatches to: argv[0] is the command's name ("info"); each returns an exit code (base/cli.h).
 * Each is defined in its room: commands/cmd_*.c, view/cmd_view.c, export/cmd_export.c,
 * bench/cmd_bench.c.
 */
#ifndef TP_APP_TERRAPATCH_H
#define TP_APP_TERRAPATCH_H

/* `terrapatch info [options] DEM`. argv[0] is "info"; returns an exit code. */
int tp_cli_info(int argc, char** argv);

/* `terrapatch coord [options] [INPUT ...]`. argv[0] is "coord"; returns an exit code. */
int tp_cli_coord(int argc, char** argv);

/* `terrapatch point DEM|STORE POS [options]`: what is here. argv[0] is "point". */
int tp_cli_point(int argc, char** argv);

/* `terrapatch los DEM|STORE --from POS --to POS [options]` (cmd_los.c): line of sight. */
int tp_cli_los(int argc, char** argv);

/* `terrapatch viewshed DEM|STORE --observer POS -o OUT.tif [options]` (cmd_viewshed.c). */
int tp_cli_viewshed(int argc, char** argv);

/* `terrapatch light DEM|STORE --date D --time T -o OUT.tif [options]` (cmd_light.c): sunlight
 * and the terrain's shadows at a moment. */
int tp_cli_light(int argc, char** argv);

/* `terrapatch profile DEM|STORE --route FILE [options]` (cmd_profile.c): a route's profile. */
int tp_cli_profile(int argc, char** argv);
/* `terrapatch contours DEM|STORE --interval M -o OUT [options]` (cmd_contours.c). */
int tp_cli_contours(int argc, char** argv);
/* `terrapatch terrain DEM|STORE -o OUT [options]` (cmd_terrain.c): slope, aspect or hillshade. */
int tp_cli_terrain(int argc, char** argv);

/* `terrapatch view [options] [DEM]`. argv[0] is "view"; returns an exit code. */
int tp_cli_view(int argc, char** argv);

/* `terrapatch export [options] DEM -o OUT`. argv[0] is "export"; returns an exit code. */
int tp_cli_export(int argc, char** argv);

/* `terrapatch bench [options] DEM`. argv[0] is "bench"; returns an exit code. */
int tp_cli_bench(int argc, char** argv);

/* `terrapatch build [options] SOURCE... -o NAME.tpt`. argv[0] is "build"; returns an exit code. */
int tp_cli_build(int argc, char** argv);

/* `terrapatch merge PART... -o MAP.tpt` (cmd_merge.c): the parts of a build in parts joined. */
int tp_cli_merge(int argc, char** argv);

/* `terrapatch imagery STORE.tpt IMAGE... [-o OUT.tpi]` (cmd_imagery.c): an imagery pyramid. */
int tp_cli_imagery(int argc, char** argv);

#endif /* TP_APP_TERRAPATCH_H */
