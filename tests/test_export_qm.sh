#!/bin/bash
# test_export_qm.sh TERRAPATCH DATA_DIR WORK_DIR CASE: issue 34, `export --tiles quantized-mesh`.
# Every tile set written here is decoded and checked by tests/qm_check.py (a decoder of its own
# from the quantized-mesh specification: byte layout, header, edges, normals, watertight
# neighbours; see its docstring). Cases:
#   geoid      Crater Lake (geographic, no data outside its footprint) and Mt Hood (NAD83 UTM,
#              voids outside the LANDFIRE footprint), --heights geoid: qm_check with 20 random
#              points each, the tile's height against `terrapatch point` within the tile's
#              measured error; every tile's measured error in errors.json at least what the
#              points found, and (qm_check) every tile's within its level's geometric error.
#   bound      Crater Lake with --max-error 1 (the deepest level 1 m, 4096 m at level 0): every
#              tile of every level measured within its level's geometric error (qm_check; the
#              TIN alone, on the lattice, left 16 m at level 12 and 1,567 m at level 8: posts
#              between lattice posts), neighbours still watertight, more triangles than at the
#              default bound, and tiles.log's bounds the levels'.
#   ellipsoid  Crater Lake with --heights ellipsoid against the geoid set: at 30 vertices of the
#              deepest level the difference of the two tiles' heights is EGM96's undulation as
#              gdaltransform (PROJ's command-line path, not ours) gives it, within both tiles'
#              measured errors; layer.json states the model.
#   resume     N42E001 to level 10, killed (SIGKILL) after some tiles: no temporary file, every
#              tile on disk whole; the rerun says how many it keeps and ends with the same
#              files, byte for byte, as an export never interrupted; a rerun with other options
#              is refused (exit 1, one line) and changes nothing; --bounds gives only the tiles
#              over the box.
#   threads    Crater Lake with --max-error 1 (refinement active): --threads 1 and --threads 3
#              give the same directory byte for byte (diff -r: tiles, layer.json, errors.json,
#              export.txt, tiles.log), at the default deepest level (25 tiles) and at
#              --max-zoom 14 (143 tiles: more than the 12 results 3 threads hold at once); an
#              export on 3 threads killed (SIGKILL) mid-way and resumed on 2 gives the same
#              directory as the unkilled one on 1 thread, and so does one stopped by SIGTERM
#              (exit 143, no layer.json); the level lines name the threads; --heights
#              ellipsoid (a geoid a thread) at --max-zoom 13 the same bytes on 1 and 3 threads.
# Needs python3 and gdal-bin (gdaltransform).
set -u
TP=$1 DATA=$2 WORK=$3 CASE=$4
HERE=$(cd "$(dirname "$0")" && pwd)
rm -rf "$WORK" && mkdir -p "$WORK" && cd "$WORK" || exit 1
export TP_CACHE_DIR=$WORK/cache
fail() { echo "FAIL: $*"; for f in out err; do [ -s $f ] && { echo "--- $f"; tail -20 $f; }; done; exit 1; }
check() { python3 "$HERE/qm_check.py" "$@" > out 2> err || fail "qm_check $*: $(tail -1 out)"; tail -1 out; }

store() { # DEM NAME: a store of the DEM
    "$TP" build --quiet "$DATA/$1" -o "$2.tpt" > out 2> err || fail "build $1"
}

case $CASE in
geoid)
    store craterlake-elev-16bit-30m.tif cl
    store lf_elev_220_mt_hood_utm.tif hood
    for s in cl hood; do
        "$TP" export $s.tpt --tiles quantized-mesh --heights geoid -o $s > out 2> err ||
            fail "export $s"
        grep -q "neighbour pairs share their edge vertices" out || fail "no summary line"
        check $s --points "$TP" $s.tpt 20
        python3 - $s > out 2>&1 << 'EOF' || fail "$s: layer.json levels"
import json, sys
d = sys.argv[1]
layer = json.load(open(d + "/layer.json"))
top = layer["terrapatch"]["levels"][-1]
assert layer["terrapatch"]["heights"] == "geoid", layer["terrapatch"]["heights"]
assert 0 < top["max_measured_error_m"] <= top["geometric_error_m"], top
errs = json.load(open(d + "/errors.json"))
assert len(errs) == sum(l["tiles"] for l in layer["terrapatch"]["levels"])
EOF
    done
    ;;
ellipsoid)
    store craterlake-elev-16bit-30m.tif cl
    "$TP" export cl.tpt --tiles quantized-mesh --heights geoid -o g > out 2> err || fail "export geoid"
    "$TP" export cl.tpt --tiles quantized-mesh --heights ellipsoid -o e > out 2> err ||
        fail "export ellipsoid"
    check e
    python3 - "$HERE" > out 2>&1 << 'EOF' || fail "ellipsoid - geoid heights"
