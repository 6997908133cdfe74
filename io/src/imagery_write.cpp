/* imagery_write.cpp - tp_imagery_build: georeferenced rasters warped by GDAL onto a render grid
 * and written as a mip pyramid of 256x256 RGBA blocks (.tpi; tp_imagery.h, docs/imagery.md).
 *
 * Each source becomes an RGBA view of itself (a VRT: its palette expanded, the colour bands
 * tp_texture_build would take, grey repeated three times, alpha from its alpha band or else
 * from its mask, so that nodata is transparent). Level 0 is made one block row (256 texel rows)
 * at a time: a MEM dataset over that strip of our own buffer, with the strip's exact
 * geotransform, into which GDALWarp draws every source overlapping it in turn (a later one
 * over an earlier one, blended by its alpha). Level l + 1 is made from level l as its block
 * rows come (the alpha-weighted 2x2 mean, written here: GDAL's average ignores alpha as a
 * weight), so each level keeps one block row in memory and the level-0 image is never whole.
 * Blocks are compressed by threads (imagery_codec.cpp) and appended in order; the block table
 * (its place follows from the geometry, reserved as a hole) is written a block row at a time,
 * checksummed at commit by reading it back, then the footer, then the header again with the
 * count of non-empty blocks; tp_file_commit makes the file. */
#include "atomic_write.hpp"
#include "crs.hpp"
#include "gdal_util.hpp"
#include "image_bands.hpp"
#include "imagery_format.hpp"
#include "tp_io.h"

#include <gdal_alg.h>
#include <gdal_utils.h>
#include <zstd.h>

#include <algorithm>
#include <atomic>
#include <cinttypes>
#include <cmath>
#include <condition_variable>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

using namespace tpio::imagery;
using tpio::fail;

