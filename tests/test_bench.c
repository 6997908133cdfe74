/*
 * test_bench.c - `terrapatch bench` end to end: the command runs as a child process
 * (posix_spawn, an argument vector, no shell) and the test reads back what it wrote:
 *
 *   - --sweep: one CSV row per configuration (full, the 24 distance configurations, the error
 *     configurations, --stitch add at the run's distance and at every tau, PGM per grid, the
 *     DEM's store from the cache at every tau with lattice and with TIN nodes), each
 *     family's Pareto column recomputed here from the CSV and the JSON, the plot (a PNG beside
 *     the CSV or at --plot), no temporary files left;
 *   - --static --max-error: the bounds hold, the meshes shrink as the bound grows, the mesh is
 *     the one `export --max-error` writes (read back with VTK), bounds below the quantisation
 *     error are reported, not measured;
 *   - --speed: the lead-in frames change what is uploaded, not what is drawn;
 *   - bad command lines exit 2 with a message naming the option and write nothing; outputs
 *     that cannot be written exit 1 and leave no temporary file.
 *
 * Frame runs use the small sample DEM data/storml_elev_orig.tif (143 x 107, 30 m, NAD83 / UTM
 * 12N) at 160x90 and one or two frames per configuration, so each test takes about a second.
 *
 * The binary comes from the environment: TP_TERRAPATCH (tests/CMakeLists.txt sets it to
 * $<TARGET_FILE:terrapatch>); without it every test here skips. Without EGL the frame tests
 * skip too (the --static ones need no OpenGL).
 */
#define _POSIX_C_SOURCE 200809L
#include "tp_test.h"
#include "tp_test_child.h"
#ifndef TP_TEST_NO_IO
#include "tp_io.h"
#endif

/* A TIN's bound holds at every sample as tin.c interpolates; the export measures each triangle
 * again with another double formula (tp_triangle_rasterize), which may find an error of exactly
 * M about 1e-13 m above it. */
#define TIN_ROUNDING_M 1e-9

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <spawn.h>
#include <sys/stat.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>


#define STORML "storml_elev_orig.tif"        /* data/ (TP_SAMPLE_DATA_DIR), Int16 */
#define MT_HOOD "lf_elev_220_mt_hood_utm.tif" /* data/, 1013 x 799, integer heights */
#define CRATER "craterlake-elev-16bit-30m.tif" /* data/: height step 1/128 m */

/* The sweep's grid (app/bench/bench_sweep.c, documented in `bench --help`): distance mode in
 * patch widths W = (patch - 1) sample spacings, error mode in pixels; the same taus with
 * --stitch add, and one distance configuration with it (the run's); PGM's grids. */
static const double grid_mindist_w[] = {1, 4};
static const double grid_maxdist_w[] = {12, 24, 48, 96};
static const double grid_exp[] = {0.5, 1, 2};
static const double grid_tau[] = {0.5, 1, 2, 4, 8, 16};
static const char* const grid_pgm[] = {"150x600", "200x800", "300x900", "600x600",
                                       "400x1600", "300x300", "430x430"};
#define COUNT(a) ((int)(sizeof(a) / sizeof *(a)))
#define SWEEP_ROWS (1 + 2 * 4 * 3 + 6 + 1 + 6 + 7 + 6 + 6)

#define TP_TMP_PREFIX "tp_bench_"
#include "tp_test_tmp.h"

/* The children's stdout and stderr go here, never into a directory whose contents a test
 * checks. */
static const char* log_dir(void)
{
    static const char* dir;
    if (!dir)
        dir = make_tmp_dir();
    return dir;
}

/* dir's entries, sorted and joined with ',' ("" when empty, "(missing)" when not there). */
static const char* dir_listing(const char* dir, char* buf, size_t cap)
{
    char names[64][256];
    int n = 0;
    DIR* d = opendir(dir);
    struct dirent* e;
    buf[0] = '\0';
    if (!d) {
        snprintf(buf, cap, "(missing)");
        return buf;
    }
    while ((e = readdir(d)) != NULL && n < 64)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, ".."))
            snprintf(names[n++], sizeof names[0], "%s", e->d_name);
    closedir(d);
    for (int i = 1; i < n; i++) /* insertion sort: a handful of names */
        for (int k = i; k > 0 && strcmp(names[k - 1], names[k]) > 0; k--) {
            char t[256];
            memcpy(t, names[k], sizeof t);
            memcpy(names[k], names[k - 1], sizeof t);
            memcpy(names[k - 1], t, sizeof t);
        }
    size_t used = 0;
    for (int i = 0; i < n && used < cap; i++)
        used += (size_t)snprintf(buf + used, cap - used, "%s%s", i ? "," : "", names[i]);
    return buf;
}

/* The directory holds exactly these entries (sorted, ','-joined; "" for none). */
#define EXPECT_DIR_IS(dir, expected)                                                               \
    do {                                                                                           \
        char tp_listing_[4096];                                                                    \
        dir_listing(dir, tp_listing_, sizeof tp_listing_);                                         \
        TP_CHECK_(0, strcmp(tp_listing_, expected) == 0, "%s holds [%s], expected [%s]", dir,      \
                  tp_listing_, expected);                                                          \
    } while (0)

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

/* argv[0] = the binary, argv[1] = cmd; skips the test without a binary. */
static void args_cmd(args* a, const char* cmd)
{
    const char* exe = getenv("TP_TERRAPATCH");
    if (!exe || !*exe)
        SKIP("TP_TERRAPATCH is not set (the terrapatch binary; set by tests/CMakeLists.txt)");
    if (access(exe, X_OK) != 0)
        SKIP("TP_TERRAPATCH=%s is not an executable", exe);
    memset(a, 0, sizeof *a);
    args_add(a, "%s", exe);
    args_add(a, "%s", cmd);
}

/* bench with the small frame settings: --frames N --size 160x90. */
static void args_bench_small(args* a, int frames)
{
    args_cmd(a, "bench");
    args_add(a, "--frames");
    args_add(a, "%d", frames);
    args_add(a, "--size");
    args_add(a, "160x90");
}

