/* stitch_add_draw.c - the added-vertex sets of `--stitch add` (see stitch_add_draw.h). */
#include "stitch_add_draw.h"

#include <assert.h>
#include <stdlib.h>
#include <string.h>

struct tp__stitch_add {
    int n;
    size_t key_count;          /* (n+1)^5 */
    tp__stitch_add_set** sets; /* by key, made on first use */
    uint32_t* remap;           /* (2^n+1)^2, UINT32_MAX between uses */
};

tp__stitch_add* tp__stitch_add_create(int n)
{
    assert(n >= 0 && n <= TP_MAX_N);
    tp__stitch_add* s = calloc(1, sizeof *s);
    if (!s)
        return NULL;
    s->n = n;
    s->key_count = 1;
    for (int i = 0; i < 5; i++)
        s->key_count *= (size_t)(n + 1);
    size_t side = ((size_t)1 << n) + 1;
    s->sets = calloc(s->key_count, sizeof *s->sets);
    s->remap = malloc(side * side * sizeof *s->remap);
    if (!s->sets || !s->remap) {
        tp__stitch_add_destroy(s);
        return NULL;
    }
    memset(s->remap, 0xff, side * side * sizeof *s->remap);
    return s;
}

void tp__stitch_add_destroy(tp__stitch_add* s)
{
    if (!s)
        return;
    if (s->sets)
        for (size_t i = 0; i < s->key_count; i++)
            if (s->sets[i]) {
                free(s->sets[i]->samples);
                free(s->sets[i]->triangles);
                free(s->sets[i]);
            }
    free(s->sets);
    free(s->remap);
    free(s);
}

int tp__stitch_add_needed(int k, const int8_t nb[4])
{
    for (int i = 0; i < 4; i++)
        if (nb[i] > k)
            return 1;
    return 0;
}

static tp__stitch_add_set* make_set(tp__stitch_add* s, int k, const int nb[4])
{
    int n = s->n;
    size_t side = ((size_t)1 << n) + 1;
    tp__stitch_add_set* set = calloc(1, sizeof *set);
    if (!set)
        return NULL;
    set->triangle_count = tp_patch_triangles_add(n, k, nb, NULL, 0);
    set->triangles = malloc(3 * set->triangle_count * sizeof *set->triangles);
    if (!set->triangles) {
        free(set);
        return NULL;
    }
    tp_patch_triangles_add(n, k, nb, set->triangles, set->triangle_count);
    /* the samples used, in lattice order */
    size_t used = 0;
    for (size_t i = 0; i < 3 * set->triangle_count; i++)
        if (s->remap[set->triangles[i]] == UINT32_MAX) {
            s->remap[set->triangles[i]] = 0;
            used++;
        }
    set->samples = malloc((used ? used : 1) * sizeof *set->samples);
    if (!set->samples) {
        for (size_t i = 0; i < 3 * set->triangle_count; i++)
            s->remap[set->triangles[i]] = UINT32_MAX;
        free(set->triangles);
        free(set);
        return NULL;
    }
    for (size_t i = 0; i < side * side; i++)
        if (s->remap[i] == 0) {
            s->remap[i] = (uint32_t)set->vertex_count;
            set->samples[set->vertex_count++] = (uint32_t)i;
        }
    for (size_t i = 0; i < 3 * set->triangle_count; i++)
        set->triangles[i] = s->remap[set->triangles[i]];
    for (size_t i = 0; i < set->vertex_count; i++)
        s->remap[set->samples[i]] = UINT32_MAX;
    set->finest = k;
    for (int i = 0; i < 4; i++)
        if (nb[i] > set->finest)
            set->finest = nb[i] > n ? n : nb[i];
    /* the smallest pool level whose slot (2^L+1)^2 and region (2 * 4^L triangles) hold it; the
     * level-finest lattice holds every sample, and its grid's triangles outnumber these */
    int L = 0;
    while (L < n && (((size_t)1 << L) + 1) * (((size_t)1 << L) + 1) < set->vertex_count)
        L++;
    while (L < n && 2 * ((size_t)1 << (2 * L)) < set->triangle_count)
        L++;
    assert(L <= set->finest);
    set->level = L;
    return set;
}

const tp__stitch_add_set* tp__stitch_add_get(tp__stitch_add* s, int k, const int8_t nb[4])
{
    int n = s->n, levels[4];
    size_t key = (size_t)k;
    for (int i = 0; i < 4; i++) {
        int d = nb[i] > k ? (nb[i] > n ? n : nb[i]) - k : 0;
        levels[i] = d ? k + d : TP_NO_NEIGHBOR;
        key = key * (size_t)(n + 1) + (size_t)d;
    }
    if (!s->sets[key])
        s->sets[key] = make_set(s, k, levels);
    return s->sets[key];
}

size_t tp__stitch_add_cpu_bytes(const tp__stitch_add* s)
{
    size_t side = ((size_t)1 << s->n) + 1;
    size_t b = sizeof *s + s->key_count * sizeof *s->sets + side * side * sizeof *s->remap;
    for (size_t i = 0; i < s->key_count; i++)
        if (s->sets[i])
            b += sizeof *s->sets[i] + s->sets[i]->vertex_count * sizeof(uint32_t) +
                 3 * s->sets[i]->triangle_count * sizeof(uint32_t);
    return b;
}

/* Compacts the level-finest lattice v (set->finest) to the set's samples, in place. */
static void compact(const tp__stitch_add* s, const tp__stitch_add_set* set, tp_vertex* v)
{
    int n = s->n, m = set->finest, shift = n - m;
    size_t side = ((size_t)1 << n) + 1, mside = ((size_t)1 << m) + 1;
    /* samples ascend in lattice order, so each one's level-m index is >= its compact index:
     * compacting forward in place never overwrites a vertex still to be read */
    for (size_t j = 0; j < set->vertex_count; j++) {
        size_t row = set->samples[j] / side, col = set->samples[j] % side;
        size_t at = (row >> shift) * mside + (col >> shift);
        assert(at >= j);
        v[j] = v[at];
    }
}

void tp__stitch_add_fill(const tp__stitch_add* s, const tp__stitch_add_set* set,
                         const tp_terrain* t, int patch, tp_vertex* v, float (*normals)[3],
                         uint8_t* filled)
{
    size_t mside = ((size_t)1 << set->finest) + 1;
    tp_patch_vertices(t, patch, set->finest, NULL, v, mside * mside);
    compact(s, set, v);
    for (size_t j = 0; j < set->vertex_count; j++) {
        tp_terrain_normal(t, v[j].x, v[j].y, normals[j]);
        filled[j] = tp_terrain_sample_class(t, v[j].x, v[j].y) == TP_SAMPLE_FILLED;
    }
}

void tp__stitch_add_fill_node(const tp__stitch_add* s, const tp__stitch_add_set* set,
                              const tp_tree* tree, const tp_cut* cut, size_t i, tp_vertex* v,
                              float (*normals)[3], uint8_t* filled)
{
    size_t mside = ((size_t)1 << set->finest) + 1;
    size_t count = 0;
    const tp_cut_node* node = &tp_cut_nodes(cut, &count)[i];
    tp_cut_vertices_at_level(cut, i, set->finest, v, mside * mside);
    compact(s, set, v);
    for (size_t j = 0; j < set->vertex_count; j++)
        filled[j] = v[j].cls == TP_SAMPLE_FILLED;
    tp_tree_node_normals(tree, node->node, v, set->vertex_count, normals);
}
