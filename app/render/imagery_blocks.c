/* imagery_blocks.c - a texture per drawn node, Brodersen's way (see imagery_blocks.h). */
#define _POSIX_C_SOURCE 200809L
#include "imagery_blocks.h"
#include "clock.h"

#include <epoxy/gl.h>

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define L TP_BLOCKS_LAYER
#define EMPTY UINT64_MAX   /* a window wholly transparent (or outside the image): no layer */
#define KEEP 1e300

typedef struct layer_info {
    uint64_t key;          /* the window it holds, EMPTY: free */
    uint64_t used;         /* frame it was last drawn */
    int next;              /* hash chain, -1 ends */
} layer_info;

struct tp_imagery_blocks {
    tp_block_source src;
    tp_imagery_cache* cache;
    tp_tree_geometry g;
    double gt[6];
    int ts, levels, layers, cap;
    GLuint tex;
    layer_info* li;
    int* bucket;
    unsigned bits;
    int pinned;            /* the coarsest window's layer */
    uint64_t frame;
    uint8_t* stage;        /* one window, assembled */
    tp_blocks_assignment* as;
    tp_render_item_texture* it;
    size_t as_cap, count;
    tp_block_key* want;
    size_t want_len, want_cap;
    uint64_t* want_sorted; /* packed, for the garbage collection's score */
    double cam_e, cam_n;
};

static uint64_t pack(int l, int64_t x, int64_t y)
{
    return ((uint64_t)l << 58) | ((uint64_t)x << 29) | (uint64_t)y;
}

static tp_block_key unpack(uint64_t k)
{
    tp_block_key b = {(int)(k >> 58), (int64_t)((k >> 29) & 0x1FFFFFFF), (int64_t)(k & 0x1FFFFFFF)};
    return b;
}

static unsigned hash(const tp_imagery_blocks* b, uint64_t key)
{
    return (unsigned)((key * 0x9E3779B97F4A7C15ull) >> (64 - b->bits));
}

static int find(const tp_imagery_blocks* b, uint64_t key)
{
    for (int i = b->bucket[hash(b, key)]; i >= 0; i = b->li[i].next)
        if (b->li[i].key == key)
            return i;
    return -1;
}

static void unlink_layer(tp_imagery_blocks* b, int i)
{
    if (b->li[i].key == EMPTY)
        return;
    int* p = &b->bucket[hash(b, b->li[i].key)];
    while (*p != i)
        p = &b->li[*p].next;
    *p = b->li[i].next;
    b->li[i].key = EMPTY;
}

static void link_layer(tp_imagery_blocks* b, int i, uint64_t key)
{
    unsigned h = hash(b, key);
    b->li[i].key = key;
    b->li[i].next = b->bucket[h];
    b->bucket[h] = i;
}

/* Half a post in level-l texels, rounded down: a window's offset from its block. */
static int64_t window_shift(const tp_imagery_blocks* b, int l)
{
    int e = b->ts - l - 1;
    return e >= 0 ? (int64_t)1 << e : 0;
}

/* The window of node (s, c, r) (imagery_blocks.h): its key (level, block column, block row). */
static uint64_t node_window(const tp_imagery_blocks* b, int s, int64_t c, int64_t r)
{
    int l = b->g.n + s + b->ts - 8;
    if (l < 0) { /* the ancestor at level 0 */
        c >>= -l;
        r >>= -l;
        l = 0;
    } else if (l > b->levels - 1) { /* that many levels coarser than the coarsest */
        c <<= l - (b->levels - 1);
        r <<= l - (b->levels - 1);
        l = b->levels - 1;
    }
    if (c >= ((int64_t)1 << 29) || r >= ((int64_t)1 << 29))
        return EMPTY;
    return pack(l, c, r);
}

static int block_in_level(const tp_imagery_blocks* b, int l, int64_t bx, int64_t by)
{
    return bx * L < b->src.width[l] && by * L < b->src.height[l];
}

static int block_empty(const tp_imagery_blocks* b, tp_block_key k)
{
    return !block_in_level(b, k.level, k.bx, k.by) ||
           (b->src.is_empty && b->src.is_empty(b->src.user, k));
}

