/* test_cut_reuse.c - tp_cut_holds_for from the figures tp_cut_prepare_reuse keeps (cut_reuse.c):
 * on real relief (N42E001), for a cut selected from one camera and asked about another (the
 * same camera, a frame of a flight, pure turns of up to 180 degrees, pure moves, jumps), the
 * answer is the one the test from scratch gives, every time; a frame's move settles nearly
 * every node without projecting it; the figures are dropped by the next update.
 */
#include "tp_core.h"
#include "tp_test.h"

#include <math.h>
#include <stdint.h>
#include <stdlib.h>

#include "tp_test_hgt.h"

static const double GT[6] = {400000, 90, 0, 4800000, 0, -90}; /* SRTM3 at about 90 m */

static uint64_t rng = 0x2545F4914F6CDD1Dull;
static double rnd(void)
{
    rng ^= rng << 13;
    rng ^= rng >> 7;
    rng ^= rng << 17;
    return (double)(rng >> 11) / 9007199254740992.0;
}

static tp_tree* tree_of(int x0, int y0, int w, int h)
{
    float* hts = load_hgt(x0, y0, w, h);
    if (!hts)
        return NULL;
    tp_tree* t = NULL;
    ASSERT_OK(tp_tree_create_from_grid(hts, (size_t)w * h, w, h, GT, 33, 0, &t, NULL));
    free(hts);
    return t;
}

/* A camera `above` metres over the ground at grid (x, y). */
static void camera_at(const tp_tree* t, double x, double y, double above, double yaw, double pitch,
                      tp_camera* cam)
{
    double z = tp_tree_sample(t, (int)x, (int)y);
    double pos[3] = {GT[0] + (x + 0.5) * GT[1], GT[3] + (y + 0.5) * GT[5],
                     (isnan(z) ? 500 : z) + above};
    tp_camera_from_pose(pos, yaw, pitch, 60, 1280, 720, cam);
}

enum { SAME, FRAME, TURN, MOVE, JUMP, KINDS };
static const char* const KIND_NAME[KINDS] = {"same", "frame", "turn", "move", "jump"};

/* Camera b from a: the kind of change k. */
static void moved(const tp_tree* t, const tp_camera* a, double x, double y, double above,
                  double yaw, double pitch, int k, tp_camera* b)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    double pos[3] = {a->position[0], a->position[1], a->position[2]};
    double dir = yaw * 3.14159265358979323846 / 180, step = 0, turn = 0, tilt = 0;
    switch (k) {
    case SAME:
        *b = *a;
        return;
    case FRAME: /* one frame of a flight: up to 10 m and 1.5 degrees */
        step = rnd() * 10, turn = (rnd() - 0.5) * 3, tilt = turn / 3;
        break;
    case TURN: /* standing still, turning by up to 180 degrees (a fast turn's frames and more) */
        turn = (rnd() - 0.5) * 360 * rnd() * rnd(), tilt = (rnd() - 0.5) * 6;
        break;
    case MOVE: /* straight on, up to 400 m, the view unchanged */
        step = rnd() * rnd() * 400;
        break;
    default: /* as Home: somewhere else */
        camera_at(t, fmod(x + 300, g->src_width - 1), y, above, yaw + 120, pitch, b);
        return;
    }
    pos[0] += step * sin(dir), pos[1] += step * cos(dir);
    tp_camera_from_pose(pos, yaw + turn, pitch + tilt, 60, 1280, 720, b);
}

/* For random pairs of cameras, the answer from the kept figures against the one from scratch
 * (tp_cut_holds_for with max_bound_px asks from scratch). */
static void answers_agree(double vertical_scale)
{
    tp_tree* t = tree_of(250, 300, 700, 420);
    if (!t)
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    ASSERT_OK(tp_cut_set_vertical_scale(cut, vertical_scale));
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    int yes[KINDS] = {0}, no[KINDS] = {0};
    double settled[KINDS] = {0}, asked[KINDS] = {0};
    for (int it = 0; it < 400; it++) {
        double x = rnd() * (g->src_width - 1), y = rnd() * (g->src_height - 1);
        double above = 30 + rnd() * rnd() * 3000, yaw = rnd() * 360, pitch = -3 - rnd() * 70;
        int k = it % KINDS;
        tp_camera a, b;
        camera_at(t, x, y, above, yaw, pitch, &a);
        moved(t, &a, x, y, above, yaw, pitch, k, &b);
        ASSERT_OK(tp_cut_update(cut, &a, &lp, NULL));
        double bound;
        size_t scratch_exact, scratch;
        int exact = tp_cut_holds_for(cut, &b, &bound, &scratch_exact);
        EXPECT_EQ_INT(1, tp_cut_prepare_reuse(cut));
        int kept = tp_cut_holds_for(cut, &b, NULL, &scratch);
        if (exact != kept)
            printf("%s: from scratch %d, from the kept figures %d\n", KIND_NAME[k], exact, kept);
        EXPECT_EQ_INT(exact, kept);
        yes[k] += exact, no[k] += !exact;
        if (exact) { /* a refusal stops at the first node that fails */
            settled[k] += (double)(scratch_exact - scratch);
            asked[k] += (double)scratch_exact;
        }
    }
    for (int k = 0; k < KINDS; k++)
        printf("scale %.0f, %-5s: held %3d, refused %3d, nodes settled without a projection "
               "%.1f%%\n",
               vertical_scale, KIND_NAME[k], yes[k], no[k],
               asked[k] > 0 ? 100 * settled[k] / asked[k] : 0.0);
    /* the same camera: nothing to project */
    EXPECT_EQ_INT(0, no[SAME]);
    EXPECT_TRUE(settled[SAME] >= 0.999 * asked[SAME]);
    /* a frame's move: nearly nothing to project */
    EXPECT_TRUE(settled[FRAME] >= 0.95 * asked[FRAME]);
    /* the comparison proves something only when both answers happen, for each kind of move */
    EXPECT_GT(yes[FRAME] + yes[TURN] + yes[MOVE], 60);
    EXPECT_GT(no[FRAME], 5);
    EXPECT_GT(no[TURN], 10);
    EXPECT_GT(no[MOVE], 1);
    EXPECT_GT(no[JUMP], 40);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
}

