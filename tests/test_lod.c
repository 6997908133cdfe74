/*
 * test_lod.c - level of detail: the distance formula (Vanek & Jezek section 3), parameter
 * resolution, and the screen-space error guarantee of TP_LOD_ERROR (Brodersen's tau).
 *
 * The screen error is measured twice: by tp_selection_measure_screen_error, and here,
 * independently, by rasterising each visible patch's drawn triangles (tp_patch_vertices +
 * tp_patch_triangles with the selection's levels) and projecting every drawn sample and the
 * drawn surface above/below it through a pinhole camera built from the tp_camera fields.
 */
#include "tp_test_geom.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#define PI 3.14159265358979323846

/* ---------------------------------------------------------------------------------------------
 * tp_lod_level_distance
 */

/* The level for valid parameters; a failed call is a test failure (and -1). */
static int distance_level(int n, double dist, double mindist, double maxdist, double exponent)
{
    int k = -1;
    tp_status st = tp_lod_level_distance(n, dist, mindist, maxdist, exponent, &k, NULL);
    if (st != TP_OK)
        ADD_FAILURE("tp_lod_level_distance(%d, %g, %g, %g, %g): %s", n, dist, mindist, maxdist,
                    exponent, tp_test_status_name_(st));
    return st == TP_OK ? k : -1;
}

