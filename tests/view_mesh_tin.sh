#!/usr/bin/env bash
# view_mesh_tin.sh - `view --mesh tin` against `view --mesh lattice` (issue 32 item 2): for each
# DEM, a store built with --patch 65 and two headless frames from the same cameras (the default
# one, and one 300 m above the DEM's middle looking north 15 degrees down): the stats JSON says
# the TIN frame drew TIN nodes (mesh "tin", tin_nodes > 0) over the same nodes as the lattice
# frame, with at most MAX_SHARE of its triangles, and both measured screen errors are within
# --tau 1; the two screenshots differ by at most 2 grey levels on average (the same surface
# within a pixel, shaded from the same normal map); from the second camera (TINs at fine
# levels) the TIN frame's GPU buffers (gpu_bytes) hold no more than the lattice frame's. Then
# `export --mesh tin` of the second camera against `export --mesh patches`: the same nodes, at
# most MAX_SHARE of the triangles.
# usage: view_mesh_tin.sh TERRAPATCH WORKDIR MAX_SHARE DEM...
set -u
exe=$1 dir=$2 max_share=$3
shift 3
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
tests=$(cd "$(dirname "$0")" && pwd)
fail=0
bad() { echo "FAIL: $*"; fail=1; }
# a number member of a stats JSON
num() { tr -d '\n ' <"$1" | sed -n "s/.*\"$2\":\([-0-9.e+]*\)[,}].*/\1/p"; }

for dem in "$@"; do
    name=$(basename "$dem")
    store="$dir/$name.tpt"
    "$exe" build --patch 65 "$dem" -o "$store" >/dev/null 2>"$dir/build.err" ||
        { bad "$name: build exit $?"; cat "$dir/build.err"; continue; }
    # the grid's middle, 300 m above its highest sample, looking north
    info=$("$exe" info --json "$store" | tr -d '\n ')
    cam=$(echo "$info" | sed -n 's/.*"size":\[\([0-9]*\),\([0-9]*\)\].*"grid_geotransform":\[\([-0-9.e+]*\),\([-0-9.e+]*\),[-0-9.e+]*,\([-0-9.e+]*\),[-0-9.e+]*,\([-0-9.e+]*\)\].*"drawn_max_m":\([-0-9.e+]*\).*/\1 \2 \3 \4 \5 \6 \7/p' |
          awk '{ printf "%.3f,%.3f,%.1f,0,-15", $3 + $4 * $1 / 2, $5 + $6 * $2 / 2, $7 + 300 }')
    cams=("")
    if [ -n "$cam" ]; then cams+=("$cam"); else bad "$name: no grid or height range in info --json"; fi
    for ci in "${!cams[@]}"; do
        camopt=() && [ -n "${cams[$ci]}" ] && camopt=(--camera "${cams[$ci]}")
        for mesh in lattice tin; do
            "$exe" view --headless --size 480x270 --tau 1 --mesh "$mesh" "${camopt[@]}" \
                --screenshot "$dir/$mesh.png" --stats-json "$dir/$mesh.json" "$store" \
                2>"$dir/$mesh.err" || { bad "$name camera $ci --mesh $mesh: exit $?"; cat "$dir/$mesh.err"; }
        done
        [ -f "$dir/tin.json" ] && [ -f "$dir/lattice.json" ] || continue
        tr -d '\n ' <"$dir/tin.json" | grep -q '"mesh":"tin"' || bad "$name camera $ci: mesh is not tin"
        tr -d '\n ' <"$dir/lattice.json" | grep -q '"mesh":"lattice"' || bad "$name camera $ci: mesh is not lattice"
        tn=$(num "$dir/tin.json" tin_nodes) tt=$(num "$dir/tin.json" triangles) lt=$(num "$dir/lattice.json" triangles)
        nt=$(num "$dir/tin.json" nodes_drawn) nl=$(num "$dir/lattice.json" nodes_drawn)
        et=$(num "$dir/tin.json" max_error_px) el=$(num "$dir/lattice.json" max_error_px)
        gt=$(num "$dir/tin.json" gpu_bytes) gl=$(num "$dir/lattice.json" gpu_bytes)
        echo "$name camera $ci: $nl nodes; lattice $lt triangles, tin $tt ($tn TIN nodes); max error $el / $et px; GPU bytes $gl / $gt"
        [ "$nt" = "$nl" ] || bad "$name camera $ci: $nt nodes drawn with TINs, $nl without"
        awk -v n="$tn" 'BEGIN { exit !(n > 0) }' || bad "$name camera $ci: no TIN node drawn"
        awk -v a="$tt" -v b="$lt" -v s="$max_share" 'BEGIN { exit !(a > 0 && a <= s * b) }' ||
            bad "$name camera $ci: $tt triangles with TINs, more than $max_share of $lt"
        # the low camera draws TINs at fine levels: their vertex slots and regions are sized to
        # the TIN's vertices, not its level's lattice, so they hold less than the lattice's
        # (sized for the lattice they held 1.1-1.7 times as much)
        [ "$ci" = 0 ] || awk -v a="$gt" -v b="$gl" 'BEGIN { exit !(a > 0 && a <= b) }' ||
            bad "$name camera $ci: the TIN frame's GPU buffers hold $gt bytes, the lattice's $gl"
        awk -v a="$et" -v b="$el" 'BEGIN { exit !(a != "" && b != "" && a <= 1.000001 && b <= 1.000001) }' ||
            bad "$name camera $ci: max screen error $et (tin), $el (lattice) px above --tau 1"
        TP_TESTS_DIR=$tests python3 - "$dir/lattice.png" "$dir/tin.png" "$name camera $ci" <<'EOF' || fail=1