import gzip, json, random, subprocess, sys
sys.path.insert(0, sys.argv[1])
import qm_check as q
le = json.load(open("e/layer.json"))["terrapatch"]
assert le["heights"] == "ellipsoid" and "EGM96" in le["geoid_model"], le
ee, eg = json.load(open("e/errors.json")), json.load(open("g/errors.json"))
z = le["max_zoom"]
keys = [k for k in ee if k.startswith("%d/" % z) and ee[k] > 0 and eg[k] > 0]
step = le["height_step_m"]
rng = random.Random(7)
pts = []
while len(pts) < 30:
    k = rng.choice(keys)
    _, x, y = map(int, k.split("/"))
    te = q.decode(gzip.decompress(open("e/%s.terrain" % k, "rb").read()), k)
    tg = q.decode(gzip.decompress(open("g/%s.terrain" % k, "rb").read()), k)
    # a vertex over the store (Crater Lake lies 1289..1880 m up; away from it tiles hold 0)
    hs = q.heights(tg)
    over = [i for i in range(len(hs)) if hs[i] > 1000]
    if not over:
        continue
    i = rng.choice(over)
    w, s, e, n = q.bounds(z, x, y)
    lat = s + (n - s) * tg["v"][i] / q.MAXC
    lon = w + (e - w) * tg["u"][i] / q.MAXC
    pts.append((k, lat, lon, q.height_at(te, z, x, y, lat, lon) - q.height_at(tg, z, x, y, lat, lon)))
inp = "".join("%.10f %.10f 0\n" % (lon, lat) for _, lat, lon, _ in pts)
out = subprocess.run(["gdaltransform", "-s_srs", "EPSG:4326+5773", "-t_srs", "EPSG:4979"],
                     input=inp, capture_output=True, text=True, check=True).stdout.split("\n")
for (k, lat, lon, diff), line in zip(pts, out):
    und = float(line.split()[2])
    tol = ee[k] + eg[k] + step  # each tile's vertex on its own step
    assert abs(diff - und) <= tol, (k, lat, lon, diff, und, tol)
    assert -30 < und < -15, und  # EGM96 at Crater Lake, 43N 122W: about -22 m
print("ok", len(pts))
EOF
    ;;
bound)
    store craterlake-elev-16bit-30m.tif cl
    "$TP" export cl.tpt --tiles quantized-mesh --heights geoid --max-error 1 -o b > out 2> err ||
        fail "export --max-error 1"
    grep -q "level 12: bound 1.000 m" out || fail "summary: $(cat out)"
    check b
    "$TP" export cl.tpt --tiles quantized-mesh --heights geoid -o d > out 2> err || fail "export"
    check d
    python3 - > out 2>&1 << 'EOF' || fail "levels of --max-error 1"
import json
b = json.load(open("b/layer.json"))["terrapatch"]["levels"]
d = json.load(open("d/layer.json"))["terrapatch"]["levels"]
assert [l["geometric_error_m"] for l in b] == [2.0 ** (12 - z) for z in range(13)], b
assert sum(l["triangles"] for l in b) > 10 * sum(l["triangles"] for l in d), (b, d)
for line in open("b/tiles.log"):
    z, bound = int(line.split()[0]), float(line.split()[4])
    assert bound == b[z]["geometric_error_m"], line
    assert float(line.split()[3]) <= bound, line
EOF
    ;;
resume)
    store N42E001.hgt n42
    "$TP" export n42.tpt --tiles quantized-mesh --heights geoid --max-zoom 10 -o whole > out 2> err ||
        fail "export whole"
    "$TP" export n42.tpt --tiles quantized-mesh --heights geoid --max-zoom 10 -o part > out 2> err &
    pid=$!
    for _ in $(seq 1 600); do
        [ -f part/tiles.log ] && [ "$(wc -l < part/tiles.log)" -ge 30 ] && break
        sleep 0.05
    done
    kill -9 $pid 2> /dev/null
    wait $pid 2> /dev/null
    n=$(wc -l < part/tiles.log)
    total=$(python3 -c "import json; print(len(json.load(open('whole/errors.json'))))")
    [ "$n" -ge 30 ] && [ "$n" -lt "$total" ] || fail "killed after $n of $total tiles: not mid-way"
    [ -f part/layer.json ] && fail "layer.json written by a killed export"
    find part -name '*.tmp*' -o -name '.*' -type f | grep -q . && fail "temporary files left"
    for f in $(find part -name '*.terrain'); do gzip -t "$f" 2> /dev/null || fail "$f cut short"; done
    # what a kill during a tile's write leaves (tp_file_write's temporary name): removed
    stale=$(find part -name '*.terrain' | head -1).tmpAbCd1234
    echo partial > "$stale"
    "$TP" export n42.tpt --tiles quantized-mesh --heights geoid --max-zoom 10 -o part > out 2> err ||
        fail "the rerun"
    [ -e "$stale" ] && fail "the rerun left $stale"
    grep -q "1 temporary files of a killed run removed" err || fail "no line for the removed file"
    grep -q "tiles already written by an earlier run: kept" err || fail "the rerun kept nothing"
    for f in layer.json errors.json; do cmp -s whole/$f part/$f || fail "$f differs after resuming"; done
    (cd whole && find . -name '*.terrain' | sort) > a
    (cd part && find . -name '*.terrain' | sort) > b
    cmp -s a b || fail "other tiles after resuming"
    while read -r f; do cmp -s "whole/$f" "part/$f" || fail "$f differs after resuming"; done < a
    check part
    cp part/errors.json before.json
    "$TP" export n42.tpt --tiles quantized-mesh --heights geoid --max-zoom 9 -o part > out 2> err
    rc=$?
    [ $rc = 1 ] || fail "other options: exit $rc, expected 1"
    [ "$(wc -l < err)" = 1 ] && grep -q "holds an export with other options" err || fail "other options: message"
    cmp -s before.json part/errors.json || fail "the refused run changed errors.json"
    # --bounds: the tiles over a box of 0.1 x 0.1 degrees only
    "$TP" export n42.tpt --tiles quantized-mesh --heights geoid --bounds 1.45,42.45,1.55,42.55 -o box > out 2> err ||
        fail "export --bounds"
    check box
    python3 - > out 2>&1 << 'EOF' || fail "--bounds tiles"
