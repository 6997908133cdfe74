/* bench_static.c - `bench --static --max-error M1,M2,...` (see bench.h): the patch-based static
 * mesh of `export --max-error --mesh patches`, and the error-bounded TINs: terrapatch's
 * (tp_tin_build_tiled, as export builds it), and with --compare delatin's, martini's and
 * martini's at a lowered threshold (bench_npm.c), all on one grid, all measured by
 * tp_tin_measure. */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"
#include "clock.h"
#include "bench.h"
#include "cli.h"
#include "json.h"
#include "mesh_export.h"
#include "tin_export.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

typedef struct static_row {
    double bound_m;
    int refused; /* below the quantisation error */
    tp_export_result res;
    double select_s, mesh_s;
} static_row;

/* One error-bounded TIN: a mesher at one bound. */
typedef struct tin_row {
    const char* mesher;
    double bound_m, threshold_m; /* the bound asked; the threshold the mesher was given */
    size_t triangles, points;
    double time_s, tile_s;       /* median; tile_s: martini's createTile part of time_s */
    tp_tin_measure_result m;     /* the true error, tp_tin_measure */
    double peak_mib;             /* peak memory the meshing adds (see PEAK_NOTE) */
    double process_mib;          /* npm: the node process's whole peak RSS; -1: ours */
    int holds;                   /* m.max_error_m <= bound_m (+ float rounding) */
    int tried;                   /* martini lowered: thresholds measured */
} tin_row;

#define TIN_TOL_M 1e-6 /* float rounding of the interpolation, as the TIN tests allow */
#define MAX_TIN_ROWS (16 * 4)
#define PEAK_NOTE                                                                                  \
    "terrapatch tin: the peak RSS one build adds (a forked child per run, its peak reset through " \
    "/proc/self/clear_refs; max over the runs); npm meshers: the node process's peak RSS less its " \
    "RSS before the first run (runtime and grid)"

/* martini lowered: the thresholds tried, as fractions of the bound, largest first */
static const double lower_factors[] = {1, 0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1, 0.05, 0.02};

/* The grid the TINs run on. */
typedef struct tin_grid {
    const float* z;
    float* owned;
    int w, h, x0, y0; /* a window's place in the render grid (0, 0 for the whole grid) */
    int window;       /* 1: the --compare window */
    size_t voids;     /* NaN samples in it */
    unsigned flags;   /* TP_TIN_CUT_VOIDS where it has voids */
} tin_grid;

/* The largest (2^k+1)^2 square centred in the render grid with no void (martini's grid shape),
 * copied out; 0 after a message when there is none of 3x3 or more. */
static int find_window(const tp_render_grid* g, const char* dem, tin_grid* tg)
{
    int side = g->width < g->height ? g->width : g->height;
    int s = 3;
    while (2 * s - 1 <= side)
        s = 2 * s - 1; /* 2^(k+1) + 1 from 2^k + 1 */
    for (; s >= 3; s = (s + 1) / 2) {
        int x0 = (g->width - s) / 2, y0 = (g->height - s) / 2, clean = 1;
        for (int y = y0; y < y0 + s && clean; y++)
            for (int x = x0; x < x0 + s; x++)
                if (isnan(g->heights[(size_t)y * g->width + x])) {
                    clean = 0;
                    break;
                }
        if (!clean)
            continue;
        tg->owned = malloc((size_t)s * s * sizeof *tg->owned);
        if (!tg->owned) {
            tp_cli_error("out of memory (a %dx%d window)", s, s);
            return 0;
        }
        for (int y = 0; y < s; y++)
            memcpy(tg->owned + (size_t)y * s, g->heights + (size_t)(y0 + y) * g->width + x0,
                   (size_t)s * sizeof *tg->owned);
        *tg = (tin_grid){.z = tg->owned, .owned = tg->owned, .w = s, .h = s, .x0 = x0, .y0 = y0,
                         .window = 1};
        return 1;
    }
    tp_cli_error("--compare: %s: no (2^k+1)^2 square of 3x3 or more centred in the "
                 "%dx%d render grid is free of voids (martini needs one, and every mesher runs on "
                 "it)",
                 dem, g->width, g->height);
    return 0;
}

