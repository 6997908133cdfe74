/*
 * test_selection.c - one frame's selection: levels, visibility, dirty flags, statistics,
 * error measurement, drawn-height queries and camera collision (tp_selection_*).
 *
 * The terrain is synthetic (float heights, nodata holes, padding) so that every branch is
 * exercised without tp_io. Expectations come from the other public functions used as building
 * blocks (tp_patch_vertices / tp_patch_triangles, tp_frustum_test_aabb) and from an
 * independent rasterisation of the drawn triangles.
 */
#include "tp_test_geom.h"

#include <pthread.h>

#define PI 3.14159265358979323846

typedef struct world {
    float* src;
    tp_terrain* t;
    tp_terrain_info ti;
    tp_selection* s;
} world;

static void world_create(world* w)
{
    int W = 100, H = 70, i;
    double gt[6] = {400000.0, 10.0, 0.0, 5200000.0, 0.0, -10.0};
    tp_error err;
    tp_rng rng = tp_rng_seed(501);
    memset(w, 0, sizeof *w);
    w->src = (float*)malloc(sizeof(float) * W * H);
    ASSERT_TRUE(w->src != NULL);
    tpt_rough_heights(w->src, W, H, 502, 1500.0, 300.0, 8.0, 0);
    for (i = 0; i < 4; ++i) { /* holes: some patches incomplete */
        int cx = tp_rng_int(&rng, 0, W - 1), cy = tp_rng_int(&rng, 0, H - 1), x, y;
        for (y = cy - 2; y <= cy + 2; ++y)
            for (x = cx - 2; x <= cx + 2; ++x)
                if (x >= 0 && y >= 0 && x < W && y < H)
                    w->src[y * W + x] = NAN;
    }
    w->t = tpt_terrain_create(w->src, W, H, 17, TP_FIT_PAD, gt);
    tp_terrain_get_info(w->t, &w->ti);
    ASSERT_OK(tp_selection_create(w->t, &w->s, &err));
}

static void world_destroy(world* w)
{
    tp_selection_destroy(w->s);
    tp_terrain_destroy(w->t);
    free(w->src);
}

static tp_camera random_camera(const world* w, tp_rng* r)
{
    tp_camera c;
    double yaw = tp_rng_range(r, 0, 2 * PI), pitch = tp_rng_range(r, -70, -5) * PI / 180;
    const double* gt = w->ti.geotransform;
    memset(&c, 0, sizeof c);
    c.position[0] = gt[0] + tp_rng_range(r, -200, w->ti.src_width * gt[1] + 200);
    c.position[1] = gt[3] + tp_rng_range(r, -200, w->ti.src_height * -gt[5] + 200) * -1.0;
    c.position[2] = w->ti.max_height_m + tp_rng_range(r, 10, 1500);
    c.forward[0] = cos(pitch) * sin(yaw);
    c.forward[1] = cos(pitch) * cos(yaw);
    c.forward[2] = sin(pitch);
    c.up[2] = 1.0;
    return c;
}

static void update(world* w, const tp_camera* c, tp_lod_mode mode, double tau)
{
    tp_lod_params lp;
    tp_error err;
    tp_status st;
    memset(&lp, 0, sizeof lp);
    lp.mode = mode;
    lp.tau_px = tau;
    lp.mindist_m = mode == TP_LOD_DISTANCE ? 50.0 : 0.0;
    lp.maxdist_m = mode == TP_LOD_DISTANCE ? 1500.0 : 0.0;
    st = tp_selection_update(w->s, c, &lp, &err);
    if (st != TP_OK)
        FAIL("tp_selection_update: %s: %s", tp_test_status_name_(st), err.message);
}

/* Drawn triangles of patch p under the selection; returns the triangle count. */
static size_t drawn_patch(const world* w, int p, tp_vertex* v, uint32_t* tri)
{
    int nb[4];
    tp_selection_neighbor_levels(w->s, p, nb);
    return tpt_patch_geometry(w->t, p, tp_selection_level(w->s, p), nb, v, 17 * 17, tri, 512);
}

/* Height of the drawn triangles of patch p at (x, y), by point location; NaN if none. */
static double drawn_at(const world* w, int p, double x, double y)
{
    static tp_vertex v[17 * 17];
    static uint32_t tri[3 * 512];
    size_t tc = drawn_patch(w, p, v, tri), i;
    for (i = 0; i < tc; ++i) {
        const tp_vertex *a = &v[tri[3 * i]], *b = &v[tri[3 * i + 1]], *c = &v[tri[3 * i + 2]];
        double area = (double)tpt_orient(a->x, a->y, b->x, b->y, c->x, c->y);
        double wa = ((b->x - x) * (c->y - y) - (b->y - y) * (c->x - x)) / area;
        double wb = ((c->x - x) * (a->y - y) - (c->y - y) * (a->x - x)) / area;
        double wc = 1.0 - wa - wb;
        if (wa >= -1e-12 && wb >= -1e-12 && wc >= -1e-12)
            return wa * a->z_m + wb * b->z_m + wc * c->z_m;
    }
    return NAN;
}

