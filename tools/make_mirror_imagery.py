#!/usr/bin/env python3
"""tools/make_mirror_imagery.py: a large test image (an "orthophoto" of 32768^2 pixels or more)
made by mirroring one real image in a checkerboard, over exactly the extent of a given DEM
(issue 15: imagery beyond the GPU's texture limit; the companion of make_mirror_dem.py).

  tools/make_mirror_imagery.py [options] SIZE OUT_DIR --like DEM [IMAGE]

SIZE      the output is SIZE pixels wide (any N >= 2; e.g. 32768, 65536); its height follows
          from the DEM's extent (SIZE for a square DEM)
OUT_DIR   created if missing; gets OUT_DIR/imagery_<SIZE>.vrt and the four small copies
--like DEM  the DEM (any raster GDAL reads, with a CRS; e.g. the mirror_8193.vrt of
          `tools/make_mirror_dem.py 8193 DIR`) whose extent and CRS the image takes. For a
          store, give the DEM or VRT it was built from (a store of a projected DEM keeps its
          grid)
IMAGE     default data/craterlake-imagery-30m.tif (in the repository): any
          image GDAL reads, RGB or RGBA bytes

Options:
  --keep-alpha    keep the image's alpha band (its transparent corners stay transparent:
                  empty blocks in the pyramid); by default only its colour is used, so the
                  mosaic is opaque everywhere (the craterlake image's transparent parts are a
                  pale yellow, like a map's paper)
  -h, --help      this text

What it makes:
  1. Four raw copies of the image's pixels (EHdr .bil/.hdr, band-interleaved by line, a few
     hundred KB each): as is (<stem>_0.bil), flipped left-right (_x), top-bottom (_y) and both
     (_xy). No warp: the image's pixels are used as they are, whatever its CRS.
  2. imagery_<SIZE>.vrt: a GDAL VRT of SIZE pixels across the DEM's extent that tiles the four
     copies in a checkerboard, a copy every w columns and h rows of the w x h image, each the
     mirror image of its neighbours (pixels are areas: the edge column is repeated, mirrored,
     so colours are continuous across every seam). Georeference: the DEM's CRS, origin and
     extent, pixel size = the DEM's extent / SIZE (32768 pixels over the 81.93 km of an 8193^2
     DEM at 10 m: 2.5003 m).

The place is made up: the image shows Crater Lake (Oregon) repeated, drawn wherever the DEM
lies (the mirror DEMs sit in a UTM zone of Spain); the image's own georeference is ignored. It
is for measuring how terrapatch handles imagery of this size (`terrapatch imagery`, the
viewer's clipmap), not for looking at a real place. The VRT references the small copies: no
big file is written (32768^2 RGB would be 3.2 GB).

Needs the GDAL command-line tools (Debian: gdal-bin) and Python 3 (no Python GDAL module).
"""
import os
import shutil
import subprocess
import sys
import time


def die(msg, code=1):
    sys.stderr.write("make_mirror_imagery: %s\n" % msg)
    sys.exit(code)


def usage_error(msg):
    die("%s (see --help)" % msg, 2)


def need_tool(name):
    if shutil.which(name) is None:
        die("%s not found: the GDAL command-line tools are missing "
            "(Debian package gdal-bin; `make deps` installs it)" % name)


def run(args):
    """Runs a GDAL tool; its stdout, or a clear error naming the command."""
    p = subprocess.run(args, capture_output=True, text=True)
    if p.returncode != 0:
        die("%s failed (exit %d): %s" % (" ".join(args), p.returncode, p.stderr.strip()))
    return p.stdout


def like_grid(dem):
    """(width, height, geotransform, srs_wkt) of DEM, from gdalinfo -json."""
    import json
    info = json.loads(run(["gdalinfo", "-json", dem]))
    wkt = info.get("coordinateSystem", {}).get("wkt", "")
    gt = info.get("geoTransform")
    if not wkt or not gt:
        die("%s has no CRS or no geotransform: the image needs both to take its place" % dem)
    if gt[2] != 0 or gt[4] != 0:
        die("%s is rotated (geotransform %s): not supported" % (dem, gt))
    w, h = info["size"]
    mapping = info.get("coordinateSystem", {}).get("dataAxisToSRSAxisMapping", [1, 2])
    return w, h, gt, wkt, ",".join(str(m) for m in mapping)


