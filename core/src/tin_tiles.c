/* tin_tiles.c - the error-bounded TIN built tile by tile on several threads (tp_tin_build_tiled).
 *
 * The grid is cut into tiles of tile_cells x tile_cells cells that share their border samples.
 * Each tile is built on its own (tp__tin_build on a copy of its window) and needs nothing from the
 * others, so that tiles can run on any thread in any order, and later one store node at a time:
 *
 * 1. Borders. Each tile side (the samples between two tile corners, on a shared border or the
 *    grid's outline) is simplified by a 1-D greedy polyline (Douglas-Peucker: the worst valid
 *    sample of an interval is chosen until every valid sample is within the bound of the line
 *    between the chosen samples around it), from the side's samples alone, in increasing
 *    coordinate order: the two tiles that share a side compute the same polyline. In the tile the
 *    chosen samples are forced vertices and the others skipped (never measured nor inserted), so
 *    the tile's outline is exactly the polyline and the bound holds on it by construction.
 * 2. Voids (TP_TIN_CUT_VOIDS). The void-outline rule (tp__tin_void_classes) looks two samples
 *    around each sample: it runs on the tile's window widened by 2 samples (clipped to the grid),
 *    which gives exactly the whole grid's answer for the tile's samples; border samples it forces
 *    are chosen in the polyline before the rest is simplified, so both sides agree.
 * 3. Corners in a void. tp__tin_build gives such a corner the nearest valid sample's height within
 *    its window, which differs between the tiles that share the corner. Without the cut the
 *    corner is a vertex of the output, so every tile corner gets one height computed on the whole
 *    grid beforehand (corner_heights) and written into the tile's window copy (the corner is a
 *    vertex anyway: its own error is never measured). With the cut, tiles are left as they are:
 *    the samples between a void corner and the next chosen sample of a side are void or belong to
 *    no valid cell (the first one that does is forced by the void rule), so no kept triangle
 *    touches them, and the dropped triangles are the only ones the corner's height shapes.
 * 4. Merge, in tile order (deterministic whatever the thread count): vertices on tile borders
 *    are keyed by their global sample (one array per border line), the others are the tile's own.
 *
 * Threads take tile indices from an atomic counter; each writes only its tile's result. */
#include "tin_int.h"

#include <limits.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <threads.h>
#if defined(__unix__) || defined(__APPLE__)
#include <unistd.h>
#endif

/* The classes of tp__tin_build (tin_int.h): 0 free, 1 forced, 2 skipped. */
enum { CLS_FREE = 0, CLS_FORCE = 1, CLS_SKIP = 2 };

/* 0 threads: the online CPUs, at most this many */
#define MAX_AUTO_THREADS 64

typedef struct tile_result {
    tp_tin* tin; /* local coordinates of the tile's window; NULL: no triangle and no vertex */
    tp_status st;
} tile_result;

typedef struct tiling {
    const float* h;
    int w, hg;
    double e;
    int cut;
    int tc;          /* tile size in cells */
    int ntx, nty;    /* tiles per row, per column */
    float* corner_z; /* (ntx + 1) * (nty + 1): a tile corner's height (no-cut mode) */
    tile_result* res;
    atomic_int next;
    atomic_int failed;
} tiling;

static int bx(const tiling* g, int i) { return i < g->ntx ? i * g->tc : g->w - 1; }
static int by(const tiling* g, int j) { return j < g->nty ? j * g->tc : g->hg - 1; }

/* An error rounded up to a float, as tin.c stores them. */
static float err_up(double d)
{
    float f = (float)d;
    if ((double)f < d)
        f = nextafterf(f, INFINITY);
    return f;
}

/* ---- corner heights (whole grid, before the tiles) ---- */

/* The nearest valid sample by Chebyshev rings up to radius r, the first in row order on the first
 * ring that has one (tin.c's corner_height, with a radius); NaN if none. */
static float ring_height(const float* h, int w, int hg, int cx, int cy, int r)
{
    float v = h[(size_t)cy * w + cx];
    if (v == v)
        return v;
    for (int k = 1; k <= r; ++k)
        for (int y = cy - k; y <= cy + k; ++y) {
            if (y < 0 || y >= hg)
                continue;
            int edge_row = y == cy - k || y == cy + k;
            for (int x = cx - k; x <= cx + k; x += edge_row ? 1 : 2 * k) {
                if (x < 0 || x >= w)
                    continue;
                float s = h[(size_t)y * w + x];
                if (s == s)
                    return s;
            }
        }
    return NAN;
}

