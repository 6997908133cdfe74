/* cut.c - the cut's object: its records of the nodes an update visits (found again through a
 * hash of node ids), the requests it lists, its life (create, destroy, the start of an update)
 * and the output of an update (after the stitching pass: the drawn nodes with their seams,
 * bounds and triangle counts, the requests most urgent first). What is drawn is decided in
 * cut_select.c, made stitchable in cut_stitch.c.
 */
#include "cut_int.h"

#include <stdlib.h>
#include <string.h>

/* ---- growing arrays and the node hash ---- */

int tp__cut_grow(tp_cut* c, void** p, size_t* cap, size_t need, size_t size)
{
    if (need <= *cap)
        return 1;
    size_t ncap = *cap ? *cap : 64;
    while (ncap < need)
        ncap *= 2;
    void* q = tp__alloc(&c->alloc, ncap, size);
    if (!q) {
        c->oom = 1;
        return 0;
    }
    if (*cap)
        memcpy(q, *p, *cap * size);
    tp__free(&c->alloc, *p);
    *p = q;
    *cap = ncap;
    return 1;
}

static int hash_put(tp_cut* c, int64_t key, int32_t val);

static int hash_grow(tp_cut* c)
{
    size_t ncap = c->hcap ? c->hcap * 2 : 1024;
    tp__cut_slot* h = tp__calloc(&c->alloc, ncap, sizeof *h);
    if (!h) {
        c->oom = 1;
        return 0;
    }
    tp__cut_slot* old = c->hash;
    size_t ocap = c->hcap;
    c->hash = h, c->hcap = ncap, c->hused = 0;
    for (size_t i = 0; i < ocap; i++)
        if (old[i].gen == c->gen)
            hash_put(c, old[i].key, old[i].val);
    tp__free(&c->alloc, old);
    return 1;
}

/* Sets key's value (inserting it). */
static int hash_put(tp_cut* c, int64_t key, int32_t val)
{
    if (2 * (c->hused + 1) > c->hcap && !hash_grow(c))
        return 0;
    for (size_t i = tp__cut_hash_slot(key, c->hcap);; i = (i + 1) & (c->hcap - 1)) {
        tp__cut_slot* sl = &c->hash[i];
        if (sl->gen != c->gen) {
            *sl = (tp__cut_slot){key, val, c->gen};
            c->hused++;
            return 1;
        }
        if (sl->key == key) {
            sl->val = val;
            return 1;
        }
    }
}

int tp__cut_add_at(tp_cut* c, int64_t node, int s, int cc, int rr)
{
    if (!tp__cut_grow(c, (void**)&c->rec, &c->rec_cap, c->rec_count + 1, sizeof *c->rec))
        return -1;
    int i = (int)c->rec_count;
    if (!hash_put(c, node, i))
        return -1;
    c->rec_count++;
    tp__cut_rec* r = &c->rec[i];
    memset(r, 0, sizeof *r);
    r->node = node;
    r->s = (int8_t)s, r->c = cc, r->r = rr;
    r->sph = -1;
    c->visited++;
    return i;
}

int tp__cut_add(tp_cut* c, int64_t node)
{
    int s, cc, rr;
    tp_tree_node_locate(&c->g, node, &s, &cc, &rr);
    return tp__cut_add_at(c, node, s, cc, rr);
}

void tp__cut_request(tp_cut* c, int64_t node, double prio)
{
    if (tp__cut_hash_get(c, node) != -1) /* visited or already requested */
        return;
    if (!tp__cut_grow(c, (void**)&c->req, &c->req_cap, c->req_count + 1, sizeof *c->req) ||
        !hash_put(c, node, -2))
        return;
    c->req[c->req_count++] = (tp__cut_req){node, prio};
}

/* ---- the cut's life and an update's output ---- */