def image_bands(image):
    """(width, height, bands) of IMAGE, checking its bands are bytes."""
    import json
    info = json.loads(run(["gdalinfo", "-json", image]))
    w, h = info["size"]
    bands = info.get("bands", [])
    if len(bands) < 3 or any(b.get("type") != "Byte" for b in bands):
        die("%s: expected 3 or 4 bands of bytes (RGB or RGBA), got %s"
            % (image, [b.get("type") for b in bands]))
    return w, h, len(bands)


def write_copies(image, out_dir, stem, nb):
    """Step 1: the image and its three mirror images as raw band-interleaved-by-line files."""
    base = os.path.join(out_dir, stem + "_0.bil")
    args = ["gdal_translate", "-q", "-of", "EHdr"]
    for b in range(1, nb + 1):
        args += ["-b", str(b)]
    run(args + [image, base])
    with open(base, "rb") as f:
        data = f.read()
    with open(base[:-4] + ".hdr") as f:
        hdr = [l for l in f if l.split()[:1] and l.split()[0].upper() not in
               ("ULXMAP", "ULYMAP", "XDIM", "YDIM")]
    with open(base[:-4] + ".hdr", "w") as f:
        f.writelines(hdr)
    return data, hdr


def flip_copies(data, hdr, out_dir, stem, w, h, nb):
    rowbytes = w * nb
    rows = [data[r * rowbytes:(r + 1) * rowbytes] for r in range(h)]

    def flip_x(row):
        return b"".join(row[b * w:(b + 1) * w][::-1] for b in range(nb))
    flips = {"x": [flip_x(r) for r in rows], "y": rows[::-1],
             "xy": [flip_x(r) for r in rows[::-1]]}
    for name, rs in flips.items():
        path = os.path.join(out_dir, "%s_%s" % (stem, name))
        with open(path + ".bil", "wb") as f:
            f.write(b"".join(rs))
        with open(path + ".hdr", "w") as f:
            f.writelines(hdr)
    for name in ("0", "x", "y", "xy"):
        for stale in (".prj", ".bil.aux.xml", ".stx"):
            p = os.path.join(out_dir, "%s_%s%s" % (stem, name, stale))
            if os.path.exists(p):
                os.remove(p)


def placements(size, n):
    """Copies along one axis of SIZE pixels of an image N pixels long: [(start, count,
    flipped)], every N pixels, odd copies flipped, the last one cropped."""
    out, i = [], 0
    while i * n < size:
        out.append((i * n, min(n, size - i * n), i % 2 == 1))
        i += 1
    return out


def write_vrt(path, sx, sy, stem, w, h, nb, gt, wkt, mapping):
    cols, rows = placements(sx, w), placements(sy, h)
    names = {(False, False): "0", (True, False): "x", (False, True): "y", (True, True): "xy"}
    interp = ["Red", "Green", "Blue", "Alpha"]
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        f.write('<VRTDataset rasterXSize="%d" rasterYSize="%d">\n' % (sx, sy))
        f.write('  <SRS dataAxisToSRSAxisMapping="%s">%s</SRS>\n'
                % (mapping, wkt.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
                .replace('"', "&quot;")))
        f.write('  <GeoTransform>%.17g, %.17g, 0, %.17g, 0, %.17g</GeoTransform>\n' % gt)
        for b in range(1, nb + 1):
            f.write('  <VRTRasterBand dataType="Byte" band="%d">\n' % b)
            f.write('    <ColorInterp>%s</ColorInterp>\n' % interp[b - 1])
            for (dy, ny, fy) in rows:
                for (dx, nx, fx) in cols:
                    f.write(
                        '    <SimpleSource>\n'
                        '      <SourceFilename relativeToVRT="1">%s_%s.bil</SourceFilename>\n'
                        '      <SourceBand>%d</SourceBand>\n'
                        '      <SourceProperties RasterXSize="%d" RasterYSize="%d" '
                        'DataType="Byte" BlockXSize="%d" BlockYSize="1"/>\n'
                        '      <SrcRect xOff="0" yOff="0" xSize="%d" ySize="%d"/>\n'
                        '      <DstRect xOff="%d" yOff="%d" xSize="%d" ySize="%d"/>\n'
                        '    </SimpleSource>\n'
                        % (stem, names[(fx, fy)], b, w, h, w, nx, ny, dx, dy, nx, ny))
            f.write('  </VRTRasterBand>\n')
        f.write('</VRTDataset>\n')
    os.replace(tmp, path)
    return len(cols) * len(rows)


