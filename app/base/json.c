/*
 * json.c - see json.h.
 */
#include "json.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>

void tp_json_init(tp_json* j, FILE* f)
{
    assert(j && f);
    j->f = f;
    j->depth = 0;
    j->count[0] = 0;
    j->kind[0] = 0;
    j->after_key = 0;
}

static void indent(tp_json* j)
{
    fputc('\n', j->f);
    for (int i = 0; i < j->depth; ++i)
        fputs("  ", j->f);
}

/* Separator before a value (or a key): commas between siblings, a new line per object key. */
static void before_value(tp_json* j)
{
    if (j->after_key) {
        j->after_key = 0;
        return;
    }
    if (j->depth > 0) {
        if (j->count[j->depth]++ > 0)
            fputs(j->kind[j->depth] == '[' ? ", " : ",", j->f);
        if (j->kind[j->depth] == '{')
            indent(j);
    }
}

static void begin(tp_json* j, char kind)
{
    before_value(j);
    assert(j->depth + 1 < TP_JSON_MAX_DEPTH);
    fputc(kind, j->f);
    ++j->depth;
    j->count[j->depth] = 0;
    j->kind[j->depth] = kind;
}

static void end(tp_json* j, char kind)
{
    assert(j->depth > 0 && j->kind[j->depth] == kind && !j->after_key);
    int empty = j->count[j->depth] == 0;
    --j->depth;
    if (kind == '{' && !empty)
        indent(j);
    fputc(kind == '{' ? '}' : ']', j->f);
    if (j->depth == 0)
        fputc('\n', j->f);
}

void tp_json_object_begin(tp_json* j)
{
    begin(j, '{');
}
void tp_json_object_end(tp_json* j)
{
    end(j, '{');
}
void tp_json_array_begin(tp_json* j)
{
    begin(j, '[');
}
void tp_json_array_end(tp_json* j)
{
    end(j, '[');
}

/* Length of the valid UTF-8 sequence at s (1 to 4), or 0 if it is not valid (overlong forms,
 * surrogates and code points above U+10FFFF included). */
static int utf8_length(const unsigned char* s)
{
    unsigned c = s[0];
    int n;
    uint32_t cp;
    if (c < 0x80)
        return 1;
    if (c >= 0xc2 && c <= 0xdf) {
        n = 2;
        cp = c & 0x1f;
    } else if (c >= 0xe0 && c <= 0xef) {
        n = 3;
        cp = c & 0x0f;
    } else if (c >= 0xf0 && c <= 0xf4) {
        n = 4;
        cp = c & 0x07;
    } else {
        return 0;
    }
    for (int i = 1; i < n; ++i) {
        if ((s[i] & 0xc0) != 0x80) /* also stops at the terminating NUL */
            return 0;
        cp = (cp << 6) | (s[i] & 0x3f);
    }
    if ((n == 3 && cp < 0x800) || (n == 4 && cp < 0x10000) || cp > 0x10ffff ||
        (cp >= 0xd800 && cp <= 0xdfff))
        return 0;
    return n;
}

static void write_string(FILE* f, const char* str)
{
    const unsigned char* s = (const unsigned char*)str;
    fputc('"', f);
    while (*s) {
        unsigned c = *s;
        int n = utf8_length(s);
        if (n == 0) {
            fputs("\\ufffd", f);
            ++s;
            continue;
        }
        if (n > 1) {
            fwrite(s, 1, (size_t)n, f);
            s += n;
            continue;
        }
        switch (c) {
        case '"': fputs("\\\"", f); break;
        case '\\': fputs("\\\\", f); break;
        case '\b': fputs("\\b", f); break;
        case '\f': fputs("\\f", f); break;
        case '\n': fputs("\\n", f); break;
        case '\r': fputs("\\r", f); break;
        case '\t': fputs("\\t", f); break;
        default:
            if (c < 0x20)
                fprintf(f, "\\u%04x", c);
            else
                fputc((int)c, f);
        }
        ++s;
    }
    fputc('"', f);
}

void tp_json_key(tp_json* j, const char* key)
{
    assert(j->depth > 0 && j->kind[j->depth] == '{' && !j->after_key);
    before_value(j);
    write_string(j->f, key);
    fputs(": ", j->f);
    j->after_key = 1;
}

void tp_json_string(tp_json* j, const char* s)
{
    if (!s) {
        tp_json_null(j);
        return;
    }
    before_value(j);
    write_string(j->f, s);
}

void tp_json_number(tp_json* j, double v)
{
    if (!isfinite(v)) {
        tp_json_null(j);
        return;
    }
    before_value(j);
    /* %.17g of a finite double is always valid JSON: "30", "0.10000000000000001", "1e+20". */
    fprintf(j->f, "%.17g", v);
}

void tp_json_int(tp_json* j, long long v)
{
    before_value(j);
    fprintf(j->f, "%lld", v);
}

void tp_json_size(tp_json* j, size_t v)
{
    before_value(j);
    fprintf(j->f, "%zu", v);
}

void tp_json_bool(tp_json* j, int v)
{
    before_value(j);
    fputs(v ? "true" : "false", j->f);
}

void tp_json_null(tp_json* j)
{
    before_value(j);
    fputs("null", j->f);
}

void tp_json_member_string(tp_json* j, const char* key, const char* s)
{
    tp_json_key(j, key);
    tp_json_string(j, s);
}

void tp_json_member_number(tp_json* j, const char* key, double v)
{
    tp_json_key(j, key);
    tp_json_number(j, v);
}

void tp_json_member_int(tp_json* j, const char* key, long long v)
{
    tp_json_key(j, key);
    tp_json_int(j, v);
}

void tp_json_member_size(tp_json* j, const char* key, size_t v)
{
    tp_json_key(j, key);
    tp_json_size(j, v);
}

void tp_json_member_bool(tp_json* j, const char* key, int v)
{
    tp_json_key(j, key);
    tp_json_bool(j, v);
}
