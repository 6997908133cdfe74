/*
 * position_int.h - what the readers of positions share among themselves (position.c,
 * position_grid.c, position_dms.c, coord_line.c), as SQLite keeps whereInt.h beside where.c:
 * tp__ names, not for commands (they include position.h).
 */
#ifndef TP_APP_POSITION_INT_H
#define TP_APP_POSITION_INT_H

#include "position.h"

#include "tp_core.h"

#include <stddef.h>

#define TP__POSITION_MAX_FIELDS 8 /* fields kept (spaced DMS: N 55 28 41.88 W 2 08 44.16) */

typedef struct tp__fields {
    int count; /* all fields of the text; only the first TP__POSITION_MAX_FIELDS are kept */
    char* field[TP__POSITION_MAX_FIELDS];
} tp__fields;

/* Splits line in place at white space, and at commas too where commas. */
tp__fields tp__position_split(char* line, int commas);

/* Reads token as the number called name (tp_position_decimal). 1 with *v; else 0 with err:
 * "NAME: expected a decimal number, got 'TOKEN'" or "NAME 'TOKEN' is too large" (the token cut
 * to 40 characters, unprintable bytes as '?'). */
int tp__position_read_number(const char* token, const char* name, double* v, tp_error* err);

/* After a call that failed with s and wrote err: tp_status_str(s) into err when the call left
 * its message empty; returns 0. */
int tp__position_failed(tp_status s, tp_error* err);

#define MAX_FIELDS TP__POSITION_MAX_FIELDS
#define QUOTE_LIMIT 40 /* characters of a bad token echoed back */

typedef tp__fields fields;

/* 'token' for a message (buf: QUOTE_LIMIT + 8 bytes): at most QUOTE_LIMIT characters,
 * unprintable bytes as '?', in quotes. */
const char* tp__position_quoted(const char* token, char* buf);

/* a and b equal but for the case of ASCII letters */
int tp__position_same_word(const char* a, const char* b);

/* lat, lon (degrees) as *pos; 0 with err when they are out of range. */
int tp__position_from_geo(double lat, double lon, tp_position* pos, tp_error* err);

/* position_grid.c: MGRS by shape (digits, a letter, then letters and digits only); the
 * reference token read (1 with *pos, else 0 with err naming the forms that are read); ZONE E N
 * in position.h's forms (1 with *out; 0 when f has not that shape; -1 with err); MGRS written
 * with spaces joined into out (1 when f is one). */
int tp__position_looks_like_mgrs(const char* token);
int tp__position_from_mgrs(const char* token, tp_position* pos, tp_error* err);
int tp__position_parse_grid(const fields* f, tp_position_readings* out, tp_error* err);
int tp__position_join_spaced_mgrs(const fields* f, char* out, size_t cap);

/* position_dms.c: LAT LON in degrees, minutes and seconds separated by spaces: 1 with *pos; 0
 * when f has not that shape; -1 with err (GeographicLib's reason). */
int tp__position_parse_spaced_dms(const fields* f, tp_position* pos, tp_error* err);

#endif /* TP_APP_POSITION_INT_H */
