#!/usr/bin/env python3
"""qm_check.py DIR [--points TERRAPATCH STORE N]: checks a Cesium quantized-mesh tile set that
`terrapatch export --tiles quantized-mesh` wrote, with a decoder of its own written from the
specification (https://github.com/CesiumGS/quantized-mesh), sharing no code with the exporter.

Checks (each failure prints "FAIL: ..." and exits 1; success prints "PASS ..." with figures):
  - layer.json: tilejson 2.1.0, quantized-mesh-1.0, tms, EPSG:4326, the tiles template, the
    octvertexnormals extension, available ranges per level 0..maxzoom, the terrapatch object
    (heights, levels with tile counts matching the files);
  - every tile of errors.json: gzip, then the byte layout: 88-byte header, vertex count,
    zig-zag delta-coded u, v, heights (all <= 32767), padding to the index size, triangle
    count, high-water-mark indices (each at most the highest so far + 1; all in range), four
    edge lists, then extension 1 (2 bytes a vertex) and nothing after it;
  - triangles counter-clockwise in (u, v), their areas summing to the whole tile (no hole, no
    overlap); edge lists = exactly the vertices with u = 0, v = 0, u = 32767, v = 32767;
  - header: minimum <= every decoded height <= maximum; the bounding sphere holds every vertex
    (ECEF computed here); the horizon occlusion point lies along the sphere centre's direction
    in scaled space, beyond the ellipsoid, and every vertex is no farther below its horizon than
    the point is (Cesium's culling test can then never hide a visible vertex);
  - normals: after oct decoding, facing up (dot with the ellipsoid's normal > -0.02: the 8-bit
    code's rounding of a vertical wall's normal);
  - the bound: every tile's measured error (errors.json) at most its level's
    geometric_error_m in layer.json (the figure Cesium refines by), and max_measured_error_m
    the level's largest;
  - watertight: neighbouring tiles of a level have the same vertices (position along the
    shared side, decoded height within 1e-6 m) on that side;
  - with --points: at N random positions inside tiles of the deepest level, the tile's height
    (barycentric in the triangle around the point) against `terrapatch point STORE lat lon`
    (the store's surface): the difference <= that tile's error in errors.json + 1e-3 m; and at N
    random vertices of that level, the vertex's height against `point` at the vertex within half
    the height step (+ 2 mm): the tiles are placed where the store is.
"""
import gzip
import json
import math
import os
import random
import struct
import subprocess
import sys

A = 6378137.0
F = 1 / 298.257223563
B = A * (1 - F)
E2 = F * (2 - F)
MAXC = 32767


def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)


def ecef(lat, lon, h):
    la, lo = math.radians(lat), math.radians(lon)
    n = A / math.sqrt(1 - E2 * math.sin(la) ** 2)
    return ((n + h) * math.cos(la) * math.cos(lo), (n + h) * math.cos(la) * math.sin(lo),
            (n * (1 - E2) + h) * math.sin(la))


def bounds(z, x, y):
    size = 180.0 / (1 << z)
    return -180 + x * size, -90 + y * size, -180 + (x + 1) * size, -90 + (y + 1) * size


def decode(data, name):
    """The tile's fields, from the specification's layout."""
    t = {}
    if len(data) < 92:
        fail("%s: %d bytes, shorter than the header" % (name, len(data)))
    h = struct.unpack_from("<3d2f4d3d", data, 0)
    t["center"], t["min"], t["max"] = h[0:3], h[3], h[4]
    t["sphere"], t["radius"], t["horizon"] = h[5:8], h[8], h[9:12]
    off = 88
    (nv,) = struct.unpack_from("<I", data, off)
    off += 4
    arrays = []
    for _ in range(3):
        vals = struct.unpack_from("<%dH" % nv, data, off)
        off += 2 * nv
        out, cur = [], 0
        for v in vals:
            cur += (v >> 1) ^ (-(v & 1))
            out.append(cur)
        arrays.append(out)
    t["u"], t["v"], t["h"] = arrays
    for name_a, arr in zip("uvh", arrays):
        if any(c < 0 or c > MAXC for c in arr):
            fail("%s: a %s code outside 0..32767" % (name, name_a))
    isz = 4 if nv > 65536 else 2
    fmt = "I" if isz == 4 else "H"
    if off % isz:
        off += isz - off % isz
    (nt,) = struct.unpack_from("<I", data, off)
    off += 4
    codes = struct.unpack_from("<%d%s" % (3 * nt, fmt), data, off)
    off += isz * 3 * nt
    idx, highest = [], 0
    for c in codes:
        if c > highest:
            fail("%s: high-water-mark code %d above the highest %d" % (name, c, highest))
        idx.append(highest - c)
        if c == 0:
            highest += 1
    if any(i >= nv for i in idx):
        fail("%s: an index out of range" % name)
    t["tris"] = [idx[k:k + 3] for k in range(0, len(idx), 3)]
    t["edges"] = []
    for _ in range(4):
        (n,) = struct.unpack_from("<I", data, off)
        off += 4
        t["edges"].append(list(struct.unpack_from("<%d%s" % (n, fmt), data, off)))
        off += isz * n
    t["ext"] = {}
    while off < len(data):
        eid, elen = struct.unpack_from("<BI", data, off)
        off += 5
        t["ext"][eid] = data[off:off + elen]
        off += elen
    if off != len(data):
        fail("%s: the last extension runs past the end" % name)
    return t


