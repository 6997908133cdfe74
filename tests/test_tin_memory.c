/* test_tin_memory.c - what a node's TINs and the TIN cache hold (issue 32 item 5: `--mesh tin`
 * within 300 MB of anonymous RSS).
 *
 *   - a level built alone holds what its rungs need and no more: per rung its header
 *     (sizeof(tp_node_tin)) and 3 indices of 16 bits a triangle, and the level's vertex
 *     positions (2 x 16 bits each, shared by its rungs: the finest rung's count), within a
 *     header of 64 bytes; on every complete node and level of a Mt Hood window. Before, each
 *     level carried a header for 72 rungs (12 KB, of which its up to 8 rungs used 1.3): the
 *     cache of the 65537^2 low flight held 115 MB where its levels needed 28;
 *   - the same level built twice is the same, byte for byte in what it draws (the cache may
 *     free a level and build it again when a cut asks: it must come back as it was);
 *   - the cache counts the time its builds take (tp_tin_cache_build_ms: the bench's TIN build
 *     figures), and nothing for a level already built.
 */
#include "tp_io.h"
#include "tp_test.h"

#define TESTS(X)                                                                                   \
    X(a_level_holds_what_its_rungs_need)                                                           \
    X(a_level_built_again_is_the_same)                                                             \
    X(the_cache_counts_its_build_time)

#include "tp_test_tin.h"

#include <stdlib.h>
#include <string.h>

#define GT ((const double[6]){0, 10, 0, 0, 0, -10})
#define HEADER_SLACK 64 /* the allocation's own fields: bytes, rungs, first[TP_MAX_LEVELS + 1] */

static tp_tree* tree_of(const float* h, int w, int hg, int patch)
{
    tp_tree* t = NULL;
    tp_error e = {{0}};
    if (tp_tree_create_from_grid(h, (size_t)w * hg, w, hg, GT, patch, 0, &t, &e) != TP_OK)
        FAIL("tree: %s", e.message);
    return t;
}

#ifdef TP_TEST_NO_IO
static tp_tree* real_tree(int size, int patch)
{
    (void)size, (void)patch;
    SKIP("built without tp_io");
    return NULL;
}
#else
/* A size x size window from the middle of Mt Hood as a tree of patch-sample nodes. */
static tp_tree* real_tree(int size, int patch)
{
    tp_render_grid* g = tin_test_render_grid("TP_SAMPLE_DATA_DIR", "lf_elev_220_mt_hood_utm.tif");
    ASSERT_TRUE(g->width >= size && g->height >= size);
    float* h = malloc(sizeof *h * (size_t)size * size);
    ASSERT_TRUE(h != NULL);
    int x0 = (g->width - size) / 2, y0 = (g->height - size) / 2;
    for (int y = 0; y < size; y++)
        for (int x = 0; x < size; x++)
            h[(size_t)y * size + x] = g->heights[(size_t)(y0 + y) * g->width + x0 + x];
    tp_render_grid_destroy(g);
    tp_tree* t = tree_of(h, size, size, patch);
    free(h);
    return t;
}
#endif

/* Level k of node built alone (NULL when the node has none there). */
static tp_node_tins* build_level(const tp_tree* t, int64_t id, int k)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_tree_info ti;
    tp_tree_get_info(t, &ti);
    int s, c, r;
    tp_tree_node_locate(g, id, &s, &c, &r);
    uint16_t carry[1 << (2 * TP_NODE_CARRY_DEPTH)];
    tp_node_carry_regions(t, id, carry);
    tp_node_tins* tins = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_node_tins_build(g->n, s, tp_tree_samples(t, id), tp_tree_meta(t, id), carry,
                                 ti.err_unit_steps, 1u << k, &tins, &err));
    return tins;
}

