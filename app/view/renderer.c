/* renderer.c - the patch renderer (see renderer.h). */
#define _POSIX_C_SOURCE 199309L
#include "renderer.h"

#include "gl_context.h"

#include <epoxy/gl.h>

#include <limits.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* One vertex on the GPU: 16 bytes. */
typedef struct gpu_vertex {
    int32_t x, y;    /* global grid coordinates (after crack removal) */
    float z;         /* height, metres */
    int8_t n[3];     /* unit normal * 127, world frame (east, north, up) */
    uint8_t flags;   /* bits 0-3: level, bit 4: filled void */
} gpu_vertex;

struct tp_renderer {
    const tp_terrain* t;
    tp_terrain_info info;
    GLuint prog, vao, vbo, ibo, ibo_custom;
    GLenum index_type;
    size_t level_offset[TP_MAX_LEVELS], level_count[TP_MAX_LEVELS];
    size_t slot_verts; /* (2^n+1)^2: one slot holds a patch at any level */
    int slots;      /* pool capacity */
    int* patch_slot;
    int* slot_patch;
    uint64_t* slot_stamp;
    uint8_t* patch_current; /* slot holds the patch's current vertex data */
    int* patch_custom;      /* incomplete patches: their triangle-list region, else -1 */
    GLsizei* custom_count;
    size_t custom_stride;   /* indices per region: 6 * 4^n */
    int custom_regions;
    uint64_t frame;
    tp_vertex* vtmp;
    gpu_vertex* gtmp;
    uint32_t* ttmp;
    GLsizei* counts;
    void** offsets;
    GLint* bases;
    GLint u_cell, u_frac, u_spacing, u_cam_z, u_exag, u_viewproj, u_sun, u_color_lod,
        u_hide_filled, u_hrange, u_textured, u_tex, u_tex_scale, u_tex_offset, u_grid,
        u_grid_origin;
    GLuint tex;
    float tex_scale[2], tex_offset[2];
};

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec * 1e3 + ts.tv_nsec / 1e6;
}

/* Shading is per vertex (hillshade, hypsometric or LoD colour, the filled-void tint): the
 * normals come from the full-resolution grid, so a coarse triangle is shaded from the terrain
 * it stands for; per-pixel work is left to what needs it (texture, grid lines). On llvmpipe
 * this halves the per-pixel cost (see docs/PERFORMANCE.md). */
