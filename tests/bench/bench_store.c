/* bench_store.c - how to store a node's samples (docs/store.md, "Node data"): bytes per source
 * sample and decode time per node of candidate codecs, then of the real store (not a test; not
 * run by ctest).
 *
 *   build/tp_bench_store [patch_size] DEM...
 *
 * Each DEM (integer heights, so a 1 m step) is cut into the nodes of every scale as tp_core.h's
 * "Hierarchy" defines them (padding and nodata = TP_TREE_NO_HEIGHT, samples relative to the
 * node's minimum). Candidates: raw uint16; zstd of the raw bytes; a predictor (left neighbour,
 * planar left+up-upleft, or LOCO-I's median edge detector), zigzag, byte planes, zstd at levels
 * 1, 3 and 9. "B/sample" counts every node (the hierarchy included) over the source samples;
 * "decode" is the median over the leaves of one node's decode (zstd + inverse predictor).
 * Then the real thing: every node through tp_store_writer, the file's bytes per source sample,
 * and the median time of tp_store_read_node (pread + CRC32 + decode) per leaf. */
#define _POSIX_C_SOURCE 200809L
#include "tp_io.h"
#include "../tp_test_tree.h"
#include "bench_util.h"

#include <zstd.h>

#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum { PRED_NONE_RAW, PRED_NONE, PRED_LEFT, PRED_PLANAR, PRED_MED };
static const char* const pred_names[] = {"raw", "zstd", "left", "planar", "med"};

static uint16_t predict(int pred, const uint16_t* row, const uint16_t* up, int i)
{
    if (!up)
        return i > 0 ? row[i - 1] : 0;
    if (i == 0 || pred == PRED_LEFT)
        return i == 0 ? up[0] : row[i - 1];
    int a = row[i - 1], b = up[i], c = up[i - 1];
    if (pred == PRED_PLANAR)
        return (uint16_t)(a + b - c);
    int lo = a < b ? a : b, hi = a < b ? b : a;
    return (uint16_t)(c >= hi ? lo : c <= lo ? hi : a + b - c);
}

/* Encodes v (side x side) into out (capacity cap): bytes written. */
static size_t encode(int pred, int level, const uint16_t* v, int side, uint8_t* planes,
                     uint8_t* out, size_t cap, ZSTD_CCtx* cctx)
{
    size_t count = (size_t)side * side;
    if (pred == PRED_NONE_RAW)
        return 2 * count;
    for (int j = 0; j < side; j++)
        for (int i = 0; i < side; i++) {
            size_t k = (size_t)j * side + i;
            uint16_t z;
            if (pred == PRED_NONE) {
                planes[2 * k] = (uint8_t)v[k], planes[2 * k + 1] = (uint8_t)(v[k] >> 8);
                continue;
            }
            uint16_t r = (uint16_t)(v[k] - predict(pred, v + (size_t)j * side,
                                                   j ? v + (size_t)(j - 1) * side : NULL, i));
            z = (uint16_t)((uint16_t)(r << 1) ^ ((r & 0x8000u) ? 0xFFFFu : 0u));
            planes[k] = (uint8_t)z, planes[count + k] = (uint8_t)(z >> 8);
        }
    size_t got = ZSTD_compressCCtx(cctx, out, cap, planes, 2 * count, level);
    if (ZSTD_isError(got)) {
        fprintf(stderr, "zstd: %s\n", ZSTD_getErrorName(got));
        exit(1);
    }
    return got;
}

static void decode(int pred, const uint8_t* in, size_t size, int side, uint8_t* planes,
                   uint16_t* v, ZSTD_DCtx* dctx)
{
    size_t count = (size_t)side * side;
    if (pred == PRED_NONE_RAW) {
        memcpy(v, in, size);
        return;
    }
    if (ZSTD_decompressDCtx(dctx, planes, 2 * count, in, size) != 2 * count)
        exit(1);
    if (pred == PRED_NONE) {
        for (size_t k = 0; k < count; k++)
            v[k] = (uint16_t)(planes[2 * k] | planes[2 * k + 1] << 8);
        return;
    }
    for (int j = 0; j < side; j++) {
        uint16_t* row = v + (size_t)j * side;
        const uint16_t* up = j ? row - side : NULL;
        for (int i = 0; i < side; i++) {
            size_t k = (size_t)j * side + i;
            uint16_t z = (uint16_t)(planes[k] | planes[count + k] << 8);
            row[i] = (uint16_t)(predict(pred, row, up, i) + ((z >> 1) ^ (uint16_t)(0u - (z & 1u))));
        }
    }
}

