/*
 * test_imagery_blocks_gl.c - Brodersen's texture per drawn node on a GPU (app/view/
 * imagery_blocks.c through Mesa llvmpipe, EGL without a display): during and after flights over
 * a tree (its cut selected by tp_cut_update, a real loader thread, the upload cap, a layer pool
 * smaller than the flight needs, so layers are reused least recently drawn first) every drawn
 * node's layer holds exactly its window of the pyramid (the texture array read back and
 * compared with the direct value of every texel), and the mapping handed to the renderer sends
 * points near each node's grid corners to the texels that the geotransforms put there. The
 * pyramid is a pattern whose every texel is a function of (level, u, v).
 */
#define _POSIX_C_SOURCE 200809L
#include "gl_context.h"
#include "imagery_blocks.h"
#include "tp_test.h"
#include "tp_test_pattern.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define BLOCK TP_PATTERN_BLOCK
#define PI 3.14159265358979323846
#define GRID 1025 /* posts a side; nodes of 17 posts: 64 x 64 leaves, 7 scales */

static const double GRID_GT[6] = {500000, 10, 0, 5010250, 0, -10};

static tp_tree* make_tree(void)
{
    float* hts = malloc(sizeof *hts * GRID * GRID);
    if (!hts)
        FAIL("out of memory");
    for (int y = 0; y < GRID; y++)
        for (int x = 0; x < GRID; x++)
            hts[(size_t)y * GRID + x] = (float)(300 * sin(x / 37.0) * cos(y / 53.0) + 80 * sin(x / 7.0 + y / 11.0));
    tp_tree* t = NULL;
    tp_error e;
    tp_status st = tp_tree_create_from_grid(hts, (size_t)GRID * GRID, GRID, GRID, GRID_GT, 17, 0, &t, &e);
    free(hts);
    if (st != TP_OK)
        FAIL("tree: %s", e.message);
    return t;
}

/* Reads the array back; checks every drawn node: its level, its layer's 256 x 256 texels
 * against the pyramid, and where the mapping sends points just inside its corners. Returns
 * the nodes drawn with their own window. */