TEST(create_marks_every_patch_dirty)
{
    world w;
    int p;
    world_create(&w);
    for (p = 0; p < w.ti.patch_count; ++p)
        EXPECT_EQ_INT(1, tp_selection_dirty(w.s, p));
    world_destroy(&w);
}

TEST(stats_are_consistent_after_update)
{
    world w;
    tp_rng rng = tp_rng_seed(511);
    static tp_vertex v[17 * 17];
    static uint32_t tri[3 * 512];
    int i;
    world_create(&w);
    for (i = 0; i < 30; ++i) {
        tp_camera c = random_camera(&w, &rng);
        tp_frame_stats st;
        tp_error_measure em;
        int p, k, per_level[TP_MAX_LEVELS] = {0}, visible = 0, sum = 0;
        size_t triangles = 0;
        update(&w, &c, i % 3 == 0 ? TP_LOD_DISTANCE : TP_LOD_ERROR, 1.0 + i % 4);
        memset(&st, 0xAB, sizeof st);
        tp_selection_stats(w.s, &st);
        for (p = 0; p < w.ti.patch_count; ++p) {
            int lv = tp_selection_level(w.s, p);
            ASSERT_TRUE(lv >= 0 && lv <= w.ti.n);
            if (!tp_selection_visible(w.s, p))
                continue;
            visible++;
            per_level[lv]++;
            triangles += drawn_patch(&w, p, v, tri);
        }
        for (k = 0; k <= w.ti.n; ++k) {
            EXPECT_EQ_INT(per_level[k], st.patches_per_level[k]);
            sum += st.patches_per_level[k];
        }
        for (k = w.ti.n + 1; k < TP_MAX_LEVELS; ++k)
            EXPECT_EQ_INT(0, st.patches_per_level[k]);
        EXPECT_EQ_INT(st.visible_patches, sum);
        EXPECT_EQ_INT(visible, st.visible_patches);
        EXPECT_EQ_INT(w.ti.patch_count, st.visible_patches + st.culled_patches);
        EXPECT_EQ_INT(triangles, st.triangles);
        EXPECT_GE(st.bound_max_error_m, 0.0);
        EXPECT_LE(st.bound_rms_error_m, st.bound_max_error_m + 1e-12);
        ASSERT_OK(tp_selection_measure_error(w.s, &em));
        EXPECT_LE(em.max_error_m, st.bound_max_error_m + 1e-9);
        EXPECT_LE(em.rms_error_m, em.max_error_m + 1e-12);
        if (tp_test_state_.failures)
            break;
    }
    world_destroy(&w);
}

TEST(culled_patches_are_outside_the_frustum)
{
    world w;
    tp_rng rng = tp_rng_seed(521);
    int i, culled = 0;
    world_create(&w);
    for (i = 0; i < 30; ++i) {
        tp_camera c = random_camera(&w, &rng);
        tp_frustum f;
        int p;
        update(&w, &c, TP_LOD_ERROR, 2.0);
        tp_frustum_from_camera(&c, &f);
        for (p = 0; p < w.ti.patch_count; ++p) {
            tp_patch_info pi;
            tp_cull cu;
            tp_patch_get_info(w.t, p, &pi);
            cu = tp_frustum_test_aabb(&f, pi.aabb_min, pi.aabb_max);
            EXPECT_EQ_INT(cu != TP_CULL_OUTSIDE, tp_selection_visible(w.s, p));
            culled += cu == TP_CULL_OUTSIDE;
        }
    }
    EXPECT_GE_INT(culled, 1);
    world_destroy(&w);
}

/* The complete patch nearest the middle of the terrain, and a complete corner patch. */
static int complete_patch(const world* w, int want_corner)
{
    int p;
    for (p = 0; p < w->ti.patch_count; ++p) {
        int q = want_corner
                    ? p
                    : (p + w->ti.patch_count / 2 + w->ti.patch_cols / 2) % w->ti.patch_count;
        tp_patch_info pi;
        tp_patch_get_info(w->t, q, &pi);
        if (!pi.complete)
            continue;
        if (want_corner && !((pi.col == 0 || pi.col == w->ti.patch_cols - 1) &&
                             (pi.row == 0 || pi.row == w->ti.patch_rows - 1)))
            continue;
        if (!want_corner && (pi.col == 0 || pi.row == 0 || pi.col == w->ti.patch_cols - 1 ||
                             pi.row == w->ti.patch_rows - 1))
            continue;
        return q;
    }
    return -1;
}

