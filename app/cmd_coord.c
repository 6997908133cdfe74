/*
 * cmd_coord.c - `terrapatch coord [options] [INPUT ...]`: a batch coordinate converter in the
 * manner of GeographicLib's GeoConvert (and GeodSolve -i with --geodesic).
 *
 * One input per line, from the arguments or standard input; one output line per input line,
 * "ERROR: reason" in place of a line that fails, so that output stays aligned with input.
 * Lines are parsed here, strictly (whole-token numbers, nothing left over); every conversion
 * is GeographicLib's, through io/include/tp_geo.h.
 */
#define _POSIX_C_SOURCE 200809L /* getline */

#include "cli.h"

#include "tp_core.h"
#include "tp_geo.h"

#include <ctype.h>
#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef enum coord_output {
    OUT_GEO = 0, /* default */
    OUT_UTM,
    OUT_MGRS,
    OUT_ECEF
} coord_output;

typedef struct coord_options {
    coord_output to;
    int to_given;
    int precision; /* MGRS digits per coordinate */
    int precision_given;
    int geodesic;
    int first_input; /* argv index of the first INPUT; == argc: read stdin */
} coord_options;

enum { OPT_TO = 256, OPT_PRECISION, OPT_GEODESIC };

#define DEFAULT_MGRS_PRECISION 5
#define MAX_FIELDS 4   /* most fields a line may have (--geodesic); more are only counted */
#define MSG_SIZE 768   /* one error message */
#define QUOTE_LIMIT 40 /* characters of a bad token echoed back */

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
          "input, one position per line, latitude first:\n"
          "  LAT LON        decimal degrees, LAT in [-90, 90], LON in [-540, 540]\n"
          "                 (e.g. 45.5 -122.68; no DMS, no N/S/E/W letters)\n"
          "  LAT LON H      the same plus H, the ELLIPSOIDAL height in metres (above the WGS84\n"
          "                 ellipsoid, not above sea level or the geoid); only with --to ecef\n"
          "  ZONE E N       UTM: zone 1..60 and hemisphere n or s (33n 500000 4649776.22);\n"
          "                 UPS: n or s alone (n 2000000 1333272.296); easting, northing in m\n"
          "  MGRS           an MGRS reference of any precision, any letter case\n"
          "                 (33TWN0000049776, 38smb4488), read as the centre of its square\n"
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
          "  $ terrapatch coord -- '-33.9 18.4'     ('--' before inputs starting with '-')\n"
          "\n"
          "Exit status: 0 every line converted, 1 some line failed or the input could not be\n"
          "read, 2 usage error.\n",
          stdout);
}

/* One stderr line naming the problem; `detail` (an argument) is quoted when not empty. */
static int usage_error(const char* what, const char* detail)
{
    if (detail[0])
        fprintf(stderr, "terrapatch coord: %s '%s' (see 'terrapatch coord --help')\n", what,
                detail);
    else
        fprintf(stderr, "terrapatch coord: %s (see 'terrapatch coord --help')\n", what);
    return TP_EXIT_USAGE;
}

