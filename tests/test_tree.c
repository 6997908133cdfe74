/*
 * test_tree.c - the hierarchy's data (issue 12): geometry (ids, parents, children, roots),
 * node metas against brute force on real data, the band builder, voids.
 *
 * The brute force draws each node the way the header says a node is drawn: the level-k
 * vertices of a patch (tp_patch_vertices on a stencil terrain of one patch gives the lattice
 * positions after crack removal, in level-k vertex units times 2^(n-k)), placed at the node's
 * samples (stride 2^s), decoded heights from the tree's resident samples, and rasterised over
 * the FULL-resolution lattice (tp_triangle_rasterize): every full-resolution sample under a
 * drawn triangle is compared with the triangle there.
 */
#include "tp_test_geom.h"

/* ---------------------------------------------------------------------------------------------
 * Fixtures
 */

/* A crop of N42E001.hgt (SRTM3, 1201 x 1201 big-endian int16, row 0 north, -32768 = void). */
static float* hgt_crop(int x0, int y0, int w, int h)
{
    char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", "N42E001.hgt");
    FILE* f = fopen(path, "rb");
    if (!f)
        FAIL("cannot open %s", path);
    unsigned char* raw = (unsigned char*)malloc((size_t)1201 * 1201 * 2);
    size_t got = raw ? fread(raw, 1, (size_t)1201 * 1201 * 2, f) : 0;
    fclose(f);
    if (got != (size_t)1201 * 1201 * 2) {
        free(raw);
        FAIL("%s: expected %d bytes, read %zu", path, 1201 * 1201 * 2, got);
    }
    float* out = (float*)malloc(sizeof(float) * (size_t)w * h);
    ASSERT_TRUE(out != NULL);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            size_t i = ((size_t)(y0 + y) * 1201 + (size_t)(x0 + x)) * 2;
            int16_t v = (int16_t)((raw[i] << 8) | raw[i + 1]);
            out[(size_t)y * w + x] = v == -32768 ? NAN : (float)v;
        }
    free(raw);
    return out;
}

static double quantised(const float* src, int w, int h, int x, int y, double step)
{
    if (x >= w || y >= h || !isfinite(src[(size_t)y * w + x]))
        return NAN;
    return floor(src[(size_t)y * w + x] / step + 0.5) * step;
}

/* ---------------------------------------------------------------------------------------------
 * Geometry
 */
static int64_t count_nodes(int cols, int rows, int scales)
{
    int64_t c = 0;
    for (int s = 0; s < scales; s++)
        c += (int64_t)(cols >> s) * (rows >> s);
    return c;
}

static void check_geometry(int w, int h, int patch_size)
{
    tp_tree_geometry g;
    tp_error err;
    ASSERT_OK(tp_tree_geometry_init(w, h, patch_size, &g, &err));
    int ps = patch_size - 1;
    int cols = (w - 1 + ps - 1) / ps, rows = (h - 1 + ps - 1) / ps;
    cols = cols < 1 ? 1 : cols;
    rows = rows < 1 ? 1 : rows;
    ASSERT_EQ_INT(cols, g.cols);
    ASSERT_EQ_INT(rows, g.rows);
    ASSERT_EQ_INT(cols * ps + 1, g.width);
    ASSERT_EQ_INT(rows * ps + 1, g.height);
    int scales = 0;
    while ((1 << scales) <= cols && (1 << scales) <= rows)
        scales++;
    ASSERT_EQ_INT(scales, g.scales);
    ASSERT_EQ_INT(count_nodes(cols, rows, scales), g.node_count);
    /* ids from the top scale down */
    ASSERT_EQ_INT(0, g.first_node[scales - 1]);
    int64_t roots = 0, seen = 0;
    for (int s = scales - 1; s >= 0; s--)
        for (int r = 0; r < rows >> s; r++)
            for (int c = 0; c < cols >> s; c++) {
                int64_t id = tp_tree_node_id(&g, s, c, r);
                ASSERT_EQ_INT(seen, id); /* dense, in order */
                seen++;
                int ls, lc, lr;
                tp_tree_node_locate(&g, id, &ls, &lc, &lr);
                ASSERT_TRUE(ls == s && lc == c && lr == r);
                /* the parent exists iff its whole square does */
                int has_parent = s + 1 < scales && ((c / 2 + 1) << (s + 1)) <= cols &&
                                 ((r / 2 + 1) << (s + 1)) <= rows;
                int64_t p = tp_tree_node_parent(&g, id);
                if (!has_parent) {
                    ASSERT_EQ_INT(-1, p);
                    roots++;
                } else {
                    ASSERT_EQ_INT(tp_tree_node_id(&g, s + 1, c / 2, r / 2), p);
                    ASSERT_EQ_INT(id, tp_tree_node_child(&g, p, (c & 1) + 2 * (r & 1)));
                }
                if (s >= 1)
                    for (int q = 0; q < 4; q++) {
                        int64_t ch = tp_tree_node_child(&g, id, q);
                        ASSERT_EQ_INT(id, tp_tree_node_parent(&g, ch));
                        tp_tree_node_locate(&g, ch, &ls, &lc, &lr);
                        ASSERT_TRUE(ls == s - 1 && lc == 2 * c + (q & 1) && lr == 2 * r + (q >> 1));
                    }
            }
    ASSERT_EQ_INT(g.node_count, seen);
    ASSERT_EQ_INT(roots, g.root_count);
    int64_t* list = (int64_t*)malloc(sizeof(int64_t) * (size_t)roots);
    ASSERT_TRUE(list != NULL);
    tp_tree_roots(&g, list, (size_t)roots);
    for (int64_t i = 0; i < roots; i++) {
        EXPECT_EQ_INT(-1, tp_tree_node_parent(&g, list[i]));
        if (i > 0)
            EXPECT_TRUE(list[i] > list[i - 1]);
    }
    /* every leaf lies under exactly one root: its chain of parents ends at one of them, and
     * the roots' areas add up to the whole grid */
    int64_t area = 0;
    for (int64_t i = 0; i < roots; i++) {
        int s, c, r;
        tp_tree_node_locate(&g, list[i], &s, &c, &r);
        area += (int64_t)1 << (2 * s);
    }
    EXPECT_EQ_INT((int64_t)cols * rows, area);
    for (int r = 0; r < rows; r++)
        for (int c = 0; c < cols; c++) {
            int64_t id = tp_tree_node_id(&g, 0, c, r), top = id;
            while (tp_tree_node_parent(&g, top) >= 0)
                top = tp_tree_node_parent(&g, top);
            int found = 0;
            for (int64_t i = 0; i < roots; i++)
                found += list[i] == top;
            if (found != 1)
                FAIL("%dx%d: leaf (%d,%d) reaches node %lld, not a listed root", w, h, c, r,
                     (long long)top);
        }
    free(list);
}

