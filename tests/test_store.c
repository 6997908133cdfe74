/*
 * test_store.c - the terrain store (.tpt; io/src/store_*.cpp, docs/store.md): exact round
 * trips of real DEMs cut into nodes (written in a builder's order: children before parents,
 * not id order), small and awkward grids, and damaged files: a flipped byte in a node, the
 * header, either table or the footer; files cut short at many lengths, tables cut short; a
 * location outside the data area (at open, and when changed in place after open); a newer and
 * an older (1) format version; the node table mapped from the file, not copied;
 * another file type; a FIFO. Writes: a missing node, abort, and a full disk (RLIMIT_FSIZE in a
 * child) leave no file. The test reads the file with its own parser of docs/store.md's layout
 * and its own CRC32, so the documentation is checked too.
 */
#define _GNU_SOURCE
#include "tp_io.h"
#include "tp_test.h"
#include "tp_test_tree.h"

#include <errno.h>
#include <limits.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#define TP_TMP_PREFIX "tp_store_"
#include "tp_test_tmp.h"

/* ---------------------------------------------------------------------------------------------
 * The documented layout (docs/store.md), read independently of io/src/store_format.hpp
 */
static uint32_t crc32_ref(const uint8_t* p, size_t n) /* the CRC32 of zlib, PNG and gzip */
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}
static uint32_t le32(const uint8_t* p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static uint64_t le64(const uint8_t* p) { return le32(p) | (uint64_t)le32(p + 4) << 32; }
static void put32(uint8_t* p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

typedef struct file_buf {
    uint8_t* data;
    size_t size;
} file_buf;

static file_buf slurp(const char* path)
{
    file_buf b = {NULL, 0};
    FILE* f = fopen(path, "rb");
    ASSERT_TRUE(f != NULL);
    fseek(f, 0, SEEK_END);
    b.size = (size_t)ftell(f);
    fseek(f, 0, SEEK_SET);
    b.data = malloc(b.size ? b.size : 1);
    ASSERT_TRUE(b.data && fread(b.data, 1, b.size, f) == b.size);
    fclose(f);
    return b;
}

static void spill(const char* path, const uint8_t* data, size_t size)
{
    FILE* f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    ASSERT_TRUE(fwrite(data, 1, size, f) == size);
    ASSERT_TRUE(fclose(f) == 0);
}

/* Where things are, per docs/store.md (format 2). */
#define FOOTER 56
#define META_ENTRY 104
#define LOC_ENTRY 24
typedef struct layout {
    uint32_t header_bytes;
    uint64_t node_count;
    uint64_t meta_offset, meta_bytes, loc_offset, loc_bytes, data_offset, data_end;
} layout;

static layout parse_layout(const file_buf* b)
{
    layout l;
    ASSERT_TRUE(b->size > 200);
    ASSERT_TRUE(memcmp(b->data, "\x89TPT\r\n\x1a\n", 8) == 0);
    ASSERT_EQ_INT(TP_STORE_VERSION, le32(b->data + 8));
    l.header_bytes = le32(b->data + 12);
    l.node_count = le64(b->data + 48);
    const uint8_t* foot = b->data + b->size - FOOTER;
    ASSERT_TRUE(memcmp(foot + 48, "TPTEND\r\n", 8) == 0);
    l.meta_offset = le64(foot);
    l.meta_bytes = le64(foot + 8);
    l.loc_offset = le64(foot + 16);
    l.loc_bytes = le64(foot + 24);
    ASSERT_EQ_INT(l.meta_offset, (l.header_bytes + 7) / 8 * 8);
    ASSERT_EQ_INT(l.meta_bytes, l.node_count * META_ENTRY);
    ASSERT_EQ_INT(l.loc_offset, l.meta_offset + l.meta_bytes);
    ASSERT_EQ_INT(l.loc_bytes, l.node_count * LOC_ENTRY);
    ASSERT_EQ_INT(0, le32(foot + 40));
    l.data_offset = l.loc_offset + l.loc_bytes;
    l.data_end = b->size - FOOTER;
    return l;
}

static uint8_t* loc_entry(const file_buf* b, const layout* l, int64_t node)
{
    return b->data + l->loc_offset + (size_t)node * LOC_ENTRY;
}

static void node_extent(const file_buf* b, const layout* l, int64_t node, uint64_t* offset,
                        uint32_t* bytes)
{
    const uint8_t* e = loc_entry(b, l, node);
    *offset = le64(e);
    *bytes = le32(e + 8);
}

/* Both tables' CRC32s and the footer's made to match the bytes again. */
static void fix_table_crcs(file_buf* b, const layout* l)
{
    uint8_t* foot = b->data + b->size - FOOTER;
    put32(foot + 32, crc32_ref(b->data + l->meta_offset, l->meta_bytes));
    put32(foot + 36, crc32_ref(b->data + l->loc_offset, l->loc_bytes));
    put32(foot + 44, crc32_ref(foot, 44));
}

/* ---------------------------------------------------------------------------------------------
 * Nodes cut from a grid as tp_core.h's "Hierarchy" defines them, with arbitrary metas
 */
typedef struct fixture {
    tp_tree_geometry g;
    int side;
    size_t count;          /* samples per node */
    int32_t* q;            /* node_count * count global quantised heights */
    uint16_t* rel;         /* the same relative to qmin, TP_TREE_NO_HEIGHT where not drawn */
    tp_node_meta* metas;   /* node_count */
    uint16_t* masks;       /* node_count cell masks (tp_node_mask_from_q of each node's q) */
    int64_t* order;        /* the writing order: children before parents, not id order */
} fixture;

/* Node id's cell mask in fixture fx. */
#define FX_MASK(fx, id) ((fx).masks + (size_t)(id) * tp_node_mask_words((fx).g.n))

static uint32_t hash32(uint64_t x)
{
    x ^= x >> 33, x *= 0xff51afd7ed558ccdull, x ^= x >> 33, x *= 0xc4ceb9fe1a85ec53ull;
    return (uint32_t)(x ^ (x >> 33));
}

static void locate(const tp_tree_geometry* g, int64_t id, int* s, int* c, int* r)
{
    int sc = 0;
    while (id < g->first_node[sc])
        sc++;
    *s = sc;
    *c = (int)((id - g->first_node[sc]) % g->node_cols[sc]);
    *r = (int)((id - g->first_node[sc]) / g->node_cols[sc]);
}

/* post-order: the 4 children (when they exist), then the node */
static void post_order(const fixture* fx, int s, int c, int r, int64_t** out)
{
    if (s > 0)
        for (int q = 0; q < 4; q++)
            post_order(fx, s - 1, 2 * c + (q & 1), 2 * r + (q >> 1), out);
    *(*out)++ = fx->g.first_node[s] + (int64_t)r * fx->g.node_cols[s] + c;
}

/* heights: w x h (NaN = nodata), quantised with a 1 m step. */
static void fixture_make(fixture* fx, const float* heights, int w, int h, int patch)
{
    memset(fx, 0, sizeof *fx);
    ASSERT_TRUE(tpt_tree_geometry(w, h, patch, &fx->g));
    const tp_tree_geometry* g = &fx->g;
    const int n = g->n;
    fx->side = patch;
    fx->count = (size_t)patch * patch;
    fx->q = malloc((size_t)g->node_count * fx->count * sizeof *fx->q);
    fx->rel = malloc((size_t)g->node_count * fx->count * sizeof *fx->rel);
    fx->metas = calloc((size_t)g->node_count, sizeof *fx->metas);
    fx->order = malloc((size_t)g->node_count * sizeof *fx->order);
    fx->masks = malloc((size_t)g->node_count * tp_node_mask_words(n) * sizeof *fx->masks);
    ASSERT_TRUE(fx->q && fx->rel && fx->metas && fx->order && fx->masks);
    for (int64_t id = 0; id < g->node_count; id++) {
        int s, c, r;
        locate(g, id, &s, &c, &r);
        int32_t* q = fx->q + (size_t)id * fx->count;
        tp_node_meta* m = &fx->metas[id];
        m->qmin = INT32_MAX, m->qmax = INT32_MIN;
        for (int j = 0; j < patch; j++)
            for (int i = 0; i < patch; i++) {
                int64_t x = ((int64_t)c << (n + s)) + ((int64_t)i << s);
                int64_t y = ((int64_t)r << (n + s)) + ((int64_t)j << s);
                float v = x < w && y < h ? heights[y * w + x] : NAN;
                int32_t qv = isnan(v) ? INT32_MIN : (int32_t)lrintf(v);
                q[j * patch + i] = qv;
                if (qv != INT32_MIN) {
                    m->qmin = qv < m->qmin ? qv : m->qmin;
                    m->qmax = qv > m->qmax ? qv : m->qmax;
                }
            }
        tp_node_mask_from_q(n, q, FX_MASK(*fx, id));
        for (size_t k = 0; k < fx->count; k++)
            fx->rel[(size_t)id * fx->count + k] =
                q[k] == INT32_MIN ? TP_TREE_NO_HEIGHT : (uint16_t)(q[k] - m->qmin);
        /* the rest is arbitrary: the store keeps what it is given, entries k > n excepted */
        m->area_qmin = (int32_t)hash32((uint64_t)id * 4 + 1);
        m->area_qmax = (int32_t)hash32((uint64_t)id * 4 + 2);
        m->flags = (uint8_t)(hash32((uint64_t)id * 4 + 3) & 3);
        for (int k = 0; k <= n; k++)
            m->delta[k] = (uint16_t)hash32((uint64_t)id << 8 | (uint64_t)k);
        for (int side = 0; side < 4; side++)
            for (int k = 0; k < n; k++)
                m->eps[side][k] = (uint16_t)hash32((uint64_t)id << 8 | 0x80 | (uint64_t)(side * 16 + k));
    }
    /* roots in descending id order, each subtree in post-order */
    int64_t* out = fx->order;
    for (int64_t id = g->node_count - 1; id >= 0; id--) {
        int s, c, r;
        locate(g, id, &s, &c, &r);
        if (s + 1 == g->scales || c / 2 >= g->node_cols[s + 1] || r / 2 >= g->node_rows[s + 1])
            post_order(fx, s, c, r, &out);
    }
    ASSERT_EQ_INT(out - fx->order, g->node_count);
    ASSERT_TRUE(g->node_count == 1 || fx->order[0] != 0);
}

static void fixture_free(fixture* fx)
{
    free(fx->q), free(fx->rel), free(fx->metas), free(fx->order), free(fx->masks);
}

static const char* const k_notes = "sources: test\nwarp: none\nUTF-8: Montréal, Sør-Trøndelag";

static tp_store_header fixture_header(const fixture* fx, const char* crs)
{
    tp_store_header h;
    memset(&h, 0, sizeof h);
    h.geometry = fx->g;
    const double gt[6] = {587049.617, 30.0, 0.0, 5037312.407, 0.0, -30.0};
    memcpy(h.geotransform, gt, sizeof gt);
    h.height_step_m = 1.0;
    h.quant_max_error_m = 0.5;
    h.err_unit_steps = 1.0 / 16;
    h.valid_samples = (size_t)fx->g.src_width * fx->g.src_height - 7;
    h.nodata_samples = 7;
    h.crs_wkt = crs;
    h.notes = k_notes;
    return h;
}

static void fixture_write(const fixture* fx, const char* path, const char* crs)
{
    tp_store_header h = fixture_header(fx, crs);
    tp_store_writer* w = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_store_writer_begin(path, &h, &w, &err));
    for (int64_t i = 0; i < fx->g.node_count; i++) {
        int64_t id = fx->order[i];
        tp_status s = tp_store_writer_add_node(w, id, &fx->metas[id], fx->q + (size_t)id * fx->count,
                                               FX_MASK(*fx, id), &err);
        if (s != TP_OK)
            tp_test_note("%s", err.message);
        ASSERT_OK(s);
    }
    tp_status s = tp_store_writer_commit(w, &err);
    if (s != TP_OK)
        tp_test_note("%s", err.message);
    ASSERT_OK(s);
}

/* Every node, meta and header field read back exactly. */
static void fixture_check(const fixture* fx, const char* path, const char* crs)
{
    tp_store* st = NULL;
    tp_error err = {{0}};
    tp_status s = tp_store_open(path, &st, &err);
    if (s != TP_OK)
        tp_test_note("%s", err.message);
    ASSERT_OK(s);
    tp_store_info info;
    tp_store_get_info(st, &info);
    const tp_store_header want = fixture_header(fx, crs);
    EXPECT_EQ_INT(info.version, TP_STORE_VERSION);
    const tp_tree_geometry *a = &info.header.geometry, *b = &fx->g;
    EXPECT_EQ_INT(a->n, b->n);
    EXPECT_EQ_INT(a->src_width, b->src_width);
    EXPECT_EQ_INT(a->src_height, b->src_height);
    EXPECT_EQ_INT(a->width, b->width);
    EXPECT_EQ_INT(a->height, b->height);
    EXPECT_EQ_INT(a->cols, b->cols);
    EXPECT_EQ_INT(a->rows, b->rows);
    EXPECT_EQ_INT(a->scales, b->scales);
    EXPECT_EQ_INT(a->node_count, b->node_count);
    EXPECT_EQ_INT(a->root_count, b->root_count);
    for (int sc = 0; sc < b->scales; sc++) {
        EXPECT_EQ_INT(a->first_node[sc], b->first_node[sc]);
        EXPECT_EQ_INT(a->node_cols[sc], b->node_cols[sc]);
        EXPECT_EQ_INT(a->node_rows[sc], b->node_rows[sc]);
    }
    for (int i = 0; i < 6; i++)
        EXPECT_EQ_DBL(info.header.geotransform[i], want.geotransform[i]);
    EXPECT_EQ_DBL(info.header.height_step_m, want.height_step_m);
    EXPECT_EQ_DBL(info.header.quant_max_error_m, want.quant_max_error_m);
    EXPECT_EQ_DBL(info.header.err_unit_steps, want.err_unit_steps);
    EXPECT_EQ_INT(info.header.valid_samples, want.valid_samples);
    EXPECT_EQ_INT(info.header.nodata_samples, want.nodata_samples);
    EXPECT_EQ_STR(crs, info.header.crs_wkt);
    EXPECT_EQ_STR(k_notes, info.header.notes);
    struct stat sb;
    ASSERT_TRUE(stat(path, &sb) == 0);
    EXPECT_EQ_INT(info.file_bytes, sb.st_size);
    EXPECT_EQ_INT(info.table_bytes, (uint64_t)b->node_count * (META_ENTRY + LOC_ENTRY));
    EXPECT_TRUE(info.data_bytes > 0 && info.data_bytes < info.file_bytes - info.table_bytes);
    file_buf fb = slurp(path);
    const layout l = parse_layout(&fb);
    EXPECT_EQ_INT(info.data_bytes, l.data_end - l.data_offset);
    /* the node table is the metas' array as in memory, unused bytes 0 */
    for (int64_t id = 0; id < b->node_count; id++) {
        uint8_t want_meta[META_ENTRY];
        memset(want_meta, 0, sizeof want_meta);
        memcpy(want_meta, &fx->metas[id], 102);
        if (memcmp(fb.data + l.meta_offset + (size_t)id * META_ENTRY, want_meta, META_ENTRY)) {
            EXPECT_TRUE(!"node table entry differs from the meta's bytes");
            break;
        }
    }
    free(fb.data);
    EXPECT_NEAR(info.bytes_per_sample,
                (double)sb.st_size / ((double)b->src_width * b->src_height), 1e-12);

    size_t count = 0;
    const tp_node_meta* metas = tp_store_metas(st, &count);
    ASSERT_EQ_INT(count, b->node_count);
    uint16_t* samples = malloc(fx->count * sizeof *samples);
    ASSERT_TRUE(samples != NULL);
    long bad_metas = 0, bad_nodes = 0;
    for (int64_t id = 0; id < b->node_count; id++) {
        bad_metas += memcmp(&metas[id], &fx->metas[id], sizeof metas[id]) != 0;
        s = tp_store_read_node(st, id, samples, fx->count, &err);
        if (s != TP_OK)
            tp_test_note("%s", err.message);
        ASSERT_OK(s);
        bad_nodes += memcmp(samples, fx->rel + (size_t)id * fx->count, fx->count * 2) != 0;
    }
    EXPECT_EQ_INT(bad_metas, 0);
    EXPECT_EQ_INT(bad_nodes, 0);
    free(samples);
    tp_store_close(st);
}

static float* read_dem(const char* file, int* w, int* h, char** crs)
{
    char path[1024];
    REQUIRE_DATA_FILE(path, "TP_SHARED_DATA_DIR", file);
    tp_dem* dem = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_dem_read(path, &dem, &err));
    *w = dem->width, *h = dem->height;
    float* heights = malloc((size_t)*w * *h * sizeof *heights);
    ASSERT_TRUE(heights != NULL);
    memcpy(heights, dem->heights, (size_t)*w * *h * sizeof *heights);
    *crs = strdup(dem->crs_wkt);
    tp_dem_destroy(dem);
    return heights;
}