/* Returns -1 when the options are fine, else the exit code to return (help, usage error). */
static int parse_options(int argc, char** argv, coord_options* o)
{
    static const struct option longs[] = {
        {"to", required_argument, NULL, OPT_TO},
        {"precision", required_argument, NULL, OPT_PRECISION},
        {"geodesic", no_argument, NULL, OPT_GEODESIC},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    *o = (coord_options){.to = OUT_GEO, .precision = DEFAULT_MGRS_PRECISION};
    opterr = 0; /* getopt's own messages would make a second stderr line */
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":h", longs, NULL)) != -1) {
        switch (c) {
        case OPT_TO:
            if (!strcmp(optarg, "geo")) {
                o->to = OUT_GEO;
            } else if (!strcmp(optarg, "utm")) {
                o->to = OUT_UTM;
            } else if (!strcmp(optarg, "mgrs")) {
                o->to = OUT_MGRS;
            } else if (!strcmp(optarg, "ecef")) {
                o->to = OUT_ECEF;
            } else {
                fprintf(stderr,
                        "terrapatch coord: --to: expected geo, utm, mgrs or ecef, got '%s'\n",
                        optarg);
                return TP_EXIT_USAGE;
            }
            o->to_given = 1;
            break;
        case OPT_PRECISION: {
            char* end;
            errno = 0;
            long v = strtol(optarg, &end, 10);
            if (*optarg == '\0' || *end != '\0' || errno || v < 0 || v > 11) {
                fprintf(stderr,
                        "terrapatch coord: --precision: expected an integer from 0 to 11, "
                        "got '%s'\n",
                        optarg);
                return TP_EXIT_USAGE;
            }
            o->precision = (int)v;
            o->precision_given = 1;
            break;
        }
        case OPT_GEODESIC: o->geodesic = 1; break;
        case 'h': print_help(); return tp_cli_finish(TP_EXIT_OK);
        case ':': return usage_error("missing value for option", argv[optind - 1]);
        default: /* '?' */
            if (isdigit(optopt) || optopt == '.') {
                /* an input such as "-33.9 18.4" read as options */
                fprintf(stderr,
                        "terrapatch coord: unknown option '-%c' (put '--' before inputs that "
                        "start with '-': terrapatch coord -- '-33.9 18.4')\n",
                        (char)optopt);
                return TP_EXIT_USAGE;
            }
            if (optopt > 0 && optopt < 256) {
                char name[3] = {'-', (char)optopt, '\0'};
                return usage_error("unknown option", name);
            }
            if (optopt >= 256) /* a long option given a value it does not take */
                return usage_error("option takes no value:", argv[optind - 1]);
            return usage_error("unknown option", argv[optind - 1]);
        }
    }
    if (o->geodesic && o->to_given)
        return usage_error("--geodesic cannot be combined with --to", "");
    if (o->precision_given && (o->geodesic || o->to != OUT_MGRS))
        return usage_error("--precision applies only to --to mgrs", "");
    o->first_input = optind;
    return -1;
}

/* ---------------------------------------------------------------------------------------------
 * Parsing one line
 */

typedef struct fields {
    int count; /* all fields on the line */
    char* field[MAX_FIELDS];
} fields;

/* Splits line in place at white space. */
static fields split_fields(char* line)
{
    fields f = {0};
    char* p = line;
    for (;;) {
        while (*p && isspace((unsigned char)*p))
            ++p;
        if (!*p)
            break;
        if (f.count < MAX_FIELDS)
            f.field[f.count] = p;
        ++f.count;
        while (*p && !isspace((unsigned char)*p))
            ++p;
        if (*p)
            *p++ = '\0';
    }
    return f;
}

/* 'token' for a message: at most QUOTE_LIMIT characters, unprintable bytes as '?'. */
static const char* quoted(const char* token, char* buf, size_t cap)
{
    size_t n = 0, len = strlen(token);
    size_t keep = len > QUOTE_LIMIT ? QUOTE_LIMIT : len;
    if (cap < QUOTE_LIMIT + 8) {
        buf[0] = '\0';
        return buf;
    }
    buf[n++] = '\'';
    for (size_t i = 0; i < keep; ++i)
        buf[n++] = isprint((unsigned char)token[i]) ? token[i] : '?';
    if (keep < len) {
        memcpy(buf + n, "...", 3);
        n += 3;
    }
    buf[n++] = '\'';
    buf[n] = '\0';
    return buf;
}

/* A decimal number and nothing else: [+-]digits[.digits][(e|E)[+-]digits], with at least
 * one digit before or after the point. strtod alone would also take "nan", "inf", hex and
 * leading blanks. Returns 1 and *v on success; 0 for text that is not such a number; -1 for
 * a number too large for a double. */
static int parse_number(const char* s, double* v)
{
    const char* p = s;
    int digits = 0;
    if (*p == '+' || *p == '-')
        ++p;
    while (isdigit((unsigned char)*p))
        ++p, ++digits;
    if (*p == '.') {
        ++p;
        while (isdigit((unsigned char)*p))
            ++p, ++digits;
    }
    if (!digits)
        return 0;
    if (*p == 'e' || *p == 'E') {
        ++p;
        if (*p == '+' || *p == '-')
            ++p;
        if (!isdigit((unsigned char)*p))
            return 0;
        while (isdigit((unsigned char)*p))
            ++p;
    }
    if (*p)
        return 0;
    char* end;
    double x = strtod(s, &end);
    if (end != p)
        return 0;
    if (!isfinite(x))
        return -1;
    *v = x;
    return 1;
}

