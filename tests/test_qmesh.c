/* test_qmesh.c - the quantized-mesh encoder (core/src/qmesh.c) against the specification's byte
 * layout (https://github.com/CesiumGS/quantized-mesh), with every expected byte worked out by
 * hand from the specification below, not from the encoder; the tiling scheme; gzip round trips
 * (io/src/gzip.cpp). tests/qm_check.py decodes whole exported tile sets. */
#include "tp_geo.h"
#include "tp_io.h"
#include "tp_test.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define PI 3.14159265358979323846

#define TESTS(X)                                                                                   \
    X(two_triangles_byte_for_byte)                                                                 \
    X(header_sphere_horizon_and_normals_of_a_flat_tile)                                            \
    X(more_than_65536_vertices_use_32_bit_indices)                                                 \
    X(bad_tiles_are_refused)                                                                       \
    X(geographic_scheme_and_level_errors)                                                          \
    X(gzip_round_trip_and_bad_streams)

static uint16_t u16_at(const uint8_t* p) { return (uint16_t)(p[0] | p[1] << 8); }
static uint32_t u32_at(const uint8_t* p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}
static double f64_at(const uint8_t* p)
{
    uint64_t v = (uint64_t)u32_at(p) | (uint64_t)u32_at(p + 4) << 32;
    double d;
    memcpy(&d, &v, 8);
    return d;
}
static float f32_at(const uint8_t* p)
{
    uint32_t v = u32_at(p);
    float f;
    memcpy(&f, &v, 4);
    return f;
}

/* A square tile: vertices 0 SW, 1 SE, 2 NW, 3 NE; triangles (0, 1, 3) and (0, 3, 2). */
static const uint16_t SU[4] = {0, 32767, 0, 32767}, SV[4] = {0, 0, 32767, 32767};

TEST(two_triangles_byte_for_byte)
{
    const uint16_t h[4] = {0, 100, 200, 32767};
    const uint32_t tris[6] = {0, 1, 3, 0, 3, 2};
    tp_qmesh_tile t = {1.0, 42.0, 1.5, 42.5, 500.0, 1500.0, 4, SU, SV, h, 2, tris};
    uint8_t* b = NULL;
    size_t n = 0;
    tp_qmesh_info info;
    tp_error err;
    ASSERT_OK(tp_qmesh_encode(&t, &b, &n, &info, &err));
    /* header 88 + count 4 + 3 arrays of 4 u16 (24) = 116, 2-aligned: no padding; triangle count
     * 4 + 6 indices (12) = 132; four edge lists of 2 (4 + 4 each) = 164; extension header 5 +
     * 4 vertices x 2 = 177 */
    ASSERT_EQ_INT((int)n, 177);
    EXPECT_EQ_DBL(f32_at(b + 24), 500.0f);
    EXPECT_EQ_DBL(f32_at(b + 28), 1500.0f);
    EXPECT_EQ_INT((int)u32_at(b + 88), 4);
    /* first use order: old 0, 1, 3, 2 -> new 0, 1, 2, 3; u = 0, 32767, 32767, 0: deltas 0,
     * 32767, 0, -32767, zig-zag (d << 1) ^ (d >> 15): 0, 65534, 0, 65533 */
    const uint16_t zu[4] = {0, 65534, 0, 65533}, zv[4] = {0, 0, 65534, 0};
    /* h = 0, 100, 32767, 200: deltas 0, 100, 32667, -32567: 0, 200, 65334, 65133 */
    const uint16_t zh[4] = {0, 200, 65334, 65133};
    for (int i = 0; i < 4; i++) {
        EXPECT_EQ_INT(u16_at(b + 92 + 2 * i), zu[i]);
        EXPECT_EQ_INT(u16_at(b + 100 + 2 * i), zv[i]);
        EXPECT_EQ_INT(u16_at(b + 108 + 2 * i), zh[i]);
    }
    EXPECT_EQ_INT((int)u32_at(b + 116), 2);
    /* new triangles (0, 1, 2), (0, 2, 3): high-water-mark codes highest - index */
    const uint16_t codes[6] = {0, 0, 0, 3, 1, 0};
    for (int i = 0; i < 6; i++)
        EXPECT_EQ_INT(u16_at(b + 120 + 2 * i), codes[i]);
    /* west (u = 0) south to north: new 0, 3; south (v = 0) west to east: 0, 1; east: 1, 2;
     * north: 3, 2 */
    const uint16_t edges[4][2] = {{0, 3}, {0, 1}, {1, 2}, {3, 2}};
    for (int s = 0; s < 4; s++) {
        EXPECT_EQ_INT((int)u32_at(b + 132 + 8 * s), 2);
        EXPECT_EQ_INT(u16_at(b + 136 + 8 * s), edges[s][0]);
        EXPECT_EQ_INT(u16_at(b + 138 + 8 * s), edges[s][1]);
    }
    EXPECT_EQ_INT(b[164], 1);                /* extension id: oct-encoded vertex normals */
    EXPECT_EQ_INT((int)u32_at(b + 165), 8);  /* its length */
    EXPECT_EQ_INT(info.index_bytes, 2);
    free(b);
}

