#!/bin/bash
# test_http_store.sh TERRAPATCH PROXY DATA_DIR WORK_DIR CASE: issue 33 item 1, a store read over
# HTTP. A real nginx (Debian's) started here on 127.0.0.1 with its configuration, logs and pid
# in WORK_DIR, serving two stores built here from DATA_DIR/lf_elev_220_mt_hood_utm.tif (patch 65
# and 33), and PROXY (tests/http_fault_proxy.py) in front of it: 50 ms a request, and the faults
# its paths name. Both are stopped by a trap whatever happens: no daemon is left behind.
#   same:   info, point (3 positions), los, profile, viewshed, terrain, contours and bench
#           (headless, 20 frames) over the URL, through the 50 ms proxy, answer as over the
#           local file (the same lines and files; bench: triangles, nodes drawn, measured
#           error); info straight from nginx too; an imagery pyramid's URL (info, found beside
#           its store's URL, bench --imagery URL); a URL that is not a store, one that is not
#           there: one line, exit 1
#   faults: point with the node it reads answered by 404, 500, a reset, a body cut short, a
#           stall (GDAL_HTTP_LOW_SPEED_TIME=2), a body garbled on the way (the node's CRC32 says
#           so) or the file replaced between two reads: exit 1,
#           one line on stderr naming the URL and what happened, nothing on stdout; bench with
#           the batch of nodes it reads ahead at open answered 500 (the batch is not retried, its
#           nodes are read one by one, those of its first block fail again): it flies on (their
#           ancestors drawn, the nodes asked for again with backoff), says so once a node a run,
#           exit 0; bench with the file replaced at that batch: one line "changed on the server",
#           exit 1
#   view_export: view --headless over the URL (with --light, the day's .tpl beside the store
#           read from its URL) draws the same PNG and measures the same error as from the file,
#           reading the store in at most 12 requests; export over the URL writes the same mesh
#           (but for the source's name); export of a URL answering 404: one line, no file
# nginx missing is a failure (make test installs it: tools/deps.sh), never a skip.
set -u
TP=$1 PROXY=$2 DATA=$3 WORK=$4 CASE=$5
fail() { echo "FAIL: $*"; for f in out err; do [ -s "$WORK/$f" ] && { echo "--- $f"; tail -5 "$WORK/$f"; }; done; exit 1; }
NGINX=$(command -v nginx || { [ -x /usr/sbin/nginx ] && echo /usr/sbin/nginx; })
[ -n "$NGINX" ] || fail "nginx is not installed (Debian package nginx: 'make deps' or tools/deps.sh installs it)"
command -v python3 > /dev/null || fail "python3 is not installed"
rm -rf "$WORK" && mkdir -p "$WORK/www" && cd "$WORK" || exit 1
chmod 755 "$WORK" "$WORK/www" # nginx's workers read as another user when started by root

"$TP" build "$DATA/lf_elev_220_mt_hood_utm.tif" -o www/hood.tpt > /dev/null 2> err ||
    fail "build hood.tpt"
"$TP" build "$DATA/lf_elev_220_mt_hood_utm.tif" --patch 33 -o www/other.tpt > /dev/null 2> err ||
    fail "build other.tpt"
cp "$DATA/lf_elev_220_mt_hood_utm.tif" www/dem.tif
"$TP" build "$DATA/craterlake-elev-16bit-30m.tif" -o www/crater.tpt > /dev/null 2> err ||
    fail "build crater.tpt"
"$TP" imagery www/crater.tpt "$DATA/craterlake-imagery-30m.tif" > /dev/null 2> err ||
    fail "imagery crater.tpi"

