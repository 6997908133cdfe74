/* range_file.cpp - a file read by byte ranges, local (pread) or over HTTP (GDAL's /vsicurl/);
 * see range_file.hpp. */
#include "range_file.hpp"

#include "format_read.hpp"
#include "gdal_util.hpp"
#include "io_util.hpp"

#include <cpl_conv.h>
#include <cpl_http.h>
#include <cpl_vsi.h>

#include <fcntl.h>
#include <strings.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <condition_variable>
#include <mutex>
#include <utility>
#include <vector>

namespace tpio {

bool is_url(const char* path)
{
    return path && (!strncasecmp(path, "http://", 7) || !strncasecmp(path, "https://", 8));
}

namespace {

/* GDAL's HTTP options for the calls of one scope on this thread (thread-local configuration
 * options, restored at the end): the precondition that keeps a replaced file out, and defaults
 * for retries and timeouts where neither the environment nor the caller set them (GDAL's own
 * defaults retry nothing and wait forever on a server that stalls). */
class HttpScope {
public:
    explicit HttpScope(const std::string& precondition)
    {
        if (!precondition.empty() && !CPLGetConfigOption("GDAL_HTTP_HEADERS", nullptr))
            set("GDAL_HTTP_HEADERS", precondition.c_str());
        static const char* const defaults[][2] = {
            {"GDAL_HTTP_MAX_RETRY", "3"},        {"GDAL_HTTP_RETRY_DELAY", "0.5"},
            {"GDAL_HTTP_CONNECTTIMEOUT", "10"},  {"GDAL_HTTP_LOW_SPEED_TIME", "10"},
            {"GDAL_HTTP_LOW_SPEED_LIMIT", "1"},
        };
        for (const auto& d : defaults)
            if (!CPLGetConfigOption(d[0], nullptr))
                set(d[0], d[1]);
        set("CPL_DEBUG", "ON"); /* the reason of a failure (note_handler) */
    }
    ~HttpScope()
    {
        for (auto& s : saved_)
            CPLSetThreadLocalConfigOption(s.first, s.second.set ? s.second.value.c_str() : nullptr);
    }
    HttpScope(const HttpScope&) = delete;
    HttpScope& operator=(const HttpScope&) = delete;

private:
    struct Saved {
        bool set;
        std::string value;
    };
    void set(const char* key, const char* value)
    {
        const char* was = CPLGetThreadLocalConfigOption(key, nullptr);
        saved_.emplace_back(key, Saved{was != nullptr, was ? was : ""});
        CPLSetThreadLocalConfigOption(key, value);
    }
    std::vector<std::pair<const char*, Saved>> saved_;
};

/* "Name: value" as one item of GDAL_HTTP_HEADERS, which splits at commas and takes a double
 * quote for the start of a quoted item: a value holding either (an ETag is quoted) is quoted,
 * its quotes and backslashes escaped. */
std::string gdal_header(const char* name, const std::string& value)
{
    if (value.find_first_of(",\"\\") == std::string::npos)
        return std::string(name) + ": " + value;
    std::string q = std::string("\"") + name + ": ";
    for (char c : value) {
        if (c == '"' || c == '\\')
            q += '\\';
        q += c;
    }
    return q + '"';
}

/* What GDAL said of this thread's last failed request: its debug lines (CPL_DEBUG, on in an
 * HttpScope) are where /vsicurl/ names the HTTP status or libcurl's error; nothing is printed. */
thread_local std::string t_http_note;

void CPL_STDCALL note_handler(CPLErr cls, CPLErrorNum, const char* msg)
{
    if (!msg)
        return;
    if (cls != CE_Debug) {
        t_http_note = msg;
        return;
    }
    if (std::strncmp(msg, "VSICURL", 7) != 0)
        return;
    if (const char* m = std::strstr(msg, "msg="))
        t_http_note = m + 4;
    else if (const char* c = std::strstr(msg, "Got response_code="))
        if (std::atoi(c + 18) >= 300) /* 0: no answer, 206: cut short; msg= said why */
            t_http_note = "HTTP " + std::string(c + 18);
}

/* GDAL's messages of a scope caught by note_handler, none printed. */
struct NoteScope {
    NoteScope()
    {
        t_http_note.clear();
        CPLPushErrorHandler(note_handler);
        CPLErrorReset();
    }
    ~NoteScope() { CPLPopErrorHandler(); }
    NoteScope(const NoteScope&) = delete;
    NoteScope& operator=(const NoteScope&) = delete;
};

/* What names one version of a file on a server. */
struct Identity {
    bool ok = false;
    uint64_t size = 0;
    std::string etag, last_modified;
    std::string describe() const
    {
        std::string d = std::to_string(size) + " bytes";
        if (!etag.empty())
            d += ", ETag " + etag;
        if (!last_modified.empty())
            d += ", Last-Modified " + last_modified;
        return d;
    }
};

/* The file's identity from a HEAD request (GDAL's HEADERS metadata, asked afresh). */
Identity ask_identity(const std::string& vsi)
{
    Identity id;
    HttpScope http("");
    NoteScope quiet;
    char** md = VSIGetFileMetadata(vsi.c_str(), "HEADERS", nullptr);
    for (char** m = md; m && *m; ++m) {
        const char* eq = std::strchr(*m, '=');
        if (!eq)
            continue;
        const std::string key(*m, (size_t)(eq - *m));
        if (!strcasecmp(key.c_str(), "ETag"))
            id.etag = eq + 1;
        else if (!strcasecmp(key.c_str(), "Last-Modified"))
            id.last_modified = eq + 1;
        else if (!strcasecmp(key.c_str(), "Content-Length")) {
            id.size = std::strtoull(eq + 1, nullptr, 10);
            id.ok = true;
        }
    }
    CSLDestroy(md);
    return id;
}

/* Reads of this many bytes or more (a store's tables) are one request of exactly their range
 * (CPLHTTPFetch), not /vsicurl/'s blocks: its cache caps one request at 16 MB and reads ahead
 * as much again after it (a 17.5 MB table cost 32.8 MB in two requests). */
constexpr size_t LARGE_READ_BYTES = 1 << 20;

} // namespace

struct RangeFile::Remote {
    std::string url, vsi;
    std::string precondition;     /* "If-Match: ETAG" (or If-Unmodified-Since), as sent */
    std::string gdal_precondition; /* the same as one item of GDAL_HTTP_HEADERS */
    Identity opened;
    std::mutex mu;
    std::vector<VSILFILE*> idle; /* handles no thread reads through now */
    /* /vsicurl/'s blocks being fetched by some thread, [first, last] each (under mu): a read
     * that needs one of them waits for it and then finds it in the block cache, rather than
     * asking the server for the same block at the same time (two loaders reading neighbouring
     * nodes of one block did, for 27% of the requests) */
    std::vector<std::pair<uint64_t, uint64_t>> fetching;
    std::condition_variable fetched;
    uint64_t block = 16384; /* CPL_VSIL_CURL_CHUNK_SIZE */
    std::string changed_why;     /* under mu, once changed_ */
    ~Remote()
    {
        for (VSILFILE* f : idle)
            VSIFCloseL(f);
    }
};

RangeFile::RangeFile() = default;

RangeFile::~RangeFile()
{
    if (fd_ >= 0)
        close(fd_);
}

tp_status RangeFile::open(const char* path, const char* what, tp_error* err, bool pin)
{
    if (!is_url(path)) {
        if (tp_status st = check_input_file(path, what, false, err))
            return st;
        fd_ = ::open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
        struct stat sb;
        if (fd_ < 0 || fstat(fd_, &sb) != 0)
            return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, std::strerror(errno));
        if (!S_ISREG(sb.st_mode)) /* replaced since check_input_file looked */
            return fail(err, TP_ERR_IO, "%s: cannot open: not a regular file", path);
        size_ = (uint64_t)sb.st_size;
        return TP_OK;
    }
    remote_ = true;
    r_.reset(new Remote);
    r_->url = path;
    r_->vsi = std::string("/vsicurl/") + path;
    VSIStatBufL sb;
    {
        HttpScope http("");
        NoteScope quiet;
        if (VSIStatExL(r_->vsi.c_str(), &sb, VSI_STAT_SIZE_FLAG) != 0) {
            const std::string why = t_http_note;
            return fail(err, TP_ERR_IO, "%s: cannot open: %s", path,
                        why.empty() ? "no such file on the server (or the server cannot be "
                                      "reached)"
                                    : why.c_str());
        }
    }
    size_ = (uint64_t)sb.st_size;
    if (const char* chunk = CPLGetConfigOption("CPL_VSIL_CURL_CHUNK_SIZE", nullptr))
        r_->block = std::max<uint64_t>(std::strtoull(chunk, nullptr, 10), 1);
    if (!pin)
        return TP_OK;
    r_->opened = ask_identity(r_->vsi);
    if (r_->opened.ok && r_->opened.size != size_) /* replaced between the two requests */
        return fail(err, TP_ERR_IO, "%s: cannot open: the file changed on the server while it "
                    "was being opened: try again", path);
    if (!r_->opened.etag.empty()) {
        r_->precondition = "If-Match: " + r_->opened.etag;
        r_->gdal_precondition = gdal_header("If-Match", r_->opened.etag);
    } else if (!r_->opened.last_modified.empty()) {
        r_->precondition = "If-Unmodified-Since: " + r_->opened.last_modified;
        r_->gdal_precondition = gdal_header("If-Unmodified-Since", r_->opened.last_modified);
    }
    return TP_OK;
}

