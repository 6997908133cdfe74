/* test_tin_node.c - a node's TINs (tp_node_tins_build, issue 32 item 2) checked from their
 * definition in tp_tree.h, apart from tin_node.c: each rung's outline is the level's lattice
 * outline, under crack removal it meets the lattice's moved outline edge for edge, it tiles the
 * node, and its error against the full-resolution grid (measured by tp_tin_measure, which shares
 * no code with the builder) is within its stated bound (carry included) plus quantisation,
 * with any neighbour levels. On real relief (Mt Hood, N42E001) and on hard grids: flat, a cliff,
 * random noise, a void. */
#include "tp_io.h"
#include "tp_test.h"

#define TESTS(X)                                                                                   \
    X(mt_hood_rungs_hold_their_bounds_with_any_neighbours)                                         \
    X(n42e001_rungs_hold_their_bounds_with_any_neighbours)                                         \
    X(rungs_save_triangles_on_real_relief)                                                         \
    X(flat_ground_keeps_only_the_outline)                                                          \
    X(cliff_and_noise_hold_their_bounds)                                                           \
    X(a_coarse_node_holds_its_bound_between_its_samples)                                           \
    X(a_node_four_times_coarser_holds_its_exact_bound)                                             \
    X(carry_regions_bound_the_surface_against_full_resolution)                                     \
    X(incomplete_nodes_have_none)                                                                  \
    X(levels_are_built_as_asked)                                                                   \
    X(the_cache_builds_once_and_prunes_by_residency_and_age)                                       \
    X(the_cache_keeps_its_byte_budget_oldest_first_but_never_what_is_drawn)

#include "tp_test_tin.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define GT ((const double[6]){0, 10, 0, 0, 0, -10})

/* ---- crack removal, written here from lattice.c's rule: a side vertex snaps to the nearest
 * multiple of m = 2^(k-kn) (level-k units); halfway goes toward the nearer corner; the exact
 * middle (against level 0) TOP -> low, RIGHT -> low, BOTTOM -> high, LEFT -> high ---- */
static int snap_to(int a, int m, int last, int low_at_middle)
{
    int r = a % m;
    if (r == 0)
        return a;
    if (2 * r != m)
        return 2 * r < m ? a - r : a + m - r;
    if (2 * a != last)
        return 2 * a < last ? a - r : a + m - r;
    return low_at_middle ? a - r : a + m - r;
}

/* Position (level-n units) of vertex (i, j) of a level-k TIN of a node of 2^n cells after crack
 * removal against nb (TP_NO_NEIGHBOR or a relative level). */
static void moved(int n, int k, const int nb[4], int i, int j, int* mi, int* mj)
{
    int last = 1 << n, st = 1 << (n - k), lk = 1 << k;
    *mi = i, *mj = j;
    int on_x = i == 0 || i == last, on_y = j == 0 || j == last;
    if (on_x && on_y)
        return;
    int side = j == 0 ? TP_SIDE_TOP : i == last ? TP_SIDE_RIGHT : j == last ? TP_SIDE_BOTTOM
             : i == 0 ? TP_SIDE_LEFT : -1;
    if (side < 0 || nb[side] < 0 || nb[side] >= k)
        return;
    ASSERT_EQ_INT(i % st, 0);
    ASSERT_EQ_INT(j % st, 0);
    int m = 1 << (k - nb[side]);
    if (side == TP_SIDE_TOP || side == TP_SIDE_BOTTOM)
        *mi = snap_to(i / st, m, lk, side == TP_SIDE_TOP) * st;
    else
        *mj = snap_to(j / st, m, lk, side == TP_SIDE_RIGHT) * st;
}

static int64_t orient2(int p[3][2])
{
    return ((int64_t)p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) -
           ((int64_t)p[1][1] - p[0][1]) * (p[2][0] - p[0][0]);
}

/* An edge key of two level-n positions. */
static uint64_t edge_key(int ax, int ay, int bx, int by)
{
    uint64_t a = (uint64_t)ay << 16 | (uint64_t)ax, b = (uint64_t)by << 16 | (uint64_t)bx;
    return a < b ? a << 32 | b : b << 32 | a;
}

/* The rung's outline and tiling, unmoved and under nb: every triangle keeps the strips' winding
 * (or collapses), the triangles' area is the node's, interior edges are shared by exactly two
 * triangles and the outline's edges are those of the moved lattice: the segments between the
 * side's vertices at the neighbour's stride (or the level's). */
