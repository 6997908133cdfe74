/* store_format.hpp - the byte layout of a terrain store (.tpt), shared by store_write.cpp and
 * store_read.cpp; docs/store.md describes it byte by byte. Private to io/.
 *
 *   [header: magic, version, header_bytes, fields, CRS, notes, CRC32] [0..7 zero bytes]
 *   [node table: node_count tp_node_meta, in id order, as in memory]      (META_BYTES each)
 *   [location table: node_count entries, in id order]                     (LOC_BYTES each)
 *   [node data, in the order the writer received the nodes]
 *   [footer: the tables' offsets, sizes and CRC32s, footer CRC32, end magic]  (FOOTER_BYTES)
 *
 * Every integer is little-endian, every double an IEEE 754 binary64 stored as its bits, also
 * little-endian. Only the node table depends on a struct layout, tp_node_meta's, pinned below. */
#pragma once

#include "tp_core.h"

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace tpio {
namespace store {

/* "\x89TPT\r\n\x1a\n": the high byte and the line endings catch 7-bit and text-mode copies, as
 * PNG's signature does. */
constexpr uint8_t MAGIC[8] = {0x89, 'T', 'P', 'T', '\r', '\n', 0x1a, '\n'};
constexpr uint8_t END_MAGIC[8] = {'T', 'P', 'T', 'E', 'N', 'D', '\r', '\n'};

/* Header: fixed part (offsets below), then crs_wkt and notes, then the CRC32 of all before. The
 * magic, version, header_bytes and the CRC32 in the last 4 header bytes keep their places in
 * every version, so a reader checks the CRC before it trusts the version. */
enum : size_t {
    H_MAGIC = 0,
    H_VERSION = 8,
    H_HEADER_BYTES = 12,
    H_N = 16,
    H_SRC_WIDTH = 20,
    H_SRC_HEIGHT = 24,
    H_WIDTH = 28,
    H_HEIGHT = 32,
    H_COLS = 36,
    H_ROWS = 40,
    H_SCALES = 44,
    H_NODE_COUNT = 48,
    H_ROOT_COUNT = 56,
    H_GEOTRANSFORM = 64, /* 6 doubles */
    H_HEIGHT_STEP = 112,
    H_QUANT_MAX_ERROR = 120,
    H_ERR_UNIT = 128,
    H_VALID_SAMPLES = 136,
    H_NODATA_SAMPLES = 144,
    H_CRS_BYTES = 152,
    H_NOTES_BYTES = 156,
    H_FIXED_BYTES = 160, /* then crs_wkt, notes, CRC32 */
};
constexpr uint32_t MAX_STRING_BYTES = 16u << 20; /* each of crs_wkt, notes */

/* Format 2: after the header (and zero bytes up to the next multiple of 8), the node table
 * laid out exactly as an array of the host's tp_node_meta, so that a reader can map it and hand
 * it out as it is (little-endian hosts; the static asserts catch a layout change), then the
 * location table (LOC_BYTES per node), then the nodes' data, then the footer. Both tables'
 * places follow from the header's size and node_count (Tables). */
constexpr size_t META_BYTES = 104;
static_assert(sizeof(tp_node_meta) == META_BYTES, "tp_node_meta changed: a new store format");
static_assert(offsetof(tp_node_meta, qmin) == 0 && offsetof(tp_node_meta, qmax) == 4 &&
                  offsetof(tp_node_meta, area_qmin) == 8 && offsetof(tp_node_meta, area_qmax) == 12 &&
                  offsetof(tp_node_meta, flags) == 16 && offsetof(tp_node_meta, pad_) == 17 &&
                  offsetof(tp_node_meta, delta) == 20 && offsetof(tp_node_meta, eps) == 38 &&
                  TP_MAX_LEVELS == 9 && TP_MAX_N == 8 && alignof(tp_node_meta) <= 8,
              "tp_node_meta's layout changed: a new store format (docs/store.md)");
constexpr size_t META_USED_BYTES = 38 + 2 * 4 * TP_MAX_N; /* 102: then 2 bytes of padding */
static_assert(META_BYTES % 8 == 0, "node table entries keep 8-byte alignment");

/* Location table entry (LOC_BYTES each, in node id order). */
enum : size_t {
    L_OFFSET = 0,    /* u64: byte offset of the node's data in the file */
    L_BYTES = 8,     /* u32: bytes stored */
    L_CRC = 12,      /* u32: CRC32 of those bytes */
    L_CODEC = 16,    /* u8: Codec; then 7 bytes 0 */
    LOC_BYTES = 24,
};

/* Footer: the last FOOTER_BYTES of the file. */
enum : size_t {
    F_META_OFFSET = 0, /* u64: node table */
    F_META_BYTES = 8,  /* u64 */
    F_LOC_OFFSET = 16, /* u64: location table */
    F_LOC_BYTES = 24,  /* u64 */
    F_META_CRC = 32,   /* u32: CRC32 of the node table */
    F_LOC_CRC = 36,    /* u32: CRC32 of the location table */
    F_RESERVED = 40,   /* u32: 0 */
    F_FOOTER_CRC = 44, /* u32: CRC32 of footer bytes 0..43 */
    F_END_MAGIC = 48,  /* 8 bytes */
    FOOTER_BYTES = 56,
};

/* Where the tables and the data area start in a file whose header takes header_bytes. */
struct Tables {
    uint64_t meta_offset, meta_bytes, loc_offset, loc_bytes, data_offset;
};
inline Tables tables_at(uint64_t header_bytes, uint64_t node_count)
{
    Tables t;
    t.meta_offset = (header_bytes + 7) & ~(uint64_t)7;
    t.meta_bytes = node_count * META_BYTES;
    t.loc_offset = t.meta_offset + t.meta_bytes;
    t.loc_bytes = node_count * LOC_BYTES;
    t.data_offset = t.loc_offset + t.loc_bytes;
    return t;
}

/* True on a little-endian host, the only kind that reads or writes format 2 or 3 (its node table is
 * the host's tp_node_meta array). */
inline bool host_little_endian()
{
    const uint16_t one = 1;
    uint8_t b;
    std::memcpy(&b, &one, 1);
    return b == 1;
}

/* How a node's samples are stored (per node, in its table entry). */
enum Codec : uint8_t {
    CODEC_RAW = 0,     /* (2^n+1)^2 uint16, little-endian, row-major */
    CODEC_PLANAR_ZSTD = 1 /* planar prediction (a + b - c), zigzag, low-byte plane then high-byte plane, zstd */
};

/* ---- little-endian fields ---- */
inline void put_u16(uint8_t* p, uint16_t v) { p[0] = (uint8_t)v, p[1] = (uint8_t)(v >> 8); }
inline void put_u32(uint8_t* p, uint32_t v)
{
    for (int i = 0; i < 4; ++i)
        p[i] = (uint8_t)(v >> (8 * i));
}
inline void put_u64(uint8_t* p, uint64_t v)
{
    for (int i = 0; i < 8; ++i)
        p[i] = (uint8_t)(v >> (8 * i));
}
inline void put_f64(uint8_t* p, double v)
{
    uint64_t bits;
    std::memcpy(&bits, &v, 8);
    put_u64(p, bits);
}
inline uint16_t get_u16(const uint8_t* p) { return (uint16_t)(p[0] | (p[1] << 8)); }
inline uint32_t get_u32(const uint8_t* p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
inline uint64_t get_u64(const uint8_t* p) { return get_u32(p) | (uint64_t)get_u32(p + 4) << 32; }
inline double get_f64(const uint8_t* p)
{
    uint64_t bits = get_u64(p);
    double v;
    std::memcpy(&v, &bits, 8);
    return v;
}

/* zlib's CRC32 (the one of gzip and PNG) of any length. */
uint32_t crc32_of(const void* data, size_t size);
/* The CRC32 of the bytes whose CRC32 is crc_so_far followed by data (crc32_of(nullptr, 0) = 0
 * to start). */
uint32_t crc32_continue(uint32_t crc_so_far, const void* data, size_t size);

/* The geometry a store of n, src_width x src_height must have: tp_tree_geometry_init's. false
 * when the sizes are outside its ranges (n 4..TP_MAX_N, sizes 1..2^30). */
bool geometry_for(int n, int src_width, int src_height, tp_tree_geometry* out);
/* Compares the fields that define a geometry (scales 0..scales-1 only); on a mismatch writes
 * which field differs ("cols 3, expected 4") into why and returns false. */
bool geometry_same(const tp_tree_geometry& got, const tp_tree_geometry& expected, std::string* why);
/* Scale, column and row of node id (0 <= id < node_count). */
void node_locate(const tp_tree_geometry& g, int64_t id, int* s, int* c, int* r);

/* ---- node samples ---- */
inline size_t sample_count(int n) { return ((size_t)1 << n | 1) * (((size_t)1 << n) | 1); }
/* Format 3: a node of scale >= 1 that is drawn in part (TP_NODE_HAS_DRAWN without
 * TP_NODE_COMPLETE) stores its cell mask (tp_node_mask_from_children) after its encoded
 * samples, as tp_node_mask_words(n) little-endian uint16: mask_bytes(n). Other nodes' masks
 * follow from their samples (a leaf) or flags (all set, or none). */
inline size_t mask_bytes(int n) { return 2 * tp_node_mask_words(n); }
inline bool stores_mask(const tp_node_meta& m, int scale)
{
    return scale > 0 && (m.flags & TP_NODE_HAS_DRAWN) && !(m.flags & TP_NODE_COMPLETE);
}
/* Format 4: a node with TP_NODE_HAS_FILLED in its meta ends with its filled bits
 * (tp_node_filled_words(n) little-endian uint16, see tp_node_filled_words) as one zstd frame
 * (its content size 2 tp_node_filled_words(n)), then that frame's size as a u32: after the
 * samples and the mask, inside the node's stored size and CRC32. */
inline size_t filled_raw_bytes(int n) { return 2 * tp_node_filled_words(n); }
inline bool stores_filled(const tp_node_meta& m) { return (m.flags & TP_NODE_HAS_FILLED) != 0; }
constexpr uint8_t KNOWN_FLAGS = TP_NODE_COMPLETE | TP_NODE_HAS_DRAWN | TP_NODE_HAS_FILLED;
/* Upper bound of the bytes one node can take in the file (either codec, a mask and the
 * filled bits included). */
size_t max_stored_bytes(int n);
/* The filled bits (words of them) as a zstd frame at level `level` into out (appended). */
void encode_filled(const uint16_t* bits, size_t words, int level, void* cctx,
                   std::vector<uint8_t>* out);
/* Decodes a frame of filled bits into bits (words); false with why when it does not decode to
 * exactly 2 words bytes. */
bool decode_filled(const uint8_t* data, size_t size, size_t words, void* dctx,
                   std::vector<uint8_t>* scratch, uint16_t* bits, std::string* why);

/* Encodes side x side samples with codec CODEC_PLANAR_ZSTD at zstd level `level` (ctx: a
 * ZSTD_CCtx*), falling back to CODEC_RAW when that is not smaller. Writes into out (resized),
 * returns the codec. scratch: reused between calls. Throws std::bad_alloc; a zstd failure
 * (which cannot happen for a correct bound) returns CODEC_RAW. */
Codec encode_node(const uint16_t* samples, int side, int level, void* cctx,
                  std::vector<uint8_t>* scratch, std::vector<uint8_t>* out);
/* Decodes stored bytes into samples (side x side). false with a reason in why ("zstd: ...",
 * "decoded 100 bytes, expected 8450") when they do not decode to exactly that many samples.
 * dctx: a ZSTD_DCtx*; scratch: reused between calls. */
bool decode_node(Codec codec, const uint8_t* data, size_t size, int side, void* dctx,
                 std::vector<uint8_t>* scratch, uint16_t* samples, std::string* why);

} // namespace store
} // namespace tpio
