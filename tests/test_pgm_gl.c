/*
 * test_pgm_gl.c - Persistent Grid Mapping on a GPU (app/render/pgm_render.c through Mesa llvmpipe,
 * EGL without a display):
 *
 *   - a tilted plane at UTM-sized coordinates (~500 km): every level of a point-sampled pyramid
 *     holds the plane exactly and bilinear interpolation of a plane is the plane, so whatever
 *     level and parent weight the shader picks, the drawn surface must be the plane; the depth
 *     buffer read back at pixels whose rays meet the plane well inside the terrain must give the
 *     plane's analytic distance along the view axis, and pixels whose rays miss the terrain (off
 *     its edge, above the horizon) must stay at the far clear value;
 *   - a flat DEM whose southern rows have no height draws nothing over them (no curtain down
 *     to the base plane) and the plane's depth elsewhere;
 *   - the GPU's vertices are tp_pgm_map_vertex's: on Mt Hood from above, each CPU-mapped vertex
 *     projected by the main camera lands where the depth buffer's 3 x 3 pixels around it hold
 *     its depth (to 0.02%, ~3 m), save the few a nearer slope hides;
 *   - Mt Hood (data/lf_elev_220_mt_hood_utm.tif) drawn by PGM with a grid of about a vertex per
 *     pixel and by the patch renderer at full resolution from the same camera: the fraction of
 *     terrain pixels and the skyline (the topmost terrain pixel of each column) mostly agree.
 */
#define _POSIX_C_SOURCE 200809L
#include "gl_context.h"
#include "pgm_render.h"
#include "renderer.h"
#include "tp_io.h"
#include "tp_test.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define W 480
#define H 270

static tp_gl_context* context_or_skip(void)
{
    tp_gl_context* ctx = NULL;
    tp_error err = {{0}};
    if (!tp_gl_context_create_headless(W, H, &ctx, &err))
        SKIP("no headless OpenGL here: %s", err.message);
    return ctx;
}

/* The plane z = Z0 + SX * x + SY * y over grid posts (x, y); 257 posts a side, so that every
 * level's posts fall on level-0 posts (256 = 2^8): no level repeats its edge. */
#define N 257
#define SP 10.0
#define Z0 300.0
#define SX 0.35 /* metres per post */
#define SY -0.2
static const double GT[6] = {500000, SP, 0, 5000000, 0, -SP};

static double plane_z(double e, double n)
{
    double x = (e - GT[0]) / GT[1] - 0.5, y = (n - GT[3]) / GT[5] - 0.5;
    return Z0 + SX * x + SY * y;
}

