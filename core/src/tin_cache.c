/* tin_cache.c - a tree's node TINs built one level at a time as the view asks for them
 * (tp_tree.h, "TINs built as the view needs them"; issue 32 item 2).
 *
 * A pointer per tree node to its entry (allocated at the node's first build): each level's
 * TINs and which levels were built, published with release stores so that a cut on another
 * thread sees either nothing or the whole entry. Entries are listed so that pruning visits only
 * the nodes that have one.
 */
#include "tree_int.h"
#include "tp_cut.h"

#include <stdatomic.h>
#include <stdlib.h>
#include <time.h>

typedef struct tin_entry {
    _Atomic(tp_node_tins*) level[TP_MAX_LEVELS];
    atomic_uint built; /* bit k: level k was built (its pointer may be NULL: no TIN there) */
    uint32_t drawn[TP_MAX_LEVELS]; /* the frame (tp_tin_cache_mark_drawn) it was last drawn */
} tin_entry;

struct tp_tin_cache {
    const tp_tree* t;
    _Atomic(tin_entry*)* node; /* node_count */
    int64_t* listed;           /* nodes with an entry */
    size_t listed_count, listed_cap;
    size_t bytes, levels, builds;
    double build_ms; /* the time tp_tin_cache_build spent building */
    uint32_t frame; /* tp_tin_cache_mark_drawn's count */
};

tp_status tp_tin_cache_create(const tp_tree* t, tp_tin_cache** out, tp_error* err)
{
    assert(t && out);
    tp_tin_cache* c = calloc(1, sizeof *c);
    int64_t count = tp_tree_get_geometry(t)->node_count;
    if (c)
        c->node = calloc((size_t)count, sizeof *c->node);
    if (!c || !c->node) {
        free(c);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "TIN cache: out of memory for %lld nodes",
                        (long long)count);
    }
    c->t = t;
    *out = c;
    return TP_OK;
}

static void entry_free(tin_entry* e)
{
    for (int k = 0; e && k < TP_MAX_LEVELS; k++)
        tp_node_tins_destroy(atomic_load_explicit(&e->level[k], memory_order_relaxed));
    free(e);
}

void tp_tin_cache_destroy(tp_tin_cache* c)
{
    if (!c)
        return;
    for (size_t i = 0; i < c->listed_count; i++)
        entry_free(atomic_load_explicit(&c->node[c->listed[i]], memory_order_relaxed));
    free(c->listed);
    free(c->node);
    free(c);
}

const tp_node_tins* tp_tin_cache_get(const tp_tin_cache* c, int64_t node, int k, int* built)
{
    assert(c && node >= 0 && k >= 0 && k < TP_MAX_LEVELS && built);
    tin_entry* e = atomic_load_explicit(&c->node[node], memory_order_acquire);
    *built = e && (atomic_load_explicit(&e->built, memory_order_acquire) >> k & 1);
    return *built ? atomic_load_explicit(&e->level[k], memory_order_relaxed) : NULL;
}

tp_status tp_tin_cache_build(tp_tin_cache* c, int64_t node, int k, tp_error* err)
{
    assert(c && node >= 0 && k >= 0 && k < TP_MAX_LEVELS);
    const uint16_t* q = tp_tree_samples(c->t, node);
    tin_entry* e = atomic_load_explicit(&c->node[node], memory_order_relaxed);
    if (!q || (e && (atomic_load_explicit(&e->built, memory_order_relaxed) >> k & 1)))
        return TP_OK;
    if (!e) {
        if (c->listed_count == c->listed_cap) {
            size_t cap = c->listed_cap ? 2 * c->listed_cap : 256;
            int64_t* l = realloc(c->listed, cap * sizeof *l);
            if (!l)
                return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "TIN cache: out of memory");
            c->listed = l, c->listed_cap = cap;
        }
        if (!(e = calloc(1, sizeof *e)))
            return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "TIN cache: out of memory");
        c->listed[c->listed_count++] = node;
        atomic_store_explicit(&c->node[node], e, memory_order_release);
    }
    const tp_tree_geometry* g = tp_tree_get_geometry(c->t);
    int s, cc, rr;
    tp_tree_node_locate(g, node, &s, &cc, &rr);
    tp_node_tins* tins = NULL;
    struct timespec t0, t1;
    int timed = timespec_get(&t0, TIME_UTC) == TIME_UTC;
    uint16_t carry[1 << (2 * TP_NODE_CARRY_DEPTH)];
    tp_node_carry_regions(c->t, node, carry);
    tp_status st = tp_node_tins_build(g->n, s, q, tp_tree_meta(c->t, node), carry,
                                      c->t->desc.err_unit_steps, 1u << k, &tins, err);
    if (timed && timespec_get(&t1, TIME_UTC) == TIME_UTC)
        c->build_ms += (double)(t1.tv_sec - t0.tv_sec) * 1e3 + (t1.tv_nsec - t0.tv_nsec) / 1e6;
    if (st != TP_OK)
        return st;
    c->bytes += tp_node_tins_bytes(tins);
    c->levels++;
    c->builds++;
    e->drawn[k] = c->frame; /* as if drawn now: kept max_age frames at least */
    atomic_store_explicit(&e->level[k], tins, memory_order_relaxed);
    atomic_fetch_or_explicit(&e->built, 1u << k, memory_order_release);
    return TP_OK;
}

