/* bench_report.c - what the benchmark writes: the table on stdout, the JSON summary, the CSV
 * of frames or of a sweep's configurations (see bench.h). */
#include "bench.h"

#include "atomic_file.h"
#include "json.h"

#include <stdio.h>

static const char* mode_name(tp_lod_mode m)
{
    return m == TP_LOD_FULL ? "full" : m == TP_LOD_DISTANCE ? "distance" : "error";
}

static void json_config(tp_json* j, const config_result* c)
{
#define tp_json_member_number(j, k, v) (tp_json_member_number(j, k, v))
    tp_json_member_number(j, "fps_median", c->fps_median);
    tp_json_member_number(j, "frame_ms_median", c->frame_ms);
    tp_json_member_number(j, "cpu_ms_median", c->cpu_ms);
    tp_json_member_number(j, "draw_ms_median", c->draw_ms);
    tp_json_member_number(j, "triangles_median", c->triangles);
    tp_json_member_number(j, "draw_calls_median", c->draw_calls);
    tp_json_member_number(j, "uploads_median", c->uploads);
    tp_json_member_number(j, "gpu_bytes", (double)c->gpu_bytes);
    if (c->stitch_add) {
        tp_json_member_number(j, "draws_median", c->draws);
        tp_json_member_number(j, "index_gpu_bytes", (double)c->index_gpu_bytes);
        tp_json_member_number(j, "index_cpu_bytes", (double)c->index_cpu_bytes);
    }
    tp_json_member_number(j, "max_screen_error_px", c->max_px);
    tp_json_member_number(j, "rms_screen_error_px", c->rms_px);
    tp_json_member_number(j, "max_vertical_error_m", c->max_m);
    tp_json_member_number(j, "rms_vertical_error_m", c->rms_m);
    if (c->pgm_cols)
        tp_json_member_number(j, "uncovered_share",
                              c->uncovered_share); /* left out of PGM's error */
    if (c->store) /* drawn nodes that drew a TIN (0 with lattice nodes) */
        tp_json_member_number(j, "tin_share", c->tin_share);
    if (c->lod.mode == TP_LOD_ERROR && c->oracle_triangles > 0) {
        tp_json_member_number(j, "oracle_triangles_median", c->oracle_triangles);
        tp_json_member_number(j, "oracle_coarser_patches_median", c->oracle_patches);
    }
}

/* The renderer of a configuration, then its LoD parameters (a persistent grid has none). */
static void json_lod(tp_json* j, const config_result* c)
{
    const tp_lod_params* lp = &c->lod;
    tp_json_key(j, "terrain_renderer"); /* "renderer" is the GL renderer's name */
    tp_json_string(j, c->store ? "store" : c->pgm_cols ? "pgm" : "patches");
    tp_json_member_string(j, "family", tp_bench_family_name(tp_bench_family_of(c)));
    if (c->store) /* the DEM's store through its cut (bench_sweep_store.c) */
        tp_json_member_string(j, "mesh", c->store == 2 ? "tin" : "lattice");
    if (c->pgm_cols) {
        char grid[32];
        snprintf(grid, sizeof grid, "%dx%d", c->pgm_cols, c->pgm_rows);
        tp_json_member_string(j, "pgm_grid", grid);
        tp_json_member_int(j, "pgm_cols", c->pgm_cols);
        tp_json_member_int(j, "pgm_rows", c->pgm_rows);
        tp_json_member_string(j, "lod_mode", "pgm");
        return;
    }
    tp_json_member_string(j, "stitch", c->stitch_add ? "add" : "move");
    if (c->stitch_add) {
        tp_json_member_string(j, "stitch_add_draw", c->stitch_add_five ? "five" : "sets");
    }
    tp_json_member_string(j, "lod_mode", mode_name(lp->mode));
    if (lp->mode == TP_LOD_ERROR) {
        tp_json_member_number(j, "tau_px", lp->tau_px);
    } else if (lp->mode == TP_LOD_DISTANCE) {
        tp_json_member_number(j, "mindist_m", lp->mindist_m);
        tp_json_member_number(j, "maxdist_m", lp->maxdist_m);
        tp_json_member_number(j, "exp", lp->exponent);
    }
}

