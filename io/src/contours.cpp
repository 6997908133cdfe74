/* contours.cpp - contour lines by GDAL's contour generator, and contour lines written as an OGR
 * vector file (see tp_vector.h, "Contours").
 *
 * The generator is GDAL's (alg/contour.cpp: marching squares over the sample centres, Hugo
 * Mercier's 2018 rewrite of Frank Warmerdam's 2003 generator); we only hand it the grid and read
 * its lines back. Voids go in as a finite nodata value below every height (GDAL turns nodata
 * into its own "no value" inside the generator; NaN itself is not a nodata value GDAL's
 * equality tests can match).
 *
 * The writer makes the file in a new temporary folder beside its target, with the driver the
 * extension names (output_format.cpp), and puts what the driver made into place only when it
 * is complete, all or none (a file set, file_set.cpp): a driver may write several files (a
 * Shapefile's .shp, .shx, .dbf, .prj, .cpg) and may leave a half-written file behind when it
 * fails, so it never writes beside the target itself.
 */
#include "atomic_write.hpp"
#include "gdal_util.hpp"
#include "output_format.hpp"
#include "tp_io.h"
#include "tp_vector.h"

#include <gdal_alg.h>
#include <ogrsf_frmts.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cfloat>
#include <cmath>
#include <dirent.h>
#include <filesystem>
#include <string>
#include <sys/stat.h>
#include <vector>

using tpio::fail;

namespace {

namespace fs = std::filesystem;

/* ---------------------------------------------------------------------------------------------
 * Generation
 */
struct Line {
    double value;
    bool ring;
    size_t first, count;
};

/* The levels one call draws (tp_contours_options): an interval's, all of them (GDAL's
 * LEVEL_INTERVAL), or a list, ascending (GDAL's FIXED_LEVELS): the levels given, or an
 * interval's within [min_m, max_m] and the heights' range. */
struct Levels {
    bool interval = false; /* LEVEL_INTERVAL: base + k * step for every k */
    double base = 0.0, step = 0.0;
    std::vector<double> fixed; /* otherwise: these, ascending */
    std::vector<double> given; /* levels given: all of them, ascending, for the index */