/* The process's peak RSS (MiB): VmHWM of /proc/self/status; -1 where it cannot be read. */
static double vm_hwm_mib(void)
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

typedef struct child_report {
    tp_status st;
    double time_s, peak_mib;
    size_t triangles, points;
    tp_tin_measure_result m;
    char message[512];
} child_report;

/* One build of ours in a forked child: its time, the peak RSS it adds, and (measure) its size
 * and true error. 0 after a message. */
static int tin_child(const tin_grid* tg, double e, int measure, child_report* out)
{
    int fd[2];
    if (pipe(fd) != 0) {
        tp_cli_error("pipe: %s", strerror(errno));
        return 0;
    }
    fflush(stdout);
    fflush(stderr);
    pid_t pid = fork();
    if (pid < 0) {
        tp_cli_error("fork: %s", strerror(errno));
        close(fd[0]);
        close(fd[1]);
        return 0;
    }
    if (pid == 0) {
        close(fd[0]);
        child_report r;
        memset(&r, 0, sizeof r);
#ifdef __GLIBC__
        malloc_trim(0); /* the parent's freed heap would otherwise be reused unseen */
#endif
        double before = -1;
        FILE* c = fopen("/proc/self/clear_refs", "w");
        int reset = c && fputs("5", c) >= 0;
        if (c && fclose(c) != 0)
            reset = 0;
        if (reset)
            before = vm_hwm_mib();
        tp_tin* t = NULL;
        tp_error err;
        memset(&err, 0, sizeof err);
        double t0 = tp_clock_s();
        /* as export builds it: tiles on every CPU */
        r.st = tp_tin_build_tiled(tg->z, (size_t)tg->w * tg->h, tg->w, tg->h, e, tg->flags,
                                  TP_TIN_EXPORT_TILE_CELLS, 0, &t, &err);
        r.time_s = tp_clock_s() - t0;
        double after = vm_hwm_mib();
        r.peak_mib = before >= 0 && after >= 0 ? after - before : -1;
        if (r.st == TP_OK) {
            r.triangles = t->triangle_count;
            r.points = t->vertex_count;
            if (measure)
                r.st = tp_tin_measure(tg->z, (size_t)tg->w * tg->h, tg->w, tg->h, t->vertices,
                                      t->vertex_count, t->triangles, t->triangle_count, &r.m,
                                      &err);
        }
        if (r.st != TP_OK)
            snprintf(r.message, sizeof r.message, "%s", err.message);
        tp_tin_destroy(t);
        _exit(write(fd[1], &r, sizeof r) == (ssize_t)sizeof r ? 0 : 1);
    }
    close(fd[1]);
    ssize_t got = 0;
    for (ssize_t k; got < (ssize_t)sizeof *out; got += k)
        if ((k = read(fd[0], (char*)out + got, sizeof *out - (size_t)got)) <= 0)
            break;
    close(fd[0]);
    int status = 0;
    while (waitpid(pid, &status, 0) < 0 && errno == EINTR)
        ;
    if (got != (ssize_t)sizeof *out) {
        tp_cli_error("the TIN build at %g m died (%s %d)", e,
                     WIFSIGNALED(status) ? "signal" : "exit",
                     WIFSIGNALED(status) ? WTERMSIG(status) : WEXITSTATUS(status));
        return 0;
    }
    if (out->st != TP_OK) {
        tp_cli_error("TIN at %g m: %s", e, out->message);
        return 0;
    }
    return 1;
}

/* Ours at bound e: runs builds (median time, max of the peaks), the first one measured. */
static int tin_ours(const tin_grid* tg, double e, int runs, tin_row* row)
{
    double* times = malloc((size_t)runs * sizeof *times);
    if (!times) {
        tp_cli_error("out of memory");
        return 0;
    }
    row->mesher = "terrapatch tin";
    row->bound_m = row->threshold_m = e;
    row->peak_mib = -1;
    row->process_mib = -1;
    for (int r = 0; r < runs; r++) {
        child_report rep;
        if (!tin_child(tg, e, r == 0, &rep)) {
            free(times);
            return 0;
        }
        if (r == 0) {
            row->triangles = rep.triangles;
            row->points = rep.points;
            row->m = rep.m;
        }
        times[r] = rep.time_s;
        row->peak_mib = rep.peak_mib > row->peak_mib ? rep.peak_mib : row->peak_mib;
    }
    row->time_s = tp_bench_median(times, runs);
    free(times);
    row->holds = row->m.max_error_m <= e + TIN_TOL_M;
    row->tried = 1;
    return 1;
}