import os, sys
sys.path.insert(0, os.environ["TP_TESTS_DIR"])
from tp_png import read_png
w, h, ch, a = read_png(sys.argv[1])
w2, h2, ch2, b = read_png(sys.argv[2])
assert (w, h) == (w2, h2)
total = sum(abs(a[y][x * ch + k] - b[y][x * ch2 + k]) for y in range(h) for x in range(w)
            for k in range(3)) / (3.0 * w * h)
print("%s: mean absolute difference %.3f grey levels" % (sys.argv[3], total))
if total > 2:
    print("FAIL: %s: the TIN frame differs from the lattice's by %.3f grey levels on average"
          % (sys.argv[3], total))
    sys.exit(1)
EOF
        rm -f "$dir"/tin.* "$dir"/lattice.*
    done
    # export of the same camera's mesh: the TIN nodes' triangles, the same nodes
    [ -n "$cam" ] || continue
    for mesh in patches tin; do
        "$exe" export "$store" --mesh "$mesh" --camera "$cam" --tau 1 -o "$dir/$mesh.vtp" \
            >"$dir/$mesh.out" 2>&1 || { bad "$name: export --mesh $mesh exit $?"; cat "$dir/$mesh.out"; }
    done
    et=$(sed -n 's/.* \([0-9]*\) triangles (.*/\1/p' "$dir/tin.out")
    ep=$(sed -n 's/.* \([0-9]*\) triangles (.*/\1/p' "$dir/patches.out")
    dt=$(sed -n 's/.*; \([0-9]*\) nodes drawn.*/\1/p' "$dir/tin.out")
    dp=$(sed -n 's/.*; \([0-9]*\) nodes drawn.*/\1/p' "$dir/patches.out")
    echo "$name export: $dp nodes, $ep triangles as patches, $et as TIN nodes"
    [ -n "$dt" ] && [ "$dt" = "$dp" ] || bad "$name export: $dt nodes drawn with TINs, $dp without"
    awk -v a="$et" -v b="$ep" -v s="$max_share" 'BEGIN { exit !(a > 0 && a <= s * b) }' ||
        bad "$name export: $et triangles with TIN nodes, more than $max_share of $ep"
    rm -f "$dir"/patches.* "$dir"/tin.*
done
exit $fail
