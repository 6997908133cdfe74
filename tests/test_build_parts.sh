#!/bin/bash
# test_build_parts.sh EXE DATA_DIR WORK_DIR CASE: a build in parts (`build --part I/N`, `merge`;
# issue 33 item 2) against the one-machine build, and merge's refusals.
#   identical  stores of real tiles built as N parts and merged equal the one-machine build
#              byte for byte (cmp: header, node table, location table, every node's bytes,
#              footer): two SRTM tiles warped to UTM with voids filled in 4 parts (nodes of 65),
#              Mt Hood in 7 parts (nodes of 17), Crater Lake in 2 (33), N42E001 in 1, and
#              N42E001 in 3 without void filling, the two tiles in 4 with --height-range (no
#              part makes a range pass then); a part is a store `info` reads whole
#   refused    merge refuses, in one line naming the part and with exit 1, writing nothing: a
#              part missing, one given twice, parts of other sources, of other options, of
#              another split, a damaged part (one byte of a node flipped), a whole store;
#              build refuses a bad --part (exit 2) and more parts than rows of nodes (exit 1),
#              a --height-range the heights leave (exit 1) and a bad one (exit 2)
#   killed     a part stopped by SIGTERM while it writes leaves no store and no temporary file
#              (exit 143); built again, the merge equals the one-machine build
set -u
EXE=$1 DATA=$2 WORK=$3 CASE=$4
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
fail() { echo "FAIL ($CASE): $*"; [ -f err ] && { echo '--- stderr'; cat err; }; exit 1; }
run() { "$EXE" "$@" > out 2> err; rc=$?; }

# parts NAME N OPTIONS... -- SOURCES...: NAME_1.tpt .. NAME_N.tpt
parts() {
    local name=$1 n=$2 i
    shift 2
    for i in $(seq 1 "$n"); do
        "$EXE" build --quiet --part "$i/$n" -o "${name}_$i.tpt" "$@" 2> err ||
            fail "$name: part $i/$n failed"
    done
}
# same NAME N OPTIONS... -- SOURCES...: the parts merged equal the one-machine build
same() {
    local name=$1 n=$2
    shift 2
    "$EXE" build --quiet -o "${name}_whole.tpt" "$@" 2> err || fail "$name: the whole build failed"
    parts "$name" "$n" "$@"
    run merge --quiet $(for i in $(seq 1 "$n"); do echo "${name}_$i.tpt"; done) -o "${name}.tpt"
    [ $rc -eq 0 ] || fail "$name: merge exit $rc"
    cmp "${name}.tpt" "${name}_whole.tpt" || fail "$name: the merged store differs from the one-machine build"
    echo "PASS $name: $n parts merged = the one-machine build ($(stat -c %s "$name.tpt") bytes)"
}
# refused WHAT PATTERN MERGE_ARGS...: exit 1, one line matching PATTERN, no output, no temp file
refused() {
    local what=$1 pattern=$2
    shift 2
    rm -f m.tpt
    run merge --quiet "$@" -o m.tpt
    [ $rc -eq 1 ] || fail "$what: exit $rc, expected 1"
    [ "$(wc -l < err)" -eq 1 ] || fail "$what: expected one line on stderr"
    grep -q "^terrapatch merge: .*$pattern" err || fail "$what: expected '$pattern'"
    ! ls m.tpt* > /dev/null 2>&1 || fail "$what: wrote something: $(ls m.tpt*)"
    echo "PASS refused $what: $(cat err)"
}

T2=("$DATA/N41E001.hgt" "$DATA/N42E001.hgt")
case "$CASE" in
identical)
    same tiles 4 --patch 65 "${T2[@]}"
    same hood 7 --patch 17 "$DATA/lf_elev_220_mt_hood_utm.tif"
    same crater 2 --patch 33 "$DATA/craterlake-elev-16bit-30m.tif"
    same one 1 "$DATA/N42E001.hgt"
    same nofill 3 --fill-max 0 "$DATA/N42E001.hgt"
    # --height-range: every part given the bound reads no more than its rows (no range pass)
    same range 4 --height-range -100,3500 "${T2[@]}"
    "$EXE" build --part 2/4 -o r2.tpt "${T2[@]}" 2> err || fail "part 2/4 failed"
    grep -q "^terrapatch build: range " err || fail "without --height-range a part makes a range pass"
    "$EXE" build --height-range -100,3500 --part 2/4 -o r2.tpt "${T2[@]}" 2> err || fail "part 2/4 failed"
    ! grep -q "^terrapatch build: range " err || fail "with --height-range a part made a range pass"
    echo "PASS --height-range: no range pass in a part"
    run info tiles_2.tpt
    [ $rc -eq 0 ] || fail "info of a part: exit $rc"
    grep -q "note: *part 2/4 of a " out || fail "info does not show the part's record"
    grep -q "checked: .*0 damaged" out || fail "info did not check the part's nodes"
    ;;