static const char* vs_src =
    "#version 330 core\n"
    "layout(location = 0) in ivec2 a_grid;\n"
    "layout(location = 1) in float a_z;\n"
    "layout(location = 2) in vec3 a_normal;\n"
    "layout(location = 3) in uint a_flags;\n"
    "uniform ivec2 u_cell;   // the camera's grid cell\n"
    "uniform vec2 u_frac;    // camera position inside that cell, metres\n"
    "uniform vec2 u_spacing; // metres per grid step in x and y (signed, from the geotransform)\n"
    "uniform float u_cam_z;\n"
    "uniform float u_exag;\n"
    "uniform mat4 u_viewproj;\n"
    "uniform vec2 u_tex_scale, u_tex_offset;\n"
    "uniform vec3 u_sun;\n"
    "uniform int u_color_lod;\n"
    "uniform int u_hide_filled;\n"
    "uniform vec2 u_hrange;\n"
    "out vec2 v_uv;\n"
    "out vec2 v_rel;\n"
    "out vec3 v_base;    // colour before light\n"
    "out float v_light;\n"
    "out float v_tint;   // filled-void tint amount\n"
    "vec3 hypsometric(float t) {\n"
    "    vec3 c0 = vec3(0.33, 0.52, 0.30), c1 = vec3(0.62, 0.66, 0.40);\n"
    "    vec3 c2 = vec3(0.58, 0.47, 0.35), c3 = vec3(0.93, 0.93, 0.93);\n"
    "    t = clamp(t, 0.0, 1.0);\n"
    "    if (t < 0.4) return mix(c0, c1, t / 0.4);\n"
    "    if (t < 0.8) return mix(c1, c2, (t - 0.4) / 0.4);\n"
    "    return mix(c2, c3, (t - 0.8) / 0.2);\n"
    "}\n"
    "vec3 level_color(uint k) {\n"
    "    vec3 c[9] = vec3[9](vec3(0.20, 0.20, 0.80), vec3(0.10, 0.60, 0.90), vec3(0.10, 0.75, 0.55),\n"
    "                        vec3(0.45, 0.80, 0.20), vec3(0.90, 0.85, 0.15), vec3(0.95, 0.55, 0.10),\n"
    "                        vec3(0.90, 0.20, 0.15), vec3(0.70, 0.10, 0.50), vec3(0.95, 0.95, 0.95));\n"
    "    return c[min(k, 8u)];\n"
    "}\n"
    "void main() {\n"
    "    // integer rebase first: exact, the same for every patch sharing the vertex\n"
    "    vec2 d = vec2(a_grid - u_cell) * u_spacing - u_frac;\n"
    "    gl_Position = u_viewproj * vec4(d, a_z * u_exag - u_cam_z, 1.0);\n"
    "    vec3 n = normalize(vec3(a_normal.xy * u_exag, a_normal.z));\n"
    "    v_light = 0.3 + 0.7 * max(dot(n, u_sun), 0.0);\n"
    "    v_base = u_color_lod != 0 ? level_color(a_flags & 15u)\n"
    "                              : hypsometric((a_z - u_hrange.x) / max(u_hrange.y - u_hrange.x, 1.0));\n"
    "    v_tint = u_hide_filled == 0 ? 0.65 * float((a_flags >> 4u) & 1u) : 0.0;\n"
    "    v_uv = vec2(a_grid) * u_tex_scale + u_tex_offset;\n"
    "    v_rel = d;\n"
    "}\n";

static const char* fs_src =
    "#version 330 core\n"
    "in vec2 v_uv;\n"
    "in vec2 v_rel;\n"
    "in vec3 v_base;\n"
    "in float v_light;\n"
    "in float v_tint;\n"
    "uniform sampler2D u_tex;\n"
    "uniform float u_grid;        // line spacing, metres (0: none)\n"
    "uniform vec2 u_grid_origin;  // camera E, N modulo the spacing\n"
    "uniform int u_textured;      // 0 also when LoD colours are on\n"
    "out vec4 o_color;\n"
    "void main() {\n"
    "    vec3 base = v_base;\n"
    "    if (u_textured != 0) {\n"
    "        vec4 t = texture(u_tex, v_uv);\n"
    "        base = mix(base, t.rgb, t.a);\n"
    "    }\n"
    "    vec3 c = mix(base, vec3(0.85, 0.25, 0.75), v_tint) * v_light;\n"
    "    if (u_grid > 0.0) {\n"
    "        // distance to the nearest grid line in pixels, from the screen-space derivative\n"
    "        vec2 g = (v_rel + u_grid_origin) / u_grid;\n"
    "        vec2 w = fwidth(g);\n"
    "        vec2 px = abs(fract(g - 0.5) - 0.5) / max(w, vec2(1e-6));\n"
    "        float line = 1.0 - clamp(min(px.x, px.y) - 0.5, 0.0, 1.0);\n"
    "        // fade where lines would be closer than 4 pixels\n"
    "        line *= clamp(1.0 / (4.0 * max(w.x, w.y)) - 0.5, 0.0, 1.0);\n"
    "        c = mix(c, vec3(0.05, 0.05, 0.35), 0.8 * line);\n"
    "    }\n"
    "    o_color = vec4(c, 1.0);\n"
    "}\n";

