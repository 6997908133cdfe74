/*
 * input_file.cpp - tp_input_check, tp_input_is_virtual, tp_input_identify (tp_io.h): the one
 * place that decides whether a path may be read, for every input of every command (DEMs, routes,
 * overlays, bookmarks), GDAL's virtual paths included.
 */
#include "tp_io.h"

#include "gdal_util.hpp"
#include "range_file.hpp"

#include <cpl_vsi.h>

#include <climits>
#include <cstdlib>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

using tpio::fail;

namespace {

/* The handlers whose path after the prefix is an archive on the local disk. */
const char* const ARCHIVE_PREFIXES[] = {"/vsizip/", "/vsigzip/", "/vsitar/", "/vsi7z/", "/vsirar/"};

/* The archive handler prefix path starts with, or nullptr. */
const char* archive_prefix(const char* path)
{
    for (const char* p : ARCHIVE_PREFIXES)
        if (std::strncmp(path, p, std::strlen(p)) == 0)
            return p;
    return nullptr;
}

std::string current_dir()
{
    char buf[PATH_MAX];
    return getcwd(buf, sizeof buf) ? std::string(buf) : std::string(".");
}

/* The archive on the local disk that an archive handler's path reads (/vsizip/DIR/a.zip/x.tif:
 * DIR/a.zip, made absolute), with its stat; "" when there is none to find (a chained handler,
 * GDAL's {...} form, a missing file). */
std::string archive_of(const char* path, struct stat* st)
{
    const char* prefix = archive_prefix(path);
    if (!prefix)
        return "";
    std::string rest = path + std::strlen(prefix);
    if (rest.empty() || rest[0] == '{' || rest.compare(0, 4, "/vsi") == 0)
        return "";
    if (rest[0] != '/')
        rest = current_dir() + "/" + rest;
    /* the first component that is not a folder is the archive */
    for (size_t at = rest.find('/', 1);; at = rest.find('/', at + 1)) {
        const std::string part = rest.substr(0, at);
        if (stat(part.c_str(), st) != 0)
            return "";
        if (!S_ISDIR(st->st_mode))
            return part;
        if (at == std::string::npos)
            return "";
    }
}

} // namespace

extern "C" int tp_input_is_virtual(const char* path)
{
    if (!path || std::strncmp(path, "/vsi", 4) != 0)
        return 0;
    const char* slash = std::strchr(path + 4, '/');
    return slash && slash > path + 4;
}

extern "C" int tp_input_is_url(const char* path)
{
    return tpio::is_url(path);
}

extern "C" tp_status tp_input_url_head(const char* url, unsigned char* head, size_t n,
                                       tp_error* err)
{
    try {
        tpio::RangeFile f;
        if (tp_status st = f.open(url, "a file", err, false))
            return st;
        std::string why;
        if (f.size() < n)
            return fail(err, TP_ERR_IO, "%s: only %llu bytes on the server", url,
                        (unsigned long long)f.size());
        if (!f.read(head, n, 0, &why))
            return fail(err, TP_ERR_IO, "%s: cannot read: %s", url, why.c_str());
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, url);
    }
}

extern "C" tp_status tp_input_check(const char* path, const char* what, int allow_directory,
                                    tp_error* err)
{
    if (!path || !*path)
        return fail(err, TP_ERR_IO, "(empty path): cannot open: expected %s file",
                    what ? what : "a");
    if (!tp_input_is_virtual(path))
        return tpio::check_input_file(path, what, allow_directory != 0, err);
    /* the archive itself is a local file: a FIFO there would block GDAL as one here would */
    struct stat ast;
    const std::string archive = archive_of(path, &ast);
    if (!archive.empty())
        if (tp_status s = tpio::check_input_file(archive.c_str(), "an archive", false, err))
            return s;
    VSIStatBufL sb;
    tpio::QuietGdal quiet;
    if (VSIStatExL(path, &sb, VSI_STAT_EXISTS_FLAG | VSI_STAT_NATURE_FLAG) != 0)
        return fail(err, TP_ERR_IO,
                    "%s: cannot open: no such file (a GDAL virtual path: check the archive's "
                    "path and the name inside it)",
                    path);
    if (VSI_ISDIR(sb.st_mode) && !allow_directory)
        return fail(err, TP_ERR_IO,
                    "%s: cannot open: it is a folder inside the archive, expected "
                    "%s file",
                    path, what);
    return TP_OK;
}

extern "C" tp_status tp_input_identify(const char* path, char* abs_path, size_t cap,
                                       tp_input_identity* out, tp_error* err)
{
    std::string abs;
    if (!tp_input_is_virtual(path)) {
        char buf[PATH_MAX];
        struct stat st;
        if (!realpath(path, buf) || stat(buf, &st) != 0)
            return fail(err, TP_ERR_IO, "%s: %s", path, std::strerror(errno));
        abs = buf;
        out->size_bytes = (int64_t)st.st_size;
        out->mtime_ns = (int64_t)st.st_mtim.tv_sec * 1000000000 + st.st_mtim.tv_nsec;
    } else {
        abs = path;
        if (const char* prefix = archive_prefix(path)) {
            const char* rest = path + std::strlen(prefix);
            /* a relative archive path, not a chained handler or GDAL's {...} form */
            if (*rest && *rest != '/' && *rest != '{')
                abs = std::string(prefix) + current_dir() + "/" + rest;
        }
        VSIStatBufL sb;
        tpio::QuietGdal quiet;
        if (VSIStatL(abs.c_str(), &sb) != 0)
            return fail(err, TP_ERR_IO, "%s: cannot open: no such file (a GDAL virtual path)",
                        path);
        out->size_bytes = (int64_t)sb.st_size;
        out->mtime_ns = (int64_t)sb.st_mtime * 1000000000;
        /* a member's time has 2 s steps (zip) and may be set back: the archive's own size and
         * time say when it changed */
        struct stat ast;
        if (!archive_of(path, &ast).empty()) {
            out->size_bytes ^= (int64_t)ast.st_size << 20;
            out->mtime_ns = (int64_t)ast.st_mtim.tv_sec * 1000000000 + ast.st_mtim.tv_nsec;
        }
    }
    if (abs.size() + 1 > cap)
        return fail(err, TP_ERR_INVALID_ARG, "%s: the absolute path is too long (%zu bytes)", path,
                    abs.size());
    std::memcpy(abs_path, abs.c_str(), abs.size() + 1);
    return TP_OK;
}
