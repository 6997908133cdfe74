/*
 * terrain_shaders.h - the GLSL 3.30 programs the patch renderer (renderer.h) draws the terrain
 * with: shading per pixel from the normal map (normal_map.h: hillshade, hypsometric colour,
 * filled-void tint), else per vertex, level colours, the old single texture (--texture),
 * imagery through a clipmap (clipmap.h) or a texture per item (imagery_blocks.h), cast shadows
 * over a window (shadow_view.h) or over the day from a light map through a second clipmap
 * (light_view.h), and grid lines. The uniforms they take are set in renderer_draw.c and
 * render_clip.c. app/render/terrain_shaders.c.
 */
#ifndef TP_APP_VIEW_TERRAIN_SHADERS_H
#define TP_APP_VIEW_TERRAIN_SHADERS_H

#include <stddef.h>

/* The program's features, a bit each: a program is compiled with only those a draw uses
 * (llvmpipe executes every branch, taken or not). */
#define TP_SHADE_IMAGERY 1u  /* a clipmap of imagery (clip set 0) */
#define TP_SHADE_LIGHT 2u    /* the day's light map (clip set 1) */
#define TP_SHADE_NORMALS 4u  /* the normal map (clip set 2) */
#define TP_SHADE_SHADOW 8u   /* the shadow window (when no light map) */
#define TP_SHADE_TEXTURE 16u /* --texture */
#define TP_SHADE_BLOCKS 32u  /* a texture per item */
#define TP_SHADE_GRID 64u    /* grid lines */
#define TP_SHADE_ALL 127u

/* Writes the vertex and fragment sources of the program with features into vs and fs, cap bytes
 * each (16 KiB is plenty); 0 when they do not fit. */
int tp_terrain_shader_sources(unsigned features, char* vs, char* fs, size_t cap);

/* GLSL that PGM's programs (pgm_render.c) share with these, so that both renderers colour alike:
 * hypsometric(t), the colour ramp of a height fraction t of the height range (0 lowest, 1
 * highest; clamped), and the declaration of c[9], the colours of levels 0 .. 8 (--color-lod;
 * level_color returns c[min(k, 8)]). */
#define TP_GLSL_HYPSOMETRIC                                                                        \
    "vec3 hypsometric(float t) {\n"                                                                \
    "    vec3 c0 = vec3(0.33, 0.52, 0.30), c1 = vec3(0.62, 0.66, 0.40);\n"                         \
    "    vec3 c2 = vec3(0.58, 0.47, 0.35), c3 = vec3(0.93, 0.93, 0.93);\n"                         \
    "    t = clamp(t, 0.0, 1.0);\n"                                                                \
    "    if (t < 0.4) return mix(c0, c1, t / 0.4);\n"                                              \
    "    if (t < 0.8) return mix(c1, c2, (t - 0.4) / 0.4);\n"                                      \
    "    return mix(c2, c3, (t - 0.8) / 0.2);\n"                                                   \
    "}\n"
#define TP_GLSL_LEVEL_COLORS                                                                       \
    "    vec3 c[9] = vec3[9](vec3(0.20, 0.20, 0.80), vec3(0.10, 0.60, 0.90), vec3(0.10, 0.75, "    \
    "0.55),\n"                                                                                     \
    "                        vec3(0.45, 0.80, 0.20), vec3(0.90, 0.85, 0.15), vec3(0.95, 0.55, "    \
    "0.10),\n"                                                                                     \
    "                        vec3(0.90, 0.20, 0.15), vec3(0.70, 0.10, 0.50), vec3(0.95, 0.95, "    \
    "0.95));\n"

#endif /* TP_APP_VIEW_TERRAIN_SHADERS_H */