typedef struct run_result {
    int exit_code;   /* exit status, or 128 + signal */
    char out[65536]; /* stdout (the start of it) */
    char err[65536]; /* stderr (the start of it) */
    int err_lines;   /* '\n' in all of stderr */
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

/* The whole file as a NUL-terminated string (malloc), or NULL. */
static char* read_file(const char* path, size_t* size)
{
    FILE* f = fopen(path, "rb");
    if (!f)
        return NULL;
    size_t cap = 1 << 16, n = 0, got;
    char* buf = malloc(cap);
    while (buf && (got = fread(buf + n, 1, cap - n - 1, f)) > 0) {
        n += got;
        if (n + 1 == cap) {
            char* more = realloc(buf, cap *= 2);
            if (!more) {
                free(buf);
                buf = NULL;
            }
            buf = more;
        }
    }
    fclose(f);
    if (buf)
        buf[n] = '\0';
    if (size)
        *size = n;
    return buf;
}

/* Runs a->v with stdin from /dev/null and stdout/stderr into files of the log directory. */
static void run(const args* a, run_result* r)
{
    char out_path[1024], err_path[1024], asan[1024];
    posix_spawn_file_actions_t fa;
    pid_t pid;
    int status = 0, rc;
    const char* logs = log_dir();
    r->exit_code = -1;
    r->out[0] = r->err[0] = '\0';
    r->err_lines = 0;
    snprintf(out_path, sizeof out_path, "%s/child.stdout", logs);
    snprintf(err_path, sizeof err_path, "%s/child.stderr", logs);
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

static void print_command(const args* a)
{
    fprintf(stderr, "command:");
    for (int i = 0; i < a->n; ++i)
        fprintf(stderr, " %s", a->v[i]);
    fputc('\n', stderr);
}

/* No EGL / OpenGL 3.3 on this machine (app/gl_context.c), or no gnuplot for --sweep's plot
 * (app/bench_plot.c; `make deps` installs gnuplot-nox): a missing backend, not a bug. */
static void skip_without_gl(const run_result* r)
{
    if (r->exit_code == 1 && (strstr(r->err, "no EGL surfaceless display") ||
                              strstr(r->err, "no OpenGL 3.3 core context through EGL")))
        SKIP("no headless OpenGL here: %s", r->err);
    if (r->exit_code == 1 && strstr(r->err, "cannot run gnuplot"))
        SKIP("no gnuplot here: %s", strstr(r->err, "cannot run gnuplot"));
}

/* The last three lines of stderr, where a failure's message is (after bench's progress). */
static const char* err_tail(const run_result* r)
{
    const char* p = r->err + strlen(r->err);
    int lines = 0;
    while (p > r->err && (lines += p[-1] == '\n') <= 3)
        p--;
    return p;
}

/* Runs and requires exit status 0 (printing the command and stderr otherwise). */
static void run_ok(const args* a, run_result* r)
{
    run(a, r);
    skip_without_gl(r);
    if (r->exit_code != 0) {
        print_command(a);
        FAIL("exit status %d, stderr ends: %s", r->exit_code, err_tail(r));
    }
}

/* Bad command line: exit status 2, one line on stderr naming what was wrong, nothing on
 * stdout, and nothing written into out_dir. */
static void expect_usage_error(const args* a, const char* needle, const char* out_dir)
{
    static run_result r;
    run(a, &r);
    if (r.exit_code != 2 || r.err_lines != 1 || !strstr(r.err, needle))
        print_command(a);
    EXPECT_EQ_INT(2, r.exit_code);
    EXPECT_EQ_INT(1, r.err_lines);
    EXPECT_CONTAINS(r.err, needle);
    EXPECT_TRUE(r.out[0] == '\0');
    if (out_dir)
        EXPECT_DIR_IS(out_dir, "");
}

static const char* sample_path(const char* file)
{
    static char path[4][1024];
    static int next;
    char* p = path[next++ % 4];
    if (!tp_test_data_path(p, sizeof path[0], "TP_SAMPLE_DATA_DIR", file))
        SKIP("data file %s not found (set TP_SAMPLE_DATA_DIR)", p);
    return p;
}

static const char* shared_path(const char* file)
{
    static char path[1024];
    if (!tp_test_data_path(path, sizeof path, "TP_SHARED_DATA_DIR", file))
        SKIP("data file %s not found (set TP_SHARED_DATA_DIR)", path);
    return path;
}

/* ---------------------------------------------------------------------------------------------
 * Reading the outputs back: CSV (comma-separated, no quoting: bench writes none), the JSON
 * keys bench writes (flat objects, one array of flat objects), PNG headers.
 */
typedef struct csv {
    char* text;
    char** cell; /* rows * cols, row 0 the header */
    int rows, cols; /* rows without the header */
    int ragged;     /* some line had another number of fields than the header */
} csv;

static void csv_read(const char* path, csv* c)
{
    memset(c, 0, sizeof *c);
    c->text = read_file(path, NULL);
    if (!c->text)
        FAIL("%s: cannot read: %s", path, strerror(errno));
    int lines = 0;
    for (const char* s = c->text; *s; s++)
        lines += *s == '\n';
    int cols = 1;
    for (const char* s = c->text; *s && *s != '\n'; s++)
        cols += *s == ',';
    c->cols = cols;
    c->cell = calloc((size_t)(lines + 1) * (size_t)cols, sizeof *c->cell);
    ASSERT_TRUE(c->cell != NULL);
    int row = 0;
    char* s = c->text;
    while (*s && row <= lines) {
        char* eol = strchr(s, '\n');
        if (!eol)
            FAIL("%s: the last line has no newline", path);
        *eol = '\0';
        int k = 0;
        for (char* f = s;; k++) {
            char* comma = strchr(f, ',');
            if (k < cols)
                c->cell[row * cols + k] = f;
            if (!comma)
                break;
            *comma = '\0';
            f = comma + 1;
        }
        if (k + 1 != cols)
            c->ragged = 1;
        row++;
        s = eol + 1;
    }
    c->rows = row - 1;
}

static void csv_free(csv* c)
{
    free(c->cell);
    free(c->text);
    memset(c, 0, sizeof *c);
}

static int csv_col(const csv* c, const char* name)
{
    for (int k = 0; k < c->cols; k++)
        if (c->cell[k] && !strcmp(c->cell[k], name))
            return k;
    FAIL("CSV has no column %s", name);
    return -1;
}

/* Cell of data row i (0-based, after the header). */
static const char* csv_str(const csv* c, int i, const char* name)
{
    const char* s = c->cell[(i + 1) * c->cols + csv_col(c, name)];
    return s ? s : "";
}

static double csv_num(const csv* c, int i, const char* name)
{
    const char* s = csv_str(c, i, name);
    char* end;
    double v = strtod(s, &end);
    if (end == s || *end)
        FAIL("CSV row %d, column %s: expected a number, got '%s'", i, name, s);
    return v;
}

/* Where the value of "key" starts in [from, to) (to NULL: the end of the string), or NULL. */
static const char* json_value(const char* from, const char* to, const char* key)
{
    char quoted[128];
    snprintf(quoted, sizeof quoted, "\"%s\":", key);
    const char* p = strstr(from, quoted);
    if (!p || (to && p >= to))
        return NULL;
    p += strlen(quoted);
    while (*p == ' ' || *p == '\n')
        p++;
    return p;
}

static double json_num(const char* from, const char* to, const char* key)
{
    const char* p = json_value(from, to, key);
    char* end;
    if (!p)
        FAIL("JSON has no key %s", key);
    double v = strtod(p, &end);
    if (end == p)
        FAIL("JSON key %s: expected a number, got '%.20s'", key, p);
    return v;
}

static int json_bool(const char* from, const char* to, const char* key)
{
    const char* p = json_value(from, to, key);
    if (!p)
        FAIL("JSON has no key %s", key);
    if (!strncmp(p, "true", 4))
        return 1;
    if (!strncmp(p, "false", 5))
        return 0;
    FAIL("JSON key %s: expected true or false, got '%.20s'", key, p);
    return -1;
}

/* Copies the string value of key into buf ("" when absent). */
static const char* json_str(const char* from, const char* to, const char* key, char* buf,
                            size_t cap)
{
    const char* p = json_value(from, to, key);
    buf[0] = '\0';
    if (p && *p == '"') {
        const char* q = strchr(p + 1, '"');
        if (q)
            snprintf(buf, cap, "%.*s", (int)(q - p - 1), p + 1);
    }
    return buf;
}

/* The objects of the array "key" (flat objects, as bench writes them): their [start, end). */
static int json_objects(const char* text, const char* key, const char** start, const char** end,
                        int cap)
{
    const char* p = json_value(text, NULL, key);
    int n = 0;
    if (!p)
        FAIL("JSON has no key %s", key);
    if (*p != '[')
        FAIL("JSON key %s: expected an array", key);
    for (p++;;) {
        while (*p == ' ' || *p == '\n' || *p == ',')
            p++;
        if (*p == ']')
            return n;
        if (*p != '{' || n == cap)
            FAIL("JSON array %s: unexpected '%.20s' after %d objects", key, p, n);
        const char* close = strchr(p, '}');
        if (!close)
            FAIL("JSON array %s: unterminated object", key);
        start[n] = p;
        end[n++] = close;
        p = close + 1;
    }
}

/* A PNG's header: signature and IHDR; *w, *h its size. Returns 1 if it is one. */
static int png_header(const char* path, unsigned* w, unsigned* h, size_t* size)
{
    static const unsigned char sig[8] = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
    unsigned char b[24];
    struct stat st;
    FILE* f = fopen(path, "rb");
    size_t got = f ? fread(b, 1, sizeof b, f) : 0;
    if (f)
        fclose(f);
    *size = stat(path, &st) == 0 ? (size_t)st.st_size : 0;
    if (got != sizeof b || memcmp(b, sig, 8) || memcmp(b + 12, "IHDR", 4))
        return 0;
    *w = (unsigned)b[16] << 24 | (unsigned)b[17] << 16 | (unsigned)b[18] << 8 | b[19];
    *h = (unsigned)b[20] << 24 | (unsigned)b[21] << 16 | (unsigned)b[22] << 8 | b[23];
    return 1;
}

/* The plot exists and is a real image: PNG signature, a plausible size, not a stub. */
static void expect_plot(const char* path)
{
    unsigned w = 0, h = 0;
    size_t size = 0;
    int ok = png_header(path, &w, &h, &size);
    TP_CHECK_(0, ok, "%s: not a PNG (missing, or no PNG signature and IHDR)", path);
    if (!ok)
        return;
    tp_test_note("%s: %ux%u, %zu bytes", path, w, h, size);
    EXPECT_GE(w, 600.0);
    EXPECT_GE(h, 300.0);
    EXPECT_GT((double)size, 10000.0); /* two panels with axes, points and labels */
}

/* `terrapatch info --json DEM`: the render grid's spacing and the patch size. */
static void dem_patch_width(const char* dem, double* patch_width_m)
{
    static run_result r;
    args a;
    args_cmd(&a, "info");
    args_add(&a, "--json");
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    *patch_width_m = (json_num(r.out, NULL, "patch") - 1) * json_num(r.out, NULL, "spacing_m");
}

/* ---------------------------------------------------------------------------------------------
 * --sweep
 */
/* The row's family: full, distance, error (vertex moving), distance+add, error+add, pgm. */
static int is_mode(const csv* c, int i, const char* family)
{
    return !strcmp(csv_str(c, i, "family"), family);
}

/* Pareto flags recomputed for rows of one family: no other row of the family has fps >= and
 * max px <= with one of them strict. */
static int dominated(const double* fps, const double* px, const int* same_mode, int n, int i)
{
    for (int k = 0; k < n; k++)
        if (k != i && same_mode[k] && fps[k] >= fps[i] && px[k] <= px[i] &&
            (fps[k] > fps[i] || px[k] < px[i]))
            return 1;
    return 0;
}

/* The store families (bench_sweep_store.c): the DEM's store through its cut in the error mode,
 * lattice nodes ("store") and TIN nodes ("store+tin"), one row at each tau of the grid (not
 * --tau's: the headline is the DEM's error mode); each measured within its tau on screen, no
 * vertical error; the TIN rows draw TINs, and fewer triangles than the lattice at the same tau
 * (the TIN of a node holds the lattice's own bound with fewer vertices, on any real relief). */
static void check_store_families(const csv* c)
{
    int rows[2][COUNT(grid_tau)];
    for (int m = 0; m < 2; m++)
        for (int k = 0; k < COUNT(grid_tau); k++)
            rows[m][k] = -1;
    for (int i = 0; i < c->rows; i++) {
        int tin = is_mode(c, i, "store+tin");
        if (!tin && !is_mode(c, i, "store"))
            continue;
        EXPECT_EQ_STR("error", csv_str(c, i, "lod_mode"));
        EXPECT_EQ_STR(tin ? "tin" : "lattice", csv_str(c, i, "mesh"));
        double t = csv_num(c, i, "tau_px");
        int k = 0;
        while (k < COUNT(grid_tau) && grid_tau[k] != t)
            k++;
        if (k == COUNT(grid_tau) || rows[tin][k] >= 0) {
            ADD_FAILURE("%s row %d: tau %s off the grid or twice", csv_str(c, i, "family"), i,
                        csv_str(c, i, "tau_px"));
            continue;
        }
        rows[tin][k] = i;
        double mpx = csv_num(c, i, "max_screen_error_px");
        EXPECT_TRUE(isfinite(mpx));
        EXPECT_LE(mpx, t * (1 + 1e-9)); /* the cut's promise, measured on what it drew */
        EXPECT_FALSE(isfinite(csv_num(c, i, "max_vertical_error_m")));
        double share = csv_num(c, i, "tin_share");
        if (tin) { /* every drawn node complete: most of them draw a TIN */
            EXPECT_GT(share, 0.0);
            EXPECT_LE(share, 1.0);
        } else {
            EXPECT_EQ_DBL(0.0, share);
        }
    }
    for (int k = 0; k < COUNT(grid_tau); k++) {
        int l = rows[0][k], t = rows[1][k];
        if (l < 0 || t < 0) {
            ADD_FAILURE("tau %g: no %s row", grid_tau[k], l < 0 ? "store" : "store+tin");
            continue;
        }
        double lt = csv_num(c, l, "triangles_median"), tt = csv_num(c, t, "triangles_median");
        tp_test_note("tau %g: store %.0f triangles, store+tin %.0f (%.0f%%), max %s / %s px",
                     grid_tau[k], lt, tt, 100 * tt / lt, csv_str(c, l, "max_screen_error_px"),
                     csv_str(c, t, "max_screen_error_px"));
        if (!(tt < lt))
            ADD_FAILURE("tau %g: TIN nodes draw %.0f triangles, the lattice %.0f", grid_tau[k],
                        tt, lt);
    }
}

/* The checks every sweep's CSV and JSON must pass; extra_tau > 0: --tau off the grid. */
static void check_sweep(const char* dem, const char* csv_path, const char* json_path,
                        const run_result* r, double extra_tau)
{
    double w;
    dem_patch_width(dem, &w);
    csv c;
    csv_read(csv_path, &c);
    static const char* const header[] = {
        "family", "lod_mode", "stitch", "pgm_grid", "tau_px", "mindist_m", "maxdist_m", "exp",
        "fps_median", "cpu_ms_median", "triangles_median", "gpu_mib", "max_screen_error_px",
        "rms_screen_error_px", "uncovered_share", "pareto", "mesh", "tin_share"};
    for (int k = 0; k < COUNT(header); k++)
        (void)csv_col(&c, header[k]);
    EXPECT_FALSE(c.ragged);
    int expected_rows = SWEEP_ROWS + (extra_tau > 0);
    ASSERT_EQ_INT(expected_rows, c.rows);

    /* families: full first, then 24 distance, then the error configurations, then the ones
     * with --stitch add and PGM's; every one measured (finite errors) and drawing triangles */
    int n_full = 0, n_dist = 0, n_err = 0, n_dadd = 0, n_eadd = 0, n_pgm = 0, n_store = 0,
        n_tin = 0;
    for (int i = 0; i < c.rows; i++) {
        n_full += is_mode(&c, i, "full");
        n_dist += is_mode(&c, i, "distance");
        n_err += is_mode(&c, i, "error");
        n_dadd += is_mode(&c, i, "distance+add");
        n_eadd += is_mode(&c, i, "error+add");
        n_pgm += is_mode(&c, i, "pgm");
        int store = is_mode(&c, i, "store") || is_mode(&c, i, "store+tin");
        n_store += is_mode(&c, i, "store");
        n_tin += is_mode(&c, i, "store+tin");
        EXPECT_GT(csv_num(&c, i, "fps_median"), 0.0);
        EXPECT_GT(csv_num(&c, i, "triangles_median"), 0.0);
        EXPECT_GT(csv_num(&c, i, "gpu_mib"), 0.0);
        double mpx = csv_num(&c, i, "max_screen_error_px");
        double rpx = csv_num(&c, i, "rms_screen_error_px");
        if (!isfinite(mpx) || !isfinite(rpx) ||
            (!store && !isfinite(csv_num(&c, i, "max_vertical_error_m"))))
            ADD_FAILURE("row %d (%s): error not measured: max %s px, rms %s px, max %s m", i,
                        csv_str(&c, i, "family"), csv_str(&c, i, "max_screen_error_px"),
                        csv_str(&c, i, "rms_screen_error_px"),
                        csv_str(&c, i, "max_vertical_error_m"));
        EXPECT_GE(mpx, rpx);
        EXPECT_GE(rpx, 0.0);
        int pgm = is_mode(&c, i, "pgm");
        EXPECT_EQ_STR(pgm ? "pgm" : strstr(csv_str(&c, i, "family"), "+add") ? "add" : "move",
                      pgm ? csv_str(&c, i, "lod_mode") : csv_str(&c, i, "stitch"));
        /* the patch renderer covers every post in view; PGM leaves some out, never all */
        double u = csv_num(&c, i, "uncovered_share");
        if (pgm) {
            EXPECT_GE(u, 0.0);
            EXPECT_LT(u, 1.0);
        } else {
            EXPECT_EQ_DBL(0.0, u);
            EXPECT_EQ_STR("", csv_str(&c, i, "pgm_grid"));
        }
    }
    EXPECT_TRUE(is_mode(&c, 0, "full"));
    EXPECT_EQ_INT(1, n_full);
    EXPECT_EQ_INT(COUNT(grid_mindist_w) * COUNT(grid_maxdist_w) * COUNT(grid_exp), n_dist);
    EXPECT_EQ_INT(COUNT(grid_tau) + (extra_tau > 0), n_err);
    EXPECT_EQ_INT(1, n_dadd);
    EXPECT_EQ_INT(COUNT(grid_tau), n_eadd);
    EXPECT_EQ_INT(COUNT(grid_pgm), n_pgm);
    EXPECT_EQ_INT(COUNT(grid_tau), n_store);
    EXPECT_EQ_INT(COUNT(grid_tau), n_tin);
    check_store_families(&c);
    /* full resolution: no LoD parameters, no error */
    EXPECT_EQ_DBL(0.0, csv_num(&c, 0, "tau_px"));
    EXPECT_EQ_DBL(0.0, csv_num(&c, 0, "maxdist_m"));
    EXPECT_EQ_DBL(0.0, csv_num(&c, 0, "max_screen_error_px"));
    EXPECT_EQ_DBL(0.0, csv_num(&c, 0, "max_vertical_error_m"));

    /* distance rows: every combination of the grid exactly once, in patch widths */
    int seen[2][4][3] = {{{0}}};
    for (int i = 0; i < c.rows; i++) {
        if (!is_mode(&c, i, "distance")) {
            continue;
        }
        double a = csv_num(&c, i, "mindist_m") / w, d = csv_num(&c, i, "maxdist_m") / w;
        double e = csv_num(&c, i, "exp");
        int ia = -1, id = -1, ie = -1;
        for (int k = 0; k < COUNT(grid_mindist_w); k++)
            if (fabs(a - grid_mindist_w[k]) <= 1e-5 * grid_mindist_w[k])
                ia = k;
        for (int k = 0; k < COUNT(grid_maxdist_w); k++)
            if (fabs(d - grid_maxdist_w[k]) <= 1e-5 * grid_maxdist_w[k])
                id = k;
        for (int k = 0; k < COUNT(grid_exp); k++)
            if (e == grid_exp[k])
                ie = k;
        if (ia < 0 || id < 0 || ie < 0) {
            ADD_FAILURE("distance row %d: mindist %s maxdist %s exp %s is not on the grid "
                        "(patch width %g m)",
                        i, csv_str(&c, i, "mindist_m"), csv_str(&c, i, "maxdist_m"),
                        csv_str(&c, i, "exp"), w);
            continue;
        }
        if (seen[ia][id][ie]++)
            ADD_FAILURE("distance row %d: mindist %s maxdist %s exp %s appears twice", i,
                        csv_str(&c, i, "mindist_m"), csv_str(&c, i, "maxdist_m"),
                        csv_str(&c, i, "exp"));
        EXPECT_EQ_DBL(0.0, csv_num(&c, i, "tau_px"));
    }

    /* error rows: the grid's taus (and --tau), each once */
    int tau_seen[7] = {0};
    for (int i = 0; i < c.rows; i++) {
        if (!is_mode(&c, i, "error"))
            continue;
        double t = csv_num(&c, i, "tau_px");
        int k = 0;
        while (k < COUNT(grid_tau) && grid_tau[k] != t)
            k++;
        if (k == COUNT(grid_tau) && !(extra_tau > 0 && t == extra_tau)) {
            ADD_FAILURE("error row %d: tau %s is not on the grid", i, csv_str(&c, i, "tau_px"));
            continue;
        }
        if (tau_seen[k]++)
            ADD_FAILURE("error row %d: tau %s appears twice", i, csv_str(&c, i, "tau_px"));
        EXPECT_EQ_DBL(0.0, csv_num(&c, i, "maxdist_m"));
    }
    /* PGM rows: each grid of the list once */
    int pgm_seen[COUNT(grid_pgm)] = {0};
    for (int i = 0; i < c.rows; i++) {
        if (!is_mode(&c, i, "pgm"))
            continue;
        int k = 0;
        while (k < COUNT(grid_pgm) && strcmp(grid_pgm[k], csv_str(&c, i, "pgm_grid")))
            k++;
        if (k == COUNT(grid_pgm))
            ADD_FAILURE("pgm row %d: grid '%s' is not in the list", i, csv_str(&c, i, "pgm_grid"));
        else if (pgm_seen[k]++)
            ADD_FAILURE("pgm row %d: grid %s appears twice", i, grid_pgm[k]);
    }
    /* --stitch add: each tau of the grid once, and the distance row at the run's (default)
     * parameters; on the same selection as vertex moving's row of the same parameters (the
     * distance mode) it keeps the coarser patches' vertices and adds the finer ones': never
     * fewer triangles; the error mode selects its own levels, so that tau holds on screen */
    int add_seen[COUNT(grid_tau)] = {0};
    for (int i = 0; i < c.rows; i++) {
        int dadd = is_mode(&c, i, "distance+add");
        if (!dadd && !is_mode(&c, i, "error+add"))
            continue;
        if (!dadd) {
            int k = 0;
            while (k < COUNT(grid_tau) && grid_tau[k] != csv_num(&c, i, "tau_px"))
                k++;
            if (k == COUNT(grid_tau) || add_seen[k]++)
                ADD_FAILURE("error+add row %d: tau %s off the grid or twice", i,
                            csv_str(&c, i, "tau_px"));
        }
        int twin = -1;
        for (int k = 0; k < c.rows; k++)
            if (is_mode(&c, k, dadd ? "distance" : "error") &&
                csv_num(&c, k, "tau_px") == csv_num(&c, i, "tau_px") &&
                csv_num(&c, k, "mindist_m") == csv_num(&c, i, "mindist_m") &&
                csv_num(&c, k, "maxdist_m") == csv_num(&c, i, "maxdist_m") &&
                csv_num(&c, k, "exp") == csv_num(&c, i, "exp"))
                twin = k;
        if (twin < 0) {
            ADD_FAILURE("%s row %d: no vertex-moving row with its parameters",
                        csv_str(&c, i, "family"), i);
            continue;
        }
        if (dadd) /* the same levels: adding only adds */
            EXPECT_GE(csv_num(&c, i, "triangles_median"), csv_num(&c, twin, "triangles_median"));
        else /* its own levels (tp_selection_set_stitch_add), bounded on its own geometry */
            EXPECT_LE(csv_num(&c, i, "max_screen_error_px"), csv_num(&c, i, "tau_px"));
    }
    ASSERT_NO_FAILURE();

    /* the JSON: the same configurations in the same order, at full precision */
    char* json = read_file(json_path, NULL);
    ASSERT_TRUE(json != NULL);
    const char *os[64], *oe[64];
    int no = json_objects(json, "configurations", os, oe, 64);
    ASSERT_EQ_INT(c.rows, no);
    double fps[64], px[64];
    int pareto[64], mode_err[64], family[64];
    ASSERT_TRUE(no <= 64);
    for (int i = 0; i < no; i++) {
        char mode[32], fam[32];
        json_str(os[i], oe[i], "lod_mode", mode, sizeof mode);
        json_str(os[i], oe[i], "family", fam, sizeof fam);
        if (strcmp(csv_str(&c, i, "lod_mode"), mode) != 0)
            ADD_FAILURE("configuration %d: %s in the JSON, %s in the CSV", i, mode,
                        csv_str(&c, i, "lod_mode"));
        EXPECT_EQ_STR(csv_str(&c, i, "family"), fam);
        char mesh[16];
        EXPECT_EQ_STR(csv_str(&c, i, "mesh"), json_str(os[i], oe[i], "mesh", mesh, sizeof mesh));
        fps[i] = json_num(os[i], oe[i], "fps_median");
        px[i] = json_num(os[i], oe[i], "max_screen_error_px");
        pareto[i] = json_bool(os[i], oe[i], "pareto");
        mode_err[i] = !strcmp(fam, "error");
        int bounded = mode_err[i] || !strncmp(fam, "store", 5); /* the error mode, px <= tau */
        family[i] = !strcmp(fam, "distance")       ? 1
                    : mode_err[i]                    ? 2
                    : !strcmp(fam, "distance+add") ? 3
                    : !strcmp(fam, "error+add")    ? 4
                    : !strcmp(fam, "pgm")          ? 5
                    : !strcmp(fam, "store")        ? 6
                    : !strcmp(fam, "store+tin")    ? 7
                                                   : 0;
        if (!strcmp(fam, "pgm"))
            EXPECT_NEAR(csv_num(&c, i, "uncovered_share"),
                        json_num(os[i], oe[i], "uncovered_share"), 0.0000051);
        EXPECT_NEAR(fps[i], csv_num(&c, i, "fps_median"), 0.00051);
        EXPECT_NEAR(px[i], csv_num(&c, i, "max_screen_error_px"), 0.000051);
        EXPECT_EQ_INT(pareto[i], (int)csv_num(&c, i, "pareto"));
        /* error mode's promise (core/src/lod.c): no error above tau px anywhere on screen */
        if (bounded)
            EXPECT_LE(px[i], json_num(os[i], oe[i], "tau_px") * (1 + 1e-9));
    }
    /* Pareto flags, recomputed from the JSON's exact values, per family */
    int fronts[8] = {0}, same[8][64] = {{0}};
    for (int i = 0; i < no; i++)
        same[family[i]][i] = 1;
    EXPECT_EQ_INT(0, pareto[0]); /* full resolution: the baseline, on no front */
    for (int i = 1; i < no; i++) {
        int expect = !dominated(fps, px, same[family[i]], no, i);
        if (expect != pareto[i])
            ADD_FAILURE("configuration %d (%s, fps %.6g, max px %.6g): pareto %d, expected %d", i,
                        csv_str(&c, i, "family"), fps[i], px[i], pareto[i], expect);
        fronts[family[i]] += expect;
    }
    for (int f = 1; f < 8; f++) /* every family has a front */
        EXPECT_GE(fronts[f], 1.0);
    /* ... and from the CSV's rounded values: a disagreement only where rounding hides a tie */
    double cfps[64], cpx[64];
    for (int i = 0; i < c.rows; i++) {
        cfps[i] = csv_num(&c, i, "fps_median");
        cpx[i] = csv_num(&c, i, "max_screen_error_px");
    }
    int ambiguous = 0;
    for (int i = 1; i < c.rows; i++) {
        const int* fam = same[family[i]];
        int expect = !dominated(cfps, cpx, fam, c.rows, i);
        if (expect == (int)csv_num(&c, i, "pareto"))
            continue;
        int tie = 0;
        for (int k = 1; k < c.rows; k++)
            tie |= k != i && fam[k] &&
                   (fabs(cfps[k] - cfps[i]) <= 0.001 || fabs(cpx[k] - cpx[i]) <= 0.0001);
        if (!tie)
            ADD_FAILURE("CSV row %d: pareto %s, but its fps %s and max px %s say %d", i,
                        csv_str(&c, i, "pareto"), csv_str(&c, i, "fps_median"),
                        csv_str(&c, i, "max_screen_error_px"), expect);
        ambiguous += tie;
    }
    if (ambiguous)
        tp_test_note("%d CSV rows whose Pareto flag the CSV's rounding leaves open", ambiguous);
    /* the table marks the same configurations */
    int marked = 0, flagged = 0;
    for (const char* p = r->out; (p = strstr(p, "  pareto\n")) != NULL; p++)
        marked++;
    for (int i = 1; i < no; i++)
        flagged += pareto[i];
    EXPECT_EQ_INT(flagged, marked);

    /* error mode: a larger tau never draws more triangles (levels only get coarser) */
    for (int i = 0; i < c.rows; i++)
        for (int k = 0; k < c.rows; k++)
            if (is_mode(&c, i, "error") && is_mode(&c, k, "error") &&
                csv_num(&c, i, "tau_px") < csv_num(&c, k, "tau_px"))
                if (csv_num(&c, i, "triangles_median") < csv_num(&c, k, "triangles_median"))
                    ADD_FAILURE("tau %s: %s triangles, fewer than the %s of tau %s",
                                csv_str(&c, i, "tau_px"), csv_str(&c, i, "triangles_median"),
                                csv_str(&c, k, "triangles_median"), csv_str(&c, k, "tau_px"));

    /* the headline is the error mode at the run's tau */
    char mode[32];
    EXPECT_CONTAINS(json_str(json, NULL, "lod_mode", mode, sizeof mode), "error");
    double tau = json_num(json, NULL, "tau_px");
    EXPECT_EQ_DBL(extra_tau > 0 ? extra_tau : 1.0, tau);
    for (int i = 0; i < no; i++)
        if (mode_err[i] && json_num(os[i], oe[i], "tau_px") == tau)
            EXPECT_EQ_DBL(fps[i], json_num(json, NULL, "fps_median"));
    free(json);
    csv_free(&c);
}

static void args_sweep(args* a, const char* dir)
{
    args_bench_small(a, 1);
    args_add(a, "--sweep");
    args_add(a, "--csv");
    args_add(a, "%s/sweep.csv", dir);
    args_add(a, "--json");
    args_add(a, "%s/sweep.json", dir);
}

/* The sweep in an empty cache: the store families' store is built there first, as `view DEM`
 * builds it (its line and progress on stderr), and left there, one NAME-KEY.tpt. */
TEST(sweep_writes_one_row_per_configuration_and_a_plot)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    const char* cache = make_tmp_dir();
    char csv_path[1024], json_path[1024], png[1024];
    const char* old_cache = getenv("TP_CACHE_DIR");
    char saved[1024] = "";
    if (old_cache)
        snprintf(saved, sizeof saved, "%s", old_cache);
    args_sweep(&a, dir);
    args_add(&a, "%s", dem);
    setenv("TP_CACHE_DIR", cache, 1);
    run(&a, &r);
    if (old_cache)
        setenv("TP_CACHE_DIR", saved, 1);
    else
        unsetenv("TP_CACHE_DIR");
    skip_without_gl(&r);
    if (r.exit_code != 0) {
        print_command(&a);
        FAIL("exit status %d, stderr ends: %s", r.exit_code, err_tail(&r));
    }
    EXPECT_CONTAINS(r.err, "building a store of");
    EXPECT_CONTAINS(r.err, cache);
    char listing[4096];
    dir_listing(cache, listing, sizeof listing);
    if (strncmp(listing, "storml_elev_orig-", 17) || strchr(listing, ',') ||
        strcmp(listing + strlen(listing) - 4, ".tpt"))
        ADD_FAILURE("the cache holds [%s], expected one storml_elev_orig-KEY.tpt", listing);
    snprintf(csv_path, sizeof csv_path, "%s/sweep.csv", dir);
    snprintf(json_path, sizeof json_path, "%s/sweep.json", dir);
    snprintf(png, sizeof png, "%s/sweep.png", dir);
    /* the plot beside the CSV, with .png for its extension; no temporary files */
    EXPECT_DIR_IS(dir, "sweep.csv,sweep.json,sweep.png");
    expect_plot(png);
    EXPECT_CONTAINS(r.err, png);
    check_sweep(dem, csv_path, json_path, &r, 0);
}

/* --pgm-grid replaces the sweep's PGM grids (no --renderer pgm needed: the sweep runs PGM);
 * the other families stay as they are. */
TEST(sweep_pgm_grid_replaces_the_grids)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    char csv_path[1024];
    args_sweep(&a, dir);
    args_add(&a, "--pgm-grid");
    args_add(&a, "40x30,64x64");
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    snprintf(csv_path, sizeof csv_path, "%s/sweep.csv", dir);
    csv c;
    csv_read(csv_path, &c);
    ASSERT_EQ_INT(SWEEP_ROWS - COUNT(grid_pgm) + 2, c.rows);
    const char* want[2] = {"40x30", "64x64"};
    int g = 0;
    for (int i = 0; i < c.rows; i++) {
        if (!is_mode(&c, i, "pgm"))
            continue;
        if (g < 2)
            EXPECT_EQ_STR(want[g], csv_str(&c, i, "pgm_grid"));
        g++;
        EXPECT_TRUE(isfinite(csv_num(&c, i, "max_screen_error_px")));
        EXPECT_GT(csv_num(&c, i, "triangles_median"), 0.0);
    }
    EXPECT_EQ_INT(2, g);
    EXPECT_CONTAINS(r.out, "pgm 40x30");
    EXPECT_CONTAINS(r.out, "uncov %");
    csv_free(&c);
}

