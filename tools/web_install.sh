#!/bin/sh
# tools/web_install.sh - the npm packages of the web page (tools/web/, docs/web.md): CesiumJS
# 1.140.0 (the page's globe; its Build/Cesium folder is served beside the tile set) and
# puppeteer-core 24.43.1 (tools/web/drive.mjs drives Debian's chromium with it: the test and the
# screenshots). Not vendored: installed from npm, exact versions, into
# ${XDG_CACHE_HOME:-~/.cache}/terrapatch/web (npm install --prefix); TP_WEB_DIR overrides it.
#
#   tools/web_install.sh           install them there unless both are already there at those
#                                  versions (then it is quick: no npm, no network); prints the folder
#   tools/web_install.sh --check   install nothing: exit 0 and print the folder when both are
#                                  there, else exit 1 after one line saying what is missing
#
# Exit 0, or 1 after one line naming what is missing (node, npm, the network for npm install).
set -u
dir=${TP_WEB_DIR:-${XDG_CACHE_HOME:-${HOME:-}/.cache}/terrapatch/web}
me="terrapatch: tools/web_install.sh"
CESIUM=1.140.0
PUPPETEER=24.43.1

installed() { # both packages at their exact versions, and Cesium's built files
    grep -q "\"version\": *\"$CESIUM\"" "$dir/node_modules/cesium/package.json" 2>/dev/null &&
        grep -q "\"version\": *\"$PUPPETEER\"" "$dir/node_modules/puppeteer-core/package.json" \
            2>/dev/null && [ -f "$dir/node_modules/cesium/Build/Cesium/Cesium.js" ]
}

case "${1:-}" in
"") ;;
--check)
    if installed; then echo "$dir"; exit 0; fi
    echo "$me: cesium@$CESIUM and puppeteer-core@$PUPPETEER are not in $dir: run tools/web_install.sh (needs npm and the network once)" >&2
    exit 1
    ;;
-h | --help) sed -n '2,/^set -u/p' "$0" | sed -e '$d' -e 's/^# \{0,1\}//'; exit 0 ;;
*) echo "$me: unknown option '$1' (--check, --help)" >&2; exit 2 ;;
esac

if ! installed; then
    if ! command -v node >/dev/null 2>&1; then
        echo "$me: node not found on PATH ($PATH): the web page's driver runs on Node.js; install it (Debian: apt-get install nodejs npm)" >&2
        exit 1
    fi
    if ! command -v npm >/dev/null 2>&1; then
        echo "$me: npm not found on PATH ($PATH): needed once to install cesium@$CESIUM and puppeteer-core@$PUPPETEER into $dir" >&2
        exit 1
    fi
    mkdir -p "$dir" || { echo "$me: cannot create $dir" >&2; exit 1; }
    echo "$me: npm install --prefix $dir cesium@$CESIUM puppeteer-core@$PUPPETEER" >&2
    # PUPPETEER_SKIP_DOWNLOAD: puppeteer-core downloads no browser anyway; Debian's chromium is used
    if ! PUPPETEER_SKIP_DOWNLOAD=1 npm install --prefix "$dir" --no-audit --no-fund --save-exact \
            "cesium@$CESIUM" "puppeteer-core@$PUPPETEER" >&2 || ! installed; then
        echo "$me: npm install of cesium@$CESIUM and puppeteer-core@$PUPPETEER into $dir failed (no network, or the npm registry unreachable?)" >&2
        exit 1
    fi
fi
echo "$dir"
