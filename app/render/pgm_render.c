/* pgm_render.c - Persistent Grid Mapping on the GPU (see pgm_render.h). */
#define _POSIX_C_SOURCE 200112L
#include "pgm_render.h"
#include "clock.h"

#include "cli.h"
#include "gl_context.h"
#include "pgm_clip.h"
#include "terrain_shaders.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* The vertex shader computes what tp_pgm_map_vertex computes (tp_core.h), in floats, relative
 * to the eye; it shades per vertex as the patch renderer does (terrain_shaders.c: hillshade
 * over hypsometric colours), the normal from the height differences of the vertex's level. */
static const char vertex_head[] =
    "#version 330 core\n"
    "uniform int u_cols;\n"
    "uniform vec2 u_px_step;   // auxiliary-camera pixels per grid step: w / (cols-1), h / "
    "(rows-1)\n"
    "uniform vec2 u_half;      // w / 2, h / 2\n"
    "uniform float u_focal;    // the auxiliary camera's focal length, pixels\n"
    "uniform vec3 u_fwd, u_right, u_up; // its frame (world: E, N, up)\n"
    "uniform float u_base_rel; // the plane the rays meet, relative to the eye: -eye_above_base_m\n"
    "uniform float u_h;        // Eq. 3's h: eye above the base plane, >= 1 m\n"
    "uniform float u_sin_a, u_cos_a, u_post_m;\n"
    "uniform int u_levels;\n"
    "uniform vec2 u_eye_grid;  // the eye in level-0 grid coordinates (post (0,0) at (0,0))\n"
    "uniform vec2 u_inv_step;  // grid steps per metre east and north: 1 / gt[1], 1 / gt[5]\n"
    "uniform vec2 u_step;      // gt[1], gt[5]\n"
    "uniform ivec2 u_size[24]; // each level's posts\n"
    "#ifdef TP_CLIP\n"
    "// a store's clipmap (pgm_clip.h): level l in layer l, post p at texel p mod w, held\n"
    "// only inside its window: posts u_org[l] .. u_org[l] + w - 1\n"
    "uniform sampler2DArray u_clip;\n"
    "uniform ivec2 u_org[24];\n"
    "uniform int u_win;\n"
    "float fetch(int l, ivec2 p) { return texelFetch(u_clip, ivec3(p & (u_win - 1), l), 0).r; }\n"
    "bool held(int l, ivec2 i, ivec2 i1) {\n"
    "    return all(greaterThanEqual(i, u_org[l])) && all(lessThan(i1, u_org[l] + u_win));\n"
    "}\n"
    "#else\n"
    "uniform ivec2 u_off[24];  // each level's texel offset in the atlas\n"
    "uniform sampler2D u_atlas;\n"
    "float fetch(int l, ivec2 p) { return texelFetch(u_atlas, u_off[l] + p, 0).r; }\n"
    "bool held(int l, ivec2 i, ivec2 i1) { return true; }\n"
    "#endif\n"
    "uniform sampler2D u_valid; // level 0: 1 where a post has a height (R8)\n"
    "uniform float u_eye_z;\n"
    "uniform mat4 u_viewproj;  // the main camera's, eye at the origin\n"
    "uniform vec3 u_sun;\n"
    "uniform vec2 u_hrange;\n"
    "uniform int u_color_lod;\n"
    "out float v_off;          // > 0 where a vertex of the triangle is off the terrain\n"
    "out vec3 v_color;\n"
    "// tp_pgm_pyramid_sample: x0 clamped to the level-0 extent, then level l bilinear at\n"
    "// x0 / 2^l between its posts; over a clipmap, the first level from l up whose window\n"
    "// holds the four posts (the last level always does)\n"
    "float sample_level(int l0, vec2 x0) {\n"
    "    for (int l = l0; l < u_levels; l++) {\n"
    "        ivec2 n = u_size[l];\n"
    "        vec2 u = clamp(x0, vec2(0.0), vec2(u_size[0] - 1)) * exp2(-float(l));\n"
    "        u = min(u, vec2(n - 1));\n"
    "        ivec2 i = min(ivec2(floor(u)), max(n - 2, ivec2(0)));\n"
    "        vec2 f = u - vec2(i);\n"
    "        ivec2 i1 = min(i + 1, n - 1);\n"
    "        if (l + 1 < u_levels && !held(l, i, i1)) continue;\n"
    "        float a = fetch(l, i), b = fetch(l, ivec2(i1.x, i.y));\n"
    "        float c = fetch(l, ivec2(i.x, i1.y)), d = fetch(l, i1);\n"
    "        // a clipmap's void texel (-3e38) voids the sample: no arithmetic on it\n"
    "        if (min(min(a, b), min(c, d)) < -1e30) return -3e38;\n"
    "        return mix(mix(a, b, f.x), mix(c, d, f.x), f.y);\n"
    "    }\n"
    "    return 0.0;\n"
    "}\n"
    "// every post of level 0's cell around g has a height\n"
    "uniform int u_has_valid;\n"
    "bool valid_at(vec2 g) {\n"
    "    if (u_has_valid == 0) return true;\n"
    "    ivec2 n = u_size[0], i = min(ivec2(floor(clamp(g, vec2(0.0), vec2(n - 1)))), n - 1);\n"
    "    ivec2 i1 = min(i + 1, n - 1);\n"
    "    return min(min(texelFetch(u_valid, i, 0).r, texelFetch(u_valid, ivec2(i1.x, i.y), 0).r),\n"
    "               min(texelFetch(u_valid, ivec2(i.x, i1.y), 0).r, texelFetch(u_valid, i1, 0).r)) "
    "> 0.5;\n"
    "}\n"
    TP_GLSL_HYPSOMETRIC
    "vec3 level_color(int k) {\n"
    TP_GLSL_LEVEL_COLORS
    "    return c[min(k, 8)];\n"
    "}\n";

