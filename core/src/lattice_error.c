/* lattice_error.c - error tables over one lattice of (2^n+1)^2 samples, for tp_terrain's patches
 * (patch_error.c) and for the nodes of a tree (node_meta.c).
 *
 * delta_k (Brodersen section 3): the largest vertical distance between a sample and the level-k
 * triangulation (same split as the strips). Stitching: crack removal moves border vertices
 * (lattice.c), so the border triangles belong to neither level's triangulation; for every side
 * and every neighbour level kn < n, eps[side][kn] is the largest error of any triangle with a
 * vertex moved by that side, over every level k > kn. With nearest-vertex snapping toward the
 * corners, a triangle with vertices moved by two sides collapses for k >= 2 (the vertices next
 * to a corner both snap onto it), so one side at a time is exact there. At k = 1 a triangle's
 * vertices can be moved by the two sides of its cell's corner (the cell's other vertices are a
 * corner and the centre, which never move): a triangle's error depends only on the moves of its
 * own vertices, so one more measure per cell, with both of its sides moved, covers every
 * combination of moved sides (measuring all 16 combinations over the whole lattice gave the
 * same values, 15 times slower).
 *
 * A leaf of a tree (and a patch) holds every full-resolution sample of its area, so measuring
 * at its own samples is exact. A node of scale s >= 1 holds every 2^s-th sample only; its
 * bounds against the full resolution come from nested decimation (see tp_node_meta_compute).
 */
#include "lattice.h"

#include <stdlib.h>
#include <string.h>
#include <threads.h>

static inline int32_t lq(const int32_t* q, int side, int i, int j)
{
    return q[(size_t)j * (size_t)side + (size_t)i];
}

double tp__lattice_level_error(int n, const int32_t* q, const uint16_t* mask, int k)
{
    assert(q && n >= 0 && n <= TP_MAX_N && k >= 0 && k <= n);
    if (k == n)
        return 0; /* every sample is a vertex of its own level */
    int side = (1 << n) + 1;
    int s = 1 << (n - k), cells = 1 << k;
    /* In integers scaled by s: the plane at (i, j) of a cell is z = q00 + (i dx + j dy) / s, so
     * s |z - v| = |s q00 + i dx + j dy - s v| exactly (|q| < 2^31, s <= 2^8: fits 64 bits), and
     * dividing the largest by s (a power of two) gives the same double as measuring each in
     * doubles would. */
    int64_t mx = 0;
    for (int cy = 0; cy < cells; cy++)
        for (int cx = 0; cx < cells; cx++) {
            int xa = cx * s, ya = cy * s;
            int32_t q00 = lq(q, side, xa, ya), q10 = lq(q, side, xa + s, ya);
            int32_t q01 = lq(q, side, xa, ya + s), q11 = lq(q, side, xa + s, ya + s);
            int lower, upper;
            if (mask) /* a whole cell or nothing; then every sample in it is drawn */
                lower = upper = tp_node_mask_all(mask, n, xa, ya, xa + s, ya + s);
            else
                lower = q00 != INT32_MIN && q10 != INT32_MIN && q01 != INT32_MIN,
                upper = q11 != INT32_MIN && q10 != INT32_MIN && q01 != INT32_MIN;
            if (!lower && !upper)
                continue;
            /* lower: i + j <= s, z s = q00 s + i (q10 - q00) + j (q01 - q00); upper (the rest,
             * or all of i + j >= s when lower is not drawn): q11 s + (s - i)(q01 - q11) +
             * (s - j)(q10 - q11) */
            const int64_t ldx = (int64_t)q10 - q00, ldy = (int64_t)q01 - q00;
            const int64_t udx = (int64_t)q11 - q01, udy = (int64_t)q11 - q10;
            const int64_t l0 = (int64_t)q00 * s, u0 = (int64_t)q11 * s - (int64_t)s * udx -
                                                      (int64_t)s * udy;
            for (int j = 0; j <= s; j++) {
                const int32_t* row = q + (size_t)(ya + j) * (size_t)side + xa;
                /* lower triangle: i in 0 .. s - j; upper: the rest (all of s - j .. s when the
                 * lower one is not drawn) */
                int split = lower ? s - j : s - j - 1; /* last i of the lower part */
                int64_t zs = l0 + j * ldy;
                for (int i = 0; lower && i <= split; i++, zs += ldx) {
                    int32_t v = row[i];
                    int64_t e = zs - (int64_t)v * s;
                    e = e < 0 ? -e : e;
                    e = v == INT32_MIN ? 0 : e;
                    mx = e > mx ? e : mx;
                }
                zs = u0 + (int64_t)(split + 1) * udx + j * udy;
                for (int i = split + 1; upper && i <= s; i++, zs += udx) {
                    int32_t v = row[i];
                    int64_t e = zs - (int64_t)v * s;
                    e = e < 0 ? -e : e;
                    e = v == INT32_MIN ? 0 : e;
                    mx = e > mx ? e : mx;
                }
            }
        }
    return (double)mx / s;
}

