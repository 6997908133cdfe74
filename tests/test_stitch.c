/*
 * test_stitch.c - crack removal by moving vertices (tp_patch_vertices, tp_patch_triangles,
 * tp_patch_error_bound; Vanek & Jezek Fig. 4).
 *
 * The exhaustive tests take the middle patch of a 3 x 3-patch terrain and try every level k of
 * it with every combination of its four neighbours' levels (0..n and TP_NO_NEIGHBOR), for n = 4
 * (5 * 6^4 = 6480 combinations) and n = 5 (6 * 7^4 = 14406). The drawn triangles are checked
 * with exact integer geometry: orientation, coverage of the patch square (two sample points per
 * cell, top-left rule on edges), conformity (no T-junction inside), and the error bound against
 * a brute-force rasterisation of the drawn surface.
 *
 * The watertightness tests set levels on a whole real DEM with tp_selection_set_level and
 * compare, for every shared edge, the vertex positions and edge segments of both patches.
 */
#include "tp_test_geom.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#define MAX_SIDE 33 /* n <= 5 here */
#define MAX_VERTS (MAX_SIDE * MAX_SIDE)
#define MAX_TRIS (2 * 32 * 32)

/* ---------------------------------------------------------------------------------------------
 * Fixtures
 */
typedef struct fixture {
    int n, side, width; /* side = 2^n + 1, width = 3 * 2^n + 1 */
    float* src;         /* the source heights of the 3 x 3-patch grid */
    tp_terrain* t;
} fixture;

static void fixture_free(fixture* f)
{
    tp_terrain_destroy(f->t);
    free(f->src);
    memset(f, 0, sizeof *f);
}

/* A rough float terrain: relief 300 m plus 20 m noise, so stitching errors are large and the
 * heights are quantised with a fractional step. */
static void fixture_synthetic(fixture* f, int n, uint64_t seed)
{
    f->n = n;
    f->side = (1 << n) + 1;
    f->width = 3 * (1 << n) + 1;
    f->src = (float*)malloc(sizeof(float) * f->width * f->width);
    ASSERT_TRUE(f->src != NULL);
    tpt_rough_heights(f->src, f->width, f->width, seed, 1500.0, 300.0, 20.0, 0);
    f->t = tpt_terrain_create(f->src, f->width, f->width, f->side, TP_FIT_PAD, NULL);
}

/* A crop of the real Storm Lake DEM (30 m LANDFIRE, Int16): the middle patch is all valid. */
static void fixture_real(fixture* f, int n)
{
#ifdef TP_TEST_NO_IO
    (void)f;
    (void)n;
    SKIP("built without tp_io");
#else
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err;
    tp_status s;
    int x, y, ox, oy;
    tp_patch_info info;
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif");
    s = tp_dem_read(path, &dem, &err);
    if (s != TP_OK)
        FAIL("tp_dem_read(%s): %s", path, err.message);
    f->n = n;
    f->side = (1 << n) + 1;
    f->width = 3 * (1 << n) + 1;
    if (dem->width < f->width || dem->height < f->width) {
        tp_dem_destroy(dem);
        FAIL("storml is %dx%d, need %d", dem->width, dem->height, f->width);
    }
    ox = (dem->width - f->width) / 2;
    oy = (dem->height - f->width) / 2;
    f->src = (float*)malloc(sizeof(float) * f->width * f->width);
    ASSERT_TRUE(f->src != NULL);
    for (y = 0; y < f->width; ++y)
        for (x = 0; x < f->width; ++x)
            f->src[y * f->width + x] = dem->heights[(size_t)(y + oy) * dem->width + (x + ox)];
    tp_dem_destroy(dem);
    f->t = tpt_terrain_create(f->src, f->width, f->width, f->side, TP_FIT_PAD, NULL);
    tp_patch_get_info(f->t, 4, &info);
    ASSERT_EQ_INT(1, info.complete);
#endif
}

/* Iterates k in 0..n and each neighbour level in -1..n. */
typedef struct combo {
    int k, nb[4];
} combo;

static int combo_first(combo* c)
{
    c->k = 0;
    tpt_fill4(c->nb, TP_NO_NEIGHBOR);
    return 1;
}
static int combo_next(combo* c, int n)
{
    int i;
    for (i = 0; i < 4; ++i) {
        if (c->nb[i] < n) {
            c->nb[i]++;
            return 1;
        }
        c->nb[i] = TP_NO_NEIGHBOR;
    }
    if (c->k < n) {
        c->k++;
        return 1;
    }
    return 0;
}

/* ---------------------------------------------------------------------------------------------
 * Expected vertex positions, from the rule in tp_core.h
 */

/* Where a border vertex at distance p (grid samples) from the side's first corner goes, with a
 * neighbour at level L < k on that side; *tie is set for the exact middle (with L = 0), where
 * both ends are possible and the side's rotation decides. */
static int expected_along(int p, int n, int L, int* tie)
{
    int s2 = 1 << (n - L), lo = p - p % s2, hi = lo + s2, half = 1 << (n - 1);
    *tie = 0;
    if (p % s2 == 0)
        return p;
    if (p - lo < hi - p)
        return lo;
    if (hi - p < p - lo)
        return hi;
    if (p < half)
        return lo; /* tie: toward the nearer corner */
    if (p > half)
        return hi;
    *tie = 1;
    return -1;
}

/* Checks one patch's vertex data against the rule. Returns the rotation of the middle
 * vertices that moved (+1: top goes +x, right +y, bottom -x, left -y, i.e. TOP->RIGHT->
 * BOTTOM->LEFT; -1 the other way; 0 if none was a tie), or 2 if sides disagreed. */
