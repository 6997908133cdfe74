/*
 * test_mesh.c - triangle meshes for ParaView (tp_mesh_write, tp_mesh_inspect): small hand-made
 * meshes written as .vtp, .vtk and .vtm and read back with VTK's readers: counts, double
 * coordinates (bounds equal to what was written, bit for bit), arrays and field data, boundary
 * loops and non-manifold edges; and every way a write can fail (bad extension, missing folder,
 * a folder in the way, a full disk), after which nothing may be left behind.
 *
 * Each test works in its own mkdtemp folder, removed at the end (or at exit after a failure).
 */
#define _POSIX_C_SOURCE 200809L /* mkdtemp, dup2 */
#define _XOPEN_SOURCE 700       /* setrlimit */

#include "tp_io.h"
#include "tp_test.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

/* ---------------------------------------------------------------------------------------------
 * A temporary folder per test
 */
static char tmp_dir[256];

static void remove_tree(const char* dir)
{
    DIR* d = opendir(dir);
    struct dirent* ent;
    char path[1024];
    if (d) {
        while ((ent = readdir(d)) != NULL) {
            if (!strcmp(ent->d_name, ".") || !strcmp(ent->d_name, ".."))
                continue;
            snprintf(path, sizeof path, "%s/%s", dir, ent->d_name);
            if (unlink(path) != 0)
                remove_tree(path);
        }
        closedir(d);
    }
    rmdir(dir);
}

static void tmp_end(void)
{
    if (tmp_dir[0])
        remove_tree(tmp_dir);
    tmp_dir[0] = '\0';
}

static void tmp_begin(void)
{
    static int registered;
    const char* base = getenv("TMPDIR");
    if (!registered) {
        atexit(tmp_end);
        registered = 1;
    }
    tmp_end();
    if (!base || !*base)
        base = "/tmp";
    snprintf(tmp_dir, sizeof tmp_dir, "%s/tp_mesh_XXXXXX", base);
    if (!mkdtemp(tmp_dir)) {
        tmp_dir[0] = '\0';
        FAIL("mkdtemp in %s: %s", base, strerror(errno));
    }
}

static void tmp_path(char* buf, size_t cap, const char* file)
{
    ASSERT_TRUE((size_t)snprintf(buf, cap, "%s/%s", tmp_dir, file) < cap);
}

/* The names in dir, sorted and '|'-separated ("" when empty), so that a leftover shows in the
 * failure message. */
static const char* listing(const char* dir)
{
    static char out[2048];
    static char names[64][256];
    int n = 0, i, j;
    DIR* d = opendir(dir);
    struct dirent* ent;
    out[0] = '\0';
    if (!d)
        return "(cannot open)";
    while ((ent = readdir(d)) != NULL && n < 64) {
        if (!strcmp(ent->d_name, ".") || !strcmp(ent->d_name, ".."))
            continue;
        snprintf(names[n++], sizeof names[0], "%.255s", ent->d_name);
    }
    closedir(d);
    for (i = 1; i < n; ++i) /* insertion sort: a handful of names */
        for (j = i; j > 0 && strcmp(names[j - 1], names[j]) > 0; --j) {
            char t[256];
            memcpy(t, names[j], sizeof t);
            memcpy(names[j], names[j - 1], sizeof t);
            memcpy(names[j - 1], t, sizeof t);
        }
    for (i = 0; i < n; ++i) {
        if (i)
            strncat(out, "|", sizeof out - strlen(out) - 1);
        strncat(out, names[i], sizeof out - strlen(out) - 1);
    }
    return out;
}

/* The files in folder dir are exactly these ('|'-separated, sorted). */
#define EXPECT_STR_LISTING_OF(dir, expected)                                                       \
    do {                                                                                           \
        const char* tp_got_ = listing(dir);                                                        \
        TP_CHECK_(0, strcmp(tp_got_, (expected)) == 0, "files in %s: expected \"%s\", got \"%s\"", \
                  (dir), (expected), tp_got_);                                                     \
    } while (0)
/* ... and in the test's folder. */
#define EXPECT_LISTING(expected) EXPECT_STR_LISTING_OF(tmp_dir, expected)

static int exists(const char* path)
{
    struct stat st;
    return stat(path, &st) == 0;
}

/* ---------------------------------------------------------------------------------------------
 * Hand-made meshes
 */
#define TEST_WKT                                                                                   \
    "PROJCRS[\"WGS 84 / UTM zone 31N\",\n    BASEGEOGCRS[\"WGS 84\"],\n    ID[\"EPSG\",32631]]"

typedef struct test_mesh {
    tp_mesh m;
    size_t max_points, max_tris;
    double* xyz;
    double* elevation_m;
    uint8_t* void_filled;
    uint64_t* triangles;
    int32_t* patch_id;
    uint8_t* lod;
    double* max_error_m;
} test_mesh;

