/*
 * tp_test_child.h - the environment for a terrapatch child process run by a test: ours, with
 * LeakSanitizer off in the child. Under TP_SANITIZE the terrapatch binary is instrumented too,
 * and eglTerminate unloads Mesa's driver (swrast_dri.so), after which LSan reports the driver's
 * still-referenced allocations (a few hundred bytes, "<unknown module>") as leaks.
 * AddressSanitizer's other checks stay on in the child.
 */
#ifndef TP_TEST_CHILD_H
#define TP_TEST_CHILD_H

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

extern char** environ;

/* envp for posix_spawn/execve; asan_buf (cap bytes) holds the new ASAN_OPTIONS entry and must
 * outlive the spawn. The array is static: one child environment at a time. */
static char** tp_test_child_environment(char* asan_buf, size_t cap)
{
    static char* envp[512];
    size_t n = 0, i;
    const char* asan = getenv("ASAN_OPTIONS");
    snprintf(asan_buf, cap, "ASAN_OPTIONS=%s%sdetect_leaks=0", asan ? asan : "",
             asan && *asan ? ":" : "");
    for (i = 0; environ[i] && n + 2 < sizeof envp / sizeof envp[0]; ++i)
        if (strncmp(environ[i], "ASAN_OPTIONS=", 13) != 0)
            envp[n++] = environ[i];
    envp[n++] = asan_buf;
    envp[n] = NULL;
    return envp;
}

#ifdef TP_TEST_H
#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

/* Reads the file at path (at most cap - 1 bytes, NUL-terminated) into buf and removes it. */
static inline void tp_test_take_file(const char* path, char* buf, size_t cap)
{
    FILE* f = fopen(path, "r");
    size_t got = f ? fread(buf, 1, cap - 1, f) : 0;
    buf[got] = '\0';
    if (f)
        fclose(f);
    remove(path);
}

/* Runs `terrapatch CMD args...` (args NULL-terminated; the binary from $TP_TERRAPATCH, stdin
 * /dev/null) in the child environment above; returns the exit status (128 + signal when
 * killed), its stdout in out (NULL: to /dev/null) and its stderr in err. Needs tp_test.h
 * included first (SKIP, ASSERT). */
static inline int tp_test_run_terrapatch_out(const char* cmd, const char* const* args, char* out,
                                             size_t out_cap, char* err, size_t err_cap)
{
    const char* exe = getenv("TP_TERRAPATCH");
    if (!exe || access(exe, X_OK) != 0)
        SKIP("TP_TERRAPATCH not set: the terrapatch binary is not built");
    const char* argv[64];
    int n = 0;
    argv[n++] = exe;
    argv[n++] = cmd;
    for (int i = 0; args[i] && n < 62; i++)
        argv[n++] = args[i];
    argv[n] = NULL;
    char err_path[] = "/tmp/tp_test_child_errXXXXXX";
    int fd = mkstemp(err_path);
    ASSERT_TRUE(fd >= 0);
    close(fd);
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    char out_path[] = "/tmp/tp_test_child_outXXXXXX";
    if (out) {
        int ofd = mkstemp(out_path);
        ASSERT_TRUE(ofd >= 0);
        close(ofd);
    }
    posix_spawn_file_actions_addopen(&fa, 1, out ? out_path : "/dev/null", O_WRONLY | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err_path, O_WRONLY | O_TRUNC, 0644);
    pid_t pid;
    static char asan[512];
    char** envp = tp_test_child_environment(asan, sizeof asan);
    int rc = posix_spawn(&pid, exe, &fa, NULL, (char* const*)argv, envp);
    posix_spawn_file_actions_destroy(&fa);
    ASSERT_EQ_INT(0, rc);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            FAIL("waitpid: %s", strerror(errno));
    tp_test_take_file(err_path, err, err_cap);
    if (out)
        tp_test_take_file(out_path, out, out_cap);
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/* tp_test_run_terrapatch_out with stdout to /dev/null. */
static inline int tp_test_run_terrapatch(const char* cmd, const char* const* args, char* err,
                                         size_t err_cap)
{
    return tp_test_run_terrapatch_out(cmd, args, NULL, 0, err, err_cap);
}

/* ---- what the tests of the planner commands (point, los, viewshed, profile) share ---- */

#include <dirent.h>
#include <math.h>

/* One folder for the test process, made on first use: /tmp/tp_test_NAMEXXXXXX (mkdtemp). */
static inline const char* tp_test_child_dir(const char* name)
{
    static char dir[64];
    if (!dir[0]) {
        snprintf(dir, sizeof dir, "/tmp/tp_test_%sXXXXXX", name);
        if (!mkdtemp(dir))
            FAIL("mkdtemp failed");
    }
    return dir;
}

/* Reads a whole small file into buf (at most cap - 1 bytes, NUL-terminated); fails the test
 * when it cannot be opened. */
static inline void tp_test_read_text(const char* path, char* buf, size_t cap)
{
    FILE* f = fopen(path, "r");
    if (!f)
        FAIL("cannot open %s", path);
    size_t got = fread(buf, 1, cap - 1, f);
    buf[got] = '\0';
    fclose(f);
}

/* The number after the first "key": in JSON text, at or after the first from (NULL: the
 * start); NaN for null. Fails the test when from or the key is not there. */
static inline double tp_test_json_number_after(const char* json, const char* from,
                                               const char* key)
{
    const char* start = from ? strstr(json, from) : json;
    if (!start)
        FAIL("no %s in %s", from, json);
    char pat[64];
    snprintf(pat, sizeof pat, "\"%s\": ", key);
    const char* p = strstr(start, pat);
    if (!p)
        FAIL("no key %s in %s", key, json);
    p += strlen(pat);
    if (!strncmp(p, "null", 4))
        return NAN;
    return strtod(p, NULL);
}

/* 1 when no file in dir has a name starting with prefix. */
static inline int tp_test_nothing_named(const char* dir, const char* prefix)
{
    DIR* d = opendir(dir);
    ASSERT_TRUE(d != NULL);
    int found = 0;
    for (struct dirent* e; (e = readdir(d));)
        found |= !strncmp(e->d_name, prefix, strlen(prefix));
    closedir(d);
    return !found;
}
#endif

#endif
