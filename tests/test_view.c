/*
 * test_view.c - the viewer, rendered headless: `terrapatch view --headless` runs as a child
 * process (posix_spawn, an argument vector, no shell) on the sample DEM
 * data/lf_elev_220_mt_hood_utm.tif (NAD83 / UTM 10N, 1013 x 799, 30 m), writes PNGs and
 * statistics JSON into a temporary directory, and the test reads them back
 * (tp_image_read_rgba) and checks pixels and numbers:
 *
 *   - no cracks: with a magenta background and a view that is ground from edge to edge, not one
 *     magenta pixel may show, under LoD settings that put neighbours several levels apart;
 *   - precision: the DEM at its true UTM coordinates and moved to a local origin renders alike;
 *   - the statistics JSON equals the core's selection computed in this process;
 *   - frustum culling (looking at the sky, looking away from patches behind);
 *   - one reference image (tests/reference/mt_hood_480x270.png) within a tolerance;
 *   - bad command lines: exit status and one-line messages.
 *
 * The binary comes from the environment: TP_TERRAPATCH (tests/CMakeLists.txt sets it to
 * $<TARGET_FILE:terrapatch>); without it every test here skips. The reference directory comes
 * from TP_TEST_REFERENCE_DIR, else <sample data dir>/../tests/reference.
 *
 * Regenerating the reference image (only after a deliberate change of what the viewer draws:
 * shading, colours, LoD defaults, camera conventions; never to make a failing test pass
 * without looking at the difference), from the repository root:
 *
 *   ./build/terrapatch view --headless --no-hud --size 480x270 \
 *       --camera 598000,5012000,4500,15,-35 --screenshot tests/reference/mt_hood_480x270.png \
 *       data/lf_elev_220_mt_hood_utm.tif
 *
 * then look at the new image and commit it with the change that explains it. A failing
 * comparison writes the image it got to mt_hood_480x270.actual.png in the test's working
 * directory (build/tests).
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"
#include "tp_test_child.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>


#define SAMPLE_DEM "lf_elev_220_mt_hood_utm.tif"
#define REFERENCE_PNG "mt_hood_480x270.png"
#define DEG (3.14159265358979323846 / 180.0)

#ifdef TP_TEST_NO_IO
#define REQUIRE_IO() SKIP("built without tp_io")
#else
#define REQUIRE_IO() ((void)0)

#define TP_TMP_PREFIX "tp_view_"
#include "tp_test_tmp.h"

/* ---------------------------------------------------------------------------------------------
 * Running terrapatch
 */
typedef struct args {
    char* v[64];
    int n;
    char buf[8192];
    size_t used;
} args;

static void args_add(args* a, const char* fmt, ...)
{
    va_list ap;
    int len;
    ASSERT_TRUE(a->n + 1 < (int)(sizeof a->v / sizeof a->v[0]));
    va_start(ap, fmt);
    len = vsnprintf(a->buf + a->used, sizeof a->buf - a->used, fmt, ap);
    va_end(ap);
    ASSERT_TRUE(len >= 0 && (size_t)len < sizeof a->buf - a->used);
    a->v[a->n++] = a->buf + a->used;
    a->v[a->n] = NULL;
    a->used += (size_t)len + 1;
}

/* argv[0] = the binary, argv[1] = "view"; skips the test without a binary. */
static void args_view(args* a)
{
    const char* exe = getenv("TP_TERRAPATCH");
    if (!exe || !*exe)
        SKIP("TP_TERRAPATCH is not set (the terrapatch binary; set by tests/CMakeLists.txt)");
    if (access(exe, X_OK) != 0)
        SKIP("TP_TERRAPATCH=%s is not an executable", exe);
    memset(a, 0, sizeof *a);
    args_add(a, "%s", exe);
    args_add(a, "view");
}

typedef struct run_result {
    int exit_code;  /* exit status, or 128 + signal */
    char out[4096]; /* the start of stdout */
    char err[4096]; /* the start of stderr */
    int err_lines;  /* '\n' in all of stderr */
} run_result;

static void read_text(const char* path, char* buf, size_t cap, int* lines)
{
    FILE* f = fopen(path, "rb");
    size_t n = 0;
    int c;
    buf[0] = '\0';
    if (lines)
        *lines = 0;
    if (!f)
        return;
    while ((c = fgetc(f)) != EOF) {
        if (n + 1 < cap)
            buf[n++] = (char)c;
        if (c == '\n' && lines)
            ++*lines;
    }
    buf[n] = '\0';
    fclose(f);
}

/* Runs a->v with stdin from /dev/null and stdout/stderr into files of log_dir. */
static void run(const args* a, const char* log_dir, run_result* r)
{
    char out_path[1024], err_path[1024], asan[1024];
    posix_spawn_file_actions_t fa;
    pid_t pid;
    int status = 0, rc;
    memset(r, 0, sizeof *r);
    snprintf(out_path, sizeof out_path, "%s/child.stdout", log_dir);
    snprintf(err_path, sizeof err_path, "%s/child.stderr", log_dir);
    ASSERT_EQ_INT(0, posix_spawn_file_actions_init(&fa));
    posix_spawn_file_actions_addopen(&fa, 0, "/dev/null", O_RDONLY, 0);
    posix_spawn_file_actions_addopen(&fa, 1, out_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_addopen(&fa, 2, err_path, O_WRONLY | O_CREAT | O_TRUNC, 0644);
    rc = posix_spawn(&pid, a->v[0], &fa, NULL, a->v, tp_test_child_environment(asan, sizeof asan));
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0)
        FAIL("posix_spawn(%s): %s", a->v[0], strerror(rc));
    while (waitpid(pid, &status, 0) < 0)
        if (errno != EINTR)
            FAIL("waitpid: %s", strerror(errno));
    r->exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
    read_text(out_path, r->out, sizeof r->out, NULL);
    read_text(err_path, r->err, sizeof r->err, &r->err_lines);
    remove(out_path);
    remove(err_path);
}

/* Runs and requires exit status 0 (printing stderr otherwise). */
static void run_ok(const args* a, const char* log_dir)
{
    run_result r;
    run(a, log_dir, &r);
    /* no EGL / OpenGL 3.3 on this machine (app/gl_context.c): a missing backend, not a bug */
    if (r.exit_code == 1 && (strstr(r.err, "no EGL surfaceless display") ||
                             strstr(r.err, "no OpenGL 3.3 core context through EGL")))
        SKIP("no headless OpenGL here: %s", r.err);
    if (r.exit_code != 0) {
        int i;
        fprintf(stderr, "command:");
        for (i = 0; i < a->n; ++i)
            fprintf(stderr, " %s", a->v[i]);
        FAIL("exit status %d, stderr: %s", r.exit_code, r.err);
    }
}

/* ---------------------------------------------------------------------------------------------
 * A view: camera, image size, LoD, background. Numbers are passed with %.17g, so the child
 * parses exactly the doubles this process uses.
 */
typedef struct view_spec {
    double cam[5]; /* E, N, H, yaw, pitch */
    int w, h;
    tp_lod_params lod; /* mode TP_LOD_DEFAULT: no --lod option (the CLI default, error, tau 1) */
    int magenta;       /* --clear-color 1,0,1 */
    int store;         /* through a store (the default path); 0: --whole, the old path, whose
                          tp_selection these tests compute in-process to compare with */
    int stitch_add;    /* --stitch add */
} view_spec;

/* --stitch-add-draw for a view's --stitch add (NULL: the default) */
static const char* add_draw_;

static void args_add_view(args* a, const char* dem, const view_spec* v)
{
    if (!v->store)
        args_add(a, "--whole");
    if (v->stitch_add) {
        args_add(a, "--stitch");
        args_add(a, "add");
    }
    if (v->stitch_add && add_draw_) {
        args_add(a, "--stitch-add-draw");
        args_add(a, "%s", add_draw_);
    }
    args_add(a, "--headless");
    args_add(a, "--no-hud"); /* the terrain only: the HUD has timings and the camera's position */
    args_add(a, "--size");
    args_add(a, "%dx%d", v->w, v->h);
    args_add(a, "--camera");
    args_add(a, "%.17g,%.17g,%.17g,%.17g,%.17g", v->cam[0], v->cam[1], v->cam[2], v->cam[3],
             v->cam[4]);
    if (v->lod.mode == TP_LOD_DISTANCE) {
        args_add(a, "--lod");
        args_add(a, "distance");
        args_add(a, "--mindist");
        args_add(a, "%.17g", v->lod.mindist_m);
        args_add(a, "--maxdist");
        args_add(a, "%.17g", v->lod.maxdist_m);
        args_add(a, "--exp");
        args_add(a, "%.17g", v->lod.exponent);
    } else if (v->lod.mode == TP_LOD_ERROR) {
        args_add(a, "--lod");
        args_add(a, "error");
        args_add(a, "--tau");
        args_add(a, "%.17g", v->lod.tau_px);
    } else if (v->lod.mode == TP_LOD_FULL) {
        args_add(a, "--lod");
        args_add(a, "full");
    }
    if (v->magenta) {
        args_add(a, "--clear-color");
        args_add(a, "1,0,1");
    }
    args_add(a, "%s", dem);
}

/* Renders v into dir/<name>.png and dir/<name>.json (either may be skipped with NULL), with
 * --stitch stitch unless NULL. */
static void render_stitch(const char* dem, const view_spec* v, const char* dir, const char* png,
                          const char* json, const char* stitch)
{
    args a;
    args_view(&a);
    if (stitch) {
        args_add(&a, "--stitch");
        args_add(&a, "%s", stitch);
    }
    if (stitch && add_draw_) {
        args_add(&a, "--stitch-add-draw");
        args_add(&a, "%s", add_draw_);
    }
    if (png) {
        args_add(&a, "--screenshot");
        args_add(&a, "%s/%s", dir, png);
    }
    if (json) {
        args_add(&a, "--stats-json");
        args_add(&a, "%s/%s", dir, json);
    }
    args_add_view(&a, dem, v);
    run_ok(&a, dir);
}

static void render(const char* dem, const view_spec* v, const char* dir, const char* png,
                   const char* json)
{
    render_stitch(dem, v, dir, png, json, NULL);
}

/* The sample DEM's path (skips when it is missing). */
static const char* sample_dem(void)
{
    static char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SAMPLE_DATA_DIR", SAMPLE_DEM);
    return path;
}

static const view_spec distance_lod_view = {
    {0, 0, 0, 0, 0},
    640,
    360,
    {.mode = TP_LOD_DISTANCE, .mindist_m = 300, .maxdist_m = 4000, .exponent = 0.3},
    1, 0, 0};

/* ---------------------------------------------------------------------------------------------
 * Images and statistics read back
 */
typedef struct image {
    int w, h;
    uint8_t* px; /* RGBA, top row first */
} image;

static void image_read(const char* dir, const char* name, image* im)
{
    char path[1024];
    tp_error err;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    memset(im, 0, sizeof *im);
    memset(&err, 0, sizeof err);
    if (tp_image_read_rgba(path, &im->w, &im->h, &im->px, &err) != TP_OK)
        FAIL("tp_image_read_rgba(%s): %s", path, err.message);
}

static int is_magenta(const uint8_t* p)
{
    return p[0] > 200 && p[1] < 60 && p[2] > 200;
}

/* Magenta pixels of rows [y0, y1); the first one found goes to *fx, *fy (-1 if none). */
static long count_magenta_rows(const image* im, int y0, int y1, int* fx, int* fy)
{
    long n = 0;
    int x, y;
    if (fx)
        *fx = *fy = -1;
    for (y = y0; y < y1; ++y)
        for (x = 0; x < im->w; ++x)
            if (is_magenta(im->px + 4 * ((size_t)y * im->w + x))) {
                if (fx && *fx < 0)
                    *fx = x, *fy = y;
                ++n;
            }
    return n;
}

