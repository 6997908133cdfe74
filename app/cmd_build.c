/*
 * cmd_build.c - `terrapatch build SOURCE... -o NAME.tpt`: sources mosaicked and put on the
 * render grid (tp_mosaic, read in bands of rows), quantised with one global step, built into
 * the node hierarchy band by band (tp_tree_builder) and written as a terrain store
 * (tp_store_writer), atomically. Memory follows the band, not the map.
 *
 * Two passes over the grid: the first finds the height range, the valid samples and the
 * quantisation error of every candidate step (the store's header, written first, holds them);
 * the second quantises and builds.
 */
#include "atomic_file.h"
#include "cli.h"
#include "json.h"
#include "memory.h"

#include "tp_core.h"
#include "tp_io.h"

#include <getopt.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

typedef struct build_options {
    const char** sources;
    int source_count;
    const char* out;
    int patch_size;
    const char* crs;
    tp_resampling resampling;
    int memory_mb;
    int threads;
    const char* json; /* NULL, "-" or a path */
    int quiet;
} build_options;

enum { OPT_CRS = 256, OPT_RESAMPLING, OPT_MEMORY, OPT_THREADS, OPT_JSON, OPT_QUIET, OPT_PATCH };

static void print_help(void)
{
    fputs("usage: terrapatch build [options] SOURCE... -o NAME.tpt\n"
          "\n"
          "Builds a terrain store from any number of rasters GDAL opens (adjacent tiles of any\n"
          "format mix, a .vrt): they are mosaicked with GDAL's VRT (a later source wins where\n"
          "they overlap, gaps are nodata), or each warped onto one grid when their CRSs or post\n"
          "spacings differ; geographic sources are warped to the UTM/UPS zone of the centre.\n"
          "The grid is read in bands of rows, quantised with one global height step and built\n"
          "into a hierarchy of (2^n+1)^2 nodes; memory stays within --memory whatever the size.\n"
          "Voids are not filled (they stay nodata, never drawn).\n"
          "\n"
          "options:\n"
          "  -o, --output FILE   the store to write (written whole or not at all)\n"
          "  --patch N           node size: 17, 33, 65, 129 or 257 (default 65)\n"
          "  --crs CRS           the sources' CRS (EPSG:N, WKT, PROJ), overriding theirs\n"
          "  --resampling R      bilinear (default) or cubic, for warps\n"
          "  --memory MB         memory budget (default 1024); GDAL's cache gets a quarter\n"
          "  --threads N         threads (default: every core)\n"
          "  --json FILE|-       statistics as JSON (samples, nodes, bytes, seconds, ...)\n"
          "  --quiet             no progress, no notes\n"
          "  -h, --help          show this help\n"
          "\n"
          "Exit status: 0 success, 1 a source could not be read or the store not written,\n"
          "2 usage error, 130/143 after SIGINT/SIGTERM (no store and no temporary file left).\n",
          stdout);
}

static int usage_error(const char* what, const char* detail)
{
    if (detail[0])
        fprintf(stderr, "terrapatch build: %s '%s' (see 'terrapatch build --help')\n", what,
                detail);
    else
        fprintf(stderr, "terrapatch build: %s (see 'terrapatch build --help')\n", what);
    return TP_EXIT_USAGE;
}

static int parse_int(const char* s, int lo, int hi, int* v)
{
    char* end;
    long x = strtol(s, &end, 10);
    if (end == s || *end || x < lo || x > hi)
        return 0;
    *v = (int)x;
    return 1;
}