static void tm_init(test_mesh* t, size_t max_points, size_t max_tris)
{
    memset(t, 0, sizeof *t);
    t->max_points = max_points;
    t->max_tris = max_tris;
    t->xyz = calloc(3 * max_points, sizeof(double));
    t->elevation_m = calloc(max_points, sizeof(double));
    t->void_filled = calloc(max_points, 1);
    t->triangles = calloc(3 * max_tris, sizeof(uint64_t));
    t->patch_id = calloc(max_tris, sizeof(int32_t));
    t->lod = calloc(max_tris, 1);
    t->max_error_m = calloc(max_tris, sizeof(double));
    ASSERT_TRUE(t->xyz && t->elevation_m && t->void_filled && t->triangles && t->patch_id &&
                t->lod && t->max_error_m);
    t->m.xyz = t->xyz;
    t->m.elevation_m = t->elevation_m;
    t->m.void_filled = t->void_filled;
    t->m.triangles = t->triangles;
    t->m.patch_id = t->patch_id;
    t->m.lod = t->lod;
    t->m.max_error_m = t->max_error_m;
    t->m.crs_wkt = TEST_WKT;
    t->m.epsg = 32631;
    t->m.utm_zone = "31n";
    t->m.source_file = "N45E003.hgt";
    t->m.camera = "45.5,3.5,2000,0,-30";
    t->m.lod_params = "mode=error tau_px=1";
    t->m.program_version = "terrapatch 0.1.0 (test)";
}

static void tm_free(test_mesh* t)
{
    free(t->xyz);
    free(t->elevation_m);
    free(t->void_filled);
    free(t->triangles);
    free(t->patch_id);
    free(t->lod);
    free(t->max_error_m);
    memset(t, 0, sizeof *t);
}

static uint32_t tm_point(test_mesh* t, double x, double y, double z)
{
    size_t i = t->m.point_count++;
    ASSERT_TRUE(i < t->max_points);
    t->xyz[3 * i + 0] = x;
    t->xyz[3 * i + 1] = y;
    t->xyz[3 * i + 2] = z;
    t->elevation_m[i] = z;
    t->void_filled[i] = (uint8_t)(i % 5 == 0);
    return (uint32_t)i;
}

static void tm_tri(test_mesh* t, uint32_t a, uint32_t b, uint32_t c, int32_t patch)
{
    size_t i = t->m.triangle_count++;
    ASSERT_TRUE(i < t->max_tris);
    t->triangles[3 * i + 0] = a;
    t->triangles[3 * i + 1] = b;
    t->triangles[3 * i + 2] = c;
    t->patch_id[i] = patch;
    t->lod[i] = (uint8_t)(2 + patch % 3);
    t->max_error_m[i] = 0.125 * (double)(i % 7) + 0.001 * (double)patch;
}

/* A square of cells x cells quads (2 triangles each, counter-clockwise from above) at
 * projected coordinates that a float cannot hold (5037312.407123 m north). Column i of cells
 * goes to patch patch0 + i / cols_per_patch (all to patch0 when cols_per_patch is 0). */
static void tm_square(test_mesh* t, double x0, double y0, int cells, int cols_per_patch,
                      int32_t patch0)
{
    const double step = 30.0000001;
    uint32_t first = (uint32_t)t->m.point_count;
    int i, j, n = cells + 1;
    for (j = 0; j < n; ++j)
        for (i = 0; i < n; ++i)
            tm_point(t, x0 + i * step, y0 + j * step, 1234.567891 + 7.25 * i - 3.0625 * j);
    for (j = 0; j < cells; ++j)
        for (i = 0; i < cells; ++i) {
            uint32_t a = first + (uint32_t)(j * n + i), b = a + 1, c = a + (uint32_t)n + 1,
                     d = a + (uint32_t)n;
            int32_t p = patch0 + (cols_per_patch ? i / cols_per_patch : 0);
            tm_tri(t, a, b, c, p);
            tm_tri(t, a, c, d, p);
        }
}

#define X0 500000.123456
#define Y0 5037312.407123

/* Writes t to tmp_dir/file and reads it back. */
static tp_mesh_summary write_and_inspect(const test_mesh* t, const char* file, tp_mesh_format f)
{
    char path[512];
    tp_error err;
    tp_mesh_summary s;
    tmp_path(path, sizeof path, file);
    memset(&err, 0, sizeof err);
    if (tp_mesh_write(path, f, &t->m, &err) != TP_OK)
        FAIL("tp_mesh_write(%s): %s", path, err.message);
    memset(&s, 0, sizeof s);
    if (tp_mesh_inspect(path, &s, &err) != TP_OK)
        FAIL("tp_mesh_inspect(%s): %s", path, err.message);
    return s;
}

