/*
 * test_cull.c - view frustum planes and AABB culling (tp_frustum_from_camera,
 * tp_frustum_test_aabb; Vanek & Jezek section 3).
 *
 * The planes are checked against an independent pinhole camera built from the tp_camera fields;
 * the AABB test against brute force over the box corners: OUTSIDE exactly when all 8 corners
 * are outside one plane, INSIDE exactly when all corners are inside every plane.
 */
#include "tp_test_geom.h"

#define PI 3.14159265358979323846
#define DEG (PI / 180.0)

static double plane_eval(const tp_frustum* f, int i, const double p[3])
{
    return f->planes[i][0] * p[0] + f->planes[i][1] * p[1] + f->planes[i][2] * p[2] +
           f->planes[i][3];
}

/* Smallest signed plane distance: >= 0 inside all planes. */
static double frustum_margin(const tp_frustum* f, const double p[3])
{
    double m = INFINITY;
    int i;
    for (i = 0; i < f->plane_count; ++i) {
        double d = plane_eval(f, i, p);
        if (d < m)
            m = d;
    }
    return m;
}

static tp_camera camera_at(double e, double n, double h, double yaw_deg, double pitch_deg)
{
    tp_camera c;
    memset(&c, 0, sizeof c);
    c.position[0] = e;
    c.position[1] = n;
    c.position[2] = h;
    c.forward[0] = cos(pitch_deg * DEG) * sin(yaw_deg * DEG);
    c.forward[1] = cos(pitch_deg * DEG) * cos(yaw_deg * DEG);
    c.forward[2] = sin(pitch_deg * DEG);
    c.up[2] = 1.0;
    return c;
}

/* A point at `dist` along the direction rotated from the camera's forward by yaw_off to the
 * right and pitch_off up (camera frame), for a level camera looking at azimuth yaw_deg. */
static void point_off_axis(const tp_camera* c, double yaw_deg, double dist, double right_deg,
                           double up_deg, double out[3])
{
    /* level camera: forward (sin a, cos a, 0), right (cos a, -sin a, 0), up (0, 0, 1) */
    double a = yaw_deg * DEG;
    double fx = sin(a), fy = cos(a), rx = cos(a), ry = -sin(a);
    double x = tan(right_deg * DEG), y = tan(up_deg * DEG);
    out[0] = c->position[0] + dist * (fx + x * rx);
    out[1] = c->position[1] + dist * (fy + x * ry);
    out[2] = c->position[2] + dist * y;
}

TEST(planes_are_unit_and_counted)
{
    tp_camera c = camera_at(500000, 5000000, 1200, 30, -10);
    tp_frustum f;
    int i;
    tp_frustum_from_camera(&c, &f);
    EXPECT_EQ_INT(5, f.plane_count);
    c.far_m = 5000.0;
    tp_frustum_from_camera(&c, &f);
    EXPECT_EQ_INT(6, f.plane_count);
    for (i = 0; i < f.plane_count; ++i)
        EXPECT_NEAR(1.0,
                    sqrt(f.planes[i][0] * f.planes[i][0] + f.planes[i][1] * f.planes[i][1] +
                         f.planes[i][2] * f.planes[i][2]),
                    1e-12);
}

TEST(point_ahead_is_inside_and_behind_is_outside)
{
    tp_camera c = camera_at(1000, 2000, 300, 123, -20);
    tp_frustum f;
    double p[3];
    int i;
    tp_frustum_from_camera(&c, &f);
    for (i = 0; i < 3; ++i)
        p[i] = c.position[i] + 50.0 * c.forward[i];
    EXPECT_GT(frustum_margin(&f, p), 0.0);
    for (i = 0; i < 3; ++i)
        p[i] = c.position[i] + 1e6 * c.forward[i]; /* no far plane */
    EXPECT_GT(frustum_margin(&f, p), 0.0);
    for (i = 0; i < 3; ++i)
        p[i] = c.position[i] - 50.0 * c.forward[i];
    EXPECT_LT(frustum_margin(&f, p), 0.0);
}

