/*
 * crs.cpp - CRS helpers over OGR shared by the io/ files (crs.hpp), and tp_crs_describe.
 */
#include "crs.hpp"

#include "io_util.hpp"
#include "tp_geo.h"
#include "tp_io.h"

#include <cpl_conv.h>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>

namespace tpio {

bool crs_present(const OGRSpatialReference* srs)
{
    return srs && !srs->IsEmpty();
}

std::string crs_wkt2(const OGRSpatialReference& srs)
{
    char* text = nullptr;
    const char* const options[] = {"FORMAT=WKT2", nullptr};
    std::string wkt;
    if (srs.exportToWkt(&text, options) == OGRERR_NONE && text)
        wkt = text;
    CPLFree(text);
    return wkt;
}

static int authority_epsg(const OGRSpatialReference& srs)
{
    const char* auth = srs.GetAuthorityName(nullptr);
    const char* code = srs.GetAuthorityCode(nullptr);
    return auth && code && EQUAL(auth, "EPSG") ? std::atoi(code) : 0;
}

int crs_epsg(const OGRSpatialReference& srs, bool identify)
{
    int epsg = authority_epsg(srs);
    if (epsg || !identify)
        return epsg;
    /* on a copy: AutoIdentifyEPSG modifies its object */
    OGRSpatialReference copy(srs);
    return copy.AutoIdentifyEPSG() == OGRERR_NONE ? authority_epsg(copy) : 0;
}

OGRSpatialReference crs_wgs84()
{
    OGRSpatialReference wgs84;
    wgs84.SetWellKnownGeogCS("WGS84");
    wgs84.SetAxisMappingStrategy(OAMS_TRADITIONAL_GIS_ORDER);
    return wgs84;
}

bool crs_on_wgs84(const OGRSpatialReference& srs)
{
    const OGRSpatialReference wgs84 = crs_wgs84();
    const char* const options[] = {"IGNORE_DATA_AXIS_TO_SRS_AXIS_MAPPING=YES",
                                   "CRITERION=EQUIVALENT_EXCEPT_AXIS_ORDER_GEOGCRS", nullptr};
    OGRSpatialReference* geog = srs.CloneGeogCS();
    bool same = geog && geog->IsSame(&wgs84, options);
    OGRSpatialReference::DestroySpatialReference(geog);
    return same;
}

int crs_utmups_zone(const OGRSpatialReference& srs, int* northp)
{
    int north = 0, zone = srs.GetUTMZone(&north);
    if (zone > 0) {
        *northp = north ? 1 : 0;
        return zone;
    }
    int epsg = authority_epsg(srs);
    *northp = epsg == 32661;
    return epsg == 32661 || epsg == 32761 ? TP_ZONE_UPS : -1;
}

int utmups_epsg(int zone, bool northp)
{
    if (zone == TP_ZONE_UPS)
        return northp ? 32661 : 32761;
    return (northp ? 32600 : 32700) + zone;
}

} // namespace tpio

extern "C" tp_status tp_crs_describe(const char* crs, tp_crs_info* out, tp_error* err)
{
    if (!crs || !out)
        return tpio::fail(err, TP_ERR_INVALID_ARG, "tp_crs_describe: crs and out must not be NULL");
    try {
        tp_crs_info info{};
        info.utm_zone = -1;
        if (*crs) {
            OGRSpatialReference srs;
            if (srs.SetFromUserInput(crs) != OGRERR_NONE)
                return tpio::fail(err, TP_ERR_BAD_DATA, "CRS '%.80s%s' is not one GDAL/PROJ reads",
                                  crs, std::strlen(crs) > 80 ? "..." : "");
            const char* name = srs.GetName();
            std::snprintf(info.name, sizeof info.name, "%s", name ? name : "");
            info.epsg = tpio::crs_epsg(srs, true);
            info.geographic = srs.IsGeographic() ? 1 : 0;
            info.utm_zone = tpio::crs_utmups_zone(srs, &info.northp);
        }
        *out = info;
        return TP_OK;
    } catch (...) {
        return tpio::caught(err, "tp_crs_describe");
    }
}
