#!/bin/bash
# Runs every benchmark of docs/PERFORMANCE.md on every DEM in data/ and writes the
# markdown tables to build/bench/tables.md and the sweep plots to docs/img/bench/.
#   tools/bench_all.sh [FRAMES] [SWEEP_FRAMES] [DEM...]    (defaults: 60 20, every DEM)
# Per DEM: bench --path low|high|orbit (FRAMES frames each), bench --sweep (low path,
# SWEEP_FRAMES frames per configuration), bench --static --max-error 1,5,20.
set -u
cd "$(dirname "$0")/.."
frames=${1:-60}
sweep_frames=${2:-20}
shift 2 2>/dev/null
dems=("$@")
[ ${#dems[@]} -gt 0 ] || dems=(N42E001.hgt N42E001.dt1 N41E001.hgt mt_rainier_90m.tif
    lf_elev_220_mt_hood_utm.tif craterlake-elev-16bit-30m.tif storml_elev.tif storml_elev_orig.tif
    front_range_srtmgl3_758.asc front_range_srtmgl3_144.asc ps_height_1k.png)
out=build/bench
mkdir -p $out docs/img/bench
tp=./build/terrapatch
extra_for() {
    case $1 in
    front_range*) echo "--crs EPSG:4326" ;;          # the .asc grids carry no CRS
    ps_height*) echo "--spacing 160 --zscale 0.1" ;; # 16-bit PNG heightmap, see PROVENANCE
    *) echo "" ;;
    esac
}
for f in "${dems[@]}"; do
    name=${f%.*}_${f##*.}
    extra=$(extra_for "$f")
    src=data/$f
    $tp info --json $extra "$src" > $out/${name}_info.json 2>/dev/null || { echo "$f: info failed" >&2; continue; }
    for path in low high orbit; do
        echo "$f: $path path" >&2
        $tp bench --frames "$frames" --path $path $extra --json $out/${name}_$path.json "$src" \
            > $out/${name}_$path.txt 2>/dev/null || echo "$f: bench $path failed" >&2
    done
    echo "$f: sweep" >&2
    $tp bench --sweep --frames "$sweep_frames" $extra --csv $out/${name}_sweep.csv \
        --plot docs/img/bench/${name}_sweep.png --json $out/${name}_sweep.json "$src" \
        > $out/${name}_sweep.txt 2>/dev/null || echo "$f: sweep failed" >&2
    echo "$f: static" >&2
    $tp bench --static --max-error 1,5,20 $extra --json $out/${name}_static.json "$src" \
        > $out/${name}_static.txt 2>/dev/null || echo "$f: static failed" >&2
done
python3 tools/bench_tables.py $out "${dems[@]}" > $out/tables.md
echo "wrote $out/tables.md" >&2