NGINX_PID= PROXY_PID=
stop() { # nginx's master stops its workers; wait for both to be gone
    if [ -s "$WORK/nginx.pid" ]; then
        NGINX_PID=$(cat "$WORK/nginx.pid")
        kill "$NGINX_PID" 2> /dev/null
        for _ in $(seq 50); do kill -0 "$NGINX_PID" 2> /dev/null || break; sleep 0.1; done
    fi
    [ -n "$PROXY_PID" ] && kill "$PROXY_PID" 2> /dev/null
    wait 2> /dev/null
}
trap stop EXIT
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
user=
[ "$(id -u)" = 0 ] && user="user root;"
cat > nginx.conf << EOF
$user
worker_processes 2;
pid $WORK/nginx.pid;
error_log $WORK/nginx_error.log;
events { worker_connections 256; }
http {
    access_log $WORK/nginx_access.log;
    client_body_temp_path $WORK/tmp_body; proxy_temp_path $WORK/tmp_proxy;
    fastcgi_temp_path $WORK/tmp_fastcgi; uwsgi_temp_path $WORK/tmp_uwsgi;
    scgi_temp_path $WORK/tmp_scgi;
    server { listen 127.0.0.1:$port; root $WORK/www; }
}
EOF
"$NGINX" -c "$WORK/nginx.conf" -p "$WORK" -e "$WORK/nginx_error.log" 2> err || fail "nginx did not start"
python3 "$PROXY" "$port" "$WORK/proxy_port" "$WORK/proxy.log" 0.05 2> proxy_err &
PROXY_PID=$!
for _ in $(seq 50); do [ -s proxy_port ] && break; sleep 0.1; done
[ -s proxy_port ] || fail "the proxy did not start"
PP=$(cat proxy_port)
DIRECT=http://127.0.0.1:$port/hood.tpt
SLOW=http://127.0.0.1:$PP/ok/hood.tpt
POS=("45.3735 -121.6959" "45.30 -121.80" "45.45 -121.55")

# one line on stderr holding each of the words after the first argument (the file err)
one_line() {
    [ "$(wc -l < err)" = 1 ] || fail "$1: $(wc -l < err) lines on stderr, expected one"
    local what=$1
    shift
    for w in "$@"; do grep -qF -- "$w" err || fail "$what: stderr does not say '$w'"; done
    grep -qiE 'sanitizer|segmentation|core dumped' err && fail "$what: crashed"
    return 0
}

case_same() {
    "$TP" info www/hood.tpt > local.txt 2> err || fail "info of the local store"
    for u in "$DIRECT" "$SLOW"; do
        "$TP" info "$u" > out 2> err || fail "info $u: exit $?"
        diff <(tail -n +2 local.txt) <(tail -n +2 out) > /dev/null || fail "info $u differs"
        grep -q "^store: *$u\$" out || fail "info $u does not name it"
    done
    grep -q "checked: *[1-9][0-9]* nodes, 0 damaged" out || fail "info did not check every node"
    for p in "${POS[@]}"; do
        "$TP" point www/hood.tpt $p > local.txt 2> err || fail "point $p (local)"
        "$TP" point "$SLOW" $p > out 2> err || fail "point $p over HTTP: exit $?"
        cmp -s local.txt out || fail "point $p over HTTP differs"
    done
    # the planner commands: the same lines, the same files
    for c in "los S --from 45.30,-121.80 --to 45.37,-121.69" \
             "profile S --through 45.30,-121.80 --through 45.37,-121.69" \
             "viewshed S --observer 45.3735,-121.6959 -o O.tif" "terrain S -o O.tif" \
             "contours S --interval 200 -o O.geojson"; do
        set -f
        for w in local url; do
            src=www/hood.tpt
            [ $w = url ] && src=$SLOW
            cmd=${c/S/$src}
            "$TP" ${cmd/O/$w} > $w.txt 2> err || fail "${c%% *} ($w): exit $?"
        done
        set +f
        # the same but for the times taken and the output's name
        diff <(grep -v '^time ' local.txt | sed 's/local\././') \
             <(grep -v '^time ' url.txt | sed 's/url\././') > /dev/null ||
            fail "${c%% *} over HTTP prints otherwise"
        for f in local.*; do
            case $f in local.txt | local.json) continue ;; esac
            cmp -s "$f" "url.${f#local.}" || fail "${c%% *} over HTTP writes otherwise"
            rm -f "$f" "url.${f#local.}"
        done
    done
    "$TP" bench www/hood.tpt --frames 20 --segments 2 --json local.json > /dev/null 2> err ||
        fail "bench (local)"
    : > proxy.log
    "$TP" bench "$SLOW" --frames 20 --segments 2 --json url.json > out 2> err ||
        fail "bench over HTTP: exit $?"
    python3 - local.json url.json proxy.log << 'EOF' > out 2>&1 || fail "bench over HTTP: $(cat out)"
import json, sys
a, b = (json.load(open(p))["configurations"] for p in sys.argv[1:3])
assert len(a) == len(b) == 2
for x, y in zip(a, b):
    for k in ("triangles_median", "nodes_drawn_median", "max_screen_error_px", "error_samples"):
        assert x[k] == y[k], "%s %s: local %s, over HTTP %s" % (x["lod_mode"], k, x[k], y[k])