static int check_nodes(const tp_imagery_blocks* b, const tp_cut* cut, const tp_tree_geometry* g,
                       const tp_test_pattern* p, const tp_block_source* src, int ts)
{
    int layers = tp_imagery_blocks_layers(b);
    size_t layer_px = (size_t)BLOCK * BLOCK;
    uint32_t* px = malloc(layer_px * layers * 4);
    if (!px)
        FAIL("out of memory");
    glBindTexture(GL_TEXTURE_2D_ARRAY, tp_imagery_blocks_texture(b));
    glPixelStorei(GL_PACK_ALIGNMENT, 4);
    glGetTexImage(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA, GL_UNSIGNED_BYTE, px);
    size_t count, na, nt;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    const tp_blocks_assignment* as = tp_imagery_blocks_assignment(b, &na);
    const tp_render_item_texture* it = tp_imagery_blocks_item_textures(b, &nt);
    ASSERT_EQ_INT((int)na, (int)count);
    ASSERT_EQ_INT((int)nt, (int)count);
    double img_gt[6] = {GRID_GT[0], ldexp(GRID_GT[1], -ts), 0, GRID_GT[3], 0, ldexp(GRID_GT[5], -ts)};
    int own = 0;
    for (size_t i = 0; i < count; i++) {
        int s, c, r;
        tp_tree_node_locate(g, nodes[i].node, &s, &c, &r);
        const tp_blocks_assignment* a = &as[i];
        int want_level = g->n + s + ts - 8;
        want_level = want_level < 0 ? 0 : want_level > src->levels - 1 ? src->levels - 1 : want_level;
        if (a->own) {
            own++;
            if (a->layer >= 0)
                EXPECT_EQ_INT(a->level, want_level);
        } else {
            EXPECT_GE_INT(a->level, want_level + 1); /* an ancestor's: coarser */
        }
        if (a->layer >= 0) { /* the layer holds exactly its window */
            ASSERT_TRUE(a->layer < layers);
            const uint32_t* lp = px + (size_t)a->layer * layer_px;
            for (int y = 0; y < BLOCK; y++)
                for (int x = 0; x < BLOCK; x++) {
                    uint32_t want = tp_test_pattern_texel(p, a->level, a->origin[0] + x, a->origin[1] + y);
                    if (lp[y * BLOCK + x] != want) {
                        ADD_FAILURE("node (%d, %d, %d), layer %d (level %d from %lld, %lld): texel "
                                    "(%d, %d) 0x%08x, the pyramid 0x%08x", s, c, r, a->layer,
                                    a->level, (long long)a->origin[0], (long long)a->origin[1], x,
                                    y, lp[y * BLOCK + x], want);
                        free(px);
                        return own;
                    }
                }
        }
        /* points 0.3 posts inside each corner: the geotransforms' texel there */
        int64_t span = (int64_t)1 << (g->n + s);
        for (int corner = 0; corner < 4; corner++) {
            double gx = (double)c * span + (corner & 1 ? span - 0.3 : 0.3);
            double gy = (double)r * span + (corner & 2 ? span - 0.3 : 0.3);
            if (gx > g->src_width - 1 || gy > g->src_height - 1)
                continue; /* padding */
            double e = GRID_GT[0] + (gx + 0.5) * GRID_GT[1], n = GRID_GT[3] + (gy + 0.5) * GRID_GT[5];
            double lu = (e - img_gt[0]) / ldexp(img_gt[1], a->level);
            double lv = (n - img_gt[3]) / ldexp(img_gt[5], a->level);
            /* within the window, or at most half a texel past its edge (clamped) */
            double wu = lu - (double)a->origin[0], wv = lv - (double)a->origin[1];
            EXPECT_TRUE(wu >= -0.5 && wu <= BLOCK + 0.5 && wv >= -0.5 && wv <= BLOCK + 0.5);
            if (a->layer < 0) { /* no layer: the pyramid is transparent there */
                EXPECT_EQ_INT(a->level, want_level);
                int64_t cu = (int64_t)floor(fmin(fmax(wu, 0), BLOCK - 1));
                int64_t cv = (int64_t)floor(fmin(fmax(wv, 0), BLOCK - 1));
                EXPECT_EQ_INT((int)tp_test_pattern_texel(p, a->level, a->origin[0] + cu, a->origin[1] + cv), 0);
                continue;
            }
            const tp_render_item_texture* t = &it[i];
            ASSERT_EQ_INT(t->layer, a->layer);
            /* as the vertex shader: floats */
            float tu = ((float)(gx - t->cell[0]) * t->scale[0] + t->offset[0]) * BLOCK;
            float tv = ((float)(gy - t->cell[1]) * t->scale[1] + t->offset[1]) * BLOCK;
            EXPECT_NEAR(tu, wu, 0.01);
            EXPECT_NEAR(tv, wv, 0.01);
            int xu = (int)floor(tu), yv = (int)floor(tv);
            if (xu >= 0 && xu < BLOCK && yv >= 0 && yv < BLOCK) {
                uint32_t got = px[(size_t)a->layer * layer_px + (size_t)yv * BLOCK + xu];
                EXPECT_EQ_INT((int)got, (int)tp_test_pattern_texel(p, a->level, (int64_t)floor(lu), (int64_t)floor(lv)));
            }
        }
        ASSERT_NO_FAILURE();
    }
    free(px);
    return own;
}

typedef struct flight_leg {
    double speed_mps, yaw_deg, seconds;
} flight_leg;

