/*
 * test_navigate.c - the viewer's navigation (app/view/navigate.c) without a window: flight
 * speed from the height above ground, the home view, orbiting.
 *
 * The terrain of the default view of data/lf_elev_220_mt_hood_utm.tif is 30 km wide and the
 * default camera 17-20 km above it; the old rule (1.5 x the height per second) flew 115 km in
 * 2 s of W and left the DEM.
 */
#include "navigate.h"
#include "tp_test.h"

static tp_camera start_camera(void)
{
    double pos[3] = {602244.617, 5010116.945, 20114.12};
    tp_camera cam;
    tp_camera_from_pose(pos, 0, -50, 60, 1280, 720, &cam);
    return cam;
}

/* Flies with the controls for seconds at 30 frames a second over flat ground at ground_z. */
static void fly(tp_nav* nav, tp_camera* cam, tp_nav_controls c, double seconds, double ground_z)
{
    int i, frames = (int)(seconds * 30 + 0.5);
    for (i = 0; i < frames; ++i)
        tp_nav_step(nav, &c, 1.0 / 30, ground_z, cam);
}

TEST(two_seconds_forward_from_the_default_view_stay_on_the_dem)
{
    tp_camera cam = start_camera();
    tp_nav nav;
    tp_nav_controls c = {0};
    double moved;
    tp_nav_init(&nav, &cam, 30000);
    c.forward = 1;
    fly(&nav, &cam, c, 2.0, 1000);
    moved = hypot(cam.position[0] - 602244.617, cam.position[1] - 5010116.945);
    tp_test_note("2 s of W at %.0f m above ground: %.0f m", 20114.12 - 1000, moved);
    EXPECT_GT(moved, 100);
    EXPECT_LE(moved, 30000 / 10.0);
}

TEST(fly_speed_follows_the_height_above_ground)
{
    EXPECT_NEAR(50, tp_nav_fly_speed(100, 30000), 1e-9);  /* half the height per second */
    EXPECT_NEAR(5, tp_nav_fly_speed(2, 30000), 1e-9);     /* at least 5 m/s */
    EXPECT_NEAR(1500, tp_nav_fly_speed(1e5, 30000), 1e-9); /* at most extent / 20 per s */
    EXPECT_NEAR(500, tp_nav_fly_speed(NAN, 30000), 1e-9);  /* off the terrain: as 1000 m */
    EXPECT_LE(tp_nav_fly_speed(10, 30000), tp_nav_fly_speed(20, 30000));
    EXPECT_NEAR(5, tp_nav_fly_speed(100, 10), 1e-9); /* a tiny DEM still moves */
}

TEST(speed_modifiers_scale_the_step)
{
    tp_camera a = start_camera(), b = start_camera();
    tp_nav na, nb;
    tp_nav_controls c = {0};
    tp_nav_init(&na, &a, 1e6);
    tp_nav_init(&nb, &b, 1e6);
    c.forward = 1;
    tp_nav_step(&na, &c, 0.1, 19714.12, &a); /* 400 m above ground: 200 m/s */
    c.speed_factor = 5;
    tp_nav_step(&nb, &c, 0.1, 19714.12, &b);
    EXPECT_NEAR(20, hypot(a.position[0] - 602244.617, a.position[1] - 5010116.945), 1e-6);
    EXPECT_NEAR(100, hypot(b.position[0] - 602244.617, b.position[1] - 5010116.945), 1e-6);
}

TEST(home_restores_the_start_view_exactly)
{
    tp_camera cam = start_camera(), start = start_camera();
    tp_nav nav;
    tp_nav_controls c = {0};
    double g[3] = {602000, 5024000, 3000};
    int i;
    tp_nav_init(&nav, &cam, 30000);
    c.forward = 1, c.right = 1, c.up = -1, c.look_dx = 30, c.look_dy = 12;
    fly(&nav, &cam, c, 1.0, 1000);
    tp_nav_toggle_orbit(&nav, &cam, g);
    EXPECT_TRUE(nav.orbit);
    fly(&nav, &cam, c, 0.5, 1000);
    cam.viewport_w_px = 800; /* the window was resized meanwhile */
    tp_nav_home(&nav, &cam);
    EXPECT_FALSE(nav.orbit);
    for (i = 0; i < 3; ++i) {
        EXPECT_EQ_DBL(start.position[i], cam.position[i]);
        EXPECT_EQ_DBL(start.forward[i], cam.forward[i]);
    }
    EXPECT_EQ_INT(800, cam.viewport_w_px);
}

TEST(orbit_keeps_its_distance_while_rotating)
{
    tp_camera cam = start_camera();
    tp_nav nav;
    tp_nav_controls c = {0};
    double g[3] = {602244.617, 5025000, 2500}, d0, d1;
    tp_nav_init(&nav, &cam, 30000);
    tp_nav_toggle_orbit(&nav, &cam, g);
    d0 = nav.distance_m;
    c.look_dx = 40;
    c.look_dy = -10;
    fly(&nav, &cam, c, 1.0, 1000);
    d1 = sqrt(pow(cam.position[0] - g[0], 2) + pow(cam.position[1] - g[1], 2) +
              pow(cam.position[2] - g[2], 2));
    EXPECT_NEAR(d0, d1, 1e-6 * d0);
    tp_nav_toggle_orbit(&nav, &cam, g); /* off again */
    EXPECT_FALSE(nav.orbit);
}

#define TESTS(X)                                                                                   \
    X(two_seconds_forward_from_the_default_view_stay_on_the_dem)                                   \
    X(fly_speed_follows_the_height_above_ground)                                                   \
    X(speed_modifiers_scale_the_step)                                                              \
    X(home_restores_the_start_view_exactly)                                                        \
    X(orbit_keeps_its_distance_while_rotating)

TP_TEST_MAIN(TESTS)