TEST(sweep_plot_option_puts_the_plot_there)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    char plots[1024], png[1100];
    snprintf(plots, sizeof plots, "%s/plots", dir);
    ASSERT_EQ_INT(0, mkdir(plots, 0755));
    snprintf(png, sizeof png, "%s/fps_vs_error.png", plots);
    args_sweep(&a, dir);
    args_add(&a, "--plot");
    args_add(&a, "%s", png);
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    EXPECT_DIR_IS(dir, "plots,sweep.csv,sweep.json"); /* no sweep.png beside the CSV */
    EXPECT_DIR_IS(plots, "fps_vs_error.png");         /* and no temporary file beside the plot */
    expect_plot(png);
}

TEST(sweep_tau_off_the_grid_adds_an_error_row)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    char csv_path[1024], json_path[1024];
    args_sweep(&a, dir);
    args_add(&a, "--tau");
    args_add(&a, "3");
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    snprintf(csv_path, sizeof csv_path, "%s/sweep.csv", dir);
    snprintf(json_path, sizeof json_path, "%s/sweep.json", dir);
    EXPECT_DIR_IS(dir, "sweep.csv,sweep.json,sweep.png");
    check_sweep(dem, csv_path, json_path, &r, 3.0); /* a 7th error row, tau 3, the headline */
    EXPECT_CONTAINS(r.out, "error mode (tau = 3 px)");
}

TEST(sweep_tau_on_the_grid_adds_no_row)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    char csv_path[1024], json_path[1024];
    args_sweep(&a, dir);
    args_add(&a, "--tau");
    args_add(&a, "4");
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    snprintf(csv_path, sizeof csv_path, "%s/sweep.csv", dir);
    snprintf(json_path, sizeof json_path, "%s/sweep.json", dir);
    csv c;
    csv_read(csv_path, &c);
    EXPECT_EQ_INT(SWEEP_ROWS, c.rows);
    csv_free(&c);
    char* json = read_file(json_path, NULL);
    ASSERT_TRUE(json != NULL);
    EXPECT_EQ_DBL(4.0, json_num(json, NULL, "tau_px"));
    free(json);
    EXPECT_CONTAINS(r.out, "error mode (tau = 4 px)");
}

/* --no-error leaves every measured error at 0: the sweep must either refuse the combination
 * as a usage error or still plot (fps only); failing after the whole sweep is neither. */
TEST(sweep_without_error_measurement_is_refused_or_plots)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    char png[1024];
    args_sweep(&a, dir);
    args_add(&a, "--no-error");
    args_add(&a, "%s", dem);
    run(&a, &r);
    skip_without_gl(&r);
    tp_test_note("exit %d, stderr ends: %s", r.exit_code, err_tail(&r));
    if (r.exit_code == 2) {
        EXPECT_CONTAINS(r.err, "--no-error");
        EXPECT_DIR_IS(dir, "");
        return;
    }
    EXPECT_EQ_INT(0, r.exit_code);
    snprintf(png, sizeof png, "%s/sweep.png", dir);
    expect_plot(png);
}

/* A flat DEM: every configuration draws the terrain exactly (0 px everywhere), a legitimate
 * result that the plot must survive. */
TEST(sweep_of_a_flat_dem_still_plots)
{
    static run_result r;
    args a;
    const char* dir = make_tmp_dir();
    char dem[1024], png[1024];
    snprintf(dem, sizeof dem, "%s/flat.asc", log_dir());
    FILE* f = fopen(dem, "w");
    ASSERT_TRUE(f != NULL);
    fprintf(f, "ncols 65\nnrows 65\nxllcorner 500000\nyllcorner 5000000\ncellsize 30\n"
               "NODATA_value -9999\n");
    for (int y = 0; y < 65; y++)
        for (int x = 0; x < 65; x++)
            fprintf(f, "100%c", x == 64 ? '\n' : ' ');
    ASSERT_EQ_INT(0, fclose(f));
    args_sweep(&a, dir);
    args_add(&a, "%s", dem);
    run(&a, &r);
    remove(dem);
    skip_without_gl(&r);
    if (r.exit_code != 0)
        print_command(&a);
    tp_test_note("exit %d, stderr ends: %s", r.exit_code, err_tail(&r));
    EXPECT_EQ_INT(0, r.exit_code);
    snprintf(png, sizeof png, "%s/sweep.png", dir);
    expect_plot(png);
    EXPECT_DIR_IS(dir, "sweep.csv,sweep.json,sweep.png");
}

/* The plot's default name is the CSV's with .png: a CSV named *.png, or --plot naming the
 * JSON, must not end up replaced by the plot (refused as a usage error, or both kept). */