static int check_vertex_rule(const fixture* f, const combo* c, const tp_vertex* v, int x0, int y0)
{
    int vs = (1 << c->k) + 1, step = 1 << (f->n - c->k), last = 1 << f->n;
    int i, j, rotation = 0;
    for (j = 0; j < vs; ++j) {
        for (i = 0; i < vs; ++i) {
            int lx = i * step, ly = j * step, ex = lx, ey = ly, tie = 0, side = -1;
            const tp_vertex* q = &v[j * vs + i];
            int corner = (i == 0 || i == vs - 1) && (j == 0 || j == vs - 1);
            if (!corner) {
                if (j == 0)
                    side = TP_SIDE_TOP;
                else if (i == vs - 1)
                    side = TP_SIDE_RIGHT;
                else if (j == vs - 1)
                    side = TP_SIDE_BOTTOM;
                else if (i == 0)
                    side = TP_SIDE_LEFT;
            }
            if (side >= 0 && c->nb[side] >= 0 && c->nb[side] < c->k) {
                int along = (side == TP_SIDE_TOP || side == TP_SIDE_BOTTOM) ? lx : ly;
                int to = expected_along(along, f->n, c->nb[side], &tie);
                if (tie) {
                    int moved =
                        (side == TP_SIDE_TOP || side == TP_SIDE_BOTTOM) ? q->x - x0 : q->y - y0;
                    int other =
                        (side == TP_SIDE_TOP || side == TP_SIDE_BOTTOM) ? q->y - y0 : q->x - x0;
                    int fixed = (side == TP_SIDE_TOP || side == TP_SIDE_BOTTOM) ? ly : lx;
                    int r;
                    if (other != fixed || (moved != 0 && moved != last)) {
                        ADD_FAILURE("k=%d nb=%d,%d,%d,%d: middle vertex (%d,%d) of side %d went to "
                                    "(%d,%d), not to an end of its side",
                                    c->k, c->nb[0], c->nb[1], c->nb[2], c->nb[3], lx, ly, side,
                                    q->x - x0, q->y - y0);
                        return 2;
                    }
                    /* +1 when it moved in the TOP->RIGHT->BOTTOM->LEFT sense */
                    if (side == TP_SIDE_TOP)
                        r = moved == last ? 1 : -1;
                    else if (side == TP_SIDE_RIGHT)
                        r = moved == last ? 1 : -1;
                    else if (side == TP_SIDE_BOTTOM)
                        r = moved == 0 ? 1 : -1;
                    else
                        r = moved == 0 ? 1 : -1;
                    if (rotation != 0 && rotation != r)
                        return 2;
                    rotation = r;
                    continue;
                }
                if (side == TP_SIDE_TOP || side == TP_SIDE_BOTTOM)
                    ex = to;
                else
                    ey = to;
            }
            if (q->x != x0 + ex || q->y != y0 + ey) {
                ADD_FAILURE("k=%d nb=%d,%d,%d,%d: vertex (%d,%d) at (%d,%d), expected (%d,%d)",
                            c->k, c->nb[0], c->nb[1], c->nb[2], c->nb[3], lx, ly, q->x - x0,
                            q->y - y0, ex, ey);
                return 2;
            }
        }
    }
    return rotation;
}

TEST(vertices_move_to_nearest_coarser_vertex)
{
    int n;
    for (n = 4; n <= 5; ++n) {
        fixture f;
        combo c;
        static tp_vertex v[MAX_VERTS];
        int x0, y0, more;
        fixture_synthetic(&f, n, 11 + n);
        x0 = y0 = 1 << n;
        for (more = combo_first(&c); more; more = combo_next(&c, n)) {
            tp_patch_vertices(f.t, 4, c.k, c.nb, v, MAX_VERTS);
            if (check_vertex_rule(&f, &c, v, x0, y0) == 2)
                break;
        }
        fixture_free(&f);
        ASSERT_NO_FAILURE();
    }
}

TEST(middle_vertex_goes_the_documented_way_around)
{
    /* The exact middle of a side (a tie only with a level-0 neighbour) goes around the patch:
     * TOP toward the first column, RIGHT toward the first row, BOTTOM toward the last column,
     * LEFT toward the last row, i.e. -1 in check_vertex_rule's terms; for every k and in every
     * combination of the other sides. */
    int n, ties = 0;
    for (n = 4; n <= 5; ++n) {
        fixture f;
        combo c;
        static tp_vertex v[MAX_VERTS];
        int more;
        fixture_synthetic(&f, n, 21 + n);
        for (more = combo_first(&c); more; more = combo_next(&c, n)) {
            int r;
            tp_patch_vertices(f.t, 4, c.k, c.nb, v, MAX_VERTS);
            r = check_vertex_rule(&f, &c, v, 1 << n, 1 << n);
            if (r == 2 || r == 1) {
                ADD_FAILURE("n=%d k=%d nb(top,right,bottom,left)=%d,%d,%d,%d: a middle vertex "
                            "went the other way (TOP must go toward the first column, RIGHT "
                            "toward the first row, BOTTOM toward the last column, LEFT toward "
                            "the last row)",
                            n, c.k, c.nb[0], c.nb[1], c.nb[2], c.nb[3]);
                break;
            }
            ties += r != 0;
        }
        fixture_free(&f);
        ASSERT_NO_FAILURE();
    }
    EXPECT_GE_INT(ties, 1);
}

TEST(null_neighbor_levels_move_nothing)
{
    int n;
    for (n = 4; n <= 5; ++n) {
        fixture f;
        static tp_vertex a[MAX_VERTS], b[MAX_VERTS];
        int k, none[4];
        tpt_fill4(none, TP_NO_NEIGHBOR);
        fixture_synthetic(&f, n, 27 + n);
        for (k = 0; k <= n; ++k) {
            size_t count = (size_t)((1 << k) + 1) * ((1 << k) + 1);
            tp_patch_vertices(f.t, 4, k, NULL, a, MAX_VERTS);
            tp_patch_vertices(f.t, 4, k, none, b, MAX_VERTS);
            size_t i;
            for (i = 0; i < count; ++i)
                if (a[i].x != b[i].x || a[i].y != b[i].y || a[i].cls != b[i].cls ||
                    memcmp(&a[i].z_m, &b[i].z_m, sizeof(float)) != 0) {
                    ADD_FAILURE("n=%d k=%d: vertex %zu differs with NULL neighbour levels", n, k,
                                i);
                    break;
                }
            EXPECT_EQ_DBL(tp_patch_error_bound(f.t, 4, k, none),
                          tp_patch_error_bound(f.t, 4, k, NULL));
        }
        fixture_free(&f);
    }
}