static void round_trip_dem(const char* file, int patch)
{
    int w, h;
    char* crs;
    float* heights = read_dem(file, &w, &h, &crs);
    fixture fx;
    fixture_make(&fx, heights, w, h, patch);
    char path[600];
    snprintf(path, sizeof path, "%s/a.tpt", make_tmp_dir());
    fixture_write(&fx, path, crs);
    fixture_check(&fx, path, crs);
    tp_store* st;
    tp_error err;
    ASSERT_OK(tp_store_open(path, &st, &err));
    tp_store_info info;
    tp_store_get_info(st, &info);
    tp_test_note("%s, %dx%d at %d: %lld nodes, %.3f bytes per source sample", file, w, h, patch,
                 (long long)fx.g.node_count, info.bytes_per_sample);
    EXPECT_LE(info.bytes_per_sample, 2.0); /* the store's budget, hierarchy included */
    tp_store_close(st);
    fixture_free(&fx);
    free(heights);
    free(crs);
}

/* A store of a real DEM for the damage tests; returns its fixture (caller frees). */
static void small_store(fixture* fx, char* path, size_t cap)
{
    int w, h;
    char* crs;
    float* heights = read_dem("storml_elev_orig.tif", &w, &h, &crs);
    fixture_make(fx, heights, w, h, 17);
    snprintf(path, cap, "%s/s.tpt", make_tmp_dir());
    fixture_write(fx, path, crs);
    free(heights);
    free(crs);
}