/* Decodes Cesium's oct encoding (AttributeCompression.octDecode). */
static void oct_decode(const uint8_t* p, double out[3])
{
    double x = p[0] / 255.0 * 2 - 1, y = p[1] / 255.0 * 2 - 1, z = 1 - fabs(x) - fabs(y);
    if (z < 0) {
        double ox = x;
        x = (1 - fabs(y)) * (ox >= 0 ? 1 : -1);
        y = (1 - fabs(ox)) * (y >= 0 ? 1 : -1);
    }
    double l = sqrt(x * x + y * y + z * z);
    out[0] = x / l, out[1] = y / l, out[2] = z / l;
}

TEST(header_sphere_horizon_and_normals_of_a_flat_tile)
{
    const uint16_t h[4] = {0, 0, 0, 0};
    const uint32_t tris[6] = {0, 1, 3, 0, 3, 2};
    tp_qmesh_tile t = {1.0, 42.0, 1.5, 42.5, 1000.0, 1000.0, 4, SU, SV, h, 2, tris};
    uint8_t* b = NULL;
    size_t n = 0;
    tp_qmesh_info info;
    tp_error err;
    ASSERT_OK(tp_qmesh_encode(&t, &b, &n, &info, &err));
    /* the sphere holds the four corners at 1000 m */
    const double lat[4] = {42.0, 42.0, 42.5, 42.5}, lon[4] = {1.0, 1.5, 1.0, 1.5};
    /* header: centre 0..23, min 24, max 28, sphere centre 32..55, radius 56, horizon 64..87 */
    double c[3] = {f64_at(b + 32), f64_at(b + 40), f64_at(b + 48)}, r = f64_at(b + 56);
    EXPECT_NEAR(c[0], f64_at(b), 1e-9); /* the header's centre is the sphere's */
    for (int i = 0; i < 4; i++) {
        double p[3];
        tp_geo_to_ecef(lat[i], lon[i], 1000.0, &p[0], &p[1], &p[2], NULL); /* GeographicLib */
        EXPECT_LE(hypot(hypot(p[0] - c[0], p[1] - c[1]), p[2] - c[2]), r + 1e-6);
    }
    /* a tile of half a degree: its diagonal is about 67 km, the radius half of it */
    EXPECT_GT(r, 30e3);
    EXPECT_LT(r, 40e3);
    /* the horizon point: defined, beyond the ellipsoid (scaled length > 1), towards the tile */
    EXPECT_TRUE(info.horizon_defined);
    const double hp[3] = {f64_at(b + 64), f64_at(b + 72), f64_at(b + 80)};
    double len = sqrt(hp[0] * hp[0] + hp[1] * hp[1] + hp[2] * hp[2]);
    EXPECT_GT(len, 1.0);
    EXPECT_LT(len, 1.01);
    /* normals of flat ground: the ellipsoid's normal at each vertex, within the 8-bit oct
     * encoding's precision (about 1 degree) */
    const uint8_t* oct = b + 165 + 4;
    const int order[4] = {0, 1, 3, 2}; /* new vertex i is old order[i] */
    for (int i = 0; i < 4; i++) {
        double nrm[3], la = lat[order[i]] * PI / 180, lo = lon[order[i]] * PI / 180;
        oct_decode(oct + 2 * i, nrm);
        double up[3] = {cos(la) * cos(lo), cos(la) * sin(lo), sin(la)};
        EXPECT_GT(nrm[0] * up[0] + nrm[1] * up[1] + nrm[2] * up[2], cos(1.5 * PI / 180));
    }
    free(b);
}