TEST(sweep_plot_never_replaces_the_csv_or_json)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    char path[1024];
    /* --csv results.png: the default plot name is the CSV's own */
    args_bench_small(&a, 1);
    args_add(&a, "--sweep");
    args_add(&a, "--csv");
    args_add(&a, "%s/results.png", dir);
    args_add(&a, "%s", dem);
    run(&a, &r);
    skip_without_gl(&r);
    tp_test_note("--csv results.png: exit %d", r.exit_code);
    snprintf(path, sizeof path, "%s/results.png", dir);
    if (r.exit_code == 2) {
        EXPECT_DIR_IS(dir, "");
    } else {
        char* text = read_file(path, NULL);
        EXPECT_TRUE(text && !strncmp(text, "lod_mode,", 9)); /* still the CSV */
        free(text);
    }
    /* --plot onto the --json file */
    const char* dir2 = make_tmp_dir();
    args_sweep(&a, dir2);
    args_add(&a, "--plot");
    args_add(&a, "%s/sweep.json", dir2);
    args_add(&a, "%s", dem);
    run(&a, &r);
    tp_test_note("--plot onto --json: exit %d", r.exit_code);
    snprintf(path, sizeof path, "%s/sweep.json", dir2);
    if (r.exit_code == 2) {
        EXPECT_DIR_IS(dir2, "");
    } else {
        char* text = read_file(path, NULL);
        EXPECT_TRUE(text && text[0] == '{'); /* still the JSON */
        free(text);
    }
}

/* ---------------------------------------------------------------------------------------------
 * --static --max-error
 */
typedef struct static_row {
    double bound, max, rms;
    int below;
    double triangles, points;
    /* TIN rows */
    double time_s, uncovered, peak_mib;
    int holds;
} static_row;

/* The rows of the JSON's "static" array whose "mesher" is mesher ("patches", "terrapatch tin",
 * ...); returns their number. */
static int static_rows_of(const char* json, const char* mesher, static_row* rows, int cap)
{
    const char *os[96], *oe[96];
    int all = json_objects(json, "static", os, oe, 96), n = 0;
    for (int k = 0; k < all && n < cap; k++) {
        char name[64];
        if (strcmp(json_str(os[k], oe[k], "mesher", name, sizeof name), mesher) != 0)
            continue;
        int i = n++;
        static_row* r = &rows[i];
        memset(r, 0, sizeof *r);
        r->bound = json_num(os[k], oe[k], "max_error_m");
        r->below = json_bool(os[k], oe[k], "below_quantisation");
        if (strcmp(mesher, "patches") != 0) { /* a TIN */
            EXPECT_FALSE(r->below);
            r->triangles = json_num(os[k], oe[k], "triangles");
            r->points = json_num(os[k], oe[k], "points");
            r->max = json_num(os[k], oe[k], "measured_max_error_m");
            r->rms = json_num(os[k], oe[k], "measured_rms_error_m");
            r->time_s = json_num(os[k], oe[k], "time_s");
            r->uncovered = json_num(os[k], oe[k], "uncovered_samples");
            /* null where /proc/self/clear_refs cannot be written (then the table says n/a) */
            const char* peak = json_value(os[k], oe[k], "peak_mib");
            EXPECT_TRUE(peak != NULL);
            r->peak_mib = peak && strncmp(peak, "null", 4) ? json_num(os[k], oe[k], "peak_mib")
                                                           : -1;
            r->holds = json_bool(os[k], oe[k], "bound_holds");
            EXPECT_EQ_DBL(r->bound, json_num(os[k], oe[k], "threshold_m"));
            EXPECT_GT(r->time_s, 0.0);
            continue;
        }
        if (r->below) {
            /* nothing measured for a refused bound */
            EXPECT_TRUE(json_value(os[k], oe[k], "triangles") == NULL);
            continue;
        }
        r->triangles = json_num(os[k], oe[k], "triangles");
        r->points = json_num(os[k], oe[k], "points");
        r->max = json_num(os[k], oe[k], "measured_max_error_m");
        r->rms = json_num(os[k], oe[k], "measured_rms_error_m");
        EXPECT_GE(json_num(os[k], oe[k], "select_s"), 0.0);
        EXPECT_GE(json_num(os[k], oe[k], "mesh_s"), 0.0);
    }
    return n;
}

/* The patch rows (`export --max-error`'s mesh). */
static int static_rows(const char* json, static_row* rows, int cap)
{
    return static_rows_of(json, "patches", rows, cap);
}

/* bench --static with one timed run per TIN (the TIN rows' own test times two). */
static void args_static(args* a, const char* bounds, const char* dir)
{
    args_cmd(a, "bench");
    args_add(a, "--static");
    args_add(a, "--runs");
    args_add(a, "1");
    args_add(a, "--max-error");
    args_add(a, "%s", bounds);
    if (dir) {
        args_add(a, "--json");
        args_add(a, "%s/static.json", dir);
        args_add(a, "--csv");
        args_add(a, "%s/static.csv", dir);
    }
}

TEST(static_bounds_hold_and_meshes_shrink)
{
    static run_result r;
    args a;
    const char* dem = sample_path(MT_HOOD);
    const char* dir = make_tmp_dir();
    char path[1024];
    args_static(&a, "1,5,20", dir);
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    EXPECT_DIR_IS(dir, "static.csv,static.json");
    snprintf(path, sizeof path, "%s/static.json", dir);
    char* json = read_file(path, NULL);
    ASSERT_TRUE(json != NULL);
    EXPECT_EQ_DBL(0.0, json_num(json, NULL, "quantisation_error_m")); /* integer heights */
    EXPECT_EQ_DBL(17.0, json_num(json, NULL, "patch_size"));
    double full = json_num(json, NULL, "full_triangles");
    static_row rows[16];
    int n = static_rows(json, rows, 16);
    ASSERT_EQ_INT(3, n);
    static const double bounds[] = {1, 5, 20};
    for (int i = 0; i < n; i++) {
        tp_test_note("bound %g m: %.0f triangles (full %.0f), %.0f points, max %.6g m, rms %.6g m",
                     rows[i].bound, rows[i].triangles, full, rows[i].points, rows[i].max,
                     rows[i].rms);
        EXPECT_EQ_DBL(bounds[i], rows[i].bound);
        EXPECT_FALSE(rows[i].below);
        EXPECT_LE(rows[i].max, rows[i].bound + 1e-9);
        EXPECT_LE(rows[i].rms, rows[i].max);
        EXPECT_GT(rows[i].triangles, 0.0);
        EXPECT_GT(rows[i].points, 0.0);
        if (i > 0) {
            EXPECT_LE(rows[i].triangles, rows[i - 1].triangles);
            EXPECT_LE(rows[i].points, rows[i - 1].points);
            EXPECT_GE(rows[i].rms, rows[i - 1].rms);
        }
    }
    /* at 20 m, far fewer triangles than the full mesh (at 1 m the max-error mesh may hold a
     * few more: patches along the voids draw 3-sample triangles that the full mesh leaves
     * out) */
    EXPECT_LT(rows[2].triangles, 0.5 * full);
    EXPECT_GT(rows[2].rms, 0.0);
    /* the CSV: one row per bound, the JSON's values */
    snprintf(path, sizeof path, "%s/static.csv", dir);
    csv c;
    csv_read(path, &c);
    EXPECT_FALSE(c.ragged);
    ASSERT_EQ_INT(6, c.rows); /* the patch rows, then the TIN rows */
    for (int i = 0; i < 3; i++) {
        EXPECT_EQ_STR("patches", csv_str(&c, i, "mesher"));
        EXPECT_EQ_DBL(rows[i].bound, csv_num(&c, i, "max_error_m"));
        EXPECT_EQ_DBL(rows[i].triangles, csv_num(&c, i, "triangles"));
        EXPECT_EQ_DBL(full, csv_num(&c, i, "full_triangles"));
        EXPECT_EQ_DBL(rows[i].points, csv_num(&c, i, "points"));
        EXPECT_NEAR(rows[i].max, csv_num(&c, i, "measured_max_error_m"), 0.000051);
        EXPECT_NEAR(rows[i].rms, csv_num(&c, i, "measured_rms_error_m"), 0.000051);
    }
    csv_free(&c);
    free(json);
    /* the table: a line per bound and the full mesh's size */
    char full_text[64];
    snprintf(full_text, sizeof full_text, "full mesh %.0f triangles", full);
    EXPECT_CONTAINS(r.out, full_text);
}

/* The TIN rows (tp_tin_build on the whole render grid, void outlines cut): the true error that
 * tp_tin_measure finds is within each bound, and the TIN needs fewer triangles than the patch
 * mesh of the same bound; JSON, CSV and table agree. */
TEST(static_tin_rows_hold_the_bound_with_fewer_triangles_than_patches)
{
    static run_result r;
    args a;
    const char* dem = sample_path(MT_HOOD);
    const char* dir = make_tmp_dir();
    char path[1024], buf[64];
    args_cmd(&a, "bench");
    args_add(&a, "--static");
    args_add(&a, "--max-error");
    args_add(&a, "1,5,20");
    args_add(&a, "--runs");
    args_add(&a, "2");
    args_add(&a, "--json");
    args_add(&a, "%s/static.json", dir);
    args_add(&a, "--csv");
    args_add(&a, "%s/static.csv", dir);
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    snprintf(path, sizeof path, "%s/static.json", dir);
    char* json = read_file(path, NULL);
    ASSERT_TRUE(json != NULL);
    static_row patch[4], tin[4];
    ASSERT_EQ_INT(3, static_rows(json, patch, 4));
    ASSERT_EQ_INT(3, static_rows_of(json, "terrapatch tin", tin, 4));
    EXPECT_EQ_INT(0, static_rows_of(json, "delatin 0.2.0", tin + 3, 1)); /* no --compare */
    /* the grid: the whole render grid (Mt Hood has voids: cut) */
    const char* grid = json_value(json, NULL, "tin_grid");
    ASSERT_TRUE(grid != NULL);
    EXPECT_EQ_STR("render", json_str(grid, NULL, "grid", buf, sizeof buf));
    EXPECT_EQ_DBL(json_num(json, NULL, "render_width"), json_num(grid, NULL, "width"));
    EXPECT_EQ_DBL(json_num(json, NULL, "render_height"), json_num(grid, NULL, "height"));
    EXPECT_EQ_DBL(1013.0, json_num(grid, NULL, "width"));
    EXPECT_GT(json_num(grid, NULL, "void_samples"), 0.0);
    EXPECT_TRUE(json_bool(grid, NULL, "cut_voids"));
    EXPECT_EQ_DBL(2.0, json_num(json, NULL, "runs"));
    EXPECT_TRUE(json_value(json, NULL, "peak_memory") != NULL);
    for (int i = 0; i < 3; i++) {
        tp_test_note("bound %g m: tin %.0f triangles (patches %.0f), true max %.6f m, %.0f "
                     "uncovered, %.3f s, peak %.1f MiB",
                     tin[i].bound, tin[i].triangles, patch[i].triangles, tin[i].max,
                     tin[i].uncovered, tin[i].time_s, tin[i].peak_mib);
        EXPECT_EQ_DBL(patch[i].bound, tin[i].bound);
        EXPECT_LE(tin[i].max, tin[i].bound + 1e-6);
        EXPECT_GT(tin[i].max, 0.5 * tin[i].bound); /* a real relief uses its budget */
        EXPECT_TRUE(tin[i].holds);
        EXPECT_LT(tin[i].triangles, patch[i].triangles);
        EXPECT_GT(tin[i].points, 2.0);
        EXPECT_LE(tin[i].rms, tin[i].max);
        /* cut at the voids, the TIN leaves out only the valid samples in no valid cell (as
         * the full mesh does): a few hundred here, far under 1 % of the grid */
        EXPECT_LT(tin[i].uncovered, 0.01 * 1013 * 799);
        if (i > 0)
            EXPECT_LT(tin[i].triangles, tin[i - 1].triangles);
    }
    if (tin[0].peak_mib >= 0) /* measured: a million-triangle build takes memory */
        EXPECT_GT(tin[0].peak_mib, 1.0);
    free(json);
    /* the CSV's TIN rows are the JSON's */
    snprintf(path, sizeof path, "%s/static.csv", dir);
    csv c;
    csv_read(path, &c);
    EXPECT_FALSE(c.ragged);
    ASSERT_EQ_INT(6, c.rows);
    for (int i = 0; i < 3; i++) {
        EXPECT_EQ_STR("terrapatch tin", csv_str(&c, 3 + i, "mesher"));
        EXPECT_EQ_STR("render", csv_str(&c, 3 + i, "grid"));
        EXPECT_EQ_DBL(tin[i].bound, csv_num(&c, 3 + i, "max_error_m"));
        EXPECT_EQ_DBL(tin[i].triangles, csv_num(&c, 3 + i, "triangles"));
        EXPECT_EQ_DBL(tin[i].points, csv_num(&c, 3 + i, "points"));
        EXPECT_NEAR(tin[i].max, csv_num(&c, 3 + i, "measured_max_error_m"), 0.0000051);
        EXPECT_EQ_DBL(tin[i].uncovered, csv_num(&c, 3 + i, "uncovered_samples"));
        EXPECT_EQ_DBL(1.0, csv_num(&c, 3 + i, "bound_holds"));
        EXPECT_EQ_DBL(2.0, csv_num(&c, 3 + i, "runs"));
    }
    csv_free(&c);
    EXPECT_CONTAINS(r.out, "error-bounded TINs on the whole 1013x799 render grid");
    EXPECT_CONTAINS(r.out, "terrapatch tin");
    EXPECT_CONTAINS(r.out, "median of 2 runs");
    EXPECT_TRUE(strstr(r.out, "bound broken") == NULL);
}

/* --compare needs node (and npm and the network once, to install delatin and martini): where
 * one is missing the run stops with exit 1 and a message naming it, before any row, and
 * writes nothing. (The comparison itself needs the network: it is run by hand, see
 * docs/PERFORMANCE.md.) */
