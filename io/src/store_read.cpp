/* store_read.cpp - opens a terrain store (.tpt; tp_io.h "Terrain stores", docs/store.md) and
 * reads its nodes. tp_store_open reads and checks the header and the footer, checks the node
 * and location tables in one streaming pass (pread into a small buffer: their pages enter the
 * page cache, not the process's anonymous memory) and maps them read-only: tp_store_metas is a
 * pointer into that mapping, so the memory a store takes does not grow with its node count.
 * tp_store_read_node reads one node with pread, so any number of threads can read at once:
 * the store is not changed after open, and each thread keeps its own zstd context and buffers
 * (thread_local), reused from one node to the next. A store named by an http(s) URL is read
 * through range_file.hpp: its tables in one request, kept in memory rather than mapped, and
 * each node a range request, from any number of threads at once. */
#include "format_read.hpp"
#include "io_util.hpp"
#include "node_prefetch.hpp"
#include "range_file.hpp"
#include "store_format.hpp"
#include "tp_io.h"

#include <zstd.h>

#include <sys/mman.h>
#include <unistd.h>

#include <algorithm>
#include <cassert>
#include <cerrno>
#include <cinttypes>
#include <memory>
#include <string>
#include <thread>
#include <vector>

using namespace tpio::store;
using tpio::fail;

namespace {
/* Bytes of the tables read at a time by the checking pass (a multiple of both entry sizes). */
constexpr size_t CHECK_PIECE_BYTES = 64 * 3 * 4 * 104;
static_assert(CHECK_PIECE_BYTES % META_BYTES == 0 && CHECK_PIECE_BYTES % LOC_BYTES == 0, "");

/* A node's location table entry, decoded. */
struct Entry {
    uint64_t offset;
    uint32_t bytes, crc;
    Codec codec;
};
Entry decode_loc(const uint8_t* e)
{
    return Entry{get_u64(e + L_OFFSET), get_u32(e + L_BYTES), get_u32(e + L_CRC),
                 (Codec)e[L_CODEC]};
}
} // namespace

struct tp_store {
    std::string path;
    tpio::RangeFile file;
    mutable tpio::NodePrefetch ahead; /* over HTTP: nodes read ahead (tp_store_prefetch) */
    uint32_t version = 0;
    uint64_t file_bytes = 0, header_bytes = 0, data_end = 0;
    Tables tables{};
    tp_store_header header;
    std::string crs, notes;
    void* map = nullptr;       /* both tables, read-only (mmap) */
    std::vector<uint8_t> tables_read; /* both tables of a store read over HTTP: not mapped */
    std::string tables_why;           /* why they could not be read (read while the footer is) */
    size_t map_bytes = 0;
    const tp_node_meta* metas = nullptr; /* node_count, inside map */
    const uint8_t* locs = nullptr;       /* node_count * LOC_BYTES, inside map */
    ~tp_store()
    {
        if (map)
            munmap(map, map_bytes);
    }
};

namespace {

/* One reading thread's zstd context and buffers. */
struct ThreadScratch {
    ZSTD_DCtx* dctx = nullptr;
    std::vector<uint8_t> stored, planes;
    std::vector<uint16_t> samples, mask, filled;
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

/* The header's fixed part, its size, checksum and version: the whole header into head (its
 * size then in s->header_bytes) once it can be believed. */
tp_status read_header(tp_store* s, std::vector<uint8_t>& head, tp_error* err)
{
    const char* path = s->path.c_str();
    uint8_t fixed[H_FIXED_BYTES];
    const size_t first = (size_t)std::min<uint64_t>(s->file_bytes, sizeof fixed);
    std::string why;
    if (!s->file.read(fixed, first, 0, &why))
        return fail(err, TP_ERR_IO, "%s: cannot read: %s", path, why.c_str());
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
    if (const tp_status st =
            tpio::read_header_bytes(s->file, path, s->file_bytes, header_bytes, head, err))
        return st;
    const uint8_t* h = head.data();
    s->version = get_u32(h + H_VERSION);
    if (s->version > TP_STORE_VERSION)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: written by a newer terrapatch (format %u; this one reads up to %d)", path,
                    s->version, TP_STORE_VERSION);
    if (s->version == 0)
        return fail(err, TP_ERR_BAD_DATA, "%s: damaged header: format version 0", path);
    if (s->version < TP_STORE_VERSION)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: written by an older terrapatch (format %u; this one reads format %d): "
                    "rebuild it with terrapatch build",
                    path, s->version, TP_STORE_VERSION);
    if (!host_little_endian())
        return fail(err, TP_ERR_BACKEND,
                    "%s: stores of format %d are read on little-endian hosts only (their node "
                    "table is mapped as it is); this host is big-endian",
                    path, TP_STORE_VERSION);
    s->header_bytes = header_bytes;
    return TP_OK;
}

