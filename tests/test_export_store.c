/*
 * test_export_store.c - `terrapatch export` on built stores (.tpt), end to end: stores built by
 * `terrapatch build` from real DEMs, meshes exported by the command (children), read back with
 * VTK (tp_mesh_inspect, tp_mesh_read_points). Expectations come from the DEM path's export of
 * the same DEM and from the mesh's own topology, not from the store export's code.
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_io.h"
#include "tp_test.h"
#include "tp_test_child.h"

/* A TIN's bound holds at every sample as tin.c interpolates; the export measures each triangle
 * again with another double formula (tp_triangle_rasterize), which may find an error of exactly
 * M about 1e-13 m above it. */
#define TIN_ROUNDING_M 1e-9

#include <errno.h>
#include <fcntl.h>
#include <math.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

static void data_path(char* buf, size_t cap, const char* file)
{
    if (!tp_test_data_path(buf, cap, "TP_SHARED_DATA_DIR", file))
        SKIP("data file %s not found (set TP_SHARED_DATA_DIR)", buf);
}

static void out_path(char* buf, size_t cap, const char* name)
{
    snprintf(buf, cap, "/tmp/tp_export_store_%ld_%s", (long)getpid(), name);
}

/* Builds a store of 17-sample nodes from the NULL-terminated data files, --fill-max fill_max
 * (NULL: the default, any size, as a DEM read whole). */
static void build_store(const char* out, const char* fill_max, const char* const* files)
{
    char paths[4][1024], err[4096];
    const char* args[16];
    int n = 0;
    args[n++] = "--quiet";
    args[n++] = "--patch";
    args[n++] = "17";
    if (fill_max) {
        args[n++] = "--fill-max";
        args[n++] = fill_max;
    }
    for (int i = 0; files[i]; i++) {
        data_path(paths[i], sizeof paths[i], files[i]);
        args[n++] = paths[i];
    }
    args[n++] = "-o";
    args[n++] = out;
    args[n] = NULL;
    int rc = tp_test_run_terrapatch("build", args, err, sizeof err);
    if (rc != 0)
        FAIL("terrapatch build %s: exit %d: %s", out, rc, err);
}

static tp_mesh_summary export_and_inspect(const char* const* args)
{
    char err[4096];
    int rc = tp_test_run_terrapatch("export", args, err, sizeof err);
    if (rc != 0)
        FAIL("terrapatch export: exit %d: %s", rc, err);
    const char* out = NULL;
    for (int i = 0; args[i]; i++)
        if (!strcmp(args[i], "-o"))
            out = args[i + 1];
    tp_mesh_summary s;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(out, &s, &e));
    return s;
}

TEST(seam_store_cuts_are_watertight)
{
    /* N42E001 and N41E001 share a row: one store over both, and every cut of it is one
     * surface whose only boundary is the drawn region's outline (the --full mesh's) */
    char store[1024], out[1024];
    out_path(store, sizeof store, "seam.tpt");
    const char* files[] = {"N42E001.hgt", "N41E001.hgt", NULL};
    build_store(store, "64", files);
    out_path(out, sizeof out, "seam.vtp");
    const char* full[] = {"--full", store, "-o", out, NULL};
    tp_mesh_summary f = export_and_inspect(full);
    EXPECT_EQ_INT(0, f.non_manifold_edges);
    EXPECT_EQ_DBL(0.0, f.max_error_m);
    const char* def[] = {store, "-o", out, NULL}; /* the viewer's default camera */
    tp_mesh_summary s = export_and_inspect(def);
    EXPECT_EQ_INT(f.boundary_loops, s.boundary_loops);
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    EXPECT_LT((double)s.triangles, 0.2 * (double)f.triangles);
    EXPECT_GT(s.max_error_m, 0.0);
    EXPECT_TRUE(s.has_elevation && s.has_void_filled && s.has_patch_id && s.has_lod &&
                s.has_max_error && s.has_crs && s.has_source && s.has_version);
    EXPECT_EQ_INT(1, s.points_are_double);
    /* the tiles keep 5 voids the build does not fill (over 64 samples, or at the border):
     * the outline is 6 loops, and a crack anywhere would add one */
    EXPECT_EQ_INT(6, f.boundary_loops);
    /* distance mode, the whole map in view: leaves near the south edge, large nodes far */
    const char* dist[] = {"--lod", "distance", "--mindist", "2000", "--maxdist",
                          "15000", store,      "-o",        out,    NULL};
    tp_mesh_summary d = export_and_inspect(dist);
    EXPECT_GT((double)d.triangles, 0.0);
    EXPECT_LT((double)d.triangles, 0.5 * (double)f.triangles);
    EXPECT_EQ_INT(0, d.non_manifold_edges);
    EXPECT_EQ_INT(f.boundary_loops, d.boundary_loops);
    /* without the pass that raises a coarser neighbour whose stitching passes M, this cut
     * measured 40 m at M = 30 (and 9.4 m at M = 8 on Mt Hood, below) */
    const char* me[] = {"--max-error", "30", "--mesh", "patches", store, "-o", out, NULL};
    tp_mesh_summary m = export_and_inspect(me);
    EXPECT_EQ_INT(f.boundary_loops, m.boundary_loops);
    EXPECT_EQ_INT(0, m.non_manifold_edges);
    EXPECT_LE(m.max_error_m, 30.0);
    EXPECT_GT(m.max_error_m, 10.0);
    EXPECT_LT((double)m.triangles, 0.6 * (double)f.triangles);
    /* the TIN, tile by tile across both DEMs' nodes: the same outline, watertight, bounded,
     * far fewer triangles than the patches */
    const char* tin[] = {"--max-error", "30", store, "-o", out, NULL};
    tp_mesh_summary t = export_and_inspect(tin);
    EXPECT_EQ_INT(f.boundary_loops, t.boundary_loops);
    EXPECT_EQ_INT(0, t.non_manifold_edges);
    EXPECT_EQ_INT(0, t.downward_triangles);
    EXPECT_LE(t.max_error_m, 30.0 + TIN_ROUNDING_M);
    EXPECT_GT(t.max_error_m, 20.0);
    EXPECT_TRUE(!t.has_patch_id && !t.has_lod && t.has_max_error && t.has_void_filled);
    EXPECT_LT((double)t.triangles, 0.5 * (double)m.triangles);
    for (int i = 0; i < 4; i++)
        EXPECT_EQ_DBL(f.bounds[i], t.bounds[i]);
    remove(out);
    remove(store);
}