TEST(a_level_holds_what_its_rungs_need)
{
    tp_tree* t = real_tree(257, 65);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    long levels = 0, rungs = 0;
    size_t held = 0, needed = 0;
    for (int64_t id = 0; id < g->node_count; id++)
        for (int k = 1; k <= g->n; k++) {
            tp_node_tins* tins = build_level(t, id, k);
            int count;
            const tp_node_tin* r = tp_node_tins_level(tins, k, &count);
            if (!count) {
                tp_node_tins_destroy(tins);
                continue;
            }
            size_t need = 4 * (size_t)r[count - 1].vertex_count; /* the finest has them all */
            for (int j = 0; j < count; j++) {
                EXPECT_TRUE(r[j].vertex_count <= r[count - 1].vertex_count);
                need += sizeof(tp_node_tin) + 6 * (size_t)r[j].triangle_count;
            }
            size_t bytes = tp_node_tins_bytes(tins);
            EXPECT_TRUE(bytes >= need && bytes <= need + HEADER_SLACK);
            if (!(bytes >= need && bytes <= need + HEADER_SLACK))
                tp_test_note("node %lld level %d: %zu bytes for %zu needed", (long long)id, k,
                             bytes, need);
            levels++, rungs += count, held += bytes, needed += need;
            tp_node_tins_destroy(tins);
        }
    tp_test_note("%ld levels, %ld rungs: %zu bytes held, %zu needed (%.0f a level)", levels, rungs,
                 held, needed, (double)held / (levels ? levels : 1));
    EXPECT_TRUE(levels >= 20); /* 16 leaves and their ancestors, levels 1..6 */
    tp_tree_destroy(t);
}

TEST(a_level_built_again_is_the_same)
{
    tp_tree* t = real_tree(257, 65);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    int compared = 0;
    for (int64_t id = 0; id < g->node_count; id++)
        for (int k = 1; k <= g->n; k++) {
            tp_node_tins *a = build_level(t, id, k), *b = build_level(t, id, k);
            int ca, cb;
            const tp_node_tin* ra = tp_node_tins_level(a, k, &ca);
            const tp_node_tin* rb = tp_node_tins_level(b, k, &cb);
            ASSERT_EQ_INT(ca, cb);
            EXPECT_TRUE(tp_node_tins_bytes(a) == tp_node_tins_bytes(b));
            for (int j = 0; j < ca; j++) {
                ASSERT_EQ_INT((int)ra[j].triangle_count, (int)rb[j].triangle_count);
                ASSERT_EQ_INT((int)ra[j].vertex_count, (int)rb[j].vertex_count);
                EXPECT_EQ_INT(0, memcmp(ra[j].triangles, rb[j].triangles,
                                        6 * (size_t)ra[j].triangle_count));
                EXPECT_EQ_INT(0, memcmp(ra[j].ij, rb[j].ij, 4 * (size_t)ra[j].vertex_count));
                EXPECT_TRUE(ra[j].own_steps == rb[j].own_steps);
                EXPECT_EQ_INT(0, memcmp(ra[j].eps_steps, rb[j].eps_steps, sizeof ra[j].eps_steps));
                compared++;
            }
            tp_node_tins_destroy(a);
            tp_node_tins_destroy(b);
        }
    EXPECT_TRUE(compared >= 40);
    tp_tree_destroy(t);
}

TEST(the_cache_counts_its_build_time)
{
    tp_tree* t = real_tree(257, 65);
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    tp_tin_cache* c = NULL;
    ASSERT_OK(tp_tin_cache_create(t, &c, NULL));
    EXPECT_TRUE(tp_tin_cache_build_ms(c) == 0);
    int64_t leaf = tp_tree_node_id(g, 0, 1, 1);
    size_t builds = 0;
    ASSERT_OK(tp_tin_cache_build(c, leaf, g->n, NULL));
    tp_tin_cache_stats(c, NULL, NULL, &builds);
    double one = tp_tin_cache_build_ms(c);
    EXPECT_EQ_INT(1, (int)builds);
    EXPECT_TRUE(one > 0 && one < 10000); /* a level of a 65-sample node: about a millisecond */
    ASSERT_OK(tp_tin_cache_build(c, leaf, g->n, NULL)); /* built: nothing to do */
    EXPECT_TRUE(tp_tin_cache_build_ms(c) == one);
    for (int k = 1; k < g->n; k++)
        ASSERT_OK(tp_tin_cache_build(c, leaf, k, NULL));
    tp_tin_cache_stats(c, NULL, NULL, &builds);
    EXPECT_EQ_INT(g->n, (int)builds);
    EXPECT_TRUE(tp_tin_cache_build_ms(c) > one);
    tp_test_note("%d levels built in %.2f ms", g->n, tp_tin_cache_build_ms(c));
    tp_tin_cache_destroy(c);
    tp_tree_destroy(t);
}

TP_TEST_MAIN(TESTS)
