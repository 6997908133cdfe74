/*
 * hud.h - text over the 3D view: stb_easy_font quads drawn with a tiny OpenGL 3.3 program.
 */
#ifndef TP_APP_HUD_H
#define TP_APP_HUD_H

typedef struct tp_hud tp_hud;

/* Needs a current GL context. NULL when the shaders fail. */
tp_hud* tp_hud_create(void);
void tp_hud_destroy(tp_hud* h);

/* Draws '\n'-separated text with its top-left corner at (x, y) pixels of a w x h viewport,
 * each font pixel `scale` screen pixels, light text with a dark shadow. */
void tp_hud_text(tp_hud* h, int w, int hgt, float x, float y, float scale, const char* text);

/* Draws a straight segment from (x0, y0) to (x1, y1) pixels, width_px wide, in rgba (over the
 * terrain, as the text). */
void tp_hud_line(tp_hud* h, int w, int hgt, float x0, float y0, float x1, float y1,
                 float width_px, const unsigned char rgba[4]);

/* Draws count squares side_px wide centred on the points (x, y, z triples: pixels and the
 * depth of tp_hud_depth), in rgba blended over what is drawn (alpha), hidden where the terrain
 * drawn is nearer (depth test) when depth_test is 1. At most 20000 per call. */
void tp_hud_dots(tp_hud* h, int w, int hgt, const float* xyz, int count, float side_px,
                 const unsigned char rgba[4], int depth_test);

/* Draws the polyline through count points (x, y, z triples: pixels and the depth of
 * tp_hud_depth) width_px wide in rgba, hidden where the terrain drawn is nearer: a line draped
 * on the ground that a ridge in front hides. Any number of points. The quads are gathered and
 * drawn together (one draw call for many lines) by the next tp_hud_flush or any other tp_hud_
 * drawing call. */
void tp_hud_polyline_depth(tp_hud* h, int w, int hgt, const float* xyz, int count,
                           float width_px, const unsigned char rgba[4]);

/* Draws what tp_hud_polyline_depth gathered. Accepts NULL. */
void tp_hud_flush(tp_hud* h);

/* The depth (OpenGL normalised device z) of a point depth_m along the view axis, for a
 * terrain drawn with the depth range near_m .. far_m (tp_render_stats), pulled toward the eye
 * by a margin that grows with distance (0.3% and the depth buffer's resolution there) so
 * that a point on the drawn ground is not hidden by the ground under it. */
float tp_hud_depth(double depth_m, double near_m, double far_m);

/* Width and height (pixels, at scale 1) of the text. */
void tp_hud_measure(const char* text, float* w, float* h);

#endif