TEST(void_store_cuts_are_watertight_and_keep_max_error)
{
    /* Mt Hood (UTM, nodata around and inside) with no void filled: incomplete nodes are drawn
     * at full detail next to coarse ones; the only boundaries are the voids' and the map's */
    char store[1024], out[1024];
    out_path(store, sizeof store, "hood.tpt");
    const char* files[] = {"lf_elev_220_mt_hood_utm.tif", NULL};
    build_store(store, "0", files);
    out_path(out, sizeof out, "hood.vtp");
    const char* full[] = {"--full", store, "-o", out, NULL};
    tp_mesh_summary f = export_and_inspect(full);
    /* 26820 nodata samples: fewer than two triangles per cell of the 1013 x 799 grid */
    EXPECT_LT((double)f.triangles, 2.0 * 1012 * 798 - 40000);
    EXPECT_EQ_INT(0, f.non_manifold_edges);
    const char* me[] = {"--max-error", "8", "--mesh", "patches", store, "-o", out, NULL};
    tp_mesh_summary m = export_and_inspect(me);
    EXPECT_EQ_INT(f.boundary_loops, m.boundary_loops);
    EXPECT_EQ_INT(0, m.non_manifold_edges);
    EXPECT_LE(m.max_error_m, 8.0);
    EXPECT_GT(m.max_error_m, 1.0); /* not the full mesh */
    EXPECT_LT((double)m.triangles, (double)f.triangles);
    /* the TIN cut at the voids (inside and around), tile by tile: the full mesh's outline */
    const char* tin[] = {"--max-error", "8", store, "-o", out, NULL};
    tp_mesh_summary t = export_and_inspect(tin);
    EXPECT_EQ_INT(f.boundary_loops, t.boundary_loops);
    EXPECT_EQ_INT(0, t.non_manifold_edges);
    EXPECT_EQ_INT(0, t.downward_triangles);
    EXPECT_LE(t.max_error_m, 8.0 + TIN_ROUNDING_M);
    EXPECT_GT(t.max_error_m, 4.0);
    EXPECT_LT((double)t.triangles, 0.5 * (double)m.triangles);
    for (int i = 0; i < 4; i++)
        EXPECT_EQ_DBL(f.bounds[i], t.bounds[i]);
    const char* top[] = {"--lod", "error", "--tau", "4", store, "-o", out, NULL};
    tp_mesh_summary s = export_and_inspect(top);
    EXPECT_EQ_INT(f.boundary_loops, s.boundary_loops);
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    remove(out);
    remove(store);
}

/* What export --full on a store reports as the full mesh: the triangles of every cell with four
 * drawn samples, i.e. exactly what it wrote; it used to be two per cell of the whole grid, void
 * and outside samples included (1,613,952 for Mt Hood's 1013 x 799 grid, 26,820 of its samples
 * nodata, so "96.0% of the at most ..."). */