gets = [l for l in open(sys.argv[3]) if l.split()[1] == "GET"]
assert gets and all(l.split()[-1] == "206" for l in gets), "not every GET was a range answered 206"
EOF
    # an imagery pyramid: info, found beside its store's URL, draped by bench over URLs
    "$TP" info www/crater.tpi > local.txt 2> err || fail "info of crater.tpi"
    "$TP" info "http://127.0.0.1:$PP/ok/crater.tpi" > out 2> err || fail "info of crater.tpi's URL"
    diff <(tail -n +2 local.txt) <(tail -n +2 out) > /dev/null || fail "info of crater.tpi's URL differs"
    "$TP" info "http://127.0.0.1:$PP/ok/crater.tpt" > out 2> err || fail "info of crater.tpt's URL"
    grep -q "^imagery: *http://127.0.0.1:$PP/ok/crater.tpi: 434 x 384 texels" out ||
        fail "info of crater.tpt's URL does not find crater.tpi beside it"
    "$TP" bench www/crater.tpt --imagery www/crater.tpi --frames 10 --segments 1 --no-error \
        --json local.json > /dev/null 2> err || fail "bench --imagery (local)"
    "$TP" bench "http://127.0.0.1:$PP/ok/crater.tpt" --imagery "http://127.0.0.1:$PP/ok/crater.tpi" \
        --frames 10 --segments 1 --no-error --json url.json > /dev/null 2> err ||
        fail "bench --imagery over HTTP: exit $?"
    python3 - local.json url.json << 'EOF' > out 2>&1 || fail "bench --imagery over HTTP: $(cat out)"
import json, sys
a, b = (json.load(open(p))["configurations"] for p in sys.argv[1:3])
x, y = a[-1], b[-1]
assert x["imagery"] and y["imagery"], "no imagery configuration"
for k in ("triangles_median", "imagery_final_diff_pixels"):
    assert x[k] == y[k], "%s: local %s, over HTTP %s" % (k, x[k], y[k])
assert y["imagery_final_diff_pixels"] == 0
EOF
    # not a store, not there
    "$TP" info "http://127.0.0.1:$port/dem.tif" > out 2> err && fail "info of a DEM's URL: exit 0"
    one_line "a DEM's URL" "http://127.0.0.1:$port/dem.tif" "not a terrapatch store"
    "$TP" point "http://127.0.0.1:$port/none.tpt" ${POS[0]} > out 2> err && fail "a missing URL: exit 0"
    one_line "a missing URL" "http://127.0.0.1:$port/none.tpt" "cannot open"
}

case_view_export() {
    # view --headless over the URL: the same picture and the same figures as from the file
    # (the error measure's leaves read over HTTP, in batches), the light map of the day beside
    # it (.tpl) streamed from its URL too
    "$TP" light www/hood.tpt --day --date 2026-06-21 --maps 8 -o www/hood.tpl > /dev/null 2> err ||
        fail "light --day hood.tpl"
    local V="--headless --size 320x240 --sun-date 2026-06-21 --sun-time 17:00Z"
    "$TP" view www/hood.tpt $V --light www/hood.tpl --screenshot local.png \
        --stats-json local.json > /dev/null 2> err || fail "view (local)"
    : > proxy.log
    "$TP" view "$SLOW" $V --light "http://127.0.0.1:$PP/ok/hood.tpl" --screenshot url.png \
        --stats-json url.json > out 2> err || fail "view over HTTP: exit $?"
    cmp -s local.png url.png || fail "view over HTTP draws another picture"
    grep -q "GET /ok/hood.tpl" proxy.log || fail "view over HTTP did not read the light map's URL"
    python3 - local.json url.json << 'EOF2' > out 2>&1 || fail "view over HTTP: $(cat out)"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:3])
for k in ("triangles", "nodes_drawn", "max_error_px", "rms_error_px", "error_samples",
          "error_leaves_measured"):
    assert a[k] == b[k], "%s: local %s, over HTTP %s" % (k, a[k], b[k])
assert b["error_leaves_read"] > 0, "no leaf read for the error measure"
for j in a, b:  # the light map's clipmap, not shadows computed around the point looked at
    assert j["light_source"] == "streamed", "not lit by the light map: %s" % j["light_source"]
EOF2
    # the store's 660 KB, 41 blocks of /vsicurl/'s 16 KB, read in batches of merged ranges
    # (the roots and coarse scales at open, then what the loaders and the measure still lack),
    # not a request a block or a node
    gets=$(grep -c "GET /ok/hood.tpt" proxy.log)
    [ "$gets" -le 12 ] || fail "view over HTTP: $gets requests for the store, expected 12 at most"
    # export over the URL: the same mesh file but for the source's name in its field data
    "$TP" export www/hood.tpt -o local.vtk > /dev/null 2> err || fail "export (local)"
    "$TP" export "$SLOW" -o url.vtk > /dev/null 2> err || fail "export over HTTP: exit $?"
    python3 - local.vtk url.vtk "$SLOW" << 'EOF2' > out 2>&1 || fail "export over HTTP: $(cat out)"
