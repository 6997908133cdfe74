/*
 * store_build.c - a terrain store from DEM sources (store_build.h), for `terrapatch build`
 * (commands/cmd_build.c) and the store cache (store_cache.c) alike: sources mosaicked and put on
 * the render grid (tp_mosaic, read in bands of rows), quantised with one global step, built into
 * the node hierarchy band by band (tp_tree_builder) and written as a terrain store
 * (tp_store_writer), atomically. Memory follows the band, not the map.
 *
 * The grid is read once when its height range is bounded beforehand (sources' statistics, or
 * the few files a VRT repeats: tp_mosaic_info.has_range): the range gives the step, which the
 * store's header (written first) holds; the quantisation error and the valid samples are
 * counted while building and given to the store at commit (tp_store_writer_set_totals). A bound
 * that does not hold (a VRT that scales its sources) costs one more build. Without a bound, a
 * range pass reads the grid first, and holds it for the build pass when it fits (build_rows.h).
 * docs/PERFORMANCE.md "Building stores" and "First picture of a new DEM" have the profiles.
 */
#include "store_build.h"
#include "build_part.h"
#include "build_plan.h"
#include "build_rows.h"

#include "cli.h"
#include "clock.h"
#include "memory.h"
#include "output_check.h"
#include "progress.h"

#include "tp_core.h"
#include "tp_io.h"

#include <errno.h>
#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

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

void tp_build_options_init(tp_build_options* o)
{
    *o = (tp_build_options){0};
    o->patch_size = 65;
    o->memory_mb = 1024;
    o->fill_max = TP_FILL_MAX_ANY;
}

/* ---- the build ---- */

/* Each node with its filled bits (TP_NODE_HAS_FILLED): the store marks filled void samples. */
static int emit_node(int64_t node, const tp_node_meta* meta, const int32_t* q, const uint16_t* mask,
                     const uint16_t* filled, void* user, tp_error* err)
{
    emit_ctx* e = user;
    if (tp_interrupted()) {
        snprintf(err->message, sizeof err->message, "interrupted");
        return 1;
    }
    if (tp_store_writer_add_node_filled(e->writer, node, meta, q, mask, filled, err) != TP_OK)
        return 1;
    e->nodes++;
    return 0;
}

/* One global step: 1 m for integral heights, else the finest 2^-p m (p <= finest_p) whose
 * quantised range fits 65534 steps (coarser powers of two beyond 65534 m). Integral: the
 * render grid's values, not the sources' type: a warped integer DEM (every geographic SRTM or
 * DTED tile) is not integral after bilinear resampling, and rounding it to 1 m moved every
 * height by up to 0.5 m. */
static double choose_step(double lo, double hi, int integral, int finest_p)
{
    double step = 1;
    if (!integral)
        for (int p = finest_p; p >= 0; p--) {
            double s = ldexp(1.0, -p);
            if (floor(hi / s + 0.5) - floor(lo / s + 0.5) <= 65534) {
                step = s;
                break;
            }
        }
    while (floor(hi / step + 0.5) - floor(lo / step + 0.5) > 65534)
        step *= 2;
    return step;
}

/* The finest step for heights resampled from whole metres: 1/16 m (a quantisation error of at
 * most 3.1 cm, a thirtieth of the metre the sources were rounded to); finer costs bytes for
 * digits the sources never had (docs/store.md, "Height step"). */
#define WARPED_INTEGER_FINEST_P 4
#define FINEST_P 10

/* The build pass: in, what it reads and how; out, what it saw. */
typedef struct build_pass {
    const tp_build_options* o;
    tp_mosaic* m;
    tp_build_rows* br; /* the rows, from the mosaic or held by the range pass */
    const tp_mosaic_info* mi;
    const tp_tree_geometry* g;
    float* rows;    /* band_rows * width */
    int32_t* q;     /* band_rows * g->width */
    uint8_t* frows; /* band_rows * width: filled flags as read; NULL when voids are not filled */
    uint8_t* fq;    /* band_rows * g->width: the band's filled flags */
    double step;
    int bounded; /* lo .. hi is a bound given before reading: check it */
    double lo, hi;
    int quiet, threads;
    const char* out;
    const char* source; /* the first, for messages */
    /* a part (build --part): its record (NULL: the whole grid), its first leaf row */
    const tp_build_part_record* rec;
    int band0;
    /* out */
    int outside; /* a height outside the bound: nothing written, build again */
    size_t valid;
    size_t filled, first_valid, first_filled; /* a part's counts (its record's) */
    double quant_err, seen_lo, seen_hi;
    int64_t nodes;
} build_pass;

