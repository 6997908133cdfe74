/* store_cut_max_error.c - the cut of `export --max-error M --mesh patches` on a store: chosen on
 * the node table (each node at the coarsest level whose bound is <= M), balanced, stitched, and
 * raised where the stitching passes M (see store_cut.h). */
#include "store_cut.h"

#include "cli.h"

#include <stdlib.h>
#include <string.h>

/* A node's error bound (m) at level k with neighbour levels nb (NULL: no stitching), its
 * quantisation included. */
static double bound_m(const store_export* x, int64_t node, int k, const int nb[4])
{
    return tp_node_error_bound(&x->metas[node], x->n, k, nb, x->step_m, x->unit) + x->quant_m;
}

/* The coarsest level k of node whose bound (no stitching) stays <= M at k and every finer
 * level, or -1 when the node is to be replaced by its children. */
static int static_level(const store_export* x, int64_t node, int scale)
{
    const tp_node_meta* m = &x->metas[node];
    double M = x->r->max_error_m;
    if (scale > 0 && (!(m->flags & TP_NODE_COMPLETE) || bound_m(x, node, x->n, NULL) > M))
        return -1;
    if (!(m->flags & TP_NODE_COMPLETE))
        return x->n; /* an incomplete leaf: only drawn at n */
    int k = x->n;
    while (k > 0 && bound_m(x, node, k - 1, NULL) <= M)
        k--;
    return k;
}

/* Chooses node, or the nodes under it, at their static levels. */
static int choose(store_export* x, choice* ch, int64_t node)
{
    int64_t stack[4 * TP_TREE_MAX_SCALES + 4];
    int top = 0;
    stack[top++] = node;
    while (top > 0) {
        int64_t id = stack[--top];
        if (!(x->metas[id].flags & TP_NODE_HAS_DRAWN))
            continue;
        int s, c, r;
        tp_tree_node_locate(x->g, id, &s, &c, &r);
        int k = static_level(x, id, s);
        if (k < 0) {
            for (int q = 0; q < 4; q++)
                stack[top++] = tp_tree_node_child(x->g, id, q);
            continue;
        }
        if (!tp_choice_add(ch, id, k))
            return 0;
    }
    return 1;
}

/* The chosen node of scale >= the scale of `node` that borders it on side (0 top, 1 right,
 * 2 bottom, 3 left), or -1 (smaller nodes there, or the map's edge). */
static int64_t chosen_neighbor(const store_export* x, const choice* ch, int64_t node, int side)
{
    static const int dc[4] = {0, 1, 0, -1}, dr[4] = {-1, 0, 1, 0};
    int s, c, r;
    tp_tree_node_locate(x->g, node, &s, &c, &r);
    int64_t cc = (int64_t)c + dc[side], rr = (int64_t)r + dr[side];
    if (cc < 0 || rr < 0)
        return -1;
    for (; s < x->g->scales; s++, cc >>= 1, rr >>= 1) {
        if (cc >= x->g->node_cols[s] || rr >= x->g->node_rows[s])
            return -1;
        int64_t id = tp_tree_node_id(x->g, s, (int)cc, (int)rr);
        if (ch->level[id] >= 0)
            return id;
    }
    return -1;
}

/* Replaces chosen node b by its children at their static levels. */
static int split_choice(store_export* x, choice* ch, int64_t b)
{
    ch->level[b] = -1;
    for (int q = 0; q < 4; q++)
        if (!choose(x, ch, tp_tree_node_child(x->g, b, q)))
            return 0;
    return 1;
}

/* No two chosen neighbours more than n scales apart (the stitching could not join them without
 * drawing an ancestor at level n, whose error is not bounded by M): the larger one is split. */
static int balance(store_export* x, choice* ch)
{
    for (int changed = 1; changed;) {
        changed = 0;
        for (size_t i = 0; i < ch->count; i++) {
            int64_t a = ch->ids[i];
            if (ch->level[a] < 0)
                continue;
            int sa, c, r;
            tp_tree_node_locate(x->g, a, &sa, &c, &r);
            for (int side = 0; side < 4; side++) {
                int64_t b = chosen_neighbor(x, ch, a, side);
                int sb;
                if (b < 0)
                    continue;
                tp_tree_node_locate(x->g, b, &sb, &c, &r);
                if (sb - sa > x->n) {
                    if (!split_choice(x, ch, b))
                        return 0;
                    changed = 1;
                }
            }
        }
    }
    size_t w = 0; /* drop the stale ids */
    for (size_t i = 0; i < ch->count; i++)
        if (ch->level[ch->ids[i]] >= 0)
            ch->ids[w++] = ch->ids[i];
    ch->count = w;
    return 1;
}

