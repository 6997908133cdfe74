#!/bin/sh
# tools/make_map_image.sh: a scanned-topographic-map-like image of a DEM, made with GDAL's
# command-line tools only, for trying imagery draping (issue 15) on real relief:
#
#   tools/make_map_image.sh DEM OUT.tif [METRES_PER_PIXEL]
#
# The DEM is warped to the WGS84 UTM zone GDAL picks for it (gdalwarp -t_srs of its centre),
# at METRES_PER_PIXEL (default 10), tinted by height as a map's layer colours are (gdaldem
# color-relief), with contour lines every 20 m and index contours every 100 m
# (gdal_contour, burnt in brown with gdal_rasterize) and the 1 km UTM grid (burnt in blue).
# OUT.tif: an RGB GeoTIFF in that UTM zone. Needs gdal-bin (tools/deps.sh installs it).
set -eu
[ $# -ge 2 ] || { sed -n '2,13p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
dem=$1 out=$2 res=${3:-10}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# the UTM zone of the DEM's centre
centre=$(gdalinfo -json "$dem" | python3 -c 'import json,sys; c=json.load(sys.stdin)["wgs84Extent"]["coordinates"][0]; xs=[p[0] for p in c]; ys=[p[1] for p in c]; print((min(xs)+max(xs))/2, (min(ys)+max(ys))/2)')
lon=${centre% *} lat=${centre#* }
zone=$(python3 -c "print(int(($lon + 180) // 6) + 1)")
epsg=$(python3 -c "print((32600 if $lat >= 0 else 32700) + $zone)")
gdalwarp -q -t_srs EPSG:$epsg -tr "$res" "$res" -r bilinear -dstnodata -32768 "$dem" "$tmp/dem.tif"
cat > "$tmp/colours.txt" <<'COLOURS'
nv      255 255 255
0       200 224 180
800     222 236 190
1400    240 238 200
2000    236 220 180
2600    222 200 170
3200    240 240 240
COLOURS
gdaldem color-relief -q "$tmp/dem.tif" "$tmp/colours.txt" "$tmp/tint.tif" -co COMPRESS=DEFLATE
gdal_contour -q -a elev -i 20 "$tmp/dem.tif" "$tmp/c20.gpkg"
gdal_contour -q -a elev -i 100 "$tmp/dem.tif" "$tmp/c100.gpkg"
gdal_rasterize -q -b 1 -b 2 -b 3 -burn 190 -burn 140 -burn 90 "$tmp/c20.gpkg" "$tmp/tint.tif"
gdal_rasterize -q -at -b 1 -b 2 -b 3 -burn 150 -burn 90 -burn 40 "$tmp/c100.gpkg" "$tmp/tint.tif"
# the 1 km grid as lines (a GeoJSON of vertical and horizontal lines over the extent)
python3 - "$tmp/dem.tif" "$tmp/grid.geojson" "$epsg" <<'PY'
import json, subprocess, sys, math
info = json.loads(subprocess.check_output(["gdalinfo", "-json", sys.argv[1]]))
gt = info["geoTransform"]; w, h = info["size"]
x0, x1 = gt[0], gt[0] + w * gt[1]; y1, y0 = gt[3], gt[3] + h * gt[5]
lines = [[[x, y0], [x, y1]] for x in range(int(math.ceil(x0 / 1000)) * 1000, int(x1), 1000)]
lines += [[[x0, y], [x1, y]] for y in range(int(math.ceil(y0 / 1000)) * 1000, int(y1), 1000)]
feats = [{"type": "Feature", "properties": {}, "geometry": {"type": "LineString", "coordinates": l}} for l in lines]
crs = {"type": "name", "properties": {"name": "EPSG:" + sys.argv[3]}}
json.dump({"type": "FeatureCollection", "crs": crs, "features": feats}, open(sys.argv[2], "w"))
PY
gdal_rasterize -q -b 1 -b 2 -b 3 -burn 60 -burn 90 -burn 200 "$tmp/grid.geojson" "$tmp/tint.tif"
gdal_translate -q -of GTiff -co COMPRESS=DEFLATE -co TILED=YES -a_srs EPSG:$epsg "$tmp/tint.tif" "$out"
echo "$out: $(gdalinfo "$out" | sed -n 's/^Size is //p') pixels of $res m, EPSG:$epsg"