/* The header's fields into s: the geometry, georeference, quantisation, CRS and notes. */
tp_status decode_header(tp_store* s, const uint8_t* h, tp_error* err)
{
    const char* path = s->path.c_str();
    const uint32_t header_bytes = (uint32_t)s->header_bytes;
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
    return tpio::read_header_strings(path, h, H_FIXED_BYTES, header_bytes, crs_bytes,
                                     notes_bytes, s->crs, s->notes, err);
}

/* The footer into foot (FOOTER_BYTES): where the tables are; s->tables and s->data_end. */
tp_status read_footer(tp_store* s, uint8_t* foot, tp_error* err)
{
    const char* path = s->path.c_str();
    const uint32_t header_bytes = (uint32_t)s->header_bytes;
    const tp_tree_geometry& g = s->header.geometry;
    /* Footer: where the tables are (they follow from the header's size and node_count). */
    const uint64_t count = (uint64_t)g.node_count;
    const Tables t = tables_at(header_bytes, count);
    s->tables = t;
    if (s->file_bytes < header_bytes + (uint64_t)FOOTER_BYTES)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated: %" PRIu64 " bytes, no room for the footer after the header",
                    path, s->file_bytes);
    std::string why;
    if (!s->file.read(foot, FOOTER_BYTES, s->file_bytes - FOOTER_BYTES, &why))
        return fail(err, TP_ERR_IO, "%s: cannot read the footer: %s", path, why.c_str());
    if (std::memcmp(foot + F_END_MAGIC, END_MAGIC, 8) != 0)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated or damaged: no footer at the end of its %" PRIu64
                    " bytes (a copy cut short, or bytes appended after the footer?)",
                    path, s->file_bytes);
    const uint32_t foot_crc = crc32_of(foot, F_FOOTER_CRC);
    if (foot_crc != get_u32(foot + F_FOOTER_CRC))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged footer (bytes %" PRIu64 "..%" PRIu64
                    "): checksum mismatch (stored 0x%08x, computed 0x%08x)",
                    path, s->file_bytes - FOOTER_BYTES, s->file_bytes - 1,
                    get_u32(foot + F_FOOTER_CRC), foot_crc);
    if (get_u64(foot + F_META_OFFSET) != t.meta_offset ||
        get_u64(foot + F_META_BYTES) != t.meta_bytes ||
        get_u64(foot + F_LOC_OFFSET) != t.loc_offset || get_u64(foot + F_LOC_BYTES) != t.loc_bytes ||
        get_u32(foot + F_RESERVED) != 0)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged footer: node table at byte %" PRIu64 " (%" PRIu64
                    " bytes), location table at byte %" PRIu64 " (%" PRIu64
                    " bytes), but %" PRIu64 " nodes after a header of %u bytes put them at %" PRIu64
                    " (%" PRIu64 ") and %" PRIu64 " (%" PRIu64 ")",
                    path, get_u64(foot + F_META_OFFSET), get_u64(foot + F_META_BYTES),
                    get_u64(foot + F_LOC_OFFSET), get_u64(foot + F_LOC_BYTES), count, header_bytes,
                    t.meta_offset, t.meta_bytes, t.loc_offset, t.loc_bytes);
    if (t.data_offset > s->file_bytes - FOOTER_BYTES)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated: %" PRIu64 " bytes, but its node and location tables end at "
                    "byte %" PRIu64 " (before the footer's %zu)",
                    path, s->file_bytes, t.data_offset, (size_t)FOOTER_BYTES);
    s->data_end = s->file_bytes - FOOTER_BYTES;
    return TP_OK;
}

/* The bytes of a node table entry that must be 0 for nodes of 2^n+1 samples a side: pad_,
 * delta[k > n], eps[][kn >= n] and the trailing padding (all ones there, as 13 words in the
 * host's order: it is little-endian). */
