/*
 * fuzz_util.h - what the libFuzzer entry points in tests/fuzz share: a private temporary folder
 * for readers that take a path, and a failure that libFuzzer records as a crash.
 */
#ifndef TP_FUZZ_UTIL_H
#define TP_FUZZ_UTIL_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>

#ifdef __cplusplus
extern "C" {
#endif

/* An invariant of our API broke (an output written on failure, a status without a message):
 * print why and abort, which libFuzzer saves as a crash input. */
#define TP_FUZZ_CHECK(cond, ...)                                                                   \
    do {                                                                                           \
        if (!(cond)) {                                                                             \
            fprintf(stderr, "fuzz check failed: %s: ", #cond);                                     \
            fprintf(stderr, __VA_ARGS__);                                                          \
            fputc('\n', stderr);                                                                   \
            abort();                                                                               \
        }                                                                                          \
    } while (0)

/* Writes data to <private folder>/<name> (the folder is made on the first call and removed at
 * exit) and returns that path, valid until the next call. NULL if it cannot be written. */
const char* tp_fuzz_write_file(const char* name, const uint8_t* data, size_t size);

#ifdef __cplusplus
}
#endif
#endif /* TP_FUZZ_UTIL_H */
