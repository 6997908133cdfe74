/* store_merge.c - the parts of a build in parts joined into one store (see store_merge.h). */
#include "store_merge.h"
#include "build_part.h"

#include "cli.h"
#include "clock.h"
#include "memory.h"
#include "output_check.h"
#include "progress.h"

#include "tp_core.h"
#include "tp_io.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

/* One part, opened and read. */
typedef struct part_in {
    const char* path;
    tp_store* s;
    tp_store_info info;
    tp_build_part_record rec;
    const char* rest; /* its notes after the record: the build's */
    const tp_node_meta* metas;
} part_in;

/* The merge: the parts by index, the whole tree, the nodes above the split. */
typedef struct merge {
    const tp_merge_options* o;
    part_in* in;       /* as given */
    part_in** part;    /* by index - 1 */
    int count;         /* N */
    tp_tree_geometry g;
    int split;         /* S */
    int64_t above;     /* nodes above the split: ids 0 .. above - 1 */
    size_t side2, mw, fw;
    int32_t* q;        /* above x side2 */
    uint16_t* mask;    /* above x mw */
    uint16_t* filled;  /* above x fw */
    tp_node_meta* metas;
} merge;

/* One line, but none after SIGINT/SIGTERM: tp_store_merge then says "interrupted". */
static int fail_line(const char* msg)
{
    if (!tp_interrupted())
        tp_cli_error("%s", msg);
    return 0;
}

/* Opens o->parts[i] into in: a store whose notes start with a part's record. 1, or 0 after one
 * line. */
static int open_part(const char* path, part_in* in)
{
    tp_error err = {0};
    in->path = path;
    if (tp_input_check(path, "a part of a build in parts (.tpt)", 0, &err) != TP_OK ||
        tp_store_open(path, &in->s, &err) != TP_OK)
        return fail_line(err.message);
    tp_store_get_info(in->s, &in->info);
    size_t count = 0;
    in->metas = tp_store_metas(in->s, &count);
    if (!tp_build_part_parse(in->info.header.notes, &in->rec, &in->rest))
        return tp_cli_error("%s: not a part of a build in parts (its notes do not start with "
                            "'part I/N'): make parts with terrapatch build --part I/N",
                            path),
               0;
    return 1;
}

/* part against the first: the same split, key, grid, step and CRS. 1, or 0 after one line. */
static int same_build(const part_in* p, const part_in* f)
{
    const tp_build_part_record *a = &p->rec, *b = &f->rec;
    const tp_store_header *ha = &p->info.header, *hb = &f->info.header;
    if (a->part.count != b->part.count)
        return tp_cli_error("%s is part %d/%d, but %s is part %d/%d: parts of two different "
                            "splits",
                            p->path, a->part.index, a->part.count, f->path, b->part.index,
                            b->part.count),
               0;
    if (a->key != b->key || a->width != b->width || a->height != b->height ||
        a->patch != b->patch)
        return tp_cli_error("%s: built from other sources or options than %s (part key %016llx, "
                            "not %016llx): give every part the same sources and options",
                            p->path, f->path, (unsigned long long)a->key,
                            (unsigned long long)b->key),
               0;
    if (ha->height_step_m != hb->height_step_m || ha->err_unit_steps != hb->err_unit_steps ||
        strcmp(ha->crs_wkt, hb->crs_wkt) || ha->geotransform[1] != hb->geotransform[1])
        return tp_cli_error("%s: height step %g m, but %s's is %g m, or another CRS: "
                            "a part whose heights left the sources' bound; build it again",
                            p->path, ha->height_step_m, f->path, hb->height_step_m),
               0;
    return 1;
}

/* The parts' records checked against each other and the split: each part once, none missing,
 * its strip the one its record names. 1, or 0 after one line. */
