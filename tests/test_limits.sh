#!/bin/bash
# test_limits.sh EXE DATA_DIR WORK_DIR CASE: the limits the pipeline keeps (docs/PERFORMANCE.md,
# "Memory"; docs/georeference.md). Each CASE is its own ctest; hostile rasters are ESRI ASCII
# grids written here (tiny, EPSG:4326 given with --crs), so every case runs in seconds.
#   memory_env_refused    TP_MEMORY_LIMIT below the estimate: exit 1, one line, no work done
#   memory_env_passes     TP_MEMORY_LIMIT above it: the command runs
#   memory_env_streams    export --full to a .vtp streams within TP_MEMORY_LIMIT (its pieces
#                         sized to fit); below one piece's need: refused, one line, no file
#   memory_store_bounded  a store's view, build and camera export keep TP_MEMORY_LIMIT: the
#                         budgets shrink with a warning, or one line refuses
#   memory_ulimit_refused ulimit -v below the export --full estimate (a .vtk, built whole): exit
#                         1, one line naming it
#   memory_ulimit_streams the same ulimit -v: export --full to a .vtp streams within it
#   memory_ulimit_passes  ulimit -v generous: info runs
#   warp_pole             143x107 0.01-degree cells at the north pole: a grid near the DEM's size, fast
#   warp_world            143x107 cells over most of the world: refused, the extent named
#   warp_globe            the whole globe, -180 .. 180 (edges 180 degrees from the zone's
#                         meridian scale by almost nothing; the inside does not): refused
#   warp_anisotropic      posts 1e-7 degrees wide, 1 degree tall: no 10^18-byte grid
#   long_path             a missing DEM under a 600-byte path: the reason survives
#   extent_antimeridian   info says the extent crosses the antimeridian, text and JSON
#   extent_pole           a grid holding the pole reaches lat 90
#   extent_outside_zone   an edge the zone cannot convert: info says so, not a silent gap
set -u
EXE=$1 DATA=$2 WORK=$3 CASE=$4
mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAIL ($CASE): $*"; [ -f out ] && { echo '--- stdout'; cat out; }; [ -f err ] && { echo '--- stderr'; cat err; }; exit 1; }

# asc NAME XLL YLL DX DY NCOLS NROWS: a smooth-ish test surface (heights 100..149 m)
asc() {
    awk -v x="$2" -v y="$3" -v dx="$4" -v dy="$5" -v nc="$6" -v nr="$7" 'BEGIN {
        printf "ncols %d\nnrows %d\nxllcorner %.10g\nyllcorner %.10g\n", nc, nr, x, y
        if (dx == dy) printf "cellsize %.10g\n", dx; else printf "dx %.10g\ndy %.10g\n", dx, dy
        printf "NODATA_value -9999\n"
        for (r = 0; r < nr; r++) { for (i = 0; i < nc; i++) printf "%d ", 100 + (i * 7 + r * 13) % 50; printf "\n" }
    }' > "$1.asc"
}
# run SECONDS ARGS...: runs EXE with a time limit, stdout to out, stderr to err; sets rc
run() { local t=$1; shift; timeout "$t" "$EXE" "$@" > out 2> err; rc=$?; }
one_line() { [ "$(wc -l < err)" -eq 1 ] || fail "expected one line on stderr, got $(wc -l < err)"; }

HGT="$DATA/N42E001.hgt"
case "$CASE" in
memory_env_refused)
    # ~155 MiB resident when the check runs, ~220 MiB estimated for info: 190M is between
    TP_MEMORY_LIMIT=190M run 60 info "$HGT"
    [ $rc -eq 1 ] || fail "exit $rc, expected 1"; one_line
    grep -q "info of its 1249x1665 grid needs about [0-9]* MiB.*available (TP_MEMORY_LIMIT)" err || fail "no need/available line"
    # a legacy .vtk is built whole in memory: refused, with the way out
    TP_MEMORY_LIMIT=400M run 60 export --full "$HGT" -o full.vtk
    [ $rc -eq 1 ] || fail "export --full: exit $rc, expected 1"; one_line
    grep -q "export --full of its .*(TP_MEMORY_LIMIT); export to a .vtp, which is written a piece at a time" err || fail "export --full: no hint"
    [ ! -e full.vtk ] || fail "export --full wrote a file" ;;
