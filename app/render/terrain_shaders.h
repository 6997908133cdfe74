/*
 * terrain_shaders.h - the GLSL 3.30 programs renderer.c draws the terrain with: per-vertex
 * shading (hillshade, hypsometric or level colours, the filled-void tint), the old single
 * texture (--texture), imagery through a clipmap (clipmap.h) or a texture per item
 * (imagery_blocks.h), cast shadows over a window (shadow_view.h) or over the day from a light
 * map through a second clipmap (light_view.h), and grid lines. The uniforms they take are set
 * in renderer.c and render_clip.c. app/view/terrain_shaders.c.
 */
#ifndef TP_APP_VIEW_TERRAIN_SHADERS_H
#define TP_APP_VIEW_TERRAIN_SHADERS_H

extern const char* const tp_terrain_vertex_shader;
const char* tp_terrain_fragment_shader(void); /* built once (render thread) */

#endif /* TP_APP_VIEW_TERRAIN_SHADERS_H */