/* (two literals: C99 promises 4095 characters a literal) */
static const char vertex_main[] =
    "void main() {\n"
    "    int i = gl_VertexID % u_cols, j = gl_VertexID / u_cols;\n"
    "    // Eq. 2's camera: the ray through its pixel (i * w / (cols-1), j * h / (rows-1))\n"
    "    vec2 px = vec2(i, j) * u_px_step;\n"
    "    float a = (px.x - u_half.x) / u_focal, b = -(px.y - u_half.y) / u_focal;\n"
    "    vec3 dir = normalize(u_fwd + a * u_right + b * u_up);\n"
    "    // Eq. 1: where it meets the base plane\n"
    "    float t = u_base_rel / min(dir.z, -1e-9);\n"
    "    vec3 p = t * dir;\n"
    "    // Eq. 3: r, the distance to the farthest neighbour; its level and Eq. 4's parent weight\n"
    "    float d = length(p), q = length(p.xy);\n"
    "    float den = u_h * u_cos_a - q * u_sin_a;\n"
    "    float r = den > 0.0 ? d * d * u_sin_a / den : 1e30;\n"
    "    int last = u_levels - 1;\n"
    "    int l = r >= u_post_m ? min(int(floor(log2(r / u_post_m))), last) : 0;\n"
    "    float w = l == last ? 0.0 : clamp(r / (u_post_m * exp2(float(l))) - 1.0, 0.0, 1.0);\n"
    "    vec2 g = u_eye_grid + p.xy * u_inv_step;\n"
    "    float z = sample_level(l, g);\n"
    "    if (w > 0.0) {\n"
    "        float zp = sample_level(l + 1, g);\n"
    "        z = min(z, zp) < -1e30 ? -3e38 : mix(z, zp, w);\n"
    "    }\n"
    "    vec2 lim = vec2(u_size[0] - 1);\n"
    "    v_off = all(greaterThanEqual(g, vec2(0.0))) && all(lessThanEqual(g, lim)) && valid_at(g) "
    "&& z > -1e30 ? 0.0 : 1.0; // (a clipmap's void texels: -3e38)\n"
    "    gl_Position = u_viewproj * vec4(p.xy, z - u_eye_z, 1.0);\n"
    "    // shading: the slope of level l over one of its posts\n"
    "    float s = exp2(float(l));\n"
    "    float e1 = sample_level(l, g + vec2(s, 0.0)), e0 = sample_level(l, g - vec2(s, 0.0));\n"
    "    float n1 = sample_level(l, g + vec2(0.0, s)), n0 = sample_level(l, g - vec2(0.0, s));\n"
    "#ifdef TP_CLIP\n"
    "    // next to a clipmap's void: the vertex's own height (flat that side)\n"
    "    float zc = z > -1e30 ? z : 0.0;\n"
    "    e1 = e1 > -1e30 ? e1 : zc, e0 = e0 > -1e30 ? e0 : zc;\n"
    "    n1 = n1 > -1e30 ? n1 : zc, n0 = n0 > -1e30 ? n0 : zc;\n"
    "#endif\n"
    "    float dx = e1 - e0, dy = n1 - n0;\n"
    "    vec3 n = normalize(vec3(-dx / (2.0 * s * u_step.x), -dy / (2.0 * s * u_step.y), 1.0));\n"
    "    float light = 0.3 + 0.7 * max(dot(n, u_sun), 0.0);\n"
    "    vec3 base = u_color_lod != 0 ? level_color(l)\n"
    "                                 : hypsometric((z - u_hrange.x) / max(u_hrange.y - "
    "u_hrange.x, 1.0));\n"
    "    v_color = base * light;\n"
    "}\n";

