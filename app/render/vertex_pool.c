/* vertex_pool.c - the renderer's vertex slots and triangle-list regions (see vertex_pool.h). */
#include "vertex_pool.h"
#include "prefetch.h"

#include "tp_core.h"

#include <epoxy/gl.h>

#include <assert.h>
#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* A handle: slot index * POOL_LEVELS + level. */
#define POOL_LEVELS 16

/* A full pool or region buffer grows by a quarter (at least one), not by doubling: the GPU
 * memory it holds is at most 1.25 times the most a frame drew (on a software rasteriser that
 * memory is the process's, docs/PERFORMANCE.md "The software rasteriser's memory"). */
static int grown(int n)
{
    return n + (n / 4 > 1 ? n / 4 : 1);
}

/* The vertex pool of one level k: slots of (2^k+1)^2 vertices in one buffer; and the
 * triangle-list regions of its incomplete items, 6 * 4^k indices each (a level-k item draws at
 * most 2 * 4^k triangles) in one index buffer, 16-bit where a slot's vertices can be so
 * numbered ((2^k+1)^2 <= 65536, k <= 7), else 32-bit. */
typedef struct pool {
    GLuint vbo;
    size_t verts;      /* (2^k+1)^2 */
    int slots;         /* capacity */
    int budget_slots;  /* grows past this only for a frame that needs more; 0: none */
    tp_pool_slot* slot;
    int* free_slot;    /* slots holding no item (a stack) */
    int free_count;
    GLuint ibo;        /* the regions; 0 until one is needed */
    size_t stride;     /* indices per region: 6 * 4^k */
    size_t isize;      /* bytes an index: 2 or 4 */
    int regions, regions_free;
    int* region_free;  /* regions holding no list (a stack) */
    GLsizei* region_count;
} pool;

struct tp_vertex_pool {
    int n;
    size_t vertex_bytes, max_pool_bytes;
    pool pool[TP_MAX_LEVELS];
    int* map;          /* open addressing, key -> handle (-1 empty); map_cap = 2^k >= 2 * items */
    size_t map_cap, map_used;
    uint64_t frame;
    uint16_t* tmp16;   /* a region's indices narrowed to 16 bits before they are written */
    size_t tmp16_count;
};

static size_t hash_key(int64_t key, size_t cap)
{
    uint64_t h = (uint64_t)key * 0x9E3779B97F4A7C15ull;
    return (size_t)(h >> 17) & (cap - 1);
}

static tp_pool_slot* map_slot(const tp_vertex_pool* p, int v)
{
    return &p->pool[v % POOL_LEVELS].slot[v / POOL_LEVELS];
}

/* The handle of key, or -1. */
static int map_find(const tp_vertex_pool* p, int64_t key)
{
    for (size_t i = hash_key(key, p->map_cap);; i = (i + 1) & (p->map_cap - 1)) {
        int v = p->map[i];
        if (v < 0)
            return -1;
        if (map_slot(p, v)->key == key)
            return v;
    }
}

static void map_insert(tp_vertex_pool* p, int64_t key, int v)
{
    size_t i = hash_key(key, p->map_cap);
    while (p->map[i] >= 0)
        i = (i + 1) & (p->map_cap - 1);
    p->map[i] = v;
    p->map_used++;
}

void tp_vertex_pool_prefetch(const tp_vertex_pool* p, int64_t key, int stage)
{
    if (!p->map_cap)
        return;
    const int* e = &p->map[hash_key(key, p->map_cap)];
    if (stage == 0)
        TP_PREFETCH(e);
    else if (*e >= 0)
        TP_PREFETCH(map_slot(p, *e));
}

/* Removes key (present) with backward-shift deletion: no tombstones. */
static void map_remove(tp_vertex_pool* p, int64_t key)
{
    size_t mask = p->map_cap - 1, i = hash_key(key, p->map_cap);
    while (map_slot(p, p->map[i])->key != key)
        i = (i + 1) & mask;
    p->map_used--;
    for (size_t j = (i + 1) & mask; p->map[j] >= 0; j = (j + 1) & mask) {
        size_t home = hash_key(map_slot(p, p->map[j])->key, p->map_cap);
        /* move j into the hole at i when its home is not in (i, j] cyclically */
        if (((j - home) & mask) >= ((j - i) & mask)) {
            p->map[i] = p->map[j];
            i = j;
        }
    }
    p->map[i] = -1;
}