/* Reads field `token` as the number called `name`; on failure writes msg. */
static int read_number(const char* token, const char* name, double* v, char* msg)
{
    char q[QUOTE_LIMIT + 8];
    int r = parse_number(token, v);
    if (r == 1)
        return 1;
    if (r < 0)
        snprintf(msg, MSG_SIZE, "%s %s is too large", name, quoted(token, q, sizeof q));
    else
        snprintf(msg, MSG_SIZE, "%s: expected a decimal number, got %s", name,
                 quoted(token, q, sizeof q));
    return 0;
}

/* A UTM zone with hemisphere ("33n", "3S", "01n") or a UPS hemisphere ("n", "s").
 * Returns 1 with *zone (0 = UPS) and *northp; 0 if token has not that shape; -1 (msg set) if
 * it has the shape but the zone is outside 1..60. */
static int parse_zone(const char* token, int* zone, int* northp, char* msg)
{
    size_t len = strlen(token), ndigits = 0;
    while (ndigits < len && isdigit((unsigned char)token[ndigits]))
        ++ndigits;
    if (len != ndigits + 1 || ndigits > 2)
        return 0;
    char h = (char)tolower((unsigned char)token[ndigits]);
    if (h != 'n' && h != 's')
        return 0;
    int z = 0;
    for (size_t i = 0; i < ndigits; ++i)
        z = 10 * z + (token[i] - '0');
    if (ndigits && (z < 1 || z > 60)) {
        snprintf(msg, MSG_SIZE, "UTM zone %d is outside [1, 60]", z);
        return -1;
    }
    *zone = ndigits ? z : TP_ZONE_UPS;
    *northp = h == 'n';
    return 1;
}

/* MGRS by shape: up to 2 digits (the zone; none for UPS), a letter, then letters and digits
 * only. Whether it is a legal reference is GeographicLib's to say (tp_mgrs_reverse). */
static int looks_like_mgrs(const char* token)
{
    size_t i = 0;
    while (i < 2 && isdigit((unsigned char)token[i]))
        ++i;
    if (!isalpha((unsigned char)token[i]))
        return 0;
    for (; token[i]; ++i)
        if (!isalnum((unsigned char)token[i]))
            return 0;
    return 1;
}

/* A position as read from one line: geographic always (once converted), and the grid
 * coordinates as given when the line was UTM/UPS or MGRS. */
typedef struct position {
    double lat_deg, lon_deg; /* lon in [-180, 180] */
    double h_m;              /* ellipsoidal height; 0 unless given */
    int has_h;
    int has_grid; /* zone, northp, easting_m, northing_m hold the input's grid coordinates */
    int zone, northp;
    double easting_m, northing_m;
} position;

/* Copies a tp_error message into msg (tp_status_str when the message is empty). */
static int geo_failed(tp_status s, const tp_error* err, char* msg)
{
    snprintf(msg, MSG_SIZE, "%s", err->message[0] ? err->message : tp_status_str(s));
    return 0;
}

/* From UTM/UPS grid coordinates (as given) to a position. */
static int position_from_grid(int zone, int northp, double e, double n, position* pos, char* msg)
{
    tp_error err = {{0}};
    double lat, lon;
    tp_status s = tp_geo_from_utmups(zone, northp, e, n, &lat, &lon, &err);
    if (s != TP_OK)
        return geo_failed(s, &err, msg);
    *pos = (position){.lat_deg = lat,
                      .lon_deg = lon,
                      .has_grid = 1,
                      .zone = zone,
                      .northp = northp,
                      .easting_m = e,
                      .northing_m = n};
    return 1;
}

static int position_from_geo(double lat, double lon, position* pos, char* msg)
{
    tp_error err = {{0}};
    double lat_n, lon_n;
    tp_status s = tp_geo_normalize(lat, lon, &lat_n, &lon_n, &err);
    if (s != TP_OK)
        return geo_failed(s, &err, msg);
    *pos = (position){.lat_deg = lat_n, .lon_deg = lon_n};
    return 1;
}

