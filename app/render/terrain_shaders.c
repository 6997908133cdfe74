/* terrain_shaders.c - the terrain renderer's GLSL (see terrain_shaders.h). */
#include "terrain_shaders.h"

#include <stdio.h>
#include <string.h>

/* The hillshade is per pixel from the terrain's normals in a clipmap (normal_map.h: the
 * full-resolution normals whatever level the geometry is drawn at), with the hypsometric colour
 * and the filled-void tint from the same texel; the vertices' own shading (v_direct, v_hyp,
 * v_tint) stays where the normal map has nothing. The level colours and the texture level stay
 * per vertex. Each feature is compiled in only when a draw uses it (TP_SHADE_*): llvmpipe runs
 * every branch of a shader, taken or not, so a texture fetch behind `if (u_x > 0)` cost every
 * pixel its time (docs/PERFORMANCE.md, "Shading from full resolution"). */
static const char vertex_body[] =
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
    "uniform int u_hide_filled;\n"
    "uniform vec2 u_hrange;\n"
    "uniform ivec2 u_blk_cell;   // the item's texture (imagery_blocks.h): layer coordinates\n"
    "uniform vec2 u_blk_scale, u_blk_offset; // are (a_grid - cell) * scale + offset\n"
    "uniform vec4 u_shadow_win; // cast shadows: the window's first post and its size (posts)\n"
    "out vec2 v_rel;     // the position relative to the eye, metres east and north\n"
    "out float v_dz;     // and its height above the eye (drawn space): the ray per pixel\n"
    "#if TP_IMAGERY || TP_LIGHT\n"
    "out float v_lod;    // log2 of the distance over the slant here: a clip set's level is this\n"
    "                    // plus its u_clip_lod_k (Blow: per vertex, not per pixel)\n"
    "#endif\n"
    "#if TP_TEXTURE\n"
    "out vec2 v_uv;\n"
    "#endif\n"
    "#if TP_BLOCKS\n"
    "out vec2 v_blk;\n"
    "#endif\n"
    "#if TP_SHADOW\n"
    "out vec2 v_shadow_uv;\n"
    "#endif\n"
    "out float v_direct; // the sun's share of the light (where the normal map has nothing)\n"
    "out vec3 v_base;    // the level's colour (u_color_lod)\n"
    "out float v_hyp;    // the height's fraction of the range (hypsometric colours)\n"
    "out float v_tint;   // filled-void tint amount\n"
    "vec3 level_color(uint k) {\n"
    TP_GLSL_LEVEL_COLORS
    "    return c[min(k, 8u)];\n"
    "}\n"
    "void main() {\n"
    "    // integer rebase first: exact, the same for every patch sharing the vertex\n"
    "    vec2 d = vec2(a_grid - u_cell) * u_spacing - u_frac;\n"
    "    gl_Position = u_viewproj * vec4(d, a_z * u_exag - u_cam_z, 1.0);\n"
    "    vec3 n = normalize(vec3(a_normal.xy * u_exag, a_normal.z));\n"
    "    v_direct = 0.7 * max(dot(n, u_sun), 0.0);\n"
    "    v_base = level_color(a_flags & 15u);\n"
    "    v_hyp = (a_z - u_hrange.x) / max(u_hrange.y - u_hrange.x, 1.0);\n"
    "    v_tint = u_hide_filled == 0 ? 0.65 * float((a_flags >> 4u) & 1u) : 0.0;\n"
    "    v_rel = d;\n"
    "    v_dz = a_z * u_exag - u_cam_z;\n"
    "#if TP_TEXTURE\n"
    "    v_uv = vec2(a_grid) * u_tex_scale + u_tex_offset;\n"
    "#endif\n"
    "#if TP_BLOCKS\n"
    "    v_blk = vec2(a_grid - u_blk_cell) * u_blk_scale + u_blk_offset;\n"
    "#endif\n"
    "#if TP_SHADOW\n"
    "    v_shadow_uv = (vec2(a_grid) - u_shadow_win.xy + 0.5) / max(u_shadow_win.zw, vec2(1.0));\n"
    "#endif\n"
    "#if TP_IMAGERY || TP_LIGHT\n"
    "    // the texel footprint grows as 1 / cos of the angle between the ray and the normal:\n"
    "    // at grazing angles the coarser level (as GL's mipmapping takes the larger axis)\n"
    "    vec3 ray = vec3(d, v_dz);\n"
    "    float slant = max(abs(dot(ray, n)) / max(length(ray), 1e-6), 0.125);\n"
    "    v_lod = log2(max(length(ray) / slant, 1e-6));\n"
    "#endif\n"
    "}\n";