/* Makes the map hold at least `items` keys at load <= 1/2 (rehashing what it holds). */
static int grow_map(tp_vertex_pool* p, size_t items)
{
    if (2 * items <= p->map_cap)
        return 1;
    size_t cap = p->map_cap ? p->map_cap : 16;
    while (cap < 2 * items)
        cap *= 2;
    int* map = malloc(cap * sizeof *map);
    if (!map)
        return 0;
    int* old = p->map;
    size_t old_cap = p->map_cap;
    p->map = map;
    p->map_cap = cap;
    p->map_used = 0;
    memset(map, 0xFF, cap * sizeof *map);
    for (size_t i = 0; i < old_cap; i++)
        if (old[i] >= 0)
            map_insert(p, map_slot(p, old[i])->key, old[i]);
    free(old);
    return 1;
}

/* Grows level k's pool to `slots` slots, keeping what it holds. */
static int grow_pool(tp_vertex_pool* vp, int k, int slots)
{
    pool* p = &vp->pool[k];
    /* Draws address a slot by its first vertex as a GLint base vertex; handles hold
     * slot * POOL_LEVELS. */
    if ((size_t)slots > (size_t)INT_MAX / p->verts || slots > INT_MAX / POOL_LEVELS)
        return 0;
    size_t max_slots = vp->max_pool_bytes / (p->verts * vp->vertex_bytes);
    if ((size_t)slots > max_slots)
        slots = (int)max_slots;
    if (slots <= p->slots)
        return 0;
    size_t bytes = (size_t)slots * p->verts * vp->vertex_bytes;
    tp_pool_slot* sl = realloc(p->slot, (size_t)slots * sizeof *sl);
    if (sl)
        p->slot = sl;
    int* fr = realloc(p->free_slot, (size_t)slots * sizeof *fr);
    if (fr)
        p->free_slot = fr;
    if (!sl || !fr)
        return 0;
    for (int i = slots - 1; i >= p->slots; i--) {
        p->slot[i].key = -1;
        p->slot[i].region = -1;
        p->slot[i].stamp = 0;
        p->free_slot[p->free_count++] = i;
    }
    GLuint vbo;
    glGenBuffers(1, &vbo);
    glBindBuffer(GL_COPY_WRITE_BUFFER, vbo);
    glBufferData(GL_COPY_WRITE_BUFFER, (GLsizeiptr)bytes, NULL, GL_DYNAMIC_DRAW);
    if (p->vbo) {
        glBindBuffer(GL_COPY_READ_BUFFER, p->vbo);
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0,
                            (GLsizeiptr)((size_t)p->slots * p->verts * vp->vertex_bytes));
        glDeleteBuffers(1, &p->vbo);
    }
    p->vbo = vbo;
    p->slots = slots;
    return 1;
}

/* A triangle-list region of pool p; its index buffer doubles when all are used. */
static int take_region(pool* p)
{
    if (p->regions_free > 0)
        return p->region_free[--p->regions_free];
    int old = p->regions, want = old ? grown(old) : 16;
    int* fr = realloc(p->region_free, (size_t)want * sizeof *fr);
    if (fr)
        p->region_free = fr;
    GLsizei* rc = realloc(p->region_count, (size_t)want * sizeof *rc);
    if (rc)
        p->region_count = rc;
    if (!fr || !rc)
        return -1;
    size_t stride_bytes = p->stride * p->isize;
    GLuint ibo;
    glGenBuffers(1, &ibo);
    glBindBuffer(GL_COPY_WRITE_BUFFER, ibo);
    glBufferData(GL_COPY_WRITE_BUFFER, (GLsizeiptr)((size_t)want * stride_bytes), NULL,
                 GL_DYNAMIC_DRAW);
    if (p->ibo) {
        glBindBuffer(GL_COPY_READ_BUFFER, p->ibo);
        glCopyBufferSubData(GL_COPY_READ_BUFFER, GL_COPY_WRITE_BUFFER, 0, 0,
                            (GLsizeiptr)((size_t)old * stride_bytes));
        glDeleteBuffers(1, &p->ibo);
    }
    p->ibo = ibo;
    for (int i = want - 1; i > old; i--)
        p->region_free[p->regions_free++] = i;
    for (int i = old; i < want; i++)
        p->region_count[i] = 0;
    p->regions = want;
    return old;
}