static void setup_vertex_format(tp_renderer* r)
{
    glBindVertexArray(r->vao);
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glEnableVertexAttribArray(0);
    glVertexAttribIPointer(0, 2, GL_INT, sizeof(gpu_vertex), (void*)offsetof(gpu_vertex, x));
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 1, GL_FLOAT, GL_FALSE, sizeof(gpu_vertex), (void*)offsetof(gpu_vertex, z));
    glEnableVertexAttribArray(2);
    glVertexAttribPointer(2, 3, GL_BYTE, GL_TRUE, sizeof(gpu_vertex), (void*)offsetof(gpu_vertex, n));
    glEnableVertexAttribArray(3);
    glVertexAttribIPointer(3, 1, GL_UNSIGNED_BYTE, sizeof(gpu_vertex),
                           (void*)offsetof(gpu_vertex, flags));
}

/* Grows the vertex pool to `slots` slots, keeping what it holds. */
static int grow_pool(tp_renderer* r, int slots)
{
    /* Draws address a slot by its first vertex as a GLint base vertex. */
    if ((size_t)slots > (size_t)INT_MAX / r->slot_verts)
        return 0;
    size_t bytes = (size_t)slots * r->slot_verts * sizeof(gpu_vertex);
    int* sp = realloc(r->slot_patch, (size_t)slots * sizeof *sp);
    if (sp)
        r->slot_patch = sp;
    uint64_t* ss = realloc(r->slot_stamp, (size_t)slots * sizeof *ss);
    if (ss)
        r->slot_stamp = ss;
    if (!sp || !ss)
        return 0;
    for (int i = r->slots; i < slots; i++) {
        r->slot_patch[i] = -1;
        r->slot_stamp[i] = 0;
    }
    GLuint vbo;
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_COPY_WRITE_BUFFER, vbo);
    glBufferData(GL_COPY_WRITE_BUFFER, (GLsizeiptr)bytes, NULL, GL_DYNAMIC_DRAW);
    if (r->vbo) {
        glBindBuffer(GL_COPY_READ_BUFFER, r->vbo);
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0,
                            (GLsizeiptr)((size_t)r->slots * r->slot_verts * sizeof(gpu_vertex)));
        glDeleteBuffers(1, &r->vbo);
    }
    r->vbo = vbo;
    r->slots = slots;
    setup_vertex_format(r);
    return 1;
}

