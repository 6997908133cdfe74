/* bench_store_report.c - the store bench's table, JSON and CSV (see bench_store.h). */
#define _POSIX_C_SOURCE 200809L
#include "bench_store.h"

#include "atomic_file.h"
#include "imagery_view.h"
#include "json.h"
#include "memory.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void tp_bench_store_tin_summary(store_result* c, int n)
{
    c->tin_builds = c->tin_build_ms = c->tin_build_ms_max = 0;
    for (int i = 0; i < n; i++) {
        const store_row* r = &c->rows[i];
        c->tin_builds += (double)r->tin_builds / n, c->tin_build_ms += r->tin_build_ms / n;
        c->tin_build_ms_max = fmax(c->tin_build_ms_max, r->tin_build_ms);
    }
}

static void json_result(tp_json* j, const store_bench* b, const store_result* c)
{
#define tp_json_member_number(j, k, v) (tp_json_member_number(j, k, v))
    tp_json_member_string(j, "terrain_renderer", c->pgm_cols ? "pgm" : "patches");
    if (c->pgm_cols) {
        char grid[32];
        snprintf(grid, sizeof grid, "%dx%d", c->pgm_cols, c->pgm_rows);
        tp_json_member_string(j, "pgm_grid", grid);
        tp_json_member_number(j, "pgm_window", c->pgm_window);
        tp_json_member_number(j, "pgm_fill_ms_median", c->pgm_fill_ms);
        tp_json_member_number(j, "pgm_fill_ms_p99", c->pgm_fill_ms_p99);
        tp_json_member_number(j, "pgm_upload_ms_median", c->pgm_upload_ms);
        tp_json_member_number(j, "pgm_upload_ms_p99", c->pgm_upload_ms_p99);
        tp_json_member_number(j, "pgm_posts_updated_median", c->pgm_posts);
        tp_json_member_number(j, "pgm_node_reads_median", c->pgm_node_reads);
    }
    tp_json_member_string(j, "stitch", c->stitch_add ? "add" : "move");
    tp_json_member_string(j, "lod_mode", c->pgm_cols                 ? "pgm"
                      : c->lod.mode == TP_LOD_ERROR ? "error"
                      : c->lod.sphere_tree        ? "spheres"
                                                  : "distance");
    if (c->lod.mode == TP_LOD_ERROR)
        tp_json_member_number(j, "tau_px", c->lod.tau_px > 0 ? c->lod.tau_px : 1);
    tp_json_member_number(j, "fps_median", c->fps_median);
    tp_json_member_number(j, "frame_ms_median", c->frame_ms);
    tp_json_member_number(j, "frame_ms_p99", c->frame_ms_p99);
    tp_json_member_number(j, "p99_over_median", c->frame_ms_p99 / c->frame_ms);
    tp_json_member_number(j, "cpu_ms_median", c->cpu_ms); /* the DEM bench's name: one schema */
    tp_json_member_number(j, "cut_ms_median", c->cut_ms); /* the render thread's part */
    tp_json_member_bool(j, "cut_thread", c->cut_thread);
    if (c->cut_thread) {
        tp_json_member_number(j, "cut_worker_ms_median", c->cut_worker_ms);
        tp_json_member_number(j, "cut_wait_ms_median", c->cut_wait_ms);
        tp_json_member_number(j, "cut_worker_cpu_ms_median", c->cut_worker_cpu_ms);
        tp_json_member_number(j, "cut_worker_cpu_ms_mean", c->cut_worker_cpu_ms_mean);
        tp_json_member_number(j, "cut_total_cpu_ms_median", c->cut_total_cpu_ms);
        tp_json_member_number(j, "cut_total_cpu_ms_mean", c->cut_total_cpu_ms_mean);
        tp_json_member_number(j, "cut_reused_share", c->cut_reused_share);
        tp_json_member_number(j, "cut_kept_share", c->cut_kept_share);
        tp_json_member_number(j, "cut_carried_share", c->cut_carried_share);
        tp_json_member_number(j, "cut_check_scratch_nodes_median", c->cut_scratch);
    }
    tp_json_member_number(j, "stream_ms_median", c->stream_ms);
    tp_json_member_number(j, "upload_ms_median", c->upload_ms);
    tp_json_member_number(j, "draw_ms_median", c->draw_ms);
    tp_json_member_number(j, "draw_calls_median", c->draw_calls);
    tp_json_member_number(j, "draw_page_faults_median", c->page_faults);
    tp_json_member_number(j, "triangles_median", c->triangles);
    tp_json_member_string(j, "mesh", c->mesh_tin ? "tin" : "lattice");
    if (c->mesh_tin) {
        tp_json_member_number(j, "tin_nodes_share", c->tin_share);
        tp_json_member_number(j, "tin_mb_max", c->tin_mb);
        tp_json_member_number(j, "tin_builds_per_frame_mean", c->tin_builds);
        tp_json_member_number(j, "tin_build_ms_per_frame_mean", c->tin_build_ms);
        tp_json_member_number(j, "tin_build_ms_per_frame_max", c->tin_build_ms_max);
    }
    tp_json_member_number(j, "nodes_drawn_median", c->nodes);
    tp_json_member_number(j, "nodes_visited_median", c->visited);
    tp_json_member_number(j, "uploads_median", c->uploads);
    tp_json_member_number(j, "substituted_nodes_max", c->substituted_max);
    tp_json_member_number(j, "frames_with_substitution", c->frames_with_substitution);
    tp_json_member_number(j, "dropped_nodes_max", c->dropped_max);
    tp_json_member_number(j, "pending_max", c->pending_max);
    tp_json_member_number(j, "rss_mb", c->rss_mb);
    tp_json_member_number(j, "rss_anon_mb", c->rss_anon_mb);
    tp_json_member_number(j, "resident_mb", c->resident_mb);
    tp_json_member_number(j, "gpu_mb", c->gpu_mb);
    tp_json_member_number(j, "settle_ms", c->settle_ms);
    tp_json_member_number(j, "settle_timeouts", c->settle_timeouts);
    tp_json_member_bool(j, "imagery", c->imagery);
    if (c->imagery) {
        tp_json_member_string(j, "imagery_mode", c->imagery_mode == TP_IMAGERY_BLOCKS ? "blocks" : "clipmap");
        tp_json_member_number(j, "imagery_ms_median", c->img_ms);
        tp_json_member_number(j, "imagery_upload_ms_median", c->img_upload_ms);
        tp_json_member_number(j, "imagery_upload_ms_p99", c->img_upload_ms_p99);
        tp_json_member_number(j, "imagery_uploads_median", c->img_uploads);
        tp_json_member_number(j, "imagery_uploads_total", c->img_uploads_total);
        tp_json_member_number(j, "imagery_gpu_mb", c->img_gpu_mb);
        tp_json_member_number(j, "imagery_cache_mb", c->img_cache_mb);
        tp_json_member_number(j, "imagery_missing_blocks_max", c->img_missing_max);
        tp_json_member_number(j, "imagery_frames_missing_blocks", c->img_frames_missing);
        tp_json_member_number(j, "imagery_final_diff_pixels", (double)c->img_final_diff);
    }
    tp_json_member_bool(j, "light", c->light);
    if (c->light) {
        tp_json_member_number(j, "light_ms_median", c->img_ms);
        tp_json_member_number(j, "light_upload_ms_median", c->img_upload_ms);
        tp_json_member_number(j, "light_upload_ms_p99", c->img_upload_ms_p99);
        tp_json_member_number(j, "light_uploads_median", c->img_uploads);
        tp_json_member_number(j, "light_uploads_total", c->img_uploads_total);
        tp_json_member_number(j, "light_gpu_mb", c->img_gpu_mb);
        tp_json_member_number(j, "light_cache_mb", c->img_cache_mb);
        tp_json_member_number(j, "light_missing_blocks_max", c->img_missing_max);
        tp_json_member_number(j, "light_frames_missing_blocks", c->img_frames_missing);
    }
    tp_json_member_string(j, "normals", c->pgm_cols ? "vertex" : "map");
    if (!c->pgm_cols) { /* the normal map's clipmap (normal_map.h) */
        tp_json_member_number(j, "normals_ms_median", c->nrm_ms);
        tp_json_member_number(j, "normals_upload_ms_median", c->nrm_upload_ms);
        tp_json_member_number(j, "normals_uploads_total", c->nrm_uploads_total);
        tp_json_member_number(j, "normals_gpu_mb", c->nrm_gpu_mb);
        tp_json_member_number(j, "normals_frames_missing_blocks", c->nrm_frames_missing);
    }
    /* frames drawn without substitution with a sample in view; null px when there were none */
    tp_json_member_number(j, "error_frames_measured", c->error_frames);
    tp_json_member_number(j, "max_screen_error_px",
                          c->error_frames && c->samples > 0 ? c->max_px : NAN);
    tp_json_member_number(j, "rms_screen_error_px",
                          c->error_frames && c->samples > 0 ? c->rms_px : NAN);
    tp_json_member_number(j, "error_samples", c->samples);
    tp_json_member_number(j, "error_samples_skipped", c->skipped);
    tp_json_member_number(j, "error_ms_median", c->measure_ms); /* a measure, untimed */
    if (c->pgm_cols) { /* posts in view no drawn triangle covers (not in the error) */
        tp_json_member_number(j, "uncovered_share", c->error_frames ? c->uncovered_share : NAN);
        /* the mean share of the view's region compared (bands of it past 2^28 posts) */
        tp_json_member_number(j, "error_post_share", c->post_share);
        return;
    }
    /* frames drawn with substitution (coarser than tau asks where children were missing) */
    tp_json_member_number(j, "error_frames_substituted", c->error_frames_subst);
    tp_json_member_number(j, "max_screen_error_px_substituted", c->max_px_subst);
    tp_json_member_number(j, "rms_screen_error_px_substituted", c->rms_px_subst);
    /* How the cut's measure sampled (tp_cut_measure_error), summed over the measured frames:
     * leaves under the drawn nodes, those chosen (at most per_node x per_node a node), those in
     * view measured, read from the store, not to be had. */
    tp_json_member_number(j, "error_posts_budget", b->o->error_posts);
    tp_json_member_number(j, "error_leaves", c->leaves);
    tp_json_member_number(j, "error_leaves_sampled", c->leaves_sampled);
    tp_json_member_number(j, "error_leaves_measured", c->leaves_measured);
    tp_json_member_number(j, "error_leaves_read", c->leaves_read);
    tp_json_member_number(j, "error_leaves_skipped", c->leaves_skipped);
    tp_json_member_number(j, "error_leaf_share", c->leaves > 0 ? c->leaves_sampled / c->leaves : NAN);
    tp_json_member_number(j, "error_leaves_per_node_min", c->per_node_min);
}

