/*
 * renderer_draw.c - tp_renderer_draw_items (see renderer.h, renderer_internal.h): the items
 * uploaded (renderer_upload.c), their draws grouped by level and kind, the frame's GL state and
 * the terrain program's uniforms set (camera, sun, colours, grid, texture, imagery, light), the
 * draws submitted, and what the frame cost.
 */
#define _POSIX_C_SOURCE 200112L
#include "renderer_internal.h"

#include "clock.h"

#include <math.h>
#include <string.h>
#include <sys/resource.h>

static long minor_faults(void)
{
    struct rusage u;
    return getrusage(RUSAGE_SELF, &u) == 0 ? u.ru_minflt : 0;
}

double tp_render_far_box(const tp_camera* cam, const double gt[6], int width, int height,
                         double min_m, double max_m)
{
    double e0 = gt[0] + 0.5 * gt[1], n0 = gt[3] + 0.5 * gt[5];
    double e1 = gt[0] + (width - 0.5) * gt[1], n1 = gt[3] + (height - 0.5) * gt[5];
    double dx = fmax(fabs(e0 - cam->position[0]), fabs(e1 - cam->position[0]));
    double dy = fmax(fabs(n0 - cam->position[1]), fabs(n1 - cam->position[1]));
    double dz = fmax(fabs(max_m - cam->position[2]), fabs(min_m - cam->position[2]));
    return 1.1 * sqrt(dx * dx + dy * dy + dz * dz) + 10;
}

/* Sorts the drawn draws (r->counts, offsets, bases, ditem) into r->gcounts, goffsets, gbases,
 * gitem by group (r->draw_level: 3 * level + strip 0, triangle list 1, five-region set 2);
 * group g's draws are group_at[g] .. group_at[g + 1] - 1. */
static void group_draws(tp_renderer* r, size_t drawn, size_t group_at[3 * TP_MAX_LEVELS + 1])
{
    /* One multi-draw per group (each level's pool is its own buffer; strips, triangle lists,
     * five-region sets): group the draws. */
    memset(group_at, 0, (3 * TP_MAX_LEVELS + 1) * sizeof *group_at);
    for (size_t j = 0; j < drawn; j++)
        group_at[r->draw_level[j] + 1]++;
    for (int g = 0; g < 3 * TP_MAX_LEVELS; g++)
        group_at[g + 1] += group_at[g];
    size_t group_end[3 * TP_MAX_LEVELS];
    memcpy(group_end, group_at, sizeof group_end);
    for (size_t j = 0; j < drawn; j++) {
        size_t at = group_end[r->draw_level[j]]++;
        r->gcounts[at] = r->counts[j];
        r->goffsets[at] = r->offsets[j];
        r->gbases[at] = r->bases[j];
        r->gitem[at] = r->ditem[j];
    }
}

/* The frame's GL state (cleared, depth test, culling, fill mode, the program) and the uniforms
 * of the camera (its cell, the view-projection with the far plane, stats' near_m and far_m),
 * the sun, the colours, the grid and the draped texture. */
static void set_camera(tp_renderer* r, const tp_camera* cam, const tp_render_settings* st,
                       double exag, tp_render_stats* stats)
{
    GLint vp[4];
    glGetIntegerv(GL_VIEWPORT, vp);
    int w = vp[2], h = vp[3];
    const double* gt = r->grid.geotransform;
    /* Far plane: the farthest corner of the terrain's box, with room. */
    double far_m = cam->far_m;
    if (far_m <= 0)
        far_m = tp_render_far_box(cam, gt, r->grid.width, r->grid.height,
                                  r->grid.min_height_m * exag, r->grid.max_height_m * exag);
    tp_camera view = *cam;
    view.viewport_w_px = w;
    view.viewport_h_px = h;
    double vpd[16];
    float vpm[16];
    tp_camera_view_projection(&view, far_m, vpd);
    stats->near_m = cam->near_m > 0 ? cam->near_m : 1.0; /* as tp_camera_view_projection */
    stats->far_m = far_m;
    for (int i = 0; i < 16; i++)
        vpm[i] = (float)vpd[i];
    /* grid coordinates of the camera (the inverse of sample (x, y) at gt0 + (x + 0.5) * gt1) */
    double cx = (cam->position[0] - gt[0]) / gt[1] - 0.5;
    double cy = (cam->position[1] - gt[3]) / gt[5] - 0.5;
    double fx = floor(cx), fy = floor(cy);

    glClearColor(st->clear_rgb[0], st->clear_rgb[1], st->clear_rgb[2], 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    /* The strips are clockwise in (column, row): counter-clockwise from above when north-up. */
    glFrontFace(gt[1] * gt[5] < 0 ? GL_CCW : GL_CW);
    glPolygonMode(GL_FRONT_AND_BACK, st->wireframe ? GL_LINE : GL_FILL);
    const tp__program* p = r->p;
    glUseProgram(p->prog);
    glUniform2i(p->u_cell, (GLint)fx, (GLint)fy);
    glUniform2f(p->u_frac, (float)((cx - fx) * gt[1]), (float)((cy - fy) * gt[5]));
    glUniform2f(p->u_spacing, (float)gt[1], (float)gt[5]);
    glUniform1f(p->u_cam_z, (float)cam->position[2]);
    glUniform1f(p->u_exag, (float)exag);
    glUniformMatrix4fv(p->u_viewproj, 1, GL_FALSE, vpm);
    double az = st->sun_azimuth_deg * 3.14159265358979323846 / 180,
           el = st->sun_elevation_deg * 3.14159265358979323846 / 180;
    glUniform3f(p->u_sun, (float)(sin(az) * cos(el)), (float)(cos(az) * cos(el)), (float)sin(el));
    glUniform1i(p->u_color_lod, st->color_lod);
    glUniform1i(p->u_hide_filled, st->hide_filled);
    glUniform2f(p->u_hrange, (float)r->grid.min_height_m, (float)r->grid.max_height_m);
    glUniform1f(p->u_grid, (float)st->grid_m);
    if (st->grid_m > 0)
        glUniform2f(p->u_grid_origin, (float)fmod(cam->position[0], st->grid_m),
                    (float)fmod(cam->position[1], st->grid_m));
    glUniform1i(p->u_tex, 0);
    glUniform2f(p->u_tex_scale, r->tex_scale[0], r->tex_scale[1]);
    glUniform2f(p->u_tex_offset, r->tex_offset[0], r->tex_offset[1]);
    if (r->tex) {
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, r->tex);
    }
}

