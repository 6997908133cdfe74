/* test_cut_query.c - what the viewer asks of a cut (cut_query.c) on real relief: ray casts
 * exact against the drawn triangles (brute force over every drawn node, as test_query.c does
 * for the selection), the vertical scale followed by culling, error projection and rays, camera
 * collision against the full-resolution surface of resident leaves, and the tree's own
 * full-resolution surface against tp_terrain's.
 */
#include "tp_test.h"

#include <stdint.h>

#include "tp_test_hgt.h"

#define LOAD_OR_SKIP(var, x0, y0, w, h)                                                            \
    float* var = load_hgt(x0, y0, w, h);                                                           \
    if (!var)                                                                                      \
    SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)")

static const double GT[6] = {400000, 90, 0, 4800000, 0, -90};

static tp_tree* make_tree(const float* hts, int w, int h, int patch_size)
{
    tp_tree* t = NULL;
    tp_error e = {{0}};
    ASSERT_OK(tp_tree_create_from_grid(hts, (size_t)w * h, w, h, GT, patch_size, 0, &t, &e));
    return t;
}

static uint64_t rng_state = 0x2545F4914F6CDD1Dull;
static double rnd(void)
{
    rng_state ^= rng_state << 13;
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return (double)(rng_state >> 11) / 9007199254740992.0;
}

/* A camera over a random point of the crop, looking down at 10..60 degrees, zs the scale. */
static void random_camera(const tp_tree* t, double zs, tp_camera* cam)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    double x = rnd() * (g->src_width - 1), y = rnd() * (g->src_height - 1), pos[3];
    tp_tree_grid_to_world(t, x, y, &pos[0], &pos[1]);
    tp_tree_info ti;
    tp_tree_get_info(t, &ti);
    pos[2] = (ti.max_height_m + 50 + rnd() * 2000) * zs;
    tp_camera_from_pose(pos, rnd() * 360, -10 - rnd() * 50, 60, 640, 360, cam);
}

/* Brute force: the nearest t over every triangle of every drawn node (tp_cut_vertices through
 * tp_cut_triangles, the renderer's own decoding of the strips), -1 if none. */
static double brute_ray(const tp_cut* cut, const tp_tree* t, const double o[3], const double d[3],
                        double zs)
{
    size_t count = 0;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    int n = tp_tree_get_geometry(t)->n;
    size_t vs = ((size_t)1 << n) + 1;
    tp_vertex* v = malloc(vs * vs * sizeof *v);
    uint32_t* tri = malloc(6 * (vs - 1) * (vs - 1) * sizeof *tri);
    double best = -1;
    for (size_t i = 0; i < count; i++) {
        int k = nodes[i].level;
        tp_cut_vertices(cut, i, v, vs * vs);
        (void)k;
        size_t nt = tp_cut_triangles(cut, i, v, tri, 2 * (vs - 1) * (vs - 1));
        for (size_t j = 0; j < nt; j++) {
            double p[3][3];
            for (int a = 0; a < 3; a++) {
                const tp_vertex* q = &v[tri[3 * j + a]];
                tp_tree_grid_to_world(t, q->x, q->y, &p[a][0], &p[a][1]);
                p[a][2] = q->z_m * zs;
            }
            /* Moller & Trumbore, written out again here */
            double e1[3], e2[3], s[3], pv[3], qv[3];
            for (int a = 0; a < 3; a++) {
                e1[a] = p[1][a] - p[0][a];
                e2[a] = p[2][a] - p[0][a];
                s[a] = o[a] - p[0][a];
            }
            pv[0] = d[1] * e2[2] - d[2] * e2[1];
            pv[1] = d[2] * e2[0] - d[0] * e2[2];
            pv[2] = d[0] * e2[1] - d[1] * e2[0];
            double det = e1[0] * pv[0] + e1[1] * pv[1] + e1[2] * pv[2];
            if (det == 0)
                continue;
            double u = (s[0] * pv[0] + s[1] * pv[1] + s[2] * pv[2]) / det;
            qv[0] = s[1] * e1[2] - s[2] * e1[1];
            qv[1] = s[2] * e1[0] - s[0] * e1[2];
            qv[2] = s[0] * e1[1] - s[1] * e1[0];
            double w = (d[0] * qv[0] + d[1] * qv[1] + d[2] * qv[2]) / det;
            if (u < -1e-9 || w < -1e-9 || u + w > 1 + 1e-9)
                continue;
            double tt = (e2[0] * qv[0] + e2[1] * qv[1] + e2[2] * qv[2]) / det;
            if (tt >= 0 && (best < 0 || tt < best))
                best = tt;
        }
    }
    free(v);
    free(tri);
    return best;
}

