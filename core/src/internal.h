/* internal.h - what every file of the core shares: the base API (status, errors, the allocator,
 * limits), the C library headers each file uses, and the allocator's helpers. Each module keeps
 * its own private state beside its files (terrain_int.h, lattice.h, tree_int.h, cut_int.h, ...;
 * docs/core.md has the map). Not installed. */
#ifndef TP_CORE_INTERNAL_H
#define TP_CORE_INTERNAL_H

#include "tp_base.h"

#include <assert.h>
#include <math.h>
#include <stdint.h>

/* The terrain's allocator (status.c). tp__alloc and tp__calloc return NULL on failure, also
 * when count * size overflows; tp__calloc zeroes. tp__free accepts NULL. */
void* tp__alloc(const tp_allocator* a, size_t count, size_t size);
void* tp__calloc(const tp_allocator* a, size_t count, size_t size);
void tp__free(const tp_allocator* a, void* p);

/* The core's name for tp_error_set. */
#define tp__fail tp_error_set

#endif