tp_status tp_cut_create(const tp_tree* t, tp_cut** out, tp_error* err)
{
    assert(t && out);
    const tp_tree_desc* d = &t->desc;
    tp_allocator a = t->alloc;
    tp_cut* c = tp__calloc(&a, 1, sizeof *c);
    if (!c)
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "cut: out of memory");
    c->t = t;
    c->alloc = a;
    c->g = *tp_tree_get_geometry(t);
    c->n = c->g.n;
    memcpy(c->gt, d->geotransform, sizeof c->gt);
    c->cell_m = fmax(fabs(c->gt[1]), fabs(c->gt[5]));
    c->step = d->height_step_m;
    c->quant = d->quant_max_error_m;
    c->err_unit = d->err_unit_steps;
    c->zscale = 1;
    c->roots = tp__alloc(&a, (size_t)c->g.root_count, sizeof *c->roots);
    if (!c->roots) {
        tp_cut_destroy(c);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "cut: out of memory for %lld roots",
                        (long long)c->g.root_count);
    }
    tp_tree_roots(&c->g, c->roots, (size_t)c->g.root_count);
    for (int k = 0; k <= c->n; k++)
        c->tri_memo_count += (size_t)(k + 1) * (k + 1) * (k + 1) * (k + 1);
    c->tri_memo = tp__alloc(&a, c->tri_memo_count, sizeof *c->tri_memo);
    if (!c->tri_memo) {
        tp_cut_destroy(c);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "cut: out of memory");
    }
    memset(c->tri_memo, 0xFF, c->tri_memo_count * sizeof *c->tri_memo);
    c->tri_cache = tp__alloc(&a, TP__CUT_TRIS_CACHE, sizeof *c->tri_cache);
    if (!c->tri_cache) {
        tp_cut_destroy(c);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "cut: out of memory");
    }
    memset(c->tri_cache, 0xFF, TP__CUT_TRIS_CACHE * sizeof *c->tri_cache);
    *out = c;
    return TP_OK;
}

void tp_cut_destroy(tp_cut* c)
{
    if (!c)
        return;
    const tp_allocator* a = &c->alloc;
    tp__free(a, c->roots);
    tp__free(a, c->rec);
    tp__free(a, c->hash);
    tp__free(a, c->out);
    tp__free(a, c->req);
    tp__free(a, c->req_ids);
    tp__free(a, c->work);
    tp__free(a, c->tri_memo);
    tp__free(a, c->tri_cache);
    tp__free(a, c->add_cache);
    tp__free(a, c->out_tin);
    tp__free(a, c->tin_req);
    tp__free(a, c->tin_prio);
    tp__free(a, c->reuse);
    tp__free(a, c->fix);
    tp__spheres_destroy(c);
    tp__free(a, c);
}

void tp__cut_begin(tp_cut* c)
{
    c->gen++;
    if (c->gen == 0) { /* wrapped: every slot would look current */
        if (c->hcap)
            memset(c->hash, 0, c->hcap * sizeof *c->hash);
        c->gen = 1;
    }
    c->hused = 0;
    c->rec_count = 0;
    c->reuse_gen = 0; /* tp_cut_prepare_reuse's table is for the update before */
    c->req_count = 0;
    c->out_count = 0;
    c->tin_req_count = 0;
    c->visited = 0;
    c->decisions = 0;
    c->sph_on = 0;
    c->kid_rec = -1;
    c->unresolved = 0;
    c->oom = 0;
    c->has_output = 0;
}

/* Whether request a goes before b: higher priority first, then lower id. */
static int req_before(const tp__cut_req* a, const tp__cut_req* b)
{
    return a->prio > b->prio || (a->prio == b->prio && a->node < b->node);
}

/* Heap sort of the requests, most urgent first (qsort may allocate). */
static void sort_requests(tp__cut_req* r, size_t count)
{
    for (size_t end = count, start = count / 2;;) {
        size_t root;
        if (start > 0)
            root = --start;
        else if (end > 1) {
            tp__cut_req tmp = r[0];
            r[0] = r[--end];
            r[end] = tmp;
            root = 0;
        } else
            return;
        /* The top of the heap is the least urgent: it goes to the end. */
        for (size_t child; (child = 2 * root + 1) < end; root = child) {
            if (child + 1 < end && req_before(&r[child], &r[child + 1]))
                child++;
            if (!req_before(&r[root], &r[child]))
                break;
            tp__cut_req tmp = r[root];
            r[root] = r[child];
            r[child] = tmp;
        }
    }
}