refused)
    parts p 4 "${T2[@]}"
    refused missing "missing part 3/4 (of 4 parts, 3 given)" p_1.tpt p_2.tpt p_4.tpt
    cp p_2.tpt again.tpt
    refused twice "p_2.tpt and again.tpt are both part 2/4" p_1.tpt p_2.tpt again.tpt p_3.tpt p_4.tpt
    "$EXE" build --quiet --part 3/4 -o other.tpt "$DATA/N42E001.hgt" "$DATA/N41E001.hgt" 2> err ||
        fail "part of other sources failed"
    refused "other sources" "other.tpt: built from other sources or options than p_1.tpt" \
        p_1.tpt p_2.tpt other.tpt p_4.tpt
    "$EXE" build --quiet --part 3/4 --fill-max 10 -o opt.tpt "${T2[@]}" 2> err ||
        fail "part of other options failed"
    refused "other options" "opt.tpt: built from other sources or options than p_1.tpt" \
        p_1.tpt p_2.tpt opt.tpt p_4.tpt
    "$EXE" build --quiet --part 3/5 -o split.tpt "${T2[@]}" 2> err || fail "part 3/5 failed"
    refused "another split" "split.tpt is part 3/5, but p_1.tpt is part 1/4" \
        p_1.tpt p_2.tpt split.tpt p_4.tpt
    # one byte flipped in the data of the part's first node (a leaf): the data starts after the
    # location table, whose offset and size are the footer's (the last 56 bytes) u64s at 16, 24
    cp p_3.tpt bad.tpt
    size=$(stat -c %s bad.tpt)
    loc_offset=$(od -An -tu8 -j$((size - 56 + 16)) -N8 bad.tpt | tr -d ' ')
    loc_bytes=$(od -An -tu8 -j$((size - 56 + 24)) -N8 bad.tpt | tr -d ' ')
    off=$((loc_offset + loc_bytes + 5))
    b=$(od -An -tu1 -j$off -N1 bad.tpt | tr -d ' ')
    printf "$(printf '\\%03o' $(((b ^ 0x5A) & 255)))" | dd of=bad.tpt bs=1 seek=$off conv=notrunc 2> /dev/null
    refused damaged "bad.tpt: node [0-9]* (scale .*damaged data: checksum mismatch" \
        p_1.tpt p_2.tpt bad.tpt p_4.tpt
    "$EXE" build --quiet -o whole.tpt "${T2[@]}" 2> err || fail "whole build failed"
    refused "a whole store" "whole.tpt: not a part of a build in parts" p_1.tpt whole.tpt
    for bad in 0/4 5/4 2 a/b 1/0; do
        run build --part "$bad" -o x.tpt "$DATA/N42E001.hgt"
        [ $rc -eq 2 ] || fail "--part $bad: exit $rc, expected 2"
        grep -q "^terrapatch build: .*--part" err || fail "--part $bad: the message does not name --part"
    done
    run build --part 2/40 -o x.tpt "$DATA/N42E001.hgt"
    [ $rc -eq 1 ] && grep -q "the grid has 26 rows of nodes (of 65 samples): at most 26 parts" err ||
        fail "--part 2/40 of a grid of 26 rows: exit $rc"
    [ ! -e x.tpt ] || fail "x.tpt written"
    echo "PASS build refuses bad --part values and too many parts"
    run build --quiet --height-range 0,1000 -o x.tpt "$DATA/N42E001.hgt"
    [ $rc -eq 1 ] && [ "$(grep -c . err)" -eq 1 ] &&
        grep -q "N42E001.hgt: heights .* outside --height-range 0,1000" err ||
        fail "--height-range 0,1000 on N42E001 (up to 3088 m): exit $rc"
    [ ! -e x.tpt ] || fail "x.tpt written"
    for bad in 5,1 a,b 1 0,1e9; do
        run build --height-range "$bad" -o x.tpt "$DATA/N42E001.hgt"
        [ $rc -eq 2 ] || fail "--height-range $bad: exit $rc, expected 2"
    done
    echo "PASS build refuses a --height-range the heights leave, and bad ranges"
    ;;
killed)
    "$EXE" build --quiet --memory 64 --threads 1 -o whole.tpt "${T2[@]}" 2> err || fail "whole build failed"
    parts k 4 --memory 64 --threads 1 "${T2[@]}"
    rm -f k_2.tpt
    caught=0
    for attempt in 1 2 3; do
        "$EXE" build --memory 64 --threads 1 --part 2/4 -o k_2.tpt "${T2[@]}" 2> err &
        pid=$!
        for i in $(seq 1 1000); do # until it writes its store
            ls k_2.tpt.tmp* > /dev/null 2>&1 && break
            sleep 0.01
        done
        kill -TERM $pid
        wait $pid
        rc=$?
        [ $rc -eq 143 ] && { caught=1; break; }
        [ $rc -eq 0 ] || fail "part 2 stopped by SIGTERM: exit $rc"
        rm -f k_2.tpt # finished before the signal: again
    done
    [ $caught -eq 1 ] || fail "part 2 was not caught while writing in 3 attempts"
    grep -q "interrupted" err || fail "no 'interrupted' line"
    ! ls k_2.tpt* > /dev/null 2>&1 || fail "the stopped part left: $(ls k_2.tpt*)"
    refused "the stopped part" "missing part 2/4" k_1.tpt k_3.tpt k_4.tpt
    "$EXE" build --quiet --memory 64 --threads 1 --part 2/4 -o k_2.tpt "${T2[@]}" 2> err ||
        fail "part 2 built again failed"
    run merge --quiet k_1.tpt k_2.tpt k_3.tpt k_4.tpt -o k.tpt
    [ $rc -eq 0 ] || fail "merge exit $rc"
    cmp k.tpt whole.tpt || fail "the merge after the rerun differs from the one-machine build"
    echo "PASS killed: nothing left; rebuilt and merged = the one-machine build"
    ;;
*) fail "unknown case" ;;
esac
echo ALL PASSED