static void expect_dirty_exactly(const world* w, int p, const char* what)
{
    int q, cols = w->ti.patch_cols;
    for (q = 0; q < w->ti.patch_count; ++q) {
        int dc = q % cols - p % cols, dr = q / cols - p / cols;
        int want = p >= 0 && ((dc == 0 && dr == 0) || (abs(dc) + abs(dr) == 1));
        if (tp_selection_dirty(w->s, q) != want)
            ADD_FAILURE("%s: patch %d dirty = %d, expected %d (changed patch %d)", what, q,
                        tp_selection_dirty(w->s, q), want, p);
    }
}

TEST(level_change_marks_patch_and_its_neighbours_dirty)
{
    world w;
    int pass;
    world_create(&w);
    for (pass = 0; pass < 2; ++pass) {
        int p = complete_patch(&w, pass), k;
        ASSERT_TRUE(p >= 0);
        tp_selection_clear_dirty(w.s);
        expect_dirty_exactly(&w, -1, "after clear");
        k = tp_selection_level(w.s, p);
        tp_selection_set_level(w.s, p, k == 0 ? 2 : k - 1);
        expect_dirty_exactly(&w, p, pass ? "corner patch changed" : "middle patch changed");
        tp_selection_clear_dirty(w.s);
        tp_selection_set_level(w.s, p, tp_selection_level(w.s, p));
        expect_dirty_exactly(&w, -1, "same level set again");
    }
    world_destroy(&w);
}

TEST(unchanged_update_leaves_nothing_dirty)
{
    world w;
    tp_rng rng = tp_rng_seed(531);
    tp_camera c;
    world_create(&w);
    c = random_camera(&w, &rng);
    update(&w, &c, TP_LOD_ERROR, 1.0);
    tp_selection_clear_dirty(w.s);
    update(&w, &c, TP_LOD_ERROR, 1.0);
    expect_dirty_exactly(&w, -1, "same camera twice");
    world_destroy(&w);
}

TEST(incomplete_patches_stay_at_finest_level)
{
    world w;
    tp_rng rng = tp_rng_seed(541);
    int p, i, incomplete = 0;
    world_create(&w);
    for (i = 0; i < 10; ++i) {
        tp_camera c = random_camera(&w, &rng);
        update(&w, &c, i % 2 ? TP_LOD_DISTANCE : TP_LOD_ERROR, 8.0);
        for (p = 0; p < w.ti.patch_count; ++p) {
            tp_patch_info pi;
            tp_patch_get_info(w.t, p, &pi);
            if (!pi.complete)
                EXPECT_EQ_INT(w.ti.n, tp_selection_level(w.s, p));
        }
    }
    for (p = 0; p < w.ti.patch_count; ++p) {
        tp_patch_info pi;
        tp_patch_get_info(w.t, p, &pi);
        tp_selection_set_level(w.s, p, 0);
        if (!pi.complete) {
            incomplete++;
            EXPECT_EQ_INT(w.ti.n, tp_selection_level(w.s, p));
        } else {
            EXPECT_EQ_INT(0, tp_selection_level(w.s, p));
        }
    }
    EXPECT_GE_INT(incomplete, 2);
    world_destroy(&w);
}

/* Every level 0..n is taken as given on a complete patch (a level outside 0..n is a caller
 * bug, asserted; no user value reaches set_level unchecked). */
TEST(set_level_takes_every_level_from_0_to_n)
{
    world w;
    int p, k;
    world_create(&w);
    p = complete_patch(&w, 0);
    for (k = 0; k <= w.ti.n; ++k) {
        tp_selection_set_level(w.s, p, k);
        EXPECT_EQ_INT(k, tp_selection_level(w.s, p));
    }
    for (k = w.ti.n; k >= 0; --k) {
        tp_selection_set_level(w.s, p, k);
        EXPECT_EQ_INT(k, tp_selection_level(w.s, p));
    }
    world_destroy(&w);
}

