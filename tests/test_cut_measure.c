/* test_cut_measure.c - the cut's screen error (tp_cut_measure_error, core/src/cut_measure.c)
 * where the leaves under the drawn nodes are not resident, as in a viewer far above a store
 * (issue 32, item 5): read through the caller's reader, the measure equals the one with every
 * leaf resident and an independent brute force over every sample (tp_cut_drawn_height_at and
 * tp_camera_project); without them nothing is measured and the figures are NaN, never 0; a
 * measured 0 comes only from full resolution; the sampling stays within its budget and only
 * ever sees errors the whole measure sees.
 */
#include "tp_test.h"

#include <stdint.h>

#include "tp_test_hgt.h"

/* the crop's posts 22.6 m apart, as a 3601^2 SRTM1 tile's on its UTM grid (the issue's) */
static const double GT[6] = {400000, 22.6, 0, 4800000, 0, -22.6};
enum { W = 900, H = 900, PATCH = 17 };

typedef struct fixture {
    float* h;
    tp_tree* t;
    const tp_tree_geometry* g;
    const uint16_t** saved; /* every node's samples, kept while detached */
    size_t block;           /* (2^n+1)^2 */
    int reads, fail;        /* the reader's calls; fail: it refuses every leaf */
    int64_t* read_ids;      /* when set: the leaves read, in order (reads of them) */
} fixture;

static int fixture_open(fixture* f)
{
    memset(f, 0, sizeof *f);
    f->h = load_hgt(150, 150, W, H);
    if (!f->h)
        return 0;
    ASSERT_OK(tp_tree_create_from_grid(f->h, (size_t)W * H, W, H, GT, PATCH, 0, &f->t, NULL));
    f->g = tp_tree_get_geometry(f->t);
    f->saved = calloc((size_t)f->g->node_count, sizeof *f->saved);
    for (int64_t id = 0; id < f->g->node_count; id++)
        f->saved[id] = tp_tree_samples(f->t, id);
    f->block = (((size_t)1 << f->g->n) + 1) * (((size_t)1 << f->g->n) + 1);
    return 1;
}

static void fixture_close(fixture* f)
{
    for (int64_t id = 0; id < f->g->node_count; id++) /* the tree frees what it owns */
        if (!tp_tree_samples(f->t, id))
            tp_tree_attach(f->t, id, f->saved[id]);
    free(f->saved);
    tp_tree_destroy(f->t);
    free(f->h);
}

/* The reader: a store's tp_store_read_node, here the leaf's saved samples. */
static int read_leaf(void* user, int64_t leaf, uint16_t* samples)
{
    fixture* f = user;
    int s, c, r;
    tp_tree_node_locate(f->g, leaf, &s, &c, &r);
    ASSERT_EQ_INT(0, s);
    ASSERT_TRUE(tp_tree_samples(f->t, leaf) == NULL); /* only what the tree lacks */
    if (f->read_ids)
        f->read_ids[f->reads] = leaf;
    f->reads++;
    if (f->fail)
        return 0;
    memcpy(samples, f->saved[leaf], f->block * sizeof *samples);
    return 1;
}

/* Detaches every leaf the cut does not draw: what a stream holds after a view from far above
 * (the drawn nodes and their ancestors). Returns how many. */
static int detach_undrawn_leaves(fixture* f, const tp_cut* cut)
{
    size_t count;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    uint8_t* drawn = calloc((size_t)f->g->node_count, 1);
    for (size_t i = 0; i < count; i++)
        drawn[nodes[i].node] = 1;
    int n = 0;
    for (int r = 0; r < f->g->rows; r++)
        for (int c = 0; c < f->g->cols; c++) {
            int64_t id = tp_tree_node_id(f->g, 0, c, r);
            if (!drawn[id] && tp_tree_samples(f->t, id)) {
                tp_tree_detach(f->t, id);
                n++;
            }
        }
    free(drawn);
    return n;
}

static void attach_all(fixture* f)
{
    for (int64_t id = 0; id < f->g->node_count; id++)
        if (!tp_tree_samples(f->t, id))
            tp_tree_attach(f->t, id, f->saved[id]);
}

/* 60 km up, 50 km south of the crop's centre looking north 50 degrees down at it: the whole
 * crop in view, drawn by coarse nodes (the view of a 3601^2 tile), leaves where its
 * voids are. */
