/* test_pgm_clip.c - PGM over a store: the elevation clipmap's bookkeeping (core/src/pgm_clip.c).
 * Flights of a window (steps of 0, +-1, +-(w-1), +-w, huge jumps, negative origins) checked by
 * brute force: after every step each texel holds the post of the window that maps to it, each
 * gained post written exactly once and no kept one rewritten; origins stay on the terrain;
 * every pyramid post of a store's tree is found in a node holding its height; the smallest
 * window holding the coarsest level (24 levels at most) is 16 up to 15 x 2^23 + 1 posts. */
#define _POSIX_C_SOURCE 200809L
#include "tp_io.h"
#include "tp_test.h"

#include <limits.h>

#define TESTS(X)                                                                                   \
    X(update_writes_each_gained_post_once_and_leaves_no_stale_texel)                               \
    X(update_cases_by_hand)                                                                        \
    X(origin_centres_and_clamps_to_the_terrain)                                                    \
    X(clamped_flight_over_small_and_large_levels)                                                  \
    X(store_post_finds_every_pyramid_post_of_mt_hood)                                              \
    X(min_window_holds_the_coarsest_level)

/* The brute force: a w x w "texture" whose texel (x mod w, y mod w) remembers the post last
 * written there; a step applies the rectangles, counting writes per post of the new window. */
typedef struct {
    int w, has;
    int ox, oy;
    long long* tag_x; /* the post written to each texel */
    long long* tag_y;
    int* writes; /* per post of the new window, this step */
} sim;

static long long wrap(long long v, int w)
{
    long long m = v % w;
    return m < 0 ? m + w : m;
}

static void sim_step(sim* s, int nx, int ny)
{
    tp_pgm_rect r[2];
    int n = tp_pgm_clip_update(s->w, s->has, s->ox, s->oy, nx, ny, r);
    ASSERT_TRUE(n >= 0 && n <= 2);
    int w = s->w;
    memset(s->writes, 0, (size_t)w * w * sizeof *s->writes);
    for (int k = 0; k < n; k++) {
        ASSERT_TRUE(r[k].x1 > r[k].x0 && r[k].y1 > r[k].y0); /* no empty rectangle */
        for (long long y = r[k].y0; y < r[k].y1; y++)
            for (long long x = r[k].x0; x < r[k].x1; x++) {
                /* inside the new window */
                ASSERT_TRUE(x >= nx && x < (long long)nx + w && y >= ny && y < (long long)ny + w);
                s->writes[(y - ny) * w + (x - nx)]++;
                size_t t = (size_t)(wrap(y, w) * w + wrap(x, w));
                s->tag_x[t] = x, s->tag_y[t] = y;
            }
    }
    for (long long y = ny; y < (long long)ny + w; y++)
        for (long long x = nx; x < (long long)nx + w; x++) {
            int kept = s->has && x >= s->ox && x < (long long)s->ox + w && y >= s->oy &&
                       y < (long long)s->oy + w;
            int c = s->writes[(y - ny) * w + (x - nx)];
            if (c != (kept ? 0 : 1))
                FAIL("w %d: (%d, %d) -> (%d, %d): post (%lld, %lld) written %d times (%s)", w,
                     s->ox, s->oy, nx, ny, x, y, c, kept ? "kept" : "gained");
            size_t t = (size_t)(wrap(y, w) * w + wrap(x, w));
            if (s->tag_x[t] != x || s->tag_y[t] != y)
                FAIL("w %d: after (%d, %d) -> (%d, %d) texel of post (%lld, %lld) holds (%lld, "
                     "%lld): stale",
                     w, s->ox, s->oy, nx, ny, x, y, s->tag_x[t], s->tag_y[t]);
        }
    s->has = 1, s->ox = nx, s->oy = ny;
}

static void sim_init(sim* s, int w)
{
    memset(s, 0, sizeof *s);
    s->w = w;
    s->tag_x = malloc((size_t)w * w * sizeof *s->tag_x);
    s->tag_y = malloc((size_t)w * w * sizeof *s->tag_y);
    s->writes = malloc((size_t)w * w * sizeof *s->writes);
    ASSERT_TRUE(s->tag_x && s->tag_y && s->writes);
    for (size_t k = 0; k < (size_t)w * w; k++)
        s->tag_x[k] = s->tag_y[k] = LLONG_MIN; /* never written */
}

