/*
 * main.c - `terrapatch`: one table of the subcommands (terrapatch.h; commands/ for the small
 * ones, view/, export/, bench/ for the big ones) drives both the dispatch and the help.
 */
#include "terrapatch.h"

#include "cli.h"
#include "memory.h"

#include "tp_core.h"
#include "tp_io.h"

#include <stdio.h>
#include <string.h>

typedef int (*command_fn)(int argc, char** argv);

/* The commands: what dispatches and what `terrapatch --help` lists, in its order. */
static const struct {
    const char* name;
    command_fn run;
    const char* args;    /* after the name in the list */
    const char* summary; /* one line */
} commands[] = {
    {"info", tp_cli_info, "DEM", "describe a DEM and the patch grid terrapatch builds from it"},
    {"view", tp_cli_view, "[DEM]",
     "show the terrain in a window, or headless to a PNG (--headless)"},
    {"export", tp_cli_export, "DEM -o OUT", "write the mesh terrapatch draws (VTK .vtp/.vtk/.vtm)"},
    {"bench", tp_cli_bench, "DEM",
     "frame rate against measured error, headless, for every LoD mode"},
    {"build", tp_cli_build, "SOURCE... -o NAME.tpt",
     "build a terrain store from DEM tiles (any size)"},
    {"merge", tp_cli_merge, "PART... -o NAME.tpt",
     "join the parts of a build in parts (build --part I/N) into one store"},
    {"imagery", tp_cli_imagery, "STORE.tpt IMAGE...",
     "orthophotos or maps as a pyramid for the viewer"},
    {"coord", tp_cli_coord, "", "convert coordinates: lat/lon, UTM/UPS, MGRS, ECEF; geodesics"},
    {"point", tp_cli_point, "DEM POS",
     "what is here: position in every form, elevation, slope, aspect"},
    {"los", tp_cli_los, "DEM --from POS --to POS",
     "line of sight: seen or not, what is in the way"},
    {"viewshed", tp_cli_viewshed, "DEM --observer POS -o OUT.tif",
     "what an observer sees (GeoTIFF)"},
    {"light", tp_cli_light, "DEM --date D --time T -o OUT.tif", "sunlight and shadows at a moment"},
    {"profile", tp_cli_profile, "DEM --route FILE",
     "a route's elevation profile: length, climb, steepest"},
    {"contours", tp_cli_contours, "DEM --interval M -o OUT",
     "contour lines (GDAL) as a vector file"},
    {"terrain", tp_cli_terrain, "DEM -o OUT", "slope, aspect or hillshade (gdaldem) as a raster"},
};
#define COMMAND_COUNT (sizeof commands / sizeof commands[0])

static void print_help(FILE* f)
{
    fputs("usage: terrapatch COMMAND [options] ...\n"
          "       terrapatch --help | --version\n"
          "\n"
          "A terrain viewer for GIS elevation rasters (any DEM GDAL reads): the heights are\n"
          "tiled into (2^n+1)^2 patches, each drawn at its own level of detail.\n"
          "\n"
          "commands:\n",
          f);
    for (size_t i = 0; i < COMMAND_COUNT; i++)
        fprintf(f, "  %s%s%s   %s\n", commands[i].name, commands[i].args[0] ? " " : "",
                commands[i].args, commands[i].summary);
    fputs("\n"
          "Run 'terrapatch COMMAND --help' for the options of a command.\n"
          "Exit status: 0 success, 1 failure, 2 usage error, 130/143 after SIGINT/SIGTERM\n"
          "(files are written whole or not at all: a temporary file beside each output,\n"
          "removed on any failure or signal, renamed into place when complete).\n",
          f);
}

/* The command named name, NULL for none. */
static command_fn command_named(const char* name)
{
    for (size_t i = 0; i < COMMAND_COUNT; i++)
        if (!strcmp(name, commands[i].name))
            return commands[i].run;
    return NULL;
}

static int run_command(int argc, char** argv)
{
    if (argc < 2) {
        tp_cli_error("missing command (try 'terrapatch --help')");
        return TP_EXIT_USAGE;
    }
    const char* cmd = argv[1];
    if (!strcmp(cmd, "--help") || !strcmp(cmd, "-h") || !strcmp(cmd, "help")) {
        print_help(stdout);
        return tp_cli_finish(TP_EXIT_OK);
    }
    if (!strcmp(cmd, "--version")) {
        printf("terrapatch %s\n", TP_VERSION);
        return tp_cli_finish(TP_EXIT_OK);
    }
    const command_fn run = command_named(cmd);
    if (run)
        return run(argc - 1, argv + 1);
    if (cmd[0] == '-')
        tp_cli_error("unknown option '%s' (try 'terrapatch --help')", cmd);
    else
        tp_cli_error("unknown command '%s' (try 'terrapatch --help')", cmd);
    return TP_EXIT_USAGE;
}

int main(int argc, char** argv)
{
    /* every line on stderr starts "terrapatch CMD: " from here on, once argv names a command
     * (the memory limit's message too) */
    if (argc >= 2 && command_named(argv[1]))
        tp_cli_set_command(argv[1]);
    /* SIGINT/SIGTERM kill at once, except while a file is being written: then the writer
     * removes its temporary file first and we exit with 128 + the signal. */
    tp_interrupt_install();
    if (!tp_memory_limit_check())
        return TP_EXIT_USAGE;
    int code = run_command(argc, argv);
    return tp_interrupted() ? tp_cli_interrupted() : code;
}