typedef struct view_stats {
    long triangles, patches_drawn, patches_culled, draw_calls, draws;
    double max_error_px;
    int levels[TP_MAX_LEVELS + 1];
    int level_count;
} view_stats;

static double json_number(const char* text, const char* key)
{
    char pat[64];
    const char* p;
    snprintf(pat, sizeof pat, "\"%s\":", key);
    p = strstr(text, pat);
    if (!p)
        FAIL("statistics JSON has no \"%s\": %s", key, text);
    return strtod(p + strlen(pat), NULL);
}

static void stats_read(const char* dir, const char* name, view_stats* s)
{
    char path[1024], text[8192];
    const char* p;
    snprintf(path, sizeof path, "%s/%s", dir, name);
    read_text(path, text, sizeof text, NULL);
    ASSERT_TRUE(text[0] == '{');
    memset(s, 0, sizeof *s);
    s->triangles = (long)json_number(text, "triangles");
    s->patches_drawn = (long)json_number(text, "patches_drawn");
    s->patches_culled = (long)json_number(text, "patches_culled");
    s->draw_calls = (long)json_number(text, "draw_calls");
    s->draws = (long)json_number(text, "draws");
    s->max_error_px = json_number(text, "max_error_px");
    p = strstr(text, "\"levels\":");
    ASSERT_TRUE(p != NULL);
    p = strchr(p, '[');
    ASSERT_TRUE(p != NULL);
    ++p;
    for (;;) {
        char* end;
        long v;
        while (*p == ' ' || *p == ',' || *p == '\n')
            ++p;
        if (*p == ']')
            break;
        v = strtol(p, &end, 10);
        ASSERT_TRUE(end != p);
        ASSERT_TRUE(s->level_count < TP_MAX_LEVELS + 1);
        s->levels[s->level_count++] = (int)v;
        p = end;
    }
}

static int distinct_levels(const view_stats* s)
{
    int k, n = 0;
    for (k = 0; k < s->level_count; ++k)
        n += s->levels[k] > 0;
    return n;
}

/* ---------------------------------------------------------------------------------------------
 * The core in this process, built as app/scene/scene.c builds it (default grid options, patch 17,
 * pad), and the camera as app/cmd_view.c's camera_from makes it.
 */
typedef struct core_scene {
    tp_dem* dem;
    tp_render_grid* grid;
    tp_terrain* t;
    tp_terrain_info info;
} core_scene;

static void core_load(const char* path, core_scene* cs)
{
    tp_grid_options go;
    tp_terrain_desc desc;
    tp_error err;
    tp_status s;
    memset(cs, 0, sizeof *cs);
    memset(&go, 0, sizeof go);
    memset(&err, 0, sizeof err);
    s = tp_dem_read(path, &cs->dem, &err);
    if (s != TP_OK)
        FAIL("tp_dem_read(%s): %s", path, err.message);
    s = tp_render_grid_build(cs->dem, &go, &cs->grid, &err);
    if (s != TP_OK)
        FAIL("tp_render_grid_build(%s): %s", path, err.message);
    desc = tp_render_grid_terrain_desc(cs->grid, 17, TP_FIT_PAD);
    s = tp_terrain_create(&desc, &cs->t, &err);
    if (s != TP_OK)
        FAIL("tp_terrain_create(%s): %s", path, err.message);
    tp_terrain_get_info(cs->t, &cs->info);
}

static void core_free(core_scene* cs)
{
    tp_terrain_destroy(cs->t);
    tp_render_grid_destroy(cs->grid);
    tp_dem_destroy(cs->dem);
    memset(cs, 0, sizeof *cs);
}

/* The CLI's camera for a view: the core's pose, fov 60 degrees, near 1 m, no far. */
static void camera_from(const view_spec* v, tp_camera* cam)
{
    tp_camera_from_pose(v->cam, v->cam[3], v->cam[4], 60, v->w, v->h, cam);
}

/* The view's selection as the viewer makes it, with cracks removed by adding vertices when
 * add (--stitch add: the error mode bounds that geometry instead, tp_selection_set_stitch_add). */
static tp_selection* core_select_stitch(const core_scene* cs, const view_spec* v, int add)
{
    tp_selection* sel = NULL;
    tp_camera cam;
    tp_lod_params lod = v->lod;
    tp_error err;
    memset(&err, 0, sizeof err);
    if (lod.mode == TP_LOD_DEFAULT)
        lod.mode = TP_LOD_ERROR; /* cmd_view.c's default */
    ASSERT_OK(tp_selection_create(cs->t, &sel, &err));
    if (add)
        ASSERT_OK(tp_terrain_prepare_stitch_add(cs->t, &err));
    tp_selection_set_stitch_add(sel, add);
    camera_from(v, &cam);
    if (tp_selection_update(sel, &cam, &lod, &err) != TP_OK)
        FAIL("tp_selection_update: %s", err.message);
    return sel;
}

static tp_selection* core_select(const core_scene* cs, const view_spec* v)
{
    return core_select_stitch(cs, v, 0);
}

/* Largest level difference between two visible patches sharing an edge. */
static int max_visible_neighbor_gap(const core_scene* cs, const tp_selection* sel)
{
    int c, r, gap = 0, cols = cs->info.patch_cols, rows = cs->info.patch_rows;
    for (r = 0; r < rows; ++r)
        for (c = 0; c < cols; ++c) {
            int p = r * cols + c, q[2], i;
            if (!tp_selection_visible(sel, p))
                continue;
            q[0] = c + 1 < cols ? p + 1 : -1;
            q[1] = r + 1 < rows ? p + cols : -1;
            for (i = 0; i < 2; ++i)
                if (q[i] >= 0 && tp_selection_visible(sel, q[i])) {
                    int d = abs(tp_selection_level(sel, p) - tp_selection_level(sel, q[i]));
                    gap = d > gap ? d : gap;
                }
        }
    return gap;
}

/* ---------------------------------------------------------------------------------------------
 * No cracks: every view below is ground from edge to edge (checked by looking at it; a crack
 * or a hole would show the magenta background).
 */
static void expect_no_magenta(const char* dem, const view_spec* v, const char* what, int min_levels,
                              int min_gap)
{
    const char* dir = make_tmp_dir();
    image im;
    view_stats st;
    core_scene cs;
    tp_selection* sel;
    long n;
    int fx, fy, gap;
    render(dem, v, dir, "view.png", "view.json");
    image_read(dir, "view.png", &im);
    stats_read(dir, "view.json", &st);
    ASSERT_EQ_INT(v->w, im.w);
    ASSERT_EQ_INT(v->h, im.h);
    n = count_magenta_rows(&im, 0, im.h, &fx, &fy);
    core_load(dem, &cs);
    sel = core_select(&cs, v);
    gap = max_visible_neighbor_gap(&cs, sel);
    tp_test_note("%s: %ld magenta pixels; %d levels drawn (%d %d %d %d %d), %ld patches, "
                 "largest level gap between visible neighbours %d",
                 what, n, distinct_levels(&st), st.levels[0], st.levels[1], st.levels[2],
                 st.levels[3], st.levels[4], st.patches_drawn, gap);
    EXPECT_EQ_INT(0, n);
    if (n)
        ADD_FAILURE("%s: first magenta pixel at (%d, %d)", what, fx, fy);
    /* the view must really be adversarial, or it proves nothing */
    EXPECT_GE_INT(distinct_levels(&st), min_levels);
    EXPECT_GE_INT(gap, min_gap);
    tp_selection_destroy(sel);
    core_free(&cs);
    free(im.px);
}

/* ---------------------------------------------------------------------------------------------
 * Precision: the same DEM at its UTM coordinates (E ~ 6e5, N ~ 5e6 m) and at a local origin.
 */

/* Pixels of a with no pixel within 1 px in b whose channels all differ by <= tol. */
static long unmatched_pixels(const image* a, const image* b, int tol, int* fx, int* fy)
{
    long bad = 0;
    int x, y, dx, dy, c;
    *fx = *fy = -1;
    for (y = 0; y < a->h; ++y)
        for (x = 0; x < a->w; ++x) {
            const uint8_t* pa = a->px + 4 * ((size_t)y * a->w + x);
            int found = 0;
            for (dy = -1; dy <= 1 && !found; ++dy)
                for (dx = -1; dx <= 1 && !found; ++dx) {
                    const uint8_t* pb;
                    int ok = 1;
                    if (x + dx < 0 || y + dy < 0 || x + dx >= b->w || y + dy >= b->h)
                        continue;
                    pb = b->px + 4 * ((size_t)(y + dy) * b->w + (x + dx));
                    for (c = 0; c < 3; ++c)
                        ok &= abs((int)pa[c] - (int)pb[c]) <= tol;
                    found = ok;
                }
            if (!found) {
                if (*fx < 0)
                    *fx = x, *fy = y;
                ++bad;
            }
        }
    return bad;
}

/* Writes dir/local.vrt: the sample with its origin at (0, 0) and no CRS. */
static void write_local_vrt(const char* dir, const char* dem_path, const tp_dem* dem)
{
    char path[1024];
    FILE* f;
    snprintf(path, sizeof path, "%s/local.vrt", dir);
    f = fopen(path, "w");
    ASSERT_TRUE(f != NULL);
    fprintf(f, "<VRTDataset rasterXSize=\"%d\" rasterYSize=\"%d\">\n", dem->width, dem->height);
    fprintf(f, "  <GeoTransform>0, %.17g, 0, 0, 0, %.17g</GeoTransform>\n", dem->geotransform[1],
            dem->geotransform[5]);
    fprintf(f, "  <VRTRasterBand dataType=\"%s\" band=\"1\">\n", dem->data_type);
    if (dem->has_nodata)
        fprintf(f, "    <NoDataValue>%.17g</NoDataValue>\n", dem->nodata_value);
    fprintf(f,
            "    <SimpleSource>\n"
            "      <SourceFilename relativeToVRT=\"0\">%s</SourceFilename>\n"
            "      <SourceBand>1</SourceBand>\n"
            "    </SimpleSource>\n"
            "  </VRTRasterBand>\n"
            "</VRTDataset>\n",
            dem_path);
    ASSERT_EQ_INT(0, fclose(f));
}

/* ---------------------------------------------------------------------------------------------
 * The statistics JSON is the core's selection for the same camera.
 */
static void expect_stats_match_core(const char* dem, const view_spec* v)
{
    const char* dir = make_tmp_dir();
    view_stats st;
    core_scene cs;
    tp_selection* sel;
    tp_frame_stats fs;
    int k;
    render(dem, v, dir, NULL, "view.json");
    stats_read(dir, "view.json", &st);
    core_load(dem, &cs);
    sel = core_select(&cs, v);
    tp_selection_stats(sel, &fs);
    tp_test_note("camera %g,%g,%g,%g,%g: %ld triangles, %ld drawn, %ld culled; core: %zu, %d, %d",
                 v->cam[0], v->cam[1], v->cam[2], v->cam[3], v->cam[4], st.triangles,
                 st.patches_drawn, st.patches_culled, fs.triangles, fs.visible_patches,
                 fs.culled_patches);
    EXPECT_EQ_INT(fs.triangles, st.triangles);
    EXPECT_EQ_INT(fs.visible_patches, st.patches_drawn);
    EXPECT_EQ_INT(fs.culled_patches, st.patches_culled);
    EXPECT_EQ_INT(cs.info.levels, st.level_count);
    for (k = 0; k < cs.info.levels && k < st.level_count; ++k)
        EXPECT_EQ_INT(fs.patches_per_level[k], st.levels[k]);
    /* and the view is not trivial */
    EXPECT_GT(st.patches_drawn, 0);
    EXPECT_GT(st.patches_culled, 0);
    tp_selection_destroy(sel);
    core_free(&cs);
}