/* Random views and pixels: tp_cut_ray_cast agrees with the brute force (hit or miss, and the
 * distance), and its hits lie on the drawn surface (tp_cut_drawn_height_at). */
static void rays_agree(double zs, double tau_px)
{
    LOAD_OR_SKIP(h, 300, 420, 300, 260); /* 300 x 260: neither size is 2^n * k + 1 */
    tp_tree* t = make_tree(h, 300, 260, 17);
    tp_cut* cut = NULL;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    ASSERT_OK(tp_cut_set_vertical_scale(cut, zs));
    EXPECT_EQ_DBL(tp_cut_vertical_scale(cut), zs);
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = tau_px};
    int hits = 0, rays = 0, stitched = 0;
    for (int ci = 0; ci < 10; ci++) {
        tp_camera cam;
        random_camera(t, zs, &cam);
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        size_t count = 0;
        const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
        for (size_t i = 0; i < count; i++)
            for (int s = 0; s < 4; s++)
                stitched += nodes[i].nb[s] >= 0 && nodes[i].nb[s] < nodes[i].level;
        for (int ri = 0; ri < 30; ri++) {
            double d[3];
            tp_camera_pixel_ray(&cam, rnd() * 640, 60 + rnd() * 300, d);
            double len = sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2]);
            for (int a = 0; a < 3; a++)
                d[a] /= len;
            tp_ray_hit hit;
            ASSERT_OK(tp_cut_ray_cast(cut, cam.position, d, &hit));
            double want = brute_ray(cut, t, cam.position, d, zs);
            rays++;
            EXPECT_EQ_INT(hit.hit, want >= 0);
            EXPECT_EQ_INT(hit.patch, -1);
            if (!hit.hit || want < 0)
                continue;
            hits++;
            EXPECT_NEAR(hit.distance_m, want, 1e-6 * (1 + want));
            EXPECT_GE(hit.node, 0);
            double x, y;
            tp_tree_world_to_grid(t, hit.position[0], hit.position[1], &x, &y);
            EXPECT_NEAR(hit.position[2], tp_cut_drawn_height_at(cut, x, y), 0.01);
            EXPECT_NEAR(cam.position[2] + hit.distance_m * d[2], hit.position[2] * zs, 1e-6 * zs);
        }
    }
    tp_test_note("%d of %d rays hit; %d stitched sides", hits, rays, stitched);
    EXPECT_GE(hits, rays / 3);
    EXPECT_GT(stitched, 0);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
    free(h);
}

TEST(ray_cast_hits_lie_on_the_drawn_surface) { rays_agree(1, 1); }
TEST(ray_cast_across_stitched_coarse_cuts) { rays_agree(1, 8); }
TEST(ray_cast_follows_the_vertical_scale) { rays_agree(4, 2); }

TEST(ray_cast_rejects_a_zero_direction)
{
    LOAD_OR_SKIP(h, 0, 0, 40, 40);
    tp_tree* t = make_tree(h, 40, 40, 17);
    tp_cut* cut = NULL;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    double o[3] = {GT[0], GT[3], 5000}, d[3] = {0, 0, 0};
    tp_ray_hit hit = {.hit = 7};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_ray_cast(cut, o, d, &hit));
    EXPECT_EQ_INT(hit.hit, 7); /* untouched */
    d[2] = NAN;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_ray_cast(cut, o, d, &hit));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_set_vertical_scale(cut, 0));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_cut_set_vertical_scale(cut, NAN));
    EXPECT_EQ_DBL(tp_cut_vertical_scale(cut), 1);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
    free(h);
}

/* The scale reaches culling and the error projection: at the same tau a 5x exaggerated view
 * draws more triangles, and its drawn boxes (bound_px) stay within tau. */
