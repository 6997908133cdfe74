/*
 * render_patches.c - what the renderer draws (see renderer.h): the visible patches of a resident
 * terrain's selection (tp_renderer_create, tp_renderer_draw) and the nodes of a store's cut
 * (tp_renderer_draw_cut), each turned into items and their vertex data, then drawn by
 * tp_renderer_draw_items.
 */
#include "renderer_internal.h"

#include <assert.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* ---- the patches of a resident terrain ---- */

tp_renderer* tp_renderer_create(const tp_terrain* t, tp_error* err)
{
    tp_terrain_info in;
    tp_terrain_get_info(t, &in);
    tp_render_grid_desc d = {.n = in.n,
                             .width = in.width,
                             .height = in.height,
                             .min_height_m = in.min_height_m,
                             .max_height_m = in.max_height_m};
    memcpy(d.geotransform, in.geotransform, sizeof d.geotransform);
    tp_renderer* r = tp_renderer_create_desc(&d, err);
    if (!r)
        return NULL;
    r->terrain = t;
    r->complete = malloc((size_t)in.patch_count);
    if (!r->complete) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        tp_renderer_destroy(r);
        return NULL;
    }
    for (int p = 0; p < in.patch_count; p++) {
        tp_patch_info pi;
        tp_patch_get_info(t, p, &pi);
        r->complete[p] = (uint8_t)pi.complete;
    }
    return r;
}

/* The next draw's --stitch add mode (s) and what it needs; 0 when out of memory. */
static int set_stitch_add(tp_renderer* r, const tp_render_settings* s)
{
    r->stitch_add = s->stitch_add;
    r->stitch_add_five = s->stitch_add_five;
    if (s->stitch_add && s->stitch_add_five)
        return r->five || (r->five = tp__stitch_five_create(r->grid.n));
    return !s->stitch_add || r->add || (r->add = tp__stitch_add_create(r->grid.n));
}

static int grow_items(tp_renderer* r, size_t count)
{
    if (count <= r->item_cap)
        return 1;
    tp_render_item* items = realloc(r->items, count * sizeof *items);
    if (!items)
        return 0;
    r->items = items;
    r->item_cap = count;
    return 1;
}

static size_t fill_patch(void* user, size_t i, tp_vertex* v, float (*normals)[3],
                         uint8_t* filled)
{
    const tp_renderer* r = user;
    const tp_render_item* it = &r->items[i];
    int nb[4] = {it->nb[0], it->nb[1], it->nb[2], it->nb[3]};
    int k = it->level, side = (1 << k) + 1;
    size_t count = (size_t)side * side;
    tp_patch_vertices(r->terrain, (int)it->key, k, nb, v, count);
    for (size_t j = 0; j < count; j++) {
        tp_terrain_normal(r->terrain, v[j].x, v[j].y, normals[j]);
        filled[j] = tp_terrain_sample_class(r->terrain, v[j].x, v[j].y) == TP_SAMPLE_FILLED;
    }
    return count;
}

void tp_renderer_draw(tp_renderer* r, tp_selection* sel, const tp_camera* cam,
                      const tp_render_settings* s, int finish, tp_render_stats* stats)
{
    assert(r->terrain);
    tp_terrain_info in;
    tp_terrain_get_info(r->terrain, &in);
    if (!grow_items(r, (size_t)in.patch_count)) {
        memset(stats, 0, sizeof *stats);
        return;
    }
    size_t count = 0;
    for (int p = 0; p < in.patch_count; p++) {
        if (!tp_selection_visible(sel, p))
            continue;
        tp_render_item* it = &r->items[count++];
        int nb[4], k = tp_selection_level(sel, p);
        tp_selection_neighbor_levels(sel, p, nb);
        it->key = p;
        it->level = (int8_t)k;
        /* only a coarser neighbour moves vertices (a finer one adds them, --stitch add): others
         * need no new upload when they change */
        for (int side = 0; side < 4; side++)
            it->nb[side] = (int8_t)(nb[side] >= 0 && (s->stitch_add ? nb[side] > k : nb[side] < k)
                                        ? nb[side]
                                        : TP_NO_NEIGHBOR);
        it->incomplete = !r->complete[p];
        it->tin = -1;
    }
    tp_selection_clear_dirty(sel);
    if (!set_stitch_add(r, s))
        count = 0; /* out of memory: nothing to draw */
    tp_renderer_draw_items(r, r->items, count, fill_patch, r, cam, s,
                           tp_selection_vertical_scale(sel), finish, stats);
    r->stitch_add = 0;
}

/* ---- the nodes of a cut over a tree ---- */

static size_t fill_node(void* user, size_t i, tp_vertex* v, float (*normals)[3], uint8_t* filled)
{
    const tp_renderer* r = user;
    const tp_render_item* it = &r->items[i];
    size_t count = tp_cut_vertex_count(r->cut, i); /* a TIN's, or (2^level+1)^2 */
    tp_cut_vertices(r->cut, i, v, count);
    tp_tree_node_normals(r->tree, it->key, v, count, normals);
    for (size_t j = 0; j < count; j++) {
        filled[j] = v[j].cls == TP_SAMPLE_FILLED; /* the store's filled bits (format 4) */
        if (isnan(v[j].z_m)) {
            normals[j][0] = normals[j][1] = 0;
            normals[j][2] = 1;
        }
    }
    return count;
}

void tp_renderer_draw_cut(tp_renderer* r, const tp_tree* tree, const tp_cut* cut,
                          const tp_camera* cam, const tp_render_settings* s, double zscale,
                          int finish, tp_render_stats* stats)
{
    size_t count = 0;
    const tp_cut_node* nodes = tp_cut_nodes(cut, &count);
    if (!grow_items(r, count)) {
        memset(stats, 0, sizeof *stats);
        return;
    }
    for (size_t i = 0; i < count; i++) {
        tp_render_item* it = &r->items[i];
        it->key = nodes[i].node;
        it->level = nodes[i].level;
        /* a side moves (below the level) or, --stitch add, takes vertices (above it) */
        for (int side = 0; side < 4; side++)
            it->nb[side] =
                (int8_t)(s->stitch_add && nodes[i].add[side] > nodes[i].level ? nodes[i].add[side]
                         : nodes[i].nb[side] >= 0 && nodes[i].nb[side] < nodes[i].level
                             ? nodes[i].nb[side]
                             : TP_NO_NEIGHBOR);
        it->incomplete = !(tp_tree_meta(tree, nodes[i].node)->flags & TP_NODE_COMPLETE);
        it->tin = nodes[i].tin;
    }
    if (!set_stitch_add(r, s))
        count = 0; /* out of memory: nothing to draw */
    r->tree = tree;
    r->cut = cut;
    tp_renderer_draw_items(r, r->items, count, fill_node, r, cam, s, zscale, finish, stats);
    r->stitch_add = 0;
    r->tree = NULL;
    r->cut = NULL;
}
