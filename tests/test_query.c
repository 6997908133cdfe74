/*
 * test_query.c - what lies under a ray, and the drawn surface under vertical exaggeration
 * (tp_selection_ray_cast, tp_selection_set_vertical_scale and what follows it: culling, the
 * error LoD, keep_above, the screen-error measure).
 *
 * Synthetic rough terrain with nodata holes and padding; levels from the error LoD and from
 * random hand-set levels, so that rays cross stitched borders. A hit is checked against
 * tp_selection_drawn_height_at (an independent O(1) query of the same drawn surface) and the
 * ray before it is sampled densely: it must never have passed below the surface (the old
 * picker stepped along the ray by x1.004 and went through ridges kilometres out).
 */
#include "tp_test_geom.h"

#define PI 3.14159265358979323846

typedef struct world {
    float* src;
    tp_terrain* t;
    tp_terrain_info ti;
    tp_selection* s;
} world;

static void world_create(world* w, int W, int H, double relief, double noise)
{
    double gt[6] = {500000.0, 30.0, 0.0, 5100000.0, 0.0, -30.0};
    tp_error err;
    tp_rng rng = tp_rng_seed(77);
    int i;
    memset(w, 0, sizeof *w);
    w->src = (float*)malloc(sizeof(float) * W * H);
    ASSERT_TRUE(w->src != NULL);
    tpt_rough_heights(w->src, W, H, 78, 1200.0, relief, noise, 0);
    for (i = 0; i < 3; ++i) { /* holes */
        int cx = tp_rng_int(&rng, 0, W - 1), cy = tp_rng_int(&rng, 0, H - 1), x, y;
        for (y = cy - 3; y <= cy + 3; ++y)
            for (x = cx - 3; x <= cx + 3; ++x)
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

/* A camera over or beside the terrain looking down at a random angle. */
static tp_camera random_camera(const world* w, tp_rng* r, double zs)
{
    const double* gt = w->ti.geotransform;
    double pos[3];
    pos[0] = gt[0] + tp_rng_range(r, -0.2, 1.2) * w->ti.src_width * gt[1];
    pos[1] = gt[3] + tp_rng_range(r, -0.2, 1.2) * w->ti.src_height * gt[5];
    pos[2] = w->ti.max_height_m * zs + tp_rng_range(r, 20, 3000);
    /* toward the terrain's centre, give or take 40 degrees */
    double ce = gt[0] + 0.5 * w->ti.src_width * gt[1], cn = gt[3] + 0.5 * w->ti.src_height * gt[5];
    double yaw = atan2(ce - pos[0], cn - pos[1]) * 180 / PI + tp_rng_range(r, -40, 40);
    tp_camera c;
    tp_camera_from_pose(pos, yaw, tp_rng_range(r, -60, -10), 60, 640, 360, &c);
    return c;
}

/* Drawn height in drawn space (true height times zs) at world (e, n), or NaN. */
static double drawn_z(const world* w, double e, double n, double zs)
{
    double x, y;
    tp_terrain_world_to_grid(w->t, e, n, &x, &y);
    return tp_selection_drawn_height_at(w->s, x, y) * zs;
}

/* Checks one ray: a hit lies on the drawn surface within 1 cm, and the ray does not cross the
 * drawn surface before it: sampled every 1/8 of a sample spacing, no step goes from above the
 * surface to more than 1 cm below it. (A ray that meets the terrain's edge below its surface
 * passes under it: the surface is not a solid.) Returns 1 on a hit. */
static int check_ray(const world* w, const double o[3], const double d[3], double zs)
{
    tp_ray_hit hit;
    double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), t, end, step;
    int was_above = 0;
    ASSERT_OK(tp_selection_ray_cast(w->s, o, d, &hit));
    if (hit.hit) {
        double z = drawn_z(w, hit.position[0], hit.position[1], zs);
        EXPECT_NEAR(hit.position[2] * zs, z, 0.01);
        EXPECT_NEAR(o[2] + hit.distance_m * d[2] / len, hit.position[2] * zs, 1e-6);
        EXPECT_GE(hit.patch, 0);
    }
    end = hit.hit ? hit.distance_m : 3 * (w->ti.width + w->ti.height) * w->ti.geotransform[1];
    step = w->ti.geotransform[1] / 8;
    for (t = step; t < end - step; t += step) {
        double p[3] = {o[0] + t * d[0] / len, o[1] + t * d[1] / len, o[2] + t * d[2] / len};
        double z = drawn_z(w, p[0], p[1], zs);
        if (isnan(z)) {
            was_above = 0;
            continue;
        }
        if (was_above && p[2] < z - 0.01) {
            EXPECT_TRUE(!"the ray crossed the drawn surface before its hit");
            tp_test_note("t %.3f of %.3f: ray z %.3f, surface %.3f", t, end, p[2], z);
            break;
        }
        was_above = p[2] >= z;
    }
    return hit.hit;
}

static void rays_from_random_cameras(double zs, int hand_levels)
{
    world w;
    tp_rng r = tp_rng_seed(zs > 1 ? 4242 : 4141);
    int cam_i, hits = 0, rays = 0, p;
    tp_lod_params lp;
    memset(&lp, 0, sizeof lp);
    lp.mode = TP_LOD_ERROR;
    lp.tau_px = 4;
    world_create(&w, 150, 120, 900.0, 40.0);
    ASSERT_OK(tp_selection_set_vertical_scale(w.s, zs));
    for (cam_i = 0; cam_i < 12; ++cam_i) {
        tp_camera cam = random_camera(&w, &r, zs);
        int i;
        ASSERT_OK(tp_selection_update(w.s, &cam, &lp, NULL));
        if (hand_levels)
            for (p = 0; p < w.ti.patch_count; ++p)
                tp_selection_set_level(w.s, p, tp_rng_int(&r, 0, w.ti.n));
        for (i = 0; i < 25; ++i) {
            double d[3];
            tp_camera_pixel_ray(&cam, tp_rng_range(&r, 0, 640), tp_rng_range(&r, 90, 360), d);
            hits += check_ray(&w, cam.position, d, zs);
            ++rays;
        }
    }
    tp_test_note("%d of %d rays hit the ground", hits, rays);
    EXPECT_GE(hits, rays / 5);
    world_destroy(&w);
}

TEST(ray_cast_hits_lie_on_the_drawn_surface_and_nothing_is_passed)
{
    rays_from_random_cameras(1.0, 0);
}

TEST(ray_cast_across_stitched_borders_of_random_levels)
{
    rays_from_random_cameras(1.0, 1);
}

TEST(ray_cast_follows_the_vertical_scale)
{
    rays_from_random_cameras(3.0, 1);
}

TEST(ray_cast_grazing_a_ridge_hits_the_ridge)
{
    /* a knife-edge ridge across flat ground: a ray that clips its top must hit it, not the
     * ground behind */
    int W = 65, H = 65, x, y;
    float* h = (float*)malloc(sizeof(float) * W * H);
    tp_terrain* t;
    tp_selection* s;
    tp_ray_hit hit;
    double o[3] = {32, -10, 0}, d[3];
    ASSERT_TRUE(h != NULL);
    for (y = 0; y < H; ++y)
        for (x = 0; x < W; ++x)
            h[y * W + x] = y == 40 ? 100.0f : 0.0f;
    t = tpt_terrain_create(h, W, H, 17, TP_FIT_PAD, NULL); /* 1 m north-up: row y at N = -y-0.5 */
    ASSERT_OK(tp_selection_create(t, &s, NULL));
    /* from 1 m above the ground at row -10 (north of the grid, N = 9.5) aim just below the
     * ridge's top (row 40, N = -40.5, 100 m) */
    o[1] = 9.5;
    o[2] = 1;
    d[0] = 0;
    d[1] = -50;
    d[2] = 99.9 - 1;
    ASSERT_OK(tp_selection_ray_cast(s, o, d, &hit));
    ASSERT_TRUE(hit.hit);
    EXPECT_NEAR(hit.position[1], -40.5, 0.01);
    EXPECT_NEAR(hit.position[2], 99.9, 0.01);
    /* and just above it: the ray clears the ridge and meets nothing (the ground behind is
     * flat at 0 and the ray climbs) */
    d[2] = 100.1 - 1;
    ASSERT_OK(tp_selection_ray_cast(s, o, d, &hit));
    EXPECT_FALSE(hit.hit);
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    free(h);
}

TEST(ray_cast_rejects_a_zero_direction)
{
    world w;
    tp_ray_hit hit;
    double o[3] = {0, 0, 0}, d[3] = {0, 0, 0};
    world_create(&w, 40, 40, 100.0, 1.0);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_selection_ray_cast(w.s, o, d, &hit));
    world_destroy(&w);
}

