/* test_spheres.c - the sphere tree (cut_spheres.c, tp_lod_params.sphere_tree): on real relief
 * (N42E001, voids kept: incomplete nodes too) and along flights (standing still, slow and fast,
 * jumps, turning, climbing, parameters changed on the way, nodes streamed out and in), the cut
 * selected through the sphere tree is the plain distance-mode traversal's at every frame:
 * same nodes in the same order, same levels, neighbour levels, substitution and requests. And
 * it re-decides fewer nodes: none standing still.
 */
#include "tp_test.h"

#include <stdint.h>

#include "tp_test_hgt.h"

#define LOAD_OR_SKIP(var, x0, y0, w, h)                                                            \
    float* var = load_hgt(x0, y0, w, h);                                                           \
    if (!var)                                                                                      \
    SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)")

static const double GT[6] = {400000, 90, 0, 4800000, 0, -90}; /* SRTM3 at about 90 m */

static uint64_t rng_state = 0x9e3779b97f4a7c15ull;
static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

/* Eye at grid (x, y), `above` m over the surface there (or over 0 in a void). */
static void camera_at(const tp_tree* t, double x, double y, double above, double yaw, double pitch,
                      tp_camera* cam)
{
    double z = tp_tree_sample(t, (int)x, (int)y);
    double pos[3] = {GT[0] + (x + 0.5) * GT[1], GT[3] + (y + 0.5) * GT[5],
                     (isnan(z) ? 0 : z) + above};
    tp_camera_from_pose(pos, yaw, pitch, 60, 1280, 720, cam);
}

/* Whether the two cuts' outputs and requests are the same, element by element. */
static int same_cut(const tp_cut* a, const tp_cut* b)
{
    size_t na, nb, ra, rb;
    const tp_cut_node* oa = tp_cut_nodes(a, &na);
    const tp_cut_node* ob = tp_cut_nodes(b, &nb);
    const int64_t* qa = tp_cut_requests(a, &ra);
    const int64_t* qb = tp_cut_requests(b, &rb);
    if (na != nb || ra != rb)
        return 0;
    for (size_t i = 0; i < na; i++)
        if (oa[i].node != ob[i].node || oa[i].level != ob[i].level ||
            memcmp(oa[i].nb, ob[i].nb, sizeof oa[i].nb) || oa[i].substituted != ob[i].substituted)
            return 0;
    for (size_t i = 0; i < ra; i++)
        if (qa[i] != qb[i])
            return 0;
    return 1;
}

typedef struct flight {
    double x, y, above, yaw, pitch;
} flight;

/* One frame of both cuts; counts the frames that differ and the decisions each made. */
static void frame(tp_tree* t, tp_cut* plain, tp_cut* sph, const flight* f, tp_lod_params lp,
                  int* differ, long* dec_plain, long* dec_sph, int* drawn)
{
    tp_camera cam;
    camera_at(t, f->x, f->y, f->above, f->yaw, f->pitch, &cam);
    lp.sphere_tree = 0;
    ASSERT_OK(tp_cut_update(plain, &cam, &lp, NULL));
    lp.sphere_tree = 1;
    ASSERT_OK(tp_cut_update(sph, &cam, &lp, NULL));
    *differ += !same_cut(plain, sph);
    tp_cut_stats sp, ss;
    tp_cut_get_stats(plain, &sp);
    tp_cut_get_stats(sph, &ss);
    *dec_plain += sp.decisions;
    *dec_sph += ss.decisions;
    *drawn += sp.drawn;
    EXPECT_EQ_INT(sp.visited, ss.visited);
}

