#!/usr/bin/env bash
# window_msaa.sh - multisampling in a real window (Xvfb): the viewer draws into a multisampled
# framebuffer of its own and resolves it into the window (gl_context.c), so `--msaa 4` and
# `--msaa 0` show the same view (the same camera, P's screenshots) but for the pixels on edges,
# which 4 samples blend: the silhouette against the sky and the ridges against the ground behind
# them. So some pixels differ (a resolve that did not happen would leave none), next to the sky
# among them, and the pictures are alike on the whole (a resolve gone wrong, black or shifted,
# would not be).
# usage: window_msaa.sh TERRAPATCH DEM WORKDIR
# Needs Xvfb, xdotool (`make deps`) and python3 (the PNGs are read with its zlib).
set -u
exe=$1 dem=$2 dir=$3
mkdir -p "$dir"
name=window_msaa
. "$(dirname "$0")/window_lib.sh"
window_xvfb 231 300
dir=$(cd "$dir" && pwd)
cd "$dir" # P writes its screenshot here
fail=0
for n in 0 4; do
    rm -f "$dir"/terrapatch-*.png
    window_view --msaa "$n" --no-hud --camera 598000,5012000,4500,15,-35 "$dem"
    window_focus
    sleep 2 # the normal map's blocks
    xdotool key p
    for _ in $(seq 100); do grep -q '^screenshot: ' "$dir/stdout.txt" && break; sleep 0.1; done
    window_close
    shot=$(sed -n 's/^screenshot: //p' "$dir/stdout.txt" | head -n1)
    [ "$rc" = 0 ] && [ -n "$shot" ] && [ -f "$dir/$shot" ] ||
        { echo "FAIL: --msaa $n: exit $rc, no screenshot"; cat "$dir/stderr.txt"; fail=1; continue; }
    mv "$dir/$shot" "$dir/msaa$n.png"
done
[ "$fail" = 0 ] || exit 1
TP_TESTS_DIR=$(cd "$(dirname "$0")" && pwd) python3 - "$dir/msaa0.png" "$dir/msaa4.png" <<'EOF'
import os, sys
sys.path.insert(0, os.environ["TP_TESTS_DIR"])
from tp_png import read_png

w, h, ch, a = read_png(sys.argv[1])
w2, h2, ch2, b = read_png(sys.argv[2])
assert (w, h) == (w2, h2)
sky = tuple(a[0][:3])
def px(rows, c, x, y): return tuple(rows[y][x * c:x * c + 3])
changed = near_sky = 0
total = 0.0
for y in range(1, h - 1):
    for x in range(1, w - 1):
        p, q = px(a, ch, x, y), px(b, ch2, x, y)
        d = sum(abs(p[k] - q[k]) for k in range(3))
        total += d / 3.0
        if d <= 6:
            continue
        changed += 1
        near_sky += any(px(a, ch, x + i, y + j) == sky for i in (-1, 0, 1) for j in (-1, 0, 1))
mad = total / ((w - 2) * (h - 2))
print('window_msaa: %d pixels changed by 4 samples (%.1f %%), %d of them next to the sky; mean '
      'absolute difference %.2f grey levels' % (changed, 100.0 * changed / (w * h), near_sky, mad))
ok = changed >= 100 and near_sky >= 50 and mad < 2
print('window_msaa: passed' if ok else 'FAIL: 4 samples should blend the silhouette with the sky')
sys.exit(0 if ok else 1)
EOF