static const char fragment_src[] = "#version 330 core\n"
                                   "in float v_off;\n"
                                   "in vec3 v_color;\n"
                                   "out vec4 o_color;\n"
                                   "void main() {\n"
                                   "    if (v_off > 0.0) discard; // a vertex off the terrain\n"
                                   "    o_color = vec4(v_color, 1.0);\n"
                                   "}\n";

struct tp_pgm_renderer {
    const tp_pgm_pyramid* p; /* over a clipmap its shape: no heights */
    tp_pgm_clipmap* clip;    /* NULL: the whole pyramid in the atlas */
    int clip_error_told;
    int cols, rows;
    GLuint prog, vao, ibo, atlas, valid;
    size_t index_count, gpu_bytes;
    int off[TP_PGM_MAX_LEVELS][2];
    GLint u_cols, u_px_step, u_half, u_focal, u_fwd, u_right, u_up, u_base_rel, u_h, u_sin_a,
        u_cos_a, u_post_m, u_levels, u_eye_grid, u_inv_step, u_step, u_off, u_size, u_atlas,
        u_valid, u_has_valid, u_eye_z, u_viewproj, u_sun, u_hrange, u_color_lod, u_clip, u_org,
        u_win;
};

/* Fills the NaN of n values v[0], v[step], ... from the nearest non-NaN one (ties: the lower
 * index); leaves them when there is none. */
static void fill_line(float* v, int n, size_t step)
{
    int last = -1;
    for (int i = 0; i < n; i++) {
        if (isnan(v[i * step]))
            continue;
        int from = last < 0 ? 0 : (last + i) / 2 + 1;
        for (int k = from; k < i; k++)
            v[k * step] = v[i * step];
        for (int k = last + 1; last >= 0 && k < from; k++)
            v[k * step] = v[last * step];
        last = i;
    }
    for (int k = last + 1; last >= 0 && k < n; k++)
        v[k * step] = v[last * step];
}

tp_status tp_pgm_pyramid_from_grid(const float* heights, int width, int height, const double gt[6],
                                   tp_pgm_pyramid* out, uint8_t** valid, tp_error* err)
{
    size_t n = (size_t)width * (size_t)height, voids = 0;
    float lo = INFINITY;
    for (size_t k = 0; k < n; k++) {
        if (heights[k] < lo)
            lo = heights[k];
        voids += isnan(heights[k]) != 0;
    }
    if (!isfinite(lo))
        lo = 0; /* nothing drawn at all */
    *valid = NULL;
    float* z = malloc(n * sizeof *z);
    uint8_t* mask = voids ? malloc(n) : NULL;
    if (!z || (voids && !mask)) {
        free(z);
        free(mask);
        memset(out, 0, sizeof *out);
        if (err)
            snprintf(err->message, sizeof err->message, "out of memory");
        return TP_ERR_OUT_OF_MEMORY;
    }
    memcpy(z, heights, n * sizeof *z);
    if (voids) {
        for (size_t k = 0; k < n; k++)
            mask[k] = !isnan(heights[k]);
        for (int y = 0; y < height; y++)
            fill_line(z + (size_t)y * width, width, 1);
        for (int x = 0; x < width; x++)
            fill_line(z + x, height, (size_t)width);
        for (size_t k = 0; k < n; k++)
            if (isnan(z[k]))
                z[k] = lo;
    }
    tp_status s = tp_pgm_pyramid_build(z, width, height, gt, out, err);
    free(z);
    if (s != TP_OK)
        free(mask);
    else
        *valid = mask;
    return s;
}