TEST(vertical_scale_rejects_zero_negative_and_nan)
{
    world w;
    world_create(&w, 40, 40, 100.0, 1.0);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_selection_set_vertical_scale(w.s, 0));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_selection_set_vertical_scale(w.s, -2));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_selection_set_vertical_scale(w.s, NAN));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_selection_set_vertical_scale(w.s, INFINITY));
    EXPECT_EQ_DBL(1.0, tp_selection_vertical_scale(w.s));
    ASSERT_OK(tp_selection_set_vertical_scale(w.s, 2.5));
    EXPECT_EQ_DBL(2.5, tp_selection_vertical_scale(w.s));
    world_destroy(&w);
}

TEST(keep_above_uses_the_exaggerated_ground)
{
    world w;
    double pos[3], x, y, g;
    world_create(&w, 60, 60, 300.0, 1.0);
    pos[0] = w.ti.geotransform[0] + 30.5 * w.ti.geotransform[1];
    pos[1] = w.ti.geotransform[3] + 30.5 * w.ti.geotransform[5];
    tp_terrain_world_to_grid(w.t, pos[0], pos[1], &x, &y);
    g = tp_terrain_height_at(w.t, x, y);
    ASSERT_FALSE(isnan(g));
    pos[2] = g * 1.5; /* above the true ground, below the ground drawn three times as high */
    ASSERT_OK(tp_selection_set_vertical_scale(w.s, 3));
    EXPECT_EQ_INT(1, tp_selection_keep_above(w.s, pos, 2.0));
    EXPECT_GE(pos[2], 3 * g + 2.0 - 1e-6);
    world_destroy(&w);
}