/* Vertex (i, j) of level k lies on which side (-1 for none or a corner)? */
static int side_of(int i, int j, int last)
{
    int corner = (i == 0 || i == last) && (j == 0 || j == last);
    if (corner)
        return -1;
    if (j == 0)
        return TP_SIDE_TOP;
    if (i == last)
        return TP_SIDE_RIGHT;
    if (j == last)
        return TP_SIDE_BOTTOM;
    if (i == 0)
        return TP_SIDE_LEFT;
    return -1;
}

static int64_t edge(const int32_t a[2], const int32_t b[2], int64_t x, int64_t y)
{
    return ((int64_t)b[0] - a[0]) * (y - a[1]) - ((int64_t)b[1] - a[1]) * (x - a[0]);
}

static int64_t floor_div(int64_t a, int64_t b) /* b > 0 */
{
    int64_t d = a / b;
    return d - (a % b != 0 && a < 0);
}

/* Narrows [*x0, *x1] to the x where sign * (w + s (x - xs)) >= 0 (w at xs, s per step in x). */
static void clip_span(int64_t w, int64_t s, int64_t xs, int64_t* x0, int64_t* x1)
{
    if (s == 0) {
        if (w < 0)
            *x1 = *x0 - 1; /* empty */
        return;
    }
    if (s > 0) { /* x >= xs + ceil(-w / s) */
        int64_t lo = xs - floor_div(w, s);
        *x0 = lo > *x0 ? lo : *x0;
    } else { /* x <= xs + floor(w / -s) */
        int64_t hi = xs + floor_div(w, -s);
        *x1 = hi < *x1 ? hi : *x1;
    }
}

/* The largest |T - q| over the lattice samples a triangle T covers (closed), the samples
 * tp__raster_triangle visits, a span per row. Exact (tp__raster_triangle's doubles round by
 * 1/area: up to ~1e-12 apart, below the 1e-6 the units add). */
