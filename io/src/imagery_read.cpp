/* imagery_read.cpp - opens an imagery pyramid (.tpi; tp_imagery.h, docs/imagery.md) and reads
 * its blocks. tp_imagery_open reads and checks the header (magic, CRC32, version, a geometry
 * recomputed from the grid's size and the texel shift), the footer and the block table (its
 * CRC32, every entry's codec and size, every block inside the data area) and keeps the table in
 * memory (24 bytes a block: 0.01% of the blocks' raw texels). tp_imagery_read_block reads one
 * block with pread, so any number of threads may read at once: the pyramid is not changed
 * after open, and each thread keeps its own zstd context and buffers (thread_local). An http(s)
 * URL is read with range requests (range_file.hpp), as a store is. */
#include "format_read.hpp"
#include "imagery_format.hpp"
#include "io_util.hpp"

#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cinttypes>
#include <memory>
#include <string>
#include <vector>

using namespace tpio::imagery;
using tpio::fail;

struct tp_imagery {
    std::string path;
    tpio::RangeFile file;
    Geometry g;
    int shift = 0;
    int grid_width = 0, grid_height = 0;
    double grid_gt[6] = {0};
    std::string crs, notes;
    uint64_t file_bytes = 0, nonempty = 0, data_offset = 0, data_end = 0;
    int kind = TP_IMAGERY_KIND_IMAGE;
    double time_first_s = 0, time_last_s = 0;
    int maps = 0;
    std::vector<uint8_t> table; /* block_count entries */
};

namespace {

struct ThreadScratch {
    ZSTD_DCtx* dctx = nullptr;
    std::vector<uint8_t> stored, planes, rgba;
    ~ThreadScratch()
    {
        ZSTD_freeDCtx(dctx);
    }
};
thread_local ThreadScratch t_scratch;

struct Entry {
    uint64_t offset;
    uint32_t bytes, crc;
    Codec codec;
};
Entry decode_entry(const uint8_t* e)
{
    return Entry{get_u64(e + E_OFFSET), get_u32(e + E_BYTES), get_u32(e + E_CRC),
                 (Codec)e[E_CODEC]};
}

/* "level 2, block (3, 4)" of table index i */
std::string block_name(const Geometry& g, uint64_t i)
{
    int l = 0;
    while (l + 1 < g.levels && i >= g.first[l + 1])
        ++l;
    const uint64_t k = i - g.first[l];
    return "level " + std::to_string(l) + ", block (" + std::to_string(k % (uint64_t)g.cols[l]) +
           ", " + std::to_string(k / (uint64_t)g.cols[l]) + ")";
}

bool same_bits(double a, double b)
{
    return std::memcmp(&a, &b, sizeof a) == 0;
}

/* The header's fixed part, its size, checksum and version: the whole header into head,
 * its version, and the size of that version's fixed part. */
tp_status read_header(tp_imagery* im, std::vector<uint8_t>& head, uint32_t* version_out,
                      size_t* fixed_out, tp_error* err)
{
    const char* path = im->path.c_str();
    uint8_t fixed[H_FIXED_BYTES_V1];
    const size_t first = (size_t)std::min<uint64_t>(im->file_bytes, sizeof fixed);
    std::string why;
    if (!im->file.read(fixed, first, 0, &why))
        return fail(err, TP_ERR_IO, "%s: cannot read: %s", path, why.c_str());
    if (first < sizeof MAGIC || std::memcmp(fixed, MAGIC, sizeof MAGIC) != 0)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: not a terrapatch imagery pyramid (.tpi): its first bytes are not the "
                    "pyramid's signature",
                    path);
    if (first < H_FIXED_BYTES_V1)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated: %" PRIu64 " bytes, a pyramid's header alone takes %zu", path,
                    im->file_bytes, (size_t)H_FIXED_BYTES_V1 + 4);
    const uint32_t header_bytes = get_u32(fixed + H_HEADER_BYTES);
    /* the fixed part of the version it claims (checked after the checksum) */
    size_t fixed_size = fixed_bytes(get_u32(fixed + H_VERSION));
    if (fixed_size == 0)
        fixed_size = H_FIXED_BYTES_V1;
    if (header_bytes < fixed_size + 4 || header_bytes > fixed_size + 4 + 2 * MAX_STRING_BYTES)
        return fail(err, TP_ERR_BAD_DATA, "%s: damaged header: it claims %u bytes", path,
                    header_bytes);
    if (const tp_status st =
            tpio::read_header_bytes(im->file, path, im->file_bytes, header_bytes, head, err))
        return st;
    const uint32_t version = get_u32(head.data() + H_VERSION);
    if (version > VERSION)
        return fail(
            err, TP_ERR_BAD_DATA,
            "%s: written by a newer terrapatch (imagery format %u; this one reads up to %u)", path,
            version, VERSION);
    if (version == 0)
        return fail(err, TP_ERR_BAD_DATA, "%s: damaged header: format version 0", path);
    *version_out = version;
    *fixed_out = fixed_size;
    return TP_OK;
}