def heights(t):
    return [t["min"] + (t["max"] - t["min"]) * c / MAXC for c in t["h"]]


def positions(t, z, x, y):
    w, s, e, n = bounds(z, x, y)
    hs = heights(t)
    return [ecef(s + (n - s) * t["v"][i] / MAXC, w + (e - w) * t["u"][i] / MAXC, hs[i])
            for i in range(len(t["u"]))]


def horizon_magnitude(p, d):
    m2 = sum(c * c for c in p)
    m = math.sqrt(m2)
    dr = [c / m for c in p]
    m2, m = max(1.0, m2), max(1.0, m)
    cos_a = sum(a * b for a, b in zip(dr, d))
    cx = (dr[1] * d[2] - dr[2] * d[1], dr[2] * d[0] - dr[0] * d[2], dr[0] * d[1] - dr[1] * d[0])
    sin_a = math.sqrt(sum(c * c for c in cx))
    cos_b = 1 / m
    sin_b = math.sqrt(m2 - 1) * cos_b
    den = cos_a * cos_b - sin_a * sin_b
    return 1 / den if den > 0 else None


def check_tile(t, z, x, y, name):
    nv = len(t["u"])
    area = 0
    for a, b, c in t["tris"]:
        cr = ((t["u"][b] - t["u"][a]) * (t["v"][c] - t["v"][a]) -
              (t["u"][c] - t["u"][a]) * (t["v"][b] - t["v"][a]))
        if cr <= 0:
            fail("%s: triangle %d %d %d not counter-clockwise (or flat)" % (name, a, b, c))
        area += cr
    if area != 2 * MAXC * MAXC:
        fail("%s: the triangles cover %d, the tile %d (twice the area)" % (name, area, 2 * MAXC * MAXC))
    want = [sorted(i for i in range(nv) if t["u"][i] == 0), sorted(i for i in range(nv) if t["v"][i] == 0),
            sorted(i for i in range(nv) if t["u"][i] == MAXC), sorted(i for i in range(nv) if t["v"][i] == MAXC)]
    for side in range(4):
        if sorted(t["edges"][side]) != want[side]:
            fail("%s: edge list %d is not the vertices on that edge" % (name, side))
    hs = heights(t)
    if min(hs) < t["min"] - 1e-6 or max(hs) > t["max"] + 1e-6:
        fail("%s: heights %g..%g outside the header's %g..%g" % (name, min(hs), max(hs), t["min"], t["max"]))
    pos = positions(t, z, x, y)
    for p in pos:
        if math.dist(p, t["sphere"]) > t["radius"] * (1 + 1e-9) + 1e-6:
            fail("%s: a vertex outside the bounding sphere" % name)
    radii = (A, A, B)
    sc = [c / r for c, r in zip(t["sphere"], radii)]
    d = [c / math.sqrt(sum(q * q for q in sc)) for c in sc]
    hp = t["horizon"]
    mag = math.sqrt(sum(c * c for c in hp))
    if mag < 1 or any(abs(hp[k] / mag - d[k]) > 1e-9 for k in range(3)):
        fail("%s: horizon occlusion point %s not beyond the ellipsoid along the centre" % (name, hp))
    mags = [horizon_magnitude([c / r for c, r in zip(p, radii)], d) for p in pos]
    if all(m is not None for m in mags) and max(mags) > mag * (1 + 1e-9):
        fail("%s: a vertex farther below the horizon than the occlusion point" % name)
    nrm = t["ext"].get(1)
    if nrm is None or len(nrm) != 2 * nv:
        fail("%s: no octvertexnormals extension of 2 bytes a vertex" % name)
    for i in range(nv):
        ox, oy = nrm[2 * i] / 255 * 2 - 1, nrm[2 * i + 1] / 255 * 2 - 1
        vz = 1 - abs(ox) - abs(oy)
        vx, vy = ox, oy
        if vz < 0:
            vx = (1 - abs(oy)) * (1 if ox >= 0 else -1)
            vy = (1 - abs(ox)) * (1 if oy >= 0 else -1)
        ln = math.sqrt(vx * vx + vy * vy + vz * vz)
        up = [c / r / r for c, r in zip(pos[i], radii)]
        # up, but for the 8-bit oct code's rounding (1/127 a component) of a vertical wall's
        # horizontal normal (a cliff down to 0 m at the store's outline)
        if sum(a * b for a, b in zip((vx / ln, vy / ln, vz / ln), up)) / math.sqrt(sum(c * c for c in up)) < -0.02:
            fail("%s: vertex %d's normal faces down" % (name, i))


