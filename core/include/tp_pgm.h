/* tp_pgm.h - Persistent Grid Mapping: the pyramid, the mapped grid, its error and the clipmap's
 * bookkeeping over a store (pgm.c, pgm_error.c, pgm_clip.c).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its
 * own. The conventions at the top of tp_core.h (coordinates, levels, failure) hold here.
 */
#ifndef TP_PGM_H
#define TP_PGM_H

#include "tp_camera.h"
#include "tp_tree.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---------------------------------------------------------------------------------------------
 * Persistent Grid Mapping (pgm.c, pgm_error.c; Livny, Kogan & El-Sana, seeds/001; issue 16)
 *
 * A grid of cols x rows vertices fixed in screen space, cached on the GPU once. Each frame,
 * vertex (i, j) (i = 0..cols-1 left to right, j = 0..rows-1 top to bottom) is the pixel
 * (i * w / (cols - 1), j * h / (rows - 1)) of the auxiliary camera (Eq. 2); the ray from the eye
 * through it meets the base plane h = base_m at P (Eq. 1); the vertex is drawn at P's E and N
 * and the height read from the elevation pyramid at P, at the level the distance r to its
 * farthest neighbour asks for (Eq. 3), blended with the parent level (Eq. 4). Cell (i, j) is the
 * two triangles (i,j) (i+1,j) (i,j+1) and (i+1,j) (i+1,j+1) (i,j+1) (split along (i+1,j)-(i,j+1));
 * a triangle with a vertex off the terrain is not drawn. The viewer's vertex shader and
 * tp_pgm_map_vertex compute the same numbers (the shader in floats, eye-relative).
 */
#define TP_PGM_MAX_LEVELS 24
#define TP_PGM_DEFAULT_COLS 300
#define TP_PGM_DEFAULT_ROWS 300

/* The elevation pyramid: level 0 is the given grid; level l has posts i = 0..width[l]-1 evenly
 * spaced at level-0 grid x = i * 2^l (the same in y), each holding the level-0 height of post
 * min(i * 2^l, width[0] - 1) (point sampling: every level's posts are source posts; the last
 * post may lie past the edge and then repeats the edge's height, so that every level reaches
 * the whole extent). width[l] = width[l-1] / 2 + 1 (integer division; = ceil((width[0] - 1) /
 * 2^l) + 1), height likewise: 1201 -> 601 -> 301 -> 151 -> 76 -> 39 ..., 1000 -> 501 -> 251.
 * Levels stop when both sides are <= 2 posts or at TP_PGM_MAX_LEVELS (a 1 x 1 or 2 x 2 grid
 * has 1 level). A shader samples level l at texel (x / 2^l, y / 2^l) (+ 0.5 for texel
 * centres) with clamp-to-edge, after clamping x, y to the level-0 extent as below. */
typedef struct tp_pgm_pyramid {
    int levels;
    int width[TP_PGM_MAX_LEVELS], height[TP_PGM_MAX_LEVELS];
    float* z[TP_PGM_MAX_LEVELS]; /* row-major, top row first; owned (tp_pgm_pyramid_free) */
    double geotransform[6];      /* of level 0: post (x, y) at E = gt[0] + (x + 0.5) * gt[1],
                                    N = gt[3] + (y + 0.5) * gt[5] (north-up: gt[2] = gt[4] = 0) */
    double min_m, max_m;         /* of level 0 */
} tp_pgm_pyramid;

/* Builds the pyramid of a width x height grid (no NaN: fill voids first; width, height >= 1).
 * Returns TP_OK and fills *out (free with tp_pgm_pyramid_free); TP_ERR_INVALID_ARG (a NaN
 * height, a size < 1 or a rotated or zero geotransform), TP_ERR_OUT_OF_MEMORY; *out is then
 * zeroed. */
tp_status tp_pgm_pyramid_build(const float* heights, int width, int height, const double gt[6],
                               tp_pgm_pyramid* out, tp_error* err);