TEST(near_plane_defaults_to_one_metre)
{
    tp_camera c = camera_at(0, 0, 0, 0, 0);
    tp_frustum f;
    double p[3] = {0, 0.99, 0}, q[3] = {0, 1.01, 0};
    tp_frustum_from_camera(&c, &f);
    EXPECT_LT(frustum_margin(&f, p), 0.0);
    EXPECT_GT(frustum_margin(&f, q), 0.0);
    c.near_m = 0.1;
    tp_frustum_from_camera(&c, &f);
    EXPECT_GT(frustum_margin(&f, p), 0.0);
}

TEST(far_plane_cuts_beyond_far)
{
    tp_camera c = camera_at(10, 20, 30, 90, 0);
    tp_frustum f;
    double p[3] = {10 + 999, 20, 30}, q[3] = {10 + 1001, 20, 30};
    c.far_m = 1000.0;
    tp_frustum_from_camera(&c, &f);
    EXPECT_GT(frustum_margin(&f, p), 0.0);
    EXPECT_LT(frustum_margin(&f, q), 0.0);
}

TEST(default_view_is_60_degrees_at_16_by_9)
{
    /* vertical half angle 30 deg; horizontal half angle atan(tan 30 * 16/9) = 45.75 deg */
    double half_h = atan(tan(30.0 * DEG) * 1280.0 / 720.0) / DEG, yaw;
    for (yaw = 0; yaw < 360; yaw += 45) {
        tp_camera c = camera_at(300000, 4000000, 100, yaw, 0);
        tp_frustum f;
        double p[3];
        tp_frustum_from_camera(&c, &f);
        point_off_axis(&c, yaw, 100, half_h - 0.2, 0, p);
        EXPECT_GT(frustum_margin(&f, p), 0.0);
        point_off_axis(&c, yaw, 100, half_h + 0.2, 0, p);
        EXPECT_LT(frustum_margin(&f, p), 0.0);
        point_off_axis(&c, yaw, 100, -(half_h - 0.2), 0, p);
        EXPECT_GT(frustum_margin(&f, p), 0.0);
        point_off_axis(&c, yaw, 100, -(half_h + 0.2), 0, p);
        EXPECT_LT(frustum_margin(&f, p), 0.0);
        point_off_axis(&c, yaw, 100, 0, 29.8, p);
        EXPECT_GT(frustum_margin(&f, p), 0.0);
        point_off_axis(&c, yaw, 100, 0, 30.2, p);
        EXPECT_LT(frustum_margin(&f, p), 0.0);
        point_off_axis(&c, yaw, 100, 0, -29.8, p);
        EXPECT_GT(frustum_margin(&f, p), 0.0);
        point_off_axis(&c, yaw, 100, 0, -30.2, p);
        EXPECT_LT(frustum_margin(&f, p), 0.0);
    }
}

TEST(viewport_and_fov_set_the_angles)
{
    tp_camera c = camera_at(0, 0, 0, 0, 0);
    tp_frustum f;
    double p[3];
    c.viewport_w_px = 800;
    c.viewport_h_px = 800;
    c.fov_y_rad = 90.0 * DEG;
    tp_frustum_from_camera(&c, &f);
    point_off_axis(&c, 0, 10, 44.5, 0, p);
    EXPECT_GT(frustum_margin(&f, p), 0.0);
    point_off_axis(&c, 0, 10, 45.5, 0, p);
    EXPECT_LT(frustum_margin(&f, p), 0.0);
    point_off_axis(&c, 0, 10, 0, 44.5, p);
    EXPECT_GT(frustum_margin(&f, p), 0.0);
    point_off_axis(&c, 0, 10, 0, -45.5, p);
    EXPECT_LT(frustum_margin(&f, p), 0.0);
}

