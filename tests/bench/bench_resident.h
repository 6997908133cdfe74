/* bench_resident.h - every node of a store read and attached to its tree, for the timing
 * programs in tests/bench that run without a loader thread (bench_cut.c, bench_tin_nodes.c). */
#ifndef TP_BENCH_RESIDENT_H
#define TP_BENCH_RESIDENT_H

#include "tp_core.h"
#include "tp_io.h"

#include <stdio.h>
#include <stdlib.h>

/* The blocks (samples and cell mask: what tp_tree_attach reads) of every node, attached to
 * tree; free them after the tree. NULL after a message on stderr. */
static inline uint16_t* bench_attach_all(const tp_store* store, tp_tree* tree)
{
    const tp_tree_geometry* g = tp_tree_get_geometry(tree);
    size_t words = tp_tree_block_words(g->n);
    uint16_t* blocks = malloc((size_t)g->node_count * words * sizeof *blocks);
    if (!blocks) {
        fprintf(stderr, "out of memory for %lld nodes\n", (long long)g->node_count);
        return NULL;
    }
    for (int64_t id = 0; id < g->node_count; id++) {
        uint16_t* b = blocks + (size_t)id * words;
        tp_error err;
        if (tp_store_read_node(store, id, b, words, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            free(blocks);
            return NULL;
        }
        tp_tree_attach(tree, id, b);
    }
    return blocks;
}

#endif