void tp_pgm_pyramid_free(tp_pgm_pyramid* p); /* accepts NULL and a zeroed pyramid */

/* The bilinear height of level `level` (0..levels-1) at level-0 grid coordinates (x, y) (post
 * units, post (0, 0) at (0, 0)): x, y are first clamped to [0, width[0] - 1] x
 * [0, height[0] - 1], then level l is interpolated at (x / 2^l, y / 2^l) between its posts.
 * Cannot fail. */
double tp_pgm_pyramid_sample(const tp_pgm_pyramid* p, int level, double x, double y);

/* Eq. 2: the auxiliary camera. Same eye, yaw, field of view, viewport and near/far planes as
 * main; its pitch is min(main's pitch, -(fov_y / 2 + epsilon_rad)) (pitch < 0 looks down), so
 * that every ray of its image goes down and meets the base plane. It is main itself when main
 * already looks down that far (for a camera rolled about its axis, as tp_camera_from_pose never
 * makes, only when its four corner rays go down too; else it is levelled: no roll, the same
 * pitch). Its yaw is the heading 90 degrees left of main's right vector (main's yaw, and
 * defined looking straight up or down as well). Cannot fail. */
void tp_pgm_aux_camera(const tp_camera* main, double epsilon_rad, tp_camera* aux);

/* Everything one frame's mapping needs, set up once per frame (the shader's uniforms). */
typedef struct tp_pgm_frame {
    int cols, rows;
    tp_camera aux;          /* tp_pgm_aux_camera(main, 1e-3 rad) */
    tp_camera_frame aux_frame;
    double base_m;          /* the base plane's height: the pyramid's min_m */
    double eye_above_base_m; /* h in Eq. 3: eye height - base_m, at least 1 m. The rays meet
                                the plane at height eye - eye_above_base_m (base_m unless the
                                eye is less than 1 m above it) */
    double sin_alpha, cos_alpha; /* alpha: the larger angle between adjacent rays at the
                                    image centre, rows or cols: atan(max(w / (cols - 1),
                                    h / (rows - 1)) / focal_px) */
    double post_m;          /* level-0 post spacing: min(|gt[1]|, |gt[5]|) */
} tp_pgm_frame;

/* Sets up *out for main (fov, viewport and pose), the grid size (cols, rows >= 2; asserted) and
 * the pyramid. Cannot fail. */
void tp_pgm_frame_setup(const tp_camera* main, int cols, int rows, const tp_pgm_pyramid* p,
                        tp_pgm_frame* out);

/* Maps grid vertex (i, j): writes world[3] (E, N, height) and *lod, the continuous level
 * l + W_p (l = floor(log2(r / post_m)) clamped to [0, levels - 1], W_p = r / (post_m * 2^l) - 1
 * clamped to [0, 1], 0 at the last level; r from Eq. 3 with d = |P - eye|, q its horizontal
 * part, h = eye_above_base_m; r is infinite (last level) where h cos(alpha) <= q sin(alpha)),
 * the height being (1 - W_p) * sample(l) + W_p * sample(l + 1). W_p reaches 1 where l steps
 * up, so heights and lod are continuous in r. Returns 1 when P lies on the terrain (inside
 * the level-0 extent: 0 <= x <= width - 1, 0 <= y <= height - 1 in grid coordinates), else 0
 * (world and lod are written anyway, the height clamped to the edge). */
int tp_pgm_map_vertex(const tp_pgm_frame* f, const tp_pgm_pyramid* p, int i, int j,
                      double world[3], double* lod);