static void far_camera(tp_camera* cam)
{
    double eye[3] = {GT[0] + W / 2.0 * GT[1], GT[3] + (H / 2.0 + 50000 / GT[1]) * GT[5], 60000};
    tp_camera_from_pose(eye, 0, -50, 60, 1280, 720, cam);
}

/* The brute force: every sample of the source grid whose true position is in view, against
 * the drawn surface above or below it (tp_cut_drawn_height_at), the on-screen distance between
 * the two projections (tp_camera_project). All leaves resident. */
static void brute_force(const fixture* f, const tp_cut* cut, const tp_camera* cam, double* max,
                        double* rms, size_t* count)
{
    double sum = 0;
    *max = 0;
    *count = 0;
    for (int y = 0; y < f->g->src_height; y++)
        for (int x = 0; x < f->g->src_width; x++) {
            double truth = tp_tree_sample(f->t, x, y), drawn = tp_cut_drawn_height_at(cut, x, y);
            if (isnan(truth) || isnan(drawn))
                continue;
            double e = GT[0] + (x + 0.5) * GT[1], n = GT[3] + (y + 0.5) * GT[5];
            double pt[3] = {e, n, truth}, pd[3] = {e, n, drawn}, a[2], b[2];
            if (!tp_camera_project(cam, pt, a, NULL) || a[0] < 0 || a[0] > cam->viewport_w_px ||
                a[1] < 0 || a[1] > cam->viewport_h_px)
                continue;
            ASSERT_TRUE(tp_camera_project(cam, pd, b, NULL)); /* far above: in front */
            double d = hypot(a[0] - b[0], a[1] - b[1]);
            *max = d > *max ? d : *max;
            sum += d * d;
            ++*count;
        }
    *rms = *count ? sqrt(sum / (double)*count) : NAN;
}

TEST(far_view_reads_the_leaves_it_lacks)
{
    fixture f;
    if (!fixture_open(&f))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(f.t, &cut, NULL));
    tp_camera cam;
    far_camera(&cam);
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
    tp_cut_stats st;
    tp_cut_get_stats(cut, &st);
    EXPECT_EQ_INT(0, st.substituted);
    /* coarse nodes over most of the crop: most leaves are not resident */
    EXPECT_GT(st.nodes_per_scale[1] + st.nodes_per_scale[2], 0);
    int detached = detach_undrawn_leaves(&f, cut);
    EXPECT_GT(detached, f.g->cols * f.g->rows * 3 / 4);
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL)); /* the same cut: no leaf was wanted */
    tp_cut_stats st2;
    tp_cut_get_stats(cut, &st2);
    EXPECT_EQ_INT(st.drawn, st2.drawn);
    EXPECT_EQ_INT((long long)st.triangles, (long long)st2.triangles);

    /* the resident leaves only (what view --stats-json measured before): those drawn, the
     * fewer samples; the rest skipped */
    tp_cut_error none;
    ASSERT_OK(tp_cut_measure_error(cut, &cam, NULL, &none));
    EXPECT_GT(none.skipped, none.samples);
    EXPECT_GT(none.leaves_skipped, (size_t)1000);
    EXPECT_EQ_INT(0, (long long)none.leaves_read);

    /* through the reader */
    tp_cut_measure_options o = {read_leaf, &f, 0, 0, NULL};
    tp_cut_error read;
    ASSERT_OK(tp_cut_measure_error(cut, &cam, &o, &read));
    EXPECT_EQ_INT(0, (long long)read.skipped);
    EXPECT_EQ_INT(0, (long long)read.leaves_skipped);
    EXPECT_EQ_INT(0, read.per_node);
    EXPECT_EQ_INT((long long)read.leaves, (long long)read.leaves_sampled);
    EXPECT_EQ_INT(f.reads, (int)read.leaves_read);
    EXPECT_GT(read.leaves_read, read.leaves_measured / 2);
    EXPECT_LE(read.leaves_read, (size_t)detached);
    EXPECT_GT(read.max_px, 0.0); /* coarse levels drawn: an error */
    EXPECT_LE(read.max_px, lp.tau_px + 1e-6);

    /* the same as with every leaf resident, and as the brute force */
    attach_all(&f);
    tp_cut_error all;
    ASSERT_OK(tp_cut_measure_error(cut, &cam, NULL, &all));
    EXPECT_EQ_INT((long long)all.samples, (long long)read.samples);
    EXPECT_EQ_DBL(all.max_px, read.max_px);
    EXPECT_EQ_DBL(all.rms_px, read.rms_px);
    EXPECT_EQ_INT(0, (long long)all.leaves_read);
    double bmax, brms;
    size_t bcount;
    brute_force(&f, cut, &cam, &bmax, &brms, &bcount);
    tp_test_note("%d nodes drawn; measured %zu samples of %zu leaves (%zu read): max %.4f px, "
                 "RMS %.4f px; brute force %zu samples, max %.4f px, RMS %.4f px",
                 st.drawn, read.samples, read.leaves_measured, read.leaves_read, read.max_px,
                 read.rms_px, bcount, bmax, brms);
    /* the same samples but where an incomplete node's hole meets a drawn edge */
    EXPECT_NEAR((double)bcount, (double)read.samples, 1e-4 * (double)bcount + 2);
    EXPECT_NEAR(bmax, read.max_px, 1e-6 * bmax);
    EXPECT_NEAR(brms, read.rms_px, 1e-4 * brms);
    EXPECT_GT((double)bcount, 0.9 * W * H); /* the whole crop is in view */

    /* a reader that fails: those leaves are left out and counted */
    detach_undrawn_leaves(&f, cut);
    f.fail = 1;
    tp_cut_error failed;
    ASSERT_OK(tp_cut_measure_error(cut, &cam, &o, &failed));
    EXPECT_EQ_INT((long long)none.skipped, (long long)failed.skipped);
    EXPECT_EQ_INT((long long)none.leaves_skipped, (long long)failed.leaves_skipped);
    EXPECT_EQ_INT((long long)none.samples, (long long)failed.samples);
    EXPECT_TRUE(none.samples ? failed.max_px == none.max_px : isnan(failed.max_px));
    tp_cut_destroy(cut);
    fixture_close(&f);
}

