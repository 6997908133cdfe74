/*
 * vector_read.cpp - tp_vector_read (tp_vector.h): any vector file OGR opens, every layer,
 * reprojected into the render CRS and flattened into points, lines and rings.
 */
#include "gdal_util.hpp"
#include "tp_io.h"
#include "tp_vector.h"

#include <ogr_geometry.h>
#include <ogrsf_frmts.h>

#include <cassert>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

namespace {

using tpio::fail;

struct TransformDeleter {
    void operator()(OGRCoordinateTransformation* ct) const
    {
        OGRCoordinateTransformation::DestroyCT(ct);
    }
};
using Transform = std::unique_ptr<OGRCoordinateTransformation, TransformDeleter>;

/* What the features become before they are copied into the malloc'd set. */
struct Collected {
    std::vector<tp_feature> items;
    std::vector<double> xy;
    std::vector<size_t> name_at; /* offset into names + 1 per item, 0 for none */
    std::string names;
};

/* Where a failure is: the message's prefix after the file. */
struct Where {
    const char* path;
    const char* layer;
    GIntBig fid;
};

/* Formats whose coordinates are WGS84 longitude/latitude by their specification. */
bool wgs84_by_definition(const char* driver)
{
    static const char* const names[] = {"GPX", "KML", "LIBKML", "GeoJSON", "GeoJSONSeq"};
    for (const char* n : names)
        if (!std::strcmp(driver, n))
            return true;
    return false;
}

/* Reprojects n points (xs, ys) into the collected set as one feature of kind. */
tp_status add_part(Collected& c, tp_feature_kind kind, std::vector<double>& xs,
                   std::vector<double>& ys, OGRCoordinateTransformation* ct, const char* name,
                   const Where& w, tp_error* err)
{
    size_t n = xs.size();
    if (kind == TP_FEATURE_RING && n >= 2 && xs[0] == xs[n - 1] && ys[0] == ys[n - 1])
        --n; /* the closing vertex */
    size_t need = kind == TP_FEATURE_POINT ? 1 : kind == TP_FEATURE_LINE ? 2 : 3;
    if (n < need)
        return TP_OK; /* a degenerate part: nothing to draw or measure */
    std::vector<double> x0(xs.begin(), xs.begin() + n), y0(ys.begin(), ys.begin() + n);
    std::vector<int> ok(n, 0);
    int all = ct->Transform((int)n, xs.data(), ys.data(), nullptr, ok.data());
    for (size_t i = 0; i < n; ++i)
        if (!all || !ok[i] || !std::isfinite(xs[i]) || !std::isfinite(ys[i]))
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: layer '%s', feature %lld: the coordinates (%.8g, %.8g) do not "
                        "transform into the DEM's CRS (outside the area where it is defined?)",
                        w.path, w.layer, (long long)w.fid, x0[i], y0[i]);
    tp_feature f;
    f.kind = kind;
    f.first = c.xy.size() / 2;
    f.count = n;
    f.value = NAN;
    f.index = 0;
    f.name = nullptr;
    for (size_t i = 0; i < n; ++i) {
        c.xy.push_back(xs[i]);
        c.xy.push_back(ys[i]);
    }
    if (name && *name) {
        c.name_at.push_back(c.names.size() + 1);
        c.names.append(name);
        c.names.push_back('\0');
    } else {
        c.name_at.push_back(0);
    }
    c.items.push_back(f);
    return TP_OK;
}

tp_status add_curve(Collected& c, tp_feature_kind kind, const OGRSimpleCurve* curve,
                    OGRCoordinateTransformation* ct, const char* name, const Where& w,
                    tp_error* err)
{
    std::vector<double> xs, ys;
    int n = curve->getNumPoints();
    xs.reserve(n);
    ys.reserve(n);
    for (int i = 0; i < n; ++i) {
        xs.push_back(curve->getX(i));
        ys.push_back(curve->getY(i));
    }
    return add_part(c, kind, xs, ys, ct, name, w, err);
}

/* Flattens g (linear: no curves) into c. */
tp_status add_geometry(Collected& c, const OGRGeometry* g, OGRCoordinateTransformation* ct,
                       const char* name, const Where& w, tp_error* err)
{
    if (!g || g->IsEmpty())
        return TP_OK;
    switch (wkbFlatten(g->getGeometryType())) {
    case wkbPoint: {
        const OGRPoint* p = g->toPoint();
        std::vector<double> xs{p->getX()}, ys{p->getY()};
        return add_part(c, TP_FEATURE_POINT, xs, ys, ct, name, w, err);
    }
    case wkbLineString:
    case wkbLinearRing:
        return add_curve(c, TP_FEATURE_LINE, g->toSimpleCurve(), ct, name, w, err);
    case wkbPolygon:
    case wkbTriangle: {
        const OGRPolygon* p = g->toPolygon();
        for (const OGRLinearRing* r : *p) {
            tp_status s = add_curve(c, TP_FEATURE_RING, r, ct, name, w, err);
            if (s != TP_OK)
                return s;
        }
        return TP_OK;
    }
    case wkbMultiPoint:
    case wkbMultiLineString:
    case wkbMultiPolygon:
    case wkbGeometryCollection:
    case wkbPolyhedralSurface:
    case wkbTIN: {
        const OGRGeometryCollection* gc =
            OGR_GT_IsSubClassOf(g->getGeometryType(), wkbGeometryCollection)
                ? g->toGeometryCollection()
                : nullptr;
        if (!gc) { /* polyhedral surfaces and TINs: their polygons */
            const OGRPolyhedralSurface* ps = g->toPolyhedralSurface();
            for (const OGRPolygon* p : *ps) {
                tp_status s = add_geometry(c, p, ct, name, w, err);
                if (s != TP_OK)
                    return s;
            }
            return TP_OK;
        }
        for (const OGRGeometry* part : *gc) {
            tp_status s = add_geometry(c, part, ct, name, w, err);
            if (s != TP_OK)
                return s;
        }
        return TP_OK;
    }
    default:
        if (g->hasCurveGeometry()) {
            std::unique_ptr<OGRGeometry> lin(g->getLinearGeometry());
            if (lin && !lin->hasCurveGeometry())
                return add_geometry(c, lin.get(), ct, name, w, err);
        }
        return TP_OK; /* a type we cannot draw: skipped */
    }
}