/* The error of one frame's PGM surface by the bench's definition: every level-0 post that the
 * main camera sees inside its viewport (projected inside, edges included, in front of the near
 * plane and not past a far plane; occlusion ignored) is compared with the drawn surface
 * vertically above or below it (the drawn triangle of the mapped grid, frame f, that covers
 * its E, N; linear interpolation): vertical error |drawn - post| in metres and screen error,
 * the on-screen distance between the projections of the two points, in pixels (infinite when
 * only the drawn point is behind the eye), as tp_selection_measure_screen_error. A post on an
 * edge two triangles share is counted once. Posts no drawn triangle covers (beyond the
 * terrain's edge triangles, which are not drawn, or outside the aux camera's footprint) are
 * counted in `uncovered`, not in the error; rms are 0 without samples. Scratch memory: about
 * 25 bytes per grid vertex and 5 per post of a band of 64 rows (tp_pgm_measure_error_source
 * over the pyramid). Returns TP_OK and writes *out;
 * TP_ERR_OUT_OF_MEMORY (*out zeroed). */
typedef struct tp_pgm_error {
    double max_m, rms_m;   /* vertical */
    double max_px, rms_px; /* screen */
    size_t samples;        /* posts in view that a triangle covers */
    size_t uncovered;      /* posts in view that none covers */
    double post_share;     /* share of the region's posts compared: 1, or less when sampled
                              (tp_pgm_source.band_every) */
} tp_pgm_error;
tp_status tp_pgm_measure_error(const tp_pgm_frame* f, const tp_pgm_pyramid* p,
                               const tp_camera* main, tp_pgm_error* out);

/* ---- PGM over a store: the elevation clipmap's bookkeeping (pgm_clip.c; seeds/001 section 4)
 *
 * For a terrain larger than texture memory, level l of the elevation pyramid (the posts
 * tp_pgm_pyramid would hold for the store's source grid: post (i, j) of level l is level-0 post
 * (min(i 2^l, width[0] - 1), min(j 2^l, height[0] - 1))) is kept as a window of w x w posts
 * (w a power of two) around the eye: posts origin_x <= i < origin_x + w, likewise in y, each at
 * texel (i mod w, j mod w) of its level's w x w texture (toroidal addressing). When the eye
 * moves, only the posts the window gains are written: at most two rectangles (the paper's L- or
 * F-shaped strips), the whole window after a jump of w posts or more. */
typedef struct tp_pgm_rect {
    int x0, y0, x1, y1; /* posts x0 <= x < x1, y0 <= y < y1 (empty when x1 <= x0 or y1 <= y0) */
} tp_pgm_rect;

/* The window's origin along one axis of a level with `posts` posts there, for a centre at
 * level-post coordinate `centre` (any value; NaN counts as 0): floor(centre) - w / 2, clamped to
 * [0, posts - w] so that the window stays on the terrain (0 when posts <= w: the whole axis
 * fits, the window never moves). w >= 1. Cannot fail. */
int tp_pgm_clip_origin(double centre, int posts, int w);

/* The posts a w x w window gains when its origin moves from (old_x, old_y) to (new_x, new_y)
 * (any integers, negative ones included, with |origin| + w < 2^31): written to out as at most 2 disjoint, non-empty
 * rectangles; returns how many (0 when it did not move). has_old = 0 (the window held nothing
 * yet) or a move of w or more posts along either axis: one rectangle, the whole new window.
 * Else the strip of columns the window gains (its whole height) and the strip of rows it gains
 * over the columns it kept. Every post of the new window that the old one did not hold is in
 * exactly one rectangle; no other post is. w >= 1 (asserted). */
int tp_pgm_clip_update(int w, int has_old, int old_x, int old_y, int new_x, int new_y,
                       tp_pgm_rect out[2]);

/* The smallest window (a power of two, at least 16) that holds the coarsest level of the
 * pyramid of a width x height grid whole (width, height >= 1; asserted), as a clipmap's
 * coarsest window must (the shader falls back to it everywhere). Levels stop at
 * TP_PGM_MAX_LEVELS, so a side of more than 2^24 + 1 posts keeps ceil((side - 1) / 2^23) + 1 > 2
 * at level 23: a window w holds it while side <= (w - 1) 2^23 + 1 (16: up to 125,829,121 posts);
 * else the coarsest level has at most 2 posts and this is 16. Cannot fail. */
int tp_pgm_clip_min_window(int width, int height);