def side(t, k):
    """(position along side k, height) of its vertices, in order."""
    hs = heights(t)
    key = t["v"] if k in (0, 2) else t["u"]
    return sorted((key[i], hs[i]) for i in t["edges"][k])


def height_at(t, z, x, y, lat, lon):
    w, s, e, n = bounds(z, x, y)
    pu, pv = (lon - w) / (e - w) * MAXC, (lat - s) / (n - s) * MAXC
    hs = heights(t)
    best = None
    for a, b, c in t["tris"]:
        ua, va, ub, vb, uc, vc = t["u"][a], t["v"][a], t["u"][b], t["v"][b], t["u"][c], t["v"][c]
        det = (ub - ua) * (vc - va) - (uc - ua) * (vb - va)
        wb = ((pu - ua) * (vc - va) - (uc - ua) * (pv - va)) / det
        wc = ((ub - ua) * (pv - va) - (pu - ua) * (vb - va)) / det
        wa = 1 - wb - wc
        if best is None or min(wa, wb, wc) > best[0]:
            best = (min(wa, wb, wc), wa * hs[a] + wb * hs[b] + wc * hs[c])
    return best[1]


def main():
    d = sys.argv[1]
    layer = json.load(open(os.path.join(d, "layer.json")))
    errors = json.load(open(os.path.join(d, "errors.json")))
    for k, v in (("tilejson", "2.1.0"), ("format", "quantized-mesh-1.0"), ("scheme", "tms"),
                 ("projection", "EPSG:4326")):
        if layer.get(k) != v:
            fail("layer.json: %s is %r, expected %r" % (k, layer.get(k), v))
    if layer.get("tiles") != ["{z}/{x}/{y}.terrain?v={version}"] or "octvertexnormals" not in layer.get("extensions", []):
        fail("layer.json: tiles or extensions")
    tp = layer["terrapatch"]
    zmax = layer["maxzoom"]
    if tp["max_zoom"] != zmax or len(layer["available"]) != zmax + 1 or len(tp["levels"]) != zmax + 1:
        fail("layer.json: maxzoom, available and levels disagree")
    if tp["heights"] not in ("ellipsoid", "geoid") or not tp.get("geoid_model"):
        fail("layer.json: heights or geoid_model")
    tiles = {}
    for z in range(zmax + 1):
        r = layer["available"][z][0]
        n = (r["endX"] - r["startX"] + 1) * (r["endY"] - r["startY"] + 1)
        if tp["levels"][z]["tiles"] != n:
            fail("level %d: %d tiles stated, %d available" % (z, tp["levels"][z]["tiles"], n))
        for y in range(r["startY"], r["endY"] + 1):
            for x in range(r["startX"], r["endX"] + 1):
                key = "%d/%d/%d" % (z, x, y)
                if key not in errors:
                    fail("errors.json has no %s" % key)
                path = os.path.join(d, key + ".terrain")
                raw = open(path, "rb").read()
                if raw[:2] != b"\x1f\x8b":
                    fail("%s is not gzip" % path)
                t = decode(gzip.decompress(raw), path)
                check_tile(t, z, x, y, path)
                tiles[(z, x, y)] = t
    # the bound: every tile's measured error (errors.json: its decoded heights against every
    # store post and lattice post in it) within its level's stated geometric error, which is
    # what Cesium refines by; and each level's stated maximum is its tiles' maximum
    for z in range(zmax + 1):
        lv = tp["levels"][z]
        bound = lv["geometric_error_m"]
        mine = [(errors["%d/%d/%d" % k], k) for k in tiles if k[0] == z]
        over = [(e, k) for e, k in mine if e > bound * (1 + 1e-9)]
        if over:
            e, k = max(over)
            fail("level %d: %d of %d tiles measured above the level's geometric error %.4f m "
                 "(worst %d/%d/%d: %.4f m)" % (z, len(over), len(mine), bound, k[0], k[1], k[2], e))
        if abs(lv["max_measured_error_m"] - max(e for e, _ in mine)) > 1e-6 * max(1.0, bound):
            fail("level %d: max_measured_error_m %r is not its tiles' maximum" % (z, lv["max_measured_error_m"]))
    pairs = 0
    for (z, x, y), t in tiles.items():
        for (dx, dy, mine, theirs) in ((1, 0, 2, 0), (0, 1, 3, 1)):
            o = tiles.get((z, x + dx, y + dy))
            if o is None:
                continue
            a, b = side(t, mine), side(o, theirs)
            if len(a) != len(b) or any(p[0] != q[0] or abs(p[1] - q[1]) > 1e-6 for p, q in zip(a, b)):
                fail("%d/%d/%d and %d/%d/%d do not share their edge vertices" % (z, x, y, z, x + dx, y + dy))
            pairs += 1
    worst = 0.0
    if len(sys.argv) > 2 and sys.argv[2] == "--points":
        exe, store, count = sys.argv[3], sys.argv[4], int(sys.argv[5])
        if tp["heights"] != "geoid":
            fail("--points compares with `point`, heights as stored: export with --heights geoid")
        rng = random.Random(34)
        deep = [k for k in tiles if k[0] == zmax]
        ext = layer["bounds"]
        done = 0
        while done < count:
            z, x, y = deep[rng.randrange(len(deep))]
            w, s, e, n = bounds(z, x, y)
            lat = rng.uniform(max(s, ext[1]), min(n, ext[3]))
            lon = rng.uniform(max(w, ext[0]), min(e, ext[2]))
            out = subprocess.run([exe, "point", store, "%.10f" % lat, "%.10f" % lon, "--json", "-"],
                                 capture_output=True, text=True)
            if out.returncode != 0:
                continue  # off the store's grid (its extent is a box around it)
            ref = json.loads(out.stdout)["elevation_m"]
            if ref is None:
                continue
            got = height_at(tiles[(z, x, y)], z, x, y, lat, lon)
            diff = abs(got - ref)
            stated = errors["%d/%d/%d" % (z, x, y)]
            if diff > stated + 1e-3:
                fail("at %.7f %.7f (tile %d/%d/%d) the tile's height %.3f and the store's %.3f differ by %.3f m, "
                     "more than the tile's measured %.3f m" % (lat, lon, z, x, y, got, ref, diff, stated))
            worst = max(worst, diff / stated if stated > 0 else 0)
            done += 1
        # the vertices: each is a lattice post sampled on the store's surface at its own lon/lat,
        # so it must equal `point` there within half the height step (its rounding): a check
        # of where the tiles are placed, not only of how far they bend
        step = tp["height_step_m"]
        done = tries = 0
        while done < count and tries < 10 * count:
            tries += 1
            z, x, y = deep[rng.randrange(len(deep))]
            t = tiles[(z, x, y)]
            i = rng.randrange(len(t["u"]))
            w, s, e, n = bounds(z, x, y)
            lat, lon = s + (n - s) * t["v"][i] / MAXC, w + (e - w) * t["u"][i] / MAXC
            out = subprocess.run([exe, "point", store, "%.10f" % lat, "%.10f" % lon, "--json", "-"],
                                 capture_output=True, text=True)
            if out.returncode != 0 or json.loads(out.stdout)["elevation_m"] is None:
                continue
            diff = abs(heights(t)[i] - json.loads(out.stdout)["elevation_m"])
            if diff > step / 2 + 2e-3:
                fail("vertex %d of %d/%d/%d at %.7f %.7f: %.4f m from the store's surface, more than "
                     "half the height step %g" % (i, z, x, y, lat, lon, diff, step))
            done += 1
        if done < count // 2:
            fail("only %d vertices of the deepest level lie on the store" % done)
    print("PASS %d tiles, %d neighbour pairs watertight, worst point/stated error ratio %.3f" %
          (len(tiles), pairs, worst))


if __name__ == "__main__":
    main()
