#!/usr/bin/env bash
# window_keys.sh - the viewer in a real window (Xvfb), driven as a person would with xdotool:
#   1. five taps of C, each key press and release sent together (a tap shorter than a frame),
#      must print the camera five times: keys are queued, not polled once a frame;
#   2. W held for 2 s from the default view moves the camera, but less than 10 km (the DEM is
#      30 km wide; the old speed rule flew 115 km and off the map);
#   3. Home brings back the start view exactly.
# usage: window_keys.sh TERRAPATCH DEM WORKDIR
# Needs Xvfb and xdotool (`make deps` installs them); exits 1 without them: a skip would hide
# that the window was never tried.
set -u
exe=$1 dem=$2 dir=$3
mkdir -p "$dir"
name=window_keys
. "$(dirname "$0")/window_lib.sh"
window_xvfb 91 160
window_view "$dem"
xdotool mousemove --window "$wid" 480 270
window_focus

tap() { xdotool key --clearmodifiers --delay 0 "$1"; sleep 0.4; }
for _ in 1 2 3 4 5; do tap c; done
xdotool keydown w; sleep 2; xdotool keyup w
sleep 0.5
tap c
tap Home
sleep 0.5
tap c
window_close
fail=0
[ "$escaped" = 1 ] || { echo "FAIL: a tap of Esc did not close the viewer"; fail=1; }
lines=$(grep -c '^--camera ' "$dir/stdout.txt")
echo "window_keys: viewer exit status $rc; $lines camera lines:"
grep '^--camera ' "$dir/stdout.txt"
[ "$fail" = 1 ] || [ "$rc" = 0 ] || { echo "FAIL: the viewer exited with $rc"; cat "$dir/stderr.txt"; fail=1; }
[ "$lines" = 7 ] || { echo "FAIL: expected 7 camera lines (5 taps, after W, after Home), got $lines"; fail=1; }
if [ "$lines" -ge 7 ]; then
    first=$(grep '^--camera ' "$dir/stdout.txt" | sed -n 1p)
    moved=$(grep '^--camera ' "$dir/stdout.txt" | sed -n 6p)
    home=$(grep '^--camera ' "$dir/stdout.txt" | sed -n 7p)
    dist=$(awk -v a="${first#--camera }" -v b="${moved#--camera }" 'BEGIN {
        split(a, p, ","); split(b, q, ","); printf "%.1f", sqrt((p[1]-q[1])^2 + (p[2]-q[2])^2) }')
    echo "window_keys: 2 s of W moved the camera $dist m"
    awk -v d="$dist" 'BEGIN { exit !(d > 100 && d < 10000) }' ||
        { echo "FAIL: 2 s of W should move more than 100 m and less than 10 km"; fail=1; }
    [ "$first" = "$home" ] || { echo "FAIL: Home did not restore the start view"; fail=1; }
fi
[ "$fail" = 0 ] && echo "window_keys: passed"
exit "$fail"