TEST(set_level_makes_every_patch_visible_and_cull_restores)
{
    world w;
    tp_camera c;
    tp_frame_stats st;
    int p, before[64];
    world_create(&w);
    ASSERT_TRUE(w.ti.patch_count <= 64);
    memset(&c, 0, sizeof c); /* in the middle, looking north: the southern patches are behind */
    tp_terrain_grid_to_world(w.t, w.ti.width / 2.0, w.ti.height / 2.0, &c.position[0],
                             &c.position[1]);
    c.position[2] = w.ti.max_height_m + 20;
    c.forward[1] = 1;
    c.up[2] = 1;
    update(&w, &c, TP_LOD_ERROR, 1.0);
    tp_selection_stats(w.s, &st);
    EXPECT_GE_INT(st.culled_patches, 1);
    tp_selection_set_level(w.s, complete_patch(&w, 0), 1);
    for (p = 0; p < w.ti.patch_count; ++p) {
        EXPECT_EQ_INT(1, tp_selection_visible(w.s, p));
        before[p] = tp_selection_level(w.s, p);
    }
    tp_selection_stats(w.s, &st);
    EXPECT_EQ_INT(w.ti.patch_count, st.visible_patches);
    tp_selection_cull(w.s, &c);
    tp_selection_stats(w.s, &st);
    EXPECT_GE_INT(st.culled_patches, 1);
    for (p = 0; p < w.ti.patch_count; ++p)
        EXPECT_EQ_INT(before[p], tp_selection_level(w.s, p));
    world_destroy(&w);
}

TEST(neighbor_levels_are_the_adjacent_patches_levels)
{
    world w;
    tp_rng rng = tp_rng_seed(551);
    int i, p;
    world_create(&w);
    for (i = 0; i < 5; ++i) {
        tp_camera c = random_camera(&w, &rng);
        update(&w, &c, TP_LOD_DISTANCE, 0);
        for (p = 0; p < w.ti.patch_count; ++p) {
            int nb[4], col = p % w.ti.patch_cols, row = p / w.ti.patch_cols, cols = w.ti.patch_cols;
            tp_selection_neighbor_levels(w.s, p, nb);
            EXPECT_EQ_INT(row > 0 ? tp_selection_level(w.s, p - cols) : TP_NO_NEIGHBOR,
                          nb[TP_SIDE_TOP]);
            EXPECT_EQ_INT(col + 1 < cols ? tp_selection_level(w.s, p + 1) : TP_NO_NEIGHBOR,
                          nb[TP_SIDE_RIGHT]);
            EXPECT_EQ_INT(row + 1 < w.ti.patch_rows ? tp_selection_level(w.s, p + cols)
                                                    : TP_NO_NEIGHBOR,
                          nb[TP_SIDE_BOTTOM]);
            EXPECT_EQ_INT(col > 0 ? tp_selection_level(w.s, p - 1) : TP_NO_NEIGHBOR,
                          nb[TP_SIDE_LEFT]);
        }
    }
    world_destroy(&w);
}

/* Sets random levels on every patch (all then visible). */
static void random_levels(world* w, tp_rng* r)
{
    int p;
    for (p = 0; p < w->ti.patch_count; ++p)
        tp_selection_set_level(w->s, p, tp_rng_int(r, 0, w->ti.n));
}

TEST(measure_error_zero_at_full_resolution)
{
    world w;
    tp_rng rng = tp_rng_seed(561);
    tp_camera c;
    tp_error_measure em;
    int p;
    world_create(&w);
    c = random_camera(&w, &rng);
    update(&w, &c, TP_LOD_FULL, 0);
    ASSERT_OK(tp_selection_measure_error(w.s, &em));
    EXPECT_EQ_DBL(0.0, em.max_error_m);
    EXPECT_EQ_DBL(0.0, em.rms_error_m);
    for (p = 0; p < w.ti.patch_count; ++p)
        tp_selection_set_level(w.s, p, w.ti.n);
    ASSERT_OK(tp_selection_measure_error(w.s, &em));
    EXPECT_EQ_DBL(0.0, em.max_error_m);
    /* every patch visible: every drawn sample once */
    EXPECT_EQ_INT(w.ti.valid_samples + w.ti.filled_samples, em.samples);
    world_destroy(&w);
}

TEST(measure_error_matches_rasterised_drawn_surface)
{
    world w;
    tp_rng rng = tp_rng_seed(571);
    static tp_vertex v[17 * 17];
    static uint32_t tri[3 * 512];
    static double drawn[17 * 17];
    int i;
    world_create(&w);
    for (i = 0; i < 10; ++i) {
        tp_error_measure em;
        tp_frame_stats st;
        double worst = 0;
        int p;
        random_levels(&w, &rng);
        for (p = 0; p < w.ti.patch_count; ++p) {
            size_t tc = drawn_patch(&w, p, v, tri);
            int x0 = (p % w.ti.patch_cols) * 16, y0 = (p / w.ti.patch_cols) * 16, j;
            tpt_patch_surface(v, tri, tc, x0, y0, 17, drawn, NULL);
            for (j = 0; j < 17 * 17; ++j) {
                double s = tp_terrain_sample(w.t, x0 + j % 17, y0 + j / 17);
                if (isnan(s) || isnan(drawn[j]))
                    continue;
                if (fabs(drawn[j] - s) > worst)
                    worst = fabs(drawn[j] - s);
            }
        }
        ASSERT_OK(tp_selection_measure_error(w.s, &em));
        EXPECT_NEAR(worst, em.max_error_m, 1e-6);
        tp_selection_stats(w.s, &st);
        EXPECT_LE(em.max_error_m, st.bound_max_error_m + 1e-9);
    }
    world_destroy(&w);
}