memory_env_streams)
    # the .vtp streams: pieces sized to what TP_MEMORY_LIMIT leaves, the peak (the program's own
    # getrusage) under it, the whole mesh written (two triangles per cell of four drawn samples)
    TP_MEMORY_LIMIT=400M run 120 export --full "$HGT" -o full.vtp
    [ $rc -eq 0 ] || fail "exit $rc, expected 0"
    grep -q "^wrote full.vtp: [0-9]* points, 3949910 triangles (100.00% of the 3949910 of the full mesh).* [0-9]* pieces of at most" out || fail "no wrote line with the full mesh's triangles"
    peak=$(sed -n 's/.*peak \([0-9]*\) MiB$/\1/p' out)
    [ -n "$peak" ] && [ "$peak" -le 400 ] || fail "peak ${peak:-?} MiB over the 400 MiB limit"
    grep -q "^terrapatch export: writing 100%" err || fail "no progress on stderr"
    # less than one piece needs: one line, nothing written
    rm -f full.vtp
    TP_MEMORY_LIMIT=120M run 60 export --full "$HGT" -o full.vtp
    [ $rc -eq 1 ] || fail "120M: exit $rc, expected 1"; one_line
    grep -q "export --full needs about [0-9]* MiB, [0-9]* MiB available (TP_MEMORY_LIMIT)" err || fail "120M: no need/available line"
    [ ! -e full.vtp ] || fail "120M: wrote a file"
    ls full.vtp.tmp* 2>/dev/null && fail "120M: left a temporary file"
    true ;;
memory_store_bounded)
    run 120 build --quiet "$DATA/lf_elev_220_mt_hood_utm.tif" -o hood.tpt
    [ $rc -eq 0 ] || fail "build: exit $rc"
    # build's --memory (the whole process's budget) shrinks to what the limit leaves, or refuses
    TP_MEMORY_LIMIT=300M run 120 build --quiet "$DATA/lf_elev_220_mt_hood_utm.tif" -o small.tpt
    [ $rc -eq 0 ] || fail "build at 300M: exit $rc"
    grep -q "terrapatch build: warning: .*MiB is available (TP_MEMORY_LIMIT): --memory [0-9]* MiB instead of 1024 MiB" err || fail "build at 300M: no warning"
    TP_MEMORY_LIMIT=60M run 60 build --quiet "$DATA/lf_elev_220_mt_hood_utm.tif" -o tiny.tpt
    [ $rc -eq 1 ] || fail "build at 60M: exit $rc, expected 1"; one_line
    grep -q "needs about [0-9]* MiB.*(TP_MEMORY_LIMIT)" err || fail "build at 60M: no need/available line"
    [ ! -e tiny.tpt ] || fail "build at 60M wrote a store"
    # a store's view: the decoded terrain's budget within the limit, or refused
    TP_MEMORY_LIMIT=200M run 60 view --headless --screenshot v.png hood.tpt
    [ $rc -eq 1 ] || fail "view at 200M: exit $rc, expected 1"; one_line
    grep -q "terrapatch view: hood.tpt: needs about [0-9]* MiB .*(TP_MEMORY_LIMIT)" err || fail "view at 200M: no need/available line"
    [ ! -e v.png ] || fail "view at 200M wrote a picture"
    # a bench flies with the decoded terrain's budget shrunk to what the limit leaves
    TP_MEMORY_LIMIT=300M run 60 bench --frames 2 hood.tpt
    [ $rc -eq 0 ] || fail "bench at 300M: exit $rc"
    grep -q "terrapatch bench: warning: hood.tpt: [0-9]* MiB is available (TP_MEMORY_LIMIT): the decoded terrain (--memory) [0-9]* MiB instead of 1024 MiB" err || fail "bench at 300M: no warning"
    # a camera's cut at full detail, built whole in memory: refused before it is built
    TP_MEMORY_LIMIT=200M run 60 export --lod full hood.tpt -o cut.vtp
    [ $rc -eq 1 ] || fail "export --lod full at 200M: exit $rc, expected 1"; one_line
    grep -q "the mesh of the cut needs about [0-9]* MiB more.*(TP_MEMORY_LIMIT)" err || fail "export at 200M: no need/available line"
    [ ! -e cut.vtp ] || fail "export at 200M wrote a mesh"
    # with room, the store's --full .vtp streams
    TP_MEMORY_LIMIT=400M run 60 export --full hood.tpt -o full.vtp
    [ $rc -eq 0 ] || fail "export --full of the store at 400M: exit $rc" ;;
memory_env_passes)
    TP_MEMORY_LIMIT=3G run 60 info "$HGT"
    [ $rc -eq 0 ] || fail "exit $rc, expected 0" ;;
memory_ulimit_refused)
    # 700 MiB of address space: the libraries load (~480 MiB mapped), the export --full estimate
    # (~0.9 GiB) does not fit
    ulimit -v 716800
    run 60 export --full "$HGT" -o full.vtk
    [ $rc -eq 1 ] || fail "exit $rc, expected 1"; one_line
    grep -q "needs about [0-9]* MiB.*available (ulimit -v)" err || fail "no need/available line naming ulimit -v" ;;
memory_ulimit_streams)
    ulimit -v 716800
    run 120 export --full "$HGT" -o full.vtp
    [ $rc -eq 0 ] || fail "exit $rc, expected 0"
    grep -q "^wrote full.vtp: .* 3949910 triangles" out || fail "no wrote line" ;;
memory_ulimit_passes)
    ulimit -v 4194304
    run 60 info "$HGT"
    [ $rc -eq 0 ] || fail "exit $rc, expected 0" ;;
