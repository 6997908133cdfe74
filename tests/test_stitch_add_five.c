/* test_stitch_add_five.c - `--stitch add` drawn as five regions a patch (app/view/
 * stitch_add_five.c, `--stitch-add-draw five`): for every patch size up to n = 5, every level
 * and every neighbour configuration in which some side takes vertices, the triangles of the
 * patch's draws, read back through its layout into sample coordinates, are exactly the
 * triangles of tp_patch_triangles_add (as a multiset, each with its vertices in the same cyclic
 * order: the same winding), so the error and the watertightness are the vertex-adding ones;
 * no draw is empty; the layout starts with the level-k grid in lattice order, its samples are
 * distinct border or grid samples and it fits its pool level; and the sets are shared: all of
 * them together hold far fewer indices than one set per configuration would. */
#include "tp_test.h"

#include "stitch_add_five.h"

#include <stdlib.h>
#include <string.h>

#define TESTS(X)                                                                                   \
    X(five_regions_are_the_added_triangulation)                                                    \
    X(layout_is_the_grid_then_the_borders)

enum { MAXN = 5, SIDE = (1 << MAXN) + 1, MAX_TRI = 2 * (1 << MAXN) * (1 << MAXN) + 4 * SIDE };

typedef struct tri {
    uint32_t v[3];
} tri;

/* The rotation starting at the smallest index: the same triangle with the same winding. */
static tri canonical(uint32_t a, uint32_t b, uint32_t c)
{
    tri t = {{a, b, c}};
    if (b < a && b < c)
        t.v[0] = b, t.v[1] = c, t.v[2] = a;
    else if (c < a && c < b)
        t.v[0] = c, t.v[1] = a, t.v[2] = b;
    return t;
}

static int cmp_tri(const void* pa, const void* pb)
{
    const tri *a = pa, *b = pb;
    for (int i = 0; i < 3; i++)
        if (a->v[i] != b->v[i])
            return a->v[i] < b->v[i] ? -1 : 1;
    return 0;
}

static uint32_t add_[3 * MAX_TRI];
static tri want_[MAX_TRI], got_[MAX_TRI];

/* One configuration: 1 when its draws are tp_patch_triangles_add's triangles. */
static int check(tp__stitch_five* f, int n, int k, const int8_t nb8[4], size_t* drawn_indices,
                 char* why, size_t cap)
{
    int nb[4] = {nb8[0], nb8[1], nb8[2], nb8[3]};
    size_t want = tp_patch_triangles_add(n, k, nb, add_, MAX_TRI);
    if (want > MAX_TRI) {
        snprintf(why, cap, "%zu triangles", want);
        return 0;
    }
    for (size_t i = 0; i < want; i++)
        want_[i] = canonical(add_[3 * i], add_[3 * i + 1], add_[3 * i + 2]);
    const tp__five_layout* lay = tp__stitch_five_layout(f, k, nb8);
    tp__five_draws d;
    if (!lay || !tp__stitch_five_draws(f, k, nb8, &d)) {
        snprintf(why, cap, "out of memory");
        return 0;
    }
    size_t list_count, got = 0;
    const uint32_t* list = tp__stitch_five_indices(f, &list_count);
    if (d.count < 1 || d.count > 5) {
        snprintf(why, cap, "%d draws", d.count);
        return 0;
    }
    for (int r = 0; r < d.count; r++) {
        if (d.index_count[r] == 0 || d.index_count[r] % 3 ||
            d.first[r] + d.index_count[r] > list_count) {
            snprintf(why, cap, "draw %d: %zu indices from %zu of %zu", r, d.index_count[r],
                     d.first[r], list_count);
            return 0;
        }
        for (size_t i = d.first[r]; i < d.first[r] + d.index_count[r]; i += 3) {
            if (got == MAX_TRI) {
                snprintf(why, cap, "more than %d triangles", MAX_TRI);
                return 0;
            }
            uint32_t s[3];
            for (int j = 0; j < 3; j++) {
                if (list[i + j] >= lay->vertex_count) {
                    snprintf(why, cap, "index %u of %zu vertices", list[i + j], lay->vertex_count);
                    return 0;
                }
                s[j] = lay->samples[list[i + j]];
            }
            got_[got++] = canonical(s[0], s[1], s[2]);
        }
        *drawn_indices += d.index_count[r];
    }
    if (got != want || d.triangles != want) {
        snprintf(why, cap, "%zu triangles drawn (%zu counted), %zu added", got, d.triangles, want);
        return 0;
    }
    qsort(want_, want, sizeof *want_, cmp_tri);
    qsort(got_, got, sizeof *got_, cmp_tri);
    for (size_t i = 0; i < want; i++)
        if (cmp_tri(&want_[i], &got_[i])) {
            snprintf(why, cap, "triangle (%u %u %u) drawn where (%u %u %u) is added", got_[i].v[0],
                     got_[i].v[1], got_[i].v[2], want_[i].v[0], want_[i].v[1], want_[i].v[2]);
            return 0;
        }
    return 1;
}