/* Places the levels: level 0 at (0, 0), the coarser ones in a column to its right or in a row
 * below it, whichever makes the atlas's longer side shorter. */
static void pack_atlas(tp_pgm_renderer* r, int* aw, int* ah)
{
    const tp_pgm_pyramid* p = r->p;
    long col_h = 0, row_w = 0;
    for (int l = 1; l < p->levels; l++) {
        col_h += p->height[l];
        row_w += p->width[l];
    }
    long w1 = p->levels > 1 ? p->width[1] : 0, h1 = p->levels > 1 ? p->height[1] : 0;
    long colw = p->width[0] + w1, colh = col_h > p->height[0] ? col_h : p->height[0];
    long roww = row_w > p->width[0] ? row_w : p->width[0], rowh = p->height[0] + h1;
    int column = (colw > colh ? colw : colh) <= (roww > rowh ? roww : rowh);
    long at = 0;
    r->off[0][0] = r->off[0][1] = 0;
    for (int l = 1; l < p->levels; l++) {
        r->off[l][0] = column ? p->width[0] : (int)at;
        r->off[l][1] = column ? (int)at : p->height[0];
        at += column ? p->height[l] : p->width[l];
    }
    *aw = (int)(column ? colw : roww);
    *ah = (int)(column ? colh : rowh);
}

/* The program (TP_CLIP defined over a clipmap), its uniforms and the grid's index buffer; NULL
 * with err on failure. */
static tp_pgm_renderer* make_grid(const tp_pgm_pyramid* p, tp_pgm_clipmap* clip, int cols, int rows,
                                  tp_error* err)
{
    if (cols < 2 || rows < 2 || p->levels < 1) {
        tp_error_set(err, TP_ERR_INVALID_ARG,
                     "persistent grid %dx%d: need at least 2x2 vertices and a pyramid", cols, rows);
        return NULL;
    }
    tp_pgm_renderer* r = calloc(1, sizeof *r);
    if (!r) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    r->p = p;
    r->clip = clip;
    r->cols = cols;
    r->rows = rows;
    static const char version[] = "#version 330 core\n", define[] = "#define TP_CLIP 1\n";
    size_t head = sizeof vertex_head - 1, vlen = sizeof version - 1;
    char* vs = malloc(sizeof define + head + sizeof vertex_main);
    if (vs) { /* the #define goes after #version */
        size_t at = 0;
        memcpy(vs, vertex_head, vlen);
        at = vlen;
        if (clip) {
            memcpy(vs + at, define, sizeof define - 1);
            at += sizeof define - 1;
        }
        memcpy(vs + at, vertex_head + vlen, head - vlen);
        memcpy(vs + at + head - vlen, vertex_main, sizeof vertex_main);
        r->prog = tp_gl_program(vs, fragment_src, err);
        free(vs);
    } else {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
    }
    if (!r->prog) {
        free(r);
        return NULL;
    }
#define U(name) r->name = glGetUniformLocation(r->prog, #name)
    U(u_cols), U(u_px_step), U(u_half), U(u_focal), U(u_fwd), U(u_right), U(u_up), U(u_base_rel);
    U(u_h), U(u_sin_a), U(u_cos_a), U(u_post_m), U(u_levels), U(u_eye_grid), U(u_inv_step);
    U(u_step), U(u_off), U(u_size), U(u_atlas), U(u_valid), U(u_has_valid), U(u_eye_z),
        U(u_viewproj), U(u_sun);
    U(u_hrange), U(u_color_lod), U(u_clip), U(u_org), U(u_win);
#undef U
    /* cell (i, j): (i,j) (i+1,j) (i,j+1) and (i+1,j) (i+1,j+1) (i,j+1), as tp_core.h splits */
    size_t cells = (size_t)(cols - 1) * (size_t)(rows - 1);
    r->index_count = 6 * cells;
    uint32_t* idx = malloc(r->index_count * sizeof *idx);
    if (!idx) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        tp_pgm_renderer_destroy(r);
        return NULL;
    }
    size_t k = 0;
    for (int j = 0; j + 1 < rows; j++)
        for (int i = 0; i + 1 < cols; i++) {
            uint32_t v = (uint32_t)j * (uint32_t)cols + (uint32_t)i;
            idx[k++] = v, idx[k++] = v + 1, idx[k++] = v + (uint32_t)cols;
            idx[k++] = v + 1, idx[k++] = v + 1 + (uint32_t)cols, idx[k++] = v + (uint32_t)cols;
        }
    glGenVertexArrays(1, &r->vao);
    glBindVertexArray(r->vao);
    glGenBuffers(1, &r->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, r->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(r->index_count * sizeof *idx), idx,
                 GL_STATIC_DRAW);
    free(idx);
    glBindVertexArray(0);
    r->gpu_bytes = r->index_count * sizeof(uint32_t);
    return r;
}

