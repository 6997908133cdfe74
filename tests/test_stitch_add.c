/* test_stitch_add.c - crack removal by adding vertices (core/src/patch_stitch_add.c,
 * tp_patch_triangles_add): for every patch size up to n = 5, every level and every neighbour
 * configuration, the triangles tile the patch's square exactly (no zero-area or flipped
 * triangle, areas summing to the square, every inner edge shared by two triangles in opposite
 * directions) and each side's border edges are exactly the neighbour's own (so two patches
 * side by side share their edge whatever their levels: watertight); with nothing added, the
 * same triangles as the level's strip; with vertices added on some sides, every triangle of the
 * level's grid without an edge on those sides is drawn unchanged, and every drawn triangle lies
 * inside one of the grid's triangles (the vertex adding only refines the grid); on real DEMs
 * the measured error of those triangles never exceeds tp_patch_error_bound_add, while it does
 * exceed the grid's own bound. */
#include "tp_test.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#define TESTS(X)                                                                                   \
    X(every_configuration_tiles_the_square_and_matches_its_neighbours)                             \
    X(nothing_added_is_the_strip)                                                                  \
    X(only_the_triangles_on_sides_that_take_vertices_change)                                       \
    X(two_patches_side_by_side_share_their_edge)                                                   \
    X(levels_above_n_are_taken_as_n)                                                               \
    X(add_bound_holds_on_real_dems)                                                                \
    X(max_error_mode_refuses_vertex_adding)

enum { MAXN = 5, SIDE = (1 << MAXN) + 1, MAX_TRI = 2 * (1 << MAXN) * (1 << MAXN) + 4 * SIDE };

static uint32_t tri_[3 * MAX_TRI];

static long cross(int n, uint32_t a, uint32_t b, uint32_t c)
{
    const long s = (1L << n) + 1;
    const long ax = (long)a % s, ay = (long)a / s, bx = (long)b % s, by = (long)b / s,
               cx = (long)c % s, cy = (long)c / s;
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax);
}

/* The strips' sign of cross products in (column, row) (every real triangle has it). */
static long strip_sign(void)
{
    uint32_t idx[64];
    tp_strip_build_u32(1, idx, 64);
    return cross(1, idx[0], idx[1], idx[2]) > 0 ? 1 : -1;
}