/* floor(x + 0.5) for |x| < 2^31 without a libm call (the loop then vectorises) */
static inline int32_t round_half_up(double x)
{
    double y = x + 0.5;
    int32_t t = (int32_t)y;
    return t - (y < (double)t);
}

/* Quantises one row of the band (NaN: not drawn) and accumulates what the pass sees. */
static void quantise_row(const float* src, int width, double step, int32_t* dst, size_t* valid,
                         double* qerr, float* lo, float* hi)
{
    const double inv = 1.0 / step; /* a power of two: exact */
    size_t n = 0;
    double e_max = *qerr;
    float l = *lo, h = *hi;
    for (int x = 0; x < width; x++) {
        float v = src[x];
        int drawn = v == v;
        double t = drawn ? v * inv : 0;
        int32_t qv = round_half_up(t);
        double e = fabs(qv * step - (drawn ? v : 0));
        e_max = e > e_max ? e : e_max;
        dst[x] = drawn ? qv : INT32_MIN;
        n += drawn;
        l = v < l ? v : l;
        h = v > h ? v : h;
    }
    *valid += n, *qerr = e_max, *lo = l, *hi = h;
}

/* The store's notes: a part's record first (with the counts so far), then the build's. */
static char* notes_for(const tp_build_options* o, const char* mosaic_notes,
                       const tp_build_part_record* rec, size_t filled)
{
    char* notes = tp_build_notes(o, mosaic_notes, filled);
    if (!notes || !rec)
        return notes;
    char* with = tp_build_part_notes(rec, notes);
    free(notes);
    return with;
}

static char* pass_notes(const build_pass* p)
{
    if (!p->rec)
        return notes_for(p->o, p->mi->notes, NULL, tp_mosaic_filled_samples(p->m));
    tp_build_part_record r = *p->rec;
    r.filled = p->filled, r.first_valid = p->first_valid, r.first_filled = p->first_filled;
    return notes_for(p->o, p->mi->notes, &r, p->filled);
}

/* Band rows y0 .. y1 of the grid (read into p->rows from y0) quantised into the band's q and
 * fq (row y_first first); a part counts its filled samples and its first row's. */
static void band_rows_in(build_pass* p, int y0, int y1, int y_first, size_t* valid,
                         double* qerr, float* lo, float* hi)
{
    const tp_tree_geometry* g = p->g;
    const tp_mosaic_info* mi = p->mi;
    const int first_row = p->band0 > 0 ? p->band0 << g->n : -1; /* shared with the part above */
    for (int y = y0; y <= y1; y++) {
        int32_t* dst = p->q + (size_t)(y - y_first) * g->width;
        int x = 0;
        if (y < mi->height) {
            const size_t before = *valid;
            quantise_row(p->rows + (size_t)(y - y0) * mi->width, mi->width, p->step, dst, valid,
                         qerr, lo, hi);
            x = mi->width;
            if (y == first_row)
                p->first_valid = *valid - before;
        }
        for (; x < g->width; x++)
            dst[x] = INT32_MIN;
        if (p->fq) {
            uint8_t* fd = p->fq + (size_t)(y - y_first) * g->width;
            memset(fd, 0, (size_t)g->width);
            if (y < mi->height) {
                memcpy(fd, p->frows + (size_t)(y - y0) * mi->width, (size_t)mi->width);
                size_t f = 0;
                for (int i = 0; i < mi->width; i++)
                    f += fd[i] != 0;
                p->filled += f;
                if (y == first_row)
                    p->first_filled = f;
            }
        }
    }
}

