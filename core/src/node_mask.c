/* node_mask.c - cell masks: which cells of a node's lattice have every full-resolution sample
 * under them drawn (see tp_node_mask_from_q in tp_core.h).
 *
 * A leaf's mask comes from its samples; a parent's from its children's, each child's 2x2 cells
 * making one parent cell (nested decimation: the parent's level-n cell is the child's level
 * n-1 cell). So the build carries 4^n bits per node up the tree, and the store keeps the masks
 * of the nodes of scale >= 1 that are incomplete (a leaf's is recomputed from its samples).
 */
#include "internal.h"
#include "tp_tree.h"

#include <string.h>

size_t tp_node_mask_words(int n)
{
    assert(n >= 2 && n <= TP_MAX_N);
    return ((size_t)1 << (2 * n)) / 16;
}

size_t tp_node_filled_words(int n)
{
    assert(n >= 2 && n <= TP_MAX_N);
    size_t side = ((size_t)1 << n) + 1;
    return (side * side + 15) / 16;
}

size_t tp_tree_block_words(int n)
{
    size_t side = ((size_t)1 << n) + 1;
    return side * side + tp_node_mask_words(n) + tp_node_filled_words(n);
}

static inline int bit(const uint16_t* mask, int n, int x, int y)
{
    size_t b = ((size_t)y << n) + (size_t)x;
    return mask[b >> 4] >> (b & 15) & 1;
}

void tp_node_mask_from_q(int n, const int32_t* q, uint16_t* mask)
{
    assert(q && mask);
    int cells = 1 << n, side = cells + 1;
    memset(mask, 0, tp_node_mask_words(n) * sizeof *mask);
    for (int y = 0; y < cells; y++) {
        const int32_t* a = q + (size_t)y * side;
        const int32_t* b = a + side;
        for (int x = 0; x < cells; x++)
            if (a[x] != INT32_MIN && a[x + 1] != INT32_MIN && b[x] != INT32_MIN &&
                b[x + 1] != INT32_MIN) {
                size_t i = ((size_t)y << n) + (size_t)x;
                mask[i >> 4] |= (uint16_t)(1u << (i & 15));
            }
    }
}

void tp_node_mask_from_samples(int n, const uint16_t* samples, uint16_t* mask)
{
    assert(samples && mask);
    int cells = 1 << n, side = cells + 1;
    memset(mask, 0, tp_node_mask_words(n) * sizeof *mask);
    for (int y = 0; y < cells; y++) {
        const uint16_t* a = samples + (size_t)y * side;
        const uint16_t* b = a + side;
        for (int x = 0; x < cells; x++)
            if (a[x] != TP_TREE_NO_HEIGHT && a[x + 1] != TP_TREE_NO_HEIGHT &&
                b[x] != TP_TREE_NO_HEIGHT && b[x + 1] != TP_TREE_NO_HEIGHT) {
                size_t i = ((size_t)y << n) + (size_t)x;
                mask[i >> 4] |= (uint16_t)(1u << (i & 15));
            }
    }
}

void tp_node_mask_from_children(int n, const uint16_t* const children[4], uint16_t* mask)
{
    assert(children && mask);
    int cells = 1 << n, half = cells / 2;
    memset(mask, 0, tp_node_mask_words(n) * sizeof *mask);
    for (int y = 0; y < cells; y++)
        for (int x = 0; x < cells; x++) {
            const uint16_t* k = children[(x >= half) + 2 * (y >= half)];
            assert(k);
            int cx = 2 * (x % half), cy = 2 * (y % half);
            if (bit(k, n, cx, cy) & bit(k, n, cx + 1, cy) & bit(k, n, cx, cy + 1) &
                bit(k, n, cx + 1, cy + 1)) {
                size_t i = ((size_t)y << n) + (size_t)x;
                mask[i >> 4] |= (uint16_t)(1u << (i & 15));
            }
        }
}

int tp_node_mask_all(const uint16_t* mask, int n, int x0, int y0, int x1, int y1)
{
    assert(mask && x0 >= 0 && y0 >= 0 && x1 <= (1 << n) && y1 <= (1 << n));
    for (int y = y0; y < y1; y++) {
        size_t b = ((size_t)y << n) + (size_t)x0, e = ((size_t)y << n) + (size_t)x1;
        while (b < e && (b & 15)) { /* to a word boundary */
            if (!(mask[b >> 4] >> (b & 15) & 1))
                return 0;
            b++;
        }
        for (; b + 16 <= e; b += 16)
            if (mask[b >> 4] != 0xFFFFu)
                return 0;
        for (; b < e; b++)
            if (!(mask[b >> 4] >> (b & 15) & 1))
                return 0;
    }
    return 1;
}