static int check_parts(merge* mg)
{
    part_in* first = &mg->in[0];
    mg->count = first->rec.part.count;
    tp_error err = {0};
    if (tp_tree_geometry_init(first->rec.width, first->rec.height, first->rec.patch, &mg->g,
                              &err) != TP_OK)
        return tp_cli_error("%s: %s", first->path, err.message), 0;
    mg->part = calloc((size_t)mg->count, sizeof *mg->part);
    if (!mg->part)
        return fail_line("merge: out of memory");
    for (int i = 0; i < mg->o->part_count; i++) {
        part_in* p = &mg->in[i];
        if (!same_build(p, first))
            return 0;
        part_in** slot = &mg->part[p->rec.part.index - 1];
        if (*slot)
            return tp_cli_error("%s and %s are both part %d/%d", (*slot)->path, p->path,
                                p->rec.part.index, mg->count),
                   0;
        *slot = p;
        tp_build_part want;
        tp_tree_geometry strip;
        const tp_tree_geometry* have = &p->info.header.geometry;
        if (tp_build_part_plan(&mg->g, p->rec.part.index, mg->count, &want, &err))
            tp_build_part_strip(&mg->g, &want, &strip);
        if (memcmp(&want, &p->rec.part, sizeof want) || have->n != strip.n ||
            have->src_width != strip.src_width || have->src_height != strip.src_height)
            return tp_cli_error("%s: its grid (%dx%d) is not part %d/%d of the %dx%d grid its "
                                "record names",
                                p->path, have->src_width, have->src_height, p->rec.part.index,
                                mg->count, mg->g.src_width, mg->g.src_height),
                   0;
    }
    char missing[512] = "";
    int gaps = 0;
    for (int i = 0; i < mg->count; i++)
        if (!mg->part[i] && ++gaps <= 16)
            snprintf(missing + strlen(missing), sizeof missing - strlen(missing), "%s%d/%d",
                     gaps > 1 ? ", " : "", i + 1, mg->count);
    if (gaps)
        return tp_cli_error("missing %s %s%s (of %d parts, %d given): give every part of the "
                            "build",
                            gaps > 1 ? "parts" : "part", missing, gaps > 16 ? ", ..." : "",
                            mg->count, mg->o->part_count),
               0;
    mg->split = first->rec.part.split_scale;
    return 1;
}

/* The part holding leaf row (band) r. */
static part_in* part_of_band(const merge* mg, int r)
{
    int lo = 0, hi = mg->count - 1;
    while (lo < hi) {
        const int mid = (lo + hi + 1) / 2;
        if (mg->part[mid]->rec.part.band0 <= r)
            lo = mid;
        else
            hi = mid - 1;
    }
    return mg->part[lo];
}

/* Node (s, c, r) of the whole tree in its part: the part and the node's id there. */
static int64_t part_node(const merge* mg, int s, int c, int r, part_in** p)
{
    *p = part_of_band(mg, r << s);
    return tp_tree_node_id(&(*p)->info.header.geometry, s, c, r - ((*p)->rec.part.band0 >> s));
}

/* Child k of above-node id: its samples, mask, filled bits and meta, from the nodes above or
 * read from its part (into block and kq). 1, or 0 with err. */
static int child_of(merge* mg, int64_t id, int k, uint16_t* block, int32_t* kq,
                    const int32_t** q, const uint16_t** mask, const uint16_t** filled,
                    const tp_node_meta** meta, tp_error* err)
{
    const int64_t ch = tp_tree_node_child(&mg->g, id, k);
    if (ch < mg->above) {
        *q = mg->q + (size_t)ch * mg->side2, *mask = mg->mask + (size_t)ch * mg->mw;
        *filled = mg->filled + (size_t)ch * mg->fw, *meta = &mg->metas[ch];
        return 1;
    }
    int s, c, r;
    tp_tree_node_locate(&mg->g, ch, &s, &c, &r);
    part_in* p;
    const int64_t pid = part_node(mg, s, c, r, &p);
    if (tp_store_read_node(p->s, pid, block, tp_tree_block_words(mg->g.n), err) != TP_OK)
        return 0;
    const tp_node_meta* m = &p->metas[pid];
    for (size_t i = 0; i < mg->side2; i++)
        kq[i] = block[i] == TP_TREE_NO_HEIGHT ? INT32_MIN : (int32_t)block[i] + m->qmin;
    *q = kq, *mask = block + mg->side2, *filled = block + mg->side2 + mg->mw, *meta = m;
    return 1;
}

/* The nodes above the split, from the top of the split up (children before parents). 1, or 0
 * after one line. */