bool RangeFile::check_changed(std::string* why) const
{
    if (!remote_ || !r_->opened.ok) /* not pinned, or the server names no version */
        return false;
    if (!changed_.load()) {
        const Identity now = ask_identity(r_->vsi);
        const Identity& was = r_->opened;
        if (!now.ok || (now.size == size_ && now.etag == was.etag &&
                        now.last_modified == was.last_modified))
            return false;
        std::lock_guard<std::mutex> lock(r_->mu);
        if (!changed_.load()) {
            r_->changed_why = "the file changed on the server since it was opened (" +
                              was.describe() + ", now " + now.describe() + "): open it again";
            changed_.store(true);
        }
    }
    std::lock_guard<std::mutex> lock(r_->mu);
    *why = r_->changed_why;
    return true;
}

bool RangeFile::read(void* buf, size_t size, uint64_t offset, std::string* why) const
{
    if (!remote_) {
        const int e = read_at(fd_, buf, size, offset);
        if (e)
            *why = e == EIO ? "the file ended early (was it changed?)" : std::strerror(e);
        return e == 0;
    }
    if (changed_.load()) {
        std::lock_guard<std::mutex> lock(r_->mu);
        *why = r_->changed_why;
        return false;
    }
    if (size >= LARGE_READ_BYTES)
        return fetch(buf, size, offset, why);
    VSILFILE* f = nullptr;
    const std::pair<uint64_t, uint64_t> blocks(offset / r_->block, (offset + size - 1) / r_->block);
    {
        std::unique_lock<std::mutex> lock(r_->mu);
        auto overlaps = [&] {
            for (const auto& b : r_->fetching)
                if (b.first <= blocks.second && blocks.first <= b.second)
                    return true;
            return false;
        };
        r_->fetched.wait(lock, [&] { return !overlaps(); });
        r_->fetching.push_back(blocks);
        if (!r_->idle.empty()) {
            f = r_->idle.back();
            r_->idle.pop_back();
        }
    }
    struct Done { /* the blocks are no longer being fetched, whatever happens */
        RangeFile::Remote* r;
        std::pair<uint64_t, uint64_t> b;
        ~Done()
        {
            std::lock_guard<std::mutex> lock(r->mu);
            r->fetching.erase(std::find(r->fetching.begin(), r->fetching.end(), b));
            r->fetched.notify_all();
        }
    } done{r_.get(), blocks};
    size_t got = 0;
    std::string gdal;
    {
        HttpScope http(r_->gdal_precondition);
        NoteScope quiet;
        if (!f)
            f = VSIFOpenL(r_->vsi.c_str(), "rb");
        if (f && VSIFSeekL(f, offset, SEEK_SET) == 0)
            got = VSIFReadL(buf, 1, size, f);
        gdal = t_http_note;
    }
    if (got == size) {
        std::lock_guard<std::mutex> lock(r_->mu);
        r_->idle.push_back(f);
        return true;
    }
    if (f)
        VSIFCloseL(f); /* its state after a failure is not to be trusted */
    if (check_changed(why))
        return false;
    *why = "the server sent " + std::to_string(got) + " of the " + std::to_string(size) +
           " bytes asked for" + (gdal.empty() ? "" : " (" + gdal + ")");
    return false;
}

bool RangeFile::fetch(void* buf, size_t size, uint64_t offset, std::string* why) const
{
    std::string headers = "HEADERS=Range: bytes=" + std::to_string(offset) + "-" +
                          std::to_string(offset + size - 1);
    if (!r_->precondition.empty())
        headers += "\r\n" + r_->precondition;
    const char* options[] = {headers.c_str(), nullptr};
    std::string problem;
    {
        HttpScope http("");
        NoteScope quiet;
        CPLHTTPResult* res = CPLHTTPFetch(r_->url.c_str(), const_cast<char**>(options));
        if (!res)
            problem = "no answer";
        else if (res->nStatus != 0 || res->pszErrBuf)
            problem = res->pszErrBuf ? res->pszErrBuf : "libcurl error " + std::to_string(res->nStatus);
        else if ((size_t)res->nDataLen != size)
            problem = "the server sent " + std::to_string(res->nDataLen) + " of the " +
                      std::to_string(size) + " bytes asked for (does it answer range requests?)";
        else
            std::memcpy(buf, res->pabyData, size);
        CPLHTTPDestroyResult(res);
    }
    if (problem.empty())
        return true;
    if (!check_changed(why))
        *why = problem;
    return false;
}

} // namespace tpio