static double raster_error(const int32_t* q, int side, const int32_t pos[3][2], const int64_t z[3])
{
    const int32_t *a = pos[0], *b = pos[1], *c = pos[2];
    int64_t area = edge(a, b, c[0], c[1]);
    if (area == 0)
        return 0;
    int32_t bx[4];
    tp__tri_box(pos, bx);
    int32_t x0 = bx[0], y0 = bx[1], x1 = bx[2], y1 = bx[3];
    /* In integers: the plane at a sample is N / area with N = wa za + wb zb + wc zc (|w| <=
     * 2^17, |z| < 2^31: N fits 64 bits), so |T - v| = |N - v area| / |area|, exactly. */
    int64_t sa = -((int64_t)c[1] - b[1]), sb = -((int64_t)a[1] - c[1]), sc = -((int64_t)b[1] - a[1]);
    int64_t sign = area > 0 ? 1 : -1, abs_area = area * sign, mx = 0;
    const int64_t dn = (sa * z[0] + sb * z[1] + sc * z[2]) * sign;
    for (int32_t y = y0; y <= y1; y++) {
        int64_t wa = edge(b, c, x0, y), wb = edge(c, a, x0, y), wc = edge(a, b, x0, y);
        const int32_t* row = q + (size_t)y * (size_t)side;
        if (x1 - x0 < 16) { /* narrow: test each sample (cheaper than the spans' divisions) */
            int64_t nn = (wa * z[0] + wb * z[1] + wc * z[2]) * sign;
            for (int32_t x = x0; x <= x1; x++, wa += sa, wb += sb, wc += sc, nn += dn) {
                int32_t v = row[x];
                int64_t e = nn - (int64_t)v * abs_area;
                e = e < 0 ? -e : e;
                int in = (wa * sign >= 0) & (wb * sign >= 0) & (wc * sign >= 0) &
                         (v != INT32_MIN);
                e = in ? e : 0;
                mx = e > mx ? e : mx;
            }
            continue;
        }
        /* the samples inside (every weight of the area's sign) form one span of the row */
        int64_t xa = x0, xb = x1;
        clip_span(wa * sign, sa * sign, x0, &xa, &xb);
        clip_span(wb * sign, sb * sign, x0, &xa, &xb);
        clip_span(wc * sign, sc * sign, x0, &xa, &xb);
        if (xa > xb)
            continue;
        wa += sa * (xa - x0), wb += sb * (xa - x0), wc += sc * (xa - x0);
        int64_t nn = (wa * z[0] + wb * z[1] + wc * z[2]) * sign; /* N |area| / area */
        for (int64_t x = xa; x <= xb; x++, nn += dn) {
            int32_t v = row[x];
            int64_t e = nn - (int64_t)v * abs_area;
            e = e < 0 ? -e : e;
            e = v == INT32_MIN ? 0 : e;
            mx = e > mx ? e : mx;
        }
    }
    return (double)mx / (double)abs_area;
}

/* The lattice cells of a triangle's bounding box that no edge of it separates from it (the
 * cells its cell bound measures): an edge separates a cell when all 4 corners are strictly
 * outside it, i.e. when its function (linear) is negative at the corner where it is largest: one
 * corner per edge. */
typedef struct kept_cells {
    const int32_t (*pos)[2];
    int64_t sign;     /* of the triangle's area */
    int dx[3], dy[3]; /* each edge's corner */
} kept_cells;

static void kept_init(kept_cells* k, const int32_t pos[3][2], int64_t sign)
{
    k->pos = pos;
    k->sign = sign;
    for (int e = 0; e < 3; e++) {
        const int32_t* a = pos[(e + 1) % 3];
        const int32_t* b = pos[(e + 2) % 3];
        k->dx[e] = -((int64_t)b[1] - a[1]) * sign > 0;
        k->dy[e] = ((int64_t)b[0] - a[0]) * sign > 0;
    }
}

/* The kept cells *lo .. *hi of cell row py among columns x0 .. x1 - 1 (*lo > *hi: none; none
 * for py == y1, the box's last row of points). */
static void kept_row(const kept_cells* k, int32_t x0, int32_t x1, int32_t py, int32_t y1,
                     int32_t* lo_out, int32_t* hi_out)
{
    int32_t lo = 1, hi = 0;
    for (int32_t cx = x0; py < y1 && cx < x1; cx++) {
        int separated = 0;
        for (int e = 0; e < 3 && !separated; e++)
            separated = edge(k->pos[(e + 1) % 3], k->pos[(e + 2) % 3], cx + k->dx[e],
                             py + k->dy[e]) * k->sign < 0;
        if (separated)
            continue;
        if (lo > hi)
            lo = cx;
        hi = cx;
    }
    *lo_out = lo;
    *hi_out = hi;
}

/* The cell bound of a node of scale >= 1 (cells = 1 in tp__lattice_eps).
 *
 * A stitched triangle T is not a union of the fine triangles of the lattice surface S_n (its
 * moved vertex makes edges that cross lattice cells), so the lattice samples inside T do not
 * bound its error. Every point x of T lies in some lattice cell C that T touches (closed sets),
 * in one of C's two triangles t, where S_n is linear. T's plane extended over t is linear too,
 * so T - S_n is linear on t and |T(x) - S_n(x)| <= max over t's vertices of |T - S_n|, which
 * are corners of C, where S_n is the sample itself. So the maximum over the corners of every
 * touched cell of |T_extended(p) - q(p)| bounds |T - S_n| over all of T (including where T's
 * edges cross cell edges); the caller adds the carry |S_n - f| of the children. Cells are
 * found in T's bounding box and kept when no edge of T separates them (exact integer test). */