/* Two threads measuring one const selection at once get the single-threaded results: the
 * measure functions write nothing shared (tp_core.h: they are safe to call concurrently). */
typedef struct measure_job {
    const tp_selection* s;
    const tp_camera* cam;
    int patch_count, screen, rounds, mismatches;
    tp_error_measure vertical;
    double screen_max_px, screen_rms_px;
    size_t screen_samples;
} measure_job;

static void* measure_thread(void* user)
{
    measure_job* j = (measure_job*)user;
    int i;
    for (i = 0; i < j->rounds; ++i) {
        if (j->screen) {
            double mx = -1, rms = -1;
            size_t n = 0;
            if (tp_selection_measure_screen_error(j->s, j->cam, &mx, &rms, &n) != TP_OK ||
                mx != j->screen_max_px || rms != j->screen_rms_px || n != j->screen_samples)
                j->mismatches++;
        } else {
            tp_error_measure em;
            if (tp_selection_measure_error(j->s, &em) != TP_OK ||
                em.max_error_m != j->vertical.max_error_m ||
                em.rms_error_m != j->vertical.rms_error_m || em.samples != j->vertical.samples)
                j->mismatches++;
        }
    }
    return NULL;
}

TEST(measure_from_two_threads_matches_single_thread)
{
    world w;
    tp_rng rng = tp_rng_seed(591);
    tp_camera c;
    measure_job jobs[2];
    pthread_t th[2];
    int i;
    world_create(&w);
    c = random_camera(&w, &rng);
    random_levels(&w, &rng); /* every patch visible, mixed levels: stitched borders */
    for (i = 0; i < 2; ++i) {
        memset(&jobs[i], 0, sizeof jobs[i]);
        jobs[i].s = w.s;
        jobs[i].cam = &c;
        jobs[i].screen = i;
        jobs[i].rounds = 200;
        ASSERT_OK(tp_selection_measure_error(w.s, &jobs[i].vertical));
        ASSERT_OK(tp_selection_measure_screen_error(w.s, &c, &jobs[i].screen_max_px,
                                                    &jobs[i].screen_rms_px,
                                                    &jobs[i].screen_samples));
    }
    EXPECT_TRUE(jobs[0].vertical.max_error_m > 0);
    EXPECT_TRUE(jobs[1].screen_samples > 0);
    for (i = 0; i < 2; ++i)
        ASSERT_TRUE(pthread_create(&th[i], NULL, measure_thread, &jobs[i]) == 0);
    for (i = 0; i < 2; ++i)
        pthread_join(th[i], NULL);
    EXPECT_EQ_INT(0, jobs[0].mismatches);
    EXPECT_EQ_INT(0, jobs[1].mismatches);
    world_destroy(&w);
}

/* An allocator that counts live blocks and fails every request once told to. */
typedef struct test_heap {
    int fail;
    long live, failed;
} test_heap;

static void* heap_alloc(size_t size, void* user)
{
    test_heap* h = (test_heap*)user;
    void* p;
    if (h->fail) {
        h->failed++;
        return NULL;
    }
    p = malloc(size);
    h->live += p != NULL;
    return p;
}

static void heap_free(void* ptr, void* user)
{
    ((test_heap*)user)->live--;
    free(ptr);
}

/* The max-error mode against the source heights: every patch's drawn triangles stay within the
 * bound at every source sample they cover, and no patch can go one level coarser alone. */