/* Checks one configuration; returns 1 when every property holds (reports the first failure). */
static int check(int n, int k, const int nb[4], char* why, size_t cap)
{
    const size_t count = tp_patch_triangles_add(n, k, nb, tri_, MAX_TRI);
    if (count > MAX_TRI) {
        snprintf(why, cap, "%zu triangles", count);
        return 0;
    }
    if (tp_patch_triangles_add(n, k, nb, NULL, 0) != count) {
        snprintf(why, cap, "counting alone gives another count");
        return 0;
    }
    const long sign = strip_sign(), full = 1L << n, S = full + 1;
    long area2 = 0;
    /* every undirected edge: +1 for a -> b with a < b, -1 for b -> a (an inner edge sums to
       0, a border edge to +-1); kept in a sorted list */
    static uint64_t list[6 * MAX_TRI];
    size_t m = 0;
    for (size_t t = 0; t < count; ++t) {
        const uint32_t* p = tri_ + 3 * t;
        const long c = cross(n, p[0], p[1], p[2]);
        if (c == 0 || (c > 0) != (sign > 0)) {
            snprintf(why, cap, "triangle %zu (%u %u %u) has cross %ld", t, p[0], p[1], p[2], c);
            return 0;
        }
        area2 += c > 0 ? c : -c;
        for (int e = 0; e < 3; ++e) {
            const uint32_t a = p[e], b = p[(e + 1) % 3];
            list[m++] = a < b ? ((uint64_t)a << 33) | ((uint64_t)b << 1) | 1
                              : ((uint64_t)b << 33) | ((uint64_t)a << 1);
        }
    }
    if (area2 != 2 * full * full) {
        snprintf(why, cap, "twice the area %ld, the square's %ld", area2, 2 * full * full);
        return 0;
    }
    /* sort (insertion is too slow at n = 5: a small radix-free qsort) */
    for (size_t gap = m / 2; gap > 0; gap /= 2) /* shell sort */
        for (size_t i = gap; i < m; ++i)
            for (size_t j = i; j >= gap && list[j - gap] > list[j]; j -= gap) {
                const uint64_t x = list[j];
                list[j] = list[j - gap], list[j - gap] = x;
            }
    /* border edges expected: per side, the neighbour's stride (or the level's) */
    long stride[4];
    for (int s = 0; s < 4; ++s) {
        const int kn = nb && nb[s] != TP_NO_NEIGHBOR ? (nb[s] > n ? n : nb[s]) : -1;
        stride[s] = kn > k ? 1L << (n - kn) : 1L << (n - k);
    }
    size_t border = 0, expected_border = 0;
    for (int s = 0; s < 4; ++s)
        expected_border += (size_t)(full / stride[s]);
    for (size_t i = 0; i < m;) {
        size_t j = i;
        int fwd = 0, back = 0;
        while (j < m && (list[j] >> 1) == (list[i] >> 1)) {
            fwd += (int)(list[j] & 1), back += !(list[j] & 1);
            ++j;
        }
        const uint32_t a = (uint32_t)(list[i] >> 33), b = (uint32_t)((list[i] >> 1) & 0xffffffffu);
        const long ax = a % S, ay = a / S, bx = b % S, by = b / S;
        const int on_border =
            (ax == bx && (ax == 0 || ax == full)) || (ay == by && (ay == 0 || ay == full));
        if (on_border) {
            const int s = ay == by ? (ay == 0 ? TP_SIDE_TOP : TP_SIDE_BOTTOM)
                                   : (ax == full ? TP_SIDE_RIGHT : TP_SIDE_LEFT);
            const long len = ax == bx ? labs(by - ay) : labs(bx - ax);
            const long along = ax == bx ? (ay < by ? ay : by) : (ax < bx ? ax : bx);
            if (fwd + back != 1 || len != stride[s] || along % stride[s]) {
                snprintf(why, cap,
                         "border edge %u-%u (side %d): used %d times, length %ld, "
                         "the neighbour's stride %ld",
                         a, b, s, fwd + back, len, stride[s]);
                return 0;
            }
            border++;
        } else if (fwd != 1 || back != 1) {
            snprintf(why, cap, "inner edge %u-%u used %d + %d times", a, b, fwd, back);
            return 0;
        }
        i = j;
    }
    if (border != expected_border) {
        snprintf(why, cap, "%zu border edges, %zu expected", border, expected_border);
        return 0;
    }
    return 1;
}

TEST(every_configuration_tiles_the_square_and_matches_its_neighbours)
{
    int configs = 0, failed = 0;
    char why[256];
    for (int n = 0; n <= MAXN; ++n)
        for (int k = 0; k <= n; ++k) {
            /* each side: no neighbour, or one at k + 1 .. n (coarser or equal ones add nothing
               and are covered by "none") */
            const int options = n - k + 1;
            int total = 1;
            for (int s = 0; s < 4; ++s)
                total *= options;
            for (int c = 0; c < total; ++c) {
                int nb[4], x = c;
                for (int s = 0; s < 4; ++s) {
                    const int o = x % options;
                    x /= options;
                    nb[s] = o == 0 ? TP_NO_NEIGHBOR : k + o;
                }
                configs++;
                if (!check(n, k, nb, why, sizeof why)) {
                    if (failed++ < 5)
                        ADD_FAILURE("n %d, level %d, neighbours %d %d %d %d: %s", n, k, nb[0],
                                    nb[1], nb[2], nb[3], why);
                }
            }
        }
    tp_test_note("%d configurations (n <= %d), %d failed", configs, MAXN, failed);
    EXPECT_EQ_INT(0, failed);
    EXPECT_EQ_INT(3724, configs); /* sum over n of 1^4 + 2^4 + ... + (n + 1)^4 */
}

