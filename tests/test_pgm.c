/* test_pgm.c - Persistent Grid Mapping's core (core/src/pgm.c, pgm_error.c): a flat terrain
 * takes the grid exactly onto its plane; the auxiliary camera sends every ray to the plane for
 * any main pitch; the pyramid's sizes and posts for awkward sizes, and bad input refused; the
 * level grows with distance and blends continuously across level switches; the error measure
 * against a brute-force search on a tiny grid, and on Mt Hood a finer grid is more exact. */
#define _POSIX_C_SOURCE 200809L
#include "tp_io.h"
#include "tp_test.h"

#define TESTS(X)                                                                                   \
    X(flat_terrain_maps_the_grid_onto_the_plane)                                                   \
    X(aux_camera_sends_every_ray_to_the_plane)                                                     \
    X(pyramid_levels_reach_the_edge_with_source_posts)                                             \
    X(pyramid_refuses_bad_input_and_zeroes_out)                                                    \
    X(level_grows_with_distance_and_blends_continuously)                                           \
    X(level_is_zero_near_the_eye_close_to_the_ground)                                              \
    X(measure_agrees_with_a_brute_force_search)                                                    \
    X(finer_grid_is_more_exact_on_mt_hood)

#ifndef M_PI
#define M_PI 3.14159265358979323846
#endif

static tp_pgm_pyramid make_pyramid(const float* z, int w, int h, const double gt[6])
{
    tp_pgm_pyramid p;
    tp_error err;
    memset(&err, 0, sizeof err);
    tp_status s = tp_pgm_pyramid_build(z, w, h, gt, &p, &err);
    if (s != TP_OK)
        FAIL("tp_pgm_pyramid_build: %s", err.message);
    return p;
}

static float* flat_grid(int w, int h, float z)
{
    float* g = malloc((size_t)w * h * sizeof *g);
    for (size_t k = 0; k < (size_t)w * h; k++)
        g[k] = z;
    return g;
}

/* Posts (E, N) of a north-up grid. */
static void post_world(const double gt[6], int x, int y, double out[2])
{
    out[0] = gt[0] + (x + 0.5) * gt[1];
    out[1] = gt[3] + (y + 0.5) * gt[5];
}

/* Whether the main camera sees point pt inside its viewport (closed), in front of near. */
static int in_view(const tp_camera* cam, const double pt[3], double px[2])
{
    tp_camera_frame fr;
    tp_camera_get_frame(cam, &fr);
    return tp_camera_project(cam, pt, px, NULL) && px[0] >= 0 && px[0] <= fr.width_px &&
           px[1] >= 0 && px[1] <= fr.height_px;
}

static size_t count_in_view(const tp_camera* cam, const tp_pgm_pyramid* p)
{
    size_t n = 0;
    for (int y = 0; y < p->height[0]; y++)
        for (int x = 0; x < p->width[0]; x++) {
            double pt[3], px[2];
            post_world(p->geotransform, x, y, pt);
            pt[2] = p->z[0][(size_t)y * p->width[0] + x];
            n += (size_t)in_view(cam, pt, px);
        }
    return n;
}

/* The measure by brute force: every post in view (tp_camera_project inside the viewport) is
 * looked up in every drawn triangle (all three vertices on the terrain) in drawing order. */