TEST(flights_select_as_the_plain_traversal)
{
    LOAD_OR_SKIP(h, 0, 0, 1201, 1201);
    tp_tree* t = NULL;
    ASSERT_OK(tp_tree_create_from_grid(h, (size_t)1201 * 1201, 1201, 1201, GT, 17, 0, &t, NULL));
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_cut *plain, *sph;
    ASSERT_OK(tp_cut_create(t, &plain, NULL));
    ASSERT_OK(tp_cut_create(t, &sph, NULL));
    int differ = 0, frames = 0, drawn = 0;
    long dec_plain = 0, dec_sph = 0;
    for (int run = 0; run < 6; run++) {
        tp_lod_params lp = {.mode = TP_LOD_DISTANCE};
        if (run == 1) /* short distances: far terrain in big nodes */
            lp.mindist_m = 500, lp.maxdist_m = 4000;
        if (run == 2)
            lp.mindist_m = 0, lp.maxdist_m = 9000, lp.exponent = 2.5;
        if (run == 3)
            lp.hole_px = 40; /* incomplete nodes coarser */
        if (run >= 4) {      /* exaggerated, then back: the spheres are rebuilt */
            ASSERT_OK(tp_cut_set_vertical_scale(plain, run == 4 ? 3 : 1));
            ASSERT_OK(tp_cut_set_vertical_scale(sph, run == 4 ? 3 : 1));
        }
        flight f = {200 + rnd() * 800, 200 + rnd() * 800, 50 + rnd() * 500, rnd() * 360, -15};
        /* nodes streamed out for half of the last run: substitution and requests */
        const uint16_t* saved[64];
        int64_t gone[64];
        int ngone = 0;
        for (int step = 0; step < 400; step++, frames++) {
            int phase = step / 50;
            if (run == 5 && step == 100)
                for (; ngone < 64; ngone++) {
                    int64_t id = g->first_node[0] +
                                 (int64_t)(rnd() * (double)(g->node_count - g->first_node[0]));
                    gone[ngone] = id;
                    saved[ngone] = tp_tree_samples(t, id);
                    tp_tree_detach(t, id);
                }
            if (run == 5 && step == 300)
                for (int k = 0; k < ngone; k++)
                    if (!tp_tree_samples(t, gone[k]))
                        tp_tree_attach(t, gone[k], saved[k]);
            switch (phase) {
            case 0: break;                           /* standing still */
            case 1: f.x += 0.02, f.y += 0.01; break; /* slow: 2 m a frame */
            case 2: f.x += 3, f.above += 2; break;   /* fast: 270 m a frame, climbing */
            case 3: f.yaw += 7; break;               /* turning on the spot */
            case 4:                                  /* jumps */
                if (step % 5 == 0)
                    f.x = rnd() * 1200, f.y = rnd() * 1200, f.above = 20 + rnd() * 3000;
                break;
            case 5: f.y -= 1, f.pitch = -5 - (step % 60); break; /* nodding */
            case 6: f.above *= 0.97; break;                      /* diving */
            default: f.x += (rnd() - 0.5) * 4, f.y += (rnd() - 0.5) * 4; break;
            }
            f.x = f.x < 0 ? 0 : f.x > 1200 ? 1200 : f.x;
            f.y = f.y < 0 ? 0 : f.y > 1200 ? 1200 : f.y;
            frame(t, plain, sph, &f, lp, &differ, &dec_plain, &dec_sph, &drawn);
        }
    }
    printf("%d frames, %d differ; decisions: plain %ld, spheres %ld; mean drawn %.0f\n", frames,
           differ, dec_plain, dec_sph, (double)drawn / frames);
    EXPECT_EQ_INT(0, differ);
    EXPECT_GT((double)drawn / frames, 50); /* real cuts, not empty ones */
    EXPECT_LT((double)dec_sph, 0.5 * (double)dec_plain);
    tp_cut_destroy(plain);
    tp_cut_destroy(sph);
    tp_tree_destroy(t);
    free(h);
}

TEST(standing_still_decides_nothing_again)
{
    LOAD_OR_SKIP(h, 0, 0, 1201, 1201);
    tp_tree* t = NULL;
    ASSERT_OK(tp_tree_create_from_grid(h, (size_t)1201 * 1201, 1201, 1201, GT, 17, 0, &t, NULL));
    tp_cut *plain, *sph;
    ASSERT_OK(tp_cut_create(t, &plain, NULL));
    ASSERT_OK(tp_cut_create(t, &sph, NULL));
    tp_lod_params lp = {.mode = TP_LOD_DISTANCE};
    int differ = 0, drawn = 0;
    long dec_plain = 0, dec_sph = 0, first_sph = 0, slow_plain = 0, slow_sph = 0;
    /* not on a post: at (600, 600) the eye is exactly 18000 m (200 posts) from a box whose
     * decision changes there, so that node would be checked again every frame */
    flight f = {600.37, 600.71, 120, 30, -10};
    for (int step = 0; step < 20; step++) {
        long before = dec_sph;
        f.yaw += step >= 10 ? 10 : 0; /* turning on the spot: still nothing to decide */
        frame(t, plain, sph, &f, lp, &differ, &dec_plain, &dec_sph, &drawn);
        if (step == 0)
            first_sph = dec_sph - before;
    }
    tp_cut_stats ss;
    tp_cut_get_stats(sph, &ss);
    printf("standing: first frame %ld decisions (the whole map's distance cut, %d entries), then "
           "%ld over 19 frames (plain: %ld a frame); sphere-tree entries visited in the last "
           "frame: %d\n",
           first_sph, ss.sphere_nodes, dec_sph - first_sph, dec_plain / 20, ss.sphere_visited);
    EXPECT_EQ_INT(0, (int)(dec_sph - first_sph));
    EXPECT_GT((double)dec_plain / 20, 100);
    EXPECT_EQ_INT(0, ss.sphere_visited);
    /* slow: walking pace, 1.5 m a frame */
    for (int step = 0; step < 100; step++) {
        long bp = dec_plain, bs = dec_sph;
        f.x += 1.5 / 90;
        frame(t, plain, sph, &f, lp, &differ, &dec_plain, &dec_sph, &drawn);
        slow_plain += dec_plain - bp, slow_sph += dec_sph - bs;
    }
    printf("slow: %ld decisions by the plain traversal, %ld through the spheres\n", slow_plain,
           slow_sph);
    EXPECT_EQ_INT(0, differ);
    EXPECT_LT((double)slow_sph, 0.05 * (double)slow_plain);
    tp_cut_destroy(plain);
    tp_cut_destroy(sph);
    tp_tree_destroy(t);
    free(h);
}