/* Everything a round trip must keep: counts, doubles, arrays, field data, exact bounds. */
static void expect_round_trip(const test_mesh* t, const tp_mesh_summary* s, size_t stored_points)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    double max_error = -INFINITY;
    size_t i;
    int k;
    for (i = 0; i < t->m.point_count; ++i)
        for (k = 0; k < 3; ++k) {
            lo[k] = fmin(lo[k], t->xyz[3 * i + k]);
            hi[k] = fmax(hi[k], t->xyz[3 * i + k]);
        }
    for (i = 0; i < t->m.triangle_count; ++i)
        max_error = fmax(max_error, t->max_error_m[i]);
    EXPECT_EQ_INT(stored_points, s->points);
    EXPECT_EQ_INT(t->m.triangle_count, s->triangles);
    EXPECT_EQ_INT(0, s->other_cells);
    EXPECT_EQ_INT(1, s->points_are_double);
    EXPECT_EQ_INT(1, s->has_elevation);
    EXPECT_EQ_INT(1, s->has_void_filled);
    EXPECT_EQ_INT(1, s->has_patch_id);
    EXPECT_EQ_INT(1, s->has_lod);
    EXPECT_EQ_INT(1, s->has_max_error);
    EXPECT_EQ_INT(1, s->has_crs);
    EXPECT_EQ_INT(1, s->has_source);
    EXPECT_EQ_INT(1, s->has_version);
    EXPECT_EQ_DBL(max_error, s->max_error_m);
    /* bit for bit: a float would turn 5037312.407123 into 5037312.5 */
    for (k = 0; k < 3; ++k) {
        EXPECT_EQ_DBL(lo[k], s->bounds[2 * k]);
        EXPECT_EQ_DBL(hi[k], s->bounds[2 * k + 1]);
    }
}

/* ---------------------------------------------------------------------------------------------
 * Round trips
 */
TEST(vtp_square_round_trip)
{
    test_mesh t;
    tp_mesh_summary s;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 0, 0);
    s = write_and_inspect(&t, "square.vtp", TP_MESH_DEFAULT);
    expect_round_trip(&t, &s, 9);
    EXPECT_EQ_DBL(Y0, s.bounds[2]); /* the very number written */
    EXPECT_EQ_INT(1, s.boundary_loops);
    EXPECT_EQ_INT(8, s.boundary_edges);
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    EXPECT_EQ_INT(1, s.blocks);
    EXPECT_LISTING("square.vtp");
    tm_free(&t);
    tmp_end();
}

TEST(vtk_square_round_trip)
{
    test_mesh t;
    tp_mesh_summary s;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 0, 0);
    s = write_and_inspect(&t, "square.vtk", TP_MESH_DEFAULT);
    expect_round_trip(&t, &s, 9);
    EXPECT_EQ_DBL(Y0, s.bounds[2]);
    EXPECT_EQ_INT(1, s.boundary_loops);
    EXPECT_EQ_INT(8, s.boundary_edges);
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    EXPECT_EQ_INT(1, s.blocks);
    EXPECT_LISTING("square.vtk");
    tm_free(&t);
    tmp_end();
}

/* Legacy binary files hold strings as raw bytes: the WKT, newlines and quotes included. */
TEST(vtk_keeps_multiline_wkt_bytes)
{
    test_mesh t;
    char path[512];
    FILE* f;
    static char buf[1 << 16];
    size_t n;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 0, 0);
    (void)write_and_inspect(&t, "square.vtk", TP_MESH_VTK);
    tmp_path(path, sizeof path, "square.vtk");
    f = fopen(path, "rb");
    ASSERT_TRUE(f != NULL);
    n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    ASSERT_LE_INT(n, sizeof buf - 2); /* the whole file was read */
    {
        size_t wl = strlen(TEST_WKT), i;
        int found = 0;
        for (i = 0; i + wl <= n && !found; ++i)
            found = memcmp(buf + i, TEST_WKT, wl) == 0;
        EXPECT_TRUE(found);
    }
    tm_free(&t);
    tmp_end();
}

/* A connected surface split into two patches: two blocks of six points each, one loop once
 * the seam points are merged. */
TEST(vtm_two_patches_round_trip)
{
    test_mesh t;
    tp_mesh_summary s;
    char pieces[512];
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 1, 7); /* patches 7 and 8 */
    s = write_and_inspect(&t, "square.vtm", TP_MESH_DEFAULT);
    expect_round_trip(&t, &s, 12);
    EXPECT_EQ_INT(2, s.blocks);
    EXPECT_EQ_INT(1, s.boundary_loops);
    EXPECT_EQ_INT(8, s.boundary_edges);
    EXPECT_EQ_INT(0, s.non_manifold_edges);
    EXPECT_LISTING("square|square.vtm");
    tmp_path(pieces, sizeof pieces, "square");
    EXPECT_STR_LISTING_OF(pieces, "square_0.vtp|square_1.vtp");
    tm_free(&t);
    tmp_end();
}

