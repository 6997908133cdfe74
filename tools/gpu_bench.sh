#!/bin/bash
# tools/gpu_bench.sh: the bench tables of docs/PERFORMANCE.md in one command, for a machine with
# a GPU (issue 32, item 6): the "Real relief at 10 m" table (stores of 8193^2, 20481^2 and
# 65537^2 mirrored from data/N42E001.hgt with real slopes, flown low at 100 and 300 m/s and
# high) and the DEM bench's low path on data/N42E001.hgt, printed as those tables are.
#
#   tools/gpu_bench.sh [options]
#
#   --quick              small and fast (what its test runs on llvmpipe, under a minute): a
#                        store of 257^2 at 60 m posts, 4 frames of 320x180 a run, the DEM
#                        bench on data/storml_elev.tif
#   --sizes "S1 S2 ..."  the stores' sizes (default "8193 20481 65537"; --quick "257"): one
#                        mosaic each (make_mirror_dem.py: ~30 s at 10 m, ~10 s at 60 m)
#   --dem FILE           the DEM bench's DEM (default data/N42E001.hgt; --quick
#                        data/storml_elev.tif)
#   --cache DIR          the mirrored DEMs and the stores, kept between runs (default
#                        ${XDG_CACHE_HOME:-~/.cache}/terrapatch/gpu_bench; --quick: .../quick)
#   --out DIR            every run's JSON, CSV and output, and tables.md (default
#                        build/gpu_bench, build/gpu_bench_quick)
#   --terrapatch BIN     the binary (default build/terrapatch)
#   --threads N          build threads (default 2, as the table's builds)
#   --allow-software     go on when the renderer is a software one (llvmpipe, softpipe,
#                        swrast); without it a full run stops there: its figures would not be
#                        a GPU's (--quick allows it)
#   -h, --help           this text
#
# Needs python3, gdal-bin (tools/make_mirror_dem.py) and about 3 GB of disk for the full sizes
# (the 65537^2 store is 2.8 GB; its build takes ~5 min on 2 threads). A store or mosaic that
# exists is reused (delete the cache to rebuild). The commands run are those listed under
# docs/PERFORMANCE.md's tables; each one's output is kept in OUT/*.txt.
set -uo pipefail
here=$PWD
root=$(cd "$(dirname "$0")/.." && pwd) || exit 1
# a path given on the command line is the caller's; the defaults are the repository's
abs() { case $1 in /*) echo "$1" ;; *) echo "$here/$1" ;; esac; }

quick=0 sizes="" cache="" out="" tp=build/terrapatch threads=2 soft=0 dem=""
usage() { sed -n '2,/^set /p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }
while [ $# -gt 0 ]; do
    case $1 in
    --quick) quick=1 ;;
    --sizes) sizes=${2:?--sizes needs a value}; shift ;;
    --dem) dem=$(abs "${2:?--dem needs a file}"); shift ;;
    --cache) cache=$(abs "${2:?--cache needs a directory}"); shift ;;
    --out) out=$(abs "${2:?--out needs a directory}"); shift ;;
    --terrapatch) tp=$(abs "${2:?--terrapatch needs a path}"); shift ;;
    --threads) threads=${2:?--threads needs a count}; shift ;;
    --allow-software) soft=1 ;;
    -h | --help) usage; exit 0 ;;
    *) echo "gpu_bench: unknown option '$1' (see --help)" >&2; exit 2 ;;
    esac
    shift
done
cd "$root" || exit 1
die() { echo "gpu_bench: $*" >&2; exit 1; }
[ -x "$tp" ] || die "$tp is not an executable: build first (make build), or give --terrapatch"
tp=$(cd "$(dirname "$tp")" && pwd)/$(basename "$tp")
command -v python3 > /dev/null || die "python3 not found"
base=${XDG_CACHE_HOME:-$HOME/.cache}/terrapatch/gpu_bench
if [ $quick = 1 ]; then
    sizes=${sizes:-257} cache=${cache:-$base/quick} out=${out:-build/gpu_bench_quick}
    dem=${dem:-data/storml_elev.tif}
    pixel=60 soft=1
    frames_low=(--frames 4 --segments 2) frames_high=(--frames 4 --segments 2)
    every=(--error-every 2) view=(--size 320x180) memory=64 dem_frames=(--frames 4)
else
    sizes=${sizes:-8193 20481 65537} cache=${cache:-$base} out=${out:-build/gpu_bench}
    dem=${dem:-data/N42E001.hgt}
    pixel=10
    frames_low=(--frames 24 --segments 4) frames_high=(--frames 12 --segments 2)
    every=(--error-every 6) view=() memory=128 dem_frames=(--frames 60)
fi
for n in $sizes; do
    [[ $n =~ ^[0-9]+$ ]] && [ "$n" -ge 17 ] || die "--sizes: '$n' is not a size of 17 or more"
done
mkdir -p "$cache" "$out" || die "cannot make $cache or $out"
out=$(cd "$out" && pwd)
echo "{\"pixel_m\": $pixel}" > "$out/real_meta.json"

# run NAME CMD...: one command, its output in OUT/NAME.txt; says how it went on stderr.
failed=0
run() {
    local name=$1 t0=$SECONDS
    shift
    echo "gpu_bench: $name: $*" >&2
    if "$@" > "$out/$name.txt" 2>&1; then
        echo "gpu_bench: $name: done in $((SECONDS - t0)) s" >&2
        return 0
    fi
    echo "gpu_bench: $name: FAILED (exit $?); the end of $out/$name.txt:" >&2
    tail -5 "$out/$name.txt" >&2
    failed=$((failed + 1))
    return 1
}

# The renderer the benches will draw with (a one-frame DEM bench): a full run on a software
# renderer measures a CPU, not a GPU.
run renderer "$tp" bench --frames 1 --size 64x64 --no-error --json "$out/renderer.json" \
    data/storml_elev.tif || die "terrapatch cannot draw: see $out/renderer.txt"
renderer=$(python3 -c 'import json, sys; print(json.load(open(sys.argv[1]))["renderer"])' \
    "$out/renderer.json")
echo "gpu_bench: renderer: $renderer" >&2
case $renderer in
*llvmpipe* | *softpipe* | *swrast* | *"Software Rasterizer"*)
    [ $soft = 1 ] || die "the renderer is '$renderer', a software one: no GPU is in use (EGL \
picked Mesa; see docs/PERFORMANCE.md, \"tools/gpu_bench.sh\"); --allow-software runs anyway" ;;
esac

slopes=(--real-slopes)
[ $pixel = 10 ] || slopes+=(--pixel-m "$pixel")
for n in $sizes; do
    vrt=$cache/mirror_${n}_real.vrt store=$cache/real_$n.tpt
    if [ ! -s "$vrt" ]; then
        run "mirror_$n" python3 "$root/tools/make_mirror_dem.py" "${slopes[@]}" "$n" "$cache" || continue
    fi
    if [ ! -s "$store" ] || [ ! -s "$cache/real_${n}_build.json" ]; then
        run "build_$n" "$tp" build --threads "$threads" --quiet --json "$cache/real_${n}_build.json" \
            "$vrt" -o "$store" || continue
    fi
    cp "$cache/real_${n}_build.json" "$out/real_${n}_build.json"
    common=(--tau 1 --memory $memory "${view[@]}")
    run "real_${n}_low100" "$tp" bench "${frames_low[@]}" "${every[@]}" --speed 100 "${common[@]}" \
        --json "$out/real_${n}_low100.json" --csv "$out/real_${n}_low100.csv" "$store"
    run "real_${n}_low300" "$tp" bench "${frames_low[@]}" --no-error --speed 300 "${common[@]}" \
        --json "$out/real_${n}_low300.json" --csv "$out/real_${n}_low300.csv" "$store"
    run "real_${n}_high" "$tp" bench "${frames_high[@]}" "${every[@]}" --speed 100 --path high \
        "${common[@]}" --json "$out/real_${n}_high.json" --csv "$out/real_${n}_high.csv" "$store"
done

[ -f "$dem" ] || die "$dem not found"
file=$(basename "$dem") name=${file%.*}_${file##*.}
echo "gpu_bench: ${name}_info: $tp info --json $dem" >&2
"$tp" info --json "$dem" > "$out/${name}_info.json" 2> "$out/${name}_info.txt" ||
    { echo "gpu_bench: ${name}_info: FAILED" >&2; failed=$((failed + 1)); }
run "${name}_low" "$tp" bench "${dem_frames[@]}" --tau 1 --path low "${view[@]}" \
    --json "$out/${name}_low.json" --csv "$out/${name}_low.csv" "$dem"

{
    echo "## tools/gpu_bench.sh$([ $quick = 1 ] && echo " --quick"), $(date -u +%Y-%m-%d), $(hostname)"
    echo
    echo "### Real relief at $pixel m"
    echo
    python3 "$root/tools/bench_tables.py" --stores "$out" $sizes
    echo "The DEM bench on $dem:"
    echo
    python3 "$root/tools/bench_tables.py" --paths low "$out" "$file"
} > "$out/tables.md" || die "the tables could not be written"
cat "$out/tables.md"
echo "gpu_bench: wrote $out/tables.md; $failed command(s) failed" >&2
[ $failed = 0 ]
