/*
 * void_fill.cpp - interior voids filled by interpolation or from a second source (the
 * delta-surface fill); see void_fill.hpp and tp_io.h ("Voids").
 *
 * Each void is filled on its own crop: its bounding box grown by its reach (the box's longer side
 * + 1) on every side. GDALFillNodata then finds, for every sample of the void, the ground on each
 * side of it, whatever the void's size, and a window of rows that holds the crop gives the same
 * heights as the whole grid (mosaic.cpp relies on that).
 */
#include "void_fill.hpp"

#include "crs.hpp"
#include "int16_voids.hpp"
#include "io_util.hpp"

#include <gdal_alg.h>
#include <gdal_utils.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>

using tpio::fail;

namespace {

struct Region {
    int x0, y0, x1, y1; /* bounding box, inclusive */
    size_t count;
    bool border, cut;
};

/* GDALFillNodata over a copy of a crop (cw x ch, NaN = to fill), search distance reach: the
 * crop with its NaNs interpolated where GDAL reached them. */
tp_status interpolate(std::vector<float>& c, int cw, int ch, const double gt[6], int reach,
                      tp_error* err)
{
    tpio::Dataset ds = tpio::mem_dataset(c.data(), cw, ch, gt, nullptr);
    if (!ds)
        return fail(err, TP_ERR_BACKEND, "void filling: %s", tpio::gdal_message().c_str());
    GDALRasterBand* band = ds->GetRasterBand(1);
    /* GDAL's work rasters in memory, not as GeoTIFFs created and deleted in the working
     * directory for every void (two files a crop: 30% of a tile's build went there, and a
     * read-only working directory failed the fill); the same values either way */
    char mem[] = "TEMP_FILE_DRIVER=MEM";
    char* options[] = {mem, nullptr};
    if (GDALFillNodata(GDALRasterBand::ToHandle(band), nullptr, reach, 0, 0, options, nullptr,
                       nullptr) != CE_None ||
        band->RasterIO(GF_Read, 0, 0, cw, ch, c.data(), cw, ch, GDT_Float32, 0, 0, nullptr) !=
            CE_None)
        return fail(err, TP_ERR_BACKEND, "void filling: %s", tpio::gdal_message().c_str());
    return TP_OK;
}

} // namespace

tp_status tpio::fill_voids(float* z, int w, int h, const double gt[6], const FillSpec& spec,
                           bool top_is_border, bool bottom_is_border, std::vector<uint8_t>& filled,
                           VoidCounts* counts, tp_error* err)
{
    const size_t n = (size_t)w * h;
    filled.assign(n, 0);
    std::vector<int> region(n, -1);
    std::vector<Region> regions;
    std::vector<size_t> stack;
    for (size_t start = 0; start < n; start++) {
        if (!std::isnan(z[start]) || region[start] >= 0)
            continue;
        const int id = (int)regions.size();
        Region r = {w, h, -1, -1, 0, false, false};
        stack.assign(1, start);
        region[start] = id;
        while (!stack.empty()) {
            const size_t i = stack.back();
            stack.pop_back();
            r.count++;
            const int x = (int)(i % w), y = (int)(i / w);
            r.x0 = std::min(r.x0, x), r.x1 = std::max(r.x1, x);
            r.y0 = std::min(r.y0, y), r.y1 = std::max(r.y1, y);
            r.border |= x == 0 || x == w - 1 || (y == 0 && top_is_border) ||
                        (y == h - 1 && bottom_is_border);
            r.cut |= (y == 0 && !top_is_border) || (y == h - 1 && !bottom_is_border);
            const int nx[4] = {x - 1, x + 1, x, x}, ny[4] = {y, y, y - 1, y + 1};
            for (int k = 0; k < 4; k++) {
                if (nx[k] < 0 || ny[k] < 0 || nx[k] >= w || ny[k] >= h)
                    continue;
                const size_t j = (size_t)ny[k] * w + nx[k];
                if (region[j] < 0 && std::isnan(z[j])) {
                    region[j] = id;
                    stack.push_back(j);
                }
            }
        }
        regions.push_back(r);
    }

    std::vector<float> c, o, d; /* a crop of z, of other, of the delta */
    for (size_t id = 0; id < regions.size(); id++) {
        const Region& r = regions[id];
        const int bw = r.x1 - r.x0 + 1, bh = r.y1 - r.y0 + 1;
        /* a cut region reaches beyond the window: it is counted where a window holds it */
        if (r.cut || r.y1 < spec.rows_y0 || r.y0 >= spec.rows_y1)
            continue;
        if (r.border) {
            counts->outside += r.count;
            continue;
        }
        if (spec.fill_max <= 0 || bw > spec.fill_max || bh > spec.fill_max ||
            fill_crop_rows(bw, bh) > spec.max_rows) {
            counts->large += r.count;
            continue;
        }
        const int reach = fill_reach(bw, bh);
        const int cx0 = std::max(0, r.x0 - reach), cx1 = std::min(w - 1, r.x1 + reach);
        const int cy0 = std::max(0, r.y0 - reach), cy1 = std::min(h - 1, r.y1 + reach);
        const int cw = cx1 - cx0 + 1, ch = cy1 - cy0 + 1;
        double cgt[6];
        std::memcpy(cgt, gt, sizeof cgt);
        cgt[0] += cx0 * gt[1] + cy0 * gt[2];
        cgt[3] += cx0 * gt[4] + cy0 * gt[5];
        auto at = [&](int cx, int cy) { return (size_t)(cy0 + cy) * w + (cx0 + cx); };
        bool need_interp = spec.other == nullptr;
        if (spec.other) {
            /* delta = z - other where both have data; across the void it is interpolated */
            o.resize((size_t)cw * ch), d.resize((size_t)cw * ch);
            for (int cy = 0; cy < ch; cy++)
                for (int cx = 0; cx < cw; cx++) {
                    const size_t i = at(cx, cy), k = (size_t)cy * cw + cx;
                    o[k] = spec.other[i];
                    d[k] = z[i] - spec.other[i]; /* NaN where either is */
                    if (region[i] == (int)id && std::isnan(o[k]))
                        need_interp = true;
                }
            if (const tp_status st = interpolate(d, cw, ch, cgt, reach, err))
                return st;
        }
        if (need_interp) {
            c.resize((size_t)cw * ch);
            for (int cy = 0; cy < ch; cy++)
                for (int cx = 0; cx < cw; cx++)
                    c[(size_t)cy * cw + cx] = z[at(cx, cy)];
            if (const tp_status st = interpolate(c, cw, ch, cgt, reach, err))
                return st;
        }
        for (int y = r.y0; y <= r.y1; y++)
            for (int x = r.x0; x <= r.x1; x++) {
                const size_t i = (size_t)y * w + x;
                if (region[i] != (int)id)
                    continue;
                const size_t k = (size_t)(y - cy0) * cw + (x - cx0);
                float v = NAN;
                if (spec.other && !std::isnan(o[k]) && !std::isnan(d[k])) {
                    v = o[k] + d[k];
                    counts->from_other++;
                } else if (need_interp) {
                    v = c[k];
                }
                if (std::isnan(v))
                    continue; /* out of GDAL's reach: cannot happen with fill_reach */
                z[i] = v;
                filled[i] = 1;
                counts->filled++;
            }
    }
    return TP_OK;
}

