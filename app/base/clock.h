/*
 * clock.h - the one clock of the app (clock.c): seconds and milliseconds on the monotonic clock,
 * for timings, progress and timeouts. Only differences between two readings mean anything.
 */
#ifndef TP_APP_CLOCK_H
#define TP_APP_CLOCK_H

/* Seconds on CLOCK_MONOTONIC. */
double tp_clock_s(void);

/* The same in milliseconds. */
double tp_clock_ms(void);

/* The calling thread's CPU time in milliseconds (CLOCK_THREAD_CPUTIME_ID): what a thread
 * spent, whoever else ran on the cores meanwhile. */
double tp_clock_thread_cpu_ms(void);

/* Milliseconds since the process started (its start time in /proc/self/stat, in clock ticks
 * since boot, against CLOCK_BOOTTIME: the dynamic loader and the libraries' initialisers
 * included); NaN when unknown. Resolution: one tick (10 ms). */
double tp_clock_ms_since_start(void);

#endif /* TP_APP_CLOCK_H */
