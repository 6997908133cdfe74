/* io_util.hpp - small C++ helpers shared by every io/ file. Private to io/. */
#pragma once

#include "tp_core.h"

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <exception>
#include <new>
#include <string>

namespace tpio {

/* Writes a one-line message into err (if any): library messages may hold newlines. */
inline void vset_error(tp_error* err, const char* fmt, va_list ap)
{
    if (!err)
        return;
    tp_error_setv(err, TP_OK, fmt, ap); /* a long message loses its middle, not its reason */
    for (char* c = err->message; *c; ++c)
        if (*c == '\n' || *c == '\r')
            *c = ' ';
}

inline void set_error(tp_error* err, const char* fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vset_error(err, fmt, ap);
    va_end(ap);
}

/* set_error, returning s. */
inline tp_status fail(tp_error* err, tp_status s, const char* fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vset_error(err, fmt, ap);
    va_end(ap);
    return s;
}

/* Call inside a catch (...) handler: sorts the exception in flight into a status and a message
 * starting with `what` (the file or the function): std::bad_alloc -> TP_ERR_OUT_OF_MEMORY, any
 * other exception -> TP_ERR_BACKEND with its what(). So no exception reaches C code. */
inline tp_status caught(tp_error* err, const char* what)
{
    try {
        throw;
    } catch (const std::bad_alloc&) {
        return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory", what);
    } catch (const std::exception& e) {
        return fail(err, TP_ERR_BACKEND, "%s: %s", what, e.what());
    } catch (...) {
        return fail(err, TP_ERR_BACKEND, "%s: unknown C++ exception", what);
    }
}

/* malloc'd copy, so C code can free() it. */
inline char* dup_c(const std::string& s)
{
    char* p = static_cast<char*>(std::malloc(s.size() + 1));
    if (p)
        std::memcpy(p, s.c_str(), s.size() + 1);
    return p;
}

} // namespace tpio
