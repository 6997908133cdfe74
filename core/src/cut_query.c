/*
 * cut_query.c - what the viewer asks of the terrain while nodes stream in: grid <-> world, the
 * full-resolution surface from resident leaves, the cut's vertical scale (its setter is
 * cut_select.c's), ray casts
 * against the drawn cut and camera collision (see tp_core.h, "queries on the tree and the cut").
 *
 * The ray cast is tp_selection_ray_cast's walk one level down: a 2D DDA (Amanatides & Woo)
 * over the leaves finds the drawn nodes the ray's ground track crosses in order; inside a
 * drawn node a second DDA over its cells at its own level tests only the two triangles of each
 * cell crossed (Moller & Trumbore), plus the whole border strip of a stitched side, where moved
 * vertices slide triangles along the side. A node's triangles stay inside its square, so the
 * first node with a hit holds the nearest one.
 */
#include "cut_int.h"
#include "ray.h"
#include "surface.h"

#include <assert.h>
#include <math.h>

void tp_tree_world_to_grid(const tp_tree* t, double e, double n, double* x, double* y)
{
    assert(t && x && y);
    const double* gt = t->desc.geotransform;
    *x = (e - gt[0]) / gt[1] - 0.5;
    *y = (n - gt[3]) / gt[5] - 0.5;
}

void tp_tree_grid_to_world(const tp_tree* t, double x, double y, double* e, double* n)
{
    assert(t && e && n);
    const double* gt = t->desc.geotransform;
    *e = gt[0] + (x + 0.5) * gt[1];
    *n = gt[3] + (y + 0.5) * gt[5];
}

int64_t tp_tree_leaf_at(const tp_tree* t, double x, double y)
{
    assert(t);
    const tp_tree_geometry* g = &t->desc.geometry;
    if (!(x >= 0 && y >= 0 && x <= g->width - 1 && y <= g->height - 1))
        return -1;
    int lc = (int)x >> g->n, lr = (int)y >> g->n;
    lc = lc < g->cols ? lc : g->cols - 1;
    lr = lr < g->rows ? lr : g->rows - 1;
    return tp_tree_node_id(g, 0, lc, lr);
}

static double tree_height(const void* grid, int x, int y)
{
    return tp_tree_sample((const tp_tree*)grid, x, y);
}

double tp_tree_height_at(const tp_tree* t, double x, double y)
{
    assert(t);
    int64_t leaf = tp_tree_leaf_at(t, x, y);
    if (leaf < 0 || !tp_tree_samples(t, leaf))
        return NAN;
    const tp_tree_geometry* g = &t->desc.geometry;
    return tp__split_height(tree_height, t, g->width, g->height, x, y);
}

double tp_cut_vertical_scale(const tp_cut* c)
{
    assert(c);
    return c->zscale;
}

int tp_cut_keep_above(const tp_cut* c, double position[3], double clearance_m)
{
    assert(c && position && isfinite(clearance_m) && clearance_m >= 0);
    double x, y;
    tp_tree_world_to_grid(c->t, position[0], position[1], &x, &y);
    double a = tp_tree_height_at(c->t, x, y), b = tp_cut_drawn_height_at(c, x, y);
    return tp__keep_above(position, a, b, c->zscale, clearance_m);
}

/* ---- ray casting ---- */


/* A 2D DDA over a grid of square cells: cell (cx, cy) spans [ox + cx * size, ox + (cx+1) *
 * size] in x (the same in y); the ray's ground track is (x0 + t gx, y0 + t gy). */
typedef struct dda {
    double x0, y0, gx, gy, ox, oy, size;
    int cx, cy, nx, ny, sx, sy;
    double tx, ty, enter, t1;
} dda;

static void dda_init(dda* w, double x0, double y0, double gx, double gy, double t0, double t1,
                     double ox, double oy, double size, int nx, int ny)
{
    *w = (dda){x0, y0, gx, gy, ox, oy, size, 0, 0, nx, ny, 0, 0, 0, 0, t0, t1};
    int cx = (int)floor((x0 + t0 * gx - ox) / size), cy = (int)floor((y0 + t0 * gy - oy) / size);
    w->cx = cx < 0 ? 0 : cx >= nx ? nx - 1 : cx;
    w->cy = cy < 0 ? 0 : cy >= ny ? ny - 1 : cy;
    w->sx = gx > 0 ? 1 : gx < 0 ? -1 : 0;
    w->sy = gy > 0 ? 1 : gy < 0 ? -1 : 0;
    w->tx = w->sx ? (ox + (w->cx + (w->sx > 0)) * size - x0) / gx : INFINITY;
    w->ty = w->sy ? (oy + (w->cy + (w->sy > 0)) * size - y0) / gy : INFINITY;
}