TEST(static_compare_without_node_or_npm_exits_1_naming_it)
{
    static run_result r;
    args a;
    const char* dem = sample_path(MT_HOOD);
    const char* dir = make_tmp_dir();
    char bin[1024], cache[1024], link_path[1200];
    snprintf(bin, sizeof bin, "%s/bin", dir);
    snprintf(cache, sizeof cache, "%s/cache", dir);
    ASSERT_EQ_INT(0, mkdir(bin, 0755));
    ASSERT_EQ_INT(0, mkdir(cache, 0755));
    const char* old_path = getenv("PATH");
    const char* old_cache = getenv("XDG_CACHE_HOME");
    char saved_path[4096], saved_cache[4096];
    snprintf(saved_path, sizeof saved_path, "%s", old_path ? old_path : "/usr/bin:/bin");
    snprintf(saved_cache, sizeof saved_cache, "%s", old_cache ? old_cache : "");
    setenv("XDG_CACHE_HOME", cache, 1); /* nothing installed there */
    unsetenv("TP_NPM_DIR");
    args_cmd(&a, "bench");
    args_add(&a, "--static");
    args_add(&a, "--compare");
    args_add(&a, "--max-error");
    args_add(&a, "5");
    args_add(&a, "--json");
    args_add(&a, "%s/out.json", dir);
    args_add(&a, "%s", dem);
    /* 1. no node on PATH (an empty folder) */
    setenv("PATH", bin, 1);
    run(&a, &r);
    setenv("PATH", saved_path, 1);
    EXPECT_EQ_INT(1, r.exit_code);
    EXPECT_CONTAINS(r.err, "node not found on PATH");
    EXPECT_CONTAINS(r.err, "no comparison without delatin and martini");
    EXPECT_TRUE(r.out[0] == '\0'); /* no table, no row */
    EXPECT_DIR_IS(dir, "bin,cache");
    /* 2. node but no npm, and nothing installed yet */
    const char* node = NULL;
    static const char* nodes[] = {"/usr/bin/node", "/usr/local/bin/node", "/bin/node"};
    for (size_t i = 0; i < sizeof nodes / sizeof *nodes && !node; i++)
        if (access(nodes[i], X_OK) == 0)
            node = nodes[i];
    if (node) {
        snprintf(link_path, sizeof link_path, "%s/node", bin);
        ASSERT_EQ_INT(0, symlink(node, link_path));
        setenv("PATH", bin, 1);
        run(&a, &r);
        setenv("PATH", saved_path, 1);
        EXPECT_EQ_INT(1, r.exit_code);
        EXPECT_CONTAINS(r.err, "npm not found on PATH");
        EXPECT_TRUE(r.out[0] == '\0');
        EXPECT_FALSE(access(link_path, F_OK) != 0); /* still there; nothing else written */
        remove(link_path);
    } else {
        tp_test_note("no node binary here: the npm case is not run");
    }
    if (old_cache)
        setenv("XDG_CACHE_HOME", saved_cache, 1);
    else
        unsetenv("XDG_CACHE_HOME");
    EXPECT_DIR_IS(dir, "bin,cache");
}

/* The static mesh of a bound is the mesh `export --max-error` writes for it (read back with
 * VTK); the full mesh count is every cell of four valid samples (counted from the DEM). */
TEST(static_mesh_is_the_export_max_error_mesh)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    static run_result r;
    args a;
    const char* dem = sample_path(MT_HOOD);
    const char* dir = make_tmp_dir();
    char path[1024];
    args_static(&a, "20", dir);
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    snprintf(path, sizeof path, "%s/static.json", dir);
    char* json = read_file(path, NULL);
    ASSERT_TRUE(json != NULL);
    static_row rows[1], tin[1];
    ASSERT_EQ_INT(1, static_rows(json, rows, 1));
    ASSERT_EQ_INT(1, static_rows_of(json, "terrapatch tin", tin, 1));
    free(json);
    /* the patches row is `export --max-error 20 --mesh patches`, the TIN row the default TIN */
    for (int k = 0; k < 2; k++) {
        args_cmd(&a, "export");
        args_add(&a, "--max-error");
        args_add(&a, "20");
        if (k == 0) {
            args_add(&a, "--mesh");
            args_add(&a, "patches");
        }
        args_add(&a, "%s", dem);
        args_add(&a, "-o");
        args_add(&a, "%s/m20_%d.vtp", dir, k);
        run_ok(&a, &r);
        snprintf(path, sizeof path, "%s/m20_%d.vtp", dir, k);
        tp_mesh_summary s;
        tp_error e;
        ASSERT_OK(tp_mesh_inspect(path, &s, &e));
        const static_row* row = k == 0 ? &rows[0] : &tin[0];
        EXPECT_EQ_DBL((double)s.triangles, row->triangles);
        EXPECT_EQ_DBL((double)s.points, row->points);
        EXPECT_LE(s.max_error_m, 20.0 + TIN_ROUNDING_M);
    }
#endif
}

TEST(static_full_triangles_count_every_valid_cell_and_16_bounds_are_taken)
{
#ifdef TP_TEST_NO_IO
    SKIP("built without tp_io");
#else
    static run_result r;
    args a;
    const char* dem = sample_path(STORML); /* nodata only along the edges: nothing filled */
    const char* dir = make_tmp_dir();
    char path[1024];
    args_static(&a, "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16", dir);
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    snprintf(path, sizeof path, "%s/static.json", dir);
    char* json = read_file(path, NULL);
    ASSERT_TRUE(json != NULL);
    double full = json_num(json, NULL, "full_triangles");
    static_row rows[16];
    int n = static_rows(json, rows, 16);
    free(json);
    EXPECT_EQ_INT(16, n);
    for (int i = 0; i < n; i++) {
        EXPECT_EQ_DBL(i + 1.0, rows[i].bound);
        EXPECT_LE(rows[i].max, rows[i].bound + 1e-9);
        if (i > 0)
            EXPECT_LE(rows[i].triangles, rows[i - 1].triangles);
    }
    tp_dem* d;
    tp_error e;
    ASSERT_OK(tp_dem_read(dem, &d, &e));
    size_t cells = 0;
    const float* h = d->heights;
    for (int y = 0; y + 1 < d->height; y++)
        for (int x = 0; x + 1 < d->width; x++)
            cells += !isnan(h[y * d->width + x]) && !isnan(h[y * d->width + x + 1]) &&
                     !isnan(h[(y + 1) * d->width + x]) && !isnan(h[(y + 1) * d->width + x + 1]);
    tp_dem_destroy(d);
    EXPECT_EQ_DBL(2.0 * (double)cells, full);
#endif
}

TEST(static_bound_below_quantisation_is_reported_not_measured)
{
    static run_result r;
    args a;
    const char* dem = shared_path(CRATER);
    const char* dir = make_tmp_dir();
    char path[1024];
    /* the quantisation error from `info`: half the height step */
    args_cmd(&a, "info");
    args_add(&a, "--json");
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    double quant = json_num(r.out, NULL, "quant_max_error_m");
    tp_test_note("quantisation error %.9g m", quant);
    ASSERT_GT(quant, 0.001);
    ASSERT_LT(quant, 1.0);
    char bounds[128];
    snprintf(bounds, sizeof bounds, "0.001,%.17g,1", quant);
    args_static(&a, bounds, dir);
    args_add(&a, "%s", dem);
    run_ok(&a, &r); /* a refused bound is reported, the run goes on */
    EXPECT_CONTAINS(r.out, "below the quantisation error");
    snprintf(path, sizeof path, "%s/static.json", dir);
    char* json = read_file(path, NULL);
    ASSERT_TRUE(json != NULL);
    EXPECT_EQ_DBL(quant, json_num(json, NULL, "quantisation_error_m"));
    static_row rows[3], tins[3];
    ASSERT_EQ_INT(3, static_rows(json, rows, 3));
    /* the TIN is refused the same bound (as by export): rows for the other two only */
    ASSERT_EQ_INT(2, static_rows_of(json, "terrapatch tin", tins, 3));
    free(json);
    EXPECT_NEAR(quant, tins[0].bound, 1e-6 * quant);
    EXPECT_EQ_DBL(1.0, tins[1].bound);
    for (int i = 0; i < 2; i++)
        EXPECT_LE(tins[i].max, tins[i].bound + 1e-6);
    EXPECT_TRUE(rows[0].below);
    EXPECT_FALSE(rows[1].below); /* the bound equal to the quantisation error is taken */
    EXPECT_FALSE(rows[2].below);
    for (int i = 1; i < 3; i++) {
        EXPECT_LE(rows[i].max, rows[i].bound + 1e-9);
        EXPECT_GT(rows[i].triangles, 0.0);
    }
    /* the CSV has one row per bound; the refused one says so and has nothing measured */
    snprintf(path, sizeof path, "%s/static.csv", dir);
    csv c;
    csv_read(path, &c);
    EXPECT_EQ_INT(5, c.rows); /* and then the two TIN rows */
    if (c.rows == 5) {
        EXPECT_EQ_STR("terrapatch tin", csv_str(&c, 3, "mesher"));
        EXPECT_EQ_STR("terrapatch tin", csv_str(&c, 4, "mesher"));
        EXPECT_EQ_DBL(0.001, csv_num(&c, 0, "max_error_m"));
        EXPECT_EQ_DBL(1.0, csv_num(&c, 0, "below_quantisation"));
        EXPECT_EQ_INT(0, (int)strlen(csv_str(&c, 0, "triangles")));
        EXPECT_EQ_INT(0, (int)strlen(csv_str(&c, 0, "measured_max_error_m")));
        EXPECT_NEAR(quant, csv_num(&c, 1, "max_error_m"), 1e-6 * quant);
        EXPECT_EQ_DBL(0.0, csv_num(&c, 1, "below_quantisation"));
        EXPECT_EQ_DBL(1.0, csv_num(&c, 2, "max_error_m"));
        EXPECT_EQ_DBL(rows[1].triangles, csv_num(&c, 1, "triangles"));
    }
    csv_free(&c);
    /* every bound below it: refused as export --max-error refuses it, nothing written */
    const char* dir2 = make_tmp_dir();
    args_static(&a, "0.001,0.002", dir2);
    args_add(&a, "%s", dem);
    run(&a, &r);
    EXPECT_EQ_INT(2, r.exit_code);
    EXPECT_CONTAINS(r.err, "below the quantisation error");
    EXPECT_DIR_IS(dir2, "");
}

/* ---------------------------------------------------------------------------------------------
 * --speed: lead-in frames
 */
typedef struct speed_run {
    run_result r;
    char* json;
    csv frames;
} speed_run;

static void run_speed(const char* dem, const char* speed, const char* camera, speed_run* s)
{
    args a;
    const char* dir = make_tmp_dir();
    char path[1024];
    args_bench_small(&a, 2);
    if (speed) {
        args_add(&a, "--speed");
        args_add(&a, "%s", speed);
    }
    if (camera) {
        args_add(&a, "--camera");
        args_add(&a, "%s", camera);
    }
    args_add(&a, "--json");
    args_add(&a, "%s/b.json", dir);
    args_add(&a, "--csv");
    args_add(&a, "%s/b.csv", dir);
    args_add(&a, "%s", dem);
    run_ok(&a, &s->r);
    EXPECT_DIR_IS(dir, "b.csv,b.json");
    snprintf(path, sizeof path, "%s/b.json", dir);
    s->json = read_file(path, NULL);
    ASSERT_TRUE(s->json != NULL);
    snprintf(path, sizeof path, "%s/b.csv", dir);
    csv_read(path, &s->frames);
}

TEST(speed_lead_in_changes_uploads_not_what_is_drawn)
{
    static speed_run cold, flight;
    const char* dem = sample_path(STORML);
    run_speed(dem, "0", NULL, &cold);
    run_speed(dem, NULL, NULL, &flight); /* the default: 100 m/s */
    EXPECT_EQ_DBL(0.0, json_num(cold.json, NULL, "speed_mps"));
    EXPECT_EQ_DBL(100.0, json_num(flight.json, NULL, "speed_mps"));
    EXPECT_TRUE(strstr(cold.r.out, "(lead-in frames)") == NULL);
    EXPECT_CONTAINS(flight.r.out, "low path (lead-in frames)");
    const csv *c = &cold.frames, *f = &flight.frames;
    ASSERT_EQ_INT(6, c->rows); /* full, distance, error x 2 frames */
    ASSERT_EQ_INT(c->rows, f->rows);
    for (int i = 0; i < c->rows; i++) {
        EXPECT_TRUE(strcmp(csv_str(f, i, "lod_mode"), csv_str(c, i, "lod_mode")) == 0);
        EXPECT_EQ_DBL(csv_num(c, i, "frame"), csv_num(f, i, "frame"));
        /* the timed frame's camera and selection are the same: same geometry, same error */
        EXPECT_EQ_DBL(csv_num(c, i, "triangles"), csv_num(f, i, "triangles"));
        EXPECT_EQ_DBL(csv_num(c, i, "max_screen_error_px"), csv_num(f, i, "max_screen_error_px"));
        EXPECT_EQ_DBL(csv_num(c, i, "max_vertical_error_m"), csv_num(f, i, "max_vertical_error_m"));
        if (csv_num(c, i, "frame") == 0) {
            /* each configuration starts cold: without a lead-in its first frame uploads, with
             * one the lead-in 1/30 s earlier has already uploaded (nearly) everything */
            double up_cold = csv_num(c, i, "uploads"), up_flight = csv_num(f, i, "uploads");
            tp_test_note("%s frame 0: %.0f uploads cold, %.0f after a lead-in",
                         csv_str(c, i, "lod_mode"), up_cold, up_flight);
            EXPECT_GT(up_cold, 0.0);
            EXPECT_LT(up_flight, up_cold);
        }
    }
    free(cold.json);
    free(flight.json);
    csv_free(&cold.frames);
    csv_free(&flight.frames);
}

TEST(speed_fixed_camera_has_no_lead_in)
{
    static speed_run s;
    const char* dem = sample_path(STORML);
    run_speed(dem, "50", "324500,5101500,2900,30,-25", &s);
    /* one camera, no path to fly along: no lead-in frames whatever --speed says */
    EXPECT_EQ_DBL(0.0, json_num(s.json, NULL, "speed_mps"));
    EXPECT_TRUE(strstr(s.r.out, "(lead-in frames)") == NULL);
    EXPECT_CONTAINS(s.r.out, "fixed path");
    free(s.json);
    csv_free(&s.frames);
}

/* ---------------------------------------------------------------------------------------------
 * Bad command lines: exit 2, one line naming the option, nothing written
 */
/* bench with outputs into dir (which must stay empty) and the DEM last */
static void args_outputs(args* a, const char* dir)
{
    args_add(a, "--json");
    args_add(a, "%s/x.json", dir);
    args_add(a, "--csv");
    args_add(a, "%s/x.csv", dir);
}

/* On a log (stderr not a terminal) the progress is a line at each tenth of the frames, not one
 * line of every frame's update joined by '\r' (issue 29, 4.8). */
TEST(progress_on_a_log_is_a_line_per_tenth)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    args_bench_small(&a, 40);
    args_add(&a, "%s", dem);
    run(&a, &r);
    skip_without_gl(&r);
    ASSERT_EQ_INT(0, r.exit_code);
    EXPECT_TRUE(strchr(r.err, '\r') == NULL);
    /* every configuration (the bench measures each LoD mode): frames 4, 8, ..., 40 */
    int lines = 0;
    for (const char* p = r.err; (p = strstr(p, ": frame ")); ++p) {
        ++lines;
        EXPECT_EQ_INT(0, atoi(p + strlen(": frame ")) % 4);
    }
    EXPECT_GT(lines, 0);
    EXPECT_EQ_INT(0, lines % 10);
    EXPECT_CONTAINS(r.err, "frame 40/40");
}

