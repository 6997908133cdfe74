/* bench_static.c - `bench --static --max-error M1,M2,...` (see bench.h). */
#define _POSIX_C_SOURCE 200809L
#include "atomic_file.h"
#include "bench.h"
#include "cli.h"
#include "json.h"
#include "mesh_export.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

typedef struct static_row {
    double bound_m;
    int refused; /* below the quantisation error */
    tp_export_result res;
    double select_s, mesh_s;
} static_row;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec / 1e9;
}

static int write_json(const char* path, const char* dem, const tp_scene* sc, size_t full,
                      const static_row* r, int count)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, path))
        return 0;
    tp_json j;
    tp_json_init(&j, file.f);
    tp_json_object_begin(&j);
    tp_json_key(&j, "dem");
    tp_json_string(&j, dem);
    tp_json_key(&j, "patch_size");
    tp_json_int(&j, sc->info.patch_size);
    tp_json_key(&j, "quantisation_error_m");
    tp_json_number(&j, sc->info.quant_max_error_m);
    tp_json_key(&j, "full_triangles");
    tp_json_size(&j, full);
    tp_json_key(&j, "static");
    tp_json_array_begin(&j);
    for (int i = 0; i < count; i++) {
        tp_json_object_begin(&j);
        tp_json_key(&j, "max_error_m");
        tp_json_number(&j, r[i].bound_m);
        tp_json_key(&j, "below_quantisation");
        tp_json_bool(&j, r[i].refused);
        if (!r[i].refused) {
            tp_json_key(&j, "triangles");
            tp_json_size(&j, r[i].res.triangles);
            tp_json_key(&j, "points");
            tp_json_size(&j, r[i].res.points);
            tp_json_key(&j, "select_s");
            tp_json_number(&j, r[i].select_s);
            tp_json_key(&j, "mesh_s");
            tp_json_number(&j, r[i].mesh_s);
            tp_json_key(&j, "measured_max_error_m");
            tp_json_number(&j, r[i].res.max_error_m);
            tp_json_key(&j, "measured_rms_error_m");
            tp_json_number(&j, r[i].res.rms_error_m);
        }
        tp_json_object_end(&j);
    }
    tp_json_array_end(&j);
    tp_json_object_end(&j);
    fputc('\n', file.f);
    return tp_atomic_commit(&file);
}

static int write_csv(const char* path, size_t full, const static_row* r, int count)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, path))
        return 0;
    fprintf(file.f, "max_error_m,below_quantisation,triangles,full_triangles,points,select_s,"
                    "mesh_s,measured_max_error_m,measured_rms_error_m\n");
    for (int i = 0; i < count; i++)
        if (r[i].refused) /* one row per bound; nothing measured */
            fprintf(file.f, "%g,1,,%zu,,,,,\n", r[i].bound_m, full);
        else
            fprintf(file.f, "%g,0,%zu,%zu,%zu,%.4f,%.4f,%.4f,%.4f\n", r[i].bound_m,
                    r[i].res.triangles, full, r[i].res.points, r[i].select_s, r[i].mesh_s,
                    r[i].res.max_error_m, r[i].res.rms_error_m);
    return tp_atomic_commit(&file);
}

int tp_bench_static(const tp_scene* sc, const char* dem, const double* max_errors, int count,
                    const char* json, const char* csv)
{
    static_row rows[16] = {{0}};
    int usable = 0;
    for (int i = 0; i < count; i++)
        usable += max_errors[i] >= sc->info.quant_max_error_m;
    if (!usable) { /* as export --max-error refuses it */
        fprintf(stderr,
                "terrapatch bench: every --max-error bound is below the quantisation error of "
                "this DEM (%g m, half of its %g m height step at most)\n",
                sc->info.quant_max_error_m, sc->info.height_step_m);
        return TP_EXIT_USAGE;
    }
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
        fprintf(stderr, "terrapatch: bench --static: max error %g m (%d/%d)\n", r->bound_m, i + 1,
                count);
        tp_selection* sel = NULL;
        tp_error err;
        if (tp_selection_create(sc->terrain, &sel, &err) != TP_OK) {
            fprintf(stderr, "terrapatch: %s: %s\n", dem, err.message);
            code = TP_EXIT_FAILURE;
            break;
        }
        double t0 = now_s();
        tp_status st = tp_select_max_error(sc, sel, r->bound_m, &err);
        double t1 = now_s();
        if (st == TP_OK)
            st = tp_export_selection(sc, sel, &eo, NULL, &r->res, &err);
        if (st != TP_OK) {
            fprintf(stderr, "terrapatch: %s\n", err.message);
            code = TP_EXIT_FAILURE;
        }
        double t2 = now_s();
        r->select_s = t1 - t0;
        r->mesh_s = t2 - t1;
        tp_selection_destroy(sel);
    }
    if (code != TP_EXIT_OK)
        return code;
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
    if (json && !write_json(json, dem, sc, full, rows, count))
        code = TP_EXIT_FAILURE;
    if (csv && !write_csv(csv, full, rows, count))
        code = TP_EXIT_FAILURE;
    return code;
}