static void check_topology(const tp_node_tin* r, int n, const int nb[4])
{
    int k = r->level, last = 1 << n;
    uint64_t* e = malloc(sizeof *e * 3 * r->triangle_count);
    size_t ne = 0;
    int64_t area = 0;
    for (uint32_t t = 0; t < r->triangle_count; t++) {
        int p[3][2];
        for (int v = 0; v < 3; v++) {
            uint16_t idx = r->triangles[3 * t + v];
            ASSERT_LT(idx, r->vertex_count);
            moved(n, k, nb, r->ij[2 * idx], r->ij[2 * idx + 1], &p[v][0], &p[v][1]);
        }
        int64_t o = orient2(p);
        ASSERT_TRUE(o <= 0); /* strips' winding: (b - a) x (c - a) < 0 in (column, row) */
        if (o == 0)
            continue;
        area -= o;
        for (int v = 0; v < 3; v++)
            e[ne++] = edge_key(p[v][0], p[v][1], p[(v + 1) % 3][0], p[(v + 1) % 3][1]);
    }
    EXPECT_EQ_INT(area, 2 * (int64_t)last * last);
    qsort(e, ne, sizeof *e, cmp_u64);
    size_t outline = 0;
    for (size_t i = 0; i < ne;) {
        size_t j = i;
        while (j < ne && e[j] == e[i])
            j++;
        ASSERT_TRUE(j - i <= 2);
        if (j - i == 1) { /* an outline edge: on a side, between the side's moved vertices */
            int ax = (int)(e[i] >> 32 & 0xFFFF), ay = (int)(e[i] >> 48);
            int bx = (int)(e[i] & 0xFFFF), by = (int)(e[i] >> 16 & 0xFFFF);
            int side = ay == 0 && by == 0         ? TP_SIDE_TOP
                       : ax == last && bx == last ? TP_SIDE_RIGHT
                       : ay == last && by == last ? TP_SIDE_BOTTOM
                       : ax == 0 && bx == 0       ? TP_SIDE_LEFT
                                                  : -1;
            ASSERT_TRUE(side >= 0);
            int kk = nb[side] >= 0 && nb[side] < k ? nb[side] : k, st = 1 << (n - kk);
            int lo = side == TP_SIDE_TOP || side == TP_SIDE_BOTTOM ? (ax < bx ? ax : bx)
                                                                   : (ay < by ? ay : by);
            int hi = side == TP_SIDE_TOP || side == TP_SIDE_BOTTOM ? (ax < bx ? bx : ax)
                                                                   : (ay < by ? by : ay);
            EXPECT_EQ_INT(lo % st, 0);
            EXPECT_EQ_INT(hi - lo, st);
            outline++;
        }
        i = j;
    }
    /* every segment of every side once */
    size_t want = 0;
    for (int s = 0; s < 4; s++)
        want += (size_t)1 << (nb[s] >= 0 && nb[s] < k ? nb[s] : k);
    EXPECT_EQ_INT(outline, want);
    free(e);
}

/* Unmoved, the outline's vertices are the level's side vertices and no other side sample. */
static void check_outline(const tp_node_tin* r, int n)
{
    int k = r->level, last = 1 << n, st = 1 << (n - k);
    size_t on_side = 0;
    for (uint32_t v = 0; v < r->vertex_count; v++) {
        int i = r->ij[2 * v], j = r->ij[2 * v + 1];
        ASSERT_TRUE(i <= last && j <= last);
        if (i == 0 || j == 0 || i == last || j == last) {
            EXPECT_EQ_INT(i % st, 0);
            EXPECT_EQ_INT(j % st, 0);
            on_side++;
        }
    }
    EXPECT_EQ_INT(on_side, (size_t)4 << k);
    EXPECT_TRUE(r->vertex_count <= (size_t)((1 << k) + 1) * ((1 << k) + 1));
    EXPECT_TRUE(r->triangle_count < (size_t)2 << (2 * k));
}

typedef struct checked {
    long rungs, configs, refused, levels, levels_with_rungs;
    double lattice_tris, first_rung_tris; /* over levels with rungs */
    double worst_ratio;                   /* measured / bound */
} checked;

/* The error of rung r of node `node` drawn with nb, against the full-resolution grid h: within
 * its bound (the carry included) plus the quantisation. */
static void check_error(const tp_tree* t, const float* h, int w, int hg, int64_t node,
                        const tp_node_tin* r, const int nb[4], checked* c)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_tree_info ti;
    tp_tree_get_info(t, &ti);
    int s, cx, cy;
    tp_tree_node_locate(g, node, &s, &cx, &cy);
    int8_t nb8[4] = {(int8_t)nb[0], (int8_t)nb[1], (int8_t)nb[2], (int8_t)nb[3]};
    double b = tp_node_tin_bound_steps(r, nb8);
    if (!isfinite(b)) {
        c->refused++;
        return; /* the cut draws the lattice then */
    }
    double bound = b * ti.height_step_m + ti.quant_max_error_m + 1e-6; /* carry included */
    float* v = malloc(sizeof *v * 3 * r->vertex_count);
    uint32_t* tri = malloc(sizeof *tri * 3 * r->triangle_count);
    for (uint32_t i = 0; i < r->vertex_count; i++) {
        int mi, mj;
        moved(g->n, r->level, nb, r->ij[2 * i], r->ij[2 * i + 1], &mi, &mj);
        int gx = (cx << (g->n + s)) + (mi << s), gy = (cy << (g->n + s)) + (mj << s);
        v[3 * i] = (float)gx, v[3 * i + 1] = (float)gy;
        v[3 * i + 2] = (float)tp_tree_sample(t, gx, gy);
        ASSERT_TRUE(isfinite(v[3 * i + 2]));
    }
    for (size_t i = 0; i < 3 * (size_t)r->triangle_count; i++)
        tri[i] = r->triangles[i];
    tp_tin_measure_result res;
    tp_error err = {{0}};
    if (tp_tin_measure(h, (size_t)w * hg, w, hg, v, r->vertex_count, tri, r->triangle_count, &res,
                       &err) != TP_OK)
        FAIL("tp_tin_measure: %s", err.message);
    if (res.max_error_m > bound)
        FAIL("node %lld level %d rung with %u triangles, nb %d %d %d %d: error %.4f m at (%d, %d) "
             "above its bound %.4f m",
             (long long)node, r->level, r->triangle_count, nb[0], nb[1], nb[2], nb[3],
             res.max_error_m, res.worst_x, res.worst_y, bound);
    double ratio = res.max_error_m / bound;
    c->worst_ratio = ratio > c->worst_ratio ? ratio : c->worst_ratio;
    c->configs++;
    free(v);
    free(tri);
}

