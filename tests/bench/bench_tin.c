/* bench_tin.c - the error-bounded TIN (tp_tin_build) at e = 1, 5, 20 m: triangles, time (median
 * of RUNS), true max error (a checker written here: every triangle rasterised with barycentric
 * weights, every valid sample compared), peak memory (a forked child runs one build: the peak
 * RSS it adds, VmHWM reset through /proc/self/clear_refs). docs/PERFORMANCE.md, "Error-bounded TIN".
 *
 *   tp_bench_tin DEM [RUNS [DELATIN_SCRIPT]]     (TP_BENCH_TIN_NO_4097=1: the DEM's grids only)
 *
 * Three grids: the DEM's render grid, the same with its voids filled (each void takes the
 * previous valid sample in its row, else the next: delatin has no voids), and a 4097 x 4097 grid
 * made of the render grid mirrored again and again (as bench_viewshed's 3601^2 one). With
 * DELATIN_SCRIPT (tools/tin_delatin.mjs, delatin from npm), delatin meshes the filled grids in
 * the same run: its triangles, median time and peak RSS, and its true error by the same checker.
 *
 * Beside each untiled row, the tiled build (tp_tin_build_tiled) with tiles of 256 and 512 cells
 * on 1 and 2 threads, on the same grid: triangles and median time as ratios to the untiled
 * build's, the runs of all five builds interleaved (run 1 of each, then run 2 of each, ...) so
 * that a change of the machine's load falls on all of them; the process's CPU time (all threads)
 * beside, which a loaded machine moves less. TP_BENCH_TIN_NO_TILED=1 leaves the tiled rows out. */
#define _GNU_SOURCE /* malloc_trim */
#include "bench_util.h"
#include "tp_io.h"

#include <malloc.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

static const double BOUNDS[3] = {1.0, 5.0, 20.0};

/* True max error of a triangulation (vertices as x, y, z floats) over the valid samples; also
 * counts samples no triangle covers. */