/* An npm mesher at threshold t for bound e, measured. */
static int tin_npm(tp_npm* n, const char* mesher, const char* label, double e, double t, int runs,
                   tin_row* row)
{
    tp_npm_mesh m;
    tp_cli_note("--compare: %s, threshold %g m", mesher, t);
    if (!tp_npm_run(n, mesher, t, runs, &m))
        return 0;
    tp_error err;
    memset(&err, 0, sizeof err);
    memset(row, 0, sizeof *row);
    tp_status st = tp_tin_measure(n->z, (size_t)n->w * n->h, n->w, n->h, m.vertices,
                                  m.vertex_count, m.triangles, m.triangle_count, &row->m, &err);
    if (st != TP_OK) {
        tp_cli_error("--compare: the mesh of %s at %g m: %s", mesher, t, err.message);
        tp_npm_mesh_free(&m);
        return 0;
    }
    row->mesher = label;
    row->bound_m = e;
    row->threshold_m = t;
    row->triangles = m.triangle_count;
    row->points = m.vertex_count;
    row->time_s = m.median_ms / 1e3;
    row->tile_s = m.tile_ms / 1e3;
    row->peak_mib = m.peak_mib - m.base_mib;
    row->process_mib = m.peak_mib;
    row->holds = row->m.max_error_m <= e + TIN_TOL_M;
    row->tried = 1;
    tp_npm_mesh_free(&m);
    return 1;
}

/* martini lowered: the largest threshold e x lower_factors[i] whose true error is <= e
 * (at_e: martini's own row at threshold e, the first one tried). */
static int tin_martini_lowered(tp_npm* n, double e, int runs, const tin_row* at_e, tin_row* row)
{
    *row = *at_e;
    row->mesher = "martini lowered";
    int tried = 1;
    for (size_t i = 1; !row->holds && i < sizeof lower_factors / sizeof *lower_factors; i++) {
        if (!tin_npm(n, "martini", "martini lowered", e, e * lower_factors[i], runs, row))
            return 0;
        tried++;
    }
    row->tried = tried;
    return 1;
}

static void json_row_common(tp_json* j, const char* mesher, const char* grid)
{
    tp_json_member_string(j, "mesher", mesher);
    tp_json_member_string(j, "grid", grid);
}

