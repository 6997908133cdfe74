/*
 * bench.h - the parts of `terrapatch bench` beyond the frame loop (cmd_bench.c): the static
 * meshes of `export --max-error` (bench_static.c) and the sweep's plot (bench_plot.c).
 */
#ifndef TP_APP_BENCH_H
#define TP_APP_BENCH_H

#include "scene.h"

/* `bench --static --max-error M1,M2,...`: for each bound, the static mesh of
 * `export --max-error` (levels selected, mesh built and measured, nothing written): triangles,
 * points, build time, measured maximum and RMS error against the source samples. Prints a
 * table; --json / --csv outputs when non-NULL. Returns TP_EXIT_*. */
int tp_bench_static(const tp_scene* sc, const char* dem, const double* max_errors, int count,
                    const char* json, const char* csv);

/* One configuration of a --sweep, as plotted. */
typedef struct tp_bench_point {
    int error_mode; /* 1: error mode (labelled with tau), 0: distance mode */
    double tau_px, fps, max_px, rms_px;
    int pareto;     /* on its mode's front of fps against measured maximum screen error */
} tp_bench_point;

/* Plots a --sweep with gnuplot into png: fps against measured maximum and RMS screen error
 * (log scales; an error of 0 px is drawn at 0.01 px), each mode's configurations and Pareto
 * front, full resolution as a line at full_fps. The PNG is written to a temporary file and
 * renamed. Returns 1, or 0 after a one-line message. */
int tp_bench_plot(const tp_bench_point* pts, int count, const char* png, const char* title,
                  double full_fps);

#endif
