#!/bin/sh
# run_fuzzer.sh MODE FUZZER SOURCE_DIR WORK_DIR SECONDS [libFuzzer options...]
#   MODE replay: run every input of SOURCE_DIR/corpus/NAME and SOURCE_DIR/regressions/NAME once;
#   MODE run:    fuzz for SECONDS from them (and from what earlier runs kept in
#                WORK_DIR/corpus/NAME, where new inputs go); a crash is saved in
#                WORK_DIR/artifacts/ and fails the test.
# NAME is the fuzzer's file name. Memory is bounded: a reader that asks for more than 2 GiB
# fails the run (libFuzzer's -rss_limit_mb and -malloc_limit_mb).
#
# TP_FUZZ_THIRD_PARTY (a grep -E pattern, e.g. 'libvtk'): in MODE run, fuzz in fork mode, going
# on after crashes, and fail only for a crash whose top frame (outside libc and libstdc++) does
# not match it: for a library whose own crashes turn up in minutes (docs/fuzzing.md), so that
# ours still fail.
set -eu
mode=$1 fuzzer=$2 src=$3 work=$4 seconds=$5
shift 5
name=$(basename "$fuzzer")
mkdir -p "$work/corpus/$name" "$work/artifacts"
dirs=
for d in "$src/corpus/$name" "$src/regressions/$name"; do
    [ -d "$d" ] && dirs="$dirs $d"
done
common="-rss_limit_mb=2048 -malloc_limit_mb=2048 -timeout=20 -artifact_prefix=$work/artifacts/$name-"
export ASAN_OPTIONS="${ASAN_OPTIONS:-allocator_may_return_null=1:detect_leaks=1}"
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$src/lsan.supp}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
case "$mode" in
    # -runs=0: read (so run) every input, then stop
    replay) exec "$fuzzer" $common "$@" -runs=0 $dirs ;;
    run) ;;
    *) echo "run_fuzzer.sh: MODE must be replay or run, not '$mode'" >&2; exit 2 ;;
esac
if [ -z "${TP_FUZZ_THIRD_PARTY:-}" ]; then
    exec "$fuzzer" $common "$@" -max_total_time="$seconds" -print_final_stats=1 \
        "$work/corpus/$name" $dirs
fi
stamp="$work/artifacts/.$name-start"
touch "$stamp"
"$fuzzer" $common "$@" -fork=1 -ignore_crashes=1 -ignore_ooms=1 -ignore_timeouts=1 \
    -max_total_time="$seconds" "$work/corpus/$name" $dirs || true
status=0
for a in $(find "$work/artifacts" -newer "$stamp" -type f -name "$name-timeout-*"); do
    echo "slow input (a timeout on a loaded machine is no failure): $a"
done
for a in $(find "$work/artifacts" -newer "$stamp" -type f \( -name "$name-crash-*" -o \
    -name "$name-leak-*" -o -name "$name-oom-*" \)); do
    # the first frame outside the C and C++ runtimes ("#0 in std::string::_M_assign" is VTK's)
    top=$("$fuzzer" "$a" 2>&1 | grep -E '^ *#[0-9]+ ' | grep -vE 'libstdc\+\+|libc\.so|libm\.so' |
        head -n 1 || true)
    if printf '%s\n' "$top" | grep -qE "$TP_FUZZ_THIRD_PARTY"; then
        echo "known third-party failure (not ours): $a: $top"
    else
        echo "FAILURE: $a: ${top:-no stack}"
        status=1
    fi
done
exit $status
