/* bench_npm.c - the npm meshers of `bench --static --compare` (see bench.h): the height grid
 * written for them, tools/tin_compare.sh run once to install them and once per mesher and
 * threshold (its stdout sent to stderr: the bench's table owns stdout), their meshes read back. */
#define _POSIX_C_SOURCE 200809L
#include "bench.h"

#include "cli.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

#ifndef TP_TOOLS_DIR
#define TP_TOOLS_DIR "tools"
#endif

/* Runs /bin/sh SCRIPT args... with stdout on stderr; returns its exit status (128 + the signal
 * that killed it), or -1 when it could not be started. */
static int run_script(const char* script, char* const* args)
{
    char* argv[16];
    int n = 0;
    argv[n++] = "sh";
    argv[n++] = (char*)script;
    for (int i = 0; args[i] && n < 15; i++)
        argv[n++] = args[i];
    argv[n] = NULL;
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0)
        return -1;
    if (pid == 0) {
        dup2(2, 1);
        execv("/bin/sh", argv);
        _exit(127);
    }
    int status;
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            return -1;
    return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

int tp_npm_open(tp_npm* n, const float* z, int w, int h)
{
    memset(n, 0, sizeof *n);
    n->z = z;
    n->w = w;
    n->h = h;
    const char* env = getenv("TP_TIN_COMPARE");
    snprintf(n->script, sizeof n->script, "%s", env && *env ? env : TP_TOOLS_DIR "/tin_compare.sh");
    if (access(n->script, R_OK) != 0) {
        tp_cli_error("--compare: cannot read %s (%s): set TP_TIN_COMPARE to "
                     "terrapatch's tools/tin_compare.sh",
                     n->script, strerror(errno));
        return 0;
    }
    tp_cli_note("--compare: %s install", n->script);
    char* install[] = {"install", NULL};
    int rc = run_script(n->script, install);
    if (rc != 0) {
        tp_cli_error("--compare: %s install failed (exit %d; the reason is above): "
                     "no comparison without delatin and martini",
                     n->script, rc);
        return 0;
    }
    const char* tmp = getenv("TMPDIR");
    snprintf(n->dir, sizeof n->dir, "%s/terrapatch-compare-XXXXXX", tmp && *tmp ? tmp : "/tmp");
    if (!mkdtemp(n->dir)) {
        tp_cli_error("--compare: cannot create %s: %s", n->dir, strerror(errno));
        n->dir[0] = 0;
        return 0;
    }
    snprintf(n->grid, sizeof n->grid, "%s/grid.f32", n->dir);
    FILE* f = fopen(n->grid, "wb");
    size_t count = (size_t)w * h;
    if (!f || fwrite(z, sizeof *z, count, f) != count || fclose(f) != 0) {
        tp_cli_error("--compare: cannot write %s: %s", n->grid, strerror(errno));
        tp_npm_close(n);
        return 0;
    }
    return 1;
}

int tp_npm_run(tp_npm* n, const char* mesher, double threshold_m, int runs, tp_npm_mesh* out)
{
    memset(out, 0, sizeof *out);
    char mesh[4200], ws[32], hs[32], rs[32], es[64];
    snprintf(mesh, sizeof mesh, "%s/%s.mesh", n->dir, mesher);
    snprintf(ws, sizeof ws, "%d", n->w);
    snprintf(hs, sizeof hs, "%d", n->h);
    snprintf(rs, sizeof rs, "%d", runs);
    snprintf(es, sizeof es, "%.17g", threshold_m);
    char* args[] = {"run", (char*)mesher, n->grid, ws, hs, rs, mesh, es, NULL};
    int rc = run_script(n->script, args);
    if (rc != 0) {
        tp_cli_error("--compare: %s at %g m failed (exit %d%s; see above): no "
                     "rows",
                     mesher, threshold_m, rc,
                     rc > 128 ? ", killed by a signal: out of memory? (TP_NODE_HEAP_MB sets node's "
                                "heap limit)"
                              : "");
        return 0;
    }
    FILE* f = fopen(mesh, "rb");
    double head[6];
    uint32_t counts[2];
    int ok = f && fread(head, sizeof head, 1, f) == 1 && fread(counts, sizeof counts, 1, f) == 1;
    uint32_t* xy = NULL;
    if (ok) {
        out->vertex_count = counts[0];
        out->triangle_count = counts[1];
        xy = malloc(2 * sizeof *xy * (out->vertex_count + 1));
        out->vertices = malloc(3 * sizeof *out->vertices * (out->vertex_count + 1));
        out->triangles = malloc(3 * sizeof *out->triangles * (out->triangle_count + 1));
        ok = xy && out->vertices && out->triangles &&
             fread(xy, 2 * sizeof *xy, out->vertex_count, f) == out->vertex_count &&
             fread(out->triangles, 3 * sizeof *out->triangles, out->triangle_count, f) ==
                 out->triangle_count;
    }
    if (f)
        fclose(f);
    unlink(mesh);
    for (size_t i = 0; ok && i < out->vertex_count; i++) {
        uint32_t x = xy[2 * i], y = xy[2 * i + 1];
        if (x >= (uint32_t)n->w || y >= (uint32_t)n->h) {
            ok = 0;
            break;
        }
        out->vertices[3 * i] = (float)x;
        out->vertices[3 * i + 1] = (float)y;
        out->vertices[3 * i + 2] = n->z[(size_t)y * n->w + x];
    }
    free(xy);
    if (!ok) {
        tp_cli_error("--compare: %s: a short or malformed mesh from %s", mesh, mesher);
        tp_npm_mesh_free(out);
        return 0;
    }
    out->median_ms = head[0];
    out->tile_ms = head[1];
    out->peak_mib = head[2];
    out->base_mib = head[3];
    return 1;
}

void tp_npm_mesh_free(tp_npm_mesh* m)
{
    free(m->vertices);
    free(m->triangles);
    memset(m, 0, sizeof *m);
}

void tp_npm_close(tp_npm* n)
{
    if (n->grid[0])
        unlink(n->grid);
    if (n->dir[0])
        rmdir(n->dir);
    n->grid[0] = n->dir[0] = 0;
}