/* Every node's every rung: outline, topology and error unmoved and under `configs` random
 * neighbour configurations (each side none or a level below the rung's). */
static checked check_tree(const tp_tree* t, const float* h, int w, int hg, int configs)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_tree_info ti;
    tp_tree_get_info(t, &ti);
    checked c = {0};
    unsigned seed = 12345;
    for (int64_t id = 0; id < g->node_count; id++) {
        int s, cx, cy;
        tp_tree_node_locate(g, id, &s, &cx, &cy);
        tp_node_tins* tins = NULL;
        tp_error err = {{0}};
        uint16_t carry[1 << (2 * TP_NODE_CARRY_DEPTH)];
        tp_node_carry_regions(t, id, carry);
        if (tp_node_tins_build(g->n, s, tp_tree_samples(t, id), tp_tree_meta(t, id), carry,
                               ti.err_unit_steps, ~0u, &tins, &err) != TP_OK)
            FAIL("tp_node_tins_build: %s", err.message);
        ASSERT_TRUE(tins != NULL); /* complete nodes */
        EXPECT_TRUE(tp_node_tins_bytes(tins) > 0);
        for (int k = 0; k <= g->n; k++) {
            int count;
            const tp_node_tin* r = tp_node_tins_level(tins, k, &count);
            if (k == 0)
                EXPECT_EQ_INT(count, 0);
            c.levels += k > 0;
            c.levels_with_rungs += count > 0;
            if (count) {
                c.lattice_tris += 2.0 * (1 << (2 * k));
                c.first_rung_tris += r[0].triangle_count;
            }
            for (int j = 0; j < count; j++) {
                c.rungs++;
                EXPECT_EQ_INT(r[j].level, k);
                if (j) /* coarser rungs first: stops of one insertion */
                    EXPECT_TRUE(r[j].triangle_count >= r[j - 1].triangle_count);
                check_outline(&r[j], g->n);
                int none[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
                check_topology(&r[j], g->n, none);
                check_error(t, h, w, hg, id, &r[j], none, &c);
                for (int q = 0; q < configs; q++) {
                    int nb[4];
                    for (int sd = 0; sd < 4; sd++) {
                        seed = seed * 1103515245u + 12345u;
                        int v = (int)(seed >> 16) % (k + 2) - 1; /* -1 .. k */
                        nb[sd] = v >= k ? TP_NO_NEIGHBOR : v;
                    }
                    int8_t nb8[4] = {(int8_t)nb[0], (int8_t)nb[1], (int8_t)nb[2], (int8_t)nb[3]};
                    if (isfinite(tp_node_tin_bound_steps(&r[j], nb8)))
                        check_topology(&r[j], g->n, nb);
                    check_error(t, h, w, hg, id, &r[j], nb, &c);
                }
            }
        }
        tp_node_tins_destroy(tins);
    }
    printf("%ld rungs, %ld configurations measured (%ld refused), levels with rungs %ld of %ld, "
           "first rungs %.1f%% of the lattices' triangles, worst error / bound %.3f\n",
           c.rungs, c.configs, c.refused, c.levels_with_rungs, c.levels,
           100 * c.first_rung_tris / (c.lattice_tris > 0 ? c.lattice_tris : 1), c.worst_ratio);
    return c;
}

static tp_tree* tree_of(const float* h, int w, int hg, int patch)
{
    tp_tree* t = NULL;
    tp_error e = {{0}};
    if (tp_tree_create_from_grid(h, (size_t)w * hg, w, hg, GT, patch, 0, &t, &e) != TP_OK)
        FAIL("tree: %s", e.message);
    return t;
}

