/* fuzz_util.c - see fuzz_util.h. */
#define _POSIX_C_SOURCE 200809L /* mkdtemp */

#include "fuzz_util.h"

#include <dirent.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static char folder[512];

/* Removes the private folder and what the readers left in it (flat: nothing makes subfolders). */
static void remove_folder(void)
{
    DIR* d = opendir(folder);
    if (d) {
        struct dirent* e;
        char path[1024];
        while ((e = readdir(d)) != NULL) {
            if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
                continue;
            snprintf(path, sizeof path, "%s/%s", folder, e->d_name);
            unlink(path);
        }
        closedir(d);
    }
    rmdir(folder);
}

const char* tp_fuzz_write_file(const char* name, const uint8_t* data, size_t size)
{
    static char path[1024];
    if (!folder[0]) {
        const char* tmp = getenv("TMPDIR");
        snprintf(folder, sizeof folder, "%s/tp_fuzz_XXXXXX", tmp && *tmp ? tmp : "/tmp");
        if (!mkdtemp(folder)) {
            perror("tp_fuzz_write_file: mkdtemp");
            abort();
        }
        atexit(remove_folder);
    }
    snprintf(path, sizeof path, "%s/%s", folder, name);
    FILE* f = fopen(path, "wb");
    if (!f)
        return NULL;
    size_t wrote = size ? fwrite(data, 1, size, f) : 0;
    if (fclose(f) != 0 || wrote != size)
        return NULL;
    return path;
}
