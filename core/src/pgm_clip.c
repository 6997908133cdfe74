/* pgm_clip.c - Persistent Grid Mapping over a store: the elevation clipmap's bookkeeping (the
 * windows' origins, the strips a move uncovers) and where a store holds a pyramid post
 * (tp_core.h; Livny, Kogan & El-Sana, seeds/001, section 4). The GPU side is the viewer's
 * app/render/pgm_clip.c. */
#include "internal.h"
#include "tp_pgm.h"

int tp_pgm_clip_origin(double centre, int posts, int w)
{
    assert(w >= 1);
    if (posts <= w || !(centre == centre))
        return 0;
    double o = floor(centre) - w / 2;
    double hi = (double)posts - w;
    o = o < 0 ? 0 : (o > hi ? hi : o);
    return (int)o;
}

static int put(tp_pgm_rect* out, int n, int x0, int y0, int x1, int y1)
{
    if (x1 <= x0 || y1 <= y0)
        return n;
    out[n] = (tp_pgm_rect){x0, y0, x1, y1};
    return n + 1;
}

int tp_pgm_clip_update(int w, int has_old, int old_x, int old_y, int new_x, int new_y,
                       tp_pgm_rect out[2])
{
    assert(w >= 1 && out);
    /* 64-bit differences: origins may be anywhere in int's range */
    long long dx = (long long)new_x - old_x, dy = (long long)new_y - old_y;
    long long ex = (long long)new_x + w, ey = (long long)new_y + w;
    if (!has_old || dx >= w || -dx >= w || dy >= w || -dy >= w) {
        out[0] = (tp_pgm_rect){new_x, new_y, (int)ex, (int)ey};
        return 1;
    }
    int n = 0;
    /* the columns gained, over the new window's whole height */
    if (dx > 0)
        n = put(out, n, old_x + w, new_y, (int)ex, (int)ey);
    else if (dx < 0)
        n = put(out, n, new_x, new_y, old_x, (int)ey);
    /* the rows gained, over the columns both windows hold */
    int kx0 = new_x > old_x ? new_x : old_x;
    int kx1 = (int)(dx > 0 ? (long long)old_x + w : ex);
    if (dy > 0)
        n = put(out, n, kx0, old_y + w, kx1, (int)ey);
    else if (dy < 0)
        n = put(out, n, kx0, new_y, kx1, old_y);
    return n;
}

int tp_pgm_clip_min_window(int width, int height)
{
    assert(width >= 1 && height >= 1);
    int w = width, h = height, levels = 1; /* tp_pgm_pyramid_build's levels */
    while (!(w <= 2 && h <= 2) && levels < TP_PGM_MAX_LEVELS) {
        w = w / 2 + 1;
        h = h / 2 + 1;
        levels++;
    }
    int side = w > h ? w : h, win = 16;
    while (win < side)
        win *= 2;
    return win;
}

int64_t tp_pgm_store_post(const tp_tree_geometry* g, int level, int x, int y, size_t* sample)
{
    assert(g && sample && x >= 0 && y >= 0 && x < g->src_width && y < g->src_height);
    int s = level < g->scales - 1 ? level : g->scales - 1;
    s = s < 0 ? 0 : s;
    /* nodes exist only as whole quadtree nodes: past the last one of scale s, a finer one */
    while (s > 0 && ((((unsigned)x | (unsigned)y) & ((1u << s) - 1)) ||
                     (long long)x > ((long long)g->node_cols[s] << (g->n + s)) ||
                     (long long)y > ((long long)g->node_rows[s] << (g->n + s))))
        s--;
    int n = g->n, shift = n + s;
    int c = x >> shift, r = y >> shift;
    c = c < g->node_cols[s] - 1 ? c : g->node_cols[s] - 1;
    r = r < g->node_rows[s] - 1 ? r : g->node_rows[s] - 1;
    int i = (x - (c << shift)) >> s, j = (y - (r << shift)) >> s;
    assert(i >= 0 && j >= 0 && i <= (1 << n) && j <= (1 << n));
    *sample = (size_t)j * (size_t)((1 << n) + 1) + (size_t)i;
    return tp_tree_node_id(g, s, c, r);
}