/* ---------------------------------------------------------------------------------------------
 * The reference image (see the top of this file for how to regenerate it).
 */
static int reference_path(char* buf, size_t cap)
{
    const char* dir = getenv("TP_TEST_REFERENCE_DIR");
    FILE* f;
    if (dir && *dir)
        snprintf(buf, cap, "%s/%s", dir, REFERENCE_PNG);
    else
        snprintf(buf, cap, "%s/../tests/reference/%s", TP_TEST_DEFAULT_SAMPLE_DATA_DIR,
                 REFERENCE_PNG);
    f = fopen(buf, "rb");
    if (!f)
        return 0;
    fclose(f);
    return 1;
}

static void copy_file(const char* from, const char* to)
{
    FILE *in = fopen(from, "rb"), *out = in ? fopen(to, "wb") : NULL;
    char buf[65536];
    size_t n;
    if (in && out)
        while ((n = fread(buf, 1, sizeof buf, in)) > 0)
            fwrite(buf, 1, n, out);
    if (in)
        fclose(in);
    if (out)
        fclose(out);
}

/* ---------------------------------------------------------------------------------------------
 * Bad command lines: exit status 1 (failure) or 2 (usage), one line on stderr naming what was
 * wrong, no output file.
 */
static void expect_failure(args* a, const char* log_dir, int code, const char* needle)
{
    run_result r;
    run(a, log_dir, &r);
    tp_test_note("exit %d, stderr: %s", r.exit_code, r.err);
    EXPECT_EQ_INT(code, r.exit_code);
    EXPECT_EQ_INT(1, r.err_lines);
    EXPECT_CONTAINS(r.err, needle);
    EXPECT_TRUE(r.out[0] == '\0');
}

static int dir_entries(const char* dir)
{
    DIR* d = opendir(dir);
    struct dirent* e;
    int n = 0;
    if (!d)
        return -1;
    while ((e = readdir(d)) != NULL)
        n += strcmp(e->d_name, ".") != 0 && strcmp(e->d_name, "..") != 0;
    closedir(d);
    return n;
}

/* --stitch add (Brodersen's crack fix by adding vertices): the same view drawn with the
 * coarser patch's border taking its finer neighbour's vertices shows no magenta either, and
 * draws exactly the triangles tp_patch_triangles_add gives each visible complete patch with
 * the neighbour levels of the viewer's selection (tp_selection_set_stitch_add: in error mode
 * it raises patches whose added vertices' bound exceeds tau; an incomplete one, at level n,
 * its unmoved level-n triangles): more than vertex moving draws, since every patch keeps its
 * own. */
static void expect_add_watertight(const char* dem, const view_spec* v_move, const char* what)
{
    const char* dir = make_tmp_dir();
    const view_spec* v = v_move;
    image im;
    view_stats st;
    core_scene cs;
    tp_selection *sel, *move;
    tp_frame_stats fs;
    tp_vertex* verts;
    size_t expected = 0, c;
    long n;
    int fx, fy, p, finer = 0;
    render_stitch(dem, v, dir, "add.png", "add.json", "add");
    image_read(dir, "add.png", &im);
    stats_read(dir, "add.json", &st);
    n = count_magenta_rows(&im, 0, im.h, &fx, &fy);
    core_load(dem, &cs);
    sel = core_select_stitch(&cs, v, 1);
    move = core_select(&cs, v);
    tp_selection_stats(move, &fs);
    tp_selection_destroy(move);
    c = ((size_t)1 << cs.info.n) + 1;
    verts = malloc(c * c * sizeof *verts);
    ASSERT_TRUE(verts != NULL);
    for (p = 0; p < cs.info.patch_count; ++p) {
        int nb[4], k, side;
        tp_patch_info pi;
        if (!tp_selection_visible(sel, p))
            continue;
        k = tp_selection_level(sel, p);
        tp_selection_neighbor_levels(sel, p, nb);
        tp_patch_get_info(cs.t, p, &pi);
        for (side = 0; side < 4; ++side)
            finer += nb[side] > k;
        if (pi.complete) {
            expected += tp_patch_triangles_add(cs.info.n, k, nb, NULL, 0);
        } else {
            c = ((size_t)1 << k) + 1;
            tp_patch_vertices(cs.t, p, k, NULL, verts, c * c);
            expected += tp_patch_triangles(verts, k, NULL, 0);
        }
    }
    free(verts);
    tp_test_note("%s, --stitch add: %ld magenta pixels; %ld triangles drawn, %zu expected "
                 "(vertex moving: %zu); %d sides take a finer neighbour's vertices",
                 what, n, st.triangles, expected, fs.triangles, finer);
    EXPECT_EQ_INT(0, n);
    if (n)
        ADD_FAILURE("%s: first magenta pixel at (%d, %d)", what, fx, fy);
    EXPECT_EQ_INT((long)expected, st.triangles);
    /* the view measures the geometry it drew (not vertex moving's), which τ bounds */
    if (v->lod.mode == TP_LOD_ERROR)
        EXPECT_LE(st.max_error_px, v->lod.tau_px + 1e-6);
    EXPECT_EQ_INT(fs.visible_patches, st.patches_drawn);
    EXPECT_GT(finer, 0); /* something was added, or it proves nothing */
    EXPECT_GT(st.triangles, (long)fs.triangles);
    tp_selection_destroy(sel);
    core_free(&cs);
    free(im.px);
}

#endif /* TP_TEST_NO_IO */

/* Straight down from just above the summit (3421 m at E 602125, N 5025267) and from 580 m above
 * it: distance LoD with mindist 300, maxdist 4000, exponent 0.3 gives levels 1..4 and 1..3. */
TEST(no_cracks_top_down_distance_lod)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dem;
        view_spec v = distance_lod_view;
        dem = sample_dem();
        v.cam[0] = 602125, v.cam[1] = 5025267, v.cam[2] = 3700, v.cam[3] = 0, v.cam[4] = -90;
        expect_no_magenta(dem, &v, "summit, 280 m above", 4, 2);
        v.cam[2] = 4000;
        expect_no_magenta(dem, &v, "summit, 580 m above", 3, 1);
    }
#endif
}

/* Oblique (pitch -55): 350 m above the summit's height just north of it, looking south over it
 * (levels 0..4, level 2 next to level 4); 400 m above a ridge west of the mountain looking north
 * (levels 1..4); 1500 m above the south flank looking up the mountain (levels 0..2). */
TEST(no_cracks_oblique_distance_lod)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dem;
        view_spec v = distance_lod_view;
        dem = sample_dem();
        v.cam[0] = 602000, v.cam[1] = 5026000, v.cam[2] = 3612, v.cam[3] = 180, v.cam[4] = -55;
        expect_no_magenta(dem, &v, "over the summit", 5, 2);
        v.cam[0] = 595000, v.cam[1] = 5022000, v.cam[2] = 1816, v.cam[3] = 0;
        expect_no_magenta(dem, &v, "ridge, 400 m above", 4, 1);
        v.cam[0] = 602125, v.cam[1] = 5018000, v.cam[2] = 2950;
        expect_no_magenta(dem, &v, "south flank, 1500 m above", 3, 1);
    }
#endif
}

/* Oblique views with the screen-space error rule at tau 8 px (solid, not wireframe), where
 * the stitching pass raises coarse neighbours: 1500 m above the east side looking west (levels
 * 0..4, level 0 next to level 3), and the south flank and ridge views above. */
TEST(no_cracks_oblique_error_lod)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dem;
        view_spec v = distance_lod_view;
        dem = sample_dem();
        v.lod.mode = TP_LOD_ERROR;
        v.lod.tau_px = 6;
        v.cam[0] = 614000, v.cam[1] = 5030000, v.cam[2] = 2811, v.cam[3] = 270, v.cam[4] = -55;
        expect_no_magenta(dem, &v, "east side, 1500 m above", 5, 2);
        v.lod.tau_px = 8;
        v.cam[0] = 602125, v.cam[1] = 5018000, v.cam[2] = 2950, v.cam[3] = 0;
        expect_no_magenta(dem, &v, "south flank, 1500 m above", 4, 2);
        v.cam[0] = 595000, v.cam[1] = 5022000, v.cam[2] = 1816;
        expect_no_magenta(dem, &v, "ridge, 400 m above", 2, 1);
    }
#endif
}

/* --stitch add under the adversarial views above (top down, oblique, distance and error LoD:
 * neighbours up to 3 levels apart), a DEM drawn whole, each patch that takes vertices drawn
 * from its configuration's index set (--stitch-add-draw sets; five: the next test). */
TEST(no_cracks_stitch_add)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dem;
        view_spec v = distance_lod_view;
        dem = sample_dem();
        add_draw_ = "sets";
        v.cam[0] = 602125, v.cam[1] = 5025267, v.cam[2] = 3700, v.cam[3] = 0, v.cam[4] = -90;
        expect_add_watertight(dem, &v, "summit, 280 m above");
        v.cam[0] = 602000, v.cam[1] = 5026000, v.cam[2] = 3612, v.cam[3] = 180, v.cam[4] = -55;
        expect_add_watertight(dem, &v, "over the summit");
        v.lod.mode = TP_LOD_ERROR;
        v.lod.tau_px = 6;
        v.cam[0] = 614000, v.cam[1] = 5030000, v.cam[2] = 2811, v.cam[3] = 270, v.cam[4] = -55;
        expect_add_watertight(dem, &v, "east side, 1500 m above");
        v.lod.tau_px = 8;
        v.cam[0] = 595000, v.cam[1] = 5022000, v.cam[2] = 1816, v.cam[3] = 0;
        expect_add_watertight(dem, &v, "ridge, 400 m above");
        add_draw_ = NULL;
    }
#endif
}

/* --stitch add drawn both ways (--stitch-add-draw sets and five) from the same view: the same
 * triangles drawn from the same vertices, so the same pixels; five takes more draws (each patch
 * that takes vertices up to five), which shows it was drawn as five regions. */
static void expect_five_as_sets(const char* dem, const view_spec* v, const char* what)
{
    const char* dir = make_tmp_dir();
    image sets, five;
    view_stats ss, sf;
    long differ = 0;
    int i, first = -1;
    const char* stitch = v->stitch_add ? NULL : "add"; /* a store view says it itself */
    add_draw_ = "sets";
    render_stitch(dem, v, dir, "sets.png", "sets.json", stitch);
    add_draw_ = "five";
    render_stitch(dem, v, dir, "five.png", "five.json", stitch);
    add_draw_ = NULL;
    image_read(dir, "sets.png", &sets);
    image_read(dir, "five.png", &five);
    stats_read(dir, "sets.json", &ss);
    stats_read(dir, "five.json", &sf);
    ASSERT_EQ_INT(sets.w, five.w);
    ASSERT_EQ_INT(sets.h, five.h);
    for (i = 0; i < sets.w * sets.h; ++i)
        if (memcmp(sets.px + 4 * i, five.px + 4 * i, 4) && differ++ == 0)
            first = i;
    tp_test_note("%s: %ld of %d pixels differ; triangles %ld and %ld; draws %ld (sets) and %ld "
                 "(five), %ld and %ld draw calls",
                 what, differ, sets.w * sets.h, ss.triangles, sf.triangles, ss.draws, sf.draws,
                 ss.draw_calls, sf.draw_calls);
    EXPECT_EQ_INT(0, differ);
    if (differ)
        ADD_FAILURE("%s: first differing pixel at (%d, %d)", what, first % sets.w, first / sets.w);
    EXPECT_EQ_INT(ss.triangles, sf.triangles);
    EXPECT_EQ_INT(ss.patches_drawn, sf.patches_drawn);
    EXPECT_GT(sf.draws, ss.draws);
    free(sets.px);
    free(five.px);
}

