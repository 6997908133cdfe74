/* atomic_write.cpp - the one way terrapatch writes a file (see tp_io.h, "Files written whole or
 * not at all"): a new temporary file of an unpredictable name beside the target, opened with
 * O_CREAT | O_EXCL | O_NOFOLLOW (so it is ours: never a file or a symlink someone else put
 * there), every write() checked, then fsync, close, rename over the target and fsync of the
 * folder. Any failure, or SIGINT/SIGTERM, removes the temporary file and leaves the target as
 * it was.
 *
 * Interruption. The handler only records the signal, and only while a temporary file or folder
 * is live (tp_interrupt_hold); otherwise it restores the default action and re-raises, so the
 * program dies at once as it would without a handler (nothing of ours is on disk then). The
 * writers look at the flag between chunks of at most CHUNK bytes and before the rename.
 */
#include "atomic_write.hpp"
#include "io_util.hpp"
#include "tp_io.h"

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <ctime>
#include <fcntl.h>
#include <string>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

using tpio::fail;

/* ---------------------------------------------------------------------------------------------
 * Interruption
 */
namespace {
volatile std::sig_atomic_t g_signal = 0; /* the signal caught while held, or 0 */
/* live temporaries and holds: any thread changes it (the store cache builds a store on one while
 * the viewer draws on another); lock-free, so the handler may read it */
std::atomic<int> g_holds{0};
static_assert(std::atomic<int>::is_always_lock_free, "the signal handler reads g_holds");

extern "C" void on_signal(int sig)
{
    const int saved = errno;
    g_signal = sig;
    if (g_holds == 0) { /* nothing of ours to remove: die as without a handler */
        std::signal(sig, SIG_DFL);
        std::raise(sig);
    }
    errno = saved;
}
} // namespace

extern "C" void tp_interrupt_install(void)
{
    const int sigs[] = {SIGINT, SIGTERM};
    for (int sig : sigs) {
        struct sigaction old;
        if (sigaction(sig, nullptr, &old) == 0 && old.sa_handler == SIG_IGN)
            continue; /* started with it ignored (nohup, a background job): keep it so */
        struct sigaction sa;
        std::memset(&sa, 0, sizeof sa);
        sa.sa_handler = on_signal;
        sigemptyset(&sa.sa_mask);
        sa.sa_flags = SA_RESTART;
        sigaction(sig, &sa, nullptr);
    }
}

extern "C" int tp_interrupted(void) { return (int)g_signal; }

extern "C" void tp_interrupt_hold(void) { g_holds.fetch_add(1); }

extern "C" void tp_interrupt_release(void)
{
    int n = g_holds.load();
    while (n > 0 && !g_holds.compare_exchange_weak(n, n - 1))
        ;
}

extern "C" void tp_interrupt_finished(void)
{
    /* ignored first: from here no handler runs, so the flag stays cleared */
    const int sigs[] = {SIGINT, SIGTERM};
    for (int sig : sigs) {
        struct sigaction sa;
        std::memset(&sa, 0, sizeof sa);
        sa.sa_handler = SIG_IGN;
        sigemptyset(&sa.sa_mask);
        sigaction(sig, &sa, nullptr);
    }
    g_signal = 0;
}

/* ---------------------------------------------------------------------------------------------
 * Shared with the other writers (atomic_write.hpp)
 */
