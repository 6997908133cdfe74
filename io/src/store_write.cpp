/* store_write.cpp - writes a terrain store (.tpt; tp_io.h "Terrain stores", docs/store.md)
 * through tp_file_*: the header first, then room for the node and location tables (a hole,
 * their places follow from the header and node_count), each node's data appended as it arrives
 * (in the builder's order, children before parents) while its meta and location are written
 * into their places in the tables (tp_file_rewrite, a run of consecutive ids at a time), then
 * the footer with the tables' CRC32 (read back in small pieces). In memory: one bit per node
 * (added or not), one run of table entries and one node's scratch, never the tables or the
 * data already written. */
#include "atomic_write.hpp"
#include "io_util.hpp"
#include "store_format.hpp"
#include "tp_io.h"

#include <zstd.h>

#include <algorithm>
#include <climits>
#include <new>
#include <string>
#include <vector>

using namespace tpio::store;
using tpio::fail;

namespace {
/* zstd level of node data: docs/store.md has the measurements (level 3 is no smaller than 1
 * on terrain residuals, and decoding speed does not depend on it). */
constexpr int ZSTD_LEVEL = 1;
/* Table entries of consecutive ids written in one tp_file_rewrite (the builder emits a band's
 * leaves left to right: consecutive ids). */
constexpr size_t RUN_NODES = 512;
/* Bytes read back at a time to checksum the tables at commit. */
constexpr size_t READ_BACK_BYTES = 64 << 10;
} // namespace

struct tp_store_writer {
    std::string path;
    tp_file_writer* file = nullptr;
    tp_tree_geometry geometry;
    Tables tables;
    std::vector<bool> have;       /* node written */
    int64_t run_first = 0;        /* the run of table entries not written yet: ids run_first.. */
    size_t run_count = 0;         /* ..run_first + run_count - 1 */
    std::vector<uint8_t> run_metas, run_locs; /* RUN_NODES entries each */
    int64_t missing = 0;          /* nodes not written yet */
    uint64_t offset = 0;          /* file size so far */
    std::vector<uint8_t> head;    /* the encoded header, rewritten at commit with the totals */
    bool totals = false;          /* tp_store_writer_set_totals was called */
    bool rewrite = false;         /* tp_store_writer_set_notes was called */
    double quant_max_error_m = 0;
    uint64_t valid_samples = 0, nodata_samples = 0;
    ZSTD_CCtx* cctx = nullptr;
    std::vector<uint16_t> rel;    /* one node's samples relative to its qmin */
    std::vector<uint8_t> scratch, packed;
    tp_status failed = TP_OK;     /* a write failed: every later call returns it, */
    std::string failure;          /* with its message */
    ~tp_store_writer()
    {
        tp_file_abort(file);
        ZSTD_freeCCtx(cctx);
    }
};

