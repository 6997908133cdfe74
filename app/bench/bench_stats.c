/* bench_stats.c - the medians and percentiles of a run's frames, for both benches (the DEM's in
 * cmd_bench.c, the store's in bench_store.c); the process's start and memory (/proc). */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

#include "cli.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static int cmp_double(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return (x > y) - (x < y);
}

double tp_bench_median(double* v, int n)
{
    qsort(v, (size_t)n, sizeof *v, cmp_double);
    return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

double tp_bench_p99(const double* v, int n)
{
    int k = (int)ceil(0.99 * n) - 1;
    return v[k < 0 ? 0 : k];
}

void tp_bench_progress(const char* progress, int frame, int frames, const char* what)
{
    if (isatty(STDERR_FILENO)) {
        fprintf(stderr, "\r%s%s: frame %d/%d, %s   ", tp_cli_prefix(), progress, frame, frames,
                what);
        return;
    }
    /* a line when the run passes another tenth, and at its end */
    if (frame == frames || (long)frame * 10 / frames != (long)(frame - 1) * 10 / frames)
        tp_cli_note("%s: frame %d/%d, %s", progress, frame, frames, what);
}

void tp_bench_progress_end(void)
{
    if (isatty(STDERR_FILENO))
        fputc('\n', stderr);
}

/* tp_bench_ms_since_start: from its start time in /proc/self/stat (clock ticks since boot)
 * against CLOCK_BOOTTIME. */
double tp_bench_ms_since_start(void)
{
    FILE* f = fopen("/proc/self/stat", "r");
    if (!f)
        return NAN;
    char buf[2048];
    size_t n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    char* p = strrchr(buf, ')'); /* the command name may hold spaces */
    if (!p)
        return NAN;
    unsigned long long start = 0;
    /* fields after ')': 3 state ... 22 starttime */
    int field = 2;
    for (char* s = p + 1; *s && field < 22; s++)
        if (*s == ' ' && ++field == 22)
            start = strtoull(s + 1, NULL, 10);
    long hz = sysconf(_SC_CLK_TCK);
    struct timespec ts;
    if (field != 22 || hz <= 0 || clock_gettime(CLOCK_BOOTTIME, &ts) != 0)
        return NAN;
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6 - (double)start * 1e3 / (double)hz;
}

void tp_bench_read_rss(double* rss_mb, double* anon_mb)
{
    *rss_mb = *anon_mb = NAN;
    FILE* f = fopen("/proc/self/status", "r");
    if (!f)
        return;
    char line[256];
    double kb;
    while (fgets(line, sizeof line, f)) {
        if (sscanf(line, "VmRSS: %lf", &kb) == 1)
            *rss_mb = kb * 1024 / 1e6;
        else if (sscanf(line, "RssAnon: %lf", &kb) == 1)
            *anon_mb = kb * 1024 / 1e6;
    }
    fclose(f);
}