TEST(max_error_mode_keeps_the_bound_against_the_source)
{
    world w;
    tp_lod_params lp;
    tp_error err;
    static tp_vertex v[17 * 17];
    static uint32_t tri[3 * 512];
    static double drawn[17 * 17];
    const double bound[3] = {0.5, 4.0, 25.0};
    int b, p, j, coarse = 0;
    world_create(&w);
    for (b = 0; b < 3; ++b) {
        double worst = 0;
        memset(&lp, 0, sizeof lp);
        lp.mode = TP_LOD_MAX_ERROR;
        lp.max_error_m = bound[b];
        lp.reference_heights = w.src;
        lp.reference_height_count = (size_t)w.ti.src_width * w.ti.src_height;
        ASSERT_OK(tp_selection_update(w.s, NULL, &lp, &err));
        for (p = 0; p < w.ti.patch_count; ++p) {
            size_t tc = drawn_patch(&w, p, v, tri);
            int x0 = (p % w.ti.patch_cols) * 16, y0 = (p / w.ti.patch_cols) * 16;
            EXPECT_TRUE(tp_selection_visible(w.s, p));
            coarse += tp_selection_level(w.s, p) < w.ti.n;
            tpt_patch_surface(v, tri, tc, x0, y0, 17, drawn, NULL);
            for (j = 0; j < 17 * 17; ++j) {
                int x = x0 + j % 17, y = y0 + j / 17;
                double src = x < w.ti.src_width && y < w.ti.src_height
                                 ? w.src[y * w.ti.src_width + x]
                                 : NAN;
                if (!isnan(src) && !isnan(drawn[j]) && fabs(drawn[j] - src) > worst)
                    worst = fabs(drawn[j] - src);
            }
        }
        tp_test_note("max error %g m: measured %.6f m", bound[b], worst);
        EXPECT_LE(worst, bound[b] + 1e-9);
    }
    EXPECT_GE_INT(coarse, 1); /* it did coarsen something */
    memset(&lp, 0, sizeof lp);
    lp.mode = TP_LOD_MAX_ERROR;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_selection_update(w.s, NULL, &lp, &err));
    EXPECT_TRUE(strstr(err.message, "max_error_m") != NULL);
    lp.max_error_m = 1;
    lp.reference_heights = w.src;
    lp.reference_height_count = 7;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_selection_update(w.s, NULL, &lp, &err));
    EXPECT_TRUE(strstr(err.message, "7") != NULL);
    world_destroy(&w);
}

/* Allocation failures come back as TP_ERR_OUT_OF_MEMORY, outputs and levels untouched, never
 * as a zero error (the max-error selection used to treat a failed measurement as 0 m). */
TEST(allocation_failure_is_reported_not_measured_as_zero)
{
    test_heap heap = {0, 0, 0};
    tp_terrain_desc d;
    tp_terrain* t = NULL;
    tp_selection* s = NULL;
    tp_terrain_info ti;
    tp_lod_params lp;
    tp_error err;
    tp_error_measure em = {-1, -1, 7};
    tp_camera cam;
    tp_ray_hit hit;
    double px = -1, mx = -1, down[3] = {0, 0, -1}, above[3];
    float* src = (float*)malloc(sizeof(float) * 70 * 50);
    int p, levels_before[64];
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, 70, 50, 503, 1500.0, 300.0, 8.0, 0);
    memset(&d, 0, sizeof d);
    d.heights = src;
    d.height_count = 70 * 50;
    d.width = 70;
    d.height = 50;
    d.patch_size = 17;
    d.allocator.alloc = heap_alloc;
    d.allocator.free = heap_free;
    d.allocator.user_data = &heap;
    ASSERT_OK(tp_terrain_create(&d, &t, &err));
    ASSERT_OK(tp_selection_create(t, &s, &err));
    EXPECT_TRUE(heap.live > 0); /* the terrain and the selection came from the allocator */
    tp_terrain_get_info(t, &ti);
    ASSERT_TRUE(ti.patch_count <= 64);
    for (p = 0; p < ti.patch_count; ++p)
        levels_before[p] = tp_selection_level(s, p);

    heap.fail = 1;
    memset(&lp, 0, sizeof lp);
    lp.mode = TP_LOD_MAX_ERROR;
    lp.max_error_m = 5.0;
    lp.reference_heights = src;
    lp.reference_height_count = 70 * 50;
    err.message[0] = 0;
    EXPECT_STATUS(TP_ERR_OUT_OF_MEMORY, tp_selection_update(s, NULL, &lp, &err));
    EXPECT_TRUE(strstr(err.message, "out of memory") != NULL);
    for (p = 0; p < ti.patch_count; ++p)
        EXPECT_EQ_INT(levels_before[p], tp_selection_level(s, p));
    EXPECT_STATUS(TP_ERR_OUT_OF_MEMORY, tp_selection_measure_error(s, &em));
    EXPECT_EQ_DBL(-1.0, em.max_error_m);
    memset(&cam, 0, sizeof cam);
    cam.position[0] = 35;
    cam.position[1] = -60;
    cam.position[2] = 3000;
    EXPECT_STATUS(TP_ERR_OUT_OF_MEMORY,
                  tp_selection_measure_screen_error(s, &cam, &mx, NULL, NULL));
    EXPECT_STATUS(TP_ERR_OUT_OF_MEMORY, tp_selection_patch_screen_error(s, &cam, 0, 0, &px));
    EXPECT_EQ_DBL(-1.0, mx);
    EXPECT_EQ_DBL(-1.0, px);
    /* a ray straight down onto the middle of the terrain needs scratch too: *out untouched */
    tp_terrain_grid_to_world(t, 35, 25, &above[0], &above[1]);
    above[2] = ti.max_height_m + 1000;
    memset(&hit, 0x5A, sizeof hit);
    EXPECT_STATUS(TP_ERR_OUT_OF_MEMORY, tp_selection_ray_cast(s, above, down, &hit));
    EXPECT_EQ_INT(0x5A5A5A5A, hit.hit);
    EXPECT_EQ_INT(0x5A5A5A5A, hit.patch);
    EXPECT_TRUE(heap.failed >= 5);

    /* the same calls succeed once memory is back, and coarsen the terrain */
    heap.fail = 0;
    ASSERT_OK(tp_selection_update(s, NULL, &lp, &err));
    ASSERT_OK(tp_selection_measure_error(s, &em));
    EXPECT_LE(em.max_error_m, 5.0 + ti.quant_max_error_m);
    ASSERT_OK(tp_selection_ray_cast(s, above, down, &hit));
    EXPECT_EQ_INT(1, hit.hit);
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    EXPECT_EQ_INT(0, (int)heap.live); /* everything went back through the allocator */
    free(src);
}