/* The geometry, recomputed from the grid and the shift (into im: g, the grid's size,
 * geotransform and the texel shift), against the header h's stored values. */
tp_status decode_geometry(tp_imagery* im, const uint8_t* h, tp_error* err)
{
    const char* path = im->path.c_str();
    /* Geometry: recomputed from the grid and the shift; every stored value must agree. */
    const uint32_t block = get_u32(h + H_BLOCK), gw = get_u32(h + H_GRID_WIDTH),
                   gh = get_u32(h + H_GRID_HEIGHT);
    const int32_t shift = (int32_t)get_u32(h + H_TEXEL_SHIFT);
    for (int i = 0; i < 6; ++i)
        im->grid_gt[i] = get_f64(h + H_GRID_GEOTRANSFORM + 8 * i);
    if (block != (uint32_t)BLOCK || gw < 1 || gw > INT32_MAX || gh < 1 || gh > INT32_MAX ||
        !geometry_for((int)gw, (int)gh, im->grid_gt, shift, &im->g))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: bad geometry: blocks of %u, grid %ux%u, texel shift %d", path, block, gw,
                    gh, shift);
    const Geometry& g = im->g;
    std::string why;
    char buf[160];
    if (get_u32(h + H_LEVELS) != (uint32_t)g.levels)
        std::snprintf(buf, sizeof buf, "levels %u, expected %d", get_u32(h + H_LEVELS), g.levels),
            why = buf;
    else if (get_u64(h + H_WIDTH) != (uint64_t)g.width[0] ||
             get_u64(h + H_HEIGHT) != (uint64_t)g.height[0])
        std::snprintf(buf, sizeof buf,
                      "level 0 %" PRIu64 "x%" PRIu64 ", expected %" PRId64 "x%" PRId64,
                      get_u64(h + H_WIDTH), get_u64(h + H_HEIGHT), g.width[0], g.height[0]),
            why = buf;
    else if (get_u64(h + H_BLOCK_COUNT) != g.block_count)
        std::snprintf(buf, sizeof buf, "%" PRIu64 " blocks, expected %" PRIu64,
                      get_u64(h + H_BLOCK_COUNT), g.block_count),
            why = buf;
    else
        for (int i = 0; i < 6 && why.empty(); ++i)
            if (!same_bits(get_f64(h + H_GEOTRANSFORM + 8 * i), g.gt[i]))
                why = "level 0's geotransform is not the grid's scaled by the texel shift";
    for (int i = 0; i < 6 && why.empty(); ++i)
        if (!std::isfinite(im->grid_gt[i]))
            why = "the grid's geotransform is not finite";
    if (!why.empty())
        return fail(err, TP_ERR_BAD_DATA, "%s: inconsistent geometry: %s", path, why.c_str());
    im->shift = shift;
    im->grid_width = (int)gw, im->grid_height = (int)gh;
    return TP_OK;
}

/* The kind, its day, the non-empty block count, the CRS and notes of header h (of version,
 * its fixed part fixed_size bytes, header_bytes in all) into im. */
