/*
 * test_normal_map.c - shading from full resolution (issue 32, item 3): the normal map
 * (app/render/normal_map.c) and multisampling (app/render/gl_context.c).
 *
 *   - the normal map's texels: level 0 holds each post's normal as the vertex path computes
 *     and quantises it (tp_tree_node_normal over a store with every leaf resident,
 *     tp_terrain_normal over a DEM drawn whole), its height's share of the range and the
 *     filled flag; a coarser level holds the mean slopes and height of its cell of posts 2^l
 *     apart; past the grid's edge nothing (alpha 0). No GL: the blocks as the loader computes
 *     them;
 *   - a store's view shades as the same DEM drawn whole at full resolution from the same camera
 *     (`view` of N42E001 against `view --whole --lod full`, the default view and one from
 *     130 km straight down): the mean absolute difference of the shaded pixels is at most 2 grey
 *     levels, and no block edges: across the borders of nodes drawn at different levels (from
 *     the same view with --color-lod) the picture's gradient is no larger than beside them
 *     (blockiness <= 1.1; the per-vertex shading before this measured 1.54 and 2.36);
 *   - --msaa: 4 samples blend the silhouette's pixels with the sky (and little else); the
 *     default is none on a software renderer, 4 on a GPU.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"
#include "tp_io.h"

#include "gl_context.h"
#include "normal_map.h"
#include "terrain_shaders.h"

#include "tp_test_child.h"

#define TP_TMP_PREFIX "tp_normal_map_"
#include "tp_test_tmp.h"

#include <epoxy/gl.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the texels, without GL ---- */

#define GW 300
#define GH 200

/* A synthetic grid of 30 m posts: two hills, a ridge of noise, a hole of nodata. */
static float* make_grid(double gt[6])
{
    float* z = malloc((size_t)GW * GH * sizeof *z);
    ASSERT_TRUE(z != NULL);
    uint32_t seed = 12345;
    for (int y = 0; y < GH; y++)
        for (int x = 0; x < GW; x++) {
            seed = seed * 1664525u + 1013904223u;
            double h = 800 + 300 * exp(-((x - 80.0) * (x - 80.0) + (y - 60.0) * (y - 60.0)) / 900) +
                       150 * sin(x / 17.0) * cos(y / 23.0) + (seed >> 24) / 16.0;
            int hole = (x - 200) * (x - 200) + (y - 120) * (y - 120) < 60;
            z[(size_t)y * GW + x] = hole ? NAN : (float)h;
        }
    double g[6] = {500000, 30, 0, 4500000, 0, -30};
    memcpy(gt, g, sizeof g);
    return z;
}

/* The store of z (every node written from a tree with every node resident, which is returned
 * for the reference normals). */
static tp_store* make_store(const float* z, const double gt[6], tp_tree** full)
{
    tp_error err = {{0}};
    ASSERT_OK(tp_tree_create_from_grid(z, (size_t)GW * GH, GW, GH, gt, 17, 0, full, &err));
    const tp_tree_geometry* g = tp_tree_get_geometry(*full);
    tp_tree_info ti;
    tp_tree_get_info(*full, &ti);
    tp_store_header hd;
    memset(&hd, 0, sizeof hd);
    hd.geometry = *g;
    memcpy(hd.geotransform, ti.geotransform, sizeof hd.geotransform);
    hd.height_step_m = ti.height_step_m;
    hd.quant_max_error_m = ti.quant_max_error_m;
    hd.err_unit_steps = ti.err_unit_steps;
    hd.crs_wkt = "";
    hd.notes = "test_normal_map";
    char path[600];
    snprintf(path, sizeof path, "%s/grid.tpt", make_tmp_dir());
    tp_store_writer* wr;
    ASSERT_OK(tp_store_writer_begin(path, &hd, &wr, &err));
    size_t v = ((size_t)1 << g->n) + 1;
    int32_t* q = malloc(v * v * sizeof *q);
    ASSERT_TRUE(q != NULL);
    for (int64_t id = g->node_count - 1; id >= 0; id--) {
        const uint16_t* s = tp_tree_samples(*full, id);
        const tp_node_meta* m = tp_tree_meta(*full, id);
        for (size_t i = 0; i < v * v; i++)
            q[i] = s[i] == TP_TREE_NO_HEIGHT ? INT32_MIN : (int32_t)s[i] + m->qmin;
        ASSERT_OK(tp_store_writer_add_node(wr, id, m, q, s + v * v, &err));
    }
    free(q);
    ASSERT_OK(tp_store_writer_commit(wr, &err));
    tp_store* st = NULL;
    ASSERT_OK(tp_store_open(path, &st, &err));
    return st;
}