TEST(vertex_heights_are_decoded_samples)
{
    int n;
    for (n = 4; n <= 5; ++n) {
        fixture f;
        combo c;
        static tp_vertex v[MAX_VERTS];
        int more;
        fixture_synthetic(&f, n, 31 + n);
        for (more = combo_first(&c); more; more = combo_next(&c, n)) {
            int vs = (1 << c.k) + 1, step = 1 << (n - c.k), i;
            tp_patch_vertices(f.t, 4, c.k, c.nb, v, MAX_VERTS);
            for (i = 0; i < vs * vs; ++i) {
                float z = (float)tp_terrain_sample(f.t, v[i].x, v[i].y);
                int ox = (1 << n) + (i % vs) * step, oy = (1 << n) + (i / vs) * step;
                if (memcmp(&z, &v[i].z_m, sizeof z) != 0) {
                    ADD_FAILURE(
                        "n=%d k=%d: vertex %d at (%d,%d) has z %.9g, sample decodes to %.9g", n,
                        c.k, i, v[i].x, v[i].y, v[i].z_m, z);
                    break;
                }
                if (v[i].cls != (uint8_t)tp_terrain_sample_class(f.t, ox, oy)) {
                    ADD_FAILURE("n=%d k=%d: vertex %d class %d, original sample (%d,%d) is %d", n,
                                c.k, i, v[i].cls, ox, oy,
                                (int)tp_terrain_sample_class(f.t, ox, oy));
                    break;
                }
            }
            if (tp_test_state_.failures)
                break;
        }
        fixture_free(&f);
        ASSERT_NO_FAILURE();
    }
}

/* A buffer of exactly (2^k+1)^2 vertices is enough at every level, and nothing past it is
 * written. (A level outside 0..n or a smaller capacity is a caller bug, asserted.) */
TEST(patch_vertices_fill_exactly_the_level_size)
{
    fixture f;
    static tp_vertex v[MAX_VERTS + 1];
    int nb[4], k;
    tp_patch_info pi;
    tpt_fill4(nb, TP_NO_NEIGHBOR);
    fixture_synthetic(&f, 4, 5);
    tp_patch_get_info(f.t, 4, &pi);
    for (k = 0; k <= 4; ++k) {
        size_t side = ((size_t)1 << k) + 1, count = side * side, i;
        memset(v, 0xAB, sizeof v);
        tp_patch_vertices(f.t, 4, k, nb, v, count);
        for (i = 0; i < count; ++i) {
            EXPECT_EQ_INT(pi.x0 + ((int)(i % side) << (4 - k)), v[i].x);
            EXPECT_EQ_INT(pi.y0 + ((int)(i / side) << (4 - k)), v[i].y);
        }
        EXPECT_EQ_INT(0xABABABAB, (uint32_t)v[count].x);
        ASSERT_NO_FAILURE();
    }
    fixture_free(&f);
}

TEST(triangle_count_respects_capacity)
{
    fixture f;
    static tp_vertex v[MAX_VERTS];
    uint32_t tri[3 * 40 + 1];
    int nb[4] = {0, 1, TP_NO_NEIGHBOR, 3};
    size_t full, got;
    static uint32_t all[3 * MAX_TRIS];
    fixture_synthetic(&f, 4, 6);
    tp_patch_vertices(f.t, 4, 4, nb, v, MAX_VERTS);
    full = tp_patch_triangles(v, 4, all, MAX_TRIS);
    EXPECT_LE_INT(full, 2 * 256);
    EXPECT_GE_INT(full, 40);
    tri[3 * 40] = 0xCAFEF00Du;
    /* the return value is the full count; only the first 40 are written */
    got = tp_patch_triangles(v, 4, tri, 40);
    EXPECT_EQ_INT(full, got);
    EXPECT_EQ_INT(0xCAFEF00Du, tri[3 * 40]);
    EXPECT_TRUE(memcmp(tri, all, sizeof(uint32_t) * 3 * 40) == 0);
    EXPECT_EQ_INT(full, tp_patch_triangles(v, 4, NULL, 0));
    /* level 0 of a patch with no coarser neighbour: the 2 triangles of the 2x2 patch */
    tpt_fill4(nb, TP_NO_NEIGHBOR);
    tp_patch_vertices(f.t, 4, 0, nb, v, MAX_VERTS);
    EXPECT_EQ_INT(2, tp_patch_triangles(v, 0, all, MAX_TRIS));
    fixture_free(&f);
}

TEST(triangles_follow_strip_order_and_winding)
{
    /* The drawn triangles are the level-k strip decoded with the GL rule (odd triangles swap
     * their first two vertices), in the same order and winding, minus the degenerate ones:
     * two vertices at one grid position, or zero area. */
    fixture f;
    combo c;
    static tp_vertex v[MAX_VERTS];
    static uint32_t tri[3 * MAX_TRIS], strip[(2 * 17 + 2) * 16];
    int more;
    fixture_synthetic(&f, 4, 29);
    for (more = combo_first(&c); more; more = combo_next(&c, 4)) {
        size_t sc = tp_strip_index_count(c.k), tc, t, at = 0;
        ASSERT_TRUE(sc <= sizeof strip / sizeof strip[0]);
        tp_strip_build_u32(c.k, strip, sizeof strip / sizeof strip[0]);
        tc = tpt_patch_geometry(f.t, 4, c.k, c.nb, v, MAX_VERTS, tri, MAX_TRIS);
        for (t = 0; t + 2 < sc; ++t) {
            uint32_t i0 = strip[t], i1 = strip[t + 1], i2 = strip[t + 2], s;
            const tp_vertex *a, *b, *d;
            int r, match = 0;
            if (t & 1) {
                s = i0;
                i0 = i1;
                i1 = s;
            }
            a = &v[i0];
            b = &v[i1];
            d = &v[i2];
            if ((a->x == b->x && a->y == b->y) || (b->x == d->x && b->y == d->y) ||
                (a->x == d->x && a->y == d->y) ||
                tpt_orient(a->x, a->y, b->x, b->y, d->x, d->y) == 0)
                continue;
            if (at >= tc) {
                ADD_FAILURE("k=%d nb=%d,%d,%d,%d: strip triangle %zu (%u,%u,%u) is not drawn", c.k,
                            c.nb[0], c.nb[1], c.nb[2], c.nb[3], t, i0, i1, i2);
                break;
            }
            for (r = 0; r < 3; ++r) /* the same triangle, same winding, any first vertex */
                match |= tri[3 * at + r] == i0 && tri[3 * at + (r + 1) % 3] == i1 &&
                         tri[3 * at + (r + 2) % 3] == i2;
            if (!match) {
                ADD_FAILURE("k=%d nb=%d,%d,%d,%d: drawn triangle %zu is (%u,%u,%u), strip "
                            "triangle %zu is (%u,%u,%u)",
                            c.k, c.nb[0], c.nb[1], c.nb[2], c.nb[3], at, tri[3 * at],
                            tri[3 * at + 1], tri[3 * at + 2], t, i0, i1, i2);
                break;
            }
            at++;
        }
        if (!tp_test_state_.failures && at != tc)
            ADD_FAILURE("k=%d nb=%d,%d,%d,%d: %zu triangles drawn, the strip has %zu real ones",
                        c.k, c.nb[0], c.nb[1], c.nb[2], c.nb[3], tc, at);
        if (tp_test_state_.failures)
            break;
    }
    fixture_free(&f);
}