namespace {

std::vector<uint8_t> encode_header(const tp_store_header* h, const std::string& crs,
                                   const std::string& notes)
{
    const size_t size = H_FIXED_BYTES + crs.size() + notes.size() + 4;
    std::vector<uint8_t> b(size, 0);
    uint8_t* p = b.data();
    std::memcpy(p + H_MAGIC, MAGIC, 8);
    put_u32(p + H_VERSION, TP_STORE_VERSION);
    put_u32(p + H_HEADER_BYTES, (uint32_t)size);
    const tp_tree_geometry& g = h->geometry;
    put_u32(p + H_N, (uint32_t)g.n);
    put_u32(p + H_SRC_WIDTH, (uint32_t)g.src_width);
    put_u32(p + H_SRC_HEIGHT, (uint32_t)g.src_height);
    put_u32(p + H_WIDTH, (uint32_t)g.width);
    put_u32(p + H_HEIGHT, (uint32_t)g.height);
    put_u32(p + H_COLS, (uint32_t)g.cols);
    put_u32(p + H_ROWS, (uint32_t)g.rows);
    put_u32(p + H_SCALES, (uint32_t)g.scales);
    put_u64(p + H_NODE_COUNT, (uint64_t)g.node_count);
    put_u64(p + H_ROOT_COUNT, (uint64_t)g.root_count);
    for (int i = 0; i < 6; ++i)
        put_f64(p + H_GEOTRANSFORM + 8 * i, h->geotransform[i]);
    put_f64(p + H_HEIGHT_STEP, h->height_step_m);
    put_f64(p + H_QUANT_MAX_ERROR, h->quant_max_error_m);
    put_f64(p + H_ERR_UNIT, h->err_unit_steps);
    put_u64(p + H_VALID_SAMPLES, (uint64_t)h->valid_samples);
    put_u64(p + H_NODATA_SAMPLES, (uint64_t)h->nodata_samples);
    put_u32(p + H_CRS_BYTES, (uint32_t)crs.size());
    put_u32(p + H_NOTES_BYTES, (uint32_t)notes.size());
    std::memcpy(p + H_FIXED_BYTES, crs.data(), crs.size());
    std::memcpy(p + H_FIXED_BYTES + crs.size(), notes.data(), notes.size());
    put_u32(p + size - 4, crc32_of(p, size - 4));
    return b;
}

/* The node table's entry of m: the tp_node_meta's own bytes with every byte the format does
 * not use (pad_, delta[k > n], eps[][kn >= n], the trailing padding) 0. */
void encode_meta(uint8_t* e, int n, const tp_node_meta* m)
{
    tp_node_meta z;
    std::memset(&z, 0, sizeof z);
    z.qmin = m->qmin;
    z.qmax = m->qmax;
    z.area_qmin = m->area_qmin;
    z.area_qmax = m->area_qmax;
    z.flags = m->flags;
    for (int k = 0; k <= n; ++k)
        z.delta[k] = m->delta[k];
    for (int side = 0; side < 4; ++side)
        for (int k = 0; k < n; ++k)
            z.eps[side][k] = m->eps[side][k];
    std::memset(e, 0, META_BYTES); /* the padding, whatever the assignments did to z's */
    std::memcpy(e, &z, META_USED_BYTES);
}

void encode_loc(uint8_t* e, uint64_t offset, uint32_t bytes, uint32_t crc, Codec codec)
{
    std::memset(e, 0, LOC_BYTES);
    put_u64(e + L_OFFSET, offset);
    put_u32(e + L_BYTES, bytes);
    put_u32(e + L_CRC, crc);
    e[L_CODEC] = codec;
}

/* Remembers a write failure, so that later calls and commit report it too. */
tp_status note(tp_store_writer* w, tp_status s, const tp_error* err)
{
    if (s != TP_OK && s != TP_ERR_INVALID_ARG) {
        w->failed = s;
        try {
            w->failure = err ? err->message : w->path + ": cannot write";
        } catch (...) {
        }
    }
    return s;
}

/* Writes the run of table entries into their places. */
tp_status flush_run(tp_store_writer* w, tp_error* err)
{
    if (w->run_count == 0)
        return TP_OK;
    const uint64_t first = (uint64_t)w->run_first;
    tp_status s = tp_file_rewrite(w->file, w->tables.meta_offset + first * META_BYTES,
                                  w->run_metas.data(), w->run_count * META_BYTES, err);
    if (s == TP_OK)
        s = tp_file_rewrite(w->file, w->tables.loc_offset + first * LOC_BYTES,
                            w->run_locs.data(), w->run_count * LOC_BYTES, err);
    w->run_count = 0;
    return note(w, s, err);
}

/* CRC32 of bytes offset .. offset + size - 1 of what was written, read back in small pieces. */
tp_status crc_read_back(tp_store_writer* w, uint64_t offset, uint64_t size, uint32_t* out,
                        tp_error* err)
{
    std::vector<uint8_t> buf((size_t)std::min<uint64_t>(size, READ_BACK_BYTES));
    uint32_t crc = crc32_of(nullptr, 0);
    for (uint64_t done = 0; done < size;) {
        const size_t piece = (size_t)std::min<uint64_t>(size - done, buf.size());
        const tp_status s = tpio::file_read_back(w->file, offset + done, buf.data(), piece, err);
        if (s != TP_OK)
            return note(w, s, err);
        crc = crc32_continue(crc, buf.data(), piece);
        done += piece;
    }
    *out = crc;
    return TP_OK;
}

/* What every added node is checked for: a writer that has not failed, a node that exists and
 * was not added, known flags. */
tp_status check_node(const tp_store_writer* w, int64_t node, const tp_node_meta* meta,
                     tp_error* err)
{
    const char* path = w->path.c_str();
    if (w->failed != TP_OK)
        return fail(err, w->failed, "%s", w->failure.empty() ? path : w->failure.c_str());
    const tp_tree_geometry& g = w->geometry;
    if (node < 0 || node >= g.node_count)
        return fail(err, TP_ERR_INVALID_ARG, "%s: node %lld does not exist (%lld nodes)", path,
                    (long long)node, (long long)g.node_count);
    if (w->have[(size_t)node])
        return fail(err, TP_ERR_INVALID_ARG, "%s: node %lld added twice", path, (long long)node);
    if (meta->flags & ~KNOWN_FLAGS)
        return fail(err, TP_ERR_INVALID_ARG, "%s: node %lld: unknown meta flags 0x%02x", path,
                    (long long)node, meta->flags);
    return TP_OK;
}

/* Appends a node's stored bytes and writes its table entries into the run (flushed when the
 * ids stop running on). */
tp_status append_node(tp_store_writer* w, int64_t node, const tp_node_meta* meta,
                      const uint8_t* bytes, size_t size, uint32_t crc, Codec codec, tp_error* err)
{
    const tp_status s = tp_file_append(w->file, bytes, size, err);
    if (s != TP_OK)
        return note(w, s, err);
    if (w->run_count > 0 &&
        (w->run_count == RUN_NODES || node != w->run_first + (int64_t)w->run_count)) {
        const tp_status fs = flush_run(w, err);
        if (fs != TP_OK)
            return fs;
    }
    if (w->run_count == 0)
        w->run_first = node;
    encode_meta(w->run_metas.data() + w->run_count * META_BYTES, w->geometry.n, meta);
    encode_loc(w->run_locs.data() + w->run_count * LOC_BYTES, w->offset, (uint32_t)size, crc,
               codec);
    ++w->run_count;
    w->offset += size;
    w->have[(size_t)node] = true;
    --w->missing;
    return TP_OK;
}

} // namespace