/* The block names say which patch each block is. */
TEST(vtm_index_names_blocks_by_patch)
{
    test_mesh t;
    char path[512];
    static char buf[4096];
    FILE* f;
    size_t n;
    tmp_begin();
    tm_init(&t, 16, 18);
    tm_square(&t, X0, Y0, 3, 1, -1); /* patches -1, 0, 1 */
    (void)write_and_inspect(&t, "m.vtm", TP_MESH_VTM);
    tmp_path(path, sizeof path, "m.vtm");
    f = fopen(path, "rb");
    ASSERT_TRUE(f != NULL);
    n = fread(buf, 1, sizeof buf - 1, f);
    fclose(f);
    buf[n] = '\0';
    EXPECT_CONTAINS(buf, "name=\"patch_-1\" file=\"m/m_0.vtp\"");
    EXPECT_CONTAINS(buf, "name=\"patch_0\" file=\"m/m_1.vtp\"");
    EXPECT_CONTAINS(buf, "name=\"patch_1\" file=\"m/m_2.vtp\"");
    tm_free(&t);
    tmp_end();
}

/* Writing again replaces the index and the whole folder of pieces: no stale third piece. */
TEST(vtm_rewrite_replaces_pieces)
{
    test_mesh t3, t2;
    tp_mesh_summary s;
    char pieces[512];
    tmp_begin();
    tm_init(&t3, 16, 18);
    tm_square(&t3, X0, Y0, 3, 1, 0);
    tm_init(&t2, 9, 8);
    tm_square(&t2, X0, Y0, 2, 1, 0);
    s = write_and_inspect(&t3, "m.vtm", TP_MESH_DEFAULT);
    EXPECT_EQ_INT(3, s.blocks);
    s = write_and_inspect(&t2, "m.vtm", TP_MESH_DEFAULT);
    EXPECT_EQ_INT(2, s.blocks);
    EXPECT_EQ_INT(8, s.triangles);
    EXPECT_LISTING("m|m.vtm");
    tmp_path(pieces, sizeof pieces, "m");
    EXPECT_STR_LISTING_OF(pieces, "m_0.vtp|m_1.vtp");
    tm_free(&t3);
    tm_free(&t2);
    tmp_end();
}

TEST(vtp_rewrite_replaces_file)
{
    test_mesh t3, t2;
    tp_mesh_summary s;
    tmp_begin();
    tm_init(&t3, 16, 18);
    tm_square(&t3, X0, Y0, 3, 0, 0);
    tm_init(&t2, 9, 8);
    tm_square(&t2, X0, Y0, 2, 0, 0);
    s = write_and_inspect(&t3, "m.vtp", TP_MESH_DEFAULT);
    EXPECT_EQ_INT(18, s.triangles);
    s = write_and_inspect(&t2, "m.vtp", TP_MESH_DEFAULT);
    EXPECT_EQ_INT(8, s.triangles);
    EXPECT_LISTING("m.vtp");
    tm_free(&t3);
    tm_free(&t2);
    tmp_end();
}

/* ---------------------------------------------------------------------------------------------
 * Topology
 */
static const tp_mesh_format all_formats[3] = {TP_MESH_VTP, TP_MESH_VTK, TP_MESH_VTM};
static const char* const all_names[3] = {"m.vtp", "m.vtk", "m.vtm"};

TEST(two_squares_have_two_loops)
{
    test_mesh t;
    int f;
    tmp_begin();
    tm_init(&t, 18, 16);
    tm_square(&t, X0, Y0, 2, 0, 0);
    tm_square(&t, X0 + 1000.0, Y0, 2, 0, 1);
    for (f = 0; f < 3; ++f) {
        tp_mesh_summary s = write_and_inspect(&t, all_names[f], all_formats[f]);
        EXPECT_EQ_INT(2, s.boundary_loops);
        EXPECT_EQ_INT(16, s.boundary_edges);
        EXPECT_EQ_INT(0, s.non_manifold_edges);
        EXPECT_EQ_INT(16, s.triangles);
        EXPECT_EQ_INT(f == 2 ? 2 : 1, s.blocks);
    }
    tm_free(&t);
    tmp_end();
}

