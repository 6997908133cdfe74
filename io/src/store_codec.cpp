/* store_codec.cpp - a node's samples in and out of their stored bytes (docs/store.md, "Node
 * data"). CODEC_PLANAR_ZSTD predicts each sample from its left (a), upper (b) and upper-left (c)
 * neighbours as a + b - c (the plane through them; "mode 7" of lossless JPEG, ITU-T T.81
 * annex H), the first row from the left neighbour and the first column from the one above.
 * Terrain is smooth, so the residuals are small; zigzag makes them small unsigned numbers, and
 * splitting them into a plane of low bytes and a plane of high bytes (almost all 0) lets zstd's
 * entropy stage see two simple distributions. All arithmetic is modulo 2^16, so
 * TP_TREE_NO_HEIGHT (0xFFFF) needs no special case: a run of it predicts itself, its edges cost
 * a few bytes. docs/store.md has the measurements that chose this over zstd alone, the left
 * neighbour and LOCO-I's median edge detector (tests/bench/bench_store.c). */
#include "store_format.hpp"

#include <zlib.h>
#include <zstd.h>

#include <algorithm>
#include <climits>
#include <new>

namespace tpio {
namespace store {

uint32_t crc32_of(const void* data, size_t size) { return crc32_continue(0, data, size); }

uint32_t crc32_continue(uint32_t crc_so_far, const void* data, size_t size)
{
    uLong crc = crc_so_far;
    const Bytef* p = static_cast<const Bytef*>(data);
    while (size > 0) { /* zlib takes uInt lengths */
        const uInt piece = (uInt)std::min<size_t>(size, UINT_MAX);
        crc = crc32(crc, p, piece);
        p += piece;
        size -= piece;
    }
    return (uint32_t)crc;
}

size_t max_stored_bytes(int n)
{
    const size_t raw = 2 * sample_count(n);
    return std::max(raw, ZSTD_compressBound(raw)) + mask_bytes(n) +
           ZSTD_compressBound(filled_raw_bytes(n)) + 4;
}

void encode_filled(const uint16_t* bits, size_t words, int level, void* cctx,
                   std::vector<uint8_t>* out)
{
    std::vector<uint8_t> raw(2 * words);
    for (size_t k = 0; k < words; ++k)
        put_u16(raw.data() + 2 * k, bits[k]);
    const size_t at = out->size();
    out->resize(at + ZSTD_compressBound(raw.size()));
    const size_t got = ZSTD_compressCCtx((ZSTD_CCtx*)cctx, out->data() + at, out->size() - at,
                                         raw.data(), raw.size(), level);
    if (ZSTD_isError(got))
        throw std::bad_alloc(); /* cannot happen with a correct bound */
    out->resize(at + got);
}

bool decode_filled(const uint8_t* data, size_t size, size_t words, void* dctx,
                   std::vector<uint8_t>* scratch, uint16_t* bits, std::string* why)
{
    const unsigned long long content = ZSTD_getFrameContentSize(data, size);
    if (content != 2 * words) {
        *why = "its filled bits are not a zstd frame of " + std::to_string(2 * words) + " bytes";
        return false;
    }
    scratch->resize(2 * words);
    const size_t got = ZSTD_decompressDCtx((ZSTD_DCtx*)dctx, scratch->data(), scratch->size(),
                                           data, size);
    if (ZSTD_isError(got) || got != 2 * words) {
        *why = std::string("its filled bits do not decode: ") +
               (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "wrong size");
        return false;
    }
    for (size_t k = 0; k < words; ++k)
        bits[k] = get_u16(scratch->data() + 2 * k);
    return true;
}

namespace {

inline uint16_t predict(const uint16_t* row, const uint16_t* up, int i)
{
    if (!up)
        return i > 0 ? row[i - 1] : 0;
    if (i == 0)
        return up[0];
    return (uint16_t)(row[i - 1] + up[i] - up[i - 1]);
}

inline uint16_t zigzag(uint16_t residual)
{
    const uint16_t sign = (residual & 0x8000u) ? 0xFFFFu : 0u;
    return (uint16_t)((uint16_t)(residual << 1) ^ sign);
}

inline uint16_t unzigzag(uint16_t z) { return (uint16_t)((z >> 1) ^ (uint16_t)(0u - (z & 1u))); }

} // namespace

Codec encode_node(const uint16_t* samples, int side, int level, void* cctx,
                  std::vector<uint8_t>* scratch, std::vector<uint8_t>* out)
{
    const size_t count = (size_t)side * side;
    scratch->resize(2 * count);
    uint8_t* lo = scratch->data();
    uint8_t* hi = lo + count;
    for (int j = 0; j < side; ++j) {
        const uint16_t* row = samples + (size_t)j * side;
        const uint16_t* up = j > 0 ? row - side : nullptr;
        for (int i = 0; i < side; ++i) {
            const uint16_t z = zigzag((uint16_t)(row[i] - predict(row, up, i)));
            lo[(size_t)j * side + i] = (uint8_t)z;
            hi[(size_t)j * side + i] = (uint8_t)(z >> 8);
        }
    }
    out->resize(ZSTD_compressBound(2 * count));
    const size_t got = ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(cctx), out->data(), out->size(),
                                         scratch->data(), 2 * count, level);
    if (!ZSTD_isError(got) && got < 2 * count) {
        out->resize(got);
        return CODEC_PLANAR_ZSTD;
    }
    out->resize(2 * count);
    for (size_t k = 0; k < count; ++k)
        put_u16(out->data() + 2 * k, samples[k]);
    return CODEC_RAW;
}

bool decode_node(Codec codec, const uint8_t* data, size_t size, int side, void* dctx,
                 std::vector<uint8_t>* scratch, uint16_t* samples, std::string* why)
{
    const size_t count = (size_t)side * side;
    if (codec == CODEC_RAW) {
        if (size != 2 * count) {
            *why = "raw node of " + std::to_string(size) + " bytes, expected " +
                   std::to_string(2 * count);
            return false;
        }
        for (size_t k = 0; k < count; ++k)
            samples[k] = get_u16(data + 2 * k);
        return true;
    }
    if (codec != CODEC_PLANAR_ZSTD) {
        *why = "unknown codec " + std::to_string((int)codec);
        return false;
    }
    /* The frame must say its size, and say the right one, before anything is decompressed. */
    const unsigned long long frame = ZSTD_getFrameContentSize(data, size);
    if (frame != 2 * count) {
        *why = frame == ZSTD_CONTENTSIZE_ERROR     ? std::string("not a zstd frame")
               : frame == ZSTD_CONTENTSIZE_UNKNOWN ? std::string("zstd frame without a size")
                                                   : "zstd frame of " + std::to_string(frame) +
                                                       " bytes, expected " +
                                                       std::to_string(2 * count);
        return false;
    }
    scratch->resize(2 * count);
    const size_t got =
        ZSTD_decompressDCtx(static_cast<ZSTD_DCtx*>(dctx), scratch->data(), 2 * count, data, size);
    if (ZSTD_isError(got)) {
        *why = std::string("zstd: ") + ZSTD_getErrorName(got);
        return false;
    }
    if (got != 2 * count) {
        *why = "decoded " + std::to_string(got) + " bytes, expected " + std::to_string(2 * count);
        return false;
    }
    const uint8_t* lo = scratch->data();
    const uint8_t* hi = lo + count;
    for (int j = 0; j < side; ++j) {
        uint16_t* row = samples + (size_t)j * side;
        const uint16_t* up = j > 0 ? row - side : nullptr;
        const size_t base = (size_t)j * side;
        for (int i = 0; i < side; ++i)
            row[i] = (uint16_t)(predict(row, up, i) +
                                unzigzag((uint16_t)(lo[base + i] | hi[base + i] << 8)));
    }
    return true;
}

} // namespace store
} // namespace tpio