/* the fragment shader in three literals (C99 promises 4095 characters a literal) */
static const char fragment_head[] =
    "in vec2 v_rel;\n"
    "in float v_dz;\n"
    "#if TP_IMAGERY || TP_LIGHT\n"
    "in float v_lod;\n"
    "#endif\n"
    "#if TP_TEXTURE\n"
    "in vec2 v_uv;\n"
    "#endif\n"
    "#if TP_BLOCKS\n"
    "in vec2 v_blk;\n"
    "#endif\n"
    "#if TP_SHADOW\n"
    "in vec2 v_shadow_uv;\n"
    "#endif\n"
    "in float v_direct;\n"
    "in vec3 v_base;\n"
    "in float v_hyp;\n"
    "in float v_tint;\n"
    "uniform vec3 u_sun;\n"
    "uniform float u_exag;\n"
    "uniform int u_color_lod;\n"
    "uniform int u_hide_filled;\n"
    "uniform sampler2D u_tex;\n"
    "uniform float u_grid;        // line spacing, metres (0: none)\n"
    "uniform vec2 u_grid_origin;  // camera E, N modulo the spacing\n"
    "uniform sampler2D u_shadow;  // cast shadows over a window (1 lit, 0 shadowed)\n"
    "// clipmaps (clipmap.h): one layer per level, toroidal; set 0 the imagery, set 1 the light\n"
    "// over a day (light_view.h), set 2 the normals (normal_map.h); a set's per-level uniforms\n"
    "// at [set * 16 + level]\n"
    "uniform sampler2DArray u_clip;    // set 0\n"
    "uniform sampler2DArray u_light;   // set 1: texels (r1, s1, r2, s2) / 255, tp_core.h\n"
    "uniform sampler2DArray u_normals; // set 2: (128 + 127 (nx, ny), 255 h, 255 - 127 filled)\n"
    "uniform int u_clip_levels[3];   // 0: none\n"
    "uniform int u_clip_first[3];    // finest level kept\n"
    "uniform float u_clip_size[3];   // texels a side of a layer\n"
    "uniform vec2 u_clip_per_m[3];   // level-0 texels per metre east and north (signed)\n"
    "uniform float u_clip_lod_k[3];  // log2 of level-0 texels per pixel per metre of distance\n"
    "uniform vec4 u_clip_rect[48];   // per level: where its bilinear footprint is valid, level\n"
    "                                // texels from the camera\n"
    "uniform vec2 u_clip_cam[48];    // per level: the camera's texel position modulo the size\n"
    "uniform float u_light_tau;      // the time in the light's day, steps (0 .. 255)\n"
    "uniform sampler2DArray u_blk; // a texture per item (imagery_blocks.h)\n"
    "uniform int u_blk_layer;      // the item's layer; -1: none\n"
    "out vec4 o_color;\n"
    TP_GLSL_HYPSOMETRIC;

static const char fragment_clip[] =
    "bool clip_at(sampler2DArray tex, int set, int l, vec2 d0, out vec4 c) {\n"
    "    vec2 d = d0 * exp2(-float(l));\n"
    "    vec4 r = u_clip_rect[set * 16 + l];\n"
    "    if (any(lessThan(d, r.xy)) || any(greaterThan(d, r.zw))) return false;\n"
    "    c = textureLod(tex, vec3((u_clip_cam[set * 16 + l] + d) / u_clip_size[set], float(l)), 0.0);\n"
    "    return true;\n"
    "}\n"
    "// the level the distance asks for (lod: log2 of metres over the slant), else the first\n"
    "// coarser level whose valid region holds the texel's bilinear footprint (Luo & Duan 3.5);\n"
    "// false: none does\n"
    "bool clip_sample(sampler2DArray tex, int set, vec2 rel, float lod, out vec4 c) {\n"
    "    vec2 d0 = rel * u_clip_per_m[set];\n"
    "    c = vec4(0.0);\n"
    "    int l0 = max(int(max(lod + u_clip_lod_k[set], 0.0)), u_clip_first[set]);\n"
    "    for (int l = l0; l < u_clip_levels[set]; l++)\n"
    "        if (clip_at(tex, set, l, d0, c)) return true;\n"
    "    return false;\n"
    "}\n"
    "#if TP_LIGHT\n"
    "// how much of the step [tau, tau + 1] lies in the lit interval [r, s] (steps): the lit rule\n"
    "// of tp_light_times_lit at whole steps, a one-step ramp in between\n"
    "float lit_in(float r, float s) {\n"
    "    return max(min(u_light_tau + 1.0, s) - max(u_light_tau, r), 0.0);\n"
    "}\n"
    "// the lit fraction here at u_light_tau; 1 where the light's clipmap has nothing\n"
    "float light_lit(vec2 rel) {\n"
    "    vec4 t;\n"
    "    if (!clip_sample(u_light, 1, rel, v_lod, t)) return 1.0;\n"
    "    t *= 255.0;\n"
    "    return clamp(lit_in(t.x, t.y) + lit_in(t.z, t.w), 0.0, 1.0);\n"
    "}\n"
    "#endif\n";

