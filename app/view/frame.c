/* frame.c - one frame of the viewer and what is written from it (see view.h). */
#define _POSIX_C_SOURCE 200809L
#include "view.h"
#include "clock.h"

#include "atomic_file.h"
#include "cli.h"
#include "cut_worker.h"
#include "imagery_view.h"
#include "json.h"
#include "normal_map.h"
#include "pgm_render.h"
#include "pick.h"
#include "view_shadows.h"

#include <epoxy/gl.h>

#include <assert.h>
#include <stdio.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* Prints a normal-map block that could not be read (once each). */
static void report_normal_failures(tp_view_scene* v)
{
    const char* f;
    while ((f = tp_normal_map_take_failure(v->normals)))
        if (tp_view_scene_say_once(v, f)) /* the stream may have said it */
            tp_cli_error("%s (shaded from the vertex normals there)", f);
}

void tp_view_frame(tp_view_scene* v, tp_renderer* r, const tp_camera* cam,
                   const tp_render_settings* render, const tp_lod_params* lod, int frozen,
                   frame_result* out)
{
    double t0 = tp_clock_ms();
    tp_error err;
    out->pgm_cols = out->pgm_rows = 0; /* set by the PGM path only (the HUD tests them) */
    out->normals = v->normals != NULL;
    out->add_sides = out->moved_sides = 0;
    out->mesh_tin = out->tin_nodes = 0;
    out->tin_bytes = out->tin_levels = 0;
    out->grid_m = render->grid_m;
    /* the core selects, culls and measures the surface as drawn: exaggerated */
    tp_view_scene_set_vertical_scale(v, render->exaggeration);
    if (v->pgm) { /* Persistent Grid Mapping: no selection, the same grid every frame */
        tp_pgm_render_stats ps;
        tp_pgm_renderer_draw(v->pgm, cam, render, 1, NULL, &ps);
        memset(&out->core, 0, sizeof out->core);
        memset(&out->render, 0, sizeof out->render);
        out->core.triangles = ps.triangles;
        out->core.bound_max_error_m = out->core.bound_rms_error_m = NAN;
        out->render.draw_calls = out->render.draws = 1;
        out->render.draw_ms = ps.draw_ms;
        out->render.gpu_bytes = ps.gpu_bytes;
        out->render.near_m = ps.near_m;
        out->render.far_m = ps.far_m;
        /* over a store's clipmap: reading the strips its windows gained is CPU work, their
         * glTexSubImage3D the upload (cpu_ms = select_ms + upload_ms) */
        out->render.upload_ms = ps.upload_ms;
        out->render.uploads = ps.posts_updated > 0;
        out->select_ms = ps.setup_ms - ps.upload_ms;
        out->pgm_cols = ps.cols;
        out->pgm_rows = ps.rows;
        out->store = 0;
        return;
    }
    if (!v->store) {
        if (!frozen)
            tp_selection_update(v->sel, cam, lod, &err);
        out->select_ms = tp_clock_ms() - t0;
        if (v->normals)
            tp_normal_map_frame(v->normals, r, cam, v->min_height_m * render->exaggeration,
                                v->max_height_m * render->exaggeration, v->normals_settle,
                                &out->normal_clip);
        report_normal_failures(v);
        tp_renderer_draw(r, v->sel, cam, render, 1, &out->render);
        tp_selection_stats(v->sel, &out->core);
        if (render->stitch_add) /* the core counts the vertex-moving triangulation's */
            out->core.triangles = out->render.triangles;
        out->store = 0;
        return;
    }
    const tp_cut_worker_params wp = {*lod, render->exaggeration, render->stitch_add,
                                     v->store->tins};
    if (frozen) {
        tp_cut_worker_idle(v->worker); /* the stream changes the tree below */
    } else if (v->worker) { /* the cut the thread selected while the last frame drew */
        tp_cut* c = tp_cut_worker_frame(v->worker, cam, &wp, NULL, &err);
        if (c)
            v->cut = c;
    } else {
        tp_cut_update(v->cut, cam, lod, &err);
    }
    tp_stream_frame(v->store->stream, v->cut, frozen ? NULL : v->prefetch, cam, lod, &out->stream);
    out->mesh_tin = v->store->tins != NULL;
    if (v->store->tins) { /* the TINs of nodes the stream released (the cut thread is idle) */
        tp_tin_cache_mark_drawn(v->store->tins, v->cut);
        tp_tin_cache_prune(v->store->tins, TP_CUT_WORKER_TIN_AGE, TP_CUT_WORKER_TIN_BYTES);
        tp_tin_cache_stats(v->store->tins, &out->tin_bytes, &out->tin_levels, NULL);
    }
    if (v->worker && !frozen) { /* the next frame's, while this one draws */
        tp_camera next, ahead;
        tp_cut_worker_predict(v->worker_have_prev ? &v->worker_prev : cam, cam, &next);
        int pre = tp_stream_prefetch_wanted(v->store->stream, &ahead);
        tp_cut_worker_next(v->worker, &next, &wp, pre ? v->prefetch : NULL, &ahead);
        v->worker_prev = *cam;
        v->worker_have_prev = 1;
    }
    tp_view_scene_report_failures(v);
    out->select_ms = tp_clock_ms() - t0;
    tp_view_shadows_frame(v, r, cam, render, out);
    out->imagery = v->imagery && !v->imagery_hidden;
    if (out->imagery) {
        tp_view_imagery_frame(v->imagery, v->store, v->cut, render->exaggeration, r, cam,
                              v->imagery_settle, &out->clip);
        tp_view_imagery_report_failures(v->imagery);
    } else {
        tp_renderer_set_clip(r, NULL);
    }
    if (v->normals)
        tp_normal_map_frame_cut(v->normals, v->store, v->cut, render->exaggeration, r, cam,
                                v->normals_settle, &out->normal_clip);
    report_normal_failures(v);
    tp_renderer_draw_cut(r, v->store->tree, v->cut, cam, render, render->exaggeration, 1,
                         &out->render);
    tp_cut_stats cs;
    tp_cut_get_stats(v->cut, &cs);
    memset(&out->core, 0, sizeof out->core);
    size_t count = 0;
    const tp_cut_node* nodes = tp_cut_nodes(v->cut, &count);
    for (size_t i = 0; i < count; i++)
        out->core.patches_per_level[nodes[i].level]++;
    out->core.visible_patches = cs.drawn;
    out->core.culled_patches = cs.culled;
    out->core.triangles = cs.triangles;
    out->core.bound_max_error_m = out->core.bound_rms_error_m = NAN;
    out->store = 1;
    out->nodes_drawn = cs.drawn;
    memcpy(out->nodes_per_scale, cs.nodes_per_scale, sizeof out->nodes_per_scale);
    out->substituted = cs.substituted;
    out->add_sides = cs.add_sides;
    out->moved_sides = cs.moved_sides;
    out->tin_nodes = cs.tin_nodes;
    out->bound_max_px = cs.max_bound_px;
    out->bound_near_nodes = cs.near_plane_nodes;
}

