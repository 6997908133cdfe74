/*
 * tp_geo.h - terrapatch coordinate conversions behind plain C: geographic <-> UTM/UPS (and the
 * text of a zone), MGRS, Earth-centred (ECEF) coordinates, the exact transverse Mercator
 * projection, the inverse geodesic problem, all on the WGS84 ellipsoid, and angles as degrees,
 * minutes and seconds.
 *
 * C11 header; the C++17 implementation (io/src/geo.cpp) is a thin shim over GeographicLib
 * (C. F. F. Karney, "Transverse Mercator with an accuracy of a few nanometers", J. Geodesy 85,
 * 2011; "Algorithms for geodesics", J. Geodesy 87, 2013). No GeographicLib type appears here.
 *
 * Units: angles in degrees, lengths in metres, at every function.
 *
 * Axis order: LATITUDE FIRST, then longitude, in every signature and every output. This departs
 * from STYLE.md section 6 ("always (lon, lat)") on purpose: these functions mirror GeographicLib,
 * GeoConvert, GeodSolve and PROJ's geodesic.h (geod_inverse(g, lat1, lon1, lat2, lon2, ...)),
 * whose text formats `terrapatch coord` reads and writes, so keeping their order avoids a swap
 * at every call. Parameter names carry the axis and the unit (lat_deg, lon_deg, easting_m).
 * Projected coordinates are (easting, northing), x first.
 *
 * Ranges accepted everywhere: latitude in [-90, 90], longitude in [-540, 540] (reduced to
 * [-180, 180] inside; GeographicLib 1.x's historical limit, wide enough for 0..360 data and
 * for longitude differences), heights and projected coordinates any finite value the
 * conversion allows. NaN and infinity are rejected.
 *
 * Errors: every function returns TP_OK or a tp_status and, if err is not NULL, a one-line
 * message (for example "latitude 91 is outside [-90, 90]"). Out-of-range or malformed input
 * is TP_ERR_INVALID_ARG, with GeographicLib's own explanation where it detected the problem;
 * an unexpected C++ failure is TP_ERR_BACKEND (TP_ERR_OUT_OF_MEMORY for std::bad_alloc). No
 * exception ever reaches the caller. On failure no output parameter is written. A NULL
 * pointer where an output is required is TP_ERR_INVALID_ARG; optional outputs say so.
 *
 * All functions are thread-safe (they keep no mutable state).
 */
#ifndef TP_GEO_H
#define TP_GEO_H

#include <stddef.h>

#include "tp_core.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Zone number meaning UPS (Universal Polar Stereographic) instead of a UTM zone 1..60. */
#define TP_ZONE_UPS 0

/* Bytes that always hold an MGRS string at the highest precision plus its NUL: "60XYZ" and
 * 2 x 11 digits are 27 characters. */
#define TP_MGRS_SIZE 32

/* ---------------------------------------------------------------------------------------------
 * Geographic positions
 */

/* Checks a geographic position (lat_deg in [-90, 90], lon_deg in [-540, 540], both finite)
 * and writes it back with the longitude reduced to [-180, 180] (GeographicLib's
 * Math::AngNormalize, exact: 180 stays 180, -180 stays -180, 540 is 180, 360 is 0). */