TEST(five_regions_are_the_added_triangulation)
{
    long configs = 0, failed = 0;
    for (int n = 0; n <= MAXN; n++) {
        tp__stitch_five* f = tp__stitch_five_create(n);
        ASSERT_TRUE(f != NULL);
        size_t drawn = 0; /* indices one set per configuration would hold */
        for (int k = 0; k < n; k++) {
            /* each side: no neighbour, or one 1 .. n - k levels finer, or above n (taken as n) */
            const int choices = n - k + 2;
            int c[4];
            for (c[0] = 0; c[0] < choices; c[0]++)
                for (c[1] = 0; c[1] < choices; c[1]++)
                    for (c[2] = 0; c[2] < choices; c[2]++)
                        for (c[3] = 0; c[3] < choices; c[3]++) {
                            int8_t nb[4];
                            int any = 0;
                            for (int s = 0; s < 4; s++) {
                                nb[s] = (int8_t)(c[s] == 0 ? (s & 1 ? TP_NO_NEIGHBOR : k)
                                                 : c[s] == choices - 1 ? n + 1
                                                                       : k + c[s]);
                                any |= c[s] > 0;
                            }
                            if (!any)
                                continue; /* nothing added: drawn as the level's strip */
                            char why[256];
                            size_t indices = 0;
                            configs++;
                            if (!check(f, n, k, nb, &indices, why, sizeof why) && failed++ < 5)
                                ADD_FAILURE("n %d level %d neighbours %d %d %d %d: %s", n, k, nb[0],
                                            nb[1], nb[2], nb[3], why);
                            /* levels above n repeat level n's configuration */
                            if (c[0] < choices - 1 && c[1] < choices - 1 && c[2] < choices - 1 &&
                                c[3] < choices - 1)
                                drawn += indices;
                        }
        }
        size_t held;
        tp__stitch_five_indices(f, &held);
        tp_test_note("n = %d: the sets hold %zu indices; one set per configuration would hold %zu",
                     n, held, drawn);
        if (n >= 3)
            EXPECT_LT((double)held * 4, (double)drawn); /* shared, not one per configuration */
        tp__stitch_five_destroy(f);
    }
    tp_test_note("%ld configurations checked", configs);
    EXPECT_EQ_INT(0, failed);
    EXPECT_GT(configs, 1000);
}

TEST(layout_is_the_grid_then_the_borders)
{
    for (int n = 1; n <= MAXN; n++) {
        tp__stitch_five* f = tp__stitch_five_create(n);
        ASSERT_TRUE(f != NULL);
        const uint32_t side = (1u << n) + 1;
        for (int k = 0; k < n; k++)
            for (int D = 1; k + D <= n; D++) {
                const int8_t nb[4] = {(int8_t)(k + D), TP_NO_NEIGHBOR, TP_NO_NEIGHBOR,
                                      TP_NO_NEIGHBOR};
                const tp__five_layout* lay = tp__stitch_five_layout(f, k, nb);
                ASSERT_TRUE(lay != NULL);
                const uint32_t cells = 1u << k, step = 1u << (n - k), fine = step >> D;
                EXPECT_EQ_INT((long)((cells + 1) * (cells + 1) + 4 * cells * ((1u << D) - 1)),
                              (long)lay->vertex_count);
                const size_t slot = ((1u << lay->level) + 1) * ((1u << lay->level) + 1);
                EXPECT_TRUE(slot >= lay->vertex_count);
                EXPECT_TRUE(lay->level <= k + D);
                static uint8_t seen[SIDE * SIDE];
                memset(seen, 0, sizeof seen);
                long bad = 0;
                for (size_t j = 0; j < lay->vertex_count; j++) {
                    uint32_t s = lay->samples[j], x = s % side, y = s / side;
                    if (j < (cells + 1) * (cells + 1)) { /* the level-k grid, lattice order */
                        bad += s != (uint32_t)(j / (cells + 1)) * step * side +
                                        (uint32_t)(j % (cells + 1)) * step;
                    } else { /* a border sample of the finest spacing, not a grid sample */
                        bad += !(x == 0 || y == 0 || x == side - 1 || y == side - 1) ||
                               (x % fine) || (y % fine) || (x % step == 0 && y % step == 0);
                    }
                    bad += s >= side * side || seen[s]++;
                }
                if (bad)
                    ADD_FAILURE("n %d level %d D %d: %ld misplaced samples", n, k, D, bad);
            }
        tp__stitch_five_destroy(f);
    }
}

TP_TEST_MAIN(TESTS)
