/*
 * tp_test_tree.h - the tree geometry of tp_core.h's "Hierarchy" section, computed here from its
 * definitions (the fewest leaves of 2^n covering the grid, node (s, c, r) for c < cols >> s and
 * r < rows >> s, ids from the top scale down, row-major), for the store's tests and bench
 * without the core's tree builder. Plain C, no test framework needed.
 */
#ifndef TP_TEST_TREE_H
#define TP_TEST_TREE_H

#include "tp_core.h"

#include <string.h>

/* 0 when the sizes are out of range (n = log2(patch_size - 1) in 4..TP_MAX_N). */
static inline int tpt_tree_geometry(int src_width, int src_height, int patch_size,
                                    tp_tree_geometry* g)
{
    int n = 0;
    while ((1 << n) + 1 < patch_size)
        n++;
    if ((1 << n) + 1 != patch_size || n < 4 || n > TP_MAX_N || src_width < 1 || src_height < 1)
        return 0;
    memset(g, 0, sizeof *g);
    g->n = n;
    g->src_width = src_width;
    g->src_height = src_height;
    g->cols = src_width > 1 ? (int)(((int64_t)src_width - 2) / (1 << n)) + 1 : 1;
    g->rows = src_height > 1 ? (int)(((int64_t)src_height - 2) / (1 << n)) + 1 : 1;
    g->width = g->cols * (1 << n) + 1;
    g->height = g->rows * (1 << n) + 1;
    while ((g->cols >> g->scales) >= 1 && (g->rows >> g->scales) >= 1)
        g->scales++;
    if (g->scales > TP_TREE_MAX_SCALES)
        return 0;
    for (int s = 0; s < TP_TREE_MAX_SCALES; s++) {
        g->node_cols[s] = g->cols >> s;
        g->node_rows[s] = g->rows >> s;
    }
    int64_t id = 0;
    for (int s = g->scales - 1; s >= 0; s--) {
        g->first_node[s] = id;
        id += (int64_t)g->node_cols[s] * g->node_rows[s];
    }
    g->node_count = id;
    /* a root: a node whose parent (s + 1, c / 2, r / 2) does not exist */
    g->root_count = 0;
    for (int s = 0; s < g->scales; s++)
        for (int r = 0; r < g->node_rows[s]; r++)
            for (int c = 0; c < g->node_cols[s]; c++)
                if (s + 1 == g->scales || c / 2 >= g->node_cols[s + 1] || r / 2 >= g->node_rows[s + 1])
                    g->root_count++;
    return 1;
}

#endif
