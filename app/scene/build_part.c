/* build_part.c - a store built in parts: the split, the part's record, the store's notes (see
 * build_part.h). */
#include "build_part.h"

#include <inttypes.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int tp_build_part_plan(const tp_tree_geometry* g, int index, int count, tp_build_part* out,
                       tp_error* err)
{
    if (count < 1 || index < 1 || index > count)
        return tp_error_set(err, TP_ERR_INVALID_ARG, "part %d/%d: expected 1 <= I <= N", index,
                            count),
               0;
    if (g->rows < count)
        return tp_error_set(err, TP_ERR_INVALID_ARG,
                            "part %d/%d: the grid has %d rows of nodes (of %d samples): at most "
                            "%d parts",
                            index, count, g->rows, (1 << g->n) + 1, g->rows),
               0;
    int s = g->scales - 1;
    while (s > 0 && g->node_rows[s] < 4 * count)
        s--;
    if (g->node_rows[s] < 4 * count) /* small grids: the coarsest scale with count rows */
        for (s = g->scales - 1; g->node_rows[s] < count; s--)
            ;
    const int rows = g->node_rows[s];
    *out = (tp_build_part){.index = index,
                           .count = count,
                           .split_scale = s,
                           .band0 = (int)((int64_t)(index - 1) * rows / count) << s,
                           .band1 = index == count ? g->rows
                                                   : (int)((int64_t)index * rows / count) << s};
    return 1;
}

int tp_build_part_strip(const tp_tree_geometry* g, const tp_build_part* p,
                        tp_tree_geometry* strip)
{
    const int ps = 1 << g->n, y0 = p->band0 * ps;
    const int height = p->band1 == g->rows ? g->src_height - y0 : (p->band1 - p->band0) * ps + 1;
    tp_status st = tp_tree_geometry_init(g->src_width, height, ps + 1, strip, NULL);
    (void)st; /* a strip of a valid grid is valid */
    return y0;
}

/* FNV-1a, 64 bits */
static uint64_t fnv(uint64_t h, const void* data, size_t size)
{
    const unsigned char* p = data;
    for (size_t i = 0; i < size; i++)
        h = (h ^ p[i]) * 1099511628211ull;
    return h;
}

static uint64_t fnv_text(uint64_t h, const char* s) { return fnv(h, s ? s : "", strlen(s ? s : "") + 1); }

static int key_file(uint64_t* h, const char* path, tp_error* err)
{
    char abs[4096];
    tp_input_identity id;
    if (tp_input_identify(path, abs, sizeof abs, &id, err) != TP_OK)
        return 0;
    *h = fnv_text(*h, abs);
    *h = fnv(*h, &id.size_bytes, sizeof id.size_bytes);
    *h = fnv(*h, &id.mtime_ns, sizeof id.mtime_ns);
    return 1;
}

int tp_build_part_key(const tp_build_options* o, uint64_t* key, tp_error* err)
{
    uint64_t h = 14695981039346656037ull;
    h = fnv_text(h, "terrapatch part key 1");
    for (int i = 0; i < o->source_count; i++)
        if (!key_file(&h, o->sources[i], err))
            return 0;
    if (o->fill_from && !key_file(&h, o->fill_from, err))
        return 0;
    char opts[512];
    snprintf(opts, sizeof opts,
             "sources %d patch %d resampling %d memory %d fill_max %d z_unit %s gaps %d step %a "
             "range %d %a %a",
             o->source_count, o->patch_size, (int)o->resampling, o->memory_mb, o->fill_max,
             o->z_unit ? o->z_unit : "", o->allow_gaps, o->height_step_m, o->height_range_given,
             o->height_range_m[0], o->height_range_m[1]);
    h = fnv_text(h, opts);
    h = fnv_text(h, o->crs);
    *key = h;
    return 1;
}

/* The record: three lines of a fixed length (the counts are known only at commit). */
#define LINE1 "part %d/%d of a %dx%d grid in nodes of %d: leaf rows %d .. %d (split at scale %d)\n"
#define LINE2 "part key %016" PRIx64 " (the sources, their sizes and times, and the options)\n"
#define LINE3 "part counts: filled %20zu; its first row (shared with the part above) valid %20zu, filled %20zu\n"