static void sim_free(sim* s)
{
    free(s->tag_x), free(s->tag_y), free(s->writes);
}

static uint32_t rng = 12345u;
static uint32_t next(void)
{
    rng = rng * 1664525u + 1013904223u;
    return rng >> 8;
}

TEST(update_writes_each_gained_post_once_and_leaves_no_stale_texel)
{
    const int ws[] = {1, 2, 4, 8, 16, 32};
    for (size_t wi = 0; wi < sizeof ws / sizeof ws[0]; wi++) {
        int w = ws[wi];
        sim s;
        sim_init(&s, w);
        sim_step(&s, -3, 5); /* the first fill: everything */
        const int steps[] = {0, 1, -1, w - 1, -(w - 1), w, -w, w + 1, -(w + 1), 2};
        int nsteps = (int)(sizeof steps / sizeof steps[0]);
        /* every pair of steps along x and y, from wherever the flight has got to */
        for (int a = 0; a < nsteps; a++)
            for (int b = 0; b < nsteps; b++)
                sim_step(&s, s.ox + steps[a], s.oy + steps[b]);
        /* a random flight through negative origins and back */
        for (int k = 0; k < 2000; k++) {
            int dx = (int)(next() % 7) - 3, dy = (int)(next() % 7) - 3;
            if (next() % 50 == 0)
                dx *= w, dy *= w; /* now and then a jump */
            sim_step(&s, s.ox + dx, s.oy + dy);
        }
        /* huge jumps, far into negative and positive origins */
        sim_step(&s, -1000000000, 7);
        sim_step(&s, -1000000000 + 1, 6);
        sim_step(&s, 1000000000, -1000000000);
        sim_step(&s, 1000000000 - (w - 1), -1000000000 + (w - 1));
        sim_free(&s);
    }
}

TEST(update_cases_by_hand)
{
    tp_pgm_rect r[2];
    /* nothing held yet: the whole window */
    ASSERT_EQ_INT(1, tp_pgm_clip_update(8, 0, 0, 0, -2, 3, r));
    EXPECT_EQ_INT(-2, r[0].x0);
    EXPECT_EQ_INT(3, r[0].y0);
    EXPECT_EQ_INT(6, r[0].x1);
    EXPECT_EQ_INT(11, r[0].y1);
    /* no move: nothing */
    EXPECT_EQ_INT(0, tp_pgm_clip_update(8, 1, 4, 4, 4, 4, r));
    /* one column east: the column x = 12, rows 4..11 */
    ASSERT_EQ_INT(1, tp_pgm_clip_update(8, 1, 4, 4, 5, 4, r));
    EXPECT_EQ_INT(12, r[0].x0);
    EXPECT_EQ_INT(13, r[0].x1);
    EXPECT_EQ_INT(4, r[0].y0);
    EXPECT_EQ_INT(12, r[0].y1);
    /* two west and one north: the L: columns 2..3 (rows 3..10) and row 3 over columns 4..9 */
    ASSERT_EQ_INT(2, tp_pgm_clip_update(8, 1, 4, 4, 2, 3, r));
    EXPECT_EQ_INT(2, r[0].x0);
    EXPECT_EQ_INT(4, r[0].x1);
    EXPECT_EQ_INT(3, r[0].y0);
    EXPECT_EQ_INT(11, r[0].y1);
    EXPECT_EQ_INT(4, r[1].x0);
    EXPECT_EQ_INT(10, r[1].x1);
    EXPECT_EQ_INT(3, r[1].y0);
    EXPECT_EQ_INT(4, r[1].y1);
    /* a move of w along one axis only: the whole window again */
    ASSERT_EQ_INT(1, tp_pgm_clip_update(8, 1, 4, 4, 4, -4, r));
    EXPECT_EQ_INT(-4, r[0].y0);
    EXPECT_EQ_INT(4, r[0].y1);
}