TEST(vertical_scale_refines_the_cut)
{
    LOAD_OR_SKIP(h, 100, 100, 513, 513);
    tp_tree* t = make_tree(h, 513, 513, 17);
    tp_cut* cut = NULL;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    size_t tri[2];
    for (int i = 0; i < 2; i++) {
        double zs = i ? 5 : 1, pos[3];
        ASSERT_OK(tp_cut_set_vertical_scale(cut, zs));
        tp_tree_grid_to_world(t, 256, 600, &pos[0], &pos[1]);
        pos[2] = 3000 * zs;
        tp_camera cam;
        tp_camera_from_pose(pos, 0, -30, 60, 1280, 720, &cam);
        ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
        tp_cut_stats st;
        tp_cut_get_stats(cut, &st);
        tri[i] = st.triangles;
        EXPECT_LE(st.max_bound_px, 1.0);
        double max_px = 0;
        ASSERT_OK(tp_cut_measure_screen_error(cut, &cam, &max_px, NULL, NULL, NULL));
        EXPECT_LE(max_px, 1.0);
    }
    tp_test_note("triangles at scale 1: %zu, at 5: %zu", tri[0], tri[1]);
    EXPECT_GT((double)tri[1], 1.2 * (double)tri[0]);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
    free(h);
}

/* The 150 x 97 grid of the tests below as a terrain (patches of 17): their reference. */
static tp_terrain* terrain_150x97(const float* h)
{
    tp_terrain* ter = NULL;
    tp_terrain_desc td = {.heights = h, .height_count = (size_t)150 * 97, .width = 150,
                          .height = 97, .patch_size = 17, .fit = TP_FIT_PAD};
    memcpy(td.geotransform, GT, sizeof GT);
    ASSERT_OK(tp_terrain_create(&td, &ter, NULL));
    return ter;
}

/* The tree's full-resolution surface is tp_terrain_height_at's on the same grid (integral
 * heights: both decode exactly), NaN where the leaf is not resident. */
TEST(tree_height_is_the_full_resolution_surface)
{
    LOAD_OR_SKIP(h, 600, 200, 150, 97);
    tp_tree* t = make_tree(h, 150, 97, 17);
    tp_terrain* ter = terrain_150x97(h);
    int compared = 0;
    for (int i = 0; i < 4000; i++) {
        double x = rnd() * 149, y = rnd() * 96;
        if (i < 200) /* on the lattice and on leaf borders too */
            x = (double)(16 * (int)(rnd() * 9)), y = floor(y);
        double a = tp_tree_height_at(t, x, y), b = tp_terrain_height_at(ter, x, y);
        EXPECT_TRUE(isnan(a) == isnan(b));
        if (!isnan(a) && !isnan(b)) {
            EXPECT_NEAR(a, b, 1e-9);
            compared++;
        }
    }
    EXPECT_GT(compared, 3000);
    EXPECT_NAN(tp_tree_height_at(t, -1, 3));
    EXPECT_EQ_INT(tp_tree_leaf_at(t, -0.5, 0), -1);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    EXPECT_EQ_INT(tp_tree_leaf_at(t, 40.5, 20), tp_tree_node_id(g, 0, 2, 1));
    EXPECT_EQ_INT(tp_tree_leaf_at(t, 32, 32), tp_tree_node_id(g, 0, 2, 2)); /* border: after */
    EXPECT_EQ_INT(tp_tree_leaf_at(t, 149, 96), tp_tree_node_id(g, 0, 9, 5)); /* far edge: last */
    int64_t leaf = tp_tree_leaf_at(t, 40.5, 20);
    const uint16_t* smp = tp_tree_samples(t, leaf);
    tp_tree_detach(t, leaf);
    EXPECT_NAN(tp_tree_height_at(t, 40.5, 20));
    tp_tree_attach(t, leaf, smp);
    tp_terrain_destroy(ter);
    tp_tree_destroy(t);
    free(h);
}

/* Collision: the eye goes to clearance above the higher of the full-resolution and the drawn
 * surface, in drawn space; with the leaf under it not resident, above the drawn surface. */