static int write_json(const char* path, const char* dem, const tp_scene* sc, size_t full,
                      const static_row* r, int count, const tin_grid* tg, const tin_row* t,
                      int nt, int runs)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, path))
        return 0;
    tp_json j;
    tp_json_init(&j, file.f);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "dem", dem);
    tp_json_member_int(&j, "patch_size", sc->info.patch_size);
    tp_json_member_number(&j, "quantisation_error_m", sc->info.quant_max_error_m);
    tp_json_member_size(&j, "full_triangles", full);
    tp_json_member_int(&j, "render_width", sc->grid->width);
    tp_json_member_int(&j, "render_height", sc->grid->height);
    tp_json_key(&j, "tin_grid");
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "grid", tg->window ? "window" : "render");
    tp_json_member_int(&j, "x0", tg->x0);
    tp_json_member_int(&j, "y0", tg->y0);
    tp_json_member_int(&j, "width", tg->w);
    tp_json_member_int(&j, "height", tg->h);
    tp_json_member_size(&j, "void_samples", tg->voids);
    tp_json_member_bool(&j, "cut_voids", tg->flags != 0);
    tp_json_object_end(&j);
    tp_json_member_int(&j, "runs", runs);
    tp_json_member_string(&j, "peak_memory", PEAK_NOTE);
    tp_json_key(&j, "static");
    tp_json_array_begin(&j);
    for (int i = 0; i < count; i++) {
        tp_json_object_begin(&j);
        json_row_common(&j, "patches", "render");
        tp_json_member_number(&j, "max_error_m", r[i].bound_m);
        tp_json_member_bool(&j, "below_quantisation", r[i].refused);
        if (!r[i].refused) {
            tp_json_member_size(&j, "triangles", r[i].res.triangles);
            tp_json_member_size(&j, "points", r[i].res.points);
            tp_json_member_number(&j, "select_s", r[i].select_s);
            tp_json_member_number(&j, "mesh_s", r[i].mesh_s);
            tp_json_member_number(&j, "measured_max_error_m", r[i].res.max_error_m);
            tp_json_member_number(&j, "measured_rms_error_m", r[i].res.rms_error_m);
        }
        tp_json_object_end(&j);
    }
    for (int i = 0; i < nt; i++) {
        tp_json_object_begin(&j);
        json_row_common(&j, t[i].mesher, tg->window ? "window" : "render");
        tp_json_member_number(&j, "max_error_m", t[i].bound_m);
        tp_json_member_bool(&j, "below_quantisation", 0);
        tp_json_member_number(&j, "threshold_m", t[i].threshold_m);
        tp_json_member_size(&j, "triangles", t[i].triangles);
        tp_json_member_size(&j, "points", t[i].points);
        tp_json_member_number(&j, "time_s", t[i].time_s);
        if (t[i].tile_s > 0) {
            tp_json_member_number(&j, "create_tile_s", t[i].tile_s);
        }
        tp_json_member_int(&j, "runs", runs);
        tp_json_member_number(&j, "measured_max_error_m", t[i].m.max_error_m);
        tp_json_member_number(&j, "measured_rms_error_m", t[i].m.rms_error_m);
        tp_json_member_int(&j, "worst_x", t[i].m.worst_x);
        tp_json_member_int(&j, "worst_y", t[i].m.worst_y);
        tp_json_member_size(&j, "uncovered_samples", t[i].m.uncovered_samples);
        tp_json_member_bool(&j, "bound_holds", t[i].holds);
        tp_json_key(&j, "peak_mib");
        if (t[i].peak_mib >= 0)
            tp_json_number(&j, t[i].peak_mib);
        else
            tp_json_null(&j);
        if (t[i].process_mib >= 0) {
            tp_json_member_number(&j, "process_peak_mib", t[i].process_mib);
        }
        if (!strcmp(t[i].mesher, "martini lowered")) {
            tp_json_member_int(&j, "thresholds_tried", t[i].tried);
        }
        tp_json_object_end(&j);
    }
    tp_json_array_end(&j);
    tp_json_object_end(&j);
    return tp_atomic_commit(&file);
}

static int write_csv(const char* path, size_t full, const static_row* r, int count,
                     const tin_grid* tg, const tin_row* t, int nt, int runs)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, path))
        return 0;
    fprintf(file.f, "max_error_m,below_quantisation,triangles,full_triangles,points,select_s,"
                    "mesh_s,measured_max_error_m,measured_rms_error_m,mesher,grid,threshold_m,"
                    "time_s,runs,uncovered_samples,bound_holds,peak_mib,process_peak_mib\n");
    for (int i = 0; i < count; i++)
        if (r[i].refused) /* one row per bound; nothing measured */
            fprintf(file.f, "%g,1,,%zu,,,,,,patches,render,,,,,,,\n", r[i].bound_m, full);
        else
            fprintf(file.f, "%g,0,%zu,%zu,%zu,%.4f,%.4f,%.4f,%.4f,patches,render,,,,,,,\n",
                    r[i].bound_m, r[i].res.triangles, full, r[i].res.points, r[i].select_s,
                    r[i].mesh_s, r[i].res.max_error_m, r[i].res.rms_error_m);
    for (int i = 0; i < nt; i++) {
        fprintf(file.f, "%g,0,%zu,%zu,%zu,,,%.6f,%.6f,%s,%s,%.6g,%.6f,%d,%zu,%d,", t[i].bound_m,
                t[i].triangles, full, t[i].points, t[i].m.max_error_m, t[i].m.rms_error_m,
                t[i].mesher, tg->window ? "window" : "render", t[i].threshold_m, t[i].time_s,
                runs, t[i].m.uncovered_samples, t[i].holds);
        if (t[i].peak_mib >= 0)
            fprintf(file.f, "%.1f", t[i].peak_mib);
        fputc(',', file.f);
        if (t[i].process_mib >= 0)
            fprintf(file.f, "%.1f", t[i].process_mib);
        fputc('\n', file.f);
    }
    return tp_atomic_commit(&file);
}

