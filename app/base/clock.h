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

#endif /* TP_APP_CLOCK_H */