static tp_status run_build_pass(build_pass* p, const tp_store_header* h, tp_error* err)
{
    const tp_tree_geometry* g = p->g;
    const tp_mosaic_info* mi = p->mi;
    const int ps = 1 << g->n, band_rows = ps + 1;
    tp_store_writer* w = NULL;
    emit_ctx ec = {.threads = p->threads};
    tp_tree_builder* b = NULL;
    tp_status st = tp_store_writer_begin(p->out, h, &w, err);
    if (st == TP_OK) {
        ec.writer = w;
        tp_tree_builder_desc bd = {0};
        bd.geometry = *g;
        bd.err_unit_steps = h->err_unit_steps;
        bd.emit_filled = emit_node;
        bd.parallel_for = parallel_for;
        bd.user = &ec;
        st = tp_tree_builder_create(&bd, &b, err);
    }
    float lo = INFINITY, hi = -INFINITY;
    double qerr = 0;
    size_t valid = 0;
    int32_t* q = p->q;
    tp_progress pr;
    tp_progress_start(&pr, !p->quiet, "build", "build");
    /* Band r = fitted rows r*ps .. (r+1)*ps (of a part: from its first row, band0*ps); the
     * first row is the last one of the band before (kept in q), so each source row is read
     * once. */
    p->filled = p->first_valid = p->first_filled = 0;
    for (int r = 0; r < g->rows && st == TP_OK; r++) {
        const int y_first = (p->band0 + r) * ps;
        const int skip = r > 0 ? 1 : 0;
        if (skip)
            memcpy(q, q + (size_t)ps * g->width, (size_t)g->width * sizeof *q);
        if (skip && p->fq)
            memcpy(p->fq, p->fq + (size_t)ps * g->width, (size_t)g->width);
        const int y1 = y_first + ps; /* rows to fill y0 .. y1, inclusive */
        int y0, nread;
        tp_build_rows_band(p->br, p->band0 + r, &y0, &nread);
        if (r == 0 && p->band0 > 0) /* a part's first row: the part above's last */
            y0--, nread++;
        const int read_to = nread > 0 ? y0 + nread - 1 : mi->height - 1;
        if (nread > 0)
            st = tp_build_rows_read(p->br, y0, nread, p->rows, p->frows, err);
        if (st != TP_OK)
            break;
        band_rows_in(p, y0, y1, y_first, &valid, &qerr, &lo, &hi);
        /* the bound may come from rounded statistics: a step of slack, if the range still fits */
        if (p->bounded && (lo < p->lo - p->step || hi > p->hi + p->step ||
                           floor(hi / p->step + 0.5) - floor(lo / p->step + 0.5) > 65534)) {
            p->outside = 1;
            break;
        }
        if (tp_interrupted()) {
            st = TP_ERR_IO;
            snprintf(err->message, sizeof err->message, "%s: interrupted: not written", p->out);
            break;
        }
        st = tp_tree_builder_add_band_filled(b, r, q, p->fq, (size_t)band_rows * g->width, err);
        tp_progress_update(&pr, r + 1, g->rows, (double)(read_to + 1 - p->band0 * ps) * mi->width);
    }
    tp_tree_builder_destroy(b);
    if (st == TP_OK && !p->outside && valid == 0 && !p->rec) /* a bound, none in the grid */
        st = tp_error_set(err, TP_ERR_BAD_DATA, "%s: no valid height in the %dx%d grid", p->source,
                          mi->width, mi->height);
    if (st == TP_OK && !p->outside) {
        tp_store_writer_set_totals(w, qerr, valid, (size_t)g->src_width * g->src_height - valid);
        char* notes = pass_notes(p);
        st = notes ? tp_store_writer_set_notes(w, notes, err)
                   : tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "build: out of memory");
        free(notes);
        if (st == TP_OK)
            st = tp_store_writer_commit(w, err);
        else
            tp_store_writer_abort(w);
    } else {
        tp_store_writer_abort(w);
    }
    p->valid = valid;
    p->quant_err = qerr;
    p->seen_lo = lo, p->seen_hi = hi;
    p->nodes = ec.nodes;
    return st;
}