extern "C" tp_status tp_store_writer_begin(const char* path, const tp_store_header* header,
                                           tp_store_writer** out, tp_error* err)
{
    if (!path || !header || !out)
        return fail(err, TP_ERR_INVALID_ARG, "store: bad arguments (path, header or out is NULL)");
    if (!host_little_endian())
        return fail(err, TP_ERR_BACKEND,
                    "%s: stores of format %d are written on little-endian hosts only (their node "
                    "table is the in-memory one); this host is big-endian",
                    path, TP_STORE_VERSION);
    tp_store_writer* w = nullptr;
    try {
        const tp_tree_geometry& g = header->geometry;
        tp_tree_geometry want;
        std::string why;
        if (!geometry_for(g.n, g.src_width, g.src_height, &want))
            return fail(err, TP_ERR_INVALID_ARG,
                        "%s: store geometry out of range (n %d, source %d x %d)", path, g.n,
                        g.src_width, g.src_height);
        if (!geometry_same(g, want, &why))
            return fail(err, TP_ERR_INVALID_ARG, "%s: inconsistent store geometry: %s", path,
                        why.c_str());
        const std::string crs = header->crs_wkt ? header->crs_wkt : "";
        const std::string notes = header->notes ? header->notes : "";
        if (crs.size() > MAX_STRING_BYTES || notes.size() > MAX_STRING_BYTES)
            return fail(err, TP_ERR_INVALID_ARG, "%s: CRS or notes longer than %u bytes", path,
                        (unsigned)MAX_STRING_BYTES);
        const std::vector<uint8_t> head = encode_header(header, crs, notes);

        w = new tp_store_writer;
        w->path = path;
        w->geometry = g;
        w->tables = tables_at(head.size(), (uint64_t)g.node_count);
        w->have.assign((size_t)g.node_count, false);
        w->run_metas.resize(RUN_NODES * META_BYTES);
        w->run_locs.resize(RUN_NODES * LOC_BYTES);
        w->missing = g.node_count;
        w->rel.resize(sample_count(g.n));
        w->cctx = ZSTD_createCCtx();
        if (!w->cctx)
            throw std::bad_alloc();
        tp_status s = tp_file_begin(path, &w->file, err);
        if (s == TP_OK)
            s = tp_file_append(w->file, head.data(), head.size(), err);
        if (s == TP_OK) /* the tables' room: a hole until their entries arrive */
            s = tpio::file_reserve(w->file, w->tables.data_offset - head.size(), err);
        if (s != TP_OK) {
            delete w;
            return s;
        }
        w->offset = w->tables.data_offset;
        w->head = head;
        *out = w;
        return TP_OK;
    } catch (...) {
        delete w;
        return tpio::caught(err, path);
    }
}

