/*
 * test_export.c - `terrapatch export` end to end: the command runs as a child process, the files
 * are read back with VTK (tp_mesh_inspect), and the expectations come from the DEM read on its
 * own (tp_dem_read), not from the export code.
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
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

static int run_export(const char* const* args, char* err, size_t err_cap)
{
    return tp_test_run_terrapatch("export", args, err, err_cap);
}

static void data_path(char* buf, size_t cap, const char* file)
{
    /* not REQUIRE_DATA_FILE: that takes sizeof(buf), the size of a pointer here */
    if (!tp_test_data_path(buf, cap, "TP_SHARED_DATA_DIR", file))
        SKIP("data file %s not found (set TP_SHARED_DATA_DIR)", buf);
}

static void out_path(char* buf, size_t cap, const char* name)
{
    snprintf(buf, cap, "/tmp/tp_export_%ld_%s", (long)getpid(), name);
}

/* Cells of four valid samples, and samples in at least one such cell, counted from the DEM. */
static void full_counts(const tp_dem* d, size_t* cells, size_t* points)
{
    *cells = *points = 0;
    for (int y = 0; y < d->height; y++)
        for (int x = 0; x < d->width; x++) {
            int used = 0;
            for (int dy = -1; dy <= 0 && !used; dy++)
                for (int dx = -1; dx <= 0 && !used; dx++) {
                    int cx = x + dx, cy = y + dy;
                    if (cx < 0 || cy < 0 || cx + 1 >= d->width || cy + 1 >= d->height)
                        continue;
                    const float* h = d->heights;
                    used = !isnan(h[cy * d->width + cx]) && !isnan(h[cy * d->width + cx + 1]) &&
                           !isnan(h[(cy + 1) * d->width + cx]) &&
                           !isnan(h[(cy + 1) * d->width + cx + 1]);
                }
            *points += used && !isnan(d->heights[y * d->width + x]);
            if (x + 1 < d->width && y + 1 < d->height) {
                const float* h = d->heights;
                *cells += !isnan(h[y * d->width + x]) && !isnan(h[y * d->width + x + 1]) &&
                          !isnan(h[(y + 1) * d->width + x]) &&
                          !isnan(h[(y + 1) * d->width + x + 1]);
            }
        }
}

TEST(full_mesh_is_every_valid_cell_in_double_precision)
{
    char dem[1024], out[1024], err[4096];
    data_path(dem, sizeof dem, "storml_elev_orig.tif"); /* NAD83 UTM 12N, 876 nodata at edges */
    out_path(out, sizeof out, "full.vtp");
    const char* args[] = {"--full", dem, "-o", out, NULL};
    ASSERT_EQ_INT(0, run_export(args, err, sizeof err));
    tp_dem* d;
    tp_error e;
    ASSERT_OK(tp_dem_read(dem, &d, &e));
    size_t cells, points;
    full_counts(d, &cells, &points);
    tp_mesh_summary s;
    ASSERT_OK(tp_mesh_inspect(out, &s, &e));
    EXPECT_EQ_INT(2 * cells, s.triangles);
    EXPECT_EQ_INT(points, s.points);
    EXPECT_EQ_INT(0, s.other_cells);
    EXPECT_EQ_INT(1, s.points_are_double);
    EXPECT_TRUE(s.has_elevation && s.has_void_filled && s.has_patch_id && s.has_lod &&
                s.has_max_error);
    EXPECT_TRUE(s.has_crs && s.has_source && s.has_version);
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    /* quantisation is exact for this Int16 DEM: the full mesh has no error */
    EXPECT_EQ_DBL(0.0, s.max_error_m);
    /* the highest sample at its exact elevation; the extent at the exact sample centres */
    EXPECT_EQ_DBL(d->max_m, s.bounds[5]);
    EXPECT_EQ_DBL(d->min_m, s.bounds[4]);
    double e0 = d->geotransform[0] + 0.5 * d->geotransform[1];
    double n0 = d->geotransform[3] + 0.5 * d->geotransform[5];
    EXPECT_GE(s.bounds[0], e0);
    EXPECT_LE(s.bounds[1], d->geotransform[0] + (d->width - 0.5) * d->geotransform[1]);
    EXPECT_LE(s.bounds[3], n0);
    EXPECT_GE(s.bounds[2], d->geotransform[3] + (d->height - 0.5) * d->geotransform[5]);
    /* a bound on a sample centre is a sample centre: (E - e0) / 30 is an integer */
    double col = (s.bounds[0] - e0) / d->geotransform[1];
    EXPECT_EQ_DBL(floor(col), col);
    tp_dem_destroy(d);
    remove(out);
}

