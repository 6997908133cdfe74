#!/bin/bash
# test_qm_compare.sh TERRAPATCH ROOT DATA_DIR WORK_DIR: qm_compare.crater (issue 34): runs
# tools/qm_compare.sh on DATA_DIR/craterlake-elev-16bit-30m.tif at --max-zoom 11 (ours, a
# martini-based and a delatin-based tiler, one independent measure) and checks its output:
#   - the three sets hold the same tiles, exactly those of our layer.json's `available`;
#   - the martini and delatin tiles pass tests/qm_check.py's checks of one tile (byte layout,
#     counter-clockwise triangles covering the tile, edge lists, header's sphere and horizon
#     point, normals): the comparison's tiles are real quantized-mesh tiles;
#   - ours is watertight (every neighbour pair shares its side's vertices), with pairs to check;
#   - the independent measure of ours (the @here decoder, posts placed by PROJ) against the
#     store's own posts agrees with errors.json (the exporter's measure, GeographicLib): nowhere
#     above it by more than 2 cm, within 2 cm on >= 90 % of the tiles of >= 1000 posts and below
#     it by at most 10 % on the others (errors.json also measures the lattice posts, which can
#     hold a tile's maximum: on the 3601^2 Pyrenees tile 799 of 815 within 2 cm, 4.7 % at most);
#   - every tile of every set with DEM posts in it has a finite true error; no post falls outside
#     every triangle of its tile; martini's and delatin's median tile at the deepest level within
#     2 x the bound (they mesh a grid of the DEM at the bound: a wrong height scale or placement
#     in the encoder or the measure would be far off);
#   - the table has its three rows.
# Needs node (the meshers and the decoder run on it; npm once: tools/qm_compare.sh installs them),
# python3 with GDAL's bindings and numpy (tools/deps.sh); a missing one fails, never a skip.
# About 10-20 s on the shared 2-core machine.
set -u
TP=$1 ROOT=$2 DATA=$3 WORK=$4
fail() { echo "FAIL: $*"; [ -s "$WORK/err" ] && tail -5 "$WORK/err"; exit 1; }
rm -rf "$WORK" && mkdir -p "$WORK" || exit 1
command -v node > /dev/null || fail "node is not installed (Node.js 18 or newer, with npm: Debian packages nodejs and npm, not installed by tools/deps.sh)"
command -v python3 > /dev/null || fail "python3 is not installed"
sh "$ROOT/tools/qm_compare.sh" --terrapatch "$TP" --max-zoom 11 "$DATA/craterlake-elev-16bit-30m.tif" \
    "$WORK/run" > "$WORK/table.txt" 2> "$WORK/err" || fail "tools/qm_compare.sh: $(tail -1 "$WORK/err")"
cat "$WORK/table.txt"
rows=$(grep -c '^| \(ours\|martini\|delatin\) |' "$WORK/table.txt")
[ "$rows" = 3 ] || fail "the table has $rows rows of tilers, not 3"
python3 - "$WORK/run" "$ROOT/tests" << 'EOF' || fail "the checks above"
import gzip, json, math, os, sys
work, tests = sys.argv[1], sys.argv[2]
sys.path.insert(0, tests)
import qm_check  # noqa: E402  (its decode and check_tile; failures print FAIL and exit 1)

def fail(msg):
    print("FAIL: " + msg)
    sys.exit(1)

layer = json.load(open(os.path.join(work, "ours", "layer.json")))
want = set()
for z, ranges in enumerate(layer["available"]):
    for r in ranges:
        want |= {(z, x, y) for x in range(r["startX"], r["endX"] + 1) for y in range(r["startY"], r["endY"] + 1)}
if layer["maxzoom"] != 11 or len(want) < 10:
    fail("ours: maxzoom %d, %d tiles" % (layer["maxzoom"], len(want)))
for s in ("ours", "martini", "delatin"):
    got = set()
    for root, _, files in os.walk(os.path.join(work, s)):
        for f in files:
            if f.endswith(".terrain"):
                z, x = root.split(os.sep)[-2:]
                got.add((int(z), int(x), int(f[:-8])))
    if got != want:
        fail("%s: %d tiles, not the %d of layer.json (%s)" % (s, len(got), len(want), sorted(got ^ want)[:4]))
    if s != "ours":
        for z, x, y in sorted(got):
            p = os.path.join(work, s, "%d/%d/%d.terrain" % (z, x, y))
            qm_check.check_tile(qm_check.decode(gzip.decompress(open(p, "rb").read()), p), z, x, y, p)
sm = json.load(open(os.path.join(work, "summary.json")))
o = sm["ours"]
if o["pairs"] < 3 or o["watertight_pairs"] != o["pairs"]:
    fail("ours: %d of %d neighbour pairs watertight" % (o["watertight_pairs"], o["pairs"]))
sc = sm["store_check"]
if not sc or sc["tiles_1000_posts"] < 5:
    fail("the store check measured %s" % sc)
# errors.json measures the store's posts and the lattice's: the independent measure may be lower
# where a lattice post holds the tile's maximum, never higher
if (sc["max_excess_m"] > 0.02 or sc["within_2cm_1000_posts"] < 0.9 * sc["tiles_1000_posts"] or
        sc["max_shortfall_ratio_1000_posts"] > 0.1):
    fail("the independent measure and errors.json disagree: %s" % sc)
for s in ("ours", "martini", "delatin"):
    m = json.load(open(os.path.join(work, "measure-%s.json" % s)))
    if m["unplaced_posts"]:
        fail("%s: %d posts outside every triangle" % (s, m["unplaced_posts"]))
    for t in m["tiles"]:
        if t["posts"] and not (isinstance(t["max_error"], (int, float)) and math.isfinite(t["max_error"])):
            fail("%s %d/%d/%d: true error %r" % (s, t["z"], t["x"], t["y"], t["max_error"]))
    if not math.isfinite(sm[s]["deep_max"]) or sm[s]["deep_max"] <= 0:
        fail("%s: deepest level's true error %r" % (s, sm[s]["deep_max"]))
    if s != "ours" and sm[s]["deep_median"] > 2 * sm[s]["deep_bound"]:
        fail("%s: deepest level's median tile %.2f m, above 2 x the bound %.2f" % (s, sm[s]["deep_median"], sm[s]["deep_bound"]))
print("PASS qm_compare.crater: %d tiles in each set; ours watertight (%d pairs), its measure within %.4f m "
      "of errors.json on the tiles of >= 1000 posts; deepest level true max: ours %.2f, martini %.2f, delatin %.2f m (bound %.2f)" % (
          len(want), o["pairs"], sc["max_abs_diff_1000_posts_m"], o["deep_max"], sm["martini"]["deep_max"],
          sm["delatin"]["deep_max"], o["deep_bound"]))
EOF
