/* store_format.hpp - the byte layout of a terrain store (.tpt), shared by store_write.cpp and
 * store_read.cpp; docs/store.md describes it byte by byte. Private to io/.
 *
 *   [header: magic, version, header_bytes, fields, CRS, notes, CRC32]
 *   [node data, in the order the writer received the nodes]
 *   [node table: node_count entries of entry_bytes(n), in id order]
 *   [footer: table offset and size, table CRC32, footer CRC32, end magic]  (FOOTER_BYTES)
 *
 * Every integer is little-endian, every double an IEEE 754 binary64 stored as its bits, also
 * little-endian; nothing depends on the host's struct layout. */
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

/* Node table entry (entry_bytes(n) each, in node id order). */
enum : size_t {
    E_OFFSET = 0,    /* u64: byte offset of the node's data in the file */
    E_BYTES = 8,     /* u32: bytes stored */
    E_CRC = 12,      /* u32: CRC32 of those bytes */
    E_CODEC = 16,    /* u8: Codec */
    E_FLAGS = 17,    /* u8: tp_node_meta.flags */
    E_RESERVED = 18, /* u16: 0 */
    E_QMIN = 20,     /* i32 x 4: qmin, qmax, area_qmin, area_qmax */
    E_DELTA = 36,    /* u16 x (n+1): delta[0..n]; then u16 x 4n: eps[side][0..n-1] */
};
inline size_t entry_bytes(int n) { return E_DELTA + 2 * (size_t)(n + 1) + 8 * (size_t)n; }

/* Footer: the last FOOTER_BYTES of the file. */
enum : size_t {
    F_TABLE_OFFSET = 0, /* u64 */
    F_TABLE_BYTES = 8,  /* u64 */
    F_TABLE_CRC = 16,   /* u32 */
    F_FOOTER_CRC = 20,  /* u32: CRC32 of footer bytes 0..19 */
    F_END_MAGIC = 24,   /* 8 bytes */
    FOOTER_BYTES = 32,
};

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
/* Upper bound of the bytes one node can take in the file (either codec). */
size_t max_stored_bytes(int n);

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