/* Reads block k of src. */
static void read_block(tp_normal_source* src, tp_block_key k, uint8_t* t, tp_block_source* bs)
{
    double gt[6];
    tp_normal_source_blocks(src, bs, gt);
    tp_error err = {{0}};
    ASSERT_TRUE(bs->read(bs->user, k, t, &err));
}

/* A normal's component as a texel holds it: 128 + the vertex path's int8. */
static int q127(double v)
{
    return 128 + (int)lrintf((float)v * 127.0f);
}

/* A height's share of the range as a texel holds it (NaN: 0). */
static int q255(double z, double lo, double hi)
{
    double t = (z - lo) / fmax(hi - lo, 1);
    return isnan(t) ? 0 : (int)lrint(fmin(fmax(t, 0), 1) * 255);
}

/* The expected texel of a coarse level's cell (i, j) from height(x, y) (NaN: none): the mean of
 * the known slopes of its two rows and columns (the cell before it where its own has none), its
 * corners' mean height. */
static void cell_texel(double (*height)(const void*, int, int), const void* ctx, int l, int i,
                       int j, const double gt[6], double lo, double hi, int out[3])
{
    int s = 1 << l;
    double gs[2] = {0, 0};
    for (int axis = 0; axis < 2; axis++) {
        for (int back = 0; back < 2; back++) {
            int a0 = back ? -1 : 0; /* the cell, else the one before it */
            double sum = 0;
            int n = 0;
            for (int r = 0; r < 2; r++) {
                int x0 = axis == 0 ? i + a0 : i + r, y0 = axis == 0 ? j + r : j + a0;
                int x1 = axis == 0 ? x0 + 1 : x0, y1 = axis == 0 ? y0 : y0 + 1;
                double d = height(ctx, x1 * s, y1 * s) - height(ctx, x0 * s, y0 * s);
                if (!isnan(d))
                    sum += d, n++;
            }
            if (n) {
                gs[axis] = sum / n / (s * (axis == 0 ? gt[1] : gt[5]));
                break;
            }
        }
    }
    double len = sqrt(gs[0] * gs[0] + gs[1] * gs[1] + 1), hs = 0;
    int n = 0;
    for (int c = 0; c < 4; c++) {
        double h = height(ctx, (i + (c & 1)) * s, (j + (c >> 1)) * s);
        if (!isnan(h))
            hs += h, n++;
    }
    out[0] = q127(-gs[0] / len);
    out[1] = q127(-gs[1] / len);
    out[2] = q255(n ? hs / n : NAN, lo, hi);
}

static double tree_height(const void* ctx, int x, int y)
{
    return tp_tree_sample(ctx, x, y); /* NaN outside and in the padding */
}

static double terrain_height(const void* ctx, int x, int y)
{
    return tp_terrain_sample(ctx, x, y);
}

/* Checks every texel of every level's blocks of src (a grid of w x h posts): level 0 against
 * normal() (the vertex path's), coarser levels against cell_texel; heights against the range;
 * nothing past the grid. */