TEST(view_dependent_mesh_is_watertight_with_distant_levels)
{
    /* a filled DEM (no voids): the drawn region is one rectangle, so one boundary loop */
    char dem[1024], out[1024], err[4096];
    data_path(dem, sizeof dem, "storml_elev.tif");
    out_path(out, sizeof out, "view.vtp");
    const char* args[] = {"--camera",  "324000,5102000,2700,45,-20",
                          "--lod",     "distance",
                          "--mindist", "100",
                          "--maxdist", "1500",
                          "--exp",     "0.3",
                          "--no-cull", dem,
                          "-o",        out,
                          NULL};
    ASSERT_EQ_INT(0, run_export(args, err, sizeof err));
    tp_mesh_summary s;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(out, &s, &e));
    EXPECT_EQ_INT(1, s.boundary_loops);
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    EXPECT_GT((double)s.triangles, 0.0);
    remove(out);
    /* the same as blocks per patch: still one surface after merging */
    out_path(out, sizeof out, "view.vtm");
    const char* args2[] = {"--camera",  "324000,5102000,2700,45,-20",
                           "--lod",     "distance",
                           "--mindist", "100",
                           "--maxdist", "1500",
                           "--exp",     "0.3",
                           "--no-cull", "--per-patch",
                           dem,         "-o",
                           out,         NULL};
    ASSERT_EQ_INT(0, run_export(args2, err, sizeof err));
    tp_mesh_summary m;
    ASSERT_OK(tp_mesh_inspect(out, &m, &e));
    EXPECT_GT((double)m.blocks, 1.0);
    EXPECT_EQ_INT(s.triangles, m.triangles);
    EXPECT_EQ_INT(1, m.boundary_loops);
    EXPECT_EQ_INT(0, m.non_manifold_edges);
    remove(out);
    char dir[1024];
    snprintf(dir, sizeof dir, "%.*s", (int)(strlen(out) - 4), out);
    /* remove the pieces folder */
    for (size_t b = 0; b < m.blocks; b++) {
        char piece[2200];
        const char* base = strrchr(dir, '/') ? strrchr(dir, '/') + 1 : dir;
        snprintf(piece, sizeof piece, "%s/%s_%zu.vtp", dir, base, b);
        remove(piece);
    }
    rmdir(dir);
}

TEST(view_dependent_mesh_has_the_viewers_triangles)
{
    /* the viewer's statistics are the core's selection: the export of the same camera must
     * hold exactly those triangles (culled patches left out) */
    char dem[1024], out[1024], json[1024], err[4096];
    data_path(dem, sizeof dem, "storml_elev_orig.tif");
    out_path(out, sizeof out, "same.vtp");
    out_path(json, sizeof json, "same.json");
    const char* cam = "324500,5101500,2900,30,-25";
    const char* eargs[] = {"--camera", cam, "--tau", "2", dem, "-o", out, NULL};
    ASSERT_EQ_INT(0, run_export(eargs, err, sizeof err));
    /* --whole: export draws a DEM whole, so the viewer's old path is the one to compare */
    const char* vargs[] = {"--whole",  "--headless", "--no-hud", "--size", "1280x720",
                           "--camera", cam,          "--tau",    "2",      "--stats-json",
                           json,       dem,          NULL};
    int rc = tp_test_run_terrapatch("view", vargs, err, sizeof err);
    if (rc == 1 && strstr(err, "EGL"))
        SKIP("no headless OpenGL here: %s", err);
    ASSERT_EQ_INT(0, rc);
    FILE* f = fopen(json, "r");
    ASSERT_TRUE(f != NULL);
    char text[4096];
    size_t got = fread(text, 1, sizeof text - 1, f);
    text[got] = '\0';
    fclose(f);
    const char* t = strstr(text, "\"triangles\":");
    ASSERT_TRUE(t != NULL);
    double triangles = strtod(t + 12, NULL);
    tp_mesh_summary s;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(out, &s, &e));
    EXPECT_EQ_DBL(triangles, (double)s.triangles);
    EXPECT_GT(triangles, 0.0);
    remove(out);
    remove(json);
}

