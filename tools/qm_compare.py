#!/usr/bin/env python3
"""qm_compare.py: the GDAL parts and the table of tools/qm_compare.sh (docs/PERFORMANCE.md, "Side
by side with martini- and delatin-based tilers"). Needs GDAL's Python bindings (osgeo) and numpy
(Debian: python3-gdal, python3-numpy).

  qm_compare.py grids LAYER.json DEM TILES.json GRIDS.f32 [SIZE]
      the tiles of our layer.json's `available` (every level, the same z/x/y for every tiler)
      with their level's bound (terrapatch.levels[z].geometric_error_m) into TILES.json, and per
      tile the DEM resampled by GDAL's warper (bilinear, to EPSG:4326) to a SIZE x SIZE grid
      (257 by default) whose posts lie on the tile's sides and corners (row 0 the north side), as
      float32 into GRIDS.f32; the web tilers read their DEM the same way (a warped window a tile).
      Where the grid leaves the DEM: GDAL's FillNodata (inverse distance, up to 64 posts), then
      0 m (our exporter: the nearest DEM post within 9 lattice cells, then 0 m).
  qm_compare.py posts DEM POSTS.bin
      every valid post of DEM (pixel centres; nodata skipped) at its WGS84 lon/lat (osr: the
      DEM's CRS to EPSG:4326, traditional lon/lat order): n float64 lon, n float64 lat, n float32
      heights, n uint8 flags (1: its 8 neighbours valid too) (what tools/qm_measure.mjs reads)
  qm_compare.py store-posts FULL.vtk POSTS.bin
      the store's own posts (what errors.json is measured against) from `terrapatch export
      STORE --full -o FULL.vtk`, the same layout as posts
  qm_compare.py table WORK_DIR
      the table from WORK_DIR's files (tools/qm_compare.sh's layout): time-*.txt (/usr/bin/time
      -v), measure-*.json, */stats.json, ours/errors.json; also WORK_DIR/summary.json
"""
import json
import os
import statistics
import sys

SETS = ("ours", "martini", "delatin")


def osgeo():
    try:
        from osgeo import gdal, osr
        import numpy as np
    except ImportError as e:
        sys.exit("qm_compare.py: %s: needs GDAL's Python bindings and numpy (Debian: python3-gdal "
                 "python3-numpy)" % e)
    gdal.UseExceptions()
    return gdal, osr, np


def tile_list(layer_file):
    layer = json.load(open(layer_file))
    levels = layer["terrapatch"]["levels"]
    tiles = []
    for z, ranges in enumerate(layer["available"]):
        size = 180.0 / (1 << z)
        for r in ranges:
            for y in range(r["startY"], r["endY"] + 1):
                for x in range(r["startX"], r["endX"] + 1):
                    tiles.append({"z": z, "x": x, "y": y, "bound": levels[z]["geometric_error_m"],
                                  "west": -180 + x * size, "south": -90 + y * size,
                                  "east": -180 + (x + 1) * size, "north": -90 + (y + 1) * size})
    return tiles


def read_dem(dem):
    """(dataset, heights as float64 with every void NaN): the tag, NaN, +-inf and for untagged
    Int16 -32768 and -32767 (SRTM's and DTED's voids), as terrapatch reads a DEM (io/src/dem_read.cpp)"""
    gdal, _, np = osgeo()
    ds = gdal.Open(dem)
    band = ds.GetRasterBand(1)
    h = band.ReadAsArray().astype("f8")
    nd = band.GetNoDataValue()
    void = ~np.isfinite(h) | (np.abs(h) >= 3.4e38)
    if nd is not None:
        void |= h == nd
    elif band.DataType == gdal.GDT_Int16:
        void |= (h == -32768) | (h == -32767)
    h[void] = np.nan
    return ds, h


def grids(layer_file, dem, list_out, grid_out, size=257):
    gdal, _, np = osgeo()
    tiles = tile_list(layer_file)
    ds, h = read_dem(dem)
    src = gdal.GetDriverByName("MEM").Create("", ds.RasterXSize, ds.RasterYSize, 1, gdal.GDT_Float32)
    src.SetGeoTransform(ds.GetGeoTransform())
    src.SetProjection(ds.GetProjection())
    src.GetRasterBand(1).SetNoDataValue(float("nan"))
    src.GetRasterBand(1).WriteArray(h.astype("f4"))
    nodata = float("nan")
    with open(grid_out + ".part", "wb") as f:
        for t in tiles:
            half = (t["east"] - t["west"]) / (size - 1) / 2  # posts on the sides: cells centred there
            ds = gdal.Warp("", src, format="MEM", dstSRS="EPSG:4326", width=size, height=size,
                           outputBounds=(t["west"] - half, t["south"] - half, t["east"] + half,
                                         t["north"] + half),
                           resampleAlg="bilinear", outputType=gdal.GDT_Float32,
                           srcNodata=nodata, dstNodata=-1e30, multithread=False)
            band = ds.GetRasterBand(1)
            a = band.ReadAsArray()
            if (a == -1e30).any() and (a != -1e30).any():
                gdal.FillNodata(band, None, 64, 0)
                a = band.ReadAsArray()
            a[a == -1e30] = 0.0
            f.write(np.ascontiguousarray(a, dtype="<f4").tobytes())
    os.replace(grid_out + ".part", grid_out)
    json.dump({"size": size, "tiles": tiles}, open(list_out, "w"))