static uint64_t file_size(const char* path)
{
    struct stat st;
    return stat(path, &st) == 0 ? (uint64_t)st.st_size : 0;
}

static int fail_line(const char* msg)
{
    tp_cli_error("%s", msg);
    return TP_EXIT_FAILURE;
}

/* o's defaults filled in (threads), the output checked, --memory fitted to what the process
 * may use, no source overwritten: TP_EXIT_OK, else the exit code after one line. */
static int prepare(tp_build_options* o)
{
    if (o->threads <= 0) {
        long n = sysconf(_SC_NPROCESSORS_ONLN);
        o->threads = n > 0 ? (int)(n > 1024 ? 1024 : n) : 1;
    }
    int rc;
    if ((rc = tp_cli_output_check("build", "-o", o->out, TP_OUTPUT_STORE)) != TP_EXIT_OK)
        return rc;
    { /* --memory (the whole process's budget) within what it may still use */
        uint64_t b =
            tp_memory_fit_budget("build", o->sources[0], "--memory", 0,
                                 (uint64_t)o->memory_mb << 20, (uint64_t)BUILD_MIN_MEMORY_MB << 20);
        if (!b)
            return TP_EXIT_FAILURE;
        o->memory_mb = (int)(b >> 20);
    }
    for (int i = 0; i < o->source_count; i++)
        if (!strcmp(o->sources[i], o->out))
            return tp_cli_error("%s: the output would replace a source", o->out), TP_EXIT_FAILURE;
    return TP_EXIT_OK;
}

/* The sources opened as one mosaic on the render grid (*m, *mi), its notes printed unless
 * quiet; NULL after one line when they cannot be read or cover too little of their mosaic. */
static tp_mosaic* open_sources(const tp_build_options* o, int coarsen, tp_mosaic_info* out)
{
    tp_error err = {0};
    tp_mosaic* m = NULL;
    tp_mosaic_options mo = {.crs = o->crs,
                            .resampling = o->resampling,
                            .memory_mb = o->memory_mb,
                            .fill_max = o->fill_max,
                            .fill_from = o->fill_from,
                            .z_unit = o->z_unit,
                            .range_given = o->height_range_given,
                            .range_min_m = o->height_range_m[0],
                            .range_max_m = o->height_range_m[1],
                            .coarsen = coarsen};
    if (tp_mosaic_open(o->sources, (size_t)o->source_count, &mo, &m, &err) != TP_OK)
        return fail_line(err.message), NULL;
    tp_mosaic_get_info(m, out);
    const tp_mosaic_info mi = *out;
    if (!o->quiet && mi.notes[0]) {
        const char* s = mi.notes;
        while (*s) {
            const char* e = strchr(s, '\n');
            int len = e ? (int)(e - s) : (int)strlen(s);
            tp_cli_note("%.*s", len, s);
            s += len + (e ? 1 : 0);
        }
    }
    /* Sources far apart leave most of their mosaic empty: minutes of work on nodata, and a
     * store mostly of gaps. Almost always a wrong source; --allow-gaps when it is meant. */
    if (mi.covered_share < TP_BUILD_MIN_COVERED && !o->allow_gaps) {
        tp_cli_error("the %d sources cover about %.1f%% of their mosaic's "
                     "%dx%d samples (%.1f%% would be gaps, nodata): check that they belong "
                     "together, or add --allow-gaps",
                     mi.source_count, 100.0 * mi.covered_share, mi.width, mi.height,
                     100.0 * (1.0 - mi.covered_share));
        tp_mosaic_close(m);
        return NULL;
    }
    return m;
}

/* What the passes of a build saw. */
typedef struct build_totals {
    double step;
    size_t valid;
    double quant_err, seen_lo, seen_hi;
    int64_t nodes;
} build_totals;

