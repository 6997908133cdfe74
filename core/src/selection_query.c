/* selection_query.c - heights of the surface a selection actually draws (stitching included),
 * and the camera collision built on them. Read-only: safe to call from several threads at once.
 */
#include "ray.h"
#include "selection_int.h"

#include <assert.h>
#include <string.h>

/* Height (steps) of the stitched triangle of cell (cx, cy) half h containing (x, y), if any. */
static int cell_height(const tp_terrain* t, int p, int k, const int nb[4], int cx, int cy,
                       double x, double y, double* z)
{
    static const int tri[2][3][2] = {{{0, 0}, {0, 1}, {1, 0}}, {{1, 0}, {0, 1}, {1, 1}}};
    for (int h = 0; h < 2; h++) {
        int32_t pos[3][2];
        double q[3];
        int ok = 1;
        for (int v = 0; v < 3; v++) {
            int32_t ox, oy;
            tp__vertex_position(t, p, k, NULL, cx + tri[h][v][0], cy + tri[h][v][1], &ox, &oy);
            ok &= tp__q(t, ox, oy) != INT32_MIN;
            tp__vertex_position(t, p, k, nb, cx + tri[h][v][0], cy + tri[h][v][1], &pos[v][0],
                                &pos[v][1]);
            q[v] = tp__q(t, pos[v][0], pos[v][1]);
        }
        double area = (double)(pos[1][0] - pos[0][0]) * (pos[2][1] - pos[0][1]) -
                      (double)(pos[1][1] - pos[0][1]) * (pos[2][0] - pos[0][0]);
        if (!ok || area == 0)
            continue;
        if (tp__tri_height(pos, q, area, x, y, z))
            return 1;
    }
    return 0;
}

/* Drawn height (steps) of patch (px, py) at (x, y) inside it, or NaN. */
static double patch_drawn_height(const tp_selection* s, int px, int py, double x, double y)
{
    const tp_terrain* t = s->t;
    int p = py * t->info.patch_cols + px, k = s->level[p], nb[4], last = 1 << k;
    tp_selection_neighbor_levels(s, p, nb);
    double cell = (double)(t->ps >> k);
    double lx = (x - px * t->ps) / cell, ly = (y - py * t->ps) / cell;
    int cx = (int)lx < last ? (int)lx : last - 1, cy = (int)ly < last ? (int)ly : last - 1;
    double z;
    /* On a cell's left or top edge the point also lies in the cell before it. */
    for (int dy = 0; dy <= (ly == cy && cy > 0); dy++)
        for (int dx = 0; dx <= (lx == cx && cx > 0); dx++)
            if (cell_height(t, p, k, nb, cx - dx, cy - dy, x, y, &z))
                return z;
    /* The point is in a stitched border strip where moved vertices shifted the triangles:
     * search the strips of the sides whose neighbour is coarser. */
    for (int side = 0; side < 4; side++) {
        if (nb[side] < 0 || nb[side] >= k)
            continue;
        for (int i = 0; i < last; i++) {
            int ccx = side == TP_SIDE_LEFT ? 0 : side == TP_SIDE_RIGHT ? last - 1 : i;
            int ccy = side == TP_SIDE_TOP ? 0 : side == TP_SIDE_BOTTOM ? last - 1 : i;
            if (cell_height(t, p, k, nb, ccx, ccy, x, y, &z))
                return z;
        }
    }
    return NAN;
}

double tp_selection_drawn_height_at(const tp_selection* s, double x, double y)
{
    assert(s);
    const tp_terrain* t = s->t;
    if (!(x >= 0 && y >= 0 && x <= t->w - 1 && y <= t->h - 1))
        return NAN;
    int pc = t->info.patch_cols, pr = t->info.patch_rows;
    int px = (int)x >> t->n, py = (int)y >> t->n;
    px = px < pc ? px : pc - 1;
    py = py < pr ? py : pr - 1;
    /* On a patch border the point belongs to the patch before it too. */
    int bx = px > 0 && x == px * t->ps, by = py > 0 && y == py * t->ps;
    for (int dy = 0; dy <= by; dy++)
        for (int dx = 0; dx <= bx; dx++) {
            double z = patch_drawn_height(s, px - dx, py - dy, x, y);
            if (!isnan(z))
                return z * t->step;
        }
    return NAN;
}

int tp_selection_keep_above(const tp_selection* s, double position[3], double clearance_m)
{
    assert(s && position && isfinite(clearance_m) && clearance_m >= 0);
    double x, y;
    tp_terrain_world_to_grid(s->t, position[0], position[1], &x, &y);
    double a = tp_terrain_height_at(s->t, x, y), b = tp_selection_drawn_height_at(s, x, y);
    return tp__keep_above(position, a, b, s->zscale, clearance_m);
}

/* ---------------------------------------------------------------------------------------------
 * Ray casting against the drawn surface: walk the patches the ray's ground track crosses, in
 * order along the ray (a 2D DDA over the patch grid, as Amanatides & Woo walk voxels), skip
 * those whose drawn box the ray passes above or below, and intersect the drawn triangles of
 * the others (Moller & Trumbore). A patch's triangles stay inside its own square, even after
 * crack removal, so the first patch with a hit holds the nearest hit.
 */