tp_status decode_kind(tp_imagery* im, const uint8_t* h, uint32_t version, size_t fixed_size,
                      uint32_t header_bytes, tp_error* err)
{
    const char* path = im->path.c_str();
    /* The kind and its day: version 1 is imagery (the field was reserved, 0) */
    const uint32_t kind = get_u32(h + H_KIND);
    const bool v2 = version >= 2;
    const double t0 = v2 ? get_f64(h + H_TIME_FIRST) : 0, t1 = v2 ? get_f64(h + H_TIME_LAST) : 0;
    const uint32_t maps = v2 ? get_u32(h + H_MAPS) : 0;
    const int shift = im->shift;
    const char* bad_kind = kind_problem(kind, t0, t1, maps, shift);
    if (!bad_kind && v2 && get_u32(h + H_RESERVED2) != 0)
        bad_kind = "reserved bytes not 0";
    if (bad_kind)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: bad header: %s (kind %u, day %.17g .. %.17g, %u maps, texel shift %d)",
                    path, bad_kind, kind, t0, t1, maps, shift);
    im->kind = (int)kind;
    im->time_first_s = t0, im->time_last_s = t1;
    im->maps = (int)maps;
    im->nonempty = get_u64(h + H_NONEMPTY);
    const uint32_t crs_bytes = get_u32(h + H_CRS_BYTES), notes_bytes = get_u32(h + H_NOTES_BYTES);
    return tpio::read_header_strings(path, h, fixed_size, header_bytes, crs_bytes, notes_bytes,
                                     im->crs, im->notes, err);
}

/* The footer into foot (FOOTER_BYTES), checked against where the block table must be
 * (*table_offset, after a header of header_bytes); im->data_offset and data_end. */
tp_status read_footer(tp_imagery* im, uint32_t header_bytes, uint8_t* foot,
                      uint64_t* table_offset_out, tp_error* err)
{
    const char* path = im->path.c_str();
    const Geometry& g = im->g;
    /* Footer */
    const uint64_t table_offset = ((uint64_t)header_bytes + 7) & ~(uint64_t)7;
    const uint64_t table_bytes = g.block_count * ENTRY_BYTES;
    im->data_offset = table_offset + table_bytes;
    if (im->file_bytes < (uint64_t)header_bytes + FOOTER_BYTES)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated: %" PRIu64 " bytes, no room for the footer after the header",
                    path, im->file_bytes);
    std::string why;
    if (!im->file.read(foot, FOOTER_BYTES, im->file_bytes - FOOTER_BYTES, &why))
        return fail(err, TP_ERR_IO, "%s: cannot read the footer: %s", path, why.c_str());
    if (std::memcmp(foot + F_END_MAGIC, END_MAGIC, 8) != 0)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated or damaged: no footer at the end of its %" PRIu64
                    " bytes (a copy cut short?)",
                    path, im->file_bytes);
    const uint32_t foot_crc = crc32_of(foot, F_FOOTER_CRC);
    if (foot_crc != get_u32(foot + F_FOOTER_CRC))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged footer: checksum mismatch (stored 0x%08x, computed 0x%08x)", path,
                    get_u32(foot + F_FOOTER_CRC), foot_crc);
    if (get_u64(foot + F_TABLE_OFFSET) != table_offset ||
        get_u64(foot + F_TABLE_BYTES) != table_bytes || get_u32(foot + F_RESERVED) != 0 ||
        get_u32(foot + F_RESERVED2) != 0)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged footer: block table at byte %" PRIu64 " (%" PRIu64
                    " bytes), but %" PRIu64 " blocks after a header of %u bytes put it at %" PRIu64
                    " (%" PRIu64 ")",
                    path, get_u64(foot + F_TABLE_OFFSET), get_u64(foot + F_TABLE_BYTES),
                    g.block_count, header_bytes, table_offset, table_bytes);
    im->data_end = im->file_bytes - FOOTER_BYTES;
    if (im->data_offset > im->data_end)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: truncated: %" PRIu64 " bytes, but its block table ends at byte %" PRIu64,
                    path, im->file_bytes, im->data_offset);
    *table_offset_out = table_offset;
    return TP_OK;
}

/* What is wrong with block table entry p (e, decoded), or nullptr: reserved bytes, codec, size
 * (at most max_bytes) and place (inside im's data area). */
