/*
 * renderer_upload.c - the first stage of a draw (see renderer_internal.h): each item takes a
 * slot of its level's vertex pool, its vertex data is (re)built when its level or its
 * neighbours' changed (or it lost its slot), and its draws are recorded: a strip of the level's
 * shared index buffer, its own triangle list (next to nodata, or --stitch add's sets), or up to
 * five draws of --stitch-add-draw five's region sets.
 */
#include "renderer_internal.h"

#include <assert.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Writes count vertices of vtmp, ntmp, ftmp (a level-k item's) into slot h. */
static void write_vertices(tp_renderer* r, int h, int k, int count)
{
    for (int j = 0; j < count; j++) {
        const tp_vertex* src = &r->vtmp[j];
        gpu_vertex* g = &r->gtmp[j];
        g->x = src->x;
        g->y = src->y;
        g->z = isnan(src->z_m) ? 0.0f : src->z_m;
        for (int a = 0; a < 3; a++)
            g->n[a] = (int8_t)lrintf(r->ntmp[j][a] * 127.0f);
        g->flags = (uint8_t)(k | ((r->ftmp[j] ? 1 : 0) << 4));
    }
    tp_vertex_pool_write(r->pool, h, r->gtmp, (size_t)count);
}

/* The pool an item's vertex data goes in: its level's, except a TIN's, which goes in the
 * smallest level m <= its level with 4^m >= its v vertices: a slot of (2^m+1)^2 >= v vertices,
 * and a region of 2 * 4^m >= 2v triangles, more than a triangulation of v points in the plane
 * has (Euler: at most 2v - 5), so nothing is cut off. A TIN draws far fewer triangles than its
 * level's lattice (at levels 4..6 of the real-relief stores, mostly 10-30% of 2 * 4^k), so slots
 * and regions sized for the lattice held 3-10 times what it draws (issue 32 item 5). */
static int pool_level(const tp_renderer* r, const tp_render_item* it, size_t i)
{
    if (it->tin < 0 || !r->cut)
        return it->level;
    size_t v = tp_cut_vertex_count(r->cut, i);
    int m = 0;
    while (m < it->level && ((size_t)1 << (2 * m)) < v)
        m++;
    return m;
}

/* Builds item i's vertex data (and its triangle list if it is incomplete) into slot h; in
 * --stitch add mode with set, the set's samples and triangles (stitch_add_draw.h), with lay,
 * the five-region layout's samples (stitch_add_five.h). tag: what the slot then holds. */
static void upload(tp_renderer* r, const tp_render_item* it, size_t i, tp_render_fill_fn fill,
                   void* user, int h, const tp__stitch_add_set* set, const tp__five_layout* lay,
                   const int8_t tag[4])
{
    tp_pool_slot* sl = tp_vertex_pool_slot(r->pool, h);
    int k = it->level, v = (1 << k) + 1, count = v * v;
    if (lay) {
        if (r->cut)
            tp__stitch_five_fill_node(r->five, lay, r->tree, r->cut, i, r->vtmp, r->ntmp, r->ftmp);
        else
            tp__stitch_five_fill(r->five, lay, r->terrain, (int)it->key, r->vtmp, r->ntmp, r->ftmp);
        write_vertices(r, h, k, (int)lay->vertex_count);
        tp_vertex_pool_drop_triangles(r->pool, h);
        sl->level = it->level;
        sl->tin = -1;
        memcpy(sl->nb, tag, sizeof sl->nb);
        return;
    }
    if (set) {
        if (r->cut)
            tp__stitch_add_fill_node(r->add, set, r->tree, r->cut, i, r->vtmp, r->ntmp, r->ftmp);
        else
            tp__stitch_add_fill(r->add, set, r->terrain, (int)it->key, r->vtmp, r->ntmp, r->ftmp);
        write_vertices(r, h, k, (int)set->vertex_count);
        tp_vertex_pool_write_triangles(r->pool, h, set->triangles, 3 * set->triangle_count);
        sl->level = it->level;
        sl->tin = -1;
        memcpy(sl->nb, it->nb, sizeof sl->nb);
        return;
    }
    assert(k == tp_vertex_pool_level(h) || it->tin >= 0);
    count = (int)fill(user, i, r->vtmp, r->ntmp, r->ftmp);
    write_vertices(r, h, k, count);
    sl->tin = it->tin;
    if (it->incomplete || it->tin >= 0) { /* its own triangle list (a TIN's fits: pool_level) */
        size_t cap = tp_vertex_pool_region_indices(r->pool, tp_vertex_pool_level(h)) / 3;
        size_t nt = r->cut ? tp_cut_triangles(r->cut, i, r->vtmp, r->ttmp, cap)
                           : tp_patch_triangles(r->vtmp, k, r->ttmp, cap);
        tp_vertex_pool_write_triangles(r->pool, h, r->ttmp, 3 * (nt < cap ? nt : cap));
    } else {
        tp_vertex_pool_drop_triangles(r->pool, h);
    }
    sl->level = it->level;
    memcpy(sl->nb, it->nb, sizeof sl->nb);
}

/* realloc's a to n elements of size bytes: the new array, else a (and *ok becomes 0). */
static void* grow_array(void* a, size_t n, size_t size, int* ok)
{
    void* p = realloc(a, n * size);
    if (!p) {
        *ok = 0;
        return a;
    }
    return p;
}