def posts(dem, out):
    _, osr, np = osgeo()
    ds, h = read_dem(dem)
    ok = np.isfinite(h)
    inner = np.zeros_like(ok)  # the 8 neighbours valid too: the posts away from voids and edges
    inner[1:-1, 1:-1] = ok[1:-1, 1:-1]
    for dy in (-1, 0, 1):
        for dx in (-1, 0, 1):
            inner[1:-1, 1:-1] &= ok[1 + dy:ok.shape[0] - 1 + dy, 1 + dx:ok.shape[1] - 1 + dx]
    gt = ds.GetGeoTransform()
    rows, cols = np.nonzero(ok)
    x = gt[0] + (cols + 0.5) * gt[1] + (rows + 0.5) * gt[2]
    y = gt[3] + (cols + 0.5) * gt[4] + (rows + 0.5) * gt[5]
    srs, wgs = osr.SpatialReference(), osr.SpatialReference()
    srs.ImportFromWkt(ds.GetProjection())
    wgs.ImportFromEPSG(4326)
    for s in (srs, wgs):
        s.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
    if srs.IsSame(wgs):
        lon, lat = x, y
    else:
        ct = osr.CoordinateTransformation(srs, wgs)
        p = np.array(ct.TransformPoints(np.column_stack([x, y])))
        lon, lat = p[:, 0], p[:, 1]
    with open(out + ".part", "wb") as f:
        for arr, t in ((lon, "<f8"), (lat, "<f8"), (h[ok], "<f4"), (inner[ok], "u1")):
            f.write(np.ascontiguousarray(arr, dtype=t).tobytes())
    os.replace(out + ".part", out)


def store_posts(vtk, out):
    """the store's posts from `terrapatch export STORE --full -o X.vtk` (legacy binary VTK: the
    CRS's WKT in the field crs_wkt, POINTS n double, big-endian: projected x, y and the height)"""
    _, osr, np = osgeo()
    data = open(vtk, "rb").read()
    k = data.find(b"crs_wkt 1 1 string\n")
    p = data.find(b"\nPOINTS ")
    if k < 0 or p < 0:
        sys.exit("qm_compare.py: %s: no crs_wkt field or no POINTS (not terrapatch's legacy VTK?)" % vtk)
    k += len(b"crs_wkt 1 1 string\n")
    nb = {3: 1, 2: 2, 1: 4, 0: 8}[data[k] >> 6]  # VTK's binary string: its length, 1 to 8 bytes
    size = int.from_bytes(bytes([data[k] & 0x3F]) + data[k + 1:k + nb], "big")
    wkt = data[k + nb:k + nb + size].decode()
    line_end = data.find(b"\n", p + 1)
    n, kind = data[p + 8:line_end].split()
    n = int(n)
    if kind != b"double":
        sys.exit("qm_compare.py: %s: POINTS are %s, expected double" % (vtk, kind.decode()))
    xyz = np.frombuffer(data, ">f8", 3 * n, line_end + 1).reshape(n, 3)
    srs, wgs = osr.SpatialReference(), osr.SpatialReference()
    srs.ImportFromWkt(wkt)
    wgs.ImportFromEPSG(4326)
    for q in (srs, wgs):
        q.SetAxisMappingStrategy(osr.OAMS_TRADITIONAL_GIS_ORDER)
    ll = np.array(osr.CoordinateTransformation(srs, wgs).TransformPoints(np.ascontiguousarray(xyz[:, :2])))
    with open(out + ".part", "wb") as f:
        for arr, t in ((ll[:, 0], "<f8"), (ll[:, 1], "<f8"), (xyz[:, 2], "<f4"), (np.ones(n), "u1")):
            f.write(np.ascontiguousarray(arr, dtype=t).tobytes())
    os.replace(out + ".part", out)


