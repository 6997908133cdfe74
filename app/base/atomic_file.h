/*
 * atomic_file.h - text outputs (statistics JSON, CSV) printed with stdio into memory
 * (open_memstream) and handed whole to io's atomic writer (tp_file_write in tp_io.h): the
 * target is replaced only by a complete file, and any failure leaves it as it was.
 */
#ifndef TP_APP_ATOMIC_FILE_H
#define TP_APP_ATOMIC_FILE_H

#include "tp_io.h"

#include <stddef.h>
#include <stdio.h>

typedef struct tp_atomic_file {
    FILE* f; /* print here: a stream into memory, no file on disk */
    const char* path;
    char* buf;
    size_t size;
} tp_atomic_file;

/* Opens the stream; 0 after a one-line message naming path (out of memory). Path "-" is
 * stdout itself (a->f = stdout), as on every command line. */
int tp_atomic_open(tp_atomic_file* a, const char* path);
/* Writes what was printed as the file path (tp_file_write) and frees the stream; 0 after a
 * one-line message, with nothing left behind and an older file untouched. For "-", flushes
 * stdout (0 when that fails). */
int tp_atomic_commit(tp_atomic_file* a);

/* Hands what was printed to set as the file path (tp_file_set_add: written to its temporary
 * file, renamed with the rest of the set at its commit) and frees the stream; 0 after a
 * one-line message (the set then fails: abort it). */
int tp_atomic_add_to_set(tp_atomic_file* a, tp_file_set* set);

/* Checks that path can be written (tp_output_check: its folder exists and is writable), before
 * a long run that ends by writing path; 0 after a one-line message naming path. */
int tp_atomic_check_dir(const char* path);

#endif