/* Nearest hit with patch p's drawn triangles (relative to origin o), or -1. */
static double ray_patch(const tp_selection* s, int p, const double o[3], const double d[3],
                        tp_vertex* vbuf, uint32_t* tbuf, size_t vcap, size_t tcap)
{
    const tp_terrain* t = s->t;
    int k = s->level[p], nb[4];
    tp_selection_neighbor_levels(s, p, nb);
    tp_patch_vertices(t, p, k, nb, vbuf, vcap);
    size_t nt = tp_patch_triangles(vbuf, k, tbuf, tcap);
    double best = -1;
    for (size_t i = 0; i < nt; i++) {
        double w[3][3];
        for (int j = 0; j < 3; j++) {
            const tp_vertex* v = &vbuf[tbuf[3 * i + j]];
            tp_terrain_grid_to_world(t, v->x, v->y, &w[j][0], &w[j][1]);
            w[j][0] -= o[0];
            w[j][1] -= o[1];
            w[j][2] = (double)v->z_m * s->zscale - o[2];
        }
        double h = tp__ray_triangle(d, w[0], w[1], w[2]);
        if (h >= 0 && (best < 0 || h < best))
            best = h;
    }
    return best;
}

tp_status tp_selection_ray_cast(const tp_selection* s, const double origin[3],
                                const double dir[3], tp_ray_hit* out)
{
    assert(s && origin && dir && out);
    const tp_terrain* t = s->t;
    double len = sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
    if (!(len > 0 && isfinite(len)) || !isfinite(origin[0] + origin[1] + origin[2]))
        return TP_ERR_INVALID_ARG;
    double d[3] = {dir[0] / len, dir[1] / len, dir[2] / len};
    const double* gt = t->info.geotransform;
    double x0, y0, gx = d[0] / gt[1], gy = d[1] / gt[5];
    tp_terrain_world_to_grid(t, origin[0], origin[1], &x0, &y0);
    double zlo = t->info.min_height_m * s->zscale, zhi = t->info.max_height_m * s->zscale;
    double t0 = 0, t1 = INFINITY;
    tp_ray_hit res = {0};
    res.patch = -1;
    res.node = -1;
    if (!tp__slab(x0, gx, 0, t->w - 1, &t0, &t1) || !tp__slab(y0, gy, 0, t->h - 1, &t0, &t1) ||
        !tp__slab(origin[2], d[2], fmin(zlo, zhi), fmax(zlo, zhi), &t0, &t1)) {
        *out = res;
        return TP_OK;
    }

    size_t v = ((size_t)1 << t->n) + 1, vcap = v * v, tcap = 2 * (v - 1) * (v - 1);
    tp_vertex* vbuf = tp__alloc(&t->alloc, vcap, sizeof *vbuf);
    uint32_t* tbuf = tp__alloc(&t->alloc, 3 * tcap, sizeof *tbuf);
    if (!vbuf || !tbuf) {
        tp__free(&t->alloc, vbuf);
        tp__free(&t->alloc, tbuf);
        return TP_ERR_OUT_OF_MEMORY;
    }
    int pc = t->info.patch_cols, pr = t->info.patch_rows, ps = t->ps;
    double xs = x0 + t0 * gx, ys = y0 + t0 * gy;
    int px = (int)floor(xs / ps), py = (int)floor(ys / ps);
    px = px < 0 ? 0 : px >= pc ? pc - 1 : px;
    py = py < 0 ? 0 : py >= pr ? pr - 1 : py;
    int sx = gx > 0 ? 1 : gx < 0 ? -1 : 0, sy = gy > 0 ? 1 : gy < 0 ? -1 : 0;
    /* t at which the ray leaves the current column / row of patches */
    double tx = sx ? ((px + (sx > 0)) * (double)ps - x0) / gx : INFINITY;
    double ty = sy ? ((py + (sy > 0)) * (double)ps - y0) / gy : INFINITY;
    double enter = t0, found = -1;
    while (found < 0 && enter <= t1 && px >= 0 && py >= 0 && px < pc && py < pr) {
        double leave = fmin(fmin(tx, ty), t1);
        int p = py * pc + px;
        tp_patch_info pi;
        tp__drawn_box(s, p, &pi);
        double za = origin[2] + enter * d[2], zb = origin[2] + leave * d[2];
        double slack = 1e-6 * (1 + fabs(za) + fabs(zb));
        if (fmin(za, zb) <= pi.aabb_max[2] + slack && fmax(za, zb) >= pi.aabb_min[2] - slack)
            found = ray_patch(s, p, origin, d, vbuf, tbuf, vcap, tcap);
        if (found >= 0) {
            res.patch = p;
            break;
        }
        if (tx < ty) {
            px += sx;
            enter = tx;
            tx += ps / fabs(gx);
        } else {
            py += sy;
            enter = ty;
            ty += ps / fabs(gy);
        }
    }
    tp__free(&t->alloc, vbuf);
    tp__free(&t->alloc, tbuf);
    if (found >= 0) {
        res.hit = 1;
        res.distance_m = found;
        res.position[0] = origin[0] + found * d[0];
        res.position[1] = origin[1] + found * d[1];
        res.position[2] = (origin[2] + found * d[2]) / s->zscale;
    }
    *out = res; /* only now: a failed cast leaves *out alone */
    return TP_OK;
}