namespace {

constexpr int ZSTD_LEVEL = 1; /* docs/imagery.md: measured */

struct Source {
    std::string path;
    tpio::Dataset ds, expanded, rgba;
    double res = 0;         /* its pixel size on the render grid (render CRS units) */
    double extent[4] = {0}; /* its bounds in the render CRS: xmin, ymin, xmax, ymax */
    std::string resampling;
    bool alpha = true; /* its RGBA view has an alpha band (else it is opaque: RGB) */
    std::string error; /* GDAL's -et: its approximate transformer's error, in source pixels */
};

/* The grid's bounds (xmin, ymin, xmax, ymax) in its CRS, for w x h pixels of gt. */
void bounds_of(const double gt[6], double w, double h, double out[4])
{
    out[0] = out[1] = INFINITY, out[2] = out[3] = -INFINITY;
    for (int k = 0; k < 4; ++k) {
        const double x = (k & 1) ? w : 0, y = (k & 2) ? h : 0;
        const double e = gt[0] + x * gt[1] + y * gt[2], n = gt[3] + x * gt[4] + y * gt[5];
        out[0] = std::min(out[0], e), out[2] = std::max(out[2], e);
        out[1] = std::min(out[1], n), out[3] = std::max(out[3], n);
    }
}

bool overlaps(const double a[4], const double b[4])
{
    return a[0] < b[2] && b[0] < a[2] && a[1] < b[3] && b[1] < a[3];
}

/* Opens a source and makes its RGBA view; measures its resolution and bounds on the grid. */
tp_status open_source(const char* path, const tp_imagery_target* t, Source* s, tp_error* err)
{
    s->path = path;
    if (tp_status st = tpio::check_input_file(path, "a raster", true, err))
        return st;
    s->ds.reset(
        GDALDataset::FromHandle(GDALOpenEx(path, GDAL_OF_RASTER, nullptr, nullptr, nullptr)));
    if (!s->ds)
        return fail(err, TP_ERR_IO, "%s: cannot open: %s", path, tpio::gdal_message().c_str());
    GDALDataset* src = s->ds.get();
    if (src->GetRasterCount() < 1)
        return fail(err, TP_ERR_BAD_DATA, "%s: has no raster bands", path);
    double gt[6];
    if (src->GetGeoTransform(gt) != CE_None)
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: has no georeference (no geotransform): cannot place it on the grid", path);
    if (t->crs_wkt[0] && !tpio::crs_present(src->GetSpatialRef()))
        return fail(err, TP_ERR_BAD_DATA, "%s: has no CRS: cannot place it on the grid", path);
    if (tp_status st = tpio::expand_palette(path, &src, &s->expanded, err))
        return st;
    /* Three colour bands (grey repeated) and alpha (its own, or its mask: nodata transparent) */
    const tpio::Bands b = tpio::choose_bands(src);
    std::vector<std::string> pick = {"-of", "VRT", "-ot", "Byte"};
    for (int c = 0; c < 3; c++)
        pick.insert(pick.end(), {"-b", std::to_string(b.colour[b.colour_count == 3 ? c : 0])});
    /* an opaque source (no alpha, every pixel valid) goes without alpha: GDAL's warp has fast
     * kernels for sources without masks, and the warp's destination alpha still marks what it
     * covers */
    s->alpha = b.alpha || !(src->GetRasterBand(b.colour[0])->GetMaskFlags() & GMF_ALL_VALID);
    if (s->alpha) {
        pick.insert(pick.end(), {"-b", b.alpha ? std::to_string(b.alpha) : std::string("mask")});
        pick.insert(pick.end(), {"-colorinterp", "red,green,blue,alpha"});
    } else {
        pick.insert(pick.end(), {"-colorinterp", "red,green,blue"});
    }
    s->rgba = tpio::translate(src, pick);
    if (!s->rgba)
        return fail(err, TP_ERR_BACKEND, "%s: cannot select the colour bands: %s", path,
                    tpio::gdal_message().c_str());
    /* Its footprint and pixel size in the render CRS, as GDAL would warp it whole. */
    char** to = nullptr;
    if (t->crs_wkt[0])
        to = CSLSetNameValue(to, "DST_SRS", t->crs_wkt);
    void* tr = GDALCreateGenImgProjTransformer2(GDALDataset::ToHandle(s->rgba.get()), nullptr, to);
    CSLDestroy(to);
    if (!tr)
        return fail(err, TP_ERR_BAD_DATA, "%s: cannot be transformed to the grid's CRS: %s", path,
                    tpio::gdal_message().c_str());
    double ogt[6];
    int px = 0, py = 0;
    const CPLErr e =
        GDALSuggestedWarpOutput2(GDALDataset::ToHandle(s->rgba.get()), GDALGenImgProjTransform, tr,
                                 ogt, &px, &py, s->extent, 0);
    GDALDestroyGenImgProjTransformer(tr);
    if (e != CE_None || px < 1 || py < 1)
        return fail(err, TP_ERR_BAD_DATA, "%s: cannot be transformed to the grid's CRS: %s", path,
                    tpio::gdal_message().c_str());
    s->res = std::fabs(ogt[1]);
    double grid[4];
    bounds_of(t->geotransform, t->width, t->height, grid);
    if (!overlaps(s->extent, grid))
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: does not overlap the grid (its bounds %.3f %.3f .. %.3f %.3f, the grid's "
                    "%.3f %.3f .. %.3f %.3f in the grid's CRS)",
                    path, s->extent[0], s->extent[1], s->extent[2], s->extent[3], grid[0], grid[1],
                    grid[2], grid[3]);
    return TP_OK;
}

/* The writer: one output file, the geometry, the level buffers. */
struct Build {
    const char* path = nullptr;
    Geometry g;
    int shift = 0;
    std::string crs, notes;
    const tp_imagery_target* target = nullptr;
    int threads = 1;
    tp_file_writer* file = nullptr;
    uint64_t table_offset = 0, data_offset = 0, offset = 0, nonempty = 0;
    std::vector<std::vector<uint8_t>> level; /* one block row per level, cols * 256 wide */
    std::vector<ZSTD_CCtx*> cctx;
    std::vector<std::vector<uint8_t>> gather, scratch, packed; /* per thread */
    std::vector<std::vector<uint8_t>> chunk_out;
    std::vector<Codec> chunk_codec;
    std::vector<uint8_t> entries;
    ~Build()
    {
        tp_file_abort(file);
        for (ZSTD_CCtx* c : cctx)
            ZSTD_freeCCtx(c);
    }
};

std::vector<uint8_t> encode_header(const Build& b)
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
    std::memcpy(p + H_FIXED_BYTES, b.crs.data(), b.crs.size());
    std::memcpy(p + H_FIXED_BYTES + b.crs.size(), b.notes.data(), b.notes.size());
    put_u32(p + size - 4, crc32_of(p, size - 4));
    return h;
}