int tp_bench_write_json(const bench_run* b, const char* renderer_name, const config_result* c, int nc,
                      const config_result* best)
{
    const bench_options* o = b->o;
    tp_atomic_file file;
    if (!tp_atomic_open(&file, o->json))
        return 0;
    FILE* f = file.f;
    tp_json j;
    tp_json_init(&j, f);
    const config_result* full = &c[0];
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "dem", o->dem);
    char size[32];
    snprintf(size, sizeof size, "%dx%d", o->vs.w, o->vs.h);
    tp_json_member_string(&j, "size", size);
    tp_json_member_string(&j, "path",
                          o->path_file       ? o->path_file
                          : o->vs.has_camera ? "fixed"
                                             : o->path_name);
    tp_json_member_number(&j, "speed_mps", b->lead_da > 0 ? o->speed_mps : 0);
    tp_json_member_number(&j, "frames", b->frames);
    tp_json_member_number(&j, "patches", b->sc->info.patch_count);
    tp_json_member_number(&j, "patch_size", b->sc->info.patch_size);
    tp_json_member_string(&j, "renderer", renderer_name);
    tp_json_member_number(&j, "msaa", b->msaa);
    /* the program's own accounting: measured peak against the up-front check's estimate */
    tp_json_member_number(&j, "peak_rss_bytes", (double)tp_memory_peak_rss());
    tp_json_member_number(
        &j, "memory_estimate_bytes",
        (double)tp_memory_estimate(TP_MEMORY_USE_BENCH,
                                   (uint64_t)b->sc->info.width * (uint64_t)b->sc->info.height));
    json_lod(&j, best);
    json_config(&j, best);
    tp_json_key(&j, "full_res");
    tp_json_object_begin(&j);
    json_config(&j, full);
    tp_json_object_end(&j);
    tp_json_member_number(&j, "speedup_vs_full", best->fps_median / full->fps_median);
    tp_json_key(&j, "configurations");
    tp_json_array_begin(&j);
    for (int i = 0; i < nc; i++) {
        tp_json_object_begin(&j);
        json_lod(&j, &c[i]);
        json_config(&j, &c[i]);
        if (o->sweep) {
            tp_json_member_bool(&j, "pareto", c[i].pareto);
        }
        tp_json_object_end(&j);
    }
    tp_json_array_end(&j);
    tp_json_object_end(&j);
    return tp_atomic_commit(&file);
}

int tp_bench_write_frames_csv(const bench_options* o, const config_result* c, int nc, int frames)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, o->csv))
        return 0;
    FILE* f = file.f;
    fprintf(f, "lod_mode,frame,frame_ms,select_ms,upload_ms,draw_ms,triangles,draw_calls,patches,"
               "uploads,gpu_bytes,max_vertical_error_m,rms_vertical_error_m,max_screen_error_px,"
               "rms_screen_error_px,pgm_grid,uncovered_share\n");
    for (int k = 0; k < nc; k++)
        for (int i = 0; i < frames; i++) {
            const frame_row* r = &c[k].rows[i];
            char grid[32] = "";
            if (c[k].pgm_cols)
                snprintf(grid, sizeof grid, "%dx%d", c[k].pgm_cols, c[k].pgm_rows);
            fprintf(f, "%s,%d,%.4f,%.4f,%.4f,%.4f,%zu,%d,%d,%d,%zu,%.4f,%.4f,%.4f,%.4f,%s,%.6f\n",
                    c[k].pgm_cols ? "pgm" : mode_name(c[k].lod.mode), i, r->frame_ms, r->select_ms,
                    r->upload_ms, r->draw_ms, r->triangles, r->draw_calls, r->patches, r->uploads,
                    r->gpu_bytes, r->max_m, r->rms_m, r->max_px, r->rms_px, grid,
                    c[k].pgm_cols ? r->uncovered_share : 0.0);
        }
    return tp_atomic_commit(&file);
}

