#!/bin/bash
# test_info_store.sh EXE DATA_DIR WORK_DIR CASE: `terrapatch info` on a built store (.tpt).
#   sound       a store of storml_elev.tif: exit 0; every node checked, none damaged; text and JSON
#               agree with the build's own --json (nodes, bytes); the build's notes are shown
#   damaged     one byte of one node's data flipped: exit 1, one error line naming the file, the
#               node and its byte offset; the other nodes still checked (the count is printed)
#   truncated   the store cut short: exit 1, one line naming the file, no crash
#   newer       a version number above this reader's (header CRC fixed up): exit 1, "newer"
#   older       format 1 (header CRC fixed up): exit 1, "older" and "rebuild it with terrapatch build"
set -u
EXE=$1 DATA=$2 WORK=$3 CASE=$4
mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAIL ($CASE): $*"; [ -f out ] && { echo '--- stdout'; cat out; }; [ -f err ] && { echo '--- stderr'; cat err; }; exit 1; }
run() { local t=$1; shift; timeout "$t" "$EXE" "$@" > out 2> err; rc=$?; }

rm -f s.tpt build.json
"$EXE" build --quiet --patch 17 --json build.json "$DATA/storml_elev.tif" -o s.tpt 2> build.err ||
    { cat build.err; fail "build failed"; }
nodes=$(sed -n 's/.*"nodes": *\([0-9]*\).*/\1/p' build.json)
bytes=$(stat -c %s s.tpt)
[ -n "$nodes" ] || fail "no node count in the build's JSON: $(cat build.json)"
# u32 little-endian at offset 12: the header's size (docs/store.md); node data starts after the
# location table, whose offset and size are the footer's (the last 56 bytes) u64s at 16 and 24
hsize=$(od -An -tu4 -j12 -N4 s.tpt | tr -d ' ')
loc_offset=$(od -An -tu8 -j$((bytes - 56 + 16)) -N8 s.tpt | tr -d ' ')
loc_bytes=$(od -An -tu8 -j$((bytes - 56 + 24)) -N8 s.tpt | tr -d ' ')
data_offset=$((loc_offset + loc_bytes))
# set_version V: the format version at offset 8, then the header's CRC32 (its last 4 bytes)
set_version() {
    printf "\\00$1" | dd of=s.tpt bs=1 seek=8 conv=notrunc 2> /dev/null
    crc=$(head -c $((hsize - 4)) s.tpt | gzip -c | tail -c 8 | head -c 4 | od -An -tx1 | tr -d ' \n')
    printf "$(echo "$crc" | sed 's/\(..\)/\\x\1/g')" | dd of=s.tpt bs=1 seek=$((hsize - 4)) conv=notrunc 2> /dev/null
}

case "$CASE" in
sound)
    run 60 info s.tpt
    [ $rc -eq 0 ] || fail "exit $rc"
    grep -q "checked: *$nodes nodes, 0 damaged" out || fail "expected all $nodes nodes checked"
    grep -q "note: *source: .*storml_elev.tif" out || fail "the build's notes are not shown"
    grep -q "$bytes bytes" out || fail "file size $bytes not shown"
    run 60 info --json s.tpt
    [ $rc -eq 0 ] || fail "exit $rc (json)"
    grep -q "\"nodes\": *$nodes" out || fail "JSON nodes differ from the build's $nodes"
    grep -q "\"damaged_nodes\": *0" out || fail "JSON damaged_nodes"
    grep -q "\"bytes\": *$bytes" out || fail "JSON bytes"
    ;;
damaged)
    # flip one byte a little into the first node's data
    off=$((data_offset + 5))
    b=$(od -An -tu1 -j$off -N1 s.tpt | tr -d ' ')
    printf "$(printf '\\%03o' $(( (b ^ 0x5A) & 255 )))" | dd of=s.tpt bs=1 seek=$off conv=notrunc 2> /dev/null
    run 60 info s.tpt
    [ $rc -eq 1 ] || fail "exit $rc, expected 1"
    [ "$(wc -l < err)" -eq 1 ] || fail "expected one line on stderr"
    grep -q "s.tpt: node [0-9]* (scale [0-9]*, column [0-9]*, row [0-9]*)" err || fail "node not named"
    grep -q "at byte [0-9]*" err || fail "offset not named"
    grep -q "checked: *$nodes nodes, 1 damaged" out || fail "expected all $nodes nodes checked, 1 damaged"
    ;;
truncated)
    head -c $((bytes / 2)) s.tpt > t.tpt
    run 60 info t.tpt
    [ $rc -eq 1 ] || fail "exit $rc, expected 1"
    [ "$(wc -l < err)" -eq 1 ] || fail "expected one line on stderr"
    grep -q "t.tpt" err || fail "file not named"
    ;;
newer)
    set_version 5
    run 60 info s.tpt
    [ $rc -eq 1 ] || fail "exit $rc, expected 1"
    grep -q "newer terrapatch (format 5" err || fail "expected the newer-version message"
    ;;
older)
    set_version 3
    run 60 info s.tpt
    [ $rc -eq 1 ] || fail "exit $rc, expected 1"
    [ "$(wc -l < err)" -eq 1 ] || fail "expected one line on stderr"
    grep -q "s.tpt: written by an older terrapatch (format 3.*rebuild it with terrapatch build" err ||
        fail "expected the older-version message"
    ;;
*) fail "unknown case" ;;
esac
exit 0