namespace tpio {

const char* interrupt_name(void)
{
    return g_signal == SIGINT ? "SIGINT" : g_signal == SIGTERM ? "SIGTERM" : "a signal";
}

std::string dir_of(const std::string& path)
{
    size_t slash = path.find_last_of('/');
    return slash == std::string::npos ? std::string(".")
           : slash == 0               ? std::string("/")
                                      : path.substr(0, slash);
}

/* path + ".tmp" + 8 random letters and digits: not guessable by someone who would plant a
 * symlink there (getrandom; the clock and a counter if the kernel has none to give). */
std::string temp_name(const std::string& path)
{
    static const char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
    static std::atomic<unsigned> counter{0};
    unsigned char r[8];
    if (getrandom(r, sizeof r, GRND_NONBLOCK) != (ssize_t)sizeof r) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        unsigned long long x = (unsigned long long)ts.tv_nsec * 6364136223846793005ull ^
                               (unsigned long long)ts.tv_sec ^ ((unsigned long long)getpid() << 32) ^
                               counter++ * 1442695040888963407ull;
        for (unsigned char& c : r) {
            x = x * 6364136223846793005ull + 1442695040888963407ull;
            c = (unsigned char)(x >> 56);
        }
    }
    std::string name = path + ".tmp";
    for (unsigned char c : r)
        name += digits[c % (sizeof digits - 1)];
    return name;
}

int create_new(const std::string& name)
{
    int fd = open(name.c_str(), O_RDWR | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666);
    return fd >= 0 ? fd : -errno;
}

int write_fd(int fd, const void* data, size_t size)
{
    const char* p = static_cast<const char*>(data);
    size_t done = 0;
    while (done < size) {
        if (g_signal)
            return EINTR;
        ssize_t n = write(fd, p + done, std::min(size - done, CHUNK));
        if (n > 0)
            done += (size_t)n;
        else if (n < 0 && errno != EINTR)
            return errno; /* ENOSPC, EFBIG (a file size limit, SIGXFSZ ignored), EDQUOT, EIO */
        else if (n == 0)
            return EIO;
    }
    return 0;
}

int finish_fd(int fd, uintmax_t expected_size)
{
    int e = 0;
    struct stat st;
    if (fstat(fd, &st) != 0)
        e = errno;
    else if ((uintmax_t)st.st_size != expected_size)
        e = EIO; /* the file is not what was written */
    /* Delayed allocation: a full disk, a quota or NFS may only say so here. */
    if (!e && fsync(fd) != 0)
        e = errno;
    if (close(fd) != 0 && !e)
        e = errno;
    return e;
}

int write_new_file(const std::string& name, const void* data, size_t size)
{
    int fd = create_new(name);
    if (fd < 0)
        return -fd;
    int e = write_fd(fd, data, size);
    if (e)
        close(fd);
    else
        e = finish_fd(fd, size);
    if (e)
        unlink(name.c_str());
    return e;
}

int make_temp_dir(const std::string& path, std::string* out)
{
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string name = temp_name(path);
        if (mkdir(name.c_str(), 0700) == 0) {
            *out = name;
            return 0;
        }
        if (errno != EEXIST)
            return errno;
    }
    return EEXIST;
}

void sync_dir(const std::string& dir)
{
    int fd = open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (fd >= 0) {
        (void)fsync(fd);
        close(fd);
    }
}

tp_status write_failed(tp_error* err, const std::string& path, int e)
{
    if (e == EINTR)
        return fail(err, TP_ERR_IO, "%s: interrupted (%s): not written", path.c_str(),
                    interrupt_name());
    return fail(err, TP_ERR_IO, "%s: cannot write: %s", path.c_str(), std::strerror(e));
}

} // namespace tpio

/* ---------------------------------------------------------------------------------------------
 * tp_file_*
 */
struct tp_file_writer {
    std::string path, tmp;
    int fd = -1;
    int error = 0; /* errno of the first failure (EINTR: interrupted); the temporary is gone */
    uintmax_t size = 0;
};

namespace {
/* Removes the temporary file (once) and records e. */
void drop(tp_file_writer* w, int e)
{
    if (w->fd >= 0) {
        close(w->fd);
        w->fd = -1;
        unlink(w->tmp.c_str());
    }
    if (!w->error)
        w->error = e;
}

/* After a pwrite or pread of the bytes from *done returned n: moves *done on, or drops w (a
 * failure other than EINTR; 0 bytes: EIO). */
void advance(tp_file_writer* w, ssize_t n, size_t* done)
{
    if (n > 0)
        *done += (size_t)n;
    else if (n < 0 && errno != EINTR)
        drop(w, errno);
    else if (n == 0)
        drop(w, EIO);
}

void destroy(tp_file_writer* w)
{
    drop(w, 0);
    delete w;
    tp_interrupt_release();
}
} // namespace