int tp_bench_write_sweep_csv(const bench_options* o, const config_result* c, int nc)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, o->csv))
        return 0;
    FILE* f = file.f;
    fprintf(f, "family,lod_mode,stitch,pgm_grid,tau_px,mindist_m,maxdist_m,exp,fps_median,"
               "frame_ms_median,cpu_ms_median,draw_ms_median,triangles_median,uploads_median,"
               "gpu_mib,max_screen_error_px,rms_screen_error_px,max_vertical_error_m,"
               "rms_vertical_error_m,uncovered_share,pareto,mesh,tin_share\n");
    for (int k = 0; k < nc; k++) {
        const config_result* r = &c[k];
        int pgm = r->pgm_cols > 0;
        int dist = !pgm && r->lod.mode == TP_LOD_DISTANCE,
            err = !pgm && r->lod.mode == TP_LOD_ERROR;
        char grid[32] = "";
        if (pgm)
            snprintf(grid, sizeof grid, "%dx%d", r->pgm_cols, r->pgm_rows);
        fprintf(f,
                "%s,%s,%s,%s,%g,%g,%g,%g,%.3f,%.3f,%.4f,%.3f,%.0f,%.0f,%.3f,%.4f,%.4f,%.4f,%.4f,"
                "%.6f,%d,%s,%.4f\n",
                tp_bench_family_name(tp_bench_family_of(r)), pgm ? "pgm" : mode_name(r->lod.mode),
                pgm             ? ""
                : r->stitch_add ? "add"
                                : "move",
                grid, err ? r->lod.tau_px : 0, dist ? r->lod.mindist_m : 0,
                dist ? r->lod.maxdist_m : 0, dist ? r->lod.exponent : 0, r->fps_median, r->frame_ms,
                r->cpu_ms, r->draw_ms, r->triangles, r->uploads, r->gpu_bytes / 1048576.0,
                r->max_px, r->rms_px, r->max_m, r->rms_m, r->uncovered_share, r->pareto,
                r->store == 2 ? "tin" : r->store ? "lattice" : "", r->tin_share);
    }
    return tp_atomic_commit(&file);
}

void tp_bench_print_table(const bench_run* b, const char* renderer_name, const config_result* c,
                        int nc, int best)
{
    const bench_options* o = b->o;
    printf("%s, %dx%d, %s path%s, %d frames, %d patches of %d, renderer %s, msaa %d\n", o->dem,
           o->vs.w, o->vs.h, o->path_file ? o->path_file : o->vs.has_camera ? "fixed" : o->path_name,
           b->lead_da > 0 ? " (lead-in frames)" : "", b->frames, b->sc->info.patch_count,
           b->sc->info.patch_size, renderer_name, b->msaa);
    int any_pgm = 0; /* PGM's error leaves out the posts no triangle covers: their share */
    for (int k = 0; k < nc; k++)
        any_pgm |= c[k].pgm_cols > 0;
    printf("%-28s %8s %9s %8s %8s %10s %6s %9s %9s %9s %9s%s\n", "lod", "fps", "frame ms", "cpu ms",
           "draw ms", "triangles", "calls", "max px", "rms px", "max m", "rms m",
           any_pgm ? "  uncov %" : "");
    for (int k = 0; k < nc; k++) {
        printf("%-28s %8.2f %9.2f %8.3f %8.2f %10.0f %6.0f %9.3f %9.3f %9.3f %9.3f", c[k].label,
               c[k].fps_median, c[k].frame_ms, c[k].cpu_ms, c[k].draw_ms, c[k].triangles,
               c[k].draw_calls, c[k].max_px, c[k].rms_px, c[k].max_m, c[k].rms_m);
        if (any_pgm && c[k].pgm_cols)
            printf(" %9.2f", 100 * c[k].uncovered_share);
        else if (any_pgm)
            printf(" %9s", "-");
        printf("%s\n", o->sweep && c[k].pareto && k > 0 ? "  pareto" : "");
    }
    printf("error mode (tau = %g px) vs full resolution: %.2fx the frame rate\n", c[best].lod.tau_px,
           c[best].fps_median / c[0].fps_median);
    for (int k = 0, head = 0; k < nc; k++) /* --stitch add: what its drawing costs */
        if (c[k].stitch_add && !c[k].pgm_cols) {
            if (!head++)
                printf("%-28s %8s %10s %10s %12s %12s\n", "--stitch add drawing", "calls",
                       "draws", "GPU MiB", "index GPU B", "index CPU B");
            printf("%-28s %8.0f %10.0f %10.2f %12zu %12zu\n", c[k].label, c[k].draw_calls,
                   c[k].draws, c[k].gpu_bytes / 1048576.0, c[k].index_gpu_bytes,
                   c[k].index_cpu_bytes);
        }
    uint64_t samples = (uint64_t)b->sc->info.width * (uint64_t)b->sc->info.height;
    printf("memory: peak resident %.0f MiB, estimated %.0f MiB for the %dx%d fitted grid\n",
           tp_memory_peak_rss() / 1048576.0,
           tp_memory_estimate(TP_MEMORY_USE_BENCH, samples) / 1048576.0, b->sc->info.width,
           b->sc->info.height);
    if (c[best].oracle_triangles > 0)
        printf("error mode (tau = %g px): %.0f triangles if every patch were at the coarsest level "
               "its measured error allows (%.0f patches could be coarser; median per frame)\n",
               c[best].lod.tau_px, c[best].oracle_triangles, c[best].oracle_patches);
}