TEST(keep_above_uses_the_full_resolution_leaf)
{
    LOAD_OR_SKIP(h, 300, 420, 300, 260);
    tp_tree* t = make_tree(h, 300, 260, 17);
    tp_cut* cut = NULL;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    const double zs = 2;
    ASSERT_OK(tp_cut_set_vertical_scale(cut, zs));
    tp_camera cam;
    double eye[3];
    tp_tree_grid_to_world(t, 150, 300, &eye[0], &eye[1]);
    eye[2] = 8000;
    tp_camera_from_pose(eye, 0, -20, 60, 1280, 720, &cam);
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 16};
    ASSERT_OK(tp_cut_update(cut, &cam, &lp, NULL));
    int raised_above_drawn = 0, tried = 0;
    for (int i = 0; i < 400; i++) {
        double x = 5 + rnd() * 280, y = 5 + rnd() * 240, p[3];
        double full = tp_tree_height_at(t, x, y), drawn = tp_cut_drawn_height_at(cut, x, y);
        if (isnan(full) || isnan(drawn))
            continue;
        tried++;
        tp_tree_grid_to_world(t, x, y, &p[0], &p[1]);
        p[2] = -1000;
        EXPECT_EQ_INT(tp_cut_keep_above(cut, p, 2.0), 1);
        EXPECT_NEAR(p[2], fmax(full, drawn) * zs + 2.0, 1e-6);
        raised_above_drawn += full > drawn + 0.5;
        EXPECT_EQ_INT(tp_cut_keep_above(cut, p, 2.0), 0); /* high enough now */
        /* without the leaf: only the drawn surface counts */
        int64_t leaf = tp_tree_leaf_at(t, x, y);
        size_t count = 0;
        const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
        int drawn_leaf = 0;
        for (size_t j = 0; j < count; j++)
            drawn_leaf |= nodes[j].node == leaf;
        if (drawn_leaf)
            continue; /* a drawn node must stay resident */
        const uint16_t* smp = tp_tree_samples(t, leaf);
        tp_tree_detach(t, leaf);
        p[2] = -1000;
        EXPECT_EQ_INT(tp_cut_keep_above(cut, p, 2.0), 1);
        EXPECT_NEAR(p[2], drawn * zs + 2.0, 1e-6);
        tp_tree_attach(t, leaf, smp);
    }
    tp_test_note("%d points, %d where the full-resolution surface is above the drawn one", tried,
                 raised_above_drawn);
    EXPECT_GT(tried, 300);
    EXPECT_GT(raised_above_drawn, 10); /* the full-resolution leaf matters */
    double off[3] = {GT[0] - 1e5, GT[3], 0};
    EXPECT_EQ_INT(tp_cut_keep_above(cut, off, 2.0), 0);
    tp_cut_destroy(cut);
    tp_tree_destroy(t);
    free(h);
}

/* Vertex normals: where the leaves are resident every node, whatever its scale, gives the
 * terrain's full-resolution normal at its vertices (so nodes of different scales shade alike
 * across their borders); where they are not, the node's own lattice. */
TEST(node_normals_are_the_terrains_where_leaves_are_resident)
{
    LOAD_OR_SKIP(h, 600, 200, 150, 97);
    tp_tree* t = make_tree(h, 150, 97, 17);
    tp_terrain* ter = terrain_150x97(h);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int compared = 0;
    for (int64_t id = 0; id < g->node_count; id++) {
        int s, c, r;
        tp_tree_node_locate(g, id, &s, &c, &r);
        int step = 1 << s, x0 = c << (g->n + s), y0 = r << (g->n + s);
        for (int j = 0; j <= 16; j += 4)
            for (int i = 0; i <= 16; i += 4) {
                int x = x0 + i * step, y = y0 + j * step;
                if (isnan(tp_terrain_sample(ter, x, y)))
                    continue;
                float a[3], b[3];
                tp_tree_node_normal(t, id, x, y, a);
                tp_terrain_normal(ter, x, y, b);
                for (int k = 0; k < 3; k++)
                    EXPECT_NEAR(a[k], b[k], 1e-6);
                compared++;
            }
    }
    EXPECT_GT(compared, 500);
    /* without the leaves, a parent shades from its own lattice: a coarser slope */
    int64_t parent = tp_tree_node_id(g, 1, 1, 1);
    const uint16_t* kept[4];
    for (int q = 0; q < 4; q++) {
        int64_t ch = tp_tree_node_child(g, parent, q);
        kept[q] = tp_tree_samples(t, ch);
        tp_tree_detach(t, ch);
    }
    int differ = 0;
    for (int j = 2; j <= 14; j += 4)
        for (int i = 2; i <= 14; i += 4) {
            int x = 32 + 2 * i, y = 32 + 2 * j;
            float a[3], b[3];
            tp_tree_node_normal(t, parent, x, y, a);
            tp_terrain_normal(ter, x, y, b);
            differ += fabs(a[0] - b[0]) + fabs(a[1] - b[1]) > 1e-4;
        }
    EXPECT_GT(differ, 0);
    for (int q = 0; q < 4; q++)
        tp_tree_attach(t, tp_tree_node_child(g, parent, q), kept[q]);
    tp_terrain_destroy(ter);
    tp_tree_destroy(t);
    free(h);
}

