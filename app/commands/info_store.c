/*
 * info_store.c - `terrapatch info STORE.tpt`: what a built store holds (its grid, tree,
 * quantisation, size on disk, the sources and decisions of its build) after reading and
 * checking every node: a damaged node makes the command fail (exit 1) naming the node and
 * its byte offset.
 */
#include "info.h"
#include "cli.h"
#include "extent.h"
#include "json.h"
#include "store_scene.h"

#include "tp_core.h"
#include "tp_io.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct check_result {
    int64_t nodes, damaged;
    char first[600]; /* the first damaged node's message */
} check_result;

/* Reads every node (its CRC32 and decoding checked), with a progress line every 10 % on big
 * stores. */
static int check_nodes(const tp_store_scene* sc, check_result* out)
{
    const tp_tree_geometry* g = &sc->info.header.geometry;
    size_t v = ((size_t)1 << g->n) + 1;
    uint16_t* buf = malloc(v * v * sizeof *buf);
    if (!buf)
        return 0;
    memset(out, 0, sizeof *out);
    int tenth = -1;
    for (int64_t id = 0; id < g->node_count; id++) {
        tp_error err;
        if (tp_store_read_node(sc->store, id, buf, v * v, &err) != TP_OK) {
            if (!out->damaged++)
                snprintf(out->first, sizeof out->first, "%s", err.message);
        }
        out->nodes++;
        int t = (int)(10 * (id + 1) / g->node_count);
        if (g->node_count > 100000 && t != tenth) {
            tenth = t;
            fprintf(stderr, "\r%schecking %s: %d %%", tp_cli_prefix(), sc->path, 10 * t);
            if (t == 10)
                fputc('\n', stderr);
        }
    }
    free(buf);
    return 1;
}

static const char* zone_of(const tp_store_scene* sc, char* buf, size_t cap)
{
    tp_crs_info ci;
    if (tp_crs_describe(sc->info.header.crs_wkt, &ci, NULL) != TP_OK || !ci.name[0])
        return "none";
    if (ci.epsg)
        snprintf(buf, cap, "%s (EPSG:%d)", ci.name, ci.epsg);
    else
        snprintf(buf, cap, "%s", ci.name);
    return buf;
}

static void print_text(const tp_store_scene* sc, const check_result* cr)
{
    const tp_store_header* h = &sc->info.header;
    const tp_tree_geometry* g = &h->geometry;
    const tp_tree_info* ti = &sc->tree_info;
    char zone[256];
    printf("store:          %s\n", sc->path);
    printf("format:         terrapatch store, version %u\n", sc->info.version);
    printf("size:           %.1f MB (%llu bytes): %.3f bytes per source sample, hierarchy "
           "included\n",
           sc->info.file_bytes / 1e6, (unsigned long long)sc->info.file_bytes,
           sc->info.bytes_per_sample);
    printf("grid:           %d x %d samples (fitted %d x %d), CRS %s\n", g->src_width,
           g->src_height, g->width, g->height, zone_of(sc, zone, sizeof zone));
    printf("spacing:        %.6g x %.6g m\n", fabs(h->geotransform[1]), fabs(h->geotransform[5]));
    double ext[4];
    tp_proj_extent(sc->georef, g->width, g->height, ext);
    printf("extent:         E %.3f .. %.3f, N %.3f .. %.3f (sample centres, padding included)\n",
           ext[0], ext[2], ext[1], ext[3]);
    int crosses = 0;
    tp_error why = {{0}};
    int geo = tp_geo_extent(sc->georef, g->width, g->height, ext, &crosses, &why);
    if (geo > 0)
        printf("extent (WGS84): lat %.6f .. %.6f, lon %.6f .. %.6f%s\n", ext[0], ext[2], ext[1],
               ext[3], crosses ? " (across the antimeridian)" : "");
    else if (geo < 0)
        printf("extent (WGS84): not available: %s\n", why.message);
    printf("samples:        %zu valid, %zu nodata\n", h->valid_samples, h->nodata_samples);
    printf("heights:        %.3f .. %.3f m, step %.6g m, quantisation error <= %.6g m\n",
           ti->min_height_m, ti->max_height_m, h->height_step_m, h->quant_max_error_m);
    printf("tree:           nodes of %d x %d samples, %d x %d leaves, %d scales, %lld nodes, "
           "%lld roots\n",
           (1 << g->n) + 1, (1 << g->n) + 1, g->cols, g->rows, g->scales,
           (long long)g->node_count, (long long)g->root_count);
    printf("checked:        %lld nodes, %lld damaged\n", (long long)cr->nodes,
           (long long)cr->damaged);
    const char* notes = h->notes;
    while (notes && *notes) {
        const char* nl = strchr(notes, '\n');
        int len = nl ? (int)(nl - notes) : (int)strlen(notes);
        printf("note:           %.*s\n", len, notes);
        notes += len + (nl ? 1 : 0);
    }
}