TEST(distance_at_or_below_mindist_is_finest)
{
    EXPECT_EQ_INT(8, distance_level(8, 0.0, 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(8, distance_level(8, 50.0, 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(8, distance_level(8, 100.0, 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(8, distance_level(8, nextafter(100.0, 1e9), 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(5, distance_level(5, 100.0, 100.0, 1100.0, 3.0));
}

TEST(distance_at_or_beyond_maxdist_is_coarsest)
{
    EXPECT_EQ_INT(0, distance_level(8, 1100.0, 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(0, distance_level(8, nextafter(1100.0, 1e9), 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(0, distance_level(8, 1e12, 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(0, distance_level(8, INFINITY, 100.0, 1100.0, 1.0));
    /* just inside maxdist the formula asks for a little more than level 0 */
    EXPECT_EQ_INT(1, distance_level(8, 1099.0, 100.0, 1100.0, 1.0));
}

TEST(distance_formula_rounds_up)
{
    /* exp 1, n 8: dist = 100 + 125 j gives exactly level 8 - j; a millimetre nearer asks for
     * slightly more, which rounds up to 9 - j; a millimetre further stays at 8 - j */
    int j;
    for (j = 1; j <= 7; ++j) {
        double d = 100.0 + 125.0 * j;
        EXPECT_EQ_INT(8 - j, distance_level(8, d, 100.0, 1100.0, 1.0));
        EXPECT_EQ_INT(9 - j, distance_level(8, d - 0.001, 100.0, 1100.0, 1.0));
        EXPECT_EQ_INT(8 - j, distance_level(8, d + 0.001, 100.0, 1100.0, 1.0));
    }
}

TEST(distance_formula_exponent)
{
    /* ratio 1/2: 8 * (1 - 1/4) = 6 with exp 2, 8 * (1 - 1/8) = 7 with exp 3 */
    EXPECT_EQ_INT(6, distance_level(8, 600.0, 100.0, 1100.0, 2.0));
    EXPECT_EQ_INT(7, distance_level(8, 600.0, 100.0, 1100.0, 3.0));
    /* ratio 1/4: 8 * (1 - 1/2) = 4 with exp 1/2 */
    EXPECT_EQ_INT(4, distance_level(8, 350.0, 100.0, 1100.0, 0.5));
    /* n = 4, ratio 0.3, exp 2: 4 * 0.91 = 3.64 -> 4; exp 1: 4 * 0.7 = 2.8 -> 3 */
    EXPECT_EQ_INT(4, distance_level(4, 400.0, 100.0, 1100.0, 2.0));
    EXPECT_EQ_INT(3, distance_level(4, 400.0, 100.0, 1100.0, 1.0));
}

TEST(distance_exponent_zero_drops_to_0_beyond_mindist)
{
    EXPECT_EQ_INT(8, distance_level(8, 100.0, 100.0, 1100.0, 0.0));
    EXPECT_EQ_INT(0, distance_level(8, 100.5, 100.0, 1100.0, 0.0));
    EXPECT_EQ_INT(0, distance_level(8, 1000.0, 100.0, 1100.0, 0.0));
}

TEST(distance_tiny_exponent_gives_level_1_inside_range)
{
    /* r^1e-9 is just below 1, so 8 * (1 - r^1e-9) is a sliver above 0: rounds up to 1 */
    EXPECT_EQ_INT(1, distance_level(8, 600.0, 100.0, 1100.0, 1e-9));
    EXPECT_EQ_INT(1, distance_level(8, 200.0, 100.0, 1100.0, 1e-9));
    EXPECT_EQ_INT(0, distance_level(8, 1100.5, 100.0, 1100.0, 1e-9));
}

TEST(distance_huge_exponent_keeps_finest_up_to_maxdist)
{
    EXPECT_EQ_INT(8, distance_level(8, 600.0, 100.0, 1100.0, 1e300));
    EXPECT_EQ_INT(8, distance_level(8, 1099.0, 100.0, 1100.0, 1e300));
    EXPECT_EQ_INT(0, distance_level(8, 1100.5, 100.0, 1100.0, 1e300));
}

TEST(distance_infinite_exponent_is_huge_or_rejected)
{
    /* not listed as invalid; if accepted it must behave as the limit of a huge exponent */
    int k = -1;
    tp_status st = tp_lod_level_distance(8, 600.0, 100.0, 1100.0, INFINITY, &k, NULL);
    EXPECT_TRUE(st == TP_ERR_INVALID_ARG || (st == TP_OK && k == 8));
}

TEST(distance_equal_min_max_is_a_step)
{
    EXPECT_EQ_INT(6, distance_level(6, 500.0, 500.0, 500.0, 1.0));
    EXPECT_EQ_INT(6, distance_level(6, 10.0, 500.0, 500.0, 1.0));
    EXPECT_EQ_INT(0, distance_level(6, nextafter(500.0, 1e9), 500.0, 500.0, 1.0));
    EXPECT_EQ_INT(0, distance_level(6, 501.0, 500.0, 500.0, 2.0));
    EXPECT_EQ_INT(6, distance_level(6, 0.0, 0.0, 0.0, 1.0));
    EXPECT_EQ_INT(0, distance_level(6, 1e-300, 0.0, 0.0, 1.0));
}

TEST(distance_negative_dist_is_clamped_to_zero)
{
    EXPECT_EQ_INT(7, distance_level(7, -5.0, 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(7, distance_level(7, -1e300, 0.0, 0.0, 1.0));
}

TEST(distance_level_0_patch_is_always_0)
{
    EXPECT_EQ_INT(0, distance_level(0, 0.0, 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(0, distance_level(0, 600.0, 100.0, 1100.0, 1.0));
    EXPECT_EQ_INT(0, distance_level(0, 1e9, 100.0, 1100.0, 1.0));
}

/* Parameters that may come from the command line: TP_ERR_INVALID_ARG with a message naming
 * what was expected and what was received, and the level left alone. (n out of 0..TP_MAX_N is a
 * caller bug, asserted, not tested here.) */
TEST(distance_rejects_invalid_parameters)
{
    static const struct {
        double dist, mindist, maxdist, exponent;
        const char* says;
    } bad[] = {
        {10.0, -1.0, 1100.0, 1.0, "-1"},
        {10.0, 100.0, -1.0, 1.0, "-1"},
        {10.0, NAN, 1100.0, 1.0, "nan"},
        {10.0, 100.0, NAN, 1.0, "nan"},
        {NAN, 100.0, 1100.0, 1.0, "NaN"},
        {10.0, 1100.0, 100.0, 1.0, "maxdist >= mindist"},
        {10.0, 100.0, 1100.0, -1.0, "exponent"},
        {10.0, 100.0, 1100.0, NAN, "exponent"},
        {10.0, 100.0, 99.99999999999999, 1.0, "maxdist >= mindist"},
    };
    size_t i;
    for (i = 0; i < sizeof bad / sizeof bad[0]; ++i) {
        int k = 42;
        tp_error err;
        memset(&err, 0, sizeof err);
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_lod_level_distance(8, bad[i].dist, bad[i].mindist, bad[i].maxdist,
                                            bad[i].exponent, &k, &err));
        EXPECT_EQ_INT(42, k);
        EXPECT_CONTAINS(err.message, bad[i].says);
        /* err is optional */
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_lod_level_distance(8, bad[i].dist, bad[i].mindist, bad[i].maxdist,
                                            bad[i].exponent, &k, NULL));
        EXPECT_EQ_INT(42, k);
    }
}

/* A valid call leaves the message alone and writes the level. */
TEST(distance_success_leaves_error_untouched)
{
    int k = -7;
    tp_error err;
    strcpy(err.message, "untouched");
    EXPECT_OK(tp_lod_level_distance(8, 600.0, 100.0, 1100.0, 1.0, &k, &err));
    EXPECT_EQ_INT(4, k);
    EXPECT_CONTAINS(err.message, "untouched");
}

TEST(distance_level_non_increasing_over_sweep)
{
    static const double params[][3] = {{100, 1100, 1}, {0, 5000, 0.3}, {250, 260, 4},
                                       {10, 10, 1},    {1, 1e6, 0.01}, {500, 2000, 7.5},
                                       {0, 1e-3, 1},   {300, 900, 0}};
    size_t p;
    int n;
    for (p = 0; p < sizeof params / sizeof params[0]; ++p) {
        for (n = 0; n <= TP_MAX_N; ++n) {
            int prev = n, i;
            double top = params[p][1] * 1.3 + 1.0;
            for (i = 0; i <= 20000; ++i) {
                double d = top * i / 20000.0;
                int k = distance_level(n, d, params[p][0], params[p][1], params[p][2]);
                if (k < 0 || k > n || k > prev) {
                    ADD_FAILURE("min %g max %g exp %g n %d: level %d at %.9g m after %d",
                                params[p][0], params[p][1], params[p][2], n, k, d, prev);
                    break;
                }
                prev = k;
            }
            if (prev != 0 && n > 0)
                ADD_FAILURE("min %g max %g exp %g n %d: level %d beyond maxdist", params[p][0],
                            params[p][1], params[p][2], n, prev);
        }
    }
}

/* ---------------------------------------------------------------------------------------------
 * tp_lod_params_resolve
 */
static tp_terrain* small_terrain_10m(int patch_size)
{
    static float h[65 * 65];
    double gt[6] = {500000.0, 10.0, 0.0, 4000000.0, 0.0, -10.0};
    tpt_rough_heights(h, 65, 65, 3, 1000.0, 100.0, 1.0, 1);
    return tpt_terrain_create(h, 65, 65, patch_size, TP_FIT_PAD, gt);
}

TEST(params_resolve_fills_defaults)
{
    tp_terrain* t = small_terrain_10m(33);
    tp_lod_params in, out;
    tp_error err;
    memset(&in, 0, sizeof in);
    memset(&out, 0, sizeof out);
    ASSERT_OK(tp_lod_params_resolve(t, &in, &out, &err));
    EXPECT_EQ_INT(TP_LOD_ERROR, out.mode);
    EXPECT_NEAR(320.0, out.mindist_m, 1e-9); /* one patch: 32 cells of 10 m */
    EXPECT_NEAR(24 * 320.0, out.maxdist_m, 1e-9);
    EXPECT_EQ_DBL(1.0, out.exponent);
    EXPECT_EQ_DBL(1.0, out.tau_px);
    tp_terrain_destroy(t);
}

TEST(params_resolve_keeps_given_values)
{
    tp_terrain* t = small_terrain_10m(17);
    tp_lod_params in, out;
    memset(&in, 0, sizeof in);
    in.mode = TP_LOD_DISTANCE;
    in.mindist_m = 50.0;
    in.maxdist_m = 5000.0;
    in.exponent = 2.5;
    in.tau_px = 0.25;
    ASSERT_OK(tp_lod_params_resolve(t, &in, &out, NULL));
    EXPECT_EQ_INT(TP_LOD_DISTANCE, out.mode);
    EXPECT_EQ_DBL(50.0, out.mindist_m);
    EXPECT_EQ_DBL(5000.0, out.maxdist_m);
    EXPECT_EQ_DBL(2.5, out.exponent);
    EXPECT_EQ_DBL(0.25, out.tau_px);
    in.mode = TP_LOD_FULL;
    ASSERT_OK(tp_lod_params_resolve(t, &in, &out, NULL));
    EXPECT_EQ_INT(TP_LOD_FULL, out.mode);
    tp_terrain_destroy(t);
}

static void expect_resolve_rejects(const tp_terrain* t, const tp_lod_params* in, const char* what)
{
    tp_lod_params out, before;
    tp_error err;
    tp_status s;
    memset(&out, 0x5A, sizeof out);
    before = out;
    memset(&err, 0, sizeof err);
    s = tp_lod_params_resolve(t, in, &out, &err);
    if (s != TP_ERR_INVALID_ARG)
        ADD_FAILURE("%s: expected TP_ERR_INVALID_ARG, got %s", what, tp_test_status_name_(s));
    if (err.message[0] == '\0')
        ADD_FAILURE("%s: no error message", what);
    if (memcmp(&out, &before, sizeof out) != 0)
        ADD_FAILURE("%s: out was written on failure", what);
    /* NULL error pointer accepted */
    s = tp_lod_params_resolve(t, in, &out, NULL);
    if (s != TP_ERR_INVALID_ARG)
        ADD_FAILURE("%s (err NULL): got %s", what, tp_test_status_name_(s));
}

TEST(params_resolve_rejects_bad_values_and_leaves_out_alone)
{
    tp_terrain* t = small_terrain_10m(17);
    tp_lod_params in;
#define REJECT(field, value)                                                                       \
    do {                                                                                           \
        memset(&in, 0, sizeof in);                                                                 \
        in.mode = TP_LOD_DISTANCE;                                                                 \
        in.field = (value);                                                                        \
        expect_resolve_rejects(t, &in, #field " = " #value);                                       \
    } while (0)
    REJECT(mindist_m, -1.0);
    REJECT(mindist_m, NAN);
    REJECT(mindist_m, INFINITY);
    REJECT(maxdist_m, -1.0);
    REJECT(maxdist_m, NAN);
    REJECT(maxdist_m, INFINITY);
    REJECT(exponent, -0.5);
    REJECT(exponent, NAN);
    REJECT(exponent, INFINITY);
    REJECT(tau_px, -1.0);
    REJECT(tau_px, NAN);
    REJECT(tau_px, INFINITY);
#undef REJECT
    memset(&in, 0, sizeof in);
    in.mode = TP_LOD_ERROR;
    in.mindist_m = 500.0;
    in.maxdist_m = 100.0;
    expect_resolve_rejects(t, &in, "maxdist < mindist");
    tp_terrain_destroy(t);
}

/* ---------------------------------------------------------------------------------------------
 * An independent pinhole camera and screen-error measurement
 */
typedef struct view {
    double eye[3], fwd[3], right[3], up[3];
    double tan_y, tan_x, f_px, near_m, far_m;
} view;

static void v3_norm(double v[3])
{
    double l = sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
    v[0] /= l;
    v[1] /= l;
    v[2] /= l;
}
static void v3_cross(const double a[3], const double b[3], double out[3])
{
    out[0] = a[1] * b[2] - a[2] * b[1];
    out[1] = a[2] * b[0] - a[0] * b[2];
    out[2] = a[0] * b[1] - a[1] * b[0];
}

static void view_from_camera(const tp_camera* c, view* v)
{
    double fov = c->fov_y_rad > 0 ? c->fov_y_rad : PI / 3.0;
    int w = c->viewport_w_px, h = c->viewport_h_px;
    if (w <= 0 || h <= 0) {
        w = 1280;
        h = 720;
    }
    memcpy(v->eye, c->position, sizeof v->eye);
    memcpy(v->fwd, c->forward, sizeof v->fwd);
    if (v->fwd[0] == 0 && v->fwd[1] == 0 && v->fwd[2] == 0)
        v->fwd[1] = 1.0;
    v3_norm(v->fwd);
    v3_cross(v->fwd, c->up, v->right);
    v3_norm(v->right);
    v3_cross(v->right, v->fwd, v->up);
    v->tan_y = tan(fov / 2);
    v->tan_x = v->tan_y * w / h;
    v->f_px = (h / 2.0) / v->tan_y;
    v->near_m = c->near_m > 0 ? c->near_m : 1.0;
    v->far_m = c->far_m;
}

/* Camera-space coordinates; returns 1 if inside the view volume. */
static int view_project(const view* v, const double p[3], double* sx, double* sy, double* z)
{
    double d[3] = {p[0] - v->eye[0], p[1] - v->eye[1], p[2] - v->eye[2]};
    double X = d[0] * v->right[0] + d[1] * v->right[1] + d[2] * v->right[2];
    double Y = d[0] * v->up[0] + d[1] * v->up[1] + d[2] * v->up[2];
    double Z = d[0] * v->fwd[0] + d[1] * v->fwd[1] + d[2] * v->fwd[2];
    *z = Z;
    if (Z <= 0)
        return 0;
    *sx = v->f_px * X / Z;
    *sy = v->f_px * Y / Z;
    if (Z < v->near_m)
        return 0;
    if (v->far_m > 0 && Z > v->far_m)
        return 0;
    return fabs(X) <= v->tan_x * Z && fabs(Y) <= v->tan_y * Z;
}

typedef struct screen_measure {
    double max_px, sum_sq;
    size_t samples;
    int worst_patch, worst_level, worst_x, worst_y;
    double worst_dz;
} screen_measure;

static void grid_to_world(const tp_terrain_info* ti, double x, double y, double* e, double* n)
{
    *e = ti->geotransform[0] + (x + 0.5) * ti->geotransform[1];
    *n = ti->geotransform[3] + (y + 0.5) * ti->geotransform[5];
}

/* Screen error of the current selection, measured from the drawn triangles of the visible
 * patches. Each sample counted once. */
static void measure_screen(const tp_terrain* t, const tp_selection* s, const tp_camera* cam,
                           screen_measure* m)
{
    tp_terrain_info ti;
    view v;
    int p;
    tp_vertex* verts;
    uint32_t* tri;
    double* drawn;
    unsigned char* seen;
    size_t vcap, tcap;
    tp_terrain_get_info(t, &ti);
    view_from_camera(cam, &v);
    memset(m, 0, sizeof *m);
    m->worst_patch = -1;
    vcap = (size_t)ti.patch_size * ti.patch_size;
    tcap = (size_t)2 << (2 * ti.n);
    verts = (tp_vertex*)malloc(sizeof *verts * vcap);
    tri = (uint32_t*)malloc(sizeof *tri * 3 * tcap);
    drawn = (double*)malloc(sizeof *drawn * vcap);
    seen = (unsigned char*)calloc((size_t)ti.width * ti.height, 1);
    ASSERT_TRUE(verts && tri && drawn && seen);
    for (p = 0; p < ti.patch_count; ++p) {
        int nb[4], k, x0, y0, x, y;
        size_t tc;
        if (!tp_selection_visible(s, p))
            continue;
        k = tp_selection_level(s, p);
        tp_selection_neighbor_levels(s, p, nb);
        x0 = (p % ti.patch_cols) << ti.n;
        y0 = (p / ti.patch_cols) << ti.n;
        tc = tpt_patch_geometry(t, p, k, nb, verts, vcap, tri, tcap);
        tpt_patch_surface(verts, tri, tc, x0, y0, ti.patch_size, drawn, NULL);
        for (y = 0; y < ti.patch_size; ++y) {
            for (x = 0; x < ti.patch_size; ++x) {
                int gx = x0 + x, gy = y0 + y;
                double d = drawn[y * ti.patch_size + x], hs, ps[3], pd[3], sx, sy, dx, dy, zs, zd,
                       px;
                size_t at = (size_t)gy * ti.width + gx;
                if (seen[at] || isnan(d))
                    continue;
                hs = tp_terrain_sample(t, gx, gy);
                if (isnan(hs))
                    continue;
                grid_to_world(&ti, gx, gy, &ps[0], &ps[1]);
                pd[0] = ps[0];
                pd[1] = ps[1];
                ps[2] = hs;
                pd[2] = d;
                if (!view_project(&v, ps, &sx, &sy, &zs))
                    continue;
                seen[at] = 1;
                view_project(&v, pd, &dx, &dy, &zd);
                px = zd > 0 ? hypot(sx - dx, sy - dy) : INFINITY;
                m->samples++;
                m->sum_sq += px * px;
                if (px > m->max_px) {
                    m->max_px = px;
                    m->worst_patch = p;
                    m->worst_level = k;
                    m->worst_x = gx;
                    m->worst_y = gy;
                    m->worst_dz = d - hs;
                }
            }
        }
    }
    free(verts);
    free(tri);
    free(drawn);
    free(seen);
}

/* ---------------------------------------------------------------------------------------------
 * Cameras
 */
static double ground_at(const tp_terrain* t, double e, double n)
{
    double x, y, h;
    tp_terrain_info ti;
    tp_terrain_get_info(t, &ti);
    tp_terrain_world_to_grid(t, e, n, &x, &y);
    h = tp_terrain_height_at(t, x, y);
    return isnan(h) ? ti.max_height_m : h;
}

/* style 0: anywhere, looking a little down; 1: low and steep, the terrain fills every corner
 * of the view; 2: low, looking at the horizon (terrain in the bottom corners); 3: other
 * viewports and fields of view. */
static tp_camera make_camera(const tp_terrain* t, tp_rng* r, int style)
{
    tp_terrain_info ti;
    tp_camera c;
    double e0, n0, e1, n1, yaw, pitch, agl;
    tp_terrain_get_info(t, &ti);
    memset(&c, 0, sizeof c);
    grid_to_world(&ti, 0, 0, &e0, &n0);
    grid_to_world(&ti, ti.src_width - 1, ti.src_height - 1, &e1, &n1);
    c.position[0] = tp_rng_range(r, fmin(e0, e1), fmax(e0, e1));
    c.position[1] = tp_rng_range(r, fmin(n0, n1), fmax(n0, n1));
    yaw = tp_rng_range(r, 0, 2 * PI);
    switch (style) {
    case 0:
        agl = exp(tp_rng_range(r, log(30.0), log(4000.0)));
        pitch = tp_rng_range(r, -50.0, -3.0);
        break;
    case 1:
        agl = tp_rng_range(r, 40.0, 600.0);
        pitch = tp_rng_range(r, -80.0, -45.0);
        break;
    case 2:
        agl = tp_rng_range(r, 3.0, 120.0);
        pitch = tp_rng_range(r, -6.0, 4.0);
        break;
    default: {
        static const int vp[4][2] = {{1920, 1080}, {800, 800}, {2400, 600}, {640, 480}};
        int i = tp_rng_int(r, 0, 3);
        c.viewport_w_px = vp[i][0];
        c.viewport_h_px = vp[i][1];
        c.fov_y_rad = tp_rng_range(r, 20.0, 100.0) * PI / 180.0;
        agl = exp(tp_rng_range(r, log(20.0), log(2000.0)));
        pitch = tp_rng_range(r, -70.0, -5.0);
        c.near_m = tp_rng_int(r, 0, 1) ? 0.5 : 0.0;
        break;
    }
    }
    c.position[2] = ground_at(t, c.position[0], c.position[1]) + agl;
    pitch *= PI / 180.0;
    c.forward[0] = cos(pitch) * sin(yaw);
    c.forward[1] = cos(pitch) * cos(yaw);
    c.forward[2] = sin(pitch);
    c.up[2] = 1.0;
    return c;
}

static void update(tp_selection* s, const tp_camera* cam, tp_lod_mode mode, double tau)
{
    tp_lod_params lp;
    tp_error err;
    tp_status st;
    memset(&lp, 0, sizeof lp);
    lp.mode = mode;
    lp.tau_px = tau;
    st = tp_selection_update(s, cam, &lp, &err);
    if (st != TP_OK)
        FAIL("tp_selection_update: %s: %s", tp_test_status_name_(st), err.message);
}

/* For many cameras and tau in {0.5, 1, 4}: the drawn surface never strays more than tau
 * pixels from any visible sample, by both measurements. */
static void error_mode_within_tau(const tp_terrain* t, const char* what, int cameras, uint64_t seed)
{
    static const double taus[3] = {0.5, 1.0, 4.0};
    tp_selection* s = NULL;
    tp_error err;
    tp_rng rng = tp_rng_seed(seed);
    int i, j;
    double worst_core = 0, worst_mine = 0;
    size_t measured = 0;
    ASSERT_OK(tp_selection_create(t, &s, &err));
    for (i = 0; i < cameras && !tp_test_state_.failures; ++i) {
        tp_camera cam = make_camera(t, &rng, i % 4);
        for (j = 0; j < 3; ++j) {
            double max_px = -1, rms_px = -1;
            size_t samples = 0;
            screen_measure m;
            update(s, &cam, TP_LOD_ERROR, taus[j]);
            ASSERT_OK(tp_selection_measure_screen_error(s, &cam, &max_px, &rms_px, &samples));
            measure_screen(t, s, &cam, &m);
            if (!(max_px <= taus[j] + 1e-9))
                ADD_FAILURE("%s camera %d (style %d, eye %.1f %.1f %.1f, fwd %.3f %.3f %.3f): "
                            "tp_selection_measure_screen_error max %.6f px > tau %.2f",
                            what, i, i % 4, cam.position[0], cam.position[1], cam.position[2],
                            cam.forward[0], cam.forward[1], cam.forward[2], max_px, taus[j]);
            if (!(m.max_px <= taus[j] + 1e-6))
                ADD_FAILURE("%s camera %d (style %d, eye %.1f %.1f %.1f, fwd %.3f %.3f %.3f): "
                            "measured here %.6f px > tau %.2f at sample (%d,%d) of patch %d at "
                            "level %d, drawn - sample = %.3f m",
                            what, i, i % 4, cam.position[0], cam.position[1], cam.position[2],
                            cam.forward[0], cam.forward[1], cam.forward[2], m.max_px, taus[j],
                            m.worst_x, m.worst_y, m.worst_patch, m.worst_level, m.worst_dz);
            if (!(rms_px <= max_px + 1e-12) || rms_px < 0)
                ADD_FAILURE("%s camera %d: rms %.6f px, max %.6f px", what, i, rms_px, max_px);
            if (max_px > worst_core)
                worst_core = max_px;
            if (m.max_px > worst_mine)
                worst_mine = m.max_px;
            measured += m.samples;
            if (tp_test_state_.failures)
                break;
        }
    }
    tp_test_note(
        "%s: %d cameras x 3 tau, %zu samples measured; worst %.4f px (core) %.4f px (here)", what,
        cameras, measured, worst_core, worst_mine);
    tp_selection_destroy(s);
}

static tp_terrain* synthetic_rough_30m(float** heights)
{
    int w = 300, h = 220;
    double gt[6] = {300000.0, 30.0, 0.0, 5000000.0, 0.0, -30.0};
    float* src = (float*)malloc(sizeof(float) * w * h);
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 91, 2000.0, 900.0, 1.0, 0);
    *heights = src;
    return tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, gt);
}

#ifndef TP_TEST_NO_IO
/* Reads a DEM of the repository's data/ folder into a terrain; skips if it is missing. */
static tp_terrain* sample_dem_terrain(const char* file, int patch_size)
{
    char path[1024];
    tp_dem* dem = NULL;
    tp_terrain* t = NULL;
    tp_error err;
    tp_terrain_desc d;
    tp_status s;
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", file);
    s = tp_dem_read(path, &dem, &err);
    if (s != TP_OK)
        FAIL("tp_dem_read(%s): %s", path, err.message);
    d = tp_dem_terrain_desc(dem, patch_size, TP_FIT_PAD);
    s = tp_terrain_create(&d, &t, &err);
    tp_dem_destroy(dem);
    if (s != TP_OK)
        FAIL("tp_terrain_create(%s): %s", path, err.message);
    return t;
}
#endif

TEST(error_mode_within_tau_synthetic)
{
    float* src;
    tp_terrain* t = synthetic_rough_30m(&src);
    error_mode_within_tau(t, "synthetic", 24, 101);
    tp_terrain_destroy(t);
    free(src);
}

TEST(error_mode_within_tau_storml)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    int ps;
    for (ps = 17; ps <= 33 && !tp_test_state_.failures; ps = 2 * ps - 1) {
        tp_terrain* t = sample_dem_terrain("storml_elev_orig.tif", ps);
        char what[32];
        snprintf(what, sizeof what, "storml patch %d", ps);
        error_mode_within_tau(t, what, 40, 200 + ps);
        tp_terrain_destroy(t);
    }
#endif
}

TEST(error_mode_within_tau_mt_hood)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    tp_terrain* t = sample_dem_terrain("lf_elev_220_mt_hood_utm.tif", 33);
    error_mode_within_tau(t, "mt_hood patch 33", 16, 301);
    tp_terrain_destroy(t);
#endif
}

TEST(screen_error_measure_matches_independent_projection)
{
    /* distance mode with coarse levels, so the errors are large, and random cameras */
    float* src;
    tp_terrain* t = synthetic_rough_30m(&src);
    tp_selection* s = NULL;
    tp_error err;
    tp_rng rng = tp_rng_seed(111);
    int i;
    ASSERT_OK(tp_selection_create(t, &s, &err));
    for (i = 0; i < 16; ++i) {
        tp_camera cam = make_camera(t, &rng, i % 4);
        tp_lod_params lp;
        double max_px, rms_px;
        size_t samples;
        screen_measure m;
        memset(&lp, 0, sizeof lp);
        lp.mode = TP_LOD_DISTANCE;
        lp.mindist_m = 100.0;
        lp.maxdist_m = 3000.0;
        ASSERT_OK(tp_selection_update(s, &cam, &lp, &err));
        ASSERT_OK(tp_selection_measure_screen_error(s, &cam, &max_px, &rms_px, &samples));
        measure_screen(t, s, &cam, &m);
        EXPECT_NEAR(m.max_px, max_px, 1e-6 + 1e-6 * m.max_px);
        if (m.samples > 0) {
            /* the sample sets may differ on the view's boundary, by a hair */
            EXPECT_NEAR((double)m.samples, (double)samples, 0.01 * m.samples + 8);
            EXPECT_NEAR(sqrt(m.sum_sq / m.samples), rms_px, 0.02 * rms_px + 1e-6);
        }
    }
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    free(src);
}

/* The per-patch measure agrees with the whole-frame one: the largest of the patches' errors at
 * their current levels is the frame's maximum (up to the samples a patch shares with a
 * neighbour, which only the whole-frame measure deduplicates); level n measures 0 when no
 * neighbour is coarser; in error
 * mode every visible patch measures <= tau at its own level. */
TEST(patch_screen_error_agrees_with_the_frame_measure)
{
    float* src;
    tp_terrain* t = synthetic_rough_30m(&src);
    tp_selection* s = NULL;
    tp_error err;
    tp_rng rng = tp_rng_seed(131);
    tp_terrain_info ti;
    int i, p, coarser = 0;
    tp_terrain_get_info(t, &ti);
    ASSERT_OK(tp_selection_create(t, &s, &err));
    for (i = 0; i < 12; ++i) {
        tp_camera cam = make_camera(t, &rng, i % 4);
        tp_lod_params lp;
        double frame_max, worst = 0;
        memset(&lp, 0, sizeof lp);
        lp.mode = i < 6 ? TP_LOD_DISTANCE : TP_LOD_ERROR;
        lp.mindist_m = 100.0;
        lp.maxdist_m = 3000.0;
        lp.tau_px = 2;
        ASSERT_OK(tp_selection_update(s, &cam, &lp, &err));
        ASSERT_OK(tp_selection_measure_screen_error(s, &cam, &frame_max, NULL, NULL));
        for (p = 0; p < ti.patch_count; ++p) {
            double e;
            if (!tp_selection_visible(s, p))
                continue;
            ASSERT_OK(tp_selection_patch_screen_error(s, &cam, p, tp_selection_level(s, p), &e));
            worst = e > worst ? e : worst;
            {
                /* level n moves nothing unless a neighbour is coarser (stitching) */
                int nb[4], a, stitched = 0;
                tp_selection_neighbor_levels(s, p, nb);
                for (a = 0; a < 4; ++a)
                    stitched |= nb[a] >= 0 && nb[a] < ti.n;
                if (!stitched) {
                    double full = -1;
                    ASSERT_OK(tp_selection_patch_screen_error(s, &cam, p, ti.n, &full));
                    EXPECT_EQ_DBL(0.0, full);
                }
            }
            if (lp.mode == TP_LOD_ERROR) {
                double down = INFINITY;
                EXPECT_LE(e, lp.tau_px);
                if (tp_selection_level(s, p) > 0)
                    ASSERT_OK(tp_selection_patch_screen_error(s, &cam, p,
                                                              tp_selection_level(s, p) - 1, &down));
                if (down <= lp.tau_px)
                    coarser++;
            }
        }
        EXPECT_NEAR(frame_max, worst, 1e-9 + 1e-9 * worst);
    }
    /* the bound is conservative: some patch could go one level down (else this proves little) */
    tp_test_note("%d visible patch-frames could be one level coarser in error mode", coarser);
    EXPECT_GE_INT(coarser, 1);
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    free(src);
}

TEST(full_mode_has_zero_error)
{
    float* src;
    tp_terrain* t = synthetic_rough_30m(&src);
    tp_selection* s = NULL;
    tp_error err;
    tp_rng rng = tp_rng_seed(121);
    tp_terrain_info ti;
    int i, p;
    tp_terrain_get_info(t, &ti);
    ASSERT_OK(tp_selection_create(t, &s, &err));
    for (i = 0; i < 6; ++i) {
        tp_camera cam = make_camera(t, &rng, i % 4);
        double max_px = -1, rms_px = -1;
        size_t samples = 0;
        tp_error_measure em;
        screen_measure m;
        update(s, &cam, TP_LOD_FULL, 0);
        for (p = 0; p < ti.patch_count; ++p)
            EXPECT_EQ_INT(ti.n, tp_selection_level(s, p));
        ASSERT_OK(tp_selection_measure_screen_error(s, &cam, &max_px, &rms_px, &samples));
        EXPECT_EQ_DBL(0.0, max_px);
        EXPECT_EQ_DBL(0.0, rms_px);
        ASSERT_OK(tp_selection_measure_error(s, &em));
        EXPECT_EQ_DBL(0.0, em.max_error_m);
        measure_screen(t, s, &cam, &m);
        EXPECT_EQ_DBL(0.0, m.max_px);
    }
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    free(src);
}

TEST(error_mode_picks_level_0_on_a_plane)
{
    /* every delta is 0 on an exactly representable plane: the coarsest level is good enough */
    static float h[97 * 81];
    int x, y, p, i;
    tp_terrain* t;
    tp_selection* s = NULL;
    tp_error err;
    tp_terrain_info ti;
    tp_rng rng = tp_rng_seed(131);
    double gt[6] = {0.0, 10.0, 0.0, 0.0, 0.0, -10.0};
    for (y = 0; y < 81; ++y)
        for (x = 0; x < 97; ++x)
            h[y * 97 + x] = (float)(200 + 2 * x - 3 * y);
    t = tpt_terrain_create(h, 97, 81, 17, TP_FIT_PAD, gt);
    tp_terrain_get_info(t, &ti);
    ASSERT_OK(tp_selection_create(t, &s, &err));
    for (i = 0; i < 8; ++i) {
        tp_camera cam = make_camera(t, &rng, i % 4);
        update(s, &cam, TP_LOD_ERROR, 0.5);
        for (p = 0; p < ti.patch_count; ++p) {
            tp_patch_info pi;
            tp_patch_get_info(t, p, &pi);
            EXPECT_EQ_INT(pi.complete ? 0 : ti.n, tp_selection_level(s, p));
        }
    }
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
}

TEST(error_mode_coarsens_far_terrain)
{
    /* seen from 5 km up, a 30 m DEM does not need full resolution everywhere at tau = 4 */
    float* src;
    tp_terrain* t = synthetic_rough_30m(&src);
    tp_selection* s = NULL;
    tp_error err;
    tp_terrain_info ti;
    tp_camera cam;
    int p, coarser = 0;
    tp_terrain_get_info(t, &ti);
    memset(&cam, 0, sizeof cam);
    grid_to_world(&ti, ti.src_width / 2.0, ti.src_height / 2.0, &cam.position[0], &cam.position[1]);
    cam.position[2] = ti.max_height_m + 5000.0;
    cam.forward[1] = 0.3;
    cam.forward[2] = -1.0;
    cam.up[2] = 1.0;
    ASSERT_OK(tp_selection_create(t, &s, &err));
    update(s, &cam, TP_LOD_ERROR, 4.0);
    for (p = 0; p < ti.patch_count; ++p)
        coarser += tp_selection_level(s, p) < ti.n;
    EXPECT_GE_INT(coarser, 1);
    tp_test_note("%d of %d patches below level n", coarser, ti.patch_count);
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    free(src);
}

TEST(distance_mode_step_selects_0_or_n)
{
    float* src;
    tp_terrain* t = synthetic_rough_30m(&src);
    tp_selection* s = NULL;
    tp_error err;
    tp_terrain_info ti;
    tp_camera cam;
    tp_lod_params lp;
    int p;
    tp_terrain_get_info(t, &ti);
    memset(&cam, 0, sizeof cam);
    grid_to_world(&ti, 10, 10, &cam.position[0], &cam.position[1]);
    cam.position[2] = ti.max_height_m + 100.0;
    cam.up[2] = 1.0;
    ASSERT_OK(tp_selection_create(t, &s, &err));
    memset(&lp, 0, sizeof lp);
    lp.mode = TP_LOD_DISTANCE;
    lp.mindist_m = lp.maxdist_m = 1e-3; /* every patch is further: level 0 */
    ASSERT_OK(tp_selection_update(s, &cam, &lp, &err));
    for (p = 0; p < ti.patch_count; ++p) {
        tp_patch_info pi;
        tp_patch_get_info(t, p, &pi);
        EXPECT_EQ_INT(pi.complete ? 0 : ti.n, tp_selection_level(s, p));
    }
    lp.mindist_m = lp.maxdist_m = 1e9; /* every patch is nearer: level n */
    ASSERT_OK(tp_selection_update(s, &cam, &lp, &err));
    for (p = 0; p < ti.patch_count; ++p)
        EXPECT_EQ_INT(ti.n, tp_selection_level(s, p));
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    free(src);
}

TEST(update_rejects_invalid_params)
{
    float* src;
    tp_terrain* t = synthetic_rough_30m(&src);
    tp_selection* s = NULL;
    tp_error err;
    tp_camera cam;
    tp_lod_params lp;
    memset(&cam, 0, sizeof cam);
    cam.position[2] = 5000.0;
    cam.up[2] = 1.0;
    ASSERT_OK(tp_selection_create(t, &s, &err));
    memset(&lp, 0, sizeof lp);
    lp.tau_px = -2.0;
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_selection_update(s, &cam, &lp, &err));
    EXPECT_TRUE(err.message[0] != '\0');
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    free(src);
}

#define TESTS(X)                                                                                   \
    X(distance_at_or_below_mindist_is_finest)                                                      \
    X(distance_at_or_beyond_maxdist_is_coarsest)                                                   \
    X(distance_formula_rounds_up)                                                                  \
    X(distance_formula_exponent)                                                                   \
    X(distance_exponent_zero_drops_to_0_beyond_mindist)                                            \
    X(distance_tiny_exponent_gives_level_1_inside_range)                                           \
    X(distance_huge_exponent_keeps_finest_up_to_maxdist)                                           \
    X(distance_infinite_exponent_is_huge_or_rejected)                                              \
    X(distance_equal_min_max_is_a_step)                                                            \
    X(distance_negative_dist_is_clamped_to_zero)                                                   \
    X(distance_level_0_patch_is_always_0)                                                          \
    X(distance_rejects_invalid_parameters)                                                         \
    X(distance_success_leaves_error_untouched)                                                     \
    X(distance_level_non_increasing_over_sweep)                                                    \
    X(params_resolve_fills_defaults)                                                               \
    X(params_resolve_keeps_given_values)                                                           \
    X(params_resolve_rejects_bad_values_and_leaves_out_alone)                                      \
    X(error_mode_within_tau_synthetic)                                                             \
    X(error_mode_within_tau_storml)                                                                \
    X(error_mode_within_tau_mt_hood)                                                               \
    X(screen_error_measure_matches_independent_projection)                                         \
    X(patch_screen_error_agrees_with_the_frame_measure)                                         \
    X(full_mode_has_zero_error)                                                                    \
    X(error_mode_picks_level_0_on_a_plane)                                                         \
    X(error_mode_coarsens_far_terrain)                                                             \
    X(distance_mode_step_selects_0_or_n)                                                           \
    X(update_rejects_invalid_params)
TP_TEST_MAIN(TESTS)
