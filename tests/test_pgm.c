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
    const int N = 33, G = 9;
    const double gt[6] = {1000, 10, 0, 2000, 0, -10};
    float z[33 * 33];
    for (int y = 0; y < N; y++)
        for (int x = 0; x < N; x++)
            z[y * N + x] = hash_height(x, y);
    tp_pgm_pyramid p = make_pyramid(z, N, N, gt);
    const struct {
        double e, n, h, yaw, pitch, fov;
    } cams[] = {{1160, 1700, 420, 0, -70, 60},
                {1100, 1600, 330, 20, -40, 50},
                {1165, 1840, 500, 200, -90, 70},
                {1000, 1650, 300, 80, 10, 60}};
    for (size_t c = 0; c < sizeof cams / sizeof cams[0]; c++) {
        const double eye[3] = {cams[c].e, cams[c].n, cams[c].h};
        tp_camera cam;
        tp_camera_from_pose(eye, cams[c].yaw, cams[c].pitch, cams[c].fov, 800, 600, &cam);
        tp_pgm_frame f;
        tp_pgm_frame_setup(&cam, G, G, &p, &f);
        tp_pgm_error e;
        ASSERT_OK(tp_pgm_measure_error(&f, &p, &cam, &e));
        /* brute force */
        double vx[81], vy[81], vz[81];
        int on[81];
        for (int j = 0; j < G; j++)
            for (int i = 0; i < G; i++) {
                double w[3], lod;
                on[j * G + i] = tp_pgm_map_vertex(&f, &p, i, j, w, &lod);
                vx[j * G + i] = (w[0] - gt[0]) / gt[1] - 0.5;
                vy[j * G + i] = (w[1] - gt[3]) / gt[5] - 0.5;
                vz[j * G + i] = w[2];
            }
        size_t samples = 0, uncovered = 0;
        double max_m = 0, sum_m = 0, max_px = 0, sum_px = 0;
        for (int y = 0; y < N; y++)
            for (int x = 0; x < N; x++) {
                double truth[3], px[2];
                post_world(gt, x, y, truth);
                truth[2] = z[y * N + x];
                if (!in_view(&cam, truth, px))
                    continue;
                int found = 0;
                double drawn = 0;
                for (int t = 0; t < 2 * (G - 1) * (G - 1) && !found; t++) {
                    int cell = t / 2, ci = cell % (G - 1), cj = cell / (G - 1);
                    int a = cj * G + ci, b = a + 1, cc = a + G, d = cc + 1;
                    int v[3] = {a, b, cc};
                    if (t % 2) {
                        v[0] = b;
                        v[1] = d;
                        v[2] = cc;
                    }
                    if (!on[v[0]] || !on[v[1]] || !on[v[2]])
                        continue;
                    double x0 = vx[v[0]], y0 = vy[v[0]];
                    double e1x = vx[v[1]] - x0, e1y = vy[v[1]] - y0;
                    double e2x = vx[v[2]] - x0, e2y = vy[v[2]] - y0;
                    double det = e1x * e2y - e1y * e2x;
                    if (det == 0)
                        continue;
                    double s = ((x - x0) * e2y - (y - y0) * e2x) / det;
                    double u = (e1x * (y - y0) - e1y * (x - x0)) / det;
                    if (s < -1e-12 || u < -1e-12 || s + u > 1 + 1e-12)
                        continue;
                    found = 1;
                    drawn = vz[v[0]] + s * (vz[v[1]] - vz[v[0]]) + u * (vz[v[2]] - vz[v[0]]);
                }
                if (!found) {
                    uncovered++;
                    continue;
                }
                double dp[3] = {truth[0], truth[1], drawn}, dpx[2];
                ASSERT_TRUE(tp_camera_project(&cam, dp, dpx, NULL));
                double ev = fabs(drawn - truth[2]), es = hypot(dpx[0] - px[0], dpx[1] - px[1]);
                max_m = fmax(max_m, ev);
                max_px = fmax(max_px, es);
                sum_m += ev * ev;
                sum_px += es * es;
                samples++;
            }
        tp_test_note("camera %zu: %zu samples, %zu uncovered, max %.3f m %.3f px, rms %.3f m", c,
                     e.samples, e.uncovered, e.max_m, e.max_px, e.rms_m);
        EXPECT_GT(samples, 50);
        EXPECT_EQ_INT(samples, e.samples);
        EXPECT_EQ_INT(uncovered, e.uncovered);
        EXPECT_NEAR(max_m, e.max_m, 1e-9 * (1 + max_m));
        EXPECT_NEAR(max_px, e.max_px, 1e-6 * (1 + max_px));
        if (samples) {
            EXPECT_NEAR(sqrt(sum_m / samples), e.rms_m, 1e-9 * (1 + max_m));
            EXPECT_NEAR(sqrt(sum_px / samples), e.rms_px, 1e-6 * (1 + max_px));
        }
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