/* The blocks window w overlaps (1, 2 or 4), those not empty into keys; returns how many. */
static int window_blocks(const tp_imagery_blocks* b, uint64_t w, tp_block_key keys[4])
{
    tp_block_key k = unpack(w);
    int span = window_shift(b, k.level) > 0 ? 2 : 1, n = 0;
    for (int j = 0; j < span; j++)
        for (int i = 0; i < span; i++) {
            tp_block_key q = {k.level, k.bx + i, k.by + j};
            if (!block_empty(b, q))
                keys[n++] = q;
        }
    return n;
}

/* Assembles window w from the blocks in RAM into b->stage; 0 when one is not read yet. now:
 * read those missing on this thread (creation). */
static int assemble(tp_imagery_blocks* b, uint64_t w, int now)
{
    tp_block_key k = unpack(w);
    int64_t f = window_shift(b, k.level);
    int span = f > 0 ? 2 : 1;
    const uint8_t* px[2][2] = {{NULL, NULL}, {NULL, NULL}};
    for (int j = 0; j < span; j++)
        for (int i = 0; i < span; i++) {
            tp_block_key q = {k.level, k.bx + i, k.by + j};
            if (block_empty(b, q))
                continue;
            px[j][i] = now ? tp_imagery_cache_load_now(b->cache, q) : tp_imagery_cache_get(b->cache, q);
            if (!px[j][i])
                return 0;
        }
    /* window texel (x, y) is block (i, j)'s texel (x + f - i L, y + f - j L) */
    for (int y = 0; y < L; y++) {
        int j = y + f >= L, by = (int)(y + f - j * L);
        uint8_t* row = b->stage + (size_t)y * L * 4;
        for (int i = 0; i < span; i++) {
            int x0 = i == 0 ? 0 : (int)(L - f), x1 = i == 0 ? (int)(L - f) : L;
            if (span == 1)
                x1 = L;
            const uint8_t* src = px[j][i];
            int bx0 = (int)(x0 + f - i * L);
            if (src)
                memcpy(row + (size_t)x0 * 4, src + ((size_t)by * L + bx0) * 4, (size_t)(x1 - x0) * 4);
            else
                memset(row + (size_t)x0 * 4, 0, (size_t)(x1 - x0) * 4);
        }
    }
    return 1;
}

static void upload(tp_imagery_blocks* b, int layer, uint64_t w)
{
    glTexSubImage3D(GL_TEXTURE_2D_ARRAY, 0, 0, 0, layer, L, L, 1, GL_RGBA, GL_UNSIGNED_BYTE,
                    b->stage);
    unlink_layer(b, layer);
    link_layer(b, layer, w);
    b->li[layer].used = b->frame;
}

/* The least recently drawn layer not drawn this frame (a free one first); -1 when every layer
 * is drawn this frame. */
static int lru_layer(const tp_imagery_blocks* b)
{
    int best = -1;
    for (int i = 0; i < b->layers; i++) {
        if (i == b->pinned || b->li[i].used == b->frame)
            continue;
        if (b->li[i].key == EMPTY)
            return i;
        if (best < 0 || b->li[i].used < b->li[best].used)
            best = i;
    }
    return best;
}

void tp_imagery_blocks_destroy(tp_imagery_blocks* b)
{
    if (!b)
        return;
    tp_imagery_cache_destroy(b->cache);
    if (b->tex)
        glDeleteTextures(1, &b->tex);
    free(b->li);
    free(b->bucket);
    free(b->stage);
    free(b->as);
    free(b->it);
    free(b->want);
    free(b->want_sorted);
    free(b);
}

