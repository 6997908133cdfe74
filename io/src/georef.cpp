/*
 * georef.cpp - tp_georef: grid <-> render CRS <-> WGS84, exact both ways where it can be.
 *
 * WGS84 UTM/UPS render CRSs (every warped DEM, and UTM DEMs on WGS84) use GeographicLib's
 * UTMUPS in the scene's zone. Anything else goes through PROJ (the C API, for the accuracy of
 * the operation it picks: GDAL's OGRCoordinateTransformation does not report it).
 */
#include "crs.hpp"
#include "gdal_util.hpp"
#include "tp_io.h"

#include <GeographicLib/UTMUPS.hpp>
#include <proj.h>

#include <cassert>
#include <cmath>
#include <exception>
#include <memory>
#include <string>

struct tp_georef {
    double gt[6];
    int has_geo = 0;
    int utm = 0; /* use GeographicLib with this zone */
    int zone = 0, northp = 0;
    PJ_CONTEXT* ctx = nullptr;
    PJ* op = nullptr; /* render CRS -> WGS84 (lat, lon order normalised to lon, lat) */
    double accuracy = 0;
    std::string note;
};

namespace {

using tpio::fail;

struct GeorefDeleter {
    void operator()(tp_georef* g) const
    {
        tp_georef_destroy(g);
    }
};

tp_status create(const char* wkt, const double gt[6], tp_georef** out, tp_error* err)
{
    /* freed on every early return and exception; released to *out on success */
    std::unique_ptr<tp_georef, GeorefDeleter> g(new tp_georef());
    std::memcpy(g->gt, gt, sizeof g->gt);
    if (!wkt || !*wkt) {
        g->note = "no CRS (local metres)";
        *out = g.release();
        return TP_OK;
    }
    OGRSpatialReference srs;
    if (srs.importFromWkt(wkt) != OGRERR_NONE) {
        return fail(err, TP_ERR_BAD_DATA, "georeference: unreadable CRS");
    }
    g->has_geo = 1;
    int north = 0, zone = tpio::crs_utmups_zone(srs, &north);
    if (zone >= 0 && tpio::crs_on_wgs84(srs)) {
        g->utm = 1;
        g->zone = zone;
        g->northp = north;
        g->note = "exact (WGS 84, GeographicLib UTMUPS)";
        *out = g.release();
        return TP_OK;
    }

    /* PROJ: the best operation from the render CRS to WGS84 available here. */
    g->ctx = proj_context_create();
    PJ* src = proj_create(g->ctx, wkt);
    PJ* dst = proj_create(g->ctx, "EPSG:4326");
    PJ_OPERATION_FACTORY_CONTEXT* fc = src && dst ? proj_create_operation_factory_context(g->ctx, nullptr) : nullptr;
    PJ_OBJ_LIST* ops = nullptr;
    if (fc) {
        proj_operation_factory_context_set_grid_availability_use(
            g->ctx, fc, PROJ_GRID_AVAILABILITY_DISCARD_OPERATION_IF_MISSING_GRID);
        proj_operation_factory_context_set_spatial_criterion(
            g->ctx, fc, PROJ_SPATIAL_CRITERION_PARTIAL_INTERSECTION);
        ops = proj_create_operations(g->ctx, src, dst, fc);
    }
    PJ* op = ops && proj_list_get_count(ops) > 0 ? proj_list_get(g->ctx, ops, 0) : nullptr;
    if (op) {
        g->accuracy = proj_coordoperation_get_accuracy(g->ctx, op);
        if (proj_coordoperation_has_ballpark_transformation(g->ctx, op))
            g->accuracy = -1;
        const char* name = proj_get_name(op);
        g->note = name ? name : "PROJ operation";
        g->op = proj_normalize_for_visualization(g->ctx, op); /* lon, lat order */
        proj_destroy(op);
    }
    proj_list_destroy(ops);
    proj_operation_factory_context_destroy(fc);
    proj_destroy(src);
    proj_destroy(dst);
    if (!g->op)
        return fail(err, TP_ERR_BACKEND, "georeference: PROJ has no operation to WGS84: %s",
                    proj_context_errno_string(g->ctx, proj_context_errno(g->ctx)));
    *out = g.release();
    return TP_OK;
}

} // namespace

extern "C" tp_status tp_georef_create(const char* crs_wkt, const double geotransform[6],
                                      tp_georef** out, tp_error* err)
{
    if (!geotransform || !out)
        return fail(err, TP_ERR_INVALID_ARG, "georeference: geotransform and out must not be NULL");
    try {
        return create(crs_wkt, geotransform, out, err);
    } catch (...) {
        return tpio::caught(err, "georeference");
    }
}

extern "C" void tp_georef_destroy(tp_georef* g)
{
    if (!g)
        return;
    proj_destroy(g->op);
    if (g->ctx)
        proj_context_destroy(g->ctx);
    delete g;
}