TEST(max_error_mesh_keeps_its_bound_and_is_smaller)
{
    char dem[1024], out[1024], err[4096];
    data_path(dem, sizeof dem, "storml_elev.tif");
    out_path(out, sizeof out, "max20.vtp");
    const char* args[] = {"--max-error", "20", dem, "-o", out, NULL};
    ASSERT_EQ_INT(0, run_export(args, err, sizeof err));
    tp_mesh_summary s, f;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(out, &s, &e));
    EXPECT_LE(s.max_error_m, 20.0 + TIN_ROUNDING_M);
    EXPECT_EQ_INT(1, s.boundary_loops);
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    char full[1024];
    out_path(full, sizeof full, "max20_full.vtp");
    const char* fargs[] = {"--full", dem, "-o", full, NULL};
    ASSERT_EQ_INT(0, run_export(fargs, err, sizeof err));
    ASSERT_OK(tp_mesh_inspect(full, &f, &e));
    EXPECT_LT((double)s.triangles, 0.8 * (double)f.triangles);
    remove(out);
    remove(full);
}

TEST(max_error_below_quantisation_is_refused)
{
    /* N42E001 is warped to UTM: its heights are no longer integers and quantisation is > 0; the
     * patches hold quantised heights, a TIN the source samples (no floor) */
    char dem[1024], out[1024], err[4096];
    data_path(dem, sizeof dem, "N42E001.hgt");
    out_path(out, sizeof out, "tiny.vtp");
    const char* args[] = {"--max-error", "0.0001", "--mesh", "patches", dem, "-o", out, NULL};
    EXPECT_EQ_INT(2, run_export(args, err, sizeof err));
    EXPECT_CONTAINS(err, "quantisation");
    EXPECT_TRUE(access(out, F_OK) != 0);
}

static int cmp_xy(const void* a, const void* b)
{
    const double *p = a, *q = b;
    for (int i = 0; i < 2; i++)
        if (p[i] != q[i])
            return p[i] < q[i] ? -1 : 1;
    return 0;
}

/* Every point of mesh a is a point of mesh b: the same easting and northing (doubles) and a
 * height within dz_m (b may hold quantised heights); returns a's point count. */
static size_t points_subset(const char* a, const char* b, double dz_m)
{
    double *pa = NULL, *pb = NULL;
    size_t na = 0, nb = 0;
    tp_error e;
    ASSERT_OK(tp_mesh_read_points(a, &pa, &na, &e));
    ASSERT_OK(tp_mesh_read_points(b, &pb, &nb, &e));
    qsort(pb, nb, 3 * sizeof *pb, cmp_xy);
    size_t missing = 0, off = 0;
    for (size_t i = 0; i < na; i++) {
        const double* q = bsearch(pa + 3 * i, pb, nb, 3 * sizeof *pb, cmp_xy);
        missing += !q;
        off += q && fabs(q[2] - pa[3 * i + 2]) > dz_m;
    }
    EXPECT_EQ_INT(0, (int)missing);
    EXPECT_EQ_INT(0, (int)off);
    free(pa);
    free(pb);
    return na;
}