/* Returns -1 when the options are fine, else the exit code to return. */
static int parse_options(int argc, char** argv, build_options* o)
{
    static const struct option longs[] = {
        {"output", required_argument, NULL, 'o'},
        {"patch", required_argument, NULL, OPT_PATCH},
        {"crs", required_argument, NULL, OPT_CRS},
        {"resampling", required_argument, NULL, OPT_RESAMPLING},
        {"memory", required_argument, NULL, OPT_MEMORY},
        {"threads", required_argument, NULL, OPT_THREADS},
        {"json", required_argument, NULL, OPT_JSON},
        {"quiet", no_argument, NULL, OPT_QUIET},
        {"help", no_argument, NULL, 'h'},
        {NULL, 0, NULL, 0},
    };
    *o = (build_options){0};
    o->patch_size = 65;
    o->memory_mb = 1024;
    opterr = 0;
    optind = 1;
    int c;
    while ((c = getopt_long(argc, argv, ":ho:", longs, NULL)) != -1) {
        switch (c) {
        case 'o': o->out = optarg; break;
        case OPT_PATCH:
            if (!parse_int(optarg, 17, 257, &o->patch_size) ||
                (o->patch_size != 17 && o->patch_size != 33 && o->patch_size != 65 &&
                 o->patch_size != 129 && o->patch_size != 257))
                return tp_option_error("build", "--patch", "17, 33, 65, 129 or 257", optarg),
                       TP_EXIT_USAGE;
            break;
        case OPT_CRS: o->crs = optarg; break;
        case OPT_RESAMPLING:
            if (!strcmp(optarg, "bilinear"))
                o->resampling = TP_RESAMPLING_BILINEAR;
            else if (!strcmp(optarg, "cubic"))
                o->resampling = TP_RESAMPLING_CUBIC;
            else
                return tp_option_error("build", "--resampling", "bilinear or cubic", optarg),
                       TP_EXIT_USAGE;
            break;
        case OPT_MEMORY:
            if (!parse_int(optarg, 64, 1 << 24, &o->memory_mb))
                return tp_option_error("build", "--memory", "megabytes, 64 or more", optarg),
                       TP_EXIT_USAGE;
            break;
        case OPT_THREADS:
            if (!parse_int(optarg, 1, 1024, &o->threads))
                return tp_option_error("build", "--threads", "1 .. 1024", optarg), TP_EXIT_USAGE;
            break;
        case OPT_JSON: o->json = optarg; break;
        case OPT_QUIET: o->quiet = 1; break;
        case 'h': print_help(); return tp_cli_finish(TP_EXIT_OK);
        case ':': return usage_error("missing value for option", argv[optind - 1]);
        default:
            if (optopt > 0 && optopt < 256) {
                char name[3] = {'-', (char)optopt, '\0'};
                return usage_error("unknown option", name);
            }
            if (optopt >= 256)
                return usage_error("option takes no value:", argv[optind - 1]);
            return usage_error("unknown option", argv[optind - 1]);
        }
    }
    if (optind >= argc)
        return usage_error("missing SOURCE", "");
    if (!o->out)
        return usage_error("missing -o NAME.tpt", "");
    o->sources = (const char**)(argv + optind);
    o->source_count = argc - optind;
    if (o->threads == 0) {
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        o->threads = n > 0 ? (int)(n > 1024 ? 1024 : n) : 1;
    }
    return -1;
}

/* The builder's user: its emit and parallel_for callbacks both get it. */
typedef struct emit_ctx {
    tp_store_writer* writer;
    int64_t nodes;
    int threads;
} emit_ctx;

/* ---- parallel_for over pthreads: the caller's thread and threads - 1 more ---- */
typedef struct pool_job {
    void (*fn)(int i, void* ctx);
    void* ctx;
    int count;
    atomic_int next;
} pool_job;

static void* pool_worker(void* arg)
{
    pool_job* j = arg;
    for (int i; (i = atomic_fetch_add(&j->next, 1)) < j->count;)
        j->fn(i, j->ctx);
    return NULL;
}

static void parallel_for(int count, void (*fn)(int i, void* ctx), void* ctx, void* user)
{
    const int threads = ((const emit_ctx*)user)->threads;
    pool_job j = {fn, ctx, count, 0};
    int extra = threads - 1 < count - 1 ? threads - 1 : count - 1;
    pthread_t t[64];
    if (extra > 64)
        extra = 64;
    int started = 0;
    for (; started < extra; started++)
        if (pthread_create(&t[started], NULL, pool_worker, &j) != 0)
            break;
    pool_worker(&j);
    for (int k = 0; k < started; k++)
        pthread_join(t[k], NULL);
}

/* ---- progress on stderr: a bar on a terminal, else a line every 10% ---- */
typedef struct progress {
    int on, tty, last_decile;
    double t0, last_draw;
    const char* what;
} progress;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static void progress_start(progress* p, int on, const char* what)
{
    p->on = on;
    p->tty = isatty(2);
    p->last_decile = 0;
    p->t0 = now_s();
    p->last_draw = 0;
    p->what = what;
}