tp_status tp__cut_finish(tp_cut* c, tp_error* err)
{
    if (!c->oom && !c->requests_only)
        tp__cut_constrain(c);
    return tp__cut_output(c, err);
}

tp_status tp__cut_output(tp_cut* c, tp_error* err)
{
    size_t drawn = 0;
    for (size_t i = 0; i < c->rec_count && !c->requests_only; i++)
        drawn += c->rec[i].state == TP__CUT_DRAWN;
    if (c->oom || !tp__cut_grow(c, (void**)&c->out, &c->out_cap, drawn, sizeof *c->out) ||
        !tp__cut_grow(c, (void**)&c->out_tin, &c->out_tin_cap, drawn, sizeof *c->out_tin) ||
        !tp__cut_grow(c, (void**)&c->req_ids, &c->req_ids_cap, c->req_count, sizeof *c->req_ids)) {
        c->rec_count = c->out_count = c->req_count = 0;
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "cut: out of memory after %d nodes", c->visited);
    }
    c->out_count = 0;
    for (size_t i = 0; i < c->rec_count; i++) {
        tp__cut_rec* r = &c->rec[i];
        int32_t tris_was = r->tris;
        r->out = -1;
        r->tris = -1;
        if (r->state != TP__CUT_DRAWN || c->requests_only)
            continue;
        r->out = (int32_t)c->out_count;
        tp_cut_node* o = &c->out[c->out_count++];
        /* a carried cut's record the stitching pass never queued has the level and the
           neighbours it was output with (tp__cut_changed queues every record whose seams may
           change): its seams, bound in metres and triangles are those */
        int same = c->carrying && !r->touched && tris_was >= 0;
        int nb[4], add[4];
        if (!same)
            r->cracks = (uint8_t)tp__cut_seams(c, (int)i, nb, add);
        c->unresolved += r->cracks;
        for (int s = 0; s < 4; s++) {
            if (same)
                nb[s] = r->nb[s], add[s] = TP_NO_NEIGHBOR;
            r->nb[s] = (int8_t)nb[s];
        }
        o->node = r->node;
        o->level = r->level;
        for (int s = 0; s < 4; s++) {
            o->nb[s] = (int8_t)nb[s];
            o->add[s] = (int8_t)add[s];
        }
        o->substituted = r->substituted;
        r->bound_px = 0;
        o->near_plane = 0;
        if (c->have_view && c->lp.mode == TP_LOD_ERROR) {
            /* over what is drawn of its box: at the near plane the box's bound is INFINITY
             * (the selection refines such a box as far as it can; a leaf with quantisation
             * error stays, and an ancestor drawn in place of nodes not resident) */
            double d = same ? r->bound_m : tp__cut_bound_m(c, (int)i, r->level, nb);
            if (add[0] != TP_NO_NEIGHBOR || add[1] != TP_NO_NEIGHBOR || add[2] != TP_NO_NEIGHBOR ||
                add[3] != TP_NO_NEIGHBOR) {
                double da = (tp__cut_add_bound_m(c, (int)i, r->level, add) + c->quant) * c->zscale;
                d = da > d ? da : d;
            }
            int near;
            r->bound_m = d;
            r->bound_px = (float)tp__projected_px_drawn(&c->v, &r->pb, d, &near);
            o->near_plane = (uint8_t)near;
        }
        o->bound_px = r->bound_px;
        int32_t tin_tris = tp__cut_pick_tin(c, (int)i, nb);
        r->tris = tin_tris >= 0 ? tin_tris : same ? tris_was : tp__cut_triangles(c, (int)i, nb);
        for (int s = 0; s < 4; s++) /* --stitch add: one more triangle per added vertex */
            if (add[s] != TP_NO_NEIGHBOR)
                r->tris += (1 << (add[s] > c->n ? c->n : add[s])) - (1 << r->level);
    }
    c->has_output = !c->requests_only;
    tp__cut_tin_sort_requests(c);
    sort_requests(c->req, c->req_count);
    for (size_t i = 0; i < c->req_count; i++)
        c->req_ids[i] = c->req[i].node;
    c->output_zscale = c->zscale;
    return TP_OK;
}

