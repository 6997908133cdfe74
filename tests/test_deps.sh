#!/bin/sh
# deps.* (ctest): the package choice of tools/deps.sh (`make deps`), given fake answers for
# which packages are installed (TP_DEPS_INSTALLED), in --dry-run: no dpkg, apt or network.
# Usage: tests/test_deps.sh [path/to/deps.sh]
set -u
DEPS=${1:-$(dirname "$0")/../tools/deps.sh}
fails=0
out=

# run INSTALLED [VAR=VALUE ...]: dry-run with exactly INSTALLED installed; output in $out.
run() {
    installed=$1
    shift
    out=$(env TP_DEPS_INSTALLED="$installed" "$@" sh "$DEPS" --dry-run 2>&1) || {
        echo "FAIL: deps.sh exited $? with installed='$installed' $*: $out"
        fails=$((fails + 1))
    }
}
field() { printf '%s\n' "$out" | sed -n "s/^$1: *//p"; }
# expect NAME FIELD WORD: FIELD's words include WORD; expect_not: they do not.
has() { case " $(field "$1") " in *" $2 "*) return 0 ;; esac; return 1; }
expect() {
    has "$2" "$3" || { echo "FAIL: $1: $2 lacks $3"; echo "$out"; fails=$((fails + 1)); }
}
expect_not() {
    if has "$2" "$3"; then echo "FAIL: $1: $2 has $3"; echo "$out"; fails=$((fails + 1)); fi
}
expect_eq() {
    [ "$(field "$2")" = "$3" ] || {
        echo "FAIL: $1: $2 is '$(field "$2")', not '$3'"; fails=$((fails + 1));
    }
}
# The two VTKs must never be asked for together: python3-paraview Conflicts python3-vtk9.
no_conflict() {
    if has packages libvtk9-dev && has packages python3-paraview; then
        echo "FAIL: $1: libvtk9-dev and python3-paraview both in the list"; fails=$((fails + 1))
    fi
}

# A bare machine: Debian's VTK, everything missing.
run ""
expect_eq bare vtk system
expect bare packages libvtk9-dev
expect bare missing libvtk9-dev
expect bare missing cmake
expect bare missing gdal-bin
expect bare missing libzstd-dev
expect bare missing libnova-dev
expect bare missing slurm-wlm
expect bare missing munge
expect bare missing nginx
expect bare missing chromium
expect bare missing python3-gdal
expect bare missing proj-data
expect_not bare packages paraview-dev
no_conflict bare

# ParaView installed the usual way (its Recommends python3-paraview too): ParaView's VTK.
run "paraview python3-paraview cmake"
expect_eq paraview vtk paraview
expect paraview packages paraview-dev
expect paraview packages python3-paraview
expect paraview missing paraview-dev
expect_not paraview missing python3-paraview
expect_not paraview missing cmake
expect_not paraview packages libvtk9-dev
no_conflict paraview

# ParaView without its Recommends: still ParaView's VTK, and its config needs python3-paraview.
run "paraview"
expect_eq paraview-norec vtk paraview
expect paraview-norec missing python3-paraview
no_conflict paraview-norec

# Only python3-paraview or paraview-dev is enough to tell.
run "python3-paraview"
expect_eq python3-paraview vtk paraview
run "paraview-dev"
expect_eq paraview-dev vtk paraview

# libvtk9-dev already there (next to a ParaView without python3-paraview): keep it.
run "libvtk9-dev paraview"
expect_eq both vtk system
expect_not both missing paraview-dev
no_conflict both

# Everything installed: nothing missing, either way.
run "cmake pkg-config gcc g++ libgdal-dev libproj-dev libgeographiclib-dev libopenimageio-dev
libglfw3-dev libepoxy-dev libegl-dev libgl-dev libgl1-mesa-dri libegl-mesa0 libstb-dev gnuplot-nox xvfb xdotool libzstd-dev zlib1g-dev gdal-bin libnova-dev slurm-wlm munge nginx proj-data chromium python3-gdal python3-numpy time
libvtk9-dev python3-vtk9"
expect_eq complete-system missing ""
run "cmake pkg-config gcc g++ libgdal-dev libproj-dev libgeographiclib-dev libopenimageio-dev
libglfw3-dev libepoxy-dev libegl-dev libgl-dev libgl1-mesa-dri libegl-mesa0 libstb-dev gnuplot-nox xvfb xdotool libzstd-dev zlib1g-dev gdal-bin libnova-dev slurm-wlm munge nginx proj-data chromium python3-gdal python3-numpy time
paraview paraview-dev python3-paraview libexpat1-dev liblzma-dev liblz4-dev
libdouble-conversion-dev zlib1g-dev libutfcpp-dev"
expect_eq complete-paraview vtk paraview
expect_eq complete-paraview missing ""

# The fuzz build (TP_DEPS_FUZZ=1, `make fuzz`) adds clang and its runtimes; others do not ask.
run "" TP_DEPS_FUZZ=1
expect fuzz packages clang
expect fuzz missing libclang-rt-14-dev
run ""
expect_not no-fuzz packages clang
expect_not no-fuzz packages libclang-rt-14-dev

# TP_VTK forces a choice; a wrong value is a usage error.
run "paraview python3-paraview" TP_VTK=system
expect_eq forced-system vtk system
run "" TP_VTK=paraview
expect_eq forced-paraview vtk paraview
expect forced-paraview missing paraview-dev
if TP_DEPS_INSTALLED="" TP_VTK=vtk8 sh "$DEPS" --dry-run >/dev/null 2>&1; then
    echo "FAIL: TP_VTK=vtk8 accepted"; fails=$((fails + 1))
fi
if TP_DEPS_INSTALLED="" sh "$DEPS" --install-everything >/dev/null 2>&1; then
    echo "FAIL: unknown option accepted"; fails=$((fails + 1))
fi

if [ "$fails" -ne 0 ]; then
    echo "$fails check(s) failed"
    exit 1
fi
echo "deps.sh package choice: all checks passed"
