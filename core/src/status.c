/* status.c - status names and error messages. */
#include "internal.h"

#include <stdarg.h>
#include <stdio.h>

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

tp_status tp__fail(tp_error* err, tp_status s, const char* fmt, ...)
{
    if (err) {
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(err->message, sizeof err->message, fmt, ap);
        va_end(ap);
    }
    return s;
}