TEST(vertical_scale_keeps_patches_that_rise_into_view)
{
    /* a plateau 100 m high; the eye at 150 m looks 40 degrees up, so the true plateau is below
     * the view, but drawn three times as high (300 m) it rises into it */
    int W = 129, H = 129, i;
    float* h = (float*)malloc(sizeof(float) * W * H);
    double gt[6] = {0, 10, 0, 1290, 0, -10}, pos[3] = {645, -500, 150};
    tp_terrain* t;
    tp_selection* s;
    tp_camera cam;
    tp_lod_params lp;
    tp_frame_stats st;
    ASSERT_TRUE(h != NULL);
    for (i = 0; i < W * H; ++i)
        h[i] = 100.0f;
    t = tpt_terrain_create(h, W, H, 17, TP_FIT_PAD, gt);
    ASSERT_OK(tp_selection_create(t, &s, NULL));
    tp_camera_from_pose(pos, 0, 40, 60, 640, 360, &cam);
    memset(&lp, 0, sizeof lp);
    lp.mode = TP_LOD_ERROR;
    ASSERT_OK(tp_selection_update(s, &cam, &lp, NULL));
    tp_selection_stats(s, &st);
    EXPECT_EQ_INT(0, st.visible_patches);
    ASSERT_OK(tp_selection_set_vertical_scale(s, 3));
    ASSERT_OK(tp_selection_update(s, &cam, &lp, NULL));
    tp_selection_stats(s, &st);
    EXPECT_GT(st.visible_patches, 0);
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    free(h);
}

TEST(error_lod_holds_tau_under_vertical_scale)
{
    world w;
    tp_rng r = tp_rng_seed(9);
    tp_lod_params lp;
    int i;
    memset(&lp, 0, sizeof lp);
    lp.mode = TP_LOD_ERROR;
    lp.tau_px = 1;
    world_create(&w, 150, 120, 900.0, 40.0);
    for (i = 0; i < 6; ++i) {
        tp_camera cam = random_camera(&w, &r, 4);
        tp_frame_stats s1, s4;
        double max_px = 0;
        ASSERT_OK(tp_selection_set_vertical_scale(w.s, 1));
        ASSERT_OK(tp_selection_update(w.s, &cam, &lp, NULL));
        tp_selection_stats(w.s, &s1);
        ASSERT_OK(tp_selection_set_vertical_scale(w.s, 4));
        ASSERT_OK(tp_selection_update(w.s, &cam, &lp, NULL));
        tp_selection_stats(w.s, &s4);
        ASSERT_OK(tp_selection_measure_screen_error(w.s, &cam, &max_px, NULL, NULL));
        EXPECT_LE(max_px, lp.tau_px + 1e-9); /* measured on the exaggerated surface */
        if (s1.visible_patches > 0)
            EXPECT_GE((double)s4.triangles, (double)s1.triangles);
    }
    world_destroy(&w);
}

