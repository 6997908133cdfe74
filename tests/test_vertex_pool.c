/*
 * test_vertex_pool.c - the renderer's vertex pools and triangle-list regions
 * (app/render/vertex_pool.c) in a headless GL context (llvmpipe here, whose buffers are the
 * process's memory: issue 32 item 5).
 *
 *   - a region holds exactly the indices written, read back from the index buffer: 16-bit at
 *     levels whose slots hold at most 65536 vertices (k <= 7), 32-bit above (level 8: 66,049
 *     vertices, an index of 66,048 must come back whole);
 *   - a full pool grows by a quarter, not by doubling: 100 items of level 4 taken in one frame
 *     from a pool of one slot leave at most 1.25 * 100 + 1 slots (doubling leaves 128), and 40
 *     regions at most 1.25 * 40 + 1 (doubling: 64); every region keeps its indices through the
 *     buffer's growth (the old buffer copied into the new).
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"

#include "gl_context.h"
#include "vertex_pool.h"

#include <epoxy/gl.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#define VERTEX_BYTES 16

static size_t slot_verts(int k)
{
    size_t side = ((size_t)1 << k) + 1;
    return side * side;
}

/* The count indices of handle h's region as stored (16 or 32-bit), widened into out. */
static size_t read_region(tp_vertex_pool* p, int h, uint32_t* out, size_t cap)
{
    int k = tp_vertex_pool_level(h);
    size_t offset = 0, count = tp_vertex_pool_triangles(p, h, &offset);
    if (count > cap)
        return 0;
    size_t isize = tp_vertex_pool_index_type(p, k) == GL_UNSIGNED_SHORT ? 2 : 4;
    void* raw = malloc(count * isize + 1);
    glBindBuffer(GL_COPY_READ_BUFFER, tp_vertex_pool_index_buffer(p, k));
    glGetBufferSubData(GL_COPY_READ_BUFFER, (GLintptr)offset, (GLsizeiptr)(count * isize), raw);
    for (size_t i = 0; i < count; i++)
        out[i] = isize == 2 ? ((const uint16_t*)raw)[i] : ((const uint32_t*)raw)[i];
    free(raw);
    return count;
}

/* Indices of a level-k item: a pseudo-random sequence over its slot, with its last vertex. */
static void make_indices(uint32_t* idx, size_t count, int k, uint32_t seed)
{
    uint32_t verts = (uint32_t)slot_verts(k), x = seed * 2654435761u + 1;
    for (size_t i = 0; i < count; i++) {
        x = x * 1664525u + 1013904223u;
        idx[i] = (x >> 8) % verts;
    }
    idx[count / 2] = verts - 1;
}

TEST(regions_hold_their_indices_16_bit_up_to_level_7_32_bit_above)
{
    tp_gl_context* ctx = NULL;
    tp_error err = {{0}};
    if (!tp_gl_context_create_headless(64, 64, &ctx, &err))
        SKIP("no headless OpenGL here: %s", err.message);
    tp_vertex_pool* p = tp_vertex_pool_create(8, VERTEX_BYTES, 0, (size_t)1 << 30, 64 << 10, &err);
    ASSERT_TRUE(p != NULL);
    for (int k = 0; k <= 8; k++)
        EXPECT_EQ_INT(k <= 7 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT,
                      (int)tp_vertex_pool_index_type(p, k));
    tp_vertex_pool_begin_frame(p);
    static const int levels[] = {2, 6, 7, 8};
    for (int j = 0; j < 4; j++) {
        int k = levels[j], fresh = 0;
        size_t count = tp_vertex_pool_region_indices(p, k) / 2 / 3 * 3; /* half a region */
        uint32_t* idx = malloc(count * sizeof *idx);
        uint32_t* back = malloc(count * sizeof *back);
        ASSERT_TRUE(idx && back);
        make_indices(idx, count, k, (uint32_t)k);
        int h = tp_vertex_pool_take(p, 1000 + k, k, &fresh);
        ASSERT_TRUE(h >= 0 && fresh);
        ASSERT_TRUE(tp_vertex_pool_write_triangles(p, h, idx, count));
        EXPECT_EQ_INT((int)count, (int)read_region(p, h, back, count));
        EXPECT_TRUE(memcmp(idx, back, count * sizeof *idx) == 0);
        if (k == 8)
            EXPECT_EQ_INT(66048, (int)back[count / 2]); /* above 65535: not truncated */
        free(idx);
        free(back);
    }
    /* 16 regions made at each level written: 2 bytes an index up to level 7, 4 at level 8 */
    double want = 0;
    for (int j = 0; j < 4; j++)
        want += 16.0 * 6 * (double)((size_t)1 << (2 * levels[j])) * (levels[j] <= 7 ? 2 : 4);
    EXPECT_EQ_DBL(want, (double)tp_vertex_pool_index_bytes(p));
    EXPECT_EQ_INT(GL_NO_ERROR, (int)glGetError());
    tp_vertex_pool_destroy(p);
    tp_gl_context_destroy(ctx);
}

