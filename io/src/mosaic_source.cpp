/*
 * mosaic_source.cpp - the sources of a tp_mosaic (mosaic.cpp opens it): each opened and checked
 * as tp_dem_read checks a DEM, the overlaps, gaps and coverage of their footprints, and the
 * bound of the heights their files give without reading the grid.
 */
#include "crs.hpp"
#include "dem_check.hpp"
#include "gdal_util.hpp"
#include "mosaic.hpp"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

using tpio::fail;

namespace tpio {
namespace mosaic {

tp_status open_source(const char* path, const char* z_unit, Source* s, tp_error* err)
{
    if (const tp_status st = tpio::check_input_file(path, "a raster", true, err))
        return st;
    tpio::Dataset ds(GDALDataset::Open(path, GDAL_OF_RASTER | GDAL_OF_READONLY, nullptr, nullptr,
                                       nullptr));
    if (!ds)
        return fail(err, TP_ERR_BAD_DATA, "%s: not a raster GDAL can open (%s)", path,
                    tpio::gdal_message().c_str());
    if (ds->GetRasterCount() < 1)
        return fail(err, TP_ERR_BAD_DATA, "%s: expected at least 1 raster band, got 0", path);
    s->path = path;
    s->name = base_name(path);
    s->w = ds->GetRasterXSize();
    s->h = ds->GetRasterYSize();
    if (s->w < 1 || s->h < 1)
        return fail(err, TP_ERR_BAD_DATA, "%s: expected a raster of at least 1x1, got %dx%d", path,
                    s->w, s->h);
    if (const tp_status st = tpio::z_unit_of(ds.get(), z_unit, &s->z, err))
        return st;
    s->has_gt = ds->GetGeoTransform(s->gt) == CE_None;
    const OGRSpatialReference* srs = ds->GetSpatialRef();
    s->has_crs = tpio::crs_present(srs);
    if (s->has_crs) {
        s->srs = *srs;
        s->srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    }
    if (s->has_gt) {
        if (const tp_status st = tpio::check_geotransform(path, s->gt, err))
            return st;
        if (const tp_status st = tpio::check_ranges(path, s->has_crs ? &s->srs : nullptr, s->gt,
                                                    s->w, s->h, err))
            return st;
        if (s->has_crs)
            if (const tp_status st = tpio::check_latitude(path, s->srs, s->gt, s->h, err))
                return st;
    } else {
        const double unit[6] = {0.0, 1.0, 0.0, 0.0, 0.0, -1.0};
        std::memcpy(s->gt, unit, sizeof unit);
    }
    s->driver = ds->GetDriver() ? ds->GetDriver()->GetDescription() : "";
    if (EQUAL(s->driver.c_str(), "AAIGrid"))
        if (const tp_status st = tpio::check_ascii_grid(path, s->w, s->h, err))
            return st;
    GDALRasterBand* b = ds->GetRasterBand(1);
    s->type = b->GetRasterDataType();
    int has = 0;
    s->nodata = b->GetNoDataValue(&has);
    s->has_nodata = has != 0;
    const char* mn = b->GetMetadataItem("STATISTICS_MINIMUM");
    const char* mx = b->GetMetadataItem("STATISTICS_MAXIMUM");
    const char* approx = b->GetMetadataItem("STATISTICS_APPROXIMATE");
    if (mn && mx && !(approx && EQUAL(approx, "YES"))) {
        s->has_stats = true;
        s->stat_min = CPLAtof(mn);
        s->stat_max = CPLAtof(mx);
        /* statistics of an untagged Int16 band that count its voids bound nothing */
        if (s->int16_voids() && s->stat_min <= -32767.0)
            s->has_stats = false;
    }
    return TP_OK;
}

double covered_share(const std::vector<Rect>& r, const Rect& whole)
{
    const int n = 1024;
    const double cw = (whole.x1 - whole.x0) / n, ch = (whole.y1 - whole.y0) / n;
    if (!(cw > 0 && ch > 0))
        return 1.0;
    std::vector<uint8_t> hit((size_t)n * n, 0);
    size_t covered = 0;
    for (const Rect& q : r) {
        /* the cells whose centre x0 + (i + 0.5) cw lies in [q.x0, q.x1) */
        const int i0 = std::max(0, (int)std::ceil((q.x0 - whole.x0) / cw - 0.5));
        const int i1 = std::min(n, (int)std::ceil((q.x1 - whole.x0) / cw - 0.5));
        const int j0 = std::max(0, (int)std::ceil((q.y0 - whole.y0) / ch - 0.5));
        const int j1 = std::min(n, (int)std::ceil((q.y1 - whole.y0) / ch - 0.5));
        for (int j = j0; j < j1; j++)
            for (int i = i0; i < i1; i++) {
                uint8_t& c = hit[(size_t)j * n + i];
                covered += !c;
                c = 1;
            }
    }
    return (double)covered / ((double)n * n);
}

double note_overlaps(const std::vector<Source>& src, const double mgt[6], int mw, int mh,
                     std::string& notes)
{
    std::vector<Rect> r; /* in mosaic samples */
    for (const Source& s : src) {
        const double x0 = (double)std::llround((s.gt[0] - mgt[0]) / mgt[1]);
        const double y0 = (double)std::llround((s.gt[3] - mgt[3]) / mgt[5]);
        r.push_back({x0, y0, x0 + s.w, y0 + s.h});
    }
    int said = 0;
    for (size_t i = 0; i < r.size(); i++)
        for (size_t j = i + 1; j < r.size(); j++) {
            const long long ox =
                std::llround(std::min(r[i].x1, r[j].x1) - std::max(r[i].x0, r[j].x0));
            const long long oy =
                std::llround(std::min(r[i].y1, r[j].y1) - std::max(r[i].y0, r[j].y0));
            if (ox <= 0 || oy <= 0)
                continue;
            if (said++ >= 20)
                continue;
            const bool srtm = src[i].driver == "SRTMHGT" && src[j].driver == "SRTMHGT";
            std::string by;
            if (oy == 1 && ox > 1)
                by = "one row";
            else if (ox == 1 && oy > 1)
                by = "one column";
            else
                by = CPLSPrintf("%lld x %lld samples", ox, oy);
            add_note(notes, CPLSPrintf("%s and %s overlap by %s%s; GDAL's VRT takes the later one "
                                       "(%s)",
                                       src[i].name.c_str(), src[j].name.c_str(), by.c_str(),
                                       srtm && (oy == 1 || ox == 1)
                                           ? " (SRTM tiles share their edge)"
                                           : "",
                                       src[j].name.c_str()));
        }
    if (said > 20)
        add_note(notes, CPLSPrintf("... and %d more overlaps", said - 20));
    const double share = covered_share(r, Rect{0, 0, (double)mw, (double)mh});
    const long long all = (long long)mw * mh;
    const long long gaps = all - std::llround(share * (double)all);
    if (src.size() > 1 && gaps > 0)
        add_note(notes, CPLSPrintf("gaps between the sources: about %lld of the mosaic's %dx%d "
                                   "samples are covered by none and are nodata",
                                   gaps, mw, mh));
    return share;
}

void range_of_files(tp_mosaic* m)
{
    char** list = m->ds->GetFileList();
    const std::string self = m->ds->GetDescription();
    const double grid = (double)m->w * m->h;
    double total = 0, lo = INFINITY, hi = -INFINITY;
    bool ok = list != nullptr;
    std::vector<tpio::Dataset> files;
    for (char** f = list; ok && f && *f; ++f) {
        if (self == *f || !GDALIdentifyDriver(*f, nullptr))
            continue; /* the VRT itself, sidecars (.hdr, .prj, .aux.xml) */
        tpio::Dataset d(GDALDataset::Open(*f, GDAL_OF_RASTER | GDAL_OF_READONLY));
        if (!d || d->GetRasterCount() < 1) {
            ok = false;
            break;
        }
        total += (double)d->GetRasterXSize() * d->GetRasterYSize() * d->GetRasterCount();
        ok = total <= grid / 2;
        files.push_back(std::move(d));
    }
    CSLDestroy(list);
    ok = ok && !files.empty();
    for (auto& d : files) {
        for (int b = 1; ok && b <= d->GetRasterCount(); b++) {
            double mm[2];
            CPLErrorReset();
            if (GDALComputeRasterMinMax(GDALRasterBand::ToHandle(d->GetRasterBand(b)), FALSE,
                                        mm) != CE_None ||
                CPLGetLastErrorType() == CE_Failure || !std::isfinite(mm[0]) ||
                !std::isfinite(mm[1]))
                ok = false;
            lo = std::min(lo, mm[0]), hi = std::max(hi, mm[1]);
        }
        if (!ok)
            break;
    }
    if (!ok)
        return;
    for (double v : {lo, hi})
        if ((m->has_nodata && (float)v == m->nodata) ||
            (m->int16_voids && (v == -32768.0 || v == -32767.0)) || std::fabs(v) >= FLT_MAX)
            return;
    m->has_range = true;
    m->min_m = lo;
    m->max_m = hi;
}

} // namespace mosaic
} // namespace tpio
