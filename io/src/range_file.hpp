/* range_file.hpp - a file read by byte ranges, local or over HTTP: what the readers of
 * terrapatch's own files (store_read.cpp, imagery_read.cpp) read through. A local file is read
 * with pread on one descriptor; an http:// or https:// URL through GDAL's virtual file system
 * (/vsicurl/: range requests, retries, its block cache, connections kept alive), one handle a
 * reading thread at a time from a small pool, so that several threads have requests in flight
 * at once. Private to io/; docs/distribution.md says why GDAL and not libcurl's multi interface.
 *
 * A file replaced on the server is never mixed with the one opened: open records its size, ETag
 * and Last-Modified (one HEAD request), every range request carries If-Match (or
 * If-Unmodified-Since) with them, so the server answers 412 instead of the new file's bytes, and
 * any failed read asks the server again (a fresh HEAD): when the file changed, that read and
 * every later one fail with "URL: the file changed on the server since it was opened (...)". */
#pragma once

#include "tp_core.h"

#include <atomic>
#include <cstdint>
#include <memory>
#include <string>

namespace tpio {

/* true for an http:// or https:// URL (the scheme in any case). */
bool is_url(const char* path);

class RangeFile {
public:
    RangeFile();
    ~RangeFile();
    RangeFile(const RangeFile&) = delete;
    RangeFile& operator=(const RangeFile&) = delete;

    /* Opens path, a local regular file (refused as check_input_file refuses: `what` names what
     * it should have been) or an http(s) URL (its size asked of the server: "URL: cannot open:
     * HTTP 404" and the like; with pin, also its ETag and Last-Modified, which every later
     * request then carries: a HEAD request more). TP_ERR_IO with a message starting with path. */
    tp_status open(const char* path, const char* what, tp_error* err, bool pin = true);
    uint64_t size() const { return size_; }
    bool remote() const { return remote_; }
    int fd() const { return fd_; } /* local files only; -1 for a URL */

    /* All of size bytes at offset into buf, or false with the reason in why (no path in it):
     * strerror's text, "the file ended early (was it changed?)", the HTTP failure, or, for a URL
     * replaced on the server since open, "the file changed on the server since it was opened
     * (...): open it again" (changed() true from then on, and every later read fails so). Any
     * number of threads may read at once. */
    bool read(void* buf, size_t size, uint64_t offset, std::string* why) const;
    /* For a URL whose bytes failed a check (a CRC32): true, with why as read's, when the file on
     * the server is no longer the one opened; false (why untouched) otherwise and for local
     * files. */
    bool check_changed(std::string* why) const;
    bool changed() const { return changed_.load(); }

private:
    struct Remote;
    /* A large read of a URL: one request of exactly its range (range_file.cpp) */
    bool fetch(void* buf, size_t size, uint64_t offset, std::string* why) const;
    int fd_ = -1;
    bool remote_ = false;
    uint64_t size_ = 0;
    std::unique_ptr<Remote> r_;
    mutable std::atomic<bool> changed_{false};
};

} // namespace tpio
