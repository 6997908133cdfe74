/* store_mesh.c - nodes, leaf samples and the merged mesh of a store export (see store_mesh.h). */
#include "store_mesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- nodes ---- */

int tp_res_load(residency* r, int64_t node)
{
    if (r->block[node])
        return 1;
    if (r->count == r->cap) {
        size_t cap = r->cap ? 2 * r->cap : 1024;
        int64_t* p = realloc(r->ids, cap * sizeof *p);
        if (!p)
            return tp_error_set(&r->err, TP_ERR_OUT_OF_MEMORY, "out of memory"), 0;
        r->ids = p;
        r->cap = cap;
    }
    uint16_t* b = malloc(r->block_samples * sizeof *b);
    if (!b)
        return tp_error_set(&r->err, TP_ERR_OUT_OF_MEMORY, "out of memory"), 0;
    if (tp_store_read_node(r->sc->store, node, b, r->block_samples, &r->err) != TP_OK) {
        free(b);
        return 0;
    }
    r->block[node] = b;
    r->ids[r->count++] = node;
    tp_tree_attach(r->sc->tree, node, b);
    r->bytes += r->block_samples * sizeof *b;
    r->peak_bytes = r->bytes > r->peak_bytes ? r->bytes : r->peak_bytes;
    return 1;
}

void tp_res_release_except(residency* r, const uint8_t* keep)
{
    size_t w = 0;
    for (size_t i = 0; i < r->count; i++) {
        int64_t id = r->ids[i];
        if (keep && keep[id]) {
            r->ids[w++] = id;
            continue;
        }
        tp_tree_detach(r->sc->tree, id);
        free(r->block[id]);
        r->block[id] = NULL;
        r->bytes -= r->block_samples * sizeof(uint16_t);
    }
    r->count = w;
}

/* ---- leaf samples ---- */

double tp_leaf_sample(leaf_cache* lc, int x, int y)
{
    return tp_leaf_sample_filled(lc, x, y, NULL);
}

double tp_leaf_sample_filled(leaf_cache* lc, int x, int y, int* filled)
{
    if (filled)
        *filled = 0;
    const tp_tree_geometry* g = lc->g;
    int n = g->n, c = x >> n, r = y >> n;
    c = c < g->cols ? c : g->cols - 1;
    r = r < g->rows ? r : g->rows - 1;
    int64_t leaf = tp_tree_node_id(g, 0, c, r);
    const uint16_t* q = lc->res->block[leaf];
    if (!q) {
        size_t s = (size_t)leaf % LEAF_CACHE_SLOTS;
        if (lc->key[s] != leaf) {
            if (!lc->slot[s] &&
                !(lc->slot[s] = malloc(lc->res->block_samples * sizeof(uint16_t)))) {
                lc->failed = 1;
                tp_error_set(&lc->res->err, TP_ERR_OUT_OF_MEMORY, "out of memory");
                return NAN;
            }
            lc->key[s] = -1;
            if (tp_store_read_node(lc->res->sc->store, leaf, lc->slot[s], lc->res->block_samples,
                                   &lc->res->err) != TP_OK) {
                lc->failed = 1;
                return NAN;
            }
            lc->key[s] = leaf;
            lc->reads++;
        }
        q = lc->slot[s];
    }
    return tp_leaf_block_sample(q, &lc->metas[leaf], n, lc->step_m, x - (c << n), y - (r << n),
                                filled);
}

double tp_leaf_block_sample(const uint16_t* q, const tp_node_meta* meta, int n, double step_m,
                            int i, int j, int* filled)
{
    int v = (1 << n) + 1;
    size_t k = (size_t)j * v + (size_t)i;
    uint16_t st = q[k];
    if (filled) {
        *filled = 0;
        if (meta->flags & TP_NODE_HAS_FILLED) {
            const uint16_t* bits = q + (size_t)v * v + tp_node_mask_words(n);
            *filled = bits[k / 16] >> (k % 16) & 1;
        }
    }
    return st == TP_TREE_NO_HEIGHT ? NAN : ((double)st + meta->qmin) * step_m;
}

