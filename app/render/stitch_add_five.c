/* stitch_add_five.c - `--stitch add` as five regions a patch (see stitch_add_five.h). */
#include "stitch_add_five.h"

#include <epoxy/gl.h>

#include <assert.h>
#include <stdlib.h>
#include <string.h>

#define NOT_MADE UINT32_MAX
#define INTERIOR 4 /* region code after the four tp_side values */

typedef struct layout_entry {
    tp__five_layout pub;
    uint32_t (*sets)[2]; /* by (side, own delta, other delta): {first, count}; NOT_MADE count */
} layout_entry;

struct tp__stitch_five {
    int n;
    layout_entry** layouts;                 /* (n+1)^2, by k * (n+1) + D, made on first use */
    uint32_t interior[TP_MAX_N + 1][16][2]; /* per level and adding sides: {first, count} */
    uint32_t* list;                         /* every set made, one after the other */
    size_t list_count, list_cap;
    uint32_t* tri; /* scratch: a configuration's tp_patch_triangles_add */
    size_t tri_cap;
    tp_vertex* lattice; /* scratch: (2^n+1)^2, for tp__stitch_five_fill */
    GLuint ibo;
    size_t ibo_count; /* indices in ibo */
};

tp__stitch_five* tp__stitch_five_create(int n)
{
    assert(n >= 0 && n <= TP_MAX_N);
    tp__stitch_five* f = calloc(1, sizeof *f);
    if (!f)
        return NULL;
    f->n = n;
    size_t side = ((size_t)1 << n) + 1;
    f->layouts = calloc((size_t)(n + 1) * (size_t)(n + 1), sizeof *f->layouts);
    f->lattice = malloc(side * side * sizeof *f->lattice);
    if (!f->layouts || !f->lattice) {
        tp__stitch_five_destroy(f);
        return NULL;
    }
    for (int k = 0; k <= n; k++)
        for (int m = 0; m < 16; m++)
            f->interior[k][m][1] = NOT_MADE;
    return f;
}

void tp__stitch_five_destroy(tp__stitch_five* f)
{
    if (!f)
        return;
    if (f->layouts)
        for (int i = 0; i < (f->n + 1) * (f->n + 1); i++)
            if (f->layouts[i]) {
                free(f->layouts[i]->pub.samples);
                free(f->layouts[i]->sets);
                free(f->layouts[i]);
            }
    if (f->ibo)
        glDeleteBuffers(1, &f->ibo);
    free(f->layouts);
    free(f->list);
    free(f->tri);
    free(f->lattice);
    free(f);
}

/* The most levels a neighbour is finer than k (0: none), and each side's. */
static int deltas(int n, int k, const int8_t nb[4], int d[4])
{
    int D = 0;
    for (int s = 0; s < 4; s++) {
        d[s] = nb[s] > k ? (nb[s] > n ? n : nb[s]) - k : 0;
        if (d[s] > D)
            D = d[s];
    }
    return D;
}

/* Vertex index in layout (k, D) of sample (x, y) of the 2^n lattice: a level-k grid sample or
 * a border sample at most D levels finer. */
static uint32_t layout_index(int n, int k, int D, int x, int y)
{
    const int full = 1 << n, step = 1 << (n - k), cells = 1 << k;
    if (x % step == 0 && y % step == 0)
        return (uint32_t)((y / step) * (cells + 1) + x / step);
    int side, pos;
    if (y == 0)
        side = TP_SIDE_TOP, pos = x;
    else if (x == full)
        side = TP_SIDE_RIGHT, pos = y;
    else if (y == full)
        side = TP_SIDE_BOTTOM, pos = x;
    else
        side = TP_SIDE_LEFT, pos = y;
    assert(side != TP_SIDE_LEFT || x == 0);
    int z = 0; /* trailing zero bits of pos: it first appears at level n - z */
    while (!(pos >> z & 1))
        z++;
    int j = n - z - k; /* 1 .. D */
    assert(j >= 1 && j <= D);
    size_t block = (size_t)cells * (((size_t)1 << D) - 1);
    return (uint32_t)((size_t)(cells + 1) * (cells + 1) + (size_t)side * block +
                      (size_t)cells * (((size_t)1 << (j - 1)) - 1) + (size_t)(pos >> (z + 1)));
}