tp_pgm_renderer* tp_pgm_renderer_create_clipmap(tp_pgm_clipmap* clip, int cols, int rows,
                                                tp_error* err)
{
    tp_pgm_renderer* r = make_grid(tp_pgm_clipmap_shape(clip), clip, cols, rows, err);
    if (r)
        r->gpu_bytes += tp_pgm_clipmap_gpu_bytes(clip);
    return r;
}

tp_pgm_renderer* tp_pgm_renderer_create(const tp_pgm_pyramid* p, const uint8_t* valid, int cols,
                                        int rows, tp_error* err)
{
    int aw = 0, ah = 0;
    GLint max = 0;
    glGetIntegerv(GL_MAX_TEXTURE_SIZE, &max);
    tp_pgm_renderer probe = {.p = p};
    if (p->levels >= 1)
        pack_atlas(&probe, &aw, &ah);
    if (aw > max || ah > max) {
        tp_error_set(err, TP_ERR_BACKEND,
                     "PGM: the elevation pyramid of a %dx%d grid needs a %dx%d texture atlas; this "
                     "GPU's GL_MAX_TEXTURE_SIZE is %d (build a store of the DEM and view the store "
                     "with --renderer pgm: its clipmaps fit any size)",
                     p->width[0], p->height[0], aw, ah, (int)max);
        return NULL;
    }
    tp_pgm_renderer* r = make_grid(p, NULL, cols, rows, err);
    if (!r)
        return NULL;
    memcpy(r->off, probe.off, sizeof r->off);
    /* errors earlier calls left would read as the upload's below (bounded: a lost context) */
    for (int k = 0; k < 64 && glGetError() != GL_NO_ERROR; k++)
        ;
    glGenTextures(1, &r->atlas);
    glBindTexture(GL_TEXTURE_2D, r->atlas);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_R32F, aw, ah, 0, GL_RED, GL_FLOAT, NULL);
    for (int l = 0; l < p->levels; l++)
        glTexSubImage2D(GL_TEXTURE_2D, 0, r->off[l][0], r->off[l][1], p->width[l], p->height[l],
                        GL_RED, GL_FLOAT, p->z[l]);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
    glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
    r->gpu_bytes += (size_t)aw * (size_t)ah * 4;
    if (valid) { /* 0 or 1 per level-0 post, read as 0 or 1/255 by texelFetch: > 0.5 needs 255 */
        size_t n = (size_t)p->width[0] * (size_t)p->height[0];
        uint8_t* v255 = malloc(n);
        if (!v255) {
            tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
            tp_pgm_renderer_destroy(r);
            return NULL;
        }
        for (size_t k = 0; k < n; k++)
            v255[k] = valid[k] ? 255 : 0;
        glGenTextures(1, &r->valid);
        glBindTexture(GL_TEXTURE_2D, r->valid);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
        glTexImage2D(GL_TEXTURE_2D, 0, GL_R8, p->width[0], p->height[0], 0, GL_RED,
                     GL_UNSIGNED_BYTE, v255);
        glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
        free(v255);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_NEAREST);
        glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAX_LEVEL, 0);
        r->gpu_bytes += n;
    }
    GLenum e = glGetError();
    if (e != GL_NO_ERROR) {
        tp_error_set(err, TP_ERR_BACKEND,
                     "PGM: uploading the %dx%d atlas and %zu indices failed (GL error "
                     "0x%x)",
                     aw, ah, r->index_count, (unsigned)e);
        tp_pgm_renderer_destroy(r);
        return NULL;
    }
    return r;
}