#ifdef TP_TEST_NO_IO
static checked real_window(const char* env, const char* file, int size, int patch, int configs)
{
    SKIP("built without tp_io: %s", file);
    (void)env, (void)size, (void)patch, (void)configs;
    return (checked){0};
}
#else
/* A size x size window from the middle of a real DEM (its valid part), as a tree of patch. */
static checked real_window(const char* env, const char* file, int size, int patch, int configs)
{
    tp_render_grid* g = tin_test_render_grid(env, file);
    ASSERT_TRUE(g->width >= size && g->height >= size);
    float* h = malloc(sizeof *h * (size_t)size * size);
    int x0 = (g->width - size) / 2, y0 = (g->height - size) / 2;
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++) {
            float z = g->heights[(size_t)(y0 + y) * g->width + x0 + x];
            ASSERT_TRUE(!isnan(z)); /* the middle of these DEMs has no void */
            h[(size_t)y * size + x] = z;
        }
    tp_render_grid_destroy(g);
    tp_tree* t = tree_of(h, size, size, patch);
    checked c = check_tree(t, h, size, size, configs);
    tp_tree_destroy(t);
    free(h);
    return c;
}
#endif

TEST(mt_hood_rungs_hold_their_bounds_with_any_neighbours)
{
    checked c = real_window("TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif", 257, 33, 4);
    EXPECT_TRUE(c.rungs > 100);
    EXPECT_TRUE(c.configs > 400);
}

TEST(n42e001_rungs_hold_their_bounds_with_any_neighbours)
{
    checked c = real_window("TP_SAMPLE_DATA_DIR", "N42E001.hgt", 257, 65, 3);
    EXPECT_TRUE(c.rungs > 20);
}

TEST(rungs_save_triangles_on_real_relief)
{
    /* the coarsest rung of a level draws well under the lattice's triangles where the relief is
     * uneven (Mt Hood: 30 m posts, a volcano and its valleys) */
    checked c = real_window("TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif", 513, 65, 0);
    EXPECT_TRUE(c.levels_with_rungs * 2 > c.levels);
    EXPECT_TRUE(c.first_rung_tris < 0.6 * c.lattice_tris);
}

TEST(flat_ground_keeps_only_the_outline)
{
    int w = 65, hg = 65;
    float* h = malloc(sizeof *h * w * hg);
    for (int i = 0; i < w * hg; i++)
        h[i] = 100.0f;
    tp_tree* t = tree_of(h, w, hg, 33);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_tree_info ti;
    tp_tree_get_info(t, &ti);
    for (int64_t id = 0; id < g->node_count; id++) {
        int s, cx, cy;
        tp_tree_node_locate(g, id, &s, &cx, &cy);
        tp_node_tins* tins = NULL;
        tp_error err = {{0}};
        ASSERT_OK(tp_node_tins_build(g->n, s, tp_tree_samples(t, id), tp_tree_meta(t, id), NULL,
                                     ti.err_unit_steps, ~0u, &tins, &err));
        for (int k = 2; k <= g->n; k++) {
            int count;
            const tp_node_tin* r = tp_node_tins_level(tins, k, &count);
            /* every bound is 0, so level n has no ladder; below it the lattice's own rung: the
             * outline and the 4 vertices forced diagonally in from the corners, V = 4 2^k + 4
             * vertices of which B = 4 2^k on the outline, so 2 V - B - 2 = 4 2^k + 6 triangles */
            EXPECT_EQ_INT(count, k < g->n ? 1 : 0);
            if (count) {
                EXPECT_EQ_INT(r->vertex_count, ((uint32_t)4 << k) + 4);
                EXPECT_EQ_INT(r->triangle_count, ((uint32_t)4 << k) + 6);
                EXPECT_TRUE(r->own_steps == 0);
            }
        }
        tp_node_tins_destroy(tins);
    }
    tp_tree_destroy(t);
    free(h);
}

TEST(cliff_and_noise_hold_their_bounds)
{
    int w = 129, hg = 129;
    float* h = malloc(sizeof *h * w * hg);
    unsigned seed = 7;
    for (int y = 0; y < hg; y++)
        for (int x = 0; x < w; x++) {
            seed = seed * 1103515245u + 12345u;
            float noise = (float)((seed >> 16) % 1000) / 100.0f;
            /* a 300 m cliff across a diagonal, noise on one half, a ramp on the other */
            h[(size_t)y * w + x] = (x + y > 120 ? 300.0f : 0.0f) + (x < 64 ? noise : 0.5f * y);
        }
    tp_tree* t = tree_of(h, w, hg, 33);
    checked c = check_tree(t, h, w, hg, 6);
    EXPECT_TRUE(c.rungs > 0);
    tp_tree_destroy(t);
    free(h);
}