/* Three triangles on one edge (a fan of fins): that edge is non-manifold. */
TEST(edge_of_three_triangles_is_non_manifold)
{
    test_mesh t;
    uint32_t a, b, c, d, e;
    int f;
    tmp_begin();
    tm_init(&t, 5, 3);
    a = tm_point(&t, X0, Y0, 100);
    b = tm_point(&t, X0 + 30, Y0, 100);
    c = tm_point(&t, X0 + 15, Y0 + 30, 100);
    d = tm_point(&t, X0 + 15, Y0 - 30, 100);
    e = tm_point(&t, X0 + 15, Y0, 130);
    tm_tri(&t, a, b, c, 0);
    tm_tri(&t, b, a, d, 0);
    tm_tri(&t, a, b, e, 1);
    for (f = 0; f < 3; ++f) {
        tp_mesh_summary s = write_and_inspect(&t, all_names[f], all_formats[f]);
        EXPECT_EQ_INT(1, s.non_manifold_edges);
        EXPECT_EQ_INT(6, s.boundary_edges);
        EXPECT_EQ_INT(3, s.triangles);
    }
    tm_free(&t);
    tmp_end();
}

/* A square with a square hole: two loops, and all of the ring in one piece. */
TEST(ring_has_two_loops)
{
    test_mesh t;
    int i, j;
    tmp_begin();
    tm_init(&t, 16, 18);
    tm_square(&t, X0, Y0, 3, 0, 0);
    /* drop the middle cell (triangles 8 and 9) */
    for (i = 8; i < 16; ++i)
        for (j = 0; j < 3; ++j)
            t.triangles[3 * i + j] = t.triangles[3 * (i + 2) + j];
    t.m.triangle_count = 16;
    {
        tp_mesh_summary s = write_and_inspect(&t, "ring.vtp", TP_MESH_DEFAULT);
        EXPECT_EQ_INT(2, s.boundary_loops);
        EXPECT_EQ_INT(16, s.boundary_edges);
        EXPECT_EQ_INT(0, s.non_manifold_edges);
    }
    tm_free(&t);
    tmp_end();
}

/* ---------------------------------------------------------------------------------------------
 * Optional parts
 */
TEST(null_arrays_and_strings_are_left_out)
{
    test_mesh t;
    int f;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 0, 0);
    t.m.elevation_m = NULL;
    t.m.void_filled = NULL;
    t.m.lod = NULL;
    t.m.max_error_m = NULL;
    t.m.crs_wkt = "";
    t.m.source_file = NULL;
    t.m.program_version = NULL;
    t.m.utm_zone = t.m.camera = t.m.lod_params = NULL;
    for (f = 0; f < 3; ++f) {
        tp_mesh_summary s = write_and_inspect(&t, all_names[f], all_formats[f]);
        EXPECT_EQ_INT(8, s.triangles);
        EXPECT_EQ_INT(0, s.has_elevation);
        EXPECT_EQ_INT(0, s.has_void_filled);
        EXPECT_EQ_INT(1, s.has_patch_id);
        EXPECT_EQ_INT(0, s.has_lod);
        EXPECT_EQ_INT(0, s.has_max_error);
        EXPECT_NAN(s.max_error_m);
        EXPECT_EQ_INT(0, s.has_crs);
        EXPECT_EQ_INT(0, s.has_source);
        EXPECT_EQ_INT(0, s.has_version);
    }
    tm_free(&t);
    tmp_end();
}

/* No patch ids in a .vtm: one block of everything. */
TEST(vtm_without_patch_ids_is_one_block)
{
    test_mesh t;
    tp_mesh_summary s;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 1, 0);
    t.m.patch_id = NULL;
    s = write_and_inspect(&t, "m.vtm", TP_MESH_DEFAULT);
    EXPECT_EQ_INT(1, s.blocks);
    EXPECT_EQ_INT(9, s.points);
    EXPECT_EQ_INT(0, s.has_patch_id);
    tm_free(&t);
    tmp_end();
}

TEST(empty_mesh_round_trip)
{
    test_mesh t;
    int f;
    tmp_begin();
    tm_init(&t, 1, 1);
    for (f = 0; f < 3; ++f) {
        tp_mesh_summary s = write_and_inspect(&t, all_names[f], all_formats[f]);
        EXPECT_EQ_INT(0, s.points);
        EXPECT_EQ_INT(0, s.triangles);
        EXPECT_EQ_INT(0, s.boundary_loops);
        EXPECT_NAN(s.bounds[0]);
        EXPECT_EQ_INT(f == 2 ? 0 : 1, s.blocks);
    }
    EXPECT_LISTING("m.vtk|m.vtm|m.vtp"); /* no folder for a .vtm of no blocks */
    tm_free(&t);
    tmp_end();
}

TEST(extension_is_case_insensitive)
{
    test_mesh t;
    tp_mesh_summary s;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 0, 0);
    s = write_and_inspect(&t, "SQUARE.VTP", TP_MESH_DEFAULT);
    EXPECT_EQ_INT(8, s.triangles);
    tm_free(&t);
    tmp_end();
}

/* ---------------------------------------------------------------------------------------------
 * Failures: the status, a message naming the path, nothing left behind
 */