tp_imagery_blocks* tp_imagery_blocks_create(const tp_block_source* src, int texel_shift,
                                            const double gt[6], const tp_tree_geometry* g,
                                            const tp_imagery_blocks_options* o, tp_error* err)
{
    tp_imagery_blocks_options d = {0};
    if (!o)
        o = &d;
    if (src->block != L) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "blocks of %d texels; the blocks mode takes %d",
                     src->block, L);
        return NULL;
    }
    tp_imagery_blocks* b = calloc(1, sizeof *b);
    if (!b) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        return NULL;
    }
    b->src = *src;
    b->g = *g;
    memcpy(b->gt, gt, sizeof b->gt);
    b->ts = texel_shift;
    b->levels = src->levels;
    b->cap = o->upload_cap_layers > 0 ? o->upload_cap_layers : 8;
    size_t layer_bytes = (size_t)L * L * 4;
    size_t budget = o->gpu_bytes ? o->gpu_bytes : TP_BLOCKS_DEFAULT_GPU_BYTES;
    GLint max_layers = 0;
    glGetIntegerv(GL_MAX_ARRAY_TEXTURE_LAYERS, &max_layers);
    size_t k = budget / layer_bytes;
    if (k > (size_t)max_layers)
        k = (size_t)max_layers;
    if (k < 8) {
        tp_error_set(err, TP_ERR_BACKEND,
                     "a GPU budget of %zu bytes holds %zu layers of %dx%d RGBA (8 at least; "
                     "the GPU holds %d)",
                     budget, budget / layer_bytes, L, L, max_layers);
        free(b);
        return NULL;
    }
    b->layers = (int)k;
    b->bits = 1;
    while ((1u << b->bits) < 2u * (unsigned)b->layers)
        b->bits++;
    b->li = malloc((size_t)b->layers * sizeof *b->li);
    b->bucket = malloc(sizeof *b->bucket << b->bits);
    b->stage = malloc(layer_bytes);
    if (!b->li || !b->bucket || !b->stage) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        tp_imagery_blocks_destroy(b);
        return NULL;
    }
    memset(b->bucket, 0xff, sizeof *b->bucket << b->bits);
    for (int i = 0; i < b->layers; i++)
        b->li[i] = (layer_info){EMPTY, 0, -1};
    while (glGetError() != GL_NO_ERROR) {
    }
    glGenTextures(1, &b->tex);
    glBindTexture(GL_TEXTURE_2D_ARRAY, b->tex);
    glTexImage3D(GL_TEXTURE_2D_ARRAY, 0, GL_RGBA8, L, L, b->layers, 0, GL_RGBA, GL_UNSIGNED_BYTE,
                 NULL);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    glTexParameteri(GL_TEXTURE_2D_ARRAY, GL_TEXTURE_MAX_LEVEL, 0);
    if (glGetError() != GL_NO_ERROR) {
        tp_error_set(err, TP_ERR_BACKEND, "the GPU cannot hold %d layers of %dx%d RGBA (%.0f MB)",
                     b->layers, L, L, b->layers * (double)layer_bytes / 1e6);
        tp_imagery_blocks_destroy(b);
        return NULL;
    }
    b->cache = tp_imagery_cache_create(src, o->cache_bytes ? o->cache_bytes : (size_t)64 << 20,
                                       o->no_loader, err);
    if (!b->cache) {
        tp_imagery_blocks_destroy(b);
        return NULL;
    }
    /* the coarsest level's window, now and for good: every node has an ancestor to show */
    uint64_t root = pack(b->levels - 1, 0, 0);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    b->frame = 1;
    if (!assemble(b, root, 1)) {
        tp_error_set(err, TP_ERR_IO, "cannot read the coarsest imagery block");
        tp_imagery_blocks_destroy(b);
        return NULL;
    }
    b->pinned = 0;
    upload(b, 0, root);
    return b;
}

static int push_want(tp_imagery_blocks* b, tp_block_key k)
{
    if (b->want_len == b->want_cap) {
        size_t c = b->want_cap ? 2 * b->want_cap : 256;
        tp_block_key* w = realloc(b->want, c * sizeof *w);
        uint64_t* ws = realloc(b->want_sorted, c * sizeof *ws);
        if (w)
            b->want = w;
        if (ws)
            b->want_sorted = ws;
        if (!w || !ws)
            return 0;
        b->want_cap = c;
    }
    b->want[b->want_len++] = k;
    return 1;
}