TEST(geometry_hard_sizes)
{
    static const int sizes[][2] = {{1, 1},      {2, 2},     {17, 17}, {18, 18},
                                   {1201, 1201}, {1013, 799}, {145, 17}, {16 * 5 + 1, 16 * 3 + 2}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++) {
        check_geometry(sizes[i][0], sizes[i][1], 17);
        check_geometry(sizes[i][0], sizes[i][1], 65);
    }
}

TEST(geometry_known_counts)
{
    tp_tree_geometry g;
    /* 1201 at n = 4: 75 leaves per side (odd), scales 0..6 */
    ASSERT_OK(tp_tree_geometry_init(1201, 1201, 17, &g, NULL));
    EXPECT_EQ_INT(75, g.cols);
    EXPECT_EQ_INT(7, g.scales);
    EXPECT_EQ_INT(5625 + 1369 + 324 + 81 + 16 + 4 + 1, g.node_count);
    /* roots per scale: nodes minus 4 x the scale above (top 1, s3 81 - 64, s1, s0) */
    EXPECT_EQ_INT(1 + 0 + 0 + (81 - 64) + 0 + (1369 - 1296) + (5625 - 5476), g.root_count);
    /* 1x1 and 2x2: one leaf, one root */
    ASSERT_OK(tp_tree_geometry_init(1, 1, 17, &g, NULL));
    EXPECT_TRUE(g.cols == 1 && g.rows == 1 && g.node_count == 1 && g.root_count == 1);
    EXPECT_EQ_INT(17, g.width);
    ASSERT_OK(tp_tree_geometry_init(18, 18, 17, &g, NULL));
    EXPECT_TRUE(g.cols == 2 && g.rows == 2 && g.scales == 2 && g.node_count == 5 &&
                g.root_count == 1);
}

TEST(geometry_rejects_bad_sizes)
{
    tp_tree_geometry g, before;
    memset(&g, 0x5a, sizeof g);
    before = g;
    tp_error err;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_geometry_init(0, 5, 17, &g, &err));
    EXPECT_CONTAINS(err.message, "0x5");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_geometry_init(100, 100, 16, &g, &err));
    EXPECT_CONTAINS(err.message, "got 16");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_geometry_init(100, (1 << 30) + 1, 17, &g, NULL));
    EXPECT_TRUE(memcmp(&g, &before, sizeof g) == 0);
}

/* ---------------------------------------------------------------------------------------------
 * Brute force of one node at level k with neighbour levels nb
 */
typedef struct brute {
    const tp_tree* t;
    double max_m; /* true error */
    size_t samples;
} brute;

static void brute_visit(int x, int y, double z, void* user)
{
    brute* b = (brute*)user;
    double f = tp_tree_sample(b->t, x, y); /* the leaves are resident: full resolution */
    if (isnan(f))
        return;
    double e = fabs(z - f);
    b->max_m = e > b->max_m ? e : b->max_m;
    b->samples++;
}

/* The stencil: one patch of size 2^n+1; tp_patch_vertices gives lattice positions. */
static double node_true_error(const tp_tree* t, const tp_terrain* stencil, int64_t node, int k,
                              const int nb[4], tp_vertex* vbuf, uint32_t* tbuf)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int s, c, r;
    tp_tree_node_locate(g, node, &s, &c, &r);
    int v = (1 << k) + 1;
    tp_patch_vertices(stencil, 0, k, nb, vbuf, (size_t)v * v);
    int64_t x0 = (int64_t)c << (g->n + s), y0 = (int64_t)r << (g->n + s);
    for (int i = 0; i < v * v; i++) {
        vbuf[i].x = (int32_t)(x0 + ((int64_t)vbuf[i].x << s));
        vbuf[i].y = (int32_t)(y0 + ((int64_t)vbuf[i].y << s));
        /* drawn iff the ORIGINAL vertex is drawn (as tp_patch_vertices marks it) */
        int oi = i % v, oj = i / v, stride = 1 << (g->n - k + s);
        double zo = tp_tree_sample(t, (int)(x0 + (int64_t)oi * stride),
                                   (int)(y0 + (int64_t)oj * stride));
        double z = tp_tree_sample(t, vbuf[i].x, vbuf[i].y);
        vbuf[i].z_m = (float)z;
        vbuf[i].cls = isnan(zo) || isnan(z) ? TP_SAMPLE_NODATA : TP_SAMPLE_VALID;
    }
    /* An incomplete node below a leaf's level n draws a triangle only where every
     * full-resolution sample of its bounding box is drawn (tp_node_mask_from_q): all of them
     * are vertices' of the vertex rule then, so filter the vertex rule's triangles. */
    int mask_rule = !(tp_tree_meta(t, node)->flags & TP_NODE_COMPLETE) && !(s == 0 && k == g->n);
    size_t nt = tp_patch_triangles(vbuf, k, tbuf, (size_t)2 << (2 * k));
    brute b = {t, 0, 0};
    for (size_t i = 0; i < nt; i++) {
        const tp_vertex *A = &vbuf[tbuf[3 * i]], *B = &vbuf[tbuf[3 * i + 1]],
                        *C = &vbuf[tbuf[3 * i + 2]];
        int32_t a[2] = {A->x, A->y}, bb[2] = {B->x, B->y}, cc[2] = {C->x, C->y};
        if (mask_rule) {
            int whole = 1;
            int bx0 = A->x < B->x ? A->x : B->x, bx1 = A->x > B->x ? A->x : B->x;
            int by0 = A->y < B->y ? A->y : B->y, by1 = A->y > B->y ? A->y : B->y;
            bx0 = C->x < bx0 ? C->x : bx0, bx1 = C->x > bx1 ? C->x : bx1;
            by0 = C->y < by0 ? C->y : by0, by1 = C->y > by1 ? C->y : by1;
            for (int y = by0; y <= by1 && whole; y++)
                for (int x = bx0; x <= bx1 && whole; x++)
                    whole = !isnan(tp_tree_sample(t, x, y));
            if (!whole)
                continue;
        }
        /* heights in double from the decoded samples (z_m is a float) */
        tp_triangle_rasterize(a, bb, cc, tp_tree_sample(t, A->x, A->y),
                              tp_tree_sample(t, B->x, B->y), tp_tree_sample(t, C->x, C->y),
                              brute_visit, &b);
    }
    return b.max_m;
}

static int cmp_dbl(const void* a, const void* b)
{
    double x = *(const double*)a, y = *(const double*)b;
    return x < y ? -1 : x > y;
}

