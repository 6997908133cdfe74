/* imagery_codec.cpp - an imagery block's texels in and out of their stored bytes
 * (docs/imagery.md, "Block data"). CODEC_ZSTD splits the RGBA texels into four planes (all
 * reds, then greens, blues, alphas) and replaces each texel of a plane by its difference from
 * its left neighbour (the first of a row: from the one above; the first of the block: from 0),
 * modulo 256, then compresses the planes as one zstd frame. Photographs and scanned maps are
 * smooth along a row and the alpha plane is almost constant, so the differences are small and
 * zstd's entropy stage sees four simple distributions; docs/imagery.md has the measurement
 * against zstd of the interleaved texels. */
#include "imagery_format.hpp"

#include <zstd.h>

#include <algorithm>
#include <cstring>
#include <new>

namespace tpio {
namespace imagery {

size_t max_block_bytes()
{
    return std::max(BLOCK_BYTES, ZSTD_compressBound(BLOCK_BYTES));
}

Codec encode_block(const uint8_t* rgba, int level, void* cctx, std::vector<uint8_t>* scratch,
                   std::vector<uint8_t>* out)
{
    const size_t count = (size_t)BLOCK * BLOCK;
    bool any = false;
    for (size_t k = 0; k < count && !any; ++k)
        any = rgba[4 * k + 3] != 0;
    if (!any) {
        out->clear();
        return CODEC_EMPTY;
    }
    scratch->resize(BLOCK_BYTES);
    uint8_t* planes = scratch->data();
    for (int c = 0; c < 4; ++c) {
        uint8_t* p = planes + (size_t)c * count;
        for (int y = 0; y < BLOCK; ++y) {
            const uint8_t* row = rgba + (size_t)y * BLOCK * 4 + c;
            uint8_t prev = y > 0 ? row[-(ptrdiff_t)BLOCK * 4] : 0;
            uint8_t* d = p + (size_t)y * BLOCK;
            for (int x = 0; x < BLOCK; ++x) {
                const uint8_t v = row[4 * x];
                d[x] = (uint8_t)(v - prev);
                prev = v;
            }
        }
    }
    out->resize(ZSTD_compressBound(BLOCK_BYTES));
    const size_t got = ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(cctx), out->data(), out->size(),
                                         planes, BLOCK_BYTES, level);
    if (!ZSTD_isError(got) && got < BLOCK_BYTES) {
        out->resize(got);
        return CODEC_ZSTD;
    }
    out->assign(rgba, rgba + BLOCK_BYTES);
    return CODEC_RAW;
}

bool decode_block(Codec codec, const uint8_t* data, size_t size, void* dctx,
                  std::vector<uint8_t>* scratch, uint8_t* rgba, std::string* why)
{
    const size_t count = (size_t)BLOCK * BLOCK;
    switch (codec) {
    case CODEC_EMPTY:
        if (size != 0) {
            *why = "empty block with " + std::to_string(size) + " bytes";
            return false;
        }
        std::memset(rgba, 0, BLOCK_BYTES);
        return true;
    case CODEC_RAW:
        if (size != BLOCK_BYTES) {
            *why = "raw block of " + std::to_string(size) + " bytes, expected " +
                   std::to_string(BLOCK_BYTES);
            return false;
        }
        std::memcpy(rgba, data, BLOCK_BYTES);
        return true;
    case CODEC_ZSTD: break;
    default: *why = "unknown codec " + std::to_string((int)codec); return false;
    }
    /* The frame must say its size, and the right one, before anything is decompressed. */
    const unsigned long long frame = ZSTD_getFrameContentSize(data, size);
    if (frame != BLOCK_BYTES) {
        *why = frame == ZSTD_CONTENTSIZE_ERROR ? std::string("not a zstd frame")
               : frame == ZSTD_CONTENTSIZE_UNKNOWN
                   ? std::string("zstd frame without a size")
                   : "zstd frame of " + std::to_string(frame) + " bytes, expected " +
                         std::to_string(BLOCK_BYTES);
        return false;
    }
    scratch->resize(BLOCK_BYTES);
    const size_t got = ZSTD_decompressDCtx(static_cast<ZSTD_DCtx*>(dctx), scratch->data(),
                                           BLOCK_BYTES, data, size);
    if (ZSTD_isError(got)) {
        *why = std::string("zstd: ") + ZSTD_getErrorName(got);
        return false;
    }
    if (got != BLOCK_BYTES) {
        *why = "decoded " + std::to_string(got) + " bytes, expected " + std::to_string(BLOCK_BYTES);
        return false;
    }
    const uint8_t* planes = scratch->data();
    for (int c = 0; c < 4; ++c) {
        const uint8_t* p = planes + (size_t)c * count;
        for (int y = 0; y < BLOCK; ++y) {
            uint8_t* row = rgba + (size_t)y * BLOCK * 4 + c;
            uint8_t prev = y > 0 ? row[-(ptrdiff_t)BLOCK * 4] : 0;
            const uint8_t* d = p + (size_t)y * BLOCK;
            for (int x = 0; x < BLOCK; ++x) {
                prev = (uint8_t)(prev + d[x]);
                row[4 * x] = prev;
            }
        }
    }
    return true;
}

} // namespace imagery
} // namespace tpio