static tp_pgm_error brute_force(const tp_pgm_frame* f, const tp_pgm_pyramid* p,
                                const tp_camera* cam)
{
    const int C = f->cols, R = f->rows, W = p->width[0], H = p->height[0];
    const double* gt = p->geotransform;
    double* v = malloc(3 * sizeof *v * C * R);
    int* on = malloc(sizeof *on * C * R);
    for (int j = 0; j < R; j++)
        for (int i = 0; i < C; i++) {
            double w[3], lod;
            int k = j * C + i;
            on[k] = tp_pgm_map_vertex(f, p, i, j, w, &lod);
            v[3 * k] = (w[0] - gt[0]) / gt[1] - 0.5;
            v[3 * k + 1] = (w[1] - gt[3]) / gt[5] - 0.5;
            v[3 * k + 2] = w[2];
        }
    tp_pgm_error e;
    memset(&e, 0, sizeof e);
    double sum_m = 0, sum_px = 0;
    for (int y = 0; y < H; y++)
        for (int x = 0; x < W; x++) {
            double truth[3], px[2];
            post_world(gt, x, y, truth);
            truth[2] = p->z[0][y * W + x];
            if (!in_view(cam, truth, px))
                continue;
            int found = 0;
            double drawn = 0;
            for (int t = 0; t < 2 * (C - 1) * (R - 1) && !found; t++) {
                int cell = t / 2, ci = cell % (C - 1), cj = cell / (C - 1);
                int a = cj * C + ci, b = a + 1, cc = a + C, d = cc + 1;
                int tri[3] = {a, b, cc};
                if (t % 2) {
                    tri[0] = b;
                    tri[1] = d;
                    tri[2] = cc;
                }
                if (!on[tri[0]] || !on[tri[1]] || !on[tri[2]])
                    continue;
                const double *v0 = v + 3 * tri[0], *v1 = v + 3 * tri[1], *v2 = v + 3 * tri[2];
                double e1x = v1[0] - v0[0], e1y = v1[1] - v0[1];
                double e2x = v2[0] - v0[0], e2y = v2[1] - v0[1];
                double det = e1x * e2y - e1y * e2x;
                if (det == 0)
                    continue;
                double s = ((x - v0[0]) * e2y - (y - v0[1]) * e2x) / det;
                double u = (e1x * (y - v0[1]) - e1y * (x - v0[0])) / det;
                if (s < -1e-12 || u < -1e-12 || s + u > 1 + 1e-12)
                    continue;
                found = 1;
                drawn = v0[2] + s * (v1[2] - v0[2]) + u * (v2[2] - v0[2]);
            }
            if (!found) {
                e.uncovered++;
                continue;
            }
            double dp[3] = {truth[0], truth[1], drawn}, dpx[2];
            if (!tp_camera_project(cam, dp, dpx, NULL))
                FAIL("the drawn point above post (%d, %d) is behind the eye", x, y);
            double ev = fabs(drawn - truth[2]), es = hypot(dpx[0] - px[0], dpx[1] - px[1]);
            e.max_m = fmax(e.max_m, ev);
            e.max_px = fmax(e.max_px, es);
            sum_m += ev * ev;
            sum_px += es * es;
            e.samples++;
        }
    if (e.samples) {
        e.rms_m = sqrt(sum_m / (double)e.samples);
        e.rms_px = sqrt(sum_px / (double)e.samples);
    }
    free(v);
    free(on);
    return e;
}

static void expect_same_error(const tp_pgm_error* want, const tp_pgm_error* got)
{
    EXPECT_EQ_INT(want->samples, got->samples);
    EXPECT_EQ_INT(want->uncovered, got->uncovered);
    EXPECT_NEAR(want->max_m, got->max_m, 1e-9 * (1 + want->max_m));
    EXPECT_NEAR(want->rms_m, got->rms_m, 1e-9 * (1 + want->max_m));
    EXPECT_NEAR(want->max_px, got->max_px, 1e-6 * (1 + want->max_px));
    EXPECT_NEAR(want->rms_px, got->rms_px, 1e-6 * (1 + want->max_px));
}

/* A flat terrain at 500 m: every vertex lies on the plane at its grid pixel of the aux camera;
 * the measured error is 0 and every post in view is either covered or outside the drawn
 * region (none at all when the view lies inside the terrain). */
TEST(flat_terrain_maps_the_grid_onto_the_plane)
{
    const int W = 201, H = 161;
    const double gt[6] = {1000, 10, 0, 9000, 0, -10};
    float* z = flat_grid(W, H, 500.0f);
    tp_pgm_pyramid p = make_pyramid(z, W, H, gt);
    EXPECT_EQ_DBL(500, p.min_m);
    const double centre[3] = {2000, 8200, 800};
    const double pitches[] = {-90, -60, -20, 0, 10};
    for (size_t c = 0; c < sizeof pitches / sizeof pitches[0]; c++) {
        tp_camera cam;
        double eye[3] = {centre[0], centre[1], pitches[c] > 0 ? 600 : centre[2]};
        tp_camera_from_pose(eye, 30, pitches[c], 50, 640, 480, &cam);
        tp_pgm_frame f;
        const int cols = 33, rows = 25;
        tp_pgm_frame_setup(&cam, cols, rows, &p, &f);
        double worst = 0;
        for (int j = 0; j < rows; j++)
            for (int i = 0; i < cols; i++) {
                double world[3], lod, px[2];
                tp_pgm_map_vertex(&f, &p, i, j, world, &lod);
                EXPECT_EQ_DBL(500, world[2]);
                ASSERT_TRUE(tp_camera_project(&f.aux, world, px, NULL));
                worst = fmax(worst, fabs(px[0] - i * 640.0 / (cols - 1)));
                worst = fmax(worst, fabs(px[1] - j * 480.0 / (rows - 1)));
            }
        EXPECT_LE(worst, 1e-6);
        tp_pgm_error e;
        ASSERT_OK(tp_pgm_measure_error(&f, &p, &cam, &e));
        EXPECT_EQ_DBL(0, e.max_m);
        EXPECT_EQ_DBL(0, e.rms_m);
        EXPECT_EQ_DBL(0, e.max_px);
        EXPECT_EQ_INT(count_in_view(&cam, &p), e.samples + e.uncovered);
        /* uncovered: exactly the posts in view under no drawn triangle */
        tp_pgm_error want = brute_force(&f, &p, &cam);
        expect_same_error(&want, &e);
        tp_test_note("pitch %g: %zu samples, %zu uncovered", pitches[c], e.samples, e.uncovered);
        if (pitches[c] == -90) {
            /* 300 m below the eye the view is about 280 x 210 m: all on the terrain */
            EXPECT_GT(e.samples, 400);
            EXPECT_EQ_INT(0, e.uncovered);
        }
        if (pitches[c] == 0)
            EXPECT_GT(e.uncovered, 0); /* the terrain's far edge is in view */
        if (pitches[c] == 10)
            EXPECT_GT(e.samples, 100); /* aux differs from main, and covers what main sees */
    }
    tp_pgm_pyramid_free(&p);
    free(z);
}