/* The current cell is valid; writes the t where the ray leaves it. */
static int dda_valid(const dda* w, double* leave)
{
    *leave = fmin(fmin(w->tx, w->ty), w->t1);
    return w->enter <= w->t1 && w->cx >= 0 && w->cy >= 0 && w->cx < w->nx && w->cy < w->ny;
}

static void dda_step(dda* w)
{
    if (w->tx < w->ty) {
        w->cx += w->sx;
        w->enter = w->tx;
        w->tx += w->size / fabs(w->gx);
    } else {
        w->cy += w->sy;
        w->enter = w->ty;
        w->ty += w->size / fabs(w->gy);
    }
}

typedef struct ray_ctx {
    const tp_cut* c;
    const double* o;      /* origin (world) */
    double d[3];          /* unit direction */
    double x0, y0, gx, gy; /* the ground track in grid coordinates */
    tp_vertex* v;         /* a node's vertices, (2^n+1)^2 */
    tp__node_draw draw;   /* which of its triangles it draws */
} ray_ctx;

/* Nearest hit with the two triangles of cell (cx, cy) of a node whose vertices are in r->v
 * (side vs), or best. The cell's diagonal runs from (1, 0) to (0, 1), as the strip draws it
 * (cut_draw.c's cell_triangle). */
static double cell_hit(const ray_ctx* r, int vs, int cx, int cy, double best)
{
    static const int tri[2][3][2] = {{{0, 0}, {0, 1}, {1, 0}}, {{1, 0}, {0, 1}, {1, 1}}};
    for (int h = 0; h < 2; h++) {
        double w[3][3];
        int32_t pos[3][2];
        int ok = 1;
        for (int k = 0; k < 3; k++) {
            const tp_vertex* v = &r->v[(size_t)(cy + tri[h][k][1]) * vs + (cx + tri[h][k][0])];
            ok &= (v->cls == TP_SAMPLE_VALID || v->cls == TP_SAMPLE_FILLED) && !isnan(v->z_m);
            pos[k][0] = v->x, pos[k][1] = v->y;
            tp_tree_grid_to_world(r->c->t, v->x, v->y, &w[k][0], &w[k][1]);
            w[k][0] -= r->o[0];
            w[k][1] -= r->o[1];
            w[k][2] = (double)v->z_m * r->c->zscale - r->o[2];
        }
        if (!tp__tri_drawn(&r->draw, pos, ok))
            continue;
        double t = tp__ray_triangle(r->d, w[0], w[1], w[2]);
        if (t >= 0 && (best < 0 || t < best))
            best = t;
    }
    return best;
}

/* Nearest hit with a triangle of a TIN node (grid positions, heights in steps). */
typedef struct tin_ray {
    const ray_ctx* r;
    double best;
} tin_ray;

static void tin_ray_tri(const int32_t pos[3][2], const double q[3], void* user)
{
    tin_ray* t = user;
    const ray_ctx* r = t->r;
    double w[3][3];
    for (int k = 0; k < 3; k++) {
        tp_tree_grid_to_world(r->c->t, pos[k][0], pos[k][1], &w[k][0], &w[k][1]);
        w[k][0] -= r->o[0];
        w[k][1] -= r->o[1];
        w[k][2] = q[k] * r->c->step * r->c->zscale - r->o[2];
    }
    double h = tp__ray_triangle(r->d, w[0], w[1], w[2]);
    if (h >= 0 && (t->best < 0 || h < t->best))
        t->best = h;
}

/* Drawn node i draws a TIN: every triangle (a few hundred: no walk over cells needed). */
static double tin_hit(const ray_ctx* r, size_t i)
{
    tin_ray t = {r, -1};
    tp__cut_tin_tris(r->c, i, tin_ray_tri, &t);
    return t.best;
}