TEST(zero_forward_looks_north_and_level)
{
    tp_camera c;
    tp_frustum f;
    double north[3] = {0, 100, 0}, south[3] = {0, -100, 0}, east[3] = {100, 0, 0},
           up[3] = {0, 10, 100}, down[3] = {0, 10, -100};
    memset(&c, 0, sizeof c);
    c.up[2] = 1.0;
    tp_frustum_from_camera(&c, &f);
    EXPECT_GT(frustum_margin(&f, north), 0.0);
    EXPECT_LT(frustum_margin(&f, south), 0.0);
    EXPECT_LT(frustum_margin(&f, east), 0.0);
    EXPECT_LT(frustum_margin(&f, up), 0.0);
    EXPECT_LT(frustum_margin(&f, down), 0.0);
}

/* An independent pinhole model of the camera: is p inside the view volume, and how far from
 * its boundary (a relative margin in tangent units)? */
static int pinhole_inside(const tp_camera* c, const double p[3], double* margin)
{
    double fwd[3], up[3], right[3], d[3], X, Y, Z, ty, tx, l, near_m;
    int i, w = c->viewport_w_px, h = c->viewport_h_px;
    double fov = c->fov_y_rad > 0 ? c->fov_y_rad : 60.0 * DEG;
    if (w <= 0 || h <= 0) {
        w = 1280;
        h = 720;
    }
    memcpy(fwd, c->forward, sizeof fwd);
    if (fwd[0] == 0 && fwd[1] == 0 && fwd[2] == 0)
        fwd[1] = 1;
    l = sqrt(fwd[0] * fwd[0] + fwd[1] * fwd[1] + fwd[2] * fwd[2]);
    for (i = 0; i < 3; ++i)
        fwd[i] /= l;
    right[0] = fwd[1] * c->up[2] - fwd[2] * c->up[1];
    right[1] = fwd[2] * c->up[0] - fwd[0] * c->up[2];
    right[2] = fwd[0] * c->up[1] - fwd[1] * c->up[0];
    l = sqrt(right[0] * right[0] + right[1] * right[1] + right[2] * right[2]);
    for (i = 0; i < 3; ++i)
        right[i] /= l;
    up[0] = right[1] * fwd[2] - right[2] * fwd[1];
    up[1] = right[2] * fwd[0] - right[0] * fwd[2];
    up[2] = right[0] * fwd[1] - right[1] * fwd[0];
    for (i = 0; i < 3; ++i)
        d[i] = p[i] - c->position[i];
    X = d[0] * right[0] + d[1] * right[1] + d[2] * right[2];
    Y = d[0] * up[0] + d[1] * up[1] + d[2] * up[2];
    Z = d[0] * fwd[0] + d[1] * fwd[1] + d[2] * fwd[2];
    ty = tan(fov / 2);
    tx = ty * w / h;
    near_m = c->near_m > 0 ? c->near_m : 1.0;
    l = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]) + 1.0;
    /* distances to each boundary, scaled to metres-ish at the point */
    {
        double m = (Z - near_m);
        double mx = (tx * Z - fabs(X)) / sqrt(1 + tx * tx);
        double my = (ty * Z - fabs(Y)) / sqrt(1 + ty * ty);
        if (mx < m)
            m = mx;
        if (my < m)
            m = my;
        if (c->far_m > 0 && c->far_m - Z < m)
            m = c->far_m - Z;
        *margin = m / l;
        return m >= 0;
    }
}