static void progress_update(progress* p, double done, double total, double samples)
{
    if (!p->on || total <= 0)
        return;
    const double t = now_s(), el = t - p->t0, f = done / total;
    const double rate = el > 0 ? samples / el : 0, eta = f > 0 ? el * (1 - f) / f : 0;
    if (p->tty) {
        if (t - p->last_draw < 0.2 && done < total)
            return;
        p->last_draw = t;
        char bar[31];
        int fill = (int)(f * 30);
        for (int i = 0; i < 30; i++)
            bar[i] = i < fill ? '#' : '.';
        bar[30] = 0;
        fprintf(stderr, "\r%s [%s] %3.0f%%  %.1f Msamples/s  ETA %.0f s   ", p->what, bar,
                100 * f, rate / 1e6, eta);
        if (done >= total)
            fputc('\n', stderr);
    } else {
        int decile = (int)(f * 10);
        if (decile <= p->last_decile && done < total)
            return;
        p->last_decile = decile;
        fprintf(stderr, "terrapatch build: %s %3.0f%% (%.1f Msamples/s, ETA %.0f s)\n", p->what,
                100 * f, rate / 1e6, eta);
    }
}

/* ---- the build ---- */
#define STEP_CANDIDATES 11 /* 2^-p m, p = 0 .. 10 */


static int emit_node(int64_t node, const tp_node_meta* meta, const int32_t* q, void* user,
                     tp_error* err)
{
    emit_ctx* e = user;
    if (tp_interrupted()) {
        snprintf(err->message, sizeof err->message, "interrupted");
        return 1;
    }
    if (tp_store_writer_add_node(e->writer, node, meta, q, err) != TP_OK)
        return 1;
    e->nodes++;
    return 0;
}

static uint64_t file_size(const char* path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (uint64_t)st.st_size : 0;
}

static int fail_line(const char* msg)
{
    fprintf(stderr, "terrapatch: %s\n", msg);
    return TP_EXIT_FAILURE;
}