TEST(tilted_plane_depth_is_the_planes)
{
    tp_gl_context* ctx = context_or_skip();
    float* z = malloc(sizeof *z * N * N);
    ASSERT_TRUE(z != NULL);
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++)
            z[y * N + x] = (float)(Z0 + SX * x + SY * y);
    tp_pgm_pyramid p;
    tp_error err;
    ASSERT_OK(tp_pgm_pyramid_build(z, N, N, GT, &p, &err));
    ASSERT_TRUE(p.levels > 4);
    tp_pgm_renderer* r = tp_pgm_renderer_create(&p, NULL, 240, 200, &err);
    ASSERT_TRUE(r != NULL);
    /* from the south-west corner's outside, looking north-east and down: the horizon, the
     * terrain's far edges and its near edge are all in the image */
    double eye[3] = {GT[0] + 0.3 * N * SP, GT[3] - 1.15 * N * SP, Z0 + 700};
    tp_camera cam;
    tp_camera_from_pose(eye, 20, -14, 60, W, H, &cam);
    tp_render_settings s;
    tp_render_settings_default(&s);
    tp_pgm_render_stats st;
    tp_gl_context_begin_frame(ctx);
    tp_pgm_renderer_draw(r, &cam, &s, 1, NULL, &st);
    EXPECT_EQ_INT((int)st.triangles, 2 * 239 * 199);
    static float depth[W * H];
    glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    tp_gl_context_end_frame(ctx);
    double n = st.near_m, f = st.far_m, A = (f + n) / (n - f), B = 2 * f * n / (n - f);
    tp_camera_frame cf;
    tp_camera_get_frame(&cam, &cf);
    int inside = 0, outside = 0, bad = 0;
    double worst = 0;
    for (int py = 2; py < H; py += 7)
        for (int px = 3; px < W; px += 9) {
            double d[3];
            tp_camera_pixel_ray(&cam, px + 0.5, py + 0.5, d);
            /* the plane: z - SX * x - SY * y = Z0 with x, y linear in E, N */
            double gx = SX / GT[1], gy = SY / GT[5];
            double k = plane_z(eye[0], eye[1]) - eye[2]; /* eye's height below the plane */
            double den = d[2] - gx * d[0] - gy * d[1];
            double t = den != 0 ? k / den : -1;
            float got = depth[(H - 1 - py) * W + px];
            double hit_x = 0, hit_y = 0;
            if (t > 0) {
                hit_x = (eye[0] + t * d[0] - GT[0]) / GT[1] - 0.5;
                hit_y = (eye[1] + t * d[1] - GT[3]) / GT[5] - 0.5;
            }
            int well_in =
                t > 0 && hit_x > 0.1 * N && hit_x < 0.9 * N && hit_y > 0.1 * N && hit_y < 0.9 * N;
            int well_out = t <= 0 || hit_x < -0.1 * N || hit_x > 1.1 * N || hit_y < -0.1 * N ||
                           hit_y > 1.1 * N;
            if (well_in) {
                double ze =
                    t * (d[0] * cf.forward[0] + d[1] * cf.forward[1] + d[2] * cf.forward[2]);
                double ze_got = B / ((2.0 * got - 1.0) + A);
                double rel = fabs(ze_got - ze) / ze;
                worst = fmax(worst, rel);
                if (rel > 0.002 && bad++ < 5)
                    fprintf(stderr, "pixel %d,%d: depth %.2f m drawn, the plane is at %.2f m\n", px,
                            py, ze_got, ze);
                inside++;
            } else if (well_out) {
                if (got != 1.0f && bad++ < 5)
                    fprintf(stderr, "pixel %d,%d: the ray misses the terrain, depth %g drawn\n", px,
                            py, got);
                outside++;
            }
        }
    fprintf(stderr, "%d pixels on the plane (worst relative depth error %.2g), %d off it\n", inside,
            worst, outside);
    EXPECT_GT((double)inside, 200);
    EXPECT_GT((double)outside, 100);
    EXPECT_EQ_INT(bad, 0);
    tp_pgm_renderer_destroy(r);
    tp_pgm_pyramid_free(&p);
    free(z);
    tp_gl_context_destroy(ctx);
}

/* A flat DEM whose southern rows have no height (NaN, as a DEM's ragged edge): PGM fills them for
 * its pyramid but draws nothing there, as the patch renderer draws nothing there: rays that
 * meet the plane in the void stay clear (no curtain down to the base plane), rays that meet it
 * on the ground show the plane's depth. */