/* ---------------------------------------------------------------------------------------------
 * Exhaustive geometry checks of one patch
 */
typedef struct geom_check {
    int n, side;
    /* coverage: 2 sample points per cell */
    unsigned char* cover;
    /* directed edges between local vertex ids: stamp and count */
    uint32_t* edge_stamp;
    unsigned char* edge_count;
    uint32_t stamp;
} geom_check;

static void geom_init(geom_check* g, int n)
{
    size_t ids;
    g->n = n;
    g->side = (1 << n) + 1;
    ids = (size_t)g->side * g->side;
    g->cover = (unsigned char*)malloc((size_t)2 << (2 * n));
    g->edge_stamp = (uint32_t*)calloc(ids * ids, sizeof(uint32_t));
    g->edge_count = (unsigned char*)calloc(ids * ids, 1);
    g->stamp = 0;
    ASSERT_TRUE(g->cover && g->edge_stamp && g->edge_count);
}
static void geom_free(geom_check* g)
{
    free(g->cover);
    free(g->edge_stamp);
    free(g->edge_count);
}

/* Top-left rule for a point exactly on a directed edge: exactly one of the two directions
 * of an edge owns it, so points on shared edges are counted once. */
static int edge_owns(int64_t dx, int64_t dy)
{
    return dy > 0 || (dy == 0 && dx < 0);
}

static int point_in_cw_triangle(const int64_t p[3][2], int64_t px, int64_t py)
{
    int e;
    for (e = 0; e < 3; ++e) {
        const int64_t* a = p[e];
        const int64_t* b = p[(e + 1) % 3];
        int64_t w = tpt_orient(a[0], a[1], b[0], b[1], px, py);
        if (w > 0)
            return 0;
        if (w == 0 && !edge_owns(b[0] - a[0], b[1] - a[1]))
            return 0;
    }
    return 1;
}

