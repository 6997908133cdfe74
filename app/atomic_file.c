/* atomic_file.c - see atomic_file.h. */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"

#include <errno.h>
#include <string.h>
#include <unistd.h>

int tp_atomic_open(tp_atomic_file* a, const char* path)
{
    a->path = path;
    snprintf(a->tmp, sizeof a->tmp, "%s.tmp%ld", path, (long)getpid());
    a->f = fopen(a->tmp, "w");
    if (!a->f)
        fprintf(stderr, "terrapatch: %s: cannot write: %s\n", path, strerror(errno));
    return a->f != NULL;
}

int tp_atomic_commit(tp_atomic_file* a)
{
    int ok = !ferror(a->f);
    ok &= fclose(a->f) == 0;
    if (!ok || rename(a->tmp, a->path) != 0) {
        fprintf(stderr, "terrapatch: %s: cannot write: %s\n", a->path, strerror(errno));
        remove(a->tmp);
        return 0;
    }
    return 1;
}

int tp_atomic_check_dir(const char* path)
{
    char dir[4096];
    const char* slash = strrchr(path, '/');
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if (slash == path)
        snprintf(dir, sizeof dir, "/");
    else
        snprintf(dir, sizeof dir, "%.*s", (int)(slash - path), path);
    if (access(dir, W_OK | X_OK) != 0) {
        fprintf(stderr, "terrapatch: %s: cannot write: %s: %s\n", path, dir, strerror(errno));
        return 0;
    }
    return 1;
}
