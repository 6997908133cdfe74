/* imagery_pyramid.cpp - a pyramid file written as its level-0 block rows come
 * (imagery_pyramid.hpp; tp_imagery.h, docs/imagery.md). Level l + 1 is made from level l as
 * its block rows come (two block rows of level l make one of level l + 1), so each level keeps
 * one block row in memory and the level-0 image is never whole: for imagery the alpha-weighted
 * 2x2 mean (written here: GDAL's average ignores alpha as a weight), for a light map each
 * texel tp_light_times_mean of its 2x2. Blocks are compressed by threads (imagery_codec.cpp)
 * and appended in order; the block table (its place follows from the geometry, reserved as a
 * hole) is written a block row at a time, checksummed at commit by reading it back, then the
 * footer, then the header again with the count of non-empty blocks; tp_file_commit makes the
 * file. */
#include "imagery_pyramid.hpp"
#include "io_util.hpp"

#include <zstd.h>

#include <algorithm>
#include <atomic>
#include <new>
#include <thread>

namespace tpio {
namespace imagery {

namespace {

constexpr int ZSTD_LEVEL = 1; /* docs/imagery.md: measured */

std::vector<uint8_t> encode_header(const Pyramid& b)
{
    const size_t size = H_FIXED_BYTES + b.crs.size() + b.notes.size() + 4;
    std::vector<uint8_t> h(size, 0);
    uint8_t* p = h.data();
    std::memcpy(p + H_MAGIC, MAGIC, 8);
    put_u32(p + H_VERSION, VERSION);
    put_u32(p + H_HEADER_BYTES, (uint32_t)size);
    put_u32(p + H_BLOCK, BLOCK);
    put_u32(p + H_LEVELS, (uint32_t)b.g.levels);
    put_u32(p + H_TEXEL_SHIFT, (uint32_t)(int32_t)b.shift);
    put_u32(p + H_GRID_WIDTH, (uint32_t)b.target->width);
    put_u32(p + H_GRID_HEIGHT, (uint32_t)b.target->height);
    put_u32(p + H_KIND, (uint32_t)b.kind);
    put_u64(p + H_WIDTH, (uint64_t)b.g.width[0]);
    put_u64(p + H_HEIGHT, (uint64_t)b.g.height[0]);
    for (int i = 0; i < 6; ++i) {
        put_f64(p + H_GEOTRANSFORM + 8 * i, b.g.gt[i]);
        put_f64(p + H_GRID_GEOTRANSFORM + 8 * i, b.target->geotransform[i]);
    }
    put_u64(p + H_BLOCK_COUNT, b.g.block_count);
    put_u64(p + H_NONEMPTY, b.nonempty);
    put_u32(p + H_CRS_BYTES, (uint32_t)b.crs.size());
    put_u32(p + H_NOTES_BYTES, (uint32_t)b.notes.size());
    put_f64(p + H_TIME_FIRST, b.time_first_s);
    put_f64(p + H_TIME_LAST, b.time_last_s);
    put_u32(p + H_MAPS, (uint32_t)b.maps);
    std::memcpy(p + H_FIXED_BYTES, b.crs.data(), b.crs.size());
    std::memcpy(p + H_FIXED_BYTES + b.crs.size(), b.notes.data(), b.notes.size());
    put_u32(p + size - 4, crc32_of(p, size - 4));
    return h;
}

/* Encodes and appends block row `row` of level l (b.level[l]); writes its table entries. */
tp_status write_row(Pyramid& b, int l, int row, tp_error* err)
{
    const int cols = b.g.cols[l];
    const size_t stride = (size_t)cols * BLOCK * 4;
    const uint8_t* buf = b.level[l].data();
    b.entries.assign((size_t)cols * ENTRY_BYTES, 0);
    const int chunk = std::max(1, b.threads * 4);
    for (int c0 = 0; c0 < cols; c0 += chunk) {
        const int n = std::min(chunk, cols - c0);
        std::atomic<int> next{0};
        std::atomic<bool> failed{false}; /* out of memory in a thread */
        auto encode_some = [&](int t) {
            for (int k; (k = next.fetch_add(1)) < n;) {
                const int bx = c0 + k;
                uint8_t* g = b.gather[t].data();
                for (int y = 0; y < BLOCK; ++y)
                    std::memcpy(g + (size_t)y * BLOCK * 4,
                                buf + y * stride + (size_t)bx * BLOCK * 4, (size_t)BLOCK * 4);
                b.chunk_codec[k] =
                    encode_block(g, ZSTD_LEVEL, b.cctx[t], &b.scratch[t], &b.packed[t]);
                b.chunk_out[k].assign(b.packed[t].begin(), b.packed[t].end());
            }
        };
        auto work = [&](int t) {
            try {
                encode_some(t);
            } catch (...) {
                failed = true;
            }
        };
        const int extra = std::min(b.threads, n) - 1;
        std::vector<std::thread> pool;
        try {
            for (int t = 1; t <= extra; ++t)
                pool.emplace_back(work, t);
        } catch (...) { /* fewer threads: this one does the rest */
        }
        work(0);
        for (std::thread& th : pool)
            th.join();
        if (failed)
            throw std::bad_alloc();
        for (int k = 0; k < n; ++k) {
            uint8_t* e = b.entries.data() + (size_t)(c0 + k) * ENTRY_BYTES;
            const std::vector<uint8_t>& out = b.chunk_out[k];
            if (b.chunk_codec[k] == CODEC_EMPTY)
                continue; /* all 0 */
            if (tp_status s = tp_file_append(b.file, out.data(), out.size(), err))
                return s;
            put_u64(e + E_OFFSET, b.offset);
            put_u32(e + E_BYTES, (uint32_t)out.size());
            put_u32(e + E_CRC, crc32_of(out.data(), out.size()));
            e[E_CODEC] = b.chunk_codec[k];
            b.offset += out.size();
            ++b.nonempty;
        }
    }
    const uint64_t first = b.g.first[l] + (uint64_t)row * cols;
    return tp_file_rewrite(b.file, b.table_offset + first * ENTRY_BYTES, b.entries.data(),
                           b.entries.size(), err);
}

/* Texel (u, v) of dst (stride dst_stride texels) from texels 2u..2u+1, 2v..2v+1 of src (stride
 * src_stride texels) that lie inside its first src_cols columns and src_rows rows: imagery the
 * alpha-weighted mean of the colours, alpha the plain mean over four (beyond src: alpha 0),
 * both rounded half up; a light map tp_light_times_mean of those there are. */
void halve(int kind, const uint8_t* src, int src_stride, int src_cols, int src_rows, uint8_t* dst,
           int dst_stride, int dst_cols, int dst_rows)
{
    for (int v = 0; v < dst_rows; ++v) {
        uint8_t* d = dst + (size_t)v * dst_stride * 4;
        for (int u = 0; u < dst_cols; ++u, d += 4) {
            const uint8_t* in[4];
            int n = 0;
            for (int j = 0; j < 2; ++j) {
                const int y = 2 * v + j;
                for (int i = 0; i < 2 && y < src_rows; ++i) {
                    const int x = 2 * u + i;
                    if (x < src_cols)
                        in[n++] = src + ((size_t)y * src_stride + x) * 4;
                }
            }
            if (n == 0) {
                d[0] = d[1] = d[2] = d[3] = 0;
                continue;
            }
            if (kind == TP_IMAGERY_KIND_LIGHT_TIMES) {
                tp_light_times_mean(in, n, d);
                continue;
            }
            uint32_t sa = 0, sc[3] = {0, 0, 0};
            for (int k = 0; k < n; ++k) {
                sa += in[k][3];
                for (int c = 0; c < 3; ++c)
                    sc[c] += (uint32_t)in[k][c] * in[k][3];
            }
            if (sa == 0) {
                d[0] = d[1] = d[2] = d[3] = 0;
                continue;
            }
            for (int c = 0; c < 3; ++c)
                d[c] = (uint8_t)((2 * sc[c] + sa) / (2 * sa));
            d[3] = (uint8_t)((sa + 2) / 4);
        }
    }
}

/* Level l's block row `row` is complete in b.level[l]: writes it and feeds level l + 1. */
tp_status finish_level_row(Pyramid& b, int l, int row, tp_error* err)
{
    if (tp_status s = write_row(b, l, row, err))
        return s;
    if (l + 1 >= b.g.levels)
        return TP_OK;
    std::vector<uint8_t>& up = b.level[l + 1];
    const int up_stride = b.g.cols[l + 1] * BLOCK;
    if (row % 2 == 0)
        std::fill(up.begin(), up.end(), 0);
    /* only the level's texels: a light map's mean must not count the blocks' padding */
    const int src_cols = (int)b.g.width[l];
    const int src_rows = (int)std::min<int64_t>(BLOCK, b.g.height[l] - (int64_t)row * BLOCK);
    const int dst_cols = (int)b.g.width[l + 1], dst_rows = (src_rows + 1) / 2;
    halve(b.kind, b.level[l].data(), b.g.cols[l] * BLOCK, src_cols, src_rows,
          up.data() + (size_t)(row % 2) * (BLOCK / 2) * up_stride * 4, up_stride, dst_cols,
          dst_rows);
    if (row % 2 == 1 || row == b.g.rows[l] - 1)
        return finish_level_row(b, l + 1, row / 2, err);
    return TP_OK;
}

} // namespace

Pyramid::~Pyramid()
{
    tp_file_abort(file);
    for (void* c : cctx)
        ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(c));
}

double pyramid_bytes(const Geometry& g, int threads)
{
    double rows_bytes = 0;
    for (int l = 0; l < g.levels; ++l)
        rows_bytes += (double)g.cols[l] * BLOCK * BLOCK * 4;
    return rows_bytes +
           (double)threads *
               (2.0 * BLOCK_BYTES + ZSTD_compressBound(BLOCK_BYTES) + 4 * max_block_bytes()) +
           threads * 1.5e6 /* zstd contexts */;
}

tp_status pyramid_begin(Pyramid& b, tp_error* err)
{
    const int threads = std::max(1, b.threads);
    b.level.resize((size_t)b.g.levels);
    for (int l = 0; l < b.g.levels; ++l)
        b.level[(size_t)l].assign((size_t)b.g.cols[l] * BLOCK * BLOCK * 4, 0);
    b.gather.resize((size_t)threads, std::vector<uint8_t>(BLOCK_BYTES));
    b.scratch.resize((size_t)threads);
    b.packed.resize((size_t)threads);
    b.chunk_out.resize((size_t)threads * 4);
    b.chunk_codec.resize((size_t)threads * 4);
    for (int i = 0; i < threads; ++i) {
        b.cctx.push_back(ZSTD_createCCtx());
        if (!b.cctx.back())
            throw std::bad_alloc();
    }
    const std::vector<uint8_t> head = encode_header(b);
    b.table_offset = (head.size() + 7) & ~(uint64_t)7;
    b.data_offset = b.table_offset + b.g.block_count * ENTRY_BYTES;
    b.offset = b.data_offset;
    tp_status st = tp_file_begin(b.path, &b.file, err);
    if (st == TP_OK)
        st = tp_file_append(b.file, head.data(), head.size(), err);
    if (st == TP_OK)
        st = file_reserve(b.file, b.data_offset - head.size(), err);
    return st;
}

tp_status pyramid_finish_row(Pyramid& b, int row, tp_error* err)
{
    return finish_level_row(b, 0, row, err);
}

tp_status pyramid_row_done(Pyramid& b, int row, const char* out_path,
                           const tp_imagery_build_options* o, tp_error* err)
{
    tp_status st = pyramid_finish_row(b, row, err);
    if (st == TP_OK && tp_interrupted())
        st = fail(err, TP_ERR_IO, "%s: interrupted (%s): not written", out_path,
                  tpio::interrupt_name());
    if (st == TP_OK && o->progress)
        o->progress(o->progress_user, (row + 1.0) / b.g.rows[0]);
    return st;
}

tp_status pyramid_commit(Pyramid& b, tp_error* err)
{
    /* The table's CRC32, read back in pieces; the footer; the header with the count */
    uint32_t crc = 0;
    tp_status st = TP_OK;
    const uint64_t table_bytes = b.g.block_count * ENTRY_BYTES;
    std::vector<uint8_t> piece((size_t)std::min<uint64_t>(table_bytes, 1 << 16) + 1);
    for (uint64_t done = 0; st == TP_OK && done < table_bytes;) {
        const size_t n = (size_t)std::min<uint64_t>(table_bytes - done, piece.size());
        st = file_read_back(b.file, b.table_offset + done, piece.data(), n, err);
        crc = crc32_continue(crc, piece.data(), n);
        done += n;
    }
    if (st == TP_OK) {
        uint8_t foot[FOOTER_BYTES] = {0};
        put_u64(foot + F_TABLE_OFFSET, b.table_offset);
        put_u64(foot + F_TABLE_BYTES, table_bytes);
        put_u32(foot + F_TABLE_CRC, crc);
        put_u32(foot + F_FOOTER_CRC, crc32_of(foot, F_FOOTER_CRC));
        std::memcpy(foot + F_END_MAGIC, END_MAGIC, 8);
        st = tp_file_append(b.file, foot, sizeof foot, err);
    }
    if (st == TP_OK) {
        const std::vector<uint8_t> final_head = encode_header(b); /* with the count */
        st = tp_file_rewrite(b.file, 0, final_head.data(), final_head.size(), err);
    }
    if (st == TP_OK) {
        tp_file_writer* f = b.file;
        b.file = nullptr; /* commit frees it, whatever happens */
        st = tp_file_commit(f, err);
    }
    return st;
}

} // namespace imagery
} // namespace tpio
