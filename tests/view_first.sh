#!/usr/bin/env bash
# view_first.sh - the first picture of a DEM whose store is not in the cache (issue 32, item 4):
# `view` draws a preview (the grid coarsened, store_cache.h) before the store is built, then
# the store; what it leaves is what a warm cache leaves.
#   preview  DEM...  for each DEM, a cold cache: the stats JSON says the first frame was drawn
#                    from the preview while the store's build ran (from "preview",
#                    build_running true, store_ms after ms), stderr says "a first picture"
#                    before the build's last line, the cache then holds the store alone (the
#                    preview removed), the store is byte for byte `build --patch 17`'s, and a
#                    second view (warm) writes the same screenshot and says it drew the store.
#   killed   DEM     kill -9 while the store's build runs on its thread (its progress seen on
#                    stderr): no store in the cache; the next view removes what the killed one
#                    left (preview, temporary file) and builds the store whole. SIGTERM there:
#                    exit 143, nothing left but the cache folder's own files.
# usage: view_first.sh TERRAPATCH WORKDIR preview|killed DEM...
# The previews are made small (TP_VIEW_PREVIEW_SAMPLES) so that the sample DEMs have one.
set -u
exe=$1 dir=$2 what=$3
shift 3
mkdir -p "$dir"
fail=0
bad() { echo "FAIL: $*"; fail=1; }
export TP_VIEW_PREVIEW_SAMPLES=20000
# the stores of the cache (not the lock, the preview or temporary files)
stores() { ls "$1" 2>/dev/null | grep -E '^[^.]+-[0-9a-f]{16}\.tpt$'; }
json_has() { tr -d '\n ' <"$1" | grep -q "$2"; }

preview_one() {
    local dem=$1 cache="$dir/cache-$(basename "$1")"
    rm -rf "$cache" "$dir"/a.* "$dir"/b.* "$dir/ref.tpt"
    TP_CACHE_DIR=$cache "$exe" view --headless --size 320x180 --screenshot "$dir/a.png" \
        --stats-json "$dir/a.json" "$dem" 2>"$dir/a.err" || bad "$dem: cold view exit $?"
    json_has "$dir/a.json" '"first_frame":{"ms":' || bad "$dem: no first_frame in the JSON"
    json_has "$dir/a.json" '"from":"preview","preview_coarsen":[0-9]*,"build_running":true' ||
        bad "$dem: the first frame was not drawn from a preview while the store was built"
    local ms store_ms
    ms=$(tr -d '\n ' <"$dir/a.json" | sed -n 's/.*"first_frame":{"ms":\([0-9.e+]*\),.*/\1/p')
    store_ms=$(tr -d '\n ' <"$dir/a.json" | sed -n 's/.*"store_ms":\([0-9.e+]*\)}.*/\1/p')
    awk -v a="$ms" -v b="$store_ms" 'BEGIN { exit !(a > 0 && b > a) }' ||
        bad "$dem: the store landed (${store_ms} ms) before the first frame (${ms} ms)"
    local first last
    first=$(grep -n 'a first picture from every' "$dir/a.err" | head -n1 | cut -d: -f1)
    last=$(grep -n '\.tpt: [0-9]*x[0-9]* samples' "$dir/a.err" | head -n1 | cut -d: -f1)
    [ -n "$first" ] && [ -n "$last" ] && [ "$first" -lt "$last" ] ||
        bad "$dem: stderr does not say the preview before the store's last line"
    local list
    list=$(ls "$cache")
    [ "$(stores "$cache" | wc -l)" = 1 ] && [ "$(echo "$list" | wc -l)" = 1 ] ||
        bad "$dem: the cache holds more than the store: $list"
    # the cache names its DEM by its absolute path (in the store's notes)
    "$exe" build --quiet --patch 17 "$(realpath "$dem")" -o "$dir/ref.tpt" || bad "$dem: build exit $?"
    cmp -s "$cache/$(stores "$cache")" "$dir/ref.tpt" ||
        bad "$dem: the view's store differs from build --patch 17's"
    TP_CACHE_DIR=$cache "$exe" view --headless --size 320x180 --screenshot "$dir/b.png" \
        --stats-json "$dir/b.json" "$dem" 2>"$dir/b.err" || bad "$dem: warm view exit $?"
    grep -q 'building' "$dir/b.err" && bad "$dem: the warm view built again"
    json_has "$dir/b.json" '"first_frame":{"ms":[0-9.e+]*,"from":"store"}' ||
        bad "$dem: the warm view's first frame is not the store's"
    cmp -s "$dir/a.png" "$dir/b.png" || bad "$dem: the cold view's screenshot differs from the warm one's"
    echo "view_first: $dem: first frame $ms ms (preview), store $store_ms ms"
}

killed_one() {
    local dem=$1 cache="$dir/cache-killed" sig
    for sig in KILL TERM; do
        rm -rf "$cache"
        TP_CACHE_DIR=$cache "$exe" view --headless --size 320x180 --stats-json "$dir/k.json" \
            "$dem" 2>"$dir/k.err" &
        local pid=$! seen=0
        for _ in $(seq 600); do # the build on its thread: its progress
            grep -qE '(range|build) +[0-9]+%' "$dir/k.err" 2>/dev/null && { seen=1; break; }
            kill -0 "$pid" 2>/dev/null || break
            sleep 0.05
        done 2>/dev/null
        kill -"$sig" "$pid" 2>/dev/null
        wait "$pid"
        local rc=$?
        [ "$seen" = 1 ] || bad "SIG$sig: no progress of the store's build seen before it ended"
        grep -q 'a first picture from every' "$dir/k.err" || bad "SIG$sig: no preview said"
        [ -z "$(stores "$cache")" ] || bad "SIG$sig: a store is in the cache after the kill"
        if [ "$sig" = TERM ]; then
            [ "$rc" = 143 ] || bad "SIGTERM: exit $rc, not 143"
            [ -z "$(ls "$cache" | grep -v '\.lock$')" ] ||
                bad "SIGTERM: left in the cache: $(ls "$cache")"
            continue
        fi
        [ -n "$(ls "$cache" | grep -E 'preview\.tpt|\.tmp')" ] ||
            echo "view_first: note: kill -9 left no preview nor temporary file"
        TP_CACHE_DIR=$cache "$exe" view --headless --size 320x180 --stats-json "$dir/k.json" \
            "$dem" 2>"$dir/k2.err" || bad "the view after kill -9: exit $?"
        [ "$(stores "$cache" | wc -l)" = 1 ] && [ "$(ls "$cache" | wc -l)" = 1 ] ||
            bad "after kill -9 and a view: $(ls "$cache")"
        "$exe" build --quiet --patch 17 "$(realpath "$dem")" -o "$dir/ref.tpt" || bad "build exit $?"
        cmp -s "$cache/$(stores "$cache")" "$dir/ref.tpt" ||
            bad "the store built after kill -9 differs from build --patch 17's"
    done
}

case $what in
preview) for dem in "$@"; do preview_one "$dem"; done ;;
killed) killed_one "$1" ;;
*) echo "usage: view_first.sh TERRAPATCH WORKDIR preview|killed DEM..."; exit 2 ;;
esac
exit $fail