/* The accessors and the grid <-> CRS arithmetic below return no status: a NULL is a caller bug
 * (assert), and they call nothing that throws. */
extern "C" int tp_georef_has_geo(const tp_georef* g)
{
    assert(g);
    return g->has_geo;
}

extern "C" void tp_georef_grid_to_proj(const tp_georef* g, double x, double y, double* e, double* n)
{
    assert(g && e && n);
    *e = g->gt[0] + (x + 0.5) * g->gt[1];
    *n = g->gt[3] + (y + 0.5) * g->gt[5];
}

extern "C" void tp_georef_proj_to_grid(const tp_georef* g, double e, double n, double* x, double* y)
{
    assert(g && x && y);
    *x = (e - g->gt[0]) / g->gt[1] - 0.5;
    *y = (n - g->gt[3]) / g->gt[5] - 0.5;
}

/* Inside a catch (...) of the conversions: GeographicLib throws GeographicErr for coordinates
 * outside UTMUPS's range, a point that cannot be converted; anything else is a failure. */
static tp_status conversion_failed(tp_error* err, const char* what)
{
    try {
        throw;
    } catch (const GeographicLib::GeographicErr& e) {
        return fail(err, TP_ERR_INVALID_ARG, "%s: %s", what, e.what());
    } catch (...) {
        return tpio::caught(err, what);
    }
}

extern "C" tp_status tp_georef_proj_to_geo(const tp_georef* g, double e, double n, double* lat,
                                           double* lon, tp_error* err)
{
    if (!g || !lat || !lon)
        return fail(err, TP_ERR_INVALID_ARG, "tp_georef_proj_to_geo: expected non-NULL pointers");
    if (!g->has_geo)
        return fail(err, TP_ERR_INVALID_ARG, "no CRS: positions have no latitude and longitude");
    if (!std::isfinite(e) || !std::isfinite(n))
        return fail(err, TP_ERR_INVALID_ARG, "E %g, N %g: not a position", e, n);
    try {
        if (g->utm) {
            double la, lo;
            GeographicLib::UTMUPS::Reverse(g->zone, g->northp != 0, e, n, la, lo, false);
            *lat = la;
            *lon = lo;
            return TP_OK;
        }
        PJ_COORD c = proj_coord(e, n, 0, 0);
        c = proj_trans(g->op, PJ_FWD, c);
        if (!std::isfinite(c.lp.lam) || !std::isfinite(c.lp.phi))
            return fail(err, TP_ERR_INVALID_ARG, "E %.3f N %.3f has no WGS84 position", e, n);
        *lon = c.xy.x;
        *lat = c.xy.y;
        return TP_OK;
    } catch (...) {
        return conversion_failed(err, CPLSPrintf("E %.3f N %.3f", e, n));
    }
}

extern "C" tp_status tp_georef_geo_to_proj(const tp_georef* g, double lat, double lon, double* e,
                                           double* n, tp_error* err)
{
    if (!g || !e || !n)
        return fail(err, TP_ERR_INVALID_ARG, "tp_georef_geo_to_proj: expected non-NULL pointers");
    if (!g->has_geo)
        return fail(err, TP_ERR_INVALID_ARG, "no CRS: positions have no latitude and longitude");
    if (!(std::fabs(lat) <= 90) || !std::isfinite(lon))
        return fail(err, TP_ERR_INVALID_ARG, "latitude %g, longitude %g: not a position", lat, lon);
    try {
        if (g->utm) {
            int zone;
            bool northp;
            double x, y;
            /* setzone = the scene's zone, mgrslimits off: points outside the standard zone
             * still get coordinates in the zone the scene is drawn in. */
            GeographicLib::UTMUPS::Forward(lat, lon, zone, northp, x, y, g->zone, false);
            if ((int)northp != g->northp) /* the other hemisphere of the same zone */
                y += northp ? -GeographicLib::UTMUPS::UTMShift() : GeographicLib::UTMUPS::UTMShift();
            *e = x;
            *n = y;
            return TP_OK;
        }
        PJ_COORD c = proj_coord(lon, lat, 0, 0);
        c = proj_trans(g->op, PJ_INV, c);
        if (!std::isfinite(c.xy.x) || !std::isfinite(c.xy.y))
            return fail(err, TP_ERR_INVALID_ARG, "latitude %g, longitude %g has no position in the "
                        "render CRS", lat, lon);
        *e = c.xy.x;
        *n = c.xy.y;
        return TP_OK;
    } catch (...) {
        return conversion_failed(err, CPLSPrintf("latitude %g, longitude %g", lat, lon));
    }
}

extern "C" double tp_georef_datum_accuracy_m(const tp_georef* g)
{
    assert(g);
    return g->utm || !g->has_geo ? 0 : g->accuracy;
}

extern "C" const char* tp_georef_datum_note(const tp_georef* g)
{
    assert(g);
    return g->note.c_str();
}
