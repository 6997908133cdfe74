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

double tp_bench_mean(const double* v, int n)
{
    double sum = 0;
    for (int i = 0; i < n; i++)
        sum += v[i];
    return n > 0 ? sum / n : NAN;
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