/* The features a draw of count items uses (TP_SHADE_*): what is set and shown. */
static unsigned draw_features(const tp_renderer* r, const tp_render_settings* st, size_t count)
{
    /* a texture per item: one draw each, its layer and mapping as uniforms */
    int blocks = r->blk_tex && r->blk_count == count && !st->color_lod;
    return (r->clip.texture && !st->color_lod && !blocks ? TP_SHADE_IMAGERY : 0) |
           (r->light.texture ? TP_SHADE_LIGHT : 0) | (r->normals.texture ? TP_SHADE_NORMALS : 0) |
           (r->shadow_tex && !r->light.texture ? TP_SHADE_SHADOW : 0) |
           (r->tex && !st->color_lod ? TP_SHADE_TEXTURE : 0) | (blocks ? TP_SHADE_BLOCKS : 0) |
           (st->grid_m > 0 ? TP_SHADE_GRID : 0);
}

/* The imagery (the clipmap, or a texture per item: returned 1 then) and the light (the streamed
 * light's clipmap, or the shadow window) of the program's features. */
static int set_imagery_light(tp_renderer* r, const tp_camera* cam, unsigned features)
{
    const tp__program* p = r->p;
    int blocks = (features & TP_SHADE_BLOCKS) != 0;
    tp__clip_uniforms_set(&p->clip_u, &r->clip, cam, (features & TP_SHADE_IMAGERY) != 0);
    tp__clip_uniforms_set(&p->light_u, &r->light, cam, 1);
    tp__clip_uniforms_set(&p->normal_u, &r->normals, cam, 1);
    glUniform1f(p->u_light_tau, (float)r->light_tau);
    glUniform1i(p->u_shadow, 3);
    glUniform4f(p->u_shadow_win, (float)r->shadow_win[0], (float)r->shadow_win[1],
                (float)r->shadow_win[2], (float)r->shadow_win[3]);
    if (r->shadow_tex) {
        glActiveTexture(GL_TEXTURE3);
        glBindTexture(GL_TEXTURE_2D, r->shadow_tex);
        glActiveTexture(GL_TEXTURE0);
    }
    glUniform1i(p->u_blk, 2);
    glUniform1i(p->u_blk_layer, -1);
    if (blocks) {
        glActiveTexture(GL_TEXTURE2);
        glBindTexture(GL_TEXTURE_2D_ARRAY, r->blk_tex);
        glActiveTexture(GL_TEXTURE0);
    }
    return blocks;
}

/* Draws r's grouped draws a .. b in one multi-draw, or, on a software rasteriser
 * (r->sync_indices), in runs that wait for it each time *since_sync reaches r->sync_indices
 * (TP_RENDER_SOFTWARE_SYNC_INDICES). */
static void multi_draw(tp_renderer* r, GLenum mode, GLenum type, size_t a, size_t b,
                       size_t* since_sync, tp_render_stats* stats)
{
    while (a < b) {
        size_t e = b;
        if (r->sync_indices) {
            for (e = a; e < b && *since_sync < r->sync_indices; e++)
                *since_sync += (size_t)r->gcounts[e];
        }
        glMultiDrawElementsBaseVertex(mode, r->gcounts + a, type,
                                      (const void* const*)(r->goffsets + a), (GLsizei)(e - a),
                                      r->gbases + a);
        stats->draw_calls++;
        if (r->sync_indices && *since_sync >= r->sync_indices) {
            glFinish();
            *since_sync = 0;
        }
        a = e;
    }
}

