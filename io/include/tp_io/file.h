/*
 * tp_io/file.h - files written whole or not at all: the atomic writer, sets of files committed
 * together, the output check before long work, SIGINT/SIGTERM while they are written.
 * Part of tp_io.h, which includes it (as every caller does); the error conventions stated
 * there hold here. C11.
 */
#ifndef TP_IO_FILE_H
#define TP_IO_FILE_H

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Files written whole or not at all (io/src/atomic_write.cpp)
 *
 * Every file terrapatch writes (images, meshes, JSON, CSV) goes through this writer. The bytes
 * go to a new temporary file beside path, named path + ".tmp" + 8 random characters and created
 * with O_CREAT | O_EXCL | O_NOFOLLOW (a file or symlink planted there is never opened, let
 * alone followed); every write() is checked (ENOSPC, EFBIG, EDQUOT, EIO end the write, EINTR
 * is retried); commit checks the size on disk, fsyncs, closes (checked), renames over path and
 * fsyncs the folder. On any failure, and on SIGINT/SIGTERM once tp_interrupt_install has run,
 * the temporary file is removed and path is left exactly as it was: the old file, or none.
 * Messages name path: "PATH: cannot write: No space left on device", "PATH: interrupted
 * (SIGTERM): not written".
 */
typedef struct tp_file_writer tp_file_writer;

/* Creates the temporary file. TP_ERR_INVALID_ARG for a name ending in '/', TP_ERR_IO when the
 * folder does not exist or is not writable (or after a signal). */
tp_status tp_file_begin(const char* path, tp_file_writer** out, tp_error* err);
/* Appends size bytes, in pieces of at most 4 MiB with the signal flag checked between them.
 * On failure the temporary file is already gone; w must still be aborted (or committed, which
 * returns the same failure). */
tp_status tp_file_append(tp_file_writer* w, const void* data, size_t size, tp_error* err);
/* Overwrites size bytes at offset of what was appended already (offset + size <= the bytes
 * appended so far; else TP_ERR_INVALID_ARG): for a header whose values are known only at the
 * end. Fails as tp_file_append does. */
tp_status tp_file_rewrite(tp_file_writer* w, uint64_t offset, const void* data, size_t size,
                          tp_error* err);
/* Makes the file path: fsync, close, rename, fsync of the folder. Frees w, whatever happens. */
tp_status tp_file_commit(tp_file_writer* w, tp_error* err);
/* Removes the temporary file and frees w; path is untouched. Accepts NULL. */
void tp_file_abort(tp_file_writer* w);
/* begin, append, commit: the whole of data as the file path. */
tp_status tp_file_write(const char* path, const void* data, size_t size, tp_error* err);

/* Several files written all or none (io/src/file_set.cpp): a command's outputs (a JSON, a
 * CSV and a plot; a raster and its sidecars). Each file added is written whole to its own
 * temporary file beside its path at once (as tp_file_write: every write checked, size checked,
 * fsync, close); nothing is renamed until the commit. The commit looks at the signal flag a
 * last time, then with SIGINT/SIGTERM blocked moves every older file aside (a hard link, so
 * the path never goes missing) and renames every temporary file over its path; if a rename
 * fails, the ones done are undone (the older files put back, new names removed). Any failure
 * before or during the commit leaves every path as it was: the older files, or none. The set
 * holds interruption (tp_interrupt_hold) from begin to commit or abort. */
typedef struct tp_file_set tp_file_set;

/* An empty set. TP_ERR_OUT_OF_MEMORY; *out written only on success. */
tp_status tp_file_set_begin(tp_file_set** out, tp_error* err);
/* Writes data (size bytes) to a new temporary file for path. TP_ERR_INVALID_ARG for a path
 * already in the set or ending in '/'; TP_ERR_IO as tp_file_write (full disk, missing folder,
 * signal), after which every later call and the commit fail the same way (abort s). */
tp_status tp_file_set_add(tp_file_set* s, const char* path, const void* data, size_t size,
                          tp_error* err);
/* Removes path, if it exists, with the commit (and puts it back if the commit fails): a stale
 * sidecar of an older output that the new one does not have. */
tp_status tp_file_set_remove(tp_file_set* s, const char* path, tp_error* err);
/* Puts every file of the set in place, all or none. Frees s, whatever happens. The message
 * names the path that failed. */
tp_status tp_file_set_commit(tp_file_set* s, tp_error* err);
/* Removes the temporary files and frees s; every path is untouched. Accepts NULL. */
void tp_file_set_abort(tp_file_set* s);

/* Checks, before long work that ends by writing path, that it can be written: its folder
 * exists and is writable and path is not a folder. Writes nothing. TP_ERR_IO (or
 * TP_ERR_INVALID_ARG for "" or a name ending in '/') with a message naming path. */
tp_status tp_output_check(const char* path, tp_error* err);

/* SIGINT and SIGTERM. tp_interrupt_install sets handlers (not for a signal the program started
 * with ignored, as nohup and background jobs do) that only record the signal while a temporary
 * file or folder of the writers is live; at any other moment they restore the default action
 * and re-raise it, so the program dies as it would without them (nothing of ours is on disk).
 * Once recorded, the writers remove their temporaries and fail; tp_interrupted() returns the
 * signal (0 if none), and the program should exit with status 128 + that signal. (A signal
 * after a writer's last look, during the rename, lets that file complete; it is still
 * recorded.)
 * tp_interrupt_hold/release bracket other work that checks tp_interrupted() itself (nested
 * holds count; the writers hold while a temporary lives). Any thread: the holds are counted
 * atomically (the store cache writes a store on a thread while the viewer draws). */
void tp_interrupt_install(void);
int tp_interrupted(void);
void tp_interrupt_hold(void);
void tp_interrupt_release(void);
/* After the program's last output is in place: SIGINT and SIGTERM are ignored from now on and a
 * signal recorded since the writers' last look is forgotten (tp_interrupted() returns 0), so the
 * program ends as having written its outputs (its "wrote" lines, status 0), never 130/143 with
 * them in place. Call it while holding (tp_interrupt_hold) across the last commit, so that no
 * signal kills the program between the rename and this call. */
void tp_interrupt_finished(void);

#ifdef __cplusplus
}
#endif
#endif /* TP_IO_FILE_H */
