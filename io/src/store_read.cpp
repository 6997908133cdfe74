/* store_read.cpp - opens a terrain store (.tpt; tp_io.h "Terrain stores", docs/store.md) and
 * reads its nodes. tp_store_open reads and checks the header, the footer and the node table and
 * keeps them (decoded) in memory; tp_store_read_node reads one node with pread, so any number
 * of threads can read at once: the store is not changed after open, and each thread keeps its
 * own zstd context and buffers (thread_local), reused from one node to the next. */
#include "io_util.hpp"
#include "store_format.hpp"
#include "tp_io.h"

#include <zstd.h>

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <cinttypes>
#include <memory>
#include <string>
#include <vector>

using namespace tpio::store;
using tpio::fail;

namespace {
struct Entry {
    uint64_t offset;
    uint32_t bytes, crc;
    Codec codec;
};
} // namespace

struct tp_store {
    std::string path;
    int fd = -1;
    uint32_t version = 0;
    uint64_t file_bytes = 0, header_bytes = 0, table_offset = 0, table_bytes = 0;
    tp_store_header header;
    std::string crs, notes;
    std::vector<tp_node_meta> metas;
    std::vector<Entry> entries;
    ~tp_store()
    {
        if (fd >= 0)
            close(fd);
    }
};

namespace {

/* All of size bytes at offset, or an errno (EIO for a file that ended early: it shrank). */
int read_at(int fd, void* buf, size_t size, uint64_t offset)
{
    uint8_t* p = static_cast<uint8_t*>(buf);
    while (size > 0) {
        const ssize_t got = pread(fd, p, size, (off_t)offset);
        if (got < 0) {
            if (errno == EINTR)
                continue;
            return errno;
        }
        if (got == 0)
            return EIO;
        p += got;
        size -= (size_t)got;
        offset += (uint64_t)got;
    }
    return 0;
}

/* One reading thread's zstd context and buffers. */
struct ThreadScratch {
    ZSTD_DCtx* dctx = nullptr;
    std::vector<uint8_t> stored, planes;
    std::vector<uint16_t> samples;
    ~ThreadScratch() { ZSTD_freeDCtx(dctx); }
};
thread_local ThreadScratch t_scratch;

std::string node_name(const tp_store* s, int64_t node)
{
    int sc, c, r;
    node_locate(s->header.geometry, node, &sc, &c, &r);
    return "node " + std::to_string(node) + " (scale " + std::to_string(sc) + ", column " +
           std::to_string(c) + ", row " + std::to_string(r) + ")";
}

/* The checks of tp_store_open after the file is open; fills s. */
tp_status load(tp_store* s, tp_error* err)
{
    const char* path = s->path.c_str();
    uint8_t fixed[H_FIXED_BYTES];
    const size_t first = (size_t)std::min<uint64_t>(s->file_bytes, sizeof fixed);
    if (int e = read_at(s->fd, fixed, first, 0))
        return fail(err, TP_ERR_IO, "%s: cannot read: %s", path, std::strerror(e));
    if (first < sizeof MAGIC || std::memcmp(fixed, MAGIC, sizeof MAGIC) != 0)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: not a terrapatch store (.tpt): its first bytes are not the store's "
                    "signature",
                    path);
    if (first < H_FIXED_BYTES)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated: %" PRIu64 " bytes, a store's header alone takes %zu", path,
                    s->file_bytes, (size_t)H_FIXED_BYTES + 4);
    /* The header's size and CRC first: they keep their places in every version, so a damaged
     * version number is reported as damage, and only a sound header's version is believed. */
    const uint32_t header_bytes = get_u32(fixed + H_HEADER_BYTES);
    if (header_bytes < H_FIXED_BYTES + 4 || header_bytes > H_FIXED_BYTES + 4 + 2 * MAX_STRING_BYTES)
        return fail(err, TP_ERR_BAD_DATA, "%s: damaged header: it claims %u bytes", path,
                    header_bytes);
    if (header_bytes > s->file_bytes)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated: %" PRIu64 " bytes, but the header alone takes %u", path,
                    s->file_bytes, header_bytes);
    std::vector<uint8_t> head(header_bytes);
    if (int e = read_at(s->fd, head.data(), head.size(), 0))
        return fail(err, TP_ERR_IO, "%s: cannot read the header: %s", path, std::strerror(e));
    const uint8_t* h = head.data();
    const uint32_t head_crc = crc32_of(h, header_bytes - 4);
    if (head_crc != get_u32(h + header_bytes - 4))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged header: checksum mismatch in bytes 0..%u (stored 0x%08x, "
                    "computed 0x%08x)",
                    path, header_bytes - 1, get_u32(h + header_bytes - 4), head_crc);
    s->version = get_u32(h + H_VERSION);
    if (s->version > TP_STORE_VERSION)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: written by a newer terrapatch (format %u; this one reads up to %d)", path,
                    s->version, TP_STORE_VERSION);
    if (s->version == 0)
        return fail(err, TP_ERR_BAD_DATA, "%s: damaged header: format version 0", path);
    s->header_bytes = header_bytes;

    /* Geometry: recomputed from n and the source size; every stored count must agree. */
    tp_tree_geometry& g = s->header.geometry;
    const uint32_t n = get_u32(h + H_N), sw = get_u32(h + H_SRC_WIDTH),
                   sh = get_u32(h + H_SRC_HEIGHT);
    if (n > 64 || sw > INT32_MAX || sh > INT32_MAX ||
        !geometry_for((int)n, (int)sw, (int)sh, &g))
        return fail(err, TP_ERR_BAD_DATA, "%s: bad geometry: node size 2^%u+1, source %u x %u",
                    path, n, sw, sh);
    tp_tree_geometry stored = g;
    stored.width = (int)get_u32(h + H_WIDTH);
    stored.height = (int)get_u32(h + H_HEIGHT);
    stored.cols = (int)get_u32(h + H_COLS);
    stored.rows = (int)get_u32(h + H_ROWS);
    stored.scales = (int)get_u32(h + H_SCALES);
    stored.node_count = (int64_t)get_u64(h + H_NODE_COUNT);
    stored.root_count = (int64_t)get_u64(h + H_ROOT_COUNT);
    std::string why;
    if (!geometry_same(stored, g, &why))
        return fail(err, TP_ERR_BAD_DATA, "%s: inconsistent geometry: %s", path, why.c_str());
    for (int i = 0; i < 6; ++i)
        s->header.geotransform[i] = get_f64(h + H_GEOTRANSFORM + 8 * i);
    s->header.height_step_m = get_f64(h + H_HEIGHT_STEP);
    s->header.quant_max_error_m = get_f64(h + H_QUANT_MAX_ERROR);
    s->header.err_unit_steps = get_f64(h + H_ERR_UNIT);
    s->header.valid_samples = (size_t)get_u64(h + H_VALID_SAMPLES);
    s->header.nodata_samples = (size_t)get_u64(h + H_NODATA_SAMPLES);
    if (!(s->header.height_step_m > 0) || !(s->header.err_unit_steps > 0))
        return fail(err, TP_ERR_BAD_DATA, "%s: bad header: height step %g m, error unit %g steps",
                    path, s->header.height_step_m, s->header.err_unit_steps);
    const uint32_t crs_bytes = get_u32(h + H_CRS_BYTES), notes_bytes = get_u32(h + H_NOTES_BYTES);
    if ((uint64_t)H_FIXED_BYTES + crs_bytes + notes_bytes + 4 != header_bytes)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: bad header: CRS (%u bytes) and notes (%u bytes) do not fill its %u bytes",
                    path, crs_bytes, notes_bytes, header_bytes);
    s->crs.assign(reinterpret_cast<const char*>(h + H_FIXED_BYTES), crs_bytes);
    s->notes.assign(reinterpret_cast<const char*>(h + H_FIXED_BYTES + crs_bytes), notes_bytes);
    if (s->crs.find('\0') != std::string::npos || s->notes.find('\0') != std::string::npos)
        return fail(err, TP_ERR_BAD_DATA, "%s: bad header: a NUL byte inside the CRS or notes",
                    path);

    /* Footer: where the table is. */
    if (s->file_bytes < header_bytes + (uint64_t)FOOTER_BYTES)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated: %" PRIu64 " bytes, no room for the footer after the header",
                    path, s->file_bytes);
    uint8_t foot[FOOTER_BYTES];
    if (int e = read_at(s->fd, foot, sizeof foot, s->file_bytes - FOOTER_BYTES))
        return fail(err, TP_ERR_IO, "%s: cannot read the footer: %s", path, std::strerror(e));
    if (std::memcmp(foot + F_END_MAGIC, END_MAGIC, 8) != 0)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated or damaged: no footer at the end of its %" PRIu64
                    " bytes (a copy cut short?)",
                    path, s->file_bytes);
    const uint32_t foot_crc = crc32_of(foot, F_FOOTER_CRC);
    if (foot_crc != get_u32(foot + F_FOOTER_CRC))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged footer (bytes %" PRIu64 "..%" PRIu64
                    "): checksum mismatch (stored 0x%08x, computed 0x%08x)",
                    path, s->file_bytes - FOOTER_BYTES, s->file_bytes - 1,
                    get_u32(foot + F_FOOTER_CRC), foot_crc);
    s->table_offset = get_u64(foot + F_TABLE_OFFSET);
    s->table_bytes = get_u64(foot + F_TABLE_BYTES);
    const size_t esize = entry_bytes(g.n);
    const uint64_t count = (uint64_t)g.node_count;
    if (s->table_offset < header_bytes || s->table_bytes > s->file_bytes ||
        s->table_offset != s->file_bytes - FOOTER_BYTES - s->table_bytes)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged footer: a node table of %" PRIu64 " bytes at byte %" PRIu64
                    " does not end where the footer starts (byte %" PRIu64 ")",
                    path, s->table_bytes, s->table_offset, s->file_bytes - FOOTER_BYTES);
    if (s->table_bytes / esize != count || s->table_bytes % esize != 0)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: the node table holds %" PRIu64 " bytes, but %" PRIu64
                    " nodes of %zu bytes each are expected",
                    path, s->table_bytes, count, esize);

    /* The table. */
    std::vector<uint8_t> table((size_t)s->table_bytes);
    if (int e = read_at(s->fd, table.data(), table.size(), s->table_offset))
        return fail(err, TP_ERR_IO, "%s: cannot read the node table: %s", path, std::strerror(e));
    const uint32_t table_crc = crc32_of(table.data(), table.size());
    if (table_crc != get_u32(foot + F_TABLE_CRC))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged node table (bytes %" PRIu64 "..%" PRIu64
                    "): checksum mismatch (stored 0x%08x, computed 0x%08x)",
                    path, s->table_offset, s->table_offset + s->table_bytes - 1,
                    get_u32(foot + F_TABLE_CRC), table_crc);
    s->metas.assign((size_t)count, tp_node_meta());
    s->entries.resize((size_t)count);
    const uint64_t max_bytes = max_stored_bytes(g.n);
    for (uint64_t id = 0; id < count; ++id) {
        const uint8_t* e = table.data() + id * esize;
        Entry& en = s->entries[(size_t)id];
        tp_node_meta& m = s->metas[(size_t)id];
        en.offset = get_u64(e + E_OFFSET);
        en.bytes = get_u32(e + E_BYTES);
        en.crc = get_u32(e + E_CRC);
        en.codec = (Codec)e[E_CODEC];
        m.flags = e[E_FLAGS];
        m.qmin = (int32_t)get_u32(e + E_QMIN);
        m.qmax = (int32_t)get_u32(e + E_QMIN + 4);
        m.area_qmin = (int32_t)get_u32(e + E_QMIN + 8);
        m.area_qmax = (int32_t)get_u32(e + E_QMIN + 12);
        const uint8_t* p = e + E_DELTA;
        for (int k = 0; k <= g.n; ++k, p += 2)
            m.delta[k] = get_u16(p);
        for (int side = 0; side < 4; ++side)
            for (int k = 0; k < g.n; ++k, p += 2)
                m.eps[side][k] = get_u16(p);
        const char* problem = nullptr;
        if (en.codec != CODEC_RAW && en.codec != CODEC_PLANAR_ZSTD)
            problem = "unknown codec";
        else if (en.bytes == 0 || en.bytes > max_bytes)
            problem = "impossible data size";
        else if (en.offset < header_bytes || en.offset > s->table_offset ||
                 en.bytes > s->table_offset - en.offset)
            problem = "data outside the data area";
        else if (m.flags & ~(TP_NODE_COMPLETE | TP_NODE_HAS_DRAWN))
            problem = "unknown flags";
        else if (m.qmin <= m.qmax && (int64_t)m.qmax - m.qmin >= (int64_t)TP_TREE_NO_HEIGHT)
            problem = "height range too wide";
        if (problem)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: node table, %s: %s (codec %d, %u bytes at byte %" PRIu64
                        "; data area %" PRIu64 "..%" PRIu64 ")",
                        path, node_name(s, (int64_t)id).c_str(), problem, (int)en.codec, en.bytes,
                        en.offset, (uint64_t)header_bytes, s->table_offset);
    }
    s->header.crs_wkt = s->crs.c_str();
    s->header.notes = s->notes.c_str();
    return TP_OK;
}

} // namespace