TEST(more_than_65536_vertices_use_32_bit_indices)
{
    /* a 300 x 300 lattice: 90000 vertices, 2 x 299^2 triangles */
    const int m = 300;
    const size_t nv = (size_t)m * m, nt = (size_t)2 * (m - 1) * (m - 1);
    uint16_t* u = malloc(nv * 2);
    uint16_t* v = malloc(nv * 2);
    uint16_t* h = calloc(nv, 2);
    uint32_t* tr = malloc(nt * 12);
    ASSERT_TRUE(u && v && h && tr);
    for (int j = 0; j < m; j++)
        for (int i = 0; i < m; i++) {
            u[j * m + i] = (uint16_t)(i * 32767 / (m - 1));
            v[j * m + i] = (uint16_t)(j * 32767 / (m - 1));
        }
    size_t k = 0;
    for (int j = 0; j + 1 < m; j++)
        for (int i = 0; i + 1 < m; i++) {
            uint32_t a = (uint32_t)(j * m + i), bb = a + 1, c = a + (uint32_t)m, d = c + 1;
            uint32_t q[6] = {a, bb, d, a, d, c};
            memcpy(tr + k, q, sizeof q);
            k += 6;
        }
    tp_qmesh_tile t = {1.0, 42.0, 1.5, 42.5, 0.0, 1.0, nv, u, v, h, nt, tr};
    uint8_t* b = NULL;
    size_t n = 0;
    tp_qmesh_info info;
    tp_error err;
    ASSERT_OK(tp_qmesh_encode(&t, &b, &n, &info, &err));
    EXPECT_EQ_INT(info.index_bytes, 4);
    /* 88 + 4 + 6 * nv, padded to 4, + 4 + 12 nt + four edge lists of m (4 + 4 m) + 5 + 2 nv */
    size_t at = 88 + 4 + 6 * nv;
    at += (4 - at % 4) % 4;
    EXPECT_EQ_INT((int)u32_at(b + at), (int)nt);
    EXPECT_EQ_INT((int)n, (int)(at + 4 + 12 * nt + 4 * (4 + 4 * (size_t)m) + 5 + 2 * nv));
    for (int s = 0; s < 4; s++)
        EXPECT_EQ_INT((int)info.edge_count[s], m);
    free(b);
    free(u);
    free(v);
    free(h);
    free(tr);
}

TEST(bad_tiles_are_refused)
{
    const uint16_t h[4] = {0, 0, 0, 40000};
    const uint32_t tris[6] = {0, 1, 3, 0, 3, 4};
    uint8_t* b = NULL;
    size_t n = 0;
    tp_error err;
    tp_qmesh_tile t = {1.0, 42.0, 1.5, 42.5, 0.0, 1.0, 4, SU, SV, h, 1, tris};
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_qmesh_encode(&t, &b, &n, NULL, &err)); /* h > 32767 */
    const uint16_t h0[4] = {0, 0, 0, 0};
    t.h = h0;
    t.triangle_count = 2;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_qmesh_encode(&t, &b, &n, NULL, &err)); /* index 4 */
    EXPECT_CONTAINS(err.message, "out of range");
    t.triangle_count = 0;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_qmesh_encode(&t, &b, &n, NULL, &err));
    t.triangle_count = 1;
    t.min_height_m = 2.0;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_qmesh_encode(&t, &b, &n, NULL, &err));
    t.min_height_m = 0.0;
    t.east_deg = 1.0;
    EXPECT_STATUS(TP_ERR_INVALID_ARG, tp_qmesh_encode(&t, &b, &n, NULL, &err));
    EXPECT_TRUE(b == NULL);
}

TEST(geographic_scheme_and_level_errors)
{
    double w, s, e, n;
    tp_qmesh_tile_bounds(0, 1, 0, &w, &s, &e, &n);
    EXPECT_EQ_DBL(w, 0.0);
    EXPECT_EQ_DBL(s, -90.0);
    EXPECT_EQ_DBL(e, 180.0);
    EXPECT_EQ_DBL(n, 90.0);
    /* the specification's example: level 1, x 3, y 1 is (90E, 0N) - (180E, 90N) */
    tp_qmesh_tile_bounds(1, 3, 1, &w, &s, &e, &n);
    EXPECT_EQ_DBL(w, 90.0);
    EXPECT_EQ_DBL(s, 0.0);
    EXPECT_EQ_DBL(e, 180.0);
    EXPECT_EQ_DBL(n, 90.0);
    /* Cesium: 6378137 * 2 pi * 0.25 / 65 / 2 = 77067.34 m at level 0, halved per level */
    EXPECT_NEAR(tp_qmesh_level_error_m(0), 77067.3398, 1e-3);
    EXPECT_NEAR(tp_qmesh_level_error_m(13), 77067.3398 / 8192, 1e-6);
}

TEST(gzip_round_trip_and_bad_streams)
{
    uint8_t data[5000];
    for (int i = 0; i < 5000; i++)
        data[i] = (uint8_t)(i * i % 251);
    uint8_t *gz = NULL, *back = NULL;
    size_t gn = 0, bn = 0;
    tp_error err;
    ASSERT_OK(tp_gzip(data, sizeof data, 6, &gz, &gn, &err));
    EXPECT_EQ_INT(gz[0], 0x1f); /* RFC 1952's magic, then deflate (8) */
    EXPECT_EQ_INT(gz[1], 0x8b);
    EXPECT_EQ_INT(gz[2], 8);
    ASSERT_OK(tp_gunzip(gz, gn, &back, &bn, &err));
    EXPECT_EQ_INT((int)bn, 5000);
    EXPECT_TRUE(!memcmp(back, data, 5000));
    free(back);
    back = NULL;
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_gunzip(gz, gn / 2, &back, &bn, &err)); /* cut short */
    EXPECT_STATUS(TP_ERR_BAD_DATA, tp_gunzip(data, 100, &back, &bn, &err));  /* not gzip */
    EXPECT_TRUE(back == NULL);
    free(gz);
}

TP_TEST_MAIN(TESTS)