/* Nearest hit with drawn node i (output index), or -1. */
static double node_hit(ray_ctx* r, size_t i)
{
    const tp_cut* c = r->c;
    const tp_cut_node* cn = &c->out[i];
    int s, nc, nr;
    tp_tree_node_locate(&c->g, cn->node, &s, &nc, &nr);
    if (c->out_tin[i])
        return tin_hit(r, i);
    int k = cn->level, vs = (1 << k) + 1, cells = 1 << k;
    tp_cut_vertices(c, i, r->v, (size_t)vs * vs);
    tp__cut_node_draw(c, i, &r->draw);
    double span = (double)((int64_t)1 << (c->n + s)), ox = nc * span, oy = nr * span;
    double t0 = 0, t1 = INFINITY;
    if (!tp__slab(r->x0, r->gx, ox, ox + span, &t0, &t1) ||
        !tp__slab(r->y0, r->gy, oy, oy + span, &t0, &t1))
        return -1;
    double best = -1;
    dda w;
    dda_init(&w, r->x0, r->y0, r->gx, r->gy, t0, t1, ox, oy, span / cells, cells, cells);
    double leave;
    for (; dda_valid(&w, &leave); dda_step(&w))
        best = cell_hit(r, vs, w.cx, w.cy, best);
    /* stitched sides: moved vertices slide the border strip's triangles along the side */
    for (int side = 0; side < 4; side++) {
        if (cn->nb[side] < 0 || cn->nb[side] >= k)
            continue;
        for (int j = 0; j < cells; j++) {
            int cx = side == TP_SIDE_LEFT ? 0 : side == TP_SIDE_RIGHT ? cells - 1 : j;
            int cy = side == TP_SIDE_TOP ? 0 : side == TP_SIDE_BOTTOM ? cells - 1 : j;
            best = cell_hit(r, vs, cx, cy, best);
        }
    }
    return best;
}

tp_status tp_cut_ray_cast(const tp_cut* c, const double origin[3], const double dir[3],
                          tp_ray_hit* out)
{
    assert(c && origin && dir && out);
    double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (!(len > 0 && isfinite(len)) || !isfinite(origin[0] + origin[1] + origin[2]))
        return TP_ERR_INVALID_ARG;
    tp_ray_hit res = {0};
    res.patch = -1;
    res.node = -1;
    ray_ctx r = {c, origin, {dir[0] / len, dir[1] / len, dir[2] / len}, 0, 0, 0, 0, NULL, {0}};
    const double* gt = c->gt;
    r.gx = r.d[0] / gt[1];
    r.gy = r.d[1] / gt[5];
    tp_tree_world_to_grid(c->t, origin[0], origin[1], &r.x0, &r.y0);
    tp_tree_info ti;
    tp_tree_get_info(c->t, &ti);
    double zlo = ti.min_height_m * c->zscale, zhi = ti.max_height_m * c->zscale;
    double t0 = 0, t1 = INFINITY;
    if (c->out_count == 0 || isnan(zlo) || !tp__slab(r.x0, r.gx, 0, c->g.width - 1, &t0, &t1) ||
        !tp__slab(r.y0, r.gy, 0, c->g.height - 1, &t0, &t1) ||
        !tp__slab(origin[2], r.d[2], fmin(zlo, zhi), fmax(zlo, zhi), &t0, &t1)) {
        *out = res;
        return TP_OK;
    }
    size_t vs = ((size_t)1 << c->n) + 1;
    r.v = tp__alloc(&c->alloc, vs * vs, sizeof *r.v);
    if (!r.v)
        return TP_ERR_OUT_OF_MEMORY;
    dda w;
    dda_init(&w, r.x0, r.y0, r.gx, r.gy, t0, t1, 0, 0, (double)(1 << c->n), c->g.cols, c->g.rows);
    double found = -1, leave;
    int last = -1;
    for (; found < 0 && dda_valid(&w, &leave); dda_step(&w)) {
        int o = tp__cut_drawn_at_leaf(c, w.cx, w.cy);
        if (o < 0 || o == last)
            continue;
        /* skip the node while the ray passes above or below its drawn box in this leaf */
        const tp_node_meta* m = tp_tree_meta(c->t, c->out[o].node);
        if (m->qmin > m->qmax)
            continue;
        double blo = m->qmin * c->step * c->zscale, bhi = m->qmax * c->step * c->zscale;
        double za = origin[2] + w.enter * r.d[2], zb = origin[2] + leave * r.d[2];
        double slack = 1e-6 * (1 + fabs(za) + fabs(zb));
        if (fmin(za, zb) > fmax(blo, bhi) + slack || fmax(za, zb) < fmin(blo, bhi) - slack)
            continue;
        last = o;
        found = node_hit(&r, (size_t)o);
        if (found >= 0)
            res.node = c->out[o].node;
    }
    tp__free(&c->alloc, r.v);
    if (found >= 0) {
        res.hit = 1;
        res.distance_m = found;
        res.position[0] = origin[0] + found * r.d[0];
        res.position[1] = origin[1] + found * r.d[1];
        res.position[2] = (origin[2] + found * r.d[2]) / c->zscale;
    }
    *out = res;
    return TP_OK;
}