void tp_pgm_renderer_destroy(tp_pgm_renderer* r)
{
    if (!r)
        return;
    if (r->prog)
        glDeleteProgram(r->prog);
    if (r->atlas)
        glDeleteTextures(1, &r->atlas);
    if (r->valid)
        glDeleteTextures(1, &r->valid);
    if (r->ibo)
        glDeleteBuffers(1, &r->ibo);
    if (r->vao)
        glDeleteVertexArrays(1, &r->vao);
    free(r);
}

void tp_pgm_renderer_grid(const tp_pgm_renderer* r, int* cols, int* rows)
{
    *cols = r->cols;
    *rows = r->rows;
}

tp_status tp_pgm_renderer_measure(const tp_pgm_renderer* r, const tp_camera* cam, size_t max_posts,
                                  tp_pgm_error* out, tp_error* err)
{
    tp_pgm_frame f;
    tp_pgm_frame_setup(cam, r->cols, r->rows, r->p, &f);
    if (r->clip)
        return tp_pgm_clipmap_measure(r->clip, &f, cam, max_posts, out, err);
    tp_status st = tp_pgm_measure_error(&f, r->p, cam, out);
    if (st != TP_OK)
        tp_error_set(err, st, "PGM error: out of memory");
    return st;
}

/* The far plane: the farthest corner of the terrain's box, with room (as the patch renderer's). */
static double far_plane(const tp_pgm_pyramid* p, const tp_camera* cam)
{
    if (cam->far_m > 0)
        return cam->far_m;
    return tp_render_far_box(cam, p->geotransform, p->width[0], p->height[0], p->min_m, p->max_m);
}