extern "C" tp_status tp_store_writer_add_node(tp_store_writer* w, int64_t node,
                                              const tp_node_meta* meta, const int32_t* q,
                                              const uint16_t* mask, tp_error* err)
{
    return tp_store_writer_add_node_filled(w, node, meta, q, mask, nullptr, err);
}

extern "C" tp_status tp_store_writer_add_node_filled(tp_store_writer* w, int64_t node,
                                                     const tp_node_meta* meta, const int32_t* q,
                                                     const uint16_t* mask,
                                                     const uint16_t* filled, tp_error* err)
{
    if (!w || !meta || !q)
        return fail(err, TP_ERR_INVALID_ARG, "store: bad arguments (writer, meta or q is NULL)");
    const char* path = w->path.c_str();
    if (const tp_status s = check_node(w, node, meta, err))
        return s;
    const tp_tree_geometry& g = w->geometry;
    int scale, col, row;
    node_locate(g, node, &scale, &col, &row);
    const bool with_mask = stores_mask(*meta, scale);
    if (with_mask && !mask)
        return fail(err, TP_ERR_INVALID_ARG,
                    "%s: node %lld: a node of scale %d drawn in part needs its cell mask", path,
                    (long long)node, scale);
    const bool with_filled = stores_filled(*meta);
    if (with_filled != (filled != nullptr))
        return fail(err, TP_ERR_INVALID_ARG,
                    "%s: node %lld: %s", path, (long long)node,
                    with_filled ? "a node marked TP_NODE_HAS_FILLED needs its filled bits"
                                : "filled bits given for a node not marked TP_NODE_HAS_FILLED");
    try {
        /* relative to qmin, every drawn sample within [qmin, qmax], a range that fits below
         * TP_TREE_NO_HEIGHT */
        const size_t count = sample_count(g.n);
        const int64_t qmin = meta->qmin, qmax = meta->qmax;
        if (qmin <= qmax && qmax - qmin >= (int64_t)TP_TREE_NO_HEIGHT)
            return fail(err, TP_ERR_INVALID_ARG,
                        "%s: node %lld: height range %lld .. %lld is wider than %u steps", path,
                        (long long)node, (long long)qmin, (long long)qmax,
                        (unsigned)TP_TREE_NO_HEIGHT - 1);
        for (size_t k = 0; k < count; ++k) {
            if (q[k] == INT32_MIN) {
                w->rel[k] = TP_TREE_NO_HEIGHT;
            } else if (q[k] < qmin || q[k] > qmax) {
                return fail(err, TP_ERR_INVALID_ARG,
                            "%s: node %lld: sample %zu is %d, outside the meta's range %lld .. %lld",
                            path, (long long)node, k, q[k], (long long)qmin, (long long)qmax);
            } else {
                w->rel[k] = (uint16_t)(q[k] - qmin);
            }
        }
        if (with_filled) { /* set on drawn samples only, and at least one */
            const size_t words = tp_node_filled_words(g.n);
            bool any = false;
            for (size_t k = 0; k < count; ++k)
                if (filled[k >> 4] >> (k & 15) & 1) {
                    if (q[k] == INT32_MIN)
                        return fail(err, TP_ERR_INVALID_ARG,
                                    "%s: node %lld: sample %zu is marked filled but not drawn",
                                    path, (long long)node, k);
                    any = true;
                }
            for (size_t k = count; k < 16 * words; ++k)
                if (filled[k >> 4] >> (k & 15) & 1)
                    return fail(err, TP_ERR_INVALID_ARG,
                                "%s: node %lld: filled bit %zu is past its %zu samples", path,
                                (long long)node, k, count);
            if (!any)
                return fail(err, TP_ERR_INVALID_ARG,
                            "%s: node %lld: marked TP_NODE_HAS_FILLED but no sample is filled",
                            path, (long long)node);
        }
        const int side = (1 << g.n) + 1;
        const Codec codec =
            encode_node(w->rel.data(), side, ZSTD_LEVEL, w->cctx, &w->scratch, &w->packed);
        if (with_mask) {
            const size_t at = w->packed.size(), words = tp_node_mask_words(g.n);
            w->packed.resize(at + mask_bytes(g.n));
            for (size_t k = 0; k < words; ++k)
                put_u16(w->packed.data() + at + 2 * k, mask[k]);
        }
        if (with_filled) {
            const size_t at = w->packed.size();
            encode_filled(filled, tp_node_filled_words(g.n), ZSTD_LEVEL, w->cctx, &w->packed);
            const size_t frame = w->packed.size() - at;
            w->packed.resize(w->packed.size() + 4);
            put_u32(w->packed.data() + w->packed.size() - 4, (uint32_t)frame);
        }
        return append_node(w, node, meta, w->packed.data(), w->packed.size(),
                           crc32_of(w->packed.data(), w->packed.size()), codec, err);
    } catch (...) {
        return note(w, tpio::caught(err, path), err);
    }
}