typedef struct node {
    int64_t id;
    int scale;
    int32_t qmin, qmax;
    int32_t* q;    /* global quantised, INT32_MIN = not drawn */
    uint16_t* rel; /* relative to qmin */
} node;

int main(int argc, char** argv)
{
    int a = 1, patch = 65;
    if (argc > 1 && atoi(argv[1]) > 0)
        patch = atoi(argv[a++]);
    if (a >= argc) {
        fprintf(stderr, "usage: %s [patch_size] DEM...\n", argv[0]);
        return 2;
    }
    const int side = patch, n = (int)lround(log2(patch - 1));
    const size_t count = (size_t)side * side;
    ZSTD_CCtx* cctx = ZSTD_createCCtx();
    ZSTD_DCtx* dctx = ZSTD_createDCtx();
    uint8_t* planes = malloc(2 * count);
    size_t cap = ZSTD_compressBound(2 * count);
    uint8_t* packed = malloc(cap);
    uint16_t* back = malloc(2 * count);
    printf("%-34s %-8s %5s %9s %11s\n", "DEM", "codec", "level", "B/sample", "decode_us");
    for (; a < argc; a++) {
        tp_dem* dem;
        tp_error err;
        if (tp_dem_read(argv[a], &dem, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
        const char* base = strrchr(argv[a], '/') ? strrchr(argv[a], '/') + 1 : argv[a];
        const int w = dem->width, h = dem->height, step = 1 << n;
        int cols = w > 1 ? (w - 1 + step - 1) / step : 1, rows = h > 1 ? (h - 1 + step - 1) / step : 1;
        int scales = 0;
        while ((cols >> scales) >= 1 && (rows >> scales) >= 1)
            scales++;
        size_t node_count = 0;
        for (int s = 0; s < scales; s++)
            node_count += (size_t)(cols >> s) * (size_t)(rows >> s);
        node* nodes = calloc(node_count, sizeof *nodes);
        /* ids from the top scale down (tp_core.h), listed leaves first as the builder emits */
        size_t k = 0;
        int64_t first = 0;
        int64_t first_node[32];
        for (int s = scales - 1; s >= 0; s--) {
            first_node[s] = first;
            first += (int64_t)(cols >> s) * (rows >> s);
        }
        for (int s = 0; s < scales; s++)
            for (int r = 0; r < (rows >> s); r++)
                for (int c = 0; c < (cols >> s); c++, k++) {
                    node* nd = &nodes[k];
                    nd->id = first_node[s] + (int64_t)r * (cols >> s) + c;
                    nd->scale = s;
                    nd->q = malloc(count * sizeof *nd->q);
                    nd->rel = malloc(count * sizeof *nd->rel);
                    nd->qmin = INT32_MAX, nd->qmax = INT32_MIN;
                    for (int j = 0; j < side; j++)
                        for (int i = 0; i < side; i++) {
                            long x = ((long)c << (n + s)) + ((long)i << s);
                            long y = ((long)r << (n + s)) + ((long)j << s);
                            float v = x < w && y < h ? dem->heights[y * w + x] : NAN;
                            int32_t q = isnan(v) ? INT32_MIN : (int32_t)lrintf(v);
                            nd->q[j * side + i] = q;
                            if (q != INT32_MIN) {
                                nd->qmin = q < nd->qmin ? q : nd->qmin;
                                nd->qmax = q > nd->qmax ? q : nd->qmax;
                            }
                        }
                    for (size_t t = 0; t < count; t++)
                        nd->rel[t] = nd->q[t] == INT32_MIN ? TP_TREE_NO_HEIGHT
                                                           : (uint16_t)(nd->q[t] - nd->qmin);
                }
        const double src = (double)w * h;
        const size_t leaves = (size_t)cols * rows;
        double* times = malloc(leaves * sizeof *times);
        static const int configs[][2] = {{PRED_NONE_RAW, 0}, {PRED_NONE, 1},   {PRED_NONE, 3},
                                         {PRED_LEFT, 1},     {PRED_LEFT, 3},   {PRED_PLANAR, 1},
                                         {PRED_PLANAR, 3},   {PRED_MED, 1},    {PRED_MED, 3},
                                         {PRED_MED, 9}};
        for (size_t ci = 0; ci < sizeof configs / sizeof configs[0]; ci++) {
            int pred = configs[ci][0], level = configs[ci][1];
            double bytes = 0;
            for (size_t t = 0; t < node_count; t++) {
                size_t got = encode(pred, level, nodes[t].rel, side, planes, packed, cap, cctx);
                bytes += (double)got;
                if (nodes[t].scale == 0) {
                    if (pred == PRED_NONE_RAW)
                        memcpy(packed, nodes[t].rel, 2 * count);
                    double best = 1e30; /* min of 3: the machine is shared */
                    for (int rep = 0; rep < 3; rep++) {
                        double t0 = (1e3 * bench_now_ms());
                        decode(pred, packed, got, side, planes, back, dctx);
                        double dt = (1e3 * bench_now_ms()) - t0;
                        best = dt < best ? dt : best;
                    }
                    if (memcmp(back, nodes[t].rel, 2 * count) != 0) {
                        fprintf(stderr, "%s: round trip failed\n", pred_names[pred]);
                        return 1;
                    }
                    times[t] = best;
                }
            }
            printf("%-34s %-8s %5d %9.3f %11.1f\n", base, pred_names[pred], level, bytes / src,
                   bench_median(times, leaves));
        }

        /* The real store, written in the builder's order (leaves first). */
        char path[] = "/tmp/tp_bench_store_XXXXXX";
        int fd = mkstemp(path);
        close(fd);
        tp_store_header hd;
        memset(&hd, 0, sizeof hd);
        if (!tpt_tree_geometry(w, h, patch, &hd.geometry)) {
            fprintf(stderr, "bad size\n");
            return 1;
        }
        memcpy(hd.geotransform, dem->geotransform, sizeof hd.geotransform);
        hd.height_step_m = 1, hd.err_unit_steps = 1.0 / 16;
        hd.valid_samples = (size_t)w * h - dem->void_count, hd.nodata_samples = dem->void_count;
        hd.crs_wkt = dem->crs_wkt, hd.notes = argv[a];
        tp_store_writer* sw;
        double t0 = (1e3 * bench_now_ms());
        if (tp_store_writer_begin(path, &hd, &sw, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
        for (size_t t = 0; t < node_count; t++) {
            tp_node_meta m;
            memset(&m, 0, sizeof m);
            m.qmin = nodes[t].qmin, m.qmax = nodes[t].qmax;
            if (tp_store_writer_add_node(sw, nodes[t].id, &m, nodes[t].q, NULL, &err) != TP_OK) {
                fprintf(stderr, "%s\n", err.message);
                return 1;
            }
        }
        if (tp_store_writer_commit(sw, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
        double write_ms = ((1e3 * bench_now_ms()) - t0) / 1e3;
        tp_store* st;
        if (tp_store_open(path, &st, &err) != TP_OK) {
            fprintf(stderr, "%s\n", err.message);
            return 1;
        }
        tp_store_info info;
        tp_store_get_info(st, &info);
        for (size_t t = 0; t < leaves; t++) {
            double best = 1e30;
            for (int rep = 0; rep < 3; rep++) {
                double t1 = (1e3 * bench_now_ms());
                if (tp_store_read_node(st, nodes[t].id, back, count, &err) != TP_OK) {
                    fprintf(stderr, "%s\n", err.message);
                    return 1;
                }
                double dt = (1e3 * bench_now_ms()) - t1;
                best = dt < best ? dt : best;
            }
            times[t] = best;
        }
        printf("%-34s %-8s %5s %9.3f %11.1f  (file %llu bytes: data %llu, table %llu; %zu nodes; "
               "written in %.0f ms)\n",
               base, "store", "-", info.bytes_per_sample, bench_median(times, leaves),
               (unsigned long long)info.file_bytes, (unsigned long long)info.data_bytes,
               (unsigned long long)info.table_bytes, node_count, write_ms);
        tp_store_close(st);
        unlink(path);
        for (size_t t = 0; t < node_count; t++)
            free(nodes[t].q), free(nodes[t].rel);
        free(nodes);
        free(times);
        tp_dem_destroy(dem);
    }
    free(planes), free(packed), free(back);
    ZSTD_freeCCtx(cctx);
    ZSTD_freeDCtx(dctx);
    return 0;
}