/* Each tile corner's height: its sample's, else the nearest valid sample within tile_cells (the
 * four tiles around it), else a nearest corner's on the corner lattice that has one (breadth
 * first over the 8 neighbours from every such corner, in row order: Chebyshev distance). The grid
 * has a valid sample, so some corner has one: every sample is within tile_cells of its tile's
 * corners. */
static int corner_heights(tiling* g)
{
    const int cw = g->ntx + 1, ch = g->nty + 1;
    const size_t n = (size_t)cw * ch;
    float* z = g->corner_z = malloc(sizeof(float) * n);
    size_t* queue = malloc(sizeof(size_t) * n);
    if (!z || !queue) {
        free(queue);
        return 0;
    }
    size_t head = 0, tail = 0;
    for (int j = 0; j < ch; ++j)
        for (int i = 0; i < cw; ++i) {
            size_t k = (size_t)j * cw + i;
            z[k] = ring_height(g->h, g->w, g->hg, bx(g, i), by(g, j), g->tc);
            if (z[k] == z[k])
                queue[tail++] = k;
        }
    while (head < tail) {
        size_t k = queue[head++];
        int i = (int)(k % (size_t)cw), j = (int)(k / (size_t)cw);
        for (int dj = -1; dj <= 1; ++dj)
            for (int di = -1; di <= 1; ++di) {
                int ni = i + di, nj = j + dj;
                if (ni < 0 || nj < 0 || ni >= cw || nj >= ch)
                    continue;
                size_t m = (size_t)nj * cw + ni;
                if (z[m] != z[m]) {
                    z[m] = z[k];
                    queue[tail++] = m;
                }
            }
    }
    free(queue);
    return 1;
}

/* ---- one tile side: the 1-D greedy polyline ---- */

/* z[0..n-1]: the side's heights in increasing coordinate (NaN = void; z[0], z[n-1] the corners'
 * heights); chosen[]: 1 where already chosen (the ends and the void rule's forced samples) on
 * entry, every vertex of the polyline on return. stack: 2 n ints of scratch. */
static void simplify_side(const float* z, int n, float bound, uint8_t* chosen, int* stack)
{
    int ns = 0;
    for (int a = 0, b = 1; b < n; ++b) /* each interval between chosen samples */
        if (chosen[b]) {
            if (b > a + 1) {
                stack[ns++] = a;
                stack[ns++] = b;
            }
            a = b;
        }
    while (ns > 0) {
        int b = stack[--ns], a = stack[--ns];
        double za = z[a], zb = z[b], worst = -1.0;
        int k = -1;
        for (int i = a + 1; i < b; ++i) {
            if (z[i] != z[i])
                continue;
            double d = fabs((double)z[i] - (za + (zb - za) * (double)(i - a) / (double)(b - a)));
            if (d > worst)
                worst = d, k = i;
        }
        if (k < 0 || !(err_up(worst) > bound))
            continue;
        chosen[k] = 1;
        /* order does not matter: the intervals are independent */
        stack[ns++] = a;
        stack[ns++] = k;
        stack[ns++] = k;
        stack[ns++] = b;
    }
}

/* ---- one tile ---- */

/* Largest error over the samples strictly between vertices a and b of a side of the tile window
 * (tw wide), against the line between them. */
static double side_error(const float* win, int tw, const float* va, const float* vb)
{
    int ax = (int)va[0], ay = (int)va[1], bxx = (int)vb[0], byy = (int)vb[1];
    int n = abs(bxx - ax) + abs(byy - ay); /* one of them is 0 */
    int dx = (bxx > ax) - (bxx < ax), dy = (byy > ay) - (byy < ay);
    double mx = 0.0;
    for (int i = 1; i < n; ++i) {
        float s = win[(size_t)(ay + i * dy) * tw + (size_t)(ax + i * dx)];
        if (s != s)
            continue;
        double d = fabs((double)s - ((double)va[2] + ((double)vb[2] - va[2]) * i / (double)n));
        mx = d > mx ? d : mx;
    }
    return mx;
}

