/* bench_plot.c - the --sweep plot: gnuplot from Debian draws the sweep's CSV (see bench.h). */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

#include "tp_io.h"

#include <errno.h>
#include <math.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

#define ZERO_PX 0.01 /* where an error of 0 px goes on the log scale */

/* s as a gnuplot single-quoted string: quotes doubled. */
static void put_quoted(FILE* f, const char* s)
{
    fputc('\'', f);
    for (; *s; s++) {
        if (*s == '\'')
            fputc('\'', f);
        if (*s != '\n')
            fputc(*s, f);
    }
    fputc('\'', f);
}

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

/* The script: two panels, fps against the maximum and the RMS screen error (log-log). */
static void write_script(FILE* f, const tp_bench_point* pts, int count, const char* png,
                         const char* title, double full_fps)
{
    put_block(f, "dist", pts, count, 0, 0);
    put_block(f, "err", pts, count, 1, 0);
    put_block(f, "dist_front", pts, count, 0, 1);
    put_block(f, "err_front", pts, count, 1, 1);
    fputs("set terminal pngcairo size 1500,600 font 'sans,10'\nset output ", f);
    put_quoted(f, png);
    fputs("\nset multiplot layout 1,2 title ", f);
    put_quoted(f, title);
    fprintf(f, " noenhanced\nfull = %.6g\n", full_fps);
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

/* Runs gnuplot on script; 1 on success, else 0 after a message. */
static int run_gnuplot(const char* script)
{
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    char* argv[] = {"gnuplot", (char*)script, NULL};
    pid_t pid;
    int rc = posix_spawnp(&pid, "gnuplot", &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) {
        fprintf(stderr, "terrapatch bench: cannot run gnuplot (%s; apt-get install gnuplot-nox)\n",
                strerror(rc));
        return 0;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (tp_interrupted()) /* Ctrl-C reached gnuplot too; main says "interrupted" */
        return 0;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        fprintf(stderr, "terrapatch bench: gnuplot failed (exit %d)%s\n",
                WIFEXITED(status) ? WEXITSTATUS(status) : -1,
                WIFEXITED(status) && WEXITSTATUS(status) == 127
                    ? "; is it installed? apt-get install gnuplot-nox"
                    : "");
        return 0;
    }
    return 1;
}

/* The whole of a file of ours into memory (malloc'd); NULL on failure. */
static unsigned char* read_all(const char* path, size_t* size)
{
    FILE* f = fopen(path, "rb");
    unsigned char* buf = NULL;
    size_t cap = 0, n = 0;
    int failed = !f;
    while (!failed) {
        if (n == cap) {
            unsigned char* b = realloc(buf, cap = cap ? 2 * cap : (size_t)1 << 16);
            if (!b) {
                failed = 1;
                break;
            }
            buf = b;
        }
        size_t got = fread(buf + n, 1, cap - n, f);
        n += got;
        if (got == 0)
            break;
    }
    if (f) {
        failed |= ferror(f);
        fclose(f);
    }
    if (failed || n == 0) {
        free(buf);
        return NULL;
    }
    *size = n;
    return buf;
}

int tp_bench_plot(const tp_bench_point* pts, int count, const char* png, const char* title,
                  double full_fps)
{
    /* gnuplot writes into a private folder of ours (mkdtemp: a new, unguessable name, mode
     * 0700); the PNG then goes through the atomic writer like every other output. */
    char dir[4200], tmp_png[4300], script[4300];
    snprintf(dir, sizeof dir, "%s.tmpXXXXXX", png);
    tp_interrupt_hold(); /* a signal now only sets the flag: the folder is removed below */
    if (!mkdtemp(dir)) {
        fprintf(stderr, "terrapatch: %s: cannot write the plot: %s\n", png, strerror(errno));
        tp_interrupt_release();
        return 0;
    }
    snprintf(tmp_png, sizeof tmp_png, "%s/plot.png", dir);
    snprintf(script, sizeof script, "%s/plot.gp", dir);
    FILE* f = fopen(script, "w");
    int ok = f != NULL;
    if (!f)
        fprintf(stderr, "terrapatch: %s: cannot write the plot: %s\n", png, strerror(errno));
    if (ok) {
        write_script(f, pts, count, tmp_png, title, full_fps);
        int bad = ferror(f);
        if (fclose(f) != 0 || bad) { /* a full disk: say so, as for every other output */
            fprintf(stderr, "terrapatch: %s: cannot write the plot's script: %s\n", png,
                    bad ? "write error" : strerror(errno));
            ok = 0;
        } else {
            ok = !tp_interrupted() && run_gnuplot(script);
        }
    }
    size_t size = 0;
    unsigned char* bytes = ok && !tp_interrupted() ? read_all(tmp_png, &size) : NULL;
    if (ok && !bytes && !tp_interrupted()) {
        fprintf(stderr, "terrapatch: %s: gnuplot wrote no plot\n", png);
        ok = 0;
    }
    remove(script);
    remove(tmp_png);
    rmdir(dir);
    tp_interrupt_release();
    if (ok && bytes) {
        tp_error err;
        if (tp_file_write(png, bytes, size, &err) != TP_OK) {
            if (!tp_interrupted())
                fprintf(stderr, "terrapatch: %s\n", err.message);
            ok = 0;
        }
    }
    ok = ok && bytes;
    free(bytes);
    if (ok)
        fprintf(stderr, "terrapatch: wrote %s\n", png);
    return ok;
}
