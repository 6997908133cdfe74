/*
 * gnuplot.h - a PNG drawn by gnuplot (Debian's gnuplot-nox) from a script we write, written
 * atomically: gnuplot draws into a private folder (mkdtemp, 0700) and the PNG then goes through
 * io's atomic writer like every other output. The pattern of app/bench/bench_plot.c, for the
 * field tools' plots (`terrapatch los --profile`). app/base/gnuplot.c.
 */
#ifndef TP_APP_GNUPLOT_H
#define TP_APP_GNUPLOT_H

#include <stddef.h>
#include <stdio.h>

/* Writes the script's body (after the terminal and output lines, which we write) to f. */
typedef void (*tp_gnuplot_script_fn)(FILE* f, void* user);

/* Draws png (width_px x height_px, pngcairo) with the script write() writes. Returns 1 after
 * "terrapatch CMD: wrote PNG" on stderr; 0 after one line naming png (gnuplot missing: "cannot run
 * gnuplot (...; apt-get install gnuplot-nox)"; gnuplot failed; a write error), with png left as
 * it was. cmd names the command in messages. */
int tp_gnuplot_png(const char* png, int width_px, int height_px, tp_gnuplot_script_fn write,
                   void* user, const char* cmd);

/* What tp_gnuplot_png draws, in memory: the PNG's bytes (malloc'd, *size of them; free them),
 * nothing written at png (named in messages only). NULL after tp_gnuplot_png's line, or after
 * SIGINT/SIGTERM (no line: the caller says "interrupted"). */
unsigned char* tp_gnuplot_draw(const char* png, int width_px, int height_px,
                               tp_gnuplot_script_fn write, void* user, const char* cmd,
                               size_t* size);

/* s as a gnuplot single-quoted string (quotes doubled, newlines dropped). */
void tp_gnuplot_quoted(FILE* f, const char* s);

#endif /* TP_APP_GNUPLOT_H */