/* A clipmap's figures of the frame under keys "<what>_...". */
static void write_clip(tp_json* j, const char* what, const tp_clipmap_stats* c)
{
    char k[64];
#define CLIP_KEY(name) (snprintf(k, sizeof k, "%s_" name, what), k)
    tp_json_member_number(j, CLIP_KEY("gpu_mb"), c->gpu_bytes / 1e6);
    tp_json_member_number(j, CLIP_KEY("cache_mb"), c->cache_bytes / 1e6);
    tp_json_member_number(j, CLIP_KEY("upload_ms"), c->upload_ms);
    tp_json_member_size(j, CLIP_KEY("uploads"), (size_t)c->uploads);
    tp_json_member_size(j, CLIP_KEY("first_level"), (size_t)c->first_level);
    tp_json_member_size(j, CLIP_KEY("missing_blocks"), (size_t)c->missing);
#undef CLIP_KEY
}

/* "first_frame": when the view's first picture was finished and from what (view.h). */
static void write_first(tp_json* j, const tp_view_first* first)
{
    tp_json_key(j, "first_frame");
    tp_json_object_begin(j);
    tp_json_member_number(j, "ms", first->ms);
    tp_json_member_string(j, "from", first->preview ? "preview" : first->dem ? "dem" : "store");
    if (first->preview) {
        tp_json_member_int(j, "preview_coarsen", first->coarsen);
        tp_json_member_bool(j, "build_running", first->build_running);
    }
    if (first->store_ms >= 0)
        tp_json_member_number(j, "store_ms", first->store_ms);
    tp_json_object_end(j);
}

int tp_view_write_stats(const char* path, const frame_result* f, const tp_error_measure* em,
                        double max_px, double rms_px, const tp_view_measured_how* how,
                        int levels, const tp_camera* cam, const tp_view_first* first)
{
    tp_atomic_file file;
    if (!tp_atomic_open(&file, path))
        return 0;
    FILE* out = file.f;
    tp_json j;
    tp_json_init(&j, out);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "renderer", f->pgm_cols ? "pgm" : "patches");
    /* the camera of the frame, as --camera takes it (render CRS) */
    double yaw, pitch;
    tp_camera_get_pose(cam, &yaw, &pitch);
    const double cam_v[5] = {cam->position[0], cam->position[1], cam->position[2], yaw, pitch};
    tp_json_key(&j, "camera");
    tp_json_array_begin(&j);
    for (int i = 0; i < 5; i++)
        tp_json_number(&j, cam_v[i]);
    tp_json_array_end(&j);
    tp_json_member_number(&j, "fov_y_deg", (cam->fov_y_rad > 0 ? cam->fov_y_rad : 60 * 3.14159265358979323846 / 180) *
                           180 / 3.14159265358979323846);
    if (f->pgm_cols) {
        char grid[32];
        snprintf(grid, sizeof grid, "%dx%d", f->pgm_cols, f->pgm_rows);
        tp_json_member_string(&j, "pgm_grid", grid);
        tp_json_member_int(&j, "pgm_cols", f->pgm_cols);
        tp_json_member_int(&j, "pgm_rows", f->pgm_rows);
    }