/* Returns a description of the first problem found, or NULL. */
static const char* geom_check_patch(geom_check* g, const tp_vertex* v, size_t vcount,
                                    const uint32_t* tri, size_t tcount, int x0, int y0)
{
    static char msg[256];
    int64_t twice_area = 0;
    size_t i;
    int cells = 1 << g->n, last = 1 << g->n;
    size_t ids = (size_t)g->side * g->side;
    memset(g->cover, 0, (size_t)2 * cells * cells);
    g->stamp++;
    for (i = 0; i < tcount; ++i) {
        int64_t p[3][2], o;
        int j, minx, maxx, miny, maxy, cx, cy;
        uint32_t id[3];
        for (j = 0; j < 3; ++j) {
            uint32_t vi = tri[3 * i + j];
            if (vi >= vcount) {
                snprintf(msg, sizeof msg, "triangle %zu uses vertex %u of %zu", i, vi, vcount);
                return msg;
            }
            p[j][0] = v[vi].x - x0;
            p[j][1] = v[vi].y - y0;
            if (p[j][0] < 0 || p[j][0] > last || p[j][1] < 0 || p[j][1] > last) {
                snprintf(msg, sizeof msg, "triangle %zu vertex at (%d,%d) outside the patch", i,
                         (int)p[j][0], (int)p[j][1]);
                return msg;
            }
            id[j] = (uint32_t)(p[j][1] * g->side + p[j][0]);
        }
        o = tpt_orient(p[0][0], p[0][1], p[1][0], p[1][1], p[2][0], p[2][1]);
        if (o == 0) {
            snprintf(msg, sizeof msg, "triangle %zu (%d,%d)(%d,%d)(%d,%d) has zero area", i,
                     (int)p[0][0], (int)p[0][1], (int)p[1][0], (int)p[1][1], (int)p[2][0],
                     (int)p[2][1]);
            return msg;
        }
        if (o > 0) {
            snprintf(msg, sizeof msg, "triangle %zu (%d,%d)(%d,%d)(%d,%d) is counter-clockwise", i,
                     (int)p[0][0], (int)p[0][1], (int)p[1][0], (int)p[1][1], (int)p[2][0],
                     (int)p[2][1]);
            return msg;
        }
        twice_area += -o;
        /* directed edges */
        for (j = 0; j < 3; ++j) {
            size_t key = (size_t)id[j] * ids + id[(j + 1) % 3];
            if (g->edge_stamp[key] != g->stamp) {
                g->edge_stamp[key] = g->stamp;
                g->edge_count[key] = 0;
            }
            if (g->edge_count[key] < 255)
                g->edge_count[key]++;
        }
        /* coverage of the sample points (c + 1/4, r + 3/8) and (c + 3/4, r + 5/8), in
         * coordinates scaled by 8 so that the arithmetic stays exact */
        minx = (int)(p[0][0] < p[1][0] ? p[0][0] : p[1][0]);
        minx = (int)(minx < p[2][0] ? minx : p[2][0]);
        maxx = (int)(p[0][0] > p[1][0] ? p[0][0] : p[1][0]);
        maxx = (int)(maxx > p[2][0] ? maxx : p[2][0]);
        miny = (int)(p[0][1] < p[1][1] ? p[0][1] : p[1][1]);
        miny = (int)(miny < p[2][1] ? miny : p[2][1]);
        maxy = (int)(p[0][1] > p[1][1] ? p[0][1] : p[1][1]);
        maxy = (int)(maxy > p[2][1] ? maxy : p[2][1]);
        for (j = 0; j < 3; ++j) {
            p[j][0] *= 8;
            p[j][1] *= 8;
        }
        for (cy = miny; cy < maxy; ++cy) {
            for (cx = minx; cx < maxx; ++cx) {
                unsigned char* cnt = &g->cover[2 * (cy * cells + cx)];
                if (point_in_cw_triangle((const int64_t(*)[2])p, 8 * cx + 2, 8 * cy + 3))
                    cnt[0]++;
                if (point_in_cw_triangle((const int64_t(*)[2])p, 8 * cx + 6, 8 * cy + 5))
                    cnt[1]++;
            }
        }
    }
    if (twice_area != 2 * (int64_t)cells * cells) {
        snprintf(msg, sizeof msg, "triangle areas sum to %.1f, the patch is %d", twice_area / 2.0,
                 cells * cells);
        return msg;
    }
    for (i = 0; i < (size_t)2 * cells * cells; ++i) {
        if (g->cover[i] != 1) {
            snprintf(msg, sizeof msg, "point %s of cell (%d,%d) covered %d times",
                     i % 2 ? "(0.75,0.625)" : "(0.25,0.375)", (int)((i / 2) % cells),
                     (int)((i / 2) / cells), g->cover[i]);
            return msg;
        }
    }
    /* every directed edge once; inside the patch its reverse exactly once, on the border never */
    for (i = 0; i < tcount; ++i) {
        int j;
        for (j = 0; j < 3; ++j) {
            const tp_vertex* a = &v[tri[3 * i + j]];
            const tp_vertex* b = &v[tri[3 * i + (j + 1) % 3]];
            int ax = a->x - x0, ay = a->y - y0, bx = b->x - x0, by = b->y - y0;
            size_t ia = (size_t)ay * g->side + ax, ib = (size_t)by * g->side + bx;
            size_t fwd = ia * ids + ib, rev = ib * ids + ia;
            int border =
                (ax == bx && (ax == 0 || ax == last)) || (ay == by && (ay == 0 || ay == last));
            int nf = g->edge_stamp[fwd] == g->stamp ? g->edge_count[fwd] : 0;
            int nr = g->edge_stamp[rev] == g->stamp ? g->edge_count[rev] : 0;
            if (nf != 1 || nr != (border ? 0 : 1)) {
                snprintf(msg, sizeof msg,
                         "edge (%d,%d)->(%d,%d)%s used %d times forward, %d backward (T-junction "
                         "or overlap)",
                         ax, ay, bx, by, border ? " on the border" : "", nf, nr);
                return msg;
            }
        }
    }
    return NULL;
}

static void exhaustive_geometry(int n)
{
    fixture f;
    geom_check g;
    combo c;
    static tp_vertex v[MAX_VERTS];
    static uint32_t tri[3 * MAX_TRIS];
    int more;
    size_t combos = 0;
    fixture_synthetic(&f, n, 41 + n);
    geom_init(&g, n);
    for (more = combo_first(&c); more; more = combo_next(&c, n)) {
        size_t tcount = tpt_patch_geometry(f.t, 4, c.k, c.nb, v, MAX_VERTS, tri, MAX_TRIS);
        size_t vcount = (size_t)((1 << c.k) + 1) * ((1 << c.k) + 1);
        const char* problem;
        if (tcount > (size_t)2 << (2 * c.k)) {
            ADD_FAILURE("n=%d k=%d nb=%d,%d,%d,%d: %zu triangles, at most %d exist", n, c.k,
                        c.nb[0], c.nb[1], c.nb[2], c.nb[3], tcount, 2 << (2 * c.k));
            break;
        }
        problem = geom_check_patch(&g, v, vcount, tri, tcount, 1 << n, 1 << n);
        if (problem) {
            ADD_FAILURE("n=%d k=%d nb(top,right,bottom,left)=%d,%d,%d,%d: %s", n, c.k, c.nb[0],
                        c.nb[1], c.nb[2], c.nb[3], problem);
            break;
        }
        combos++;
    }
    geom_free(&g);
    fixture_free(&f);
    ASSERT_NO_FAILURE();
    tp_test_note("n=%d: %zu combinations checked", n, combos);
}

TEST(stitched_triangles_tile_patch_n4_all_combinations)
{
    exhaustive_geometry(4);
}
TEST(stitched_triangles_tile_patch_n5_all_combinations)
{
    exhaustive_geometry(5);
}

TEST(unstitched_triangle_count_is_two_per_cell)
{
    int n;
    for (n = 4; n <= 5; ++n) {
        fixture f;
        static tp_vertex v[MAX_VERTS];
        static uint32_t tri[3 * MAX_TRIS];
        int k, nb[4];
        fixture_synthetic(&f, n, 51 + n);
        for (k = 0; k <= n; ++k) {
            int l;
            for (l = -1; l <= n; ++l) {
                if (l >= 0 && l < k)
                    continue; /* only neighbours that move nothing */
                tpt_fill4(nb, l);
                EXPECT_EQ_INT((size_t)2 << (2 * k),
                              tpt_patch_geometry(f.t, 4, k, nb, v, MAX_VERTS, tri, MAX_TRIS));
            }
        }
        fixture_free(&f);
    }
}

/* ---------------------------------------------------------------------------------------------
 * Error bound against brute force
 */