/* A node's normals in one call (as the renderer asks for them, its lattice in order) are the
 * terrain's where the leaves are resident, and bit for bit those of one vertex at a time when
 * some leaves are not (the leaf the call reads from changes along the way). */
TEST(node_normals_in_one_call_are_those_one_at_a_time)
{
    LOAD_OR_SKIP(h, 600, 200, 150, 97);
    tp_tree* t = make_tree(h, 150, 97, 17);
    tp_terrain* ter = terrain_150x97(h);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_vertex v[17 * 17];
    float batch[17 * 17][3];
    int compared = 0, identical = 0, lattice = 0;
    for (int pass = 0; pass < 2; pass++) {
        const uint16_t* kept[64];
        int64_t gone[64];
        int ngone = 0;
        if (pass == 1) /* every third leaf away: reads fall back to coarser nodes or lattices */
            for (int64_t id = 0; id < g->node_count && ngone < 64; id++) {
                int s, c, r;
                tp_tree_node_locate(g, id, &s, &c, &r);
                if (s == 0 && (c + 2 * r) % 3 == 1 && tp_tree_samples(t, id)) {
                    kept[ngone] = tp_tree_samples(t, id);
                    gone[ngone++] = id;
                    tp_tree_detach(t, id);
                }
            }
        for (int64_t id = 0; id < g->node_count; id++) {
            if (!tp_tree_samples(t, id))
                continue;
            int s, c, r;
            tp_tree_node_locate(g, id, &s, &c, &r);
            int step = 1 << s, x0 = c << (g->n + s), y0 = r << (g->n + s);
            for (int j = 0; j <= 16; j++)
                for (int i = 0; i <= 16; i++)
                    v[j * 17 + i] = (tp_vertex){x0 + i * step, y0 + j * step, 0, 0};
            tp_tree_node_normals(t, id, v, 17 * 17, batch);
            for (int k = 0; k < 17 * 17; k++) {
                float a[3], b[3];
                if (v[k].x >= 150 || v[k].y >= 97)
                    continue;
                tp_tree_node_normal(t, id, v[k].x, v[k].y, a);
                identical += !memcmp(a, batch[k], sizeof a);
                compared++;
                if (pass == 0 && !isnan(tp_terrain_sample(ter, v[k].x, v[k].y))) {
                    tp_terrain_normal(ter, v[k].x, v[k].y, b);
                    for (int q = 0; q < 3; q++)
                        EXPECT_NEAR(batch[k][q], b[q], 1e-6);
                }
                if (pass == 1 && !isnan(tp_terrain_sample(ter, v[k].x, v[k].y))) {
                    tp_terrain_normal(ter, v[k].x, v[k].y, b);
                    lattice += fabs(batch[k][0] - b[0]) + fabs(batch[k][1] - b[1]) > 1e-4;
                }
            }
        }
        for (int q = 0; q < ngone; q++)
            tp_tree_attach(t, gone[q], kept[q]);
        if (pass == 1)
            EXPECT_GT(ngone, 5);
    }
    EXPECT_EQ_INT(compared, identical);
    EXPECT_GT(compared, 5000);
    EXPECT_GT(lattice, 10); /* the second pass did read lattices where leaves were missing */
    tp_terrain_destroy(ter);
    tp_tree_destroy(t);
    free(h);
}

#define TESTS(X)                                                                                   \
    X(ray_cast_hits_lie_on_the_drawn_surface)                                                      \
    X(ray_cast_across_stitched_coarse_cuts)                                                        \
    X(ray_cast_follows_the_vertical_scale)                                                         \
    X(ray_cast_rejects_a_zero_direction)                                                           \
    X(vertical_scale_refines_the_cut)                                                              \
    X(tree_height_is_the_full_resolution_surface)                                                  \
    X(keep_above_uses_the_full_resolution_leaf)                                                    \
    X(node_normals_are_the_terrains_where_leaves_are_resident)                                     \
    X(node_normals_in_one_call_are_those_one_at_a_time)
TP_TEST_MAIN(TESTS)
