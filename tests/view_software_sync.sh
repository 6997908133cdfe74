#!/usr/bin/env bash
# view_software_sync.sh - the renderer's waits on a software rasteriser (issue 32 item 5;
# TP_RENDER_SOFTWARE_SYNC_INDICES in app/render/renderer.h): the same headless frame of a store
# drawn without waits (TP_SOFTWARE_SYNC_INDICES=0), with the default, and with a wait every 1,000
# indices. The three screenshots are identical byte for byte, the triangles the same, and the
# frame with a wait every 1,000 indices was cut into more draw calls than the one without (the
# waits happened; a GPU is never made to wait, and this test runs on llvmpipe or fails).
# usage: view_software_sync.sh TERRAPATCH WORKDIR DEM
set -u
exe=$1 dir=$2 dem=$3
mkdir -p "$dir"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
num() { tr -d '\n ' <"$1" | sed -n "s/.*\"$2\":\([-0-9.e+]*\)[,}].*/\1/p"; }

"$exe" build --patch 65 "$dem" -o "$dir/s.tpt" >/dev/null 2>"$dir/build.err" ||
    { cat "$dir/build.err"; echo "FAIL: build exit"; exit 1; }
for s in 0 default 1000; do
    env_set=() && [ "$s" != default ] && env_set=(env "TP_SOFTWARE_SYNC_INDICES=$s")
    "${env_set[@]}" "$exe" view --headless --size 640x360 --tau 0.5 --screenshot "$dir/$s.png" \
        --stats-json "$dir/$s.json" "$dir/s.tpt" 2>"$dir/$s.err" ||
        { bad "TP_SOFTWARE_SYNC_INDICES=$s: exit $?"; cat "$dir/$s.err"; }
done
renderer=$(tr -d '\n' <"$dir/0.json" | sed -n 's/.*"gl_renderer": *"\([^"]*\)".*/\1/p')
case $renderer in
*llvmpipe* | *softpipe* | *SwiftShader*) ;;
*) bad "not a software rasteriser ('$renderer'): the waits are not made there" ;;
esac
for s in default 1000; do
    cmp -s "$dir/0.png" "$dir/$s.png" || bad "the picture with TP_SOFTWARE_SYNC_INDICES=$s differs from the one without waits"
    [ "$(num "$dir/0.json" triangles)" = "$(num "$dir/$s.json" triangles)" ] ||
        bad "triangles $(num "$dir/0.json" triangles) without waits, $(num "$dir/$s.json" triangles) with $s"
done
c0=$(num "$dir/0.json" draw_calls) c1=$(num "$dir/1000.json" draw_calls)
echo "draw calls: $c0 without waits, $c1 with a wait every 1,000 indices; triangles $(num "$dir/0.json" triangles)"
[ -n "$c0" ] && [ -n "$c1" ] && [ "$c1" -gt "$c0" ] || bad "no more draw calls with a wait every 1,000 indices ($c0 -> $c1)"
[ "$fail" = 0 ] && echo "PASS"
exit $fail