tp_vertex_pool* tp_vertex_pool_create(int n, size_t vertex_bytes, size_t budget_bytes,
                                      size_t max_pool_bytes, size_t initial_bytes, tp_error* err)
{
    assert(n >= 0 && n < TP_MAX_LEVELS && n < POOL_LEVELS);
    assert(vertex_bytes > 0);
    tp_vertex_pool* p = calloc(1, sizeof *p);
    if (!p) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    p->n = n;
    p->vertex_bytes = vertex_bytes;
    p->max_pool_bytes = max_pool_bytes;
    /* Each level's pool starts small (a view draws a few levels; the pool doubles when a frame
     * needs more) and its budget is an even share. */
    for (int k = 0; k <= n; k++) {
        pool* q = &p->pool[k];
        size_t side = ((size_t)1 << k) + 1;
        q->verts = side * side;
        q->stride = 6 * ((size_t)1 << (2 * k));
        q->isize = q->verts <= 65536 ? 2 : 4;
        if (q->isize == 2)
            p->tmp16_count = q->stride;
        size_t slot_bytes = q->verts * vertex_bytes;
        if (budget_bytes > 0) {
            size_t b = budget_bytes / (size_t)(n + 1) / slot_bytes;
            q->budget_slots = b < 1 ? 1 : b > (size_t)INT_MAX / 2 ? INT_MAX / 2 : (int)b;
        }
        size_t b = initial_bytes / slot_bytes;
        int first = b < 1 ? 1 : b > 4096 ? 4096 : (int)b;
        if (q->budget_slots > 0 && q->budget_slots < first)
            first = q->budget_slots;
        if (!grow_pool(p, k, first)) {
            tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
            tp_vertex_pool_destroy(p);
            return NULL;
        }
    }
    p->tmp16 = malloc((p->tmp16_count ? p->tmp16_count : 1) * sizeof *p->tmp16);
    if (!p->tmp16 || !grow_map(p, 64)) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        tp_vertex_pool_destroy(p);
        return NULL;
    }
    return p;
}

void tp_vertex_pool_destroy(tp_vertex_pool* p)
{
    if (!p)
        return;
    for (int k = 0; k < TP_MAX_LEVELS; k++) {
        if (p->pool[k].vbo)
            glDeleteBuffers(1, &p->pool[k].vbo);
        if (p->pool[k].ibo)
            glDeleteBuffers(1, &p->pool[k].ibo);
        free(p->pool[k].slot);
        free(p->pool[k].free_slot);
        free(p->pool[k].region_free);
        free(p->pool[k].region_count);
    }
    free(p->map);
    free(p->tmp16);
    free(p);
}

void tp_vertex_pool_begin_frame(tp_vertex_pool* p)
{
    p->frame++;
}

/* Empties the slot of handle v: the key leaves the map, a triangle-list region goes back. */
static void release_slot(tp_vertex_pool* vp, int v)
{
    tp_pool_slot* sl = map_slot(vp, v);
    pool* p = &vp->pool[v % POOL_LEVELS];
    map_remove(vp, sl->key);
    sl->key = -1;
    sl->stamp = 0;
    tp_vertex_pool_drop_triangles(vp, v);
    p->free_slot[p->free_count++] = v / POOL_LEVELS;
}

int tp_vertex_pool_take(tp_vertex_pool* vp, int64_t key, int k, int* fresh)
{
    assert(k >= 0 && k <= vp->n && key >= 0);
    int v = map_find(vp, key);
    *fresh = 0;
    if (v >= 0) {
        if (v % POOL_LEVELS == k) {
            map_slot(vp, v)->stamp = vp->frame;
            return v;
        }
        release_slot(vp, v);
    }
    pool* p = &vp->pool[k];
    int best = -1;
    while (p->free_count > 0 && best < 0) {
        int i = p->free_slot[--p->free_count];
        if (p->slot[i].key < 0)
            best = i;
    }
    for (int i = 0; best < 0 && i < p->slots; i++)
        if (p->slot[i].stamp != vp->frame)
            best = i;
    if (best >= 0 && p->slot[best].key >= 0) /* the least recently used one */
        for (int i = best + 1; i < p->slots; i++)
            if (p->slot[i].stamp != vp->frame && p->slot[i].stamp < p->slot[best].stamp)
                best = i;
    if (best < 0) {
        int old = p->slots, want = grown(old);
        if (p->budget_slots > 0 && old < p->budget_slots && want > p->budget_slots)
            want = p->budget_slots; /* up to the budget, no further unless a frame needs it */
        if (!grow_pool(vp, k, want))
            return -1;
        best = p->free_slot[--p->free_count];
    }
    if (p->slot[best].key >= 0)
        release_slot(vp, best * POOL_LEVELS + k);
    /* release_slot pushed it back: take it off again */
    for (int i = p->free_count - 1; i >= 0; i--)
        if (p->free_slot[i] == best) {
            p->free_slot[i] = p->free_slot[--p->free_count];
            break;
        }
    if (!grow_map(vp, vp->map_used + 1))
        return -1;
    tp_pool_slot* sl = &p->slot[best];
    sl->key = key;
    sl->stamp = vp->frame;
    v = best * POOL_LEVELS + k;
    map_insert(vp, key, v);
    *fresh = 1;
    return v;
}

