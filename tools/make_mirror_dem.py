#!/usr/bin/env python3
"""tools/make_mirror_dem.py: a large test DEM with real relief everywhere, made by mirroring one
real tile's metric grid (issue 12: terrains like Vanek & Jezek's, up to 20481^2 at ten metres).

  tools/make_mirror_dem.py [options] SIZE OUT_DIR [TILE]

SIZE      the output is SIZE x SIZE samples (any N >= 2; e.g. 8193, 20481, 65537)
OUT_DIR   created if missing; gets OUT_DIR/mirror_<SIZE>.vrt and the four small copies
TILE      default data/N42E001.hgt (in the repository): any DEM GDAL reads
          that has a CRS

Options:
  --pixel-m M     pixel size of the mosaic in metres (default 10)
  --real-slopes   resample the tile's grid to --pixel-m posts (cubic spline) before mirroring,
                  so the relief keeps its real size and slopes (smooth between the tile's own
                  posts) instead of being compressed horizontally; the VRT is then named
                  mirror_<SIZE>_real.vrt
  --keep-voids    keep the tile's voids (SRTM holes) instead of filling them
  --read          read the whole mosaic once (gdalinfo -stats) and print the time and MB/s
  -h, --help      this text

What it makes:
  1. The tile's render grid, once: the tile warped (gdalwarp, bilinear, Float32, nodata
     -32768) to the WGS84 UTM zone of its centre, at a square pixel equal to its finest post
     spacing (what `terrapatch info` warps to; 67.93 m for N42E001 in EPSG:32631), cropped to
     the largest axis-aligned rectangle inside the tile's footprint, so the slanted edges of a
     geographic tile in UTM leave no nodata margin (N42E001: 1181 x 1614 posts). A tile
     already in its zone keeps its own posts. A tile whose data does not fill its rectangle
     (nodata margins) gets them filled with made-up heights: prefer full tiles (SRTM).
  2. Its voids filled (gdal_fillnodata.py, every void whatever its size), so the mosaic has
     relief everywhere: a benchmark over it measures terrain, not holes. --keep-voids keeps
     them, mirrored with the rest, for testing how the viewer handles voids at scale.
  3. Four raw Float32 copies (EHdr .bil/.hdr, a few MB each): the grid as is
     (<stem>_0.bil), flipped left-right (_x), top-bottom (_y) and both (_xy).
  4. mirror_<SIZE>.vrt: a GDAL VRT of SIZE x SIZE that tiles the four copies in a
     checkerboard. Copies are placed every (w - 1) columns and (h - 1) rows of the w x h
     grid, each neighbour the mirror image of the other across the shared row or column, so
     the seam post is the grid's edge post, once: along a row the mosaic reads the grid's
     columns 0, 1, .., w-2, w-1, w-2, .., 1, 0, 1, .. The surface is continuous at every seam
     (its slope flips, as in any mirror) with no repeated sample, i.e. no flat step. The VRT
     references the small copies: no big file is written (65537^2 Float32 would be 17 GB).

Georeference: the tile's UTM zone (EPSG:326zz or 327zz), pixel --pixel-m, centred on the
zone's central meridian at 45 degrees latitude (northing 4985000, or 5015000 in the south),
so 65537^2 at 10 m (655 km) spans eastings 172..828 km and stays a sensible UTM map. The
relief is the tile's real relief compressed horizontally (66.7 m posts drawn 10 m apart for
N42E001, x6.7): heights are real, slopes are steeper than real. With --real-slopes the tile's
grid is first resampled to --pixel-m posts (gdal_translate -r cubicspline; N42E001 at 10 m:
8018 x 10958 posts, 351 MB per copy): real slopes at 10 m posts, but with no detail finer than
the tile's 68 m between them. Real 10 m DEMs lie between the two: the compressed mosaic is
the hard case for a level-of-detail renderer, the resampled one the easy case.

Needs the GDAL command-line tools (Debian: gdal-bin; `make deps` installs it) and Python 3
(no Python GDAL module is used: the flips are done on the raw files).
"""
import array
import os
import shutil
import subprocess
import sys
import time

NODATA = -32768.0
MAX_HALF_EXTENT_M = 450000.0  # eastings 50..950 km: a sensible UTM map