extern "C" tp_status tp_store_open(const char* path, tp_store** out, tp_error* err)
{
    if (!path || !out)
        return fail(err, TP_ERR_INVALID_ARG, "store: bad arguments (path or out is NULL)");
    tp_status st = tpio::check_input_file(path, "a terrapatch store (.tpt)", false, err);
    if (st != TP_OK)
        return st;
    try {
        std::unique_ptr<tp_store> s(new tp_store);
        std::memset(&s->header, 0, sizeof s->header);
        s->path = path;
        s->fd = open(path, O_RDONLY | O_CLOEXEC | O_NONBLOCK);
        if (s->fd < 0)
            return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, std::strerror(errno));
        struct stat sb;
        if (fstat(s->fd, &sb) != 0)
            return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, std::strerror(errno));
        if (!S_ISREG(sb.st_mode)) /* replaced since check_input_file looked */
            return fail(err, TP_ERR_IO, "%s: cannot open: not a regular file", path);
        s->file_bytes = (uint64_t)sb.st_size;
        st = load(s.get(), err);
        if (st != TP_OK)
            return st;
        *out = s.release();
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}

extern "C" void tp_store_close(tp_store* s) { delete s; }

extern "C" void tp_store_get_info(const tp_store* s, tp_store_info* out)
{
    assert(s && out);
    std::memset(out, 0, sizeof *out);
    out->header = s->header;
    out->version = s->version;
    out->file_bytes = s->file_bytes;
    out->data_bytes = s->table_offset - s->header_bytes;
    out->table_bytes = s->table_bytes;
    out->bytes_per_sample = (double)s->file_bytes /
                            ((double)s->header.geometry.src_width * s->header.geometry.src_height);
}