    /* How many levels lie at or below z, up to a constant: the levels a grid edge between two
     * heights crosses are the difference of the two counts. */
    double below(double z) const
    {
        if (interval)
            return std::floor((z - base) / step);
        return (double)(std::upper_bound(fixed.begin(), fixed.end(), z) - fixed.begin());
    }
    size_t count() const
    {
        return fixed.size();
    }
};

/* Index contour: with an interval, (value - base) a multiple of every * interval; with levels,
 * every every-th of the levels given, the lowest first. */
bool is_index(double value, const tp_contours_options& o, const Levels& lv)
{
    const int every = o.index_every;
    if (every <= 0)
        return false;
    if (o.interval_m > 0.0) {
        const double k = (value - o.base_m) / o.interval_m / every;
        return std::fabs(k - std::round(k)) < 1e-6;
    }
    const auto at = std::lower_bound(lv.given.begin(), lv.given.end(), value);
    return at != lv.given.end() && *at == value && (at - lv.given.begin()) % every == 0;
}

/* The lines of one geometry (a LineString, or each part of a MultiLineString) appended; those
 * with fewer than min_vertices points (as GDAL wrote them) counted in *dropped instead. */
void take_geometry(const OGRGeometry* g, double value, size_t min_vertices, std::vector<double>* xy,
                   std::vector<Line>* lines, size_t* dropped)
{
    if (!g)
        return;
    const OGRwkbGeometryType t = wkbFlatten(g->getGeometryType());
    if (t == wkbMultiLineString || t == wkbGeometryCollection) {
        const auto* c = g->toGeometryCollection();
        for (int i = 0; i < c->getNumGeometries(); ++i)
            take_geometry(c->getGeometryRef(i), value, min_vertices, xy, lines, dropped);
        return;
    }
    if (t != wkbLineString)
        return;
    const OGRLineString* ls = g->toLineString();
    int n = ls->getNumPoints();
    if (n < 2)
        return;
    if ((size_t)n < min_vertices) {
        ++*dropped;
        return;
    }
    const bool ring = n >= 4 && ls->getX(0) == ls->getX(n - 1) && ls->getY(0) == ls->getY(n - 1);
    if (ring)
        --n; /* tp_feature's ring does not repeat its first vertex */
    lines->push_back({value, ring, xy->size() / 2, (size_t)n});
    for (int i = 0; i < n; ++i) {
        xy->push_back(ls->getX(i));
        xy->push_back(ls->getY(i));
    }
}

tp_status check_arguments(const float* heights, size_t height_count, int width, int height,
                          const double* geotransform, const tp_contours_options* o,
                          tp_features** out, tp_error* err)
{
    if (!heights || !geotransform || !o || !out)
        return fail(err, TP_ERR_INVALID_ARG,
                    "contours: NULL heights, geotransform, options or out");
    if (width < 1 || height < 1 || height_count != (size_t)width * (size_t)height)
        return fail(err, TP_ERR_INVALID_ARG,
                    "contours: expected a grid of at least 1x1 with width * height heights, got "
                    "%dx%d and %zu heights",
                    width, height, height_count);
    for (int i = 0; i < 6; ++i)
        if (!std::isfinite(geotransform[i]))
            return fail(err, TP_ERR_INVALID_ARG, "contours: geotransform[%d] is not finite", i);
    if (geotransform[1] == 0.0 || geotransform[5] == 0.0)
        return fail(err, TP_ERR_INVALID_ARG,
                    "contours: expected a geotransform with non-zero sample sizes, got %g, %g",
                    geotransform[1], geotransform[5]);
    const bool has_levels = o->levels && o->level_count > 0;
    if (!std::isfinite(o->interval_m) || o->interval_m < 0.0 ||
        (o->interval_m == 0.0 && !has_levels))
        return fail(err, TP_ERR_INVALID_ARG,
                    "contours: expected an interval > 0 m (or levels), got %g", o->interval_m);
    if (o->interval_m > 0.0 && has_levels)
        return fail(err, TP_ERR_INVALID_ARG,
                    "contours: expected an interval or levels, got an interval of %g m and %zu "
                    "levels",
                    o->interval_m, o->level_count);
    if (!std::isfinite(o->base_m))
        return fail(err, TP_ERR_INVALID_ARG, "contours: expected a finite base, got %g", o->base_m);
    if (has_levels && o->level_count > TP_CONTOURS_MAX_LEVELS)
        return fail(err, TP_ERR_INVALID_ARG, "contours: %zu levels given (at most %d)",
                    o->level_count, TP_CONTOURS_MAX_LEVELS);
    for (size_t i = 0; has_levels && i < o->level_count; ++i)
        if (!std::isfinite(o->levels[i]))
            return fail(err, TP_ERR_INVALID_ARG, "contours: level %zu is not finite (%g)", i + 1,
                        o->levels[i]);
    if (std::isnan(o->min_m) || std::isnan(o->max_m) || o->min_m > o->max_m)
        return fail(err, TP_ERR_INVALID_ARG,
                    "contours: expected a range of levels with min <= max, got %g .. %g", o->min_m,
                    o->max_m);
    if (o->index_every < 0)
        return fail(err, TP_ERR_INVALID_ARG,
                    "contours: expected index_every >= 0 (0: no index contours), got %d",
                    o->index_every);
    return TP_OK;
}

/* The levels o draws over heights lo .. hi (lo > hi: no valid height). */
tp_status choose_levels(const tp_contours_options& o, float lo, float hi, Levels* lv, tp_error* err)
{
    const bool all = o.min_m == -HUGE_VAL && o.max_m == HUGE_VAL;
    if (o.interval_m > 0.0) {
        if (lo <= hi && ((double)hi - lo) / o.interval_m > TP_CONTOURS_MAX_LEVELS)
            return fail(err, TP_ERR_INVALID_ARG,
                        "contours: an interval of %g m gives %.0f levels over the heights %.1f "
                        ".. %.1f m (at most %d)",
                        o.interval_m, ((double)hi - lo) / o.interval_m, (double)lo, (double)hi,
                        TP_CONTOURS_MAX_LEVELS);
        if (all) {
            lv->interval = true, lv->base = o.base_m, lv->step = o.interval_m;
            return TP_OK;
        }
        /* the interval's levels in [min, max] and in the heights' range, as GDAL computes
         * them (base + k * interval); a level within rounding of min or max is in */
        if (lo > hi)
            return TP_OK;
        const double a = std::max(o.min_m, (double)lo), b = std::min(o.max_m, (double)hi);
        const double k0 = std::ceil((a - o.base_m) / o.interval_m - 1e-9);
        const double k1 = std::floor((b - o.base_m) / o.interval_m + 1e-9);
        for (double k = k0; k <= k1; ++k)
            lv->fixed.push_back(o.base_m + k * o.interval_m);
        return TP_OK;
    }
    lv->given.assign(o.levels, o.levels + o.level_count);
    std::sort(lv->given.begin(), lv->given.end());
    lv->given.erase(std::unique(lv->given.begin(), lv->given.end()), lv->given.end());
    for (double v : lv->given)
        if (v >= o.min_m && v <= o.max_m)
            lv->fixed.push_back(v);
    return TP_OK;
}

/* The vertices the lines will have, before any is made: a level crosses a grid edge between
 * two valid samples once for each level between their heights, and GDAL's lines put one vertex
 * on each crossing. A tiny interval over rough ground is billions of them (minutes,
 * gigabytes), however few levels it has. */
tp_status check_vertices(const float* heights, int width, int height, const Levels& lv,
                         const tp_contours_options& o, tp_error* err)
{
    double vertices = 0;
    for (int y = 0; y < height; ++y)
        for (int x = 0; x < width; ++x) {
            const float z = heights[(size_t)y * width + x];
            if (std::isnan(z))
                continue;
            const double k = lv.below(z);
            const float r = x + 1 < width ? heights[(size_t)y * width + x + 1] : NAN;
            const float d = y + 1 < height ? heights[(size_t)(y + 1) * width + x] : NAN;
            if (!std::isnan(r))
                vertices += std::fabs(lv.below(r) - k);
            if (!std::isnan(d))
                vertices += std::fabs(lv.below(d) - k);
        }
    if (vertices <= TP_CONTOURS_MAX_VERTICES)
        return TP_OK;
    if (o.interval_m > 0.0)
        return fail(err, TP_ERR_INVALID_ARG,
                    "contours: an interval of %g m would draw about %.3g vertices over these "
                    "%dx%d posts (at most %.0f): choose an interval of about %.2g m or more, "
                    "or a smaller area",
                    o.interval_m, vertices, width, height, (double)TP_CONTOURS_MAX_VERTICES,
                    o.interval_m * vertices / TP_CONTOURS_MAX_VERTICES);
    return fail(err, TP_ERR_INVALID_ARG,
                "contours: %zu levels would draw about %.3g vertices over these %dx%d posts (at "
                "most %.0f): choose fewer levels, or a smaller area",
                lv.count(), vertices, width, height, (double)TP_CONTOURS_MAX_VERTICES);
}

/* GDAL's lines at lv over heights (voids given as nodata, a value below lo), read back into xy
 * and lines. */
tp_status run_gdal(const float* heights, size_t height_count, int width, int height,
                   const double* geotransform, float lo, const Levels& lv, size_t min_vertices,
                   std::vector<double>* xy, std::vector<Line>* lines, size_t* dropped,
                   tp_error* err)
{
    tpio::register_drivers();
    tpio::QuietGdal quiet;
    /* voids: a value far below the heights, yet finite, as GDAL's nodata */
    const float nodata = lo - 1e6f;
    std::vector<float> z(heights, heights + height_count);
    for (float& v : z)
        if (std::isnan(v))
            v = nodata;
    tpio::Dataset src = tpio::mem_dataset(z.data(), width, height, geotransform, nullptr);
    if (!src)
        return fail(err, TP_ERR_BACKEND, "contours: cannot make a MEM dataset: %s",
                    tpio::gdal_message().c_str());
    src->GetRasterBand(1)->SetNoDataValue(nodata);
    GDALDriver* memv = GetGDALDriverManager()->GetDriverByName("Memory");
    if (!memv)
        return fail(err, TP_ERR_BACKEND, "contours: GDAL has no Memory vector driver");
    tpio::Dataset dst(memv->Create("", 0, 0, 0, GDT_Unknown, nullptr));
    OGRLayer* layer = dst ? dst->CreateLayer("contours", nullptr, wkbLineString, nullptr) : nullptr;
    if (!layer)
        return fail(err, TP_ERR_BACKEND, "contours: cannot make a Memory layer: %s",
                    tpio::gdal_message().c_str());
    OGRFieldDefn id("id", OFTInteger), elev("elevation_m", OFTReal);
    if (layer->CreateField(&id) != OGRERR_NONE || layer->CreateField(&elev) != OGRERR_NONE)
        return fail(err, TP_ERR_BACKEND, "contours: cannot make the fields: %s",
                    tpio::gdal_message().c_str());
    /* the levels: LEVEL_INTERVAL and LEVEL_BASE, or FIXED_LEVELS (each as %.17g: the same
     * double back) */
    std::string first, second;
    char buf[64];
    if (lv.interval) {
        std::snprintf(buf, sizeof buf, "LEVEL_INTERVAL=%.17g", lv.step);
        first = buf;
        std::snprintf(buf, sizeof buf, "LEVEL_BASE=%.17g", lv.base);
        second = buf;
    } else {
        first = "FIXED_LEVELS=";
        for (size_t i = 0; i < lv.fixed.size(); ++i) {
            std::snprintf(buf, sizeof buf, "%s%.17g", i ? "," : "", lv.fixed[i]);
            first += buf;
        }
    }
    char nd[64];
    std::snprintf(nd, sizeof nd, "NODATA=%.17g", (double)nodata);
    const char* opts[] = {
        first.c_str(), nd, "ID_FIELD=0", "ELEV_FIELD=1", lv.interval ? second.c_str() : nullptr,
        nullptr};
    CPLErr e = GDALContourGenerateEx(GDALGetRasterBand(GDALDataset::ToHandle(src.get()), 1),
                                     OGRLayer::ToHandle(layer), const_cast<char**>(opts), nullptr,
                                     nullptr);
    if (e != CE_None)
        return fail(err, TP_ERR_BACKEND, "contours: GDALContourGenerateEx failed: %s",
                    tpio::gdal_message().c_str());
    layer->ResetReading();
    for (auto& feat : *layer)
        take_geometry(feat->GetGeometryRef(), feat->GetFieldAsDouble(1), min_vertices, xy, lines,
                      dropped);
    return TP_OK;
}

} // namespace