static void print_json(const tp_store_scene* sc, const check_result* cr)
{
    const tp_store_header* h = &sc->info.header;
    const tp_tree_geometry* g = &h->geometry;
    tp_json j;
    tp_json_init(&j, stdout);
    tp_json_object_begin(&j);
    tp_json_member_string(&j, "file", sc->path);
    tp_json_member_string(&j, "kind", "store");
    tp_json_member_int(&j, "format_version", sc->info.version);
    tp_json_member_size(&j, "bytes", (size_t)sc->info.file_bytes);
    tp_json_member_number(&j, "bytes_per_sample", sc->info.bytes_per_sample);
    tp_json_key(&j, "size");
    tp_json_array_begin(&j);
    tp_json_int(&j, g->src_width);
    tp_json_int(&j, g->src_height);
    tp_json_array_end(&j);
    tp_json_key(&j, "grid");
    tp_json_array_begin(&j);
    tp_json_int(&j, g->width);
    tp_json_int(&j, g->height);
    tp_json_array_end(&j);
    tp_json_key(&j, "grid_geotransform");
    tp_json_array_begin(&j);
    for (int i = 0; i < 6; i++)
        tp_json_number(&j, h->geotransform[i]);
    tp_json_array_end(&j);
    tp_json_member_string(&j, "crs_wkt", h->crs_wkt);
    double ext[4];
    int crosses = 0;
    tp_error why;
    tp_json_key(&j, "extent_geo");
    if (tp_geo_extent(sc->georef, g->width, g->height, ext, &crosses, &why) > 0) {
        tp_json_array_begin(&j);
        for (int i = 0; i < 4; i++)
            tp_json_number(&j, ext[i]);
        tp_json_array_end(&j);
    } else {
        tp_json_null(&j);
    }
    tp_json_member_int(&j, "patch", (1 << g->n) + 1);
    tp_json_key(&j, "leaves");
    tp_json_array_begin(&j);
    tp_json_int(&j, g->cols);
    tp_json_int(&j, g->rows);
    tp_json_array_end(&j);
    tp_json_member_int(&j, "scales", g->scales);
    tp_json_member_int(&j, "nodes", g->node_count);
    tp_json_member_int(&j, "roots", g->root_count);
    tp_json_member_number(&j, "height_step_m", h->height_step_m);
    tp_json_member_number(&j, "quant_max_error_m", h->quant_max_error_m);
    tp_json_member_number(&j, "drawn_min_m", sc->tree_info.min_height_m);
    tp_json_member_number(&j, "drawn_max_m", sc->tree_info.max_height_m);
    tp_json_member_size(&j, "valid_samples", h->valid_samples);
    tp_json_member_size(&j, "nodata_samples", h->nodata_samples);
    tp_json_member_int(&j, "damaged_nodes", cr->damaged);
    tp_json_key(&j, "notes");
    tp_json_array_begin(&j);
    for (const char* n = h->notes; n && *n;) {
        const char* nl = strchr(n, '\n');
        size_t len = nl ? (size_t)(nl - n) : strlen(n);
        char line[1024];
        snprintf(line, sizeof line, "%.*s", (int)(len < sizeof line ? len : sizeof line - 1), n);
        tp_json_string(&j, line);
        n += len + (nl ? 1 : 0);
    }
    tp_json_array_end(&j);
    tp_json_object_end(&j);
}

int tp_info_store(const char* path, int json)
{
    tp_store_scene sc;
    int code = tp_store_scene_open(path, &sc);
    if (code != TP_EXIT_OK)
        return code;
    check_result cr;
    if (!check_nodes(&sc, &cr)) {
        tp_cli_error("%s: out of memory", path);
        tp_store_scene_close(&sc);
        return TP_EXIT_FAILURE;
    }
    if (json)
        print_json(&sc, &cr);
    else
        print_text(&sc, &cr), tp_info_imagery_beside(path);
    if (cr.damaged)
        tp_cli_error("%s (%lld damaged node%s in all)", cr.first, (long long)cr.damaged,
                     cr.damaged == 1 ? "" : "s");
    tp_store_scene_close(&sc);
    return tp_cli_finish(cr.damaged ? TP_EXIT_FAILURE : TP_EXIT_OK);
}
