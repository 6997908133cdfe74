#!/bin/sh
# tools/deps.sh: choose the Debian 12 packages terrapatch builds with and install the missing
# ones (`make deps`, hence `make run` and `make test`, call it).
#
#   tools/deps.sh             install what is missing (apt-get, through sudo when not root)
#   tools/deps.sh --dry-run   print the choice and what is missing; install nothing
#
# VTK comes from one of two places, because Debian's two VTK builds cannot be installed together:
#
#   system    libvtk9-dev (VTK 9.1). It Depends (hard, not Recommends) on python3-vtk9, and
#             python3-paraview Conflicts with python3-vtk9 (both ship the Python module
#             `vtkmodules`), so libvtk9-dev cannot be installed where ParaView's Python is.
#   paraview  ParaView's own VTK (9.2, libraries libvtk*-pv5.11.so from `paraview`), whose CMake
#             package paraview-dev ships in /usr/lib/<arch>/cmake/paraview-5.11/vtk;
#             CMakeLists.txt looks there when no other VTK is found. That package also needs
#             python3-paraview (its VTKPython targets name vtkmodules/*.so, checked on load)
#             and the -dev packages its find_package calls want for the modules we use.
#
# TP_DEPS_FUZZ=1 adds the packages of the fuzz build (`make fuzz`, tests/fuzz): clang and
# libclang-rt-14-dev.
#
# TP_VTK=auto (default) picks `system` when libvtk9-dev is installed, else `paraview` when any
# of paraview, python3-paraview or paraview-dev is installed, else `system`. TP_VTK=system or
# TP_VTK=paraview forces one.
#
# One dpkg-query answers for every package, so the script is quick when nothing is missing.
# Tests (tests/test_deps.sh) set TP_DEPS_INSTALLED="pkg ..." to pretend that exactly those
# packages are installed, in place of asking dpkg.
set -eu

# gdal-bin: the GDAL command-line tools tools/make_mirror_dem.py (and its test) and
# tests/test_contours_levels.c (gdal_contour, the reference for contours' levels) run.
# libzstd-dev, zlib1g-dev: the store's compression and checksums (io/src/store_codec.cpp); zlib
# also gzips Cesium's terrain tiles (io/src/gzip.cpp).
# proj-data: PROJ's grids, among them EGM96 (egm96_15.gtx), which `export --tiles quantized-mesh
# --heights ellipsoid` adds to the heights (io/src/geoid.cpp; libproj25 depends on it anyway).
# libnova-dev: the sun's position, rise and set (io/src/sun.cpp, `terrapatch light`).
# slurm-wlm, munge: the one-node Slurm cluster tests/test_slurm_build.sh starts on localhost
# (tools/slurm_build.sh, a build in parts); the test starts and stops its daemons itself.
# nginx: the web server tests/test_http_store.sh starts on 127.0.0.1 with its own configuration
# (and stops) to serve stores over HTTP (issue 33). The tests never use the package's service: a
# container's policy-rc.d keeps it from starting; under systemd Debian starts it on port 80
# (`systemctl disable --now nginx` stops it; the tests do not need it).
# chromium: the headless browser tests/test_web_cesium.sh drives (through tools/web/drive.mjs and
# puppeteer-core) to show a quantized-mesh tile set in CesiumJS (issue 34, tools/web/).
# python3-gdal, python3-numpy, time: tools/qm_compare.sh (and its test qm_compare.crater) warps
# the DEM a tile at a time and places its posts with GDAL's Python bindings, and times each step
# with /usr/bin/time -v.
COMMON="cmake pkg-config gcc g++ libgdal-dev libproj-dev libgeographiclib-dev libopenimageio-dev
libglfw3-dev libepoxy-dev libegl-dev libgl-dev libgl1-mesa-dri libegl-mesa0 libstb-dev gnuplot-nox
xvfb xdotool libzstd-dev zlib1g-dev gdal-bin libnova-dev slurm-wlm munge nginx proj-data
chromium python3-gdal python3-numpy time"
VTK_SYSTEM="libvtk9-dev"
# ParaView's VTK config finds Threads, EXPAT, LZMA, LZ4, double-conversion, ZLIB and utf8cpp
# for CommonCore, IOCore, IOXML, IOLegacy, FiltersCore and their dependencies.
VTK_PARAVIEW="paraview-dev python3-paraview libexpat1-dev liblzma-dev liblz4-dev
libdouble-conversion-dev zlib1g-dev libutfcpp-dev"
PARAVIEW_MARKERS="paraview python3-paraview paraview-dev"
# `make fuzz` (TP_DEPS_FUZZ=1) also needs clang and its runtimes: libFuzzer, ASan and UBSan for
# clang are in libclang-rt-14-dev (Debian 12's clang is clang 14).
FUZZ="clang libclang-rt-14-dev"

dry_run=0
case "${1:-}" in
    "") ;;
    -n | --dry-run) dry_run=1 ;;
    -h | --help) sed -n '2,/^set -eu/p' "$0" | sed -e '$d' -e 's/^# \{0,1\}//'; exit 0 ;;
    *) echo "deps.sh: unknown option '$1' (--dry-run, --help)" >&2; exit 2 ;;
esac

# Every package either flavour might need, asked about at once.
all=$(echo $COMMON $VTK_SYSTEM $VTK_PARAVIEW paraview $FUZZ | tr ' ' '\n' | sort -u | tr '\n' ' ')
if [ -n "${TP_DEPS_INSTALLED+set}" ]; then
    installed=" $(echo $TP_DEPS_INSTALLED) "
else
    installed=" $(dpkg-query -W -f='${db:Status-Abbrev} ${Package}\n' $all 2>/dev/null |
        awk '$1 == "ii" { print $2 }' | tr '\n' ' ') "
fi
is_installed() { case "$installed" in *" $1 "*) return 0 ;; esac; return 1; }

vtk=${TP_VTK:-auto}
case "$vtk" in
    auto)
        vtk=system
        if ! is_installed libvtk9-dev; then
            for p in $PARAVIEW_MARKERS; do
                if is_installed "$p"; then vtk=paraview; fi
            done
        fi
        ;;
    system | paraview) ;;
    *) echo "deps.sh: TP_VTK must be auto, system or paraview, not '$vtk'" >&2; exit 2 ;;
esac
if [ "$vtk" = paraview ]; then vtk_debs=$VTK_PARAVIEW; else vtk_debs=$VTK_SYSTEM; fi

packages=$(echo $COMMON $vtk_debs)
[ "${TP_DEPS_FUZZ:-0}" = 1 ] && packages="$packages $FUZZ"
missing=
for p in $packages; do
    is_installed "$p" || missing="$missing $p"
done

if [ "$dry_run" = 1 ]; then
    echo "vtk: $vtk"
    echo "packages: $packages"
    echo "missing:$missing"
    exit 0
fi
[ -n "$missing" ] || exit 0

echo "deps: installing$missing (VTK: $vtk)"
SUDO=
[ "$(id -u)" = 0 ] || SUDO=sudo
# `env` because sudo drops DEBIAN_FRONTEND from the environment.
$SUDO apt-get update -qq
$SUDO env DEBIAN_FRONTEND=noninteractive apt-get install -y --no-install-recommends $missing