static layout_entry* make_layout(int n, int k, int D)
{
    layout_entry* e = calloc(1, sizeof *e);
    if (!e)
        return NULL;
    const int full = 1 << n, step = 1 << (n - k), cells = 1 << k;
    size_t grid = (size_t)(cells + 1) * (cells + 1), block = (size_t)cells * ((1u << D) - 1);
    e->pub.k = k;
    e->pub.D = D;
    e->pub.vertex_count = grid + 4 * block;
    e->pub.samples = malloc(e->pub.vertex_count * sizeof *e->pub.samples);
    e->sets = malloc((size_t)4 * (D + 1) * (D + 1) * sizeof *e->sets);
    if (!e->pub.samples || !e->sets) {
        free(e->pub.samples);
        free(e->sets);
        free(e);
        return NULL;
    }
    for (size_t i = 0; i < (size_t)4 * (D + 1) * (D + 1); i++)
        e->sets[i][0] = 0, e->sets[i][1] = NOT_MADE;
    const uint32_t side = (uint32_t)full + 1;
    for (int y = 0; y <= full; y += step)
        for (int x = 0; x <= full; x += step)
            e->pub.samples[layout_index(n, k, D, x, y)] = (uint32_t)y * side + (uint32_t)x;
    const int fine = step >> D; /* the finest border spacing */
    for (int p = fine; p < full; p += fine) {
        if (p % step == 0)
            continue;
        e->pub.samples[layout_index(n, k, D, p, 0)] = (uint32_t)p;
        e->pub.samples[layout_index(n, k, D, full, p)] = (uint32_t)p * side + (uint32_t)full;
        e->pub.samples[layout_index(n, k, D, p, full)] = (uint32_t)full * side + (uint32_t)p;
        e->pub.samples[layout_index(n, k, D, 0, p)] = (uint32_t)p * side;
    }
    int L = 0;
    while ((((size_t)1 << L) + 1) * (((size_t)1 << L) + 1) < e->pub.vertex_count)
        L++;
    assert(L <= k + D);
    e->pub.level = L;
    return e;
}

const tp__five_layout* tp__stitch_five_layout(tp__stitch_five* f, int k, const int8_t nb[4])
{
    int d[4], D = deltas(f->n, k, nb, d);
    assert(D >= 1);
    layout_entry** e = &f->layouts[k * (f->n + 1) + D];
    if (!*e)
        *e = make_layout(f->n, k, D);
    return *e ? &(*e)->pub : NULL;
}

/* The region of triangle t (sample indices of the 2^n lattice) of a level-k patch whose sides
 * in mask (bit s: side s) take vertices: the tp_side whose region holds its grid triangle, or
 * INTERIOR. A side that takes nothing has no region (its triangles are the interior's); the
 * corner triangle of cell (0, 0) (TOP and LEFT edges) is TOP's if TOP takes vertices, else
 * LEFT's if it does; the last cell's (BOTTOM and RIGHT) BOTTOM's, else RIGHT's. */
static int region(int n, int k, unsigned mask, const uint32_t* t)
{
    const int side = (1 << n) + 1, step = 1 << (n - k), cells = 1 << k;
    int sx = 0, sy = 0; /* 3 * the centroid, strictly inside one grid triangle */
    for (int i = 0; i < 3; i++)
        sx += (int)(t[i] % (uint32_t)side), sy += (int)(t[i] / (uint32_t)side);
    int c = sx / (3 * step), r = sy / (3 * step);
    int upper_left = (sx - 3 * step * c) + (sy - 3 * step * r) < 3 * step;
    int s = upper_left ? (r == 0   ? TP_SIDE_TOP
                          : c == 0 ? TP_SIDE_LEFT
                                   : INTERIOR)
                       : (r == cells - 1   ? TP_SIDE_BOTTOM
                          : c == cells - 1 ? TP_SIDE_RIGHT
                                           : INTERIOR);
    if (s == TP_SIDE_TOP && c == 0 && !(mask >> TP_SIDE_TOP & 1))
        s = TP_SIDE_LEFT; /* the corner, TOP taking nothing */
    if (s == TP_SIDE_BOTTOM && c == cells - 1 && !(mask >> TP_SIDE_BOTTOM & 1))
        s = TP_SIDE_RIGHT;
    return s != INTERIOR && (mask >> s & 1) ? s : INTERIOR;
}