/* Every node, every level, no neighbours and random neighbour levels: true <= bound. Also the
 * area range and flags against the source. Prints the median true/bound ratio. */
static void check_bounds(const float* src, int w, int h, int patch_size, int trials)
{
    tp_tree* t = NULL;
    tp_error err;
    ASSERT_OK(tp_tree_create_from_grid(src, (size_t)w * h, w, h, NULL, patch_size, 0, &t, &err));
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int n = g->n, side = patch_size;
    float* zero = (float*)calloc((size_t)side * side, sizeof(float));
    ASSERT_TRUE(zero != NULL);
    tp_terrain* stencil = tpt_terrain_create(zero, side, side, side, TP_FIT_PAD, NULL);
    free(zero);
    tp_vertex* vbuf = (tp_vertex*)malloc(sizeof(tp_vertex) * (size_t)side * side);
    uint32_t* tbuf = (uint32_t*)malloc(sizeof(uint32_t) * 6 * (size_t)(side - 1) * (side - 1));
    ASSERT_TRUE(vbuf && tbuf);
    /* the tree's own step and unit: from the metas of the decoded grid */
    double step = 0, unit = 0;
    {
        /* integral heights: 1 m; the unit from the global range */
        double lo = INFINITY, hi = -INFINITY;
        for (size_t i = 0; i < (size_t)w * h; i++)
            if (isfinite(src[i])) {
                lo = src[i] < lo ? src[i] : lo;
                hi = src[i] > hi ? src[i] : hi;
            }
        step = 1;
        unit = tp_tree_err_unit_steps(hi - lo);
        EXPECT_EQ_DBL(1.0 / 16, unit);
    }
    tp_rng rng = tp_rng_seed(12);
    size_t ratio_count[2] = {0, 0};
    double* by_scale[2];
    by_scale[0] = (double*)malloc(sizeof(double) * (size_t)g->node_count * (n + 1));
    by_scale[1] = (double*)malloc(sizeof(double) * (size_t)g->node_count * (n + 1));
    ASSERT_TRUE(by_scale[0] && by_scale[1]);
    for (int64_t id = 0; id < g->node_count; id++) {
        const tp_node_meta* m = tp_tree_meta(t, id);
        int s, c, r;
        tp_tree_node_locate(g, id, &s, &c, &r);
        /* area range and flags, brute force over the source */
        int span = 1 << (n + s), x0 = c * span, y0 = r * span;
        double lo = INFINITY, hi = -INFINITY;
        int all = 1;
        for (int y = y0; y <= y0 + span; y++)
            for (int x = x0; x <= x0 + span; x++) {
                double z = quantised(src, w, h, x, y, step);
                if (isnan(z)) {
                    all = 0;
                    continue;
                }
                lo = z < lo ? z : lo;
                hi = z > hi ? z : hi;
            }
        EXPECT_EQ_INT(all, (m->flags & TP_NODE_COMPLETE) != 0);
        EXPECT_EQ_INT(lo <= hi, (m->flags & TP_NODE_HAS_DRAWN) != 0);
        if (lo <= hi) {
            EXPECT_EQ_DBL(lo, m->area_qmin * step);
            EXPECT_EQ_DBL(hi, m->area_qmax * step);
        }
        for (int k = 0; k <= n; k++) {
            double truth = node_true_error(t, stencil, id, k, NULL, vbuf, tbuf);
            double bound = tp_node_error_bound(m, n, k, NULL, step, unit);
            if (truth > bound + 1e-9)
                ADD_FAILURE("node %lld (s %d, %d, %d) level %d: true %.4f m > bound %.4f m",
                            (long long)id, s, c, r, k, truth, bound);
            if (bound > 0 && (m->flags & TP_NODE_COMPLETE) && k < n)
                by_scale[s > 0][ratio_count[s > 0]++] = truth / bound;
            for (int trial = 0; trial < trials && k >= 1; trial++) {
                int nb[4];
                for (int q = 0; q < 4; q++) {
                    int pick = tp_rng_int(&rng, -1, n);
                    nb[q] = pick < 0 ? TP_NO_NEIGHBOR : pick % k; /* mostly coarser */
                    if (tp_rng_int(&rng, 0, 3) == 0)
                        nb[q] = pick < 0 ? TP_NO_NEIGHBOR : pick;
                }
                double tr = node_true_error(t, stencil, id, k, nb, vbuf, tbuf);
                double bd = tp_node_error_bound(m, n, k, nb, step, unit);
                if (tr > bd + 1e-9)
                    ADD_FAILURE("node %lld (s %d) level %d nb %d %d %d %d: true %.4f m > bound "
                                "%.4f m",
                                (long long)id, s, k, nb[0], nb[1], nb[2], nb[3], tr, bd);
            }
        }
        ASSERT_NO_FAILURE();
    }
    for (int i = 0; i < 2; i++)
        if (ratio_count[i]) {
            qsort(by_scale[i], ratio_count[i], sizeof(double), cmp_dbl);
            tp_test_note("%dx%d n=%d %s: median true/bound %.3f over %zu (node, level)s, "
                         "10%% %.3f, 90%% %.3f",
                         w, h, n, i ? "scale>=1" : "leaves", by_scale[i][ratio_count[i] / 2],
                         ratio_count[i], by_scale[i][ratio_count[i] / 10],
                         by_scale[i][ratio_count[i] * 9 / 10]);
        }
    free(by_scale[0]);
    free(by_scale[1]);
    free(vbuf);
    free(tbuf);
    tp_terrain_destroy(stencil);
    tp_tree_destroy(t);
}

TEST(bounds_hold_against_full_resolution_n4)
{
    /* 257 x 257: 16 x 16 leaves, a single root of scale 4; all samples valid */
    float* src = hgt_crop(300, 400, 257, 257);
    check_bounds(src, 257, 257, 17, 2);
    free(src);
}

TEST(bounds_hold_with_padding_and_voids_n5)
{
    /* not a multiple: padding on the far edges; a void block inside */
    int w = 230, h = 171;
    float* src = hgt_crop(600, 100, w, h);
    for (int y = 40; y < 47; y++)
        for (int x = 70; x < 75; x++)
            src[(size_t)y * w + x] = NAN;
    check_bounds(src, w, h, 33, 1);
    free(src);
}

