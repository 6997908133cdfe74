#!/bin/bash
# test_cli_prefix.sh EXE DATA_DIR WORK_DIR COMMAND: one prefix, "terrapatch COMMAND: ", on every
# line a command writes to stderr (docs/cli.md, "Messages"; issue 29, 4.9). For COMMAND:
#   - a bad option: exit 2, and stderr's first line starts "terrapatch COMMAND: ";
#   - a missing file (the DEM, store, route, image ...): exit 1, the same; for coord, which
#     opens no file, an input line it cannot read;
#   - every line of stderr in both runs starts with the prefix (errors, warnings, notes).
# COMMAND "none" checks the lines before a command is known ("terrapatch: "), "lines" the
# warnings, notes, progress and "wrote" lines of commands that succeed.
set -u
EXE=$1 DATA=$2 WORK=$3 CMD=$4
mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAIL ($CMD): $*"; [ -f err ] && { echo '--- stderr'; cat err; }; exit 1; }
# run ARGS...: runs EXE (60 s at most), stdout to out, stderr to err; sets rc
run() { timeout 60 "$EXE" "$@" > out 2> err; rc=$?; }
# expect RC PREFIX WHAT: the exit status, the first line and every line of stderr
expect() {
    [ "$rc" -eq "$1" ] || fail "$3: exit $rc, expected $1"
    [ -s err ] || fail "$3: nothing on stderr"
    head -n 1 err | grep -q "^$2" || fail "$3: stderr's first line does not start '$2'"
    ! grep -v "^$2" err > /dev/null || fail "$3: a line of stderr does not start '$2'"
}

MISSING=$WORK/no_such_dir/missing.tif
HGT=$DATA/N42E001.hgt
export TP_CACHE_DIR=$WORK/cache

case "$CMD" in
none)
    run --no-such-option; expect 2 "terrapatch: " "an unknown option before the command"
    run no-such-command; expect 2 "terrapatch: " "an unknown command"
    run; expect 2 "terrapatch: " "no command"
    exit 0 ;;
lines)
    # a warning (no CRS, plainly degrees) and nothing else on stderr
    run info "$DATA/front_range_srtmgl3_144.asc"
    expect 0 "terrapatch info: warning: " "info's warning"
    # notes and "wrote" lines: the cache build's, the position's, the outputs'
    run los "$HGT" --from 42.5,1.5 --to 42.6,1.6 --json a.json --csv a.csv
    expect 0 "terrapatch los: " "los with outputs"
    grep -q "^terrapatch los: wrote .*a\.json$" err || fail "los: no wrote line for a.json"
    # the progress of a build on a log (not a terminal): a line per tenth
    run build "$DATA/storml_elev_orig.tif" -o s.tpt --patch 17
    expect 0 "terrapatch build: " "build's progress"
    grep -q "^terrapatch build: build 100%" err || fail "build: no progress line"
    exit 0 ;;
esac

P="terrapatch $CMD: "
run "$CMD" --no-such-option-xyz
expect 2 "$P" "a bad option"
case "$CMD" in
info) run info "$MISSING" ;;
view) run view --headless --stats-json s.json "$MISSING" ;;
export) run export "$MISSING" -o x.vtp ;;
bench) run bench --frames 1 "$MISSING" ;;
build) run build "$MISSING" -o x.tpt ;;
merge) run merge "$MISSING" -o x.tpt ;;
imagery) run imagery "$WORK/missing.tpt" "$MISSING" ;;
coord) run coord '91 0' ;;
point) run point "$MISSING" 42.5 1.5 ;;
los) run los "$MISSING" --from 42.5,1.5 --to 42.6,1.6 ;;
viewshed) run viewshed "$MISSING" --observer 42.5,1.5 -o v.tif ;;
light) run light "$MISSING" --date 2026-06-21 --time 12:00 -o l.tif ;;
profile) run profile "$DATA/storml_elev_orig.tif" --route "$WORK/no_such_dir/route.gpx" ;;
contours) run contours "$MISSING" --interval 20 -o c.gpkg ;;
terrain) run terrain "$MISSING" -o t.tif ;;
*) fail "unknown case" ;;
esac
expect 1 "$P" "a missing file"
exit 0
