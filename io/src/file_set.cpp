/* file_set.cpp - several files written all or none (tp_io.h, "Several files written all or
 * none"): each file goes whole to a temporary file beside its path when it is added (the
 * pieces of atomic_write.cpp), and the commit renames them all or puts everything back.
 *
 * Why hard links: an older file is kept under a temporary name (link(), the path still names
 * it) until every rename has succeeded, so a failed rename can put it back; once the set is in
 * place the links are removed. A filesystem without hard links (EPERM, EOPNOTSUPP) gets no
 * backup: a rename that fails after one over such a file cannot undo that one.
 *
 * Why signals are blocked during the renames: a handler that finds no live temporary re-raises
 * (atomic_write.cpp); blocked, a signal waits until the set is either all in place or all
 * undone, and is recorded then (the set still holds interruption).
 */
#include "atomic_write.hpp"
#include "io_util.hpp"
#include "tp_io.h"

#include <algorithm>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <pthread.h>
#include <string>
#include <sys/stat.h>
#include <unistd.h>
#include <vector>

using tpio::fail;

namespace {
struct Entry {
    std::string path;
    std::string tmp;    /* the new file; "" for a removal */
    std::string backup; /* the older file kept aside during the commit; "" when none */
    bool aside = false; /* a removal whose file was renamed to backup */
    bool placed = false;
};
} // namespace

struct tp_file_set {
    std::vector<Entry> entries;
    int error = 0; /* errno of the first failure (EINTR: interrupted) */
    std::string error_path;
};

namespace {

/* Removes every temporary file of the set. */
void drop_temporaries(tp_file_set* s)
{
    for (Entry& e : s->entries)
        if (!e.tmp.empty() && !e.placed) {
            unlink(e.tmp.c_str());
            e.tmp.clear();
        }
}

void destroy(tp_file_set* s)
{
    drop_temporaries(s);
    delete s;
    tp_interrupt_release();
}

bool exists(const std::string& p)
{
    struct stat st;
    return lstat(p.c_str(), &st) == 0;
}

bool in_set(const tp_file_set* s, const std::string& path)
{
    return std::any_of(s->entries.begin(), s->entries.end(),
                       [&](const Entry& e) { return e.path == path; });
}

/* Undoes what the commit did so far: new files off their paths, older ones back. */
void undo(tp_file_set* s)
{
    for (auto it = s->entries.rbegin(); it != s->entries.rend(); ++it) {
        Entry& e = *it;
        if (e.placed) {
            if (!e.backup.empty())
                (void)std::rename(e.backup.c_str(), e.path.c_str());
            else
                unlink(e.path.c_str());
            e.placed = false;
            e.backup.clear();
            e.tmp.clear(); /* renamed: gone */
        } else if (e.aside) {
            (void)std::rename(e.backup.c_str(), e.path.c_str());
            e.aside = false;
            e.backup.clear();
        } else if (!e.backup.empty()) {
            unlink(e.backup.c_str()); /* a link: the path still names the older file */
            e.backup.clear();
        }
    }
}

/* A free temporary name beside path for the older file. */
int backup_name(const std::string& path, std::string* out)
{
    for (int attempt = 0; attempt < 100; ++attempt) {
        std::string name = tpio::temp_name(path);
        if (!exists(name)) {
            *out = name;
            return 0;
        }
    }
    return EEXIST;
}

/* Keeps the older file of e aside (a link; a removal's file renamed); 0 or an errno. */
int keep_older(Entry& e)
{
    if (!exists(e.path))
        return 0;
    std::string name;
    int err = backup_name(e.path, &name);
    if (err)
        return err;
    if (e.tmp.empty()) { /* a removal: the path goes now */
        if (std::rename(e.path.c_str(), name.c_str()) != 0)
            return errno;
        e.backup = name;
        e.aside = true;
        return 0;
    }
    if (link(e.path.c_str(), name.c_str()) == 0) {
        e.backup = name;
        return 0;
    }
    return errno == EPERM || errno == EOPNOTSUPP ? 0 : errno; /* no hard links here */
}

/* The whole commit with signals blocked; 0 or an errno with s->error_path set. */
int place_all(tp_file_set* s)
{
    for (Entry& e : s->entries) {
        int err = keep_older(e);
        if (err) {
            s->error_path = e.path;
            undo(s);
            return err;
        }
    }
    for (Entry& e : s->entries) {
        if (e.tmp.empty())
            continue;
        if (std::rename(e.tmp.c_str(), e.path.c_str()) != 0) {
            const int err = errno;
            s->error_path = e.path;
            undo(s);
            return err;
        }
        e.placed = true;
    }
    std::vector<std::string> dirs;
    for (Entry& e : s->entries) {
        if (!e.backup.empty())
            unlink(e.backup.c_str());
        const std::string d = tpio::dir_of(e.path);
        if (std::find(dirs.begin(), dirs.end(), d) == dirs.end())
            dirs.push_back(d);
    }
    for (const std::string& d : dirs)
        tpio::sync_dir(d); /* best effort: the renames reach the disk */
    return 0;
}

/* SIGINT and SIGTERM blocked for a scope (this thread: the writers run on the main thread). */
struct BlockSignals {
    sigset_t old;
    BlockSignals()
    {
        sigset_t block;
        sigemptyset(&block);
        sigaddset(&block, SIGINT);
        sigaddset(&block, SIGTERM);
        pthread_sigmask(SIG_BLOCK, &block, &old);
    }
    ~BlockSignals()
    {
        pthread_sigmask(SIG_SETMASK, &old, nullptr);
    }
    BlockSignals(const BlockSignals&) = delete;
    BlockSignals& operator=(const BlockSignals&) = delete;
};

tp_status set_failed(tp_file_set* s, tp_error* err)
{
    return tpio::write_failed(err, s->error_path, s->error);
}

} // namespace

