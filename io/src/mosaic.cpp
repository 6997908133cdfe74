/*
 * mosaic.cpp - tp_mosaic: many sources as one render grid, opened and planned (the sources
 * are opened in mosaic_source.cpp, the rows read in mosaic_read.cpp).
 *
 * GDAL does the mosaicking (GDALBuildVRT) and the warping (GDALWarp to a VRT, read block by
 * block on demand); the grid is planned by render_grid.hpp's functions, the same as for one
 * DEM in memory, so a single source gives tp_render_grid_build's grid and heights. The VRTs
 * live in /vsimem/ under names private to the mosaic, removed on close.
 */
#include "crs.hpp"
#include "gdal_util.hpp"
#include "int16_voids.hpp"
#include "mosaic.hpp"
#include "render_grid.hpp"
#include "void_fill.hpp"
#include "tp_io.h"

#include <gdal_utils.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <cfloat>
#include <climits>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

using namespace tpio::mosaic;
using tpio::fail;

namespace {

/* GDAL's argument vectors from strings. */
struct Args {
    std::vector<std::string> s;
    std::vector<char*> v;
    char** get()
    {
        v.clear();
        for (auto& a : s)
            v.push_back(const_cast<char*>(a.c_str()));
        v.push_back(nullptr);
        return v.data();
    }
};

bool same_spacing(double a, double b)
{
    return std::fabs(a - b) <= 1e-9 * std::max(std::fabs(a), std::fabs(b));
}

/* A preview's warp: each post takes its nearest source post (a filter as wide as the coarse
 * spacing would read every source post for each: several times slower, for a picture that
 * lasts seconds). */
void coarse_sampling(std::vector<std::string>& args)
{
    for (size_t i = 0; i + 1 < args.size(); i++)
        if (args[i] == "-r")
            args[i + 1] = "near";
}

/* The value GDAL writes into a Float32 buffer for a nodata tag (clamped to the float range). */
float as_float(double v)
{
    if (std::isnan(v))
        return NAN;
    if (v > FLT_MAX)
        return FLT_MAX;
    if (v < -FLT_MAX)
        return -FLT_MAX;
    return (float)v;
}

std::atomic<unsigned> mosaic_serial{0};

/* The plan's input: a tp_dem with the dataset's size, georeference and CRS, no heights. */
struct PlanDem {
    tp_dem dem{};
    std::string wkt;
    PlanDem(int w, int h, const double gt[6], bool has_gt, const OGRSpatialReference* srs)
    {
        dem.width = w;
        dem.height = h;
        std::memcpy(dem.geotransform, gt, sizeof dem.geotransform);
        dem.has_geotransform = has_gt;
        wkt = srs ? tpio::crs_wkt2(*srs) : std::string();
        dem.crs_wkt = const_cast<char*>(wkt.c_str());
    }
};

std::string vsimem_name(tp_mosaic* m, const char* what)
{
    std::string name = CPLSPrintf("/vsimem/terrapatch_mosaic_%u_%p_%s.vrt", mosaic_serial++,
                                  (void*)m, what);
    m->vsimem.push_back(name);
    return name;
}

/* For GDAL's warp and VRT mosaic (one nodata value per band): source s with both its void
 * values read as -32768, its nodata (int16_voids.hpp), under a /vsimem/ name of the mosaic's;
 * s.srs is written into it (an override of the file's own included). Null when GDAL fails. */
tpio::Dataset int16_voids_as_one(tp_mosaic* m, const Source& s)
{
    return tpio::int16_voids_vrt(s.path, s.w, s.h, s.gt, s.has_gt, s.has_crs ? &s.srs : nullptr,
                                 vsimem_name(m, "int16"));
}

/* GDALBuildVRT of the named files into a /vsimem/ VRT; extra: more arguments. */
tpio::Dataset build_vrt(tp_mosaic* m, const std::vector<std::string>& files,
                        const std::vector<std::string>& extra, const char* what)
{
    Args a;
    a.s = extra;
    GDALBuildVRTOptions* o = GDALBuildVRTOptionsNew(a.get(), nullptr);
    if (!o)
        return nullptr;
    std::vector<const char*> names;
    for (auto& f : files)
        names.push_back(f.c_str());
    int usage = 0;
    const std::string dst = vsimem_name(m, what);
    GDALDatasetH h = GDALBuildVRT(dst.c_str(), (int)names.size(), nullptr, names.data(), o, &usage);
    GDALBuildVRTOptionsFree(o);
    if (!h)
        return nullptr;
    /* written on close; reopened by name so that a warped VRT may refer to it */
    GDALClose(h);
    return tpio::Dataset(GDALDataset::Open(dst.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
}

tpio::Dataset warp_vrt(tp_mosaic* m, GDALDataset* src, const std::vector<std::string>& args,
                       const char* what)
{
    Args a;
    a.s = args;
    GDALWarpAppOptions* o = GDALWarpAppOptionsNew(a.get(), nullptr);
    if (!o)
        return nullptr;
    GDALDatasetH in = GDALDataset::ToHandle(src);
    int usage = 0;
    const std::string dst = vsimem_name(m, what);
    GDALDatasetH h = GDALWarp(dst.c_str(), nullptr, 1, &in, o, &usage);
    GDALWarpAppOptionsFree(o);
    if (!h)
        return nullptr;
    /* the VRT is written on close; reopen it by name so that a later VRT may refer to it */
    GDALClose(h);
    return tpio::Dataset(GDALDataset::Open(dst.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
}

/* A preview's source: src with every f-th post of each row and column (nearest), as a /vsimem/
 * VRT, so that the warp onto the coarse grid reads a sixteenth of it, not all of it for each
 * chunk (f = 4: 1.7 s -> 0.2 s for a 3601x3601 tile). Null when GDAL fails. */
tpio::Dataset decimated(tp_mosaic* m, GDALDataset* src, int f)
{
    Args a;
    a.s = {"-of", "VRT", "-r", "nearest", "-outsize",
           std::to_string((src->GetRasterXSize() + f - 1) / f),
           std::to_string((src->GetRasterYSize() + f - 1) / f)};
    GDALTranslateOptions* o = GDALTranslateOptionsNew(a.get(), nullptr);
    if (!o)
        return nullptr;
    int usage = 0;
    const std::string dst = vsimem_name(m, "decimated");
    GDALDatasetH h = GDALTranslate(dst.c_str(), GDALDataset::ToHandle(src), o, &usage);
    GDALTranslateOptionsFree(o);
    if (!h)
        return nullptr;
    GDALClose(h); /* written on close; reopened by name, as the warp refers to it */
    return tpio::Dataset(GDALDataset::Open(dst.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
}

/* What open_mosaic works from: its arguments, and the sources once opened. */
struct Opening {
    const char* const* paths = nullptr;
    size_t count = 0;
    tp_mosaic_options o{};
    int memory_mb = 0;
    OGRSpatialReference over; /* --crs (has_over) */
    bool has_over = false;
    std::vector<Source> src;
    bool untagged_int16 = false; /* some source is an Int16 one without a nodata tag */

    tp_status open_sources(tp_mosaic* m, tp_error* err);
    tp_status open_shared(tp_mosaic* m, tp_error* err);
    tp_status open_coarse(tp_mosaic* m, tpio::Dataset base, const double bgt[6], tp_error* err);
    tp_status render_crs(OGRSpatialReference& dst, tp_error* err) const;
    tp_status open_warped(tp_mosaic* m, tp_error* err);
    tp_status finish_open(tp_mosaic* m, tp_error* err) const;
};

/* Opens and checks every source (one height unit for all), with their notes. */
tp_status Opening::open_sources(tp_mosaic* m, tp_error* err)
{
    src.resize(count);
    for (size_t i = 0; i < count; i++) {
        if (const tp_status st = open_source(paths[i], o.z_unit, &src[i], err))
            return st;
        if (src[i].z.to_m != src[0].z.to_m)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: heights in %s (%s), but %s's are in %s (%s): give --z-unit, or "
                        "convert one first",
                        paths[i],
                        src[i].z.name.empty() ? "metres (no unit stated)" : src[i].z.name.c_str(),
                        src[i].z.from.c_str(), src[0].name.c_str(),
                        src[0].z.name.empty() ? "metres (no unit stated)" : src[0].z.name.c_str(),
                        src[0].z.from.c_str());
        if (!src[i].z.warning.empty())
            add_note(m->notes, "warning: " + src[i].name + ": " + src[i].z.warning);
        if (count > 1 && !src[i].has_gt)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: no geotransform: a mosaic of several sources needs to know where "
                        "each one lies",
                        paths[i]);
        if (has_over) {
            src[i].srs = over;
            src[i].has_crs = true;
        }
        m->integer = m->integer && GDALDataTypeIsInteger(src[i].type);
    }
    m->source_count = (int)count;
    m->z_to_m = src[0].z.to_m;
    m->integer = m->integer && m->z_to_m == 1.0; /* whole feet are not whole metres */
    if (src[0].z.to_m != 1.0)
        add_note(m->notes, CPLSPrintf("heights in %s (%s): converted to metres (x %.10g)",
                                      src[0].z.name.c_str(), src[0].z.from.c_str(), src[0].z.to_m));
    if (count > 1)
        add_note(m->notes, CPLSPrintf("%zu sources", count));

    for (const Source& s : src)
        untagged_int16 |= s.int16_voids();
    m->int16_voids = untagged_int16;
    return TP_OK;
}

/* 1 when every source shares the first one's CRS and post spacing: one GDALBuildVRT. */
bool share_one_grid(const std::vector<Source>& src)
{
    const size_t count = src.size();
    bool shared = true;
    for (size_t i = 1; i < count && shared; i++) {
        shared = src[i].has_crs == src[0].has_crs &&
                 (!src[0].has_crs || src[i].srs.IsSame(&src[0].srs)) &&
                 same_spacing(src[i].gt[1], src[0].gt[1]) && same_spacing(src[i].gt[5], src[0].gt[5]);
    }
    return shared;
}

/* Sources of one CRS and spacing: one source, or their GDALBuildVRT mosaic, warped onto the
 * render grid when the plan says so (as tp_render_grid_build would warp one DEM). */
tp_status Opening::open_shared(tp_mosaic* m, tp_error* err)
{
    tpio::Dataset base; /* the grid before any warp: one source, or the mosaic VRT */
    if (count == 1) {
        base.reset(GDALDataset::Open(paths[0], GDAL_OF_RASTER | GDAL_OF_READONLY));
    } else {
        /* each source's own nodata, and -32768 for the untagged Int16 ones (-32767 read
         * as -32768 first): a source's voids leave an earlier source's heights */
        std::vector<std::string> files, extra;
        for (const Source& s : src) {
            if (!s.int16_voids()) {
                files.push_back(s.path);
                continue;
            }
            if (!int16_voids_as_one(m, s))
                return fail(err, TP_ERR_BACKEND, "%s: mosaic: %s", s.path.c_str(),
                            tpio::gdal_message().c_str());
            files.push_back(m->vsimem.back());
        }
        if (untagged_int16)
            extra = {"-vrtnodata", "-32768"};
        extra.insert(extra.end(), {"-b", "1"});
        base = build_vrt(m, files, extra, "mosaic");
    }
    if (!base)
        return fail(err, TP_ERR_BACKEND, "%s: mosaic: %s", paths[0], tpio::gdal_message().c_str());
    /* --crs: on the mosaic VRT, never on a source's own file (GDAL would write it into a
     * .aux.xml beside the file on close); the plan and the warp take src[0].srs */
    if (has_over && count > 1)
        base->SetSpatialRef(&over);
    double bgt[6];
    base->GetGeoTransform(bgt);
    if (count > 1)
        m->covered_share =
            note_overlaps(src, bgt, base->GetRasterXSize(), base->GetRasterYSize(), m->notes);

    PlanDem pd(base->GetRasterXSize(), base->GetRasterYSize(), src[0].gt, src[0].has_gt,
               src[0].has_crs ? &src[0].srs : nullptr);
    std::memcpy(pd.dem.geotransform, bgt, sizeof bgt);
    tpio::GridPlan plan;
    tp_grid_options go{};
    go.resampling = o.resampling;
    if (const tp_status st = tpio::render_grid_plan(&pd.dem, &go, &plan, err)) {
        std::string msg = err ? err->message : "";
        return fail(err, st, "%s: %s", paths[0], msg.c_str());
    }
    if (!plan.warnings.empty())
        add_note(m->notes, plan.warnings);
    const int coarsen = o.coarsen > 1 ? o.coarsen : 1;
    if (plan.warp) {
        plan.res *= coarsen;
        std::vector<std::string> args = tpio::render_grid_warp_args(plan, "VRT");
        if (coarsen > 1)
            coarse_sampling(args);
        if (untagged_int16 && count == 1) { /* -32767 read as -32768 first */
            base = int16_voids_as_one(m, src[0]);
            if (!base)
                return fail(err, TP_ERR_BACKEND, "%s: %s", paths[0],
                            tpio::gdal_message().c_str());
            args.insert(args.end(), {"-srcnodata", "-32768"});
        }
        if (coarsen > 1 && !(base = decimated(m, base.get(), coarsen)))
            return fail(err, TP_ERR_BACKEND, "%s: a preview: %s", paths[0],
                        tpio::gdal_message().c_str());
        /* the plan's source CRS: --crs, or EPSG:4326 for a grid plainly in degrees */
        args.insert(args.end(), {"-s_srs", tpio::crs_wkt2(plan.src)});
        tpio::Dataset w = warp_vrt(m, base.get(), args, "warp");
        if (!w)
            return fail(err, TP_ERR_BACKEND, "%s: warp to %s failed: %s", paths[0],
                        plan.t_srs.c_str(), tpio::gdal_message().c_str());
        add_note(m->notes, CPLSPrintf("warped from %s to %s (%s), posts %.6g m apart",
                                      plan.src.GetName() ? plan.src.GetName() : "its CRS",
                                      plan.dst.GetName() ? plan.dst.GetName() : "",
                                      plan.t_srs.c_str(), plan.res));
        m->back.reset(OGRCreateCoordinateTransformation(&plan.dst, &plan.src));
        if (!m->back)
            return fail(err, TP_ERR_BACKEND, "no transformation back from %s: %s",
                        plan.t_srs.c_str(), tpio::gdal_message().c_str());
        m->back_geographic = plan.src.IsGeographic();
        std::memcpy(m->sgt, bgt, sizeof bgt);
        m->sw = pd.dem.width; /* the grid's, before a preview's decimation */
        m->sh = pd.dem.height;
        m->warped = true;
        m->ds = std::move(w); /* it opens the mosaic itself, by name */
    } else if (coarsen > 1) { /* a grid already in metres, resampled at coarser posts */
        if (const tp_status st = open_coarse(m, std::move(base), bgt, err))
            return st;
    } else {
        m->ds = std::move(base);
    }
    if (plan.has_crs) {
        m->crs_wkt = tpio::crs_wkt2(plan.dst);
        const char* name = plan.dst.GetName();
        std::snprintf(m->crs_name, sizeof m->crs_name, "%s", name ? name : "unnamed CRS");
        m->epsg = tpio::crs_epsg(plan.dst);
    } else {
        std::snprintf(m->crs_name, sizeof m->crs_name, "local metres (no CRS)");
    }
    return TP_OK;
}

/* A preview's grid (o.coarsen > 1) over base, a grid in metres that needs no warp: base
 * resampled onto posts coarsen times farther apart (bgt: its geotransform). */
tp_status Opening::open_coarse(tp_mosaic* m, tpio::Dataset base, const double bgt[6],
                               tp_error* err)
{
    const double res = std::fabs(bgt[1]) * o.coarsen;
    const std::string tr = CPLSPrintf("%.17g", res);
    std::vector<std::string> args = {"-tr", tr, tr, "-r", "near", "-et", "0", "-dstnodata",
                                     "nan", "-ot", "Float32", "-of", "VRT"};
    if (untagged_int16 && count == 1) { /* -32767 read as -32768 first */
        base = int16_voids_as_one(m, src[0]);
        if (!base)
            return fail(err, TP_ERR_BACKEND, "%s: %s", paths[0], tpio::gdal_message().c_str());
        args.insert(args.end(), {"-srcnodata", "-32768"});
    }
    if (!(base = decimated(m, base.get(), o.coarsen)))
        return fail(err, TP_ERR_BACKEND, "%s: a preview: %s", paths[0],
                    tpio::gdal_message().c_str());
    tpio::Dataset w = warp_vrt(m, base.get(), args, "coarse");
    if (!w)
        return fail(err, TP_ERR_BACKEND, "%s: resampling for a preview failed: %s", paths[0],
                    tpio::gdal_message().c_str());
    m->warped = true;
    m->ds = std::move(w);
    return TP_OK;
}

/* The render CRS of sources that differ in CRS or spacing (dst). */
tp_status Opening::render_crs(OGRSpatialReference& dst, tp_error* err) const
{
    /* The render CRS: the sources' own when all of them are in one projected CRS in metres;
     * else the UTM/UPS zone of the centre of their geographic extent. */
    bool one_projected = true;
    for (const Source& s : src)
        one_projected = one_projected && s.srs.IsProjected() &&
                        std::fabs(s.srs.GetLinearUnits() - 1.0) < 1e-12 && s.srs.IsSame(&src[0].srs);
    if (one_projected) {
        dst = src[0].srs;
    } else {
        OGRSpatialReference wgs84 = tpio::crs_wgs84();
        double lon0 = INFINITY, lon1 = -INFINITY, lat0 = INFINITY, lat1 = -INFINITY;
        for (const Source& s : src) {
            std::unique_ptr<OGRCoordinateTransformation> ct(
                OGRCreateCoordinateTransformation(&s.srs, &wgs84));
            if (!ct)
                return fail(err, TP_ERR_BACKEND, "%s: no transformation to WGS84: %s",
                            s.path.c_str(), tpio::gdal_message().c_str());
            for (int k = 0; k < 4; k++) {
                double x = s.gt[0] + (k & 1 ? s.w - 0.5 : 0.5) * s.gt[1];
                double y = s.gt[3] + (k & 2 ? s.h - 0.5 : 0.5) * s.gt[5];
                if (!ct->Transform(1, &x, &y))
                    continue;
                lon0 = std::min(lon0, x), lon1 = std::max(lon1, x);
                lat0 = std::min(lat0, y), lat1 = std::max(lat1, y);
            }
        }
        if (!(lon1 >= lon0 && lat1 >= lat0))
            return fail(err, TP_ERR_BACKEND, "%s: the sources have no WGS84 extent", paths[0]);
        /* The zone as one geographic DEM over that extent would get it. */
        const double egt[6] = {lon0, (lon1 - lon0) / 2, 0, lat1, 0, -(lat1 - lat0) / 2};
        PlanDem pd(2, 2, egt, true, &wgs84);
        if (egt[1] <= 0 || egt[5] >= 0) { /* a point: widen it a little */
            pd.dem.geotransform[1] = 1e-4;
            pd.dem.geotransform[5] = -1e-4;
        }
        tpio::GridPlan zplan;
        if (const tp_status st = tpio::render_grid_plan(&pd.dem, nullptr, &zplan, err))
            return st;
        dst = zplan.dst;
    }
    return TP_OK;
}

/* Sources that differ in CRS or spacing: each warped onto one grid, then mosaicked. */
tp_status Opening::open_warped(tp_mosaic* m, tp_error* err)
{
    for (const Source& s : src)
        if (!s.has_crs)
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: no CRS, and the other sources differ in CRS or spacing: give "
                        "--crs, or sources that share one",
                        s.path.c_str());
    OGRSpatialReference dst;
    dst.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    if (const tp_status st = render_crs(dst, err))
        return st;
    const std::string t_srs = tpio::crs_wkt2(dst);
    double res = INFINITY, ext[4] = {INFINITY, INFINITY, -INFINITY, -INFINITY};
    std::vector<Rect> footprints; /* each source's extent in the render CRS */
    for (Source& s : src) {
        std::unique_ptr<OGRCoordinateTransformation> ct(
            OGRCreateCoordinateTransformation(&s.srs, &dst));
        if (!ct)
            return fail(err, TP_ERR_BACKEND, "%s: no transformation to the render CRS: %s",
                        s.path.c_str(), tpio::gdal_message().c_str());
        res = std::min(res, tpio::grid_finest_spacing(ct.get(), s.gt, s.w, s.h));
        PlanDem pd(s.w, s.h, s.gt, true, &s.srs);
        double e[4];
        if (!tpio::grid_warp_extent(&pd.dem, s.srs, t_srs, e))
            return fail(err, TP_ERR_BACKEND, "%s: no extent in the render CRS: %s",
                        s.path.c_str(), tpio::gdal_message().c_str());
        ext[0] = std::min(ext[0], e[0]), ext[1] = std::min(ext[1], e[1]);
        ext[2] = std::max(ext[2], e[2]), ext[3] = std::max(ext[3], e[3]);
        footprints.push_back({e[0], e[1], e[2], e[3]});
    }
    m->covered_share = covered_share(footprints, Rect{ext[0], ext[1], ext[2], ext[3]});
    if (m->covered_share < 1.0 - 1e-6)
        add_note(m->notes, CPLSPrintf("gaps between the sources: about %.1f%% of the "
                                      "mosaic's extent is covered by none and is nodata",
                                      100.0 * (1.0 - m->covered_share)));
    if (!std::isfinite(res) || res <= 0)
        return fail(err, TP_ERR_BACKEND, "%s: could not measure the post spacing", paths[0]);
    if (o.coarsen > 1)
        res *= o.coarsen;
    /* a grid aligned on the spacing, holding every source */
    const double x0 = std::floor(ext[0] / res) * res, y1 = std::ceil(ext[3] / res) * res;
    const double x1 = x0 + std::ceil((ext[2] - x0) / res) * res;
    const double y0 = y1 - std::ceil((y1 - ext[1]) / res) * res;
    const char* dst_name = dst.GetName() ? dst.GetName() : "the render CRS";
    std::vector<std::string> files;
    for (size_t i = 0; i < count; i++) {
        const Source& s = src[i];
        tpio::Dataset in; /* an untagged Int16 source: -32767 read as -32768 */
        if (s.int16_voids())
            in = int16_voids_as_one(m, s); /* in s.srs: --crs included */
        else
            in.reset(GDALDataset::Open(s.path.c_str(), GDAL_OF_RASTER | GDAL_OF_READONLY));
        if (!in)
            return fail(err, TP_ERR_BAD_DATA, "%s: cannot reopen: %s", s.path.c_str(),
                        tpio::gdal_message().c_str());
        const std::string tr = CPLSPrintf("%.17g", res);
        std::vector<std::string> args = {
            "-t_srs", t_srs, "-tr", tr, tr, "-te", CPLSPrintf("%.17g", x0),
            CPLSPrintf("%.17g", y0), CPLSPrintf("%.17g", x1), CPLSPrintf("%.17g", y1), "-r",
            o.resampling == TP_RESAMPLING_CUBIC ? "cubic" : "bilinear", "-et", "0",
            "-dstnodata", "nan", "-ot", "Float32", "-of", "VRT"};
        if (o.coarsen > 1)
            coarse_sampling(args);
        if (s.int16_voids())
            args.insert(args.end(), {"-srcnodata", "-32768"});
        if (has_over) /* as the warp's, not the file's: see the shared grid's --crs */
            args.insert(args.end(), {"-s_srs", tpio::crs_wkt2(over)});
        tpio::Dataset w = warp_vrt(m, in.get(), args, CPLSPrintf("warp%zu", i));
        if (!w)
            return fail(err, TP_ERR_BACKEND, "%s: warp to %s failed: %s", s.path.c_str(),
                        dst_name, tpio::gdal_message().c_str());
        files.push_back(m->vsimem.back());
        const bool same_crs = s.srs.IsSame(&dst);
        add_note(m->notes,
                 CPLSPrintf("%s: %s, posts %.6g x %.6g%s: %s onto %s, posts %.6g m apart",
                            s.name.c_str(), s.srs.GetName() ? s.srs.GetName() : "its CRS",
                            std::fabs(s.gt[1]), std::fabs(s.gt[5]),
                            s.srs.IsGeographic() ? " degrees" : "",
                            same_crs ? "resampled" : "warped", dst_name, res));
        m->warped = true;
    }
    add_note(m->notes, "the sources differ in CRS or post spacing: each is warped onto one "
                       "grid and GDAL's VRT mosaics them (a later source wins where they "
                       "overlap)");
    tpio::Dataset v = build_vrt(m, files, {"-b", "1"}, "mosaic");
    if (!v)
        return fail(err, TP_ERR_BACKEND, "%s: mosaic: %s", paths[0], tpio::gdal_message().c_str());
    m->ds = std::move(v);
    m->crs_wkt = t_srs;
    std::snprintf(m->crs_name, sizeof m->crs_name, "%s", dst_name);
    m->epsg = tpio::crs_epsg(dst);
    return TP_OK;
}

/* What is read once the grid is planned: its size and nodata, the void window and the
 * --fill-from source, and a bound of its heights. */
tp_status Opening::finish_open(tp_mosaic* m, tp_error* err) const
{
    m->w = m->ds->GetRasterXSize();
    m->h = m->ds->GetRasterYSize();
    m->ds->GetGeoTransform(m->gt);
    m->spacing_m = std::min(std::fabs(m->gt[1]), std::fabs(m->gt[5]));
    GDALRasterBand* b = m->ds->GetRasterBand(1);
    int has = 0;
    double nd = b->GetNoDataValue(&has);
    m->has_nodata = has != 0;
    m->nodata = as_float(nd);
    m->int16_guess = !m->warped && untagged_int16 && !m->has_nodata;

    /* void filling: the window a void is filled in may take fill_window_mb (about 60 bytes a
     * sample of a row: the window as read and filled, the second source, labels, marks, crops) */
    if (m->fill_max > 0) {
        const double bytes = (o.fill_window_mb > 0 ? o.fill_window_mb : memory_mb / 8.0) * 1048576.0;
        m->fill_max_rows = (int)std::min<double>(INT_MAX, std::max(8.0, bytes / (60.0 * m->w)));
    }
    if (o.fill_from && *o.fill_from) {
        const std::string name = vsimem_name(m, "fill_from");
        m->vsimem.push_back(tpio::fill_source_int16_name(name)); /* if made, unlinked too */
        if (const tp_status st =
                tpio::fill_source_open(o.fill_from, m->gt, m->w, m->h, m->crs_wkt, "VRT", name,
                                       &m->other, &m->other_unit, err))
            return st;
        const std::string unit = tpio::fill_source_unit_note(m->other_unit);
        add_note(m->notes, CPLSPrintf("voids filled from %s (%s%swarped onto the grid, shifted "
                                      "to meet the ground around each void)",
                                      base_name(o.fill_from).c_str(), unit.c_str(),
                                      unit.empty() ? "" : "; "));
        if (!m->other_unit.warning.empty())
            add_note(m->notes, "warning: " + m->other_unit.warning);
    }
    if (untagged_int16)
        add_note(m->notes, "Int16 sources without a nodata tag: -32768 and -32767 taken as nodata");

    /* A bound of the heights without reading them: every source's exact statistics. */
    bool stats = o.resampling != TP_RESAMPLING_CUBIC;
    for (const Source& s : src)
        stats = stats && s.has_stats;
    if (o.range_given) { /* metres, as the caller knows them */
        m->has_range = true;
        m->min_m = o.range_min_m, m->max_m = o.range_max_m;
        return TP_OK;
    }
    if (stats) {
        m->has_range = true;
        m->min_m = src[0].stat_min, m->max_m = src[0].stat_max;
        for (const Source& s : src)
            m->min_m = std::min(m->min_m, s.stat_min), m->max_m = std::max(m->max_m, s.stat_max);
    } else if (!m->warped) {
        range_of_files(m);
    }
    if (m->has_range) { /* in the sources' unit: the heights read are in metres */
        m->min_m *= m->z_to_m;
        m->max_m *= m->z_to_m;
    }
    return TP_OK;
}

tp_status open_mosaic(const char* const* paths, size_t count, const tp_mosaic_options* opt,
                      tp_mosaic* m, tp_error* err)
{
    tpio::register_drivers();
    tpio::QuietGdal quiet;
    Opening op;
    op.paths = paths;
    op.count = count;
    op.o = opt ? *opt : tp_mosaic_options{};
    const tp_mosaic_options& o = op.o;
    const int memory_mb = op.memory_mb = o.memory_mb > 0 ? o.memory_mb : 1024;
    m->fill_max = o.fill_max > 0 ? o.fill_max : 0;
    /* a quarter of the budget: GDAL's block cache, or, when filling voids without a
     * fill_window_mb, half of it the cache and half the void window */
    const bool split = m->fill_max > 0 && o.fill_window_mb <= 0;
    GDALSetCacheMax64((GIntBig)memory_mb * 1024 * 1024 / (split ? 8 : 4));

    op.over.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    op.has_over = o.crs && *o.crs;
    if (op.has_over && op.over.SetFromUserInput(o.crs) != OGRERR_NONE)
        return fail(err, TP_ERR_INVALID_ARG, "CRS '%s' is not one GDAL/PROJ knows", o.crs);

    if (const tp_status st = op.open_sources(m, err))
        return st;
    if (const tp_status st = share_one_grid(op.src) ? op.open_shared(m, err)
                                                    : op.open_warped(m, err))
        return st;
    if (o.coarsen > 1)
        add_note(m->notes, CPLSPrintf("a preview: posts %d times farther apart than the "
                                      "grid's",
                                      o.coarsen));
    return op.finish_open(m, err);
}

} // namespace

extern "C" tp_status tp_mosaic_open(const char* const* paths, size_t path_count,
                                    const tp_mosaic_options* options, tp_mosaic** out,
                                    tp_error* err)
{
    if (!paths || path_count < 1 || !out)
        return fail(err, TP_ERR_INVALID_ARG, "mosaic: paths and out must not be NULL");
    for (size_t i = 0; i < path_count; i++)
        if (!paths[i] || !*paths[i])
            return fail(err, TP_ERR_INVALID_ARG, "mosaic: source %zu has an empty name", i + 1);
    try {
        std::unique_ptr<tp_mosaic> m(new tp_mosaic);
        /* DTED checksums are verified when read (tp_dem_read does the same) */
        if (!CPLGetConfigOption("DTED_VERIFY_CHECKSUM", nullptr))
            CPLSetConfigOption("DTED_VERIFY_CHECKSUM", "YES");
        const tp_status st = open_mosaic(paths, path_count, options, m.get(), err);
        if (st != TP_OK)
            return st;
        *out = m.release();
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, "mosaic");
    }
}

extern "C" void tp_mosaic_close(tp_mosaic* m)
{
    try {
        delete m;
    } catch (...) {
    }
}

extern "C" void tp_mosaic_get_info(const tp_mosaic* m, tp_mosaic_info* out)
{
    *out = tp_mosaic_info{};
    out->width = m->w;
    out->height = m->h;
    std::memcpy(out->geotransform, m->gt, sizeof m->gt);
    out->crs_wkt = m->crs_wkt.c_str();
    std::memcpy(out->crs_name, m->crs_name, sizeof out->crs_name);
    out->epsg = m->epsg;
    out->spacing_m = m->spacing_m;
    out->source_count = m->source_count;
    out->warped = m->warped;
    out->covered_share = m->covered_share;
    out->integer_sources = m->integer;
    out->has_range = m->has_range;
    out->min_m = m->min_m;
    out->max_m = m->max_m;
    out->notes = m->notes.c_str();
}