static const char fragment_main[] =
    "void main() {\n"
    "    float direct = v_direct; // the sun's share of the light\n"
    "    float hyp = v_hyp, tint = v_tint;\n"
    "    vec4 t;\n"
    "#if TP_NORMALS\n"
    "    // the terrain's normal, height and filled share from the normal map, its level from\n"
    "    // this pixel's ray (the slant of level ground: nothing of the geometry's level, whose\n"
    "    // triangles interpolate v_lod differently); else the vertices' shading\n"
    "    float dist = max(length(vec3(v_rel, v_dz)), 1e-6);\n"
    "    if (clip_sample(u_normals, 2, v_rel, log2(dist / max(abs(v_dz) / dist, 0.125)), t) &&\n"
    "        t.a > 0.25) {\n"
    "        vec2 nxy = (t.xy * 255.0 - 128.0) / 127.0;\n"
    "        vec3 n = vec3(nxy * u_exag, sqrt(max(1.0 - dot(nxy, nxy), 0.0)));\n"
    "        direct = 0.7 * max(dot(normalize(n), u_sun), 0.0);\n"
    "        hyp = t.z;\n"
    "        tint = u_hide_filled == 0 ? 0.65 * clamp(2.0 - 2.0 * t.a, 0.0, 1.0) : 0.0;\n"
    "    }\n"
    "#endif\n"
    "    vec3 base = u_color_lod != 0 ? v_base : hypsometric(hyp);\n"
    "#if TP_TEXTURE\n"
    "    t = texture(u_tex, v_uv);\n"
    "    base = mix(base, t.rgb, t.a);\n"
    "#endif\n"
    "#if TP_IMAGERY\n"
    "    if (clip_sample(u_clip, 0, v_rel, v_lod, t))\n"
    "        base = mix(base, t.rgb, t.a);\n"
    "#endif\n"
    "#if TP_BLOCKS\n"
    "    if (u_blk_layer >= 0) {\n"
    "        t = texture(u_blk, vec3(v_blk, float(u_blk_layer)));\n"
    "        base = mix(base, t.rgb, t.a);\n"
    "    }\n"
    "#endif\n"
    "    float light = 0.3 + direct;\n"
    "#if TP_LIGHT // the day's light (it replaces the shadow window)\n"
    "    light -= direct * (1.0 - light_lit(v_rel));\n"
    "#elif TP_SHADOW\n"
    "    if (all(greaterThanEqual(v_shadow_uv, vec2(0.0))) &&\n"
    "        all(lessThanEqual(v_shadow_uv, vec2(1.0))))\n"
    "        light -= direct * (1.0 - texture(u_shadow, v_shadow_uv).r);\n"
    "#endif\n"
    "    vec3 c = mix(base, vec3(0.85, 0.25, 0.75), tint) * light;\n"
    "#if TP_GRID\n"
    "    // distance to the nearest grid line in pixels, from the screen-space derivative\n"
    "    vec2 g = (v_rel + u_grid_origin) / u_grid;\n"
    "    vec2 w = fwidth(g);\n"
    "    vec2 px = abs(fract(g - 0.5) - 0.5) / max(w, vec2(1e-6));\n"
    "    float line = 1.0 - clamp(min(px.x, px.y) - 0.5, 0.0, 1.0);\n"
    "    // fade where lines would be closer than 4 pixels\n"
    "    line *= clamp(1.0 / (4.0 * max(w.x, w.y)) - 0.5, 0.0, 1.0);\n"
    "    c = mix(c, vec3(0.05, 0.05, 0.35), 0.8 * line);\n"
    "#endif\n"
    "    o_color = vec4(c, 1.0);\n"
    "}\n";

/* "#version 330 core" and the features' defines into out; the bytes written, or 0 when cap is
 * too small. */
static size_t prologue(unsigned features, char* out, size_t cap)
{
    static const char* const names[] = {"TP_IMAGERY", "TP_LIGHT",  "TP_NORMALS", "TP_SHADOW",
                                        "TP_TEXTURE", "TP_BLOCKS", "TP_GRID"};
    size_t at = 0;
    int n = snprintf(out, cap, "#version 330 core\n");
    for (int i = 0; n > 0 && (size_t)n < cap - at && i < 7; i++) {
        at += (size_t)n;
        n = snprintf(out + at, cap - at, "#define %s %d\n", names[i], (features >> i) & 1);
    }
    if (n < 0 || (size_t)n >= cap - at)
        return 0;
    return at + (size_t)n;
}

/* Appends src (NUL-terminated) at out + *at; 0 when it does not fit in cap. */
static int append(char* out, size_t cap, size_t* at, const char* src)
{
    size_t n = strlen(src);
    if (*at + n + 1 > cap)
        return 0;
    memcpy(out + *at, src, n + 1);
    *at += n;
    return 1;
}

int tp_terrain_shader_sources(unsigned features, char* vs, char* fs, size_t cap)
{
    size_t v = prologue(features, vs, cap), f = prologue(features, fs, cap);
    return v && f && append(vs, cap, &v, vertex_body) && append(fs, cap, &f, fragment_head) &&
           append(fs, cap, &f, fragment_clip) && append(fs, cap, &f, fragment_main);
}