extern "C" tp_status tp_file_begin(const char* path, tp_file_writer** out, tp_error* err)
{
    if (!path || !*path || !out)
        return fail(err, TP_ERR_INVALID_ARG, "file: bad arguments (path or out is NULL)");
    if (path[std::strlen(path) - 1] == '/')
        return fail(err, TP_ERR_INVALID_ARG, "%s: a file name is needed, not a folder", path);
    tp_interrupt_hold(); /* before the file exists: a signal now only sets the flag */
    tp_file_writer* w = nullptr; /* owns the hold once it exists (destroy releases it) */
    try {
        w = new (std::nothrow) tp_file_writer;
        if (!w) {
            tp_interrupt_release();
            return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory", path);
        }
        w->path = path;
        int fd = -EEXIST;
        for (int attempt = 0; attempt < 100 && fd == -EEXIST; ++attempt) {
            w->tmp = tpio::temp_name(w->path);
            fd = tpio::create_new(w->tmp);
        }
        if (fd < 0 || g_signal) {
            const std::string p = w->path; /* may throw: before destroy */
            if (fd >= 0)
                w->fd = fd; /* destroy removes it */
            else
                w->tmp.clear();
            destroy(w);
            w = nullptr;
            return tpio::write_failed(err, p, fd < 0 ? -fd : EINTR);
        }
        w->fd = fd;
        *out = w;
        return TP_OK;
    } catch (...) {
        /* std::bad_alloc from a string: neither the writer (with its temporary file) nor the
         * hold may outlive us, or a later Ctrl-C would only set the flag */
        if (w)
            destroy(w);
        else
            tp_interrupt_release();
        return tpio::caught(err, path);
    }
}

extern "C" tp_status tp_file_append(tp_file_writer* w, const void* data, size_t size,
                                    tp_error* err)
{
    if (!w || (!data && size))
        return fail(err, TP_ERR_INVALID_ARG, "file: bad arguments (writer or data is NULL)");
    if (!w->error) {
        int e = tpio::write_fd(w->fd, data, size);
        if (e)
            drop(w, e);
        else
            w->size += size;
    }
    return w->error ? tpio::write_failed(err, w->path, w->error) : TP_OK;
}

extern "C" tp_status tp_file_rewrite(tp_file_writer* w, uint64_t offset, const void* data,
                                     size_t size, tp_error* err)
{
    if (!w || (!data && size))
        return fail(err, TP_ERR_INVALID_ARG, "file: bad arguments (writer or data is NULL)");
    if (offset > w->size || size > w->size - offset)
        return fail(err, TP_ERR_INVALID_ARG,
                    "%s: rewrite of bytes %llu .. %llu beyond the %llu written", w->path.c_str(),
                    (unsigned long long)offset, (unsigned long long)(offset + size),
                    (unsigned long long)w->size);
    const char* p = static_cast<const char*>(data);
    for (size_t done = 0; !w->error && done < size;) {
        if (g_signal) {
            drop(w, EINTR);
            break;
        }
        advance(w, pwrite(w->fd, p + done, size - done, (off_t)(offset + done)), &done);
    }
    return w->error ? tpio::write_failed(err, w->path, w->error) : TP_OK;
}