tp_pool_slot* tp_vertex_pool_slot(tp_vertex_pool* p, int handle)
{
    assert(handle >= 0);
    return map_slot(p, handle);
}

int tp_vertex_pool_level(int handle)
{
    assert(handle >= 0);
    return handle % POOL_LEVELS;
}

void tp_vertex_pool_write(tp_vertex_pool* vp, int handle, const void* vertices, size_t count)
{
    const pool* p = &vp->pool[handle % POOL_LEVELS];
    assert(count <= p->verts);
    glBindBuffer(GL_ARRAY_BUFFER, p->vbo);
    glBufferSubData(GL_ARRAY_BUFFER,
                    (GLintptr)((size_t)(handle / POOL_LEVELS) * p->verts * vp->vertex_bytes),
                    (GLsizeiptr)(count * vp->vertex_bytes), vertices);
}

size_t tp_vertex_pool_region_indices(const tp_vertex_pool* p, int k)
{
    assert(k >= 0 && k <= p->n);
    return p->pool[k].stride;
}

int tp_vertex_pool_write_triangles(tp_vertex_pool* vp, int handle, const uint32_t* indices,
                                   size_t index_count)
{
    tp_pool_slot* sl = map_slot(vp, handle);
    pool* p = &vp->pool[handle % POOL_LEVELS];
    assert(index_count <= p->stride);
    if (sl->region < 0)
        sl->region = take_region(p);
    if (sl->region < 0)
        return 0;
    p->region_count[sl->region] = (GLsizei)index_count;
    const void* data = indices;
    if (p->isize == 2) { /* every index < (2^k+1)^2 <= 65536 */
        for (size_t i = 0; i < index_count; i++) {
            assert(indices[i] < p->verts);
            vp->tmp16[i] = (uint16_t)indices[i];
        }
        data = vp->tmp16;
    }
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, p->ibo);
    glBufferSubData(GL_ELEMENT_ARRAY_BUFFER,
                    (GLintptr)((size_t)sl->region * p->stride * p->isize),
                    (GLsizeiptr)(index_count * p->isize), data);
    return 1;
}

void tp_vertex_pool_drop_triangles(tp_vertex_pool* vp, int handle)
{
    tp_pool_slot* sl = map_slot(vp, handle);
    pool* p = &vp->pool[handle % POOL_LEVELS];
    if (sl->region < 0)
        return;
    p->region_free[p->regions_free++] = sl->region;
    sl->region = -1;
}

unsigned int tp_vertex_pool_vertex_buffer(const tp_vertex_pool* p, int k)
{
    assert(k >= 0 && k <= p->n);
    return p->pool[k].vbo;
}

int32_t tp_vertex_pool_base_vertex(const tp_vertex_pool* p, int handle)
{
    /* fits: grow_pool keeps slots * verts <= INT_MAX */
    return (int32_t)((size_t)(handle / POOL_LEVELS) * p->pool[handle % POOL_LEVELS].verts);
}

unsigned int tp_vertex_pool_index_buffer(const tp_vertex_pool* p, int k)
{
    assert(k >= 0 && k <= p->n);
    return p->pool[k].ibo;
}

unsigned int tp_vertex_pool_index_type(const tp_vertex_pool* p, int k)
{
    assert(k >= 0 && k <= p->n);
    return p->pool[k].isize == 2 ? GL_UNSIGNED_SHORT : GL_UNSIGNED_INT;
}

size_t tp_vertex_pool_triangles(const tp_vertex_pool* p, int handle, size_t* offset_bytes)
{
    const tp_pool_slot* sl = map_slot(p, handle);
    const pool* q = &p->pool[handle % POOL_LEVELS];
    *offset_bytes = 0;
    if (sl->region < 0)
        return 0;
    *offset_bytes = (size_t)sl->region * q->stride * q->isize;
    return (size_t)q->region_count[sl->region];
}

size_t tp_vertex_pool_gpu_bytes(const tp_vertex_pool* p)
{
    size_t bytes = 0;
    for (int k = 0; k <= p->n; k++) {
        const pool* q = &p->pool[k];
        bytes += (size_t)q->slots * q->verts * p->vertex_bytes +
                 (size_t)q->regions * q->stride * q->isize;
    }
    return bytes;
}

size_t tp_vertex_pool_index_bytes(const tp_vertex_pool* p)
{
    size_t bytes = 0;
    for (int k = 0; k <= p->n; k++)
        bytes += (size_t)p->pool[k].regions * p->pool[k].stride * p->pool[k].isize;
    return bytes;
}