tp_status tpio::fill_source_open(const char* path, const double gt[6], int w, int h,
                                 const std::string& crs_wkt, const char* format,
                                 const std::string& vrt_name, Dataset* out, ZUnit* unit,
                                 tp_error* err)
{
    if (const tp_status st = tpio::check_input_file(path, "a raster", true, err)) {
        const std::string why = err ? err->message : path;
        return fail(err, st, "--fill-from %s", why.c_str());
    }
    tpio::Dataset in(GDALDataset::Open(path, GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr,
                                       nullptr));
    if (!in || in->GetRasterCount() < 1)
        return fail(err, TP_ERR_BAD_DATA, "--fill-from %s: not a raster GDAL can open (%s)", path,
                    tpio::gdal_message().c_str());
    /* the unit of its heights, found as a DEM's is (--z-unit is the DEM's, not this file's) */
    ZUnit zu;
    if (const tp_status st = tpio::z_unit_of(in.get(), nullptr, &zu, err))
        return st;
    if (!zu.warning.empty()) {
        const size_t hint = zu.warning.find("; --z-unit");
        zu.warning = std::string("--fill-from ") + path + ": " + zu.warning.substr(0, hint);
    }
    double sgt[6];
    if (in->GetGeoTransform(sgt) != CE_None)
        return fail(err, TP_ERR_BAD_DATA,
                    "--fill-from %s: no georeference: cannot tell where it lies on the DEM", path);
    const OGRSpatialReference* ssrs = in->GetSpatialRef();
    const bool grid_crs = !crs_wkt.empty();
    if (grid_crs && !tpio::crs_present(ssrs))
        return fail(err, TP_ERR_BAD_DATA,
                    "--fill-from %s: no CRS: cannot warp it onto the DEM's grid", path);

    /* overlap: the source's extent in the grid's CRS against the grid's */
    const int sw = in->GetRasterXSize(), sh = in->GetRasterYSize();
    double sx0 = std::min(sgt[0], sgt[0] + sw * sgt[1]), sx1 = std::max(sgt[0], sgt[0] + sw * sgt[1]);
    double sy0 = std::min(sgt[3], sgt[3] + sh * sgt[5]), sy1 = std::max(sgt[3], sgt[3] + sh * sgt[5]);
    double ex0 = sx0, ey0 = sy0, ex1 = sx1, ey1 = sy1;
    if (grid_crs) {
        OGRSpatialReference s = *ssrs, d;
        s.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        d.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        if (d.importFromWkt(crs_wkt.c_str()) != OGRERR_NONE)
            return fail(err, TP_ERR_BACKEND, "--fill-from %s: the grid's CRS: %s", path,
                        tpio::gdal_message().c_str());
        std::unique_ptr<OGRCoordinateTransformation> ct(OGRCreateCoordinateTransformation(&s, &d));
        if (!ct || !ct->TransformBounds(sx0, sy0, sx1, sy1, &ex0, &ey0, &ex1, &ey1, 21))
            return fail(err, TP_ERR_BAD_DATA,
                        "--fill-from %s: its extent has no place in the DEM's CRS (%s)", path,
                        tpio::gdal_message().c_str());
    }
    const double gx0 = gt[0], gx1 = gt[0] + w * gt[1];
    const double gy0 = gt[3] + h * gt[5], gy1 = gt[3];
    if (!(ex1 > gx0 && ex0 < gx1 && ey1 > gy0 && ey0 < gy1))
        return fail(err, TP_ERR_BAD_DATA,
                    "--fill-from %s: it does not overlap the DEM (its extent x %.10g .. %.10g, "
                    "y %.10g .. %.10g in the DEM's CRS; the DEM's x %.10g .. %.10g, y %.10g .. "
                    "%.10g)",
                    path, ex0, ex1, ey0, ey1, gx0, gx1, gy0, gy1);

    std::vector<std::string> a = {"-te", CPLSPrintf("%.17g", gx0), CPLSPrintf("%.17g", gy0),
                                  CPLSPrintf("%.17g", gx1), CPLSPrintf("%.17g", gy1),
                                  "-ts", std::to_string(w), std::to_string(h),
                                  "-r", "bilinear", "-et", "0", "-dstnodata", "nan",
                                  "-ot", "Float32", "-of", format};
    if (grid_crs)
        a.insert(a.begin(), {"-t_srs", crs_wkt});
    const bool vrt = EQUAL(format, "VRT");
    GDALRasterBand* b = in->GetRasterBand(1);
    int has_nd = 0;
    b->GetNoDataValue(&has_nd);
    std::string voids_name; /* an untagged Int16 source read with -32767 as -32768 */
    if (!has_nd && b->GetRasterDataType() == GDT_Int16) {
        static std::atomic<unsigned> serial{0};
        voids_name = vrt ? fill_source_int16_name(vrt_name)
                         : CPLSPrintf("/vsimem/terrapatch_fill_int16_%u_%p.vrt", serial++,
                                      (void*)out);
        std::unique_ptr<OGRSpatialReference> srs(tpio::crs_present(ssrs) ? ssrs->Clone()
                                                                          : nullptr);
        in = tpio::int16_voids_vrt(path, sw, sh, sgt, true, srs.get(), voids_name);
        if (!in)
            return fail(err, TP_ERR_BACKEND, "--fill-from %s: %s", path,
                        tpio::gdal_message().c_str());
        a.insert(a.end(), {"-srcnodata", "-32768"});
    }
    /* the MEM warp's own copy outlives its source: unlinked on return */
    struct Unlink {
        std::string name;
        ~Unlink()
        {
            if (!name.empty())
                VSIUnlink(name.c_str());
        }
    } unlink_voids{vrt ? std::string() : voids_name};
    std::vector<char*> v;
    for (auto& s : a)
        v.push_back(const_cast<char*>(s.c_str()));
    v.push_back(nullptr);
    GDALWarpAppOptions* wo = GDALWarpAppOptionsNew(v.data(), nullptr);
    if (!wo)
        return fail(err, TP_ERR_BACKEND, "--fill-from %s: %s", path, tpio::gdal_message().c_str());
    GDALDatasetH src = GDALDataset::ToHandle(in.get());
    int usage = 0;
    GDALDatasetH hd = GDALWarp(vrt ? vrt_name.c_str() : "", nullptr, 1, &src, wo, &usage);
    GDALWarpAppOptionsFree(wo);
    if (!hd)
        return fail(err, TP_ERR_BACKEND, "--fill-from %s: warp onto the DEM's grid failed: %s",
                    path, tpio::gdal_message().c_str());
    if (vrt) { /* written on close, reopened by name (it refers to path by name) */
        GDALClose(hd);
        out->reset(GDALDataset::Open(vrt_name.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
        if (!*out)
            return fail(err, TP_ERR_BACKEND, "--fill-from %s: %s", path,
                        tpio::gdal_message().c_str());
    } else {
        out->reset(GDALDataset::FromHandle(hd));
    }
    if (unit)
        *unit = zu;
    return TP_OK;
}

void tpio::fill_source_to_metres(float* z, size_t n, const ZUnit& unit)
{
    if (unit.to_m != 1.0)
        for (size_t i = 0; i < n; i++)
            z[i] = (float)(z[i] * unit.to_m); /* NaN stays NaN */
}

std::string tpio::fill_source_unit_note(const ZUnit& unit)
{
    if (unit.to_m == 1.0 || unit.name.empty())
        return "";
    return "heights in " + unit.name + " (" + unit.from + "), converted to metres";
}

std::string tpio::fill_source_int16_name(const std::string& vrt_name)
{
    return vrt_name + ".int16.vrt";
}
