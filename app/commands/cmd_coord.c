/*
 * cmd_coord.c - `terrapatch coord [options] [INPUT ...]`: a batch coordinate converter in the
 * manner of GeographicLib's GeoConvert (and GeodSolve -i with --geodesic).
 *
 * One input per line, from the arguments or standard input; one output line per input line,
 * "ERROR: reason" in place of a line that fails, so that output stays aligned with input.
 * Each line is parsed and converted by tp_coord_line_convert (coord_line.c); every conversion
 * is GeographicLib's, through io/include/tp_geo.h.
 */
#define _POSIX_C_SOURCE 200809L /* getline */

#include "terrapatch.h"
#include "cli.h"
#include "coord_line.h"
#include "options.h"

#include "tp_core.h"
#include "tp_geo.h"

#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct coord_options {
    tp_coord_request req;
    int to_given;
    int inputs; /* the INPUTs, argv[1 .. inputs]; 0: read stdin */
} coord_options;

enum { OPT_TO = 1 };

#define DEFAULT_MGRS_PRECISION 5

static void print_help(void)
{
    fputs("usage: terrapatch coord [options] [INPUT ...]\n"
          "\n"
          "Converts coordinates on the WGS84 ellipsoid one input at a time, like GeographicLib's\n"
          "GeoConvert (GeodSolve -i with --geodesic); every conversion is GeographicLib's. Each\n"
          "INPUT argument is one input line; with none, lines are read from standard input. Each\n"
          "input line gives exactly one output line: a line that cannot be converted gives\n"
          "'ERROR: reason' on stdout in its place (so output stays aligned with input), the\n"
          "reason with the line number on stderr, and the run goes on.\n"
          "\n"
          "input, one position per line, latitude first (a comma counts as a space):\n"
          "  LAT LON        decimal degrees, LAT in [-90, 90], LON in [-540, 540]\n"
          "                 (45.5 -122.68, or 45.5,-122.68), or degrees-minutes-seconds as\n"
          "                 GeoConvert reads them (GeographicLib's DMS): 40d26'46\"N 79d58'56\"W,\n"
          "                 40:26:46N 079:58:56W, N40.446 W79.982; with N/S/E/W letters\n"
          "                 either order works; with spaces the letters end (or start) each\n"
          "                 coordinate: 55 28 41.88 N 2 08 44.16 W, N 55 28.698 W 2 08.736\n"
          "  LAT LON H      the same plus H, the ELLIPSOIDAL height in metres (above the WGS84\n"
          "                 ellipsoid, not above sea level or the geoid); only with --to ecef\n"
          "  ZONE E N       UTM: zone 1..60 and hemisphere n or s in lower case, or north or\n"
          "                 south (33n 500000 4649776.22, 33south ...; E N ZONE also reads);\n"
          "                 UPS: n or s alone (n 2000000 1333272.296, or UPS n ...); easting,\n"
          "                 northing in m, labels allowed (31n 376749.5 E 4706383.2 N)\n"
          "  ZONE E N       with a latitude band as maps and GPS units write it: 30U 554001\n"
          "                 6148350, 19J 300000 6900000 (C..X; A B Y Z for UPS); the position\n"
          "                 must lie in the band. S is band S (32N..40N) on a map but the\n"
          "                 south in GeographicLib's notation: where both are positions\n"
          "                 (33S 500000 4000000) the line is an ERROR naming both; write\n"
          "                 33north, 33south or MGRS. N is north either way\n"
          "  MGRS           an MGRS reference of any precision, any letter case\n"
          "                 (33TWN0000049776, 38smb4488, 33T WN 00000 49776), read as the\n"
          "                 centre of its square\n"
          "                 Every form 'coord' and 'point' print reads back ('UTM' or 'MGRS'\n"
          "                 before it is passed over)\n"
          "\n"
          "options:\n"
          "  --to geo        LAT LON in degrees with 9 decimals, LON in [-180, 180] (default)\n"
          "  --to utm        ZONE E N in metres with 3 decimals (GeoConvert -u -p 3), in the\n"
          "                  standard zone: UTM from 80S to 84N (Norway and Svalbard\n"
          "                  exceptions included), else UPS with the zone printed as n or s;\n"
          "                  ZONE E N or MGRS input already in that zone keeps its own E N\n"
          "  --to mgrs       an MGRS reference with --precision digits per coordinate\n"
          "  --to ecef       X Y Z, geocentric (Earth-centred, Earth-fixed) WGS84 coordinates\n"
          "                  in metres with 6 decimals; height 0 unless the line is LAT LON H\n"
          "  --precision P   MGRS digits per coordinate, 0..11 (default 5 = 1 m, 0 = the\n"
          "                  100 km square, 11 = 1 um); MGRS truncates, it does not round\n"
          "                  (GeoConvert -m -p P-5)\n"
          "  --geodesic      each line is LAT1 LON1 LAT2 LON2; prints AZI1 AZI2 S12: the\n"
          "                  azimuths at both ends (degrees clockwise from north, 12 decimals)\n"
          "                  and the length of the shortest path on the ellipsoid (metres, 9\n"
          "                  decimals), as GeodSolve -i -p 9\n"
          "  -h, --help      show this help\n"
          "\n"
          "examples:\n"
          "  $ terrapatch coord --to utm '45.5 -122.68'\n"
          "  10n 525000.574 5038546.300\n"
          "  $ terrapatch coord --to mgrs --precision 2 '33.3 44.4'\n"
          "  38SMB4484\n"
          "  $ printf '33n 500000 4649776.22\\n38SMB4484\\n91 0\\n' | terrapatch coord\n"
          "  41.999999957 15.000000000\n"
          "  33.298157366 44.403873473\n"
          "  ERROR: latitude 91 is outside [-90, 90]\n"
          "  (and on stderr: terrapatch coord: line 3: latitude 91 is outside [-90, 90])\n"
          "  $ terrapatch coord --to ecef '0 0 100'\n"
          "  6378237.000000 0.000000 0.000000\n"
          "  $ terrapatch coord --geodesic '40.6 -73.8 51.6 -0.5'\n"
          "  51.198882845580 107.821776735514 5551759.400318678\n"
          "  $ terrapatch coord '-33.9 18.4'        (an input may start with '-')\n"
          "\n"
          "Exit status: 0 every line converted, 1 some line failed or the input could not be\n"
          "read, 2 usage error.\n",
          stdout);
}

