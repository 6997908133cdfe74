/*
 * coord_line.h - one input line of `terrapatch coord` converted to its output line
 * (app/base/coord_line.c). Split from cmd_coord.c, which reads the lines and prints the results, so
 * that the parser can be called without a process around it (tests/fuzz/fuzz_coord_line.c).
 */
#ifndef TP_APP_COORD_LINE_H
#define TP_APP_COORD_LINE_H

#include "tp_core.h"

#include <stddef.h>

/* What each line is converted to. */
typedef enum tp_coord_to {
    TP_COORD_TO_GEO = 0, /* LAT LON in degrees (the default) */
    TP_COORD_TO_UTM,     /* ZONE E N in the standard zone, as GeoConvert -u -p 3 */
    TP_COORD_TO_MGRS,    /* MGRS at tp_coord_request.precision digits */
    TP_COORD_TO_ECEF     /* X Y Z in metres */
} tp_coord_to;

typedef struct tp_coord_request {
    tp_coord_to to;
    int precision; /* MGRS digits per coordinate, 0..11 (5 is 1 m); only with TP_COORD_TO_MGRS */
    int geodesic;  /* 1: lines are LAT1 LON1 LAT2 LON2, answered as GeodSolve -i; `to` unused */
} tp_coord_request;

/* Bytes that always hold an output line, NUL included. */
#define TP_COORD_TEXT_SIZE 768

/* Converts one input line of len bytes (modified in place: split at white space; it may hold
 * any bytes, a NUL among them, which is an error). Returns 1 with the output line in out
 * (without a newline), or 0 with the reason in err ("latitude 91 is outside [-90, 90]"; out
 * untouched). out holds out_size bytes, at least TP_COORD_TEXT_SIZE. */
int tp_coord_line_convert(const tp_coord_request* req, char* line, size_t len, char* out,
                          size_t out_size, tp_error* err);

#endif /* TP_APP_COORD_LINE_H */