void meta_zero_mask(int n, uint64_t zero_mask[META_BYTES / 8])
{
    uint8_t mask[META_BYTES];
    std::memset(mask, 0, sizeof mask);
    std::memset(mask + offsetof(tp_node_meta, pad_), 0xFF, sizeof(tp_node_meta::pad_));
    for (int j = n + 1; j < TP_MAX_LEVELS; ++j)
        std::memset(mask + offsetof(tp_node_meta, delta) + 2 * j, 0xFF, 2);
    for (int side = 0; side < 4; ++side)
        for (int j = n; j < TP_MAX_N; ++j)
            std::memset(mask + offsetof(tp_node_meta, eps) + 2 * (TP_MAX_N * side + j), 0xFF, 2);
    std::memset(mask + META_USED_BYTES, 0xFF, META_BYTES - META_USED_BYTES);
    std::memcpy(zero_mask, mask, sizeof mask);
}

/* What is wrong with node table entry e, or nullptr: flags, range, and the bytes the format
 * leaves 0 (zero_mask, 8 bytes at a time). */
const char* meta_problem(const uint8_t* e, const uint64_t* zero_mask)
{
    uint64_t nonzero = 0;
    for (size_t j = 0; j < META_BYTES / 8; ++j) {
        uint64_t word;
        std::memcpy(&word, e + 8 * j, 8);
        nonzero |= word & zero_mask[j];
    }
    const int32_t qmin = (int32_t)get_u32(e), qmax = (int32_t)get_u32(e + 4);
    if (e[16] & ~KNOWN_FLAGS)
        return "unknown flags";
    if ((e[16] & TP_NODE_HAS_FILLED) && !(e[16] & TP_NODE_HAS_DRAWN))
        return "filled samples but nothing drawn";
    if (qmin <= qmax && (int64_t)qmax - qmin >= (int64_t)TP_TREE_NO_HEIGHT)
        return "height range too wide";
    if (nonzero)
        return "unused bytes not 0";
    return nullptr;
}

/* What is wrong with location table entry e (en, decoded), or nullptr: codec, reserved bytes,
 * size (at most max_bytes) and place (inside s's data area). */
const char* loc_problem(const tp_store* s, const Entry& en, const uint8_t* e, uint64_t max_bytes)
{
    bool zero = true;
    for (size_t j = L_CODEC + 1; j < LOC_BYTES; ++j)
        zero = zero && e[j] == 0;
    if (en.codec != CODEC_RAW && en.codec != CODEC_PLANAR_ZSTD)
        return "unknown codec";
    if (!zero)
        return "reserved bytes not 0";
    if (en.bytes == 0 || en.bytes > max_bytes)
        return "impossible data size";
    if (en.offset < s->tables.data_offset || en.offset > s->data_end ||
        en.bytes > s->data_end - en.offset)
        return "data outside the data area";
    return nullptr;
}

/* Both tables against the footer's checksums (foot), every entry checked, in one streaming
 * pass. */