/* The leaves named to o->prefetch, recorded (one call a measure). */
typedef struct prefetched {
    int64_t* ids;
    size_t count;
    int calls;
} prefetched;
static prefetched g_pre;

static void record_prefetch(void* user, const int64_t* leaves, size_t count)
{
    (void)user;
    g_pre.calls++;
    free(g_pre.ids);
    g_pre.ids = malloc(count * sizeof *leaves);
    memcpy(g_pre.ids, leaves, count * sizeof *leaves);
    g_pre.count = count;
}

/* o->prefetch (a store over HTTP fetches them concurrently) is told, once and before any is
 * read, exactly the leaves read_leaf is then asked for, in that order: every leaf, and sampled
 * to a budget; the measure is the one without it. */
TEST(prefetch_names_the_leaves_read)
{
    fixture f;
    if (!fixture_open(&f))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(f.t, &cut, NULL));
    tp_camera cam;
    double eye[3] = {GT[0] + W / 2.0 * GT[1], GT[3] + (H + 100.0) * GT[5], 28000};
    double pitch = -atan2(eye[2], (H / 2.0 + 100) * GT[1]) * 180 / 3.14159265358979;
    tp_camera_from_pose(eye, 0, pitch, 60, 640, 360, &cam);
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 2};
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
    detach_undrawn_leaves(&f, cut);
    f.read_ids = calloc((size_t)f.g->node_count, sizeof *f.read_ids);
    for (size_t max_leaves = 0; max_leaves <= 64; max_leaves += 64) {
        tp_cut_measure_options plain = {read_leaf, &f, max_leaves, 7, NULL};
        tp_cut_measure_options o = {read_leaf, &f, max_leaves, 7, record_prefetch};
        tp_cut_error a, b;
        f.reads = 0;
        ASSERT_OK(tp_cut_measure_error(cut, &cam, &plain, &a));
        free(g_pre.ids);
        memset(&g_pre, 0, sizeof g_pre);
        f.reads = 0;
        ASSERT_OK(tp_cut_measure_error(cut, &cam, &o, &b));
        tp_test_note("max_leaves %zu: %zu leaves named, %d read, %zu sampled", max_leaves,
                     g_pre.count, f.reads, b.leaves_sampled);
        EXPECT_EQ_INT(1, g_pre.calls);
        ASSERT_EQ_INT(f.reads, (long long)g_pre.count);
        EXPECT_GT(f.reads, 10);
        for (int i = 0; i < f.reads; i++)
            ASSERT_EQ_INT((long long)f.read_ids[i], (long long)g_pre.ids[i]);
        EXPECT_EQ_INT((long long)a.samples, (long long)b.samples);
        EXPECT_EQ_DBL(a.max_px, b.max_px);
        EXPECT_EQ_INT((long long)a.leaves_read, (long long)b.leaves_read);
        if (max_leaves)
            EXPECT_GT(b.per_node, 0); /* the sampling took part */
    }
    free(g_pre.ids);
    free(f.read_ids);
    f.read_ids = NULL;
    tp_cut_destroy(cut);
    fixture_close(&f);
}

