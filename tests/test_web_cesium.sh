#!/bin/bash
# test_web_cesium.sh TERRAPATCH ROOT DATA_DIR WORK_DIR CASE: issue 34, the tile set of `terrapatch
# export --tiles quantized-mesh` shown by the web page (tools/web/) in a real browser: Debian's
# chromium, headless, WebGL through SwiftShader, driven by tools/web/drive.mjs (puppeteer-core,
# installed with CesiumJS by tools/web_install.sh). A store is built from
# DATA_DIR/craterlake-elev-16bit-30m.tif, exported with --heights geoid --max-error 1 (the
# default bound, Cesium's geometric error per level, leaves 18.8 m at level 12), its imagery tiled by
# gdal2tiles.py --profile geodetic, and all of it served on 127.0.0.1 by tools/web/serve.py
# (tiles with Content-Encoding: gzip), started here and stopped by a trap.
#   page:     the tiles load with no error of any kind (Cesium's tile, imagery and render
#             errors, console errors, failed or >= 400 requests, any request off 127.0.0.1);
#             the picture differs from the bare ellipsoid's (same camera, same imagery) in at
#             least 10% of its pixels; Cesium's height (sampleTerrainMostDetailed) at 20
#             positions agrees with `terrapatch point` within the measured error of the tile it
#             comes from (errors.json) plus one 15-bit height step and 5 cm (web_cesium_check.py);
#             the ground covers the same pixels as in `terrapatch view --headless` from the same
#             --camera-geo string (IoU >= 0.92; 0.95 measured, 0.91 with view's picture shifted
#             6 px, about 1 degree of heading)
#   corrupt:  the most detailed tile under the first position cut to half its length (then
#             gzipped again): the run must report an error, and name that position
#   offset:   every tile's heights raised by twice the largest measured error of the deepest
#             level + 5 m: no error is reported, and every height must disagree
# A missing node, chromium or gdal2tiles.py is a failure naming it, never a skip.
set -u
TP=$1 ROOT=$2 DATA=$3 WORK=$4 CASE=$5
CHECK="python3 $ROOT/tests/web_cesium_check.py"
# the default view of `terrapatch view` on this store (--stats-json's camera, in --camera-geo form)
CAM=42.889828581,-122.108291171,8470.74,0,-50
SIZE=640x360
fail() { echo "FAIL: $*"; for f in err check.txt; do [ -s "$WORK/$f" ] && { echo "--- $f"; tail -8 "$WORK/$f"; }; done; exit 1; }
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
command -v node > /dev/null || fail "node is not installed (Node.js 18 or newer, with npm: Debian packages nodejs and npm, not installed by tools/deps.sh)"
command -v chromium > /dev/null || fail "chromium is not installed (Debian package chromium: 'make deps' or tools/deps.sh installs it)"
command -v python3 > /dev/null || fail "python3 is not installed"
command -v gdal2tiles.py > /dev/null || fail "gdal2tiles.py is not installed (Debian package gdal-bin)"
sh "$ROOT/tools/web_install.sh" > /dev/null 2> err || fail "tools/web_install.sh: $(tail -1 err)"

"$TP" build "$DATA/craterlake-elev-16bit-30m.tif" -o crater.tpt > /dev/null 2> err || fail "build"
"$TP" export crater.tpt --tiles quantized-mesh --heights geoid --max-error 1 -o tiles > /dev/null 2> err ||
    fail "export --tiles quantized-mesh"
[ -s tiles/layer.json ] && [ -s tiles/errors.json ] || fail "export wrote no layer.json or errors.json"
gdal2tiles.py --profile geodetic --tmscompatible -w none -q "$DATA/craterlake-imagery-30m.tif" \
    imagery > /dev/null 2> err || fail "gdal2tiles.py"
$CHECK points "$TP" crater.tpt points.json 2> err || fail "the positions"

SERVER_PID=
stop() {
    [ -n "$SERVER_PID" ] && kill "$SERVER_PID" 2> /dev/null
    wait 2> /dev/null
}
trap stop EXIT
python3 "$ROOT/tools/web/serve.py" tiles --imagery imagery --port-file port --log access.log \
    > /dev/null 2> server_err &