/* For main pitches from straight down to straight up, every vertex's ray meets the plane in
 * front of the eye and the vertex lies where that ray meets it; aux == main when main looks
 * down far enough, else aux has main's yaw and the limiting pitch. */
TEST(aux_camera_sends_every_ray_to_the_plane)
{
    float z[9] = {100, 100, 100, 100, 100, 100, 100, 100, 100};
    const double gt[6] = {0, 30, 0, 90, 0, -30};
    tp_pgm_pyramid p = make_pyramid(z, 3, 3, gt);
    const double yaws[] = {0, 45, 137, 270};
    const double fovs[] = {30, 60, 90};
    const int vps[][2] = {{1280, 720}, {720, 1280}, {500, 500}};
    const double eye[3] = {45, 45, 400};
    int checked = 0, same = 0;
    for (double pitch = -90; pitch <= 90; pitch += 7.5)
        for (size_t a = 0; a < 4; a++)
            for (size_t b = 0; b < 3; b++)
                for (size_t c = 0; c < 3; c++) {
                    tp_camera cam, aux;
                    tp_camera_from_pose(eye, yaws[a], pitch, fovs[b], vps[c][0], vps[c][1], &cam);
                    tp_pgm_aux_camera(&cam, 1e-3, &aux);
                    double limit_deg = -(fovs[b] / 2 + 1e-3 * 180 / M_PI);
                    if (pitch <= limit_deg) {
                        EXPECT_TRUE(memcmp(&cam, &aux, sizeof cam) == 0);
                        same++;
                    } else {
                        double ay, ap;
                        tp_camera_get_pose(&aux, &ay, &ap);
                        EXPECT_NEAR(limit_deg, ap, 1e-9);
                        if (fabs(pitch) < 90)
                            EXPECT_NEAR(0, remainder(ay - yaws[a], 360), 1e-9);
                    }
                    tp_pgm_frame f;
                    tp_pgm_frame_setup(&cam, 9, 7, &p, &f);
                    EXPECT_EQ_DBL(300, f.eye_above_base_m);
                    for (int j = 0; j < 7; j++)
                        for (int i = 0; i < 9; i++) {
                            double dir[3], world[3], lod;
                            tp_camera_pixel_ray(&f.aux, i * vps[c][0] / 8.0, j * vps[c][1] / 6.0,
                                                dir);
                            double t = 300 / -dir[2];
                            ASSERT_TRUE(isfinite(t) && t > 0);
                            tp_pgm_map_vertex(&f, &p, i, j, world, &lod);
                            EXPECT_NEAR(eye[0] + t * dir[0], world[0], 1e-9 * t);
                            EXPECT_NEAR(eye[1] + t * dir[1], world[1], 1e-9 * t);
                            EXPECT_TRUE(isfinite(lod) && lod >= 0 && lod <= p.levels - 1);
                            checked++;
                        }
                }
    EXPECT_GT(same, 0);
    tp_test_note("%d vertices checked, %d cameras with aux == main", checked, same);
    /* A camera rolled about its axis (up turned towards right): main itself while its corner
     * rays all go down, else levelled at its own pitch; the grid's rays go down either way. */
    int rolled_same = 0, levelled = 0;
    const double rolls[] = {0, 2, 30, 50, 90};
    const double pitches[] = {-89, -60, -40};
    for (size_t r = 0; r < 5; r++)
        for (size_t q = 0; q < 3; q++) {
            tp_camera cam, aux;
            tp_camera_from_pose(eye, 60, pitches[q], 60, 1280, 720, &cam);
            tp_camera_frame fr;
            tp_camera_get_frame(&cam, &fr);
            double ro = rolls[r] * M_PI / 180;
            for (int k = 0; k < 3; k++)
                cam.up[k] = fr.up[k] * cos(ro) + fr.right[k] * sin(ro);
            tp_pgm_aux_camera(&cam, 1e-3, &aux);
            int corners_down = 1;
            for (int c = 0; c < 4; c++) {
                double dir[3];
                tp_camera_pixel_ray(&cam, (c & 1) * 1280.0, (c >> 1) * 720.0, dir);
                corners_down &= dir[2] < 0;
            }
            if (corners_down) {
                EXPECT_TRUE(memcmp(&cam, &aux, sizeof cam) == 0);
                rolled_same++;
            } else {
                tp_camera_frame fa;
                tp_camera_get_frame(&aux, &fa);
                EXPECT_NEAR(0, fa.right[2], 1e-12);
                double ay, ap, my, mp;
                tp_camera_get_pose(&aux, &ay, &ap);
                tp_camera_get_pose(&cam, &my, &mp);
                EXPECT_NEAR(mp, ap, 1e-9);
                levelled++;
            }
            for (int j = 0; j < 7; j++)
                for (int i = 0; i < 9; i++) {
                    double dir[3];
                    tp_camera_pixel_ray(&aux, i * 1280 / 8.0, j * 720 / 6.0, dir);
                    EXPECT_LT(dir[2], 0);
                }
        }
    EXPECT_GT(rolled_same, 0);
    EXPECT_GT(levelled, 0);
    tp_pgm_pyramid_free(&p);
}