static void print_tins(const char* dem, const tp_scene* sc, const tin_grid* tg, const tin_row* t,
                       int nt, int runs)
{
    if (tg->window)
        printf("%s: error-bounded TINs on the %dx%d window at (%d, %d) of the %dx%d render grid "
               "(the largest (2^k+1)^2 square centred in it with no void)\n",
               dem, tg->w, tg->h, tg->x0, tg->y0, sc->grid->width, sc->grid->height);
    else
        printf("%s: error-bounded TINs on the whole %dx%d render grid (%zu void samples%s)\n", dem,
               tg->w, tg->h, tg->voids, tg->flags ? ", void outlines cut" : "");
    char timed[64] = "one run";
    if (runs > 1)
        snprintf(timed, sizeof timed, "median of %d runs", runs);
    printf("time: %s; true error: tp_tin_measure at every valid sample; peak: %s\n", timed,
           PEAK_NOTE);
    if (tg->flags)
        printf("uncovered: valid samples that are the corner of no valid cell (four valid "
               "samples), which the full mesh does not draw either\n");
    printf("%8s %-16s %10s %10s %9s %9s %10s %10s %9s %9s\n", "bound m", "mesher", "thresh m",
           "triangles", "points", "time s", "max m", "rms m", "uncovered", "peak MiB");
    for (int i = 0; i < nt; i++) {
        char peak[32] = "n/a";
        if (t[i].peak_mib >= 0)
            snprintf(peak, sizeof peak, "%.1f", t[i].peak_mib);
        printf("%8g %-16s %10.4g %10zu %9zu %9.3f %10.4f %10.4f %9zu %9s%s\n", t[i].bound_m,
               t[i].mesher, t[i].threshold_m, t[i].triangles, t[i].points, t[i].time_s,
               t[i].m.max_error_m, t[i].m.rms_error_m, t[i].m.uncovered_samples, peak,
               t[i].holds ? "" : "  bound broken");
        if (!strcmp(t[i].mesher, "martini lowered") && !t[i].holds)
            printf("%8s %-16s no threshold down to %g x the bound holds it (%d tried)\n", "", "",
                   lower_factors[sizeof lower_factors / sizeof *lower_factors - 1], t[i].tried);
    }
}