/* A measured 0 only at full resolution: the full mode's cut measures exactly 0 over every
 * sample in view; the error mode's cut, which draws coarser levels, measures more; a view of
 * the sky measures nothing (NaN, and the old figures' 0 with 0 samples). */
TEST(zero_only_at_full_resolution)
{
    fixture f;
    if (!fixture_open(&f))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(f.t, &cut, NULL));
    tp_cut_measure_options o = {read_leaf, &f, 0, 0, NULL};
    for (int k = 0; k < 3; k++) { /* 8, 28 and 48 km up, south of the crop, looking at it */
        tp_camera cam;
        double eye[3] = {GT[0] + W / 2.0 * GT[1], GT[3] + (H + 100.0) * GT[5], 8000 + 20000 * k};
        double pitch = -atan2(eye[2], (H / 2.0 + 100) * GT[1]) * 180 / 3.14159265358979;
        tp_camera_from_pose(eye, 0, pitch, 60, 640, 360, &cam);
        tp_lod_params full = {.mode = TP_LOD_FULL};
        ASSERT_OK(tp_cut_update(cut, &cam, &full, NULL));
        tp_cut_error e;
        ASSERT_OK(tp_cut_measure_error(cut, &cam, &o, &e));
        EXPECT_GT(e.samples, (size_t)10000);
        EXPECT_EQ_DBL(0.0, e.max_px);
        EXPECT_EQ_DBL(0.0, e.rms_px);
        for (int tau = 1; tau <= 4; tau *= 2) {
            tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = tau};
            ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
            size_t count;
            const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
            int coarse = 0;
            for (size_t i = 0; i < count; i++) {
                int s, c, r;
                tp_tree_node_locate(f.g, nodes[i].node, &s, &c, &r);
                coarse += s > 0 || nodes[i].level < f.g->n;
            }
            detach_undrawn_leaves(&f, cut);
            f.reads = 0;
            ASSERT_OK(tp_cut_measure_error(cut, &cam, &o, &e));
            tp_test_note("camera %d, tau %d: %d of %zu nodes coarse; max %.3f px RMS %.3f px over "
                         "%zu samples (%d leaves read)",
                         k, tau, coarse, count, e.max_px, e.rms_px, e.samples, f.reads);
            ASSERT_GT(coarse, 0);
            EXPECT_GT(e.samples, (size_t)10000);
            EXPECT_GT(e.max_px, 0.0);
            EXPECT_GT(e.rms_px, 0.0);
            EXPECT_LE(e.max_px, tau + 1e-6);
            EXPECT_GT(f.reads, 0);
            attach_all(&f);
        }
    }
    tp_camera sky;
    double eye[3] = {GT[0] + W / 2.0 * GT[1], GT[3] + H / 2.0 * GT[5], 5000};
    tp_camera_from_pose(eye, 0, 60, 60, 640, 360, &sky);
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    ASSERT_OK(tp_cut_update(cut, &sky, &lp, NULL));
    tp_cut_error e;
    ASSERT_OK(tp_cut_measure_error(cut, &sky, &o, &e));
    EXPECT_EQ_INT(0, (long long)e.samples);
    EXPECT_TRUE(isnan(e.max_px) && isnan(e.rms_px));
    double max_px = -1, rms_px = -1;
    size_t samples = 1;
    ASSERT_OK(tp_cut_measure_screen_error(cut, &sky, &max_px, &rms_px, &samples, NULL));
    EXPECT_EQ_INT(0, (long long)samples); /* the old figures: 0 with 0 samples */
    EXPECT_EQ_DBL(0.0, max_px);
    tp_cut_destroy(cut);
    fixture_close(&f);
}

/* Sampling: at most m x m leaves a node, m a power of two chosen for the budget; a subset of
 * the whole measure's samples (so never a larger error), every drawn node measured; a budget
 * the cut fits measures everything. */