int tp_bench_store_write_json(const store_bench* b, const char* renderer_name, const store_result* c,
                      int nc)
{
    const bench_options* o = b->o;
    tp_atomic_file file;
    if (!tp_atomic_open(&file, o->json))
        return 0;
    tp_json j;
    tp_json_init(&j, file.f);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "store", o->dem);
    char size[32];
    snprintf(size, sizeof size, "%dx%d", o->vs.w, o->vs.h);
    tp_json_member_string(&j, "size", size);
    tp_json_member_string(&j, "path", o->path_name);
    tp_json_member_number(&j, "speed_mps", o->speed_mps);
    tp_json_member_bool(&j, "realtime", o->realtime);
    tp_json_member_bool(&j, "prefetch", !o->no_prefetch);
    tp_json_member_number(&j, "frames", b->segments * b->per_segment);
    /* the frames measured: every error_every-th (0: --no-error) */
    tp_json_member_number(&j, "error_every", o->no_error ? 0 : o->error_every);
    tp_json_member_number(&j, "segments", b->segments);
    tp_json_member_number(&j, "samples", (double)b->g->src_width * b->g->src_height);
    tp_json_member_number(&j, "src_width", b->g->src_width);
    tp_json_member_number(&j, "src_height", b->g->src_height);
    tp_json_member_number(&j, "nodes", (double)b->g->node_count);
    tp_json_member_number(&j, "patch_size", (1 << b->g->n) + 1);
    tp_json_member_number(&j, "memory_budget_mb", (double)((size_t)o->memory_mb << 20) / 1e6);
    tp_json_member_string(&j, "renderer", renderer_name);
    tp_json_member_number(&j, "msaa", b->msaa);
    /* first_frame_ms: from the process's start (/proc/self/stat, 10 ms ticks) to the end of
     * the first drawn frame (glFinish); first_frame_from_open_ms: from opening the store */
    tp_json_member_number(&j, "first_frame_ms", b->first_frame_ms);
    tp_json_member_number(&j, "first_frame_from_open_ms", b->first_frame_open_ms);
    tp_json_member_number(&j, "store_open_ms", b->open_ms);
    tp_json_member_number(&j, "gl_context_ms", b->context_ms);
    tp_json_member_number(&j, "startup_to_bench_ms", b->entered_ms);
    tp_json_member_number(&j, "renderer_create_ms", b->renderer_ms);
    tp_json_member_number(&j, "stream_create_ms", b->stream_create_ms);
    tp_json_member_number(&j, "first_cut_stream_ms", b->first_cut_ms);
    tp_json_member_number(&j, "first_draw_ms", b->first_draw_ms);
    tp_json_member_number(&j, "georef_wait_ms", b->georef_wait_ms);
    tp_json_member_number(&j, "peak_rss_mb", tp_memory_peak_rss() / 1e6);
    /* before any node, cut or renderer: libraries, the GL driver, the store's node table */
    tp_json_member_number(&j, "base_rss_mb", b->base_rss_mb);
    tp_json_member_number(&j, "base_rss_anon_mb", b->base_anon_mb);
    json_result(&j, b, &c[0]); /* the headline: the first configuration (error mode) */
    tp_json_key(&j, "configurations");
    tp_json_array_begin(&j);
    for (int i = 0; i < nc; i++) {
        tp_json_object_begin(&j);
        json_result(&j, b, &c[i]);
        tp_json_object_end(&j);
    }
    tp_json_array_end(&j);
    tp_json_object_end(&j);
    return tp_atomic_commit(&file);
}