/* Opening fails with status and a message naming path and containing needle; out untouched. */
static void expect_open_fails(const char* path, tp_status status, const char* needle)
{
    tp_store* sentinel = (tp_store*)&sentinel;
    tp_store* st = sentinel;
    tp_error err = {{0}};
    EXPECT_STATUS(status, tp_store_open(path, &st, &err));
    EXPECT_TRUE(st == sentinel);
    EXPECT_CONTAINS(err.message, path);
    EXPECT_CONTAINS(err.message, needle);
}

static int dir_is_empty(const char* dir)
{
    DIR* d = opendir(dir);
    struct dirent* e;
    int empty = 1;
    ASSERT_TRUE(d != NULL);
    while ((e = readdir(d)) != NULL)
        if (strcmp(e->d_name, ".") && strcmp(e->d_name, "..")) {
            tp_test_note("left in the folder: %s", e->d_name);
            empty = 0;
        }
    closedir(d);
    return empty;
}

/* ---------------------------------------------------------------------------------------------
 * Round trips
 */
TEST(round_trip_n42e001_65) { round_trip_dem("N42E001.hgt", 65); }
TEST(round_trip_mt_rainier_129) { round_trip_dem("mt_rainier_90m.tif", 129); }
TEST(round_trip_mt_hood_nodata_33) { round_trip_dem("lf_elev_220_mt_hood_utm.tif", 33); }
TEST(round_trip_storm_lake_nodata_edges_17) { round_trip_dem("storml_elev_orig.tif", 17); }

/* 1x1, 2x2, sizes that are not 2^n*k+1, flat, all nodata, a cliff across the whole 16-bit
 * range (residuals that wrap around), random noise (stored raw: zstd cannot shrink it). */
TEST(round_trip_small_and_awkward_grids)
{
    static const int sizes[][3] = {{1, 1, 17}, {2, 2, 17},  {17, 17, 17}, {18, 17, 17},
                                   {17, 50, 17}, {40, 33, 33}, {300, 20, 17}, {257, 257, 257}};
    const char* dir = make_tmp_dir();
    for (size_t si = 0; si < sizeof sizes / sizeof sizes[0]; si++)
        for (int kind = 0; kind < 5; kind++) {
            const int w = sizes[si][0], h = sizes[si][1], patch = sizes[si][2];
            float* heights = malloc((size_t)w * h * sizeof *heights);
            ASSERT_TRUE(heights != NULL);
            for (int y = 0; y < h; y++)
                for (int x = 0; x < w; x++) {
                    float v = kind == 0   ? 1234.0f
                              : kind == 1 ? NAN
                              : kind == 2 ? ((x + y) % 7 < 3 ? -500.0f : 65034.0f)
                              : kind == 3 ? (float)(hash32((uint64_t)y * 100003u + (uint64_t)x) % 65535u)
                                          : (x * 7 + y * 3) % 11 == 0 ? NAN : (float)((x * x) % 4093 - y);
                    heights[(size_t)y * w + x] = v;
                }
            fixture fx;
            fixture_make(&fx, heights, w, h, patch);
            char path[600];
            snprintf(path, sizeof path, "%s/g.tpt", dir);
            fixture_write(&fx, path, "");
            fixture_check(&fx, path, "");
            tp_store* st;
            tp_error err;
            ASSERT_OK(tp_store_open(path, &st, &err));
            tp_store_info info;
            tp_store_get_info(st, &info);
            const uint64_t raw = (uint64_t)fx.g.node_count * fx.count * 2;
            if (kind == 3 && w == fx.g.width && h == fx.g.height) /* noise without padding:
                                                                    kept raw, not grown by zstd */
                EXPECT_EQ_INT(info.data_bytes, raw);
            else if (kind == 0 || kind == 1) /* flat, nothing drawn: a few bytes per node */
                EXPECT_LE_INT(info.data_bytes, (uint64_t)fx.g.node_count * 64);
            else
                EXPECT_LE_INT(info.data_bytes, raw);
            tp_store_close(st);
            unlink(path);
            fixture_free(&fx);
            free(heights);
        }
}

/* The real producer: tp_tree_builder's emit callback writes straight into the store (its order:
 * children before parents), and the store reads back exactly the metas and samples of
 * tp_tree_create_from_grid on the same grid (same step, same error unit). */
static int emit_to_store(int64_t node, const tp_node_meta* meta, const int32_t* q,
                         const uint16_t* mask, void* user, tp_error* err)
{
    return tp_store_writer_add_node((tp_store_writer*)user, node, meta, q, mask, err) != TP_OK;
}