TEST(planes_agree_with_independent_pinhole_model)
{
    tp_rng rng = tp_rng_seed(401);
    int cam_i, checked = 0;
    for (cam_i = 0; cam_i < 200; ++cam_i) {
        tp_camera c;
        tp_frustum f;
        int i;
        memset(&c, 0, sizeof c);
        c.position[0] = tp_rng_range(&rng, 3e5, 7e5);
        c.position[1] = tp_rng_range(&rng, 4e6, 6e6);
        c.position[2] = tp_rng_range(&rng, 0, 5000);
        for (i = 0; i < 3; ++i)
            c.forward[i] = tp_rng_range(&rng, -3, 3); /* not unit */
        c.up[0] = tp_rng_range(&rng, -0.3, 0.3);
        c.up[1] = tp_rng_range(&rng, -0.3, 0.3);
        c.up[2] = tp_rng_range(&rng, 0.5, 4);
        if (cam_i % 3 == 1) {
            c.fov_y_rad = tp_rng_range(&rng, 10, 120) * DEG;
            c.viewport_w_px = tp_rng_int(&rng, 100, 4000);
            c.viewport_h_px = tp_rng_int(&rng, 100, 4000);
            c.near_m = tp_rng_range(&rng, 0.01, 20);
        }
        if (cam_i % 4 == 2)
            c.far_m = tp_rng_range(&rng, 100, 20000);
        /* skip cameras with up nearly parallel to forward */
        {
            double l1 = sqrt(c.forward[0] * c.forward[0] + c.forward[1] * c.forward[1] +
                             c.forward[2] * c.forward[2]),
                   l2 = sqrt(c.up[0] * c.up[0] + c.up[1] * c.up[1] + c.up[2] * c.up[2]);
            double dot =
                (c.forward[0] * c.up[0] + c.forward[1] * c.up[1] + c.forward[2] * c.up[2]) /
                (l1 * l2);
            if (fabs(dot) > 0.95 || l1 < 0.1)
                continue;
        }
        tp_frustum_from_camera(&c, &f);
        for (i = 0; i < 400; ++i) {
            double p[3], margin;
            int inside, in_planes;
            p[0] = c.position[0] + tp_rng_range(&rng, -3000, 3000);
            p[1] = c.position[1] + tp_rng_range(&rng, -3000, 3000);
            p[2] = c.position[2] + tp_rng_range(&rng, -3000, 3000);
            if (i % 4 == 0) { /* near the camera too */
                int j;
                for (j = 0; j < 3; ++j)
                    p[j] = c.position[j] + (p[j] - c.position[j]) * 0.003;
            }
            inside = pinhole_inside(&c, p, &margin);
            if (fabs(margin) < 1e-6)
                continue;
            in_planes = frustum_margin(&f, p) >= 0;
            checked++;
            if (inside != in_planes) {
                ADD_FAILURE("camera %d (fov %g deg, %dx%d, near %g, far %g): point %.3f %.3f %.3f "
                            "is %s the pinhole view but %s the planes",
                            cam_i, c.fov_y_rad / DEG, c.viewport_w_px, c.viewport_h_px, c.near_m,
                            c.far_m, p[0], p[1], p[2], inside ? "inside" : "outside",
                            in_planes ? "inside" : "outside");
                break;
            }
        }
        if (tp_test_state_.failures)
            break;
    }
    EXPECT_GE_INT(checked, 10000);
}

/* ---------------------------------------------------------------------------------------------
 * AABB test against brute force
 */
typedef struct box_truth {
    int separated; /* all corners strictly outside one plane */
    int contained; /* all corners strictly inside every plane */
    int ambiguous; /* some corner within eps of a plane that decides */
} box_truth;

static box_truth box_brute(const tp_frustum* f, const double lo[3], const double hi[3], double eps)
{
    box_truth r = {0, 1, 0};
    int i, c;
    for (i = 0; i < f->plane_count; ++i) {
        int all_out = 1, near_out = 0;
        for (c = 0; c < 8; ++c) {
            double p[3] = {c & 1 ? hi[0] : lo[0], c & 2 ? hi[1] : lo[1], c & 4 ? hi[2] : lo[2]};
            double d = plane_eval(f, i, p);
            if (d >= -eps)
                all_out = 0;
            if (fabs(d) <= eps)
                near_out = 1;
            if (d <= eps)
                r.contained = 0;
        }
        if (all_out)
            r.separated = 1;
        if (near_out)
            r.ambiguous = 1;
    }
    return r;
}