tp_status check_tables(tp_store* s, const uint8_t* foot, tp_error* err)
{
    const char* path = s->path.c_str();
    const tp_tree_geometry& g = s->header.geometry;
    const Tables& t = s->tables;
    /* Both tables, checked in one streaming pass (pread, not the mapping: the checks leave
     * nothing in the process's memory). The first bad entry is reported only once the tables'
     * CRC32s match: a damaged table is reported as damage, not as one odd entry. */
    const uint64_t max_bytes = max_stored_bytes(g.n);
    std::vector<uint8_t> piece(CHECK_PIECE_BYTES);
    uint64_t zero_mask[META_BYTES / 8];
    meta_zero_mask(g.n, zero_mask);
    uint32_t meta_crc = 0, loc_crc = 0;
    uint64_t data_sum = 0; /* the nodes' data bytes: they fill the data area, end to end */
    tp_error bad_entry;
    bad_entry.message[0] = '\0';
    std::string why;
    if (s->file.remote()) { /* over HTTP: both tables in one request, kept (map_tables) */
        if (s->tables_read.size() != t.data_offset - t.meta_offset && s->tables_why.empty()) {
            s->tables_read.resize((size_t)(t.data_offset - t.meta_offset));
            if (!s->file.read(s->tables_read.data(), s->tables_read.size(), t.meta_offset, &why))
                s->tables_why = why;
        }
        if (!s->tables_why.empty())
            return fail(err, TP_ERR_IO, "%s: cannot read the node and location tables: %s",
                        path, s->tables_why.c_str());
    }
    for (uint64_t at = t.meta_offset; at < t.data_offset;) {
        const bool metas = at < t.loc_offset;
        const uint64_t end = metas ? t.loc_offset : t.data_offset;
        const size_t size = (size_t)std::min<uint64_t>(end - at, piece.size());
        const uint8_t* bytes = piece.data();
        if (s->file.remote())
            bytes = s->tables_read.data() + (at - t.meta_offset);
        else if (!s->file.read(piece.data(), size, at, &why))
            return fail(err, TP_ERR_IO, "%s: cannot read the %s table: %s", path,
                        metas ? "node" : "location", why.c_str());
        if (metas)
            meta_crc = crc32_continue(meta_crc, bytes, size);
        else
            loc_crc = crc32_continue(loc_crc, bytes, size);
        const size_t esize = metas ? META_BYTES : LOC_BYTES;
        const uint64_t first = (at - (metas ? t.meta_offset : t.loc_offset)) / esize;
        for (size_t k = 0; k * esize < size; ++k) {
            const uint8_t* e = bytes + k * esize;
            const char* problem = nullptr;
            Entry en{};
            if (metas) {
                problem = meta_problem(e, zero_mask);
            } else {
                en = decode_loc(e);
                problem = loc_problem(s, en, e, max_bytes);
                if (!problem)
                    data_sum += en.bytes;
            }
            if (!problem || bad_entry.message[0])
                continue;
            if (metas)
                fail(&bad_entry, TP_ERR_BAD_DATA, "%s: node table, %s: %s", path,
                            node_name(s, (int64_t)(first + k)).c_str(), problem);
            else
                fail(&bad_entry, TP_ERR_BAD_DATA,
                            "%s: location table, %s: %s (codec %d, %u bytes at byte %" PRIu64
                            "; data area %" PRIu64 "..%" PRIu64 ")",
                            path, node_name(s, (int64_t)(first + k)).c_str(), problem,
                            (int)en.codec, en.bytes, en.offset, t.data_offset, s->data_end);
        }
        at += size;
    }
    if (meta_crc != get_u32(foot + F_META_CRC))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged node table (bytes %" PRIu64 "..%" PRIu64
                    "): checksum mismatch (stored 0x%08x, computed 0x%08x)",
                    path, t.meta_offset, t.loc_offset - 1, get_u32(foot + F_META_CRC), meta_crc);
    if (loc_crc != get_u32(foot + F_LOC_CRC))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged location table (bytes %" PRIu64 "..%" PRIu64
                    "): checksum mismatch (stored 0x%08x, computed 0x%08x)",
                    path, t.loc_offset, t.data_offset - 1, get_u32(foot + F_LOC_CRC), loc_crc);
    if (bad_entry.message[0])
        return fail(err, TP_ERR_BAD_DATA, "%s", bad_entry.message);
    /* A writer leaves no byte between the nodes' data and the footer: more is a file that grew
     * after it was written (a valid footer copied after the first, a copy appended twice). */
    if (data_sum != s->data_end - t.data_offset)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: %" PRId64 " bytes between the last node's data and the footer (its "
                    "nodes hold %" PRIu64 " bytes of the %" PRIu64 "-byte data area): bytes "
                    "appended after the footer?",
                    path, (int64_t)(s->data_end - t.data_offset) - (int64_t)data_sum, data_sum,
                    s->data_end - t.data_offset);
    return TP_OK;
}

/* Maps both tables read-only: s->metas and s->locs point into the mapping (over HTTP: into
 * the tables read by check_tables). */
tp_status map_tables(tp_store* s, tp_error* err)
{
    const char* path = s->path.c_str();
    const Tables& t = s->tables;
    if (s->file.remote()) {
        s->metas = reinterpret_cast<const tp_node_meta*>(s->tables_read.data());
        s->locs = s->tables_read.data() + (t.loc_offset - t.meta_offset);
        return TP_OK;
    }
    /* Map both tables (page-aligned start). */
    const long page = sysconf(_SC_PAGESIZE);
    const uint64_t map_from = t.meta_offset - t.meta_offset % (uint64_t)(page > 0 ? page : 4096);
    s->map_bytes = (size_t)(t.data_offset - map_from);
    void* map = mmap(nullptr, s->map_bytes, PROT_READ, MAP_SHARED, s->file.fd(), (off_t)map_from);
    if (map == MAP_FAILED)
        return fail(err, TP_ERR_IO, "%s: cannot map its node table (%zu bytes): %s", path,
                    s->map_bytes, std::strerror(errno));
    s->map = map;
    const uint8_t* base = static_cast<const uint8_t*>(map) - map_from;
    s->metas = reinterpret_cast<const tp_node_meta*>(base + t.meta_offset);
    s->locs = base + t.loc_offset;
    return TP_OK;
}