/* --stitch-add-draw five under no_cracks_stitch_add's adversarial views: watertight (no magenta,
 * the triangles tp_patch_triangles_add counts, error within tau) and pixel-identical to sets,
 * also through a store (store_no_cracks_stitch_add finds no magenta there with the default,
 * five). */
TEST(no_cracks_stitch_add_five)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dem;
        view_spec v = distance_lod_view;
        dem = sample_dem();
        v.cam[0] = 602000, v.cam[1] = 5026000, v.cam[2] = 3612, v.cam[3] = 180, v.cam[4] = -55;
        add_draw_ = "five";
        expect_add_watertight(dem, &v, "over the summit");
        expect_five_as_sets(dem, &v, "over the summit");
        v.lod.mode = TP_LOD_ERROR;
        v.lod.tau_px = 6;
        v.cam[0] = 614000, v.cam[1] = 5030000, v.cam[2] = 2811, v.cam[3] = 270, v.cam[4] = -55;
        add_draw_ = "five";
        expect_add_watertight(dem, &v, "east side, 1500 m above");
        expect_five_as_sets(dem, &v, "east side, 1500 m above");
        v.store = 1; /* through a store: same-size nodes add, smaller ones move theirs */
        v.stitch_add = 1;
        expect_five_as_sets(dem, &v, "east side, 1500 m above, a store");
    }
#endif
}


TEST(utm_and_local_origin_render_alike)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        /* The reference view, and two 5 m above the ground looking level (near the summit,
         * nearly horizontal: ridges and sky close by). Rendering in float32 world
         * coordinates (0.5 m steps at N = 5e6) fails all three, the last by ~200 pixels. */
        static const double cams[][5] = {{598000, 5012000, 4500, 15, -35},
                                         {595000, 5022000, 1421, 90, 0},
                                         {602000, 5026000, 2867, 0, -3}};
        const char *dem_path, *dir;
        char vrt[1024];
        tp_dem* dem = NULL;
        tp_error err;
        int i, k;
        dem_path = sample_dem();
        dir = make_tmp_dir();
        memset(&err, 0, sizeof err);
        ASSERT_OK(tp_dem_read(dem_path, &dem, &err));
        ASSERT_GT(fabs(dem->geotransform[3]), 1e6); /* really at large coordinates */
        write_local_vrt(dir, dem_path, dem);
        snprintf(vrt, sizeof vrt, "%s/local.vrt", dir);
        for (i = 0; i < (int)(sizeof cams / sizeof cams[0]); ++i) {
            view_spec utm = {{0, 0, 0, 0, 0}, 1280, 720, {.mode = TP_LOD_DEFAULT}, 1, 0, 0};
            view_spec local;
            image a, b;
            view_stats sa, sb;
            long bad_ab, bad_ba, same = 0;
            int fx, fy, gx, gy;
            size_t p;
            memcpy(utm.cam, cams[i], sizeof utm.cam);
            local = utm;
            local.cam[0] = utm.cam[0] - dem->geotransform[0];
            local.cam[1] = utm.cam[1] - dem->geotransform[3];
            render(dem_path, &utm, dir, "utm.png", "utm.json");
            render(vrt, &local, dir, "local.png", "local.json");
            image_read(dir, "utm.png", &a);
            image_read(dir, "local.png", &b);
            stats_read(dir, "utm.json", &sa);
            stats_read(dir, "local.json", &sb);
            ASSERT_EQ_INT(a.w, b.w);
            ASSERT_EQ_INT(a.h, b.h);
            /* the same patches at the same levels, or the comparison below is not like for like */
            EXPECT_EQ_INT(sa.triangles, sb.triangles);
            for (k = 0; k < sa.level_count; ++k)
                EXPECT_EQ_INT(sa.levels[k], sb.levels[k]);
            bad_ab = unmatched_pixels(&a, &b, 8, &fx, &fy);
            bad_ba = unmatched_pixels(&b, &a, 8, &gx, &gy);
            for (p = 0; p < (size_t)a.w * a.h * 4; p += 4)
                same += !memcmp(a.px + p, b.px + p, 3);
            tp_test_note(
                "view %d: %ld of %d pixels of the UTM image unmatched in the local one, %ld "
                "the other way; %ld identical pixels; %ld magenta (sky)",
                i, bad_ab, a.w * a.h, bad_ba, same, count_magenta_rows(&a, 0, a.h, NULL, NULL));
            EXPECT_EQ_INT(0, bad_ab);
            EXPECT_EQ_INT(0, bad_ba);
            if (bad_ab || bad_ba)
                ADD_FAILURE("view %d: first unmatched pixels (%d, %d) and (%d, %d)", i, fx, fy, gx,
                            gy);
            free(a.px);
            free(b.px);
        }
        tp_dem_destroy(dem);
    }
#endif
}

TEST(stats_json_equals_core_selection_error_lod)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dem;
        view_spec v = {{598000, 5012000, 4500, 15, -35}, 640, 360, {.mode = TP_LOD_ERROR, .tau_px = 2.5}, 0, 0, 0};
        dem = sample_dem();
        expect_stats_match_core(dem, &v);
    }
#endif
}

TEST(stats_json_equals_core_selection_distance_lod)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dem;
        view_spec v = {
            {609000, 5033000, 2600, 225, -25}, 512, 384, {.mode = TP_LOD_DISTANCE, .mindist_m = 500, .maxdist_m = 9000, .exponent = 1.7}, 0, 0, 0};
        dem = sample_dem();
        expect_stats_match_core(dem, &v);
    }
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Culling
 */
TEST(looking_at_the_sky_culls_every_patch)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char *dem, *dir;
        /* 1079 m above the summit, 60 degrees up: the lowest ray of the view climbs 30 degrees */
        view_spec v = {{602125, 5025267, 4500, 0, 60}, 320, 180, {.mode = TP_LOD_DEFAULT}, 1, 0, 0};
        core_scene cs;
        view_stats st;
        image im;
        dem = sample_dem();
        dir = make_tmp_dir();
        render(dem, &v, dir, "sky.png", "sky.json");
        stats_read(dir, "sky.json", &st);
        image_read(dir, "sky.png", &im);
        core_load(dem, &cs);
        tp_test_note("%ld drawn, %ld culled of %d patches", st.patches_drawn, st.patches_culled,
                     cs.info.patch_count);
        EXPECT_EQ_INT(0, st.patches_drawn);
        EXPECT_EQ_INT(cs.info.patch_count, st.patches_culled);
        EXPECT_EQ_INT(0, st.triangles);
        /* nothing drawn: the whole image is the background (this also shows that the magenta test
         * of the crack tests sees the background) */
        EXPECT_EQ_INT((long)im.w * im.h, count_magenta_rows(&im, 0, im.h, NULL, NULL));
        core_free(&cs);
        free(im.px);
    }
#endif
}

TEST(looking_north_culls_the_patches_behind)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char *dem, *dir;
        /* 300 m above the ground 1.6 km from the south edge, 10 degrees down, looking north */
        view_spec v = {{602125, 5015000, 1500, 0, -10}, 320, 180, {.mode = TP_LOD_DEFAULT}, 1, 0, 0};
        core_scene cs;
        view_stats st;
        image im;
        int p, behind = 0, ahead = 0;
        long sky_top, sky_bottom;
        dem = sample_dem();
        dir = make_tmp_dir();
        render(dem, &v, dir, "north.png", "north.json");
        stats_read(dir, "north.json", &st);
        image_read(dir, "north.png", &im);
        core_load(dem, &cs);
        /* patches entirely south of the eye are behind it; those entirely north of it, in the
         * column under the eye, are ahead */
        for (p = 0; p < cs.info.patch_count; ++p) {
            tp_patch_info pi;
            tp_patch_get_info(cs.t, p, &pi);
            if (pi.aabb_max[1] < v.cam[1])
                ++behind;
            else if (pi.aabb_min[1] > v.cam[1] && pi.aabb_min[0] <= v.cam[0] &&
                     pi.aabb_max[0] >= v.cam[0])
                ++ahead;
        }
        sky_top = count_magenta_rows(&im, 0, 1, NULL, NULL);
        sky_bottom = count_magenta_rows(&im, im.h - 1, im.h, NULL, NULL);
        tp_test_note("%ld drawn, %ld culled of %d patches; %d entirely behind the eye; top row %ld "
                     "of %d px sky, bottom row %ld",
                     st.patches_drawn, st.patches_culled, cs.info.patch_count, behind, sky_top,
                     im.w, sky_bottom);
        ASSERT_GT(behind, 100); /* the view is what this test means */
        EXPECT_GE_INT(st.patches_culled, behind);
        EXPECT_GE_INT(st.patches_drawn, ahead);
        EXPECT_EQ_INT(cs.info.patch_count, st.patches_drawn + st.patches_culled);
        /* 10 degrees down with a 60-degree field of view: sky at the top, ground at the bottom */
        EXPECT_EQ_INT(im.w, sky_top);
        EXPECT_EQ_INT(0, sky_bottom);
        core_free(&cs);
        free(im.px);
    }
#endif
}

TEST(reference_view_matches_committed_image)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char *dem, *dir;
        char ref_path[1024], got_path[1024];
        view_spec v = {{598000, 5012000, 4500, 15, -35}, 480, 270, {.mode = TP_LOD_DEFAULT}, 0, 0, 0};
        image got, ref;
        tp_error err;
        double sum[3] = {0, 0, 0}, mad[3];
        long within = 0, n;
        int max_diff = 0, c;
        size_t p;
        dem = sample_dem();
        if (!reference_path(ref_path, sizeof ref_path))
            FAIL("reference image %s is missing", ref_path);
        dir = make_tmp_dir();
        render(dem, &v, dir, "got.png", NULL);
        image_read(dir, "got.png", &got);
        memset(&err, 0, sizeof err);
        if (tp_image_read_rgba(ref_path, &ref.w, &ref.h, &ref.px, &err) != TP_OK)
            FAIL("tp_image_read_rgba(%s): %s", ref_path, err.message);
        ASSERT_EQ_INT(ref.w, got.w);
        ASSERT_EQ_INT(ref.h, got.h);
        n = (long)got.w * got.h;
        for (p = 0; p < (size_t)n * 4; p += 4) {
            int m = 0;
            for (c = 0; c < 3; ++c) {
                int d = abs((int)got.px[p + c] - (int)ref.px[p + c]);
                sum[c] += d;
                m = d > m ? d : m;
            }
            within += m <= 12;
            max_diff = m > max_diff ? m : max_diff;
        }
        for (c = 0; c < 3; ++c)
            mad[c] = sum[c] / (double)n;
        tp_test_note("mean absolute difference R %.4f G %.4f B %.4f; %ld of %ld pixels within 12 "
                     "(%.4f%%); largest difference %d",
                     mad[0], mad[1], mad[2], within, n, 100.0 * (double)within / (double)n,
                     max_diff);
        for (c = 0; c < 3; ++c)
            EXPECT_LT(mad[c], 1.5);
        EXPECT_GE((double)within / (double)n, 0.995);
        if (tp_test_state_.failures) {
            snprintf(got_path, sizeof got_path, "%s/got.png", dir);
            copy_file(got_path, "mt_hood_480x270.actual.png");
            tp_test_note(
                "the image rendered now is in mt_hood_480x270.actual.png (working directory)");
        }
        free(got.px);
        free(ref.px);
    }
