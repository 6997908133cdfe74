/* progress.c - a long command's progress on stderr (see progress.h). */
#define _POSIX_C_SOURCE 200112L
#include "progress.h"
#include "clock.h"

#include "cli.h"

#include <stdio.h>
#include <time.h>
#include <unistd.h>

void tp_progress_start(tp_progress* p, int on, const char* who, const char* what)
{
    p->on = on;
    p->tty = isatty(2);
    p->last_decile = 0;
    p->t0 = tp_clock_s();
    p->last_draw = 0;
    p->who = who;
    p->what = what;
}

void tp_progress_update(tp_progress* p, double done, double total, double samples)
{
    if (!p->on || total <= 0)
        return;
    const double t = tp_clock_s(), el = t - p->t0, f = done / total;
    const double eta = f > 0 ? el * (1 - f) / f : 0;
    char rate[48] = "";
    if (p->tty) {
        if (t - p->last_draw < 0.2 && done < total)
            return;
        p->last_draw = t;
        char bar[31];
        int fill = (int)(f * 30);
        for (int i = 0; i < 30; i++)
            bar[i] = i < fill ? '#' : '.';
        bar[30] = 0;
        if (samples >= 0)
            snprintf(rate, sizeof rate, "%.1f Msamples/s  ", el > 0 ? samples / el / 1e6 : 0.0);
        fprintf(stderr, "\r%s%s [%s] %3.0f%%  %sETA %.0f s   ", tp_cli_prefix(), p->what, bar,
                100 * f, rate, eta);
        if (done >= total)
            fputc('\n', stderr);
    } else {
        int decile = (int)(f * 10);
        if (decile <= p->last_decile && done < total)
            return;
        p->last_decile = decile;
        if (samples >= 0)
            snprintf(rate, sizeof rate, "%.1f Msamples/s, ", el > 0 ? samples / el / 1e6 : 0.0);
        tp_cli_note("%s %3.0f%% (%sETA %.0f s)", p->what, 100 * f, rate, eta);
    }
}