def main(argv):
    keep_alpha, like, pos = False, None, []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a in ("-h", "--help"):
            print(__doc__.strip())
            return 0
        elif a == "--keep-alpha":
            keep_alpha = True
        elif a == "--like":
            i += 1
            if i >= len(argv):
                usage_error("--like needs a DEM")
            like = argv[i]
        elif a.startswith("-") and len(a) > 1 and not a[1:].isdigit():
            usage_error("unknown option '%s'" % a)
        else:
            pos.append(a)
        i += 1
    if len(pos) not in (2, 3):
        usage_error("expected SIZE OUT_DIR [IMAGE], got %d argument(s)" % len(pos))
    if like is None:
        usage_error("missing --like DEM (the extent and CRS to cover)")
    try:
        size = int(pos[0])
    except ValueError:
        usage_error("SIZE must be a whole number of pixels, got '%s'" % pos[0])
    if size < 2 or size > 2147483647:
        usage_error("SIZE must be 2 .. 2^31 - 1, got %d" % size)
    out_dir = pos[1]
    here = os.path.dirname(os.path.abspath(__file__))
    image = pos[2] if len(pos) == 3 else os.path.normpath(
        os.path.join(here, "..", "data", "craterlake-imagery-30m.tif"))
    for f, what in ((image, "image"), (like, "--like DEM")):
        if not os.path.isfile(f):
            die("%s %s not found" % (what, f))
    for t in ("gdalinfo", "gdal_translate"):
        need_tool(t)
    os.makedirs(out_dir, exist_ok=True)

    t0 = time.time()
    dw, dh, dgt, wkt, mapping = like_grid(like)
    ext_x, ext_y = dw * abs(dgt[1]), dh * abs(dgt[5])
    px = ext_x / size
    sx, sy = size, max(1, int(round(ext_y / px)))
    py = ext_y / sy
    gt = (dgt[0], px if dgt[1] > 0 else -px, dgt[3], -py if dgt[5] < 0 else py)
    w, h, nb_in = image_bands(image)
    nb = nb_in if keep_alpha else 3
    stem = os.path.splitext(os.path.basename(image))[0] + ("_rgba" if nb == 4 else "_rgb")
    data, hdr = write_copies(image, out_dir, stem, nb)
    if len(data) != w * h * nb:
        die("%s: %d bytes of pixels, expected %dx%dx%d" % (image, len(data), w, h, nb))
    flip_copies(data, hdr, out_dir, stem, w, h, nb)
    vrt = os.path.join(out_dir, "imagery_%d.vrt" % size)
    copies = write_vrt(vrt, sx, sy, stem, w, h, nb, gt, wkt, mapping)
    print("image:   %s (%dx%d, %d bands used)" % (image, w, h, nb))
    print("like:    %s (%dx%d, %.2f x %.2f km)" % (like, dw, dh, ext_x / 1e3, ext_y / 1e3))
    print("mosaic:  %s: %dx%d pixels of %.4f x %.4f m, %d copies, %s"
          % (vrt, sx, sy, px, py, copies, "alpha kept" if nb == 4 else "opaque"))
    print("made in: %.1f s" % (time.time() - t0))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
