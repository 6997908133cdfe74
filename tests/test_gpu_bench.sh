#!/bin/bash
# test_gpu_bench.sh TERRAPATCH WORK_DIR: tools/gpu_bench.sh --quick (issue 32, item 6) on this
# machine's renderer (llvmpipe): it exits 0 and prints the "Real relief" table of one 257^2
# store and the DEM bench's low-path table, in docs/PERFORMANCE.md's form, every cell filled;
# cells checked against the JSON the benches wrote (fps, triangles, measured error, the map's
# width) and the table on stdout is OUT/tables.md. The cache (the mosaic and store) is kept in
# WORK_DIR between runs: the first takes ~30 s, the next ~15 s.
set -u
TP=$1 WORK=$2
ROOT=$(cd "$(dirname "$0")/.." && pwd)
mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAIL: $*"; [ -s err ] && { echo "--- stderr"; tail -20 err; }; exit 1; }
rm -rf out
"$ROOT/tools/gpu_bench.sh" --quick --terrapatch "$TP" --cache "$WORK/cache" --out "$WORK/out" \
    > table 2> err || fail "gpu_bench.sh --quick: exit $?"
cmp -s table out/tables.md || fail "stdout is not out/tables.md"
python3 - << 'PY' || fail "the table"
import json, re
text = open("table").read()
print(text)
rows = {}
for line in text.splitlines():
    m = re.match(r"^\| ([^|]+?) \| (.*) \|$", line)
    if m:
        rows.setdefault(m.group(1).strip(), []).append([c.strip() for c in m.group(2).split("|")])
j = lambda name: json.load(open("out/%s.json" % name))
low, low300, high, build = (j("real_257_%s" % k) for k in ("low100", "low300", "high", "build"))
meta = j("real_meta")
assert meta["pixel_m"] == 60
head = [l for l in text.splitlines() if l.startswith("| | ")][0]
assert head == "| | 257² (%.0f km) |" % ((build["width"] - 1) * 60 / 1000.0), head
want = ["build (`terrapatch build --json`)",
        "first frame from the process's start (open + GL context)", "fps median, low 100 m/s",
        "triangles median / nodes drawn / visited", "CPU ms median (cut + stream + uploads)",
        "measured max screen error (frames without substitution)",
        "frames with substitution, 100 / 300 m/s", "p99 / median, 100 / 300 m/s",
        "high path: fps, triangles, nodes", "high path: measured max screen error",
        "distance mode, low: fps, triangles, nodes, CPU", "GPU vertex data",
        "RSS anonymous during the flight", "RSS anonymous at start (node table mapped)",
        "decoded nodes resident (stream)", "peak RSS"]
for name in want:
    assert name in rows, "no row '%s'" % name
    cell = rows[name][0][0]
    assert cell and "not run" not in cell and "n/a" not in cell and "not measured" not in cell, \
        "%s: '%s'" % (name, cell)
    assert re.search(r"\d", cell), "%s: '%s'" % (name, cell)
c0 = low["configurations"]
assert rows["fps median, low 100 m/s"][0][0] == "%.1f" % c0[0]["fps_median"]
assert rows["measured max screen error (frames without substitution)"][0][0].startswith(
    "%.3f px" % c0[0]["max_screen_error_px"])
assert rows["high path: measured max screen error"][0][0].startswith(
    "%.3f px" % high["configurations"][0]["max_screen_error_px"])
assert 0 < c0[0]["max_screen_error_px"] <= 1 + 1e-3  # tau = 1
assert rows["frames with substitution, 100 / 300 m/s"][0][0] == "%d of %d / %d of %d" % (
    c0[0]["frames_with_substitution"], low["frames"],
    low300["configurations"][0]["frames_with_substitution"], low300["frames"])
assert "Renderer: %s;" % low["renderer"] in text
dem = j("storml_elev_tif_low")
tri = {r[2]: r[7] for r in rows["storml_elev.tif"]}  # configuration -> triangles
for c in dem["configurations"]:
    key = {"error": "error τ=%g" % c.get("tau_px", 1), "distance": "distance"}.get(c["lod_mode"], "full")
    assert tri[key] == "%.0f" % c["triangles_median"], (key, tri[key], c["triangles_median"])
print("checked %d rows" % len(want))
PY
echo PASS