TEST(tree_builder_into_store_matches_tree_from_grid)
{
    int w, h;
    char* crs;
    float* heights = read_dem("lf_elev_220_mt_hood_utm.tif", &w, &h, &crs);
    const int patch = 65;
    const double gt[6] = {587049.617, 30, 0, 5037312.407, 0, -30};
    tp_tree* t = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_tree_create_from_grid(heights, (size_t)w * h, w, h, gt, patch, 1.0, &t, &err));
    const tp_tree_geometry* g = tp_tree_get_geometry(t);
    float lo = INFINITY, hi = -INFINITY;
    for (size_t i = 0; i < (size_t)w * h; i++)
        if (isfinite(heights[i]))
            lo = heights[i] < lo ? heights[i] : lo, hi = heights[i] > hi ? heights[i] : hi;
    const double unit = tp_tree_err_unit_steps(floor(hi + 0.5) - floor(lo + 0.5));

    char path[600];
    snprintf(path, sizeof path, "%s/built.tpt", make_tmp_dir());
    tp_store_header hd;
    memset(&hd, 0, sizeof hd);
    hd.geometry = *g;
    memcpy(hd.geotransform, gt, sizeof gt);
    hd.height_step_m = 1.0, hd.err_unit_steps = unit, hd.crs_wkt = crs, hd.notes = "built";
    tp_store_writer* sw;
    ASSERT_OK(tp_store_writer_begin(path, &hd, &sw, &err));
    tp_tree_builder_desc bd;
    memset(&bd, 0, sizeof bd);
    bd.geometry = *g;
    bd.err_unit_steps = unit;
    bd.emit = emit_to_store;
    bd.user = sw;
    tp_tree_builder* b;
    ASSERT_OK(tp_tree_builder_create(&bd, &b, &err));
    const int side = patch;
    int32_t* band = malloc((size_t)side * g->width * sizeof *band);
    ASSERT_TRUE(band != NULL);
    for (int r = 0; r < g->rows; r++) {
        for (int j = 0; j < side; j++) {
            int y = r * (side - 1) + j;
            for (int x = 0; x < g->width; x++) {
                float v = x < w && y < h ? heights[(size_t)y * w + x] : NAN;
                band[(size_t)j * g->width + x] = isfinite(v) ? (int32_t)floor(v + 0.5) : INT32_MIN;
            }
        }
        tp_status s = tp_tree_builder_add_band(b, r, band, (size_t)side * g->width, &err);
        if (s != TP_OK)
            tp_test_note("%s", err.message);
        ASSERT_OK(s);
    }
    tp_tree_builder_destroy(b);
    ASSERT_OK(tp_store_writer_commit(sw, &err));

    tp_store* st;
    ASSERT_OK(tp_store_open(path, &st, &err));
    size_t count;
    const tp_node_meta* metas = tp_store_metas(st, &count);
    ASSERT_EQ_INT(count, g->node_count);
    const size_t per = (size_t)side * side;
    uint16_t* samples = malloc(per * sizeof *samples);
    long bad_metas = 0, bad_nodes = 0;
    for (int64_t id = 0; id < g->node_count; id++) {
        const tp_node_meta* want = tp_tree_meta(t, id);
        bad_metas += memcmp(&metas[id], want, sizeof *want) != 0;
        ASSERT_OK(tp_store_read_node(st, id, samples, per, &err));
        const uint16_t* resident = tp_tree_samples(t, id);
        ASSERT_TRUE(resident != NULL);
        bad_nodes += memcmp(samples, resident, per * sizeof *samples) != 0;
    }
    EXPECT_EQ_INT(bad_metas, 0);
    EXPECT_EQ_INT(bad_nodes, 0);
    tp_store_info info;
    tp_store_get_info(st, &info);
    tp_test_note("%lld nodes from the builder, %.3f bytes per source sample",
                 (long long)g->node_count, info.bytes_per_sample);
    free(samples);
    free(band);
    tp_store_close(st);
    tp_tree_destroy(t);
    free(heights);
    free(crs);
}

/* Several threads read every node of one open store at once (tp_store_read_node is thread-safe). */
typedef struct reader_job {
    const tp_store* st;
    const fixture* fx;
    int first;
    long mismatches, failures;
} reader_job;

static void* reader(void* p)
{
    reader_job* j = p;
    uint16_t* samples = malloc(j->fx->count * sizeof *samples);
    for (int pass = 0; pass < 3; pass++)
        for (int64_t k = 0; k < j->fx->g.node_count; k++) {
            int64_t id = (k * 7 + j->first) % j->fx->g.node_count;
            tp_error err;
            if (tp_store_read_node(j->st, id, samples, j->fx->count, &err) != TP_OK)
                j->failures++;
            else if (memcmp(samples, j->fx->rel + (size_t)id * j->fx->count, j->fx->count * 2))
                j->mismatches++;
        }
    free(samples);
    return NULL;
}

TEST(threads_read_one_store_at_once)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    tp_store* st;
    tp_error err;
    ASSERT_OK(tp_store_open(path, &st, &err));
    pthread_t th[4];
    reader_job jobs[4];
    for (int i = 0; i < 4; i++) {
        jobs[i] = (reader_job){st, &fx, i * 13, 0, 0};
        ASSERT_TRUE(pthread_create(&th[i], NULL, reader, &jobs[i]) == 0);
    }
    for (int i = 0; i < 4; i++) {
        pthread_join(th[i], NULL);
        EXPECT_EQ_INT(jobs[i].failures, 0);
        EXPECT_EQ_INT(jobs[i].mismatches, 0);
    }
    tp_store_close(st);
    fixture_free(&fx);
}

/* ---------------------------------------------------------------------------------------------
 * Damaged files
 */
TEST(flipped_node_byte_fails_that_node_only)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    const int64_t victim = fx.g.node_count / 2;
    uint64_t offset;
    uint32_t bytes;
    node_extent(&b, &l, victim, &offset, &bytes);
    b.data[offset + bytes / 2] ^= 0x10;
    spill(path, b.data, b.size);

    tp_store* st;
    tp_error err = {{0}};
    ASSERT_OK(tp_store_open(path, &st, &err)); /* the table is sound */
    uint16_t* samples = malloc(fx.count * sizeof *samples);
    memset(samples, 0xAB, fx.count * sizeof *samples);
    ASSERT_STATUS(TP_ERR_BAD_DATA, tp_store_read_node(st, victim, samples, fx.count, &err));
    char want[128];
    int s, c, r;
    locate(&fx.g, victim, &s, &c, &r);
    snprintf(want, sizeof want, "node %lld (scale %d, column %d, row %d)", (long long)victim, s, c, r);
    EXPECT_CONTAINS(err.message, want);
    snprintf(want, sizeof want, "at byte %llu", (unsigned long long)offset);
    EXPECT_CONTAINS(err.message, want);
    EXPECT_CONTAINS(err.message, path);
    EXPECT_CONTAINS(err.message, "checksum");
    for (size_t k = 0; k < fx.count; k++) /* output untouched */
        ASSERT_EQ_INT(samples[k], 0xABAB);
    long others = 0;
    for (int64_t id = 0; id < fx.g.node_count; id++)
        if (id != victim) {
            others += tp_store_read_node(st, id, samples, fx.count, &err) == TP_OK &&
                      !memcmp(samples, fx.rel + (size_t)id * fx.count, fx.count * 2);
        }
    EXPECT_EQ_INT(others, fx.g.node_count - 1);
    free(samples);
    free(b.data);
    tp_store_close(st);
    fixture_free(&fx);
}

/* tp_store_read_stored and tp_store_writer_add_stored (a build in parts merges so): every node
 * copied as stored, in the order of the original's data, gives the original file byte for
 * byte; bytes that do not match their CRC32, and a node added twice, are refused. */
