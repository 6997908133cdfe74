#!/usr/bin/env bash
# window_bookmarks.sh - bookmarks in a real window (Xvfb + xdotool): Ctrl+1 saves the view as
# "view 1" (into --bookmarks FILE), W flies away, 1 brings the saved view back exactly (C prints
# the camera each time), and the file holds the line.
# usage: window_bookmarks.sh TERRAPATCH DEM WORKDIR
# Needs Xvfb and xdotool (`make deps` installs them); exits 1 without them: a skip would hide
# that the window was never tried.
set -u
exe=$1 dem=$2 dir=$3
mkdir -p "$dir"
name=window_bookmarks
. "$(dirname "$0")/window_lib.sh"
window_xvfb 91 160
rm -f "$dir/b.bookmarks"
window_view --bookmarks "$dir/b.bookmarks" "$dem"
xdotool mousemove --window "$wid" 480 270
window_focus

tap() { xdotool key --clearmodifiers --delay 0 "$1"; sleep 0.4; }
tap c
xdotool key --delay 0 ctrl+1; sleep 0.6
xdotool keydown w; sleep 1.5; xdotool keyup w
sleep 0.5
tap c
tap 1
sleep 0.5
tap c
window_close
fail=0
cat "$dir/stdout.txt"
[ "$rc" = 0 ] || { echo "FAIL: the viewer exited with $rc"; cat "$dir/stderr.txt"; fail=1; }
grep -q "^bookmark 'view 1' saved in $dir/b.bookmarks" "$dir/stdout.txt" || { echo "FAIL: Ctrl+1 did not save"; fail=1; }
grep -q "^bookmark 'view 1'$" "$dir/stdout.txt" || { echo "FAIL: 1 did not recall"; fail=1; }
grep -q "^view 1 --camera-geo " "$dir/b.bookmarks" || { echo "FAIL: no 'view 1' line in the file"; fail=1; }
cams=$(grep -c '^--camera ' "$dir/stdout.txt")
if [ "$cams" = 3 ]; then
    first=$(grep '^--camera ' "$dir/stdout.txt" | sed -n 1p)
    moved=$(grep '^--camera ' "$dir/stdout.txt" | sed -n 2p)
    back=$(grep '^--camera ' "$dir/stdout.txt" | sed -n 3p)
    [ "$first" != "$moved" ] || { echo "FAIL: W did not move the camera"; fail=1; }
    # the file keeps the position to 1e-9 degrees and 1 cm: compare to 0.05 m
    awk -v a="${first#--camera }" -v b="${back#--camera }" 'BEGIN { split(a, p, ","); split(b, q, ",");
        for (i = 1; i <= 5; i++) if ((p[i] - q[i]) ^ 2 > 0.0025) exit 1 }' ||
        { echo "FAIL: 1 did not bring back the saved view: $first vs $back"; fail=1; }
else
    echo "FAIL: expected 3 camera lines, got $cams"; fail=1
fi
[ "$fail" = 0 ] && echo "window_bookmarks: passed"
exit "$fail"
