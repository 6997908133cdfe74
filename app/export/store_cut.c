/* store_cut.c - the cuts of a store export drawn by a camera or by --full, and the nodes a static
 * cut chooses, installed as the cut (see store_cut.h). */
#include "store_cut.h"
#include "cut_worker.h"

#include "cli.h"

#include <stdlib.h>
#include <string.h>

/* Memory that must stay free while the cut's nodes are read. */
#define NODE_READ_MARGIN_BYTES ((uint64_t)64 << 20)

/* Reads nodes ids[0..n-1] (those not resident yet); TP_EXIT_OK, or a failure naming the node. */
static int load_nodes(store_export* x, const int64_t* ids, size_t n)
{
    for (size_t i = 0; i < n; i++)
        if (!tp_res_load(&x->res, ids[i]))
            return tp_store_export_fail(x, x->res.err.message);
    return TP_EXIT_OK;
}

int tp_store_cut_camera(store_export* x, const tp_camera* cam, const tp_lod_params* lod)
{
    int64_t* roots = malloc((size_t)x->g->root_count * sizeof *roots);
    if (!roots)
        return tp_store_export_fail(x, "out of memory");
    tp_tree_roots(x->g, roots, (size_t)x->g->root_count);
    int code = load_nodes(x, roots, (size_t)x->g->root_count);
    free(roots);
    if (code != TP_EXIT_OK)
        return code;
    tp_error err;
    for (int it = 0;; it++) {
        if (tp_cut_update(x->cut, cam, lod, &err) != TP_OK)
            return tp_store_export_fail(x, err.message);
        tp_cut_stats st;
        tp_cut_get_stats(x->cut, &st);
        if (st.triangles > TP_STORE_EXPORT_MAX_TRIANGLES)
            return tp_store_export_too_many(x, st.triangles, "the camera's cut draws at least");
        size_t nr;
        const int64_t* req = tp_cut_requests(x->cut, &nr);
        if (nr == 0 && x->tins && tp_cut_tins_build(x->tins, x->cut, 0) > 0)
            continue; /* every node read: the TIN levels it asked for, then once more */
        if (nr == 0) {
            if (st.substituted != 0) /* cannot happen: a substituted node requests */
                return tp_store_export_fail(
                    x, "the cut still substitutes nodes with nothing left to read");
            x->tris_cut = st.triangles;
            break;
        }
        /* the requests are valid until the next update: copy them before reading */
        int64_t* ids = malloc(nr * sizeof *ids);
        if (!ids)
            return tp_store_export_fail(x, "out of memory");
        memcpy(ids, req, nr * sizeof *ids);
        code = load_nodes(x, ids, nr);
        free(ids);
        if (code != TP_EXIT_OK)
            return code;
        if (tp_interrupted())
            return tp_cli_interrupted();
        if (!tp_store_export_room_for(x, NODE_READ_MARGIN_BYTES,
                                      "reading the camera's cut at full detail"))
            return TP_EXIT_FAILURE;
    }
    return TP_EXIT_OK;
}

int tp_store_cut_full(store_export* x)
{
    choice ch;
    int code = tp_choice_init(x, &ch);
    for (int r = 0; r < x->g->rows && code == TP_EXIT_OK; r++)
        for (int c = 0; c < x->g->cols && code == TP_EXIT_OK; c++) {
            int64_t id = tp_tree_node_id(x->g, 0, c, r);
            if ((x->metas[id].flags & TP_NODE_HAS_DRAWN) && !tp_choice_add(&ch, id, x->n))
                code = tp_store_export_fail(x, "out of memory");
        }
    if (code == TP_EXIT_OK)
        code = tp_choice_install(x, &ch);
    tp_choice_free(&ch);
    return code;
}

/* ---- the nodes a static cut chooses ---- */

int tp_choice_init(store_export* x, choice* ch)
{
    memset(ch, 0, sizeof *ch);
    ch->keep = calloc((size_t)x->g->node_count, 1);
    ch->level = malloc((size_t)x->g->node_count);
    if (!ch->keep || !ch->level)
        return tp_store_export_fail(x, "out of memory");
    memset(ch->level, -1, (size_t)x->g->node_count);
    return TP_EXIT_OK;
}

void tp_choice_free(choice* ch)
{
    free(ch->keep);
    free(ch->level);
    free(ch->ids);
}

int tp_choice_add(choice* ch, int64_t id, int k)
{
    if (!tp_array_grow((void**)&ch->ids, &ch->cap, ch->count + 1, sizeof *ch->ids))
        return 0;
    ch->level[id] = (int8_t)k;
    ch->ids[ch->count++] = id;
    return 1;
}

int tp_choice_install(store_export* x, choice* ch)
{
    uint8_t* keep = ch->keep;
    int* levels = malloc((ch->count ? ch->count : 1) * sizeof *levels);
    if (!levels)
        return tp_store_export_fail(x, "out of memory");
    for (size_t i = 0; i < ch->count; i++) {
        levels[i] = ch->level[ch->ids[i]];
        keep[ch->ids[i]] = 1;
    }
    tp_res_release_except(&x->res, keep);
    for (size_t i = 0; i < ch->count; i++) {
        keep[ch->ids[i]] = 0;
        if (!tp_res_load(&x->res, ch->ids[i])) {
            free(levels);
            return tp_store_export_fail(x, x->res.err.message);
        }
    }
    tp_error err;
    tp_status st = tp_cut_set_nodes(x->cut, ch->ids, levels, ch->count, &err);
    free(levels);
    return st == TP_OK ? TP_EXIT_OK : tp_store_export_fail(x, err.message);
}