#endif
}

/* --texture drapes the orthophoto: Crater Lake's imagery (a colour map of the same grid, RGBA
 * with alpha 0 outside the data) over its DEM, seen from straight above. The textured picture
 * differs from the untextured one on the terrain, and its colours are the imagery's: the share
 * of strongly blue pixels (the lake) on the terrain is about that of the imagery's valid
 * pixels, where the untextured render (green-brown shading) has none. */
static int is_strong_blue(const uint8_t* p)
{
    return p[2] > p[0] + 60 && p[2] > p[1] + 30;
}

TEST(texture_drapes_the_imagery)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        char dem[1024], ortho[1024];
        const char* dir;
        view_spec v = {{0, 0, 0, 0, 0}, 320, 240, {.mode = TP_LOD_DEFAULT}, 1, 0, 0};
        image plain, tex, img;
        tp_error err;
        long terrain = 0, differ = 0, blue_tex = 0, blue_plain = 0, valid = 0, blue_img = 0;
        size_t i;
        args a;
        REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif");
        REQUIRE_DATA_FILE(ortho, "TP_SHARED_DATA_DIR", "craterlake-imagery-30m.tif");
        dir = make_tmp_dir();
        args_view(&a);
        args_add(&a, "--headless");
        args_add(&a, "--no-hud");
        args_add(&a, "--size");
        args_add(&a, "%dx%d", v.w, v.h);
        args_add(&a, "--clear-color");
        args_add(&a, "1,0,1");
        args_add(&a, "--camera-geo");
        args_add(&a, "42.94,-122.10,14000,0,-90");
        args_add(&a, "--screenshot");
        args_add(&a, "%s/plain.png", dir);
        args_add(&a, "%s", dem);
        run_ok(&a, dir);
        a.n -= 3; /* the same command line up to --screenshot, then --texture */
        a.v[a.n] = NULL;
        args_add(&a, "--texture");
        args_add(&a, "%s", ortho);
        args_add(&a, "--screenshot");
        args_add(&a, "%s/tex.png", dir);
        args_add(&a, "%s", dem);
        run_ok(&a, dir);
        image_read(dir, "plain.png", &plain);
        image_read(dir, "tex.png", &tex);
        ASSERT_EQ_INT(plain.w, tex.w);
        ASSERT_EQ_INT(plain.h, tex.h);
        for (i = 0; i < (size_t)plain.w * plain.h; ++i) {
            const uint8_t *p = plain.px + 4 * i, *t = tex.px + 4 * i;
            int c, d = 0;
            if (is_magenta(p) || is_magenta(t))
                continue; /* background */
            ++terrain;
            for (c = 0; c < 3; ++c)
                d = abs((int)p[c] - (int)t[c]) > d ? abs((int)p[c] - (int)t[c]) : d;
            differ += d > 40;
            blue_tex += is_strong_blue(t);
            blue_plain += is_strong_blue(p);
        }
        memset(&err, 0, sizeof err);
        if (tp_image_read_rgba(ortho, &img.w, &img.h, &img.px, &err) != TP_OK)
            FAIL("tp_image_read_rgba(%s): %s", ortho, err.message);
        for (i = 0; i < (size_t)img.w * img.h; ++i)
            if (img.px[4 * i + 3] > 0) {
                ++valid;
                blue_img += is_strong_blue(img.px + 4 * i);
            }
        tp_test_note("terrain pixels %ld, differing %ld; strongly blue: textured %ld, untextured "
                     "%ld; imagery %ld of %ld valid",
                     terrain, differ, blue_tex, blue_plain, blue_img, valid);
        ASSERT_GT((double)terrain, 0.1 * plain.w * plain.h);
        EXPECT_GT((double)differ, 0.5 * (double)terrain);
        EXPECT_EQ_INT(0, blue_plain);
        ASSERT_GT((double)blue_img, 0.05 * (double)valid);
        EXPECT_NEAR((double)blue_tex / (double)terrain, (double)blue_img / (double)valid,
                    0.35 * (double)blue_img / (double)valid);
        free(plain.px);
        free(tex.px);
        free(img.px);
    }
#endif
}

TEST(screenshot_into_missing_directory_exits_1)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* log_dir;
        args a;
        args_view(&a);
        log_dir = make_tmp_dir();
        ASSERT_TRUE(access("/nonexistent-dir", F_OK) != 0);
        args_add(&a, "--headless");
        args_add(&a, "--size");
        args_add(&a, "64x36");
        args_add(&a, "--screenshot");
        args_add(&a, "/nonexistent-dir/x.png");
        args_add(&a, "%s", sample_dem());
        expect_failure(&a, log_dir, 1, "/nonexistent-dir/x.png");
        EXPECT_TRUE(access("/nonexistent-dir", F_OK) != 0);
        EXPECT_EQ_INT(0, dir_entries(log_dir)); /* nothing written beside the logs */
    }
#endif
}

TEST(screenshot_onto_a_directory_exits_1_and_leaves_no_file)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dir;
        char shots[1024], target[1024];
        args a;
        args_view(&a);
        dir = make_tmp_dir();
        snprintf(shots, sizeof shots, "%s/shots", dir);
        snprintf(target, sizeof target, "%s/shots/x.png", dir);
        ASSERT_EQ_INT(0, mkdir(shots, 0755));
        ASSERT_EQ_INT(0, mkdir(target, 0755)); /* the PNG's name is taken by a directory */
        args_add(&a, "--headless");
        args_add(&a, "--size");
        args_add(&a, "64x36");
        args_add(&a, "--screenshot");
        args_add(&a, "%s", target);
        args_add(&a, "%s", sample_dem());
        expect_failure(&a, dir, 1, target);
        EXPECT_EQ_INT(1, dir_entries(shots));  /* only x.png/, no temporary file left beside it */
        EXPECT_EQ_INT(0, dir_entries(target)); /* and nothing inside it */
    }
#endif
}

TEST(size_below_16_exits_2)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        args a;
        args_view(&a);
        args_add(&a, "--headless");
        args_add(&a, "--size");
        args_add(&a, "10x10");
        args_add(&a, "%s", sample_dem());
        expect_failure(&a, make_tmp_dir(), 2, "--size");
    }
#endif
}

TEST(camera_with_three_values_exits_2)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        args a;
        args_view(&a);
        args_add(&a, "--headless");
        args_add(&a, "--camera");
        args_add(&a, "1,2,3");
        args_add(&a, "%s", sample_dem());
        expect_failure(&a, make_tmp_dir(), 2, "--camera");
    }
#endif
}

TEST(unknown_lod_mode_exits_2)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        args a;
        args_view(&a);
        args_add(&a, "--headless");
        args_add(&a, "--lod");
        args_add(&a, "bogus");
        args_add(&a, "%s", sample_dem());
        expect_failure(&a, make_tmp_dir(), 2, "bogus");
    }
#endif
}

TEST(missing_dem_exits_1)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        args a;
        args_view(&a);
        const char* dir = make_tmp_dir();
        args_add(&a, "--headless");
        args_add(&a, "--stats-json");
        args_add(&a, "%s/stats.json", dir);
        args_add(&a, "--size");
        args_add(&a, "64x36");
        args_add(&a, "/nonexistent-dir/no_such_dem.tif");
        expect_failure(&a, dir, 1, "no_such_dem.tif");
    }
#endif
}


/* ---------------------------------------------------------------------------------------------
 * The default path (two multi-draw calls) draws exactly what one draw call per patch draws.
 * Mesa (22.3, llvmpipe) shifts the base vertex of the draws that follow a zero-count draw in
 * glMultiDrawElementsBaseVertex: patches of nodata or padding only (no triangles) made border
 * patches vanish (a notch at Mt Hood's right and bottom edges, 18,910 pixels).
 */
static void expect_draw_paths_agree(const char* dem, const char* const* extra, int extra_count)
{
    const char* dir = make_tmp_dir();
    image multi, single;
    long differ = 0;
    int pass, i, fx = -1, fy = -1;
    for (pass = 0; pass < 2; ++pass) {
        args a;
        args_view(&a);
        args_add(&a, "--headless");
        args_add(&a, "--no-hud");
        args_add(&a, "--size");
        args_add(&a, "640x360");
        args_add(&a, "--clear-color");
        args_add(&a, "1,0,1");
        for (i = 0; i < extra_count; ++i)
            args_add(&a, "%s", extra[i]);
        if (pass)
            args_add(&a, "--one-draw-per-patch");
        args_add(&a, "--screenshot");
        args_add(&a, "%s/%s", dir, pass ? "single.png" : "multi.png");
        args_add(&a, "%s", dem);
        run_ok(&a, dir);
    }
    image_read(dir, "multi.png", &multi);
    image_read(dir, "single.png", &single);
    ASSERT_EQ_INT(single.w, multi.w);
    ASSERT_EQ_INT(single.h, multi.h);
    for (i = 0; i < multi.w * multi.h; ++i)
        if (memcmp(multi.px + 4 * (size_t)i, single.px + 4 * (size_t)i, 3) != 0) {
            if (fx < 0)
                fx = i % multi.w, fy = i / multi.w;
            ++differ;
        }
    if (differ)
        tp_test_note("%s: %ld pixels differ, the first at (%d, %d)", dem, differ, fx, fy);
    EXPECT_EQ_INT(0, (int)differ);
    free(multi.px);
    free(single.px);
}

TEST(multi_draw_equals_one_draw_per_patch_default_view)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    expect_draw_paths_agree(sample_dem(), NULL, 0);
#endif
}

TEST(multi_draw_equals_one_draw_per_patch_crater_lake_full_from_above)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        static const char* extra[] = {"--lod", "full", "--camera", "572800,4754700,14000,0,-89"};
        char dem[1024];
        REQUIRE_DATA_FILE(dem, "TP_SHARED_DATA_DIR", "craterlake-elev-16bit-30m.tif");
        expect_draw_paths_agree(dem, extra, 4);
    }
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Vertical exaggeration reaches the core: culling, the error LoD, picking.
 */
static void stats_for(const char* dem, const view_spec* v, const char* exag, view_stats* st)
{
    const char* dir = make_tmp_dir();
    args a;
    args_view(&a);
    args_add(&a, "--stats-json");
    args_add(&a, "%s/s.json", dir);
    if (exag) {
        args_add(&a, "--exaggeration");
        args_add(&a, "%s", exag);
    }
    args_add_view(&a, dem, v);
    run_ok(&a, dir);
    stats_read(dir, "s.json", st);
}

TEST(exaggeration_keeps_patches_that_rise_into_view)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        /* 3600 m over the south of Mt Hood (summit 3426 m) looking 32 degrees up: the true
         * terrain is below the view, drawn three times as high it rises into it */
        view_spec v = {{602000, 5008000, 3600, 0, 32}, 320, 180, {.mode = TP_LOD_DEFAULT}, 0, 0, 0};
        view_stats flat, tall;
        stats_for(sample_dem(), &v, NULL, &flat);
        stats_for(sample_dem(), &v, "3", &tall);
        EXPECT_EQ_INT(0, (int)flat.patches_drawn);
        EXPECT_GT((double)tall.patches_drawn, 0);
    }
#endif
}

TEST(exaggeration_error_lod_keeps_tau_on_screen)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        view_spec v = {{598000, 5012000, 4500, 15, -35}, 640, 360, {.mode = TP_LOD_ERROR, .tau_px = 1}, 0, 0, 0};
        view_stats flat, tall;
        stats_for(sample_dem(), &v, NULL, &flat);
        stats_for(sample_dem(), &v, "3", &tall);
        tp_test_note("triangles: %.0f unexaggerated, %.0f at x3; measured max %.3f px at x3",
                     (double)flat.triangles, (double)tall.triangles, tall.max_error_px);
        EXPECT_GT((double)tall.triangles, 1.2 * (double)flat.triangles);
        EXPECT_LE(tall.max_error_px, 1.0 + 1e-9);
    }