extern "C" tp_contours_options tp_contours_options_default(void)
{
    tp_contours_options o;
    std::memset(&o, 0, sizeof o);
    o.interval_m = 10.0;
    o.min_m = -HUGE_VAL;
    o.max_m = HUGE_VAL;
    o.index_every = 5;
    return o;
}

extern "C" tp_status tp_contours_generate(const float* heights, size_t height_count, int width,
                                          int height, const double geotransform[6],
                                          double interval_m, double base_m, int index_every,
                                          tp_features** out, tp_error* err)
{
    tp_contours_options o = tp_contours_options_default();
    o.interval_m = interval_m;
    o.base_m = base_m;
    o.index_every = index_every;
    return tp_contours_generate_ex(heights, height_count, width, height, geotransform, &o, out,
                                   nullptr, err);
}

extern "C" tp_status tp_contours_generate_ex(const float* heights, size_t height_count, int width,
                                             int height, const double geotransform[6],
                                             const tp_contours_options* options, tp_features** out,
                                             size_t* dropped, tp_error* err)
{
    tp_status s =
        check_arguments(heights, height_count, width, height, geotransform, options, out, err);
    if (s != TP_OK)
        return s;
    const tp_contours_options& o = *options;
    float lo = FLT_MAX, hi = -FLT_MAX;
    for (size_t i = 0; i < height_count; ++i) {
        const float z = heights[i];
        if (std::isnan(z))
            continue;
        if (std::isinf(z))
            return fail(err, TP_ERR_BAD_DATA, "contours: height %zu (x %zu, y %zu) is infinite",
                        i, i % (size_t)width, i / (size_t)width);
        lo = std::min(lo, z);
        hi = std::max(hi, z);
    }
    try {
        Levels lv;
        if ((s = choose_levels(o, lo, hi, &lv, err)) != TP_OK)
            return s;
        if (lo <= hi && (s = check_vertices(heights, width, height, lv, o, err)) != TP_OK)
            return s;
        std::vector<double> xy;
        std::vector<Line> lines;
        size_t gone = 0;
        if (lo <= hi && width > 1 && height > 1 && (lv.interval || !lv.fixed.empty()) &&
            (s = run_gdal(heights, height_count, width, height, geotransform, lo, lv,
                          o.min_vertices, &xy, &lines, &gone, err)) != TP_OK)
            return s;
        tp_features* f = (tp_features*)std::calloc(1, sizeof *f);
        tp_feature* items =
            (tp_feature*)std::malloc(std::max<size_t>(1, lines.size()) * sizeof *items);
        double* v = (double*)std::malloc(std::max<size_t>(1, xy.size()) * sizeof *v);
        if (!f || !items || !v) {
            std::free(f);
            std::free(items);
            std::free(v);
            return fail(err, TP_ERR_OUT_OF_MEMORY, "contours: out of memory for %zu lines",
                        lines.size());
        }
        for (size_t i = 0; i < lines.size(); ++i) {
            const Line& l = lines[i];
            items[i] =
                tp_feature{l.ring ? TP_FEATURE_RING : TP_FEATURE_LINE, l.first, l.count, l.value,
                           is_index(l.value, o, lv) ? 1 : 0,           nullptr};
        }
        if (!xy.empty())
            std::memcpy(v, xy.data(), xy.size() * sizeof *v);
        f->items = items;
        f->count = lines.size();
        f->xy = v;
        f->vertex_count = xy.size() / 2;
        f->strings = nullptr;
        *out = f;
        if (dropped)
            *dropped = gone;
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, "contours");
    }
}