static void error_bound_all_combinations(fixture* f, const char* what)
{
    combo c;
    static tp_vertex v[MAX_VERTS];
    static uint32_t tri[3 * MAX_TRIS];
    static double drawn[MAX_VERTS];
    int more, x0 = 1 << f->n, y0 = 1 << f->n;
    double worst_ratio = 0.0, max_err = 0.0;
    tp_terrain_info ti;
    tp_terrain_get_info(f->t, &ti);
    for (more = combo_first(&c); more; more = combo_next(&c, f->n)) {
        size_t tcount = tpt_patch_geometry(f->t, 4, c.k, c.nb, v, MAX_VERTS, tri, MAX_TRIS);
        double err = 0.0, bound, disagreement;
        int x, y;
        disagreement = tpt_patch_surface(v, tri, tcount, x0, y0, f->side, drawn, NULL);
        if (disagreement > 1e-6) {
            ADD_FAILURE("%s k=%d nb=%d,%d,%d,%d: drawn surface discontinuous by %g m", what, c.k,
                        c.nb[0], c.nb[1], c.nb[2], c.nb[3], disagreement);
            break;
        }
        for (y = 0; y < f->side; ++y) {
            for (x = 0; x < f->side; ++x) {
                double d = drawn[y * f->side + x];
                double s = f->src[(size_t)(y0 + y) * f->width + (x0 + x)];
                if (isnan(d)) {
                    ADD_FAILURE("%s k=%d: sample (%d,%d) of the patch is not drawn", what, c.k, x,
                                y);
                    goto done;
                }
                if (fabs(d - s) > err)
                    err = fabs(d - s);
            }
        }
        bound = tp_patch_error_bound(f->t, 4, c.k, c.nb);
        if (!(bound + 1e-6 >= err) || !isfinite(bound)) {
            ADD_FAILURE("%s k=%d nb(top,right,bottom,left)=%d,%d,%d,%d: bound %.9g m < measured "
                        "error %.9g m against the source",
                        what, c.k, c.nb[0], c.nb[1], c.nb[2], c.nb[3], bound, err);
            break;
        }
        if (err > max_err)
            max_err = err;
        if (err > 0 && err / bound > worst_ratio)
            worst_ratio = err / bound;
    }
done:
    tp_test_note("%s: largest error %.3f m; tightest error/bound %.3f (quant step %g m)", what,
                 max_err, worst_ratio, ti.height_step_m);
}

TEST(error_bound_holds_synthetic_all_combinations)
{
    int n;
    for (n = 4; n <= 5; ++n) {
        fixture f;
        char what[32];
        fixture_synthetic(&f, n, 61 + n);
        snprintf(what, sizeof what, "synthetic n=%d", n);
        error_bound_all_combinations(&f, what);
        fixture_free(&f);
        ASSERT_NO_FAILURE();
    }
}

TEST(error_bound_holds_real_dem_all_combinations)
{
    int n;
    for (n = 4; n <= 5; ++n) {
        fixture f;
        char what[32];
        fixture_real(&f, n);
        snprintf(what, sizeof what, "storml n=%d", n);
        error_bound_all_combinations(&f, what);
        fixture_free(&f);
        ASSERT_NO_FAILURE();
    }
}

TEST(error_bound_ignores_finer_or_missing_neighbours)
{
    /* With no coarser neighbour nothing moves, so the bound of the same k must be the same
     * whatever the (finer or missing) neighbours are. */
    fixture f;
    int k, l;
    fixture_synthetic(&f, 4, 71);
    for (k = 0; k <= 4; ++k) {
        int nb[4];
        double ref;
        tpt_fill4(nb, TP_NO_NEIGHBOR);
        ref = tp_patch_error_bound(f.t, 4, k, nb);
        for (l = k; l <= 4; ++l) {
            tpt_fill4(nb, l);
            EXPECT_EQ_DBL(ref, tp_patch_error_bound(f.t, 4, k, nb));
        }
    }
    fixture_free(&f);
}

/* ---------------------------------------------------------------------------------------------
 * Watertightness across a whole terrain
 */
typedef struct pos3 {
    int32_t x, y;
    float z;
} pos3;

static int pos3_cmp(const void* a, const void* b)
{
    const pos3 *p = (const pos3*)a, *q = (const pos3*)b;
    uint32_t zp, zq;
    if (p->x != q->x)
        return p->x < q->x ? -1 : 1;
    if (p->y != q->y)
        return p->y < q->y ? -1 : 1;
    memcpy(&zp, &p->z, 4);
    memcpy(&zq, &q->z, 4);
    return zp < zq ? -1 : zp > zq;
}

typedef struct seg {
    int32_t ax, ay, bx, by; /* a < b lexicographically */
} seg;

static int seg_cmp(const void* a, const void* b)
{
    return memcmp(a, b, sizeof(seg));
}

typedef struct patch_geom {
    tp_vertex* v;
    uint32_t* tri;
    size_t vcount, tcount;
    int complete;
} patch_geom;

/* Distinct vertex positions of g lying on the segment x in [xa, xb], y in [ya, yb]. */
static size_t edge_positions(const patch_geom* g, int xa, int xb, int ya, int yb, pos3* out)
{
    size_t i, n = 0, m = 0;
    for (i = 0; i < g->vcount; ++i) {
        const tp_vertex* q = &g->v[i];
        if (q->x >= xa && q->x <= xb && q->y >= ya && q->y <= yb) {
            out[n].x = q->x;
            out[n].y = q->y;
            out[n].z = q->z_m;
            n++;
        }
    }
    qsort(out, n, sizeof *out, pos3_cmp);
    for (i = 0; i < n; ++i)
        if (m == 0 || pos3_cmp(&out[m - 1], &out[i]) != 0)
            out[m++] = out[i];
    return m;
}

