"""web_cesium_check.py - judges a run of the web page (tools/web/drive.mjs's report) for
tests/test_web_cesium.sh. Not a test of its own: the shell cases run it and say what they expect.

  web_cesium_check.py points TP STORE OUT.json
      20 positions inside the store's data (a fixed pseudo-random sequence; those where
      `terrapatch point` has no height are passed over), with the height `terrapatch point --json`
      gives there: [{"lon", "lat", "height"}, ...]; their [lon, lat] in OUT.json.lonlat
  web_cesium_check.py tile TILES LON LAT
      prints "z/x/y" of the most detailed tile of TILES/layer.json's availability holding LON, LAT
  web_cesium_check.py footprint PAGE.png VIEW.png LEAST
      the ground's footprint in the page's picture against `terrapatch view`'s from the same
      camera: prints the IoU, exit 1 below LEAST
  web_cesium_check.py check REPORT.json TILES POINTS.json [TERRAIN.png ELLIPSOID.png]
      prints one line per finding, then "errors N", "heights N bad of M (worst ...)",
      "screens P% of pixels differ"; exit 0 when there is no error, every height agrees and the
      pictures differ in at least 10% of their pixels, else 1

A sampled height agrees when |Cesium - terrapatch point| <= the measured error of its tile
(TILES/errors.json, the tile at the level Cesium sampled) + (max - min height of the tile)/32767
(one step of quantized-mesh's 15-bit heights) + 0.05 m (the 15-bit u, v: under 6 cm across a
level-13 tile, at slopes up to 45 degrees).
"""
import concurrent.futures
import gzip
import json
import math
import os
import struct
import subprocess
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from tp_png import read_png  # noqa: E402

PIXEL_STEP = 24  # a pixel differs when a channel differs by more than this (of 255)
MIN_DIFFERENT = 0.10  # of the pixels, between the terrain and the bare ellipsoid
UV_SLACK_M = 0.05


def lcg(seed):
    while True:
        seed = (seed * 6364136223846793005 + 1442695040888963407) % (1 << 64)
        yield (seed >> 11) / float(1 << 53)


def points(tp, store, out):
    """20 positions where the store has a height, with that height."""
    info = json.loads(subprocess.run([tp, "info", "--json", store], capture_output=True,
                                     check=True, text=True).stdout)
    geo = find_geo(info)
    lat0, lat1, lon0, lon1 = geo
    r, got, tries = lcg(34), [], 0

    def height(pos):
        p = subprocess.run([tp, "point", store, "%.7f" % pos[0], "%.7f" % pos[1], "--json", "-"],
                           capture_output=True, text=True)
        return json.loads(p.stdout)["elevation_m"] if p.returncode == 0 else None

    # in batches of 24, four at a time (each a process); the first 20 with a height, in order
    with concurrent.futures.ThreadPoolExecutor(4) as pool:
        while len(got) < 20 and tries < 240:
            batch = []
            for _ in range(24):
                lat = lat0 + (0.1 + 0.8 * next(r)) * (lat1 - lat0)
                lon = lon0 + (0.1 + 0.8 * next(r)) * (lon1 - lon0)
                batch.append((round(lat, 7), round(lon, 7)))
            tries += len(batch)
            for (lat, lon), h in zip(batch, pool.map(height, batch)):
                if h is not None and len(got) < 20:
                    got.append({"lon": lon, "lat": lat, "height": h})
    if len(got) < 20:
        sys.exit("only %d of %d positions have a height in %s" % (len(got), tries, store))
    json.dump(got, open(out, "w"), indent=1)
    json.dump([[p["lon"], p["lat"]] for p in got], open(out + ".lonlat", "w"))


def find_geo(info):
    """(lat0, lat1, lon0, lon1) of `info --json`'s extent_geo (lat0, lon0, lat1, lon1)."""
    e = info.get("extent_geo")
    if not (isinstance(e, list) and len(e) == 4):
        sys.exit("no extent_geo in info --json")
    return e[0], e[2], e[1], e[3]


def tile_of(lon, lat, z):
    size = 180.0 / (1 << z)
    return z, int(math.floor((lon + 180) / size)), int(math.floor((lat + 90) / size))


def deepest(tiles, lon, lat):
    layer = json.load(open(os.path.join(tiles, "layer.json")))
    best = None
    for z, ranges in enumerate(layer["available"]):
        _, x, y = tile_of(lon, lat, z)
        if any(r["startX"] <= x <= r["endX"] and r["startY"] <= y <= r["endY"] for r in ranges):
            best = (z, x, y)
    return best


def tile_heights(tiles, z, x, y):
    """(min, max) height of a tile's header (quantized-mesh-1.0, gzip or not)."""
    data = open(os.path.join(tiles, str(z), str(x), "%d.terrain" % y), "rb").read()
    if data[:2] == b"\x1f\x8b":
        data = gzip.decompress(data)
    return struct.unpack_from("<2f", data, 24)