TEST(stored_bytes_copied_give_the_same_file)
{
    fixture fx;
    char path[600], copy[640];
    small_store(&fx, path, sizeof path);
    snprintf(copy, sizeof copy, "%s.copy.tpt", path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    const int64_t count = fx.g.node_count;
    int64_t* order = malloc((size_t)count * sizeof *order);
    uint64_t* at = malloc((size_t)count * sizeof *at);
    ASSERT_TRUE(order && at);
    for (int64_t id = 0; id < count; id++) { /* the nodes in the order of their data */
        uint32_t bytes;
        node_extent(&b, &l, id, &at[id], &bytes);
        int64_t k = id;
        for (; k > 0 && at[order[k - 1]] > at[id]; k--)
            order[k] = order[k - 1];
        order[k] = id;
    }
    tp_store* st;
    tp_error err = {{0}};
    ASSERT_OK(tp_store_open(path, &st, &err));
    tp_store_info info;
    tp_store_get_info(st, &info);
    size_t n_metas;
    const tp_node_meta* metas = tp_store_metas(st, &n_metas);
    tp_store_writer* w;
    ASSERT_OK(tp_store_writer_begin(copy, &info.header, &w, &err));
    for (int64_t k = 0; k < count; k++) {
        tp_store_stored x;
        ASSERT_OK(tp_store_read_stored(st, order[k], &x, &err));
        if (k == 0) { /* damaged bytes, and the node twice */
            tp_store_stored bad = x;
            bad.crc ^= 1;
            EXPECT_STATUS(TP_ERR_BAD_DATA, tp_store_writer_add_stored(w, order[k], &metas[order[k]], &bad, &err));
            EXPECT_CONTAINS(err.message, "CRC32");
            ASSERT_OK(tp_store_writer_add_stored(w, order[k], &metas[order[k]], &x, &err));
            EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_store_writer_add_stored(w, order[k], &metas[order[k]], &x, &err));
            EXPECT_CONTAINS(err.message, "added twice");
            continue;
        }
        ASSERT_OK(tp_store_writer_add_stored(w, order[k], &metas[order[k]], &x, &err));
    }
    ASSERT_OK(tp_store_writer_commit(w, &err));
    tp_store_close(st);
    file_buf c = slurp(copy);
    ASSERT_EQ_INT((long long)c.size, (long long)b.size);
    EXPECT_TRUE(memcmp(c.data, b.data, b.size) == 0);
    free(order), free(at), free(b.data), free(c.data);
    fixture_free(&fx);
}

/* A node whose bytes were replaced by a valid zstd frame of other content: the checksum stored
 * in the table is made to match, so the decoder's own checks must catch it. */
TEST(node_with_matching_checksum_but_wrong_content_fails)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    /* node victim's entry points at node 0's data */
    uint8_t* e0 = loc_entry(&b, &l, 0);
    int64_t victim = -1;
    /* find a node with a smaller range than node 0's data: its samples fall outside; and
     * which keeps a cell mask after its samples exactly when node 0 does */
    int s0, c0, r0;
    locate(&fx.g, 0, &s0, &c0, &r0);
    int mask0 = s0 > 0 && (fx.metas[0].flags & TP_NODE_HAS_DRAWN) &&
                !(fx.metas[0].flags & TP_NODE_COMPLETE);
    for (int64_t id = 1; id < fx.g.node_count && victim < 0; id++) {
        int s, c, r;
        locate(&fx.g, id, &s, &c, &r);
        int mask = s > 0 && (fx.metas[id].flags & TP_NODE_HAS_DRAWN) &&
                   !(fx.metas[id].flags & TP_NODE_COMPLETE);
        if (mask == mask0 && fx.metas[id].qmin <= fx.metas[id].qmax &&
            fx.metas[0].qmax - fx.metas[0].qmin > fx.metas[id].qmax - fx.metas[id].qmin + 10)
            victim = id;
    }
    ASSERT_TRUE(victim > 0);
    uint8_t* ev = loc_entry(&b, &l, victim);
    /* offset, bytes, CRC, codec: node 0's data, and node 0 the victim's (swapped, so that the
     * nodes still fill the data area end to end, as opening checks) */
    uint8_t tmp[LOC_ENTRY];
    memcpy(tmp, ev, LOC_ENTRY);
    memcpy(ev, e0, LOC_ENTRY);
    memcpy(e0, tmp, LOC_ENTRY);
    fix_table_crcs(&b, &l);
    spill(path, b.data, b.size);
    tp_store* st;
    tp_error err = {{0}};
    ASSERT_OK(tp_store_open(path, &st, &err));
    uint16_t* samples = malloc(fx.count * sizeof *samples);
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_store_read_node(st, victim, samples, fx.count, &err));
    EXPECT_CONTAINS(err.message, "outside the node's range");
    free(samples);
    free(b.data);
    tp_store_close(st);
    fixture_free(&fx);
}

TEST(flipped_header_byte_fails_open)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    /* the version, the source width, a geotransform byte, the CRS text, the header CRC */
    const size_t where[] = {8, 20, 70, 170, l.header_bytes - 2};
    for (size_t i = 0; i < sizeof where / sizeof where[0]; i++) {
        b.data[where[i]] ^= 0x04;
        spill(path, b.data, b.size);
        expect_open_fails(path, TP_ERR_BAD_DATA, "damaged header: checksum mismatch");
        b.data[where[i]] ^= 0x04;
    }
    spill(path, b.data, b.size); /* restored: opens again */
    tp_store* st;
    tp_error err;
    ASSERT_OK(tp_store_open(path, &st, &err));
    tp_store_close(st);
    free(b.data);
    fixture_free(&fx);
}

TEST(flipped_table_byte_fails_open)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    const uint64_t where[] = {l.meta_offset, l.meta_offset + l.meta_bytes / 2 + 16,
                              l.loc_offset - 1, l.loc_offset, l.loc_offset + l.loc_bytes / 2,
                              l.data_offset - 1};
    for (size_t i = 0; i < 6; i++) {
        b.data[where[i]] ^= 0x80;
        spill(path, b.data, b.size);
        expect_open_fails(path, TP_ERR_BAD_DATA,
                          where[i] < l.loc_offset ? "damaged node table" : "damaged location table");
        b.data[where[i]] ^= 0x80;
    }
    /* a byte the format leaves 0 (a meta's padding, a location's reserved bytes), the
     * checksums made to match: the entry is refused, naming the node */
    const uint64_t unused[] = {l.meta_offset + 3 * META_ENTRY + 17, l.meta_offset + 3 * META_ENTRY + 103,
                               l.loc_offset + 3 * LOC_ENTRY + 20};
    for (size_t i = 0; i < 3; i++) {
        b.data[unused[i]] ^= 0x01;
        fix_table_crcs(&b, &l);
        spill(path, b.data, b.size);
        expect_open_fails(path, TP_ERR_BAD_DATA, "node 3 (scale");
        expect_open_fails(path, TP_ERR_BAD_DATA, i < 2 ? "unused bytes not 0" : "reserved bytes not 0");
        b.data[unused[i]] ^= 0x01;
    }
    fix_table_crcs(&b, &l);
    spill(path, b.data, b.size); /* restored: opens again */
    tp_store* st;
    tp_error err;
    ASSERT_OK(tp_store_open(path, &st, &err));
    tp_store_close(st);
    free(b.data);
    fixture_free(&fx);
}