TEST(a_coarse_node_holds_its_bound_between_its_samples)
{
    /* The full resolution is exactly the root's level-n surface (random coarse samples, every
     * other one interpolated along the strips' diagonal, from (i+1, j) to (i, j+1)), so the
     * root's carry is 0 and its TINs' error between its samples shows only at full resolution:
     * measured at its own samples alone, the rungs' bounds would be too small. */
    int cw = 65, w = 2 * cw - 1;
    float* coarse = malloc(sizeof *coarse * cw * cw);
    float* h = malloc(sizeof *h * w * w);
    unsigned seed = 99;
    for (int i = 0; i < cw * cw; i++) {
        seed = seed * 1103515245u + 12345u;
        coarse[i] = (float)(2 * ((seed >> 16) % 200));
    }
#define C(i, j) coarse[(size_t)(j) * cw + (i)]
    for (int y = 0; y < w; y++)
        for (int x = 0; x < w; x++) {
            int i = x / 2, j = y / 2;
            float z = x % 2 == 0 && y % 2 == 0 ? C(i, j)
                      : y % 2 == 0            ? 0.5f * (C(i, j) + C(i + 1, j))
                      : x % 2 == 0            ? 0.5f * (C(i, j) + C(i, j + 1))
                                              : 0.5f * (C(i + 1, j) + C(i, j + 1));
            h[(size_t)y * w + x] = z;
        }
#undef C
    tp_tree* t = tree_of(h, w, w, 65);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    ASSERT_EQ_INT(g->scales, 2);
    int64_t root = tp_tree_node_id(g, 1, 0, 0);
    EXPECT_EQ_INT(tp_tree_meta(t, root)->delta[g->n], 0);
    checked c = check_tree(t, h, w, w, 3);
    EXPECT_TRUE(c.rungs > 10);
    tp_tree_destroy(t);
    free(h);
    free(coarse);
}

/* The root's level-n surface (65 x 65 random samples, multiples of 4: exact at quarter points),
 * its cells split from (i+1, j) to (i, j+1), sampled f times finer as the full resolution. */
static float* upsampled_surface(int f, unsigned seed, int* width)
{
    int cw = 65, w = f * (cw - 1) + 1;
    float* coarse = malloc(sizeof *coarse * cw * cw);
    float* h = malloc(sizeof *h * w * w);
    for (int i = 0; i < cw * cw; i++) {
        seed = seed * 1103515245u + 12345u;
        coarse[i] = (float)(4 * ((seed >> 16) % 100));
    }
#define C(i, j) coarse[(size_t)(j) * cw + (i)]
    for (int y = 0; y < w; y++)
        for (int x = 0; x < w; x++) {
            int i = x / f, j = y / f, fx = x % f, fy = y % f;
            double z;
            if (fx + fy <= f) /* lower triangle (also the samples: fx = fy = 0) */
                z = C(i, j) + (double)fx / f * (C(i + 1 < cw ? i + 1 : i, j) - C(i, j)) +
                    (double)fy / f * (C(i, j + 1 < cw ? j + 1 : j) - C(i, j));
            else
                z = C(i + 1, j + 1) + (double)(f - fx) / f * (C(i, j + 1) - C(i + 1, j + 1)) +
                    (double)(f - fy) / f * (C(i + 1, j) - C(i + 1, j + 1));
            h[(size_t)y * w + x] = (float)z;
        }
#undef C
    free(coarse);
    *width = w;
    return h;
}

TEST(a_node_four_times_coarser_holds_its_exact_bound)
{
    /* As above, a root of scale 2: every carry is 0 (the children's surfaces nest in the root's),
     * so each rung's bound is its measured |T - S_n| alone, which the full resolution (the
     * surface at quarter points) samples between the crossings of T's edges with the cells: the
     * error there reaches the bound (an exact bound, not the cell bound's extension a cell
     * beyond T). */
    int w;
    float* h = upsampled_surface(4, 4242, &w);
    tp_tree* t = tree_of(h, w, w, 65);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    ASSERT_EQ_INT(g->scales, 3);
    int64_t root = tp_tree_node_id(g, 2, 0, 0);
    EXPECT_EQ_INT(tp_tree_meta(t, root)->delta[g->n], 0);
    checked c = check_tree(t, h, w, w, 2);
    EXPECT_TRUE(c.rungs > 10);
    EXPECT_TRUE(c.worst_ratio > 0.9); /* the bound is reached: exact, not a loose margin */
    tp_tree_destroy(t);
    free(h);
}

/* The level-n surface of node `id` at full-resolution sample (x, y) of its area (metres), written
 * here from tp_tree.h's definition: its samples, each cell split from (i+1, j) to (i, j+1). */
static double level_n_surface(const tp_tree* t, int64_t id, int x, int y)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int s, cx, cy;
    tp_tree_node_locate(g, id, &s, &cx, &cy);
    int x0 = cx << (g->n + s), y0 = cy << (g->n + s), f = 1 << s;
    int i = (x - x0) >> s, j = (y - y0) >> s, fx = (x - x0) & (f - 1), fy = (y - y0) & (f - 1);
    if (fx == 0 && fy == 0)
        return tp_tree_sample(t, x, y);
#define S(a, b) tp_tree_sample(t, x0 + ((a) << s), y0 + ((b) << s))
    if (fx + fy <= f)
        return S(i, j) + (double)fx / f * (S(i + 1, j) - S(i, j)) +
               (double)fy / f * (S(i, j + 1) - S(i, j));
    return S(i + 1, j + 1) + (double)(f - fx) / f * (S(i, j + 1) - S(i + 1, j + 1)) +
           (double)(f - fy) / f * (S(i + 1, j) - S(i + 1, j + 1));
