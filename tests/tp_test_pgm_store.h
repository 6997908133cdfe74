/*
 * tp_test_pgm_store.h - the PGM-over-a-store GL tests' fixture (test_pgm_clip_gl.c,
 * test_pgm_clip_error_gl.c): a headless GL context of W x H, stores written in a temporary
 * folder from Mt Hood (data/lf_elev_220_mt_hood_utm.tif, its voids filled as
 * tp_pgm_pyramid_from_grid fills them, or kept), the tree for the reference heights, cameras
 * and one frame's draw. Include after tp_test.h, tp_test_tmp.h (with TP_TMP_PREFIX), gl_context.h,
 * pgm_clip.h, pgm_render.h and tp_io.h.
 */
#ifndef TP_TEST_PGM_STORE_H
#define TP_TEST_PGM_STORE_H

#include <epoxy/gl.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 480
#define H 270

static inline tp_gl_context* context_or_skip(void)
{
    tp_gl_context* ctx = NULL;
    tp_error err = {{0}};
    if (!tp_gl_context_create_headless(W, H, &ctx, &err))
        SKIP("no headless OpenGL here: %s", err.message);
    return ctx;
}

/* A store of Mt Hood's filled grid, cropped to its first cw x ch posts (0: whole); the tree
 * (every node resident) for the reference heights. */
typedef struct fixture {
    char path[600];
    tp_tree* full;
    tp_store* store;
    int w, h;
    double gt[6];
} fixture;

static inline void open_fixture_voids(fixture* fx, int cw, int ch, const char* name, int fill);
static inline void open_fixture(fixture* fx, int cw, int ch, const char* name)
{
    open_fixture_voids(fx, cw, ch, name, 1);
}

/* fill = 0: Mt Hood's voids kept (NaN: no height in the store) */
static inline void open_fixture_voids(fixture* fx, int cw, int ch, const char* name, int fill)
{
    memset(fx, 0, sizeof *fx);
    char dem_path[1024];
    REQUIRE_DATA_FILE(dem_path, "TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    tp_dem* dem = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_dem_read(dem_path, &dem, &err));
    tp_pgm_pyramid filled;
    uint8_t* valid = NULL;
    ASSERT_OK(tp_pgm_pyramid_from_grid(dem->heights, dem->width, dem->height, dem->geotransform,
                                       &filled, &valid, &err));
    free(valid);
    fx->w = cw ? cw : dem->width, fx->h = ch ? ch : dem->height;
    memcpy(fx->gt, dem->geotransform, sizeof fx->gt);
    float* z = malloc((size_t)fx->w * fx->h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    for (int y = 0; y < fx->h; y++)
        memcpy(z + (size_t)y * fx->w, (fill ? filled.z[0] : dem->heights) + (size_t)y * dem->width,
               fx->w * sizeof *z);
    tp_pgm_pyramid_free(&filled);
    tp_dem_destroy(dem);
    ASSERT_OK(tp_tree_create_from_grid(z, (size_t)fx->w * fx->h, fx->w, fx->h, fx->gt, 33, 0,
                                       &fx->full, &err));
    free(z);
    const tp_tree_geometry* g = tp_tree_get_geometry(fx->full);
    tp_tree_info ti;
    tp_tree_get_info(fx->full, &ti);
    tp_store_header hd;
    memset(&hd, 0, sizeof hd);
    hd.geometry = *g;
    memcpy(hd.geotransform, ti.geotransform, sizeof hd.geotransform);
    hd.height_step_m = ti.height_step_m;
    hd.quant_max_error_m = ti.quant_max_error_m;
    hd.err_unit_steps = ti.err_unit_steps;
    hd.crs_wkt = "";
    hd.notes = "test_pgm_clip_gl";
    snprintf(fx->path, sizeof fx->path, "%s/%s.tpt", make_tmp_dir(), name);
    tp_store_writer* wr;
    ASSERT_OK(tp_store_writer_begin(fx->path, &hd, &wr, &err));
    size_t v = ((size_t)1 << g->n) + 1;
    int32_t* q = malloc(v * v * sizeof *q);
    ASSERT_TRUE(q != NULL);
    for (int64_t id = g->node_count - 1; id >= 0; id--) {
        const uint16_t* s = tp_tree_samples(fx->full, id);
        const tp_node_meta* m = tp_tree_meta(fx->full, id);
        for (size_t i = 0; i < v * v; i++)
            q[i] = s[i] == TP_TREE_NO_HEIGHT ? INT32_MIN : (int32_t)s[i] + m->qmin;
        ASSERT_OK(tp_store_writer_add_node(wr, id, m, q, s + v * v, &err));
    }
    free(q);
    ASSERT_OK(tp_store_writer_commit(wr, &err));
    ASSERT_OK(tp_store_open(fx->path, &fx->store, &err));
}

static inline void close_fixture(fixture* fx)
{
    tp_store_close(fx->store);
    tp_tree_destroy(fx->full);
}

/* The decoded height of level-0 post (x, y), clamped to the grid. */
static inline double height_at(const fixture* fx, int x, int y)
{
    x = x < 0 ? 0 : (x >= fx->w ? fx->w - 1 : x);
    y = y < 0 ? 0 : (y >= fx->h ? fx->h - 1 : y);
    return tp_tree_sample(fx->full, x, y);
}

/* A camera h_m above the ground at post (x, y), heading yaw_deg, pitched pitch_deg. */
static inline tp_camera camera_at(const fixture* fx, double x, double y, double h_m, double yaw_deg,
                                  double pitch_deg)
{
    double eye[3] = {fx->gt[0] + (x + 0.5) * fx->gt[1], fx->gt[3] + (y + 0.5) * fx->gt[5], 0};
    eye[2] = height_at(fx, (int)x, (int)y) + h_m;
    tp_camera cam;
    tp_camera_from_pose(eye, yaw_deg, pitch_deg, 60, W, H, &cam);
    return cam;
}

/* Draws one frame; reads colour and depth back. */
static inline void draw(tp_gl_context* ctx, tp_pgm_renderer* r, const tp_camera* cam, uint8_t* rgba,
                        float* depth, tp_pgm_render_stats* st)
{
    /* tp_render_settings_default's (renderer.c is not linked here) */
    tp_render_settings s;
    memset(&s, 0, sizeof s);
    s.sun_azimuth_deg = 315, s.sun_elevation_deg = 45, s.exaggeration = 1;
    s.clear_rgb[0] = 0.55f, s.clear_rgb[1] = 0.70f, s.clear_rgb[2] = 0.90f;
    tp_gl_context_begin_frame(ctx);
    tp_pgm_renderer_draw(r, cam, &s, 1, NULL, st);
    if (depth)
        glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    tp_gl_context_end_frame(ctx);
    if (rgba)
        tp_gl_context_read_rgba(ctx, rgba);
}

/* The DEM's pyramid from the store's own heights (quantised as stored). */
static inline void store_pyramid(const fixture* fx, tp_pgm_pyramid* p)
{
    float* z = malloc((size_t)fx->w * fx->h * sizeof *z);
    ASSERT_TRUE(z != NULL);
    for (int y = 0; y < fx->h; y++)
        for (int x = 0; x < fx->w; x++)
            z[(size_t)y * fx->w + x] = (float)height_at(fx, x, y);
    tp_error err = {{0}};
    ASSERT_OK(tp_pgm_pyramid_build(z, fx->w, fx->h, fx->gt, p, &err));
    free(z);
}

#endif