#endif
}

/* --pick prints the ground point under a pixel; it must lie on the drawn surface (within
 * 1 cm) and project back onto the pixel, also with exaggeration. */
static void expect_picks_on_surface(const char* exag, double zs)
{
    view_spec v = {{598000, 5012000, 4500, 15, -35}, 640, 360, {.mode = TP_LOD_ERROR, .tau_px = 1}, 0, 0, 0};
    v.cam[2] *= zs; /* above the exaggerated mountains too */
    const char* dir = make_tmp_dir();
    core_scene cs;
    tp_selection* sel;
    tp_camera cam;
    run_result rr;
    args a;
    int i, hits = 0;
    const char* line;
    args_view(&a);
    for (i = 0; i < 12; ++i) {
        args_add(&a, "--pick");
        args_add(&a, "%d,%d", 25 + 53 * i, 120 + 19 * (i % 12));
    }
    if (exag) {
        args_add(&a, "--exaggeration");
        args_add(&a, "%s", exag);
    }
    args_add_view(&a, sample_dem(), &v);
    run(&a, dir, &rr);
    ASSERT_EQ_INT(0, rr.exit_code);
    core_load(sample_dem(), &cs);
    ASSERT_OK(tp_selection_create(cs.t, &sel, NULL));
    ASSERT_OK(tp_selection_set_vertical_scale(sel, zs));
    camera_from(&v, &cam);
    ASSERT_OK(tp_selection_update(sel, &cam, &v.lod, NULL));
    for (line = rr.out; (line = strstr(line, "pick ")) != NULL; ++line) {
        double px, py, e, n, h, x, y, back[2], p[3];
        if (sscanf(line, "pick %lf,%lf: E %lf N %lf height %lf", &px, &py, &e, &n, &h) != 5)
            continue;
        ++hits;
        tp_terrain_world_to_grid(cs.t, e, n, &x, &y);
        EXPECT_NEAR(h, tp_selection_drawn_height_at(sel, x, y), 0.01);
        p[0] = e, p[1] = n, p[2] = h * zs;
        ASSERT_TRUE(tp_camera_project(&cam, p, back, NULL));
        EXPECT_NEAR(px, back[0], 0.05);
        EXPECT_NEAR(py, back[1], 0.05);
    }
    tp_test_note("%d of 12 picks hit the ground", hits);
    EXPECT_GE(hits, 10);
    tp_selection_destroy(sel);
    core_free(&cs);
}

TEST(picked_points_lie_on_the_drawn_surface)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    expect_picks_on_surface(NULL, 1);
#endif
}

TEST(picked_points_lie_on_the_exaggerated_surface)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    expect_picks_on_surface("2.5", 2.5);
#endif
}

/* ---------------------------------------------------------------------------------------------
 * The HUD fits the window: looking at the sky over a magenta background, no HUD pixel may
 * reach the last 4 columns (a cut line runs to the edge).
 */
static void expect_hud_fits(int w, int h)
{
    const char* dir = make_tmp_dir();
    image im;
    args a;
    int x, y;
    long edge = 0, text = 0;
    args_view(&a);
    args_add(&a, "--headless");
    args_add(&a, "--hud");
    args_add(&a, "--size");
    args_add(&a, "%dx%d", w, h);
    args_add(&a, "--camera");
    args_add(&a, "600000,5012000,3600,0,60");
    args_add(&a, "--clear-color");
    args_add(&a, "1,0,1");
    args_add(&a, "--measure");
    args_add(&a, "595000,5018000,600000,5014000");
    args_add(&a, "--screenshot");
    args_add(&a, "%s/hud.png", dir);
    args_add(&a, "%s", sample_dem());
    run_ok(&a, dir);
    image_read(dir, "hud.png", &im);
    for (y = 0; y < im.h; ++y)
        for (x = 0; x < im.w; ++x)
            if (!is_magenta(im.px + 4 * ((size_t)y * im.w + x))) {
                ++text;
                edge += x >= im.w - 4;
            }
    tp_test_note("%dx%d: %ld HUD pixels, %ld in the last 4 columns", w, h, text, edge);
    EXPECT_GT((double)text, 1000);
    EXPECT_EQ_INT(0, (int)edge);
    free(im.px);
}

TEST(hud_is_not_cut_at_1024x768)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    expect_hud_fits(1024, 768);
#endif
}

TEST(hud_is_not_cut_at_1280x720)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    expect_hud_fits(1280, 720);
#endif
}

/* A frame without terrain says so on stderr (and still exits 0). */
TEST(frame_without_terrain_says_so)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dir = make_tmp_dir();
        char asc[1024];
        FILE* f;
        run_result rr;
        args a;
        args_view(&a);
        args_add(&a, "--headless");
        args_add(&a, "--stats-json");
        args_add(&a, "%s/stats.json", dir);
        args_add(&a, "--size");
        args_add(&a, "64x36");
        args_add(&a, "--camera");
        args_add(&a, "600000,5012000,3600,0,60");
        args_add(&a, "%s", sample_dem());
        run(&a, dir, &rr);
        EXPECT_EQ_INT(0, rr.exit_code);
        EXPECT_CONTAINS(rr.err, "the frame shows no terrain: the camera looks away");
        /* a 1x1 DEM has nothing to draw */
        snprintf(asc, sizeof asc, "%s/one.asc", dir);
        f = fopen(asc, "w");
        ASSERT_TRUE(f != NULL);
        fputs("ncols 1\nnrows 1\nxllcorner 0\nyllcorner 0\ncellsize 30\nNODATA_value -9999\n100\n", f);
        fclose(f);
        args_view(&a);
        args_add(&a, "--headless");
        args_add(&a, "--stats-json");
        args_add(&a, "%s/stats.json", dir);
        args_add(&a, "--size");
        args_add(&a, "64x36");
        args_add(&a, "%s", asc);
        run(&a, dir, &rr);
        EXPECT_EQ_INT(0, rr.exit_code);
        EXPECT_CONTAINS(rr.err, "the frame shows no terrain: the DEM has no 2x2 block");
    }
#endif
}

/* ---------------------------------------------------------------------------------------------
 * Stores: the default path. The same magenta check, and the two-tile seam of issue 12 section 4.
 */
#ifndef TP_TEST_NO_IO
/* Renders v through a store and checks: no magenta pixel in rows y0.. (below the horizon), the
 * frame complete (nothing pending, nothing substituted), and at least min_levels levels. */
static void expect_store_no_magenta(const char* path, const view_spec* v, int patch, int y0,
                                    const char* what, int min_levels)
{
    const char* dir = make_tmp_dir();
    image im;
    char text[8192], json[1024];
    int fx, fy, lines;
    view_spec sv = *v;
    sv.store = 1;
    sv.magenta = 1;
    args a;
    args_view(&a);
    args_add(&a, "--screenshot");
    args_add(&a, "%s/view.png", dir);
    args_add(&a, "--stats-json");
    args_add(&a, "%s/view.json", dir);
    if (patch) {
        args_add(&a, "--patch");
        args_add(&a, "%d", patch);
    }
    args_add_view(&a, path, &sv);
    run_ok(&a, dir);
    image_read(dir, "view.png", &im);
    snprintf(json, sizeof json, "%s/view.json", dir);
    read_text(json, text, sizeof text, &lines);
    long n = count_magenta_rows(&im, y0, im.h, &fx, &fy);
    view_stats st;
    stats_read(dir, "view.json", &st);
    tp_test_note("%s: %ld magenta pixels below row %d; %.0f nodes drawn, %.0f substituted, "
                 "%.0f pending, %d levels", what, n, y0, json_number(text, "nodes_drawn"),
                 json_number(text, "substituted_nodes"), json_number(text, "pending"),
                 distinct_levels(&st));
    EXPECT_EQ_INT(0, n);
    if (n)
        ADD_FAILURE("%s: first magenta pixel at (%d, %d)", what, fx, fy);
    EXPECT_EQ_DBL(0, json_number(text, "pending"));
    EXPECT_EQ_DBL(0, json_number(text, "substituted_nodes"));
    EXPECT_GT(json_number(text, "nodes_drawn"), 0);
    if (sv.stitch_add) {
        /* vertices were added (else it proves nothing); the error is the drawn triangles' */
        tp_test_note("%s, --stitch add: %.0f sides take vertices, %.0f move; max error %.3f px",
                     what, json_number(text, "add_sides"), json_number(text, "moved_sides"),
                     json_number(text, "max_error_px"));
        EXPECT_GT(json_number(text, "add_sides"), 0);
        if (sv.lod.mode == TP_LOD_ERROR)
            EXPECT_LE(json_number(text, "max_error_px"), sv.lod.tau_px + 1e-6);
    } else {
        EXPECT_EQ_DBL(0, json_number(text, "add_sides"));
    }
    EXPECT_GE_INT(distinct_levels(&st), min_levels);
    free(im.px);
}
#endif

/* The error-LoD crack views of no_cracks_oblique_error_lod, drawn through a store (the sample
 * DEM built into the cache first, with the old path's patch size so nodes are small). */
TEST(store_no_cracks_oblique_error_lod)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dem = sample_dem();
        view_spec v = distance_lod_view;
        v.lod.mode = TP_LOD_ERROR;
        v.lod.tau_px = 6;
        v.cam[0] = 614000, v.cam[1] = 5030000, v.cam[2] = 2811, v.cam[3] = 270, v.cam[4] = -55;
        expect_store_no_magenta(dem, &v, 17, 0, "east side, 1500 m above", 2);
        v.lod.tau_px = 1;
        v.cam[0] = 602125, v.cam[1] = 5018000, v.cam[2] = 2950, v.cam[3] = 0;
        expect_store_no_magenta(dem, &v, 17, 0, "south flank, 1500 m above, tau 1", 1);
    }
#endif
}

/* --stitch add through a store (a DEM without --whole is built into one): the error-LoD crack
 * views of no_cracks_oblique_error_lod and a top-down distance view. Same-size nodes add
 * vertices, smaller ones next to larger ones move theirs; both must happen. The view measures
 * the triangles drawn, which tau bounds. A bad mode is a usage error. */
TEST(store_no_cracks_stitch_add)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dem = sample_dem();
        view_spec v = distance_lod_view;
        v.stitch_add = 1;
        v.cam[0] = 602125, v.cam[1] = 5025267, v.cam[2] = 3700, v.cam[3] = 0, v.cam[4] = -90;
        expect_store_no_magenta(dem, &v, 17, 0, "summit, 280 m above, distance", 2);
        v.lod.mode = TP_LOD_ERROR;
        v.lod.tau_px = 6;
        v.cam[0] = 614000, v.cam[1] = 5030000, v.cam[2] = 2811, v.cam[3] = 270, v.cam[4] = -55;
        expect_store_no_magenta(dem, &v, 17, 0, "east side, 1500 m above", 2);
        v.lod.tau_px = 8;
        v.cam[0] = 602125, v.cam[1] = 5018000, v.cam[2] = 2950, v.cam[3] = 0;
        expect_store_no_magenta(dem, &v, 17, 0, "south flank, 1500 m above", 2);

        const char* dir = make_tmp_dir();
        args a;
        args_view(&a);
        args_add(&a, "--stitch");
        args_add(&a, "sideways");
        args_add(&a, "--whole");
        args_add(&a, "%s", sample_dem());
        expect_failure(&a, dir, 2, "--stitch");
    }
