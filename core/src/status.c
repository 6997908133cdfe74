/* status.c - status names and error messages. */
#include "internal.h"

#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

const char* tp_status_str(tp_status s)
{
    switch (s) {
    case TP_OK: return "ok";
    case TP_ERR_INVALID_ARG: return "invalid argument";
    case TP_ERR_BAD_DATA: return "bad data";
    case TP_ERR_IO: return "input/output error";
    case TP_ERR_OUT_OF_MEMORY: return "out of memory";
    case TP_ERR_BACKEND: return "backend library error";
    }
    return "unknown status";
}

/* Keeps the first `head` bytes of text (len bytes) and its end, "..." between, in cap bytes. */
static void shorten_middle(char* dst, size_t cap, const char* text, size_t len)
{
    static const char dots[] = "...";
    size_t room = cap - 1 - (sizeof dots - 1);
    size_t head = room / 3, tail = room - head;
    while (head > 0 && ((unsigned char)text[head] & 0xC0) == 0x80)
        head--; /* do not split a UTF-8 character */
    size_t from = len - tail;
    while (from < len && ((unsigned char)text[from] & 0xC0) == 0x80)
        from++;
    memcpy(dst, text, head);
    memcpy(dst + head, dots, sizeof dots - 1);
    memcpy(dst + head + sizeof dots - 1, text + from, len - from);
    dst[head + sizeof dots - 1 + (len - from)] = '\0';
}

tp_status tp_error_setv(tp_error* err, tp_status s, const char* fmt, va_list ap)
{
    if (!err)
        return s;
    va_list again;
    va_copy(again, ap);
    int n = vsnprintf(err->message, sizeof err->message, fmt, ap);
    if (n >= (int)sizeof err->message) {
        /* Too long: format whole on the heap, then cut the middle (usually the path). */
        char* full = malloc((size_t)n + 1);
        if (full) {
            vsnprintf(full, (size_t)n + 1, fmt, again);
            shorten_middle(err->message, sizeof err->message, full, (size_t)n);
            free(full);
        }
    } else if (n < 0) {
        snprintf(err->message, sizeof err->message, "(message could not be formatted)");
    }
    va_end(again);
    return s;
}

tp_status tp_error_set(tp_error* err, tp_status s, const char* fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    tp_error_setv(err, s, fmt, ap);
    va_end(ap);
    return s;
}

void* tp__alloc(const tp_allocator* a, size_t count, size_t size)
{
    if (size && count > SIZE_MAX / size)
        return NULL;
    size_t bytes = count * size != 0 ? count * size : 1;
    return a->alloc ? a->alloc(bytes, a->user_data) : malloc(bytes);
}

void* tp__calloc(const tp_allocator* a, size_t count, size_t size)
{
    void* p = tp__alloc(a, count, size);
    if (p)
        memset(p, 0, count * size);
    return p;
}

void tp__free(const tp_allocator* a, void* p)
{
    if (!p)
        return;
    if (a->free)
        a->free(p, a->user_data);
    else
        free(p);
}