TEST(full_export_reports_the_drawn_cells_of_the_full_mesh)
{
    char store[1024], out[1024], text[4096], err[4096];
    out_path(store, sizeof store, "hood_count.tpt");
    const char* files[] = {"lf_elev_220_mt_hood_utm.tif", NULL};
    build_store(store, "0", files);
    out_path(out, sizeof out, "hood_count.vtp");
    const char* full[] = {"--full", store, "-o", out, NULL};
    int rc = tp_test_run_terrapatch_out("export", full, text, sizeof text, err, sizeof err);
    if (rc != 0)
        FAIL("terrapatch export: exit %d: %s", rc, err);
    tp_mesh_summary f;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(out, &f, &e));
    tp_test_note("%s", text);
    const char* p = strstr(text, "% of the ");
    ASSERT_TRUE(p != NULL);
    p += strlen("% of the ");
    EXPECT_TRUE(strncmp(p, "at most", 7) != 0); /* an exact count */
    double reported = strtod(p, NULL);
    EXPECT_EQ_DBL((double)f.triangles, reported);
    EXPECT_LT(reported, 2.0 * 1012 * 798 - 40000);
    EXPECT_TRUE(strstr(text, "(100.00% of the ") != NULL);
    remove(out);
    remove(store);
}

static int cmp_xy(const void* a, const void* b)
{
    const double *p = a, *q = b;
    for (int i = 0; i < 2; i++)
        if (p[i] != q[i])
            return p[i] < q[i] ? -1 : 1;
    return 0;
}

TEST(store_and_dem_exports_have_the_same_points)
{
    /* the same DEM, node size and camera, --lod full: the store's cut and the DEM's selection
     * draw the same samples at the same positions */
    char store[1024], dem[1024], a[1024], b[1024];
    out_path(store, sizeof store, "n42.tpt");
    const char* files[] = {"N42E001.hgt", NULL};
    build_store(store, NULL, files); /* the default void filling, as the DEM's export */
    data_path(dem, sizeof dem, "N42E001.hgt");
    out_path(a, sizeof a, "n42_dem.vtp");
    out_path(b, sizeof b, "n42_store.vtp");
    const char* cam = "42.5,1.5,150000,0,-89"; /* over the tile, all of it in view */
    const char* da[] = {"--camera-geo", cam, "--lod", "full", "--patch", "17", dem, "-o", a, NULL};
    const char* sa[] = {"--camera-geo", cam, "--lod", "full", store, "-o", b, NULL};
    tp_mesh_summary ds = export_and_inspect(da), ss = export_and_inspect(sa);
    EXPECT_EQ_INT(ds.points, ss.points);
    EXPECT_EQ_INT(ds.triangles, ss.triangles);
    /* the same samples marked filled: the DEM's render grid knows them, the store (format 4)
     * keeps them */
    tp_test_note("void_filled points: DEM %zu, store %zu", ds.void_filled_points,
                 ss.void_filled_points);
    EXPECT_GT((double)ds.void_filled_points, 1000.0);
    EXPECT_EQ_INT(ds.void_filled_points, ss.void_filled_points);
    double *pa = NULL, *pb = NULL;
    size_t na = 0, nb = 0;
    tp_error e;
    ASSERT_OK(tp_mesh_read_points(a, &pa, &na, &e));
    ASSERT_OK(tp_mesh_read_points(b, &pb, &nb, &e));
    ASSERT_EQ_INT(na, nb);
    ASSERT_GT((double)na, 1e6);
    qsort(pa, na, 3 * sizeof *pa, cmp_xy);
    qsort(pb, nb, 3 * sizeof *pb, cmp_xy);
    size_t moved = 0, higher = 0;
    double worst_xy = 0, worst_z = 0;
    for (size_t i = 0; i < na; i++) {
        for (int c = 0; c < 2; c++) {
            double d = fabs(pa[3 * i + c] - pb[3 * i + c]);
            moved += d > 1e-6;
            worst_xy = d > worst_xy ? d : worst_xy;
        }
        double dz = fabs(pa[3 * i + 2] - pb[3 * i + 2]);
        higher += dz > 0;
        worst_z = dz > worst_z ? dz : worst_z;
    }
    EXPECT_EQ_INT(0, moved);
    EXPECT_LE(worst_xy, 1e-6);
    /* heights: the tile is warped to UTM (bilinear: fractional heights); the DEM path draws
     * them with a fine step, the store keeps whole metres ("quantisation error <= 0.5 m" in
     * its info): within half a step, and some must differ (else this compares nothing) */
    EXPECT_LE(worst_z, 0.5);
    EXPECT_GT((double)higher, 0.0);
    free(pa);
    free(pb);
    remove(a);
    remove(b);
    remove(store);
}