TEST(void_rows_are_not_drawn)
{
    tp_gl_context* ctx = context_or_skip();
    enum { VOID_FROM = 180 }; /* rows VOID_FROM.. (the south) have no height */
    float* z = malloc(sizeof *z * N * N);
    ASSERT_TRUE(z != NULL);
    for (int k = 0; k < N * N; k++)
        z[k] = k / N >= VOID_FROM ? NAN : (float)Z0;
    tp_pgm_pyramid p;
    uint8_t* valid = NULL;
    tp_error err;
    ASSERT_OK(tp_pgm_pyramid_from_grid(z, N, N, GT, &p, &valid, &err));
    ASSERT_TRUE(valid != NULL);
    EXPECT_EQ_DBL(Z0, p.min_m); /* the fill is the edge's height: nothing lower */
    tp_pgm_renderer* r = tp_pgm_renderer_create(&p, valid, 240, 200, &err);
    ASSERT_TRUE(r != NULL);
    double eye[3] = {GT[0] + 0.5 * N * SP, GT[3] - 1.1 * N * SP, Z0 + 900};
    tp_camera cam;
    tp_camera_from_pose(eye, 0, -25, 60, W, H, &cam);
    tp_render_settings s;
    tp_render_settings_default(&s);
    tp_pgm_render_stats st;
    tp_gl_context_begin_frame(ctx);
    tp_pgm_renderer_draw(r, &cam, &s, 1, NULL, &st);
    static float depth[W * H];
    glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    tp_gl_context_end_frame(ctx);
    double n = st.near_m, f = st.far_m, A = (f + n) / (n - f), B = 2 * f * n / (n - f);
    tp_camera_frame cf;
    tp_camera_get_frame(&cam, &cf);
    int ground = 0, in_void = 0, bad = 0;
    for (int py = 1; py < H; py += 5)
        for (int px = 2; px < W; px += 7) {
            double d[3];
            tp_camera_pixel_ray(&cam, px + 0.5, py + 0.5, d);
            if (d[2] >= 0)
                continue;
            double t = (Z0 - eye[2]) / d[2];
            double hx = (eye[0] + t * d[0] - GT[0]) / GT[1] - 0.5;
            double hy = (eye[1] + t * d[1] - GT[3]) / GT[5] - 0.5;
            float got = depth[(H - 1 - py) * W + px];
            if (hx < 0.1 * N || hx > 0.9 * N)
                continue;
            if (hy > 0.1 * N && hy < VOID_FROM - 0.05 * N) {
                double ze =
                    t * (d[0] * cf.forward[0] + d[1] * cf.forward[1] + d[2] * cf.forward[2]);
                double ze_got = B / ((2.0 * got - 1.0) + A);
                if (fabs(ze_got - ze) > 0.002 * ze && bad++ < 5)
                    fprintf(stderr, "pixel %d,%d: %.1f m drawn, the ground is at %.1f m\n", px, py,
                            ze_got, ze);
                ground++;
            } else if (hy > VOID_FROM + 0.05 * N && hy < 0.95 * N) {
                if (got != 1.0f && bad++ < 5)
                    fprintf(stderr, "pixel %d,%d: the ray meets the void, depth %g drawn\n", px, py,
                            got);
                in_void++;
            }
        }
    fprintf(stderr, "%d pixels on the ground, %d over the void\n", ground, in_void);
    EXPECT_GT((double)ground, 100);
    EXPECT_GT((double)in_void, 100);
    EXPECT_EQ_INT(0, bad);
    tp_pgm_renderer_destroy(r);
    tp_pgm_pyramid_free(&p);
    free(valid);
    free(z);
    tp_gl_context_destroy(ctx);
}

/* Mt Hood's sample DEM as a PGM pyramid and its mask of drawn posts (*valid, malloc'ed, NULL
 * when every post has a height); skips without the file. */
static tp_dem* hood_dem(tp_pgm_pyramid* p, uint8_t** valid)
{
    char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    tp_dem* dem = NULL;
    tp_error err;
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    ASSERT_OK(tp_pgm_pyramid_from_grid(dem->heights, dem->width, dem->height, dem->geotransform, p,
                                       valid, &err));
    return dem;
}

