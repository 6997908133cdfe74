/* atomic_file.c - see atomic_file.h. */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"

#include "cli.h"
#include "tp_io.h"

#include <errno.h>
#include <stdlib.h>
#include <string.h>

int tp_atomic_open(tp_atomic_file* a, const char* path)
{
    a->path = path;
    a->buf = NULL;
    a->size = 0;
    if (!strcmp(path, "-")) {
        a->f = stdout;
        return 1;
    }
    a->f = open_memstream(&a->buf, &a->size);
    if (!a->f)
        tp_cli_error("%s: cannot write: %s", path, strerror(errno));
    return a->f != NULL;
}

/* Closes the stream and hands what was printed to write (set NULL: tp_file_write, else
 * tp_file_set_add to set); frees it. 1, or 0 after a line. */
static int hand_over(tp_atomic_file* a, tp_file_set* set)
{
    if (a->f == stdout) /* "-" */
        return fflush(stdout) == 0;
    int ok = !ferror(a->f);
    ok &= fclose(a->f) == 0; /* sets buf and size */
    tp_error err;
    if (!ok) {
        tp_cli_error("%s: cannot write: out of memory", a->path);
    } else if ((set ? tp_file_set_add(set, a->path, a->buf, a->size, &err)
                    : tp_file_write(a->path, a->buf, a->size, &err)) != TP_OK) {
        if (!tp_interrupted()) /* else main says "interrupted" */
            tp_cli_error("%s", err.message);
        ok = 0;
    }
    free(a->buf);
    a->buf = NULL;
    return ok;
}

int tp_atomic_commit(tp_atomic_file* a)
{
    return hand_over(a, NULL);
}

int tp_atomic_add_to_set(tp_atomic_file* a, tp_file_set* set)
{
    return hand_over(a, set);
}

int tp_atomic_check_dir(const char* path)
{
    tp_error err;
    if (tp_output_check(path, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return 0;
    }
    return 1;
}
