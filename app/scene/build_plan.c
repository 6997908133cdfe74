/* build_plan.c - what a store build needs before it reads (see build_plan.h). */
#include "build_plan.h"

#include "cli.h"

#include <math.h>
#include <stdio.h>

/* The --memory (MB) to suggest for need_mb of what grows with the grid: that in three quarters
 * of the budget, never below what --memory accepts. */
static double memory_to_suggest(double need_mb)
{
    double mb = ceil(need_mb / 0.75);
    return mb < BUILD_MIN_MEMORY_MB ? BUILD_MIN_MEMORY_MB : mb;
}

/* What the build allocates that grows with the grid (bytes, build_plan.h): the band read
 * (floats) and quantised (int32), the tree builder (tp_core.h: its decimated rows, a block of
 * samples per node of a row, two rows of metas and masks per scale) and the store writer's bit
 * per node (it writes the node and location tables into the file as nodes come:
 * docs/store.md). GDAL's block cache comes on top (a quarter of --memory); the program's fixed
 * part (libraries, about 156 MB resident: docs/PERFORMANCE.md) is not counted. */
double tp_build_memory_bytes(const tp_tree_geometry* g, int src_width, int fill_max)
{
    const double side = (1 << g->n) + 1;
    /* void filling: the mosaic's window (2 rows each side at least) as read and filled, its
     * regions (int) and marks (byte) while it holds a void; a window grown for a void takes
     * what is left of the budget (tp_mosaic_options.fill_window_mb, set once the need is known) */
    const double fill = fill_max > 0 ? (side + 4.0) * src_width * 13.0 +
                                           side * (src_width + (double)g->width) /* flags */
                                     : 0;
    const double band = side * src_width * sizeof(float) + side * g->width * sizeof(int32_t);
    const double builder = 4 * side * ((2 + 1.0 / (1 << g->n)) * g->width + g->scales) +
                           4.0 * g->cols * (sizeof(tp_node_meta) + (1u << (2 * g->n - 3))) +
                           (double)g->cols * ((1u << (2 * g->n - 3)) + (1u << (g->n - 2)) + 2) +
                           (fill_max > 0 ? side * (g->width + g->scales) : 0) + 2048;
    const double added = (double)g->node_count / 8;
    /* zstd's context, one node's scratch, the writer's run of table entries and read-back buffer */
    return band + fill + builder + added + (1 << 20);
}

/* build_plan.h */
int tp_build_plan_geometry(const tp_build_options* o, const tp_mosaic_info* mi, tp_tree_geometry* g)
{
    tp_error err = {0};
    if (tp_tree_geometry_init(mi->width, mi->height, o->patch_size, g, &err) != TP_OK)
        return tp_cli_error("%s", err.message), 0;
    const int ps = 1 << g->n, band_rows = ps + 1;
    const double need_mb = tp_build_memory_bytes(g, mi->width, o->fill_max) / (1024.0 * 1024.0);
    if (need_mb <= o->memory_mb * 0.75)
        return 1;
    /* the node size that needs least: small nodes make a large table, large ones wide bands */
    int best = o->patch_size;
    double best_mb = need_mb;
    for (int p = 17; p <= 257; p = 2 * p - 1) {
        tp_tree_geometry gp;
        tp_error e2;
        if (tp_tree_geometry_init(mi->width, mi->height, p, &gp, &e2) != TP_OK)
            continue;
        double mb = tp_build_memory_bytes(&gp, mi->width, o->fill_max) / (1024.0 * 1024.0);
        if (mb < best_mb)
            best = p, best_mb = mb;
    }
    char alt[96] = "";
    if (best != o->patch_size)
        snprintf(alt, sizeof alt, " (or --memory %.0f with --patch %d)", memory_to_suggest(best_mb),
                 best);
    tp_cli_error("--memory %d MB is too small for a %dx%d grid in %dx%d "
                 "nodes: one band of %d rows, the tree builder and the store writer need "
                 "%.0f MB, besides GDAL's block cache (a quarter of the budget); give --memory "
                 "%.0f or more%s",
                 o->memory_mb, mi->width, mi->height, ps + 1, ps + 1, band_rows, need_mb,
                 memory_to_suggest(need_mb), alt);
    return 0;
}


int tp_build_preview_coarsen(int width, int height, double max_samples)
{
    int f = 1;
    while (f < (1 << 20) && ceil((double)width / f) * ceil((double)height / f) > max_samples)
        f *= 2;
    return f;
}