/* With nothing added the triangles are the strip's real ones, in the same order per cell. */
TEST(nothing_added_is_the_strip)
{
    for (int n = 0; n <= MAXN; ++n)
        for (int k = 0; k <= n; ++k) {
            const int same[4] = {k, k - 1, TP_NO_NEIGHBOR, 0};
            const size_t count = tp_patch_triangles_add(n, k, same, tri_, MAX_TRI);
            ASSERT_EQ_INT(2 << (2 * k), (int)count);
            /* the strip of level k, decoded, mapped to this patch's samples */
            static uint32_t idx[20000];
            const size_t ni = tp_strip_index_count(k);
            tp_strip_build_u32(k, idx, ni);
            const uint32_t v = (1u << k) + 1, step = 1u << (n - k), S = (1u << n) + 1;
            size_t found = 0;
            for (size_t i = 2; i < ni; ++i) {
                uint32_t a = idx[i - 2], b = idx[i - 1], c = idx[i];
                if (a == b || b == c || a == c)
                    continue;
                if (i % 2) { /* odd triangles swap their first two */
                    const uint32_t t = a;
                    a = b, b = t;
                }
                const uint32_t m[3] = {(a / v) * step * S + (a % v) * step,
                                       (b / v) * step * S + (b % v) * step,
                                       (c / v) * step * S + (c % v) * step};
                for (size_t t = 0; t < count; ++t) {
                    const uint32_t* p = tri_ + 3 * t;
                    for (int r = 0; r < 3; ++r) /* the same triangle, any rotation */
                        if (p[r] == m[0] && p[(r + 1) % 3] == m[1] && p[(r + 2) % 3] == m[2]) {
                            found++;
                            r = 3, t = count;
                        }
                }
            }
            EXPECT_EQ_INT((int)count, (int)found);
        }
}

/* A triangle as a key that ignores its rotation (the smallest index first, order kept). */
static uint64_t tri_key(const uint32_t* p)
{
    const int r = p[0] < p[1] ? (p[0] < p[2] ? 0 : 2) : (p[1] < p[2] ? 1 : 2);
    return ((uint64_t)p[r] << 42) | ((uint64_t)p[(r + 1) % 3] << 21) | p[(r + 2) % 3];
}

static int cmp_u64(const void* a, const void* b)
{
    const uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
    return x < y ? -1 : x > y;
}

/* One configuration with vertices added on some sides against the plain level-k grid (the
 * triangles with no neighbour): 1 when every grid triangle with no edge on a side that takes
 * vertices (and so every one outside those sides' border cells) is drawn as it is, and every
 * drawn triangle lies inside one grid triangle. */
static int check_refines_the_grid(int n, int k, const int nb[4], char* why, size_t cap)
{
    static uint32_t plain[3 * MAX_TRI];
    static uint64_t keys[MAX_TRI];
    const size_t count = tp_patch_triangles_add(n, k, nb, tri_, MAX_TRI);
    const size_t np = tp_patch_triangles_add(n, k, NULL, plain, MAX_TRI);
    const long full = 1L << n, S = full + 1, step = 1L << (n - k);
    int adds[4];
    for (int s = 0; s < 4; ++s)
        adds[s] = nb[s] != TP_NO_NEIGHBOR && (nb[s] > n ? n : nb[s]) > k;
    for (size_t t = 0; t < count; ++t)
        keys[t] = tri_key(tri_ + 3 * t);
    qsort(keys, count, sizeof *keys, cmp_u64);
    for (size_t t = 0; t < np; ++t) {
        const uint32_t* p = plain + 3 * t;
        int on_adding_side = 0, in_adding_border_cell = 0;
        long minx = full, miny = full;
        for (int e = 0; e < 3; ++e) {
            const long ax = p[e] % S, ay = p[e] / S, bx = p[(e + 1) % 3] % S,
                       by = p[(e + 1) % 3] / S;
            minx = ax < minx ? ax : minx, miny = ay < miny ? ay : miny;
            on_adding_side |= (ay == 0 && by == 0 && adds[TP_SIDE_TOP]) ||
                              (ax == full && bx == full && adds[TP_SIDE_RIGHT]) ||
                              (ay == full && by == full && adds[TP_SIDE_BOTTOM]) ||
                              (ax == 0 && bx == 0 && adds[TP_SIDE_LEFT]);
        }
        /* the cell (minx, miny) .. + step holds the grid triangle */
        in_adding_border_cell =
            (miny == 0 && adds[TP_SIDE_TOP]) || (minx + step == full && adds[TP_SIDE_RIGHT]) ||
            (miny + step == full && adds[TP_SIDE_BOTTOM]) || (minx == 0 && adds[TP_SIDE_LEFT]);
        const uint64_t key = tri_key(p);
        const int found = bsearch(&key, keys, count, sizeof *keys, cmp_u64) != NULL;
        if (!on_adding_side && !found) {
            snprintf(why, cap,
                     "grid triangle %u %u %u (%s a border cell that takes vertices) "
                     "not drawn",
                     p[0], p[1], p[2], in_adding_border_cell ? "in" : "outside");
            return 0;
        }
        if (on_adding_side && found) {
            snprintf(why, cap, "grid triangle %u %u %u drawn whole across added vertices", p[0],
                     p[1], p[2]);
            return 0;
        }
    }
    /* every drawn triangle inside the grid triangle holding its centroid (strictly inside it:
       a non-degenerate triangle inside a grid triangle) */
    for (size_t t = 0; t < count; ++t) {
        const uint32_t* p = tri_ + 3 * t;
        long sx = 0, sy = 0;
        for (int e = 0; e < 3; ++e)
            sx += p[e] % S, sy += p[e] / S;
        const long x0 = sx / (3 * step) * step, y0 = sy / (3 * step) * step;
        const int upper_left = (sx - 3 * x0) + (sy - 3 * y0) < 3 * step;
        for (int e = 0; e < 3; ++e) {
            const long x = p[e] % S, y = p[e] / S, d = (x - x0) + (y - y0);
            const int inside = upper_left ? x >= x0 && y >= y0 && d <= step
                                          : x <= x0 + step && y <= y0 + step && d >= step;
            if (!inside) {
                snprintf(why, cap,
                         "triangle %u %u %u crosses the grid triangle %s of cell "
                         "(%ld, %ld)",
                         p[0], p[1], p[2], upper_left ? "upper left" : "lower right", x0 / step,
                         y0 / step);
                return 0;
            }
        }
    }
    /* Euler: every vertex added on an edge splits one more triangle off */
    size_t added = 0;
    for (int s = 0; s < 4; ++s)
        if (adds[s])
            added += (size_t)(full / (1L << (n - (nb[s] > n ? n : nb[s])))) - ((size_t)1 << k);
    if (count != np + added) {
        snprintf(why, cap, "%zu triangles: the grid's %zu and %zu added vertices", count, np,
                 added);
        return 0;
    }
    return 1;
}

