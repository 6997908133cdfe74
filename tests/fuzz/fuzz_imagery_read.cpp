/*
 * fuzz_imagery_read.cpp - libFuzzer entry point for the imagery pyramid reader (io/src/
 * imagery_read.cpp): tp_imagery_open, then tp_imagery_read_block on every block of every
 * level (and a few out of range). The first byte of the input is a switch, the rest the file.
 * With bit 0 of the switch set, the harness first rewrites every checksum it can locate
 * (docs/imagery.md's layout: the header's, each block's in the table, the table's and the
 * footer's) to match the bytes, so that mutations get past the CRC32 checks and reach the
 * geometry, table and decoder checks behind them; with it clear the file is read as it is.
 * Invariants checked: a failure has a message and leaves *out alone; a failed block read names
 * the block and leaves the buffer alone; an empty block (tp_imagery_block_is_empty) reads as
 * zeros; the level sizes halve (rounded up) down to one block. Seed: corpus/fuzz_imagery_read/,
 * a small pyramid of the Crater Lake imagery written by make_seeds.cpp.
 */
#include "fuzz_util.h"
#include "tp_imagery.h"

#include <algorithm>
#include <cstring>
#include <vector>

namespace {

uint32_t crc32_ref(const uint8_t* p, size_t n)
{
    uint32_t c = 0xFFFFFFFFu;
    for (size_t i = 0; i < n; i++) {
        c ^= p[i];
        for (int k = 0; k < 8; k++)
            c = (c >> 1) ^ (0xEDB88320u & (0u - (c & 1u)));
    }
    return ~c;
}
uint32_t le32(const uint8_t* p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
uint64_t le64(const uint8_t* p)
{
    return le32(p) | (uint64_t)le32(p + 4) << 32;
}
void put32(uint8_t* p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

constexpr size_t FOOTER = 40;

void fix_checksums(std::vector<uint8_t>& f)
{
    const size_t size = f.size();
    if (size >= 20) {
        const uint32_t hb = le32(&f[12]);
        if (hb >= 180 && hb <= size)
            put32(&f[hb - 4], crc32_ref(f.data(), hb - 4));
    }
    if (size < FOOTER + 20)
        return;
    uint8_t* foot = &f[size - FOOTER];
    const uint64_t table = le64(foot), table_bytes = le64(foot + 8);
    if (table <= size - FOOTER && table_bytes <= size - FOOTER - table) {
        for (uint64_t e = 0; e + 24 <= table_bytes; e += 24) {
            uint8_t* p = &f[table + e];
            const uint64_t off = le64(p);
            const uint32_t bytes = le32(p + 8);
            if (p[16] != 0 && off <= size && bytes <= size - off)
                put32(p + 12, crc32_ref(&f[off], bytes));
        }
        put32(foot + 16, crc32_ref(&f[table], (size_t)table_bytes));
    }
    put32(foot + 24, crc32_ref(foot, 24));
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
        return 0;
    std::vector<uint8_t> file(data + 1, data + size);
    if (data[0] & 1)
        fix_checksums(file);
    const char* path = tp_fuzz_write_file("imagery.tpi", file.data(), file.size());
    if (!path)
        return 0;
    tp_imagery* none = reinterpret_cast<tp_imagery*>(&none);
    tp_imagery* im = none;
    tp_error err = {{0}};
    const tp_status s = tp_imagery_open(path, &im, &err);
    if (s != TP_OK) {
        TP_FUZZ_CHECK(im == none, "status %d wrote *out", (int)s);
        TP_FUZZ_CHECK(err.message[0] != '\0', "status %d without a message", (int)s);
        return 0;
    }
    tp_imagery_info info;
    tp_imagery_get_info(im, &info);
    TP_FUZZ_CHECK(info.levels >= 1 && info.levels <= TP_IMAGERY_MAX_LEVELS, "%d levels",
                  info.levels);
    std::vector<uint8_t> rgba((size_t)TP_IMAGERY_BLOCK * TP_IMAGERY_BLOCK * 4);
    uint64_t reads = 0;
    for (int l = 0; l < info.levels; l++) {
        int64_t w, h;
        int cols, rows;
        tp_imagery_level_size(im, l, &w, &h, &cols, &rows);
        if (l == info.levels - 1)
            TP_FUZZ_CHECK(w <= TP_IMAGERY_BLOCK && h <= TP_IMAGERY_BLOCK, "last level %lldx%lld",
                          (long long)w, (long long)h);
        else {
            int64_t w1, h1;
            tp_imagery_level_size(im, l + 1, &w1, &h1, nullptr, nullptr);
            TP_FUZZ_CHECK(w1 == (w + 1) / 2 && h1 == (h + 1) / 2, "level %d does not halve", l);
        }
        for (int by = -1; by <= rows; by++)
            for (int bx = -1; bx <= cols; bx++) {
                if (++reads > 4096) /* a file claiming millions of blocks: enough */
                    break;
                std::fill(rgba.begin(), rgba.end(), 0x5A);
                tp_error e = {{0}};
                const int empty = tp_imagery_block_is_empty(im, l, bx, by);
                if (tp_imagery_read_block(im, l, bx, by, rgba.data(), &e) != TP_OK) {
                    TP_FUZZ_CHECK(!empty, "an empty block failed to read");
                    TP_FUZZ_CHECK(std::strstr(e.message, "block (") != nullptr, "no block in: %s",
                                  e.message);
                    for (uint8_t v : rgba)
                        TP_FUZZ_CHECK(v == 0x5A, "a failed read wrote texels");
                    continue;
                }
                if (empty)
                    for (uint8_t v : rgba)
                        TP_FUZZ_CHECK(v == 0, "an empty block read as not zero");
            }
    }
    tp_imagery_close(im);
    return 0;
}