int tp_bench_store_write_csv(const store_bench* b, const store_result* c, int nc)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, b->o->csv))
        return 0;
    FILE* f = file.f;
    fprintf(f, "lod_mode,frame,frame_ms,cut_ms,stream_ms,upload_ms,draw_ms,cpu_ms,triangles,nodes,"
               "visited,substituted,requests,uploads,pending,gpu_bytes,resident_bytes,rss_mb,"
               "rss_anon_mb,measured,max_screen_error_px,rms_screen_error_px,samples,skipped,"
               "imagery_ms,imagery_upload_ms,imagery_uploads,imagery_missing_blocks,"
               "cut_worker_ms,cut_wait_ms,cut_reused,error_leaves,error_leaves_sampled,"
               "error_leaves_read,error_ms,cut_worker_cpu_ms,cut_kept,cut_carried\n");
    int frames = b->segments * b->per_segment;
    for (int k = 0; k < nc; k++)
        for (int i = 0; i < frames; i++) {
            const store_row* r = &c[k].rows[i];
            fprintf(f, "%s,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f,%zu,%d,%d,%d,%d,%d,%d,%zu,%zu,%.1f,"
                       "%.1f,%d,%.4f,%.4f,%zu,%zu,%.4f,%.4f,%d,%d,%.4f,%.4f,%d,%zu,%zu,%zu,%.2f,%.4f,%d,%d\n",
                    c[k].pgm_cols ? "pgm"
                    : c[k].light ? "error+light"
                    : c[k].imagery ? (c[k].imagery_mode == TP_IMAGERY_BLOCKS ? "error+blocks"
                                                                             : "error+imagery")
                    : c[k].stitch_add ? (c[k].lod.mode == TP_LOD_ERROR ? "error+add"
                                                                       : "distance+add")
                    : c[k].lod.mode == TP_LOD_ERROR ? "error"
                    : c[k].lod.sphere_tree          ? "spheres"
                                                    : "distance",
                    i, r->frame_ms,
                    r->cut_ms, r->stream_ms, r->upload_ms, r->draw_ms, r->cpu_ms, r->triangles,
                    r->nodes, r->visited, r->substituted, r->requests, r->uploads, r->pending,
                    r->gpu_bytes, r->resident_bytes, r->rss_mb, r->rss_anon_mb, r->measured,
                    r->max_px, r->rms_px, r->samples, r->skipped, r->img_ms, r->img_upload_ms,
                    r->img_uploads, r->img_missing, r->cut_worker_ms, r->cut_wait_ms,
                    r->cut_reused, r->cut.leaves, r->cut.leaves_sampled, r->cut.leaves_read,
                    r->measure_ms, r->cut_worker_cpu_ms, r->cut_kept, r->cut_carried);
        }
    return tp_atomic_commit(&file);
}