const char* entry_problem(const tp_imagery* im, const Entry& e, const uint8_t* p, size_t max_bytes)
{
    bool zero = true;
    for (size_t j = E_CODEC + 1; j < ENTRY_BYTES; ++j)
        zero = zero && p[j] == 0;
    if (!zero)
        return "reserved bytes not 0";
    if (e.codec == CODEC_EMPTY) {
        if (e.offset != 0 || e.bytes != 0 || e.crc != 0)
            return "an empty block with an offset, size or checksum";
        return nullptr;
    }
    if (e.codec != CODEC_ZSTD && e.codec != CODEC_RAW)
        return "unknown codec";
    if (e.bytes == 0 || e.bytes > max_bytes || (e.codec == CODEC_RAW && e.bytes != BLOCK_BYTES))
        return "impossible data size";
    if (e.offset < im->data_offset || e.offset > im->data_end ||
        e.bytes > im->data_end - e.offset)
        return "data outside the data area";
    return nullptr;
}

/* The block table at table_offset, read into im->table: its CRC32 against the footer's (foot),
 * then every entry. */
tp_status check_table(tp_imagery* im, uint64_t table_offset, const uint8_t* foot, tp_error* err)
{
    const char* path = im->path.c_str();
    const Geometry& g = im->g;
    const uint64_t table_bytes = g.block_count * ENTRY_BYTES;
    /* The table: CRC32, then every entry */
    im->table.resize((size_t)table_bytes);
    std::string why;
    if (!im->file.read(im->table.data(), im->table.size(), table_offset, &why))
        return fail(err, TP_ERR_IO, "%s: cannot read the block table: %s", path, why.c_str());
    const uint32_t table_crc = crc32_of(im->table.data(), im->table.size());
    if (table_crc != get_u32(foot + F_TABLE_CRC))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: damaged block table (bytes %" PRIu64 "..%" PRIu64
                    "): checksum mismatch (stored 0x%08x, computed 0x%08x)",
                    path, table_offset, im->data_offset - 1, get_u32(foot + F_TABLE_CRC),
                    table_crc);
    uint64_t nonempty = 0;
    const size_t max_bytes = max_block_bytes();
    for (uint64_t i = 0; i < g.block_count; ++i) {
        const uint8_t* p = im->table.data() + i * ENTRY_BYTES;
        const Entry e = decode_entry(p);
        const char* problem = entry_problem(im, e, p, max_bytes);
        if (problem)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: block table, %s: %s (codec %d, %u bytes at byte %" PRIu64
                        "; data area %" PRIu64 "..%" PRIu64 ")",
                        path, block_name(g, i).c_str(), problem, (int)e.codec, e.bytes, e.offset,
                        im->data_offset, im->data_end);
        nonempty += e.codec != CODEC_EMPTY;
    }
    if (nonempty != im->nonempty)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: inconsistent header: %" PRIu64 " non-empty blocks, the table has %" PRIu64,
                    path, im->nonempty, nonempty);
    return TP_OK;
}

tp_status load(tp_imagery* im, tp_error* err)
{
    std::vector<uint8_t> head;
    uint32_t version = 0;
    size_t fixed_size = 0;
    if (const tp_status st = read_header(im, head, &version, &fixed_size, err))
        return st;
    const uint32_t header_bytes = (uint32_t)head.size();
    if (const tp_status st = decode_geometry(im, head.data(), err))
        return st;
    if (const tp_status st =
            decode_kind(im, head.data(), version, fixed_size, header_bytes, err))
        return st;
    uint8_t foot[FOOTER_BYTES];
    uint64_t table_offset = 0;
    if (const tp_status st = read_footer(im, header_bytes, foot, &table_offset, err))
        return st;
    return check_table(im, table_offset, foot, err);
}

} // namespace