static double true_error(const float* vxyz, size_t nv, const uint32_t* tri, size_t nt,
                         const float* z, int w, int h, size_t* uncovered)
{
    (void)nv;
    uint8_t* cov = calloc((size_t)w * h, 1);
    double mx = 0.0;
    for (size_t i = 0; i < nt; ++i) {
        const float *a = vxyz + 3 * tri[3 * i], *b = vxyz + 3 * tri[3 * i + 1],
                    *c = vxyz + 3 * tri[3 * i + 2];
        const int64_t ax = (int64_t)a[0], ay = (int64_t)a[1], bx = (int64_t)b[0],
                      by = (int64_t)b[1], cx = (int64_t)c[0], cy = (int64_t)c[1];
        const int64_t area = (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
        if (area == 0)
            continue;
        const int64_t sg = area < 0 ? -1 : 1;
        int64_t x0 = ax < bx ? ax : bx, x1 = ax > bx ? ax : bx;
        x0 = cx < x0 ? cx : x0, x1 = cx > x1 ? cx : x1;
        int64_t y0 = ay < by ? ay : by, y1 = ay > by ? ay : by;
        y0 = cy < y0 ? cy : y0, y1 = cy > y1 ? cy : y1;
        for (int64_t y = y0; y <= y1; ++y)
            for (int64_t x = x0; x <= x1; ++x) {
                int64_t la = ((bx - x) * (cy - y) - (by - y) * (cx - x)) * sg;
                int64_t lb = ((x - ax) * (cy - ay) - (y - ay) * (cx - ax)) * sg;
                int64_t lc = ((bx - ax) * (y - ay) - (by - ay) * (x - ax)) * sg;
                if (la < 0 || lb < 0 || lc < 0)
                    continue;
                size_t s = (size_t)y * w + (size_t)x;
                cov[s] = 1;
                if (z[s] != z[s])
                    continue;
                double zi = (la * (double)a[2] + lb * (double)b[2] + lc * (double)c[2]) /
                            (double)(area * sg);
                double e = fabs(z[s] - zi);
                mx = e > mx ? e : mx;
            }
    }
    size_t u = 0;
    for (size_t s = 0; s < (size_t)w * h; ++s)
        u += !cov[s];
    *uncovered = u;
    free(cov);
    return mx;
}

/* The process's peak RSS (MiB): VmHWM of /proc/self/status; -1 where it cannot be read. */
static double peak_rss_mib(void)
{
    FILE* f = fopen("/proc/self/status", "r");
    char line[256];
    double kb = -1;
    while (f && fgets(line, sizeof line, f))
        if (strncmp(line, "VmHWM:", 6) == 0)
            kb = atof(line + 6);
    if (f)
        fclose(f);
    return kb < 0 ? -1 : kb / 1024.0;
}

/* Peak memory one build adds, in a forked child: its peak RSS is reset to its current RSS
 * (Linux: "5" written to /proc/self/clear_refs), then read after the build. MiB; -1 if not
 * measurable. */
/* A build: tile 0 is tp_tin_build, else tp_tin_build_tiled with that tile and thread count. */
typedef struct variant {
    int tile, threads;
} variant;

static tp_status build(const variant* v, const float* z, int w, int h, double e, tp_tin** t,
                       tp_error* err)
{
    if (!v || v->tile == 0)
        return tp_tin_build(z, (size_t)w * h, w, h, e, 0, t, err);
    return tp_tin_build_tiled(z, (size_t)w * h, w, h, e, 0, v->tile, v->threads, t, err);
}

static double build_peak_mib(const variant* var, const float* z, int w, int h, double e)
{
    int fd[2];
    if (pipe(fd) != 0)
        return -1;
    pid_t pid = fork();
    if (pid == 0) {
        close(fd[0]);
        double d = -1;
        malloc_trim(0); /* the parent's freed heap would otherwise be reused unseen */
        FILE* c = fopen("/proc/self/clear_refs", "w");
        if (c && fputs("5", c) >= 0 && fclose(c) == 0) {
            double before = peak_rss_mib();
            tp_tin* t = NULL;
            build(var, z, w, h, e, &t, NULL);
            d = peak_rss_mib() - before;
            tp_tin_destroy(t);
        }
        if (write(fd[1], &d, sizeof d) != (ssize_t)sizeof d)
            _exit(1);
        _exit(0);
    }
    close(fd[1]);
    double d = -1;
    if (read(fd[0], &d, sizeof d) != (ssize_t)sizeof d)
        d = -1;
    close(fd[0]);
    waitpid(pid, NULL, 0);
    return d;
}

/* delatin through node: writes the grid, runs the script, reads its meshes back. */
static void run_delatin(const char* script, const char* name, const float* z, int w, int h,
                        int runs)
{
    char grid[256], cmd[1024];
    snprintf(grid, sizeof grid, "/tmp/tp_bench_tin_%d.f32", (int)getpid());
    FILE* f = fopen(grid, "wb");
    if (!f || fwrite(z, sizeof(float), (size_t)w * h, f) != (size_t)w * h) {
        fprintf(stderr, "cannot write %s\n", grid);
        exit(1);
    }
    fclose(f);
    snprintf(cmd, sizeof cmd, "node %s %s %d %d %d", script, grid, w, h, runs);
    if (system(cmd) != 0) {
        fprintf(stderr, "%s failed\n", cmd);
        exit(1);
    }
    for (int k = 0; k < 3; ++k) {
        char mesh[300];
        snprintf(mesh, sizeof mesh, "%s.e%g.mesh", grid, BOUNDS[k]);
        FILE* m = fopen(mesh, "rb");
        uint32_t hdr[2];
        double stats[2]; /* median ms, peak RSS MiB */
        if (!m || fread(stats, sizeof(double), 2, m) != 2 || fread(hdr, 4, 2, m) != 2) {
            fprintf(stderr, "cannot read %s\n", mesh);
            exit(1);
        }
        size_t nv = hdr[0], nt = hdr[1];
        uint32_t* c = malloc(sizeof(uint32_t) * 2 * nv);
        uint32_t* t = malloc(sizeof(uint32_t) * 3 * nt);
        float* v = malloc(sizeof(float) * 3 * nv);
        if (fread(c, 4, 2 * nv, m) != 2 * nv || fread(t, 4, 3 * nt, m) != 3 * nt) {
            fprintf(stderr, "short %s\n", mesh);
            exit(1);
        }
        fclose(m);
        remove(mesh);
        for (size_t i = 0; i < nv; ++i) {
            v[3 * i] = (float)c[2 * i];
            v[3 * i + 1] = (float)c[2 * i + 1];
            v[3 * i + 2] = z[(size_t)c[2 * i + 1] * w + c[2 * i]];
        }
        size_t unc = 0;
        double te = true_error(v, nv, t, nt, z, w, h, &unc);
        printf("| %-22s | delatin 0.2.0 | %4g | %9zu | %9.1f | %8.4f | %7.0f (node RSS) |%s\n", name,
               BOUNDS[k], nt, stats[0], te, stats[1],
               unc ? " UNCOVERED SAMPLES" : "");
        free(c);
        free(t);
        free(v);
    }
    remove(grid);
}

/* The process's CPU time (ms), all threads. */
static double cpu_ms(void)
{
    struct timespec t;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
    return (double)t.tv_sec * 1e3 + (double)t.tv_nsec / 1e6;
}

static const variant VARIANTS[5] = {{0, 1}, {256, 1}, {256, 2}, {512, 1}, {512, 2}};

static void run(const char* name, const float* z, int w, int h, int runs, const char* delatin)
{
    const int nvar = getenv("TP_BENCH_TIN_NO_TILED") ? 1 : 5;
    double* ms = malloc(sizeof(double) * runs * nvar);
    double* cpu = malloc(sizeof(double) * runs * nvar);
    for (int k = 0; k < 3; ++k) {
        size_t tris[5] = {0};
        double te[5] = {0}, per_sample[5] = {0};
        size_t unc[5] = {0};
        for (int r = 0; r < runs; ++r)
            for (int v = 0; v < nvar; ++v) {
                tp_tin* t = NULL;
                tp_error err;
                double t0 = bench_now_ms(), c0 = cpu_ms();
                if (build(&VARIANTS[v], z, w, h, BOUNDS[k], &t, &err) != TP_OK) {
                    fprintf(stderr, "%s\n", err.message);
                    exit(1);
                }
                ms[v * runs + r] = bench_now_ms() - t0;
                cpu[v * runs + r] = cpu_ms() - c0;
                if (r == 0) {
                    tris[v] = t->triangle_count;
                    per_sample[v] = (double)t->samples_rasterised / ((double)w * h);
                    te[v] = true_error(t->vertices, t->vertex_count, t->triangles,
                                       t->triangle_count, z, w, h, &unc[v]);
                }
                tp_tin_destroy(t);
            }
        const double base_ms = bench_median(ms, runs), base_cpu = bench_median(cpu, runs);
        for (int v = 0; v < nvar; ++v) {
            double med = bench_median(ms + v * runs, runs);
            double med_cpu = bench_median(cpu + v * runs, runs);
            double mib = build_peak_mib(&VARIANTS[v], z, w, h, BOUNDS[k]);
            char mesher[40];
            if (v == 0)
                snprintf(mesher, sizeof mesher, "terrapatch   ");
            else
                snprintf(mesher, sizeof mesher, "tiled %d, %d thr", VARIANTS[v].tile,
                         VARIANTS[v].threads);
            printf("| %-22s | %s | %4g | %9zu | %9.1f | %8.4f | %7.1f (build)    |%s "
                   "(%.2f samples rasterised per sample)",
                   v == 0 ? name : "", mesher, BOUNDS[k], tris[v], med, te[v], mib,
                   unc[v] ? " UNCOVERED SAMPLES" : "", per_sample[v]);
            printf(" cpu %.0f ms", med_cpu);
            if (v > 0)
                printf("; triangles %.4fx, time %.2fx, cpu %.2fx untiled",
                       (double)tris[v] / (double)tris[0], med / base_ms, med_cpu / base_cpu);
            printf("\n");
        }
        fflush(stdout);
    }
    free(ms);
    free(cpu);
    if (delatin)
        run_delatin(delatin, name, z, w, h, runs);
}

/* voids filled from the previous valid sample of the row, else the next, else the row above */
static float* filled_copy(const float* z, int w, int h)
{
    float* f = malloc(sizeof(float) * (size_t)w * h);
    memcpy(f, z, sizeof(float) * (size_t)w * h);
    for (int y = 0; y < h; ++y) {
        float* row = f + (size_t)y * w;
        float last = NAN;
        for (int x = 0; x < w; ++x)
            row[x] = row[x] == row[x] ? (last = row[x]) : last;
        last = NAN;
        for (int x = w - 1; x >= 0; --x)
            row[x] = row[x] == row[x] ? (last = row[x]) : last;
        for (int x = 0; x < w; ++x)
            if (row[x] != row[x])
                row[x] = y > 0 ? row[x - w] : 0.0f;
    }
    return f;
}

int main(int argc, char** argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: tp_bench_tin DEM [RUNS [DELATIN_SCRIPT]]\n");
        return 2;
    }
    const int runs = argc > 2 ? atoi(argv[2]) : 3;
    const char* delatin = argc > 3 ? argv[3] : NULL;
    tp_error err;
    tp_dem* dem = NULL;
    tp_render_grid* g = NULL;
    if (tp_dem_read(argv[1], &dem, &err) != TP_OK ||
        tp_render_grid_build(dem, NULL, &g, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    tp_dem_destroy(dem);
    size_t voids = 0;
    for (size_t i = 0; i < (size_t)g->width * g->height; ++i)
        voids += g->heights[i] != g->heights[i];
    printf("%s: render grid %dx%d (%zu voids), medians of %d\n\n", argv[1], g->width, g->height,
           voids, runs);
    printf("| grid | mesher | e (m) | triangles | time (ms) | true max error (m) | peak memory "
           "(MiB) |\n|---|---|---|---|---|---|---|\n");
    char name[64];
    snprintf(name, sizeof name, "render %dx%d", g->width, g->height);
    run(name, g->heights, g->width, g->height, runs, NULL);
    float* f = filled_copy(g->heights, g->width, g->height);
    snprintf(name, sizeof name, "filled %dx%d", g->width, g->height);
    run(name, f, g->width, g->height, runs, delatin);
    free(f);

    if (getenv("TP_BENCH_TIN_NO_4097")) { /* quick A/B runs on the DEM's grids only */
        tp_render_grid_destroy(g);
        return 0;
    }
    enum { S = 4097 };
    float* big = malloc(sizeof(float) * S * S);
    for (int y = 0; y < S; ++y) {
        int p = 2 * (g->height - 1), j = y % p;
        j = j < g->height ? j : p - j;
        for (int x = 0; x < S; ++x) {
            int q = 2 * (g->width - 1), i = x % q;
            i = i < g->width ? i : q - i;
            big[(size_t)y * S + x] = g->heights[(size_t)j * g->width + i];
        }
    }
    float* bigf = filled_copy(big, S, S);
    free(big);
    run("4097^2 mirrored, filled", bigf, S, S, runs, delatin);
    free(bigf);
    tp_render_grid_destroy(g);
    return 0;
}