TEST(sweep_without_csv_exits_2)
{
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    args_bench_small(&a, 1);
    args_add(&a, "--sweep");
    args_add(&a, "--json");
    args_add(&a, "%s/x.json", dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--csv", dir);
}

/* --fit shapes a DEM drawn whole; the sweep's store families draw the DEM's store, which --fit
 * does not shape: refused before anything runs or is built. */
TEST(sweep_with_fit_exits_2)
{
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    args_bench_small(&a, 1);
    args_add(&a, "--sweep");
    args_add(&a, "--csv");
    args_add(&a, "%s/x.csv", dir);
    args_add(&a, "--fit");
    args_add(&a, "pad");
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--fit", dir);
}

/* --stitch add (Brodersen's vertex-adding crack fix) against the default vertex moving, frame by
 * frame over the same path on Mt Hood: the same selection, so full resolution draws the same
 * triangles exactly (nothing to add or move) with no error in either; the LoD modes draw at
 * least as many (the coarser patches keep their own vertices and take the finer ones'), more
 * on some frame (a view where nothing is added would prove nothing); the vertical and screen
 * errors are measured for add on its own geometry (0 at full resolution, as moving's). */
TEST(stitch_add_against_move_frame_by_frame)
{
    const char* dem = sample_path(MT_HOOD);
    const char* dir = make_tmp_dir();
    const char* mode[2] = {"move", "add"};
    csv c[2];
    run_result r;
    args a;
    for (int m = 0; m < 2; m++) {
        args_bench_small(&a, 4);
        args_add(&a, "--stitch");
        args_add(&a, "%s", mode[m]);
        args_add(&a, "--csv");
        args_add(&a, "%s/%s.csv", dir, mode[m]);
        args_add(&a, "%s", dem);
        run_ok(&a, &r);
        char path[1024];
        snprintf(path, sizeof path, "%s/%s.csv", dir, mode[m]);
        csv_read(path, &c[m]);
    }
    ASSERT_EQ_INT(c[0].rows, c[1].rows);
    ASSERT_EQ_INT(12, c[1].rows); /* 3 configurations x 4 frames */
    int more = 0;
    for (int i = 0; i < c[1].rows; i++) {
        const char* lod = csv_str(&c[0], i, "lod_mode");
        double tm = csv_num(&c[0], i, "triangles"), ta = csv_num(&c[1], i, "triangles");
        double em = csv_num(&c[0], i, "max_vertical_error_m");
        double ea = csv_num(&c[1], i, "max_vertical_error_m");
        tp_test_note("%s frame %g: %g triangles moving, %g adding; max error %g m, %g m", lod,
                     csv_num(&c[0], i, "frame"), tm, ta, em, ea);
        EXPECT_EQ_STR(lod, csv_str(&c[1], i, "lod_mode"));
        EXPECT_EQ_DBL(csv_num(&c[0], i, "patches"), csv_num(&c[1], i, "patches"));
        double pa = csv_num(&c[1], i, "max_screen_error_px");
        EXPECT_TRUE(isfinite(pa) && pa >= csv_num(&c[1], i, "rms_screen_error_px"));
        EXPECT_TRUE(ea >= 0);
        if (ea == 0) /* the drawn surface on every sample: nothing to see on screen */
            EXPECT_EQ_DBL(0, pa);
        if (!strcmp(lod, "full")) {
            EXPECT_EQ_DBL(tm, ta);
            EXPECT_EQ_DBL(0, em);
            EXPECT_EQ_DBL(0, ea);
            EXPECT_EQ_DBL(0, pa);
        } else {
            EXPECT_GE(ta, tm);
            more += ta > tm;
        }
        /* the error mode bounds the added vertices' triangles too (tp_patch_error_bound_add):
           tau (1 px by default) holds on screen, as it does for vertex moving */
        if (!strcmp(lod, "error")) {
            EXPECT_LE(pa, 1.0);
            EXPECT_LE(csv_num(&c[0], i, "max_screen_error_px"), 1.0);
        }
    }
    EXPECT_GT(more, 0);
    csv_free(&c[0]);
    csv_free(&c[1]);
}

/* --stitch-add-draw both: every LoD configuration with --stitch add drawn as sets, then as five
 * regions, on the same frames (full resolution once: nothing is added there); frame by frame
 * the two draw the same triangles of the same patches with the same measured errors (the same
 * geometry), five in at least as many draws; bad values and both with --sweep exit 2. */
TEST(stitch_add_draw_sets_and_five_measure_alike)
{
    const char* dem = sample_path(MT_HOOD);
    const char* dir = make_tmp_dir();
    static const char* const cols[] = {"triangles", "patches", "max_vertical_error_m",
                                       "rms_vertical_error_m", "max_screen_error_px",
                                       "rms_screen_error_px"};
    csv c;
    run_result r;
    args a;
    char path[1024];
    args_bench_small(&a, 3);
    args_add(&a, "--stitch");
    args_add(&a, "add");
    args_add(&a, "--stitch-add-draw");
    args_add(&a, "both");
    args_add(&a, "--csv");
    args_add(&a, "%s/both.csv", dir);
    args_add(&a, "--json");
    args_add(&a, "%s/both.json", dir);
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    EXPECT_CONTAINS(r.out, "error+add tau=1 sets");
    EXPECT_CONTAINS(r.out, "error+add tau=1 five");
    EXPECT_CONTAINS(r.out, "--stitch add drawing");
    snprintf(path, sizeof path, "%s/both.csv", dir);
    csv_read(path, &c);
    ASSERT_EQ_INT(15, c.rows); /* full, distance sets, five, error sets, five: 3 frames each */
    for (int cfg = 1; cfg < 5; cfg += 2)
        for (int f = 0; f < 3; f++) {
            int s = 3 * cfg + f, v = s + 3; /* sets' row, five's */
            EXPECT_EQ_STR(csv_str(&c, s, "lod_mode"), csv_str(&c, v, "lod_mode"));
            for (size_t k = 0; k < sizeof cols / sizeof *cols; k++)
                EXPECT_EQ_DBL(csv_num(&c, s, cols[k]), csv_num(&c, v, cols[k]));
            EXPECT_GE(csv_num(&c, v, "draw_calls"), csv_num(&c, s, "draw_calls"));
            tp_test_note("%s frame %d: %g triangles, max %g px; draw calls %g (sets) %g (five)",
                         csv_str(&c, s, "lod_mode"), f + 1, csv_num(&c, s, "triangles"),
                         csv_num(&c, s, "max_screen_error_px"), csv_num(&c, s, "draw_calls"),
                         csv_num(&c, v, "draw_calls"));
        }
    csv_free(&c);
    /* the JSON: five is drawn as more draws (1 + the sides that take vertices, per such patch):
       it was drawn as five regions, and something was added */
    snprintf(path, sizeof path, "%s/both.json", dir);
    char* json = read_file(path, NULL);
    ASSERT_TRUE(json != NULL);
    const char *os[8], *oe[8];
    ASSERT_EQ_INT(5, json_objects(json, "configurations", os, oe, 8));
    for (int cfg = 1; cfg < 5; cfg += 2) {
        char sets[16], five[16];
        json_str(os[cfg], oe[cfg], "stitch_add_draw", sets, sizeof sets);
        json_str(os[cfg + 1], oe[cfg + 1], "stitch_add_draw", five, sizeof five);
        EXPECT_EQ_STR("sets", sets);
        EXPECT_EQ_STR("five", five);
        EXPECT_GT(json_num(os[cfg + 1], oe[cfg + 1], "draws_median"),
                  json_num(os[cfg], oe[cfg], "draws_median"));
    }
    free(json);
    dir = make_tmp_dir(); /* empty: a usage error writes nothing */
    args_bench_small(&a, 1);
    args_add(&a, "--stitch-add-draw");
    args_add(&a, "sideways");
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--stitch-add-draw: expected sets, five or both", dir);
    args_sweep(&a, dir);
    args_add(&a, "--stitch-add-draw");
    args_add(&a, "both");
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--stitch-add-draw both: not with --sweep", dir);
}

TEST(stitch_add_static_or_bad_mode_exits_2)
{
    args a;
    const char* dem = sample_path(MT_HOOD);
    const char* dir = make_tmp_dir();
    args_bench_small(&a, 1);
    args_add(&a, "--stitch");
    args_add(&a, "add");
    args_add(&a, "--static");
    args_add(&a, "--max-error");
    args_add(&a, "5");
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--stitch add: not with --static", dir);
    args_bench_small(&a, 1);
    args_add(&a, "--stitch");
    args_add(&a, "sideways");
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--stitch: expected move or add", dir);
    args_sweep(&a, dir); /* the sweep runs both crack fixes already */
    args_add(&a, "--stitch");
    args_add(&a, "add");
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "takes no --stitch", dir);
}

TEST(static_and_max_error_go_together_exits_2)
{
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    args_cmd(&a, "bench");
    args_add(&a, "--static");
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--max-error", dir);
    args_cmd(&a, "bench");
    args_add(&a, "--max-error");
    args_add(&a, "5");
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--static", dir);
}

TEST(plot_without_sweep_exits_2)
{
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    args_bench_small(&a, 1);
    args_add(&a, "--plot");
    args_add(&a, "%s/p.png", dir);
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--plot", dir);
    /* with --static too */
    args_static(&a, "5", dir);
    args_add(&a, "--plot");
    args_add(&a, "%s/p.png", dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--plot", dir);
}

TEST(static_with_sweep_exits_2)
{
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    args_static(&a, "5", NULL);
    args_add(&a, "--sweep");
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--sweep", dir);
}

TEST(static_compare_and_runs_need_static_exits_2)
{
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    args_bench_small(&a, 1);
    args_add(&a, "--compare");
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--compare needs --static", dir);
    args_bench_small(&a, 1);
    args_add(&a, "--runs");
    args_add(&a, "2");
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--runs needs --static", dir);
    args_static(&a, "5", NULL);
    args_add(&a, "--runs");
    args_add(&a, "0");
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--runs", dir);
}

TEST(bad_speed_exits_2)
{
    static const char* const bad[] = {"-1", "abc", "", "nan", "inf", "1e999", "5x", "-0.5"};
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    for (int i = 0; i < COUNT(bad); i++) {
        tp_test_note("--speed '%s'", bad[i]);
        args_bench_small(&a, 1);
        args_add(&a, "--speed");
        args_add(&a, "%s", bad[i]);
        args_outputs(&a, dir);
        args_add(&a, "%s", dem);
        expect_usage_error(&a, "--speed", dir);
    }
    /* no value at all */
    args_bench_small(&a, 1);
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    args_add(&a, "--speed");
    expect_usage_error(&a, "--speed", dir);
}

TEST(bad_max_error_list_exits_2)
{
    static const char* const bad[] = {
        "0",   "-1",     "1,,5", "1,5,", ",1",  "abc", "1;5", "1 5", "nan", "inf",
        "5m",  "1,0,5",  "",     "1e999",
        "1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16,17", /* 17 bounds: 16 at most */
    };
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    for (int i = 0; i < COUNT(bad); i++) {
        tp_test_note("--max-error '%s'", bad[i]);
        args_static(&a, bad[i], NULL);
        args_outputs(&a, dir);
        args_add(&a, "%s", dem);
        expect_usage_error(&a, "--max-error", dir);
    }
}

TEST(extra_positional_argument_exits_2)
{
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    args_static(&a, "5", NULL);
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    args_add(&a, "second_dem.tif");
    expect_usage_error(&a, "second_dem.tif", dir);
    args_bench_small(&a, 1);
    args_add(&a, "--sweep");
    args_outputs(&a, dir);
    args_add(&a, "%s", dem);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "extra argument", dir);
}

/* ---------------------------------------------------------------------------------------------
 * Outputs that cannot be written: exit 1, a message naming the path, no temporary file left
 */
static void expect_write_failure(const args* a, const char* needle, run_result* r)
{
    run(a, r);
    skip_without_gl(r);
    if (r->exit_code != 1 || !strstr(r->err, needle))
        print_command(a);
    tp_test_note("exit %d, stderr ends: %s", r->exit_code, err_tail(r));
    EXPECT_EQ_INT(1, r->exit_code);
    EXPECT_CONTAINS(r->err, needle);
}

TEST(unwritable_outputs_exit_1)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    ASSERT_TRUE(access("/nonexistent-dir", F_OK) != 0);
    /* --static --json, --static --csv */
    args_static(&a, "5", NULL);
    args_add(&a, "--json");
    args_add(&a, "/nonexistent-dir/x.json");
    args_add(&a, "%s", dem);
    expect_write_failure(&a, "/nonexistent-dir/x.json", &r);
    args_static(&a, "5", NULL);
    args_add(&a, "--csv");
    args_add(&a, "/nonexistent-dir/x.csv");
    args_add(&a, "%s", dem);
    expect_write_failure(&a, "/nonexistent-dir/x.csv", &r);
    /* frames: --json and --csv */
    args_bench_small(&a, 1);
    args_add(&a, "--json");
    args_add(&a, "/nonexistent-dir/x.json");
    args_add(&a, "%s", dem);
    expect_write_failure(&a, "/nonexistent-dir/x.json", &r);
    args_bench_small(&a, 1);
    args_add(&a, "--csv");
    args_add(&a, "/nonexistent-dir/x.csv");
    args_add(&a, "%s", dem);
    expect_write_failure(&a, "/nonexistent-dir/x.csv", &r);
    /* --sweep: the CSV, then the plot */
    args_bench_small(&a, 1);
    args_add(&a, "--sweep");
    args_add(&a, "--csv");
    args_add(&a, "/nonexistent-dir/x.csv");
    args_add(&a, "%s", dem);
    expect_write_failure(&a, "/nonexistent-dir/x.csv", &r);
    args_sweep(&a, dir);
    args_add(&a, "--plot");
    args_add(&a, "/nonexistent-dir/x.png");
    args_add(&a, "%s", dem);
    expect_write_failure(&a, "/nonexistent-dir/x.png", &r);
    EXPECT_TRUE(access("/nonexistent-dir", F_OK) != 0);
    char listing[4096];
    tp_test_note("after the failed plot, the output directory holds [%s]",
                 dir_listing(dir, listing, sizeof listing));
    EXPECT_TRUE(strstr(listing, ".tmp") == NULL);
    EXPECT_TRUE(strstr(listing, ".png") == NULL);
}

/* The target's name is taken by a directory: the temporary file beside it is removed. */
TEST(output_onto_a_directory_leaves_no_temporary_file)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    char target[1024];
    snprintf(target, sizeof target, "%s/out.csv", dir);
    ASSERT_EQ_INT(0, mkdir(target, 0755));
    args_static(&a, "5", NULL);
    args_add(&a, "--csv");
    args_add(&a, "%s", target);
    args_add(&a, "%s", dem);
    expect_write_failure(&a, target, &r);
    EXPECT_DIR_IS(dir, "out.csv");
    EXPECT_DIR_IS(target, "");
    snprintf(target, sizeof target, "%s/out.json", dir);
    ASSERT_EQ_INT(0, mkdir(target, 0755));
    args_static(&a, "5", NULL);
    args_add(&a, "--json");
    args_add(&a, "%s", target);
    args_add(&a, "%s", dem);
    expect_write_failure(&a, target, &r);
    EXPECT_DIR_IS(dir, "out.csv,out.json");
    EXPECT_DIR_IS(target, "");
}

TEST(sweep_plot_onto_a_directory_leaves_no_temporary_file)
{
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    const char* dir = make_tmp_dir();
    char target[1024];
    snprintf(target, sizeof target, "%s/p.png", dir);
    ASSERT_EQ_INT(0, mkdir(target, 0755));
    args_bench_small(&a, 1);
    args_add(&a, "--sweep");
    args_add(&a, "--csv");
    args_add(&a, "%s/s.csv", dir);
    args_add(&a, "--plot");
    args_add(&a, "%s", target);
    args_add(&a, "%s", dem);
    expect_write_failure(&a, target, &r);
    char listing[4096];
    dir_listing(dir, listing, sizeof listing);
    tp_test_note("output directory: [%s]", listing);
    EXPECT_TRUE(strstr(listing, ".tmp") == NULL); /* no p.png.tmpPID.png / .gp left */
    EXPECT_DIR_IS(target, "");
}

