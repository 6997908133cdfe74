/* qmesh.c - the quantized-mesh-1.0 encoder and the geographic tiling scheme (see tp_qmesh.h). */
#include "tp_qmesh.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define WGS84_A 6378137.0
#define WGS84_F (1.0 / 298.257223563)
#define WGS84_B (WGS84_A * (1.0 - WGS84_F))
#define DEG (3.14159265358979323846 / 180.0)

void tp_qmesh_tile_bounds(int z, int x, int y, double* west_deg, double* south_deg,
                          double* east_deg, double* north_deg)
{
    const double size = 180.0 / ldexp(1.0, z);
    *west_deg = -180.0 + x * size;
    *east_deg = -180.0 + (x + 1) * size;
    *south_deg = -90.0 + y * size;
    *north_deg = -90.0 + (y + 1) * size;
}

double tp_qmesh_level_error_m(int z)
{
    return WGS84_A * 2.0 * 3.14159265358979323846 * 0.25 / 65.0 / 2.0 / ldexp(1.0, z);
}

void tp_qmesh_geo_to_ecef(double lat_deg, double lon_deg, double h_m, double ecef[3])
{
    const double e2 = WGS84_F * (2.0 - WGS84_F);
    const double sl = sin(lat_deg * DEG), cl = cos(lat_deg * DEG);
    const double n = WGS84_A / sqrt(1.0 - e2 * sl * sl);
    ecef[0] = (n + h_m) * cl * cos(lon_deg * DEG);
    ecef[1] = (n + h_m) * cl * sin(lon_deg * DEG);
    ecef[2] = (n * (1.0 - e2) + h_m) * sl;
}

/* ---- a growing little-endian byte buffer ---- */

typedef struct buf {
    uint8_t* p;
    size_t n, cap;
    int failed;
} buf;

static void put(buf* b, const void* data, size_t n)
{
    if (b->failed)
        return;
    if (b->n + n > b->cap) {
        size_t cap = b->cap ? b->cap : 4096;
        while (cap < b->n + n)
            cap *= 2;
        uint8_t* q = realloc(b->p, cap);
        if (!q) {
            b->failed = 1;
            return;
        }
        b->p = q;
        b->cap = cap;
    }
    memcpy(b->p + b->n, data, n);
    b->n += n;
}

static void put_u8(buf* b, uint8_t v) { put(b, &v, 1); }
static void put_u16(buf* b, uint16_t v)
{
    uint8_t c[2] = {(uint8_t)v, (uint8_t)(v >> 8)};
    put(b, c, 2);
}
static void put_u32(buf* b, uint32_t v)
{
    uint8_t c[4] = {(uint8_t)v, (uint8_t)(v >> 8), (uint8_t)(v >> 16), (uint8_t)(v >> 24)};
    put(b, c, 4);
}
static void put_f64(buf* b, double d)
{
    uint64_t v;
    memcpy(&v, &d, 8);
    put_u32(b, (uint32_t)v);
    put_u32(b, (uint32_t)(v >> 32));
}
static void put_f32(buf* b, float f)
{
    uint32_t v;
    memcpy(&v, &f, 4);
    put_u32(b, v);
}
static void put_index(buf* b, uint32_t v, int bytes)
{
    if (bytes == 2)
        put_u16(b, (uint16_t)v);
    else
        put_u32(b, v);
}

static uint16_t zigzag(int32_t d) { return (uint16_t)(((uint32_t)d << 1) ^ (uint32_t)(d >> 31)); }

/* ---- geometry ---- */

/* Cesium's EllipsoidalOccluder computeMagnitude: the scale of the direction d (unit, scaled
 * space) at which p (scaled space) is just below the horizon; <= 0 when none is. */
static double horizon_magnitude(const double p[3], const double d[3])
{
    double m2 = p[0] * p[0] + p[1] * p[1] + p[2] * p[2];
    double m = sqrt(m2);
    double dir[3] = {p[0] / m, p[1] / m, p[2] / m};
    m2 = fmax(1.0, m2);
    m = fmax(1.0, m);
    double cos_a = dir[0] * d[0] + dir[1] * d[1] + dir[2] * d[2];
    double cx = dir[1] * d[2] - dir[2] * d[1], cy = dir[2] * d[0] - dir[0] * d[2],
           cz = dir[0] * d[1] - dir[1] * d[0];
    double sin_a = sqrt(cx * cx + cy * cy + cz * cz);
    double cos_b = 1.0 / m, sin_b = sqrt(m2 - 1.0) * cos_b;
    double den = cos_a * cos_b - sin_a * sin_b;
    return den > 0 ? 1.0 / den : -1.0;
}