tp_status tp_geo_normalize(double lat_deg, double lon_deg, double* lat_out_deg, double* lon_out_deg,
                           tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Degrees, minutes and seconds (GeographicLib's DMS class, as GeoConvert reads and writes them)
 */

/* Reads a latitude and a longitude, each in any form GeographicLib's DMS::Decode accepts:
 * decimal degrees ("40.446", "-79.98"), degrees-minutes-seconds with d, ', " or the Unicode
 * degree, prime and double-prime signs ("40d26'46\"N", "40°26′46″"), colon-separated
 * ("40:26:46N", "-79:58:56"), a hemisphere letter N, S, E or W before or after the number
 * instead of a sign ("N40d26'46\"", "79d58'56\"W"). Without hemisphere letters `a` is the
 * latitude and `b` the longitude; with them either order works ("79:58:56W 40:26:46N"), as in
 * GeographicLib's DMS::DecodeLatLon (longfirst false). Writes *lat_deg in [-90, 90] and
 * *lon_deg as given (within [-540, 540]; reduce it with tp_geo_normalize). Each string is at
 * most 64 bytes. TP_ERR_INVALID_ARG with GeographicLib's reason ("Both 40N and 41N interpreted
 * as latitudes", "Illegal character g in DMS string garbage") for anything else, NaN and
 * infinities included. */
tp_status tp_dms_decode_latlon(const char* a, const char* b, double* lat_deg, double* lon_deg,
                               tp_error* err);

/* What tp_dms_encode writes after the angle. */
typedef enum tp_dms_kind {
    TP_DMS_PLAIN = 0,  /* signed, no hemisphere letter: "-79d58'56\"" */
    TP_DMS_LATITUDE,   /* no sign, 2-digit degrees, N or S after: "40d26'46\"N" */
    TP_DMS_LONGITUDE   /* no sign, 3-digit degrees, E or W after: "079d58'56\"W" */
} tp_dms_kind;

/* Bytes that always hold an angle written by tp_dms_encode (with up to 9 decimals of a
 * second), NUL included. */
#define TP_DMS_TEXT_SIZE 40

/* Writes angle_deg (finite; a latitude within [-90, 90]) as degrees, minutes and seconds with
 * seconds_decimals decimals (0..9), rounded, into out (out_size >= TP_DMS_TEXT_SIZE), as
 * GeoConvert -d writes it (GeographicLib's DMS::Encode with trailing component SECOND):
 * 40.446111 at 1 decimal is "40d26'46.0\"N" as TP_DMS_LATITUDE. TP_ERR_INVALID_ARG for a
 * non-finite angle, a latitude out of range, decimals out of range or a short buffer (out
 * untouched). */
tp_status tp_dms_encode(double angle_deg, tp_dms_kind kind, int seconds_decimals, char* out,
                        size_t out_size, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * UTM / UPS
 */

/* Geographic (lat_deg, lon_deg) to UTM/UPS in the standard zone: UTM zones 1..60 from 80S
 * (inclusive) to 84N (exclusive), with the Norway 32V and Svalbard 31X..37X exceptions, and
 * UPS (*zone = TP_ZONE_UPS) poleward of them. Writes the zone, the hemisphere (*northp: 1
 * north, 0 south; the hemisphere of the point by the sign bit of lat_deg, so -0.0 is south,
 * with northing 10000 km, as GeographicLib and GeoConvert have it) and
 * (*easting_m, *northing_m) with the usual false easting and northing (UTM: 500 km, 0 or
 * 10000 km; UPS: 2000 km, 2000 km). Accurate to about 5 nm (GeographicLib UTMUPS::Forward). */
tp_status tp_geo_to_utmups(double lat_deg, double lon_deg, int* zone, int* northp,
                           double* easting_m, double* northing_m, tp_error* err);

/* UTM/UPS (zone 1..60, or TP_ZONE_UPS; northp 1 north, 0 south; easting, northing in metres)
 * to geographic (*lat_deg, *lon_deg); the longitude is in [-180, 180). Any zone is accepted,
 * not only the standard one for the point. Easting and northing must lie in GeographicLib's
 * UTMUPS ranges (UTM easting [0, 1000] km; northing [-9100, 9600] km north, [900, 19600] km
 * south; UPS [1200, 2800] km north, [700, 3300] km south); otherwise TP_ERR_INVALID_ARG. */
tp_status tp_geo_from_utmups(int zone, int northp, double easting_m, double northing_m,
                             double* lat_deg, double* lon_deg, tp_error* err);

/* UTM/UPS coordinates (zone, northp, easting_m, northing_m) in the standard zone of the point
 * they name (as tp_geo_to_utmups chooses it). Coordinates already in that zone are written
 * back exactly as given, not through latitude and longitude (which would move them by
 * nanometres, enough to change a truncated MGRS digit). On the equator either hemisphere is
 * standard, as in GeographicLib's GeoCoords: 4s E 10000000 stays south (GeoConvert keeps it
 * so), and 4n E 0 north. Errors as tp_geo_from_utmups; outputs are written only on success. */
tp_status tp_utmups_to_standard(int zone, int northp, double easting_m, double northing_m,
                                int* std_zone, int* std_northp, double* std_easting_m,
                                double* std_northing_m, tp_error* err);

/* How tp_zone_format writes a zone. Each is the text one program already shows, kept as is. */
typedef enum tp_zone_style {
    TP_ZONE_STYLE_DEFAULT = 0, /* = TP_ZONE_STYLE_SHORT */
    TP_ZONE_STYLE_SHORT,       /* "31n", "4s", "UPS n", "UPS s" (mesh field data "utm_zone") */
    TP_ZONE_STYLE_GEOCONVERT,  /* "31n", "04s", "n", "s" (GeoConvert -u, `terrapatch coord`) */
    TP_ZONE_STYLE_UPPER,       /* "31N", "4S", "UPS N", "UPS S" (the viewer's overlay) */
    TP_ZONE_STYLE_LONG         /* "31n", "4s", "UPS north", "UPS south" (`terrapatch info`) */
} tp_zone_style;

/* Bytes that always hold a zone written by tp_zone_format, NUL included ("UPS north" is 9). */
#define TP_ZONE_TEXT_SIZE 16

/* Writes UTM zone 1..60 or TP_ZONE_UPS, hemisphere northp (1 north, 0 south), as text in the
 * given style into out, a buffer of out_size bytes (TP_ZONE_TEXT_SIZE always suffices),
 * NUL-terminated. TP_ERR_INVALID_ARG for a zone outside [0, 60], an unknown style, a NULL
 * out or an out_size too small (out is then left untouched). */
tp_status tp_zone_format(int zone, int northp, tp_zone_style style, char* out, size_t out_size,
                         tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * MGRS (Military Grid Reference System), as GeographicLib's MGRS class writes and reads it.
 */

/* Writes the MGRS reference of UTM/UPS (zone, northp, easting_m, northing_m) into out, a
 * buffer of out_size bytes (TP_MGRS_SIZE always suffices), NUL-terminated.
 * precision is the number of digits per coordinate: 0 (100 km square) .. 5 (1 m) .. 11 (1 um),
 * or -1 for the grid zone designator alone ("33T"). The coordinates are TRUNCATED to the
 * precision, not rounded, as MGRS requires (38n 444999 3688999 at precision 2 is 38SMB4488).
 * lat_deg, the point's latitude, picks the latitude band letter exactly near a band boundary;
 * pass NAN to have it computed from the UTM coordinates. The zone is kept as given.
 * Errors: precision outside [-1, 11], coordinates outside the MGRS ranges (100 km narrower
 * than UTM/UPS), a latitude inconsistent with the coordinates, out_size too small (then out
 * is left untouched). */
tp_status tp_mgrs_forward(int zone, int northp, double easting_m, double northing_m, double lat_deg,
                          int precision, char* out, size_t out_size, tp_error* err);

/* Reads an MGRS reference (case-insensitive, e.g. "33TWN0000049776", "38smb4488", the grid
 * zone designator "33T" alone, leading 0 of zones 1..9 optional) into UTM/UPS zone, hemisphere
 * and (easting, northing) in metres. centerp = 1 gives the centre of the square the reference
 * names (as GeoConvert does; then converting back is stable), 0 its south-west corner.
 * *precision (may be NULL) receives the digits per coordinate (-1 for a grid zone designator
 * alone, which returns some point inside that zone). Malformed references, illegal letters,
 * odd digit counts and squares outside their band are TP_ERR_INVALID_ARG with
 * GeographicLib's explanation; so is GeographicLib's "INVALID" placeholder. */
tp_status tp_mgrs_reverse(const char* mgrs, int centerp, int* zone, int* northp, double* easting_m,
                          double* northing_m, int* precision, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Earth-centred, Earth-fixed (geocentric) coordinates
 */

/* Geographic (lat_deg, lon_deg, h_m) to WGS84 geocentric (x_m, y_m, z_m): X towards (0N, 0E),
 * Y towards (0N, 90E), Z towards the north pole. h_m is the ELLIPSOIDAL height (above the
 * WGS84 ellipsoid along its normal), not a height above sea level or the geoid. */
tp_status tp_geo_to_ecef(double lat_deg, double lon_deg, double h_m, double* x_m, double* y_m,
                         double* z_m, tp_error* err);

/* WGS84 geocentric (x_m, y_m, z_m) to geographic (*lat_deg, *lon_deg, *h_m); h_m is the
 * ellipsoidal height. The longitude is in [-180, 180]. Errors stay below 7 nm for points
 * within 5000 km of the ellipsoid's surface. */
tp_status tp_geo_from_ecef(double x_m, double y_m, double z_m, double* lat_deg, double* lon_deg,
                           double* h_m, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Transverse Mercator, exact (GeographicLib TransverseMercatorExact, Lee's elliptic-function
 * formulation). The exact form is used rather than the 6th-order Krueger series
 * (TransverseMercator) because it stays accurate to nanometres far from the central meridian:
 * the series is good to 5 nm only within 35 degrees of lon0, and the reference data set
 * (Karney's TMcoords) goes 50 degrees out. It is slower than the series; UTM/UPS above uses
 * the series (GeographicLib's UTMUPS does), as UTM zones stay within a few degrees of their
 * central meridian.
 * No false easting or northing; the latitude of origin is the equator.
 */

/* Geographic (lat_deg, lon_deg) to transverse Mercator (x_m, y_m) with central meridian
 * lon0_deg and central scale k0 (0 < k0 <= 2; UTM uses 0.9996). gamma_deg (meridian
 * convergence: bearing of grid north, clockwise from true north) and k (point scale) are
 * optional outputs (NULL to skip). */
tp_status tp_tm_forward(double lon0_deg, double k0, double lat_deg, double lon_deg, double* x_m,
                        double* y_m, double* gamma_deg, double* k, tp_error* err);

/* Transverse Mercator (x_m, y_m) with central meridian lon0_deg and scale k0 back to
 * geographic (*lat_deg, *lon_deg); lon in [-180, 180]. gamma_deg and k are optional. */
tp_status tp_tm_reverse(double lon0_deg, double k0, double x_m, double y_m, double* lat_deg,
                        double* lon_deg, double* gamma_deg, double* k, tp_error* err);

/* ---------------------------------------------------------------------------------------------
 * Geodesics on the WGS84 ellipsoid
 */

/* The inverse geodesic problem (GeographicLib Geodesic::WGS84().Inverse, as GeodSolve -i):
 * the shortest path from (lat1_deg, lon1_deg) to (lat2_deg, lon2_deg). Writes the forward
 * azimuths at both ends (*azi1_deg, *azi2_deg: clockwise from north, in [-180, 180]) and the
 * length *s12_m. Accurate to about 15 nm for any pair, antipodal ones included. */
tp_status tp_geodesic_inverse(double lat1_deg, double lon1_deg, double lat2_deg, double lon2_deg,
                              double* azi1_deg, double* azi2_deg, double* s12_m, tp_error* err);

#ifdef __cplusplus
}
#endif
#endif /* TP_GEO_H */