tp_status tp_tin_build_tile(const float* window, size_t stride, int win_w, int win_h, int tile_x,
                            int tile_y, int tile_w, int tile_h, const float corner_z[4],
                            double max_error_m, unsigned flags, tp_tin** out, tp_error* err)
{
    assert(out && window);
    *out = NULL;
    const int cut = (flags & TP_TIN_CUT_VOIDS) != 0;
    if (tile_w < 2 || tile_h < 2 || tile_x < 0 || tile_y < 0 || tile_x > 2 || tile_y > 2 ||
        tile_x + tile_w > win_w || tile_y + tile_h > win_h || win_w - tile_x - tile_w > 2 ||
        win_h - tile_y - tile_h > 2 || stride < (size_t)win_w)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tin: tile %dx%d at (%d, %d) does not fit a window of %dx%d with at most "
                        "2 samples around it", tile_w, tile_h, tile_x, tile_y, win_w, win_h);
    if (!(max_error_m >= 0.0) || !isfinite(max_error_m))
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tin: expected a finite max error >= 0 m, got %g", max_error_m);
    if (!cut && !corner_z)
        return tp__fail(err, TP_ERR_INVALID_ARG, "tin: a tile without the cut needs corner heights");
    const float bound = tp__tin_bound(max_error_m);
    const int tw = tile_w, th = tile_h;
    const float* tile = window + (size_t)tile_y * stride + (size_t)tile_x;
    const size_t n = (size_t)tw * th;
    const int side_max = tw > th ? tw : th;
    float* win = malloc(sizeof(float) * n);
    uint8_t* cls = calloc(n, 1);
    float* sz = malloc(sizeof(float) * (size_t)side_max);
    uint8_t* chosen = malloc((size_t)side_max);
    int* stack = malloc(sizeof(int) * 2 * (size_t)side_max);
    tp_status st = TP_OK;
    if (!win || !cls || !sz || !chosen || !stack)
        goto oom;
    size_t valid = 0;
    for (int y = 0; y < th; ++y) {
        const float* src = tile + (size_t)y * stride;
        memcpy(win + (size_t)y * tw, src, sizeof(float) * tw);
        for (int x = 0; x < tw; ++x)
            valid += src[x] == src[x];
    }

    /* the void rule on the whole window (the tile and 2 samples around it, where the grid has
     * them): the whole grid's answer for the tile's samples */
    if (cut) {
        int any_void = 0;
        for (int y = 0; y < win_h && !any_void; ++y)
            for (int x = 0; x < win_w && !any_void; ++x)
                any_void = window[(size_t)y * stride + x] != window[(size_t)y * stride + x];
        if (any_void) {
            float* mwin = malloc(sizeof(float) * (size_t)win_w * win_h);
            uint8_t* mcls = calloc((size_t)win_w * win_h, 1);
            if (!mwin || !mcls) {
                free(mwin);
                free(mcls);
                goto oom;
            }
            for (int y = 0; y < win_h; ++y)
                memcpy(mwin + (size_t)y * win_w, window + (size_t)y * stride,
                       sizeof(float) * win_w);
            tp__tin_void_classes(mwin, win_w, win_h, mcls);
            for (int y = 0; y < th; ++y)
                memcpy(cls + (size_t)y * tw, mcls + (size_t)(tile_y + y) * win_w + tile_x,
                       (size_t)tw);
            free(mwin);
            free(mcls);
        }
    }

    /* the four sides: top, bottom (rows 0, th-1), left, right (columns 0, tw-1); corners
     * 0 top-left, 1 top-right, 2 bottom-left, 3 bottom-right */
    static const int ends[4][2] = {{0, 1}, {2, 3}, {0, 2}, {1, 3}};
    for (int s = 0; s < 4; ++s) {
        const int horiz = s < 2;
        const int len = horiz ? tw : th;
        const size_t base = s == 1 ? (size_t)(th - 1) * tw : s == 3 ? (size_t)(tw - 1) : 0;
        const size_t step = horiz ? 1 : (size_t)tw;
        for (int k = 0; k < len; ++k) {
            sz[k] = win[base + k * step];
            chosen[k] = cls[base + k * step] == CLS_FORCE;
        }
        if (corner_z) { /* the ends: the corners' shared heights */
            sz[0] = corner_z[ends[s][0]];
            sz[len - 1] = corner_z[ends[s][1]];
        }
        chosen[0] = chosen[len - 1] = 1;
        simplify_side(sz, len, bound, chosen, stack);
        for (int k = 0; k < len; ++k)
            cls[base + k * step] = chosen[k] ? CLS_FORCE : CLS_SKIP;
    }
    /* the corners: the shared height in a void (not with the cut: see the top of the file) */
    if (!cut) {
        const size_t c[4] = {0, (size_t)tw - 1, (size_t)(th - 1) * tw, n - 1};
        for (int k = 0; k < 4; ++k)
            if (win[c[k]] != win[c[k]]) {
                win[c[k]] = corner_z[k];
                ++valid;
            }
    }
    free(sz);
    free(chosen);
    free(stack);
    sz = NULL, chosen = NULL, stack = NULL;
    if (valid == 0) /* cut, a tile without a valid sample: nothing */
        goto done;

    tp_tin* t = NULL;
    st = tp__tin_build(win, tw, th, max_error_m, cls, cut, &t, err);
    if (st != TP_OK)
        goto done;
    /* the skipped border samples count in the error of the triangle whose edge they lie on */
    double mx = t->max_error_m;
    for (size_t k = 0; k < t->triangle_count; ++k) {
        const uint32_t* tr = t->triangles + 3 * k;
        for (int e = 0; e < 3; ++e) {
            const float *a = t->vertices + 3 * tr[e], *b = t->vertices + 3 * tr[(e + 1) % 3];
            int on_side = (a[0] == b[0] && (a[0] == 0 || a[0] == tw - 1)) ||
                          (a[1] == b[1] && (a[1] == 0 || a[1] == th - 1));
            if (!on_side)
                continue;
            float f = err_up(side_error(win, tw, a, b));
            if (f > t->triangle_error_m[k])
                t->triangle_error_m[k] = f;
        }
        mx = t->triangle_error_m[k] > mx ? t->triangle_error_m[k] : mx;
    }
    t->max_error_m = mx;
    *out = t;