/* Where a stitched node's bound (its eps table for the neighbour levels it really has) passes
 * M, raises the coarser neighbour that moves its vertices one level (a node at level n is split
 * instead). Returns how many were raised, or -1 when out of memory. */
static long raise_neighbors(store_export* x, choice* ch, const tp_cut_node* out, size_t count)
{
    double M = x->r->max_error_m;
    long raised = 0;
    for (size_t i = 0; i < count; i++) {
        int nb[4];
        memcpy(nb, (int[4]){out[i].nb[0], out[i].nb[1], out[i].nb[2], out[i].nb[3]}, sizeof nb);
        if (bound_m(x, out[i].node, out[i].level, nb) <= M)
            continue;
        for (int side = 0; side < 4; side++) {
            int one[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
            one[side] = nb[side];
            if (nb[side] == TP_NO_NEIGHBOR || bound_m(x, out[i].node, out[i].level, one) <= M)
                continue;
            int64_t b = chosen_neighbor(x, ch, out[i].node, side);
            if (b < 0 || b == out[i].node)
                continue;
            if (ch->level[b] < x->n) {
                ch->level[b]++;
            } else {
                int sb, c, r;
                tp_tree_node_locate(x->g, b, &sb, &c, &r);
                if (sb == 0)
                    continue; /* a leaf at n moves nothing of a node of its size */
                if (!split_choice(x, ch, b))
                    return -1;
            }
            raised++;
        }
    }
    return raised;
}

/* --max-error M: chosen on the node table, stitched, and where a stitched node's bound passes
 * M, the coarser neighbour raised (raise_neighbors), until no drawn node passes M. */
int tp_store_cut_max_error(store_export* x)
{
    choice ch;
    int code = tp_choice_init(x, &ch);
    int64_t* roots = malloc((size_t)x->g->root_count * sizeof *roots);
    if (code != TP_EXIT_OK || !roots) {
        code = code != TP_EXIT_OK ? code : tp_store_export_fail(x, "out of memory");
        goto done;
    }
    tp_tree_roots(x->g, roots, (size_t)x->g->root_count);
    for (int64_t i = 0; i < x->g->root_count; i++)
        if (!choose(x, &ch, roots[i])) {
            code = tp_store_export_fail(x, "out of memory");
            goto done;
        }
    for (int round = 0;; round++) {
        if (!balance(x, &ch)) {
            code = tp_store_export_fail(x, "out of memory");
            goto done;
        }
        size_t tris = 0;
        for (size_t i = 0; i < ch.count; i++)
            tris += (size_t)2 << (2 * ch.level[ch.ids[i]]);
        if (tris > TP_STORE_EXPORT_MAX_TRIANGLES) {
            code = tp_store_export_too_many(x, tris, "--max-error's cut draws up to");
            goto done;
        }
        if ((code = tp_choice_install(x, &ch)) != TP_EXIT_OK)
            goto done;
        size_t count;
        const tp_cut_node* out = tp_cut_nodes(x->cut, &count);
        for (size_t i = 0; i < count; i++) /* the stitching only raises levels */
            ch.level[out[i].node] = out[i].level;
        long raised = raise_neighbors(x, &ch, out, count);
        if (raised < 0) {
            code = tp_store_export_fail(x, "out of memory");
            goto done;
        }
        if (!raised)
            break;
        if (round > 64 * (x->n + x->g->scales)) {
            code = tp_store_export_fail(x, "--max-error: the stitched cut does not settle (a bug)");
            goto done;
        }
    }
    {
        tp_cut_stats st;
        tp_cut_get_stats(x->cut, &st);
        x->tris_cut = st.triangles;
    }
done:
    tp_choice_free(&ch);
    free(roots);
    return code;
}