static int position_from_mgrs(const char* token, position* pos, char* msg)
{
    tp_error err = {{0}};
    int zone, northp, precision;
    double e, n;
    tp_status s = tp_mgrs_reverse(token, 1, &zone, &northp, &e, &n, &precision, &err);
    if (s != TP_OK)
        return geo_failed(s, &err, msg);
    if (precision < 0) {
        /* GeographicLib returns "some suitable (but essentially arbitrary) point" of the zone */
        char q[QUOTE_LIMIT + 8];
        snprintf(msg, MSG_SIZE,
                 "MGRS %s is a grid zone designator, not a position: add the 100 km square "
                 "letters and digits (e.g. 33TWN0000049776)",
                 quoted(token, q, sizeof q));
        return 0;
    }
    return position_from_grid(zone, northp, e, n, pos, msg);
}

/* Reads one input line (not --geodesic) into pos. Returns 1, or 0 with msg set. */
static int parse_position(const fields* f, position* pos, char* msg)
{
    char* const* field = f->field;
    char q[QUOTE_LIMIT + 8];
    double a, b, c;
    int zone, northp;
    switch (f->count) {
    case 0:
        snprintf(msg, MSG_SIZE,
                 "expected LAT LON, ZONE E N or an MGRS reference, got an empty line");
        return 0;
    case 1:
        if (looks_like_mgrs(field[0]))
            return position_from_mgrs(field[0], pos, msg);
        if (parse_number(field[0], &a) == 1)
            snprintf(msg, MSG_SIZE, "expected LAT LON, got a single number %s",
                     quoted(field[0], q, sizeof q));
        else
            snprintf(msg, MSG_SIZE, "expected LAT LON, ZONE E N or an MGRS reference, got %s",
                     quoted(field[0], q, sizeof q));
        return 0;
    case 2:
        if (!read_number(field[0], "latitude", &a, msg) ||
            !read_number(field[1], "longitude", &b, msg))
            return 0;
        return position_from_geo(a, b, pos, msg);
    case 3:
        if (parse_number(field[0], &a) == 1) { /* LAT LON H */
            if (!read_number(field[1], "longitude", &b, msg) ||
                !read_number(field[2], "height", &c, msg) || !position_from_geo(a, b, pos, msg))
                return 0;
            pos->h_m = c;
            pos->has_h = 1;
            return 1;
        }
        switch (parse_zone(field[0], &zone, &northp, msg)) {
        case 1: break;
        case 0:
            snprintf(msg, MSG_SIZE,
                     "expected LAT LON H or ZONE E N, but %s is neither a number nor a zone "
                     "(1n..60n, 1s..60s, or n or s for UPS)",
                     quoted(field[0], q, sizeof q));
            return 0;
        default: return 0;
        }
        if (!read_number(field[1], "easting", &a, msg) ||
            !read_number(field[2], "northing", &b, msg))
            return 0;
        return position_from_grid(zone, northp, a, b, pos, msg);
    default:
        snprintf(msg, MSG_SIZE,
                 "expected LAT LON, LAT LON H, ZONE E N or an MGRS reference, got %d fields",
                 f->count);
        return 0;
    }
}

/* ---------------------------------------------------------------------------------------------
 * Converting and printing
 */

/* -0.0 prints as "-0.000"; a computed exact zero should not. */
static double unsigned_zero(double v)
{
    return v + 0.0;
}

/* The standard UTM/UPS zone of pos and its coordinates there. Grid input already in that zone
 * keeps its own easting and northing, exactly as given, and on the equator its own hemisphere
 * (as GeoConvert does; see tp_utmups_to_standard). */
static int standard_grid(const position* pos, int* zone, int* northp, double* e, double* n,
                         char* msg)
{
    tp_error err = {{0}};
    tp_status s = pos->has_grid ? tp_utmups_to_standard(pos->zone, pos->northp, pos->easting_m,
                                                        pos->northing_m, zone, northp, e, n, &err)
                                : tp_geo_to_utmups(pos->lat_deg, pos->lon_deg, zone, northp, e, n,
                                                   &err);
    return s == TP_OK ? 1 : geo_failed(s, &err, msg);
}

/* Converts one parsed position and prints the output line. Returns 1, or 0 with msg set
 * (then nothing is printed). */