TEST(bounds_hold_on_spiky_synthetic_terrain)
{
    /* integer heights on a smooth base with sharp spikes and pits (10% of the samples): the
     * stitched triangles' edges cross cells next to spikes outside them */
    int w = 129, h = 129;
    float* src = (float*)malloc(sizeof(float) * w * h);
    ASSERT_TRUE(src != NULL);
    tp_rng rng = tp_rng_seed(77);
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            double z = 1000 + 200 * sin(x / 20.0) * cos(y / 17.0);
            if (tp_rng_int(&rng, 0, 9) == 0)
                z += tp_rng_range(&rng, -300, 300);
            src[(size_t)y * w + x] = (float)floor(z);
        }
    check_bounds(src, w, h, 17, 4);
    free(src);
}

TEST(stitched_bound_covers_samples_between_node_samples)
{
    /* The full resolution IS the scale-1 node's surface S_n (every odd sample interpolated
     * from the even ones along the strips' diagonal), so the children's errors at level n-1
     * are 0: the carry adds nothing. A stitched triangle of the node at level n still has
     * errors at odd samples, where its moved edge crosses S_n's cells: the bound must come from
     * the cells it touches, not from the node's samples inside it (measuring those alone, this
     * test fails). */
    int w = 33, h = 33, cw = 17;
    float* src = (float*)malloc(sizeof(float) * w * h);
    int* coarse = (int*)malloc(sizeof(int) * cw * cw);
    ASSERT_TRUE(src && coarse);
    tp_rng rng = tp_rng_seed(5);
    /* even values (midpoints are integers); a plane on the border ring, so that the node's
     * own samples inside its stitched triangles (on the border) have no error at all */
    for (int j = 0; j < cw; j++)
        for (int i = 0; i < cw; i++)
            coarse[j * cw + i] = i == 0 || j == 0 || i == cw - 1 || j == cw - 1
                                     ? 2 * (100 + 3 * i + 5 * j)
                                     : 2 * tp_rng_int(&rng, 0, 400);
#define C(i, j) coarse[(j) * cw + (i)]
    for (int y = 0; y < h; y++)
        for (int x = 0; x < w; x++) {
            int i = x / 2, j = y / 2, z;
            if (x % 2 == 0 && y % 2 == 0)
                z = C(i, j);
            else if (y % 2 == 0)
                z = (C(i, j) + C(i + 1, j)) / 2;
            else if (x % 2 == 0)
                z = (C(i, j) + C(i, j + 1)) / 2;
            else
                z = (C(i + 1, j) + C(i, j + 1)) / 2; /* on the diagonal (c+1, r)-(c, r+1) */
            src[(size_t)y * w + x] = (float)z;
        }
#undef C
    check_bounds(src, w, h, 17, 60);
    free(coarse);
    free(src);
}

/* ---------------------------------------------------------------------------------------------
 * Leaves are patches
 */
TEST(leaf_metas_equal_patch_tables)
{
    int w = 145, h = 113; /* 9 x 7 patches */
    float* src = hgt_crop(800, 900, w, h);
    for (int y = 30; y < 33; y++) /* a void across a patch border */
        for (int x = 14; x < 19; x++)
            src[(size_t)y * w + x] = NAN;
    tp_terrain* ter = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL);
    tp_tree* t = NULL;
    ASSERT_OK(tp_tree_create_from_grid(src, (size_t)w * h, w, h, NULL, 17, 0, &t, NULL));
    tp_terrain_info ti;
    tp_terrain_get_info(ter, &ti);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    ASSERT_EQ_INT(ti.patch_cols, g->cols);
    ASSERT_EQ_INT(ti.patch_rows, g->rows);
    double step = ti.height_step_m, unit = ti.error_unit_m / step;
    int n = g->n, compared = 0, nonzero = 0;
    for (int r = 0; r < g->rows; r++)
        for (int c = 0; c < g->cols; c++) {
            int p = r * g->cols + c;
            const tp_node_meta* m = tp_tree_meta(t, tp_tree_node_id(g, 0, c, r));
            tp_patch_info pi;
            tp_patch_get_info(ter, p, &pi);
            EXPECT_EQ_INT(pi.complete, (m->flags & TP_NODE_COMPLETE) != 0);
            EXPECT_EQ_DBL(pi.aabb_min[2], m->qmin * step);
            EXPECT_EQ_DBL(pi.aabb_max[2], m->qmax * step);
            /* an incomplete patch is drawn at level n only; an incomplete leaf at any level,
             * by its cell mask: below n their tables differ, and so do the eps, which cover
             * every level (bounds_hold_* checks those) */
            for (int k = pi.complete ? 0 : n; k <= n; k++)
                for (int side = -1; side < (pi.complete ? 4 : 0); side++)
                    for (int kn = 0; kn < (side < 0 ? 1 : k); kn++) {
                        int nb[4];
                        tpt_fill4(nb, TP_NO_NEIGHBOR);
                        if (side >= 0)
                            nb[side] = kn;
                        double a = tp_patch_error_bound(ter, p, k, nb) - ti.quant_max_error_m;
                        double b = tp_node_error_bound(m, n, k, nb, step, unit);
                        if (fabs(a - b) > 1e-12)
                            ADD_FAILURE("leaf (%d,%d) k %d side %d kn %d: patch %.5f, node %.5f",
                                        c, r, k, side, kn, a, b);
                        compared++;
                        nonzero += b > 0;
                    }
        }
    EXPECT_GT(nonzero, compared / 2); /* a real comparison, not of zeros */
    tp_tree_destroy(t);
    tp_terrain_destroy(ter);
    free(src);
}

/* ---------------------------------------------------------------------------------------------
 * Builder
 */
typedef struct order_log {
    const tp_tree_geometry* g;
    uint8_t* seen;
    int64_t emitted;
    int errors;
    tp_node_meta* metas;   /* optional: copies */
    uint64_t* q_hash;      /* optional */
    uint16_t* masks;       /* optional: copies, tp_node_mask_words(n) per node */
    int stop_at;           /* emit fails at this count (-1: never) */
} order_log;

static int log_emit(int64_t node, const tp_node_meta* meta, const int32_t* q,
                    const uint16_t* mask, void* user, tp_error* err)
{
    order_log* l = (order_log*)user;
    if (l->emitted == l->stop_at) {
        if (err)
            snprintf(err->message, sizeof err->message, "disk full at node %lld",
                     (long long)node);
        return 1;
    }
    if (node < 0 || node >= l->g->node_count || l->seen[node])
        l->errors++;
    else {
        int s, c, r;
        tp_tree_node_locate(l->g, node, &s, &c, &r);
        for (int k = 0; s > 0 && k < 4; k++)
            if (!l->seen[tp_tree_node_child(l->g, node, k)])
                l->errors++;
        l->seen[node] = 1;
    }
    if (l->metas)
        l->metas[node] = *meta;
    if (l->masks) {
        size_t words = tp_node_mask_words(l->g->n);
        memcpy(l->masks + (size_t)node * words, mask, words * sizeof *mask);
    }
    if (l->q_hash) {
        uint64_t hsh = 1469598103934665603ull;
        int side = (1 << l->g->n) + 1;
        for (int i = 0; i < side * side; i++)
            hsh = (hsh ^ (uint32_t)q[i]) * 1099511628211ull;
        l->q_hash[node] = hsh;
    }
    l->emitted++;
    return 0;
}