tp_renderer* tp_renderer_create(const tp_terrain* t, char* msg, size_t msg_size)
{
    tp_renderer* r = calloc(1, sizeof *r);
    if (!r) {
        snprintf(msg, msg_size, "out of memory");
        return NULL;
    }
    r->t = t;
    tp_terrain_get_info(t, &r->info);
    int n = r->info.n, pc = r->info.patch_count;
    size_t v = ((size_t)1 << n) + 1;
    r->slot_verts = v * v;

    r->prog = tp_gl_program(vs_src, fs_src, msg, msg_size);
    if (!r->prog) {
        free(r);
        return NULL;
    }
#define TP_UNIFORM(name) r->name = glGetUniformLocation(r->prog, #name)
    TP_UNIFORM(u_cell);
    TP_UNIFORM(u_frac);
    TP_UNIFORM(u_spacing);
    TP_UNIFORM(u_cam_z);
    TP_UNIFORM(u_exag);
    TP_UNIFORM(u_viewproj);
    TP_UNIFORM(u_sun);
    TP_UNIFORM(u_color_lod);
    TP_UNIFORM(u_hide_filled);
    TP_UNIFORM(u_hrange);
    TP_UNIFORM(u_textured);
    TP_UNIFORM(u_tex);
    TP_UNIFORM(u_tex_scale);
    TP_UNIFORM(u_tex_offset);
    TP_UNIFORM(u_grid);
    TP_UNIFORM(u_grid_origin);
#undef TP_UNIFORM

    /* The strips of every level, one after the other, in one index buffer. */
    r->index_type = n <= 7 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
    size_t isize = n <= 7 ? 2 : 4, total = 0;
    for (int k = 0; k <= n; k++)
        total += tp_strip_index_count(k);
    void* idx = malloc(total * isize);
    r->patch_slot = malloc((size_t)pc * sizeof *r->patch_slot);
    r->patch_current = calloc((size_t)pc, 1);
    r->patch_custom = malloc((size_t)pc * sizeof *r->patch_custom);
    r->vtmp = malloc(r->slot_verts * sizeof *r->vtmp);
    r->gtmp = malloc(r->slot_verts * sizeof *r->gtmp);
    r->custom_stride = 6 * ((size_t)1 << (2 * n));
    r->ttmp = malloc(r->custom_stride * sizeof *r->ttmp);
    r->counts = malloc((size_t)pc * sizeof *r->counts);
    r->offsets = malloc((size_t)pc * sizeof *r->offsets);
    r->bases = malloc((size_t)pc * sizeof *r->bases);
    if (!idx || !r->patch_slot || !r->patch_current || !r->patch_custom || !r->vtmp ||
        !r->gtmp || !r->ttmp || !r->counts || !r->offsets || !r->bases) {
        free(idx);
        snprintf(msg, msg_size, "out of memory");
        tp_renderer_destroy(r);
        return NULL;
    }
    size_t at = 0;
    for (int k = 0; k <= n; k++) {
        size_t c = tp_strip_index_count(k);
        r->level_offset[k] = at * isize;
        r->level_count[k] = c;
        if (isize == 2)
            tp_strip_build_u16(k, (uint16_t*)idx + at, c);
        else
            tp_strip_build_u32(k, (uint32_t*)idx + at, c);
        at += c;
    }
    glGenVertexArrays(1, &r->vao);
    glBindVertexArray(r->vao);
    glGenBuffers(1, &r->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(total * isize), idx, GL_STATIC_DRAW);
    free(idx);

    /* Patches next to nodata or padding draw their own triangle lists (always level n). */
    for (int p = 0; p < pc; p++) {
        tp_patch_info pi;
        tp_patch_get_info(t, p, &pi);
        r->patch_custom[p] = pi.complete ? -1 : r->custom_regions++;
        r->patch_slot[p] = -1;
    }
    r->custom_count = calloc((size_t)(r->custom_regions + 1), sizeof *r->custom_count);
    glGenBuffers(1, &r->ibo_custom);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo_custom);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER,
                 (GLsizeiptr)((size_t)(r->custom_regions ? r->custom_regions : 1) *
                              r->custom_stride * 4),
                 NULL, GL_DYNAMIC_DRAW);
    /* Start with room for a typical visible set; the pool grows when a frame needs more. */
    if (!r->custom_count || !grow_pool(r, pc < 512 ? pc : 512)) {
        snprintf(msg, msg_size, "out of memory");
        tp_renderer_destroy(r);
        return NULL;
    }
    return r;
}

void tp_renderer_destroy(tp_renderer* r)
{
    if (!r)
        return;
    glDeleteProgram(r->prog);
    if (r->tex)
        glDeleteTextures(1, &r->tex);
    glDeleteBuffers(1, &r->vbo);
    glDeleteBuffers(1, &r->ibo);
    glDeleteBuffers(1, &r->ibo_custom);
    glDeleteVertexArrays(1, &r->vao);
    free(r->patch_slot);
    free(r->slot_patch);
    free(r->slot_stamp);
    free(r->patch_current);
    free(r->patch_custom);
    free(r->custom_count);
    free(r->vtmp);
    free(r->gtmp);
    free(r->ttmp);
    free(r->counts);
    free(r->offsets);
    free(r->bases);
    free(r);
}