static int compute_above(merge* mg, double err_unit)
{
    const tp_tree_geometry* g = &mg->g;
    mg->above = g->first_node[mg->split];
    if (mg->above == 0)
        return 1;
    mg->side2 = (size_t)((1 << g->n) + 1) * ((1 << g->n) + 1);
    mg->mw = tp_node_mask_words(g->n), mg->fw = tp_node_filled_words(g->n);
    const size_t a = (size_t)mg->above, bw = tp_tree_block_words(g->n);
    mg->q = malloc(a * mg->side2 * sizeof *mg->q);
    mg->mask = malloc(a * mg->mw * sizeof *mg->mask);
    mg->filled = malloc(a * mg->fw * sizeof *mg->filled);
    mg->metas = calloc(a, sizeof *mg->metas);
    uint16_t* blocks = malloc(4 * bw * sizeof *blocks);
    int32_t* kq = malloc(4 * mg->side2 * sizeof *kq);
    if (!mg->q || !mg->mask || !mg->filled || !mg->metas || !blocks || !kq) {
        free(blocks), free(kq);
        return fail_line("merge: out of memory for the nodes above the parts");
    }
    tp_progress pr;
    tp_progress_start(&pr, !mg->o->quiet, "merge", "above");
    tp_error err = {0};
    int ok = 1;
    for (int64_t id = mg->above - 1; id >= 0 && ok; id--) { /* ids run from the top down */
        const int32_t* cq[4];
        const uint16_t *cm[4], *cf[4];
        const tp_node_meta* cmeta[4];
        for (int k = 0; k < 4 && ok; k++)
            ok = child_of(mg, id, k, blocks + k * bw, kq + k * mg->side2, &cq[k], &cm[k], &cf[k],
                          &cmeta[k], &err);
        if (!ok)
            break;
        int s, c, r;
        tp_tree_node_locate(g, id, &s, &c, &r);
        tp_tree_node_from_children(g->n, s, cq, cm, cf, cmeta, err_unit,
                                   mg->q + (size_t)id * mg->side2, mg->mask + (size_t)id * mg->mw,
                                   mg->filled + (size_t)id * mg->fw, &mg->metas[id]);
        tp_progress_update(&pr, (double)(mg->above - id), (double)mg->above, -1);
        if (tp_interrupted())
            ok = 0, snprintf(err.message, sizeof err.message, "%s: interrupted: not written",
                             mg->o->out);
    }
    free(blocks), free(kq);
    return ok ? 1 : fail_line(err.message);
}

/* Node (s, c, r) of the whole tree into the writer: copied from its part, or computed above. */
static tp_status write_node(merge* mg, tp_store_writer* w, int s, int c, int r, tp_error* err)
{
    const int64_t id = tp_tree_node_id(&mg->g, s, c, r);
    if (s > mg->split)
        return tp_store_writer_add_node_filled(
            w, id, &mg->metas[id], mg->q + (size_t)id * mg->side2, mg->mask + (size_t)id * mg->mw,
            (mg->metas[id].flags & TP_NODE_HAS_FILLED) ? mg->filled + (size_t)id * mg->fw : NULL,
            err);
    part_in* p;
    const int64_t pid = part_node(mg, s, c, r, &p);
    tp_store_stored st;
    tp_status rc = tp_store_read_stored(p->s, pid, &st, err);
    return rc != TP_OK ? rc : tp_store_writer_add_stored(w, id, &p->metas[pid], &st, err);
}

/* Every node in the order one build emits them (tree_build.c: a band's leaves, then each
 * coarser scale's row it completes), then the totals and the commit. */
static tp_status write_all(merge* mg, const tp_store_header* h, size_t valid, double qerr,
                           tp_error* err)
{
    const tp_tree_geometry* g = &mg->g;
    tp_store_writer* w = NULL;
    tp_status st = tp_store_writer_begin(mg->o->out, h, &w, err);
    tp_progress pr;
    tp_progress_start(&pr, !mg->o->quiet, "merge", "merge");
    for (int r = 0; r < g->rows && st == TP_OK; r++) {
        for (int c = 0; c < g->cols && st == TP_OK; c++)
            st = write_node(mg, w, 0, c, r, err);
        for (int s = 1; s < g->scales && ((r + 1) & ((1 << s) - 1)) == 0 && st == TP_OK; s++) {
            const int rs = ((r + 1) >> s) - 1;
            if (rs >= g->node_rows[s])
                break;
            for (int c = 0; c < g->node_cols[s] && st == TP_OK; c++)
                st = write_node(mg, w, s, c, rs, err);
        }
        if (st == TP_OK && tp_interrupted())
            st = tp_error_set(err, TP_ERR_IO, "%s: interrupted: not written", mg->o->out);
        tp_progress_update(&pr, r + 1, g->rows, -1);
    }
    if (st != TP_OK) {
        tp_store_writer_abort(w);
        return st;
    }
    tp_store_writer_set_totals(w, qerr, valid, (size_t)g->src_width * g->src_height - valid);
    return tp_store_writer_commit(w, err);
}