TEST(only_the_triangles_on_sides_that_take_vertices_change)
{
    int configs = 0, failed = 0, partial = 0;
    char why[256];
    for (int n = 0; n <= MAXN; ++n)
        for (int k = 0; k <= n; ++k) {
            const int options = n - k + 1;
            int total = 1;
            for (int s = 0; s < 4; ++s)
                total *= options;
            for (int c = 0; c < total; ++c) {
                int nb[4], x = c, adding = 0;
                for (int s = 0; s < 4; ++s) {
                    const int o = x % options;
                    x /= options;
                    nb[s] = o == 0 ? TP_NO_NEIGHBOR : k + o;
                    adding += o != 0;
                }
                configs++;
                partial += adding > 0 && adding < 4;
                if (!check_refines_the_grid(n, k, nb, why, sizeof why) && failed++ < 5)
                    ADD_FAILURE("n %d, level %d, neighbours %d %d %d %d: %s", n, k, nb[0], nb[1],
                                nb[2], nb[3], why);
            }
        }
    tp_test_note("%d configurations (n <= %d), %d with vertices added on 1 to 3 sides, %d failed",
                 configs, MAXN, partial, failed);
    EXPECT_EQ_INT(0, failed);
    EXPECT_EQ_INT(3724, configs);
}

/* A level-1 patch beside a level-4 one (n = 5): the coarse patch's right side and the fine
 * patch's left side have the same vertices (every 2nd sample) and the same edges. */