TEST(origin_centres_and_clamps_to_the_terrain)
{
    /* the whole axis fits: never moves */
    EXPECT_EQ_INT(0, tp_pgm_clip_origin(-1e9, 64, 64));
    EXPECT_EQ_INT(0, tp_pgm_clip_origin(37.5, 40, 64));
    EXPECT_EQ_INT(0, tp_pgm_clip_origin(1e12, 2, 512));
    /* centred: floor(c) - w / 2, so that the post under the eye and its neighbours are held */
    EXPECT_EQ_INT(100 - 32, tp_pgm_clip_origin(100.9, 1000, 64));
    EXPECT_EQ_INT(100 - 32, tp_pgm_clip_origin(100.0, 1000, 64));
    EXPECT_EQ_INT(99 - 32, tp_pgm_clip_origin(99.99, 1000, 64));
    /* clamped at either edge, for eyes off the terrain (negative, huge, infinite) and NaN */
    EXPECT_EQ_INT(0, tp_pgm_clip_origin(10, 1000, 64));
    EXPECT_EQ_INT(0, tp_pgm_clip_origin(-5e9, 1000, 64));
    EXPECT_EQ_INT(0, tp_pgm_clip_origin(-INFINITY, 1000, 64));
    EXPECT_EQ_INT(1000 - 64, tp_pgm_clip_origin(990, 1000, 64));
    EXPECT_EQ_INT(1000 - 64, tp_pgm_clip_origin(5e9, 1000, 64));
    EXPECT_EQ_INT(1000 - 64, tp_pgm_clip_origin(INFINITY, 1000, 64));
    EXPECT_EQ_INT(0, tp_pgm_clip_origin(NAN, 1000, 64));
    /* one post more than the window: two origins only */
    EXPECT_EQ_INT(0, tp_pgm_clip_origin(31.9, 65, 64));
    EXPECT_EQ_INT(1, tp_pgm_clip_origin(33, 65, 64));
}

/* A flight over a level of 37 posts (smaller than the window: partly off the terrain, never
 * moves) and one of 300 (clamped at its edges): origins from tp_pgm_clip_origin, the window on
 * the terrain, the brute force as above. */
TEST(clamped_flight_over_small_and_large_levels)
{
    const int w = 64, sizes[2] = {37, 300};
    for (int k = 0; k < 2; k++) {
        int posts = sizes[k];
        sim s;
        sim_init(&s, w);
        int updates = 0;
        double cx = -200, cy = posts + 150.0; /* off the terrain at first */
        for (int f = 0; f < 1500; f++) {
            cx += (f < 700 ? 0.9 : -0.4) + 0.01 * (int)(next() % 50);
            cy -= 0.7;
            int ox = tp_pgm_clip_origin(cx, posts, w), oy = tp_pgm_clip_origin(cy, posts, w);
            if (posts >= w) {
                EXPECT_TRUE(ox >= 0 && ox + w <= posts && oy >= 0 && oy + w <= posts);
            } else {
                EXPECT_EQ_INT(0, ox);
                EXPECT_EQ_INT(0, oy);
            }
            tp_pgm_rect r[2];
            updates += tp_pgm_clip_update(w, s.has, s.ox, s.oy, ox, oy, r) > 0;
            sim_step(&s, ox, oy);
        }
        if (posts < w)
            EXPECT_EQ_INT(1, updates); /* filled once */
        else
            EXPECT_GT(updates, 100);
        sim_free(&s);
    }
}

/* Every post of every level of the pyramid of Mt Hood's grid (1013 x 799, nodes of 17 and 65:
 * leaf columns not a power of two, posts past the last whole node of a scale) is found in a
 * node of scale <= its level, in the node's lattice, holding the full-resolution height there
 * (the tree's finest resident sample); posts of levels at or below the roots' scale whose node
 * exists come from that scale. */