int tp_renderer_set_texture(tp_renderer* r, const uint8_t* rgba, int w, int h,
                            const float scale[2], const float offset[2])
{
    GLint max = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max);
    if (w > max || h > max)
        return 0;
    if (!r->tex)
        glGenTextures(1, &r->tex);
    glBindTexture(GL_TEXTURE_2D, r->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    /* top row first, and v grows downward with the grid rows: no flip needed */
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGBA8, w, h, 0, GL_RGBA, GL_UNSIGNED_BYTE, rgba);
    glGenerateMipmap(GL_TEXTURE_2D);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR_MIPMAP_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    for (int i = 0; i < 2; i++) {
        r->tex_scale[i] = scale[i];
        r->tex_offset[i] = offset[i];
    }
    return glGetError() == GL_NO_ERROR;
}

void tp_render_settings_default(tp_render_settings* s)
{
    memset(s, 0, sizeof *s);
    s->sun_azimuth_deg = 315;
    s->sun_elevation_deg = 45;
    s->exaggeration = 1;
    s->clear_rgb[0] = 0.55f;
    s->clear_rgb[1] = 0.70f;
    s->clear_rgb[2] = 0.90f;
}

/* A slot for patch p: its own, a free one, or the least recently used one not drawn this
 * frame; the pool doubles when every slot is in use this frame. */
static int slot_for(tp_renderer* r, int p)
{
    if (r->patch_slot[p] >= 0)
        return r->patch_slot[p];
    int best = -1;
    for (int i = 0; i < r->slots; i++) {
        if (r->slot_patch[i] < 0) {
            best = i;
            break;
        }
        if (r->slot_stamp[i] != r->frame && (best < 0 || r->slot_stamp[i] < r->slot_stamp[best]))
            best = i;
    }
    if (best < 0) {
        int old = r->slots, want = old * 2 > r->info.patch_count ? r->info.patch_count : old * 2;
        if (want <= old || !grow_pool(r, want))
            return -1;
        best = old;
    }
    if (r->slot_patch[best] >= 0) {
        r->patch_slot[r->slot_patch[best]] = -1;
        r->patch_current[r->slot_patch[best]] = 0;
    }
    r->slot_patch[best] = p;
    r->patch_slot[p] = best;
    r->patch_current[p] = 0;
    return best;
}

static void upload(tp_renderer* r, tp_selection* sel, int p, int slot)
{
    int k = tp_selection_level(sel, p), nb[4];
    tp_selection_neighbor_levels(sel, p, nb);
    int v = (1 << k) + 1, count = v * v;
    tp_patch_vertices(r->t, p, k, nb, r->vtmp, r->slot_verts);
    for (int i = 0; i < count; i++) {
        const tp_vertex* s = &r->vtmp[i];
        gpu_vertex* g = &r->gtmp[i];
        float nrm[3];
        tp_terrain_normal(r->t, s->x, s->y, nrm);
        g->x = s->x;
        g->y = s->y;
        g->z = isnan(s->z_m) ? 0.0f : s->z_m;
        for (int a = 0; a < 3; a++)
            g->n[a] = (int8_t)lrintf(nrm[a] * 127.0f);
        int filled = tp_terrain_sample_class(r->t, s->x, s->y) == TP_SAMPLE_FILLED;
        g->flags = (uint8_t)(k | (filled << 4));
    }
    glBindBuffer(GL_ARRAY_BUFFER, r->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, (GLintptr)((size_t)slot * r->slot_verts * sizeof(gpu_vertex)),
                    (GLsizeiptr)(count * sizeof(gpu_vertex)), r->gtmp);
    int c = r->patch_custom[p];
    if (c >= 0) {
        size_t nt = tp_patch_triangles(r->vtmp, k, r->ttmp, r->custom_stride / 3);
        r->custom_count[c] = (GLsizei)(3 * nt);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo_custom);
        glBufferSubData(GL_ELEMENT_ARRAY_BUFFER, (GLintptr)((size_t)c * r->custom_stride * 4),
                        (GLsizeiptr)(3 * nt * 4), r->ttmp);
    }
    r->patch_current[p] = 1;
}