int tp_cli_build(int argc, char** argv)
{
    build_options o;
    int rc = parse_options(argc, argv, &o);
    if (rc >= 0)
        return rc;
    const double t0 = now_s();
    tp_error err = {0};
    if (tp_output_check(o.out, &err) != TP_OK)
        return fail_line(err.message);
    for (int i = 0; i < o.source_count; i++)
        if (!strcmp(o.sources[i], o.out))
            return fprintf(stderr, "terrapatch: %s: the output would replace a source\n", o.out),
                   TP_EXIT_FAILURE;
    if (o.json && strcmp(o.json, "-") && !tp_atomic_check_dir(o.json))
        return TP_EXIT_FAILURE;

    tp_mosaic* m = NULL;
    tp_mosaic_options mo = {.crs = o.crs, .resampling = o.resampling, .memory_mb = o.memory_mb};
    if (tp_mosaic_open(o.sources, (size_t)o.source_count, &mo, &m, &err) != TP_OK)
        return fail_line(err.message);
    tp_mosaic_info mi;
    tp_mosaic_get_info(m, &mi);
    if (!o.quiet && mi.notes[0]) {
        const char* s = mi.notes;
        while (*s) {
            const char* e = strchr(s, '\n');
            int len = e ? (int)(e - s) : (int)strlen(s);
            fprintf(stderr, "terrapatch build: %.*s\n", len, s);
            s += len + (e ? 1 : 0);
        }
    }

    tp_tree_geometry g;
    if (tp_tree_geometry_init(mi.width, mi.height, o.patch_size, &g, &err) != TP_OK) {
        tp_mosaic_close(m);
        return fail_line(err.message);
    }
    const int ps = 1 << g.n, band_rows = ps + 1;
    const double samples = (double)mi.width * mi.height;
    float* rows = malloc((size_t)band_rows * mi.width * sizeof *rows);
    int32_t* q = malloc((size_t)band_rows * g.width * sizeof *q);
    if (!rows || !q) {
        free(rows), free(q), tp_mosaic_close(m);
        return fail_line("build: out of memory for one band of rows");
    }

    /* Pass 1: range, valid samples, and each candidate step's quantisation error. */
    double lo = INFINITY, hi = -INFINITY, qerr[STEP_CANDIDATES] = {0};
    size_t valid = 0;
    progress pr;
    progress_start(&pr, !o.quiet, "range");
    tp_status st = TP_OK;
    for (int y = 0; y < mi.height && st == TP_OK; y += band_rows) {
        int n = mi.height - y < band_rows ? mi.height - y : band_rows;
        st = tp_mosaic_read_rows(m, y, n, rows, (size_t)n * mi.width, &err);
        if (st != TP_OK)
            break;
        const size_t count = (size_t)n * mi.width;
        for (size_t i = 0; i < count; i++) {
            float v = rows[i];
            if (isnan(v))
                continue;
            valid++;
            lo = v < lo ? v : lo;
            hi = v > hi ? v : hi;
            for (int p = 0; p < STEP_CANDIDATES; p++) {
                double s = ldexp(1.0, -p), e = fabs(floor(v / s + 0.5) * s - v);
                qerr[p] = e > qerr[p] ? e : qerr[p];
            }
        }
        progress_update(&pr, y + n, mi.height, (double)(y + n) * mi.width);
    }
    if (st == TP_OK && valid == 0) {
        snprintf(err.message, sizeof err.message, "%s: no valid height in the %dx%d grid",
                 o.sources[0], mi.width, mi.height);
        st = TP_ERR_BAD_DATA;
    }
    if (st != TP_OK) {
        free(rows), free(q), tp_mosaic_close(m);
        return fail_line(err.message);
    }

    /* One global step: 1 m for integer sources, else the finest 2^-p m (p <= 10) whose
     * quantised range fits 65534 steps (coarser powers of two beyond 65534 m). */
    double step = 1;
    int cand = 0;
    if (!mi.integer_sources) {
        for (int p = 10; p >= 0; p--) {
            double s = ldexp(1.0, -p);
            if (floor(hi / s + 0.5) - floor(lo / s + 0.5) <= 65534) {
                step = s, cand = p;
                break;
            }
        }
    }
    while (floor(hi / step + 0.5) - floor(lo / step + 0.5) > 65534)
        step *= 2, cand = -1;
    const double quant_err = cand >= 0 ? qerr[cand] : step / 2;
    const double range_steps = floor(hi / step + 0.5) - floor(lo / step + 0.5);
    const double err_unit = tp_tree_err_unit_steps(range_steps);

    tp_store_header h = {0};
    h.geometry = g;
    memcpy(h.geotransform, mi.geotransform, sizeof h.geotransform);
    h.height_step_m = step;
    h.quant_max_error_m = quant_err;
    h.err_unit_steps = err_unit;
    h.valid_samples = valid;
    h.nodata_samples = (size_t)mi.width * mi.height - valid;
    h.crs_wkt = mi.crs_wkt;
    /* notes: the sources, then the mosaic's own */
    size_t notes_cap = strlen(mi.notes) + 64;
    for (int i = 0; i < o.source_count; i++)
        notes_cap += strlen(o.sources[i]) + 16;
    char* notes = malloc(notes_cap);
    if (!notes) {
        free(rows), free(q), tp_mosaic_close(m);
        return fail_line("build: out of memory");
    }
    size_t at = 0;
    for (int i = 0; i < o.source_count; i++)
        at += (size_t)snprintf(notes + at, notes_cap - at, "source: %s\n", o.sources[i]);
    snprintf(notes + at, notes_cap - at, "%s%svoids are not filled", mi.notes,
             mi.notes[0] ? "\n" : "");
    h.notes = notes;

    tp_store_writer* w = NULL;
    emit_ctx ec = {.threads = o.threads};
    tp_tree_builder* b = NULL;
    st = tp_store_writer_begin(o.out, &h, &w, &err);
    if (st == TP_OK) {
        ec.writer = w;
        tp_tree_builder_desc bd = {0};
        bd.geometry = g;
        bd.err_unit_steps = err_unit;
        bd.emit = emit_node;
        bd.parallel_for = parallel_for;
        bd.user = &ec;
        st = tp_tree_builder_create(&bd, &b, &err);
    }

    /* Pass 2: band r = fitted rows r*ps .. (r+1)*ps; the first row is the last one of the band
     * before (kept in q), so each source row is read once. */
    progress_start(&pr, !o.quiet, "build");
    for (int r = 0; r < g.rows && st == TP_OK; r++) {
        const int y_first = r * ps;
        const int skip = r > 0 ? 1 : 0;
        if (skip)
            memcpy(q, q + (size_t)ps * g.width, (size_t)g.width * sizeof *q);
        const int y0 = y_first + skip, y1 = y_first + ps; /* rows to fill, inclusive */
        int read_to = y1 < mi.height - 1 ? y1 : mi.height - 1;
        int nread = read_to >= y0 ? read_to - y0 + 1 : 0;
        if (nread > 0)
            st = tp_mosaic_read_rows(m, y0, nread, rows, (size_t)nread * mi.width, &err);
        if (st != TP_OK)
            break;
        for (int y = y0; y <= y1; y++) {
            int32_t* dst = q + (size_t)(y - y_first) * g.width;
            if (y >= mi.height) {
                for (int x = 0; x < g.width; x++)
                    dst[x] = INT32_MIN;
                continue;
            }
            const float* src = rows + (size_t)(y - y0) * mi.width;
            for (int x = 0; x < mi.width; x++)
                dst[x] = isnan(src[x]) ? INT32_MIN : (int32_t)floor(src[x] / step + 0.5);
            for (int x = mi.width; x < g.width; x++)
                dst[x] = INT32_MIN;
        }
        if (tp_interrupted()) {
            st = TP_ERR_IO;
            snprintf(err.message, sizeof err.message, "%s: interrupted: not written", o.out);
            break;
        }
        st = tp_tree_builder_add_band(b, r, q, (size_t)band_rows * g.width, &err);
        progress_update(&pr, r + 1, g.rows, (double)(read_to + 1) * mi.width);
    }
    tp_tree_builder_destroy(b);
    free(rows);
    free(q);
    tp_mosaic_close(m);
    if (st == TP_OK)
        st = tp_store_writer_commit(w, &err);
    else
        tp_store_writer_abort(w);
    free(notes);
    if (st != TP_OK) {
        if (tp_interrupted())
            return tp_cli_interrupted();
        return fail_line(err.message);
    }

    const double seconds = now_s() - t0;
    const uint64_t bytes = file_size(o.out);
    const double rss_mb = tp_memory_peak_rss() / (1024.0 * 1024.0);
    if (!o.quiet)
        fprintf(stderr,
                "terrapatch build: %s: %dx%d samples, %lld nodes, %.3f bytes/sample, step %g m, "
                "%.1f s, peak RSS %.0f MB\n",
                o.out, mi.width, mi.height, (long long)ec.nodes, bytes / samples, step, seconds,
                rss_mb);
    if (o.json) {
        tp_atomic_file af;
        FILE* f = stdout;
        if (strcmp(o.json, "-")) {
            if (!tp_atomic_open(&af, o.json))
                return TP_EXIT_FAILURE;
            f = af.f;
        }
        tp_json j;
        tp_json_init(&j, f);
        tp_json_object_begin(&j);
        tp_json_key(&j, "output"), tp_json_string(&j, o.out);
        tp_json_key(&j, "sources"), tp_json_int(&j, o.source_count);
        tp_json_key(&j, "width"), tp_json_int(&j, mi.width);
        tp_json_key(&j, "height"), tp_json_int(&j, mi.height);
        tp_json_key(&j, "samples"), tp_json_number(&j, samples);
        tp_json_key(&j, "valid_samples"), tp_json_size(&j, valid);
        tp_json_key(&j, "patch_size"), tp_json_int(&j, ps + 1);
        tp_json_key(&j, "nodes"), tp_json_int(&j, ec.nodes);
        tp_json_key(&j, "bytes"), tp_json_number(&j, (double)bytes);
        tp_json_key(&j, "bytes_per_sample"), tp_json_number(&j, bytes / samples);
        tp_json_key(&j, "step"), tp_json_number(&j, step);
        tp_json_key(&j, "quant_max_error_m"), tp_json_number(&j, quant_err);
        tp_json_key(&j, "min_m"), tp_json_number(&j, lo);
        tp_json_key(&j, "max_m"), tp_json_number(&j, hi);
        tp_json_key(&j, "crs"), tp_json_string(&j, mi.crs_name);
        tp_json_key(&j, "warped"), tp_json_bool(&j, mi.warped);
        tp_json_key(&j, "threads"), tp_json_int(&j, o.threads);
        tp_json_key(&j, "memory_mb"), tp_json_int(&j, o.memory_mb);
        tp_json_key(&j, "seconds"), tp_json_number(&j, seconds);
        tp_json_key(&j, "rss_peak_mb"), tp_json_number(&j, rss_mb);
        tp_json_object_end(&j);
        fputc('\n', f);
        if (f != stdout && !tp_atomic_commit(&af))
            return TP_EXIT_FAILURE;
    }
    return tp_cli_finish(TP_EXIT_OK);
}
