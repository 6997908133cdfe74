/* imagery_build.cpp - tp_imagery_build: georeferenced rasters warped by GDAL onto a render grid
 * and written as a mip pyramid of 256x256 RGBA blocks (.tpi; tp_imagery.h, docs/imagery.md).
 *
 * Each source becomes an RGBA view of itself (a VRT: its palette expanded, the colour bands
 * tp_texture_build would take, grey repeated three times, alpha from its alpha band or else
 * from its mask, so that nodata is transparent). Level 0 is made one block row (256 texel rows)
 * at a time: a MEM dataset over that strip of our own buffer, with the strip's exact
 * geotransform, into which GDALWarp draws every source overlapping it in turn (a later one
 * over an earlier one, blended by its alpha). Level l + 1 is made from level l as its block
 * rows come (the alpha-weighted 2x2 mean, written here: GDAL's average ignores alpha as a
 * weight), so each level keeps one block row in memory and the level-0 image is never whole;
 * imagery_pyramid.cpp makes the coarser levels and writes the file. */
#include "crs.hpp"
#include "gdal_util.hpp"
#include "image_bands.hpp"
#include "imagery_pyramid.hpp"
#include "tp_io.h"

#include <gdal_alg.h>
#include <gdal_utils.h>

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

/* Warps every source overlapping it onto level 0's block row `row`, into buf (a block row of
 * level 0); warp_threads for GDAL's kernel. */
tp_status warp_row(const Pyramid& b, std::vector<Source>& sources, const OGRSpatialReference* srs,
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
    const Pyramid* b = nullptr;
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
    Pyramid b;
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
    const double pyramid = pyramid_bytes(b.g, threads);
    /* Level-0 warps in parallel, each into its own block row (and one more waiting), each with
     * GDAL's working memory (-wm): a twentieth of the budget whatever the threads, so that the
     * warps' chunks, and so the bytes, do not depend on them; as many warps as fit. */
    const double warp_mb = std::max(16.0, std::min(128.0, budget * 0.05 / 1048576.0));
    const double slot_bytes = (double)b.g.cols[0] * BLOCK * BLOCK * 4;
    const double per_warp = slot_bytes + warp_mb * 1048576.0;
    const double need = pyramid + slot_bytes + per_warp;
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

    tp_status st = pyramid_begin(b, err);
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
            st = pyramid_row_done(b, row, out_path, o, err);
    }
    if (st == TP_OK)
        st = pyramid_commit(b, err);
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
    if (!target_ok(target))
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
