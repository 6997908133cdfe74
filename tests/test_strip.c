/*
 * test_strip.c - the shared per-level triangle strips (tp_strip_*).
 *
 * Every check decodes the strip independently with the GL_TRIANGLE_STRIP rule: triangle t is
 * (i[t], i[t+1], i[t+2]) and odd t swaps its first two vertices (Vanek & Jezek, section 2).
 */
#include "tp_test_geom.h"

static size_t expected_count(int k)
{
    size_t v = ((size_t)1 << k) + 1;
    return (2 * v + 2) * (v - 1);
}

/* Builds the level-k strip in a fresh buffer with a canary after it. */
static uint32_t* build_u32(int k, size_t* count)
{
    size_t n = expected_count(k);
    uint32_t* idx = (uint32_t*)malloc((n + 1) * sizeof *idx);
    ASSERT_TRUE(idx != NULL);
    idx[n] = 0xDEADBEEFu;
    tp_strip_build_u32(k, idx, n);
    if (idx[n] != 0xDEADBEEFu) {
        free(idx);
        FAIL("tp_strip_build_u32(%d) wrote past its capacity", k);
    }
    *count = n;
    return idx;
}

/* Walks the strip; for each real (non-degenerate) triangle calls back with its three vertices
 * in (col, row). Counts the triangles with a repeated index; other zero-area triangles are
 * reported as failures by the callers through `flat`. */
typedef struct strip_walk {
    int v;
    size_t real, repeated, flat, counterclockwise, out_of_range;
} strip_walk;

typedef void (*tri_fn)(void* user, const int p[3][2]);

static void walk(const uint32_t* idx, size_t n, int k, strip_walk* w, tri_fn fn, void* user)
{
    size_t t;
    memset(w, 0, sizeof *w);
    w->v = (1 << k) + 1;
    for (t = 0; t + 2 < n; ++t) {
        uint32_t a = idx[t], b = idx[t + 1], c = idx[t + 2];
        int p[3][2];
        int64_t o;
        if (t & 1) {
            uint32_t s = a;
            a = b;
            b = s;
        }
        if (a >= (uint32_t)(w->v * w->v) || b >= (uint32_t)(w->v * w->v) ||
            c >= (uint32_t)(w->v * w->v)) {
            w->out_of_range++;
            continue;
        }
        if (a == b || b == c || a == c) {
            w->repeated++;
            continue;
        }
        p[0][0] = (int)(a % w->v), p[0][1] = (int)(a / w->v);
        p[1][0] = (int)(b % w->v), p[1][1] = (int)(b / w->v);
        p[2][0] = (int)(c % w->v), p[2][1] = (int)(c / w->v);
        o = tpt_orient(p[0][0], p[0][1], p[1][0], p[1][1], p[2][0], p[2][1]);
        if (o == 0) {
            w->flat++;
            continue;
        }
        if (o > 0)
            w->counterclockwise++;
        w->real++;
        if (fn)
            fn(user, (const int(*)[2])p);
    }
}

TEST(index_count_matches_formula)
{
    int k;
    for (k = 0; k <= TP_MAX_N; ++k)
        EXPECT_EQ_INT(expected_count(k), tp_strip_index_count(k));
    /* the paper's table: (2n+2)(m-1) indices for an n x m height map; 17 x 17 -> 576 */
    EXPECT_EQ_INT(576, tp_strip_index_count(4));
    EXPECT_EQ_INT(6, tp_strip_index_count(0));
}

/* A larger buffer than the strip needs is fine: exactly tp_strip_index_count(k) indices are
 * written and the rest is left alone. (A level outside 0..TP_MAX_N, a smaller capacity or
 * the u16 variant above level 7 are caller bugs, asserted.) */
TEST(build_with_spare_capacity_writes_only_the_strip)
{
    uint32_t buf32[64];
    uint16_t buf16[64];
    int k;
    for (k = 0; k <= 2; ++k) {
        size_t n = tp_strip_index_count(k), i;
        ASSERT_TRUE(n < 64);
        for (i = 0; i < 64; ++i) {
            buf32[i] = 0xDEADBEEFu;
            buf16[i] = 0xBEEF;
        }
        tp_strip_build_u32(k, buf32, 64);
        tp_strip_build_u16(k, buf16, 64);
        for (i = 0; i < 64; ++i) {
            if (i < n && buf32[i] != buf16[i])
                ADD_FAILURE("k=%d: u32[%zu] = %u, u16 = %u", k, i, buf32[i], buf16[i]);
            if (i < n && buf32[i] >= (((uint32_t)1 << k) + 1) * (((uint32_t)1 << k) + 1))
                ADD_FAILURE("k=%d: index %u at %zu out of range", k, buf32[i], i);
            if (i >= n && (buf32[i] != 0xDEADBEEFu || buf16[i] != 0xBEEF))
                ADD_FAILURE("k=%d: wrote past the strip at %zu", k, i);
        }
        ASSERT_NO_FAILURE();
    }
}

