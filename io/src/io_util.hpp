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

#include <cerrno>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

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

/* Refuses an input path that is not a regular file before any library opens it: opening a FIFO
 * (named pipe) blocks until something writes to it, forever if nothing does, and a character
 * device such as /dev/zero never ends. A directory is refused too unless allow_directory (a
 * GDAL raster can be one: an ArcInfo binary grid). GDAL virtual paths (/vsizip/, /vsicurl/,
 * ...) are left to GDAL. `what` says what the file should have been ("a raster", "an image").
 * TP_ERR_IO with a message starting with the path; TP_OK otherwise. */
inline tp_status check_input_file(const char* path, const char* what, bool allow_directory,
                                  tp_error* err)
{
    if (std::strncmp(path, "/vsi", 4) == 0)
        return TP_OK;
    struct stat st;
    if (stat(path, &st) != 0)
        return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, std::strerror(errno));
    if (S_ISREG(st.st_mode) || (allow_directory && S_ISDIR(st.st_mode)))
        return TP_OK;
    const char* kind = S_ISFIFO(st.st_mode) ? "a FIFO (named pipe)"
                       : S_ISCHR(st.st_mode)  ? "a character device"
                       : S_ISBLK(st.st_mode)  ? "a block device"
                       : S_ISSOCK(st.st_mode) ? "a socket"
                                              : "a special file";
    if (S_ISDIR(st.st_mode))
        return fail(err, TP_ERR_IO, "%s: cannot open: %s, expected %s file", path,
                    std::strerror(EISDIR), what);
    return fail(err, TP_ERR_IO,
                "%s: cannot open: it is %s, not a regular file (reading it could block or never end); "
                "expected %s file",
                path, kind, what);
}

/* Refuses a raster of w x h samples needing bytes_per_sample bytes each when that would not fit
 * in this machine's memory, before anything is allocated (a header is all it takes to claim
 * 10^12 samples): TP_ERR_OUT_OF_MEMORY with a message naming the path, the size and `what`
 * ("for the heights (4 bytes each)"). Defined in dem_read.cpp. */
tp_status check_fits_in_memory(const char* path, int w, int h, double bytes_per_sample,
                               const char* what, tp_error* err);

/* Points stderr at /dev/null for a scope. libpng prints "libpng error: ..." itself before
 * OpenImageIO's handler gets the message (OpenImageIO's error callback returns, and libpng then
 * calls its default handler, which prints), and other codecs print too; OpenImageIO hands the
 * same text to geterror(), which goes into our one-line message. Only while decoding an input,
 * on the loading thread, before any window exists (a sanitizer report in that window would
 * be lost too; the exit status still says something went wrong). */
struct QuietStderr {
    int saved = -1;
    QuietStderr()
    {
        std::fflush(stderr);
        const int null_fd = open("/dev/null", O_WRONLY | O_CLOEXEC);
        if (null_fd < 0)
            return;
        saved = dup(2);
        if (saved >= 0 && dup2(null_fd, 2) < 0) {
            close(saved);
            saved = -1;
        }
        close(null_fd);
    }
    ~QuietStderr()
    {
        if (saved < 0)
            return;
        std::fflush(stderr);
        dup2(saved, 2);
        close(saved);
    }
    QuietStderr(const QuietStderr&) = delete;
    QuietStderr& operator=(const QuietStderr&) = delete;
};

/* A PNG's chunks walked before a decoder sees them: TP_ERR_BAD_DATA when one is cut short or
 * fails its CRC, or when the header claims more pixels than the compressed data can hold
 * (deflate expands at most 1032:1); TP_OK for anything else, PNG or not (the decoder decides).
 * Reads the file once, allocating nothing of the image's size. Defined in image_read.cpp. */
tp_status check_png(const char* path, tp_error* err);

/* malloc'd copy, so C code can free() it. */
inline char* dup_c(const std::string& s)
{
    char* p = static_cast<char*>(std::malloc(s.size() + 1));
    if (p)
        std::memcpy(p, s.c_str(), s.size() + 1);
    return p;
}

} // namespace tpio