def differing(a_png, b_png):
    wa, ha, ca, ra = read_png(a_png)
    wb, hb, cb, rb = read_png(b_png)
    if (wa, ha) != (wb, hb):
        return 1.0
    n = 0
    for la, lb in zip(ra, rb):
        for i in range(wa):
            if any(abs(la[i * ca + k] - lb[i * cb + k]) > PIXEL_STEP for k in range(3)):
                n += 1
    return n / float(wa * ha)


def footprint(page_png, view_png, least):
    """IoU of the ground drawn in the page's picture and in `terrapatch view`'s from the same
    --camera-geo: a pixel is ground unless it is within 18 (page) or 6 (view) of the picture's
    top-left pixel in every channel (the camera must leave that corner off the data); the
    bottom 1/12 (Cesium's credit) is left out of both."""
    w, h, c, rp = read_png(page_png)
    w2, h2, c2, rv = read_png(view_png)
    if (w, h) != (w2, h2):
        print("footprint: %dx%d against %dx%d" % (w, h, w2, h2))
        return 1
    pb, vb = rp[0][0:3], rv[0][0:3]
    inter = union = 0
    for y in range(h - h // 12):
        for x in range(w):
            p = any(abs(rp[y][x * c + k] - pb[k]) > 18 for k in range(3))
            v = any(abs(rv[y][x * c2 + k] - vb[k]) > 6 for k in range(3))
            inter += p and v
            union += p or v
    iou = inter / float(union) if union else 0.0
    print("footprint IoU %.3f (page and view, same camera; at least %.2f)" % (iou, least))
    return 0 if iou >= least else 1


def check(report_path, tiles, points_path, pngs):
    rep = json.load(open(report_path))
    want = json.load(open(points_path))
    errors = json.load(open(os.path.join(tiles, "errors.json")))
    ok = True
    problems = rep["errors"] + rep["failed_requests"] + rep["http_errors"] + \
        ["external request " + u for u in rep["external_requests"]]
    for p in problems:
        print("error: %s" % p)
    print("errors %d" % len(problems))
    ok &= not problems
    got = rep.get("samples") or []
    bad, worst, diffs = 0, (0.0, ""), []
    if len(got) != len(want):
        print("samples: %d of %d" % (len(got), len(want)))
        ok = False
    for w, g in zip(want, got):
        if g.get("height") is None:
            bad += 1
            print("height: none at %.6f %.6f" % (w["lon"], w["lat"]))
            continue
        z, x, y = tile_of(w["lon"], w["lat"], g["level"])
        key = "%d/%d/%d" % (z, x, y)
        if key not in errors:
            bad += 1
            print("height: %s (level Cesium sampled) is not in errors.json" % key)
            continue
        lo, hi = tile_heights(tiles, z, x, y)
        tol = errors[key] + (hi - lo) / 32767.0 + UV_SLACK_M
        d = g["height"] - w["height"]
        diffs.append(abs(d))
        if abs(d) - tol > worst[0] or not worst[1]:
            worst = (abs(d) - tol, "%+.3f m at %.6f %.6f, tile %s, allowed %.3f" %
                     (d, w["lon"], w["lat"], key, tol))
        if abs(d) > tol:
            bad += 1
            print("height: Cesium %.3f, terrapatch point %.3f (%+.3f m) at %.6f %.6f; tile %s "
                  "measured error %.3f m, allowed %.3f" % (g["height"], w["height"], d, w["lon"],
                                                           w["lat"], key, errors[key], tol))
    diffs.sort()
    print("heights %d bad of %d (|Cesium - point|: median %.3f m, max %.3f m; nearest its limit: %s)"
          % (bad, len(want), diffs[len(diffs) // 2] if diffs else float("nan"),
             diffs[-1] if diffs else float("nan"), worst[1]))
    ok &= bad == 0 and len(got) == len(want)
    if pngs:
        f = differing(*pngs)
        print("screens %.1f%% of pixels differ (a channel by more than %d)" % (100 * f, PIXEL_STEP))
        ok &= f >= MIN_DIFFERENT
    return 0 if ok else 1


def main():
    cmd = sys.argv[1] if len(sys.argv) > 1 else ""
    if cmd == "points" and len(sys.argv) == 5:
        points(*sys.argv[2:])
    elif cmd == "tile" and len(sys.argv) == 5:
        print("%d/%d/%d" % deepest(sys.argv[2], float(sys.argv[3]), float(sys.argv[4])))
    elif cmd == "footprint" and len(sys.argv) == 5:
        sys.exit(footprint(sys.argv[2], sys.argv[3], float(sys.argv[4])))
    elif cmd == "check" and len(sys.argv) in (5, 7):
        sys.exit(check(sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5:]))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
