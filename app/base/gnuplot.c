/* gnuplot.c - a PNG drawn by gnuplot, written atomically (gnuplot.h). */
#define _POSIX_C_SOURCE 200809L
#include "gnuplot.h"

#include "cli.h"
#include "tp_io.h"

#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

void tp_gnuplot_quoted(FILE* f, const char* s)
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

/* Runs gnuplot on script; 1 on success, else 0 after a message. */
static int run_gnuplot(const char* script, const char* png)
{
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    char* argv[] = {"gnuplot", (char*)script, NULL};
    pid_t pid;
    int rc = posix_spawnp(&pid, "gnuplot", &fa, NULL, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) {
        tp_cli_error("%s: cannot run gnuplot (%s; apt-get install gnuplot-nox); "
                     "the plot is not drawn",
                     png, strerror(rc));
        return 0;
    }
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (tp_interrupted())
        return 0;
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
        tp_cli_error("%s: gnuplot failed (exit %d)%s", png,
                     WIFEXITED(status) ? WEXITSTATUS(status) : -1,
                     WIFEXITED(status) && WEXITSTATUS(status) == 127
                         ? "; is it installed? apt-get install gnuplot-nox"
                         : "");
        return 0;
    }
    return 1;
}

/* The whole of a file of ours into memory (malloc'd); NULL on failure or when empty. */
static unsigned char* read_all(const char* path, size_t* size)
{
    FILE* f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char* buf = NULL;
    size_t cap = 0, n = 0;
    int failed = 0;
    for (;;) {
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
    failed |= ferror(f);
    fclose(f);
    if (failed || n == 0) {
        free(buf);
        return NULL;
    }
    *size = n;
    return buf;
}

unsigned char* tp_gnuplot_draw(const char* png, int width_px, int height_px,
                               tp_gnuplot_script_fn write, void* user, const char* cmd,
                               size_t* size)
{
    (void)cmd; /* messages name the command main() dispatched to (tp_cli_error) */
    char dir[4200], tmp_png[4300], script[4300];
    snprintf(dir, sizeof dir, "%s.tmpXXXXXX", png);
    tp_interrupt_hold(); /* a signal now only sets the flag: the folder is removed below */
    if (!mkdtemp(dir)) {
        tp_cli_error("%s: cannot write the plot: %s", png, strerror(errno));
        tp_interrupt_release();
        return NULL;
    }
    snprintf(tmp_png, sizeof tmp_png, "%s/plot.png", dir);
    snprintf(script, sizeof script, "%s/plot.gp", dir);
    FILE* f = fopen(script, "w");
    int ok = f != NULL;
    if (!f)
        tp_cli_error("%s: cannot write the plot: %s", png, strerror(errno));
    if (ok) {
        fprintf(f, "set terminal pngcairo size %d,%d font 'sans,10'\nset output ", width_px,
                height_px);
        tp_gnuplot_quoted(f, tmp_png);
        fputc('\n', f);
        write(f, user);
        int bad = ferror(f);
        if (fclose(f) != 0 || bad) {
            tp_cli_error("%s: cannot write the plot's script: %s", png,
                         bad ? "write error" : strerror(errno));
            ok = 0;
        } else {
            ok = !tp_interrupted() && run_gnuplot(script, png);
        }
    }
    unsigned char* bytes = ok && !tp_interrupted() ? read_all(tmp_png, size) : NULL;
    if (ok && !bytes && !tp_interrupted())
        tp_cli_error("%s: gnuplot wrote no plot", png);
    remove(script);
    remove(tmp_png);
    rmdir(dir);
    tp_interrupt_release();
    return bytes;
}

int tp_gnuplot_png(const char* png, int width_px, int height_px, tp_gnuplot_script_fn write,
                   void* user, const char* cmd)
{
    size_t size = 0;
    unsigned char* bytes = tp_gnuplot_draw(png, width_px, height_px, write, user, cmd, &size);
    int ok = bytes != NULL;
    if (ok) {
        tp_error err;
        if (tp_file_write(png, bytes, size, &err) != TP_OK) {
            if (!tp_interrupted())
                tp_cli_error("%s", err.message);
            ok = 0;
        }
    }
    free(bytes);
    if (ok)
        tp_cli_note("wrote %s", png);
    return ok;
}