def die(msg, code=1):
    sys.stderr.write("make_mirror_dem: %s\n" % msg)
    sys.exit(code)


def usage_error(msg):
    die("%s (see --help)" % msg, 2)


def need_tool(name):
    if shutil.which(name) is None:
        die("%s not found: the GDAL command-line tools are missing "
            "(Debian package gdal-bin; `make deps` installs it)" % name)


def run(args, stdin=None):
    """Runs a GDAL tool; its stdout, or a clear error naming the command."""
    p = subprocess.run(args, input=stdin, capture_output=True, text=True)
    if p.returncode != 0:
        die("%s failed (exit %d): %s" % (" ".join(args), p.returncode, p.stderr.strip()))
    return p.stdout


def transform(tile, t_srs, pixel_line):
    """Maps (pixel, line) positions of TILE to T_SRS with gdaltransform; [(x, y)]."""
    text = "".join("%.6f %.6f\n" % p for p in pixel_line)
    out = run(["gdaltransform", "-t_srs", t_srs, tile], stdin=text).split("\n")
    pts = []
    for line in out:
        f = line.split()
        if len(f) >= 2:
            pts.append((float(f[0]), float(f[1])))
    if len(pts) != len(pixel_line):
        die("gdaltransform gave %d points for %d: does %s have a CRS?" % (len(pts), len(pixel_line), tile))
    return pts


def raster_size(path):
    for line in run(["gdalinfo", path]).split("\n"):
        if line.startswith("Size is "):
            w, h = line[len("Size is "):].split(",")
            return int(w), int(h)
    die("gdalinfo %s: no 'Size is' line" % path)


