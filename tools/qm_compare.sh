#!/bin/sh
# tools/qm_compare.sh - our quantized-mesh tiles side by side with a martini-based and a
# delatin-based tiler's, in one run on one DEM (issue 34; docs/PERFORMANCE.md, "Side by side with
# martini- and delatin-based tilers"): the same z/x/y tiles (our layer.json's `available`), the
# same error bound a level (our level's geometric_error_m), one independent measure of the true
# error for all three.
#
#   tools/qm_compare.sh [--terrapatch EXE] [--max-zoom Z] [--bounds W,S,E,N] [--no-store-check]
#                       DEM WORK_DIR
#
#   1. ours: `terrapatch build DEM` then `terrapatch export --tiles quantized-mesh --heights
#      geoid` (the DEM's own heights) into WORK_DIR/ours, each under /usr/bin/time -v;
#   2. theirs: tools/qm_compare.py grids (GDAL's warper: a 257^2 lon/lat grid a tile, bilinear),
#      then tools/qm_tiler.mjs martini and delatin (meshed at the level's bound, encoded as
#      quantized-mesh-1.0 + normals + gzip) into WORK_DIR/martini and WORK_DIR/delatin, each
#      under /usr/bin/time -v;
#   3. tools/qm_compare.py posts (the DEM's posts at their WGS84 lon/lat, GDAL/osr), then
#      tools/qm_measure.mjs on each set: decoded by @here/quantized-mesh-decoder, the TIN
#      against every post inside the tile; neighbours' shared sides;
#   3b. unless --no-store-check: ours measured the same way against the store's own posts
#      (`terrapatch export --full` to a legacy VTK, tools/qm_compare.py store-posts): what
#      errors.json measures (the store is the DEM warped to UTM, voids filled), to check the two
#      measures against each other;
#   4. tools/qm_compare.py table: the table on stdout (and WORK_DIR/summary.json).
#
# WORK_DIR is emptied first (refused when it holds anything but an earlier run). npm packages (delatin 0.2.0, @mapbox/martini 0.2.0,
# @here/quantized-mesh-decoder 1.2.8), not vendored: installed with exact versions into
# ${XDG_CACHE_HOME:-~/.cache}/terrapatch/npm (TP_NPM_DIR overrides it), as tools/tin_compare.sh
# does; needs node and, once, npm and the registry. The Python steps need GDAL's bindings and
# numpy (python3-gdal, python3-numpy): the first of python3 and /usr/bin/python3 that has them.
# Exit 0, or 1 after one line naming what failed (2: usage).
set -u
case $0 in */*) here=${0%/*} ;; *) here=. ;; esac
me="terrapatch: tools/qm_compare.sh"
dir=${TP_NPM_DIR:-${XDG_CACHE_HOME:-${HOME:-}/.cache}/terrapatch/npm}
PKGS="delatin@0.2.0 @mapbox/martini@0.2.0 @here/quantized-mesh-decoder@1.2.8"
die() { echo "$me: $*" >&2; exit 1; }
usage() { echo "usage: $0 [--terrapatch EXE] [--max-zoom Z] [--bounds W,S,E,N] [--no-store-check] DEM WORK_DIR" >&2; exit 2; }

tp=${TERRAPATCH:-terrapatch} zoom= bounds= store_check=1
while [ $# -gt 0 ]; do
    case $1 in
    --terrapatch) [ $# -ge 2 ] || usage; tp=$2; shift 2 ;;
    --max-zoom) [ $# -ge 2 ] || usage; zoom=$2; shift 2 ;;
    --bounds) [ $# -ge 2 ] || usage; bounds=$2; shift 2 ;;
    --no-store-check) store_check=0; shift ;;
    -h | --help) sed -n '2,/^set -u/p' "$0" | sed -e '$d' -e 's/^# \{0,1\}//'; exit 0 ;;
    -*) echo "$me: unknown option '$1'" >&2; usage ;;
    *) break ;;
    esac
done
[ $# -eq 2 ] || usage
dem=$1 work=$2
[ -r "$dem" ] || die "$dem: cannot read the DEM"
command -v node > /dev/null 2>&1 || die "node not found on PATH ($PATH): the meshers and the measure run on Node.js (Debian: apt-get install nodejs npm)"
[ -x /usr/bin/time ] || die "/usr/bin/time not found (Debian package time)"
py=
for p in python3 /usr/bin/python3; do
    if "$p" -c 'import numpy; from osgeo import gdal' > /dev/null 2>&1; then py=$p; break; fi
done
[ -n "$py" ] || die "no python3 with GDAL's bindings and numpy (Debian: python3-gdal python3-numpy)"

installed() {
    grep -q '"version": *"0.2.0"' "$dir/node_modules/delatin/package.json" 2>/dev/null &&
        grep -q '"version": *"0.2.0"' "$dir/node_modules/@mapbox/martini/package.json" 2>/dev/null &&
        grep -q '"version": *"1.2.8"' "$dir/node_modules/@here/quantized-mesh-decoder/package.json" 2>/dev/null
}
if ! installed; then
    command -v npm > /dev/null 2>&1 || die "npm not found on PATH: needed once to install $PKGS into $dir"
    mkdir -p "$dir" || die "cannot create $dir"
    echo "$me: npm install --prefix $dir $PKGS" >&2
    # shellcheck disable=SC2086
    npm install --prefix "$dir" --no-audit --no-fund --save-exact $PKGS >&2 && installed ||
        die "npm install of $PKGS into $dir failed (no network, or the npm registry unreachable?)"
fi
export TP_NPM_DIR=$dir

# WORK_DIR is emptied: only an empty folder or an earlier run's (its marker file) is touched
if [ -e "$work" ] && [ -n "$(ls -A "$work" 2> /dev/null)" ] && [ ! -f "$work/.qm_compare" ]; then
    die "$work exists and is not an earlier run's work folder (no .qm_compare in it): choose another"
fi
rm -rf "$work" && mkdir -p "$work" && : > "$work/.qm_compare" || die "cannot make $work"
T="/usr/bin/time -v -o"
set -- --tiles quantized-mesh --heights geoid
[ -n "$zoom" ] && set -- "$@" --max-zoom "$zoom"
[ -n "$bounds" ] && set -- "$@" --bounds "$bounds"
step() { # step NAME COMMAND...: the command under /usr/bin/time -v, its stderr in NAME.err
    name=$1; shift
    echo "$me: $name" >&2
    $T "$work/time-$name.txt" "$@" > "$work/$name.out" 2> "$work/$name.err" ||
        die "$name failed: $(tail -1 "$work/$name.err")"
}
step build "$tp" build --quiet --threads 1 "$dem" -o "$work/dem.tpt"
step export "$tp" export "$work/dem.tpt" "$@" -o "$work/ours"
step grids "$py" "$here/qm_compare.py" grids "$work/ours/layer.json" "$dem" "$work/tiles.json" "$work/grids.f32"
for m in martini delatin; do
    step "$m" node --max-old-space-size="${TP_NODE_HEAP_MB:-4096}" "$here/qm_tiler.mjs" "$m" \
        "$work/tiles.json" "$work/grids.f32" "$work/$m"
done
rm -f "$work/grids.f32"
step posts "$py" "$here/qm_compare.py" posts "$dem" "$work/posts.bin"
for s in ours martini delatin; do
    step "measure-$s" node --max-old-space-size="${TP_NODE_HEAP_MB:-4096}" "$here/qm_measure.mjs" \
        "$work/$s" "$work/tiles.json" "$work/posts.bin" "$work/measure-$s.json"
done
rm -f "$work/posts.bin"
if [ "$store_check" = 1 ]; then # ours against the store's posts too: errors.json's own reference
    step full "$tp" export "$work/dem.tpt" --full -o "$work/full.vtk"
    step store-posts "$py" "$here/qm_compare.py" store-posts "$work/full.vtk" "$work/posts.bin"
    rm -f "$work/full.vtk"
    step measure-ours-store node --max-old-space-size="${TP_NODE_HEAP_MB:-4096}" "$here/qm_measure.mjs" \
        "$work/ours" "$work/tiles.json" "$work/posts.bin" "$work/measure-ours-store.json"
    rm -f "$work/posts.bin"
fi
"$py" "$here/qm_compare.py" table "$work" || die "the table failed"
