#!/bin/bash
# readme_examples.sh README EXE DATA_DIR WORK_DIR [selfcheck]: runs the README's examples and
# compares what they print with the text (issue 29, 4.10). With "selfcheck", checks the check:
# a copy of README with one figure changed fails, naming that line, and timings pass within
# their tolerance and fail outside it.
#
# An example is a fenced block (```) whose first line starts with "$ ": each "$ " line is a
# command, run by bash from WORK_DIR, where build/terrapatch is EXE and data/ is DATA_DIR (the
# README's examples are run from the repository root); the lines after it, up to the next "$ "
# line or the fence, are what it prints on stdout, compared line for line:
#   - exactly, but for
#   - timings: on a line starting "time", a number followed by " ms" or " s" matches any number
#     from 0 to 20 times the README's figure, or to 1 s where that is more (machines, loads and
#     sanitizer builds differ; the other figures of the line are compared exactly).
# stderr (progress, the store cache's notes) is not compared. The store cache is WORK_DIR/cache,
# kept between runs; the files the examples write go to WORK_DIR. Fenced blocks without a "$ "
# first line (```sh lists of commands) are not run: they need a display, the network or minutes.
set -u
README=$1 EXE=$2 DATA=$3 WORK=$4 MODE=${5:-}
SELF=$(cd "$(dirname "$0")" && pwd)/$(basename "$0")
README=$(cd "$(dirname "$README")" && pwd)/$(basename "$README")
EXE=$(cd "$(dirname "$EXE")" && pwd)/$(basename "$EXE")
DATA=$(cd "$DATA" && pwd)
mkdir -p "$WORK/build" && cd "$WORK" || exit 1

ln -sfn "$EXE" build/terrapatch && ln -sfn "$DATA" data || exit 1
export TP_CACHE_DIR=$WORK/cache

# The examples, as records: "C<TAB>command" then "E<TAB>expected line" for each line it prints.
awk '
    /^```/ { if (fence) { fence = 0; run = 0 } else { fence = 1; first = 1 }; next }
    fence && first { first = 0; run = /^\$ / }
    fence && run && /^\$ / { print "C\t" substr($0, 3); next }
    fence && run { print "E\t" $0 }
' "$README" > examples.tsv
count=$(grep -c '^C' examples.tsv)
[ "$count" -gt 0 ] || { echo "FAIL: no examples found in $README"; exit 1; }

# compare EXPECTED ACTUAL: 0 when they match as above
compare() {
    awk -v tol=20 -v floor_ms=1000 '
        function timing_ok(want, got, unit,   lim) {
            if (got !~ /^[0-9]+(\.[0-9]+)?$/) return 0
            lim = tol * want
            if (unit == "ms" && lim < floor_ms) lim = floor_ms
            if (unit == "s" && lim < floor_ms / 1000) lim = floor_ms / 1000
            return got + 0 >= 0 && got + 0 <= lim
        }
        NR == FNR { want[++n] = $0; next }
        { got[++m] = $0 }
        END {
            bad = 0
            for (i = 1; i <= (n > m ? n : m); i++) {
                w = want[i]; g = got[i]
                if (w == g) continue
                if (w ~ /^time/ && g ~ /^time/) {
                    nw = split(w, a, " "); ng = split(g, b, " ")
                    ok = nw == ng
                    for (k = 1; ok && k <= nw; k++) {
                        if (a[k] == b[k]) continue
                        if (k < nw && (a[k + 1] == "ms" || a[k + 1] == "s") && a[k] ~ /^[0-9.]+$/)
                            ok = timing_ok(a[k], b[k], a[k + 1])
                        else
                            ok = 0
                    }
                    if (ok) continue
                }
                printf "  line %d: README: %s\n  line %d: printed: %s\n", i, w, i, g
                bad = 1
            }
            exit bad
        }' "$1" "$2"
}

if [ "$MODE" = selfcheck ]; then
    # 1. the last digit of the first example's first figure changed: that example fails, naming
    # the line
    awk '/^\$ / && !done { cmd = 1; print; next }
         cmd && !done && match($0, /[0-9]\.[0-9]+/) {
             d = substr($0, RSTART + RLENGTH - 1, 1); d = (d + 1) % 10
             $0 = substr($0, 1, RSTART + RLENGTH - 2) d substr($0, RSTART + RLENGTH); done = 1 }
         { print }' "$README" > figure.md
    ! cmp -s "$README" figure.md || { echo "FAIL: the copy changed nothing"; exit 1; }
    if bash "$SELF" "$WORK/figure.md" "$EXE" "$DATA" "$WORK/figure" > figure.out 2>&1; then
        cat figure.out; echo "FAIL: a README with a wrong figure passed"; exit 1
    fi
    changed=$(diff "$README" figure.md | sed -n 's/^> //p')
    grep -qF "README: $changed" figure.out && [ "$(grep -c '^FAIL ' figure.out)" -eq 1 ] ||
        { cat figure.out; echo "FAIL: the wrong figure is not the one failure named"; exit 1; }
    echo "ok: a wrong figure is found"; grep -m 2 'line [0-9]*: ' figure.out
    # 2. timings: within 0 .. max(20 x, 1 s); the other words of a time line exactly
    t() { printf '%s\n' "$1" > want.txt; printf '%s\n' "$2" > got.txt
          compare want.txt got.txt > /dev/null; r=$?
          [ "$r" -eq "$3" ] || { echo "FAIL: '$1' against '$2': $r, expected $3"; exit 1; }; }
    t "time  10.0 ms reading, 5.0 s for it" "time  999.9 ms reading, 100.0 s for it" 0
    t "time  100.0 ms reading" "time  2000.0 ms reading" 0
    t "time  100.0 ms reading" "time  2000.1 ms reading" 1
    t "time  1.0 s for it" "time  1.1 s for it" 0
    t "time  0.1 s for it" "time  2.1 s for it" 1
    t "time  10.0 ms reading" "time  -1.0 ms reading" 1
    t "time  10.0 ms reading" "time  10.0 s reading" 1
    t "time  10.0 ms reading" "time  10.0 ms writing" 1
    t "seen  10.0 ms" "seen  10.1 ms" 1
    echo "ok: timings within their tolerance, nothing else"
    exit 0
fi

failed=0 i=0
while IFS= read -r rec; do
    case "$rec" in C$'\t'*) ;; *) continue ;; esac
    i=$((i + 1))
    cmd=${rec#C$'\t'}
    # its expected lines: the E records up to the next C
    awk -v k="$i" -F '\t' '$1 == "C" { c++; next } c == k { sub(/^E\t/, ""); print }' \
        examples.tsv > expected.txt
    bash -c "$cmd" > printed.txt 2> stderr.txt
    rc=$?
    if compare expected.txt printed.txt > diff.txt; then
        echo "ok   $i/$count: \$ $cmd"
    else
        failed=$((failed + 1))
        echo "FAIL $i/$count: \$ $cmd (exit $rc)"
        cat diff.txt
        sed 's/^/  stderr: /' stderr.txt | tail -n 5
    fi
done < examples.tsv
[ "$failed" -eq 0 ] || { echo "$failed of $count examples print other figures than the README"; exit 1; }
echo "all $count examples print what the README says"