/* tp_mesh_write(tmp_dir/file) must fail with `status` and a message naming the path and
 * holding `needle`, leave the folder's listing at `listing_after`; also with a NULL tp_error. */
static void expect_write_refused(const test_mesh* t, const char* file, tp_mesh_format f,
                                 tp_status status, const char* needle, const char* listing_after)
{
    char path[512];
    tp_error err;
    if (file[0] == '/')
        snprintf(path, sizeof path, "%s", file);
    else
        tmp_path(path, sizeof path, file);
    memset(&err, 0, sizeof err);
    EXPECT_STATUS(status, tp_mesh_write(path, f, &t->m, &err));
    tp_test_note("%s", err.message);
    EXPECT_CONTAINS(err.message, path);
    if (needle)
        EXPECT_CONTAINS(err.message, needle);
    EXPECT_LISTING(listing_after);
    EXPECT_STATUS(status, tp_mesh_write(path, f, &t->m, NULL));
    EXPECT_LISTING(listing_after);
}

TEST(bad_extension_is_invalid_arg)
{
    test_mesh t;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 0, 0);
    expect_write_refused(&t, "mesh.obj", TP_MESH_DEFAULT, TP_ERR_INVALID_ARG, ".vtp, .vtk or .vtm",
                         "");
    expect_write_refused(&t, "mesh", TP_MESH_DEFAULT, TP_ERR_INVALID_ARG, NULL, "");
    expect_write_refused(&t, "mesh", TP_MESH_VTM, TP_ERR_INVALID_ARG, "extension", "");
    expect_write_refused(&t, "mesh.vtp", (tp_mesh_format)42, TP_ERR_INVALID_ARG, NULL, "");
    tm_free(&t);
    tmp_end();
}

TEST(point_index_out_of_range_is_invalid_arg)
{
    test_mesh t;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 0, 0);
    t.triangles[3 * 5 + 1] = 9;
    expect_write_refused(&t, "m.vtp", TP_MESH_DEFAULT, TP_ERR_INVALID_ARG, "triangle 5", "");
    expect_write_refused(&t, "m.vtm", TP_MESH_DEFAULT, TP_ERR_INVALID_ARG, "triangle 5", "");
    tm_free(&t);
    tmp_end();
}

TEST(missing_folder_is_io_error)
{
    test_mesh t;
    int f;
    static const char* const paths[3] = {"/nonexistent-dir/x.vtp", "/nonexistent-dir/x.vtk",
                                         "/nonexistent-dir/x.vtm"};
    if (exists("/nonexistent-dir"))
        SKIP("/nonexistent-dir exists on this machine");
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 1, 0);
    for (f = 0; f < 3; ++f) {
        expect_write_refused(&t, paths[f], TP_MESH_DEFAULT, TP_ERR_IO, "No such file or directory",
                             "");
        EXPECT_FALSE(exists("/nonexistent-dir")); /* not created on the way */
    }
    tm_free(&t);
    tmp_end();
}

/* A folder where the file should go: the rename fails; no temporary file stays. */
TEST(folder_in_the_way_is_io_error)
{
    test_mesh t;
    char path[512];
    int f;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 1, 0);
    for (f = 0; f < 3; ++f) {
        char expected[64];
        tmp_path(path, sizeof path, all_names[f]);
        ASSERT_EQ_INT(0, mkdir(path, 0777));
        snprintf(expected, sizeof expected, "%s", all_names[f]);
        expect_write_refused(&t, all_names[f], TP_MESH_DEFAULT, TP_ERR_IO, NULL, expected);
        EXPECT_STR_LISTING_OF(path, ""); /* the folder in the way is untouched */
        ASSERT_EQ_INT(0, rmdir(path));
    }
    tm_free(&t);
    tmp_end();
}

/* The index cannot be renamed into place: the new pieces are taken back and the old ones
 * restored, so the earlier mesh's folder is as it was. */
TEST(vtm_failed_rename_restores_old_pieces)
{
    test_mesh t2, t3;
    char index[512], pieces[512];
    tmp_begin();
    tm_init(&t2, 9, 8);
    tm_square(&t2, X0, Y0, 2, 1, 0);
    tm_init(&t3, 16, 18);
    tm_square(&t3, X0, Y0, 3, 1, 0);
    (void)write_and_inspect(&t2, "m.vtm", TP_MESH_DEFAULT);
    tmp_path(index, sizeof index, "m.vtm");
    ASSERT_EQ_INT(0, unlink(index));
    ASSERT_EQ_INT(0, mkdir(index, 0777)); /* a folder where the index goes */
    expect_write_refused(&t3, "m.vtm", TP_MESH_DEFAULT, TP_ERR_IO, "Is a directory", "m|m.vtm");
    tmp_path(pieces, sizeof pieces, "m");
    EXPECT_STR_LISTING_OF(pieces, "m_0.vtp|m_1.vtp");
    EXPECT_STR_LISTING_OF(index, "");
    tm_free(&t2);
    tm_free(&t3);
    tmp_end();
}

