/* hud.c - the text overlay (see hud.h). */
#include "hud.h"

#include "gl_context.h"

#include <epoxy/gl.h>
#include <stb/stb_easy_font.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define HUD_MAX_QUADS 20000

struct tp_hud {
    GLuint prog, vao, vbo, ibo;
    GLint u_screen, u_offset;
    char* verts; /* stb_easy_font output: 16 bytes per vertex (x, y, z floats, rgba bytes) */
    int pending;     /* depth-tested line quads gathered in verts, not drawn yet */
    int pending_w, pending_h;
};

static const char* vs =
    "#version 330 core\n"
    "layout(location = 0) in vec3 a_pos; // pixels, and the depth for depth-tested lines\n"
    "layout(location = 1) in vec4 a_color;\n"
    "uniform vec2 u_screen;\n"
    "uniform vec3 u_offset; // x, y, scale\n"
    "out vec4 v_color;\n"
    "void main() {\n"
    "    vec2 p = a_pos.xy * u_offset.z + u_offset.xy;\n"
    "    gl_Position = vec4(p.x / u_screen.x * 2.0 - 1.0, 1.0 - p.y / u_screen.y * 2.0, a_pos.z, 1.0);\n"
    "    v_color = a_color;\n"
    "}\n";
static const char* fs =
    "#version 330 core\n"
    "in vec4 v_color;\n"
    "out vec4 o_color;\n"
    "void main() { o_color = v_color; }\n";

tp_hud* tp_hud_create(void)
{
    tp_hud* h = calloc(1, sizeof *h);
    uint32_t* idx = malloc(HUD_MAX_QUADS * 6 * sizeof *idx);
    if (h)
        h->verts = malloc(HUD_MAX_QUADS * 4 * 16);
    if (!h || !idx || !h->verts || !(h->prog = tp_gl_program(vs, fs, NULL))) {
        free(idx);
        if (h)
            free(h->verts);
        free(h);
        return NULL;
    }
    h->u_screen = glGetUniformLocation(h->prog, "u_screen");
    h->u_offset = glGetUniformLocation(h->prog, "u_offset");
    /* quads -> two triangles each */
    for (uint32_t q = 0; q < HUD_MAX_QUADS; q++) {
        const uint32_t b = 4 * q, t[6] = {b, b + 1, b + 2, b, b + 2, b + 3};
        memcpy(idx + 6 * q, t, sizeof t);
    }
    glGenVertexArrays(1, &h->vao);
    glBindVertexArray(h->vao);
    glGenBuffers(1, &h->vbo);
    glBindBuffer(GL_ARRAY_BUFFER, h->vbo);
    glBufferData(GL_ARRAY_BUFFER, HUD_MAX_QUADS * 4 * 16, NULL, GL_STREAM_DRAW);
    glGenBuffers(1, &h->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, h->ibo);
    glBufferData(GL_ELEMENT_ARRAY_BUFFER, HUD_MAX_QUADS * 6 * sizeof *idx, idx, GL_STATIC_DRAW);
    free(idx);
    glEnableVertexAttribArray(0);
    glVertexAttribPointer(0, 3, GL_FLOAT, GL_FALSE, 16, (void*)0);
    glEnableVertexAttribArray(1);
    glVertexAttribPointer(1, 4, GL_UNSIGNED_BYTE, GL_TRUE, 16, (void*)12);
    return h;
}

void tp_hud_destroy(tp_hud* h)
{
    if (!h)
        return;
    glDeleteProgram(h->prog);
    glDeleteBuffers(1, &h->vbo);
    glDeleteBuffers(1, &h->ibo);
    glDeleteVertexArrays(1, &h->vao);
    free(h->verts);
    free(h);
}

void tp_hud_measure(const char* text, float* w, float* h)
{
    *w = (float)stb_easy_font_width((char*)text);
    *h = (float)stb_easy_font_height((char*)text);
}

static void draw(tp_hud* h, int w, int hgt, float x, float y, float scale, const char* text,
                 unsigned char rgba[4])
{
    int quads = stb_easy_font_print(0, 0, (char*)text, rgba, h->verts, HUD_MAX_QUADS * 4 * 16);
    if (quads <= 0)
        return;
    glBindBuffer(GL_ARRAY_BUFFER, h->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)quads * 4 * 16, h->verts);
    glUniform2f(h->u_screen, (float)w, (float)hgt);
    glUniform3f(h->u_offset, x, y, scale);
    glDrawElements(GL_TRIANGLES, quads * 6, GL_UNSIGNED_INT, NULL);
}

void tp_hud_text(tp_hud* h, int w, int hgt, float x, float y, float scale, const char* text)
{
    tp_hud_flush(h);
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glUseProgram(h->prog);
    glBindVertexArray(h->vao);
    unsigned char shadow[4] = {0, 0, 0, 255}, light[4] = {255, 255, 240, 255};
    draw(h, w, hgt, x + scale, y + scale, scale, text, shadow);
    draw(h, w, hgt, x, y, scale, text, light);
    glEnable(GL_DEPTH_TEST);
}

