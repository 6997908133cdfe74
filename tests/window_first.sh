#!/usr/bin/env bash
# window_first.sh - the first picture of a new DEM in a real window (Xvfb, xdotool; issue 32,
# item 4): the window opens on a preview (its title says so) while the store is built, then
# goes on with the store in the same window from the same camera (C prints it before and
# after), Home still returns to the start view, and the store in the cache is `build
# --patch 17`'s. Esc during the preview closes the window and the build finishes (exit 0, the
# store complete).
# usage: window_first.sh TERRAPATCH DEM WORKDIR
# Needs Xvfb and xdotool (`make deps` installs them); exits 1 without them.
set -u
exe=$1 dem=$2 dir=$3
mkdir -p "$dir"
name=window_first
. "$(dirname "$0")/window_lib.sh"
window_xvfb 91 160
export TP_VIEW_PREVIEW_SAMPLES=20000
fail=0
bad() { echo "FAIL: $*"; fail=1; }
stores() { ls "$1" 2>/dev/null | grep -E '^[^.]+-[0-9a-f]{16}\.tpt$'; }
title() { xdotool getwindowname "$wid" 2>/dev/null; }

# 1. the preview, then the store in the same window
export TP_CACHE_DIR="$dir/cache"
rm -rf "$TP_CACHE_DIR"
window_view "$dem"
first_title=$(title)
echo "window_first: first title: $first_title"
echo "$first_title" | grep -q 'a preview of every [0-9]*[a-z]* post: building the store' ||
    bad "the first title does not say it is a preview"
xdotool mousemove --window "$wid" 480 270
window_focus
xdotool key --clearmodifiers c
sleep 0.5
for _ in $(seq 1200); do title | grep -q preview || break; sleep 0.1; done
title | grep -q preview && bad "the store never replaced the preview"
sleep 0.5
xdotool key --clearmodifiers c
sleep 0.5
xdotool keydown w; sleep 1; xdotool keyup w
sleep 0.5
xdotool key --clearmodifiers Home
sleep 0.5
xdotool key --clearmodifiers c
sleep 0.5
window_close
[ "$escaped" = 1 ] && [ "$rc" = 0 ] || bad "Esc after the store: escaped $escaped, exit $rc"
cams=$(grep -c '^--camera ' "$dir/stdout.txt")
[ "$cams" = 3 ] || bad "expected 3 camera lines, got $cams"
before=$(grep '^--camera ' "$dir/stdout.txt" | sed -n 1p)
after=$(grep '^--camera ' "$dir/stdout.txt" | sed -n 2p)
home=$(grep '^--camera ' "$dir/stdout.txt" | sed -n 3p)
[ -n "$before" ] && [ "$before" = "$after" ] ||
    bad "the store's view did not go on from the preview's camera: '$before' then '$after'"
[ "$before" = "$home" ] || bad "Home after the store landed: '$home', not the start '$before'"
grep -q 'a first picture from every' "$dir/stderr.txt" || bad "stderr does not say the preview"
[ "$(ls "$TP_CACHE_DIR")" = "$(stores "$TP_CACHE_DIR")" ] ||
    bad "the cache holds more than the store: $(ls "$TP_CACHE_DIR")"
"$exe" build --quiet --patch 17 "$(realpath "$dem")" -o "$dir/ref.tpt" || bad "build exit $?"
cmp -s "$TP_CACHE_DIR/$(stores "$TP_CACHE_DIR")" "$dir/ref.tpt" ||
    bad "the view's store differs from build --patch 17's"

# 2. Esc during the preview: the window closes, the store is still built whole
rm -rf "$TP_CACHE_DIR"
window_view "$dem"
title | grep -q preview || echo "window_first: note: the store landed before Esc (fast machine)"
xdotool key Escape
closed=0 # the window goes at once; the process when the build is done
for _ in $(seq 100); do
    xdotool search --name '^terrapatch' >/dev/null 2>&1 || { closed=1; break; }
    sleep 0.1
done
[ "$closed" = 1 ] || bad "Esc during the preview did not close the window"
for _ in $(seq 1200); do kill -0 "$vpid" 2>/dev/null || break; sleep 0.1; done
kill "$vpid" 2>/dev/null && bad "the build after Esc did not end in 120 s"
wait "$vpid"
rc=$?
vpid=
[ "$rc" = 0 ] || bad "Esc during the preview: exit $rc"
grep -q "finishing the store's build" "$dir/stderr.txt" ||
    echo "window_first: note: no 'finishing' line (the store landed before Esc)"
[ "$(stores "$TP_CACHE_DIR" | wc -l)" = 1 ] && [ "$(ls "$TP_CACHE_DIR" | wc -l)" = 1 ] ||
    bad "after Esc during the preview the cache holds: $(ls "$TP_CACHE_DIR")"
cmp -s "$TP_CACHE_DIR/$(stores "$TP_CACHE_DIR")" "$dir/ref.tpt" ||
    bad "the store finished after Esc differs from build --patch 17's"
[ "$fail" = 0 ] && echo "window_first: preview, store, Home and Esc as expected"
exit $fail