int tp_bench_static(const tp_scene* sc, const bench_options* o)
{
    const char* dem = o->dem;
    const double* max_errors = o->max_errors;
    int count = o->max_error_count;
    static_row rows[16] = {{0}};
    int usable = 0;
    for (int i = 0; i < count; i++)
        usable += max_errors[i] >= sc->info.quant_max_error_m;
    if (!usable) { /* as export --max-error refuses it */
        tp_cli_error("every --max-error bound is below the quantisation error of "
                     "this DEM (%g m, half of its %g m height step at most)",
                     sc->info.quant_max_error_m, sc->info.height_step_m);
        return TP_EXIT_USAGE;
    }
    /* the TINs' grid, and the npm meshers first: a missing node fails before anything runs */
    tin_grid tg = {.z = sc->grid->heights, .w = sc->grid->width, .h = sc->grid->height};
    tp_npm npm;
    memset(&npm, 0, sizeof npm);
    if (o->compare) {
        if (!find_window(sc->grid, dem, &tg))
            return TP_EXIT_FAILURE;
        tp_cli_note("--compare: the %dx%d window at (%d, %d)", tg.w, tg.h, tg.x0, tg.y0);
        if (!tp_npm_open(&npm, tg.z, tg.w, tg.h)) {
            free(tg.owned);
            return TP_EXIT_FAILURE;
        }
    }
    for (size_t s = 0; s < (size_t)tg.w * tg.h; s++)
        tg.voids += isnan(tg.z[s]);
    tg.flags = tg.voids ? TP_TIN_CUT_VOIDS : 0;

    size_t full = tp_full_mesh_triangles(sc);
    tp_export_options eo = {.include_culled = 1};
    int code = TP_EXIT_OK;
    for (int i = 0; i < count && code == TP_EXIT_OK; i++) {
        static_row* r = &rows[i];
        r->bound_m = max_errors[i];
        if (r->bound_m < sc->info.quant_max_error_m) {
            r->refused = 1;
            continue;
        }
        tp_cli_note("--static: max error %g m (%d/%d)", r->bound_m, i + 1, count);
        tp_selection* sel = NULL;
        tp_error err;
        if (tp_selection_create(sc->terrain, &sel, &err) != TP_OK) {
            tp_cli_error("%s: %s", dem, err.message);
            code = TP_EXIT_FAILURE;
            break;
        }
        double t0 = tp_clock_s();
        tp_status st = tp_select_max_error(sc, sel, r->bound_m, &err);
        double t1 = tp_clock_s();
        if (st == TP_OK)
            st = tp_export_selection(sc, sel, &eo, NULL, &r->res, &err);
        if (st != TP_OK) {
            tp_cli_error("%s", err.message);
            code = TP_EXIT_FAILURE;
        }
        double t2 = tp_clock_s();
        r->select_s = t1 - t0;
        r->mesh_s = t2 - t1;
        tp_selection_destroy(sel);
    }
    /* the TINs, bound by bound (a refused bound is refused for them too, as by export) */
    static tin_row tins[MAX_TIN_ROWS];
    int nt = 0;
    for (int i = 0; i < count && code == TP_EXIT_OK; i++) {
        if (rows[i].refused)
            continue;
        double e = max_errors[i];
        tp_cli_note("--static: TIN at %g m (%d/%d)", e, i + 1, count);
        if (!tin_ours(&tg, e, o->runs, &tins[nt++])) {
            code = TP_EXIT_FAILURE;
            break;
        }
        if (!o->compare)
            continue;
        if (!tin_npm(&npm, "delatin", "delatin 0.2.0", e, e, o->runs, &tins[nt]) ||
            !tin_npm(&npm, "martini", "martini 0.2.0", e, e, o->runs, &tins[nt + 1]) ||
            !tin_martini_lowered(&npm, e, o->runs, &tins[nt + 1], &tins[nt + 2])) {
            code = TP_EXIT_FAILURE;
            break;
        }
        nt += 3;
    }
    if (o->compare)
        tp_npm_close(&npm);
    if (code != TP_EXIT_OK) {
        free(tg.owned);
        return code;
    }
    printf("%s: static meshes of 'export --max-error M' (every patch; nothing written); full mesh "
           "%zu triangles\n",
           dem, full);
    printf("%10s %10s %7s %9s %9s %9s %11s %11s\n", "bound m", "triangles", "% full", "points",
           "select s", "mesh s", "max m", "rms m");
    for (int i = 0; i < count; i++) {
        const static_row* r = &rows[i];
        if (r->refused)
            printf("%10g  below the quantisation error of this DEM (%g m): refused, as by export\n",
                   r->bound_m, sc->info.quant_max_error_m);
        else
            printf("%10g %10zu %7.2f %9zu %9.3f %9.3f %11.3f %11.3f\n", r->bound_m,
                   r->res.triangles, 100.0 * r->res.triangles / (double)(full ? full : 1),
                   r->res.points, r->select_s, r->mesh_s, r->res.max_error_m, r->res.rms_error_m);
    }
    print_tins(dem, sc, &tg, tins, nt, o->runs);
    if (o->json && !write_json(o->json, dem, sc, full, rows, count, &tg, tins, nt, o->runs))
        code = TP_EXIT_FAILURE;
    if (o->csv && !write_csv(o->csv, full, rows, count, &tg, tins, nt, o->runs))
        code = TP_EXIT_FAILURE;
    free(tg.owned);
    return code;
}
