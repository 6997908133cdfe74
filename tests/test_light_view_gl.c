/*
 * test_light_view_gl.c - the viewer's streamed light over a day on a GPU (app/view/
 * light_view.c, the renderer's light clipmap and its shader, through Mesa llvmpipe, EGL
 * without a display), on real ground: a 1025 x 1025-post crop of N42E001 (the Pyrenees around
 * its highest post; its voids are never lit and not drawn), its day's light times made by
 * tp_light_times_build (25 sun positions, a synthetic day from 06:00 to 18:00) and served from
 * memory as the pyramid a .tpl holds (level l + 1 the tp_light_times_mean of level l), drawn as a
 * tree's cut.
 *
 *   - a post deep inside a cast shadow (tp_shadow_compute says so for that sun, and every light
 *     times texel around it is shadowed at that time, with three steps to spare) on a slope
 *     facing the sun is drawn darker than in the same frame without the light map; a post
 *     deep in the light is drawn exactly as without it;
 *   - moving tau moves the shadow: a post shadowed in the morning is lit in the afternoon,
 *     and one lit in the morning shadowed in the afternoon, in the same streamed map;
 *   - after a long fast flight with small clip windows the frame equals the one a fresh light
 *     clipmap draws at the same place (no stale light).
 */
#define _POSIX_C_SOURCE 200809L
#include "gl_context.h"
#include "light_view.h"
#include "renderer.h"
#include "store_scene.h"
#include "tp_io.h"
#include "tp_test.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846
#define N 1025  /* posts a side of the crop */
#define MAPS 25 /* sun positions over the day */
#define DX 68.3 /* metres a post east and north (3 arc seconds at 42.5 N) */
#define DY 92.6
#define BLOCK 256
#define W 400 /* frames */
#define H 300
#define T0 1782021600.0 /* 2026-06-21 06:00 UTC */
#define R 4             /* the neighbourhood that must agree: (2R + 1)^2 posts */

static const double GT[6] = {400000, DX, 0, 4700000, 0, -DY};

/* The crop, its light times, the day's suns. */
typedef struct day {
    float* z;
    uint8_t* texels[TP_CLIP_MAX_LEVELS]; /* per level, 4 bytes a texel */
    int64_t w[TP_CLIP_MAX_LEVELS], h[TP_CLIP_MAX_LEVELS];
    int levels;
    double t[MAPS], az[MAPS], el[MAPS];
} day;

static void sun_at(int k, double* az, double* el)
{
    *az = 90 + 180.0 * k / (MAPS - 1);
    *el = 2 + 60 * sin(PI * k / (MAPS - 1));
}

/* The crop of N42E001 around its highest post, the day's light times and their coarser levels. */
static void make_day(day* d)
{
    char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    tp_dem* dem = NULL;
    tp_error err;
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    int dw = dem->width, dh = dem->height;
    size_t top = 0;
    for (size_t i = 0; i < (size_t)dw * dh; i++)
        if (dem->heights[i] > dem->heights[top] || dem->heights[top] != dem->heights[top])
            top = i;
    int x0 = (int)(top % dw) - N / 2, y0 = (int)(top / dw) - N / 2;
    x0 = x0 < 0 ? 0 : x0 > dw - N ? dw - N : x0;
    y0 = y0 < 0 ? 0 : y0 > dh - N ? dh - N : y0;
    d->z = malloc(sizeof *d->z * N * N);
    ASSERT_TRUE(d->z != NULL);
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++) {
            float v = dem->heights[(size_t)(y0 + y) * dem->width + x0 + x];
            d->z[(size_t)y * N + x] = v;
        }
    tp_dem_destroy(dem);
    for (int k = 0; k < MAPS; k++) {
        d->t[k] = T0 + 1800.0 * k;
        sun_at(k, &d->az[k], &d->el[k]);
    }
    d->w[0] = d->h[0] = N;
    d->texels[0] = malloc((size_t)N * N * 4);
    ASSERT_TRUE(d->texels[0] != NULL);
    tp_light_times_stats st;
    ASSERT_OK(tp_light_times_build(d->z, (size_t)N * N, N, N, DX, DY, d->t, d->az, d->el, MAPS,
                                   d->texels[0], (size_t)N * N * 4, &st, NULL, NULL, &err));
    ASSERT_GT((double)st.lit_any, 0.5 * N * N);
    fprintf(stderr,
            "crop from post (%d, %d) of N42E001: %zu posts lit at some time, %zu "
            "simplified to two intervals\n",
            x0, y0, st.lit_any, st.simplified);
    /* the pyramid's levels, as a .tpl's: until one fits in a block */
    int l = 0;
    while (d->w[l] > BLOCK || d->h[l] > BLOCK) {
        int64_t w = (d->w[l] + 1) / 2, h = (d->h[l] + 1) / 2;
        uint8_t* c = malloc((size_t)(w * h * 4));
        ASSERT_TRUE(c != NULL);
        for (int64_t v = 0; v < h; v++)
            for (int64_t u = 0; u < w; u++) {
                const uint8_t* in[4];
                int n = 0;
                for (int j = 0; j < 4; j++) {
                    int64_t fu = 2 * u + (j & 1), fv = 2 * v + (j >> 1);
                    if (fu < d->w[l] && fv < d->h[l])
                        in[n++] = d->texels[l] + (size_t)(fv * d->w[l] + fu) * 4;
                }
                tp_light_times_mean(in, n, c + (size_t)(v * w + u) * 4);
            }
        l++;
        d->texels[l] = c;
        d->w[l] = w;
        d->h[l] = h;
    }
    d->levels = l + 1;
}

