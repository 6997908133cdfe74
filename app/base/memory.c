/* memory.c - the up-front memory check (see memory.h). Linux: /proc and /sys/fs/cgroup. */
#define _GNU_SOURCE
#include "memory.h"

#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <unistd.h>

/* Base (MiB) and bytes per fitted sample, per command: peaks measured on N42E001.hgt at 1201^2
 * and 3601^2, mt_rainier_90m.tif, front_range_srtmgl3_758.asc and lf_elev_220_mt_hood_utm.tif
 * (docs/PERFORMANCE.md), the largest per-sample cost seen, plus a quarter. */
static const struct {
    const char* name;
    double base_mib, bytes_per_sample;
} costs[] = {
    [TP_MEMORY_USE_INFO] = {"info", 160, 30},
    [TP_MEMORY_USE_VIEW] = {"view", 250, 70},
    [TP_MEMORY_USE_EXPORT] = {"export", 170, 40},
    [TP_MEMORY_USE_EXPORT_FULL] = {"export --full", 170, 390},
    [TP_MEMORY_USE_BENCH] = {"bench", 250, 150},
};

const char* tp_memory_use_name(tp_memory_use use)
{
    return costs[use].name;
}

uint64_t tp_memory_estimate(tp_memory_use use, uint64_t samples)
{
    return (uint64_t)(costs[use].base_mib * 1048576.0 +
                      costs[use].bytes_per_sample * (double)samples);
}

/* A "Key:   N kB" line of a /proc file, in bytes; 0 if missing. */
static uint64_t proc_kb(const char* file, const char* key)
{
    FILE* f = fopen(file, "r");
    if (!f)
        return 0;
    char line[256];
    uint64_t v = 0;
    size_t n = strlen(key);
    while (fgets(line, sizeof line, f)) {
        if (!strncmp(line, key, n) && line[n] == ':') {
            v = strtoull(line + n + 1, NULL, 10) * 1024;
            break;
        }
    }
    fclose(f);
    return v;
}

/* A number in a one-line file ("max" or missing: 0). */
static uint64_t file_number(const char* path)
{
    FILE* f = fopen(path, "r");
    if (!f)
        return 0;
    char buf[64] = "";
    uint64_t v = 0;
    if (fgets(buf, sizeof buf, f) && buf[0] >= '0' && buf[0] <= '9')
        v = strtoull(buf, NULL, 10);
    fclose(f);
    return v;
}

/* TP_MEMORY_LIMIT: bytes, with an optional K, M or G (binary) suffix; 0 if unset or bad
 * (tp_memory_limit_check refuses a bad one before any command runs). */
static uint64_t env_limit(void)
{
    const char* s = getenv("TP_MEMORY_LIMIT");
    if (!s || !*s)
        return 0;
    char* end;
    /* digits and one point, then a suffix: strtod alone would take "inf", "nan", hex, blanks */
    size_t digits = strspn(s, "0123456789.");
    if (!digits || strchr(s + digits, '.') || (s[digits] && strchr("xX", s[digits])))
        return 0;
    double v = strtod(s, &end);
    if (end != s + digits)
        return 0;
    switch (*end) {
    case 'k':
    case 'K': v *= 1024.0, end++; break;
    case 'm':
    case 'M': v *= 1048576.0, end++; break;
    case 'g':
    case 'G': v *= 1073741824.0, end++; break;
    }
    return *end == '\0' && v > 0 && v < 1.8e19 ? (uint64_t)v : 0;
}

int tp_memory_limit_check(void)
{
    const char* s = getenv("TP_MEMORY_LIMIT");
    if (!s || !*s || env_limit() > 0)
        return 1;
    tp_cli_error("TP_MEMORY_LIMIT=%s: expected a number of bytes > 0 with an "
                 "optional K, M or G suffix (e.g. 512M, 2G)",
                 s);
    return 0;
}

static void consider(tp_memory_room* r, uint64_t limit, uint64_t used, const char* bound)
{
    if (!limit)
        return;
    uint64_t room = limit > used ? limit - used : 0;
    if (room < r->bytes)
        r->bytes = room, r->bound = bound;
}

