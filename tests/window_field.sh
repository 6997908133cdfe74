#!/usr/bin/env bash
# window_field.sh - the viewer's field tools in a real window (Xvfb), driven with xdotool:
#   1. R, then two right clicks (a valley east of Mt Hood, then its upper east flank): the line of
#      sight is printed ("los: from LAT LON ... to LAT LON ...: ... HIDDEN/VISIBLE ..."), and
#      `terrapatch los` between the same two points gives the same answer (and the same blocking
#      within 1 m: the viewer prints the points to 1e-6 degrees);
#   2. B over the summit: the viewshed's line ("viewshed from ... % of N posts hidden") with
#      N > 100000 (10 km of 30 m posts) and a share strictly between 0 and 100%.
# usage: window_field.sh TERRAPATCH DEM WORKDIR. Needs Xvfb and xdotool (exit 1 without them).
set -u
exe=$1 dem=$2 dir=$3
mkdir -p "$dir"
name=window_field
. "$(dirname "$0")/window_lib.sh"
window_xvfb 161 230
window_view "$dem"
window_focus
xdotool key --clearmodifiers r; sleep 0.5
xdotool mousemove --window "$wid" 700 260; sleep 0.3; xdotool click 3; sleep 0.8
xdotool mousemove --window "$wid" 480 290; sleep 0.3; xdotool click 3; sleep 1.5
xdotool mousemove --window "$wid" 468 258; sleep 0.3
xdotool key --clearmodifiers b; sleep 2
window_close
fail=0
[ "$rc" = 0 ] || { echo "FAIL: the viewer exited with $rc"; cat "$dir/stderr.txt"; fail=1; }
los=$(grep '^los: from ' "$dir/stdout.txt" | head -n1)
vs=$(grep '^viewshed from ' "$dir/stdout.txt" | head -n1)
echo "window_field: $los"
echo "window_field: $vs"
if [ -z "$los" ]; then
    echo "FAIL: no line of sight printed"; fail=1
else
    from=$(echo "$los" | sed -E 's/^los: from ([-0-9.]+) ([-0-9.]+) .*/\1,\2/')
    to=$(echo "$los" | sed -E 's/.* to ([-0-9.]+) ([-0-9.]+) .*/\1,\2/')
    "$exe" los "$dem" --from "$from" --to "$to" --json "$dir/los.json" >/dev/null 2>"$dir/los.err" ||
        { echo "FAIL: terrapatch los $from $to failed"; cat "$dir/los.err"; fail=1; }
    if [ -f "$dir/los.json" ]; then
        if grep -q '"visible": true' "$dir/los.json"; then cli=VISIBLE; else cli=HIDDEN; fi
        echo "$los" | grep -q ": $cli" || { echo "FAIL: the viewer and terrapatch los ($cli) disagree"; fail=1; }
        if [ "$cli" = HIDDEN ]; then
            b1=$(echo "$los" | sed -E 's/.*obstruction ([0-9.]+) m above.*/\1/')
            b2=$(sed -n 's/.*"blocking_m": \([0-9.]*\).*/\1/p' "$dir/los.json")
            awk -v a="$b1" -v b="$b2" 'BEGIN { d = a - b; exit !(d < 1 && d > -1) }' ||
                { echo "FAIL: blocking $b1 m in the viewer, $b2 m from terrapatch los"; fail=1; }
        fi
    fi
fi
if [ -z "$vs" ]; then
    echo "FAIL: no viewshed printed"; fail=1
else
    share=$(echo "$vs" | sed -E 's/.*: ([0-9.]+)% of ([0-9]+) posts.*/\1/')
    posts=$(echo "$vs" | sed -E 's/.*: ([0-9.]+)% of ([0-9]+) posts.*/\2/')
    awk -v s="$share" -v n="$posts" 'BEGIN { exit !(s > 0 && s < 100 && n > 100000) }' ||
        { echo "FAIL: viewshed share $share% of $posts posts"; fail=1; }
fi
[ "$fail" = 0 ] && echo "window_field: passed"
exit "$fail"