TEST(sampling_keeps_to_its_budget)
{
    fixture f;
    if (!fixture_open(&f))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(f.t, &cut, NULL));
    tp_camera cam;
    far_camera(&cam);
    tp_lod_params lp = {.mode = TP_LOD_DISTANCE}; /* few large nodes */
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
    size_t count;
    tp_cut_nodes(cut, &count);
    detach_undrawn_leaves(&f, cut);
    tp_cut_measure_options o = {read_leaf, &f, 0, 0, NULL};
    tp_cut_error all;
    ASSERT_OK(tp_cut_measure_error(cut, &cam, &o, &all));
    ASSERT_GT(all.max_px, 0.0);
    const size_t budgets[] = {1, 64, 500, 2000, all.leaves};
    for (size_t b = 0; b < sizeof budgets / sizeof *budgets; b++)
        for (uint32_t seed = 0; seed < 3; seed++) {
            o.max_leaves = budgets[b];
            o.seed = seed;
            f.reads = 0;
            tp_cut_error e;
            ASSERT_OK(tp_cut_measure_error(cut, &cam, &o, &e));
            tp_test_note("budget %zu, seed %u: %zu nodes, m %d, %zu of %zu leaves, max %.3f px "
                         "(whole %.3f)",
                         budgets[b], seed, count, e.per_node, e.leaves_sampled, e.leaves,
                         e.max_px, all.max_px);
            EXPECT_EQ_INT((long long)all.leaves, (long long)e.leaves);
            EXPECT_LE(e.max_px, all.max_px);
            EXPECT_LE(e.samples, all.samples);
            EXPECT_GT(e.samples, (size_t)0);
            EXPECT_EQ_INT(f.reads, (int)e.leaves_read);
            if (budgets[b] >= all.leaves) { /* it fits: everything, the same figures */
                EXPECT_EQ_INT(0, e.per_node);
                EXPECT_EQ_INT((long long)all.samples, (long long)e.samples);
                EXPECT_EQ_DBL(all.max_px, e.max_px);
                continue;
            }
            ASSERT_GT(e.per_node, 0);
            EXPECT_EQ_INT(0, e.per_node & (e.per_node - 1)); /* a power of two */
            EXPECT_GE(e.leaves_sampled, count); /* every drawn node: a leaf at least */
            if (e.per_node > 1)
                EXPECT_LE(e.leaves_sampled, budgets[b]);
            else
                EXPECT_LE(e.leaves_sampled, budgets[b] > count ? budgets[b] : count);
        }
    tp_cut_destroy(cut);
    fixture_close(&f);
}

/* --stitch add: the triangles drawn, added vertices included; read leaves or resident ones,
 * the same figures. */
TEST(stitch_add_reads_the_same_as_resident)
{
    fixture f;
    if (!fixture_open(&f))
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(f.t, &cut, NULL));
    tp_cut_set_stitch_add(cut, 1);
    tp_camera cam;
    far_camera(&cam);
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
    tp_cut_stats st;
    tp_cut_get_stats(cut, &st);
    tp_cut_error all, read;
    ASSERT_OK(tp_cut_measure_error(cut, &cam, NULL, &all));
    detach_undrawn_leaves(&f, cut);
    tp_cut_measure_options o = {read_leaf, &f, 0, 0, NULL};
    ASSERT_OK(tp_cut_measure_error(cut, &cam, &o, &read));
    tp_test_note("%d sides take vertices; max %.4f px over %zu samples", st.add_sides,
                 read.max_px, read.samples);
    EXPECT_GT(st.add_sides, 0);
    EXPECT_GT(read.leaves_read, (size_t)0);
    EXPECT_EQ_INT((long long)all.samples, (long long)read.samples);
    EXPECT_EQ_DBL(all.max_px, read.max_px);
    EXPECT_EQ_DBL(all.rms_px, read.rms_px);
    EXPECT_GT(read.max_px, 0.0);
    EXPECT_LE(read.max_px, 1 + 1e-6);
    tp_cut_destroy(cut);
    fixture_close(&f);
}

#define TESTS(X)                                                                                   \
    X(far_view_reads_the_leaves_it_lacks)                                                          \
    X(prefetch_names_the_leaves_read)                                                              \
    X(zero_only_at_full_resolution)                                                                \
    X(sampling_keeps_to_its_budget)                                                                \
    X(stitch_add_reads_the_same_as_resident)

TP_TEST_MAIN(TESTS)