static double cell_bound(const int32_t* q, int side, const int32_t pos[3][2], const int64_t z[3])
{
    int64_t area = edge(pos[0], pos[1], pos[2][0], pos[2][1]);
    if (area == 0)
        return 0; /* collapsed: not drawn */
    int64_t sign = area > 0 ? 1 : -1;
    int32_t bx[4];
    tp__tri_box(pos, bx);
    int32_t x0 = bx[0], y0 = bx[1], x1 = bx[2], y1 = bx[3];
    kept_cells kc;
    kept_init(&kc, pos, sign);
    /* Kept cells of each cell row: one interval (T and the row's strip are convex); the
     * corners of kept cells of point row py are those of cell rows py - 1 and py. Each corner
     * is measured once (the same value as once per cell it belongs to). */
    int64_t abs_area = area * sign, mx = 0; /* in integers as raster_error */
    int32_t prev_lo = 1, prev_hi = 0; /* kept cells of the cell row above, empty */
    for (int32_t py = y0; py <= y1; py++) {
        int32_t lo, hi; /* kept cells of cell row py (none for py == y1) */
        kept_row(&kc, x0, x1, py, y1, &lo, &hi);
        /* points: corners of cells prev_lo..prev_hi and lo..hi, i.e. x in [l, h + 1] */
        for (int pass = 0; pass < 2; pass++) {
            int32_t l = pass ? lo : prev_lo, h = pass ? hi : prev_hi;
            if (l > h)
                continue;
            if (pass == 1 && prev_lo <= prev_hi) { /* skip what pass 0 measured */
                if (l >= prev_lo && h <= prev_hi)
                    continue;
            }
            for (int32_t px = l; px <= h + 1; px++) {
                if (pass == 1 && prev_lo <= prev_hi && px >= prev_lo && px <= prev_hi + 1)
                    continue;
                int32_t v = lq(q, side, px, py);
                if (v == INT32_MIN)
                    continue;
                int64_t nn = (edge(pos[1], pos[2], px, py) * z[0] +
                              edge(pos[2], pos[0], px, py) * z[1] +
                              edge(pos[0], pos[1], px, py) * z[2]) * sign;
                int64_t e = nn - (int64_t)v * abs_area;
                e = e < 0 ? -e : e;
                mx = e > mx ? e : mx;
            }
        }
        prev_lo = lo, prev_hi = hi;
    }
    return (double)mx / (double)abs_area;
}

/* Measures the stitched triangles of cells [cx0, cx1) x [cy0, cy1) of the level-k
 * triangulation with neighbour levels nb; each triangle's error (steps) is folded into out[side]
 * for every side that moved one of its vertices. */
/* Whether a triangle with unmoved lattice positions orig and moved ones pos, of a level-k
 * triangulation, is drawn (see tp_node_mask_from_q): with a mask and not a leaf's level n, when
 * every lattice cell of pos's bounding box is set; else when every vertex is drawn. */
static int tri_drawn(int n, const int32_t* q, const uint16_t* mask, int vertex_rule,
                     const int32_t orig[3][2], const int32_t pos[3][2])
{
    int side = (1 << n) + 1;
    if (!mask || vertex_rule) {
        for (int v = 0; v < 3; v++)
            if (lq(q, side, orig[v][0], orig[v][1]) == INT32_MIN ||
                lq(q, side, pos[v][0], pos[v][1]) == INT32_MIN)
                return 0;
        return 1;
    }
    int32_t bx[4];
    tp__tri_box(pos, bx);
    int32_t x0 = bx[0], y0 = bx[1], x1 = bx[2], y1 = bx[3];
    return tp_node_mask_all(mask, n, x0, y0, x1, y1);
}

/* Triangle h of level-k cell (cx, cy) (the cell's two triangles in strip winding) with
 * neighbour levels nb: its lattice positions unmoved (orig) and moved (pos), stride lattice
 * samples per level-k vertex; returns the sides that moved one of its vertices (bit side). */