warp_pole)
    asc pole -180 88.93 0.01 0.01 143 107
    start=$(date +%s)
    run 30 info --json --crs EPSG:4326 pole.asc
    [ $rc -eq 0 ] || fail "exit $rc, expected 0"
    [ $(( $(date +%s) - start )) -le 20 ] || fail "took over 20 s"
    grep -q '"crs": *32661' out || fail "not UPS north"
    # the render grid: at most 4x the source's 15301 samples
    size=$(tr -d ' \n' < out | sed -n 's/.*"render_grid":\[\([0-9]*\),\([0-9]*\)\].*/\1 \2/p')
    set -- $size
    [ -n "${2:-}" ] && [ $(( $1 * $2 )) -le $(( 4 * 15301 )) ] || fail "render grid $size: over 4x the source"
    grep -q "as many samples as the DEM" err || fail "no warning saying what was chosen" ;;
warp_world)
    asc world -180 -85.6 1.6 1.6 143 107
    run 30 info --crs EPSG:4326 world.asc
    [ $rc -eq 1 ] || fail "exit $rc, expected 1"; one_line
    grep -q "span lon -179.2 .. 48, lat -84.8 .. 84.8.*cannot hold it; reproject it first" err || fail "no message naming the extent" ;;
warp_globe)
    asc globe -180 -85 2.5 2.5 144 68
    run 30 info --crs EPSG:4326 globe.asc
    [ $rc -eq 1 ] || fail "exit $rc, expected 1"; one_line
    grep -q "span lon -178.75 .. 178.75, lat -83.75 .. 83.75.*by more than 1000%.*cannot hold it; reproject it first, e.g. .gdalwarp -t_srs EPSG:8857 IN OUT.tif. (Equal Earth" err || fail "no message naming the extent and a CRS" ;;
warp_anisotropic)
    asc aniso 10 40 0.0000001 1 143 3
    run 30 info --json --crs EPSG:4326 aniso.asc
    [ $rc -le 1 ] || fail "exit $rc (a crash or a timeout)"
    if [ $rc -eq 0 ]; then
        size=$(tr -d ' \n' < out | sed -n 's/.*"render_grid":\[\([0-9]*\),\([0-9]*\)\].*/\1 \2/p')
        set -- $size
        [ -n "${2:-}" ] && [ $(( $1 * $2 )) -le 4096 ] || fail "render grid $size: unbounded"
    else
        ! grep -qi "out of memory\|allocat" err || fail "an allocation failure, not a bound"
        grep -q "as many samples as the DEM" err || fail "no warning saying what was chosen"
    fi ;;
long_path)
    dir=$WORK/long
    for i in $(seq 1 17); do dir="$dir/a_folder_with_a_rather_long_name_$i"; done
    mkdir -p "$dir"
    path="$dir/no_such_dem.tif"
    [ ${#path} -ge 600 ] || fail "path only ${#path} bytes"
    run 30 info "$path"
    [ $rc -eq 1 ] || fail "exit $rc, expected 1"; one_line
    grep -qi "no such file" err || fail "the reason was cut off"
    grep -q "^terrapatch info: $WORK/long/a_folder" err || fail "the start of the path was lost" ;;
extent_antimeridian)
    asc anti 179 40 0.01 0.01 143 107
    run 30 info --crs EPSG:4326 anti.asc
    [ $rc -eq 0 ] || fail "exit $rc, expected 0"
    line=$(grep "geographic   lat" out)
    echo "$line" | grep -q "lon 17[89]\.[0-9]* .. -179\.[0-9]* (crosses the antimeridian)" || fail "extent: $line"
    # every edge sample: the data's posts reach 179.005 and -179.575
    west=$(echo "$line" | sed 's/.*lon \([0-9.]*\) .*/\1/')
    awk -v w="$west" 'BEGIN { exit !(w <= 179.005) }' || fail "west $west is east of the first posts (179.005)"
    run 30 info --json --crs EPSG:4326 anti.asc
    grep -q '"extent_crosses_antimeridian": *true' out || fail "JSON does not say it crosses" ;;
extent_outside_zone)
    # 355..370 E at 50..60 N in UTM 31N: the west edge has a negative easting
    asc wrap 355 50 0.25 0.25 60 40
    run 30 info --crs EPSG:4326 wrap.asc
    [ $rc -eq 0 ] || fail "exit $rc, expected 0"
    grep -q "geographic   not available: .*Easting -[0-9.]*km not in UTM range" out ||
        fail "no word on the geographic extent" ;;
extent_pole)
    asc southpole 0 -90 0.01 0.01 143 107
    run 30 info --crs EPSG:4326 southpole.asc
    [ $rc -eq 0 ] || fail "exit $rc, expected 0"
    line=$(grep "geographic   lat" out)
    # posts reach -89.995: the reported extent must too
    south=$(echo "$line" | sed 's/.*lat \([-0-9.]*\) .*/\1/')
    awk -v s="$south" 'BEGIN { exit !(s <= -89.995) }' || fail "south $south does not reach the posts at -89.995: $line" ;;
*)
    fail "unknown case" ;;
esac
echo "ok ($CASE)"
