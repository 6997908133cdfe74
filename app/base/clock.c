/* clock.c - the app's monotonic clock (clock.h). */
#define _POSIX_C_SOURCE 200809L
#include "clock.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

double tp_clock_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + (double)ts.tv_nsec * 1e-9;
}

double tp_clock_ms(void)
{
    return tp_clock_s() * 1e3;
}

double tp_clock_thread_cpu_ms(void)
{
    struct timespec ts;
    if (clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts) != 0)
        return NAN;
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec / 1e6;
}

/* clock.h: the start time is field 22 of /proc/self/stat, in clock ticks since boot */
double tp_clock_ms_since_start(void)
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