/* Appends the triangles of region `want` of tp_patch_triangles_add(n, k, levels), as indices
 * of layout (k, D), to the list; *at, *count: where. Returns 0 when out of memory. */
static int make_set(tp__stitch_five* f, int k, int D, const int levels[4], int want, uint32_t* at,
                    uint32_t* count)
{
    int n = f->n;
    unsigned mask = 0;
    for (int s = 0; s < 4; s++)
        mask |= (unsigned)(levels[s] > k) << s;
    size_t nt = tp_patch_triangles_add(n, k, levels, NULL, 0);
    if (nt > f->tri_cap) {
        uint32_t* t = realloc(f->tri, 3 * nt * sizeof *t);
        if (!t)
            return 0;
        f->tri = t;
        f->tri_cap = nt;
    }
    tp_patch_triangles_add(n, k, levels, f->tri, nt);
    if (f->list_count + 3 * nt > f->list_cap) {
        size_t cap = f->list_cap ? f->list_cap : 4096;
        while (cap < f->list_count + 3 * nt)
            cap *= 2;
        uint32_t* l = realloc(f->list, cap * sizeof *l);
        if (!l)
            return 0;
        f->list = l;
        f->list_cap = cap;
    }
    const uint32_t side = ((uint32_t)1 << n) + 1;
    *at = (uint32_t)f->list_count;
    for (size_t i = 0; i < nt; i++) {
        const uint32_t* t = f->tri + 3 * i;
        if (region(n, k, mask, t) != want)
            continue;
        for (int j = 0; j < 3; j++) /* the same vertices in the same order: same winding */
            f->list[f->list_count++] =
                want == INTERIOR ? layout_index(n, k, 1, (int)(t[j] % side), (int)(t[j] / side))
                                 : layout_index(n, k, D, (int)(t[j] % side), (int)(t[j] / side));
    }
    *count = (uint32_t)(f->list_count - *at);
    return 1;
}