#undef S
}

TEST(carry_regions_bound_the_surface_against_full_resolution)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    /* Mt Hood, 257 x 257 in leaves of 33: nodes of scale 1 to 3. Each region's carry bounds the
     * node's level-n surface against every full-resolution sample of the region (closed), and
     * is at most the node's delta[n]; on this relief it is below it somewhere. */
    tp_render_grid* rg = tin_test_render_grid("TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    int size = 257, x0 = (rg->width - size) / 2, y0 = (rg->height - size) / 2;
    float* h = malloc(sizeof *h * (size_t)size * size);
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++)
            h[(size_t)y * size + x] = rg->heights[(size_t)(y0 + y) * rg->width + x0 + x];
    tp_render_grid_destroy(rg);
    tp_tree* t = tree_of(h, size, size, 33);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_tree_info ti;
    tp_tree_get_info(t, &ti);
    double unit_m = ti.err_unit_steps * ti.height_step_m;
    long regions = 0, tighter = 0;
    for (int64_t id = 0; id < g->node_count; id++) {
        int s, cx, cy;
        tp_tree_node_locate(g, id, &s, &cx, &cy);
        int d = tp_node_carry_depth(s), nr = 1 << d;
        EXPECT_EQ_INT(d, s < 3 ? s : 3);
        uint16_t carry[1 << (2 * TP_NODE_CARRY_DEPTH)];
        tp_node_carry_regions(t, id, carry);
        uint16_t own = tp_tree_meta(t, id)->delta[g->n];
        int span = 1 << (g->n + s - d); /* full-resolution samples a region side */
        for (int r = 0; r < nr * nr; r++) {
            EXPECT_TRUE(carry[r] <= own);
            regions++;
            tighter += carry[r] < own;
            int rx = (cx << (g->n + s)) + (r % nr) * span, ry = (cy << (g->n + s)) + (r / nr) * span;
            double worst = 0;
            for (int y = ry; y <= ry + span; y++)
                for (int x = rx; x <= rx + span; x++) {
                    double e = fabs(level_n_surface(t, id, x, y) - h[(size_t)y * size + x]);
                    worst = e > worst ? e : worst;
                }
            if (worst > carry[r] * unit_m + ti.quant_max_error_m + 1e-6)
                FAIL("node %lld region %d: |S_n - f| %.4f m above its carry %.4f m",
                     (long long)id, r, worst, carry[r] * unit_m);
        }
    }
    printf("%ld regions, %ld below their node's carry\n", regions, tighter);
    EXPECT_TRUE(regions > 64);
    EXPECT_TRUE(tighter * 4 > regions);
    tp_tree_destroy(t);
    free(h);
#endif
}

TEST(incomplete_nodes_have_none)
{
    int w = 65, hg = 65;
    float* h = malloc(sizeof *h * w * hg);
    for (int y = 0; y < hg; y++)
        for (int x = 0; x < w; x++)
            h[(size_t)y * w + x] = (float)(x * 3 + y);
    h[(size_t)10 * w + 10] = NAN; /* one void in the top-left leaf */
    tp_tree* t = tree_of(h, w, hg, 33);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_tree_info ti;
    tp_tree_get_info(t, &ti);
    int with = 0, without = 0;
    for (int64_t id = 0; id < g->node_count; id++) {
        int s, cx, cy;
        tp_tree_node_locate(g, id, &s, &cx, &cy);
        tp_node_tins* tins = (tp_node_tins*)1;
        tp_error err = {{0}};
        ASSERT_OK(tp_node_tins_build(g->n, s, tp_tree_samples(t, id), tp_tree_meta(t, id), NULL,
                                     ti.err_unit_steps, ~0u, &tins, &err));
        /* a node holds sample (10, 10) when it lies on its stride and in its area */
        int span = 1 << (g->n + s);
        int holds_void = 10 % (1 << s) == 0 && 10 >= cx * span && 10 <= (cx + 1) * span &&
                         10 >= cy * span && 10 <= (cy + 1) * span;
        EXPECT_EQ_INT(tins == NULL, holds_void);
        with += tins != NULL, without += tins == NULL;
        tp_node_tins_destroy(tins);
    }
    EXPECT_EQ_INT(without, 2); /* the top-left leaf and the root */
    EXPECT_EQ_INT(with, (int)g->node_count - 2);
    tp_tree_destroy(t);
    free(h);
}

/* A smooth 129 x 129 wave with a tilt, as a tree of 33-sample nodes (its grid in *h). */
static tp_tree* wave_tree(float** h_out)
{
    int w = 129, hg = 129;
    float* h = malloc(sizeof *h * w * hg);
    for (int y = 0; y < hg; y++)
        for (int x = 0; x < w; x++)
            h[(size_t)y * w + x] = 50.0f * sinf(x * 0.11f) * cosf(y * 0.07f) + 0.01f * x * y;
    *h_out = h;
    return tree_of(h, w, hg, 33);
}