int tp__renderer_grow_draws(tp_renderer* r, size_t count)
{
    if (count <= r->draw_cap)
        return 1;
    size_t cap = r->draw_cap ? r->draw_cap : 256;
    while (cap < count)
        cap *= 2;
    int ok = 1;
    r->counts = grow_array(r->counts, cap, sizeof *r->counts, &ok);
    r->offsets = grow_array(r->offsets, cap, sizeof *r->offsets, &ok);
    r->bases = grow_array(r->bases, cap, sizeof *r->bases, &ok);
    r->gcounts = grow_array(r->gcounts, cap, sizeof *r->gcounts, &ok);
    r->goffsets = grow_array(r->goffsets, cap, sizeof *r->goffsets, &ok);
    r->gbases = grow_array(r->gbases, cap, sizeof *r->gbases, &ok);
    r->draw_level = grow_array(r->draw_level, cap, sizeof *r->draw_level, &ok);
    r->ditem = grow_array(r->ditem, cap, sizeof *r->ditem, &ok);
    r->gitem = grow_array(r->gitem, cap, sizeof *r->gitem, &ok);
    if (!ok)
        return 0;
    r->draw_cap = cap;
    return 1;
}

size_t tp__renderer_upload(tp_renderer* r, const tp_render_item* items, size_t count,
                           tp_render_fill_fn fill, void* user, tp_render_stats* stats)
{
    int five = r->stitch_add && r->stitch_add_five;
    size_t drawn = 0;
    enum { AHEAD = 8 }; /* the map entries 2 AHEAD items on, the slots AHEAD on */
    for (size_t i = 0; i < count; i++) {
        const tp_render_item* it = &items[i];
        int fresh;
        if (i + 2 * AHEAD < count)
            tp_vertex_pool_prefetch(r->pool, items[i + 2 * AHEAD].key, 0);
        if (i + AHEAD < count)
            tp_vertex_pool_prefetch(r->pool, items[i + AHEAD].key, 1);
        const tp__stitch_add_set* set = NULL;
        const tp__five_layout* lay = NULL;
        tp__five_draws fd;
        if (r->stitch_add && !it->incomplete && tp__stitch_add_needed(it->level, it->nb) &&
            (five ? !(lay = tp__stitch_five_layout(r->five, it->level, it->nb)) ||
                        !tp__stitch_five_draws(r->five, it->level, it->nb, &fd)
                  : !(set = tp__stitch_add_get(r->add, it->level, it->nb)))) {
            stats->dropped++; /* out of memory */
            continue;
        }
        int h = tp_vertex_pool_take(r->pool, it->key,
                                    set   ? set->level
                                    : lay ? lay->level
                                          : pool_level(r, it, i),
                                    &fresh);
        if (h < 0) {
            stats->dropped++;
            continue;
        }
        /* a five-region layout's vertices depend on (level, D) and the sides that move (a
         * store's) only: its tag says so */
        int8_t tag[4] = {it->nb[0], it->nb[1], it->nb[2], it->nb[3]};
        for (int s = 0; lay && s < 4; s++)
            if (tag[s] > it->level)
                tag[s] = (int8_t)(-2 - lay->D);
        const tp_pool_slot* sl = tp_vertex_pool_slot(r->pool, h);
        int own_list = it->incomplete || set || it->tin >= 0;
        if (fresh || sl->level != it->level || memcmp(sl->nb, tag, sizeof sl->nb) ||
            sl->tin != it->tin || own_list != (sl->region >= 0)) {
            upload(r, it, i, fill, user, h, set, lay, tag);
            stats->uploads++;
        }
        stats->patches_drawn++;
        if (lay) { /* its regions, each a draw of the shared sets (none empty) */
            for (int d = 0; d < fd.count; d++, drawn++) {
                r->draw_level[drawn] = 3 * tp_vertex_pool_level(h) + 2;
                r->counts[drawn] = (GLsizei)fd.index_count[d];
                r->offsets[drawn] = (void*)(fd.first[d] * sizeof(uint32_t));
                r->bases[drawn] = tp_vertex_pool_base_vertex(r->pool, h);
                r->ditem[drawn] = i;
            }
            stats->triangles += fd.triangles;
            continue;
        }
        int c = sl->region;
        if ((it->incomplete || it->tin >= 0) && c < 0)
            continue; /* no region could be made */
        size_t list_offset = 0, list_count = tp_vertex_pool_triangles(r->pool, h, &list_offset);
        /* An item of nodata only has no triangles. It must not become a zero-count draw: Mesa
         * 22.3 (llvmpipe) applies the wrong base vertex to the draws after a zero-count one in
         * glMultiDrawElementsBaseVertex, which dropped border patches. */
        if (c >= 0 && list_count == 0)
            continue;
        int k = tp_vertex_pool_level(h); /* its pool's level (an added-vertex set's) */
        if (r->stitch_add)               /* strips: the level-k grid, nothing moved */
            stats->triangles += c >= 0 ? list_count / 3 : (size_t)2 << (2 * it->level);
        r->draw_level[drawn] = 3 * k + (c >= 0); /* the group: level, strip or triangle list */
        r->counts[drawn] = (GLsizei)(c < 0 ? r->level_count[k] : list_count);
        r->offsets[drawn] = (void*)(c < 0 ? r->level_offset[k] : list_offset);
        r->bases[drawn] = tp_vertex_pool_base_vertex(r->pool, h);
        r->ditem[drawn] = i;
        drawn++;
    }
    return drawn;
}