/* Triangle edges of g lying on the segment. */
static size_t edge_segments(const patch_geom* g, int xa, int xb, int ya, int yb, seg* out)
{
    size_t i, n = 0;
    for (i = 0; i < g->tcount; ++i) {
        int j;
        for (j = 0; j < 3; ++j) {
            const tp_vertex* a = &g->v[g->tri[3 * i + j]];
            const tp_vertex* b = &g->v[g->tri[3 * i + (j + 1) % 3]];
            if (a->x >= xa && a->x <= xb && a->y >= ya && a->y <= yb && b->x >= xa && b->x <= xb &&
                b->y >= ya && b->y <= yb) {
                int swap = a->x > b->x || (a->x == b->x && a->y > b->y);
                const tp_vertex* lo = swap ? b : a;
                const tp_vertex* hi = swap ? a : b;
                out[n].ax = lo->x;
                out[n].ay = lo->y;
                out[n].bx = hi->x;
                out[n].by = hi->y;
                n++;
            }
        }
    }
    qsort(out, n, sizeof *out, seg_cmp);
    return n;
}

/* Sets the levels, rebuilds every patch and compares every shared edge. */
static void check_watertight(const tp_terrain* t, const int* levels, const char* pattern)
{
    tp_terrain_info ti;
    tp_selection* sel = NULL;
    tp_error err;
    patch_geom* g;
    int p, cols, rows, n, side;
    size_t vcap, tcap;
    pos3 *pa, *pb;
    seg *sa, *sb;
    tp_terrain_get_info(t, &ti);
    n = ti.n;
    side = ti.patch_size;
    cols = ti.patch_cols;
    rows = ti.patch_rows;
    vcap = (size_t)side * side;
    tcap = (size_t)2 << (2 * n);
    ASSERT_OK(tp_selection_create(t, &sel, &err));
    g = (patch_geom*)calloc((size_t)ti.patch_count, sizeof *g);
    pa = (pos3*)malloc(sizeof(pos3) * vcap);
    pb = (pos3*)malloc(sizeof(pos3) * vcap);
    sa = (seg*)malloc(sizeof(seg) * 3 * tcap);
    sb = (seg*)malloc(sizeof(seg) * 3 * tcap);
    ASSERT_TRUE(g && pa && pb && sa && sb);
    for (p = 0; p < ti.patch_count; ++p)
        tp_selection_set_level(sel, p, levels[p]);
    for (p = 0; p < ti.patch_count; ++p) {
        tp_patch_info pi;
        int k = tp_selection_level(sel, p), nb[4], expect_nb[4], col = p % cols, row = p / cols;
        tp_patch_get_info(t, p, &pi);
        g[p].complete = pi.complete;
        if (k != (pi.complete ? levels[p] : n))
            ADD_FAILURE("%s: patch %d (complete %d) at level %d after set_level(%d)", pattern, p,
                        pi.complete, k, levels[p]);
        tp_selection_neighbor_levels(sel, p, nb);
        expect_nb[TP_SIDE_TOP] = row > 0 ? tp_selection_level(sel, p - cols) : TP_NO_NEIGHBOR;
        expect_nb[TP_SIDE_RIGHT] = col + 1 < cols ? tp_selection_level(sel, p + 1) : TP_NO_NEIGHBOR;
        expect_nb[TP_SIDE_BOTTOM] =
            row + 1 < rows ? tp_selection_level(sel, p + cols) : TP_NO_NEIGHBOR;
        expect_nb[TP_SIDE_LEFT] = col > 0 ? tp_selection_level(sel, p - 1) : TP_NO_NEIGHBOR;
        if (memcmp(nb, expect_nb, sizeof nb) != 0)
            ADD_FAILURE(
                "%s: patch %d neighbour levels %d,%d,%d,%d, the neighbours are at %d,%d,%d,%d",
                pattern, p, nb[0], nb[1], nb[2], nb[3], expect_nb[0], expect_nb[1], expect_nb[2],
                expect_nb[3]);
        g[p].vcount = (size_t)((1 << k) + 1) * ((1 << k) + 1);
        g[p].v = (tp_vertex*)malloc(sizeof(tp_vertex) * vcap);
        g[p].tri = (uint32_t*)malloc(sizeof(uint32_t) * 3 * tcap);
        ASSERT_TRUE(g[p].v && g[p].tri);
        tp_patch_vertices(t, p, k, nb, g[p].v, vcap);
        g[p].tcount = tp_patch_triangles(g[p].v, k, g[p].tri, tcap);
    }
    for (p = 0; p < ti.patch_count && !tp_test_state_.failures; ++p) {
        int dir, col = p % cols, row = p / cols, x0 = col << n, y0 = row << n, last = 1 << n;
        for (dir = 0; dir < 2; ++dir) { /* 0: right neighbour, 1: bottom neighbour */
            int q, xa, xb, ya, yb;
            size_t na, nbv, i;
            if (dir == 0 && col + 1 >= cols)
                continue;
            if (dir == 1 && row + 1 >= rows)
                continue;
            q = dir == 0 ? p + 1 : p + cols;
            xa = dir == 0 ? x0 + last : x0;
            xb = x0 + last;
            ya = dir == 0 ? y0 : y0 + last;
            yb = y0 + last;
            na = edge_positions(&g[p], xa, xb, ya, yb, pa);
            nbv = edge_positions(&g[q], xa, xb, ya, yb, pb);
            if (na != nbv || memcmp(pa, pb, na * sizeof *pa) != 0) {
                for (i = 0; i < na && i < nbv && pos3_cmp(&pa[i], &pb[i]) == 0; ++i) {
                }
                ADD_FAILURE("%s: edge of patches %d (level %d) and %d (level %d): %zu vs %zu "
                            "distinct vertex positions; first difference at #%zu: (%d,%d,%.9g) vs "
                            "(%d,%d,%.9g)",
                            pattern, p, tp_selection_level(sel, p), q, tp_selection_level(sel, q),
                            na, nbv, i, i < na ? pa[i].x : -1, i < na ? pa[i].y : -1,
                            i < na ? pa[i].z : 0.0f, i < nbv ? pb[i].x : -1, i < nbv ? pb[i].y : -1,
                            i < nbv ? pb[i].z : 0.0f);
                break;
            }
            if (g[p].complete && g[q].complete) {
                na = edge_segments(&g[p], xa, xb, ya, yb, sa);
                nbv = edge_segments(&g[q], xa, xb, ya, yb, sb);
                if (na != nbv || memcmp(sa, sb, na * sizeof *sa) != 0) {
                    ADD_FAILURE("%s: edge of patches %d (level %d) and %d (level %d): the drawn "
                                "polylines differ (%zu vs %zu segments)",
                                pattern, p, tp_selection_level(sel, p), q,
                                tp_selection_level(sel, q), na, nbv);
                    break;
                }
                /* the segments chain along the whole edge without gaps or overlaps */
                {
                    int reach = dir == 0 ? ya : xa;
                    for (i = 0; i < na; ++i) {
                        int from = dir == 0 ? sa[i].ay : sa[i].ax,
                            to = dir == 0 ? sa[i].by : sa[i].bx;
                        if (from != reach)
                            break;
                        reach = to;
                    }
                    if (i != na || reach != (dir == 0 ? yb : xb))
                        ADD_FAILURE("%s: edge of patches %d and %d is not one chain of segments",
                                    pattern, p, q);
                }
            }
        }
    }
    for (p = 0; p < ti.patch_count; ++p) {
        free(g[p].v);
        free(g[p].tri);
    }
    free(g);
    free(pa);
    free(pb);
    free(sa);
    free(sb);
    tp_selection_destroy(sel);
}