extern "C" tp_status tp_store_writer_add_stored(tp_store_writer* w, int64_t node,
                                                const tp_node_meta* meta,
                                                const tp_store_stored* stored, tp_error* err)
{
    if (!w || !meta || !stored || !stored->bytes)
        return fail(err, TP_ERR_INVALID_ARG, "store: bad arguments (writer, meta or bytes NULL)");
    const char* path = w->path.c_str();
    if (const tp_status s = check_node(w, node, meta, err))
        return s;
    const int n = w->geometry.n;
    if ((stored->codec != CODEC_RAW && stored->codec != CODEC_PLANAR_ZSTD) || stored->size == 0 ||
        stored->size > max_stored_bytes(n))
        return fail(err, TP_ERR_INVALID_ARG, "%s: node %lld: codec %d, %zu bytes: not a node's",
                    path, (long long)node, stored->codec, stored->size);
    const uint32_t crc = crc32_of(stored->bytes, stored->size);
    if (crc != stored->crc)
        return fail(err, TP_ERR_BAD_DATA, "%s: node %lld: its bytes do not match their CRC32",
                    path, (long long)node);
    try {
        return append_node(w, node, meta, stored->bytes, stored->size, crc, (Codec)stored->codec,
                           err);
    } catch (...) {
        return note(w, tpio::caught(err, path), err);
    }
}