import json
errs = json.load(open("box/errors.json"))
for k in errs:
    z, x, y = map(int, k.split("/"))
    if z == 0:
        continue
    size = 180.0 / (1 << z)
    w, s = -180 + x * size, -90 + y * size
    assert w <= 1.55 and w + size >= 1.45 and s <= 42.55 and s + size >= 42.45, k
assert max(int(k.split("/")[0]) for k in errs) == json.load(open("box/layer.json"))["maxzoom"]
EOF
    ;;
threads)
    store craterlake-elev-16bit-30m.tif cl
    for a in "" "--max-zoom 14"; do
        for t in 1 3; do
            # shellcheck disable=SC2086 # $a: no option or two words
            "$TP" export cl.tpt --tiles quantized-mesh --heights geoid --max-error 1 $a \
                --threads $t -o "t$t$a" > out 2> err || fail "export $a --threads $t"
            grep -Eq "tiles built in .* s of CPU, $t threads?\)" err || fail "no level line of $t threads"
        done
        [ "$(find "t1$a" -name '*.terrain' | wc -l)" -ge 25 ] || fail "$a: too few tiles"
        diff -r "t1$a" "t3$a" > out 2>&1 || fail "$a: --threads 1 and 3 differ: $(head -3 out)"
    done
    # heights above the ellipsoid: each thread with a geoid of its own
    for t in 1 3; do
        "$TP" export cl.tpt --tiles quantized-mesh --heights ellipsoid --max-zoom 13 \
            --threads $t -o "e$t" > out 2> err || fail "export --heights ellipsoid --threads $t"
    done
    grep -q '"heights": "ellipsoid"' e1/layer.json || fail "e1: not ellipsoid heights"
    diff -r e1 e3 > out 2>&1 || fail "--heights ellipsoid: --threads 1 and 3 differ: $(head -3 out)"
    total=$(wc -l < "t1--max-zoom 14/tiles.log")
    [ "$total" -ge 100 ] || fail "--max-zoom 14: $total tiles"
    # SIGKILL, then SIGTERM (the threads stopped, the tiles built ahead dropped: exit 143)
    for sig in KILL TERM; do
        rm -rf part
        "$TP" export cl.tpt --tiles quantized-mesh --heights geoid --max-error 1 --max-zoom 14 \
            --threads 3 -o part > out 2> err &
        pid=$!
        for _ in $(seq 1 1000); do
            [ -f part/tiles.log ] && [ "$(wc -l < part/tiles.log)" -ge 45 ] && break
            sleep 0.02
        done
        kill -$sig $pid 2> /dev/null
        wait $pid 2> /dev/null
        rc=$?
        [ $sig = KILL ] || [ $rc = 143 ] || fail "SIGTERM: exit $rc, expected 143"
        n=$(wc -l < part/tiles.log)
        [ "$n" -ge 45 ] && [ "$n" -lt "$total" ] || fail "SIG$sig after $n of $total tiles: not mid-way"
        [ -f part/layer.json ] && fail "layer.json written by an export stopped by SIG$sig"
        "$TP" export cl.tpt --tiles quantized-mesh --heights geoid --max-error 1 --max-zoom 14 \
            --threads 2 -o part > out 2> err || fail "the rerun on 2 threads after SIG$sig"
        grep -q "tiles already written by an earlier run: kept" err || fail "the rerun kept nothing"
        diff -r "t1--max-zoom 14" part > out 2>&1 ||
            fail "SIG$sig, resumed on 2 threads: differs: $(head -3 out)"
    done
    check part
    ;;
*) fail "unknown case $CASE" ;;
esac
echo "PASS $CASE"