void tp_pgm_renderer_draw(tp_pgm_renderer* r, const tp_camera* cam, const tp_render_settings* s,
                          int finish, tp_pgm_frame* frame_out, tp_pgm_render_stats* stats)
{
    memset(stats, 0, sizeof *stats);
    double t0 = tp_clock_ms();
    const tp_pgm_pyramid* p = r->p;
    GLint vp[4];
    glGetIntegerv(GL_VIEWPORT, vp);
    tp_camera view = *cam;
    view.viewport_w_px = vp[2];
    view.viewport_h_px = vp[3];
    tp_pgm_frame f;
    tp_pgm_frame_setup(&view, r->cols, r->rows, p, &f);
    if (frame_out)
        *frame_out = f;
    double far_m = far_plane(p, cam), vpd[16];
    float vpm[16];
    tp_camera_view_projection(&view, far_m, vpd);
    for (int i = 0; i < 16; i++)
        vpm[i] = (float)vpd[i];
    const tp_camera_frame* a = &f.aux_frame;
    const double* gt = p->geotransform;
    const double* eye = cam->position;
    /* the eye in level-0 grid coordinates: post (x, y) at E = gt0 + (x + 0.5) * gt1 */
    double eye_x = (eye[0] - gt[0]) / gt[1] - 0.5, eye_y = (eye[1] - gt[3]) / gt[5] - 0.5;
    if (r->clip) { /* the windows follow the eye before the shader reads them */
        tp_pgm_clip_stats cs;
        tp_error err = {{0}};
        if (!tp_pgm_clipmap_update(r->clip, eye_x, eye_y, &cs, &err) && !r->clip_error_told) {
            tp_cli_error("%s (those posts are not drawn)", err.message);
            r->clip_error_told = 1;
        }
        stats->fill_ms = cs.fill_ms;
        stats->upload_ms = cs.upload_ms;
        stats->posts_updated = cs.posts;
        stats->node_reads = cs.node_reads;
        if (!tp_pgm_clipmap_filled(r->clip)) { /* its texels are uninitialised: clear only */
            glClearColor(s->clear_rgb[0], s->clear_rgb[1], s->clear_rgb[2], 1);
            glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
            stats->cols = r->cols;
            stats->rows = r->rows;
            stats->gpu_bytes = r->gpu_bytes;
            stats->setup_ms = tp_clock_ms() - t0;
            return;
        }
    }

    glClearColor(s->clear_rgb[0], s->clear_rgb[1], s->clear_rgb[2], 1);
    glClear(GL_COLOR_BUFFER_BIT | GL_DEPTH_BUFFER_BIT);
    glEnable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE); /* a mapped grid may fold over itself behind a ridge */
    glPolygonMode(GL_FRONT_AND_BACK, s->wireframe ? GL_LINE : GL_FILL);
    glUseProgram(r->prog);
    glUniform1i(r->u_cols, r->cols);
    glUniform2f(r->u_px_step, (float)((double)a->width_px / (r->cols - 1)),
                (float)((double)a->height_px / (r->rows - 1)));
    glUniform2f(r->u_half, (float)(a->width_px / 2.0), (float)(a->height_px / 2.0));
    glUniform1f(r->u_focal, (float)a->focal_px);
    glUniform3f(r->u_fwd, (float)a->forward[0], (float)a->forward[1], (float)a->forward[2]);
    glUniform3f(r->u_right, (float)a->right[0], (float)a->right[1], (float)a->right[2]);
    glUniform3f(r->u_up, (float)a->up[0], (float)a->up[1], (float)a->up[2]);
    glUniform1f(r->u_base_rel, (float)-f.eye_above_base_m); /* tp_core.h: the plane's height */
    glUniform1f(r->u_h, (float)f.eye_above_base_m);
    glUniform1f(r->u_sin_a, (float)f.sin_alpha);
    glUniform1f(r->u_cos_a, (float)f.cos_alpha);
    glUniform1f(r->u_post_m, (float)f.post_m);
    glUniform1i(r->u_levels, p->levels);
    glUniform2f(r->u_eye_grid, (float)eye_x, (float)eye_y);
    glUniform2f(r->u_inv_step, (float)(1 / gt[1]), (float)(1 / gt[5]));
    glUniform2f(r->u_step, (float)gt[1], (float)gt[5]);
    GLint off[2 * TP_PGM_MAX_LEVELS], size[2 * TP_PGM_MAX_LEVELS];
    for (int l = 0; l < p->levels; l++) {
        off[2 * l] = r->off[l][0], off[2 * l + 1] = r->off[l][1];
        size[2 * l] = p->width[l], size[2 * l + 1] = p->height[l];
    }
    glUniform2iv(r->u_off, p->levels, off);
    glUniform2iv(r->u_size, p->levels, size);
    glUniform1i(r->u_atlas, 0);
    glUniform1f(r->u_eye_z, (float)eye[2]);
    glUniformMatrix4fv(r->u_viewproj, 1, GL_FALSE, vpm);
    double az = s->sun_azimuth_deg * 3.14159265358979323846 / 180,
           el = s->sun_elevation_deg * 3.14159265358979323846 / 180;
    glUniform3f(r->u_sun, (float)(sin(az) * cos(el)), (float)(cos(az) * cos(el)), (float)sin(el));
    glUniform2f(r->u_hrange, (float)p->min_m, (float)p->max_m);
    glUniform1i(r->u_color_lod, s->color_lod);
    glUniform1i(r->u_valid, 1);
    glUniform1i(r->u_has_valid, r->valid != 0);
    if (r->valid) {
        glActiveTexture(GL_TEXTURE1);
        glBindTexture(GL_TEXTURE_2D, r->valid);
    }
    glActiveTexture(GL_TEXTURE0);
    if (r->clip) {
        GLint org[2 * TP_PGM_MAX_LEVELS];
        tp_pgm_clipmap_origins(r->clip, org);
        glUniform2iv(r->u_org, p->levels, org);
        glUniform1i(r->u_win, tp_pgm_clipmap_window(r->clip));
        glUniform1i(r->u_clip, 0);
        glBindTexture(GL_TEXTURE_2D_ARRAY, tp_pgm_clipmap_texture(r->clip));
    } else {
        glBindTexture(GL_TEXTURE_2D, r->atlas);
    }
    double t1 = tp_clock_ms();
    glBindVertexArray(r->vao);
    glDrawElements(GL_TRIANGLES, (GLsizei)r->index_count, GL_UNSIGNED_INT, NULL);
    glBindVertexArray(0);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    if (finish)
        glFinish();
    stats->cols = r->cols;
    stats->rows = r->rows;
    stats->triangles = r->index_count / 3;
    stats->gpu_bytes = r->gpu_bytes;
    stats->setup_ms = t1 - t0;
    stats->draw_ms = tp_clock_ms() - t1;
    stats->near_m = cam->near_m > 0 ? cam->near_m : 1.0;
    stats->far_m = far_m;
}
