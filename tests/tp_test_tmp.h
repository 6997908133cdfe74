/*
 * tp_test_tmp.h - temporary directories for tests that run the terrapatch binary: each
 * make_tmp_dir() is a fresh empty directory under $TMPDIR (or /tmp), named TP_TMP_PREFIX
 * followed by random characters, removed with its contents at exit, so a test that fails part
 * way cleans up too. Define TP_TMP_PREFIX (e.g. "tp_view_") before including; include after
 * tp_test.h (uses ASSERT_TRUE and FAIL).
 */
#ifndef TP_TEST_TMP_H
#define TP_TEST_TMP_H

#include <dirent.h>
#include <errno.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

#define MAX_TMP_DIRS 16
static char tmp_dirs_[MAX_TMP_DIRS][512];
static int tmp_dir_count_;

static void remove_tree(const char* dir)
{
    DIR* d = opendir(dir);
    struct dirent* e;
    if (d) {
        while ((e = readdir(d)) != NULL) {
            char p[1024];
            struct stat st;
            if (!strcmp(e->d_name, ".") || !strcmp(e->d_name, ".."))
                continue;
            snprintf(p, sizeof p, "%s/%s", dir, e->d_name);
            if (lstat(p, &st) == 0 && S_ISDIR(st.st_mode))
                remove_tree(p);
            else
                unlink(p);
        }
        closedir(d);
    }
    rmdir(dir);
}

static void remove_tmp_dirs(void)
{
    while (tmp_dir_count_ > 0)
        remove_tree(tmp_dirs_[--tmp_dir_count_]);
}

/* A fresh empty directory (static storage; removed at exit). */
static const char* make_tmp_dir(void)
{
    const char* base = getenv("TMPDIR");
    char* d;
    if (!base || !*base)
        base = "/tmp";
    ASSERT_TRUE(tmp_dir_count_ < MAX_TMP_DIRS);
    d = tmp_dirs_[tmp_dir_count_];
    snprintf(d, sizeof tmp_dirs_[0], "%s/" TP_TMP_PREFIX "XXXXXX", base);
    if (!mkdtemp(d))
        FAIL("mkdtemp(%s): %s", d, strerror(errno));
    if (tmp_dir_count_++ == 0)
        atexit(remove_tmp_dirs);
    return d;
}

#endif
