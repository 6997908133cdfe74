#!/usr/bin/env bash
# tools/first_picture.sh - the first picture of DEMs not in the cache (issue 32, item 4),
# measured for two terrapatch binaries in one run, alternated (docs/PERFORMANCE.md, "First
# picture of a new DEM").
#
#   tools/first_picture.sh OLD NEW REPS DEM...
#
# For each repetition, DEM and binary (OLD then NEW): a fresh cache folder, then
#   BIN view --headless --screenshot x.png --stats-json j.json DEM
# under /usr/bin/time. One line each, tab-separated: dem (its folder/name), binary (old/new),
# repetition, wall s, user s, sys s, peak RSS MB, first_frame ms and what it was drawn from
# (from the JSON: a binary that does not say has "-"), store_ms (when the store landed, after
# a preview) and the load average. Then the medians per DEM and binary. Needs python3 for the
# JSON and the medians.
set -u
[ $# -ge 4 ] || { echo "usage: tools/first_picture.sh OLD NEW REPS DEM..."; exit 2; }
old=$1 new=$2 reps=$3
shift 3
work=$(mktemp -d "${TMPDIR:-/tmp}/first_picture.XXXXXX")
trap 'rm -rf "$work"' EXIT
rows="$work/rows.tsv"
: >"$rows"
for rep in $(seq "$reps"); do
    for dem in "$@"; do
        for which in old new; do
            bin=$old
            [ "$which" = new ] && bin=$new
            rm -rf "$work/cache" "$work/j.json"
            TP_CACHE_DIR="$work/cache" /usr/bin/time -o "$work/time" -f "%e %U %S %M" \
                "$bin" view --headless --screenshot "$work/x.png" --stats-json "$work/j.json" \
                "$dem" >/dev/null 2>"$work/err" || { echo "$bin $dem: exit $?"; cat "$work/err"; }
            read -r wall user sys rss <"$work/time"
            first=$(python3 -c '
import json, sys
f = json.load(open(sys.argv[1])).get("first_frame")
print("\t".join(["-", "-", "-"]) if not f else "%.0f\t%s%s\t%s" % (f["ms"], f["from"],
      "/%d" % f["preview_coarsen"] if "preview_coarsen" in f else "",
      "%.0f" % f["store_ms"] if "store_ms" in f else "-"))' "$work/j.json" 2>/dev/null ||
                    printf -- '-\t-\t-')
            load=$(cut -d' ' -f1 /proc/loadavg)
            printf '%s\t%s\t%s\t%s\t%s\t%s\t%.0f\t%s\t%s\n' \
                "$(basename "$(dirname "$dem")")/$(basename "$dem")" "$which" "$rep" \
                "$wall" "$user" "$sys" "$((rss / 1024))" "$first" "$load" | tee -a "$rows"
        done
    done
done
python3 - "$rows" <<'EOF'
import statistics, sys
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1]) if l.strip()]
print("\nmedians: dem, binary, runs, wall s, user+sys s, peak RSS MB, first frame ms (from), "
      "store ms")
seen = []
for r in rows:
    if (r[0], r[1]) not in seen:
        seen.append((r[0], r[1]))
med = lambda xs: statistics.median(xs) if xs else float("nan")
for dem, which in seen:
    rs = [r for r in rows if r[0] == dem and r[1] == which]
    num = lambda i: [float(r[i]) for r in rs if r[i] not in ("-", "")]
    cpu = [float(r[4]) + float(r[5]) for r in rs]
    first = num(7)
    store = num(9)
    print("%s\t%s\t%d\t%.2f\t%.2f\t%.0f\t%s (%s)\t%s" % (
        dem, which, len(rs), med(num(3)), med(cpu), med(num(6)),
        "%.0f" % med(first) if first else "-", rs[0][8], "%.0f" % med(store) if store else "-"))
EOF