void tp_renderer_draw(tp_renderer* r, tp_selection* sel, const tp_camera* cam,
                      const tp_render_settings* st, int finish, tp_render_stats* stats)
{
    memset(stats, 0, sizeof *stats);
    r->frame++;
    /* Element-buffer bindings belong to the bound vertex array: bind ours before any upload. */
    glBindVertexArray(r->vao);
    int pc = r->info.patch_count;
    double t0 = now_ms();
    /* Vertex data goes stale when the patch's or a neighbour's level changed. */
    for (int p = 0; p < pc; p++)
        if (tp_selection_dirty(sel, p))
            r->patch_current[p] = 0;
    tp_selection_clear_dirty(sel);
    int strips = 0, lists = 0;
    for (int p = 0; p < pc; p++) {
        if (!tp_selection_visible(sel, p))
            continue;
        int slot = slot_for(r, p);
        if (slot < 0)
            continue;
        r->slot_stamp[slot] = r->frame;
        if (!r->patch_current[p]) {
            upload(r, sel, p, slot);
            stats->uploads++;
        }
        stats->patches_drawn++;
        int c = r->patch_custom[p];
        /* A patch of nodata or padding only has no triangles. It must not become a zero-count
         * draw: Mesa 22.3 (llvmpipe) applies the wrong base vertex to the draws after a
         * zero-count one in glMultiDrawElementsBaseVertex, which dropped border patches. */
        if (c >= 0 && r->custom_count[c] == 0)
            continue;
        /* strips fill the arrays from the front, triangle lists from the back */
        int at = c < 0 ? strips++ : pc - 1 - lists++;
        int k = tp_selection_level(sel, p);
        r->counts[at] = c < 0 ? (GLsizei)r->level_count[k] : r->custom_count[c];
        r->offsets[at] = (void*)(c < 0 ? r->level_offset[k] : (size_t)c * r->custom_stride * 4);
        r->bases[at] = (GLint)((size_t)slot * r->slot_verts); /* < INT_MAX: grow_pool */
    }
    double t1 = now_ms();
    stats->upload_ms = t1 - t0;

    int w = 0, h = 0;
    GLint vp[4];
    glGetIntegerv(GL_VIEWPORT, vp);
    w = vp[2], h = vp[3];
    /* Far plane: the farthest corner of the terrain's box, with room. */
    /* the selection culled and chose levels for this exaggeration: draw exactly that surface */
    double exag = tp_selection_vertical_scale(sel);
    double far_m = cam->far_m;
    if (far_m <= 0) {
        double e0, n0, e1, n1;
        tp_terrain_grid_to_world(r->t, 0, 0, &e0, &n0);
        tp_terrain_grid_to_world(r->t, r->info.width - 1, r->info.height - 1, &e1, &n1);
        double dx = fmax(fabs(e0 - cam->position[0]), fabs(e1 - cam->position[0]));
        double dy = fmax(fabs(n0 - cam->position[1]), fabs(n1 - cam->position[1]));
        double dz = fmax(fabs(r->info.max_height_m * exag - cam->position[2]),
                         fabs(r->info.min_height_m * exag - cam->position[2]));
        far_m = 1.1 * sqrt(dx * dx + dy * dy + dz * dz) + 10;
    }
    tp_camera view = *cam;
    view.viewport_w_px = w;
    view.viewport_h_px = h;
    double vpd[16];
    float vpm[16];
    tp_camera_view_projection(&view, far_m, vpd);
    for (int i = 0; i < 16; i++)
        vpm[i] = (float)vpd[i];
    double cx, cy;
    tp_terrain_world_to_grid(r->t, cam->position[0], cam->position[1], &cx, &cy);
    double fx = floor(cx), fy = floor(cy);
    const double* gt = r->info.geotransform;

    glClearColor(st->clear_rgb[0], st->clear_rgb[1], st->clear_rgb[2], 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glEnable(GL_CULL_FACE);
    /* The strips are clockwise in (column, row): counter-clockwise from above when north-up. */
    glFrontFace(gt[1] * gt[5] < 0 ? GL_CCW : GL_CW);
    glPolygonMode(GL_FRONT_AND_BACK, st->wireframe ? GL_LINE : GL_FILL);
    glUseProgram(r->prog);
    glUniform2i(r->u_cell, (GLint)fx, (GLint)fy);
    glUniform2f(r->u_frac, (float)((cx - fx) * gt[1]), (float)((cy - fy) * gt[5]));
    glUniform2f(r->u_spacing, (float)gt[1], (float)gt[5]);
    glUniform1f(r->u_cam_z, (float)cam->position[2]);
    glUniform1f(r->u_exag, (float)exag);
    glUniformMatrix4fv(r->u_viewproj, 1, GL_FALSE, vpm);
    double az = st->sun_azimuth_deg * 3.14159265358979323846 / 180,
           el = st->sun_elevation_deg * 3.14159265358979323846 / 180;
    glUniform3f(r->u_sun, (float)(sin(az) * cos(el)), (float)(cos(az) * cos(el)), (float)sin(el));
    glUniform1i(r->u_color_lod, st->color_lod);
    glUniform1i(r->u_hide_filled, st->hide_filled);
    glUniform2f(r->u_hrange, (float)r->info.min_height_m, (float)r->info.max_height_m);
    glUniform1i(r->u_textured, r->tex != 0 && !st->color_lod);
    glUniform1f(r->u_grid, (float)st->grid_m);
    if (st->grid_m > 0)
        glUniform2f(r->u_grid_origin, (float)fmod(cam->position[0], st->grid_m),
                    (float)fmod(cam->position[1], st->grid_m));
    glUniform1i(r->u_tex, 0);
    glUniform2f(r->u_tex_scale, r->tex_scale[0], r->tex_scale[1]);
    glUniform2f(r->u_tex_offset, r->tex_offset[0], r->tex_offset[1]);
    if (r->tex) {
        glActiveTexture(GL_TEXTURE0);
        glBindTexture(GL_TEXTURE_2D, r->tex);
    }
    glBindVertexArray(r->vao);
    if (st->one_draw_per_patch) {
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
        for (int i = 0; i < strips; i++)
            glDrawElementsBaseVertex(GL_TRIANGLE_STRIP, r->counts[i], r->index_type,
                                     r->offsets[i], r->bases[i]);
        glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo_custom);
        for (int i = pc - lists; i < pc; i++)
            glDrawElementsBaseVertex(GL_TRIANGLES, r->counts[i], GL_UNSIGNED_INT, r->offsets[i],
                                     r->bases[i]);
        stats->draw_calls = strips + lists;
    } else {
        if (strips) {
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
            glMultiDrawElementsBaseVertex(GL_TRIANGLE_STRIP, r->counts, r->index_type,
                                          (const void* const*)r->offsets, strips, r->bases);
            stats->draw_calls++;
        }
        if (lists) {
            glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo_custom);
            glMultiDrawElementsBaseVertex(GL_TRIANGLES, r->counts + pc - lists, GL_UNSIGNED_INT,
                                          (const void* const*)(r->offsets + pc - lists), lists,
                                          r->bases + pc - lists);
            stats->draw_calls++;
        }
    }
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    if (finish)
        glFinish();
    stats->draw_ms = now_ms() - t1;
    stats->gpu_bytes = (size_t)r->slots * r->slot_verts * sizeof(gpu_vertex) +
                       (size_t)r->custom_regions * r->custom_stride * 4;
    for (int k = 0; k <= r->info.n; k++)
        stats->gpu_bytes += r->level_count[k] * (r->index_type == GL_UNSIGNED_SHORT ? 2 : 4);
}