void tp_bench_store_print(const store_bench* b, const char* renderer_name, const store_result* c,
                        int nc)
{
    const bench_options* o = b->o;
    int frames = b->segments * b->per_segment;
    printf("%s, %dx%d samples, %dx%d, %s path at %g m/s%s, %d frames in %d stretches, memory "
           "budget %d MB, renderer %s, msaa %d\n",
           o->dem, b->g->src_width, b->g->src_height, o->vs.w, o->vs.h, o->path_name,
           o->speed_mps, o->realtime ? " (real time)" : " (30 Hz steps)", frames, b->segments,
           o->memory_mb, renderer_name, b->msaa);
    printf("first frame %.0f ms after the process started, %.0f ms after opening the store "
           "(open %.0f ms, GL context %.0f ms)\n",
           b->first_frame_ms, b->first_frame_open_ms, b->open_ms, b->context_ms);
    printf("first frame's parts: start to bench %.0f, open %.0f, GL context %.0f, renderer %.0f, "
           "stream %.0f, georef wait %.0f, cut %.0f, draw %.0f ms\n",
           b->entered_ms, b->open_ms, b->context_ms, b->renderer_ms, b->stream_create_ms,
           b->georef_wait_ms, b->first_cut_ms, b->first_draw_ms);
    printf("memory before the first node: %.0f MB resident, %.0f MB anonymous (libraries, GL "
           "driver, node table)\n",
           b->base_rss_mb, b->base_anon_mb);
    printf("%-16s %7s %8s %7s %7s %7s %7s %7s %9s %6s %6s %8s %7s %7s %7s %7s %7s\n", "lod", "fps",
           "frame ms", "p99 ms", "cpu ms", "cut ms", "strm ms", "draw ms", "triangles", "nodes",
           "subst", "subst fr", "rss MB", "anon MB", "res MB", "gpu MB", "max px");
    for (int k = 0; k < nc; k++)
        printf("%-16s %7.2f %8.2f %7.2f %7.3f %7.3f %7.3f %7.2f %9.0f %6.0f %6d %7.1f%% %7.0f "
               "%7.0f %7.0f %7.0f %7.3f\n",
               c[k].label, c[k].fps_median, c[k].frame_ms, c[k].frame_ms_p99, c[k].cpu_ms,
               c[k].cut_ms, c[k].stream_ms, c[k].draw_ms, c[k].triangles, c[k].nodes,
               c[k].substituted_max, 100.0 * c[k].frames_with_substitution / frames, c[k].rss_mb,
               c[k].rss_anon_mb, c[k].resident_mb, c[k].gpu_mb,
               c[k].samples > 0 ? c[k].max_px : NAN);
    for (int k = 0; k < nc; k++)
        if (c[k].imagery)
            printf("%s: imagery %.3f ms a frame (upload %.3f ms median, %.3f p99; %.0f %s), "
                   "GPU %.1f MB, RAM %.1f MB, %d frames lacking %s (at most %d), %.0f draw calls, "
                   "last frame vs a fresh %s: %ld pixels differ\n",
                   c[k].label, c[k].img_ms, c[k].img_upload_ms, c[k].img_upload_ms_p99,
                   c[k].img_uploads, c[k].imagery_mode == TP_IMAGERY_BLOCKS ? "layers" : "blocks",
                   c[k].img_gpu_mb, c[k].img_cache_mb, c[k].img_frames_missing,
                   c[k].imagery_mode == TP_IMAGERY_BLOCKS ? "node textures" : "blocks",
                   c[k].img_missing_max, c[k].draw_calls,
                   c[k].imagery_mode == TP_IMAGERY_BLOCKS ? "blocks pool" : "clipmap",
                   c[k].img_final_diff);
    for (int k = 0; k < nc; k++)
        if (!c[k].pgm_cols)
            printf("%s: normal map %.3f ms a frame (upload %.3f ms median; %.0f blocks in all), "
                   "GPU %.1f MB, %d frames lacking blocks\n",
                   c[k].label, c[k].nrm_ms, c[k].nrm_upload_ms, c[k].nrm_uploads_total,
                   c[k].nrm_gpu_mb, c[k].nrm_frames_missing);
    for (int k = 0; k < nc; k++)
        if (c[k].light)
            printf("%s: streamed light %.3f ms a frame (upload %.3f ms median, %.3f p99; %.0f "
                   "blocks), GPU %.1f MB, RAM %.1f MB, %d frames lacking blocks (at most %d)\n",
                   c[k].label, c[k].img_ms, c[k].img_upload_ms, c[k].img_upload_ms_p99,
                   c[k].img_uploads, c[k].img_gpu_mb, c[k].img_cache_mb, c[k].img_frames_missing,
                   c[k].img_missing_max);
    for (int k = 0; k < nc; k++)
        if (c[k].pgm_cols)
            printf("%s: clipmap of %d x %d posts a level: fill %.3f ms a frame median (%.3f p99), "
                   "upload %.3f ms median (%.3f p99), %.0f posts and %.0f node reads median; "
                   "GPU %.1f MB; screen error (the windows' surface against the level-0 posts in "
                   "view) measured on %d frames: max %.3f px, RMS %.3f px, %.0f samples, %.2f %% "
                   "of the posts in view uncovered\n",
                   c[k].label, c[k].pgm_window, c[k].pgm_window, c[k].pgm_fill_ms,
                   c[k].pgm_fill_ms_p99, c[k].pgm_upload_ms, c[k].pgm_upload_ms_p99, c[k].pgm_posts,
                   c[k].pgm_node_reads, c[k].gpu_mb, c[k].error_frames,
                   c[k].samples > 0 ? c[k].max_px : NAN, c[k].samples > 0 ? c[k].rms_px : NAN,
                   c[k].samples, 100 * c[k].uncovered_share);
    for (int k = 0; k < nc; k++)
        if (c[k].pgm_cols && c[k].post_share < 1)
            printf("%s: the error compared %.1f%% of the view's posts (bands of them: regions "
                   "of more than 2^28 posts)\n",
                   c[k].label, 100 * c[k].post_share);
    for (int k = 0; k < nc; k++)
        if (!o->no_error && !c[k].pgm_cols)
            printf("%s: screen error measured on %d frames without substitution (%.0f samples, "
                   "%.0f skipped: leaves not to be had), %.1f%% of the leaves under the cut "
                   "(%s), %.0f ms a measure; %d frames with substitution: max %.3f px\n",
                   c[k].label, c[k].error_frames, c[k].samples, c[k].skipped,
                   c[k].leaves > 0 ? 100 * c[k].leaves_sampled / c[k].leaves : 0.0,
                   c[k].per_node_min ? "sampled" : "every leaf", c[k].measure_ms,
                   c[k].error_frames_subst, c[k].max_px_subst);
}