static void free_day(day* d)
{
    free(d->z);
    for (int l = 0; l < d->levels; l++)
        free(d->texels[l]);
}

static int read_block(void* user, tp_block_key k, uint8_t* rgba, tp_error* err)
{
    (void)err;
    const day* d = user;
    memset(rgba, 0, (size_t)BLOCK * BLOCK * 4);
    for (int y = 0; y < BLOCK; y++) {
        int64_t v = k.by * BLOCK + y;
        int64_t u0 = k.bx * BLOCK, n = d->w[k.level] - u0;
        if (v >= d->h[k.level] || n <= 0)
            continue;
        memcpy(rgba + (size_t)y * BLOCK * 4,
               d->texels[k.level] + (size_t)(v * d->w[k.level] + u0) * 4,
               (size_t)(n < BLOCK ? n : BLOCK) * 4);
    }
    return 1;
}

static tp_block_source source(day* d)
{
    tp_block_source s = {.block = BLOCK, .levels = d->levels, .read = read_block, .user = d};
    for (int l = 0; l < d->levels; l++)
        s.width[l] = d->w[l], s.height[l] = d->h[l];
    return s;
}

/* Which part of its day a texel is in at tau, with margin steps to spare on both sides: 0
 * before r1, 1 in [r1, s1), 2 between s1 and r2, 3 in [r2, s2), 4 after s2; -1 within margin
 * of an end. Texels of one category around a post filter (bilinearly, and averaged into
 * coarser levels) to a texel of that category. */
static int category(const uint8_t* t, double tau, double margin)
{
    for (int i = 0; i < 4; i++)
        if (fabs(tau - t[i]) < margin)
            return -1;
    int c = 0;
    for (int i = 0; i < 4; i++)
        c += tau >= t[i];
    return c;
}

/* 1 when every texel within R of (x, y) is in category lit (1 or 3 when lit, else 0, 2 or 4)
 * at tau, with 3 steps to spare, all in the same category; and tp_shadow_compute's map for
 * sun k (shadow) agrees at each of those posts. */
static int uniform(const day* d, const uint8_t* shadow, int x, int y, double tau, int lit)
{
    int c0 = category(d->texels[0] + ((size_t)y * N + x) * 4, tau, 3);
    if (c0 < 0 || (c0 == 1 || c0 == 3) != lit)
        return 0;
    for (int j = -R; j <= R; j++)
        for (int i = -R; i <= R; i++) {
            size_t p = (size_t)(y + j) * N + x + i;
            if (d->z[p] != d->z[p] || category(d->texels[0] + p * 4, tau, 3) != c0)
                return 0;
            if ((shadow[p] == TP_SHADOW_LIT) != lit)
                return 0;
        }
    return 1;
}

/* How straight the ground at (x, y) faces sun k (the cosine of the incidence). */
static double facing(const day* d, int x, int y, int k)
{
    double gx = (d->z[(size_t)y * N + x + 1] - d->z[(size_t)y * N + x - 1]) / (2 * DX);
    double gy = (d->z[(size_t)(y - 1) * N + x] - d->z[(size_t)(y + 1) * N + x]) / (2 * DY);
    double a = d->az[k] * PI / 180, e = d->el[k] * PI / 180;
    double s[3] = {sin(a) * cos(e), cos(a) * cos(e), sin(e)};
    return (-gx * s[0] - gy * s[1] + s[2]) / sqrt(gx * gx + gy * gy + 1);
}

