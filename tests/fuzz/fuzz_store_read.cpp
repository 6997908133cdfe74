/*
 * fuzz_store_read.cpp - libFuzzer entry point for the terrain store reader (io/src/
 * store_read.cpp): tp_store_open, then tp_store_read_node on every node. The first byte of the
 * input is a switch, the rest the file. With bit 0 of the switch set, the harness first
 * rewrites every checksum it can locate (docs/store.md's layout, format 2: the header's, each
 * node's in the location table, both tables' and the footer's) to match the bytes, so that mutations get past the
 * CRC32 checks and reach the geometry, table and decoder checks behind them; with it clear the
 * file is read as it is, which exercises the checksums themselves. Invariants checked: a
 * failure has a message and leaves *out alone, metas match the geometry, every decoded sample
 * is TP_TREE_NO_HEIGHT or within its node's range. Seed: corpus/fuzz_store_read/, one small
 * store of real data written by make_seeds.cpp.
 */
#include "fuzz_util.h"
#include "tp_io.h"

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
uint64_t le64(const uint8_t* p) { return le32(p) | (uint64_t)le32(p + 4) << 32; }
void put32(uint8_t* p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (uint8_t)(v >> (8 * i));
}

void fix_checksums(std::vector<uint8_t>& f)
{
    const size_t size = f.size();
    if (size >= 20) {
        const uint32_t hb = le32(&f[12]);
        if (hb >= 164 && hb <= size)
            put32(&f[hb - 4], crc32_ref(f.data(), hb - 4));
    }
    /* format 2: the node table (104-byte metas) and the location table (24-byte entries: data
     * offset, size, CRC32, codec) at the places the footer names */
    if (size < 56 + 20)
        return;
    uint8_t* foot = &f[size - 56];
    const uint64_t meta_offset = le64(foot), meta_bytes = le64(foot + 8);
    const uint64_t loc_offset = le64(foot + 16), loc_bytes = le64(foot + 24);
    if (loc_offset <= size - 56 && loc_bytes <= size - 56 - loc_offset) {
        for (uint64_t e = 0; e + 24 <= loc_bytes; e += 24) {
            uint8_t* p = &f[loc_offset + e];
            const uint64_t off = le64(p);
            const uint32_t bytes = le32(p + 8);
            if (off <= size && bytes <= size - off)
                put32(p + 12, crc32_ref(&f[off], bytes));
        }
        put32(foot + 36, crc32_ref(&f[loc_offset], (size_t)loc_bytes));
    }
    if (meta_offset <= size - 56 && meta_bytes <= size - 56 - meta_offset)
        put32(foot + 32, crc32_ref(&f[meta_offset], (size_t)meta_bytes));
    put32(foot + 44, crc32_ref(foot, 44));
}

} // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size)
{
    if (size < 1)
        return 0;
    std::vector<uint8_t> file(data + 1, data + size);
    if (data[0] & 1)
        fix_checksums(file);
    const char* path = tp_fuzz_write_file("store.tpt", file.data(), file.size());
    if (!path)
        return 0;
    tp_store* none = reinterpret_cast<tp_store*>(&none);
    tp_store* st = none;
    tp_error err = {{0}};
    const tp_status s = tp_store_open(path, &st, &err);
    if (s != TP_OK) {
        TP_FUZZ_CHECK(st == none, "status %d wrote *out", (int)s);
        TP_FUZZ_CHECK(err.message[0] != '\0', "status %d without a message", (int)s);
        return 0;
    }
    tp_store_info info;
    tp_store_get_info(st, &info);
    size_t count = 0;
    const tp_node_meta* metas = tp_store_metas(st, &count);
    const tp_tree_geometry& g = info.header.geometry;
    TP_FUZZ_CHECK(count == (size_t)g.node_count, "%zu metas for %lld nodes", count,
                  (long long)g.node_count);
    TP_FUZZ_CHECK(g.n >= 4 && g.n <= TP_MAX_N, "n %d", g.n);
    const size_t samples_per_node = (size_t)((1 << g.n) + 1) * ((1 << g.n) + 1);
    std::vector<uint16_t> samples(samples_per_node);
    for (size_t id = 0; id < count; ++id) {
        std::fill(samples.begin(), samples.end(), 0x5A5A);
        tp_error e = {{0}};
        if (tp_store_read_node(st, (int64_t)id, samples.data(), samples.size(), &e) != TP_OK) {
            TP_FUZZ_CHECK(std::strstr(e.message, "node ") != nullptr, "no node in: %s", e.message);
            for (uint16_t v : samples)
                TP_FUZZ_CHECK(v == 0x5A5A, "a failed read wrote samples");
            continue;
        }
        const tp_node_meta& m = metas[id];
        for (uint16_t v : samples)
            TP_FUZZ_CHECK(v == TP_TREE_NO_HEIGHT ||
                              (m.qmin <= m.qmax && (int64_t)v <= (int64_t)m.qmax - m.qmin),
                          "node %zu: sample %u outside its range", id, v);
    }
    tp_store_close(st);
    return 0;
}
