#!/bin/bash
# tools/make_void_tile.sh OUT_DIR [TILE]: a 3601 x 3601 SRTM1-shaped tile whose northern half is
# void, made from a real tile with the GDAL command-line tools (issue 32, item 5: the view of
# such a tile from 60 km up measured its error as 0).
#
#   OUT_DIR   created if missing; gets OUT_DIR/N42E001.hgt (named after the tile's south-west
#             corner, as the SRTMHGT driver wants) and OUT_DIR/full.tif, the whole tile
#             resampled, voids as in TILE; prints the .hgt's path
#   TILE      default data/N42E001.hgt (SRTM3, 1201 x 1201); any 1 x 1 degree tile GDAL reads
#
# 1. The tile resampled to 3601 x 3601 posts over the same 1 x 1 degree cell (cubic, Int16,
#    voids kept as -32768): the posts of an SRTM1 tile, the relief of the SRTM3 one.
# 2. Its southern 1801 rows cut out and warped back onto the whole tile's grid: the northern
#    1800 rows are nodata (-32768), the southern half unchanged, post for post.
# 3. Written as an SRTM .hgt (big-endian Int16, 3601 x 3601), as a downloaded SRTM1 tile is.
# A second run with an OUT_DIR/N42E001.hgt newer than TILE does nothing. Needs gdal-bin
# (gdalinfo, gdalwarp, gdal_translate; `make deps` installs it).
set -euo pipefail
die() { echo "make_void_tile: $*" >&2; exit 1; }
[ $# -ge 1 ] && [ $# -le 2 ] || { sed -n '2,8p' "$0" >&2; exit 2; }
out=$1
tile=${2:-$(dirname "$0")/../data/N42E001.hgt}
[ -f "$tile" ] || die "$tile not found"
for t in gdalinfo gdalwarp gdal_translate; do
    command -v $t > /dev/null || die "$t not found: install gdal-bin (\`make deps\`)"
done
# the tile's 1 x 1 degree cell from its origin (pixel-is-point: half a post outside the cell)
read -r x0 y0 < <(gdalinfo "$tile" | sed -n 's/^Origin = (\([-0-9.]*\),\([-0-9.]*\))$/\1 \2/p')
[ -n "${x0:-}" ] || die "$tile: no origin in gdalinfo's output"
lon=$(printf '%.0f' "$x0") lat=$(printf '%.0f' "$y0")
name=$(awk -v lon="$lon" -v lat="$lat" 'BEGIN { s = lat - 1;
    printf "%s%02d%s%03d.hgt", s < 0 ? "S" : "N", s < 0 ? -s : s, lon < 0 ? "W" : "E",
        lon < 0 ? -lon : lon }')
mkdir -p "$out"
hgt=$out/$name
if [ -s "$hgt" ] && [ "$hgt" -nt "$tile" ]; then
    echo "$hgt"
    exit 0
fi
# the SRTM1 grid: 3601 posts a side, 1/3600 degree apart, centred on the cell's whole degrees
te=$(awk -v lon="$lon" -v lat="$lat" 'BEGIN { h = 0.5 / 3600;
    printf "%.12f %.12f %.12f %.12f", lon - h, lat - 1 - h, lon + 1 + h, lat + h }')
tmp=$(mktemp -d "$out/.void.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
# shellcheck disable=SC2086
gdalwarp -q -overwrite -te $te -ts 3601 3601 -r cubic -ot Int16 -srcnodata -32768 \
    -dstnodata -32768 "$tile" "$tmp/full.tif"
gdal_translate -q -srcwin 0 1800 3601 1801 "$tmp/full.tif" "$tmp/south.tif"
# shellcheck disable=SC2086
gdalwarp -q -overwrite -te $te -ts 3601 3601 -r near -dstnodata -32768 "$tmp/south.tif" \
    "$tmp/half.tif"
gdal_translate -q -of SRTMHGT "$tmp/half.tif" "$tmp/$name"
mv "$tmp/full.tif" "$out/full.tif"
mv "$tmp/$name" "$hgt"
echo "$hgt"