TEST(gpu_vertices_are_the_cpu_replicas)
{
    tp_gl_context* ctx = context_or_skip();
    tp_pgm_pyramid p;
    uint8_t* valid = NULL;
    tp_dem* dem = hood_dem(&p, &valid);
    tp_error err = {{0}};
    enum { COLS = 97, ROWS = 61 };
    tp_pgm_renderer* r = tp_pgm_renderer_create(&p, valid, COLS, ROWS, &err);
    ASSERT_TRUE(r != NULL);
    const double* gt = dem->geotransform;
    double eye[3] = {gt[0] + 0.5 * dem->width * gt[1], gt[3] + 1.05 * dem->height * gt[5],
                     dem->max_m + 9000};
    tp_camera cam;
    tp_camera_from_pose(eye, 0, -50, 60, W, H, &cam);
    cam.near_m = 2000; /* the terrain is 9 km or more away: depth precision to centimetres */
    tp_render_settings s;
    tp_render_settings_default(&s);
    tp_pgm_render_stats st;
    tp_pgm_frame f;
    tp_gl_context_begin_frame(ctx);
    tp_pgm_renderer_draw(r, &cam, &s, 1, &f, &st);
    static float depth[W * H];
    glReadPixels(0, 0, W, H, GL_DEPTH_COMPONENT, GL_FLOAT, depth);
    tp_gl_context_end_frame(ctx);
    double n = st.near_m, fa = st.far_m, A = (fa + n) / (n - fa), B = 2 * fa * n / (n - fa);
    int tried = 0, found = 0, bad_shown = 0;
    for (int j = 0; j < ROWS; j++)
        for (int i = 0; i < COLS; i++) {
            double w[3], lod, px[2], ze;
            if (!tp_pgm_map_vertex(&f, &p, i, j, w, &lod) || !tp_camera_project(&cam, w, px, &ze))
                continue;
            /* next to nodata (the DEM's ragged edge): drawn nowhere */
            int gx = (int)((w[0] - gt[0]) / gt[1] - 0.5), gy = (int)((w[1] - gt[3]) / gt[5] - 0.5);
            int nodata = 0;
            for (int k = 0; valid && k < 4; k++) {
                int qx = gx + k % 2 < dem->width ? gx + k % 2 : dem->width - 1;
                int qy = gy + k / 2 < dem->height ? gy + k / 2 : dem->height - 1;
                nodata |= !valid[(size_t)qy * dem->width + qx];
            }
            if (nodata)
                continue;
            int x = (int)floor(px[0]), y = (int)floor(px[1]);
            if (x < 1 || y < 1 || x > W - 2 || y > H - 2)
                continue;
            double lo = INFINITY, hi = 0;
            for (int dy = -1; dy <= 1; dy++)
                for (int dx = -1; dx <= 1; dx++) {
                    float d = depth[(H - 1 - (y + dy)) * W + (x + dx)];
                    double z = d < 1.0f ? B / ((2.0 * d - 1.0) + A) : INFINITY;
                    lo = fmin(lo, z), hi = fmax(hi, z);
                }
            tried++;
            if (ze >= lo * 0.9998 && ze <= hi * 1.0002)
                found++;
            else if (bad_shown++ < 5)
                fprintf(stderr,
                        "vertex %d,%d (level %.2f) at pixel %.1f,%.1f, %.1f m: the "
                        "depth buffer holds %.1f .. %.1f m there\n",
                        i, j, lod, px[0], px[1], ze, lo, hi);
        }
    fprintf(stderr, "%d of %d vertices in the image found in the depth buffer\n", found, tried);
    EXPECT_GT((double)tried, 0.5 * COLS * ROWS);
    /* from 9 km above, 50 degrees down, few vertices hide behind a nearer slope */
    EXPECT_GT((double)found, 0.95 * tried);
    tp_pgm_renderer_destroy(r);
    tp_pgm_pyramid_free(&p);
    free(valid);
    tp_dem_destroy(dem);
    tp_gl_context_destroy(ctx);
}

/* The topmost terrain row of each column (H: none) and the terrain pixel count. */
static size_t terrain_pixels(const uint8_t* rgba, const float clear[3], int* top)
{
    size_t count = 0;
    for (int x = 0; x < W; x++)
        top[x] = H;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            const uint8_t* c = rgba + ((size_t)y * W + x) * 4;
            int sky = 1;
            for (int k = 0; k < 3; k++)
                sky &= abs(c[k] - (int)lrintf(clear[k] * 255)) <= 1;
            if (!sky) {
                count++;
                if (top[x] == H)
                    top[x] = y;
            }
        }
    return count;
}

static int cmp_int(const void* a, const void* b)
{
    return *(const int*)a - *(const int*)b;
}

