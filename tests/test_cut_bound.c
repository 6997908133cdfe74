/*
 * test_cut_bound.c - the error bound a cut reports for its drawn nodes (tp_cut_node.bound_px,
 * tp_cut_stats.max_bound_px: the viewer's "error bound max N px") stays finite for a camera on
 * the ground (issue 29, 4.4). A node whose box reaches the near plane had the projection
 * bound's INFINITY (lod.c: a point of the box may lie at any depth down to 0): every full-
 * resolution leaf next to a low eye once heights carry a quantisation error (a warped DEM's
 * float heights stored in 1 m steps), and every coarser ancestor drawn in place of nodes not
 * read yet (a store's first frames in a window). Drawn, such a node is on screen only in front
 * of the near plane and inside the view: its bound covers that, is finite, and the stats say
 * which nodes it concerns (tp_cut_stats.near_plane_nodes).
 */
#include "tp_test.h"

#include "tp_test_hgt.h"

static const double GT[6] = {400000, 90, 0, 4800000, 0, -90}; /* SRTM3 at about 90 m */

/* A 513 x 513 crop of N42E001 with fractional heights (a warped DEM's), stored in 1 m steps:
 * the tree's quantisation error is about half a metre. */
static tp_tree* quantised_tree(void)
{
    const int w = 513, h = 513;
    float* hts = load_hgt(300, 300, w, h);
    if (!hts)
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++)
            if (!isnan(hts[(size_t)y * w + x]))
                hts[(size_t)y * w + x] += 0.37f * (float)((x * 7 + y * 13) % 5) / 4.0f;
    tp_tree* t = NULL;
    tp_error e = {{0}};
    tp_status st = tp_tree_create_from_grid(hts, (size_t)w * h, w, h, GT, 17, 1.0, &t, &e);
    free(hts);
    if (st != TP_OK)
        FAIL("tree: %s", e.message);
    tp_tree_info info;
    tp_tree_get_info(t, &info);
    ASSERT_GT(info.quant_max_error_m, 0.1);
    return t;
}

/* A camera 2 m over grid point (x, y) (the viewer's terrain following keeps it there). */
static void low_camera(const tp_tree* t, int x, int y, double yaw, double pitch, tp_camera* cam)
{
    double p[3] = {GT[0] + (x + 0.5) * GT[1], GT[3] + (y + 0.5) * GT[5],
                   tp_tree_sample(t, x, y) + 2.0};
    ASSERT_TRUE(!isnan(p[2]));
    tp_camera_from_pose(p, yaw, pitch, 60, 1280, 720, cam);
}

/* The bound of every drawn node is finite; the nodes at the near plane are counted; returns the
 * stats. */
static tp_cut_stats check_finite(const tp_cut* cut, const char* what)
{
    tp_cut_stats st;
    tp_cut_get_stats(cut, &st);
    size_t count;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    int near = 0;
    for (size_t i = 0; i < count; i++) {
        if (!isfinite(nodes[i].bound_px))
            FAIL("%s: drawn node %lld (level %d%s) has bound %g px", what, (long long)nodes[i].node,
                 nodes[i].level, nodes[i].substituted ? ", substituted" : "",
                 (double)nodes[i].bound_px);
        near += nodes[i].near_plane;
    }
    EXPECT_TRUE(isfinite(st.max_bound_px));
    EXPECT_TRUE(isfinite(st.substitution_bound_px));
    EXPECT_EQ_INT(near, st.near_plane_nodes);
    printf("%s: %d drawn, %d substituted, %d at the near plane, bound max %.1f px "
           "(substituted %.1f px)\n",
           what, st.drawn, st.substituted, st.near_plane_nodes, st.max_bound_px,
           st.substitution_bound_px);
    return st;
}

/* Every node resident: the leaves around the eye are drawn at full resolution, their bound is
 * the quantisation error seen from under 2 m: finite, more than tau (not hidden), and not
 * below what is measured on screen. */
TEST(low_camera_full_resolution_bound_is_finite)
{
    tp_tree* t = quantised_tree();
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    const double views[][4] = {
        {256, 256, 0, -5}, {100, 400, 90, 0}, {400, 120, 200, -20}, {256, 256, 45, -60}};
    for (size_t v = 0; v < sizeof views / sizeof views[0]; v++) {
        tp_camera cam;
        low_camera(t, (int)views[v][0], (int)views[v][1], views[v][2], views[v][3], &cam);
        tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        tp_cut_stats st = check_finite(cut, "resident");
        EXPECT_EQ_INT(0, st.substituted);
        EXPECT_GT(st.near_plane_nodes, 0);
        EXPECT_GT(st.max_bound_px, lp.tau_px); /* half a metre under the eye is many pixels */
        /* about f * d / near at most: 624 px per metre at 1 m, d under a metre */
        EXPECT_LE(st.max_bound_px, 624.0 * 4);
        double measured = -1;
        ASSERT_OK(tp_cut_measure_screen_error(cut, &cam, &measured, NULL, NULL, NULL));
        EXPECT_LE(measured, st.max_bound_px);
    }
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
}

/* A store's first frames: only the roots are resident, so coarse roots are drawn in place of
 * the nodes the eye needs (substituted), with the eye inside their boxes. Their bound is large
 * (metres of error under the eye) and finite; once the nodes arrive it shrinks. */
TEST(substituted_nodes_at_the_eye_have_a_finite_bound)
{
    tp_tree* t = quantised_tree();
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    const uint16_t** saved = calloc((size_t)g->node_count, sizeof *saved);
    for (int64_t id = 0; id < g->node_count; id++)
        if (tp_tree_node_parent(g, id) >= 0) {
            saved[id] = tp_tree_samples(t, id);
            tp_tree_detach(t, id);
        }
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    tp_camera cam;
    low_camera(t, 256, 256, 30, -10, &cam);
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
    tp_cut_stats first = check_finite(cut, "roots only");
    EXPECT_GT(first.substituted, 0);
    EXPECT_GT(first.near_plane_nodes, 0);
    EXPECT_GT(first.substitution_bound_px, 10 * lp.tau_px); /* a real problem, not hidden */
    for (int64_t id = 0; id < g->node_count; id++)
        if (saved[id])
            tp_tree_attach(t, id, saved[id]);
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
    tp_cut_stats all = check_finite(cut, "all resident");
    EXPECT_EQ_INT(0, all.substituted);
    EXPECT_LT(all.max_bound_px, first.max_bound_px);
    free(saved);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
}

/* A camera high above the ground: no box reaches the near plane, nothing is counted, tau holds
 * (the bound away from the eye is the one the selection uses, unchanged). */
TEST(high_camera_counts_no_near_plane_nodes)
{
    tp_tree* t = quantised_tree();
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    tp_camera cam;
    low_camera(t, 256, 256, 20, -30, &cam);
    cam.position[2] += 3000;
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
    tp_cut_stats st = check_finite(cut, "high");
    EXPECT_EQ_INT(0, st.near_plane_nodes);
    EXPECT_LE(st.max_bound_px, lp.tau_px + 1e-6);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
}

#define TESTS(X)                                                                                   \
    X(low_camera_full_resolution_bound_is_finite)                                                  \
    X(substituted_nodes_at_the_eye_have_a_finite_bound)                                            \
    X(high_camera_counts_no_near_plane_nodes)
TP_TEST_MAIN(TESTS)