def rusage(path):
    """(CPU seconds, wall seconds, peak RSS MB) from /usr/bin/time -v's report."""
    cpu = wall = rss = 0.0
    for line in open(path):
        k, _, v = line.strip().rpartition(": ")
        if k in ("User time (seconds)", "System time (seconds)"):
            cpu += float(v)
        elif k.startswith("Elapsed (wall clock) time"):
            parts = [float(p) for p in v.split(":")]
            wall = sum(p * 60 ** i for i, p in enumerate(reversed(parts)))
        elif k == "Maximum resident set size (kbytes)":
            rss = float(v) / 1024
    return cpu, wall, rss


def level_rows(m):
    out = {}
    for t in m["tiles"]:
        out.setdefault(t["z"], []).append(t)
    return out


def summarize(work, name):
    m = json.load(open(os.path.join(work, "measure-%s.json" % name)))
    tiles = m["tiles"]
    measured = [t for t in tiles if t["max_error"] is not None]
    ratios = [t["max_error"] / t["bound"] for t in measured]
    deep = max(t["z"] for t in tiles)
    deep_m = [t["max_error"] for t in measured if t["z"] == deep]
    deep_i = [t["max_error_inner"] for t in measured if t["z"] == deep]
    s = {"tiles": len(tiles), "triangles": sum(t["triangles"] for t in tiles),
         "bytes": sum(t["bytes"] for t in tiles), "pairs": m["pairs"],
         "watertight_pairs": m["watertight_pairs"], "unplaced_posts": m["unplaced_posts"],
         "worst_ratio": max(ratios), "median_ratio": statistics.median(ratios),
         "tiles_over_bound": sum(r > 1 for r in ratios), "deep_zoom": deep,
         "deep_bound": next(t["bound"] for t in tiles if t["z"] == deep),
         "deep_max": max(deep_m), "deep_median": statistics.median(deep_m),
         "deep_inner_max": max(deep_i), "deep_inner_median": statistics.median(deep_i),
         "levels": {}, "tile_errors": {}}
    for z, ts in sorted(level_rows(m).items()):
        e = [t["max_error"] for t in ts if t["max_error"] is not None]
        s["levels"][z] = {"tiles": len(ts), "triangles": sum(t["triangles"] for t in ts),
                          "bytes": sum(t["bytes"] for t in ts), "bound": ts[0]["bound"],
                          "max": max(e) if e else None, "median": statistics.median(e) if e else None,
                          "pairs": m.get("pairs_by_level", {}).get(str(z), [0, 0])}
    if name == "ours":
        s["cpu_s"], s["wall_s"], s["rss_mb"] = rusage(os.path.join(work, "time-export.txt"))
        s["build_cpu_s"] = rusage(os.path.join(work, "time-build.txt"))[0]
        s["mesh_cpu_s"] = None
    else:
        g = rusage(os.path.join(work, "time-grids.txt"))
        c = rusage(os.path.join(work, "time-%s.txt" % name))
        st = json.load(open(os.path.join(work, name, "stats.json")))
        s["cpu_s"], s["wall_s"], s["rss_mb"] = g[0] + c[0], g[1] + c[1], max(g[2], c[2])
        s["grids_cpu_s"], s["grids_rss_mb"], s["node_cpu_s"], s["node_rss_mb"] = g[0], g[2], c[0], c[2]
        s["mesh_cpu_s"], s["encode_s"] = st["mesh_ms"] / 1e3, st["encode_ms"] / 1e3
    return s


def store_check(work, errs):
    """ours measured against the store's own posts (measure-ours-store.json) beside errors.json"""
    path = os.path.join(work, "measure-ours-store.json")
    if not os.path.exists(path):
        return None
    tiles = [t for t in json.load(open(path))["tiles"] if t["max_error"] is not None]
    key = lambda t: "%d/%d/%d" % (t["z"], t["x"], t["y"])
    big = [t for t in tiles if t["posts"] >= 1000]
    diff = [errs[key(t)] - t["max_error"] for t in big]
    return {"tiles": len(tiles), "tiles_1000_posts": len(big),
            "within_2cm_1000_posts": sum(abs(d) <= 0.02 for d in diff),
            "median_abs_diff_1000_posts_m": statistics.median(abs(d) for d in diff) if diff else None,
            "max_abs_diff_1000_posts_m": max((abs(d) for d in diff), default=0.0),
            "max_shortfall_ratio_1000_posts": max((d / errs[key(t)] for d, t in zip(diff, big)), default=0.0),
            "max_excess_m": max(t["max_error"] - errs[key(t)] for t in tiles),
            "max_shortfall_m": max(errs[key(t)] - t["max_error"] for t in tiles)}