/* Where a store holds level-0 post (x, y) (0 <= x < src_width, 0 <= y < src_height; asserted)
 * for level `level` of the pyramid: the node of the coarsest scale s <= level (and < g->scales)
 * whose lattice holds it (x and y multiples of 2^s, inside the nodes of that scale, which
 * exist only as whole quadtree nodes; the node's column min(x >> (n + s), node_cols[s] - 1),
 * row likewise, so that posts on the far edge of the last node column are found too), and the
 * sample's index in that node's (2^n + 1)^2 samples. Reading coarse levels
 * from coarse nodes keeps the nodes a window touches about w^2 / 4^n whatever the level. Every
 * node holding a sample holds the same height (tp_tree_samples), so the choice only matters for
 * speed. Returns the node id and writes *sample. Cannot fail. */
int64_t tp_pgm_store_post(const tp_tree_geometry* g, int level, int x, int y, size_t* sample);

/* ---- the error of a PGM surface whose heights are not one tp_pgm_pyramid's (pgm_error.c)
 *
 * What a renderer draws and the level-0 posts it is compared with, for
 * tp_pgm_measure_error_source: a whole pyramid (tp_pgm_measure_error), or a store's clipmap
 * (the viewer's app/render/pgm_clip_error.c: its windows' posts, level-0 posts read from nodes). */
typedef struct tp_pgm_source {
    void* ctx;
    /* The height drawn at level-0 grid coordinates (x, y) when level `level` (0 .. levels - 1)
     * is read there, as tp_pgm_pyramid_sample reads a whole pyramid; NaN where nothing is drawn
     * (the vertex then counts as off the terrain). */
    double (*sample)(void* ctx, int level, double x, double y);
    /* The level-0 posts x0 <= x < x1 of rows y0 <= y < y1 into out (row-major, x1 - x0 a row),
     * NaN where a post has no height (then neither compared nor counted). 1, or 0 when they
     * cannot be read (the measure fails with TP_ERR_IO; the source keeps its own message). */
    int (*posts)(void* ctx, int x0, int y0, int x1, int y1, float* out);
    int band_rows; /* rows asked for at once, in bands aligned to its multiples; 0: 64 */
    /* Sampling: only the bands whose index (first row / band_rows) is band_phase modulo
     * band_every are compared (0 or 1: every band); tp_pgm_error.post_share says what share of
     * the region's rows that was. */
    int band_every, band_phase;
} tp_pgm_source;

/* A rectangle of level-0 posts (inside shape's level-0 extent) that holds every post main can
 * see at a height between shape->min_m and max_m (a superset: the bounding box of the view's
 * part of that slab, two posts of room); empty (x1 <= x0 or y1 <= y0) when there is none. The
 * whole extent along an axis when a corner ray of the view does not go down (the view reaches
 * the horizon) and no far plane bounds it. Cannot fail. */
void tp_pgm_view_region(const tp_pgm_pyramid* shape, const tp_camera* main, tp_pgm_rect* out);

/* tp_pgm_measure_error over a source: the same definition and results, the drawn heights
 * src->sample's (Eq. 4's blend of a level and its parent as tp_pgm_map_vertex blends them; a
 * NaN in either voids the vertex), the posts compared those of region (NULL: the whole level-0
 * extent; tp_pgm_view_region bounds them) read with src->posts band by band. shape gives the
 * levels, sizes, geotransform and min_m (the base plane, as for tp_pgm_frame_setup); its z are
 * not read. Memory: about 25 bytes a grid vertex and 5 bytes a post of one band (region's width
 * x band_rows). Time: every triangle per band, and every post of the region. TP_OK and *out;
 * TP_ERR_IO (src->posts failed) or TP_ERR_OUT_OF_MEMORY with *out zeroed. */
tp_status tp_pgm_measure_error_source(const tp_pgm_frame* f, const tp_pgm_pyramid* shape,
                                      const tp_pgm_source* src, const tp_pgm_rect* region,
                                      const tp_camera* main, tp_pgm_error* out);

#ifdef __cplusplus
}
#endif
#endif /* TP_PGM_H */