#endif
}

/* A store viewed low over N42E001 (~420k triangles at tau = 1): from the third frame on, the
 * draw maps no new memory. llvmpipe frees its binned scene (~18 MB here) at the end of every
 * frame; before gl_context.c kept it in the heap (mallopt), glibc returned it to the system and
 * the next frame faulted it in again: 4,539 minor faults per frame on this view, twice the draw
 * time of the same frame through --whole (whose process had raised glibc's trim threshold by
 * freeing a large block while loading the DEM). */
TEST(store_frames_reuse_the_drivers_memory)
{
    REQUIRE_IO();
    /* Under AddressSanitizer malloc is ASan's and mallopt does not apply: the view is still
     * drawn and its statistics checked, the fault count is not. */
    int asan = 0;
#if defined(__SANITIZE_ADDRESS__)
    asan = 1;
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
    asan = 1;
#endif
#endif
#ifndef TP_TEST_NO_IO
    {
        char dem[1024];
        if (!tp_test_data_path(dem, sizeof dem, "TP_SHARED_DATA_DIR", "N42E001.hgt"))
            SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
        const char* dir = make_tmp_dir();
        char json[1200], text[8192];
        args a;
        args_view(&a);
        args_add(&a, "--headless");
        args_add(&a, "--no-hud");
        args_add(&a, "--frames");
        args_add(&a, "3");
        args_add(&a, "--camera-geo");
        args_add(&a, "42.5,1.2,1500,90,-10");
        args_add(&a, "--stats-json");
        args_add(&a, "%s/view.json", dir);
        args_add(&a, "%s", dem);
        run_ok(&a, dir);
        snprintf(json, sizeof json, "%s/view.json", dir);
        read_text(json, text, sizeof text, NULL);
        double faults = json_number(text, "draw_page_faults");
        double triangles = json_number(text, "triangles");
        tp_test_note("third frame: %.0f triangles, %.0f nodes, draw %.1f ms, %.0f page faults",
                     triangles, json_number(text, "nodes_drawn"), json_number(text, "draw_ms"),
                     faults);
        EXPECT_GT(triangles, 100000); /* a view whose scene is megabytes */
        EXPECT_GE(faults, 0); /* the key is there */
        if (!asan)
            EXPECT_LT(faults, 512); /* 2 MB; 4,539 before */
    }
#endif
}

/* Issue 12 section 4: N41E001 + N42E001 built into one store; a low view from the south across
 * the 42N seam shows no background below the horizon, and along the seam the full-resolution
 * surface has no gap and the drawn surface (a full-resolution cut of that view) is the
 * full-resolution surface on the seam and half a sample either side of it. */
TEST(two_tile_seam_shows_no_crack_and_no_step)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        char tiles[2][1024], store_path[1200];
        if (!tp_test_data_path(tiles[0], sizeof tiles[0], "TP_SHARED_DATA_DIR", "N41E001.hgt") ||
            !tp_test_data_path(tiles[1], sizeof tiles[1], "TP_SHARED_DATA_DIR", "N42E001.hgt"))
            SKIP("N41E001.hgt / N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
        const char* dir = make_tmp_dir();
        snprintf(store_path, sizeof store_path, "%s/two.tpt", dir);
        args a;
        args_view(&a);
        a.n = 1; /* the binary, then build's arguments */
        args_add(&a, "build");
        args_add(&a, "--quiet");
        args_add(&a, "%s", tiles[0]);
        args_add(&a, "%s", tiles[1]);
        args_add(&a, "-o");
        args_add(&a, "%s", store_path);
        run_ok(&a, dir);

        tp_store* st = NULL;
        tp_error err = {{0}};
        ASSERT_OK(tp_store_open(store_path, &st, &err));
        tp_store_info si;
        tp_store_get_info(st, &si);
        size_t count = 0;
        const tp_node_meta* metas = tp_store_metas(st, &count);
        tp_tree_desc td;
        memset(&td, 0, sizeof td);
        td.geometry = si.header.geometry;
        memcpy(td.geotransform, si.header.geotransform, sizeof td.geotransform);
        td.height_step_m = si.header.height_step_m;
        td.quant_max_error_m = si.header.quant_max_error_m;
        td.err_unit_steps = si.header.err_unit_steps;
        td.metas = metas;
        td.meta_count = count;
        tp_tree* t = NULL;
        ASSERT_OK(tp_tree_create(&td, &t, &err));
        const tp_tree_geometry* g = tp_tree_get_geometry(t);
        size_t side = ((size_t)1 << g->n) + 1;
        uint16_t* blocks = malloc((size_t)g->node_count * side * side * sizeof *blocks);
        ASSERT_TRUE(blocks != NULL);
        for (int64_t i = 0; i < g->node_count; i++) {
            ASSERT_OK(tp_store_read_node(st, i, blocks + (size_t)i * side * side, side * side, &err));
            tp_tree_attach(t, i, blocks + (size_t)i * side * side);
        }
        tp_georef* geo = NULL;
        ASSERT_OK(tp_georef_create(si.header.crs_wkt, si.header.geotransform, &geo, &err));

        /* from 12 km south of the seam at 1.5E, 350 m above the highest ground, looking north */
        tp_tree_info ti;
        tp_tree_get_info(t, &ti);
        double ce, cn;
        ASSERT_OK(tp_georef_geo_to_proj(geo, 41.89, 1.5, &ce, &cn, &err));
        view_spec v = {{ce, cn, 0, 0, -6}, 640, 360, {.mode = TP_LOD_ERROR, .tau_px = 1}, 1, 1, 0};
        double cx, cy;
        tp_tree_world_to_grid(t, ce, cn, &cx, &cy);
        v.cam[2] = 350 + fmax(tp_tree_height_at(t, cx, cy), 600);
        /* the horizon: the far plane of a flat earth at the eye's height is at the image centre;
         * terrain rises above it, so only rows below the middle must be ground */
        expect_store_no_magenta(store_path, &v, 0, v.h / 2 + 2, "across the 42N seam", 2);

        /* the seam in the drawn surface */
        tp_cut* cut = NULL;
        ASSERT_OK(tp_cut_create(t, &cut, &err));
        tp_camera cam;
        camera_from(&v, &cam);
        tp_lod_params full = {.mode = TP_LOD_FULL};
        ASSERT_OK(tp_cut_update(cut, &cam, &full, &err));
        int along = 0, defined = 0, drawn = 0;
        double worst = 0;
        for (double lon = 1.02; lon <= 1.98; lon += 0.0005) {
            double e, n, x, y;
            ASSERT_OK(tp_georef_geo_to_proj(geo, 42.0, lon, &e, &n, &err));
            tp_tree_world_to_grid(t, e, n, &x, &y);
            along++;
            for (int k = -1; k <= 1; k++) {
                double yy = y + 0.5 * k, h = tp_tree_height_at(t, x, yy);
                if (isnan(h))
                    continue;
                defined += k == 0;
                double d = tp_cut_drawn_height_at(cut, x, yy);
                if (isnan(d))
                    continue; /* outside the view */
                drawn++;
                worst = fmax(worst, fabs(d - h));
            }
        }
        tp_test_note("seam: %d points, %d with a full-resolution height, %d drawn samples; "
                     "largest |drawn - full| %.3g m", along, defined, drawn, worst);
        EXPECT_EQ_INT(along, defined); /* no gap between the tiles */
        EXPECT_GT(drawn, along);       /* the view covers the seam */
        EXPECT_LE(worst, 1e-3);
        tp_cut_destroy(cut);
        tp_georef_destroy(geo);
        tp_tree_destroy(t);
        free(blocks);
        tp_store_close(st);
    }
#endif
}

/* A store with one damaged node: the view says so once (one line naming the node), draws its
 * ancestor there (a substitution, no hole) and exits 0; a tiny --gpu-memory still draws every
 * node (the pool grows past it for that frame). */
TEST(store_damaged_node_is_reported_once_and_drawn_as_its_ancestor)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dir = make_tmp_dir();
        char store_path[1200], text[8192], json[1200];
        snprintf(store_path, sizeof store_path, "%s/hood.tpt", dir);
        args a;
        args_view(&a);
        a.n = 1;
        args_add(&a, "build");
        args_add(&a, "--quiet");
        args_add(&a, "--patch");
        args_add(&a, "17");
        args_add(&a, "%s", sample_dem());
        args_add(&a, "-o");
        args_add(&a, "%s", store_path);
        run_ok(&a, dir);
        char ok_path[1300];
        snprintf(ok_path, sizeof ok_path, "%s/hood_ok.tpt", dir);
        copy_file(store_path, ok_path);
        /* --lod full draws every leaf in view: damage node data a third into the data area,
         * which starts after the location table (docs/store.md: its offset and size are u64s
         * at 16 and 24 in the 56-byte footer) */
        FILE* f = fopen(store_path, "r+b");
        ASSERT_TRUE(f != NULL);
        fseek(f, 0, SEEK_END);
        long size = ftell(f);
        uint8_t foot[56];
        fseek(f, size - 56, SEEK_SET);
        ASSERT_TRUE(fread(foot, 1, 56, f) == 56);
        long data = 0;
        for (int k = 7; k >= 0; k--)
            data = data << 8 | foot[16 + k];
        long loc_bytes = 0;
        for (int k = 7; k >= 0; k--)
            loc_bytes = loc_bytes << 8 | foot[24 + k];
        data += loc_bytes;
        const long at = data + (size - 56 - data) / 3;
        fseek(f, at, SEEK_SET);
        int c = fgetc(f);
        fseek(f, at, SEEK_SET);
        fputc(c ^ 0x5A, f);
        fclose(f);
        image ok_im;
        for (int frames = 0; frames <= 3; frames += 2) { /* 0: the intact store */
            run_result rr;
            args_view(&a);
            args_add(&a, "--headless");
            args_add(&a, "--size");
            args_add(&a, "320x180");
            args_add(&a, "--clear-color");
            args_add(&a, "1,0,1");
            args_add(&a, "--camera");
            args_add(&a, "602125,5025267,40000,0,-90"); /* straight down on the whole map */
            args_add(&a, "--lod");
            args_add(&a, "full");
            args_add(&a, "--gpu-memory");
            args_add(&a, "16");
            args_add(&a, "--frames");
            args_add(&a, "%d", frames > 0 ? frames : 1);
            args_add(&a, "--stats-json");
            args_add(&a, "%s/bad.json", dir);
            args_add(&a, "--screenshot");
            args_add(&a, "%s/%s", dir, frames ? "bad.png" : "ok.png");
            args_add(&a, "%s", frames ? store_path : ok_path);
            run(&a, dir, &rr);
            if (!frames) {
                EXPECT_EQ_INT(0, rr.exit_code);
                EXPECT_EQ_INT(0, rr.err_lines);
                image_read(dir, "ok.png", &ok_im);
                continue;
            }
            tp_test_note("frames %d: exit %d, stderr: %s", frames, rr.exit_code, rr.err);
            EXPECT_EQ_INT(0, rr.exit_code);
            EXPECT_EQ_INT(1, rr.err_lines);
            EXPECT_CONTAINS(rr.err, "checksum");
            EXPECT_CONTAINS(rr.err, "drawing its ancestor instead");
            snprintf(json, sizeof json, "%s/bad.json", dir);
            int lines;
            read_text(json, text, sizeof text, &lines);
            EXPECT_GE(json_number(text, "substituted_nodes"), 1);
            EXPECT_EQ_DBL(0, json_number(text, "pending"));
            EXPECT_GT(json_number(text, "gpu_mb"), 16 * 1.048576); /* grown past the budget */
            image im;
            image_read(dir, "bad.png", &im);
            long n = 0;
            for (size_t i = 0; i < (size_t)im.w * im.h; i++)
                n += is_magenta(im.px + 4 * i) && !is_magenta(ok_im.px + 4 * i);
            EXPECT_EQ_INT(0, n); /* the ancestor covers the damaged node: no hole */
            free(im.px);
        }
        free(ok_im.px);
    }