static int convert_position(const coord_options* o, const position* pos, char* msg)
{
    tp_error err = {{0}};
    tp_status s;
    int zone, northp;
    double e, n;
    if (pos->has_h && o->to != OUT_ECEF) {
        snprintf(msg, MSG_SIZE, "a height (LAT LON H) is only used with --to ecef");
        return 0;
    }
    switch (o->to) {
    case OUT_GEO:
        printf("%.9f %.9f\n", unsigned_zero(pos->lat_deg), unsigned_zero(pos->lon_deg));
        return 1;
    case OUT_UTM: {
        if (!standard_grid(pos, &zone, &northp, &e, &n, msg))
            return 0;
        char zone_name[TP_ZONE_TEXT_SIZE];
        s = tp_zone_format(zone, northp, TP_ZONE_STYLE_GEOCONVERT, zone_name, sizeof zone_name,
                           &err);
        if (s != TP_OK)
            return geo_failed(s, &err, msg);
        printf("%s %.3f %.3f\n", zone_name, unsigned_zero(e), unsigned_zero(n));
        return 1;
    }
    case OUT_MGRS: {
        char mgrs[TP_MGRS_SIZE];
        if (!standard_grid(pos, &zone, &northp, &e, &n, msg))
            return 0;
        s = tp_mgrs_forward(zone, northp, e, n, pos->lat_deg, o->precision, mgrs, sizeof mgrs,
                            &err);
        if (s != TP_OK)
            return geo_failed(s, &err, msg);
        printf("%s\n", mgrs);
        return 1;
    }
    case OUT_ECEF: {
        double x, y, z;
        s = tp_geo_to_ecef(pos->lat_deg, pos->lon_deg, pos->h_m, &x, &y, &z, &err);
        if (s != TP_OK)
            return geo_failed(s, &err, msg);
        printf("%.6f %.6f %.6f\n", unsigned_zero(x), unsigned_zero(y), unsigned_zero(z));
        return 1;
    }
    }
    snprintf(msg, MSG_SIZE, "unknown output kind %d", (int)o->to);
    return 0;
}

static int convert_geodesic(const fields* f, char* msg)
{
    char* const* field = f->field;
    static const char* const names[4] = {"lat1", "lon1", "lat2", "lon2"};
    double v[4];
    if (f->count != 4) {
        snprintf(msg, MSG_SIZE, "expected LAT1 LON1 LAT2 LON2 (4 numbers), got %d field%s",
                 f->count, f->count == 1 ? "" : "s");
        return 0;
    }
    for (int i = 0; i < 4; ++i)
        if (!read_number(field[i], names[i], &v[i], msg))
            return 0;
    tp_error err = {{0}};
    double azi1, azi2, s12;
    tp_status s = tp_geodesic_inverse(v[0], v[1], v[2], v[3], &azi1, &azi2, &s12, &err);
    if (s != TP_OK)
        return geo_failed(s, &err, msg);
    printf("%.12f %.12f %.9f\n", unsigned_zero(azi1), unsigned_zero(azi2), unsigned_zero(s12));
    return 1;
}

/* Converts one input line (modified in place) and prints its output line, or its ERROR line
 * and the stderr message. Returns 1 if it converted. */
static int convert_line(const coord_options* o, char* line, size_t len, long line_no)
{
    char msg[MSG_SIZE];
    int ok;
    if (strlen(line) != len) {
        snprintf(msg, MSG_SIZE, "the line contains a NUL byte");
        ok = 0;
    } else {
        fields f = split_fields(line);
        if (o->geodesic) {
            ok = convert_geodesic(&f, msg);
        } else {
            position pos;
            ok = parse_position(&f, &pos, msg) && convert_position(o, &pos, msg);
        }
    }
    if (!ok) {
        printf("ERROR: %s\n", msg);
        fprintf(stderr, "terrapatch coord: line %ld: %s\n", line_no, msg);
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
    if (o.first_input < argc) {
        for (int i = o.first_input; i < argc; ++i)
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
        fprintf(stderr, "terrapatch coord: cannot read standard input after line %ld: %s\n",
                line_no, strerror(saved_errno ? saved_errno : EIO));
        tp_cli_finish(TP_EXIT_FAILURE);
        return TP_EXIT_FAILURE;
    }
    return tp_cli_finish(failures ? TP_EXIT_FAILURE : TP_EXIT_OK);
}