static int stitched_triangle(int k, const int nb[4], int stride, int cx, int cy, int h,
                             int32_t orig[3][2], int32_t pos[3][2])
{
    static const int tri[2][3][2] = {{{0, 0}, {0, 1}, {1, 0}}, {{1, 0}, {0, 1}, {1, 1}}};
    int last = 1 << k, sides = 0;
    for (int v = 0; v < 3; v++) {
        int i = cx + tri[h][v][0], j = cy + tri[h][v][1], mi, mj;
        if (tp__lattice_vertex(k, nb, i, j, &mi, &mj))
            sides |= 1 << side_of(i, j, last);
        orig[v][0] = i * stride, orig[v][1] = j * stride;
        pos[v][0] = mi * stride, pos[v][1] = mj * stride;
    }
    return sides;
}

static void stitched_error(int n, const int32_t* q, const uint16_t* mask, int cells_mode, int k,
                           const int nb[4], int cx0, int cx1, int cy0, int cy1, double out[4])
{
    int stride = 1 << (n - k), side = (1 << n) + 1;
    for (int cy = cy0; cy < cy1; cy++)
        for (int cx = cx0; cx < cx1; cx++) {
            for (int h = 0; h < 2; h++) {
                int32_t orig[3][2], pos[3][2];
                int64_t z[3];
                int sides = stitched_triangle(k, nb, stride, cx, cy, h, orig, pos);
                for (int v = 0; v < 3; v++)
                    z[v] = lq(q, side, pos[v][0], pos[v][1]);
                if (!sides || !tri_drawn(n, q, mask, !cells_mode && k == n, orig, pos))
                    continue;
                double e = cells_mode ? cell_bound(q, side, pos, z) : raster_error(q, side, pos, z);
                for (int s = 0; s < 4; s++)
                    if (sides >> s & 1)
                        out[s] = e > out[s] ? e : out[s];
            }
        }
}

/* The measures of the eps tables, in order: for k = 1..n, kn < k and each side s, the strip of
 * cells along s (only there are vertices moved) with s's neighbour at kn; at k = 1 also each
 * corner cell with both of its sides' neighbours at 0 (s = -1; see the top of this file). */
typedef void (*measure_fn)(void* ctx, int k, int kn, int s, const int nb[4], int cx0, int cx1,
                           int cy0, int cy1);

