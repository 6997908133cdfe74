/* bench_plot.c - the --sweep plot: gnuplot from Debian draws the sweep's CSV (see bench.h),
 * through app/base/gnuplot.h (a private folder, then the atomic writer). */
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

/* Inline data block $NAME: the points of one family with a finite error (only its front,
 * sorted, when front): max px, RMS px, fps, label (tau, the PGM grid, or "-"). */
static void put_block(FILE* f, const char* name, const tp_bench_point* pts, int count,
                      tp_bench_family family, int front)
{
    tp_bench_point* sorted = malloc((size_t)(count ? count : 1) * sizeof *sorted);
    int n = 0;
    for (int i = 0; sorted && i < count; i++)
        if (pts[i].family == family && (!front || pts[i].pareto) && isfinite(pts[i].max_px) &&
            isfinite(pts[i].rms_px))
            sorted[n++] = pts[i];
    if (sorted)
        qsort(sorted, (size_t)n, sizeof *sorted, cmp_max_px);
    fprintf(f, "$%s << EOD\n", name);
    for (int i = 0; i < n; i++) {
        fprintf(f, "%.6g %.6g %.6g ", fmax(sorted[i].max_px, ZERO_PX),
                fmax(sorted[i].rms_px, ZERO_PX), sorted[i].fps);
        if (family == TP_FAMILY_PGM)
            fprintf(f, "%dx%d\n", sorted[i].pgm_cols, sorted[i].pgm_rows);
        else
            fprintf(f, "%g\n", sorted[i].tau_px);
    }
    fputs("EOD\n", f);
    free(sorted);
}

typedef struct plot_data {
    const tp_bench_point* pts;
    int count;
    const char* title;
    double full_fps;
} plot_data;

/* How each family is drawn: point type and size, colour, legend; label: where its points'
 * tau or grid go (a gnuplot offset, away from the other labelled families'), NULL: none. */
static const struct {
    tp_bench_family family;
    const char *block, *style, *colour, *legend, *label;
} families[] = {
    {TP_FAMILY_DISTANCE, "dist", "pt 7 ps 0.8", "#3070c0",
     "distance, vertex moving (mindist x maxdist x exp grid)", NULL},
    {TP_FAMILY_ERROR, "err", "pt 5 ps 1.1", "#d04020", "error, vertex moving (tau, px)", "1.4,0.6"},
    {TP_FAMILY_DISTANCE_ADD, "dadd", "pt 9 ps 1.6", "#8040b0",
     "distance, vertex adding (--mindist, --maxdist, --exp as run)", NULL},
    {TP_FAMILY_ERROR_ADD, "eadd", "pt 13 ps 1.3", "#e09000", "error, vertex adding (tau, px)",
     "1.4,-0.7"},
    {TP_FAMILY_PGM, "pgm", "pt 11 ps 1.4", "#208040", "PGM (grid cols x rows)", "1.4,0.6"},
    {TP_FAMILY_STORE, "store", "pt 4 ps 1.3", "#00a0b0",
     "error, through the DEM store: lattice nodes (tau, px)", NULL},
    {TP_FAMILY_STORE_TIN, "tin", "pt 3 ps 1.5", "#c02080",
     "error, through the DEM store: TIN nodes (--mesh tin; tau, px)", "-1.6,0.6"},
};
#define FAMILIES ((int)(sizeof families / sizeof *families))

/* The script (tp_gnuplot_script_fn): two panels, fps against the maximum and the RMS screen
 * error (log-log), each family's points and (left) its Pareto front. */
static void write_script(FILE* f, void* user)
{
    const plot_data* d = user;
    char name[32];
    for (int k = 0; k < FAMILIES; k++) {
        put_block(f, families[k].block, d->pts, d->count, families[k].family, 0);
        snprintf(name, sizeof name, "%s_front", families[k].block);
        put_block(f, name, d->pts, d->count, families[k].family, 1);
    }
    fputs("set multiplot layout 1,2 title ", f);
    tp_gnuplot_quoted(f, d->title);
    fprintf(f, " noenhanced\nfull = %.6g\n", d->full_fps);
    fputs("set logscale xy\n"
          "set grid xtics ytics mxtics mytics lc rgb '#dddddd'\n"
          "set ylabel 'frames per second (median)'\n"
          "set key bottom right box opaque font ',9' spacing 1.1\n"
          "set format x '%g'\nset format y '%g'\n",
          f);
    const char* xlabel[2] = {"measured maximum screen error over all frames (px; 0 drawn at 0.01)",
                             "measured RMS screen error over all frames (px; 0 drawn at 0.01)"};
    for (int i = 0; i < 2; i++) {
        int c = i + 1; /* column of the x value */
        fprintf(f, "set xlabel '%s'\nset key title '%s'\nplot ", xlabel[i],
                i == 0 ? "lines: Pareto front of each family" : "");
        for (int k = 0; k < FAMILIES; k++) {
            fprintf(f, "$%s using %d:3 with points %s lc rgb '%s' title '%s', \\\n  ",
                    families[k].block, c, families[k].style, families[k].colour,
                    families[k].legend);
            if (families[k].label)
                fprintf(f,
                        "$%s using %d:3:4 with labels offset %s font ',7' tc rgb '%s' "
                        "notitle, \\\n  ",
                        families[k].block, c, families[k].label, families[k].colour);
            if (i == 0) /* the fronts are of fps against the maximum */
                fprintf(f, "$%s_front using 1:3 with lines lw 1.5 lc rgb '%s' notitle, \\\n  ",
                        families[k].block, families[k].colour);
        }
        fputs("full with lines dt 2 lw 1.5 lc rgb 'black' title sprintf('full resolution "
              "(0 px): %.1f fps', full)\n",
              f);
    }
    fputs("unset multiplot\n", f);
}

int tp_bench_plot(const tp_bench_point* pts, int count, const char* png, const char* title,
                  double full_fps)
{
    plot_data d = {pts, count, title, full_fps};
    return tp_gnuplot_png(png, 1800, 760, write_script, &d, "bench");
}