def print_levels(sums):
    print("per level: tiles, bound; per tiler: triangles, bytes, true max (median tile) in m, "
          "neighbour pairs watertight")
    for z in sorted(sums["ours"]["levels"]):
        cells = []
        for n in SETS:
            lv = sums[n]["levels"][z]
            err = "—" if lv["max"] is None else "%.2f (%.2f)" % (lv["max"], lv["median"])
            tight = " %d/%d watertight" % (lv["pairs"][1], lv["pairs"][0]) if lv["pairs"][0] else ""
            cells.append("%s %d tri %d B %s%s" % (n, lv["triangles"], lv["bytes"], err, tight))
        print("z%d: %d tiles, bound %.2f m; %s" % (z, sums["ours"]["levels"][z]["tiles"],
                                                  sums["ours"]["levels"][z]["bound"], "; ".join(cells)))


def table(work):
    sums = {n: summarize(work, n) for n in SETS}
    errs = json.load(open(os.path.join(work, "ours", "errors.json")))
    print("| tiler | tiles | triangles (a tile) | bytes gzip'd (a tile) | CPU s total (meshing) | "
          "peak RSS MB | true error / bound: worst tile, median tile (tiles over) | deepest level z%d: "
          "bound → true max, median tile (posts away from voids) | watertight |" % sums["ours"]["deep_zoom"])
    print("|---|---|---|---|---|---|---|---|---|")
    for n in SETS:
        s = sums[n]
        mesh = "%.2f" % s["mesh_cpu_s"] if s["mesh_cpu_s"] is not None else "—"
        print("| %s | %d | %d (%.0f) | %d (%.0f) | %.2f (%s) | %.0f | %.2f, %.2f (%d) | %.2f → %.2f, %.2f m (%.2f, %.2f) | %s (%d/%d pairs) |" % (
            n, s["tiles"], s["triangles"], s["triangles"] / s["tiles"], s["bytes"], s["bytes"] / s["tiles"],
            s["cpu_s"], mesh, s["rss_mb"], s["worst_ratio"], s["median_ratio"], s["tiles_over_bound"],
            s["deep_bound"], s["deep_max"], s["deep_median"], s["deep_inner_max"], s["deep_inner_median"],
            "yes" if s["watertight_pairs"] == s["pairs"] else "no", s["watertight_pairs"], s["pairs"]))
    print()
    print_levels(sums)
    print()
    m, d = sums["martini"], sums["delatin"]
    print("ours: build %.2f s CPU (not in the total; the export's total includes its own measure of every "
          "tile); martini/delatin: grids (GDAL's warp, shared, in each total) %.2f s CPU, %.0f MB; the "
          "tiler's node process %.2f / %.2f s CPU, %.0f / %.0f MB, of which encode+gzip %.2f / %.2f s" % (
              sums["ours"]["build_cpu_s"], m["grids_cpu_s"], m["grids_rss_mb"], m["node_cpu_s"],
              d["node_cpu_s"], m["node_rss_mb"], d["node_rss_mb"], m["encode_s"], d["encode_s"]))
    for n in SETS:
        if sums[n]["unplaced_posts"]:
            print("%s: %d posts outside every triangle of their tile (holes)" % (n, sums[n]["unplaced_posts"]))
    sc = store_check(work, errs)
    if sc:
        print("ours against the store's own posts (what errors.json measures), %d tiles: on the %d tiles of "
              ">= 1000 posts, %d within 2 cm of errors.json, median |difference| %.4f m, largest %.4f m "
              "(errors.json %.1f %% higher: it also measures the lattice posts); nowhere above errors.json by "
              "more than %.4f m" % (sc["tiles"], sc["tiles_1000_posts"], sc["within_2cm_1000_posts"],
                                    sc["median_abs_diff_1000_posts_m"] or 0, sc["max_abs_diff_1000_posts_m"],
                                    100 * sc["max_shortfall_ratio_1000_posts"], sc["max_excess_m"]))
    for n in SETS:
        del sums[n]["tile_errors"]
    sums["store_check"] = sc
    json.dump(sums, open(os.path.join(work, "summary.json"), "w"), indent=1)


def main():
    a = sys.argv[1:]
    if len(a) in (5, 6) and a[0] == "grids":
        grids(a[1], a[2], a[3], a[4], int(a[5]) if len(a) == 6 else 257)
    elif len(a) == 3 and a[0] == "posts":
        posts(a[1], a[2])
    elif len(a) == 3 and a[0] == "store-posts":
        store_posts(a[1], a[2])
    elif len(a) == 2 and a[0] == "table":
        table(a[1])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