def render_grid(tile, out_dir, stem, fill):
    """Steps 1-2: the cropped, filled UTM grid of TILE as OUT_DIR/<stem>_0.bil; (w, h, epsg,
    res_m, voids_found, voids_left)."""
    info = run(["gdalinfo", tile])
    if "Coordinate System is `'" in info or "Coordinate System is:" not in info:
        die("%s has no CRS: the tool needs one to find its UTM zone (a .prj beside it, or "
            "gdal_translate -a_srs EPSG:N)" % tile)
    tw, th = raster_size(tile)
    if tw < 2 or th < 2:
        die("%s is %dx%d: a tile needs at least 2x2 posts" % (tile, tw, th))
    (lon, lat), = transform(tile, "EPSG:4326", [(tw / 2.0, th / 2.0)])
    zone = int((lon + 180.0) // 6.0) % 60 + 1  # no Norway/Svalbard exceptions: any zone will do
    epsg = (32600 if lat >= 0 else 32700) + zone
    t_srs = "EPSG:%d" % epsg

    # Finest post spacing in the zone: one column and one row step at the corners and centre.
    at = [(0.5, 0.5), (tw - 1.5, 0.5), (0.5, th - 1.5), (tw - 1.5, th - 1.5), (tw / 2.0, th / 2.0)]
    probe = []
    for x, y in at:
        probe += [(x, y), (x + 1, y), (x, y + 1)]
    p = transform(tile, t_srs, probe)
    res = min(min(((p[i + 1][0] - p[i][0]) ** 2 + (p[i + 1][1] - p[i][1]) ** 2) ** 0.5,
                  ((p[i + 2][0] - p[i][0]) ** 2 + (p[i + 2][1] - p[i][1]) ** 2) ** 0.5)
              for i in range(0, len(p), 3))

    # The largest axis-aligned box inside the footprint of the posts (centres 0.5 .. n - 0.5),
    # sampled every few posts along each edge (a parallel is a curve in UTM).
    def edge(n):
        return [0.5 + (n - 1) * k / 64.0 for k in range(65)]
    left = transform(tile, t_srs, [(0.5, y) for y in edge(th)])
    right = transform(tile, t_srs, [(tw - 0.5, y) for y in edge(th)])
    top = transform(tile, t_srs, [(x, 0.5) for x in edge(tw)])
    bottom = transform(tile, t_srs, [(x, th - 0.5) for x in edge(tw)])
    x0, x1 = max(q[0] for q in left), min(q[0] for q in right)
    y0, y1 = max(q[1] for q in bottom), min(q[1] for q in top)
    if not res > 0.01:
        die("%s: its post spacing in %s is %g m" % (tile, t_srs, res))
    if x1 <= x0 or y1 <= y0:
        die("%s is not stored north up, west to east (or is too rotated in %s): no box fits "
            "inside it" % (tile, t_srs))
    # Posts from (x0, y1) on, every res: the first post on the footprint's corner, so a tile
    # already in the zone keeps its own posts (bilinear at a post is the post).
    w, h = int((x1 - x0) / res + 1e-6) + 1, int((y1 - y0) / res + 1e-6) + 1
    if w < 2 or h < 2:
        die("%s: its grid in %s is only %dx%d posts" % (tile, t_srs, w, h))

    warped = os.path.join(out_dir, stem + "_warp.tif")
    run(["gdalwarp", "-q", "-overwrite", "-t_srs", t_srs, "-r", "bilinear", "-ot", "Float32",
         "-dstnodata", "%g" % NODATA, "-te", "%.6f" % (x0 - res / 2), "%.6f" % (y1 - (h - 0.5) * res),
         "%.6f" % (x0 + (w - 0.5) * res), "%.6f" % (y1 + res / 2), "-ts", str(w), str(h), tile, warped])
    src = warped
    if fill:
        need_tool("gdal_fillnodata.py")
        filled = os.path.join(out_dir, stem + "_fill.tif")
        if os.path.exists(filled):
            os.remove(filled)
        run(["gdal_fillnodata.py", "-q", "-md", str(max(w, h)), warped, filled])
        src = filled
    base = os.path.join(out_dir, stem + "_0.bil")
    run(["gdal_translate", "-q", "-of", "EHdr", "-ot", "Float32", src, base])
    voids_found = count_voids_tif(warped, w, h)
    voids_left = count_voids(base, w, h)
    for f in (warped, os.path.join(out_dir, stem + "_fill.tif"), base + ".aux.xml"):
        if os.path.exists(f):
            os.remove(f)
    return w, h, epsg, res, voids_found, voids_left


def resample(out_dir, stem, w, h, res, pixel_m):
    """--real-slopes: <stem>_0.bil (w x h posts every res m) resampled in place to posts every
    pixel_m over the same span (edge posts kept); the new (w, h)."""
    nw = int(round((w - 1) * res / pixel_m)) + 1
    nh = int(round((h - 1) * res / pixel_m)) + 1
    base = os.path.join(out_dir, stem + "_0.bil")
    tmp = os.path.join(out_dir, stem + "_rs.bil")
    run(["gdal_translate", "-q", "-of", "EHdr", "-ot", "Float32", "-r", "cubicspline",
         "-outsize", str(nw), str(nh), base, tmp])
    for ext in (".bil", ".hdr"):
        os.replace(tmp[:-4] + ext, base[:-4] + ext)
    for ext in (".prj", ".bil.aux.xml"):
        for f in (tmp[:-4] + ext, base[:-4] + ext):
            if os.path.exists(f) and f.startswith(tmp[:-4]):
                os.remove(f)
    return nw, nh


def read_floats(path, w, h):
    """Float32 samples of a raw .bil (native order after swapping per its .hdr)."""
    a = array.array("f")
    with open(path, "rb") as f:
        a.frombytes(f.read())
    if len(a) != w * h:
        die("%s holds %d samples, expected %dx%d" % (path, len(a), w, h))
    if header_byteorder(path) != sys.byteorder:
        a.byteswap()
    return a


def header_byteorder(bil):
    hdr = bil[:-4] + ".hdr"
    with open(hdr) as f:
        for line in f:
            k = line.split()
            if len(k) == 2 and k[0].upper() == "BYTEORDER":
                return "big" if k[1].upper() == "M" else "little"
    return "little"


def count_voids(bil, w, h):
    """Nodata (or NaN) samples in a raw Float32 .bil."""
    return sum(1 for v in read_floats(bil, w, h) if v == NODATA or v != v)


def count_voids_tif(tif, w, h):
    """Nodata samples in a GeoTIFF, read through a raw copy (removed after)."""
    raw = tif[:-4] + "_raw.bil"
    run(["gdal_translate", "-q", "-of", "EHdr", "-ot", "Float32", tif, raw])
    n = count_voids(raw, w, h)
    for ext in (".bil", ".hdr", ".prj", ".bil.aux.xml"):
        if os.path.exists(raw[:-4] + ext):
            os.remove(raw[:-4] + ext)
    return n


def write_copies(out_dir, stem, w, h):
    """Step 3: the three mirror images of <stem>_0.bil, with headers minus the georeference
    (their placement is the VRT's)."""
    base = os.path.join(out_dir, stem + "_0.bil")
    a = read_floats(base, w, h)
    if header_byteorder(base) != sys.byteorder:
        a.byteswap()  # back to the file's order: flips move whole samples
    rows = [a[r * w:(r + 1) * w] for r in range(h)]
    flips = {
        "x": [r[::-1] for r in rows],
        "y": rows[::-1],
        "xy": [r[::-1] for r in rows[::-1]],
    }
    with open(base[:-4] + ".hdr") as f:
        hdr = [l for l in f if l.split()[:1] and l.split()[0].upper() not in
               ("ULXMAP", "ULYMAP", "XDIM", "YDIM")]
    for name, rs in flips.items():
        path = os.path.join(out_dir, "%s_%s" % (stem, name))
        with open(path + ".bil", "wb") as f:
            for r in rs:
                r.tofile(f)
        with open(path + ".hdr", "w") as f:
            f.writelines(hdr)
        for stale in (".prj", ".bil.aux.xml"):
            if os.path.exists(path + stale):
                os.remove(path + stale)


def placements(size, n):
    """Copies along one axis of SIZE posts over a grid of N posts: [(start, count, flipped)],
    every (n - 1) posts, odd copies flipped; each copy contributes its first n - 1 posts (the
    next copy's first post is this one's last), the last copy is cropped."""
    step, out, i = n - 1, [], 0
    while i * step < size:
        out.append((i * step, min(step, size - i * step), i % 2 == 1))
        i += 1
    return out


def write_vrt(path, size, stem, w, h, epsg, pixel_m, north):
    half = size * pixel_m / 2.0
    ox = 500000.0 - half
    oy = (4985000.0 if north else 5015000.0) + half
    cols, rows = placements(size, w), placements(size, h)
    src = []
    for (dy, ny, fy) in rows:
        for (dx, nx, fx) in cols:
            name = "%s_%s.bil" % (stem, {(False, False): "0", (True, False): "x",
                                         (False, True): "y", (True, True): "xy"}[(fx, fy)])
            src.append(
                '    <SimpleSource>\n'
                '      <SourceFilename relativeToVRT="1">%s</SourceFilename>\n'
                '      <SourceBand>1</SourceBand>\n'
                '      <SourceProperties RasterXSize="%d" RasterYSize="%d" DataType="Float32" '
                'BlockXSize="%d" BlockYSize="1"/>\n'
                '      <SrcRect xOff="0" yOff="0" xSize="%d" ySize="%d"/>\n'
                '      <DstRect xOff="%d" yOff="%d" xSize="%d" ySize="%d"/>\n'
                '    </SimpleSource>\n' % (name, w, h, w, nx, ny, dx, dy, nx, ny))
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write('<VRTDataset rasterXSize="%d" rasterYSize="%d">\n' % (size, size))
        f.write('  <SRS dataAxisToSRSAxisMapping="1,2">EPSG:%d</SRS>\n' % epsg)
        f.write('  <GeoTransform>%.3f, %.6g, 0, %.3f, 0, %.6g</GeoTransform>\n'
                % (ox, pixel_m, oy, -pixel_m))
        f.write('  <VRTRasterBand dataType="Float32" band="1">\n')
        f.write('    <NoDataValue>%g</NoDataValue>\n' % NODATA)
        f.writelines(src)
        f.write('  </VRTRasterBand>\n</VRTDataset>\n')
    os.replace(tmp, path)
    return len(src), (ox, oy - size * pixel_m, ox + size * pixel_m, oy)


def main(argv):
    pixel_m, fill, read, real, pos = 10.0, True, False, False, []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            print(__doc__.strip())
            return 0
        elif a == "--keep-voids":
            fill = False
        elif a == "--read":
            read = True
        elif a == "--real-slopes":
            real = True
        elif a == "--pixel-m":
            i += 1
            try:
                pixel_m = float(argv[i])
            except (IndexError, ValueError):
                usage_error("--pixel-m needs a number of metres")
            if not pixel_m > 0 or pixel_m != pixel_m:
                usage_error("--pixel-m must be positive, got %g" % pixel_m)
        elif a.startswith("-") and len(a) > 1 and not a[1:].isdigit():
            usage_error("unknown option '%s'" % a)
        else:
            pos.append(a)
        i += 1
    if len(pos) not in (2, 3):
        usage_error("expected SIZE OUT_DIR [TILE], got %d argument(s)" % len(pos))
    try:
        size = int(pos[0])
    except ValueError:
        usage_error("SIZE must be a whole number of samples, got '%s'" % pos[0])
    if size < 2:
        usage_error("SIZE must be at least 2, got %d" % size)
    if size > 2147483647:
        usage_error("SIZE %d is beyond what GDAL rasters hold (2^31 - 1)" % size)
    if size * pixel_m / 2.0 > MAX_HALF_EXTENT_M:
        usage_error("%d samples at %g m span %.0f km: more than the %.0f km a UTM map holds "
                    "sensibly (use a smaller --pixel-m)" % (size, pixel_m, size * pixel_m / 1e3,
                                                           2 * MAX_HALF_EXTENT_M / 1e3))
    out_dir = pos[1]
    here = os.path.dirname(os.path.abspath(__file__))
    tile = pos[2] if len(pos) == 3 else os.path.normpath(
        os.path.join(here, "..", "data", "N42E001.hgt"))
    if not os.path.isfile(tile):
        die("tile %s not found (give TILE, a DEM GDAL reads)" % tile)
    for t in ("gdalinfo", "gdalwarp", "gdal_translate", "gdaltransform"):
        need_tool(t)
    os.makedirs(out_dir, exist_ok=True)

    t0 = time.time()
    stem = os.path.splitext(os.path.basename(tile))[0] + ("_filled" if fill else "_voids")
    if real:
        stem += "_real%g" % pixel_m
    w, h, epsg, res, voids_found, voids_left = render_grid(tile, out_dir, stem, fill)
    tile_w, tile_h = w, h
    if real:
        w, h = resample(out_dir, stem, w, h, res, pixel_m)
    write_copies(out_dir, stem, w, h)
    vrt = os.path.join(out_dir, "mirror_%d%s.vrt" % (size, "_real" if real else ""))
    nsrc, ext = write_vrt(vrt, size, stem, w, h, epsg, pixel_m, epsg < 32700)
    made_s = time.time() - t0

    print("tile:    %s" % tile)
    print("grid:    %dx%d at %.2f m in EPSG:%d; %d void samples in the tile's grid, %d left%s"
          % (tile_w, tile_h, res, epsg, voids_found, voids_left, "" if fill else " (--keep-voids)"))
    if real:
        print("resampled: %dx%d at %g m (cubic spline; real slopes)" % (w, h, pixel_m))
    print("copies:  %s_{0,x,y,xy}.bil, %.1f MB each" % (stem, w * h * 4 / 1e6))
    print("mosaic:  %s: %dx%d Float32 at %g m (%s), %d sources, copies every %dx%d samples"
          % (vrt, size, size, pixel_m, "real size" if real else
             "x%.1f horizontal compression" % (res / pixel_m), nsrc, w - 1, h - 1))
    print("extent:  EPSG:%d x %.0f .. %.0f, y %.0f .. %.0f (%.1f km square)"
          % (epsg, ext[0], ext[2], ext[1], ext[3], size * pixel_m / 1e3))
    print("made in: %.1f s; a full read is %.2f GB of Float32" % (made_s, size * size * 4 / 1e9))
    if read:
        # gdalinfo -stats writes the statistics into the VRT it reads: read a copy instead
        probe = os.path.join(out_dir, ".read_%d.vrt" % size)
        shutil.copyfile(vrt, probe)
        t0 = time.time()
        try:
            out = run(["gdalinfo", "-stats", probe])
        finally:
            for f in (probe, probe + ".aux.xml"):
                if os.path.exists(f):
                    os.remove(f)
        s = time.time() - t0
        stats = [l.strip() for l in out.split("\n") if "Minimum=" in l]
        print("read:    gdalinfo -stats %.1f s, %.0f MB/s (Float32); %s"
              % (s, size * size * 4 / 1e6 / s, stats[0] if stats else "no statistics"))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