extern "C" tp_status tp_imagery_open(const char* path, tp_imagery** out, tp_error* err)
{
    if (!path || !out)
        return fail(err, TP_ERR_INVALID_ARG, "imagery: bad arguments (path or out is NULL)");
    try {
        std::unique_ptr<tp_imagery> im(new tp_imagery);
        im->path = path;
        if (tp_status st = im->file.open(path, "a terrapatch imagery pyramid (.tpi)", err))
            return st;
        im->file_bytes = im->file.size();
        if (tp_status st = load(im.get(), err))
            return st;
        *out = im.release();
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}

extern "C" void tp_imagery_close(tp_imagery* im)
{
    delete im;
}

extern "C" void tp_imagery_get_info(const tp_imagery* im, tp_imagery_info* out)
{
    std::memset(out, 0, sizeof *out);
    const Geometry& g = im->g;
    out->block = BLOCK;
    out->levels = g.levels;
    out->texel_shift = im->shift;
    out->width = g.width[0];
    out->height = g.height[0];
    std::memcpy(out->geotransform, g.gt, sizeof out->geotransform);
    out->grid_width = im->grid_width;
    out->grid_height = im->grid_height;
    std::memcpy(out->grid_geotransform, im->grid_gt, sizeof out->grid_geotransform);
    out->crs_wkt = im->crs.c_str();
    out->notes = im->notes.c_str();
    out->file_bytes = im->file_bytes;
    out->nonempty_blocks = im->nonempty;
    out->kind = im->kind;
    out->time_first_s = im->time_first_s;
    out->time_last_s = im->time_last_s;
    out->maps = im->maps;
}

extern "C" void tp_imagery_level_size(const tp_imagery* im, int level, int64_t* width,
                                      int64_t* height, int* block_cols, int* block_rows)
{
    const bool in = im && level >= 0 && level < im->g.levels;
    if (width)
        *width = in ? im->g.width[level] : 0;
    if (height)
        *height = in ? im->g.height[level] : 0;
    if (block_cols)
        *block_cols = in ? im->g.cols[level] : 0;
    if (block_rows)
        *block_rows = in ? im->g.rows[level] : 0;
}

namespace {
/* Table index of a block, or -1 out of range. */
int64_t block_index(const tp_imagery* im, int level, int bx, int by)
{
    if (!im || level < 0 || level >= im->g.levels || bx < 0 || by < 0 || bx >= im->g.cols[level] ||
        by >= im->g.rows[level])
        return -1;
    return (int64_t)(im->g.first[level] + (uint64_t)by * im->g.cols[level] + (uint64_t)bx);
}
} // namespace

extern "C" int tp_imagery_block_is_empty(const tp_imagery* im, int level, int bx, int by)
{
    const int64_t i = block_index(im, level, bx, by);
    return i < 0 || im->table[(size_t)i * ENTRY_BYTES + E_CODEC] == CODEC_EMPTY;
}

extern "C" tp_status tp_imagery_read_block(const tp_imagery* im, int level, int bx, int by,
                                           uint8_t* rgba, tp_error* err)
{
    if (!im || !rgba)
        return fail(err, TP_ERR_INVALID_ARG, "imagery: bad arguments (pyramid or rgba is NULL)");
    const int64_t i = block_index(im, level, bx, by);
    const Entry e = i < 0 ? Entry{0, 0, 0, CODEC_EMPTY}
                          : decode_entry(im->table.data() + (size_t)i * ENTRY_BYTES);
    if (e.codec == CODEC_EMPTY) {
        std::memset(rgba, 0, BLOCK_BYTES);
        return TP_OK;
    }
    const char* path = im->path.c_str();
    try {
        ThreadScratch& t = t_scratch;
        t.stored.resize(e.bytes);
        std::string why;
        if (!im->file.read(t.stored.data(), e.bytes, e.offset, &why))
            return fail(
                err, TP_ERR_IO,
                "%s: level %d, block (%d, %d), %u bytes at byte %" PRIu64 ": cannot read: %s", path,
                level, bx, by, e.bytes, e.offset, why.c_str());
        const uint32_t crc = crc32_of(t.stored.data(), e.bytes);
        if (crc != e.crc && im->file.check_changed(&why))
            return fail(err, TP_ERR_IO,
                        "%s: level %d, block (%d, %d), %u bytes at byte %" PRIu64 ": %s", path,
                        level, bx, by, e.bytes, e.offset, why.c_str());
        if (crc != e.crc)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: level %d, block (%d, %d), %u bytes at byte %" PRIu64
                        ": damaged data: checksum mismatch (stored 0x%08x, computed 0x%08x)",
                        path, level, bx, by, e.bytes, e.offset, e.crc, crc);
        if (!t.dctx && !(t.dctx = ZSTD_createDCtx()))
            throw std::bad_alloc();
        t.rgba.resize(BLOCK_BYTES);
        if (!decode_block(e.codec, t.stored.data(), e.bytes, t.dctx, &t.planes, t.rgba.data(),
                          &why))
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: level %d, block (%d, %d), %u bytes at byte %" PRIu64 ": %s", path,
                        level, bx, by, e.bytes, e.offset, why.c_str());
        std::memcpy(rgba, t.rgba.data(), BLOCK_BYTES);
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, path);
    }
}
