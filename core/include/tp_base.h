/* tp_base.h - the core's foundations: version, limits, status and errors, the allocator.
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_BASE_H
#define TP_BASE_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

#define TP_VERSION "0.1.0"

/* Largest supported n: patches of up to 2^8+1 = 257 samples per side. */
#define TP_MAX_N 8
#define TP_MAX_LEVELS (TP_MAX_N + 1)
#define TP_DEFAULT_PATCH_SIZE 17

/* ---------------------------------------------------------------------------------------------
 * Status and errors
 */
typedef enum tp_status {
    TP_OK = 0,
    TP_ERR_INVALID_ARG, /* value outside its documented range */
    TP_ERR_BAD_DATA,    /* input file or buffer malformed */
    TP_ERR_IO,
    TP_ERR_OUT_OF_MEMORY,
    TP_ERR_BACKEND /* a wrapped C++ library failed; see the message */
} tp_status;

/* Returns the short English name of a status ("invalid argument", ...); "unknown status" for a
 * value outside the enum. Never NULL; a static string. */
const char* tp_status_str(tp_status s);

/* Optional out-parameter of failing calls: a one-line message saying what was expected and
 * what was received. Functions that take a tp_error* accept NULL. On success it is untouched. */
typedef struct tp_error {
    char message[512];
} tp_error;

/* Writes a printf-style message into err->message (when err is not NULL) and returns s: how
 * every function that takes a tp_error* fails, in the core and above it. A message longer than
 * the buffer keeps its start and its end with "..." between them (cut on UTF-8 character
 * boundaries), so the reason at the end of "PATH: reason" survives a very long path. */
tp_status tp_error_set(tp_error* err, tp_status s, const char* fmt, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 3, 4)))
#endif
    ;

/* tp_error_set with a va_list (for wrappers that take their own "..."). */
tp_status tp_error_setv(tp_error* err, tp_status s, const char* fmt, va_list ap);

/* Optional allocator (the cgltf / sokol shape). Both functions NULL means malloc and free; else
 * both must be set. alloc returns NULL on failure; free accepts NULL. When given in
 * tp_terrain_desc it makes every allocation of the terrain, of its selections and of their
 * measurements (which may run on several threads at once: it must then be thread-safe). */
typedef struct tp_allocator {
    void* (*alloc)(size_t size, void* user_data);
    void (*free)(void* ptr, void* user_data);
    void* user_data;
} tp_allocator;

#ifdef __cplusplus
}
#endif
#endif /* TP_BASE_H */