/* Runs the adversarial and random level patterns on terrain t. */
static void watertight_patterns(const tp_terrain* t, uint64_t seed)
{
    tp_terrain_info ti;
    int *lv, p, i, pattern;
    tp_rng rng = tp_rng_seed(seed);
    tp_terrain_get_info(t, &ti);
    lv = (int*)malloc(sizeof(int) * ti.patch_count);
    ASSERT_TRUE(lv != NULL);
    for (pattern = 0; pattern < 8 && !tp_test_state_.failures; ++pattern) {
        static const char* names[8] = {
            "all 0",       "all n",    "checkerboard 0/n", "checkerboard n/0",
            "column ramp", "row ramp", "stripes 0/n",      "diagonal ramp"};
        for (p = 0; p < ti.patch_count; ++p) {
            int col = p % ti.patch_cols, row = p / ti.patch_cols;
            switch (pattern) {
            case 0: lv[p] = 0; break;
            case 1: lv[p] = ti.n; break;
            case 2: lv[p] = (col + row) % 2 ? ti.n : 0; break;
            case 3: lv[p] = (col + row) % 2 ? 0 : ti.n; break;
            case 4: lv[p] = col % (ti.n + 1); break;
            case 5: lv[p] = row % (ti.n + 1); break;
            case 6: lv[p] = (col / 2 + row) % 2 ? ti.n : 0; break;
            default: lv[p] = (col + 2 * row) % (ti.n + 1); break;
            }
        }
        check_watertight(t, lv, names[pattern]);
    }
    for (i = 0; i < 40 && !tp_test_state_.failures; ++i) {
        char name[48];
        for (p = 0; p < ti.patch_count; ++p)
            lv[p] = i % 2 ? (tp_rng_int(&rng, 0, 1) ? ti.n : 0) : tp_rng_int(&rng, 0, ti.n);
        snprintf(name, sizeof name, "random #%d", i);
        check_watertight(t, lv, name);
    }
    free(lv);
}

TEST(watertight_shared_edges_real_dem)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    char path[1024];
    tp_dem* dem = NULL;
    tp_error err;
    int ps;
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", "storml_elev_orig.tif");
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    for (ps = 17; ps <= 33 && !tp_test_state_.failures; ps = 2 * ps - 1) {
        tp_terrain_desc d = tp_dem_terrain_desc(dem, ps, TP_FIT_PAD);
        tp_terrain* t = NULL;
        tp_status s = tp_terrain_create(&d, &t, &err);
        if (s != TP_OK) {
            tp_dem_destroy(dem);
            FAIL("tp_terrain_create(storml, %d): %s", ps, err.message);
        }
        watertight_patterns(t, 1000 + ps);
        tp_terrain_destroy(t);
    }
    tp_dem_destroy(dem);
#endif
}

TEST(watertight_shared_edges_synthetic_with_holes)
{
    /* float heights with a fractional quantisation step (per-patch offsets differ), nodata
     * holes and padding: runs without tp_io */
    int w = 90, h = 70, i;
    float* src = (float*)malloc(sizeof(float) * w * h);
    tp_terrain* t;
    tp_rng rng = tp_rng_seed(77);
    ASSERT_TRUE(src != NULL);
    tpt_rough_heights(src, w, h, 78, 800.0, 600.0, 5.0, 0);
    for (i = 0; i < 6; ++i) { /* a few small holes */
        int cx = tp_rng_int(&rng, 0, w - 1), cy = tp_rng_int(&rng, 0, h - 1), x, y;
        for (y = cy - 1; y <= cy + 1; ++y)
            for (x = cx - 1; x <= cx + 1; ++x)
                if (x >= 0 && y >= 0 && x < w && y < h)
                    src[y * w + x] = NAN;
    }
    t = tpt_terrain_create(src, w, h, 17, TP_FIT_PAD, NULL);
    watertight_patterns(t, 79);
    tp_terrain_destroy(t);
    free(src);
}

#define TESTS(X)                                                                                   \
    X(vertices_move_to_nearest_coarser_vertex)                                                     \
    X(middle_vertex_goes_the_documented_way_around)                                                \
    X(null_neighbor_levels_move_nothing)                                                           \
    X(vertex_heights_are_decoded_samples)                                                          \
    X(patch_vertices_fill_exactly_the_level_size)                                               \
    X(triangle_count_respects_capacity)                                                            \
    X(triangles_follow_strip_order_and_winding)                                                    \
    X(stitched_triangles_tile_patch_n4_all_combinations)                                           \
    X(stitched_triangles_tile_patch_n5_all_combinations)                                           \
    X(unstitched_triangle_count_is_two_per_cell)                                                   \
    X(error_bound_holds_synthetic_all_combinations)                                                \
    X(error_bound_holds_real_dem_all_combinations)                                                 \
    X(error_bound_ignores_finer_or_missing_neighbours)                                             \
    X(watertight_shared_edges_real_dem)                                                            \
    X(watertight_shared_edges_synthetic_with_holes)
TP_TEST_MAIN(TESTS)