#endif
}

/* The renderer's vertex pools (app/render/vertex_pool.c) hold what the frame draws at the levels
 * it draws: N42E001 through a 65-sample store, seen whole from above, draws its nodes at levels
 * 0..6, most of them at 2..4. GPU memory (gpu_bytes) is bounded here from the frame's level mix
 * alone, as the renderer documents its pools: a pool per level k of (2^k+1)^2-vertex slots, 16
 * bytes a vertex, starting with the slots that fit in 64 KB (at least one) and growing by a
 * quarter (at least one), so at most max(start, 1.25 * drawn + 1) slots; triangle-list regions
 * of 6 * 4^k 16-bit indices (k <= 7), 16 then growing by a quarter, at most
 * max(16, 1.25 * drawn + 1) at a drawn level; and the strips of levels 0..n (16-bit indices up
 * to n = 7). Slots of the finest level for every node (the pools before per-level slots), 64
 * slots a level to start with, regions of 6 * 4^n indices at every level, or pools that double
 * (up to 2 * drawn), each breaks the bound. */
TEST(store_vertex_pools_hold_the_levels_drawn)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        char dem[1024], text[8192], json[1200];
        if (!tp_test_data_path(dem, sizeof dem, "TP_SHARED_DATA_DIR", "N42E001.hgt"))
            SKIP("N42E001.hgt not found (set TP_SHARED_DATA_DIR)");
        const char* dir = make_tmp_dir();
        args a;
        args_view(&a);
        args_add(&a, "--headless");
        args_add(&a, "--no-hud");
        args_add(&a, "--size");
        args_add(&a, "640x360");
        args_add(&a, "--patch");
        args_add(&a, "65");
        args_add(&a, "--stats-json");
        args_add(&a, "%s/view.json", dir);
        args_add(&a, "%s", dem);
        run_ok(&a, dir);
        view_stats st;
        stats_read(dir, "view.json", &st);
        snprintf(json, sizeof json, "%s/view.json", dir);
        read_text(json, text, sizeof text, NULL);
        double gpu = json_number(text, "gpu_bytes");
        ASSERT_EQ_INT(7, st.level_count); /* levels 0..6: 65-sample nodes */
        int n = st.level_count - 1;
        double vertex_bytes = 16, nodes = 0, bound = 0;
        double finest_slot = ((1 << n) + 1) * ((1 << n) + 1) * vertex_bytes;
        for (int k = 0; k <= n; k++) {
            double slot = ((1 << k) + 1) * ((1 << k) + 1) * vertex_bytes;
            double start = floor(65536 / slot) < 1 ? 1 : floor(65536 / slot);
            double drawn = st.levels[k];
            nodes += drawn;
            bound += fmax(start, 1.25 * drawn + 1) * slot;
            if (drawn > 0)
                bound += fmax(16, 1.25 * drawn + 1) * 6 * pow(4, k) * 2;
            bound += (double)tp_strip_index_count(k) * 2;
        }
        double finest = nodes * finest_slot;
        tp_test_note("levels 0..6: %d %d %d %d %d %d %d (%.0f nodes); gpu_bytes %.0f, bound from "
                     "the levels %.0f, finest-level slots %.0f", st.levels[0], st.levels[1],
                     st.levels[2], st.levels[3], st.levels[4], st.levels[5], st.levels[6], nodes,
                     gpu, bound, finest);
        /* the view is one where the level mix matters: most nodes coarser than level n */
        ASSERT_TRUE(nodes >= 50);
        ASSERT_TRUE(st.levels[n] < nodes / 4);
        ASSERT_TRUE(bound < finest / 2);
        EXPECT_GT(gpu, 0);
        EXPECT_LE(gpu, bound);
        EXPECT_LT(gpu, finest / 2);
    }
#endif
}

/* `view DEM` builds the DEM into a store in the cache once and reuses it; another patch size
 * is another store; a cache directory that cannot be written builds in a temporary one. */
TEST(dem_is_built_into_the_cache_once)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dir = make_tmp_dir();
        char cache[1200], ro[1200];
        snprintf(cache, sizeof cache, "%s/cache", dir);
        /* below a plain file: not creatable, even for root */
        snprintf(ro, sizeof ro, "%s/plain", dir);
        FILE* pf = fopen(ro, "w");
        ASSERT_TRUE(pf != NULL);
        fclose(pf);
        snprintf(ro, sizeof ro, "%s/plain/cache", dir);
        const char* want[4] = {"building a store", NULL, "building a store", "not writable"};
        for (int i = 0; i < 4; i++) {
            args a;
            run_result rr;
            args_view(&a);
            args_add(&a, "--headless");
            args_add(&a, "--stats-json");
            args_add(&a, "%s/stats.json", dir);
            args_add(&a, "--size");
            args_add(&a, "64x36");
            args_add(&a, "--cache-dir");
            args_add(&a, "%s", i == 3 ? ro : cache);
            if (i == 2) {
                args_add(&a, "--patch");
                args_add(&a, "33");
            }
            args_add(&a, "%s", sample_dem());
            run(&a, dir, &rr);
            tp_test_note("run %d: exit %d, stderr: %s", i, rr.exit_code, rr.err);
            EXPECT_EQ_INT(0, rr.exit_code);
            if (want[i])
                EXPECT_CONTAINS(rr.err, want[i]);
            else
                EXPECT_TRUE(strstr(rr.err, "building") == NULL); /* reused */
        }
        EXPECT_EQ_INT(2, dir_entries(cache)); /* one store per patch size, no temp files */
        /* the temporary store is not left in the cache: TMPDIR got it */
    }
#endif
}

/* A store of an older format in the cache (left there by an earlier terrapatch) is stale: the
 * next `view DEM` builds it again, over it, and views. */
TEST(older_format_store_in_the_cache_is_rebuilt)
{
    REQUIRE_IO();
#ifndef TP_TEST_NO_IO
    {
        const char* dir = make_tmp_dir();
        char cache[1200];
        snprintf(cache, sizeof cache, "%s/cache", dir);
        char store[1600] = "";
        for (int i = 0; i < 2; i++) {
            args a;
            run_result rr;
            args_view(&a);
            args_add(&a, "--headless");
            args_add(&a, "--stats-json");
            args_add(&a, "%s/stats.json", dir);
            args_add(&a, "--size");
            args_add(&a, "64x36");
            args_add(&a, "--cache-dir");
            args_add(&a, "%s", cache);
            args_add(&a, "%s", sample_dem());
            run(&a, dir, &rr);
            tp_test_note("run %d: exit %d, stderr: %s", i, rr.exit_code, rr.err);
            EXPECT_EQ_INT(0, rr.exit_code);
            EXPECT_CONTAINS(rr.err, "building a store");
            ASSERT_EQ_INT(1, dir_entries(cache));
            DIR* d = opendir(cache);
            struct dirent* e;
            while ((e = readdir(d)) != NULL)
                if (e->d_name[0] != '.')
                    snprintf(store, sizeof store, "%s/%s", cache, e->d_name);
            closedir(d);
            /* the header's version (u32 at 8) and CRC32 (its last 4 bytes): docs/store.md */
            int fd = open(store, O_RDWR);
            ASSERT_TRUE(fd >= 0);
            uint8_t head[160];
            ASSERT_TRUE(pread(fd, head, sizeof head, 0) == (ssize_t)sizeof head);
            const uint32_t version = (uint32_t)head[8] | (uint32_t)head[9] << 8;
            EXPECT_EQ_INT(TP_STORE_VERSION, version);
            if (i == 0) {
                const uint32_t hsize = (uint32_t)head[12] | (uint32_t)head[13] << 8 |
                                       (uint32_t)head[14] << 16 | (uint32_t)head[15] << 24;
                uint8_t* h = malloc(hsize);
                ASSERT_TRUE(h && pread(fd, h, hsize, 0) == (ssize_t)hsize);
                h[8] = TP_STORE_VERSION - 1, h[9] = h[10] = h[11] = 0; /* format 3: no filled bits */
                uint32_t c = 0xFFFFFFFFu;
                for (uint32_t k = 0; k < hsize - 4; k++) {
                    c ^= h[k];
                    for (int b = 0; b < 8; b++)
                        c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
                }
                c = ~c;
                for (int b = 0; b < 4; b++)
                    h[hsize - 4 + b] = (uint8_t)(c >> (8 * b));
                ASSERT_TRUE(pwrite(fd, h, hsize, 0) == (ssize_t)hsize);
                free(h);
                tp_store* st = NULL;
                tp_error err = {{0}};
                EXPECT_STATUS(TP_ERR_BAD_DATA, tp_store_open(store, &st, &err));
                char want[64];
                snprintf(want, sizeof want, "older terrapatch (format %d", TP_STORE_VERSION - 1);
                EXPECT_CONTAINS(err.message, want);
            }
            close(fd);
        }
    }
#endif
}

#define TESTS(X)                                                                                   \
    X(store_no_cracks_oblique_error_lod)                                                           \
    X(store_frames_reuse_the_drivers_memory)                                                       \
    X(two_tile_seam_shows_no_crack_and_no_step)                                                    \
    X(store_damaged_node_is_reported_once_and_drawn_as_its_ancestor)                               \
    X(store_vertex_pools_hold_the_levels_drawn)                                                    \
    X(dem_is_built_into_the_cache_once)                                                            \
    X(older_format_store_in_the_cache_is_rebuilt)                                                  \
    X(no_cracks_top_down_distance_lod)                                                             \
    X(no_cracks_oblique_distance_lod)                                                              \
    X(no_cracks_oblique_error_lod)                                                                 \
    X(no_cracks_stitch_add)                                                                        \
    X(no_cracks_stitch_add_five)                                                                   \
    X(store_no_cracks_stitch_add)                                            \
    X(utm_and_local_origin_render_alike)                                                           \
    X(stats_json_equals_core_selection_error_lod)                                                  \
    X(stats_json_equals_core_selection_distance_lod)                                               \
    X(looking_at_the_sky_culls_every_patch)                                                        \
    X(looking_north_culls_the_patches_behind)                                                      \
    X(reference_view_matches_committed_image)                                                      \
    X(texture_drapes_the_imagery)                                                                  \
    X(screenshot_into_missing_directory_exits_1)                                                   \
    X(screenshot_onto_a_directory_exits_1_and_leaves_no_file)                                      \
    X(size_below_16_exits_2)                                                                       \
    X(camera_with_three_values_exits_2)                                                            \
    X(unknown_lod_mode_exits_2)                                                                    \
    X(missing_dem_exits_1)                                                                         \
    X(multi_draw_equals_one_draw_per_patch_default_view)                                           \
    X(multi_draw_equals_one_draw_per_patch_crater_lake_full_from_above)                            \
    X(exaggeration_keeps_patches_that_rise_into_view)                                              \
    X(exaggeration_error_lod_keeps_tau_on_screen)                                                  \
    X(picked_points_lie_on_the_drawn_surface)                                                      \
    X(picked_points_lie_on_the_exaggerated_surface)                                                \
    X(hud_is_not_cut_at_1024x768)                                                                  \
    X(hud_is_not_cut_at_1280x720)                                                                  \
    X(frame_without_terrain_says_so)

TP_TEST_MAIN(TESTS)