/* Submits the grouped draws, level by level: a multi-draw a group (its pool's vertex buffer, the
 * group's index buffer), else a draw an item (blocks: each with its texture's uniforms; or
 * st->one_draw_per_patch). five_ibo: the five-region sets' index buffer (0: none). */
static void submit_draws(tp_renderer* r, const size_t group_at[3 * TP_MAX_LEVELS + 1],
                         GLuint five_ibo, int blocks, const tp_render_settings* st,
                         tp_render_stats* stats)
{
    size_t since_sync = 0; /* indices submitted since the rasteriser last caught up */
    for (int k = 0; k <= r->grid.n; k++) {
        if (group_at[3 * k] == group_at[3 * k + 3])
            continue;
        tp__renderer_vertex_format(r, tp_vertex_pool_vertex_buffer(r->pool, k));
        for (int list = 0; list < 3; list++) { /* strips, triangle lists, five-region sets */
            size_t a = group_at[3 * k + list], b = group_at[3 * k + list + 1];
            GLuint ebo = list == 0   ? r->ibo
                         : list == 1 ? tp_vertex_pool_index_buffer(r->pool, k)
                                     : five_ibo;
            if (a == b || !ebo)
                continue;
            stats->draws += (int)(b - a);
            GLenum mode = list ? GL_TRIANGLES : GL_TRIANGLE_STRIP;
            GLenum type = list == 1   ? tp_vertex_pool_index_type(r->pool, k)
                          : list == 2 ? GL_UNSIGNED_INT
                                      : r->index_type;
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, ebo);
            if (blocks) {
                for (size_t j = a; j < b; j++) {
                    const tp_render_item_texture* t = &r->blk[r->gitem[j]];
                    glUniform1i(r->p->u_blk_layer, t->layer);
                    glUniform2i(r->p->u_blk_cell, t->cell[0], t->cell[1]);
                    glUniform2f(r->p->u_blk_scale, t->scale[0], t->scale[1]);
                    glUniform2f(r->p->u_blk_offset, t->offset[0], t->offset[1]);
                    glDrawElementsBaseVertex(mode, r->gcounts[j], type, r->goffsets[j],
                                             r->gbases[j]);
                }
                stats->draw_calls += (int)(b - a);
            } else if (st->one_draw_per_patch) {
                for (size_t j = a; j < b; j++)
                    glDrawElementsBaseVertex(mode, r->gcounts[j], type, r->goffsets[j],
                                             r->gbases[j]);
                stats->draw_calls += (int)(b - a);
            } else {
                multi_draw(r, mode, type, a, b, &since_sync, stats);
            }
        }
    }
}

void tp_renderer_draw_items(tp_renderer* r, const tp_render_item* items, size_t count,
                            tp_render_fill_fn fill, void* user, const tp_camera* cam,
                            const tp_render_settings* st, double exag, int finish,
                            tp_render_stats* stats)
{
    memset(stats, 0, sizeof *stats);
    unsigned features = draw_features(r, st, count);
    tp_error perr;
    if (!(r->p = tp__renderer_program(r, features, &perr)))
        return; /* cannot happen: every program is a subset of the one made at creation */
    tp_vertex_pool_begin_frame(r->pool);
    /* Element-buffer bindings belong to the bound vertex array: bind ours before any upload. */
    glBindVertexArray(r->vao);
    double t0 = tp_clock_ms();
    int five = r->stitch_add && r->stitch_add_five, per = five ? 5 : 1; /* draws an item takes */
    if (!tp__renderer_grow_draws(r, per * count))
        count = r->draw_cap / per; /* draw what fits; the next frame tries again */
    size_t drawn = tp__renderer_upload(r, items, count, fill, user, stats);
    size_t group_at[3 * TP_MAX_LEVELS + 1];
    group_draws(r, drawn, group_at);
    size_t five_bytes = 0; /* the sets made this frame go to the GPU with the upload */
    GLuint five_ibo = five ? tp__stitch_five_gl_buffer(r->five, &five_bytes) : 0;
    double t1 = tp_clock_ms();
    stats->upload_ms = t1 - t0;
    long faults0 = minor_faults();

    set_camera(r, cam, st, exag, stats);
    int blocks = set_imagery_light(r, cam, features);
    submit_draws(r, group_at, five_ibo, blocks, st, stats);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    if (finish)
        glFinish();
    stats->draw_ms = tp_clock_ms() - t1;
    stats->page_faults = minor_faults() - faults0;
    stats->gpu_bytes = tp_vertex_pool_gpu_bytes(r->pool) + five_bytes;
    stats->index_gpu_bytes = tp_vertex_pool_index_bytes(r->pool) + five_bytes;
    for (int k = 0; k <= r->grid.n; k++) {
        size_t b = r->level_count[k] * (r->index_type == GL_UNSIGNED_SHORT ? 2 : 4);
        stats->gpu_bytes += b;
        stats->index_gpu_bytes += b;
    }
    if (r->stitch_add)
        stats->index_cpu_bytes =
            five ? tp__stitch_five_cpu_bytes(r->five) : tp__stitch_add_cpu_bytes(r->add);
}