/* Is some point of a dense lattice of the box strictly inside the frustum? */
static int box_has_inner_point(const tp_frustum* f, const double lo[3], const double hi[3])
{
    int i, j, k;
    for (i = 0; i <= 6; ++i)
        for (j = 0; j <= 6; ++j)
            for (k = 0; k <= 6; ++k) {
                double p[3] = {lo[0] + (hi[0] - lo[0]) * i / 6.0, lo[1] + (hi[1] - lo[1]) * j / 6.0,
                               lo[2] + (hi[2] - lo[2]) * k / 6.0};
                if (frustum_margin(f, p) > 1e-6)
                    return 1;
            }
    return 0;
}

static void check_boxes(const tp_frustum* f, tp_rng* rng, const double centre[3], double spread,
                        int boxes, const char* what, int* counts)
{
    int b;
    for (b = 0; b < boxes; ++b) {
        double lo[3], hi[3];
        box_truth truth;
        tp_cull got;
        int i;
        for (i = 0; i < 3; ++i) {
            double c = centre[i] + tp_rng_range(rng, -spread, spread);
            double half = b % 5 == 0 ? 0.0 : exp(tp_rng_range(rng, log(0.1), log(spread)));
            lo[i] = c - half * tp_rng_unit(rng);
            hi[i] = c + half * tp_rng_unit(rng);
        }
        truth = box_brute(f, lo, hi, 1e-6);
        got = tp_frustum_test_aabb(f, lo, hi);
        counts[got]++;
        if (got == TP_CULL_OUTSIDE && box_has_inner_point(f, lo, hi)) {
            ADD_FAILURE("%s box %d: OUTSIDE, but it has a point inside the frustum", what, b);
            return;
        }
        if (truth.ambiguous)
            continue;
        if ((got == TP_CULL_OUTSIDE) != truth.separated) {
            ADD_FAILURE("%s box %d [%.3f %.3f %.3f]-[%.3f %.3f %.3f]: got %d, but all corners "
                        "outside one plane: %d",
                        what, b, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], (int)got,
                        truth.separated);
            return;
        }
        if ((got == TP_CULL_INSIDE) != truth.contained) {
            ADD_FAILURE("%s box %d [%.3f %.3f %.3f]-[%.3f %.3f %.3f]: got %d, but all corners "
                        "inside every plane: %d",
                        what, b, lo[0], lo[1], lo[2], hi[0], hi[1], hi[2], (int)got,
                        truth.contained);
            return;
        }
    }
}

TEST(aabb_test_agrees_with_brute_force_on_camera_frusta)
{
    tp_rng rng = tp_rng_seed(411);
    int i, counts[3] = {0, 0, 0};
    for (i = 0; i < 100 && !tp_test_state_.failures; ++i) {
        tp_camera c = camera_at(tp_rng_range(&rng, 3e5, 7e5), tp_rng_range(&rng, 4e6, 6e6),
                                tp_rng_range(&rng, 0, 3000), tp_rng_range(&rng, 0, 360),
                                tp_rng_range(&rng, -89, 60));
        tp_frustum f;
        double centre[3];
        int j;
        if (i % 2)
            c.far_m = tp_rng_range(&rng, 200, 5000);
        tp_frustum_from_camera(&c, &f);
        for (j = 0; j < 3; ++j)
            centre[j] = c.position[j] + 600.0 * c.forward[j];
        check_boxes(&f, &rng, centre, 1500.0, 400, "camera frustum", counts);
    }
    tp_test_note("outside %d, intersects %d, inside %d", counts[0], counts[1], counts[2]);
    EXPECT_GE_INT(counts[TP_CULL_OUTSIDE], 100);
    EXPECT_GE_INT(counts[TP_CULL_INTERSECTS], 100);
    EXPECT_GE_INT(counts[TP_CULL_INSIDE], 100);
}