/* Cesium's AttributeCompression.octEncode to two bytes. */
static void oct_encode(const double n[3], uint8_t out[2])
{
    double s = fabs(n[0]) + fabs(n[1]) + fabs(n[2]);
    double x = n[0] / s, y = n[1] / s;
    if (n[2] < 0) {
        double ox = x, oy = y;
        x = (1.0 - fabs(oy)) * (ox >= 0 ? 1.0 : -1.0);
        y = (1.0 - fabs(ox)) * (oy >= 0 ? 1.0 : -1.0);
    }
    x = fmin(1.0, fmax(-1.0, x));
    y = fmin(1.0, fmax(-1.0, y));
    out[0] = (uint8_t)lround((x * 0.5 + 0.5) * 255.0);
    out[1] = (uint8_t)lround((y * 0.5 + 0.5) * 255.0);
}

static tp_status check(const tp_qmesh_tile* t, tp_error* err)
{
    if (!t->triangle_count || !t->vertex_count || !t->u || !t->v || !t->h || !t->triangles)
        return tp_error_set(err, TP_ERR_INVALID_ARG, "a quantized-mesh tile needs triangles");
    if (!(t->west_deg < t->east_deg && t->south_deg < t->north_deg) || !isfinite(t->west_deg) ||
        !isfinite(t->east_deg) || !isfinite(t->south_deg) || !isfinite(t->north_deg))
        return tp_error_set(err, TP_ERR_INVALID_ARG, "tile bounds not increasing or not finite");
    if (!(t->min_height_m <= t->max_height_m) || !isfinite(t->min_height_m) ||
        !isfinite(t->max_height_m))
        return tp_error_set(err, TP_ERR_INVALID_ARG, "tile heights %g .. %g", t->min_height_m,
                            t->max_height_m);
    if (t->vertex_count > UINT32_MAX || t->triangle_count > UINT32_MAX / 3)
        return tp_error_set(err, TP_ERR_INVALID_ARG, "too many vertices or triangles");
    for (size_t i = 0; i < t->vertex_count; i++)
        if (t->u[i] > TP_QMESH_MAX_CODE || t->v[i] > TP_QMESH_MAX_CODE ||
            t->h[i] > TP_QMESH_MAX_CODE)
            return tp_error_set(err, TP_ERR_INVALID_ARG, "vertex %zu: a code above 32767", i);
    for (size_t i = 0; i < 3 * t->triangle_count; i++)
        if (t->triangles[i] >= t->vertex_count)
            return tp_error_set(err, TP_ERR_INVALID_ARG, "triangle index %u out of range",
                                (unsigned)t->triangles[i]);
    return TP_OK;
}

/* The decoded position of vertex i in ECEF, as Cesium decodes it. */
static void vertex_ecef(const tp_qmesh_tile* t, uint32_t i, double out[3])
{
    double fu = t->u[i] / (double)TP_QMESH_MAX_CODE, fv = t->v[i] / (double)TP_QMESH_MAX_CODE;
    double fh = t->h[i] / (double)TP_QMESH_MAX_CODE;
    double lon = (1.0 - fu) * t->west_deg + fu * t->east_deg;
    double lat = (1.0 - fv) * t->south_deg + fv * t->north_deg;
    double hgt = (1.0 - fh) * (float)t->min_height_m + fh * (float)t->max_height_m;
    tp_qmesh_geo_to_ecef(lat, lon, hgt, out);
}

