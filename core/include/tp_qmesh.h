/* tp_qmesh.h - Cesium quantized-mesh-1.0 terrain tiles: the geographic tiling scheme and the
 * encoder of one tile's bytes (qmesh.c; docs/quantized_mesh.md).
 *
 * One concept of the core's API, included by tp_core.h with the others; it compiles on its own.
 * Pure C: the tile is encoded into memory (gzip and files are the caller's: app/export/qm_*.c).
 *
 * The format (https://github.com/CesiumGS/quantized-mesh, little-endian): an 88-byte header
 * (tile centre in ECEF, minimum and maximum height as floats, bounding sphere, horizon occlusion
 * point in the ellipsoid-scaled ECEF frame), the vertex count and the u, v and height arrays
 * (uint16, 0..32767, each delta-coded from the previous vertex and zig-zag encoded), padding to
 * the index size, the triangle count and the indices (uint16, or uint32 above 65536 vertices)
 * high-water-mark encoded, the west, south, east and north edge index lists, and the
 * `octvertexnormals` extension (id 1: two bytes per vertex, the oct-encoded unit normal in ECEF).
 *
 * Geometry on the WGS84 ellipsoid (a = 6378137 m, f = 1/298.257223563), as Cesium's.
 */
#ifndef TP_QMESH_H
#define TP_QMESH_H

#include "tp_base.h"

#ifdef __cplusplus
extern "C" {
#endif

/* The largest u, v and height code: the tile's east or north edge, its maximum height. */
#define TP_QMESH_MAX_CODE 32767

/* The geographic tiling scheme (EPSG:4326, TMS): level z has 2^(z+1) x 2^z tiles of
 * 180 / 2^z degrees, x from -180 eastwards, y from -90 northwards. Writes the tile's bounds in
 * degrees. x, y are not checked. */
void tp_qmesh_tile_bounds(int z, int x, int y, double* west_deg, double* south_deg,
                          double* east_deg, double* north_deg);

/* Cesium's geometric error of a level in this scheme: level 0's is
 * TerrainProvider.getEstimatedLevelZeroGeometricErrorForAHeightmap(WGS84, 65, 2) =
 * a * 2 pi * 0.25 / 65 / 2 (77,067.34 m), halved per level. */
double tp_qmesh_level_error_m(int z);

/* One tile to encode. Vertices by u (0 west .. 32767 east), v (0 south .. 32767 north) and
 * height code h (0 = min_height_m .. 32767 = max_height_m, linear); triangles of three vertex
 * indices, counter-clockwise seen from above (in u, v). min/max are written as floats: pass
 * values a float holds exactly where heights must decode identically in two tiles. */
typedef struct tp_qmesh_tile {
    double west_deg, south_deg, east_deg, north_deg;
    double min_height_m, max_height_m;
    size_t vertex_count;
    const uint16_t* u;
    const uint16_t* v;
    const uint16_t* h;
    size_t triangle_count;
    const uint32_t* triangles;
} tp_qmesh_tile;

/* What tp_qmesh_encode computed, for checks and reports. */
typedef struct tp_qmesh_info {
    double center[3];         /* ECEF: the bounding sphere's centre (also the header's centre) */
    double radius_m;          /* the bounding sphere's radius */
    double horizon[3];        /* ellipsoid-scaled ECEF */
    int horizon_defined;      /* 0: no point occludes the tile (a tile of a hemisphere): the
                                 point written is the centre's direction at 1000 radii */
    size_t edge_count[4];     /* vertices on the west, south, east, north edges */
    int index_bytes;          /* 2 or 4 */
} tp_qmesh_info;

/* Encodes the tile (with the octvertexnormals extension) into a new buffer *out of *size bytes
 * (free it with free()). Vertices are renumbered in the order the triangles first use them (what
 * high-water-mark coding needs); vertices no triangle uses are dropped. Normals: the unit sum of
 * the area-weighted normals of the triangles around each vertex, in ECEF. Fails with
 * TP_ERR_INVALID_ARG for no triangle, an index out of range, a code above 32767, bounds not
 * increasing, min_height_m > max_height_m or a non-finite value; TP_ERR_OUT_OF_MEMORY. info may
 * be NULL. Reentrant. */
tp_status tp_qmesh_encode(const tp_qmesh_tile* t, uint8_t** out, size_t* size,
                          tp_qmesh_info* info, tp_error* err);

/* Geographic (lat, lon in degrees, ellipsoidal height in m) to WGS84 ECEF (m). */
void tp_qmesh_geo_to_ecef(double lat_deg, double lon_deg, double h_m, double ecef[3]);

#ifdef __cplusplus
}
#endif
#endif /* TP_QMESH_H */