static double tau_of(const day* d, int k)
{
    return tp_light_times_tau(d->t[0], d->t[MAPS - 1], d->t[k]);
}

/* The post of the crop's interior whose neighbourhood is wholly lit_a at map a and lit_b at
 * map b (b < 0: any), facing sun face_k best; 0 when there is none. */
static int find_post(const day* d, uint8_t* const* shadows, int a, int lit_a, int b, int lit_b,
                     int face_k, int* px, int* py)
{
    double best = 0.3; /* at least: the direct light is a clear share of the shading */
    int found = 0;
    for (int y = 16; y < N - 16; y++)
        for (int x = 16; x < N - 16; x++) {
            double f = facing(d, x, y, face_k);
            if (f <= best || !uniform(d, shadows[a], x, y, tau_of(d, a), lit_a))
                continue;
            if (b >= 0 && !uniform(d, shadows[b], x, y, tau_of(d, b), lit_b))
                continue;
            best = f;
            *px = x, *py = y;
            found = 1;
        }
    return found;
}

/* What a frame needs: the tree of the crop, its cut, a renderer. */
typedef struct scene {
    tp_gl_context* ctx;
    tp_tree* tree;
    tp_cut* cut;
    tp_renderer* r;
    tp_store_scene st;
} scene;

static void open_scene(scene* s, const day* d)
{
    memset(s, 0, sizeof *s);
    tp_error err = {{0}};
    if (!tp_gl_context_create_headless(W, H, &s->ctx, &err))
        SKIP("no headless OpenGL here: %s", err.message);
    ASSERT_OK(tp_tree_create_from_grid(d->z, (size_t)N * N, N, N, GT, 17, 0, &s->tree, &err));
    ASSERT_OK(tp_cut_create(s->tree, &s->cut, &err));
    s->st.tree = s->tree;
    tp_tree_get_info(s->tree, &s->st.tree_info);
    tp_render_grid_desc gd = {.n = tp_tree_get_geometry(s->tree)->n,
                              .width = N,
                              .height = N,
                              .min_height_m = s->st.tree_info.min_height_m,
                              .max_height_m = s->st.tree_info.max_height_m};
    memcpy(gd.geotransform, GT, sizeof GT);
    s->r = tp_renderer_create_desc(&gd, &err);
    if (!s->r)
        FAIL("renderer: %s", err.message);
}

static void close_scene(scene* s)
{
    tp_renderer_destroy(s->r);
    tp_cut_destroy(s->cut);
    tp_tree_destroy(s->tree);
    tp_gl_context_destroy(s->ctx);
}

/* Draws the frame for cam at map k's sun, with the light map l at that time (NULL: without),
 * into rgba (W * H * 4, top row first). settle: the light's windows whole first. */
static void draw(scene* s, const day* d, tp_view_light* l, const tp_camera* cam, double t_s, int k,
                 int settle, uint8_t* rgba)
{
    tp_lod_params lod = {.mode = TP_LOD_ERROR, .tau_px = 1};
    tp_error err;
    ASSERT_OK(tp_cut_update(s->cut, cam, &lod, &err));
    tp_render_settings rs;
    tp_render_settings_default(&rs);
    rs.sun_azimuth_deg = d->az[k];
    rs.sun_elevation_deg = d->el[k];
    tp_gl_context_begin_frame(s->ctx);
    if (l)
        tp_view_light_frame(l, &s->st, s->cut, 1, s->r, cam, t_s, settle, NULL);
    else
        tp_renderer_set_light(s->r, NULL, 0);
    tp_render_stats stats;
    tp_renderer_draw_cut(s->r, s->tree, s->cut, cam, &rs, 1, 1, &stats);
    tp_gl_context_end_frame(s->ctx);
    if (rgba)
        tp_gl_context_read_rgba(s->ctx, rgba);
}

static tp_view_light* light(day* d, int clip_blocks)
{
    tp_block_source src = source(d);
    tp_clipmap_options o = {.clip_blocks = clip_blocks, .frame_s = 1 / 30.0};
    tp_error err = {{0}};
    tp_view_light* l = tp_view_light_create(&src, GT, d->t[0], d->t[MAPS - 1], &o, &err);
    if (!l)
        FAIL("light: %s", err.message);
    return l;
}