static void fill_band(const float* src, int w, int h, const tp_tree_geometry* g, int r,
                      int32_t* band)
{
    int ps = 1 << g->n;
    for (int j = 0; j <= ps; j++)
        for (int x = 0; x < g->width; x++) {
            int y = r * ps + j;
            float s = x < w && y < h ? src[(size_t)y * w + x] : NAN;
            band[(size_t)j * g->width + x] = isfinite(s) ? (int32_t)floor(s + 0.5) : INT32_MIN;
        }
}

static void reverse_for(int count, void (*fn)(int i, void* ctx), void* ctx, void* user)
{
    (void)user;
    for (int i = count - 1; i >= 0; i--)
        fn(i, ctx);
}

static void run_builder(const float* src, int w, int h, int patch_size,
                        void (*pf)(int, void (*)(int, void*), void*, void*), order_log* l,
                        const tp_allocator* alloc)
{
    tp_tree_geometry g;
    ASSERT_OK(tp_tree_geometry_init(w, h, patch_size, &g, NULL));
    tp_tree_builder_desc d;
    memset(&d, 0, sizeof d);
    d.geometry = g;
    d.err_unit_steps = 1.0 / 16;
    d.emit = log_emit;
    d.parallel_for = pf;
    d.user = l;
    if (alloc)
        d.allocator = *alloc;
    tp_tree_builder* b = NULL;
    ASSERT_OK(tp_tree_builder_create(&d, &b, NULL));
    size_t count = (size_t)patch_size * g.width;
    int32_t* band = (int32_t*)malloc(sizeof(int32_t) * count);
    ASSERT_TRUE(band != NULL);
    for (int r = 0; r < g.rows; r++) {
        fill_band(src, w, h, &g, r, band);
        ASSERT_OK(tp_tree_builder_add_band(b, r, band, count, NULL));
    }
    free(band);
    tp_tree_builder_destroy(b);
}

TEST(builder_emits_children_first_each_node_once)
{
    int w = 1013, h = 300; /* 64 x 19 leaves: roots of several scales along the far edges */
    float* src = hgt_crop(100, 100, w, h);
    tp_tree_geometry g;
    ASSERT_OK(tp_tree_geometry_init(w, h, 17, &g, NULL));
    order_log l;
    memset(&l, 0, sizeof l);
    l.g = &g;
    l.stop_at = -1;
    l.seen = (uint8_t*)calloc((size_t)g.node_count, 1);
    run_builder(src, w, h, 17, NULL, &l, NULL);
    EXPECT_EQ_INT(0, l.errors);
    EXPECT_EQ_INT(g.node_count, l.emitted);
    for (int64_t i = 0; i < g.node_count; i++)
        EXPECT_EQ_INT(1, l.seen[i]);
    free(l.seen);
    free(src);
}

TEST(builder_refuses_bands_out_of_order)
{
    float* src = hgt_crop(0, 0, 100, 60);
    tp_tree_geometry g;
    ASSERT_OK(tp_tree_geometry_init(100, 60, 17, &g, NULL));
    order_log l;
    memset(&l, 0, sizeof l);
    l.g = &g;
    l.stop_at = -1;
    l.seen = (uint8_t*)calloc((size_t)g.node_count, 1);
    tp_tree_builder_desc d;
    memset(&d, 0, sizeof d);
    d.geometry = g;
    d.err_unit_steps = 1.0 / 16;
    d.emit = log_emit;
    d.user = &l;
    tp_tree_builder* b = NULL;
    ASSERT_OK(tp_tree_builder_create(&d, &b, NULL));
    size_t count = (size_t)17 * g.width;
    int32_t* band = (int32_t*)malloc(sizeof(int32_t) * count);
    tp_error err;
    fill_band(src, 100, 60, &g, 1, band);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_builder_add_band(b, 1, band, count, &err));
    EXPECT_CONTAINS(err.message, "expected band 0");
    EXPECT_EQ_INT(0, l.emitted); /* nothing emitted */
    fill_band(src, 100, 60, &g, 0, band);
    EXPECT_OK(tp_tree_builder_add_band(b, 0, band, count, &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_builder_add_band(b, 0, band, count, &err));
    EXPECT_CONTAINS(err.message, "expected band 1");
    for (int r = 1; r < g.rows; r++) {
        fill_band(src, 100, 60, &g, r, band);
        EXPECT_OK(tp_tree_builder_add_band(b, r, band, count, &err));
    }
    EXPECT_EQ_INT(g.node_count, l.emitted);
    EXPECT_EQ_INT(0, l.errors);
    tp_tree_builder_destroy(b);
    free(band);
    free(l.seen);
    free(src);
}

TEST(builder_emit_failure_stops_the_build)
{
    float* src = hgt_crop(0, 0, 100, 60);
    tp_tree_geometry g;
    ASSERT_OK(tp_tree_geometry_init(100, 60, 17, &g, NULL));
    order_log l;
    memset(&l, 0, sizeof l);
    l.g = &g;
    l.stop_at = 3;
    l.seen = (uint8_t*)calloc((size_t)g.node_count, 1);
    tp_tree_builder_desc d;
    memset(&d, 0, sizeof d);
    d.geometry = g;
    d.err_unit_steps = 1.0 / 16;
    d.emit = log_emit;
    d.user = &l;
    tp_tree_builder* b = NULL;
    ASSERT_OK(tp_tree_builder_create(&d, &b, NULL));
    size_t count = (size_t)17 * g.width;
    int32_t* band = (int32_t*)malloc(sizeof(int32_t) * count);
    tp_error err;
    fill_band(src, 100, 60, &g, 0, band);
    EXPECT_STATUS(TP_ERR_IO, tp_tree_builder_add_band(b, 0, band, count, &err));
    EXPECT_CONTAINS(err.message, "disk full at node");
    EXPECT_EQ_INT(3, l.emitted);
    fill_band(src, 100, 60, &g, 1, band);
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_builder_add_band(b, 1, band, count, &err));
    tp_tree_builder_destroy(b);
    free(band);
    free(l.seen);
    free(src);
}