void tp_hud_line(tp_hud* h, int w, int hgt, float x0, float y0, float x1, float y1,
                 float width_px, const unsigned char rgba[4])
{
    tp_hud_flush(h);
    float dx = x1 - x0, dy = y1 - y0, len = sqrtf(dx * dx + dy * dy);
    if (len < 1e-3f)
        return;
    /* half the width across the segment */
    float nx = -dy / len * width_px * 0.5f, ny = dx / len * width_px * 0.5f;
    const float p[4][2] = {{x0 + nx, y0 + ny}, {x1 + nx, y1 + ny}, {x1 - nx, y1 - ny},
                           {x0 - nx, y0 - ny}};
    char* v = h->verts;
    for (int i = 0; i < 4; i++) {
        float xyz[3] = {p[i][0], p[i][1], 0.0f};
        memcpy(v + 16 * i, xyz, 12);
        memcpy(v + 16 * i + 12, rgba, 4);
    }
    glDisable(GL_DEPTH_TEST);
    glDisable(GL_CULL_FACE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glUseProgram(h->prog);
    glBindVertexArray(h->vao);
    glBindBuffer(GL_ARRAY_BUFFER, h->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, 4 * 16, h->verts);
    glUniform2f(h->u_screen, (float)w, (float)hgt);
    glUniform3f(h->u_offset, 0.0f, 0.0f, 1.0f);
    glDrawElements(GL_TRIANGLES, 6, GL_UNSIGNED_INT, NULL);
    glEnable(GL_DEPTH_TEST);
}

/* Draws quads (4 vertices each in h->verts), blended, with or without the depth test (which
 * never writes depth: what the overlay draws hides nothing). */
static void draw_quads(tp_hud* h, int w, int hgt, int quads, int depth_test)
{
    if (depth_test) {
        glEnable(GL_DEPTH_TEST);
        glDepthFunc(GL_LEQUAL);
    } else {
        glDisable(GL_DEPTH_TEST);
    }
    glDepthMask(GL_FALSE);
    glDisable(GL_CULL_FACE);
    glPolygonMode(GL_FRONT_AND_BACK, GL_FILL);
    glEnable(GL_BLEND);
    /* colour blended; the framebuffer's alpha kept (opaque screenshots) */
    glBlendFuncSeparate(GL_SRC_ALPHA, GL_ONE_MINUS_SRC_ALPHA, GL_ZERO, GL_ONE);
    glUseProgram(h->prog);
    glBindVertexArray(h->vao);
    glBindBuffer(GL_ARRAY_BUFFER, h->vbo);
    glBufferSubData(GL_ARRAY_BUFFER, 0, (GLsizeiptr)quads * 4 * 16, h->verts);
    glUniform2f(h->u_screen, (float)w, (float)hgt);
    glUniform3f(h->u_offset, 0.0f, 0.0f, 1.0f);
    glDrawElements(GL_TRIANGLES, quads * 6, GL_UNSIGNED_INT, NULL);
    glDisable(GL_BLEND);
    glDepthMask(GL_TRUE);
    glDepthFunc(GL_LESS);
    glEnable(GL_DEPTH_TEST);
}

static void put_vertex(char* v, float x, float y, float z, const unsigned char rgba[4])
{
    const float xyz[3] = {x, y, z};
    memcpy(v, xyz, 12);
    memcpy(v + 12, rgba, 4);
}

void tp_hud_dots(tp_hud* h, int w, int hgt, const float* xyz, int count, float side_px,
                 const unsigned char rgba[4], int depth_test)
{
    tp_hud_flush(h);
    if (count <= 0)
        return;
    if (count > HUD_MAX_QUADS)
        count = HUD_MAX_QUADS;
    const float r = side_px * 0.5f, c[4][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}};
    for (int i = 0; i < count; i++)
        for (int k = 0; k < 4; k++)
            put_vertex(h->verts + 16 * (4 * i + k), xyz[3 * i] + c[k][0] * r,
                       xyz[3 * i + 1] + c[k][1] * r, depth_test ? xyz[3 * i + 2] : 0.0f, rgba);
    draw_quads(h, w, hgt, count, depth_test);
}

void tp_hud_flush(tp_hud* h)
{
    if (h && h->pending) {
        int quads = h->pending;
        h->pending = 0;
        draw_quads(h, h->pending_w, h->pending_h, quads, 1);
    }
}

void tp_hud_polyline_depth(tp_hud* h, int w, int hgt, const float* xyz, int count,
                           float width_px, const unsigned char rgba[4])
{
    if (h->pending && (w != h->pending_w || hgt != h->pending_h))
        tp_hud_flush(h);
    h->pending_w = w;
    h->pending_h = hgt;
    int quads = h->pending;
    for (int i = 0; i + 1 < count; i++) {
        const float* a = xyz + 3 * i;
        const float* b = a + 3;
        float dx = b[0] - a[0], dy = b[1] - a[1], len = sqrtf(dx * dx + dy * dy);
        if (len < 1e-3f)
            continue;
        /* half the width across, and as much past each end so that joints close */
        float ux = dx / len * width_px * 0.5f, uy = dy / len * width_px * 0.5f;
        char* v = h->verts + 16 * 4 * quads;
        put_vertex(v, a[0] - ux - uy, a[1] - uy + ux, a[2], rgba);
        put_vertex(v + 16, b[0] + ux - uy, b[1] + uy + ux, b[2], rgba);
        put_vertex(v + 32, b[0] + ux + uy, b[1] + uy - ux, b[2], rgba);
        put_vertex(v + 48, a[0] - ux + uy, a[1] - uy - ux, a[2], rgba);
        if (++quads == HUD_MAX_QUADS) {
            draw_quads(h, w, hgt, quads, 1);
            quads = 0;
        }
    }
    h->pending = quads; /* drawn by the next flush: many lines in one draw call */
}

float tp_hud_depth(double depth_m, double near_m, double far_m)
{
    /* the depth buffer's step (24 bits) at this distance: d^2 (f - n) / (2^24 f n) */
    double step = depth_m * depth_m * (far_m - near_m) / (16777216.0 * far_m * near_m);
    double d = depth_m - 0.003 * depth_m - 4 * step;
    if (d < near_m)
        d = near_m;
    return (float)((far_m + near_m) / (far_m - near_m) - 2 * far_m * near_m / ((far_m - near_m) * d));
}