namespace tpio {

tp_status file_set_adopt(tp_file_set* s, const std::string& tmp, const std::string& path,
                         tp_error* err)
{
    if (s->error)
        return set_failed(s, err);
    if (in_set(s, path))
        return fail(err, TP_ERR_INVALID_ARG, "%s: written twice in one set", path.c_str());
    int fd = open(tmp.c_str(), O_RDONLY | O_CLOEXEC);
    int e = fd < 0 ? errno : fsync(fd) != 0 ? errno : 0;
    if (fd >= 0)
        close(fd);
    if (e) {
        s->error = e;
        s->error_path = path;
        return set_failed(s, err);
    }
    s->entries.push_back(Entry{path, tmp, std::string(), false, false});
    return TP_OK;
}

} // namespace tpio

extern "C" tp_status tp_file_set_begin(tp_file_set** out, tp_error* err)
{
    if (!out)
        return fail(err, TP_ERR_INVALID_ARG, "file set: bad arguments (out is NULL)");
    tp_file_set* s = new (std::nothrow) tp_file_set;
    if (!s)
        return fail(err, TP_ERR_OUT_OF_MEMORY, "file set: out of memory");
    tp_interrupt_hold(); /* released by destroy */
    *out = s;
    return TP_OK;
}

extern "C" tp_status tp_file_set_add(tp_file_set* s, const char* path, const void* data,
                                     size_t size, tp_error* err)
{
    if (!s || !path || !*path || (!data && size))
        return fail(err, TP_ERR_INVALID_ARG, "file set: bad arguments (set, path or data)");
    if (path[std::strlen(path) - 1] == '/')
        return fail(err, TP_ERR_INVALID_ARG, "%s: a file name is needed, not a folder", path);
    try {
        if (s->error)
            return set_failed(s, err);
        if (in_set(s, path))
            return fail(err, TP_ERR_INVALID_ARG, "%s: written twice in one set", path);
        s->entries.reserve(s->entries.size() + 1); /* the push below cannot throw */
        const std::string p = path;
        int e = EEXIST;
        std::string tmp;
        for (int attempt = 0; attempt < 100 && e == EEXIST; ++attempt) {
            tmp = tpio::temp_name(p);
            e = tp_interrupted() ? EINTR : tpio::write_new_file(tmp, data, size);
        }
        if (e) {
            s->error = e;
            s->error_path = p;
            return set_failed(s, err);
        }
        s->entries.push_back(Entry{p, tmp, std::string(), false, false});
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}

extern "C" tp_status tp_file_set_remove(tp_file_set* s, const char* path, tp_error* err)
{
    if (!s || !path || !*path)
        return fail(err, TP_ERR_INVALID_ARG, "file set: bad arguments (set or path)");
    try {
        if (!in_set(s, path))
            s->entries.push_back(Entry{path, std::string(), std::string(), false, false});
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}

extern "C" tp_status tp_file_set_commit(tp_file_set* s, tp_error* err)
{
    if (!s)
        return fail(err, TP_ERR_INVALID_ARG, "file set: bad arguments (set is NULL)");
    tp_status st = TP_OK;
    try {
        if (!s->error) {
            BlockSignals blocked;
            if (tp_interrupted()) { /* the last look: after it the set goes in whole */
                s->error = EINTR;
                s->error_path = s->entries.empty() ? std::string("output") : s->entries[0].path;
            } else {
                s->error = place_all(s);
            }
        }
        if (s->error)
            st = set_failed(s, err);
    } catch (...) {
        undo(s);
        st = tpio::caught(err, "file set");
    }
    destroy(s);
    return st;
}

extern "C" void tp_file_set_abort(tp_file_set* s)
{
    if (s)
        destroy(s);
}