TEST(drawn_height_equals_full_resolution_at_full)
{
    world w;
    tp_rng rng = tp_rng_seed(581);
    int p, i;
    world_create(&w);
    for (p = 0; p < w.ti.patch_count; ++p)
        tp_selection_set_level(w.s, p, w.ti.n);
    for (i = 0; i < 20000; ++i) {
        double x = tp_rng_range(&rng, -2, w.ti.width + 1),
               y = tp_rng_range(&rng, -2, w.ti.height + 1);
        double a = tp_selection_drawn_height_at(w.s, x, y), b = tp_terrain_height_at(w.t, x, y);
        if (i % 3 == 0) {
            x = floor(x);
            y = floor(y);
            a = tp_selection_drawn_height_at(w.s, x, y);
            b = tp_terrain_height_at(w.t, x, y);
        }
        if (isnan(a) != isnan(b) || (!isnan(a) && !(fabs(a - b) <= 1e-6))) {
            ADD_FAILURE("at (%.6f, %.6f): drawn %.9g, full resolution %.9g", x, y, a, b);
            break;
        }
    }
    world_destroy(&w);
}

TEST(drawn_height_follows_stitched_triangles)
{
    world w;
    tp_rng rng = tp_rng_seed(591);
    int round, i;
    world_create(&w);
    for (round = 0; round < 8 && !tp_test_state_.failures; ++round) {
        random_levels(&w, &rng);
        for (i = 0; i < 3000; ++i) {
            double x = tp_rng_range(&rng, 0, w.ti.width - 1),
                   y = tp_rng_range(&rng, 0, w.ti.height - 1);
            int col = (int)(x / 16), row = (int)(y / 16), p;
            double want, got;
            if (col >= w.ti.patch_cols)
                col = w.ti.patch_cols - 1;
            if (row >= w.ti.patch_rows)
                row = w.ti.patch_rows - 1;
            if (i % 4 == 0)
                x = floor(x); /* on grid lines, and on patch borders */
            if (i % 8 == 0)
                x = col * 16;
            p = row * w.ti.patch_cols + col;
            want = drawn_at(&w, p, x, y);
            got = tp_selection_drawn_height_at(w.s, x, y);
            if (isnan(want))
                continue; /* hole: either patch's answer is fine only if drawn */
            if (!(fabs(want - got) <= 1e-6 * (1 + fabs(want)))) {
                ADD_FAILURE("round %d at (%.6f, %.6f), patch %d level %d: drawn_height_at %.9g, "
                            "the drawn triangles give %.9g",
                            round, x, y, p, tp_selection_level(w.s, p), got, want);
                break;
            }
        }
    }
    world_destroy(&w);
}