/* ---------------------------------------------------------------------------------------------
 * Stores (.tpt): a short flight through the hierarchy with streaming (app/bench/bench_store.c)
 */

/* Builds the Storm Lake sample (143 x 107, 30 m) into a store of 17-sample nodes (9 x 7 leaves,
 * 4 scales) in a new temporary folder; returns its path. */
static const char* build_small_store(void)
{
    static char path[1024];
    static run_result r;
    args a;
    const char* dem = sample_path(STORML);
    args_cmd(&a, "build");
    args_add(&a, "--patch");
    args_add(&a, "17");
    args_add(&a, "--quiet");
    args_add(&a, "--threads");
    args_add(&a, "1");
    snprintf(path, sizeof path, "%s/storml.tpt", make_tmp_dir());
    args_add(&a, "-o");
    args_add(&a, "%s", path);
    args_add(&a, "%s", dem);
    run_ok(&a, &r);
    return path;
}

TEST(store_flight_reports_memory_streaming_and_error)
{
    static run_result r;
    static csv frames;
    args a;
    const char* store = build_small_store();
    const char* dir = make_tmp_dir();
    char path[1024];
    args_bench_small(&a, 6);
    args_add(&a, "--segments");
    args_add(&a, "2");
    args_add(&a, "--memory");
    args_add(&a, "64");
    args_add(&a, "--json");
    args_add(&a, "%s/s.json", dir);
    args_add(&a, "--csv");
    args_add(&a, "%s/s.csv", dir);
    args_add(&a, "%s", store);
    run_ok(&a, &r);
    EXPECT_DIR_IS(dir, "s.csv,s.json");
    snprintf(path, sizeof path, "%s/s.json", dir);
    char* json = read_file(path, NULL);
    ASSERT_TRUE(json != NULL);
    snprintf(path, sizeof path, "%s/s.csv", dir);
    csv_read(path, &frames);
    EXPECT_CONTAINS(r.out, "first frame");

    /* every key the issue asks for, numbers (json_num fails on null, i.e. NaN), sane */
    const char* conf = strstr(json, "\"configurations\"");
    ASSERT_TRUE(conf != NULL);
    EXPECT_EQ_DBL(6.0, json_num(json, conf, "frames"));
    EXPECT_EQ_DBL(143.0 * 107.0, json_num(json, conf, "samples"));
    double rss = json_num(json, conf, "rss_mb"), anon = json_num(json, conf, "rss_anon_mb");
    double resident = json_num(json, conf, "resident_mb"), gpu = json_num(json, conf, "gpu_mb");
    double first = json_num(json, conf, "first_frame_ms");
    double first_open = json_num(json, conf, "first_frame_from_open_ms");
    double median = json_num(json, conf, "frame_ms_median");
    double p99 = json_num(json, conf, "frame_ms_p99");
    tp_test_note("rss %.1f MB (anon %.1f), resident %.3f MB, gpu %.2f MB, first frame %.0f ms "
                 "(%.0f from open), frame %.1f ms (p99 %.1f)",
                 rss, anon, resident, gpu, first, first_open, median, p99);
    EXPECT_GT(anon, 0.0);
    EXPECT_LE(anon, rss);
    /* the whole map decoded is 63 leaves + 21 coarser nodes of 17 x 17 uint16: 0.049 MB */
    EXPECT_GT(resident, 0.0);
    EXPECT_LE(resident, 84 * 17 * 17 * 2 / 1e6 + 1e-9);
    EXPECT_GT(gpu, 0.0);
    EXPECT_GT(first_open, 0.0);
    EXPECT_GE(first + 10.0, first_open); /* /proc's start time has 10 ms ticks */
    EXPECT_GT(median, 0.0);
    EXPECT_GE(p99, median);
    EXPECT_GE(json_num(json, conf, "nodes_drawn_median"), 1.0);
    EXPECT_GT(json_num(json, conf, "fps_median"), 0.0);
    /* one schema for DEMs and stores: the DEM bench's cpu_ms_median (a store said cpu_ms) */
    EXPECT_GE(json_num(json, conf, "cpu_ms_median"), 0.0);
    EXPECT_TRUE(strstr(json, "\"cpu_ms\"") == NULL);
    double subst_max = json_num(json, conf, "substituted_nodes_max");
    double subst_frames = json_num(json, conf, "frames_with_substitution");
    EXPECT_GE(subst_max, 0.0);
    EXPECT_GE(subst_frames, 0.0);
    EXPECT_LE(subst_frames, 6.0);

    /* the error over frames without substitution: at tau = 1 px (the default), within it */
    double measured = json_num(json, conf, "error_frames_measured");
    double max_px = json_num(json, conf, "max_screen_error_px");
    EXPECT_GE(measured, 1.0);
    EXPECT_GT(json_num(json, conf, "error_samples"), 0.0);
    EXPECT_GE(max_px, 0.0);
    EXPECT_LE(max_px, 1.0 + 1e-3);
    /* how: every leaf under the cut (a small store, far below the budget), read from the store
     * where the stream did not hold it, none lost */
    double leaves = json_num(json, conf, "error_leaves");
    EXPECT_GT(leaves, 0.0);
    EXPECT_EQ_DBL(leaves, json_num(json, conf, "error_leaves_sampled"));
    EXPECT_EQ_DBL(1.0, json_num(json, conf, "error_leaf_share"));
    EXPECT_EQ_DBL(0.0, json_num(json, conf, "error_leaves_per_node_min"));
    EXPECT_EQ_DBL(0.0, json_num(json, conf, "error_leaves_skipped"));
    EXPECT_EQ_DBL(0.0, json_num(json, conf, "error_samples_skipped"));
    EXPECT_LE(json_num(json, conf, "error_leaves_read"), json_num(json, conf, "error_leaves_measured"));
    EXPECT_EQ_DBL(4194304.0, json_num(json, conf, "error_posts_budget"));
    EXPECT_EQ_DBL(1.0, json_num(json, NULL, "error_every")); /* the top level: every frame */
    EXPECT_GE(json_num(json, conf, "error_ms_median"), 0.0);
    EXPECT_GE(json_num(json, conf, "error_frames_substituted"), 0.0);

    /* the summary is the CSV's frames: error mode first, 6 frames per configuration */
    ASSERT_EQ_INT(12, frames.rows);
    double csv_subst_max = 0, csv_subst_frames = 0, csv_measured = 0, csv_max_px = 0;
    for (int i = 0; i < 6; i++) {
        EXPECT_TRUE(strcmp(csv_str(&frames, i, "lod_mode"), "error") == 0);
        double s = csv_num(&frames, i, "substituted");
        csv_subst_max = s > csv_subst_max ? s : csv_subst_max;
        csv_subst_frames += s > 0;
        double how = csv_num(&frames, i, "measured"); /* 1: without substitution, 2: with */
        EXPECT_EQ_DBL(s > 0 ? 2.0 : 1.0, how); /* every frame measured (--error-every 1) */
        EXPECT_LE(csv_num(&frames, i, "error_leaves_sampled"), csv_num(&frames, i, "error_leaves"));
        if (how == 1) {
            csv_measured++;
            double px = csv_num(&frames, i, "max_screen_error_px");
            csv_max_px = px > csv_max_px ? px : csv_max_px;
        }
        EXPECT_GE(csv_num(&frames, i, "frame_ms"),
                  csv_num(&frames, i, "cut_ms") + csv_num(&frames, i, "stream_ms"));
    }
    EXPECT_TRUE(strcmp(csv_str(&frames, 6, "lod_mode"), "distance") == 0);
    EXPECT_EQ_DBL(csv_subst_max, subst_max);
    EXPECT_EQ_DBL(csv_subst_frames, subst_frames);
    EXPECT_EQ_DBL(csv_measured, measured);
    EXPECT_NEAR(csv_max_px, max_px, 1e-4); /* the CSV has 4 decimals */
    free(json);
    csv_free(&frames);
}

/* bench STORE --stitch add: the error and distance modes again with vertex adding, on the same
 * frames; the error mode's measured error (the triangles drawn, added vertices included) stays
 * within tau, and the store's nodes did take vertices (more triangles than vertex moving's). */
TEST(store_stitch_add_runs_both_modes_again)
{
    static run_result r;
    static csv frames;
    args a;
    const char* store = build_small_store();
    const char* dir = make_tmp_dir();
    char path[1024];
    args_bench_small(&a, 6);
    args_add(&a, "--stitch");
    args_add(&a, "add");
    args_add(&a, "--csv");
    args_add(&a, "%s/s.csv", dir);
    args_add(&a, "%s", store);
    run_ok(&a, &r);
    snprintf(path, sizeof path, "%s/s.csv", dir);
    csv_read(path, &frames);
    /* four configurations of the same frames (the flight's whole segments of the 6 asked) */
    ASSERT_TRUE(frames.rows > 0 && frames.rows % 4 == 0);
    const int per = frames.rows / 4;
    static const char* modes[4] = {"error", "distance", "error+add", "distance+add"};
    double tris[4] = {0}, max_px[4] = {0};
    int measured[4] = {0};
    for (int i = 0; i < frames.rows; i++) {
        int m = i / per;
        EXPECT_TRUE(strcmp(csv_str(&frames, i, "lod_mode"), modes[m]) == 0);
        tris[m] += csv_num(&frames, i, "triangles");
        if (csv_num(&frames, i, "measured") == 1) { /* drawn without substitution */
            measured[m]++;
            max_px[m] = fmax(max_px[m], csv_num(&frames, i, "max_screen_error_px"));
        }
    }
    tp_test_note("triangles over the frames: error %.0f, +add %.0f; distance %.0f, +add %.0f; "
                 "max px error %.3f, +add %.3f", tris[0], tris[2], tris[1], tris[3], max_px[0],
                 max_px[2]);
    EXPECT_GT(measured[2], 0);
    EXPECT_LE(max_px[2], 1.0 + 1e-3); /* tau = 1 px, the default */
    EXPECT_GT(tris[2], tris[0]);
    EXPECT_GT(tris[3], tris[1]);
    csv_free(&frames);
}

TEST(store_refuses_what_needs_a_terrain_exits_2)
{
    args a;
    const char* store = build_small_store();
    const char* dir = make_tmp_dir();
    args_bench_small(&a, 1);
    args_add(&a, "--path");
    args_add(&a, "orbit");
    args_add(&a, "--json");
    args_add(&a, "%s/s.json", dir);
    args_add(&a, "%s", store);
    expect_usage_error(&a, "--path orbit is not available for a store", dir);
    args_bench_small(&a, 1);
    args_add(&a, "--segments");
    args_add(&a, "0");
    args_add(&a, "%s", store);
    expect_usage_error(&a, "--segments", NULL);
}

/* ---------------------------------------------------------------------------------------------
 * Persistent Grid Mapping (--renderer pgm; app/bench/bench_pgm.c, app/render/pgm_render.c)
 */

/* bench --renderer pgm: one configuration per grid after the three patch ones, every frame of
 * the same path; a grid's triangles are 2 (cols - 1)(rows - 1) every frame, drawn in one call;
 * the error is measured on every --error-every-th frame only. */
TEST(pgm_bench_adds_a_configuration_per_grid)
{
    static run_result r;
    static csv c;
    const char* dir = make_tmp_dir();
    char csv_path[1024], json_path[1024];
    snprintf(csv_path, sizeof csv_path, "%s/pgm.csv", dir);
    snprintf(json_path, sizeof json_path, "%s/pgm.json", dir);
    args a;
    args_bench_small(&a, 4);
    args_add(&a, "--renderer");
    args_add(&a, "pgm");
    args_add(&a, "--pgm-grid");
    args_add(&a, "40x30,64x64");
    args_add(&a, "--error-every");
    args_add(&a, "2");
    args_add(&a, "--csv");
    args_add(&a, "%s", csv_path);
    args_add(&a, "--json");
    args_add(&a, "%s", json_path);
    args_add(&a, "%s", sample_path(MT_HOOD));
    run_ok(&a, &r);
    EXPECT_CONTAINS(r.out, "pgm 40x30");
    EXPECT_CONTAINS(r.out, "pgm 64x64");
    csv_read(csv_path, &c);
    ASSERT_EQ_INT(5 * 4, c.rows); /* full, distance, error, two grids; 4 frames each */
    const int grid[2][2] = {{40, 30}, {64, 64}};
    int pgm_rows = 0;
    double share_sum[2] = {0, 0}; /* the measured frames' uncovered shares, per grid */
    for (int i = 0; i < c.rows; i++) {
        if (strcmp(csv_str(&c, i, "lod_mode"), "pgm") != 0) {
            EXPECT_EQ_STR("", csv_str(&c, i, "pgm_grid"));
            EXPECT_EQ_DBL(0, csv_num(&c, i, "uncovered_share")); /* patches cover every post */
            continue;
        }
        int g = pgm_rows++ / 4, frame = (int)csv_num(&c, i, "frame");
        char want[32];
        snprintf(want, sizeof want, "%dx%d", grid[g][0], grid[g][1]);
        EXPECT_EQ_STR(want, csv_str(&c, i, "pgm_grid"));
        EXPECT_EQ_DBL(2.0 * (grid[g][0] - 1) * (grid[g][1] - 1), csv_num(&c, i, "triangles"));
        EXPECT_EQ_DBL(1, csv_num(&c, i, "draw_calls"));
        EXPECT_GT(csv_num(&c, i, "gpu_bytes"), 0);
        EXPECT_GT(csv_num(&c, i, "frame_ms"), 0);
        double max_m = csv_num(&c, i, "max_vertical_error_m");
        double rms_px = csv_num(&c, i, "rms_screen_error_px");
        if (frame % 2 == 0) { /* measured: a low flight over Mt Hood is never exact */
            EXPECT_GT(max_m, 0);
            EXPECT_GE(max_m, csv_num(&c, i, "rms_vertical_error_m"));
            EXPECT_GE(csv_num(&c, i, "max_screen_error_px"), rms_px);
            EXPECT_GT(rms_px, 0);
            double u = csv_num(&c, i, "uncovered_share");
            EXPECT_TRUE(u >= 0 && u < 1);
            share_sum[g] += u;
        } else {
            EXPECT_TRUE(isnan(max_m) && isnan(rms_px));
            EXPECT_TRUE(isnan(csv_num(&c, i, "uncovered_share")));
        }
    }
    EXPECT_EQ_INT(8, pgm_rows);
    csv_free(&c);
    size_t size = 0;
    char* json = read_file(json_path, &size);
    ASSERT_TRUE(json != NULL);
    const char *os[8], *oe[8];
    int n = json_objects(json, "configurations", os, oe, 8);
    ASSERT_EQ_INT(5, n);
    char buf[64];
    for (int i = 0; i < 3; i++)
        EXPECT_EQ_STR("patches", json_str(os[i], oe[i], "terrain_renderer", buf, sizeof buf));
    for (int g = 0; g < 2; g++) {
        char want[32];
        snprintf(want, sizeof want, "%dx%d", grid[g][0], grid[g][1]);
        EXPECT_EQ_STR("pgm", json_str(os[3 + g], oe[3 + g], "terrain_renderer", buf, sizeof buf));
        EXPECT_EQ_STR(want, json_str(os[3 + g], oe[3 + g], "pgm_grid", buf, sizeof buf));
        EXPECT_EQ_DBL(2.0 * (grid[g][0] - 1) * (grid[g][1] - 1),
                      json_num(os[3 + g], oe[3 + g], "triangles_median"));
        EXPECT_GT(json_num(os[3 + g], oe[3 + g], "max_screen_error_px"), 0);
        /* the summary's share: the mean over the measured frames (0 and 2; CSV at 1e-6) */
        EXPECT_NEAR(share_sum[g] / 2, json_num(os[3 + g], oe[3 + g], "uncovered_share"), 1e-6);
    }
    free(json);
}

