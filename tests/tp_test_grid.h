/*
 * tp_test_grid.h - the render grid of a real DEM of TP_SHARED_DATA_DIR for the tests of the
 * field tools (test_viewshed.c, test_viewshed_cli.c, test_los_cli.c, test_light_cli.c): skips
 * when the file is missing, fails when it cannot be read or gridded.
 */
#ifndef TP_TEST_GRID_H
#define TP_TEST_GRID_H

#include "tp_io.h"
#include "tp_test.h"

#include <string.h>

/* The render grid of file (tp_dem_read, tp_render_grid_build with the defaults); its path in
 * path (cap bytes). */
static inline tp_render_grid* tp_test_render_grid(const char* file, char* path, size_t cap)
{
    tp_dem* dem = NULL;
    tp_render_grid* g = NULL;
    tp_error err;
    memset(&err, 0, sizeof err);
    if (!tp_test_data_path(path, cap, "TP_SHARED_DATA_DIR", file))
        SKIP("%s not found (set TP_SHARED_DATA_DIR)", file);
    if (tp_dem_read(path, &dem, &err) != TP_OK)
        FAIL("tp_dem_read(%s): %s", path, err.message);
    tp_status s = tp_render_grid_build(dem, NULL, &g, &err);
    tp_dem_destroy(dem);
    if (s != TP_OK)
        FAIL("tp_render_grid_build(%s): %s", path, err.message);
    return g;
}

#endif /* TP_TEST_GRID_H */
