#!/bin/bash
# test_slurm_build.sh EXE SLURM_BUILD DATA_DIR WORK_DIR: tools/slurm_build.sh on a one-node Slurm
# cluster this test starts on localhost (issue 33 item 2): munged, slurmctld and slurmd (Debian's
# munge and slurm-wlm, tools/deps.sh), configured in a folder of their own under WORK_DIR, on
# free ports, as the user running the test; all stopped by a trap, whatever happens (every
# process started with this cluster's mark in its environment is ended, the job steps
# included: no daemon left behind).
#   1. the shared tiles N41E001 + N42E001 built as 4 parts by a job array and merged by a job
#      that depends on it: the store equals the one-machine build byte for byte;
#   2. part 3 of a second run cancelled (scancel) while it builds: it leaves no store and no
#      temporary file, the merge job never runs (no MAP), and the same command run again builds
#      part 3 alone and merges: the store equals the one-machine build.
# Fails (never skips) when Slurm or munge is missing.
set -u
EXE=$1 SCRIPT=$2 DATA=$3 WORK=$4
fail() { echo "FAIL: $*"; for f in "$T"/*.log "$OUT"/*/*.log; do [ -f "$f" ] && { echo "--- $f"; tail -20 "$f"; }; done; exit 1; }
for tool in munged slurmctld slurmd sbatch squeue scancel sinfo; do
    command -v $tool > /dev/null || { echo "FAIL: $tool not found: install slurm-wlm and munge (make deps)"; exit 1; }
done
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
T=$(mktemp -d "$WORK/cluster.XXXX") && chmod 700 "$T"
OUT=$WORK/out
mkdir -p "$OUT"
export SLURM_CONF=$T/slurm.conf

# The daemons are started with a mark in their environment, which slurmstepd inherits: every
# process of this cluster is found by it, and ended by its id.
MARK=TP_SLURM_TEST_CLUSTER=$T
ours() {
    local p
    for p in /proc/[0-9]*; do
        { tr '\0' '\n' < "$p/environ"; } 2> /dev/null | grep -qx "$MARK" && echo "${p#/proc/}"
    done
}
stop_cluster() {
    scancel --full $(squeue -h -o %i 2> /dev/null) 2> /dev/null
    local pids pid i
    for i in $(seq 1 50); do
        pids=$(ours)
        [ -z "$pids" ] && break
        for pid in $pids; do kill -TERM "$pid" 2> /dev/null; done
        sleep 0.2
    done
    for pid in $(ours); do kill -KILL "$pid" 2> /dev/null; done
    [ -z "$(ours)" ] || echo "FAIL: processes left: $(ours)"
}
trap stop_cluster EXIT

free_port() {
    local p
    for _ in $(seq 1 50); do
        p=$((20000 + RANDOM % 20000))
        (exec 3<> /dev/tcp/127.0.0.1/$p) 2> /dev/null || { echo $p; return; }
    done
}
user=$(id -un) host=$(hostname -s)
dd if=/dev/urandom of="$T/munge.key" bs=1024 count=1 2> /dev/null && chmod 400 "$T/munge.key"
env "$MARK" munged --force --socket="$T/munge.sock" --key-file="$T/munge.key" \
    --pid-file="$T/munged.pid" --log-file="$T/munged.log" --seed-file="$T/munge.seed" ||
    fail "munged did not start"
cat > "$T/slurm.conf" << EOF
ClusterName=tptest
SlurmctldHost=$host(127.0.0.1)
SlurmUser=$user
SlurmdUser=$user
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
AuthType=auth/munge
AuthInfo=socket=$T/munge.sock
CredType=cred/munge
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/slurmctld.log
SlurmdLogFile=$T/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
KillWait=5
NodeName=$host NodeAddr=127.0.0.1 CPUs=2 RealMemory=2000 State=UNKNOWN
PartitionName=tp Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
mkdir -p "$T/state" "$T/spool"
env "$MARK" slurmctld -f "$T/slurm.conf" || fail "slurmctld did not start"
env "$MARK" slurmd -f "$T/slurm.conf" -N "$host" || fail "slurmd did not start"
for i in $(seq 1 100); do
    [ "$(sinfo -h -o %T 2> /dev/null)" = idle ] && break
    sleep 0.2
done
[ "$(sinfo -h -o %T)" = idle ] || fail "the node is not idle: $(sinfo 2>&1)"
echo "cluster up: $(sinfo -h -o '%P %D %T %N')"

SRC=("$DATA/N41E001.hgt" "$DATA/N42E001.hgt")
OPTS=(--patch 65 --memory 400)
"$EXE" build --quiet "${OPTS[@]}" "${SRC[@]}" -o "$OUT/whole.tpt" || fail "the one-machine build failed"