TEST(two_patches_side_by_side_share_their_edge)
{
    enum { N = 5, F = 1 << N };
    const int coarse_nb[4] = {TP_NO_NEIGHBOR, 4, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
    const int fine_nb[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, 1};
    int coarse[F + 1] = {0}, fine[F + 1] = {0};
    size_t nc = tp_patch_triangles_add(N, 1, coarse_nb, tri_, MAX_TRI);
    for (size_t t = 0; t < nc; ++t)
        for (int e = 0; e < 3; ++e) {
            const uint32_t v = tri_[3 * t + e];
            if ((int)(v % (F + 1)) == F)
                coarse[v / (F + 1)] = 1;
        }
    size_t nf = tp_patch_triangles_add(N, 4, fine_nb, tri_, MAX_TRI);
    for (size_t t = 0; t < nf; ++t)
        for (int e = 0; e < 3; ++e) {
            const uint32_t v = tri_[3 * t + e];
            if (v % (F + 1) == 0)
                fine[v / (F + 1)] = 1;
        }
    int shared = 0;
    for (int y = 0; y <= F; ++y) {
        EXPECT_EQ_INT(fine[y], coarse[y]);
        shared += fine[y];
        EXPECT_EQ_INT(y % 2 == 0, fine[y]);
    }
    EXPECT_EQ_INT(F / 2 + 1, shared);
}

TEST(levels_above_n_are_taken_as_n)
{
    char why[256];
    const int nb[4] = {9, 3, TP_NO_NEIGHBOR, 7};
    const size_t a = tp_patch_triangles_add(3, 0, nb, NULL, 0);
    const int capped[4] = {3, 3, TP_NO_NEIGHBOR, 3};
    EXPECT_EQ_INT((int)tp_patch_triangles_add(3, 0, capped, NULL, 0), (int)a);
    EXPECT_TRUE(check(3, 0, nb, why, sizeof why));
    /* the level-0 grid's 2 triangles, one more per vertex added: 7 on top, right and left */
    EXPECT_EQ_INT(2 + 7 + 7 + 7, (int)a);
}

#ifndef TP_TEST_NO_IO
typedef struct measured {
    const tp_terrain* t;
    double max_m;
} measured;

static void measure_visit(int x, int y, double z, void* user)
{
    measured* m = user;
    const double s = tp_terrain_sample(m->t, x, y);
    if (!isnan(s) && fabs(z - s) > m->max_m)
        m->max_m = fabs(z - s);
}

/* The exact error (m, against the decoded samples) of patch p drawn by tp_patch_triangles_add
 * at level k with neighbours nb; v holds its level-n vertices. */
static double add_error(const tp_terrain* t, int n, int k, const int nb[4], const tp_vertex* v)
{
    measured m = {t, 0};
    const size_t count = tp_patch_triangles_add(n, k, nb, tri_, MAX_TRI);
    for (size_t i = 0; i < count; ++i) {
        const tp_vertex *a = &v[tri_[3 * i]], *b = &v[tri_[3 * i + 1]], *c = &v[tri_[3 * i + 2]];
        const int32_t pa[2] = {a->x, a->y}, pb[2] = {b->x, b->y}, pc[2] = {c->x, c->y};
        tp_triangle_rasterize(pa, pb, pc, a->z_m, b->z_m, c->z_m, measure_visit, &m);
    }
    return m.max_m;
}
#endif

/* Every complete patch of two real DEMs (every 2nd of Mt Hood's), every level below n, with
 * vertices added on one side (each finer level), on two sides meeting at a corner (both
 * corners that share a grid triangle, levels k + 1 and n either way) and on all four (k + 1,
 * n): the error measured against the samples is within tp_patch_error_bound_add less the
 * quantisation error; with nothing added the bound is tp_patch_error_bound's. */
TEST(add_bound_holds_on_real_dems)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    const char* files[2] = {"storml_elev_orig.tif", "lf_elev_220_mt_hood_utm.tif"};
    for (int f = 0; f < 2; ++f) {
        char path[1024];
        tp_dem* dem = NULL;
        tp_terrain* t = NULL;
        tp_error err;
        REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", files[f]);
        ASSERT_OK(tp_dem_read(path, &dem, &err));
        tp_terrain_desc d = tp_dem_terrain_desc(dem, 17, TP_FIT_PAD);
        ASSERT_OK(tp_terrain_create(&d, &t, &err));
        tp_terrain_info ti;
        tp_terrain_get_info(t, &ti);
        /* before its table is made, a side that takes vertices is bounded by the height range:
         * looser than (or as) the table's, never tighter */
        const int all_n[4] = {ti.n, ti.n, ti.n, ti.n};
        const double loose = tp_patch_error_bound_add(t, 0, 0, all_n);
        ASSERT_OK(tp_terrain_prepare_stitch_add(t, &err));
        ASSERT_OK(tp_terrain_prepare_stitch_add(t, &err)); /* again: a no-op */
        EXPECT_GE(loose, tp_patch_error_bound_add(t, 0, 0, all_n));
        EXPECT_GE(loose, tp_patch_error_bound(t, 0, 0, NULL));
        const int n = ti.n, side = (1 << n) + 1;
        ASSERT_TRUE(n <= MAXN);
        static tp_vertex v[SIDE * SIDE];
        long checked = 0, over_delta = 0, failed = 0;
        double worst_ratio = 0; /* measured / the grid's bound, where vertices are added */
        for (int p = 0; p < ti.patch_count; p += f + 1) {
            tp_patch_info pi;
            tp_patch_get_info(t, p, &pi);
            if (!pi.complete)
                continue;
            tp_patch_vertices(t, p, n, NULL, v, (size_t)side * side);
            for (int k = 0; k < n; ++k) {
                const double grid = tp_patch_error_bound(t, p, k, NULL);
                EXPECT_EQ_DBL(grid, tp_patch_error_bound_add(t, p, k, NULL));
                int configs[4 * MAXN + 8][4], nc = 0;
                for (int s = 0; s < 4; ++s)
                    for (int kn = k + 1; kn <= n; ++kn) {
                        int* c = configs[nc++];
                        c[0] = c[1] = c[2] = c[3] = TP_NO_NEIGHBOR;
                        c[s] = kn;
                    }
                const int pairs[2][2] = {{TP_SIDE_TOP, TP_SIDE_LEFT},
                                         {TP_SIDE_RIGHT, TP_SIDE_BOTTOM}};
                for (int pr = 0; pr < 2; ++pr)
                    for (int o = 0; o < 3; ++o) {
                        int* c = configs[nc++];
                        c[0] = c[1] = c[2] = c[3] = TP_NO_NEIGHBOR;
                        c[pairs[pr][0]] = o == 1 ? k + 1 : n;
                        c[pairs[pr][1]] = o == 2 ? k + 1 : n;
                    }
                for (int o = 0; o < 2; ++o) {
                    int* c = configs[nc++];
                    c[0] = c[1] = c[2] = c[3] = o ? n : k + 1;
                }
                for (int i = 0; i < nc; ++i) {
                    const double e = add_error(t, n, k, configs[i], v);
                    const double b = tp_patch_error_bound_add(t, p, k, configs[i]);
                    checked++;
                    if (e > b - ti.quant_max_error_m + 1e-6 && failed++ < 5)
                        ADD_FAILURE("%s patch %d level %d neighbours %d %d %d %d: measured %.4f m "
                                    "> bound %.4f m",
                                    files[f], p, k, configs[i][0], configs[i][1], configs[i][2],
                                    configs[i][3], e, b);
                    if (e > grid - ti.quant_max_error_m + 1e-6)
                        over_delta++;
                    if (grid - ti.quant_max_error_m > 0 &&
                        e / (grid - ti.quant_max_error_m) > worst_ratio)
                        worst_ratio = e / (grid - ti.quant_max_error_m);
                }
            }
        }
        tp_test_note("%s: %ld patch configurations, %ld above the grid's bound (up to %.2fx), "
                     "%ld above tp_patch_error_bound_add",
                     files[f], checked, over_delta, worst_ratio, failed);
        EXPECT_EQ_INT(0, failed);
        EXPECT_GT(over_delta, 0); /* the grid's bound alone does not hold: this proves something */
        tp_terrain_destroy(t);
        tp_dem_destroy(dem);
    }
#endif
}