static void check_levels(tp_normal_source* src, int w, int h,
                         double (*height)(const void*, int, int), const void* ctx,
                         void (*normal)(const void*, int, int, float[3]), const double gt[6],
                         double lo, double hi)
{
    uint8_t* t = malloc((size_t)TP_NORMAL_MAP_BLOCK * TP_NORMAL_MAP_BLOCK * 4);
    ASSERT_TRUE(t != NULL);
    tp_block_source bs;
    double g[6];
    tp_normal_source_blocks(src, &bs, g);
    ASSERT_EQ_INT(2, bs.levels); /* 300 x 200: 150 x 100 fits a block */
    ASSERT_EQ_INT(w, (int)bs.width[0]);
    ASSERT_EQ_INT(h, (int)bs.height[0]);
    ASSERT_EQ_INT((w + 1) / 2, (int)bs.width[1]);
    ASSERT_EQ_INT((h + 1) / 2, (int)bs.height[1]);
    for (int i = 0; i < 6; i++)
        EXPECT_EQ_DBL(gt[i], g[i]);
    long checked = 0, off = 0;
    for (int l = 0; l < bs.levels; l++)
        for (int by = 0; by * TP_NORMAL_MAP_BLOCK < bs.height[l]; by++)
            for (int bx = 0; bx * TP_NORMAL_MAP_BLOCK < bs.width[l]; bx++) {
                read_block(src, (tp_block_key){l, bx, by}, t, &bs);
                for (int j = 0; j < TP_NORMAL_MAP_BLOCK; j++)
                    for (int i = 0; i < TP_NORMAL_MAP_BLOCK; i++) {
                        const uint8_t* p = t + ((size_t)j * TP_NORMAL_MAP_BLOCK + i) * 4;
                        int x = bx * TP_NORMAL_MAP_BLOCK + i, y = by * TP_NORMAL_MAP_BLOCK + j;
                        if (x >= bs.width[l] || y >= bs.height[l]) {
                            off += p[0] || p[1] || p[2] || p[3];
                            continue;
                        }
                        int e[3];
                        if (l == 0) {
                            float n[3];
                            normal(ctx, x, y, n); /* the vertex path's, renderer_upload.c */
                            e[0] = 128 + (int8_t)lrintf(n[0] * 127.0f);
                            e[1] = 128 + (int8_t)lrintf(n[1] * 127.0f);
                            e[2] = q255(height(ctx, x, y), lo, hi);
                        } else {
                            cell_texel(height, ctx, l, x, y, gt, lo, hi, e);
                        }
                        if (checked < 1 || p[0] != e[0] || p[1] != e[1] || abs(p[2] - e[2]) > 1 ||
                            p[3] != 255) {
                            EXPECT_EQ_INT(e[0], p[0]);
                            EXPECT_EQ_INT(e[1], p[1]);
                            EXPECT_LE_INT(abs(p[2] - e[2]), 1);
                            EXPECT_EQ_INT(255, p[3]);
                            ASSERT_NO_FAILURE();
                        }
                        checked++;
                    }
            }
    EXPECT_EQ_INT(0, (int)off);
    EXPECT_EQ_INT(w * h + (w + 1) / 2 * ((h + 1) / 2), (int)checked);
    free(t);
}

static void tree_normal(const void* ctx, int x, int y, float n[3])
{
    const tp_tree* t = ctx;
    tp_tree_node_normal(t, tp_tree_leaf_at(t, x, y), x, y, n);
}

static void terrain_normal(const void* ctx, int x, int y, float n[3])
{
    tp_terrain_normal(ctx, x, y, n);
}

TEST(store_texels_are_the_vertex_normals)
{
    double gt[6];
    float* z = make_grid(gt);
    tp_tree* full = NULL;
    tp_store* st = make_store(z, gt, &full);
    tp_tree_info ti;
    tp_tree_get_info(full, &ti);
    tp_error err = {{0}};
    tp_normal_source* src = tp_normal_source_store(st, ti.min_height_m, ti.max_height_m, &err);
    ASSERT_TRUE(src != NULL);
    check_levels(src, GW, GH, tree_height, full, tree_normal, gt, ti.min_height_m,
                 ti.max_height_m);
    tp_normal_source_destroy(src);
    tp_store_close(st);
    tp_tree_destroy(full);
    free(z);
}

TEST(terrain_texels_are_the_vertex_normals)
{
    double gt[6];
    float* z = make_grid(gt);
    tp_terrain_desc d = {.heights = z, .height_count = (size_t)GW * GH, .width = GW, .height = GH,
                         .patch_size = 17};
    memcpy(d.geotransform, gt, sizeof d.geotransform);
    tp_terrain* t = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_terrain_create(&d, &t, &err));
    tp_terrain_info in;
    tp_terrain_get_info(t, &in);
    tp_normal_source* src = tp_normal_source_terrain(t, &err);
    ASSERT_TRUE(src != NULL);
    /* the fitted grid (305 x 209) is the source's: its padding has no height */
    ASSERT_EQ_INT(305, in.width);
    check_levels(src, in.width, in.height, terrain_height, t, terrain_normal, in.geotransform,
                 in.min_height_m, in.max_height_m);
    tp_normal_source_destroy(src);
    tp_terrain_destroy(t);
    free(z);
}