TEST(flipped_footer_byte_fails_open)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    /* the node table's offset, the location table's size, the node table's CRC, the location
     * table's, the reserved word, the footer's CRC */
    const size_t backs[] = {56, 32, 24, 20, 16, 12};
    for (size_t i = 0; i < 6; i++) {
        b.data[b.size - backs[i]] ^= 0x01;
        spill(path, b.data, b.size);
        expect_open_fails(path, TP_ERR_BAD_DATA, "damaged footer");
        b.data[b.size - backs[i]] ^= 0x01;
    }
    b.data[b.size - 1] ^= 0x01; /* the end signature */
    spill(path, b.data, b.size);
    expect_open_fails(path, TP_ERR_BAD_DATA, "no footer");
    free(b.data);
    fixture_free(&fx);
}

/* A location outside the data area (into the footer, past the end of the file, into the
 * tables), checksums made to match: refused at open, naming the node. */
TEST(entry_outside_the_data_area_fails_open)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    uint8_t* e = loc_entry(&b, &l, 5);
    const uint64_t offsets[] = {l.data_end - 3, b.size + 100, l.data_offset - 8, l.meta_offset};
    for (size_t i = 0; i < sizeof offsets / sizeof offsets[0]; i++) {
        file_buf c = {malloc(b.size), b.size};
        memcpy(c.data, b.data, b.size);
        put32(c.data + (e - b.data), (uint32_t)offsets[i]);
        put32(c.data + (e - b.data) + 4, (uint32_t)(offsets[i] >> 32));
        fix_table_crcs(&c, &l);
        spill(path, c.data, c.size);
        expect_open_fails(path, TP_ERR_BAD_DATA, "location table, node 5 (scale");
        expect_open_fails(path, TP_ERR_BAD_DATA, "data outside the data area");
        free(c.data);
    }
    free(b.data);
    fixture_free(&fx);
}

/* The location table is read from the mapping when a node is read, so a file changed in place
 * after open (which terrapatch never does, but another program may) must not send the read
 * outside the data area: the bounds are checked again then. */
TEST(location_changed_after_open_is_checked_when_read)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    tp_store* st;
    tp_error err = {{0}};
    ASSERT_OK(tp_store_open(path, &st, &err));
    uint8_t loc[LOC_ENTRY];
    memcpy(loc, loc_entry(&b, &l, 7), sizeof loc);
    put32(loc, (uint32_t)(b.size - 10)); /* its bytes now run past the end of the file */
    int fd = open(path, O_WRONLY);
    ASSERT_TRUE(fd >= 0);
    ASSERT_TRUE(pwrite(fd, loc, sizeof loc, (off_t)(l.loc_offset + 7 * LOC_ENTRY)) == sizeof loc);
    close(fd);
    uint16_t* samples = malloc(fx.count * sizeof *samples);
    memset(samples, 0xAB, fx.count * sizeof *samples);
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_store_read_node(st, 7, samples, fx.count, &err));
    EXPECT_CONTAINS(err.message, "node 7 (scale");
    EXPECT_CONTAINS(err.message, "data outside the data area");
    EXPECT_EQ_INT(0xABAB, samples[0]);
    ASSERT_OK(tp_store_read_node(st, 6, samples, fx.count, &err)); /* the others still read */
    EXPECT_TRUE(memcmp(samples, fx.rel + 6 * fx.count, fx.count * 2) == 0);
    free(samples);
    free(b.data);
    tp_store_close(st);
    fixture_free(&fx);
}

/* tp_store_metas is the file's node table mapped read-only (the process's anonymous memory does
 * not grow with the node count): the pointer lies in a read-only mapping of path, at the node
 * table's offset. */
TEST(metas_are_mapped_from_the_file)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    tp_store* st;
    tp_error err = {{0}};
    ASSERT_OK(tp_store_open(path, &st, &err));
    size_t count = 0;
    const tp_node_meta* metas = tp_store_metas(st, &count);
    EXPECT_EQ_INT(0, (uintptr_t)metas % 8);
    char real[PATH_MAX];
    ASSERT_TRUE(realpath(path, real) != NULL);
    FILE* f = fopen("/proc/self/maps", "r");
    ASSERT_TRUE(f != NULL);
    char line[PATH_MAX + 256];
    int found = 0;
    while (fgets(line, sizeof line, f)) {
        unsigned long long lo, hi, off;
        char perms[8];
        int name_at = 0;
        if (sscanf(line, "%llx-%llx %7s %llx %*s %*s %n", &lo, &hi, perms, &off, &name_at) < 4)
            continue;
        const uintptr_t p = (uintptr_t)metas;
        if (p < lo || p >= hi)
            continue;
        line[strcspn(line, "\n")] = '\0';
        EXPECT_EQ_STR(real, line + name_at);
        EXPECT_TRUE(perms[0] == 'r' && perms[1] == '-');
        EXPECT_EQ_INT(l.meta_offset, off + (p - lo));
        found = 1;
    }
    fclose(f);
    EXPECT_TRUE(found);
    tp_store_close(st);
    free(b.data);
    fixture_free(&fx);
}

TEST(truncated_files_fail_clearly)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    const size_t lengths[] = {0, 1, 7, 8, 12, 100, l.header_bytes - 1, l.header_bytes,
                              l.header_bytes + 55, l.header_bytes + 1000, b.size / 2,
                              (size_t)l.loc_offset, (size_t)l.data_offset + 50, b.size - FOOTER,
                              b.size - 1};
    for (size_t i = 0; i < sizeof lengths / sizeof lengths[0]; i++) {
        spill(path, b.data, lengths[i]);
        expect_open_fails(path, TP_ERR_BAD_DATA, lengths[i] < 8 ? "not a terrapatch store" : "truncated");
    }
    /* the tables cut short, a sound footer after them (a copy that lost a middle part) */
    const size_t keeps[] = {(size_t)l.meta_offset + 10, (size_t)l.loc_offset + l.loc_bytes / 2,
                            (size_t)l.data_offset - 1};
    for (size_t i = 0; i < 3; i++) {
        file_buf c = {malloc(keeps[i] + FOOTER), keeps[i] + FOOTER};
        memcpy(c.data, b.data, keeps[i]);
        memcpy(c.data + keeps[i], b.data + b.size - FOOTER, FOOTER);
        spill(path, c.data, c.size);
        expect_open_fails(path, TP_ERR_BAD_DATA, "truncated");
        expect_open_fails(path, TP_ERR_BAD_DATA, "tables end at byte");
        free(c.data);
    }
    free(b.data);
    fixture_free(&fx);
}

/* The version is checked after the header's checksum: a sound header of format 2. */
TEST(newer_version_says_so)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    put32(b.data + 8, TP_STORE_VERSION + 1);
    put32(b.data + l.header_bytes - 4, crc32_ref(b.data, l.header_bytes - 4));
    spill(path, b.data, b.size);
    char want[128];
    snprintf(want, sizeof want, "written by a newer terrapatch (format %d; this one reads up to %d)",
             TP_STORE_VERSION + 1, TP_STORE_VERSION);
    expect_open_fails(path, TP_ERR_BAD_DATA, want);
    free(b.data);
    fixture_free(&fx);
}

/* A sound store of format 1 (the header's version and CRC32 are all a reader looks at before
 * refusing it): refused with what to do. */
TEST(older_version_says_rebuild)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    layout l = parse_layout(&b);
    put32(b.data + 8, 3);
    put32(b.data + l.header_bytes - 4, crc32_ref(b.data, l.header_bytes - 4));
    spill(path, b.data, b.size);
    expect_open_fails(path, TP_ERR_BAD_DATA,
                      "written by an older terrapatch (format 3; this one reads format 4): "
                      "rebuild it with terrapatch build");
    free(b.data);
    fixture_free(&fx);
}

TEST(other_files_are_not_stores)
{
    char tif[1024];
    REQUIRE_DATA_FILE(tif, "TP_SHARED_DATA_DIR", "storml_elev.tif");
    expect_open_fails(tif, TP_ERR_BAD_DATA, "not a terrapatch store");
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf b = slurp(path);
    b.data[1] = 'X';
    spill(path, b.data, b.size);
    expect_open_fails(path, TP_ERR_BAD_DATA, "not a terrapatch store");
    free(b.data);
    fixture_free(&fx);
}