/* Bounding sphere (centre of the box, largest distance), horizon point, normals. */
static void geometry(const tp_qmesh_tile* t, const uint32_t* order, const uint32_t* inverse,
                     size_t nv, const double* p, uint8_t* oct, tp_qmesh_info* info)
{
    double lo[3] = {INFINITY, INFINITY, INFINITY}, hi[3] = {-INFINITY, -INFINITY, -INFINITY};
    for (size_t i = 0; i < nv; i++)
        for (int c = 0; c < 3; c++) {
            lo[c] = fmin(lo[c], p[3 * i + c]);
            hi[c] = fmax(hi[c], p[3 * i + c]);
        }
    double r2 = 0;
    for (int c = 0; c < 3; c++)
        info->center[c] = 0.5 * (lo[c] + hi[c]);
    for (size_t i = 0; i < nv; i++) {
        double dx = p[3 * i] - info->center[0], dy = p[3 * i + 1] - info->center[1],
               dz = p[3 * i + 2] - info->center[2];
        r2 = fmax(r2, dx * dx + dy * dy + dz * dz);
    }
    info->radius_m = sqrt(r2);
    const double radii[3] = {WGS84_A, WGS84_A, WGS84_B};
    double d[3], dl = 0;
    for (int c = 0; c < 3; c++) {
        d[c] = info->center[c] / radii[c];
        dl += d[c] * d[c];
    }
    dl = sqrt(dl);
    for (int c = 0; c < 3; c++)
        d[c] /= dl;
    double mag = 0;
    info->horizon_defined = 1;
    for (size_t i = 0; i < nv && info->horizon_defined; i++) {
        double s[3] = {p[3 * i] / radii[0], p[3 * i + 1] / radii[1], p[3 * i + 2] / radii[2]};
        double m = horizon_magnitude(s, d);
        if (m <= 0)
            info->horizon_defined = 0;
        mag = fmax(mag, m);
    }
    if (!info->horizon_defined)
        mag = 1000.0;
    for (int c = 0; c < 3; c++)
        info->horizon[c] = d[c] * mag;
    /* normals: area-weighted sums of the triangles' normals taken in local east-north-up
     * metres (the tile's u, v scaled by the metres a degree spans at the triangle's latitude),
     * then turned into ECEF at each vertex: on flat ground the ellipsoid's normal, whatever
     * the triangles' size (a chord of a root tile would tilt it) */
    double* nrm = calloc(3 * nv, sizeof *nrm);
    if (!nrm)
        return; /* oct stays zero-filled: the caller checks allocations before */
    const double e2 = WGS84_F * (2.0 - WGS84_F);
    const double du = (t->east_deg - t->west_deg) / TP_QMESH_MAX_CODE * DEG;
    const double dv = (t->north_deg - t->south_deg) / TP_QMESH_MAX_CODE * DEG;
    const double dh = ((float)t->max_height_m - (float)t->min_height_m) / TP_QMESH_MAX_CODE;
    for (size_t k = 0; k < t->triangle_count; k++) {
        const uint32_t* o = t->triangles + 3 * k;
        const double lat = (t->south_deg + (t->v[o[0]] + t->v[o[1]] + t->v[o[2]]) / 3.0 *
                                               (t->north_deg - t->south_deg) / TP_QMESH_MAX_CODE) * DEG;
        const double w = sqrt(1.0 - e2 * sin(lat) * sin(lat));
        const double mx = WGS84_A / w * cos(lat) * du, my = WGS84_A * (1.0 - e2) / (w * w * w) * dv;
        double e1[3] = {((double)t->u[o[1]] - t->u[o[0]]) * mx, ((double)t->v[o[1]] - t->v[o[0]]) * my,
                        ((double)t->h[o[1]] - t->h[o[0]]) * dh};
        double f2[3] = {((double)t->u[o[2]] - t->u[o[0]]) * mx, ((double)t->v[o[2]] - t->v[o[0]]) * my,
                        ((double)t->h[o[2]] - t->h[o[0]]) * dh};
        double n[3] = {e1[1] * f2[2] - e1[2] * f2[1], e1[2] * f2[0] - e1[0] * f2[2],
                       e1[0] * f2[1] - e1[1] * f2[0]};
        for (int c = 0; c < 3; c++)
            for (int q = 0; q < 3; q++)
                nrm[3 * order[o[c]] + q] += n[q];
    }
    for (size_t i = 0; i < nv; i++) {
        double* n = nrm + 3 * i;
        double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        double enu[3] = {0, 0, 1};
        if (l > 0)
            enu[0] = n[0] / l, enu[1] = n[1] / l, enu[2] = n[2] / l;
        const uint32_t v = inverse[i];
        const double lat = (t->south_deg + t->v[v] * (t->north_deg - t->south_deg) / TP_QMESH_MAX_CODE) * DEG;
        const double lon = (t->west_deg + t->u[v] * (t->east_deg - t->west_deg) / TP_QMESH_MAX_CODE) * DEG;
        const double sl = sin(lat), cl = cos(lat), so = sin(lon), co = cos(lon);
        /* east (-sin lon, cos lon, 0), north (-sin lat cos lon, -sin lat sin lon, cos lat),
         * up (cos lat cos lon, cos lat sin lon, sin lat) */
        double q[3] = {-so * enu[0] - sl * co * enu[1] + cl * co * enu[2],
                       co * enu[0] - sl * so * enu[1] + cl * so * enu[2], cl * enu[1] + sl * enu[2]};
        oct_encode(q, oct + 2 * i);
    }
    free(nrm);
}

static void write_edge(buf* b, const uint32_t* list, size_t n, int bytes)
{
    put_u32(b, (uint32_t)n);
    for (size_t i = 0; i < n; i++)
        put_index(b, list[i], bytes);
}