#define KEY_NUM(k, v) (tp_json_member_number(&j, k, v))
#define KEY_SIZE(k, v) (tp_json_member_size(&j, k, v))
    KEY_SIZE("triangles", f->core.triangles);
    KEY_SIZE("draw_calls", (size_t)f->render.draw_calls);
    KEY_SIZE("draws", (size_t)f->render.draws); /* each of a multi-draw's counted */
    KEY_SIZE("patches_drawn", (size_t)f->render.patches_drawn);
    KEY_SIZE("patches_culled", (size_t)f->core.culled_patches);
    tp_json_key(&j, "levels");
    tp_json_array_begin(&j);
    for (int k = 0; k < levels; k++)
        tp_json_int(&j, f->core.patches_per_level[k]);
    tp_json_array_end(&j);
    /* the frame rate these times allow (the HUD's fps is the window's, between frames) */
    KEY_NUM("fps", 1000 / fmax(f->select_ms + f->render.upload_ms + f->render.draw_ms, 1e-6));
    KEY_NUM("cpu_ms", f->select_ms + f->render.upload_ms);
    KEY_NUM("select_ms", f->select_ms);
    KEY_NUM("upload_ms", f->render.upload_ms);
    KEY_NUM("draw_ms", f->render.draw_ms);
    KEY_SIZE("draw_page_faults", (size_t)(f->render.page_faults > 0 ? f->render.page_faults : 0));
    KEY_SIZE("uploads", (size_t)f->render.uploads);
    KEY_SIZE("gpu_bytes", f->render.gpu_bytes);
    KEY_NUM("grid_m", f->grid_m); /* the spacing drawn (--grid's, times 10^k by the scale) */
    KEY_SIZE("msaa", (size_t)f->msaa);
    const char* gl = (const char*)glGetString(GL_RENDERER); /* what drew it */
    tp_json_member_string(&j, "gl_renderer", gl ? gl : "?");
    tp_json_member_string(&j, "normals", f->normals ? "map" : "vertex");
    if (f->normals) {
        write_clip(&j, "normals", &f->normal_clip);
    }
    if (em) {
        KEY_NUM("max_error_m", em->max_error_m);
        KEY_NUM("rms_error_m", em->rms_error_m);
    }
    KEY_NUM("max_error_px", max_px);
    KEY_NUM("rms_error_px", rms_px);
    const tp_cut_error* ce = how && how->cut ? &how->cut_error : NULL;
    if (how && (how->cut || !isnan(how->post_share))) /* the measure's own time (untimed) */
        KEY_NUM("error_ms", how->ms);
    if (how && !isnan(how->post_share)) /* PGM: share of the view's posts compared */
        KEY_NUM("error_post_share", how->post_share);
    if (ce) { /* a store's cut: what was measured (null px above when no sample was) */
        KEY_SIZE("error_samples", ce->samples);
        KEY_SIZE("error_samples_skipped", ce->skipped);
        KEY_SIZE("error_leaves", ce->leaves);
        KEY_SIZE("error_leaves_sampled", ce->leaves_sampled);
        KEY_SIZE("error_leaves_measured", ce->leaves_measured);
        KEY_SIZE("error_leaves_read", ce->leaves_read);
        KEY_SIZE("error_leaves_skipped", ce->leaves_skipped);
        KEY_SIZE("error_leaves_per_node", (size_t)ce->per_node);
        KEY_SIZE("error_posts_budget", TP_STORE_MEASURE_POSTS); /* leaves of at most these */
        KEY_NUM("error_leaf_share",
                ce->leaves ? (double)ce->leaves_sampled / (double)ce->leaves : NAN);
    }
    if (!f->store) {
        KEY_NUM("bound_max_error_m", f->core.bound_max_error_m);
        KEY_NUM("bound_rms_error_m", f->core.bound_rms_error_m);
    } else {
        KEY_NUM("bound_max_px", f->bound_max_px);
        /* nodes whose box reaches the near plane: bounded over what is drawn of them */
        KEY_SIZE("bound_near_plane_nodes", (size_t)f->bound_near_nodes);
        KEY_NUM("resident_mb", f->stream.resident_bytes / 1e6);
        KEY_NUM("gpu_mb", f->render.gpu_bytes / 1e6);
        KEY_SIZE("nodes_drawn", (size_t)f->nodes_drawn);
        tp_json_key(&j, "nodes_per_scale"); /* scale 0: leaves; coarser from 1 */
        tp_json_array_begin(&j);
        int top = TP_TREE_MAX_SCALES;
        while (top > 1 && f->nodes_per_scale[top - 1] == 0)
            top--;
        for (int s = 0; s < top; s++)
            tp_json_int(&j, f->nodes_per_scale[s]);
        tp_json_array_end(&j);
        KEY_SIZE("substituted_nodes", (size_t)f->substituted);
        KEY_SIZE("add_sides", (size_t)f->add_sides);
        KEY_SIZE("moved_sides", (size_t)f->moved_sides);
        tp_json_member_string(&j, "mesh", f->mesh_tin ? "tin" : "lattice");
        if (f->mesh_tin) {
            KEY_SIZE("tin_nodes", (size_t)f->tin_nodes);
            KEY_SIZE("tin_levels", f->tin_levels);
            KEY_NUM("tin_mb", f->tin_bytes / 1e6);
        }
        KEY_SIZE("pending", (size_t)f->stream.pending);
        if (f->imagery) {
            write_clip(&j, "imagery", &f->clip);
        }
        tp_json_member_string(&j, "light_source", f->light_source == TP_VIEW_LIGHT_STREAMED ? "streamed"
                           : f->light_source == TP_VIEW_LIGHT_WINDOW ? "window" : "none");
        if (f->light_source == TP_VIEW_LIGHT_STREAMED) {
            KEY_NUM("light_tau", f->light_tau);
            KEY_NUM("light_gpu_mb", f->light_clip.gpu_bytes / 1e6);
            KEY_NUM("light_cache_mb", f->light_clip.cache_bytes / 1e6);
            KEY_NUM("light_upload_ms", f->light_clip.upload_ms);
            KEY_SIZE("light_uploads", (size_t)f->light_clip.uploads);
            KEY_SIZE("light_first_level", (size_t)f->light_clip.first_level);
            KEY_SIZE("light_missing_blocks", (size_t)f->light_clip.missing);
        } else if (f->light_source == TP_VIEW_LIGHT_WINDOW) {
            KEY_NUM("light_window_ms", f->shadow_ms);
            KEY_SIZE("light_window_posts", (size_t)f->shadow_posts);
        }
    }