TEST(builder_reversed_parallel_for_gives_identical_metas)
{
    int w = 300, h = 250;
    float* src = hgt_crop(500, 500, w, h);
    for (int y = 100; y < 140; y++) /* voids: incomplete nodes too */
        for (int x = 30; x < 33; x++)
            src[(size_t)y * w + x] = NAN;
    tp_tree_geometry g;
    ASSERT_OK(tp_tree_geometry_init(w, h, 17, &g, NULL));
    order_log a, b;
    memset(&a, 0, sizeof a);
    memset(&b, 0, sizeof b);
    a.g = b.g = &g;
    a.stop_at = b.stop_at = -1;
    a.seen = (uint8_t*)calloc((size_t)g.node_count, 1);
    b.seen = (uint8_t*)calloc((size_t)g.node_count, 1);
    a.metas = (tp_node_meta*)calloc((size_t)g.node_count, sizeof(tp_node_meta));
    b.metas = (tp_node_meta*)calloc((size_t)g.node_count, sizeof(tp_node_meta));
    a.q_hash = (uint64_t*)calloc((size_t)g.node_count, sizeof(uint64_t));
    b.q_hash = (uint64_t*)calloc((size_t)g.node_count, sizeof(uint64_t));
    size_t words = tp_node_mask_words(4);
    a.masks = (uint16_t*)calloc((size_t)g.node_count * words, sizeof(uint16_t));
    run_builder(src, w, h, 17, NULL, &a, NULL);
    run_builder(src, w, h, 17, reverse_for, &b, NULL);
    EXPECT_EQ_INT(g.node_count, b.emitted);
    EXPECT_EQ_INT(0, b.errors);
    EXPECT_TRUE(memcmp(a.metas, b.metas, sizeof(tp_node_meta) * (size_t)g.node_count) == 0);
    EXPECT_TRUE(memcmp(a.q_hash, b.q_hash, sizeof(uint64_t) * (size_t)g.node_count) == 0);
    /* and the metas are those of a direct computation over each node's samples */
    int side = 17, ps = 16;
    int32_t* q = (int32_t*)malloc(sizeof(int32_t) * side * side);
    for (int64_t id = 0; id < g.node_count; id++) {
        int s, c, r;
        tp_tree_node_locate(&g, id, &s, &c, &r);
        for (int j = 0; j < side; j++)
            for (int i = 0; i < side; i++) {
                int x = (c * ps + i) << s, y = (r * ps + j) << s;
                float v = x < w && y < h ? src[(size_t)y * w + x] : NAN;
                q[j * side + i] = isfinite(v) ? (int32_t)floor(v + 0.5) : INT32_MIN;
            }
        /* the cell mask, from the source grid: every full-resolution sample of the cell */
        const uint16_t* mask = a.masks + (size_t)id * words;
        int wrong = 0;
        for (int cy = 0; cy < ps; cy++)
            for (int cx = 0; cx < ps; cx++) {
                int whole = 1;
                for (int y = (r * ps + cy) << s; y <= (r * ps + cy + 1) << s; y++)
                    for (int x = (c * ps + cx) << s; x <= (c * ps + cx + 1) << s; x++)
                        whole &= x < w && y < h && isfinite(src[(size_t)y * w + x]);
                int b = cy * ps + cx;
                wrong += whole != (mask[b / 16] >> (b % 16) & 1);
            }
        if (wrong)
            ADD_FAILURE("node %lld (s %d, %d, %d): %d mask cells differ from the grid's",
                        (long long)id, s, c, r, wrong);
        const tp_node_meta* ch[4] = {NULL, NULL, NULL, NULL};
        for (int k = 0; s > 0 && k < 4; k++)
            ch[k] = &a.metas[tp_tree_node_child(&g, id, k)];
        tp_node_meta m;
        tp_node_meta_compute(4, s, q, mask, s > 0 ? ch : NULL, 1.0 / 16, &m);
        if (memcmp(&m, &a.metas[id], sizeof m) != 0)
            ADD_FAILURE("node %lld (s %d, %d, %d): builder meta differs", (long long)id, s, c, r);
    }
    free(q);
    free(a.masks);
    free(a.seen);
    free(b.seen);
    free(a.metas);
    free(b.metas);
    free(a.q_hash);
    free(b.q_hash);
    free(src);
}

/* A counting allocator: current and peak bytes, and the number of allocations. */
typedef struct counting {
    size_t now, peak, allocs;
} counting;

static void* count_alloc(size_t size, void* user)
{
    counting* c = (counting*)user;
    size_t* p = (size_t*)malloc(size + sizeof(size_t) * 2);
    if (!p)
        return NULL;
    p[0] = size;
    c->now += size;
    c->peak = c->now > c->peak ? c->now : c->peak;
    c->allocs++;
    return p + 2;
}

static void count_free(void* ptr, void* user)
{
    if (!ptr)
        return;
    counting* c = (counting*)user;
    size_t* p = (size_t*)ptr - 2;
    c->now -= p[0];
    free(p);
}

TEST(builder_memory_does_not_depend_on_height)
{
    /* same width and number of scales (the 38 leaf columns cap them at 6), 32 or 75 leaf
     * rows: the same peak to the byte */
    int w = 600;
    int heights[2] = {16 * 32 + 1, 1201};
    size_t peak[2];
    for (int i = 0; i < 2; i++) {
        int h = heights[i];
        float* src = hgt_crop(0, 0, w, h);
        tp_tree_geometry g;
        ASSERT_OK(tp_tree_geometry_init(w, h, 17, &g, NULL));
        order_log l;
        memset(&l, 0, sizeof l);
        l.g = &g;
        l.stop_at = -1;
        l.seen = (uint8_t*)calloc((size_t)g.node_count, 1);
        counting cnt = {0, 0, 0};
        tp_allocator a = {count_alloc, count_free, &cnt};
        run_builder(src, w, h, 17, NULL, &l, &a);
        EXPECT_EQ_INT(g.node_count, l.emitted);
        EXPECT_EQ_INT(0, cnt.now); /* everything released */
        peak[i] = cnt.peak;
        /* the header's formula: 4 (2^n+1) ((2 + 2^-n) width + scales)
         *   + 4 cols (sizeof(tp_node_meta) + 2^(2n-3)) + cols (2^(2n-3) + 2^(n-2) + 2) + 2048 */
        double formula = 4.0 * 17 * ((2 + 1.0 / 16) * g.width + g.scales) +
                         4.0 * g.cols * (sizeof(tp_node_meta) + (1 << (2 * 4 - 3))) +
                         g.cols * ((1 << (2 * 4 - 3)) + (1 << (4 - 2)) + 2) /* filled bits */ +
                         2048;
        EXPECT_EQ_INT(6, g.scales);
        tp_test_note("%dx%d: builder peak %zu bytes, formula %.0f, scales %d", w, h, cnt.peak,
                     formula, g.scales);
        EXPECT_LE((double)cnt.peak, formula);
        free(l.seen);
        free(src);
    }
    EXPECT_EQ_INT(peak[0], peak[1]);
}

