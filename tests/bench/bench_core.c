/* bench_core.c - timings of the core stages on a real DEM (not a test; not run by ctest).
 *
 *   build/tp_bench_core DEM [patch_size]
 *
 * The DEM goes through the render grid (geographic DEMs are warped to UTM) as in the program.
 * Prints the median over repeated runs of: terrain build, one selection update (error mode,
 * tau = 1 px, 1280x720, 60 degrees) along a low flight across the DEM, vertex rebuilds of the
 * dirty patches, and the exact error measurement. Medians, because the machines are shared. */
#define _POSIX_C_SOURCE 199309L
#include "tp_io.h"
#include "bench_util.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int main(int argc, char** argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: %s DEM [patch_size]\n", argv[0]);
        return 2;
    }
    int patch = argc > 2 ? atoi(argv[2]) : 17;
    tp_dem* dem;
    tp_error err;
    if (tp_dem_read(argv[1], &dem, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    tp_render_grid* grid;
    if (tp_render_grid_build(dem, NULL, &grid, &err) != TP_OK) {
        fprintf(stderr, "%s\n", err.message);
        return 1;
    }
    tp_terrain_desc desc = tp_render_grid_terrain_desc(grid, patch, TP_FIT_PAD);
    enum { BUILDS = 5, FRAMES = 200 };
    double build[BUILDS], update[FRAMES], verts[FRAMES];
    tp_terrain* t = NULL;
    for (int i = 0; i < BUILDS; i++) {
        tp_terrain_destroy(t);
        double t0 = bench_now_ms();
        if (tp_terrain_create(&desc, &t, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
        build[i] = bench_now_ms() - t0;
    }
    tp_terrain_info ti;
    tp_terrain_get_info(t, &ti);
    tp_selection* s;
    tp_selection_create(t, &s, &err);
    size_t v = (size_t)ti.patch_size, vcap = v * v;
    tp_vertex* vb = malloc(vcap * sizeof *vb);
    double e0, n0, e1, n1;
    tp_terrain_grid_to_world(t, 0, ti.src_height / 2.0, &e0, &n0);
    tp_terrain_grid_to_world(t, ti.src_width - 1, ti.src_height / 2.0, &e1, &n1);
    tp_lod_params lp = {.mode = TP_LOD_ERROR, .tau_px = 1};
    size_t tris = 0;
    double meas = 0;
    for (int f = 0; f < FRAMES; f++) {
        /* A flight 60 m above the ground, west to east along the middle row, looking ahead
         * and slightly down. */
        double a = (f + 0.5) / FRAMES;
        tp_camera cam = {.position = {e0 + a * (e1 - e0), n0, 0}, .forward = {1, 0, -0.15},
                         .up = {0, 0, 1}};
        double x, y;
        tp_terrain_world_to_grid(t, cam.position[0], cam.position[1], &x, &y);
        double g = tp_terrain_height_at(t, x, y);
        cam.position[2] = (isnan(g) ? ti.max_height_m : g) + 60;
        double t0 = bench_now_ms();
        tp_selection_update(s, &cam, &lp, &err);
        double t1 = bench_now_ms();
        for (int p = 0; p < ti.patch_count; p++)
            if (tp_selection_dirty(s, p) && tp_selection_visible(s, p)) {
                int nb[4];
                tp_selection_neighbor_levels(s, p, nb);
                tp_patch_vertices(t, p, tp_selection_level(s, p), nb, vb, vcap);
            }
        tp_selection_clear_dirty(s);
        verts[f] = bench_now_ms() - t1;
        update[f] = t1 - t0;
        if (f == FRAMES / 2) {
            tp_frame_stats st;
            tp_selection_stats(s, &st);
            tris = st.triangles;
            double m0 = bench_now_ms(), mx, rms;
            tp_selection_measure_screen_error(s, &cam, &mx, &rms, NULL);
            meas = bench_now_ms() - m0;
            printf("mid-flight frame: %d visible patches, %zu triangles, screen error max %.3f "
                   "px, rms %.3f px\n",
                   st.visible_patches, tris, mx, rms);
        }
    }
    printf("%s, patch %d: %dx%d, %d patches, %.3f bytes/sample\n", argv[1], patch, ti.width,
           ti.height, ti.patch_count, ti.bytes_per_source_sample);
    printf("terrain build     median %8.2f ms (%d runs)\n", bench_median(build, (size_t)BUILDS), BUILDS);
    printf("selection update  median %8.3f ms (%d frames)\n", bench_median(update, (size_t)FRAMES), FRAMES);
    printf("dirty vertex data median %8.3f ms\n", bench_median(verts, (size_t)FRAMES));
    printf("screen error measurement %8.2f ms (one frame)\n", meas);
    free(vb);
    tp_selection_destroy(s);
    tp_terrain_destroy(t);
    tp_render_grid_destroy(grid);
    tp_dem_destroy(dem);
    return 0;
}