static void merge_free(merge* mg)
{
    for (int i = 0; i < mg->o->part_count; i++)
        tp_store_close(mg->in[i].s);
    free(mg->in), free(mg->part);
    free(mg->q), free(mg->mask), free(mg->filled), free(mg->metas);
}

/* The whole store's header, from the first part's (its strip starts at the grid's origin) and
 * the parts' counts (a part's first row is also the last of the part above: counted once). */
static int whole_header(const merge* mg, tp_store_header* h, size_t* valid, double* qerr,
                        char** notes)
{
    size_t filled = 0;
    *valid = 0, *qerr = 0;
    for (int i = 0; i < mg->count; i++) {
        const part_in* p = mg->part[i];
        *valid += p->info.header.valid_samples - p->rec.first_valid;
        filled += p->rec.filled - p->rec.first_filled;
        if (p->info.header.quant_max_error_m > *qerr)
            *qerr = p->info.header.quant_max_error_m;
    }
    const part_in* first = mg->part[0];
    *h = first->info.header;
    h->geometry = mg->g;
    h->quant_max_error_m = *qerr;
    h->valid_samples = *valid;
    h->nodata_samples = (size_t)mg->g.src_width * mg->g.src_height - *valid;
    *notes = tp_build_notes_refill(first->rest, filled);
    h->notes = *notes;
    return *notes ? 1 : fail_line("merge: out of memory");
}

int tp_store_merge(const tp_merge_options* o, tp_merge_result* result)
{
    const double t0 = tp_clock_s();
    if (o->part_count < 1)
        return fail_line("merge: no part given"), TP_EXIT_USAGE;
    int rc = tp_cli_output_check("merge", "-o", o->out, TP_OUTPUT_STORE);
    if (rc != TP_EXIT_OK)
        return rc;
    for (int i = 0; i < o->part_count; i++)
        if (!strcmp(o->parts[i], o->out))
            return tp_cli_error("%s: the output would replace a part", o->out), TP_EXIT_FAILURE;
    merge mg = {.o = o};
    mg.in = calloc((unsigned)o->part_count, sizeof *mg.in);
    if (!mg.in)
        return fail_line("merge: out of memory"), TP_EXIT_FAILURE;
    int ok = 1;
    for (int i = 0; i < o->part_count && ok; i++)
        ok = open_part(o->parts[i], &mg.in[i]);
    ok = ok && check_parts(&mg);
    const double t_checked = tp_clock_s();
    if (ok && !o->quiet)
        tp_cli_note("%d parts of a %dx%d grid, split at scale %d: %lld nodes above them to "
                    "compute",
                    mg.count, mg.g.src_width, mg.g.src_height, mg.split,
                    (long long)mg.g.first_node[mg.split]);
    ok = ok && compute_above(&mg, mg.in[0].info.header.err_unit_steps);
    const double t_above = tp_clock_s();
    tp_store_header h = {0};
    size_t valid = 0;
    double qerr = 0;
    char* notes = NULL;
    ok = ok && whole_header(&mg, &h, &valid, &qerr, &notes);
    tp_error err = {0};
    if (ok && write_all(&mg, &h, valid, qerr, &err) != TP_OK)
        ok = fail_line(err.message);
    free(notes);
    const int64_t above = mg.above;
    const int split = mg.split;
    merge_free(&mg);
    if (!ok)
        return tp_interrupted() ? tp_cli_interrupted() : TP_EXIT_FAILURE;
    struct stat sb;
    const uint64_t bytes = stat(o->out, &sb) == 0 ? (uint64_t)sb.st_size : 0;
    const double seconds = tp_clock_s() - t0, rss = tp_memory_peak_rss() / 1048576.0;
    if (!o->quiet)
        tp_cli_note("%s: %dx%d samples, %lld nodes (%lld computed above the parts), %.1f s "
                    "(checks %.1f s, above %.1f s), peak RSS %.0f MB",
                    o->out, h.geometry.src_width, h.geometry.src_height,
                    (long long)h.geometry.node_count, (long long)above, seconds, t_checked - t0,
                    t_above - t_checked, rss);
    if (result)
        *result = (tp_merge_result){.width = h.geometry.src_width,
                                    .height = h.geometry.src_height,
                                    .parts = o->part_count,
                                    .split_scale = split,
                                    .nodes = h.geometry.node_count,
                                    .copied = h.geometry.node_count - above,
                                    .computed = above,
                                    .bytes = bytes,
                                    .check_seconds = t_checked - t0,
                                    .above_seconds = t_above - t_checked,
                                    .seconds = seconds,
                                    .rss_peak_mb = rss};
    return TP_EXIT_OK;
}