/* x.vtm's pieces go in x/: a folder x/ holding anything else is not replaced. */
TEST(vtm_keeps_a_foreign_folder)
{
    test_mesh t;
    char dir[512], file[512];
    FILE* f;
    tmp_begin();
    tm_init(&t, 9, 8);
    tm_square(&t, X0, Y0, 2, 1, 0);
    tmp_path(dir, sizeof dir, "m");
    ASSERT_EQ_INT(0, mkdir(dir, 0777));
    tmp_path(file, sizeof file, "m/notes.txt");
    f = fopen(file, "w");
    ASSERT_TRUE(f != NULL);
    fputs("mine\n", f);
    fclose(f);
    expect_write_refused(&t, "m.vtm", TP_MESH_DEFAULT, TP_ERR_IO, "not replacing", "m");
    EXPECT_STR_LISTING_OF(dir, "notes.txt");
    tm_free(&t);
    tmp_end();
}

/* A full disk, as a file size limit: write() fails part way with EFBIG. */
TEST(full_disk_is_io_error_and_leaves_nothing)
{
    test_mesh t;
    struct rlimit old, small;
    int f;
    tmp_begin();
    tm_init(&t, 33 * 33, 2 * 32 * 32);
    tm_square(&t, X0, Y0, 32, 8, 0);
    ASSERT_EQ_INT(0, getrlimit(RLIMIT_FSIZE, &old));
    small = old;
    small.rlim_cur = 2000; /* bytes: the index of a .vtm fits, its pieces do not */
    signal(SIGXFSZ, SIG_IGN);
    ASSERT_EQ_INT(0, setrlimit(RLIMIT_FSIZE, &small));
    for (f = 0; f < 3; ++f)
        expect_write_refused(&t, all_names[f], TP_MESH_DEFAULT, TP_ERR_IO, "File too large", "");
    ASSERT_EQ_INT(0, setrlimit(RLIMIT_FSIZE, &old));
    signal(SIGXFSZ, SIG_DFL);
    /* and it all works again */
    for (f = 0; f < 3; ++f) {
        tp_mesh_summary s = write_and_inspect(&t, all_names[f], all_formats[f]);
        EXPECT_EQ_INT(2048, s.triangles);
        EXPECT_EQ_INT(1, s.boundary_loops);
    }
    tm_free(&t);
    tmp_end();
}

/* ---------------------------------------------------------------------------------------------
 * Reading bad files
 */
static void write_text(const char* file, const char* text)
{
    char path[512];
    FILE* f;
    tmp_path(path, sizeof path, file);
    f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    fputs(text, f);
    fclose(f);
}

/* tp_mesh_inspect(tmp_dir/file) fails with `status`, names the path, leaves *out alone. */
static void expect_inspect_refused(const char* file, tp_status status)
{
    char path[512];
    tp_error err;
    tp_mesh_summary s;
    tmp_path(path, sizeof path, file);
    memset(&err, 0, sizeof err);
    memset(&s, 0xAB, sizeof s);
    EXPECT_STATUS(status, tp_mesh_inspect(path, &s, &err));
    tp_test_note("%s", err.message);
    EXPECT_CONTAINS(err.message, path);
    EXPECT_EQ_INT(0xABABABABABABABABull, (unsigned long long)s.points);
    EXPECT_STATUS(status, tp_mesh_inspect(path, &s, NULL));
}

TEST(inspect_refuses_bad_files)
{
    tmp_begin();
    expect_inspect_refused("missing.vtp", TP_ERR_IO);
    write_text("mesh.obj", "v 0 0 0\n");
    expect_inspect_refused("mesh.obj", TP_ERR_INVALID_ARG);
    write_text("empty.vtp", "");
    expect_inspect_refused("empty.vtp", TP_ERR_BAD_DATA);
    write_text("garbage.vtp", "this is not XML at all\n");
    expect_inspect_refused("garbage.vtp", TP_ERR_BAD_DATA);
    write_text("garbage.vtk", "# vtk DataFile Version 4.2\nnonsense\nBINARY\nDATASET TEAPOT\n");
    expect_inspect_refused("garbage.vtk", TP_ERR_BAD_DATA);
    write_text("garbage.vtm",
               "<?xml version=\"1.0\"?>\n<VTKFile type=\"vtkMultiBlockDataSet\" "
               "version=\"1.0\">\n<vtkMultiBlockDataSet>\n<DataSet index=\"0\" "
               "file=\"nowhere/piece.vtp\"/>\n</vtkMultiBlockDataSet>\n</VTKFile>\n");
    expect_inspect_refused("garbage.vtm", TP_ERR_BAD_DATA);
    tmp_end();
}