SERVER_PID=$!
for _ in $(seq 100); do [ -s port ] && break; sleep 0.1; done
[ -s port ] || fail "tools/web/serve.py did not start: $(cat server_err)"
URL="http://127.0.0.1:$(cat port)/index.html?tiles=tiles/&imagery=imagery/&camera-geo=$CAM&lean=1"

# drive NAME [URL-SUFFIX] [--points FILE]: the page, its report in NAME.json, picture NAME.png
drive() {
    local name=$1 suffix=$2
    shift 2
    node "$ROOT/tools/web/drive.mjs" --url "$URL$suffix" --size $SIZE --timeout 120 \
        --out "$name.png" --json "$name.json" "$@" 2> "$name.err"
}

case_page() {
    drive terrain "" --points points.json.lonlat || fail "the page reported errors: $(head -3 terrain.err)"
    drive ellipsoid "&terrain=ellipsoid" || fail "the ellipsoid page reported errors: $(head -3 ellipsoid.err)"
    $CHECK check terrain.json tiles points.json terrain.png ellipsoid.png > check.txt 2>&1 ||
        fail "the page: $(grep -v '^height:' check.txt | tr '\n' ';')"
    grep -c '\.terrain' access.log | grep -qv '^0$' || fail "no tile was asked for"
    # the same camera string in terrapatch view: the ground covers the same pixels
    "$TP" view --headless crater.tpt --camera-geo $CAM --size $SIZE --screenshot view.png \
        > /dev/null 2> err || fail "view --camera-geo $CAM"
    $CHECK footprint terrain.png view.png 0.92 >> check.txt 2>&1 ||
        fail "the page and view do not show the same view: $(tail -1 check.txt)"
    cat check.txt
}

case_corrupt() {
    local t first
    first=$(python3 -c 'import json; p = json.load(open("points.json"))[0]; print(p["lon"], p["lat"])')
    t=$($CHECK tile tiles $first) || fail "the tile under the first position"
    python3 - "tiles/${t%/*}/${t##*/}.terrain" << 'EOF' || fail "corrupting $t"
import gzip, sys
p = sys.argv[1]
d = open(p, "rb").read()
raw = gzip.decompress(d) if d[:2] == b"\x1f\x8b" else d
open(p, "wb").write(gzip.compress(raw[:len(raw) // 2]))
EOF
    drive terrain "" --points points.json.lonlat && fail "tile $t cut short: the run reported no error"
    $CHECK check terrain.json tiles points.json > check.txt 2>&1 && fail "tile $t cut short: the check passed"
    grep -q '^errors [1-9]' check.txt || fail "tile $t cut short: no error collected"
    grep -q "^error: sample: no height at $first " check.txt ||
        fail "tile $t cut short: no error names the position $first"
    echo "tile $t cut short: $(grep -m1 '^error:' check.txt)"
}

case_offset() {
    python3 - tiles << 'EOF' > offset.txt || fail "raising the heights"
import gzip, json, os, struct, sys
root = sys.argv[1]
errors = json.load(open(os.path.join(root, "errors.json")))
deepest = max(int(k.split("/")[0]) for k in errors)
off = 2 * max(v for k, v in errors.items() if int(k.split("/")[0]) == deepest) + 5
for d, _, files in os.walk(root):
    for f in files:
        if f.endswith(".terrain"):
            p = os.path.join(d, f)
            raw = bytearray(gzip.decompress(open(p, "rb").read()))
            lo, hi = struct.unpack_from("<2f", raw, 24)
            struct.pack_into("<2f", raw, 24, lo + off, hi + off)
            open(p, "wb").write(gzip.compress(bytes(raw)))
print("%.3f" % off)
EOF
    drive terrain "" --points points.json.lonlat || fail "heights raised: the page reported errors: $(head -3 terrain.err)"
    $CHECK check terrain.json tiles points.json > check.txt 2>&1 && fail "heights raised by $(cat offset.txt) m: the check passed"
    grep -q '^errors 0' check.txt || fail "heights raised: errors reported"
    grep -q '^heights 20 bad of 20' check.txt || fail "heights raised by $(cat offset.txt) m: not every height disagrees: $(grep '^heights' check.txt)"
    echo "heights raised by $(cat offset.txt) m: $(grep '^heights' check.txt)"
}

case_$CASE
stop
trap - EXIT
kill -0 "$SERVER_PID" 2> /dev/null && fail "the server still runs"
echo PASS