done:
    free(win);
    free(cls);
    free(sz);
    free(chosen);
    free(stack);
    return st;
oom:
    st = tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tin: out of memory for a tile of %dx%d samples",
                  tw, th);
    goto done;
}

/* Tile ti of the grid: its window (2 samples around it, clipped to the grid) and corner heights. */
static tp_status build_tile(const tiling* g, int ti, tp_tin** out, tp_error* err)
{
    const int i = ti % g->ntx, j = ti / g->ntx;
    const int x0 = bx(g, i), x1 = bx(g, i + 1), y0 = by(g, j), y1 = by(g, j + 1);
    const int mx0 = x0 - 2 < 0 ? 0 : x0 - 2, my0 = y0 - 2 < 0 ? 0 : y0 - 2;
    const int mx1 = x1 + 2 > g->w - 1 ? g->w - 1 : x1 + 2;
    const int my1 = y1 + 2 > g->hg - 1 ? g->hg - 1 : y1 + 2;
    const int cw = g->ntx + 1;
    const float cz[4] = {g->corner_z[(size_t)j * cw + i], g->corner_z[(size_t)j * cw + i + 1],
                         g->corner_z[(size_t)(j + 1) * cw + i],
                         g->corner_z[(size_t)(j + 1) * cw + i + 1]};
    return tp_tin_build_tile(g->h + (size_t)my0 * g->w + mx0, (size_t)g->w, mx1 - mx0 + 1,
                             my1 - my0 + 1, x0 - mx0, y0 - my0, x1 - x0 + 1, y1 - y0 + 1, cz, g->e,
                             g->cut ? TP_TIN_CUT_VOIDS : 0u, out, err);
}

/* One thread: its first failure (the tile and the message). */
typedef struct worker_ctx {
    tiling* g;
    int failed_tile; /* INT_MAX: none */
    tp_error err;
} worker_ctx;

static int worker(void* arg)
{
    worker_ctx* w = arg;
    tiling* g = w->g;
    const int count = g->ntx * g->nty;
    for (;;) {
        if (atomic_load(&g->failed))
            break;
        int k = atomic_fetch_add(&g->next, 1);
        if (k >= count)
            break;
        tile_result* r = &g->res[k];
        r->st = build_tile(g, k, &r->tin, &w->err);
        if (r->st != TP_OK) {
            w->failed_tile = k;
            atomic_store(&g->failed, 1);
            break;
        }
    }
    return 0;
}