static float pattern(int x, int y)
{
    return (float)((x * 7919 + y * 104729) % 1000) * 0.5f + (float)y * 0.25f;
}

/* Sizes: width[l] - 1 = ceil((w - 1) / 2^l), so the last post reaches (or passes) the edge and
 * the one before it does not; every post is the level-0 post at min(i 2^l, w - 1); sampling
 * at a post gives it, halfway between two gives their mean, outside clamps. */
TEST(pyramid_levels_reach_the_edge_with_source_posts)
{
    const int sizes[][2] = {{1201, 1201}, {1000, 77}, {2, 2}, {1, 1}, {1, 1000}, {3, 2}};
    const double gt[6] = {500000, 30, 0, 4000000, 0, -30};
    for (size_t s = 0; s < sizeof sizes / sizeof sizes[0]; s++) {
        const int W = sizes[s][0], H = sizes[s][1];
        float* z = malloc((size_t)W * H * sizeof *z);
        for (int y = 0; y < H; y++)
            for (int x = 0; x < W; x++)
                z[(size_t)y * W + x] = pattern(x, y);
        tp_pgm_pyramid p = make_pyramid(z, W, H, gt);
        ASSERT_GE_INT(p.levels, 1);
        EXPECT_EQ_INT(W, p.width[0]);
        EXPECT_EQ_INT(H, p.height[0]);
        for (int l = 0; l < p.levels; l++) {
            long long step = 1LL << l;
            long long want_w = (W - 1 + step - 1) / step + 1,
                      want_h = (H - 1 + step - 1) / step + 1;
            EXPECT_EQ_INT(want_w, p.width[l]);
            EXPECT_EQ_INT(want_h, p.height[l]);
            if (W > 1)
                EXPECT_TRUE((p.width[l] - 1) * step >= W - 1 && (p.width[l] - 2) * step < W - 1);
            int mism = 0;
            for (int j = 0; j < p.height[l]; j++)
                for (int i = 0; i < p.width[l]; i++) {
                    long long sx = i * step < W - 1 ? i * step : W - 1;
                    long long sy = j * step < H - 1 ? j * step : H - 1;
                    mism += p.z[l][(size_t)j * p.width[l] + i] != z[(size_t)sy * W + sx];
                }
            EXPECT_EQ_INT(0, mism);
            /* sampling at the level's posts inside the extent, and halfway between two */
            for (int i = 0; i + 1 < p.width[l] && (i + 1) * step <= W - 1; i += 3) {
                int j = p.height[l] / 2;
                double y = (double)j * step <= H - 1 ? (double)j * step : H - 1;
                int jj = (int)(y / step); /* the level row at or above y */
                double fy = y / step - jj;
                const float* r0 = p.z[l] + (size_t)jj * p.width[l];
                const float* r1 =
                    p.z[l] + (size_t)(jj + 1 < p.height[l] ? jj + 1 : jj) * p.width[l];
                double at = r0[i] + fy * (r1[i] - r0[i]);
                double next = r0[i + 1] + fy * (r1[i + 1] - r0[i + 1]);
                EXPECT_NEAR(at, tp_pgm_pyramid_sample(&p, l, (double)i * step, y), 1e-9);
                EXPECT_NEAR((at + next) / 2, tp_pgm_pyramid_sample(&p, l, (i + 0.5) * step, y),
                            1e-9);
            }
        }
        /* outside clamps to the edge */
        EXPECT_EQ_DBL(z[0], tp_pgm_pyramid_sample(&p, 0, -5, -7));
        EXPECT_EQ_DBL(z[(size_t)H * W - 1], tp_pgm_pyramid_sample(&p, 0, W + 3.0, H + 9.0));
        EXPECT_EQ_DBL(z[0], tp_pgm_pyramid_sample(&p, p.levels - 1, -5, -7));
        if (W <= 2 && H <= 2)
            EXPECT_EQ_INT(1, p.levels);
        if (W == 1201) { /* by hand: ceil(1200 / 2^l) + 1 */
            const int chain[] = {1201, 601, 301, 151, 76, 39, 20, 11, 6, 4, 3, 2};
            ASSERT_EQ_INT(12, p.levels);
            for (int l = 0; l < 12; l++)
                EXPECT_EQ_INT(chain[l], p.width[l]);
        }
        EXPECT_TRUE(p.width[p.levels - 1] <= 2 && p.height[p.levels - 1] <= 2);
        double mn = INFINITY, mx = -INFINITY;
        for (size_t k = 0; k < (size_t)W * H; k++) {
            mn = fmin(mn, z[k]);
            mx = fmax(mx, z[k]);
        }
        EXPECT_EQ_DBL(mn, p.min_m);
        EXPECT_EQ_DBL(mx, p.max_m);
        EXPECT_TRUE(memcmp(gt, p.geotransform, sizeof gt) == 0);
        tp_test_note("%d x %d: %d levels, coarsest %d x %d", W, H, p.levels, p.width[p.levels - 1],
                     p.height[p.levels - 1]);
        tp_pgm_pyramid_free(&p);
        free(z);
    }
    tp_pgm_pyramid_free(NULL);
}

