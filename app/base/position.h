/*
 * position.h - a position as people type it on the command line, read in one place for every
 * command that takes one (`coord`, `point`, `los`, `viewshed`, `light`, `contours`, `profile`), and
 * written back as people read it (MGRS with spaces). app/base/position.c; its fuzz entry point is
 * tests/fuzz/fuzz_position.c. Every form a command prints reads back here.
 *
 * The text is split into fields at white space and commas (a comma is a space, as in
 * GeographicLib's GeoCoords, so "45.5,-122.68" and "45.5, -122.68" are LAT LON); a first field
 * "UTM" or "MGRS" (the label `point` prints) is passed over. Then, as GeoConvert reads them:
 *   MGRS  any precision, any letter case, one field (33TWN0000049776) or spaced as on maps
 *      (33T WN 00000 49776), read as the centre of its square; a grid zone designator alone
 *      (33T) is refused.
 *   LAT LON  decimal degrees, or degrees-minutes-seconds in any form GeographicLib's
 *      DMS::Decode reads (40d26'46"N 79d58'56"W, 40:26:46N 079:58:56W, N40.446 W79.982,
 *      40°26′46″ -79°58′56″); with hemisphere letters either order works, and degrees,
 *      minutes and seconds may be separate fields (55 28 41.88 N 2 08 44.16 W, N 55 28.698 W 2
 *      08.736: the letters end, or start, each coordinate). Latitude in [-90, 90], longitude in
 *      [-540, 540] (reduced to [-180, 180]).
 *   ZONE E N  metres, E N ZONE too (GeoConvert); each number may carry its label, attached or
 *      not, as `point` prints it (31n 387224.0 E 4705969.1 N, 554001mE 6148350mN). ZONE is
 *      UTM 1..60 or, for UPS, nothing (optionally after "UPS"), then
 *        - the hemisphere as GeographicLib writes it: n or s in lower case (as `coord --to utm`
 *          and `point` print them), north or south in any case (33n, 33south, UPS s, n);
 *        - or a latitude band as maps and GPS units write it: C..X without I and O (30U, 19J),
 *          A, B, Y, Z for UPS. The position must lie in that band (GeographicLib's MGRS check:
 *          the 100 km square's row must meet it). N reads as north either way. S after a zone
 *          number is band S (32..40 deg N) on a map but the southern hemisphere in
 *          GeographicLib's notation: when both readings are positions in range (33S 500000
 *          4000000: 36.1 N or 54.1 S) the text is ambiguous and refused, naming both (a command
 *          with a DEM takes the one on it: tp_position_parse_readings); when only one is, that
 *          one is read. Write 33north / 33south (or 33n / 33s) or MGRS to say which.
 *   LAT LON H  decimal degrees and an ellipsoidal height in metres: only where the caller
 *      allows heights.
 * Decimal numbers are read strictly (no "nan", "inf", hex or trailing text); everything else
 * that is not MGRS or a zone goes to GeographicLib, whose reason is kept in the message.
 */
#ifndef TP_APP_POSITION_H
#define TP_APP_POSITION_H

#include "tp_core.h"

#include <stddef.h>

typedef struct tp_position {
    double lat_deg, lon_deg; /* WGS84; lon in [-180, 180] */
    double h_m;              /* ellipsoidal height; 0 unless has_h */
    int has_h;               /* the input was LAT LON H */
    /* The input was ZONE E N or MGRS: its grid coordinates as given (zone 0 = UPS). Callers
     * that work in the same zone use these, not lat/lon, so that nothing moves by rounding. */
    int has_grid;
    int zone, northp;
    double easting_m, northing_m;
} tp_position;

/* Reads the len bytes of text (need not be NUL-terminated; a NUL among them is an error) as
 * one position. allow_height: 1 accepts LAT LON H, 0 refuses it. Returns 1 with *out, or 0
 * with the reason in err, e.g. "latitude 91 is outside [-90, 90]"; *out is written only on
 * success. */
int tp_position_parse(const char* text, size_t len, int allow_height, tp_position* out,
                      tp_error* err);

/* Every reading of a text: one, or two where a zone's S is band S or the southern hemisphere
 * and both are positions (see above). */
typedef struct tp_position_readings {
    int count;              /* 1 or 2 */
    tp_position reading[2]; /* with 2: [0] band S (north), [1] the zone's southern hemisphere */
} tp_position_readings;

/* tp_position_parse for a caller that can choose between two readings (a command with a DEM
 * takes the one on it). Returns 1 with *out, and with out->count 2 the refusal
 * tp_position_parse gives ("'33S' is ambiguous: band S (...) ... or zone 33 south (...) ...")
 * in err; 0 with err as tp_position_parse. */
int tp_position_parse_readings(const char* text, size_t len, int allow_height,
                               tp_position_readings* out, tp_error* err);

/* Names reading k of r (count 2) in a message: "band S (36.140541 15.000000)", "zone 33 south
 * (-54.148104 15.000000)". */
void tp_position_reading_text(const tp_position_readings* r, int k, char* out, size_t cap);

/* A decimal number and nothing else: [+-]digits[.digits][(e|E)[+-]digits], with at least one
 * digit before or after the point (strtod alone would also take "nan", "inf", hex and leading
 * blanks). Returns 1 and *v; 0 for text that is not such a number; -1 for a number too large
 * for a double. */
int tp_position_decimal(const char* s, double* v);

/* Joins argv[0 .. count-1] with spaces into buf (cap bytes) for tp_position_parse, so that
 * `point DEM 45.5 -122.68` and `point DEM "45.5 -122.68"` read alike. Returns 1 (buf may be
 * empty: tp_position_parse says so), or 0 when it does not fit (or count is 0). */
int tp_position_join(char* const* argv, int count, char* buf, size_t cap);

/* Bytes that always hold tp_position_mgrs_spaced's output ("60X AB 12345678901 12345678901"). */
#define TP_POSITION_MGRS_SPACED_SIZE 40

/* Writes an MGRS reference as printed on maps, with spaces between the grid zone designator,
 * the 100 km square letters and the easting and northing digits: "31TCH7665100831" ->
 * "31T CH 76651 00831", "ZAA0000033272" -> "Z AA 00000 33272". A reference without digits
 * keeps its letters ("31T CH"). Returns 0 (out untouched) when mgrs does not have that shape or
 * out (cap bytes) is too small. */
int tp_position_mgrs_spaced(const char* mgrs, char* out, size_t cap);

/* When text is two decimal numbers that do not read as a position but do the other way round
 * ("139.7 35.6": longitude first), writes them swapped ("35.6 139.7") into out (cap bytes) and
 * returns 1; else 0. */
int tp_position_swapped(const char* text, char* out, size_t cap);

#endif /* TP_APP_POSITION_H */