TEST(drawn_height_on_a_lone_drawn_triangle)
{
    /* Only three samples are valid: the one triangle they form is all that is drawn. */
    static float h[33 * 33];
    static const int tri[2][3][2] = {{{10, 10}, {11, 10}, {10, 11}},
                                     {{21, 20}, {20, 21}, {21, 21}}};
    tp_terrain* t;
    tp_selection* s = NULL;
    tp_error err;
    int i, j;
    for (i = 0; i < 33 * 33; ++i)
        h[i] = NAN;
    for (j = 0; j < 2; ++j)
        for (i = 0; i < 3; ++i)
            h[tri[j][i][1] * 33 + tri[j][i][0]] = (float)(100 + 7 * i + 50 * j);
    t = tpt_terrain_create(h, 33, 33, 17, TP_FIT_PAD, NULL);
    ASSERT_OK(tp_selection_create(t, &s, &err));
    for (i = 0; i < 4; ++i)
        tp_selection_set_level(s, i, 0); /* stays at n: incomplete */
    for (j = 0; j < 2; ++j) {
        const int(*p)[2] = tri[j];
        for (i = 0; i < 3; ++i) {
            int k = (i + 1) % 3;
            double za = tp_terrain_sample(t, p[i][0], p[i][1]),
                   zb = tp_terrain_sample(t, p[k][0], p[k][1]);
            EXPECT_NEAR(za, tp_selection_drawn_height_at(s, p[i][0], p[i][1]), 1e-6);
            EXPECT_NEAR((za + zb) / 2,
                        tp_selection_drawn_height_at(s, (p[i][0] + p[k][0]) / 2.0,
                                                     (p[i][1] + p[k][1]) / 2.0),
                        1e-6);
        }
    }
    EXPECT_NAN(tp_selection_drawn_height_at(s, 10.6, 10.6));
    EXPECT_NAN(tp_selection_drawn_height_at(s, 5.0, 5.0));
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
}

TEST(keep_above_lifts_eye_over_both_surfaces)
{
    world w;
    tp_rng rng = tp_rng_seed(601);
    int i, lifted = 0;
    world_create(&w);
    random_levels(&w, &rng); /* coarse levels: the drawn surface differs from the full one */
    for (i = 0; i < 3000; ++i) {
        double pos[3], x = tp_rng_range(&rng, 0, w.ti.src_width - 1),
                       y = tp_rng_range(&rng, 0, w.ti.src_height - 1), full, drawn, top, orig;
        int r;
        tp_terrain_grid_to_world(w.t, x, y, &pos[0], &pos[1]);
        full = tp_terrain_height_at(w.t, x, y);
        drawn = tp_selection_drawn_height_at(w.s, x, y);
        if (isnan(full) || isnan(drawn))
            continue;
        top = fmax(full, drawn);
        orig = pos[2] = top + tp_rng_range(&rng, -100, 100);
        r = tp_selection_keep_above(w.s, pos, 2.0);
        if (orig < top + 2.0 - 1e-6) {
            EXPECT_EQ_INT(1, r);
            EXPECT_GE(pos[2], top + 2.0 - 1e-6);
            EXPECT_LE(pos[2], top + 2.0 + 1e-3);
            lifted++;
        } else if (orig > top + 2.0 + 1e-6) {
            EXPECT_EQ_INT(0, r);
            EXPECT_EQ_DBL(orig, pos[2]);
        }
        if (tp_test_state_.failures)
            break;
    }
    EXPECT_GE_INT(lifted, 100);
    world_destroy(&w);
}

TEST(keep_above_ignores_positions_outside_terrain)
{
    world w;
    double pos[3];
    world_create(&w);
    pos[0] = w.ti.geotransform[0] - 5000.0;
    pos[1] = w.ti.geotransform[3] + 5000.0;
    pos[2] = -1000.0;
    EXPECT_EQ_INT(0, tp_selection_keep_above(w.s, pos, 2.0));
    EXPECT_EQ_DBL(-1000.0, pos[2]);
    EXPECT_EQ_DBL(w.ti.geotransform[0] - 5000.0, pos[0]);
    world_destroy(&w);
}

#define TESTS(X)                                                                                   \
    X(create_marks_every_patch_dirty)                                                              \
    X(stats_are_consistent_after_update)                                                           \
    X(culled_patches_are_outside_the_frustum)                                                      \
    X(level_change_marks_patch_and_its_neighbours_dirty)                                           \
    X(unchanged_update_leaves_nothing_dirty)                                                       \
    X(incomplete_patches_stay_at_finest_level)                                                     \
    X(set_level_takes_every_level_from_0_to_n)                                                       \
    X(set_level_makes_every_patch_visible_and_cull_restores)                                       \
    X(neighbor_levels_are_the_adjacent_patches_levels)                                             \
    X(measure_error_zero_at_full_resolution)                                                       \
    X(measure_error_matches_rasterised_drawn_surface)                                              \
    X(measure_from_two_threads_matches_single_thread)                                              \
    X(max_error_mode_keeps_the_bound_against_the_source)                                           \
    X(allocation_failure_is_reported_not_measured_as_zero)                                         \
    X(drawn_height_equals_full_resolution_at_full)                                                 \
    X(drawn_height_follows_stitched_triangles)                                                     \
    X(drawn_height_on_a_lone_drawn_triangle)                                                       \
    X(keep_above_lifts_eye_over_both_surfaces)                                                     \
    X(keep_above_ignores_positions_outside_terrain)
TP_TEST_MAIN(TESTS)