static int all_zero(const void* p, size_t n)
{
    const unsigned char* b = p;
    for (size_t k = 0; k < n; k++)
        if (b[k])
            return 0;
    return 1;
}

TEST(pyramid_refuses_bad_input_and_zeroes_out)
{
    float z[6] = {1, 2, 3, 4, 5, 6};
    double gt[6] = {0, 10, 0, 0, 0, -10};
    tp_pgm_pyramid p;
    tp_error err;
    struct {
        int w, h;
        int nan_at, gt_k;
        double gt_v;
        const char* says;
    } bad[] = {{3, 2, 4, -1, 0, "fill voids"}, {0, 2, -1, -1, 0, "0 x 2"},
               {3, 0, -1, -1, 0, "3 x 0"},     {3, 2, -1, 2, 0.1, "rotated"},
               {3, 2, -1, 4, -0.5, "rotated"}, {3, 2, -1, 1, 0, "zero post spacing"},
               {3, 2, -1, 5, 0, "zero post"},  {3, 2, -1, 0, NAN, "not finite"}};
    for (size_t c = 0; c < sizeof bad / sizeof bad[0]; c++) {
        float zz[6];
        double g[6];
        memcpy(zz, z, sizeof z);
        memcpy(g, gt, sizeof gt);
        if (bad[c].nan_at >= 0)
            zz[bad[c].nan_at] = NAN;
        if (bad[c].gt_k >= 0)
            g[bad[c].gt_k] = bad[c].gt_v;
        memset(&p, 0xAB, sizeof p);
        memset(&err, 0, sizeof err);
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_pgm_pyramid_build(zz, bad[c].w, bad[c].h, g, &p, &err));
        EXPECT_CONTAINS(err.message, bad[c].says);
        EXPECT_TRUE(all_zero(&p, sizeof p));
        tp_pgm_pyramid_free(&p); /* a zeroed pyramid */
    }
    ASSERT_OK(tp_pgm_pyramid_build(z, 3, 2, gt, &p, &err));
    tp_pgm_pyramid_free(&p);
    EXPECT_TRUE(all_zero(&p, sizeof p));
}