static int cmp_u64(const void* a, const void* b)
{
    uint64_t x = *(const uint64_t*)a, y = *(const uint64_t*)b;
    return (x > y) - (x < y);
}

/* Garbage collection of the RAM pool: the blocks this frame's missing windows need are kept;
 * of the rest (mostly blocks already on the GPU) the farthest from the camera, in blocks of its
 * own level, goes first. */
static double gc_score(void* user, tp_block_key k)
{
    const tp_imagery_blocks* b = user;
    uint64_t key = pack(k.level, k.bx, k.by);
    if (b->want_len && bsearch(&key, b->want_sorted, b->want_len, sizeof key, cmp_u64))
        return KEEP;
    double size_e = ldexp(b->gt[1], k.level) * L, size_n = ldexp(b->gt[5], k.level) * L;
    double e = b->gt[0] + (k.bx + 0.5) * size_e, n = b->gt[3] + (k.by + 0.5) * size_n;
    return -hypot((e - b->cam_e) / size_e, (n - b->cam_n) / size_n);
}

/* Assigns every drawn node a layer; returns the nodes drawn with an ancestor's. */
static int assign(tp_imagery_blocks* b, const tp_cut_node* nodes, size_t count, int capped,
                  tp_clipmap_stats* st)
{
    int missing = 0;
    b->want_len = 0;
    glBindTexture(GL_TEXTURE_2D_ARRAY, b->tex);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 4);
    double t0 = tp_clock_ms();
    for (size_t i = 0; i < count; i++) {
        int s, c, r;
        tp_tree_node_locate(&b->g, nodes[i].node, &s, &c, &r);
        uint64_t w = node_window(b, s, c, r);
        tp_block_key keys[4];
        int nk = w == EMPTY ? 0 : window_blocks(b, w, keys);
        tp_blocks_assignment* a = &b->as[i];
        a->own = 1;
        a->layer = -1;
        if (nk == 0) { /* wholly transparent: nothing to sample */
            tp_block_key k = w == EMPTY ? (tp_block_key){0, 0, 0} : unpack(w);
            a->level = k.level;
            a->origin[0] = k.bx * L + window_shift(b, k.level);
            a->origin[1] = k.by * L + window_shift(b, k.level);
            continue;
        }
        int layer = find(b, w);
        if (layer < 0 && (!capped || st->uploads < b->cap) && assemble(b, w, 0) &&
            (layer = lru_layer(b)) >= 0) {
            upload(b, layer, w);
            st->uploads++;
            st->upload_bytes += (size_t)L * L * 4;
        }
        if (layer < 0) { /* the nearest ancestor with a layer (the pinned root at last) */
            a->own = 0;
            missing++;
            for (int k = 0; k < nk; k++)
                push_want(b, keys[k]);
            uint64_t up = w;
            for (int sa = s + 1; layer < 0 && sa < 62; sa++) {
                uint64_t wa = node_window(b, sa, (int64_t)c >> (sa - s), (int64_t)r >> (sa - s));
                if (wa == up)
                    continue;
                up = wa;
                layer = wa == EMPTY ? -1 : find(b, wa);
                if (wa != EMPTY && unpack(wa).level == b->levels - 1 && layer < 0)
                    break;
            }
            if (layer < 0)
                layer = b->pinned;
        }
        b->li[layer].used = b->frame;
        tp_block_key k = unpack(b->li[layer].key);
        int64_t f = window_shift(b, k.level);
        a->layer = layer;
        a->level = k.level;
        a->origin[0] = k.bx * L + f;
        a->origin[1] = k.by * L + f;
    }
    st->upload_ms = tp_clock_ms() - t0;
    return missing;
}

/* Hands the loader this frame's missing blocks and frees RAM blocks not among them. */
static void want_and_collect(tp_imagery_blocks* b)
{
    tp_imagery_cache_want(b->cache, b->want, b->want_len);
    for (size_t i = 0; i < b->want_len; i++)
        b->want_sorted[i] = pack(b->want[i].level, b->want[i].bx, b->want[i].by);
    qsort(b->want_sorted, b->want_len, sizeof *b->want_sorted, cmp_u64);
    tp_imagery_cache_collect(b->cache, gc_score, b, KEEP);
}