import sys
def without_source(path):  # the field data's source_file string (VTK legacy binary length)
    d = open(path, "rb").read()
    key = b"source_file 1 1 string\n"
    i = d.index(key) + len(key)
    kind, n = d[i] >> 6, d[i] & 0x3F
    k = {3: 1, 2: 2}[kind]
    for j in range(1, k):
        n = n << 8 | d[i + j]
    return d[:i] + d[i + k + n:], d[i + k:i + k + n]
a, _ = without_source(sys.argv[1])
b, src = without_source(sys.argv[2])
assert src == sys.argv[3].encode(), "export over HTTP names %r, not its URL" % src
assert a == b, "export over HTTP writes another mesh"
EOF2
    "$TP" export "http://127.0.0.1:$PP/404/0-999999999/hood.tpt" -o none.vtk > out 2> err &&
        fail "export of a URL answering 404: exit 0"
    one_line "export of a URL answering 404" "HTTP 404"
    [ -e none.vtk ] && fail "export of a URL answering 404 wrote a file"
    return 0
}

case_faults() {
    # the range GDAL asks for the leaf under POS[0], from a run without faults
    : > proxy.log
    "$TP" point "$SLOW" ${POS[0]} > local.txt 2> err || fail "point over HTTP"
    from=$(awk '$2 == "GET" {r = $4} END {sub("bytes=", "", r); sub("-.*", "", r); print r}' proxy.log)
    [ -n "$from" ] || fail "no range asked for"
    range=$from-$((from + 1))
    for m in 404:"HTTP 404" 500:"HTTP 500" reset:"cannot read" truncate:"transfer closed" \
             stall:"too slow" garble:"checksum mismatch" replace:other.tpt:"changed on the server"; do
        mode=${m%:*} says=${m##*:}
        url=http://127.0.0.1:$PP/$mode/$range/hood.tpt
        GDAL_HTTP_LOW_SPEED_TIME=2 GDAL_HTTP_MAX_RETRY=1 "$TP" point "$url" ${POS[0]} > out 2> err
        rc=$?
        [ $rc = 1 ] || fail "point with $mode: exit $rc, expected 1"
        [ -s out ] && fail "point with $mode printed an answer"
        one_line "point with $mode" "$url" "$says"
    done
    # bench: a node's range answered 500 (its ancestor drawn, the flight goes on), then the file
    # replaced in flight (at the same range)
    : > proxy.log
    "$TP" bench "$SLOW" --frames 20 --segments 2 --no-error > out 2> err || fail "bench over HTTP"
    # the start of the largest range an unfaulted flight asked for: the batch of nodes read
    # ahead at open (requests made at once finish in any order, so not the last one); failed,
    # its nodes are read one by one, and those in its first block fail again
    last=$(awk '$2 == "GET" {split($4, b, "[=-]"); if (b[3] - b[2] > m) {m = b[3] - b[2]; r = b[2]}}
        END {print r}' proxy.log)
    url=http://127.0.0.1:$PP/500/$last-$((last + 1))/hood.tpt
    "$TP" bench "$url" --frames 20 --segments 2 --no-error > out 2> err || fail "bench with 500: exit $?"
    grep -q "HTTP 500" err || fail "bench with 500 did not say so"
    [ -z "$(grep "HTTP 500" err | sort | uniq -d)" ] || fail "bench with 500 said a node's failure twice"
    grep -qiE 'sanitizer|segmentation' err && fail "bench with 500 crashed"
    url=http://127.0.0.1:$PP/replace:other.tpt/$last-$((last + 1))/hood.tpt
    "$TP" bench "$url" --frames 20 --segments 2 --no-error > out 2> err
    rc=$?
    [ $rc = 1 ] || fail "bench with the file replaced: exit $rc, expected 1"
    grep -v "^\s*$" err | grep -c "changed on the server" | grep -qx 1 ||
        fail "bench with the file replaced: not one line saying it changed"
}

case_$CASE
stop
trap - EXIT
kill -0 "$NGINX_PID" 2> /dev/null && fail "nginx still runs"
pgrep -f "$WORK/nginx.conf" > /dev/null && fail "nginx still runs"
echo PASS