/* The store written from m in bands of rows: the height range decides the step (written first,
 * in the header): a bound the mosaic knows without reading the grid (sources' statistics, or
 * the few files a VRT repeats), or else a first pass over the grid. The quantisation error and
 * the valid samples are counted while building and given to the store at commit. A bound that
 * does not hold (a VRT that scales its sources) costs one more build. err's message on failure
 * (not printed). */
static tp_status build_passes(const tp_build_options* o, tp_mosaic* m, const tp_mosaic_info* mip,
                              const tp_tree_geometry* gp, const tp_build_part_record* rec,
                              build_totals* t, tp_error* errp)
{
    const tp_mosaic_info mi = *mip;
    const tp_tree_geometry g = *gp;
    tp_tree_geometry sg = g; /* what is built: the grid, or a part's strip of it */
    const int y_strip = rec ? tp_build_part_strip(&g, &rec->part, &sg) : 0;
    tp_error err = {0};
    const int band_rows = (1 << g.n) + 1;
    float* rows = malloc((size_t)band_rows * mi.width * sizeof *rows);
    int32_t* q = malloc((size_t)band_rows * g.width * sizeof *q);
    uint8_t* frows = o->fill_max > 0 ? malloc((size_t)band_rows * mi.width) : NULL;
    uint8_t* fq = o->fill_max > 0 ? malloc((size_t)band_rows * g.width) : NULL;
    if (!rows || !q || (o->fill_max > 0 && (!frows || !fq))) {
        free(rows), free(q), free(frows), free(fq);
        snprintf(errp->message, sizeof errp->message, "build: out of memory for one band of rows");
        return TP_ERR_OUT_OF_MEMORY;
    }

    /* the range pass holds the grid for the build pass within a quarter of the budget and
     * what the band, the builder and the writer leave of its three quarters */
    tp_build_rows br = {.m = m,
                        .width = mi.width,
                        .height = mi.height,
                        .ps = 1 << g.n,
                        .fill = o->fill_max > 0};
    const double budget = (double)o->memory_mb * 1048576.0;
    const double left = 0.75 * budget - tp_build_memory_bytes(&g, mi.width, o->fill_max);
    const size_t hold_bytes = (size_t)fmax(0, fmin(budget / 4, left));
    double lo = mi.min_m, hi = mi.max_m;
    int bounded = mi.has_range;
    size_t valid = 0;
    double quant_err = 0, seen_lo = INFINITY, seen_hi = -INFINITY;
    double step = 1, err_unit = 1;
    int integral = 1; /* every height a whole metre, where the range pass looked */
    tp_status st = TP_OK;
    int64_t nodes = 0;
    char* notes = notes_for(o, mi.notes, rec, 0);
    if (!notes) {
        free(rows), free(q), free(frows), free(fq);
        snprintf(errp->message, sizeof errp->message, "build: out of memory");
        return TP_ERR_OUT_OF_MEMORY;
    }
    for (int attempt = 0;; attempt++) {
        if (!bounded) {
            tp_build_range range;
            st = tp_build_rows_range(&br, g.rows, hold_bytes, o->quiet, rows, frows, &range,
                                     &err);
            lo = range.lo, hi = range.hi, valid = range.valid, integral = range.integral;
            if (st == TP_OK && valid == 0) {
                snprintf(err.message, sizeof err.message, "%s: no valid height in the %dx%d grid",
                         o->sources[0], mi.width, mi.height);
                st = TP_ERR_BAD_DATA;
            }
            if (st != TP_OK)
                break;
        }
        step = choose_step(lo, hi, mi.integer_sources && !mi.warped && integral,
                           mi.integer_sources ? WARPED_INTEGER_FINEST_P : FINEST_P);
        if (o->height_step_m > 0) {
            step = o->height_step_m;
            if (floor(hi / step + 0.5) - floor(lo / step + 0.5) > 65534) {
                snprintf(err.message, sizeof err.message,
                         "--height-step %g m is too fine for heights %g .. %g m (at most "
                         "65534 steps: %g m or more)",
                         step, lo, hi, (hi - lo) / 65534 * 1.0001);
                st = TP_ERR_INVALID_ARG;
                break;
            }
        }
        const double range_steps = floor(hi / step + 0.5) - floor(lo / step + 0.5);
        err_unit = tp_tree_err_unit_steps(range_steps);

        tp_store_header h = {0};
        h.geometry = sg;
        memcpy(h.geotransform, mi.geotransform, sizeof h.geotransform);
        h.geotransform[3] += y_strip * h.geotransform[5];
        h.height_step_m = step;
        h.quant_max_error_m = step / 2; /* the totals replace these at commit */
        h.err_unit_steps = err_unit;
        h.valid_samples = 0;
        h.nodata_samples = (size_t)sg.src_width * sg.src_height;
        h.crs_wkt = mi.crs_wkt;
        h.notes = notes;
        build_pass bp = {.o = o,
                         .m = m,
                         .br = &br,
                         .mi = &mi,
                         .g = &sg,
                         .rows = rows,
                         .q = q,
                         .frows = frows,
                         .fq = fq,
                         .step = step,
                         .bounded = bounded,
                         .lo = lo,
                         .hi = hi,
                         .quiet = o->quiet,
                         .threads = o->threads,
                         .out = o->out,
                         .source = o->sources[0],
                         .rec = rec,
                         .band0 = rec ? rec->part.band0 : 0};
        st = run_build_pass(&bp, &h, &err);
        if (st == TP_OK && bp.outside && o->height_range_given) {
            snprintf(err.message, sizeof err.message,
                     "%s: heights %g .. %g m outside --height-range %g,%g: give a range that "
                     "holds every height",
                     o->sources[0], bp.seen_lo, bp.seen_hi, lo, hi);
            st = TP_ERR_BAD_DATA;
        } else if (st == TP_OK && bp.outside) {
            /* a VRT that scales its sources: the bound did not hold; measure the range */
            if (!o->quiet)
                tp_cli_note("heights %g .. %g m outside the bound %g .. %g "
                            "m the sources gave: building again after a range pass",
                            bp.seen_lo, bp.seen_hi, lo, hi);
            bounded = 0;
            if (attempt == 0)
                continue;
            snprintf(err.message, sizeof err.message, "build: the heights changed between reads");
            st = TP_ERR_BAD_DATA;
        }
        valid = bp.valid;
        quant_err = bp.quant_err;
        seen_lo = bp.seen_lo, seen_hi = bp.seen_hi;
        nodes = bp.nodes;
        break;
    }
    tp_build_rows_release(&br);
    free(rows);
    free(q);
    free(frows);
    free(fq);
    free(notes);
    *t = (build_totals){.step = step,
                        .valid = valid,
                        .quant_err = quant_err,
                        .seen_lo = seen_lo,
                        .seen_hi = seen_hi,
                        .nodes = nodes};
    *errp = err;
    return st;
}