TEST(aabb_test_agrees_with_brute_force_on_arbitrary_planes)
{
    /* the test is defined for any set of unit planes, not only camera frusta */
    tp_rng rng = tp_rng_seed(421);
    int i, counts[3] = {0, 0, 0};
    for (i = 0; i < 200 && !tp_test_state_.failures; ++i) {
        tp_frustum f;
        double centre[3] = {0, 0, 0};
        int j;
        f.plane_count = i % 2 ? 6 : 5;
        for (j = 0; j < 6; ++j) {
            double a = tp_rng_range(&rng, -1, 1), b = tp_rng_range(&rng, -1, 1),
                   c = tp_rng_range(&rng, -1, 1), l = sqrt(a * a + b * b + c * c);
            if (l < 1e-3) {
                a = 1;
                l = 1;
            }
            f.planes[j][0] = a / l;
            f.planes[j][1] = b / l;
            f.planes[j][2] = c / l;
            f.planes[j][3] = tp_rng_range(&rng, -5, 50);
        }
        check_boxes(&f, &rng, centre, 60.0, 300, "random planes", counts);
    }
    tp_test_note("outside %d, intersects %d, inside %d", counts[0], counts[1], counts[2]);
}

TEST(aabb_outside_only_behind_a_single_plane)
{
    /* a box beyond the right and top planes at once, but not wholly behind either: the test
     * is conservative and must say INTERSECTS, never OUTSIDE */
    tp_frustum f;
    double lo[3] = {9, 9, -1}, hi[3] = {12, 12, 1};
    memset(&f, 0, sizeof f);
    f.plane_count = 5;
    /* x <= 10, y <= 10, x >= -10, y >= -10, z >= -100 */
    f.planes[0][0] = -1;
    f.planes[0][3] = 10;
    f.planes[1][1] = -1;
    f.planes[1][3] = 10;
    f.planes[2][0] = 1;
    f.planes[2][3] = 10;
    f.planes[3][1] = 1;
    f.planes[3][3] = 10;
    f.planes[4][2] = 1;
    f.planes[4][3] = 100;
    EXPECT_EQ_INT(TP_CULL_INTERSECTS, tp_frustum_test_aabb(&f, lo, hi));
    lo[0] = 10.5;
    EXPECT_EQ_INT(TP_CULL_OUTSIDE, tp_frustum_test_aabb(&f, lo, hi));
    lo[0] = -5;
    lo[1] = -5;
    hi[0] = 5;
    hi[1] = 5;
    EXPECT_EQ_INT(TP_CULL_INSIDE, tp_frustum_test_aabb(&f, lo, hi));
}

TEST(aabb_point_boxes)
{
    tp_camera c = camera_at(100, 100, 100, 0, 0);
    tp_frustum f;
    double in[3] = {100, 300, 100}, out[3] = {100, -300, 100};
    tp_frustum_from_camera(&c, &f);
    EXPECT_EQ_INT(TP_CULL_INSIDE, tp_frustum_test_aabb(&f, in, in));
    EXPECT_EQ_INT(TP_CULL_OUTSIDE, tp_frustum_test_aabb(&f, out, out));
}

#define TESTS(X)                                                                                   \
    X(planes_are_unit_and_counted)                                                                 \
    X(point_ahead_is_inside_and_behind_is_outside)                                                 \
    X(near_plane_defaults_to_one_metre)                                                            \
    X(far_plane_cuts_beyond_far)                                                                   \
    X(default_view_is_60_degrees_at_16_by_9)                                                       \
    X(viewport_and_fov_set_the_angles)                                                             \
    X(zero_forward_looks_north_and_level)                                                          \
    X(planes_agree_with_independent_pinhole_model)                                                 \
    X(aabb_test_agrees_with_brute_force_on_camera_frusta)                                          \
    X(aabb_test_agrees_with_brute_force_on_arbitrary_planes)                                       \
    X(aabb_outside_only_behind_a_single_plane)                                                     \
    X(aabb_point_boxes)
TP_TEST_MAIN(TESTS)