/* Post (x, y) drawn from 2500 m straight above it at map k, with and without the light: the
 * sums of its pixel's RGB (the 3 x 3 pixels around it averaged). */
static void post_pixels(scene* s, day* d, tp_view_light* l, int x, int y, int k, double* with,
                        double* without)
{
    double e = GT[0] + (x + 0.5) * DX, n = GT[3] - (y + 0.5) * DY, z = d->z[(size_t)y * N + x];
    double pos[3] = {e, n, z + 2500};
    tp_camera cam;
    tp_camera_from_pose(pos, 0, -90, 60, W, H, &cam);
    double world[3] = {e, n, z}, px[2];
    ASSERT_TRUE(tp_camera_project(&cam, world, px, NULL));
    int cx = (int)px[0], cy = (int)px[1];
    ASSERT_TRUE(cx >= 1 && cx < W - 1 && cy >= 1 && cy < H - 1);
    static uint8_t rgba[W * H * 4];
    double* out[2] = {with, without};
    for (int pass = 0; pass < 2; pass++) {
        draw(s, d, pass ? NULL : l, &cam, d->t[k], k, 1, rgba);
        double sum = 0;
        for (int j = -1; j <= 1; j++)
            for (int i = -1; i <= 1; i++) {
                const uint8_t* p = rgba + ((size_t)(cy + j) * W + cx + i) * 4;
                sum += p[0] + p[1] + p[2];
            }
        *out[pass] = sum / 9;
    }
}

static uint8_t* shadow_map(const day* d, int k)
{
    uint8_t* lit = malloc((size_t)N * N);
    ASSERT_TRUE(lit != NULL);
    tp_error err;
    ASSERT_OK(tp_shadow_compute(d->z, (size_t)N * N, N, N, DX, DY, d->az[k], d->el[k], lit, NULL,
                                (size_t)N * N, &err));
    return lit;
}

#define MORNING 2    /* 07:00: the sun at azimuth 105, 17.5 degrees up */
#define AFTERNOON 22 /* 17:00: azimuth 255, 17.5 degrees up */

/* In the morning: a post deep in a cast shadow drawn darker than without the light map, one
 * deep in the light drawn exactly as without it. */
TEST(shadowed_post_darker_lit_post_unchanged)
{
    day d = {0};
    make_day(&d);
    uint8_t* sh[MAPS] = {0};
    sh[MORNING] = shadow_map(&d, MORNING);
    int px, py, lx, ly;
    ASSERT_TRUE(find_post(&d, sh, MORNING, 0, -1, 0, MORNING, &px, &py));
    ASSERT_TRUE(find_post(&d, sh, MORNING, 1, -1, 0, MORNING, &lx, &ly));
    fprintf(stderr, "shadowed post (%d, %d) faces the sun at %.2f; lit post (%d, %d) at %.2f\n", px,
            py, facing(&d, px, py, MORNING), lx, ly, facing(&d, lx, ly, MORNING));
    scene s;
    open_scene(&s, &d);
    tp_view_light* l = light(&d, 0);
    double with, without;
    post_pixels(&s, &d, l, px, py, MORNING, &with, &without);
    fprintf(stderr, "shadowed post: %.1f with the light map, %.1f without\n", with, without);
    /* the direct light is >= 0.7 * 0.3 of 0.3 + that: at least 40% taken away */
    EXPECT_GT(without, 60);
    EXPECT_LT(with, 0.8 * without);
    post_pixels(&s, &d, l, lx, ly, MORNING, &with, &without);
    fprintf(stderr, "lit post: %.1f with the light map, %.1f without\n", with, without);
    EXPECT_NEAR(with, without, 1.0);
    tp_view_light_close(l);
    close_scene(&s);
    free(sh[MORNING]);
    free_day(&d);
}

/* The same map at two times: a post shadowed in the morning and lit in the afternoon, and one
 * lit in the morning and shadowed in the afternoon, each drawn so. */
