#!/bin/bash
# bench_ab.sh OLD_BINARY NEW_BINARY OUT_DIR DEM... - `terrapatch bench` of two binaries alternated
# on the same DEMs (old, new, old, new, ...; ROUNDS rounds, default 3), so that both see the same
# load on a shared machine; one JSON a run in OUT_DIR, NAME-old-R.json / NAME-new-R.json. The
# figures of docs/PERFORMANCE.md "The rooms (issue 30): old and new binaries" came from
#   tools/bench_ab.sh OLD/terrapatch build/terrapatch /tmp/bench_ab data/lf_elev_220_mt_hood_utm.tif
# with ROUNDS=6.
set -eu
[ $# -ge 4 ] || { echo "usage: $0 OLD NEW OUT_DIR DEM..." >&2; exit 2; }
old=$1 new=$2 out=$3
shift 3
mkdir -p "$out"
export TP_CACHE_DIR="$out/cache"
for dem in "$@"; do
    name=$(basename "$dem" | cut -d. -f1)
    for r in $(seq 1 "${ROUNDS:-3}"); do
        for b in old new; do
            bin=$old
            [ $b = new ] && bin=$new
            "$bin" bench --frames 30 --size 640x360 --json "$out/$name-$b-$r.json" "$dem" \
                > "$out/$name-$b-$r.txt" 2>&1
        done
    done
done