TEST(store_options_for_a_dem_only_are_refused)
{
    char store[1024], out[1024], err[4096];
    out_path(store, sizeof store, "small.tpt");
    const char* files[] = {"storml_elev.tif", NULL};
    build_store(store, "64", files);
    out_path(out, sizeof out, "small.vtp");
    const char* nc[] = {"--no-cull", store, "-o", out, NULL};
    EXPECT_EQ_INT(2, tp_test_run_terrapatch("export", nc, err, sizeof err));
    EXPECT_TRUE(strstr(err, "is a store") != NULL);
    EXPECT_TRUE(access(out, F_OK) != 0);
    remove(store);
}

TEST(damaged_node_fails_and_writes_nothing)
{
    /* a byte flipped in the middle of the file lands in some node's compressed samples: the
     * export reads every node it draws, so it must fail naming the node, with no output */
    char store[1024], out[1024], err[4096];
    out_path(store, sizeof store, "damaged.tpt");
    const char* files[] = {"storml_elev.tif", NULL};
    build_store(store, "64", files);
    FILE* f = fopen(store, "r+b");
    ASSERT_TRUE(f != NULL);
    ASSERT_EQ_INT(0, fseek(f, 0, SEEK_END));
    long size = ftell(f);
    ASSERT_EQ_INT(0, fseek(f, size / 2, SEEK_SET));
    int c = fgetc(f);
    ASSERT_EQ_INT(0, fseek(f, size / 2, SEEK_SET));
    fputc(c ^ 0x5A, f);
    fclose(f);
    out_path(out, sizeof out, "damaged.vtp");
    const char* args[] = {"--full", store, "-o", out, NULL};
    EXPECT_EQ_INT(1, tp_test_run_terrapatch("export", args, err, sizeof err));
    EXPECT_TRUE(strstr(err, "node") != NULL);
    EXPECT_TRUE(access(out, F_OK) != 0);
    remove(store);
}

/* A store's export --full to a .vtp, written in blocks of leaves (issue 29, 1.5), is the mesh of
 * the in-memory writer (.vtk): the same triangles and merged points, the same outline, and the
 * same filled samples (the store's filled bits; N42E001 has voids, filled by the build). */
TEST(full_export_of_a_store_in_pieces_is_the_whole_mesh)
{
    char store[1024], whole[1024], pieces[1024], text[4096], err[4096];
    out_path(store, sizeof store, "n42_pieces.tpt");
    const char* files[] = {"N42E001.hgt", NULL};
    build_store(store, NULL, files);
    out_path(whole, sizeof whole, "n42_whole.vtk");
    out_path(pieces, sizeof pieces, "n42_pieces.vtp");
    const char* wargs[] = {"--full", store, "-o", whole, NULL};
    tp_mesh_summary w = export_and_inspect(wargs);
    setenv("TP_EXPORT_PIECE_SAMPLES", "100000", 1);
    const char* pargs[] = {"--full", store, "-o", pieces, NULL};
    int rc = tp_test_run_terrapatch_out("export", pargs, text, sizeof text, err, sizeof err);
    unsetenv("TP_EXPORT_PIECE_SAMPLES");
    ASSERT_EQ_INT(0, rc);
    tp_mesh_summary p;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(pieces, &p, &e));
    tp_test_note("%s", text);
    EXPECT_GT((double)p.pieces, 10.0);
    EXPECT_EQ_INT(w.triangles, p.triangles);
    EXPECT_EQ_INT(w.points, p.points);
    EXPECT_GT((double)w.void_filled_points, 1000.0);
    EXPECT_EQ_INT(w.void_filled_points, p.void_filled_points);
    EXPECT_EQ_INT(w.boundary_loops, p.boundary_loops);
    EXPECT_EQ_INT(0, p.non_manifold_edges);
    EXPECT_EQ_INT(0, p.downward_triangles);
    for (int i = 0; i < 6; i++)
        EXPECT_EQ_DBL(w.bounds[i], p.bounds[i]);
    remove(whole);
    remove(pieces);
    remove(store);
}

#define TESTS(X)                                                                                   \
    X(seam_store_cuts_are_watertight)                                                              \
    X(void_store_cuts_are_watertight_and_keep_max_error)                                           \
    X(full_export_reports_the_drawn_cells_of_the_full_mesh)                                        \
    X(store_and_dem_exports_have_the_same_points)                                                  \
    X(store_options_for_a_dem_only_are_refused)                                                    \
    X(damaged_node_fails_and_writes_nothing)                                                       \
    X(full_export_of_a_store_in_pieces_is_the_whole_mesh)
TP_TEST_MAIN(TESTS)