/* Copies n elements of size bytes from src into *dst, grown to hold them. */
static int copy_array(tp_cut* c, void** dst, size_t* cap, const void* src, size_t n, size_t size)
{
    if (n > *cap) { /* nothing of the old content is kept: no copy on growing */
        tp__free(&c->alloc, *dst);
        *dst = NULL, *cap = 0;
    }
    if (!tp__cut_grow(c, dst, cap, n, size))
        return 0;
    if (n)
        memcpy(*dst, src, n * size);
    return 1;
}

int tp__cut_copy(tp_cut* c, const tp_cut* from)
{
    assert(c->t == from->t);
    tp__cut_begin(c);
    if (from->hcap > c->hcap) {
        tp__free(&c->alloc, c->hash);
        c->hash = tp__alloc(&c->alloc, from->hcap, sizeof *c->hash);
        c->hcap = c->hash ? from->hcap : 0;
        if (!c->hash) {
            c->oom = 1;
            return 0;
        }
    }
    if (!copy_array(c, (void**)&c->rec, &c->rec_cap, from->rec, from->rec_count, sizeof *c->rec) ||
        !copy_array(c, (void**)&c->req, &c->req_cap, from->req, from->req_count, sizeof *c->req) ||
        !copy_array(c, (void**)&c->out, &c->out_cap, from->out, from->out_count, sizeof *c->out) ||
        !copy_array(c, (void**)&c->out_tin, &c->out_tin_cap, from->out_tin, from->out_count,
                    sizeof *c->out_tin))
        return 0;
    /* The hash slot for slot: slots are placed by the table's size, so c takes from's (a
       larger array of c's is used in part) */
    c->hcap = from->hcap;
    memcpy(c->hash, from->hash, from->hcap * sizeof *c->hash);
    c->hused = from->hused;
    c->gen = from->gen;
    c->rec_count = from->rec_count;
    c->req_count = from->req_count;
    c->out_count = from->out_count;
    c->lp = from->lp;
    c->have_view = from->have_view;
    c->output_zscale = from->output_zscale;
    c->v = from->v;
    c->f = from->f;
    c->zscale = from->zscale;
    c->visited = from->visited;
    return 1;
}

tp_status tp_cut_set_nodes(tp_cut* c, const int64_t* nodes, const int* levels, size_t count,
                           tp_error* err)
{
    assert(c && (nodes || count == 0) && (levels || count == 0));
    tp__cut_begin(c);
    c->have_view = 0;
    c->lp = (tp_lod_params){0};
    for (size_t i = 0; i < count && !c->oom; i++) {
        assert(nodes[i] >= 0 && nodes[i] < c->g.node_count && levels[i] >= 0 && levels[i] <= c->n &&
               tp__cut_find(c, nodes[i]) < 0);
        int r = tp__cut_add(c, nodes[i]);
        if (r < 0)
            break;
        const tp_node_meta* m = tp_tree_meta(c->t, nodes[i]);
        c->rec[r].level = (int8_t)levels[i];
        c->rec[r].state = m->qmin <= m->qmax ? TP__CUT_DRAWN : TP__CUT_EMPTY;
    }
    /* Ancestors as refined nodes, so that the stitching pass may collapse onto them. */
    for (size_t i = 0; i < count && !c->oom; i++)
        for (int64_t p = tp_tree_node_parent(&c->g, nodes[i]); p >= 0 && tp__cut_find(c, p) < 0;
             p = tp_tree_node_parent(&c->g, p)) {
            int r = tp__cut_add(c, p);
            if (r < 0)
                break;
            c->rec[r].state = TP__CUT_INTERIOR;
        }
    return tp__cut_finish(c, err);
}

tp_status tp_cut_set_vertical_scale(tp_cut* c, double scale)
{
    assert(c);
    if (!(scale >= TP_VERTICAL_SCALE_MIN && scale <= TP_VERTICAL_SCALE_MAX))
        return TP_ERR_INVALID_ARG;
    c->zscale = scale;
    return TP_OK;
}

const tp_cut_node* tp_cut_nodes(const tp_cut* c, size_t* count)
{
    assert(c && count);
    *count = c->out_count;
    return c->out;
}

const int64_t* tp_cut_requests(const tp_cut* c, size_t* count)
{
    assert(c && count);
    *count = c->req_count;
    return c->req_ids;
}