TEST(a_full_pool_and_its_regions_grow_by_a_quarter_keeping_what_they_hold)
{
    tp_gl_context* ctx = NULL;
    tp_error err = {{0}};
    if (!tp_gl_context_create_headless(64, 64, &ctx, &err))
        SKIP("no headless OpenGL here: %s", err.message);
    const int k = 4, items = 100, lists = 40;
    size_t slot_bytes = slot_verts(k) * VERTEX_BYTES; /* 4,624 */
    /* initial bytes of one level-4 slot: levels 0..3 start with what fits in it */
    tp_vertex_pool* p = tp_vertex_pool_create(k, VERTEX_BYTES, 0, (size_t)1 << 30, slot_bytes, &err);
    ASSERT_TRUE(p != NULL);
    size_t start = tp_vertex_pool_gpu_bytes(p);
    double others = 0;
    for (int l = 0; l < k; l++)
        others += (double)(slot_bytes / (slot_verts(l) * VERTEX_BYTES)) * slot_verts(l) * VERTEX_BYTES;
    EXPECT_EQ_DBL(others + (double)slot_bytes, (double)start); /* level 4: one slot */
    tp_vertex_pool_begin_frame(p);
    int h[100];
    size_t count = tp_vertex_pool_region_indices(p, k) / 3 * 3;
    uint32_t* idx = malloc(count * sizeof *idx);
    uint32_t* back = malloc(count * sizeof *back);
    ASSERT_TRUE(idx && back);
    for (int i = 0; i < items; i++) {
        int fresh = 0;
        h[i] = tp_vertex_pool_take(p, i, k, &fresh);
        ASSERT_TRUE(h[i] >= 0 && fresh);
        if (i < lists) {
            make_indices(idx, count - 3 * (size_t)i, k, (uint32_t)i);
            ASSERT_TRUE(tp_vertex_pool_write_triangles(p, h[i], idx, count - 3 * (size_t)i));
        }
    }
    /* every item has its own slot */
    for (int i = 0; i < items; i++)
        for (int j = 0; j < i; j++)
            ASSERT_TRUE(tp_vertex_pool_base_vertex(p, h[i]) != tp_vertex_pool_base_vertex(p, h[j]));
    double region_bytes = (double)tp_vertex_pool_region_indices(p, k) * 2;
    double index_bytes = (double)tp_vertex_pool_index_bytes(p);
    double vertex_bytes = (double)tp_vertex_pool_gpu_bytes(p) - index_bytes - others;
    tp_test_note("level 4: %.0f slots for %d items, %.0f regions for %d lists", vertex_bytes /
                 (double)slot_bytes, items, index_bytes / region_bytes, lists);
    EXPECT_GE(vertex_bytes, items * (double)slot_bytes);
    EXPECT_LE(vertex_bytes, (1.25 * items + 1) * (double)slot_bytes);
    EXPECT_GE(index_bytes, lists * region_bytes);
    EXPECT_LE(index_bytes, (1.25 * lists + 1) * region_bytes);
    /* the first regions written went through every growth of the index buffer */
    for (int i = 0; i < lists; i++) {
        size_t n = count - 3 * (size_t)i;
        make_indices(idx, n, k, (uint32_t)i);
        ASSERT_EQ_INT((int)n, (int)read_region(p, h[i], back, count));
        if (memcmp(idx, back, n * sizeof *idx) != 0)
            FAIL("region of item %d changed", i);
    }
    EXPECT_EQ_INT(GL_NO_ERROR, (int)glGetError());
    free(idx);
    free(back);
    tp_vertex_pool_destroy(p);
    tp_gl_context_destroy(ctx);
}

#define TESTS(X)                                                                                   \
    X(regions_hold_their_indices_16_bit_up_to_level_7_32_bit_above)                                \
    X(a_full_pool_and_its_regions_grow_by_a_quarter_keeping_what_they_hold)
TP_TEST_MAIN(TESTS)
