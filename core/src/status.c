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

tp_status tp_error_set(tp_error* err, tp_status s, const char* fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
    }
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