TEST(fifo_folder_and_missing_file_refused)
{
    const char* dir = make_tmp_dir();
    char fifo[600], missing[600];
    snprintf(fifo, sizeof fifo, "%s/pipe.tpt", dir);
    snprintf(missing, sizeof missing, "%s/none.tpt", dir);
    ASSERT_TRUE(mkfifo(fifo, 0600) == 0);
    expect_open_fails(fifo, TP_ERR_IO, "FIFO");
    expect_open_fails(dir, TP_ERR_IO, "cannot open");
    expect_open_fails(missing, TP_ERR_IO, "No such file");
}

/* ---------------------------------------------------------------------------------------------
 * Writing
 */
TEST(missing_node_at_commit_fails_and_leaves_no_file)
{
    int w, h;
    char* crs;
    float* heights = read_dem("storml_elev_orig.tif", &w, &h, &crs);
    fixture fx;
    fixture_make(&fx, heights, w, h, 17);
    const char* dir = make_tmp_dir();
    char path[600];
    snprintf(path, sizeof path, "%s/m.tpt", dir);
    tp_store_header hd = fixture_header(&fx, crs);
    tp_store_writer* wr;
    tp_error err = {{0}};
    ASSERT_OK(tp_store_writer_begin(path, &hd, &wr, &err));
    const int64_t skipped = fx.order[fx.g.node_count / 3];
    for (int64_t i = 0; i < fx.g.node_count; i++)
        if (fx.order[i] != skipped)
            ASSERT_OK(tp_store_writer_add_node(wr, fx.order[i], &fx.metas[fx.order[i]],
                                               fx.q + (size_t)fx.order[i] * fx.count,
                                               FX_MASK(fx, fx.order[i]), &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_store_writer_commit(wr, &err));
    char want[64];
    snprintf(want, sizeof want, "(the first: node %lld)", (long long)skipped);
    EXPECT_CONTAINS(err.message, "1 of");
    EXPECT_CONTAINS(err.message, want);
    EXPECT_TRUE(dir_is_empty(dir));
    fixture_free(&fx);
    free(heights);
    free(crs);
}

TEST(abort_leaves_no_file)
{
    fixture fx;
    char path[600];
    small_store(&fx, path, sizeof path);
    file_buf old = slurp(path);
    for (int nodes = 0; nodes <= 2; nodes++) {
        tp_store_header hd = fixture_header(&fx, "");
        tp_store_writer* wr;
        tp_error err;
        ASSERT_OK(tp_store_writer_begin(path, &hd, &wr, &err));
        for (int64_t i = 0; i < nodes * 10; i++)
            ASSERT_OK(tp_store_writer_add_node(wr, fx.order[i], &fx.metas[fx.order[i]],
                                               fx.q + (size_t)fx.order[i] * fx.count,
                                               FX_MASK(fx, fx.order[i]), &err));
        tp_store_writer_abort(wr);
        file_buf now = slurp(path); /* the older store, byte for byte */
        EXPECT_TRUE(now.size == old.size && memcmp(now.data, old.data, old.size) == 0);
        free(now.data);
    }
    unlink(path);
    char dir[600];
    snprintf(dir, sizeof dir, "%s", path);
    *strrchr(dir, '/') = '\0';
    EXPECT_TRUE(dir_is_empty(dir));
    tp_store_writer_abort(NULL);
    free(old.data);
    fixture_free(&fx);
}

TEST(bad_nodes_refused_by_the_writer)
{
    int w, h;
    char* crs;
    float* heights = read_dem("storml_elev_orig.tif", &w, &h, &crs);
    fixture fx;
    fixture_make(&fx, heights, w, h, 17);
    char path[600];
    snprintf(path, sizeof path, "%s/b.tpt", make_tmp_dir());
    tp_store_header hd = fixture_header(&fx, crs);
    tp_store_writer* wr;
    tp_error err = {{0}};
    ASSERT_OK(tp_store_writer_begin(path, &hd, &wr, &err));
    const int64_t id = fx.order[0];
    int32_t* q = fx.q + (size_t)id * fx.count;
    tp_node_meta m = fx.metas[id];
    m.qmax = m.qmin + 2; /* its samples are outside that range */
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_store_writer_add_node(wr, id, &m, q, FX_MASK(fx, id), &err));
    EXPECT_CONTAINS(err.message, "outside the meta's range");
    m.qmax = m.qmin + 70000; /* wider than 16 bits */
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_store_writer_add_node(wr, id, &m, q, FX_MASK(fx, id), &err));
    EXPECT_CONTAINS(err.message, "wider than");
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_store_writer_add_node(wr, fx.g.node_count, &fx.metas[id], q, FX_MASK(fx, id), &err));
    EXPECT_CONTAINS(err.message, "does not exist");
    ASSERT_OK(tp_store_writer_add_node(wr, id, &fx.metas[id], q, FX_MASK(fx, id), &err));
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_store_writer_add_node(wr, id, &fx.metas[id], q, FX_MASK(fx, id), &err));
    EXPECT_CONTAINS(err.message, "added twice");
    /* the refusals changed nothing: the rest of the nodes make a sound store */
    for (int64_t i = 1; i < fx.g.node_count; i++)
        ASSERT_OK(tp_store_writer_add_node(wr, fx.order[i], &fx.metas[fx.order[i]],
                                           fx.q + (size_t)fx.order[i] * fx.count,
                                               FX_MASK(fx, fx.order[i]), &err));
    ASSERT_OK(tp_store_writer_commit(wr, &err));
    fixture_check(&fx, path, crs);
    fixture_free(&fx);
    free(heights);
    free(crs);
}

TEST(inconsistent_geometry_refused_by_the_writer)
{
    fixture fx;
    float one = 5.0f;
    fixture_make(&fx, &one, 1, 1, 17);
    const char* dir = make_tmp_dir();
    char path[600];
    snprintf(path, sizeof path, "%s/g.tpt", dir);
    tp_store_header hd = fixture_header(&fx, "");
    hd.geometry.node_count = 2;
    tp_store_writer* sentinel = (tp_store_writer*)&sentinel;
    tp_store_writer* wr = sentinel;
    tp_error err = {{0}};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_store_writer_begin(path, &hd, &wr, &err));
    EXPECT_CONTAINS(err.message, "node_count 2, expected 1");
    EXPECT_TRUE(wr == sentinel);
    hd = fixture_header(&fx, "");
    hd.geometry.n = 3;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_store_writer_begin(path, &hd, &wr, &err));
    EXPECT_TRUE(dir_is_empty(dir));
    fixture_free(&fx);
}

/* A full disk (RLIMIT_FSIZE in a child, SIGXFSZ ignored so that write() fails with EFBIG as it
 * does on ENOSPC): the write fails with TP_ERR_IO, the older store is as it was and nothing else
 * is left. The child's exit status: 0 the write failed as expected, 1 it did not fail, 2 the
 * wrong status or message. */