/* A smooth terrain with short waves (levels differ by metres): 513 x 513 posts of 30 m. */
static float* wave_terrain(int n)
{
    float* z = malloc((size_t)n * n * sizeof *z);
    for (int y = 0; y < n; y++)
        for (int x = 0; x < n; x++)
            z[(size_t)y * n + x] =
                (float)(1000 + 20 * sin(2 * M_PI * x / 7.3) * cos(2 * M_PI * y / 5.9) + 0.1 * x);
    return z;
}

/* Along each column of the grid (a fan of rays going away from the eye) lod never decreases
 * and spans several levels; the height is the documented blend of the two levels; as the eye
 * rises smoothly, a vertex's lod and height change smoothly even where the level steps up,
 * although the two levels there differ by metres. */
TEST(level_grows_with_distance_and_blends_continuously)
{
    const int N = 513;
    const double gt[6] = {600000, 30, 0, 5000000, 0, -30};
    float* z = wave_terrain(N);
    tp_pgm_pyramid p = make_pyramid(z, N, N, gt);
    const double eye[3] = {600000 + 256 * 30, 5000000 - 400 * 30, 1600};
    tp_camera cam;
    tp_camera_from_pose(eye, 0, -30, 60, 1280, 720, &cam);
    tp_pgm_frame f;
    tp_pgm_frame_setup(&cam, 300, 300, &p, &f);
    for (int i = 0; i < 300; i += 37) {
        double prev = -1, prev_d = -1, first = 0;
        for (int j = 299; j >= 0; j--) {
            double w[3], lod;
            tp_pgm_map_vertex(&f, &p, i, j, w, &lod);
            double d = hypot(w[0] - eye[0], w[1] - eye[1]);
            EXPECT_GT(d, prev_d);
            EXPECT_GE(lod, prev - 1e-12);
            if (j == 299)
                first = lod;
            prev = lod;
            prev_d = d;
            int l = (int)floor(lod);
            double wp = lod - l;
            double x = (w[0] - gt[0]) / gt[1] - 0.5, y = (w[1] - gt[3]) / gt[5] - 0.5;
            double want = tp_pgm_pyramid_sample(&p, l, x, y);
            if (l + 1 < p.levels)
                want = (1 - wp) * want + wp * tp_pgm_pyramid_sample(&p, l + 1, x, y);
            EXPECT_NEAR(want, w[2], 1e-6);
        }
        EXPECT_GT(prev - first, 3); /* from near to the horizon: several levels */
    }
    /* The eye rising from 1100 to 3100 m in 1 cm steps, above the south end of a larger
     * terrain: the vertex 30 rows from the top (about 11 eye heights ahead). */
    tp_pgm_pyramid_free(&p);
    free(z);
    const int N2 = 1025;
    z = wave_terrain(N2);
    p = make_pyramid(z, N2, N2, gt);
    const double eye2[3] = {600000 + 512 * 30, 5000000 - 1010 * 30, 0};
    int switches = 0;
    double worst_switch = 0, worst_other = 0, worst_lod_step = 0, biggest_jump = 0;
    double last_z = NAN, last_lod = NAN;
    for (int k = 0; k <= 200000; k++) {
        double e2[3] = {eye2[0], eye2[1], 1100 + 0.01 * k};
        tp_camera c2;
        tp_camera_from_pose(e2, 0, -30, 60, 1280, 720, &c2);
        tp_pgm_frame f2;
        tp_pgm_frame_setup(&c2, 300, 300, &p, &f2);
        double w[3], lod;
        ASSERT_TRUE(tp_pgm_map_vertex(&f2, &p, 150, 30, w, &lod));
        if (k > 0) {
            double step = fabs(w[2] - last_z);
            worst_lod_step = fmax(worst_lod_step, fabs(lod - last_lod));
            if (floor(lod) != floor(last_lod)) {
                switches++;
                worst_switch = fmax(worst_switch, step);
                int l = (int)fmin(floor(lod), floor(last_lod));
                double x = (w[0] - gt[0]) / gt[1] - 0.5, y = (w[1] - gt[3]) / gt[5] - 0.5;
                if (l + 1 < p.levels)
                    biggest_jump = fmax(biggest_jump, fabs(tp_pgm_pyramid_sample(&p, l + 1, x, y) -
                                                           tp_pgm_pyramid_sample(&p, l, x, y)));
            } else {
                worst_other = fmax(worst_other, step);
            }
        }
        last_z = w[2];
        last_lod = lod;
    }
    tp_test_note("%d level switches: height steps there <= %.4f m (elsewhere <= %.4f m), lod "
                 "steps <= %.2g; unblended jump up to %.2f m",
                 switches, worst_switch, worst_other, worst_lod_step, biggest_jump);
    EXPECT_GE_INT(switches, 3);
    EXPECT_LE(worst_lod_step, 1e-3);
    EXPECT_LE(worst_switch, 2 * worst_other);
    EXPECT_GT(biggest_jump, 20 * worst_other); /* without the blend, the height would jump */
    tp_pgm_pyramid_free(&p);
    free(z);
}