int tp__stitch_five_draws(tp__stitch_five* f, int k, const int8_t nb[4], tp__five_draws* out)
{
    int n = f->n, d[4], D = deltas(n, k, nb, d);
    assert(D >= 1);
    layout_entry** le = &f->layouts[k * (n + 1) + D];
    if (!*le && !(*le = make_layout(n, k, D)))
        return 0;
    layout_entry* e = *le;
    unsigned mask = 0;
    for (int s = 0; s < 4; s++)
        mask |= (unsigned)(d[s] > 0) << s;
    uint32_t* sets[5];
    int count = 0;
    sets[count++] = f->interior[k][mask];
    if (sets[0][1] == NOT_MADE) { /* the grid triangles in no side's region: grid samples only;
                                     any finer level stands for a side's */
        int levels[4];
        for (int s = 0; s < 4; s++)
            levels[s] = mask >> s & 1 ? k + 1 : TP_NO_NEIGHBOR;
        if (!make_set(f, k, 1, levels, INTERIOR, &sets[0][0], &sets[0][1]))
            return 0;
    }
    for (int s = 0; s < 4; s++) {
        if (!d[s])
            continue;
        /* TOP holds cell (0, 0)'s corner and its set depends on LEFT's delta there, BOTTOM the
         * last cell's with RIGHT's; LEFT (RIGHT) holds that corner only when TOP (BOTTOM) takes
         * nothing: its set depends on whether it does (1 or 0) */
        int other = s == TP_SIDE_TOP      ? TP_SIDE_LEFT
                    : s == TP_SIDE_BOTTOM ? TP_SIDE_RIGHT
                    : s == TP_SIDE_LEFT   ? TP_SIDE_TOP
                                          : TP_SIDE_BOTTOM;
        int key = s == TP_SIDE_TOP || s == TP_SIDE_BOTTOM ? d[other] : d[other] == 0;
        uint32_t* set = e->sets[(s * (D + 1) + d[s]) * (D + 1) + key];
        if (set[1] == NOT_MADE) {
            int levels[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
            levels[s] = k + d[s];
            if (s == TP_SIDE_TOP || s == TP_SIDE_BOTTOM ? key > 0 : !key)
                levels[other] = k + (s == TP_SIDE_TOP || s == TP_SIDE_BOTTOM ? key : 1);
            if (!make_set(f, k, D, levels, s, &set[0], &set[1]))
                return 0;
        }
        sets[count++] = set;
    }
    memset(out, 0, sizeof *out);
    for (int i = 0; i < count; i++)
        if (sets[i][1] > 0) {
            out->first[out->count] = sets[i][0];
            out->index_count[out->count++] = sets[i][1];
            out->triangles += sets[i][1] / 3;
        }
    return 1;
}

const uint32_t* tp__stitch_five_indices(const tp__stitch_five* f, size_t* count)
{
    *count = f->list_count;
    return f->list;
}

size_t tp__stitch_five_cpu_bytes(const tp__stitch_five* f)
{
    size_t side = ((size_t)1 << f->n) + 1;
    size_t b = sizeof *f + (size_t)(f->n + 1) * (f->n + 1) * sizeof *f->layouts +
               f->list_cap * sizeof *f->list + 3 * f->tri_cap * sizeof *f->tri +
               side * side * sizeof *f->lattice;
    for (int i = 0; i < (f->n + 1) * (f->n + 1); i++)
        if (f->layouts[i]) {
            size_t D = (size_t)f->layouts[i]->pub.D;
            b += sizeof **f->layouts + f->layouts[i]->pub.vertex_count * sizeof(uint32_t) +
                 4 * (D + 1) * (D + 1) * sizeof *f->layouts[i]->sets;
        }
    return b;
}

void tp__stitch_five_fill(tp__stitch_five* f, const tp__five_layout* lay, const tp_terrain* t,
                          int patch, tp_vertex* v, float (*normals)[3], uint8_t* filled)
{
    int n = f->n, m = lay->k + lay->D, shift = n - m;
    size_t side = ((size_t)1 << n) + 1, mside = ((size_t)1 << m) + 1;
    tp_patch_vertices(t, patch, m, NULL, f->lattice, mside * mside);
    for (size_t j = 0; j < lay->vertex_count; j++) {
        size_t row = lay->samples[j] / side, col = lay->samples[j] % side;
        v[j] = f->lattice[(row >> shift) * mside + (col >> shift)];
        tp_terrain_normal(t, v[j].x, v[j].y, normals[j]);
        filled[j] = tp_terrain_sample_class(t, v[j].x, v[j].y) == TP_SAMPLE_FILLED;
    }
}

void tp__stitch_five_fill_node(tp__stitch_five* f, const tp__five_layout* lay,
                               const tp_tree* tree, const tp_cut* cut, size_t i, tp_vertex* v,
                               float (*normals)[3], uint8_t* filled)
{
    int n = f->n, m = lay->k + lay->D, shift = n - m;
    size_t side = ((size_t)1 << n) + 1, mside = ((size_t)1 << m) + 1, count = 0;
    const tp_cut_node* node = &tp_cut_nodes(cut, &count)[i];
    tp_cut_vertices_at_level(cut, i, m, f->lattice, mside * mside);
    for (size_t j = 0; j < lay->vertex_count; j++) {
        size_t row = lay->samples[j] / side, col = lay->samples[j] % side;
        v[j] = f->lattice[(row >> shift) * mside + (col >> shift)];
        filled[j] = v[j].cls == TP_SAMPLE_FILLED;
    }
    tp_tree_node_normals(tree, node->node, v, lay->vertex_count, normals);
}

unsigned int tp__stitch_five_gl_buffer(tp__stitch_five* f, size_t* bytes)
{
    if (!f->ibo)
        glGenBuffers(1, &f->ibo);
    glBindBuffer(GL_ELEMENT_ARRAY_BUFFER, f->ibo);
    if (f->ibo_count != f->list_count) {
        /* the whole list again (sets are made rarely: a few times while new configurations
         * first appear) */
        glBufferData(GL_ELEMENT_ARRAY_BUFFER, (GLsizeiptr)(f->list_count * sizeof *f->list),
                     f->list, GL_STATIC_DRAW);
        f->ibo_count = glGetError() == GL_NO_ERROR ? f->list_count : 0;
    }
    *bytes = f->ibo_count * sizeof *f->list;
    return f->ibo_count == f->list_count ? f->ibo : 0;
}