TEST(full_disk_leaves_no_file)
{
    int w, h;
    char* crs;
    float* heights = read_dem("lf_elev_220_mt_hood_utm.tif", &w, &h, &crs);
    fixture fx;
    fixture_make(&fx, heights, w, h, 65);
    const char* dir = make_tmp_dir();
    char path[600];
    snprintf(path, sizeof path, "%s/full.tpt", dir);
    static const uint8_t older[] = "an older file";
    spill(path, older, sizeof older);
    const rlim_t limits[] = {100, 50000, 300000};
    for (size_t li = 0; li < 3; li++) {
        fflush(NULL);
        pid_t pid = fork();
        ASSERT_TRUE(pid >= 0);
        if (pid == 0) {
            struct rlimit rl = {limits[li], limits[li]};
            signal(SIGXFSZ, SIG_IGN);
            if (setrlimit(RLIMIT_FSIZE, &rl) != 0)
                _exit(3);
            tp_store_header hd = fixture_header(&fx, crs);
            tp_store_writer* wr = NULL;
            tp_error err = {{0}};
            tp_status s = tp_store_writer_begin(path, &hd, &wr, &err);
            for (int64_t i = 0; s == TP_OK && i < fx.g.node_count; i++)
                s = tp_store_writer_add_node(wr, fx.order[i], &fx.metas[fx.order[i]],
                                             fx.q + (size_t)fx.order[i] * fx.count,
                                               FX_MASK(fx, fx.order[i]), &err);
            if (s == TP_OK)
                s = tp_store_writer_commit(wr, &err);
            else if (wr && s != TP_OK && li > 0)
                s = tp_store_writer_commit(wr, &err); /* commit after a failed add: same failure */
            if (s == TP_OK)
                _exit(1);
            _exit(s == TP_ERR_IO && strstr(err.message, path) && strstr(err.message, "File too large") ? 0 : 2);
        }
        int status = 0;
        ASSERT_TRUE(waitpid(pid, &status, 0) == pid);
        EXPECT_TRUE(WIFEXITED(status));
        EXPECT_EQ_INT(WEXITSTATUS(status), 0);
        file_buf now = slurp(path);
        EXPECT_TRUE(now.size == sizeof older && memcmp(now.data, older, sizeof older) == 0);
        free(now.data);
        DIR* d = opendir(dir);
        int entries = 0;
        struct dirent* e;
        while ((e = readdir(d)) != NULL)
            entries += e->d_name[0] != '.';
        closedir(d);
        EXPECT_EQ_INT(entries, 1); /* the older file only */
    }
    fixture_free(&fx);
    free(heights);
    free(crs);
}

/* Totals given last (tp_store_writer_set_totals: what a build knows only at the end) replace
 * the header's three fields; everything else, the nodes included, is as without them. */
TEST(totals_given_at_commit_rewrite_the_header)
{
    int w, h;
    char* crs;
    float* heights = read_dem("storml_elev_orig.tif", &w, &h, &crs);
    fixture fx;
    fixture_make(&fx, heights, w, h, 17);
    const char* dir = make_tmp_dir();
    char p1[600], p2[600];
    snprintf(p1, sizeof p1, "%s/plain.tpt", dir);
    snprintf(p2, sizeof p2, "%s/totals.tpt", dir);
    fixture_write(&fx, p1, crs);
    tp_store_header hd = fixture_header(&fx, crs);
    tp_store_writer* wr = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_store_writer_begin(p2, &hd, &wr, &err));
    tp_store_writer_set_totals(wr, 99.0, 1, 2); /* replaced by the next call */
    for (int64_t i = 0; i < fx.g.node_count; i++) {
        int64_t id = fx.order[i];
        ASSERT_OK(tp_store_writer_add_node(wr, id, &fx.metas[id], fx.q + (size_t)id * fx.count,
                                           FX_MASK(fx, id), &err));
    }
    const size_t all = (size_t)w * h;
    tp_store_writer_set_totals(wr, 0.25, all - 3, 3);
    ASSERT_OK(tp_store_writer_commit(wr, &err));
    tp_store* st = NULL;
    ASSERT_OK(tp_store_open(p2, &st, &err)); /* the rewritten header's CRC32 holds */
    tp_store_info info;
    tp_store_get_info(st, &info);
    EXPECT_EQ_DBL(0.25, info.header.quant_max_error_m);
    EXPECT_EQ_INT((long long)(all - 3), (long long)info.header.valid_samples);
    EXPECT_EQ_INT(3, (long long)info.header.nodata_samples);
    EXPECT_EQ_DBL(hd.height_step_m, info.header.height_step_m);
    tp_store_close(st);
    /* byte for byte the plain store but for those fields and the header's CRC32 */
    file_buf a = slurp(p1), b = slurp(p2);
    ASSERT_EQ_INT((long long)a.size, (long long)b.size);
    const uint32_t hsize = le32(a.data + 12);
    size_t differ = 0;
    for (size_t i = 0; i < a.size; i++) {
        int field = (i >= 120 && i < 128) || (i >= 136 && i < 152) || (i >= hsize - 4 && i < hsize);
        if (!field)
            differ += a.data[i] != b.data[i];
    }
    EXPECT_EQ_INT(0, (long long)differ);
    EXPECT_TRUE(memcmp(a.data + 120, b.data + 120, 8) != 0);
    free(a.data), free(b.data);
    fixture_free(&fx);
    free(heights);
    free(crs);
}

/* tp_file_rewrite: only bytes already written. */
TEST(file_rewrite_only_within_what_was_written)
{
    char path[600];
    snprintf(path, sizeof path, "%s/f.bin", make_tmp_dir());
    tp_file_writer* f = NULL;
    tp_error err = {{0}};
    ASSERT_OK(tp_file_begin(path, &f, &err));
    ASSERT_OK(tp_file_append(f, "abcdef", 6, &err));
    EXPECT_EQ_INT(TP_ERR_INVALID_ARG, tp_file_rewrite(f, 4, "XYZ", 3, &err));
    EXPECT_TRUE(strstr(err.message, "beyond the 6 written") != NULL);
    ASSERT_OK(tp_file_rewrite(f, 1, "XY", 2, &err));
    ASSERT_OK(tp_file_rewrite(f, 4, "ZW", 2, &err));
    ASSERT_OK(tp_file_append(f, "g", 1, &err));
    ASSERT_OK(tp_file_commit(f, &err));
    file_buf b = slurp(path);
    ASSERT_EQ_INT(7, (long long)b.size);
    EXPECT_TRUE(memcmp(b.data, "aXYdZWg", 7) == 0);
    free(b.data);
}

#define TESTS(X)                                                                                   \
    X(round_trip_n42e001_65)                                                                       \
    X(round_trip_mt_rainier_129)                                                                   \
    X(round_trip_mt_hood_nodata_33)                                                                \
    X(round_trip_storm_lake_nodata_edges_17)                                                       \
    X(round_trip_small_and_awkward_grids)                                                          \
    X(tree_builder_into_store_matches_tree_from_grid)                                              \
    X(threads_read_one_store_at_once)                                                              \
    X(flipped_node_byte_fails_that_node_only)                                                      \
    X(node_with_matching_checksum_but_wrong_content_fails)                                         \
    X(flipped_header_byte_fails_open)                                                              \
    X(flipped_table_byte_fails_open)                                                               \
    X(flipped_footer_byte_fails_open)                                                              \
    X(entry_outside_the_data_area_fails_open)                                                      \
    X(location_changed_after_open_is_checked_when_read)                                            \
    X(metas_are_mapped_from_the_file)                                                              \
    X(truncated_files_fail_clearly)                                                                \
    X(newer_version_says_so)                                                                       \
    X(older_version_says_rebuild)                                                                  \
    X(other_files_are_not_stores)                                                                  \
    X(fifo_folder_and_missing_file_refused)                                                        \
    X(missing_node_at_commit_fails_and_leaves_no_file)                                             \
    X(abort_leaves_no_file)                                                                        \
    X(bad_nodes_refused_by_the_writer)                                                             \
    X(inconsistent_geometry_refused_by_the_writer)                                                 \
    X(full_disk_leaves_no_file)                                                                    \
    X(totals_given_at_commit_rewrite_the_header)                                                   \
    X(file_rewrite_only_within_what_was_written)                                                   \
    X(stored_bytes_copied_give_the_same_file)
TP_TEST_MAIN(TESTS)