TEST(store_post_finds_every_pyramid_post_of_mt_hood)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    const int patch[2] = {17, 65};
    for (int pk = 0; pk < 2; pk++) {
        tp_tree* t = NULL;
        ASSERT_OK(tp_tree_create_from_grid(dem->heights, (size_t)dem->width * dem->height,
                                           dem->width, dem->height, dem->geotransform, patch[pk], 0,
                                           &t, &err));
        const tp_tree_geometry* g = tp_tree_get_geometry(t);
        tp_tree_info ti;
        tp_tree_get_info(t, &ti);
        size_t checked = 0, drawn = 0, at_level_scale = 0;
        for (int l = 0; l < 12; l++) {
            int pw = (int)(((long long)g->src_width - 1 + (1ll << l) - 1) >> l) + 1;
            int ph = (int)(((long long)g->src_height - 1 + (1ll << l) - 1) >> l) + 1;
            for (int j = 0; j < ph; j++)
                for (int i = 0; i < pw; i++) {
                    long long xl = (long long)i << l, yl = (long long)j << l;
                    int x = (int)(xl < g->src_width - 1 ? xl : g->src_width - 1);
                    int y = (int)(yl < g->src_height - 1 ? yl : g->src_height - 1);
                    size_t sample;
                    int64_t node = tp_pgm_store_post(g, l, x, y, &sample);
                    int s, c, r;
                    tp_tree_node_locate(g, node, &s, &c, &r);
                    ASSERT_TRUE(s <= l && sample < (size_t)((1 << g->n) + 1) * ((1 << g->n) + 1));
                    int si = (int)(sample % (size_t)((1 << g->n) + 1));
                    int sj = (int)(sample / (size_t)((1 << g->n) + 1));
                    /* the node's lattice point is the post */
                    ASSERT_EQ_INT(x, (c << (g->n + s)) + (si << s));
                    ASSERT_EQ_INT(y, (r << (g->n + s)) + (sj << s));
                    const uint16_t* z = tp_tree_samples(t, node);
                    ASSERT_TRUE(z != NULL);
                    double want = tp_tree_sample(t, x, y);
                    if (z[sample] == TP_TREE_NO_HEIGHT) {
                        ASSERT_TRUE(isnan(want));
                    } else {
                        double got = (z[sample] + tp_tree_meta(t, node)->qmin) * ti.height_step_m;
                        ASSERT_NEAR(want, got, 0.0);
                        drawn++;
                    }
                    int want_s = l < g->scales - 1 ? l : g->scales - 1;
                    at_level_scale += s == want_s;
                    checked++;
                }
        }
        tp_test_note("patch %d: %zu posts checked (%zu drawn), %zu from the level's own scale",
                     patch[pk], checked, drawn, at_level_scale);
        EXPECT_GT(drawn, checked / 2);
        EXPECT_GT(at_level_scale, checked / 2);
        tp_tree_destroy(t);
    }
    tp_dem_destroy(dem);
}

/* The closed form of the coarsest level's posts along a side (tp_core.h: width[l] =
 * ceil((width[0] - 1) / 2^l) + 1, levels stop at <= 2 posts or 24 levels). */
static long long coarsest_posts(long long side)
{
    for (int l = 0;; l++) {
        long long step = 1LL << l, n = (side - 1 + step - 1) / step + 1;
        if (side == 1)
            n = 1;
        if (n <= 2 || l == TP_PGM_MAX_LEVELS - 1)
            return n;
    }
}

TEST(min_window_holds_the_coarsest_level)
{
    const long long t = 1LL << 23;
    const long long sides[] = {1,          2,          3,          1201,       65537,
                               1LL << 24,  (1LL << 24) + 1, (1LL << 24) + 2, 1LL << 30,
                               15 * t + 1, 15 * t + 2, 16 * t + 1, 31 * t + 2, INT_MAX};
    const int n = (int)(sizeof sides / sizeof sides[0]);
    for (int a = 0; a < n; a++)
        for (int b = 0; b < n; b += 3) {
            long long ca = coarsest_posts(sides[a]), cb = coarsest_posts(sides[b]);
            long long c = ca > cb ? ca : cb, want = 16;
            while (want < c)
                want *= 2;
            int got = tp_pgm_clip_min_window((int)sides[a], (int)sides[b]);
            if (got != want)
                ADD_FAILURE("%lld x %lld: %d, expected %lld (the coarsest level: %lld posts)",
                            sides[a], sides[b], got, want, c);
        }
    /* the boundaries by hand: 16 posts at level 23 fit 16, 17 need 32, 33 need 64 */
    EXPECT_EQ_INT(16, tp_pgm_clip_min_window(65537, 65537));
    EXPECT_EQ_INT(16, tp_pgm_clip_min_window((int)(15 * t + 1), 3));
    EXPECT_EQ_INT(32, tp_pgm_clip_min_window((int)(15 * t + 2), 3));
    EXPECT_EQ_INT(32, tp_pgm_clip_min_window(3, (int)(16 * t + 1)));
    EXPECT_EQ_INT(32, tp_pgm_clip_min_window(3, (int)(31 * t + 1)));
    EXPECT_EQ_INT(64, tp_pgm_clip_min_window(3, (int)(31 * t + 2)));
    EXPECT_EQ_INT(512, tp_pgm_clip_min_window(INT_MAX, INT_MAX)); /* 257 posts */
}

TP_TEST_MAIN(TESTS)