static void each_measure(int n, measure_fn fn, void* ctx)
{
    for (int k = 1; k <= n; k++) {
        int cn = 1 << k;
        for (int kn = 0; kn < k; kn++)
            for (int s = 0; s < 4; s++) {
                int nb[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
                nb[s] = kn;
                fn(ctx, k, kn, s, nb, s == TP_SIDE_RIGHT ? cn - 1 : 0, s == TP_SIDE_LEFT ? 1 : cn,
                   s == TP_SIDE_BOTTOM ? cn - 1 : 0, s == TP_SIDE_TOP ? 1 : cn);
            }
        if (k == 1) /* both sides of each cell's corner moved */
            for (int c = 0; c < 4; c++) {
                int cx = c & 1, cy = c >> 1;
                int nb[4] = {TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR, TP_NO_NEIGHBOR};
                nb[cy ? TP_SIDE_BOTTOM : TP_SIDE_TOP] = 0;
                nb[cx ? TP_SIDE_RIGHT : TP_SIDE_LEFT] = 0;
                fn(ctx, 1, 0, -1, nb, cx, cx + 1, cy, cy + 1);
            }
    }
}

typedef struct direct_ctx {
    int n, cells;
    const int32_t* q;
    const uint16_t* mask;
    double (*eps)[TP_MAX_N];
} direct_ctx;

/* One measure, folded into eps[s][kn] (a corner's, s = -1: into eps[side][0] of every side). */
static void direct_measure(void* ctx, int k, int kn, int s, const int nb[4], int cx0, int cx1,
                           int cy0, int cy1)
{
    direct_ctx* d = ctx;
    double e[4] = {0, 0, 0, 0};
    stitched_error(d->n, d->q, d->mask, d->cells, k, nb, cx0, cx1, cy0, cy1, e);
    for (int side = 0; side < 4; side++)
        if (s < 0 || side == s)
            d->eps[side][kn] = e[side] > d->eps[side][kn] ? e[side] : d->eps[side][kn];
}

static void lattice_eps_direct(int n, const int32_t* q, const uint16_t* mask, int cells,
                               double eps[4][TP_MAX_N])
{
    memset(eps, 0, sizeof(double) * 4 * TP_MAX_N);
    direct_ctx d = {n, cells, q, mask, eps};
    each_measure(n, direct_measure, &d);
}

/* ---------------------------------------------------------------------------------------------
 * The same measure from a plan: which triangles the stitched triangulations have, and which
 * lattice positions each one's error is taken at, depend only on n (and the mode), not on the
 * heights. So they are worked out once per (n, mode) (lattice_vertex, areas, the spans of each
 * row, the cell bound's kept corners) and each node only runs the spans: the same positions and
 * the same integers as lattice_eps_direct, without its per-triangle setup.
 */
typedef struct {
    int16_t y, xa, xb; /* lattice positions x = xa .. xb of row y */
    int32_t wa, wb, wc; /* edge weights at (xa, y) */
} plan_span;

typedef struct {
    int32_t orig[3], pos[3]; /* lattice indices of the unmoved and the moved vertices */
    int32_t sa, sb, sc;      /* weight steps per x */
    int32_t abs_area;
    int8_t sign;
    uint8_t kn, sides;       /* folded into eps[side][kn] for each side bit */
    uint8_t vertex_rule;     /* a leaf's level n: drawn when its vertices are */
    int16_t box[4];          /* x0, y0, x1, y1: the lattice cells of pos's bounding box */
    uint32_t span0, span_count;
} plan_tri;

typedef struct {
    plan_tri* tris;
    plan_span* spans;
    size_t tri_count, span_count, tri_cap, span_cap;
    int failed;
} eps_plan;

/* Room for one more of the count elements of elem bytes in *arr (*cap of them, doubling from
 * first); 0, p->failed set, without memory. */
static int plan_grow(eps_plan* p, void** arr, size_t* cap, size_t count, size_t first, size_t elem)
{
    if (count != *cap)
        return 1;
    size_t ncap = *cap ? 2 * *cap : first;
    void* grown = realloc(*arr, ncap * elem);
    if (!grown) {
        p->failed = 1;
        return 0;
    }
    *arr = grown;
    *cap = ncap;
    return 1;
}

static void plan_add_span(eps_plan* p, int y, int64_t xa, int64_t xb, const int32_t pos[3][2])
{
    if (xa > xb || p->failed)
        return;
    if (!plan_grow(p, (void**)&p->spans, &p->span_cap, p->span_count, 4096, sizeof *p->spans))
        return;
    plan_span* sp = &p->spans[p->span_count++];
    sp->y = (int16_t)y, sp->xa = (int16_t)xa, sp->xb = (int16_t)xb;
    sp->wa = (int32_t)edge(pos[1], pos[2], xa, y);
    sp->wb = (int32_t)edge(pos[2], pos[0], xa, y);
    sp->wc = (int32_t)edge(pos[0], pos[1], xa, y);
}

/* One triangle (moved positions pos, unmoved orig) and the positions its error is taken at. */
static void plan_add_tri(eps_plan* p, int n, int k, int cells, const int32_t orig[3][2],
                         const int32_t pos[3][2], int kn, int sides)
{
    int side = (1 << n) + 1;
    int64_t area = edge(pos[0], pos[1], pos[2][0], pos[2][1]);
    if (area == 0 || p->failed)
        return; /* collapsed: measured as 0 */
    if (!plan_grow(p, (void**)&p->tris, &p->tri_cap, p->tri_count, 1024, sizeof *p->tris))
        return;
    plan_tri* t = &p->tris[p->tri_count];
    int64_t sign = area > 0 ? 1 : -1;
    for (int v = 0; v < 3; v++) {
        t->orig[v] = orig[v][1] * side + orig[v][0];
        t->pos[v] = pos[v][1] * side + pos[v][0];
    }
    const int32_t *a = pos[0], *b = pos[1], *c = pos[2];
    t->sa = -(c[1] - b[1]), t->sb = -(a[1] - c[1]), t->sc = -(b[1] - a[1]);
    t->abs_area = (int32_t)(area * sign);
    t->sign = (int8_t)sign;
    t->kn = (uint8_t)kn, t->sides = (uint8_t)sides;
    t->span0 = (uint32_t)p->span_count;
    int32_t bx[4];
    tp__tri_box(pos, bx);
    int32_t x0 = bx[0], y0 = bx[1], x1 = bx[2], y1 = bx[3];
    t->vertex_rule = (uint8_t)(!cells && k == n);
    t->box[0] = (int16_t)x0, t->box[1] = (int16_t)y0, t->box[2] = (int16_t)x1,
    t->box[3] = (int16_t)y1;
    if (!cells) { /* the samples inside, as raster_error */
        for (int32_t y = y0; y <= y1; y++) {
            int64_t xa = x0, xb = x1;
            clip_span(edge(b, c, x0, y) * sign, t->sa * sign, x0, &xa, &xb);
            clip_span(edge(c, a, x0, y) * sign, t->sb * sign, x0, &xa, &xb);
            clip_span(edge(a, b, x0, y) * sign, t->sc * sign, x0, &xa, &xb);
            plan_add_span(p, y, xa, xb, pos);
        }
    } else { /* the corners of the kept cells, each once, as cell_bound */
        kept_cells kc;
        kept_init(&kc, pos, sign);
        int32_t prev_lo = 1, prev_hi = 0;
        for (int32_t py = y0; py <= y1; py++) {
            int32_t lo, hi;
            kept_row(&kc, x0, x1, py, y1, &lo, &hi);
            int have_prev = prev_lo <= prev_hi;
            if (have_prev)
                plan_add_span(p, py, prev_lo, prev_hi + 1, pos);
            if (lo <= hi) {
                if (!have_prev) {
                    plan_add_span(p, py, lo, hi + 1, pos);
                } else { /* what [lo, hi + 1] adds to [prev_lo, prev_hi + 1] */
                    if (lo < prev_lo)
                        plan_add_span(p, py, lo, (hi + 1 < prev_lo - 1 ? hi + 1 : prev_lo - 1), pos);
                    if (hi + 1 > prev_hi + 1)
                        plan_add_span(p, py, (lo > prev_hi + 2 ? lo : prev_hi + 2), hi + 1, pos);
                }
            }
            prev_lo = lo, prev_hi = hi;
        }
    }
    t->span_count = (uint32_t)(p->span_count - t->span0);
    if (!p->failed)
        p->tri_count++;
}

/* The triangles of stitched_error's loops in lattice_eps_direct's order. */
static void plan_cells(eps_plan* p, int n, int cells, int k, int kn, const int nb[4], int cx0,
                       int cx1, int cy0, int cy1)
{
    int stride = 1 << (n - k);
    for (int cy = cy0; cy < cy1; cy++)
        for (int cx = cx0; cx < cx1; cx++)
            for (int h = 0; h < 2; h++) {
                int32_t orig[3][2], pos[3][2];
                int sides = stitched_triangle(k, nb, stride, cx, cy, h, orig, pos);
                if (sides)
                    plan_add_tri(p, n, k, cells, orig, pos, kn, sides);
            }
}

typedef struct plan_ctx {
    eps_plan* p;
    int n, cells;
} plan_ctx;

static void plan_measure(void* ctx, int k, int kn, int s, const int nb[4], int cx0, int cx1,
                         int cy0, int cy1)
{
    plan_ctx* c = ctx;
    (void)s; /* each triangle carries the sides that moved it */
    plan_cells(c->p, c->n, c->cells, k, kn, nb, cx0, cx1, cy0, cy1);
}

static eps_plan* plan_build(int n, int cells)
{
    eps_plan* p = calloc(1, sizeof *p);
    if (!p)
        return NULL;
    plan_ctx c = {p, n, cells};
    each_measure(n, plan_measure, &c);
    if (p->failed) {
        free(p->tris), free(p->spans), free(p);
        return NULL;
    }
    return p;
}

/* One plan per (n, mode), made once (call_once: nodes are measured on many threads) and kept
 * for the process (n = 8: a few MB). NULL (out of memory): the direct measure is used. */
static eps_plan* g_plans[TP_MAX_N + 1][2];
#define PLAN_ONCE(N, C)                                                                            \
    static once_flag once_##N##_##C = ONCE_FLAG_INIT;                                              \
    static void make_##N##_##C(void) { g_plans[N][C] = plan_build(N, C); }
PLAN_ONCE(1, 0) PLAN_ONCE(2, 0) PLAN_ONCE(3, 0) PLAN_ONCE(4, 0)
PLAN_ONCE(5, 0) PLAN_ONCE(6, 0) PLAN_ONCE(7, 0) PLAN_ONCE(8, 0)
PLAN_ONCE(1, 1) PLAN_ONCE(2, 1) PLAN_ONCE(3, 1) PLAN_ONCE(4, 1)
PLAN_ONCE(5, 1) PLAN_ONCE(6, 1) PLAN_ONCE(7, 1) PLAN_ONCE(8, 1)
#undef PLAN_ONCE

static const eps_plan* plan_get(int n, int cells)
{
#define PLAN_CASE(N)                                                                               \
    case N:                                                                                        \
        if (cells)                                                                                 \
            call_once(&once_##N##_1, make_##N##_1);                                                \
        else                                                                                       \
            call_once(&once_##N##_0, make_##N##_0);                                                \
        break;
    switch (n) {
        PLAN_CASE(1) PLAN_CASE(2) PLAN_CASE(3) PLAN_CASE(4)
        PLAN_CASE(5) PLAN_CASE(6) PLAN_CASE(7) PLAN_CASE(8)
    default: return NULL;
    }
#undef PLAN_CASE
    return g_plans[n][cells ? 1 : 0];
}

void tp__lattice_eps(int n, const int32_t* q, const uint16_t* mask, int cells,
                     double eps[4][TP_MAX_N])
{
    assert(q && n >= 1 && n <= TP_MAX_N);
    _Static_assert(TP_MAX_N == 8, "one plan per n: PLAN_ONCE above");
    const eps_plan* p = plan_get(n, cells);
    if (!p) {
        lattice_eps_direct(n, q, mask, cells, eps);
        return;
    }
    memset(eps, 0, sizeof(double) * 4 * TP_MAX_N);
    const int side = (1 << n) + 1;
    for (size_t i = 0; i < p->tri_count; i++) {
        const plan_tri* t = &p->tris[i];
        int64_t z[3];
        int drawn = 1;
        for (int v = 0; v < 3; v++) {
            int32_t qv = q[t->pos[v]];
            drawn &= (q[t->orig[v]] != INT32_MIN) & (qv != INT32_MIN);
            z[v] = qv;
        }
        if (mask && !t->vertex_rule) /* as tri_drawn */
            drawn = tp_node_mask_all(mask, n, t->box[0], t->box[1], t->box[2], t->box[3]);
        if (!drawn)
            continue;
        const int64_t sign = t->sign, abs_area = t->abs_area;
        const int64_t dn = ((int64_t)t->sa * z[0] + (int64_t)t->sb * z[1] + (int64_t)t->sc * z[2]) * sign;
        int64_t mx = 0;
        const plan_span* sp = p->spans + t->span0;
        for (uint32_t k = 0; k < t->span_count; k++, sp++) {
            int64_t nn = ((int64_t)sp->wa * z[0] + (int64_t)sp->wb * z[1] + (int64_t)sp->wc * z[2]) * sign;
            const int32_t* row = q + (size_t)sp->y * (size_t)side;
            for (int x = sp->xa; x <= sp->xb; x++, nn += dn) {
                int32_t v = row[x];
                int64_t e = nn - (int64_t)v * abs_area;
                e = e < 0 ? -e : e;
                e = v == INT32_MIN ? 0 : e;
                mx = e > mx ? e : mx;
            }
        }
        double e = (double)mx / (double)abs_area;
        for (int s = 0; s < 4; s++)
            if (t->sides >> s & 1)
                eps[s][t->kn] = e > eps[s][t->kn] ? e : eps[s][t->kn];
    }
}

double tp__lattice_triangle_error(const int32_t* q, int side, const int32_t pos[3][2],
                                  const int64_t z[3], int cells)
{
    return cells ? cell_bound(q, side, pos, z) : raster_error(q, side, pos, z);
}