# 1. four parts and their merge
t0=$(date +%s.%N)
timeout 300 "$SCRIPT" "${SRC[@]}" -o "$OUT/a/map.tpt" --parts 4 --terrapatch "$EXE" --wait \
    --sbatch "--mem=400" -- "${OPTS[@]}" > submit_a.txt 2>&1 ||
    { cat submit_a.txt; fail "slurm_build.sh --wait failed (merge job)"; }
cat submit_a.txt
grep -q "job array" submit_a.txt || fail "no job array submitted"
cmp "$OUT/a/map.tpt" "$OUT/whole.tpt" || fail "the store built by Slurm differs from the one-machine build"
for i in 1 2 3 4; do
    grep -q "part $i/4" "$OUT/a/map.tpt.parts/part_${i}_of_4.log" || fail "part $i's log does not name it"
done
echo "PASS step 1: 4 parts by a job array and a merge after it, identical ($(echo "$(date +%s.%N) - $t0" | bc) s)"

# 2. part 3 cancelled while it writes its store (one thread and --memory 64, so that the
# grid is read again rather than held and the writing takes a second or more), then rerun; when
# the cancel lands after the part has finished (a loaded machine), the run is tried again
OPTS_B=(--patch 65 --memory 64 --threads 1)
"$EXE" build --quiet "${OPTS_B[@]}" "${SRC[@]}" -o "$OUT/whole_b.tpt" 2> /dev/null ||
    fail "the one-machine build with ${OPTS_B[*]} failed"
caught=0
for attempt in 1 2 3; do
    rm -rf "$OUT/b"
    "$SCRIPT" "${SRC[@]}" -o "$OUT/b/map.tpt" --parts 4 --terrapatch "$EXE" -- "${OPTS_B[@]}" \
        > submit_b.txt 2>&1 || { cat submit_b.txt; fail "slurm_build.sh failed"; }
    array=$(sed -n 's/.*job array \([0-9]*\).*/\1/p' submit_b.txt)
    merge=$(sed -n 's/.*merge: job \([0-9]*\).*/\1/p' submit_b.txt)
    [ -n "$array" ] && [ -n "$merge" ] || fail "job ids not printed: $(cat submit_b.txt)"
    log=$OUT/b/map.tpt.parts/part_3_of_4.log
    tmp=("$OUT/b/map.tpt.parts/part_3_of_4.tpt.tmp"*)
    for i in $(seq 1 3000); do # until part 3 writes its store (its temporary file)
        tmp=("$OUT/b/map.tpt.parts/part_3_of_4.tpt.tmp"*)
        [ -e "${tmp[0]}" ] && break
        sleep 0.02
    done
    [ -e "${tmp[0]}" ] || fail "part 3 never started writing: $(cat "$log")"
    scancel "${array}_3"
    for i in $(seq 1 150); do # the array done, the merge job gone (its dependency never met)
        [ -z "$(squeue -h -j "$array,$merge" 2> /dev/null)" ] && break
        sleep 0.2
    done
    [ -z "$(squeue -h -j "$array,$merge" 2> /dev/null)" ] || fail "jobs still queued: $(squeue)"
    if [ ! -e "$OUT/b/map.tpt.parts/part_3_of_4.tpt" ] && ! grep -q "build 100%" "$log"; then
        caught=1
        break
    fi
    echo "attempt $attempt: part 3 finished before the cancel landed; again"
done
[ $caught -eq 1 ] || fail "part 3 could not be cancelled while building in 3 attempts"
grep -q "CANCELLED\|interrupted\|Terminated" "$log" || fail "part 3's log does not say it was stopped: $(tail -3 "$log")"
ls -la "$OUT/b/map.tpt.parts" > listing.txt
if ls -a "$OUT/b/map.tpt.parts" | grep -v '\.log$\|\.sh$\|^\.\.\?$\|^part_[124]_of_4\.tpt$' | grep -q .; then
    fail "the cancelled part left a file: $(cat listing.txt)"
fi
[ ! -e "$OUT/b/map.tpt" ] || fail "a store was merged without part 3"
for i in 1 2 4; do
    [ -f "$OUT/b/map.tpt.parts/part_${i}_of_4.tpt" ] || fail "part $i missing: $(cat listing.txt)"
done
timeout 300 "$SCRIPT" "${SRC[@]}" -o "$OUT/b/map.tpt" --parts 4 --terrapatch "$EXE" --wait -- \
    "${OPTS_B[@]}" > submit_c.txt 2>&1 || { cat submit_c.txt; fail "the rerun failed"; }
cat submit_c.txt
grep -q "parts 3 of 4" submit_c.txt || fail "the rerun should build part 3 alone"
cmp "$OUT/b/map.tpt" "$OUT/whole_b.tpt" || fail "the store after the rerun differs from the one-machine build"
echo "PASS step 2: part 3 cancelled left nothing; the rerun built it alone and merged, identical"
stop_cluster
trap - EXIT
[ -z "$(ours)" ] || fail "processes left after the stop"
echo "ALL PASSED"