TEST(level_is_zero_near_the_eye_close_to_the_ground)
{
    const int N = 257;
    const double gt[6] = {0, 30, 0, 30 * N, 0, -30};
    float* z = flat_grid(N, N, 1000.0f);
    tp_pgm_pyramid p = make_pyramid(z, N, N, gt);
    const double eye[3] = {128 * 30, 50 * 30, 1005};
    tp_camera cam;
    tp_camera_from_pose(eye, 0, -10, 60, 1280, 720, &cam);
    tp_pgm_frame f;
    tp_pgm_frame_setup(&cam, 300, 300, &p, &f);
    for (int i = 0; i < 300; i += 13) {
        double w[3], lod;
        ASSERT_TRUE(tp_pgm_map_vertex(&f, &p, i, 299, w, &lod));
        EXPECT_EQ_DBL(0, lod);
        tp_pgm_map_vertex(&f, &p, i, 0, w, &lod);
        EXPECT_GT(lod, 1); /* the top row reaches far */
    }
    tp_pgm_pyramid_free(&p);
    free(z);
}

static float hash_height(int x, int y)
{
    unsigned h = (unsigned)x * 73856093u ^ (unsigned)y * 19349663u;
    h ^= h >> 13;
    h *= 0x5bd1e995u;
    h ^= h >> 15;
    return 200.0f + (float)(h % 4000) * 0.01f + 2.0f * (float)x;
}

/* The rasterising measure and a search of every triangle for every post agree: same samples,
 * same uncovered posts, same max and RMS (vertical and screen). */
TEST(measure_agrees_with_a_brute_force_search)
{
    const int N = 33;
    const double gt[6] = {1000, 10, 0, 2000, 0, -10};
    float z[33 * 33];
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++)
            z[y * N + x] = hash_height(x, y);
    tp_pgm_pyramid p = make_pyramid(z, N, N, gt);
    const struct {
        double e, n, h, yaw, pitch, fov;
        int cols, rows;
    } cams[] = {{1160, 1700, 420, 0, -70, 60, 9, 9},   {1100, 1600, 330, 20, -40, 50, 9, 9},
                {1165, 1840, 500, 200, -90, 70, 9, 9}, {1000, 1650, 300, 80, 10, 60, 9, 9},
                {1160, 1700, 420, 0, -70, 60, 40, 23}, {1100, 1600, 330, 20, -40, 50, 2, 2}};
    for (size_t c = 0; c < sizeof cams / sizeof cams[0]; c++) {
        const double eye[3] = {cams[c].e, cams[c].n, cams[c].h};
        tp_camera cam;
        tp_camera_from_pose(eye, cams[c].yaw, cams[c].pitch, cams[c].fov, 800, 600, &cam);
        tp_pgm_frame f;
        tp_pgm_frame_setup(&cam, cams[c].cols, cams[c].rows, &p, &f);
        tp_pgm_error e;
        ASSERT_OK(tp_pgm_measure_error(&f, &p, &cam, &e));
        tp_pgm_error want = brute_force(&f, &p, &cam);
        tp_test_note("camera %zu (%d x %d): %zu samples, %zu uncovered, max %.3f m %.3f px, "
                     "rms %.3f m",
                     c, cams[c].cols, cams[c].rows, e.samples, e.uncovered, e.max_m, e.max_px,
                     e.rms_m);
        if (cams[c].cols > 2)
            EXPECT_GT(want.samples, 50);
        expect_same_error(&want, &e);
    }
    tp_pgm_pyramid_free(&p);
}