TEST(moving_tau_moves_the_shadow)
{
    day d = {0};
    make_day(&d);
    uint8_t* sh[MAPS] = {0};
    sh[MORNING] = shadow_map(&d, MORNING);
    sh[AFTERNOON] = shadow_map(&d, AFTERNOON);
    int ax, ay, bx, by;
    ASSERT_TRUE(find_post(&d, sh, MORNING, 0, AFTERNOON, 1, MORNING, &ax, &ay));
    ASSERT_TRUE(find_post(&d, sh, MORNING, 1, AFTERNOON, 0, AFTERNOON, &bx, &by));
    scene s;
    open_scene(&s, &d);
    tp_view_light* l = light(&d, 0);
    double with, without;
    post_pixels(&s, &d, l, ax, ay, MORNING, &with, &without);
    fprintf(stderr, "post (%d, %d) at 07:00: %.1f (without the map %.1f)\n", ax, ay, with, without);
    EXPECT_LT(with, 0.8 * without);
    post_pixels(&s, &d, l, ax, ay, AFTERNOON, &with, &without);
    fprintf(stderr, "post (%d, %d) at 17:00: %.1f (without the map %.1f)\n", ax, ay, with, without);
    EXPECT_NEAR(with, without, 1.0);
    post_pixels(&s, &d, l, bx, by, MORNING, &with, &without);
    fprintf(stderr, "post (%d, %d) at 07:00: %.1f (without the map %.1f)\n", bx, by, with, without);
    EXPECT_NEAR(with, without, 1.0);
    post_pixels(&s, &d, l, bx, by, AFTERNOON, &with, &without);
    fprintf(stderr, "post (%d, %d) at 17:00: %.1f (without the map %.1f)\n", bx, by, with, without);
    EXPECT_LT(with, 0.8 * without);
    tp_view_light_close(l);
    close_scene(&s);
    free(sh[MORNING]);
    free(sh[AFTERNOON]);
    free_day(&d);
}

/* A fast flight low over the crop with 2 x 2-block windows (512 posts) and the upload cap, the
 * time moving too: the last frame equals the one a fresh light clipmap draws there, and shows
 * shadows (differs from the frame without the light map). */
TEST(fast_flight_leaves_no_stale_light)
{
    day d = {0};
    make_day(&d);
    scene s;
    open_scene(&s, &d);
    tp_view_light* l = light(&d, 2);
    double top = s.st.tree_info.max_height_m;
    tp_camera cam;
    int frames = 0;
    /* legs: east, then north-west, then south (grid metres a second, seconds) */
    struct {
        double yaw, speed, seconds;
    } legs[] = {{90, 1500, 5}, {315, 1500, 4}, {180, 2000, 4}};
    double e = GT[0] + 100 * DX, n = GT[3] - 200 * DY;
    for (int i = 0; i < 3; i++)
        for (int f = 0; f < (int)(legs[i].seconds * 30); f++, frames++) {
            double a = legs[i].yaw * PI / 180;
            e += sin(a) * legs[i].speed / 30;
            n += cos(a) * legs[i].speed / 30;
            e = fmin(fmax(e, GT[0] + 50 * DX), GT[0] + (N - 50) * DX);
            n = fmax(fmin(n, GT[3] - 50 * DY), GT[3] - (N - 50) * DY);
            double pos[3] = {e, n, top + 400};
            tp_camera_from_pose(pos, legs[i].yaw, -35, 60, W, H, &cam);
            draw(&s, &d, l, &cam, d.t[6] + 60.0 * frames, 6, 0, NULL);
        }
    double t = d.t[6] + 60.0 * frames;
    static uint8_t a[W * H * 4], b[W * H * 4], c[W * H * 4];
    draw(&s, &d, l, &cam, t, 6, 1, a);
    tp_view_light_close(l);
    l = light(&d, 2);
    draw(&s, &d, l, &cam, t, 6, 1, b);
    draw(&s, &d, NULL, &cam, t, 6, 1, c);
    size_t diff = 0, shadowed = 0;
    for (size_t i = 0; i < (size_t)W * H; i++) {
        diff += memcmp(a + i * 4, b + i * 4, 3) != 0;
        shadowed +=
            a[i * 4] + a[i * 4 + 1] + a[i * 4 + 2] + 6 < c[i * 4] + c[i * 4 + 1] + c[i * 4 + 2];
    }
    fprintf(stderr,
            "%d frames; %zu pixels differ from a fresh light clipmap's, %zu darker than "
            "without it\n",
            frames, diff, shadowed);
    EXPECT_EQ_INT((int)diff, 0);
    EXPECT_GT((double)shadowed, 0.01 * W * H);
    tp_view_light_close(l);
    close_scene(&s);
    free_day(&d);
}

#define TESTS(X)                                                                                   \
    X(shadowed_post_darker_lit_post_unchanged)                                                     \
    X(moving_tau_moves_the_shadow)                                                                 \
    X(fast_flight_leaves_no_stale_light)

TP_TEST_MAIN(TESTS)
