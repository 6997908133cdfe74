#!/bin/bash
# test_void_measure.sh TERRAPATCH TOOL DATA_DIR WORK_DIR: issue 32, item 5. A 3601^2 SRTM1-shaped
# tile whose northern half is void (tools/make_void_tile.sh, from the real data/N42E001.hgt),
# viewed from 60 km up looking north over its valid half: before the fix view --stats-json
# reported max_error_px 0 and RMS 0 there while drawing coarse levels (only the resident leaves
# were measured: none under the coarse nodes). Now:
#   - the tile: 3601 x 3601, its northern 1800 rows void (gdallocationinfo), the south as the
#     resampled whole (full.tif), every post compared on two rows;
#   - error mode: coarse nodes drawn, the error measured over the samples in view (every leaf
#     under the cut read from the store), > 0 and <= tau; never 0 with coarse levels drawn;
#   - the same camera at full resolution (--lod full): exactly 0, over the same samples give or
#     take the holes coarse nodes leave along the void (within 5%);
#   - bench --path high over the store (cached by view): max_screen_error_px is a number on
#     every configuration, error and distance.
# Needs gdal-bin and python3. The store build takes 30-70 s on two busy cores.
set -u
TP=$1 TOOL=$2 DATA=$3 WORK=$4
mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAIL: $*"; for f in out err; do [ -s $f ] && { echo "--- $f"; tail -20 $f; }; done; exit 1; }
export TP_CACHE_DIR=$WORK/cache
rm -rf "$TP_CACHE_DIR" j_*.json

hgt=$("$TOOL" "$WORK/tile" "$DATA/N42E001.hgt" 2> err) || fail "make_void_tile.sh: exit $?"
[ "$hgt" = "$WORK/tile/N42E001.hgt" ] || fail "make_void_tile.sh printed '$hgt'"
gdalinfo "$hgt" | grep -q '^Size is 3601, 3601$' || fail "$hgt is not 3601 x 3601"
# rows 0..1799 void, 1800.. the resampled tile's own posts (gdallocationinfo: pixel line)
python3 - "$hgt" "$WORK/tile/full.tif" > out 2>&1 << 'EOF' || fail "the tile's rows"
import subprocess, sys
hgt, full = sys.argv[1:]
def values(path, line):
    pts = "".join("%d %d\n" % (x, line) for x in range(0, 3601, 7))
    out = subprocess.run(["gdallocationinfo", "-valonly", path], input=pts, text=True,
                         capture_output=True, check=True).stdout.split()
    return [int(float(v)) for v in out]
for line in (0, 900, 1799):
    assert all(v == -32768 for v in values(hgt, line)), "row %d is not void" % line
for line in (1800, 3000):
    a, b = values(hgt, line), values(full, line)
    assert a == b, "row %d differs from the resampled tile" % line
    assert sum(v != -32768 for v in a) > 0.9 * len(a), "row %d is void" % line
EOF

CAM=376000,4550000,60000,0,-35 # 60 km up, south of the tile, looking north over its valid half
"$TP" view --headless "$hgt" --camera $CAM --size 640x360 --stats-json j_error.json \
    > out 2> err || fail "view (error mode): exit $?"
"$TP" view --headless "$hgt" --camera $CAM --size 640x360 --lod full --stats-json j_full.json \
    > out 2> err || fail "view --lod full: exit $?"
python3 - > out 2>&1 << 'EOF' || fail "the views' measures"
import json
e, f = (json.load(open("j_%s.json" % k)) for k in ("error", "full"))
for k, d in (("error", e), ("full", f)):
    print(k, {x: d[x] for x in ("max_error_px", "rms_error_px", "error_samples", "error_leaves",
                                "error_leaves_read", "error_leaf_share", "levels",
                                "nodes_per_scale")})
n = len(e["levels"]) - 1
coarse = sum(e["levels"][:n]) + sum(e["nodes_per_scale"][1:])
assert coarse > 100, "the error mode drew no coarse node"
assert e["max_error_px"] is not None and e["max_error_px"] > 0, "error mode measured 0 or nothing"
assert e["rms_error_px"] > 0
assert e["max_error_px"] <= 1 + 1e-6, "over tau = 1 px"
assert e["max_error_px"] <= e["bound_max_px"] + 1e-6, "over the cut's bound"
assert e["error_leaf_share"] == 1 and e["error_leaves_skipped"] == 0
assert e["error_leaves_read"] > 0.9 * e["error_leaves_measured"], "the leaves were not read"
assert f["nodes_per_scale"] == [f["nodes_drawn"]] and sum(f["levels"][:n]) == 0
assert f["max_error_px"] == 0 and f["rms_error_px"] == 0, "full resolution is not 0"
assert f["error_samples"] > 5e6, "the full view measured too few samples"
ratio = e["error_samples"] / f["error_samples"]
print("samples error / full: %.4f" % ratio)
assert 0.95 <= ratio <= 1.0, "the error mode measured %.3f of the samples in view" % ratio
EOF
cat out

store=$(ls "$TP_CACHE_DIR"/N42E001-*.tpt 2> /dev/null | head -1)
[ -f "$store" ] || fail "no store in $TP_CACHE_DIR"
"$TP" bench --path high --frames 4 --segments 2 --size 320x180 --memory 128 \
    --json j_bench.json "$store" > out 2> err || fail "bench --path high: exit $?"
python3 - > out 2>&1 << 'EOF' || fail "the bench's measures"
import json
d = json.load(open("j_bench.json"))
for c in d["configurations"]:
    print(c["lod_mode"], c["max_screen_error_px"], c["error_frames_measured"],
          c["error_leaf_share"])
    assert c["max_screen_error_px"] is not None, "%s: not measured" % c["lod_mode"]
    assert c["max_screen_error_px"] > 0 and c["error_frames_measured"] >= 1
    assert c["error_leaves_read"] > 0 and c["error_samples_skipped"] == 0
    if c["lod_mode"] == "error":
        assert c["max_screen_error_px"] <= 1 + 1e-3
EOF
cat out
echo "PASS"