/* Returns -1 when the options are fine, else the exit code to return (help, usage error). */
static int parse_options(int argc, char** argv, coord_options* o)
{
    static const char* const to[] = {"geo", "utm", "mgrs", "ecef"}; /* tp_coord_to's order */
    *o = (coord_options){.req = {.to = TP_COORD_TO_GEO, .precision = -1}};
    const tp_option options[] = {
        TP_OPT_CODE("--to", NULL, OPT_TO, 1),
        TP_OPT_INTEGER("--precision", &o->req.precision, 0, 11, "an integer from 0 to 11"),
        TP_OPT_FLAG("--geodesic", &o->req.geodesic),
    };
    tp_options p;
    tp_options_init(&p, "coord", argc, argv, print_help);
    p.negative_operands = 1; /* an input such as "-33.9 18.4" */
    tp_options_add(&p, options, TP_OPTIONS_COUNT(options), NULL, NULL);
    for (int c; (c = tp_options_next(&p)) != TP_OPTIONS_END;) {
        if (c == TP_OPTIONS_EXIT)
            return p.exit;
        if (c == TP_OPTIONS_OPERAND) {
            tp_options_keep(&p, &o->inputs);
            continue;
        }
        int k = 0; /* --to */
        while (k < 4 && strcmp(p.value, to[k]))
            ++k;
        if (k == 4)
            return tp_options_bad_value(&p, "geo, utm, mgrs or ecef"), TP_EXIT_USAGE;
        o->req.to = (tp_coord_to)k;
        o->to_given = 1;
    }
    if (o->req.geodesic && o->to_given)
        return tp_cli_usage_at("coord", "--geodesic cannot be combined with --to", "");
    if (o->req.precision >= 0 && (o->req.geodesic || o->req.to != TP_COORD_TO_MGRS))
        return tp_cli_usage_at("coord", "--precision applies only to --to mgrs", "");
    if (o->req.precision < 0)
        o->req.precision = DEFAULT_MGRS_PRECISION;
    return -1;
}

/* Converts one input line (modified in place) and prints its output line, or its ERROR line
 * and the stderr message. Returns 1 if it converted. */
static int convert_line(const coord_options* o, char* line, size_t len, long line_no)
{
    char text[TP_COORD_TEXT_SIZE];
    tp_error err = {{0}};
    int ok = tp_coord_line_convert(&o->req, line, len, text, sizeof text, &err);
    if (ok) {
        printf("%s\n", text);
    } else {
        printf("ERROR: %s\n", err.message);
        tp_cli_error("line %ld: %s", line_no, err.message);
    }
    return ok;
}

int tp_cli_coord(int argc, char** argv)
{
    coord_options o;
    int code = parse_options(argc, argv, &o);
    if (code >= 0)
        return code;

    long failures = 0, line_no = 0;
    if (o.inputs) {
        for (int i = 1; i <= o.inputs; ++i)
            failures += !convert_line(&o, argv[i], strlen(argv[i]), ++line_no);
        return tp_cli_finish(failures ? TP_EXIT_FAILURE : TP_EXIT_OK);
    }

    char* line = NULL;
    size_t cap = 0;
    for (;;) {
        errno = 0; /* so that a read error reports its own errno, not an earlier ERANGE */
        ssize_t got = getline(&line, &cap, stdin);
        if (got < 0)
            break;
        size_t len = (size_t)got;
        if (len && line[len - 1] == '\n')
            line[--len] = '\0';
        failures += !convert_line(&o, line, len, ++line_no);
    }
    int read_error = ferror(stdin);
    int saved_errno = errno;
    free(line);
    if (read_error) {
        tp_cli_error("cannot read standard input after line %ld: %s", line_no,
                     strerror(saved_errno ? saved_errno : EIO));
        tp_cli_finish(TP_EXIT_FAILURE);
        return TP_EXIT_FAILURE;
    }
    return tp_cli_finish(failures ? TP_EXIT_FAILURE : TP_EXIT_OK);
}