/* ---- the picture: a store's view against the DEM drawn whole ---- */

typedef struct image {
    int w, h;
    uint8_t* px;
} image;

static image load(const char* path)
{
    image m = {0};
    ASSERT_OK(tp_image_read_rgba(path, &m.w, &m.h, &m.px, NULL));
    return m;
}

static void view(const char* dem, const char* cam, const char* extra1, const char* extra2,
                 const char* png)
{
    char err[8192], camera[160];
    snprintf(camera, sizeof camera, "--camera=%s", cam);
    const char* args[16];
    int n = 0;
    args[n++] = "--headless";
    args[n++] = "--no-hud";
    args[n++] = camera;
    if (extra1)
        args[n++] = extra1;
    if (extra2)
        args[n++] = extra2;
    args[n++] = "--screenshot";
    args[n++] = png;
    args[n++] = dem;
    args[n] = NULL;
    if (tp_test_run_terrapatch("view", args, err, sizeof err) != 0)
        FAIL("view %s %s: %s", extra1 ? extra1 : "", extra2 ? extra2 : "", err);
}

static int same_rgb(const uint8_t* a, const uint8_t* b)
{
    return a[0] == b[0] && a[1] == b[1] && a[2] == b[2];
}

static double luma(const uint8_t* p)
{
    return 0.299 * p[0] + 0.587 * p[1] + 0.114 * p[2];
}

/* The level of a --color-lod pixel: the level colour (terrain_shaders.h) whose chromaticity is
 * nearest, -1 when none is near (the tint of filled voids, the sky). */
static int level_of(const uint8_t* p)
{
    static const float c[9][3] = {{0.20f, 0.20f, 0.80f}, {0.10f, 0.60f, 0.90f},
                                  {0.10f, 0.75f, 0.55f}, {0.45f, 0.80f, 0.20f},
                                  {0.90f, 0.85f, 0.15f}, {0.95f, 0.55f, 0.10f},
                                  {0.90f, 0.20f, 0.15f}, {0.70f, 0.10f, 0.50f},
                                  {0.95f, 0.95f, 0.95f}};
    double s = (double)p[0] + p[1] + p[2];
    if (s < 30)
        return -1;
    int best = -1;
    double bd = 1e9;
    for (int k = 0; k < 9; k++) {
        double t = c[k][0] + c[k][1] + c[k][2];
        double dr = p[0] / s - c[k][0] / t, dg = p[1] / s - c[k][1] / t;
        if (dr * dr + dg * dg < bd)
            bd = dr * dr + dg * dg, best = k;
    }
    return bd < 0.002 ? best : -1;
}

typedef struct comparison {
    double mad;          /* mean absolute difference of the shaded pixels, grey levels */
    long shaded;
    double blockiness;   /* store: |gradient| across level borders over beside them */
    double ref_blockiness; /* the same pairs in the reference */
    long border_pairs;
} comparison;

/* s: the store's view, r: the DEM drawn whole, lod: the store's view with --color-lod (the same
 * cut). A pixel is shaded where neither picture shows the sky (the top-left pixel's colour).
 * Blockiness: over pairs of neighbouring pixels (along x and along y) whose levels differ, each
 * with a pixel of its own level on its far side (a - p | q - b), the mean of |Y(q) - Y(p)| over
 * the mean of (|Y(p) - Y(a)| + |Y(b) - Y(q)|) / 2: above 1 where the picture steps at node
 * borders (the JPEG-like blockiness of a known block grid). */