TEST(indices_are_in_range_and_all_vertices_used)
{
    int k;
    for (k = 0; k <= TP_MAX_N; ++k) {
        size_t n, i;
        int v = (1 << k) + 1;
        uint32_t* idx = build_u32(k, &n);
        unsigned char* used = (unsigned char*)calloc((size_t)v * v, 1);
        ASSERT_TRUE(used != NULL);
        for (i = 0; i < n; ++i) {
            if (idx[i] >= (uint32_t)(v * v)) {
                ADD_FAILURE("k=%d: index %zu is %u, beyond %d vertices", k, i, idx[i], v * v);
                break;
            }
            used[idx[i]] = 1;
        }
        for (i = 0; i < (size_t)v * v; ++i)
            if (!used[i]) {
                ADD_FAILURE("k=%d: vertex %zu never referenced", k, i);
                break;
            }
        free(used);
        free(idx);
    }
}

TEST(real_triangles_are_clockwise_in_col_row)
{
    int k;
    for (k = 0; k <= TP_MAX_N; ++k) {
        size_t n;
        strip_walk w;
        uint32_t* idx = build_u32(k, &n);
        walk(idx, n, k, &w, NULL, NULL);
        EXPECT_EQ_INT(0, w.out_of_range);
        EXPECT_EQ_INT(0, w.counterclockwise);
        free(idx);
    }
}

TEST(degenerate_triangles_repeat_an_index)
{
    /* the only invisible triangles are the row joins, which repeat an index; no triangle of
     * three distinct collinear vertices */
    int k;
    for (k = 0; k <= TP_MAX_N; ++k) {
        size_t n;
        strip_walk w;
        uint32_t* idx = build_u32(k, &n);
        size_t v = ((size_t)1 << k) + 1;
        walk(idx, n, k, &w, NULL, NULL);
        EXPECT_EQ_INT(0, w.flat);
        /* real triangles: two per cell; the rest of the n - 2 are row joins */
        EXPECT_EQ_INT(2 * (v - 1) * (v - 1), w.real);
        EXPECT_EQ_INT(n - 2 - 2 * (v - 1) * (v - 1), w.repeated);
        free(idx);
    }
}

/* Each real triangle must be one half of a unit cell split along (c+1, r)-(c, r+1):
 * upper-left {(c,r), (c+1,r), (c,r+1)} (half 0) or lower-right {(c+1,r), (c,r+1), (c+1,r+1)}
 * (half 1). Records how often each half appears. */
typedef struct half_count {
    int v;
    unsigned char* seen; /* (v-1)^2 cells x 2 halves */
    size_t not_a_half;
} half_count;

static void count_half(void* user, const int p[3][2])
{
    half_count* hc = (half_count*)user;
    int minx = p[0][0], miny = p[0][1], i, c, r, half, ul = 0, lr = 0;
    for (i = 1; i < 3; ++i) {
        if (p[i][0] < minx)
            minx = p[i][0];
        if (p[i][1] < miny)
            miny = p[i][1];
    }
    c = minx;
    r = miny;
    for (i = 0; i < 3; ++i) {
        int dx = p[i][0] - c, dy = p[i][1] - r;
        if (dx < 0 || dx > 1 || dy < 0 || dy > 1) {
            hc->not_a_half++;
            return;
        }
        if (dx + dy <= 1)
            ul++;
        if (dx + dy >= 1)
            lr++;
    }
    if (ul == 3)
        half = 0;
    else if (lr == 3)
        half = 1;
    else { /* a half split along the other diagonal */
        hc->not_a_half++;
        return;
    }
    if (c >= hc->v - 1 || r >= hc->v - 1) {
        hc->not_a_half++;
        return;
    }
    hc->seen[((size_t)r * (hc->v - 1) + c) * 2 + half]++;
}

