/* imagery_rows.cpp - tp_imagery_build_rows: a pyramid (a light map's .tpl) whose level-0 texels
 * a callback makes, a block row at a time, written by imagery_pyramid.cpp (tp_imagery.h,
 * docs/imagery.md). The callback fills a buffer of the level's width; its rows are copied into
 * the writer's block row (whose width is a whole number of blocks). */
#include "imagery_pyramid.hpp"
#include "io_util.hpp"

#include <algorithm>
#include <cinttypes>
#include <thread>

using namespace tpio::imagery;
using tpio::fail;

namespace {

tp_status build(const tp_imagery_target* t, const tp_imagery_rows* r,
                const tp_imagery_build_options* o, const char* out_path, tp_error* err)
{
    const double budget = o->memory_bytes > 0 ? o->memory_bytes : 1024.0 * 1024 * 1024;
    int threads = o->threads;
    if (threads <= 0)
        threads = (int)std::max(1u, std::min(64u, std::thread::hardware_concurrency()));
    Pyramid b;
    b.path = out_path;
    b.target = t;
    b.shift = r->texel_shift;
    b.threads = threads;
    b.kind = r->kind;
    if (r->kind == TP_IMAGERY_KIND_LIGHT_TIMES) {
        b.time_first_s = r->time_first_s;
        b.time_last_s = r->time_last_s;
        b.maps = r->maps;
    }
    if (!geometry_for(t->width, t->height, t->geotransform, b.shift, &b.g))
        return fail(err, TP_ERR_INVALID_ARG,
                    "%s: a %dx%d grid at texel shift %d makes a level 0 over 2^31 texels a side",
                    out_path, t->width, t->height, b.shift);
    const int64_t width = b.g.width[0];
    const double row_bytes = (double)width * BLOCK * 4; /* the callback's buffer */
    const double need = pyramid_bytes(b.g, threads) + row_bytes;
    if (need > 0.6 * budget)
        return fail(err, TP_ERR_OUT_OF_MEMORY,
                    "%s: a %" PRId64 "x%" PRId64
                    " level 0 needs %.0f MB for one block row of every level and %d threads' "
                    "buffers, over 60%% of the memory budget (%.0f MB): give %.0f MB or more",
                    out_path, width, b.g.height[0], need / 1048576.0, threads, budget / 1048576.0,
                    std::ceil(need / 0.6 / 1048576.0));
    b.crs = t->crs_wkt;
    b.notes = r->notes ? r->notes : "";
    if (b.crs.size() > MAX_STRING_BYTES || b.notes.size() > MAX_STRING_BYTES)
        return fail(err, TP_ERR_INVALID_ARG, "%s: CRS or notes over 16 MiB", out_path);
    std::vector<uint8_t> rows((size_t)row_bytes);
    tp_status st = pyramid_begin(b, err);
    const size_t stride = (size_t)b.g.cols[0] * BLOCK * 4, line = (size_t)width * 4;
    for (int row = 0; row < b.g.rows[0] && st == TP_OK; ++row) {
        const int64_t row0 = (int64_t)row * BLOCK;
        const int count = (int)std::min<int64_t>(BLOCK, b.g.height[0] - row0);
        tp_error e{};
        st = r->rows(r->user, row0, count, rows.data(), &e);
        if (st != TP_OK) {
            if (err)
                *err = e;
            if (!e.message[0])
                st = fail(err, st, "%s: level-0 rows %" PRId64 "..%" PRId64 " not made", out_path,
                          row0, row0 + count - 1);
            break;
        }
        std::vector<uint8_t>& l0 = b.level[0];
        std::fill(l0.begin(), l0.end(), 0);
        for (int y = 0; y < count; ++y)
            std::memcpy(l0.data() + (size_t)y * stride, rows.data() + (size_t)y * line, line);
        st = pyramid_row_done(b, row, out_path, o, err);
    }
    if (st == TP_OK)
        st = pyramid_commit(b, err);
    return st;
}

} // namespace

extern "C" tp_status tp_imagery_build_rows(const tp_imagery_target* target,
                                           const tp_imagery_rows* rows,
                                           const tp_imagery_build_options* options,
                                           const char* out_path, tp_error* err)
{
    if (!target || !rows || !rows->rows || !out_path)
        return fail(err, TP_ERR_INVALID_ARG,
                    "imagery: bad arguments (no target, rows callback or output)");
    if (!target_ok(target))
        return fail(err, TP_ERR_INVALID_ARG, "%s: bad render grid (%dx%d)", out_path, target->width,
                    target->height);
    if (rows->texel_shift < TP_IMAGERY_SHIFT_MIN || rows->texel_shift > TP_IMAGERY_SHIFT_MAX)
        return fail(err, TP_ERR_INVALID_ARG, "%s: texel shift %d outside %d..%d", out_path,
                    rows->texel_shift, TP_IMAGERY_SHIFT_MIN, TP_IMAGERY_SHIFT_MAX);
    const bool light = rows->kind == TP_IMAGERY_KIND_LIGHT_TIMES;
    if (const char* why = kind_problem(
            (uint32_t)rows->kind, light ? rows->time_first_s : 0, light ? rows->time_last_s : 0,
            light ? (uint32_t)std::max(0, rows->maps) : 0, rows->texel_shift))
        return fail(err, TP_ERR_INVALID_ARG, "%s: %s (kind %d, times %.17g .. %.17g, %d maps)",
                    out_path, why, rows->kind, rows->time_first_s, rows->time_last_s, rows->maps);
    tp_imagery_build_options o{};
    if (options)
        o = *options;
    try {
        return build(target, rows, &o, out_path, err);
    } catch (...) {
        return tpio::caught(err, out_path);
    }
}