static comparison compare(const image* s, const image* r, const image* lod)
{
    ASSERT_TRUE(s->w == r->w && s->h == r->h && s->w == lod->w && s->h == lod->h);
    int w = s->w, h = s->h;
    comparison c = {0};
    uint8_t* ok = calloc((size_t)w * h, 1);
    int* lv = malloc((size_t)w * h * sizeof *lv);
    ASSERT_TRUE(ok && lv);
    double sum = 0;
    for (int i = 0; i < w * h; i++) {
        const uint8_t *a = s->px + 4 * (size_t)i, *b = r->px + 4 * (size_t)i;
        lv[i] = same_rgb(lod->px + 4 * (size_t)i, lod->px) ? -1 : level_of(lod->px + 4 * (size_t)i);
        if (same_rgb(a, s->px) || same_rgb(b, r->px))
            continue;
        ok[i] = 1;
        for (int k = 0; k < 3; k++)
            sum += fabs((double)a[k] - b[k]) / 3;
        c.shaded++;
    }
    c.mad = c.shaded ? sum / c.shaded : NAN;
    double across[2] = {0, 0}, beside[2] = {0, 0};
    for (int dir = 0; dir < 2; dir++)
        for (int y = 1; y + 2 < h; y++)
            for (int x = 1; x + 2 < w; x++) {
                int dx = dir == 0, dy = dir == 1;
                int a = (y - dy) * w + (x - dx), p = y * w + x, q = (y + dy) * w + (x + dx),
                    b = (y + 2 * dy) * w + (x + 2 * dx);
                if (!ok[a] || !ok[p] || !ok[q] || !ok[b] || lv[p] < 0 || lv[q] < 0 ||
                    lv[p] == lv[q] || lv[a] != lv[p] || lv[b] != lv[q])
                    continue;
                const image* im[2] = {s, r};
                for (int k = 0; k < 2; k++) {
                    const uint8_t* px = im[k]->px;
                    double ya = luma(px + 4 * (size_t)a), yp = luma(px + 4 * (size_t)p),
                           yq = luma(px + 4 * (size_t)q), yb = luma(px + 4 * (size_t)b);
                    across[k] += fabs(yq - yp);
                    beside[k] += (fabs(yp - ya) + fabs(yb - yq)) / 2;
                }
                c.border_pairs++;
            }
    c.blockiness = across[0] / fmax(beside[0], 1e-9);
    c.ref_blockiness = across[1] / fmax(beside[1], 1e-9);
    free(ok);
    free(lv);
    return c;
}

static void store_against_whole(const char* cam, const char* tag)
{
    char dem[1024], s[512], r[512], l[512];
    REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    const char* dir = make_tmp_dir();
    snprintf(s, sizeof s, "%s/%s-store.png", dir, tag);
    snprintf(r, sizeof r, "%s/%s-whole.png", dir, tag);
    snprintf(l, sizeof l, "%s/%s-lod.png", dir, tag);
    view(dem, cam, NULL, NULL, s);                 /* through its store (the cache) */
    view(dem, cam, "--color-lod", NULL, l);        /* the same cut, its levels */
    view(dem, cam, "--whole", "--lod=full", r);    /* the DEM whole, full resolution */
    image is = load(s), ir = load(r), il = load(l);
    comparison c = compare(&is, &ir, &il);
    printf("%s: %ld shaded pixels, mean absolute difference %.3f grey levels; %ld pixel pairs "
           "across level borders: blockiness %.3f (the DEM drawn whole on the same pairs: %.3f)\n",
           tag, c.shaded, c.mad, c.border_pairs, c.blockiness, c.ref_blockiness);
    EXPECT_GE((double)c.shaded, 0.15 * is.w * is.h);
    EXPECT_GE((double)c.border_pairs, 2000.0); /* the detector sees borders */
    EXPECT_LE(c.mad, 2.0);
    EXPECT_LE(c.blockiness, 1.1);
    free(is.px);
    free(ir.px);
    free(il.px);
}

TEST(store_view_shades_as_the_dem_drawn_whole)
{
    /* the default view (the whole tile from the south) and 130 km straight down */
    store_against_whole("376407.717,4631510.585,91115.503,0,-50", "default");
    store_against_whole("376408,4706523,130000,0,-90", "down");
}

/* ---- the terrain program's specialisations ---- */

/* Each of the 128 feature sets (TP_SHADE_*) makes a program that compiles and links, and sets
 * without a feature leave its uniforms out (llvmpipe would run its code); the shadow window's
 * are out also beside the day's light, which replaces it. */
