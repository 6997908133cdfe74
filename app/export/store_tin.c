/* store_tin.c - a store's error-bounded TIN, one window of leaf samples at a time (see
 * store_tin.h). */
#include "store_tin.h"

#include "cli.h"
#include "tin_export.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Tile corner i of n over a side of `last` + 1 samples in steps of tc (tp_tin_build_tiled's). */
static int corner(int i, int n, int tc, int last) { return i < n ? i * tc : last; }

typedef struct tile_error {
    const float* win;
    int stride, ox, oy; /* tile (0, 0) in the window */
    int own_w, own_h;   /* samples the tile counts in the RMS: its own, not the next tile's */
    double max, sum;
    size_t count;
    uint8_t* seen;      /* own_w * own_h */
} tile_error;

static void error_at(int x, int y, double z, void* user)
{
    tile_error* e = user;
    float s = e->win[(size_t)(y + e->oy) * e->stride + (size_t)(x + e->ox)];
    if (s != s)
        return;
    double d = fabs(z - s);
    e->max = d > e->max ? d : e->max;
    if (x >= e->own_w || y >= e->own_h || e->seen[(size_t)y * e->own_w + x])
        return;
    e->seen[(size_t)y * e->own_w + x] = 1;
    e->sum += d * d;
    e->count++;
}

int tp_store_tin_mesh(leaf_cache* lc, int width, int height, double m, size_t max_triangles,
                      mesh_build* out, tp_store_tin_stats* stats, tp_error* err)
{
    memset(stats, 0, sizeof *stats);
    const int tc = TP_TIN_EXPORT_TILE_CELLS;
    const int ntx = (width - 1 + tc - 1) / tc, nty = (height - 1 + tc - 1) / tc;
    const int ww = tc + 5; /* the largest window: a tile of tc + 1 samples and 2 around it */
    float* win = malloc(sizeof(float) * (size_t)ww * ww);
    uint8_t* seen = malloc((size_t)tc * tc);
    int ok = 0;
    if (width < 2 || height < 2) {
        tp_error_set(err, TP_ERR_INVALID_ARG, "a grid of %dx%d samples has no cell", width, height);
        goto done;
    }
    if (!win || !seen) {
        tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory");
        goto done;
    }
    for (int j = 0; j < nty; j++)
        for (int i = 0; i < ntx; i++) {
            const int x0 = corner(i, ntx, tc, width - 1), x1 = corner(i + 1, ntx, tc, width - 1);
            const int y0 = corner(j, nty, tc, height - 1), y1 = corner(j + 1, nty, tc, height - 1);
            const int mx0 = x0 - 2 < 0 ? 0 : x0 - 2, my0 = y0 - 2 < 0 ? 0 : y0 - 2;
            const int mx1 = x1 + 2 > width - 1 ? width - 1 : x1 + 2;
            const int my1 = y1 + 2 > height - 1 ? height - 1 : y1 + 2;
            const int mw = mx1 - mx0 + 1, mh = my1 - my0 + 1;
            for (int y = 0; y < mh; y++)
                for (int x = 0; x < mw; x++)
                    win[(size_t)y * mw + x] = (float)tp_leaf_sample(lc, mx0 + x, my0 + y);
            if (lc->failed) {
                *err = lc->res->err;
                goto done;
            }
            stats->tiles++;
            stats->peak_window = (size_t)mw * mh > stats->peak_window ? (size_t)mw * mh
                                                                       : stats->peak_window;
            tp_tin* t = NULL;
            if (tp_tin_build_tile(win, (size_t)mw, mw, mh, x0 - mx0, y0 - my0, x1 - x0 + 1,
                                  y1 - y0 + 1, NULL, m, TP_TIN_CUT_VOIDS, &t, err) != TP_OK)
                goto done;
            if (!t)
                continue;
            /* a tile counts its own samples in the RMS: not its last column and row, which are
             * the next tile's first, but at the grid's edge */
            tile_error te = {win, mw, x0 - mx0, y0 - my0, x1 - x0 + (x1 == width - 1),
                             y1 - y0 + (y1 == height - 1), 0, 0, 0, seen};
            memset(seen, 0, (size_t)te.own_w * te.own_h);
            int failed = 0;
            for (size_t k = 0; k < t->triangle_count && !failed; k++) {
                const uint32_t* tr = t->triangles + 3 * k;
                uint64_t p[3];
                int32_t g[3][2];
                for (int c = 0; c < 3 && !failed; c++) {
                    const float* v = t->vertices + 3 * tr[c];
                    g[c][0] = (int32_t)v[0];
                    g[c][1] = (int32_t)v[1];
                    int filled = 0;
                    tp_leaf_sample_filled(lc, x0 + g[c][0], y0 + g[c][1], &filled);
                    p[c] = tp_mesh_point(out, x0 + g[c][0], y0 + g[c][1], v[2], filled);
                    failed = p[c] == UINT64_MAX;
                }
                if (failed)
                    break;
                te.max = 0;
                const float *a = t->vertices + 3 * tr[0], *b = t->vertices + 3 * tr[1],
                            *c = t->vertices + 3 * tr[2];
                tp_triangle_rasterize(g[0], g[1], g[2], a[2], b[2], c[2], error_at, &te);
                failed = !tp_mesh_add_triangle(out, p, 0, 0, te.max);
            }
            tp_tin_destroy(t);
            if (failed) {
                tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory building the mesh");
                goto done;
            }
            stats->sum_sq += te.sum;
            stats->samples += te.count;
            if (out->tris > max_triangles) {
                tp_error_set(err, TP_ERR_INVALID_ARG, "the TIN passes %zu triangles", max_triangles);
                goto done;
            }
            if (tp_interrupted()) {
                tp_error_set(err, TP_ERR_IO, "interrupted");
                goto done;
            }
        }
    ok = 1;
done:
    free(win);
    free(seen);
    return ok;
}