/* The max-error mode measures vertex moving's geometry: with vertex adding it refuses to
 * update (it used to ignore the setting and select for the other geometry). */
TEST(max_error_mode_refuses_vertex_adding)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    char path[1024];
    tp_dem* dem = NULL;
    tp_terrain* t = NULL;
    tp_selection* sel = NULL;
    tp_error err;
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif");
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    tp_terrain_desc d = tp_dem_terrain_desc(dem, 17, TP_FIT_PAD);
    ASSERT_OK(tp_terrain_create(&d, &t, &err));
    ASSERT_OK(tp_selection_create(t, &sel, &err));
    tp_lod_params lp = {.mode = TP_LOD_MAX_ERROR, .max_error_m = 5};
    ASSERT_OK(tp_selection_update(sel, NULL, &lp, &err));
    tp_selection_set_stitch_add(sel, 1);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_selection_update(sel, NULL, &lp, &err));
    EXPECT_CONTAINS(err.message, "max-error mode");
    tp_selection_set_stitch_add(sel, 0);
    EXPECT_OK(tp_selection_update(sel, NULL, &lp, &err));
    tp_selection_destroy(sel);
    tp_terrain_destroy(t);
    tp_dem_destroy(dem);
#endif
}

TP_TEST_MAIN(TESTS)