TEST(tin_is_bounded_watertight_and_on_the_full_meshs_points)
{
    /* N42E001 warped to UTM: void margins around the tile, so the TIN is cut at voids */
    char dem[1024], out[1024], full[1024], pat[1024], err[4096];
    data_path(dem, sizeof dem, "N42E001.hgt");
    out_path(out, sizeof out, "tin20.vtp");
    out_path(full, sizeof full, "tin20_full.vtp");
    out_path(pat, sizeof pat, "tin20_patches.vtp");
    const char* args[] = {"--max-error", "20", dem, "-o", out, NULL};
    ASSERT_EQ_INT(0, run_export(args, err, sizeof err));
    const char* fargs[] = {"--full", dem, "-o", full, NULL};
    ASSERT_EQ_INT(0, run_export(fargs, err, sizeof err));
    const char* pargs[] = {"--max-error", "20", "--mesh", "patches", dem, "-o", pat, NULL};
    ASSERT_EQ_INT(0, run_export(pargs, err, sizeof err));
    tp_mesh_summary s, f, p;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(out, &s, &e));
    ASSERT_OK(tp_mesh_inspect(full, &f, &e));
    ASSERT_OK(tp_mesh_inspect(pat, &p, &e));
    /* the bound, measured per triangle; the fields of the other modes but patch_id and lod */
    EXPECT_LE(s.max_error_m, 20.0 + TIN_ROUNDING_M);
    EXPECT_GT(s.max_error_m, 10.0);
    EXPECT_TRUE(s.points_are_double && s.has_elevation && s.has_void_filled && s.has_max_error &&
                s.has_crs && s.has_source && s.has_version);
    EXPECT_TRUE(!s.has_patch_id && !s.has_lod);
    /* watertight over exactly the full mesh's cells: one outline, same extent, no edge shared
     * by three triangles, every vertex a sample of the full mesh */
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    EXPECT_EQ_INT(0, s.downward_triangles);
    EXPECT_EQ_INT(0, f.downward_triangles);
    EXPECT_EQ_INT(f.boundary_loops, s.boundary_loops);
    for (int i = 0; i < 4; i++)
        EXPECT_EQ_DBL(f.bounds[i], s.bounds[i]);
    /* the full mesh holds the terrain's quantised heights (a step of 1/64 m here), the TIN the
     * source samples */
    EXPECT_GT(points_subset(out, full, 1.0 / 64), 1000);
    /* far fewer triangles than the patches at the same bound */
    EXPECT_LT((double)s.triangles, 0.5 * (double)p.triangles);
    printf("N42E001 at 20 m: TIN %zu triangles, patches %zu, full %zu\n", s.triangles, p.triangles,
           f.triangles);
    remove(out);
    remove(full);
    remove(pat);
}

/* FNV-1a over the points' doubles in file order. */
static uint64_t points_hash(const char* path, size_t* count)
{
    double* p = NULL;
    tp_error e;
    ASSERT_OK(tp_mesh_read_points(path, &p, count, &e));
    uint64_t h = 1469598103934665603ull;
    const unsigned char* b = (const unsigned char*)p;
    for (size_t i = 0; i < 3 * *count * sizeof *p; i++)
        h = (h ^ b[i]) * 1099511628211ull;
    free(p);
    return h;
}

TEST(mesh_patches_is_the_max_error_mesh_of_before)
{
    /* Pinned from terrapatch 65b6cee (before --mesh existed: --max-error meant patches), whose
     * file for this command was byte-identical to today's --mesh patches file: 14053 points,
     * 27616 triangles, measured error max 5.000 m, RMS 0.331 m, and these points. */
    char dem[1024], out[1024], err[4096];
    data_path(dem, sizeof dem, "storml_elev.tif");
    out_path(out, sizeof out, "patches5.vtp");
    const char* args[] = {"--max-error", "5", "--mesh", "patches", dem, "-o", out, NULL};
    ASSERT_EQ_INT(0, run_export(args, err, sizeof err));
    tp_mesh_summary s;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(out, &s, &e));
    EXPECT_EQ_INT(14053, s.points);
    EXPECT_EQ_INT(27616, s.triangles);
    EXPECT_TRUE(s.has_patch_id && s.has_lod);
    size_t n = 0;
    uint64_t h = points_hash(out, &n);
    printf("points hash %016llx\n", (unsigned long long)h);
    EXPECT_TRUE(h == 0x163568587a8435e1ull);
    remove(out);
}

