/*
 * atomic_file.h - text outputs (statistics JSON, CSV) written whole or not at all: into a
 * temporary file beside the target, renamed over it on success, removed on failure.
 */
#ifndef TP_APP_ATOMIC_FILE_H
#define TP_APP_ATOMIC_FILE_H

#include <stdio.h>

typedef struct tp_atomic_file {
    FILE* f;
    const char* path;
    char tmp[4096];
} tp_atomic_file;

/* Opens the temporary file; 0 after a one-line message naming path. */
int tp_atomic_open(tp_atomic_file* a, const char* path);
/* Finishes the write (flush, close, rename); 0 after a message, with nothing left behind. */
int tp_atomic_commit(tp_atomic_file* a);

/* Checks that path's folder exists and is writable (before a long run that ends by writing
 * path); 0 after a one-line message naming path. */
int tp_atomic_check_dir(const char* path);

#endif