TEST(levels_are_built_as_asked)
{
    float* h;
    tp_tree* t = wave_tree(&h);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_tree_info ti;
    tp_tree_get_info(t, &ti);
    int64_t leaf = tp_tree_node_id(g, 0, 1, 1);
    tp_node_tins *all = NULL, *some = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_node_tins_build(g->n, 0, tp_tree_samples(t, leaf), tp_tree_meta(t, leaf), NULL,
                                 ti.err_unit_steps, ~0u, &all, &err));
    ASSERT_OK(tp_node_tins_build(g->n, 0, tp_tree_samples(t, leaf), tp_tree_meta(t, leaf), NULL,
                                 ti.err_unit_steps, 1u << 3, &some, &err));
    int ca, cs;
    const tp_node_tin* ra = tp_node_tins_level(all, 3, &ca);
    const tp_node_tin* rs = tp_node_tins_level(some, 3, &cs);
    ASSERT_TRUE(ca > 0);
    ASSERT_EQ_INT(ca, cs);
    for (int j = 0; j < ca; j++) { /* the same rungs, alone or with the others */
        EXPECT_EQ_INT(ra[j].triangle_count, rs[j].triangle_count);
        EXPECT_EQ_INT(memcmp(ra[j].triangles, rs[j].triangles, 6 * ra[j].triangle_count), 0);
        EXPECT_TRUE(ra[j].own_steps == rs[j].own_steps);
    }
    for (int k = 0; k <= g->n; k++)
        if (k != 3)
            EXPECT_TRUE(tp_node_tins_level(some, k, &cs) == NULL && cs == 0);
    EXPECT_TRUE(tp_node_tins_bytes(some) < tp_node_tins_bytes(all));
    tp_node_tins_destroy(all);
    tp_node_tins_destroy(some);
    tp_tree_destroy(t);
    free(h);
}

TEST(the_cache_builds_once_and_prunes_by_residency_and_age)
{
    float* h;
    tp_tree* t = wave_tree(&h);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int64_t leaf = tp_tree_node_id(g, 0, 1, 1), other = tp_tree_node_id(g, 0, 0, 0);
    tp_tin_cache* c = NULL;
    ASSERT_OK(tp_tin_cache_create(t, &c, NULL));
    int built = -1;
    EXPECT_TRUE(tp_tin_cache_get(c, leaf, 3, &built) == NULL && built == 0);
    ASSERT_OK(tp_tin_cache_build(c, leaf, 3, NULL));
    ASSERT_OK(tp_tin_cache_build(c, leaf, 3, NULL)); /* once */
    const tp_node_tins* tins = tp_tin_cache_get(c, leaf, 3, &built);
    int count;
    EXPECT_TRUE(built == 1 && tins && tp_node_tins_level(tins, 3, &count) && count > 0);
    EXPECT_TRUE(tp_tin_cache_get(c, leaf, 2, &built) == NULL && built == 0);
    size_t bytes, levels, builds;
    tp_tin_cache_stats(c, &bytes, &levels, &builds);
    EXPECT_EQ_INT((int)levels, 1);
    EXPECT_EQ_INT((int)builds, 1);
    EXPECT_EQ_INT((int)bytes, (int)tp_node_tins_bytes(tins));
    /* drawn: kept by the age limit; not drawn for more frames than it: freed */
    tp_cut* cut = NULL;
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    int64_t nodes[1] = {leaf};
    int lv[1] = {3};
    ASSERT_OK(tp_cut_set_nodes(cut, nodes, lv, 1, NULL));
    for (int f = 0; f < 10; f++)
        tp_tin_cache_mark_drawn(c, cut);
    tp_tin_cache_prune(c, 5, 0);
    EXPECT_TRUE(tp_tin_cache_get(c, leaf, 3, &built) != NULL && built == 1);
    nodes[0] = other;
    ASSERT_OK(tp_cut_set_nodes(cut, nodes, lv, 1, NULL));
    for (int f = 0; f < 5; f++)
        tp_tin_cache_mark_drawn(c, cut);
    tp_tin_cache_prune(c, 5, 0); /* drawn 5 frames ago: kept */
    EXPECT_TRUE(tp_tin_cache_get(c, leaf, 3, &built) != NULL && built == 1);
    tp_tin_cache_mark_drawn(c, cut);
    tp_tin_cache_prune(c, 5, 0); /* 6 frames ago: freed */
    EXPECT_TRUE(tp_tin_cache_get(c, leaf, 3, &built) == NULL && built == 0);
    tp_tin_cache_stats(c, &bytes, &levels, NULL);
    EXPECT_EQ_INT((int)levels, 0);
    EXPECT_EQ_INT((int)bytes, 0);
    /* released by the stream: freed whatever its age; not resident: nothing built */
    ASSERT_OK(tp_tin_cache_build(c, leaf, 3, NULL));
    EXPECT_TRUE(tp_tin_cache_get(c, leaf, 3, &built) != NULL && built == 1);
    const uint16_t* samples = tp_tree_samples(t, leaf);
    tp_tree_detach(t, leaf);
    tp_tin_cache_prune(c, 0, 0);
    EXPECT_TRUE(tp_tin_cache_get(c, leaf, 3, &built) == NULL && built == 0);
    ASSERT_OK(tp_tin_cache_build(c, leaf, 3, NULL));
    EXPECT_TRUE(tp_tin_cache_get(c, leaf, 3, &built) == NULL && built == 0);
    tp_tree_attach(t, leaf, samples);
    tp_cut_destroy(cut);
    tp_tin_cache_destroy(c);
    tp_tree_destroy(t);
    free(h);
}