/* Encodes and appends block row `row` of level l (b.level[l]); writes its table entries. */
tp_status write_row(Build& b, int l, int row, tp_error* err)
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

/* Texel (u, v) of dst = the alpha-weighted mean of texels 2u..2u+1, 2v..2v+1 of src (alpha 0
 * beyond src's columns or rows); alpha the plain mean. Both rounded half up. */
void halve(const uint8_t* src, int src_cols, int src_rows, uint8_t* dst, int dst_cols, int dst_rows)
{
    for (int v = 0; v < dst_rows; ++v) {
        uint8_t* d = dst + (size_t)v * dst_cols * 4;
        for (int u = 0; u < dst_cols; ++u, d += 4) {
            uint32_t sa = 0, sc[3] = {0, 0, 0};
            for (int j = 0; j < 2; ++j) {
                const int y = 2 * v + j;
                if (y >= src_rows)
                    continue;
                for (int i = 0; i < 2; ++i) {
                    const int x = 2 * u + i;
                    if (x >= src_cols)
                        continue;
                    const uint8_t* s = src + ((size_t)y * src_cols + x) * 4;
                    sa += s[3];
                    for (int c = 0; c < 3; ++c)
                        sc[c] += (uint32_t)s[c] * s[3];
                }
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
tp_status finish_row(Build& b, int l, int row, tp_error* err)
{
    if (tp_status s = write_row(b, l, row, err))
        return s;
    if (l + 1 >= b.g.levels)
        return TP_OK;
    std::vector<uint8_t>& up = b.level[l + 1];
    const int up_cols = b.g.cols[l + 1] * BLOCK;
    if (row % 2 == 0)
        std::fill(up.begin(), up.end(), 0);
    halve(b.level[l].data(), b.g.cols[l] * BLOCK, BLOCK,
          up.data() + (size_t)(row % 2) * (BLOCK / 2) * up_cols * 4, up_cols, BLOCK / 2);
    if (row % 2 == 1 || row == b.g.rows[l] - 1)
        return finish_row(b, l + 1, row / 2, err);
    return TP_OK;
}

/* Warps every source overlapping it onto level 0's block row `row`, into buf (a block row of
 * level 0); warp_threads for GDAL's kernel. */
tp_status warp_row(const Build& b, std::vector<Source>& sources, const OGRSpatialReference* srs,
                   int row, double warp_mb, int warp_threads, std::vector<uint8_t>& buf,
                   tp_error* err)
{
    std::fill(buf.begin(), buf.end(), 0);
    const int w = (int)b.g.width[0];
    const int rows = (int)std::min<int64_t>(BLOCK, b.g.height[0] - (int64_t)row * BLOCK);
    double gt[6];
    std::memcpy(gt, b.g.gt, sizeof gt);
    gt[0] += (double)row * BLOCK * gt[2];
    gt[3] += (double)row * BLOCK * gt[5];
    double strip[4];
    bounds_of(gt, w, rows, strip);
    GDALDriver* mem = GetGDALDriverManager()->GetDriverByName("MEM");
    if (!mem)
        return fail(err, TP_ERR_BACKEND, "%s: GDAL has no MEM driver", b.path);
    tpio::Dataset dst(mem->Create("", w, rows, 0, GDT_Byte, nullptr));
    if (!dst)
        return fail(err, TP_ERR_BACKEND, "%s: %s", b.path, tpio::gdal_message().c_str());
    const GDALColorInterp ci[4] = {GCI_RedBand, GCI_GreenBand, GCI_BlueBand, GCI_AlphaBand};
    const std::string line = std::to_string((size_t)b.g.cols[0] * BLOCK * 4);
    for (int c = 0; c < 4; ++c) {
        char ptr[64];
        const int len = CPLPrintPointer(ptr, buf.data() + c, sizeof ptr - 1);
        ptr[len] = 0;
        char** o = CSLSetNameValue(nullptr, "DATAPOINTER", ptr);
        o = CSLSetNameValue(o, "PIXELOFFSET", "4");
        o = CSLSetNameValue(o, "LINEOFFSET", line.c_str());
        const CPLErr e = dst->AddBand(GDT_Byte, o);
        CSLDestroy(o);
        if (e != CE_None)
            return fail(err, TP_ERR_BACKEND, "%s: %s", b.path, tpio::gdal_message().c_str());
        dst->GetRasterBand(c + 1)->SetColorInterpretation(ci[c]);
    }
    dst->SetGeoTransform(gt);
    if (srs)
        dst->SetSpatialRef(srs);
    const std::string threads = "NUM_THREADS=" + std::to_string(warp_threads);
    const std::string wm = std::to_string(std::max(16.0, warp_mb));
    for (Source& s : sources) {
        if (!overlaps(s.extent, strip))
            continue;
        const char* args[] = {"-dstalpha",
                              "-r",
                              s.resampling.c_str(),
                              "-wo",
                              threads.c_str(),
                              "-wm",
                              wm.c_str(),
                              "-et",
                              s.error.c_str(),
                              s.alpha ? "-srcalpha" : "-nosrcalpha",
                              nullptr};
        GDALWarpAppOptions* wo = GDALWarpAppOptionsNew(const_cast<char**>(args), nullptr);
        GDALDatasetH in = GDALDataset::ToHandle(s.rgba.get());
        int usage = 0;
        GDALDatasetH out = GDALWarp(nullptr, GDALDataset::ToHandle(dst.get()), 1, &in, wo, &usage);
        GDALWarpAppOptionsFree(wo);
        if (!out)
            return fail(err, TP_ERR_BACKEND, "%s: cannot warp onto the grid: %s", s.path.c_str(),
                        tpio::gdal_message().c_str());
    }
    dst.reset();
    /* transparent texels are 0, whatever the warp left in their colour */
    for (size_t k = 3; k < buf.size(); k += 4)
        if (buf[k] == 0)
            buf[k - 3] = buf[k - 2] = buf[k - 1] = 0;
    return TP_OK;
}

/* Level 0's block rows warped by `workers` threads, each with its own view of the sources (a
 * GDAL dataset is used by one thread at a time), into `slots` buffers: at most that many rows
 * ahead of the building thread, which takes them in order (take). */
struct Warps {
    const Build* b = nullptr;
    const OGRSpatialReference* srs = nullptr;
    double warp_mb = 0;
    int warp_threads = 1;
    std::vector<std::vector<Source>>* views = nullptr;
    std::vector<std::vector<uint8_t>> slot;
    std::vector<char> ready;
    int next = 0, consumed = 0;
    bool stop = false;
    tp_status status = TP_OK;
    tp_error err{};
    std::mutex m;
    std::condition_variable cv;
    std::vector<std::thread> pool;

    void work(int k)
    {
        const int slots = (int)slot.size();
        for (;;) {
            std::unique_lock<std::mutex> lock(m);
            const int row = next++;
            if (row >= b->g.rows[0])
                return;
            cv.wait(lock, [&] { return stop || row < consumed + slots; });
            if (stop)
                return;
            lock.unlock();
            tp_error e{};
            tp_status st = TP_OK;
            try {
                st = warp_row(*b, (*views)[(size_t)k], srs, row, warp_mb, warp_threads,
                              slot[(size_t)(row % slots)], &e);
            } catch (...) {
                st = tpio::caught(&e, b->path);
            }
            lock.lock();
            if (st != TP_OK && status == TP_OK)
                status = st, err = e, stop = true;
            ready[(size_t)(row % slots)] = 1;
            cv.notify_all();
        }
    }
    void start(int workers, size_t slot_bytes)
    {
        slot.assign((size_t)workers + 1, std::vector<uint8_t>(slot_bytes));
        ready.assign(slot.size(), 0);
        for (int k = 0; k < workers; ++k)
            pool.emplace_back(&Warps::work, this, k);
    }
    /* Swaps row's texels into buf (a level-0 block row); a warp's failure otherwise. */
    tp_status take(int row, std::vector<uint8_t>& buf, tp_error* out)
    {
        std::unique_lock<std::mutex> lock(m);
        const size_t k = (size_t)(row % (int)slot.size());
        cv.wait(lock, [&] { return stop || ready[k]; });
        if (status != TP_OK) {
            *out = err;
            return status;
        }
        buf.swap(slot[k]);
        ready[k] = 0;
        consumed = row + 1;
        cv.notify_all();
        return TP_OK;
    }
    ~Warps()
    {
        {
            std::lock_guard<std::mutex> lock(m);
            stop = true;
        }
        cv.notify_all();
        for (std::thread& t : pool)
            t.join();
    }
};

tp_status build(const char* const* paths, int count, const tp_imagery_target* t,
                const tp_imagery_build_options* o, const char* out_path, tp_error* err)
{
    tpio::register_drivers();
    tpio::QuietGdal quiet;
    const double budget = o->memory_bytes > 0 ? o->memory_bytes : 1024.0 * 1024 * 1024;
    int threads = o->threads;
    if (threads <= 0)
        threads = (int)std::max(1u, std::min(64u, std::thread::hardware_concurrency()));
    std::vector<Source> sources((size_t)count);
    for (int i = 0; i < count; ++i)
        if (tp_status s = open_source(paths[i], t, &sources[(size_t)i], err))
            return s;

    /* The texel size: given, or the finest source's on the grid (nearest power of two) */
    const double grid_px = std::sqrt(std::fabs(t->geotransform[1] * t->geotransform[5] -
                                               t->geotransform[2] * t->geotransform[4]));
    int shift = o->texel_shift;
    const bool automatic = shift == TP_IMAGERY_SHIFT_AUTO;
    if (automatic) {
        double finest = INFINITY;
        for (const Source& s : sources)
            finest = std::min(finest, s.res);
        shift = (int)std::lround(std::log2(grid_px / finest));
        shift = std::max(TP_IMAGERY_SHIFT_MIN, std::min(TP_IMAGERY_SHIFT_MAX, shift));
    }
    Build b;
    b.path = out_path;
    b.target = t;
    b.shift = shift;
    b.threads = threads;
    if (shift < TP_IMAGERY_SHIFT_MIN || shift > TP_IMAGERY_SHIFT_MAX)
        return fail(err, TP_ERR_INVALID_ARG, "%s: texel shift %d outside %d..%d", out_path, shift,
                    TP_IMAGERY_SHIFT_MIN, TP_IMAGERY_SHIFT_MAX);
    if (!geometry_for(t->width, t->height, t->geotransform, shift, &b.g))
        return fail(err, TP_ERR_INVALID_ARG,
                    "%s: a %dx%d grid at texel shift %d makes a level 0 over 2^31 texels a side",
                    out_path, t->width, t->height, shift);
    const double texel = grid_px * std::ldexp(1.0, -shift);
    for (Source& s : sources) {
        /* averaging where a source is finer than the texels */
        s.resampling = texel >= 2 * s.res ? "average" : "bilinear";
        /* GDAL's approximate transformer errs by up to -et source pixels (0.125 by default):
         * an eighth of a texel, also where source pixels span many texels */
        s.error = std::to_string(0.125 * std::min(1.0, texel / s.res));
    }

    /* Memory: a block row of every level, the threads' scratch, GDAL's cache and warp memory */
    double rows_bytes = 0;
    for (int l = 0; l < b.g.levels; ++l)
        rows_bytes += (double)b.g.cols[l] * BLOCK * BLOCK * 4;
    const double thread_bytes =
        (double)threads *
            (2.0 * BLOCK_BYTES + ZSTD_compressBound(BLOCK_BYTES) + 4 * max_block_bytes()) +
        threads * 1.5e6 /* zstd contexts */;
    /* Level-0 warps in parallel, each into its own block row (and one more waiting), each with
     * GDAL's working memory (-wm): a twentieth of the budget whatever the threads, so that the
     * warps' chunks, and so the bytes, do not depend on them; as many warps as fit. */
    const double warp_mb = std::max(16.0, std::min(128.0, budget * 0.05 / 1048576.0));
    const double slot_bytes = (double)b.g.cols[0] * BLOCK * BLOCK * 4;
    const double per_warp = slot_bytes + warp_mb * 1048576.0;
    const double need = rows_bytes + thread_bytes + slot_bytes + per_warp;
    if (need > 0.6 * budget)
        return fail(err, TP_ERR_OUT_OF_MEMORY,
                    "%s: a %" PRId64 "x%" PRId64
                    " level 0 needs %.0f MB for one block row of every level, a warp and %d "
                    "threads' buffers, over 60%% of the memory budget (%.0f MB): give %.0f MB or "
                    "more",
                    out_path, b.g.width[0], b.g.height[0], need / 1048576.0, threads,
                    budget / 1048576.0, std::ceil(need / 0.6 / 1048576.0));
    const int fit = 1 + (int)((0.6 * budget - need) / per_warp);
    const int workers = std::max(1, std::min(std::min(threads, fit), b.g.rows[0]));
    GDALSetCacheMax64((GIntBig)(budget * 0.2));

    /* Notes: the sources and the decisions */
    char line[512];
    std::snprintf(line, sizeof line,
                  "level 0: %" PRId64 "x%" PRId64 " texels of %.6g m (texel shift %d, %s), %d "
                  "levels, %" PRIu64 " blocks of %dx%d",
                  b.g.width[0], b.g.height[0], texel, shift,
                  automatic ? "from the finest source" : "given", b.g.levels, b.g.block_count,
                  BLOCK, BLOCK);
    b.notes = line;
    for (const Source& s : sources) {
        std::snprintf(line, sizeof line, "\nsource: %s (%dx%d, %.6g m per pixel on the grid, %s)",
                      s.path.c_str(), s.ds->GetRasterXSize(), s.ds->GetRasterYSize(), s.res,
                      s.resampling.c_str());
        b.notes += line;
    }
    if (count > 1)
        b.notes += "\nmosaic: later sources drawn over earlier ones (blended by their alpha)";
    b.crs = t->crs_wkt;
    if (b.crs.size() > MAX_STRING_BYTES || b.notes.size() > MAX_STRING_BYTES)
        return fail(err, TP_ERR_INVALID_ARG, "%s: CRS or notes over 16 MiB", out_path);
    OGRSpatialReference srs;
    const bool has_srs = t->crs_wkt[0] != 0;
    if (has_srs && srs.SetFromUserInput(t->crs_wkt) != OGRERR_NONE)
        return fail(err, TP_ERR_INVALID_ARG, "%s: the grid's CRS cannot be read", out_path);

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
    tp_status st = tp_file_begin(out_path, &b.file, err);
    if (st == TP_OK)
        st = tp_file_append(b.file, head.data(), head.size(), err);
    if (st == TP_OK)
        st = tpio::file_reserve(b.file, b.data_offset - head.size(), err);
    b.offset = b.data_offset;
    /* each warping thread's own view of the sources: the first the ones opened above */
    std::vector<std::vector<Source>> views((size_t)workers);
    views[0] = std::move(sources);
    for (int k = 1; k < workers && st == TP_OK; ++k) {
        views[(size_t)k].resize((size_t)count);
        for (int i = 0; i < count && st == TP_OK; ++i) {
            Source& v = views[(size_t)k][(size_t)i];
            st = open_source(paths[i], t, &v, err);
            v.resampling = views[0][(size_t)i].resampling;
            v.error = views[0][(size_t)i].error;
        }
    }
    Warps warps;
    warps.b = &b;
    warps.srs = has_srs ? &srs : nullptr;
    warps.warp_mb = warp_mb;
    warps.warp_threads = std::max(1, threads / workers);
    warps.views = &views;
    if (st == TP_OK)
        warps.start(workers, (size_t)slot_bytes);
    for (int row = 0; row < b.g.rows[0] && st == TP_OK; ++row) {
        st = warps.take(row, b.level[0], err);
        if (st == TP_OK)
            st = finish_row(b, 0, row, err);
        if (st == TP_OK && tp_interrupted())
            st = fail(err, TP_ERR_IO, "%s: interrupted (%s): not written", out_path,
                      tpio::interrupt_name());
        if (st == TP_OK && o->progress)
            o->progress(o->progress_user, (row + 1.0) / b.g.rows[0]);
    }
    /* The table's CRC32, read back in pieces; the footer; the header with the count */
    uint32_t crc = 0;
    const uint64_t table_bytes = b.g.block_count * ENTRY_BYTES;
    std::vector<uint8_t> piece((size_t)std::min<uint64_t>(table_bytes, 1 << 16) + 1);
    for (uint64_t done = 0; st == TP_OK && done < table_bytes;) {
        const size_t n = (size_t)std::min<uint64_t>(table_bytes - done, piece.size());
        st = tpio::file_read_back(b.file, b.table_offset + done, piece.data(), n, err);
        crc = tpio::store::crc32_continue(crc, piece.data(), n);
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

} // namespace

extern "C" tp_status tp_imagery_build(const char* const* sources, int count,
                                      const tp_imagery_target* target,
                                      const tp_imagery_build_options* options, const char* out_path,
                                      tp_error* err)
{
    if (!sources || count < 1 || !target || !out_path)
        return fail(err, TP_ERR_INVALID_ARG,
                    "imagery: bad arguments (no sources, target or output)");
    for (int i = 0; i < count; ++i)
        if (!sources[i])
            return fail(err, TP_ERR_INVALID_ARG, "imagery: bad arguments (source %d is NULL)", i);
    if (target->width < 1 || target->height < 1 || !target->crs_wkt ||
        !std::isfinite(target->geotransform[1]) || !std::isfinite(target->geotransform[5]) ||
        target->geotransform[1] * target->geotransform[5] -
                target->geotransform[2] * target->geotransform[4] ==
            0)
        return fail(err, TP_ERR_INVALID_ARG, "%s: bad render grid (%dx%d)", out_path, target->width,
                    target->height);
    tp_imagery_build_options o{};
    o.texel_shift = TP_IMAGERY_SHIFT_AUTO;
    if (options)
        o = *options;
    if (o.texel_shift != TP_IMAGERY_SHIFT_AUTO &&
        (o.texel_shift < TP_IMAGERY_SHIFT_MIN || o.texel_shift > TP_IMAGERY_SHIFT_MAX))
        return fail(err, TP_ERR_INVALID_ARG, "%s: texel shift %d outside %d..%d", out_path,
                    o.texel_shift, TP_IMAGERY_SHIFT_MIN, TP_IMAGERY_SHIFT_MAX);
    try {
        return build(sources, count, target, &o, out_path, err);
    } catch (...) {
        return tpio::caught(err, out_path);
    }
}
