/* query.c - heights of the surface a selection actually draws (stitching included), and the
 * camera collision built on them. Read-only: safe to call from several threads at once.
 */
#include "internal.h"

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
        double w[3];
        for (int v = 0; v < 3; v++) {
            const int32_t* a = pos[(v + 1) % 3];
            const int32_t* b = pos[(v + 2) % 3];
            w[v] = ((b[0] - a[0]) * (y - a[1]) - (b[1] - a[1]) * (x - a[0])) / area;
        }
        const double eps = 1e-9;
        if (w[0] >= -eps && w[1] >= -eps && w[2] >= -eps) {
            *z = w[0] * q[0] + w[1] * q[1] + w[2] * q[2];
            return 1;
        }
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
    double x, y;
    tp_terrain_world_to_grid(s->t, position[0], position[1], &x, &y);
    double a = tp_terrain_height_at(s->t, x, y), b = tp_selection_drawn_height_at(s, x, y);
    double ground = isnan(a) ? b : isnan(b) ? a : (a > b ? a : b);
    if (isnan(ground) || position[2] >= ground + clearance_m)
        return 0;
    position[2] = ground + clearance_m;
    return 1;
}