/* The prefetch's selection (tp_cut_update_requests) through the spheres asks for the same nodes
 * in the same order, with a quarter of the leaves and of their parents not resident. */
TEST(requests_only_updates_ask_as_the_plain_traversal)
{
    LOAD_OR_SKIP(h, 0, 0, 1201, 1201);
    tp_tree* t = NULL;
    ASSERT_OK(tp_tree_create_from_grid(h, (size_t)1201 * 1201, 1201, 1201, GT, 17, 0, &t, NULL));
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    /* leaves and scale-1 nodes whose id is 1 mod 4 leave */
    ASSERT_GE_INT(g->scales, 3);
    int64_t count = g->node_count - g->first_node[1];
    const uint16_t** saved = calloc((size_t)count, sizeof *saved);
    ASSERT_TRUE(saved != NULL);
    for (int64_t id = g->first_node[1]; id < g->node_count; id++)
        if (id % 4 == 1) {
            saved[id - g->first_node[1]] = tp_tree_samples(t, id);
            tp_tree_detach(t, id);
        }
    tp_cut *plain, *sph;
    ASSERT_OK(tp_cut_create(t, &plain, NULL));
    ASSERT_OK(tp_cut_create(t, &sph, NULL));
    int differ = 0, with_requests = 0;
    flight f = {300.3, 700.6, 80, 60, -12};
    for (int step = 0; step < 200; step++) {
        f.x += step < 100 ? 0.4 : 0, f.yaw += step >= 100 ? 4 : 0;
        tp_camera cam;
        camera_at(t, f.x, f.y, f.above, f.yaw, f.pitch, &cam);
        tp_lod_params lp = {.mode = TP_LOD_DISTANCE};
        ASSERT_OK(tp_cut_update_requests(plain, &cam, &lp, NULL));
        lp.sphere_tree = 1;
        ASSERT_OK(tp_cut_update_requests(sph, &cam, &lp, NULL));
        size_t na, nb, da, db;
        const int64_t* ra = tp_cut_requests(plain, &na);
        const int64_t* rb = tp_cut_requests(sph, &nb);
        tp_cut_nodes(plain, &da);
        tp_cut_nodes(sph, &db);
        differ += na != nb || (na && memcmp(ra, rb, na * sizeof *ra)) || da || db;
        with_requests += na > 0;
    }
    printf("200 frames, %d with requests, %d differ\n", with_requests, differ);
    EXPECT_EQ_INT(0, differ);
    EXPECT_GE_INT(with_requests, 150);
    tp_cut_destroy(plain);
    tp_cut_destroy(sph);
    for (int64_t id = g->first_node[1]; id < g->node_count; id++)
        if (saved[id - g->first_node[1]])
            tp_tree_attach(t, id, saved[id - g->first_node[1]]);
    free(saved);
    tp_tree_destroy(t);
    free(h);
}

#define TESTS(X)                                                                                   \
    X(flights_select_as_the_plain_traversal)                                                       \
    X(standing_still_decides_nothing_again)                                                        \
    X(requests_only_updates_ask_as_the_plain_traversal)
TP_TEST_MAIN(TESTS)
