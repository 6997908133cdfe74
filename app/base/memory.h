/*
 * memory.h - how much memory a command will need and how much this process may still use, so
 * that a DEM too big for the machine is refused up front with one line instead of being killed
 * part way by the kernel.
 *
 * The need is an estimate of the peak resident size: a base (the libraries, a GL context) plus
 * bytes per sample of the fitted render grid, per command, measured with /usr/bin/time -v on
 * the real DEMs (docs/PERFORMANCE.md, "Memory") and rounded up. The room is the smallest of:
 * TP_MEMORY_LIMIT (bytes, a K/M/G suffix allowed; a budget for the whole process, for tests and
 * shared machines), ulimit -v (RLIMIT_AS) and ulimit -d (RLIMIT_DATA) less what is mapped now,
 * the cgroup's memory.max less its memory.current, and MemAvailable of /proc/meminfo.
 */
#ifndef TP_APP_MEMORY_H
#define TP_APP_MEMORY_H

#include <stddef.h>
#include <stdint.h>

typedef enum tp_memory_use {
    TP_MEMORY_USE_INFO = 0,    /* terrapatch info (the default) */
    TP_MEMORY_USE_VIEW,        /* view: the terrain and its GL buffers, a GL context */
    TP_MEMORY_USE_EXPORT,      /* export of a view-dependent or --max-error mesh */
    TP_MEMORY_USE_EXPORT_FULL, /* export --full to a .vtk/.vtm, built whole (a .vtp streams:
                                  full_export.h) */
    TP_MEMORY_USE_BENCH,       /* bench: view, plus the error measurement */
} tp_memory_use;

/* The command's name as the user types it ("export --full"). */
const char* tp_memory_use_name(tp_memory_use use);

/* Estimated peak resident bytes of the command for a fitted grid of `samples` samples. */
uint64_t tp_memory_estimate(tp_memory_use use, uint64_t samples);

typedef struct tp_memory_room {
    uint64_t bytes;     /* what the process may still add; UINT64_MAX when nothing bounds it */
    const char* bound;  /* what bounds it ("TP_MEMORY_LIMIT", "ulimit -v", "MemAvailable", ...) */
    uint64_t rss_bytes; /* resident now (0 if unknown) */
} tp_memory_room;

void tp_memory_room_now(tp_memory_room* out);

/* 1 when TP_MEMORY_LIMIT is unset or a number of bytes > 0 (K/M/G suffix allowed); else 0 after
 * one line naming it ("abc", "-5", "0", "1X": a bound the user meant and we could not read is
 * not silently no bound). main() checks it before any command. */
int tp_memory_limit_check(void);

/* Peak resident bytes of this process so far (getrusage ru_maxrss); 0 if unknown. */
uint64_t tp_memory_peak_rss(void);

/* Checks that `use` of a fitted grid of width x height samples fits the room left. Returns 0 if
 * it does, else prints one line ("terrapatch CMD: PATH: ... needs about X GiB ..., Y GiB available
 * (BOUND); ...") and returns -1. */
int tp_memory_check(const char* path, tp_memory_use use, int width, int height);

/* A budget a command can shrink (a store's decoded nodes in view and bench, build's --memory)
 * fitted to the room left: want_bytes when base_bytes more (what the command needs besides the
 * budget: libraries, a GL context) and want_bytes fit, else what fits, after one warning line
 * naming the bound ("terrapatch CMD: warning: PATH: TP_MEMORY_LIMIT leaves ... : WHAT ... MiB
 * instead of ..."); 0 after one error line when not even min_bytes fits. */
uint64_t tp_memory_fit_budget(const char* cmd, const char* path, const char* what,
                              uint64_t base_bytes, uint64_t want_bytes, uint64_t min_bytes);

#endif /* TP_APP_MEMORY_H */
