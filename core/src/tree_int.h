/* tree_int.h - the tree's private state (tree.c, tree_build.c), read by the cut (cut_int.h). */
#ifndef TP_CORE_TREE_INT_H
#define TP_CORE_TREE_INT_H

#include "internal.h"
#include "tp_tree.h"

/* The tree at run time (tree.c). Core code (the cut) reads desc for the step, quantisation
 * error, err_unit and metas. */
struct tp_tree {
    tp_tree_desc desc;         /* metas borrowed (or owned, below) */
    tp_allocator alloc;        /* always set */
    const uint16_t** samples;  /* node_count pointers, NULL when not resident */
    tp_node_meta* owned_metas; /* tp_tree_create_from_grid: metas and samples owned */
    uint16_t* owned_samples;
    uint64_t detaches;         /* tp_tree_detaches */
};

/* The tree takes ownership of metas and samples (tree.c; for tp_tree_create_from_grid). */
void tp__tree_own(tp_tree* t, tp_node_meta* metas, uint16_t* samples);

#endif