/* A part's record (o->part_index of o->part_count over g), its counts 0; 1, or 0 after one
 * line. */
static int part_record(const tp_build_options* o, const tp_mosaic_info* mi,
                       const tp_tree_geometry* g, tp_build_part_record* rec)
{
    tp_error err = {0};
    *rec = (tp_build_part_record){.width = mi->width, .height = mi->height, .patch = o->patch_size};
    if (!tp_build_part_plan(g, o->part_index, o->part_count, &rec->part, &err) ||
        !tp_build_part_key(o, &rec->key, &err))
        return fail_line(err.message), 0;
    if (!o->quiet)
        tp_cli_note("part %d/%d: leaf rows %d .. %d of %d (grid rows %d .. %d), split at scale %d",
                    o->part_index, o->part_count, rec->part.band0, rec->part.band1 - 1, g->rows,
                    rec->part.band0 * (o->patch_size - 1),
                    rec->part.band1 == g->rows ? mi->height - 1
                                               : rec->part.band1 * (o->patch_size - 1),
                    rec->part.split_scale);
    return 1;
}

int tp_store_build(const tp_build_options* options, tp_build_result* result)
{
    const double t0 = tp_clock_s();
    tp_error err = {0};
    tp_build_options oc = *options;
    tp_build_options* o = &oc;
    int rc = prepare(o);
    if (rc != TP_EXIT_OK)
        return rc;
    tp_mosaic_info mi;
    tp_mosaic* m = open_sources(o, 1, &mi);
    if (!m)
        return TP_EXIT_FAILURE;
    int coarsen = 1; /* a preview: the grid opened again, coarser */
    if (o->preview_max_samples > 0) {
        coarsen = tp_build_preview_coarsen(mi.width, mi.height, o->preview_max_samples);
        tp_mosaic_close(m);
        if (coarsen == 1) {
            if (result)
                *result = (tp_build_result){.width = mi.width, .height = mi.height, .coarsen = 1};
            return TP_EXIT_OK;
        }
        if (result) /* a failure from here on is the preview's own */
            *result = (tp_build_result){.coarsen = coarsen};
        if (!(m = open_sources(o, coarsen, &mi)))
            return TP_EXIT_FAILURE;
    }
    const int preview = coarsen > 1; /* its voids and failures are the caller's to judge */
    tp_tree_geometry g;
    if (!tp_build_plan_geometry(o, &mi, &g)) {
        tp_mosaic_close(m);
        return TP_EXIT_FAILURE;
    }
    const int ps = 1 << g.n;
    tp_build_part_record rec = {0}; /* a part: its strip of the grid */
    tp_tree_geometry sg = g;
    if (o->part_count > 0) {
        if (!part_record(o, &mi, &g, &rec)) {
            tp_mosaic_close(m);
            return TP_EXIT_FAILURE;
        }
        tp_build_part_strip(&g, &rec.part, &sg);
    }
    const double samples = (double)sg.src_width * sg.src_height;
    build_totals t;
    const tp_status st = build_passes(o, m, &mi, &g, o->part_count > 0 ? &rec : NULL, &t, &err);
    const size_t filled = tp_mosaic_filled_samples(m);
    tp_mosaic_voids mv;
    tp_mosaic_get_voids(m, &mv);
    tp_mosaic_close(m);
    if (st == TP_OK && mv.too_large_samples > 0 && !preview)
        tp_cli_warning("%zu void samples left unfilled: their voids need a "
                       "window of more than %d rows to be filled whole (an eighth of --memory %d); "
                       "give more --memory to fill them",
                       mv.too_large_samples, mv.max_void_rows, o->memory_mb);
    if (st != TP_OK) {
        if (tp_interrupted())
            return tp_cli_interrupted();
        return preview ? TP_EXIT_FAILURE : fail_line(err.message);
    }

    const double seconds = tp_clock_s() - t0;
    const uint64_t bytes = file_size(o->out);
    const double rss_mb = tp_memory_peak_rss() / (1024.0 * 1024.0);
    if (!o->quiet)
        tp_cli_note("%s: %dx%d samples%s, %lld nodes, %.3f bytes/sample, step %g m, "
                    "%.1f s, peak RSS %.0f MB",
                    o->out, sg.src_width, sg.src_height, o->part_count > 0 ? " (a part)" : "",
                    (long long)t.nodes, bytes / samples, t.step, seconds, rss_mb);

    if (result) {
        *result = (tp_build_result){.width = mi.width,
                                    .height = mi.height,
                                    .samples = samples,
                                    .valid_samples = t.valid,
                                    .patch_size = ps + 1,
                                    .nodes = t.nodes,
                                    .bytes = bytes,
                                    .step_m = t.step,
                                    .quant_max_error_m = t.quant_err,
                                    .min_m = t.seen_lo,
                                    .max_m = t.seen_hi,
                                    .warped = mi.warped,
                                    .threads = o->threads,
                                    .memory_mb = o->memory_mb,
                                    .filled_samples = filled,
                                    .filled_from_samples = mv.filled_from_samples,
                                    .void_samples_too_large = mv.too_large_samples,
                                    .seconds = seconds,
                                    .rss_peak_mb = rss_mb,
                                    .coarsen = coarsen};
        snprintf(result->crs_name, sizeof result->crs_name, "%s", mi.crs_name);
    }
    return TP_EXIT_OK;
}