TEST(cells_split_along_documented_diagonal_once_each)
{
    int k;
    for (k = 0; k <= TP_MAX_N; ++k) {
        size_t n, i, cells;
        strip_walk w;
        half_count hc;
        uint32_t* idx = build_u32(k, &n);
        hc.v = (1 << k) + 1;
        cells = (size_t)(hc.v - 1) * (hc.v - 1);
        hc.seen = (unsigned char*)calloc(cells * 2, 1);
        hc.not_a_half = 0;
        ASSERT_TRUE(hc.seen != NULL);
        walk(idx, n, k, &w, count_half, &hc);
        EXPECT_EQ_INT(0, hc.not_a_half);
        for (i = 0; i < cells * 2; ++i) {
            if (hc.seen[i] != 1) {
                ADD_FAILURE("k=%d: cell (%zu,%zu) half %zu drawn %d times, expected once", k,
                            (i / 2) % (hc.v - 1), (i / 2) / (hc.v - 1), i % 2, hc.seen[i]);
                break;
            }
        }
        free(hc.seen);
        free(idx);
    }
}

typedef struct area_sum {
    int64_t twice_area;
} area_sum;

static void add_area(void* user, const int p[3][2])
{
    area_sum* a = (area_sum*)user;
    a->twice_area += -tpt_orient(p[0][0], p[0][1], p[1][0], p[1][1], p[2][0], p[2][1]);
}

TEST(real_triangles_cover_patch_area)
{
    int k;
    for (k = 0; k <= TP_MAX_N; ++k) {
        size_t n;
        strip_walk w;
        area_sum a = {0};
        int64_t side = ((int64_t)1 << k);
        uint32_t* idx = build_u32(k, &n);
        walk(idx, n, k, &w, add_area, &a);
        EXPECT_EQ_INT(2 * side * side, a.twice_area); /* (v-1)^2, doubled */
        free(idx);
    }
}

TEST(sequence_is_the_papers_construction)
{
    /* The index buffer code of Vanek & Jezek section 2, transcribed for an m = n = v grid. */
    int k;
    for (k = 0; k <= TP_MAX_N; ++k) {
        size_t n, at = 0;
        int v = (1 << k) + 1, i, j, mismatch = 0;
        uint32_t* idx = build_u32(k, &n);
#define PAPER_ADD(value)                                                                           \
    do {                                                                                           \
        if (!mismatch && idx[at] != (uint32_t)(value)) {                                           \
            ADD_FAILURE("k=%d: index %zu is %u, the paper's construction has %d", k, at, idx[at],  \
                        (int)(value));                                                             \
            mismatch = 1;                                                                          \
        }                                                                                          \
        at++;                                                                                      \
    } while (0)
        for (i = 0; i < v - 1; i++) {
            if (i % 2) {
                for (j = v - 1; j >= 0; j--) {
                    PAPER_ADD((i + 1) * v + j);
                    PAPER_ADD(i * v + j);
                }
                PAPER_ADD((i + 1) * v);
                PAPER_ADD((i + 1) * v);
            } else {
                for (j = 0; j < v; j++) {
                    PAPER_ADD(i * v + j);
                    PAPER_ADD((i + 1) * v + j);
                }
                PAPER_ADD((i + 2) * v - 1);
                PAPER_ADD((i + 2) * v - 1);
            }
        }
#undef PAPER_ADD
        EXPECT_EQ_INT(n, at);
        free(idx);
    }
}

TEST(u16_matches_u32_up_to_level_7)
{
    int k;
    for (k = 0; k <= 7; ++k) {
        size_t n, i;
        uint32_t* idx = build_u32(k, &n);
        uint16_t* idx16 = (uint16_t*)malloc((n + 1) * sizeof *idx16);
        ASSERT_TRUE(idx16 != NULL);
        idx16[n] = 0xBEEF;
        tp_strip_build_u16(k, idx16, n);
        EXPECT_EQ_INT(0xBEEF, idx16[n]);
        for (i = 0; i < n; ++i)
            if (idx16[i] != idx[i]) {
                ADD_FAILURE("k=%d: u16[%zu] = %u, u32 = %u", k, i, idx16[i], idx[i]);
                break;
            }
        free(idx16);
        free(idx);
    }
}

#define TESTS(X)                                                                                   \
    X(index_count_matches_formula)                                                                 \
    X(build_with_spare_capacity_writes_only_the_strip)                                           \
    X(indices_are_in_range_and_all_vertices_used)                                                  \
    X(real_triangles_are_clockwise_in_col_row)                                                     \
    X(degenerate_triangles_repeat_an_index)                                                        \
    X(cells_split_along_documented_diagonal_once_each)                                             \
    X(real_triangles_cover_patch_area)                                                             \
    X(sequence_is_the_papers_construction)                                                         \
    X(u16_matches_u32_up_to_level_7)
TP_TEST_MAIN(TESTS)
