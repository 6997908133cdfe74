/*
 * json.h - a small streaming JSON writer for the command line's --json output.
 *
 * Values are written in order; the writer inserts commas, newlines and indentation. Objects put
 * one key per line; arrays stay on one line. Strings are escaped per RFC 8259 and bytes that are
 * not valid UTF-8 become U+FFFD, so the output always parses. Numbers are written with %.17g
 * (exact round trip); NaN and infinities become null. The outermost object or array ends
 * with a newline.
 */
#ifndef TP_APP_JSON_H
#define TP_APP_JSON_H

#include <stdio.h>

#define TP_JSON_MAX_DEPTH 16

typedef struct tp_json {
    FILE* f;
    int depth;
    int count[TP_JSON_MAX_DEPTH]; /* values written so far at each depth */
    char kind[TP_JSON_MAX_DEPTH]; /* '{' or '[' */
    int after_key;                /* a key was written, its value comes next */
} tp_json;

void tp_json_init(tp_json* j, FILE* f);
void tp_json_object_begin(tp_json* j);
void tp_json_object_end(tp_json* j);
void tp_json_array_begin(tp_json* j);
void tp_json_array_end(tp_json* j);
void tp_json_key(tp_json* j, const char* key);
void tp_json_string(tp_json* j, const char* s); /* NULL writes null */
void tp_json_number(tp_json* j, double v);
void tp_json_int(tp_json* j, long long v);
void tp_json_size(tp_json* j, size_t v);
void tp_json_bool(tp_json* j, int v);
void tp_json_null(tp_json* j);

/* A key and its value in one call: "key": value. */
void tp_json_member_string(tp_json* j, const char* key, const char* s); /* NULL writes null */
void tp_json_member_number(tp_json* j, const char* key, double v);
void tp_json_member_int(tp_json* j, const char* key, long long v);
void tp_json_member_size(tp_json* j, const char* key, size_t v);
void tp_json_member_bool(tp_json* j, const char* key, int v);

#endif /* TP_APP_JSON_H */