/* The checks of tp_store_open after the file is open; fills s. */
tp_status load(tp_store* s, tp_error* err)
{
    std::vector<uint8_t> head;
    if (const tp_status st = read_header(s, head, err))
        return st;
    if (const tp_status st = decode_header(s, head.data(), err))
        return st;
    /* over HTTP: the tables (where the header puts them) read while the footer is: a round
     * trip less; check_tables checks them against the footer as ever */
    std::thread tables;
    const Tables t = tables_at((uint32_t)s->header_bytes, (uint64_t)s->header.geometry.node_count);
    if (s->file.remote() && t.data_offset <= s->file_bytes) {
        s->tables_read.resize((size_t)(t.data_offset - t.meta_offset));
        try {
            tables = std::thread([s, t] {
                std::string why;
                if (!s->file.read(s->tables_read.data(), s->tables_read.size(), t.meta_offset, &why))
                    s->tables_why = why.empty() ? "failed" : why;
            });
        } catch (...) {
            s->tables_read.clear(); /* check_tables reads them */
        }
    }
    uint8_t foot[FOOTER_BYTES];
    const tp_status footer = read_footer(s, foot, err);
    if (tables.joinable())
        tables.join();
    if (footer)
        return footer;
    if (const tp_status st = check_tables(s, foot, err))
        return st;
    if (const tp_status st = map_tables(s, err))
        return st;
    s->header.crs_wkt = s->crs.c_str();
    s->header.notes = s->notes.c_str();
    return TP_OK;
}

} // namespace

extern "C" tp_status tp_store_open(const char* path, tp_store** out, tp_error* err)
{
    if (!path || !out)
        return fail(err, TP_ERR_INVALID_ARG, "store: bad arguments (path or out is NULL)");
    try {
        std::unique_ptr<tp_store> s(new tp_store);
        std::memset(&s->header, 0, sizeof s->header);
        s->path = path;
        tp_status st = s->file.open(path, "a terrapatch store (.tpt)", err);
        if (st != TP_OK)
            return st;
        s->file_bytes = s->file.size();
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

extern "C" int tp_store_changed(const tp_store* s) { return s && s->file.changed(); }

extern "C" void tp_store_get_info(const tp_store* s, tp_store_info* out)
{
    assert(s && out);
    std::memset(out, 0, sizeof *out);
    out->header = s->header;
    out->version = s->version;
    out->remote = s->file.remote();
    out->file_bytes = s->file_bytes;
    out->data_bytes = s->data_end - s->tables.data_offset;
    out->table_bytes = s->tables.meta_bytes + s->tables.loc_bytes;
    out->bytes_per_sample = (double)s->file_bytes /
                            ((double)s->header.geometry.src_width * s->header.geometry.src_height);
}

extern "C" const tp_node_meta* tp_store_metas(const tp_store* s, size_t* count)
{
    assert(s && count);
    *count = (size_t)s->header.geometry.node_count;
    return s->metas;
}

/* Node's stored bytes into the thread's t.stored, checked against the location's bounds
 * (again: the file may have been changed in place since open) and its CRC32. */
static tp_status read_checked(const tp_store* s, int64_t node, Entry* out, tp_error* err)
{
    const char* path = s->path.c_str();
    const Entry e = decode_loc(s->locs + (size_t)node * LOC_BYTES);
    if (e.bytes == 0 || e.bytes > max_stored_bytes(s->header.geometry.n) ||
        e.offset < s->tables.data_offset || e.offset > s->data_end ||
        e.bytes > s->data_end - e.offset)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: %s, %u bytes at byte %" PRIu64
                    ": data outside the data area (was the file changed?)",
                    path, node_name(s, node).c_str(), e.bytes, e.offset);
    ThreadScratch& t = t_scratch;
    std::string why;
    const bool held = s->file.remote() && s->ahead.get(node, &t.stored) && t.stored.size() == e.bytes;
    if (!held)
        t.stored.resize(e.bytes);
    if (!held && !s->file.read(t.stored.data(), e.bytes, e.offset, &why))
        return fail(err, TP_ERR_IO, "%s: %s, %u bytes at byte %" PRIu64 ": cannot read: %s",
                    path, node_name(s, node).c_str(), e.bytes, e.offset, why.c_str());
    const uint32_t crc = crc32_of(t.stored.data(), e.bytes);
    if (crc != e.crc && s->file.check_changed(&why)) /* replaced on the server */
        return fail(err, TP_ERR_IO, "%s: %s, %u bytes at byte %" PRIu64 ": %s", path,
                    node_name(s, node).c_str(), e.bytes, e.offset, why.c_str());
    if (crc != e.crc)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: %s, %u bytes at byte %" PRIu64
                    ": damaged data: checksum mismatch (stored 0x%08x, computed 0x%08x)",
                    path, node_name(s, node).c_str(), e.bytes, e.offset, e.crc, crc);
    *out = e;
    return TP_OK;
}