TEST(kept_figures_answer_as_the_test_from_scratch)
{
    answers_agree(1);
}

TEST(kept_figures_answer_as_the_test_from_scratch_exaggerated)
{
    answers_agree(3);
}

/* tp_cut_keep_for: the answer from scratch for another camera b, and the figures kept from b,
 * so that the test for a camera c near b agrees with the one from scratch and b itself needs no
 * projection. */
TEST(figures_kept_for_another_camera_answer_as_the_test_from_scratch)
{
    tp_tree* t = tree_of(250, 300, 700, 420);
    if (!t)
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    int held = 0, refused = 0, near_held = 0;
    for (int it = 0; it < 300; it++) {
        double x = rnd() * (g->src_width - 1), y = rnd() * (g->src_height - 1);
        double above = 30 + rnd() * rnd() * 3000, yaw = rnd() * 360, pitch = -3 - rnd() * 70;
        tp_camera a, b, c;
        camera_at(t, x, y, above, yaw, pitch, &a);
        moved(t, &a, x, y, above, yaw, pitch, 1 + it % (KINDS - 1), &b);
        moved(t, &b, x, y, above, yaw, pitch, FRAME, &c);
        ASSERT_OK(tp_cut_update(cut, &a, &lp, NULL));
        EXPECT_EQ_INT(1, tp_cut_prepare_reuse(cut));
        double bound;
        int exact_b = tp_cut_holds_for(cut, &b, &bound, NULL);
        EXPECT_EQ_INT(exact_b, tp_cut_keep_for(cut, &b));
        held += exact_b, refused += !exact_b;
        size_t scratch;
        int at_b = tp_cut_holds_for(cut, &b, NULL, &scratch);
        EXPECT_EQ_INT(exact_b, at_b);
        if (exact_b) /* the figures are b's own: every node settled */
            EXPECT_EQ_INT(0, (int)scratch);
        int exact_c = tp_cut_holds_for(cut, &c, &bound, NULL);
        EXPECT_EQ_INT(exact_c, tp_cut_holds_for(cut, &c, NULL, &scratch));
        near_held += exact_c;
    }
    printf("kept for another camera: held %d, refused %d; a frame further: held %d\n", held,
           refused, near_held);
    EXPECT_GT(held, 50);
    EXPECT_GT(refused, 50);
    EXPECT_GT(near_held, 30);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
}

/* The next update drops the figures (they describe the cut before it): from scratch again. */
TEST(the_next_update_drops_the_kept_figures)
{
    tp_tree* t = tree_of(0, 0, 1201, 1201);
    if (!t)
        SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
    tp_cut* cut;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    tp_camera a, b;
    camera_at(t, 600, 600, 800, 30, -20, &a);
    camera_at(t, 610, 600, 800, 32, -20, &b);
    ASSERT_OK(tp_cut_update(cut, &a, &lp, NULL));
    size_t all, scratch;
    tp_cut_holds_for(cut, &a, &(double){0}, &all);
    EXPECT_EQ_INT(1, tp_cut_prepare_reuse(cut));
    tp_cut_holds_for(cut, &a, NULL, &scratch);
    EXPECT_EQ_INT(0, (int)scratch);
    ASSERT_OK(tp_cut_update(cut, &b, &lp, NULL));
    tp_cut_holds_for(cut, &b, NULL, &scratch);
    tp_cut_holds_for(cut, &b, &(double){0}, &all);
    EXPECT_EQ_INT((int)all, (int)scratch);
    EXPECT_GT((int)all, 100);
    /* an installed cut keeps nothing */
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int64_t* roots = malloc((size_t)g->root_count * sizeof *roots);
    int* levels = calloc((size_t)g->root_count, sizeof *levels);
    ASSERT_TRUE(roots && levels);
    tp_tree_roots(g, roots, (size_t)g->root_count);
    ASSERT_OK(tp_cut_set_nodes(cut, roots, levels, (size_t)g->root_count, NULL));
    EXPECT_EQ_INT(0, tp_cut_prepare_reuse(cut));
    EXPECT_TRUE(tp_cut_holds_for(cut, &b, NULL, &scratch));
    free(roots);
    free(levels);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
}

#define TESTS(X)                                                                                   \
    X(kept_figures_answer_as_the_test_from_scratch)                                                \
    X(kept_figures_answer_as_the_test_from_scratch_exaggerated)                                    \
    X(figures_kept_for_another_camera_answer_as_the_test_from_scratch)                             \
    X(the_next_update_drops_the_kept_figures)
TP_TEST_MAIN(TESTS)