/* The byte budget of tp_tin_cache_prune: the levels drawn longest ago go first, down to the
 * budget, but never those drawn or built in the last two frames, whatever the budget. */
TEST(the_cache_keeps_its_byte_budget_oldest_first_but_never_what_is_drawn)
{
    float* h;
    tp_tree* t = wave_tree(&h);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int64_t leaf[4] = {tp_tree_node_id(g, 0, 0, 0), tp_tree_node_id(g, 0, 1, 0),
                       tp_tree_node_id(g, 0, 0, 1), tp_tree_node_id(g, 0, 1, 1)};
    tp_tin_cache* c = NULL;
    tp_cut* cut = NULL;
    ASSERT_OK(tp_tin_cache_create(t, &c, NULL));
    ASSERT_OK(tp_cut_create(t, &cut, NULL));
    int lv[1] = {3}, built;
    size_t each[4], bytes, levels;
    /* leaf i built and drawn at frame 2 i + 1 (leaf 0 drawn longest ago), then 3 frames of
     * nothing of them drawn */
    for (int i = 0; i < 4; i++) {
        ASSERT_OK(tp_tin_cache_build(c, leaf[i], 3, NULL));
        each[i] = tp_node_tins_bytes(tp_tin_cache_get(c, leaf[i], 3, &built));
        ASSERT_TRUE(each[i] > 0);
        ASSERT_OK(tp_cut_set_nodes(cut, &leaf[i], lv, 1, NULL));
        tp_tin_cache_mark_drawn(c, cut);
        tp_tin_cache_mark_drawn(c, cut);
    }
    int64_t parent = tp_tree_node_id(g, 1, 0, 0);
    int plv[1] = {2};
    ASSERT_OK(tp_cut_set_nodes(cut, &parent, plv, 1, NULL));
    for (int f = 0; f < 3; f++)
        tp_tin_cache_mark_drawn(c, cut);
    /* a budget of the two newest: leaves 0 and 1 go, 2 and 3 stay */
    tp_tin_cache_prune(c, 0, each[2] + each[3]);
    for (int i = 0; i < 4; i++)
        EXPECT_EQ_INT(tp_tin_cache_get(c, leaf[i], 3, &built) != NULL, i >= 2);
    tp_tin_cache_stats(c, &bytes, &levels, NULL);
    EXPECT_EQ_INT((int)levels, 2);
    EXPECT_EQ_INT((int)bytes, (int)(each[2] + each[3]));
    /* one byte under: leaf 2 goes too */
    tp_tin_cache_prune(c, 0, each[2] + each[3] - 1);
    EXPECT_TRUE(tp_tin_cache_get(c, leaf[2], 3, &built) == NULL && built == 0);
    EXPECT_TRUE(tp_tin_cache_get(c, leaf[3], 3, &built) != NULL);
    /* drawn in the last frame, or built since: kept under any budget */
    ASSERT_OK(tp_cut_set_nodes(cut, &leaf[3], lv, 1, NULL));
    tp_tin_cache_mark_drawn(c, cut);
    ASSERT_OK(tp_tin_cache_build(c, leaf[0], 3, NULL));
    tp_tin_cache_prune(c, 0, 1);
    EXPECT_TRUE(tp_tin_cache_get(c, leaf[3], 3, &built) != NULL);
    EXPECT_TRUE(tp_tin_cache_get(c, leaf[0], 3, &built) != NULL);
    /* a frame later (the next cut drew neither): still kept, a level built while a frame drew
     * is drawn by the cut after it */
    ASSERT_OK(tp_cut_set_nodes(cut, &parent, plv, 1, NULL));
    tp_tin_cache_mark_drawn(c, cut);
    tp_tin_cache_prune(c, 0, 1);
    EXPECT_TRUE(tp_tin_cache_get(c, leaf[3], 3, &built) != NULL);
    EXPECT_TRUE(tp_tin_cache_get(c, leaf[0], 3, &built) != NULL);
    /* a frame more, neither drawn: both go */
    tp_tin_cache_mark_drawn(c, cut);
    tp_tin_cache_prune(c, 0, 1);
    tp_tin_cache_stats(c, &bytes, &levels, NULL);
    EXPECT_EQ_INT((int)levels, 0);
    EXPECT_EQ_INT((int)bytes, 0);
    tp_cut_destroy(cut);
    tp_tin_cache_destroy(c);
    tp_tree_destroy(t);
    free(h);
}

TP_TEST_MAIN(TESTS)