/* ---- merge, in tile order ---- */

static tp_status merge(tiling* g, tp_tin** out, tp_error* err)
{
    const int count = g->ntx * g->nty;
    size_t nv = 0, nt = 0;
    for (int k = 0; k < count; ++k)
        if (g->res[k].tin) {
            nv += g->res[k].tin->vertex_count;
            nt += g->res[k].tin->triangle_count;
        }
    tp_tin* t = calloc(1, sizeof *t);
    /* border vertices by global sample: one array per border row (w) and column (hg) */
    uint32_t* hmap = malloc(sizeof(uint32_t) * (size_t)(g->nty + 1) * g->w);
    uint32_t* vmap = malloc(sizeof(uint32_t) * (size_t)(g->ntx + 1) * g->hg);
    size_t max_local = 1;
    for (int k = 0; k < count; ++k)
        if (g->res[k].tin && g->res[k].tin->vertex_count > max_local)
            max_local = g->res[k].tin->vertex_count;
    uint32_t* remap = malloc(sizeof(uint32_t) * max_local);
    if (t) {
        t->vertices = malloc(sizeof(float) * 3 * (nv ? nv : 1));
        t->triangles = malloc(sizeof(uint32_t) * 3 * (nt ? nt : 1));
        t->triangle_error_m = malloc(sizeof(float) * (nt ? nt : 1));
    }
    if (!t || !hmap || !vmap || !remap || !t->vertices || !t->triangles || !t->triangle_error_m) {
        tp_tin_destroy(t);
        free(hmap);
        free(vmap);
        free(remap);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY,
                        "tin: out of memory merging %d tiles (%zu triangles)", count, nt);
    }
    for (size_t k = 0; k < (size_t)(g->nty + 1) * g->w; ++k)
        hmap[k] = UINT32_MAX;
    for (size_t k = 0; k < (size_t)(g->ntx + 1) * g->hg; ++k)
        vmap[k] = UINT32_MAX;
    size_t v = 0, m = 0;
    double mx = 0.0;
    for (int k = 0; k < count; ++k) {
        tp_tin* s = g->res[k].tin;
        if (!s)
            continue;
        const int i = k % g->ntx, j = k / g->ntx;
        const int x0 = bx(g, i), y0 = by(g, j);
        const int tw = bx(g, i + 1) - x0 + 1, th = by(g, j + 1) - y0 + 1;
        for (size_t a = 0; a < s->vertex_count; ++a) {
            const float* p = s->vertices + 3 * a;
            const int lx = (int)p[0], ly = (int)p[1];
            uint32_t* slot = NULL;
            if (ly == 0 || ly == th - 1)
                slot = &hmap[(size_t)(ly == 0 ? j : j + 1) * g->w + (size_t)(x0 + lx)];
            else if (lx == 0 || lx == tw - 1)
                slot = &vmap[(size_t)(lx == 0 ? i : i + 1) * g->hg + (size_t)(y0 + ly)];
            if (slot && *slot != UINT32_MAX) {
                remap[a] = *slot;
                continue;
            }
            t->vertices[3 * v] = (float)(x0 + lx);
            t->vertices[3 * v + 1] = (float)(y0 + ly);
            t->vertices[3 * v + 2] = p[2];
            remap[a] = (uint32_t)v;
            if (slot)
                *slot = (uint32_t)v;
            ++v;
        }
        for (size_t b = 0; b < s->triangle_count; ++b, ++m) {
            for (int c = 0; c < 3; ++c)
                t->triangles[3 * m + c] = remap[s->triangles[3 * b + c]];
            t->triangle_error_m[m] = s->triangle_error_m[b];
        }
        mx = s->max_error_m > mx ? s->max_error_m : mx;
        t->samples_rasterised += s->samples_rasterised;
        tp_tin_destroy(s);
        g->res[k].tin = NULL;
    }
    free(hmap);
    free(vmap);
    free(remap);
    float* shrunk = realloc(t->vertices, sizeof(float) * 3 * (v ? v : 1));
    if (shrunk)
        t->vertices = shrunk;
    t->vertex_count = v;
    t->triangle_count = m;
    t->max_error_m = mx;
    *out = t;
    return TP_OK;
}