TEST(camera_project_and_pixel_ray_are_inverse)
{
    tp_rng r = tp_rng_seed(5);
    int i;
    for (i = 0; i < 200; ++i) {
        double pos[3] = {tp_rng_range(&r, -1e6, 1e6), tp_rng_range(&r, 0, 1e7), 500};
        double px[2] = {tp_rng_range(&r, 0, 1280), tp_rng_range(&r, 0, 720)}, d[3], q[3],
               back[2], depth;
        tp_camera cam;
        tp_camera_from_pose(pos, tp_rng_range(&r, 0, 360), tp_rng_range(&r, -89, 89), 60, 1280,
                            720, &cam);
        tp_camera_pixel_ray(&cam, px[0], px[1], d);
        EXPECT_NEAR(1.0, sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]), 1e-12);
        q[0] = pos[0] + 1000 * d[0];
        q[1] = pos[1] + 1000 * d[1];
        q[2] = pos[2] + 1000 * d[2];
        ASSERT_TRUE(tp_camera_project(&cam, q, back, &depth));
        EXPECT_NEAR(px[0], back[0], 1e-6);
        EXPECT_NEAR(px[1], back[1], 1e-6);
        EXPECT_GT(depth, 0);
    }
}

TEST(camera_pose_round_trips)
{
    double pos[3] = {1, 2, 3}, yaw, pitch;
    tp_camera cam;
    tp_camera_from_pose(pos, 123.5, -37.25, 45, 800, 600, &cam);
    tp_camera_get_pose(&cam, &yaw, &pitch);
    EXPECT_NEAR(123.5, yaw, 1e-9);
    EXPECT_NEAR(-37.25, pitch, 1e-9);
    tp_camera_from_pose(pos, 0, -90, 45, 800, 600, &cam); /* straight down: still a frame */
    {
        double px[2], below[3] = {1, 2, -100};
        ASSERT_TRUE(tp_camera_project(&cam, below, px, NULL));
        EXPECT_NEAR(400, px[0], 1e-6);
        EXPECT_NEAR(300, px[1], 1e-6);
    }
}

TEST(view_projection_matches_project)
{
    /* the matrix the renderer uploads puts a point where tp_camera_project says */
    tp_rng r = tp_rng_seed(6);
    int i;
    for (i = 0; i < 100; ++i) {
        double pos[3] = {0, 0, 100}, m[16], q[3], px[2], clip[4] = {0, 0, 0, 0};
        int a, b;
        tp_camera cam;
        tp_camera_from_pose(pos, tp_rng_range(&r, 0, 360), tp_rng_range(&r, -80, 80), 50, 1024,
                            768, &cam);
        tp_camera_pixel_ray(&cam, tp_rng_range(&r, 0, 1024), tp_rng_range(&r, 0, 768), q);
        for (a = 0; a < 3; ++a)
            q[a] *= tp_rng_range(&r, 10, 5000);
        ASSERT_TRUE(tp_camera_project(&cam, (double[3]){q[0], q[1], q[2] + 100}, px, NULL));
        tp_camera_view_projection(&cam, 10000, m);
        for (b = 0; b < 4; ++b)
            clip[b] = m[0 * 4 + b] * q[0] + m[1 * 4 + b] * q[1] + m[2 * 4 + b] * q[2] + m[12 + b];
        EXPECT_NEAR(px[0], (clip[0] / clip[3] + 1) * 512, 1e-6);
        EXPECT_NEAR(px[1], (1 - clip[1] / clip[3]) * 384, 1e-6);
        EXPECT_TRUE(clip[2] / clip[3] > -1 && clip[2] / clip[3] < 1);
    }
}

#define TESTS(X)                                                                                   \
    X(ray_cast_hits_lie_on_the_drawn_surface_and_nothing_is_passed)                                \
    X(ray_cast_across_stitched_borders_of_random_levels)                                           \
    X(ray_cast_follows_the_vertical_scale)                                                         \
    X(ray_cast_grazing_a_ridge_hits_the_ridge)                                                     \
    X(ray_cast_rejects_a_zero_direction)                                                           \
    X(vertical_scale_rejects_zero_negative_and_nan)                                                \
    X(keep_above_uses_the_exaggerated_ground)                                                      \
    X(vertical_scale_keeps_patches_that_rise_into_view)                                            \
    X(error_lod_holds_tau_under_vertical_scale)                                                    \
    X(camera_project_and_pixel_ray_are_inverse)                                                    \
    X(camera_pose_round_trips)                                                                     \
    X(view_projection_matches_project)

TP_TEST_MAIN(TESTS)
