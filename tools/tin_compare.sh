#!/bin/sh
# tools/tin_compare.sh - the npm meshers that `terrapatch bench --static --compare` runs beside
# terrapatch's TIN: delatin 0.2.0 (greedy Delaunay insertion) and @mapbox/martini 0.2.0 (RTIN).
# Not vendored: installed from npm, exact versions, into
# ${XDG_CACHE_HOME:-~/.cache}/terrapatch/npm (npm install --prefix); TP_NPM_DIR overrides it.
#
#   tools/tin_compare.sh install
#       installs them there unless both are already there at those versions; prints the folder
#   tools/tin_compare.sh run delatin|martini GRID.f32 W H RUNS OUT.mesh MAX_ERROR
#       one mesher, one bound, in its own node process (tools/tin_compare.mjs: the file formats);
#       node's heap limit is TP_NODE_HEAP_MB (default 12288)
#
# Exit 0, or 1 after one line naming what is missing (node, npm, the network for npm install).
set -u
case $0 in */*) here=${0%/*} ;; *) here=. ;; esac
dir=${TP_NPM_DIR:-${XDG_CACHE_HOME:-${HOME:-}/.cache}/terrapatch/npm}
me="terrapatch: tools/tin_compare.sh"

need_node() {
    if ! command -v node >/dev/null 2>&1; then
        echo "$me: node not found on PATH ($PATH): bench --compare runs delatin and martini with Node.js; install it (Debian: apt-get install nodejs npm)" >&2
        exit 1
    fi
}

installed() { # both packages at their exact versions
    grep -q '"version": *"0.2.0"' "$dir/node_modules/delatin/package.json" 2>/dev/null &&
        grep -q '"version": *"0.2.0"' "$dir/node_modules/@mapbox/martini/package.json" 2>/dev/null
}

case "${1:-}" in
install)
    need_node
    if ! installed; then
        if ! command -v npm >/dev/null 2>&1; then
            echo "$me: npm not found on PATH ($PATH): needed once to install delatin@0.2.0 and @mapbox/martini@0.2.0 into $dir" >&2
            exit 1
        fi
        mkdir -p "$dir" || { echo "$me: cannot create $dir" >&2; exit 1; }
        echo "$me: npm install --prefix $dir delatin@0.2.0 @mapbox/martini@0.2.0" >&2
        if ! npm install --prefix "$dir" --no-audit --no-fund --save-exact \
                delatin@0.2.0 @mapbox/martini@0.2.0 >&2 || ! installed; then
            echo "$me: npm install of delatin@0.2.0 and @mapbox/martini@0.2.0 into $dir failed (no network, or the npm registry unreachable?)" >&2
            exit 1
        fi
    fi
    echo "$dir"
    ;;
run)
    shift
    need_node
    if ! installed; then
        echo "$me: delatin@0.2.0 and @mapbox/martini@0.2.0 are not in $dir: run '$0 install' first" >&2
        exit 1
    fi
    # delatin keeps its mesh in plain JS arrays: a 4097^2 grid at e = 1 (25 M triangles) outgrows
    # node's default heap (about 4 GB); TP_NODE_HEAP_MB sets the limit (default 12288)
    TP_NPM_DIR=$dir exec node --max-old-space-size="${TP_NODE_HEAP_MB:-12288}" \
        "$here/tin_compare.mjs" "$@"
    ;;
*)
    echo "usage: $0 install | run delatin|martini GRID.f32 W H RUNS OUT.mesh MAX_ERROR" >&2
    exit 2
    ;;
esac