extern "C" tp_status tp_store_writer_commit(tp_store_writer* w, tp_error* err)
{
    if (!w)
        return fail(err, TP_ERR_INVALID_ARG, "store: bad arguments (writer is NULL)");
    tp_status s = TP_OK;
    try {
        const char* path = w->path.c_str();
        if (w->failed != TP_OK) {
            s = fail(err, w->failed, "%s", w->failure.empty() ? path : w->failure.c_str());
        } else if (w->missing > 0) {
            int64_t first = 0;
            while (w->have[(size_t)first])
                ++first;
            s = fail(err, TP_ERR_INVALID_ARG,
                     "%s: %lld of %lld nodes were not added (the first: node %lld); not written",
                     path, (long long)w->missing, (long long)w->geometry.node_count,
                     (long long)first);
        } else {
            const Tables& t = w->tables;
            uint32_t meta_crc = 0, loc_crc = 0;
            s = flush_run(w, err);
            if (s == TP_OK)
                s = crc_read_back(w, t.meta_offset, t.meta_bytes, &meta_crc, err);
            if (s == TP_OK)
                s = crc_read_back(w, t.loc_offset, t.loc_bytes, &loc_crc, err);
            uint8_t footer[FOOTER_BYTES] = {0};
            put_u64(footer + F_META_OFFSET, t.meta_offset);
            put_u64(footer + F_META_BYTES, t.meta_bytes);
            put_u64(footer + F_LOC_OFFSET, t.loc_offset);
            put_u64(footer + F_LOC_BYTES, t.loc_bytes);
            put_u32(footer + F_META_CRC, meta_crc);
            put_u32(footer + F_LOC_CRC, loc_crc);
            put_u32(footer + F_FOOTER_CRC, crc32_of(footer, F_FOOTER_CRC));
            std::memcpy(footer + F_END_MAGIC, END_MAGIC, 8);
            if (s == TP_OK)
                s = tp_file_append(w->file, footer, sizeof footer, err);
            if (s == TP_OK && (w->totals || w->rewrite)) {
                uint8_t* h = w->head.data();
                if (w->totals) {
                    put_f64(h + H_QUANT_MAX_ERROR, w->quant_max_error_m);
                    put_u64(h + H_VALID_SAMPLES, w->valid_samples);
                    put_u64(h + H_NODATA_SAMPLES, w->nodata_samples);
                }
                put_u32(h + w->head.size() - 4, crc32_of(h, w->head.size() - 4));
                s = tp_file_rewrite(w->file, 0, h, w->head.size(), err);
            }
            if (s == TP_OK) {
                tp_file_writer* file = w->file;
                w->file = nullptr; /* commit frees it, whatever happens */
                s = tp_file_commit(file, err);
            }
        }
    } catch (...) {
        s = tpio::caught(err, w->path.c_str());
    }
    delete w; /* aborts the file unless committed */
    return s;
}

extern "C" void tp_store_writer_set_totals(tp_store_writer* w, double quant_max_error_m,
                                           size_t valid_samples, size_t nodata_samples)
{
    if (!w)
        return;
    w->totals = true;
    w->quant_max_error_m = quant_max_error_m;
    w->valid_samples = valid_samples;
    w->nodata_samples = nodata_samples;
}

extern "C" tp_status tp_store_writer_set_notes(tp_store_writer* w, const char* notes,
                                               tp_error* err)
{
    if (!w || !notes)
        return fail(err, TP_ERR_INVALID_ARG, "store: bad arguments (w or notes is NULL)");
    uint8_t* h = w->head.data();
    const uint32_t crs_bytes = get_u32(h + H_CRS_BYTES), notes_bytes = get_u32(h + H_NOTES_BYTES);
    if (std::strlen(notes) != notes_bytes)
        return fail(err, TP_ERR_INVALID_ARG, "%s: new notes of %zu bytes for %u", w->path.c_str(),
                    std::strlen(notes), notes_bytes);
    std::memcpy(h + H_FIXED_BYTES + crs_bytes, notes, notes_bytes);
    w->rewrite = true;
    return TP_OK;
}

extern "C" void tp_store_writer_abort(tp_store_writer* w) { delete w; }
