#!/bin/bash
# Runs `terrapatch bench` on every DEM in ../shared/data and prints a markdown table
# (docs/PERFORMANCE.md). Usage: tools/bench_all.sh [FRAMES] [PATH]   (defaults: 60 low)
cd "$(dirname "$0")/.."
frames=${1:-60}
path=${2:-low}
mkdir -p build/bench
echo "| DEM | render grid | patches | configuration | fps (median) | frame ms | CPU ms | draw ms | triangles | max px | RMS px | max m | RMS m |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for f in N42E001.hgt N41E001.hgt mt_rainier_90m.tif lf_elev_220_mt_hood_utm.tif craterlake-elev-16bit-30m.tif storml_elev.tif front_range_srtmgl3_758.asc ps_height_1k.png; do
  extra=""
  case $f in front_range*) extra="--crs EPSG:4326";; ps_height*) extra="--spacing 160 --zscale 0.1";; esac
  json=build/bench/${f%%.*}_$path.json
  ./build/terrapatch bench --frames "$frames" --path "$path" $extra --json "$json" ../shared/data/$f >/dev/null 2>&1 || { echo "| $f | failed |"; continue; }
  ./build/terrapatch info --json $extra ../shared/data/$f 2>/dev/null > build/bench/info.json
  python3 - "$json" "$f" build/bench/info.json <<'PY'
import json, sys
d = json.load(open(sys.argv[1])); info = json.load(open(sys.argv[3]))
grid = "%dx%d" % tuple(info["render_grid"])
for c in d["configurations"]:
    print("| %s | %s | %d | %s | %.1f | %.1f | %.3f | %.1f | %.0f | %.2f | %.3f | %.1f | %.2f |" % (
        sys.argv[2], grid, d["patches"], c["lod_mode"], c["fps_median"], c["frame_ms_median"],
        c["cpu_ms_median"], c["draw_ms_median"], c["triangles_median"], c["max_screen_error_px"],
        c["rms_screen_error_px"], c["max_vertical_error_m"], c["rms_vertical_error_m"]))
print("| | | | **error vs full** | **%.2fx** | | | | | | | | |" % d["speedup_vs_full"])
PY
done