/* ---- the mesh ---- */

int tp_array_grow(void** p, size_t* cap, size_t need, size_t size)
{
    if (need <= *cap)
        return 1;
    size_t c = *cap ? *cap : 4096;
    while (c < need)
        c *= 2;
    void* q = realloc(*p, c * size);
    if (!q)
        return 0;
    *p = q;
    *cap = c;
    return 1;
}

static uint64_t hash64(uint64_t k)
{
    k ^= k >> 33;
    k *= 0xff51afd7ed558ccdULL;
    k ^= k >> 33;
    return k;
}

static int rehash(mesh_build* m, size_t cap)
{
    uint64_t* key = calloc(cap, sizeof *key);
    uint64_t* val = malloc(cap * sizeof *val);
    if (!key || !val) {
        free(key);
        free(val);
        return 0;
    }
    for (size_t i = 0; i < m->hcap; i++)
        if (m->key[i]) {
            size_t h = hash64(m->key[i]) & (cap - 1);
            while (key[h])
                h = (h + 1) & (cap - 1);
            key[h] = m->key[i];
            val[h] = m->val[i];
        }
    free(m->key);
    free(m->val);
    m->key = key;
    m->val = val;
    m->hcap = cap;
    return 1;
}

uint64_t tp_mesh_point(mesh_build* m, int32_t x, int32_t y, double z, int filled)
{
    if (2 * (m->points + 1) > m->hcap && !rehash(m, m->hcap ? 2 * m->hcap : 1 << 16))
        return UINT64_MAX;
    uint64_t k = (((uint64_t)(uint32_t)x << 32) | (uint32_t)y) + 1;
    size_t h = hash64(k) & (m->hcap - 1);
    while (m->key[h]) {
        if (m->key[h] == k)
            return m->val[h];
        h = (h + 1) & (m->hcap - 1);
    }
    if (!tp_array_grow((void**)&m->px, &m->cap_x, m->points + 1, sizeof *m->px) ||
        !tp_array_grow((void**)&m->py, &m->cap_y, m->points + 1, sizeof *m->py) ||
        !tp_array_grow((void**)&m->pz, &m->cap_z, m->points + 1, sizeof *m->pz) ||
        !tp_array_grow((void**)&m->pf, &m->cap_f, m->points + 1, sizeof *m->pf))
        return UINT64_MAX;
    m->key[h] = k;
    m->val[h] = m->points;
    m->px[m->points] = x;
    m->py[m->points] = y;
    m->pz[m->points] = z;
    m->pf[m->points] = (uint8_t)filled;
    return m->points++;
}

int tp_mesh_add_triangle(mesh_build* m, const uint64_t p[3], int32_t patch, uint8_t lod, double e)
{
    if (!tp_array_grow((void**)&m->tri, &m->cap_tri, 3 * (m->tris + 1), sizeof *m->tri) ||
        !tp_array_grow((void**)&m->patch, &m->cap_patch, m->tris + 1, sizeof *m->patch) ||
        !tp_array_grow((void**)&m->lod, &m->cap_lod, m->tris + 1, sizeof *m->lod) ||
        !tp_array_grow((void**)&m->err, &m->cap_err, m->tris + 1, sizeof *m->err))
        return 0;
    for (int c = 0; c < 3; c++)
        m->tri[3 * m->tris + c] = p[c];
    m->patch[m->tris] = patch;
    m->lod[m->tris] = lod;
    m->err[m->tris] = e;
    m->tris++;
    return 1;
}

void tp_mesh_build_free(mesh_build* m)
{
    free(m->key);
    free(m->val);
    free(m->px);
    free(m->py);
    free(m->pz);
    free(m->pf);
    free(m->tri);
    free(m->patch);
    free(m->lod);
    free(m->err);
    memset(m, 0, sizeof *m);
}
