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

#endif
