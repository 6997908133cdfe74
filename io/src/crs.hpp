/* crs.hpp - the questions io/ asks about a CRS, answered through OGR in one place (crs.cpp).
 * Private to io/. */
#pragma once

#include <ogr_spatialref.h>

#include <string>

namespace tpio {

/* True when srs is set and not empty (GDAL gives an empty one for rasters without a CRS). */
bool crs_present(const OGRSpatialReference* srs);

/* WKT2 text of srs; "" if OGR cannot write it. */
std::string crs_wkt2(const OGRSpatialReference& srs);

/* The EPSG code srs carries as its authority, else 0. With identify, a CRS without one is also
 * matched by OGR against the common ones (UTM zones, WGS84, ...: AutoIdentifyEPSG). */
int crs_epsg(const OGRSpatialReference& srs, bool identify = false);

/* WGS84 geographic, in (longitude, latitude) order. */
OGRSpatialReference crs_wgs84();

/* True when the datum (geographic CRS) of srs is WGS84, axis order aside. */
bool crs_on_wgs84(const OGRSpatialReference& srs);

/* The zone of a UTM or UPS CRS: 1..60 for a UTM zone (any datum), TP_ZONE_UPS (0) for WGS84
 * UPS (EPSG:32661 north, EPSG:32761 south), -1 for anything else. *northp gets the
 * hemisphere (1 north; 0 south or none). */
int crs_utmups_zone(const OGRSpatialReference& srs, int* northp);

/* The EPSG code of the WGS84 UTM zone (1..60) or UPS (zone TP_ZONE_UPS) of hemisphere northp:
 * 326zz / 327zz, 32661 / 32761. */
int utmups_epsg(int zone, bool northp);

} // namespace tpio