/* Usage errors: a bad grid, a grid without --renderer pgm, a window that is not a power of two
 * (view and bench), a window for a DEM drawn whole or without --renderer pgm. */
TEST(pgm_bad_grids_and_windows_exit_2)
{
    const char* store = build_small_store();
    const char* dem = sample_path(MT_HOOD);
    const char* dir = make_tmp_dir();
    args a;
    args_bench_small(&a, 1);
    args_add(&a, "--renderer");
    args_add(&a, "pgm");
    args_add(&a, "--pgm-window");
    args_add(&a, "100");
    args_add(&a, "%s", store);
    expect_usage_error(&a, "--pgm-window", dir);
    args_cmd(&a, "view");
    args_add(&a, "--renderer");
    args_add(&a, "pgm");
    args_add(&a, "--pgm-window");
    args_add(&a, "8");
    args_add(&a, "--headless");
    args_add(&a, "--screenshot");
    args_add(&a, "%s/x.png", dir);
    args_add(&a, "%s", store);
    expect_usage_error(&a, "--pgm-window", dir);
    args_cmd(&a, "view");
    args_add(&a, "--renderer");
    args_add(&a, "pgm");
    args_add(&a, "--pgm-window");
    args_add(&a, "64");
    args_add(&a, "--headless");
    args_add(&a, "--screenshot");
    args_add(&a, "%s/x.png", dir);
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--pgm-window is for --renderer pgm over a store", dir);
    args_bench_small(&a, 1);
    args_add(&a, "--pgm-window");
    args_add(&a, "64");
    args_add(&a, "%s", store);
    expect_usage_error(&a, "--pgm-window is for --renderer pgm over a store", dir);
    args_bench_small(&a, 1);
    args_add(&a, "--renderer");
    args_add(&a, "pgm");
    args_add(&a, "--pgm-grid");
    args_add(&a, "1x600");
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--pgm-grid", dir);
    args_bench_small(&a, 1);
    args_add(&a, "--pgm-grid");
    args_add(&a, "300x300");
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--pgm-grid needs --renderer pgm", dir);
    args_cmd(&a, "view");
    args_add(&a, "--renderer");
    args_add(&a, "quads");
    args_add(&a, "%s", dem);
    expect_usage_error(&a, "--renderer", dir);
}

/* view --renderer pgm --headless on the sample DEM (drawn whole, no store built): the
 * screenshot at the asked size, the statistics JSON naming the renderer and the grid, whose
 * triangles are the grid's. */
TEST(pgm_view_headless_writes_screenshot_and_stats)
{
    static run_result r;
    const char* dir = make_tmp_dir();
    char png[1024], json_path[1024];
    snprintf(png, sizeof png, "%s/pgm.png", dir);
    snprintf(json_path, sizeof json_path, "%s/pgm.json", dir);
    args a;
    args_cmd(&a, "view");
    args_add(&a, "--renderer");
    args_add(&a, "pgm");
    args_add(&a, "--pgm-grid");
    args_add(&a, "200x100");
    args_add(&a, "--headless");
    args_add(&a, "--size");
    args_add(&a, "320x180");
    args_add(&a, "--screenshot");
    args_add(&a, "%s", png);
    args_add(&a, "--stats-json");
    args_add(&a, "%s", json_path);
    args_add(&a, "%s", sample_path(MT_HOOD));
    run_ok(&a, &r);
    unsigned w = 0, h = 0;
    size_t size = 0;
    EXPECT_TRUE(png_header(png, &w, &h, &size));
    EXPECT_EQ_INT(320, (int)w);
    EXPECT_EQ_INT(180, (int)h);
    char* json = read_file(json_path, &size);
    ASSERT_TRUE(json != NULL);
    char buf[64];
    EXPECT_EQ_STR("pgm", json_str(json, NULL, "renderer", buf, sizeof buf));
    EXPECT_EQ_STR("200x100", json_str(json, NULL, "pgm_grid", buf, sizeof buf));
    EXPECT_EQ_DBL(2.0 * 199 * 99, json_num(json, NULL, "triangles"));
    EXPECT_EQ_DBL(1, json_num(json, NULL, "draw_calls"));
    /* the default view looks at the whole DEM: posts are in view and the surface is measured */
    EXPECT_GT(json_num(json, NULL, "max_error_px"), 0);
    EXPECT_GE(json_num(json, NULL, "max_error_m"), json_num(json, NULL, "rms_error_m"));
    free(json);
}

/* The PGM clipmap's GPU bytes for a store of src_width x src_height posts: the grid's indices
 * and one window x window R32F layer per pyramid level (pgm_clip.h). */
static double pgm_clip_bytes(int cols, int rows, int window, int src_width, int src_height)
{
    int w = src_width, h = src_height, levels = 1;
    while (!(w <= 2 && h <= 2)) {
        w = w / 2 + 1, h = h / 2 + 1;
        levels++;
    }
    return 6.0 * (cols - 1) * (rows - 1) * 4 + (double)levels * window * window * 4;
}

/* view STORE --renderer pgm --headless (issue 16): drawn through the store's clipmap; the
 * screenshot at its size, the statistics naming the renderer, the grid's triangles, the GPU
 * bytes of the clipmap (bounded: the window, not the store), the error measured against the
 * store's level-0 posts (tp_pgm_clipmap_measure: numbers, max >= RMS >= 0). */
TEST(pgm_view_store_headless_draws_through_its_clipmap)
{
    static run_result r;
    const char* store = build_small_store();
    const char* dir = make_tmp_dir();
    char png[1024], json_path[1024];
    snprintf(png, sizeof png, "%s/pgm.png", dir);
    snprintf(json_path, sizeof json_path, "%s/pgm.json", dir);
    args a;
    args_cmd(&a, "view");
    args_add(&a, "--renderer");
    args_add(&a, "pgm");
    args_add(&a, "--pgm-grid");
    args_add(&a, "200x100");
    args_add(&a, "--pgm-window");
    args_add(&a, "32");
    args_add(&a, "--headless");
    args_add(&a, "--frames");
    args_add(&a, "3");
    args_add(&a, "--size");
    args_add(&a, "320x180");
    args_add(&a, "--screenshot");
    args_add(&a, "%s", png);
    args_add(&a, "--stats-json");
    args_add(&a, "%s", json_path);
    args_add(&a, "%s", store);
    run_ok(&a, &r);
    unsigned w = 0, h = 0;
    size_t size = 0;
    EXPECT_TRUE(png_header(png, &w, &h, &size));
    EXPECT_EQ_INT(320, (int)w);
    EXPECT_EQ_INT(180, (int)h);
    char* json = read_file(json_path, &size);
    ASSERT_TRUE(json != NULL);
    char buf[64];
    EXPECT_EQ_STR("pgm", json_str(json, NULL, "renderer", buf, sizeof buf));
    EXPECT_EQ_STR("200x100", json_str(json, NULL, "pgm_grid", buf, sizeof buf));
    EXPECT_EQ_DBL(2.0 * 199 * 99, json_num(json, NULL, "triangles"));
    EXPECT_EQ_DBL(pgm_clip_bytes(200, 100, 32, 143, 107), json_num(json, NULL, "gpu_bytes"));
    double max_px = json_num(json, NULL, "max_error_px");
    double rms_px = json_num(json, NULL, "rms_error_px");
    EXPECT_TRUE(isfinite(max_px));
    EXPECT_GE(max_px, rms_px);
    EXPECT_GE(rms_px, 0.0);
    EXPECT_GE(json_num(json, NULL, "max_error_m"), json_num(json, NULL, "rms_error_m"));
    free(json);
}

/* bench STORE --renderer pgm: a configuration per grid after the patch ones, flown on the same
 * path, with the clipmap's figures (fill and upload ms, posts updated), its GPU bytes and the
 * error measured on every frame (numbers, and the share of the posts in view left uncovered). */
TEST(pgm_store_bench_reports_the_clipmap)
{
    static run_result r;
    const char* store = build_small_store();
    const char* dir = make_tmp_dir();
    char path[1024];
    args a;
    args_bench_small(&a, 6);
    args_add(&a, "--segments");
    args_add(&a, "2");
    args_add(&a, "--renderer");
    args_add(&a, "pgm");
    args_add(&a, "--pgm-grid");
    args_add(&a, "64x48,40x40");
    args_add(&a, "--pgm-window");
    args_add(&a, "32");
    args_add(&a, "--json");
    args_add(&a, "%s/s.json", dir);
    args_add(&a, "%s", store);
    run_ok(&a, &r);
    EXPECT_CONTAINS(r.out, "pgm 64x48: clipmap of 32 x 32 posts a level");
    EXPECT_CONTAINS(r.out, "screen error (the windows' surface against the level-0 posts in "
                           "view) measured on 6 frames");
    snprintf(path, sizeof path, "%s/s.json", dir);
    char* json = read_file(path, NULL);
    ASSERT_TRUE(json != NULL);
    const char *os[8], *oe[8];
    int n = json_objects(json, "configurations", os, oe, 8);
    ASSERT_EQ_INT(4, n); /* error, distance, two grids */
    char buf[64];
    const int grid[2][2] = {{64, 48}, {40, 40}};
    for (int k = 0; k < 2; k++) {
        const char *o0 = os[2 + k], *o1 = oe[2 + k];
        char want[32];
        snprintf(want, sizeof want, "%dx%d", grid[k][0], grid[k][1]);
        EXPECT_EQ_STR("pgm", json_str(o0, o1, "terrain_renderer", buf, sizeof buf));
        EXPECT_EQ_STR(want, json_str(o0, o1, "pgm_grid", buf, sizeof buf));
        EXPECT_EQ_DBL(32, json_num(o0, o1, "pgm_window"));
        EXPECT_EQ_DBL(2.0 * (grid[k][0] - 1) * (grid[k][1] - 1),
                      json_num(o0, o1, "triangles_median"));
        EXPECT_NEAR(pgm_clip_bytes(grid[k][0], grid[k][1], 32, 143, 107) / 1e6,
                    json_num(o0, o1, "gpu_mb"), 1e-9);
        EXPECT_GE(json_num(o0, o1, "pgm_fill_ms_median"), 0.0);
        EXPECT_GE(json_num(o0, o1, "pgm_upload_ms_p99"), json_num(o0, o1, "pgm_upload_ms_median"));
        EXPECT_GE(json_num(o0, o1, "pgm_posts_updated_median"), 0.0);
        EXPECT_GT(json_num(o0, o1, "fps_median"), 0.0);
        EXPECT_EQ_DBL(6, json_num(o0, o1, "error_frames_measured"));
        EXPECT_EQ_DBL(1, json_num(o0, o1, "error_post_share")); /* a small store: every post */
        double max_px = json_num(o0, o1, "max_screen_error_px");
        EXPECT_TRUE(isfinite(max_px));
        EXPECT_GE(max_px, json_num(o0, o1, "rms_screen_error_px"));
        EXPECT_GT(json_num(o0, o1, "error_samples"), 0.0);
        double share = json_num(o0, o1, "uncovered_share");
        EXPECT_TRUE(share >= 0 && share < 1);
    }
    for (int k = 0; k < 2; k++)
        EXPECT_EQ_STR("patches", json_str(os[k], oe[k], "terrain_renderer", buf, sizeof buf));
    free(json);
}

#define TESTS(X)                                                                                   \
    X(progress_on_a_log_is_a_line_per_tenth)                                                       \
    X(pgm_bench_adds_a_configuration_per_grid)                                                     \
    X(pgm_bad_grids_and_windows_exit_2)                                                            \
    X(pgm_view_store_headless_draws_through_its_clipmap)                                           \
    X(pgm_store_bench_reports_the_clipmap)                                                         \
    X(pgm_view_headless_writes_screenshot_and_stats)                                               \
    X(sweep_writes_one_row_per_configuration_and_a_plot)                                           \
    X(stitch_add_against_move_frame_by_frame)                                                      \
    X(stitch_add_draw_sets_and_five_measure_alike)                                                 \
    X(stitch_add_static_or_bad_mode_exits_2)                                                       \
    X(store_stitch_add_runs_both_modes_again)                                                      \
    X(sweep_pgm_grid_replaces_the_grids)                                                           \
    X(sweep_plot_option_puts_the_plot_there)                                                       \
    X(sweep_tau_off_the_grid_adds_an_error_row)                                                    \
    X(sweep_tau_on_the_grid_adds_no_row)                                                           \
    X(sweep_without_error_measurement_is_refused_or_plots)                                         \
    X(sweep_of_a_flat_dem_still_plots)                                                             \
    X(sweep_plot_never_replaces_the_csv_or_json)                                                   \
    X(static_bounds_hold_and_meshes_shrink)                                                        \
    X(static_mesh_is_the_export_max_error_mesh)                                                    \
    X(static_tin_rows_hold_the_bound_with_fewer_triangles_than_patches)                            \
    X(static_compare_without_node_or_npm_exits_1_naming_it)                                        \
    X(static_compare_and_runs_need_static_exits_2)                                                 \
    X(static_full_triangles_count_every_valid_cell_and_16_bounds_are_taken)                        \
    X(static_bound_below_quantisation_is_reported_not_measured)                                    \
    X(speed_lead_in_changes_uploads_not_what_is_drawn)                                             \
    X(speed_fixed_camera_has_no_lead_in)                                                           \
    X(sweep_without_csv_exits_2)                                                                   \
    X(sweep_with_fit_exits_2)                                                                      \
    X(static_and_max_error_go_together_exits_2)                                                    \
    X(plot_without_sweep_exits_2)                                                                  \
    X(static_with_sweep_exits_2)                                                                   \
    X(bad_speed_exits_2)                                                                           \
    X(bad_max_error_list_exits_2)                                                                  \
    X(extra_positional_argument_exits_2)                                                           \
    X(unwritable_outputs_exit_1)                                                                   \
    X(output_onto_a_directory_leaves_no_temporary_file)                                            \
    X(sweep_plot_onto_a_directory_leaves_no_temporary_file)                                        \
    X(store_flight_reports_memory_streaming_and_error)                                             \
    X(store_refuses_what_needs_a_terrain_exits_2)

TP_TEST_MAIN(TESTS)
