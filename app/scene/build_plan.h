/*
 * build_plan.h - what a store build (store_build.c) decides before it reads a row: the node
 * hierarchy's geometry within the memory budget, and how coarse a preview's grid is.
 */
#ifndef TP_APP_BUILD_PLAN_H
#define TP_APP_BUILD_PLAN_H

#include "store_build.h"

/* Bytes the build allocates that grow with the grid (the band, the void window, the tree
 * builder, the writer's bit per node) for geometry g over a source grid src_width wide. */
double tp_build_memory_bytes(const tp_tree_geometry* g, int src_width, int fill_max);

/* The node hierarchy's geometry for the mosaic (*g), checked against the budget before any
 * reading: GDAL's block cache has a quarter of it (tp_mosaic_open); what grows with the grid
 * must fit the other three quarters. 1, or 0 after one line (with the --memory or --patch that
 * would do). */
int tp_build_plan_geometry(const tp_build_options* o, const tp_mosaic_info* mi,
                           tp_tree_geometry* g);

/* A preview's coarsening of a width x height grid: the smallest power of two f with
 * ceil(width / f) * ceil(height / f) <= max_samples (1 when the grid is that small). */
int tp_build_preview_coarsen(int width, int height, double max_samples);

#endif /* TP_APP_BUILD_PLAN_H */
