/*
 * progress.h - progress of a long command on stderr (build, imagery): on a terminal one bar
 * redrawn at most every 0.2 s, after the prefix of every line (tp_cli_prefix),
 *     "\rterrapatch build: build [#########.....................]  30%  12.4 Msamples/s  ETA 41 s"
 * else (a log, a pipe) one line each time another tenth is done,
 *     "terrapatch build: build  30% (12.4 Msamples/s, ETA 41 s)".
 * The rate is shown only when the caller counts samples.
 */
#ifndef TP_APP_PROGRESS_H
#define TP_APP_PROGRESS_H

typedef struct tp_progress {
    int on, tty, last_decile;
    double t0, last_draw;
    const char* who;  /* the command: "build" (the lines' prefix is tp_cli_prefix's) */
    const char* what; /* the stage: "range", "build", "imagery" */
} tp_progress;

/* Starts the clock; on = 0 (--quiet) makes every update print nothing. who and what are
 * borrowed. */
void tp_progress_start(tp_progress* p, int on, const char* who, const char* what);

/* done of total units (total <= 0: nothing printed); samples >= 0 shows the rate in samples
 * per second since the start, < 0 shows none. The last update (done >= total) always prints. */
void tp_progress_update(tp_progress* p, double done, double total, double samples);

#endif
