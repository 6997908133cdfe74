#!/bin/bash
# tools/slurm_build.sh: a terrain store built across the machines of a Slurm cluster (issue 33,
# item 2; docs/distribution.md, "A build in parts"): a job array of `terrapatch build --part
# I/N`, one task a part, and a `terrapatch merge` job that runs when every part has succeeded
# (sbatch --array, --dependency=afterok), whose store is the one `terrapatch build` writes on
# one machine, byte for byte.
#
#   tools/slurm_build.sh [options] SOURCE... -o MAP.tpt --parts N [-- BUILD_OPTION...]
#
#   -o MAP.tpt          the store (written by the merge job, whole or not at all)
#   --parts N           parts (1 .. 1000, and at most the grid's rows of nodes)
#   --work DIR          where the parts and the jobs' logs go (default MAP.tpt.parts/); every
#                       node must reach it, as it must reach the sources and MAP.tpt's folder
#   --terrapatch BIN    the binary the jobs run (default: terrapatch on PATH, else the
#                       repository's build/terrapatch), the same path on every node
#   --sbatch "ARGS"     more arguments for both sbatch calls (partition, --mem, --time, -c, ...)
#   --wait              wait until the merge job ends; exit with its status
#   -h, --help          this text
#   -- BUILD_OPTION...  given to every part's build (--patch, --memory, --fill-max, ...): every
#                       part must get the same, and the one-machine build too to compare
#
# SOURCEs are GDAL paths every node can read: files on a shared file system (made absolute
# here; the same path, size and time on every node, which the parts' key names) or virtual
# paths (/vsicurl/https://..., /vsis3/...). Give the parts a --height-range LO,HI (or sources
# with statistics): without a bound each part reads the whole grid once for it. A part whose store exists in DIR
# already is not built again: after a failure (a node lost, a job cancelled: a part's store is
# written atomically, so a killed part leaves nothing), the same command builds what is missing
# and merges. The merge refuses parts of other sources or options, missing, repeated or damaged
# ones, in one line each (its log, DIR/merge.log). Each part uses the CPUs Slurm gives its task
# (--threads $SLURM_CPUS_ON_NODE); give sbatch a --mem at least terrapatch's --memory
# (default 1024 MB).
set -euo pipefail

usage() { sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//'; }
die() { echo "slurm_build.sh: $*" >&2; exit 2; }

sources=() build_opts=() out="" parts="" work="" exe="" sbatch_args="" wait=0
while [ $# -gt 0 ]; do
    case "$1" in
    -o | --output) out=${2:?}; shift 2 ;;
    --parts) parts=${2:?}; shift 2 ;;
    --work) work=${2:?}; shift 2 ;;
    --terrapatch) exe=${2:?}; shift 2 ;;
    --sbatch) sbatch_args=${2?}; shift 2 ;;
    --wait) wait=1; shift ;;
    -h | --help) usage; exit 0 ;;
    --) shift; build_opts=("$@"); break ;;
    -*) die "unknown option '$1' (build options go after --)" ;;
    *) sources+=("$1"); shift ;;
    esac
done
[ ${#sources[@]} -gt 0 ] || die "missing SOURCE"
[ -n "$out" ] || die "missing -o MAP.tpt"
[[ "$parts" =~ ^[0-9]+$ ]] && [ "$parts" -ge 1 ] && [ "$parts" -le 1000 ] ||
    die "--parts: expected 1 .. 1000, got '$parts'"
command -v sbatch > /dev/null || die "sbatch not found: is this a Slurm login node?"

here=$(cd "$(dirname "$0")/.." && pwd)
if [ -z "$exe" ]; then
    exe=$(command -v terrapatch || echo "$here/build/terrapatch")
fi
[ -x "$exe" ] || die "$exe: not an executable (give --terrapatch BIN)"
exe=$(realpath "$exe")
abs() { case "$1" in /vsi*) printf '%s' "$1" ;; *) realpath -m "$1" ;; esac; }
for i in "${!sources[@]}"; do sources[$i]=$(abs "${sources[$i]}"); done
out=$(abs "$out")
work=$(abs "${work:-$out.parts}")
mkdir -p "$work"

part_path() { printf '%s/part_%d_of_%d.tpt' "$work" "$1" "$parts"; }
todo=()
for i in $(seq 1 "$parts"); do
    [ -f "$(part_path "$i")" ] || todo+=("$i")
done

# The jobs' scripts, kept in DIR for a look: every argument quoted once here.
q() { local a; for a in "$@"; do printf ' %q' "$a"; done; }
{
    echo '#!/bin/bash'
    printf 'work=%q\n' "$work"
    printf 'exec%s --threads "${SLURM_CPUS_ON_NODE:-1}"%s --part "$SLURM_ARRAY_TASK_ID/%d" \\\n' \
        "$(q "$exe" build "${sources[@]}")" "$(q "${build_opts[@]+"${build_opts[@]}"}")" "$parts"
    printf '    -o "$work/part_${SLURM_ARRAY_TASK_ID}_of_%d.tpt"\n' "$parts"
} > "$work/part.sh"
{
    echo '#!/bin/bash'
    printf 'exec%s' "$(q "$exe" merge)"
    for i in $(seq 1 "$parts"); do printf ' %q' "$(part_path "$i")"; done
    printf ' -o %q --json %q\n' "$out" "$work/merge.json"
} > "$work/merge.sh"
chmod +x "$work/part.sh" "$work/merge.sh"

# shellcheck disable=SC2206 # --sbatch's words are meant to split
extra=($sbatch_args)
dep=()
if [ ${#todo[@]} -gt 0 ]; then
    list=$(IFS=,; echo "${todo[*]}")
    array=$(sbatch --parsable "${extra[@]+"${extra[@]}"}" --job-name=tp-part \
        --array="$list" -o "$work/part_%a_of_$parts.log" "$work/part.sh")
    array=${array%%;*}
    dep=(--dependency="afterok:$array" --kill-on-invalid-dep=yes)
    echo "slurm_build.sh: parts $list of $parts: job array $array"
else
    echo "slurm_build.sh: every part of $parts is built already"
fi
merge=$(sbatch --parsable "${extra[@]+"${extra[@]}"}" --job-name=tp-merge "${dep[@]+"${dep[@]}"}" \
    -o "$work/merge.log" "$work/merge.sh")
merge=${merge%%;*}
echo "slurm_build.sh: merge: job $merge${dep[*]+ after job $array} into $out (log $work/merge.log)"
[ $wait -eq 1 ] || exit 0
# --wait: the merge job's state each second (scontrol keeps it MinJobAge, 300 s by default, after
# the end; sbatch --wait polls far less often)
while :; do
    state=$(scontrol show job "$merge" 2> /dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
    case "$state" in
    COMPLETED) echo "slurm_build.sh: merge job $merge: $state"; exit 0 ;;
    PENDING | RUNNING | CONFIGURING | COMPLETING | SUSPENDED | REQUEUED | RESIZING) sleep 1 ;;
    *) echo "slurm_build.sh: merge job $merge: ${state:-gone}: see $work/*.log" >&2; exit 1 ;;
    esac
done