static int online_cpus(void)
{
#if defined(_SC_NPROCESSORS_ONLN)
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > MAX_AUTO_THREADS ? MAX_AUTO_THREADS : (int)n;
#else
    return 1;
#endif
}

tp_status tp_tin_build_tiled(const float* heights, size_t height_count, int width, int height,
                             double max_error_m, unsigned flags, int tile_cells, int threads,
                             tp_tin** out, tp_error* err)
{
    assert(out);
    if (tile_cells < 1)
        return tp__fail(err, TP_ERR_INVALID_ARG, "tin: expected tiles of at least 1 cell, got %d",
                        tile_cells);
    if (threads < 0)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tin: expected threads >= 0 (0: one per CPU), got %d", threads);
    if (width < 2 || height < 2) /* no area (or the arguments' errors): as tp_tin_build */
        return tp_tin_build(heights, height_count, width, height, max_error_m, flags, out, err);
    assert(heights && height_count == (size_t)width * (size_t)height);
    if ((uint64_t)width * (uint64_t)height >= ((uint64_t)1 << 32) || !(max_error_m >= 0.0) ||
        !isfinite(max_error_m))
        return tp_tin_build(heights, height_count, width, height, max_error_m, flags, out, err);
    size_t valid = 0;
    for (size_t k = 0; k < height_count && !valid; ++k)
        valid += heights[k] == heights[k];
    if (!valid) /* nothing, as tp_tin_build */
        return tp_tin_build(heights, height_count, width, height, max_error_m, flags, out, err);

    tiling g;
    memset(&g, 0, sizeof g);
    g.h = heights;
    g.w = width;
    g.hg = height;
    g.e = max_error_m;
    g.cut = (flags & TP_TIN_CUT_VOIDS) != 0;
    const int longest = (width > height ? width : height) - 1;
    g.tc = tile_cells < longest ? tile_cells : longest;
    g.ntx = (width - 1 + g.tc - 1) / g.tc;
    g.nty = (height - 1 + g.tc - 1) / g.tc;
    if ((int64_t)g.ntx * g.nty > INT_MAX / 2)
        return tp__fail(err, TP_ERR_INVALID_ARG,
                        "tin: %dx%d samples in tiles of %d cells make too many tiles", width,
                        height, tile_cells);
    atomic_init(&g.next, 0);
    atomic_init(&g.failed, 0);
    const int count = g.ntx * g.nty;
    g.res = calloc((size_t)count, sizeof *g.res);
    if (!g.res || !corner_heights(&g)) {
        free(g.res);
        free(g.corner_z);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tin: out of memory for %d tiles", count);
    }

    int nth = threads == 0 ? online_cpus() : threads;
    nth = nth < count ? nth : count;
    thrd_t* th = nth > 1 ? malloc(sizeof(thrd_t) * (size_t)(nth - 1)) : NULL;
    worker_ctx* ctx = calloc((size_t)nth, sizeof *ctx);
    if (!ctx) {
        free(th);
        free(g.res);
        free(g.corner_z);
        return tp__fail(err, TP_ERR_OUT_OF_MEMORY, "tin: out of memory for %d threads", nth);
    }
    for (int k = 0; k < nth; ++k)
        ctx[k] = (worker_ctx){.g = &g, .failed_tile = INT_MAX};
    int started = 0;
    for (int k = 0; th && k < nth - 1; ++k) {
        if (thrd_create(&th[k], worker, &ctx[k + 1]) != thrd_success)
            break; /* fewer threads: this one takes the rest */
        ++started;
    }
    worker(&ctx[0]);
    for (int k = 0; k < started; ++k)
        thrd_join(th[k], NULL);
    free(th);

    /* the first failed tile's message (in tile order among those that ran) */
    tp_status st = TP_OK;
    int first = INT_MAX;
    for (int k = 0; k < nth; ++k)
        if (ctx[k].failed_tile < first) {
            first = ctx[k].failed_tile;
            st = g.res[first].st;
            if (err)
                *err = ctx[k].err;
        }
    free(ctx);
    if (st == TP_OK)
        st = merge(&g, out, err);
    for (int k = 0; k < count; ++k)
        tp_tin_destroy(g.res[k].tin);
    free(g.res);
    free(g.corner_z);
    return st;
}