extern "C" const tp_node_meta* tp_store_metas(const tp_store* s, size_t* count)
{
    assert(s && count);
    *count = s->metas.size();
    return s->metas.data();
}

extern "C" tp_status tp_store_read_node(const tp_store* s, int64_t node, uint16_t* samples,
                                        size_t sample_capacity, tp_error* err)
{
    assert(s && samples);
    assert(node >= 0 && node < (int64_t)s->entries.size());
    const size_t count = sample_count(s->header.geometry.n);
    assert(sample_capacity >= count);
    (void)sample_capacity;
    const char* path = s->path.c_str();
    try {
        const Entry& e = s->entries[(size_t)node];
        ThreadScratch& t = t_scratch;
        t.stored.resize(e.bytes);
        if (int code = read_at(s->fd, t.stored.data(), e.bytes, e.offset))
            return fail(err, TP_ERR_IO, "%s: %s, %u bytes at byte %" PRIu64 ": cannot read: %s",
                        path, node_name(s, node).c_str(), e.bytes, e.offset,
                        code == EIO ? "the file ended early (was it changed?)" : std::strerror(code));
        const uint32_t crc = crc32_of(t.stored.data(), e.bytes);
        if (crc != e.crc)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: %s, %u bytes at byte %" PRIu64
                        ": damaged data: checksum mismatch (stored 0x%08x, computed 0x%08x)",
                        path, node_name(s, node).c_str(), e.bytes, e.offset, e.crc, crc);
        if (!t.dctx && !(t.dctx = ZSTD_createDCtx()))
            throw std::bad_alloc();
        t.samples.resize(count);
        std::string why;
        const int side = (1 << s->header.geometry.n) + 1;
        if (!decode_node(e.codec, t.stored.data(), e.bytes, side, t.dctx, &t.planes,
                         t.samples.data(), &why))
            return fail(err, TP_ERR_BAD_DATA, "%s: %s, %u bytes at byte %" PRIu64 ": %s", path,
                        node_name(s, node).c_str(), e.bytes, e.offset, why.c_str());
        /* every drawn sample inside the node's range (a wrong table or an encoder bug) */
        const tp_node_meta& m = s->metas[(size_t)node];
        const uint32_t top = m.qmin <= m.qmax ? (uint32_t)((int64_t)m.qmax - m.qmin) : 0;
        const bool none = m.qmin > m.qmax;
        for (size_t k = 0; k < count; ++k) {
            const uint16_t v = t.samples[k];
            if (v != TP_TREE_NO_HEIGHT && (none || v > top))
                return fail(err, TP_ERR_BAD_DATA,
                            "%s: %s, %u bytes at byte %" PRIu64
                            ": sample %zu is %u, outside the node's range 0..%u",
                            path, node_name(s, node).c_str(), e.bytes, e.offset, k, v, top);
        }
        std::memcpy(samples, t.samples.data(), count * sizeof *samples);
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}