TEST(every_feature_set_compiles)
{
    tp_gl_context* ctx = NULL;
    tp_error err = {{0}};
    if (!tp_gl_context_create_headless(64, 64, &ctx, &err))
        SKIP("no headless OpenGL here: %s", err.message);
    static char vs[16384], fs[16384];
    for (unsigned f = 0; f <= TP_SHADE_ALL; f++) {
        ASSERT_TRUE(tp_terrain_shader_sources(f, vs, fs, sizeof vs));
        unsigned prog = tp_gl_program(vs, fs, &err);
        if (!prog)
            FAIL("features %u: %s", f, err.message);
        static const struct {
            unsigned feature;
            const char* uniform;
        } own[] = {{TP_SHADE_IMAGERY, "u_clip"},      {TP_SHADE_LIGHT, "u_light_tau"},
                   {TP_SHADE_NORMALS, "u_normals"},   {TP_SHADE_SHADOW, "u_shadow"},
                   {TP_SHADE_TEXTURE, "u_tex"},       {TP_SHADE_BLOCKS, "u_blk_layer"},
                   {TP_SHADE_GRID, "u_grid_origin"}};
        for (int k = 0; k < 7; k++) {
            /* the day's light replaces the shadow window */
            int on = (f & own[k].feature) &&
                     !(own[k].feature == TP_SHADE_SHADOW && (f & TP_SHADE_LIGHT));
            if (on != (glGetUniformLocation(prog, own[k].uniform) >= 0))
                FAIL("features %u: %s %s", f, own[k].uniform, on ? "missing" : "there");
        }
        glDeleteProgram(prog);
        ASSERT_NO_FAILURE();
    }
    tp_gl_context_destroy(ctx);
}

/* ---- multisampling ---- */

TEST(msaa_blends_the_silhouette)
{
    char dem[1024], a[512], b[512], ja[512], jb[512], err[8192], json[16384];
    REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif");
    const char* dir = make_tmp_dir();
    snprintf(a, sizeof a, "%s/none.png", dir);
    snprintf(b, sizeof b, "%s/four.png", dir);
    snprintf(ja, sizeof ja, "%s/none.json", dir);
    snprintf(jb, sizeof jb, "%s/four.json", dir);
    const char* args_a[] = {"--headless", "--no-hud", "--size", "480x270", "--screenshot", a,
                            "--stats-json", ja, dem, NULL};
    const char* args_b[] = {"--headless", "--no-hud", "--size", "480x270", "--msaa", "4",
                            "--screenshot", b, "--stats-json", jb, dem, NULL};
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("view", args_a, err, sizeof err));
    ASSERT_EQ_INT(0, tp_test_run_terrapatch("view", args_b, err, sizeof err));
    tp_test_read_text(jb, json, sizeof json);
    EXPECT_EQ_DBL(4, tp_test_json_number_after(json, NULL, "msaa"));
    tp_test_read_text(ja, json, sizeof json);
    double def = tp_test_json_number_after(json, NULL, "msaa");
    const char* gl = strstr(json, "\"gl_renderer\"");
    ASSERT_TRUE(gl != NULL);
    EXPECT_EQ_DBL(strstr(gl, "llvmpipe") && strstr(gl, "llvmpipe") < strchr(gl, ',') ? 0 : 4, def);
    if (def != 0)
        SKIP("a GPU: --msaa is 4 by default, nothing to compare with");
    image ia = load(a), ib = load(b);
    int w = ia.w, h = ia.h;
    long blended = 0, at_sky = 0;
    for (int y = 1; y + 1 < h; y++)
        for (int x = 1; x + 1 < w; x++) {
            const uint8_t *p = ia.px + 4 * ((size_t)y * w + x), *q = ib.px + 4 * ((size_t)y * w + x);
            if (fabs(luma(p) - luma(q)) <= 2)
                continue;
            blended++;
            int near_sky = 0;
            for (int k = -1; k <= 1; k++)
                for (int m = -1; m <= 1; m++)
                    near_sky |= same_rgb(ia.px + 4 * ((size_t)(y + k) * w + x + m), ia.px);
            at_sky += near_sky;
        }
    printf("pixels changed by 4 samples: %ld, %ld of them next to the sky\n", blended, at_sky);
    EXPECT_GE((double)blended, 100.0);
    EXPECT_GE((double)at_sky, 0.8 * blended);
    free(ia.px);
    free(ib.px);
}

#define TESTS(X)                                                                                   \
    X(store_texels_are_the_vertex_normals)                                                         \
    X(terrain_texels_are_the_vertex_normals)                                                       \
    X(store_view_shades_as_the_dem_drawn_whole)                                                    \
    X(every_feature_set_compiles)                                                                  \
    X(msaa_blends_the_silhouette)
TP_TEST_MAIN(TESTS)