void tp_memory_room_now(tp_memory_room* r)
{
    r->bytes = UINT64_MAX;
    r->bound = "nothing";
    r->rss_bytes = proc_kb("/proc/self/status", "VmRSS");
    consider(r, env_limit(), r->rss_bytes, "TP_MEMORY_LIMIT");
    struct rlimit rl;
    if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
        consider(r, rl.rlim_cur, proc_kb("/proc/self/status", "VmSize"), "ulimit -v");
    if (getrlimit(RLIMIT_DATA, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
        consider(r, rl.rlim_cur, proc_kb("/proc/self/status", "VmData"), "ulimit -d");
    /* cgroup v2: this process's group ("0::/path" in /proc/self/cgroup), then the root view */
    char group[512] = "", path[640];
    FILE* f = fopen("/proc/self/cgroup", "r");
    if (f) {
        char line[512];
        while (fgets(line, sizeof line, f))
            if (!strncmp(line, "0::", 3)) {
                snprintf(group, sizeof group, "%s", line + 3);
                group[strcspn(group, "\n")] = '\0';
            }
        fclose(f);
    }
    snprintf(path, sizeof path, "/sys/fs/cgroup%s/memory.max", group);
    uint64_t max = file_number(path);
    if (!max)
        max = file_number("/sys/fs/cgroup/memory.max");
    if (max) {
        snprintf(path, sizeof path, "/sys/fs/cgroup%s/memory.current", group);
        uint64_t cur = file_number(path);
        if (!cur)
            cur = file_number("/sys/fs/cgroup/memory.current");
        consider(r, max, cur, "the cgroup's memory.max");
    }
    uint64_t avail = proc_kb("/proc/meminfo", "MemAvailable");
    if (!avail) { /* no /proc: free pages (page cache not counted, so on the safe side) */
        long pages = sysconf(_SC_AVPHYS_PAGES), page = sysconf(_SC_PAGESIZE);
        avail = pages > 0 && page > 0 ? (uint64_t)pages * (uint64_t)page : 0;
    }
    consider(r, avail, 0, "MemAvailable");
}

uint64_t tp_memory_peak_rss(void)
{
    struct rusage ru;
    if (getrusage(RUSAGE_SELF, &ru) != 0)
        return 0;
    return (uint64_t)ru.ru_maxrss * 1024; /* Linux: kilobytes */
}

static double mib(uint64_t b)
{
    return (double)b / 1048576.0;
}

int tp_memory_check(const char* path, tp_memory_use use, int width, int height)
{
    uint64_t samples = (uint64_t)width * (uint64_t)height;
    uint64_t need = tp_memory_estimate(use, samples);
    tp_memory_room room;
    tp_memory_room_now(&room);
    uint64_t more = need > room.rss_bytes ? need - room.rss_bytes : 0;
    if (more <= room.bytes)
        return 0;
    const char* hint = use == TP_MEMORY_USE_EXPORT_FULL
                           ? "export to a .vtp, which is written a piece at a time, or without "
                             "--full (a --max-error or view-dependent mesh)"
                           : "cut the DEM (gdal_translate -srcwin) or coarsen it (gdalwarp -tr)";
    tp_cli_error("%s: %s of its %dx%d grid needs about %.0f MiB (%.0f MiB more than the "
                 "%.0f MiB in use), but only %.0f MiB is available (%s); %s",
                 path, tp_memory_use_name(use), width, height, mib(need), mib(more),
                 mib(room.rss_bytes), mib(room.bytes), room.bound, hint);
    return -1;
}

uint64_t tp_memory_fit_budget(const char* cmd, const char* path, const char* what,
                              uint64_t base_bytes, uint64_t want_bytes, uint64_t min_bytes)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    tp_memory_room room;
    tp_memory_room_now(&room);
    if (room.bytes == UINT64_MAX || room.bytes >= base_bytes + want_bytes)
        return want_bytes;
    uint64_t fit = room.bytes > base_bytes ? room.bytes - base_bytes : 0;
    if (fit < min_bytes) {
        tp_cli_error("%s: needs about %.0f MiB (%.0f MiB for %s at least), but only "
                     "%.0f MiB is available (%s)",
                     path, mib(base_bytes + min_bytes), mib(min_bytes), what, mib(room.bytes),
                     room.bound);
        return 0;
    }
    tp_cli_warning("%s: %.0f MiB is available (%s): %s %.0f MiB instead of "
                   "%.0f MiB",
                   path, mib(room.bytes), room.bound, what, mib(fit), mib(want_bytes));
    return fit;
}