extern "C" size_t tp_store_prefetch(const tp_store* s, const int64_t* nodes, size_t count)
{
    assert(s && (nodes || !count));
    if (!s->file.remote() || !count)
        return 0;
    try {
        std::vector<tpio::NodePrefetch::Want> wants;
        wants.reserve(count);
        for (size_t i = 0; i < count; ++i) {
            assert(nodes[i] >= 0 && nodes[i] < s->header.geometry.node_count);
            const Entry e = decode_loc(s->locs + (size_t)nodes[i] * LOC_BYTES);
            if (e.bytes && e.offset >= s->tables.data_offset && e.offset <= s->data_end &&
                e.bytes <= s->data_end - e.offset) /* else its own read says what is wrong */
                wants.push_back({nodes[i], e.offset, e.bytes});
        }
        return s->ahead.prefetch(s->file, std::move(wants));
    } catch (...) {
        return 0; /* out of memory or threads: the nodes are read one at a time */
    }
}

extern "C" tp_status tp_store_read_stored(const tp_store* s, int64_t node, tp_store_stored* out,
                                          tp_error* err)
{
    assert(s && out && node >= 0 && node < s->header.geometry.node_count);
    try {
        Entry e;
        if (const tp_status st = read_checked(s, node, &e, err))
            return st;
        const ThreadScratch& t = t_scratch;
        *out = tp_store_stored{t.stored.data(), e.bytes, e.crc, (int)e.codec};
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, s->path.c_str());
    }
}