TEST(tin_of_a_resampled_fit_keeps_its_bound)
{
    char dem[1024], out[1024], err[4096];
    data_path(dem, sizeof dem, "storml_elev.tif");
    out_path(out, sizeof out, "tin_resample.vtp");
    const char* args[] = {"--max-error", "2", "--fit", "resample", dem, "-o", out, NULL};
    ASSERT_EQ_INT(0, run_export(args, err, sizeof err));
    tp_mesh_summary s;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(out, &s, &e));
    EXPECT_LE(s.max_error_m, 2.0 + TIN_ROUNDING_M);
    EXPECT_EQ_INT(1, s.boundary_loops);
    EXPECT_EQ_INT(0, s.downward_triangles);
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    remove(out);
}

TEST(unwritable_output_fails_and_leaves_nothing)
{
    char dem[1024], err[4096];
    data_path(dem, sizeof dem, "storml_elev.tif");
    const char* args[] = {"--full", dem, "-o", "/nonexistent-dir/mesh.vtp", NULL};
    EXPECT_EQ_INT(1, run_export(args, err, sizeof err));
    EXPECT_CONTAINS(err, "/nonexistent-dir/mesh.vtp");
    EXPECT_TRUE(access("/nonexistent-dir", F_OK) != 0);
}

TEST(invalid_options_are_usage_errors)
{
    char dem[1024], out[1024], err[4096];
    data_path(dem, sizeof dem, "storml_elev.tif");
    out_path(out, sizeof out, "bad.vtp");
    const char* a1[] = {"--max-error", "-1", dem, "-o", out, NULL};
    EXPECT_EQ_INT(2, run_export(a1, err, sizeof err));
    const char* a2[] = {"--per-patch", dem, "-o", out, NULL};
    EXPECT_EQ_INT(2, run_export(a2, err, sizeof err));
    const char* a3[] = {"--full", "--max-error", "5", dem, "-o", out, NULL};
    EXPECT_EQ_INT(2, run_export(a3, err, sizeof err));
    const char* a4[] = {"--full", dem, "-o", "/tmp/mesh.obj", NULL};
    EXPECT_EQ_INT(2, run_export(a4, err, sizeof err));
    const char* a5[] = {"--full", dem, NULL};
    EXPECT_EQ_INT(2, run_export(a5, err, sizeof err));
    const char* a6[] = {"--max-error", "5", "--mesh", "strips", dem, "-o", out, NULL};
    EXPECT_EQ_INT(2, run_export(a6, err, sizeof err));
    EXPECT_CONTAINS(err, "tin or patches");
    const char* a7[] = {"--mesh", "tin", dem, "-o", out, NULL}; /* no --max-error */
    EXPECT_EQ_INT(2, run_export(a7, err, sizeof err));
    const char* a8[] = {"--max-error", "5", "--per-patch", dem, "-o", "/tmp/tp_x.vtm", NULL};
    EXPECT_EQ_INT(2, run_export(a8, err, sizeof err));
    EXPECT_CONTAINS(err, "--mesh patches");
    EXPECT_TRUE(access(out, F_OK) != 0);
}

TEST(origin_local_shifts_points_and_records_it)
{
    char dem[1024], a[1024], b[1024], err[4096];
    data_path(dem, sizeof dem, "storml_elev.tif");
    out_path(a, sizeof a, "true.vtk");
    out_path(b, sizeof b, "local.vtk");
    const char* args[] = {"--full", dem, "-o", a, NULL};
    const char* largs[] = {"--full", "--origin", "local", dem, "-o", b, NULL};
    ASSERT_EQ_INT(0, run_export(args, err, sizeof err));
    ASSERT_EQ_INT(0, run_export(largs, err, sizeof err));
    tp_mesh_summary s, l;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(a, &s, &e));
    ASSERT_OK(tp_mesh_inspect(b, &l, &e));
    EXPECT_EQ_INT(s.triangles, l.triangles);
    /* the origin is a whole kilometre, so the shift is exact */
    double de = s.bounds[0] - l.bounds[0], dn = s.bounds[2] - l.bounds[2];
    EXPECT_EQ_DBL(floor(de / 1000) * 1000, de);
    EXPECT_EQ_DBL(floor(dn / 1000) * 1000, dn);
    EXPECT_GT(de, 0.0);
    EXPECT_EQ_DBL(s.bounds[1] - de, l.bounds[1]);
    remove(a);
    remove(b);
}