/* ---------------------------------------------------------------------------------------------
 * Voids and the whole-tree builder
 */
TEST(complete_flags_follow_voids_up_the_tree)
{
    /* 4 x 4 leaves of 16; a void in leaf (1, 1) only; a void on the shared border x = 32
     * between leaves (1, 3) and (2, 3); no padding */
    int w = 65, h = 65;
    float* src = hgt_crop(200, 200, w, h);
    for (int i = 0; i < w * h; i++) /* the crop's own 2 voids: filled, so ours are the only ones */
        src[i] = isfinite(src[i]) ? src[i] : 1500.0f;
    src[(size_t)20 * w + 21] = NAN;
    src[(size_t)55 * w + 32] = NAN;
    tp_tree* t = NULL;
    ASSERT_OK(tp_tree_create_from_grid(src, (size_t)w * h, w, h, NULL, 17, 0, &t, NULL));
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    ASSERT_EQ_INT(3, g->scales);
#define COMPLETE(s, c, r) ((tp_tree_meta(t, tp_tree_node_id(g, s, c, r))->flags & TP_NODE_COMPLETE) != 0)
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++) {
            int expect = !((c == 1 && r == 1) || (r == 3 && (c == 1 || c == 2)));
            if (expect != COMPLETE(0, c, r))
                ADD_FAILURE("leaf (%d,%d): complete %d, expected %d", c, r, !expect, expect);
        }
    EXPECT_EQ_INT(0, COMPLETE(1, 0, 0));
    EXPECT_EQ_INT(1, COMPLETE(1, 1, 0));
    EXPECT_EQ_INT(0, COMPLETE(1, 0, 1));
    EXPECT_EQ_INT(0, COMPLETE(1, 1, 1));
    EXPECT_EQ_INT(0, COMPLETE(2, 0, 0));
    /* an incomplete node's bounds count only what its mask draws: its level 0 (one cell over
     * a void) draws nothing of its own, so only its children's carry (= its level n's), no
     * longer its area range */
    const tp_node_meta* m = tp_tree_meta(t, tp_tree_node_id(g, 1, 0, 0));
    EXPECT_EQ_INT(m->delta[g->n], m->delta[0]);
    EXPECT_TRUE(m->delta[g->n] > 0);
    EXPECT_LT(m->delta[0] / 16.0, (double)(m->area_qmax - m->area_qmin));
    tp_tree_destroy(t);

    /* padding counts as not drawn: 60 wide, so x >= 60 is padding in the last leaf column */
    float* crop = (float*)malloc(sizeof(float) * 60 * 65);
    for (int y = 0; y < 65; y++)
        for (int x = 0; x < 60; x++)
            crop[y * 60 + x] = 1000 + (float)((x * 7 + y * 3) % 50);
    ASSERT_OK(tp_tree_create_from_grid(crop, 60 * 65, 60, 65, NULL, 17, 0, &t, NULL));
    g = tp_tree_get_geometry(t);
    ASSERT_EQ_INT(4, g->cols);
    for (int r = 0; r < 4; r++)
        for (int c = 0; c < 4; c++)
            EXPECT_EQ_INT(c < 3, COMPLETE(0, c, r));
    EXPECT_EQ_INT(1, COMPLETE(1, 0, 1));
    EXPECT_EQ_INT(0, COMPLETE(1, 1, 1));
    EXPECT_EQ_INT(0, COMPLETE(2, 0, 0));
    EXPECT_TRUE(tp_tree_meta(t, 0)->flags & TP_NODE_HAS_DRAWN);
    tp_tree_destroy(t);

    /* a leaf with nothing drawn */
    for (int y = 0; y <= 16; y++)
        for (int x = 0; x <= 16; x++)
            crop[y * 60 + x] = NAN;
    ASSERT_OK(tp_tree_create_from_grid(crop, 60 * 65, 60, 65, NULL, 17, 0, &t, NULL));
    g = tp_tree_get_geometry(t);
    m = tp_tree_meta(t, tp_tree_node_id(g, 0, 0, 0));
    EXPECT_EQ_INT(0, m->flags);
    EXPECT_TRUE(m->qmin > m->qmax);
    EXPECT_EQ_INT(TP_NODE_HAS_DRAWN, tp_tree_meta(t, tp_tree_node_id(g, 1, 0, 0))->flags);
#undef COMPLETE
    tp_tree_destroy(t);
    free(crop);
    free(src);
}

TEST(create_from_grid_samples_and_residency)
{
    int w = 70, h = 40;
    float* src = (float*)malloc(sizeof(float) * w * h);
    for (int i = 0; i < w * h; i++)
        src[i] = 100.25f + 0.37f * (float)(i % 91) - 0.11f * (float)(i / 7 % 13);
    src[5 * w + 6] = NAN;
    tp_tree* t = NULL;
    tp_error err;
    ASSERT_OK(tp_tree_create_from_grid(src, (size_t)w * h, w, h, NULL, 17, 0, &t, &err));
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    /* fractional heights: the finest power of two, here 2^-10 m (range ~ 35 m) */
    double step = 1.0 / 1024;
    for (int y = 0; y < g->height; y++)
        for (int x = 0; x < g->width; x++) {
            double want = quantised(src, w, h, x, y, step), got = tp_tree_sample(t, x, y);
            if (!(isnan(want) ? isnan(got) : got == want))
                FAIL("sample (%d,%d): %.6f, expected %.6f", x, y, got, want);
        }
    EXPECT_NAN(tp_tree_sample(t, -1, 0));
    EXPECT_NAN(tp_tree_sample(t, g->width, 0));
    /* without the leaves only the samples of coarser nodes remain: even positions */
    for (int r = 0; r < g->rows; r++)
        for (int c = 0; c < g->cols; c++)
            tp_tree_detach(t, tp_tree_node_id(g, 0, c, r));
    EXPECT_NAN(tp_tree_sample(t, 3, 4));
    EXPECT_EQ_DBL(quantised(src, w, h, 2, 4, step), tp_tree_sample(t, 2, 4));
    EXPECT_TRUE(tp_tree_samples(t, tp_tree_node_id(g, 0, 0, 0)) == NULL);
    EXPECT_TRUE(tp_tree_samples(t, tp_tree_node_id(g, 1, 0, 0)) != NULL);
    tp_tree_destroy(t);
    free(src);
}

