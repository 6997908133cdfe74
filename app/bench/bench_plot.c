/* bench_plot.c - the --sweep plot: gnuplot from Debian draws the sweep's CSV (see bench.h),
 * through app/gnuplot.h (a private folder, then the atomic writer). */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

#include "gnuplot.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#define ZERO_PX 0.01 /* where an error of 0 px goes on the log scale */

static int cmp_max_px(const void* a, const void* b)
{
    double x = ((const tp_bench_point*)a)->max_px, y = ((const tp_bench_point*)b)->max_px;
    return (x > y) - (x < y);
}

/* Inline data block $NAME: the points of one mode (only its front, sorted, when front). */
static void put_block(FILE* f, const char* name, const tp_bench_point* pts, int count, int error_mode,
                      int front)
{
    tp_bench_point* sorted = malloc((size_t)(count ? count : 1) * sizeof *sorted);
    int n = 0;
    for (int i = 0; sorted && i < count; i++)
        if (pts[i].error_mode == error_mode && (!front || pts[i].pareto))
            sorted[n++] = pts[i];
    if (sorted)
        qsort(sorted, (size_t)n, sizeof *sorted, cmp_max_px);
    fprintf(f, "$%s << EOD\n", name);
    for (int i = 0; i < n; i++)
        fprintf(f, "%.6g %.6g %.6g %g\n", fmax(sorted[i].max_px, ZERO_PX),
                fmax(sorted[i].rms_px, ZERO_PX), sorted[i].fps, sorted[i].tau_px);
    fputs("EOD\n", f);
    free(sorted);
}

typedef struct plot_data {
    const tp_bench_point* pts;
    int count;
    const char* title;
    double full_fps;
} plot_data;

/* The script (tp_gnuplot_script_fn): two panels, fps against the maximum and the RMS screen
 * error (log-log). */
static void write_script(FILE* f, void* user)
{
    const plot_data* d = user;
    const tp_bench_point* pts = d->pts;
    const int count = d->count;
    put_block(f, "dist", pts, count, 0, 0);
    put_block(f, "err", pts, count, 1, 0);
    put_block(f, "dist_front", pts, count, 0, 1);
    put_block(f, "err_front", pts, count, 1, 1);
    fputs("set multiplot layout 1,2 title ", f);
    tp_gnuplot_quoted(f, d->title);
    fprintf(f, " noenhanced\nfull = %.6g\n", d->full_fps);
    fputs("set logscale xy\n"
          "set grid xtics ytics mxtics mytics lc rgb '#dddddd'\n"
          "set ylabel 'frames per second (median)'\n"
          "set key bottom right box opaque\n"
          "set format x '%g'\nset format y '%g'\n",
          f);
    const char* xlabel[2] = {"measured maximum screen error over all frames (px; 0 drawn at 0.01)",
                             "measured RMS screen error over all frames (px; 0 drawn at 0.01)"};
    for (int i = 0; i < 2; i++) {
        int c = i + 1; /* column of the x value */
        fprintf(f,
                "set xlabel '%s'\n"
                "plot $dist using %d:3 with points pt 7 ps 0.9 lc rgb '#3070c0' "
                "title 'distance mode (mindist x maxdist x exp grid)', \\\n"
                "  $err using %d:3 with points pt 5 ps 1.1 lc rgb '#d04020' "
                "title 'error mode (labelled with tau, px)', \\\n"
                "  $err using %d:3:(sprintf('%%g', $4)) with labels offset 1.2,0.7 font ',8' "
                "tc rgb '#d04020' notitle, \\\n",
                xlabel[i], c, c, c);
        if (i == 0)
            fputs("  $dist_front using 1:3 with lines lw 2 lc rgb '#3070c0' "
                  "title 'distance: Pareto front', \\\n"
                  "  $err_front using 1:3 with lines lw 2 lc rgb '#d04020' "
                  "title 'error: Pareto front', \\\n",
                  f);
        fputs("  full with lines dt 2 lw 1.5 lc rgb 'black' title sprintf('full resolution "
              "(0 px): %.1f fps', full)\n",
              f);
    }
    fputs("unset multiplot\n", f);
}

int tp_bench_plot(const tp_bench_point* pts, int count, const char* png, const char* title,
                  double full_fps)
{
    plot_data d = {pts, count, title, full_fps};
    return tp_gnuplot_png(png, 1500, 600, write_script, &d, "bench");
}