namespace tpio {

tp_status file_reserve(tp_file_writer* w, uint64_t size, tp_error* err)
{
    if (!w->error && size > 0) {
        const uintmax_t end = w->size + size;
        if (g_signal)
            drop(w, EINTR);
        else if (end > (uintmax_t)INT64_MAX || ftruncate(w->fd, (off_t)end) != 0)
            drop(w, end > (uintmax_t)INT64_MAX ? EFBIG : errno);
        else if (lseek(w->fd, 0, SEEK_END) < 0)
            drop(w, errno);
        else
            w->size = end;
    }
    return w->error ? write_failed(err, w->path, w->error) : TP_OK;
}

tp_status file_read_back(tp_file_writer* w, uint64_t offset, void* data, size_t size,
                         tp_error* err)
{
    if (offset > w->size || size > w->size - offset)
        return fail(err, TP_ERR_INVALID_ARG, "%s: read back of bytes %llu .. %llu beyond the %llu written",
                    w->path.c_str(), (unsigned long long)offset, (unsigned long long)(offset + size),
                    (unsigned long long)w->size);
    char* p = static_cast<char*>(data);
    for (size_t done = 0; !w->error && done < size;) {
        advance(w, pread(w->fd, p + done, size - done, (off_t)(offset + done)), &done);
    }
    return w->error ? write_failed(err, w->path, w->error) : TP_OK;
}

} // namespace tpio

extern "C" tp_status tp_file_commit(tp_file_writer* w, tp_error* err)
{
    if (!w)
        return fail(err, TP_ERR_INVALID_ARG, "file: bad arguments (writer is NULL)");
    if (!w->error && g_signal)
        drop(w, EINTR);
    if (!w->error) {
        int e = tpio::finish_fd(w->fd, w->size);
        w->fd = -1; /* closed, whatever happened */
        if (!e && g_signal)
            e = EINTR;
        if (!e && std::rename(w->tmp.c_str(), w->path.c_str()) != 0)
            e = errno;
        if (e)
            unlink(w->tmp.c_str());
        else
            tpio::sync_dir(tpio::dir_of(w->path)); /* best effort: the rename reaches the disk */
        w->error = e;
    }
    tp_status s = TP_OK;
    if (w->error) {
        try {
            s = tpio::write_failed(err, w->path, w->error);
        } catch (...) {
            s = TP_ERR_IO;
        }
    }
    destroy(w);
    return s;
}

extern "C" void tp_file_abort(tp_file_writer* w)
{
    if (w)
        destroy(w);
}

extern "C" tp_status tp_file_write(const char* path, const void* data, size_t size, tp_error* err)
{
    if (!data && size)
        return fail(err, TP_ERR_INVALID_ARG, "%s: bad arguments (data is NULL)", path ? path : "file");
    tp_file_writer* w;
    tp_status s = tp_file_begin(path, &w, err);
    if (s != TP_OK)
        return s;
    s = tp_file_append(w, data, size, err);
    if (s != TP_OK) {
        tp_file_abort(w);
        return s;
    }
    return tp_file_commit(w, err);
}

extern "C" tp_status tp_output_check(const char* path, tp_error* err)
{
    if (!path || !*path)
        return fail(err, TP_ERR_INVALID_ARG, "output: an empty file name");
    try {
        const std::string p = path;
        if (p.back() == '/')
            return fail(err, TP_ERR_INVALID_ARG, "%s: a file name is needed, not a folder", path);
        const std::string dir = tpio::dir_of(p);
        struct stat st;
        if (stat(dir.c_str(), &st) != 0)
            return fail(err, TP_ERR_IO, "%s: cannot write: %s: %s", path, dir.c_str(),
                        std::strerror(errno));
        if (!S_ISDIR(st.st_mode))
            return fail(err, TP_ERR_IO, "%s: cannot write: %s is not a folder", path, dir.c_str());
        if (access(dir.c_str(), W_OK | X_OK) != 0)
            return fail(err, TP_ERR_IO, "%s: cannot write: %s: %s", path, dir.c_str(),
                        std::strerror(errno));
        if (stat(path, &st) == 0 && S_ISDIR(st.st_mode))
            return fail(err, TP_ERR_IO, "%s: cannot write: it is a folder", path);
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}