#ifdef TP_TEST_NO_IO
static void test_finer_grid_is_more_exact_on_mt_hood(void)
{
    SKIP("built without tp_io");
}
#else
/* Fills voids along rows from the nearest valid post, then whole void rows from a neighbour. */
static void fill_voids(float* z, int w, int h)
{
    int last_full = -1;
    for (int y = 0; y < h; y++) {
        float* r = z + (size_t)y * w;
        int first = -1;
        for (int x = 0; x < w; x++)
            if (!isnan(r[x])) {
                first = x;
                break;
            }
        if (first < 0)
            continue;
        for (int x = 0; x < first; x++)
            r[x] = r[first];
        for (int x = first + 1; x < w; x++)
            if (isnan(r[x]))
                r[x] = r[x - 1];
        if (last_full < y - 1)
            for (int yy = last_full + 1; yy < y; yy++)
                memcpy(z + (size_t)yy * w, r, (size_t)w * sizeof *r);
        last_full = y;
    }
    for (int yy = last_full + 1; yy < h && last_full >= 0; yy++)
        memcpy(z + (size_t)yy * w, z + (size_t)last_full * w, (size_t)w * sizeof *z);
}

/* Mt Hood from a camera above its south-west slopes, looking north-east up the valley towards
 * the summit: a 600 x 600 grid is more exact than 150 x 150: the vertical RMS, the screen
 * error's maximum and RMS; it leaves fewer posts in view uncovered at the terrain's edges. */
TEST(finer_grid_is_more_exact_on_mt_hood)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    const int w = dem->width, h = dem->height;
    fill_voids(dem->heights, w, h);
    tp_pgm_pyramid p = make_pyramid(dem->heights, w, h, dem->geotransform);
    tp_dem_destroy(dem);
    const double* gt = p.geotransform;
    /* the eye 700 m above the post a quarter in from the west and south edges */
    int ex = w / 4, ey = 3 * h / 4;
    double eye[3];
    post_world(gt, ex, ey, eye);
    eye[2] = p.z[0][(size_t)ey * w + ex] + 700;
    tp_camera cam;
    tp_camera_from_pose(eye, 45, -20, 60, 1280, 720, &cam);
    tp_pgm_error e[2];
    const int sizes[2] = {150, 600};
    double seconds[2];
    for (int k = 0; k < 2; k++) {
        tp_pgm_frame f;
        tp_pgm_frame_setup(&cam, sizes[k], sizes[k], &p, &f);
        struct timespec t0, t1;
        clock_gettime(CLOCK_MONOTONIC, &t0);
        ASSERT_OK(tp_pgm_measure_error(&f, &p, &cam, &e[k]));
        clock_gettime(CLOCK_MONOTONIC, &t1);
        seconds[k] = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        tp_test_note("%d x %d: max %.2f m rms %.3f m, max %.2f px rms %.3f px, %zu samples, "
                     "%zu uncovered, %.3f s",
                     sizes[k], sizes[k], e[k].max_m, e[k].rms_m, e[k].max_px, e[k].rms_px,
                     e[k].samples, e[k].uncovered, seconds[k]);
    }
    EXPECT_GT(e[0].samples, 100000);
    EXPECT_EQ_INT(e[0].samples + e[0].uncovered, e[1].samples + e[1].uncovered);
    EXPECT_LT(e[1].uncovered, e[0].uncovered);
    /* Not the vertical maximum: it lies at the farthest posts (a valley at the north edge,
     * 20 km away), under triangles hundreds of metres long in either grid, and either may be
     * the unluckier (level 0 everywhere, below, does not change it much). */
    EXPECT_LT(e[1].rms_m, e[0].rms_m);
    EXPECT_LT(e[1].max_px, e[0].max_px);
    EXPECT_LT(e[1].rms_px, e[0].rms_px);
    EXPECT_LT(seconds[1], 10.0); /* about 0.1 s in a release build; sanitizers are slower */
    /* Level 0 everywhere (a one-level pyramid: the same vertices, exact heights at them) is
     * more exact still: the coarser levels' point samples only lose detail. */
    int levels = p.levels;
    p.levels = 1;
    tp_pgm_frame f;
    tp_pgm_frame_setup(&cam, 600, 600, &p, &f);
    tp_pgm_error e0;
    ASSERT_OK(tp_pgm_measure_error(&f, &p, &cam, &e0));
    p.levels = levels;
    tp_test_note("600 x 600 at level 0 only: max %.2f m rms %.3f m, max %.2f px rms %.3f px",
                 e0.max_m, e0.rms_m, e0.max_px, e0.rms_px);
    EXPECT_EQ_INT(e[1].samples, e0.samples);
    EXPECT_LT(e0.rms_m, e[1].rms_m);
    EXPECT_LT(e0.rms_px, e[1].rms_px);
    tp_pgm_pyramid_free(&p);
}
#endif

TP_TEST_MAIN(TESTS)