static void fly(int ts, const tp_imagery_blocks_options* o, const flight_leg* legs, int leg_count,
                int check_every, int expect_evictions)
{
    tp_gl_context* ctx = tp_test_gl_context_or_skip();
    tp_tree* tree = make_tree();
    const tp_tree_geometry* g = tp_tree_get_geometry(tree);
    tp_test_pattern p;
    tp_block_source src = tp_test_pattern_source(&p, (int64_t)GRID << ts, (int64_t)GRID << ts);
    double img_gt[6] = {GRID_GT[0], ldexp(GRID_GT[1], -ts), 0, GRID_GT[3], 0, ldexp(GRID_GT[5], -ts)};
    tp_error err = {{0}};
    tp_imagery_blocks* b = tp_imagery_blocks_create(&src, ts, img_gt, g, o, &err);
    if (!b)
        FAIL("create: %s", err.message);
    tp_cut* cut = NULL;
    ASSERT_OK(tp_cut_create(tree, &cut, &err));
    tp_lod_params lod = {.mode = TP_LOD_ERROR, .tau_px = 2};
    double e = 501500, n = 5008000;
    tp_camera cam;
    tp_clipmap_stats st;
    int frame = 0, ancestors = 0, uploads = 0, max_nodes = 0;
    for (int i = 0; i < leg_count; i++) {
        double a = legs[i].yaw_deg * PI / 180;
        for (int f = 0; f < (int)(legs[i].seconds * 30); f++, frame++) {
            e += sin(a) * legs[i].speed_mps / 30;
            n += cos(a) * legs[i].speed_mps / 30;
            double pos[3] = {e, n, 700};
            tp_camera_from_pose(pos, legs[i].yaw_deg, -25, 60, 1280, 720, &cam);
            ASSERT_OK(tp_cut_update(cut, &cam, &lod, &err));
            tp_imagery_blocks_frame(b, cut, NULL, &cam, 0, 0, &st);
            EXPECT_LE_INT(st.uploads, o->upload_cap_layers ? o->upload_cap_layers : 8);
            EXPECT_EQ_INT((int)st.gpu_bytes, tp_imagery_blocks_layers(b) * BLOCK * BLOCK * 4);
            ancestors += st.missing;
            uploads += st.uploads;
            size_t count;
            tp_cut_nodes(cut, &count);
            max_nodes = (int)count > max_nodes ? (int)count : max_nodes;
            if (frame % check_every == 0)
                check_nodes(b, cut, g, &p, &src, ts);
            ASSERT_NO_FAILURE();
        }
    }
    tp_imagery_blocks_frame(b, cut, NULL, &cam, 1, 30, &st);
    size_t count;
    tp_cut_nodes(cut, &count);
    int own = check_nodes(b, cut, g, &p, &src, ts);
    /* settled: every node its own window, when the pool holds them */
    if ((int)count < tp_imagery_blocks_layers(b)) {
        EXPECT_EQ_INT(st.missing, 0);
        EXPECT_EQ_INT(own, (int)count);
    }
    /* the flight needed more windows than the pool holds: layers were reused */
    EXPECT_GE_INT(uploads, tp_imagery_blocks_layers(b) + 1);
    EXPECT_GE_INT(ancestors, 1); /* and nodes waited on their ancestors' */
    if (expect_evictions) /* the RAM pool collected blocks and read them again: still exact */
        EXPECT_GT((double)st.evictions, 0);
    fprintf(stderr, "%d frames, %d uploads, %d node-frames on an ancestor's layer, at most %d nodes\n",
            frame, uploads, ancestors, max_nodes);
    tp_cut_destroy(cut);
    tp_imagery_blocks_destroy(b);
    tp_tree_destroy(tree);
    tp_gl_context_destroy(ctx);
}

/* 8 texels a post (windows offset from the blocks by half a post at levels 0-2), 96 layers. */
TEST(layers_hold_their_windows_after_a_flight)
{
    flight_leg legs[] = {{900, 90, 3}, {900, 20, 2}, {1500, 200, 2}, {300, 300, 2}};
    tp_imagery_blocks_options o = {.gpu_bytes = 96 * BLOCK * BLOCK * 4};
    fly(3, &o, legs, 4, 7, 0);
}

/* One texel a post (windows are blocks: 16 + 4 + 1 of them with content at levels 0-2), the
 * smallest pool (8 layers), the smallest RAM pool (16 blocks: collected) and one layer a
 * frame. */
TEST(small_pools_one_layer_a_frame_stay_exact)
{
    flight_leg legs[] = {{1500, 90, 5}, {1500, 180, 3}, {1500, 290, 4}};
    tp_imagery_blocks_options o = {.gpu_bytes = 8 * BLOCK * BLOCK * 4,
                                   .cache_bytes = 16 * BLOCK * BLOCK * 4,
                                   .upload_cap_layers = 1};
    fly(0, &o, legs, 3, 11, 1);
}

#define TESTS(X)                                                                                   \
    X(layers_hold_their_windows_after_a_flight)                                                    \
    X(small_pools_one_layer_a_frame_stay_exact)

TP_TEST_MAIN(TESTS)
