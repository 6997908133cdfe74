/* imagery_pyramid.hpp - writing a pyramid file (.tpi, .tpl) whose level-0 block rows come in
 * order from a caller (imagery_build.cpp warps them from rasters, imagery_rows.cpp asks a
 * callback): the coarser levels made as the rows come (one block row a level in memory), the
 * blocks compressed by threads and appended, the table, footer and header, the file committed
 * whole (imagery_pyramid.cpp; the layout in imagery_format.hpp). Private to io/. */
#pragma once

#include "atomic_write.hpp"
#include "imagery_format.hpp"

#include <string>
#include <vector>

namespace tpio {
namespace imagery {

/* One output file: set the fields marked "in", then begin, finish_row for each level-0 block
 * row in order (its texels in level[0]), then commit. The destructor abandons an uncommitted
 * file (nothing left behind). */
struct Pyramid {
    /* in */
    const char* path = nullptr;
    const tp_imagery_target* target = nullptr;
    Geometry g; /* geometry_for(target, shift) */
    int shift = 0;
    int kind = TP_IMAGERY_KIND_IMAGE;
    double time_first_s = 0, time_last_s = 0;
    int maps = 0;
    std::string crs, notes;
    int threads = 1; /* compressing threads */
    /* the writer's */
    std::vector<std::vector<uint8_t>> level; /* one block row per level, cols * 256 wide */
    tp_file_writer* file = nullptr;
    uint64_t table_offset = 0, data_offset = 0, offset = 0, nonempty = 0;
    std::vector<void*> cctx;                                   /* ZSTD_CCtx, per thread */
    std::vector<std::vector<uint8_t>> gather, scratch, packed; /* per thread */
    std::vector<std::vector<uint8_t>> chunk_out;
    std::vector<Codec> chunk_codec;
    std::vector<uint8_t> entries;
    ~Pyramid();
};

/* A render grid a pyramid can be built for: a size >= 1x1, a CRS string, an invertible finite
 * geotransform. */
inline bool target_ok(const tp_imagery_target* t)
{
    return t->width >= 1 && t->height >= 1 && t->crs_wkt && std::isfinite(t->geotransform[1]) &&
           std::isfinite(t->geotransform[5]) &&
           t->geotransform[1] * t->geotransform[5] - t->geotransform[2] * t->geotransform[4] != 0;
}

/* Bytes the writer holds for g and threads: a block row of every level, the threads' buffers
 * and zstd contexts (what a build checks against its memory budget). */
double pyramid_bytes(const Geometry& g, int threads);

/* Allocates the level rows (zeroed) and the threads' buffers, starts the file (the header, the
 * table reserved). tp_file_begin's errors; std::bad_alloc. */
tp_status pyramid_begin(Pyramid& p, tp_error* err);

/* Level 0's block row `row` is complete in p.level[0] (zero beyond the level's width and
 * height): writes it and every coarser block row it completes. p.level[0] may be overwritten
 * afterwards. Write errors. */
tp_status pyramid_finish_row(Pyramid& p, int row, tp_error* err);

/* pyramid_finish_row, then what every builder does after a row: fails, naming out_path, after
 * SIGINT/SIGTERM (tp_interrupted), and reports progress through o (of p's level-0 rows). */
tp_status pyramid_row_done(Pyramid& p, int row, const char* out_path,
                           const tp_imagery_build_options* o, tp_error* err);

/* After the last row: the table's CRC32, the footer, the header with the count of non-empty
 * blocks; commits the file. Write errors (the file then abandoned). */
tp_status pyramid_commit(Pyramid& p, tp_error* err);

} // namespace imagery
} // namespace tpio