#undef KEY_NUM
#undef KEY_SIZE
    if (first && first->known)
        write_first(&j, first);
    tp_json_object_end(&j);
    return tp_atomic_commit(&file);
}

int tp_view_screenshot(tp_gl_context* ctx, const char* path)
{
    int w, h;
    tp_gl_context_size(ctx, &w, &h);
    uint8_t* px = malloc((size_t)w * h * 4);
    if (!px) {
        tp_cli_error("%s: out of memory", path);
        return 0;
    }
    tp_gl_context_read_rgba(ctx, px);
    tp_error err;
    tp_status s = tp_image_write_rgba(path, w, h, px, &err);
    free(px);
    if (s != TP_OK) {
        if (!tp_interrupted()) /* else main says "interrupted" */
            tp_cli_error("%s", err.message);
        return 0;
    }
    return 1;
}

int tp_view_load_texture(const tp_scene* sc, tp_renderer* r, const char* path)
{
    GLint max = 4096;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max);
    tp_texture* tex = NULL;
    tp_error err;
    if (tp_texture_build(path, sc->grid, max < 8192 ? max : 8192, &tex, &err) != TP_OK) {
        tp_cli_error("%s", err.message);
        return 0;
    }
    /* Tiled-grid sample x sits at render-grid x * ratio (1 unless the fit resampled), whose
     * pixel centre is at u = (x_render + 0.5) / render width. */
    const tp_terrain_info* in = &sc->info;
    double rx = in->fit == TP_FIT_RESAMPLE ? (double)(in->src_width - 1) / (in->width - 1) : 1;
    double ry = in->fit == TP_FIT_RESAMPLE ? (double)(in->src_height - 1) / (in->height - 1) : 1;
    float scale[2] = {(float)(rx / sc->grid->width), (float)(ry / sc->grid->height)};
    float offset[2] = {(float)(0.5 / sc->grid->width), (float)(0.5 / sc->grid->height)};
    int ok = tp_renderer_set_texture(r, tex->rgba, tex->width, tex->height, scale, offset);
    if (!ok)
        tp_cli_error("%s: the GPU cannot hold a %dx%d texture", path, tex->width, tex->height);
    tp_texture_destroy(tex);
    return ok;
}