/* ---------------------------------------------------------------------------------------------
 * Writing
 */
namespace {

/* Holds interruption while the temporary folder lives and removes it (with whatever the driver
 * left in it) whatever happens. */
struct TempDir {
    std::string name;
    TempDir() { tp_interrupt_hold(); }
    ~TempDir()
    {
        if (!name.empty()) {
            std::error_code ec;
            fs::remove_all(name, ec);
        }
        tp_interrupt_release();
    }
    TempDir(const TempDir&) = delete;
    TempDir& operator=(const TempDir&) = delete;
};

/* The vector file in memory order: build it with the driver at file (in the temporary folder). */
tp_status build_file(GDALDriver* drv, const std::string& file, const std::string& path,
                     const tp_features* f, const OGRSpatialReference* srs, tp_error* err)
{
    tpio::Dataset ds(drv->Create(file.c_str(), 0, 0, 0, GDT_Unknown, nullptr));
    if (!ds)
        return fail(err, TP_ERR_BACKEND, "%s: %s cannot create the file: %s", path.c_str(),
                    drv->GetDescription(), tpio::gdal_message().c_str());
    const bool csv = !std::strcmp(drv->GetDescription(), "CSV");
    const char* lco[] = {csv ? "GEOMETRY=AS_WKT" : nullptr, nullptr};
    OGRLayer* layer =
        ds->CreateLayer("contours", const_cast<OGRSpatialReference*>(srs), wkbLineString, const_cast<char**>(lco));
    if (!layer)
        return fail(err, TP_ERR_BACKEND, "%s: %s cannot make the contours layer: %s",
                    path.c_str(), drv->GetDescription(), tpio::gdal_message().c_str());
    OGRFieldDefn elev("elevation_m", OFTReal), idx("index", OFTInteger);
    if (layer->CreateField(&elev) != OGRERR_NONE || layer->CreateField(&idx) != OGRERR_NONE)
        return fail(err, TP_ERR_BACKEND, "%s: %s cannot make the fields: %s", path.c_str(),
                    drv->GetDescription(), tpio::gdal_message().c_str());
    const bool tx = layer->TestCapability(OLCTransactions) != 0;
    if (tx && layer->StartTransaction() != OGRERR_NONE)
        return fail(err, TP_ERR_BACKEND, "%s: %s cannot start a transaction: %s", path.c_str(),
                    drv->GetDescription(), tpio::gdal_message().c_str());
    for (size_t i = 0; i < f->count; ++i) {
        const tp_feature& it = f->items[i];
        if (it.kind == TP_FEATURE_POINT || it.count < 2)
            continue;
        if ((i & 1023) == 0 && tp_interrupted())
            return tpio::write_failed(err, path, EINTR);
        OGRFeature feat(layer->GetLayerDefn());
        OGRLineString ls;
        const bool ring = it.kind == TP_FEATURE_RING;
        ls.setNumPoints((int)(it.count + (ring ? 1 : 0)), FALSE);
        for (size_t k = 0; k < it.count; ++k)
            ls.setPoint((int)k, f->xy[2 * (it.first + k)], f->xy[2 * (it.first + k) + 1]);
        if (ring)
            ls.setPoint((int)it.count, f->xy[2 * it.first], f->xy[2 * it.first + 1]);
        feat.SetField(0, it.value);
        feat.SetField(1, it.index);
        feat.SetGeometry(&ls);
        if (layer->CreateFeature(&feat) != OGRERR_NONE)
            return fail(err, TP_ERR_BACKEND, "%s: %s cannot write line %zu: %s", path.c_str(),
                        drv->GetDescription(), i, tpio::gdal_message().c_str());
    }
    if (tx && layer->CommitTransaction() != OGRERR_NONE)
        return fail(err, TP_ERR_BACKEND, "%s: %s cannot commit: %s", path.c_str(),
                    drv->GetDescription(), tpio::gdal_message().c_str());
    CPLErrorReset();
    ds.reset(); /* closed: everything flushed into the temporary folder */
    if (CPLGetLastErrorType() == CE_Failure)
        return fail(err, TP_ERR_BACKEND, "%s: %s cannot finish the file: %s", path.c_str(),
                    drv->GetDescription(), tpio::gdal_message().c_str());
    return TP_OK;
}

/* The file names the driver made in folder tmp (plain files only), sorted. */
std::vector<std::string> files_in(const std::string& tmp)
{
    std::vector<std::string> names;
    if (DIR* d = opendir(tmp.c_str())) {
        while (struct dirent* e = readdir(d))
            if (std::strcmp(e->d_name, ".") && std::strcmp(e->d_name, ".."))
                names.push_back(e->d_name);
        closedir(d);
    }
    std::sort(names.begin(), names.end());
    return names;
}

/* The driver for path's extension (output_format.cpp) and the output check; name and dot of
 * the file name. */
tp_status output_driver(const std::string& path, GDALDriver** drv, std::string* name,
                        size_t* dot, tp_error* err)
{
    const size_t slash = path.rfind('/');
    *name = slash == std::string::npos ? path : path.substr(slash + 1);
    *dot = name->rfind('.');
    const char* const* options;
    tp_status s = tpio::output_driver(path.c_str(), TP_OUTPUT_VECTOR, drv, &options, err);
    return s != TP_OK ? s : tp_output_check(path.c_str(), err);
}

} // namespace