TEST(create_from_grid_rejects_bad_input)
{
    float h[4] = {NAN, NAN, NAN, NAN};
    tp_tree* t = (tp_tree*)&h; /* must stay untouched */
    tp_tree* before = t;
    tp_error err;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_create_from_grid(h, 3, 2, 2, NULL, 17, 0, &t, &err));
    EXPECT_CONTAINS(err.message, "expected 4 heights");
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_tree_create_from_grid(h, 4, 2, 2, NULL, 17, 0, &t, &err));
    EXPECT_CONTAINS(err.message, "no valid height");
    float v[4] = {0, 70000, 1, 2};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_create_from_grid(v, 4, 2, 2, NULL, 17, 0.5, &t,
                                                               &err));
    EXPECT_CONTAINS(err.message, "too fine");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_create_from_grid(v, 4, 2, 2, NULL, 20, 0, &t, &err));
    EXPECT_TRUE(t == before);
    /* 70000 m of range at 1 m does not fit: the automatic step goes to 2 m */
    ASSERT_OK(tp_tree_create_from_grid(v, 4, 2, 2, NULL, 17, 0, &t, &err));
    EXPECT_EQ_DBL(70000.0, tp_tree_sample(t, 1, 0));
    EXPECT_EQ_DBL(2.0, tp_tree_sample(t, 1, 1));
    EXPECT_NAN(tp_tree_sample(t, 2, 0)); /* padding */
    tp_tree_destroy(t);
}

TEST(tree_create_checks_its_desc)
{
    tp_tree_desc d;
    memset(&d, 0, sizeof d);
    tp_tree* t = NULL;
    tp_error err;
    ASSERT_OK(tp_tree_geometry_init(40, 40, 17, &d.geometry, NULL));
    tp_node_meta metas[8];
    memset(metas, 0, sizeof metas);
    d.metas = metas;
    d.meta_count = 4; /* 3 x 3 leaves + 1 = 10 nodes */
    d.height_step_m = 1;
    d.err_unit_steps = 1.0 / 16;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_tree_create(&d, &t, &err));
    EXPECT_CONTAINS(err.message, "expected 10 node metas, got 4");
    EXPECT_TRUE(t == NULL);
}

/* tp_tree_node_from_children (a build in parts joins its parts' top nodes with it): every node
 * of scale >= 1 recomputed from its children's blocks equals the builder's, samples, mask and
 * meta byte for byte, on real relief with voids and padding. */
TEST(node_from_children_equals_the_builder)
{
    int w = 300, h = 230; /* 17-sample nodes: padding right and below, voids of the crop */
    float* src = hgt_crop(100, 500, w, h);
    src[(size_t)40 * w + 50] = NAN;
    tp_tree* t = NULL;
    ASSERT_OK(tp_tree_create_from_grid(src, (size_t)w * h, w, h, NULL, 17, 0, &t, NULL));
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_tree_info info;
    tp_tree_get_info(t, &info);
    const int n = g->n, side = (1 << n) + 1;
    const size_t count = (size_t)side * side, mw = tp_node_mask_words(n);
    int32_t* kq = malloc(4 * count * sizeof *kq);
    int32_t* q = malloc(count * sizeof *q);
    uint16_t mask[64], filled[32];
    ASSERT_TRUE(kq && q && mw <= 64 && tp_node_filled_words(n) <= 32);
    int checked = 0, partial = 0;
    for (int64_t id = 0; id < g->first_node[0]; id++) {
        const int64_t kid[4] = {tp_tree_node_child(g, id, 0), tp_tree_node_child(g, id, 1),
                                tp_tree_node_child(g, id, 2), tp_tree_node_child(g, id, 3)};
        const int32_t* cq[4];
        const uint16_t* cm[4];
        const tp_node_meta* cmeta[4];
        for (int k = 0; k < 4; k++) {
            const uint16_t* b = tp_tree_samples(t, kid[k]);
            cmeta[k] = tp_tree_meta(t, kid[k]);
            for (size_t i = 0; i < count; i++)
                kq[k * count + i] = b[i] == TP_TREE_NO_HEIGHT ? INT32_MIN : b[i] + cmeta[k]->qmin;
            cq[k] = kq + k * count;
            cm[k] = b + count;
        }
        int s, c, r;
        tp_tree_node_locate(g, id, &s, &c, &r);
        tp_node_meta m;
        tp_tree_node_from_children(n, s, cq, cm, NULL, cmeta, info.err_unit_steps, q, mask,
                                   filled, &m);
        const tp_node_meta* want = tp_tree_meta(t, id);
        if (memcmp(&m, want, offsetof(tp_node_meta, eps) + sizeof m.eps)) /* not the tail padding */
            FAIL("node %lld (scale %d): meta differs from the builder's", (long long)id, s);
        const uint16_t* b = tp_tree_samples(t, id);
        for (size_t i = 0; i < count; i++)
            if ((b[i] == TP_TREE_NO_HEIGHT ? INT32_MIN : b[i] + want->qmin) != q[i])
                FAIL("node %lld: sample %zu differs", (long long)id, i);
        if (memcmp(mask, b + count, mw * sizeof *mask))
            FAIL("node %lld: mask differs", (long long)id);
        checked++;
        partial += !(m.flags & TP_NODE_COMPLETE);
    }
    tp_test_note("%d nodes above the leaves, %d of them drawn in part", checked, partial);
    EXPECT_TRUE(checked > 50 && partial > 5);
    free(kq), free(q), free(src);
    tp_tree_destroy(t);
}

#define TESTS(X)                                                                                   \
    X(geometry_hard_sizes)                                                                         \
    X(geometry_known_counts)                                                                       \
    X(geometry_rejects_bad_sizes)                                                                  \
    X(bounds_hold_against_full_resolution_n4)                                                      \
    X(bounds_hold_with_padding_and_voids_n5)                                                       \
    X(bounds_hold_on_spiky_synthetic_terrain)                                                      \
    X(stitched_bound_covers_samples_between_node_samples)                                          \
    X(leaf_metas_equal_patch_tables)                                                               \
    X(builder_emits_children_first_each_node_once)                                                 \
    X(builder_refuses_bands_out_of_order)                                                          \
    X(builder_emit_failure_stops_the_build)                                                        \
    X(builder_reversed_parallel_for_gives_identical_metas)                                         \
    X(builder_memory_does_not_depend_on_height)                                                    \
    X(complete_flags_follow_voids_up_the_tree)                                                     \
    X(create_from_grid_samples_and_residency)                                                      \
    X(create_from_grid_rejects_bad_input)                                                          \
    X(tree_create_checks_its_desc)                                                                 \
    X(node_from_children_equals_the_builder)
TP_TEST_MAIN(TESTS)

