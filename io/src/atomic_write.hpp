/* atomic_write.hpp - the pieces of atomic_write.cpp that io's multi-file writer (the .vtm in
 * vtk_mesh_write.cpp) builds on. Private to io/. Functions returning int return 0 or an errno
 * value; EINTR means SIGINT/SIGTERM arrived (tp_interrupted), never a retried system call. */
#pragma once

#include "tp_io.h"

#include <cstddef>
#include <cstdint>
#include <string>

namespace tpio {

/* Writes go out in pieces of at most this many bytes, the interruption flag checked between. */
constexpr size_t CHUNK = (size_t)4 << 20;

std::string dir_of(const std::string& path);   /* "." for a bare name */
std::string temp_name(const std::string& path); /* path + ".tmp" + 8 random characters */

/* open(O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0666): fd, or -errno. */
int create_new(const std::string& name);
/* All of data to fd in CHUNK pieces; retries EINTR; stops with EINTR when interrupted. */
int write_fd(int fd, const void* data, size_t size);
/* Checks fd holds expected_size bytes, fsync, close (fd is closed whatever happens). */
int finish_fd(int fd, uintmax_t expected_size);
/* A complete new file (create_new, write_fd, finish_fd); on failure nothing is left. */
int write_new_file(const std::string& name, const void* data, size_t size);
/* A new folder (mode 0700) named temp_name(path); *out set only on success. */
int make_temp_dir(const std::string& path, std::string* out);
/* fsync of a folder, best effort: the renames in it reach the disk. */
void sync_dir(const std::string& dir);

/* "SIGINT" or "SIGTERM": the signal tp_interrupted reports. */
const char* interrupt_name(void);
/* TP_ERR_IO with "PATH: cannot write: <strerror(e)>" or, for EINTR, "PATH: interrupted ...". */
tp_status write_failed(tp_error* err, const std::string& path, int e);

/* For a writer that fills parts of a tp_file_writer's file out of order (the store's tables):
 * file_reserve appends size zero bytes (a hole: ftruncate, nothing written), which
 * tp_file_rewrite may then overwrite; file_read_back reads bytes already appended or reserved
 * (pread). Both fail as tp_file_append does (the temporary file is gone, w must be aborted). */
tp_status file_reserve(tp_file_writer* w, uint64_t size, tp_error* err);
tp_status file_read_back(tp_file_writer* w, uint64_t offset, void* data, size_t size,
                         tp_error* err);

/* For a writer whose files a library makes on disk itself (an OGR driver's sidecars): the
 * complete file tmp (any name on path's filesystem; fsynced here) becomes path when set s is
 * committed, all or none with the rest (file_set.cpp). Fails as tp_file_set_add. */
tp_status file_set_adopt(tp_file_set* s, const std::string& tmp, const std::string& path,
                         tp_error* err);

} // namespace tpio