/* export --full to a .vtp is written a piece at a time (issue 29, 1.5): cut into many pieces
 * (TP_EXPORT_PIECE_SAMPLES), it is the whole mesh the in-memory writer makes (the .vtk): the same
 * triangles, the same points once the pieces' shared points are merged, the same outline, every
 * triangle counter-clockwise from above, no error. */
TEST(full_export_in_pieces_is_the_whole_mesh)
{
    char dem[1024], whole[1024], pieces[1024], text[4096], err[4096];
    data_path(dem, sizeof dem, "storml_elev_orig.tif"); /* NAD83 UTM 12N, 876 nodata at edges */
    out_path(whole, sizeof whole, "whole.vtk");
    out_path(pieces, sizeof pieces, "pieces.vtp");
    const char* wargs[] = {"--full", dem, "-o", whole, NULL};
    ASSERT_EQ_INT(0, run_export(wargs, err, sizeof err));
    setenv("TP_EXPORT_PIECE_SAMPLES", "1000", 1);
    const char* pargs[] = {"--full", dem, "-o", pieces, NULL};
    int rc = tp_test_run_terrapatch_out("export", pargs, text, sizeof text, err, sizeof err);
    unsetenv("TP_EXPORT_PIECE_SAMPLES");
    ASSERT_EQ_INT(0, rc);
    EXPECT_CONTAINS(text, "pieces of at most");
    tp_mesh_summary w, p;
    tp_error e;
    ASSERT_OK(tp_mesh_inspect(whole, &w, &e));
    ASSERT_OK(tp_mesh_inspect(pieces, &p, &e));
    EXPECT_EQ_INT(1, w.pieces);
    EXPECT_GT((double)p.pieces, 10.0);
    EXPECT_EQ_INT(w.triangles, p.triangles);
    EXPECT_EQ_INT(w.points, p.points); /* merged */
    EXPECT_EQ_INT(w.boundary_loops, p.boundary_loops);
    EXPECT_EQ_INT(w.boundary_edges, p.boundary_edges);
    EXPECT_EQ_INT(0, p.non_manifold_edges);
    EXPECT_EQ_INT(0, p.downward_triangles);
    EXPECT_EQ_INT(0, p.other_cells);
    EXPECT_EQ_DBL(0.0, p.max_error_m);
    EXPECT_TRUE(p.points_are_double && p.has_elevation && p.has_void_filled && p.has_patch_id &&
                p.has_lod && p.has_max_error && p.has_crs && p.has_source && p.has_version);
    for (int i = 0; i < 6; i++)
        EXPECT_EQ_DBL(w.bounds[i], p.bounds[i]);
    /* every point of each is a point of the other (this Int16 DEM quantises exactly) */
    points_subset(whole, pieces, 0.0);
    points_subset(pieces, whole, 0.0);
    remove(whole);
    remove(pieces);
}

#define TESTS(X)                                                                                   \
    X(full_mesh_is_every_valid_cell_in_double_precision)                                           \
    X(view_dependent_mesh_is_watertight_with_distant_levels)                                       \
    X(view_dependent_mesh_has_the_viewers_triangles)                                               \
    X(max_error_mesh_keeps_its_bound_and_is_smaller)                                               \
    X(max_error_below_quantisation_is_refused)                                                     \
    X(tin_is_bounded_watertight_and_on_the_full_meshs_points)                                      \
    X(tin_of_a_resampled_fit_keeps_its_bound)                                                      \
    X(mesh_patches_is_the_max_error_mesh_of_before)                                                \
    X(unwritable_output_fails_and_leaves_nothing)                                                  \
    X(invalid_options_are_usage_errors)                                                            \
    X(origin_local_shifts_points_and_records_it)                                                   \
    X(full_export_in_pieces_is_the_whole_mesh)
TP_TEST_MAIN(TESTS)