/* Sorts edge vertex list by key (insertion sort: edges hold few vertices; stable). */
static void sort_edge(uint32_t* list, size_t n, const uint16_t* key, const uint32_t* inverse)
{
    for (size_t i = 1; i < n; i++) {
        uint32_t x = list[i];
        size_t j = i;
        while (j > 0 && key[inverse[list[j - 1]]] > key[inverse[x]]) {
            list[j] = list[j - 1];
            j--;
        }
        list[j] = x;
    }
}

tp_status tp_qmesh_encode(const tp_qmesh_tile* t, uint8_t** out, size_t* size,
                          tp_qmesh_info* info, tp_error* err)
{
    tp_status s = check(t, err);
    if (s != TP_OK)
        return s;
    tp_qmesh_info local;
    info = info ? info : &local;
    memset(info, 0, sizeof *info);
    const size_t nv_in = t->vertex_count;
    uint32_t* order = malloc(nv_in * sizeof *order);   /* old -> new */
    uint32_t* inverse = malloc(nv_in * sizeof *inverse); /* new -> old */
    uint32_t* edges = malloc(4 * nv_in * sizeof *edges);
    double* p = NULL;
    uint8_t* oct = NULL;
    buf b = {0};
    if (!order || !inverse || !edges)
        goto oom;
    for (size_t i = 0; i < nv_in; i++)
        order[i] = UINT32_MAX;
    size_t nv = 0;
    for (size_t i = 0; i < 3 * t->triangle_count; i++)
        if (order[t->triangles[i]] == UINT32_MAX) {
            inverse[nv] = t->triangles[i];
            order[t->triangles[i]] = (uint32_t)nv++;
        }
    p = malloc(3 * nv * sizeof *p);
    oct = calloc(2 * nv, 1);
    if (!p || !oct)
        goto oom;
    for (size_t i = 0; i < nv; i++)
        vertex_ecef(t, inverse[i], p + 3 * i);
    geometry(t, order, inverse, nv, p, oct, info);
    const int bytes = nv > 65536 ? 4 : 2;
    info->index_bytes = bytes;
    /* header */
    for (int c = 0; c < 3; c++)
        put_f64(&b, info->center[c]);
    put_f32(&b, (float)t->min_height_m);
    put_f32(&b, (float)t->max_height_m);
    for (int c = 0; c < 3; c++)
        put_f64(&b, info->center[c]);
    put_f64(&b, info->radius_m);
    for (int c = 0; c < 3; c++)
        put_f64(&b, info->horizon[c]);
    /* vertices */
    put_u32(&b, (uint32_t)nv);
    const uint16_t* arrays[3] = {t->u, t->v, t->h};
    for (int a = 0; a < 3; a++) {
        int32_t prev = 0;
        for (size_t i = 0; i < nv; i++) {
            int32_t cur = arrays[a][inverse[i]];
            put_u16(&b, zigzag(cur - prev));
            prev = cur;
        }
    }
    /* indices, high-water mark */
    while (b.n % (size_t)bytes)
        put_u8(&b, 0);
    put_u32(&b, (uint32_t)t->triangle_count);
    uint32_t highest = 0;
    for (size_t i = 0; i < 3 * t->triangle_count; i++) {
        uint32_t idx = order[t->triangles[i]];
        put_index(&b, highest - idx, bytes);
        if (idx == highest)
            highest++;
    }
    /* edges: west (u = 0) and east (u = max) south to north, south (v = 0) and north (v = max)
     * west to east */
    for (int side = 0; side < 4; side++) {
        uint32_t* list = edges + side * nv_in;
        size_t n = 0;
        for (size_t i = 0; i < nv; i++) {
            uint32_t o = inverse[i];
            int on = side == 0   ? t->u[o] == 0
                     : side == 1 ? t->v[o] == 0
                     : side == 2 ? t->u[o] == TP_QMESH_MAX_CODE
                                 : t->v[o] == TP_QMESH_MAX_CODE;
            if (on)
                list[n++] = (uint32_t)i;
        }
        sort_edge(list, n, side == 0 || side == 2 ? t->v : t->u, inverse);
        info->edge_count[side] = n;
        write_edge(&b, list, n, bytes);
    }
    /* extension 1: oct-encoded vertex normals */
    put_u8(&b, 1);
    put_u32(&b, (uint32_t)(2 * nv));
    put(&b, oct, 2 * nv);
    if (b.failed)
        goto oom;
    free(order);
    free(inverse);
    free(edges);
    free(p);
    free(oct);
    *out = b.p;
    *size = b.n;
    return TP_OK;
oom:
    free(order);
    free(inverse);
    free(edges);
    free(p);
    free(oct);
    free(b.p);
    return tp_error_set(err, TP_ERR_OUT_OF_MEMORY, "out of memory encoding a tile");
}