void tp_tin_cache_mark_drawn(tp_tin_cache* c, const tp_cut* cut)
{
    assert(c && cut);
    c->frame++;
    size_t count;
    const tp_cut_node* o = tp_cut_nodes(cut, &count);
    for (size_t i = 0; i < count; i++) {
        tin_entry* e = atomic_load_explicit(&c->node[o[i].node], memory_order_relaxed);
        if (e)
            e->drawn[o[i].level] = c->frame;
    }
}

/* Frees level k of entry e (built) and says so in the counts. */
static void drop_level(tp_tin_cache* c, tin_entry* e, int k)
{
    tp_node_tins* t = atomic_load_explicit(&e->level[k], memory_order_relaxed);
    atomic_fetch_and_explicit(&e->built, ~(1u << k), memory_order_release);
    atomic_store_explicit(&e->level[k], NULL, memory_order_relaxed);
    c->bytes -= tp_node_tins_bytes(t);
    c->levels--;
    tp_node_tins_destroy(t);
}

/* Frees levels of resident nodes that were not drawn, and those drawn too long ago; then frees
 * the entries left with no level. */
static void prune_age(tp_tin_cache* c, unsigned max_age_frames)
{
    size_t o = 0;
    for (size_t i = 0; i < c->listed_count; i++) {
        int64_t node = c->listed[i];
        tin_entry* e = atomic_load_explicit(&c->node[node], memory_order_relaxed);
        unsigned built = atomic_load_explicit(&e->built, memory_order_relaxed);
        int resident = tp_tree_samples(c->t, node) != NULL;
        for (int k = 0; k < TP_MAX_LEVELS; k++)
            if ((built >> k & 1) &&
                (!resident || (max_age_frames && c->frame - e->drawn[k] > max_age_frames)))
                drop_level(c, e, k);
        if (atomic_load_explicit(&e->built, memory_order_relaxed)) {
            c->listed[o++] = node;
            continue;
        }
        atomic_store_explicit(&c->node[node], NULL, memory_order_release);
        free(e);
    }
    c->listed_count = o;
}

typedef struct aged_level {
    uint32_t age; /* frames since it was last drawn */
    int k;
    tin_entry* e;
} aged_level;

static int older_first(const void* a, const void* b)
{
    uint32_t x = ((const aged_level*)a)->age, y = ((const aged_level*)b)->age;
    return x < y ? 1 : x > y ? -1 : 0;
}

/* Frees the levels drawn longest ago until c holds at most max_bytes; never one drawn in the last
 * two marked frames (the frame's cut, or built since the frame before: the next cut draws it). Returns 1 when it freed any (their entries may now be empty). */
static int drop_oldest(tp_tin_cache* c, size_t max_bytes)
{
    size_t n = 0;
    aged_level* a = malloc(c->levels * sizeof *a);
    if (!a)
        return 0; /* the budget is kept at the next prune */
    for (size_t i = 0; i < c->listed_count && n < c->levels; i++) {
        tin_entry* e = atomic_load_explicit(&c->node[c->listed[i]], memory_order_relaxed);
        unsigned built = atomic_load_explicit(&e->built, memory_order_relaxed);
        for (int k = 0; k < TP_MAX_LEVELS && n < c->levels; k++)
            if ((built >> k & 1) && c->frame - e->drawn[k] > 1)
                a[n++] = (aged_level){c->frame - e->drawn[k], k, e};
    }
    qsort(a, n, sizeof *a, older_first);
    size_t i = 0;
    for (; i < n && c->bytes > max_bytes; i++)
        drop_level(c, a[i].e, a[i].k);
    free(a);
    return i > 0;
}

void tp_tin_cache_prune(tp_tin_cache* c, unsigned max_age_frames, size_t max_bytes)
{
    assert(c);
    prune_age(c, max_age_frames);
    if (max_bytes && c->bytes > max_bytes && drop_oldest(c, max_bytes))
        prune_age(c, 0);
}

void tp_tin_cache_stats(const tp_tin_cache* c, size_t* bytes, size_t* levels, size_t* builds)
{
    assert(c);
    if (bytes)
        *bytes = c->bytes;
    if (levels)
        *levels = c->levels;
    if (builds)
        *builds = c->builds;
}

double tp_tin_cache_build_ms(const tp_tin_cache* c)
{
    assert(c);
    return c->build_ms;
}