extern "C" tp_status tp_contours_check_output(const char* path, tp_error* err)
{
    if (!path || !*path)
        return fail(err, TP_ERR_INVALID_ARG, "contours: write: NULL or empty path");
    try {
        GDALDriver* drv;
        std::string name;
        size_t dot;
        return output_driver(path, &drv, &name, &dot, err);
    } catch (...) {
        return tpio::caught(err, path);
    }
}

extern "C" tp_status tp_contours_write(const char* path_c, const tp_features* f,
                                       const char* crs_wkt, tp_error* err)
{
    if (!path_c || !*path_c || !f)
        return fail(err, TP_ERR_INVALID_ARG, "contours: write: NULL or empty path, or NULL set");
    try {
        const std::string path = path_c;
        GDALDriver* drv;
        std::string name;
        size_t dot;
        tp_status s = output_driver(path, &drv, &name, &dot, err);
        if (s != TP_OK)
            return s;
        tpio::QuietGdal quiet;
        OGRSpatialReference srs;
        const bool has_crs = crs_wkt && *crs_wkt;
        if (has_crs) {
            if (srs.SetFromUserInput(crs_wkt) != OGRERR_NONE)
                return fail(err, TP_ERR_BAD_DATA, "%s: GDAL cannot read the CRS: %s", path_c,
                            tpio::gdal_message().c_str());
            srs.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        }
        TempDir tmp;
        int e = tpio::make_temp_dir(path, &tmp.name);
        if (e)
            return tpio::write_failed(err, path, e);
        s = build_file(drv, tmp.name + "/" + name, path, f, has_crs ? &srs : nullptr, err);
        if (s != TP_OK)
            return s;
        /* every file the driver made, all or none, with an older Shapefile's sidecars the new
         * one may lack */
        const std::vector<std::string> names = files_in(tmp.name);
        if (names.empty())
            return fail(err, TP_ERR_BACKEND, "%s: the OGR driver wrote no file", path_c);
        const std::string dir = path.substr(0, path.size() - name.size());
        tp_file_set* set = nullptr;
        s = tp_file_set_begin(&set, err);
        for (size_t i = 0; s == TP_OK && i < names.size(); ++i)
            s = tpio::file_set_adopt(set, tmp.name + "/" + names[i], dir + names[i], err);
        if (s == TP_OK && !std::strcmp(drv->GetDescription(), "ESRI Shapefile")) {
            const std::string stem = name.substr(0, dot);
            for (const char* x : {".shp", ".shx", ".dbf", ".prj", ".cpg", ".qix", ".sbn", ".sbx",
                                  ".SHP", ".SHX", ".DBF", ".PRJ", ".CPG", ".QIX", ".SBN", ".SBX"})
                if (s == TP_OK && std::find(names.begin(), names.end(), stem + x) == names.end())
                    s = tp_file_set_remove(set, (dir + stem + x).c_str(), err);
        }
        if (s != TP_OK) {
            tp_file_set_abort(set);
            return s;
        }
        return tp_file_set_commit(set, err);
    } catch (...) {
        return tpio::caught(err, path_c);
    }
}
