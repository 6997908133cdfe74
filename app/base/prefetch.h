/*
 * prefetch.h - TP_PREFETCH(address): a hint that the memory at address will be read soon. Loops
 * over thousands of entries scattered in memory (the renderer's vertex-pool map, the stream's
 * residency) ask a few entries ahead, so that their cache misses overlap instead of following
 * one another. Changes nothing but time; nothing where the compiler has no such hint.
 */
#ifndef TP_APP_PREFETCH_H
#define TP_APP_PREFETCH_H

#if defined(__GNUC__)
#define TP_PREFETCH(address) __builtin_prefetch(address)
#else
#define TP_PREFETCH(address) ((void)(address))
#endif

#endif /* TP_APP_PREFETCH_H */