extern "C" tp_status tp_store_read_node(const tp_store* s, int64_t node, uint16_t* samples,
                                        size_t sample_capacity, tp_error* err)
{
    assert(s && samples);
    assert(node >= 0 && node < s->header.geometry.node_count);
    const size_t count = sample_count(s->header.geometry.n);
    assert(sample_capacity >= count);
    const char* path = s->path.c_str();
    try {
        Entry e;
        if (const tp_status st = read_checked(s, node, &e, err))
            return st;
        ThreadScratch& t = t_scratch;
        std::string why;
        if (!t.dctx && !(t.dctx = ZSTD_createDCtx()))
            throw std::bad_alloc();
        t.samples.resize(count);
        const int n = s->header.geometry.n, side = (1 << n) + 1;
        const tp_node_meta m = s->metas[(size_t)node];
        int scale, col, row;
        node_locate(s->header.geometry, node, &scale, &col, &row);
        const size_t mbytes = stores_mask(m, scale) ? mask_bytes(n) : 0;
        /* format 4: the filled bits' frame and its size end the node's bytes */
        size_t fbytes = 0;
        const size_t fwords = tp_node_filled_words(n);
        if (stores_filled(m)) {
            const uint32_t frame = e.bytes >= 4 ? get_u32(t.stored.data() + e.bytes - 4) : 0;
            if (e.bytes < 4 || frame == 0 || frame > e.bytes - 4 - mbytes - 1)
                return fail(err, TP_ERR_BAD_DATA,
                            "%s: %s, %u bytes at byte %" PRIu64
                            ": damaged filled table: its size (%u bytes) does not fit the node",
                            path, node_name(s, node).c_str(), e.bytes, e.offset, frame);
            fbytes = (size_t)frame + 4;
            t.filled.resize(fwords);
            if (!decode_filled(t.stored.data() + e.bytes - fbytes, frame, fwords, t.dctx,
                               &t.planes, t.filled.data(), &why))
                return fail(err, TP_ERR_BAD_DATA,
                            "%s: %s, %u bytes at byte %" PRIu64 ": damaged filled table: %s",
                            path, node_name(s, node).c_str(), e.bytes, e.offset, why.c_str());
        }
        if (e.bytes <= mbytes + fbytes)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: %s, %u bytes at byte %" PRIu64 ": too short for its cell mask",
                        path, node_name(s, node).c_str(), e.bytes, e.offset);
        if (!decode_node(e.codec, t.stored.data(), e.bytes - mbytes - fbytes, side, t.dctx, &t.planes,
                         t.samples.data(), &why))
            return fail(err, TP_ERR_BAD_DATA, "%s: %s, %u bytes at byte %" PRIu64 ": %s", path,
                        node_name(s, node).c_str(), e.bytes, e.offset, why.c_str());
        /* every drawn sample inside the node's range (a wrong table or an encoder bug) */
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
        const size_t words = tp_node_mask_words(n);
        if (mbytes) { /* a whole cell's corners must be drawn: what drawing relies on */
            t.mask.resize(words);
            const uint8_t* mp = t.stored.data() + (e.bytes - fbytes - mbytes);
            for (size_t k = 0; k < words; ++k)
                t.mask[k] = get_u16(mp + 2 * k);
            const int cells = 1 << n;
            for (int y = 0; y < cells; ++y)
                for (int x = 0; x < cells; ++x) {
                    const size_t b = ((size_t)y << n) + (size_t)x;
                    if (!(t.mask[b >> 4] >> (b & 15) & 1))
                        continue;
                    const uint16_t* a = t.samples.data() + (size_t)y * side + x;
                    if (a[0] == TP_TREE_NO_HEIGHT || a[1] == TP_TREE_NO_HEIGHT ||
                        a[side] == TP_TREE_NO_HEIGHT || a[side + 1] == TP_TREE_NO_HEIGHT)
                        return fail(err, TP_ERR_BAD_DATA,
                                    "%s: %s, %u bytes at byte %" PRIu64
                                    ": its cell mask has cell (%d, %d) whole, but a corner of "
                                    "it is not drawn",
                                    path, node_name(s, node).c_str(), e.bytes, e.offset, x, y);
                }
        }
        if (fbytes) { /* filled: drawn samples only, at least one, no bit past the samples */
            bool any = false;
            for (size_t k = 0; k < 16 * fwords; ++k) {
                if (!(t.filled[k >> 4] >> (k & 15) & 1))
                    continue;
                if (k >= count || t.samples[k] == TP_TREE_NO_HEIGHT)
                    return fail(err, TP_ERR_BAD_DATA,
                                "%s: %s, %u bytes at byte %" PRIu64
                                ": damaged filled table: sample %zu is marked filled but %s",
                                path, node_name(s, node).c_str(), e.bytes, e.offset, k,
                                k >= count ? "does not exist" : "is not drawn");
                any = true;
            }
            if (!any)
                return fail(err, TP_ERR_BAD_DATA,
                            "%s: %s, %u bytes at byte %" PRIu64
                            ": damaged filled table: the node is marked filled but no sample is",
                            path, node_name(s, node).c_str(), e.bytes, e.offset);
        }
        std::memcpy(samples, t.samples.data(), count * sizeof *samples);
        if (sample_capacity >= count + words + fwords) { /* a whole block: mask, filled bits */
            uint16_t* fb = samples + count + words;
            if (fbytes)
                std::memcpy(fb, t.filled.data(), fwords * sizeof *fb);
            else
                std::memset(fb, 0, fwords * sizeof *fb);
        }
        if (sample_capacity >= count + words) { /* a whole block: the mask follows */
            uint16_t* mask = samples + count;
            if (mbytes)
                std::memcpy(mask, t.mask.data(), words * sizeof *mask);
            else if (scale == 0)
                tp_node_mask_from_samples(n, samples, mask);
            else
                std::memset(mask, (m.flags & TP_NODE_COMPLETE) ? 0xFF : 0, words * sizeof *mask);
        }
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}