TEST(mt_hood_pgm_agrees_with_full_resolution_patches)
{
    tp_gl_context* ctx = context_or_skip();
    tp_pgm_pyramid p;
    uint8_t* valid = NULL;
    tp_dem* dem = hood_dem(&p, &valid);
    tp_error err;
    tp_terrain_desc desc = {.heights = dem->heights,
                            .height_count = (size_t)dem->width * dem->height,
                            .width = dem->width,
                            .height = dem->height,
                            .patch_size = 17};
    memcpy(desc.geotransform, dem->geotransform, sizeof desc.geotransform);
    tp_terrain* t = NULL;
    ASSERT_OK(tp_terrain_create(&desc, &t, &err));
    tp_selection* sel = NULL;
    ASSERT_OK(tp_selection_create(t, &sel, &err));
    tp_renderer* patches = tp_renderer_create(t, &err);
    ASSERT_TRUE(patches != NULL);
    tp_pgm_renderer* pgm = tp_pgm_renderer_create(&p, valid, W, H, &err); /* ~1 vertex/px */
    ASSERT_TRUE(pgm != NULL);
    /* south of the summit, low, looking north and slightly down: the mountain makes the skyline */
    const double* gt = dem->geotransform;
    double eye[3] = {gt[0] + 0.46 * dem->width * gt[1], gt[3] + 0.93 * dem->height * gt[5],
                     dem->min_m + 1300};
    tp_camera cam;
    tp_camera_from_pose(eye, 5, -8, 60, W, H, &cam);
    tp_render_settings s;
    tp_render_settings_default(&s);
    static uint8_t a[W * H * 4], b[W * H * 4];
    tp_lod_params full = {.mode = TP_LOD_FULL};
    tp_gl_context_begin_frame(ctx);
    ASSERT_OK(tp_selection_update(sel, &cam, &full, &err));
    tp_render_stats rs;
    tp_renderer_draw(patches, sel, &cam, &s, 1, &rs);
    tp_gl_context_end_frame(ctx);
    tp_gl_context_read_rgba(ctx, a);
    tp_gl_context_begin_frame(ctx);
    tp_pgm_render_stats ps;
    tp_pgm_renderer_draw(pgm, &cam, &s, 1, NULL, &ps);
    tp_gl_context_end_frame(ctx);
    tp_gl_context_read_rgba(ctx, b);
    static int top_a[W], top_b[W], diff[W];
    size_t na = terrain_pixels(a, s.clear_rgb, top_a), nb = terrain_pixels(b, s.clear_rgb, top_b);
    int columns = 0;
    for (int x = 0; x < W; x++)
        if (top_a[x] < H && top_b[x] < H)
            diff[columns++] = abs(top_a[x] - top_b[x]);
    ASSERT_TRUE(columns > 0);
    qsort(diff, (size_t)columns, sizeof *diff, cmp_int);
    int median = diff[columns / 2], p90 = diff[columns * 9 / 10];
    fprintf(stderr,
            "terrain pixels: patches %zu, pgm %zu of %d; skyline over %d columns: median %d px, "
            "90th percentile %d px, max %d px apart\n",
            na, nb, W * H, columns, median, p90, diff[columns - 1]);
    /* the view is mostly ground and shows the mountain against the sky in both */
    EXPECT_GT((double)na, 0.5 * W * H);
    EXPECT_TRUE(na < (size_t)W * H);
    EXPECT_GT((double)columns, 0.95 * W);
    /* the same terrain: within 3% of the image, the skyline a few pixels apart (PGM's far
     * vertices sample coarse levels: the distant skyline sinks a little, never by much) */
    EXPECT_TRUE(fabs((double)na - (double)nb) < 0.03 * W * H);
    EXPECT_TRUE(median <= 3);
    EXPECT_TRUE(p90 <= 10);
    tp_pgm_renderer_destroy(pgm);
    tp_renderer_destroy(patches);
    tp_selection_destroy(sel);
    tp_terrain_destroy(t);
    tp_pgm_pyramid_free(&p);
    free(valid);
    tp_dem_destroy(dem);
    tp_gl_context_destroy(ctx);
}

#define TESTS(X)                                                                                   \
    X(tilted_plane_depth_is_the_planes)                                                            \
    X(void_rows_are_not_drawn)                                                                     \
    X(gpu_vertices_are_the_cpu_replicas)                                                           \
    X(mt_hood_pgm_agrees_with_full_resolution_patches)

TP_TEST_MAIN(TESTS)