tp_status read(const char* path, const char* target_wkt, tp_features** out, tp_error* err)
{
    tpio::register_drivers();
    tpio::QuietGdal quiet;
    if (!target_wkt || !*target_wkt)
        return fail(err, TP_ERR_INVALID_ARG,
                    "%s: the DEM has no CRS, so the file's features cannot be placed on it",
                    path);
    OGRSpatialReference dst;
    if (dst.importFromWkt(target_wkt) != OGRERR_NONE)
        return fail(err, TP_ERR_INVALID_ARG, "%s: the DEM's CRS is unreadable (%s)", path,
                    tpio::gdal_message().c_str());
    dst.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);

    VSIStatBufL st;
    if (VSIStatL(path, &st) != 0)
        return fail(err, TP_ERR_IO, "%s: no such file", path);
    tpio::Dataset ds(GDALDataset::Open(path, GDAL_OF_VECTOR | GDAL_OF_READONLY));
    if (!ds)
        return fail(err, TP_ERR_IO, "%s: OGR cannot open it as a vector file (%s)", path,
                    CPLGetLastErrorMsg()[0] ? CPLGetLastErrorMsg()
                                            : "not a format OGR reads, or damaged");
    const char* driver = ds->GetDriver() ? ds->GetDriver()->GetDescription() : "";
    const bool gpx = !std::strcmp(driver, "GPX");

    Collected c;
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    for (OGRLayer* layer : ds->GetLayers()) {
        const char* lname = layer->GetName();
        if (gpx && (!std::strcmp(lname, "route_points") || !std::strcmp(lname, "track_points")))
            continue;
        const OGRSpatialReference* lsrs = layer->GetSpatialRef();
        OGRSpatialReference src;
        if (lsrs && !lsrs->IsEmpty()) {
            src = *lsrs;
        } else if (wgs84_by_definition(driver)) {
            src = wgs84;
        } else {
            if (layer->GetFeatureCount(FALSE) == 0)
                continue; /* nothing to place */
            return fail(err, TP_ERR_BAD_DATA,
                        "%s: layer '%s' has no CRS (a %s file needs one: a Shapefile its .prj)",
                        path, lname, driver);
        }
        src.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
        Transform ct(OGRCreateCoordinateTransformation(&src, &dst));
        if (!ct)
            return fail(err, TP_ERR_BACKEND,
                        "%s: layer '%s': no transformation from its CRS (%s) to the DEM's (%s)",
                        path, lname, src.GetName() ? src.GetName() : "?",
                        tpio::gdal_message().c_str());
        const int name_field = layer->GetLayerDefn()->GetFieldIndex("name");
        layer->ResetReading();
        for (auto& feature : *layer) {
            const char* name = nullptr;
            if (name_field >= 0 && feature->IsFieldSetAndNotNull(name_field))
                name = feature->GetFieldAsString(name_field);
            Where w{path, lname, feature->GetFID()};
            tp_status s = add_geometry(c, feature->GetGeometryRef(), ct.get(), name, w, err);
            if (s != TP_OK)
                return s;
        }
    }
    if (c.items.empty())
        return fail(err, TP_ERR_BAD_DATA,
                    "%s: no features (no point, line or polygon in any layer: an empty file?)",
                    path);

    /* the set, in malloc'd arrays (tp_features_destroy frees them) */
    tp_features* f = (tp_features*)std::calloc(1, sizeof *f);
    tp_feature* items = (tp_feature*)std::malloc(c.items.size() * sizeof *items);
    double* xy = (double*)std::malloc(c.xy.size() * sizeof *xy);
    char* strings = (char*)std::malloc(c.names.size() + 1);
    if (!f || !items || !xy || !strings) {
        std::free(f);
        std::free(items);
        std::free(xy);
        std::free(strings);
        return fail(err, TP_ERR_OUT_OF_MEMORY, "%s: out of memory for %zu features", path,
                    c.items.size());
    }
    std::memcpy(items, c.items.data(), c.items.size() * sizeof *items);
    std::memcpy(xy, c.xy.data(), c.xy.size() * sizeof *xy);
    std::memcpy(strings, c.names.c_str(), c.names.size() + 1);
    for (size_t i = 0; i < c.items.size(); ++i)
        items[i].name = c.name_at[i] ? strings + c.name_at[i] - 1 : nullptr;
    f->items = items;
    f->count = c.items.size();
    f->xy = xy;
    f->vertex_count = c.xy.size() / 2;
    f->strings = strings;
    *out = f;
    return TP_OK;
}

} // namespace

extern "C" tp_status tp_vector_read(const char* path, const char* target_crs_wkt,
                                    tp_features** out, tp_error* err)
{
    assert(path && out);
    /* a FIFO or a device would block OGR's open, or never end */
    if (tp_status s = tp_input_check(path, "a vector (GeoJSON, GPX, KML, GeoPackage, ...)", 1, err))
        return s;
    try {
        return read(path, target_crs_wkt, out, err);
    } catch (...) {
        return tpio::caught(err, path);
    }
}
