/* imagery_format.hpp - the byte layout of an imagery pyramid (.tpi, and a light map's .tpl),
 * shared by imagery_pyramid.cpp (the writer) and imagery_read.cpp; docs/imagery.md describes it
 * byte by byte. Private to io/.
 *
 *   [header: magic, version, header_bytes, fields, CRS, notes, CRC32] [0..7 zero bytes]
 *   [block table: block_count entries (offset, size, CRC32, codec), level by level, row-major]
 *   [block data, level 0's first block row, ... in the order the writer made them]
 *   [footer: the table's offset, size and CRC32, footer CRC32, end magic]
 *
 * Integers little-endian, doubles IEEE 754 binary64 as their little-endian bits (the store's
 * helpers, store_format.hpp). */
#pragma once

#include "store_format.hpp"
#include "tp_imagery.h"

#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace tpio {
namespace imagery {

using store::crc32_continue;
using store::crc32_of;
using store::get_f64;
using store::get_u32;
using store::get_u64;
using store::put_f64;
using store::put_u32;
using store::put_u64;

/* Version 1: imagery only, a fixed header of 176 bytes (H_KIND reserved, 0). Version 2 (what
 * is written): the kind at H_KIND and the day (H_TIME_FIRST .. H_RESERVED2) after the fields
 * of version 1, a fixed header of 200 bytes. */
constexpr uint32_t VERSION = 2;
constexpr uint8_t MAGIC[8] = {0x89, 'T', 'P', 'I', '\r', '\n', 0x1a, '\n'};
constexpr uint8_t END_MAGIC[8] = {'T', 'P', 'I', 'E', 'N', 'D', '\r', '\n'};

enum : size_t {
    H_MAGIC = 0,
    H_VERSION = 8,
    H_HEADER_BYTES = 12,
    H_BLOCK = 16,
    H_LEVELS = 20,
    H_TEXEL_SHIFT = 24, /* i32 */
    H_GRID_WIDTH = 28,
    H_GRID_HEIGHT = 32,
    H_KIND = 36, /* TP_IMAGERY_KIND_* (version 1: 0) */
    H_WIDTH = 40, /* u64 */
    H_HEIGHT = 48,
    H_GEOTRANSFORM = 56,       /* 6 doubles: level 0 */
    H_GRID_GEOTRANSFORM = 104, /* 6 doubles */
    H_BLOCK_COUNT = 152,
    H_NONEMPTY = 160,
    H_CRS_BYTES = 168,
    H_NOTES_BYTES = 172,
    H_FIXED_BYTES_V1 = 176, /* version 1: then crs_wkt, notes, CRC32 */
    H_TIME_FIRST = 176,     /* version 2: double, Unix seconds (0 for imagery) */
    H_TIME_LAST = 184,      /* double */
    H_MAPS = 192,           /* u32 (0 for imagery) */
    H_RESERVED2 = 196,      /* u32 0 */
    H_FIXED_BYTES = 200,    /* version 2: then crs_wkt, notes, CRC32 */
};

/* The fixed part of a header of a version (0 for an unknown one). */
inline size_t fixed_bytes(uint32_t version)
{
    return version == 1 ? (size_t)H_FIXED_BYTES_V1 : version == 2 ? (size_t)H_FIXED_BYTES : 0;
}
constexpr uint32_t MAX_STRING_BYTES = 16u << 20;

/* What is wrong with a pyramid's kind and day (the header's H_KIND .. H_MAPS and its texel
 * shift), or nullptr: imagery has no day (times and maps 0); a light map a day of finite times,
 * first < last, from two or more maps, a texel a post (shift 0). */
inline const char* kind_problem(uint32_t kind, double first_s, double last_s, uint32_t maps,
                                int shift)
{
    if (kind == TP_IMAGERY_KIND_IMAGE)
        return first_s == 0 && last_s == 0 && maps == 0 ? nullptr
                                                        : "imagery with a day (times or maps)";
    if (kind != TP_IMAGERY_KIND_LIGHT_TIMES)
        return "unknown kind";
    if (!std::isfinite(first_s) || !std::isfinite(last_s) || !(first_s < last_s))
        return "a light map whose day does not run forward (first time >= last)";
    if (maps < 2 || maps > INT32_MAX)
        return "a light map from fewer than 2 maps";
    if (shift != 0)
        return "a light map with a texel shift other than 0";
    return nullptr;
}

/* Block table entry */
enum : size_t {
    E_OFFSET = 0, /* u64 */
    E_BYTES = 8,  /* u32 */
    E_CRC = 12,   /* u32 */
    E_CODEC = 16, /* u8, then 7 bytes 0 */
    ENTRY_BYTES = 24,
};

/* Footer: the last FOOTER_BYTES of the file */
enum : size_t {
    F_TABLE_OFFSET = 0, /* u64 */
    F_TABLE_BYTES = 8,  /* u64 */
    F_TABLE_CRC = 16,   /* u32 */
    F_RESERVED = 20,    /* u32 0 */
    F_FOOTER_CRC = 24,  /* u32: CRC32 of bytes 0..23 */
    F_RESERVED2 = 28,   /* u32 0 */
    F_END_MAGIC = 32,
    FOOTER_BYTES = 40,
};

enum Codec : uint8_t {
    CODEC_EMPTY = 0, /* no bytes: every texel 0 */
    CODEC_ZSTD = 1,  /* planes R, G, B, A, each row left-delta coded, one zstd frame */
    CODEC_RAW = 2,   /* block * block * 4 bytes RGBA */
};

constexpr int BLOCK = TP_IMAGERY_BLOCK;
constexpr size_t BLOCK_BYTES = (size_t)BLOCK * BLOCK * 4;

/* The geometry a pyramid of (grid, texel_shift) has: level sizes and block counts. */
struct Geometry {
    int levels = 0;
    int64_t width[TP_IMAGERY_MAX_LEVELS] = {0}, height[TP_IMAGERY_MAX_LEVELS] = {0};
    int cols[TP_IMAGERY_MAX_LEVELS] = {0}, rows[TP_IMAGERY_MAX_LEVELS] = {0};
    uint64_t first[TP_IMAGERY_MAX_LEVELS] = {0}; /* index of block (l, 0, 0) in the table */
    uint64_t block_count = 0;
    double gt[6];
};

/* false when the shift is out of range or the level-0 side exceeds 2^31 texels. */
inline bool geometry_for(int grid_width, int grid_height, const double grid_gt[6], int shift,
                         Geometry* g)
{
    if (grid_width < 1 || grid_height < 1 || shift < TP_IMAGERY_SHIFT_MIN ||
        shift > TP_IMAGERY_SHIFT_MAX)
        return false;
    const auto scale = [shift](int64_t n) -> int64_t {
        return shift >= 0 ? n << shift : (n + ((int64_t)1 << -shift) - 1) >> -shift;
    };
    int64_t w = scale(grid_width), h = scale(grid_height);
    if (w > ((int64_t)1 << 31) || h > ((int64_t)1 << 31))
        return false;
    const double f = std::ldexp(1.0, -shift); /* exact */
    g->gt[0] = grid_gt[0], g->gt[3] = grid_gt[3];
    g->gt[1] = grid_gt[1] * f, g->gt[2] = grid_gt[2] * f;
    g->gt[4] = grid_gt[4] * f, g->gt[5] = grid_gt[5] * f;
    g->levels = 0;
    g->block_count = 0;
    for (;;) {
        const int l = g->levels++;
        g->width[l] = w, g->height[l] = h;
        g->cols[l] = (int)((w + BLOCK - 1) / BLOCK), g->rows[l] = (int)((h + BLOCK - 1) / BLOCK);
        g->first[l] = g->block_count;
        g->block_count += (uint64_t)g->cols[l] * g->rows[l];
        if (w <= BLOCK && h <= BLOCK)
            return true;
        if (g->levels == TP_IMAGERY_MAX_LEVELS)
            return false; /* cannot happen for 2^31 */
        w = (w + 1) / 2, h = (h + 1) / 2;
    }
}

/* Encodes a block (BLOCK_BYTES of RGBA) as CODEC_ZSTD, or CODEC_RAW when that is not smaller,
 * or CODEC_EMPTY (no bytes) when every alpha is 0. out is resized. */
Codec encode_block(const uint8_t* rgba, int level, void* cctx, std::vector<uint8_t>* scratch,
                   std::vector<uint8_t>* out);
/* Decodes stored bytes into rgba (BLOCK_BYTES); false with why. */
bool decode_block(Codec codec, const uint8_t* data, size_t size, void* dctx,
                  std::vector<uint8_t>* scratch, uint8_t* rgba, std::string* why);
/* Upper bound of a stored block's bytes. */
size_t max_block_bytes();

} // namespace imagery
} // namespace tpio