void tp_imagery_blocks_frame(tp_imagery_blocks* b, const tp_cut* cut, tp_renderer* r,
                             const tp_camera* cam, int settle, double timeout_s,
                             tp_clipmap_stats* st)
{
    memset(st, 0, sizeof *st);
    size_t count = 0;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    if (count > b->as_cap) {
        tp_blocks_assignment* as = realloc(b->as, count * sizeof *as);
        if (as)
            b->as = as;
        tp_render_item_texture* it = realloc(b->it, count * sizeof *it);
        if (it)
            b->it = it;
        if (!as || !it) {
            b->count = 0;
            if (r)
                tp_renderer_set_item_textures(r, 0, NULL, 0);
            return;
        }
        b->as_cap = count;
    }
    b->count = count;
    b->cam_e = cam->position[0];
    b->cam_n = cam->position[1];
    double until = tp_clock_ms() + timeout_s * 1e3;
    b->frame++;
    st->missing = assign(b, nodes, count, !settle, st);
    want_and_collect(b);
    while (settle && st->missing > 0 && tp_clock_ms() < until) {
        tp_imagery_cache_wait(b->cache, 0.05);
        b->frame++;
        tp_clipmap_stats more = {0};
        st->missing = assign(b, nodes, count, 0, &more);
        want_and_collect(b);
        tp_imagery_cache_stats cs;
        tp_imagery_cache_get_stats(b->cache, &cs);
        if (more.uploads == 0 && cs.pending == 0)
            break; /* more nodes than layers: the rest stay with their ancestors' */
        st->uploads += more.uploads;
        st->upload_bytes += more.upload_bytes;
        st->upload_ms += more.upload_ms;
    }

    /* the mapping of each node's posts to its layer: level-lv texel of post x is
     * (x + 0.5) 2^(ts - lv), minus the window's origin */
    for (size_t i = 0; i < count; i++) {
        const tp_blocks_assignment* a = &b->as[i];
        tp_render_item_texture* t = &b->it[i];
        int s, c, rr;
        tp_tree_node_locate(&b->g, nodes[i].node, &s, &c, &rr);
        int64_t cell[2] = {(int64_t)c << (b->g.n + s), (int64_t)rr << (b->g.n + s)};
        double k = ldexp(1.0, b->ts - a->level);
        t->layer = a->layer;
        for (int d = 0; d < 2; d++) {
            t->cell[d] = (int32_t)cell[d];
            t->scale[d] = (float)(k / L);
            t->offset[d] = (float)(((cell[d] + 0.5) * k - (double)a->origin[d]) / L);
        }
    }
    if (r) {
        tp_renderer_set_clip(r, NULL);
        tp_renderer_set_item_textures(r, b->tex, b->it, count);
    }

    tp_imagery_cache_stats cs;
    tp_imagery_cache_get_stats(b->cache, &cs);
    st->pending = cs.pending;
    st->gpu_bytes = (size_t)b->layers * L * L * 4;
    st->cache_bytes = cs.resident_blocks * cs.block_bytes;
    st->loads = cs.loads;
    st->evictions = cs.evictions;
    st->valid_levels = b->levels;
}

const tp_blocks_assignment* tp_imagery_blocks_assignment(const tp_imagery_blocks* b, size_t* count)
{
    *count = b->count;
    return b->as;
}

const tp_render_item_texture* tp_imagery_blocks_item_textures(const tp_imagery_blocks* b,
                                                              size_t* count)
{
    *count = b->count;
    return b->it;
}

unsigned tp_imagery_blocks_texture(const tp_imagery_blocks* b)
{
    return b->tex;
}

int tp_imagery_blocks_layers(const tp_imagery_blocks* b)
{
    return b->layers;
}

const char* tp_imagery_blocks_take_failure(tp_imagery_blocks* b)
{
    return tp_imagery_cache_take_failure(b->cache);
}