char* tp_build_part_notes(const tp_build_part_record* r, const char* notes)
{
    const tp_build_part* p = &r->part;
    size_t cap = strlen(notes) + 512;
    char* out = malloc(cap);
    if (!out)
        return NULL;
    snprintf(out, cap, LINE1 LINE2 LINE3 "%s", p->index, p->count, r->width, r->height, r->patch,
             p->band0, p->band1 - 1, p->split_scale, r->key, r->filled, r->first_valid,
             r->first_filled, notes);
    return out;
}

int tp_build_part_parse(const char* notes, tp_build_part_record* r, const char** rest)
{
    tp_build_part_record x = {0};
    tp_build_part* p = &x.part;
    int last = 0, used = 0;
    if (sscanf(notes, "part %d/%d of a %dx%d grid in nodes of %d: leaf rows %d .. %d (split at "
                      "scale %d)\n%n",
               &p->index, &p->count, &x.width, &x.height, &x.patch, &p->band0, &last,
               &p->split_scale, &used) != 8 || !used)
        return 0;
    notes += used, used = 0;
    if (sscanf(notes, "part key %" SCNx64 " (the sources, their sizes and times, and the "
                      "options)\n%n", &x.key, &used) != 1 || !used)
        return 0;
    notes += used, used = 0;
    if (sscanf(notes, "part counts: filled %zu; its first row (shared with the part above) "
                      "valid %zu, filled %zu\n%n",
               &x.filled, &x.first_valid, &x.first_filled, &used) != 3 || !used)
        return 0;
    p->band1 = last + 1;
    *r = x;
    *rest = notes + used;
    return 1;
}

/* ---- the store's notes ---- */

#define FILLED_TAIL " samples (marked per sample)"

/* "COUNT samples (marked per sample)" padded to a fixed length, at `at` */
static void filled_tail(char* at, size_t cap, size_t filled)
{
    int digits = snprintf(at, cap, "%zu" FILLED_TAIL, filled) - (int)strlen(FILLED_TAIL);
    snprintf(at + strlen(at), cap - strlen(at), "%*s", 20 - digits, "");
}

char* tp_build_notes(const tp_build_options* o, const char* mosaic_notes, size_t filled)
{
    size_t cap = strlen(mosaic_notes) + 256;
    for (int i = 0; i < o->source_count; i++)
        cap += strlen(o->sources[i]) + 16;
    cap += 320;
    char* notes = malloc(cap);
    if (!notes)
        return NULL;
    size_t at = 0;
    for (int i = 0; i < o->source_count; i++)
        at += (size_t)snprintf(notes + at, cap - at, "source: %s\n", o->sources[i]);
    at += (size_t)snprintf(notes + at, cap - at, "%s%s", mosaic_notes, mosaic_notes[0] ? "\n" : "");
    if (o->fill_max <= 0) {
        snprintf(notes + at, cap - at, "voids are not filled (--fill-max 0)");
        return notes;
    }
    char size[64] = "voids of any size";
    if (o->fill_max != TP_FILL_MAX_ANY)
        snprintf(size, sizeof size, "voids up to %d x %d samples", o->fill_max, o->fill_max);
    char how[320] = "by interpolation (GDALFillNodata)";
    if (o->fill_from)
        snprintf(how, sizeof how, "from %.250s (shifted onto the ground around each void)",
                 o->fill_from);
    at += (size_t)snprintf(notes + at, cap - at, "%s filled %s: ", size, how);
    filled_tail(notes + at, cap - at, filled);
    return notes;
}

char* tp_build_notes_refill(const char* notes, size_t filled)
{
    char* out = strdup(notes);
    if (!out)
        return NULL;
    char* tail = NULL;
    for (char* t = strstr(out, FILLED_TAIL); t; t = strstr(t + 1, FILLED_TAIL))
        tail = t;
    if (!tail)
        return out; /* voids not filled: no count */
    char* digits = tail;
    while (digits > out && digits[-1] >= '0' && digits[-1] <= '9')
        digits--;
    filled_tail(digits, strlen(digits) + 1, filled);
    return out;
}