/* VTK's own messages never reach stderr: the only message is ours. */
TEST(vtk_prints_nothing)
{
    char path[512], log[512];
    int saved, fd;
    struct stat st;
    tmp_begin();
    write_text("garbage.vtp", "<VTKFile type=\"PolyData\"><PolyData><Piece");
    write_text("garbage.vtk", "# vtk DataFile Version 4.2\nx\nASCII\nDATASET POLYDATA\nPOINTS 9");
    tmp_path(log, sizeof log, "stderr.txt");
    fflush(stderr);
    saved = dup(2);
    fd = open(log, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    ASSERT_TRUE(saved >= 0 && fd >= 0);
    dup2(fd, 2);
    close(fd);
    tmp_path(path, sizeof path, "garbage.vtp");
    (void)tp_mesh_inspect(path, &(tp_mesh_summary){0}, NULL);
    tmp_path(path, sizeof path, "garbage.vtk");
    (void)tp_mesh_inspect(path, &(tp_mesh_summary){0}, NULL);
    fflush(stderr);
    dup2(saved, 2);
    close(saved);
    ASSERT_EQ_INT(0, stat(log, &st));
    EXPECT_EQ_INT(0, st.st_size);
    tmp_end();
}

/* Point and triangle counts are size_t and checked against each format's limits without
 * building anything: past 2^31 points (where the export's int32 point numbering wrapped) a mesh
 * still fits VTK's 64-bit ids; beyond vtkIdType it is refused with a message naming the limit. */
TEST(size_check_follows_vtk_id_limits)
{
    const tp_mesh_format formats[3] = {TP_MESH_VTP, TP_MESH_VTK, TP_MESH_VTM};
    const size_t past_int32 = ((size_t)1 << 31) + 1;
    const size_t id_max = (size_t)INT64_MAX;
    tp_error err;
    int f;
    for (f = 0; f < 3; ++f) {
        EXPECT_OK(tp_mesh_check_size(formats[f], past_int32, past_int32, &err));
        EXPECT_OK(tp_mesh_check_size(formats[f], ((size_t)1 << 32) + 1, 3, &err));
        EXPECT_OK(tp_mesh_check_size(formats[f], id_max, (id_max - 1) / 3, &err));

        memset(&err, 0, sizeof err);
        EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_mesh_check_size(formats[f], id_max + 1, 1, &err));
        EXPECT_TRUE(strstr(err.message, "9223372036854775808 points") != NULL);
        EXPECT_TRUE(strstr(err.message, "9223372036854775807") != NULL);
        EXPECT_TRUE(strstr(err.message, "vtkIdType") != NULL);

        memset(&err, 0, sizeof err);
        EXPECT_STATUS(TP_ERR_INVALID_ARG,
                      tp_mesh_check_size(formats[f], 3, (id_max - 1) / 3 + 1, &err));
        EXPECT_TRUE(strstr(err.message, "triangles") != NULL);
        EXPECT_TRUE(strstr(err.message, "vtkIdType") != NULL);
        EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_mesh_check_size(formats[f], 3, SIZE_MAX, NULL));
    }
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_mesh_check_size((tp_mesh_format)7, 3, 1, &err));
}

#define TESTS(X)                                                                                   \
    X(vtp_square_round_trip)                                                                       \
    X(size_check_follows_vtk_id_limits)                                                            \
    X(vtk_square_round_trip)                                                                       \
    X(vtk_keeps_multiline_wkt_bytes)                                                               \
    X(vtm_two_patches_round_trip)                                                                  \
    X(vtm_index_names_blocks_by_patch)                                                             \
    X(vtm_rewrite_replaces_pieces)                                                                 \
    X(vtp_rewrite_replaces_file)                                                                   \
    X(two_squares_have_two_loops)                                                                  \
    X(edge_of_three_triangles_is_non_manifold)                                                     \
    X(ring_has_two_loops)                                                                          \
    X(null_arrays_and_strings_are_left_out)                                                        \
    X(vtm_without_patch_ids_is_one_block)                                                          \
    X(empty_mesh_round_trip)                                                                       \
    X(extension_is_case_insensitive)                                                               \
    X(bad_extension_is_invalid_arg)                                                                \
    X(point_index_out_of_range_is_invalid_arg)                                                     \
    X(missing_folder_is_io_error)                                                                  \
    X(folder_in_the_way_is_io_error)                                                               \
    X(vtm_failed_rename_restores_old_pieces)                                                       \
    X(vtm_keeps_a_foreign_folder)                                                                  \
    X(full_disk_is_io_error_and_leaves_nothing)                                                    \
    X(inspect_refuses_bad_files)                                                                   \
    X(vtk_prints_nothing)
TP_TEST_MAIN(TESTS)
